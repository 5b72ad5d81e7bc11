/* KIN_STEP_SPARSE, the bordering (see sparse.c's header): the stand-in
 * rows' choice and pattern, the factorization of J0 = [C; e_k1^T; ...] with
 * Z = J0^-1 [e_nb ...] and the capacitance, the dense-row route where J0
 * or the capacitance goes bad, and the solves with the true J by the
 * Sherman-Morrison-Woodbury correction. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <klu.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "path/sparse_internal.h"

/* Below this reciprocal pivot growth (min over columns of max|J(:,j)| /
 * max|U(:,j)|) a reused pivot order has lost too many digits: pivot again. */
static const double RGROWTH_MIN = 1e-8;
/* Largest entry of Z = J0^-1 [e_nb ...] tolerated before the stand-ins are
 * re-chosen. Complete pivoting leaves it near 1; the correction's rounding
 * error grows with it (a factor 100 costs two of 16 digits). */
static const double ZGROWTH_MAX = 1e2;
/* Below this reciprocal condition (1-norm) of the capacitance, equilibrated
 * by the norms of the border rows and of Z's columns, the point is solved
 * with the dense rows in the matrix instead. */
static const double RCOND_MIN = 1e-10;
/* Two entries within this relative distance count as equal when the
 * stand-ins are chosen (the smaller index wins), so a choice does not
 * depend on rounding-level differences between two factorizations. */
static const double PIVOT_TIE = 1e-6;

/* Choose the stand-in coordinates s->k from the basis B (nf x nbr, ld nf;
 * overwritten) by complete pivoting: the largest entry left, its column
 * eliminated from the others. The chosen rows of a basis of null(C) are then
 * a well-conditioned nbr x nbr block, which is what makes J0 regular and
 * Z's entries small. Bumps the generation: each slot re-analyses at its
 * next factorization. */
void kin__standin_choose(struct kin_sparse *s, double *B)
{
    int n = s->n, nbr = s->nbr;
    unsigned used = 0; /* columns done (nbr <= 1 + 6 rigid mechanisms) */
    for (int r = 0; r < nbr; ++r) s->k[r] = -1;
    for (int step = 0; step < nbr; ++step) {
        double m = 0.0;
        for (int c = 0; c < nbr; ++c)
            if (!(used >> c & 1u))
                for (int i = 0; i < n; ++i) m = fmax(m, fabs(B[i + (size_t)c * n]));
        int pc = -1, pi = -1;
        for (int c = 0; c < nbr && pc < 0; ++c)
            if (!(used >> c & 1u)) {
                if (!(m > 0.0 && isfinite(m))) {
                    pc = c; /* degenerate basis: any coordinate not yet taken */
                    for (int i = 0; i < n && pi < 0; ++i) {
                        int taken = 0;
                        for (int q = 0; q < nbr; ++q) taken |= s->k[q] == i;
                        if (!taken) pi = i;
                    }
                    break;
                }
                for (int i = 0; i < n; ++i)
                    if (fabs(B[i + (size_t)c * n]) >= (1.0 - PIVOT_TIE) * m) {
                        pc = c;
                        pi = i;
                        break;
                    }
            }
        s->k[pc] = pi;
        used |= 1u << pc;
        double p = B[pi + (size_t)pc * n];
        if (!(m > 0.0 && isfinite(m))) continue;
        for (int c = 0; c < nbr; ++c)
            if (!(used >> c & 1u)) {
                double *bc = B + (size_t)c * n, f = bc[pi] / p;
                for (int i = 0; i < n; ++i) bc[i] -= f * B[i + (size_t)pc * n];
                bc[pi] = 0.0;
            }
    }
    s->gen++;
}

/* J0's pattern for the current stand-ins in slot sl: C's entries of each
 * column (bar rows ascending), then row nb + r in column k_r */
void kin__standin_pattern(struct kin_sparse *s, struct kin_slot *sl)
{
    int nz = 0;
    memcpy(sl->k, s->k, sizeof(int) * (size_t)s->nbr);
    for (int j = 0; j < s->n; ++j) {
        sl->Ap[j] = nz;
        for (int p = s->Ap[j]; p < s->Ap[j + 1] - s->nbr; ++p) sl->Ai[nz++] = s->Ai[p];
        for (int r = 0; r < s->nbr; ++r)
            if (sl->k[r] == j) sl->Ai[nz++] = s->nb + r;
    }
    sl->Ap[s->n] = nz;
    sl->gen = s->gen;
}

