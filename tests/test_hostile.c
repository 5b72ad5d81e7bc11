/* Hostile input: absurd sizes, overflowing or non-finite geometry, NaN and
 * infinite solver input. Each call must return its documented status, leave
 * the assembly as it was, and write its outputs (handles NULL, counts 0,
 * info structs zeroed) even on the earliest argument checks. The GSL error
 * handler, process-wide state of the application, must come out of the
 * root scan untouched and never be called. */
#include <limits.h>
#include <string.h>

#include <gsl/gsl_errno.h>

#include "check.h"
#include "model/internal.h"
#include "libkin.h"

/* every byte of an output struct zero (they are filled with 0xFF first) */
/* every byte of a size-prefixed struct after its size is zero, the size kept */
static int all_zero(const void *p, size_t n)
{
    const unsigned char *b = p;
    size_t size;
    memcpy(&size, p, sizeof size);
    if (size != n) return 0;
    for (size_t i = sizeof size; i < n; ++i)
        if (b[i]) return 0;
    return 1;
}

/* fill a size-prefixed struct with garbage after a valid size */
static void garbage(void *p, size_t n)
{
    memset(p, 0xFF, n);
    memcpy(p, &n, sizeof n);
}

/* a failed create sets *out to NULL and fills errbuf */
static void create_fails(int dim, int nj, const double *xyz, int nb, const int *bars, const double *rest, int want)
{
    kin_assembly *a = (kin_assembly *)&a;
    char msg[256] = "";
    CHECK_RC(kin_assembly_create(dim, nj, xyz, NULL, nb, bars, rest, &a, msg, sizeof msg), want);
    CHECK(a == NULL);
    CHECK(msg[0] != '\0');
}

static void absurd_sizes(void)
{
    const double xyz[6] = {0, 0, 0, 1, 0, 0};
    const int bar01[2] = {0, 1};
    /* INT_MAX joints in 3D: 3 * INT_MAX coordinates; refused before the
     * (short) array is read */
    create_fails(3, INT_MAX, xyz, 1, bar01, NULL, KIN_ERANGE);
    create_fails(2, INT_MAX / 2 + 1, xyz, 1, bar01, NULL, KIN_ERANGE);
    /* INT_MAX bars: 2 * INT_MAX joint indices */
    create_fails(3, 2, xyz, INT_MAX, bar01, NULL, KIN_ERANGE);
}

static void overflowing_geometry(void)
{
    const int bar01[2] = {0, 1};
    /* finite coordinates whose difference overflows: the length is inf */
    const double far[4] = {-1e308, 0, 1e308, 0};
    create_fails(2, 2, far, 1, bar01, NULL, KIN_EGEOM);
    /* finite length whose square overflows */
    const double big[4] = {0, 0, 1e200, 0};
    create_fails(2, 2, big, 1, bar01, NULL, KIN_EGEOM);
    /* a length whose square underflows to zero */
    const double tiny[4] = {0, 0, 1e-200, 0};
    create_fails(2, 2, tiny, 1, bar01, NULL, KIN_EGEOM);
    const double inf_xyz[4] = {0, 0, INFINITY, 0};
    create_fails(2, 2, inf_xyz, 1, bar01, NULL, KIN_EGEOM);

    /* rest lengths: NaN, inf, finite but too long or too short */
    const double unit[4] = {0, 0, 1, 0};
    const double bad_rest[4] = {NAN, INFINITY, 1e300, 1e-300};
    for (int i = 0; i < 4; ++i) create_fails(2, 2, unit, 1, bar01, &bad_rest[i], KIN_EGEOM);

    /* the bounds leave room: a bar across the whole allowed box (length
     * 3.5e150 > the largest coordinate) is created, cloned (its rest length
     * passes create again) and analysed */
    const double box[6] = {-1e150, -1e150, -1e150, 1e150, 1e150, 1e150};
    kin_assembly *a = NULL, *b = NULL;
    CHECK_RC(kin_assembly_create(3, 2, box, NULL, 1, bar01, NULL, &a, NULL, 0), KIN_OK);
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(b, &an), KIN_OK);
    CHECK(an.rank == 1 && an.m == 5);
    CHECK(kin_max_strain(b) == 0.0);
    kin_assembly_free(b);
    kin_assembly_free(a);
    const double small[4] = {0, 0, 1e-149, 0};
    CHECK_RC(kin_assembly_create(2, 2, small, NULL, 1, bar01, NULL, &a, NULL, 0), KIN_OK);
    kin_assembly_free(a);

    /* set_coords: the same boundary, and nothing changes on refusal */
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double before[8], xyz[8], after[8];
    kin_get_coords(a, before);
    memcpy(xyz, before, sizeof xyz);
    xyz[0] = 1e308; /* J1 x: bars S1-J1 and J1-J2 overflow */
    CHECK_RC(kin_set_coords(a, xyz), KIN_EGEOM);
    xyz[0] = NAN;
    CHECK_RC(kin_set_coords(a, xyz), KIN_EGEOM);
    xyz[0] = 1e-200; /* J1 next to S1 = (0, 0): bar S1-J1 shorter than 1e-150 */
    xyz[1] = 0.0;
    CHECK_RC(kin_set_coords(a, xyz), KIN_EGEOM);
    kin_get_coords(a, after);
    CHECK(memcmp(before, after, sizeof before) == 0);
    kin_assembly_free(a);
}

