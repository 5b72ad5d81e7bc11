/* Lockstep tracking: HOM_BATCH paths of the complete solver at once, one
 * path per lane, with the kernels of homotopy_lanes.c.
 *
 * Each lane follows its path through exactly the operations of the
 * one-path tracker kin__hom_track (homotopy_track.c, the reference: same
 * predictor, corrector, acceptance tests, charts and certificate, every sum
 * in the same order), so a path's endpoint, step counts and class are bit
 * for bit those of the one-path tracker, whatever other paths share its
 * batch (tests/test_homotopy_batch.c).
 *
 * Rounds: almost every step is the same sequence (Taylor series at the base
 * point, predictor (Taylor or rational, homotopy_pade.c, per lane), two
 * Newton iterations, accept; on the hexagonal sail's flat state 1 % of the
 * steps are rejected and 0.01 % need a third Newton iteration), so all lanes
 * go through one round per step: the series for every lane, then the Newton
 * iterations while any lane still iterates. A lane whose step is rejected
 * repeats the round with half the step (its series is recomputed from the
 * same base point, bit for bit the same); a third Newton iteration runs for
 * all lanes, the others' results discarded. A lane whose path ends is
 * certified (one path, kin__hom_certify) and takes the next path from the
 * sink; its start point (and a lane's change of chart) gets the base-point
 * evaluation before the round's series.
 *
 * Base and trial points: the round's Newton iterations write the trial
 * slot; when some lanes accept, the others' base points are copied into the
 * trial slot and the slots swap. */
#define _POSIX_C_SOURCE 200112L /* posix_memalign */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/track/homotopy_lanes.h"

#if defined(HOM_LANES_VECTOR)

/* what a lane is doing */
enum { LANE_EMPTY = 0, LANE_START, LANE_RECHART, LANE_TOP, LANE_RETRY };

typedef struct blane {
    int state, path;
    hom_end e;
    double t, rsep, hcap, calib, na, h, t1, rho, tail, prevd;
    double hser, target, calibp, pest; /* the rational predictor's step control, as in kin__hom_track */
    hom_pade pd;
    int first, pade;
    int it_ok; /* Newton: 0 iterating, 1 accepted, -1 rejected */
} blane;

