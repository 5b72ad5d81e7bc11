/* The kernels of the lockstep tracker (homotopy_lanes.h), HOM_BATCH paths
 * at once. */
#include <math.h>
#include <string.h>

#include "homotopy/track/homotopy_lanes.h"

#if defined(HOM_LANES_VECTOR)

/* cloned as the one-path kernels are (homotopy_control.h), with an AVX-512
 * clone as well */
#if defined(HOM_MULTIVERSION)
#define HOMB_KERNEL HOM_KERNEL_WIDE
#else
#define HOMB_KERNEL
#endif


/* y = Q x from the lockstep copy of Q (row r*s + j: row r of Q_j), each row
 * summed over c in order, as qmul in homotopy_kernels.c */
HOM_INLINE void bqmul_rows(const hom_problem *P, const lanes *restrict xr, const lanes *restrict xi,
                           lanes *restrict yr, lanes *restrict yi)
{
    int n = kin__hom_srows(P->m, P->s), m = P->m;
    const double *qb = P->Qs;
    for (int i = 0; i < n; i += HOM_SBLOCK, qb += HOM_SBLOCK * m) {
        lanes a0 = ALL(0.0), a1 = a0, a2 = a0, a3 = a0, b0 = a0, b1 = a0, b2 = a0, b3 = a0;
        for (int c = 0; c < m; ++c) {
            const double *q = qb + HOM_SBLOCK * c;
            lanes u = xr[c], v = xi[c];
            a0 += q[0] * u, b0 += q[0] * v;
            a1 += q[1] * u, b1 += q[1] * v;
            a2 += q[2] * u, b2 += q[2] * v;
            a3 += q[3] * u, b3 += q[3] * v;
        }
        lanes *ur = yr + i, *ui = yi + i;
        ur[0] = a0, ur[1] = a1, ur[2] = a2, ur[3] = a3;
        ui[0] = b0, ui[1] = b1, ui[2] = b2, ui[3] = b3;
    }
}
HOMB_KERNEL static void bqmul(const hom_problem *P, const lanes *xr, const lanes *xi, lanes *yr, lanes *yi)
{
    bqmul_rows(P, xr, xi, yr, yi);
}

/* out_j = sum_c u_c y[c*s + j], j < s, summed over c in order */
HOMB_KERNEL static void bdots(int m, int s, const lanes *restrict ur, const lanes *restrict ui,
                              const lanes *restrict yr, const lanes *restrict yi, lanes *restrict outr,
                              lanes *restrict outi)
{
    int j = 0;
    for (; j + 4 <= s; j += 4) { /* 8 independent sums keep the adders busy */
        lanes p0 = ALL(0.0), q0 = p0, p1 = p0, q1 = p0, p2 = p0, q2 = p0, p3 = p0, q3 = p0;
        for (int c = 0; c < m; ++c) {
            const lanes *ar = yr + c * s + j, *ai = yi + c * s + j;
            lanes a = ur[c], b = ui[c];
            p0 += a * ar[0] - b * ai[0], q0 += a * ai[0] + b * ar[0];
            p1 += a * ar[1] - b * ai[1], q1 += a * ai[1] + b * ar[1];
            p2 += a * ar[2] - b * ai[2], q2 += a * ai[2] + b * ar[2];
            p3 += a * ar[3] - b * ai[3], q3 += a * ai[3] + b * ar[3];
        }
        outr[j] = p0, outi[j] = q0, outr[j + 1] = p1, outi[j + 1] = q1;
        outr[j + 2] = p2, outi[j + 2] = q2, outr[j + 3] = p3, outi[j + 3] = q3;
    }
    for (; j < s; ++j) {
        lanes p0 = ALL(0.0), q0 = p0;
        for (int c = 0; c < m; ++c) {
            lanes a = ur[c], b = ui[c], ar = yr[c * s + j], ai = yi[c * s + j];
            p0 += a * ar - b * ai, q0 += a * ai + b * ar;
        }
        outr[j] = p0, outi[j] = q0;
    }
}

