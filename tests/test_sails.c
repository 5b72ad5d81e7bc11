/* Counts of the paper's two solar sails (docs/models.md): flat states,
 * generic states, and the hexagonal sail's R^B; the square sail's rigid-body
 * mechanism is the rotation about the axis V0-V2. */
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"


static kin_assembly *sail(int n, int loops)
{
    kin_assembly *a = test_sail(n, loops);
    CHECK(a != NULL);
    return a;
}

static void make_generic(kin_assembly *a, double amp)
{
    CHECK_RC(test_make_generic(a, amp), KIN_OK);
    CHECK(kin_max_strain(a) <= 1e-12);
}

static void square(void)
{
    kin_assembly *a = sail(4, 1);
    kin_analysis an = {.size = sizeof an};
    CHECK(kin_nfree(a) == 18 && kin_nbars(a) == 16 && kin_njoints(a) == 8);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    printf("square flat: r=%d m=%d (rigid %d, internal %d) s=%d\n", an.rank, an.m, an.m_rigid,
           an.m_internal, an.s);
    CHECK(an.rank == 12 && an.m == 6 && an.m_rigid == 1 && an.m_internal == 5 && an.s == 4);
    /* the rigid mechanism: rotation about the axis through V0 and V2 */
    double R[18], xyz[24];
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_RIGID, R, 18, 1), KIN_OK);
    kin_get_coords(a, xyz);
    double ax[3] = {1 / sqrt(2.0), 1 / sqrt(2.0), 0}, rot[18] = {0};
    for (int j = 0; j < 8; ++j) {
        double p[3] = {xyz[3 * j] + 0.5, xyz[3 * j + 1] + 0.5, xyz[3 * j + 2]};
        double w[3] = {ax[1] * p[2] - ax[2] * p[1], ax[2] * p[0] - ax[0] * p[2], ax[0] * p[1] - ax[1] * p[0]};
        for (int c = 0; c < 3; ++c) {
            int r = kin_free_index(a, j, c);
            if (r >= 0) rot[r] = w[c];
        }
    }
    double nr = 0, dot = 0;
    for (int i = 0; i < 18; ++i) { nr += rot[i] * rot[i]; dot += rot[i] * R[i]; }
    CHECK_CLOSE(fabs(dot) / sqrt(nr), 1.0, 64 * DBL_EPSILON);
    make_generic(a, 0.3);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    printf("square generic: r=%d m=%d (rigid %d, internal %d) s=%d, v_r=%.3g\n", an.rank, an.m,
           an.m_rigid, an.m_internal, an.s, an.v_r);
    CHECK(an.rank == 16 && an.m == 2 && an.m_rigid == 1 && an.m_internal == 1 && an.s == 0);
    /* and it moves: a few steps along the internal mechanism */
    kin_step_info info = {.size = sizeof info};
    for (int k = 0; k < 5; ++k) CHECK_RC(kin_step(a, 0.05, &info), KIN_OK);
    CHECK(kin_max_strain(a) <= 1e-12);
    kin_assembly_free(a);
}

static void hexagon(void)
{
    kin_assembly *a = sail(6, 2);
    kin_analysis an = {.size = sizeof an};
    CHECK(kin_nfree(a) == 46 && kin_nbars(a) == 45 && kin_njoints(a) == 19);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    printf("hex flat: r=%d m=%d (rigid %d, internal %d) s=%d\n", an.rank, an.m, an.m_rigid,
           an.m_internal, an.s);
    CHECK(an.rank == 30 && an.m == 16 && an.m_rigid == 0 && an.m_internal == 16 && an.s == 15);

    /* R^B: hub flat, A_k = V_k +- w e_z alternating, loop 2 relaxed */
    CHECK_RC(test_hex_to_RB(a), KIN_OK);
    CHECK(kin_max_strain(a) <= 1e-12);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    printf("hex R^B: r=%d m=%d (rigid %d, internal %d) s=%d, strain %.2e\n", an.rank, an.m,
           an.m_rigid, an.m_internal, an.s, kin_max_strain(a));
    CHECK(an.m == 4 && an.s == 3 && an.m_internal == 4);
    kin_assembly_free(a);

    a = sail(6, 2);
    make_generic(a, 0.3);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    printf("hex generic: r=%d m=%d s=%d v_r=%.3g\n", an.rank, an.m, an.s, an.v_r);
    CHECK(an.m == 1 && an.s == 0 && an.m_internal == 1);
    kin_assembly_free(a);
}

static void family(void)
{
    kin_sail_params p = {.size = sizeof p};
    kin_sail_params_default(&p, 8, 3);
    int nj, nb;
    CHECK_RC(kin_sail_size(&p, &nj, &nb), KIN_OK);
    CHECK(nj == 1 + 8 * 4 && nb == 4 + 8 + 3 * 8 * 3);
    kin_assembly *a = NULL;
    char msg[128];
    p.n_sides = 5;
    CHECK_RC(kin_model_sail(&p, &a, msg, sizeof msg), KIN_EINVAL);
    CHECK(strstr(msg, "even") != NULL && a == NULL);
    p.n_sides = 8; p.side = -1;
    CHECK_RC(kin_model_sail(&p, &a, msg, sizeof msg), KIN_EINVAL);
    p.side = 1; p.diagonal = 7;
    CHECK_RC(kin_model_sail(&p, &a, msg, sizeof msg), KIN_EINVAL);
    p.diagonal = KIN_SAIL_DIAG_BACKWARD;
    CHECK_RC(kin_model_sail(&p, &a, msg, sizeof msg), KIN_OK);
    CHECK(kin_njoints(a) == nj && kin_nbars(a) == nb);
    kin_assembly_free(a);
    CHECK_RC(kin_model_sail(NULL, &a, msg, sizeof msg), KIN_ENULL);
}

int main(void)
{
    square();
    hexagon();
    family();
    TEST_REPORT("test_sails");
}
