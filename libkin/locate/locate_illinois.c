/* The Illinois locator (modified regula falsi) on the signed test function
 * over the bracketing step (kin_locate.h, KIN_LOCATE_ILLINOIS). */
#include <math.h>

#include "model/internal.h"
#include "locate/locate_internal.h"

/* the bracket has collapsed to this fraction of its first width without v_r
 * vanishing: the test function changed sign without a zero */
static const double GIVE_UP_FRACTION = 1e-9;

/* Illinois iteration on tau(delta) over [0, hi] from prev (tau_lo there) */
int kin__locate_illinois(loc_ctx *c, double hi, double tau_lo, double tau_hi)
{
    double lo = 0.0, width0 = fabs(hi);
    int side = 0;
    for (int it = 0; it < c->o->max_iter; ++it) {
        if (kin__loc_cancelled(c)) return KIN_ECANCELLED;
        if (fabs(hi - lo) < GIVE_UP_FRACTION * width0) {
            /* the bracket has collapsed but v_r stays finite: tau changed sign
             * without a zero, i.e. the step crossed a near-singular but
             * regular configuration onto a neighbouring sheet of the path */
            return kin__fail(c->a, KIN_ENOTFOUND,
                             "no bifurcation: the test function changed sign but v_r stays at %.3g relative "
                             "(a near-singular regular configuration; take smaller steps here)",
                             kin__loc_rel(c->work));
        }
        double d = hi - tau_hi * (hi - lo) / (tau_hi - tau_lo);
        if (!(d > fmin(lo, hi) && d < fmax(lo, hi))) d = 0.5 * (lo + hi);
        double used;
        int rc = kin__loc_forward(c, c->prev, c->work, d, &used);
        if (rc != KIN_OK || used != d) {
            d = 0.5 * (lo + hi);
            rc = kin__loc_forward(c, c->prev, c->work, d, &used);
            if (rc != KIN_OK) return rc;
        }
        if (kin__loc_at_bifurcation(c->work, c->o->vr_tol)) return KIN_OK;
        double tau;
        rc = kin_test_function(c->work, &tau);
        if (rc) return rc;
        if (tau == 0.0) return KIN_OK;
        if ((tau > 0) == (tau_hi > 0)) {
            hi = used;
            tau_hi = tau;
            if (side == 1) tau_lo *= 0.5; /* Illinois: halve the stale end */
            side = 1;
        } else {
            lo = used;
            tau_lo = tau;
            if (side == -1) tau_hi *= 0.5;
            side = -1;
        }
    }
    return kin__fail(c->a, KIN_ENOTFOUND,
                     "signed test function: no convergence in %d iterations, v_r still %.3g relative: a "
                     "near-singular but regular configuration, or a bifurcation this method cannot resolve",
                     c->o->max_iter, kin__loc_rel(c->work));
}
