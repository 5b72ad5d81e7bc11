/* kin_quadrics_homotopy_sym's monodromy route (homotopy_sym_route.c picks the
 * route): the complete solver for a system with a
 * symmetry group G acting on beta by orthogonal R_g, q(R_g b) = S_g q(b).
 *
 * Every member P of the linear family E = {P : q_P(R_g b) = S_g q_P(b)} is
 * equivariant, so along any path of systems inside E the group maps paths
 * of roots to paths of roots: tracking one root per orbit is enough. The
 * roots of a random complex start system P0 in E are found by monodromy:
 * three random complex members P0, P1, P2 of E (Reynolds projections of
 * random systems; P0 corrected so that a random point is a root) joined by
 * straight segments, each direction from P_a to gamma P_b with its own
 * random complex gamma (P_b and gamma P_b have the same roots; without it
 * a segment and its way back would cancel); every root known at P0 (one
 * per orbit) goes once round the loops P0 -> P1 -> P0 and P0 -> P2 -> P0,
 * a new endpoint adds its whole orbit to the node it reached, until P0 has
 * 2^s roots (Bezout's count: Q, a member of the closure of E, has 2^s when
 * its roots are isolated, and so has the generic member). Loop paths may
 * jump without harm: a landed point counts only once Newton has converged
 * to a root of the node's system, and roots are kept in hashed sets. Then
 * each orbit's representative is tracked from P0 to Q, its endpoint's
 * images under the group give the other endpoints, and all 2^s are refined
 * and certified on Q with the certificate and checks of the plain solver
 * (homotopy_track.c, homotopy_merge.c). Representatives of suspect
 * endpoints (failed, duplicate, unpaired) are tracked again with tighter
 * settings.
 *
 * The batches of paths are tracked on the solver's thread pool
 * (homotopy_pool.c), each worker four paths at a time in lockstep (homotopy_param_batch.c: every path bit for bit as the one-path
 * tracker follows it); results are stored by index and processed in order,
 * so the result does not depend on the thread count or on which paths
 * share a batch. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/solver/homotopy_pool.h"
#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"

enum { RETRACK_ROUNDS = 3, BUDGET_PER_ORBIT = 40, BUDGET_EXTRA = 1000 };
/* Loops: loose (a jump only wastes a path). The leg to Q: tighter; a jump
 * there lands on a root another path reaches too (every root of Q is
 * reached by exactly one orbit's path when all are simple), which the
 * duplicate check sees and a re-track with tighter settings repairs. */
static const hpar_settings LOOP_SETTINGS = {1e-3, 1e-2, 0.0};
static const hpar_settings FINAL_SETTINGS = {1e-4, 3e-3, 1e-10};
static const double TIGHTEN = 0.1, SIGMA_TIGHTEN = 0.01;

enum { JOB_LOOP, JOB_FINAL, JOB_CERT };


typedef struct sym_batch {
    sym_ctx *C;
    int kind, n;
    const int *items;          /* point indices (node `from`, or node 0) */
    int from;                  /* JOB_LOOP: source node */
    const hpar_problem *P;
    const hpar_settings *S;
    double *xr, *xi;           /* outputs, m per item */
    const double *inr, *ini;   /* JOB_CERT inputs, m per item */
    hpar_end *pe;
    hom_end *he;
} sym_batch;

static void report(sym_ctx *C, long done, int force)
{
    if (!C->fn || C->cancelled) return;
    double t = kin__hom_seconds();
    if (!force && t - C->last < HOM_POOL_REPORT) return;
    C->last = t;
    if (C->fn(C->user, (double)done, (double)(done + C->queued))) C->cancelled = 1;
}

/* the certified endpoint of a path of the leg to Q (item i, tracked into
 * B->xr, B->pe) */