/* The lockstep twin of the one complex LU (homotopy_lu.h, in
 * homotopy_kernels.c), kept separate: bench_hom_kernel onepath shows 1.63x
 * (hexflat paths 0..2047 on one thread: the one-path tracker 2.39-2.56 s,
 * the lockstep tracker 1.51-1.52 s; the lanes' vector layout is what makes
 * the difference). It serves both lockstep trackers (homotopy_batch.c and,
 * through homotopy_param_lanes.c, homotopy_param_batch.c).
 * LU with partial pivoting (largest |re| + |im|, the first of equals), each
 * lane its own pivots; F->ok[l] = 0 where a pivot is zero or not finite
 * (that lane's factors are then meaningless) */
HOMB_KERNEL static void blu_factor(int n, hom_llu *F)
{
    for (int l = 0; l < BL; ++l) F->ok[l] = 1;
    for (int k = 0; k < n; ++k) {
        lanes *ar = F->r + k * n, *ai = F->i + k * n; /* column k */
        /* the pivots: the first largest |re| + |im| in rows k.. of each lane */
        const lmask nosign = (lmask){0} + 0x7fffffffffffffffLL;
        lanes best = (lanes)((lmask)ar[k] & nosign) + (lanes)((lmask)ai[k] & nosign);
        lmask piv = (lmask){0} + k;
        for (int i = k + 1; i < n; ++i) {
            lanes v = (lanes)((lmask)ar[i] & nosign) + (lanes)((lmask)ai[i] & nosign);
            lmask gt = v > best;
            best = select_lanes(gt, v, best);
            piv = (gt & ((lmask){0} + i)) | (~gt & piv);
        }
        for (int l = 0; l < BL; ++l) {
            int p = (int)piv[l];
            F->piv[k][l] = p;
            if (!(best[l] > 0.0) || !isfinite(best[l])) F->ok[l] = 0;
            if (p != k) /* rows k and p: of L in columns j < k, of the rest in the others */
                for (int j = 0; j < n; ++j) {
                    lanes *cr = j < k ? F->lr : F->r, *ci = j < k ? F->li : F->i;
                    double t = cr[j * n + k][l];
                    cr[j * n + k][l] = cr[j * n + p][l], cr[j * n + p][l] = t;
                    t = ci[j * n + k][l];
                    ci[j * n + k][l] = ci[j * n + p][l], ci[j * n + p][l] = t;
                }
        }
        lanes pr = ar[k], pi = ai[k], d = pr * pr + pi * pi;
        lanes ir = pr / d, ii = -pi / d; /* 1 / pivot */
        F->dr[k] = ir, F->di[k] = ii;
        lanes *mr = F->lr + k * n, *mi = F->li + k * n; /* column k of L */
        for (int i = k + 1; i < n; ++i) {
            lanes a = ar[i], b = ai[i];
            mr[i] = a * ir - b * ii, mi[i] = a * ii + b * ir;
        }
        int j = k + 1;
        for (; j + 1 < n; j += 2) { /* columns j, j + 1 -= L(:, k) U(k, j..j+1): L loaded once */
            lanes *br = F->r + j * n, *bi = F->i + j * n, *cr = br + n, *ci = bi + n;
            lanes vr = br[k], vi = bi[k], ur = cr[k], ui = ci[k];
            for (int i = k + 1; i < n; ++i) {
                lanes a = mr[i], b = mi[i];
                br[i] -= a * vr - b * vi, bi[i] -= a * vi + b * vr;
                cr[i] -= a * ur - b * ui, ci[i] -= a * ui + b * ur;
            }
        }
        for (; j < n; ++j) { /* column j -= L(:, k) U(k, j) */
            lanes *br = F->r + j * n, *bi = F->i + j * n;
            lanes vr = br[k], vi = bi[k];
            for (int i = k + 1; i < n; ++i) {
                br[i] -= mr[i] * vr - mi[i] * vi;
                bi[i] -= mr[i] * vi + mi[i] * vr;
            }
        }
    }
}

/* exchange entries k and piv[k] of every lane of b (forward: k ascending;
 * back: descending) */
HOMB_KERNEL static void bpermute(int n, const hom_llu *F, lanes *br, lanes *bi, int back)
{
    for (int kk = 0; kk < n; ++kk) {
        int k = back ? n - 1 - kk : kk;
        for (int l = 0; l < BL; ++l) {
            int p = F->piv[k][l];
            double t = br[k][l];
            br[k][l] = br[p][l], br[p][l] = t;
            t = bi[k][l];
            bi[k][l] = bi[p][l], bi[p][l] = t;
        }
    }
}

