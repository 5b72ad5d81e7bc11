/* First-order analysis without the dense SVD: kin_analyse in the sparse
 * mode (KIN_STEP_SPARSE), for structures whose nf x nb equilibrium matrix H
 * is too big to hold densely (a 10^4-joint mast: 30,000 x 29,999, 7 GB, and
 * dgesdd's workspace several times that). Nothing of size nf x nb is made:
 * H is applied from the bars' direction cosines, and every dense array is
 * nf or nb long times a block of at most MAX_BLOCK columns.
 *
 * The counts come from the same rule as the dense path (a singular value
 * counts when it is > tau = rank_tol * v_max) applied to three computations:
 *
 *  1. v_max bracketed: Golub-Kahan-Lanczos bidiagonalisation of H (products
 *     with H and H^T only, full reorthogonalisation; at most GKL_MAX steps)
 *     gives a lower bound theta and a residual; a CHOLMOD Cholesky
 *     factorization of mu^2 I - H^T H, which exists exactly when mu > v_max,
 *     gives an upper bound, and bisection narrows the bracket to
 *     BRACKET_UNITS rounding units (vmax_bracket). Lanczos alone does not
 *     do: a long periodic structure's top singular values form a dense band
 *     (a 300-bay mast: relative residual 4e-4 after 300 steps). The rank
 *     decision below allows for the bracket's width.
 *
 *  2. The singular subspaces at the small end by subspace iteration with the
 *     shift-invert operator of the augmented matrix
 *         M = [ sigma I   H       ]    (nf + nb square, symmetric pattern,
 *             [ H^T      -sigma I ]     sigma = tau),
 *     factorized once by KLU (COLAMD order, strict partial pivoting: with
 *     sigma ~ 0 on the diagonal every pivot is off it, and a symmetric AMD
 *     order filled in catastrophically). Its inverse maps [x; 0] to
 *     [sigma (sigma^2 I + H H^T)^-1 x; ...] and [0; y] to
 *     [...; -sigma (sigma^2 I + H^T H)^-1 y], so iterating with the top
 *     (bottom) block converges to the left (right) singular vectors of the
 *     smallest singular values, at the rate (sigma^2 + s_i^2) /
 *     (sigma^2 + s_j^2) between kept and dropped ones; H H^T and H^T H are
 *     never formed (the factorization is of M, whose condition is v_max /
 *     sigma, not its square), which is what keeps singular values at
 *     rank_tol = 1e-11 resolvable. The mechanisms are the left side, the
 *     self-stresses the right one.
 *
 *  3. Rayleigh-Ritz with H itself: the block X (orthonormal) of each side
 *     gives the small SVD of H^T X (or H X); its singular values theta_i are
 *     Ritz values of H (each an upper bound of the matching smallest
 *     singular value, by interlacing), its vectors rotate X to Ritz vectors.
 *     m (s) counts the theta_i <= tau on the left (right); v_r is the
 *     smallest theta_i above tau on either side.
 *
 * The decision is checked, not assumed: a count is decided when it held
 * over two iterations, the block holds PAD_MIN Ritz vectors beyond the null
 * space (else it grows, capped at MAX_BLOCK), the residual of v_r's Ritz
 * pair (a singular value of H lies within it) keeps v_r above tau (the
 * bracket's upper end), the largest null Ritz value lies below tau by more
 * than the rounding of the products (ROUNDING_UNITS eps v_max), and the two
 * sides agree (nf - m = nb - s). The iteration stops when, besides, v_r
 * moved by less than VR_STEADY, or at MAX_ITER iterations or the budget
 * (the count decided: answered). A count never decided: KIN_ENOTCONVERGED.
 *
 * The budget: where the dense analysis is affordable, the iteration's work
 * is counted in operations against its predicted cost, and the sparse
 * analysis gives up (*over) where it would cost more, so that kin_analyse
 * takes the dense route (analysis.c). What no iteration can prove
 * is that a singular value the random start missed is not hiding below tau
 * (no inertia count is made): subspace iteration from a random block
 * misses one with probability zero, and the padding's Ritz values (all
 * above tau) are the evidence.
 *
 * The rigid/internal split is the dense path's (kin__split_basis). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cholmod.h>
#include <klu.h>

#include "model/internal.h"
#include "model/lapack.h"

/* Ritz vectors kept beyond the null space on each side: the block starts
 * with PAD more columns than the least the counts allow, and grows (doubles)
 * while fewer than PAD_MIN are left beyond the null space. */
static const int PAD = 8;
static const int PAD_MIN = 4;
/* Largest block of either side: the bases kept and the iteration's arrays
 * are nf (nb) times it. A block grows (doubles) up to it, never past it;
 * more than MAX_BLOCK - PAD_MIN mechanisms or self-stresses: KIN_ELIMIT
 * (at once where nf - nb or nb - nf already says so). */
static const int MAX_BLOCK = 1024;
/* Subspace iterations at most (each one solve per column of the block).
 * A count decided (the gap at tau clear on both sides of it, held over two
 * iterations) whose v_r has not settled (VR_STEADY) by then is answered, v_r
 * as the Ritz value it is (an upper bound of a singular value of H, within
 * its residual): clustered singular values above tau settle slowly and do
 * not make the count doubtful (a 2D chain's band at 0.22 v_max was called
 * "undecided"). Likewise where the work passes the budget. */
static const int MAX_ITER = 60;
/* The iterations the prediction of a block's cost counts (a decision takes
 * two at least; with three, sail:24:40's 1024-column blocks were started
 * and then cost twice the dense analysis) */
static const int PREDICT_ITER = 6;
/* The iteration's operations run at about half the rate of dgesdd's (block
 * solves and thin QR and SVD against blocked BLAS 3; measured on a 26 x 26
 * plate and sail:24:40, one OpenBLAS thread, Haswell and SkylakeX kernels
 * alike): each counts twice against the dense analysis's. */
static const double SPARSE_FLOP_WEIGHT = 2.0;
/* Lanczos steps at most for v_max, and the relative residual bound that
 * stops them. */
