/* Panels, thicknesses and the clearance between parts (kin_contact.h,
 * docs/contact.md).
 *
 * The clearance: every bar is one primitive (a segment), every panel the
 * fan of its triangles; each primitive's box is grown by its radius. A
 * bounding-volume tree (split at the median, moved to a multiple of 8 so
 * that the leaves are full, of the box centres along whichever of x, y, z,
 * x + y, x - y and the node's own two directions, along its parts and
 * across them, gives the two halves the least surface measure) is built at the first call and then refitted to each configuration
 * (O(n): the boxes bottom up, the topology kept), and built again only when
 * the refitted boxes have grown by half against those right after its
 * build. Primitives and joints are stored in tree order and boxes as floats
 * rounded outward (24 bytes per primitive, an 816-byte block of 8 lanes per
 * leaf, 56 bytes per node), so the walk reads contiguous memory; leaves and
 * nodes also carry the slabs across x + y and x - y, and each leaf its own
 * axis across its parts (in their plane) with its lanes' intervals on it. The tree is walked
 * against itself, pairs of nodes nearer first, a pair dropped when its
 * boxes or slabs are no nearer than the best clearance found so far (the
 * last call's closest pair, evaluated first, gives that bound from the
 * start); two leaves are tested a row at a time, 8 lanes at once without a
 * branch per pair (boxes, shared joints, then for the pairs left the
 * first leaf's axis, the slabs, the line of the box centres and the row
 * primitive's own axes),
 * and the pairs left of parts that share no joint get the separating-axis
 * bound and the exact test of distance.c. A check with a cutoff lists the
 * leaf pairs its walk meets (with a skin for each leaf) and later checks
 * test only those while no leaf has moved more than its skin (the
 * near-pair list, near_list_holds). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/contact_internal.h"

#if defined(__SSE2__)
#include <emmintrin.h> /* the leaf tests (every x86-64 has SSE2) */
#endif

#define LEAF_MAX KIN__LEAF_MAX
/* a leaf's skin in the near-pair list at most, a fraction of its box's
 * largest side (see near_list_skins) */
#define NEAR_SKIN_MAX 0.4
/* the split's fixed directions: x, y, z and the slabs' x + y, x - y */
#define NDIR 5
#define CEN (3 * NDIR) /* doubles per primitive in cen */
#define SPLIT_SAMPLE 256 /* primitives a split tries its directions on, at most */
static const double split_dir[NDIR][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, -1, 0}};

static inline double dmin(double x, double y) { return x < y ? x : y; }
static inline double dmax(double x, double y) { return x > y ? x : y; }

static void ct_release(struct kin_contact *c)
{
    if (!c) return;
    free(c->poff), free(c->pj), free(c->rbar), free(c->tpan);
    free(c->prim_part), free(c->prim_v), free(c->prim_r), free(c->cen), free(c->scratch), free(c->skey), free(c->lr), free(c->jpos);
    free(c->order), free(c->node), free(c->lp), free(c->leaf), free(c->ev_prev), free(c->ev_x), free(c->ev_xyz), free(c->stack), free(c->sgap), free(c->pts);
    free(c->ev_box), free(c->ev_key), free(c->ax), free(c->ax_call), free(c->vl), free(c->vl_x0), free(c->vl_sk), free(c->vl_dl), free(c->vl_dj);
    free(c);
}

static void ct_free(kin_assembly *a)
{
    ct_release(a->ct);
    a->ct = NULL;
}

