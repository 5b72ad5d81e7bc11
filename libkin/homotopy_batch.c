/* Lockstep tracking: HOM_BATCH paths of the complete solver at once, one
 * path per lane of a structure of arrays (entry c of lane l's vector at
 * v[c][l]), so that every kernel (Q x, the LU factorisation with each lane's
 * own pivots, the substitutions, the Taylor series' sums) runs its inner
 * loop across the lanes: independent operations of equal length that the
 * compiler puts in vector registers whatever m is, and that share every
 * load of Q.
 *
 * Each lane follows its path through exactly the operations of the
 * one-path tracker kin__hom_track (homotopy_track.c, the reference: same
 * predictor, corrector, acceptance tests, charts and certificate, every sum
 * in the same order, no contraction to fused multiply-adds), so a path's
 * endpoint, step counts and class are bit for bit those of the one-path
 * tracker, whatever other paths share its batch (tests/test_homotopy_batch.c).
 *
 * Rounds: almost every step is the same sequence (Taylor series at the
 * base point, predictor, two Newton iterations, accept), so all lanes go
 * through one round per step: the Taylor series for every lane, then the
 * Newton iterations for the lanes still iterating. A lane whose step is
 * rejected repeats the round with half the step (its series is recomputed
 * from the same base point, bit for bit the same); the rare third Newton
 * iteration runs for all lanes, the others' results discarded. A lane whose
 * path ends is certified (one path, kin__hom_certify) and takes the next
 * path from the source; its start point (and a lane's change of chart) gets
 * the base-point evaluation before the round's series.
 *
 * Base and trial points: the round's Newton iterations write the trial
 * slot; on acceptance the slots swap when every lane accepted, and
 * otherwise the rejected lanes' base points are copied into the trial slot
 * before the swap. */
#define _POSIX_C_SOURCE 200112L /* posix_memalign */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy_control.h"

#if defined(__GNUC__) /* GCC and Clang: vector extensions */

#define BL HOM_BATCH

/* the kernels are cloned as in homotopy_track.c, with AVX-512 as well:
 * with 8 lanes a vector register holds one value of every lane */
#if defined(HOM_MULTIVERSION)
#define HOMB_KERNEL __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define HOMB_KERNEL
#endif

/* one value per lane: a vector of BL doubles (element-wise IEEE
 * arithmetic, no contraction under -std=c99) */
typedef double lanes __attribute__((vector_size(BL * sizeof(double))));
typedef long long lmask __attribute__((vector_size(BL * sizeof(double))));
#define ALL(x) ((lanes){0.0} + (x))

/* LU factors of the lanes' Jacobians: entry (row j, column c) at [c*m + j] */
typedef struct blu {
    lanes r[HOM_MM], i[HOM_MM];   /* J; after factoring, U strictly above the diagonal */
    lanes lr[HOM_MM], li[HOM_MM]; /* after factoring, L strictly below the diagonal */
    lanes dr[HOM_MAX_M], di[HOM_MAX_M]; /* 1 / U_kk */
    int piv[HOM_MAX_M][BL];
    int ok[BL]; /* the factorisation succeeded (no zero pivot) */
} blu;

/* a point of every lane with Q x, H and the LU factors of J */
typedef struct bpoint {
    lanes xr[HOM_MAX_M], xi[HOM_MAX_M];
    lanes yr[HOM_MAX_ROWS], yi[HOM_MAX_ROWS];
    lanes hr[HOM_MAX_M], hi[HOM_MAX_M];
    blu lu;
} bpoint;

/* what a lane is doing */
enum { LANE_EMPTY = 0, LANE_START, LANE_RECHART, LANE_TOP, LANE_RETRY };

typedef struct blane {
    int state, path;
    hom_end e;
    double t, rsep, hcap, calib, na, h, t1, rho, tail, prevd;
    int it_ok; /* Newton: 0 iterating, 1 accepted, -1 rejected */
} blane;

struct hom_bws {
    bpoint pt[2];
    bpoint *base, *trial;
    lanes xr[HOM_MAX_M], xi[HOM_MAX_M];   /* each lane's current point (x in kin__hom_track) */
    lanes dr[HOM_MAX_M], di[HOM_MAX_M];   /* Newton's corrections */
    lanes car[HOM_MAX_M], cai[HOM_MAX_M]; /* each lane's chart */
    lanes cr[HOM_ORDER + 1][HOM_MAX_M], ci[HOM_ORDER + 1][HOM_MAX_M]; /* Taylor coefficients */
    lanes ykr[HOM_NY][HOM_MAX_ROWS], yki[HOM_NY][HOM_MAX_ROWS];       /* Q x_k, k >= 1 */
    lanes tv;                                                         /* each lane's t for the kernels */
    blane L[BL];
};

