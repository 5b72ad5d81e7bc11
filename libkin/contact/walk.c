/* The pair walk of the clearance (kin_clearance, contact.c): the closest
 * pair of parts that share no joint, within the cutoff, on the tree fitted
 * to the configuration (tree.c). The tree is walked against itself, pairs
 * of nodes nearer first, a pair dropped when its boxes or slabs are no
 * nearer than the best clearance found so far (the last call's closest
 * pair, evaluated first, gives that bound from the start); two leaves are
 * tested a row at a time, 8 lanes at once without a branch per pair
 * (lanes.h: boxes, shared joints, then for the pairs left the first leaf's
 * axis, the slabs, the line of the box centres and the row primitive's own
 * axes), and the pairs left of parts that share no joint get the
 * separating-axis bound and the exact test (primitives.c). A check with a
 * cutoff lists the leaf pairs its walk meets (with a skin for each leaf),
 * and later checks test only those while no leaf has moved more than its
 * skin (near_list.c). */
#include <math.h>
#include <string.h>

#include "contact/lanes.h"

#define LEAF_MAX KIN__LEAF_MAX

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

/* (a1, b1) before (a2, b2) */
static inline int pair_less(int a1, int b1, int a2, int b2) { return a1 < a2 || (a1 == a2 && b1 < b2); }

/* a pair met within prune (best + band) kept as a tie for kin_clearance's
 * name (kin__tie_name); those that best has since left behind are dropped
 * when the list fills, and a list still full is given up (w->tie_full:
 * kin_clearance then names by a second walk) */
static void note_tie(kin__pair_search *w, double d, int fa, int fb, int qa, int qb, const double *p, const double *q)
{
    if (w->tie_full || !(d <= w->prune)) return;
    if (w->nties == KIN__TIES_MAX) {
        int k = 0;
        for (int i = 0; i < w->nties; ++i)
            if (w->ties[i].d <= w->prune) w->ties[k++] = w->ties[i];
        w->nties = k;
        if (k == KIN__TIES_MAX) {
            w->tie_full = 1;
            return;
        }
    }
    kin__tie *t = &w->ties[w->nties++];
    t->d = d, t->fa = fa, t->fb = fb, t->qa = qa, t->qb = qb;
    memcpy(t->p, p, sizeof t->p);
    memcpy(t->q, q, sizeof t->q);
}

int kin__tie_name(const kin__pair_search *w, double bound)
{
    int k = -1;
    for (int i = 0; i < w->nties; ++i) {
        const kin__tie *t = &w->ties[i];
        if (!(t->d <= bound)) continue;
        if (k < 0) { k = i; continue; }
        const kin__tie *b = &w->ties[k];
        if (pair_less(t->fa, t->fb, b->fa, b->fb) ||
            (t->fa == b->fa && t->fb == b->fb && pair_less(t->qa, t->qb, b->qa, b->qb)))
            k = i;
    }
    return k;
}

/* own_axes: the KIN__OWN_AXES unit axes of the row's primitive (leaf S's
 * lane i, L) for own_lanes (lanes.h: why these, and the rounding), each
 * with the primitive's interval on it (5 floats an axis): a triangle's
 * normal and the in-plane normals of its sides; across a bar, two
 * perpendicular directions and their diagonals. A disabled axis (a
 * degenerate primitive) has the interval (-inf, inf). */
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

/* leaf node u against leaf node v (u == v: the leaf against itself): a row
 * of pairs at a time, box and joint tests of all 8 lanes at once, then the
 * exact tests of the pairs left in row order (the same pairs, in the same
 * order, as one pair at a time) */
