/* The equivariant total-degree homotopy (homotopy_equi.h): finding a cyclic
 * subgroup that acts by permutations, the change of coordinates and
 * equations that shows it, and the orbits of the start roots.
 *
 * Which subgroups qualify. h of order k acts on beta by R_h and on the
 * equations by S_h (q(R_h b) = S_h q(b)). Real representations with the
 * same character are isomorphic, so R_h is a permutation of coordinates
 * that fixes one (in some orthonormal basis) and S_h the same permutation
 * of the others exactly when tr R_{h^j} = 1 + tr S_{h^j} for every j and
 * tr S_{h^j} counts the fixed points of a permutation of s points made of
 * cycles whose lengths divide k: with a_l cycles of length l, h^j fixes
 * sum_{l | gcd(j, k)} l a_l points, which determines the a_l (from the
 * divisors of k up) and they must come out as non-negative integers.
 * Both -R_h and R_h are tried (the caller's group is projective).
 *
 * The change of basis. With the Q_j made orthonormal (Frobenius inner
 * product), S_h is orthogonal. An intertwiner U (R_h U = U P) is the
 * average sum_j R_h^j M P^-j of a random M, invertible because the two
 * representations are isomorphic; its polar factor is an orthogonal
 * intertwiner. The same for the equations: W S_h = Phat W, Phat the
 * permutation of the equations. Then Qt_e = sum_i W_ei U^T Q_i U. Only one
 * equation per cycle is computed so; the others are its exact permutations
 * (checked against the computed ones), so that the tracked system is
 * equivariant to the last bit. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/symmetric/homotopy_equi.h"
#include "model/internal.h"
#include "model/lapack.h"

enum { ORDER_MAX = 64 }; /* cyclic subgroups of larger order are not considered */
/* An element's power is the identity within IDENTITY_TOL (largest entry);
 * characters are integers within CHAR_TOL; the change of basis must
 * intertwine within BASIS_TOL. */
static const double IDENTITY_TOL = 1e-8, CHAR_TOL = 1e-6, BASIS_TOL = 1e-8;

/* C = A B, n x n column-major */
static void mat_mul(int n, const double *A, const double *B, double *C)
{
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) {
            double v = 0.0;
            for (int k = 0; k < n; ++k) v += A[k * n + r] * B[c * n + k];
            C[c * n + r] = v;
        }
}

/* C = A^T B A, n x n column-major (C must not alias) */
static void congruence(int n, const double *A, const double *B, double *C, double *T)
{
    mat_mul(n, B, A, T);
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) {
            double v = 0.0;
            for (int k = 0; k < n; ++k) v += A[r * n + k] * T[c * n + k];
            C[c * n + r] = v;
        }
}

static double dot(size_t n, const double *a, const double *b)
{
    double v = 0.0;
    for (size_t i = 0; i < n; ++i) v += a[i] * b[i];
    return v;
}

static double max_dev_identity(int n, const double *A)
{
    double d = 0.0;
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) d = fmax(d, fabs(A[c * n + r] - (r == c)));
    return d;
}

/* the orthogonal polar factor of A (n x n, replaced); ws: 3 n^2 doubles.
 * KIN_OK, KIN_ENOTCONVERGED (A numerically singular), KIN_ENOMEM, LAPACK's */
static int polar(int n, double *A, double *ws)
{
    double *u = ws, *vt = ws + n * n, sv[HOM_MAX_M], q;
    int info = 0, lwork = -1;
    dgesvd_("A", "A", &n, &n, A, &n, sv, u, &n, vt, &n, &q, &lwork, &info, 1, 1);
    if (info) return info < 0 ? KIN_ELAPACK_ARG : KIN_ELAPACK_CONV;
    lwork = (int)q;
    double *work = malloc(sizeof(double) * (size_t)lwork);
    if (!work) return KIN_ENOMEM;
    dgesvd_("A", "A", &n, &n, A, &n, sv, u, &n, vt, &n, work, &lwork, &info, 1, 1);
    free(work);
    if (info) return info < 0 ? KIN_ELAPACK_ARG : KIN_ELAPACK_CONV;
    if (!(sv[n - 1] > 1e-6 * sv[0])) return KIN_ENOTCONVERGED;
    mat_mul(n, u, vt, A);
    return KIN_OK;
}

