/* The fast locator: Hermite interpolation of the path and of the signed
 * vanishing singular value over the bracketing step (kin_locate.h,
 * KIN_LOCATE_FAST; docs/locate.md). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "locate/locate_internal.h"

/* ---- the fast (Hermite) method ----
 * Nodes: points of the path with their tangents and the vanishing singular
 * value with its derivative. At most this many (the bracket's two ends plus
 * forward calculations). */
enum { HERMITE_MAX_NODES = 8 };
/* A new node sits this fraction of the larger side of its sub-bracket away
 * from the current estimate: near enough to sharpen the interpolant by about
 * two orders, far enough from the bifurcation that the corrector there is
 * well conditioned (its smallest singular values shrink like the distance). */
static const double NODE_OFFSET_FRACTION = 0.1;
/* ... but never nearer than this fraction of the first bracket's width */
static const double NODE_OFFSET_MIN = 1e-3;
/* A node is accurate enough when its estimated position error (the
 * correction its own factorization would still make) is below this fraction
 * of vr_tol x the RMS bar length: an error dx changes v_r by about
 * v_max |dx| / L. */
static const double NODE_ERROR_FRACTION = 1.0;
/* ... and new nodes keep this multiple of the distance where that accuracy
 * is just reached */
static const double NODE_RHO_MARGIN = 1.5;
/* chord iterations that polish a node to the strain floor (no factorization) */
enum { NODE_POLISH_ITER = 3 };
/* A node that lands farther than this times its distance from the estimate
 * away from the interpolated prediction has left the path for a
 * neighbouring branch. */
static const double NODE_JUMP_FRACTION = 0.25;
/* A check whose vanishing singular value does not fall below this fraction
 * of the best so far makes no progress ... */
static const double MIN_PROGRESS = 0.5;
/* ... MAX_STALLS such checks in a row end the iteration */
enum { MAX_STALLS = 2 };
/* The order p of the zero (v_r ~ |l - l*|^p) estimated from the bracket is
 * rounded to 1 or 2 (a tangency, Figure 7(b)); at most this order. */
enum { MAX_ZERO_ORDER = 2 };
/* The interpolated bifurcation is off the strain-free set by the
 * interpolation error; chord corrections with its own factorization remove
 * that along singular values above POLISH_CUT times the located tolerance
 * (those below belong to the bifurcation: dividing by them would throw the
 * point away), at most POLISH_MAX_ITER times. */
static const double POLISH_CUT = 1e3;
enum { POLISH_MAX_ITER = 5 };
/* corank-k Newton steps at a check point of the corank-k mode */
enum { CORANK_NEWTON_ITER = 8 };
/* bisection steps for the root of the interpolated signed singular value */
enum { ROOT_BISECTIONS = 100 };
/* LU nodes (loc_ctx.lu_nodes): the node's vanishing singular triple by
 * subspace iteration with this many vectors, at most this many passes,
 * until its vector moves less than this (as the follower's slope) */
enum { LU_NODE_BLOCK = 2, LU_NODE_PASSES = 40 };
static const double LU_NODE_VECTOR_TOL = 1e-9;

/* ---- the fast method: Hermite interpolation of the path -----------------
 *
 * Along the path, parametrised by z = t0.(x - x0) (t0, x0: tangent and point
 * where following stopped), the configuration x(z) and the vanishing
 * singular value are analytic through the bifurcation, v_r up to its sign:
 * s(z) = sign(dv/dz) v^(1/p) (p = 1 for a transversal crossing, 2 for a
 * tangency) is smooth with a simple zero. Every node carries x, dx/dz (the
 * tangent, scaled), v and dv/dz (kin__sv_derivative, no factorization), so
 * both are interpolated by Hermite polynomials. The zero z* of the
 * interpolated s gives the bifurcation x(z*) by interpolation, never by a
 * corrector there: near the point the strain constraint fixes a
 * configuration only to about sqrt(tolerance) in the directions of the
 * vanishing singular values (measured: 4e-7 at the hexagonal sail's R^B),
 * while nodes a little away from it are computed to full accuracy. One SVD
 * checks each estimate; if it is not yet within the tolerance a node is
 * added next to the estimate (a forward calculation whose predictor is the
 * interpolant, so it cannot slide onto a neighbouring branch). */
struct hermite_ws {
    int n, nf;
    /* the corank-k mode (kin__locate_hermite): the vanishing group is the
     * lowest singular value and the grp above it; a node carries their sum
     * and its derivative (0: the lowest alone, the corank-1 method) */
    int grp, gsz; /* ... and the size of the top cluster, the node value */
    kin__corank_ws *cw; /* the corank-k Newton's (locate_corank.c) */
    double z[HERMITE_MAX_NODES], v[HERMITE_MAX_NODES], dv[HERMITE_MAX_NODES];
    double err[HERMITE_MAX_NODES]; /* estimated position error of the node */
    double *x, *dx;   /* HERMITE_MAX_NODES * nf each: the nodes */
    double *sx, *sdx; /* HERMITE_MAX_NODES * nf each: the nodes in use, packed */
    double *coef;     /* 2 * HERMITE_MAX_NODES * nf: divided differences */
    double *xs;       /* nf: an interpolated point */
    double *xyz;      /* nj * dim */
    double *e, *y, *d; /* nb, max(nf, nb), nf */
    double *scratch;  /* 2 * nj * dim */
    double *sv;       /* min(nf, nb): a check's singular values */
    double *blk, *uu, *ww; /* LU nodes: the subspace (2 LU_NODE_BLOCK nf), u (nf), w (nb) */
};

void kin__hermite_free(hermite_ws *h)
{
    if (!h) return;
    free(h->x);
    kin__corank_free(h->cw);
    free(h);
}

double *kin__hermite_scratch(hermite_ws *h) { return h->scratch; }

