/* The LU modes of kin_step (KIN_STEP_LU, KIN_STEP_SPARSE): factorization of
 * the bordered matrix J = [C; b^T; R^T] of a point (dense LU/LQ, or KLU via
 * sparse.c), the chord and Newton corrections made with it, the tangent and
 * the v_r / v_max estimates of a new point. path.c decides when they run. */
#include <math.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "path/path.h"
#include "path/step_lu.h"

/* LU mode: a new point gets the full SVD analysis when its estimated
 * v_r / v_max is below this multiple of rank_tol. The SVD calls a point a
 * bifurcation at v_r <= rank_tol * v_max; the estimates bound v_r from
 * above and v_max from below (Rayleigh quotients) and are usually within a
 * few per cent, so a factor of 1000 keeps the SVD's verdict unless they are
 * off by more than that. */
static const double LU_SVD_MARGIN = 1e3;
/* LU mode: inverse-iteration passes (each one solve with J^T and one with J)
 * for the v_r estimate at a new point, warm-started from the previous
 * point's vector: enough where v_r is well separated (near a bifurcation,
 * where it matters); elsewhere the estimate is rougher but far above the
 * threshold. */
enum { LU_VR_PASSES = 2 };
/* LU mode: weight of a fixed pseudo-random vector added to the warm start of
 * that inverse iteration. The warm start can be orthogonal to the singular
 * vector of v_r (exactly so, by symmetry, next to a bifurcation, where the
 * vanishing vector was a mechanism); near a bifurcation, where the estimate
 * matters, each pass multiplies this share by (v_(r-1) / v_r)^2. */
static const double LU_VR_SEED_WEIGHT = 1e-3;
/* seed of that pseudo-random vector (any fixed value: runs are repeatable) */
static const unsigned long long LU_VR_SEED = 0x5eedULL;


/* Euclidean norm for the LU side's vectors (estimates, the slope's
 * subspace): the plain sum of squares in 4 partial sums, no division. The
 * scaled kin__norm (as BLAS dnrm2) cost a division per entry: 2.6% of a
 * cheap follow on the flat state in these calls. Where the sum could have
 * overflowed or lost its underflowed squares (outside 2^-900 ... 2^1000),
 * or is not finite, kin__norm's. Agrees with it to rounding (7.7e-16
 * relative on random vectors). Not used for the tangent, whose bits the
 * next step's predictor carries. */
static const double FAST_NORM_LO = 0x1p-900, FAST_NORM_HI = 0x1p+1000;

static double fast_norm(int n, const double *x)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int i = 0;
    for (; i + 4 <= n; i += 4) {
        s0 += x[i] * x[i];
        s1 += x[i + 1] * x[i + 1];
        s2 += x[i + 2] * x[i + 2];
        s3 += x[i + 3] * x[i + 3];
    }
    for (; i < n; ++i) s0 += x[i] * x[i];
    double s = (s0 + s1) + (s2 + s3);
    return s >= FAST_NORM_LO && s <= FAST_NORM_HI ? sqrt(s) : kin__norm(n, x);
}

/* the sparse route applies to a point with mr rigid mechanisms */
static int sparse_route(const kin_assembly *a, int mr)
{
    return a->opt.factorization == KIN_STEP_SPARSE && kin__sparse_usable(a, mr);
}

/* Solve with the bordered factors F of J = [C; b^T; R^T] (rows x nf):
 * trans = 0: v (rows entries) := least-squares solution x of J x = v, in
 *            v[0..nf-1] (the exact solution when J is square);
 * trans = 1: v (first nf entries given, room for rows) := minimum-norm
 *            solution w of J^T w = v (rows entries). */
