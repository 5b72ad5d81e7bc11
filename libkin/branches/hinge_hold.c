/* Held hinges (kin_follow_options.hold_hinges, kin_follow.h HELD HINGES,
 * docs/contact.md "Held hinges"): a hinge that closes during a follow is
 * held closed, the membrane cannot pass through it, and it reopens only
 * where the motion opens it.
 *
 * The hold is a unilateral constraint on the angle delta_h >= 0 between
 * the hinge's panels. In libkin's model the constraint that holds it is
 * the bar between its far corners at their closed distance: its zero set
 * near closure is exactly delta_h = 0. But that bar, like any bar among the
 * four joints of two panels folded flat (making the two panels one rigid
 * body adds only such bars), lies in their common plane: its length is
 * stationary in delta_h (|x_a - x_b|^2 = c + 2 h_a h_b (1 - cos delta_h)),
 * so it adds a self-stress, not a first-order constraint, and acts only at
 * second order (docs/sail_study.md: the locked R^B, m = 4, s = 9). So the
 * follower linearises the hold by the gradient of the hinge's signed volume
 * V = e . (u_a x u_b), which is not stationary there: along a motion v the
 * angle opens at the rate side * dV/dv / (|e| h_a h_b). A held path (every
 * held hinge's rate zero) is a path of the structure itself along which the
 * hinge stays closed: the follower follows it as any path and checks at
 * every step that the held hinges stay closed (hinge_event.c).
 *
 * Reopening follows the rate form of the unilateral contact conditions
 * (Signorini; Moreau's viability lemma): where the constraint is active,
 * the contact force lambda >= 0 and the rate of the gap g' >= 0 are
 * complementary (lambda g' = 0). A motion along which a held hinge's angle
 * opens (g' > 0) is admissible with lambda = 0: the hold is released; one
 * along which it would close further (g' < 0, into penetration) is not:
 * the contact would have to push, and the held structure must move
 * otherwise or not at all (rigid); g' = 0 keeps it held. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "branches/hinge_hold.h"
#include "contact/contact_internal.h"

/* a hinge is closed where its gap is at most this x the RMS rest length
 * (hinge_event.c's closed-at-start threshold) */
static const double HOLD_CLOSED = 1e-6;
/* the held analysis counts singular values up to this x v_max as zero: a
 * closure is located as a contact to 1e-9 of the RMS length, where a
 * bifurcation it coincides with shows v_r / v_max of 1e-5 (the vertex of
 * tests/test_hinge_hold.c); genuine regular points have far more */
static const double HOLD_NEAR = 1e-3;

/* the velocity of every joint (3 nj) for the free-coordinate motion t */
static void velocity(const kin_assembly *a, const double *t, double *v)
{
    memset(v, 0, sizeof(double) * 3 * (size_t)a->nj);
    for (int i = 0; i < a->nf; ++i) v[a->free_coord[i]] = t[i];
}

double kin__hold_rate(const kin_assembly *a, int h, int side, const double *v)
{
    const int *g = a->ct->hg + 6 * h;
    const double *x = a->xyz;
    double e[3], ua[3], ub[3], de[3], da[3], db[3];
    for (int k = 0; k < 3; ++k) {
        e[k] = x[3 * g[1] + k] - x[3 * g[0] + k], de[k] = v[3 * g[1] + k] - v[3 * g[0] + k];
        ua[k] = x[3 * g[2] + k] - x[3 * g[0] + k], da[k] = v[3 * g[2] + k] - v[3 * g[0] + k];
        ub[k] = x[3 * g[3] + k] - x[3 * g[0] + k], db[k] = v[3 * g[3] + k] - v[3 * g[0] + k];
    }
#define CROSSDOT(p, q, r) \
    ((p)[0] * ((q)[1] * (r)[2] - (q)[2] * (r)[1]) - (p)[1] * ((q)[0] * (r)[2] - (q)[2] * (r)[0]) + \
     (p)[2] * ((q)[0] * (r)[1] - (q)[1] * (r)[0]))
    double dv = CROSSDOT(de, ua, ub) + CROSSDOT(e, da, ub) + CROSSDOT(e, ua, db);
#undef CROSSDOT
    double ee = e[0] * e[0] + e[1] * e[1] + e[2] * e[2], pa = 0.0, pb = 0.0, ha = 0.0, hb = 0.0;
    for (int k = 0; k < 3; ++k) pa += ua[k] * e[k], pb += ub[k] * e[k];
    for (int k = 0; k < 3; ++k) {
        double qa = ua[k] - pa / ee * e[k], qb = ub[k] - pb / ee * e[k];
        ha += qa * qa, hb += qb * qb;
    }
    double den = sqrt(ee) * sqrt(ha) * sqrt(hb);
    return den > 0.0 ? side * dv / den : 0.0;
}

