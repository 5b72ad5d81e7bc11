/* Private: homotopy/param/, the parameter homotopies of the symmetric
 * complete solver (symmetric/): one root of M(t)[x, x] = 0 followed from
 * t = 0 to 1, one path at a time (homotopy_param.c, the reference, with the
 * step control of homotopy_param_control.h) or HOM_BATCH paths in lockstep,
 * each bit for bit as the one-path tracker follows it
 * (homotopy_param_batch.c, kernels homotopy_param_lanes.c). It uses track/
 * (the complex LU, the rational predictor, the lane kernels) and nothing
 * of solver/, its peer.
 *
 * This header: a path tracker for parameter homotopies of quadrics,
 *     H(x, t) = M(t)[x, x] = (A + t D)[x, x] = 0,  j < s, x in P^s,
 * with complex symmetric A and D = B - A (kin_quadrics_homotopy_sym:
 * monodromy between random members of an equivariant family and the last
 * leg to the caller's system). Complex matrices are split into real and
 * imaginary arrays in the "stacked" layout: the m columns of the (s m) x m
 * matrix whose row r*s + j is row r of the equation's matrix M_j, column c
 * at offset c*s*m, so that y = M x (y[r*s + j] = (M_j x)_r) is m
 * contiguous axpys and the dots u . (M_j x) run over the equations j
 * innermost. */
#ifndef KIN_HOMOTOPY_PARAM_H
#define KIN_HOMOTOPY_PARAM_H

#include "homotopy/track/homotopy_track.h"

typedef struct hpar_problem {
    int m, s;
    const double *Ar, *Ai; /* A (stacked) */
    const double *Dr, *Di; /* D = B - A (stacked) */
    double ar[HOM_MAX_M], ai[HOM_MAX_M]; /* the random affine chart a.x = 1 */
} hpar_problem;

/* tracking tolerances */
typedef struct hpar_settings {
    double pred_rel;  /* predictor error target relative to |x| */
    double corr_rel;  /* largest first Newton correction accepted, relative to |x| */
    double sigma_end; /* stop when 1 - t falls below this (0: track to t = 1 and refine there) */
} hpar_settings;

/* outcome of one path */
typedef struct hpar_end {
    int ok;       /* reached the end (and, sigma_end = 0, Newton at t = 1 converged) */
    int steps;    /* accepted steps */
    int rejected; /* rejected steps */
    int pade;     /* accepted steps the rational predictor predicted */
    int pade_rejected; /* rejected steps it predicted */
    double sigma; /* 1 - t where tracking stopped */
} hpar_end;

typedef struct hpar_ws hpar_ws;
/* workspace for problems of s equations and m unknowns (m <= HOM_MAX_M) */
hpar_ws *kin__hpar_ws_new(int m, int s);
void kin__hpar_ws_free(hpar_ws *w);

/* Track the root x0 (m complex, any scale) of A from t = 0 to 1; x receives
 * the endpoint (any scale). */
void kin__hpar_track(const hpar_problem *P, const hpar_settings *S, hpar_ws *w, const double *x0r,
                     const double *x0i, double *xr, double *xi, hpar_end *e);

/* y = M x for a stacked complex matrix (sm = s*m rows, m columns) */
void kin__hpar_matvec(int sm, int m, const double *Mr, const double *Mi, const double *xr, const double *xi,
                      double *yr, double *yi);

/* ---- lockstep tracking (homotopy_param_batch.c) ---- */
enum { HPAR_BATCH_STOP = -2 }; /* hpar_batch_sink.next: abandon the paths in flight */
/* where the batch tracker gets its paths and leaves their endpoints */
typedef struct hpar_batch_sink {
    void *ctx;
    /* the next path: its id (>= 0) with its start point written to x0r,
     * x0i (m each); -1 when there is none, HPAR_BATCH_STOP to stop at once
     * (the paths in flight are abandoned: not passed to done) */
    int (*next)(void *ctx, double *x0r, double *x0i);
    /* path id's endpoint (m each, any scale) and record, as
     * kin__hpar_track gives them (where that one leaves x unwritten, a
     * start point with a = 0 in the chart, x is the start point) */
    void (*done)(void *ctx, int id, const double *xr, const double *xi, const hpar_end *e);
} hpar_batch_sink;
typedef struct hpar_bws hpar_bws;
/* per-thread workspace of the batch tracker for problems of s equations and
 * m unknowns (m <= HOM_MAX_M), allocated once per thread */
hpar_bws *kin__hpar_bws_new(int m, int s);
void kin__hpar_bws_free(hpar_bws *b);
/* Track every path K->next hands out, HOM_BATCH at a time, each exactly as
 * kin__hpar_track would (the same endpoint and record, bit for bit). */
void kin__hpar_track_batch(const hpar_problem *P, const hpar_settings *S, hpar_bws *B, const hpar_batch_sink *K);

#endif /* KIN_HOMOTOPY_PARAM_H */