/* the three-bar linkage at R^B (m = 2, s = 1), analysed, with its Q */
static kin_assembly *bifurcation(double Q[4])
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RB, &a), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 2 && an.s == 1);
    int s = 0;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s), KIN_OK);
    CHECK(s == 1);
    return a;
}

static void second_order_sizes(void)
{
    double Q[4];
    kin_assembly *a = bifurcation(Q);
    double out[4] = {7, 7, 7, 7};
    int s = -1;
    /* m^2 s past INT_MAX: with m = 46341, s = 1 the int product wraps
     * negative and a check in int lets any nq through. No structure that
     * large fits a fast test, so the analysis counts are set directly. */
    kin_factor *f = &a->fac[a->cur];
    kin_analysis keep = f->an;
    f->an.m_internal = 46341;
    f->an.s = 1;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, out, 4, &s), KIN_ERANGE);
    CHECK(s == 0);
    f->an.m_internal = 65536; /* m^2 = 2^32: wraps to 0 in int */
    s = -1;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, out, 4, &s), KIN_ERANGE);
    CHECK(s == 0);
    f->an = keep;
    s = -1;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, out, -1, &s), KIN_ERANGE);
    CHECK(s == 0);
    for (int i = 0; i < 4; ++i) CHECK(out[i] == 7.0); /* never written */
    s = -1;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, NULL, 4, &s), KIN_ENULL);
    CHECK(s == 0);
    kin_assembly_free(a);
}

static void solvers(void)
{
    const double Qgood[4] = {1, 0, 0, -1}; /* beta0^2 = beta1^2: two lines */
    double betas[2 * 4];
    int nsol;
    kin_solve_info si = {.size = sizeof si};
    kin_homotopy_info hi = {.size = sizeof hi};
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 3; ++k) {
        double Q[4] = {1, 0, 0, -1};
        Q[k + 1] = bad[k];
        nsol = -1;
        garbage(&si, sizeof si);
        CHECK_RC(kin_quadrics_scan(2, 1, Q, 16, 1, betas, 4, &nsol, &si), KIN_EINVAL);
        CHECK(nsol == 0 && all_zero(&si, sizeof si));
        nsol = -1;
        garbage(&hi, sizeof hi);
        CHECK_RC(kin_quadrics_homotopy(2, 1, Q, 1, 1, betas, 4, &nsol, NULL, &hi), KIN_EINVAL);
        CHECK(nsol == 0 && all_zero(&hi, sizeof hi));
    }
    /* the earliest checks write the outputs too */
    struct {
        int m, s;
        const double *Q;
        int want;
    } early[] = {{2, 1, NULL, KIN_ENULL}, {1, 0, Qgood, KIN_EINVAL}, {2, 2, Qgood, KIN_EINVAL},
                 {300, 299, Qgood, KIN_ERANGE}};
    for (size_t i = 0; i < sizeof early / sizeof early[0]; ++i) {
        nsol = -1;
        garbage(&si, sizeof si);
        CHECK_RC(kin_quadrics_scan(early[i].m, early[i].s, early[i].Q, 16, 1, betas, 4, &nsol, &si), early[i].want);
        CHECK(nsol == 0 && all_zero(&si, sizeof si));
        nsol = -1;
        garbage(&hi, sizeof hi);
        CHECK_RC(kin_quadrics_homotopy(early[i].m, early[i].s, early[i].Q, 1, 1, betas, 4, &nsol, NULL, &hi),
                 early[i].want);
        CHECK(nsol == 0 && all_zero(&hi, sizeof hi));
    }
    nsol = -1;
    garbage(&si, sizeof si);
    CHECK_RC(kin_quadrics_scan(2, 1, Qgood, 0, 1, betas, 4, &nsol, &si), KIN_EINVAL); /* starts */
    CHECK(nsol == 0 && all_zero(&si, sizeof si));
    nsol = -1;
    garbage(&hi, sizeof hi);
    CHECK_RC(kin_quadrics_homotopy(2, 1, Qgood, 1, 1, betas, 4, &nsol, NULL, NULL), KIN_ENULL); /* info */
    CHECK(nsol == 0);
    CHECK_RC(kin_quadrics_homotopy(2, 1, Qgood, 1, 2, betas, 0, &nsol, NULL, &hi), KIN_EINVAL); /* maxsol */
    CHECK(nsol == 0 && all_zero(&hi, sizeof hi));
    /* an absurd thread count does not allocate per thread: 2 paths, 2 threads */
    CHECK_RC(kin_quadrics_homotopy(2, 1, Qgood, 1, INT_MAX, betas, 4, &nsol, NULL, &hi), KIN_OK);
    CHECK(nsol == 2 && hi.real_distinct == 2);
    /* Q_j scaled without overflow or underflow: the same two solutions at
     * any magnitude */
    const double scales[2] = {1e300, 1e-300};
    for (int k = 0; k < 2; ++k) {
        double Q[4] = {scales[k], 0, 0, -scales[k]};
        nsol = 0;
        CHECK_RC(kin_quadrics_homotopy(2, 1, Q, 1, 1, betas, 4, &nsol, NULL, &hi), KIN_OK);
        CHECK(nsol == 2 && hi.real == 2 && hi.singular == 0);
    }
}