hom_bws *kin__hom_bws_new(void)
{
    void *b = NULL;
    if (posix_memalign(&b, 64, sizeof(hom_bws)) != 0) return NULL; /* vector alignment */
    memset(b, 0, sizeof(hom_bws));
    return b;
}
void kin__hom_bws_free(hom_bws *b) { free(b); }

/* ---- kernels across lanes ---- */

/* y = Q x from the blocked copy of Q (rows r*sp + j: row r of Q_j), each
 * row summed over c in order, as qmul in homotopy_track.c */
HOM_INLINE void bqmul_rows(const hom_problem *P, const lanes *restrict xr, const lanes *restrict xi,
                           lanes *restrict yr, lanes *restrict yi)
{
    int n = P->sp * P->m, m = P->m;
    const double *qb = P->Qb;
    for (int i = 0; i < n; i += HOM_QBLOCK, qb += HOM_QBLOCK * m)
        for (int r0 = 0; r0 < HOM_QBLOCK; r0 += 4) {
            lanes a0 = ALL(0.0), a1 = a0, a2 = a0, a3 = a0, b0 = a0, b1 = a0, b2 = a0, b3 = a0;
            for (int c = 0; c < m; ++c) {
                const double *q = qb + HOM_QBLOCK * c + r0;
                lanes u = xr[c], v = xi[c];
                a0 += q[0] * u, b0 += q[0] * v;
                a1 += q[1] * u, b1 += q[1] * v;
                a2 += q[2] * u, b2 += q[2] * v;
                a3 += q[3] * u, b3 += q[3] * v;
            }
            lanes *ur = yr + i + r0, *ui = yi + i + r0;
            ur[0] = a0, ur[1] = a1, ur[2] = a2, ur[3] = a3;
            ui[0] = b0, ui[1] = b1, ui[2] = b2, ui[3] = b3;
        }
}
HOMB_KERNEL static void bqmul(const hom_problem *P, const lanes *xr, const lanes *xi, lanes *yr, lanes *yi)
{
    bqmul_rows(P, xr, xi, yr, yi);
}

/* out_j = sum_c u_c y[c*sp + j], j < s, summed over c in order */
HOMB_KERNEL static void bdots(int m, int s, int sp, const lanes *restrict ur, const lanes *restrict ui,
                              const lanes *restrict yr, const lanes *restrict yi, lanes *restrict outr,
                              lanes *restrict outi)
{
    int j = 0;
    for (; j + 4 <= s; j += 4) { /* 8 independent sums keep the adders busy */
        lanes p0 = ALL(0.0), q0 = p0, p1 = p0, q1 = p0, p2 = p0, q2 = p0, p3 = p0, q3 = p0;
        for (int c = 0; c < m; ++c) {
            const lanes *ar = yr + c * sp + j, *ai = yi + c * sp + j;
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
            lanes a = ur[c], b = ui[c], ar = yr[c * sp + j], ai = yi[c * sp + j];
            p0 += a * ar - b * ai, q0 += a * ai + b * ar;
        }
        outr[j] = p0, outi[j] = q0;
    }
}

/* the lanes of a where mask is set (all bits), of b elsewhere */
#define select_lanes(mask, a, b) ((lanes)(((mask) & (lmask)(a)) | (~(mask) & (lmask)(b))))

/* LU with partial pivoting (largest |re| + |im|, the first of equals), each
 * lane its own pivots; F->ok[l] = 0 where a pivot is zero or not finite
 * (that lane's factors are then meaningless) */
