/* kin_symmetries and kin_mechanism_group: the symmetries of the sails (3D,
 * flat: rotations and the mirror z -> -z), of symmetric and asymmetric
 * planar linkages, the group's invariants (identity first, orthogonal,
 * closed under products up to sign, every symmetry keeps the
 * configuration and the bars), the equivariance of the second-order
 * system (kin_quadrics_homotopy_sym accepts it and counts as the plain
 * solver), and every error path. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "libkin.h"
#include "sail_states.h"

#define MAXG 64

/* index of the matrix of G (ng of m x m) equal to A up to sign, or -1 */
static int find_up_to_sign(int m, int ng, const double *G, const double *A, double tol)
{
    for (int k = 0; k < ng; ++k) {
        int plus = 1, minus = 1;
        for (int i = 0; i < m * m; ++i) {
            if (fabs(G[k * m * m + i] - A[i]) > tol) plus = 0;
            if (fabs(G[k * m * m + i] + A[i]) > tol) minus = 0;
        }
        if (plus || minus) return k;
    }
    return -1;
}

/* the invariants of a mechanism group: R_0 = I, every R orthogonal, every
 * product in the list up to sign */
static void check_group(int m, int ng, const double *R)
{
    double tol = 1e3 * m * DBL_EPSILON, worst = 0.0;
    for (int i = 0; i < m * m; ++i) worst = fmax(worst, fabs(R[i] - (i % (m + 1) == 0)));
    CHECK(worst <= tol);
    double *P = malloc(sizeof(double) * m * m);
    for (int g = 0; g < ng; ++g) {
        const double *A = R + (size_t)g * m * m;
        double orth = 0.0;
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c) {
                double v = 0.0;
                for (int k = 0; k < m; ++k) v += A[k + r * m] * A[k + c * m];
                orth = fmax(orth, fabs(v - (r == c)));
            }
        CHECK(orth <= tol);
        for (int h = 0; h < ng; ++h) {
            const double *B = R + (size_t)h * m * m;
            for (int r = 0; r < m; ++r)
                for (int c = 0; c < m; ++c) {
                    double v = 0.0;
                    for (int k = 0; k < m; ++k) v += A[r + k * m] * B[k + c * m];
                    P[r + c * m] = v;
                }
            CHECK(find_up_to_sign(m, ng, R, P, 1e-8) >= 0);
        }
    }
    free(P);
}

/* every symmetry keeps the configuration, maps bars to bars of the same
 * rest length and has an orthogonal Q; the identity comes first */
static void check_symmetries(kin_assembly *a, int ns, const int *perm, const double *Q, const double *t)
{
    int nj = kin_njoints(a), nb = kin_nbars(a), d = kin_dim(a);
    double *X = malloc(sizeof(double) * nj * d), *L0 = malloc(sizeof(double) * nb);
    int *bars = malloc(sizeof(int) * 2 * nb);
    kin_get_coords(a, X);
    kin_get_rest_lengths(a, L0);
    kin_get_bars(a, bars);
    double size = 1.0;
    for (int i = 0; i < nj * d; ++i) size = fmax(size, fabs(X[i]));
    for (int i = 0; i < nj; ++i) CHECK(perm[i] == i);
    for (int i = 0; i < d * d; ++i) CHECK(Q[i] == (i % (d + 1) == 0)); /* the identity exactly */
    for (int i = 0; i < d; ++i) CHECK(t[i] == 0.0);
    for (int g = 0; g < ns; ++g) {
        const int *p = perm + (size_t)g * nj;
        const double *q = Q + (size_t)g * d * d, *tg = t + (size_t)g * d;
        double worst = 0.0, orth = 0.0;
        for (int i = 0; i < nj; ++i)
            for (int r = 0; r < d; ++r) {
                double y = tg[r];
                for (int k = 0; k < d; ++k) y += q[r + k * d] * X[i * d + k];
                worst = fmax(worst, fabs(y - X[p[i] * d + r]));
            }
        CHECK(worst <= 1e-7 * size);
        for (int r = 0; r < d; ++r)
            for (int c = 0; c < d; ++c) {
                double v = 0.0;
                for (int k = 0; k < d; ++k) v += q[k + r * d] * q[k + c * d];
                orth = fmax(orth, fabs(v - (r == c)));
            }
        CHECK(orth <= 100 * DBL_EPSILON);
        for (int k = 0; k < nb; ++k) { /* bar (A, B) -> some bar (pA, pB) of the same rest length */
            int A = p[bars[2 * k]], B = p[bars[2 * k + 1]], found = 0;
            for (int l = 0; l < nb && !found; ++l)
                found = ((bars[2 * l] == A && bars[2 * l + 1] == B) || (bars[2 * l] == B && bars[2 * l + 1] == A)) &&
                        fabs(L0[l] - L0[k]) <= 1e-7 * L0[k];
            CHECK(found);
        }
    }
    free(X), free(L0), free(bars);
}

