/* The one-path kernels of the complete solver (homotopy_kernels.h): small
 * complex linear algebra on split arrays, Q x, the homotopy's evaluation and
 * Newton's step. They are written so that the compiler vectorises them
 * within one path without reordering any floating-point sum, and the hottest
 * are cloned per instruction set (homotopy_control.h). */
#include <math.h>
#include <string.h>

#include "homotopy/track/homotopy_kernels.h"

double kin__hom_vnorm(int n, const double *xr, const double *xi)
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

void kin__hom_qmul(const hom_problem *P, const double *xr, const double *xi, double *yr, double *yi)
{
#if defined(HOM_MULTIVERSION)
    if (__builtin_cpu_supports("avx2")) {
        qmul_avx2(P, xr, xi, yr, yi);
        return;
    }
#endif
    qmul_blocks(P, 0, xr, xi, yr, yi);
}


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
    int np = kin__hom_lanes_up(n);
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
 * kin__hom_lanes_up(n) entries (the last ones scratch). */
HOM_KERNEL static void lu_solve(int n, const hom_lu *F, double *restrict br, double *restrict bi)
{
    int np = kin__hom_lanes_up(n), j0 = 0;
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
        axpy_sub(0, kin__hom_lanes_up(j), F->r + j * np, F->i + j * np, vr, vi, br, bi);
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
    int np = kin__hom_lanes_up(n);
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
double kin__hom_inv_norm1(int n, const hom_lu *F)
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

/* ---- the homotopy's evaluations ---- */

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
void kin__hom_eval(const hom_problem *P, const double *car, const double *cai, double t, hom_point *p)
{
    int m = P->m, s = P->s, sp = P->sp;
    const double *xr = p->xr, *xi = p->xi;
    kin__hom_qmul(P, xr, xi, p->yr, p->yi);
    double alr = (1.0 - t) * P->gr, ali = (1.0 - t) * P->gi;
    double *Jr = p->lu.r, *Ji = p->lu.i;
    double fr[HOM_MAX_M], fi[HOM_MAX_M]; /* F_j(x) */
    dots_raw(m, sp, xr, xi, p->yr, p->yi, fr, fi);
    int np = kin__hom_lanes_up(m);
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

/* H, J at p->x and Newton's correction d = J^-1 H; 0 if J is singular */
int kin__hom_newton_step(const hom_problem *P, const double *car, const double *cai, double t, hom_point *p,
                       double *dr, double *di)
{
    int m = P->m;
    kin__hom_eval(P, car, cai, t, p);
    if (!lu_factor(m, &p->lu)) return 0;
    memcpy(dr, p->hr, sizeof(double) * (size_t)m);
    memcpy(di, p->hi, sizeof(double) * (size_t)m);
    lu_solve(m, &p->lu, dr, di);
    return isfinite(kin__hom_vnorm(m, dr, di));
}

/* The entry points the other files call: plain functions that call the
 * cloned kernels of this file (homotopy_control.h: a cloned function is
 * called only from the file that defines it). */
int kin__hom_lu_factor(int n, hom_lu *F)
{
    return lu_factor(n, F);
}

void kin__hom_lu_solve(int n, const hom_lu *F, double *restrict br, double *restrict bi)
{
    lu_solve(n, F, br, bi);
}

void kin__hom_dots_raw(int m, int sp, const double *restrict ur, const double *restrict ui,
                       const double *restrict yr, const double *restrict yi, double *restrict outr,
                       double *restrict outi)
{
    dots_raw(m, sp, ur, ui, yr, yi, outr, outi);
}
