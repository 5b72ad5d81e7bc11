/* A complete solver for beta^T Q_j beta = 0 (j < s), beta in P^s: total-degree
 * homotopy continuation. Every one of the 2^s paths from the start system
 * x_j^2 - x_0^2 = 0 is tracked in a random complex affine chart a.x = 1 with
 * the gamma trick,
 *     H(x, t) = (1 - t) gamma G(x) + t F(x),
 * and its endpoint certified and classified: real, complex, singular (a
 * multiple root, a point of a positive-dimensional component, Figure
 * 5(c)-(d), or a root too ill-conditioned to certify), or failed. The tracker
 * and the certificate are in homotopy_track.c.
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

#include "homotopy_track.h"
#include "internal.h"

/* First tracking pass. The predictor error target is the smaller of
 * pred_rel |x| and pred_sep times the separation radius r (the distance to
 * the nearest other path); a first Newton correction above corr_sep r
 * rejects the step (0.2 keeps the Kantorovich quantity 2 |d| / r at <= 0.4,
 * and a jump would need a predictor error of 0.8 r, 16 times the target).
 * A path still short of t = 1 at 1 - t = sigma_end is heading for a singular
 * endpoint (the series' radius shrinks with 1 - t) and is classified there.
 * The values were chosen on the hexagonal sail's flat state (s = 15), where
 * they give the same accounting as settings 10x and 100x tighter. */
static const hom_settings BASE_SETTINGS = {1e-4, 0.05, 0.2, 1e-10};
/* Each re-tracking round multiplies the three tolerances by TIGHTEN and
 * sigma_end by SIGMA_TIGHTEN. */
static const double TIGHTEN = 0.1, SIGMA_TIGHTEN = 0.01;
enum { RETRACK_ROUNDS = 3 };
/* Two endpoints approximate the same root if they are closer than
 * SAME_FRACTION times the smaller uniqueness radius (by the certificate the
 * roots in their existence balls then coincide). */
static const double SAME_FRACTION = 0.5;
/* Sort-key window: two approximations of one root differ by at most the sum
 * of their existence radii (each <= 1e-8 |z|, see homotopy_track.c), which
 * moves the key by at most 8e-8; pairs farther apart in key are distinct. */
static const double KEY_WINDOW = 1e-6;

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

/* the caller's progress callback and what it has been told */
typedef struct hom_report {
    kin_progress_fn fn;
    void *user;
    double base;  /* paths tracked in earlier runs */
    double total; /* 2^s plus the paths scheduled for re-tracking so far */
    double last;  /* time of the last call (seconds, monotonic) */
    int cancelled;
} hom_report;

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
    const int *list; /* paths to track, NULL: 0 .. n-1 */
    hom_queue *queue;
    hom_ws *ws;
    hom_end *ends;
    double *zr, *zi;
} hom_job;

/* Track chunks of paths until the queue is empty or stopped; R (the
 * calling thread only, else NULL) reports progress between paths. */
static void track_chunks(hom_job *J, hom_report *R)
{
    hom_queue *q = J->queue;
    int m = J->P->m;
    for (;;) {
        pthread_mutex_lock(&q->lock);
        int first = q->next, last = first + PATH_CHUNK < q->n ? first + PATH_CHUNK : q->n;
        if (q->stop) last = first;
        q->next = last;
        pthread_mutex_unlock(&q->lock);
        if (first >= last) break;
        for (int i = first; i < last; ++i) {
            int p = J->list ? J->list[i] : i;
            kin__hom_track(J->P, J->S, J->ws, p, J->zr + (size_t)p * m, J->zi + (size_t)p * m, &J->ends[p]);
            pthread_mutex_lock(&q->lock);
            q->tracked++;
            int stop = q->stop;
            pthread_mutex_unlock(&q->lock);
            if (R) report(R, q, 0);
            if (stop || (R && R->cancelled)) break;
        }
    }
}

static void *worker(void *arg)
{
    hom_job *J = arg;
    track_chunks(J, NULL);
    pthread_mutex_lock(&J->queue->lock);
    J->queue->active--;
    pthread_cond_signal(&J->queue->idle);
    pthread_mutex_unlock(&J->queue->lock);
    return NULL;
}

/* Track the paths of list (n of them; NULL: all n) on nthreads threads,
 * reporting through R; R->cancelled says whether the caller stopped it
 * (then some paths were not tracked). */
