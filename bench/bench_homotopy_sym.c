/* The complete solver with and without symmetry on the hexagonal sail's
 * flat state (sail 6, 2: m = 16, s = 15, 32768 roots) in one run: wall and
 * CPU seconds, paths tracked, the accounting, and the real roots compared
 * root by root. The symmetry group is found by kin_mechanism_group
 * (kin_symmetry.h): for the hexagonal sail the rotations by 0, 120 and 240
 * degrees about the z axis through the centroid and the mirror z -> -z of
 * the flat state, acting on beta by R = U^T P U (U: the internal
 * mechanisms, P: the action on free coordinates); any sail works.
 * The symmetric solver's route: "auto" (kin_quadrics_homotopy_sym: the
 * equivariant start system where a cyclic subgroup permutes coordinates,
 * as for the hexagonal sail, else the monodromy) or "monodromy" (always:
 * the parameter trackers of homotopy_param*.c).
 * usage: bench_homotopy_sym [n_sides (6)] [loops (2)] [runs (1)] [auto|monodromy (auto)] */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "homotopy/symmetric/homotopy_sym.h"
#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"
#include "root_match.h"

enum { THREADS = 2, MAXG = 64 };

static double cpu(void) { return (double)clock() / CLOCKS_PER_SEC; }

static int match(int m, int n, const double *a, const double *b) { return unmatched_roots(m, n, a, b, 1e-8); }

int main(int argc, char **argv)
{
    print_blas();
    int sides = argc > 1 ? atoi(argv[1]) : 6, loops = argc > 2 ? atoi(argv[2]) : 2;
    int runs = argc > 3 ? atoi(argv[3]) : 1;
    int route = argc > 4 && !strcmp(argv[4], "monodromy") ? KIN__SYM_MONODROMY : KIN__SYM_AUTO;
    if (argc > 4 && route == KIN__SYM_AUTO && strcmp(argv[4], "auto")) {
        fprintf(stderr, "usage: bench_homotopy_sym [n_sides] [loops] [runs] [auto|monodromy]\n");
        return 1;
    }
    kin_assembly *a = test_sail(sides, loops);
    kin_analysis an = {.size = sizeof an};
    if (!a || kin_analyse(a, &an)) return 1;
    int m = an.m_internal, s = 0, ng = 0;
    double *Q = malloc(sizeof(double) * m * m * an.s);
    double *R = malloc(sizeof(double) * MAXG * m * m);
    if (kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s) || s != m - 1) return 1;
    if (kin_mechanism_group(a, MAXG, R, &ng)) {
        fprintf(stderr, "bench_homotopy_sym: %s\n", kin_last_error(a));
        return 1;
    }
    int N = 1 << s;
    double *b0 = malloc(sizeof(double) * m * N), *b1 = malloc(sizeof(double) * m * N);
    printf("sail %d,%d flat: m = %d, s = %d, %d paths, %d symmetries found, route %s; load: ", sides, loops, m, s, N,
           ng, route == KIN__SYM_MONODROMY ? "monodromy" : "auto");
    fflush(stdout);
    if (system("cat /proc/loadavg")) printf("\n");
    printf("%-6s %8s %8s %7s %7s %7s %6s %6s %6s %5s %4s %4s %6s\n", "solver", "wall[s]", "cpu[s]", "paths",
           "loops", "to Q", "real", "dist", "cmplx", "sing", "fail", "dup", "unpair");
    for (int run = 0; run < runs; ++run) {
        kin_homotopy_options o;
        kin_homotopy_options_default(&o);
        o.nthreads = THREADS;
        kin_homotopy_info h0 = {.size = sizeof h0}, h1 = {.size = sizeof h1};
        kin_homotopy_sym_info si = {.size = sizeof si};
        int n0 = 0, n1 = 0;
        char err[256] = "";
        double t0 = now(), c0 = cpu();
        int rc0 = kin_quadrics_homotopy_ex(m, s, Q, &o, b0, N, &n0, NULL, &h0);
        double w0 = now() - t0, cp0 = cpu() - c0;
        t0 = now(), c0 = cpu();
        int rc1 = kin__quadrics_homotopy_sym_route(route, m, s, Q, ng, R, &o, b1, N, &n1, NULL, &h1, &si, err,
                                                   sizeof err);
        double w1 = now() - t0, cp1 = cpu() - c0;
        if (rc0 || rc1) {
            printf("plain: %s; sym: %s %s\n", kin_strerror(rc0), kin_strerror(rc1), err);
            continue;
        }
        printf("%-6s %8.2f %8.2f %7d %7s %7d %6d %6d %6d %5d %4d %4d %6d\n", "plain", w0, cp0, h0.paths, "-", h0.paths,
               h0.real, h0.real_distinct, h0.nonreal, h0.singular, h0.failed, h0.duplicates, h0.unpaired);
        printf("%-6s %8.2f %8.2f %7d %7d %7d %6d %6d %6d %5d %4d %4d %6d\n", "sym", w1, cp1,
               si.monodromy_paths + si.final_paths, si.monodromy_paths, si.final_paths, h1.real, h1.real_distinct,
               h1.nonreal, h1.singular, h1.failed, h1.duplicates, h1.unpaired);
        printf("steps per path: plain %.1f (+%.1f rejected); sym loops %.1f (+%.1f), to Q %.1f (+%.1f)\n",
               (double)h0.steps / h0.paths, (double)h0.rejected / h0.paths,
               si.monodromy_paths ? si.monodromy_steps / si.monodromy_paths : 0.0,
               si.monodromy_paths ? si.monodromy_rejected / si.monodromy_paths : 0.0,
               (double)h1.steps / si.final_paths, (double)h1.rejected / si.final_paths);
        printf("group %d, orbits %d, found %d; wall ratio %.2f, cpu ratio %.2f; real roots: %d of sym not in plain, "
               "%d of plain not in sym\n",
               si.group, si.orbits, si.found, w0 / w1, cp0 / cp1, n1 == n0 ? match(m, n1, b1, b0) : -1,
               n1 == n0 ? match(m, n0, b0, b1) : -1);
        fflush(stdout);
    }
    free(Q), free(R), free(b0), free(b1);
    kin_assembly_free(a);
    return 0;
}
