/* The lockstep tracker (homotopy_batch.c) against the one-path reference
 * tracker (kin__hom_track): every path's endpoint record and coordinates
 * must be the same bit for bit (the batch runs each lane through the same
 * operations in the same order), whatever order the paths are handed out in
 * and whichever paths share a batch; random systems of every size class
 * (m = 2 .. 24) and the hexagonal sail's flat state (clustered paths:
 * rejected steps, chart changes), with the first pass's settings and the
 * tightened ones of a re-track; a stop abandons the paths in flight. */
#include <string.h>

#include "check.h"
#include "homotopy/solver/homotopy_solver.h"
#include "homotopy/track/homotopy_control.h"
#include "model/internal.h"
#include "libkin.h"
#include "sail_states.h"

/* the sink: paths from a list, endpoints stored by path index */
typedef struct sink_ctx {
    const int *list;
    int n, next, stop_after, handed, done;
    int m;
    hom_end *ends;
    double *zr, *zi;
    unsigned char *seen;
} sink_ctx;

static int sink_next(void *ctx)
{
    sink_ctx *c = ctx;
    if (c->stop_after >= 0 && c->handed >= c->stop_after) return HOM_BATCH_STOP;
    if (c->next >= c->n) return -1;
    c->handed++;
    return c->list[c->next++];
}

static void sink_done(void *ctx, int path, const double *zr, const double *zi, const hom_end *e)
{
    sink_ctx *c = ctx;
    c->done++;
    c->seen[path]++;
    c->ends[path] = *e;
    memcpy(c->zr + (size_t)path * c->m, zr, sizeof(double) * (size_t)c->m);
    memcpy(c->zi + (size_t)path * c->m, zi, sizeof(double) * (size_t)c->m);
}

