/* The path tracker behind kin_quadrics_homotopy, one path at a time: the
 * reference that the lockstep tracker (homotopy_batch.c, which the solver
 * runs) follows operation for operation, and the endpoint certificate both
 * use.
 *
 * Predictor: the Taylor series of the path x(t0 + h) to order HOM_ORDER,
 * exact and cheap here because H is quadratic in x and linear in t: with
 * A(t) = (1 - t) gamma G + t F (a symmetric bilinear form per equation) the
 * coefficient of h^k of H(x(t0 + h), t0 + h) = 0 gives, for k >= 1,
 *     J x_k = -( sum_{i+l=k, 0<i,l<k} A(t0)[x_i, x_l]
 *                + sum_{i+l=k-1} (F - gamma G)[x_i, x_l] ),   a.x_k = 0,
 * so every coefficient costs one solve with the LU factors of J = dH/dx that
 * the corrector made anyway, and F[x_i, x_l] = x_l . (Q x_i) needs Q x_i only
 * for i <= k/2. The step h is chosen from the series' estimated radius of
 * convergence and truncation error (calibrated along the path by the errors
 * actually made), against two targets: a relative error and a fraction of
 * the separation radius r = 1 / (|J^-1| |A(t)|) (for a quadratic map,
 * H(x + d) = H(x) + J d + A[d, d], so no other solution of H(., t) = 0 lies
 * within r of a solution x).
 * Where the series' radius is set by a nearby complex singularity (the
 * clustered paths of the sails' flat states), the rational approximant
 * [K-1/1] built from the same coefficients (homotopy_pade.c) is usually
 * far more accurate: it replaces the Taylor polynomial whenever its own
 * error estimate (calibrated along the path like the Taylor model) meets
 * the target at the Taylor step, and the step then grows while it still
 * does (on the hexagonal sail's flat state 20 % fewer steps). The Taylor
 * model, calibrated by the steps it predicted, gives the first trial step
 * and the fallback.
 * Corrector: Newton with a fresh Jacobian per iteration; a step is accepted
 * only if the first correction is a small fraction of the separation radius
 * at the new t (then, by the Kantorovich theorem, Newton converges to the
 * root nearest the prediction and that root is the path's: another path is
 * at least r away) and the following ones contract to NEWTON_TOL. The LU
 * factors of the last iterate serve the next step's series.
 * Chart: when the path nears the hyperplane at infinity of its affine chart
 * (a.x = 0 in P^s), the chart is replaced by the one orthogonal to x.
 * End: a path that reaches t = 1, or comes within sigma_end of it (near a
 * singular endpoint the series' radius shrinks like 1 - t and steps become a
 * fixed fraction of it, so this costs a few dozen steps, not step halving),
 * is refined by Newton on F in the chart z_k = 1 (k: its largest entry) and
 * certified by the Kantorovich theorem: with beta >= |J^-1| (the Frobenius
 * norm of the computed inverse), L = 2 normF >= the Lipschitz constant of J
 * and eta >= |J^-1 F(z)| (the computed correction plus beta times a bound on
 * the rounding in F(z)), h = beta L eta <= 1/2 proves a root within
 * rminus = 2 eta / (1 + sqrt(1 - 2h)) of z and no other within
 * rplus = (1 + sqrt(1 - 2h)) / (beta L). A certified root is real if its
 * conjugate must lie in the same uniqueness ball (then it is certified again
 * at Re z), non-real if the existence ball misses the real subspace;
 * anything not certified is singular (a multiple root, a point of a
 * positive-dimensional component, or a root too ill-conditioned for double
 * precision). The certificate is computed in floating point with an a-priori
 * rounding bound for F, not in interval arithmetic. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/track/homotopy_kernels.h"

/* Refinement at t = 1 stops when the correction is below REFINE_TOL |z|
 * or stops shrinking by at least REFINE_RATE per iteration. */
static const double REFINE_TOL = 4.0 * DBL_EPSILON, REFINE_RATE = 0.5;
/* Kantorovich's theorem needs h <= 1/2; H_CERT leaves a margin of 2 for the
 * rounding in the computed beta and eta. */
static const double H_CERT = 0.25;
/* Rounding in F_j(z) = z^T Q_j z (|Q_j|_F = 1) is at most about
 * 2 m u |z|^2 (u = DBL_EPSILON / 2, a sum of m^2 products); EVAL_ROUNDING
 * times m |z|^2 bounds it with a margin of 2. */
