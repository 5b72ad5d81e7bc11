/* Test helper for the rational predictor's tests: vectors with known
 * poles, x_c(h) = w_c + sum_p u[p][c] / (1 - z_p h) (c < m, u with row
 * stride m), their Taylor coefficients and the distance of a point to
 * x(h). */
#ifndef KIN_TEST_PADE_SERIES_H
#define KIN_TEST_PADE_SERIES_H

#include <complex.h>
#include <math.h>
#include <string.h>

#include "homotopy/track/homotopy_track.h"

/* cr, ci rows 0..order: the Taylor coefficients of x at h = 0 (the other
 * entries of those rows zero) */
static inline void pade_series(int m, int order, int np, const double complex *z, const double complex *u,
                               const double complex *w, double (*cr)[HOM_MAX_M], double (*ci)[HOM_MAX_M])
{
    memset(cr, 0, sizeof(double) * HOM_MAX_M * (size_t)(order + 1));
    memset(ci, 0, sizeof(double) * HOM_MAX_M * (size_t)(order + 1));
    for (int c = 0; c < m; ++c) {
        double complex v = w[c];
        for (int p = 0; p < np; ++p) v += u[p * m + c];
        cr[0][c] = creal(v), ci[0][c] = cimag(v);
        for (int k = 1; k <= order; ++k) {
            double complex s = 0.0;
            for (int p = 0; p < np; ++p) s += u[p * m + c] * cpow(z[p], k);
            cr[k][c] = creal(s), ci[k][c] = cimag(s);
        }
    }
}

/* |x(h) - (xr, xi)|; *norm receives |x(h)| */
static inline double pade_dist(int m, int np, const double complex *z, const double complex *u,
                               const double complex *w, double h, const double *xr, const double *xi, double *norm)
{
    double d = 0.0, n = 0.0;
    for (int c = 0; c < m; ++c) {
        double complex v = w[c];
        for (int p = 0; p < np; ++p) v += u[p * m + c] / (1.0 - z[p] * h);
        d += cabs(v - (xr[c] + I * xi[c])) * cabs(v - (xr[c] + I * xi[c]));
        n += cabs(v) * cabs(v);
    }
    *norm = sqrt(n);
    return sqrt(d);
}

#endif