static void leaf_pair(kin__pair_search *w, int u, int v)
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
        rows &= near_lanes(SU, V->lo, V->hi, near_bound(w->prune)) & ~diag_lanes(SU, V->lo, V->hi, near_bound2(w->prune), rows);
        if (!rows) return;
        project_lanes(SV, SU->w, pl, ph);
        float l = FLT_MAX, h = -FLT_MAX;
        for (int j = 0; j < V->count; ++j) l = pl[j] < l ? pl[j] : l, h = ph[j] > h ? ph[j] : h;
        rows &= ~orient_lanes(SU->olo, SU->ohi, SU->r, l, h, near_bound(w->prune) + rmax_f + slack, rows);
        vlo = pl, vhi = ph;
    }
    while (rows) {
        int i = low_bit(rows);
        rows &= rows - 1;
        const float lo[5] = {SU->lo[0][i], SU->lo[1][i], SU->lo[2][i], SU->lo[3][i], SU->lo[4][i]};
        const float hi[5] = {SU->hi[0][i], SU->hi[1][i], SU->hi[2][i], SU->hi[3][i], SU->hi[4][i]};
        unsigned cols = near_lanes(SV, lo, hi, near_bound(w->prune)) & lanes &
                        ~adjacent_lanes(SV, SU->v[0][i], SU->v[1][i], SU->v[2][i]);
        if (u == v) cols &= ~((2u << i) - 1); /* each pair once */
        float thr0 = near_bound(w->prune) + SU->r[i] + slack; /* see apart_lanes */
        if (cols) cols &= ~orient_lanes(vlo, vhi, SV->r, SU->olo[i], SU->ohi[i], thr0, cols);
        if (cols) cols &= ~diag_lanes(SV, lo, hi, near_bound2(w->prune), cols);
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
            if (cannot_beat(lane_gap2(SU, i, SV, j), -(double)Lp->r - Lq->r, w->prune)) continue;
            /* joints shared were dropped above; parts with more
             * joints than the primitives have are compared whole */
            if (!(Lp->own && Lq->own) && kin__adjacent_parts(w->a, Lp->part, Lq->part)) continue;
            if (kin__prim_far(c, Lp, Lq, c->lr[x] + c->lr[y], w->prune)) continue;
            if ((x == w->sx && y == w->sy) || (x == w->sy && y == w->sx)) continue; /* done first */
            double d = kin__prim_clearance(c, x, y, xp, xq);
            int pa = Lp->part, pb = Lq->part, sw = pa > pb;
            int fa = sw ? pb : pa, fb = sw ? pa : pb;
            int qa = c->order[sw ? y : x], qb = c->order[sw ? x : y];
            /* ties: the smallest pair of parts, then of primitives (naming:
             * every pair within the bound is a tie) */
            int smaller = w->ba >= 0 && (pair_less(fa, fb, w->ba, w->bb) ||
                                         (fa == w->ba && fb == w->bb && pair_less(qa, qb, w->bxa, w->bxb)));
            int wins = w->naming ? d <= w->best && (w->ba < 0 || smaller)
                                 : d < w->best || (d == w->best && smaller);
            if (wins && !w->naming) w->best = d, w->prune = fmin(d + w->band, w->cutoff);
            if (!w->naming && w->band > 0.0) note_tie(w, d, fa, fb, qa, qb, sw ? xq : xp, sw ? xp : xq);
            if (wins) {
                w->named = d;
                w->ba = fa, w->bb = fb, w->bxa = qa, w->bxb = qb;
                memcpy(w->bp, sw ? xq : xp, sizeof w->bp);
                memcpy(w->bq, sw ? xp : xq, sizeof w->bq);
                if (!w->naming) c->seed[0] = x, c->seed[1] = y; /* the closest pair: the next call's bound */
            }
        }
    }
}

/* The pair walk, nearer pairs first; each pair on the stack with the
 * squared gap of its boxes (0 for a node against itself), tested again
 * when it is taken (best may have come down since). A cutoff of 0 or more
 * makes a new near-pair list on the way: the walk then keeps every pair of
 * nodes within the cutoff plus their skins, not only those within best,
 * and lists the leaf pairs it meets (moves: as kin__near_list_start). */
