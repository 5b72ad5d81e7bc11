/* Contact as an event of kin_follow_event (kin_contact.h,
 * kin_set_contact_events; docs/contact.md). follow.c calls three functions:
 * arm at the start, check after every accepted step, locate when a check
 * stopped the follow. The location bisects the last step's chord in free
 * coordinates; each trial point is brought back onto the path by kin_relax
 * (a trial whose relaxation fails counts as not located further: the bracket
 * stays where it is) and tested by kin_clearance with a cutoff just above
 * zero. No allocation: the workspace is the contact record's (made by
 * kin_set_contact_events).
 *
 * Two bars in 3D that pass through each other touch only at an instant: a
 * check of the clearance at the steps alone misses it whenever no step lands
 * on it. So the check also asks, for every two bars that share no joint and
 * whose boxes over the step overlap (a sort-and-sweep on x), whether the
 * orientation of their four ends (the signed volume of the tetrahedron) changed
 * sign within the step while, on the chord between the two points, the two
 * bars met where they were coplanar; such a pair is located by bisection on
 * that sign along the path, then as any contact. (A panel that passes
 * through a bar or a panel overlaps it over a stretch, which the clearance
 * catches unless the stretch is shorter than a step.)
 *
 * Hinges (two panels on one fold line) are watched apart, by their fold
 * sides (hinge_event.c): armed whenever the model has them, even where the
 * start touches elsewhere, since a hinge closed at a start is no contact
 * until it opens; the clearance checked here leaves them out. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "branches/contact_event.h"
#include "branches/hinge_event.h"
#include "contact/contact_internal.h"

/* Contact at the handle's configuration: clearance <= 64 eps x the RMS rest
 * length (two segments that cross in a plane, or a bar through a panel, are
 * at distance zero only up to rounding); the cutoff resolves nothing else */
static int in_contact(kin_assembly *a, double *clearance, int *parts, double *points)
{
    double c = INFINITY, eps = 64.0 * DBL_EPSILON * a->rms_length;
    int hinges = a->ct->hinge_on;
    a->ct->hinge_on = 0; /* hinges: hinge_event.c */
    int rc = kin_clearance(a, NULL, nextafter(eps, INFINITY), &c, parts, points);
    a->ct->hinge_on = hinges;
    if (rc != KIN_OK) return 0;
    if (clearance) *clearance = c;
    return c <= eps;
}

/* 6 x the signed volume of tetrahedron (p0, p1, q0, q1): zero where the
 * two segments are coplanar, its sign says on which side of p's line q passes */
