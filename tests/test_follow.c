/* kin_follow_event: every directed branch out of a bifurcation ends in a
 * classified event (kin_follow.h). */
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

static const char *event_name(int e)
{
    static const char *n[] = {"none", "bifurcation", "near-miss", "closed-loop", "length", "steps", "failed"};
    return e >= 0 && e <= 6 ? n[e] : "?";
}

/* Follow every directed branch (2 per second-order solution) out of the
 * bifurcation a sits on; counts[event] += 1. Returns the number followed. */
static int follow_all_branches(kin_assembly *a, const kin_follow_options *o, int stride, int counts[7], double *ends,
                               int maxends, int keep_m, kin_assembly **kept, int verbose)
{
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    int m = an.m_internal, s = 0, nsol = 0, nf = kin_nfree(a);
    double *Q = malloc(sizeof(double) * (size_t)m * m * an.s), *betas = malloc(sizeof(double) * (size_t)m * 64);
    double *dir = malloc(sizeof(double) * (size_t)nf);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s), KIN_OK);
    kin_homotopy_info hi = {.size = sizeof hi};
    CHECK_RC(kin_quadrics_homotopy(m, s, Q, 1, 1, betas, 64, &nsol, NULL, &hi), KIN_OK);
    int n = 0;
    for (int k = 0; k < 2 * nsol; k += stride, ++n) {
        double beta[64];
        for (int i = 0; i < m; ++i) beta[i] = (k % 2 ? -1.0 : 1.0) * betas[m * (k / 2) + i];
        test_mechanism(a, beta, m, dir);
        kin_assembly *b = NULL;
        CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
        kin_follow_info fi = {.size = sizeof fi};
        int rc = kin_follow_event(b, dir, o, &fi);
        CHECK(rc == fi.status);
        CHECK(fi.event >= KIN_FOLLOW_BIFURCATION && fi.event <= KIN_FOLLOW_FAILED);
        counts[fi.event]++;
        if (verbose)
            printf("  branch %2d: %-11s rc %-12s steps %3d len %.4f v_r %.2e tol %.0e m %d s %d start %d (%.3g)%s%s\n", k,
                   event_name(fi.event), kin_status_name(rc), fi.steps, fi.length, fi.v_r_rel, fi.vr_tol_used,
                   fi.m_internal, fi.s, fi.at_start, fi.start_distance, rc ? ": " : "", rc ? kin_last_error(b) : "");
        if (ends && k < maxends) kin_get_coords(b, ends + (size_t)k * kin_njoints(b) * kin_dim(b));
        if (fi.event == KIN_FOLLOW_BIFURCATION) {
            kin_analysis e = {.size = sizeof e};
            CHECK(kin_get_analysis(b, &e) == KIN_OK && e.m_internal >= 2 && e.m_internal == fi.m_internal);
            CHECK(fi.v_r_rel <= fi.vr_tol_used && fi.vr_tol_used <= o->vr_floor);
            CHECK(kin_max_strain(b) <= 1e-9);
            if (kept && !*kept && fi.m_internal == keep_m) CHECK_RC(kin_assembly_clone(b, kept), KIN_OK);
        }
        kin_assembly_free(b);
    }
    free(Q);
    free(betas);
    free(dir);
    return n;
}

/* The three-bar linkage from R^C: both paths lead to the other
 * bifurcations (R^A along P1, R^B along P2) or around a loop back to R^C. */
static void threebar(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_follow_options o;
    kin_follow_options_default(&o);
    int counts[7] = {0};
    double ends[4 * 8];
    int n = follow_all_branches(a, &o, 1, counts, ends, 4, 0, NULL, 1);
    CHECK(n == 4);
    CHECK(counts[KIN_FOLLOW_BIFURCATION] + counts[KIN_FOLLOW_CLOSED_LOOP] == n);
    /* the ends: R^A (J1 = (-1,0), J2 = (0,0)) or R^B (J1 = (1,0), J2 =
     * (0,0)), paper Figure 1, each reached by one branch and its mirror */
    const double want[2][8] = {{-1, 0, 0, 0, 0, 0, 1, 0}, {1, 0, 0, 0, 0, 0, 1, 0}};
    int reached[2] = {0, 0};
    for (int k = 0; k < n && k < 4; ++k) {
        int hit = -1;
        for (int w = 0; w < 2; ++w) {
            int ok = 1;
            for (int i = 0; i < 8; ++i) ok &= fabs(ends[8 * k + i] - want[w][i]) <= 1e-6;
            if (ok) hit = w;
        }
        CHECK(hit >= 0);
        if (hit >= 0) reached[hit]++;
    }
    CHECK(reached[0] == 2 && reached[1] == 2);
    kin_assembly_free(a);
}

