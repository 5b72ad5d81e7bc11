/* Detecting and converging onto bifurcation points (paper section 4) with a
 * signed test function; see kin_locate.h. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"
#include "lapack.h"

/* Developer trace of the fast method: build with -DKIN_LOCATE_TRACE. */
#ifdef KIN_LOCATE_TRACE
#include <stdio.h>
#define TRACE(...) fprintf(stderr, __VA_ARGS__)
#else
#define TRACE(...) ((void)0)
#endif

/* eq. 26: the path is kept if the new tangent agrees with the old one to this |cos| */
static const double PATH_KEPT_COS = 0.9;
/* overshoot probe of the paper's method, as a fraction of the trial delta */
static const double PROBE_FRACTION = 1e-3;
/* the paper's method gives up when delta has shrunk below this fraction of
 * the step without reaching the tolerance: v_r has a non-zero minimum */
static const double GIVE_UP_FRACTION = 1e-9;
/* while locating, singular values count as zero only below this fraction of
 * the target tolerance, so that the test function keeps its sign (and the
 * analysis its single mechanism) until the target is met */
static const double LOCATE_RANK_FRACTION = 1e-3;
/* m and s at a located point are counted with rank tolerance at least this
 * multiple of vr_tol: the point is only that exact */
static const double LOCATED_RANK_MARGIN = 10.0;

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
/* bisection steps for the root of the interpolated signed singular value */
enum { ROOT_BISECTIONS = 100 };
/* steps the fast method follows past a sign change of the test function at
 * which v_r is still decreasing, looking for v_r to turn */
enum { TAU_LOOK_AHEAD = 2 };

void kin_locate_options_default(kin_locate_options *o)
{
    if (!o) return;
    memset(o, 0, sizeof *o);
    o->size = sizeof *o;
    o->method = KIN_LOCATE_FAST;
    o->vr_tol = 1e-10;
    o->switch_eps = 1e-2;
    o->delta = 0.0;
    o->max_steps = 1000;
    o->max_iter = 60;
    o->use_switch_rule = 1;
}

