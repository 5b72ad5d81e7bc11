/* The pieces of an LU point of the follower's cheap steps (path/step_lu.c,
 * factor_point) at the hexagonal sail's size: one dgetrf, one dgetri (the
 * explicit (J^T)^-1), the same inverse by Gauss-Jordan (path/gauss_jordan.c,
 * what the follower uses), one solve by dgetrs (1 right-hand side) against
 * one product with the inverse (dgemv), and a 2-vector block (the slope's
 * subspace iteration) by dgetrs against dgemm. On a random dense N x N
 * matrix, and (N = 46) on the hexagonal sail's own bordered matrix
 * J^T = [H, t] at a regular point near its flat state, whose bar columns
 * are sparse. Prints microseconds per call (best of `rounds` rounds of many
 * calls, CPU time) and the number of solves above which the inverse pays at
 * one point. Not a test.
 *
 * usage: bench_lu_point [N [ROUNDS]]   (N default 46: the hexagonal sail's
 * free coordinates; ROUNDS default 5). Run with OPENBLAS_NUM_THREADS=1. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_common.h"
#include "libkin.h"
#include "model/internal.h"
#include "model/lapack.h"
#include "path/step_lu.h"
#include "sail_states.h"

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

enum { KIND_GETRF, KIND_GETRI, KIND_GJ, KIND_GETRS, KIND_GEMV, KIND_GETRS2, KIND_GEMM2, KINDS };
static const char *const NAMES[KINDS] = {"dgetrf", "dgetri (from the factors)", "Gauss-Jordan inverse",
                                         "dgetrs, 1 vector", "dgemv with the inverse", "dgetrs, 2 vectors",
                                         "dgemm with the inverse, 2 vectors"};

/* the hexagonal sail's bordered J^T = [H, t] (46 x 46) at a regular point
 * near the flat state (tests/sail_states.h); 0 when it is not square */
static int sail_matrix(double *A, int n)
{
    kin_assembly *a = test_sail(6, 2);
    kin_analysis an = {.size = sizeof an};
    int ok = a && test_make_generic(a, 0.3) == KIN_OK && kin_analyse(a, &an) == KIN_OK && kin_step(a, 0.0, NULL) == KIN_OK &&
             a->nf == n && a->nb + 1 == n && a->have_t;
    if (ok) {
        kin__build_H(a, a->xyz, A, n);
        memcpy(A + (size_t)a->nb * n, a->t, sizeof(double) * (size_t)n);
    }
    kin_assembly_free(a);
    return ok;
}