hermite_ws *kin__hermite_alloc(const kin_assembly *a)
{
    hermite_ws *h = calloc(1, sizeof *h);
    if (!h) return NULL;
    size_t nf = (size_t)a->nf, nb = (size_t)a->nb, K = HERMITE_MAX_NODES, nc = (size_t)a->nj * (size_t)a->dim;
    size_t ny = nf > nb ? nf : nb;
    h->nf = a->nf;
    h->x = malloc(sizeof(double) * (K * nf * 6 + nf + nc + nb + ny + nf + 2 * nc + ny + 2 * LU_NODE_BLOCK * nf + nf + nb));
    h->cw = kin__corank_alloc(a);
    if (!h->x || !h->cw) {
        kin__hermite_free(h);
        return NULL;
    }
    h->dx = h->x + K * nf;
    h->sx = h->dx + K * nf;
    h->sdx = h->sx + K * nf;
    h->coef = h->sdx + K * nf;
    h->xs = h->coef + 2 * K * nf;
    h->xyz = h->xs + nf;
    h->e = h->xyz + nc;
    h->y = h->e + nb;
    h->d = h->y + ny;
    h->scratch = h->d + nf;
    h->sv = h->scratch + 2 * nc;
    h->blk = h->sv + ny;
    h->uu = h->blk + 2 * LU_NODE_BLOCK * nf;
    h->ww = h->uu + nf;
    return h;
}

/* One chord polish's acceptance: the corrected point d replaces x (and res
 * becomes its strain residual) only while the residual decreases; else x,
 * xyz and e are left as they were at x. Returns whether to go on. */
static int polish_accept(const kin_assembly *a, double *x, const double *d, double *xyz, double *e, double *res)
{
    kin__scatter(a, d, xyz);
    kin__extensions(a, xyz, e);
    double rn = kin__norm(a->nb, e);
    if (!(rn < *res)) {
        kin__scatter(a, x, xyz);
        kin__extensions(a, xyz, e);
        return 0;
    }
    memcpy(x, d, sizeof(double) * (size_t)a->nf);
    *res = rn;
    return 1;
}

/* A node's parameter along the path from base, z = t_base . (x - x_base),
 * into h->z[h->n], and dx = dx/dz there (its tangent over t . t_base); 0
 * where the tangent is at right angles to base's (no parameter). */
static int node_parameter(hermite_ws *h, const kin_assembly *st, const kin_assembly *base, const double *x, double *dx)
{
    int nf = st->nf;
    kin__gather(base, base->xyz, h->xs);
    double z = 0.0, tt = kin__dot(nf, st->t, base->t);
    for (int i = 0; i < nf; ++i) z += base->t[i] * (x[i] - h->xs[i]);
    if (!(fabs(tt) > 0.0)) return 0;
    for (int i = 0; i < nf; ++i) dx[i] = st->t[i] / tt;
    h->z[h->n] = z;
    return 1;
}

/* Chord corrections x -= sum_{i<r} u_i (w_i^T e) / v_i with factorization
 * f (made at or next to x), while the strain residual |e| decreases, at most
 * maxit times. xyz: full coordinates (fixed ones already in place), kept in
 * step with x. Returns the size (max-norm, length units) of the correction
 * the final point would still take: with f exact there, the error of x in
 * the directions the constraints see (near a bifurcation, |e| / v_min
 * overstates it: the rounding of x itself makes residuals along the large
 * singular values). No factorization. */
static double chord_polish(const kin_assembly *a, const kin_factor *f, int r, double *x, double *xyz, double *e,
                           double *y, double *d, int maxit)
{
    int nf = a->nf, nb = a->nb;
    kin__scatter(a, x, xyz);
    kin__extensions(a, xyz, e);
    double res = kin__norm(nb, e), corr = 0.0;
    for (int it = 0; it <= maxit; ++it) {
        for (int i = 0; i < r; ++i) {
            double sum = 0.0;
            for (int k = 0; k < nb; ++k) sum += f->VT[i + (size_t)k * nb] * e[k];
            y[i] = sum / f->sv[i];
        }
        corr = 0.0;
        for (int j = 0; j < nf; ++j) {
            double sum = 0.0;
            for (int i = 0; i < r; ++i) sum += f->U[j + (size_t)i * nf] * y[i];
            d[j] = x[j] - sum;
            corr = fmax(corr, fabs(sum));
        }
        if (it == maxit || res == 0.0 || !polish_accept(a, x, d, xyz, e, &res)) break;
    }
    return corr;
}

/* Record the analysed state st as a node, parametrised from base: its point
 * polished to the strain floor with its own factorization, and its error
 * estimated by the correction that factorization would still make (near a
 * bifurcation the smallest singular value amplifies what is left of the
 * residual: that is what limits a node's accuracy). */
static int hermite_add(hermite_ws *h, const kin_assembly *st, const kin_assembly *base)
{
    int nf = h->nf, k = kin__loc_vanishing_index(st);
    if (h->n >= HERMITE_MAX_NODES || k < 0) return 0;
    const kin_factor *f = kin__cur(st);
    double *x = h->x + (size_t)h->n * nf, *dx = h->dx + (size_t)h->n * nf;
    kin__gather(st, st->xyz, x);
    memcpy(h->xyz, st->xyz, sizeof(double) * (size_t)(st->nj * st->dim));
    /* in the corank-k mode not along the group: its values are small over
     * the whole neighbourhood (the three of the collapsed hub stay at
     * 1e-8 over +-3e-3), and dividing by them would call every node there
     * inaccurate by what the strain cannot see */
    int r = h->grp > 0 ? k - h->grp : k + 1;
    double corr = chord_polish(st, f, r, x, h->xyz, h->e, h->y, h->d, NODE_POLISH_ITER);
    double floor = DBL_EPSILON * st->rms_length;
    if (!node_parameter(h, st, base, x, dx)) return 0;
    if (k < h->grp) return 0;
    /* the top cluster's sum: smooth where the cluster is apart from the
     * rest, its derivative (a trace) independent of the SVD's basis inside
     * it. Not the values below it: those that vanish to a high order sit at
     * the nodes' rounding (1e-8) over the whole neighbourhood and would add
     * that noise to the zero */
    h->v[h->n] = h->dv[h->n] = 0.0;
    for (int i = k - h->grp; i < k - h->grp + h->gsz; ++i) {
        h->v[h->n] += f->sv[i];
        h->dv[h->n] += kin__sv_derivative(st, f, st->xyz, dx, i, h->scratch);
    }
    h->err[h->n] = fmax(corr, floor);
    h->n++;
    return 1;
}