/* b <- A^-1 b, every lane: the updates of each entry in the order of the
 * one-path lu_solve (forward by increasing column, backward by decreasing) */
HOMB_KERNEL static void blu_solve(int n, const hom_llu *F, lanes *restrict br, lanes *restrict bi)
{
    bpermute(n, F, br, bi, 0);
    /* L y = b (unit diagonal), two columns at a time: each entry below them
     * loaded and stored once for both updates, in column order */
    int j = 0;
    for (; j + 2 < n; j += 2) {
        const lanes *cr = F->lr + j * n, *ci = F->li + j * n, *dr = cr + n, *di = ci + n;
        lanes vr = br[j], vi = bi[j];
        br[j + 1] -= cr[j + 1] * vr - ci[j + 1] * vi, bi[j + 1] -= cr[j + 1] * vi + ci[j + 1] * vr;
        lanes ur = br[j + 1], ui = bi[j + 1];
        for (int i = j + 2; i < n; ++i) {
            lanes xr = br[i], xi = bi[i];
            xr -= cr[i] * vr - ci[i] * vi, xi -= cr[i] * vi + ci[i] * vr;
            xr -= dr[i] * ur - di[i] * ui, xi -= dr[i] * ui + di[i] * ur;
            br[i] = xr, bi[i] = xi;
        }
    }
    for (; j < n - 1; ++j) {
        const lanes *cr = F->lr + j * n, *ci = F->li + j * n;
        lanes vr = br[j], vi = bi[j];
        for (int i = j + 1; i < n; ++i) {
            br[i] -= cr[i] * vr - ci[i] * vi;
            bi[i] -= cr[i] * vi + ci[i] * vr;
        }
    }
    /* U x = y, two columns at a time (the last first) */
    j = n - 1;
    for (; j >= 1; j -= 2) {
        const lanes *cr = F->r + j * n, *ci = F->i + j * n, *dr = cr - n, *di = ci - n;
        lanes vr = br[j] * F->dr[j] - bi[j] * F->di[j], vi = br[j] * F->di[j] + bi[j] * F->dr[j];
        br[j] = vr, bi[j] = vi;
        lanes xr = br[j - 1], xi = bi[j - 1];
        xr -= cr[j - 1] * vr - ci[j - 1] * vi, xi -= cr[j - 1] * vi + ci[j - 1] * vr;
        lanes ur = xr * F->dr[j - 1] - xi * F->di[j - 1], ui = xr * F->di[j - 1] + xi * F->dr[j - 1];
        br[j - 1] = ur, bi[j - 1] = ui;
        for (int i = 0; i < j - 1; ++i) {
            lanes yr = br[i], yi = bi[i];
            yr -= cr[i] * vr - ci[i] * vi, yi -= cr[i] * vi + ci[i] * vr;
            yr -= dr[i] * ur - di[i] * ui, yi -= dr[i] * ui + di[i] * ur;
            br[i] = yr, bi[i] = yi;
        }
    }
    if (j == 0) {
        lanes vr = br[0] * F->dr[0] - bi[0] * F->di[0], vi = br[0] * F->di[0] + bi[0] * F->dr[0];
        br[0] = vr, bi[0] = vi;
    }
}

/* b <- A^-H b (A = P^T L U), as lu_solve_adj */
HOMB_KERNEL static void blu_solve_adj(int n, const hom_llu *F, lanes *restrict br, lanes *restrict bi)
{
    for (int j = 0; j < n; ++j) { /* U^H w = b */
        lanes vr = br[j] * F->dr[j] + bi[j] * F->di[j], vi = bi[j] * F->dr[j] - br[j] * F->di[j];
        br[j] = vr, bi[j] = vi;
        for (int i = j + 1; i < n; ++i) {
            lanes ur = F->r[i * n + j], ui = -F->i[i * n + j];
            br[i] -= ur * vr - ui * vi;
            bi[i] -= ur * vi + ui * vr;
        }
    }
    for (int j = n - 1; j > 0; --j) { /* L^H v = w */
        lanes vr = br[j], vi = bi[j];
        for (int i = 0; i < j; ++i) {
            lanes lr = F->lr[i * n + j], li = -F->li[i * n + j];
            br[i] -= lr * vr - li * vi;
            bi[i] -= lr * vi + li * vr;
        }
    }
    bpermute(n, F, br, bi, 1);
}

