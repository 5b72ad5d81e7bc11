/* The two factorization modes of kin_step (kin_options.factorization):
 * KIN_STEP_LU follows the same paths as the default KIN_STEP_SVD, to the
 * corrector's position tolerance, keeps the strain within corrector_tol,
 * falls back to the SVD analysis where a step lands near a bifurcation
 * (the three-bar linkage's R^C), uses a QR (LQ) of the bordered matrix when
 * redundant bars make it tall, and rejects invalid mode values. No timing. */
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "path/path.h"
#include "libkin.h"
#include "sail_states.h"
#include "step_compare.h"

static void set_mode(kin_assembly *a, int mode)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = mode;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
}

static void invalid_options(void)
{
    kin_assembly *a = threebar_at(PI / 3);
    kin_options o = {.size = sizeof o}, keep = {.size = sizeof keep};
    kin_options_default(&o);
    CHECK(o.factorization == KIN_STEP_SVD);
    kin_get_options(a, &keep);
    const int bad[] = {-1, 3, 99};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        o.factorization = bad[i];
        CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
        CHECK(strstr(kin_last_error(a), "factorization") != NULL);
    }
    kin_get_options(a, &o);
    CHECK(memcmp(&o, &keep, sizeof o) == 0);
    kin_assembly_free(a);
}

/* Follow the same path in both modes, comparing the points after every
 * step. Returns the number of steps taken. */
static int same_path(kin_assembly *svd, kin_assembly *lu, int steps, double delta, const char *name)
{
    int n = kin_njoints(svd) * kin_dim(svd), done = 0;
    double *x1 = malloc(sizeof(double) * (size_t)n), *x2 = malloc(sizeof(double) * (size_t)n);
    set_mode(lu, KIN_STEP_LU);
    kin_options o = {.size = sizeof o};
    /* automatic steps with the SVD mode's amplitudes: the same points */
    kin_get_options(lu, &o);
    o.step_control = KIN_STEP_CONTROL_SHARED;
    CHECK_RC(kin_set_options(lu, &o), KIN_OK);
    kin_get_options(svd, &o);
    double worst = 0.0, worst_strain = 0.0, vr_ratio_max = 0.0, vr_ratio_min = INFINITY;
    int fact_svd = 0, fact_lu = 0, fallbacks = 0;
    for (int k = 0; k < steps; ++k) {
        kin_step_info i1 = {.size = sizeof i1}, i2 = {.size = sizeof i2};
        int rc1 = kin_step(svd, delta, &i1), rc2 = kin_step(lu, delta, &i2);
        CHECK_RC(rc1, KIN_OK);
        CHECK_RC(rc2, KIN_OK);
        if (rc1 || rc2) break;
        ++done;
        fact_svd += i1.factorizations;
        fact_lu += i2.factorizations;
        kin_get_coords(svd, x1);
        kin_get_coords(lu, x2);
        double diff = max_diff(n, x1, x2);
        worst = fmax(worst, diff);
        CHECK(diff <= path_tol(svd, done));
        CHECK(i1.m_internal == 1 && i2.m_internal == 1);
        CHECK(kin_max_strain(svd) <= o.corrector_tol);
        CHECK(kin_max_strain(lu) <= o.corrector_tol);
        worst_strain = fmax(worst_strain, fmax(kin_max_strain(svd), kin_max_strain(lu)));
        /* same path length, tangent and step amplitude */
        CHECK_CLOSE(kin_path_length(lu), kin_path_length(svd), path_tol(svd, done));
        CHECK_CLOSE(i2.delta, i1.delta, 0.0);
        /* the LU mode's v_r is an upper-bound estimate (a Rayleigh quotient)
         * unless the step fell back to an SVD (then the analysis is current) */
        kin_analysis an = {.size = sizeof an};
        if (kin_get_analysis(lu, &an) == KIN_OK) {
            ++fallbacks;
            CHECK_CLOSE(i2.v_r, an.v_r, 0.0);
        } else {
            /* against the SVD of the same point (a copy, so that the LU
             * handle goes on without an analysis) */
            kin_assembly *c = NULL;
            CHECK_RC(kin_assembly_clone(lu, &c), KIN_OK);
            CHECK_RC(kin_analyse(c, &an), KIN_OK);
            double r = i2.v_r / an.v_r;
            vr_ratio_max = fmax(vr_ratio_max, r);
            vr_ratio_min = fmin(vr_ratio_min, r);
            kin_assembly_free(c);
        }
    }
    /* the estimate never undershoots beyond rounding and stays close */
    if (vr_ratio_min <= vr_ratio_max) {
        CHECK(vr_ratio_min >= 1.0 - 1e3 * DBL_EPSILON);
        CHECK(vr_ratio_max <= 2.0);
    }
    printf("%-28s %3d steps: max |x_svd - x_lu| %.2e (allowed %.1e), max strain %.1e, "
           "factorizations %d (SVD) / %d (LU, %d SVD fallbacks), v_r estimate / v_r in [%.6f, %.6f]\n",
           name, done, worst, path_tol(svd, done), worst_strain, fact_svd, fact_lu, fallbacks,
           vr_ratio_min, vr_ratio_max);
    free(x1);
    free(x2);
    return done;
}