static double gauss(unsigned long long *st)
{
    double u = ((kin__splitmix(st) >> 11) + 1.0) * 0x1.0p-53, v = (kin__splitmix(st) >> 11) * 0x1.0p-53;
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* the cycle type of a permutation character: f[d] (fixed points of h^d)
 * for the divisors d of k; a[l] receives the cycles of length l. 1 if it
 * is one. */
static int cycle_type(int k, const int *f, int *a)
{
    for (int l = 1; l <= k; ++l) {
        a[l] = 0;
        if (k % l) continue;
        int rem = f[l];
        for (int d = 1; d < l; ++d)
            if (l % d == 0) rem -= d * a[d];
        if (rem < 0 || rem % l) return 0;
        a[l] = rem / l;
    }
    return 1;
}

static int gcd(int a, int b)
{
    while (b) {
        int t = a % b;
        a = b, b = t;
    }
    return a;
}

/* Does <h> qualify? k receives its order, perm (m) the permutation. Qo:
 * the orthonormal Q_j; ws: 3 m^2 doubles. */
static int qualifies(int m, int s, const double *h, const double *Qo, int *k_out, int *perm, double *ws)
{
    size_t mm = (size_t)m * m;
    double *Hp = ws, *T = ws + mm, *C = ws + 2 * mm;
    int k = 0;
    memcpy(Hp, h, sizeof(double) * mm);
    for (int j = 1; j <= ORDER_MAX; ++j) {
        if (max_dev_identity(m, Hp) <= IDENTITY_TOL) {
            k = j;
            break;
        }
        mat_mul(m, Hp, h, T);
        memcpy(Hp, T, sizeof(double) * mm);
    }
    if (k < 2) return 0;
    int f[ORDER_MAX + 1], a[ORDER_MAX + 1];
    memcpy(Hp, h, sizeof(double) * mm);
    for (int j = 1; j < k; ++j) {
        double trR = 0.0, trS = 0.0;
        for (int i = 0; i < m; ++i) trR += Hp[i * m + i];
        for (int e = 0; e < s; ++e) { /* (S)_ee = <R^T Q_e R, Q_e> */
            congruence(m, Hp, Qo + e * mm, C, T);
            trS += dot(mm, C, Qo + e * mm);
        }
        double fr = nearbyint(trS);
        if (!(fabs(trS - fr) <= CHAR_TOL) || !(fabs(trR - 1.0 - fr) <= CHAR_TOL) || fr < 0.0) return 0;
        f[j] = (int)fr;
        mat_mul(m, Hp, h, T);
        memcpy(Hp, T, sizeof(double) * mm);
    }
    f[k] = s;
    for (int j = 1; j < k; ++j)
        if (f[j] != f[gcd(j, k)]) return 0;
    if (!cycle_type(k, f, a)) return 0;
    /* coordinate 0 fixed, then the cycles by length, each on consecutive
     * coordinates */
    int i = 1;
    perm[0] = 0;
    for (int l = 1; l <= k; ++l)
        for (int c = 0; c < a[l]; ++c, i += l)
            for (int t = 0; t < l; ++t) perm[i + t] = i + (t + 1) % l;
    *k_out = k;
    return i == m;
}

/* P as a matrix: P[i][p(i)] = 1 (column-major n x n) */
static void perm_matrix(int n, const int *p, double *P)
{
    memset(P, 0, sizeof(double) * (size_t)n * n);
    for (int i = 0; i < n; ++i) P[p[i] * n + i] = 1.0;
}

/* X = sum_{j<k} A^j M B^-j (B orthogonal: B^-1 = B^T), then its polar
 * factor: an orthogonal X with A X = X B. ws: 6 n^2 doubles. */
static int intertwiner(int n, int k, const double *A, const double *B, unsigned long long *st, double *X, double *ws)
{
    size_t nn = (size_t)n * n;
    double *T = ws, *V = ws + nn, *Bt = ws + 2 * nn;
    for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) Bt[c * n + r] = B[r * n + c];
    for (size_t e = 0; e < nn; ++e) T[e] = gauss(st);
    memset(X, 0, sizeof(double) * nn);
    for (int j = 0; j < k; ++j) {
        for (size_t e = 0; e < nn; ++e) X[e] += T[e];
        mat_mul(n, A, T, V);
        mat_mul(n, V, Bt, T);
    }
    int rc = polar(n, X, ws + 3 * nn);
    if (rc) return rc;
    /* A X = X B within BASIS_TOL */
    mat_mul(n, A, X, T);
    mat_mul(n, X, B, V);
    for (size_t e = 0; e < nn; ++e)
        if (!(fabs(T[e] - V[e]) <= BASIS_TOL)) return KIN_ENOTCONVERGED;
    return KIN_OK;
}