static int run_paths(const hom_problem *P, const hom_settings *S, const int *list, int n, int nthreads,
                     hom_ws **ws, hom_job *jobs, pthread_t *th, int *running, hom_end *ends, double *zr,
                     double *zi, hom_report *R)
{
    hom_queue q;
    memset(&q, 0, sizeof q);
    q.n = n;
    if (pthread_mutex_init(&q.lock, NULL) != 0) return KIN_ENOMEM;
    if (pthread_cond_init(&q.idle, NULL) != 0) {
        pthread_mutex_destroy(&q.lock);
        return KIN_ENOMEM;
    }
    for (int t = 0; t < nthreads; ++t) jobs[t] = (hom_job){P, S, list, &q, ws[t], ends, zr, zi};
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
    track_chunks(&jobs[0], R);
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

static int key_cmp(const void *a, const void *b)
{
    const hom_key *x = a, *y = b;
    if (x->key < y->key) return -1;
    if (x->key > y->key) return 1;
    return (x->path > y->path) - (x->path < y->path);
}

int kin__hom_find(int *parent, int p)
{
    while (parent[p] != p) {
        parent[p] = parent[parent[p]];
        p = parent[p];
    }
    return p;
}

static void unite(int *parent, int p, int q)
{
    p = kin__hom_find(parent, p), q = kin__hom_find(parent, q);
    if (p < q) parent[q] = p;
    else if (q < p) parent[p] = q;
}

/* Do endpoints p and q (q conjugated if conj) approximate the same root?
 * Compared in p's chart. */
static int same_root(int m, const hom_end *ep, const double *pr, const double *pi, const hom_end *eq,
                     const double *qr, const double *qi, int conj)
{
    int k = ep->chart;
    double sg = conj ? -1.0 : 1.0, a = qr[k], b = sg * qi[k], d = a * a + b * b, dist2 = 0.0;
    if (!(d > 0.0)) return 0;
    for (int c = 0; c < m; ++c) {
        double vr = (qr[c] * a + sg * qi[c] * b) / d, vi = (sg * qi[c] * a - qr[c] * b) / d;
        dist2 += (pr[c] - vr) * (pr[c] - vr) + (pi[c] - vi) * (pi[c] - vi);
    }
    return sqrt(dist2) <= SAME_FRACTION * fmin(ep->rplus, eq->rplus);
}

hom_checks kin__hom_check(int m, int npaths, const hom_end *ends, const double *zr, const double *zi, const double *w,
                          hom_key *keys, int *parent, unsigned char *paired)
{
    hom_checks c = {0, 0};
    int n = 0;
    for (int p = 0; p < npaths; ++p) {
        parent[p] = p;
        paired[p] = 0;
        if (ends[p].kind != HOM_REAL && ends[p].kind != HOM_NONREAL) continue;
        const double *xr = zr + (size_t)p * m, *xi = zi + (size_t)p * m;
        double wr = 0.0, wi = 0.0, nz = 0.0;
        for (int i = 0; i < m; ++i) {
            wr += w[i] * xr[i], wi += w[i] * xi[i];
            nz += xr[i] * xr[i] + xi[i] * xi[i];
        }
        keys[n++] = (hom_key){(wr * wr + wi * wi) / nz, p};
    }
    qsort(keys, (size_t)n, sizeof *keys, key_cmp);
    for (int i = 0; i < n; ++i) {
        int p = keys[i].path;
        const double *pr = zr + (size_t)p * m, *pi = zi + (size_t)p * m;
        for (int j = i + 1; j < n && keys[j].key - keys[i].key <= KEY_WINDOW; ++j) {
            int q = keys[j].path;
            const double *qr = zr + (size_t)q * m, *qi = zi + (size_t)q * m;
            if (same_root(m, &ends[p], pr, pi, &ends[q], qr, qi, 0)) unite(parent, p, q);
            if (ends[p].kind == HOM_NONREAL && ends[q].kind == HOM_NONREAL &&
                same_root(m, &ends[p], pr, pi, &ends[q], qr, qi, 1))
                paired[p] = paired[q] = 1;
        }
    }
    for (int i = 0; i < n; ++i) {
        int p = keys[i].path;
        if (kin__hom_find(parent, p) != p) c.duplicates++;
        if (ends[p].kind == HOM_NONREAL && !paired[p]) c.unpaired++;
    }
    return c;
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

int kin_quadrics_homotopy(int m, int s, const double *Q, unsigned long seed, int nthreads, double *betas,
                          int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.seed = seed;
    o.nthreads = nthreads < 1 ? -1 : nthreads; /* 0 means "all processors" only in the options */
    return kin_quadrics_homotopy_ex(m, s, Q, &o, betas, maxsol, nsol, multiplicity, info);
}

static int homotopy_impl(int m, int s, const double *Q, const kin_homotopy_options *opt, double *betas, int maxsol,
                         int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (nsol) *nsol = 0;
    if (info) memset(info, 0, sizeof *info);
    kin_homotopy_options o;
    if (opt) o = *opt;
    else kin_homotopy_options_default(&o);
    if (!Q || !betas || !nsol || !info) return KIN_ENULL;
    if (m < 2 || s != m - 1 || maxsol < 1 || o.nthreads < 0 || o.max_paths < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE; /* so 2^s <= 2^23 and every size below fits */
    for (size_t i = 0; i < (size_t)m * m * s; ++i)
        if (!isfinite(Q[i])) return KIN_EINVAL;
    if ((1L << s) > o.max_paths) return KIN_ELIMIT;
    int npaths = 1 << s;
    int cpus = online_processors();
    int nthreads = o.nthreads == 0 || o.nthreads > cpus ? cpus : o.nthreads;
    if (nthreads > npaths) nthreads = npaths; /* more would idle; the result is the same */
    unsigned long seed = o.seed;
    hom_report R = {o.progress, o.user, 0.0, (double)npaths, 0.0, 0};
    size_t mm = (size_t)m * m;
    size_t nrows = ((size_t)s * m + HOM_QBLOCK - 1) / HOM_QBLOCK * HOM_QBLOCK;
    double *Qr = malloc(sizeof(double) * mm * (size_t)s), *Qb = calloc(nrows * m, sizeof(double));
    hom_end *ends = malloc(sizeof(hom_end) * (size_t)npaths);
    double *zr = malloc(sizeof(double) * (size_t)npaths * (size_t)m);
    double *zi = malloc(sizeof(double) * (size_t)npaths * (size_t)m);
    hom_key *keys = malloc(sizeof(hom_key) * (size_t)npaths);
    int *parent = malloc(sizeof(int) * (size_t)npaths), *list = malloc(sizeof(int) * (size_t)npaths);
    int *size = calloc((size_t)npaths, sizeof(int));
    unsigned char *paired = malloc((size_t)npaths);
    hom_job *jobs = malloc(sizeof(hom_job) * (size_t)nthreads);
    pthread_t *th = malloc(sizeof(pthread_t) * (size_t)nthreads);
    int *running = calloc((size_t)nthreads, sizeof(int));
    hom_ws **ws = calloc((size_t)nthreads, sizeof(hom_ws *));
    int rc = KIN_OK;
    if (!Qr || !Qb || !ends || !zr || !zi || !keys || !parent || !list || !size || !paired || !jobs || !th || !running ||
        !ws)
        rc = KIN_ENOMEM;
    for (int t = 0; !rc && t < nthreads; ++t)
        if (!(ws[t] = kin__hom_ws_new())) rc = KIN_ENOMEM;
    if (rc) goto done;

    /* the problem: Q_j scaled to unit Frobenius norm (the roots do not
     * change; the tolerances then mean the same for every input), by rows
     * and in blocks of rows for Q x */
    hom_problem P;
    memset(&P, 0, sizeof P);
    P.m = m, P.s = s, P.Qr = Qr, P.Qb = Qb;
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
    P.normF = sqrt(nf2);
    for (size_t i = 0; i < (size_t)s * m; ++i) /* row i to block i / B, slot i % B */
        for (int c = 0; c < m; ++c)
            Qb[(i / HOM_QBLOCK) * HOM_QBLOCK * m + (size_t)c * HOM_QBLOCK + i % HOM_QBLOCK] = Qr[i * m + c];
    P.normG = sqrt((double)s);
    unsigned long long st = (unsigned long long)seed * 0x2545F4914F6CDD1Dull + 7u;
    double th0 = 6.283185307179586 * ((kin__splitmix(&st) >> 11) * 0x1.0p-53);
    P.gr = cos(th0), P.gi = sin(th0);
    for (int i = 0; i < m; ++i) {
        double a = 6.283185307179586 * ((kin__splitmix(&st) >> 11) * 0x1.0p-53);
        P.ar[i] = cos(a), P.ai[i] = sin(a);
    }
    /* the sort key's direction: a fixed random unit vector */
    double w[HOM_MAX_M], wn = 0.0;
    for (int i = 0; i < m; ++i) {
        w[i] = ((kin__splitmix(&st) >> 11) * 0x1.0p-53) - 0.5;
        wn += w[i] * w[i];
    }
    for (int i = 0; i < m; ++i) w[i] /= sqrt(wn);

    hom_settings S = BASE_SETTINGS;
    report(&R, NULL, 1);
    if (!R.cancelled && (rc = run_paths(&P, &S, NULL, npaths, nthreads, ws, jobs, th, running, ends, zr, zi, &R)))
        goto done;
    if (R.cancelled) goto cancelled;
    hom_checks ck = kin__hom_check(m, npaths, ends, zr, zi, w, keys, parent, paired);
    int retracked = 0;
    for (int round = 1; round <= RETRACK_ROUNDS; ++round) {
        /* the suspects: failed paths, every path on a root reached more than
         * once, non-real endpoints without a conjugate and, from the second
         * round on while conjugates are missing, the singular endpoints (a
         * lost conjugate may have been taken for one) */
        memset(size, 0, sizeof(int) * (size_t)npaths);
        for (int p = 0; p < npaths; ++p)
            if (ends[p].kind == HOM_REAL || ends[p].kind == HOM_NONREAL) size[kin__hom_find(parent, p)]++;
        int n = 0;
        for (int p = 0; p < npaths; ++p) {
            int k = ends[p].kind;
            int sus = k == HOM_FAILED || ((k == HOM_REAL || k == HOM_NONREAL) && size[kin__hom_find(parent, p)] > 1) ||
                      (k == HOM_NONREAL && !paired[p]) || (k == HOM_SINGULAR && round >= 2 && ck.unpaired > 0);
            if (sus) list[n++] = p;
        }
        if (!n) break;
        S.pred_rel *= TIGHTEN, S.pred_sep *= TIGHTEN, S.corr_sep *= TIGHTEN;
        S.sigma_end *= SIGMA_TIGHTEN;
        R.total += n;
        if ((rc = run_paths(&P, &S, list, n, nthreads, ws, jobs, th, running, ends, zr, zi, &R))) goto done;
        if (R.cancelled) goto cancelled;
        retracked += n;
        ck = kin__hom_check(m, npaths, ends, zr, zi, w, keys, parent, paired);
    }

    memset(info, 0, sizeof *info);
    info->paths = npaths;
    info->retracked = retracked;
    info->duplicates = ck.duplicates;
    info->unpaired = ck.unpaired;
    memset(size, 0, sizeof(int) * (size_t)npaths);
    for (int p = 0; p < npaths; ++p) {
        const hom_end *e = &ends[p];
        info->steps += e->steps;
        info->rejected += e->rejected;
        switch (e->kind) {
        case HOM_REAL: info->real++; break;
        case HOM_NONREAL: info->nonreal++; break;
        case HOM_SINGULAR:
            info->singular++;
            if (e->converged) info->uncertified++;
            continue;
        default: info->failed++; continue;
        }
        if (e->cond > info->max_cond) info->max_cond = e->cond;
        if (e->kind == HOM_REAL) size[kin__hom_find(parent, p)]++;
    }
    int nd = 0;
    for (int p = 0; p < npaths; ++p) {
        if (ends[p].kind != HOM_REAL || kin__hom_find(parent, p) != p) continue;
        double b[HOM_MAX_M];
        memcpy(b, zr + (size_t)p * m, sizeof(double) * (size_t)m);
        double nb = kin__norm(m, b);
        int big = 0;
        for (int i = 0; i < m; ++i) {
            b[i] /= nb;
            if (fabs(b[i]) > fabs(b[big])) big = i;
        }
        if (b[big] < 0)
            for (int i = 0; i < m; ++i) b[i] = -b[i];
        for (int j = 0; j < s; ++j) { /* residual of the unit solution, Q_j / |Q_j|_F */
            const double *q = Qr + (size_t)j * mm;
            double v = 0.0;
            for (int r = 0; r < m; ++r)
                for (int c = 0; c < m; ++c) v += b[r] * q[(size_t)r * m + c] * b[c];
            if (fabs(v) > info->max_residual) info->max_residual = fabs(v);
        }
        if (nd < maxsol) {
            memcpy(betas + (size_t)nd * m, b, sizeof(double) * (size_t)m);
            if (multiplicity) multiplicity[nd] = size[p];
        }
        ++nd;
    }
    info->real_distinct = nd;
    *nsol = nd < maxsol ? nd : maxsol;
    if (R.fn) R.fn(R.user, R.total, R.total); /* finished: its answer no longer matters */
    goto done;

cancelled:
    memset(info, 0, sizeof *info);
    *nsol = 0;
    rc = KIN_ECANCELLED;
done:
    if (ws)
        for (int t = 0; t < nthreads; ++t) kin__hom_ws_free(ws[t]);
    free(ws), free(running), free(th), free(jobs), free(paired), free(size), free(list), free(parent);
    free(keys), free(zi), free(zr), free(ends), free(Qb), free(Qr);
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
    kin_homotopy_options_default(&o); /* fields an older caller does not have keep their defaults */
    if (opt) {
        if (kin__abi_check(opt, KIN__V1_SIZE(kin_homotopy_options, user), sizeof *opt)) return KIN_EINVAL;
        kin__abi_read(&o, opt, sizeof o);
    }
    kin_homotopy_info local = {.size = sizeof local};
    int rc = homotopy_impl(m, s, Q, &o, betas, maxsol, nsol, multiplicity, &local);
    kin__abi_write(info, &local, sizeof local);
    return rc;
}