static void threebar_lap(double delta)
{
    kin_assembly *s = threebar_at(PI / 3), *l = NULL;
    CHECK_RC(kin_assembly_clone(s, &l), KIN_OK);
    char name[64];
    snprintf(name, sizeof name, "three-bar P1 lap, delta %.4f", delta);
    /* a lap is 2*sqrt(2)*pi long: through R^C and R^A */
    int steps = (int)(2.0 * sqrt(2.0) * PI / delta);
    CHECK(same_path(s, l, steps, delta, name) == steps);
    /* still on the parallelogram: J2 = J1 + (1, 0) */
    double xyz[8];
    kin_get_coords(l, xyz);
    CHECK_CLOSE(xyz[2] - xyz[0], 1.0, path_tol(l, steps));
    CHECK_CLOSE(xyz[3] - xyz[1], 0.0, path_tol(l, steps));
    kin_assembly_free(s);
    kin_assembly_free(l);
}

static void hex_sail(void)
{
    kin_assembly *s = test_sail(6, 2), *l = NULL;
    CHECK(s != NULL);
    if (!s) return;
    CHECK_RC(test_make_generic(s, 0.3), KIN_OK);
    CHECK_RC(kin_assembly_clone(s, &l), KIN_OK);
    int n = 3 * kin_njoints(s);
    double *x0 = malloc(sizeof(double) * (size_t)n), *x1 = malloc(sizeof(double) * (size_t)n);
    kin_get_coords(s, x0);
    int steps = same_path(s, l, 30, 0.0, "hexagonal sail, generic");
    /* and back by the same path length: both modes return to the same
     * point, near the start (the chord sum is not the arc length, so the
     * last step lands only to O(delta^2) of the start) */
    kin_step_info info = {.size = sizeof info};
    int back = 0;
    while (kin_path_length(l) > 0.0 && back < 3 * steps) {
        double d = -fmin(kin_path_length(l), 0.1 * l->rms_length);
        CHECK_RC(kin_step(l, d, &info), KIN_OK);
        CHECK_RC(kin_step(s, d, &info), KIN_OK);
        ++back;
    }
    kin_get_coords(l, x1);
    double closure = max_diff(n, x0, x1);
    kin_get_coords(s, x0);
    double modes = max_diff(n, x0, x1);
    printf("hexagonal sail, out and back: %d + %d steps, |x_svd - x_lu| %.2e, LU closure %.2e\n", steps, back,
           modes, closure);
    CHECK(modes <= path_tol(s, steps + back));
    CHECK(closure <= 1e-2 * l->rms_length);
    /* a clone continues exactly like its original */
    kin_assembly *c = NULL;
    CHECK_RC(kin_assembly_clone(l, &c), KIN_OK);
    CHECK_RC(kin_step(l, 0.0, &info), KIN_OK);
    CHECK_RC(kin_step(c, 0.0, &info), KIN_OK);
    kin_get_coords(l, x0);
    kin_get_coords(c, x1);
    CHECK(max_diff(n, x0, x1) == 0.0);
    /* an analysis on demand does not disturb the path */
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_get_analysis(l, &an), KIN_ESTATE);
    double *t = malloc(sizeof(double) * (size_t)kin_nfree(l));
    CHECK_RC(kin_get_tangent(l, t, kin_nfree(l)), KIN_OK);
    CHECK_RC(kin_analyse(l, &an), KIN_OK);
    CHECK(an.m_internal == 1);
    CHECK_RC(kin_step(l, 0.0, &info), KIN_OK);
    CHECK_RC(kin_step(c, 0.0, &info), KIN_OK);
    kin_get_coords(l, x0);
    kin_get_coords(c, x1);
    CHECK(max_diff(n, x0, x1) <= path_tol(l, 1));
    free(t);
    free(x0);
    free(x1);
    kin_assembly_free(c);
    kin_assembly_free(s);
    kin_assembly_free(l);
}

