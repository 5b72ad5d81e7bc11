/* The leaf tests of the clearance's walk (walk.c, leaf_pair): one
 * primitive of a leaf (a row) against the 8 lanes of another leaf
 * (kin__leafsoa) at once, each test a bit mask of lanes, in SSE2 (every
 * x86-64 has it) or plain C. Static inline in this header because they are
 * the walk's inner loop, inlined into it as they were when they shared its
 * file; the refit (tree.c) projects a leaf's lanes on its own axis with
 * the walk's project_lanes, so that both round alike. */
#ifndef KIN_CONTACT_LANES_H
#define KIN_CONTACT_LANES_H

#include "contact/clearance.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* The leaf tests in straight-line code (no branch per pair: a walk over
 * thousands of leaf pairs, each pair's outcome different, is more than a
 * branch predictor can learn). near_lanes: bit i set unless lane i's box is
 * more than T apart from box (lo, hi) along some axis, in float: a superset
 * of the pairs the exact test (walk.c: cannot_beat of gap2, in double)
 * keeps, for T = near_bound(best) (rounding to float is monotone, and T is
 * above the largest axis gap that test keeps); NaN differences (none arise: boxes are
 * finite or clamped) would keep the lane. adjacent_lanes: bit i set when
 * lane i shares a joint with (v0, v1, v2). Lanes past the leaf's count are
 * masked by the caller. SSE2 (every x86-64) or plain C. */
static inline float near_bound(double best) { return best >= 0.0 ? f_up(best) : 0.0f; }
/* the bound on the x + y, x - y slabs (projections on (1, +-1, 0), of
 * length sqrt 2): a float gap g > T2 there means a distance above
 * g (1 - 2^-24) / sqrt 2 > best */
static inline float near_bound2(double best) { return best >= 0.0 ? f_up(best * 1.4142135623730951 * (1.0 + 0x1p-20)) : 0.0f; }

#if defined(__SSE2__)
static inline unsigned near_lanes(const kin__leafsoa *S, const float *lo, const float *hi, float T)
{
    const __m128 t = _mm_set1_ps(T);
    unsigned m = 0;
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        __m128 far = _mm_setzero_ps();
        for (int k = 0; k < 3; ++k) {
            far = _mm_or_ps(far, _mm_cmpgt_ps(_mm_sub_ps(_mm_loadu_ps(S->lo[k] + h), _mm_set1_ps(hi[k])), t));
            far = _mm_or_ps(far, _mm_cmpgt_ps(_mm_sub_ps(_mm_set1_ps(lo[k]), _mm_loadu_ps(S->hi[k] + h)), t));
        }
        m |= (unsigned)(~_mm_movemask_ps(far) & 15) << h;
    }
    return m;
}
/* diag_lanes: bit i set when lane i's slab across x + y or x - y is more
 * than T2 (near_bound2) apart from lo, hi (the row's slabs 3, 4); lanes
 * outside cols are not tested. Long thin parts tilted in a nearly flat
 * sheet (a sail) have boxes far larger than they are; these two slabs
 * drop most of the pairs such boxes keep. */