static void final_item(sym_batch *B, int t, int i)
{
    sym_ctx *C = B->C;
    int m = C->m;
    double *xr = B->xr + (size_t)i * m, *xi = B->xi + (size_t)i * m;
    hom_end *e = &B->he[i];
    memset(e, 0, sizeof *e);
    e->kind = HOM_FAILED;
    e->rminus = e->rplus = e->cond = INFINITY;
    if (B->pe[i].ok) {
        double zr[HOM_MAX_M], zi[HOM_MAX_M];
        kin__hom_certify(&C->H.P, kin__hom_pool_ws(&C->H, t), xr, xi, zr, zi, e);
        memcpy(xr, zr, sizeof(double) * (size_t)m);
        memcpy(xi, zi, sizeof(double) * (size_t)m);
    }
    e->steps = B->pe[i].steps, e->rejected = B->pe[i].rejected, e->sigma = B->pe[i].sigma;
}

/* the paths of a batch go through the lockstep tracker
 * (homotopy_param_batch.c) of each worker: items handed out in order by the
 * pool, endpoints stored by index */
typedef struct sym_sink {
    sym_batch *B;
    int t;
} sym_sink;

static int sink_next(void *ctx, double *x0r, double *x0i)
{
    sym_sink *k = ctx;
    sym_batch *B = k->B;
    int i, got = kin__hom_pool_take(B->C->H.pool, 1, &i);
    if (got < 0) return HPAR_BATCH_STOP;
    if (got == 0) return -1;
    int m = B->C->m, p = B->items[i];
    const sym_set *S = &B->C->set[B->kind == JOB_LOOP ? B->from : 0];
    memcpy(x0r, S->xr + (size_t)p * m, sizeof(double) * (size_t)m);
    memcpy(x0i, S->xi + (size_t)p * m, sizeof(double) * (size_t)m);
    return i;
}

static void sink_done(void *ctx, int i, const double *xr, const double *xi, const hpar_end *e)
{
    sym_sink *k = ctx;
    sym_batch *B = k->B;
    int m = B->C->m;
    memcpy(B->xr + (size_t)i * m, xr, sizeof(double) * (size_t)m);
    memcpy(B->xi + (size_t)i * m, xi, sizeof(double) * (size_t)m);
    B->pe[i] = *e;
    if (B->kind == JOB_FINAL) final_item(B, k->t, i);
    kin__hom_pool_done(B->C->H.pool, k->t);
}

/* worker t's share of the batch */
static void batch_work(void *ctx, int t)
{
    sym_batch *B = ctx;
    sym_ctx *C = B->C;
    if (B->kind != JOB_CERT) {
        sym_sink k = {B, t};
        hpar_batch_sink K = {&k, sink_next, sink_done};
        kin__hpar_track_batch(B->P, B->S, C->pb[t], &K);
        return;
    }
    int m = C->m, i;
    while (kin__hom_pool_take(C->H.pool, 1, &i) > 0) {
        memset(&B->he[i], 0, sizeof B->he[i]);
        kin__hom_certify(&C->H.P, kin__hom_pool_ws(&C->H, t), B->inr + (size_t)i * m, B->ini + (size_t)i * m,
                         B->xr + (size_t)i * m, B->xi + (size_t)i * m, &B->he[i]);
        kin__hom_pool_done(C->H.pool, t);
    }
}

/* the calling thread's progress reports (the loops and the leg to Q; the
 * certificates are not counted) */
static int batch_progress(void *ctx, long done)
{
    sym_batch *B = ctx;
    report(B->C, B->C->done + done, 0);
    return B->C->cancelled;
}

/* run the batch on the solver's thread pool; KIN_OK or KIN_ECANCELLED */
static int run(sym_batch *B)
{
    sym_ctx *C = B->C;
    hom_pool_job J = {batch_work, B->kind != JOB_CERT && C->fn ? batch_progress : NULL, B};
    long finished = kin__hom_pool_run(C->H.pool, B->n, &J);
    if (B->kind != JOB_CERT) C->done += finished;
    return C->cancelled ? KIN_ECANCELLED : KIN_OK;
}

