/* The path tracker of the symmetric complete solver (homotopy_sym.c): one
 * root of the quadrics M(t)[x, x] = 0, M(t) = A + t D (complex, symmetric),
 * followed from t = 0 to 1 in a random complex affine chart a.x = 1.
 *
 * Predictor: the Taylor series of x(t0 + h), as in homotopy_track.c but for
 * a general complex A and D: with M0 = M(t0), the coefficient of h^k of
 * M(t0 + h)[x(t0 + h), x(t0 + h)] = 0 gives, for k >= 1,
 *     J x_k = -( sum_{i+l=k, 0<i,l<k} M0[x_i, x_l] + sum_{i+l=k-1} D[x_i, x_l] ),
 *     a.x_k = 0,
 * J = 2 M0[x_0, .] (one LU per step), and M0[x_i, x_l] = x_l . (M0 x_i)
 * needs M0 x_i only for i <= k/2 (the forms are symmetric), D x_i for
 * i <= (k-1)/2. The step is the one whose estimated truncation error (from
 * the series' radius of convergence and last terms) meets pred_rel |x|.
 * Where the rational approximant [K-1/1] of the same series
 * (homotopy_pade.c) has an error estimate, calibrated along the path, that
 * meets the target at that step, it predicts instead, and the step grows
 * while its estimate still meets the target (as in homotopy_track.c; on
 * the hexagonal sail's flat state 17-26 % fewer steps, docs/performance.md).
 * Corrector: Newton at the new t. A step is accepted only if the first
 * correction is at most corr_rel |x| and the next ones contract by at least
 * CONTRACTION: for a quadratic map the ratio of two Newton corrections is
 * about |d0| / r, r the distance to the nearest other root, so a contraction
 * by 4 or more says the prediction was well inside the root's basin and the
 * path did not jump to another one.
 * Chart: when x tilts away from the chart's direction (the path nears the
 * chart's hyperplane at infinity), the chart is replaced by the one
 * orthogonal to x, as in homotopy_track.c. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/param/homotopy_param_control.h"
#include "homotopy/track/homotopy_lu.h"

/* the kernels are simple loops over contiguous arrays: let GCC vectorise
 * them (at -O2 its cost model leaves loops with a remainder scalar) */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("tree-vectorize", "vect-cost-model=dynamic")
#endif

/* compile the matrix-vector product for AVX2 too where possible (as
 * homotopy_track.c does; the result is bit-identical) */
#if defined(__x86_64__) && defined(__ELF__) && defined(__has_attribute) && !defined(KIN_NO_MULTIVERSION)
#if __has_attribute(target_clones)
#define HPAR_KERNEL __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef HPAR_KERNEL
#define HPAR_KERNEL
#endif

/* the step control (constants shared with the lockstep tracker) */
enum {
    ORDER = HPAR_ORDER,
    NY = HPAR_NY,
    NZ = HPAR_NZ,
    NEWTON_MAX = HPAR_NEWTON_MAX,
    REFINE_MAX = HPAR_REFINE_MAX,
    MAX_STEPS = HPAR_MAX_STEPS
};
#define NEWTON_TOL HPAR_NEWTON_TOL
#define CONTRACTION HPAR_CONTRACTION
#define NOISE HPAR_NOISE
#define STALL_TOL HPAR_STALL_TOL
#define REJECT_SHRINK HPAR_REJECT_SHRINK
#define ACCEPT_GROW HPAR_ACCEPT_GROW
#define H_MIN HPAR_H_MIN
#define CHART_TILT HPAR_CHART_TILT
#define REFINE_TOL HPAR_REFINE_TOL
/* the step is at most this fraction of the series' radius of convergence */
static const double RADIUS_FRACTION = 0.7;

struct hpar_ws {
    int m, s, sm;
    double *block; /* the one allocation behind the arrays below */
    double *m0r, *m0i, *m1r, *m1i; /* M(t) at the base point and at the trial point (stacked) */
    double *yr[NY], *yi[NY];       /* M0 x_k */
    double *zr[NZ], *zi[NZ];       /* D x_k */
    double *pyr, *pyi;             /* M(t1) x at a corrector iterate */
    double cr[ORDER + 1][HOM_MAX_M], ci[ORDER + 1][HOM_MAX_M];
    hom_lu lu;                     /* J, then its LU factors (the one-path tracker's kernel) */
};

