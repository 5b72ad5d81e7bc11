/* The equivariant start system's set-up (homotopy_equi.c): which cyclic
 * subgroup is chosen, the change of coordinates and equations (checked
 * through invariants: U orthogonal, R_h U = U P, the new system exactly
 * equivariant and spanning the same quadrics), the orbits of the start
 * roots (a bijection, Burnside's count), and the groups that do not
 * qualify. The solver's results on such systems are in
 * test_homotopy_sym.c. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "homotopy/symmetric/homotopy_equi.h"
#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"
#include "libkin.h"

enum { MAXM = 10 };

static unsigned long long rng = 7;
static double urand(void)
{
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return ((rng >> 11) * 0x1.0p-53) * 2.0 - 1.0;
}

static void matmul(int n, const double *A, const double *B, double *C)
{
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) {
            double v = 0.0;
            for (int k = 0; k < n; ++k) v += A[k * n + r] * B[c * n + k];
            C[c * n + r] = v;
        }
}

/* C = A^T B A */
static void congruence(int n, const double *A, const double *B, double *C)
{
    double T[MAXM * MAXM];
    matmul(n, B, A, T);
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) {
            double v = 0.0;
            for (int k = 0; k < n; ++k) v += A[r * n + k] * T[c * n + k];
            C[c * n + r] = v;
        }
}

/* a random orthogonal n x n matrix (Gram-Schmidt of random columns) */
static void random_orthogonal(int n, double *V)
{
    for (int i = 0; i < n * n; ++i) V[i] = urand();
    for (int c = 0; c < n; ++c) {
        double *v = V + c * n;
        for (int pass = 0; pass < 2; ++pass)
            for (int d = 0; d < c; ++d) {
                double p = 0.0;
                for (int r = 0; r < n; ++r) p += v[r] * V[d * n + r];
                for (int r = 0; r < n; ++r) v[r] -= p * V[d * n + r];
            }
        double nv = 0.0;
        for (int r = 0; r < n; ++r) nv += v[r] * v[r];
        for (int r = 0; r < n; ++r) v[r] /= sqrt(nv);
    }
}

/* A system equivariant under the permutation perm of coordinates (perm[0]
 * = 0, order k) with equations numbered like coordinates 1..s, hidden by a
 * random orthogonal change of coordinates V (beta = V x) and a random
 * invertible mixing of the equations; R receives the k group elements
 * V P^j V^T. */
static void hidden_system(int m, int k, const int *perm, double *Q, double *R)
{
    int s = m - 1;
    size_t mm = (size_t)m * m;
    int pinv[MAXM];
    for (int i = 0; i < m; ++i) pinv[perm[i]] = i;
    double *X = malloc(sizeof(double) * mm * s);
    unsigned char done[MAXM] = {0};
    for (int e0 = 0; e0 < s; ++e0) { /* one random matrix per cycle, its permutations */
        if (done[e0]) continue;
        int l = 1;
        for (int f = perm[e0 + 1] - 1; f != e0; f = perm[f + 1] - 1) ++l;
        /* the cycle's first matrix: a random one averaged over the
         * stabiliser <P^l> (A -> A[pinv^l a][pinv^l b]) */
        double A[MAXM * MAXM], *q = X + e0 * mm;
        int pl[MAXM], pi[MAXM];
        for (int c = 0; c < m; ++c)
            for (int r = 0; r <= c; ++r) A[c * m + r] = A[r * m + c] = urand();
        for (int i = 0; i < m; ++i) pl[i] = i;
        for (int i = 0; i < l; ++i)
            for (int c = 0; c < m; ++c) pl[c] = pinv[pl[c]];
        memset(q, 0, sizeof(double) * mm);
        for (int i = 0; i < m; ++i) pi[i] = i;
        for (int i = 0; i < k / l; ++i) {
            for (int c = 0; c < m; ++c)
                for (int r = 0; r < m; ++r) q[c * m + r] += A[pi[c] * m + pi[r]];
            for (int c = 0; c < m; ++c) pi[c] = pl[pi[c]];
        }
        done[e0] = 1;
        for (int e = e0, f = perm[e0 + 1] - 1; f != e0; e = f, f = perm[f + 1] - 1) {
            for (int c = 0; c < m; ++c)
                for (int r = 0; r < m; ++r) X[f * mm + c * m + r] = X[e * mm + pinv[c] * m + pinv[r]];
            done[f] = 1;
        }
    }
    double V[MAXM * MAXM], Vt[MAXM * MAXM], P[MAXM * MAXM] = {0}, T[MAXM * MAXM], Mix[MAXM * MAXM];
    random_orthogonal(m, V);
    for (int c = 0; c < m; ++c)
        for (int r = 0; r < m; ++r) Vt[c * m + r] = V[r * m + c];
    for (int i = 0; i < m; ++i) P[perm[i] * m + i] = 1.0;
    for (int i = 0; i < s * s; ++i) Mix[i] = urand() + (i % (s + 1) == 0 ? 3.0 : 0.0);
    for (int j = 0; j < s; ++j) { /* Q_j = sum_e Mix_je V X_e V^T */
        double *q = Q + j * mm;
        memset(q, 0, sizeof(double) * mm);
        for (int e = 0; e < s; ++e) {
            congruence(m, Vt, X + e * mm, T);
            for (size_t x = 0; x < mm; ++x) q[x] += Mix[e * s + j] * T[x];
        }
    }
    /* R_j = V P^j V^T */
    double Pj[MAXM * MAXM] = {0};
    for (int i = 0; i < m; ++i) Pj[i * m + i] = 1.0;
    for (int j = 0; j < k; ++j) {
        matmul(m, V, Pj, T);
        matmul(m, T, Vt, R + j * mm);
        matmul(m, Pj, P, T);
        memcpy(Pj, T, sizeof(double) * mm);
    }
    free(X);
}