/* J0's values: C's from the last kin__sparse_fill(), 1 in the stand-in rows */
void kin__standin_values(const struct kin_sparse *s, struct kin_slot *sl)
{
    for (int j = 0; j < s->n; ++j) {
        int c = s->Ap[j + 1] - s->nbr - s->Ap[j];
        memcpy(sl->Ax + sl->Ap[j], s->Ax + s->Ap[j], sizeof(double) * (size_t)c);
        for (int p = sl->Ap[j] + c; p < sl->Ap[j + 1]; ++p) sl->Ax[p] = 1.0;
    }
}

/* New pattern and analysis of slot sl for the current stand-ins (the kept
 * column order; allocates). KIN_OK or KIN_ENOMEM. */
int kin__standin_analyse(kin_assembly *a, struct kin_slot *sl)
{
    struct kin_sparse *s = a->sp;
    if (sl->num) klu_free_numeric(&sl->num, &s->common);
    if (sl->sym) klu_free_symbolic(&sl->sym, &s->common);
    kin__standin_pattern(s, sl);
    sl->sym = klu_analyze_given(s->n, sl->Ap, sl->Ai, NULL, s->Q, &s->common);
    if (!sl->sym) return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU analysis of the stand-in pattern failed");
    return KIN_OK;
}

/* outcomes of factor_standin */
enum { STANDIN_OK = 0, STANDIN_SINGULAR, STANDIN_GROWTH, STANDIN_CAPACITANCE, STANDIN_NOMEM };

/* Factorize slot sl's J0 (refactorization when its pivot order holds), Z
 * and the capacitance's LU. STANDIN_OK when the correction is usable. */
static int factor_standin(kin_assembly *a, struct kin_slot *sl)
{
    struct kin_sparse *s = a->sp;
    int n = s->n, nbr = s->nbr, info = 0;
    kin__standin_values(s, sl);
    int ok = 0;
    if (sl->num) {
        ok = a->fault != KIN__FAULT_SPARSE_REPIVOT &&
             klu_refactor(sl->Ap, sl->Ai, sl->Ax, sl->sym, sl->num, &s->common) && s->common.status == KLU_OK &&
             klu_rgrowth(sl->Ap, sl->Ai, sl->Ax, sl->sym, sl->num, &s->common) && s->common.rgrowth >= RGROWTH_MIN;
        if (!ok) klu_free_numeric(&sl->num, &s->common);
    }
    if (!ok) {
        sl->num = klu_factor(sl->Ap, sl->Ai, sl->Ax, sl->sym, &s->common);
        if (!sl->num) return s->common.status == KLU_SINGULAR ? STANDIN_SINGULAR : STANDIN_NOMEM;
    }
    memset(sl->Z, 0, sizeof(double) * (size_t)n * (size_t)nbr);
    for (int r = 0; r < nbr; ++r) sl->Z[s->nb + r + (size_t)r * n] = 1.0;
    if (!klu_solve(sl->sym, sl->num, n, nbr, sl->Z, &s->common)) return STANDIN_NOMEM;
    double zmax = 0.0;
    for (size_t i = 0; i < (size_t)n * (size_t)nbr; ++i) zmax = fmax(zmax, fabs(sl->Z[i]));
    if (!isfinite(zmax)) return STANDIN_SINGULAR;
    if (zmax > ZGROWTH_MAX) return STANDIN_GROWTH;
    /* S = I + V^T Z; its equilibrated 1-norm and that of its inverse */
    double *S = sl->S, *inv = s->h, norm = 0.0, norm_inv = 0.0;
    double *wn = s->h + (size_t)nbr * nbr, *zn = wn + nbr; /* norms of the border rows, of Z's columns */
    for (int r = 0; r < nbr; ++r) {
        wn[r] = kin__norm(n, sl->W + (size_t)r * n);
        zn[r] = kin__norm(n, sl->Z + (size_t)r * n);
    }
    for (int c = 0; c < nbr; ++c) {
        const double *z = sl->Z + (size_t)c * n;
        double col = 0.0;
        for (int r = 0; r < nbr; ++r) {
            double v = (r == c) + kin__dot(n, sl->W + (size_t)r * n, z) - z[sl->k[r]];
            S[r + c * nbr] = v;
            col += fabs(v) / (wn[r] * zn[c]);
        }
        norm = fmax(norm, col);
    }
    dgetrf_(&nbr, &nbr, S, &nbr, sl->piv, &info);
    if (info != 0) return STANDIN_CAPACITANCE;
    memset(inv, 0, sizeof(double) * (size_t)nbr * nbr);
    for (int r = 0; r < nbr; ++r) inv[r + r * nbr] = 1.0;
    dgetrs_("N", &nbr, &nbr, S, &nbr, sl->piv, inv, &nbr, &info, 1);
    for (int r = 0; r < nbr; ++r) { /* column r of the equilibrated inverse */
        double col = 0.0;
        for (int c = 0; c < nbr; ++c) col += fabs(inv[c + r * nbr]) * zn[c] * wn[r];
        norm_inv = fmax(norm_inv, col);
    }
    double rcond = 1.0 / (norm * norm_inv);
    if (!(rcond >= RCOND_MIN) || a->fault == KIN__FAULT_SPARSE_CAPACITANCE) return STANDIN_CAPACITANCE;
    return STANDIN_OK;
}

