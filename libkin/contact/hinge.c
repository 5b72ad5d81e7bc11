/* Hinges (kin_contact.h, docs/contact.md "Hinges"): two panels that share an
 * edge, a fold line, in 3D. The clearance never compares parts that share a
 * joint, so two panels folding through each other across their common fold
 * line would go unseen; a hinge is seen by its dihedral angle instead.
 *
 * Each hinge is (i, j, a, b, pa, pb): the edge i < j shared by panels pa <
 * pb, and a, b the third joints of the fan triangles of pa and pb that hold
 * the edge (the panel's own triangle for a triangle panel; for a longer
 * loop the fan's, since the fan is the panel libkin checks). With e = x_j -
 * x_i and u_a, u_b the parts of x_a - x_i, x_b - x_i across e, the angle
 * delta between u_a and u_b is pi where the hinge lies flat open and 0
 * where it is folded flat (closed: the panels lie on each other); the fold
 * angle is psi = sigma (pi - delta) with sigma the sign of e . (u_a x u_b):
 * continuous through flat open (0), and it jumps from pi to -pi where the
 * hinge passes through flat-folded, which is the penetration the follower
 * watches (branches/hinge_event.c; sigma is the sign of the signed volume
 * of (i, j, a, b), the measure a pass-through changes).
 *
 * The hinge's gap, 2 h sin(delta / 2) with h the smaller of |u_a|, |u_b|,
 * is the distance of the points at h from the edge's middle across it on
 * each panel: 2h when open flat, 0 when closed; less the two panels' half
 * thicknesses it is the hinge's clearance, which kin_clearance counts (a
 * closed hinge is in contact). A panel of zero height over the edge (its
 * far joint on the edge's line) makes no hinge: NaN, never counted. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/clearance.h"

/* an edge of a panel: its joints (lo < hi), the panel and the far joint */
typedef struct {
    int lo, hi, panel, far;
} hedge;

static int cmp_hedge(const void *p, const void *q)
{
    const hedge *x = p, *y = q;
    if (x->lo != y->lo) return (x->lo > y->lo) - (x->lo < y->lo);
    if (x->hi != y->hi) return (x->hi > y->hi) - (x->hi < y->hi);
    return (x->panel > y->panel) - (x->panel < y->panel);
}

int kin__hinges_make(const kin_assembly *a, struct kin_contact *c)
{
    c->nh = 0;
    free(c->hg), free(c->hg_side), free(c->hg_c0), free(c->hg_held), free(c->hg_ws);
    c->hg = NULL, c->hg_side = NULL, c->hg_c0 = NULL, c->hg_held = NULL, c->hg_ws = NULL;
    c->hg_side_ok = 0;
    if (a->dim != 3 || c->np < 2) return KIN_OK;
    size_t ne = (size_t)c->poff[c->np];
    hedge *E = malloc(sizeof *E * ne);
    if (!E) return KIN_ENOMEM;
    size_t k = 0;
    for (int p = 0; p < c->np; ++p) {
        const int *f = c->pj + c->poff[p];
        int n = c->poff[p + 1] - c->poff[p];
        for (int q = 0; q < n; ++q, ++k) {
            int u = f[q], v = f[(q + 1) % n];
            E[k].lo = u < v ? u : v, E[k].hi = u < v ? v : u, E[k].panel = p;
            /* the fan triangle (f0, f_q, f_q+1) holding the edge */
            E[k].far = q == 0 ? f[2] : q == n - 1 ? f[n - 2] : f[0];
        }
    }
    qsort(E, ne, sizeof *E, cmp_hedge);
    /* hinges: every two panels on one edge (more than two on one edge is a
     * book of panels: each pair is a hinge) */
    int nh = 0;
    for (size_t s = 0, t; s < ne; s = t) {
        for (t = s + 1; t < ne && E[t].lo == E[s].lo && E[t].hi == E[s].hi; ++t) {}
        nh += (int)((t - s) * (t - s - 1) / 2);
    }
    c->hg = malloc(sizeof(int) * 6 * (size_t)(nh ? nh : 1));
    c->hg_side = calloc((size_t)(nh ? nh : 1), 1);
    c->hg_c0 = calloc((size_t)(nh ? nh : 1), 1);
    c->hg_held = calloc((size_t)(nh ? nh : 1), 1);
    c->hg_ws = malloc(sizeof(double) * kin__hold_ws_size(a, nh));
    if (!c->hg || !c->hg_side || !c->hg_c0 || !c->hg_held || !c->hg_ws) {
        free(E);
        return KIN_ENOMEM;
    }
    int h = 0;
    for (size_t s = 0, t; s < ne; s = t) {
        for (t = s + 1; t < ne && E[t].lo == E[s].lo && E[t].hi == E[s].hi; ++t) {}
        for (size_t x = s; x < t; ++x)
            for (size_t y = x + 1; y < t; ++y, ++h) {
                int *g = c->hg + 6 * h;
                g[0] = E[s].lo, g[1] = E[s].hi, g[2] = E[x].far, g[3] = E[y].far;
                g[4] = E[x].panel, g[5] = E[y].panel;
            }
    }
    c->nh = nh;
    free(E);
    return KIN_OK;
}