static const double EVAL_ROUNDING = 2.0 * DBL_EPSILON;
/* A certificate must also localise the root to R_MINUS_MAX |z|: the
 * duplicate search (homotopy_merge.c) compares endpoints at 1e-6 and relies on
 * existence balls far smaller than that. */
static const double R_MINUS_MAX = 1e-8;

struct hom_ws {
    hom_point pt[3]; /* base point and two corrector iterates, used by rotation */
    double cr[HOM_ORDER + 1][HOM_MAX_M], ci[HOM_ORDER + 1][HOM_MAX_M]; /* Taylor coefficients */
    double ykr[HOM_NY][HOM_MAX_ROWS], yki[HOM_NY][HOM_MAX_ROWS]; /* Q x_k, k >= 1 */
    double rho, tail; /* the series' error model (series_step) */
};

hom_ws *kin__hom_ws_new(void) { return malloc(sizeof(hom_ws)); }
void kin__hom_ws_free(hom_ws *w) { free(w); }

/* out_j += wgt * (u . y_j), j < s: the dot of u with each equation's
 * part of y = Q x */
static void dots(int m, int s, int sp, double wgt, const double *ur, const double *ui, const double *yr,
                 const double *yi, double *outr, double *outi)
{
    double pr[HOM_MAX_M], pi[HOM_MAX_M];
    kin__hom_dots_raw(m, sp, ur, ui, yr, yi, pr, pi);
    for (int j = 0; j < s; ++j) outr[j] += wgt * pr[j], outi[j] += wgt * pi[j];
}

/* f_j = sum_{i = lo}^{k - lo} F_j[x_i, x_{k-i}] and g_j the same for G_j,
 * all j, from the coefficients c[] and y[i] = Q x_i (F_j[x_i, x_l] =
 * x_l . (Q_j x_i), symmetric, so y[i] is needed for i <= k/2 only) */
static void pair_sums(const hom_problem *P, const hom_ws *w, const double *const *yr, const double *const *yi, int k,
                      int lo, double *fr, double *fi, double *gr, double *gi)
{
    int m = P->m, s = P->s;
    for (int j = 0; j < s; ++j) fr[j] = fi[j] = gr[j] = gi[j] = 0.0;
    for (int i = lo; 2 * i <= k; ++i) {
        int l = k - i;
        double wgt = i < l ? 2.0 : 1.0;
        const double *ar = w->cr[l], *ai = w->ci[l], *ur = w->cr[i], *ui = w->ci[i];
        dots(m, s, P->sp, wgt, ar, ai, yr[i], yi[i], fr, fi);
        double e0r = ur[0] * ar[0] - ui[0] * ai[0], e0i = ur[0] * ai[0] + ui[0] * ar[0];
        for (int j = 0; j < s; ++j) {
            int q = j + 1;
            gr[j] += wgt * (ur[q] * ar[q] - ui[q] * ai[q] - e0r);
            gi[j] += wgt * (ur[q] * ai[q] + ui[q] * ar[q] - e0i);
        }
    }
}

/* Taylor coefficients c[1..HOM_ORDER] of the path through c[0] at t0, with
 * the LU factors, Q x and H of the base point b (b->x: the last corrector
 * iterate, c[0] = b->x minus its last correction). The terms with x_0 use
 * b->x, where J and Q x were evaluated; their F parts come for free once
 * t0 >= T_RECOVER: J v = 2 t0 F[b->x, v] + 2 alpha G[b->x, v] and the
 * right-hand side r_k = J x_k is known, as is H = alpha G + t0 F at b->x. */
