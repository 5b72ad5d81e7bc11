/* The complete solver's set-up and path runs, below the checks
 * (homotopy_merge.c) and the entry points (homotopy.c): the options
 * reader, the scaled problem with its threads' workspaces (hom_solver), the
 * endpoint sets and records, and kin__hom_run, which tracks a list of paths
 * on the thread pool (homotopy_pool.c), each worker HOM_BATCH paths at a
 * time in lockstep (homotopy_batch.c), each path exactly as the one-path
 * tracker would.
 *
 * Paths are independent and each result is stored by path index, so the
 * result does not depend on the thread count nor on which thread tracked
 * which path.
 *
 * Progress and cancellation: the calling thread tracks paths too and, every
 * HOM_POOL_REPORT seconds, calls the caller's callback with the shared
 * count of tracked paths (never from another thread). A cancel stops the
 * pool's counter; every worker abandons its paths in flight at its next
 * path boundary. */
#define _POSIX_C_SOURCE 200809L /* sysconf */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "homotopy/solver/homotopy_pool.h"
#include "homotopy/solver/homotopy_solver.h"
#include "model/internal.h"

/* Paths are handed out in chunks of PATH_CHUNK, so a thread slowed down by
 * other work on the machine takes fewer (which path a thread tracks does
 * not change its result). */
enum { PATH_CHUNK = 16 };

/* Call the progress callback (done: paths tracked in this run) if
 * HOM_POOL_REPORT has passed (or force); calling thread only. */
static void report(hom_report *R, long done, int force)
{
    if (!R->fn || R->cancelled) return;
    double t = kin__hom_seconds();
    if (!force && t - R->last < HOM_POOL_REPORT) return;
    R->last = t;
    if (R->fn(R->user, R->base + (double)done, R->total)) R->cancelled = 1;
}

void kin__hom_report_start(hom_report *R) { report(R, 0, 1); }

/* one run of kin__hom_run, shared by its workers */
typedef struct hom_job {
    const hom_solver *H;
    const hom_settings *S;
    const int *list; /* paths to track, NULL: first .. first + n - 1 */
    int first, offset; /* path p goes to index p - offset of ends, zr, zi */
    hom_end *ends;
    double *zr, *zi;
    hom_report *R;
    const hom_orbits *orb; /* NULL, or every finished path's orbit is stored (offset 0) */
} hom_job;

/* a worker's view of the run: the chunk of items it holds */
typedef struct hom_cursor {
    const hom_job *J;
    int t;           /* the worker */
    int taken, left; /* the chunk of items this worker holds */
    int stopped;     /* the run was cancelled (seen at the last path finished) */
} hom_cursor;

/* the batch tracker's next path: from the worker's chunk, refilled from the
 * pool; HOM_BATCH_STOP once the caller cancelled */
static int job_next(void *ctx)
{
    hom_cursor *c = ctx;
    const hom_job *J = c->J;
    if (c->stopped) return HOM_BATCH_STOP;
    if (c->left == 0) {
        int first, k = kin__hom_pool_take(J->H->pool, PATH_CHUNK, &first);
        if (k < 0) return HOM_BATCH_STOP;
        if (k == 0) return -1;
        c->taken = first, c->left = k;
    }
    int i = c->taken++;
    c->left--;
    return J->list ? J->list[i] : J->first + i;
}


/* The endpoints of the other members of path p's orbit: p's endpoint (z,
 * e) permuted, each then refined and certified on its own (the tracked
 * system is exactly equivariant, but its scaling and the certificate's
 * sums are not: each point gets its own certificate); uncertified ones are
 * copied as they are. No steps are counted for them. */
