/* Following a path to its next event (kin_follow.h, docs/follow.md): the
 * locator (kin_locate_next, fast method) does the location and the
 * following near events; the follower adds, in the order of a call: the
 * start off a bifurcation (leave_start); the cheap stretches of LU steps
 * between events and the handovers to and from the locator
 * (follow_cheap.c, and the hook's resume); the checks after every step, in
 * both (follow_watch.c: path length, samples, the return to the start and
 * whether it is a loop, with the start's branch directions if given); the
 * relaxation of the location tolerance where rounding puts it out of reach
 * (locate_events); and the classification of how the path ended
 * (attempt_ends, finish). A new kind of event belongs in
 * kin__follow_after_step (a stop with its own reason) and in that
 * classification. This file is the call: its options and follow_impl's
 * stages, which share the call's state (follow_ctx, follow_internal.h). */
#include <math.h>
#ifdef KIN_FOLLOW_TRACE
#include <stdio.h>
#endif
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "branches/contact_event.h"
#include "branches/hinge_hold.h"
#include "model/internal.h"
#include "path/path.h"
#include "locate/locate.h"
#include "locate/locate_internal.h"
#include "locate/sing_proof.h"
#include "branches/branches_internal.h"
#include "branches/follow_internal.h"

/* the defaults, in one table (fields not named are zero) */
static const kin_follow_options DEFAULTS = {
    .size = sizeof(kin_follow_options),
    .vr_tol = 1e-10,
    .vr_floor = 1e-6,
    .switch_eps = 1e-2,
    .delta = 0.0,
    .max_steps = 1000,
    .max_iter = 60,
    .max_length = 0.0,
    .loop_tol = 1e-2,
    .first_step = 1e-3,
    .branch_cos = 0.99,
    .steps_mode = KIN_FOLLOW_STEPS_CHEAP,
    .branch_margin = 0.05,
    .return_fn = NULL,
    .return_user = NULL,
    .return_own = -1,
    .hold_hinges = 0,
    .hold_rate_tol = 1e-6,
};

int kin_follow_options_init(kin_follow_options *o, size_t size)
{
    return kin__abi_init(o, size, &DEFAULTS, KIN__ABI(kin_follow_options));
}

/* for binaries built before the macro: the first layout only (docs/abi.md) */
void (kin_follow_options_default)(kin_follow_options *o)
{
    if (o) kin__abi_init(o, KIN__ABI(kin_follow_options)->size[0], &DEFAULTS, KIN__ABI(kin_follow_options));
}

/* the locator's progress, made cumulative over the attempts */
static int progress_adapter(void *user, double done, double total)
{
    (void)total;
    follow_ctx *c = user;
    double d = c->done_base + done;
    return c->user_fn(c->user_data, d < c->total ? d : c->total, c->total);
}

static int options_ok(const kin_follow_options *o)
{
    return o->vr_tol > 0.0 && o->vr_tol < 1.0 && o->vr_floor >= o->vr_tol && o->vr_floor < 1.0 &&
           o->switch_eps > 0.0 && o->switch_eps < 1.0 && isfinite(o->delta) && o->max_steps >= 1 &&
           o->max_iter >= 1 && o->max_length >= 0.0 && isfinite(o->max_length) && o->loop_tol > 0.0 &&
           isfinite(o->loop_tol) && o->first_step > 0.0 && o->first_step <= 1.0 && o->branch_cos >= 0.0 &&
           o->branch_cos <= 1.0 && (o->steps_mode == KIN_FOLLOW_STEPS_CHEAP || o->steps_mode == KIN_FOLLOW_STEPS_SVD) &&
           o->branch_margin >= 0.0 && o->branch_margin <= HALF_PI && (!o->return_fn || o->return_own >= 0) &&
           (o->hold_hinges == 0 || o->hold_hinges == 1) && o->hold_rate_tol > 0.0 && o->hold_rate_tol < 1.0;
}

/* number of location attempts: vr_tol, then relaxed tenfold up to vr_floor */
static int max_attempts(const kin_follow_options *o)
{
    int n = 1;
    for (double t = o->vr_tol; t * RELAX_FACTOR <= o->vr_floor * (1.0 + 1e-9) && n < 64; t *= RELAX_FACTOR) ++n;
    return n;
}

/* the locator's progress made cumulative (progress_adapter) over the
 * attempts, or the caller's own callback back (between them, and at the
 * end) */
static void adapt_progress(follow_ctx *c)
{
    if (c->user_fn) {
        c->a->progress = progress_adapter;
        c->a->progress_user = c;
    }
}

static void user_progress(follow_ctx *c)
{
    c->a->progress = c->user_fn;
    c->a->progress_user = c->user_data;
}

/* STAGE 1: whether the follow can start here (a status; *at_bif: the start
 * is a bifurcation) */
