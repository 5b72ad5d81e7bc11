/* The cheap stretches of the follower (kin_follow_event, follow.c;
 * KIN_FOLLOW_STEPS_CHEAP): LU steps, without an SVD, on the regular
 * stretches between events, which are most of a path; the handovers to
 * the SVD locator where something may happen within a step; and, off a
 * bifurcation, the first step by LU with the verdict the SVD step would
 * have given. The SVD locator, started at any of their points, goes on as
 * the SVD follower would have from there, so the cheap steps change the
 * cost, not the events. The checks after every step are follow_watch.c's. */
#include <math.h>
#ifdef KIN_FOLLOW_TRACE
#include <stdio.h>
#endif
#include <string.h>

#include "branches/follow_internal.h"

static void keep_point(follow_ctx *c, const double *border)
{
    if (c->nkept == 2) {
        kept_point t = c->kept[0];
        c->kept[0] = c->kept[1];
        c->kept[1] = t;
        c->nkept = 1;
    }
    kept_point *k = &c->kept[c->nkept++];
    kin__path_save(c->a, &k->p);
    /* an LU point: its factors' border row, the tangent before the step (c->tprev) */
    k->has_border = border != NULL;
    if (border) memcpy(k->border, border, sizeof(double) * (size_t)c->a->nf);
    k->length = c->length;
    k->left = c->left;
    k->index = c->p;
}

/* back to a kept point (0 the older, 1 the newer if there are two): the
 * handle (no analysis), the length, the samples beyond it dropped */
void kin__follow_back_to_kept(follow_ctx *c, int newer)
{
    const kept_point *k = &c->kept[newer && c->nkept == 2 ? 1 : 0];
    int nf = c->a->nf, undone = c->p - k->index;
    /* the steps stepped again count once: steps are the path's (as the SVD follower counts them) */
    c->info->steps -= undone;
    c->info->cheap_steps -= undone;
    kin__path_restore(c->a, &k->p);
    c->length = c->len_pp = k->length;
    c->left = k->left;
    c->p = k->index;
    if (k->has_border) {
        /* its LU factors again (the same as the step made): the locator
         * starts there without an SVD (locate.h, kin__locate_ws.lu_nodes) */
        int regular = 0;
        c->a->lu_inverse = 1;
        if (kin__lu_refactor(c->a, k->border, &regular) != KIN_OK) c->a->lu[c->a->lu_cur].valid = 0;
    }
    kin__gather(c->a, c->a->xyz, c->xp);
    memcpy(c->xpp, c->xp, sizeof(double) * (size_t)nf);
    memcpy(c->xq, c->xp, sizeof(double) * (size_t)nf);
}

/* v_r turned from decreasing to increasing over a step of length len:
 * where the tangent lines at its two ends meet (locate.c's rule) */
static double turn_value(double v0, double sl0, double v1, double sl1, double len)
{
    double s = (v1 - v0 - sl1 * len) / (sl0 - sl1);
    if (!(s >= 0.0)) s = 0.0;
    if (s > len) s = len;
    return v0 + sl0 * s;
}

/* The vanishing singular value v of the current point, its slope along the
 * motion and v_max, as the SVD detector sees them: from the SVD where the
 * point has one, else from the LU factors (inverse iteration to
 * convergence). Returns 0 when they cannot be had reliably (the two lowest
 * singular values too close for the iteration). */
static int vanishing_slope(follow_ctx *c, double *v, double *sl, double *vmax)
{
    kin_assembly *a = c->a;
    const kin_factor *f = kin__cur(a);
    double dir = c->o->delta < 0.0 ? -1.0 : 1.0;
    if (f->valid) {
        int k = a->nf - 2 - f->an.m_rigid, mn = a->nf < a->nb ? a->nf : a->nb;
        if (k < 0 || k >= mn) return 0;
        *v = f->sv[k];
        *sl = dir * kin__sv_derivative(a, f, a->xyz, a->t, k, c->scr);
        *vmax = f->an.v_max;
        return 1;
    }
    int conv = 0;
    if (kin__lu_vr_triple(a, SLOPE_PASSES, SLOPE_VECTOR_TOL, SLOPE_BLOCK, c->blk, &c->blk_warm, c->u, c->w, v,
                          &conv) != KIN_OK ||
        !conv)
        return 0;
    *sl = dir * kin__sv_derivative_uw(a, a->xyz, a->t, c->u, c->w, c->scr);
    *vmax = a->lu[a->lu_cur].v_max;
    return *vmax > 0.0;
}