static void expand_orbit(const hom_job *J, hom_ws *ws, int p, const double *zr, const double *zi, const hom_end *e)
{
    const hom_orbits *O = J->orb;
    int m = J->H->P.m, pinv[HOM_MAX_M];
    for (int c = 0; c < m; ++c) pinv[O->perm[c]] = c;
    double xr[HOM_MAX_M], xi[HOM_MAX_M], yr[HOM_MAX_M], yi[HOM_MAX_M];
    memcpy(xr, zr, sizeof(double) * (size_t)m);
    memcpy(xi, zi, sizeof(double) * (size_t)m);
    int chart = e->chart;
    for (int q = O->next[p]; q != p; q = O->next[q]) {
        for (int c = 0; c < m; ++c) yr[c] = xr[O->perm[c]], yi[c] = xi[O->perm[c]]; /* (P x)_c = x_{p(c)} */
        memcpy(xr, yr, sizeof(double) * (size_t)m);
        memcpy(xi, yi, sizeof(double) * (size_t)m);
        chart = pinv[chart];
        hom_end f = *e;
        f.steps = f.rejected = f.recharts = 0;
        size_t at = (size_t)(O->slot ? O->slot[q] : q);
        double *outr = J->zr + at * m, *outi = J->zi + at * m;
        if (e->kind == HOM_REAL || e->kind == HOM_NONREAL) {
            kin__hom_certify(&J->H->P, ws, xr, xi, outr, outi, &f);
        } else {
            f.chart = chart;
            memcpy(outr, xr, sizeof(double) * (size_t)m);
            memcpy(outi, xi, sizeof(double) * (size_t)m);
        }
        J->ends[O->slot ? O->slot[q] : q] = f;
    }
}

/* the batch tracker's finished path: stored by index, counted, reported */
static void job_done(void *ctx, int p, const double *zr, const double *zi, const hom_end *e)
{
    hom_cursor *c = ctx;
    const hom_job *J = c->J;
    int m = J->H->P.m, k = J->orb && J->orb->slot ? J->orb->slot[p] : p - J->offset;
    memcpy(J->zr + (size_t)k * m, zr, sizeof(double) * (size_t)m);
    memcpy(J->zi + (size_t)k * m, zi, sizeof(double) * (size_t)m);
    J->ends[k] = *e;
    if (J->orb) expand_orbit(J, J->H->ws[c->t], p, zr, zi, e);
    c->stopped = kin__hom_pool_done(J->H->pool, c->t);
}

/* worker t: paths, HOM_BATCH at a time, until the pool has none or stops */
static void job_work(void *ctx, int t)
{
    const hom_job *J = ctx;
    hom_cursor c = {J, t, 0, 0, 0};
    hom_batch_sink K = {&c, job_next, job_done};
    kin__hom_track_batch(&J->H->P, J->S, J->H->bws[t], J->H->ws[t], &K);
}

static int job_progress(void *ctx, long done)
{
    const hom_job *J = ctx;
    report(J->R, done, 0);
    return J->R->cancelled;
}

int kin__hom_run(hom_solver *H, const hom_settings *S, const int *list, int first, int n, int offset, hom_end *ends,
                 double *zr, double *zi, hom_report *R)
{
    hom_orbits *O = H->orb;
    if (O) { /* the distinct orbit representatives of the paths, in order */
        int nr = 0;
        for (int i = 0; i < n; ++i) {
            int r = O->rep[list ? list[i] : first + i];
            if (!O->mark[r]) O->mark[r] = 1, O->list[nr++] = r;
        }
        for (int i = 0; i < nr; ++i) O->mark[O->list[i]] = 0;
        R->total -= (double)(n - nr); /* the caller scheduled n paths; nr are tracked */
        list = O->list, n = nr, offset = 0;
    }
    hom_job J = {H, S, list, first, offset, ends, zr, zi, R, O};
    hom_pool_job W = {job_work, R->fn ? job_progress : NULL, &J};
    R->base += (double)kin__hom_pool_run(H->pool, n, &W);
    return KIN_OK;
}

/* processors online: the bound on useful threads */
static int online_processors(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > INT_MAX ? INT_MAX : (int)n;
}

static const kin_homotopy_options DEFAULTS = {
    .size = sizeof(kin_homotopy_options),
    .seed = 1,
    .nthreads = 0,
    .max_paths = KIN_HOMOTOPY_MAX_PATHS,
    .progress = NULL,
    .user = NULL,
    .prove = 2, /* Arb and FLINT only: no hand-derived rounding bound (kin_branch.h) */
};

int kin_homotopy_options_init(kin_homotopy_options *o, size_t size)
{
    return kin__abi_init(o, size, &DEFAULTS, KIN__ABI(kin_homotopy_options));
}

/* for binaries built before the macro: the first layout only (docs/abi.md) */
void (kin_homotopy_options_default)(kin_homotopy_options *o)
{
    if (o) kin__abi_init(o, KIN__ABI(kin_homotopy_options)->size[0], &DEFAULTS, KIN__ABI(kin_homotopy_options));
}