/* Make q (the first equation e0 of its cycle, of length l) exactly
 * symmetric and exactly invariant under the cycle's stabiliser <P^l>: the
 * entries (a, b) -> (pi(a), pi(b)), pi = p^l, and (b, a) of an orbit all get
 * the orbit's mean. */
static void stabilise(int m, int k, const int *perm, const int *pe, int e0, double *q)
{
    int l = 1, pi[HOM_MAX_M];
    for (int f = pe[e0]; f != e0; f = pe[f]) ++l;
    for (int i = 0; i < m; ++i) {
        int c = i;
        for (int j = 0; j < l; ++j) c = perm[c];
        pi[i] = c;
    }
    unsigned char seen[HOM_MAX_M * HOM_MAX_M] = {0};
    int orbit[2 * HOM_MAX_M * HOM_MAX_M];
    for (int c = 0; c < m; ++c)
        for (int r = 0; r < m; ++r) {
            if (seen[c * m + r]) continue;
            int n = 0;
            double sum = 0.0;
            for (int i = 0, a = r, b = c; i < k; ++i, a = pi[a], b = pi[b]) {
                if (!seen[b * m + a]) seen[b * m + a] = 1, orbit[n++] = b * m + a, sum += q[b * m + a];
                if (!seen[a * m + b]) seen[a * m + b] = 1, orbit[n++] = a * m + b, sum += q[a * m + b];
            }
            double v = sum / n;
            for (int i = 0; i < n; ++i) q[orbit[i]] = v;
        }
}