/* the LU mode of a cheap stretch (user: the handle's own options, which
 * lu_mode_off puts back) */
static void lu_mode_on(kin_assembly *a, const kin_follow_options *o, const kin_options *user)
{
    a->opt.factorization = KIN_STEP_LU;
    a->opt.rank_tol = fmin(user->rank_tol, CHEAP_RANK_FRACTION * o->vr_tol);
    /* the SVD mode's amplitudes: the LU steps reach the points the SVD
     * steps would (to rounding), so that the SVD locator, started from any
     * of them, continues exactly as the SVD follower would have */
    a->opt.step_control = KIN_STEP_CONTROL_SHARED;
    /* small J: solves by products with (J^T)^-1, kept with each point
     * (path/step_lu.c): some 15 solves a point here, more near events */
    a->lu_inverse = 1;
    /* the strain in plain double (model/assembly.c): on a cheap stretch v_r
     * is above the LU mode's margin, so its rounding (eps x L) moves a
     * corrected point by eps x L / v_r, far below the corrector's tolerance;
     * the double-double form is for the locators near v_r = 0. 2,000
     * flat-state branches: the same events, steps, accuracies and ends
     * (6e-6 of the identification tolerance at worst), median CPU 4.84 ->
     * 4.52 ms (the kernel was a tenth of a follow) */
    a->plain_extensions = 1;
}

static void lu_mode_off(kin_assembly *a, const kin_options *user)
{
    a->opt = *user;
    a->lu_inverse = 0;
    a->plain_extensions = 0;
}

/* a handover: the SVD locator takes over, and the hook watches for where
 * LU steps may resume (kin__follow_after_step) */
static void svd_takes_over(follow_ctx *c, kin_follow_info *info)
{
    c->watch = 1;
    c->svd_steps = 0;
    c->rho_prev = c->rho_cur = -INFINITY;
    info->handovers++;
}

/* Follow by LU steps (KIN_STEP_LU: no SVD) while nothing the SVD detectors
 * of kin_locate_next watch can happen within them. They fire on a sign
 * change of tau = sign(det [C; t^T; R^T]) v_r, on a turn of v_r (decreasing
 * then increasing) within a step, and where a step lands on a point with
 * several mechanisms. Here, after every step: the same sign from the step's
 * own LU factors (kin__lu_det_sign), and v_r / v_max as the LU mode
 * estimates it. The stretch hands over on a sign change, a step that fell
 * back to the SVD (estimated v_r / v_max below 1000 rank_tol), an estimate
 * below CHEAP_NEAR_FACTOR x switch_eps, or a sampled minimum of
 * the estimate (a turn of v_r within a step shows as a smaller sample at one
 * of its ends, before a larger one), and puts the handle back one point
 * before the current one (two after a sampled minimum), so that the SVD
 * locator steps over the suspect stretch again. The LU steps take the SVD
 * mode's amplitudes (KIN_STEP_CONTROL_SHARED) and the same rank tolerance
 * as the locator's steps: they reach the SVD follower's points to rounding,
 * and the locator, started at one of them, goes on exactly as the SVD
 * follower would have from there. Returns a status; *stop = 1 when the
 * hook stopped (loop, length) or the step budget ran out (info->event set),
 * else hand over. */