/* ---- monodromy ---- */


/* the edge systems: edge a -> b goes from P_a to gamma_ab P_b (the same
 * roots as P_b) with a random gamma_ab of modulus 1 for each direction, so
 * that going there and back is a loop too */
static void set_edges(sym_ctx *C)
{
    size_t ns = C->nsys;
    for (int a = 0; a < NODES; ++a)
        for (int b = 0; b < NODES; ++b) {
            if (a == b) continue;
            double th = 6.283185307179586 * kin__sym_uniform(&C->st), gr = cos(th), gi = sin(th);
            const double *pr = C->sys[b][0], *pi = C->sys[b][1];
            for (size_t i = 0; i < ns; ++i) {
                C->dif[a][b][0][i] = gr * pr[i] - gi * pi[i] - C->sys[a][0][i];
                C->dif[a][b][1][i] = gr * pi[i] + gi * pr[i] - C->sys[a][1][i];
            }
        }
}

/* a new root at `node` waits for its loops: from node 0 out along both
 * edges, from nodes 1 and 2 back to node 0 only (loops 0 -> 1 -> 0 and
 * 0 -> 2 -> 0; the edges between 1 and 2 would fill nodes 1 and 2 with
 * roots, work that brings nothing to node 0) */
static void enqueue(sym_ctx *C, int node, int p)
{
    for (int e = 0; e < 2; ++e)
        if (node == 0 || (node + 1 + e) % NODES == 0) C->queue[node][e][C->nq[node][e]++] = p, C->queued++;
}

/* new random nodes 1 and 2 with empty sets; node 0's roots queued again */
static void new_helpers(sym_ctx *C)
{
    for (int a = 1; a < NODES; ++a) {
        kin__sym_random_member(C, &C->st, C->tmp[0], C->tmp[1], C->sys[a][0], C->sys[a][1]);
        sym_set *S = &C->set[a];
        S->n = 0;
        for (int i = 0; i < S->hsize; ++i) S->head[i] = -1;
    }
    set_edges(C);
    C->queued = 0;
    for (int a = 0; a < NODES; ++a) C->nq[a][0] = C->nq[a][1] = 0;
    for (int p = 0; p < C->set[0].n; ++p)
        if (C->set[0].rep[p] == p) enqueue(C, 0, p);
}

/* Fill node 0 with all 2^s roots. KIN_OK, KIN_ENOTCONVERGED (budget
 * spent or no path left to track), KIN_ECANCELLED, KIN_ENOMEM. */