/* the gap of hinge h at the handle's point, relative to the closed threshold */
static int closed_here(const kin_assembly *a, int h)
{
    double delta;
    int sigma;
    double gap = kin__hinge_measure(a->xyz, a->ct->hg + 6 * h, &delta, &sigma, NULL);
    return gap <= HOLD_CLOSED * a->rms_length;
}

/* An orthonormal basis of the near-zero internal mechanisms at the
 * handle's point (dense analysis) into N (ld nf), after the rigid ones:
 * returns their count (*first: the column of the first), or -1 where it
 * cannot be made (no dense analysis, more than KIN__HOLD_MAX_M) */
static int near_mechanisms(const kin_assembly *a, double *N, int *first)
{
    const kin_factor *f = kin__cur(a);
    int nf = a->nf, mn = a->nf < a->nb ? a->nf : a->nb;
    if (!f->valid || !f->U || !f->sv || kin__sparse_an_current(a)) return -1;
    double cut = HOLD_NEAR * (mn > 0 ? f->sv[0] : 0.0);
    int mr = f->an.m_rigid, cnt = 0, near = 0;
    for (int k = 0; k < mr; ++k, ++cnt) memcpy(N + (size_t)cnt * nf, f->Urig + (size_t)k * nf, sizeof(double) * (size_t)nf);
    for (int k = 0; k < nf; ++k)
        if (k >= mn || f->sv[k] <= cut) ++near;
    if (near - mr > KIN__HOLD_MAX_M) return -1;
    for (int k = 0; k < nf; ++k) {
        if (k < mn && f->sv[k] > cut) continue;
        double *v = N + (size_t)cnt * nf;
        memcpy(v, f->U + (size_t)k * nf, sizeof(double) * (size_t)nf);
        /* the rigid motions' span taken out: what is left is internal */
        if (kin__gs_column(nf, N, nf, cnt, v) > 0.5 && cnt < mr + KIN__HOLD_MAX_M) ++cnt;
    }
    *first = mr;
    return cnt - mr;
}