/* set up the solver's problem and group for (Q, R) and plan */
static int plan(int m, const double *Q, int ng, const double *R, hom_equi *E, hom_solver *H, sym_group *G)
{
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = 1;
    char err[128];
    int rc = kin__hom_solver_init(H, m, m - 1, Q, &o, 1);
    if (!rc) rc = kin__sym_group_init(G, m, m - 1, H->Qr, ng, R, err, sizeof err);
    if (!rc) rc = kin__equi_plan(E, m, m - 1, H->Qr, G, 5);
    return rc;
}

static void check_plan(const char *name, int m, int k, const int *perm)
{
    int s = m - 1;
    size_t mm = (size_t)m * m;
    double *Q = malloc(sizeof(double) * mm * s), *R = malloc(sizeof(double) * mm * k);
    hidden_system(m, k, perm, Q, R);
    hom_equi E;
    hom_solver H;
    sym_group G;
    memset(&G, 0, sizeof G);
    CHECK_RC(plan(m, Q, k, R, &E, &H, &G), KIN_OK);
    printf("%s: subgroup order %d (want %d)\n", name, E.k, k);
    CHECK(E.k == k);
    if (E.k == k) {
        /* U orthogonal */
        double UtU[MAXM * MAXM], Ut[MAXM * MAXM], A[MAXM * MAXM], B[MAXM * MAXM], P[MAXM * MAXM] = {0};
        for (int c = 0; c < m; ++c)
            for (int r = 0; r < m; ++r) Ut[c * m + r] = E.U[r * m + c];
        matmul(m, Ut, E.U, UtU);
        double dev = 0.0;
        for (int c = 0; c < m; ++c)
            for (int r = 0; r < m; ++r) dev = fmax(dev, fabs(UtU[c * m + r] - (r == c)));
        CHECK(dev <= 100 * m * DBL_EPSILON);
        /* some group element h with h U = U P (P: the plan's permutation) */
        for (int i = 0; i < m; ++i) P[E.perm[i] * m + i] = 1.0;
        double best = INFINITY;
        for (int g = 0; g < G.n; ++g)
            for (int sg = -1; sg <= 1; sg += 2) {
                double h[MAXM * MAXM];
                for (size_t x = 0; x < mm; ++x) h[x] = sg * G.R[g * mm + x];
                matmul(m, h, E.U, A);
                matmul(m, E.U, P, B);
                double d = 0.0;
                for (size_t x = 0; x < mm; ++x) d = fmax(d, fabs(A[x] - B[x]));
                best = fmin(best, d);
            }
        CHECK(best <= 1e3 * DBL_EPSILON);
        /* the new system exactly equivariant: Qt_{p(j)}[a][b] = Qt_j[pinv a][pinv b] */
        int pinv[MAXM], exact = 1;
        for (int i = 0; i < m; ++i) pinv[E.perm[i]] = i;
        for (int j = 1; j <= s; ++j) {
            const double *qa = E.Qt + (j - 1) * mm, *qb = E.Qt + (E.perm[j] - 1) * mm;
            for (int c = 0; c < m; ++c)
                for (int r = 0; r < m; ++r) exact &= qb[c * m + r] == qa[pinv[c] * m + pinv[r]];
        }
        CHECK(exact);
        /* ... and spanning the quadrics U^T Q_i U: each Qt_e's distance to
         * their span (least squares through the Gram matrix) */
        double *B2 = malloc(sizeof(double) * mm * s), Gm[MAXM * MAXM], worst = 0.0;
        for (int i = 0; i < s; ++i) congruence(m, E.U, H.Qr + i * mm, B2 + i * mm);
        for (int i = 0; i < s; ++i) /* orthonormalise the B_i (Gram-Schmidt twice) */
            for (int pass = 0; pass < 2; ++pass) {
                for (int d = 0; d < i; ++d) {
                    double p = 0.0;
                    for (size_t x = 0; x < mm; ++x) p += B2[i * mm + x] * B2[d * mm + x];
                    for (size_t x = 0; x < mm; ++x) B2[i * mm + x] -= p * B2[d * mm + x];
                }
                double nb = 0.0;
                for (size_t x = 0; x < mm; ++x) nb += B2[i * mm + x] * B2[i * mm + x];
                for (size_t x = 0; x < mm; ++x) B2[i * mm + x] /= sqrt(nb);
            }
        (void)Gm;
        for (int e = 0; e < s; ++e) {
            double r[MAXM * MAXM], nq = 0.0, nr = 0.0;
            memcpy(r, E.Qt + e * mm, sizeof(double) * mm);
            for (size_t x = 0; x < mm; ++x) nq += r[x] * r[x];
            for (int d = 0; d < s; ++d) {
                double p = 0.0;
                for (size_t x = 0; x < mm; ++x) p += r[x] * B2[d * mm + x];
                for (size_t x = 0; x < mm; ++x) r[x] -= p * B2[d * mm + x];
            }
            for (size_t x = 0; x < mm; ++x) nr += r[x] * r[x];
            worst = fmax(worst, sqrt(nr / nq));
        }
        CHECK(worst <= 1e3 * DBL_EPSILON);
        free(B2);
        /* the orbits */
        hom_orbits O;
        CHECK_RC(kin__orbits_init(&O, m, E.perm), KIN_OK);
        CHECK(O.nreps == kin__orbits_count(m, k, E.perm)); /* the table against Burnside */
        int *hits = calloc((size_t)O.npaths, sizeof(int)), okrep = 1;
        for (int b = 0; b < O.npaths; ++b) {
            hits[O.next[b]]++;
            okrep &= O.rep[b] <= b && O.rep[O.next[b]] == O.rep[b] && O.rep[O.rep[b]] == O.rep[b];
            /* the orbit's length divides k */
            int len = 1;
            for (int c = O.next[b]; c != b; c = O.next[c]) ++len;
            okrep &= k % len == 0;
        }
        for (int b = 0; b < O.npaths; ++b) okrep &= hits[b] == 1; /* a bijection */
        for (int i = 1; i < O.nreps; ++i) okrep &= O.reps[i - 1] < O.reps[i] && O.rep[O.reps[i]] == O.reps[i];
        CHECK(okrep);
        free(hits);
        kin__orbits_free(&O);
    }
    kin__equi_free(&E);
    kin__sym_group_free(&G);
    kin__hom_solver_free(&H);
    free(Q), free(R);
}