/* the clearance workspace of model (np, poff) on handle a, into c */
static int ct_workspace(const kin_assembly *a, struct kin_contact *c)
{
    int ntri = 0;
    for (int i = 0; i < c->np; ++i) ntri += c->poff[i + 1] - c->poff[i] - 2;
    int n = a->nb + ntri;
    c->nprim = n;
    /* tree depth <= log2(n) + 2 (each split within 4 of the median, and
     * 16 or fewer primitives split into two leaves: checked for every n up
     * to 200,000); the pair walk keeps at most 3 entries per level of each
     * tree, plus the root pair */
    int depth = 2;
    while ((1 << (depth - 2)) < n && depth < 62) ++depth;
    c->stack_cap = 8 * depth + 16;
    size_t N = (size_t)n;
    c->prim_part = malloc(sizeof(int) * N);
    c->prim_v = malloc(sizeof(int) * 3 * N);
    c->prim_r = malloc(sizeof(double) * N);
    c->cen = malloc(sizeof(double) * CEN * N);
    c->scratch = malloc(sizeof(int) * 2 * (N ? N : 1));
    c->skey = malloc(sizeof(double) * 2 * (N ? N : 1));
    c->lr = malloc(sizeof(double) * (N ? N : 1));
    c->jpos = malloc(sizeof(int) * ((size_t)a->nj + 1));
    c->order = malloc(sizeof(int) * N);
    /* a split node has more than LEAF_MAX primitives, so every leaf of a
     * tree of more than LEAF_MAX has at least (LEAF_MAX + 1) / 2: at most
     * N / that leaves, and one fewer inner nodes */
    c->node = malloc(sizeof(kin__bvh_node) * (2 * (N / ((LEAF_MAX + 1) / 2) + 1)));
    c->lp = malloc(sizeof(kin__leafprim) * (N ? N : 1));
    c->leaf = malloc(sizeof(kin__leafsoa) * (N / ((LEAF_MAX + 1) / 2) + 1));
    c->stack = malloc(sizeof(int) * 2 * (size_t)c->stack_cap);
    c->sgap = malloc(sizeof(double) * (size_t)c->stack_cap);
    c->ax = malloc(sizeof(float) * 5 * KIN__OWN_AXES * (N ? N : 1));
    c->ax_call = calloc(N ? N : 1, sizeof(unsigned));
    c->call = 0;
    c->pts = malloc(sizeof(double) * 3 * (size_t)a->nj);
    /* the near-pair list: 16 leaf pairs a leaf (a sheet's leaf meets
     * a handful); a walk that meets more makes no list */
    c->vl_cap = 16 * (int)(N / ((LEAF_MAX + 1) / 2) + 1);
    c->vl_nocut = INFINITY;
    c->vl = malloc(sizeof(int) * 2 * (size_t)c->vl_cap);
    c->vl_x0 = malloc(sizeof(double) * 3 * ((size_t)a->nj + 1));
    c->vl_sk = malloc(sizeof(double) * (2 * (N / ((LEAF_MAX + 1) / 2) + 1)));
    c->vl_dl = malloc(sizeof(double) * (2 * (N / ((LEAF_MAX + 1) / 2) + 1)));
    c->vl_dj = malloc(sizeof(double) * ((size_t)a->nj + 1));
    c->ev_prev = malloc(sizeof(double) * ((size_t)a->nf + 1));
    c->ev_x = malloc(sizeof(double) * (2 * (size_t)a->nf + 1));
    c->ev_xyz = malloc(sizeof(double) * 2 * (size_t)a->nj * (size_t)a->dim);
    c->ev_box = malloc(sizeof(double) * 6 * ((size_t)a->nb + 1));
    c->ev_key = malloc(sizeof(kin__sweepkey) * ((size_t)a->nb + 1));
    c->ev_pair[0] = c->ev_pair[1] = -1;
    c->ev_tol = 1e-9;
    if (!c->prim_part || !c->prim_v || !c->prim_r || !c->cen || !c->scratch || !c->skey || !c->lr || !c->jpos || !c->order || !c->node || !c->lp || !c->leaf ||
        !c->stack || !c->sgap || !c->ax || !c->ax_call || !c->pts || !c->vl || !c->vl_x0 || !c->vl_sk || !c->vl_dl || !c->vl_dj || !c->ev_prev || !c->ev_x || !c->ev_xyz || !c->ev_box || !c->ev_key)
        return KIN_ENOMEM;
    int p = 0;
    for (int k = 0; k < a->nb; ++k, ++p) {
        c->prim_part[p] = k;
        c->prim_v[3 * p] = a->bars[2 * k];
        c->prim_v[3 * p + 1] = a->bars[2 * k + 1];
        c->prim_v[3 * p + 2] = -1;
    }
    for (int i = 0; i < c->np; ++i) {
        const int *j = c->pj + c->poff[i];
        for (int q = 1; q + 1 < c->poff[i + 1] - c->poff[i]; ++q, ++p) {
            c->prim_part[p] = a->nb + i;
            c->prim_v[3 * p] = j[0];
            c->prim_v[3 * p + 1] = j[q];
            c->prim_v[3 * p + 2] = j[q + 1];
        }
    }
    return KIN_OK;
}

/* the radius of each primitive from the thicknesses */
static void ct_radii(const kin_assembly *a, struct kin_contact *c)
{
    for (int p = 0; p < c->nprim; ++p) {
        int part = c->prim_part[p];
        double r;
        if (part < a->nb) r = c->rbar && c->rbar[part] >= 0.0 ? c->rbar[part] : 0.5 * c->t0;
        else {
            double t = c->tpan && c->tpan[part - a->nb] >= 0.0 ? c->tpan[part - a->nb] : c->t0;
            r = 0.5 * t;
        }
        c->prim_r[p] = r;
    }
    c->tree_ok = 0; /* the leaves carry the radii: build again */
}

/* a new contact record: model (np, poff, pj, t0, rbar, tpan) copied, the
 * workspace made */
static int ct_make(const kin_assembly *a, int np, const int *poff, const int *pj, double t0, const double *rbar,
                   const double *tpan, struct kin_contact **out)
{
    struct kin_contact *c = calloc(1, sizeof *c);
    if (!c) return KIN_ENOMEM;
    size_t nj = np > 0 ? (size_t)poff[np] : 0;
    c->np = np;
    c->t0 = t0;
    c->poff = malloc(sizeof(int) * ((size_t)np + 1));
    c->pj = malloc(sizeof(int) * (nj ? nj : 1));
    c->rbar = malloc(sizeof(double) * (size_t)a->nb);
    c->tpan = malloc(sizeof(double) * (np ? (size_t)np : 1));
    if (!c->poff || !c->pj || !c->rbar || !c->tpan) {
        ct_release(c);
        return KIN_ENOMEM;
    }
    c->poff[0] = 0;
    if (np) memcpy(c->poff, poff, sizeof(int) * ((size_t)np + 1));
    if (nj) memcpy(c->pj, pj, sizeof(int) * nj);
    for (int k = 0; k < a->nb; ++k) c->rbar[k] = rbar ? rbar[k] : -1.0;
    for (int i = 0; i < np; ++i) c->tpan[i] = tpan ? tpan[i] : -1.0;
    if (ct_workspace(a, c) != KIN_OK) {
        ct_release(c);
        return KIN_ENOMEM;
    }
    ct_radii(a, c);
    *out = c;
    return KIN_OK;
}

static int ct_clone(kin_assembly *dst, const kin_assembly *src)
{
    const struct kin_contact *s = src->ct;
    struct kin_contact *c;
    int rc = ct_make(dst, s->np, s->poff, s->pj, s->t0, s->rbar, s->tpan, &c);
    if (rc) return rc;
    c->ev_on = s->ev_on, c->ev_tol = s->ev_tol;
    if (dst->ct_free) dst->ct_free(dst);
    dst->ct = c;
    dst->ct_free = ct_free;
    dst->ct_clone = ct_clone;
    return KIN_OK;
}

