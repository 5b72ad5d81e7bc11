/* Following a path to the next bifurcation (paper Section 4): the detector
 * loop of kin_locate_next, which steps, watches the test function and the
 * vanishing singular value (detect.c), and hands the bracket to one of the
 * three locators (locate_hermite.c, locate_illinois.c, locate_paper.c);
 * see kin_locate.h. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_min.h>

#include "model/internal.h"
#include "model/lapack.h"

#include "locate/locate.h"
#include "locate/locate_internal.h"
#include "locate/sing_proof.h"

/* while locating, singular values count as zero only below this fraction of
 * the target tolerance, so that the test function keeps its sign (and the
 * analysis its single mechanism) until the target is met */
static const double LOCATE_RANK_FRACTION = 1e-3;
/* m and s at a located point are counted with rank tolerance at least this
 * multiple of vr_tol: the point is only that exact */
static const double LOCATED_RANK_MARGIN = 10.0;
/* steps the fast method follows past a sign change of the test function at
 * which v_r is still decreasing, looking for v_r to turn */
enum { TAU_LOOK_AHEAD = 2 };

/* the defaults, in one table (fields not named are zero) */
static const kin_locate_options DEFAULTS = {
    .size = sizeof(kin_locate_options),
    .method = KIN_LOCATE_FAST,
    .vr_tol = 1e-10,
    .switch_eps = 1e-2,
    .delta = 0.0,
    .max_steps = 1000,
    .max_iter = 60,
    .use_switch_rule = 1,
};

int kin_locate_options_init(kin_locate_options *o, size_t size)
{
    return kin__abi_init(o, size, &DEFAULTS, KIN__ABI(kin_locate_options));
}

/* for binaries built before the macro: the first layout only (docs/abi.md) */
void (kin_locate_options_default)(kin_locate_options *o)
{
    if (o) kin__abi_init(o, KIN__ABI(kin_locate_options)->size[0], &DEFAULTS, KIN__ABI(kin_locate_options));
}

/* dv/dl of the vanishing singular value of the analysed state st along its
 * direction of motion, dir * t (no factorization) */
static double motion_slope(loc_ctx *c, const kin_assembly *st, double dir)
{
    int k = kin__loc_vanishing_index(st);
    if (k < 0) return 0.0;
    return dir * kin__sv_derivative(st, kin__cur(st), st->xyz, st->t, k, kin__hermite_scratch(c->hw));
}

/* v_r turned from decreasing to increasing over the last step (length len):
 * where the tangent lines at its two ends meet, v_r is about (for a crossing
 * exactly) zero. That value, to compare with the switch threshold. */
static double turn_value(double v0, double sl0, double v1, double sl1, double len)
{
    double s = (v1 - v0 - sl1 * len) / (sl0 - sl1);
    if (!(s >= 0.0)) s = 0.0;
    if (s > len) s = len;
    return v0 + sl0 * s;
}

void kin__locate_ws_free(kin__locate_ws *ws)
{
    if (!ws) return;
    kin_assembly_free(ws->prev);
    kin_assembly_free(ws->work);
    kin_assembly_free(ws->probe);
    kin_assembly_free(ws->tb0);
    kin_assembly_free(ws->tb1);
    kin__hermite_free(ws->hw);
    free(ws->near_buf);
    if (ws->near_min) gsl_min_fminimizer_free(ws->near_min);
    memset(ws, 0, sizeof *ws);
}

/* the caller's working copies: made at the first call (as clones of a, with
 * the locator's options), then refreshed from a (state and options: what a
 * clone of a made now would hold) */
static int use_ws(loc_ctx *c, kin_assembly *a, kin__locate_ws *ws)
{
    if (!ws->hw) {
        /* the look-ahead's pair (tb0, tb1) and the paper's probe only when
         * one needs it (kin__loc_probe) */
        ws->hw = kin__hermite_alloc(a);
        if (!ws->hw || kin_assembly_clone(a, &ws->prev) || kin_assembly_clone(a, &ws->work)) {
            kin__locate_ws_free(ws);
            return KIN_ENOMEM;
        }
    } else {
        kin_assembly *copies[] = {ws->prev, ws->work, ws->probe, ws->tb0, ws->tb1};
        for (int i = 0; i < 5; ++i)
            if (copies[i]) {
                kin__copy_state(copies[i], a);
                copies[i]->opt = a->opt;
            }
    }
    c->prev = ws->prev;
    c->work = ws->work;
    c->probe = ws->probe;
    c->tb0 = ws->tb0;
    c->tb1 = ws->tb1;
    c->hw = ws->hw;
    return KIN_OK;
}

