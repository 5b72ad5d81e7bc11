/* The proven singular configuration near a located bifurcation (issue 38
 * item 2, kin_locate_info layout 3, libkin/locate/sing_proof.c):
 *  - the three-bar linkage's R^A, R^B, R^C (exact in closed form, corank 1),
 *    located along each path with the fast method (1e-10) and the paper's
 *    (1e-6): proven, and the exact point lies within the proven distance;
 *  - a regular point far from any bifurcation: not proven;
 *  - the hexagonal sail's flat state (15 self-stresses) and R^B (3): not
 *    proven, corank reported;
 *  - a four-bar pinned at one joint only (a rigid rotation, gauged): its
 *    collinear state proven, also from a point 1e-9 off it, and located;
 *  - kin_prove_singular's argument checks. */
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

/* (J1x, J2x) of R^A, R^B, R^C; every y is 0 */
static const double EXACT[3][2] = {{-1, 0}, {1, 0}, {1, 2}};

/* max-norm distance of the free coordinates x (J1, J2) to the nearest exact point */
static double to_exact(const double *x)
{
    double best = INFINITY;
    for (int k = 0; k < 3; ++k) {
        double d = fmax(fmax(fabs(x[0] - EXACT[k][0]), fabs(x[2] - EXACT[k][1])), fmax(fabs(x[1]), fabs(x[3])));
        best = fmin(best, d);
    }
    return best;
}

/* a point of path 0 (P1), 1 (J2 at S1) or 2 (J1 at S2) at angle th */
static void start(kin_assembly *a, int path, double th)
{
    double x[8];
    kin_get_coords(a, x);
    if (path == 0) { x[0] = cos(th); x[1] = sin(th); x[2] = x[0] + 1; x[3] = x[1]; }
    if (path == 1) { x[0] = cos(th); x[1] = sin(th); x[2] = 0; x[3] = 0; }
    if (path == 2) { x[0] = 1; x[1] = 0; x[2] = 1 + cos(th); x[3] = sin(th); }
    CHECK_RC(kin_set_coords(a, x), KIN_OK);
}

static void threebar(void)
{
    const int methods[2] = {KIN_LOCATE_FAST, KIN_LOCATE_PAPER};
    const double tols[2] = {1e-10, 1e-6};
    for (int mi = 0; mi < 2; ++mi)
        for (int path = 0; path < 3; ++path)
            for (int dir = 0; dir < 2; ++dir) {
                kin_assembly *a = NULL;
                CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
                start(a, path, 1.0);
                kin_locate_options o = {.size = sizeof o};
                kin_locate_options_default(&o);
                o.method = methods[mi];
                o.vr_tol = tols[mi];
                o.delta = dir ? -0.1 : 0.1;
                kin_locate_info info = {.size = sizeof info};
                CHECK_RC(kin_locate_next(a, &o, &info), KIN_OK);
                double x[8];
                kin_get_coords(a, x);
                double d = to_exact(x);
                printf("%s path %d dir %d: located %.2e from the exact point, proven %d: distance <= %.3e, "
                       "|L* - L0| <= %.3e, unique within %.3e\n",
                       mi ? "paper" : "fast", path, dir, d, info.sing_proven, info.sing_distance, info.sing_dlength,
                       info.sing_unique);
                CHECK(info.located);
                CHECK(info.sing_proven == 1 && info.sing_corank == 1);
                /* the exact point solves the extended system with mu = 0: within the
                 * uniqueness radius it is the proven one, so it lies within the distance */
                CHECK(d <= info.sing_distance);
                /* the bound is of the location's accuracy (v_r ~ distance here) */
                CHECK(info.sing_distance <= 100.0 * tols[mi]);
                CHECK(info.sing_unique >= info.sing_distance);
                /* rest lengths 1: the backward error is rounding */
                CHECK(info.sing_dlength <= 64 * DBL_EPSILON);
                /* the public call on the same point agrees */
                kin_locate_info again = {.size = sizeof again};
                CHECK_RC(kin_prove_singular(a, &again), KIN_OK);
                CHECK(again.sing_proven == 1 && again.sing_distance == info.sing_distance);
                kin_assembly_free(a);
            }
}