hpar_ws *kin__hpar_ws_new(int m, int s)
{
    hpar_ws *w = calloc(1, sizeof *w);
    if (!w) return NULL;
    w->m = m, w->s = s, w->sm = s * m;
    size_t mat = (size_t)s * m * m, vec = (size_t)s * m;
    size_t total = 4 * mat + 2 * vec * (NY + NZ + 1);
    double *b = malloc(sizeof(double) * total);
    if (!b) {
        free(w);
        return NULL;
    }
    w->block = b;
    w->m0r = b, w->m0i = b + mat, w->m1r = b + 2 * mat, w->m1i = b + 3 * mat;
    b += 4 * mat;
    for (int k = 0; k < NY; ++k) w->yr[k] = b, w->yi[k] = b + vec, b += 2 * vec;
    for (int k = 0; k < NZ; ++k) w->zr[k] = b, w->zi[k] = b + vec, b += 2 * vec;
    w->pyr = b, w->pyi = b + vec;
    return w;
}

void kin__hpar_ws_free(hpar_ws *w)
{
    if (!w) return;
    free(w->block);
    free(w);
}

HPAR_KERNEL static void matvec(int sm, int m, const double *restrict Mr, const double *restrict Mi,
                               const double *restrict xr, const double *restrict xi, double *restrict yr,
                               double *restrict yi)
{
    for (int i = 0; i < sm; ++i) yr[i] = yi[i] = 0.0;
    for (int c = 0; c < m; ++c) {
        const double *cr = Mr + (size_t)c * sm, *ci = Mi + (size_t)c * sm;
        double a = xr[c], b = xi[c];
        for (int i = 0; i < sm; ++i) {
            yr[i] += cr[i] * a - ci[i] * b;
            yi[i] += cr[i] * b + ci[i] * a;
        }
    }
}

/* M = A + t D (stacked) */
HPAR_KERNEL static void form(const hpar_problem *P, double t, double *restrict Mr, double *restrict Mi)
{
    size_t n = (size_t)P->s * P->m * P->m;
    for (size_t i = 0; i < n; ++i) Mr[i] = P->Ar[i] + t * P->Dr[i], Mi[i] = P->Ai[i] + t * P->Di[i];
}

/* out_j += wgt * (u . y_j), j < s (y_j: entries r*s + j of y): the
 * equations are the inner, contiguous loop (independent sums) */
HPAR_KERNEL static void dots(int m, int s, double wgt, const double *restrict ur, const double *restrict ui,
                             const double *restrict yr, const double *restrict yi, double *restrict outr,
                             double *restrict outi)
{
    double pr[HOM_MAX_M] = {0}, pi[HOM_MAX_M] = {0};
    for (int r = 0; r < m; ++r) {
        const double *ar = yr + r * s, *ai = yi + r * s;
        double a = ur[r], b = ui[r];
        for (int j = 0; j < s; ++j) pr[j] += a * ar[j] - b * ai[j], pi[j] += a * ai[j] + b * ar[j];
    }
    for (int j = 0; j < s; ++j) outr[j] += wgt * pr[j], outi[j] += wgt * pi[j];
}

static double vnorm(int n, const double *xr, const double *xi)
{
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += xr[k] * xr[k] + xi[k] * xi[k];
    return sqrt(s);
}

/* Newton's correction d = J^-1 H at x for the system M (stacked) in the
 * chart (car, cai); J's LU factors stay in w. y: scratch for M x. 0 if J is
 * singular. */
