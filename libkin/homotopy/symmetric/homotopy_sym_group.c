/* The symmetry group of kin_quadrics_homotopy_sym: the checks on the
 * caller's matrices, the equation-space action S_g, the Reynolds
 * projection onto the equivariant family, and the root sets (points of
 * P^s up to scale, stored orbit by orbit). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"
#include "model/lapack.h"

/* |R^T R - I| (largest entry) and the equivariance residual
 * |R^T Q_j R - sum_i S_ji Q_i|_F (Q_j of unit Frobenius norm) must be at
 * most these: rounding in R computed from a mechanism basis and in Q from
 * kin_second_order is far below, and a wrong or mismatched symmetry far
 * above. */
static const double ORTH_TOL = 1e-8, EQUI_TOL = 1e-7;
/* the Gram matrix of the Q_j (unit norm) must have a pivot above this:
 * the equations are linearly independent, so S_g is unique */
static const double GRAM_TOL = 1e-10;
/* two normalised points are the same if they differ by at most SAME_TOL
 * (relative, largest entry); keys are bucketed at KEY_STEP, far above */
static const double SAME_TOL = 1e-7, KEY_STEP = 1e-4;


/* C = A^T B A for m x m A (column-major), symmetric B */
static void congruence(int m, const double *A, const double *B, double *T, double *C)
{
    for (int c = 0; c < m; ++c) /* T = B A */
        for (int r = 0; r < m; ++r) {
            double v = 0.0;
            for (int k = 0; k < m; ++k) v += B[k * m + r] * A[c * m + k];
            T[c * m + r] = v;
        }
    for (int c = 0; c < m; ++c)
        for (int r = 0; r < m; ++r) {
            double v = 0.0;
            for (int k = 0; k < m; ++k) v += A[r * m + k] * T[c * m + k];
            C[c * m + r] = v;
        }
}

/* are a and b equal up to sign (entries within tol)? */
static int same_up_to_sign(int n, const double *a, const double *b, double tol)
{
    int plus = 1, minus = 1;
    for (int i = 0; i < n; ++i) {
        if (fabs(a[i] - b[i]) > tol) plus = 0;
        if (fabs(a[i] + b[i]) > tol) minus = 0;
    }
    return plus || minus;
}