/* symmetries and group of a: sizes as expected, invariants; returns ng */
static int group_of(kin_assembly *a, int want_sym, int want_m, double *R)
{
    int nj = kin_njoints(a), d = kin_dim(a), ns = -1, ng = -1;
    int *perm = malloc(sizeof(int) * MAXG * nj);
    double *Q = malloc(sizeof(double) * MAXG * d * d), *t = malloc(sizeof(double) * MAXG * d);
    CHECK_RC(kin_symmetries(a, MAXG, perm, Q, t, &ns), KIN_OK);
    CHECK(ns == want_sym);
    if (ns >= 1 && ns <= MAXG) check_symmetries(a, ns, perm, Q, t);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_mechanism_group(a, MAXG, R, &ng), KIN_OK);
    CHECK_RC(kin_get_analysis(a, &an), KIN_OK); /* made by kin_mechanism_group */
    CHECK(an.m_internal == want_m);
    CHECK(ng == want_sym);
    if (ng >= 1 && ng <= MAXG && an.m_internal == want_m) check_group(want_m, ng, R);
    free(perm), free(Q), free(t);
    return ng;
}

static void sails(void)
{
    /* hub sides, loops, symmetries (rotations x mirror), m_internal:
     * the counts Python's libkin.automorphisms finds */
    const int cases[][4] = {{4, 1, 4, 5}, {6, 1, 6, 10}, {4, 2, 4, 9}, {6, 2, 6, 16}, {8, 1, 8, 13}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        kin_assembly *a = test_sail(cases[c][0], cases[c][1]);
        CHECK(a != NULL);
        if (!a) continue;
        int m = cases[c][3];
        double *R = malloc(sizeof(double) * MAXG * m * m);
        int ng = group_of(a, cases[c][2], m, R);
        printf("sail %d,%d flat: %d symmetries, m = %d\n", cases[c][0], cases[c][1], ng, m);
        if (cases[c][0] == 6 && ng == 6) {
            /* the same set as the hand-written C3 x mirror finder of sail_states.h */
            int nf = kin_nfree(a);
            double *U = malloc(sizeof(double) * nf * m), *Rh = malloc(sizeof(double) * 6 * m * m);
            CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, nf, m), KIN_OK);
            CHECK(test_rotation_group(a, m, U, Rh, 6) == 6);
            for (int g = 0; g < 6; ++g) {
                int k = -1; /* R_g exactly (not up to sign) among Rh */
                for (int h = 0; h < 6 && k < 0; ++h) {
                    double dmax = 0.0;
                    for (int i = 0; i < m * m; ++i) dmax = fmax(dmax, fabs(R[g * m * m + i] - Rh[h * m * m + i]));
                    if (dmax <= 1e-10) k = h;
                }
                CHECK(k >= 0);
            }
            free(U), free(Rh);
        }
        free(R);
        kin_assembly_free(a);
    }
}

/* the symmetries do not depend on the unit: the hexagonal sail scaled by
 * 1e-100 and 1e100 has the same 6 (an absolute tolerance would accept
 * every candidate of the tiny one) */
static void units(void)
{
    kin_assembly *a = test_sail(6, 1);
    CHECK(a != NULL);
    if (!a) return;
    int nj = kin_njoints(a), nb = kin_nbars(a), *bars = malloc(sizeof(int) * 2 * nb);
    double *xyz = malloc(sizeof(double) * 3 * nj), *L0 = malloc(sizeof(double) * nb), *x2 = malloc(sizeof(double) * 3 * nj);
    double *l2 = malloc(sizeof(double) * nb), R[MAXG * 100];
    unsigned char *fixed = malloc((size_t)3 * nj);
    kin_get_coords(a, xyz), kin_get_rest_lengths(a, L0), kin_get_bars(a, bars), kin_get_fixed(a, fixed);
    const double scales[] = {1e-100, 1e100};
    for (int k = 0; k < 2; ++k) {
        for (int i = 0; i < 3 * nj; ++i) x2[i] = xyz[i] * scales[k];
        for (int i = 0; i < nb; ++i) l2[i] = L0[i] * scales[k];
        kin_assembly *b = NULL;
        CHECK_RC(kin_assembly_create(3, nj, x2, fixed, nb, bars, l2, &b, NULL, 0), KIN_OK);
        if (b) group_of(b, 6, 10, R);
        kin_assembly_free(b);
    }
    free(bars), free(xyz), free(L0), free(x2), free(l2), free(fixed);
    kin_assembly_free(a);
}

