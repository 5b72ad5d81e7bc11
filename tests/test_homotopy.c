/* The complete solver against the four kinds of intersection of the
 * paper's Figure 5, on small quadric systems in P^2 (s = 2, m = 3), each
 * rotated by a fixed orthogonal matrix so that no coordinate is special, and
 * on the structures: all 2^s paths accounted for, the same answer for any
 * thread count. The root scan is run on the same systems for comparison.
 * Then the endpoint checks: on made-up endpoints (the duplicate and
 * conjugate-pair detection must flag what it is shown), and on a random
 * s = 8 system, whose 256 roots are all simple (generic), half of them or
 * more non-real. */
#include <string.h>

#include "check.h"
#include "homotopy/solver/homotopy_solver.h" /* the endpoint checker (private) */
#include "model/internal.h"                  /* kin__splitmix */
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
        kin_homotopy_info h = {.size = sizeof h};
        CHECK_RC(kin_quadrics_homotopy(3, 2, Q, 1, 1, betas, 64, &nsol, mult, &h), KIN_OK);
        int ns = 0;
        kin_solve_info si = {.size = sizeof si};
        double sb[3 * 64];
        CHECK_RC(kin_quadrics_scan(3, 2, Q, 512, 1, sb, 64, &ns, &si), KIN_OK);
        printf("%-22s homotopy: %d paths = %d real (%d distinct) + %d complex + %d singular + %d failed"
               " (%d re-tracked); scan (512 starts): %d distinct\n", cases[c].name, h.paths, h.real, h.real_distinct,
               h.nonreal, h.singular, h.failed, h.retracked, si.distinct);
        CHECK(h.paths == 4 && h.real + h.nonreal + h.singular + h.failed == 4);
        CHECK(h.real_distinct == cases[c].real_distinct);
        CHECK(h.nonreal == cases[c].nonreal);
        CHECK(h.singular == cases[c].singular);
        CHECK(h.failed == 0);
        CHECK(h.duplicates == 0 && h.unpaired == 0); /* (b): the 2 complex roots are a conjugate pair */
        if (h.real_distinct) CHECK(h.max_residual < 64 * DBL_EPSILON);
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
    kin_analysis an = {.size = sizeof an};
    kin_analyse(a, &an);
    double Q[100], b1[5 * 32], b2[5 * 32];
    int s, n1, n2;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 100, &s), KIN_OK);
    kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
    CHECK_RC(kin_quadrics_homotopy(5, 4, Q, 3, 1, b1, 32, &n1, NULL, &h1), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy(5, 4, Q, 3, 2, b2, 32, &n2, NULL, &h2), KIN_OK);
    printf("square sail flat: %d paths = %d real (%d distinct) + %d complex + %d singular + %d failed\n", h1.paths,
           h1.real, h1.real_distinct, h1.nonreal, h1.singular, h1.failed);
    CHECK(h1.paths == 16 && h1.real == 16 && h1.real_distinct == 16);
    CHECK(h1.duplicates == 0 && h1.unpaired == 0 && h1.max_residual < 64 * DBL_EPSILON);
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

/* The checker on made-up endpoints in P^2, in the charts z_k = 1: a real
 * root reached by three paths (twice in chart 0, once written in chart 1),
 * a conjugate pair, a non-real root without its conjugate, and a singular
 * endpoint (not looked at). */
