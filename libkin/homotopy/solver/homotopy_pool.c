/* The complete solvers' thread pool (homotopy_pool.h). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <pthread.h>
#include <stdlib.h>
#include <time.h>

#include "homotopy/solver/homotopy_pool.h"

typedef struct hom_worker {
    hom_pool *P;
    int t;
} hom_worker;

struct hom_pool {
    int nthreads;
    pthread_t *th;
    int *started;
    hom_worker *w;
    pthread_mutex_t lock;
    pthread_cond_t idle; /* signalled when a started worker returns */
    /* the run: */
    const hom_pool_job *job;
    int next, n; /* next item to hand out, of n */
    long done;   /* items finished */
    int active;  /* started workers still running */
    int stop;    /* cancelled: hand out no more items */
};

double kin__hom_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

hom_pool *kin__hom_pool_new(int nthreads)
{
    if (nthreads < 1) nthreads = 1;
    hom_pool *P = calloc(1, sizeof *P);
    if (!P) return NULL;
    P->nthreads = nthreads;
    P->th = malloc(sizeof(pthread_t) * (size_t)nthreads);
    P->started = calloc((size_t)nthreads, sizeof(int));
    P->w = malloc(sizeof(hom_worker) * (size_t)nthreads);
    int lock = 0;
    if (P->th && P->started && P->w && (lock = pthread_mutex_init(&P->lock, NULL) == 0) &&
        pthread_cond_init(&P->idle, NULL) == 0)
        return P;
    if (lock) pthread_mutex_destroy(&P->lock);
    free(P->th), free(P->started), free(P->w), free(P);
    return NULL;
}

void kin__hom_pool_free(hom_pool *P)
{
    if (!P) return;
    pthread_cond_destroy(&P->idle);
    pthread_mutex_destroy(&P->lock);
    free(P->th), free(P->started), free(P->w), free(P);
}

int kin__hom_pool_take(hom_pool *P, int chunk, int *first)
{
    pthread_mutex_lock(&P->lock);
    int f = P->next, k = P->stop ? -1 : P->n - f < chunk ? P->n - f : chunk;
    if (k > 0) P->next = f + k;
    pthread_mutex_unlock(&P->lock);
    *first = f;
    return k < 0 ? -1 : k;
}

/* the progress hook (calling thread): a cancel stops the counter */
static void progress(hom_pool *P)
{
    const hom_pool_job *J = P->job;
    if (!J->progress) return;
    pthread_mutex_lock(&P->lock);
    long done = P->done;
    int stop = P->stop;
    pthread_mutex_unlock(&P->lock);
    if (!stop && J->progress(J->ctx, done)) {
        pthread_mutex_lock(&P->lock);
        P->stop = 1;
        pthread_mutex_unlock(&P->lock);
    }
}

int kin__hom_pool_done(hom_pool *P, int t)
{
    pthread_mutex_lock(&P->lock);
    P->done++;
    pthread_mutex_unlock(&P->lock);
    if (t == 0) progress(P);
    pthread_mutex_lock(&P->lock);
    int stop = P->stop;
    pthread_mutex_unlock(&P->lock);
    return stop;
}

static void *worker(void *arg)
{
    hom_worker *W = arg;
    hom_pool *P = W->P;
    P->job->work(P->job->ctx, W->t);
    pthread_mutex_lock(&P->lock);
    P->active--;
    pthread_cond_signal(&P->idle);
    pthread_mutex_unlock(&P->lock);
    return NULL;
}

long kin__hom_pool_run(hom_pool *P, int n, const hom_pool_job *J)
{
    int nt = P->nthreads < n ? P->nthreads : n;
    P->job = J;
    P->next = 0, P->n = n, P->done = 0, P->active = 0, P->stop = 0;
    for (int t = 1; t < nt; ++t) {
        P->w[t] = (hom_worker){P, t};
        pthread_mutex_lock(&P->lock);
        P->active++;
        pthread_mutex_unlock(&P->lock);
        P->started[t] = pthread_create(&P->th[t], NULL, worker, &P->w[t]) == 0;
        if (!P->started[t]) {
            pthread_mutex_lock(&P->lock);
            P->active--;
            pthread_mutex_unlock(&P->lock);
        }
    }
    if (n > 0) J->work(J->ctx, 0);
    /* the others finish their last items: keep reporting meanwhile */
    pthread_mutex_lock(&P->lock);
    while (P->active > 0) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        ts.tv_nsec += (long)(HOM_POOL_REPORT * 1e9);
        if (ts.tv_nsec >= 1000000000L) ts.tv_sec++, ts.tv_nsec -= 1000000000L;
        pthread_cond_timedwait(&P->idle, &P->lock, &ts);
        if (P->active > 0 && J->progress && !P->stop) {
            pthread_mutex_unlock(&P->lock);
            progress(P);
            pthread_mutex_lock(&P->lock);
        }
    }
    long done = P->done;
    pthread_mutex_unlock(&P->lock);
    for (int t = 1; t < nt; ++t)
        if (P->started[t]) pthread_join(P->th[t], NULL);
    P->job = NULL;
    return done;
}