/* B := J^-1 [e_nb ... e_(nf-1)] with the dense-row factors num (a basis of
 * null(C) whatever the border rows), then the stand-ins chosen from it */
int kin__standin_from_dense(kin_assembly *a, klu_numeric *num)
{
    struct kin_sparse *s = a->sp;
    int n = s->n, nbr = s->nbr;
    memset(s->B, 0, sizeof(double) * (size_t)n * (size_t)nbr);
    for (int r = 0; r < nbr; ++r) s->B[s->nb + r + (size_t)r * n] = 1.0;
    if (!klu_solve(s->dsym, num, n, nbr, s->B, &s->common))
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU solve failed (status %d)", s->common.status);
    kin__standin_choose(s, s->B);
    return KIN_OK;
}

/* J with its dense rows into slot sl's dnum (fresh pivoting; allocates) */
static int factor_dense(kin_assembly *a, struct kin_slot *sl, int *singular)
{
    struct kin_sparse *s = a->sp;
    if (sl->dnum) klu_free_numeric(&sl->dnum, &s->common);
    sl->dnum = klu_factor(s->Ap, s->Ai, s->Ax, s->dsym, &s->common);
    if (sl->dnum) return KIN_OK;
    if (s->common.status == KLU_SINGULAR) {
        *singular = 1;
        return KIN_OK;
    }
    return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU factorization failed (status %d)", s->common.status);
}

