/* Private: the rational (vector Pade) predictor of homotopy_pade.c, shared
 * by the complete solver's trackers (homotopy_track.c, homotopy_batch.c:
 * series of order HOM_ORDER, see homotopy_control.h) and the symmetric
 * solver's parameter trackers (homotopy_param.c, homotopy_param_batch.c:
 * order HPAR_ORDER). The series is c[0..K] with coordinate c of c_k at
 * c[k][c] (rows of HOM_MAX_M), K the order given to the setup. */
#ifndef KIN_HOMOTOPY_PADE_H
#define KIN_HOMOTOPY_PADE_H

#include "homotopy/track/homotopy_track.h"

/* Where the rational predictor is good enough the step may grow past the
 * Taylor predictor's, by factors of PADE_GROW up to PADE_REACH times the
 * series step, while the estimated error stays within the target.
 * PADE_POLE bounds |q| h, q the reciprocal of the estimated pole's
 * position: the pole lies off the real axis (no singularity is on the
 * path), so a step may reach somewhat past its distance, not far. */
static const double PADE_GROW = 1.1, PADE_REACH = 2.5, PADE_POLE = 1.5;
/* The vector Pade approximants of the path from its Taylor coefficients
 * c_0..c_K, one denominator for all coordinates (the singularity that
 * limits the series is a point of the path, common to every coordinate):
 *     [K-1/1]: x(h) = sum_{k<K-1} c_k h^k + c_{K-1} h^{K-1} / (1 - q h),
 * q = <c_{K-1}, c_K> / |c_{K-1}|^2 (least squares for c_K = q c_{K-1}),
 * and [K-2/1] the same one order lower (q', from c_{K-2}, c_{K-1}). Their
 * difference h^{K-1} (a c_{K-1} - b c_{K-2}), a = 1 / (1 - q h),
 * b = q' / (1 - q' h), estimates the error of the lower one and so bounds
 * that of [K-1/1]; its norm needs only the Gram numbers kept here. */
typedef struct hom_pade {
    double qr, qi, q2r, q2i, qabs; /* q, q' and |q| */
    double g1, g2, g12r, g12i; /* |c_{K-1}|^2, |c_{K-2}|^2, sum conj(c_{K-2}) c_{K-1} */
    int order;                /* K */
    int ok;                   /* 0: a coefficient vanishes or is not finite (no approximant) */
} hom_pade;
/* the approximants of the series c[0..order] (m coordinates, order >= 3) */
void kin__hom_pade_setup_order(int order, int m, const double (*cr)[HOM_MAX_M], const double (*ci)[HOM_MAX_M],
                               hom_pade *pd);
/* the error estimate of [K-1/1] at step h; INFINITY where |q| h > PADE_POLE or !pd->ok */
double kin__hom_pade_error(const hom_pade *pd, double h);
/* The largest h * PADE_GROW^j (j >= 0) within lim and sigma (then sigma
 * itself) whose error estimate stays within tol, h's estimate being within
 * it; *err receives that step's estimate. */
double kin__hom_pade_extend(const hom_pade *pd, double h, double lim, double sigma, double tol, double *err);
/* x = [K-1/1] at h, from the series pd was set up with */
void kin__hom_pade_predict(int m, const double (*cr)[HOM_MAX_M], const double (*ci)[HOM_MAX_M], const hom_pade *pd,
                           double h, double *xr, double *xi);

#endif /* KIN_HOMOTOPY_PADE_H */