/* chord_polish with the LU-mode factors of st (made at xyz, the point x):
 * the same minimum-norm corrections pinv(C) e, by solves with them. dc
 * (nf) holds a correction, d the corrected point. */
static double chord_polish_lu(kin_assembly *st, double *x, double *xyz, double *e, double *dc, double *d, int maxit)
{
    int nf = st->nf, nb = st->nb;
    kin__scatter(st, x, xyz);
    kin__extensions(st, xyz, e);
    double res = kin__norm(nb, e), corr = 0.0;
    for (int it = 0; it <= maxit; ++it) {
        if (kin__lu_pinv_correction(st, e, dc) != KIN_OK) return INFINITY;
        corr = 0.0;
        for (int j = 0; j < nf; ++j) {
            d[j] = x[j] - dc[j];
            corr = fmax(corr, fabs(dc[j]));
        }
        if (it == maxit || res == 0.0 || !polish_accept(st, x, d, xyz, e, &res)) break;
    }
    return corr;
}

/* hermite_add for a state st that has the LU mode's factors and no SVD (a
 * forward calculation with loc_ctx.lu_nodes): the vanishing singular value
 * and its vectors by subspace iteration with those factors, the polish by
 * their minimum-norm corrections (the same quantities as the SVD's, to
 * rounding). Returns 1 (added), 0 (no room, or no vanishing index) or -1:
 * the triple did not converge (the caller analyses st by SVD). */
static int hermite_add_lu(hermite_ws *h, kin_assembly *st, const kin_assembly *base)
{
    int nf = h->nf, nb = st->nb, mn = nf < nb ? nf : nb;
    const kin_lufactor *F = &st->lu[st->lu_cur];
    int k = nf - 2 - (F->rows - nb - 1); /* nf - 2 - m_rigid, as kin__loc_vanishing_index */
    if (h->n >= HERMITE_MAX_NODES || k < 0 || k >= mn) return 0;
    int warm = 0, conv = 0;
    double v = 0.0;
    if (kin__lu_vr_triple(st, LU_NODE_PASSES, LU_NODE_VECTOR_TOL, LU_NODE_BLOCK, h->blk, &warm, h->uu, h->ww, &v,
                          &conv) != KIN_OK ||
        !conv || !(v > 0.0))
        return -1;
    double *x = h->x + (size_t)h->n * nf, *dx = h->dx + (size_t)h->n * nf;
    kin__gather(st, st->xyz, x);
    memcpy(h->xyz, st->xyz, sizeof(double) * (size_t)(st->nj * st->dim));
    double corr = chord_polish_lu(st, x, h->xyz, h->e, h->y, h->d, NODE_POLISH_ITER);
    if (!isfinite(corr)) return -1;
    double floor = DBL_EPSILON * st->rms_length;
    if (!node_parameter(h, st, base, x, dx)) return 0;
    h->v[h->n] = v;
    h->dv[h->n] = kin__sv_derivative_uw(st, st->xyz, dx, h->uu, h->ww, h->scratch);
    h->err[h->n] = fmax(corr, floor);
    h->n++;
    return 1;
}

int kin__hermite_lu_vanishing(hermite_ws *h, kin_assembly *st, double dir, double *v, double *sl)
{
    int warm = 0, conv = 0;
    if (kin__lu_vr_triple(st, LU_NODE_PASSES, LU_NODE_VECTOR_TOL, LU_NODE_BLOCK, h->blk, &warm, h->uu, h->ww, v,
                          &conv) != KIN_OK ||
        !conv || !(*v > 0.0))
        return 0;
    *sl = dir * kin__sv_derivative_uw(st, st->xyz, st->t, h->uu, h->ww, h->scratch);
    return 1;
}

/* Hermite divided differences of `dim`-vectors f (values) and df
 * (derivatives) at the n nodes z, each taken twice (zz = z0 z0 z1 z1 ...),
 * into coef (2n x dim, row j = f[zz_0 .. zz_j]) */
static void hermite_coef(int n, const double *z, int dim, const double *f, const double *df, double *coef)
{
    int K = 2 * n;
    for (int i = 0; i < K; ++i) memcpy(coef + (size_t)i * dim, f + (size_t)(i / 2) * dim, sizeof(double) * dim);
    for (int j = 1; j < K; ++j)
        for (int i = K - 1; i >= j; --i) {
            double *ci = coef + (size_t)i * dim;
            const double *cm = coef + (size_t)(i - 1) * dim;
            if (j == 1 && (i % 2) == 1) {
                memcpy(ci, df + (size_t)(i / 2) * dim, sizeof(double) * dim); /* repeated node */
            } else {
                double dz = z[i / 2] - z[(i - j) / 2];
                for (int r = 0; r < dim; ++r) ci[r] = (ci[r] - cm[r]) / dz;
            }
        }
}

static void hermite_eval(int n, const double *z, int dim, const double *coef, double at, double *out)
{
    int K = 2 * n;
    memcpy(out, coef + (size_t)(K - 1) * dim, sizeof(double) * dim);
    for (int j = K - 2; j >= 0; --j)
        for (int r = 0; r < dim; ++r) out[r] = out[r] * (at - z[j / 2]) + coef[(size_t)j * dim + r];
}

/* signed, smooth form of the vanishing singular value at node i for order p:
 * in z, s = sign(dv/dz) v^(1/p) increases through its zero whichever way
 * the motion runs, and ds/dz = |d v^(1/p) / dz| */
static void signed_sv(const hermite_ws *h, int i, int p, double *s, double *ds)
{
    double v = h->v[i], dv = h->dv[i], sg = dv < 0.0 ? -1.0 : 1.0;
    if (p == 1) {
        *s = sg * v;
        *ds = fabs(dv);
    } else {
        double r = pow(v, 1.0 / p);
        *s = sg * r;
        *ds = v > 0.0 ? fabs(dv) * r / (p * v) : 0.0;
    }
}

/* The located test: the largest singular value of the vanishing group
 * (detect.c's, by the ratio gap), and in the corank-k mode also the top of
 * the group the bracket showed (h->grp above the lowest, k): every one of
 * them must meet the tolerance. From singular values alone (descending). */
