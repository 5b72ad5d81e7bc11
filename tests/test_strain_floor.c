/* The strain the input allows (kin_path.h, STRAIN FLOOR): the corrector's
 * tolerance in effect is max(corrector_tol, strain_floor), strain_floor =
 * max(the path start's own strain, sqrt(dim) * coord_resolution / min L0),
 * both stated in kin_step_info; the rank test does not count singular values
 * below the coordinate part.
 *
 * The overconstrained linkage: three equal parallel cranks from three pins,
 * their free ends joined by a rigid triangle of couplers (6 free
 * coordinates, 6 bars: 0 by count, yet the triangle translates on a circle:
 * one mechanism and one self-stress). Written with 6 decimals from a
 * generic placement, the rounding breaks the self-stress: to the default
 * rank test the rounded linkage is rigid, to the input's accuracy it still
 * moves (with a strain that grows as it moves, below the floor). */
#include <stddef.h>
#include <string.h>

#include "check.h"
#include "libkin.h"

static const double XYZ[12] = {
    0.122001, 0.123176, 1.20613, 0.214321, 2.321572, 0.753348, /* pins */
    0.554243, 0.796353, 1.638372, 0.887497, 2.753814, 1.426524 /* crank ends, rounded */
};
static const int BARS[12] = {0, 3, 1, 4, 2, 5, 3, 4, 4, 5, 3, 5};
static const unsigned char FIXED[12] = {1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0};

static kin_assembly *linkage(const double *lengths)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 6, XYZ, FIXED, 6, BARS, lengths, &a, NULL, 0), KIN_OK);
    return a;
}

static double min_rest_length(void)
{
    double m = INFINITY;
    for (int k = 0; k < 6; ++k) {
        const double *p = XYZ + 2 * BARS[2 * k], *q = XYZ + 2 * BARS[2 * k + 1];
        m = fmin(m, hypot(p[0] - q[0], p[1] - q[1]));
    }
    return m;
}

/* rounded coordinates: rigid to the default rank test; with their
 * resolution given, followed, each step within the floor */
static void rounded_linkage_moves(void)
{
    kin_assembly *a = linkage(NULL);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 0 && an.s == 0);
    kin_step_info info = {.size = sizeof info};
    CHECK_RC(kin_step(a, 0.0, &info), KIN_ENOMECH);

    kin_options o = {.size = sizeof o};
    kin_options_default(&o);
    CHECK(o.coord_resolution == 0.0);
    o.coord_resolution = -1e-6;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o.coord_resolution = 1e-6;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 1 && an.s == 1);
    double floor_want = sqrt(2.0) * 1e-6 / min_rest_length();
    for (int k = 0; k < 40; ++k) {
        CHECK_RC(kin_step(a, 0.0, &info), KIN_OK);
        CHECK_CLOSE(info.strain_floor, floor_want, 1e-15);
        CHECK_CLOSE(info.tol_used, floor_want, 1e-15);
        CHECK(info.residual <= info.tol_used);
    }
    CHECK(kin_path_length(a) > 3.0); /* well round the crank circle (radius 0.8) */
    CHECK(kin_max_strain(a) <= floor_want);
    kin_assembly_free(a);
}

/* exact input: the tolerance is corrector_tol; a strained start raises the
 * floor to its own strain, measured again where a new path starts */
static void start_strain(void)
{
    double L[6];
    for (int k = 0; k < 6; ++k) {
        const double *p = XYZ + 2 * BARS[2 * k], *q = XYZ + 2 * BARS[2 * k + 1];
        L[k] = hypot(p[0] - q[0], p[1] - q[1]);
    }
    /* drop the redundant coupler 3-5: an ordinary four-bar-like linkage */
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 6, XYZ, FIXED, 5, BARS, L, &a, NULL, 0), KIN_OK);
    kin_step_info info = {.size = sizeof info};
    CHECK_RC(kin_step(a, 0.0, &info), KIN_OK);
    CHECK(info.strain_floor <= 4 * DBL_EPSILON && info.tol_used == 1e-12 && info.residual <= 1e-12);
    kin_assembly_free(a);

    L[0] *= 1.0 + 1e-9; /* the file's lengths disagree with its coordinates */
    CHECK_RC(kin_assembly_create(2, 6, XYZ, FIXED, 5, BARS, L, &a, NULL, 0), KIN_OK);
    double start = kin_max_strain(a);
    CHECK(start > 0.9e-9);
    CHECK_RC(kin_step(a, 0.0, &info), KIN_OK);
    CHECK_CLOSE(info.strain_floor, start, 1e-20);
    CHECK_CLOSE(info.tol_used, start, 1e-20);
    CHECK_RC(kin_step(a, 0.0, &info), KIN_OK);
    CHECK_CLOSE(info.strain_floor, start, 1e-20); /* the start's, not the current point's */
    /* relax: to corrector_tol (the start strain is what it removes); the
     * path starting there has the relaxed point's strain */
    double res = 1.0;
    CHECK_RC(kin_relax(a, 50, &res), KIN_OK);
    CHECK(res <= 1e-12);
    CHECK_RC(kin_step(a, 0.0, &info), KIN_OK);
    CHECK(info.strain_floor <= 1e-12 && info.tol_used == 1e-12);
    kin_assembly_free(a);
}

/* a caller compiled before the fields were appended is not written past
 * its size */
static void old_callers(void)
{
    kin_assembly *a = linkage(NULL);
    kin_options o = {.size = sizeof o};
    kin_options_default(&o);
    o.coord_resolution = 1e-6;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    union {
        kin_step_info info;
        unsigned char b[sizeof(kin_step_info) + 16];
    } u;
    memset(u.b, 0xAB, sizeof u.b);
    size_t old = offsetof(kin_step_info, strain_floor);
    memcpy(u.b, &old, sizeof old);
    CHECK_RC(kin_step(a, 0.0, &u.info), KIN_OK);
    for (size_t i = old; i < sizeof u.b; ++i) CHECK(u.b[i] == 0xAB);
    kin_assembly_free(a);
}

int main(void)
{
    rounded_linkage_moves();
    start_strain();
    old_callers();
    TEST_REPORT("test_strain_floor");
}