int kin__sym_group_init(sym_group *G, int m, int s, const double *Qr, int ngroup, const double *R, char *err,
                        size_t errlen)
{
    memset(G, 0, sizeof *G);
    size_t mm = (size_t)m * m;
    G->m = m, G->s = s;
    G->R = malloc(sizeof(double) * mm * (size_t)(ngroup + 1));
    G->S = malloc(sizeof(double) * (size_t)s * s * (ngroup + 1));
    G->Sinv = malloc(sizeof(double) * (size_t)s * s * (ngroup + 1));
    double *T = malloc(sizeof(double) * mm * 2), *gram = malloc(sizeof(double) * (size_t)s * s);
    double *rhs = malloc(sizeof(double) * (size_t)s * s), *RQR = malloc(sizeof(double) * mm * (size_t)s);
    int *ipiv = malloc(sizeof(int) * (size_t)(s > m ? s : m));
    int rc = KIN_OK;
    if (!G->R || !G->S || !G->Sinv || !T || !gram || !rhs || !RQR || !ipiv) {
        rc = KIN_ENOMEM;
        goto done;
    }
    for (size_t i = 0; i < mm * (size_t)ngroup; ++i)
        if (!isfinite(R[i])) {
            rc = kin__failbuf(err, errlen, KIN_EINVAL, "R has a NaN or infinite entry");
            goto done;
        }
    /* the Gram matrix of the equations, factored once */
    for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j) gram[j * s + i] = kin__dot((int)mm, Qr + (size_t)i * mm, Qr + (size_t)j * mm);
    int n = s, info = 0;
    dgetrf_(&n, &n, gram, &n, ipiv, &info);
    for (int i = 0; i < s && !info; ++i)
        if (!(fabs(gram[i * s + i]) > GRAM_TOL)) info = 1;
    if (info) {
        rc = kin__failbuf(err, errlen, KIN_EINVAL, "the quadrics Q_j are linearly dependent");
        goto done;
    }
    int *gpiv = malloc(sizeof(int) * (size_t)s);
    if (!gpiv) {
        rc = KIN_ENOMEM;
        goto done;
    }
    memcpy(gpiv, ipiv, sizeof(int) * (size_t)s);
    /* element 0 is the identity (the caller's list may or may not have it) */
    memset(G->R, 0, sizeof(double) * mm);
    memset(G->S, 0, sizeof(double) * (size_t)s * s);
    memset(G->Sinv, 0, sizeof(double) * (size_t)s * s);
    for (int i = 0; i < m; ++i) G->R[i * m + i] = 1.0;
    for (int i = 0; i < s; ++i) G->S[i * s + i] = G->Sinv[i * s + i] = 1.0;
    G->n = 1;
    for (int g = 0; g < ngroup && !rc; ++g) {
        const double *Rg = R + (size_t)g * mm;
        double orth = 0.0;
        for (int i = 0; i < m; ++i)
            for (int j = 0; j < m; ++j)
                orth = fmax(orth, fabs(kin__dot(m, Rg + (size_t)i * m, Rg + (size_t)j * m) - (i == j)));
        if (!(orth <= ORTH_TOL)) {
            rc = kin__failbuf(err, errlen, KIN_EINVAL, "R[%d] is not orthogonal (|R^T R - I| = %.3g > %.1g)", g, orth,
                      ORTH_TOL);
            break;
        }
        int dup = 0;
        for (int h = 0; h < G->n && !dup; ++h) dup = same_up_to_sign((int)mm, Rg, G->R + (size_t)h * mm, ORTH_TOL);
        if (dup) continue;
        int k = G->n;
        /* S_g by least squares: vec(R^T Q_j R) = sum_i S_ji vec(Q_i) */
        for (int j = 0; j < s; ++j) congruence(m, Rg, Qr + (size_t)j * mm, T, RQR + (size_t)j * mm);
        for (int j = 0; j < s; ++j)
            for (int i = 0; i < s; ++i) rhs[j * s + i] = kin__dot((int)mm, Qr + (size_t)i * mm, RQR + (size_t)j * mm);
        dgetrs_("N", &n, &n, gram, &n, gpiv, rhs, &n, &info, 1); /* rhs column j: row j of S */
        double *Sg = G->S + (size_t)k * s * s, worst = 0.0;
        for (int j = 0; j < s; ++j)
            for (int i = 0; i < s; ++i) Sg[i * s + j] = rhs[j * s + i];
        for (int j = 0; j < s; ++j) {
            double r2 = 0.0;
            for (size_t e = 0; e < mm; ++e) {
                double v = RQR[(size_t)j * mm + e];
                for (int i = 0; i < s; ++i) v -= Sg[i * s + j] * Qr[(size_t)i * mm + e];
                r2 += v * v;
            }
            worst = fmax(worst, sqrt(r2));
        }
        if (!(worst <= EQUI_TOL)) {
            rc = kin__failbuf(err, errlen, KIN_EINVAL,
                      "the quadrics are not equivariant under R[%d] (residual %.3g > %.1g)", g, worst, EQUI_TOL);
            break;
        }
        double *Si = G->Sinv + (size_t)k * s * s;
        memcpy(T, Sg, sizeof(double) * (size_t)s * s);
        for (int i = 0; i < s * s; ++i) Si[i] = i % (s + 1) == 0;
        dgetrf_(&n, &n, T, &n, ipiv, &info);
        if (!info) dgetrs_("N", &n, &n, T, &n, ipiv, Si, &n, &info, 1);
        if (info) {
            rc = kin__failbuf(err, errlen, KIN_EINVAL, "S for R[%d] is singular", g);
            break;
        }
        memcpy(G->R + (size_t)k * mm, Rg, sizeof(double) * mm);
        G->n++;
    }
    free(gpiv);
    /* a group up to sign: every product of two elements is one of them */
    for (int a = 0; a < G->n && !rc; ++a)
        for (int b = 0; b < G->n && !rc; ++b) {
            const double *A = G->R + (size_t)a * mm, *B = G->R + (size_t)b * mm;
            for (int c = 0; c < m; ++c)
                for (int r = 0; r < m; ++r) {
                    double v = 0.0;
                    for (int q = 0; q < m; ++q) v += A[q * m + r] * B[c * m + q];
                    T[c * m + r] = v;
                }
            int found = 0;
            for (int h = 0; h < G->n && !found; ++h)
                found = same_up_to_sign((int)mm, T, G->R + (size_t)h * mm, 1e3 * ORTH_TOL);
            if (!found) rc = kin__failbuf(err, errlen, KIN_EINVAL, "R is not a group: R[%d] R[%d] is not in it", a, b);
        }