/* the plan for <h> (qualifying, order k, permutation perm) */
static int build(hom_equi *E, int m, int s, const double *Qo, const double *h, int k, const int *perm,
                 unsigned long long *st, double *big)
{
    size_t mm = (size_t)m * m, ss = (size_t)s * s;
    int pe[HOM_MAX_M], pinv[HOM_MAX_M];
    for (int i = 0; i < m; ++i) pinv[perm[i]] = i;
    for (int e = 0; e < s; ++e) pe[e] = perm[e + 1] - 1; /* the equations' permutation */
    double *P = big, *Ph = P + mm, *Sh = Ph + ss, *W = Sh + ss, *T = W + ss, *C = T + mm, *Bi = C + mm;
    double *ws = Bi + (size_t)s * mm; /* 6 max(m, s)^2 */
    perm_matrix(m, perm, P);
    perm_matrix(s, pe, Ph);
    int rc = intertwiner(m, k, h, P, st, E->U, ws);
    if (rc) return rc;
    /* S_h in the orthonormal basis: (S)_ei = <h^T Q_e h, Q_i> */
    for (int e = 0; e < s; ++e) {
        congruence(m, h, Qo + e * mm, C, T);
        for (int i = 0; i < s; ++i) Sh[i * s + e] = dot(mm, C, Qo + i * mm);
    }
    /* W S = Phat W: the intertwiner from Phat to S, transposed:
     * S^T W^T = W^T Phat^T, i.e. W^T = X with S^T X = X Phat^T */
    double *St = T, *Pht = C;
    for (int c = 0; c < s; ++c)
        for (int r = 0; r < s; ++r) St[c * s + r] = Sh[r * s + c], Pht[c * s + r] = Ph[r * s + c];
    double *X = Bi; /* scratch until Bi is filled */
    if ((rc = intertwiner(s, k, St, Pht, st, X, ws))) return rc;
    for (int c = 0; c < s; ++c)
        for (int r = 0; r < s; ++r) W[c * s + r] = X[r * s + c];
    /* B_i = U^T Q_i U, then Qt_e = sum_i W_ei B_i for one equation per
     * cycle and its exact permutations for the others */
    for (int i = 0; i < s; ++i) congruence(m, E->U, Qo + i * mm, Bi + i * mm, T);
    unsigned char done[HOM_MAX_M] = {0};
    double dev = 0.0;
    for (int e0 = 0; e0 < s; ++e0) {
        if (done[e0]) continue;
        double *q = E->Qt + e0 * mm;
        memset(q, 0, sizeof(double) * mm);
        for (int i = 0; i < s; ++i)
            for (size_t x = 0; x < mm; ++x) q[x] += W[i * s + e0] * Bi[i * mm + x];
        stabilise(m, k, perm, pe, e0, q);
        done[e0] = 1;
        /* coordinate j = e + 1 goes to p(j): Qt_{p(j)}[a][b] = Qt_j[pinv a][pinv b] */
        for (int e = e0, f = pe[e0]; f != e0; e = f, f = pe[f]) {
            const double *src = E->Qt + e * mm;
            double *dst = E->Qt + f * mm;
            for (int c = 0; c < m; ++c)
                for (int r = 0; r < m; ++r) dst[c * m + r] = src[pinv[c] * m + pinv[r]];
            done[f] = 1;
            for (size_t x = 0; x < mm; ++x) { /* against the computed one */
                double v = 0.0;
                for (int i = 0; i < s; ++i) v += W[i * s + f] * Bi[i * mm + x];
                dev = fmax(dev, fabs(v - dst[x]));
            }
        }
    }
    if (!(dev <= BASIS_TOL)) return KIN_ENOTCONVERGED;
    memcpy(E->perm, perm, sizeof(int) * (size_t)m);
    E->k = k;
    return KIN_OK;
}

