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

#include "homotopy_control.h"

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
 * duplicate search (homotopy.c) compares endpoints at 1e-6 and relies on
 * existence balls far smaller than that. */
static const double R_MINUS_MAX = 1e-8;

/* Complex n x n matrices are column-major with the column stride
 * np = n rounded up to whole lanes (entry (i, j) at j*np + i, rows n..np-1
 * zero): the factorisation's updates and both substitutions run down
 * contiguous columns in whole groups of HOM_LANES rows (independent
 * updates the compiler puts in vector registers), the rows outside the
 * range being multiplied by stored zeros. Every entry in the range receives
 * the same operations in the same order as in a row-oriented elimination. */
typedef struct hom_lu {
    double r[HOM_MM], i[HOM_MM];     /* J; after factoring, U strictly above the diagonal (zeros on
                                        and below it) */
    double lr[HOM_MM], li[HOM_MM];   /* after factoring, L strictly below the diagonal (zeros on
                                        and above it; the unit diagonal is implied) */
    double dr[HOM_MAX_M], di[HOM_MAX_M]; /* 1 / U_kk */
    int piv[HOM_MAX_M];
} hom_lu;

/* a point with Q x, H and the LU factors of J */
typedef struct hom_point {
    double xr[HOM_MAX_M], xi[HOM_MAX_M];
    double yr[HOM_MAX_ROWS], yi[HOM_MAX_ROWS];
    double hr[HOM_MAX_M], hi[HOM_MAX_M];
    hom_lu lu;
} hom_point;

struct hom_ws {
    hom_point pt[3]; /* base point and two corrector iterates, used by rotation */
    double cr[HOM_ORDER + 1][HOM_MAX_M], ci[HOM_ORDER + 1][HOM_MAX_M]; /* Taylor coefficients */
    double ykr[HOM_NY][HOM_MAX_ROWS], yki[HOM_NY][HOM_MAX_ROWS]; /* Q x_k, k >= 1 */
    double rho, tail; /* the series' error model (series_step) */
};

hom_ws *kin__hom_ws_new(void) { return malloc(sizeof(hom_ws)); }
void kin__hom_ws_free(hom_ws *w) { free(w); }

/* ---- small complex linear algebra on split arrays ---- */

static double vnorm(int n, const double *xr, const double *xi)
{
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += xr[k] * xr[k] + xi[k] * xi[k];
    return sqrt(s);
}

/* rows i .. i + 7 of y = Q x from block qb of the blocked copy of Q */
#define HOM_QBLOCK_DECL(r, im)                                                                                     \
    double r##0 = 0.0, r##1 = 0.0, r##2 = 0.0, r##3 = 0.0, r##4 = 0.0, r##5 = 0.0, r##6 = 0.0, r##7 = 0.0;         \
    double im##0 = 0.0, im##1 = 0.0, im##2 = 0.0, im##3 = 0.0, im##4 = 0.0, im##5 = 0.0, im##6 = 0.0, im##7 = 0.0
