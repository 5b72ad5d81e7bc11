/* Bifurcation location: factorizations, time and final accuracy of the three
 * methods (the paper's quadratic, the fast Hermite method, Illinois on the
 * test function) over several step sizes, on
 *   - the three-bar linkage: R^C along P1, R^B along "J2 held at S1";
 *   - the hexagonal sail: R^B approached back along one of its 8 paths,
 *     the flat state R^A (15 singular values vanish) approached from R^B
 *     along the folding path, and R^B from the flat state along it.
 * Not a test: prints a table and writes bench_locate.csv for
 * bench/plot_locate.py. The time of location alone is that of
 * kin_locate_next from the last point before detection minus one step.
 * usage: bench_locate [outdir] */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <time.h>

#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

static kin_assembly *threebar_start(int path)
{
    kin_assembly *a = NULL;
    kin_model_threebar(KIN_THREEBAR_RC, &a);
    double x[8];
    kin_get_coords(a, x);
    if (path == 0) { x[0] = cos(1.0); x[1] = sin(1.0); x[2] = x[0] + 1; x[3] = x[1]; }
    else { x[0] = cos(1.0); x[1] = sin(1.0); x[2] = 0; x[3] = 0; }
    kin_set_coords(a, x);
    return a;
}

/* R^B left along one of its 8 paths (a second-order solution of the root
 * scan) and followed 0.4 away */
static kin_assembly *hex_rb_start(void)
{
    kin_assembly *a = test_sail(6, 2);
    test_hex_to_RB(a);
    kin_analysis an = {.size = sizeof an};
    kin_analyse(a, &an);
    int s, nsol;
    double Q[48], betas[64], dir[46];
    kin_second_order(a, KIN_Q_EXACT, 1, Q, 48, &s);
    kin_quadrics_scan(4, 3, Q, 256, 5, betas, 16, &nsol, NULL);
    test_mechanism(a, betas, 4, dir);
    kin_path_set_direction(a, dir, 46);
    kin_step(a, 1e-3, NULL);
    for (int k = 0; k < 8; ++k) kin_step(a, 0.05, NULL);
    return a;
}

static kin_assembly *copy(const kin_assembly *a)
{
    kin_assembly *b = NULL;
    kin_assembly_clone(a, &b);
    return b;
}

/* a copy of start moved `steps` steps of delta along its path */
static kin_assembly *advanced(const kin_assembly *start, double delta, int steps)
{
    kin_assembly *a = copy(start);
    for (int k = 0; k < steps; ++k)
        if (kin_step(a, delta, NULL)) break;
    return a;
}

enum { REPS = 3 }; /* timings: the best of REPS runs */

/* seconds of location alone: kin_locate_next from the last point before
 * detection (one step, then locating) minus that step with its test
 * function, each the best of REPS */
static double locate_seconds(const kin_assembly *pre, const kin_locate_options *o)
{
    double best_all = INFINITY, best_step = INFINITY, tau;
    for (int r = 0; r < REPS; ++r) {
        kin_assembly *a = copy(pre), *b = copy(pre);
        kin_locate_info info = {.size = sizeof info};
        double t0 = now();
        kin_locate_next(a, o, &info);
        double t1 = now();
        kin_step(b, o->delta, NULL);
        kin_test_function(b, &tau);
        double t2 = now();
        best_all = fmin(best_all, t1 - t0);
        best_step = fmin(best_step, t2 - t1);
        kin_assembly_free(a);
        kin_assembly_free(b);
    }
    return fmax(best_all - best_step, 0.0);
}

int main(int argc, char **argv)
{
    print_blas();
    const char *dir = argc > 1 ? argv[1] : ".";
    char path[1024];
    snprintf(path, sizeof path, "%s/bench_locate.csv", dir);
    FILE *csv = fopen(path, "w");
    if (!csv) {
        fprintf(stderr, "cannot write %s\n", path);
        return 1;
    }
    kin_assembly *starts[5] = {threebar_start(0), threebar_start(1), hex_rb_start(), NULL, NULL};
    if (test_hex_fold(&starts[3], &starts[4], NULL, NULL)) {
        fprintf(stderr, "could not build the hexagonal sail's fold\n");
        return 1;
    }
    const char *cases[5] = {"three-bar R^C (P1)", "three-bar R^B (J2 at S1)", "hex R^B (back along a path)",
                            "hex R^A (15 vanish)", "hex R^B (from R^A)"};
    const double sign[5] = {1, 1, -1, 1, 1};
    const double deltas[] = {0.01, 0.02, 0.05, 0.1, 0.2, 0.4};
    /* the paper's method also at the paper's own tolerance, 1e-6 */
    const int methods[4] = {KIN_LOCATE_FAST, KIN_LOCATE_ILLINOIS, KIN_LOCATE_PAPER, KIN_LOCATE_PAPER};
    const double tols[4] = {1e-10, 1e-10, 1e-10, 1e-6};
    const char *mnames[4] = {"fast", "illinois", "paper", "paper@1e-6"};
    fprintf(csv, "case,method,vr_tol,delta,event,steps,factorizations,forward,vr_rel,m,s,seconds,ok\n");
    printf("%-28s %-10s %6s %5s %5s %7s %7s %10s %5s %9s\n", "case", "method", "delta", "event", "steps",
           "factor.", "forward", "v_r/v_max", "m/s", "ms");
    for (int c = 0; c < 5; ++c)
        for (int mi = 0; mi < 4; ++mi)
            for (size_t d = 0; d < sizeof deltas / sizeof deltas[0]; ++d) {
                double delta = sign[c] * deltas[d];
                if (c >= 2 && deltas[d] > 0.2) continue; /* the sail's paths turn within 0.4 */
                kin_assembly *a = copy(starts[c]);
                kin_options op = {.size = sizeof op};
                kin_get_options(a, &op);
                op.step_fraction = 1.0; /* let delta, not the default clamp, set the step */
                kin_set_options(a, &op);
                kin_assembly *b = copy(a);
                kin_locate_options o = {.size = sizeof o};
                kin_locate_options_default(&o);
                o.method = methods[mi];
                o.vr_tol = tols[mi];
                o.delta = delta;
                kin_locate_info info = {.size = sizeof info};
                int rc = kin_locate_next(a, &o, &info);
                kin_assembly *pre = advanced(b, delta, info.steps - 1);
                double sec = locate_seconds(pre, &o);
                printf("%-28s %-10s %6.3f %5d %5d %7d %7d %10.2e %2d/%-2d %9.3f%s\n", cases[c], mnames[mi], delta,
                       info.event, info.steps, info.factorizations, info.forward, info.v_r_rel, info.m_internal,
                       info.s, 1e3 * sec, rc ? "  (not located)" : "");
                fprintf(csv, "%s,%s,%.0e,%.3f,%d,%d,%d,%d,%.3e,%d,%d,%.6f,%d\n", cases[c], mnames[mi], tols[mi], delta,
                        info.event, info.steps, info.factorizations, info.forward, info.v_r_rel, info.m_internal,
                        info.s, sec, rc == 0);
                fflush(stdout);
                kin_assembly_free(a);
                kin_assembly_free(b);
                kin_assembly_free(pre);
            }
    for (int c = 0; c < 5; ++c) kin_assembly_free(starts[c]);
    fclose(csv);
    return 0;
}