/* the square sail's flat state: the system is equivariant under the group
 * found, and the complete solver with symmetry counts as the plain one */
static void sail_solve(void)
{
    kin_assembly *a = test_sail(4, 1);
    CHECK(a != NULL);
    if (!a) return;
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    int m = an.m_internal, s = 0, ng = 0, n1 = 0, n2 = 0;
    double *Q = malloc(sizeof(double) * m * m * an.s), *R = malloc(sizeof(double) * MAXG * m * m);
    double *b1 = malloc(sizeof(double) * m * 64), *b2 = malloc(sizeof(double) * m * 64);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s), KIN_OK);
    CHECK_RC(kin_mechanism_group(a, MAXG, R, &ng), KIN_OK);
    CHECK(m == 5 && s == 4 && ng == 4);
    if (m == 5 && s == 4 && ng == 4) {
        kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
        kin_homotopy_sym_info si = {.size = sizeof si};
        kin_homotopy_options o;
        kin_homotopy_options_default(&o);
        o.nthreads = 1;
        CHECK_RC(kin_quadrics_homotopy_ex(m, s, Q, &o, b1, 64, &n1, NULL, &h1), KIN_OK);
        CHECK_RC(kin_quadrics_homotopy_sym(m, s, Q, ng, R, &o, b2, 64, &n2, NULL, &h2, &si, NULL, 0), KIN_OK);
        CHECK(h1.paths == 16 && h2.paths == 16);
        CHECK(h1.real == h2.real && h1.real_distinct == h2.real_distinct && n1 == n2);
        CHECK(si.group >= 2); /* projectively: the C2 rotation at least */
        printf("sail 4,1 flat: plain solver %d real (%d distinct), with the group of %d: %d real (%d distinct), "
               "projective order %d\n",
               h1.real, h1.real_distinct, ng, h2.real, h2.real_distinct, si.group);
    }
    free(Q), free(R), free(b1), free(b2);
    kin_assembly_free(a);
}

/* planar linkages: a symmetric five-bar chain between two supports (the
 * mirror x -> -x; m = 2), the same with one joint moved (no symmetry but
 * the identity), and a symmetric four-bar (m = 1) */
static void planar(void)
{
    {
        double xyz[] = {-1, 0, 1, 0, -1.2, 1, 1.2, 1, 0, 1.8};
        unsigned char fixed[] = {1, 1, 1, 1, 0, 0, 0, 0, 0, 0};
        int bars[] = {0, 2, 2, 4, 4, 3, 3, 1};
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(2, 5, xyz, fixed, 4, bars, NULL, &a, NULL, 0), KIN_OK);
        double R[MAXG * 4];
        int ng = group_of(a, 2, 2, R);
        /* the mirror is a reflection of the plane of mechanisms, not +-I: one
         * mechanism is symmetric, one antisymmetric (trace 0, determinant -1) */
        if (ng == 2) {
            CHECK(fabs(R[4] + R[7]) <= 1e-12);
            CHECK(fabs(R[4] * R[7] - R[5] * R[6] + 1.0) <= 1e-12);
        }
        kin_assembly_free(a);
        xyz[8] = 0.1; /* the apex off the axis */
        CHECK_RC(kin_assembly_create(2, 5, xyz, fixed, 4, bars, NULL, &a, NULL, 0), KIN_OK);
        ng = group_of(a, 1, 2, R);
        kin_assembly_free(a);
    }
    {
        double xyz[] = {-1, 0, 1, 0, -1, 1, 1, 1};
        unsigned char fixed[] = {1, 1, 1, 1, 0, 0, 0, 0};
        int bars[] = {0, 2, 2, 3, 3, 1};
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(2, 4, xyz, fixed, 3, bars, NULL, &a, NULL, 0), KIN_OK);
        double R[MAXG];
        int ng = group_of(a, 2, 1, R);
        if (ng == 2) CHECK(fabs(R[1] + 1.0) <= 1e-12); /* the sway mechanism: mirrored, reversed */
        kin_assembly_free(a);
    }
}

