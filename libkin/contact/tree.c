/* The bounding-volume tree of the clearance (kin_clearance, contact.c),
 * fitted to each configuration before the pair walk (walk.c). Every bar is
 * one primitive (a segment), every panel the fan of its triangles; each
 * primitive's box is grown by its radius. The tree (split at the median,
 * moved to a multiple of 8 so that the leaves are full, of the box centres
 * along whichever of x, y, z, x + y, x - y and the node's own two
 * directions, along its parts and across them, gives the two halves the
 * least surface measure) is built at the first call and then refitted to
 * each configuration (O(n): the boxes bottom up, the topology kept), and
 * built again only when the refitted boxes have grown by half against
 * those right after its build. Primitives and joints are stored in tree
 * order and boxes as floats rounded outward (24 bytes per primitive, an
 * 816-byte block of 8 lanes per leaf, 56 bytes per node), so the walk
 * reads contiguous memory; leaves and nodes also carry the slabs across
 * x + y and x - y, and each leaf its own axis across its parts (in their
 * plane) with its lanes' intervals on it. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "contact/lanes.h" /* project_lanes, and SSE2 for leaf_slabs */

#define LEAF_MAX KIN__LEAF_MAX
/* the split's fixed directions: x, y, z and the slabs' x + y, x - y */
#define NDIR KIN__SPLIT_NDIR
#define CEN KIN__CEN /* doubles per primitive in cen */
#define SPLIT_SAMPLE 256 /* primitives a split tries its directions on, at most */
static const double split_dir[NDIR][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, -1, 0}};

/* partial sort of idx[0..n) by key[stride * idx + ax] so that idx[m] is in place */
static void select_nth(int *idx, int n, int m, const double *key, int stride, int ax)
{
    int lo = 0, hi = n - 1;
    while (hi > lo) {
        double piv = key[stride * idx[(lo + hi) / 2] + ax];
        int i = lo, j = hi;
        while (i <= j) {
            while (key[stride * idx[i] + ax] < piv) ++i;
            while (key[stride * idx[j] + ax] > piv) --j;
            if (i <= j) {
                int t = idx[i];
                idx[i] = idx[j], idx[j] = t;
                ++i, --j;
            }
        }
        if (m <= j) hi = j;
        else if (m >= i) lo = i;
        else break;
    }
}

/* area and perimeter of the rectangle lo[0..1]..hi[0..1] (x, y) with its
 * corners cut by the slabs lo[3] <= x + y <= hi[3], lo[4] <= x - y <=
 * hi[4] (what a node's box and slabs leave of the plane): each corner cut
 * is a right isosceles triangle, its legs clamped to the shorter side (an
 * estimate where two cuts overlap, which is all a split's cost needs) */
static void octagon(const double *lo, const double *hi, double *area, double *perim)
{
    double ex = dmax(hi[0] - lo[0], 0.0), ey = dmax(hi[1] - lo[1], 0.0), e = dmin(ex, ey);
    double t[4] = {lo[3] - (lo[0] + lo[1]), (hi[0] + hi[1]) - hi[3], lo[4] - (lo[0] - hi[1]), (hi[0] - lo[1]) - hi[4]};
    double A = ex * ey, L = 2.0 * (ex + ey);
    for (int k = 0; k < 4; ++k) {
        double d = dmin(dmax(t[k], 0.0), e);
        A -= 0.5 * d * d, L -= (2.0 - 1.4142135623730951) * d;
    }
    *area = dmax(A, 0.0), *perim = L;
}

/* the surface measure of two halves idx[0..m), idx[m..n): each half's
 * bound as a node has it (box and slabs, of its primitives' extents: an
 * octagonal prism) surface area over 2, times its primitives */
static double split_cost(const struct kin_contact *c, const int *idx, int n, int m)
{
    const double *cen = c->cen;
    double cost = 0.0;
    for (int h = 0; h < 2; ++h) {
        double lo[5] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY}, hi[5] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY};
        for (int q = h ? m : 0; q < (h ? n : m); ++q) {
            const double *x = cen + CEN * idx[q];
            for (int k = 0; k < 5; ++k) lo[k] = dmin(lo[k], x[NDIR + k]), hi[k] = dmax(hi[k], x[2 * NDIR + k]);
        }
        double A, L;
        octagon(lo, hi, &A, &L);
        cost += (A + 0.5 * L * (hi[2] - lo[2])) * (h ? n - m : m);
    }
    return cost;
}