int kin_test_function(kin_assembly *a, double *tau)
{
    if (!a || !tau) return KIN_ENULL;
    if (!kin__cur(a)->valid) {
        int rc = kin_analyse(a, NULL);
        if (rc) return rc;
    }
    const kin_factor *f = kin__cur(a);
    int nf = a->nf, nb = a->nb, mr = f->an.m_rigid;
    if (f->an.m_internal == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism");
    if (f->an.m_internal >= 2) {
        *tau = 0.0;
        return KIN_OK;
    }
    double *t = a->chord;
    if (kin_get_tangent(a, t, nf) != KIN_OK) memcpy(t, f->Uint, sizeof(double) * (size_t)nf);
    /* rigid mechanisms, oriented continuously against the previous ones */
    double *R = a->Rref;
    for (int c = 0; c < mr; ++c) {
        const double *r = f->Urig + (size_t)c * nf;
        double sg = a->have_Rref && kin__dot(nf, r, R + (size_t)c * nf) < 0.0 ? -1.0 : 1.0;
        for (int i = 0; i < nf; ++i) R[i + (size_t)c * nf] = sg * r[i];
    }
    a->have_Rref = 1;
    if (nb + 1 + mr != nf) {
        /* redundant bars on the path (s > 0): no square border, no sign */
        *tau = f->an.v_r;
        return KIN_OK;
    }
    double *B = a->mwork;
    int *ipiv = a->iwork, info = 0;
    kin__build_H(a, a->xyz, a->H, nf);
    for (int k = 0; k < nb; ++k)
        for (int i = 0; i < nf; ++i) B[k + (size_t)i * nf] = a->H[i + (size_t)k * nf];
    for (int i = 0; i < nf; ++i) B[nb + (size_t)i * nf] = t[i];
    for (int c = 0; c < mr; ++c)
        for (int i = 0; i < nf; ++i) B[nb + 1 + c + (size_t)i * nf] = R[i + (size_t)c * nf];
    a->nfact++;
    dgetrf_(&nf, &nf, B, &nf, ipiv, &info);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrf info = %d", info);
    double sg = 1.0;
    for (int i = 0; i < nf; ++i) {
        if (B[i + (size_t)i * nf] < 0.0) sg = -sg;
        if (ipiv[i] != i + 1) sg = -sg;
    }
    *tau = info > 0 ? 0.0 : sg * f->an.v_r;
    return KIN_OK;
}

typedef struct hermite_ws hermite_ws;

typedef struct loc_ctx {
    kin_assembly *a, *prev, *work, *probe;
    kin_assembly *tb0, *tb1; /* fast method: a test-function bracket kept while looking ahead */
    const kin_locate_options *o;
    kin_locate_info *info;
    hermite_ws *hw;
} loc_ctx;

static double rel(const kin_assembly *a) { return kin__cur(a)->an.v_r / kin__cur(a)->an.v_max; }

/* index of the singular value that vanishes at a bifurcation: a point on a
 * path has rank nfree - 1 - m_rigid, so it is the last non-zero one there */
static int vanishing_index(const kin_assembly *a)
{
    int mn = a->nf < a->nb ? a->nf : a->nb, k = a->nf - 2 - kin__cur(a)->an.m_rigid;
    return k >= 0 && k < mn ? k : -1;
}

static double vanishing_sv(const kin_assembly *a)
{
    int k = vanishing_index(a);
    return k >= 0 ? kin__cur(a)->sv[k] : kin__cur(a)->an.v_r;
}

/* The largest of the singular values that vanish at the bifurcation being
 * located. Several vanish together at most bifurcations of the sails (15 at
 * the hexagonal sail's flat state), with different slopes: the lowest alone
 * can meet the tolerance at a point still 1e-9 away, where m and s would
 * come out wrong. The group: from the path's lowest singular value up to the
 * largest ratio gap among those at most sqrt(tol) * v_max and the first one
 * above. */
static double group_top(const kin_assembly *a, double tol)
{
    const kin_factor *f = kin__cur(a);
    int k = vanishing_index(a);
    if (k < 0) return f->an.v_r;
    double cut = sqrt(tol) * f->an.v_max, top = f->sv[k], gap = 1.0;
    for (int i = k - 1; i >= 0; --i) {
        double r = f->sv[i + 1] > 0.0 ? f->sv[i] / f->sv[i + 1] : INFINITY;
        if (r > gap) {
            gap = r;
            top = f->sv[i + 1];
        }
        if (f->sv[i] > cut) break;
    }
    return top;
}

static int at_bifurcation(const kin_assembly *a, double tol)
{
    return group_top(a, tol) <= tol * kin__cur(a)->an.v_max;
}

/* forward calculation: work := base moved by delta along its tangent */
static int forward(loc_ctx *c, const kin_assembly *base, kin_assembly *dst, double delta, double *used)
{
    kin__copy_state(dst, base);
    kin_step_info si = {.size = sizeof si};
    c->info->forward++;
    int rc = kin_step(dst, delta, &si);
    if (used) *used = rc == KIN_OK ? si.delta : 0.0;
    return rc;
}

/* Progress through the caller's callback (kin_set_progress): steps plus
 * forward calculations, out of max_steps + max_iter. Called at the top of
 * every following step and location iteration, so a cancel takes effect
 * within one step. Returns 1 when the caller cancels. */
static int loc_cancelled(const loc_ctx *c)
{
    double total = (double)c->o->max_steps + (double)c->o->max_iter;
    return kin__progress(c->a, (double)c->info->steps + (double)c->info->forward, total);
}

static double tangent_cos(const kin_assembly *x, const kin_assembly *y)
{
    return fabs(kin__dot(x->nf, x->t, y->t));
}

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
    double z[HERMITE_MAX_NODES], v[HERMITE_MAX_NODES], dv[HERMITE_MAX_NODES];
    double err[HERMITE_MAX_NODES]; /* estimated position error of the node */
    double *x, *dx;   /* HERMITE_MAX_NODES * nf each: the nodes */
    double *sx, *sdx; /* HERMITE_MAX_NODES * nf each: the nodes in use, packed */
    double *coef;     /* 2 * HERMITE_MAX_NODES * nf: divided differences */
    double *xs;       /* nf: an interpolated point */
    double *xyz;      /* nj * dim */
    double *e, *y, *d; /* nb, max(nf, nb), nf */
    double *scratch;  /* 2 * nj * dim */
};

static void hermite_free(hermite_ws *h)
{
    if (!h) return;
    free(h->x);
    free(h);
}