/* |v| per lane (2-norm, summed in order) */
HOMB_KERNEL static void bnorm2(int n, const lanes *xr, const lanes *xi, double *out)
{
    lanes s = ALL(0.0);
    for (int k = 0; k < n; ++k) s += xr[k] * xr[k] + xi[k] * xi[k];
    for (int l = 0; l < BL; ++l) out[l] = sqrt(s[l]);
}

HOMB_KERNEL static void bnorm1(int n, const lanes *xr, const lanes *xi, double *out)
{
    for (int l = 0; l < BL; ++l) out[l] = 0.0;
    for (int k = 0; k < n; ++k)
        for (int l = 0; l < BL; ++l) out[l] += sqrt(xr[k][l] * xr[k][l] + xi[k][l] * xi[k][l]);
}

/* the Hager-Higham estimate of |A^-1|_1 per lane, as inv_norm1 */
HOMB_KERNEL static void binv_norm1(int n, const hom_llu *F, double *est)
{
    lanes xr[HOM_MAX_M], xi[HOM_MAX_M];
    for (int k = 0; k < n; ++k)
        for (int l = 0; l < BL; ++l) xr[k][l] = 1.0 / n, xi[k][l] = 0.0;
    blu_solve(n, F, xr, xi);
    bnorm1(n, xr, xi, est);
    int go[BL];
    for (int l = 0; l < BL; ++l) go[l] = 1;
    for (int it = 0; it < HAGER_ITERS; ++it) {
        for (int k = 0; k < n; ++k)
            for (int l = 0; l < BL; ++l) { /* sign(y) */
                double a = sqrt(xr[k][l] * xr[k][l] + xi[k][l] * xi[k][l]);
                if (a > 0.0) xr[k][l] /= a, xi[k][l] /= a;
                else xr[k][l] = 1.0, xi[k][l] = 0.0;
            }
        blu_solve_adj(n, F, xr, xi);
        for (int l = 0; l < BL; ++l) {
            int j = 0;
            double zmax = -1.0;
            for (int k = 0; k < n; ++k) {
                double a = xr[k][l] * xr[k][l] + xi[k][l] * xi[k][l];
                if (a > zmax) zmax = a, j = k;
            }
            for (int k = 0; k < n; ++k) xr[k][l] = xi[k][l] = 0.0;
            xr[j][l] = 1.0;
        }
        blu_solve(n, F, xr, xi);
        double e[BL];
        bnorm1(n, xr, xi, e);
        int any = 0;
        for (int l = 0; l < BL; ++l) {
            if (go[l] && e[l] > est[l]) est[l] = e[l];
            else go[l] = 0;
            any |= go[l];
        }
        if (!any) break;
    }
}

/* Q x, H and J at p->x, each lane at its t in its chart, as eval */
HOM_INLINE void beval(const hom_problem *P, const lanes *tp, const lanes *car, const lanes *cai, hom_lpoint *p)
{
    int m = P->m, s = P->s;
    const lanes *xr = p->xr, *xi = p->xi;
    lanes t = *tp, two_t = 2.0 * t;
    bqmul(P, xr, xi, p->yr, p->yi);
    lanes alr = (1.0 - t) * P->gr, ali = (1.0 - t) * P->gi;
    lanes *Jr = p->lu.r, *Ji = p->lu.i;
    lanes fr[HOM_MAX_M], fi[HOM_MAX_M]; /* F_j(x) */
    bdots(m, s, xr, xi, p->yr, p->yi, fr, fi);
    for (int c = 0; c < m; ++c) { /* J(j, c) = 2 t (Q_j x)_c + the G terms below */
        const lanes *yr = p->yr + c * s, *yi = p->yi + c * s;
        lanes *jr = Jr + c * m, *ji = Ji + c * m;
        for (int j = 0; j < s; ++j) jr[j] = two_t * yr[j], ji[j] = two_t * yi[j];
        jr[s] = car[c], ji[s] = cai[c];
    }
    lanes g0r = xr[0] * xr[0] - xi[0] * xi[0], g0i = 2.0 * xr[0] * xi[0];
    for (int j = 0; j < s; ++j) {
        int q = j + 1;
        lanes gr = xr[q] * xr[q] - xi[q] * xi[q] - g0r, gi = 2.0 * xr[q] * xi[q] - g0i;
        p->hr[j] = alr * gr - ali * gi + t * fr[j];
        p->hi[j] = alr * gi + ali * gr + t * fi[j];
        Jr[j] -= 2.0 * (alr * xr[0] - ali * xi[0]);
        Ji[j] -= 2.0 * (alr * xi[0] + ali * xr[0]);
        Jr[q * m + j] += 2.0 * (alr * xr[q] - ali * xi[q]);
        Ji[q * m + j] += 2.0 * (alr * xi[q] + ali * xr[q]);
    }
    lanes cr = ALL(-1.0), ci = ALL(0.0);
    for (int c = 0; c < m; ++c) {
        cr += car[c] * xr[c] - cai[c] * xi[c];
        ci += car[c] * xi[c] + cai[c] * xr[c];
    }
    p->hr[s] = cr, p->hi[s] = ci;
}