int kin__equi_plan(hom_equi *E, int m, int s, const double *Qr, const sym_group *G, unsigned long long seed)
{
    memset(E, 0, sizeof *E);
    size_t mm = (size_t)m * m;
    int n = m > s ? m : s;
    double *Qo = malloc(sizeof(double) * mm * (size_t)s);
    double *big = malloc(sizeof(double) * (4 * mm + 3 * (size_t)s * s + (size_t)s * mm + 6 * (size_t)n * n));
    E->Qt = malloc(sizeof(double) * mm * (size_t)s);
    if (!Qo || !big || !E->Qt) {
        free(Qo), free(big), kin__equi_free(E);
        return KIN_ENOMEM;
    }
    /* the Q_j orthonormal (modified Gram-Schmidt, twice); Qr's rows are
     * the symmetric matrices' columns too */
    memcpy(Qo, Qr, sizeof(double) * mm * (size_t)s);
    int ok = 1;
    for (int j = 0; j < s && ok; ++j)
        for (int pass = 0; pass < 2; ++pass) {
            double *q = Qo + j * mm;
            for (int i = 0; i < j; ++i) {
                double c = dot(mm, q, Qo + i * mm);
                for (size_t x = 0; x < mm; ++x) q[x] -= c * Qo[i * mm + x];
            }
            double nq = sqrt(dot(mm, q, q));
            if (!(nq > 1e-8)) ok = 0; /* dependent: the group check refuses that before */
            else
                for (size_t x = 0; x < mm; ++x) q[x] /= nq;
        }
    int rc = KIN_OK, best = -1, bestk = 0, bestsign = 1, perm[HOM_MAX_M], bestperm[HOM_MAX_M];
    double h[HOM_MAX_M * HOM_MAX_M];
    for (int g = 0; g < G->n && ok; ++g)
        for (int sg = 1; sg >= -1; sg -= 2) {
            for (size_t x = 0; x < mm; ++x) h[x] = sg * G->R[g * mm + x];
            int k = 0;
            if (qualifies(m, s, h, Qo, &k, perm, big) && k > bestk) {
                best = g, bestk = k, bestsign = sg;
                memcpy(bestperm, perm, sizeof(int) * (size_t)m);
            }
        }
    if (best >= 0) {
        for (size_t x = 0; x < mm; ++x) h[x] = bestsign * G->R[best * mm + x];
        unsigned long long st = seed * 0xD1B54A32D192ED03ull + 0x8BB84B93962EACC9ull;
        rc = build(E, m, s, Qo, h, bestk, bestperm, &st, big);
        if (rc == KIN_ENOTCONVERGED) rc = KIN_OK, E->k = 0; /* numerically unfit: the monodromy instead */
    }
    free(Qo), free(big);
    if (rc || E->k == 0) {
        free(E->Qt);
        E->Qt = NULL;
        E->k = 0;
    }
    return rc;
}

void kin__equi_free(hom_equi *E)
{
    free(E->Qt);
    memset(E, 0, sizeof *E);
}

long kin__orbits_count(int m, int k, const int *perm)
{
    long total = 0;
    int pj[HOM_MAX_M];
    for (int i = 0; i < m; ++i) pj[i] = i;
    for (int j = 0; j < k; ++j) { /* Burnside: the mean number of patterns fixed by perm^j */
        unsigned char seen[HOM_MAX_M] = {0};
        int cycles = 0;
        for (int i = 1; i < m; ++i) {
            if (seen[i]) continue;
            cycles++;
            for (int c = i; !seen[c]; c = pj[c]) seen[c] = 1;
        }
        total += 1L << cycles;
        for (int i = 0; i < m; ++i) pj[i] = perm[pj[i]];
    }
    return total / k;
}

int kin__orbits_init(hom_orbits *O, int m, const int *perm)
{
    memset(O, 0, sizeof *O);
    int s = m - 1, N = 1 << s;
    O->npaths = N, O->m = m;
    memcpy(O->perm, perm, sizeof(int) * (size_t)m);
    O->next = malloc(sizeof(int) * (size_t)N);
    O->rep = malloc(sizeof(int) * (size_t)N);
    O->reps = malloc(sizeof(int) * (size_t)N);
    O->list = malloc(sizeof(int) * (size_t)N);
    O->mark = calloc((size_t)N, 1);
    if (!O->next || !O->rep || !O->reps || !O->list || !O->mark) {
        kin__orbits_free(O);
        return KIN_ENOMEM;
    }
    /* start root b: x_j = -x_0 where bit j - 1 is set; (P x)_j = x_{p(j)} */
    for (int b = 0; b < N; ++b) {
        int c = 0;
        for (int j = 1; j <= s; ++j) c |= ((b >> (perm[j] - 1)) & 1) << (j - 1);
        O->next[b] = c;
        O->rep[b] = -1;
    }
    for (int b = 0; b < N; ++b) {
        if (O->rep[b] >= 0) continue;
        O->reps[O->nreps++] = b;
        for (int c = b; O->rep[c] < 0; c = O->next[c]) O->rep[c] = b;
    }
    return KIN_OK;
}

void kin__orbits_free(hom_orbits *O)
{
    free(O->next), free(O->rep), free(O->reps), free(O->list), free(O->mark), free(O->slot);
    memset(O, 0, sizeof *O);
}
