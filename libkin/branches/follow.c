/* Following a path to its next event (kin_follow.h, docs/follow.md): the
 * locator (kin_locate_next, fast method) does the location and the
 * following near events; this file adds, in the order of a call: the start
 * off a bifurcation (follow_impl); the cheap stretches of LU steps between
 * events and the handovers to and from the locator (cheap_stretch, the
 * hook's resume); the checks after every step, in both (after_step: path
 * length, samples, the return to the start and whether it is a loop, with
 * the start's branch directions if given: is_loop); the relaxation of the
 * location tolerance where rounding puts it out of reach; and the
 * classification of how the path ended. A new kind of event belongs in
 * after_step (a stop with its own reason) and in that classification. */
#include <math.h>
#ifdef KIN_FOLLOW_TRACE
#include <stdio.h>
#endif
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "branches/contact_event.h"
#include "model/internal.h"
#include "path/path.h"
#include "locate/locate.h"
#include "branches/branches_internal.h"

/* a return to the start counts only with the tangent parallel to the
 * start's to this |cos| (another path through a nearby point does not),
 * where the caller gave no branch directions */
static const double LOOP_TANGENT_COS = 0.9;
/* each relaxation of the location tolerance multiplies it by this */
static const double RELAX_FACTOR = 10.0;
/* cheap stretches hand over to the SVD locator where the estimated
 * v_r / v_max is below this multiple of switch_eps, and LU steps resume
 * only above it. The detector's turn rule fires on any turn of v_r whose
 * tangent lines meet below switch_eps, however shallow; the LU estimates
 * (an upper bound, a few 1e-3 relative) cannot show such a dip (the
 * hexagonal sail's R^C: 3 of 64 near misses at v_r / v_max 0.0054 missed
 * with 0.1 here), so below the threshold, with a margin, every step is an
 * SVD step. */
static const double CHEAP_NEAR_FACTOR = 3.0;
/* below it the slope of the vanishing singular value is computed as the SVD
 * detector does (kin__sv_derivative), from the singular vectors by inverse
 * iteration with the LU factors: at most this many passes, until the unit
 * vector moves less than this (else the SVD takes over) */
enum { SLOPE_PASSES = 40 };
/* ... by subspace iteration with this many vectors (kin__lu_vr_triple): the
 * flat state's lowest singular values come in close groups, where one
 * vector converges at (v_r / v_(r-1))^2 per pass: on the 200-branch
 * benchmark 11.6 passes per point, 1% of points not converged in 40 (each a
 * handover), 12% of the cheap follower's time. With 2 vectors 5.4 passes
 * (each about 1.6x the cost of one vector's) and every point converged;
 * 3 and 4 vectors take 4.8 and 4.4 passes at 2.3x and 2.6x the cost. */
enum { SLOPE_BLOCK = 2 };
static const double SLOPE_VECTOR_TOL = 1e-9;
/* a slope below this x v_max / RMS length is too flat to tell its sign:
 * the SVD takes over */
static const double SLOPE_ZERO = 1e-6;
/* the turn rule's threshold, switch_eps x v_max, with this margin for the
 * lower-bound estimate of v_max */
static const double SLOPE_TURN_MARGIN = 1.5;
/* the LU steps count singular values as zero (and fall back to the SVD)
 * below 1000 x this fraction of vr_tol, as the locator's steps do */
static const double CHEAP_RANK_FRACTION = 1e-3;
/* after a handover the SVD locator steps at least this many steps, and up
 * to the point where the cheap stretch stopped (a step that failed: past
 * it, and 2 steps), before LU steps resume. The detectors have then seen
 * the suspect step with the SVD: resuming at its end, not a step later,
 * saves an SVD step per handover that finds nothing (2 before) */
enum { RESUME_AFTER = 1, RESUME_AFTER_FAILED = 2 };
/* ... and, where v_r / v_max is below CHEAP_NEAR_FACTOR x switch_eps, only
 * once v_r is at most RESUME_GAP of the singular value SLOPE_BLOCK above it
 * (the slope's subspace converges at their ratio squared per pass) and at
 * most RESUME_PAIR_GAP of the next one (the Ritz vector of v_r within the
 * subspace needs that gap: at R^B, without it, the iteration did not
 * converge in 40 passes and the SVD took over again at the next step, 5.6
 * handovers a branch instead of 1.3). Measured against the earlier rule
 * (RESUME_GAP of the next singular value): LU-only steps 90% -> 94% on the
 * flat state's 200 branches, 62% -> 73% at R^B, the same events and points */