#define HOM_QBLOCK_ACC(r, im, q, a, b)                                                                             \
    (r##0 += (q)[0] * (a), r##1 += (q)[1] * (a), r##2 += (q)[2] * (a), r##3 += (q)[3] * (a),                      \
     r##4 += (q)[4] * (a), r##5 += (q)[5] * (a), r##6 += (q)[6] * (a), r##7 += (q)[7] * (a),                      \
     im##0 += (q)[0] * (b), im##1 += (q)[1] * (b), im##2 += (q)[2] * (b), im##3 += (q)[3] * (b),                  \
     im##4 += (q)[4] * (b), im##5 += (q)[5] * (b), im##6 += (q)[6] * (b), im##7 += (q)[7] * (b))
#define HOM_QBLOCK_STORE(r, im, u, v)                                                                              \
    ((u)[0] = r##0, (u)[1] = r##1, (u)[2] = r##2, (u)[3] = r##3, (u)[4] = r##4, (u)[5] = r##5, (u)[6] = r##6,      \
     (u)[7] = r##7, (v)[0] = im##0, (v)[1] = im##1, (v)[2] = im##2, (v)[3] = im##3, (v)[4] = im##4,              \
     (v)[5] = im##5, (v)[6] = im##6, (v)[7] = im##7)

/* y_i = sum_c Q[i][c] x_c, i < m*sp (the interleaved rows: y[r*sp + j] is
 * row r of Q_j x), from the blocked copy of Q: eight rows at a time, their
 * entries of column c adjacent (independent sums over c in order, which the
 * compiler pairs in vector registers); `pairs`: two blocks at once (sixteen
 * independent sums: with 4-wide registers, eight would leave the adders
 * waiting on their own latency; with 2-wide ones, sixteen would not fit) */
HOM_INLINE void qmul_blocks(const hom_problem *P, int pairs, const double *restrict xr, const double *restrict xi,
                            double *restrict yr, double *restrict yi)
{
    int n = P->sp * P->m, m = P->m, i = 0;
    const double *qb = P->Qb;
    if (pairs)
        for (; i + 2 * HOM_QBLOCK <= n; i += 2 * HOM_QBLOCK, qb += 2 * HOM_QBLOCK * m) {
            HOM_QBLOCK_DECL(r, ri);
            HOM_QBLOCK_DECL(u, ui);
            const double *qc = qb + HOM_QBLOCK * m;
            for (int c = 0; c < m; ++c) {
                double a = xr[c], b = xi[c];
                HOM_QBLOCK_ACC(r, ri, qb + HOM_QBLOCK * c, a, b);
                HOM_QBLOCK_ACC(u, ui, qc + HOM_QBLOCK * c, a, b);
            }
            HOM_QBLOCK_STORE(r, ri, yr + i, yi + i);
            HOM_QBLOCK_STORE(u, ui, yr + i + HOM_QBLOCK, yi + i + HOM_QBLOCK);
        }
    for (; i < n; i += HOM_QBLOCK, qb += HOM_QBLOCK * m) {
        HOM_QBLOCK_DECL(r, ri);
        for (int c = 0; c < m; ++c) {
            double a = xr[c], b = xi[c];
            HOM_QBLOCK_ACC(r, ri, qb + HOM_QBLOCK * c, a, b);
        }
        HOM_QBLOCK_STORE(r, ri, yr + i, yi + i); /* padded to a whole block */
    }
}

#if defined(HOM_MULTIVERSION)
__attribute__((target("avx2"))) static void qmul_avx2(const hom_problem *P, const double *xr, const double *xi,
                                                      double *yr, double *yi)
{
    qmul_blocks(P, 1, xr, xi, yr, yi);
}
#endif

static void qmul(const hom_problem *P, const double *xr, const double *xi, double *yr, double *yi)
{
#if defined(HOM_MULTIVERSION)
    if (__builtin_cpu_supports("avx2")) {
        qmul_avx2(P, xr, xi, yr, yi);
        return;
    }
#endif
    qmul_blocks(P, 0, xr, xi, yr, yi);
}

static int lanes_up(int n) { return (n + HOM_LANES - 1) / HOM_LANES * HOM_LANES; }

/* b[i] -= (lr + i li)[i] * (vr + i vi) for lo <= i < hi, lo and hi whole
 * lanes */
HOM_INLINE void axpy_sub(int lo, int hi, const double *restrict lr, const double *restrict li, double vr,
                         double vi, double *restrict br, double *restrict bi)
{
    for (int i = lo; i < hi; i += HOM_LANES) {
        br[i] -= lr[i] * vr - li[i] * vi, bi[i] -= lr[i] * vi + li[i] * vr;
        br[i + 1] -= lr[i + 1] * vr - li[i + 1] * vi, bi[i + 1] -= lr[i + 1] * vi + li[i + 1] * vr;
        br[i + 2] -= lr[i + 2] * vr - li[i + 2] * vi, bi[i + 2] -= lr[i + 2] * vi + li[i + 2] * vr;
        br[i + 3] -= lr[i + 3] * vr - li[i + 3] * vi, bi[i + 3] -= lr[i + 3] * vi + li[i + 3] * vr;
    }
}

/* LU with partial pivoting (largest |re| + |im|) in place; 0 if singular */
HOM_KERNEL static int lu_factor(int n, hom_lu *F)
{
    int np = lanes_up(n);
    double *Ar = F->r, *Ai = F->i;
    for (int k = 0; k < n; ++k) {
        double *lr = Ar + k * np, *li = Ai + k * np; /* column k */
        int p = k;
        double best = fabs(lr[k]) + fabs(li[k]);
        for (int i = k + 1; i < n; ++i) {
            double v = fabs(lr[i]) + fabs(li[i]);
            if (v > best) best = v, p = i;
        }
        F->piv[k] = p;
        if (!(best > 0.0) || !isfinite(best)) return 0;
        if (p != k) /* rows k and p: of L in columns j < k, of the rest in the others */
            for (int j = 0; j < n; ++j) {
                double *cr = j < k ? F->lr : Ar, *ci = j < k ? F->li : Ai;
                double t = cr[j * np + k];
                cr[j * np + k] = cr[j * np + p], cr[j * np + p] = t;
                t = ci[j * np + k];
                ci[j * np + k] = ci[j * np + p], ci[j * np + p] = t;
            }
        double pr = lr[k], pi = li[k], d = pr * pr + pi * pi;
        double ir = pr / d, ii = -pi / d; /* 1 / pivot */
        F->dr[k] = ir, F->di[k] = ii;
        /* column k of L, in F->lr (zeros outside k < i < n) */
        double *restrict mr = F->lr + k * np, *restrict mi = F->li + k * np;
        for (int i = 0; i < np; ++i) mr[i] = mi[i] = 0.0;
        for (int i = k + 1; i < n; ++i) {
            mr[i] = lr[i] * ir - li[i] * ii, mi[i] = lr[i] * ii + li[i] * ir;
            lr[i] = li[i] = 0.0;
        }
        int lo = (k + 1) / HOM_LANES * HOM_LANES;
        for (int j = k + 1; j < n; ++j) /* column j -= L(:, k) U(k, j) */
            axpy_sub(lo, np, mr, mi, Ar[j * np + k], Ai[j * np + k], Ar + j * np, Ai + j * np);
    }
    for (int j = 0; j < n; ++j) Ar[j * np + j] = Ai[j * np + j] = 0.0; /* U's diagonal is in dr, di */
    return 1;
}

/* exchange entries p and k of the split complex vector (br, bi) */
static void swap_entries(int p, int k, double *br, double *bi)
{
    if (p == k) return;
    double t = br[k];
    br[k] = br[p], br[p] = t;
    t = bi[k];
    bi[k] = bi[p], bi[p] = t;
}

/* b[lo..hi-1] -= sum_{c = 0..3} (cr[c] + i ci[c]) (vr[c] + i vi[c]), the four
 * columns applied in the order given (lo, hi whole lanes): b stays in
 * registers across the four updates */
#define HOM_UPD4(x, y, cr, ci, k, i, vr, vi)                                                                       \
    (x##0 -= cr[k][i] * vr[k] - ci[k][i] * vi[k], y##0 -= cr[k][i] * vi[k] + ci[k][i] * vr[k],                     \
     x##1 -= cr[k][i + 1] * vr[k] - ci[k][i + 1] * vi[k], y##1 -= cr[k][i + 1] * vi[k] + ci[k][i + 1] * vr[k],     \
     x##2 -= cr[k][i + 2] * vr[k] - ci[k][i + 2] * vi[k], y##2 -= cr[k][i + 2] * vi[k] + ci[k][i + 2] * vr[k],     \
     x##3 -= cr[k][i + 3] * vr[k] - ci[k][i + 3] * vi[k], y##3 -= cr[k][i + 3] * vi[k] + ci[k][i + 3] * vr[k])
/* x + i y -= (lr + i li) (vr + i vi) */
#define HOM_CSUB(x, y, lr, li, vr, vi) ((x) -= (lr) * (vr) - (li) * (vi), (y) -= (lr) * (vi) + (li) * (vr))
HOM_INLINE void axpy4_sub(int lo, int hi, const double *const *cr, const double *const *ci, const double *vr,
                          const double *vi, double *restrict br, double *restrict bi)
{
    for (int i = lo; i < hi; i += HOM_LANES) {
        double x0 = br[i], x1 = br[i + 1], x2 = br[i + 2], x3 = br[i + 3];
        double y0 = bi[i], y1 = bi[i + 1], y2 = bi[i + 2], y3 = bi[i + 3];
        HOM_UPD4(x, y, cr, ci, 0, i, vr, vi);
        HOM_UPD4(x, y, cr, ci, 1, i, vr, vi);
        HOM_UPD4(x, y, cr, ci, 2, i, vr, vi);
        HOM_UPD4(x, y, cr, ci, 3, i, vr, vi);
        br[i] = x0, br[i + 1] = x1, br[i + 2] = x2, br[i + 3] = x3;
        bi[i] = y0, bi[i + 1] = y1, bi[i + 2] = y2, bi[i + 3] = y3;
    }
}

/* b <- A^-1 b: column-oriented substitutions (independent updates), in
 * blocks of four columns (the block's triangle in scalars, then the rows
 * beyond it updated by all four columns at once); every entry receives the
 * updates of the columns in the same order as one column at a time. b has
 * lanes_up(n) entries (the last ones scratch). */
HOM_KERNEL static void lu_solve(int n, const hom_lu *F, double *restrict br, double *restrict bi)
{
    int np = lanes_up(n), j0 = 0;
    for (int k = 0; k < n; ++k) swap_entries(F->piv[k], k, br, bi);
    for (; j0 + HOM_LANES <= n; j0 += HOM_LANES) { /* L y = b, unit diagonal */
        const double *cr[HOM_LANES], *ci[HOM_LANES];
        for (int a = 0; a < HOM_LANES; ++a) cr[a] = F->lr + (j0 + a) * np, ci[a] = F->li + (j0 + a) * np;
        double vr[HOM_LANES], vi[HOM_LANES];
        double x0 = br[j0], y0 = bi[j0], x1 = br[j0 + 1], y1 = bi[j0 + 1];
        double x2 = br[j0 + 2], y2 = bi[j0 + 2], x3 = br[j0 + 3], y3 = bi[j0 + 3];
        HOM_CSUB(x1, y1, cr[0][j0 + 1], ci[0][j0 + 1], x0, y0);
        HOM_CSUB(x2, y2, cr[0][j0 + 2], ci[0][j0 + 2], x0, y0);
        HOM_CSUB(x3, y3, cr[0][j0 + 3], ci[0][j0 + 3], x0, y0);
        HOM_CSUB(x2, y2, cr[1][j0 + 2], ci[1][j0 + 2], x1, y1);
        HOM_CSUB(x3, y3, cr[1][j0 + 3], ci[1][j0 + 3], x1, y1);
        HOM_CSUB(x3, y3, cr[2][j0 + 3], ci[2][j0 + 3], x2, y2);
        br[j0] = vr[0] = x0, bi[j0] = vi[0] = y0, br[j0 + 1] = vr[1] = x1, bi[j0 + 1] = vi[1] = y1;
        br[j0 + 2] = vr[2] = x2, bi[j0 + 2] = vi[2] = y2, br[j0 + 3] = vr[3] = x3, bi[j0 + 3] = vi[3] = y3;
        axpy4_sub(j0 + HOM_LANES, np, cr, ci, vr, vi, br, bi);
    }
    for (int j = j0; j < n - 1; ++j) {
        double vr = br[j], vi = bi[j];
        if (vr == 0.0 && vi == 0.0) continue;
        axpy_sub((j + 1) / HOM_LANES * HOM_LANES, np, F->lr + j * np, F->li + j * np, vr, vi, br, bi);
    }
    /* U x = y: the columns beyond the last whole block one at a time */
    for (int j = n - 1; j >= j0; --j) {
        double vr = br[j] * F->dr[j] - bi[j] * F->di[j], vi = br[j] * F->di[j] + bi[j] * F->dr[j];
        br[j] = vr, bi[j] = vi;
        axpy_sub(0, lanes_up(j), F->r + j * np, F->i + j * np, vr, vi, br, bi);
    }
    for (j0 -= HOM_LANES; j0 >= 0; j0 -= HOM_LANES) {
        const double *cr[HOM_LANES], *ci[HOM_LANES]; /* the block's columns, last first */
        for (int a = 0; a < HOM_LANES; ++a)
            cr[a] = F->r + (j0 + HOM_LANES - 1 - a) * np, ci[a] = F->i + (j0 + HOM_LANES - 1 - a) * np;
        const double *dr = F->dr + j0, *di = F->di + j0;
        double vr[HOM_LANES], vi[HOM_LANES], t;
        double x0 = br[j0], y0 = bi[j0], x1 = br[j0 + 1], y1 = bi[j0 + 1];
        double x2 = br[j0 + 2], y2 = bi[j0 + 2], x3 = br[j0 + 3], y3 = bi[j0 + 3];
        t = x3 * dr[3] - y3 * di[3], y3 = x3 * di[3] + y3 * dr[3], x3 = t;
        HOM_CSUB(x0, y0, cr[0][j0], ci[0][j0], x3, y3);
        HOM_CSUB(x1, y1, cr[0][j0 + 1], ci[0][j0 + 1], x3, y3);
        HOM_CSUB(x2, y2, cr[0][j0 + 2], ci[0][j0 + 2], x3, y3);
        t = x2 * dr[2] - y2 * di[2], y2 = x2 * di[2] + y2 * dr[2], x2 = t;
        HOM_CSUB(x0, y0, cr[1][j0], ci[1][j0], x2, y2);
        HOM_CSUB(x1, y1, cr[1][j0 + 1], ci[1][j0 + 1], x2, y2);
        t = x1 * dr[1] - y1 * di[1], y1 = x1 * di[1] + y1 * dr[1], x1 = t;
        HOM_CSUB(x0, y0, cr[2][j0], ci[2][j0], x1, y1);
        t = x0 * dr[0] - y0 * di[0], y0 = x0 * di[0] + y0 * dr[0], x0 = t;
        br[j0] = vr[3] = x0, bi[j0] = vi[3] = y0, br[j0 + 1] = vr[2] = x1, bi[j0 + 1] = vi[2] = y1;
        br[j0 + 2] = vr[1] = x2, bi[j0 + 2] = vi[1] = y2, br[j0 + 3] = vr[0] = x3, bi[j0 + 3] = vi[0] = y3;
        axpy4_sub(0, j0, cr, ci, vr, vi, br, bi);
    }
}

/* b <- A^-H b (A = P^T L U, so A^H = U^H L^H P) */
static void lu_solve_adj(int n, const hom_lu *F, double *br, double *bi)
{
    int np = lanes_up(n);
    const double *Ar = F->r, *Ai = F->i;
    for (int j = 0; j < n; ++j) { /* U^H w = b: forward, column j of U^H is conj of row j of U */
        double vr = br[j] * F->dr[j] + bi[j] * F->di[j], vi = bi[j] * F->dr[j] - br[j] * F->di[j];
        br[j] = vr, bi[j] = vi;
        for (int i = j + 1; i < n; ++i) {
            double ur = Ar[i * np + j], ui = -Ai[i * np + j];
            br[i] -= ur * vr - ui * vi;
            bi[i] -= ur * vi + ui * vr;
        }
    }
    for (int j = n - 1; j > 0; --j) { /* L^H v = w: backward, unit diagonal */
        double vr = br[j], vi = bi[j];
        for (int i = 0; i < j; ++i) {
            double lr = F->lr[i * np + j], li = -F->li[i * np + j];
            br[i] -= lr * vr - li * vi;
            bi[i] -= lr * vi + li * vr;
        }
    }
    for (int k = n - 1; k >= 0; --k) swap_entries(F->piv[k], k, br, bi);
}

static double norm1(int n, const double *xr, const double *xi)
{
    double s = 0.0;
    for (int k = 0; k < n; ++k) s += sqrt(xr[k] * xr[k] + xi[k] * xi[k]);
    return s;
}

/* Hager-Higham estimate of |A^-1|_1 (a lower bound, usually exact) */
static double inv_norm1(int n, const hom_lu *F)
{
    double xr[HOM_MAX_M], xi[HOM_MAX_M];
    for (int k = 0; k < n; ++k) xr[k] = 1.0 / n, xi[k] = 0.0;
    lu_solve(n, F, xr, xi);
    double est = norm1(n, xr, xi);
    for (int it = 0; it < HAGER_ITERS; ++it) {
        for (int k = 0; k < n; ++k) { /* sign(y) */
            double a = sqrt(xr[k] * xr[k] + xi[k] * xi[k]);
            if (a > 0.0) xr[k] /= a, xi[k] /= a;
            else xr[k] = 1.0, xi[k] = 0.0;
        }
        lu_solve_adj(n, F, xr, xi);
        int j = 0;
        double zmax = -1.0;
        for (int k = 0; k < n; ++k) {
            double a = xr[k] * xr[k] + xi[k] * xi[k];
            if (a > zmax) zmax = a, j = k;
        }
        for (int k = 0; k < n; ++k) xr[k] = xi[k] = 0.0;
        xr[j] = 1.0;
        lu_solve(n, F, xr, xi);
        double e = norm1(n, xr, xi);
        if (!(e > est)) break;
        est = e;
    }
    return est;
}

/* ---- the homotopy ---- */

/* out_j = sum_c u_c y[c*sp + j], j < sp (the complex dots of u with Q_j x,
 * from y = Q x in the interleaved rows): eight equations at a time (four
 * for the last group when sp is not a multiple of eight), each summed over c
 * in order; eight independent sums keep the adders busy */
HOM_KERNEL static void dots_raw(int m, int sp, const double *restrict ur, const double *restrict ui,
                                const double *restrict yr, const double *restrict yi, double *restrict outr,
                                double *restrict outi)
{
    int j = 0;
    for (; j + 8 <= sp; j += 8) {
        double p0 = 0.0, p1 = 0.0, p2 = 0.0, p3 = 0.0, p4 = 0.0, p5 = 0.0, p6 = 0.0, p7 = 0.0;
        double q0 = 0.0, q1 = 0.0, q2 = 0.0, q3 = 0.0, q4 = 0.0, q5 = 0.0, q6 = 0.0, q7 = 0.0;
        for (int c = 0; c < m; ++c) {
            const double *ar = yr + c * sp + j, *ai = yi + c * sp + j;
            double a = ur[c], b = ui[c];
            p0 += a * ar[0] - b * ai[0], p1 += a * ar[1] - b * ai[1];
            p2 += a * ar[2] - b * ai[2], p3 += a * ar[3] - b * ai[3];
            p4 += a * ar[4] - b * ai[4], p5 += a * ar[5] - b * ai[5];
            p6 += a * ar[6] - b * ai[6], p7 += a * ar[7] - b * ai[7];
            q0 += a * ai[0] + b * ar[0], q1 += a * ai[1] + b * ar[1];
            q2 += a * ai[2] + b * ar[2], q3 += a * ai[3] + b * ar[3];
            q4 += a * ai[4] + b * ar[4], q5 += a * ai[5] + b * ar[5];
            q6 += a * ai[6] + b * ar[6], q7 += a * ai[7] + b * ar[7];
        }
        outr[j] = p0, outr[j + 1] = p1, outr[j + 2] = p2, outr[j + 3] = p3;
        outr[j + 4] = p4, outr[j + 5] = p5, outr[j + 6] = p6, outr[j + 7] = p7;
        outi[j] = q0, outi[j + 1] = q1, outi[j + 2] = q2, outi[j + 3] = q3;
        outi[j + 4] = q4, outi[j + 5] = q5, outi[j + 6] = q6, outi[j + 7] = q7;
    }
    if (j < sp) {
        double p0 = 0.0, p1 = 0.0, p2 = 0.0, p3 = 0.0, q0 = 0.0, q1 = 0.0, q2 = 0.0, q3 = 0.0;
        for (int c = 0; c < m; ++c) {
            const double *ar = yr + c * sp + j, *ai = yi + c * sp + j;
            double a = ur[c], b = ui[c];
            p0 += a * ar[0] - b * ai[0], p1 += a * ar[1] - b * ai[1];
            p2 += a * ar[2] - b * ai[2], p3 += a * ar[3] - b * ai[3];
            q0 += a * ai[0] + b * ar[0], q1 += a * ai[1] + b * ar[1];
            q2 += a * ai[2] + b * ar[2], q3 += a * ai[3] + b * ar[3];
        }
        outr[j] = p0, outr[j + 1] = p1, outr[j + 2] = p2, outr[j + 3] = p3;
        outi[j] = q0, outi[j + 1] = q1, outi[j + 2] = q2, outi[j + 3] = q3;
    }
}

/* Q x, H and J at p->x, t, in the chart (car, cai); J goes to p->lu
 * (unfactored, column-major) */
static void eval(const hom_problem *P, const double *car, const double *cai, double t, hom_point *p)
{
    int m = P->m, s = P->s, sp = P->sp;
    const double *xr = p->xr, *xi = p->xi;
    qmul(P, xr, xi, p->yr, p->yi);
    double alr = (1.0 - t) * P->gr, ali = (1.0 - t) * P->gi;
    double *Jr = p->lu.r, *Ji = p->lu.i;
    double fr[HOM_MAX_M], fi[HOM_MAX_M]; /* F_j(x) */
    dots_raw(m, sp, xr, xi, p->yr, p->yi, fr, fi);
    int np = lanes_up(m);
    for (int c = 0; c < m; ++c) { /* J(j, c) = 2 t (Q_j x)_c + the G terms below */
        const double *yr = p->yr + c * sp, *yi = p->yi + c * sp;
        double *jr = Jr + c * np, *ji = Ji + c * np;
        for (int j = 0; j < s; ++j) jr[j] = 2.0 * t * yr[j], ji[j] = 2.0 * t * yi[j];
        jr[s] = car[c], ji[s] = cai[c];
        for (int j = m; j < np; ++j) jr[j] = ji[j] = 0.0;
    }
    double g0r = xr[0] * xr[0] - xi[0] * xi[0], g0i = 2.0 * xr[0] * xi[0];
    for (int j = 0; j < s; ++j) {
        int q = j + 1;
        double gr = xr[q] * xr[q] - xi[q] * xi[q] - g0r, gi = 2.0 * xr[q] * xi[q] - g0i;
        p->hr[j] = alr * gr - ali * gi + t * fr[j];
        p->hi[j] = alr * gi + ali * gr + t * fi[j];
        Jr[j] -= 2.0 * (alr * xr[0] - ali * xi[0]);
        Ji[j] -= 2.0 * (alr * xi[0] + ali * xr[0]);
        Jr[q * np + j] += 2.0 * (alr * xr[q] - ali * xi[q]);
        Ji[q * np + j] += 2.0 * (alr * xi[q] + ali * xr[q]);
    }
    double cr = -1.0, ci = 0.0;
    for (int c = 0; c < m; ++c) {
        cr += car[c] * xr[c] - cai[c] * xi[c];
        ci += car[c] * xi[c] + cai[c] * xr[c];
    }
    p->hr[s] = cr;
    p->hi[s] = ci;
}

/* |A(t)[u, v]| <= normA |u||v| for the homotopy's bilinear form */
static double norm_A(const hom_problem *P, double t) { return (1.0 - t) * P->normG + t * P->normF; }

/* out_j += wgt * (u . y_j), j < s: the dot of u with each equation's
 * part of y = Q x */
static void dots(int m, int s, int sp, double wgt, const double *ur, const double *ui, const double *yr,
                 const double *yi, double *outr, double *outi)
{
    double pr[HOM_MAX_M], pi[HOM_MAX_M];
    dots_raw(m, sp, ur, ui, yr, yi, pr, pi);
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
        lu_solve(m, &b->lu, rr, ri);
        if (k < HOM_NY) qmul(P, rr, ri, w->ykr[k], w->yki[k]);
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
    for (int k = 1; k <= HOM_ORDER; ++k) n[k] = vnorm(m, w->cr[k], w->ci[k]);
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

/* H, J at p->x and Newton's correction d = J^-1 H; 0 if J is singular */
static int newton_step(const hom_problem *P, const double *car, const double *cai, double t, hom_point *p,
                       double *dr, double *di)
{
    int m = P->m;
    eval(P, car, cai, t, p);
    if (!lu_factor(m, &p->lu)) return 0;
    memcpy(dr, p->hr, sizeof(double) * (size_t)m);
    memcpy(di, p->hi, sizeof(double) * (size_t)m);
    lu_solve(m, &p->lu, dr, di);
    return isfinite(vnorm(m, dr, di));
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
        if (!newton_step(P, car, cai, 1.0, p, dr, di)) break;
        double nd = vnorm(m, dr, di), nz = vnorm(m, p->xr, p->xi);
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
        eval(P, car, cai, 1.0, p);
        for (int j = 0; j < s; ++j) /* rows j < s of J, row by row (column-major) */
            for (int c = 0; c < m; ++c) {
                double a = p->lu.r[c * lanes_up(m) + j], b = p->lu.i[c * lanes_up(m) + j];
                jf += a * a + b * b;
            }
        if (!lu_factor(m, &p->lu)) return;
        memcpy(dr, p->hr, sizeof(double) * (size_t)m);
        memcpy(di, p->hi, sizeof(double) * (size_t)m);
        lu_solve(m, &p->lu, dr, di);
        double eta = vnorm(m, dr, di), beta2 = 0.0;
        for (int j = 0; j < s; ++j) {
            double vr[HOM_MAX_M] = {0}, vi[HOM_MAX_M] = {0};
            vr[j] = 1.0;
            lu_solve(m, &p->lu, vr, vi);
            for (int c = 0; c < m; ++c) beta2 += vr[c] * vr[c] + vi[c] * vi[c];
        }
        double beta = sqrt(beta2), L = 2.0 * P->normF, nz = vnorm(m, zr, zi);
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
        double im = vnorm(m, zi, zi) / sqrt(2.0); /* |Im z| */
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
    double na = vnorm(m, car, cai);
    for (int c = 0; c < m; ++c) sr += P->ar[c] * base->xr[c], si += P->ai[c] * base->xr[c];
    double d = sr * sr + si * si;
    for (int c = 0; c < m; ++c) {
        double v = base->xr[c];
        base->xr[c] = v * sr / d, base->xi[c] = -v * si / d;
    }
    double t = 0.0, dr[HOM_MAX_M], di[HOM_MAX_M], xr[HOM_MAX_M], xi[HOM_MAX_M];
    if (!newton_step(P, car, cai, t, base, dr, di)) return;
    memcpy(xr, base->xr, sizeof xr);
    memcpy(xi, base->xi, sizeof xi);
    double rsep = 1.0 / (inv_norm1(m, &base->lu) * norm_A(P, t)), hcap = INFINITY, calib = 1.0;
    int lost = 0;
    while (t < 1.0) {
        double sigma = 1.0 - t;
        if (sigma <= S->sigma_end) break;
        if (e->steps + e->rejected >= MAX_STEPS) {
            lost = 1;
            break;
        }
        double nx = vnorm(m, xr, xi);
        if (nx * na > CHART_TILT * sqrt((double)m)) {
            /* the path nears the chart's hyperplane at infinity, where
             * distances in the chart blow up: move to the chart through x
             * orthogonal to it, a = conj(x) / |x|^2 (a.x = 1, x unchanged) */
            for (int c = 0; c < m; ++c) car[c] = xr[c] / (nx * nx), cai[c] = -xi[c] / (nx * nx);
            na = 1.0 / nx;
            memcpy(base->xr, xr, sizeof xr);
            memcpy(base->xi, xi, sizeof xi);
            if (!newton_step(P, car, cai, t, base, dr, di)) {
                lost = 1;
                break;
            }
            rsep = 1.0 / (inv_norm1(m, &base->lu) * norm_A(P, t));
            e->recharts++;
        }
        memcpy(w->cr[0], xr, sizeof(double) * (size_t)m);
        memcpy(w->ci[0], xi, sizeof(double) * (size_t)m);
        taylor(P, w, base, t);
        double target = fmin(S->pred_rel * nx, S->pred_sep * rsep);
        double hser = series_step(w, m, target / calib), h = fmin(hser, hcap);
        int accepted = 0;
        while (!accepted) {
            if (h >= sigma) h = sigma;
            if (h < H_MIN) {
                lost = 1;
                break;
            }
            double t1 = h == sigma ? 1.0 : t + h;
            hom_point *p = tr[0];
            predict(w, m, h, p->xr, p->xi);
            double prevd = INFINITY;
            int ok = 0;
            for (int it = 0; it < NEWTON_MAX; ++it) {
                p = tr[it & 1];
                if (it > 0) {
                    const hom_point *q = tr[(it - 1) & 1];
                    for (int c = 0; c < m; ++c) p->xr[c] = q->xr[c] - dr[c], p->xi[c] = q->xi[c] - di[c];
                }
                if (!newton_step(P, car, cai, t1, p, dr, di)) break;
                double nd = vnorm(m, dr, di), np = vnorm(m, p->xr, p->xi);
                double tol = fmax(NEWTON_TOL, NOISE_FACTOR * DBL_EPSILON * np / rsep) * np;
                if (it == 0) {
                    double est = series_error(w, h);
                    if (est > 0.0 && nd > 0.0) /* calibrate the error model by the actual error */
                        calib = fmin(CALIB_MAX, fmax(CALIB_MIN, sqrt(calib * nd / est)));
                    double rs = 1.0 / (inv_norm1(m, &p->lu) * norm_A(P, t1));
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
