/* The interval certificates of a solve's endpoints (issue 38): every
 * endpoint the tracker did not lose is proven by certify/'s Krawczyk test
 * on the caller's system (not the scaled copy the tracker follows, nor the
 * equivariant route's rotated one: its endpoints are mapped back by U
 * first), on the solver's threads, each thread with its own Arb workspace;
 * then the proven boxes are shown pairwise disjoint and counted into
 * kin_homotopy_info's proven_* fields. Each endpoint's proof depends on
 * that endpoint alone, so the counts are the same for any thread count. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/certify/homotopy_prove.h"
#include "homotopy/solver/homotopy_pool.h"
#include "homotopy/solver/homotopy_solver.h"
#include "model/internal.h"

/* endpoints per take from the pool: a proof costs ~0.1 ms */
enum { PROVE_CHUNK = 16 };

typedef struct prove_job {
    const hom_solver *H;
    const hom_end *ends;
    double *zr, *zi;
    hom_proof *proof;
    hom_prover **w;
    hom_report *R; /* NULL: no progress calls (no cancel) */
    double last;
} prove_job;

/* an endpoint with a point to test: not lost, and if singular, Newton converged
 * (a box cannot hold a root that is not simple alone) */
static int tested(const hom_end *e) { return e->kind != HOM_FAILED && !(e->kind == HOM_SINGULAR && !e->converged); }

static void prove_one(const prove_job *J, hom_prover *w, int p)
{
    const hom_solver *H = J->H;
    const hom_end *e = &J->ends[p];
    int m = H->P.m;
    double *zr = J->zr + (size_t)p * m, *zi = J->zi + (size_t)p * m;
    memset(&J->proof[p], 0, sizeof J->proof[p]);
    if (!tested(e)) return;
    if (H->U) { /* the equivariant route's x to the caller's beta = U x */
        double yr[HOM_MAX_M], yi[HOM_MAX_M];
        for (int r = 0; r < m; ++r) {
            double vr = 0.0, vi = 0.0;
            for (int c = 0; c < m; ++c) vr += H->U[c * m + r] * zr[c], vi += H->U[c * m + r] * zi[c];
            yr[r] = vr, yi[r] = vi;
        }
        memcpy(zr, yr, sizeof yr[0] * (size_t)m);
        memcpy(zi, yi, sizeof yi[0] * (size_t)m);
    }
    kin__prove_endpoint(w, zr, zi, e->kind == HOM_REAL, 256, &J->proof[p]);
}

static void prove_work(void *ctx, int t)
{
    prove_job *J = ctx;
    int first, k;
    while ((k = kin__hom_pool_take(J->H->pool, PROVE_CHUNK, &first)) > 0)
        for (int p = first; p < first + k; ++p) {
            prove_one(J, J->w[t], p);
            if (kin__hom_pool_done(J->H->pool, t)) goto end;
        }
end:
    kin__prove_thread_end();
}

/* the caller's cancel, asked every HOM_POOL_REPORT seconds (the counts it
 * is told stay those of the finished tracking) */
static int prove_progress(void *ctx, long done)
{
    prove_job *J = ctx;
    (void)done;
    double now = kin__hom_seconds();
    if (now - J->last < HOM_POOL_REPORT) return 0;
    J->last = now;
    if (J->R->fn(J->R->user, J->R->total, J->R->total)) J->R->cancelled = 1;
    return J->R->cancelled;
}

/* count the proven boxes into info (clash: boxes not shown disjoint) */
static void count(int npaths, const hom_end *ends, const hom_proof *proof, const unsigned char *clash,
                  kin_homotopy_info *info)
{
    info->proven_real = info->proven_nonreal = info->proven_refined = info->proven_overlap = 0;
    info->unproven_nopoint = info->unproven_refused = 0;
    for (int p = 0; p < npaths; ++p) {
        if (proof[p].kind == HOM_PROOF_NONE) {
            if (!tested(&ends[p])) info->unproven_nopoint++;
            else info->unproven_refused++;
            continue;
        }
        if (clash[p]) {
            info->proven_overlap++;
            continue;
        }
        if (proof[p].kind == HOM_PROOF_REAL) info->proven_real++;
        else info->proven_nonreal++;
        if (proof[p].prec > 53) info->proven_refined++;
    }
    info->unproven = npaths - info->proven_real - info->proven_nonreal;
    info->proven_all = info->unproven == 0;
}

int kin__hom_prove(const hom_solver *H, const hom_end *ends, double *zr, double *zi, hom_report *R,
                   kin_homotopy_info *info)
{
    int npaths = H->npaths, m = H->P.m, nt = H->nthreads, rc = KIN_OK;
    if (!H->prove) return KIN_OK;
    hom_proof *proof = malloc(sizeof *proof * (size_t)npaths);
    unsigned char *clash = malloc((size_t)npaths);
    hom_prover **w = calloc((size_t)nt, sizeof *w);
    if (!proof || !clash || !w) rc = KIN_ENOMEM;
    for (int t = 0; !rc && t < nt; ++t)
        if (!(w[t] = kin__prove_new(m, H->P.s, H->Qin))) rc = KIN_ENOMEM;
        else kin__prove_use_fast(w[t], H->prove != 2);
    if (!rc) {
        prove_job J = {H, ends, zr, zi, proof, w, R, kin__hom_seconds()};
        hom_pool_job W = {prove_work, R && R->fn ? prove_progress : NULL, &J};
        kin__hom_pool_run(H->pool, npaths, &W);
        if (R && R->cancelled) rc = KIN_ECANCELLED;
    }
    if (!rc && kin__prove_disjoint(m, npaths, zr, zi, proof, H->w, clash) < 0) rc = KIN_ENOMEM;
    if (!rc) count(npaths, ends, proof, clash, info);
    for (int t = 0; w && t < nt; ++t) kin__prove_free(w[t]);
    free(w), free(clash), free(proof);
    return rc;
}
