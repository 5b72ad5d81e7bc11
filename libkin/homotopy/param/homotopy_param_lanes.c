/* The kernels of the lockstep parameter tracker (homotopy_param_lanes.h),
 * HOM_BATCH paths at once; each mirrors its one-path twin in
 * homotopy_param.c operation for operation. */
#include <math.h>
#include <string.h>

#include "homotopy/param/homotopy_param_lanes.h"

#if defined(HOM_LANES_VECTOR)

/* cloned as the one-path kernels are (homotopy_control.h) */
#if defined(HOM_MULTIVERSION)
#define PLAN_KERNEL HOM_KERNEL_WIDE
#else
#define PLAN_KERNEL
#endif

enum { MAT_D, MAT_FORM, MAT_LANES }; /* M = D, A + t D formed where used, formed already (Mr, Mi) */
/* one entry of M: A + t D formed as the one-path `form` does, or D */
#define PENTRY(o) (formed == MAT_LANES ? Mr[o] : formed == MAT_FORM ? Ar[o] + t * Dr[o] : ALL(Dr[o]))
#define PENTRYI(o) (formed == MAT_LANES ? Mi[o] : formed == MAT_FORM ? Ai[o] + t * Di[o] : ALL(Di[o]))

/* y = M x (M: see PENTRY), each row summed over the columns c in order
 * from 0, as kin__hpar_matvec; four rows at a time in registers */
HOM_INLINE void pmatvec(const hpar_problem *P, int formed, const lanes *tp, const lanes *Mr, const lanes *Mi,
                        const lanes *restrict xr, const lanes *restrict xi, lanes *restrict yr, lanes *restrict yi)
{
    int m = P->m, sm = P->s * P->m, i = 0;
    const double *Ar = P->Ar, *Ai = P->Ai, *Dr = P->Dr, *Di = P->Di;
    lanes t = *tp;
    for (; i + 4 <= sm; i += 4) {
        lanes u0 = ALL(0.0), u1 = u0, u2 = u0, u3 = u0, v0 = u0, v1 = u0, v2 = u0, v3 = u0;
        for (int c = 0; c < m; ++c) {
            size_t o = (size_t)c * sm + i;
            lanes a = xr[c], b = xi[c], mr, mi;
            mr = PENTRY(o), mi = PENTRYI(o);
            u0 += mr * a - mi * b, v0 += mr * b + mi * a;
            mr = PENTRY(o + 1), mi = PENTRYI(o + 1);
            u1 += mr * a - mi * b, v1 += mr * b + mi * a;
            mr = PENTRY(o + 2), mi = PENTRYI(o + 2);
            u2 += mr * a - mi * b, v2 += mr * b + mi * a;
            mr = PENTRY(o + 3), mi = PENTRYI(o + 3);
            u3 += mr * a - mi * b, v3 += mr * b + mi * a;
        }
        yr[i] = u0, yr[i + 1] = u1, yr[i + 2] = u2, yr[i + 3] = u3;
        yi[i] = v0, yi[i + 1] = v1, yi[i + 2] = v2, yi[i + 3] = v3;
    }
    for (; i < sm; ++i) {
        lanes u = ALL(0.0), v = ALL(0.0);
        for (int c = 0; c < m; ++c) {
            size_t o = (size_t)c * sm + i;
            lanes mr = PENTRY(o), mi = PENTRYI(o);
            u += mr * xr[c] - mi * xi[c];
            v += mr * xi[c] + mi * xr[c];
        }
        yr[i] = u, yi[i] = v;
    }
}

/* out_j += wgt * (u . y_j), j < s (y_j: entries r*s + j of y), as dots;
 * four equations at a time in registers */
HOM_INLINE void pdots(int m, int s, double wgt, const lanes *restrict ur, const lanes *restrict ui,
                      const lanes *restrict yr, const lanes *restrict yi, lanes *restrict outr,
                      lanes *restrict outi)
{
    int j = 0;
    for (; j + 4 <= s; j += 4) {
        lanes p0 = ALL(0.0), p1 = p0, p2 = p0, p3 = p0, q0 = p0, q1 = p0, q2 = p0, q3 = p0;
        for (int r = 0; r < m; ++r) {
            const lanes *ar = yr + r * s + j, *ai = yi + r * s + j;
            lanes a = ur[r], b = ui[r];
            p0 += a * ar[0] - b * ai[0], q0 += a * ai[0] + b * ar[0];
            p1 += a * ar[1] - b * ai[1], q1 += a * ai[1] + b * ar[1];
            p2 += a * ar[2] - b * ai[2], q2 += a * ai[2] + b * ar[2];
            p3 += a * ar[3] - b * ai[3], q3 += a * ai[3] + b * ar[3];
        }
        outr[j] += wgt * p0, outi[j] += wgt * q0, outr[j + 1] += wgt * p1, outi[j + 1] += wgt * q1;
        outr[j + 2] += wgt * p2, outi[j + 2] += wgt * q2, outr[j + 3] += wgt * p3, outi[j + 3] += wgt * q3;
    }
    for (; j < s; ++j) {
        lanes p0 = ALL(0.0), q0 = p0;
        for (int r = 0; r < m; ++r) {
            lanes a = ur[r], b = ui[r], ar = yr[r * s + j], ai = yi[r * s + j];
            p0 += a * ar - b * ai, q0 += a * ai + b * ar;
        }
        outr[j] += wgt * p0, outi[j] += wgt * q0;
    }
}

