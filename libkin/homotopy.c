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
 * which path. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

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

typedef struct hom_queue {
    pthread_mutex_t lock;
    int next, n;
} hom_queue;

typedef struct hom_job {
    const hom_problem *P;
    const hom_settings *S;
    const int *list; /* paths to track, NULL: 0 .. n-1 */
    hom_queue *queue;
    hom_ws *ws;
    hom_end *ends;
    double *zr, *zi;
} hom_job;

static void *worker(void *arg)
{
    hom_job *J = arg;
    int m = J->P->m;
    for (;;) {
        pthread_mutex_lock(&J->queue->lock);
        int first = J->queue->next, last = first + PATH_CHUNK < J->queue->n ? first + PATH_CHUNK : J->queue->n;
        J->queue->next = last;
        pthread_mutex_unlock(&J->queue->lock);
        if (first >= last) break;
        for (int i = first; i < last; ++i) {
            int p = J->list ? J->list[i] : i;
            kin__hom_track(J->P, J->S, J->ws, p, J->zr + (size_t)p * m, J->zi + (size_t)p * m, &J->ends[p]);
        }
    }
    return NULL;
}

/* track the paths of list (n of them; NULL: all n) on nthreads threads */
static int run_paths(const hom_problem *P, const hom_settings *S, const int *list, int n, int nthreads,
                     hom_ws **ws, hom_job *jobs, pthread_t *th, int *running, hom_end *ends, double *zr,
                     double *zi)
{
    hom_queue q;
    q.next = 0, q.n = n;
    if (pthread_mutex_init(&q.lock, NULL) != 0) return KIN_ENOMEM;
    for (int t = 0; t < nthreads; ++t) jobs[t] = (hom_job){P, S, list, &q, ws[t], ends, zr, zi};
    /* thread 0 is this one; threads that cannot be started leave their
     * share to the others */
    for (int t = 1; t < nthreads; ++t) running[t] = pthread_create(&th[t], NULL, worker, &jobs[t]) == 0;
    worker(&jobs[0]);
    for (int t = 1; t < nthreads; ++t)
        if (running[t]) pthread_join(th[t], NULL);
    pthread_mutex_destroy(&q.lock);
    return KIN_OK;
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

static int homotopy_impl(int m, int s, const double *Q, unsigned long seed, int nthreads, double *betas,
                         int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (!Q || !betas || !nsol || !info) return KIN_ENULL;
    if (m < 2 || s != m - 1 || maxsol < 1 || nthreads < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE;
    int npaths = 1 << s;
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
        double f = 0.0, n1 = 0.0;
        for (size_t i = 0; i < mm; ++i) f += q[i] * q[i];
        f = sqrt(f);
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
    if ((rc = run_paths(&P, &S, NULL, npaths, nthreads, ws, jobs, th, running, ends, zr, zi))) goto done;
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
        if ((rc = run_paths(&P, &S, list, n, nthreads, ws, jobs, th, running, ends, zr, zi))) goto done;
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

done:
    if (ws)
        for (int t = 0; t < nthreads; ++t) kin__hom_ws_free(ws[t]);
    free(ws), free(running), free(th), free(jobs), free(paired), free(size), free(list), free(parent);
    free(keys), free(zi), free(zr), free(ends), free(Qb), free(Qr);
    return rc;
}

int kin_quadrics_homotopy(int m, int s, const double *Q, unsigned long seed, int nthreads, double *betas,
                          int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (!info) return KIN_ENULL;
    if (kin__abi_check(info, KIN__V1_SIZE(kin_homotopy_info, max_cond), sizeof *info)) return KIN_EINVAL;
    kin__abi_zero(info);
    kin_homotopy_info local = {.size = sizeof local};
    int rc = homotopy_impl(m, s, Q, seed, nthreads, betas, maxsol, nsol, multiplicity, &local);
    kin__abi_write(info, &local, sizeof local);
    return rc;
}