static hermite_ws *hermite_alloc(const kin_assembly *a)
{
    hermite_ws *h = calloc(1, sizeof *h);
    if (!h) return NULL;
    size_t nf = (size_t)a->nf, nb = (size_t)a->nb, K = HERMITE_MAX_NODES, nc = (size_t)a->nj * (size_t)a->dim;
    size_t ny = nf > nb ? nf : nb;
    h->nf = a->nf;
    h->x = malloc(sizeof(double) * (K * nf * 6 + nf + nc + nb + ny + nf + 2 * nc));
    if (!h->x) {
        free(h);
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
    return h;
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
        if (it == maxit || res == 0.0) break;
        kin__scatter(a, d, xyz);
        kin__extensions(a, xyz, e);
        double rn = kin__norm(nb, e);
        if (!(rn < res)) {
            kin__scatter(a, x, xyz);
            kin__extensions(a, xyz, e);
            break;
        }
        memcpy(x, d, sizeof(double) * (size_t)nf);
        res = rn;
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
    int nf = h->nf, k = vanishing_index(st);
    if (h->n >= HERMITE_MAX_NODES || k < 0) return 0;
    const kin_factor *f = kin__cur(st);
    double *x = h->x + (size_t)h->n * nf, *dx = h->dx + (size_t)h->n * nf;
    kin__gather(st, st->xyz, x);
    memcpy(h->xyz, st->xyz, sizeof(double) * (size_t)(st->nj * st->dim));
    double corr = chord_polish(st, f, k + 1, x, h->xyz, h->e, h->y, h->d, NODE_POLISH_ITER);
    double floor = DBL_EPSILON * st->rms_length;
    kin__gather(base, base->xyz, h->xs);
    double z = 0.0, tt = kin__dot(nf, st->t, base->t);
    for (int i = 0; i < nf; ++i) z += base->t[i] * (x[i] - h->xs[i]);
    if (!(fabs(tt) > 0.0)) return 0;
    for (int i = 0; i < nf; ++i) dx[i] = st->t[i] / tt;
    h->z[h->n] = z;
    h->v[h->n] = f->sv[k];
    h->dv[h->n] = kin__sv_derivative(st, f, st->xyz, dx, k, h->scratch);
    h->err[h->n] = fmax(corr, floor);
    h->n++;
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

enum { HERMITE_NO_BRACKET = -1 };

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

/* Locate between c->prev and c->a (the bracketing step). On success c->work
 * sits on the bifurcation, analysed. Returns KIN_OK, HERMITE_NO_BRACKET
 * (the vanishing singular value does not turn within the step: the caller
 * may fall back on the test function), KIN_ENOTFOUND, or a step/LAPACK
 * code. */
static int locate_hermite(loc_ctx *c)
{
    hermite_ws *h = c->hw;
    kin_assembly *prev = c->prev, *w = c->work;
    int nf = h->nf, all[HERMITE_MAX_NODES], good[HERMITE_MAX_NODES];
    h->n = 0;
    if (!hermite_add(h, prev, prev) || !hermite_add(h, c->a, prev)) return HERMITE_NO_BRACKET;
    double width0 = fabs(h->z[1] - h->z[0]);
    double err_ok = NODE_ERROR_FRACTION * c->o->vr_tol * prev->rms_length;
    for (int i = 0; i < HERMITE_MAX_NODES; ++i) all[i] = 1;
    herm_est E;
    if (!hermite_estimate(h, all, 0, &E)) return HERMITE_NO_BRACKET;
    int checked = 0, stalls = 0; /* accurate nodes at the last check; checks without progress */
    double best = INFINITY;
    for (int it = 0; it < c->o->max_iter && h->n <= HERMITE_MAX_NODES; ++it) {
        if (loc_cancelled(c)) return KIN_ECANCELLED;
        int ngood = 0;
        for (int i = 0; i < h->n; ++i) ngood += good[i] = h->err[i] <= err_ok;
        /* the estimate: from the accurate nodes once they bracket the zero,
         * else (roughly) from all */
        int from_good = ngood >= 2 && hermite_estimate(h, good, 1, &E);
        if (!from_good && !hermite_estimate(h, all, 0, &E)) break;
        c->info->zero_order = E.p;
        if (from_good && ngood > checked) {
            checked = ngood;
            /* check the estimate: one SVD at the interpolated point */
            kin__copy_state(w, prev);
            kin__scatter(w, h->xs, w->xyz);
            int rc = kin__analyse_into(w, w->xyz, w->cur);
            if (rc) return rc;
            double vv = group_top(w, c->o->vr_tol), vmax = kin__cur(w)->an.v_max;
            double strain = kin__lengths(w, w->xyz, NULL);
            TRACE("  check %d nodes (%d accurate): z* = %.12g (order %d), v_r %.3g, strain %.2g\n", h->n, ngood,
                  E.zs, E.p, vv / vmax, strain);
            if (vv <= c->o->vr_tol * vmax && !(strain <= w->opt.corrector_tol)) {
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
                vv = group_top(w, c->o->vr_tol);
                vmax = kin__cur(w)->an.v_max;
                strain = kin__lengths(w, w->xyz, NULL);
            }
            if (vv <= c->o->vr_tol * vmax && strain <= w->opt.corrector_tol) {
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
        int rc = kin__step_predicted(w, dz, h->xs, NULL);
        if (rc == KIN_ENOTCONVERGED || rc == KIN_EPATHJUMP || rc == KIN_ENOMECH) break;
        if (rc) return rc;
        double jump = 0.0;
        kin__gather(w, w->xyz, x0);
        for (int i = 0; i < nf; ++i) jump = fmax(jump, fabs(x0[i] - h->xs[i]));
        if (jump > NODE_JUMP_FRACTION * fabs(zn - E.zs)) break; /* onto a neighbouring branch */
        if (!hermite_add(h, w, prev)) break;
        TRACE("  node %d at z = %.12g (estimate %.12g, rho_min %.3g): v %.3g, error %.3g\n", h->n - 1, h->z[h->n - 1],
              E.zs, rho_min, h->v[h->n - 1], h->err[h->n - 1]);
    }
    /* no certified point. v_r brought below sqrt(vr_tol) means a
     * bifurcation pinned only so far (a tangency, where v_r ~ |l - l*|^2 and
     * the strain fixes a point less sharply) or a near miss of that size;
     * above that, a non-zero minimum of v_r */
    double vmax0 = kin__cur(prev)->an.v_max;
    for (int i = 0; i < h->n; ++i) best = fmin(best, h->v[i] / vmax0); /* points of the path, too */
    if (best <= sqrt(c->o->vr_tol))
        return kin__fail(c->a, KIN_ENOTFOUND,
                         "a bifurcation (v_r ~ |l - l*|^%d) was located only to v_r = %.2g relative, above "
                         "vr_tol = %.2g: the attainable accuracy here, or a near miss of that size (a larger "
                         "vr_tol accepts it)",
                         E.p, best, c->o->vr_tol);
    return kin__fail(c->a, KIN_ENOTFOUND,
                     "v_r has a non-zero minimum (%.3g relative) here: a near-singular but regular configuration",
                     best);
}

/* Illinois iteration on tau(delta) over [0, hi] from prev (tau_lo there) */
static int locate_fast(loc_ctx *c, double hi, double tau_lo, double tau_hi)
{
    double lo = 0.0, width0 = fabs(hi);
    int side = 0;
    for (int it = 0; it < c->o->max_iter; ++it) {
        if (loc_cancelled(c)) return KIN_ECANCELLED;
        if (fabs(hi - lo) < GIVE_UP_FRACTION * width0) {
            /* the bracket has collapsed but v_r stays finite: tau changed sign
             * without a zero, i.e. the step crossed a near-singular but
             * regular configuration onto a neighbouring sheet of the path */
            return kin__fail(c->a, KIN_ENOTFOUND,
                             "no bifurcation: the test function changed sign but v_r stays at %.3g relative "
                             "(a near-singular regular configuration; take smaller steps here)",
                             rel(c->work));
        }
        double d = hi - tau_hi * (hi - lo) / (tau_hi - tau_lo);
        if (!(d > fmin(lo, hi) && d < fmax(lo, hi))) d = 0.5 * (lo + hi);
        double used;
        int rc = forward(c, c->prev, c->work, d, &used);
        if (rc != KIN_OK || used != d) {
            d = 0.5 * (lo + hi);
            rc = forward(c, c->prev, c->work, d, &used);
            if (rc != KIN_OK) return rc;
        }
        if (at_bifurcation(c->work, c->o->vr_tol)) return KIN_OK;
        double tau;
        rc = kin_test_function(c->work, &tau);
        if (rc) return rc;
        if (tau == 0.0) return KIN_OK;
        if ((tau > 0) == (tau_hi > 0)) {
            hi = used;
            tau_hi = tau;
            if (side == 1) tau_lo *= 0.5; /* Illinois: halve the stale end */
            side = 1;
        } else {
            lo = used;
            tau_lo = tau;
            if (side == -1) tau_hi *= 0.5;
            side = -1;
        }
    }
    return kin__fail(c->a, KIN_ENOTFOUND,
                     "signed test function: no convergence in %d iterations, v_r still %.3g relative: a "
                     "near-singular but regular configuration, or a bifurcation this method cannot resolve",
                     c->o->max_iter, rel(c->work));
}

/* A non-zero minimum of v_r, by the paper's own model (eq. 23): among the
 * sampled points (l[i], v[i]) find the lowest one with a higher neighbour on
 * each side along the path (a bracketed minimum) and fit the quadratic
 * through it and its neighbours. Near a bifurcation v_r is V-shaped (a
 * crossing: the fitted vertex lies at most half as high as the lowest sample,
 * usually below zero) or touches zero (a tangency, Figure 7(b): the vertex is
 * near zero); a near-singular regular point is a smooth minimum that the
 * quadratic fits, its vertex within NEAR_MISS_FIT of the lowest sample. Only
 * minima above NEAR_MISS_FLOOR x the tolerance count, where rounding cannot
 * fake that agreement. */
static const double NEAR_MISS_FIT = 0.9;
static const double NEAR_MISS_FLOOR = 100.0;
static int nonzero_minimum(double *l, double *v, int n, double v_tol, double *v_min)
{
    for (int i = 1; i < n; ++i) /* insertion sort by l: n <= 4 */
        for (int k = i; k > 0 && l[k] < l[k - 1]; --k) {
            double tl = l[k], tv = v[k];
            l[k] = l[k - 1]; v[k] = v[k - 1];
            l[k - 1] = tl; v[k - 1] = tv;
        }
    int best = -1;
    for (int i = 1; i + 1 < n; ++i)
        if (v[i] < v[i - 1] && v[i] < v[i + 1] && l[i - 1] < l[i] && l[i] < l[i + 1] &&
            (best < 0 || v[i] < v[best]))
            best = i;
    if (best < 0 || !(v[best] > NEAR_MISS_FLOOR * v_tol)) return 0;
    double x0 = l[best - 1], x1 = l[best], x2 = l[best + 1];
    double d01 = (v[best] - v[best - 1]) / (x1 - x0), d12 = (v[best + 1] - v[best]) / (x2 - x1);
    double A = (d12 - d01) / (x2 - x0);
    if (!(A > 0.0)) return 0;
    double B = d01 - A * (x0 + x1), C = v[best - 1] - A * x0 * x0 - B * x0;
    *v_min = C - B * B / (4 * A);
    TRACE("near-miss fit: %.6g %.6g | %.6g %.6g | %.6g %.6g -> vertex %.6g at %.6g\n", x0, v[best - 1], x1, v[best], x2,
          v[best + 1], *v_min, -B / (2 * A));
    return *v_min >= NEAR_MISS_FIT * v[best];
}

/* the paper's method: quadratic through the last three (l, v_r) */
static int locate_paper(loc_ctx *c, double *hl, double *hv, int nh, double step)
{
    kin_assembly *base = c->prev;
    double delta = 0.0, shrink = 1.0;
    for (int it = 0; it < c->o->max_iter; ++it) {
        if (loc_cancelled(c)) return KIN_ECANCELLED;
        double ln;
        if (nh >= 3) {
            /* Lagrange quadratic v = A l^2 + B l + C through the last three points */
            double x0 = hl[nh - 3], x1 = hl[nh - 2], x2 = hl[nh - 1];
            double y0 = hv[nh - 3], y1 = hv[nh - 2], y2 = hv[nh - 1];
            double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
            double A = (d12 - d01) / (x2 - x0), B = d01 - A * (x0 + x1), C = y0 - A * x0 * x0 - B * x0;
            double disc = B * B - 4 * A * C;
            if (A != 0.0 && disc >= 0.0) {
                double r1 = (-B + sqrt(disc)) / (2 * A), r2 = (-B - sqrt(disc)) / (2 * A);
                /* Figure 7(a), and (b) translated down: the root nearest l_{n-1} ahead */
                double best = NAN;
                if ((r1 - x2) * (x2 - x1) > 0) best = r1;
                if ((r2 - x2) * (x2 - x1) > 0 && (isnan(best) || fabs(r2 - x2) < fabs(best - x2))) best = r2;
                ln = isnan(best) ? x2 + (x2 - x1) : best;
            } else if (A > 0.0) {
                ln = -B / (2 * A); /* Figure 7(b) translated up: the minimum */
                if ((ln - x2) * (x2 - x1) <= 0) ln = x2 + 0.5 * (x2 - x1);
            } else {
                ln = x2 + (x2 - x1);
            }
        } else {
            double x1 = hl[nh - 2], x2 = hl[nh - 1], y1 = hv[nh - 2], y2 = hv[nh - 1];
            ln = y2 < y1 ? x2 + y2 * (x2 - x1) / (y1 - y2) : x2 + (x2 - x1);
        }
        double dir = hl[nh - 1] >= hl[nh - 2] ? 1.0 : -1.0;
        delta = dir * fabs(ln - hl[nh - 1]) * shrink;
        if (fabs(delta) < GIVE_UP_FRACTION * step)
            return kin__fail(c->a, KIN_ENOTFOUND,
                             "v_r has a non-zero minimum (%.3g relative) here: a near-singular but regular configuration",
                             rel(base));
        double used;
        int rc = forward(c, base, c->work, delta, &used);
        if (rc != KIN_OK) { shrink *= 0.5; continue; }
        if (at_bifurcation(c->work, c->o->vr_tol)) {
            if (tangent_cos(c->work, base) >= PATH_KEPT_COS || kin__cur(c->work)->an.m_internal >= 2) return KIN_OK;
        }
        /* eq. 26: still on the same path? */
        if (kin__cur(c->work)->an.m_internal == 1 && tangent_cos(c->work, base) < PATH_KEPT_COS) {
            shrink *= 0.5;
            continue;
        }
        /* overshoot probe: a small extra step; v_r growing means we crossed */
        rc = forward(c, c->work, c->probe, PROBE_FRACTION * delta, NULL);
        if (rc == KIN_OK) {
            /* the samples so far bracket a smooth non-zero minimum: no bifurcation here */
            double sl[4] = {base->l, c->work->l, c->probe->l, 0.0};
            double sv[4] = {kin__cur(base)->an.v_r, kin__cur(c->work)->an.v_r, kin__cur(c->probe)->an.v_r, 0.0};
            int ns = 3;
            if (nh >= 2) { sl[3] = hl[nh - 2]; sv[3] = hv[nh - 2]; ns = 4; }
            double v_min, v_max = kin__cur(base)->an.v_max;
            if (nonzero_minimum(sl, sv, ns, c->o->vr_tol * v_max, &v_min))
                return kin__fail(c->a, KIN_ENOTFOUND,
                                 "v_r has a non-zero minimum (%.3g relative, from the quadratic of eq. 23) "
                                 "here: a near-singular but regular configuration",
                                 v_min / v_max);
        }
        if (rc != KIN_OK || kin__cur(c->probe)->an.v_r > kin__cur(c->work)->an.v_r) {
            shrink *= 0.5;
            continue;
        }
        /* accept: the window moves on */
        kin__copy_state(base, c->work);
        if (nh >= 3) {
            hl[0] = hl[1]; hv[0] = hv[1];
            hl[1] = hl[2]; hv[1] = hv[2];
            nh = 2;
        }
        hl[nh] = base->l;
        hv[nh] = kin__cur(base)->an.v_r;
        ++nh;
        shrink = 1.0;
    }
    return kin__fail(c->a, KIN_ENOTFOUND, "paper's method: v_r %.3g relative after %d forward calculations",
                     rel(base), c->o->max_iter);
}

/* dv/dl of the vanishing singular value of the analysed state st along its
 * direction of motion, dir * t (no factorization) */
static double motion_slope(loc_ctx *c, const kin_assembly *st, double dir)
{
    int k = vanishing_index(st);
    if (k < 0) return 0.0;
    return dir * kin__sv_derivative(st, kin__cur(st), st->xyz, st->t, k, c->hw->scratch);
}

/* v_r turned from decreasing to increasing over the last step (length len):
 * where the tangent lines at its two ends meet, v_r is about (for a crossing
 * exactly) zero. That value, to compare with the switch threshold. */
static double turn_value(double v0, double sl0, double v1, double sl1, double len)
{
    double s = (v1 - v0 - sl1 * len) / (sl0 - sl1);
    if (!(s >= 0.0)) s = 0.0;
    if (s > len) s = len;
    return v0 + sl0 * s;
}

static void free_ctx(loc_ctx *c)
{
    kin_assembly_free(c->prev);
    kin_assembly_free(c->work);
    kin_assembly_free(c->probe);
    kin_assembly_free(c->tb0);
    kin_assembly_free(c->tb1);
    hermite_free(c->hw);
}

static int locate_impl(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info)
{
    kin_locate_options o = *opt;
    if ((o.method != KIN_LOCATE_PAPER && o.method != KIN_LOCATE_FAST && o.method != KIN_LOCATE_ILLINOIS) ||
        !(o.vr_tol > 0 && o.vr_tol < 1) || !(o.switch_eps > 0 && o.switch_eps < 1) || !isfinite(o.delta) ||
        o.max_steps < 1 || o.max_iter < 1)
        return kin__fail(a, KIN_EINVAL, "locate options out of range");
    int rc = kin__cur(a)->valid ? KIN_OK : kin_analyse(a, NULL);
    if (rc) return rc;
    if (kin__cur(a)->an.m_internal >= 2)
        return kin__fail(a, KIN_EBIFURCATION, "already at a bifurcation (m_internal = %d)",
                         kin__cur(a)->an.m_internal);
    if (kin__cur(a)->an.m_internal == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism to follow");
    loc_ctx c = {a, NULL, NULL, NULL, NULL, NULL, &o, info, NULL};
    kin_options user = a->opt;
    double fine = fmin(user.rank_tol, LOCATE_RANK_FRACTION * o.vr_tol);
    a->opt.rank_tol = fine;
    /* the detectors and the nodes need every point's SVD */
    a->opt.factorization = KIN_STEP_SVD;
    c.hw = hermite_alloc(a);
    if (!c.hw || kin_assembly_clone(a, &c.prev) || kin_assembly_clone(a, &c.work) ||
        kin_assembly_clone(a, &c.probe) ||
        (o.method == KIN_LOCATE_FAST && (kin_assembly_clone(a, &c.tb0) || kin_assembly_clone(a, &c.tb1)))) {
        a->opt = user;
        free_ctx(&c);
        return kin__fail(a, KIN_ENOMEM, "locator working copies");
    }
    if (!a->have_t) {
        /* a regular start point: its own (deterministically oriented) mechanism */
        memcpy(a->t, kin__cur(a)->Uint, sizeof(double) * (size_t)a->nf);
        a->have_t = 1;
    }
    double dir = o.delta < 0.0 ? -1.0 : 1.0, tb_delta = 0.0, tb_tau0 = 0.0, tb_tau1 = 0.0;
    int pending = 0;
    double tau0, tau1, hl[4], hv[4];
    int nh = 0;
    rc = kin_test_function(a, &tau0);
    double v0 = vanishing_sv(a), sl0 = motion_slope(&c, a, dir);
    hl[nh] = a->l;
    hv[nh++] = kin__cur(a)->an.v_r;
    kin_step_info si = {.size = sizeof si};
    long fa = 0, fw = 0, fp = 0, fpv = 0;
    while (rc == KIN_OK && info->steps < o.max_steps) {
        if (loc_cancelled(&c)) {
            rc = KIN_ECANCELLED;
            break;
        }
        kin__copy_state(c.prev, a);
        rc = kin_step(a, o.delta, &si);
        if (rc) break;
        info->steps++;
        if (si.m_internal >= 2) {
            info->event = KIN_EVENT_LANDED;
            break;
        }
        rc = kin_test_function(a, &tau1);
        if (rc) break;
        double vr = kin__cur(a)->an.v_r, vmax = kin__cur(a)->an.v_max;
        double v1 = vanishing_sv(a), sl1 = motion_slope(&c, a, dir);
        TRACE(" step %d: l %.6f tau %+.3e v %.3e slope %+.3e\n", info->steps, a->l, tau1, v1 / vmax, sl1 / vmax);
        if (tau0 != 0.0 && tau1 != 0.0 && (tau0 > 0) != (tau1 > 0)) {
            if (o.method == KIN_LOCATE_FAST && sl1 < 0.0) {
                /* tau flipped while v_r still falls: with several singular
                 * values vanishing together the determinant can change sign
                 * (even twice) just before the point. Keep the first such
                 * bracket and look a step or two further for v_r to turn. */
                if (!pending) {
                    kin__copy_state(c.tb0, c.prev);
                    kin__copy_state(c.tb1, a);
                    tb_delta = si.delta;
                    tb_tau0 = tau0;
                    tb_tau1 = tau1;
                }
                pending = 1;
            } else {
                info->event = KIN_EVENT_SIGN_CHANGE;
                break;
            }
        }
        if (nh == 4) {
            memmove(hl, hl + 1, 3 * sizeof *hl);
            memmove(hv, hv + 1, 3 * sizeof *hv);
            nh = 3;
        }
        hl[nh] = a->l;
        hv[nh++] = vr;
        if (o.method == KIN_LOCATE_PAPER && o.use_switch_rule && vr < o.switch_eps * vmax && vr < hv[nh - 2]) {
            info->event = KIN_EVENT_SWITCH_RULE;
            kin__copy_state(c.prev, a);
            break;
        }
        if (o.method != KIN_LOCATE_PAPER && sl0 < 0.0 && sl1 > 0.0 &&
            turn_value(v0, sl0, v1, sl1, fabs(a->l - c.prev->l)) < o.switch_eps * vmax) {
            /* v_r turned over this step without tau changing sign: an even
             * number of singular values crossed zero, a tangency, or a
             * non-zero minimum */
            info->event = KIN_EVENT_MINIMUM;
            nh--; /* the paper's history ends at the point before */
            break;
        }
        if (pending && ++pending > TAU_LOOK_AHEAD) {
            /* v_r did not turn: locate on the test function's bracket */
            kin__copy_state(c.prev, c.tb0);
            kin__copy_state(a, c.tb1);
            si.delta = tb_delta;
            tau0 = tb_tau0;
            tau1 = tb_tau1;
            info->event = KIN_EVENT_SIGN_CHANGE;
            break;
        }
        tau0 = tau1;
        v0 = v1;
        sl0 = sl1;
    }
    fa = a->nfact;
    fw = c.work->nfact;
    fp = c.probe->nfact;
    fpv = c.prev->nfact;
    if (rc == KIN_OK && info->event == KIN_EVENT_NONE)
        rc = kin__fail(a, KIN_ENOTFOUND, "no bifurcation within %d steps", o.max_steps);
    if (rc == KIN_OK && info->event != KIN_EVENT_LANDED) {
        double step = o.delta != 0.0 ? fabs(o.delta) : a->opt.step_fraction * a->rms_length;
        int bracket = info->event == KIN_EVENT_SIGN_CHANGE || info->event == KIN_EVENT_MINIMUM;
        if (o.method == KIN_LOCATE_FAST && bracket) {
            rc = locate_hermite(&c);
            TRACE(" event %d: hermite returned %d\n", info->event, rc);
            if (rc == HERMITE_NO_BRACKET) {
                /* v_r does not turn within the step although tau changed
                 * sign: the test function's bracket, then the paper's
                 * quadratic from the point before */
                rc = info->event == KIN_EVENT_SIGN_CHANGE ? locate_fast(&c, si.delta, tau0, tau1) : KIN_ENOTFOUND;
                if (rc == KIN_ENOTFOUND) rc = nh >= 2 ? locate_paper(&c, hl, hv, nh, step) : rc;
                if (rc == KIN_ENOTFOUND && !kin_last_error(a)[0])
                    rc = kin__fail(a, KIN_ENOTFOUND, "v_r does not turn within the step");
            }
        } else if (o.method == KIN_LOCATE_ILLINOIS && info->event == KIN_EVENT_SIGN_CHANGE) {
            rc = locate_fast(&c, si.delta, tau0, tau1);
        } else {
            /* the paper's method; also the fallback when tau does not change sign */
            /* the history ends at c.prev, the last point before the bifurcation */
            rc = nh >= 2 ? locate_paper(&c, hl, hv, nh, step) : kin__fail(a, KIN_ENOTFOUND, "too little history");
        }
        if (rc == KIN_OK) {
            /* eq. 26: the move from the last regular point must continue its
             * tangent, or the search slid onto a neighbouring path */
            double *ch = c.probe->chord, *x1 = c.probe->x;
            kin__gather(a, c.prev->xyz, ch);
            kin__gather(a, c.work->xyz, x1);
            for (int i = 0; i < a->nf; ++i) ch[i] = x1[i] - ch[i];
            double n = kin__norm(a->nf, ch);
            info->path_kept = n == 0.0 || fabs(kin__dot(a->nf, ch, c.prev->t)) >= PATH_KEPT_COS * n;
            /* move the caller's assembly onto the located point */
            double dist = 0.0;
            for (int i = 0; i < a->nj * a->dim; ++i) dist += (c.work->xyz[i] - a->xyz[i]) * (c.work->xyz[i] - a->xyz[i]);
            info->distance = sqrt(dist);
            kin__copy_state(a, c.work);
        } else if (rc == KIN_ENOTFOUND || rc == KIN_ECANCELLED) {
            /* leave the assembly at the best regular point: the base of the search */
            kin__copy_state(a, c.prev);
        }
    }
    if (rc == KIN_OK && info->event == KIN_EVENT_LANDED)
        info->path_kept = 1; /* an ordinary step landed there: its direction check applied */
    /* count m and s at the final point from its factorization (no new one):
     * at a located point with the rank tolerance the location supports (the
     * vanishing singular values are only down to vr_tol there), elsewhere
     * with the caller's */
    a->opt = user;
    if (rc == KIN_OK && info->event != KIN_EVENT_LANDED)
        a->opt.rank_tol = fmax(user.rank_tol, LOCATED_RANK_MARGIN * o.vr_tol);
    {
        int rc2 = kin__cur(a)->valid ? kin__reclassify(a, a->xyz, a->cur) : kin_analyse(a, NULL);
        if (rc == KIN_OK) rc = rc2;
    }
    a->opt = user;
    info->factorizations = (int)((a->nfact - fa) + (c.work->nfact - fw) + (c.probe->nfact - fp) + (c.prev->nfact - fpv));
    info->located = rc == KIN_OK;
    info->v_r = group_top(a, o.vr_tol);
    info->v_r_rel = kin__cur(a)->an.v_max > 0 ? info->v_r / kin__cur(a)->an.v_max : 0.0;
    info->m_internal = kin__cur(a)->an.m_internal;
    info->s = kin__cur(a)->an.s;
    if (rc == KIN_ECANCELLED)
        kin__fail(a, KIN_ECANCELLED, "cancelled by the progress callback after %d steps and %d forward calculations",
                  info->steps, info->forward);
    else if (rc == KIN_OK)
        (void)kin__progress(a, (double)o.max_steps + (double)o.max_iter, (double)o.max_steps + (double)o.max_iter);
    free_ctx(&c);
    return rc;
}

int kin_locate_next(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info)
{
    if (info) {
        if (kin__abi_check(info, KIN__V1_SIZE(kin_locate_info, zero_order), sizeof *info))
            return a ? kin__fail(a, KIN_EINVAL, "info->size = %zu: set it to sizeof(kin_locate_info)",
                                 kin__abi_size(info))
                     : KIN_EINVAL;
        kin__abi_zero(info);
    }
    if (!a) return KIN_ENULL;
    kin_locate_options o;
    kin_locate_options_default(&o); /* fields an older caller does not have keep their defaults */
    if (opt) {
        if (kin__abi_check(opt, KIN__V1_SIZE(kin_locate_options, use_switch_rule), sizeof *opt))
            return kin__fail(a, KIN_EINVAL,
                             "options->size = %zu: not set by kin_locate_options_default() of this libkin",
                             kin__abi_size(opt));
        kin__abi_read(&o, opt, sizeof o);
    }
    kin_locate_info local = {.size = sizeof local};
    int rc = locate_impl(a, &o, &local);
    if (info) kin__abi_write(info, &local, sizeof local);
    return rc;
}
