/* The complete solvers' thread pool (libkin/homotopy/solver/homotopy_pool.c):
 * every item handed out exactly once, in increasing order from the shared
 * counter, whatever the thread count and chunk size; progress reports and
 * the cancel only on the calling thread; a cancel mid-run stops the counter
 * and the run returns with the items finished before it. Then the plain
 * solver's result does not depend on the thread count, and a cancel from a
 * later progress call (inside the pool's run) gives KIN_ECANCELLED. */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "homotopy/solver/homotopy_pool.h"

enum { N = 2000, MAXT = 4 };

typedef struct ctx {
    hom_pool *P;
    int chunk;
    int count[N];      /* times item i was taken */
    int owner[N];      /* the worker that took it */
    double value[N];   /* its result (depends on i only) */
    int last[MAXT];    /* the last item each worker took (increasing order) */
    int order_ok;
    pthread_t caller;
    int foreign_progress; /* progress called off the calling thread */
    int progress_calls;
    long cancel_at;    /* cancel when done reaches it (0: never) */
    int stopped_seen;
} ctx;

static void work(void *arg, int t)
{
    ctx *c = arg;
    int first, k;
    while ((k = kin__hom_pool_take(c->P, c->chunk, &first)) > 0) {
        if (first <= c->last[t]) c->order_ok = 0;
        for (int i = first; i < first + k; ++i) {
            double v = 0.0; /* a little work, a result that depends on i only */
            for (int r = 1; r <= 20000; ++r) v += 1.0 / (r + i);
            __atomic_fetch_add(&c->count[i], 1, __ATOMIC_RELAXED);
            c->owner[i] = t, c->value[i] = v;
            c->last[t] = i;
            if (kin__hom_pool_done(c->P, t)) {
                __atomic_store_n(&c->stopped_seen, 1, __ATOMIC_RELAXED);
                return; /* abandon the rest of the chunk */
            }
        }
    }
}

static int progress(void *arg, long done)
{
    ctx *c = arg;
    if (!pthread_equal(pthread_self(), c->caller)) c->foreign_progress = 1;
    c->progress_calls++;
    return c->cancel_at > 0 && done >= c->cancel_at;
}

static void run(int nthreads, int chunk, long cancel_at, ctx *c)
{
    memset(c, 0, sizeof *c);
    for (int t = 0; t < MAXT; ++t) c->last[t] = -1;
    c->order_ok = 1, c->chunk = chunk, c->cancel_at = cancel_at, c->caller = pthread_self();
    c->P = kin__hom_pool_new(nthreads);
    CHECK(c->P != NULL);
    if (!c->P) return;
    hom_pool_job J = {work, progress, c};
    long done = kin__hom_pool_run(c->P, N, &J);
    long taken = 0;
    for (int i = 0; i < N; ++i) taken += c->count[i];
    CHECK(done == taken);
    CHECK(c->order_ok);
    CHECK(!c->foreign_progress);
    CHECK(c->progress_calls > 0);
    for (int i = 0; i < N; ++i) CHECK(c->count[i] <= 1);
    if (!cancel_at) {
        CHECK(done == N && !c->stopped_seen);
    } else {
        CHECK(c->stopped_seen);
        CHECK(done >= cancel_at && done < N);
    }
    /* the pool is reusable: an empty run, then a full one */
    hom_pool_job E = {work, NULL, c};
    CHECK(kin__hom_pool_run(c->P, 0, &E) == 0);
    kin__hom_pool_free(c->P);
}

static int cancel_second(void *user, double done, double total)
{
    (void)done, (void)total;
    return ++*(int *)user >= 2;
}

int main(void)
{
    static ctx a, b;
    run(1, 1, 0, &a);
    double ref[N];
    memcpy(ref, a.value, sizeof ref);
    for (int nt = 1; nt <= MAXT; ++nt)
        for (int chunk = 1; chunk <= 16; chunk *= 4) {
            run(nt, chunk, 0, &b);
            CHECK(memcmp(ref, b.value, sizeof ref) == 0); /* results by index: the same */
            if (nt == 1) /* one worker: the calling thread takes every item, in order */
                for (int i = 0; i < N; ++i) CHECK(b.owner[i] == 0);
            run(nt, chunk, 100, &b); /* cancelled by the calling thread mid-run */
        }

    /* the plain solver: the same result on 1 and 2 threads; cancelled
     * mid-run from the third progress call */
    enum { M = 11, S = M - 1, NP = 1 << S };
    double Q[M * M * S];
    unsigned long long st = 7;
    for (int i = 0; i < M * M * S; ++i) {
        st = st * 6364136223846793005ull + 1442695040888963407ull;
        Q[i] = (double)(st >> 11) * 0x1.0p-53 - 0.5;
    }
    static double b1[M * NP], b2[M * NP];
    int n1 = 0, n2 = 0;
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
    o.nthreads = 1;
    CHECK_RC(kin_quadrics_homotopy_ex(M, S, Q, &o, b1, NP, &n1, NULL, &h1), KIN_OK);
    o.nthreads = 2;
    CHECK_RC(kin_quadrics_homotopy_ex(M, S, Q, &o, b2, NP, &n2, NULL, &h2), KIN_OK);
    CHECK(n1 == n2 && n1 > 0 && memcmp(b1, b2, sizeof(double) * (size_t)M * n1) == 0);
    CHECK(h1.steps == h2.steps && h1.rejected == h2.rejected && h1.real == h2.real && h1.nonreal == h2.nonreal);
    CHECK(h1.real + h1.nonreal == NP);
    int calls = 0;
    o.progress = cancel_second, o.user = &calls;
    CHECK_RC(kin_quadrics_homotopy_ex(M, S, Q, &o, b2, NP, &n2, NULL, &h2), KIN_ECANCELLED);
    CHECK(calls == 2 && n2 == 0 && h2.paths == 0);
    TEST_REPORT("test_homotopy_pool");
}
