/* The follower's inverse of the bordered matrix by Gauss-Jordan elimination
 * (libkin/path/gauss_jordan.c), checked against LAPACK (dgetrf + dgetri):
 * residual |A X - I| within a multiple of n eps |A| |X| (the bound both
 * methods share), the sign of the determinant equal to the LU's, on dense
 * and sparse matrices (a bordered J^T of a real sail point, random ones
 * with J^T's sparsity) of sizes 1..64; exact answers on permutations;
 * singular and non-finite matrices refused. No timing. */
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "model/lapack.h"
#include "path/path.h"
#include "path/step_lu.h"
#include "libkin.h"
#include "sail_states.h"

enum { NMAX = 64 };

static double urand(unsigned long long *s) { return (double)(kin__splitmix(s) >> 11) * 0x1.0p-53 - 0.5; }

/* max_ij |(A X - I)_ij| / (n eps max_i (|A| |X|)_i-row sum): how many n eps
 * of the component-wise bound the residual takes */
static double residual_ratio(int n, const double *A, const double *X)
{
    double worst = 0.0, scale = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            double r = i == j ? -1.0 : 0.0, b = 0.0;
            for (int k = 0; k < n; ++k) {
                r += A[i + (size_t)k * n] * X[k + (size_t)j * n];
                b += fabs(A[i + (size_t)k * n]) * fabs(X[k + (size_t)j * n]);
            }
            worst = fmax(worst, fabs(r));
            scale = fmax(scale, b);
        }
    return worst / ((double)n * DBL_EPSILON * scale);
}

/* the sign of det(A) from dgetrf; 0 when singular */
static int lapack_sign(int n, const double *A)
{
    double F[NMAX * NMAX];
    int ipiv[NMAX], info = 0, sg = 1;
    memcpy(F, A, sizeof(double) * (size_t)n * (size_t)n);
    dgetrf_(&n, &n, F, &n, ipiv, &info);
    if (info != 0) return 0;
    for (int i = 0; i < n; ++i) {
        if (F[i + (size_t)i * n] < 0.0) sg = -sg;
        if (ipiv[i] != i + 1) sg = -sg;
    }
    return sg;
}

/* invert A (n x n) both ways; both residuals within 8 n eps |A||X|, the
 * same determinant sign, the two inverses equal to the conditioning's
 * rounding (relative to |X| times kappa) */
static void compare(int n, const double *A, const char *what)
{
    double X[NMAX * NMAX], L[NMAX * NMAX], work[64 * NMAX], col[NMAX];
    int perm[NMAX], cols[NMAX], ipiv[NMAX], sign = 7, info = 0, lwork = 64 * NMAX;
    memcpy(X, A, sizeof(double) * (size_t)n * (size_t)n);
    CHECK(kin__gauss_jordan_inverse(n, X, perm, cols, col, &sign) == 0);
    memcpy(L, A, sizeof(double) * (size_t)n * (size_t)n);
    dgetrf_(&n, &n, L, &n, ipiv, &info);
    CHECK(info == 0);
    dgetri_(&n, L, &n, ipiv, work, &lwork, &info);
    CHECK(info == 0);
    double rg = residual_ratio(n, A, X), rl = residual_ratio(n, A, L);
    if (!(rg <= 8.0) || sign != lapack_sign(n, A))
        fprintf(stderr, "%s (n = %d): residual %.3g n eps (LAPACK %.3g), sign %d vs %d\n", what, n, rg, rl, sign,
                lapack_sign(n, A));
    CHECK(rg <= 8.0);
    CHECK(rl <= 8.0);
    CHECK(sign == lapack_sign(n, A));
    /* kappa_inf estimated from the two inverses' norms */
    double na = 0.0, nx = 0.0, diff = 0.0;
    for (int i = 0; i < n; ++i) {
        double ra = 0.0, rx = 0.0;
        for (int j = 0; j < n; ++j) {
            ra += fabs(A[i + (size_t)j * n]);
            rx += fabs(X[i + (size_t)j * n]);
            diff = fmax(diff, fabs(X[i + (size_t)j * n] - L[i + (size_t)j * n]));
        }
        na = fmax(na, ra);
        nx = fmax(nx, rx);
    }
    CHECK(diff <= 64.0 * (double)n * DBL_EPSILON * na * nx * nx);
}

/* random dense matrices, sizes 1..64 */
static void dense(void)
{
    unsigned long long s = 0x6a;
    double A[NMAX * NMAX];
    for (int n = 1; n <= NMAX; n += (n < 8 ? 1 : 7)) {
        for (int i = 0; i < n * n; ++i) A[i] = urand(&s);
        compare(n, A, "dense");
    }
}

/* J^T's pattern: sparse bar columns (2 dim entries each), then dense
 * border columns; the elimination skips the columns with a zero in the
 * pivot row, which must not change the answer */