static void errors(void)
{
    kin_assembly *a = test_sail(6, 1);
    CHECK(a != NULL);
    if (!a) return;
    int nj = kin_njoints(a), ns = -1, ng = -1, m = 10;
    double *R = malloc(sizeof(double) * MAXG * m * m), Q[9 * MAXG], t[3 * MAXG];
    int *perm = malloc(sizeof(int) * MAXG * nj);
    CHECK_RC(kin_symmetries(NULL, MAXG, perm, Q, t, &ns), KIN_ENULL);
    CHECK(ns == 0);
    CHECK_RC(kin_symmetries(a, MAXG, perm, Q, t, NULL), KIN_ENULL);
    ns = -1;
    CHECK_RC(kin_symmetries(a, 0, perm, Q, t, &ns), KIN_EINVAL);
    CHECK(ns == 0);
    CHECK_RC(kin_symmetries(a, 5, perm, Q, t, &ns), KIN_ERANGE);
    CHECK(ns == 6); /* how many there are */
    CHECK_RC(kin_symmetries(a, 6, NULL, NULL, NULL, &ns), KIN_OK); /* counting only */
    CHECK(ns == 6);
    CHECK_RC(kin_mechanism_group(NULL, MAXG, R, &ng), KIN_ENULL);
    CHECK(ng == 0);
    CHECK_RC(kin_mechanism_group(a, MAXG, NULL, &ng), KIN_ENULL);
    CHECK_RC(kin_mechanism_group(a, MAXG, R, NULL), KIN_ENULL);
    ng = -1;
    CHECK_RC(kin_mechanism_group(a, 0, R, &ng), KIN_EINVAL);
    CHECK(ng == 0);
    R[0] = 42.0;
    CHECK_RC(kin_mechanism_group(a, 3, R, &ng), KIN_ERANGE);
    CHECK(ng == 6 && R[0] == 42.0);
    /* a broken group action is refused, not returned */
    kin__set_fault(a, KIN__FAULT_SYM_NOT_ORTHOGONAL);
    CHECK_RC(kin_mechanism_group(a, MAXG, R, &ng), KIN_ESTATE);
    CHECK(ng == 0 && R[0] == 42.0);
    /* the analysis fails: its status */
    kin__set_fault(a, KIN__FAULT_SVD_ARG);
    double *xyz = malloc(sizeof(double) * 3 * nj);
    kin_get_coords(a, xyz);
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK); /* invalidates the analysis */
    CHECK_RC(kin_mechanism_group(a, MAXG, R, &ng), KIN_ELAPACK_ARG);
    kin__set_fault(a, KIN__FAULT_NONE);
    CHECK_RC(kin_mechanism_group(a, MAXG, R, &ng), KIN_OK);
    CHECK(ng == 6);
    free(xyz), free(R), free(perm);
    kin_assembly_free(a);

    /* no internal mechanism: a braced triangle on two supports */
    {
        double p[] = {0, 0, 2, 0, 1, 1};
        unsigned char fx[] = {1, 1, 1, 1, 0, 0};
        int b[] = {0, 1, 0, 2, 1, 2};
        kin_assembly *tri = NULL;
        double r[4];
        CHECK_RC(kin_assembly_create(2, 3, p, fx, 3, b, NULL, &tri, NULL, 0), KIN_OK);
        CHECK_RC(kin_mechanism_group(tri, 4, r, &ng), KIN_ENOMECH);
        CHECK(ng == 0);
        CHECK_RC(kin_symmetries(tri, 4, NULL, NULL, NULL, &ns), KIN_OK);
        CHECK(ns == 2); /* the mirror x -> 2 - x */
        kin_assembly_free(tri);
    }
    /* too many graph automorphisms: a star of 9 equal spokes from a
     * support (9! = 362880 candidates; 18 of them geometric) */
    {
        enum { K = 9 };
        double p[2 * (K + 1)] = {0, 0};
        unsigned char fx[2 * (K + 1)] = {1, 1};
        int b[2 * K];
        for (int k = 0; k < K; ++k) {
            p[2 + 2 * k] = cos(2 * 3.14159265358979323846 * k / K);
            p[3 + 2 * k] = sin(2 * 3.14159265358979323846 * k / K);
            b[2 * k] = 0, b[2 * k + 1] = k + 1;
        }
        kin_assembly *star = NULL;
        CHECK_RC(kin_assembly_create(2, K + 1, p, fx, K, b, NULL, &star, NULL, 0), KIN_OK);
        ns = -1;
        CHECK_RC(kin_symmetries(star, MAXG, NULL, NULL, NULL, &ns), KIN_ELIMIT);
        CHECK(ns == 0);
        kin_assembly_free(star);
    }
}

int main(void)
{
    sails();
    units();
    sail_solve();
    planar();
    errors();
    TEST_REPORT("test_mechanism_group");
}
