/* The exact distance tests of the clearance (primitives.c): point-segment,
 * segment-segment, point-triangle, segment-triangle and triangle-triangle,
 * each returning the distance and the two closest points.
 *
 * Method (the standard decomposition): the distance of two convex sets that
 * do not meet is attained between a feature of one and a feature of the
 * other, so
 *   segment-segment = the interior solution of the 2x2 normal equations,
 *                     clamped, and the four endpoint-to-segment distances
 *                     (the smallest; exact in the parallel case, where the
 *                     interior solution is not unique);
 *   segment-triangle = 0 where the segment crosses the triangle's plane
 *                     inside it, else the smallest of the segment against
 *                     each side and each endpoint against the triangle;
 *   triangle-triangle = the smallest of the six side-triangle distances (two
 *                     triangles that meet have a side of one meeting the
 *                     other, coplanar or not).
 * A zero-area triangle (collinear or repeated corners) is its sides. */
#include <math.h>
#include <string.h>

#include "contact/contact_internal.h"

static inline void sub3(const double *a, const double *b, double *o)
{
    o[0] = a[0] - b[0], o[1] = a[1] - b[1], o[2] = a[2] - b[2];
}
static inline double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static inline void lerp3(const double *a, const double *b, double s, double *o)
{
    for (int k = 0; k < 3; ++k) o[k] = a[k] + s * (b[k] - a[k]);
}
static inline double dist3(const double *a, const double *b)
{
    double d[3];
    sub3(a, b, d);
    return sqrt(dot3(d, d));
}
static inline double clamp01(double s) { return s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s); }

/* closest point of segment [a,b] to p into o */
static void pt_seg(const double *p, const double *a, const double *b, double *o)
{
    double ab[3], ap[3];
    sub3(b, a, ab);
    sub3(p, a, ap);
    double L = dot3(ab, ab);
    double s = L > 0.0 ? clamp01(dot3(ap, ab) / L) : 0.0;
    if (s == 1.0) memcpy(o, b, 3 * sizeof *o);
    else lerp3(a, b, s, o);
}

double kin__dist_seg_seg(const double *p0, const double *p1, const double *q0, const double *q1, double *cp,
                         double *cq)
{
    double d1[3], d2[3], r[3], best, x[3], y[3];
    sub3(p1, p0, d1);
    sub3(q1, q0, d2);
    sub3(p0, q0, r);
    double a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r), c = dot3(d1, r), b = dot3(d1, d2);
    /* endpoint candidates first: they settle the parallel and degenerate cases */
    memcpy(cp, p0, sizeof(double) * 3);
    pt_seg(p0, q0, q1, cq);
    best = dist3(cp, cq);
    pt_seg(p1, q0, q1, y);
    double dd = dist3(p1, y);
    if (dd < best) best = dd, memcpy(cp, p1, sizeof x), memcpy(cq, y, sizeof y);
    pt_seg(q0, p0, p1, x);
    dd = dist3(x, q0);
    if (dd < best) best = dd, memcpy(cp, x, sizeof x), memcpy(cq, q0, sizeof y);
    pt_seg(q1, p0, p1, x);
    dd = dist3(x, q1);
    if (dd < best) best = dd, memcpy(cp, x, sizeof x), memcpy(cq, q1, sizeof y);
    /* interior solution of the normal equations (both parameters in (0,1));
     * near parallel it may be inaccurate, but it is a pair of points of the
     * two segments, so it never undercuts the true distance */
    double den = a * e - b * b;
    if (a > 0.0 && e > 0.0 && den > 0.0) {
        double s = (b * f - c * e) / den, t = (a * f - b * c) / den;
        if (s > 0.0 && s < 1.0 && t > 0.0 && t < 1.0) {
            lerp3(p0, p1, s, x);
            lerp3(q0, q1, t, y);
            dd = dist3(x, y);
            if (dd < best) best = dd, memcpy(cp, x, sizeof x), memcpy(cq, y, sizeof y);
        }
    }
    return best;
}

/* barycentric solve of the closest point of the triangle's plane to p:
 * returns 0 for a zero-area triangle; otherwise (u, v, w) weights of a, b, c */
