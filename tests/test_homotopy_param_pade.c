/* The rational predictor (homotopy_pade.c) at the parameter trackers'
 * series order HPAR_ORDER (the plain trackers' HOM_ORDER is covered by
 * test_homotopy_pade.c), and the parameter trackers' step choice and
 * calibration (homotopy_param_control.h): a one-pole path is reproduced to
 * rounding with its estimate at the rounding level of its Gram form; with a second pole the
 * estimate bounds the error; the setup at HOM_ORDER through the
 * order-taking entry equals the plain one; the choice takes the rational
 * predictor only where its estimate meets the target over the calibration,
 * extends the step on the first attempt only and within PADE_REACH times
 * the Taylor step and the cap; the calibration follows the geometric mean
 * within its bounds and ignores a missing correction. */
#include <complex.h>
#include <string.h>

#include "check.h"
#include "pade_series.h"
#include "homotopy/track/homotopy_control.h"
#include "homotopy/param/homotopy_param_control.h"

enum { M = 4, K = HPAR_ORDER };

static double cr[HOM_ORDER + 1][HOM_MAX_M], ci[HOM_ORDER + 1][HOM_MAX_M];

/* the series and distances of pade_series.h for M coordinates */
static void series(int np, const double complex *z, const double complex u[][M], const double complex *w)
{
    pade_series(M, HOM_ORDER, np, z, u[0], w, cr, ci);
}
static double dist_to_sum(int np, const double complex *z, const double complex u[][M], const double complex *w,
                          double h, const double *xr, const double *xi, double *norm)
{
    return pade_dist(M, np, z, u[0], w, h, xr, xi, norm);
}

