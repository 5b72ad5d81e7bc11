/* Why endpoints are left unproven (issue 38: "the octagonal 2-loop sail's
 * unproven count ... with the reason for each class left"): a sample of the
 * complete solver's paths on a sail's flat state (kin_quadrics_homotopy_range,
 * the plain start system, `ranges` contiguous ranges spread over the 2^s
 * paths), each endpoint given to the prover (homotopy/certify/, the
 * library's own test with its input width HOM_PROVE_Q_WIDTH) and sorted by
 * outcome: proven at 53 bits, proven after refinement (128/256 bits),
 * refused, or no point to test (the tracker lost the path or Newton at t = 1
 * did not converge). Per class: the count and the tracker's condition number
 * |J|_F |J^-1|_F at the endpoint (min, median, max), the quantity that
 * decides whether a root can be proven for every system within the input
 * width: the root moves by about cond x width when Q does.
 * usage: bench_prove_classes [n_sides (8)] [loops (2)] [paths (4096)] [ranges (8)] */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "homotopy/certify/homotopy_prove.h" /* the prover (private: this program links the static library) */
#include "libkin.h"
#include "sail_states.h"

enum { CLASSES = 4 };
static const char *const NAMES[CLASSES] = {"proven at 53 bits", "proven at 128/256 bits", "refused", "no point"};

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    int sides = argc > 1 ? atoi(argv[1]) : 8, loops = argc > 2 ? atoi(argv[2]) : 2;
    long want = argc > 3 ? atol(argv[3]) : 4096, ranges = argc > 4 ? atol(argv[4]) : 8;
    kin_assembly *a = test_sail(sides, loops);
    kin_analysis an = {.size = sizeof an};
    if (!a || kin_analyse(a, &an) || ranges < 1 || want < ranges) return 1;
    int m = an.m_internal, s = 0;
    double *Q = malloc(sizeof(double) * m * m * an.s);
    if (!Q || kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s) || s != m - 1) return 1;
    long total = 1L << s, per = want / ranges;
    print_blas();
    printf("sail %d,%d flat state: m = %d, s = %d; %ld of %ld paths in %ld ranges; input width 2^%d S_j\n", sides,
           loops, m, s, per * ranges, total, ranges, (int)log2(HOM_PROVE_Q_WIDTH));
    kin_homotopy_endpoint *ends = calloc((size_t)per, sizeof *ends);
    double *z = malloc(sizeof(double) * 2 * (size_t)m * (size_t)per);
    double *cond[CLASSES];
    long n[CLASSES] = {0};
    for (int c = 0; c < CLASSES; ++c) cond[c] = malloc(sizeof(double) * (size_t)(per * ranges));
    hom_prover *w = kin__prove_new(m, s, Q);
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = 2;
    double t0 = now();
    for (long r = 0; r < ranges && ends && z && w; ++r) {
        long first = r * (total / ranges);
        ends[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE;
        if (kin_quadrics_homotopy_range(m, s, Q, &o, first, per, ends, z)) return 1;
        for (long i = 0; i < per; ++i) {
            const kin_homotopy_endpoint *e = ends + i;
            double zr[HOM_PROVE_MAX_M], zi[HOM_PROVE_MAX_M];
            memcpy(zr, z + 2 * (size_t)m * i, sizeof(double) * m);
            memcpy(zi, z + 2 * (size_t)m * i + m, sizeof(double) * m);
            int c = 3;
            if (e->kind != KIN_HOM_END_FAILED && e->converged) {
                hom_proof pr;
                kin__prove_endpoint(w, zr, zi, e->kind == KIN_HOM_END_REAL, 256, &pr);
                c = pr.kind == HOM_PROOF_NONE ? 2 : pr.prec > 53 ? 1 : 0;
            }
            cond[c][n[c]++] = e->cond;
        }
    }
    printf("tracking and proving: %.1f s wall\n", now() - t0);
    printf("%-24s %8s %10s %10s %10s\n", "class", "paths", "cond min", "median", "max");
    for (int c = 0; c < CLASSES; ++c) {
        qsort(cond[c], (size_t)n[c], sizeof(double), cmp);
        if (n[c])
            printf("%-24s %8ld %10.3g %10.3g %10.3g\n", NAMES[c], n[c], cond[c][0], cond[c][n[c] / 2],
                   cond[c][n[c] - 1]);
        else
            printf("%-24s %8ld\n", NAMES[c], n[c]);
    }
    kin__prove_free(w);
    kin__prove_thread_end();
    for (int c = 0; c < CLASSES; ++c) free(cond[c]);
    free(ends), free(z), free(Q);
    kin_assembly_free(a);
    return 0;
}