static int lu_solve(kin_assembly *a, const kin_lufactor *F, int trans, double *v)
{
    int nf = a->nf, rows = F->rows, one = 1, info = 0;
    if (F->sparse) return kin__sparse_solve(a, (int)(F - a->lu), trans, v); /* KLU holds J itself */
    if (rows == nf && F->inv) {
        /* with (J^T)^-1 (made with the factors, factor_point): J^T w = v is
         * w = (J^T)^-1 v, J x = v is x = ((J^T)^-1)^T v */
        double d1 = 1.0, d0 = 0.0;
        dgemv_(trans ? "N" : "T", &nf, &nf, &d1, F->Jinv, &nf, v, &one, &d0, a->luw2, &one, 1);
        memcpy(v, a->luw2, sizeof(double) * (size_t)nf);
        return KIN_OK;
    }
    if (rows == nf) {
        /* J = (J^T)^T and F holds the LU of J^T */
        dgetrs_(trans ? "N" : "T", &nf, &one, F->JT, &nf, F->ipiv, v, &nf, &info, 1);
    } else if (!trans) {
        /* J^T = L Q: J x ~ v  <=>  L^T x = (Q v)[0..nf-1] */
        dormlq_("L", "N", &rows, &one, &nf, F->JT, &nf, F->tq, v, &rows, a->work, &a->lwork, &info, 1, 1);
        if (info == 0) dtrtrs_("L", "T", "N", &nf, &one, F->JT, &nf, v, &rows, &info, 1, 1, 1);
    } else {
        /* L Q w = v, minimum norm: w = Q^T [L^-1 v; 0] */
        dtrtrs_("L", "N", "N", &nf, &one, F->JT, &nf, v, &rows, &info, 1, 1, 1);
        for (int i = nf; i < rows; ++i) v[i] = 0.0;
        if (info == 0)
            dormlq_("L", "T", &rows, &one, &nf, F->JT, &nf, F->tq, v, &rows, a->work, &a->lwork, &info, 1, 1);
    }
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "bordered solve: LAPACK info = %d", info);
    if (info > 0) return kin__fail(a, KIN_ELAPACK_CONV, "bordered solve: singular factor (info = %d)", info);
    return KIN_OK;
}

/* The LU mode's factors of the current point, if they are usable: made at
 * this very configuration, judged regular, with the tangent known */
int kin__lu_current(const kin_assembly *a)
{
    const kin_lufactor *L = &a->lu[a->lu_cur];
    return L->valid && a->have_t && !a->t_chosen &&
           memcmp(L->xyz, a->xyz, sizeof(double) * (size_t)(a->nj * a->dim)) == 0;
}

/* Chord correction with the current point's bordered factors: solve
 * [C; b^T; R^T] d = [e; 0; 0] and remove the component along the tangent t.
 * C d = e and d _|_ (t, R) = null(C): the minimum-norm correction of eq. 11. */
int kin__lu_chord_correction(kin_assembly *a, const double *e, double *d)
{
    const kin_lufactor *F = &a->lu[a->lu_cur];
    int nf = a->nf, nb = a->nb;
    double *w = a->luw;
    memcpy(w, e, sizeof(double) * (size_t)nb);
    for (int i = nb; i < F->rows; ++i) w[i] = 0.0;
    int rc = lu_solve(a, F, 0, w);
    if (rc) return rc;
    double p = kin__dot(nf, a->t, w);
    for (int i = 0; i < nf; ++i) d[i] = w[i] - p * a->t[i];
    return KIN_OK;
}

int kin__lu_square_current(const kin_assembly *a)
{
    const kin_lufactor *F = &a->lu[a->lu_cur];
    return kin__lu_current(a) && !F->sparse && F->rows == a->nf && F->rows == a->nb + 1;
}

int kin__lu_pinv_correction(kin_assembly *a, const double *e, double *d)
{
    if (!kin__lu_current(a)) return KIN_ESTATE;
    return kin__lu_chord_correction(a, e, d);
}

/* v := v - sum_c q_c (q_c . v) over the columns of Q (nf x k, ld nf) */
static void remove_components(int nf, const double *Q, int k, double *v)
{
    for (int c = 0; c < k; ++c) {
        const double *q = Q + (size_t)c * nf;
        double p = kin__dot(nf, q, v);
        for (int i = 0; i < nf; ++i) v[i] -= p * q[i];
    }
}

/* Normalise v (nf); a zero or non-finite v becomes the unit vector
 * (1, ..., 1)/sqrt(nf). */
static void unit_or_ones(int nf, double *v)
{
    double n = fast_norm(nf, v);
    if (!(n > 0.0 && isfinite(n))) {
        for (int i = 0; i < nf; ++i) v[i] = 1.0;
        n = sqrt((double)nf);
    }
    for (int i = 0; i < nf; ++i) v[i] /= n;
}

/* LU mode's Newton correction at xyz: the solution s of
 * [C(xyz); t^T; R^T] s = [-e; 0; 0] by LU (dgetrf) of the square bordered
 * matrix, in the trial slot's storage (lu_new_point overwrites it later).
 * C s = -e, s _|_ (t, R): the same correction as kin__bordered_solve's
 * minimum-norm solution of [C; t^T] s = [-e; 0] at a fraction of the cost
 * of its QR. When the matrix is not square, or singular, it is
 * kin__bordered_solve's. */