static double group_top_sv(const hermite_ws *h, const double *sv, int k, double tol)
{
    double top = kin__loc_group_top_sv(sv, k, tol);
    return h->grp > 0 && k >= h->grp ? fmax(top, sv[k - h->grp]) : top;
}

/* ... of the analysed a, its v_max into *vmax */
static double group_top(const hermite_ws *h, const kin_assembly *a, double tol, double *vmax)
{
    int k = kin__loc_vanishing_index(a);
    *vmax = kin__cur(a)->an.v_max;
    return k < 0 ? kin__loc_group_top(a, tol) : group_top_sv(h, kin__cur(a)->sv, k, tol);
}

/* An estimate from the nodes with use[i] != 0: the adjacent pair (lo, hi)
 * between which v turns from decreasing to increasing in z, the order p of
 * the zero, z*, and (if want_x) x(z*) into h->xs with the x interpolant's
 * coefficients kept in h->coef over the used nodes (their z in zu, count
 * *nu). Returns 0 without such a pair. */
typedef struct herm_est {
    int lo, hi, p, nu;
    double zs, zu[HERMITE_MAX_NODES];
} herm_est;

static int hermite_estimate(hermite_ws *h, const int *use, int want_x, herm_est *E)
{
    int n = h->n, ord[HERMITE_MAX_NODES], nu = 0;
    for (int i = 0; i < n; ++i)
        if (use[i]) ord[nu++] = i;
    for (int i = 1; i < nu; ++i)
        for (int j = i; j > 0 && h->z[ord[j]] < h->z[ord[j - 1]]; --j) {
            int t = ord[j];
            ord[j] = ord[j - 1];
            ord[j - 1] = t;
        }
    int lo = -1, hi = -1;
    for (int j = 0; j + 1 < nu && lo < 0; ++j)
        if (h->dv[ord[j]] < 0.0 && h->dv[ord[j + 1]] > 0.0) {
            lo = ord[j];
            hi = ord[j + 1];
        }
    if (lo < 0) return 0;
    /* order of the zero: v/v' = (z - z*)/p at both ends of the bracket */
    double pe = (h->z[hi] - h->z[lo]) / (h->v[hi] / h->dv[hi] - h->v[lo] / h->dv[lo]);
    int p = isfinite(pe) && pe > 1.5 ? 2 : 1;
    if (p > MAX_ZERO_ORDER) p = MAX_ZERO_ORDER;
    double s[HERMITE_MAX_NODES], ds[HERMITE_MAX_NODES], c1[2 * HERMITE_MAX_NODES];
    for (int j = 0; j < nu; ++j) {
        E->zu[j] = h->z[ord[j]];
        signed_sv(h, ord[j], p, &s[j], &ds[j]);
    }
    hermite_coef(nu, E->zu, 1, s, ds, c1);
    double a = h->z[lo], b = h->z[hi], fa;
    hermite_eval(nu, E->zu, 1, c1, a, &fa);
    for (int it = 0; it < ROOT_BISECTIONS; ++it) {
        double mid = 0.5 * (a + b), fm;
        if (!(mid > a && mid < b)) break;
        hermite_eval(nu, E->zu, 1, c1, mid, &fm);
        if ((fm < 0.0) == (fa < 0.0)) {
            a = mid;
            fa = fm;
        } else {
            b = mid;
        }
    }
    E->zs = 0.5 * (a + b);
    E->lo = lo;
    E->hi = hi;
    E->p = p;
    E->nu = nu;
    if (want_x) {
        size_t nf = (size_t)h->nf;
        for (int j = 0; j < nu; ++j) {
            memcpy(h->sx + j * nf, h->x + (size_t)ord[j] * nf, sizeof(double) * nf);
            memcpy(h->sdx + j * nf, h->dx + (size_t)ord[j] * nf, sizeof(double) * nf);
        }
        hermite_coef(nu, E->zu, h->nf, h->sx, h->sdx, h->coef);
        hermite_eval(nu, E->zu, h->nf, h->coef, E->zs, h->xs);
    }
    return 1;
}


/* Where the next node goes. Nodes nearer the bifurcation than rho_min are
 * not accurate enough (their error grows as v shrinks), so new nodes
 * sit at z* +- rho, rho = max(1.5 rho_min, NODE_OFFSET_FRACTION x the
 * bracket) and then further out, first on a side that has no accurate
 * node, else on the side whose nearest accurate node is farther. */
static double next_node(const hermite_ws *h, const int *good, const herm_est *E, double rho_min, double width0)
{
    double near[2] = {INFINITY, INFINITY}; /* nearest accurate node left / right of z* */
    for (int i = 0; i < h->n; ++i)
        if (good[i]) {
            double dz = h->z[i] - E->zs;
            int side = dz > 0.0;
            if (fabs(dz) < near[side]) near[side] = fabs(dz);
        }
    double zl = fmin(h->z[E->lo], h->z[E->hi]), zh = fmax(h->z[E->lo], h->z[E->hi]);
    double base = fmax(NODE_OFFSET_FRACTION * fmax(E->zs - zl, zh - E->zs), NODE_OFFSET_MIN * width0);
    double rho = fmax(NODE_RHO_MARGIN * rho_min, base);
    int side = near[1] > near[0]; /* the side with the farther (or no) accurate node */
    double gap = near[side];
    /* at z* +- rho, unless an accurate node is already within twice rho on
     * that side: then one rho beyond it, to widen the interpolant's span */
    double off = isfinite(gap) && gap <= 2.0 * rho ? gap + rho : rho;
    return E->zs + (side ? off : -off);
}

/* The corank-k mode's check point c->work (analysed; its free coordinates
 * in h->xs) brought onto the bifurcation: Gauss-Newton steps on the group's
 * k x k block (kin__corank_step), each followed by chord corrections along
 * the singular values above the group (the strain the step made there) and
 * an analysis, while the group's top shrinks, at most CORANK_NEWTON_ITER.
 * *vv, *vmax, *strain: the point's located test, v_max and strain; a point
 * that does not improve the test is not kept. A status. */