static int monodromy(sym_ctx *C, long *paths)
{
    int m = C->m, N = C->N, rc = KIN_OK;
    long budget = (long)BUDGET_PER_ORBIT * N / C->G.n + BUDGET_EXTRA;
    int *items = malloc(sizeof(int) * (size_t)N);
    double *xr = malloc(sizeof(double) * (size_t)N * m), *xi = malloc(sizeof(double) * (size_t)N * m);
    hpar_end *pe = malloc(sizeof(hpar_end) * (size_t)N);
    if (!items || !xr || !xi || !pe) {
        rc = KIN_ENOMEM;
        goto done;
    }
    while (C->set[0].n < N) {
        int a = -1, e = 0, best = 0; /* the fullest queue, edges back to node 0 first */
        for (int na = 0; na < NODES; ++na)
            for (int ne = 0; ne < 2; ++ne) {
                int into0 = (na + 1 + ne) % NODES == 0;
                int q = C->nq[na][ne] + (into0 ? N : 0);
                if (C->nq[na][ne] > 0 && q > best) best = q, a = na, e = ne;
            }
        if (a < 0 && *paths < budget) {
            /* every known root has been round every loop of the graph: the
             * loops' permutations keep the missing roots apart; draw new
             * nodes 1 and 2 (new loops) and start again from node 0's roots */
            new_helpers(C);
            continue;
        }
        if (a < 0 || *paths >= budget) {
            rc = KIN_ENOTCONVERGED;
            break;
        }
        int b = (a + 1 + e) % NODES, n = C->nq[a][e];
        if (*paths + n > budget) n = (int)(budget - *paths);
        memcpy(items, C->queue[a][e] + (C->nq[a][e] - n), sizeof(int) * (size_t)n);
        C->nq[a][e] -= n;
        C->queued -= n;
        hpar_problem P = {m, C->s, C->sys[a][0], C->sys[a][1], C->dif[a][b][0], C->dif[a][b][1], {0}, {0}};
        memcpy(P.ar, C->ar, sizeof P.ar);
        memcpy(P.ai, C->ai, sizeof P.ai);
        sym_batch B = {.C = C, .kind = JOB_LOOP, .n = n, .items = items, .from = a, .P = &P, .S = &LOOP_SETTINGS,
                       .xr = xr, .xi = xi, .pe = pe};
        if ((rc = run(&B))) break;
        *paths += n;
        for (int i = 0; i < n; ++i) C->lsteps += pe[i].steps, C->lrej += pe[i].rejected;
        for (int i = 0; i < n; ++i) {
            const double *yr = xr + (size_t)i * m, *yi = xi + (size_t)i * m;
            if (!pe[i].ok || kin__sym_set_find(&C->set[b], yr, yi) >= 0) continue;
            int r = kin__sym_set_add_orbit(&C->set[b], &C->G, yr, yi);
            if (r >= 0) enqueue(C, b, r);
        }
    }
done:
    free(items), free(xr), free(xi), free(pe);
    return rc;
}

/* ---- the leg to Q and the orbits' expansion ---- */

/* Track the representatives reps[0..n-1] (node 0 indices) to Q with the
 * settings S and put every point of their orbits into the endpoint set
 * (index = node 0 index): the representative's certified endpoint, the
 * others certified from its images. */
static int final_leg(sym_ctx *C, const int *reps, int n, const hpar_settings *S, hom_endset *E, long *paths)
{
    int m = C->m, N = C->N, rc = KIN_OK;
    const sym_set *Z = &C->set[0];
    double *xr = malloc(sizeof(double) * (size_t)N * m), *xi = malloc(sizeof(double) * (size_t)N * m);
    double *yr = malloc(sizeof(double) * (size_t)N * m), *yi = malloc(sizeof(double) * (size_t)N * m);
    hpar_end *pe = malloc(sizeof(hpar_end) * (size_t)n);
    hom_end *he = malloc(sizeof(hom_end) * (size_t)N);
    int *where = malloc(sizeof(int) * (size_t)N), *img = malloc(sizeof(int) * (size_t)N);
    if (!xr || !xi || !yr || !yi || !pe || !he || !where || !img) {
        rc = KIN_ENOMEM;
        goto done;
    }
    hpar_problem P = {m, C->s, C->sys[0][0], C->sys[0][1], C->dq[0], C->dq[1], {0}, {0}};
    memcpy(P.ar, C->ar, sizeof P.ar);
    memcpy(P.ai, C->ai, sizeof P.ai);
    sym_batch B = {.C = C, .kind = JOB_FINAL, .n = n, .items = reps, .P = &P, .S = S, .xr = xr, .xi = xi,
                   .pe = pe, .he = he};
    if ((rc = run(&B))) goto done;
    *paths += n;
    for (int p = 0; p < N; ++p) where[p] = -1;
    for (int i = 0; i < n; ++i) where[reps[i]] = i;
    /* the representatives' endpoints; the other orbit points: images of
     * certified endpoints to certify, copies of the others */
    int ni = 0;
    for (int p = 0; p < N; ++p) {
        int r = Z->rep[p], i = where[r];
        if (i < 0) continue;
        double *zr = E->zr + (size_t)p * m, *zi = E->zi + (size_t)p * m;
        const double *sr = xr + (size_t)i * m, *si = xi + (size_t)i * m;
        if (p == r) {
            E->ends[p] = he[i];
            memcpy(zr, sr, sizeof(double) * (size_t)m), memcpy(zi, si, sizeof(double) * (size_t)m);
            continue;
        }
        kin__sym_apply(&C->G, Z->elem[p], sr, si, zr, zi);
        E->ends[p] = he[i];
        E->ends[p].steps = E->ends[p].rejected = 0;
        if (he[i].kind == HOM_REAL || he[i].kind == HOM_NONREAL) {
            memcpy(yr + (size_t)ni * m, zr, sizeof(double) * (size_t)m);
            memcpy(yi + (size_t)ni * m, zi, sizeof(double) * (size_t)m);
            img[ni++] = p;
        }
    }
    sym_batch Bc = {.C = C, .kind = JOB_CERT, .n = ni, .inr = yr, .ini = yi, .xr = xr, .xi = xi, .he = he};
    if (ni > 0 && (rc = run(&Bc))) goto done;
    for (int k = 0; k < ni; ++k) {
        int p = img[k];
        he[k].steps = he[k].rejected = 0;
        he[k].sigma = E->ends[p].sigma;
        E->ends[p] = he[k];
        memcpy(E->zr + (size_t)p * m, xr + (size_t)k * m, sizeof(double) * (size_t)m);
        memcpy(E->zi + (size_t)p * m, xi + (size_t)k * m, sizeof(double) * (size_t)m);
    }
done:
    free(xr), free(xi), free(yr), free(yi), free(pe), free(he), free(where), free(img);
    return rc;
}

