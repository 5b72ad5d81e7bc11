/* The complete solver against the four kinds of intersection of the
 * paper's Figure 5, on small quadric systems in P^2 (s = 2, m = 3), each
 * rotated by a fixed orthogonal matrix so that no coordinate is special, and
 * on the structures: all 2^s paths accounted for, the same answer for any
 * thread count. The root scan is run on the same systems for comparison. */
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

/* Q' = R^T Q R for a fixed rotation R (so solutions are R^T beta) */
static void rotate(const double *Q, double *out)
{
    const double c1 = cos(0.3), s1 = sin(0.3), c2 = cos(1.1), s2 = sin(1.1);
    const double Rz[9] = {c1, -s1, 0, s1, c1, 0, 0, 0, 1}, Rx[9] = {1, 0, 0, 0, c2, -s2, 0, s2, c2};
    double R[9] = {0};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) R[i * 3 + j] += Rz[i * 3 + k] * Rx[k * 3 + j];
    for (int q = 0; q < 2; ++q)
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                double v = 0;
                for (int k = 0; k < 3; ++k)
                    for (int l = 0; l < 3; ++l) v += R[k * 3 + i] * Q[q * 9 + k + 3 * l] * R[l * 3 + j];
                out[q * 9 + i + 3 * j] = v;
            }
}

typedef struct expect {
    const char *name;
    double Q[18];
    int real_distinct, nonreal, singular;
} expect;

static void figure5(void)
{
    /* symmetric 3x3 matrices, column-major; x = (x0, x1, x2) */
    const expect cases[4] = {
        /* (a) x0^2 = x1^2, x0^2 = x2^2: 4 distinct real points */
        {"(a) 2^s real points", {1, 0, 0, 0, -1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, -1}, 4, 0, 0},
        /* (b) x0^2 = x1^2, x2^2 = x0 x1: 2 real, 2 complex */
        {"(b) complex points", {1, 0, 0, 0, -1, 0, 0, 0, 0, 0, -0.5, 0, -0.5, 0, 0, 0, 0, 1}, 2, 2, 0},
        /* (c) x1^2 = 0 (double), x0^2 = x2^2: 2 points of multiplicity 2 */
        {"(c) multiple points", {0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, -1}, 0, 0, 4},
        /* (d) x0 x1 = 0, x0 x2 = 0: the line x0 = 0 plus the point (1,0,0) */
        {"(d) curve plus point", {0, 0.5, 0, 0.5, 0, 0, 0, 0, 0, 0, 0, 0.5, 0, 0, 0, 0.5, 0, 0}, 1, 0, 3},
    };
    for (int c = 0; c < 4; ++c) {
        double Q[18], betas[3 * 64];
        int mult[64], nsol = 0;
        rotate(cases[c].Q, Q);
        kin_homotopy_info h;
        CHECK_RC(kin_quadrics_homotopy(3, 2, Q, 1, 1, betas, 64, &nsol, mult, &h), KIN_OK);
        int ns = 0;
        kin_solve_info si;
        double sb[3 * 64];
        CHECK_RC(kin_quadrics_scan(3, 2, Q, 512, 1, sb, 64, &ns, &si), KIN_OK);
        printf("%-22s homotopy: %d paths = %d real (%d distinct) + %d complex + %d singular + %d failed;"
               " scan (512 starts): %d distinct\n", cases[c].name, h.paths, h.real, h.real_distinct, h.nonreal,
               h.singular, h.failed, si.distinct);
        CHECK(h.paths == 4 && h.real + h.nonreal + h.singular + h.failed == 4);
        CHECK(h.real_distinct == cases[c].real_distinct);
        CHECK(h.nonreal == cases[c].nonreal);
        CHECK(h.singular == cases[c].singular);
        CHECK(h.failed == 0);
        for (int k = 0; k < nsol; ++k)
            for (int q = 0; q < 2; ++q) {
                double v = 0;
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j) v += betas[3 * k + i] * Q[q * 9 + i + 3 * j] * betas[3 * k + j];
                CHECK(fabs(v) < 1e-12);
            }
        if (c == 3) CHECK(si.distinct > 10); /* the scan keeps finding new points on the line */
        if (c < 2) CHECK(si.distinct == cases[c].real_distinct);
    }
}

static void structures(void)
{
    kin_assembly *a = test_sail(4, 1);
    kin_analysis an;
    kin_analyse(a, &an);
    double Q[100], b1[5 * 32], b2[5 * 32];
    int s, n1, n2;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 100, &s), KIN_OK);
    kin_homotopy_info h1, h2;
    CHECK_RC(kin_quadrics_homotopy(5, 4, Q, 3, 1, b1, 32, &n1, NULL, &h1), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy(5, 4, Q, 3, 2, b2, 32, &n2, NULL, &h2), KIN_OK);
    printf("square sail flat: %d paths = %d real (%d distinct) + %d complex + %d singular + %d failed\n", h1.paths,
           h1.real, h1.real_distinct, h1.nonreal, h1.singular, h1.failed);
    CHECK(h1.paths == 16 && h1.real == 16 && h1.real_distinct == 16);
    CHECK(n1 == n2 && memcmp(&h1, &h2, sizeof h1) == 0 && memcmp(b1, b2, sizeof(double) * 5 * n1) == 0);
    kin_assembly_free(a);

    a = test_sail(6, 2);
    CHECK_RC(test_hex_to_RB(a), KIN_OK);
    kin_analyse(a, &an);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 100, &s), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy(4, 3, Q, 3, 2, b1, 32, &n1, NULL, &h1), KIN_OK);
    printf("hexagonal sail R^B: %d paths = %d real (%d distinct) + %d complex + %d singular + %d failed\n",
           h1.paths, h1.real, h1.real_distinct, h1.nonreal, h1.singular, h1.failed);
    CHECK(h1.paths == 8 && h1.real_distinct == 8);
    kin_assembly_free(a);

    int n;
    CHECK_RC(kin_quadrics_homotopy(3, 1, Q, 1, 1, b1, 4, &n, NULL, &h1), KIN_EINVAL);
    CHECK_RC(kin_quadrics_homotopy(3, 2, Q, 1, 0, b1, 4, &n, NULL, &h1), KIN_EINVAL);
    CHECK_RC(kin_quadrics_homotopy(30, 29, Q, 1, 1, b1, 4, &n, NULL, &h1), KIN_ERANGE);
    CHECK_RC(kin_quadrics_homotopy(3, 2, NULL, 1, 1, b1, 4, &n, NULL, &h1), KIN_ENULL);
}

int main(void)
{
    figure5();
    structures();
    TEST_REPORT("test_homotopy");
}