static void taylor(const hom_problem *P, hom_ws *w, const hom_point *b, double t0)
{
    int m = P->m, s = P->s;
    const double *yr[HOM_NY], *yi[HOM_NY];
    yr[0] = b->yr, yi[0] = b->yi;
    for (int i = 1; i < HOM_NY; ++i) yr[i] = w->ykr[i], yi[i] = w->yki[i];
    double alr = (1.0 - t0) * P->gr, ali = (1.0 - t0) * P->gi;
    double ftr[HOM_MAX_M], fti[HOM_MAX_M], gtr[HOM_MAX_M], gti[HOM_MAX_M];
    double fr[HOM_MAX_M], fi[HOM_MAX_M], gr[HOM_MAX_M], gi[HOM_MAX_M];
    double rhr[HOM_MAX_M], rhi[HOM_MAX_M]; /* H at b->x, then r_{k-1} = J x_{k-1} */
    const double *vr = b->xr, *vi = b->xi;
    int recover = t0 >= T_RECOVER;
    memcpy(rhr, b->hr, sizeof(double) * (size_t)s);
    memcpy(rhi, b->hi, sizeof(double) * (size_t)s);
    for (int j = 0; j < s; ++j) ftr[j] = fti[j] = gtr[j] = gti[j] = 0.0;
    for (int k = 1; k <= HOM_ORDER; ++k) {
        double *rr = w->cr[k], *ri = w->ci[k];
        /* f_{k-1} = ft_{k-1} + (2 or 1) F[x_0, x_{k-1}], the same for g */
        const double *ur = k > 1 ? w->cr[k - 1] : vr, *ui = k > 1 ? w->ci[k - 1] : vi;
        double wgt = k > 1 ? 2.0 : 1.0;
        for (int j = 0; j < s; ++j) {
            int q = j + 1;
            double er = ur[q] * vr[q] - ui[q] * vi[q] - (ur[0] * vr[0] - ui[0] * vi[0]); /* G_j[x_0, x_{k-1}] */
            double ei = ur[q] * vi[q] + ui[q] * vr[q] - (ur[0] * vi[0] + ui[0] * vr[0]);
            gr[j] = gtr[j] + wgt * er, gi[j] = gti[j] + wgt * ei;
            fr[j] = ftr[j], fi[j] = fti[j];
            if (recover) { /* F_j[x_0, x_{k-1}] = (r_j - wgt alpha G_j) / (wgt t0), wgt = 2 or 1 (H) */
                fr[j] += (rhr[j] - wgt * (alr * er - ali * ei)) / t0;
                fi[j] += (rhi[j] - wgt * (alr * ei + ali * er)) / t0;
            }
        }
        if (!recover) dots(m, s, P->sp, wgt, ur, ui, yr[0], yi[0], fr, fi);
        if (k >= 2) pair_sums(P, w, yr, yi, k, 1, ftr, fti, gtr, gti);
        for (int j = 0; j < s; ++j) { /* -(alpha gt + t0 ft - gamma g + f) */
            rr[j] = -(alr * gtr[j] - ali * gti[j] + t0 * ftr[j] - (P->gr * gr[j] - P->gi * gi[j]) + fr[j]);
            ri[j] = -(alr * gti[j] + ali * gtr[j] + t0 * fti[j] - (P->gr * gi[j] + P->gi * gr[j]) + fi[j]);
        }
        rr[s] = ri[s] = 0.0;
        memcpy(rhr, rr, sizeof(double) * (size_t)s);
        memcpy(rhi, ri, sizeof(double) * (size_t)s);
        kin__hom_lu_solve(m, &b->lu, rr, ri);
        if (k < HOM_NY) kin__hom_qmul(P, rr, ri, w->ykr[k], w->yki[k]);
    }
}

double kin__hom_series_step(const double *n, double target, double *rho_out, double *tail_out)
{
    const int K = HOM_ORDER;
    /* radius of convergence from the last coefficients (the smallest of
     * three ratio estimates: robust to one coefficient that happens to be
     * small) */
    double rho = INFINITY;
    if (n[K] > 0.0) rho = fmin(n[K - 1] / n[K], sqrt(n[K - 2] / n[K]));
    if (n[K - 1] > 0.0) rho = fmin(rho, n[K - 2] / n[K - 1]);
    *rho_out = rho, *tail_out = 0.0;
    if (!(rho < INFINITY)) return INFINITY; /* the series terminates: any step */
    if (!(rho > 0.0)) return 0.0;
    /* geometric tail: error(h) ~ tail (h / rho)^(K+1) for h <= rho / 2 */
    double tail = 2.0 * fmax(n[K] * pow(rho, K), n[K - 1] * pow(rho, K - 1));
    *tail_out = tail;
    double q = tail > 0.0 ? pow(target / tail, 1.0 / (K + 1)) : RADIUS_FRACTION;
    return fmin(q, RADIUS_FRACTION) * rho;
}

double kin__hom_series_error(double rho, double tail, double h)
{
    return rho < INFINITY ? tail * pow(h / rho, HOM_ORDER + 1) : 0.0;
}

/* the predictor's step for an error target, from the coefficients */
static double series_step(hom_ws *w, int m, double target)
{
    double n[HOM_ORDER + 1];
    for (int k = 1; k <= HOM_ORDER; ++k) n[k] = kin__hom_vnorm(m, w->cr[k], w->ci[k]);
    return kin__hom_series_step(n, target, &w->rho, &w->tail);
}

