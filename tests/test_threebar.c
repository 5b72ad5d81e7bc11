/* First-order analysis of the paper's three-bar linkage (eq. 27-28) at R^A,
 * R^B and R^C, checked through SVD invariants rather than raw vectors. */
#include <string.h>

#include "check.h"
#include "libkin.h"

/* |H^T U| and |U^T U - I| for the mechanisms; |H W| and |W^T W - I| for the
 * self-stresses: rounding-level multiples of DBL_EPSILON * v_max. */
static void check_invariants(kin_assembly *a, const kin_analysis *an)
{
    int nf = kin_nfree(a), nb = kin_nbars(a);
    double H[64], U[64], W[64];
    kin_get_equilibrium_matrix(a, H, nf);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, nf, an->m_internal), KIN_OK);
    CHECK_RC(kin_get_self_stresses(a, W, nb, an->s), KIN_OK);
    double tol = 16 * DBL_EPSILON * an->v_max;
    for (int c = 0; c < an->m_internal; ++c) {
        for (int k = 0; k < nb; ++k) {
            double s = 0;
            for (int i = 0; i < nf; ++i) s += H[i + k * nf] * U[i + c * nf];
            CHECK(fabs(s) <= tol);
        }
        for (int d = 0; d < an->m_internal; ++d) {
            double s = 0;
            for (int i = 0; i < nf; ++i) s += U[i + c * nf] * U[i + d * nf];
            CHECK_CLOSE(s, c == d, 16 * DBL_EPSILON);
        }
    }
    for (int c = 0; c < an->s; ++c)
        for (int i = 0; i < nf; ++i) {
            double s = 0;
            for (int k = 0; k < nb; ++k) s += H[i + k * nf] * W[k + c * nb];
            CHECK(fabs(s) <= tol);
        }
}

int main(void)
{
    kin_assembly *a = NULL;
    kin_analysis an = {.size = sizeof an};

    /* R^C: eq. 27 */
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    CHECK(kin_nfree(a) == 4 && kin_nbars(a) == 3 && kin_dim(a) == 2 && kin_njoints(a) == 4);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    double sv[3];
    CHECK_RC(kin_get_singular_values(a, sv, 3), KIN_OK);
    CHECK_CLOSE(sv[0], sqrt(3.0), 8 * DBL_EPSILON);
    CHECK_CLOSE(sv[1], 1.0, 8 * DBL_EPSILON);
    CHECK(sv[2] <= 8 * DBL_EPSILON);
    CHECK(an.rank == 2 && an.m == 2 && an.s == 1 && an.m_rigid == 0 && an.m_internal == 2);
    CHECK_CLOSE(an.v_r, 1.0, 8 * DBL_EPSILON);
    check_invariants(a, &an);
    /* eq. 28 up to sign and basis: span(U_m) = span(e_J1y, e_J2y), i.e. the
     * projector U U^T is diag(0,1,0,1); W_s = +-(1,1,-1)/sqrt(3) */
    double U[8], W[3];
    kin_get_mechanisms(a, KIN_MECH_ALL, U, 4, 2);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            double p = U[i] * U[j] + U[i + 4] * U[j + 4];
            CHECK_CLOSE(p, (i == j && (i == 1 || i == 3)) ? 1.0 : 0.0, 8 * DBL_EPSILON);
        }
    kin_get_self_stresses(a, W, 3, 1);
    double sg = W[0] > 0 ? 1.0 : -1.0;
    CHECK_CLOSE(sg * W[0], 1 / sqrt(3.0), 8 * DBL_EPSILON);
    CHECK_CLOSE(sg * W[1], 1 / sqrt(3.0), 8 * DBL_EPSILON);
    CHECK_CLOSE(sg * W[2], -1 / sqrt(3.0), 8 * DBL_EPSILON);
    /* H as printed in the paper's eq. 27 is U V W^T: check the product */
    double H[12];
    kin_get_equilibrium_matrix(a, H, 4);
    const double Hpaper[12] = {1, 0, 0, 0, -1, 0, 1, 0, 0, 0, 1, 0};
    for (int i = 0; i < 12; ++i) CHECK_CLOSE(H[i], Hpaper[i], 0.0);
    kin_assembly_free(a);

    /* R^A and R^B: each a bifurcation with m = 2, s = 1 */
    for (int st = KIN_THREEBAR_RA; st <= KIN_THREEBAR_RB; ++st) {
        CHECK_RC(kin_model_threebar(st, &a), KIN_OK);
        CHECK_RC(kin_analyse(a, &an), KIN_OK);
        CHECK(an.rank == 2 && an.m == 2 && an.s == 1 && an.m_internal == 2 && an.m_rigid == 0);
        check_invariants(a, &an);
        kin_assembly_free(a);
    }

    /* a regular point of the parallelogram mode: m = 1, s = 0 */
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double xyz[8];
    kin_get_coords(a, xyz);
    xyz[0] = 0.6; xyz[1] = 0.8; xyz[2] = 1.6; xyz[3] = 0.8;
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.rank == 3 && an.m == 1 && an.s == 0 && an.m_internal == 1);
    check_invariants(a, &an);
    /* the mechanism is the parallelogram motion: J1 and J2 move alike,
     * perpendicular to S1-J1 */
    kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, 4, 1);
    CHECK_CLOSE(fabs(U[0] * 0.8 - U[1] * 0.6), 1 / sqrt(2.0), 8 * DBL_EPSILON);
    CHECK_CLOSE(U[0], U[2], 8 * DBL_EPSILON);
    CHECK_CLOSE(U[1], U[3], 8 * DBL_EPSILON);
    kin_assembly *b = NULL;
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    kin_analysis bn = {.size = sizeof bn};
    CHECK_RC(kin_get_analysis(b, &bn), KIN_OK);
    CHECK(memcmp(&an, &bn, sizeof an) == 0);
    kin_assembly_free(b);
    kin_assembly_free(a);
    TEST_REPORT("test_threebar");
}