static int corank_refine(loc_ctx *c, double *vv, double *vmax, double *strain)
{
    hermite_ws *h = c->hw;
    kin_assembly *w = c->work;
    int nf = h->nf;
    double *x = h->sx, *x0 = h->sx + nf; /* the trial and the best point (nodes not in use now) */
    memcpy(x0, h->xs, sizeof(double) * (size_t)nf);
    /* a check that failed on its singular values alone has no vectors yet */
    int rc0 = kin__cur(w)->valid ? KIN_OK : kin__analyse_into(w, w->xyz, w->cur);
    if (rc0) return rc0;
    *vv = group_top(h, w, c->o->vr_tol, vmax);
    for (int it = 0; it < CORANK_NEWTON_ITER && !(*vv <= c->o->vr_tol * *vmax); ++it) {
        double step = 0.0;
        memcpy(x, x0, sizeof(double) * (size_t)nf);
        int rc = kin__corank_step(w, h->grp, h->cw, x, &step);
        if (rc == KIN_EINVAL) break;
        if (rc) return rc;
        int k = kin__loc_vanishing_index(w);
        if (k < h->grp) break;
        chord_polish(w, kin__cur(w), k - h->grp, x, w->xyz, h->e, h->y, h->d, POLISH_MAX_ITER);
        if ((rc = kin__analyse_into(w, w->xyz, w->cur)) != KIN_OK) return rc;
        double nm, nv = group_top(h, w, c->o->vr_tol, &nm), ns = kin__lengths(w, w->xyz, NULL);
        TRACE("  corank Newton %d: step %.3g, group top %.3g, strain %.2g\n", it, step, nv / nm, ns);
        if (!(nv / nm < *vv / *vmax)) break;
        *vv = nv;
        *vmax = nm;
        *strain = ns;
        memcpy(x0, x, sizeof(double) * (size_t)nf);
    }
    /* the state is the best point's: analyse it again where the last trial was worse */
    memcpy(h->xs, x0, sizeof(double) * (size_t)nf);
    kin__scatter(w, x0, w->xyz);
    return kin__analyse_into(w, w->xyz, w->cur);
}

/* One Hermite location between c->prev and c->a (the bracketing step) on
 * the node value h->grp selects. On success c->work sits on the
 * bifurcation, analysed. Returns KIN_OK, KIN__HERMITE_NO_BRACKET (the
 * vanishing singular value does not turn within the step: the caller may
 * fall back on the test function), KIN_ENOTFOUND, or a step/LAPACK code. */
