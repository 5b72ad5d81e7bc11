/* Private: the one-path kernels of the complete solver's tracker and
 * certificate (homotopy_kernels.c): complex vectors as separate real and
 * imaginary arrays, the Jacobian's LU factors, Q x and the homotopy's
 * evaluation. */
#ifndef KIN_HOMOTOPY_KERNELS_H
#define KIN_HOMOTOPY_KERNELS_H

#include "homotopy/homotopy_control.h"

/* Complex n x n matrices are column-major with the column stride
 * np = n rounded up to whole lanes (entry (i, j) at j*np + i, rows n..np-1
 * zero): the factorisation's updates and both substitutions run down
 * contiguous columns in whole groups of HOM_LANES rows (independent
 * updates the compiler puts in vector registers), the rows outside the
 * range being multiplied by stored zeros. Every entry in the range receives
 * the same operations in the same order as in a row-oriented elimination. */
typedef struct hom_lu {
    double r[HOM_MM], i[HOM_MM];     /* J; after factoring, U strictly above the diagonal (zeros on
                                        and below it) */
    double lr[HOM_MM], li[HOM_MM];   /* after factoring, L strictly below the diagonal (zeros on
                                        and above it; the unit diagonal is implied) */
    double dr[HOM_MAX_M], di[HOM_MAX_M]; /* 1 / U_kk */
    int piv[HOM_MAX_M];
} hom_lu;

/* a point with Q x, H and the LU factors of J */
typedef struct hom_point {
    double xr[HOM_MAX_M], xi[HOM_MAX_M];
    double yr[HOM_MAX_ROWS], yi[HOM_MAX_ROWS];
    double hr[HOM_MAX_M], hi[HOM_MAX_M];
    hom_lu lu;
} hom_point;

/* n rounded up to whole lanes: the column stride of hom_lu */
static inline int kin__hom_lanes_up(int n) { return (n + HOM_LANES - 1) / HOM_LANES * HOM_LANES; }
/* |x| (2-norm, summed in order) */
double kin__hom_vnorm(int n, const double *xr, const double *xi);
/* y = Q x in the interleaved rows (y[r*sp + j]: row r of Q_j x), whole blocks */
void kin__hom_qmul(const hom_problem *P, const double *xr, const double *xi, double *yr, double *yi);
/* LU with partial pivoting in place; 0 if singular */
int kin__hom_lu_factor(int n, hom_lu *F);
/* b <- A^-1 b (b: n rounded up to HOM_LANES entries, the last ones scratch) */
void kin__hom_lu_solve(int n, const hom_lu *F, double *restrict br, double *restrict bi);
/* the Hager-Higham estimate of |A^-1|_1 (a lower bound, usually exact) */
double kin__hom_inv_norm1(int n, const hom_lu *F);
/* out_j = u . (Q_j x) for j < sp from y = Q x */
void kin__hom_dots_raw(int m, int sp, const double *restrict ur, const double *restrict ui, const double *restrict yr,
                       const double *restrict yi, double *restrict outr, double *restrict outi);
/* Q x, H and J (unfactored) at p->x, t, in the chart (car, cai) */
void kin__hom_eval(const hom_problem *P, const double *car, const double *cai, double t, hom_point *p);
/* H, J at p->x (J factored) and Newton's correction d = J^-1 H; 0 if J is singular or d not finite */
int kin__hom_newton_step(const hom_problem *P, const double *car, const double *cai, double t, hom_point *p,
                         double *dr, double *di);
/* |A(t)[u, v]| <= normA |u||v| for the homotopy's bilinear form */
static inline double kin__hom_norm_A(const hom_problem *P, double t) { return (1.0 - t) * P->normG + t * P->normF; }


#endif /* KIN_HOMOTOPY_KERNELS_H */