done:
    free(T), free(gram), free(rhs), free(RQR), free(ipiv);
    if (rc) kin__sym_group_free(G);
    return rc;
}

void kin__sym_group_free(sym_group *G)
{
    free(G->R), free(G->S), free(G->Sinv);
    memset(G, 0, sizeof *G);
}

void kin__sym_reynolds(const sym_group *G, const double *Zr, const double *Zi, double *Pr, double *Pi)
{
    int m = G->m, s = G->s, sm = s * m;
    size_t mm = (size_t)m * m, n = mm * s;
    memset(Pr, 0, sizeof(double) * n);
    memset(Pi, 0, sizeof(double) * n);
    double T[HOM_MAX_M * HOM_MAX_M], B[HOM_MAX_M * HOM_MAX_M], C[HOM_MAX_M * HOM_MAX_M];
    for (int g = 0; g < G->n; ++g) {
        const double *Rg = G->R + (size_t)g * mm, *Si = G->Sinv + (size_t)g * s * s;
        for (int part = 0; part < 2; ++part) {
            const double *Z = part ? Zi : Zr;
            double *P = part ? Pi : Pr;
            for (int i = 0; i < s; ++i) {
                for (int c = 0; c < m; ++c) /* Z_i (stacked) to column-major B */
                    for (int r = 0; r < m; ++r) B[c * m + r] = Z[(size_t)c * sm + r * s + i];
                congruence(m, Rg, B, T, C);
                for (int j = 0; j < s; ++j) {
                    double f = Si[i * s + j] / G->n;
                    if (f == 0.0) continue;
                    for (int c = 0; c < m; ++c)
                        for (int r = 0; r < m; ++r) P[(size_t)c * sm + r * s + j] += f * C[c * m + r];
                }
            }
        }
    }
}

void kin__sym_apply(const sym_group *G, int g, const double *xr, const double *xi, double *yr, double *yi)
{
    int m = G->m;
    const double *Rg = G->R + (size_t)g * m * m;
    for (int r = 0; r < m; ++r) yr[r] = yi[r] = 0.0;
    for (int c = 0; c < m; ++c)
        for (int r = 0; r < m; ++r) yr[r] += Rg[c * m + r] * xr[c], yi[r] += Rg[c * m + r] * xi[c];
}

/* ---- root sets ---- */

int kin__sym_set_init(sym_set *S, int m, int cap, const double *wr, const double *wi, const double *key)
{
    memset(S, 0, sizeof *S);
    S->m = m, S->cap = cap, S->wr = wr, S->wi = wi, S->key = key;
    S->hsize = 1;
    while (S->hsize < 2 * cap) S->hsize *= 2;
    S->xr = malloc(sizeof(double) * (size_t)m * cap);
    S->xi = malloc(sizeof(double) * (size_t)m * cap);
    S->rep = malloc(sizeof(int) * (size_t)cap);
    S->elem = malloc(sizeof(int) * (size_t)cap);
    S->next = malloc(sizeof(int) * (size_t)cap);
    S->bucket = malloc(sizeof(long long) * (size_t)cap);
    S->head = malloc(sizeof(int) * (size_t)S->hsize);
    if (!S->xr || !S->xi || !S->rep || !S->elem || !S->next || !S->bucket || !S->head) {
        kin__sym_set_free(S);
        return KIN_ENOMEM;
    }
    for (int i = 0; i < S->hsize; ++i) S->head[i] = -1;
    return KIN_OK;
}