int kin__hold_analyse(kin_assembly *a, double rate_tol, double *dir)
{
    struct kin_contact *c = a->ct;
    int nf = a->nf, nh = c->nh, first = 0;
    double *N = c->hg_ws, *G = N + (size_t)nf * (KIN__HOLD_MAX_M + 6), *R = G + (size_t)nh * KIN__HOLD_MAX_M;
    double *beta = R + (size_t)KIN__HOLD_MAX_M * KIN__HOLD_MAX_M, *v = beta + KIN__HOLD_MAX_M + nf;
    int m = near_mechanisms(a, N, &first);
    if (m < 0) return -1;
    /* each held hinge's rate along each mechanism (x the RMS length) */
    int rows = 0;
    for (int h = 0; h < nh; ++h) {
        if (!c->hg_held[h]) continue;
        for (int k = 0; k < m; ++k) {
            velocity(a, N + (size_t)(first + k) * nf, v);
            G[rows * KIN__HOLD_MAX_M + k] = kin__hold_rate(a, h, c->hg_held[h], v) * a->rms_length;
        }
        ++rows;
    }
    /* the rows' span by Gram-Schmidt (a residual at most rate_tol is no
     * new constraint), then the null vectors: what no held rate sees */
    int r = 0;
    for (int i = 0; i < rows && r < m; ++i) {
        double *q = R + (size_t)r * KIN__HOLD_MAX_M;
        memcpy(q, G + (size_t)i * KIN__HOLD_MAX_M, sizeof(double) * (size_t)m);
        for (int pass = 0; pass < 2; ++pass)
            for (int j = 0; j < r; ++j) {
                double d = 0.0;
                for (int k = 0; k < m; ++k) d += q[k] * R[j * KIN__HOLD_MAX_M + k];
                for (int k = 0; k < m; ++k) q[k] -= d * R[j * KIN__HOLD_MAX_M + k];
            }
        double nq = 0.0;
        for (int k = 0; k < m; ++k) nq += q[k] * q[k];
        nq = sqrt(nq);
        if (nq <= rate_tol) continue;
        for (int k = 0; k < m; ++k) q[k] /= nq;
        ++r;
    }
    int held_m = m - r;
    if (held_m < 1 || !dir) return held_m;
    /* the first null vector: e_k less its part in the rows' span, for the
     * first k that keeps at least half of it */
    for (int e = 0; e < m; ++e) {
        for (int k = 0; k < m; ++k) beta[k] = k == e;
        for (int pass = 0; pass < 2; ++pass)
            for (int j = 0; j < r; ++j) {
                double d = 0.0;
                for (int k = 0; k < m; ++k) d += beta[k] * R[j * KIN__HOLD_MAX_M + k];
                for (int k = 0; k < m; ++k) beta[k] -= d * R[j * KIN__HOLD_MAX_M + k];
            }
        double nb = 0.0;
        for (int k = 0; k < m; ++k) nb += beta[k] * beta[k];
        if (nb >= 0.25) break;
    }
    memset(dir, 0, sizeof(double) * (size_t)nf);
    for (int k = 0; k < m; ++k)
        for (int i = 0; i < nf; ++i) dir[i] += beta[k] * N[(size_t)(first + k) * nf + i];
    /* a sign of its own: the largest component positive */
    int big = 0;
    for (int i = 1; i < nf; ++i)
        if (fabs(dir[i]) > fabs(dir[big])) big = i;
    double s = dir[big] < 0.0 ? -1.0 : 1.0, nd = 0.0;
    for (int i = 0; i < nf; ++i) nd += dir[i] * dir[i];
    for (int i = 0; i < nf; ++i) dir[i] *= s / sqrt(nd);
    return held_m;
}

/* the holds belong to the configuration they were kept with (as the
 * tracked sides): forgotten at a start away from it */
static int holds_here(kin_assembly *a)
{
    struct kin_contact *c = a->ct;
    int n = a->nj * a->dim, any = 0;
    for (int h = 0; h < c->nh; ++h) any |= c->hg_held[h] != 0;
    if (!any) return 0;
    int near = c->hg_side_ok;
    for (int i = 0; near && i < n; ++i)
        if (!(fabs(a->xyz[i] - c->hg_x[i]) <= 1e-3 * a->rms_length)) near = 0;
    for (int h = 0; h < c->nh; ++h)
        if (!near || !closed_here(a, h)) c->hg_held[h] = 0;
    any = 0;
    for (int h = 0; h < c->nh; ++h) any |= c->hg_held[h] != 0;
    return any;
}