static int newton(const hpar_problem *P, hpar_ws *w, const double *Mr, const double *Mi, const double *car,
                  const double *cai, const double *xr, const double *xi, double *yr, double *yi, double *dr,
                  double *di)
{
    int m = P->m, s = P->s;
    matvec(w->sm, m, Mr, Mi, xr, xi, yr, yi);
    for (int j = 0; j < s; ++j) dr[j] = di[j] = 0.0;
    dots(m, s, 1.0, xr, xi, yr, yi, dr, di);
    double cr = -1.0, ci = 0.0;
    for (int c = 0; c < m; ++c) {
        cr += car[c] * xr[c] - cai[c] * xi[c];
        ci += car[c] * xi[c] + cai[c] * xr[c];
    }
    dr[s] = cr, di[s] = ci;
    int np = kin__hom_lanes_up(m);
    for (int c = 0; c < m; ++c) { /* J(j, c) = 2 (M_j x)_c (symmetric M_j); the chart row; rows m..np-1 zero */
        double *jr = w->lu.r + c * np, *ji = w->lu.i + c * np;
        for (int j = 0; j < s; ++j) jr[j] = 2.0 * yr[c * s + j], ji[j] = 2.0 * yi[c * s + j];
        jr[s] = car[c], ji[s] = cai[c];
        for (int j = m; j < np; ++j) jr[j] = ji[j] = 0.0;
    }
    if (!kin__hom_lu_factor(m, &w->lu)) return 0;
    kin__hom_lu_solve(m, &w->lu, dr, di);
    return isfinite(vnorm(m, dr, di));
}

/* Taylor coefficients c[1..ORDER] of the path through c[0] at t0 (w->m0:
 * M(t0); J's factors at (about) c[0] in w) */
static void taylor(const hpar_problem *P, hpar_ws *w)
{
    int m = P->m, s = P->s, sm = w->sm;
    matvec(sm, m, w->m0r, w->m0i, w->cr[0], w->ci[0], w->yr[0], w->yi[0]);
    matvec(sm, m, P->Dr, P->Di, w->cr[0], w->ci[0], w->zr[0], w->zi[0]);
    for (int k = 1; k <= ORDER; ++k) {
        double *rr = w->cr[k], *ri = w->ci[k];
        for (int j = 0; j <= s; ++j) rr[j] = ri[j] = 0.0;
        for (int i = 1; 2 * i <= k; ++i) /* sum_{0<i,l<k, i+l=k} M0[x_i, x_l] */
            dots(m, s, 2 * i < k ? 2.0 : 1.0, w->cr[k - i], w->ci[k - i], w->yr[i], w->yi[i], rr, ri);
        for (int i = 0; 2 * i <= k - 1; ++i) /* sum_{i+l=k-1} D[x_i, x_l] */
            dots(m, s, 2 * i < k - 1 ? 2.0 : 1.0, w->cr[k - 1 - i], w->ci[k - 1 - i], w->zr[i], w->zi[i], rr, ri);
        for (int j = 0; j < s; ++j) rr[j] = -rr[j], ri[j] = -ri[j];
        kin__hom_lu_solve(m, &w->lu, rr, ri);
        if (k < NY) matvec(sm, m, w->m0r, w->m0i, rr, ri, w->yr[k], w->yi[k]);
        if (k < NZ) matvec(sm, m, P->Dr, P->Di, rr, ri, w->zr[k], w->zi[k]);
    }
}

double kin__hpar_series_step(const double *n, double target)
{
    const int K = ORDER;
    double rho = INFINITY;
    if (n[K] > 0.0) rho = fmin(n[K - 1] / n[K], sqrt(n[K - 2] / n[K]));
    if (n[K - 1] > 0.0) rho = fmin(rho, n[K - 2] / n[K - 1]);
    if (!(rho < INFINITY)) return INFINITY;
    if (!(rho > 0.0)) return 0.0;
    double tail = 2.0 * fmax(n[K] * pow(rho, K), n[K - 1] * pow(rho, K - 1));
    double q = tail > 0.0 ? pow(target / tail, 1.0 / (K + 1)) : RADIUS_FRACTION;
    return fmin(q, RADIUS_FRACTION) * rho;
}

/* the step whose estimated truncation error is `target` */
static double series_step(hpar_ws *w, int m, double target)
{
    double n[ORDER + 1];
    for (int k = 1; k <= ORDER; ++k) n[k] = vnorm(m, w->cr[k], w->ci[k]);
    return kin__hpar_series_step(n, target);
}

