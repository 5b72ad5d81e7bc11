/* Lockstep tracking for the parameter homotopies of the symmetric complete
 * solver: HOM_BATCH paths at once, one per lane, with the kernels of
 * homotopy_param_lanes.c.
 *
 * Each lane follows its path through exactly the operations of the
 * one-path tracker kin__hpar_track (homotopy_param.c, the reference: same
 * predictor (Taylor or rational, per lane), corrector, acceptance tests,
 * charts and refinement, every sum in the same order), so a path's endpoint and record are bit for bit the
 * one-path tracker's, whatever other paths share its batch
 * (tests/test_homotopy_param_batch.c).
 *
 * Schedule: every lane is either waiting for its series or wants a Newton
 * iteration (the start point's corrector at t = 0, the J for the series in
 * a new chart, a step's corrector, the refinement at t = 1). Newton
 * iterations run for all lanes at once (each at its own t, point and chart)
 * while any lane wants one; a lane that finished takes the next path from
 * the sink at once and joins in; then the series of all the lanes (all
 * waiting for it by then) are computed together and each lane predicts its
 * step. A rejected step needs no new series (the predictor shrinks the step
 * on the same one) and goes straight back to Newton. The J factors a lane's
 * series needs (its last accepted Newton iteration's) are kept aside in
 * `ser`, since the shared Newton workspace is overwritten by every
 * iteration. */
#define _POSIX_C_SOURCE 200112L /* posix_memalign */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/param/homotopy_param_lanes.h"

#if defined(HOM_LANES_VECTOR)

/* what a lane is doing: waiting for its series, or the kind of its Newton
 * iterations */
enum { LANE_EMPTY = 0, LANE_SERIES, LANE_START, LANE_FRESH, LANE_STEP, LANE_REFINE };

typedef struct plane {
    int mode, id, it;
    hpar_end e;
    double t, t1, h, hcap, na, nx, sigma, prev;
    /* the rational predictor's step control, as in kin__hpar_track */
    double hser, target, calib, pest;
    hom_pade pd;
    int first, pade;
} plane;

struct hpar_bws {
    hom_llu work, ser;                   /* every Newton iteration's J; the series' J */
    lanes xr[HOM_MAX_M], xi[HOM_MAX_M];   /* each lane's current point (x in kin__hpar_track) */
    lanes pr[HOM_MAX_M], pi[HOM_MAX_M];   /* the Newton iterate */
    lanes dr[HOM_MAX_M], di[HOM_MAX_M];   /* Newton's correction */
    lanes car[HOM_MAX_M], cai[HOM_MAX_M]; /* each lane's chart */
    lanes cr[HPAR_ORDER + 1][HOM_MAX_M], ci[HPAR_ORDER + 1][HOM_MAX_M]; /* the series */
    double pcr[BL][HPAR_ORDER + 1][HOM_MAX_M], pci[BL][HPAR_ORDER + 1][HOM_MAX_M]; /* each lane's, for the rational predictor */
    lanes tv;
    plane L[BL];
    hpar_lscratch W;
    int m, s;
    lanes *block; /* behind W */
};

hpar_bws *kin__hpar_bws_new(int m, int s)
{
    void *b = NULL, *v = NULL;
    size_t nv = (size_t)2 * (HPAR_NY + HPAR_NZ + 1) * s * m + (size_t)2 * s * m * m;
    if (posix_memalign(&b, 64, sizeof(hpar_bws)) != 0) return NULL; /* vector alignment */
    if (posix_memalign(&v, 64, sizeof(lanes) * nv) != 0) {
        free(b);
        return NULL;
    }
    memset(b, 0, sizeof(hpar_bws));
    memset(v, 0, sizeof(lanes) * nv);
    hpar_bws *B = b;
    B->m = m, B->s = s, B->block = v;
    lanes *p = v;
    size_t sm = (size_t)s * m;
    for (int k = 0; k < HPAR_NY; ++k) B->W.yr[k] = p, B->W.yi[k] = p + sm, p += 2 * sm;
    for (int k = 0; k < HPAR_NZ; ++k) B->W.zr[k] = p, B->W.zi[k] = p + sm, p += 2 * sm;
    B->W.pyr = p, B->W.pyi = p + sm, p += 2 * sm;
    B->W.mr = p, B->W.mi = p + sm * m;
    return B;
}

