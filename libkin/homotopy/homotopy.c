/* A complete solver for beta^T Q_j beta = 0 (j < s), beta in P^s: total-degree
 * homotopy continuation. Every one of the 2^s paths from the start system
 * x_j^2 - x_0^2 = 0 is tracked in a random complex affine chart a.x = 1 with
 * the gamma trick,
 *     H(x, t) = (1 - t) gamma G(x) + t F(x),
 * and its endpoint certified and classified: real, complex, singular (a
 * multiple root, a point of a positive-dimensional component, Figure
 * 5(c)-(d), or a root too ill-conditioned to certify), or failed. The tracker
 * and the certificate are in homotopy_track.c; each thread tracks its paths
 * HOM_BATCH at a time in lockstep (homotopy_batch.c), each path exactly as
 * the one-path tracker would.
 *
 * Then the endpoints are checked against what total-degree homotopy
 * guarantees: every non-singular root is reached by exactly one path, so two
 * paths on the same certified root means a path jumped; complex roots of a
 * real system come in conjugate pairs, so a certified non-real root whose
 * conjugate no path reached means a path was lost on the way. Paths involved
 * (and failed ones) are tracked again with tighter settings, up to
 * RETRACK_ROUNDS times; what remains is reported in kin_homotopy_info.
 * Duplicates and conjugates are found in O(n log n): endpoints are sorted by
 * a key that does not depend on the representative of the projective point
 * nor on conjugation, and only neighbours within KEY_WINDOW are compared.
 *
 * Paths are independent and each result is stored by path index, so the
 * result does not depend on the thread count nor on which thread tracked
 * which path.
 *
 * Progress and cancellation: the calling thread tracks paths too and, every
 * REPORT_INTERVAL, reads the shared count of tracked paths and calls the
 * caller's callback (never from another thread: a Python caller's signal
 * handlers run in its own thread). A cancel sets a flag every thread reads
 * at its next path boundary. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime, sysconf */
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "homotopy/homotopy_equi.h"
#include "homotopy/homotopy_track.h"
#include "model/internal.h"

/* Paths are handed out in chunks of PATH_CHUNK from a shared counter, so a
 * thread slowed down by other work on the machine takes fewer (which path
 * a thread tracks does not change its result). */
enum { PATH_CHUNK = 16 };

/* Seconds between progress reports: short enough for Ctrl-C to feel
 * immediate, long enough to cost nothing next to the tracking. */
static const double REPORT_INTERVAL = 0.05;

typedef struct hom_queue {
    pthread_mutex_t lock;
    pthread_cond_t idle; /* signalled when a worker thread finishes */
    int next, n;         /* next path to hand out, of n */
    int tracked;         /* paths finished in this run */
    int active;          /* started worker threads (not the caller's) still running */
    int stop;            /* the caller cancelled: hand out no more paths */
} hom_queue;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Call the progress callback if REPORT_INTERVAL has passed (or force);
 * calling thread only. A cancel stops the queue. */
static void report(hom_report *R, hom_queue *q, int force)
{
    if (!R->fn || R->cancelled) return;
    double t = now_seconds();
    if (!force && t - R->last < REPORT_INTERVAL) return;
    R->last = t;
    int done = 0;
    if (q) {
        pthread_mutex_lock(&q->lock);
        done = q->tracked;
        pthread_mutex_unlock(&q->lock);
    }
    if (R->fn(R->user, R->base + done, R->total)) {
        R->cancelled = 1;
        if (q) {
            pthread_mutex_lock(&q->lock);
            q->stop = 1;
            pthread_mutex_unlock(&q->lock);
        }
    }
}