static void predict(const hpar_ws *w, int m, double h, double *xr, double *xi)
{
    for (int c = 0; c < m; ++c) {
        double vr = w->cr[ORDER][c], vi = w->ci[ORDER][c];
        for (int k = ORDER - 1; k >= 0; --k) vr = vr * h + w->cr[k][c], vi = vi * h + w->ci[k][c];
        xr[c] = vr, xi[c] = vi;
    }
}

/* Newton from (xr, xi) for the system w->m1 in the chart; 1 if it was
 * accepted (x then the corrected point). *nd0: the first correction's norm
 * (the predictor's error), 0 if there was none. */
static int correct(const hpar_problem *P, const hpar_settings *S, hpar_ws *w, const double *car, const double *cai,
                   double *xr, double *xi, double *nd0)
{
    int m = P->m;
    double dr[HOM_MAX_M], di[HOM_MAX_M], prev = INFINITY;
    *nd0 = 0.0;
    for (int it = 0; it < NEWTON_MAX; ++it) {
        if (!newton(P, w, w->m1r, w->m1i, car, cai, xr, xi, w->pyr, w->pyi, dr, di)) return 0;
        double nd = vnorm(m, dr, di), nx = vnorm(m, xr, xi);
        if (it == 0) *nd0 = nd;
        /* at rounding level there is no contraction to see: a correction
         * below NOISE |x|, or two below NEWTON_TOL |x| and STALL_TOL |x| (the
         * rounding of a point far out in its chart) */
        int noise = nd <= NOISE * nx || (it > 0 && nd <= NEWTON_TOL * nx && prev <= STALL_TOL * nx);
        if (it == 0 && !(nd <= S->corr_rel * nx)) return 0;
        if (it > 0 && !noise && !(nd <= CONTRACTION * prev)) return 0;
        for (int c = 0; c < m; ++c) xr[c] -= dr[c], xi[c] -= di[c];
        if (noise || (it > 0 && nd <= NEWTON_TOL * nx)) return 1;
        prev = nd;
    }
    return 0;
}

