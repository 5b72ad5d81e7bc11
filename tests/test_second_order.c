/* Second-order compatibility (eq. 12-18) and the root scan on the three-bar
 * linkage at R^C (eq. 29-33). */
#include <string.h>

#include "check.h"
#include "libkin.h"

int main(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double Q[4], U[8], betas[2 * 8];
    int s = 0;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, Q, 4, &s), KIN_ESTATE);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK_RC(kin_second_order(a, 7, 0, Q, 4, &s), KIN_EINVAL);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, Q, 3, &s), KIN_ERANGE);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, NULL, 4, &s), KIN_ENULL);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, Q, 4, &s), KIN_OK);
    CHECK(s == 1);
    /* eq. 30 in the paper's basis U_m = [-e_J1y, e_J2y]: Q = [[2,1],[1,0]]/sqrt(3)
     * up to sign. Our basis is U = [u0 u1]; map: beta^T Q beta is basis
     * independent, so compare the quadratic form on the displacement
     * directions: q(d) = d^T (U Q U^T) d */
    kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, 4, 2);
    double P[16] = {0};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int p = 0; p < 2; ++p)
                for (int q = 0; q < 2; ++q) P[i + 4 * j] += U[i + 4 * p] * Q[p + 2 * q] * U[j + 4 * q];
    /* paper: in (J1y, J2y) with J1y = -beta1, J2y = beta2:
     * Q_paper(beta) = (2 b1^2 + 2 b1 b2)/sqrt(3) -> in (J1y, J2y): (2 y1^2 - 2 y1 y2)/sqrt(3) */
    double sg = P[1 + 4 * 1] > 0 ? 1.0 : -1.0;
    CHECK_CLOSE(sg * P[1 + 4 * 1], 2 / sqrt(3.0), 16 * DBL_EPSILON);
    CHECK_CLOSE(sg * P[1 + 4 * 3], -1 / sqrt(3.0), 16 * DBL_EPSILON);
    CHECK_CLOSE(sg * P[3 + 4 * 3], 0.0, 16 * DBL_EPSILON);
    for (int i = 0; i < 4; i += 2)
        for (int j = 0; j < 4; ++j) CHECK_CLOSE(P[i + 4 * j], 0.0, 16 * DBL_EPSILON);
    /* the exact weighting equals the paper's here: every bar has L = 1 */
    double Qp[4];
    CHECK_RC(kin_second_order(a, KIN_Q_PAPER_EQ17, 0, Qp, 4, &s), KIN_OK);
    for (int i = 0; i < 4; ++i) CHECK_CLOSE(Qp[i], Q[i], 0.0);
    /* eq. 18 normalisation: unit Frobenius norm */
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s), KIN_OK);
    CHECK_CLOSE(Q[0] * Q[0] + Q[1] * Q[1] + Q[2] * Q[2] + Q[3] * Q[3], 1.0, 8 * DBL_EPSILON);

    /* eq. 33: two solutions, the directions (J1y, J2y) ~ (1, 1) (path P1,
     * Figure 1(b)) and (0, 1) (J1 held at S2, Figure 1(d)) */
    int nsol = 0;
    kin_solve_info info = {.size = sizeof info};
    CHECK_RC(kin_quadrics_scan(2, 1, Q, 64, 1, betas, 8, &nsol, &info), KIN_OK);
    CHECK(nsol == 2 && info.distinct == 2 && info.max_residual < 1e-13);
    int seen_p1 = 0, seen_j1 = 0;
    for (int k = 0; k < nsol; ++k) {
        double d[4];
        for (int i = 0; i < 4; ++i) d[i] = U[i] * betas[2 * k] + U[i + 4] * betas[2 * k + 1];
        CHECK(fabs(d[0]) < 1e-14 && fabs(d[2]) < 1e-14);
        if (fabs(fabs(d[1]) - fabs(d[3])) < 1e-12 && d[1] * d[3] > 0) seen_p1++;
        if (fabs(d[1]) < 1e-12 && fabs(fabs(d[3]) - 1.0) < 1e-12) seen_j1++;
    }
    CHECK(seen_p1 == 1 && seen_j1 == 1);
    /* same seed, same answer */
    double again[16];
    int n2 = 0;
    CHECK_RC(kin_quadrics_scan(2, 1, Q, 64, 1, again, 8, &n2, NULL), KIN_OK);
    CHECK(n2 == nsol && memcmp(again, betas, sizeof(double) * 2 * nsol) == 0);
    CHECK_RC(kin_quadrics_scan(3, 1, Q, 64, 1, betas, 8, &nsol, NULL), KIN_EINVAL);
    CHECK_RC(kin_quadrics_scan(2, 1, Q, 0, 1, betas, 8, &nsol, NULL), KIN_EINVAL);
    CHECK_RC(kin_quadrics_scan(2, 1, NULL, 4, 1, betas, 8, &nsol, NULL), KIN_ENULL);

    /* regular point: not a bifurcation */
    double xyz[8];
    kin_get_coords(a, xyz);
    xyz[0] = 0.6; xyz[1] = 0.8; xyz[2] = 1.6; xyz[3] = 0.8;
    kin_set_coords(a, xyz);
    kin_analyse(a, &an);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s), KIN_EINVAL);
    kin_assembly_free(a);
    TEST_REPORT("test_second_order");
}
