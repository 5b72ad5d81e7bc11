/* The inverse of a small dense matrix by Gauss-Jordan elimination with
 * partial pivoting, in place: the follower's cheap stretches keep the
 * inverse of every point's bordered matrix (step_lu.c), and there one
 * factorization serves about 15 solves, each a product with the inverse.
 *
 * Why not dgetrf + dgetri: for the hexagonal sail's 46 x 46 bordered
 * matrices they cost 9.9 + 15.8 us with OpenBLAS (one thread); dgetri
 * inverts U (dtrtri: level-2 calls on 46 columns) then solves with L column
 * by column, and each call pays OpenBLAS's per-call overhead. Gauss-Jordan
 * does the same n^3 multiply-adds (LU 2n^3/3 + inverse 4n^3/3 = 2n^3 flops)
 * as n rank-one updates of contiguous columns, four columns per pass over
 * the multipliers, and skips the columns a bar's sparsity leaves untouched:
 * 14.7 us on a dense 46 x 46 matrix, 6.7 us on the sail's own J^T
 * (bench/bench_lu_point.c). A product with the inverse (0.2 us at 46)
 * stays 5x cheaper than a solve with the factors (dgetrs 1.1-1.3 us; a
 * hand-written triangular solve was no better, 1.2-1.4 us: the substitution
 * is a chain of dependent updates).
 *
 * Accuracy: Gauss-Jordan with partial pivoting picks the same pivots as LU
 * with partial pivoting (the same Schur complements, rounded alike), and
 * its computed inverse has residuals of the same size as dgetri's (Higham,
 * Accuracy and Stability of Numerical Algorithms, 2nd ed., sec. 14.4:
 * |A X - I| bounded by c n u |A| |X| for both; measured on random 46 x 46
 * matrices 2.7e-14 against dgetri's 2.2e-14). */
#include <math.h>

#include "path/step_lu.h"

/* simple loops over contiguous columns: let GCC vectorise them (at -O2 its
 * cost model leaves loops with a remainder scalar), as homotopy_param.c */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("tree-vectorize", "vect-cost-model=dynamic")
#endif

/* an AVX2 clone where the CPU has it (no FMA: the library is built with
 * -ffp-contract=off, so both clones round every operation alike and give
 * the same bits); static and called through the plain function below
 * (homotopy_control.h: Clang before 18 dispatches clones only from their
 * own file) */
#if defined(__x86_64__) && defined(__ELF__) && defined(__has_attribute) && !defined(KIN_NO_MULTIVERSION)
#if __has_attribute(target_clones)
#define GJ_KERNEL __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef GJ_KERNEL
#define GJ_KERNEL
#endif

/* columns updated per pass over the multipliers (each multiplier loaded
 * once for four columns: 18.7 -> 15.6 us on a dense 46 x 46 matrix) */
enum { GJ_BLOCK = 4 };

GJ_KERNEL static int gauss_jordan(int n, double *restrict A, int *restrict perm, int *restrict nzc,
                                  double *restrict col, int *sign)
{
    int sg = 1;
    for (int k = 0; k < n; ++k) {
        double *restrict ck = A + (size_t)k * n;
        int p = k;
        double best = fabs(ck[k]);
        for (int i = k + 1; i < n; ++i)
            if (fabs(ck[i]) > best) {
                best = fabs(ck[i]);
                p = i;
            }
        perm[k] = p;
        if (!(best > 0.0) || !isfinite(best)) return k + 1; /* exactly singular (or not finite) */
        if (p != k) {
            sg = -sg;
            for (int j = 0; j < n; ++j) {
                double *c = A + (size_t)j * n, tmp = c[k];
                c[k] = c[p];
                c[p] = tmp;
            }
        }
        double piv = ck[k], r = 1.0 / piv;
        if (piv < 0.0) sg = -sg;
        /* the multipliers: column k without its pivot */
        for (int i = 0; i < n; ++i) col[i] = ck[i];
        col[k] = 0.0;
        /* every column j != k with c_j[k] != 0: c_j -= col * (c_j[k] / piv),
         * c_j[k] := c_j[k] / piv. J^T is sparse (a bar's column has 2 dim
         * nonzeros) and fills in only as the elimination goes: the columns
         * with a zero in row k are skipped: the hexagonal sail's J^T in
         * 6.7 us against 14.7 us for a dense matrix of its size
         * (bench_lu_point) */
        int nz = 0;
        for (int j = 0; j < n; ++j)
            if (A[k + (size_t)j * n] != 0.0 && j != k) nzc[nz++] = j;
        int q = 0;
        for (; q + GJ_BLOCK <= nz; q += GJ_BLOCK) {
            double *restrict c0 = A + (size_t)nzc[q] * n, *restrict c1 = A + (size_t)nzc[q + 1] * n,
                             *restrict c2 = A + (size_t)nzc[q + 2] * n, *restrict c3 = A + (size_t)nzc[q + 3] * n;
            double f0 = c0[k] * r, f1 = c1[k] * r, f2 = c2[k] * r, f3 = c3[k] * r;
            for (int i = 0; i < n; ++i) {
                double v = col[i];
                c0[i] -= v * f0;
                c1[i] -= v * f1;
                c2[i] -= v * f2;
                c3[i] -= v * f3;
            }
            c0[k] = f0;
            c1[k] = f1;
            c2[k] = f2;
            c3[k] = f3;
        }
        for (; q < nz; ++q) {
            double *restrict c = A + (size_t)nzc[q] * n, f = c[k] * r;
            for (int i = 0; i < n; ++i) c[i] -= col[i] * f;
            c[k] = f;
        }
        for (int i = 0; i < n; ++i) ck[i] = -col[i] * r;
        ck[k] = r;
    }
    /* the row interchanges of A are column interchanges of its inverse,
     * undone in reverse order */
    for (int k = n - 1; k >= 0; --k) {
        int p = perm[k];
        if (p == k) continue;
        double *u = A + (size_t)k * n, *v = A + (size_t)p * n;
        for (int i = 0; i < n; ++i) {
            double tmp = u[i];
            u[i] = v[i];
            v[i] = tmp;
        }
    }
    *sign = sg;
    return 0;
}

int kin__gauss_jordan_inverse(int n, double *A, int *perm, int *cols, double *col, int *sign)
{
    *sign = 0;
    return gauss_jordan(n, A, perm, cols, col, sign);
}
