/* The lockstep parameter tracker (homotopy_param_batch.c) against the
 * one-path reference (kin__hpar_track): every path's endpoint and record
 * must be the same bit for bit (each lane goes through the same operations
 * in the same order), whatever order the paths are handed out in and
 * whichever paths share a batch. Systems: the total-degree start system
 * (times a random complex gamma) to random complex symmetric quadrics of
 * several sizes, and to the hexagonal sail's flat state (clustered,
 * singular endpoints: rejected steps, chart changes, stalls), with the
 * solver's loop settings (refined at t = 1), its leg-to-Q settings (stop
 * short of t = 1) and tightened ones; a stop abandons the paths in flight.
 * The records count the steps of the rational predictor (homotopy_pade.c)
 * too, accepted and rejected: both predictors must take and lose steps
 * here, so that the rational one's step logic (choice, extension,
 * calibration) is compared lane by lane. */
#include <string.h>

#include "check.h"
#include "homotopy/param/homotopy_param.h"
#include "model/internal.h"
#include "libkin.h"
#include "sail_states.h"

typedef struct sink_ctx {
    const int *list;
    int n, next, stop_after, handed, done, m;
    const double *x0r, *x0i; /* start points, m per path */
    hpar_end *ends;
    double *xr, *xi;
    unsigned char *seen;
} sink_ctx;

static int sink_next(void *ctx, double *x0r, double *x0i)
{
    sink_ctx *c = ctx;
    if (c->stop_after >= 0 && c->handed >= c->stop_after) return HPAR_BATCH_STOP;
    if (c->next >= c->n) return -1;
    c->handed++;
    int p = c->list[c->next++];
    memcpy(x0r, c->x0r + (size_t)p * c->m, sizeof(double) * (size_t)c->m);
    memcpy(x0i, c->x0i + (size_t)p * c->m, sizeof(double) * (size_t)c->m);
    return p;
}

static void sink_done(void *ctx, int p, const double *xr, const double *xi, const hpar_end *e)
{
    sink_ctx *c = ctx;
    c->done++;
    c->seen[p]++;
    c->ends[p] = *e;
    memcpy(c->xr + (size_t)p * c->m, xr, sizeof(double) * (size_t)c->m);
    memcpy(c->xi + (size_t)p * c->m, xi, sizeof(double) * (size_t)c->m);
}

static int same_double(double a, double b) { return a == b || (isnan(a) && isnan(b)); }

static int same_end(int m, const hpar_end *a, const hpar_end *b, const double *ar, const double *ai, const double *br,
                    const double *bi)
{
    int ok = a->ok == b->ok && a->steps == b->steps && a->rejected == b->rejected && a->pade == b->pade &&
             a->pade_rejected == b->pade_rejected && same_double(a->sigma, b->sigma);
    for (int c = 0; c < m; ++c) ok = ok && same_double(ar[c], br[c]) && same_double(ai[c], bi[c]);
    return ok;
}

static double uniform(unsigned long long *st) { return (double)(kin__splitmix(st) >> 11) * 0x1.0p-53 - 0.5; }

typedef struct totals {
    long paths, ok, steps, rejected, pade, pade_rejected;
} totals;

/* paths[0..n-1] of the problem P from the start points x0: the reference
 * one by one, the batch in the given order and in a shuffled one */