static int check_start(kin_assembly *a, const double *dir, const kin_follow_options *o, int *at_bif)
{
    if (!options_ok(o)) return kin__fail(a, KIN_EINVAL, "follow options out of range");
    int nf = a->nf, rc = kin__cur(a)->valid ? KIN_OK : kin__analyse(a, NULL);
    if (rc) return rc;
    int m = kin__cur(a)->an.m_internal;
    *at_bif = m >= 2;
    if (m == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism to follow");
    if (*at_bif && !dir && !o->hold_hinges) /* with holds: hinge_hold.c may find the direction */
        return kin__fail(a, KIN_EBIFURCATION, "at a bifurcation (m_internal = %d): give a branch direction", m);
    if (dir)
        for (int i = 0; i < nf; ++i)
            if (!isfinite(dir[i])) return kin__fail(a, KIN_EINVAL, "dir[%d] is not finite", i);
    return KIN_OK;
}

/* STAGE 2: the call's state (c zeroed by the caller): its workspace, dir's
 * own branch and the start's second-order equations for the returns
 * (return_branch.c), the start point, the progress budget. A status
 * (nothing to free on failure). */
static int open_ctx(follow_ctx *c, kin_assembly *a, const double *dir, const kin_follow_options *o,
                    const follow_extra *x, kin_follow_info *info, int at_bif)
{
    int nf = a->nf;
    c->a = a;
    c->o = o;
    c->x = x;
    c->info = info;
    c->scale = a->rms_length;
    c->at_bif = at_bif;
    c->own = -1;
    c->stride = 1;
    c->user_fn = a->progress;
    c->user_data = a->progress_user;
    info->return_branch = -1;
#ifdef KIN_FOLLOW_TRACE
    fprintf(stderr, "follow start\n");
#endif
    size_t nc = (size_t)(a->nj * a->dim);
    c->xs = malloc(sizeof(double) * (6 * (size_t)nf + 2 * (nc + (size_t)nf) + (size_t)nf + (size_t)a->nb + 2 * nc +
                                     2 * (size_t)SLOPE_BLOCK * nf + (3 + ARRIVAL_KEEP) * (size_t)nf));
    if (!c->xs) return kin__fail(a, KIN_ENOMEM, "follow workspace");
    c->ts = c->xs + nf;
    c->xp = c->ts + nf;
    c->xq = c->xp + nf;
    c->xpp = c->xq + nf;
    c->tprev = c->xpp + nf;
    for (int k = 0; k < 2; ++k) {
        c->kept[k].p.xyz = c->tprev + nf + (size_t)k * (nc + (size_t)nf);
        c->kept[k].p.t = c->kept[k].p.xyz + nc;
    }
    c->u = c->kept[1].p.t + nf;
    c->w = c->u + nf;
    c->scr = c->w + a->nb;
    c->blk = c->scr + 2 * nc;
    c->kept[0].border = c->blk + 2 * (size_t)SLOPE_BLOCK * nf;
    c->kept[1].border = c->kept[0].border + nf;
    c->tarr = c->kept[1].border + nf;
    c->hist = c->tarr + nf;
    if (at_bif && (x->nbranch > 0 || o->return_fn)) {
        double ang = 0.0, gap = 0.0;
        c->own = o->return_fn ? o->return_own : kin__follow_nearest_branch(c, dir, &ang, &gap);
        int rc = kin__return_open(c);
        if (rc) {
            free(c->xs);
            return rc;
        }
    }
    kin__gather(a, a->xyz, c->xs);
    kin__contact_event_arm(a);
    memcpy(c->xp, c->xs, sizeof(double) * (size_t)nf);
    memcpy(c->xpp, c->xs, sizeof(double) * (size_t)nf);
    c->attempts = max_attempts(o);
    c->total = (double)o->max_steps + (double)o->max_iter * c->attempts;
    return KIN_OK;
}

static void close_ctx(follow_ctx *c)
{
    free(c->xs);
    kin__return_close(c);
}

/* STAGE 3, at a regular point: orient the path along dir (or keep the
 * handle's tangent, or take the analysis's). Not KIN_OK: nothing moved
 * (event NONE), the follow ends. */
static int orient_start(follow_ctx *c, const double *dir)
{
    kin_assembly *a = c->a;
    int nf = a->nf, rc = KIN_OK;
    if (dir) rc = kin_path_set_direction(a, dir, nf);
    else if (!a->have_t) {
        memcpy(a->t, kin__cur(a)->Uint, sizeof(double) * (size_t)nf);
        a->have_t = 1;
    }
    if (rc) return rc; /* nothing moved: event NONE */
    memcpy(c->ts, a->t, sizeof(double) * (size_t)nf);
    return KIN_OK;
}

/* STAGE 3, at a bifurcation: the first step along dir, its chord counted.
 * Not KIN_OK: the follow ends (dir refused: nothing moved, event NONE;
 * else event FAILED). */
static int leave_start(follow_ctx *c, const double *dir)
{
    kin_assembly *a = c->a;
    const kin_follow_options *o = c->o;
    kin_follow_info *info = c->info;
    int nf = a->nf, rc = KIN_OK;
    double nd = kin__norm(nf, dir);
    if (!(nd > 0.0)) return kin__fail(a, KIN_EINVAL, "dir is zero");
    if (kin__progress(a, 0.0, c->total)) {
        rc = kin__fail(a, KIN_ECANCELLED, "cancelled by the progress callback before the first step");
        info->event = KIN_FOLLOW_FAILED;
        return rc;
    }
    kin_step_info si = {.size = sizeof si};
    double cs = 0.0;
    /* Along some branches the vanishing singular values grow so slowly
     * (a high-order contact) that the first small step still counts as
     * a bifurcation: start again with a step ten times as long, up to
     * the largest step. */
    kin_assembly *start = NULL;
    if (kin_assembly_clone(a, &start)) return kin__fail(a, KIN_ENOMEM, "follow: a copy of the start");
    kin_options user_opt = a->opt;
    for (double fr = o->first_step;; fr *= RELAX_FACTOR) {
        if (o->steps_mode == KIN_FOLLOW_STEPS_CHEAP) kin__follow_first_step_lu(c, &user_opt);
        rc = kin__leave_bifurcation(a, dir, fr, &si, &cs);
        a->opt = user_opt;
        a->lu_inverse = 0;
        if (rc == KIN_OK && o->steps_mode == KIN_FOLLOW_STEPS_CHEAP &&
            (rc = kin__follow_first_point_verdict(c, &si)) != KIN_OK)
            break;
        if (rc || si.m_internal < 2 || fr * RELAX_FACTOR > 1.0) break;
        kin__copy_state(a, start);
    }
    kin_assembly_free(start);
    info->tangent_cos = cs;
    if (rc == KIN_EINVAL || rc == KIN_EGEOM || rc == KIN_ERANGE) return rc; /* dir refused: nothing moved */
    info->event = KIN_FOLLOW_FAILED;
    if (rc) return rc;
    info->steps = 1;
    if (cs < o->branch_cos)
        return kin__fail(a, KIN_EPATHJUMP,
                         "the first step left at cos %.3g to the branch direction (< %.3g): not a branch", cs,
                         o->branch_cos);
    memcpy(c->ts, a->t, sizeof(double) * (size_t)nf);
    (void)kin__follow_after_step(c, a); /* count the first chord */
    return KIN_OK;
}

/* STAGE 3 with held hinges, leaving along the held motion the holds found
 * (hinge_hold.c; not a direction of the caller's): a first-order motion.
 * Where it is no path of the structure (the first step's chord leaves it:
 * KIN_EPATHJUMP) the other sign is tried; where neither is a path the held
 * structure has no motion (at second order): *rigid, the assembly back at
 * the start. */
static int leave_held(follow_ctx *c, double *dir, int *rigid)
{
    kin_assembly *a = c->a, *save = NULL;
    if (kin_assembly_clone(a, &save)) return kin__fail(a, KIN_ENOMEM, "follow: a copy of the start");
    int rc = leave_start(c, dir);
    if (rc == KIN_EPATHJUMP) {
        kin__copy_state(a, save);
        for (int i = 0; i < a->nf; ++i) dir[i] = -dir[i];
        c->info->steps = 0;
        rc = leave_start(c, dir);
    }
    if (rc == KIN_EPATHJUMP) {
        kin__copy_state(a, save);
        c->info->steps = 0;
        c->info->event = KIN_FOLLOW_HELD_RIGID;
        kin__hold_mark_rigid(a);
        *rigid = 1;
        rc = KIN_OK;
    }
    kin_assembly_free(save);
    return rc;
}

/* STAGE 4 (KIN_FOLLOW_STEPS_CHEAP): regular stretches by LU steps, until
 * something may happen. *stop: the follow ends (a status, or an event) */
static int first_stretch(follow_ctx *c, int *stop)
{
    int rc = kin__follow_cheap_stretch(c, c->info, -INFINITY, stop);
    if (rc) {
        c->info->event = KIN_FOLLOW_FAILED;
        *stop = 1;
        return rc;
    }
    if (*stop) (void)kin__progress(c->a, c->total, c->total);
    return KIN_OK;
}

/* one location attempt by the locator, with after every step the hook:
 * first, where the cheap stretch left one, on the bracket its LU steps
 * stepped over; where that fails (or there is none), the usual handover.
 * The locator's status (KIN_ENOTFOUND: no event located) */
static int locate_attempt(follow_ctx *c, const kin_locate_options *lo, kin_locate_info *li, kin__locate_ws *lws)
{
    kin_assembly *a = c->a;
    lws->nonzero_min = 0.0;
    int rc = KIN__LOCATE_DIRECT_FAILED;
    if (c->direct) {
        /* the bracket the LU steps stepped over (kin__follow_cheap_stretch) */
        c->direct = 0;
        lws->direct_prev = &c->kept[1].p;
        lws->direct_border = c->kept[1].border;
        rc = kin__locate_hooked(a, lo, li, kin__follow_after_step, c, lws);
        if (rc == KIN__LOCATE_DIRECT_FAILED) {
            kin__follow_back_to_kept(c, c->direct_newer);
            *li = (kin_locate_info){.size = sizeof *li};
            lws->nonzero_min = 0.0;
        }
    }
    if (rc == KIN__LOCATE_DIRECT_FAILED) rc = kin__locate_hooked(a, lo, li, kin__follow_after_step, c, lws);
    return rc;
}

/* the SVD locator stepped over the suspect stretch and found nothing: LU
 * steps again, from its steps' counts (li). A status; *stop: the follow
 * ends */
static int resume_cheap(follow_ctx *c, const kin_locate_info *li, int *stop)
{
    kin_follow_info *info = c->info;
    info->steps += li->steps;
    c->done_base += li->steps;
    user_progress(c);
    int rc = kin__follow_cheap_stretch(c, info, c->rho_prev, stop);
    adapt_progress(c);
    c->done_base = info->steps;
    return rc;
}

/* An attempt's counts into info, and whether the follow ends with it
 * (returns 1: info->event set, *rc the call's status) or tries again with
 * the tolerance relaxed (*tol). rc: the locator's status. */
static int attempt_ends(follow_ctx *c, int *rc, const kin_locate_info *li, const kin__locate_ws *lws, double *tol)
{
    kin_assembly *a = c->a;
    const kin_follow_options *o = c->o;
    kin_follow_info *info = c->info;
    info->attempts++;
    info->steps += li->steps;
    info->forward += li->forward;
    info->factorizations += li->factorizations;
    c->done_base += li->steps + li->forward;
    info->v_r_rel = li->v_r_rel;
    info->m_internal = li->m_internal;
    info->s = li->s;
    if (*rc == KIN_OK) {
        info->event = KIN_FOLLOW_BIFURCATION;
        info->vr_tol_used = *tol;
        info->zero_order = li->zero_order;
        info->path_kept = li->path_kept;
        return 1;
    }
    if (*rc != KIN_ENOTFOUND) return 1; /* FAILED */
    *rc = KIN_OK;
    if (c->reason) {
        info->event = c->reason;
        return 1;
    }
    if (li->event == KIN_EVENT_NONE) {
        info->event = KIN_FOLLOW_STEP_LIMIT;
        return 1;
    }
    /* location gave up. The point it stopped at may already count as a
     * bifurcation with the handle's rank tolerance: located to the
     * floor of that point, as accurately as it could be */
    const kin_factor *f = kin__cur(a);
    if (f->valid && f->an.m_internal >= 2 && li->v_r_rel <= o->vr_floor) {
        info->event = KIN_FOLLOW_BIFURCATION;
        info->vr_tol_used = fmax(*tol, li->v_r_rel);
        info->path_kept = 1;
        return 1;
    }
    /* else try a tolerance nearer the floor from the regular point
     * before the event, or report the near miss */
    info->event = KIN_FOLLOW_NEAR_MISS;
    /* ... but not where the fast method found a non-zero minimum of v_r
     * above sqrt(vr_floor): each relaxed attempt steps over the same
     * bracket again and gives up on the same minimum (it calls a
     * minimum non-zero above sqrt of its own tolerance, and would have
     * to find a point a thousand times lower than any it saw to
     * succeed). The flat state's near misses (v_r / v_max 2e-4 ...
     * 1e-2) took all 5 attempts, each an SVD step, a start analysis
     * and a Hermite location: 4 of them for nothing */
    if (lws->nonzero_min > sqrt(o->vr_floor)) return 1;
    *tol *= RELAX_FACTOR;
    if (*tol > o->vr_floor * (1.0 + 1e-9)) return 1;
    return 0;
}

/* A bifurcation accepted only at a relaxed tolerance with one vanishing
 * singular value (m = 2) is a point within sqrt(tol) of either a crossing or
 * a smooth minimum of v_r above the strict tolerance (a near miss): the
 * relaxed floor cannot tell them apart (issue 35). Where the strict
 * attempt left its bracket (sb: start, end) the handle goes back there and
 * the minimum of v_r decides (near_minimum; the relaxed point kept in sb[2]
 * and its v_r / v_max, tolerance in relaxed). 1: done, the event is to be a
 * near miss until then */
static int relaxed_to_minimum(follow_ctx *c, kin__locate_ws *lws, kin_assembly *sb[3], double relaxed[2])
{
    kin_follow_info *info = c->info;
    if (info->event != KIN_FOLLOW_BIFURCATION || !sb[0] || info->m_internal != 2 ||
        !(info->vr_tol_used > c->o->vr_tol * (1.0 + 1e-9)))
        return 0;
    if (info->v_r_rel <= c->o->vr_tol) { /* the relaxed point is at the strict tolerance itself */
        info->vr_tol_used = c->o->vr_tol;
        return 0;
    }
    /* the relaxed point itself, for near_minimum */
    if (!sb[2] && kin_assembly_clone(c->a, &sb[2])) return 0;
    kin__copy_state(sb[2], c->a);
    relaxed[0] = info->v_r_rel;
    relaxed[1] = info->vr_tol_used;
    kin__copy_state(c->a, sb[0]);
    kin__copy_state(lws->work, sb[1]);
    lws->near_bracket = 1;
    info->vr_tol_used = 0.0;
    info->zero_order = 0;
    info->path_kept = 0;
    return 1;
}

/* bar lengths within this fraction of the RMS length of the given ones are
 * the given structure to the rounding of its model (the proofs of the
 * hexagonal sail's located crossings need 4e-16 .. 1.4e-14, docs/atlas.md) */
static const double ROUNDING_DLENGTH = 1e-12;

/* A corank-1 end whose v_r / v_max stays above the strict tolerance (a near
 * miss below vr_floor, or undecided) may be a crossing that the model's
 * rounding broke: a structure with bar lengths off by d from an exactly
 * singular one passes the crossing at v_r / v_max ~ sqrt(d) (the unfolding
 * of an imperfect bifurcation: 1e-8 for d ~ 1e-16), which neither a
 * minimum nor a relaxed point can bring to the strict tolerance, and which
 * side of it the path passes on follows rounding (issue 35). Moore's
 * extended system decides it (locate/sing_proof.c): where it proves an
 * exactly singular configuration of a structure whose bar lengths are within
 * ROUNDING_DLENGTH x the RMS length of the given ones, the end is the
 * proof's centre (a bifurcation of the structure as given, to its rounding;
 * v_r / v_max there at the strict tolerance, m and s counted at 10 x it).
 * 1 if so; otherwise the handle is back where it was (0), or a status < 0
 * on failure (out of memory) */
static int rounding_crossing(follow_ctx *c)
{
    kin_assembly *a = c->a;
    kin_follow_info *info = c->info;
    size_t n = (size_t)a->nj * a->dim;
    double *xyz = malloc(sizeof(double) * 2 * n), *keep = xyz + n;
    if (!xyz) return -KIN_ENOMEM;
    memcpy(keep, a->xyz, sizeof(double) * n);
    kin__sing_proof p;
    int rc = kin__sing_prove_centre(a, &p, xyz), ok = 0;
    if (rc == KIN_OK && p.proven && p.corank <= 1 && p.dlength <= ROUNDING_DLENGTH * a->rms_length) {
        kin__set_configuration(a, xyz);
        if ((rc = kin__analyse(a, NULL)) == KIN_OK) {
            double vmax = kin__cur(a)->an.v_max, v = vmax > 0.0 ? kin__loc_vanishing_sv(a) / vmax : NAN;
            if (v <= c->o->vr_tol) {
                kin_options user = a->opt;
                a->opt.rank_tol = fmax(user.rank_tol, 10.0 * c->o->vr_tol);
                rc = kin__reclassify(a, a->xyz, a->cur);
                a->opt = user;
                if (rc == KIN_OK) {
                    info->event = KIN_FOLLOW_BIFURCATION;
                    info->vr_tol_used = c->o->vr_tol;
                    info->v_r_rel = v;
                    info->min_located = 1;
                    info->min_width = p.distance / a->rms_length;
                    info->m_internal = kin__cur(a)->an.m_internal;
                    info->s = kin__cur(a)->an.s;
                    ok = 1;
                }
            }
        }
        if (!ok) { /* back to the end as it was */
            kin__set_configuration(a, keep);
            if (rc == KIN_OK) rc = kin__analyse(a, NULL);
        }
    }
    free(xyz);
    return rc == KIN_ENOMEM ? -KIN_ENOMEM : ok;
}

/* the near miss's end at the minimum of v_r / v_max (locate_nearmin.c) and
 * the decision there, with a margin (issue 35 item 4): v_r_rel <= vr_tol is
 * a bifurcation located to the strict tolerance (m, s counted at 10 x it, as
 * the locator's points are); otherwise a near miss whose vr_tol_used is the
 * floor a crossing would leave at that width (the caller calls it a near
 * miss only where v_r_rel is 10 x above it, else undecided). A status */
static int near_minimum(follow_ctx *c, kin__locate_ws *lws, kin_assembly *relaxed_pt, const double relaxed[2])
{
    kin_assembly *a = c->a;
    kin_follow_info *info = c->info;
    kin__near_min nm;
    int rc = kin__locate_near_minimum(a, lws, &nm);
    info->min_located = nm.located;
    info->min_width = nm.located ? nm.width : 0.0;
    info->min_evals = nm.evals;
    info->vr_tol_used = nm.located ? nm.floor : 0.0;
    if (rc) {
        info->event = KIN_FOLLOW_FAILED;
        return rc;
    }
    /* a relaxed point (relaxed_pt, its v_r / v_max and tolerance) lower than
     * the minimum found: that minimum is not the one the relaxed location
     * reached (several small singular values: v_r is not one smooth
     * function there). Undecided: the relaxed point, not located
     * (min_located 0), its tolerance as the floor */
    if (relaxed_pt && !(nm.located && nm.v_rel <= c->o->vr_tol) && (!nm.located || !(nm.v_rel <= relaxed[0]))) {
        /* Moore's system from the minimum first (the handle is there), then from the relaxed point */
        int r = nm.located && nm.v_rel <= c->o->vr_floor ? rounding_crossing(c) : 0;
        if (r) return r < 0 ? kin__fail(a, -r, "follow: the extended system at an undecided point") : KIN_OK;
        kin__copy_state(a, relaxed_pt);
        info->min_located = 0;
        info->min_width = 0.0;
        info->vr_tol_used = relaxed[1];
        r = rounding_crossing(c);
        return r < 0 ? kin__fail(a, -r, "follow: the extended system at an undecided point") : KIN_OK;
    }
    if (nm.located && nm.v_rel <= c->o->vr_tol) {
        kin_options user = a->opt;
        a->opt.rank_tol = fmax(user.rank_tol, 10.0 * c->o->vr_tol);
        rc = kin__reclassify(a, a->xyz, a->cur);
        a->opt = user;
        if (rc) {
            info->event = KIN_FOLLOW_FAILED;
            return rc;
        }
        info->event = KIN_FOLLOW_BIFURCATION;
        info->vr_tol_used = c->o->vr_tol;
        info->v_r_rel = nm.v_rel;
        info->m_internal = kin__cur(a)->an.m_internal;
        info->s = kin__cur(a)->an.s;
    } else if (nm.located && nm.v_rel <= c->o->vr_floor) { /* a near miss low enough to be rounding's */
        int r = rounding_crossing(c);
        if (r < 0) return kin__fail(a, -r, "follow: the extended system at a near miss");
    }
    return KIN_OK;
}

/* STAGE 5: follow and locate, relaxing the tolerance where it is out of
 * reach; a near miss ends at the minimum of v_r / v_max along the path. A
 * status. */
static int locate_events(follow_ctx *c)
{
    kin_assembly *a = c->a;
    const kin_follow_options *o = c->o;
    kin_follow_info *info = c->info;
    int rc = KIN_OK;
    adapt_progress(c);
    c->done_base = info->steps;
    kin_locate_options lo;
    kin_locate_options_default(&lo);
    lo.method = KIN_LOCATE_FAST;
    lo.switch_eps = o->switch_eps;
    lo.delta = o->delta;
    lo.max_iter = o->max_iter;
    double tol = o->vr_tol;
    /* the locator's working copies, made once for all the attempts and
     * handovers of this call (1.1 handovers and 1.0 attempts per branch on
     * the flat state: 5 clones at each was 4% of the time) */
    kin__locate_ws lws = {0};
    kin_assembly *sb[3] = {NULL, NULL, NULL}; /* the strict attempt's bracket; a relaxed point */
    /* cheap steps: the Hermite nodes from LU steps too (locate.h) */
    lws.lu_nodes = o->steps_mode == KIN_FOLLOW_STEPS_CHEAP;
    for (int k = 0; k < c->attempts; ++k) {
        int left = o->max_steps - info->steps;
        if (left < 1) {
            info->event = KIN_FOLLOW_STEP_LIMIT;
            rc = KIN_OK;
            break;
        }
        lo.vr_tol = tol;
        lo.max_steps = left;
        kin_locate_info li = {.size = sizeof li};
        rc = locate_attempt(c, &lo, &li, &lws);
        int resume = c->reason == REASON_RESUME;
        if (resume) c->reason = 0;
        kin__follow_resync(c);
        if (rc == KIN_ENOTFOUND && resume && li.event == KIN_EVENT_NONE) {
            int stop = 0;
            rc = resume_cheap(c, &li, &stop);
            if (rc) break;
            if (stop) {
                rc = KIN_OK;
                break;
            }
            --k; /* not an attempt */
            continue;
        }
        /* the strict attempt's bracket, kept for relaxed_to_minimum */
        if (rc == KIN_ENOTFOUND && tol == o->vr_tol && lws.near_bracket && !sb[0]) {
            if (kin_assembly_clone(a, &sb[0]) || kin_assembly_clone(lws.work, &sb[1])) {
                rc = kin__fail(a, KIN_ENOMEM, "follow: a copy of the bracket");
                break;
            }
        }
        if (attempt_ends(c, &rc, &li, &lws, &tol)) break;
    }
    /* a corank-1 point accepted only at a relaxed tolerance is decided at
     * the minimum of v_r over the strict attempt's bracket instead */
    double relaxed[2] = {0.0, 0.0};
    int conv = rc == KIN_OK && relaxed_to_minimum(c, &lws, sb, relaxed);
    if (conv) info->event = KIN_FOLLOW_NEAR_MISS;
    /* a near miss ends at the minimum of v_r / v_max along the path, found
     * within the bracket the last location attempt gave up on */
    if (rc == KIN_OK && info->event == KIN_FOLLOW_NEAR_MISS && lws.near_bracket)
        rc = near_minimum(c, &lws, conv ? sb[2] : NULL, relaxed);
    for (int i = 0; i < 3; ++i) kin_assembly_free(sb[i]);
    kin__locate_ws_free(&lws);
    user_progress(c);
    if (conv && info->event == KIN_FOLLOW_NEAR_MISS && !info->min_located)
        info->v_r_rel = relaxed[0]; /* undecided: the relaxed point's own value */
    else if (info->event == KIN_FOLLOW_NEAR_MISS && kin__cur(a)->valid) /* the path's own singular value,
        which the rank tolerance may count as zero (then an.v_r is the next one up) */
        info->v_r_rel = kin__loc_vanishing_sv(a) / kin__cur(a)->an.v_max;
    if (rc == KIN_OK) (void)kin__progress(a, c->total, c->total);
    return rc;
}

/* STAGE 6, however the follow ended (rc its status so far): a contact
 * located, the length, the distance from the start, the samples, the end
 * point's analysis. Returns the call's status. */
static int finish(follow_ctx *c, int rc)
{
    kin_assembly *a = c->a;
    const kin_follow_options *o = c->o;
    kin_follow_info *info = c->info;
    int nf = a->nf;
    /* a contact, whether an LU step or an SVD step met it: located here,
     * once, with the handle's own options */
    if (rc == KIN_OK && info->event == KIN_FOLLOW_CONTACT && (rc = kin__contact_event_locate(a)) != KIN_OK)
        info->event = KIN_FOLLOW_FAILED;
    if (c->hook_rc) { /* return_fn failed: the follow stopped there */
        rc = c->hook_rc;
        info->event = KIN_FOLLOW_FAILED;
    }
    info->status = rc;
    kin__contact_event_finish(a);
    /* a contact located within the last step: the length to it */
    info->length = c->length - (rc == KIN_OK && info->event == KIN_FOLLOW_CONTACT ? kin__contact_event_back(a) : 0.0);
    {
        double *xe = c->xq;
        kin__gather(a, a->xyz, xe);
        info->start_distance = kin__follow_distance(nf, xe, c->xs) / c->scale;
        info->at_start = info->event == KIN_FOLLOW_CLOSED_LOOP ||
                         (info->event == KIN_FOLLOW_BIFURCATION && c->at_bif && info->start_distance <= o->loop_tol);
    }
    info->samples = kin__follow_deliver_samples(c);
    if (!kin__cur(a)->valid && info->event != KIN_FOLLOW_NONE) (void)kin__analyse(a, NULL); /* after LU steps */
    if (kin__cur(a)->valid && info->event != KIN_FOLLOW_BIFURCATION && info->event != KIN_FOLLOW_NEAR_MISS) {
        info->m_internal = kin__cur(a)->an.m_internal;
        info->s = kin__cur(a)->an.s;
        info->v_r_rel = kin__cur(a)->an.v_max > 0 ? kin__cur(a)->an.v_r / kin__cur(a)->an.v_max : 0.0;
    }
    kin__hold_finish(a, o, info); /* held hinges: new holds, reopenings, the held analysis */
    return rc;
}

/* The stages of a follow: check_start, open_ctx, orient_start or
 * leave_start, first_stretch (cheap steps), locate_events, finish. */
static int follow_impl(kin_assembly *a, const double *dir, const kin_follow_options *o, const follow_extra *x,
                       kin_follow_info *info)
{
    int at_bif = 0, held_event = 0, rigid = 0;
    const double *user_dir = dir;
    info->hinge = -1, info->held_m = -1;
    int rc = check_start(a, dir, o, &at_bif);
    if (rc) return rc;
    /* held hinges (hinge_hold.c): the direction they leave, or none */
    if ((rc = kin__hold_start(a, o, dir, &at_bif, &dir, &held_event, &info->reopened)) != KIN_OK) {
        kin__hold_abort(a);
        return rc;
    }
    if (!held_event && at_bif && !dir) {
        kin__hold_abort(a);
        return kin__fail(a, KIN_EBIFURCATION, "at a bifurcation (m_internal = %d): give a branch direction",
                         kin__cur(a)->an.m_internal);
    }
    if (held_event) {
        /* nothing to follow: the structure with its holds is rigid here */
        info->event = held_event;
        info->held = kin__hold_abort(a);
        info->held_m = 0;
        info->m_internal = kin__cur(a)->an.m_internal, info->s = kin__cur(a)->an.s;
        return KIN_OK;
    }
    follow_ctx c = {0};
    if ((rc = open_ctx(&c, a, dir, o, x, info, at_bif)) != KIN_OK) {
        kin__hold_abort(a);
        return rc;
    }
    /* the start: orient (regular point) or leave the bifurcation */
    info->tangent_cos = 1.0;
    if (at_bif && dir != user_dir) rc = leave_held(&c, (double *)dir, &rigid); /* the holds' buffer */
    else rc = at_bif ? leave_start(&c, dir) : orient_start(&c, dir);
    int stop = rc != KIN_OK || rigid;
    if (!stop) {
        info->event = KIN_FOLLOW_FAILED;
        if (o->steps_mode == KIN_FOLLOW_STEPS_CHEAP) rc = first_stretch(&c, &stop);
        if (!stop) rc = locate_events(&c);
    }
    rc = finish(&c, rc);
    close_ctx(&c);
    return rc;
}


int kin_follow_event_ex(kin_assembly *a, const double *dir, const kin_follow_options *opt, const double *branches,
                        int nbranch, double *samples, double *sample_length, int capacity, int *nsamples,
                        kin_follow_info *info)
{
    kin_follow_options o;
    kin_follow_options_default(&o); /* fields an older caller does not have keep their defaults */
    int rc = kin__abi_entry(a, info, KIN__ABI(kin_follow_info), opt, &o, KIN__ABI(kin_follow_options));
    if (rc) return rc;
    if (nsamples) *nsamples = 0;
    if (nbranch < 0 || (nbranch > 0 && !branches) || capacity < 0 || (capacity > 0 && !nsamples)) {
        if (info) kin__abi_zero(info);
        return kin__fail(a, KIN_EINVAL, "follow: nbranch %d, capacity %d (or a NULL buffer)", nbranch, capacity);
    }
    if (nbranch > 0 && o.return_fn) {
        if (info) kin__abi_zero(info);
        return kin__fail(a, KIN_EINVAL, "follow: branch directions given both as branches and by return_fn");
    }
    for (long i = 0; i < (long)nbranch * a->nf; ++i)
        if (!isfinite(branches[i])) {
            if (info) kin__abi_zero(info);
            return kin__fail(a, KIN_EINVAL, "branches[%ld] is not finite", i);
        }
    follow_extra x = {branches, nbranch, samples, sample_length, capacity, NULL, NULL, NULL, 0};
    if (capacity > 0) {
        size_t nc = (size_t)(a->nj * a->dim);
        x.rec_room = capacity > (INT_MAX - 4) / 2 ? INT_MAX : 2 * capacity + 4;
        x.rec = malloc(sizeof(double) * nc * (size_t)x.rec_room);
        x.rec_len = malloc(sizeof(double) * (size_t)x.rec_room);
        x.rec_idx = malloc(sizeof(int) * (size_t)x.rec_room);
        if (!x.rec || !x.rec_len || !x.rec_idx) {
            free(x.rec);
            free(x.rec_len);
            free(x.rec_idx);
            if (info) kin__abi_zero(info);
            return kin__fail(a, KIN_ENOMEM, "follow: the sample record");
        }
    }
    kin_follow_info local = {.size = sizeof local};
    /* small matrices: one BLAS thread (model/blas_threads.c), the caller's setting restored */
    int token = kin__blas_threads_small(a);
    rc = follow_impl(a, dir, &o, &x, &local);
    kin__blas_threads_restore(token);
    free(x.rec);
    free(x.rec_len);
    free(x.rec_idx);
    if (nsamples) *nsamples = local.samples;
    if (info) {
        if (local.event == KIN_FOLLOW_NONE && rc != KIN_OK) {
            kin__abi_zero(info);
        } else {
            kin__abi_write(info, &local, KIN__ABI(kin_follow_info));
        }
    }
    return rc;
}

int kin_follow_event(kin_assembly *a, const double *dir, const kin_follow_options *opt, kin_follow_info *info)
{
    return kin_follow_event_ex(a, dir, opt, NULL, 0, NULL, NULL, 0, NULL, info);
}