/* a group that does not qualify: E.k == 0, nothing allocated */
static void check_none(const char *name, int m, const double *Q, int ng, const double *R)
{
    hom_equi E;
    hom_solver H;
    sym_group G;
    memset(&G, 0, sizeof G);
    CHECK_RC(plan(m, Q, ng, R, &E, &H, &G), KIN_OK);
    printf("%s: subgroup order %d (want 0)\n", name, E.k);
    CHECK(E.k == 0 && E.Qt == NULL);
    kin__equi_free(&E);
    kin__sym_group_free(&G);
    kin__hom_solver_free(&H);
}

int main(void)
{
    /* C3 on two triples (the hexagonal sail's kind), C4 on two 4-cycles
     * (the octagonal one's), C6 on cycles of lengths 1, 2, 3 (a fixed
     * coordinate besides x_0; the cycle type from the characters at every
     * divisor) and C2 on pairs */
    int c3[7] = {0, 2, 3, 1, 5, 6, 4};
    check_plan("C3 on 2 triples", 7, 3, c3);
    int c4[9] = {0, 2, 3, 4, 1, 6, 7, 8, 5};
    check_plan("C4 on 2 four-cycles", 9, 4, c4);
    int c6[7] = {0, 1, 3, 2, 5, 6, 4};
    check_plan("C6 on cycles 1, 2, 3", 7, 6, c6);
    int c2[5] = {0, 2, 1, 4, 3};
    check_plan("C2 on 2 pairs", 5, 2, c2);

    /* not qualifying: sign changes of two coordinates with invariant
     * equations; the trivial group */
    {
        int m = 5, s = 4;
        size_t mm = (size_t)m * m;
        double Q[5 * 5 * 4], R[2 * 5 * 5] = {0}, A[25], C[25];
        for (int i = 0; i < m; ++i) R[i * m + i] = 1.0, R[mm + i * m + i] = i == 1 || i == 2 ? -1.0 : 1.0;
        for (int j = 0; j < s; ++j) { /* Q_j = A + D A D: invariant */
            for (int c = 0; c < m; ++c)
                for (int r = 0; r <= c; ++r) A[c * m + r] = A[r * m + c] = urand();
            congruence(m, R + mm, A, C);
            for (size_t x = 0; x < mm; ++x) Q[j * mm + x] = A[x] + C[x];
        }
        check_none("C2 sign changes", m, Q, 2, R);
        check_none("trivial group", m, Q, 0, NULL);
    }
    TEST_REPORT("test_homotopy_equi");
}