PLAN_KERNEL static void pnewton(const hpar_problem *P, const lanes *t, const lanes *car, const lanes *cai,
                                const lanes *xr, const lanes *xi, const hpar_lscratch *W, hom_llu *F,
                                lanes *dr, lanes *di, int *ok)
{
    int m = P->m, s = P->s;
    lanes *yr = W->pyr, *yi = W->pyi;
    pmatvec(P, MAT_FORM, t, NULL, NULL, xr, xi, yr, yi);
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
    kin__lanes_lu_factor(m, F);
    kin__lanes_lu_solve(m, F, dr, di);
    lanes n2 = ALL(0.0);
    for (int k = 0; k < m; ++k) n2 += dr[k] * dr[k] + di[k] * di[k];
    for (int l = 0; l < BL; ++l) ok[l] = F->ok[l] && isfinite(sqrt(n2[l]));
}

PLAN_KERNEL static void ptaylor(const hpar_problem *P, const lanes *t0, const hom_llu *F, const hpar_lscratch *W,
                                lanes (*cr)[HOM_MAX_M], lanes (*ci)[HOM_MAX_M])
{
    int m = P->m, s = P->s;
    { /* M(t0) of every lane, used HPAR_NY times */
        size_t n = (size_t)s * m * m;
        lanes t = *t0;
        for (size_t i = 0; i < n; ++i) W->mr[i] = P->Ar[i] + t * P->Dr[i], W->mi[i] = P->Ai[i] + t * P->Di[i];
    }
    pmatvec(P, MAT_LANES, t0, W->mr, W->mi, cr[0], ci[0], W->yr[0], W->yi[0]);
    pmatvec(P, MAT_D, t0, NULL, NULL, cr[0], ci[0], W->zr[0], W->zi[0]);
    for (int k = 1; k <= HPAR_ORDER; ++k) {
        lanes *rr = cr[k], *ri = ci[k];
        for (int j = 0; j <= s; ++j) rr[j] = ri[j] = ALL(0.0);
        for (int i = 1; 2 * i <= k; ++i) /* sum_{0<i,l<k, i+l=k} M0[x_i, x_l] */
            pdots(m, s, 2 * i < k ? 2.0 : 1.0, cr[k - i], ci[k - i], W->yr[i], W->yi[i], rr, ri);
        for (int i = 0; 2 * i <= k - 1; ++i) /* sum_{i+l=k-1} D[x_i, x_l] */
            pdots(m, s, 2 * i < k - 1 ? 2.0 : 1.0, cr[k - 1 - i], ci[k - 1 - i], W->zr[i], W->zi[i], rr, ri);
        for (int j = 0; j < s; ++j) rr[j] = -rr[j], ri[j] = -ri[j];
        kin__lanes_lu_solve(m, F, rr, ri);
        if (k < HPAR_NY) pmatvec(P, MAT_LANES, t0, W->mr, W->mi, rr, ri, W->yr[k], W->yi[k]);
        if (k < HPAR_NZ) pmatvec(P, MAT_D, t0, NULL, NULL, rr, ri, W->zr[k], W->zi[k]);
    }
}

/* The entry points the other files call: plain functions that call the
 * cloned kernels of this file (homotopy_control.h: a cloned function is
 * called only from the file that defines it). */
void kin__plan_newton(const hpar_problem *P, const lanes *t, const lanes *car, const lanes *cai,
                      const lanes *xr, const lanes *xi, const hpar_lscratch *W, hom_llu *F, lanes *dr,
                      lanes *di, int *ok)
{
    pnewton(P, t, car, cai, xr, xi, W, F, dr, di, ok);
}

void kin__plan_taylor(const hpar_problem *P, const lanes *t0, const hom_llu *F, const hpar_lscratch *W,
                      lanes (*cr)[HOM_MAX_M], lanes (*ci)[HOM_MAX_M])
{
    ptaylor(P, t0, F, W, cr, ci);
}

#endif /* HOM_LANES_VECTOR */
