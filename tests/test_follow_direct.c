/* The cheap follower's direct location (branches/follow.c, locate/locate.c:
 * kin__locate_ws.direct_prev): where its LU steps hand over on a sign
 * change that the SVD locator would bracket on the very same step, the
 * locator locates on the LU points' bracket without stepping over it again
 * by SVD. Checked on the 16 directed branches out of the hexagonal sail's
 * R^B: the same events, located accuracies, m, s and ends (to the
 * identification tolerance) as the SVD follower and as the cheap follower
 * with the direct location made to fail (fault hook: the usual handover
 * takes over), the same number of steps; and the direct path taken on at
 * least one branch (its bracket's end counts as an LU step). No timing. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "libkin.h"
#include "sail_states.h"

enum { NF = 46, NC = 57, MAXSOL = 8 };

static void follow(const kin_assembly *a, const double *dir, int steps_mode, int fault, kin_follow_info *fi,
                   double *xyz)
{
    kin_assembly *b = NULL;
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    if (!b) return;
    kin__set_fault(b, fault);
    kin_follow_options o;
    kin_follow_options_default(&o);
    o.steps_mode = steps_mode;
    fi->size = sizeof *fi;
    CHECK_RC(kin_follow_event(b, dir, &o, fi), KIN_OK);
    kin_get_coords(b, xyz);
    kin_assembly_free(b);
}

static double max_diff(const double *x, const double *y)
{
    double d = 0.0;
    for (int i = 0; i < NC; ++i) d = fmax(d, fabs(x[i] - y[i]));
    return d;
}

int main(void)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL);
    CHECK_RC(test_hex_to_RB(a), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 4 && kin_nfree(a) == NF && kin_njoints(a) * kin_dim(a) == NC);
    double Q[4 * 4 * 4], betas[4 * MAXSOL], dir[NF];
    int s = 0, nsol = 0;
    kin_homotopy_info hi = {.size = sizeof hi};
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4 * 4 * 4, &s), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy(an.m_internal, s, Q, 1, 1, betas, MAXSOL, &nsol, NULL, &hi), KIN_OK);
    CHECK(nsol == MAXSOL);
    double x0[NC], scale = 1.0;
    kin_get_coords(a, x0);
    for (int i = 0; i < NC; ++i) scale = fmax(scale, fabs(x0[i]));
    int direct = 0, bif = 0;
    for (int k = 0; k < 2 * nsol; ++k) {
        double beta[4], xs[NC], xc[NC], xf[NC];
        for (int i = 0; i < 4; ++i) beta[i] = (k % 2 ? -1.0 : 1.0) * betas[4 * (k / 2) + i];
        test_mechanism(a, beta, an.m_internal, dir);
        kin_follow_info fs, fc, ff;
        follow(a, dir, KIN_FOLLOW_STEPS_SVD, KIN__FAULT_NONE, &fs, xs);
        follow(a, dir, KIN_FOLLOW_STEPS_CHEAP, KIN__FAULT_NONE, &fc, xc);
        follow(a, dir, KIN_FOLLOW_STEPS_CHEAP, KIN__FAULT_LOCATE_DIRECT, &ff, xf);
        /* the same outcome all three ways */
        CHECK(fc.event == fs.event && ff.event == fs.event);
        CHECK(fc.steps == fs.steps && ff.steps == fs.steps);
        if (fs.event == KIN_FOLLOW_BIFURCATION) {
            ++bif;
            /* the atlas's identification tolerance: the size times
             * max(1e-6, 10 sqrt(vr_tol)) (bench_follow_atlas) */
            double tol = scale * fmax(1e-6, 10.0 * sqrt(fmax(fs.vr_tol_used, fc.vr_tol_used)));
            CHECK(fc.vr_tol_used <= fs.vr_tol_used && ff.vr_tol_used <= fs.vr_tol_used);
            CHECK(fc.m_internal == fs.m_internal && ff.m_internal == fs.m_internal);
            CHECK(fc.s == fs.s && ff.s == fs.s);
            CHECK(max_diff(xc, xs) <= tol && max_diff(xf, xs) <= tol);
        }
        /* the direct location counts its bracket's end as the LU step that
         * reached it; the usual handover steps over it again by SVD */
        CHECK(fc.cheap_steps >= ff.cheap_steps);
        direct += fc.cheap_steps > ff.cheap_steps;
    }
    printf("R^B: %d directed branches, %d to a bifurcation, %d located directly on the LU steps' bracket\n",
           2 * nsol, bif, direct);
    CHECK(bif > 0 && direct > 0);
    kin_assembly_free(a);
    TEST_REPORT("test_follow_direct");
}