static void ct_install(kin_assembly *a, struct kin_contact *c)
{
    if (a->ct) c->ev_on = a->ct->ev_on, c->ev_tol = a->ct->ev_tol; /* the event setting stays */
    if (a->ct) ct_release(a->ct);
    a->ct = c;
    a->ct_free = ct_free;
    a->ct_clone = ct_clone;
}

int kin__contact_ensure(kin_assembly *a)
{
    if (a->ct) return KIN_OK;
    struct kin_contact *c;
    int zero = 0;
    int rc = ct_make(a, 0, &zero, NULL, 0.0, NULL, NULL, &c);
    if (rc) return kin__fail(a, rc, "clearance workspace for %d bars", a->nb);
    ct_install(a, c);
    return KIN_OK;
}

/* ---- the public calls --------------------------------------------------- */

static int cmp_int(const void *p, const void *q)
{
    int x = *(const int *)p, y = *(const int *)q;
    return (x > y) - (x < y);
}

int kin_set_panels(kin_assembly *a, int np, const int *offsets, const int *joints)
{
    if (!a) return KIN_ENULL;
    if (np < 0) return kin__fail(a, KIN_EINVAL, "npanels %d < 0", np);
    if (np > 0 && (!offsets || !joints)) return kin__fail(a, KIN_ENULL, "panel offsets or joints is NULL");
    if (np > 0 && offsets[0] != 0) return kin__fail(a, KIN_EINVAL, "offsets[0] = %d, not 0", offsets[0]);
    int sorted[KIN_PANEL_MAX_JOINTS];
    for (int i = 0; i < np; ++i) {
        long len = (long)offsets[i + 1] - offsets[i];
        if (len < 3 || len > KIN_PANEL_MAX_JOINTS)
            return kin__fail(a, KIN_EINVAL, "panel %d has %ld joints (3..%d)", i, len, KIN_PANEL_MAX_JOINTS);
        for (int q = 0; q < len; ++q) {
            int j = joints[offsets[i] + q];
            if (j < 0 || j >= a->nj)
                return kin__fail(a, KIN_EJOINT, "panel %d: joint %d out of range 0..%d", i, j, a->nj - 1);
            sorted[q] = j;
        }
        qsort(sorted, (size_t)len, sizeof(int), cmp_int);
        for (int q = 1; q < len; ++q)
            if (sorted[q] == sorted[q - 1])
                return kin__fail(a, KIN_EINVAL, "panel %d: joint %d repeated", i, sorted[q]);
    }
    struct kin_contact *c;
    double t0 = a->ct ? a->ct->t0 : 0.0;
    int zero = 0;
    int rc = ct_make(a, np, np ? offsets : &zero, joints, t0, a->ct ? a->ct->rbar : NULL, NULL, &c);
    if (rc) return kin__fail(a, rc, "panels and clearance workspace");
    ct_install(a, c);
    return KIN_OK;
}

int kin_npanels(const kin_assembly *a) { return a ? (a->ct ? a->ct->np : 0) : -1; }

int kin_get_panels(const kin_assembly *a, int *offsets, int *joints)
{
    if (!a) return KIN_ENULL;
    int np = a->ct ? a->ct->np : 0;
    if (offsets) {
        if (np) memcpy(offsets, a->ct->poff, sizeof(int) * ((size_t)np + 1));
        else offsets[0] = 0;
    }
    if (joints && np) memcpy(joints, a->ct->pj, sizeof(int) * (size_t)a->ct->poff[np]);
    return KIN_OK;
}

static int bad_thickness(double t) { return !isfinite(t) || t > 1e150; }

int kin_set_thickness(kin_assembly *a, double t0, const double *rbar, const double *tpan)
{
    if (!a) return KIN_ENULL;
    if (bad_thickness(t0) || t0 < 0.0) return kin__fail(a, KIN_EGEOM, "default thickness %g", t0);
    for (int k = 0; rbar && k < a->nb; ++k)
        if (bad_thickness(rbar[k])) return kin__fail(a, KIN_EGEOM, "bar %d: radius %g", k, rbar[k]);
    int np = a->ct ? a->ct->np : 0;
    for (int i = 0; tpan && i < np; ++i)
        if (bad_thickness(tpan[i])) return kin__fail(a, KIN_EGEOM, "panel %d: thickness %g", i, tpan[i]);
    int rc = kin__contact_ensure(a);
    if (rc) return rc;
    struct kin_contact *c = a->ct;
    c->t0 = t0;
    for (int k = 0; k < a->nb; ++k) c->rbar[k] = rbar ? (rbar[k] < 0.0 ? -1.0 : rbar[k]) : -1.0;
    for (int i = 0; i < np; ++i) c->tpan[i] = tpan ? (tpan[i] < 0.0 ? -1.0 : tpan[i]) : -1.0;
    ct_radii(a, c);
    return KIN_OK;
}

int kin_get_thickness(const kin_assembly *a, double *t0, double *rbar, double *tpan)
{
    if (!a) return KIN_ENULL;
    const struct kin_contact *c = a->ct;
    double t = c ? c->t0 : 0.0;
    if (t0) *t0 = t;
    for (int k = 0; rbar && k < a->nb; ++k) rbar[k] = c && c->rbar[k] >= 0.0 ? c->rbar[k] : 0.5 * t;
    for (int i = 0; c && tpan && i < c->np; ++i) tpan[i] = c->tpan[i] >= 0.0 ? c->tpan[i] : t;
    return KIN_OK;
}

int kin_has_contact_model(const kin_assembly *a)
{
    if (!a) return -1;
    const struct kin_contact *c = a->ct;
    if (!c) return 0;
    if (c->np > 0 || c->t0 > 0.0) return 1;
    for (int k = 0; k < a->nb; ++k)
        if (c->rbar[k] > 0.0) return 1;
    return 0;
}

