/* KIN_STEP_SPARSE (a sparse LU of the bordered matrix by KLU): the same
 * points as KIN_STEP_SVD and KIN_STEP_LU over a path on the hexagonal sail
 * and on a random free-floating 3D mechanism (six dense rigid-body border
 * rows); a start point factorized sparsely (no SVD); the fallback to the
 * SVD near the three-bar linkage's bifurcation R^C and the stop on it; the
 * dense LQ route where redundant bars make J tall; the LU modes' own step
 * control (fewer factorizations per automatic step than the shared one);
 * every error path (invalid options, no memory, singular factors, a
 * rejected refactorization). No timing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "path/path.h"
#include "libkin.h"
#include "sail_states.h"
#include "lattice_model.h"
#include "step_compare.h"

static void set_mode(kin_assembly *a, int mode, int control)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = mode;
    o.step_control = control;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
}

/* copy of a in mode (shared step control: the SVD mode's amplitudes) */
static kin_assembly *copy_in(const kin_assembly *a, int mode)
{
    kin_assembly *b = NULL;
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    if (b) set_mode(b, mode, KIN_STEP_CONTROL_SHARED);
    return b;
}

/* Follow a path from a in the three modes, `steps` steps of delta, and
 * compare the points after every step. Every handle starts from no
 * factors at all (kin_set_coords): the dense modes analyse the start point
 * by SVD, the sparse mode factorizes it sparsely. Returns the SVD fallbacks of the sparse mode. */
static int three_modes(const kin_assembly *a, int steps, double delta, const char *name)
{
    kin_assembly *h[3] = {copy_in(a, KIN_STEP_SVD), copy_in(a, KIN_STEP_LU), copy_in(a, KIN_STEP_SPARSE)};
    if (!h[0] || !h[1] || !h[2]) return -1;
    int n = kin_njoints(a) * kin_dim(a), fallbacks = 0;
    double *x[3];
    for (int m = 0; m < 3; ++m) x[m] = malloc(sizeof(double) * (size_t)n);
    kin_get_coords(a, x[0]);
    for (int m = 0; m < 3; ++m) CHECK_RC(kin_set_coords(h[m], x[0]), KIN_OK);
    double worst = 0.0;
    for (int k = 0; k < steps; ++k) {
        kin_step_info info[3] = {{.size = sizeof info[0]}, {.size = sizeof info[0]}, {.size = sizeof info[0]}};
        for (int m = 0; m < 3; ++m) {
            CHECK_RC(kin_step(h[m], delta, &info[m]), KIN_OK);
            kin_get_coords(h[m], x[m]);
        }
        if (k == 0) {
            /* the sparse start: a KLU factorization there instead of the
             * dense LU mode's SVD (the point is regular), the rest alike */
            kin_analysis an = {.size = sizeof an};
            CHECK_RC(kin_get_analysis(h[2], &an), KIN_ESTATE);
            CHECK(info[2].factorizations == info[1].factorizations);
        }
        double d = fmax(max_diff(n, x[0], x[2]), max_diff(n, x[1], x[2]));
        worst = fmax(worst, d);
        CHECK(d <= path_tol(a, k + 1));
        CHECK_CLOSE(info[2].delta, info[0].delta, 0.0);
        CHECK(kin_max_strain(h[2]) <= a->opt.corrector_tol);
        CHECK_CLOSE(kin_path_length(h[2]), kin_path_length(h[0]), path_tol(a, k + 1));
        kin_analysis an = {.size = sizeof an};
        if (kin_get_analysis(h[2], &an) == KIN_OK) ++fallbacks;
    }
    printf("%-34s %3d steps: max |x_sparse - x_dense| %.2e (allowed %.1e), %d SVD fallbacks\n", name, steps, worst,
           path_tol(a, steps), fallbacks);
    for (int m = 0; m < 3; ++m) {
        free(x[m]);
        kin_assembly_free(h[m]);
    }
    return fallbacks;
}

static void hex_sail(void)
{
    kin_assembly *s = test_sail(6, 2);
    CHECK(s != NULL);
    if (!s) return;
    CHECK_RC(test_make_generic(s, 0.3), KIN_OK);
    three_modes(s, 20, 0.0, "hexagonal sail, generic");
    kin_assembly_free(s);
}

/* A random free-floating 3D mechanism: a chain of tetrahedra (joint j >= 3
 * braced to j-1, j-2, j-3: rigid and isostatic) with one bar taken out
 * (one internal mechanism), no supports: six rigid-body mechanisms, so J
 * has seven dense border rows. */
