/* Private: the one-path kernels of the complete solver's tracker and
 * certificate (homotopy_kernels.c): complex vectors as separate real and
 * imaginary arrays, Q x and the homotopy's evaluation; the Jacobian's LU
 * factors in homotopy_lu.h. */
#ifndef KIN_HOMOTOPY_KERNELS_H
#define KIN_HOMOTOPY_KERNELS_H

#include "homotopy/track/homotopy_control.h"
#include "homotopy/track/homotopy_lu.h"

/* a point with Q x, H and the LU factors of J */
typedef struct hom_point {
    double xr[HOM_MAX_M], xi[HOM_MAX_M];
    double yr[HOM_MAX_ROWS], yi[HOM_MAX_ROWS];
    double hr[HOM_MAX_M], hi[HOM_MAX_M];
    hom_lu lu;
} hom_point;

/* |x| (2-norm, summed in order) */
double kin__hom_vnorm(int n, const double *xr, const double *xi);
/* y = Q x in the interleaved rows (y[r*sp + j]: row r of Q_j x), whole blocks */
void kin__hom_qmul(const hom_problem *P, const double *xr, const double *xi, double *yr, double *yi);
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