static int hermite_run(loc_ctx *c)
{
    hermite_ws *h = c->hw;
    kin_assembly *prev = c->prev, *w = c->work;
    int nf = h->nf, all[HERMITE_MAX_NODES], good[HERMITE_MAX_NODES];
    h->n = 0;
    /* prev may be the follower's LU point (no SVD): its node from the LU
     * factors, or its SVD where the triple does not converge */
    int added = kin__cur(prev)->valid ? -1 : hermite_add_lu(h, prev, prev);
    if (added < 0 && !kin__cur(prev)->valid) {
        int rc = kin__analyse(prev, NULL);
        if (rc) return rc;
    }
    if (added < 0) added = hermite_add(h, prev, prev);
    if (!added) return KIN__HERMITE_NO_BRACKET;
    /* the bracket's end: the SVD locator's step analysed it; the
     * follower's own LU step to it (kin__locate_ws.direct_prev) did not */
    int added_end = kin__cur(c->a)->valid || !c->lu_nodes ? -1 : hermite_add_lu(h, c->a, prev);
    if (added_end < 0 && !kin__cur(c->a)->valid) {
        int rc = kin__analyse(c->a, NULL);
        if (rc) return rc;
    }
    if (added_end < 0) added_end = hermite_add(h, c->a, prev);
    if (!added_end) return KIN__HERMITE_NO_BRACKET;
    double width0 = fabs(h->z[1] - h->z[0]);
    double err_ok = NODE_ERROR_FRACTION * c->o->vr_tol * prev->rms_length;
    for (int i = 0; i < HERMITE_MAX_NODES; ++i) all[i] = 1;
    herm_est E;
    if (!hermite_estimate(h, all, 0, &E)) return KIN__HERMITE_NO_BRACKET;
    int checked = 0, stalls = 0; /* accurate nodes at the last check; checks without progress */
    double best = INFINITY;
    for (int it = 0; it < c->o->max_iter && h->n <= HERMITE_MAX_NODES; ++it) {
        if (kin__loc_cancelled(c)) return KIN_ECANCELLED;
        int ngood = 0;
        for (int i = 0; i < h->n; ++i) ngood += good[i] = h->err[i] <= err_ok;
        /* the estimate: from the accurate nodes once they bracket the zero,
         * else (roughly) from all */
        int from_good = ngood >= 2 && hermite_estimate(h, good, 1, &E);
        if (!from_good && !hermite_estimate(h, all, 0, &E)) break;
        c->info->zero_order = E.p;
        if (from_good && ngood > checked) {
            checked = ngood;
            /* check the estimate: one SVD at the interpolated point. Its
             * singular values first (no vectors: 0.09 against 0.23 ms on the
             * hexagonal sail): of 4.3 checks per location on the flat
             * state's benchmark 3.5 fail, and a failed check needs nothing
             * else; one that passes is analysed in full, and its own values
             * decide, as before */
            kin__copy_state(w, prev);
            kin__scatter(w, h->xs, w->xyz);
            int kv = kin__loc_vanishing_index(prev), rc;
            double vv = INFINITY, vmax = 0.0;
            if (kv >= 0) {
                if ((rc = kin__singular_values(w, w->xyz, h->sv)) != KIN_OK) return rc;
                w->fac[w->cur].valid = 0; /* prev's analysis, not this point's */
                vv = group_top_sv(h, h->sv, kv, c->o->vr_tol);
                vmax = h->sv[0];
            }
            if (kv >= 0 && !(vv <= c->o->vr_tol * vmax)) {
                w->nfact++; /* this point's one factorization */
            } else {
                if ((rc = kin__analyse_into(w, w->xyz, w->cur)) != KIN_OK) return rc;
                vv = group_top(h, w, c->o->vr_tol, &vmax);
            }
            double strain = kin__lengths(w, w->xyz, NULL);
            TRACE("  check %d nodes (%d accurate): z* = %.12g (order %d), v_r %.3g, strain %.2g\n", h->n, ngood,
                  E.zs, E.p, vv / vmax, strain);
            if (vv <= c->o->vr_tol * vmax && !(strain <= kin__corrector_tol(w))) {
                /* the interpolant is off the strain-free set by its error,
                 * along well-conditioned directions: remove that with the
                 * point's own factorization, leaving the bifurcation's null
                 * directions alone, then analyse the corrected point */
                const kin_factor *f = kin__cur(w);
                int mn = nf < w->nb ? nf : w->nb, r = 0;
                double cut = POLISH_CUT * c->o->vr_tol * vmax;
                while (r < mn && f->sv[r] > cut) ++r;
                chord_polish(w, f, r, h->xs, w->xyz, h->e, h->y, h->d, POLISH_MAX_ITER);
                rc = kin__analyse_into(w, w->xyz, w->cur);
                if (rc) return rc;
                vv = group_top(h, w, c->o->vr_tol, &vmax);
                strain = kin__lengths(w, w->xyz, NULL);
            }
            if (h->grp > 0 && !(vv <= c->o->vr_tol * vmax) && (rc = corank_refine(c, &vv, &vmax, &strain)) != KIN_OK)
                return rc;
            if (vv <= c->o->vr_tol * vmax && strain <= kin__corrector_tol(w)) {
                /* the path length: chords from the last regular point */
                double *ch = w->chord;
                kin__gather(w, prev->xyz, ch);
                for (int i = 0; i < nf; ++i) ch[i] = h->xs[i] - ch[i];
                w->l = prev->l + (E.zs < 0.0 ? -1.0 : 1.0) * kin__norm(nf, ch);
                w->have_t = w->t_chosen = 0;
                return KIN_OK;
            }
            double vr = vv / vmax;
            stalls = vr > MIN_PROGRESS * best ? stalls + 1 : 0;
            best = fmin(best, vr);
            if (stalls >= MAX_STALLS) break;
        }
        if (h->n >= HERMITE_MAX_NODES) break;
        /* the singular value a node needs to be accurate enough, and the
         * distance from z* where v reaches it: v ~ cc |z - z*|^p, cc from
         * the accurate node nearest z* on each side; the noise of a node is
         * its error times its v */
        double noise = 0.0, rho_min = 0.0, nearest[2] = {INFINITY, INFINITY};
        int near_i[2] = {-1, -1};
        for (int i = 0; i < h->n; ++i) {
            if (!good[i]) {
                /* nodes nearer than an inaccurate one will be no better */
                rho_min = fmax(rho_min, fabs(h->z[i] - E.zs));
                continue;
            }
            noise = fmax(noise, h->err[i] * h->v[i]);
            double dz = h->z[i] - E.zs;
            int side = dz > 0.0;
            if (fabs(dz) < nearest[side]) {
                nearest[side] = fabs(dz);
                near_i[side] = i;
            }
        }
        for (int side = 0; side < 2; ++side)
            if (near_i[side] >= 0) {
                double cc = h->v[near_i[side]] / pow(nearest[side], E.p);
                double r = pow(noise / err_ok / cc, 1.0 / E.p);
                if (isfinite(r) && r > rho_min) rho_min = r;
            }
        /* a new node, predicted by the cubic through the two accurate nodes
         * nearest to it (a high-degree interpolant extrapolates badly) */
        double zn = next_node(h, good, &E, rho_min, width0);
        int i1 = -1, i2 = -1;
        for (int i = 0; i < h->n; ++i) {
            if (!good[i]) continue;
            if (i1 < 0 || fabs(h->z[i] - zn) < fabs(h->z[i1] - zn)) {
                i2 = i1;
                i1 = i;
            } else if (i2 < 0 || fabs(h->z[i] - zn) < fabs(h->z[i2] - zn)) {
                i2 = i;
            }
        }
        if (i2 < 0) {
            i1 = 0;
            i2 = 1;
        }
        double zp[2] = {h->z[i1], h->z[i2]};
        memcpy(h->sx, h->x + (size_t)i1 * nf, sizeof(double) * (size_t)nf);
        memcpy(h->sx + nf, h->x + (size_t)i2 * nf, sizeof(double) * (size_t)nf);
        memcpy(h->sdx, h->dx + (size_t)i1 * nf, sizeof(double) * (size_t)nf);
        memcpy(h->sdx + nf, h->dx + (size_t)i2 * nf, sizeof(double) * (size_t)nf);
        hermite_coef(2, zp, nf, h->sx, h->sdx, h->coef);
        hermite_eval(2, zp, nf, h->coef, zn, h->xs);
        /* from the end of the first bracket on zn's side: the corrector keeps
         * the correction orthogonal to that end's tangent */
        double span = h->z[1] - h->z[0];
        const kin_assembly *from = (zn - h->z[0]) * span > span * span ? c->a : prev;
        double dz = 0.0, *x0 = w->chord;
        kin__gather(from, from->xyz, x0);
        for (int i = 0; i < nf; ++i) dz += from->t[i] * (h->xs[i] - x0[i]);
        kin__copy_state(w, from);
        c->info->forward++;
        if (c->lu_nodes) {
            /* the LU mode's factors at the node (the SVD where it is not regular) */
            w->opt.factorization = KIN_STEP_LU;
            w->lu_inverse = w->lu_predicted = 1;
        }
        int rc = kin__step_predicted(w, dz, h->xs, NULL);
        w->opt.factorization = KIN_STEP_SVD;
        w->lu_inverse = w->lu_predicted = 0;
        if (rc == KIN_ENOTCONVERGED || rc == KIN_EPATHJUMP || rc == KIN_ENOMECH) break;
        if (rc) return rc;
        double jump = 0.0;
        kin__gather(w, w->xyz, x0);
        for (int i = 0; i < nf; ++i) jump = fmax(jump, fabs(x0[i] - h->xs[i]));
        if (jump > NODE_JUMP_FRACTION * fabs(zn - E.zs)) break; /* onto a neighbouring branch */
        int added = kin__cur(w)->valid ? -1 : hermite_add_lu(h, w, prev);
        if (added < 0 && !kin__cur(w)->valid && (rc = kin__analyse_into(w, w->xyz, w->cur)) != KIN_OK) return rc;
        if (added < 0) added = hermite_add(h, w, prev);
        if (!added) break;
        TRACE("  node %d at z = %.12g (estimate %.12g, rho_min %.3g): v %.3g, error %.3g\n", h->n - 1, h->z[h->n - 1],
              E.zs, rho_min, h->v[h->n - 1], h->err[h->n - 1]);
    }
    /* no certified point. v_r brought below sqrt(vr_tol) means a
     * bifurcation pinned only so far (a tangency, where v_r ~ |l - l*|^2 and
     * the strain fixes a point less sharply) or a near miss of that size;
     * above that, a non-zero minimum of v_r */
    double vmax0 = kin__cur(prev)->valid ? kin__cur(prev)->an.v_max : prev->lu[prev->lu_cur].v_max;
    for (int i = 0; i < h->n; ++i) best = fmin(best, h->v[i] / vmax0); /* points of the path, too */
    if (best <= sqrt(c->o->vr_tol))
        return kin__fail(c->a, KIN_ENOTFOUND,
                         "a bifurcation (v_r ~ |l - l*|^%d) was located only to v_r = %.2g relative, above "
                         "vr_tol = %.2g: the attainable accuracy here, or a near miss of that size (a larger "
                         "vr_tol accepts it)",
                         E.p, best, c->o->vr_tol);
    c->nonzero_min = best;
    return kin__fail(c->a, KIN_ENOTFOUND,
                     "v_r has a non-zero minimum (%.3g relative) here: a near-singular but regular configuration",
                     best);
}

