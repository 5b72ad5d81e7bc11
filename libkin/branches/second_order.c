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
#include <string.h>

#include "model/internal.h"

/* A matrix whose norm drops below this fraction after orthogonalisation is
 * a combination of the previous ones (two Gram-Schmidt passes). */
static const double Q_DEPENDENT_TOL = 1e-10;

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
    const kin_analysis *an = sa ? &sa->an : &f->an;
    const double *U = sa ? sa->Uint : f->Uint, *W = sa ? sa->Ws : f->VT + an->rank;
    size_t wi = sa ? 1 : (size_t)a->nb, wj = sa ? (size_t)a->nb : 1;
    if (weighting != KIN_Q_EXACT && weighting != KIN_Q_PAPER_EQ17) return KIN_EINVAL;
    int m = an->m_internal, s = an->s, nf = a->nf, nb = a->nb, d = a->dim;
    if (m < 2 || s < 1)
        return kin__fail((kin_assembly *)a, KIN_EINVAL,
                         "not a bifurcation: %d internal mechanisms and %d self-stresses (the second order needs "
                         "at least 2 and 1)", m, s);
    /* m^2 s can pass INT_MAX for a large enough structure: counted in size_t */
    size_t need;
    if (nq < 0 || !kin__mul_size3((size_t)m * (size_t)m, (size_t)s, sizeof(double), &need) ||
        need / sizeof(double) > (size_t)nq)
        return KIN_ERANGE;
    memset(Q, 0, need);
    for (int i = 0; i < nb; ++i) {
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
                for (int j = 0; j < s; ++j) {
                    double t = W[(size_t)i * wi + (size_t)j * wj]; /* W_s(i, j) */
                    double v = t * w * g;
                    Q[(size_t)j * m * m + p + (size_t)q * m] += v;
                    if (p != q) Q[(size_t)j * m * m + q + (size_t)p * m] += v;
                }
            }
    }
    *s_out = s;
    if (!normalise) return KIN_OK;
    /* eq. 18: orthonormalise vec(Q_j) */
    int mm = m * m, kept = 0; /* m^2 fits: m <= 1020 (sparse analysis) or nfree^2 <= INT_MAX (dense) */
    for (int j = 0; j < s; ++j) {
        double *v = Q + (size_t)j * mm;
        if (kin__gs_column(mm, Q, mm, kept, v) < Q_DEPENDENT_TOL) continue;
        memmove(Q + (size_t)kept * mm, v, sizeof(double) * (size_t)mm);
        ++kept;
    }
    *s_out = kept;
    return KIN_OK;
}
