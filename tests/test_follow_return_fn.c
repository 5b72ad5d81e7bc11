/* kin_follow_options.return_fn (kin_follow.h, docs/follow.md "Branch
 * directions"): the start's branch lines held by the caller, asked for the
 * nearest line at each return to the start, decide every return as the
 * same lines passed as `branches` (the same events, steps, end points and
 * return branch); a hook that stops or answers nonsense fails the follow
 * with its own status; bad settings are refused before anything moves. On
 * the flat state of the 4-sided sail, whose branches come back to within
 * loop_tol = 0.05 of it (passing by it, not along one of its branches:
 * those returns are undecided, and never loops). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

enum { MAXSOL = 64, MAXNF = 32 };

/* the caller's lines and what the hook saw */
typedef struct lines {
    const double *v;
    int n, nf, calls, mode; /* mode 0: answer; 1: stop; 2: a NaN angle */
} lines;

/* the nearest line by angle (atan2 of the sine and |cos|), the first of equals */
static int nearest(void *user, const double *t, int nf, double *angle, double *gap)
{
    lines *L = user;
    CHECK(nf == L->nf);
    L->calls++;
    if (L->mode == 1) return -1;
    int best = -1;
    double b1 = INFINITY, b2 = INFINITY;
    for (int j = 0; j < L->n; ++j) {
        const double *v = L->v + (size_t)j * nf;
        double uu = 0.0, vv = 0.0, uv = 0.0, s2 = 0.0;
        for (int i = 0; i < nf; ++i) {
            uu += t[i] * t[i];
            vv += v[i] * v[i];
            uv += t[i] * v[i];
        }
        for (int i = 0; i < nf; ++i) s2 += (t[i] - uv / vv * v[i]) * (t[i] - uv / vv * v[i]);
        double g = atan2(sqrt(s2 / uu), fabs(uv) / sqrt(uu * vv));
        if (g < b1) {
            b2 = b1;
            b1 = g;
            best = j;
        } else if (g < b2) {
            b2 = g;
        }
    }
    *angle = L->mode == 2 ? NAN : b1;
    *gap = b2 - b1;
    return best;
}