/* ---- several singular values vanishing together (corank k) -------------
 *
 * Where k > 1 singular values vanish at one point they need not vanish
 * alike: on the hexagonal sail's collapsed-hub state three go like a high
 * power of the distance (at or below 1e-8 of v_max over +-3e-3 of path, the
 * rounding of the nodes' positions is larger than their values there) while
 * a symmetric pair crosses zero linearly at the same point. The lowest alone
 * then pins nothing: the corank-1 method wanders in the flat stretch and
 * gives up ("located only to ..."), and a relaxed tolerance accepts a point
 * up to 7.6e-3 away whose pair is still 6e-4. The corank-k mode finds the
 * group from the bracket's two ends and locates the zero of its top
 * cluster (the sum of the values of the highest cluster of the group, each
 * >= 0, so the sum vanishes exactly where all of them do), the one that
 * fixes the point sharply; the located test requires every value of the
 * group below the tolerance. */

/* Two singular values closer than this (relative) at a bracket's end are
 * one cluster (a degenerate pair of a symmetric structure): a group never
 * cuts through one, where the basis inside it would decide. */
static const double CLUSTER_RTOL = 1e-6;
/* A cluster vanishes over the bracket when it turns (falls at the start,
 * rises at the end, in the chord's direction) and its two tangent lines
 * meet at most this fraction of its lower end value high: a V through zero
 * (their meeting point lies near or below zero) and not a smooth non-zero
 * minimum (which its tangents meet just below the minimum). */
static const double VANISH_MEET_FRACTION = 0.5;
/* at most this many singular values above the lowest (the flat state of the
 * hexagonal sail has 15 vanishing together) */
enum { MAX_GROUP = 31 };

/* The values d[i] (i in [lo, hi]) of the cluster's mean derivative along
 * the unit chord dir at st; its mean value into *v */
static double cluster_slope(const kin_assembly *st, const double *dir, int lo, int hi, double *v, double *scratch)
{
    const kin_factor *f = kin__cur(st);
    double dv = 0.0;
    *v = 0.0;
    for (int i = lo; i <= hi; ++i) {
        *v += f->sv[i];
        dv += kin__sv_derivative(st, f, st->xyz, dir, i, scratch);
    }
    return dv / (hi - lo + 1);
}

/* A cluster monotone over the bracket whose tangent line at the nearer end
 * reaches zero within this fraction of the bracket beyond that end vanishes
 * just outside it: the detector's bracket is the lowest value's, and where
 * that one is flat (the collapsed hub's three) it may turn a step after the
 * steep pair crossed */
static const double OUTSIDE_FRACTION = 0.5;

/* the group's top cluster: its size, and where it vanishes outside the
 * bracket (outside != 0), the predicted point: s along the unit chord from
 * the start (negative: behind it) */
typedef struct group_top_cluster {
    int size, outside;
    double s;
} group_top_cluster;

/* How many singular values above the lowest vanish with it over the
 * bracket [c->prev, c->a] (both analysed by SVD): the highest cluster below
 * switch_eps * v_max whose values vanish there (VANISH_MEET_FRACTION) or
 * just outside (OUTSIDE_FRACTION). The chord's unit direction is left in
 * h->d. */
static int vanishing_group(loc_ctx *c, group_top_cluster *tc)
{
    hermite_ws *h = c->hw;
    const kin_assembly *p = c->prev, *a = c->a;
    const kin_factor *fp = kin__cur(p), *fa = kin__cur(a);
    int k = kin__loc_vanishing_index(p), nf = h->nf, grp = 0;
    if (k < 1 || k != kin__loc_vanishing_index(a)) return 0;
    double *dir = h->d, *xa = h->xs;
    kin__gather(p, p->xyz, dir);
    kin__gather(a, a->xyz, xa);
    for (int i = 0; i < nf; ++i) dir[i] = xa[i] - dir[i];
    double w = kin__norm(nf, dir);
    if (!(w > 0.0)) return 0;
    for (int i = 0; i < nf; ++i) dir[i] /= w;
    double cut = c->o->switch_eps * fmax(fp->an.v_max, fa->an.v_max);
    for (int hi = k - 1; hi >= 0 && k - hi <= MAX_GROUP;) {
        int lo = hi;
        while (lo > 0 && fp->sv[lo - 1] - fp->sv[lo] <= CLUSTER_RTOL * fp->sv[lo - 1] &&
               fa->sv[lo - 1] - fa->sv[lo] <= CLUSTER_RTOL * fa->sv[lo - 1])
            --lo;
        double v0, v1, d0 = cluster_slope(p, dir, lo, hi, &v0, h->scratch);
        double d1 = cluster_slope(a, dir, lo, hi, &v1, h->scratch);
        v0 /= hi - lo + 1;
        v1 /= hi - lo + 1;
        if (fmin(v0, v1) > cut) break;
        /* the tangent lines v0 + d0 s and v1 + d1 (s - w) meet at s* */
        double s = (v1 - v0 - d1 * w) / (d0 - d1), meet = v0 + d0 * s;
        int inside = d0 < 0.0 && d1 > 0.0 && meet <= VANISH_MEET_FRACTION * fmin(v0, v1);
        /* monotone: the zero of the tangent line at the lower end */
        double zs = v0 <= v1 ? -v0 / d0 : w - v1 / d1;
        int outside = !inside && d0 * d1 > 0.0 && (v0 <= v1 ? zs < 0.0 : zs > w) &&
                      fabs(v0 <= v1 ? zs : zs - w) <= OUTSIDE_FRACTION * w;
        if ((inside || outside) && k - lo <= MAX_GROUP) {
            grp = k - lo;
            tc->size = hi - lo + 1;
            tc->outside = outside;
            tc->s = zs;
        }
        TRACE("  group: values %d..%d at %.3g / %.3g, slopes %.3g / %.3g, tangents meet at %.3g%s\n", lo, hi, v0, v1,
              d0, d1, meet, grp == k - lo ? (outside ? " (vanishing outside)" : " (vanishing)") : "");
        hi = lo - 1;
    }
    return grp;
}

