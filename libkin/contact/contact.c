/* Panels, thicknesses and the clearance between parts (kin_contact.h,
 * docs/contact.md): the contact record on the handle (the model's panels
 * and thicknesses, the clearance's workspace, the contact event's
 * settings) and the public calls.
 *
 * The clearance: every bar is one primitive (a segment), every panel the
 * fan of its triangles, each with a radius (half its thickness). A check
 * fits the bounding-volume tree to the configuration (tree.c) and walks it
 * against itself for the closest pair of parts that share no joint
 * (walk.c: the leaf tests of lanes.h, the near-pair list of near_list.c
 * for checks with a cutoff, the exact tests of primitives.c and
 * distance.c); clearance.h is what those files share. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/clearance.h"

#define LEAF_MAX KIN__LEAF_MAX

static void ct_release(struct kin_contact *c)
{
    if (!c) return;
    free(c->poff), free(c->pj), free(c->rbar), free(c->tpan);
    free(c->prim_part), free(c->prim_v), free(c->prim_r), free(c->cen), free(c->scratch), free(c->skey), free(c->lr), free(c->jpos);
    free(c->order), free(c->node), free(c->lp), free(c->leaf), free(c->ev_prev), free(c->ev_x), free(c->ev_xyz), free(c->stack), free(c->sgap), free(c->pts);
    free(c->ev_box), free(c->ev_key), free(c->ax), free(c->ax_call), free(c->vl), free(c->vl_x0), free(c->vl_sk), free(c->vl_dl), free(c->vl_dj);
    free(c->dev), free(c->hg), free(c->hg_side), free(c->hg_c0), free(c->hg_x), free(c->hg_held), free(c->hg_ws);
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
    int ntri = 0, ndev = 0;
    for (int i = 0; i < c->np; ++i) ntri += c->poff[i + 1] - c->poff[i] - 2;
    for (int k = 0; c->dev && k < a->nb; ++k) ndev += c->dev[k] != 0;
    int n = a->nb - ndev + ntri;
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
    c->cen = malloc(sizeof(double) * KIN__CEN * N);
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
    for (int k = 0; k < a->nb; ++k) {
        if (c->dev && c->dev[k]) continue; /* a device: not a part that can touch */
        c->prim_part[p] = k;
        c->prim_v[3 * p] = a->bars[2 * k];
        c->prim_v[3 * p + 1] = a->bars[2 * k + 1];
        c->prim_v[3 * p + 2] = -1;
        ++p;
    }
    c->nprim = p + ntri;
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
                   const double *tpan, const unsigned char *dev, struct kin_contact **out)
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
    c->hg_x = malloc(sizeof(double) * 3 * ((size_t)a->nj + 1));
    c->hinge_on = 1;
    c->ev_hinge = -1;
    int anydev = 0;
    for (int k = 0; dev && k < a->nb; ++k) anydev |= dev[k] != 0;
    if (anydev && (c->dev = malloc((size_t)a->nb)) != NULL) memcpy(c->dev, dev, (size_t)a->nb);
    if (!c->poff || !c->pj || !c->rbar || !c->tpan || !c->hg_x || (anydev && !c->dev)) {
        ct_release(c);
        return KIN_ENOMEM;
    }
    c->poff[0] = 0;
    if (np) memcpy(c->poff, poff, sizeof(int) * ((size_t)np + 1));
    if (nj) memcpy(c->pj, pj, sizeof(int) * nj);
    for (int k = 0; k < a->nb; ++k) c->rbar[k] = rbar ? rbar[k] : -1.0;
    for (int i = 0; i < np; ++i) c->tpan[i] = tpan ? tpan[i] : -1.0;
    if (ct_workspace(a, c) != KIN_OK || kin__hinges_make(a, c) != KIN_OK) {
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
    int rc = ct_make(dst, s->np, s->poff, s->pj, s->t0, s->rbar, s->tpan, s->dev, &c);
    if (rc) return rc;
    c->ev_on = s->ev_on, c->ev_tol = s->ev_tol, c->hinge_on = s->hinge_on;
    /* the tracked fold sides go with the configuration they belong to */
    if (s->hg_side_ok && c->nh == s->nh) {
        memcpy(c->hg_side, s->hg_side, (size_t)c->nh);
        memcpy(c->hg_held, s->hg_held, (size_t)c->nh);
        memcpy(c->hg_x, s->hg_x, sizeof(double) * (size_t)src->nj * (size_t)src->dim);
        c->hg_side_ok = 1;
    }
    if (dst->ct_free) dst->ct_free(dst);
    dst->ct = c;
    dst->ct_free = ct_free;
    dst->ct_clone = ct_clone;
    return KIN_OK;
}

