/* The kernels of the lockstep parameter tracker (homotopy_param_lanes.h),
 * HOM_BATCH paths at once; each mirrors its one-path twin in
 * homotopy_param.c operation for operation. */
#include <math.h>
#include <string.h>

#include "homotopy_param_lanes.h"

#if defined(HOM_LANES_VECTOR)

/* cloned as the one-path kernels are (homotopy_control.h) */
#if defined(HOM_MULTIVERSION)
#define PLAN_KERNEL __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define PLAN_KERNEL
#endif

enum { RB = 4 }; /* rows of y kept in registers by the products */

/* y = M x, M = A + t D formed entry by entry (formed) or M = D, each row
 * summed over the columns c in order from 0, as kin__hpar_matvec */
HOM_INLINE void pmatvec(const hpar_problem *P, int formed, const lanes *tp, const lanes *restrict xr,
                        const lanes *restrict xi, lanes *restrict yr, lanes *restrict yi)
{
    int m = P->m, sm = P->s * P->m, i = 0;
    const double *Ar = P->Ar, *Ai = P->Ai, *Dr = P->Dr, *Di = P->Di;
    lanes t = *tp;
    for (; i + RB <= sm; i += RB) {
        lanes ur[RB], ui[RB];
        for (int q = 0; q < RB; ++q) ur[q] = ui[q] = ALL(0.0);
        for (int c = 0; c < m; ++c) {
            size_t o = (size_t)c * sm + i;
            lanes a = xr[c], b = xi[c];
            for (int q = 0; q < RB; ++q) {
                lanes mr, mi;
                if (formed) mr = Ar[o + q] + t * Dr[o + q], mi = Ai[o + q] + t * Di[o + q];
                else mr = ALL(Dr[o + q]), mi = ALL(Di[o + q]);
                ur[q] += mr * a - mi * b;
                ui[q] += mr * b + mi * a;
            }
        }
        for (int q = 0; q < RB; ++q) yr[i + q] = ur[q], yi[i + q] = ui[q];
    }
    for (; i < sm; ++i) {
        lanes ur = ALL(0.0), ui = ALL(0.0);
        for (int c = 0; c < m; ++c) {
            size_t o = (size_t)c * sm + i;
            lanes mr, mi;
            if (formed) mr = Ar[o] + t * Dr[o], mi = Ai[o] + t * Di[o];
            else mr = ALL(Dr[o]), mi = ALL(Di[o]);
            ur += mr * xr[c] - mi * xi[c];
            ui += mr * xi[c] + mi * xr[c];
        }
        yr[i] = ur, yi[i] = ui;
    }
}

/* out_j += wgt * (u . y_j), j < s (y_j: entries r*s + j of y), as dots */
HOM_INLINE void pdots(int m, int s, double wgt, const lanes *restrict ur, const lanes *restrict ui,
                      const lanes *restrict yr, const lanes *restrict yi, lanes *restrict outr,
                      lanes *restrict outi)
{
    lanes pr[HOM_MAX_M], pi[HOM_MAX_M];
    for (int j = 0; j < s; ++j) pr[j] = pi[j] = ALL(0.0);
    for (int r = 0; r < m; ++r) {
        const lanes *ar = yr + r * s, *ai = yi + r * s;
        lanes a = ur[r], b = ui[r];
        for (int j = 0; j < s; ++j) pr[j] += a * ar[j] - b * ai[j], pi[j] += a * ai[j] + b * ar[j];
    }
    for (int j = 0; j < s; ++j) outr[j] += wgt * pr[j], outi[j] += wgt * pi[j];
}

/* LU with partial pivoting (the first largest |re| + |im|), each lane its
 * own pivots, as lu_factor; a lane whose U(k, j) is exactly zero keeps
 * column j as it is (lu_factor skips that update) */