/* The corank-k mode where the top cluster vanishes just outside the
 * bracket: from the point s along the unit chord h->d from c->prev (its
 * tangent line's zero), the Newton of corank_refine alone. On success
 * c->work sits on the bifurcation, analysed. KIN_OK, KIN_ENOTFOUND or a
 * status. */
static int corank_outside(loc_ctx *c, double s)
{
    hermite_ws *h = c->hw;
    kin_assembly *w = c->work, *prev = c->prev;
    int nf = h->nf, rc;
    /* onto the path there: a forward calculation along prev's tangent */
    double used = 0.0;
    rc = kin__loc_forward(c, prev, w, s * kin__dot(nf, prev->t, h->d), &used);
    if (rc == KIN_ENOTCONVERGED || rc == KIN_EPATHJUMP || rc == KIN_ENOMECH)
        return kin__fail(c->a, KIN_ENOTFOUND, "the forward calculation to a corank-%d point failed", h->grp + 1);
    if (rc) return rc;
    kin__gather(w, w->xyz, h->xs);
    if (!kin__cur(w)->valid && (rc = kin__analyse_into(w, w->xyz, w->cur)) != KIN_OK) return rc;
    double vmax, vv = group_top(h, w, c->o->vr_tol, &vmax), strain = kin__lengths(w, w->xyz, NULL);
    TRACE("  corank-k outside the bracket: from s = %.6g, group top %.3g\n", s, vv / vmax);
    if ((rc = corank_refine(c, &vv, &vmax, &strain)) != KIN_OK) return rc;
    if (!(vv <= c->o->vr_tol * vmax && strain <= kin__corrector_tol(w)))
        return kin__fail(c->a, KIN_ENOTFOUND,
                         "%d singular values vanish together here; their Newton reached only v_r = %.2g relative, "
                         "above vr_tol = %.2g", h->grp + 1, vv / vmax, c->o->vr_tol);
    kin__gather(w, prev->xyz, w->chord);
    double z = 0.0;
    for (int i = 0; i < nf; ++i) {
        w->chord[i] = h->xs[i] - w->chord[i];
        z += prev->t[i] * w->chord[i];
    }
    w->l = prev->l + (z < 0.0 ? -1.0 : 1.0) * kin__norm(nf, w->chord);
    w->have_t = w->t_chosen = 0;
    return KIN_OK;
}

/* Locate between c->prev and c->a (the bracketing step). On success c->work
 * sits on the bifurcation, analysed. The corank-1 method first, as it
 * always was; where the bracket shows more singular values vanishing with
 * the lowest (vanishing_group) and that method gave up or left one of them
 * above the tolerance, the corank-k mode on the group's sum, with SVD nodes.
 * Returns KIN_OK, KIN__HERMITE_NO_BRACKET (the vanishing singular value does
 * not turn within the step: the caller may fall back on the test function),
 * KIN_ENOTFOUND, or a step/LAPACK code. */
int kin__locate_hermite(loc_ctx *c)
{
    hermite_ws *h = c->hw;
    h->grp = 0;
    h->gsz = 1;
    int rc = hermite_run(c);
    if (rc != KIN_OK && rc != KIN_ENOTFOUND) return rc;
    /* a corank-1 success from LU ends (the follower's cheap steps): as before */
    if (rc == KIN_OK && !(kin__cur(c->prev)->valid && kin__cur(c->a)->valid)) return rc;
    int r2;
    if (!kin__cur(c->prev)->valid && (r2 = kin__analyse(c->prev, NULL)) != KIN_OK) return r2;
    if (!kin__cur(c->a)->valid && (r2 = kin__analyse(c->a, NULL)) != KIN_OK) return r2;
    group_top_cluster tc = {1, 0, 0.0};
    int grp = vanishing_group(c, &tc);
    if (grp == 0) return rc;
    if (rc == KIN_OK) {
        int k = kin__loc_vanishing_index(c->work);
        const kin_factor *f = kin__cur(c->work);
        if (k < grp || f->sv[k - grp] <= c->o->vr_tol * f->an.v_max) return rc;
    }
    TRACE("  corank-%d mode (the lowest and %d above it)\n", grp + 1, grp);
    int lu = c->lu_nodes, first = rc;
    double nonzero_min = c->nonzero_min;
    h->grp = grp;
    h->gsz = tc.size;
    c->lu_nodes = 0;
    c->nonzero_min = 0.0;
    rc = tc.outside ? corank_outside(c, tc.s) : hermite_run(c);
    h->grp = 0;
    h->gsz = 1;
    c->lu_nodes = lu;
    if (rc == KIN_OK || rc != KIN_ENOTFOUND) return rc;
    /* the group's sum did not reach the tolerance either: the corank-1
     * answer stands (its point again, where it had one; its minimum) */
    c->nonzero_min = nonzero_min;
    return first == KIN_OK ? hermite_run(c) : rc;
}
