/* Private: the step control of the parameter tracker, shared by the
 * one-path tracker (homotopy_param.c, the reference) and the lockstep one
 * (homotopy_param_batch.c), which follow every path through the same
 * operations and so must use the same constants. */
#ifndef KIN_HOMOTOPY_PARAM_CONTROL_H
#define KIN_HOMOTOPY_PARAM_CONTROL_H

#include "homotopy_param.h"

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

#endif /* KIN_HOMOTOPY_PARAM_CONTROL_H */