int kin__sparse_factor(kin_assembly *a, int slot, const double *xyz, const double *b, const double *R,
                       int mr, int *singular)
{
    struct kin_sparse *s = a->sp;
    *singular = 0;
    if (!kin__sparse_usable(a, mr)) return kin__fail(a, KIN_ESTATE, "sparse mode: J is not square here");
    struct kin_slot *sl = &s->slot[slot];
    int n = s->n;
    kin__sparse_fill(a, xyz, b, R);
    a->nfact++;
    sl->dense = 0;
    if (sl->dnum) klu_free_numeric(&sl->dnum, &s->common);
    if (a->fault == KIN__FAULT_SPARSE_SINGULAR) {
        *singular = 1; /* test hook: as klu_factor on a singular J */
        return KIN_OK;
    }
    if (a->fault == KIN__FAULT_SPARSE_FACTOR_NOMEM)
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU factorization failed (test fault)");
    memcpy(sl->W, b, sizeof(double) * (size_t)n);
    memcpy(sl->W + n, R, sizeof(double) * (size_t)n * (size_t)(s->nbr - 1));
    int rc;
    if (sl->gen != s->gen && (rc = kin__standin_analyse(a, sl)) != KIN_OK) return rc;
    int st = factor_standin(a, sl);
    if (st == STANDIN_GROWTH) {
        /* null(C) has moved away from the stand-ins: re-choose from Z */
        memcpy(s->B, sl->Z, sizeof(double) * (size_t)n * (size_t)s->nbr);
        kin__standin_choose(s, s->B);
        s->rechoices++;
        if ((rc = kin__standin_analyse(a, sl)) != KIN_OK) return rc;
        st = factor_standin(a, sl);
    }
    if (st == STANDIN_NOMEM)
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU factorization failed (status %d)", s->common.status);
    if (st == STANDIN_OK) return KIN_OK;
    /* J0 singular or the capacitance ill-conditioned: this point with the
     * dense rows in the matrix */
    if ((rc = factor_dense(a, sl, singular)) != KIN_OK || *singular) return rc;
    s->dense_points++;
    sl->dense = 1;
    if (st == STANDIN_CAPACITANCE) return KIN_OK; /* J itself is nearly singular: the stand-ins are not to blame */
    /* re-choose from this point's null space and try J0 again */
    if ((rc = kin__standin_from_dense(a, sl->dnum)) != KIN_OK) return rc;
    s->rechoices++;
    if ((rc = kin__standin_analyse(a, sl)) != KIN_OK) return rc;
    st = factor_standin(a, sl);
    if (st == STANDIN_NOMEM)
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU factorization failed (status %d)", s->common.status);
    if (st == STANDIN_OK) {
        klu_free_numeric(&sl->dnum, &s->common);
        sl->dense = 0;
    }
    return KIN_OK;
}

int kin__sparse_solve(kin_assembly *a, int slot, int trans, double *v)
{
    struct kin_sparse *s = a->sp;
    const struct kin_slot *sl = s ? &s->slot[slot] : NULL;
    if (!sl || !(sl->dense ? sl->dnum : sl->num))
        return kin__fail(a, KIN_ESTATE, "sparse mode: no factors in slot %d", slot);
    int n = s->n, nbr = s->nbr, one = 1, info = 0, ok = 1;
    if (sl->dense) {
        ok = trans ? klu_tsolve(s->dsym, sl->dnum, n, 1, v, &s->common)
                   : klu_solve(s->dsym, sl->dnum, n, 1, v, &s->common);
    } else if (!trans) {
        /* x = y - Z S^-1 V^T y, y = J0^-1 v */
        double *g = s->h;
        ok = klu_solve(sl->sym, sl->num, n, 1, v, &s->common);
        for (int r = 0; r < nbr; ++r) g[r] = kin__dot(n, sl->W + (size_t)r * n, v) - v[sl->k[r]];
        dgetrs_("N", &nbr, &one, sl->S, &nbr, sl->piv, g, &nbr, &info, 1);
        for (int r = 0; r < nbr; ++r)
            for (int i = 0; i < n; ++i) v[i] -= g[r] * sl->Z[i + (size_t)r * n];
    } else {
        /* w = J0^-T (v - V S^-T Z^T v) */
        double *g = s->h;
        for (int r = 0; r < nbr; ++r) g[r] = kin__dot(n, sl->Z + (size_t)r * n, v);
        dgetrs_("T", &nbr, &one, sl->S, &nbr, sl->piv, g, &nbr, &info, 1);
        for (int r = 0; r < nbr; ++r) {
            for (int i = 0; i < n; ++i) v[i] -= g[r] * sl->W[i + (size_t)r * n];
            v[sl->k[r]] += g[r];
        }
        ok = klu_tsolve(sl->sym, sl->num, n, 1, v, &s->common);
    }
    if (!ok) return kin__fail(a, KIN_ESTATE, "sparse mode: KLU solve failed (status %d)", s->common.status);
    return KIN_OK;
}

int kin__sparse_set_standins(kin_assembly *a, const int *k)
{
    struct kin_sparse *s = a->sp;
    if (!s) return KIN_ESTATE;
    for (int r = 0; r < s->nbr; ++r) {
        if (k[r] < 0 || k[r] >= s->n) return KIN_EINVAL;
        for (int q = 0; q < r; ++q)
            if (k[q] == k[r]) return KIN_EINVAL;
    }
    memcpy(s->k, k, sizeof(int) * (size_t)s->nbr);
    s->gen++;
    return KIN_OK;
}