static const double RESUME_GAP = 0.5;
static const double RESUME_PAIR_GAP = 0.9;
/* follow_ctx.reason: the SVD locator handed back to LU steps */
enum { REASON_RESUME = -1 };
static const double HALF_PI = 1.5707963267948966;

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

/* the caller's extras (kin_follow_event_ex) */
typedef struct follow_extra {
    const double *branches; /* nbranch x nf, or NULL */
    int nbranch;
    double *samples, *sample_length; /* capacity entries, or NULL */
    int capacity;
    /* the record behind them: room for 2 capacity + 4 points, their path
     * indices and lengths (SAMPLES below) */
    double *rec, *rec_len;
    int *rec_idx, rec_room;
} follow_extra;

/* a point the cheap stretch may go back to, with the follower's counters there */
typedef struct kept_point {
    kin__path_point p;
    double *border; /* nf: the border row of its LU factors (the tangent before the step to it) */
    int has_border; /* it was an LU point (its factors can be made again) */
    double length;
    int left, index;
} kept_point;

typedef struct follow_ctx {
    kin_assembly *a;
    const kin_follow_options *o;
    const follow_extra *x;
    kin_follow_info *info;
    double *xs, *ts;  /* start: free coordinates and tangent */
    double *xp, *xq;  /* the previous point and the new one */
    double *xpp;      /* the point before xp, where the path had length len_pp */
    double *tprev;    /* cheap stretch: the tangent before the step */
    double *u, *w, *scr; /* cheap stretch: singular vectors (nf, nb), scratch (2 nj dim) */
    double *blk;      /* ... the slope's subspace (2 SLOPE_BLOCK nf), its Ritz vectors kept where blk_warm */
    int blk_warm;
    kin_assembly *probe; /* with branch directions: a copy to measure a return's direction on */
    double scale;     /* RMS rest length */
    double length;    /* sum of chords */
    double len_pp;
    int left;         /* has been 2 loop_tol away from the start */
    int reason;       /* KIN_FOLLOW_CLOSED_LOOP / _LENGTH_LIMIT when the hook stopped */
    int at_bif;       /* the start is a bifurcation */
    int own;          /* index of dir's own branch among x->branches (or o->return_fn's lines), or -1 */
    int hook_rc;      /* o->return_fn failed: the call's status (event FAILED) */
    /* SAMPLES: the current point's index along the path (steps from the
     * start), the points recorded, every stride-th index */
    int p, nrec, stride;
    kept_point kept[2]; /* cheap stretch: the two points before the current one */
    int nkept;
    /* after a handover: SVD steps taken, the length to pass, and the exact
     * v_r / v_max at the last two SVD points */
    int watch, svd_steps, resume_after;
    double resume_len, rho_prev, rho_cur;
    /* a handover on a sign change the SVD locator would bracket at once
     * (cheap_stretch): the handle left at the bracket's end, kept[1] its
     * start; direct_newer: the kept point the usual handover goes back to */
    int direct, direct_newer;
    /* progress: the caller's callback, fed cumulative counts */
    kin_progress_fn user_fn;
    void *user_data;
    double done_base, total;
} follow_ctx;

/* distance from point p to the segment [x0, x1] (n entries); *s the
 * parameter of the nearest point */
static double segment_distance(int n, const double *x0, const double *x1, const double *p, double *sp)
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
    if (sp) *sp = s;
    return sqrt(r);
}

static double distance(int n, const double *x, const double *y)
{
    double r = 0.0;
    for (int i = 0; i < n; ++i) r += (x[i] - y[i]) * (x[i] - y[i]);
    return sqrt(r);
}

/* angle (radians, in [0, pi/2]) between the lines of u and v (n entries):
 * atan2 of the sine and |cosine|, accurate for nearly parallel lines */
static double line_angle(int n, const double *u, const double *v)
{
    double uu = kin__dot(n, u, u), vv = kin__dot(n, v, v), uv = kin__dot(n, u, v);
    if (!(uu > 0.0 && vv > 0.0)) return HALF_PI;
    double s2 = 0.0, k = uv / vv;
    for (int i = 0; i < n; ++i) s2 += (u[i] - k * v[i]) * (u[i] - k * v[i]);
    return atan2(sqrt(s2 / uu), fabs(uv) / sqrt(uu * vv));
}