/* a node's own directions (primitives idx[0 .. count), points
 * c->pts by joint number): dirs[0] along its parts (the sum of their
 * longest sides, each turned to agree with the sum so far), dirs[1] across
 * them in their plane (the sum of the triangles' normals, turned so too,
 * crossed with dirs[0]; 0 for bars alone). Unnormalized: only the order of
 * the projections matters */
static void node_dirs(const struct kin_contact *c, const int *idx, int count, double dirs[2][3])
{
    double sd[3] = {0, 0, 0}, nd[3] = {0, 0, 0};
    for (int q = 0; q < count; ++q) {
        const int *v = c->prim_v + 3 * idx[q];
        const double *A = c->pts + 3 * v[0], *B = c->pts + 3 * v[1];
        double e[3][3];
        int lk = 0;
        for (int k = 0; k < 3; ++k) e[0][k] = B[k] - A[k];
        if (v[2] >= 0) {
            const double *C = c->pts + 3 * v[2];
            for (int k = 0; k < 3; ++k) e[1][k] = C[k] - B[k], e[2][k] = A[k] - C[k];
            double n[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                           e[0][0] * e[1][1] - e[0][1] * e[1][0]};
            double sg = n[0] * nd[0] + n[1] * nd[1] + n[2] * nd[2] < 0.0 ? -1.0 : 1.0;
            for (int k = 0; k < 3; ++k) nd[k] += sg * n[k];
            double l0 = 0.0, l1 = 0.0, l2 = 0.0;
            for (int k = 0; k < 3; ++k) l0 += e[0][k] * e[0][k], l1 += e[1][k] * e[1][k], l2 += e[2][k] * e[2][k];
            lk = l0 >= l1 && l0 >= l2 ? 0 : (l1 >= l2 ? 1 : 2);
        }
        double sg = e[lk][0] * sd[0] + e[lk][1] * sd[1] + e[lk][2] * sd[2] < 0.0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; ++k) sd[k] += sg * e[lk][k];
    }
    for (int k = 0; k < 3; ++k) dirs[0][k] = sd[k];
    dirs[1][0] = nd[1] * sd[2] - nd[2] * sd[1];
    dirs[1][1] = nd[2] * sd[0] - nd[0] * sd[2];
    dirs[1][2] = nd[0] * sd[1] - nd[1] * sd[0];
}

/* the subtree of order[start .. start+count) into node *nn (split of
 * the box centres at the median, along whichever of x, y, z, x + y and
 * x - y gives the two halves the least summed surface measure); returns its
 * index. Boxes are set by refit. */
static int build(struct kin_contact *c, int start, int count, int *nn)
{
    int id = (*nn)++;
    kin__bvh_node *N = &c->node[id];
    N->start = start, N->count = count;
    if (count <= LEAF_MAX) {
        N->left = -1;
        N->right = c->nleaf++; /* its leaf block */
        return id;
    }
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int q = start; q < start + count; ++q) {
        const double *x = c->cen + CEN * c->order[q];
        for (int k = 0; k < 3; ++k) clo[k] = dmin(clo[k], x[k]), chi[k] = dmax(chi[k], x[k]);
    }
    int ax = 0;
    for (int k = 1; k < 3; ++k)
        if (chi[k] - clo[k] > chi[ax] - clo[ax]) ax = k;
    int half = count / 2;
    if (count > 2 * LEAF_MAX) half = (half + LEAF_MAX / 2) / LEAF_MAX * LEAF_MAX; /* full leaves on the left */
    /* the least surface measure among the fixed directions (the widest
     * first: it keeps ties) and the node's own two, tried on at most
     * SPLIT_SAMPLE of its primitives (every s-th) */
    int *w = c->scratch, *smp = c->scratch + count;
    int s = count / SPLIT_SAMPLE + 1, ns = (count + s - 1) / s, hs = (int)((long long)ns * half / count);
    for (int q = 0; q < ns; ++q) smp[q] = c->order[start + q * s];
    double best = INFINITY, dirs[2][3];
    int bax = ax;
    node_dirs(c, smp, ns, dirs);
    for (int k = 0; k < NDIR + 2; ++k) {
        int kk = k == 0 ? ax : (k <= ax ? k - 1 : k);
        if (kk >= NDIR) {
            const double *u = dirs[kk - NDIR];
            for (int q = 0; q < ns; ++q) {
                const double *C = c->cen + CEN * smp[q];
                c->skey[2 * smp[q] + kk - NDIR] = C[0] * u[0] + C[1] * u[1] + C[2] * u[2];
            }
        }
        memcpy(w, smp, sizeof(int) * (size_t)ns);
        if (kk < NDIR) select_nth(w, ns, hs, c->cen, CEN, kk);
        else select_nth(w, ns, hs, c->skey, 2, kk - NDIR);
        double cost = split_cost(c, w, ns, hs);
        if (cost < best) best = cost, bax = kk;
    }
    if (bax < NDIR) select_nth(c->order + start, count, half, c->cen, CEN, bax);
    else {
        const double *u = dirs[bax - NDIR];
        for (int q = start; q < start + count; ++q) {
            const double *C = c->cen + CEN * c->order[q];
            c->skey[2 * c->order[q] + bax - NDIR] = C[0] * u[0] + C[1] * u[1] + C[2] * u[2];
        }
        select_nth(c->order + start, count, half, c->skey, 2, bax - NDIR);
    }
    int l = build(c, start, half, nn);
    int r = build(c, start + half, count - half, nn);
    N = &c->node[id];
    N->left = l, N->right = r;
    return id;
}

