/* Second-order compatibility matrices (paper 3.3, eq. 12-18), with the bar
 * length factor that eq. 12 carries.
 *
 * Derivation. For a bar of length L between A and B, eq. 12 is exact:
 *     e + e^2/(2L) = c.(dA - dB) + |dA - dB|^2/(2L).
 * Put d = U_m beta delta + d2 delta^2 + O(delta^3) and ask e = 0 to second
 * order. The first-order term vanishes (U_m beta is a mechanism); the
 * delta^2 terms give C d2 = -q with q_i = beta^T D_i^T D_i beta / (2 L_i),
 * D_i = (rows of U_m at A) - (rows at B). C d2 = -q has a solution iff q is
 * orthogonal to every self-stress: W_s^T q = 0, i.e.
 *     sum_i t_ij / L_i  beta^T D_i^T D_i beta = 0,   j = 1..s.
 * The printed eq. 14/17 omit the 1/L_i (harmless for the three-bar linkage,
 * whose bars all have L = 1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"

/* A matrix whose part outside the span of the previous ones is below this
 * fraction of the largest Q_j is a combination of them (two Gram-Schmidt
 * passes). Measured against the largest, not against Q_j's own norm: every
 * Q_j comes from a unit self-stress, so their rounding is that of the
 * largest, and a Q_j that is zero but for rounding (a self-stress whose
 * bars do not stretch at second order) is noise, not an equation. */
static const double Q_DEPENDENT_TOL = 1e-10;
/* the projected self-stresses' singular values are 1 (kinematic) or 0
 * (trivial) but for rounding: the midpoint decides */
static const double KINEMATIC_SV_CUT = 0.5;

/* the analysis the second order is built from: its counts, the internal
 * mechanisms U (nf x m, ld nf) and the self-stresses W_s(i, j) =
 * W[i * wi + j * wj] (the SVD's rows of V^T, or the sparse analysis's
 * columns) */
typedef struct second_basis {
    const kin_analysis *an;
    const double *U, *W;
    size_t wi, wj;
} second_basis;

/* The self-stresses the second order uses, into W (nb x *sk, ld nb): with
 * no fixed bars, the analysis' W_s itself; with fixed bars, an orthonormal
 * basis of the self-stresses with no force in them (W_s with those rows
 * zeroed, then its left singular vectors of value 1). The self-stress
 * space is the orthogonal sum of the fixed bars' unit vectors and these,
 * so the second-order equations lose nothing: a fixed bar's own equation
 * is 0 = 0 at every order. A status; W is allocated here (*W_out, the
 * caller frees it). */
static int kinematic_self_stresses(const kin_assembly *a, const second_basis *B, double **W_out, int *sk)
{
    int nb = a->nb, s = B->an->s, info = 0, lwork = -1;
    *W_out = NULL;
    *sk = 0;
    size_t bytes;
    double *W = kin__mul_size3((size_t)nb, (size_t)s, sizeof(double), &bytes) ? malloc(bytes) : NULL;
    if (!W) return KIN_ENOMEM;
    for (int j = 0; j < s; ++j)
        for (int i = 0; i < nb; ++i)
            W[i + (size_t)j * nb] = kin__bar_fixed(a, i) ? 0.0 : B->W[(size_t)i * B->wi + (size_t)j * B->wj];
    *W_out = W;
    if (B->an->s_trivial == 0) {
        *sk = s;
        return KIN_OK;
    }
    int mn = nb < s ? nb : s;
    double q = 0.0, dummy = 0.0;
    double *sv = malloc(sizeof(double) * (size_t)mn), *U = malloc(bytes), *work = NULL;
    dgesvd_("S", "N", &nb, &s, W, &nb, sv, U, &nb, &dummy, &s, &q, &lwork, &info, 1, 1);
    lwork = info == 0 && q < 1e9 ? (int)q + 1 : 0;
    if (!sv || !U || lwork == 0 || !(work = malloc(sizeof(double) * (size_t)lwork))) {
        free(sv), free(U), free(work);
        return info ? KIN_ELAPACK_ARG : KIN_ENOMEM;
    }
    dgesvd_("S", "N", &nb, &s, W, &nb, sv, U, &nb, &dummy, &s, work, &lwork, &info, 1, 1);
    int kept = 0;
    while (info == 0 && kept < mn && sv[kept] > KINEMATIC_SV_CUT) ++kept;
    memcpy(W, U, sizeof(double) * (size_t)nb * (size_t)kept);
    free(sv), free(U), free(work);
    if (info < 0) return KIN_ELAPACK_ARG;
    if (info > 0) return KIN_ELAPACK_CONV;
    *sk = kept;
    return KIN_OK;
}