/* ---- the entry point ---- */

void kin__sym_ctx_free(sym_ctx *C)
{
    for (int a = 0; a < NODES; ++a) {
        free(C->sys[a][0]);
        for (int b = 0; b < NODES; ++b) free(C->dif[a][b][0]);
        kin__sym_set_free(&C->set[a]);
        for (int e = 0; e < 2; ++e) free(C->queue[a][e]);
    }
    free(C->dq[0]), free(C->Qst), free(C->scr);
    for (int k = 0; k < 4; ++k) free(C->tmp[k]);
    if (C->pw)
        for (int t = 0; t < C->H.nthreads; ++t) kin__hpar_ws_free(C->pw[t]);
    if (C->pb)
        for (int t = 0; t < C->H.nthreads; ++t) kin__hpar_bws_free(C->pb[t]);
    free(C->pw), free(C->pb);
    kin__sym_group_free(&C->G);
    kin__hom_solver_free(&C->H);
}

/* the monodromy's state, C->H and C->G set up */
static int monodromy_init(sym_ctx *C, int m, int s, const kin_homotopy_options *o)
{
    int rc;
    C->m = m, C->s = s, C->N = 1 << s, C->sm = s * m;
    C->nsys = (size_t)s * m * m;
    size_t ns = C->nsys;
    C->Qst = calloc(2 * ns, sizeof(double));
    C->dq[0] = malloc(sizeof(double) * 2 * ns);
    C->scr = malloc(sizeof(double) * 2 * (size_t)C->sm);
    C->pw = calloc((size_t)C->H.nthreads, sizeof(hpar_ws *));
    C->pb = calloc((size_t)C->H.nthreads, sizeof(hpar_bws *));
    if (!C->Qst || !C->dq[0] || !C->scr || !C->pw || !C->pb) return KIN_ENOMEM;
    C->Qr0 = C->Qst + ns, C->dq[1] = C->dq[0] + ns;
    for (int k = 0; k < 4; ++k)
        if (!(C->tmp[k] = malloc(sizeof(double) * ns))) return KIN_ENOMEM;
    for (int t = 0; t < C->H.nthreads; ++t)
        if (!(C->pw[t] = kin__hpar_ws_new(m, s)) || !(C->pb[t] = kin__hpar_bws_new(m, s))) return KIN_ENOMEM;
    for (int a = 0; a < NODES; ++a) {
        if (!(C->sys[a][0] = malloc(sizeof(double) * 2 * ns))) return KIN_ENOMEM;
        C->sys[a][1] = C->sys[a][0] + ns;
        for (int b = 0; b < NODES; ++b) {
            if (a == b) continue;
            if (!(C->dif[a][b][0] = malloc(sizeof(double) * 2 * ns))) return KIN_ENOMEM;
            C->dif[a][b][1] = C->dif[a][b][0] + ns;
        }
        if ((rc = kin__sym_set_init(&C->set[a], m, C->N, C->wr, C->wi, C->key))) return rc;
        for (int e = 0; e < 2; ++e)
            if (!(C->queue[a][e] = malloc(sizeof(int) * (size_t)C->N))) return KIN_ENOMEM;
    }
    /* Q stacked (the scaled symmetric rows of the certificate's problem) */
    for (int j = 0; j < s; ++j)
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c) C->Qst[(size_t)c * C->sm + r * s + j] = C->H.Qr[((size_t)j * m + r) * m + c];
    /* the random systems, chart and set keys (from the seed: deterministic) */
    C->st = (unsigned long long)o->seed * 0x9E3779B97F4A7C15ull + 0x5851F42D4C957F2Dull;
    unsigned long long *st = &C->st;
    for (int c = 0; c < m; ++c) {
        kin__sym_gaussian2(st, &C->wr[c], &C->wi[c]);
        C->key[c] = kin__sym_uniform(st) - 0.5;
        double a = 6.283185307179586 * kin__sym_uniform(st);
        C->ar[c] = cos(a), C->ai[c] = sin(a);
    }
    for (int a = 0; a < NODES; ++a) kin__sym_random_member(C, st, C->tmp[0], C->tmp[1], C->sys[a][0], C->sys[a][1]);
    enum { MAXSEEDS = 64 };
    double *b0r = C->seeds, *b0i = C->seeds + MAXSEEDS * HOM_MAX_M;
    int nseeds = kin__sym_seeds(C, st, b0r, b0i, MAXSEEDS);
    if (nseeds < 0) return KIN_ENOMEM;
    if (!kin__sym_force_roots(C, st, nseeds, b0r, b0i, C->tmp[2], C->tmp[3])) return KIN_ENOTCONVERGED;
    set_edges(C);
    for (size_t i = 0; i < 2 * ns; ++i) C->dq[0][i] = C->Qst[i] - C->sys[0][0][i];
    /* the forced root, refined by Newton on P0 (a track of length zero) */
    hpar_problem P = {m, s, C->sys[0][0], C->sys[0][1], C->tmp[0], C->tmp[1], {0}, {0}};
    memset(C->tmp[0], 0, sizeof(double) * ns), memset(C->tmp[1], 0, sizeof(double) * ns);
    memcpy(P.ar, C->ar, sizeof P.ar), memcpy(P.ai, C->ai, sizeof P.ai);
    for (int k = 0; k < nseeds; ++k) {
        hpar_end e;
        double xr[HOM_MAX_M], xi[HOM_MAX_M];
        kin__hpar_track(&P, &LOOP_SETTINGS, C->pw[0], b0r + k * m, b0i + k * m, xr, xi, &e);
        if (!e.ok || kin__sym_set_find(&C->set[0], xr, xi) >= 0) continue;
        int r = kin__sym_set_add_orbit(&C->set[0], &C->G, xr, xi);
        if (r >= 0) enqueue(C, 0, r);
    }
    if (C->set[0].n == 0) return KIN_ENOTCONVERGED;
    return KIN_OK;
}