/* c->pts from the configuration xyz (njoints*dim): joint j at its tree
 * position jpos[j] (tree = 1), or at j (tree = 0) */
static void load_points(const kin_assembly *a, struct kin_contact *c, const double *xyz, int tree)
{
    int dim = a->dim;
    for (int j = 0; j < a->nj; ++j) {
        double *x = c->pts + 3 * (tree ? c->jpos[j] : j);
        for (int k = 0; k < 3; ++k) x[k] = k < dim ? xyz[j * dim + k] : 0.0;
    }
}

/* A new tree for the configuration xyz: topology (order, node), the joints
 * numbered in the order the leaves first use them (jpos), the leaves in tree
 * order (lp, lr); c->pts is left in tree order. Boxes: refit. */
static void tree_build(const kin_assembly *a, struct kin_contact *c, const double *xyz)
{
    load_points(a, c, xyz, 0);
    for (int p = 0; p < c->nprim; ++p) {
        const int *v = c->prim_v + 3 * p;
        int nv = v[2] >= 0 ? 3 : 2;
        double *C = c->cen + CEN * p, r = c->prim_r[p];
        for (int k = 0; k < NDIR; ++k) {
            double lo = INFINITY, hi = -INFINITY;
            const double *u = split_dir[k];
            for (int q = 0; q < nv; ++q) {
                const double *x = c->pts + 3 * v[q];
                double t = x[0] * u[0] + x[1] * u[1] + x[2] * u[2];
                lo = dmin(lo, t), hi = dmax(hi, t);
            }
            double rr = r * sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
            C[k] = 0.5 * lo + 0.5 * hi;
            C[NDIR + k] = lo - rr, C[2 * NDIR + k] = hi + rr;
        }
        c->order[p] = p;
    }
    int nn = 0;
    c->nleaf = 0;
    build(c, 0, c->nprim, &nn);
    c->nnode = nn;
    for (int j = 0; j < a->nj; ++j) c->jpos[j] = -1;
    int next = 0;
    for (int q = 0; q < c->nprim; ++q) {
        const int *v = c->prim_v + 3 * c->order[q];
        for (int k = 0; k < 3; ++k)
            if (v[k] >= 0 && c->jpos[v[k]] < 0) c->jpos[v[k]] = next++;
    }
    for (int j = 0; j < a->nj; ++j)
        if (c->jpos[j] < 0) c->jpos[j] = next++;
    c->rmax = 0.0;
    for (int q = 0; q < c->nprim; ++q) {
        int p = c->order[q];
        kin__leafprim *L = &c->lp[q];
        const int *v = c->prim_v + 3 * p;
        for (int k = 0; k < 3; ++k) L->v[k] = v[k] >= 0 ? c->jpos[v[k]] : -1;
        L->part = c->prim_part[p];
        L->own = L->part < a->nb || c->poff[L->part - a->nb + 1] - c->poff[L->part - a->nb] == 3;
        c->lr[q] = c->prim_r[p];
        L->r = f_up(c->prim_r[p]);
        c->rmax = dmax(c->rmax, c->prim_r[p]);
    }
    for (int id = 0; id < c->nnode; ++id) {
        const kin__bvh_node *N = &c->node[id];
        if (N->left >= 0) continue;
        kin__leafsoa *S = &c->leaf[N->right];
        for (int i = 0; i < LEAF_MAX; ++i) {
            const int *v = i < N->count ? c->lp[N->start + i].v : NULL;
            for (int k = 0; k < 3; ++k) S->v[k][i] = v ? (v[k] >= 0 ? v[k] : v[1]) : -1;
            for (int k = 0; k < 5; ++k) S->lo[k][i] = FLT_MAX, S->hi[k][i] = -FLT_MAX;
            for (int q = 0; q < 3; ++q)
                for (int k = 0; k < 3; ++k) S->p[q][k][i] = 0.0f;
            S->r[i] = v ? c->lp[N->start + i].r : 0.0f;
        }
    }
    load_points(a, c, xyz, 1);
    c->seed[0] = c->seed[1] = -1;
    c->ax_next = -1; /* every leaf's axis made at the refit */
    memset(c->ax_call, 0, sizeof(unsigned) * (size_t)c->nprim); /* tree positions renumbered */
    c->tree_ok = 1;
    c->fresh = 1;
    c->vl_ok = 0; /* the list names leaves of the old tree */
    c->vl_nocut = INFINITY;
}

