/* The rational predictor of the complete solver's trackers
 * (homotopy_pade.c) on series whose sums are known: a path with a single
 * pole is reproduced to rounding and its error estimate vanishes; with a
 * second, farther pole the estimate bounds the actual error and the
 * approximant beats the Taylor polynomial by 10x from half the radius of
 * convergence on; the step extension stops at the
 * tolerance, the limit or sigma; degenerate and non-finite series and
 * steps past the pole guard give no approximant (INFINITY). */
#include <complex.h>
#include <string.h>

#include "check.h"
#include "pade_series.h"
#include "homotopy/track/homotopy_control.h"

enum { M = 5, K = HOM_ORDER };

static double cr[K + 1][HOM_MAX_M], ci[K + 1][HOM_MAX_M];

/* the series and distances of pade_series.h for M coordinates */
static void series(int np, const double complex *z, const double complex u[][M], const double complex *w)
{
    pade_series(M, K, np, z, u[0], w, cr, ci);
}
static double dist_to_sum(int np, const double complex *z, const double complex u[][M], const double complex *w,
                          double h, const double *xr, const double *xi, double *norm)
{
    return pade_dist(M, np, z, u[0], w, h, xr, xi, norm);
}

int main(void)
{
    const double complex w[M] = {1.0, -0.5 + 0.25 * I, 2.0 * I, 0.75, -1.0 - I};
    const double complex u[2][M] = {{0.3, 0.1 - 0.2 * I, -0.4 * I, 0.25 + 0.05 * I, -0.15},
                                    {0.2 * I, -0.1, 0.05 + 0.3 * I, 0.4, 0.1 - 0.1 * I}};
    const double complex z[2] = {1.25 * cexp(0.6 * I), 0.4 * cexp(-2.0 * I)}; /* poles at 0.8 and 2.5 */
    double xr[HOM_MAX_M], xi[HOM_MAX_M], nx;
    const double (*Cr)[HOM_MAX_M] = (const double(*)[HOM_MAX_M])cr, (*Ci)[HOM_MAX_M] = (const double(*)[HOM_MAX_M])ci;
    hom_pade pd;

    /* one pole: [K-1/1] is the function itself, the estimate is rounding */
    series(1, z, u, w);
    kin__hom_pade_setup(M, Cr, Ci, &pd);
    CHECK(pd.ok);
    CHECK_CLOSE(pd.qr, creal(z[0]), 16 * DBL_EPSILON);
    CHECK_CLOSE(pd.qi, cimag(z[0]), 16 * DBL_EPSILON);
    for (double h = 0.1; h <= 0.8 * PADE_POLE / cabs(z[0]); h += 0.2) {
        kin__hom_pade_predict(M, Cr, Ci, &pd, h, xr, xi);
        double d = dist_to_sum(1, z, u, w, h, xr, xi, &nx);
        CHECK(d <= 64 * DBL_EPSILON * nx);
        double e = kin__hom_pade_error(&pd, h), tail = pow(cabs(z[0]) * h, K - 1) / cabs(1.0 - z[0] * h);
        CHECK(e >= 0.0 && e <= 64 * DBL_EPSILON * tail);
    }
    /* the pole guard */
    CHECK(isinf(kin__hom_pade_error(&pd, 1.01 * PADE_POLE / cabs(z[0]))));
    /* estimate zero: extension to the limit, or to sigma exactly */
    double e = -1.0, h = kin__hom_pade_extend(&pd, 0.05, 0.3, 1.0, 1e-6, &e);
    CHECK(h <= 0.3 && h * PADE_GROW > 0.3 && e >= 0.0);
    h = kin__hom_pade_extend(&pd, 0.05, 0.3, 0.2, 1e-6, &e);
    CHECK(h == 0.2);

    /* two poles: the estimate bounds the error, which is far below the
     * Taylor polynomial's at half the radius of convergence */
    series(2, z, u, w);
    kin__hom_pade_setup(M, Cr, Ci, &pd);
    CHECK(pd.ok);
    for (double h2 = 0.1; h2 <= 0.6; h2 += 0.1) {
        kin__hom_pade_predict(M, Cr, Ci, &pd, h2, xr, xi);
        double d = dist_to_sum(2, z, u, w, h2, xr, xi, &nx), est = kin__hom_pade_error(&pd, h2);
        CHECK(d <= est);
        double tr[HOM_MAX_M], ti[HOM_MAX_M], nt;
        for (int c = 0; c < M; ++c) { /* the Taylor polynomial */
            tr[c] = cr[K][c], ti[c] = ci[K][c];
            for (int k = K - 1; k >= 0; --k) tr[c] = tr[c] * h2 + cr[k][c], ti[c] = ti[c] * h2 + ci[k][c];
        }
        double dt = dist_to_sum(2, z, u, w, h2, tr, ti, &nt);
        if (h2 >= 0.35) CHECK(d <= 0.1 * dt);
    }
    /* the extension stops where the estimate passes the tolerance */
    double tol = kin__hom_pade_error(&pd, 0.3);
    h = kin__hom_pade_extend(&pd, 0.1, 10.0, 10.0, tol, &e);
    CHECK(e <= tol && e == kin__hom_pade_error(&pd, h) && !(kin__hom_pade_error(&pd, h * PADE_GROW) <= tol));
    /* an estimate past the tolerance at the first step: no extension */
    h = kin__hom_pade_extend(&pd, 0.3, 10.0, 10.0, 0.5 * tol, &e);
    CHECK(h == 0.3);

    /* degenerate series: a vanishing or non-finite coefficient */
    series(1, z, u, w);
    for (int c = 0; c < M; ++c) cr[K - 1][c] = ci[K - 1][c] = 0.0;
    kin__hom_pade_setup(M, Cr, Ci, &pd);
    CHECK(!pd.ok && isinf(kin__hom_pade_error(&pd, 0.1)));
    h = kin__hom_pade_extend(&pd, 0.1, 1.0, 1.0, 1.0, &e);
    CHECK(h == 0.1);
    series(1, z, u, w);
    cr[K][2] = NAN;
    kin__hom_pade_setup(M, Cr, Ci, &pd);
    CHECK(!pd.ok && isinf(kin__hom_pade_error(&pd, 0.1)));
    TEST_REPORT("homotopy_pade");
}