/* a regular point (v_r / v_max about 0.4) is not near a singular one */
static void regular(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    start(a, 0, 1.0);
    kin_locate_info info = {.size = sizeof info};
    info.sing_proven = 7;
    CHECK_RC(kin_prove_singular(a, &info), KIN_OK);
    CHECK(info.sing_proven == 0 && info.sing_corank == 0);
    /* arguments */
    CHECK_RC(kin_prove_singular(a, NULL), KIN_ENULL);
    CHECK_RC(kin_prove_singular(NULL, &info), KIN_ENULL);
    info.size = 8;
    CHECK_RC(kin_prove_singular(a, &info), KIN_EINVAL);
    kin_assembly_free(a);
}

/* the hexagonal sail's flat state (s = 15) and R^B (s = 3): the extended
 * system is not square there, no proof */
static void corank(void)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL);
    if (!a) return;
    kin_locate_info info = {.size = sizeof info};
    CHECK_RC(kin_prove_singular(a, &info), KIN_OK);
    CHECK(info.sing_proven == 0 && info.sing_corank == 15);
    CHECK_RC(test_hex_to_RB(a), KIN_OK);
    CHECK_RC(kin_prove_singular(a, &info), KIN_OK);
    CHECK(info.sing_proven == 0 && info.sing_corank == 3);
    kin_assembly_free(a);
}

/* S1 = (0,0) pinned, J1, J2, S2 free; bars S1-J1, J1-J2, J2-S2, S2-S1, all of
 * length 1: the rhombus turns freely about S1 (m_rigid = 1) */
static kin_assembly *pinned_rhombus(double th)
{
    double xyz[8] = {0, 0, cos(th), sin(th), cos(th) + 1, sin(th), 1, 0};
    const unsigned char fixed[8] = {1, 1, 0, 0, 0, 0, 0, 0};
    const int bars[8] = {0, 1, 1, 2, 2, 3, 3, 0};
    const double L0[4] = {1, 1, 1, 1};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 4, xyz, fixed, 4, bars, L0, &a, NULL, 0), KIN_OK);
    return a;
}

static void rigid(void)
{
    /* the collinear state J1 = (-1,0), J2 = (0,0), S2 = (1,0): exactly singular */
    kin_assembly *a = pinned_rhombus(1.0);
    if (!a) return;
    double x[8] = {0, 0, -1, 0, 0, 0, 1, 0};
    CHECK_RC(kin_set_coords(a, x), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_rigid == 1 && an.m_internal == 2 && an.s == 1);
    kin_locate_info info = {.size = sizeof info};
    CHECK_RC(kin_prove_singular(a, &info), KIN_OK);
    CHECK(info.sing_proven == 1 && info.sing_corank == 1);
    CHECK(info.sing_distance <= 64 * DBL_EPSILON && info.sing_dlength <= 64 * DBL_EPSILON);
    /* 1e-9 off it, not along the rotation (which the gauge holds where the
     * state has it: J1y or S2y, both 0): the state is the proven point */
    x[5] = 1e-9;
    CHECK_RC(kin_set_coords(a, x), KIN_OK);
    CHECK_RC(kin_prove_singular(a, &info), KIN_OK);
    printf("pinned rhombus, 1e-9 off the collinear state: proven %d, distance <= %.3e\n", info.sing_proven,
           info.sing_distance);
    CHECK(info.sing_proven == 1 && info.sing_distance >= 1e-9 && info.sing_distance <= 2e-9);
    kin_assembly_free(a);
    /* located along the rhombus's path */
    a = pinned_rhombus(1.0);
    kin_locate_options o = {.size = sizeof o};
    kin_locate_options_default(&o);
    CHECK_RC(kin_locate_next(a, &o, &info), KIN_OK);
    printf("pinned rhombus located: v_r/v_max %.2e, proven %d, distance <= %.3e, |L* - L0| <= %.3e\n", info.v_r_rel,
           info.sing_proven, info.sing_distance, info.sing_dlength);
    CHECK(info.located && info.sing_proven == 1 && info.sing_distance <= 1e-8);
    kin_assembly_free(a);
}

int main(void)
{
    threebar();
    regular();
    corank();
    rigid();
    TEST_REPORT("test_sing_proof");
}