static void compare(const char *name, const hpar_problem *P, const hpar_settings *S, const double *x0r,
                    const double *x0i, int np, const int *paths, int n, totals *T)
{
    int m = P->m;
    hpar_end *ref = calloc((size_t)np, sizeof *ref), *got = calloc((size_t)np, sizeof *got);
    double *rxr = calloc((size_t)np * m, sizeof(double)), *rxi = calloc((size_t)np * m, sizeof(double));
    double *gxr = calloc((size_t)np * m, sizeof(double)), *gxi = calloc((size_t)np * m, sizeof(double));
    unsigned char *seen = calloc((size_t)np, 1);
    int *order = malloc(sizeof(int) * (size_t)n);
    hpar_ws *w = kin__hpar_ws_new(m, P->s);
    hpar_bws *B = kin__hpar_bws_new(m, P->s);
    if (!ref || !got || !rxr || !rxi || !gxr || !gxi || !seen || !order || !w || !B) {
        CHECK(!"allocation");
        goto done;
    }
    for (int i = 0; i < n; ++i) {
        int p = paths[i];
        kin__hpar_track(P, S, w, x0r + (size_t)p * m, x0i + (size_t)p * m, rxr + (size_t)p * m, rxi + (size_t)p * m,
                        &ref[p]);
        T->paths++, T->ok += ref[p].ok, T->steps += ref[p].steps, T->rejected += ref[p].rejected;
        T->pade += ref[p].pade, T->pade_rejected += ref[p].pade_rejected;
    }
    for (int pass = 0; pass < 2; ++pass) {
        /* pass 1: a stride-7 permutation (n is prime to 7 here): other
         * paths share each path's batch */
        for (int i = 0; i < n; ++i) order[i] = pass == 0 ? paths[i] : paths[(i * 7 + 3) % n];
        memset(seen, 0, (size_t)np);
        sink_ctx c = {order, n, 0, -1, 0, 0, m, x0r, x0i, got, gxr, gxi, seen};
        hpar_batch_sink K = {&c, sink_next, sink_done};
        kin__hpar_track_batch(P, S, B, &K);
        CHECK(c.done == n);
        int differ = 0;
        for (int i = 0; i < n; ++i) {
            int p = paths[i];
            CHECK(seen[p] == 1);
            if (!same_end(m, &ref[p], &got[p], rxr + (size_t)p * m, rxi + (size_t)p * m, gxr + (size_t)p * m,
                          gxi + (size_t)p * m))
                differ++;
        }
        if (differ) fprintf(stderr, "%s pass %d: %d of %d paths differ from the reference\n", name, pass, differ, n);
        CHECK(differ == 0);
    }
    { /* a stop abandons the paths in flight */
        memset(seen, 0, (size_t)np);
        sink_ctx c = {paths, n, 0, n > 6 ? 6 : n - 1, 0, 0, m, x0r, x0i, got, gxr, gxi, seen};
        hpar_batch_sink K = {&c, sink_next, sink_done};
        kin__hpar_track_batch(P, S, B, &K);
        CHECK(c.done <= c.handed && c.handed == c.stop_after);
    }
done:
    kin__hpar_bws_free(B), kin__hpar_ws_free(w);
    free(order), free(seen), free(ref), free(got), free(rxr), free(rxi), free(gxr), free(gxi);
}

/* A = gamma (x_{j+1}^2 - x_0^2) (stacked), D = B - A for the stacked
 * complex B; the chart and the start points (+-1 vectors times random
 * complex scales) drawn from st; the paths: n distinct of the 2^s */
static void run_system(const char *name, int m, const double *Br, const double *Bi, unsigned long long st, int n,
                       int bad_starts, totals *T)
{
    int s = m - 1, sm = s * m, np = 1 << s;
    size_t ns = (size_t)s * m * m;
    double *A = calloc(4 * ns, sizeof(double)), *x0 = malloc(sizeof(double) * 2 * (size_t)np * m);
    int *paths = malloc(sizeof(int) * (size_t)n);
    if (!A || !x0 || !paths) {
        CHECK(!"allocation");
        free(A), free(x0), free(paths);
        return;
    }
    double *Ar = A, *Ai = A + ns, *Dr = A + 2 * ns, *Di = A + 3 * ns, *x0r = x0, *x0i = x0 + (size_t)np * m;
    double th = 6.283185307179586 * uniform(&st), gr = cos(th), gi = sin(th);
    for (int j = 0; j < s; ++j) {
        int q = j + 1;
        Ar[(size_t)q * sm + q * s + j] = gr, Ai[(size_t)q * sm + q * s + j] = gi;
        Ar[j] = -gr, Ai[j] = -gi; /* row 0, column 0 */
    }
    for (size_t i = 0; i < ns; ++i) Dr[i] = Br[i] - Ar[i], Di[i] = Bi[i] - Ai[i];
    hpar_problem P = {m, s, Ar, Ai, Dr, Di, {0}, {0}};
    for (int c = 0; c < m; ++c) {
        double a = 6.283185307179586 * uniform(&st);
        P.ar[c] = cos(a), P.ai[c] = sin(a);
    }
    for (int p = 0; p < np; ++p) {
        double zr = 1.0 + uniform(&st), zi = uniform(&st);
        for (int c = 0; c < m; ++c) {
            double v = c > 0 && (p >> (c - 1)) & 1 ? -1.0 : 1.0;
            x0r[(size_t)p * m + c] = v * zr, x0i[(size_t)p * m + c] = v * zi;
        }
        if (bad_starts && p % 3 == 0) x0r[(size_t)p * m] *= 1.5; /* not a root: the start's corrector fails */
    }
    for (int i = 0; i < n; ++i) paths[i] = (int)(((long long)i * 2654435761LL) % np);
    for (int i = 0; i < n; ++i) /* distinct paths */
        for (int j = 0; j < i; ++j)
            if (paths[j] == paths[i]) paths[i] = (paths[i] + 1) % np, j = -1;
    const hpar_settings loop = {1e-3, 1e-2, 0.0}, leg = {1e-4, 3e-3, 1e-10}, tight = {1e-5, 3e-4, 1e-12};
    compare(name, &P, &loop, x0r, x0i, np, paths, n, T);
    compare(name, &P, &leg, x0r, x0i, np, paths, n, T);
    if (m <= 9) compare(name, &P, &tight, x0r, x0i, np, paths, n, T);
    free(A), free(x0), free(paths);
}

