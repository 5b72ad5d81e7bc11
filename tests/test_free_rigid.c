/* The test function on free structures (issue 36 item 1): with several
 * rigid-body mechanisms (3 for a free body in 2D, 6 in 3D) the SVD's basis
 * of the rigid span turns freely inside the span from one point to the
 * next, and tau = sign(det [C; t^T; R^T]) v_r must not change sign with it.
 * Free structures with one internal mechanism and no bifurcation on their
 * path, followed many steps:
 *  - the free two-triangle crease (4 joints in 3D, 6 rigid mechanisms), the
 *    FOLD file of the issue, from the flat state;
 *  - two tetrahedra hinged along a common edge (6 joints in 3D);
 *  - a free four-bar linkage in the plane (3 rigid mechanisms).
 * tau keeps its sign over every step; the detector (kin_locate_next) finds
 * nothing (KIN_ENOTFOUND, event NONE); kin_follow_event, with SVD steps
 * and with its cheap LU steps, ends in a closed loop or its step budget (a
 * free body's path need not come back to the same place: it may come back
 * rotated), never in a bifurcation or a near miss; the LU modes' border
 * determinant (kin__border_det_sign: [C; t^T; R^T] with the pivoted
 * Gram-Schmidt basis of the rigid fields) keeps its sign too, so the cheap
 * steps never hand a stretch over to the SVD locator. */
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "path/path.h"
#include "libkin.h"

typedef struct {
    const char *name;
    int dim, nj, nb;
    double xyz[18];
    int bars[22];
} free_model;

static const free_model MODELS[] = {
    {"free crease", 3, 4, 5, {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 1, 2, 2, 3, 3, 0, 3, 1}},
    {"hinged tetrahedra",
     3,
     6,
     11,
     {0, 0, 0, 1, 0, 0, 0.3, 0.8, 0.1, 0.5, 0.3, 0.9, 0.6, -0.7, 0.2, 0.4, -0.2, -0.8},
     {0, 1, 0, 2, 0, 3, 1, 2, 1, 3, 2, 3, 0, 4, 0, 5, 1, 4, 1, 5, 4, 5}},
    {"free planar four-bar", 2, 4, 4, {0, 0, 2, 0, 2.5, 1.2, 0.3, 1}, {0, 1, 1, 2, 2, 3, 3, 0}},
};

static kin_assembly *make(const free_model *m)
{
    kin_assembly *a = NULL;
    unsigned char fixed[18] = {0};
    CHECK_RC(kin_assembly_create(m->dim, m->nj, m->xyz, fixed, m->nb, m->bars, NULL, &a, NULL, 0), KIN_OK);
    return a;
}

/* many steps: tau never changes sign, v_r stays away from zero */
static void tau_keeps_sign(const free_model *m)
{
    kin_assembly *a = make(m);
    if (!a) return;
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_rigid == (m->dim == 3 ? 6 : 3));
    CHECK(an.m_internal == 1);
    double tau0 = 0.0, tau1 = 0.0;
    CHECK_RC(kin_test_function(a, &tau0), KIN_OK);
    int flips = 0, steps = 0, lu0 = 0, lu1 = 0, lu_flips = 0;
    for (int k = 0; k < 120; ++k) {
        kin_step_info si = {.size = sizeof si};
        if (kin_step(a, 0.05, &si) != KIN_OK) break;
        ++steps;
        CHECK(si.m_internal == 1);
        CHECK_RC(kin_test_function(a, &tau1), KIN_OK);
        if ((tau0 > 0.0) != (tau1 > 0.0)) ++flips;
        tau0 = tau1;
        CHECK_RC(kin__border_det_sign(a, &lu1), KIN_OK);
        CHECK(lu1 != 0);
        if (lu0 && lu1 != lu0) ++lu_flips;
        lu0 = lu1;
    }
    if (flips || lu_flips)
        fprintf(stderr, "%s: tau changed sign %d times, the LU border's determinant %d times, in %d steps\n",
                m->name, flips, lu_flips, steps);
    CHECK(steps == 120);
    CHECK(flips == 0);
    CHECK(lu_flips == 0);
    kin_assembly_free(a);
}

static void locate_finds_nothing(const free_model *m)
{
    kin_assembly *a = make(m);
    if (!a) return;
    kin_locate_options o;
    kin_locate_options_default(&o);
    o.max_steps = 200;
    kin_locate_info info = {.size = sizeof info};
    int rc = kin_locate_next(a, &o, &info);
    if (rc != KIN_ENOTFOUND || info.event != KIN_EVENT_NONE)
        fprintf(stderr, "%s: locate: %s, event %d after %d steps, v_r/v_max %.3g\n", m->name, kin_status_name(rc),
                info.event, info.steps, info.v_r_rel);
    CHECK_RC(rc, KIN_ENOTFOUND);
    CHECK(info.event == KIN_EVENT_NONE);
    CHECK(!info.located);
    kin_assembly_free(a);
}

static void follow_finds_nothing(const free_model *m, int steps_mode)
{
    kin_assembly *a = make(m);
    if (!a) return;
    kin_follow_options o;
    kin_follow_options_default(&o);
    o.steps_mode = steps_mode;
    o.max_steps = 400;
    kin_follow_info info = {.size = sizeof info};
    int rc = kin_follow_event(a, NULL, &o, &info);
    int ok = info.event == KIN_FOLLOW_CLOSED_LOOP || info.event == KIN_FOLLOW_STEP_LIMIT;
    if (!ok)
        fprintf(stderr, "%s (%s steps): follow ends in event %d (%s), %d handovers\n", m->name,
                steps_mode ? "cheap" : "SVD", info.event, kin_status_name(rc), info.handovers);
    CHECK_RC(rc, KIN_OK);
    CHECK(ok);
    kin_assembly_free(a);
}

int main(void)
{
    for (size_t k = 0; k < sizeof MODELS / sizeof MODELS[0]; ++k) {
        tau_keeps_sign(&MODELS[k]);
        locate_finds_nothing(&MODELS[k]);
        follow_finds_nothing(&MODELS[k], KIN_FOLLOW_STEPS_SVD);
        follow_finds_nothing(&MODELS[k], KIN_FOLLOW_STEPS_CHEAP);
    }
    TEST_REPORT("test_free_rigid");
}