int main(void)
{
    kin_assembly *a = test_sail(4, 1);
    CHECK(a != NULL);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    int m = an.m_internal, s = 0, nsol = 0, nf = kin_nfree(a), nc = kin_njoints(a) * kin_dim(a);
    CHECK(m >= 2 && nf <= MAXNF);
    double *Q = malloc(sizeof(double) * (size_t)m * m * an.s), betas[MAXSOL * 8], dirs[2 * MAXSOL * MAXNF];
    double lv[MAXSOL * MAXNF];
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s), KIN_OK);
    kin_homotopy_info hi = {.size = sizeof hi};
    CHECK_RC(kin_quadrics_homotopy(m, s, Q, 1, 1, betas, MAXSOL, &nsol, NULL, &hi), KIN_OK);
    CHECK(nsol >= 2);
    for (int k = 0; k < 2 * nsol; ++k) {
        double beta[8];
        for (int i = 0; i < m; ++i) beta[i] = (k % 2 ? -1.0 : 1.0) * betas[m * (k / 2) + i];
        test_mechanism(a, beta, m, dirs + (size_t)k * nf);
        if (k % 2 == 0) memcpy(lv + (size_t)(k / 2) * nf, dirs + (size_t)k * nf, sizeof(double) * (size_t)nf);
    }
    kin_follow_options o;
    kin_follow_options_default(&o);
    CHECK(o.return_fn == NULL && o.return_user == NULL && o.return_own == -1);
    o.loop_tol = 0.05;
    lines L = {lv, nsol, nf, 0, 0};
    int returns = 0, returning = -1;
    for (int k = 0; k < 2 * nsol; ++k) {
        const double *dir = dirs + (size_t)k * nf;
        kin_assembly *b = NULL, *c = NULL;
        CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
        CHECK_RC(kin_assembly_clone(a, &c), KIN_OK);
        kin_follow_info fb = {.size = sizeof fb}, fc = {.size = sizeof fc};
        CHECK_RC(kin_follow_event_ex(b, dir, &o, lv, nsol, NULL, NULL, 0, NULL, &fb), KIN_OK);
        kin_follow_options oh = o;
        oh.return_fn = nearest;
        oh.return_user = &L;
        oh.return_own = k / 2;
        int calls = L.calls;
        CHECK_RC(kin_follow_event_ex(c, dir, &oh, NULL, 0, NULL, NULL, 0, NULL, &fc), KIN_OK);
        /* the same decision at every return: the same path and end */
        CHECK(fc.event == fb.event && fc.steps == fb.steps && fc.at_start == fb.at_start);
        CHECK(fc.return_branch == fb.return_branch &&
              ((isnan(fc.return_angle) && isnan(fb.return_angle)) ||
               fabs(fc.return_angle - fb.return_angle) <= 64 * DBL_EPSILON));
        CHECK(fb.return_branch != -1 || L.calls == calls); /* the caller is asked only at returns */
        CHECK(fb.return_branch >= KIN_FOLLOW_RETURN_UNDECIDED && fb.return_branch < nsol);
        if (fb.return_branch == KIN_FOLLOW_RETURN_UNDECIDED) CHECK(fb.event != KIN_FOLLOW_CLOSED_LOOP);
        double xb[64], xc[64];
        kin_get_coords(b, xb);
        kin_get_coords(c, xc);
        CHECK(memcmp(xb, xc, sizeof(double) * (size_t)nc) == 0);
        if (fb.return_branch != -1) {
            ++returns;
            returning = k;
        }
        kin_assembly_free(b);
        kin_assembly_free(c);
    }
    printf("sail 4x1 flat: %d directed branches, %d back near the start, decided by the caller's lines (%d calls)\n",
           2 * nsol, returns, L.calls);
    CHECK(returns >= 1);
    /* a hook that stops the follow, one that answers a NaN angle: FAILED with their status */
    if (returning >= 0) {
        const double *dir = dirs + (size_t)returning * nf;
        kin_follow_options oh = o;
        oh.return_fn = nearest;
        oh.return_user = &L;
        oh.return_own = returning / 2;
        for (int mode = 1; mode <= 2; ++mode) {
            kin_assembly *c = NULL;
            CHECK_RC(kin_assembly_clone(a, &c), KIN_OK);
            L.mode = mode;
            kin_follow_info fi = {.size = sizeof fi};
            int want = mode == 1 ? KIN_ECANCELLED : KIN_EINVAL;
            CHECK_RC(kin_follow_event_ex(c, dir, &oh, NULL, 0, NULL, NULL, 0, NULL, &fi), want);
            CHECK(fi.event == KIN_FOLLOW_FAILED && fi.status == want && fi.steps > 0);
            CHECK(strlen(kin_last_error(c)) > 0);
            kin_assembly_free(c);
        }
        L.mode = 0;
    }
    /* refused before anything moves: return_fn without return_own, with branches too */
    kin_follow_options oh = o;
    oh.return_fn = nearest;
    oh.return_user = &L;
    kin_follow_info fi = {.size = sizeof fi};
    CHECK_RC(kin_follow_event_ex(a, dirs, &oh, NULL, 0, NULL, NULL, 0, NULL, &fi), KIN_EINVAL);
    CHECK(fi.event == KIN_FOLLOW_NONE);
    oh.return_own = 0;
    CHECK_RC(kin_follow_event_ex(a, dirs, &oh, lv, nsol, NULL, NULL, 0, NULL, &fi), KIN_EINVAL);
    CHECK(fi.event == KIN_FOLLOW_NONE);
    kin_analysis after = {.size = sizeof after};
    CHECK_RC(kin_analyse(a, &after), KIN_OK);
    CHECK(after.m_internal == m); /* still at the flat state */
    free(Q);
    kin_assembly_free(a);
    TEST_REPORT("test_follow_return_fn");
}