/* The slabs across x + y and x - y of a leaf's count lanes (see
 * diag_lanes), from their points and radii in float, 4 lanes at once; folded
 * into the node's lo[3..4], hi[3..4]. Rounding: the points are within
 * 2^-24 of the doubles (relative), and the sum, the radius term r sqrt 2
 * (r rounded up, the constant above sqrt 2) and the two differences each
 * round by 2^-24 relative to |x| + |y| + r sqrt 2 at most: a slack of 2^-20
 * of that (and 2^-130 for subnormal points) keeps the slabs outward. Points
 * beyond the float range give inf or NaN bounds, which no test drops. */
#if defined(__SSE2__)
static void leaf_slabs(kin__leafsoa *S, int count, float *lo, float *hi)
{
    const __m128 sq2 = _mm_set1_ps(1.4142136f), eps = _mm_set1_ps(0x1p-20f), tiny = _mm_set1_ps(0x1p-130f);
    const __m128 sign = _mm_set1_ps(-0.0f);
    for (int h = 0; h < LEAF_MAX; h += 4) {
        __m128 rs = _mm_mul_ps(_mm_loadu_ps(S->r + h), sq2), big = _mm_setzero_ps();
        __m128 l[2], u[2];
        for (int q = 0; q < 3; ++q) {
            __m128 x = _mm_loadu_ps(S->p[q][0] + h), y = _mm_loadu_ps(S->p[q][1] + h);
            __m128 a = _mm_add_ps(x, y), b = _mm_sub_ps(x, y);
            big = _mm_max_ps(big, _mm_add_ps(_mm_andnot_ps(sign, x), _mm_andnot_ps(sign, y)));
            l[0] = q ? _mm_min_ps(l[0], a) : a, u[0] = q ? _mm_max_ps(u[0], a) : a;
            l[1] = q ? _mm_min_ps(l[1], b) : b, u[1] = q ? _mm_max_ps(u[1], b) : b;
        }
        __m128 pad = _mm_add_ps(rs, _mm_add_ps(_mm_mul_ps(eps, _mm_add_ps(big, rs)), tiny));
        const __m128 ninf = _mm_set1_ps(-INFINITY), pinf = _mm_set1_ps(INFINITY);
        for (int d = 0; d < 2; ++d) { /* NaN (inf - inf): the whole line */
            __m128 a = _mm_sub_ps(l[d], pad), b = _mm_add_ps(u[d], pad);
            __m128 oka = _mm_cmpord_ps(a, a), okb = _mm_cmpord_ps(b, b);
            _mm_storeu_ps(S->lo[3 + d] + h, _mm_or_ps(_mm_and_ps(oka, a), _mm_andnot_ps(oka, ninf)));
            _mm_storeu_ps(S->hi[3 + d] + h, _mm_or_ps(_mm_and_ps(okb, b), _mm_andnot_ps(okb, pinf)));
        }
    }
    for (int i = 0; i < LEAF_MAX; ++i)
        for (int d = 3; d < 5; ++d) {
            if (i >= count) S->lo[d][i] = FLT_MAX, S->hi[d][i] = -FLT_MAX;
            lo[d] = S->lo[d][i] < lo[d] ? S->lo[d][i] : lo[d], hi[d] = S->hi[d][i] > hi[d] ? S->hi[d][i] : hi[d];
        }
}
#else
static void leaf_slabs(kin__leafsoa *S, int count, float *lo, float *hi)
{
    for (int i = 0; i < LEAF_MAX; ++i) {
        float rs = S->r[i] * 1.4142136f, big = 0.0f, l[2] = {INFINITY, INFINITY}, u[2] = {-INFINITY, -INFINITY};
        for (int q = 0; q < 3; ++q) {
            float x = S->p[q][0][i], y = S->p[q][1][i], a = x + y, b = x - y, m = fabsf(x) + fabsf(y);
            big = m > big ? m : big;
            l[0] = a < l[0] ? a : l[0], u[0] = a > u[0] ? a : u[0], l[1] = b < l[1] ? b : l[1], u[1] = b > u[1] ? b : u[1];
        }
        float pad = rs + (0x1p-20f * (big + rs) + 0x1p-130f);
        for (int d = 0; d < 2; ++d) {
            float a = l[d] - pad, b = u[d] + pad; /* NaN (inf - inf): the whole line */
            a = a == a ? a : -INFINITY, b = b == b ? b : INFINITY;
            S->lo[3 + d][i] = i < count ? a : FLT_MAX, S->hi[3 + d][i] = i < count ? b : -FLT_MAX;
            lo[3 + d] = S->lo[3 + d][i] < lo[3 + d] ? S->lo[3 + d][i] : lo[3 + d];
            hi[3 + d] = S->hi[3 + d][i] > hi[3 + d] ? S->hi[3 + d][i] : hi[3 + d];
        }
    }
}
#endif