static void ct_install(kin_assembly *a, struct kin_contact *c)
{
    if (a->ct) /* the event and hinge settings stay */
        c->ev_on = a->ct->ev_on, c->ev_tol = a->ct->ev_tol, c->hinge_on = a->ct->hinge_on;
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
    int rc = ct_make(a, 0, &zero, NULL, 0.0, NULL, NULL, NULL, &c);
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
    int rc = ct_make(a, np, np ? offsets : &zero, joints, t0, a->ct ? a->ct->rbar : NULL, NULL,
                     a->ct ? a->ct->dev : NULL, &c);
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

/* the largest |coordinate| of a configuration given to kin_clearance, as
 * kin_assembly_create's bound (kin_assembly.h) */
static const double CLEARANCE_COORD_MAX = 1e150;

int kin_clearance(kin_assembly *a, const double *xyz, double cutoff, double *clearance, int *parts, double *points)
{
    if (!a || !clearance) return a ? kin__fail(a, KIN_ENULL, "clearance is NULL") : KIN_ENULL;
    *clearance = INFINITY;
    if (parts) parts[0] = parts[1] = parts[2] = parts[3] = -1;
    if (isnan(cutoff)) return kin__fail(a, KIN_EINVAL, "clearance: cutoff is NaN");
    if (!xyz) xyz = a->xyz;
    int dim = a->dim;
    double xmax = 0.0; /* the largest |coordinate|: the scale of the distances' rounding */
    for (int i = 0; i < a->nj * dim; ++i) {
        if (!isfinite(xyz[i])) return kin__fail(a, KIN_EGEOM, "joint %d: non-finite coordinate", i / dim);
        xmax = fmax(xmax, fabs(xyz[i]));
        /* the range kin_assembly_create accepts: the squared distances of
         * the exact tests stay finite (beyond it they overflowed, and every
         * pair looked infinitely far) */
        if (!(fabs(xyz[i]) <= CLEARANCE_COORD_MAX))
            return kin__fail(a, KIN_EGEOM, "clearance: joint %d: coordinate %g beyond +-%g", i / dim, xyz[i],
                             CLEARANCE_COORD_MAX);
    }
    int rc = kin__contact_ensure(a);
    if (rc) return rc;
    struct kin_contact *c = a->ct;
    kin__tree_fit(a, c, xyz);
    kin__pair_search W;
    /* the rounding of a distance computed from coordinates up to xmax */
    double band = 4.0 * DBL_EPSILON * xmax;
    if ((rc = kin__closest_pair(a, c, cutoff, parts || points ? band : 0.0, &W)) != KIN_OK) return rc;
    *clearance = W.ba >= 0 ? W.best : INFINITY;
    if (W.ba >= 0 && (parts || points)) {
        /* several pairs at the closest clearance up to rounding (parts that
         * touch along a common edge, a symmetric structure's images): which
         * one the walk met first depends on the last bits of the coordinates,
         * so the pair named is the smallest of those within 4 eps x the
         * largest |coordinate| of it (the rounding of a distance computed
         * from such coordinates): the first walk met them all and kept
         * them (or, when there were too many to keep, a second walk bounded
         * there finds it) */
        double bound = fmin(W.best + band, cutoff);
        int k = W.tie_full ? -1 : kin__tie_name(&W, bound);
        if (k >= 0) {
            const kin__tie *t = &W.ties[k];
            W.ba = t->fa, W.bb = t->fb, memcpy(W.bp, t->p, sizeof W.bp), memcpy(W.bq, t->q, sizeof W.bq);
        } else if (W.tie_full) {
            kin__pair_search N;
            if ((rc = kin__name_pair(a, c, bound, &N)) != KIN_OK) return rc;
            if (N.ba >= 0) W.ba = N.ba, W.bb = N.bb, memcpy(W.bp, N.bp, sizeof W.bp), memcpy(W.bq, N.bq, sizeof W.bq);
        }
    }
    /* the hinges (hinge.c): a closed hinge is in contact */
    kin__hinge_best H = {.value = W.ba >= 0 ? W.best : INFINITY, .pa = W.ba, .pb = W.bb, .hinge = -1};
    if (dim == 3) kin__hinge_closest(a, c, xyz, cutoff, &H);
    if (H.hinge >= 0) {
        W.best = H.value, W.ba = H.pa, W.bb = H.pb;
        memcpy(W.bp, H.pts, sizeof W.bp);
        memcpy(W.bq, H.pts + 3, sizeof W.bq);
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

/* ---- devices and hinges ------------------------------------------------- */

int kin_set_device_bars(kin_assembly *a, int ndev, const int *bars)
{
    if (!a) return KIN_ENULL;
    if (ndev < 0 || ndev > a->nb) return kin__fail(a, KIN_EINVAL, "device bars: %d not in 0..%d", ndev, a->nb);
    if (ndev > 0 && !bars) return kin__fail(a, KIN_ENULL, "device bars is NULL");
    unsigned char *dev = calloc((size_t)a->nb + 1, 1);
    if (!dev) return kin__fail(a, KIN_ENOMEM, "device bars");
    for (int q = 0; q < ndev; ++q) {
        if (bars[q] < 0 || bars[q] >= a->nb) {
            free(dev);
            return kin__fail(a, KIN_ERANGE, "device bar %d out of range 0..%d", bars[q], a->nb - 1);
        }
        dev[bars[q]] = 1;
    }
    const struct kin_contact *o = a->ct;
    struct kin_contact *c;
    int zero = 0;
    int rc = o ? ct_make(a, o->np, o->poff, o->pj, o->t0, o->rbar, o->tpan, dev, &c)
               : ct_make(a, 0, &zero, NULL, 0.0, NULL, NULL, dev, &c);
    free(dev);
    if (rc) return kin__fail(a, rc, "device bars and clearance workspace");
    ct_install(a, c);
    return KIN_OK;
}

int kin_get_device_bars(const kin_assembly *a, int *ndev, int *bars)
{
    if (!a || !ndev) return KIN_ENULL;
    const struct kin_contact *c = a->ct;
    int n = 0;
    for (int k = 0; c && c->dev && k < a->nb; ++k)
        if (c->dev[k]) {
            if (bars) bars[n] = k;
            ++n;
        }
    *ndev = n;
    return KIN_OK;
}

int kin_set_hinge_contact(kin_assembly *a, int on)
{
    if (!a) return KIN_ENULL;
    int rc = kin__contact_ensure(a);
    if (rc) return rc;
    a->ct->hinge_on = on != 0;
    return KIN_OK;
}

int kin_get_hinge_contact(const kin_assembly *a)
{
    if (!a) return -1;
    return a->ct ? a->ct->hinge_on : 1;
}

int kin_nhinges(const kin_assembly *a) { return a ? (a->ct ? a->ct->nh : 0) : -1; }

int kin_get_hinges(const kin_assembly *a, int *joints, int *panels)
{
    if (!a) return KIN_ENULL;
    const struct kin_contact *c = a->ct;
    for (int h = 0; c && h < c->nh; ++h) {
        if (joints) memcpy(joints + 4 * h, c->hg + 6 * h, sizeof(int) * 4);
        if (panels) panels[2 * h] = c->hg[6 * h + 4], panels[2 * h + 1] = c->hg[6 * h + 5];
    }
    return KIN_OK;
}

int kin_hinge_angles(kin_assembly *a, const double *xyz, double *fold)
{
    if (!a || !fold) return a ? kin__fail(a, KIN_ENULL, "hinge angles: fold is NULL") : KIN_ENULL;
    if (!xyz) xyz = a->xyz;
    const struct kin_contact *c = a->ct;
    int nh = c ? c->nh : 0;
    for (int h = 0; h < nh; ++h) {
        const int *g = c->hg + 6 * h;
        for (int q = 0; q < 4; ++q)
            for (int k = 0; k < 3; ++k)
                if (!isfinite(xyz[3 * g[q] + k]))
                    return kin__fail(a, KIN_EGEOM, "hinge angles: joint %d: non-finite coordinate", g[q]);
    }
    for (int h = 0; h < nh; ++h) {
        double delta;
        int sigma;
        kin__hinge_measure(xyz, c->hg + 6 * h, &delta, &sigma, NULL);
        fold[h] = (sigma < 0 ? -1.0 : 1.0) * (3.14159265358979323846 - delta);
    }
    return KIN_OK;
}

int kin_hinge_sides(const kin_assembly *a, int *sides)
{
    if (!a || !sides) return KIN_ENULL;
    const struct kin_contact *c = a->ct;
    if (!c || !c->hg_side_ok) return KIN_ESTATE;
    for (int h = 0; h < c->nh; ++h) sides[h] = c->hg_side[h];
    return KIN_OK;
}
