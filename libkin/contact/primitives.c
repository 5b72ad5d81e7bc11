/* A pair of primitives of the clearance as the pair walk (walk.c) tests
 * it once the leaf tests (lanes.h) keep it, in double on the joints in tree
 * order (c->pts): whether their parts share a joint (a panel has joints
 * beyond its triangle's), a cheap lower bound by separating axes that
 * shows most pairs near each other but apart without the exact test
 * (kin__prim_far), and the exact clearance (kin__prim_clearance: the
 * distance tests of distance.c less the radii, the same bits whichever
 * tree hands the pair in, so that the answer does not depend on the tree). */
#include <float.h>
#include <math.h>

#include "contact/clearance.h"

/* distances at most this x the largest |coordinate| of the pair are
 * contact (prim_distance) */
static const double TOUCH_ROUNDING = 256.0 * DBL_EPSILON;

/* the joints of a part */
static int part_joints(const kin_assembly *a, int part, const int **j)
{
    if (part < a->nb) {
        *j = a->bars + 2 * part;
        return 2;
    }
    const struct kin_contact *c = a->ct;
    int i = part - a->nb;
    *j = c->pj + c->poff[i];
    return c->poff[i + 1] - c->poff[i];
}

int kin__adjacent_parts(const kin_assembly *a, int pa, int pb)
{
    if (pa == pb) return 1;
    const int *ja, *jb;
    int na = part_joints(a, pa, &ja), nb = part_joints(a, pb, &jb);
    for (int x = 0; x < na; ++x)
        for (int y = 0; y < nb; ++y)
            if (ja[x] == jb[y]) return 1;
    return 0;
}

/* gap of the projections of nv points V (3 each, by index) and nw points W
 * on axis u (any vector; divided by its length; 0 for a zero vector or
 * projections that overlap): a lower bound of the distance of their convex
 * hulls */
static double axis_gap(const double *P, const int *v, int nv, const int *w, int nw, const double *u)
{
    double lo1 = INFINITY, hi1 = -INFINITY, lo2 = INFINITY, hi2 = -INFINITY;
    for (int i = 0; i < nv; ++i) {
        const double *x = P + 3 * v[i];
        double t = x[0] * u[0] + x[1] * u[1] + x[2] * u[2];
        lo1 = dmin(lo1, t), hi1 = dmax(hi1, t);
    }
    for (int i = 0; i < nw; ++i) {
        const double *x = P + 3 * w[i];
        double t = x[0] * u[0] + x[1] * u[1] + x[2] * u[2];
        lo2 = dmin(lo2, t), hi2 = dmax(hi2, t);
    }
    double g = dmax(lo2 - hi1, lo1 - hi2);
    if (!(g > 0.0)) return 0.0;
    double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    return uu > 0.0 ? g / sqrt(uu) : 0.0;
}

/* The points of the primitives v, w (3 joints each; a bar's third -1) of
 * P copied into Q (v's at 0-2, w's at 3-5) with their indices into Q (vq,
 * wq), scaled by 2^-k, k returned: 0 (an exact copy, the same bits as on P)
 * while the largest |coordinate| is within 2^-200..2^200, else such that it
 * is about 1. The tests below multiply up to four lengths (cross products,
 * their projections, the normal equations' determinants): at 1e150 these
 * overflowed (a panel missed or pruned, its clearance wrong) and at 1e-100
 * underflowed (a triangle taken for a zero-area one); scaled by a power of
 * two they are exact, and scale back exactly. */
static int gather(const double *P, const int *v, const int *w, double *Q, int *vq, int *wq)
{
    double m = 0.0;
    for (int i = 0; i < 6; ++i) {
        int j = i < 3 ? v[i] : w[i - 3];
        int *o = i < 3 ? vq + i : wq + i - 3;
        *o = j >= 0 ? i : -1;
        for (int a = 0; a < 3; ++a) {
            Q[3 * i + a] = j >= 0 ? P[3 * j + a] : 0.0;
            m = fmax(m, fabs(Q[3 * i + a]));
        }
    }
    if (!(m > 0x1p200 || (m < 0x1p-200 && m > 0.0))) return 0;
    int k = ilogb(m);
    for (int i = 0; i < 18; ++i) Q[i] = ldexp(Q[i], -k);
    return k;
}

