/* Progress callbacks and cancellation of the long calls (kin_progress.h):
 * - the complete solver: reports from the calling thread only, done
 *   monotonic and <= total, first 0 and last done == total; a cancel from
 *   the first report returns before tracking, one from a later report stops
 *   every thread at once (KIN_ECANCELLED, info zeroed, betas not written);
 *   the path limit refuses a problem before anything is tracked; a thread
 *   count beyond the machine is clamped (same result as one thread);
 * - kin_locate_next: a report per step, a cancel while following or while
 *   locating leaves the assembly on the path at a regular point, from where
 *   a second call finds the bifurcation;
 * - kin_branch_paths: a cancel zeroes the path records and leaves the
 *   caller's assembly and final_xyz untouched;
 * - clones start without a callback. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <limits.h>
#include <pthread.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "model/internal.h" /* kin__splitmix */
#include "libkin.h"

typedef struct recorder {
    int calls;
    int cancel_at;      /* return 1 at this call (1-based); 0: never */
    int monotonic;      /* done and total never decreased, 0 <= done <= total */
    int other_thread;   /* a call came from a thread other than the caller's */
    double first_done, last_done, last_total;
    pthread_t caller;
} recorder;

static void rec_init(recorder *r, int cancel_at)
{
    memset(r, 0, sizeof *r);
    r->cancel_at = cancel_at;
    r->monotonic = 1;
    r->first_done = r->last_done = r->last_total = -1.0;
    r->caller = pthread_self();
}

static int record(void *user, double done, double total)
{
    recorder *r = user;
    if (!pthread_equal(pthread_self(), r->caller)) r->other_thread = 1;
    if (r->calls == 0) r->first_done = done;
    if (!(done >= 0.0 && done <= total) || done < r->last_done || total < r->last_total) r->monotonic = 0;
    r->last_done = done;
    r->last_total = total;
    return ++r->calls == r->cancel_at;
}

static double seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* s Gaussian symmetric (s+1) x (s+1) matrices: every root simple */
static void random_quadrics(int s, unsigned long long seed, double *Q)
{
    int m = s + 1;
    for (int j = 0; j < s; ++j)
        for (int r = 0; r < m; ++r)
            for (int c = r; c < m; ++c) {
                double u = ((kin__splitmix(&seed) >> 11) + 0.5) * 0x1.0p-53;
                double v = ((kin__splitmix(&seed) >> 11) + 0.5) * 0x1.0p-53;
                Q[j * m * m + r + c * m] = Q[j * m * m + c + r * m] =
                    sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
            }
}

enum { S_SMALL = 7, M_SMALL = S_SMALL + 1, N_SMALL = 1 << S_SMALL };
enum { S_CANCEL = 12, M_CANCEL = S_CANCEL + 1, N_CANCEL = 1 << S_CANCEL };

