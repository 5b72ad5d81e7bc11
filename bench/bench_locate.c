/* Bifurcation location: factorizations and final accuracy of both methods
 * over several step sizes, on the three-bar linkage (R^C along P1 and R^B
 * along "J2 at S1") and the hexagonal sail's R^B (approached back along one
 * of its folding paths). Not a test: prints a table and writes
 * bench_locate.csv for bench/plot_locate.py. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <time.h>

#include "libkin.h"
#include "sail_states.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static kin_assembly *threebar_start(int path)
{
    kin_assembly *a = NULL;
    kin_model_threebar(KIN_THREEBAR_RC, &a);
    double x[8];
    kin_get_coords(a, x);
    if (path == 0) { x[0] = cos(1.0); x[1] = sin(1.0); x[2] = x[0] + 1; x[3] = x[1]; }
    else { x[0] = cos(1.0); x[1] = sin(1.0); x[2] = 0; x[3] = 0; }
    kin_set_coords(a, x);
    kin_options o;
    kin_get_options(a, &o);
    o.step_fraction = 1.0;
    kin_set_options(a, &o);
    return a;
}

static kin_assembly *hex_start(void)
{
    kin_assembly *a = test_sail(6, 2);
    test_hex_to_RB(a);
    kin_analysis an;
    kin_analyse(a, &an);
    int s;
    double Q[48], betas[64], U[46 * 4], dir[46];
    kin_second_order(a, KIN_Q_EXACT, 1, Q, 48, &s);
    int nsol;
    kin_quadrics_scan(4, 3, Q, 256, 5, betas, 16, &nsol, NULL);
    kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, 46, 4);
    for (int i = 0; i < 46; ++i) {
        dir[i] = 0;
        for (int k = 0; k < 4; ++k) dir[i] += U[i + 46 * k] * betas[k];
    }
    kin_path_set_direction(a, dir, 46);
    kin_step(a, 1e-3, NULL);
    for (int k = 0; k < 8; ++k) kin_step(a, 0.05, NULL);
    return a;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : ".";
    char path[1024];
    snprintf(path, sizeof path, "%s/bench_locate.csv", dir);
    FILE *csv = fopen(path, "w");
    if (!csv) return 1;
    fprintf(csv, "case,method,delta,event,steps,factorizations,forward,vr_rel,seconds,ok\n");
    const char *cases[3] = {"three-bar R^C (P1)", "three-bar R^B (J2 at S1)", "hex sail R^B"};
    const double deltas[] = {0.02, 0.05, 0.1, 0.2, 0.4};
    printf("%-26s %-6s %6s %6s %6s %8s %8s %10s %9s\n", "case", "method", "delta", "event", "steps",
           "factor.", "forward", "v_r/v_max", "ms");
    for (int c = 0; c < 3; ++c)
        for (int m = 0; m < 2; ++m)
            for (size_t d = 0; d < sizeof deltas / sizeof deltas[0]; ++d) {
                double delta = c == 2 ? -deltas[d] / 2 : deltas[d];
                kin_assembly *a = c == 2 ? hex_start() : threebar_start(c);
                kin_locate_options o;
                kin_locate_options_default(&o);
                o.method = m;
                o.delta = delta;
                kin_locate_info info;
                double t0 = now();
                int rc = kin_locate_next(a, &o, &info);
                double ms = 1e3 * (now() - t0);
                printf("%-26s %-6s %6.3f %6d %6d %8d %8d %10.2e %9.2f%s\n", cases[c], m ? "fast" : "paper", delta,
                       info.event, info.steps, info.factorizations, info.forward, info.v_r_rel, ms,
                       rc ? "  (not located)" : "");
                fprintf(csv, "%s,%s,%.3f,%d,%d,%d,%d,%.3e,%.6f,%d\n", cases[c], m ? "fast" : "paper", delta,
                        info.event, info.steps, info.factorizations, info.forward, info.v_r_rel, ms / 1e3, rc == 0);
                kin_assembly_free(a);
            }
    fclose(csv);
    return 0;
}