int kin__follow_cheap_stretch(follow_ctx *c, kin_follow_info *info, double r_before, int *stop)
{
    kin_assembly *a = c->a;
    const kin_follow_options *o = c->o;
    int nf = a->nf, sg0 = 0, rc;
    *stop = 0;
    kin_options user = a->opt;
    if ((rc = kin__border_det_sign(a, &sg0)) != KIN_OK) return rc;
    lu_mode_on(a, o, &user);
    c->nkept = 0;
    c->watch = 0;
    keep_point(c, NULL); /* an SVD point (or one whose border is not known) */
    double r0 = kin__lu_rel_estimate(a), rm = r_before; /* this point's v_r / v_max and the one before */
    /* the vanishing singular value and its slope at the start (an SVD point) */
    double v0 = NAN, sl0 = NAN, vm = 0.0, l0 = a->l;
    if (!vanishing_slope(c, &v0, &sl0, &vm)) v0 = sl0 = NAN;
    for (;;) {
        if (info->steps >= o->max_steps) {
            info->event = KIN_FOLLOW_STEP_LIMIT;
            *stop = 1;
            break;
        }
        if (kin__progress(a, (double)info->steps, c->total)) {
            rc = kin__fail(a, KIN_ECANCELLED, "cancelled by the progress callback after %d steps", info->steps);
            break;
        }
        memcpy(c->tprev, a->t, sizeof(double) * (size_t)nf);
        kin_step_info si = {.size = sizeof si};
        if (kin_step(a, o->delta, &si) != KIN_OK) {
            /* the SVD locator takes over (state unchanged) */
            c->resume_after = RESUME_AFTER_FAILED;
            c->resume_len = c->length;
            svd_takes_over(c, info);
            break;
        }
        info->steps++;
        info->cheap_steps++;
        if (kin__follow_after_step(c, a)) {
            *stop = 1;
            info->event = c->reason;
            break;
        }
        int sg = 0;
        if (si.m_internal == 1 && kin__cur(a)->valid) {
            /* the step fell back to the SVD (v_r small) and found one mechanism */
            if ((rc = kin__border_det_sign(a, &sg)) != KIN_OK) break;
        } else {
            kin__lu_det_sign(a, c->tprev, &sg);
        }
        double r1 = kin__lu_rel_estimate(a);
        /* a turn of v_r may lie in either step next to the sampled minimum:
         * back two points; everything else happened within the last step */
        int turned = r0 < rm && r1 > r0;
        /* where v_r is small the SVD detector's own turn rule, on the slope
         * of the vanishing singular value (exact vectors by inverse
         * iteration with these factors) */
        double v1 = NAN, sl1 = NAN, l1 = a->l;
        int slope_turn = 0;
        if (r1 > 0.0 && r1 < CHEAP_NEAR_FACTOR * o->switch_eps) {
            if (!vanishing_slope(c, &v1, &sl1, &vm) || fabs(sl1) <= SLOPE_ZERO * vm / c->scale)
                slope_turn = 1; /* not to be had reliably, or too flat to tell its sign */
            else if (sl1 > 0.0 && (isnan(sl0) || sl0 < 0.0) &&
                     (isnan(sl0) || turn_value(v0, sl0, v1, sl1, fabs(l1 - l0)) < SLOPE_TURN_MARGIN * o->switch_eps * vm))
                slope_turn = 1;
        }
        if (si.m_internal != 1 || (sg0 != 0 && sg != sg0) || !(r1 > 0.0) || slope_turn || turned) {
#ifdef KIN_FOLLOW_TRACE
            fprintf(stderr, "handover at step %d: m %d sg %d/%d r %.3g %.3g %.3g slope_turn %d turned %d v1 %.3g sl1 %.3g sl0 %.3g\n", info->steps,
                    si.m_internal, sg0, sg, rm, r0, r1, slope_turn, turned, v1 / vm, sl1 * c->scale / vm, sl0 * c->scale / vm);
#endif
            /* the SVD steps retake the LU steps' amplitudes: past the middle
             * of the last step, the SVD stepping has reached its end */
            c->resume_len = c->length - 0.5 * (c->length - c->len_pp);
            c->resume_after = RESUME_AFTER;
            /* A sign change over the last step that the SVD locator, stepping
             * over the same points again (to rounding), would bracket on
             * this very step: tau's sign flipped between two LU points
             * (one internal mechanism at both), v_r rises at the later one
             * (no look-ahead past the flip) and, where the handover goes
             * back two points, still falls at the earlier one (no turn of
             * v_r within the step before). Both slopes are the SVD
             * detector's own (converged singular vectors), with signs
             * clear of SLOPE_ZERO. The locator then locates on the LU
             * points' bracket without stepping over it again by SVD (the
             * one or two SVD steps of the usual handover saved; 2,000
             * flat-state branches: median CPU 3.3 -> 2.8 ms, the same
             * events, ends and accuracies); where that fails, the usual
             * handover. */
            double flat = SLOPE_ZERO * vm / c->scale;
            c->direct = sg0 != 0 && sg != 0 && sg != sg0 && si.m_internal == 1 && !kin__cur(a)->valid &&
                        c->nkept == 2 && c->kept[1].has_border && c->kept[1].index == c->p - 1 && sl1 > flat &&
                        (!turned || sl0 < -flat);
            c->direct_newer = !turned;
            if (!c->direct) kin__follow_back_to_kept(c, !turned);
            svd_takes_over(c, info);
            break;
        }
        keep_point(c, si.m_internal == 1 && !kin__cur(a)->valid ? c->tprev : NULL);
        rm = r0;
        r0 = r1;
        sg0 = sg;
        v0 = v1;
        sl0 = sl1;
        l0 = l1;
    }
    lu_mode_off(a, &user);
    return rc;
}