static const int GKL_MAX = 40;
static const double GKL_TOL = 1e-12;
/* v_r is steady when it moved by less than this (relative) in an
 * iteration, or by less than ROUNDING_UNITS eps v_max. */
static const double VR_STEADY = 1e-12;
/* The products' rounding, in units of eps v_max: a Ritz value closer to tau
 * than this is undecidable. */
static const double ROUNDING_UNITS = 16.0;
/* The bisection of v_max stops when its bracket is this many rounding
 * units wide (relative). */
static const double BRACKET_UNITS = 16.0;
/* Seed of the random starts (any fixed value: analyses repeat exactly). */
static const unsigned long long START_SEED = 0x5a17ab1eULL;

/* H as bar data: per bar its free rows at each end and its direction
 * cosines; the augmented matrix and its KLU factors */
typedef struct {
    int nf, nb, d;
    int *row;      /* nb * 2 * d: free row of bar k, end e, axis c (or -1) */
    double *cs;    /* nb * d: direction cosines (X_A - X_B) / L */
    int *Ap, *Ai;  /* M in compressed columns */
    double *Ax;
    klu_common common;
    klu_symbolic *sym;
    klu_numeric *num;
} aug_t;

/* y = H x (x: nb, y: nf) */
static void mul_H(const aug_t *g, const double *x, double *y)
{
    int d = g->d;
    memset(y, 0, sizeof(double) * (size_t)g->nf);
    for (int k = 0; k < g->nb; ++k) {
        const int *r = g->row + (size_t)k * 2 * d;
        for (int c = 0; c < d; ++c) {
            double v = g->cs[(size_t)k * d + c] * x[k];
            if (r[c] >= 0) y[r[c]] += v;
            if (r[d + c] >= 0) y[r[d + c]] -= v;
        }
    }
}

/* y = H^T x (x: nf, y: nb) */
static void mul_HT(const aug_t *g, const double *x, double *y)
{
    int d = g->d;
    for (int k = 0; k < g->nb; ++k) {
        const int *r = g->row + (size_t)k * 2 * d;
        double s = 0.0;
        for (int c = 0; c < d; ++c) {
            double v = 0.0;
            if (r[c] >= 0) v += x[r[c]];
            if (r[d + c] >= 0) v -= x[r[d + c]];
            s += g->cs[(size_t)k * d + c] * v;
        }
        y[k] = s;
    }
}

static void aug_free(aug_t *g)
{
    if (g->num) klu_free_numeric(&g->num, &g->common);
    if (g->sym) klu_free_symbolic(&g->sym, &g->common);
    free(g->row);
    free(g->cs);
    free(g->Ap);
    free(g->Ai);
    free(g->Ax);
}

/* bar data of configuration xyz; KIN_OK or KIN_ENOMEM */
static int aug_bars(kin_assembly *a, const double *xyz, aug_t *g)
{
    int d = a->dim;
    g->nf = a->nf;
    g->nb = a->nb;
    g->d = d;
    g->row = malloc(sizeof(int) * (size_t)a->nb * 2 * (size_t)d);
    g->cs = malloc(sizeof(double) * (size_t)a->nb * (size_t)d);
    if (!g->row || !g->cs) return kin__fail(a, KIN_ENOMEM, "sparse analysis: bar data");
    for (int k = 0; k < a->nb; ++k) {
        int ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
        double v[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c < d; ++c) v[c] = xyz[ja * d + c] - xyz[jb * d + c];
        double L = kin__norm(d, v);
        for (int c = 0; c < d; ++c) {
            g->cs[(size_t)k * d + c] = v[c] / L;
            g->row[(size_t)k * 2 * d + c] = a->free_index[ja * d + c];
            g->row[(size_t)k * 2 * d + d + c] = a->free_index[jb * d + c];
        }
    }
    return KIN_OK;
}

/* M = [sigma I, H; H^T, -sigma I] in compressed columns, factorized by KLU */
static int aug_factor(kin_assembly *a, aug_t *g, double sigma)
{
    int nf = g->nf, nb = g->nb, d = g->d, n = nf + nb;
    g->Ap = calloc((size_t)n + 1, sizeof *g->Ap);
    if (!g->Ap) return kin__fail(a, KIN_ENOMEM, "sparse analysis: augmented matrix");
    /* counts: the diagonal, H's entries in the bar columns and (transposed) in the coordinate columns */
    for (int j = 0; j < n; ++j) g->Ap[j + 1] = 1;
    for (int k = 0; k < nb; ++k)
        for (int p = 0; p < 2 * d; ++p) {
            int r = g->row[(size_t)k * 2 * d + p];
            if (r >= 0) {
                g->Ap[nf + k + 1]++;
                g->Ap[r + 1]++;
            }
        }
    for (int j = 0; j < n; ++j) g->Ap[j + 1] += g->Ap[j];
    size_t nnz = (size_t)g->Ap[n];
    g->Ai = malloc(nnz * sizeof *g->Ai);
    g->Ax = malloc(nnz * sizeof *g->Ax);
    int *next = malloc((size_t)n * sizeof *next);
    if (!g->Ai || !g->Ax || !next) {
        free(next);
        return kin__fail(a, KIN_ENOMEM, "sparse analysis: augmented matrix (%zu entries)", nnz);
    }
    memcpy(next, g->Ap, (size_t)n * sizeof *next);
    /* coordinate columns j < nf: sigma at row j, then bar rows nf + k ascending */
    for (int j = 0; j < nf; ++j) {
        g->Ai[next[j]] = j;
        g->Ax[next[j]++] = sigma;
    }
    for (int k = 0; k < nb; ++k)
        for (int p = 0; p < 2 * d; ++p) {
            int r = g->row[(size_t)k * 2 * d + p];
            if (r < 0) continue;
            double v = p < d ? g->cs[(size_t)k * d + p] : -g->cs[(size_t)k * d + p - d];
            g->Ai[next[r]] = nf + k;
            g->Ax[next[r]++] = v;
            g->Ai[next[nf + k]] = r;
            g->Ax[next[nf + k]++] = v;
        }
    for (int k = 0; k < nb; ++k) {
        g->Ai[next[nf + k]] = nf + k;
        g->Ax[next[nf + k]++] = -sigma;
    }
    free(next);
    klu_defaults(&g->common);
    g->common.ordering = 1; /* COLAMD: an order for any row pivoting (sigma ~ 0 on the diagonal: every pivot is off it) */
    g->common.btf = 0;
    g->common.tol = 1.0; /* strict partial pivoting: M's condition is v_max / sigma */
    g->common.halt_if_singular = 1;
    /* KLU takes the row indices in any order; each column holds a row at most
     * once (no bar joins a joint to itself) */
    g->sym = klu_analyze(n, g->Ap, g->Ai, &g->common);
    if (!g->sym)
        return kin__fail(a, KIN_ENOMEM, "sparse analysis: KLU analysis of the augmented matrix failed (status %d)",
                         g->common.status);
    g->num = klu_factor(g->Ap, g->Ai, g->Ax, g->sym, &g->common);
    if (!g->num) {
        if (g->common.status == KLU_SINGULAR)
            return kin__fail(a, KIN_ENOTCONVERGED, "sparse analysis: the augmented matrix is singular to KLU");
        return kin__fail(a, KIN_ENOMEM, "sparse analysis: KLU factorization failed (status %d)", g->common.status);
    }
    return KIN_OK;
}