void kin__hpar_bws_free(hpar_bws *b)
{
    if (!b) return;
    free(b->block);
    free(b);
}

/* |v| of lane l of an m-vector, summed in order (as vnorm) */
static double lane_norm(int m, const lanes *vr, const lanes *vi, int l)
{
    double s = 0.0;
    for (int k = 0; k < m; ++k) s += vr[k][l] * vr[k][l] + vi[k][l] * vi[k][l];
    return sqrt(s);
}

static void copy_lane(int m, int l, const lanes *ar, const lanes *ai, lanes *br, lanes *bi)
{
    for (int c = 0; c < m; ++c) br[c][l] = ar[c][l], bi[c][l] = ai[c][l];
}

/* lane l's path ends at (vr, vi) lane l; the lane is then empty */
static void finish(hpar_bws *B, int l, const lanes *vr, const lanes *vi, const hpar_batch_sink *K)
{
    double xr[HOM_MAX_M], xi[HOM_MAX_M];
    for (int c = 0; c < B->m; ++c) xr[c] = vr[c][l], xi[c] = vi[c][l];
    K->done(K->ctx, B->L[l].id, xr, xi, &B->L[l].e);
    B->L[l].mode = LANE_EMPTY;
}

/* a break out of kin__hpar_track's step loop: lost at the current point */
static void lost(hpar_bws *B, int l, const hpar_batch_sink *K)
{
    B->L[l].e.sigma = 1.0 - B->L[l].t;
    finish(B, l, B->xr, B->xi, K);
}

/* the start of path id from x0 in lane l, as kin__hpar_track up to its
 * first corrector; 0 if the path ended at once */
static int start_lane(const hpar_problem *P, hpar_bws *B, int l, int id, const double *x0r, const double *x0i,
                      const hpar_batch_sink *K)
{
    int m = P->m;
    plane *L = &B->L[l];
    memset(L, 0, sizeof *L);
    L->id = id, L->mode = LANE_START, L->e.sigma = 1.0;
    double car[HOM_MAX_M], cai[HOM_MAX_M], sr = 0.0, si = 0.0, na = 0.0;
    memcpy(car, P->ar, sizeof car);
    memcpy(cai, P->ai, sizeof cai);
    for (int k = 0; k < m; ++k) na += car[k] * car[k] + cai[k] * cai[k];
    na = sqrt(na);
    for (int c = 0; c < m; ++c) sr += car[c] * x0r[c] - cai[c] * x0i[c], si += car[c] * x0i[c] + cai[c] * x0r[c];
    double d = sr * sr + si * si;
    if (!(d > 0.0)) {
        for (int c = 0; c < m; ++c) B->xr[c][l] = x0r[c], B->xi[c][l] = x0i[c];
        finish(B, l, B->xr, B->xi, K);
        return 0;
    }
    for (int c = 0; c < m; ++c) {
        B->xr[c][l] = (x0r[c] * sr + x0i[c] * si) / d, B->xi[c][l] = (x0i[c] * sr - x0r[c] * si) / d;
        B->car[c][l] = car[c], B->cai[c][l] = cai[c];
    }
    double nx0 = lane_norm(m, B->xr, B->xi, l);
    if (nx0 * na > HPAR_CHART_TILT * sqrt((double)m)) {
        for (int c = 0; c < m; ++c)
            B->car[c][l] = B->xr[c][l] / (nx0 * nx0), B->cai[c][l] = -B->xi[c][l] / (nx0 * nx0);
        na = 1.0 / nx0;
    }
    L->na = na, L->t = 0.0, L->hcap = INFINITY, L->it = 0, L->prev = INFINITY, L->calib = 1.0;
    copy_lane(m, l, B->xr, B->xi, B->pr, B->pi);
    return 1;
}