HOMB_KERNEL static void blu_factor(int n, blu *F)
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
        for (int j = k + 1; j < n; ++j) { /* column j -= L(:, k) U(k, j) */
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
HOMB_KERNEL static void bpermute(int n, const blu *F, lanes *br, lanes *bi, int back)
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
HOMB_KERNEL static void blu_solve(int n, const blu *F, lanes *restrict br, lanes *restrict bi)
{
    bpermute(n, F, br, bi, 0);
    for (int j = 0; j < n - 1; ++j) { /* L y = b, unit diagonal */
        const lanes *cr = F->lr + j * n, *ci = F->li + j * n;
        lanes vr = br[j], vi = bi[j];
        for (int i = j + 1; i < n; ++i) {
            br[i] -= cr[i] * vr - ci[i] * vi;
            bi[i] -= cr[i] * vi + ci[i] * vr;
        }
    }
    for (int j = n - 1; j >= 0; --j) { /* U x = y */
        const lanes *cr = F->r + j * n, *ci = F->i + j * n;
        lanes vr = br[j] * F->dr[j] - bi[j] * F->di[j], vi = br[j] * F->di[j] + bi[j] * F->dr[j];
        br[j] = vr, bi[j] = vi;
        for (int i = 0; i < j; ++i) {
            br[i] -= cr[i] * vr - ci[i] * vi;
            bi[i] -= cr[i] * vi + ci[i] * vr;
        }
    }
}

/* b <- A^-H b (A = P^T L U), as lu_solve_adj */
HOMB_KERNEL static void blu_solve_adj(int n, const blu *F, lanes *restrict br, lanes *restrict bi)
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
HOMB_KERNEL static void bvnorm(int n, const lanes *xr, const lanes *xi, double *out)
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
HOMB_KERNEL static void binv_norm1(int n, const blu *F, double *est)
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

/* Q x, H and J at p->x, each lane at its t (B->tv) in its chart, as eval */
HOMB_KERNEL static void beval(const hom_problem *P, hom_bws *B, bpoint *p)
{
    int m = P->m, s = P->s, sp = P->sp;
    const lanes *xr = p->xr, *xi = p->xi;
    lanes t = B->tv, two_t = 2.0 * t;
    bqmul(P, xr, xi, p->yr, p->yi);
    lanes alr = (1.0 - t) * P->gr, ali = (1.0 - t) * P->gi;
    lanes *Jr = p->lu.r, *Ji = p->lu.i;
    lanes fr[HOM_MAX_M], fi[HOM_MAX_M]; /* F_j(x) */
    bdots(m, s, sp, xr, xi, p->yr, p->yi, fr, fi);
    for (int c = 0; c < m; ++c) { /* J(j, c) = 2 t (Q_j x)_c + the G terms below */
        const lanes *yr = p->yr + c * sp, *yi = p->yi + c * sp;
        lanes *jr = Jr + c * m, *ji = Ji + c * m;
        for (int j = 0; j < s; ++j) jr[j] = two_t * yr[j], ji[j] = two_t * yi[j];
        jr[s] = B->car[c], ji[s] = B->cai[c];
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
        cr += B->car[c] * xr[c] - B->cai[c] * xi[c];
        ci += B->car[c] * xi[c] + B->cai[c] * xr[c];
    }
    p->hr[s] = cr, p->hi[s] = ci;
}

/* H, J at p->x and Newton's correction d = J^-1 H in B->d, every lane;
 * ok[l] = 0 where J is singular or d not finite (as newton_step) */
HOMB_KERNEL static void bnewton(const hom_problem *P, hom_bws *B, bpoint *p, int *ok)
{
    int m = P->m;
    beval(P, B, p);
    blu_factor(m, &p->lu);
    memcpy(B->dr, p->hr, sizeof(lanes) * (size_t)m);
    memcpy(B->di, p->hi, sizeof(lanes) * (size_t)m);
    blu_solve(m, &p->lu, B->dr, B->di);
    double nd[BL];
    bvnorm(m, B->dr, B->di, nd);
    for (int l = 0; l < BL; ++l) ok[l] = p->lu.ok[l] && isfinite(nd[l]);
}

/* out_j += wgt * (u . y_j), j < s, every lane (as dots) */
HOMB_KERNEL static void bdots_add(int m, int s, int sp, double wgt, const lanes *ur, const lanes *ui, const lanes *yr,
                      const lanes *yi, lanes *outr, lanes *outi)
{
    lanes pr[HOM_MAX_M], pi[HOM_MAX_M];
    bdots(m, s, sp, ur, ui, yr, yi, pr, pi);
    for (int j = 0; j < s; ++j) outr[j] += wgt * pr[j], outi[j] += wgt * pi[j];
}

/* pair_sums of homotopy_track.c, every lane */
HOMB_KERNEL static void bpair_sums(const hom_problem *P, const hom_bws *B, const lanes *const *yr, const lanes *const *yi, int k,
                       lanes *fr, lanes *fi, lanes *gr, lanes *gi)
{
    int m = P->m, s = P->s;
    for (int j = 0; j < s; ++j) fr[j] = fi[j] = gr[j] = gi[j] = ALL(0.0);
    for (int i = 1; 2 * i <= k; ++i) {
        int li = k - i;
        double wgt = i < li ? 2.0 : 1.0;
        const lanes *ar = B->cr[li], *ai = B->ci[li], *ur = B->cr[i], *ui = B->ci[i];
        bdots_add(m, s, P->sp, wgt, ar, ai, yr[i], yi[i], fr, fi);
        lanes e0r = ur[0] * ar[0] - ui[0] * ai[0], e0i = ur[0] * ai[0] + ui[0] * ar[0];
        for (int j = 0; j < s; ++j) {
            int q = j + 1;
            gr[j] += wgt * (ur[q] * ar[q] - ui[q] * ai[q] - e0r);
            gi[j] += wgt * (ur[q] * ai[q] + ui[q] * ar[q] - e0i);
        }
    }
}

/* the Taylor coefficients of every lane's path through c[0] at its t (B->tv)
 * from its base point b, as taylor in homotopy_track.c (the F[x_0, x_{k-1}]
 * terms recovered from J x_k in the lanes where t >= T_RECOVER, computed
 * directly in the others) */
HOMB_KERNEL static void btaylor(const hom_problem *P, hom_bws *B, const bpoint *b)
{
    int m = P->m, s = P->s;
    lanes t0 = B->tv;
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
            bdots(m, s, P->sp, ur, ui, yr[0], yi[0], dtr, dti);
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

/* ---- lanes ---- */

/* copy lane l of point a into point b */
static void copy_lane(int m, int rows, int l, const bpoint *a, bpoint *b)
{
    for (int c = 0; c < m; ++c) {
        b->xr[c][l] = a->xr[c][l], b->xi[c][l] = a->xi[c][l];
        b->hr[c][l] = a->hr[c][l], b->hi[c][l] = a->hi[c][l];
        b->lu.dr[c][l] = a->lu.dr[c][l], b->lu.di[c][l] = a->lu.di[c][l];
        b->lu.piv[c][l] = a->lu.piv[c][l];
    }
    for (int r = 0; r < rows; ++r) b->yr[r][l] = a->yr[r][l], b->yi[r][l] = a->yi[r][l];
    for (int r = 0; r < m * m; ++r) {
        b->lu.r[r][l] = a->lu.r[r][l], b->lu.i[r][l] = a->lu.i[r][l];
        b->lu.lr[r][l] = a->lu.lr[r][l], b->lu.li[r][l] = a->lu.li[r][l];
    }
    b->lu.ok[l] = a->lu.ok[l];
}

/* the start solution of `path` in lane l (x_j = +-x_0, scaled into the
 * chart P->a), as kin__hom_track */
static void start_lane(const hom_problem *P, hom_bws *B, int l, int path)
{
    int m = P->m;
    blane *L = &B->L[l];
    memset(L, 0, sizeof *L);
    L->path = path;
    L->state = LANE_START;
    L->e.kind = HOM_FAILED;
    L->e.rminus = L->e.rplus = L->e.cond = INFINITY;
    double xr[HOM_MAX_M], sr = 0.0, si = 0.0;
    xr[0] = 1.0;
    for (int j = 1; j < m; ++j) xr[j] = (path >> (j - 1)) & 1 ? -1.0 : 1.0;
    double na = 0.0;
    for (int c = 0; c < m; ++c) {
        B->car[c][l] = P->ar[c], B->cai[c][l] = P->ai[c];
        na += P->ar[c] * P->ar[c] + P->ai[c] * P->ai[c];
    }
    L->na = sqrt(na);
    for (int c = 0; c < m; ++c) sr += P->ar[c] * xr[c], si += P->ai[c] * xr[c];
    double d = sr * sr + si * si;
    for (int c = 0; c < m; ++c) B->xr[c][l] = xr[c] * sr / d, B->xi[c][l] = -xr[c] * si / d;
    L->t = 0.0;
    L->hcap = INFINITY;
    L->calib = 1.0;
}

/* the end of lane l's path: certified from its current point (or returned
 * as it is when lost early, or not even started); the lane is then empty */
static void finish_lane(const hom_problem *P, hom_bws *B, hom_ws *w, int l, int lost, int started,
                        const hom_batch_sink *K)
{
    int m = P->m;
    blane *L = &B->L[l];
    double xr[HOM_MAX_M], xi[HOM_MAX_M], zr[HOM_MAX_M], zi[HOM_MAX_M];
    for (int c = 0; c < m; ++c) xr[c] = B->xr[c][l], xi[c] = B->xi[c][l];
    hom_end *e = &L->e;
    if (started) e->sigma = 1.0 - L->t;
    if (!started || (lost && e->sigma > SIGMA_STALL)) {
        K->done(K->ctx, L->path, xr, xi, e);
    } else {
        kin__hom_certify(P, w, xr, xi, zr, zi, e);
        K->done(K->ctx, L->path, zr, zi, e);
    }
    L->state = LANE_EMPTY;
    L->path = -1;
}

/* the checks at the top of kin__hom_track's step loop for lane l: the end
 * (1 - t below sigma_end), the step budget, the chart's tilt. 1 if the lane
 * goes on (state LANE_TOP, or LANE_RECHART with the new chart), 0 if its
 * path ended (finished). */
static int top_checks(const hom_problem *P, const hom_settings *S, hom_bws *B, hom_ws *w, int l,
                      const hom_batch_sink *K)
{
    int m = P->m;
    blane *L = &B->L[l];
    if (1.0 - L->t <= S->sigma_end) {
        finish_lane(P, B, w, l, 0, 1, K);
        return 0;
    }
    if (L->e.steps + L->e.rejected >= MAX_STEPS) {
        finish_lane(P, B, w, l, 1, 1, K);
        return 0;
    }
    double s = 0.0;
    for (int c = 0; c < m; ++c) s += B->xr[c][l] * B->xr[c][l] + B->xi[c][l] * B->xi[c][l];
    double nx = sqrt(s);
    if (nx * L->na > CHART_TILT * sqrt((double)m)) {
        for (int c = 0; c < m; ++c) B->car[c][l] = B->xr[c][l] / (nx * nx), B->cai[c][l] = -B->xi[c][l] / (nx * nx);
        L->na = 1.0 / nx;
        L->state = LANE_RECHART;
        return 1;
    }
    L->state = LANE_TOP;
    return 1;
}

/* Evaluate the base point of the lanes in LANE_START or LANE_RECHART at their
 * t (Newton's first step, J factored, the separation radius), in the trial
 * slot, then copy it into the base slot lane by lane. Lanes whose
 * evaluation fails end (a start: as not started; a rechart: lost). */
static void prepare_bases(const hom_problem *P, const hom_settings *S, hom_bws *B, hom_ws *w,
                          const hom_batch_sink *K)
{
    int m = P->m, rows = kin__hom_rows(m, P->s);
    for (;;) {
        int any = 0;
        for (int l = 0; l < BL; ++l) any |= B->L[l].state == LANE_START || B->L[l].state == LANE_RECHART;
        if (!any) return;
        bpoint *p = B->trial;
        memcpy(p->xr, B->xr, sizeof(lanes) * (size_t)m);
        memcpy(p->xi, B->xi, sizeof(lanes) * (size_t)m);
        for (int l = 0; l < BL; ++l) B->tv[l] = B->L[l].state == LANE_EMPTY ? 0.0 : B->L[l].t;
        int ok[BL];
        double inv[BL];
        bnewton(P, B, p, ok);
        binv_norm1(m, &p->lu, inv);
        for (int l = 0; l < BL; ++l) {
            blane *L = &B->L[l];
            int start = L->state == LANE_START;
            if (!start && L->state != LANE_RECHART) continue;
            if (!ok[l]) {
                finish_lane(P, B, w, l, 1, !start, K);
                continue;
            }
            copy_lane(m, rows, l, p, B->base);
            L->rsep = 1.0 / (inv[l] * ((1.0 - L->t) * P->normG + L->t * P->normF));
            if (start) { /* the start point is exact: x = base->x */
                for (int c = 0; c < m; ++c) B->xr[c][l] = p->xr[c][l], B->xi[c][l] = p->xi[c][l];
                top_checks(P, S, B, w, l, K); /* LANE_TOP or LANE_RECHART again */
            } else {
                L->e.recharts++;
                L->state = LANE_TOP;
            }
        }
    }
}

void kin__hom_track_batch(const hom_problem *P, const hom_settings *S, hom_bws *B, hom_ws *w,
                          const hom_batch_sink *K)
{
    int m = P->m, rows = kin__hom_rows(m, P->s), drained = 0;
    B->base = &B->pt[0], B->trial = &B->pt[1];
    for (int l = 0; l < BL; ++l) B->L[l].state = LANE_EMPTY, B->L[l].path = -1;
    for (;;) {
        /* fill the empty lanes */
        for (int l = 0; l < BL && !drained; ++l)
            if (B->L[l].state == LANE_EMPTY) {
                int path = K->next(K->ctx);
                if (path == HOM_BATCH_STOP) return; /* cancelled: abandon the lanes' paths */
                if (path < 0) drained = 1;
                else start_lane(P, B, l, path);
            }
        prepare_bases(P, S, B, w, K);
        int active = 0;
        for (int l = 0; l < BL; ++l) active += B->L[l].state != LANE_EMPTY;
        if (!active) {
            if (drained) return;
            continue;
        }
        /* the series at every lane's base point (a lane retrying a step
         * gets the same coefficients again) */
        for (int c = 0; c < m; ++c)
            for (int l = 0; l < BL; ++l) B->cr[0][c][l] = B->xr[c][l], B->ci[0][c][l] = B->xi[c][l];
        for (int l = 0; l < BL; ++l) B->tv[l] = B->L[l].state == LANE_EMPTY ? 1.0 : B->L[l].t;
        btaylor(P, B, B->base);
        /* each lane's step and prediction */
        bpoint *p = B->trial;
        int in[BL]; /* the lane takes part in this round's Newton iterations */
        for (int l = 0; l < BL; ++l) {
            blane *L = &B->L[l];
            in[l] = 0;
            if (L->state == LANE_EMPTY) {
                B->tv[l] = 0.0;
                for (int c = 0; c < m; ++c) p->xr[c][l] = p->xi[c][l] = 0.0;
                continue;
            }
            double sigma = 1.0 - L->t;
            if (L->state == LANE_TOP) {
                double n[HOM_ORDER + 1], nx = 0.0;
                for (int k = 1; k <= HOM_ORDER; ++k) {
                    double s2 = 0.0;
                    for (int c = 0; c < m; ++c) s2 += B->cr[k][c][l] * B->cr[k][c][l] + B->ci[k][c][l] * B->ci[k][c][l];
                    n[k] = sqrt(s2);
                }
                for (int c = 0; c < m; ++c) nx += B->xr[c][l] * B->xr[c][l] + B->xi[c][l] * B->xi[c][l];
                nx = sqrt(nx);
                double target = fmin(S->pred_rel * nx, S->pred_sep * L->rsep);
                double hser = kin__hom_series_step(n, target / L->calib, &L->rho, &L->tail);
                L->h = fmin(hser, L->hcap);
                L->state = LANE_RETRY;
            }
            if (L->h >= sigma) L->h = sigma;
            if (L->h < H_MIN) {
                finish_lane(P, B, w, l, 1, 1, K);
                B->tv[l] = 0.0;
                for (int c = 0; c < m; ++c) p->xr[c][l] = p->xi[c][l] = 0.0;
                continue;
            }
            L->t1 = L->h == sigma ? 1.0 : L->t + L->h;
            B->tv[l] = L->t1;
            double h = L->h;
            for (int c = 0; c < m; ++c) { /* the predictor, as predict */
                double vr = B->cr[HOM_ORDER][c][l], vi = B->ci[HOM_ORDER][c][l];
                for (int k = HOM_ORDER - 1; k >= 0; --k) {
                    vr = vr * h + B->cr[k][c][l];
                    vi = vi * h + B->ci[k][c][l];
                }
                p->xr[c][l] = vr, p->xi[c][l] = vi;
            }
            L->prevd = INFINITY;
            L->it_ok = 0;
            in[l] = 1;
        }
        /* Newton, as in kin__hom_track; a lane that accepted before the
         * last iteration run is moved to the base slot first */
        int moved[BL] = {0};
        for (int it = 0; it < NEWTON_MAX; ++it) {
            int going = 0;
            for (int l = 0; l < BL; ++l) going |= in[l] && B->L[l].it_ok == 0;
            if (!going) break;
            if (it > 0) {
                for (int l = 0; l < BL; ++l)
                    if (in[l] && B->L[l].it_ok == 1 && !moved[l]) {
                        /* accepted at it - 1: its point becomes the base now */
                        copy_lane(m, rows, l, p, B->base);
                        moved[l] = 1;
                    }
                for (int c = 0; c < m; ++c)
                    for (int l = 0; l < BL; ++l) p->xr[c][l] -= B->dr[c][l], p->xi[c][l] -= B->di[c][l];
            }
            int ok[BL];
            double nd[BL], np[BL], inv[BL];
            bnewton(P, B, p, ok);
            if (it == 0) binv_norm1(m, &p->lu, inv);
            bvnorm(m, B->dr, B->di, nd);
            bvnorm(m, p->xr, p->xi, np);
            for (int l = 0; l < BL; ++l) {
                blane *L = &B->L[l];
                if (!in[l] || L->it_ok != 0) continue;
                if (!ok[l]) {
                    L->it_ok = -1;
                    continue;
                }
                double tol = fmax(NEWTON_TOL, NOISE_FACTOR * DBL_EPSILON * np[l] / L->rsep) * np[l];
                if (it == 0) {
                    double est = kin__hom_series_error(L->rho, L->tail, L->h);
                    if (est > 0.0 && nd[l] > 0.0)
                        L->calib = fmin(CALIB_MAX, fmax(CALIB_MIN, sqrt(L->calib * nd[l] / est)));
                    double rs = 1.0 / (inv[l] * ((1.0 - L->t1) * P->normG + L->t1 * P->normF));
                    if (!(nd[l] <= S->corr_sep * rs) || !(nd[l] <= CORR_REL_MAX * np[l])) {
                        L->it_ok = -1;
                        continue;
                    }
                    L->rsep = rs;
                } else {
                    if (nd[l] * nd[l] <= NEWTON_TOL * np[l] * L->rsep || nd[l] <= tol) {
                        L->it_ok = 1;
                        /* x = p->x - d */
                        for (int c = 0; c < m; ++c)
                            B->xr[c][l] = p->xr[c][l] - B->dr[c][l], B->xi[c][l] = p->xi[c][l] - B->di[c][l];
                        continue;
                    }
                    if (!(nd[l] <= CONTRACTION * L->prevd)) {
                        L->it_ok = -1;
                        continue;
                    }
                }
                L->prevd = nd[l];
            }
        }
        /* the new base points: the trial slot where every taking part lane
         * accepted in the last iteration; else the rejected lanes' (and the
         * moved lanes') base points go to the trial slot first */
        int acc = 0;
        for (int l = 0; l < BL; ++l) acc += in[l] && B->L[l].it_ok == 1 && !moved[l];
        if (acc > 0) {
            for (int l = 0; l < BL; ++l)
                if (in[l] && !(B->L[l].it_ok == 1 && !moved[l])) copy_lane(m, rows, l, B->base, p);
            B->trial = B->base, B->base = p;
        }
        for (int l = 0; l < BL; ++l) {
            if (!in[l]) continue;
            blane *L = &B->L[l];
            if (L->it_ok == 1) {
                L->t = L->t1;
                L->hcap = L->h * ACCEPT_GROW;
                L->e.steps++;
                top_checks(P, S, B, w, l, K);
            } else {
                L->e.rejected++;
                L->h *= REJECT_SHRINK;
                L->hcap = L->h;
                if (L->e.steps + L->e.rejected >= MAX_STEPS) finish_lane(P, B, w, l, 1, 1, K);
            }
        }
    }
}

#else /* other compilers: one path at a time with the reference tracker */

struct hom_bws {
    double zr[HOM_MAX_M], zi[HOM_MAX_M];
};
hom_bws *kin__hom_bws_new(void) { return malloc(sizeof(hom_bws)); }
void kin__hom_bws_free(hom_bws *b) { free(b); }

void kin__hom_track_batch(const hom_problem *P, const hom_settings *S, hom_bws *B, hom_ws *w,
                          const hom_batch_sink *K)
{
    for (;;) {
        int path = K->next(K->ctx);
        if (path < 0) return;
        hom_end e;
        kin__hom_track(P, S, w, path, B->zr, B->zi, &e);
        K->done(K->ctx, path, B->zr, B->zi, &e);
    }
}

#endif
