/* Private: the parameter tracker's complex linear algebra on HOM_BATCH
 * paths at once (homotopy_param_batch.c), one path per lane of the `lanes`
 * vectors of homotopy_lanes.h (entry c of lane l's vector at v[c][l]).
 * Each lane gets exactly the operations of the one-path kernels of
 * homotopy_param.c, every sum in the same order and no contraction to fused
 * multiply-adds, so each lane's results are bit for bit theirs. Every lane
 * has its own t, so M(t) = A + t D is formed per lane with the one-path
 * `form`'s expression: in Newton where it is used (once per iteration; the
 * loads of A and D shared among the lanes), for the series once into
 * scratch (used HPAR_NY times). GCC and Clang only. */
#ifndef KIN_HOMOTOPY_PARAM_LANES_H
#define KIN_HOMOTOPY_PARAM_LANES_H

#include "homotopy/param/homotopy_param_control.h"
#include "homotopy/track/homotopy_lanes.h"

#if defined(HOM_LANES_VECTOR)

/* scratch of s*m rows per vector (allocated by the caller, 32-byte aligned) */
typedef struct hpar_lscratch {
    lanes *yr[HPAR_NY], *yi[HPAR_NY]; /* M0 x_k */
    lanes *zr[HPAR_NZ], *zi[HPAR_NZ]; /* D x_k */
    lanes *pyr, *pyi;                 /* M(t) x in Newton */
    lanes *mr, *mi;                   /* M(t0) of the series (s*m*m each) */
} hpar_lscratch;

/* Newton's correction d = J^-1 H at x for M(t) (each lane its t, *t) in the
 * chart (car, cai); J factored in F; ok[l] = 0 where J is singular or d not
 * finite (as newton in homotopy_param.c) */
void kin__plan_newton(const hpar_problem *P, const lanes *t, const lanes *car, const lanes *cai, const lanes *xr,
                      const lanes *xi, const hpar_lscratch *W, hom_llu *F, lanes *dr, lanes *di, int *ok);
/* the Taylor coefficients c[1..HPAR_ORDER] (cr, ci: HPAR_ORDER + 1 vectors
 * of HOM_MAX_M) of every lane's path through c[0] at its t (*t0), J's
 * factors in F (as taylor) */
void kin__plan_taylor(const hpar_problem *P, const lanes *t0, const hom_llu *F, const hpar_lscratch *W,
                      lanes (*cr)[HOM_MAX_M], lanes (*ci)[HOM_MAX_M]);

#endif /* HOM_LANES_VECTOR */
#endif /* KIN_HOMOTOPY_PARAM_LANES_H */