static inline unsigned diag_lanes(const kin__leafsoa *S, const float *lo, const float *hi, float T2, unsigned cols)
{
    const __m128 t = _mm_set1_ps(T2);
    unsigned m = 0;
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        if (!((cols >> h) & 15u)) continue;
        __m128 far = _mm_setzero_ps();
        for (int k = 3; k < 5; ++k) {
            far = _mm_or_ps(far, _mm_cmpgt_ps(_mm_sub_ps(_mm_loadu_ps(S->lo[k] + h), _mm_set1_ps(hi[k])), t));
            far = _mm_or_ps(far, _mm_cmpgt_ps(_mm_sub_ps(_mm_set1_ps(lo[k]), _mm_loadu_ps(S->hi[k] + h)), t));
        }
        m |= (unsigned)_mm_movemask_ps(far) << h;
    }
    return m & cols;
}
static inline unsigned adjacent_lanes(const kin__leafsoa *S, int v0, int v1, int v2)
{
    const __m128i a = _mm_set1_epi32(v0), b = _mm_set1_epi32(v1), d = _mm_set1_epi32(v2);
    unsigned m = 0;
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        __m128i eq = _mm_setzero_si128();
        for (int k = 0; k < 3; ++k) {
            __m128i w = _mm_loadu_si128((const __m128i *)(S->v[k] + h));
            eq = _mm_or_si128(eq, _mm_or_si128(_mm_cmpeq_epi32(w, a), _mm_or_si128(_mm_cmpeq_epi32(w, b), _mm_cmpeq_epi32(w, d))));
        }
        m |= (unsigned)_mm_movemask_ps(_mm_castsi128_ps(eq)) << h;
    }
    return m;
}
#else
static inline unsigned near_lanes(const kin__leafsoa *S, const float *lo, const float *hi, float T)
{
    unsigned m = 0;
    for (int i = 0; i < KIN__LEAF_MAX; ++i) {
        int far = 0;
        for (int k = 0; k < 3; ++k) far |= (S->lo[k][i] - hi[k] > T) | (lo[k] - S->hi[k][i] > T);
        m |= (unsigned)!far << i;
    }
    return m;
}
static inline unsigned diag_lanes(const kin__leafsoa *S, const float *lo, const float *hi, float T2, unsigned cols)
{
    unsigned m = 0;
    for (int i = 0; i < KIN__LEAF_MAX; ++i) {
        if (!((cols >> i) & 1u)) continue;
        int far = 0;
        for (int k = 3; k < 5; ++k) far |= (S->lo[k][i] - hi[k] > T2) | (lo[k] - S->hi[k][i] > T2);
        m |= (unsigned)far << i;
    }
    return m;
}
static inline unsigned adjacent_lanes(const kin__leafsoa *S, int v0, int v1, int v2)
{
    unsigned m = 0;
    for (int i = 0; i < KIN__LEAF_MAX; ++i) {
        int eq = 0;
        for (int k = 0; k < 3; ++k) eq |= (S->v[k][i] == v0) | (S->v[k][i] == v1) | (S->v[k][i] == v2);
        m |= (unsigned)eq << i;
    }
    return m;
}
#endif

/* apart_lanes: bit j set when lane j of S and lane i of X are shown
 * apart by more than T along the line of their box centres (the first
 * separating axis of kin__prim_far, primitives.c; in float on the joints'
 * points rounded to float): bound = (gap of the projections) / |u| - radii. Rounding: every
 * point is within M (the root box's largest coordinate), so the points'
 * rounding and the float arithmetic move the bound by less than 2^-19 M,
 * and slack = 2^-16 M is added to T and the radii (slack inf for M
 * outside 2^-40 .. 2^100, where products would overflow or underflow: no
 * lane; where the float sum thr0 = T + r + slack loses more than the
 * slack to its rounding, it is beyond any gap the points can have). A
 * superset of what the exact bounds keep stays kept: it only drops pairs
 * whose clearance is above T >= best. */
static inline void apart_row(const kin__leafsoa *X, int i, float cx[3], float xp[3][3])
{
    for (int k = 0; k < 3; ++k) cx[k] = 0.5f * X->lo[k][i] + 0.5f * X->hi[k][i];
    for (int q = 0; q < 3; ++q)
        for (int k = 0; k < 3; ++k) xp[q][k] = X->p[q][k][i];
}
#if defined(__SSE2__)
static inline unsigned apart_lanes(const kin__leafsoa *S, const float cx[3], float xp[3][3], float thr0, unsigned cols)
{
    const __m128 half = _mm_set1_ps(0.5f), zero = _mm_setzero_ps();
    unsigned m = 0;
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        if (!((cols >> h) & 15u)) continue;
        __m128 u[3];
        for (int k = 0; k < 3; ++k)
            u[k] = _mm_sub_ps(_mm_add_ps(_mm_mul_ps(half, _mm_loadu_ps(S->lo[k] + h)), _mm_mul_ps(half, _mm_loadu_ps(S->hi[k] + h))),
                              _mm_set1_ps(cx[k]));
        __m128 lo1 = _mm_set1_ps(INFINITY), hi1 = _mm_set1_ps(-INFINITY), lo2 = lo1, hi2 = hi1;
        for (int q = 0; q < 3; ++q) {
            __m128 t = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u[0], _mm_set1_ps(xp[q][0])), _mm_mul_ps(u[1], _mm_set1_ps(xp[q][1]))),
                                  _mm_mul_ps(u[2], _mm_set1_ps(xp[q][2])));
            lo1 = _mm_min_ps(lo1, t), hi1 = _mm_max_ps(hi1, t);
            __m128 w = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u[0], _mm_loadu_ps(S->p[q][0] + h)), _mm_mul_ps(u[1], _mm_loadu_ps(S->p[q][1] + h))),
                                  _mm_mul_ps(u[2], _mm_loadu_ps(S->p[q][2] + h)));
            lo2 = _mm_min_ps(lo2, w), hi2 = _mm_max_ps(hi2, w);
        }
        __m128 gap = _mm_max_ps(_mm_sub_ps(lo2, hi1), _mm_sub_ps(lo1, hi2));
        __m128 thr = _mm_add_ps(_mm_set1_ps(thr0), _mm_loadu_ps(S->r + h));
        __m128 uu = _mm_add_ps(_mm_add_ps(_mm_mul_ps(u[0], u[0]), _mm_mul_ps(u[1], u[1])), _mm_mul_ps(u[2], u[2]));
        __m128 apart = _mm_and_ps(_mm_cmpgt_ps(gap, zero), _mm_cmpgt_ps(_mm_mul_ps(gap, gap), _mm_mul_ps(_mm_mul_ps(thr, thr), uu)));
        m |= (unsigned)_mm_movemask_ps(apart) << h;
    }
    return m;
}
#else
static inline unsigned apart_lanes(const kin__leafsoa *S, const float cx[3], float xp[3][3], float thr0, unsigned cols)
{
    unsigned m = 0;
    for (int j = 0; j < KIN__LEAF_MAX; ++j) {
        if (!((cols >> j) & 1u)) continue;
        float u[3], lo1 = INFINITY, hi1 = -INFINITY, lo2 = INFINITY, hi2 = -INFINITY;
        for (int k = 0; k < 3; ++k) u[k] = (0.5f * S->lo[k][j] + 0.5f * S->hi[k][j]) - cx[k];
        for (int q = 0; q < 3; ++q) {
            float t = u[0] * xp[q][0] + u[1] * xp[q][1] + u[2] * xp[q][2];
            float w = u[0] * S->p[q][0][j] + u[1] * S->p[q][1][j] + u[2] * S->p[q][2][j];
            lo1 = t < lo1 ? t : lo1, hi1 = t > hi1 ? t : hi1, lo2 = w < lo2 ? w : lo2, hi2 = w > hi2 ? w : hi2;
        }
        float gap = lo2 - hi1 > lo1 - hi2 ? lo2 - hi1 : lo1 - hi2, thr = thr0 + S->r[j];
        float uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
        m |= (unsigned)(gap > 0.0f && gap * gap > thr * thr * uu) << j;
    }
    return m;
}
#endif