void kin__hpar_track(const hpar_problem *P, const hpar_settings *S, hpar_ws *w, const double *x0r,
                     const double *x0i, double *xr, double *xi, hpar_end *e)
{
    int m = P->m;
    memset(e, 0, sizeof *e);
    e->sigma = 1.0;
    double car[HOM_MAX_M], cai[HOM_MAX_M];
    memcpy(car, P->ar, sizeof car);
    memcpy(cai, P->ai, sizeof cai);
    double na = vnorm(m, car, cai);
    /* x0 scaled into the chart */
    double sr = 0.0, si = 0.0;
    for (int c = 0; c < m; ++c) sr += car[c] * x0r[c] - cai[c] * x0i[c], si += car[c] * x0i[c] + cai[c] * x0r[c];
    double d = sr * sr + si * si;
    if (!(d > 0.0)) return;
    for (int c = 0; c < m; ++c)
        xr[c] = (x0r[c] * sr + x0i[c] * si) / d, xi[c] = (x0i[c] * sr - x0r[c] * si) / d;
    double nx0 = vnorm(m, xr, xi);
    if (nx0 * na > CHART_TILT * sqrt((double)m)) { /* x0 far out in the chart: the one orthogonal to it */
        for (int c = 0; c < m; ++c) car[c] = xr[c] / (nx0 * nx0), cai[c] = -xi[c] / (nx0 * nx0);
        na = 1.0 / nx0;
    }
    double t = 0.0, hcap = INFINITY, calib = 1.0, nd0; /* calib: the rational predictor's calibration */
    form(P, 0.0, w->m1r, w->m1i);
    if (!correct(P, S, w, car, cai, xr, xi, &nd0)) return;
    double *tmp;
    tmp = w->m0r, w->m0r = w->m1r, w->m1r = tmp;
    tmp = w->m0i, w->m0i = w->m1i, w->m1i = tmp;
    double pr[HOM_MAX_M], pi[HOM_MAX_M];
    while (1.0 - t > S->sigma_end) {
        double sigma = 1.0 - t, nx = vnorm(m, xr, xi);
        if (e->steps + e->rejected >= MAX_STEPS) break;
        int fresh = e->steps == 0;
        if (nx * na > CHART_TILT * sqrt((double)m)) { /* move to the chart orthogonal to x */
            for (int c = 0; c < m; ++c) car[c] = xr[c] / (nx * nx), cai[c] = -xi[c] / (nx * nx);
            na = 1.0 / nx;
            fresh = 1;
        }
        /* J for the series: the corrector's last factors (at the iterate
         * before the last, tiny, correction), or fresh ones in a new chart */
        double dr[HOM_MAX_M], di[HOM_MAX_M];
        if (fresh && !newton(P, w, w->m0r, w->m0i, car, cai, xr, xi, w->pyr, w->pyi, dr, di)) break;
        memcpy(w->cr[0], xr, sizeof(double) * (size_t)m);
        memcpy(w->ci[0], xi, sizeof(double) * (size_t)m);
        taylor(P, w);
        double target = S->pred_rel * nx, hser = series_step(w, m, target), h = fmin(hser, hcap);
        hom_pade pd;
        kin__hom_pade_setup_order(ORDER, m, (const double(*)[HOM_MAX_M])w->cr, (const double(*)[HOM_MAX_M])w->ci,
                                  &pd);
        int accepted = 0, first = 1;
        while (!accepted) {
            if (h >= sigma) h = sigma;
            /* the rational predictor where its estimate meets the target
             * (and as far as it does on the first attempt) */
            double pest;
            int pade = kin__hpar_pade_attempt(&pd, first, hser, hcap, sigma, target, calib, &h, &pest);
            first = 0;
            if (h < H_MIN) break;
            double t1 = h == sigma ? 1.0 : t + h;
            if (pade)
                kin__hom_pade_predict(m, (const double(*)[HOM_MAX_M])w->cr, (const double(*)[HOM_MAX_M])w->ci, &pd, h,
                                      pr, pi);
            else
                predict(w, m, h, pr, pi);
            form(P, t1, w->m1r, w->m1i);
            int ok = correct(P, S, w, car, cai, pr, pi, &nd0);
            if (pade) calib = kin__hpar_pade_calibrate(calib, pest, nd0);
            if (ok) {
                accepted = 1;
                memcpy(xr, pr, sizeof pr[0] * (size_t)m);
                memcpy(xi, pi, sizeof pi[0] * (size_t)m);
                t = t1;
                hcap = h * ACCEPT_GROW;
                e->steps++;
                e->pade += pade;
                tmp = w->m0r, w->m0r = w->m1r, w->m1r = tmp;
                tmp = w->m0i, w->m0i = w->m1i, w->m1i = tmp;
            } else {
                e->rejected++;
                e->pade_rejected += pade;
                h *= REJECT_SHRINK;
                hcap = h;
                if (e->steps + e->rejected >= MAX_STEPS) break;
            }
        }
        if (!accepted) break;
    }
    e->sigma = 1.0 - t;
    if (e->sigma > S->sigma_end) return;
    if (S->sigma_end > 0.0) {
        e->ok = 1;
        return;
    }
    /* at t = 1 (w->m0 = B): refine to rounding level */
    double dr[HOM_MAX_M], di[HOM_MAX_M];
    for (int it = 0; it < REFINE_MAX; ++it) {
        if (!newton(P, w, w->m0r, w->m0i, car, cai, xr, xi, w->pyr, w->pyi, dr, di)) return;
        double nd = vnorm(m, dr, di), nx = vnorm(m, xr, xi);
        for (int c = 0; c < m; ++c) xr[c] -= dr[c], xi[c] -= di[c];
        if (nd <= REFINE_TOL * nx) {
            e->ok = 1;
            return;
        }
    }
}

/* The entry points the other files call: plain functions that call the
 * cloned kernels of this file (homotopy_control.h: a cloned function is
 * called only from the file that defines it). */
void kin__hpar_matvec(int sm, int m, const double *restrict Mr, const double *restrict Mi,
                      const double *restrict xr, const double *restrict xi, double *restrict yr,
                      double *restrict yi)
{
    matvec(sm, m, Mr, Mi, xr, xi, yr, yi);
}