static kin_assembly *random_mechanism(int nj, unsigned long long seed)
{
    for (int attempt = 0; attempt < 20; ++attempt) {
        double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
        int *bars = malloc(sizeof(int) * 2 * 3 * (size_t)nj), nb = 0;
        for (int i = 0; i < 3 * nj; ++i) xyz[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53;
        int skip = 3 * (nj / 2); /* a bar in the middle of the chain */
        for (int j = 1; j < nj; ++j)
            for (int b = 1; b <= 3 && j - b >= 0; ++b) {
                bars[nb++] = j - b;
                bars[nb++] = j;
            }
        nb /= 2;
        /* take out bar `skip` */
        memmove(bars + 2 * skip, bars + 2 * skip + 2, sizeof(int) * 2 * (size_t)(nb - skip - 1));
        --nb;
        kin_assembly *a = NULL;
        int rc = kin_assembly_create(3, nj, xyz, NULL, nb, bars, NULL, &a, NULL, 0);
        free(xyz);
        free(bars);
        kin_analysis an = {.size = sizeof an};
        if (rc == KIN_OK && kin_analyse(a, &an) == KIN_OK && an.m_internal == 1 && an.m_rigid == 6 &&
            an.v_r > 1e-3 * an.v_max && kin_nfree(a) == kin_nbars(a) + 7)
            return a;
        kin_assembly_free(a);
    }
    return NULL;
}

static void random_3d(void)
{
    kin_assembly *a = random_mechanism(12, 42);
    CHECK(a != NULL);
    if (!a) return;
    three_modes(a, 15, 0.0, "random 3D mechanism (7 dense rows)");
    kin_assembly_free(a);
}

/* The column order kept at set-up is the one with the fewer factor
 * entries (COLAMD or METIS nested dissection); without a nested-dissection
 * order (as when METIS fails) COLAMD is used; either way the same points. */
static void column_orders(kin_assembly *a, int steps)
{
    kin_assembly *h[2] = {NULL, NULL};
    double ec[2], en[2];
    int nested[2];
    for (int k = 0; k < 2; ++k) {
        CHECK_RC(kin_assembly_clone(a, &h[k]), KIN_OK);
        if (k == 1) kin__set_fault(h[k], KIN__FAULT_SPARSE_NO_ND);
        set_mode(h[k], KIN_STEP_SPARSE, KIN_STEP_CONTROL_SHARED);
        nested[k] = kin__sparse_order(h[k], &ec[k], &en[k]);
    }
    /* the kept order has the fewer entries */
    CHECK(isfinite(ec[0]) && ec[0] == ec[1]);
    CHECK(nested[0] ? en[0] < ec[0] : !(en[0] < ec[0]));
    CHECK(nested[1] == 0 && en[1] == INFINITY);
    printf("%d free coordinates: column order %s (factor entries: COLAMD %.0f, nested dissection %.0f)\n",
           kin_nfree(a), nested[0] ? "nested dissection" : "COLAMD", ec[0], en[0]);
    kin_step_info info = {.size = sizeof info};
    for (int s = 0; s < steps; ++s)
        for (int k = 0; k < 2; ++k) CHECK_RC(kin_step(h[k], 0.0, &info), KIN_OK);
    int n = kin_njoints(a) * kin_dim(a);
    double *x = malloc(sizeof(double) * 2 * (size_t)n);
    kin_get_coords(h[0], x);
    kin_get_coords(h[1], x + n);
    /* the corrector stops anywhere within its tolerance; across the path
     * that difference is amplified by up to the conditioning v_max / v_r */
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(h[1], &an), KIN_OK);
    double allowed = path_tol(a, steps) * fmax(1.0, an.v_max / an.v_r);
    printf("  after %d steps: |x_kept - x_colamd| = %.1e (allowed %.1e)\n", steps, max_diff(n, x, x + n), allowed);
    CHECK(max_diff(n, x, x + n) <= allowed);
    free(x);
    for (int k = 0; k < 2; ++k) kin_assembly_free(h[k]);
}

static void orders(void)
{
    kin_assembly *a = random_mechanism(60, 7);
    CHECK(a != NULL);
    if (a) column_orders(a, 8);
    kin_assembly_free(a);
    /* a compact 3D block (the two orders within a few per cent here) */
    kin_assembly *b = lattice(8, 8, 8);
    CHECK(b != NULL);
    if (b) column_orders(b, 3);
    kin_assembly_free(b);
    kin_assembly *s = test_sail(6, 2);
    CHECK(s != NULL && test_make_generic(s, 0.3) == KIN_OK);
    if (s) column_orders(s, 8);
    kin_assembly_free(s);
    /* no sparse factors: no order */
    kin_assembly *t = test_sail(6, 2);
    double ec = 0.0, en = 0.0;
    CHECK(t != NULL && kin__sparse_order(t, &ec, &en) == 0 && ec == INFINITY && en == INFINITY);
    kin_assembly_free(t);
}