static double prim_distance(const double *P, const int *vp, const int *vq, double *cp, double *cq);
static int prim_far(const double *P, const int *vp, const int *vq, double rr, double best);

int kin__prim_far(const struct kin_contact *c, const kin__leafprim *Lp, const kin__leafprim *Lq, double rr,
                  double best)
{
    if (-rr > best) return 1; /* the distance is >= 0 */
    double P[18];
    int vp[3], vq[3], k = gather(c->pts, Lp->v, Lq->v, P, vp, vq);
    /* the bounds scale with the points: compare rr and best in P's unit */
    return prim_far(P, vp, vq, ldexp(rr, -k), ldexp(best, -k));
}

/* 1 if a cheap lower bound shows that leaves p and q (radii sum rr) have
 * clearance above best: separating axes (the line of their centroids; for
 * a triangle its normal and the in-plane normals of its sides; then the
 * cross products of their sides), stopping at the first that shows it, so that most pairs near each other but apart
 * never reach the exact test */
static int prim_far(const double *P, const int *vp, const int *vq, double rr, double best)
{
    int np = vp[2] >= 0 ? 3 : 2, nq = vq[2] >= 0 ? 3 : 2;
    double u[3]; /* the line of the centroids: np * nq times their difference */
    for (int k = 0; k < 3; ++k) {
        double sp = P[3 * vp[0] + k] + P[3 * vp[1] + k], sq = P[3 * vq[0] + k] + P[3 * vq[1] + k];
        if (np == 3) sp += P[3 * vp[2] + k];
        if (nq == 3) sq += P[3 * vq[2] + k];
        u[k] = np * sq - nq * sp;
    }
    if (axis_gap(P, vp, np, vq, nq, u) - rr > best) return 1;
    if (np == 2 && nq == 2) {
        /* two segments: the common normal of their lines, and the normal of
         * each in the plane of both (segments side by side in a plane) */
        double d1[3], d2[3], n[3], m[3];
        for (int k = 0; k < 3; ++k) d1[k] = P[3 * vp[1] + k] - P[3 * vp[0] + k], d2[k] = P[3 * vq[1] + k] - P[3 * vq[0] + k];
        n[0] = d1[1] * d2[2] - d1[2] * d2[1];
        n[1] = d1[2] * d2[0] - d1[0] * d2[2];
        n[2] = d1[0] * d2[1] - d1[1] * d2[0];
        if (axis_gap(P, vp, np, vq, nq, n) - rr > best) return 1;
        for (int side = 0; side < 2; ++side) {
            const double *e = side ? d2 : d1;
            m[0] = e[1] * n[2] - e[2] * n[1];
            m[1] = e[2] * n[0] - e[0] * n[2];
            m[2] = e[0] * n[1] - e[1] * n[0];
            if (axis_gap(P, vp, np, vq, nq, m) - rr > best) return 1;
        }
        return 0;
    }
    for (int side = 0; side < 2; ++side) {
        const int *t = side ? vq : vp;
        if ((side ? nq : np) < 3) continue;
        const double *a = P + 3 * t[0], *b = P + 3 * t[1], *cc = P + 3 * t[2];
        double e[3][3], n[3];
        for (int k = 0; k < 3; ++k) e[0][k] = b[k] - a[k], e[1][k] = cc[k] - b[k], e[2][k] = a[k] - cc[k];
        n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
        n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
        n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
        if (axis_gap(P, vp, np, vq, nq, n) - rr > best) return 1;
        for (int i = 0; i < 3; ++i) {
            double m[3] = {e[i][1] * n[2] - e[i][2] * n[1], e[i][2] * n[0] - e[i][0] * n[2],
                           e[i][0] * n[1] - e[i][1] * n[0]};
            if (axis_gap(P, vp, np, vq, nq, m) - rr > best) return 1;
        }
    }
    /* the cross products of a side of one with a side of the other (with
     * the axes above, every axis that can separate them: a long bar that
     * passes over a triangle, say, is not separated by any of those) */
    double ep[3][3], eq[3][3];
    for (int i = 0; i < np; ++i)
        for (int k = 0; k < 3; ++k) ep[i][k] = P[3 * vp[(i + 1) % np] + k] - P[3 * vp[i] + k];
    for (int i = 0; i < nq; ++i)
        for (int k = 0; k < 3; ++k) eq[i][k] = P[3 * vq[(i + 1) % nq] + k] - P[3 * vq[i] + k];
    for (int i = 0; i < (np == 3 ? 3 : 1); ++i)
        for (int j = 0; j < (nq == 3 ? 3 : 1); ++j) {
            const double *e = ep[i], *f = eq[j];
            double m[3] = {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2], e[0] * f[1] - e[1] * f[0]};
            if (axis_gap(P, vp, np, vq, nq, m) - rr > best) return 1;
        }
    return 0;
}