int kin__lu_newton_solve(kin_assembly *a, const double *xyz, const double *e, double *s, int *reusable)
{
    int slot = 1 - a->lu_cur;
    kin_lufactor *T = &a->lu[slot];
    int nf = a->nf, nb = a->nb, mr = 0, info = 0, one = 1;
    T->valid = 0;
    T->sparse = 0;
    T->inv = 0;
    T->det_sign = 0;
    *reusable = 0;
    int rc = kin__rigid_basis(a, xyz, a->luR, &mr);
    if (rc) return rc;
    if (nb + 1 + mr != nf) return kin__bordered_solve(a, xyz, a->t, e, s);
    if (sparse_route(a, mr)) {
        int singular = 0;
        rc = kin__sparse_factor(a, slot, xyz, a->t, a->luR, mr, &singular);
        if (rc) return rc;
        if (singular) return kin__bordered_solve(a, xyz, a->t, e, s);
        T->sparse = 1;
        for (int k = 0; k < nb; ++k) s[k] = -e[k];
        for (int k = nb; k < nf; ++k) s[k] = 0.0;
        rc = kin__sparse_solve(a, slot, 0, s);
        if (rc) return rc;
        *reusable = 1;
        return KIN_OK;
    }
    /* where the follower keeps inverses (factor_point), Newton's matrix is
     * inverted the same way: Gauss-Jordan on the sparse J^T costs less than
     * dgetrf alone (6.7 against 10.2 us on the hexagonal sail,
     * bench_lu_point), and each reuse is a product (0.2 us, dgetrs 1.3) */
    int gj = T->Jinv && a->lu_inverse;
    double *JT = gj ? T->Jinv : T->JT;
    kin__build_H(a, xyz, JT, nf);
    memcpy(JT + (size_t)nb * nf, a->t, sizeof(double) * (size_t)nf);
    memcpy(JT + (size_t)(nb + 1) * nf, a->luR, sizeof(double) * (size_t)nf * (size_t)mr);
    a->nfact++;
    for (int k = 0; k < nb; ++k) s[k] = -e[k];
    for (int k = nb; k < nf; ++k) s[k] = 0.0;
    if (gj) {
        if (kin__gauss_jordan_inverse(nf, JT, T->ipiv, a->iwork, a->luw, &T->det_sign) != 0)
            return kin__bordered_solve(a, xyz, a->t, e, s);
        T->inv = 1;
        T->rows = nf;
        rc = lu_solve(a, T, 0, s);
        if (rc) return rc;
        *reusable = 1;
        return KIN_OK;
    }
    dgetrf_(&nf, &nf, JT, &nf, T->ipiv, &info);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrf info = %d", info);
    if (info > 0) return kin__bordered_solve(a, xyz, a->t, e, s);
    dgetrs_("T", &nf, &one, JT, &nf, T->ipiv, s, &nf, &info, 1);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrs info = %d", info);
    *reusable = 1;
    return KIN_OK;
}

/* The same correction with the factors the last lu_newton_solve left (a
 * chord step with the Jacobian of a nearby iterate: no factorization). */
int kin__lu_newton_reuse(kin_assembly *a, const double *e, double *s)
{
    const kin_lufactor *T = &a->lu[1 - a->lu_cur];
    int nf = a->nf, nb = a->nb, info = 0, one = 1;
    for (int k = 0; k < nb; ++k) s[k] = -e[k];
    for (int k = nb; k < nf; ++k) s[k] = 0.0;
    if (T->sparse) return kin__sparse_solve(a, 1 - a->lu_cur, 0, s);
    if (T->inv) return lu_solve(a, T, 0, s);
    dgetrs_("T", &nf, &one, T->JT, &nf, T->ipiv, s, &nf, &info, 1);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrs info = %d", info);
    return KIN_OK;
}

/* sign of the determinant of an LU factorization (dgetrf: diagonal of U and
 * row interchanges) */
static int lu_sign(int n, const double *LU, const int *ipiv)
{
    int sg = 1;
    for (int i = 0; i < n; ++i) {
        double d = LU[i + (size_t)i * n];
        if (d == 0.0) return 0;
        if (d < 0.0) sg = -sg;
        if (ipiv[i] != i + 1) sg = -sg;
    }
    return sg;
}

