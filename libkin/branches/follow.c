/* Following a path to its next event (kin_follow.h, docs/follow.md): the
 * locator (kin_locate_next, fast method) does the following and the
 * location; this file adds the start off a bifurcation, the closed-loop and
 * path-length checks after every step (a hook of the locator), the
 * relaxation of the location tolerance where rounding puts it out of reach,
 * and the classification of how the path ended. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "branches/contact_event.h"
#include "model/internal.h"
#include "path/path.h"
#include "locate/locate.h"
#include "branches/branches_internal.h"

/* a return to the start counts only with the tangent parallel to the
 * start's to this |cos| (another path through a nearby point does not) */
static const double LOOP_TANGENT_COS = 0.9;
/* each relaxation of the location tolerance multiplies it by this */
static const double RELAX_FACTOR = 10.0;

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

typedef struct follow_ctx {
    kin_assembly *a;
    const kin_follow_options *o;
    double *xs, *ts;  /* start: free coordinates and tangent */
    double *xp, *xq;  /* the previous point and the new one */
    double *xpp;      /* the point before xp, where the path had length len_pp */
    double scale;     /* RMS rest length */
    double length;    /* sum of chords */
    double len_pp;
    int left;         /* has been 2 loop_tol away from the start */
    int reason;       /* KIN_FOLLOW_CLOSED_LOOP / _LENGTH_LIMIT when the hook stopped */
    /* progress: the caller's callback, fed cumulative counts */
    kin_progress_fn user_fn;
    void *user_data;
    double done_base, total;
} follow_ctx;

/* distance from point p to the segment [x0, x1] (n entries) */
static double segment_distance(int n, const double *x0, const double *x1, const double *p)
{
    double dd = 0.0, dp = 0.0;
    for (int i = 0; i < n; ++i) {
        dd += (x1[i] - x0[i]) * (x1[i] - x0[i]);
        dp += (x1[i] - x0[i]) * (p[i] - x0[i]);
    }
    double s = dd > 0.0 ? dp / dd : 0.0, r = 0.0;
    if (s < 0.0) s = 0.0;
    if (s > 1.0) s = 1.0;
    for (int i = 0; i < n; ++i) {
        double v = x0[i] + s * (x1[i] - x0[i]) - p[i];
        r += v * v;
    }
    return sqrt(r);
}

static double distance(int n, const double *x, const double *y)
{
    double r = 0.0;
    for (int i = 0; i < n; ++i) r += (x[i] - y[i]) * (x[i] - y[i]);
    return sqrt(r);
}

/* after every accepted step: count the chord, stop on a return to the start
 * or at the length budget */
static int after_step(void *user, const kin_assembly *a)
{
    follow_ctx *c = user;
    int nf = a->nf;
    kin__gather(a, a->xyz, c->xq);
    c->len_pp = c->length;
    memcpy(c->xpp, c->xp, sizeof(double) * (size_t)nf);
    c->length += distance(nf, c->xp, c->xq);
    double tol = c->o->loop_tol * c->scale;
    int stop = 0, was_away = c->left; /* away from the start before this chord */
    if (distance(nf, c->xq, c->xs) > 2.0 * tol) c->left = 1;
    if (was_away && segment_distance(nf, c->xp, c->xq, c->xs) <= tol &&
        fabs(kin__dot(nf, a->t, c->ts)) >= LOOP_TANGENT_COS) {
        c->reason = KIN_FOLLOW_CLOSED_LOOP;
        stop = 1;
    } else if (c->o->max_length > 0.0 && c->length >= c->o->max_length) {
        c->reason = KIN_FOLLOW_LENGTH_LIMIT;
        stop = 1;
    } else if (kin__contact_event_check(c->a, c->xp)) {
        c->reason = KIN_FOLLOW_CONTACT;
        stop = 1;
    }
    memcpy(c->xp, c->xq, sizeof(double) * (size_t)nf);
    return stop;
}

/* After the locator returns: the assembly is at the last step's point, the
 * located point within the last step, or (location gave up) the point
 * before the last step. The length is the one at the point before the last
 * step plus the distance from there; that point starts the next attempt. */
static void resync(follow_ctx *c)
{
    int nf = c->a->nf;
    kin__gather(c->a, c->a->xyz, c->xq);
    c->length = c->len_pp + distance(nf, c->xpp, c->xq);
    c->len_pp = c->length;
    memcpy(c->xp, c->xq, sizeof(double) * (size_t)nf);
    memcpy(c->xpp, c->xq, sizeof(double) * (size_t)nf);
    /* the locator may have moved back towards the start: the next chord
     * counts for a return only if this point is away from it */
    c->left = distance(nf, c->xq, c->xs) > 2.0 * c->o->loop_tol * c->scale;
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
           o->branch_cos <= 1.0;
}