struct hom_bws {
    hom_lpoint pt[2];
    hom_lpoint *base, *trial;
    lanes xr[HOM_MAX_M], xi[HOM_MAX_M];   /* each lane's current point (x in kin__hom_track) */
    lanes dr[HOM_MAX_M], di[HOM_MAX_M];   /* Newton's corrections */
    lanes car[HOM_MAX_M], cai[HOM_MAX_M]; /* each lane's chart */
    hom_lseries T;                        /* the series at the base points */
    double pcr[BL][HOM_ORDER + 1][HOM_MAX_M], pci[BL][HOM_ORDER + 1][HOM_MAX_M]; /* each lane's series */
    lanes tv;                             /* each lane's t for the kernels */
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

/* ---- lanes ---- */

/* copy lane l of point a into point b */
static void copy_lane(int m, int rows, int l, const hom_lpoint *a, hom_lpoint *b)
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
    L->calibp = 1.0;
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
    int m = P->m, rows = kin__hom_srows(m, P->s);
    for (;;) {
        int any = 0;
        for (int l = 0; l < BL; ++l) any |= B->L[l].state == LANE_START || B->L[l].state == LANE_RECHART;
        if (!any) return;
        hom_lpoint *p = B->trial;
        memcpy(p->xr, B->xr, sizeof(lanes) * (size_t)m);
        memcpy(p->xi, B->xi, sizeof(lanes) * (size_t)m);
        for (int l = 0; l < BL; ++l) B->tv[l] = B->L[l].state == LANE_EMPTY ? 0.0 : B->L[l].t;
        int ok[BL];
        double inv[BL];
        kin__lanes_newton(P, &B->tv, B->car, B->cai, p, B->dr, B->di, ok);
        kin__lanes_inv_norm1(m, &p->lu, inv);
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
    int m = P->m, rows = kin__hom_srows(m, P->s), drained = 0;
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
            for (int l = 0; l < BL; ++l) B->T.cr[0][c][l] = B->xr[c][l], B->T.ci[0][c][l] = B->xi[c][l];
        for (int l = 0; l < BL; ++l) B->tv[l] = B->L[l].state == LANE_EMPTY ? 1.0 : B->L[l].t;
        kin__lanes_taylor(P, &B->tv, B->base, &B->T);
        /* each lane's step and prediction */
        hom_lpoint *p = B->trial;
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
                    for (int c = 0; c < m; ++c) s2 += B->T.cr[k][c][l] * B->T.cr[k][c][l] + B->T.ci[k][c][l] * B->T.ci[k][c][l];
                    n[k] = sqrt(s2);
                }
                for (int c = 0; c < m; ++c) nx += B->xr[c][l] * B->xr[c][l] + B->xi[c][l] * B->xi[c][l];
                nx = sqrt(nx);
                double target = fmin(S->pred_rel * nx, S->pred_sep * L->rsep);
                double hser = kin__hom_series_step(n, target / L->calib, &L->rho, &L->tail);
                L->h = fmin(hser, L->hcap);
                L->hser = hser, L->target = target;
                L->first = 1;
                L->state = LANE_RETRY;
            }
            /* the lane's series (the same every round until accepted) */
            for (int k = 0; k <= HOM_ORDER; ++k)
                for (int c = 0; c < m; ++c) B->pcr[l][k][c] = B->T.cr[k][c][l], B->pci[l][k][c] = B->T.ci[k][c][l];
            const double(*lcr)[HOM_MAX_M] = (const double(*)[HOM_MAX_M])B->pcr[l];
            const double(*lci)[HOM_MAX_M] = (const double(*)[HOM_MAX_M])B->pci[l];
            if (L->first) kin__hom_pade_setup(m, lcr, lci, &L->pd);
            if (L->h >= sigma) L->h = sigma;
            /* the rational predictor, as in kin__hom_track */
            L->pest = kin__hom_pade_error(&L->pd, L->h);
            L->pade = L->pest <= L->target / L->calibp;
            if (L->pade && L->first)
                L->h = kin__hom_pade_extend(&L->pd, L->h, fmin(PADE_REACH * L->hser, L->hcap), sigma,
                                            L->target / L->calibp, &L->pest);
            L->first = 0;
            if (L->h < H_MIN) {
                finish_lane(P, B, w, l, 1, 1, K);
                B->tv[l] = 0.0;
                for (int c = 0; c < m; ++c) p->xr[c][l] = p->xi[c][l] = 0.0;
                continue;
            }
            L->t1 = L->h == sigma ? 1.0 : L->t + L->h;
            B->tv[l] = L->t1;
            double h = L->h;
            if (L->pade) {
                double xr[HOM_MAX_M], xi[HOM_MAX_M];
                kin__hom_pade_predict(m, lcr, lci, &L->pd, h, xr, xi);
                for (int c = 0; c < m; ++c) p->xr[c][l] = xr[c], p->xi[c][l] = xi[c];
            } else
            for (int c = 0; c < m; ++c) { /* the predictor, as predict */
                double vr = B->T.cr[HOM_ORDER][c][l], vi = B->T.ci[HOM_ORDER][c][l];
                for (int k = HOM_ORDER - 1; k >= 0; --k) {
                    vr = vr * h + B->T.cr[k][c][l];
                    vi = vi * h + B->T.ci[k][c][l];
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
            kin__lanes_newton(P, &B->tv, B->car, B->cai, p, B->dr, B->di, ok);
            if (it == 0) kin__lanes_inv_norm1(m, &p->lu, inv);
            kin__lanes_norm2(m, B->dr, B->di, nd);
            kin__lanes_norm2(m, p->xr, p->xi, np);
            for (int l = 0; l < BL; ++l) {
                blane *L = &B->L[l];
                if (!in[l] || L->it_ok != 0) continue;
                if (!ok[l]) {
                    L->it_ok = -1;
                    continue;
                }
                double tol = fmax(NEWTON_TOL, NOISE_FACTOR * DBL_EPSILON * np[l] / L->rsep) * np[l];
                if (it == 0) {
                    double est = L->pade ? L->pest : kin__hom_series_error(L->rho, L->tail, L->h);
                    if (est > 0.0 && nd[l] > 0.0) {
                        double *cal = L->pade ? &L->calibp : &L->calib;
                        *cal = fmin(CALIB_MAX, fmax(CALIB_MIN, sqrt(*cal * nd[l] / est)));
                    }
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