/* The hexagonal sail's R^B: 16 directed branches, none unexplained */
static void hex_rb(void)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL);
    CHECK_RC(test_hex_to_RB(a), KIN_OK);
    kin_follow_options o;
    kin_follow_options_default(&o);
    o.max_steps = 400;
    int counts[7] = {0};
    printf("hex sail R^B:\n");
    kin_assembly *rc = NULL;
    int n = follow_all_branches(a, &o, 1, counts, NULL, 0, 6, &rc, 1);
    CHECK(n == 16);
    CHECK(counts[KIN_FOLLOW_FAILED] == 0 && counts[KIN_FOLLOW_STEP_LIMIT] == 0);
    CHECK(counts[KIN_FOLLOW_BIFURCATION] >= 1);
    kin_assembly_free(a);
    /* R^C: the bifurcation with m = 6, s = 5 after R^B (docs/sail_study.md);
     * a sample of its 64 directed branches (all: bench/bench_follow_atlas) */
    CHECK(rc != NULL);
    if (!rc) return;
    int counts_c[7] = {0};
    printf("hex sail R^C:\n");
    n = follow_all_branches(rc, &o, 13, counts_c, NULL, 0, 0, NULL, 1);
    CHECK(n >= 5);
    CHECK(counts_c[KIN_FOLLOW_FAILED] == 0 && counts_c[KIN_FOLLOW_STEP_LIMIT] == 0);
    kin_assembly_free(rc);
}

/* The rhombus whose v_r has a non-zero minimum (test_locate.c): a near miss */
static void near_miss(void)
{
    const double xyz[8] = {cos(1.0), sin(1.0), cos(1.0) + 1, sin(1.0), 0, 0, 1, 0};
    const unsigned char fixed[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    const int bars[6] = {2, 0, 0, 1, 1, 3};
    const double L[3] = {1.0, 1.0 + 1e-4, 1.0};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 4, xyz, fixed, 3, bars, L, &a, NULL, 0), KIN_OK);
    CHECK_RC(kin_relax(a, 100, NULL), KIN_OK);
    kin_follow_options o;
    kin_follow_options_default(&o);
    o.delta = 0.05;
    kin_assembly *b = NULL; /* the same start, followed without relaxed attempts */
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    kin_follow_info fi = {.size = sizeof fi};
    CHECK_RC(kin_follow_event(a, NULL, &o, &fi), KIN_OK);
    printf("rhombus: %s after %d steps, v_r %.3g, %d attempts\n", event_name(fi.event), fi.steps, fi.v_r_rel,
           fi.attempts);
    CHECK(fi.event == KIN_FOLLOW_NEAR_MISS && fi.m_internal == 1 && fi.v_r_rel > 1e-4);
    CHECK(kin_max_strain(a) <= 1e-12);
    /* a minimum of v_r above sqrt(vr_floor) ends the follow without relaxed
     * attempts (docs/follow.md): at the point and v_r that the relaxed
     * attempts reach where they are made (vr_floor 1e-4: the minimum, about
     * 0.008, is below its square root; each attempt fails, the last on a
     * minimum above 1e-4) */
    if (b) {
        kin_follow_options o1 = o;
        o1.vr_floor = 1e-4;
        kin_follow_info f1 = {.size = sizeof f1};
        CHECK_RC(kin_follow_event(b, NULL, &o1, &f1), KIN_OK);
        double xa[8], xb[8], d = 0.0;
        kin_get_coords(a, xa);
        kin_get_coords(b, xb);
        for (int i = 0; i < 8; ++i) d = fmax(d, fabs(xa[i] - xb[i]));
        printf("rhombus, relaxed to 1e-4: %s after %d attempts, end %.3g from the other\n", event_name(f1.event),
               f1.attempts, d);
        CHECK(f1.event == fi.event);
        CHECK(d <= 4 * DBL_EPSILON && fabs(f1.v_r_rel - fi.v_r_rel) <= 4 * DBL_EPSILON);
        kin_assembly_free(b);
    }
    kin_assembly_free(a);
}

static int cancel_at(void *user, double done, double total)
{
    (void)total;
    return done >= *(double *)user;
}

/* every error path: arguments, sizes, options, a start without a branch,
 * a direction that is no branch, a cancel */