static void free_ctx(loc_ctx *c, const kin__locate_ws *ws)
{
    if (ws) return; /* the caller's */
    kin_assembly_free(c->prev);
    kin_assembly_free(c->work);
    kin_assembly_free(c->probe);
    kin_assembly_free(c->tb0);
    kin_assembly_free(c->tb1);
    kin__hermite_free(c->hw);
}

/* a location succeeded (the located point in c->work, the last regular
 * point in c->prev): eq. 26's check that the move from the last regular
 * point continues its tangent (else the search slid onto a neighbouring
 * path), and the caller's handle moved onto the located point */
static void take_located(loc_ctx *c, kin_assembly *a, kin_locate_info *info)
{
    double *ch = kin__hermite_scratch(c->hw), *x1 = ch + a->nf; /* 2 nj dim doubles */
    kin__gather(a, c->prev->xyz, ch);
    kin__gather(a, c->work->xyz, x1);
    for (int i = 0; i < a->nf; ++i) ch[i] = x1[i] - ch[i];
    double n = kin__norm(a->nf, ch);
    info->path_kept = n == 0.0 || fabs(kin__dot(a->nf, ch, c->prev->t)) >= KIN__PATH_KEPT_COS * n;
    double dist = 0.0;
    for (int i = 0; i < a->nj * a->dim; ++i) dist += (c->work->xyz[i] - a->xyz[i]) * (c->work->xyz[i] - a->xyz[i]);
    info->distance = sqrt(dist);
    kin__copy_state(a, c->work);
}

/* v_r / v_max, and the rigorous enclosure of v_r (kin_locate_info layout
 * 2): the index of the singular value reported as v_r, bounded by
 * model/sv_enclosure.c */
static void enclose_v_r(const kin_assembly *a, kin_locate_info *info)
{
    const kin_factor *f = kin__cur(a);
    info->v_r_rel = f->an.v_max > 0 ? info->v_r / f->an.v_max : 0.0;
    int p = a->nf < a->nb ? a->nf : a->nb, idx = -1;
    double lo, hi, max_lo;
    info->v_r_bounded = 0;
    info->v_r_lo = info->v_r_hi = info->v_r_rel_hi = 0.0;
    if (!f->valid || !f->sv) return;
    for (int i = 0; i < p; ++i)
        if (f->sv[i] == info->v_r) idx = i;
    if (idx < 0 || !kin__sv_enclose(a, idx, &lo, &hi, &max_lo) || !(max_lo > 0.0)) return;
    info->v_r_lo = lo, info->v_r_hi = hi;
    info->v_r_rel_hi = hi / max_lo * (1.0 + 0x1p-50); /* rounded up */
    info->v_r_bounded = 1;
}

/* kin_locate_info's layout-3 fields from locate/sing_proof.c */
static int prove_singular(kin_assembly *a, kin_locate_info *info)
{
    kin__sing_proof p;
    int rc = kin__sing_prove(a, &p);
    info->sing_proven = p.proven;
    info->sing_corank = p.corank;
    info->sing_distance = p.distance;
    info->sing_dlength = p.dlength;
    info->sing_unique = p.unique;
    return rc;
}

/* a location's final point (its analysis current): v_r's enclosure (layout
 * 2) always, the singular point's proof (layout 3) where it was located,
 * except for the follower (ws given), whose events do not report it and
 * whose branches would pay ~10 ms each for it (kin_prove_singular proves
 * one of its points on demand); returns rc, or the proof's error (out of
 * memory) */
static int certify(kin_assembly *a, kin_locate_info *info, int rc, const kin__locate_ws *ws)
{
    enclose_v_r(a, info);
    if (rc != KIN_OK || ws) return rc;
    return prove_singular(a, info);
}