/* Factorize J = [C(xyz); b^T; R^T] (b = border, nf entries; R the rigid
 * mechanisms at xyz) into lu[slot], put the unit tangent (solution of
 * J tau = e_nb, not yet oriented) in a->d, estimate v_max and v_r starting
 * from the vectors wr and wm (NULL: a fixed start). *regular = 1 when the
 * point needs no SVD; 0 when the caller must analyse by SVD (estimated
 * v_r / v_max small, J singular, or J wide). */
/* Sparse mode: a point whose estimates are too close to rank_tol to call it
 * regular, where the dense SVD that decides such points cannot be had (its
 * workspace does not fit in memory, or LAPACK's int sizes; the 10^4-joint
 * mast at the default rank_tol, v_r / v_max = 2.3e-7): the sparse analysis
 * (model/analysis_sparse.c) decides instead. One internal mechanism and
 * mr rigid ones there: the point is regular, with the analysis's v_r and
 * v_max. Another count: not regular (the caller's dense route then refuses,
 * saying why). A failed analysis: its status and message. Allocates (the
 * analysis's workspace), only at such points. */
static int confirm_sparse(kin_assembly *a, const double *xyz, kin_lufactor *T, int mr, int *regular)
{
    if (a->opt.factorization != KIN_STEP_SPARSE || !T->sparse || kin__dense_affordable(a)) return KIN_OK;
    int over = 0, rc = kin__analyse_sparse(a, xyz, 0, INFINITY, &over);
    if (rc) return rc;
    const kin_analysis *an = &a->san->an;
    if (an->m_internal == 1 && an->m_rigid == mr) {
        T->v_r = an->v_r;
        T->v_max = an->v_max;
        T->valid = 1;
        *regular = 1;
    }
    return KIN_OK;
}