/* From th0 on P1 one step landing at angle th1 near R^C (th = 0): near it
 * the sparse mode falls back to the SVD (and on R^C the SVD finds the
 * bifurcation, m_internal = 2, as the SVD mode does) */
static void land_near_rc(double th1, int want_fallback, int want_m_internal)
{
    const double th0 = 0.05, delta = sqrt(2.0) * sin(th1 - th0);
    kin_assembly *s = threebar_at(th0), *p = NULL;
    CHECK_RC(kin_assembly_clone(s, &p), KIN_OK);
    set_mode(p, KIN_STEP_SPARSE, KIN_STEP_CONTROL_MODE);
    kin_step_info i1 = {.size = sizeof i1}, i2 = {.size = sizeof i2};
    CHECK_RC(kin_step(s, delta, &i1), KIN_OK);
    CHECK_RC(kin_step(p, delta, &i2), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK((kin_get_analysis(p, &an) == KIN_OK) == want_fallback);
    CHECK(i1.m_internal == want_m_internal && i2.m_internal == want_m_internal);
    double x1[8], x2[8];
    kin_get_coords(s, x1);
    kin_get_coords(p, x2);
    CHECK(max_diff(8, x1, x2) <= path_tol(s, 1));
    if (want_m_internal >= 2) {
        CHECK_RC(kin_step(p, 0.0, &i2), KIN_EBIFURCATION);
        CHECK_RC(kin_step(s, 0.0, &i1), KIN_EBIFURCATION);
        /* the bifurcation is where the SVD mode finds it */
        CHECK_CLOSE(atan2(x2[1], x2[0]), atan2(x1[1], x1[0]), path_tol(s, 1));
    }
    printf("three-bar step to angle %.0e from R^C: m_internal %d, sparse mode fell back to SVD: %s\n", th1,
           want_m_internal, want_fallback ? "yes" : "no");
    kin_assembly_free(s);
    kin_assembly_free(p);
}

/* Redundant bars (three parallel cranks carrying a triangle: J is 7 x 6):
 * the sparse mode takes the dense LQ route, without an SVD */
static void redundant_cranks(void)
{
    const double th = PI / 3, c = cos(th), s = sin(th);
    double xyz[12] = {c, s, 1.0 + c, s, 0.5 + c, 0.3 + s, 0, 0, 1.0, 0, 0.5, 0.3}, x1[12], x2[12];
    unsigned char fixed[12] = {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
    int bars[12] = {3, 0, 4, 1, 5, 2, 0, 1, 1, 2, 0, 2};
    kin_assembly *a = NULL, *b = NULL;
    CHECK_RC(kin_assembly_create(2, 6, xyz, fixed, 6, bars, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return;
    b = copy_in(a, KIN_STEP_SPARSE);
    kin_step_info info = {.size = sizeof info};
    for (int k = 0; k < 10; ++k) {
        CHECK_RC(kin_step(a, 0.1, &info), KIN_OK);
        CHECK_RC(kin_step(b, 0.1, &info), KIN_OK);
    }
    kin_get_coords(a, x1);
    kin_get_coords(b, x2);
    CHECK(max_diff(12, x1, x2) <= path_tol(a, 10));
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_get_analysis(b, &an), KIN_ESTATE);
    kin_assembly_free(a);
    kin_assembly_free(b);
}

/* The LU modes' step control halves a stalling chord instead of paying for
 * Newton. The hexagonal sail's generic point is close to a bifurcation,
 * where shorter steps do not help the chord (it then goes back to Newton
 * at the full amplitude): there it must cost about what the shared control
 * costs per unit path length (measured: 14 against 12 factorizations), and
 * keep the strain. (Where it pays, on the larger sails, see
 * docs/performance.md.) */
static void step_control(void)
{
    kin_assembly *s = test_sail(6, 2);
    if (!s) return;
    CHECK_RC(test_make_generic(s, 0.3), KIN_OK);
    kin_assembly *h[2] = {copy_in(s, KIN_STEP_SPARSE), copy_in(s, KIN_STEP_SPARSE)};
    set_mode(h[0], KIN_STEP_SPARSE, KIN_STEP_CONTROL_MODE);
    kin_step_info info = {.size = sizeof info};
    long f[2] = {0, 0};
    int n[2] = {0, 0};
    for (int m = 0; m < 2; ++m)
        while (kin_path_length(h[m]) < 1.0 && n[m] < 200) {
            CHECK_RC(kin_step(h[m], 0.0, &info), KIN_OK);
            CHECK(kin_max_strain(h[m]) <= s->opt.corrector_tol);
            f[m] += info.factorizations;
            ++n[m];
        }
    CHECK(kin_path_length(h[0]) >= 1.0 && kin_path_length(h[1]) >= 1.0);
    CHECK(f[0] <= 1.5 * f[1]);
    printf("step control over path length 1: own %d steps, %ld factorizations; shared %d steps, %ld\n", n[0], f[0],
           n[1], f[1]);
    kin_assembly_free(s);
    kin_assembly_free(h[0]);
    kin_assembly_free(h[1]);
}

static void errors(void)
{
    kin_assembly *a = threebar_at(PI / 3);
    kin_options o = {.size = sizeof o}, keep = {.size = sizeof keep};
    kin_get_options(a, &keep);
    o = keep;
    o.factorization = 3;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep;
    o.step_control = 2;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o.step_control = -1;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    /* the KLU analysis cannot allocate: KIN_ENOMEM, options unchanged */
    kin__set_fault(a, KIN__FAULT_SPARSE_NOMEM);
    o = keep;
    o.factorization = KIN_STEP_SPARSE;
    CHECK_RC(kin_set_options(a, &o), KIN_ENOMEM);
    kin_get_options(a, &o);
    CHECK(memcmp(&o, &keep, sizeof o) == 0);
    kin__set_fault(a, KIN__FAULT_NONE);
    set_mode(a, KIN_STEP_SPARSE, KIN_STEP_CONTROL_MODE);
    /* a factorization cannot allocate: the step fails, the state is kept */
    double x0[8], x1[8];
    kin_get_coords(a, x0);
    kin__set_fault(a, KIN__FAULT_SPARSE_FACTOR_NOMEM);
    kin_step_info info = {.size = sizeof info};
    CHECK_RC(kin_step(a, 0.1, &info), KIN_ENOMEM);
    kin_get_coords(a, x1);
    CHECK(max_diff(8, x0, x1) == 0.0);
    /* every factorization singular: each point falls back to the SVD (and
     * Newton to the least-squares solve); the same point as the SVD mode */
    kin_assembly *s = threebar_at(PI / 3);
    kin__set_fault(a, KIN__FAULT_SPARSE_SINGULAR);
    for (int k = 0; k < 3; ++k) {
        CHECK_RC(kin_step(a, 0.1, &info), KIN_OK);
        CHECK_RC(kin_step(s, 0.1, &info), KIN_OK);
    }
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
    kin_get_coords(a, x0);
    kin_get_coords(s, x1);
    CHECK(max_diff(8, x0, x1) <= path_tol(s, 3));
    /* every refactorization rejected: fresh pivoting each time, same points */
    kin__set_fault(a, KIN__FAULT_SPARSE_REPIVOT);
    for (int k = 0; k < 3; ++k) {
        CHECK_RC(kin_step(a, 0.1, &info), KIN_OK);
        CHECK_RC(kin_step(s, 0.1, &info), KIN_OK);
    }
    CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE);
    kin_get_coords(a, x0);
    kin_get_coords(s, x1);
    CHECK(max_diff(8, x0, x1) <= path_tol(s, 6));
    /* a clone of a sparse-mode handle has its own sparse workspace */
    kin_assembly *c = NULL;
    CHECK_RC(kin_assembly_clone(a, &c), KIN_OK);
    CHECK(c && c->sp != NULL && c->sp != a->sp);
    if (c) CHECK_RC(kin_step(c, 0.1, &info), KIN_OK);
    kin_assembly_free(c);
    kin_assembly_free(s);
    kin_assembly_free(a);
}

int main(void)
{
    hex_sail();
    random_3d();
    orders();
    land_near_rc(0.0, 1, 2);  /* on R^C: the SVD finds m_internal = 2 */
    land_near_rc(1e-7, 1, 1); /* v_r / v_max ~ 5e-8: SVD fallback */
    land_near_rc(0.02, 0, 1); /* v_r / v_max ~ 1e-2: no SVD */
    redundant_cranks();
    step_control();
    errors();
    TEST_REPORT("test_step_sparse");
}