/* time the pieces on the matrix A (n x n); F, I, work, v, w, ipiv, perm scratch */
static int run(int n, int rounds, const char *label, const double *A, double *F, double *I, double *work, int lwork,
               double *v, double *w, int *ipiv, int *perm)
{
    size_t nn = (size_t)n * (size_t)n;
    int info = 0, one = 1, two = 2, sign = 0;
    for (int i = 0; i < 2 * n; ++i) v[i] = sin((double)i);
    memcpy(F, A, sizeof(double) * nn);
    dgetrf_(&n, &n, F, &n, ipiv, &info);
    if (info != 0) return 1;
    memcpy(I, F, sizeof(double) * nn);
    dgetri_(&n, I, &n, ipiv, work, &lwork, &info);
    if (info != 0) return 1;
    double best[KINDS];
    for (int k = 0; k < KINDS; ++k) best[k] = INFINITY;
    /* calls per round: about 0.1 s at n = 46 */
    long calls = (long)(2e7 / ((double)n * (double)n * (double)n) + 1.0), vcalls = calls * 20;
    double d1 = 1.0, d0 = 0.0, sink = 0.0;
    for (int r = 0; r < rounds; ++r) {
        for (int k = 0; k < KINDS; ++k) {
            long c = k == KIND_GETRF || k == KIND_GETRI || k == KIND_GJ ? calls : vcalls;
            double t0 = cpu_now();
            for (long j = 0; j < c; ++j) {
                switch (k) {
                case KIND_GETRF:
                    memcpy(F, A, sizeof(double) * nn);
                    dgetrf_(&n, &n, F, &n, ipiv, &info);
                    break;
                case KIND_GETRI:
                    memcpy(I, F, sizeof(double) * nn);
                    dgetri_(&n, I, &n, ipiv, work, &lwork, &info);
                    break;
                case KIND_GJ:
                    memcpy(I, A, sizeof(double) * nn);
                    (void)kin__gauss_jordan_inverse(n, I, perm, perm + n, work, &sign);
                    break;
                case KIND_GETRS:
                    memcpy(w, v, sizeof(double) * (size_t)n);
                    dgetrs_("T", &n, &one, F, &n, ipiv, w, &n, &info, 1);
                    break;
                case KIND_GEMV:
                    dgemv_("T", &n, &n, &d1, I, &n, v, &one, &d0, w, &one, 1);
                    break;
                case KIND_GETRS2:
                    memcpy(w, v, sizeof(double) * 2 * (size_t)n);
                    dgetrs_("T", &n, &two, F, &n, ipiv, w, &n, &info, 1);
                    break;
                default:
                    dgemm_("T", "N", &n, &two, &n, &d1, I, &n, v, &n, &d0, w, &n, 1, 1);
                    break;
                }
                sink += w[0];
            }
            double t = (cpu_now() - t0) / (double)c;
            if (t < best[k]) best[k] = t;
        }
    }
    printf("LU point pieces at n = %d, %s (best of %d rounds, CPU microseconds per call)\n", n, label, rounds);
    for (int k = 0; k < KINDS; ++k) printf("  %-36s %8.2f\n", NAMES[k], 1e6 * best[k]);
    double save = best[KIND_GETRS] - best[KIND_GEMV];
    if (save > 0.0)
        printf("  the inverse pays from %.1f single-vector solves a point (dgetri / (dgetrs - dgemv))\n",
               best[KIND_GETRI] / save);
    else
        printf("  the inverse never pays here (a product costs more than a solve)\n");
    printf("  Gauss-Jordan / (dgetrf + dgetri): %.2f\n", best[KIND_GJ] / (best[KIND_GETRF] + best[KIND_GETRI]));
    if (!isfinite(sink)) printf("  (non-finite results)\n");
    return 0;
}


int main(int argc, char **argv)
{
    print_blas();
    int n = argc > 1 ? atoi(argv[1]) : 46, rounds = argc > 2 ? atoi(argv[2]) : 5;
    if (n < 2 || n > 2000 || rounds < 1 || rounds > 1000) {
        fprintf(stderr, "usage: bench_lu_point [N (2..2000) [ROUNDS (1..1000)]]\n");
        return 2;
    }
    size_t nn = (size_t)n * (size_t)n;
    int lwork = 64 * n;
    double *A = malloc(sizeof(double) * nn), *F = malloc(sizeof(double) * nn), *I = malloc(sizeof(double) * nn),
           *work = malloc(sizeof(double) * (size_t)lwork), *v = malloc(sizeof(double) * 2 * (size_t)n),
           *w = malloc(sizeof(double) * 2 * (size_t)n);
    int *ipiv = malloc(sizeof(int) * (size_t)n);
    if (!A || !F || !I || !work || !v || !w || !ipiv) {
        fprintf(stderr, "out of memory\n");
        return 1;
    }
    int *perm = malloc(sizeof(int) * 2 * (size_t)n);
    if (!perm) return 1;
    for (int which = 0; which < 2; ++which) {
        const char *label = which ? "the hexagonal sail's bordered J^T" : "a random dense matrix";
        if (which == 0) {
            unsigned long long s = 0x5eedULL;
            for (size_t i = 0; i < nn; ++i) {
                s = s * 6364136223846793005ULL + 1442695040888963407ULL;
                A[i] = (double)(s >> 11) * 0x1.0p-53 - 0.5 + (i % ((size_t)n + 1) == 0 ? 2.0 : 0.0);
            }
        } else if (n != 46 || !sail_matrix(A, n)) {
            break;
        }
        if (run(n, rounds, label, A, F, I, work, lwork, v, w, ipiv, perm)) return 1;
    }
    free(perm);
    free(A), free(F), free(I), free(work), free(v), free(w), free(ipiv);
    return 0;
}