static void homotopy(void)
{
    static double Q[M_CANCEL * M_CANCEL * S_CANCEL], b1[M_SMALL * N_SMALL], b2[M_SMALL * N_SMALL];
    int n1 = 0, n2 = 0;
    kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
    random_quadrics(S_SMALL, 7, Q);

    /* the reference: the old entry point, one thread, no callback */
    CHECK_RC(kin_quadrics_homotopy(M_SMALL, S_SMALL, Q, 3, 1, b1, N_SMALL, &n1, NULL, &h1), KIN_OK);
    CHECK(h1.paths == N_SMALL && h1.real + h1.nonreal == N_SMALL);

    /* reports, and the path limit is inclusive */
    recorder r;
    rec_init(&r, 0);
    kin_homotopy_options o = {.size = sizeof o};
    kin_homotopy_options_default(&o);
    CHECK(o.seed == 1 && o.nthreads == 0 && o.max_paths == (1L << 20) && !o.progress && !o.user);
    o.seed = 3;
    o.nthreads = 2;
    o.max_paths = N_SMALL;
    o.progress = record;
    o.user = &r;
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, Q, &o, b2, N_SMALL, &n2, NULL, &h2), KIN_OK);
    printf("homotopy s = %d: %d reports, last %.0f of %.0f\n", S_SMALL, r.calls, r.last_done, r.last_total);
    CHECK(r.calls >= 2 && r.monotonic && !r.other_thread);
    CHECK(r.first_done == 0.0 && r.last_done == r.last_total && r.last_total == N_SMALL + h2.retracked);
    CHECK(n1 == n2 && memcmp(&h1, &h2, sizeof h1) == 0 && memcmp(b1, b2, sizeof(double) * M_SMALL * n1) == 0);

    /* more threads than the machine has: clamped, the same answer (unclamped,
     * INT_MAX threads' workspaces could not be allocated) */
    o.nthreads = INT_MAX;
    o.progress = NULL;
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, Q, &o, b2, N_SMALL, &n2, NULL, &h2), KIN_OK);
    CHECK(n1 == n2 && memcmp(&h1, &h2, sizeof h1) == 0 && memcmp(b1, b2, sizeof(double) * M_SMALL * n1) == 0);
    CHECK_RC(kin_quadrics_homotopy(M_SMALL, S_SMALL, Q, 3, INT_MAX, b2, N_SMALL, &n2, NULL, &h2), KIN_OK);
    CHECK(n1 == n2 && memcmp(&h1, &h2, sizeof h1) == 0);

    /* over the limit: refused before any work (no report) */
    rec_init(&r, 0);
    o.progress = record;
    o.max_paths = N_SMALL - 1;
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, Q, &o, b2, N_SMALL, &n2, NULL, &h2), KIN_ELIMIT);
    CHECK(r.calls == 0);
    /* the default limit, 2^20 paths: s = 21 is refused at once */
    {
        enum { S = 21, M = S + 1 };
        static double Qbig[M * M * S], bb[M];
        int nb = -1;
        kin_homotopy_info hb = {.size = sizeof hb};
        random_quadrics(S, 11, Qbig);
        CHECK_RC(kin_quadrics_homotopy(M, S, Qbig, 1, 1, bb, 1, &nb, NULL, &hb), KIN_ELIMIT);
        CHECK_RC(kin_quadrics_homotopy_ex(M, S, Qbig, NULL, bb, 1, &nb, NULL, &hb), KIN_ELIMIT);
        CHECK(nb == 0 && hb.paths == 0); /* refused before any tracking: outputs zeroed */
    }
    /* bad settings */
    kin_homotopy_options_default(&o);
    o.nthreads = -1;
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, Q, &o, b2, N_SMALL, &n2, NULL, &h2), KIN_EINVAL);
    kin_homotopy_options_default(&o);
    o.max_paths = 0;
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, Q, &o, b2, N_SMALL, &n2, NULL, &h2), KIN_EINVAL);
    CHECK_RC(kin_quadrics_homotopy(M_SMALL, S_SMALL, Q, 1, 0, b2, N_SMALL, &n2, NULL, &h2), KIN_EINVAL);
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, NULL, &o, b2, N_SMALL, &n2, NULL, &h2), KIN_ENULL);
    CHECK_RC(kin_quadrics_homotopy_ex(M_SMALL, S_SMALL, Q, &o, b2, N_SMALL, &n2, NULL, NULL), KIN_ENULL);
    kin_homotopy_options_default(NULL); /* no crash */

    /* cancel: at the first report (nothing tracked), then at the second
     * (50 ms into a run of 4096 paths, several hundred ms uncancelled) */
    random_quadrics(S_CANCEL, 13, Q);
    static double bc[M_CANCEL * N_CANCEL];
    for (int at = 1; at <= 2; ++at) {
        for (int i = 0; i < M_CANCEL * N_CANCEL; ++i) bc[i] = -7.0;
        int mult[4] = {-7, -7, -7, -7}, nc = -1;
        kin_homotopy_info hc = {.size = sizeof hc};
        memset(&hc, 0x5a, sizeof hc);
        hc.size = sizeof hc; /* garbage after the size: zeroed on cancel */
        rec_init(&r, at);
        kin_homotopy_options_default(&o);
        o.nthreads = 2;
        o.progress = record;
        o.user = &r;
        double t0 = seconds();
        CHECK_RC(kin_quadrics_homotopy_ex(M_CANCEL, S_CANCEL, Q, &o, bc, 4, &nc, mult, &hc), KIN_ECANCELLED);
        double dt = seconds() - t0;
        printf("homotopy s = %d cancelled at report %d: returned after %.3f s, %d reports, done %.0f of %.0f\n",
               S_CANCEL, at, dt, r.calls, r.last_done, r.last_total);
        kin_homotopy_info zero = {.size = sizeof zero};
        memset(&zero, 0, sizeof zero);
        zero.size = sizeof zero;
        CHECK(r.calls == at && !r.other_thread && r.monotonic);
        CHECK(at == 1 ? r.last_done == 0.0 : r.last_done > 0.0 && r.last_done < N_CANCEL);
        CHECK(nc == 0 && memcmp(&hc, &zero, sizeof hc) == 0);
        CHECK(bc[0] == -7.0 && bc[M_CANCEL * 4 - 1] == -7.0 && mult[0] == -7);
        /* how soon it returned is printed above, not asserted: the machine may be loaded */
    }
}

/* the three-bar linkage on path P1 (J2 at S1 moves with J1), regular */
static kin_assembly *threebar_on_path(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double x[8];
    kin_get_coords(a, x);
    x[0] = cos(1.0), x[1] = sin(1.0), x[2] = x[0] + 1.0, x[3] = x[1];
    CHECK_RC(kin_set_coords(a, x), KIN_OK);
    return a;
}