static int tree_walk(kin__pair_search *w, double cutoff, int moves)
{
    kin_assembly *a = w->a;
    struct kin_contact *c = w->c;
    int collect = kin__near_list_start(c, cutoff, moves);
    const double *sk = c->vl_sk;
    const double neg_node = -2.0 * c->rmax;
    const kin__bvh_node *node = c->node;
    int *st = c->stack, top;
    double *sg = c->sgap;
    st[0] = 0, st[1] = 0, sg[0] = 0.0, top = 1;
    while (top > 0) {
        --top;
        int u = st[2 * top], v = st[2 * top + 1];
        double bound = collect ? cutoff + sk[u] + sk[v] : w->prune;
        if (u != v && cannot_beat(sg[top], neg_node, bound)) continue;
        const kin__bvh_node *U = &node[u], *V = &node[v];
        if (U->left < 0 && V->left < 0) {
            if (collect) collect = kin__near_list_add(c, u, v, cutoff);
            leaf_pair(w, u, v);
            continue;
        }
        if (top + 3 > c->stack_cap) return kin__fail(a, KIN_ERANGE, "clearance: tree walk deeper than planned");
        if (u == v) {
            int l = U->left, r = U->right;
            double g = gap2_node(&node[l], &node[r]);
            if (!cannot_beat(g, neg_node, collect ? cutoff + sk[l] + sk[r] : w->prune)) st[2 * top] = l, st[2 * top + 1] = r, sg[top] = g, ++top;
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
        double b1 = collect ? cutoff + sk[c1] + sk[o] : w->prune, b2 = collect ? cutoff + sk[c2] + sk[o] : w->prune;
        if (!cannot_beat(near ? g2 : g1, neg_node, near ? b2 : b1))
            st[2 * top] = near ? c2 : c1, st[2 * top + 1] = o, sg[top] = near ? g2 : g1, ++top;
        if (!cannot_beat(near ? g1 : g2, neg_node, near ? b1 : b2))
            st[2 * top] = near ? c1 : c2, st[2 * top + 1] = o, sg[top] = near ? g1 : g2, ++top;
    }
    if (collect) kin__near_list_done(c, cutoff, a->nj);
    return KIN_OK;
}

/* the walk's float slacks, from the root box */
static void search_slacks(kin__pair_search *w)
{
    const struct kin_contact *c = w->c;
    double M = 0.0;
    for (int k = 0; k < 3; ++k) M = dmax(M, dmax(fabs((double)c->node[0].lo[k]), fabs((double)c->node[0].hi[k])));
    /* far from 1 (float overflow, underflow): no lane is dropped so */
    w->slack = M > 0x1p-40 && M < 0x1p100 ? f_up(0x1p-16 * M) : INFINITY;
    w->rmax_f = f_up(c->rmax);
}

/* the pairs within the bound, by the near-pair list where it holds for it,
 * else by a walk that makes no list (clearance.h) */
int kin__name_pair(kin_assembly *a, struct kin_contact *c, double bound, kin__pair_search *w)
{
    if (++c->call == 0) memset(c->ax_call, 0, sizeof(unsigned) * (size_t)c->nprim), c->call = 1;
    *w = (kin__pair_search){.a = a, .c = c, .best = bound, .prune = bound, .cutoff = bound, .named = INFINITY,
                            .ba = -1, .bb = -1, .bxa = -1, .bxb = -1, .sx = -1, .sy = -1, .naming = 1};
    search_slacks(w);
    if (bound >= 0.0 && kin__near_list_holds(c, a->nj, bound) > 0) {
        for (int k = 0; k < c->vl_n; ++k) leaf_pair(w, c->vl[2 * k], c->vl[2 * k + 1]);
        return KIN_OK;
    }
    return tree_walk(w, -1.0, 0);
}

/* the seed pair, then the near-pair list or the walk (clearance.h) */
int kin__closest_pair(kin_assembly *a, struct kin_contact *c, double cutoff, double band, kin__pair_search *w)
{
    if (++c->call == 0) memset(c->ax_call, 0, sizeof(unsigned) * (size_t)c->nprim), c->call = 1;
    *w = (kin__pair_search){.a = a, .c = c, .best = cutoff, .prune = cutoff, .cutoff = cutoff, .band = band,
                            .named = INFINITY, .ba = -1, .bb = -1, .bxa = -1, .bxb = -1};
    /* the last answer's pair first (when the tree is the same): an upper
     * bound that prunes from the start */
    if (c->seed[0] >= 0) {
        int x = c->seed[0], y = c->seed[1];
        double xp[3], xq[3];
        double d = kin__prim_clearance(c, x, y, xp, xq);
        int pa = c->lp[x].part, pb = c->lp[y].part, sw = pa > pb;
        if (d < w->best) {
            w->best = w->named = d;
            w->prune = fmin(d + band, cutoff);
            w->ba = sw ? pb : pa, w->bb = sw ? pa : pb;
            w->bxa = c->order[sw ? y : x], w->bxb = c->order[sw ? x : y];
            memcpy(w->bp, sw ? xq : xp, sizeof w->bp);
            memcpy(w->bq, sw ? xp : xq, sizeof w->bq);
            if (band > 0.0) note_tie(w, d, w->ba, w->bb, w->bxa, w->bxb, w->bp, w->bq);
        }
    }
    w->sx = c->seed[0], w->sy = c->seed[1];
    search_slacks(w);
    int holds = kin__near_list_holds(c, a->nj, cutoff);
    if (holds > 0) {
        for (int k = 0; k < c->vl_n; ++k) leaf_pair(w, c->vl[2 * k], c->vl[2 * k + 1]);
        ++c->vl_used;
        return KIN_OK;
    }
    return tree_walk(w, cutoff, holds == 0);
}