/* Q_j (m x m, j < sk) from the self-stresses W (nb x sk) */
static void build_q(const kin_assembly *a, const second_basis *B, int weighting, const double *W, int sk,
                    double *Q)
{
    int m = B->an->m_internal, nf = a->nf, nb = a->nb, d = a->dim;
    const double *U = B->U;
    for (int i = 0; i < nb; ++i) {
        if (kin__bar_fixed(a, i)) continue; /* D_i = 0 */
        int ja = a->bars[2 * i], jb = a->bars[2 * i + 1];
        double w = weighting == KIN_Q_EXACT ? 1.0 / a->L0[i] : 1.0;
        /* G = D_i^T D_i (m x m), added to each Q_j with weight t_ij * w */
        for (int p = 0; p < m; ++p)
            for (int q = 0; q <= p; ++q) {
                double g = 0.0;
                for (int c = 0; c < d; ++c) {
                    int ra = a->free_index[ja * d + c], rb = a->free_index[jb * d + c];
                    double dp = (ra >= 0 ? U[ra + (size_t)p * nf] : 0.0) - (rb >= 0 ? U[rb + (size_t)p * nf] : 0.0);
                    double dq = (ra >= 0 ? U[ra + (size_t)q * nf] : 0.0) - (rb >= 0 ? U[rb + (size_t)q * nf] : 0.0);
                    g += dp * dq;
                }
                if (g == 0.0) continue;
                for (int j = 0; j < sk; ++j) {
                    double v = W[i + (size_t)j * nb] * w * g; /* t_ij w g */
                    Q[(size_t)j * m * m + p + (size_t)q * m] += v;
                    if (p != q) Q[(size_t)j * m * m + q + (size_t)p * m] += v;
                }
            }
    }
}

int kin_second_order(const kin_assembly *a, int weighting, int normalise, double *Q, int nq,
                     int *s_out)
{
    if (s_out) *s_out = 0;
    if (!a || !Q || !s_out) return KIN_ENULL;
    /* the internal mechanisms U (ld nf) and the self-stresses W_s(i, j) =
     * W[i * wi + j * wj]: of the SVD analysis (W_s = the last rows of V^T),
     * or of the sparse mode's analysis, which has both bases too */
    const kin_factor *f = kin__cur(a);
    const kin_sparse_an *sa = f->valid ? NULL : kin__sparse_an_current(a);
    if (!f->valid && !sa) return kin__fail((kin_assembly *)a, KIN_ESTATE, "no current analysis (kin_analyse)");
    second_basis B = {.an = sa ? &sa->an : &f->an, .U = sa ? sa->Uint : f->Uint};
    B.W = sa ? sa->Ws : f->VT + B.an->rank;
    B.wi = sa ? 1 : (size_t)a->nb, B.wj = sa ? (size_t)a->nb : 1;
    if (weighting != KIN_Q_EXACT && weighting != KIN_Q_PAPER_EQ17) return KIN_EINVAL;
    int m = B.an->m_internal, s = B.an->s - B.an->s_trivial;
    if (m < 2 || s < 1)
        return kin__fail((kin_assembly *)a, KIN_EINVAL,
                         "not a bifurcation: m_internal = %d, s = %d of which %d of bars between fixed joints", m,
                         B.an->s, B.an->s_trivial);
    /* m^2 s can pass INT_MAX for a large enough structure: counted in size_t */
    size_t need;
    if (nq < 0 || !kin__mul_size3((size_t)m * (size_t)m, (size_t)s, sizeof(double), &need) ||
        need / sizeof(double) > (size_t)nq)
        return KIN_ERANGE;
    double *W = NULL;
    int rc = kinematic_self_stresses(a, &B, &W, &s);
    if (rc) {
        free(W);
        return kin__fail((kin_assembly *)a, rc, "second order: the self-stresses without the fixed bars' (%s)",
                         rc == KIN_ENOMEM ? "memory" : "dgesvd");
    }
    memset(Q, 0, sizeof(double) * (size_t)m * (size_t)m * (size_t)s);
    build_q(a, &B, weighting, W, s, Q);
    free(W);
    *s_out = s;
    if (!normalise) return KIN_OK;
    /* eq. 18: orthonormalise vec(Q_j) */
    int mm = m * m, kept = 0; /* m^2 fits: m <= 1020 (sparse analysis) or nfree^2 <= INT_MAX (dense) */
    double qmax = 0.0;
    for (int j = 0; j < s; ++j) qmax = fmax(qmax, kin__norm(mm, Q + (size_t)j * mm));
    for (int j = 0; j < s; ++j) {
        double *v = Q + (size_t)j * mm, before = kin__norm(mm, v);
        if (!(kin__gs_column(mm, Q, mm, kept, v) * before > Q_DEPENDENT_TOL * qmax)) continue;
        memmove(Q + (size_t)kept * mm, v, sizeof(double) * (size_t)mm);
        ++kept;
    }
    *s_out = kept;
    return KIN_OK;
}