/* the top of kin__hpar_track's step loop for lane l (at its accepted point) */
static void top(const hpar_problem *P, const hpar_settings *S, hpar_bws *B, int l, const hpar_batch_sink *K)
{
    int m = P->m;
    plane *L = &B->L[l];
    if (!(1.0 - L->t > S->sigma_end)) { /* the end */
        L->e.sigma = 1.0 - L->t;
        if (S->sigma_end > 0.0) {
            L->e.ok = 1;
            finish(B, l, B->xr, B->xi, K);
            return;
        }
        L->mode = LANE_REFINE, L->it = 0;
        copy_lane(m, l, B->xr, B->xi, B->pr, B->pi);
        return;
    }
    double nx = lane_norm(m, B->xr, B->xi, l);
    L->sigma = 1.0 - L->t, L->nx = nx;
    if (L->e.steps + L->e.rejected >= HPAR_MAX_STEPS) {
        lost(B, l, K);
        return;
    }
    int fresh = L->e.steps == 0;
    if (nx * L->na > HPAR_CHART_TILT * sqrt((double)m)) {
        for (int c = 0; c < m; ++c) B->car[c][l] = B->xr[c][l] / (nx * nx), B->cai[c][l] = -B->xi[c][l] / (nx * nx);
        L->na = 1.0 / nx;
        fresh = 1;
    }
    if (fresh) {
        L->mode = LANE_FRESH;
        copy_lane(m, l, B->xr, B->xi, B->pr, B->pi);
    } else {
        L->mode = LANE_SERIES;
    }
}

/* an attempt at lane l's step L->h from its series: the prediction */
static void attempt(const hpar_problem *P, hpar_bws *B, int l, const hpar_batch_sink *K)
{
    plane *L = &B->L[l];
    if (L->h >= L->sigma) L->h = L->sigma;
    L->pade = kin__hpar_pade_attempt(&L->pd, L->first, L->hser, L->hcap, L->sigma, L->target, L->calib, &L->h,
                                     &L->pest);
    L->first = 0;
    if (L->h < HPAR_H_MIN) {
        lost(B, l, K);
        return;
    }
    double h = L->h;
    L->t1 = h == L->sigma ? 1.0 : L->t + h;
    if (L->pade) {
        double xr[HOM_MAX_M], xi[HOM_MAX_M];
        kin__hom_pade_predict(P->m, (const double(*)[HOM_MAX_M])B->pcr[l], (const double(*)[HOM_MAX_M])B->pci[l],
                              &L->pd, h, xr, xi);
        for (int c = 0; c < P->m; ++c) B->pr[c][l] = xr[c], B->pi[c][l] = xi[c];
    } else
    for (int c = 0; c < P->m; ++c) {
        double vr = B->cr[HPAR_ORDER][c][l], vi = B->ci[HPAR_ORDER][c][l];
        for (int k = HPAR_ORDER - 1; k >= 0; --k) vr = vr * h + B->cr[k][c][l], vi = vi * h + B->ci[k][c][l];
        B->pr[c][l] = vr, B->pi[c][l] = vi;
    }
    L->mode = LANE_STEP, L->it = 0, L->prev = INFINITY;
}

/* keep lane l's J factors (the last Newton iteration's) for its series */
static void keep_factors(int m, hpar_bws *B, int l)
{
    hom_llu *S = &B->ser;
    const hom_llu *W = &B->work;
    for (int k = 0; k < m * m; ++k) {
        S->r[k][l] = W->r[k][l], S->i[k][l] = W->i[k][l];
        S->lr[k][l] = W->lr[k][l], S->li[k][l] = W->li[k][l];
    }
    for (int k = 0; k < m; ++k) S->dr[k][l] = W->dr[k][l], S->di[k][l] = W->di[k][l], S->piv[k][l] = W->piv[k][l];
}

