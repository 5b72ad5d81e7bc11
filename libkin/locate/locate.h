/* Private: what the location layer (paper Section 4) offers the layers
 * above it (branches/follow.c). Not installed. */
#ifndef KIN__LAYER_LOCATE_H
#define KIN__LAYER_LOCATE_H

#include "model/internal.h"

/* kin_locate_next with a hook called after every accepted following step
 * (before the detectors look at it): KIN__HOOK_STOP stops following there
 * as if max_steps were reached (KIN_ENOTFOUND, event NONE, the assembly at
 * that point); KIN__HOOK_STOP_IDLE the same once the detectors have looked
 * at that step, if they fired on nothing and hold no bracket back (the fast
 * method's look-ahead past a sign change); 0 goes on. hook NULL:
 * kin_locate_next itself. */
enum { KIN__HOOK_GO = 0, KIN__HOOK_STOP = 1, KIN__HOOK_STOP_IDLE = 2 };
typedef int (*kin__step_hook)(void *user, const kin_assembly *a);
/* The locator's working copies of the handle (3 clones, 2 more at the
 * first look-ahead past a sign change, and the Hermite workspace), for a
 * caller that locates several times on one handle (the follower: once per
 * handover and per relaxed tolerance). Zero-initialize; the first
 * kin__locate_hooked that gets it makes them (cloning the handle, as a call
 * without it does every time), later calls only copy the handle's state and
 * options into them: a clone costs about as much as a step of the locator. Valid while the handle's model (bars, rest lengths,
 * fixed coordinates, contact settings) is unchanged; kin__locate_ws_free
 * releases them. */
typedef struct kin__locate_ws {
    kin_assembly *prev, *work, *probe, *tb0, *tb1;
    struct hermite_ws *hw;
    /* out, each call: where the fast method gave up (KIN_ENOTFOUND) on a
     * non-zero minimum of v_r, the lowest v_r / v_max its nodes and checks
     * reached; 0 otherwise */
    double nonzero_min;
    /* in: the fast method's forward calculations (Hermite nodes) by LU
     * steps, the node's singular triple by subspace iteration with their
     * factors and its polish by their minimum-norm corrections; the SVD
     * where the point is not regular or the triple does not converge (the
     * follower's cheap steps) */
    int lu_nodes;
    /* out, each call: 1 where it gave up (KIN_ENOTFOUND) on a turn of v_r
     * (KIN_EVENT_MINIMUM) without a zero: the handle is left at the
     * bracket's start and `work` holds its end, for
     * kin__locate_near_minimum; 0 otherwise */
    int near_bracket;
    /* kin__locate_near_minimum's workspace, made at its first call */
    double *near_buf;
    void *near_min; /* gsl_min_fminimizer */
    /* in (the follower's cheap steps): a sign-change bracket the LU steps
     * already stepped over, so that the locator need not step over it
     * again by SVD. Where direct_prev is not NULL the handle is at the
     * bracket's end (an LU point: factors, tangent, no SVD) and
     * direct_prev (with direct_border, its factors' border row) is the
     * point one step before it; the caller has checked that the SVD
     * locator, stepping there, would stop on this very step with a sign
     * change and locate on it (kin_follow's cheap stretches, kin__follow_cheap_stretch). The locator
     * then locates on that bracket at once (the Hermite method, its nodes
     * from the LU factors); where that does not succeed it returns
     * KIN__LOCATE_DIRECT_FAILED, the handle's position unchanged, and the
     * caller steps over the bracket by SVD as usual. Reset to NULL by the
     * call. */
    const struct kin__path_point *direct_prev;
    const double *direct_border;
} kin__locate_ws;
/* kin__locate_hooked with kin__locate_ws.direct_prev: no location on the
 * given bracket (a private code, not a kin_status) */
enum { KIN__LOCATE_DIRECT_FAILED = -2 };
void kin__locate_ws_free(kin__locate_ws *ws);
/* ws: NULL (copies made and freed in the call) or the caller's, as above */
int kin__locate_hooked(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info, kin__step_hook hook,
                       void *hook_user, kin__locate_ws *ws);

/* A near miss located at its minimum: v_r / v_max minimised along the
 * path over the bracket ws->near_bracket holds (the handle at its start,
 * ws->work at its end) by Brent's method (GSL) on the path parameter z
 * (t0.(x - x0), the arc length to within the step's turn), each trial point
 * a forward calculation onto the path (locate_nearmin.c). Where a point
 * below both ends is found the handle moves to the best point (analysed by
 * SVD), out->located = 1 when the minimum's position is within width (a
 * fraction of the RMS rest length, at most 1e-8 then) and out->v_rel its
 * v_r / v_max; else the handle stays (located 0). Returns KIN_OK or
 * KIN_ENOMEM (the workspace, made once per ws). */
typedef struct kin__near_min {
    int located, evals; /* the minimum located to its tolerance; trial points computed */
    double z, width, v_rel;
    /* the v_r / v_max a crossing inside the final interval could still
     * show there (the steeper side's secant slope x the width, at least the
     * rounding of v_r): a minimum NEAR_MIN_MARGIN (10) x above it is a near
     * miss; one not above it was narrowed to 1e-13 of the RMS length */
    double floor;
} kin__near_min;
int kin__locate_near_minimum(kin_assembly *a, kin__locate_ws *ws, kin__near_min *out);

#endif /* KIN__LAYER_LOCATE_H */