/* the branch nearest the line of t: its index, angle, and the gap to the
 * next nearest (INFINITY with one branch) */
static int nearest_branch(const follow_ctx *c, const double *t, double *angle, double *gap)
{
    int nf = c->a->nf, best = -1;
    double b1 = INFINITY, b2 = INFINITY;
    for (int j = 0; j < c->x->nbranch; ++j) {
        double g = line_angle(nf, t, c->x->branches + (size_t)j * nf);
        if (g < b1) {
            b2 = b1;
            b1 = g;
            best = j;
        } else if (g < b2) {
            b2 = g;
        }
    }
    *angle = b1;
    *gap = b2 - b1;
    return best;
}

/* SAMPLES. The points of the path's steps, by index p (the start 0): the
 * record keeps those whose index is a multiple of `stride`, doubling the
 * stride (and keeping every second point) when it is full. A point stepped
 * over again (after a handover, or a location that gave up) replaces the
 * record from its index on. At the end, with P the last step's index
 * before the end, the caller gets the multiples of the smallest power of
 * two S with at most `capacity` multiples in 1..P: a function of the path
 * alone (the SVD follower gives the same, and so do mirror-image branches),
 * not of where the LU steps handed over. The record's room (2 capacity + 4)
 * keeps its stride at most S although steps may have gone a few past P. */
static void record_sample(follow_ctx *c, const kin_assembly *a)
{
    follow_extra *x = (follow_extra *)c->x;
    if (x->capacity <= 0) return;
    size_t nc = (size_t)(a->nj * a->dim);
    while (c->nrec > 0 && x->rec_idx[c->nrec - 1] >= c->p) c->nrec--;
    if (c->p % c->stride) return;
    if (c->nrec == x->rec_room) {
        int k = 0;
        for (int i = 0; i < c->nrec; ++i)
            if (x->rec_idx[i] % (2 * c->stride) == 0) {
                memmove(x->rec + (size_t)k * nc, x->rec + (size_t)i * nc, sizeof(double) * nc);
                x->rec_len[k] = x->rec_len[i];
                x->rec_idx[k++] = x->rec_idx[i];
            }
        c->nrec = k;
        c->stride *= 2;
        if (c->p % c->stride) return;
    }
    memcpy(x->rec + (size_t)c->nrec * nc, a->xyz, sizeof(double) * nc);
    x->rec_len[c->nrec] = c->length;
    x->rec_idx[c->nrec++] = c->p;
}

/* the caller's samples from the record (SAMPLES above); returns their count */
static int deliver_samples(const follow_ctx *c)
{
    const follow_extra *x = c->x;
    if (x->capacity <= 0) return 0;
    int P = c->p - 1, S = 1, n = 0;
    while (P / S > x->capacity) S *= 2;
    size_t nc = (size_t)(c->a->nj * c->a->dim);
    for (int i = 0; i < c->nrec && n < x->capacity; ++i) {
        int q = x->rec_idx[i];
        if (q < 1 || q > P || q % S || !(x->rec_len[i] < c->length)) continue;
        if (x->samples) memcpy(x->samples + (size_t)n * nc, x->rec + (size_t)i * nc, sizeof(double) * nc);
        if (x->sample_length) x->sample_length[n] = x->rec_len[i];
        ++n;
    }
    return n;
}

/* A return to the start (the last chord passes within loop_tol of it): is
 * it a closed loop? Without branch directions: the tangent parallel to the
 * start's. With them (or the caller's o->return_fn): the direction the path
 * comes back along, measured at the point of the path nearest the start (a
 * step back from the chord's end, on a copy), is nearest dir's own branch
 * by branch_margin. -1: return_fn failed (c->hook_rc). */