/* the record of a failed kin_branch_paths: zeroed, path_id -1 */
static int no_paths(const kin_branch_path *p, int n)
{
    for (int i = 0; i < n; ++i)
        if (p[i].exists || p[i].tangent_ok || p[i].beta || p[i].sign || p[i].length != 0.0 || p[i].path_id != -1)
            return 0;
    return 1;
}

static void branch_paths(void)
{
    double Q[4], betas[4];
    kin_assembly *a = bifurcation(Q);
    int nsol = 0;
    CHECK_RC(kin_quadrics_scan(2, 1, Q, 32, 1, betas, 2, &nsol, NULL), KIN_OK);
    CHECK(nsol == 2);
    kin_branch_path p[4] = {{.size = sizeof(kin_branch_path)}};
    double before[8], after[8];
    kin_get_coords(a, before);
    const double targets[3] = {INFINITY, NAN, -1.0};
    for (int k = 0; k < 3; ++k) {
        int nd = -1;
        memset(p, 0xFF, sizeof p);
        p[0].size = sizeof p[0];
        CHECK_RC(kin_branch_paths(a, betas, 2, targets[k], p, NULL, &nd), KIN_EINVAL);
        CHECK(nd == 0 && no_paths(p, 4));
    }
    /* finite but absurd: 1e300 path length would never end */
    int nd = -1;
    memset(p, 0xFF, sizeof p);
        p[0].size = sizeof p[0];
    CHECK_RC(kin_branch_paths(a, betas, 2, 1e300, p, NULL, &nd), KIN_ERANGE);
    CHECK(nd == 0 && no_paths(p, 4));
    /* non-finite betas */
    double nb[4] = {betas[0], NAN, betas[2], betas[3]};
    nd = -1;
    CHECK_RC(kin_branch_paths(a, nb, 2, 0.5, p, NULL, &nd), KIN_EINVAL);
    CHECK(nd == 0);
    /* counts: 2 * nbeta paths must be countable in int */
    nd = -1;
    CHECK_RC(kin_branch_paths(a, betas, INT_MAX, 0.5, p, NULL, &nd), KIN_ERANGE);
    CHECK(nd == 0);
    nd = -1;
    CHECK_RC(kin_branch_paths(a, betas, 2, 0.5, NULL, NULL, &nd), KIN_ENULL);
    CHECK(nd == 0);
    kin_get_coords(a, after);
    CHECK(memcmp(before, after, sizeof before) == 0);
    /* and a sane call still works */
    CHECK_RC(kin_branch_paths(a, betas, 2, 0.5, p, NULL, &nd), KIN_OK);
    CHECK(nd == 4);
    kin_assembly_free(a);
}

