/* Built-in structures: the paper's three-bar linkage and the wrapping-fold
 * solar-sail family (docs/models.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"

#define KIN_PI 3.14159265358979323846

/* Side and loop widths of a sail: well inside the coordinates and lengths
 * kin_assembly_create accepts (|x| <= 1e150, bars >= 1e-150), whatever n. */
static const double SAIL_LENGTH_MIN = 1e-140, SAIL_LENGTH_MAX = 1e140;

int kin_model_threebar(int state, kin_assembly **out)
{
    if (!out) return KIN_ENULL;
    *out = NULL;
    /* joints J1, J2, S1, S2 */
    static const double J[3][4] = {{-1, 0, 0, 0}, {1, 0, 0, 0}, {1, 0, 2, 0}};
    if (state < KIN_THREEBAR_RA || state > KIN_THREEBAR_RC) return KIN_EINVAL;
    double xyz[8] = {J[state][0], J[state][1], J[state][2], J[state][3], 0.0, 0.0, 1.0, 0.0};
    const unsigned char fixed[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    const int bars[6] = {2, 0, 0, 1, 1, 3};
    const double L[3] = {1.0, 1.0, 1.0};
    return kin_assembly_create(2, 4, xyz, fixed, 3, bars, L, out, NULL, 0);
}

static int sail_init(kin_sail_params *p, size_t size, int n_sides, int n_loops)
{
    const kin_sail_params defaults = {
        .size = sizeof(kin_sail_params),
        .n_sides = n_sides,
        .n_loops = n_loops,
        .side = 1.0,
        .widths = NULL,
        .support = KIN_SAIL_SUPPORT_AUTO,
        .diagonal = KIN_SAIL_DIAG_FORWARD,
    };
    return kin__abi_init(p, size, &defaults, KIN__ABI(kin_sail_params));
}

int kin_sail_params_init(kin_sail_params *p, size_t size, int n_sides, int n_loops)
{
    return sail_init(p, size, n_sides, n_loops);
}

/* for binaries built before the macro: the first layout only (docs/abi.md) */
void (kin_sail_params_default)(kin_sail_params *p, int n_sides, int n_loops)
{
    if (p) sail_init(p, KIN__ABI(kin_sail_params)->size[0], n_sides, n_loops);
}

#define sail_fail(eb, el, ...) kin__failbuf(eb, el, KIN_EINVAL, __VA_ARGS__)

/* the caller's parameters into *p (fields it lacks keep their defaults) */
static int sail_read(const kin_sail_params *user, kin_sail_params *p, char *eb, size_t el)
{
    if (kin__abi_check(user, KIN__ABI(kin_sail_params)))
        return sail_fail(eb, el, "params->size = %zu: not set by kin_sail_params_default() of this libkin",
                         kin__abi_size(user));
    kin_sail_params_default(p, 0, 0);
    kin__abi_read(p, user, KIN__ABI(kin_sail_params));
    return KIN_OK;
}

static int sail_check(const kin_sail_params *p, int *support, char *eb, size_t el)
{
    if (p->n_sides < 3 || p->n_sides > 64)
        return sail_fail(eb, el, "n_sides = %d, need 3..64", p->n_sides);
    if (p->n_loops < 1 || p->n_loops > 64)
        return sail_fail(eb, el, "n_loops = %d, need 1..64", p->n_loops);
    if (!(isfinite(p->side) && p->side >= SAIL_LENGTH_MIN && p->side <= SAIL_LENGTH_MAX))
        return sail_fail(eb, el, "side = %g, need %g..%g", p->side, SAIL_LENGTH_MIN, SAIL_LENGTH_MAX);
    if (p->widths) {
        double total = 0.0;
        for (int i = 0; i < p->n_loops; ++i) {
            if (!(isfinite(p->widths[i]) && p->widths[i] >= SAIL_LENGTH_MIN && p->widths[i] <= SAIL_LENGTH_MAX))
                return sail_fail(eb, el, "widths[%d] = %g, need %g..%g", i, p->widths[i], SAIL_LENGTH_MIN,
                                 SAIL_LENGTH_MAX);
            total += p->widths[i];
        }
        if (!(total <= SAIL_LENGTH_MAX))
            return sail_fail(eb, el, "widths add up to %g, need <= %g", total, SAIL_LENGTH_MAX);
    }
    int s = p->support;
    if (s == KIN_SAIL_SUPPORT_AUTO) s = p->n_sides == 4 ? KIN_SAIL_SUPPORT_OPPOSITE : KIN_SAIL_SUPPORT_CENTRE;
    if (s != KIN_SAIL_SUPPORT_OPPOSITE && s != KIN_SAIL_SUPPORT_CENTRE)
        return sail_fail(eb, el, "support = %d is not a kin_sail_support", p->support);
    if (p->n_sides % 2) return sail_fail(eb, el, "support patterns need an even n_sides, got %d", p->n_sides);
    if (p->diagonal != KIN_SAIL_DIAG_FORWARD && p->diagonal != KIN_SAIL_DIAG_BACKWARD)
        return sail_fail(eb, el, "diagonal = %d is not a kin_sail_diagonal", p->diagonal);
    *support = s;
    return KIN_OK;
}

int kin_sail_size(const kin_sail_params *user, int *njoints, int *nbars)
{
    int s;
    if (njoints) *njoints = 0;
    if (nbars) *nbars = 0;
    if (!user) return KIN_ENULL;
    kin_sail_params params, *p = &params;
    int rc = sail_read(user, p, NULL, 0);
    if (!rc) rc = sail_check(p, &s, NULL, 0);
    if (rc) return rc;
    int n = p->n_sides, k = p->n_loops, c = s == KIN_SAIL_SUPPORT_CENTRE;
    if (njoints) *njoints = c + n * (k + 1);
    if (nbars) *nbars = c * (n / 2) + n + 3 * n * k;
    return KIN_OK;
}

int kin_model_sail(const kin_sail_params *user, kin_assembly **out, char *eb, size_t el)
{
    if (eb && el) eb[0] = '\0';
    if (!out) return kin__failbuf(eb, el, KIN_ENULL, "out is NULL");
    *out = NULL;
    if (!user) return kin__failbuf(eb, el, KIN_ENULL, "p is NULL");
    int support, nj, nb;
    kin_sail_params params, *p = &params;
    int rc = sail_read(user, p, eb, el);
    if (!rc) rc = sail_check(p, &support, eb, el);
    if (rc) return rc;
    kin_sail_size(p, &nj, &nb);
    int n = p->n_sides, K = p->n_loops, c = support == KIN_SAIL_SUPPORT_CENTRE;
    double *xyz = calloc((size_t)nj * 3, sizeof *xyz);
    unsigned char *fixed = calloc((size_t)nj * 3, 1);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    if (!xyz || !fixed || !bars) {
        free(xyz); free(fixed); free(bars);
        return kin__failbuf(eb, el, KIN_ENOMEM, "sail of %d joints", nj);
    }
    double a = p->side, R = a / (2.0 * sin(KIN_PI / n));
    /* joint index of hub vertex k (mod n) and of loop-q node k */
#define V_(k) (c + (((k) % n) + n) % n)
#define N_(q, k) (c + n * (q) + (((k) % n) + n) % n) /* q = 0: hub, q >= 1: loop q */
    if (c) { fixed[0] = fixed[1] = 1; } /* C moves in z only */
    for (int k = 0; k < n; ++k) {
        double th = -KIN_PI / 2 - KIN_PI / n + 2 * KIN_PI * k / n;
        xyz[3 * V_(k)] = R * cos(th);
        xyz[3 * V_(k) + 1] = R * sin(th);
    }
    for (int k = 0; k < n; ++k) {
        /* fold k: perpendicular to hub edge V(k-1)V(k), pointing away from the hub */
        const double *vp = xyz + 3 * V_(k - 1), *vk = xyz + 3 * V_(k);
        double ex = vk[0] - vp[0], ey = vk[1] - vp[1], el2 = sqrt(ex * ex + ey * ey);
        double nx = ey / el2, ny = -ex / el2; /* outward normal of a CCW polygon edge */
        double dist = 0.0;
        for (int q = 1; q <= K; ++q) {
            dist += p->widths ? p->widths[q - 1] : a * tan(KIN_PI / n);
            xyz[3 * N_(q, k)] = vk[0] + dist * nx;
            xyz[3 * N_(q, k) + 1] = vk[1] + dist * ny;
        }
    }
    for (int k = 0; k < n; ++k) {
        int fix = support == KIN_SAIL_SUPPORT_OPPOSITE ? (k == 0 || k == n / 2) : (k % 2 == 0);
        if (fix) fixed[3 * V_(k)] = fixed[3 * V_(k) + 1] = fixed[3 * V_(k) + 2] = 1;
    }
    int b = 0;
    if (c)
        for (int k = 1; k < n; k += 2) { bars[2 * b] = 0; bars[2 * b + 1] = V_(k); ++b; }
    for (int k = 0; k < n; ++k) { bars[2 * b] = V_(k); bars[2 * b + 1] = V_(k + 1); ++b; }
    for (int q = 1; q <= K; ++q)
        for (int k = 0; k < n; ++k) {
            bars[2 * b] = N_(q - 1, k); bars[2 * b + 1] = N_(q, k); ++b;        /* fold */
            bars[2 * b] = N_(q, k); bars[2 * b + 1] = N_(q, k + 1); ++b;        /* ring */
            if (p->diagonal == KIN_SAIL_DIAG_FORWARD) {
                bars[2 * b] = N_(q - 1, k); bars[2 * b + 1] = N_(q, k + 1);    /* diagonal */
            } else {
                bars[2 * b] = N_(q, k); bars[2 * b + 1] = N_(q - 1, k + 1);
            }
            ++b;
        }
#undef V_
#undef N_
    rc = kin_assembly_create(3, nj, xyz, fixed, nb, bars, NULL, out, eb, el);
    free(xyz); free(fixed); free(bars);
    if (rc == KIN_OK && c) {
        /* the spokes hold the hub's shape: a device of the model, not
         * membrane, so no part that can touch (kin_set_device_bars) */
        int spokes[64 / 2 + 1], ns = 0; /* n_sides <= 64 (sail_check) */
        for (int k = 1; k < n; k += 2) spokes[ns] = ns, ++ns;
        if ((rc = kin_set_device_bars(*out, ns, spokes)) != KIN_OK) {
            kin__failbuf(eb, el, rc, "sail: device bars");
            kin_assembly_free(*out);
            *out = NULL;
        }
    }
    return rc;
}