typedef struct hom_job {
    const hom_problem *P;
    const hom_settings *S;
    const int *list; /* paths to track, NULL: first .. first + n - 1 */
    int first, offset; /* path p goes to index p - offset of ends, zr, zi */
    hom_queue *queue;
    hom_ws *ws;
    hom_bws *bws;
    hom_end *ends;
    double *zr, *zi;
    hom_report *R; /* the calling thread's job only, else NULL */
    const hom_orbits *orb; /* NULL, or every finished path's orbit is stored (offset 0) */
    int taken, left; /* the chunk of queue positions this thread holds */
    int stopped;     /* the queue was stopped (seen at the last path finished) */
} hom_job;

/* the batch tracker's next path: from the thread's chunk, refilled from the
 * shared queue; HOM_BATCH_STOP once the caller cancelled */
static int job_next(void *ctx)
{
    hom_job *J = ctx;
    hom_queue *q = J->queue;
    if (J->stopped || (J->R && J->R->cancelled)) return HOM_BATCH_STOP;
    if (J->left == 0) {
        pthread_mutex_lock(&q->lock);
        int first = q->next, last = first + PATH_CHUNK < q->n ? first + PATH_CHUNK : q->n, stop = q->stop;
        if (!stop) q->next = last;
        pthread_mutex_unlock(&q->lock);
        if (stop) return HOM_BATCH_STOP;
        J->taken = first, J->left = last - first;
        if (J->left <= 0) {
            J->left = 0;
            return -1;
        }
    }
    int i = J->taken++;
    J->left--;
    return J->list ? J->list[i] : J->first + i;
}

/* The endpoints of the other members of path p's orbit: p's endpoint (z,
 * e) permuted, each then refined and certified on its own (the tracked
 * system is exactly equivariant, but its scaling and the certificate's
 * sums are not: each point gets its own certificate); uncertified ones are
 * copied as they are. No steps are counted for them. */
static void expand_orbit(hom_job *J, int p, const double *zr, const double *zi, const hom_end *e)
{
    const hom_orbits *O = J->orb;
    int m = J->P->m, pinv[HOM_MAX_M];
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
            kin__hom_certify(J->P, J->ws, xr, xi, outr, outi, &f);
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
    hom_job *J = ctx;
    hom_queue *q = J->queue;
    int m = J->P->m, k = J->orb && J->orb->slot ? J->orb->slot[p] : p - J->offset;
    memcpy(J->zr + (size_t)k * m, zr, sizeof(double) * (size_t)m);
    memcpy(J->zi + (size_t)k * m, zi, sizeof(double) * (size_t)m);
    J->ends[k] = *e;
    if (J->orb) expand_orbit(J, p, zr, zi, e);
    pthread_mutex_lock(&q->lock);
    q->tracked++;
    J->stopped = q->stop;
    pthread_mutex_unlock(&q->lock);
    if (J->R) report(J->R, q, 0);
}

/* Track paths, HOM_BATCH at a time, until the queue is empty or stopped. */
static void track_chunks(hom_job *J)
{
    hom_batch_sink K = {J, job_next, job_done};
    J->taken = J->left = 0;
    kin__hom_track_batch(J->P, J->S, J->bws, J->ws, &K);
}

static void *worker(void *arg)
{
    hom_job *J = arg;
    track_chunks(J);
    pthread_mutex_lock(&J->queue->lock);
    J->queue->active--;
    pthread_cond_signal(&J->queue->idle);
    pthread_mutex_unlock(&J->queue->lock);
    return NULL;
}

typedef struct hom_pool {
    hom_ws **ws;
    hom_bws **bws;
    hom_job *jobs;
    pthread_t *th;
    int *running;
} hom_pool;

