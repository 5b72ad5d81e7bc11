/* kin_follow_event_ex (kin_follow.h, docs/follow.md): the cheap steps
 * (KIN_FOLLOW_STEPS_CHEAP) against the SVD steps, the samples recorded along
 * the path, the start's branch directions deciding what a return to the
 * start is, the BLAS threads (one while following, the caller's after), and
 * the errors. On the three-bar linkage from R^C. */
#define _GNU_SOURCE /* RTLD_DEFAULT */
#include <dlfcn.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

enum { NB = 4 }; /* directed branches out of R^C */

/* the directed branches out of R^C (nf entries each) and the undirected ones */
static int branches(kin_assembly *a, double *dirs, double *lines, int *nlines)
{
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    int m = an.m_internal, s = 0, nsol = 0, nf = kin_nfree(a);
    double Q[64], betas[64];
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 64, &s), KIN_OK);
    kin_homotopy_info hi = {.size = sizeof hi};
    CHECK_RC(kin_quadrics_homotopy(m, s, Q, 1, 1, betas, 16, &nsol, NULL, &hi), KIN_OK);
    CHECK(2 * nsol == NB);
    for (int k = 0; k < 2 * nsol && k < NB; ++k) {
        double beta[8];
        for (int i = 0; i < m; ++i) beta[i] = (k % 2 ? -1.0 : 1.0) * betas[m * (k / 2) + i];
        test_mechanism(a, beta, m, dirs + (size_t)k * nf);
        if (k % 2 == 0) memcpy(lines + (size_t)(k / 2) * nf, dirs + (size_t)k * nf, sizeof(double) * (size_t)nf);
    }
    *nlines = nsol;
    return 2 * nsol;
}

/* OpenBLAS's thread count, where the linked BLAS is OpenBLAS */
typedef int (*get_fn)(void);
typedef void (*set_fn)(int);
static get_fn get_threads;

static int threads_inside = -1;
static int watch_threads(void *user, double done, double total)
{
    (void)user, (void)done, (void)total;
    if (get_threads) threads_inside = get_threads();
    return 0;
}

static void blas_threads(kin_assembly *a, const double *dir)
{
    void *g = dlsym(RTLD_DEFAULT, "openblas_get_num_threads"), *s = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    if (!g || !s) {
        printf("BLAS threads: not OpenBLAS, nothing to check\n");
        return;
    }
    set_fn set_threads;
    memcpy(&get_threads, &g, sizeof g);
    memcpy(&set_threads, &s, sizeof s);
    int before = get_threads();
    set_threads(3);
    kin_assembly *b = NULL;
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    CHECK_RC(kin_set_progress(b, watch_threads, NULL), KIN_OK);
    kin_follow_info fi = {.size = sizeof fi};
    CHECK_RC(kin_follow_event(b, dir, NULL, &fi), KIN_OK);
    printf("BLAS threads: 3 before, %d while following, %d after\n", threads_inside, get_threads());
    CHECK(threads_inside == 1 && get_threads() == 3);
    /* kin_analyse too: its SVD (the mechanism basis) on one thread, whatever the caller's count */
    threads_inside = -1;
    CHECK_RC(kin_analyse(b, NULL), KIN_OK);
    printf("BLAS threads: 3 before, %d while analysing, %d after\n", threads_inside, get_threads());
    CHECK(threads_inside == 1 && get_threads() == 3);
    set_threads(before);
    kin_assembly_free(b);
}