/* From th0 on P1, one step aimed (along the tangent, corrected orthogonally
 * to it) at joint angle th1 near R^C (th = 0): sqrt(2) sin(th1 - th0) is
 * the step amplitude that lands there. */
static void land_near_rc(double th1, int want_fallback, int want_m_internal)
{
    const double th0 = 0.05;
    double delta = sqrt(2.0) * sin(th1 - th0);
    kin_assembly *s = threebar_at(th0), *l = NULL;
    CHECK_RC(kin_assembly_clone(s, &l), KIN_OK);
    set_mode(l, KIN_STEP_LU);
    kin_step_info i1 = {.size = sizeof i1}, i2 = {.size = sizeof i2};
    CHECK_RC(kin_step(s, delta, &i1), KIN_OK);
    /* a first LU-mode step analyses its start point by SVD; the landing point
     * costs one LU and, if it falls back, one more SVD */
    CHECK_RC(kin_step(l, delta, &i2), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    int have = kin_get_analysis(l, &an) == KIN_OK;
    CHECK(have == want_fallback);
    CHECK(i2.factorizations == (want_fallback ? 3 : 2));
    CHECK(i1.m_internal == want_m_internal);
    CHECK(i2.m_internal == want_m_internal);
    if (have) {
        CHECK(an.m_internal == want_m_internal);
        CHECK_CLOSE(i2.v_r, an.v_r, 0.0);
    }
    double x1[8], x2[8];
    kin_get_coords(s, x1);
    kin_get_coords(l, x2);
    CHECK(max_diff(8, x1, x2) <= path_tol(s, 1));
    printf("three-bar step to angle %.0e from R^C: m_internal %d (SVD) / %d (LU), LU fell back to SVD: %s, "
           "v_r %.2e, |x_svd - x_lu| %.1e\n",
           th1, i1.m_internal, i2.m_internal, have ? "yes" : "no", i2.v_r, max_diff(8, x1, x2));
    if (want_m_internal >= 2) {
        /* both stop at the bifurcation until a direction is chosen */
        CHECK_RC(kin_step(l, 0.0, &i2), KIN_EBIFURCATION);
        CHECK_RC(kin_step(s, 0.0, &i1), KIN_EBIFURCATION);
    } else {
        CHECK_RC(kin_step(l, -0.05, &i2), KIN_OK);
        CHECK_RC(kin_step(s, -0.05, &i1), KIN_OK);
        kin_get_coords(s, x1);
        kin_get_coords(l, x2);
        CHECK(max_diff(8, x1, x2) <= path_tol(s, 2) / fmax(fabs(th1), 1e-3));
    }
    kin_assembly_free(s);
    kin_assembly_free(l);
}

/* Leaving a bifurcation along a chosen direction (Newton from the start,
 * since the start point has two internal mechanisms): the three-bar
 * linkage's R^C along the parallelogram mode P1, in both modes. */
static void leave_rc(void)
{
    kin_assembly *s = NULL, *l = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &s), KIN_OK);
    CHECK_RC(kin_assembly_clone(s, &l), KIN_OK);
    set_mode(l, KIN_STEP_LU);
    const double dir[4] = {0, 1, 0, 1};
    CHECK_RC(kin_path_set_direction(s, dir, 4), KIN_OK);
    CHECK_RC(kin_path_set_direction(l, dir, 4), KIN_OK);
    kin_step_info i1 = {.size = sizeof i1}, i2 = {.size = sizeof i2};
    CHECK_RC(kin_step(s, 1e-3, &i1), KIN_OK);
    CHECK_RC(kin_step(l, 1e-3, &i2), KIN_OK);
    CHECK(i1.m_internal == 1 && i2.m_internal == 1);
    int steps = same_path(s, l, 20, 0.05, "three-bar leaving R^C on P1");
    CHECK(steps == 20);
    double xyz[8];
    kin_get_coords(l, xyz);
    CHECK_CLOSE(xyz[2] - xyz[0], 1.0, path_tol(l, steps + 1));
    CHECK_CLOSE(xyz[3] - xyz[1], 0.0, path_tol(l, steps + 1));
    kin_assembly_free(s);
    kin_assembly_free(l);
}

