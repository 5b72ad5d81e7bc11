/* The near-pair list of the clearance (a Verlet list, as molecular
 * dynamics keeps one): the leaf pairs (U, V) whose boxes were within
 * cutoff + s_U + s_V of each other when it was made, at the joints vl_x0,
 * for a cutoff of vl_cut, with a skin s_U for each leaf (near_list_skins).
 * While no leaf's joints have moved more than its skin, two parts not on
 * the list are still more than the cutoff apart (a point of a part moves no
 * more than its corners do), so a check of that cutoff or less needs only
 * the pairs on the list: no walk of the tree, whose cost per primitive
 * grows with the tree's depth and with the memory it hops over. A check
 * with a cutoff whose list does not hold makes a new one: the pair walk
 * (walk.c) lists the leaf pairs it meets (kin__near_list_start, _add,
 * _done). */
#include <math.h>
#include <string.h>

#include "contact/clearance.h"

/* a leaf's skin in the near-pair list at most, a fraction of its box's
 * largest side (see near_list_skins) */
#define NEAR_SKIN_MAX 0.4

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

/* 1 if the list holds at the current joints (c->pts): each joint's move
 * computed in double and taken a little larger than its rounding can make
 * it; each leaf's largest move is kept (vl_dl) for the next list's skins.
 * 0 if it does not hold there (vl_dl made), -1 if there is no list for
 * this cutoff (vl_dl not made). */
int kin__near_list_holds(struct kin_contact *c, int nj, double cutoff)
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

/* a walk for this cutoff makes a new list (at or above vl_nocut: none), the
 * skins from the leaves' moves where moves (see near_list_skins) */
int kin__near_list_start(struct kin_contact *c, double cutoff, int moves)
{
    int collect = cutoff >= 0.0 && cutoff < c->vl_nocut;
    if (collect) near_list_skins(c, moves), c->vl_ok = 0, c->vl_n = 0;
    return collect;
}

/* leaf pair (u, v) on the list; 0 when it is full */
int kin__near_list_add(struct kin_contact *c, int u, int v, double cutoff)
{
    if (c->vl_n < c->vl_cap) {
        c->vl[2 * c->vl_n] = u, c->vl[2 * c->vl_n + 1] = v, ++c->vl_n;
        return 1;
    }
    /* more than the list holds: no list, nor for this cutoff or more until the tree is new */
    c->vl_nocut = cutoff;
    return 0;
}

/* the walk has listed every leaf pair it met: the list holds from here */
void kin__near_list_done(struct kin_contact *c, double cutoff, int nj)
{
    c->vl_ok = 1, c->vl_cut = cutoff;
    memcpy(c->vl_x0, c->pts, sizeof(double) * 3 * (size_t)nj);
}