/* the error model's estimate for step h */
static double series_error(const hom_ws *w, double h) { return kin__hom_series_error(w->rho, w->tail, h); }

static void predict(const hom_ws *w, int m, double h, double *xr, double *xi)
{
    for (int c = 0; c < m; ++c) {
        double vr = w->cr[HOM_ORDER][c], vi = w->ci[HOM_ORDER][c];
        for (int k = HOM_ORDER - 1; k >= 0; --k) {
            vr = vr * h + w->cr[k][c];
            vi = vi * h + w->ci[k][c];
        }
        xr[c] = vr, xi[c] = vi;
    }
}

/* ---- endpoint: refine at t = 1 in the chart z_k = 1 and certify ---- */

void kin__hom_certify(const hom_problem *P, hom_ws *w, const double *xr, const double *xi, double *zr, double *zi,
                      hom_end *e)
{
    int m = P->m, s = P->s, k = 0;
    double big = -1.0;
    for (int c = 0; c < m; ++c) {
        double a = xr[c] * xr[c] + xi[c] * xi[c];
        if (a > big) big = a, k = c;
    }
    double car[HOM_MAX_M] = {0}, cai[HOM_MAX_M] = {0};
    car[k] = 1.0;
    e->chart = k;
    e->kind = HOM_SINGULAR;
    e->converged = 0;
    e->rminus = e->rplus = INFINITY;
    e->cond = INFINITY;
    hom_point *p = &w->pt[0];
    for (int c = 0; c < m; ++c) { /* z = x / x_k */
        p->xr[c] = (xr[c] * xr[k] + xi[c] * xi[k]) / big;
        p->xi[c] = (xi[c] * xr[k] - xr[c] * xi[k]) / big;
    }
    p->xr[k] = 1.0, p->xi[k] = 0.0;
    double dr[HOM_MAX_M], di[HOM_MAX_M], prev = INFINITY;
    for (int it = 0; it < REFINE_MAX; ++it) {
        if (!kin__hom_newton_step(P, car, cai, 1.0, p, dr, di)) break;
        double nd = kin__hom_vnorm(m, dr, di), nz = kin__hom_vnorm(m, p->xr, p->xi);
        int stalled = it > 0 && nd > REFINE_RATE * prev; /* rounding level, or not a simple root */
        if (!stalled || nd < prev) {
            for (int c = 0; c < m; ++c) p->xr[c] -= dr[c], p->xi[c] -= di[c];
            p->xr[k] = 1.0, p->xi[k] = 0.0;
        }
        if (stalled) {
            e->converged = nd <= sqrt(REFINE_TOL) * nz;
            break;
        }
        prev = nd;
        if (nd <= REFINE_TOL * nz) {
            e->converged = 1;
            break;
        }
    }
    memcpy(zr, p->xr, sizeof(double) * (size_t)m);
    memcpy(zi, p->xi, sizeof(double) * (size_t)m);
    for (int pass = 0; pass < 2; ++pass) {
        /* the certificate at z: eta = |J^-1 F(z)|, beta = |J^-1|_F (the
         * chart's s x s block: the inverse's columns for the F rows) */
        memcpy(p->xr, zr, sizeof(double) * (size_t)m);
        memcpy(p->xi, zi, sizeof(double) * (size_t)m);
        double jf = 0.0;
        kin__hom_eval(P, car, cai, 1.0, p);
        for (int j = 0; j < s; ++j) /* rows j < s of J, row by row (column-major) */
            for (int c = 0; c < m; ++c) {
                double a = p->lu.r[c * kin__hom_lanes_up(m) + j], b = p->lu.i[c * kin__hom_lanes_up(m) + j];
                jf += a * a + b * b;
            }
        if (!kin__hom_lu_factor(m, &p->lu)) return;
        memcpy(dr, p->hr, sizeof(double) * (size_t)m);
        memcpy(di, p->hi, sizeof(double) * (size_t)m);
        kin__hom_lu_solve(m, &p->lu, dr, di);
        double eta = kin__hom_vnorm(m, dr, di), beta2 = 0.0;
        for (int j = 0; j < s; ++j) {
            double vr[HOM_MAX_M] = {0}, vi[HOM_MAX_M] = {0};
            vr[j] = 1.0;
            kin__hom_lu_solve(m, &p->lu, vr, vi);
            for (int c = 0; c < m; ++c) beta2 += vr[c] * vr[c] + vi[c] * vi[c];
        }
        double beta = sqrt(beta2), L = 2.0 * P->normF, nz = kin__hom_vnorm(m, zr, zi);
        /* |F(z)| may be below the rounding of its evaluation (near a
         * multiple root it is): eta is bounded with that rounding added */
        eta += beta * sqrt((double)s) * EVAL_ROUNDING * m * nz * nz;
        double h = beta * L * eta;
        e->cond = sqrt(jf) * beta;
        if (!(h <= H_CERT) || !isfinite(e->cond)) return;
        double sq = sqrt(1.0 - 2.0 * h);
        double rminus = 2.0 * eta / (1.0 + sq), rplus = (1.0 + sq) / (beta * L);
        if (!(rminus <= R_MINUS_MAX * nz)) return;
        e->rminus = rminus, e->rplus = rplus;
        double im = kin__hom_vnorm(m, zi, zi) / sqrt(2.0); /* |Im z| */
        if (pass == 1 || im == 0.0) { /* z real: the conjugate root is in the same ball */
            e->kind = HOM_REAL;
            return;
        }
        if (2.0 * im + rminus < rplus) {
            /* the conjugate of the root lies in its uniqueness ball: the
             * root is real; certify at the real point Re z */
            memset(zi, 0, sizeof(double) * (size_t)m);
            continue;
        }
        if (im > rminus) e->kind = HOM_NONREAL;
        return;
    }
}