static void sail_params(void)
{
    kin_sail_params p = {.size = sizeof p};
    kin_assembly *a = (kin_assembly *)&a;
    char msg[256];
    kin_sail_params_default(&p, 6, 2);
    p.side = 1e300; /* coordinates past the create bound */
    CHECK_RC(kin_model_sail(&p, &a, msg, sizeof msg), KIN_EINVAL);
    CHECK(a == NULL);
    int nj = -1, nb = -1;
    CHECK_RC(kin_sail_size(&p, &nj, &nb), KIN_EINVAL);
    CHECK(nj == 0 && nb == 0);
    const double widths[2] = {1e308, 1e308}; /* each finite, the sum is not */
    kin_sail_params_default(&p, 6, 2);
    p.widths = widths;
    a = (kin_assembly *)&a;
    CHECK_RC(kin_model_sail(&p, &a, msg, sizeof msg), KIN_EINVAL);
    CHECK(a == NULL);
    nj = nb = -1;
    CHECK_RC(kin_sail_size(NULL, &nj, &nb), KIN_ENULL);
    CHECK(nj == 0 && nb == 0);
}

/* the GSL error handler: recorded calls */
static int gsl_calls = 0;
static void record_gsl(const char *reason, const char *file, int line, int gsl_errno)
{
    (void)reason, (void)file, (void)line, (void)gsl_errno;
    ++gsl_calls;
}

static void gsl_handler(void)
{
    gsl_error_handler_t *prev = gsl_set_error_handler(record_gsl);
    /* the recorder records (so the checks below can fail) */
    gsl_error("raised on purpose", __FILE__, __LINE__, GSL_EINVAL);
    CHECK(gsl_calls == 1);
    gsl_calls = 0;
    double betas[2 * 64];
    int nsol = 0;
    /* two real lines; no real solution (beta^T I beta = 0 has none, every
     * start stalls); a zero matrix; badly scaled ones */
    const double Qs[5][4] = {{1, 0, 0, -1}, {1, 0, 0, 1}, {0, 0, 0, 0}, {1e300, 0, 0, -1e300}, {1e-300, 0, 0, 1e-300}};
    for (int k = 0; k < 5; ++k) CHECK_RC(kin_quadrics_scan(2, 1, Qs[k], 64, 1, betas, 64, &nsol, NULL), KIN_OK);
    /* a larger random system */
    double Q3[3 * 16];
    unsigned long long st = 12345;
    for (int i = 0; i < 3 * 16; ++i) Q3[i] = (double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5;
    CHECK_RC(kin_quadrics_scan(4, 3, Q3, 64, 1, betas, 32, &nsol, NULL), KIN_OK);
    gsl_error_handler_t *after = gsl_set_error_handler(prev);
    CHECK(after == record_gsl); /* the scan left the application's handler in place */
    CHECK(gsl_calls == 0);      /* and never raised an error through it */
}

/* two joints in 3D, a bar off the axes: the fit leaves Q free about the
 * bar, and the identity must still come first, exactly (it was missing:
 * KIN_OK with no symmetry, or 8 without the identity) */
static void symmetry_two_joints(void)
{
    const double xyz[6] = {-4.57424, -4.39533, -2.70921, -4.3799, -3.39662, -0.327001};
    const int bar01[2] = {0, 1};
    unsigned char fixed[6] = {1, 0, 0, 0, 0, 1}; /* joint 0's x, joint 1's z */
    for (int sup = 0; sup < 2; ++sup) {
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(3, 2, xyz, sup ? fixed : NULL, 1, bar01, NULL, &a, NULL, 0), KIN_OK);
        int perm[2 * 16], nsym = -1;
        double Q[9 * 16], t[3 * 16];
        memset(perm, 0xFF, sizeof perm);
        CHECK_RC(kin_symmetries(a, 16, perm, Q, t, &nsym), KIN_OK);
        CHECK(nsym >= 1 && nsym <= 8);
        CHECK(perm[0] == 0 && perm[1] == 1);
        for (int k = 0; k < 9; ++k) CHECK(Q[k] == (k % 4 == 0 ? 1.0 : 0.0));
        for (int k = 0; k < 3; ++k) CHECK(t[k] == 0.0);
        if (!sup) CHECK(nsym == 8); /* the reflections through the two missing directions, times the swap */
        kin_assembly_free(a);
    }
}

