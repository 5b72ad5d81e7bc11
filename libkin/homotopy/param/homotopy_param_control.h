/* Private: the step control of the parameter tracker, shared by the
 * one-path tracker (homotopy_param.c, the reference) and the lockstep one
 * (homotopy_param_batch.c), which follow every path through the same
 * operations and so must use the same constants. */
#ifndef KIN_HOMOTOPY_PARAM_CONTROL_H
#define KIN_HOMOTOPY_PARAM_CONTROL_H

#include <math.h>

#include "homotopy/param/homotopy_param.h"
#include "homotopy/track/homotopy_pade.h"

enum {
    HPAR_ORDER = 6,                     /* Taylor order of the predictor */
    HPAR_NY = HPAR_ORDER / 2 + 1,       /* M0 x_i for i <= HPAR_ORDER / 2 */
    HPAR_NZ = (HPAR_ORDER - 1) / 2 + 1, /* D x_i for i <= (HPAR_ORDER - 1) / 2 */
    HPAR_NEWTON_MAX = 3,                /* corrector iterations per step */
    HPAR_REFINE_MAX = 6,                /* Newton iterations at t = 1 */
    HPAR_MAX_STEPS = 5000               /* accepted + rejected steps before a path counts as lost */
};

/* a correction below NEWTON_TOL |x| ends the corrector (the next step's
 * predictor starts from there; endpoints are refined anyway) */
static const double HPAR_NEWTON_TOL = 1e-10;
/* the second correction must be at most CONTRACTION times the first (see
 * homotopy_param.c) */
static const double HPAR_CONTRACTION = 0.25;
/* corrections below NOISE |x| are rounding: the point is on its root (two
 * roots that close cannot be told apart in double precision anyway) */
static const double HPAR_NOISE = 1e-13, HPAR_STALL_TOL = 1e-8;
static const double HPAR_REJECT_SHRINK = 0.5, HPAR_ACCEPT_GROW = 2.0, HPAR_H_MIN = 1e-14;
/* chart change when |a||x| exceeds CHART_TILT sqrt(m) (see homotopy_track.c) */
static const double HPAR_CHART_TILT = 8.0;
/* at t = 1: converged when the correction is below REFINE_TOL |x| */
static const double HPAR_REFINE_TOL = 1e-12;

/* the step whose estimated truncation error is `target`, from the norms
 * n[1..HPAR_ORDER] of the Taylor coefficients */
double kin__hpar_series_step(const double *n, double target);

/* The rational predictor (homotopy_pade.c), used as the plain trackers use
 * it (homotopy_track.c): where its error estimate, calibrated along the
 * path, meets the Taylor predictor's target at the step the Taylor model
 * gives, it predicts instead of the Taylor polynomial, and on the first
 * attempt at a step the step grows while the estimate still meets the
 * target. The Taylor model is not calibrated here (its step is what the
 * parameter tracker always took); the rational one's estimate, which
 * bounds the error of the approximant one order lower, is: by the ratio
 * of the first Newton correction to it (a running geometric mean) within
 * [HPAR_CALIB_MIN, HPAR_CALIB_MAX], as homotopy_control.h's CALIB_MIN and
 * CALIB_MAX. */
static const double HPAR_CALIB_MIN = 0.1, HPAR_CALIB_MAX = 4.0;

/* An attempt at the step *h (the Taylor model's, or the last attempt's
 * halved; at most sigma) on the series pd was set up with: 1 if the
 * rational predictor is to predict it, *pest then its error estimate at
 * the (on the first attempt possibly grown) step *h. hser: the Taylor
 * model's step, hcap: the step's cap, target: the error target, calib:
 * the rational model's calibration. */
static inline int kin__hpar_pade_attempt(const hom_pade *pd, int first, double hser, double hcap, double sigma,
                                         double target, double calib, double *h, double *pest)
{
    *pest = kin__hom_pade_error(pd, *h);
    int pade = *pest <= target / calib;
    if (pade && first) *h = kin__hom_pade_extend(pd, *h, fmin(PADE_REACH * hser, hcap), sigma, target / calib, pest);
    return pade;
}

/* the rational model's calibration after a step it predicted with the
 * estimate est and whose first Newton correction was nd */
static inline double kin__hpar_pade_calibrate(double calib, double est, double nd)
{
    if (!(est > 0.0 && nd > 0.0)) return calib;
    return fmin(HPAR_CALIB_MAX, fmax(HPAR_CALIB_MIN, sqrt(calib * nd / est)));
}

#endif /* KIN_HOMOTOPY_PARAM_CONTROL_H */