int kin__sym_monodromy_solve(sym_ctx *C, const kin_homotopy_options *o, double *betas, int maxsol, int *nsol,
                             int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *si, char *err,
                             size_t errlen)
{
    int m = C->H.P.m, s = C->H.P.s;
    hom_endset E = {NULL, NULL, NULL};
    int rc = monodromy_init(C, m, s, o);
    long loops = 0, finals = 0;
    int *reps = NULL, *list = NULL, *parent = NULL;
    hom_key *keys = NULL;
    unsigned char *paired = NULL;
    report(C, 0, 1);
    if (!rc && C->cancelled) rc = KIN_ECANCELLED;
    if (!rc) rc = monodromy(C, &loops);
    if (si) {
        si->group = C->G.n, si->found = C->set[0].n;
        si->monodromy_paths = (int)loops;
        si->monodromy_steps = C->lsteps, si->monodromy_rejected = C->lrej;
    }
    if (rc == KIN_ENOTCONVERGED) {
        info->paths = 1 << s;
        kin__failbuf(err, errlen, rc, "monodromy found %d of %d roots in %ld paths", C->set[0].n, 1 << s, loops);
        goto done;
    }
    int N = C->N, norb = 0;
    if (!rc) rc = kin__hom_endset_alloc(&E, N, m);
    if (!rc) {
        reps = malloc(sizeof(int) * (size_t)N), list = malloc(sizeof(int) * (size_t)N);
        parent = malloc(sizeof(int) * (size_t)N), keys = malloc(sizeof(hom_key) * (size_t)N);
        paired = malloc((size_t)N);
        if (!reps || !list || !parent || !keys || !paired) rc = KIN_ENOMEM;
    }
    if (rc) goto done;
    for (int p = 0; p < N; ++p)
        if (C->set[0].rep[p] == p) reps[norb++] = p;
    C->queued = norb;
    if ((rc = final_leg(C, reps, norb, &FINAL_SETTINGS, &E, &finals))) goto done;
    hom_checks ck = kin__hom_check(m, N, E.ends, E.zr, E.zi, C->H.w, keys, parent, paired);
    hpar_settings S = FINAL_SETTINGS;
    int retracked = 0, *size = list; /* size: root multiplicities, then the suspects' representatives */
    for (int round = 1; round <= RETRACK_ROUNDS; ++round) {
        memset(size, 0, sizeof(int) * (size_t)N);
        for (int p = 0; p < N; ++p)
            if (E.ends[p].kind == HOM_REAL || E.ends[p].kind == HOM_NONREAL) size[kin__hom_find(parent, p)]++;
        int n = 0;
        for (int p = 0; p < N; ++p) {
            int k = E.ends[p].kind;
            int sus = k == HOM_FAILED || ((k == HOM_REAL || k == HOM_NONREAL) && size[kin__hom_find(parent, p)] > 1) ||
                      (k == HOM_NONREAL && !paired[p]) || (k == HOM_SINGULAR && round >= 2 && ck.unpaired > 0);
            if (sus) reps[n++] = C->set[0].rep[p];
        }
        if (!n) break;
        /* distinct representatives, in order */
        memset(size, 0, sizeof(int) * (size_t)N);
        int nr = 0;
        for (int i = 0; i < n; ++i)
            if (!size[reps[i]]) size[reps[i]] = 1, reps[nr++] = reps[i];
        S.pred_rel *= TIGHTEN, S.corr_rel *= TIGHTEN, S.sigma_end *= SIGMA_TIGHTEN;
        C->queued = nr;
        if ((rc = final_leg(C, reps, nr, &S, &E, &finals))) goto done;
        retracked += nr;
        ck = kin__hom_check(m, N, E.ends, E.zr, E.zi, C->H.w, keys, parent, paired);
    }
    rc = kin__hom_tally(&C->H, E.ends, E.zr, E.zi, parent, ck, retracked, betas, maxsol, nsol, multiplicity, info);
    if (!rc && C->fn) C->fn(C->user, (double)C->done, (double)C->done);
    if (si) si->orbits = norb, si->final_paths = (int)finals;
done:
    if (rc && rc != KIN_ENOTCONVERGED) memset(info, 0, sizeof *info);
    if (rc) *nsol = 0;
    free(reps), free(list), free(parent), free(keys), free(paired);
    kin__hom_endset_free(&E);
    return rc;
}