static void errors(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_follow_options o;
    kin_follow_options_default(&o);
    kin_follow_info fi = {.size = sizeof fi};
    double d[4] = {0, 1, 0, 1}, xyz0[8], xyz[8];
    kin_get_coords(a, xyz0);
    CHECK_RC(kin_follow_event(NULL, d, &o, &fi), KIN_ENULL);
    CHECK_RC(kin_follow_event(a, NULL, &o, &fi), KIN_EBIFURCATION);
    CHECK(fi.event == KIN_FOLLOW_NONE && fi.steps == 0);
    fi.size = 3;
    CHECK_RC(kin_follow_event(a, d, &o, &fi), KIN_EINVAL);
    fi.size = sizeof fi;
    kin_follow_options bad = o;
    bad.size = 0;
    CHECK_RC(kin_follow_event(a, d, &bad, &fi), KIN_EINVAL);
    bad = o;
    bad.vr_floor = 1e-12; /* below vr_tol */
    CHECK_RC(kin_follow_event(a, d, &bad, &fi), KIN_EINVAL);
    bad = o;
    bad.loop_tol = NAN;
    CHECK_RC(kin_follow_event(a, d, &bad, &fi), KIN_EINVAL);
    double nan_dir[4] = {0, NAN, 0, 1}, zero[4] = {0, 0, 0, 0};
    CHECK_RC(kin_follow_event(a, nan_dir, &o, &fi), KIN_EINVAL);
    CHECK_RC(kin_follow_event(a, zero, &o, &fi), KIN_EINVAL);
    CHECK(fi.event == KIN_FOLLOW_NONE);
    /* a first-order mechanism that is not a branch: the first chord leaves
     * along another direction */
    double mixed[4] = {0, 1, 0, 0};
    CHECK_RC(kin_follow_event(a, mixed, &o, &fi), KIN_EPATHJUMP);
    CHECK(fi.event == KIN_FOLLOW_FAILED && fi.status == KIN_EPATHJUMP && fi.tangent_cos < o.branch_cos);
    kin_get_coords(a, xyz);
    kin_assembly_free(a);
    /* nothing moved before following started */
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    CHECK_RC(kin_follow_event(a, nan_dir, &o, &fi), KIN_EINVAL);
    kin_get_coords(a, xyz);
    for (int i = 0; i < 8; ++i) CHECK(xyz[i] == xyz0[i]);
    /* a cancel after a few steps: FAILED, the assembly on the path */
    double stop = 5;
    CHECK_RC(kin_set_progress(a, cancel_at, &stop), KIN_OK);
    CHECK_RC(kin_follow_event(a, d, &o, &fi), KIN_ECANCELLED);
    CHECK(fi.event == KIN_FOLLOW_FAILED && fi.status == KIN_ECANCELLED && fi.steps >= 1);
    CHECK(kin_max_strain(a) <= 1e-12);
    kin_assembly_free(a);
    /* budgets */
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_assembly *b = NULL;
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    o.max_steps = 3;
    CHECK_RC(kin_follow_event(a, d, &o, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_STEP_LIMIT && fi.steps == 3);
    kin_follow_options_default(&o);
    o.max_length = 0.5;
    CHECK_RC(kin_follow_event(b, d, &o, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_LENGTH_LIMIT && fi.length >= 0.5 && fi.length < 0.5 + 0.2);
    kin_assembly_free(a);
    kin_assembly_free(b);
}

/* A lifted, relaxed hexagonal sail near its flat state: the flat state is
 * reached and located, to 1e-10 or the accuracy reachable there (never a
 * closed loop after a relaxed retry that moved back towards the start) */
static void lifted_hex(void)
{
    for (int k = 0; k < 3; ++k) {
        kin_assembly *a = test_sail(6, 2);
        CHECK(a != NULL);
        CHECK_RC(test_make_generic(a, 0.1 + 0.2 * k), KIN_OK);
        kin_follow_info fi = {.size = sizeof fi};
        CHECK_RC(kin_follow_event(a, NULL, NULL, &fi), KIN_OK);
        printf("lifted hex sail (%.1f): %s after %d steps, %d attempts, v_r %.2g, m %d s %d\n", 0.1 + 0.2 * k,
               event_name(fi.event), fi.steps, fi.attempts, fi.v_r_rel, fi.m_internal, fi.s);
        CHECK(fi.event == KIN_FOLLOW_BIFURCATION && fi.m_internal == 16 && fi.s == 15 && !fi.at_start);
        CHECK(fi.v_r_rel <= fi.vr_tol_used && fi.vr_tol_used <= 1e-6);
        kin_assembly_free(a);
    }
}

int main(void)
{
    errors();
    lifted_hex();
    threebar();
    near_miss();
    hex_rb();
    TEST_REPORT("test_follow");
}
