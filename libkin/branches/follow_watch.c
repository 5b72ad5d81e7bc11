/* What the follower (kin_follow_event, follow.c) checks after every
 * accepted step, in the cheap stretches (follow_cheap.c) and in the SVD
 * locator alike, which calls kin__follow_after_step as its hook: the path
 * length by chords, the samples the caller asked for, a return to the
 * start and whether it is a closed loop (with the start's branch
 * directions if given: is_loop, with return_branch.c), the length budget,
 * a contact, and after a handover whether LU steps may resume; and, after the locator returns,
 * the length and points from where it left the handle (kin__follow_resync).
 * A new kind of event belongs in kin__follow_after_step (a stop with its
 * own reason) and in follow.c's classification of how the path ended. */
#include <math.h>
#ifdef KIN_FOLLOW_TRACE
#include <stdio.h>
#endif
#include <string.h>

#include "branches/contact_event.h"
#include "branches/follow_internal.h"
#include "locate/locate.h"

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

double kin__follow_distance(int n, const double *x, const double *y)
{
    double r = 0.0;
    for (int i = 0; i < n; ++i) r += (x[i] - y[i]) * (x[i] - y[i]);
    return sqrt(r);
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
int kin__follow_deliver_samples(const follow_ctx *c)
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
 * start's. With them (or the caller's o->return_fn): the branch it comes
 * back along (kin__return_branch: Newton on the start's second-order
 * equations from the direction it arrives along) is dir's own. The arrival
 * direction is measured on the arriving side, never by a step through the
 * start (which can land on a neighbouring branch): the secants to the start
 * from the point before the chord and from an earlier one, extrapolated to
 * the start; undecided (never a loop) without them.
 * -1: return_fn failed (c->hook_rc). */
static int is_loop(follow_ctx *c, const kin_assembly *a)
{
    int nf = a->nf;
    if (!c->at_bif || c->own < 0)
        return fabs(kin__dot(nf, a->t, c->ts)) >= LOOP_TANGENT_COS;
    /* the secants from the newest point outside the loop_tol ball (xp, or
     * an earlier one where the locator left xp inside it; at d1) and from
     * the newest point before it at d2 >= ARRIVAL_SPREAD d1, u(d) = b -
     * kappa d / 2 + O(d^2) along a branch b, extrapolated linearly to d = 0;
     * without two such points the return is undecided */
    const double *near = NULL, *far = NULL;
    double d1 = 0.0, d2 = 0.0;
    for (int k = 0; k <= c->nhist && !far; ++k) {
        const double *h = k == 0 ? c->xp : c->hist + (size_t)((c->hist_pos - k + ARRIVAL_KEEP) % ARRIVAL_KEEP) * nf;
        double d = kin__follow_distance(nf, h, c->xs);
        if (!near && d > c->o->loop_tol * c->scale) {
            near = h;
            d1 = d;
        } else if (near && d >= ARRIVAL_SPREAD * d1) {
            far = h;
            d2 = d;
        }
    }
    if (!far) {
        c->info->return_branch = KIN_FOLLOW_RETURN_UNDECIDED;
        c->info->return_angle = c->info->return_gap = NAN;
        return 0;
    }
    for (int i = 0; i < nf; ++i) {
        double u1 = (c->xs[i] - near[i]) / d1, u2 = (c->xs[i] - far[i]) / d2;
        c->tarr[i] = (d2 * u1 - d1 * u2) / (d2 - d1);
    }
    const double *t = c->tarr;
    double ang = 0.0, gap = 0.0;
    int j = kin__return_branch(c, t, &ang, &gap);
    if (j == -1) return -1;
    c->info->return_branch = j;
    c->info->return_angle = ang;
    c->info->return_gap = gap;
    return j == c->own;
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
int kin__follow_after_step(void *user, const kin_assembly *a)
{
    follow_ctx *c = user;
    int nf = a->nf;
    kin__gather(a, a->xyz, c->xq);
    c->len_pp = c->length;
    memcpy(c->xpp, c->xp, sizeof(double) * (size_t)nf);
    c->length += kin__follow_distance(nf, c->xp, c->xq);
    c->p++;
    record_sample(c, a);
    double tol = c->o->loop_tol * c->scale;
    int stop = 0, was_away = c->left; /* away from the start before this chord */
    if (kin__follow_distance(nf, c->xq, c->xs) > 2.0 * tol) c->left = 1;
    int back = was_away && segment_distance(nf, c->xp, c->xq, c->xs, NULL) <= tol;
    int loop = back ? is_loop(c, a) : 0;
    /* with branch directions a return is decided once, as the path arrives:
     * the next is counted only after the path has been 2 loop_tol away again
     * (the chords after it, within loop_tol, have no arrival to measure) */
    if (back && !loop && c->at_bif && c->own >= 0) c->left = kin__follow_distance(nf, c->xq, c->xs) > 2.0 * tol;
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
    memcpy(c->hist + (size_t)c->hist_pos * nf, c->xp, sizeof(double) * (size_t)nf);
    c->hist_pos = (c->hist_pos + 1) % ARRIVAL_KEEP;
    if (c->nhist < ARRIVAL_KEEP) c->nhist++;
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
void kin__follow_resync(follow_ctx *c)
{
    int nf = c->a->nf;
    kin__gather(c->a, c->a->xyz, c->xq);
    double back = kin__follow_distance(nf, c->xpp, c->xq);
    if (back == 0.0 && c->p > 0) c->p--; /* at the point before the last step */
    c->length = c->len_pp + back;
    c->len_pp = c->length;
    memcpy(c->xp, c->xq, sizeof(double) * (size_t)nf);
    memcpy(c->xpp, c->xq, sizeof(double) * (size_t)nf);
    /* the locator may have moved back towards the start: the next chord
     * counts for a return only if this point is away from it */
    c->left = kin__follow_distance(nf, c->xq, c->xs) > 2.0 * c->o->loop_tol * c->scale;
}