int kin_prove_singular(kin_assembly *a, kin_locate_info *info)
{
    if (!a || !info) return a ? kin__fail(a, KIN_ENULL, "kin_prove_singular: info is NULL") : KIN_ENULL;
    if (kin__abi_check(info, KIN__ABI(kin_locate_info)) || info->size < sizeof(kin_locate_info))
        return kin__fail(a, KIN_EINVAL, "kin_prove_singular: info->size is not the current sizeof(kin_locate_info)");
    int token = kin__blas_threads_small(a);
    int rc = prove_singular(a, info);
    kin__blas_threads_restore(token);
    return rc;
}

static int locate_impl(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info, kin__step_hook hook,
                       void *hook_user, kin__locate_ws *ws)
{
    kin_locate_options o = *opt;
    if ((o.method != KIN_LOCATE_PAPER && o.method != KIN_LOCATE_FAST && o.method != KIN_LOCATE_ILLINOIS) ||
        !(o.vr_tol > 0 && o.vr_tol < 1) || !(o.switch_eps > 0 && o.switch_eps < 1) || !isfinite(o.delta) ||
        o.max_steps < 1 || o.max_iter < 1)
        return kin__fail(a, KIN_EINVAL, "locate options out of range");
    /* the follower's LU steps hand over at a point they factorized
     * (kin__locate_ws.lu_nodes): it starts without an SVD, its test
     * function, vanishing singular value and slope from those factors (a
     * regular point: one internal mechanism) and the first step's chord
     * corrector with them; else (or where the slope's iteration does not
     * converge) its SVD analysis as always */
    /* a bracket the follower's LU steps already stepped over (locate.h) */
    const kin__path_point *direct_prev = ws ? ws->direct_prev : NULL;
    const double *direct_border = ws ? ws->direct_border : NULL;
    if (ws) ws->direct_prev = NULL, ws->direct_border = NULL;
    if (direct_prev && !(ws->lu_nodes && !kin__cur(a)->valid && kin__lu_square_current(a) && a->have_t && !a->t_chosen))
        return KIN__LOCATE_DIRECT_FAILED;
    int lu_start = ws && ws->lu_nodes && !kin__cur(a)->valid && kin__lu_square_current(a) && a->have_t && !a->t_chosen;
    int rc = kin__cur(a)->valid || lu_start ? KIN_OK : kin__analyse(a, NULL);
    if (rc) return rc;
    if (!lu_start && kin__cur(a)->an.m_internal >= 2)
        return kin__fail(a, KIN_EBIFURCATION, "already at a bifurcation (m_internal = %d)",
                         kin__cur(a)->an.m_internal);
    if (!lu_start && kin__cur(a)->an.m_internal == 0)
        return kin__fail(a, KIN_ENOMECH, "no internal mechanism to follow");
    if (ws) ws->near_bracket = 0;
    loc_ctx c = {a, NULL, NULL, NULL, NULL, NULL, &o, info, NULL, hook, hook_user, 0.0, ws ? ws->lu_nodes : 0, ws};
    kin_options user = a->opt;
    double fine = fmin(user.rank_tol, LOCATE_RANK_FRACTION * o.vr_tol);
    a->opt.rank_tol = fine;
    /* the detectors and the nodes need every point's SVD */
    a->opt.factorization = KIN_STEP_SVD;
    if (ws) {
        if (use_ws(&c, a, ws)) {
            a->opt = user;
            return kin__fail(a, KIN_ENOMEM, "locator working copies");
        }
    } else if (!(c.hw = kin__hermite_alloc(a)) || kin_assembly_clone(a, &c.prev) || kin_assembly_clone(a, &c.work)) {
        a->opt = user;
        free_ctx(&c, NULL);
        return kin__fail(a, KIN_ENOMEM, "locator working copies");
    }
    if (!a->have_t) {
        /* a regular start point: its own (deterministically oriented) mechanism */
        memcpy(a->t, kin__cur(a)->Uint, sizeof(double) * (size_t)a->nf);
        a->have_t = 1;
    }
    double dir = o.delta < 0.0 ? -1.0 : 1.0, tb_delta = 0.0, tb_tau0 = 0.0, tb_tau1 = 0.0;
    int pending = 0, stopped = 0;
    double tau0 = 0.0, tau1 = 0.0, hl[4], hv[4], v0 = 0.0, sl0 = 0.0;
    int nh = 0;
    kin_step_info si = {.size = sizeof si};
    long fa = 0, fw = 0, fp = 0, fpv = 0;
    if (direct_prev) {
        /* the bracket's start from the follower's kept point, its LU
         * factors made again (as the follower's own handover does); the
         * handle is the bracket's end, where the step to it left it */
        int regular = 0;
        kin__path_restore(c.prev, direct_prev);
        c.prev->lu_inverse = 1;
        rc = kin__lu_refactor(c.prev, direct_border, &regular);
        c.prev->lu_inverse = 0;
        fa = a->nfact;
        fw = c.work->nfact;
        fpv = c.prev->nfact;
        if (rc == KIN_OK && regular && kin__lu_square_current(c.prev) && a->fault != KIN__FAULT_LOCATE_DIRECT) {
            info->steps = 0; /* the step to the end was the caller's */
            info->event = KIN_EVENT_SIGN_CHANGE;
            rc = kin__locate_hermite(&c);
            TRACE(" direct bracket: hermite returned %d\n", rc);
        } else {
            rc = KIN__HERMITE_NO_BRACKET;
        }
        if (rc != KIN_OK) {
            a->opt = user;
            free_ctx(&c, ws);
            return rc == KIN_ECANCELLED || rc == KIN_ENOMEM ? rc : KIN__LOCATE_DIRECT_FAILED;
        }
        take_located(&c, a, info);
        goto classify;
    }
    if (lu_start && !kin__hermite_lu_vanishing(c.hw, a, dir, &v0, &sl0)) {
        lu_start = 0;
        if ((rc = kin__analyse(a, NULL)) != KIN_OK || kin__cur(a)->an.m_internal != 1) {
            a->opt = user;
            free_ctx(&c, ws);
            return rc ? rc : kin__fail(a, KIN_EBIFURCATION, "the locator's start is not a regular point");
        }
    }
    if (lu_start) {
        /* tau = sign(det [C; t^T]) v_r, as kin_test_function (no rigid mechanisms here) */
        int sg = 0;
        rc = kin__border_det_sign(a, &sg);
        tau0 = sg * v0;
        hv[nh] = v0;
        a->lu_svd_start = 1;
    } else {
        rc = kin_test_function(a, &tau0);
        v0 = kin__loc_vanishing_sv(a);
        sl0 = motion_slope(&c, a, dir);
        hv[nh] = kin__cur(a)->an.v_r;
    }
    hl[nh++] = a->l;
    while (rc == KIN_OK && info->steps < o.max_steps) {
        if (kin__loc_cancelled(&c)) {
            rc = KIN_ECANCELLED;
            break;
        }
        kin__copy_state(c.prev, a);
        rc = kin_step(a, o.delta, &si);
        if (rc) break;
        info->steps++;
        int hook_says = c.hook ? c.hook(c.hook_user, a) : 0;
        if (hook_says == KIN__HOOK_STOP) {
            stopped = 1;
            break;
        }
        if (si.m_internal >= 2) {
            info->event = KIN_EVENT_LANDED;
            break;
        }
        rc = kin_test_function(a, &tau1);
        if (rc) break;
        double vr = kin__cur(a)->an.v_r, vmax = kin__cur(a)->an.v_max;
        double v1 = kin__loc_vanishing_sv(a), sl1 = motion_slope(&c, a, dir);
        TRACE(" step %d: l %.6f tau %+.3e v %.3e slope %+.3e\n", info->steps, a->l, tau1, v1 / vmax, sl1 / vmax);
        if (tau0 != 0.0 && tau1 != 0.0 && (tau0 > 0) != (tau1 > 0)) {
            if (o.method == KIN_LOCATE_FAST && sl1 < 0.0) {
                /* tau flipped while v_r still falls: with several singular
                 * values vanishing together the determinant can change sign
                 * (even twice) just before the point. Keep the first such
                 * bracket and look a step or two further for v_r to turn. */
                if (!pending) {
                    /* the pair that keeps the bracket, made at the first
                     * look-ahead (most follows never need one: 2 of the 5
                     * working copies, each a clone of the handle) */
                    int bad = (!c.tb0 && kin_assembly_clone(a, &c.tb0)) || (!c.tb1 && kin_assembly_clone(a, &c.tb1));
                    if (ws) { /* the caller's from now on (freed with the rest) */
                        ws->tb0 = c.tb0;
                        ws->tb1 = c.tb1;
                    }
                    if (bad) {
                        rc = kin__fail(a, KIN_ENOMEM, "locator working copies");
                        break;
                    }
                    kin__copy_state(c.tb0, c.prev);
                    kin__copy_state(c.tb1, a);
                    tb_delta = si.delta;
                    tb_tau0 = tau0;
                    tb_tau1 = tau1;
                }
                pending = 1;
            } else {
                info->event = KIN_EVENT_SIGN_CHANGE;
                break;
            }
        }
        if (nh == 4) {
            memmove(hl, hl + 1, 3 * sizeof *hl);
            memmove(hv, hv + 1, 3 * sizeof *hv);
            nh = 3;
        }
        hl[nh] = a->l;
        hv[nh++] = vr;
        if (o.method == KIN_LOCATE_PAPER && o.use_switch_rule && vr < o.switch_eps * vmax && vr < hv[nh - 2]) {
            info->event = KIN_EVENT_SWITCH_RULE;
            kin__copy_state(c.prev, a);
            break;
        }
        if (o.method != KIN_LOCATE_PAPER && sl0 < 0.0 && sl1 > 0.0 &&
            turn_value(v0, sl0, v1, sl1, fabs(a->l - c.prev->l)) < o.switch_eps * vmax) {
            /* v_r turned over this step without tau changing sign: an even
             * number of singular values crossed zero, a tangency, or a
             * non-zero minimum */
            info->event = KIN_EVENT_MINIMUM;
            nh--; /* the paper's history ends at the point before */
            break;
        }
        if (pending && ++pending > TAU_LOOK_AHEAD) {
            /* v_r did not turn: locate on the test function's bracket */
            kin__copy_state(c.prev, c.tb0);
            kin__copy_state(a, c.tb1);
            si.delta = tb_delta;
            tau0 = tb_tau0;
            tau1 = tb_tau1;
            info->event = KIN_EVENT_SIGN_CHANGE;
            break;
        }
        tau0 = tau1;
        v0 = v1;
        sl0 = sl1;
        if (hook_says == KIN__HOOK_STOP_IDLE && !pending) {
            /* the detectors saw this step and hold nothing back */
            stopped = 1;
            break;
        }
    }
    a->lu_svd_start = 0;
    fa = a->nfact;
    fw = c.work->nfact;
    fp = c.probe ? c.probe->nfact : 0;
    fpv = c.prev->nfact;
    if (rc == KIN_OK && info->event == KIN_EVENT_NONE)
        rc = stopped ? kin__fail(a, KIN_ENOTFOUND, "following stopped by the caller after %d steps", info->steps)
                     : kin__fail(a, KIN_ENOTFOUND, "no bifurcation within %d steps", o.max_steps);
    if (rc == KIN_OK && info->event != KIN_EVENT_LANDED) {
        double step = o.delta != 0.0 ? fabs(o.delta) : a->opt.step_fraction * a->rms_length;
        int bracket = info->event == KIN_EVENT_SIGN_CHANGE || info->event == KIN_EVENT_MINIMUM;
        if (o.method == KIN_LOCATE_FAST && bracket) {
            rc = kin__locate_hermite(&c);
            TRACE(" event %d: hermite returned %d\n", info->event, rc);
            if (rc == KIN__HERMITE_NO_BRACKET && !kin__cur(c.prev)->valid) {
                /* the fallbacks read the SVD analysis of the point before */
                int rc2 = kin__analyse(c.prev, NULL);
                if (rc2) rc = rc2;
            }
            if (rc == KIN__HERMITE_NO_BRACKET) {
                /* v_r does not turn within the step although tau changed
                 * sign: the test function's bracket, then the paper's
                 * quadratic from the point before */
                rc = info->event == KIN_EVENT_SIGN_CHANGE ? kin__locate_illinois(&c, si.delta, tau0, tau1) : KIN_ENOTFOUND;
                if (rc == KIN_ENOTFOUND) rc = nh >= 2 ? kin__locate_paper(&c, hl, hv, nh, step) : rc;
                if (rc == KIN_ENOTFOUND && !kin_last_error(a)[0])
                    rc = kin__fail(a, KIN_ENOTFOUND, "v_r does not turn within the step");
            }
        } else if (o.method == KIN_LOCATE_ILLINOIS && info->event == KIN_EVENT_SIGN_CHANGE) {
            rc = kin__locate_illinois(&c, si.delta, tau0, tau1);
        } else {
            /* the paper's method; also the fallback when tau does not change sign */
            /* the history ends at c.prev, the last point before the bifurcation */
            rc = nh >= 2 ? kin__locate_paper(&c, hl, hv, nh, step) : kin__fail(a, KIN_ENOTFOUND, "too little history");
        }
        if (rc == KIN_OK) {
            take_located(&c, a, info);
        } else if (rc == KIN_ENOTFOUND || rc == KIN_ECANCELLED) {
            /* a turn of v_r without a zero: the bracket's end kept for
             * kin__locate_near_minimum (the working copy is free now) */
            if (ws && rc == KIN_ENOTFOUND && (info->event == KIN_EVENT_MINIMUM || info->event == KIN_EVENT_SIGN_CHANGE)) {
                kin__copy_state(c.work, a);
                ws->near_bracket = 1;
            }
            /* leave the assembly at the best regular point: the base of the search */
            kin__copy_state(a, c.prev);
        }
    }
    if (rc == KIN_OK && info->event == KIN_EVENT_LANDED)
        info->path_kept = 1; /* an ordinary step landed there: its direction check applied */
classify:
    /* count m and s at the final point from its factorization (no new one):
     * at a located point with the rank tolerance the location supports (the
     * vanishing singular values are only down to vr_tol there), elsewhere
     * with the caller's */
    a->opt = user;
    if (rc == KIN_OK && info->event != KIN_EVENT_LANDED)
        a->opt.rank_tol = fmax(user.rank_tol, LOCATED_RANK_MARGIN * o.vr_tol);
    {
        int rc2 = kin__cur(a)->valid ? kin__reclassify(a, a->xyz, a->cur) : kin__analyse(a, NULL);
        if (rc == KIN_OK) rc = rc2;
    }
    a->opt = user;
    info->factorizations =
        (int)((a->nfact - fa) + (c.work->nfact - fw) + (c.probe ? c.probe->nfact - fp : 0) + (c.prev->nfact - fpv));
    info->located = rc == KIN_OK;
    info->v_r = kin__loc_group_top(a, o.vr_tol);
    rc = certify(a, info, rc, ws); /* v_r / v_max, its enclosure, the proof of a singular point near */
    info->m_internal = kin__cur(a)->an.m_internal;
    info->s = kin__cur(a)->an.s;
    if (rc == KIN_ECANCELLED)
        kin__fail(a, KIN_ECANCELLED, "cancelled by the progress callback after %d steps and %d forward calculations",
                  info->steps, info->forward);
    else if (rc == KIN_OK)
        (void)kin__progress(a, (double)o.max_steps + (double)o.max_iter, (double)o.max_steps + (double)o.max_iter);
    if (ws) ws->nonzero_min = rc == KIN_ENOTFOUND ? c.nonzero_min : 0.0;
    free_ctx(&c, ws);
    return rc;
}

int kin_locate_next(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info)
{
    int token = kin__blas_threads_small(a); /* small matrices: one BLAS thread, restored after */
    int rc = kin__locate_hooked(a, opt, info, NULL, NULL, NULL);
    kin__blas_threads_restore(token);
    return rc;
}

int kin__locate_hooked(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info, kin__step_hook hook,
                       void *hook_user, kin__locate_ws *ws)
{
    kin_locate_options o;
    kin_locate_options_default(&o); /* fields an older caller does not have keep their defaults */
    int rc = kin__abi_entry(a, info, KIN__ABI(kin_locate_info), opt, &o, KIN__ABI(kin_locate_options));
    if (rc) return rc;
    kin_locate_info local = {.size = sizeof local};
    rc = locate_impl(a, &o, &local, hook, hook_user, ws);
    if (info) kin__abi_write(info, &local, KIN__ABI(kin_locate_info));
    return rc;
}