HOMB_KERNEL static void bnewton(const hom_problem *P, const lanes *t, const lanes *car, const lanes *cai,
                                hom_lpoint *p, lanes *dr, lanes *di, int *ok)
{
    int m = P->m;
    beval(P, t, car, cai, p);
    blu_factor(m, &p->lu);
    memcpy(dr, p->hr, sizeof(lanes) * (size_t)m);
    memcpy(di, p->hi, sizeof(lanes) * (size_t)m);
    blu_solve(m, &p->lu, dr, di);
    double nd[BL];
    bnorm2(m, dr, di, nd);
    for (int l = 0; l < BL; ++l) ok[l] = p->lu.ok[l] && isfinite(nd[l]);
}

/* out_j += wgt * (u . y_j), j < s, every lane (as dots) */
HOMB_KERNEL static void bdots_add(int m, int s, double wgt, const lanes *ur, const lanes *ui, const lanes *yr,
                      const lanes *yi, lanes *outr, lanes *outi)
{
    lanes pr[HOM_MAX_M], pi[HOM_MAX_M];
    bdots(m, s, ur, ui, yr, yi, pr, pi);
    for (int j = 0; j < s; ++j) outr[j] += wgt * pr[j], outi[j] += wgt * pi[j];
}

/* pair_sums of homotopy_track.c, every lane */
HOMB_KERNEL static void bpair_sums(const hom_problem *P, const hom_lseries *B, const lanes *const *yr, const lanes *const *yi, int k,
                       lanes *fr, lanes *fi, lanes *gr, lanes *gi)
{
    int m = P->m, s = P->s;
    for (int j = 0; j < s; ++j) fr[j] = fi[j] = gr[j] = gi[j] = ALL(0.0);
    for (int i = 1; 2 * i <= k; ++i) {
        int li = k - i;
        double wgt = i < li ? 2.0 : 1.0;
        const lanes *ar = B->cr[li], *ai = B->ci[li], *ur = B->cr[i], *ui = B->ci[i];
        bdots_add(m, s, wgt, ar, ai, yr[i], yi[i], fr, fi);
        lanes e0r = ur[0] * ar[0] - ui[0] * ai[0], e0i = ur[0] * ai[0] + ui[0] * ar[0];
        for (int j = 0; j < s; ++j) {
            int q = j + 1;
            gr[j] += wgt * (ur[q] * ar[q] - ui[q] * ai[q] - e0r);
            gi[j] += wgt * (ur[q] * ai[q] + ui[q] * ar[q] - e0i);
        }
    }
}

/* (the F[x_0, x_{k-1}] terms are recovered from J x_k in the lanes where
 * t >= T_RECOVER, computed directly in the others) */