void kin__sym_set_free(sym_set *S)
{
    free(S->xr), free(S->xi), free(S->rep), free(S->elem), free(S->next), free(S->bucket), free(S->head);
    memset(S, 0, sizeof *S);
}

/* x / (w.x) into (yr, yi) and its key's bucket; 0 if w.x is tiny */
static int normalise(const sym_set *S, const double *xr, const double *xi, double *yr, double *yi, long long *b)
{
    int m = S->m;
    double sr = 0.0, si = 0.0, nx = 0.0;
    for (int c = 0; c < m; ++c) {
        sr += S->wr[c] * xr[c] - S->wi[c] * xi[c], si += S->wr[c] * xi[c] + S->wi[c] * xr[c];
        nx += xr[c] * xr[c] + xi[c] * xi[c];
    }
    double d = sr * sr + si * si;
    if (!(d > 1e-12 * nx)) return 0;
    double key = 0.0;
    for (int c = 0; c < m; ++c) {
        yr[c] = (xr[c] * sr + xi[c] * si) / d, yi[c] = (xi[c] * sr - xr[c] * si) / d;
        key += S->key[c] * (yr[c] + yi[c]);
    }
    if (!(fabs(key) < 1e12)) return 0;
    *b = (long long)floor(key / KEY_STEP);
    return 1;
}

static int slot(const sym_set *S, long long b)
{
    unsigned long long h = (unsigned long long)b * 0x9E3779B97F4A7C15ull;
    return (int)(h >> 40) & (S->hsize - 1);
}

static int find_normalised(const sym_set *S, const double *yr, const double *yi, long long b)
{
    int m = S->m;
    double big = 1.0;
    for (int c = 0; c < m; ++c) big = fmax(big, fmax(fabs(yr[c]), fabs(yi[c])));
    for (long long bb = b - 1; bb <= b + 1; ++bb)
        for (int i = S->head[slot(S, bb)]; i >= 0; i = S->next[i]) {
            if (S->bucket[i] != bb) continue;
            const double *pr = S->xr + (size_t)i * m, *pi = S->xi + (size_t)i * m;
            int same = 1;
            for (int c = 0; c < m && same; ++c)
                same = fabs(pr[c] - yr[c]) <= SAME_TOL * big && fabs(pi[c] - yi[c]) <= SAME_TOL * big;
            if (same) return i;
        }
    return -1;
}

int kin__sym_set_find(const sym_set *S, const double *xr, const double *xi)
{
    double yr[HOM_MAX_M], yi[HOM_MAX_M];
    long long b;
    if (!normalise(S, xr, xi, yr, yi, &b)) return -1;
    return find_normalised(S, yr, yi, b);
}

int kin__sym_set_add_orbit(sym_set *S, const sym_group *G, const double *xr, const double *xi)
{
    int m = S->m, first = S->n;
    for (int g = 0; g < G->n; ++g) {
        double ur[HOM_MAX_M], ui[HOM_MAX_M], yr[HOM_MAX_M], yi[HOM_MAX_M];
        long long b;
        kin__sym_apply(G, g, xr, xi, ur, ui);
        if (!normalise(S, ur, ui, yr, yi, &b)) {
            if (g == 0) return -1;
            continue;
        }
        if (find_normalised(S, yr, yi, b) >= 0) continue; /* a fixed point of g (up to scale) */
        if (S->n == S->cap) { /* more roots than the count: undo */
            for (int i = S->n - 1; i >= first; --i) S->head[slot(S, S->bucket[i])] = S->next[i];
            S->n = first;
            return -1;
        }
        int i = S->n++;
        memcpy(S->xr + (size_t)i * m, yr, sizeof(double) * (size_t)m);
        memcpy(S->xi + (size_t)i * m, yi, sizeof(double) * (size_t)m);
        S->rep[i] = first, S->elem[i] = g, S->bucket[i] = b;
        int h = slot(S, b);
        S->next[i] = S->head[h], S->head[h] = i;
    }
    return first;
}