int kin__hold_start(kin_assembly *a, const kin_follow_options *o, const double *dir, int *at_bif,
                    const double **use_dir, int *event, int *reopened)
{
    struct kin_contact *c = a->ct;
    *use_dir = dir, *event = 0, *reopened = 0;
    if (!c) return KIN_OK;
    c->hold_rigid = 0;
    c->hold_on = o->hold_hinges && c->ev_on && c->hinge_on && c->nh > 0;
    if (!c->hold_on || !holds_here(a)) return KIN_OK;
    int nf = a->nf;
    double *hd = c->hg_ws + kin__hold_ws_size(a, c->nh) - (size_t)nf - 3 * (size_t)a->nj;
    double *v = hd + nf, tol = o->hold_rate_tol;
    const double *d = dir;
    if (!d) {
        int hm = kin__hold_analyse(a, tol, hd);
        if (hm == 0) {
            *event = KIN_FOLLOW_HELD_RIGID;
            return KIN_OK;
        }
        if (*at_bif && hm != 1)
            return kin__fail(a, KIN_EBIFURCATION, "held hinges: %d held motions here: give a direction", hm);
        if (hm == 1) {
            /* the held motion: where it is not the path's tangent (a closure
             * located next to a bifurcation) the follow leaves along it as
             * out of one; else it orients the path */
            const double *t = a->have_t ? a->t : kin__cur(a)->Uint;
            double ct = 0.0;
            for (int i = 0; i < nf; ++i) ct += hd[i] * t[i];
            if (*at_bif || fabs(ct) < o->branch_cos) *at_bif = 1;
            else
                for (int i = 0; i < nf; ++i) hd[i] = ct < 0.0 ? -t[i] : t[i];
            d = *use_dir = hd;
        } else {
            d = a->have_t ? a->t : kin__cur(a)->Uint;
        }
    }
    double nd = 0.0;
    for (int i = 0; i < nf; ++i) nd += d[i] * d[i];
    nd = sqrt(nd);
    velocity(a, d, v);
    /* each held hinge's rate along d: pressing through refuses it, opening
     * releases the hold, zero keeps it */
    for (int h = 0; h < c->nh && nd > 0.0; ++h) {
        if (!c->hg_held[h]) continue;
        double r = kin__hold_rate(a, h, c->hg_held[h], v) * a->rms_length / nd;
        if (r < -tol) {
            if (*at_bif && dir)
                return kin__fail(a, KIN_EINVAL, "dir presses held hinge %d through (angle rate %.3g)", h, r);
            *event = KIN_FOLLOW_HELD_RIGID;
            return KIN_OK;
        }
    }
    for (int h = 0; h < c->nh && nd > 0.0; ++h) {
        if (!c->hg_held[h]) continue;
        if (kin__hold_rate(a, h, c->hg_held[h], v) * a->rms_length / nd > tol) {
            c->hg_held[h] = 0;
            ++*reopened;
        }
    }
    return KIN_OK;
}

void kin__hold_finish(kin_assembly *a, const kin_follow_options *o, kin_follow_info *info)
{
    struct kin_contact *c = a->ct;
    info->hinge = -1, info->held = 0, info->held_m = -1;
    if (!c || !c->hold_on) return;
    if (info->event == KIN_FOLLOW_CONTACT && c->ev_reopen && c->ev_hinge >= 0) {
        info->event = KIN_FOLLOW_HINGE_REOPENED;
        info->hinge = c->ev_hinge;
        c->hg_held[c->ev_hinge] = 0;
    }
    int fresh = -1, ends = info->event == KIN_FOLLOW_CONTACT || info->event == KIN_FOLLOW_BIFURCATION;
    for (int h = 0; h < c->nh; ++h) {
        if (!c->hg_held[h] && ends && c->hg_side[h] != 0 && closed_here(a, h)) {
            c->hg_held[h] = c->hg_side[h];
            if (fresh < 0) fresh = h;
        }
        info->held += c->hg_held[h] != 0;
    }
    if (info->held) info->held_m = c->hold_rigid ? 0 : kin__hold_analyse(a, o->hold_rate_tol, NULL);
    c->hold_rigid = 0;
    if (fresh >= 0) {
        info->hinge = fresh;
        if (info->event == KIN_FOLLOW_CONTACT)
            info->event = info->held_m == 0 ? KIN_FOLLOW_HELD_RIGID : KIN_FOLLOW_HINGE_CLOSED;
    }
    c->hold_on = 0;
}

void kin__hold_mark_rigid(kin_assembly *a)
{
    if (a->ct) a->ct->hold_rigid = 1;
}

int kin__hold_abort(kin_assembly *a)
{
    struct kin_contact *c = a->ct;
    int held = 0;
    if (!c) return 0;
    c->hold_on = 0;
    for (int h = 0; h < c->nh; ++h) held += c->hg_held[h] != 0;
    return held;
}