int main(void)
{
    const double complex w[M] = {1.0, -0.5 + 0.25 * I, 2.0 * I, 0.75};
    const double complex u[2][M] = {{0.3, 0.1 - 0.2 * I, -0.4 * I, 0.25 + 0.05 * I},
                                    {0.2 * I, -0.1, 0.05 + 0.3 * I, 0.4}};
    const double complex z[2] = {1.25 * cexp(0.6 * I), 0.4 * cexp(-2.0 * I)}; /* poles at 0.8 and 2.5 */
    const double (*Cr)[HOM_MAX_M] = (const double(*)[HOM_MAX_M])cr, (*Ci)[HOM_MAX_M] = (const double(*)[HOM_MAX_M])ci;
    double xr[HOM_MAX_M], xi[HOM_MAX_M], nx;
    hom_pade pd, p8;

    /* one pole: [K-1/1] is the function, its estimate rounding */
    series(1, z, u, w);
    kin__hom_pade_setup_order(K, M, Cr, Ci, &pd);
    CHECK(pd.ok && pd.order == K);
    CHECK_CLOSE(pd.qr, creal(z[0]), 16 * DBL_EPSILON);
    CHECK_CLOSE(pd.qi, cimag(z[0]), 16 * DBL_EPSILON);
    for (double h = 0.1; h <= 0.8 * PADE_POLE / cabs(z[0]); h += 0.2) {
        kin__hom_pade_predict(M, Cr, Ci, &pd, h, xr, xi);
        CHECK(dist_to_sum(1, z, u, w, h, xr, xi, &nx) <= 64 * DBL_EPSILON * nx);
        double e = kin__hom_pade_error(&pd, h), tail = pow(cabs(z[0]) * h, K - 1) / cabs(1.0 - z[0] * h);
        /* the estimate's norm is a difference of Gram terms of the size of
         * tail^2 (|a|^2 g1 + |b|^2 g2 - 2 Re(...)): its rounding leaves
         * sqrt(eps) tail */
        CHECK(e >= 0.0 && e <= 4 * sqrt(DBL_EPSILON) * tail);
    }
    CHECK(isinf(kin__hom_pade_error(&pd, 1.01 * PADE_POLE / cabs(z[0]))));

    /* the plain trackers' setup is the order-taking one at HOM_ORDER */
    kin__hom_pade_setup(M, Cr, Ci, &p8);
    kin__hom_pade_setup_order(HOM_ORDER, M, Cr, Ci, &pd);
    CHECK(p8.order == HOM_ORDER && pd.order == HOM_ORDER && p8.ok == pd.ok);
    CHECK(p8.qr == pd.qr && p8.qi == pd.qi && p8.q2r == pd.q2r && p8.q2i == pd.q2i && p8.qabs == pd.qabs);
    CHECK(p8.g1 == pd.g1 && p8.g2 == pd.g2 && p8.g12r == pd.g12r && p8.g12i == pd.g12i);

    /* two poles: the estimate bounds the error; the order matters (the
     * approximant one order up is closer) */
    series(2, z, u, w);
    kin__hom_pade_setup_order(K, M, Cr, Ci, &pd);
    kin__hom_pade_setup_order(K + 1, M, Cr, Ci, &p8);
    CHECK(pd.ok && p8.ok);
    for (double h = 0.1; h <= 0.6; h += 0.1) {
        kin__hom_pade_predict(M, Cr, Ci, &pd, h, xr, xi);
        double d = dist_to_sum(2, z, u, w, h, xr, xi, &nx);
        CHECK(d <= kin__hom_pade_error(&pd, h));
        kin__hom_pade_predict(M, Cr, Ci, &p8, h, xr, xi);
        CHECK(dist_to_sum(2, z, u, w, h, xr, xi, &nx) < d);
    }

    /* the step choice: rational where the estimate meets target / calib */
    double h0 = 0.2, est = kin__hom_pade_error(&pd, h0), h, pest;
    h = h0;
    CHECK(!kin__hpar_pade_attempt(&pd, 1, h0, 10.0, 10.0, 0.5 * est, 1.0, &h, &pest) && h == h0);
    h = h0;
    CHECK(!kin__hpar_pade_attempt(&pd, 1, h0, 10.0, 10.0, 1.5 * est, 2.0, &h, &pest) && h == h0);
    /* a later attempt: no extension */
    h = h0;
    CHECK(kin__hpar_pade_attempt(&pd, 0, h0, 10.0, 10.0, 4.0 * est, 1.0, &h, &pest) && h == h0 && pest == est);
    /* the first: extended while the estimate meets the target ... */
    h = h0;
    CHECK(kin__hpar_pade_attempt(&pd, 1, h0, 10.0, 10.0, 4.0 * est, 1.0, &h, &pest));
    CHECK(h > h0 && pest <= 4.0 * est && pest == kin__hom_pade_error(&pd, h));
    CHECK(!(kin__hom_pade_error(&pd, h * PADE_GROW) <= 4.0 * est));
    /* ... within PADE_REACH times the Taylor step, the cap and sigma */
    double big = 1e6 * est;
    h = h0;
    CHECK(kin__hpar_pade_attempt(&pd, 1, 0.1, 10.0, 10.0, big, 1.0, &h, &pest) && h <= PADE_REACH * 0.1);
    h = h0;
    CHECK(kin__hpar_pade_attempt(&pd, 1, h0, 0.21, 10.0, big, 1.0, &h, &pest) && h <= 0.21);
    h = h0;
    CHECK(kin__hpar_pade_attempt(&pd, 1, h0, 10.0, 0.3, big, 1.0, &h, &pest) && h == 0.3);
    /* no approximant: never rational */
    for (int c = 0; c < M; ++c) cr[K - 1][c] = ci[K - 1][c] = 0.0;
    kin__hom_pade_setup_order(K, M, Cr, Ci, &pd);
    h = h0;
    CHECK(!pd.ok && !kin__hpar_pade_attempt(&pd, 1, h0, 10.0, 10.0, 1e300, 1.0, &h, &pest) && h == h0);

    /* calibration: the geometric mean of the old value and the ratio, within bounds */
    CHECK_CLOSE(kin__hpar_pade_calibrate(1.0, 1e-6, 0.25e-6), 0.5, 4 * DBL_EPSILON);
    CHECK(kin__hpar_pade_calibrate(1.0, 1.0, 1e-6) == HPAR_CALIB_MIN);
    CHECK(kin__hpar_pade_calibrate(1.0, 1e-6, 1.0) == HPAR_CALIB_MAX);
    CHECK(kin__hpar_pade_calibrate(0.7, 1e-6, 0.0) == 0.7); /* no correction (Newton failed) */
    CHECK(kin__hpar_pade_calibrate(0.7, 0.0, 1e-6) == 0.7);
    TEST_REPORT("homotopy_param_pade");
}