static void checker(void)
{
    enum { N = 7, M = 3 };
    const double zr[N * M] = {1, 0.5, 0.25, 1, 0.5 + 1e-13, 0.25, 1, 0.3, 0.2, 1, 0.3, 0.2,
                              1, 0.7, 0.1, 2, 1, 0.5,           0, 0,   1};
    const double zi[N * M] = {0, 0, 0, 0, 0, 0, 0, 0.4, -0.1, 0, -0.4, 0.1, 0, 0, 0.5, 0, 0, 0, 0, 0, 0};
    const int kind[N] = {HOM_REAL, HOM_REAL, HOM_NONREAL, HOM_NONREAL, HOM_NONREAL, HOM_REAL, HOM_SINGULAR};
    const int chart[N] = {0, 0, 0, 0, 0, 1, 2};
    hom_end e[N];
    memset(e, 0, sizeof e);
    for (int p = 0; p < N; ++p) {
        e[p].kind = kind[p], e[p].chart = chart[p];
        e[p].rminus = 1e-15, e[p].rplus = 1e-2; /* as a certificate would give */
    }
    const double w[M] = {0.6, 0.0, 0.8};
    hom_key keys[N];
    int parent[N];
    unsigned char paired[N];
    hom_checks c = kin__hom_check(M, N, e, zr, zi, w, keys, parent, paired);
    printf("checker on made-up endpoints: %d duplicates, %d unpaired\n", c.duplicates, c.unpaired);
    CHECK(c.duplicates == 2 && c.unpaired == 1);
    CHECK(kin__hom_find(parent, 1) == 0 && kin__hom_find(parent, 5) == 0);
    CHECK(kin__hom_find(parent, 2) == 2 && kin__hom_find(parent, 3) == 3 && kin__hom_find(parent, 4) == 4);
    CHECK(paired[2] && paired[3] && !paired[4]);
    /* farther apart than half the uniqueness radius: distinct roots */
    e[1].rplus = e[0].rplus = 1e-14;
    c = kin__hom_check(M, N, e, zr, zi, w, keys, parent, paired);
    CHECK(c.duplicates == 1 && kin__hom_find(parent, 1) == 1);
}

/* A random system of s = 8 quadrics (Gaussian symmetric matrices): every
 * path accounted for, non-real endpoints in conjugate pairs, no root
 * reached twice, no path lost, real solutions satisfying the equations to
 * rounding, and the same answer for 1 and 2 threads. */
static void random_system(void)
{
    enum { S = 8, M = S + 1, MAXSOL = 1 << S };
    static double Q[M * M * S], b1[M * MAXSOL], b2[M * MAXSOL];
    int m1[MAXSOL], m2[MAXSOL], n1 = 0, n2 = 0;
    unsigned long long st = 2024;
    for (int j = 0; j < S; ++j)
        for (int r = 0; r < M; ++r)
            for (int c = r; c < M; ++c) {
                double u = ((kin__splitmix(&st) >> 11) + 0.5) * 0x1.0p-53;
                double v = ((kin__splitmix(&st) >> 11) + 0.5) * 0x1.0p-53;
                Q[j * M * M + r + c * M] = Q[j * M * M + c + r * M] = sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
            }
    kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
    CHECK_RC(kin_quadrics_homotopy(M, S, Q, 5, 1, b1, MAXSOL, &n1, m1, &h1), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy(M, S, Q, 5, 2, b2, MAXSOL, &n2, m2, &h2), KIN_OK);
    printf("random s = %d: %d paths = %d real (%d distinct) + %d complex + %d singular + %d failed; %d duplicates,"
           " %d unpaired, %d re-tracked, %.1f steps/path, residual %.1e, max cond %.1e\n",
           S, h1.paths, h1.real, h1.real_distinct, h1.nonreal, h1.singular, h1.failed, h1.duplicates, h1.unpaired,
           h1.retracked, (double)h1.steps / h1.paths, h1.max_residual, h1.max_cond);
    CHECK(h1.paths == MAXSOL && h1.real + h1.nonreal + h1.singular + h1.failed == h1.paths);
    CHECK(h1.nonreal % 2 == 0);
    CHECK(h1.failed == 0 && h1.singular == 0); /* generic: all 2^s roots simple */
    CHECK(h1.duplicates == 0 && h1.unpaired == 0 && h1.real == h1.real_distinct);
    CHECK(h1.max_residual < 64 * DBL_EPSILON);
    CHECK(n1 == h1.real_distinct);
    for (int k = 0; k < n1; ++k) CHECK(m1[k] == 1);
    CHECK(n1 == n2 && memcmp(&h1, &h2, sizeof h1) == 0 && memcmp(b1, b2, sizeof(double) * M * n1) == 0);
    CHECK(memcmp(m1, m2, sizeof(int) * n1) == 0);
}

int main(void)
{
    figure5();
    structures();
    checker();
    random_system();
    TEST_REPORT("test_homotopy");
}