/* Redundant bars: three parallel cranks of length 1 carry a translating
 * triangle (nfree 6, nbars 6, s = 1 and m = 1 along the path), so the
 * bordered matrix [C; t^T] is 7 x 6 and the LU mode uses its QR (LQ). */
static void redundant_cranks(void)
{
    const double th = PI / 3, c = cos(th), s = sin(th);
    /* J1, J2, J3 free; S1, S2, S3 fixed */
    double xyz[12] = {c, s, 1.0 + c, s, 0.5 + c, 0.3 + s, 0, 0, 1.0, 0, 0.5, 0.3};
    unsigned char fixed[12] = {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
    int bars[12] = {3, 0, 4, 1, 5, 2, 0, 1, 1, 2, 0, 2};
    kin_assembly *a = NULL, *b = NULL;
    CHECK_RC(kin_assembly_create(2, 6, xyz, fixed, 6, bars, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return;
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 1 && an.s == 1);
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    int steps = same_path(a, b, 12, 0.1, "redundant cranks (QR)");
    CHECK(steps == 12);
    /* the LU mode did not analyse by SVD on the way */
    CHECK_RC(kin_get_analysis(b, &an), KIN_ESTATE);
    /* still a translating triangle on cranks of length 1 */
    kin_get_coords(b, xyz);
    for (int j = 0; j < 3; ++j)
        CHECK_CLOSE(hypot(xyz[2 * j] - xyz[6 + 2 * j], xyz[2 * j + 1] - xyz[7 + 2 * j]), 1.0, 1e-12);
    kin_assembly_free(a);
    kin_assembly_free(b);
}

/* The locator's forward calculations (kin__step_predicted) analyse by SVD
 * in either mode: the locator reads the singular values of the point. */
static void predicted_step_is_analysed(void)
{
    kin_assembly *a = threebar_at(PI / 3);
    set_mode(a, KIN_STEP_LU);
    kin_step_info info = {.size = sizeof info};
    CHECK_RC(kin_step(a, 0.1, &info), KIN_OK);
    double xyz[8], t[4], pred[4];
    kin_get_coords(a, xyz);
    CHECK_RC(kin_get_tangent(a, t, 4), KIN_OK);
    for (int i = 0; i < 4; ++i) pred[i] = xyz[i] + 0.05 * t[i];
    CHECK_RC(kin__step_predicted(a, 0.05, pred, &info), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
    CHECK(an.m_internal == 1);
    kin_assembly_free(a);
}

int main(void)
{
    invalid_options();
    threebar_lap(0.1);
    threebar_lap(0.0371);
    hex_sail();
    land_near_rc(0.0, 1, 2);  /* on R^C: the SVD finds m_internal = 2 */
    land_near_rc(1e-7, 1, 1); /* v_r / v_max ~ 5e-8: SVD fallback, still a path point */
    land_near_rc(0.02, 0, 1); /* v_r / v_max ~ 1e-2: no SVD */
    leave_rc();
    redundant_cranks();
    predicted_step_is_analysed();
    TEST_REPORT("test_step_modes");
}