/* lane l's corrector iteration (as correct): 1 accepted, 0 rejected, -1 going on */
static int corrector(const hpar_settings *S, hpar_bws *B, int l, int ok, double nd, double nx)
{
    plane *L = &B->L[l];
    if (!ok) return 0;
    int it = L->it;
    int noise = nd <= HPAR_NOISE * nx ||
                (it > 0 && nd <= HPAR_NEWTON_TOL * nx && L->prev <= HPAR_STALL_TOL * nx);
    if (it == 0 && !(nd <= S->corr_rel * nx)) return 0;
    if (it > 0 && !noise && !(nd <= HPAR_CONTRACTION * L->prev)) return 0;
    for (int c = 0; c < B->m; ++c) B->pr[c][l] -= B->dr[c][l], B->pi[c][l] -= B->di[c][l];
    if (noise || (it > 0 && nd <= HPAR_NEWTON_TOL * nx)) return 1;
    L->prev = nd;
    return ++L->it < HPAR_NEWTON_MAX ? -1 : 0;
}

/* one Newton iteration for every lane that wants one, and its outcome */
static void newton_round(const hpar_problem *P, const hpar_settings *S, hpar_bws *B, const hpar_batch_sink *K)
{
    int m = P->m, ok[BL];
    for (int l = 0; l < BL; ++l) {
        int md = B->L[l].mode;
        B->tv[l] = md == LANE_STEP ? B->L[l].t1 : md == LANE_FRESH || md == LANE_REFINE ? B->L[l].t : 0.0;
    }
    kin__plan_newton(P, &B->tv, B->car, B->cai, B->pr, B->pi, &B->W, &B->work, B->dr, B->di, ok);
    double nd[BL], nx[BL];
    kin__lanes_norm2(m, B->dr, B->di, nd);
    kin__lanes_norm2(m, B->pr, B->pi, nx);
    for (int l = 0; l < BL; ++l) {
        plane *L = &B->L[l];
        int r;
        switch (L->mode) {
        case LANE_START:
            if ((r = corrector(S, B, l, ok[l], nd[l], nx[l])) < 0) break;
            copy_lane(m, l, B->pr, B->pi, B->xr, B->xi);
            if (r) top(P, S, B, l, K);
            else finish(B, l, B->xr, B->xi, K);
            break;
        case LANE_FRESH:
            if (!ok[l]) {
                lost(B, l, K);
                break;
            }
            keep_factors(m, B, l);
            L->mode = LANE_SERIES;
            break;
        case LANE_STEP:
            if (L->it == 0 && L->pade) L->calib = kin__hpar_pade_calibrate(L->calib, L->pest, ok[l] ? nd[l] : 0.0);
            if ((r = corrector(S, B, l, ok[l], nd[l], nx[l])) < 0) break;
            if (r) {
                copy_lane(m, l, B->pr, B->pi, B->xr, B->xi);
                L->t = L->t1;
                L->hcap = L->h * HPAR_ACCEPT_GROW;
                L->e.steps++;
                L->e.pade += L->pade;
                keep_factors(m, B, l);
                top(P, S, B, l, K);
            } else {
                L->e.rejected++;
                L->e.pade_rejected += L->pade;
                L->h *= HPAR_REJECT_SHRINK;
                L->hcap = L->h;
                if (L->e.steps + L->e.rejected >= HPAR_MAX_STEPS) lost(B, l, K);
                else attempt(P, B, l, K);
            }
            break;
        case LANE_REFINE:
            if (!ok[l]) {
                finish(B, l, B->xr, B->xi, K);
                break;
            }
            for (int c = 0; c < m; ++c) B->xr[c][l] -= B->dr[c][l], B->xi[c][l] -= B->di[c][l];
            copy_lane(m, l, B->xr, B->xi, B->pr, B->pi);
            if (nd[l] <= HPAR_REFINE_TOL * nx[l]) {
                L->e.ok = 1;
                finish(B, l, B->xr, B->xi, K);
            } else if (++L->it >= HPAR_REFINE_MAX) {
                finish(B, l, B->xr, B->xi, K);
            }
            break;
        default:
            break;
        }
    }
}

/* the series of every lane (all waiting for it or empty) and each waiting
 * lane's first attempt at its step */