int kin_set_contact_events(kin_assembly *a, int on, double tol)
{
    if (!a) return KIN_ENULL;
    if (!(tol > 0.0 && tol <= 1.0)) return kin__fail(a, KIN_EINVAL, "contact location tolerance %g not in (0, 1]", tol);
    int rc = kin__contact_ensure(a);
    if (rc) return rc;
    a->ct->ev_on = on != 0;
    a->ct->ev_tol = tol;
    a->ct->ev_have = 0;
    return KIN_OK;
}

int kin_last_contact(const kin_assembly *a, double *clearance, int *parts, double *points, double *bracket)
{
    if (!a) return KIN_ENULL;
    const struct kin_contact *c = a->ct;
    if (!c || !c->ev_have) return KIN_ESTATE;
    if (clearance) *clearance = c->ev_clearance;
    if (parts) memcpy(parts, c->ev_parts, sizeof c->ev_parts);
    if (points) memcpy(points, c->ev_points, sizeof(double) * 2 * (size_t)a->dim);
    if (bracket) *bracket = c->ev_bracket;
    return KIN_OK;
}

/* ---- the tree ----------------------------------------------------------- */

/* A double bound rounded outward to float: lo down, hi up. The slack
 * (2^-23 relative, 2^-140 absolute) is more than the rounding to nearest of
 * the conversion and of the double arithmetic before it; the clamp keeps a
 * bound beyond the float range on its own side (lo <= FLT_MAX, hi >=
 * -FLT_MAX), so box gaps are never inf - inf. */
static inline float f_down(double x) { return (float)dmin(x - fabs(x) * 0x1p-23 - 0x1p-140, FLT_MAX); }
static inline float f_up(double x) { return (float)dmax(x + fabs(x) * 0x1p-23 + 0x1p-140, -FLT_MAX); }

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
 * past count: empty). Rounding: as apart_lanes (the slack of the walk). */
static inline void project_lanes(const kin__leafsoa *S, const float *w, float *lo, float *hi);
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

/* gap2: squared gap of two float boxes (0 when they meet), in double: a
 * lower bound of the squared distance of anything inside them. gap2_node:
 * of two nodes, with their slabs across x + y and x - y too: the larger of
 * that and a slab's squared gap over 2 (the slabs are projections on
 * vectors of length sqrt 2) */
static inline double gap2(const float *alo, const float *ahi, const float *blo, const float *bhi)
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        double g = dmax((double)alo[k] - bhi[k], (double)blo[k] - ahi[k]);
        if (g > 0.0) s += g * g;
    }
    return s;
}
static inline double gap2_node(const kin__bvh_node *A, const kin__bvh_node *B)
{
    double s = gap2(A->lo, A->hi, B->lo, B->hi);
    for (int k = 3; k < 5; ++k) {
        double g = dmax((double)A->lo[k] - B->hi[k], (double)B->lo[k] - A->hi[k]);
        if (g > 0.0) s = dmax(s, 0.5 * g * g);
    }
    return s;
}

/* 1 if a pair in boxes s2 (squared gap) apart cannot have clearance at or
 * below best (a tie is kept: ties go to the smallest pair of parts, then
 * of primitives, so
 * the answer does not depend on the order of the walk): boxes apart by
 * g > 0 give clearance >= g; boxes that meet give clearance >= neg */
static inline int cannot_beat(double s2, double neg, double best)
{
    if (s2 > 0.0) return best < 0.0 || s2 > best * best * (1.0 + 0x1p-40);
    return neg > best;
}

/* The leaf tests in straight-line code (no branch per pair: a walk over
 * thousands of leaf pairs, each pair's outcome different, is more than a
 * branch predictor can learn). near_lanes: bit i set unless lane i's box is
 * more than T apart from box (lo, hi) along some axis, in float: a superset
 * of the pairs the exact test (cannot_beat of gap2, in double) keeps, for T
 * = near_bound(best) (rounding to float is monotone, and T is above the
 * largest axis gap that test keeps); NaN differences (none arise: boxes are
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
    for (int h = 0; h < LEAF_MAX; h += 4) {
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
    for (int h = 0; h < LEAF_MAX; h += 4) {
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
    for (int h = 0; h < LEAF_MAX; h += 4) {
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
    for (int i = 0; i < LEAF_MAX; ++i) {
        int far = 0;
        for (int k = 0; k < 3; ++k) far |= (S->lo[k][i] - hi[k] > T) | (lo[k] - S->hi[k][i] > T);
        m |= (unsigned)!far << i;
    }
    return m;
}
static inline unsigned diag_lanes(const kin__leafsoa *S, const float *lo, const float *hi, float T2, unsigned cols)
{
    unsigned m = 0;
    for (int i = 0; i < LEAF_MAX; ++i) {
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
    for (int i = 0; i < LEAF_MAX; ++i) {
        int eq = 0;
        for (int k = 0; k < 3; ++k) eq |= (S->v[k][i] == v0) | (S->v[k][i] == v1) | (S->v[k][i] == v2);
        m |= (unsigned)eq << i;
    }
    return m;
}
#endif

/* apart_lanes: bit j set when lane j of S and lane i of X are shown
 * apart by more than T along the line of their box centres (the first
 * separating axis of prim_far, in float on the joints' points rounded to
 * float): bound = (gap of the projections) / |u| - radii. Rounding: every
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
    for (int h = 0; h < LEAF_MAX; h += 4) {
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
    for (int j = 0; j < LEAF_MAX; ++j) {
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
 * own_axes); lanes outside cols are not tested. The axes are the ones
 * prim_far finds separating most pairs that the box test and the line of
 * the centres keep (long thin triangles side by side in a dome: the
 * in-plane normals of their sides): one row's axes against 8 lanes in
 * straight-line code cost less than the scalar bounds they save. Rounding:
 * as apart_lanes (points rounded to float, float arithmetic, axes of length
 * 1 to 2^-22: the slack in T covers it). A disabled axis (a degenerate
 * primitive) has the interval (-inf, inf). */