static int factor_point(kin_assembly *a, const double *xyz, const double *border, int slot, const double *wr,
                        const double *wm, int *regular)
{
    kin_lufactor *T = &a->lu[slot];
    int nf = a->nf, nb = a->nb, mr = 0, info = 0, inc = 1;
    double done = 1.0, zero = 0.0;
    *regular = 0;
    T->valid = 0;
    T->sparse = 0;
    T->inv = 0;
    T->det_sign = 0;
    int rc = kin__rigid_basis(a, xyz, a->luR, &mr);
    if (rc) return rc;
    int rows = nb + 1 + mr;
    if (rows < nf) return KIN_OK; /* at least two internal mechanisms: the SVD decides */
    T->rows = rows;
    if (wr) memcpy(T->vr_vec, wr, sizeof(double) * (size_t)nf);
    else memset(T->vr_vec, 0, sizeof(double) * (size_t)nf);
    if (wm) memcpy(T->vmax_vec, wm, sizeof(double) * (size_t)nf);
    else memset(T->vmax_vec, 0, sizeof(double) * (size_t)nf);
    double *x = T->vmax_vec, *y = a->y;
    unit_or_ones(nf, x);
    if (sparse_route(a, mr)) {
        /* KLU of J in compressed columns; v_max by the same power-iteration
         * pass, with C from the values just factorized */
        int singular = 0;
        rc = kin__sparse_factor(a, slot, xyz, border, a->luR, mr, &singular);
        if (rc) return rc;
        kin__sparse_C(a, x, y);
        kin__sparse_CT(a, y, x);
        T->v_max = sqrt(fast_norm(nf, x));
        unit_or_ones(nf, x);
        if (singular) return KIN_OK;
        T->sparse = 1;
    } else {
        /* J^T = [H, b, R] (nf x rows, ld nf). Where the follower asks
         * (a->lu_inverse) and J is square and small (KIN__LU_INVERSE_MAX_NF),
         * J^T is built straight into Jinv and inverted there (Gauss-Jordan,
         * gauss_jordan.c): a point's factors serve some 15 solves (the
         * tangent, the v_r estimate's passes, the next step's chord
         * corrections; near events the slope's subspace iteration), and a
         * product with the inverse costs 0.2 us against 1.3 us for a solve
         * by dgetrs (46 coordinates). The inverse by Gauss-Jordan costs
         * 6.7 us on the sail's J^T, dgetrf + dgetri 25.3 us
         * (bench_lu_point). */
        if ((rc = kin__dense_ready(a)) != KIN_OK) return rc;
        int gj = rows == nf && T->Jinv && a->lu_inverse;
        double *JT = gj ? T->Jinv : T->JT;
        kin__build_H(a, xyz, JT, nf);
        memcpy(JT + (size_t)nb * nf, border, sizeof(double) * (size_t)nf);
        memcpy(JT + (size_t)(nb + 1) * nf, a->luR, sizeof(double) * (size_t)nf * (size_t)mr);
        /* v_max: one power-iteration pass on H H^T (a lower bound) */
        dgemv_("T", &nf, &nb, &done, JT, &nf, x, &inc, &zero, y, &inc, 1);
        dgemv_("N", &nf, &nb, &done, JT, &nf, y, &inc, &zero, x, &inc, 1);
        double nx = fast_norm(nf, x);
        T->v_max = sqrt(nx);
        unit_or_ones(nf, x);
        a->nfact++;
        if (gj) {
            /* workspace: ipiv (nf), a->iwork (at least 8 nf, query_lwork), a->luw */
            if (kin__gauss_jordan_inverse(nf, JT, T->ipiv, a->iwork, a->luw, &T->det_sign) != 0) return KIN_OK; /* singular */
            T->inv = 1;
        } else if (rows == nf) {
            dgetrf_(&nf, &nf, JT, &nf, T->ipiv, &info);
            if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrf info = %d", info);
            if (info > 0) return KIN_OK; /* exactly singular */
            T->det_sign = lu_sign(nf, JT, T->ipiv);
        } else {
            dgelqf_(&nf, &rows, JT, &nf, T->tq, a->work, &a->lwork, &info);
            if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgelqf info = %d", info);
            for (int i = 0; i < nf; ++i)
                if (JT[i + (size_t)i * nf] == 0.0) return KIN_OK; /* exactly rank deficient */
        }
    }
    /* tangent: C tau = 0, b . tau = 1, R^T tau = 0 */
    double *w = a->luw, *t1 = a->d;
    for (int i = 0; i < rows; ++i) w[i] = 0.0;
    w[nb] = 1.0;
    rc = lu_solve(a, T, 0, w);
    if (rc) return rc;
    double nt = kin__norm(nf, w);
    if (!(nt > 0.0 && isfinite(nt))) return KIN_OK;
    for (int i = 0; i < nf; ++i) t1[i] = w[i] / nt;
    /* v_r: inverse iteration on pinv(C) pinv(C)^T, whose largest eigenvalue
     * is 1/v_r^2, in the complement of null(C) = span(t1, R). For x there,
     * the first nb entries of J^-T x are pinv(C)^T x, and J^-1 [y; 0; 0]
     * minus its t1 component is pinv(C) y. */
    x = T->vr_vec;
    unit_or_ones(nf, x);
    unsigned long long seed = LU_VR_SEED;
    for (int i = 0; i < nf; ++i)
        x[i] += LU_VR_SEED_WEIGHT * ((double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53 - 0.5);
    remove_components(nf, a->luR, mr, x);
    remove_components(nf, t1, 1, x);
    unit_or_ones(nf, x);
    double vr = INFINITY;
    for (int k = 0; k < LU_VR_PASSES; ++k) {
        memcpy(w, x, sizeof(double) * (size_t)nf);
        rc = lu_solve(a, T, 1, w);
        if (rc) return rc;
        double ny = fast_norm(nb, w);
        vr = ny > 0.0 ? 1.0 / ny : INFINITY;
        for (int i = nb; i < rows; ++i) w[i] = 0.0;
        rc = lu_solve(a, T, 0, w);
        if (rc) return rc;
        remove_components(nf, t1, 1, w);
        memcpy(x, w, sizeof(double) * (size_t)nf);
        unit_or_ones(nf, x);
    }
    T->v_r = vr;
    memcpy(T->xyz, xyz, sizeof(double) * (size_t)(a->nj * a->dim));
    if (isfinite(vr) && vr > LU_SVD_MARGIN * a->opt.rank_tol * T->v_max) {
        T->valid = 1;
        *regular = 1;
        return KIN_OK;
    }
    return confirm_sparse(a, xyz, T, mr, regular);
}

int kin__lu_refactor(kin_assembly *a, const double *border, int *regular)
{
    *regular = 0;
    if (!a->have_t || a->t_chosen) return KIN_OK;
    /* warm starts: the slot's last vectors (a nearby point's), copied out
     * of the slot factor_point writes */
    const kin_lufactor *P = &a->lu[a->lu_cur];
    memcpy(a->luw2, P->vr_vec, sizeof(double) * (size_t)a->nf);
    memcpy(a->y, P->vmax_vec, sizeof(double) * (size_t)a->nf);
    int rc = factor_point(a, a->xyz, border, a->lu_cur, a->luw2, a->y, regular);
    if (rc == KIN_OK && !*regular) a->lu[a->lu_cur].valid = 0;
    return rc;
}

int kin__lu_new_point(kin_assembly *a, const double *xyz, int *regular)
{
    /* warm starts: the previous point's SVD vectors, or its estimates' */
    const kin_lufactor *P = &a->lu[a->lu_cur];
    const kin_factor *f0 = kin__cur(a);
    const double *wr = P->vr_vec, *wm = P->vmax_vec;
    if (f0->valid && f0->an.rank > 0) {
        wr = f0->U + (size_t)(f0->an.rank - 1) * a->nf;
        wm = f0->U;
    }
    return factor_point(a, xyz, a->t, 1 - a->lu_cur, wr, wm, regular);
}

/* Make the largest-magnitude entry of v positive: the SVD analysis's sign
 * rule for a lone internal mechanism (analysis.c), so a sparse start
 * follows the same direction as an SVD start. */
static void orient_like_svd(int n, double *v)
{
    int im = 0;
    for (int i = 1; i < n; ++i)
        if (fabs(v[i]) > fabs(v[im]) * (1.0 + 1e-12)) im = i;
    if (v[im] < 0.0)
        for (int i = 0; i < n; ++i) v[i] = -v[i];
}

/* Seed of the border row of a start point without a tangent (any fixed
 * value: runs are repeatable). A random row has a non-zero component along
 * the internal mechanism with probability one. */
static const unsigned long long START_BORDER_SEED = 0x5ba45eULL;

int kin__lu_start(kin_assembly *a, int *started)
{
    int nf = a->nf;
    *started = 0;
    if (a->opt.factorization != KIN_STEP_SPARSE || !a->sp || a->t_chosen) return KIN_OK;
    double *b = a->chord; /* scratch until the step computes its chord */
    if (a->have_t) {
        memcpy(b, a->t, sizeof(double) * (size_t)nf);
    } else {
        unsigned long long seed = START_BORDER_SEED;
        for (int i = 0; i < nf; ++i) b[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53 - 0.5;
    }
    int regular = 0;
    int rc = factor_point(a, a->xyz, b, a->lu_cur, NULL, NULL, &regular);
    if (rc || !regular) return rc;
    if (a->have_t) {
        if (kin__dot(nf, a->d, a->t) < 0.0)
            for (int i = 0; i < nf; ++i) a->d[i] = -a->d[i];
    } else {
        orient_like_svd(nf, a->d);
    }
    memcpy(a->t, a->d, sizeof(double) * (size_t)nf);
    a->have_t = 1;
    *started = 1;
    return KIN_OK;
}

/* ---- the cheap stretches of a follow (path.h) ---- */

void kin__lu_det_sign(const kin_assembly *a, const double *t_prev, int *sign)
{
    const kin_lufactor *F = &a->lu[a->lu_cur];
    *sign = 0;
    if (!kin__lu_current(a) || F->sparse || F->rows != a->nf) return;
    double c = kin__dot(a->nf, t_prev, a->t);
    if (c == 0.0) return;
    *sign = F->det_sign * (c > 0.0 ? 1 : -1);
}

int kin__border_det_sign(kin_assembly *a, int *sign)
{
    int nf = a->nf, nb = a->nb, mr = 0, info = 0;
    *sign = 0;
    if (!a->have_t) return KIN_OK;
    int rc = kin__dense_ready(a);
    if (rc) return rc;
    if ((rc = kin__rigid_basis(a, a->xyz, a->luR, &mr)) != KIN_OK) return rc;
    if (nb + 1 + mr != nf) return KIN_OK;
    double *JT = a->mwork; /* 2 nf^2 scratch */
    kin__build_H(a, a->xyz, JT, nf);
    memcpy(JT + (size_t)nb * nf, a->t, sizeof(double) * (size_t)nf);
    memcpy(JT + (size_t)(nb + 1) * nf, a->luR, sizeof(double) * (size_t)nf * (size_t)mr);
    a->nfact++;
    dgetrf_(&nf, &nf, JT, &nf, a->iwork, &info);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrf info = %d", info);
    if (info == 0) *sign = lu_sign(nf, JT, a->iwork);
    return KIN_OK;
}

double kin__lu_rel_estimate(const kin_assembly *a)
{
    const kin_factor *f = kin__cur(a);
    if (f->valid) return f->an.v_max > 0.0 ? f->an.v_r / f->an.v_max : -1.0;
    const kin_lufactor *F = &a->lu[a->lu_cur];
    if (kin__lu_current(a) && F->v_max > 0.0) return F->v_r / F->v_max;
    return -1.0;
}

void kin__path_save(const kin_assembly *a, kin__path_point *p)
{
    memcpy(p->xyz, a->xyz, sizeof(double) * (size_t)(a->nj * a->dim));
    memcpy(p->t, a->t, sizeof(double) * (size_t)a->nf);
    p->l = a->l;
    p->step_hint = a->step_hint;
    p->start_strain = a->start_strain;
    p->have_start_strain = a->have_start_strain;
    p->chord_hopeless = a->chord_hopeless;
}

void kin__path_restore(kin_assembly *a, const kin__path_point *p)
{
    memcpy(a->xyz, p->xyz, sizeof(double) * (size_t)(a->nj * a->dim));
    memcpy(a->t, p->t, sizeof(double) * (size_t)a->nf);
    a->have_t = 1;
    a->t_chosen = 0;
    a->l = p->l;
    a->step_hint = p->step_hint;
    a->start_strain = p->start_strain;
    a->have_start_strain = p->have_start_strain;
    a->chord_hopeless = p->chord_hopeless;
    a->fac[0].valid = a->fac[1].valid = 0;
    a->lu[0].valid = a->lu[1].valid = 0;
}

/* orthonormalize the k columns of X (nf x k, ld nf) against t and each
 * other (Gram-Schmidt twice); a column that vanishes is replaced by a fixed
 * pseudo-random one. */
static void block_orthonormalize(int nf, const double *t, int k, double *X, unsigned long long *seed)
{
    for (int j = 0; j < k; ++j) {
        double *x = X + (size_t)j * nf;
        for (int tries = 0; tries < 3; ++tries) {
            double n0 = fast_norm(nf, x);
            for (int pass = 0; pass < 2; ++pass) {
                remove_components(nf, t, 1, x);
                remove_components(nf, X, j, x);
            }
            double n = fast_norm(nf, x);
            if (n > 1e-8 * n0 && isfinite(n)) {
                for (int i = 0; i < nf; ++i) x[i] /= n;
                break;
            }
            for (int i = 0; i < nf; ++i) x[i] = (double)(kin__splitmix(seed) >> 11) * 0x1.0p-53 - 0.5;
        }
    }
}

/* Eigen-decomposition of the symmetric 2 x 2 matrix B (column-major, both
 * triangles set) as dsyev ("V") leaves it: eigenvalues ascending in lam,
 * unit eigenvectors in B's columns. One Jacobi rotation (Golub & Van Loan,
 * the symmetric Schur decomposition), accurate to rounding; the Rayleigh-Ritz
 * step of the slope's subspace iteration calls it at every pass, where
 * dsyev's call and workspace handling cost about 1% of a cheap follow. */
static void sym2_eig(double *B, double *lam)
{
    double p = B[0], q = B[1], r = B[3], c = 1.0, s = 0.0;
    if (q != 0.0) {
        double tau = (r - p) / (2.0 * q);
        double t = (tau >= 0.0 ? 1.0 : -1.0) / (fabs(tau) + sqrt(1.0 + tau * tau));
        c = 1.0 / sqrt(1.0 + t * t);
        s = t * c;
        p -= t * q; /* the eigenvalue of (c, -s) */
        r += t * q; /* ... of (s, c) */
    }
    if (p <= r) {
        lam[0] = p;
        lam[1] = r;
        B[0] = c, B[1] = -s, B[2] = s, B[3] = c;
    } else {
        lam[0] = r;
        lam[1] = p;
        B[0] = s, B[1] = c, B[2] = c, B[3] = -s;
    }
}

/* seed of the pseudo-random start vectors of the triple's subspace */
static const unsigned long long VR_BLOCK_SEED = 0xb10cULL;

int kin__lu_vr_triple(kin_assembly *a, int max_passes, double tol, int k, double *block, int *warm, double *u,
                      double *w, double *v, int *converged)
{
    const kin_lufactor *F = &a->lu[a->lu_cur];
    int nf = a->nf, nb = a->nb, rows = F->rows, info = 0;
    *converged = 0;
    if (!kin__lu_current(a) || F->sparse || rows != nf || k < 1 || k > KIN__VR_BLOCK_MAX) return KIN_ESTATE;
    double *t = a->t, *R = block, *X = block + (size_t)k * nf;
    double B[KIN__VR_BLOCK_MAX * KIN__VR_BLOCK_MAX], lam[KIN__VR_BLOCK_MAX], ew[64];
    double *Y = a->mwork; /* 3 nf^2 + 8 nf: room for k nf */
    double d1 = 1.0, d0 = 0.0;
    int lwork = 64;
    unsigned long long seed = VR_BLOCK_SEED;
    /* the start: the LU mode's vector, then the last call's next Ritz
     * vectors (they follow the path's next singular values) */
    memcpy(X, F->vr_vec, sizeof(double) * (size_t)nf);
    for (int j = 1; j < k; ++j)
        for (int i = 0; i < nf; ++i)
            X[i + (size_t)j * nf] =
                *warm ? R[i + (size_t)j * nf] : (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53 - 0.5;
    block_orthonormalize(nf, t, k, X, &seed);
    memcpy(u, X, sizeof(double) * (size_t)nf);
    for (int pass = 0; pass < max_passes; ++pass) {
        /* Y = J^-T X: its first nb rows are pinv(C)^T X (F holds the LU of J^T) */
        if (F->inv) {
            dgemm_("N", "N", &nf, &k, &nf, &d1, F->Jinv, &nf, X, &nf, &d0, Y, &nf, 1, 1);
        } else {
            memcpy(Y, X, sizeof(double) * (size_t)nf * (size_t)k);
            dgetrs_("N", &nf, &k, F->JT, &nf, F->ipiv, Y, &nf, &info, 1);
            if (info) return kin__fail(a, KIN_ELAPACK_ARG, "bordered solve: LAPACK info = %d", info);
        }
        /* Rayleigh-Ritz: B = (pinv(C)^T X)^T (pinv(C)^T X) = X^T M X */
        for (int p = 0; p < k; ++p)
            for (int q = 0; q <= p; ++q)
                B[p + q * k] = B[q + p * k] = kin__dot(nb, Y + (size_t)p * nf, Y + (size_t)q * nf);
        if (k == 2) sym2_eig(B, lam);
        else dsyev_("V", "L", &k, B, &k, lam, ew, &lwork, &info, 1, 1);
        if (info || !(lam[k - 1] > 0.0 && isfinite(lam[k - 1]))) return KIN_OK;
        /* the Ritz vectors, largest eigenvalue (smallest singular value) first */
        for (int j = 0; j < k; ++j) {
            const double *s = B + (size_t)(k - 1 - j) * k;
            double *r = R + (size_t)j * nf;
            for (int i = 0; i < nf; ++i) {
                double acc = 0.0;
                for (int q = 0; q < k; ++q) acc += X[i + (size_t)q * nf] * s[q];
                r[i] = acc;
            }
        }
        *warm = 1;
        unit_or_ones(nf, R);
        if (kin__dot(nf, R, u) < 0.0)
            for (int i = 0; i < nf; ++i) R[i] = -R[i];
        double moved = 0.0;
        for (int i = 0; i < nf; ++i) moved += (R[i] - u[i]) * (R[i] - u[i]);
        memcpy(u, R, sizeof(double) * (size_t)nf);
        *v = 1.0 / sqrt(lam[k - 1]);
        if (pass > 0 && sqrt(moved) <= tol) { /* moved under the operator, not only rotated within X */
            *converged = 1;
            break;
        }
        if (pass + 1 == max_passes) break;
        /* X := J^-1 [pinv(C)^T X; 0] = M X up to the null direction t */
        for (int j = 0; j < k; ++j)
            for (int i = nb; i < rows; ++i) Y[i + (size_t)j * nf] = 0.0;
        if (F->inv) {
            dgemm_("T", "N", &nf, &k, &nf, &d1, F->Jinv, &nf, Y, &nf, &d0, X, &nf, 1, 1);
        } else {
            dgetrs_("T", &nf, &k, F->JT, &nf, F->ipiv, Y, &nf, &info, 1);
            if (info) return kin__fail(a, KIN_ELAPACK_ARG, "bordered solve: LAPACK info = %d", info);
            memcpy(X, Y, sizeof(double) * (size_t)nf * (size_t)k);
        }
        block_orthonormalize(nf, t, k, X, &seed);
    }
    /* w and v for the final u */
    double *y = a->luw;
    memcpy(y, u, sizeof(double) * (size_t)nf);
    int rc = lu_solve(a, F, 1, y);
    if (rc) return rc;
    double ny = fast_norm(nb, y);
    if (!(ny > 0.0 && isfinite(ny))) {
        *converged = 0;
        return KIN_OK;
    }
    *v = 1.0 / ny;
    for (int i = 0; i < nb; ++i) w[i] = y[i] / ny;
    return KIN_OK;
}