static int is_loop(follow_ctx *c, const kin_assembly *a, double s)
{
    int nf = a->nf;
    if (!c->at_bif || c->own < 0)
        return fabs(kin__dot(nf, a->t, c->ts)) >= LOOP_TANGENT_COS;
    const double *t = a->t;
    kin_assembly *b = c->probe; /* made at the start of the call */
    double back = (1.0 - s) * distance(nf, c->xp, c->xq);
    if (back > 0.0 && b) {
        kin__copy_state(b, a);
        b->opt = a->opt;
        b->opt.factorization = KIN_STEP_SVD;
        kin_step_info si = {.size = sizeof si};
        if (kin_step(b, -back, &si) == KIN_OK && si.m_internal == 1) t = b->t;
    }
    double ang = 0.0, gap = 0.0;
    int j;
    if (c->o->return_fn) {
        ang = gap = NAN;
        j = c->o->return_fn(c->o->return_user, t, nf, &ang, &gap);
        if (j < 0) {
            c->hook_rc = kin__fail(c->a, KIN_ECANCELLED, "follow: return_fn stopped the follow (returned %d)", j);
            return -1;
        }
        if (!(ang >= 0.0 && ang <= HALF_PI * (1.0 + 1e-12)) || !(gap >= 0.0)) {
            c->hook_rc = kin__fail(c->a, KIN_EINVAL, "follow: return_fn gave angle %g, gap %g", ang, gap);
            return -1;
        }
    } else {
        j = nearest_branch(c, t, &ang, &gap);
    }
    c->info->return_branch = j;
    c->info->return_angle = ang;
    c->info->return_gap = gap;
    return j == c->own && gap >= c->o->branch_margin;
}

/* the vanishing singular value of an SVD point is well separated from the
 * SLOPE_BLOCK-th above it (the slope's subspace iteration with LU factors
 * converges at their ratio squared: fast there), and a little from the next
 * one (RESUME_PAIR_GAP). With one vector this was the next singular value
 * (RESUME_GAP): the flat state's close pairs kept the SVD stepping (5.2 SVD
 * steps per handover); the subspace resumes over them (measured: the same
 * events and located points on the 200-branch benchmark, rb and R^C) */
static int separated(const kin_assembly *a)
{
    const kin_factor *f = kin__cur(a);
    int k = a->nf - 2 - f->an.m_rigid, mn = a->nf < a->nb ? a->nf : a->nb, j = k - SLOPE_BLOCK;
    return f->valid && j >= 0 && k < mn && f->sv[k] <= RESUME_GAP * f->sv[j] && f->sv[k] <= RESUME_PAIR_GAP * f->sv[k - 1];
}

/* after every accepted step: count the chord, keep a sample, stop on a
 * return to the start or at the length budget */
static int after_step(void *user, const kin_assembly *a)
{
    follow_ctx *c = user;
    int nf = a->nf;
    kin__gather(a, a->xyz, c->xq);
    c->len_pp = c->length;
    memcpy(c->xpp, c->xp, sizeof(double) * (size_t)nf);
    c->length += distance(nf, c->xp, c->xq);
    c->p++;
    record_sample(c, a);
    double tol = c->o->loop_tol * c->scale, s = 0.0;
    int stop = 0, was_away = c->left; /* away from the start before this chord */
    if (distance(nf, c->xq, c->xs) > 2.0 * tol) c->left = 1;
    int loop = was_away && segment_distance(nf, c->xp, c->xq, c->xs, &s) <= tol ? is_loop(c, a, s) : 0;
    if (loop) {
        c->reason = loop < 0 ? KIN_FOLLOW_FAILED : KIN_FOLLOW_CLOSED_LOOP;
        stop = 1;
    } else if (c->o->max_length > 0.0 && c->length >= c->o->max_length) {
        c->reason = KIN_FOLLOW_LENGTH_LIMIT;
        stop = 1;
    } else if (kin__contact_event_check(c->a, c->xp)) {
        c->reason = KIN_FOLLOW_CONTACT;
        stop = 1;
    }
    memcpy(c->xp, c->xq, sizeof(double) * (size_t)nf);
    if (stop) return KIN__HOOK_STOP;
    if (c->watch) {
        /* the SVD locator after a handover: back to LU steps once it has
         * stepped over the suspect stretch, unless v_r is small and falling */
        double r = kin__lu_rel_estimate(a);
        c->rho_prev = c->rho_cur;
        c->rho_cur = r;
        if (++c->svd_steps >= c->resume_after && c->length > c->resume_len && r > 0.0 &&
            (r >= CHEAP_NEAR_FACTOR * c->o->switch_eps || separated(a))) {
            c->reason = REASON_RESUME;
#ifdef KIN_FOLLOW_TRACE
            fprintf(stderr, "resume after %d svd steps r %.3g\n", c->svd_steps, r);
#endif
            return KIN__HOOK_STOP_IDLE;
        }
    }
    return KIN__HOOK_GO;
}