static void locate(void)
{
    kin_locate_options o = {.size = sizeof o};
    kin_locate_options_default(&o);
    o.delta = 0.1;
    kin_locate_info info = {.size = sizeof info};

    /* uncancelled: one report per step and location iteration */
    kin_assembly *a = threebar_on_path();
    recorder r;
    rec_init(&r, 0);
    CHECK_RC(kin_set_progress(a, record, &r), KIN_OK);
    CHECK_RC(kin_locate_next(a, &o, &info), KIN_OK);
    int full_calls = r.calls, full_steps = info.steps;
    printf("locate: %d reports for %d steps and %d forward calculations\n", r.calls, info.steps, info.forward);
    CHECK(info.located && r.monotonic && r.first_done == 0.0);
    CHECK(r.last_done == r.last_total && r.last_total == o.max_steps + o.max_iter);
    CHECK(r.calls >= info.steps + 1 && info.forward >= 1 && r.calls > info.steps + 1); /* location reported too */
    /* a clone starts without the callback */
    kin_assembly *b = threebar_on_path(), *c = NULL;
    CHECK_RC(kin_set_progress(b, record, &r), KIN_OK);
    CHECK_RC(kin_assembly_clone(b, &c), KIN_OK);
    rec_init(&r, 0);
    CHECK_RC(kin_locate_next(c, &o, &info), KIN_OK);
    CHECK(r.calls == 0);
    kin_assembly_free(c);
    kin_assembly_free(b);
    kin_assembly_free(a);

    /* cancel at the first report (before any step): nothing moved */
    a = threebar_on_path();
    double x0[8], x1[8];
    kin_get_coords(a, x0);
    rec_init(&r, 1);
    kin_set_progress(a, record, &r);
    CHECK_RC(kin_locate_next(a, &o, &info), KIN_ECANCELLED);
    kin_get_coords(a, x1);
    CHECK(r.calls == 1 && info.steps == 0 && !info.located && memcmp(x0, x1, sizeof x0) == 0);
    kin_assembly_free(a);

    /* cancel while following (report 3: after two steps) and while locating
     * (the last report before the final one): on the path, at a regular
     * point, and a second call (callback removed) locates the bifurcation */
    const int at[2] = {3, full_calls - 1};
    for (int k = 0; k < 2; ++k) {
        a = threebar_on_path();
        rec_init(&r, at[k]);
        kin_set_progress(a, record, &r);
        CHECK_RC(kin_locate_next(a, &o, &info), KIN_ECANCELLED);
        CHECK(r.calls == at[k] && !info.located);
        if (k == 0) CHECK(info.steps == 2 && info.forward == 0);
        else CHECK(info.steps == full_steps && info.forward >= 1);
        kin_analysis an = {.size = sizeof an};
        CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
        CHECK(an.m_internal == 1 && kin_max_strain(a) <= 1e-12);
        CHECK_RC(kin_set_progress(a, NULL, NULL), KIN_OK);
        CHECK_RC(kin_locate_next(a, &o, &info), KIN_OK);
        CHECK(info.located && info.m_internal == 2);
        kin_assembly_free(a);
    }
    CHECK_RC(kin_set_progress(NULL, record, &r), KIN_ENULL);
}

static void branch_paths(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 2 && an.s == 1);
    double Q[4], betas[2 * 4];
    int s = 0, nsol = 0;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s), KIN_OK);
    kin_homotopy_info h = {.size = sizeof h};
    CHECK_RC(kin_quadrics_homotopy_ex(2, 1, Q, NULL, betas, 4, &nsol, NULL, &h), KIN_OK);
    CHECK(nsol == 2);
    kin_branch_path p[4] = {{.size = sizeof(kin_branch_path)}};
    double fx[4 * 8], x0[8], x1[8];
    int nd = -1;

    recorder r;
    rec_init(&r, 0);
    kin_set_progress(a, record, &r);
    CHECK_RC(kin_branch_paths(a, betas, nsol, 1.0, p, fx, &nd), KIN_OK);
    printf("branch paths: %d reports for %d directed paths, %d distinct\n", r.calls, 2 * nsol, nd);
    CHECK(nd == 4 && r.monotonic && r.first_done == 0.0 && r.last_done == 2.0 * nsol && r.last_total == 2.0 * nsol);
    CHECK(r.calls > 2 * nsol);

    for (int at = 1; at <= 3; at += 2) {
        kin_get_coords(a, x0);
        for (int i = 0; i < 4 * 8; ++i) fx[i] = -7.0;
        memset(p, 0x5a, sizeof p);
        p[0].size = sizeof p[0];
        nd = -1;
        rec_init(&r, at);
        CHECK_RC(kin_branch_paths(a, betas, nsol, 1.0, p, fx, &nd), KIN_ECANCELLED);
        kin_get_coords(a, x1);
        CHECK(r.calls == at && nd == 0 && memcmp(x0, x1, sizeof x0) == 0);
        CHECK(fx[0] == -7.0 && fx[4 * 8 - 1] == -7.0);
        for (int k = 0; k < 2 * nsol; ++k) CHECK(!p[k].exists && p[k].path_id == -1 && p[k].length == 0.0);
        CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
        CHECK(an.m_internal == 2);
    }
    kin_assembly_free(a);
}

int main(void)
{
    homotopy();
    locate();
    branch_paths();
    TEST_REPORT("test_progress");
}