static void sparse_bordered(void)
{
    unsigned long long s = 0x5ba;
    double A[NMAX * NMAX];
    int sizes[] = {6, 12, 46, 63};
    for (size_t t = 0; t < sizeof sizes / sizeof sizes[0]; ++t) {
        int n = sizes[t];
        for (int trial = 0; trial < 5; ++trial) {
            memset(A, 0, sizeof(double) * (size_t)n * (size_t)n);
            int border = 1 + trial % 3;
            for (int j = 0; j < n - border; ++j) {
                /* a bar's column: -d at one joint, +d at another (3 coordinates each) */
                int p = (int)(kin__splitmix(&s) % (unsigned long long)(n / 3)) * 3, q = (p + 3 * (1 + j % 5)) % (n - n % 3);
                for (int c = 0; c < 3 && p + c < n && q + c < n; ++c) {
                    double d = urand(&s);
                    A[p + c + (size_t)j * n] -= d;
                    A[q + c + (size_t)j * n] += d;
                }
                A[j + (size_t)j * n] += 0.25; /* keeps the random pattern regular */
            }
            for (int j = n - border; j < n; ++j)
                for (int i = 0; i < n; ++i) A[i + (size_t)j * n] = urand(&s);
            compare(n, A, "sparse bordered");
        }
    }
}

/* a real bordered matrix: the hexagonal sail's J^T = [H, t] at a regular
 * point of a path (a generic configuration near the flat state, one step
 * on), as the follower inverts it */
static void sail_point(void)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL);
    if (!a) return;
    CHECK_RC(test_make_generic(a, 0.3), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 1 && an.m_rigid == 0);
    CHECK_RC(kin_step(a, 0.0, NULL), KIN_OK);
    int nf = a->nf, nb = a->nb;
    CHECK(nb + 1 == nf && nf <= NMAX && a->have_t);
    if (nb + 1 == nf && nf <= NMAX && a->have_t) {
        double A[NMAX * NMAX];
        kin__build_H(a, a->xyz, A, nf);
        memcpy(A + (size_t)nb * nf, a->t, sizeof(double) * (size_t)nf);
        compare(nf, A, "sail point");
    }
    kin_assembly_free(a);
}

/* permutation matrices (with signs): the inverse is the transpose, exactly */
static void permutations(void)
{
    double A[NMAX * NMAX], X[NMAX * NMAX], col[NMAX];
    int perm[NMAX], cols[NMAX], sign = 0;
    for (int n = 2; n <= 9; ++n) {
        memset(A, 0, sizeof(double) * (size_t)n * (size_t)n);
        for (int i = 0; i < n; ++i) A[(n - 1 - i) + (size_t)i * n] = i % 3 == 0 ? -2.0 : 0.5; /* anti-diagonal */
        memcpy(X, A, sizeof(double) * (size_t)n * (size_t)n);
        CHECK(kin__gauss_jordan_inverse(n, X, perm, cols, col, &sign) == 0);
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                double a = A[j + (size_t)i * n], want = a != 0.0 ? 1.0 / a : 0.0; /* (A^-1)_ij = 1 / A_ji */
                CHECK(X[i + (size_t)j * n] == want);
            }
        CHECK(sign == lapack_sign(n, A));
    }
}

/* exactly singular and non-finite matrices are refused with sign 0 */
static void refused(void)
{
    double A[16], col[4];
    int perm[4], cols[4], sign = 5;
    unsigned long long s = 0x51;
    for (int i = 0; i < 16; ++i) A[i] = urand(&s);
    for (int i = 0; i < 4; ++i) A[i + 2 * 4] = 0.0; /* a zero column */
    CHECK(kin__gauss_jordan_inverse(4, A, perm, cols, col, &sign) > 0);
    CHECK(sign == 0);
    for (int i = 0; i < 16; ++i) A[i] = urand(&s);
    for (int i = 0; i < 4; ++i) A[i + 3 * 4] = A[i + 1 * 4]; /* two equal columns: a zero pivot, exactly */
    sign = 5;
    CHECK(kin__gauss_jordan_inverse(4, A, perm, cols, col, &sign) > 0);
    CHECK(sign == 0);
    for (int i = 0; i < 16; ++i) A[i] = urand(&s);
    A[5] = NAN;
    sign = 5;
    CHECK(kin__gauss_jordan_inverse(4, A, perm, cols, col, &sign) > 0);
    CHECK(sign == 0);
    for (int i = 0; i < 16; ++i) A[i] = urand(&s);
    A[0] = INFINITY;
    sign = 5;
    CHECK(kin__gauss_jordan_inverse(4, A, perm, cols, col, &sign) > 0);
    CHECK(sign == 0);
}

int main(void)
{
    dense();
    sparse_bordered();
    sail_point();
    permutations();
    refused();
    TEST_REPORT("test_gauss_jordan");
}