/* Orthonormalise the n x b block X (ld n) in place by Householder QR.
 * work: lwork doubles (at least b * 64 + b). */
static int orthonormalise(kin_assembly *a, int n, int b, double *X, double *work, int lwork)
{
    int info = 0, lw = lwork - b;
    double *tau = work, *w = work + b;
    dgeqrf_(&n, &b, X, &n, tau, w, &lw, &info);
    if (info == 0) dorgqr_(&n, &b, &b, X, &n, tau, w, &lw, &info);
    if (info != 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgeqrf/dorgqr (sparse analysis) info = %d", info);
    return KIN_OK;
}

/* v_max to rounding, from Lanczos's Ritz value theta (a lower bound) and
 * its residual res: mu^2 I - H^T H is positive definite exactly when
 * mu > v_max, which a CHOLMOD Cholesky factorization decides (it fails
 * otherwise); the first mu = theta (1 + delta) with delta = res / theta,
 * 8x that, ... (up to 1) that passes is an upper bound, and bisection on
 * that bracket narrows it to BRACKET_UNITS rounding units (each step one
 * numeric factorization on the one symbolic analysis). Forming H^T H is
 * harmless at the top of the spectrum: its rounding moves the eigenvalues
 * near v_max^2 by a few eps v_max^2, i.e. v_max by a few eps relative.
 * *vmax := the bracket's middle, *delta := its relative width. KIN_OK,
 * KIN_ENOMEM, or KIN_ENOTCONVERGED (no bound up to 2 theta). */
static int vmax_bracket(kin_assembly *a, const aug_t *g, double theta, double res, double *vmax, double *delta)
{
    int nf = g->nf, nb = g->nb, d = g->d, rc = KIN_ENOMEM;
    cholmod_common cc;
    cholmod_start(&cc);
    cc.print = 0;
    cc.error_handler = NULL;
    cc.supernodal = CHOLMOD_SUPERNODAL; /* LL' (which fails where not positive definite), not a simplicial LDL' */
    cholmod_sparse *H = cholmod_allocate_sparse((size_t)nf, (size_t)nb, (size_t)nb * 2 * (size_t)d, 0, 1, 0,
                                                CHOLMOD_REAL, &cc);
    cholmod_sparse *HT = NULL, *C = NULL, *E = NULL;
    cholmod_factor *L = NULL;
    if (H) {
        int *Hp = H->p, *Hi = H->i, nz = 0;
        double *Hx = H->x;
        for (int k = 0; k < nb; ++k) {
            Hp[k] = nz;
            for (int p = 0; p < 2 * d; ++p) {
                int r = g->row[(size_t)k * 2 * d + p];
                if (r < 0) continue;
                Hi[nz] = r;
                Hx[nz++] = p < d ? g->cs[(size_t)k * d + p] : -g->cs[(size_t)k * d + p - d];
            }
        }
        Hp[nb] = nz;
        HT = cholmod_transpose(H, 1, &cc); /* nb x nf, sorted */
    }
    if (HT) C = cholmod_ssmult(HT, H, 0, 1, 1, &cc); /* H^T H */
    if (C) E = cholmod_speye((size_t)nb, (size_t)nb, CHOLMOD_REAL, &cc);
    double lo = theta, hi = INFINITY;
    int failed = !(C && E);
    /* 1: mu > v_max; 0: not; -1: CHOLMOD failed */
#define KIN_PD_TEST(mu, out)                                                                             \
    do {                                                                                                 \
        double al_[2] = {(mu) * (mu), 0.0}, be_[2] = {-1.0, 0.0};                                        \
        cholmod_sparse *D_ = cholmod_add(E, C, al_, be_, 1, 1, &cc);                                     \
        cholmod_sparse *S_ = D_ ? cholmod_copy(D_, 1, 1, &cc) : NULL;                                    \
        if (S_ && !L) L = cholmod_analyze(S_, &cc);                                                      \
        int ok_ = S_ && L && cholmod_factorize(S_, L, &cc) && cc.status != CHOLMOD_OUT_OF_MEMORY;        \
        (out) = !ok_ ? -1 : (cc.status == CHOLMOD_OK && L->is_ll && L->minor == (size_t)nb);            \
        cholmod_free_sparse(&D_, &cc);                                                                   \
        cholmod_free_sparse(&S_, &cc);                                                                   \
    } while (0)
    for (double dl = fmax(res / theta, BRACKET_UNITS * DBL_EPSILON); !failed && dl <= 1.0; dl *= 8.0) {
        int pd = 0;
        KIN_PD_TEST(theta * (1.0 + dl), pd);
        if (pd < 0) failed = 1;
        else if (pd) {
            hi = theta * (1.0 + dl);
            break;
        } else lo = theta * (1.0 + dl);
    }
    while (!failed && isfinite(hi) && hi - lo > BRACKET_UNITS * DBL_EPSILON * hi) {
        double mid = 0.5 * (lo + hi);
        int pd = 0;
        KIN_PD_TEST(mid, pd);
        if (pd < 0) failed = 1;
        else if (pd) hi = mid;
        else lo = mid;
    }
#undef KIN_PD_TEST
    if (!failed && isfinite(hi)) {
        rc = KIN_OK;
        *vmax = 0.5 * (lo + hi);
        *delta = (hi - lo) / lo;
    } else if (!failed) rc = KIN_ENOTCONVERGED;
    cholmod_free_factor(&L, &cc);
    cholmod_free_sparse(&E, &cc);
    cholmod_free_sparse(&C, &cc);
    cholmod_free_sparse(&HT, &cc);
    cholmod_free_sparse(&H, &cc);
    cholmod_finish(&cc);
    if (rc == KIN_ENOMEM) return kin__fail(a, KIN_ENOMEM, "sparse analysis: CHOLMOD bracket of v_max");
    if (rc) return kin__fail(a, KIN_ENOTCONVERGED, "sparse analysis: no upper bound of v_max up to twice Lanczos's");
    return KIN_OK;
}

/* v_max by Golub-Kahan-Lanczos bidiagonalisation of H with full
 * reorthogonalisation (work: (nf + nb) * (GKL_MAX + 1) doubles and the
 * small matrices). KIN_OK or KIN_ENOMEM / KIN_ENOTCONVERGED. */
static int gkl_vmax(kin_assembly *a, const aug_t *g, double *vmax, double *vres)
{
    int nf = g->nf, nb = g->nb, kmax = GKL_MAX;
    if (kmax > nf) kmax = nf;
    if (kmax > nb) kmax = nb;
    double *P = malloc(sizeof(double) * (size_t)nb * (size_t)(kmax + 1));
    double *U = malloc(sizeof(double) * (size_t)nf * (size_t)kmax);
    double *al = calloc((size_t)kmax + 1, sizeof *al), *be = calloc((size_t)kmax + 2, sizeof *be);
    double *B = malloc(sizeof(double) * (size_t)kmax * (size_t)kmax);
    double *sv = malloc(sizeof(double) * (size_t)kmax), *Ub = malloc(sizeof(double) * (size_t)kmax * kmax);
    int lw = 5 * kmax + 64;
    double *w = malloc(sizeof(double) * (size_t)lw);
    int rc = KIN_OK;
    *vmax = 0.0;
    *vres = 0.0;
    if (!P || !U || !al || !be || !B || !sv || !Ub || !w) {
        rc = kin__fail(a, KIN_ENOMEM, "sparse analysis: Lanczos vectors (%d steps)", kmax);
        goto out;
    }
    unsigned long long seed = START_SEED;
    for (int i = 0; i < nb; ++i) P[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53 - 0.5;
    double nrm = kin__norm(nb, P);
    for (int i = 0; i < nb; ++i) P[i] /= nrm;
    int converged = 0;
    for (int j = 0; j < kmax && !converged; ++j) {
        double *u = U + (size_t)j * nf, *p = P + (size_t)j * nb, *pn = P + (size_t)(j + 1) * nb;
        mul_H(g, p, u);
        if (j > 0)
            for (int i = 0; i < nf; ++i) u[i] -= be[j] * U[i + (size_t)(j - 1) * nf];
        for (int pass = 0; pass < 2; ++pass)
            for (int q = 0; q < j; ++q) {
                const double *uq = U + (size_t)q * nf;
                double c = kin__dot(nf, uq, u);
                for (int i = 0; i < nf; ++i) u[i] -= c * uq[i];
            }
        al[j] = kin__norm(nf, u);
        int stop = !(al[j] > 0.0);
        if (!stop)
            for (int i = 0; i < nf; ++i) u[i] /= al[j];
        if (!stop) {
            mul_HT(g, u, pn);
            for (int i = 0; i < nb; ++i) pn[i] -= al[j] * p[i];
            for (int pass = 0; pass < 2; ++pass)
                for (int q = 0; q <= j; ++q) {
                    const double *pq = P + (size_t)q * nb;
                    double c = kin__dot(nb, pq, pn);
                    for (int i = 0; i < nb; ++i) pn[i] -= c * pq[i];
                }
            be[j + 1] = kin__norm(nb, pn);
            if (be[j + 1] > 0.0)
                for (int i = 0; i < nb; ++i) pn[i] /= be[j + 1];
        }
        /* the largest singular value of the bidiagonal B (k x k, upper: al on
         * the diagonal, be above) and its residual bound be_(k) |last entry
         * of its left vector| (checked every few steps: the SVD is O(k^3)) */
        int k = stop ? j : j + 1;
        if (k == 0) { /* H p = 0 for a random p: H = 0 */
            converged = 1;
            break;
        }
        if (!(stop || j + 1 == kmax || (j + 1) % 4 == 0 || be[j + 1] == 0.0)) continue;
        memset(B, 0, sizeof(double) * (size_t)k * (size_t)k);
        for (int q = 0; q < k; ++q) {
            B[q + (size_t)q * k] = al[q];
            if (q > 0) B[(q - 1) + (size_t)q * k] = be[q];
        }
        int info = 0, one = 1;
        double vt = 0.0;
        dgesvd_("A", "N", &k, &k, B, &k, sv, Ub, &k, &vt, &one, w, &lw, &info, 1, 1);
        if (info != 0) {
            rc = kin__fail(a, info < 0 ? KIN_ELAPACK_ARG : KIN_ELAPACK_CONV, "dgesvd (Lanczos) info = %d", info);
            goto out;
        }
        *vmax = sv[0];
        double res = stop ? 0.0 : be[k] * fabs(Ub[k - 1]);
        *vres = res;
        converged = stop || res <= GKL_TOL * sv[0] || k == nf || k == nb;
        if (stop || k == nf || k == nb) *vres = 0.0; /* the whole Krylov space: exact */
    }
out:
    free(P), free(U), free(al), free(be), free(B), free(sv), free(Ub), free(w);
    return rc;
}

/* The work of the iteration, counted in floating-point operations, against
 * the budget (the dense analysis's predicted cost where the dense route is
 * affordable): the route that costs less answers. Counted, not timed, so
 * the route taken does not depend on the machine's load. */
typedef struct {
    double budget, spent;
    double lu_nnz; /* entries of the augmented matrix's KLU factors */
    double h_nnz;  /* entries of H */
    int *over;     /* set where the budget or the block limit stopped the iteration */
} cost_t;

/* one iteration of a side with a block of b columns in R^dim (products in
 * R^other): the block solve, the QR, the products with H, the Ritz SVD and
 * the rotation */
static double iter_flops(const cost_t *c, int dim, int other, int b)
{
    double bd = (double)b;
    return SPARSE_FLOP_WEIGHT *
           (bd * (4.0 * c->lu_nnz + 4.0 * c->h_nnz) + (6.0 * dim + 4.0 * other) * bd * bd + 8.0 * bd * bd * bd);
}

/* One side's subspace iteration (side 0: the left singular vectors, the
 * mechanisms, in R^nf; side 1: the right ones, the self-stresses, in
 * R^nb). Its block and results. */
typedef struct {
    int side, dim, other; /* R^dim; the products land in R^other */
    int b;                /* columns */
    double *X;            /* dim x b: orthonormal, Ritz vectors ascending after ritz() */
    double *theta;        /* b Ritz values ascending */
    int k0;               /* Ritz values <= tau */
    double vr;            /* theta[k0] (INFINITY when k0 == b) */
    double res;           /* residual bound of vr */
} side_t;

/* Rayleigh-Ritz with H on the block: G = H^T X (H X), its SVD, X := X V
 * ascending, the count below tau and v_r's residual. Scratch: G (other x
 * b), V (b x b), T (dim x b), s (b), w (lw). */
static int ritz(kin_assembly *a, const aug_t *g, side_t *S, double tau, double *G, double *V, double *T,
                double *s, double *w, int lw, double *pv, double *hv)
{
    int dim = S->dim, oth = S->other, b = S->b, info = 0, one = 1;
    for (int c = 0; c < b; ++c) {
        if (S->side == 0) mul_HT(g, S->X + (size_t)c * dim, G + (size_t)c * oth);
        else mul_H(g, S->X + (size_t)c * dim, G + (size_t)c * oth);
    }
    double udum = 0.0;
    int mn = oth < b ? oth : b;
    double *Gc = T; /* G is kept for the residual: its copy is destroyed */
    memcpy(Gc, G, sizeof(double) * (size_t)oth * (size_t)b);
    dgesvd_("N", "A", &oth, &b, Gc, &oth, s, &udum, &one, V, &b, w, &lw, &info, 1, 1);
    if (info != 0)
        return kin__fail(a, info < 0 ? KIN_ELAPACK_ARG : KIN_ELAPACK_CONV, "dgesvd (Ritz values) info = %d", info);
    for (int i = mn; i < b; ++i) s[i] = 0.0; /* G has at most oth non-zero singular values */
    /* ascending: theta_i = s[b-1-i], Ritz vector X V^T's row b-1-i */
    for (int i = 0; i < b; ++i) S->theta[i] = s[b - 1 - i];
    double one_d = 1.0, zero = 0.0;
    dgemm_("N", "T", &dim, &b, &b, &one_d, S->X, &dim, V, &b, &zero, T, &dim, 1, 1);
    for (int i = 0; i < b; ++i) memcpy(S->X + (size_t)i * dim, T + (size_t)(b - 1 - i) * dim, sizeof(double) * (size_t)dim);
    S->k0 = 0;
    while (S->k0 < b && S->theta[S->k0] <= tau) S->k0++;
    S->vr = INFINITY;
    S->res = INFINITY;
    if (S->k0 < b) {
        /* Ritz pair (x, p = G v / theta): the residual ||H p - theta x|| (||H^T p - theta x||) bounds
         * the distance from theta to a singular value of H */
        int k = S->k0;
        const double *x = S->X + (size_t)k * dim;
        double th = S->theta[k];
        S->vr = th;
        if (S->side == 0) mul_HT(g, x, pv);
        else mul_H(g, x, pv);
        for (int i = 0; i < oth; ++i) pv[i] /= th;
        if (S->side == 0) mul_H(g, pv, hv);
        else mul_HT(g, pv, hv);
        for (int i = 0; i < dim; ++i) hv[i] -= th * x[i];
        S->res = kin__norm(dim, hv);
    }
    return KIN_OK;
}

/* apply the side's block of M^-1 to X (in place), through the n x b
 * scratch R */
static int apply(kin_assembly *a, aug_t *g, side_t *S, double *R)
{
    int nf = g->nf, n = g->nf + g->nb, dim = S->dim, b = S->b, off = S->side == 0 ? 0 : nf;
    memset(R, 0, sizeof(double) * (size_t)n * (size_t)b);
    for (int c = 0; c < b; ++c) memcpy(R + (size_t)c * n + off, S->X + (size_t)c * dim, sizeof(double) * (size_t)dim);
    if (!klu_solve(g->sym, g->num, n, b, R, &g->common))
        return kin__fail(a, KIN_ENOMEM, "sparse analysis: KLU solve failed (status %d)", g->common.status);
    for (int c = 0; c < b; ++c) memcpy(S->X + (size_t)c * dim, R + (size_t)c * n + off, sizeof(double) * (size_t)dim);
    return KIN_OK;
}

/* the iteration's scratch for blocks of b columns at most */
typedef struct {
    double *R, *G, *V, *T, *s, *w, *pv, *hv;
    int lw;
} scratch_t;

static void scratch_free(scratch_t *w)
{
    free(w->R), free(w->G), free(w->V), free(w->T), free(w->s), free(w->w), free(w->pv), free(w->hv);
    memset(w, 0, sizeof *w);
}

static int scratch_alloc(kin_assembly *a, scratch_t *w, int nf, int nb, int b)
{
    size_t n = (size_t)nf + (size_t)nb, big = (size_t)(nf > nb ? nf : nb), bb = (size_t)b;
    scratch_free(w);
    w->lw = (int)big + 70 * b + 64; /* dgesvd of an other x b matrix; dgeqrf/dorgqr of dim x b */
    w->R = malloc(sizeof(double) * n * bb);
    w->G = malloc(sizeof(double) * big * bb);
    w->V = malloc(sizeof(double) * bb * bb);
    w->T = malloc(sizeof(double) * big * bb);
    w->s = malloc(sizeof(double) * bb);
    w->w = malloc(sizeof(double) * (size_t)w->lw);
    w->pv = malloc(sizeof(double) * big);
    w->hv = malloc(sizeof(double) * big);
    if (!w->R || !w->G || !w->V || !w->T || !w->s || !w->w || !w->pv || !w->hv)
        return kin__fail(a, KIN_ENOMEM, "sparse analysis: block of %d columns", b);
    return KIN_OK;
}

/* a random orthonormal block of b columns, the first `keep` columns of
 * the old block (old_b columns) kept */
static int side_start(kin_assembly *a, side_t *S, int b, int keep, unsigned long long *seed, double *w, int lw)
{
    double *X = malloc(sizeof(double) * (size_t)S->dim * (size_t)b), *th = malloc(sizeof(double) * (size_t)b);
    if (!X || !th) {
        free(X), free(th);
        return kin__fail(a, KIN_ENOMEM, "sparse analysis: block of %d columns", b);
    }
    if (keep > 0) memcpy(X, S->X, sizeof(double) * (size_t)S->dim * (size_t)keep);
    for (size_t i = (size_t)S->dim * (size_t)keep; i < (size_t)S->dim * (size_t)b; ++i)
        X[i] = (double)(kin__splitmix(seed) >> 11) * 0x1.0p-53 - 0.5;
    free(S->X);
    free(S->theta);
    S->X = X;
    S->theta = th;
    S->b = b;
    return orthonormalise(a, S->dim, b, X, w, lw);
}

/* The block of a side that has too few Ritz vectors beyond its null space
 * grows: doubled, capped at MAX_BLOCK (and the dimension); a block already
 * at the cap cannot grow (KIN_ELIMIT), nor one whose next iterations would
 * take the work past the budget (KIN_ELIMIT too: the dense route answers). */
static int side_grow(kin_assembly *a, aug_t *g, side_t *S, scratch_t *w, unsigned long long *seed, int *b_scratch,
                     cost_t *cost)
{
    const char *what = S->side == 0 ? "mechanisms" : "self-stresses";
    if (S->b >= MAX_BLOCK) {
        *cost->over = 1;
        return kin__fail(a, KIN_ELIMIT,
                         "sparse analysis: more than %d %s (its block of singular vectors holds at most %d "
                         "columns, %d of them beyond the null space)",
                         MAX_BLOCK - PAD_MIN, what, MAX_BLOCK, PAD_MIN);
    }
    int nb2 = 2 * S->b, rc;
    if (nb2 > S->dim) nb2 = S->dim;
    if (nb2 > MAX_BLOCK) nb2 = MAX_BLOCK;
    if (cost->spent + PREDICT_ITER * iter_flops(cost, S->dim, S->other, nb2) > cost->budget) {
        *cost->over = 1;
        return kin__fail(a, KIN_ELIMIT, "sparse analysis: at least %d %s; a block of %d columns would cost more "
                         "than the dense analysis", S->k0, what, nb2);
    }
    if (nb2 > *b_scratch) {
        if ((rc = scratch_alloc(a, w, g->nf, g->nb, nb2)) != KIN_OK) return rc;
        *b_scratch = nb2;
    }
    return side_start(a, S, nb2, S->b, seed, w->w, w->lw);
}

/* The subspace iteration of one side to a decided count: the count held
 * over two iterations with the gap at tau clear on both sides of it, and
 * v_r settled (or MAX_ITER iterations, or the budget, reached). */
static int side_iterate(kin_assembly *a, aug_t *g, side_t *S, double tau, double tau_hi, double vmax, scratch_t *w,
                        unsigned long long *seed, int *b_scratch, cost_t *cost)
{
    double round = ROUNDING_UNITS * DBL_EPSILON * vmax;
    int last_k0 = -1;
    double last_vr = NAN;
    for (int it = 0; it < MAX_ITER; ++it) {
        int rc = apply(a, g, S, w->R);
        if (!rc) rc = orthonormalise(a, S->dim, S->b, S->X, w->w, w->lw);
        if (!rc) rc = ritz(a, g, S, tau, w->G, w->V, w->T, w->s, w->w, w->lw, w->pv, w->hv);
        if (rc) return rc;
        cost->spent += iter_flops(cost, S->dim, S->other, S->b);
        if (S->b < S->dim && S->k0 + PAD_MIN > S->b) {
            /* too few Ritz vectors beyond the null space: a larger block, the Ritz vectors kept */
            if ((rc = side_grow(a, g, S, w, seed, b_scratch, cost)) != KIN_OK) return rc;
            last_k0 = -1;
            continue;
        }
        int whole = S->b == S->dim; /* the block is the whole space: Rayleigh-Ritz is exact */
        int decided = (S->k0 == 0 || S->theta[S->k0 - 1] <= tau - round) &&
                      (S->k0 == S->b || S->vr - fmax(S->res, round) > tau_hi);
        int counted = decided && (whole || S->k0 == last_k0);
        int vr_settled = whole || S->k0 == S->b || fabs(S->vr - last_vr) <= VR_STEADY * S->vr + round;
        if (counted && (vr_settled || it == MAX_ITER - 1 || cost->spent > cost->budget)) return KIN_OK;
        if (whole && !decided) break;
        if (cost->spent > cost->budget) {
            *cost->over = 1;
            return kin__fail(a, KIN_ELIMIT, "sparse analysis: the %s count undecided after more work than the "
                             "dense analysis takes", S->side == 0 ? "mechanism" : "self-stress");
        }
        last_k0 = S->k0;
        last_vr = S->vr;
    }
    return kin__fail(a, KIN_ENOTCONVERGED,
                     "sparse analysis: the %s count is undecided at rank_tol (a singular value within its "
                     "uncertainty of rank_tol * v_max, or the iteration not converged in %d steps)",
                     S->side == 0 ? "mechanism" : "self-stress", MAX_ITER);
}

/* Room for the results: m and s columns (and the config). */
static int san_reserve(kin_assembly *a, size_t m, size_t s)
{
    size_t nf = (size_t)a->nf, nb = (size_t)a->nb, nj = (size_t)a->nj * (size_t)a->dim;
    if (!a->san) {
        a->san = calloc(1, sizeof *a->san);
        if (!a->san) return kin__fail(a, KIN_ENOMEM, "sparse analysis: results");
        a->san->xyz = malloc(sizeof(double) * nj);
        a->san->Urig = malloc(sizeof(double) * nf * 6);
        if (!a->san->xyz || !a->san->Urig) return kin__fail(a, KIN_ENOMEM, "sparse analysis: results");
    }
    kin_sparse_an *r = a->san;
    if (m > r->cap_m || !r->Um) {
        free(r->Um), free(r->Uint);
        size_t c = m > 0 ? m : 1;
        r->Um = malloc(sizeof(double) * nf * c);
        r->Uint = malloc(sizeof(double) * nf * c);
        r->cap_m = r->Um && r->Uint ? c : 0;
        if (!r->cap_m) return kin__fail(a, KIN_ENOMEM, "sparse analysis: %zu mechanisms", m);
    }
    if (s > r->cap_s || !r->Ws) {
        free(r->Ws);
        size_t c = s > 0 ? s : 1;
        r->Ws = malloc(sizeof(double) * nb * c);
        r->cap_s = r->Ws ? c : 0;
        if (!r->cap_s) return kin__fail(a, KIN_ENOMEM, "sparse analysis: %zu self-stresses", s);
    }
    return KIN_OK;
}

const kin_sparse_an *kin__sparse_an_current(const kin_assembly *a)
{
    const kin_sparse_an *r = a ? a->san : NULL;
    if (!r || !r->valid || r->tol != kin__rank_tolerance(a)) return NULL;
    if (memcmp(r->xyz, a->xyz, sizeof(double) * (size_t)a->nj * (size_t)a->dim) != 0) return NULL;
    return r;
}

static int start_block(int dim, int least)
{
    int b = least + PAD;
    if (b > MAX_BLOCK) b = MAX_BLOCK;
    return b > dim ? dim : b;
}

double kin__dense_analysis_flops(const kin_assembly *a)
{
    /* dgesdd, jobz = 'A', on a p x q matrix (p >= q): the bidiagonalisation
     * and the full p x p and q x q orthogonal factors, about
     * 4 p q^2 + 4 p^2 q + 8 q^3 */
    double p = fmax(a->nf, a->nb), q = fmin(a->nf, a->nb);
    return 4.0 * p * q * q + 4.0 * p * p * q + 8.0 * q * q * q;
}

/* Refusals that need no factorization: a side whose least count
 * (nf - nb mechanisms, nb - nf self-stresses) is beyond the block limit,
 * or whose iterations with the start blocks would already cost more than
 * the budget. */
static int refuse_early(kin_assembly *a, int least_m, int least_s, cost_t *cost)
{
    int nf = a->nf, nb = a->nb;
    if (least_m > MAX_BLOCK - PAD_MIN || least_s > MAX_BLOCK - PAD_MIN) {
        *cost->over = 1;
        return kin__fail(a, KIN_ELIMIT,
                         "sparse analysis: at least %d %s (%d free coordinates, %d bars), more than the %d its "
                         "block of singular vectors can hold",
                         least_m > least_s ? least_m : least_s, least_m > least_s ? "mechanisms" : "self-stresses",
                         nf, nb, MAX_BLOCK - PAD_MIN);
    }
    double predicted = PREDICT_ITER * (iter_flops(cost, nf, nb, start_block(nf, least_m + 1 + a->nrig)) +
                                       iter_flops(cost, nb, nf, start_block(nb, least_s + 1)));
    if (predicted > cost->budget) {
        *cost->over = 1;
        return kin__fail(a, KIN_ELIMIT, "sparse analysis: at least %d mechanisms and %d self-stresses; its blocks "
                         "would cost more than the dense analysis", least_m, least_s);
    }
    return KIN_OK;
}

/* The right side's start block of b columns for s_expect self-stresses:
 * within the block limit, and its iterations within the budget. */
static int refuse_block(kin_assembly *a, const side_t *S, int b, int s_expect, cost_t *cost)
{
    if (s_expect > MAX_BLOCK - PAD_MIN || cost->spent + PREDICT_ITER * iter_flops(cost, S->dim, S->other, b) >
                                              cost->budget) {
        *cost->over = 1;
        return kin__fail(a, KIN_ELIMIT, "sparse analysis: %d self-stresses (by the mechanisms' count), %s", s_expect,
                         s_expect > MAX_BLOCK - PAD_MIN ? "more than its block of singular vectors can hold"
                                                        : "a block that would cost more than the dense analysis");
    }
    return KIN_OK;
}

int kin__analyse_sparse(kin_assembly *a, const double *xyz, int report, double budget, int *over)
{
    int nf = a->nf, nb = a->nb, rc;
    *over = 0;
    cost_t cost = {.budget = budget, .spent = 0.0, .lu_nnz = 0.0, .h_nnz = 2.0 * a->dim * (double)nb, .over = over};
    /* at least nf - nb mechanisms and nb - nf self-stresses; the left start
     * block has room for the rigid ones too */
    int least_m = nf > nb ? nf - nb : 0, least_s = nb > nf ? nb - nf : 0;
    if ((rc = refuse_early(a, least_m, least_s, &cost)) != KIN_OK) return rc;
    if (report && kin__progress(a, 0.0, 2.0))
        return kin__fail(a, KIN_ECANCELLED, "analysis cancelled before the factorization");
    aug_t g;
    memset(&g, 0, sizeof g);
    side_t L = {.side = 0, .dim = nf, .other = nb}, R = {.side = 1, .dim = nb, .other = nf};
    scratch_t w;
    memset(&w, 0, sizeof w);
    double vmax = 0.0, vres = 0.0, delta = 0.0, tol = kin__rank_tolerance(a);
    if ((rc = aug_bars(a, xyz, &g)) != KIN_OK) goto out;
    if ((rc = gkl_vmax(a, &g, &vmax, &vres)) != KIN_OK) goto out;
    /* v_max lies in [vmax, vmax (1 + delta)]: Lanczos's Ritz value is a lower bound, CHOLMOD certifies the upper */
    if (vmax > 0.0 && vres > 0.0 && (rc = vmax_bracket(a, &g, vmax, vres, &vmax, &delta)) != KIN_OK) goto out;
    double tau = tol * vmax, tau_hi = tau * (1.0 + delta);
    int m, s;
    if (!(vmax > 0.0)) {
        /* H = 0 (every bar between fixed joints): everything is null */
        m = nf;
        s = nb;
        if (m > MAX_BLOCK || s > MAX_BLOCK) {
            *over = 1;
            rc = kin__fail(a, KIN_ELIMIT, "sparse analysis: H = 0 with %d mechanisms and %d self-stresses", m, s);
            goto out;
        }
        if ((rc = san_reserve(a, (size_t)m, (size_t)s)) != KIN_OK) goto out;
        memset(a->san->Um, 0, sizeof(double) * (size_t)nf * (size_t)m);
        memset(a->san->Ws, 0, sizeof(double) * (size_t)nb * (size_t)s);
        for (int i = 0; i < m; ++i) a->san->Um[i + (size_t)i * nf] = 1.0;
        for (int i = 0; i < s; ++i) a->san->Ws[i + (size_t)i * nb] = 1.0;
        a->san->an.v_r = 0.0;
    } else {
        if ((rc = aug_factor(a, &g, tau)) != KIN_OK) goto out;
        cost.lu_nnz = (double)g.num->lnz + (double)g.num->unz;
        if (report && kin__progress(a, 1.0, 2.0)) {
            rc = kin__fail(a, KIN_ECANCELLED, "analysis cancelled after the factorization");
            goto out;
        }
        int bl = start_block(nf, least_m + 1 + a->nrig);
        int br = start_block(nb, least_s + 1);
        int bmax = bl > br ? bl : br;
        unsigned long long seed = START_SEED;
        if ((rc = scratch_alloc(a, &w, nf, nb, bmax)) != KIN_OK) goto out;
        if ((rc = side_start(a, &L, bl, 0, &seed, w.w, w.lw)) != KIN_OK) goto out;
        if ((rc = side_iterate(a, &g, &L, tau, tau_hi, vmax, &w, &seed, &bmax, &cost)) != KIN_OK) goto out;
        /* the mechanisms' count says how many self-stresses to expect (one
         * rank: nf - m = nb - s): the right block starts with room for them instead
         * of doubling up to it, and where that block would cost more than
         * the dense analysis, the dense one answers */
        int s_expect = nb - nf + L.k0;
        if (s_expect + 1 > least_s) br = start_block(nb, s_expect + 1);
        if ((rc = refuse_block(a, &R, br, s_expect, &cost)) != KIN_OK) goto out;
        if (br > bmax) {
            if ((rc = scratch_alloc(a, &w, nf, nb, br)) != KIN_OK) goto out;
            bmax = br;
        }
        if ((rc = side_start(a, &R, br, 0, &seed, w.w, w.lw)) != KIN_OK) goto out;
        if ((rc = side_iterate(a, &g, &R, tau, tau_hi, vmax, &w, &seed, &bmax, &cost)) != KIN_OK) goto out;
        m = L.k0;
        s = R.k0;
        if (nf - m != nb - s) {
            rc = kin__fail(a, KIN_ENOTCONVERGED,
                           "sparse analysis: the two sides disagree (rank %d from the mechanisms, %d from the "
                           "self-stresses)",
                           nf - m, nb - s);
            goto out;
        }
        if ((rc = san_reserve(a, (size_t)m, (size_t)s)) != KIN_OK) goto out;
        memcpy(a->san->Um, L.X, sizeof(double) * (size_t)nf * (size_t)m);
        memcpy(a->san->Ws, R.X, sizeof(double) * (size_t)nb * (size_t)s);
        a->san->an.v_r = nf - m > 0 ? fmin(L.vr, R.vr) : 0.0;
    }
    kin_sparse_an *r = a->san;
    r->valid = 0;
    r->an.size = sizeof r->an;
    r->an.rank = nf - m;
    r->an.m = m;
    r->an.s = s;
    r->an.s_trivial = a->nfixed_bars < s ? a->nfixed_bars : s; /* as the dense analysis (analysis.c) */
    r->an.v_max = vmax;
    int mr = 0;
    double *sw = malloc(sizeof(double) * kin__split_work(nf, m));
    if (!sw) {
        rc = kin__fail(a, KIN_ENOMEM, "sparse analysis: mechanism split");
        goto out;
    }
    rc = kin__split_basis(a, xyz, r->Um, m, r->Urig, r->Uint, &mr, sw);
    free(sw);
    if (rc) goto out;
    r->an.m_rigid = mr;
    r->an.m_internal = m - mr;
    r->tol = tol;
    memcpy(r->xyz, xyz, sizeof(double) * (size_t)a->nj * (size_t)a->dim);
    r->valid = 1;
    if (report) (void)kin__progress(a, 2.0, 2.0);
out:
    free(L.X), free(L.theta), free(R.X), free(R.theta);
    scratch_free(&w);
    aug_free(&g);
    return rc;
}