HOM_INLINE void plu_factor(int n, hpar_llu *F)
{
    const lmask nosign = (lmask){0} + 0x7fffffffffffffffLL;
    for (int l = 0; l < BL; ++l) F->ok[l] = 1;
    for (int k = 0; k < n; ++k) {
        lanes *Ar = F->r, *Ai = F->i;
        lanes best = (lanes)((lmask)Ar[k * n + k] & nosign) + (lanes)((lmask)Ai[k * n + k] & nosign);
        lmask piv = (lmask){0} + k;
        for (int i = k + 1; i < n; ++i) {
            lanes v = (lanes)((lmask)Ar[k * n + i] & nosign) + (lanes)((lmask)Ai[k * n + i] & nosign);
            lmask gt = v > best;
            best = select_lanes(gt, v, best);
            piv = (gt & ((lmask){0} + i)) | (~gt & piv);
        }
        for (int l = 0; l < BL; ++l) {
            int p = (int)piv[l];
            F->piv[k][l] = p;
            if (!(best[l] > 0.0) || !isfinite(best[l])) F->ok[l] = 0;
            if (p != k)
                for (int j = 0; j < n; ++j) {
                    double t = Ar[j * n + k][l];
                    Ar[j * n + k][l] = Ar[j * n + p][l], Ar[j * n + p][l] = t;
                    t = Ai[j * n + k][l];
                    Ai[j * n + k][l] = Ai[j * n + p][l], Ai[j * n + p][l] = t;
                }
        }
        lanes pr = Ar[k * n + k], pi = Ai[k * n + k], d = pr * pr + pi * pi;
        lanes ir = pr / d, ii = -pi / d;
        for (int i = k + 1; i < n; ++i) {
            lanes a = Ar[k * n + i], b = Ai[k * n + i];
            Ar[k * n + i] = a * ir - b * ii, Ai[k * n + i] = a * ii + b * ir;
        }
        const lanes *lr = Ar + k * n, *li = Ai + k * n;
        for (int j = k + 1; j < n; ++j) {
            lanes ur = Ar[j * n + k], ui = Ai[j * n + k];
            lmask skip = (ur == 0.0) & (ui == 0.0);
            int all = 1, any = 0;
            for (int l = 0; l < BL; ++l) all &= skip[l] != 0, any |= skip[l] != 0;
            if (all) continue;
            lanes *cr = Ar + j * n, *ci = Ai + j * n;
            if (!any) {
                for (int i = k + 1; i < n; ++i) {
                    cr[i] -= lr[i] * ur - li[i] * ui;
                    ci[i] -= lr[i] * ui + li[i] * ur;
                }
            } else {
                for (int i = k + 1; i < n; ++i) {
                    lanes nr = cr[i] - (lr[i] * ur - li[i] * ui), ni = ci[i] - (lr[i] * ui + li[i] * ur);
                    cr[i] = select_lanes(skip, cr[i], nr), ci[i] = select_lanes(skip, ci[i], ni);
                }
            }
        }
    }
}

/* b <- J^-1 b, every lane, as lu_solve */
HOM_INLINE void plu_solve(int n, const hpar_llu *F, lanes *restrict br, lanes *restrict bi)
{
    const lanes *Ar = F->r, *Ai = F->i;
    for (int k = 0; k < n; ++k)
        for (int l = 0; l < BL; ++l) {
            int p = F->piv[k][l];
            if (p != k) {
                double t = br[k][l];
                br[k][l] = br[p][l], br[p][l] = t;
                t = bi[k][l];
                bi[k][l] = bi[p][l], bi[p][l] = t;
            }
        }
    for (int j = 0; j < n; ++j) {
        lanes vr = br[j], vi = bi[j];
        for (int i = j + 1; i < n; ++i) {
            br[i] -= Ar[j * n + i] * vr - Ai[j * n + i] * vi;
            bi[i] -= Ar[j * n + i] * vi + Ai[j * n + i] * vr;
        }
    }
    for (int j = n - 1; j >= 0; --j) {
        lanes pr = Ar[j * n + j], pi = Ai[j * n + j], d = pr * pr + pi * pi;
        lanes vr = (br[j] * pr + bi[j] * pi) / d, vi = (bi[j] * pr - br[j] * pi) / d;
        br[j] = vr, bi[j] = vi;
        for (int i = 0; i < j; ++i) {
            br[i] -= Ar[j * n + i] * vr - Ai[j * n + i] * vi;
            bi[i] -= Ar[j * n + i] * vi + Ai[j * n + i] * vr;
        }
    }
}