HOMB_KERNEL static void btaylor(const hom_problem *P, const lanes *t0p, const hom_lpoint *b, hom_lseries *B)
{
    int m = P->m, s = P->s;
    lanes t0 = *t0p;
    const lanes *yr[HOM_NY], *yi[HOM_NY];
    yr[0] = b->yr, yi[0] = b->yi;
    for (int i = 1; i < HOM_NY; ++i) yr[i] = B->ykr[i], yi[i] = B->yki[i];
    lanes alr = (1.0 - t0) * P->gr, ali = (1.0 - t0) * P->gi;
    lmask recover = t0 >= T_RECOVER;
    int anydirect = 0;
    for (int l = 0; l < BL; ++l) anydirect |= !recover[l];
    lanes ftr[HOM_MAX_M], fti[HOM_MAX_M], gtr[HOM_MAX_M], gti[HOM_MAX_M];
    lanes fr[HOM_MAX_M], fi[HOM_MAX_M], gr[HOM_MAX_M], gi[HOM_MAX_M];
    lanes rhr[HOM_MAX_M], rhi[HOM_MAX_M], dtr[HOM_MAX_M], dti[HOM_MAX_M];
    const lanes *vr = b->xr, *vi = b->xi;
    memcpy(rhr, b->hr, sizeof(lanes) * (size_t)s);
    memcpy(rhi, b->hi, sizeof(lanes) * (size_t)s);
    for (int j = 0; j < s; ++j) ftr[j] = fti[j] = gtr[j] = gti[j] = ALL(0.0);
    for (int k = 1; k <= HOM_ORDER; ++k) {
        lanes *rr = B->cr[k], *ri = B->ci[k];
        const lanes *ur = k > 1 ? B->cr[k - 1] : vr, *ui = k > 1 ? B->ci[k - 1] : vi;
        double wgt = k > 1 ? 2.0 : 1.0;
        if (anydirect) { /* wgt F[x_0, x_{k-1}] directly, for the lanes that need it */
            bdots(m, s, ur, ui, yr[0], yi[0], dtr, dti);
            for (int j = 0; j < s; ++j) dtr[j] = wgt * dtr[j], dti[j] = wgt * dti[j];
        }
        lanes u0r = ur[0] * vr[0] - ui[0] * vi[0], u0i = ur[0] * vi[0] + ui[0] * vr[0];
        for (int j = 0; j < s; ++j) {
            int q = j + 1;
            lanes er = ur[q] * vr[q] - ui[q] * vi[q] - u0r; /* G_j[x_0, x_{k-1}] */
            lanes ei = ur[q] * vi[q] + ui[q] * vr[q] - u0i;
            gr[j] = gtr[j] + wgt * er, gi[j] = gti[j] + wgt * ei;
            lanes rcr = (rhr[j] - wgt * (alr * er - ali * ei)) / t0;
            lanes rci = (rhi[j] - wgt * (alr * ei + ali * er)) / t0;
            if (anydirect) rcr = select_lanes(recover, rcr, dtr[j]), rci = select_lanes(recover, rci, dti[j]);
            fr[j] = ftr[j] + rcr, fi[j] = fti[j] + rci;
        }
        if (k >= 2) bpair_sums(P, B, yr, yi, k, ftr, fti, gtr, gti);
        for (int j = 0; j < s; ++j) {
            rr[j] = -(alr * gtr[j] - ali * gti[j] + t0 * ftr[j] - (P->gr * gr[j] - P->gi * gi[j]) + fr[j]);
            ri[j] = -(alr * gti[j] + ali * gtr[j] + t0 * fti[j] - (P->gr * gi[j] + P->gi * gr[j]) + fi[j]);
        }
        rr[s] = ri[s] = ALL(0.0);
        memcpy(rhr, rr, sizeof(lanes) * (size_t)s);
        memcpy(rhi, ri, sizeof(lanes) * (size_t)s);
        blu_solve(m, &b->lu, rr, ri);
        if (k < HOM_NY) bqmul(P, rr, ri, B->ykr[k], B->yki[k]);
    }
}

/* The entry points the other files call: plain functions that call the
 * cloned kernels of this file (homotopy_control.h: a cloned function is
 * called only from the file that defines it). */
void kin__lanes_lu_factor(int n, hom_llu *F)
{
    blu_factor(n, F);
}

void kin__lanes_lu_solve(int n, const hom_llu *F, lanes *restrict br, lanes *restrict bi)
{
    blu_solve(n, F, br, bi);
}

void kin__lanes_norm2(int n, const lanes *xr, const lanes *xi, double *out)
{
    bnorm2(n, xr, xi, out);
}

void kin__lanes_inv_norm1(int n, const hom_llu *F, double *est)
{
    binv_norm1(n, F, est);
}

void kin__lanes_newton(const hom_problem *P, const lanes *t, const lanes *car, const lanes *cai,
                       hom_lpoint *p, lanes *dr, lanes *di, int *ok)
{
    bnewton(P, t, car, cai, p, dr, di, ok);
}

void kin__lanes_taylor(const hom_problem *P, const lanes *t0p, const hom_lpoint *b, hom_lseries *B)
{
    btaylor(P, t0p, b, B);
}

#endif /* HOM_LANES_VECTOR */
