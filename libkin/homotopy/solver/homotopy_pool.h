/* Private: the one thread pool of the complete solvers (homotopy_solver.c's
 * path runs, homotopy_sym.c's monodromy loops and legs to Q). A run hands
 * out the work items 0 .. n-1 in increasing order from one locked counter
 * to the calling thread (worker 0) and up to nthreads - 1 started threads
 * (workers 1..), each with the workspaces its caller set up for it: results
 * stored by item index then do not depend on the thread count nor on which
 * worker took which item. Progress reports and the cancel come from the
 * calling thread only (a Python caller's signal handlers run in its own
 * thread): after each item it finishes, and every HOM_POOL_REPORT seconds
 * while it waits for the others. A cancel stops the counter; the items in
 * flight are abandoned by their workers (kin__hom_pool_done says so). The
 * pool allocates nothing while it runs (pthread_create aside). */
#ifndef KIN_HOMOTOPY_POOL_H
#define KIN_HOMOTOPY_POOL_H

typedef struct hom_pool hom_pool;

/* a pool of nthreads >= 1 workers (the calling thread and nthreads - 1 to
 * start at each run); NULL if out of memory */
hom_pool *kin__hom_pool_new(int nthreads);
void kin__hom_pool_free(hom_pool *P);

/* one run's work */
typedef struct hom_pool_job {
    /* worker t's loop (t = 0: the calling thread): take items with
     * kin__hom_pool_take until there are none, report each finished one
     * with kin__hom_pool_done */
    void (*work)(void *ctx, int t);
    /* NULL, or the progress hook, called on the calling thread only with
     * the items finished so far in this run; nonzero cancels the run */
    int (*progress)(void *ctx, long done);
    void *ctx;
} hom_pool_job;

/* Run J on min(nthreads, n) workers over the items 0 .. n-1 (workers that
 * cannot be started leave their share to the others); returns when every
 * worker has returned, with the number of items finished. */
long kin__hom_pool_run(hom_pool *P, int n, const hom_pool_job *J);
/* The next items for a worker: at most `chunk` (>= 1) consecutive ones from
 * *first; returns their count, 0 when none is left, -1 once the run was
 * cancelled (abandon the items held). */
int kin__hom_pool_take(hom_pool *P, int chunk, int *first);
/* Worker t finished an item: counted and, on the calling thread (t = 0),
 * the progress hook called. Returns 1 once the run was cancelled. */
int kin__hom_pool_done(hom_pool *P, int t);

/* seconds on a monotonic clock (the progress reports' rate limit) */
double kin__hom_seconds(void);
/* seconds between progress reports: short enough for Ctrl-C to feel
 * immediate, long enough to cost nothing next to the tracking */
#define HOM_POOL_REPORT 0.05

#endif /* KIN_HOMOTOPY_POOL_H */