int kin__hom_run(hom_solver *H, const hom_settings *S, const int *list, int first, int n, int offset, hom_end *ends,
                 double *zr, double *zi, hom_report *R)
{
    hom_pool *pool = H->pool;
    const hom_problem *P = &H->P;
    int nthreads = H->nthreads;
    hom_job *jobs = pool->jobs;
    pthread_t *th = pool->th;
    int *running = pool->running;
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
    hom_queue q;
    memset(&q, 0, sizeof q);
    q.n = n;
    if (pthread_mutex_init(&q.lock, NULL) != 0) return KIN_ENOMEM;
    if (pthread_cond_init(&q.idle, NULL) != 0) {
        pthread_mutex_destroy(&q.lock);
        return KIN_ENOMEM;
    }
    for (int t = 0; t < nthreads; ++t) jobs[t] = (hom_job){P, S, list, first, offset, &q, pool->ws[t], pool->bws[t], ends, zr, zi,
                                           t == 0 ? R : NULL, O, 0, 0, 0};
    /* thread 0 is this one; threads that cannot be started leave their
     * share to the others */
    for (int t = 1; t < nthreads; ++t) {
        pthread_mutex_lock(&q.lock);
        q.active++;
        pthread_mutex_unlock(&q.lock);
        running[t] = pthread_create(&th[t], NULL, worker, &jobs[t]) == 0;
        if (!running[t]) {
            pthread_mutex_lock(&q.lock);
            q.active--;
            pthread_mutex_unlock(&q.lock);
        }
    }
    track_chunks(&jobs[0]);
    /* the others finish their last paths: keep reporting meanwhile */
    pthread_mutex_lock(&q.lock);
    while (q.active > 0) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        ts.tv_nsec += (long)(REPORT_INTERVAL * 1e9);
        if (ts.tv_nsec >= 1000000000L) ts.tv_sec++, ts.tv_nsec -= 1000000000L;
        pthread_cond_timedwait(&q.idle, &q.lock, &ts);
        if (q.active > 0 && R->fn && !R->cancelled) {
            pthread_mutex_unlock(&q.lock);
            report(R, &q, 0);
            pthread_mutex_lock(&q.lock);
        }
    }
    pthread_mutex_unlock(&q.lock);
    for (int t = 1; t < nthreads; ++t)
        if (running[t]) pthread_join(th[t], NULL);
    R->base += q.tracked;
    pthread_cond_destroy(&q.idle);
    pthread_mutex_destroy(&q.lock);
    return KIN_OK;
}

/* processors online: the bound on useful threads */
static int online_processors(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > INT_MAX ? INT_MAX : (int)n;
}

void kin_homotopy_options_default(kin_homotopy_options *o)
{
    if (!o) return;
    memset(o, 0, sizeof *o);
    o->size = sizeof *o;
    o->seed = 1;
    o->nthreads = 0;
    o->max_paths = KIN_HOMOTOPY_MAX_PATHS;
    o->progress = NULL;
    o->user = NULL;
}

int kin__hom_options(const kin_homotopy_options *opt, kin_homotopy_options *o)
{
    kin_homotopy_options_default(o); /* fields an older caller does not have keep their defaults */
    if (!opt) return KIN_OK;
    if (kin__abi_check(opt, KIN__V1_SIZE(kin_homotopy_options, user), sizeof *opt)) return KIN_EINVAL;
    kin__abi_read(o, opt, sizeof *o);
    return KIN_OK;
}

int kin_quadrics_homotopy(int m, int s, const double *Q, unsigned long seed, int nthreads, double *betas,
                          int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.seed = seed;
    o.nthreads = nthreads < 1 ? -1 : nthreads; /* 0 means "all processors" only in the options */
    return kin_quadrics_homotopy_ex(m, s, Q, &o, betas, maxsol, nsol, multiplicity, info);
}

