/* Root scan completeness against cost: for the square sail's flat state
 * (2^4 = 16 real solutions), the hexagonal sail's R^B (2^3 = 8) and its flat
 * state R^A (s = 15, 29828 real solutions, see bench_homotopy), the number of
 * distinct real second-order solutions the scan finds from 2^6 .. 2^14
 * starting points, and the seconds it takes. Not a test: prints a table and
 * writes bench_branches.csv for bench/plot_branches.py.
 * (bench_homotopy matches the scan's solutions to the complete solver's.) */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

static void scan(FILE *csv, const char *name, kin_assembly *a, int max_log2, int nreal)
{
    kin_analysis an = {.size = sizeof an};
    kin_analyse(a, &an);
    int m = an.m_internal, s = 0;
    double *Q = malloc(sizeof(double) * m * m * an.s);
    double *betas = malloc(sizeof(double) * m * 40000);
    kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s);
    for (int k = 6; k <= max_log2; ++k) {
        int starts = 1 << k, nsol = 0;
        kin_solve_info info = {.size = sizeof info};
        double t0 = now();
        kin_quadrics_scan(m, s, Q, starts, 11, betas, 40000, &nsol, &info);
        double t = now() - t0;
        printf("%-22s m=%2d s=%2d starts %6d: %5d of %d real solutions, %6d converged, %.3f s\n", name, m, s,
               starts, info.distinct, nreal, info.converged, t);
        fprintf(csv, "%s,%d,%d,%d,%d,%d,%.6f\n", name, m, s, starts, info.distinct, info.converged, t);
        fflush(stdout);
    }
    free(Q);
    free(betas);
}

int main(int argc, char **argv)
{
    print_blas();
    const char *dir = argc > 1 ? argv[1] : ".";
    int max_log2 = argc > 2 ? atoi(argv[2]) : 14;
    char path[1024];
    snprintf(path, sizeof path, "%s/bench_branches.csv", dir);
    FILE *csv = fopen(path, "w");
    if (!csv) return 1;
    fprintf(csv, "model,m,s,starts,distinct,converged,seconds\n");
    kin_assembly *a = test_sail(4, 1);
    scan(csv, "square sail flat", a, max_log2, 16);
    kin_assembly_free(a);
    a = test_sail(6, 2);
    test_hex_to_RB(a);
    scan(csv, "hexagonal sail R^B", a, max_log2, 8);
    kin_assembly_free(a);
    a = test_sail(6, 2);
    scan(csv, "hexagonal sail flat", a, max_log2, 29828);
    kin_assembly_free(a);
    fclose(csv);
    return 0;
}