/* names that are not UTF-8: refused as such, not as out of memory */
static void non_utf8_names(void)
{
    const char *model = "{\"name\": \"%s\", \"dimension\": 2, \"joints\": ["
                        "{\"index\": 0, \"xyz\": [0, 0], \"free\": [false, false]},"
                        "{\"index\": 1, \"xyz\": [1, 0], \"free\": [true, true]}],"
                        " \"bars\": [{\"index\": 0, \"joints\": [0, 1]}]}";
    /* a stray byte, a truncated sequence, an overlong '/', a surrogate */
    const char *bad[4] = {"ab\xff", "ab\xc3", "\xc0\xaf", "\xed\xa0\x80"};
    char text[512], msg[256];
    for (int k = 0; k < 4; ++k) {
        kin_assembly *a = (kin_assembly *)&a;
        snprintf(text, sizeof text, model, bad[k]);
        msg[0] = '\0';
        CHECK_RC(kin_assembly_load_string(text, strlen(text), &a, msg, sizeof msg), KIN_EFORMAT);
        CHECK(a == NULL);
        CHECK(strstr(msg, "not valid UTF-8") != NULL);
    }
    const char *good = "caf\xc3\xa9 \xe2\x9c\x93 \xf0\x9d\x84\x9e"; /* café ✓ and U+1D11E */
    kin_assembly *a = NULL, *b = NULL;
    snprintf(text, sizeof text, model, good);
    CHECK_RC(kin_assembly_load_string(text, strlen(text), &a, msg, sizeof msg), KIN_OK);
    char *out = NULL;
    CHECK_RC(kin_assembly_save_string(a, good, &out, NULL, msg, sizeof msg), KIN_OK);
    CHECK(out && strstr(out, "caf") != NULL);
    CHECK_RC(kin_assembly_load_string(out, strlen(out), &b, msg, sizeof msg), KIN_OK);
    kin_free_string(out);
    kin_assembly_free(b);
    for (int k = 0; k < 4; ++k) {
        out = (char *)&out;
        msg[0] = '\0';
        CHECK_RC(kin_assembly_save_string(a, bad[k], &out, NULL, msg, sizeof msg), KIN_EINVAL);
        CHECK(out == NULL);
        CHECK(strstr(msg, "name is not valid UTF-8") != NULL);
    }
    kin_assembly_free(a);
}

/* kin_clearance at huge coordinates: right up to kin_assembly_create's
 * bound 1e150, refused beyond it (squared distances overflowed there, and
 * the answer was "no pair", +INFINITY, with KIN_OK) */
static void clearance_far(void)
{
    /* a triangle panel 0-1-2 in z = 0, a bar 3-4 at z = 1 over it, a bar
     * 4-5 going up; the triangle's bars */
    const double xyz[18] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.25, 0.25, 1, 1, 0.25, 1, 1, 0.25, 3};
    const int bars[10] = {0, 1, 1, 2, 2, 0, 3, 4, 4, 5};
    const int off[2] = {0, 3}, pj[3] = {0, 1, 2};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(3, 6, xyz, NULL, 5, bars, NULL, &a, NULL, 0), KIN_OK);
    CHECK_RC(kin_set_panels(a, 1, off, pj), KIN_OK);
    const double scales[6] = {1.0, 1e100, 3e149, 1e-100, 1e160, 1e300};
    for (int k = 0; k < 6; ++k) {
        double x[18], c = -1.0;
        int parts[4];
        for (int i = 0; i < 18; ++i) x[i] = xyz[i] * scales[k];
        CHECK_RC(kin_clearance(a, x, INFINITY, &c, parts, NULL), k < 4 ? KIN_OK : KIN_EGEOM);
        if (k < 4) {
            CHECK_CLOSE(c / scales[k], 1.0, 1e-12); /* the bar 3-4 over the panel */
            CHECK(parts[0] == KIN_PART_BAR && parts[1] == 3 && parts[2] == KIN_PART_PANEL && parts[3] == 0);
            /* the bar 3-4 moved to pierce the panel: clearance 0 */
            x[9] = x[10] = 0.25 * scales[k], x[11] = -scales[k];
            x[12] = x[13] = 0.25 * scales[k];
            CHECK_RC(kin_clearance(a, x, INFINITY, &c, parts, NULL), KIN_OK);
            CHECK(c == 0.0 && parts[1] == 3 && parts[2] == KIN_PART_PANEL);
        } else {
            CHECK(c == INFINITY && parts[0] == -1);
            CHECK(strstr(kin_last_error(a), "beyond") != NULL);
        }
    }
    kin_assembly_free(a);
}

int main(void)
{
    absurd_sizes();
    overflowing_geometry();
    second_order_sizes();
    solvers();
    branch_paths();
    sail_params();
    gsl_handler();
    symmetry_two_joints();
    non_utf8_names();
    clearance_far();
    TEST_REPORT("test_hostile");
}