int main(void)
{
    totals T = {0};
    int ms[] = {2, 3, 4, 5, 7, 9, 12, 17};
    for (size_t k = 0; k < sizeof ms / sizeof ms[0]; ++k) {
        int m = ms[k], s = m - 1, np = 1 << s, sm = s * m;
        size_t ns = (size_t)s * m * m;
        double *Bs = malloc(sizeof(double) * 2 * ns);
        if (!Bs) return 1;
        unsigned long long st = 1234u + (unsigned)m;
        for (int j = 0; j < s; ++j) /* random complex symmetric B_j */
            for (int r = 0; r < m; ++r)
                for (int c = r; c < m; ++c) {
                    double vr = uniform(&st), vi = uniform(&st);
                    Bs[(size_t)c * sm + r * s + j] = Bs[(size_t)r * sm + c * s + j] = vr;
                    Bs[ns + (size_t)c * sm + r * s + j] = Bs[ns + (size_t)r * sm + c * s + j] = vi;
                }
        char name[32];
        snprintf(name, sizeof name, "random m = %d", m);
        run_system(name, m, Bs, Bs + ns, st, np < 23 ? np : 23, 0, &T);
        free(Bs);
    }
    { /* B_j[x, x] = x_0 (l_j . x): all but one path end on the component
       * x_0 = 0 (singular endpoints, lost paths), a third of the start
       * points are not roots */
        int m = 6, s = m - 1, sm = s * m;
        size_t ns = (size_t)s * m * m;
        double Bs[2 * 5 * 6 * 6] = {0};
        unsigned long long st = 4321u;
        for (int j = 0; j < s; ++j)
            for (int c = 0; c < m; ++c) {
                double vr = uniform(&st), vi = uniform(&st), f = c == 0 ? 2.0 : 1.0;
                Bs[(size_t)c * sm + j] += f * vr, Bs[ns + (size_t)c * sm + j] += f * vi; /* row 0 */
                if (c > 0) Bs[c * s + j] += vr, Bs[ns + c * s + j] += vi;              /* column 0 */
            }
        run_system("x_0 (l . x)", m, Bs, Bs + ns, st, 23, 1, &T);
    }
    /* the hexagonal sail's flat state (real Q): 29 of its 32768 paths */
    kin_assembly *a = test_sail(6, 2);
    kin_analysis an = {.size = sizeof an};
    CHECK(a && kin_analyse(a, &an) == KIN_OK);
    if (a && an.m_internal == an.s + 1) {
        int m = an.m_internal, s = 0, sm = an.s * m;
        size_t ns = (size_t)an.s * m * m;
        double *Q = malloc(sizeof(double) * ns), *Bs = calloc(2 * ns, sizeof(double));
        CHECK(Q && Bs && kin_second_order(a, KIN_Q_EXACT, 1, Q, (int)ns, &s) == KIN_OK);
        if (Q && Bs && s == an.s) {
            for (int j = 0; j < s; ++j) /* stacked: row r of Q_j at r*s + j */
                for (int r = 0; r < m; ++r)
                    for (int c = 0; c < m; ++c) Bs[(size_t)c * sm + r * s + j] = Q[((size_t)j * m + r) * m + c];
            run_system("hexagonal flat state", m, Bs, Bs + ns, 99u, 29, 0, &T);
        }
        free(Q), free(Bs);
    }
    kin_assembly_free(a);
    printf("%ld paths compared: %ld reached the end, %ld steps (%ld rational), %ld rejected (%ld rational)\n", T.paths,
           T.ok, T.steps, T.pade, T.rejected, T.pade_rejected);
    /* covers failures, rejections, and steps of either predictor, accepted and rejected */
    CHECK(T.ok > 0 && T.ok < T.paths && T.rejected > 0);
    CHECK(T.pade > 0 && T.pade < T.steps && T.pade_rejected > 0 && T.pade_rejected < T.rejected);
    TEST_REPORT("homotopy_param_batch");
}
