/* Private: the complete solver's complex linear algebra and homotopy
 * evaluations on HOM_BATCH paths at once, one path per lane of a structure
 * of arrays (entry c of lane l's vector at v[c][l]): every inner loop runs
 * across the lanes, independent operations of equal length that the
 * compiler puts in vector registers whatever m is, and Q x shares every load
 * of Q among the lanes. Each lane gets exactly the operations of the
 * one-path kernels in homotopy_track.c, every sum in the same order and no
 * contraction to fused multiply-adds, so each lane's results are bit for
 * bit the one-path kernels'. Vectors cross between files only by pointer
 * (the kernels are cloned per instruction set, whose calling conventions for
 * vectors differ). GCC and Clang only (vector extensions); homotopy_batch.c
 * falls back to the one-path tracker elsewhere. */
#ifndef KIN_HOMOTOPY_LANES_H
#define KIN_HOMOTOPY_LANES_H

#include "homotopy/track/homotopy_control.h"

#if defined(__GNUC__)
#define HOM_LANES_VECTOR 1
#define BL HOM_BATCH

/* one value per lane: a vector of BL doubles (element-wise IEEE arithmetic,
 * no contraction under -std=c99) */
typedef double lanes __attribute__((vector_size(BL * sizeof(double))));
typedef long long lmask __attribute__((vector_size(BL * sizeof(double))));
#define ALL(x) ((lanes){0.0} + (x))
/* the lanes of a where mask is set (all bits), of b elsewhere */
#define select_lanes(mask, a, b) ((lanes)(((mask) & (lmask)(a)) | (~(mask) & (lmask)(b))))

/* LU factors of the lanes' Jacobians: entry (row j, column c) at [c*m + j] */
typedef struct hom_llu {
    lanes r[HOM_MM], i[HOM_MM];         /* J; after factoring, U strictly above the diagonal */
    lanes lr[HOM_MM], li[HOM_MM];       /* after factoring, L strictly below the diagonal */
    lanes dr[HOM_MAX_M], di[HOM_MAX_M]; /* 1 / U_kk */
    int piv[HOM_MAX_M][BL];
    int ok[BL]; /* the factorisation succeeded (no zero pivot) */
} hom_llu;

/* a point of every lane with Q x, H and the LU factors of J */
typedef struct hom_lpoint {
    lanes xr[HOM_MAX_M], xi[HOM_MAX_M];
    lanes yr[HOM_MAX_ROWS], yi[HOM_MAX_ROWS];
    lanes hr[HOM_MAX_M], hi[HOM_MAX_M];
    hom_llu lu;
} hom_lpoint;

/* the Taylor series of every lane's path: coefficients (c[0] set by the
 * caller) and Q x_k for 1 <= k < HOM_NY */
typedef struct hom_lseries {
    lanes cr[HOM_ORDER + 1][HOM_MAX_M], ci[HOM_ORDER + 1][HOM_MAX_M];
    lanes ykr[HOM_NY][HOM_MAX_ROWS], yki[HOM_NY][HOM_MAX_ROWS];
} hom_lseries;

/* LU with partial pivoting of every lane's J (n x n, stride n), each lane
 * its own pivots, exactly as kin__hom_lu_factor (homotopy_lu.h); F->ok[l] =
 * 0 where a pivot is zero or not finite (that lane's factors are then
 * meaningless) */
void kin__lanes_lu_factor(int n, hom_llu *F);
/* b <- A^-1 b, every lane, exactly as kin__hom_lu_solve */
void kin__lanes_lu_solve(int n, const hom_llu *F, lanes *br, lanes *bi);
/* |v| (2-norm) of every lane, out[BL] */
void kin__lanes_norm2(int n, const lanes *xr, const lanes *xi, double *out);
/* H and J at p->x, every lane at its t (*t) in its chart (car, cai), J
 * factored, and Newton's correction d = J^-1 H (dr, di: m entries); ok[l] =
 * 0 where J is singular or d not finite (as newton_step) */
void kin__lanes_newton(const hom_problem *P, const lanes *t, const lanes *car, const lanes *cai, hom_lpoint *p,
                       lanes *dr, lanes *di, int *ok);
/* the Hager-Higham estimate of |A^-1|_1 per lane (est[BL]), as inv_norm1 */
void kin__lanes_inv_norm1(int n, const hom_llu *F, double *est);
/* the Taylor coefficients T->c[1..HOM_ORDER] of every lane's path through
 * T->c[0] at its t (*t0) from its base point b, as taylor */
void kin__lanes_taylor(const hom_problem *P, const lanes *t0, const hom_lpoint *b, hom_lseries *T);

#endif /* __GNUC__ */
#endif /* KIN_HOMOTOPY_LANES_H */