int kin__hom_solver_init(hom_solver *H, int m, int s, const double *Q, const kin_homotopy_options *o, long work)
{
    memset(H, 0, sizeof *H);
    if (m < 2 || s != m - 1 || o->nthreads < 0 || o->max_paths < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE; /* so 2^s <= 2^23 and every size below fits */
    for (size_t i = 0; i < (size_t)m * m * s; ++i)
        if (!isfinite(Q[i])) return KIN_EINVAL;
    H->npaths = 1 << s;
    int cpus = online_processors();
    int nthreads = o->nthreads == 0 || o->nthreads > cpus ? cpus : o->nthreads;
    if (work < 1) work = 1;
    if (nthreads > work) nthreads = (int)work; /* more would idle; the result is the same */
    H->nthreads = nthreads;
    size_t mm = (size_t)m * m;
    size_t nrows = (size_t)kin__hom_rows(m, s);
    double *Qr = H->Qr = malloc(sizeof(double) * mm * (size_t)s), *Qb = H->Qb = calloc(nrows * m, sizeof(double));
    double *Qs = H->Qs = calloc((size_t)kin__hom_srows(m, s) * m, sizeof(double));
    hom_pool *pool = H->pool = calloc(1, sizeof(hom_pool));
    if (!Qr || !Qb || !Qs || !pool) return KIN_ENOMEM;
    pool->jobs = malloc(sizeof(hom_job) * (size_t)nthreads);
    pool->th = malloc(sizeof(pthread_t) * (size_t)nthreads);
    pool->running = calloc((size_t)nthreads, sizeof(int));
    pool->ws = calloc((size_t)nthreads, sizeof(hom_ws *));
    pool->bws = calloc((size_t)nthreads, sizeof(hom_bws *));
    if (!pool->jobs || !pool->th || !pool->running || !pool->ws || !pool->bws) return KIN_ENOMEM;
    for (int t = 0; t < nthreads; ++t)
        if (!(pool->ws[t] = kin__hom_ws_new()) || !(pool->bws[t] = kin__hom_bws_new())) return KIN_ENOMEM;

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

hom_ws *kin__hom_pool_ws(const hom_solver *H, int t) { return ((hom_pool *)H->pool)->ws[t]; }

void kin__hom_solver_free(hom_solver *H)
{
    hom_pool *pool = H->pool;
    if (pool) {
        if (pool->ws)
            for (int t = 0; t < H->nthreads; ++t) kin__hom_ws_free(pool->ws[t]);
        if (pool->bws)
            for (int t = 0; t < H->nthreads; ++t) kin__hom_bws_free(pool->bws[t]);
        free(pool->ws), free(pool->bws), free(pool->running), free(pool->th), free(pool->jobs), free(pool);
    }
    free(H->Qr), free(H->Qb), free(H->Qs);
    memset(H, 0, sizeof *H);
}

/* range over every path, then the merge: the one path of every result */
static int homotopy_impl(int m, int s, const double *Q, const kin_homotopy_options *o, double *betas, int maxsol,
                         int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (nsol) *nsol = 0;
    if (!Q || !betas || !nsol || !info) return KIN_ENULL;
    if (maxsol < 1) return KIN_EINVAL;
    if (m >= 2 && s == m - 1 && m <= HOM_MAX_M && o->max_paths >= 1 && (1L << s) > o->max_paths) {
        /* refused before anything is allocated, unless the arguments are wrong anyway */
        for (size_t i = 0; i < (size_t)m * m * s; ++i)
            if (!isfinite(Q[i])) return KIN_EINVAL;
        if (o->nthreads < 0) return KIN_EINVAL;
        return KIN_ELIMIT;
    }
    hom_solver H;
    long tracked = 0;
    int rc = kin__hom_solver_init(&H, m, s, Q, o, m >= 2 && m <= HOM_MAX_M ? 1L << (m - 1) : 1);
    if (!rc) rc = kin__hom_solve(&H, NULL, H.npaths, o, betas, maxsol, nsol, multiplicity, info, &tracked);
    if (rc) {
        memset(info, 0, sizeof *info);
        *nsol = 0;
    }
    kin__hom_solver_free(&H);
    return rc;
}

void kin__hom_report_start(hom_report *R) { report(R, NULL, 1); }

int kin__hom_solve(hom_solver *H, const int *list, int n, const kin_homotopy_options *o, double *betas, int maxsol,
                   int *nsol, int *multiplicity, kin_homotopy_info *info, long *tracked)
{
    hom_endset E = {NULL, NULL, NULL};
    hom_report R = {o->progress, o->user, 0.0, (double)n, 0.0, 0};
    int rc = kin__hom_endset_alloc(&E, H->npaths, H->P.m);
    if (!rc) {
        report(&R, NULL, 1);
        if (!R.cancelled) rc = kin__hom_run(H, &kin__hom_base_settings, list, 0, n, 0, E.ends, E.zr, E.zi, &R);
        if (!rc && R.cancelled) rc = KIN_ECANCELLED;
        if (!rc) rc = kin__hom_merge(H, E.ends, E.zr, E.zi, &R, betas, maxsol, nsol, multiplicity, info);
    }
    *tracked = (long)R.base;
    kin__hom_endset_free(&E);
    return rc;
}

int kin_quadrics_homotopy_ex(int m, int s, const double *Q, const kin_homotopy_options *opt, double *betas,
                             int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (nsol) *nsol = 0;
    if (!info) return KIN_ENULL;
    if (kin__abi_check(info, KIN__V1_SIZE(kin_homotopy_info, max_cond), sizeof *info)) return KIN_EINVAL;
    kin__abi_zero(info);
    kin_homotopy_options o;
    if (kin__hom_options(opt, &o)) return KIN_EINVAL;
    kin_homotopy_info local = {.size = sizeof local};
    int rc = homotopy_impl(m, s, Q, &o, betas, maxsol, nsol, multiplicity, &local);
    kin__abi_write(info, &local, sizeof local);
    return rc;
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

int kin_quadrics_homotopy_range(int m, int s, const double *Q, const kin_homotopy_options *opt, long first_path,
                                long npaths, kin_homotopy_endpoint *ends, double *z)
{
    if (!Q || !ends || !z) return KIN_ENULL;
    if (ends[0].size != KIN_HOMOTOPY_ENDPOINT_SIZE || sizeof *ends != KIN_HOMOTOPY_ENDPOINT_SIZE) return KIN_EINVAL;
    kin_homotopy_options o;
    if (kin__hom_options(opt, &o)) return KIN_EINVAL;
    if (m < 2 || s != m - 1 || o.nthreads < 0 || o.max_paths < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE;
    if (first_path < 0 || npaths < 1 || first_path > (1L << s) - npaths) return KIN_ERANGE;
    kin__hom_zero_records(ends, npaths);
    if (npaths > o.max_paths) {
        for (size_t i = 0; i < (size_t)m * m * s; ++i)
            if (!isfinite(Q[i])) return KIN_EINVAL;
        return KIN_ELIMIT;
    }
    hom_solver H;
    int rc = kin__hom_solver_init(&H, m, s, Q, &o, npaths);
    int n = (int)npaths, first = (int)first_path;
    hom_endset E = {NULL, NULL, NULL};
    if (!rc) rc = kin__hom_endset_alloc(&E, n, m);
    if (!rc) {
        hom_report R = {o.progress, o.user, 0.0, (double)n, 0.0, 0};
        report(&R, NULL, 1);
        if (!R.cancelled)
            rc = kin__hom_run(&H, &kin__hom_base_settings, NULL, first, n, first, E.ends, E.zr, E.zi, &R);
        if (!rc && R.cancelled) rc = KIN_ECANCELLED;
        if (!rc) {
            for (int i = 0; i < n; ++i)
                kin__hom_export(m, first + i, &E.ends[i], E.zr + (size_t)i * m, E.zi + (size_t)i * m, &ends[i],
                                z + (size_t)2 * m * i);
            if (R.fn) R.fn(R.user, R.total, R.total); /* finished: its answer no longer matters */
        }
    }
    kin__hom_endset_free(&E);
    kin__hom_solver_free(&H);
    return rc;
}