/* The leaf's own axis w (see kin__leafsoa) from its count lanes' float
 * points: across the sum of the primitives' longest sides (each turned to
 * agree with the sum so far), in the plane normal to the sum of their
 * triangles' normals (turned alike); for bars alone, or where those are
 * parallel, any direction across the sides. A degenerate leaf gets w = 0,
 * which separates nothing. Any axis gives the same answer (the test only
 * drops pairs its bound shows apart): this is about speed only. */
static void leaf_axis(kin__leafsoa *S, int count)
{
    double ns[3] = {0, 0, 0}, ls[3] = {0, 0, 0}, w[3];
    for (int i = 0; i < count; ++i) {
        double P[3][3], e[3][3], n[3];
        for (int q = 0; q < 3; ++q)
            for (int k = 0; k < 3; ++k) P[q][k] = S->p[q][k][i];
        for (int k = 0; k < 3; ++k) e[0][k] = P[1][k] - P[0][k], e[1][k] = P[2][k] - P[1][k], e[2][k] = P[0][k] - P[2][k];
        int m = 0;
        double mm = -1.0;
        for (int q = 0; q < 3; ++q) {
            double l2 = e[q][0] * e[q][0] + e[q][1] * e[q][1] + e[q][2] * e[q][2];
            if (l2 > mm) mm = l2, m = q;
        }
        double sl = e[m][0] * ls[0] + e[m][1] * ls[1] + e[m][2] * ls[2] < 0.0 ? -1.0 : 1.0;
        n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
        n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
        n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
        double sn = n[0] * ns[0] + n[1] * ns[1] + n[2] * ns[2] < 0.0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; ++k) ls[k] += sl * e[m][k], ns[k] += sn * n[k];
    }
    w[0] = ns[1] * ls[2] - ns[2] * ls[1];
    w[1] = ns[2] * ls[0] - ns[0] * ls[2];
    w[2] = ns[0] * ls[1] - ns[1] * ls[0];
    double nw = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), nl = sqrt(ls[0] * ls[0] + ls[1] * ls[1] + ls[2] * ls[2]);
    if (!(nw > 1e-6 * nl * sqrt(ns[0] * ns[0] + ns[1] * ns[1] + ns[2] * ns[2]))) {
        /* no plane: across the sides, normal to their smallest coordinate axis */
        double z[3] = {0, 0, 0};
        int m = fabs(ls[0]) <= fabs(ls[1]) ? (fabs(ls[0]) <= fabs(ls[2]) ? 0 : 2) : (fabs(ls[1]) <= fabs(ls[2]) ? 1 : 2);
        z[m] = 1.0;
        w[0] = ls[1] * z[2] - ls[2] * z[1], w[1] = ls[2] * z[0] - ls[0] * z[2], w[2] = ls[0] * z[1] - ls[1] * z[0];
        nw = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    int ok = nw > 0.0 && isfinite(nw);
    for (int k = 0; k < 3; ++k) S->w[k] = ok ? (float)(w[k] / nw) : 0.0f;
    S->w[3] = 0.0f;
}

