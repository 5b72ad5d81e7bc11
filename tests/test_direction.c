/* Leaving a bifurcation along a chosen direction: from the three-bar
 * linkage's R^C, the parallelogram direction (J1y, J2y) ~ (1, 1) stays on P1
 * (J2 = J1 + (1,0)), and (0, 1) follows the circle with J1 held at S2. */
#include <string.h>

#include "check.h"
#include "libkin.h"

static void leave(const double dir[4], int parallelogram)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 2);
    double t[4];
    CHECK_RC(kin_get_tangent(a, t, 4), KIN_EBIFURCATION);
    CHECK_RC(kin_path_set_direction(a, dir, 4), KIN_OK);
    CHECK_RC(kin_get_tangent(a, t, 4), KIN_OK);
    double nd = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2] + dir[3] * dir[3]);
    for (int i = 0; i < 4; ++i) CHECK_CLOSE(t[i], dir[i] / nd, 16 * DBL_EPSILON);
    kin_step_info info = {.size = sizeof info};
    double xyz[8];
    for (int k = 0; k < 20; ++k) {
        CHECK_RC(kin_step(a, k == 0 ? 1e-3 : 0.05, &info), KIN_OK);
        CHECK(info.m_internal == 1);
        kin_get_coords(a, xyz);
        if (parallelogram) {
            CHECK_CLOSE(xyz[2] - xyz[0], 1.0, 1e-12);
            CHECK_CLOSE(xyz[3] - xyz[1], 0.0, 1e-12);
        } else {
            CHECK_CLOSE(xyz[0], 1.0, 1e-12); /* J1 stays on S2 */
            CHECK_CLOSE(xyz[1], 0.0, 1e-12);
        }
        CHECK(kin_max_strain(a) <= 1e-12);
    }
    /* the first small step left R^C along the chosen direction */
    CHECK(kin_path_length(a) > 0.9);
    kin_assembly_free(a);
}

int main(void)
{
    const double p1[4] = {0, 1, 0, 1}, j1_at_s2[4] = {0, 0, 0, 1};
    leave(p1, 1);
    leave(j1_at_s2, 0);
    /* a direction that is not a mechanism is refused */
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    const double bad[4] = {1, 0, 1, 0};
    CHECK_RC(kin_path_set_direction(a, bad, 4), KIN_EINVAL);
    CHECK(strstr(kin_last_error(a), "not a first-order mechanism") != NULL);
    kin_assembly_free(a);
    TEST_REPORT("test_direction");
}