static int same_double(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

/* records and coordinates of path p identical (an exact zero may differ in sign) */
static int same_end(int m, const hom_end *a, const hom_end *b, const double *ar, const double *ai, const double *br,
                    const double *bi)
{
    int ok = a->kind == b->kind && a->chart == b->chart && a->steps == b->steps && a->rejected == b->rejected &&
             a->recharts == b->recharts && a->converged == b->converged && same_double(a->rminus, b->rminus) &&
             same_double(a->rplus, b->rplus) && same_double(a->cond, b->cond) && same_double(a->sigma, b->sigma);
    for (int c = 0; c < m; ++c) ok = ok && same_double(ar[c], br[c]) && same_double(ai[c], bi[c]);
    return ok;
}

/* s random symmetric m x m matrices */
static void random_quadrics(int m, int s, unsigned long long seed, double *Q)
{
    unsigned long long st = seed;
    for (int j = 0; j < s; ++j)
        for (int r = 0; r < m; ++r)
            for (int c = r; c < m; ++c) {
                double v = (double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5;
                Q[(size_t)j * m * m + r + (size_t)c * m] = Q[(size_t)j * m * m + c + (size_t)r * m] = v;
            }
}

typedef struct totals {
    long paths, rejected, recharts, kinds[4];
} totals;

/* paths `paths[0..n-1]` of the system: the reference one by one, the batch
 * in the given order and in a shuffled one; all three must agree */
static void compare(const char *name, int m, const double *Q, const hom_settings *S, const int *paths, int n,
                    totals *T)
{
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = 1;
    hom_solver H;
    int rc = kin__hom_solver_init(&H, m, m - 1, Q, &o, n);
    CHECK(rc == KIN_OK);
    int np = 1 << (m - 1);
    hom_end *ref = calloc((size_t)np, sizeof *ref), *got = calloc((size_t)np, sizeof *got);
    double *rzr = calloc((size_t)np * m, sizeof(double)), *rzi = calloc((size_t)np * m, sizeof(double));
    double *gzr = calloc((size_t)np * m, sizeof(double)), *gzi = calloc((size_t)np * m, sizeof(double));
    unsigned char *seen = calloc((size_t)np, 1);
    int *order = malloc(sizeof(int) * (size_t)n);
    hom_bws *B = kin__hom_bws_new();
    if (rc != KIN_OK || !ref || !got || !rzr || !rzi || !gzr || !gzi || !seen || !order || !B) {
        CHECK(!"allocation");
        goto done;
    }
    hom_ws *w = kin__hom_pool_ws(&H, 0);
    for (int i = 0; i < n; ++i) {
        int p = paths[i];
        kin__hom_track(&H.P, S, w, p, rzr + (size_t)p * m, rzi + (size_t)p * m, &ref[p]);
        T->paths++, T->rejected += ref[p].rejected, T->recharts += ref[p].recharts, T->kinds[ref[p].kind & 3]++;
    }
    for (int pass = 0; pass < 2; ++pass) {
        /* pass 1: a stride-7 permutation (n is prime to 7 here), so that
         * each path shares its batch with other paths than in pass 0 */
        for (int i = 0; i < n; ++i) order[i] = pass == 0 ? paths[i] : paths[(i * 7 + 3) % n];
        memset(seen, 0, (size_t)np);
        sink_ctx c = {order, n, 0, -1, 0, 0, m, got, gzr, gzi, seen};
        hom_batch_sink K = {&c, sink_next, sink_done};
        kin__hom_track_batch(&H.P, S, B, w, &K);
        CHECK(c.done == n);
        int differ = 0;
        for (int i = 0; i < n; ++i) {
            int p = paths[i];
            CHECK(seen[p] == 1);
            if (!same_end(m, &ref[p], &got[p], rzr + (size_t)p * m, rzi + (size_t)p * m, gzr + (size_t)p * m,
                          gzi + (size_t)p * m))
                differ++;
        }
        if (differ) fprintf(stderr, "%s pass %d: %d of %d paths differ from the reference\n", name, pass, differ, n);
        CHECK(differ == 0);
    }
    /* a stop abandons the paths in flight: no more than were handed out are
     * finished, and the call returns */
    {
        memset(seen, 0, (size_t)np);
        sink_ctx c = {paths, n, 0, n > 6 ? 6 : n - 1, 0, 0, m, got, gzr, gzi, seen};
        hom_batch_sink K = {&c, sink_next, sink_done};
        kin__hom_track_batch(&H.P, S, B, w, &K);
        CHECK(c.done <= c.handed && c.handed == c.stop_after);
    }
done:
    kin__hom_bws_free(B);
    free(order), free(seen), free(ref), free(got), free(rzr), free(rzi), free(gzr), free(gzi);
    kin__hom_solver_free(&H);
}

int main(void)
{
    totals T = {0};
    hom_settings tight = kin__hom_base_settings;
    tight.pred_rel *= 0.01, tight.pred_sep *= 0.01, tight.corr_sep *= 0.01, tight.sigma_end *= 1e-4;
    int ms[] = {2, 3, 4, 5, 7, 9, 12, 17, 24};
    for (size_t k = 0; k < sizeof ms / sizeof ms[0]; ++k) {
        int m = ms[k], s = m - 1, np = 1 << s;
        double *Q = malloc(sizeof(double) * (size_t)m * m * s);
        int n = np < 23 ? np : 23, *paths = malloc(sizeof(int) * (size_t)n);
        if (!Q || !paths) return 1;
        random_quadrics(m, s, 77u + (unsigned)m, Q);
        for (int i = 0; i < n; ++i) paths[i] = (int)(((long long)i * 2654435761LL) % np);
        for (int i = 0; i < n; ++i) /* distinct paths */
            for (int j = 0; j < i; ++j)
                if (paths[j] == paths[i]) paths[i] = (paths[i] + 1) % np, j = -1;
        char name[32];
        snprintf(name, sizeof name, "random m = %d", m);
        compare(name, m, Q, &kin__hom_base_settings, paths, n, &T);
        if (m <= 9) compare(name, m, Q, &tight, paths, n, &T);
        free(Q), free(paths);
    }
    /* the hexagonal sail's flat state: 33 of its 32768 paths */
    kin_assembly *a = test_sail(6, 2);
    kin_analysis an = {.size = sizeof an};
    CHECK(a && kin_analyse(a, &an) == KIN_OK);
    if (a && an.m_internal == an.s + 1) {
        int m = an.m_internal, s = 0;
        double *Q = malloc(sizeof(double) * (size_t)m * m * an.s);
        int paths[33];
        for (int i = 0; i < 33; ++i) paths[i] = (i * 997 + 11) % (1 << an.s);
        CHECK(Q && kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s) == KIN_OK);
        if (Q && s == an.s) compare("hexagonal flat state", m, Q, &kin__hom_base_settings, paths, 33, &T);
        free(Q);
    }
    kin_assembly_free(a);
    printf("%ld paths compared: %ld real, %ld non-real, %ld singular, %ld failed; %ld rejected steps, %ld chart "
           "changes\n",
           T.paths, T.kinds[0], T.kinds[1], T.kinds[2], T.kinds[3], T.rejected, T.recharts);
    TEST_REPORT("homotopy_batch");
}