/* exact clearance of leaves x, y (centre distance minus radii), closest
 * points cp on x, cq on y. Symmetric: the two primitives are taken in the
 * order of their numbers (prim_part's, which no tree changes), so a pair's
 * clearance and points are the same bits whichever tree hands it in
 * whichever order (the radii are subtracted in that order too) */
double kin__prim_clearance(const struct kin_contact *c, int x, int y, double *cp, double *cq)
{
    if (c->order[x] > c->order[y]) {
        int t = x;
        double *tp = cp;
        x = y, y = t, cp = cq, cq = tp;
    }
    double P[18];
    int vp[3], vq[3], k = gather(c->pts, c->lp[x].v, c->lp[y].v, P, vp, vq);
    double d = prim_distance(P, vp, vq, cp, cq);
    if (k) {
        d = ldexp(d, k);
        for (int i = 0; i < 3; ++i) cp[i] = ldexp(cp[i], k), cq[i] = ldexp(cq[i], k);
    }
    return d - c->lr[x] - c->lr[y];
}

/* the distance of the primitives vp, vq of P, closest points cp, cq */
static double prim_distance(const double *P, const int *vp, const int *vq, double *cp, double *cq)
{
    double d;
    int tp = vp[2] >= 0, tq = vq[2] >= 0;
    if (!tp && !tq) d = kin__dist_seg_seg(P + 3 * vp[0], P + 3 * vp[1], P + 3 * vq[0], P + 3 * vq[1], cp, cq);
    else if (!tp) d = kin__dist_seg_tri(P + 3 * vp[0], P + 3 * vp[1], P + 3 * vq[0], P + 3 * vq[1], P + 3 * vq[2], cp, cq);
    else if (!tq) d = kin__dist_seg_tri(P + 3 * vq[0], P + 3 * vq[1], P + 3 * vp[0], P + 3 * vp[1], P + 3 * vp[2], cq, cp);
    else {
        const double *A[3] = {P + 3 * vp[0], P + 3 * vp[1], P + 3 * vp[2]};
        const double *B[3] = {P + 3 * vq[0], P + 3 * vq[1], P + 3 * vq[2]};
        d = kin__dist_tri_tri(A, B, cp, cq);
    }
    /* within rounding of touching is touching: a bar that crosses a panel
     * or another bar in their plane came out at 1e-17..5e-14 (the exact
     * tests round at eps x the coordinates), which read as no contact */
    double m = 0.0;
    for (int i = 0; i < 3; ++i) {
        if (vp[i] >= 0) m = fmax(m, fmax(fabs(P[3 * vp[i]]), fmax(fabs(P[3 * vp[i] + 1]), fabs(P[3 * vp[i] + 2]))));
        if (vq[i] >= 0) m = fmax(m, fmax(fabs(P[3 * vq[i]]), fmax(fabs(P[3 * vq[i] + 1]), fabs(P[3 * vq[i] + 2]))));
    }
    if (d > 0.0 && d <= TOUCH_ROUNDING * m) {
        d = 0.0;
        for (int i = 0; i < 3; ++i) cp[i] = cq[i] = 0.5 * (cp[i] + cq[i]);
    }
    return d;
}