PLAN_KERNEL void kin__plan_newton(const hpar_problem *P, const lanes *t, const lanes *car, const lanes *cai,
                                  const lanes *xr, const lanes *xi, const hpar_lscratch *W, hpar_llu *F,
                                  lanes *dr, lanes *di, int *ok)
{
    int m = P->m, s = P->s;
    lanes *yr = W->pyr, *yi = W->pyi;
    pmatvec(P, 1, t, xr, xi, yr, yi);
    for (int j = 0; j < s; ++j) dr[j] = di[j] = ALL(0.0);
    pdots(m, s, 1.0, xr, xi, yr, yi, dr, di);
    lanes cr = ALL(-1.0), ci = ALL(0.0);
    for (int c = 0; c < m; ++c) {
        cr += car[c] * xr[c] - cai[c] * xi[c];
        ci += car[c] * xi[c] + cai[c] * xr[c];
    }
    dr[s] = cr, di[s] = ci;
    for (int c = 0; c < m; ++c) { /* J(j, c) = 2 (M_j x)_c; the chart row */
        for (int j = 0; j < s; ++j) F->r[c * m + j] = 2.0 * yr[c * s + j], F->i[c * m + j] = 2.0 * yi[c * s + j];
        F->r[c * m + s] = car[c], F->i[c * m + s] = cai[c];
    }
    plu_factor(m, F);
    plu_solve(m, F, dr, di);
    lanes n2 = ALL(0.0);
    for (int k = 0; k < m; ++k) n2 += dr[k] * dr[k] + di[k] * di[k];
    for (int l = 0; l < BL; ++l) ok[l] = F->ok[l] && isfinite(sqrt(n2[l]));
}

PLAN_KERNEL void kin__plan_taylor(const hpar_problem *P, const lanes *t0, const hpar_llu *F, const hpar_lscratch *W,
                                  lanes (*cr)[HOM_MAX_M], lanes (*ci)[HOM_MAX_M])
{
    int m = P->m, s = P->s;
    pmatvec(P, 1, t0, cr[0], ci[0], W->yr[0], W->yi[0]);
    pmatvec(P, 0, t0, cr[0], ci[0], W->zr[0], W->zi[0]);
    for (int k = 1; k <= HPAR_ORDER; ++k) {
        lanes *rr = cr[k], *ri = ci[k];
        for (int j = 0; j <= s; ++j) rr[j] = ri[j] = ALL(0.0);
        for (int i = 1; 2 * i <= k; ++i) /* sum_{0<i,l<k, i+l=k} M0[x_i, x_l] */
            pdots(m, s, 2 * i < k ? 2.0 : 1.0, cr[k - i], ci[k - i], W->yr[i], W->yi[i], rr, ri);
        for (int i = 0; 2 * i <= k - 1; ++i) /* sum_{i+l=k-1} D[x_i, x_l] */
            pdots(m, s, 2 * i < k - 1 ? 2.0 : 1.0, cr[k - 1 - i], ci[k - 1 - i], W->zr[i], W->zi[i], rr, ri);
        for (int j = 0; j < s; ++j) rr[j] = -rr[j], ri[j] = -ri[j];
        plu_solve(m, F, rr, ri);
        if (k < HPAR_NY) pmatvec(P, 1, t0, rr, ri, W->yr[k], W->yi[k]);
        if (k < HPAR_NZ) pmatvec(P, 0, t0, rr, ri, W->zr[k], W->zi[k]);
    }
}

#endif /* HOM_LANES_VECTOR */