static void series_round(const hpar_problem *P, const hpar_settings *S, hpar_bws *B, const hpar_batch_sink *K)
{
    int m = P->m;
    for (int l = 0; l < BL; ++l) B->tv[l] = B->L[l].mode == LANE_SERIES ? B->L[l].t : 0.0;
    memcpy(B->cr[0], B->xr, sizeof(lanes) * (size_t)m);
    memcpy(B->ci[0], B->xi, sizeof(lanes) * (size_t)m);
    kin__plan_taylor(P, &B->tv, &B->ser, &B->W, B->cr, B->ci);
    double n[HPAR_ORDER + 1][BL];
    for (int k = 1; k <= HPAR_ORDER; ++k) kin__lanes_norm2(m, B->cr[k], B->ci[k], n[k]);
    for (int l = 0; l < BL; ++l) {
        plane *L = &B->L[l];
        if (L->mode != LANE_SERIES) continue;
        double nl[HPAR_ORDER + 1];
        for (int k = 1; k <= HPAR_ORDER; ++k) nl[k] = n[k][l];
        L->target = S->pred_rel * L->nx;
        L->hser = kin__hpar_series_step(nl, L->target);
        L->h = fmin(L->hser, L->hcap);
        for (int k = 0; k <= HPAR_ORDER; ++k) /* the lane's series (the same every attempt until accepted) */
            for (int c = 0; c < m; ++c) B->pcr[l][k][c] = B->cr[k][c][l], B->pci[l][k][c] = B->ci[k][c][l];
        kin__hom_pade_setup_order(HPAR_ORDER, m, (const double(*)[HOM_MAX_M])B->pcr[l],
                                  (const double(*)[HOM_MAX_M])B->pci[l], &L->pd);
        L->first = 1;
        attempt(P, B, l, K);
    }
}

void kin__hpar_track_batch(const hpar_problem *P, const hpar_settings *S, hpar_bws *B, const hpar_batch_sink *K)
{
    int drained = 0;
    for (int l = 0; l < BL; ++l) B->L[l].mode = LANE_EMPTY;
    for (;;) {
        double x0r[HOM_MAX_M], x0i[HOM_MAX_M];
        for (int l = 0; l < BL; ++l)
            while (B->L[l].mode == LANE_EMPTY && !drained) {
                int id = K->next(K->ctx, x0r, x0i);
                if (id == HPAR_BATCH_STOP) return; /* cancelled: abandon the lanes' paths */
                if (id < 0) drained = 1;
                else start_lane(P, B, l, id, x0r, x0i, K);
            }
        int newton = 0, series = 0;
        for (int l = 0; l < BL; ++l) {
            int md = B->L[l].mode;
            newton |= md >= LANE_START, series |= md == LANE_SERIES;
        }
        if (newton) newton_round(P, S, B, K);
        else if (series) series_round(P, S, B, K);
        else if (drained) return;
    }
}

#else /* other compilers: one path at a time with the reference tracker */

struct hpar_bws {
    hpar_ws *w;
};
hpar_bws *kin__hpar_bws_new(int m, int s)
{
    hpar_bws *b = malloc(sizeof *b);
    if (!b) return NULL;
    if (!(b->w = kin__hpar_ws_new(m, s))) {
        free(b);
        return NULL;
    }
    return b;
}
void kin__hpar_bws_free(hpar_bws *b)
{
    if (!b) return;
    kin__hpar_ws_free(b->w);
    free(b);
}

void kin__hpar_track_batch(const hpar_problem *P, const hpar_settings *S, hpar_bws *B, const hpar_batch_sink *K)
{
    double x0r[HOM_MAX_M], x0i[HOM_MAX_M], xr[HOM_MAX_M], xi[HOM_MAX_M];
    for (;;) {
        int id = K->next(K->ctx, x0r, x0i);
        if (id < 0) return;
        hpar_end e;
        memcpy(xr, x0r, sizeof xr), memcpy(xi, x0i, sizeof xi);
        kin__hpar_track(P, S, B->w, x0r, x0i, xr, xi, &e);
        K->done(K->ctx, id, xr, xi, &e);
    }
}

#endif