/* ---- tracking ---- */

void kin__hom_track(const hom_problem *P, const hom_settings *S, hom_ws *w, int path, double *zr, double *zi,
                    hom_end *e)
{
    int m = P->m;
    memset(e, 0, sizeof *e);
    e->kind = HOM_FAILED;
    e->rminus = e->rplus = e->cond = INFINITY;
    hom_point *base = &w->pt[0], *tr[2] = {&w->pt[1], &w->pt[2]};
    /* start solution: x_j = +-x_0, scaled into the chart */
    double sr = 0.0, si = 0.0;
    base->xr[0] = 1.0, base->xi[0] = 0.0;
    for (int j = 1; j < m; ++j) base->xr[j] = (path >> (j - 1)) & 1 ? -1.0 : 1.0, base->xi[j] = 0.0;
    double car[HOM_MAX_M], cai[HOM_MAX_M]; /* the chart, changed when x tilts away from it */
    memcpy(car, P->ar, sizeof car);
    memcpy(cai, P->ai, sizeof cai);
    double na = kin__hom_vnorm(m, car, cai);
    for (int c = 0; c < m; ++c) sr += P->ar[c] * base->xr[c], si += P->ai[c] * base->xr[c];
    double d = sr * sr + si * si;
    for (int c = 0; c < m; ++c) {
        double v = base->xr[c];
        base->xr[c] = v * sr / d, base->xi[c] = -v * si / d;
    }
    double t = 0.0, dr[HOM_MAX_M], di[HOM_MAX_M], xr[HOM_MAX_M], xi[HOM_MAX_M];
    if (!kin__hom_newton_step(P, car, cai, t, base, dr, di)) return;
    memcpy(xr, base->xr, sizeof xr);
    memcpy(xi, base->xi, sizeof xi);
    double rsep = 1.0 / (kin__hom_inv_norm1(m, &base->lu) * kin__hom_norm_A(P, t)), hcap = INFINITY;
    double calib = 1.0, calibp = 1.0; /* the Taylor and the rational error models' calibrations */
    int lost = 0;
    while (t < 1.0) {
        double sigma = 1.0 - t;
        if (sigma <= S->sigma_end) break;
        if (e->steps + e->rejected >= MAX_STEPS) {
            lost = 1;
            break;
        }
        double nx = kin__hom_vnorm(m, xr, xi);
        if (nx * na > CHART_TILT * sqrt((double)m)) {
            /* the path nears the chart's hyperplane at infinity, where
             * distances in the chart blow up: move to the chart through x
             * orthogonal to it, a = conj(x) / |x|^2 (a.x = 1, x unchanged) */
            for (int c = 0; c < m; ++c) car[c] = xr[c] / (nx * nx), cai[c] = -xi[c] / (nx * nx);
            na = 1.0 / nx;
            memcpy(base->xr, xr, sizeof xr);
            memcpy(base->xi, xi, sizeof xi);
            if (!kin__hom_newton_step(P, car, cai, t, base, dr, di)) {
                lost = 1;
                break;
            }
            rsep = 1.0 / (kin__hom_inv_norm1(m, &base->lu) * kin__hom_norm_A(P, t));
            e->recharts++;
        }
        memcpy(w->cr[0], xr, sizeof(double) * (size_t)m);
        memcpy(w->ci[0], xi, sizeof(double) * (size_t)m);
        taylor(P, w, base, t);
        double target = fmin(S->pred_rel * nx, S->pred_sep * rsep);
        double hser = series_step(w, m, target / calib), h = fmin(hser, hcap);
        hom_pade pd;
        kin__hom_pade_setup(m, (const double(*)[HOM_MAX_M])w->cr, (const double(*)[HOM_MAX_M])w->ci, &pd);
        int accepted = 0, first = 1;
        while (!accepted) {
            if (h >= sigma) h = sigma;
            /* the rational predictor where its estimate meets the target,
             * then as far as it does (first attempt only) */
            double pest = kin__hom_pade_error(&pd, h);
            int pade = pest <= target / calibp;
            if (pade && first)
                h = kin__hom_pade_extend(&pd, h, fmin(PADE_REACH * hser, hcap), sigma, target / calibp, &pest);
            first = 0;
            if (h < H_MIN) {
                lost = 1;
                break;
            }
            double t1 = h == sigma ? 1.0 : t + h;
            hom_point *p = tr[0];
            if (pade)
                kin__hom_pade_predict(m, (const double(*)[HOM_MAX_M])w->cr, (const double(*)[HOM_MAX_M])w->ci, &pd, h,
                                      p->xr, p->xi);
            else
                predict(w, m, h, p->xr, p->xi);
            double prevd = INFINITY;
            int ok = 0;
            for (int it = 0; it < NEWTON_MAX; ++it) {
                p = tr[it & 1];
                if (it > 0) {
                    const hom_point *q = tr[(it - 1) & 1];
                    for (int c = 0; c < m; ++c) p->xr[c] = q->xr[c] - dr[c], p->xi[c] = q->xi[c] - di[c];
                }
                if (!kin__hom_newton_step(P, car, cai, t1, p, dr, di)) break;
                double nd = kin__hom_vnorm(m, dr, di), np = kin__hom_vnorm(m, p->xr, p->xi);
                double tol = fmax(NEWTON_TOL, NOISE_FACTOR * DBL_EPSILON * np / rsep) * np;
                if (it == 0) {
                    /* calibrate the predictor's error model by the actual error */
                    double est = pade ? pest : series_error(w, h);
                    if (est > 0.0 && nd > 0.0) {
                        double *cal = pade ? &calibp : &calib;
                        *cal = fmin(CALIB_MAX, fmax(CALIB_MIN, sqrt(*cal * nd / est)));
                    }
                    double rs = 1.0 / (kin__hom_inv_norm1(m, &p->lu) * kin__hom_norm_A(P, t1));
                    if (!(nd <= S->corr_sep * rs) || !(nd <= CORR_REL_MAX * np)) break;
                    rsep = rs;
                } else {
                    /* the error left after this correction is about nd^2 / rsep */
                    if (nd * nd <= NEWTON_TOL * np * rsep || nd <= tol) {
                        ok = 1;
                        break;
                    }
                    if (!(nd <= CONTRACTION * prevd)) break;
                }
                prevd = nd;
            }
            if (ok) {
                for (int c = 0; c < m; ++c) xr[c] = p->xr[c] - dr[c], xi[c] = p->xi[c] - di[c];
                hom_point *tmp = base;
                base = p;
                if (p == tr[0]) tr[0] = tmp;
                else tr[1] = tmp;
                t = t1;
                hcap = h * ACCEPT_GROW;
                e->steps++;
                accepted = 1;
            } else {
                e->rejected++;
                h *= REJECT_SHRINK;
                hcap = h;
                if (e->steps + e->rejected >= MAX_STEPS) {
                    lost = 1;
                    break;
                }
            }
        }
        if (lost) break;
    }
    e->sigma = 1.0 - t;
    if (lost && e->sigma > SIGMA_STALL) {
        memcpy(zr, xr, sizeof(double) * (size_t)m);
        memcpy(zi, xi, sizeof(double) * (size_t)m);
        return;
    }
    kin__hom_certify(P, w, xr, xi, zr, zi, e);
}