static int plane_bary(const double *p, const double *a, const double *b, const double *c, double *u, double *v,
                      double *w)
{
    double ab[3], ac[3], ap[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    sub3(p, a, ap);
    double d00 = dot3(ab, ab), d01 = dot3(ab, ac), d11 = dot3(ac, ac);
    double d20 = dot3(ap, ab), d21 = dot3(ap, ac);
    double n[3];
    cross3(ab, ac, n);
    double den = dot3(n, n); /* = d00*d11 - d01^2, without the cancellation */
    if (!(den > 1e-28 * d00 * d11) || den == 0.0) return 0;
    *v = (d11 * d20 - d01 * d21) / den;
    *w = (d00 * d21 - d01 * d20) / den;
    *u = 1.0 - *v - *w;
    return 1;
}

double kin__dist_pt_tri(const double *p, const double *a, const double *b, const double *c, double *cq)
{
    double u, v, w;
    if (plane_bary(p, a, b, c, &u, &v, &w) && u >= 0.0 && v >= 0.0 && w >= 0.0) {
        for (int k = 0; k < 3; ++k) cq[k] = u * a[k] + v * b[k] + w * c[k];
        return dist3(p, cq);
    }
    /* outside (or zero area): the nearest side */
    double x[3];
    pt_seg(p, a, b, cq);
    double best = dist3(p, cq);
    pt_seg(p, b, c, x);
    double d = dist3(p, x);
    if (d < best) best = d, memcpy(cq, x, sizeof x);
    pt_seg(p, c, a, x);
    d = dist3(p, x);
    if (d < best) best = d, memcpy(cq, x, sizeof x);
    return best;
}

double kin__dist_seg_tri(const double *p0, const double *p1, const double *a, const double *b, const double *c,
                         double *cp, double *cq)
{
    double ab[3], ac[3], n[3];
    sub3(b, a, ab);
    sub3(c, a, ac);
    cross3(ab, ac, n);
    double nn = dot3(n, n);
    if (nn > 1e-28 * dot3(ab, ab) * dot3(ac, ac) && nn > 0.0) {
        /* does the segment cross the plane inside the triangle? */
        double e0[3], e1[3];
        sub3(p0, a, e0);
        sub3(p1, a, e1);
        double s0 = dot3(e0, n), s1 = dot3(e1, n);
        if ((s0 <= 0.0 && s1 >= 0.0) || (s0 >= 0.0 && s1 <= 0.0)) {
            if (s0 != s1) {
                double x[3], u, v, w;
                lerp3(p0, p1, s0 / (s0 - s1), x);
                if (plane_bary(x, a, b, c, &u, &v, &w) && u >= 0.0 && v >= 0.0 && w >= 0.0) {
                    memcpy(cp, x, sizeof x);
                    memcpy(cq, x, sizeof x);
                    return 0.0;
                }
            }
        }
    }
    /* no crossing (or coplanar, or zero area): sides and endpoints */
    double x[3], y[3];
    double best = kin__dist_seg_seg(p0, p1, a, b, cp, cq);
    double d = kin__dist_seg_seg(p0, p1, b, c, x, y);
    if (d < best) best = d, memcpy(cp, x, sizeof x), memcpy(cq, y, sizeof y);
    d = kin__dist_seg_seg(p0, p1, c, a, x, y);
    if (d < best) best = d, memcpy(cp, x, sizeof x), memcpy(cq, y, sizeof y);
    d = kin__dist_pt_tri(p0, a, b, c, y);
    if (d < best) best = d, memcpy(cp, p0, sizeof x), memcpy(cq, y, sizeof y);
    d = kin__dist_pt_tri(p1, a, b, c, y);
    if (d < best) best = d, memcpy(cp, p1, sizeof x), memcpy(cq, y, sizeof y);
    return best;
}

double kin__dist_tri_tri(const double *const A[3], const double *const B[3], double *cp, double *cq)
{
    double x[3], y[3], best = INFINITY;
    for (int i = 0; i < 3 && best > 0.0; ++i) {
        double d = kin__dist_seg_tri(A[i], A[(i + 1) % 3], B[0], B[1], B[2], x, y);
        if (d < best) best = d, memcpy(cp, x, sizeof x), memcpy(cq, y, sizeof y);
    }
    for (int i = 0; i < 3 && best > 0.0; ++i) {
        double d = kin__dist_seg_tri(B[i], B[(i + 1) % 3], A[0], A[1], A[2], y, x);
        if (d < best) best = d, memcpy(cp, x, sizeof x), memcpy(cq, y, sizeof y);
    }
    return best;
}