int main(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    int nf = kin_nfree(a), nc = kin_njoints(a) * kin_dim(a), nlines = 0;
    double dirs[NB * 16], lines[NB * 16], dup[3 * 16];
    int n = branches(a, dirs, lines, &nlines);
    kin_follow_options svd, cheap;
    kin_follow_options_default(&svd);
    kin_follow_options_default(&cheap);
    CHECK(cheap.steps_mode == KIN_FOLLOW_STEPS_CHEAP && cheap.branch_margin > 0.0);
    svd.steps_mode = KIN_FOLLOW_STEPS_SVD;
    int loops = 0;
    for (int k = 0; k < n; ++k) {
        const double *dir = dirs + (size_t)k * nf;
        kin_assembly *b = NULL, *c = NULL, *d = NULL;
        CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
        CHECK_RC(kin_assembly_clone(a, &c), KIN_OK);
        CHECK_RC(kin_assembly_clone(a, &d), KIN_OK);
        kin_follow_info fs = {.size = sizeof fs}, fc = {.size = sizeof fc}, fb = {.size = sizeof fb};
        double smp[5 * 16], len[5];
        int ns = -1;
        CHECK_RC(kin_follow_event(b, dir, &svd, &fs), KIN_OK);
        CHECK(fs.cheap_steps == 0 && fs.return_branch == -1);
        /* cheap steps: the same event and end; samples along the way */
        CHECK_RC(kin_follow_event_ex(c, dir, &cheap, NULL, 0, smp, len, 5, &ns, &fc), KIN_OK);
        CHECK(fc.event == fs.event && fc.cheap_steps > 0 && fc.cheap_steps <= fc.steps);
        double xb[16], xc[16];
        kin_get_coords(b, xb);
        kin_get_coords(c, xc);
        double dist = 0.0;
        for (int i = 0; i < nc; ++i) dist = fmax(dist, fabs(xb[i] - xc[i]));
        if (fs.event == KIN_FOLLOW_BIFURCATION) CHECK(dist <= 1e-6 && fc.m_internal == fs.m_internal);
        CHECK(ns == fc.samples && ns >= 1 && ns <= 5);
        for (int j = 0; j < ns; ++j) {
            /* on the path (strain-free), in order, inside it */
            CHECK(len[j] > 0.0 && len[j] < fc.length && (j == 0 || len[j] > len[j - 1]));
            kin_assembly *p = NULL;
            CHECK_RC(kin_assembly_clone(a, &p), KIN_OK);
            CHECK_RC(kin_set_coords(p, smp + (size_t)j * nc), KIN_OK);
            CHECK(kin_max_strain(p) <= 1e-9);
            kin_assembly_free(p);
        }
        /* branch directions: a return along the own branch stays a loop;
         * with the own branch listed twice the return is too close to call
         * and the start is located as a bifurcation instead */
        CHECK_RC(kin_follow_event_ex(d, dir, &svd, lines, nlines, NULL, NULL, 0, NULL, &fb), KIN_OK);
        CHECK(fb.event == fs.event);
        if (fs.event == KIN_FOLLOW_CLOSED_LOOP) {
            ++loops;
            CHECK(fb.return_branch == k / 2 && fb.return_gap >= svd.branch_margin);
            memcpy(dup, lines, sizeof(double) * (size_t)nlines * nf);
            memcpy(dup + (size_t)nlines * nf, dir, sizeof(double) * (size_t)nf);
            kin_assembly *e = NULL;
            CHECK_RC(kin_assembly_clone(a, &e), KIN_OK);
            kin_follow_info fe = {.size = sizeof fe};
            CHECK_RC(kin_follow_event_ex(e, dir, &svd, dup, nlines + 1, NULL, NULL, 0, NULL, &fe), KIN_OK);
            CHECK(fe.event == KIN_FOLLOW_BIFURCATION && fe.at_start && fe.v_r_rel <= fe.vr_tol_used);
            kin_assembly_free(e);
        }
        kin_assembly_free(b);
        kin_assembly_free(c);
        kin_assembly_free(d);
    }
    printf("three-bar R^C: %d directed branches, %d closed loops\n", n, loops);
    /* (no start of this linkage returns to itself before another event: the
     * loop decision runs only where loops occur, e.g. the flat state of the
     * hexagonal sail, bench/bench_follow_atlas) */
    blas_threads(a, dirs);
    /* errors: nothing moves, info zeroed */
    kin_follow_info fi = {.size = sizeof fi};
    int ns = 0;
    double bad[16];
    memcpy(bad, lines, sizeof bad);
    bad[0] = NAN;
    CHECK_RC(kin_follow_event_ex(a, dirs, &svd, lines, -1, NULL, NULL, 0, NULL, &fi), KIN_EINVAL);
    CHECK(fi.event == KIN_FOLLOW_NONE);
    CHECK_RC(kin_follow_event_ex(a, dirs, &svd, NULL, 2, NULL, NULL, 0, NULL, &fi), KIN_EINVAL);
    CHECK_RC(kin_follow_event_ex(a, dirs, &svd, bad, 1, NULL, NULL, 0, NULL, &fi), KIN_EINVAL);
    CHECK_RC(kin_follow_event_ex(a, dirs, &svd, NULL, 0, NULL, NULL, 3, NULL, &fi), KIN_EINVAL);
    CHECK_RC(kin_follow_event_ex(a, dirs, &svd, NULL, 0, NULL, NULL, -1, &ns, &fi), KIN_EINVAL);
    kin_follow_options o = svd;
    o.steps_mode = 7;
    CHECK_RC(kin_follow_event(a, dirs, &o, &fi), KIN_EINVAL);
    o = svd;
    o.branch_margin = -0.1;
    CHECK_RC(kin_follow_event(a, dirs, &o, &fi), KIN_EINVAL);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal >= 2); /* still at R^C */
    kin_assembly_free(a);
    TEST_REPORT("test_follow_ex");
}