/* own_lanes: bit j set when lane j of S is shown apart by more than T from
 * the row's primitive along one of its own axes (ax: KIN__OWN_AXES unit
 * axes, each with the interval of the row's primitive on it: made by
 * own_axes, walk.c); lanes outside cols are not tested. The axes are the
 * ones kin__prim_far (primitives.c) finds separating most pairs that the box
 * test and the line of the centres keep (long thin triangles side by side
 * in a dome: the in-plane normals of their sides): one row's axes against
 * 8 lanes in straight-line code cost less than the scalar bounds they
 * save. Rounding:
 * as apart_lanes (points rounded to float, float arithmetic, axes of length
 * 1 to 2^-22: the slack in T covers it). A disabled axis (a degenerate
 * primitive) has the interval (-inf, inf). */
#if defined(__SSE2__)
static inline unsigned own_lanes(const kin__leafsoa *S, const float *ax, float thr0, unsigned cols)
{
    unsigned m = 0;
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        if (!((cols >> h) & 15u)) continue;
        __m128 p[3][3];
        for (int q = 0; q < 3; ++q)
            for (int k = 0; k < 3; ++k) p[q][k] = _mm_loadu_ps(S->p[q][k] + h);
        __m128 thr = _mm_add_ps(_mm_set1_ps(thr0), _mm_loadu_ps(S->r + h)), apart = _mm_setzero_ps();
        for (int s = 0; s < KIN__OWN_AXES; ++s) {
            const float *a = ax + 5 * s;
            __m128 a0 = _mm_set1_ps(a[0]), a1 = _mm_set1_ps(a[1]), a2 = _mm_set1_ps(a[2]), lo = lo, hi = hi;
            for (int q = 0; q < 3; ++q) {
                __m128 t = _mm_add_ps(_mm_add_ps(_mm_mul_ps(a0, p[q][0]), _mm_mul_ps(a1, p[q][1])), _mm_mul_ps(a2, p[q][2]));
                lo = q ? _mm_min_ps(lo, t) : t, hi = q ? _mm_max_ps(hi, t) : t;
            }
            __m128 gap = _mm_max_ps(_mm_sub_ps(lo, _mm_set1_ps(a[4])), _mm_sub_ps(_mm_set1_ps(a[3]), hi));
            apart = _mm_or_ps(apart, _mm_cmpgt_ps(gap, thr));
        }
        m |= (unsigned)_mm_movemask_ps(apart) << h;
    }
    return m & cols;
}
#else
static inline unsigned own_lanes(const kin__leafsoa *S, const float *ax, float thr0, unsigned cols)
{
    unsigned m = 0;
    for (int j = 0; j < KIN__LEAF_MAX; ++j) {
        if (!((cols >> j) & 1u)) continue;
        float thr = thr0 + S->r[j];
        int apart = 0;
        for (int s = 0; s < KIN__OWN_AXES; ++s) {
            const float *a = ax + 5 * s;
            float lo = INFINITY, hi = -INFINITY;
            for (int q = 0; q < 3; ++q) {
                float t = a[0] * S->p[q][0][j] + a[1] * S->p[q][1][j] + a[2] * S->p[q][2][j];
                lo = t < lo ? t : lo, hi = t > hi ? t : hi;
            }
            float gap = lo - a[4] > a[3] - hi ? lo - a[4] : a[3] - hi;
            apart |= gap > thr;
        }
        m |= (unsigned)apart << j;
    }
    return m;
}
#endif