/* After the locator returns: the assembly is at the last step's point, the
 * located point within the last step, or (location gave up) the point
 * before the last step. The length is the one at the point before the last
 * step plus the distance from there; that point starts the next attempt. */
static void resync(follow_ctx *c)
{
    int nf = c->a->nf;
    kin__gather(c->a, c->a->xyz, c->xq);
    double back = distance(nf, c->xpp, c->xq);
    if (back == 0.0 && c->p > 0) c->p--; /* at the point before the last step */
    c->length = c->len_pp + back;
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

/* ---- cheap stretches (KIN_FOLLOW_STEPS_CHEAP) ---- */

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
static void back_to_kept(follow_ctx *c, int newer)
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

static int cheap_stretch(follow_ctx *c, kin_follow_info *info, double r_before, int *stop)
{
    kin_assembly *a = c->a;
    const kin_follow_options *o = c->o;
    int nf = a->nf, sg0 = 0, rc;
    *stop = 0;
    kin_options user = a->opt;
    if ((rc = kin__border_det_sign(a, &sg0)) != KIN_OK) return rc;
    a->opt.factorization = KIN_STEP_LU;
    a->opt.rank_tol = fmin(user.rank_tol, CHEAP_RANK_FRACTION * o->vr_tol);
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
            c->watch = 1; /* the SVD locator takes over (state unchanged) */
            c->svd_steps = 0;
            c->resume_after = RESUME_AFTER_FAILED;
            c->resume_len = c->length;
            c->rho_prev = c->rho_cur = -INFINITY;
            info->handovers++;
            break;
        }
        info->steps++;
        info->cheap_steps++;
        if (after_step(c, a)) {
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
            if (!c->direct) back_to_kept(c, !turned);
            c->watch = 1;
            c->svd_steps = 0;
            c->rho_prev = c->rho_cur = -INFINITY;
            info->handovers++;
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
    a->opt = user;
    a->lu_inverse = 0;
    a->plain_extensions = 0;
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

static void first_step_lu(follow_ctx *c, const kin_options *user)
{
    kin_assembly *a = c->a;
    a->opt = *user;
    a->opt.factorization = KIN_STEP_LU;
    a->opt.rank_tol = user->rank_tol * FIRST_LU_MARGIN * 1e-3;
    a->lu_inverse = 1;
}

/* after the first step (the handle's own options back): the mechanism count
 * the SVD step would have given, into si->m_internal */
static int first_point_verdict(follow_ctx *c, kin_step_info *si)
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

static int options_ok(const kin_follow_options *o)
{
    return o->vr_tol > 0.0 && o->vr_tol < 1.0 && o->vr_floor >= o->vr_tol && o->vr_floor < 1.0 &&
           o->switch_eps > 0.0 && o->switch_eps < 1.0 && isfinite(o->delta) && o->max_steps >= 1 &&
           o->max_iter >= 1 && o->max_length >= 0.0 && isfinite(o->max_length) && o->loop_tol > 0.0 &&
           isfinite(o->loop_tol) && o->first_step > 0.0 && o->first_step <= 1.0 && o->branch_cos >= 0.0 &&
           o->branch_cos <= 1.0 && (o->steps_mode == KIN_FOLLOW_STEPS_CHEAP || o->steps_mode == KIN_FOLLOW_STEPS_SVD) &&
           o->branch_margin >= 0.0 && o->branch_margin <= HALF_PI && (!o->return_fn || o->return_own >= 0);
}

/* number of location attempts: vr_tol, then relaxed tenfold up to vr_floor */
static int max_attempts(const kin_follow_options *o)
{
    int n = 1;
    for (double t = o->vr_tol; t * RELAX_FACTOR <= o->vr_floor * (1.0 + 1e-9) && n < 64; t *= RELAX_FACTOR) ++n;
    return n;
}

static int follow_impl(kin_assembly *a, const double *dir, const kin_follow_options *o, const follow_extra *x,
                       kin_follow_info *info)
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

    follow_ctx c = {0};
    c.a = a;
    c.o = o;
    c.x = x;
    c.info = info;
    c.scale = a->rms_length;
    c.at_bif = at_bif;
    c.own = -1;
    c.stride = 1;
    c.user_fn = a->progress;
    c.user_data = a->progress_user;
    info->return_branch = -1;
#ifdef KIN_FOLLOW_TRACE
    fprintf(stderr, "follow start\n");
#endif
    size_t nc = (size_t)(a->nj * a->dim);
    c.xs = malloc(sizeof(double) * (6 * (size_t)nf + 2 * (nc + (size_t)nf) + (size_t)nf + (size_t)a->nb + 2 * nc +
                                    2 * (size_t)SLOPE_BLOCK * nf + 2 * (size_t)nf));
    if (!c.xs) return kin__fail(a, KIN_ENOMEM, "follow workspace");
    c.ts = c.xs + nf;
    c.xp = c.ts + nf;
    c.xq = c.xp + nf;
    c.xpp = c.xq + nf;
    c.tprev = c.xpp + nf;
    for (int k = 0; k < 2; ++k) {
        c.kept[k].p.xyz = c.tprev + nf + (size_t)k * (nc + (size_t)nf);
        c.kept[k].p.t = c.kept[k].p.xyz + nc;
    }
    c.u = c.kept[1].p.t + nf;
    c.w = c.u + nf;
    c.scr = c.w + a->nb;
    c.blk = c.scr + 2 * nc;
    c.kept[0].border = c.blk + 2 * (size_t)SLOPE_BLOCK * nf;
    c.kept[1].border = c.kept[0].border + nf;
    if (at_bif && (x->nbranch > 0 || o->return_fn)) {
        double ang = 0.0, gap = 0.0;
        c.own = o->return_fn ? o->return_own : nearest_branch(&c, dir, &ang, &gap);
        if (kin_assembly_clone(a, &c.probe)) {
            free(c.xs);
            return kin__fail(a, KIN_ENOMEM, "follow: a copy for the return direction");
        }
    }
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
        kin_options user_opt = a->opt;
        for (double fr = o->first_step;; fr *= RELAX_FACTOR) {
            if (o->steps_mode == KIN_FOLLOW_STEPS_CHEAP) first_step_lu(&c, &user_opt);
            rc = kin__leave_bifurcation(a, dir, fr, &si, &cs);
            a->opt = user_opt;
            a->lu_inverse = 0;
            if (rc == KIN_OK && o->steps_mode == KIN_FOLLOW_STEPS_CHEAP && (rc = first_point_verdict(&c, &si)) != KIN_OK)
                break;
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

    /* regular stretches by LU steps, until something may happen */
    if (o->steps_mode == KIN_FOLLOW_STEPS_CHEAP) {
        int stop = 0;
        rc = cheap_stretch(&c, info, -INFINITY, &stop);
        if (rc) {
            info->event = KIN_FOLLOW_FAILED;
            goto out;
        }
        if (stop) {
            (void)kin__progress(a, c.total, c.total);
            goto out;
        }
    }

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
    /* the locator's working copies, made once for all the attempts and
     * handovers of this call (1.1 handovers and 1.0 attempts per branch on
     * the flat state: 5 clones at each was 4% of the time) */
    kin__locate_ws lws = {0};
    /* cheap steps: the Hermite nodes from LU steps too (locate.h) */
    lws.lu_nodes = o->steps_mode == KIN_FOLLOW_STEPS_CHEAP;
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
        lws.nonzero_min = 0.0;
        rc = KIN__LOCATE_DIRECT_FAILED;
        if (c.direct) {
            /* the bracket the LU steps stepped over (cheap_stretch) */
            c.direct = 0;
            lws.direct_prev = &c.kept[1].p;
            lws.direct_border = c.kept[1].border;
            rc = kin__locate_hooked(a, &lo, &li, after_step, &c, &lws);
            if (rc == KIN__LOCATE_DIRECT_FAILED) {
                back_to_kept(&c, c.direct_newer);
                li = (kin_locate_info){.size = sizeof li};
                lws.nonzero_min = 0.0;
            }
        }
        if (rc == KIN__LOCATE_DIRECT_FAILED) rc = kin__locate_hooked(a, &lo, &li, after_step, &c, &lws);
        int resume = c.reason == REASON_RESUME;
        if (resume) c.reason = 0;
        resync(&c);
        if (rc == KIN_ENOTFOUND && resume && li.event == KIN_EVENT_NONE) {
            /* the SVD locator stepped over the suspect stretch: LU steps again */
            info->steps += li.steps;
            c.done_base += li.steps;
            int stop = 0;
            a->progress = c.user_fn;
            a->progress_user = c.user_data;
            rc = cheap_stretch(&c, info, c.rho_prev, &stop);
            if (c.user_fn) {
                a->progress = progress_adapter;
                a->progress_user = &c;
            }
            c.done_base = info->steps;
            if (rc) break;
            if (stop) {
                rc = KIN_OK;
                break;
            }
            --k; /* not an attempt */
            continue;
        }
        info->attempts++;
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
        /* ... but not where the fast method found a non-zero minimum of v_r
         * above sqrt(vr_floor): each relaxed attempt steps over the same
         * bracket again and gives up on the same minimum (it calls a
         * minimum non-zero above sqrt of its own tolerance, and would have
         * to find a point a thousand times lower than any it saw to
         * succeed). The flat state's near misses (v_r / v_max 2e-4 ...
         * 1e-2) took all 5 attempts, each an SVD step, a start analysis
         * and a Hermite location: 4 of them for nothing */
        if (lws.nonzero_min > sqrt(o->vr_floor)) break;
        tol *= RELAX_FACTOR;
        if (tol > o->vr_floor * (1.0 + 1e-9)) break;
    }
    /* a near miss ends at the minimum of v_r / v_max along the path, found
     * within the bracket the last location attempt gave up on */
    if (rc == KIN_OK && info->event == KIN_FOLLOW_NEAR_MISS && lws.near_bracket) {
        kin__near_min nm;
        rc = kin__locate_near_minimum(a, &lws, &nm);
        info->min_located = nm.located;
        info->min_width = nm.located ? nm.width : 0.0;
        info->min_evals = nm.evals;
        if (rc) info->event = KIN_FOLLOW_FAILED;
    }
    kin__locate_ws_free(&lws);
    a->progress = c.user_fn;
    a->progress_user = c.user_data;
    if (info->event == KIN_FOLLOW_NEAR_MISS && kin__cur(a)->valid)
        info->v_r_rel = kin__cur(a)->an.v_r / kin__cur(a)->an.v_max;
    if (rc == KIN_OK) (void)kin__progress(a, c.total, c.total);
out:
    /* a contact, whether an LU step or an SVD step met it: located here,
     * once, with the handle's own options */
    if (rc == KIN_OK && info->event == KIN_FOLLOW_CONTACT && (rc = kin__contact_event_locate(a)) != KIN_OK)
        info->event = KIN_FOLLOW_FAILED;
    if (c.hook_rc) { /* return_fn failed: the follow stopped there */
        rc = c.hook_rc;
        info->event = KIN_FOLLOW_FAILED;
    }
    info->status = rc;
    /* a contact located within the last step: the length to it */
    info->length = c.length - (rc == KIN_OK && info->event == KIN_FOLLOW_CONTACT ? kin__contact_event_back(a) : 0.0);
    {
        double *xe = c.xq;
        kin__gather(a, a->xyz, xe);
        info->start_distance = distance(nf, xe, c.xs) / c.scale;
        info->at_start = info->event == KIN_FOLLOW_CLOSED_LOOP ||
                         (info->event == KIN_FOLLOW_BIFURCATION && at_bif && info->start_distance <= o->loop_tol);
    }
    info->samples = deliver_samples(&c);
    if (!kin__cur(a)->valid && info->event != KIN_FOLLOW_NONE) (void)kin__analyse(a, NULL); /* after LU steps */
    if (kin__cur(a)->valid && info->event != KIN_FOLLOW_BIFURCATION && info->event != KIN_FOLLOW_NEAR_MISS) {
        info->m_internal = kin__cur(a)->an.m_internal;
        info->s = kin__cur(a)->an.s;
        info->v_r_rel = kin__cur(a)->an.v_max > 0 ? kin__cur(a)->an.v_r / kin__cur(a)->an.v_max : 0.0;
    }
    free(c.xs);
    kin_assembly_free(c.probe);
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