/* number of location attempts: vr_tol, then relaxed tenfold up to vr_floor */
static int max_attempts(const kin_follow_options *o)
{
    int n = 1;
    for (double t = o->vr_tol; t * RELAX_FACTOR <= o->vr_floor * (1.0 + 1e-9) && n < 64; t *= RELAX_FACTOR) ++n;
    return n;
}

static int follow_impl(kin_assembly *a, const double *dir, const kin_follow_options *o, kin_follow_info *info)
{
    if (!options_ok(o)) return kin__fail(a, KIN_EINVAL, "follow options out of range");
    int nf = a->nf, rc = kin__cur(a)->valid ? KIN_OK : kin__analyse(a, NULL);
    if (rc) return rc;
    int m = kin__cur(a)->an.m_internal, at_bif = m >= 2;
    if (m == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism to follow");
    if (at_bif && !dir)
        return kin__fail(a, KIN_EBIFURCATION, "at a bifurcation (m_internal = %d): give a branch direction", m);
    if (dir)
        for (int i = 0; i < nf; ++i)
            if (!isfinite(dir[i])) return kin__fail(a, KIN_EINVAL, "dir[%d] is not finite", i);

    follow_ctx c = {a, o, NULL, NULL, NULL, NULL, NULL, a->rms_length, 0.0, 0.0, 0, 0, a->progress, a->progress_user,
                    0.0, 0.0};
    c.xs = malloc(sizeof(double) * 5 * (size_t)nf);
    if (!c.xs) return kin__fail(a, KIN_ENOMEM, "follow workspace");
    c.ts = c.xs + nf;
    c.xp = c.ts + nf;
    c.xq = c.xp + nf;
    c.xpp = c.xq + nf;
    kin__gather(a, a->xyz, c.xs);
    kin__contact_event_arm(a);
    memcpy(c.xp, c.xs, sizeof(double) * (size_t)nf);
    memcpy(c.xpp, c.xs, sizeof(double) * (size_t)nf);
    int attempts = max_attempts(o);
    c.total = (double)o->max_steps + (double)o->max_iter * attempts;

    /* the start: orient (regular point) or leave the bifurcation */
    info->tangent_cos = 1.0;
    if (!at_bif) {
        if (dir) rc = kin_path_set_direction(a, dir, nf);
        else if (!a->have_t) {
            memcpy(a->t, kin__cur(a)->Uint, sizeof(double) * (size_t)nf);
            a->have_t = 1;
        }
        if (rc) goto out; /* nothing moved: event NONE */
        memcpy(c.ts, a->t, sizeof(double) * (size_t)nf);
    } else {
        double nd = kin__norm(nf, dir);
        if (!(nd > 0.0)) {
            rc = kin__fail(a, KIN_EINVAL, "dir is zero");
            goto out;
        }
        if (kin__progress(a, 0.0, c.total)) {
            rc = kin__fail(a, KIN_ECANCELLED, "cancelled by the progress callback before the first step");
            info->event = KIN_FOLLOW_FAILED;
            goto out;
        }
        kin_step_info si = {.size = sizeof si};
        double cs = 0.0;
        /* Along some branches the vanishing singular values grow so slowly
         * (a high-order contact) that the first small step still counts as
         * a bifurcation: start again with a step ten times as long, up to
         * the largest step. */
        kin_assembly *start = NULL;
        if (kin_assembly_clone(a, &start)) {
            rc = kin__fail(a, KIN_ENOMEM, "follow: a copy of the start");
            goto out;
        }
        for (double fr = o->first_step;; fr *= RELAX_FACTOR) {
            rc = kin__leave_bifurcation(a, dir, fr, &si, &cs);
            if (rc || si.m_internal < 2 || fr * RELAX_FACTOR > 1.0) break;
            kin__copy_state(a, start);
        }
        kin_assembly_free(start);
        info->tangent_cos = cs;
        if (rc == KIN_EINVAL || rc == KIN_EGEOM || rc == KIN_ERANGE) goto out; /* dir refused: nothing moved */
        info->event = KIN_FOLLOW_FAILED;
        if (rc) goto out;
        info->steps = 1;
        if (cs < o->branch_cos) {
            rc = kin__fail(a, KIN_EPATHJUMP,
                           "the first step left at cos %.3g to the branch direction (< %.3g): not a branch", cs,
                           o->branch_cos);
            goto out;
        }
        memcpy(c.ts, a->t, sizeof(double) * (size_t)nf);
        (void)after_step(&c, a); /* count the first chord */
    }
    info->event = KIN_FOLLOW_FAILED;

    /* follow and locate, relaxing the tolerance where it is out of reach */
    if (c.user_fn) {
        a->progress = progress_adapter;
        a->progress_user = &c;
    }
    c.done_base = info->steps;
    kin_locate_options lo;
    kin_locate_options_default(&lo);
    lo.method = KIN_LOCATE_FAST;
    lo.switch_eps = o->switch_eps;
    lo.delta = o->delta;
    lo.max_iter = o->max_iter;
    double tol = o->vr_tol;
    for (int k = 0; k < attempts; ++k) {
        int left = o->max_steps - info->steps;
        if (left < 1) {
            info->event = KIN_FOLLOW_STEP_LIMIT;
            rc = KIN_OK;
            break;
        }
        lo.vr_tol = tol;
        lo.max_steps = left;
        kin_locate_info li = {.size = sizeof li};
        rc = kin__locate_hooked(a, &lo, &li, after_step, &c);
        info->attempts++;
        resync(&c);
        info->steps += li.steps;
        info->forward += li.forward;
        info->factorizations += li.factorizations;
        c.done_base += li.steps + li.forward;
        info->v_r_rel = li.v_r_rel;
        info->m_internal = li.m_internal;
        info->s = li.s;
        if (rc == KIN_OK) {
            info->event = KIN_FOLLOW_BIFURCATION;
            info->vr_tol_used = tol;
            info->zero_order = li.zero_order;
            info->path_kept = li.path_kept;
            break;
        }
        if (rc != KIN_ENOTFOUND) break; /* FAILED */
        rc = KIN_OK;
        if (c.reason) {
            info->event = c.reason;
            if (c.reason == KIN_FOLLOW_CONTACT && (rc = kin__contact_event_locate(a)) != KIN_OK)
                info->event = KIN_FOLLOW_FAILED;
            break;
        }
        if (li.event == KIN_EVENT_NONE) {
            info->event = KIN_FOLLOW_STEP_LIMIT;
            break;
        }
        /* location gave up. The point it stopped at may already count as a
         * bifurcation with the handle's rank tolerance: located to the
         * floor of that point, as accurately as it could be */
        const kin_factor *f = kin__cur(a);
        if (f->valid && f->an.m_internal >= 2 && li.v_r_rel <= o->vr_floor) {
            info->event = KIN_FOLLOW_BIFURCATION;
            info->vr_tol_used = fmax(tol, li.v_r_rel);
            info->path_kept = 1;
            break;
        }
        /* else try a tolerance nearer the floor from the regular point
         * before the event, or report the near miss */
        info->event = KIN_FOLLOW_NEAR_MISS;
        tol *= RELAX_FACTOR;
        if (tol > o->vr_floor * (1.0 + 1e-9)) break;
    }
    a->progress = c.user_fn;
    a->progress_user = c.user_data;
    if (info->event == KIN_FOLLOW_NEAR_MISS && kin__cur(a)->valid)
        info->v_r_rel = kin__cur(a)->an.v_r / kin__cur(a)->an.v_max;
    if (rc == KIN_OK) (void)kin__progress(a, c.total, c.total);
out:
    info->status = rc;
    info->length = c.length;
    {
        double *xe = c.xq;
        kin__gather(a, a->xyz, xe);
        info->start_distance = distance(nf, xe, c.xs) / c.scale;
        info->at_start = info->event == KIN_FOLLOW_CLOSED_LOOP ||
                         (info->event == KIN_FOLLOW_BIFURCATION && at_bif && info->start_distance <= o->loop_tol);
    }
    if (kin__cur(a)->valid && info->event != KIN_FOLLOW_BIFURCATION && info->event != KIN_FOLLOW_NEAR_MISS) {
        info->m_internal = kin__cur(a)->an.m_internal;
        info->s = kin__cur(a)->an.s;
        info->v_r_rel = kin__cur(a)->an.v_max > 0 ? kin__cur(a)->an.v_r / kin__cur(a)->an.v_max : 0.0;
    }
    free(c.xs);
    return rc;
}

int kin_follow_event(kin_assembly *a, const double *dir, const kin_follow_options *opt, kin_follow_info *info)
{
    kin_follow_options o;
    kin_follow_options_default(&o); /* fields an older caller does not have keep their defaults */
    int rc = kin__abi_entry(a, info, KIN__ABI(kin_follow_info), opt, &o, KIN__ABI(kin_follow_options));
    if (rc) return rc;
    kin_follow_info local = {.size = sizeof local};
    rc = follow_impl(a, dir, &o, &local);
    if (info) {
        if (local.event == KIN_FOLLOW_NONE && rc != KIN_OK) {
            kin__abi_zero(info);
        } else {
            kin__abi_write(info, &local, KIN__ABI(kin_follow_info));
        }
    }
    return rc;
}