/* project_lanes: the intervals (lo, hi) of S's 8 lanes' float points on
 * the axis w (another leaf's; lanes past S's count are masked by the
 * caller). orient_lanes: bit j set when lane j's interval (lo, hi) on a
 * row's leaf axis is more than thr0 + its radius apart from the row's
 * (rlo, rhi), thr0 as in apart_lanes (best, the row's radius and the
 * slack); lanes outside cols are not tested. The leaf axis lies across a
 * leaf's long parts in their plane, so it separates parallel long tilted
 * parts side by side, which boxes and fixed slabs do not (a sail's outer
 * loops). Rounding: as apart_lanes (a unit float axis, float points and
 * arithmetic: the slack covers it). */
#if defined(__SSE2__)
static inline void project_lanes(const kin__leafsoa *S, const float *w, float *lo, float *hi)
{
    const __m128 w0 = _mm_set1_ps(w[0]), w1 = _mm_set1_ps(w[1]), w2 = _mm_set1_ps(w[2]);
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        __m128 l = _mm_setzero_ps(), u = l;
        for (int q = 0; q < 3; ++q) {
            __m128 t = _mm_add_ps(_mm_add_ps(_mm_mul_ps(w0, _mm_loadu_ps(S->p[q][0] + h)), _mm_mul_ps(w1, _mm_loadu_ps(S->p[q][1] + h))),
                                  _mm_mul_ps(w2, _mm_loadu_ps(S->p[q][2] + h)));
            l = q ? _mm_min_ps(l, t) : t, u = q ? _mm_max_ps(u, t) : t;
        }
        _mm_storeu_ps(lo + h, l), _mm_storeu_ps(hi + h, u);
    }
}
static inline unsigned orient_lanes(const float *lo, const float *hi, const float *r, float rlo, float rhi, float thr0, unsigned cols)
{
    const __m128 a = _mm_set1_ps(rlo), b = _mm_set1_ps(rhi), t0 = _mm_set1_ps(thr0);
    unsigned m = 0;
    for (int h = 0; h < KIN__LEAF_MAX; h += 4) {
        if (!((cols >> h) & 15u)) continue;
        __m128 gap = _mm_max_ps(_mm_sub_ps(_mm_loadu_ps(lo + h), b), _mm_sub_ps(a, _mm_loadu_ps(hi + h)));
        m |= (unsigned)_mm_movemask_ps(_mm_cmpgt_ps(gap, _mm_add_ps(t0, _mm_loadu_ps(r + h)))) << h;
    }
    return m & cols;
}
#else
static inline void project_lanes(const kin__leafsoa *S, const float *w, float *lo, float *hi)
{
    for (int j = 0; j < KIN__LEAF_MAX; ++j) {
        float l = INFINITY, u = -INFINITY;
        for (int q = 0; q < 3; ++q) {
            float t = w[0] * S->p[q][0][j] + w[1] * S->p[q][1][j] + w[2] * S->p[q][2][j];
            l = t < l ? t : l, u = t > u ? t : u;
        }
        lo[j] = l, hi[j] = u;
    }
}
static inline unsigned orient_lanes(const float *lo, const float *hi, const float *r, float rlo, float rhi, float thr0, unsigned cols)
{
    unsigned m = 0;
    for (int j = 0; j < KIN__LEAF_MAX; ++j) {
        float gap = lo[j] - rhi > rlo - hi[j] ? lo[j] - rhi : rlo - hi[j];
        m |= (unsigned)(gap > thr0 + r[j]) << j;
    }
    return m & cols;
}
#endif

/* the lowest set bit's index of m != 0 */
static inline int low_bit(unsigned m)
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctz(m);
#else
    int i = 0;
    while (!(m & 1u)) m >>= 1, ++i;
    return i;
#endif
}

#endif /* KIN_CONTACT_LANES_H */