static double orient(const double *p0, const double *p1, const double *q0, const double *q1)
{
    double u[3], v[3], w[3];
    for (int i = 0; i < 3; ++i) u[i] = p1[i] - p0[i], v[i] = q0[i] - p0[i], w[i] = q1[i] - p0[i];
    return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/* the orientation of bars k and l at configuration xyz (3D) */
static double bar_orient(const kin_assembly *a, const double *xyz, int k, int l)
{
    const int *b = a->bars;
    return orient(xyz + 3 * b[2 * k], xyz + 3 * b[2 * k + 1], xyz + 3 * b[2 * l], xyz + 3 * b[2 * l + 1]);
}

/* a sign that rounding cannot have made: |d| above 64 eps x the scale^3 */
static int side(double d, double scale3)
{
    double floor = 64.0 * DBL_EPSILON * scale3;
    return d > floor ? 1 : d < -floor ? -1 : 0;
}

/* the ends of bars k and l at t of the chord from P to Q (12 numbers) */
static void ends_at(const kin_assembly *a, const double *P, const double *Q, double t, int k, int l, double *e)
{
    const int j[4] = {a->bars[2 * k], a->bars[2 * k + 1], a->bars[2 * l], a->bars[2 * l + 1]};
    for (int q = 0; q < 4; ++q)
        for (int i = 0; i < 3; ++i) e[3 * q + i] = P[3 * j[q] + i] + t * (Q[3 * j[q] + i] - P[3 * j[q] + i]);
}

/* Did bars k and l pass through each other on the chord from P to Q (their
 * orientation changes sign from s0 and, where it is zero, they meet)? */
static int met_on_chord(const kin_assembly *a, const double *P, const double *Q, int k, int l, int s0)
{
    double lo = 0.0, hi = 1.0, e[12], cp[3], cq[3];
    for (int it = 0; it < 60; ++it) {
        double mid = 0.5 * (lo + hi);
        ends_at(a, P, Q, mid, k, l, e);
        if ((orient(e, e + 3, e + 6, e + 9) > 0) == (s0 > 0)) lo = mid;
        else hi = mid;
    }
    ends_at(a, P, Q, 0.5 * (lo + hi), k, l, e);
    /* coplanar there: they meet if their distance is nil (to 1e-9 of the
     * model's size: the chord stands in for the path, located later) */
    return kin__dist_seg_seg(e, e + 3, e + 6, e + 9, cp, cq) <= 1e-9 * a->rms_length;
}

static int cmp_key(const void *p, const void *q)
{
    double x = ((const kin__sweepkey *)p)->x, y = ((const kin__sweepkey *)q)->x;
    return (x > y) - (x < y);
}

/* Two bars that passed through each other between P (the point before the
 * step) and Q (after it): 1 with ct->ev_pair, ev_side set, else 0. 3D only
 * (in a plane, crossing bars overlap over a stretch: the clearance sees it). */
static int crossed(kin_assembly *a, const double *P, const double *Q)
{
    struct kin_contact *ct = a->ct;
    int nb = a->nb;
    if (a->dim != 3 || nb < 2) return 0;
    double scale3 = a->rms_length * a->rms_length * a->rms_length;
    for (int k = 0; k < nb; ++k) {
        double *bx = ct->ev_box + 6 * k;
        const int j0 = a->bars[2 * k], j1 = a->bars[2 * k + 1];
        for (int i = 0; i < 3; ++i) {
            double v[4] = {P[3 * j0 + i], P[3 * j1 + i], Q[3 * j0 + i], Q[3 * j1 + i]};
            double lo = v[0], hi = v[0];
            for (int q = 1; q < 4; ++q) lo = v[q] < lo ? v[q] : lo, hi = v[q] > hi ? v[q] : hi;
            bx[i] = lo, bx[3 + i] = hi;
        }
        ct->ev_key[k].x = bx[0];
        ct->ev_key[k].k = k;
    }
    qsort(ct->ev_key, (size_t)nb, sizeof *ct->ev_key, cmp_key);
    for (int u = 0; u < nb; ++u) {
        int k = ct->ev_key[u].k;
        const double *bk = ct->ev_box + 6 * k;
        const int *jk = a->bars + 2 * k;
        if (ct->dev && ct->dev[k]) continue; /* a device bar */
        for (int w = u + 1; w < nb && ct->ev_key[w].x <= bk[3]; ++w) {
            int l = ct->ev_key[w].k;
            const double *bl = ct->ev_box + 6 * l;
            const int *jl = a->bars + 2 * l;
            if (ct->dev && ct->dev[l]) continue;
            if (bl[1] > bk[4] || bk[1] > bl[4] || bl[2] > bk[5] || bk[2] > bl[5]) continue;
            if (jk[0] == jl[0] || jk[0] == jl[1] || jk[1] == jl[0] || jk[1] == jl[1]) continue;
            int s0 = side(bar_orient(a, P, k, l), scale3), s1 = side(bar_orient(a, Q, k, l), scale3);
            if (s0 == 0 || s1 == 0 || s0 == s1 || !met_on_chord(a, P, Q, k, l, s0)) continue;
            ct->ev_pair[0] = k, ct->ev_pair[1] = l;
            ct->ev_side = s0;
            return 1;
        }
    }
    return 0;
}

void kin__contact_event_arm(kin_assembly *a)
{
    struct kin_contact *ct = a->ct;
    if (!ct) return;
    ct->ev_have = 0;
    ct->ev_back = 0.0;
    ct->ev_armed = ct->ev_on && !in_contact(a, NULL, NULL, NULL);
    kin__hinge_event_arm(a);
}

int kin__contact_event_check(kin_assembly *a, const double *xprev)
{
    struct kin_contact *ct = a->ct;
    if (!ct || (!ct->ev_armed && !ct->hg_armed)) return 0;
    ct->ev_pair[0] = ct->ev_pair[1] = -1;
    int hit = ct->ev_armed && in_contact(a, NULL, NULL, NULL);
    if (!hit && ct->ev_armed) {
        /* the point before the step, in full coordinates (the trial buffer) */
        int n = a->nj * a->dim;
        double *P = ct->ev_xyz + n;
        memcpy(P, a->xyz, sizeof(double) * (size_t)n);
        kin__scatter(a, xprev, P);
        hit = crossed(a, P, a->xyz);
    }
    /* the hinges too (the location finds whichever came first); their
     * sides move on only with a step free of contact */
    if (kin__hinge_event_check(a)) hit = 1;
    if (!hit) {
        kin__hinge_event_advance(a);
        return 0;
    }
    memcpy(ct->ev_prev, xprev, sizeof(double) * (size_t)a->nf);
    return 1;
}

/* a bar's radius: its own, or half the model-wide thickness */
static double bar_radius(const struct kin_contact *ct, int k)
{
    return ct->rbar && ct->rbar[k] >= 0.0 ? ct->rbar[k] : 0.5 * ct->t0;
}

/* the location's test at the handle's point: in contact, or (a pair of bars
 * that crossed within the step) past their crossing */
static int reached(kin_assembly *a)
{
    struct kin_contact *ct = a->ct;
    if (kin__hinge_event_reached(a)) return 1;
    if (!ct->ev_armed) return 0;
    if (ct->ev_pair[0] >= 0) {
        double s3 = a->rms_length * a->rms_length * a->rms_length;
        if (side(bar_orient(a, a->xyz, ct->ev_pair[0], ct->ev_pair[1]), s3) != (int)ct->ev_side) return 1;
    }
    return in_contact(a, NULL, NULL, NULL);
}

int kin__contact_event_locate(kin_assembly *a)
{
    struct kin_contact *ct = a->ct;
    int nf = a->nf, n = a->nj * a->dim;
    double *x0 = ct->ev_prev, *x = ct->ev_x, *x1 = ct->ev_x + nf, *hi_xyz = ct->ev_xyz, *trial = ct->ev_xyz + n;
    memcpy(hi_xyz, a->xyz, sizeof(double) * (size_t)n);
    /* the chord: x0 (free of contact) to the current point (in contact, or
     * past the crossing of the pair ev_pair) */
    kin__gather(a, a->xyz, x1);
    double h = 0.0;
    for (int i = 0; i < nf; ++i) h += (x1[i] - x0[i]) * (x1[i] - x0[i]);
    h = sqrt(h);
    double lo = 0.0, hi = 1.0, goal = ct->ev_tol * a->rms_length;
    int rc = KIN_OK;
    for (int it = 0; it < 200 && (hi - lo) * h > goal; ++it) {
        double mid = 0.5 * (lo + hi);
        for (int i = 0; i < nf; ++i) x[i] = x0[i] + mid * (x1[i] - x0[i]);
        memcpy(trial, hi_xyz, sizeof(double) * (size_t)n);
        kin__scatter(a, x, trial);
        if (kin_set_coords(a, trial) != KIN_OK || kin_relax(a, 30, NULL) != KIN_OK) break;
        if (reached(a)) {
            hi = mid;
            memcpy(hi_xyz, a->xyz, sizeof(double) * (size_t)n);
        } else {
            lo = mid;
        }
    }
    /* the assembly at the first point in contact found */
    if ((rc = kin_set_coords(a, hi_xyz)) != KIN_OK) return rc;
    ct->ev_bracket = (hi - lo) * h;
    ct->ev_back = (1.0 - hi) * h;
    ct->ev_have = 0;
    if (kin__hinge_event_reached(a)) {
        /* a hinge closed or through: its two panels, its signed clearance */
        int h = ct->ev_hinge;
        const int *g = ct->hg + 6 * h;
        double delta;
        int sigma;
        kin__hinge_measure(a->xyz, g, &delta, &sigma, ct->ev_points);
        ct->ev_clearance = kin__hinge_signed_clearance(a, a->xyz, h, ct->hg_side[h]);
        ct->ev_parts[0] = KIN_PART_PANEL, ct->ev_parts[1] = g[4];
        ct->ev_parts[2] = KIN_PART_PANEL, ct->ev_parts[3] = g[5];
        ct->ev_have = 1;
    }
    if (!ct->ev_have && ct->ev_armed)
        ct->ev_have = in_contact(a, &ct->ev_clearance, ct->ev_parts, ct->ev_points);
    if (!ct->ev_have && ct->ev_pair[0] >= 0) {
        /* bare bars that crossed: the first point found past the crossing,
         * their distance there at most the bracket's movement */
        int k = ct->ev_pair[0], l = ct->ev_pair[1];
        const int *b = a->bars;
        double cp[3], cq[3];
        double d = kin__dist_seg_seg(a->xyz + 3 * b[2 * k], a->xyz + 3 * b[2 * k + 1], a->xyz + 3 * b[2 * l],
                                     a->xyz + 3 * b[2 * l + 1], cp, cq);
        ct->ev_clearance = d - bar_radius(ct, k) - bar_radius(ct, l);
        ct->ev_parts[0] = KIN_PART_BAR, ct->ev_parts[1] = k, ct->ev_parts[2] = KIN_PART_BAR, ct->ev_parts[3] = l;
        memcpy(ct->ev_points, cp, sizeof cp);
        memcpy(ct->ev_points + 3, cq, sizeof cq);
        ct->ev_have = 1;
    }
    ct->ev_armed = 0;
    return KIN_OK;
}

void kin__contact_event_finish(kin_assembly *a)
{
    if (a->ct) kin__hinge_event_finish(a);
}

double kin__contact_event_back(const kin_assembly *a)
{
    return a->ct ? a->ct->ev_back : 0.0;
}