/* CHEAP STEPS: THE FIRST STEP OFF A BIFURCATION. Its point (1e-3 of the
 * largest step away) still counts as a bifurcation where v_r / v_max <= the
 * handle's rank tolerance (then a step ten times as long is tried), and
 * v_r / v_max there is far below the LU mode's margin (1000 x the rank
 * tolerance: 8e-8 on the flat state's branch 0), so the LU step alone would
 * always analyse it by SVD (4% of a cheap follow). Instead: the LU step with
 * a rank tolerance FIRST_LU_MARGIN / 1000 x the handle's (its estimate, an
 * upper bound, must be above FIRST_LU_MARGIN x the tolerance), then the
 * verdict from the vanishing singular value converged by the slope's
 * subspace iteration (Rayleigh-Ritz: accurate to rounding once the vector
 * has converged) and the LU mode's v_max (a lower bound, from the start's
 * top singular vector: within a few 1e-6): a mechanism count of 1 where
 * v_r / v_max > FIRST_LU_MARGIN x the handle's rank tolerance, else the
 * SVD, classified with the handle's own tolerance as the SVD step was. */
static const double FIRST_LU_MARGIN = 2.0;

void kin__follow_first_step_lu(follow_ctx *c, const kin_options *user)
{
    kin_assembly *a = c->a;
    a->opt = *user;
    a->opt.factorization = KIN_STEP_LU;
    a->opt.rank_tol = user->rank_tol * FIRST_LU_MARGIN * 1e-3;
    a->lu_inverse = 1;
}

/* after the first step (the handle's own options back): the mechanism count
 * the SVD step would have given, into si->m_internal */
int kin__follow_first_point_verdict(follow_ctx *c, kin_step_info *si)
{
    kin_assembly *a = c->a;
    if (kin__cur(a)->valid) {
        /* analysed by SVD in the step, with the lower tolerance: the handle's */
        int rc = kin__reclassify(a, a->xyz, a->cur);
        if (rc) return rc;
        si->m_internal = kin__cur(a)->an.m_internal;
        return KIN_OK;
    }
    double v = 0.0, vmax = a->lu[a->lu_cur].v_max;
    int conv = 0;
    c->blk_warm = 0;
    if (kin__lu_vr_triple(a, SLOPE_PASSES, SLOPE_VECTOR_TOL, SLOPE_BLOCK, c->blk, &c->blk_warm, c->u, c->w, &v,
                          &conv) == KIN_OK &&
        conv && vmax > 0.0 && v > FIRST_LU_MARGIN * kin__rank_tolerance(a) * vmax) {
        si->m_internal = 1;
        return KIN_OK;
    }
    int rc = kin__analyse(a, NULL);
    if (rc) return rc;
    si->m_internal = kin__cur(a)->an.m_internal;
    return KIN_OK;
}
