/* Finite paths out of the hexagonal sail's flat state (paper 3.4): every real
 * second-order solution of the complete solver (29828 of 2^15), both signs,
 * each followed to path length l (default 0.1) with kin_branch_paths; how
 * many exist, leave along U_m beta (the tangent check), and are distinct by
 * eq. 22. Not a test: prints a summary.
 * usage: bench_flat_paths [l] [threads] */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

int main(int argc, char **argv)
{
    print_blas();
    double l = argc > 1 ? atof(argv[1]) : 0.1;
    int threads = argc > 2 ? atoi(argv[2]) : 2;
    kin_assembly *a = test_sail(6, 2);
    kin_analysis an = {.size = sizeof an};
    if (!a || kin_analyse(a, &an)) return 1;
    int m = an.m_internal, s = 0, maxsol = 1 << an.s, nsol = 0;
    double *Q = malloc(sizeof(double) * (size_t)m * m * an.s);
    double *betas = malloc(sizeof(double) * (size_t)m * maxsol);
    kin_branch_path *paths = malloc(sizeof(kin_branch_path) * 2 * (size_t)maxsol);
    if (paths) paths[0].size = sizeof *paths;
    if (!Q || !betas || !paths || kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s)) return 1;
    kin_homotopy_info hi = {.size = sizeof hi};
    double t0 = now();
    if (kin_quadrics_homotopy(m, s, Q, 1, threads, betas, maxsol, &nsol, NULL, &hi)) return 1;
    double t1 = now();
    printf("flat state: m = %d, s = %d; complete solver: %d paths, %d real (%d distinct), %d complex, %d singular, "
           "%d failed in %.1f s\n",
           m, s, hi.paths, hi.real, hi.real_distinct, hi.nonreal, hi.singular, hi.failed, t1 - t0);
    int nd = 0;
    if (kin_branch_paths(a, betas, nsol, l, paths, NULL, &nd)) return 1;
    double t2 = now();
    int exists = 0, tangent = 0, reached = 0;
    for (int i = 0; i < 2 * nsol; ++i) {
        exists += paths[i].exists;
        tangent += paths[i].exists && paths[i].tangent_ok;
        reached += paths[i].exists && paths[i].length >= l * (1.0 - 1e-9);
    }
    printf("finite paths to l = %g: %d directed candidates, %d exist (first step converged), %d leave along "
           "U_m beta (|cos| >= 0.99), %d reach l, %d distinct (eq. 22); %.1f s\n",
           l, 2 * nsol, exists, tangent, reached, nd, t2 - t1);
    /* the coinciding ones: do they reach l? */
    int *count = calloc((size_t)nd, sizeof(int)), shared_reached = 0, shared_short = 0;
    for (int i = 0; count && i < 2 * nsol; ++i)
        if (paths[i].path_id >= 0) count[paths[i].path_id]++;
    for (int i = 0; count && i < 2 * nsol; ++i)
        if (paths[i].path_id >= 0 && count[paths[i].path_id] > 1) {
            if (paths[i].length >= l * (1.0 - 1e-9)) shared_reached++;
            else shared_short++;
        }
    printf("candidates sharing a path with another: %d that reach l, %d that stop short\n", shared_reached,
           shared_short);
    free(count);
    free(Q);
    free(betas);
    free(paths);
    kin_assembly_free(a);
    return 0;
}