int kin__hom_options(const kin_homotopy_options *opt, kin_homotopy_options *o)
{
    kin_homotopy_options_default(o); /* fields an older caller does not have keep their defaults */
    if (!opt) return KIN_OK;
    if (kin__abi_check(opt, KIN__ABI(kin_homotopy_options))) return KIN_EINVAL;
    kin__abi_read(o, opt, KIN__ABI(kin_homotopy_options));
    return KIN_OK;
}

int kin__hom_entry(const kin_homotopy_options *opt, kin_homotopy_options *o, kin_homotopy_info *info, int *nsol)
{
    if (nsol) *nsol = 0;
    if (!info) return KIN_ENULL;
    if (kin__abi_check(info, KIN__ABI(kin_homotopy_info))) return KIN_EINVAL;
    kin__abi_zero(info);
    return kin__hom_options(opt, o);
}

int kin__hom_solver_init(hom_solver *H, int m, int s, const double *Q, const kin_homotopy_options *o, long work)
{
    memset(H, 0, sizeof *H);
    if (m < 2 || s != m - 1 || o->nthreads < 0 || o->max_paths < 1 || o->prove < 0 || o->prove > 2)
        return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE; /* so 2^s <= 2^23 and every size below fits */
    for (size_t i = 0; i < (size_t)m * m * s; ++i)
        if (!isfinite(Q[i])) return KIN_EINVAL;
    H->npaths = 1 << s;
    H->Qin = Q;
    H->prove = o->prove;
    int cpus = online_processors();
    int nthreads = o->nthreads == 0 || o->nthreads > cpus ? cpus : o->nthreads;
    if (work < 1) work = 1;
    if (nthreads > work) nthreads = (int)work; /* more would idle; the result is the same */
    H->nthreads = nthreads;
    size_t mm = (size_t)m * m;
    size_t nrows = (size_t)kin__hom_rows(m, s);
    double *Qr = H->Qr = malloc(sizeof(double) * mm * (size_t)s), *Qb = H->Qb = calloc(nrows * m, sizeof(double));
    double *Qs = H->Qs = calloc((size_t)kin__hom_srows(m, s) * m, sizeof(double));
    H->pool = kin__hom_pool_new(nthreads);
    H->ws = calloc((size_t)nthreads, sizeof(hom_ws *));
    H->bws = calloc((size_t)nthreads, sizeof(hom_bws *));
    if (!Qr || !Qb || !Qs || !H->pool || !H->ws || !H->bws) return KIN_ENOMEM;
    for (int t = 0; t < nthreads; ++t)
        if (!(H->ws[t] = kin__hom_ws_new()) || !(H->bws[t] = kin__hom_bws_new())) return KIN_ENOMEM;

    /* the problem: Q_j scaled to unit Frobenius norm (the roots do not
     * change; the tolerances then mean the same for every input), by rows
     * and in blocks of rows for Q x */
    hom_problem *P = &H->P;
    P->m = m, P->s = s, P->sp = kin__hom_sp(s), P->Qr = Qr, P->Qb = Qb, P->Qs = Qs;
    double nf2 = 0.0;
    for (int j = 0; j < s; ++j) {
        const double *q = Q + (size_t)j * mm;
        double f = kin__norm((int)mm, q), n1 = 0.0; /* scaled: no overflow or underflow */
        double sc = f > 0.0 ? 1.0 / f : 1.0;
        for (int r = 0; r < m; ++r) {
            double col = 0.0;
            for (int c = 0; c < m; ++c) {
                double v = 0.5 * (q[r + (size_t)c * m] + q[c + (size_t)r * m]) * sc; /* symmetric part */
                Qr[((size_t)j * m + r) * m + c] = v;
                col += fabs(v);
            }
            n1 = fmax(n1, col);
        }
        /* |Q_j|_2 <= min(|Q_j|_F, |Q_j|_1) (symmetric) */
        double n2 = fmin(f > 0.0 ? 1.0 : 0.0, n1);
        nf2 += n2 * n2;
    }
    P->normF = sqrt(nf2);
    for (int j = 0; j < s; ++j) /* row r of Q_j to interleaved row i = r*sp + j: block i / B, slot i % B */
        for (int r = 0; r < m; ++r) {
            size_t i = (size_t)r * P->sp + j;
            for (int c = 0; c < m; ++c)
                Qb[(i / HOM_QBLOCK) * HOM_QBLOCK * m + (size_t)c * HOM_QBLOCK + i % HOM_QBLOCK] =
                    Qr[((size_t)j * m + r) * m + c];
        }
    for (int j = 0; j < s; ++j) /* row r of Q_j to row i = r*s + j: block i / HOM_SBLOCK, slot i % HOM_SBLOCK */
        for (int r = 0; r < m; ++r) {
            size_t i = (size_t)r * s + j;
            for (int c = 0; c < m; ++c)
                Qs[(i / HOM_SBLOCK) * HOM_SBLOCK * m + (size_t)c * HOM_SBLOCK + i % HOM_SBLOCK] =
                    Qr[((size_t)j * m + r) * m + c];
        }
    P->normG = sqrt((double)s);
    unsigned long long st = (unsigned long long)o->seed * 0x2545F4914F6CDD1Dull + 7u;
    double th0 = 6.283185307179586 * ((kin__splitmix(&st) >> 11) * 0x1.0p-53);
    P->gr = cos(th0), P->gi = sin(th0);
    for (int i = 0; i < m; ++i) {
        double a = 6.283185307179586 * ((kin__splitmix(&st) >> 11) * 0x1.0p-53);
        P->ar[i] = cos(a), P->ai[i] = sin(a);
    }
    /* the sort key's direction: a fixed random unit vector */
    double wn = 0.0;
    for (int i = 0; i < m; ++i) {
        H->w[i] = ((kin__splitmix(&st) >> 11) * 0x1.0p-53) - 0.5;
        wn += H->w[i] * H->w[i];
    }
    for (int i = 0; i < m; ++i) H->w[i] /= sqrt(wn);
    return KIN_OK;
}