double kin__hinge_measure(const double *xyz, const int *g, double *delta, int *sigma, double *pts)
{
    const double *xi = xyz + 3 * g[0], *xj = xyz + 3 * g[1], *xa = xyz + 3 * g[2], *xb = xyz + 3 * g[3];
    double e[3], ua[3], ub[3], ee = 0.0, pa = 0.0, pb = 0.0;
    for (int k = 0; k < 3; ++k) {
        e[k] = xj[k] - xi[k], ua[k] = xa[k] - xi[k], ub[k] = xb[k] - xi[k];
        ee += e[k] * e[k], pa += ua[k] * e[k], pb += ub[k] * e[k];
    }
    double la = 0.0, lb = 0.0, dot = 0.0;
    for (int k = 0; k < 3; ++k) {
        ua[k] -= ee > 0.0 ? pa / ee * e[k] : 0.0;
        ub[k] -= ee > 0.0 ? pb / ee * e[k] : 0.0;
        la += ua[k] * ua[k], lb += ub[k] * ub[k], dot += ua[k] * ub[k];
    }
    double cr[3] = {ua[1] * ub[2] - ua[2] * ub[1], ua[2] * ub[0] - ua[0] * ub[2], ua[0] * ub[1] - ua[1] * ub[0]};
    double sn = sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
    double vol = cr[0] * e[0] + cr[1] * e[1] + cr[2] * e[2];
    *delta = atan2(sn, dot);
    *sigma = vol > 0.0 ? 1 : vol < 0.0 ? -1 : 0;
    la = sqrt(la), lb = sqrt(lb);
    double hmin = la < lb ? la : lb;
    if (!(hmin > 0.0)) {
        /* a panel of zero height over the edge (its far joint on the edge's
         * line): no angle, no hinge to close */
        *delta = NAN, *sigma = 0;
        if (pts)
            for (int k = 0; k < 6; ++k) pts[k] = NAN;
        return NAN;
    }
    if (pts) {
        for (int k = 0; k < 3; ++k) {
            double m = 0.5 * (xi[k] + xj[k]);
            pts[k] = m + (la > 0.0 ? hmin / la * ua[k] : 0.0);
            pts[3 + k] = m + (lb > 0.0 ? hmin / lb * ub[k] : 0.0);
        }
    }
    return 2.0 * hmin * sin(0.5 * *delta);
}

/* a panel's half thickness */
static double half_t(const struct kin_contact *c, int p)
{
    return 0.5 * (c->tpan && c->tpan[p] >= 0.0 ? c->tpan[p] : c->t0);
}

void kin__hinge_closest(const kin_assembly *a, const struct kin_contact *c, const double *xyz, double cutoff,
                        kin__hinge_best *best)
{
    for (int h = 0; c->hinge_on && h < c->nh; ++h) {
        const int *g = c->hg + 6 * h;
        double delta, pts[6];
        int sigma;
        double v = kin__hinge_measure(xyz, g, &delta, &sigma, pts) - half_t(c, g[4]) - half_t(c, g[5]);
        int pa = a->nb + g[4], pb = a->nb + g[5];
        if (!(v <= cutoff)) continue;
        /* ties: the smaller pair of parts, as the tree's walk */
        if (best->pa >= 0 && !(v < best->value || (v == best->value && (pa < best->pa || (pa == best->pa && pb < best->pb)))))
            continue;
        best->value = v, best->pa = pa, best->pb = pb, best->hinge = h;
        memcpy(best->pts, pts, sizeof pts);
    }
}