static void own_axes(const struct kin_contact *c, const kin__leafsoa *S, int i, const kin__leafprim *L, float *ax)
{
    const double *P = c->pts;
    double u[KIN__OWN_AXES][3];
    int ok[KIN__OWN_AXES] = {0};
    const double *A = P + 3 * L->v[0], *B = P + 3 * L->v[1];
    if (L->v[2] >= 0) {
        const double *C = P + 3 * L->v[2];
        double e[3][3], n[3];
        for (int k = 0; k < 3; ++k) e[0][k] = B[k] - A[k], e[1][k] = C[k] - B[k], e[2][k] = A[k] - C[k];
        n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
        n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
        n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
        for (int k = 0; k < 3; ++k) u[0][k] = n[k];
        for (int s = 0; s < 3; ++s) {
            u[s + 1][0] = e[s][1] * n[2] - e[s][2] * n[1];
            u[s + 1][1] = e[s][2] * n[0] - e[s][0] * n[2];
            u[s + 1][2] = e[s][0] * n[1] - e[s][1] * n[0];
        }
    } else {
        /* across the bar: two perpendicular directions and their diagonals */
        double d[3], w[3] = {0, 0, 0}, v1[3], v2[3];
        for (int k = 0; k < 3; ++k) d[k] = B[k] - A[k];
        int m = fabs(d[0]) <= fabs(d[1]) ? (fabs(d[0]) <= fabs(d[2]) ? 0 : 2) : (fabs(d[1]) <= fabs(d[2]) ? 1 : 2);
        w[m] = 1.0;
        v1[0] = d[1] * w[2] - d[2] * w[1], v1[1] = d[2] * w[0] - d[0] * w[2], v1[2] = d[0] * w[1] - d[1] * w[0];
        double n1 = sqrt(v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2]);
        if (n1 > 0.0 && isfinite(n1))
            for (int k = 0; k < 3; ++k) v1[k] /= n1;
        v2[0] = d[1] * v1[2] - d[2] * v1[1], v2[1] = d[2] * v1[0] - d[0] * v1[2], v2[2] = d[0] * v1[1] - d[1] * v1[0];
        double n2 = sqrt(v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]);
        if (n2 > 0.0 && isfinite(n2))
            for (int k = 0; k < 3; ++k) v2[k] /= n2;
        for (int k = 0; k < 3; ++k) u[0][k] = v1[k], u[1][k] = v2[k], u[2][k] = v1[k] + v2[k], u[3][k] = v1[k] - v2[k];
    }
    for (int s = 0; s < KIN__OWN_AXES; ++s) {
        double nn = sqrt(u[s][0] * u[s][0] + u[s][1] * u[s][1] + u[s][2] * u[s][2]);
        ok[s] = nn > 0.0 && isfinite(nn);
        float *a = ax + 5 * s;
        for (int k = 0; k < 3; ++k) a[k] = ok[s] ? (float)(u[s][k] / nn) : 0.0f;
        float lo = INFINITY, hi = -INFINITY;
        for (int q = 0; q < 3; ++q) {
            float t = a[0] * S->p[q][0][i] + a[1] * S->p[q][1][i] + a[2] * S->p[q][2][i];
            lo = t < lo ? t : lo, hi = t > hi ? t : hi;
        }
        a[3] = ok[s] ? lo : -INFINITY, a[4] = ok[s] ? hi : INFINITY;
    }
}
#if defined(__SSE2__)
static inline unsigned own_lanes(const kin__leafsoa *S, const float *ax, float thr0, unsigned cols)
{
    unsigned m = 0;
    for (int h = 0; h < LEAF_MAX; h += 4) {
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
    for (int j = 0; j < LEAF_MAX; ++j) {
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
    for (int h = 0; h < LEAF_MAX; h += 4) {
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
    for (int h = 0; h < LEAF_MAX; h += 4) {
        if (!((cols >> h) & 15u)) continue;
        __m128 gap = _mm_max_ps(_mm_sub_ps(_mm_loadu_ps(lo + h), b), _mm_sub_ps(a, _mm_loadu_ps(hi + h)));
        m |= (unsigned)_mm_movemask_ps(_mm_cmpgt_ps(gap, _mm_add_ps(t0, _mm_loadu_ps(r + h)))) << h;
    }
    return m & cols;
}
#else
static inline void project_lanes(const kin__leafsoa *S, const float *w, float *lo, float *hi)
{
    for (int j = 0; j < LEAF_MAX; ++j) {
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
    for (int j = 0; j < LEAF_MAX; ++j) {
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

/* squared gap of lanes i of S and j of T (gap2 of their boxes) */
static inline double lane_gap2(const kin__leafsoa *S, int i, const kin__leafsoa *T, int j)
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        double g = dmax((double)S->lo[k][i] - T->hi[k][j], (double)T->lo[k][j] - S->hi[k][i]);
        if (g > 0.0) s += g * g;
    }
    return s;
}

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

static int adjacent_parts(const kin_assembly *a, int pa, int pb)
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

/* 1 if a cheap lower bound shows that leaves p and q (radii sum rr) have
 * clearance above best: separating axes (the line of their centroids; for
 * a triangle its normal and the in-plane normals of its sides; then the
 * cross products of their sides), stopping at the first that shows it, so that most pairs near each other but apart
 * never reach the exact test */
static int prim_far(const struct kin_contact *c, const kin__leafprim *Lp, const kin__leafprim *Lq, double rr,
                    double best)
{
    if (-rr > best) return 1; /* the distance is >= 0 */
    const double *P = c->pts;
    const int *vp = Lp->v, *vq = Lq->v;
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

/* (a1, b1) before (a2, b2) */
static inline int pair_less(int a1, int b1, int a2, int b2) { return a1 < a2 || (a1 == a2 && b1 < b2); }

/* exact clearance of leaves x, y (centre distance minus radii), closest
 * points cp on x, cq on y. Symmetric: the two primitives are taken in the
 * order of their numbers (prim_part's, which no tree changes), so a pair's
 * clearance and points are the same bits whichever tree hands it in
 * whichever order (the radii are subtracted in that order too) */
static double prim_clearance(const struct kin_contact *c, int x, int y, double *cp, double *cq)
{
    if (c->order[x] > c->order[y]) {
        int t = x;
        double *tp = cp;
        x = y, y = t, cp = cq, cq = tp;
    }
    const double *P = c->pts;
    const int *vp = c->lp[x].v, *vq = c->lp[y].v;
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
    return d - c->lr[x] - c->lr[y];
}

/* One call's pair search: the best pair so far (clearance best, parts ba <
 * bb, their primitives' numbers bxa, bxb, closest points bp, bq), the
 * seed pair tested first (tree positions sx, sy) and the walk's float
 * slacks */
typedef struct pair_search {
    kin_assembly *a;
    struct kin_contact *c;
    double best, bp[3], bq[3];
    int ba, bb, bxa, bxb, sx, sy;
    float slack, rmax_f;
} pair_search;

/* leaf node u against leaf node v (u == v: the leaf against itself): a row
 * of pairs at a time, box and joint tests of all 8 lanes at once, then the
 * exact tests of the pairs left in row order (the same pairs, in the same
 * order, as one pair at a time) */
static void leaf_pair(pair_search *w, int u, int v)
{
    struct kin_contact *c = w->c;
    const kin__bvh_node *U = &c->node[u], *V = &c->node[v];
    const kin__leafprim *lp = c->lp;
    const kin__leafsoa *SU = &c->leaf[U->right], *SV = &c->leaf[V->right];
    const float slack = w->slack, rmax_f = w->rmax_f;
    double xp[3], xq[3];
    float cx[3], rp[3][3]; /* a row's box centre and points */
    unsigned rows = (1u << U->count) - 1, lanes = (1u << V->count) - 1;
    const float *vlo = SU->olo, *vhi = SU->ohi; /* V's lanes on U's axis */
    float pl[LEAF_MAX], ph[LEAF_MAX];
    if (u != v) { /* against the other node's box and slabs, and V's lanes on U's axis */
        rows &= near_lanes(SU, V->lo, V->hi, near_bound(w->best)) & ~diag_lanes(SU, V->lo, V->hi, near_bound2(w->best), rows);
        if (!rows) return;
        project_lanes(SV, SU->w, pl, ph);
        float l = FLT_MAX, h = -FLT_MAX;
        for (int j = 0; j < V->count; ++j) l = pl[j] < l ? pl[j] : l, h = ph[j] > h ? ph[j] : h;
        rows &= ~orient_lanes(SU->olo, SU->ohi, SU->r, l, h, near_bound(w->best) + rmax_f + slack, rows);
        vlo = pl, vhi = ph;
    }
    while (rows) {
        int i = low_bit(rows);
        rows &= rows - 1;
        const float lo[5] = {SU->lo[0][i], SU->lo[1][i], SU->lo[2][i], SU->lo[3][i], SU->lo[4][i]};
        const float hi[5] = {SU->hi[0][i], SU->hi[1][i], SU->hi[2][i], SU->hi[3][i], SU->hi[4][i]};
        unsigned cols = near_lanes(SV, lo, hi, near_bound(w->best)) & lanes &
                        ~adjacent_lanes(SV, SU->v[0][i], SU->v[1][i], SU->v[2][i]);
        if (u == v) cols &= ~((2u << i) - 1); /* each pair once */
        float thr0 = near_bound(w->best) + SU->r[i] + slack; /* see apart_lanes */
        if (cols) cols &= ~orient_lanes(vlo, vhi, SV->r, SU->olo[i], SU->ohi[i], thr0, cols);
        if (cols) cols &= ~diag_lanes(SV, lo, hi, near_bound2(w->best), cols);
        if (cols) {
            apart_row(SU, i, cx, rp);
            cols &= ~apart_lanes(SV, cx, rp, thr0, cols);
            if (cols) { /* the row's own axes, made once per call */
                int x = U->start + i;
                float *ax = c->ax + 5 * KIN__OWN_AXES * x;
                if (c->ax_call[x] != c->call) own_axes(c, SU, i, &lp[x], ax), c->ax_call[x] = c->call;
                cols &= ~own_lanes(SV, ax, thr0, cols);
            }
        }
        int x = U->start + i;
        const kin__leafprim *Lp = &lp[x];
        while (cols) {
            int j = low_bit(cols);
            cols &= cols - 1;
            int y = V->start + j;
            const kin__leafprim *Lq = &lp[y];
            if (cannot_beat(lane_gap2(SU, i, SV, j), -(double)Lp->r - Lq->r, w->best)) continue;
            /* joints shared were dropped above; parts with more
             * joints than the primitives have are compared whole */
            if (!(Lp->own && Lq->own) && adjacent_parts(w->a, Lp->part, Lq->part)) continue;
            if (prim_far(c, Lp, Lq, c->lr[x] + c->lr[y], w->best)) continue;
            if ((x == w->sx && y == w->sy) || (x == w->sy && y == w->sx)) continue; /* done first */
            double d = prim_clearance(c, x, y, xp, xq);
            int pa = Lp->part, pb = Lq->part, sw = pa > pb;
            int fa = sw ? pb : pa, fb = sw ? pa : pb;
            int qa = c->order[sw ? y : x], qb = c->order[sw ? x : y];
            /* ties: the smallest pair of parts, then of primitives */
            if (d < w->best || (d == w->best && w->ba >= 0 &&
                                (pair_less(fa, fb, w->ba, w->bb) ||
                                 (fa == w->ba && fb == w->bb && pair_less(qa, qb, w->bxa, w->bxb))))) {
                w->best = d;
                w->ba = fa, w->bb = fb, w->bxa = qa, w->bxb = qb;
                memcpy(w->bp, sw ? xq : xp, sizeof w->bp);
                memcpy(w->bq, sw ? xp : xq, sizeof w->bq);
                c->seed[0] = x, c->seed[1] = y;
            }
        }
    }
}

/* The near-pair list (a Verlet list, as molecular dynamics keeps one): the
 * leaf pairs (U, V) whose boxes were within cutoff + s_U + s_V of each other
 * when it was made, at the joints vl_x0, for a cutoff of vl_cut, with a
 * skin s_U for each leaf (near_list_skins). While no leaf's joints have
 * moved more than its skin, two parts not on the list are still more than
 * the cutoff apart (a point of a part moves no more than its corners do),
 * so a check of that cutoff or less needs only the pairs on the list: no
 * walk of the tree, whose cost per primitive grows with the tree's depth
 * and with the memory it hops over. 1 if the list holds at the current
 * joints (c->pts): each joint's move computed in double and taken a little
 * larger than its rounding can make it; each leaf's largest move is kept
 * (vl_dl) for the next list's skins. 0 if it does not hold there (vl_dl
 * made), -1 if there is no list for this cutoff (vl_dl not made). */
static int near_list_holds(struct kin_contact *c, int nj, double cutoff)
{
    if (!c->vl_ok || !(cutoff >= 0.0) || !(cutoff <= c->vl_cut)) return -1;
    const double *P = c->pts, *Q = c->vl_x0;
    double *dj = c->vl_dj;
    for (int j = 0; j < nj; ++j) {
        double dx = P[3 * j] - Q[3 * j], dy = P[3 * j + 1] - Q[3 * j + 1], dz = P[3 * j + 2] - Q[3 * j + 2];
        dj[j] = sqrt(dx * dx + dy * dy + dz * dz) * (1.0 + 0x1p-40);
    }
    int ok = 1;
    for (int id = 0; id < c->nnode; ++id) {
        const kin__bvh_node *N = &c->node[id];
        if (N->left >= 0) continue;
        const kin__leafsoa *S = &c->leaf[N->right];
        double m = 0.0;
        for (int i = 0; i < N->count; ++i)
            for (int q = 0; q < 3; ++q) m = dj[S->v[q][i]] > m ? dj[S->v[q][i]] : m;
        c->vl_dl[id] = m;
        ok &= m <= c->vl_sk[id];
    }
    return ok;
}

/* each node's skin for a new near-pair list (c->vl_sk): a leaf's, twice
 * the largest move of its joints over the last list's life (vl_dl, where
 * moves: none for the first list of a tree, or after a cutoff above the
 * last list's), so that the
 * next list lasts about twice as long where the structure keeps moving as
 * it did, and a part that does not move adds no pairs; at most
 * NEAR_SKIN_MAX times its box's largest side (wider skins list more pairs
 * than they save walking); an inner node's, the largest of its leaves'
 * (nodes are in pre-order: children after their parent) */
static void near_list_skins(struct kin_contact *c, int moves)
{
    for (int id = c->nnode - 1; id >= 0; --id) {
        const kin__bvh_node *N = &c->node[id];
        if (N->left < 0) {
            double e = 0.0;
            for (int k = 0; k < 3; ++k) e = dmax(e, (double)N->hi[k] - N->lo[k]);
            double s = moves ? 2.0 * c->vl_dl[id] : 0.0;
            s = dmin(s, NEAR_SKIN_MAX * e);
            c->vl_sk[id] = isfinite(s) ? s : 0.0;
        } else
            c->vl_sk[id] = dmax(c->vl_sk[N->left], c->vl_sk[N->right]);
    }
}

int kin_clearance(kin_assembly *a, const double *xyz, double cutoff, double *clearance, int *parts, double *points)
{
    if (!a || !clearance) return a ? kin__fail(a, KIN_ENULL, "clearance is NULL") : KIN_ENULL;
    *clearance = INFINITY;
    if (parts) parts[0] = parts[1] = parts[2] = parts[3] = -1;
    if (isnan(cutoff)) return kin__fail(a, KIN_EINVAL, "clearance: cutoff is NaN");
    if (!xyz) xyz = a->xyz;
    int dim = a->dim;
    for (int i = 0; i < a->nj * dim; ++i)
        if (!isfinite(xyz[i])) return kin__fail(a, KIN_EGEOM, "joint %d: non-finite coordinate", i / dim);
    int rc = kin__contact_ensure(a);
    if (rc) return rc;
    struct kin_contact *c = a->ct;
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
    if (++c->call == 0) memset(c->ax_call, 0, sizeof(unsigned) * (size_t)c->nprim), c->call = 1;
    pair_search W = {.a = a, .c = c, .best = cutoff, .ba = -1, .bb = -1, .bxa = -1, .bxb = -1};
    /* the last answer's pair first (when the tree is the same): an upper
     * bound that prunes from the start */
    if (c->seed[0] >= 0) {
        int x = c->seed[0], y = c->seed[1];
        double xp[3], xq[3];
        double d = prim_clearance(c, x, y, xp, xq);
        int pa = c->lp[x].part, pb = c->lp[y].part, sw = pa > pb;
        if (d < W.best) {
            W.best = d;
            W.ba = sw ? pb : pa, W.bb = sw ? pa : pb;
            W.bxa = c->order[sw ? y : x], W.bxb = c->order[sw ? x : y];
            memcpy(W.bp, sw ? xq : xp, sizeof W.bp);
            memcpy(W.bq, sw ? xp : xq, sizeof W.bq);
        }
    }
    W.sx = c->seed[0], W.sy = c->seed[1];
    {
        double M = 0.0;
        for (int k = 0; k < 3; ++k) M = dmax(M, dmax(fabs((double)c->node[0].lo[k]), fabs((double)c->node[0].hi[k])));
        /* far from 1 (float overflow, underflow): no lane is dropped so */
        W.slack = M > 0x1p-40 && M < 0x1p100 ? f_up(0x1p-16 * M) : INFINITY;
    }
    W.rmax_f = f_up(c->rmax);
    int holds = near_list_holds(c, a->nj, cutoff);
    if (holds > 0) {
        for (int k = 0; k < c->vl_n; ++k) leaf_pair(&W, c->vl[2 * k], c->vl[2 * k + 1]);
        ++c->vl_used;
    } else {
        /* the pair walk, nearer pairs first; each pair on the stack with
         * the squared gap of its boxes (0 for a node against itself),
         * tested again when it is taken (best may have come down since).
         * A cutoff of 0 or more makes a new near-pair list on the way: the
         * walk then keeps every pair of nodes within the cutoff plus their
         * skins, not only those within best, and lists the leaf pairs it
         * meets */
        int collect = cutoff >= 0.0 && cutoff < c->vl_nocut;
        const double *sk = c->vl_sk;
        if (collect) near_list_skins(c, holds == 0), c->vl_ok = 0, c->vl_n = 0;
        const double neg_node = -2.0 * c->rmax;
        const kin__bvh_node *node = c->node;
        int *st = c->stack, top;
        double *sg = c->sgap;
        st[0] = 0, st[1] = 0, sg[0] = 0.0, top = 1;
        while (top > 0) {
            --top;
            int u = st[2 * top], v = st[2 * top + 1];
            double bound = collect ? cutoff + sk[u] + sk[v] : W.best;
            if (u != v && cannot_beat(sg[top], neg_node, bound)) continue;
            const kin__bvh_node *U = &node[u], *V = &node[v];
            if (U->left < 0 && V->left < 0) {
                if (collect) {
                    if (c->vl_n < c->vl_cap) c->vl[2 * c->vl_n] = u, c->vl[2 * c->vl_n + 1] = v, ++c->vl_n;
                    else /* more than the list holds: no list, nor for this cutoff or more until the tree is new */
                        collect = 0, c->vl_nocut = cutoff;
                }
                leaf_pair(&W, u, v);
                continue;
            }
            if (top + 3 > c->stack_cap) return kin__fail(a, KIN_ERANGE, "clearance: tree walk deeper than planned");
            if (u == v) {
                int l = U->left, r = U->right;
                double g = gap2_node(&node[l], &node[r]);
                if (!cannot_beat(g, neg_node, collect ? cutoff + sk[l] + sk[r] : W.best)) st[2 * top] = l, st[2 * top + 1] = r, sg[top] = g, ++top;
                st[2 * top] = r, st[2 * top + 1] = r, sg[top] = 0.0, ++top;
                st[2 * top] = l, st[2 * top + 1] = l, sg[top] = 0.0, ++top;
                continue;
            }
            /* split the larger (or the inner) node; the nearer child pair last (popped first) */
            int splitU = V->left < 0 || (U->left >= 0 && U->count >= V->count);
            int c1 = splitU ? U->left : V->left, c2 = splitU ? U->right : V->right, o = splitU ? v : u;
            const kin__bvh_node *O = &node[o], *C1 = &node[c1], *C2 = &node[c2];
            double g1 = gap2_node(C1, O), g2 = gap2_node(C2, O);
            int near = g1 <= g2;
            double b1 = collect ? cutoff + sk[c1] + sk[o] : W.best, b2 = collect ? cutoff + sk[c2] + sk[o] : W.best;
            if (!cannot_beat(near ? g2 : g1, neg_node, near ? b2 : b1))
                st[2 * top] = near ? c2 : c1, st[2 * top + 1] = o, sg[top] = near ? g2 : g1, ++top;
            if (!cannot_beat(near ? g1 : g2, neg_node, near ? b1 : b2))
                st[2 * top] = near ? c1 : c2, st[2 * top + 1] = o, sg[top] = near ? g1 : g2, ++top;
        }
        if (collect) {
            c->vl_ok = 1, c->vl_cut = cutoff;
            memcpy(c->vl_x0, c->pts, sizeof(double) * 3 * (size_t)a->nj);
        }
    }
    *clearance = W.ba >= 0 ? W.best : INFINITY;
    if (W.ba >= 0) {
        if (parts) {
            parts[0] = W.ba < a->nb ? KIN_PART_BAR : KIN_PART_PANEL;
            parts[1] = W.ba < a->nb ? W.ba : W.ba - a->nb;
            parts[2] = W.bb < a->nb ? KIN_PART_BAR : KIN_PART_PANEL;
            parts[3] = W.bb < a->nb ? W.bb : W.bb - a->nb;
        }
        if (points)
            for (int k = 0; k < dim; ++k) points[k] = W.bp[k], points[dim + k] = W.bq[k];
    }
    return KIN_OK;
}