hom_ws *kin__hom_pool_ws(const hom_solver *H, int t) { return H->ws[t]; }

void kin__hom_solver_free(hom_solver *H)
{
    if (H->ws)
        for (int t = 0; t < H->nthreads; ++t) kin__hom_ws_free(H->ws[t]);
    if (H->bws)
        for (int t = 0; t < H->nthreads; ++t) kin__hom_bws_free(H->bws[t]);
    free(H->ws), free(H->bws);
    kin__hom_pool_free(H->pool);
    free(H->Qr), free(H->Qb), free(H->Qs);
    memset(H, 0, sizeof *H);
}

/* zero n records of a caller's array (stride: the checked element size) */
void kin__hom_zero_records(kin_homotopy_endpoint *ends, long n)
{
    for (long i = 0; i < n; ++i) {
        kin_homotopy_endpoint *r = &ends[i];
        memset(r, 0, sizeof *r);
        r->size = sizeof *r;
    }
}

int kin__hom_endset_alloc(hom_endset *E, int n, int m)
{
    E->ends = malloc(sizeof(hom_end) * (size_t)n);
    E->zr = malloc(sizeof(double) * (size_t)n * (size_t)m);
    E->zi = malloc(sizeof(double) * (size_t)n * (size_t)m);
    if (E->ends && E->zr && E->zi) return KIN_OK;
    kin__hom_endset_free(E);
    return KIN_ENOMEM;
}

void kin__hom_endset_free(hom_endset *E)
{
    free(E->ends), free(E->zr), free(E->zi);
    E->ends = NULL, E->zr = E->zi = NULL;
}

void kin__hom_export(int m, int path, const hom_end *e, const double *zr, const double *zi, kin_homotopy_endpoint *r,
                     double *z)
{
    memset(r, 0, sizeof *r);
    r->size = sizeof *r;
    r->path = path;
    r->kind = e->kind;
    r->chart = e->chart;
    r->steps = e->steps;
    r->rejected = e->rejected;
    r->recharts = e->recharts;
    r->converged = e->converged;
    r->rminus = e->rminus;
    r->rplus = e->rplus;
    r->cond = e->cond;
    r->sigma = e->sigma;
    memcpy(z, zr, sizeof(double) * (size_t)m);
    memcpy(z + m, zi, sizeof(double) * (size_t)m);
}