/* each lane's interval on the leaf's axis w over its float points (lanes
 * past count: empty). Rounding: as apart_lanes (lanes.h: the slack of the
 * walk). */
static void leaf_orient(kin__leafsoa *S, int count)
{
    project_lanes(S, S->w, S->olo, S->ohi);
    for (int i = count; i < LEAF_MAX; ++i) S->olo[i] = FLT_MAX, S->ohi[i] = -FLT_MAX;
}

/* The boxes of the leaves and nodes at the configuration c->pts, bottom up
 * (nodes are in pre-order). Returns the tree's quality measure: the summed
 * half surface areas of the node boxes over the root's (it grows as the
 * configuration moves away from the one the tree was built for; 0 for a
 * degenerate root). */
static double refit(struct kin_contact *c)
{
    const double *P = c->pts;
    double sum = 0.0;
    /* the leaves' axes: all after a build, else an eighth of them anew per
     * call, in turn (they follow the configuration at little cost) */
    int a0 = c->ax_next, a1 = a0 < 0 ? c->nleaf : a0 + c->nleaf / 8 + 1;
    if (a0 < 0) a0 = 0;
    c->ax_next = a1 >= c->nleaf ? 0 : a1;
    for (int id = c->nnode - 1; id >= 0; --id) {
        kin__bvh_node *N = &c->node[id];
        float lo[5] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
        float hi[5] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY, -INFINITY};
        if (N->left < 0) {
            /* its primitives' boxes (a bar's third joint is its second) */
            kin__leafsoa *S = &c->leaf[N->right];
            const double *r = c->lr + N->start;
            for (int i = 0; i < N->count; ++i) {
                const double *x = P + 3 * S->v[0][i], *y = P + 3 * S->v[1][i], *z = P + 3 * S->v[2][i];
                for (int k = 0; k < 3; ++k) S->p[0][k][i] = (float)x[k], S->p[1][k][i] = (float)y[k], S->p[2][k][i] = (float)z[k];
                for (int k = 0; k < 3; ++k) {
                    float l = f_down(dmin(dmin(x[k], y[k]), z[k]) - r[i]);
                    float h = f_up(dmax(dmax(x[k], y[k]), z[k]) + r[i]);
                    S->lo[k][i] = l, S->hi[k][i] = h;
                    lo[k] = l < lo[k] ? l : lo[k], hi[k] = h > hi[k] ? h : hi[k];
                }
            }
            leaf_slabs(S, N->count, lo, hi);
            if (N->right >= a0 && N->right < a1) leaf_axis(S, N->count);
            leaf_orient(S, N->count);
        } else {
            const kin__bvh_node *A = &c->node[N->left], *B = &c->node[N->right];
            for (int k = 0; k < 5; ++k)
                lo[k] = A->lo[k] < B->lo[k] ? A->lo[k] : B->lo[k], hi[k] = A->hi[k] > B->hi[k] ? A->hi[k] : B->hi[k];
        }
        double e[3];
        for (int k = 0; k < 5; ++k) N->lo[k] = lo[k], N->hi[k] = hi[k];
        for (int k = 0; k < 3; ++k) e[k] = dmax((double)hi[k] - lo[k], 0.0);
        sum += e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    }
    const kin__bvh_node *R = &c->node[0];
    double e[3];
    for (int k = 0; k < 3; ++k) e[k] = dmax((double)R->hi[k] - R->lo[k], 0.0);
    double root = e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
    return root > 0.0 && isfinite(sum) ? sum / root : 0.0;
}

void kin__tree_fit(const kin_assembly *a, struct kin_contact *c, const double *xyz)
{
    if (!c->tree_ok) tree_build(a, c, xyz);
    else load_points(a, c, xyz, 1);
    /* refit the tree to this configuration; build it again when the
     * configuration has moved so far from the one it was built for that its
     * boxes have grown by half (any tree gives the same answer: this is
     * only about speed) */
    double quality = refit(c);
    if (c->fresh) c->quality0 = quality, c->fresh = 0;
    else if (quality > 1.5 * c->quality0) {
        tree_build(a, c, xyz);
        c->quality0 = refit(c);
        c->fresh = 0;
    }
}
