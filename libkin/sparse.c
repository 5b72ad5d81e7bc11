/* KIN_STEP_SPARSE: the square bordered matrix J = [C; b^T; R^T] of a point
 * in compressed-column form, factorized by SuiteSparse KLU.
 *
 * Why the dense border rows stay in the matrix: C (nb x nf) is wide, so it
 * cannot be factorized alone, and a bordering (Schur complement) scheme
 * would need a square sparse stand-in for the border (e.g. unit rows at a
 * few chosen coordinates) whose choice can go bad along a path. COLAMD,
 * the column ordering used here, ignores dense rows when it orders, and
 * partial pivoting takes them as pivot rows only where they are needed;
 * they cost about (1 + m_rigid) * nf entries of the factors: the sparsity
 * of C is kept, the solve is exact, and one symbolic analysis serves the
 * whole life of the handle (the pattern depends on the bars alone).
 *
 * Numeric factorization: klu_factor (partial pivoting, allocates) once per
 * slot when the mode is set; each new point then reuses the pivot order
 * with klu_refactor (no allocation). A refactorization whose reciprocal
 * pivot growth falls below RGROWTH_MIN, or that meets a zero pivot, is
 * redone by klu_factor with fresh pivoting (rare: the order of one point
 * is good for the points nearby). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cholmod.h>
#include <klu.h>

#include "internal.h"

/* Below this reciprocal pivot growth (min over columns of max|J(:,j)| /
 * max|U(:,j)|) a reused pivot order has lost too many digits: pivot again. */
static const double RGROWTH_MIN = 1e-8;
/* Seed of the pseudo-random border rows of the first factorization (any
 * fixed value: runs are repeatable). */
static const unsigned long long FIRST_BORDER_SEED = 0xb0dea5ULL;

struct kin_sparse {
    int n;       /* nf: J is n x n */
    int nbr;     /* border rows: n - nb (1 + m_rigid) */
    int *Ap;     /* n + 1 column pointers */
    int *Ai;     /* row indices: bar rows ascending, then the border rows nb..n-1 */
    double *Ax;  /* values of the last factorization */
    int *pos;    /* nb * 2 * dim: Ax index of bar k, end e, axis c (or -1: fixed) */
    klu_common common;
    klu_symbolic *sym;
    klu_numeric *num[2];
    int nested_dissection; /* the column order is METIS's (1) or COLAMD's (0) */
    double entries[2];     /* factor entries of the first factorization: COLAMD, METIS */
};

void kin__sparse_free(kin_assembly *a)
{
    if (!a || !a->sp) return;
    struct kin_sparse *s = a->sp;
    for (int f = 0; f < 2; ++f)
        if (s->num[f]) klu_free_numeric(&s->num[f], &s->common);
    if (s->sym) klu_free_symbolic(&s->sym, &s->common);
    free(s->Ap);
    free(s->Ai);
    free(s->Ax);
    free(s->pos);
    free(s);
    a->sp = NULL;
}

int kin__sparse_usable(const kin_assembly *a, int mr)
{
    return a->sp && a->sp->sym && a->nb + 1 + mr == a->nf;
}

/* the values of J(xyz) with border rows b and R (mr = nbr - 1 columns) */
static void fill(const kin_assembly *a, const double *xyz, const double *b, const double *R)
{
    const struct kin_sparse *s = a->sp;
    int d = a->dim, nf = a->nf;
    for (int k = 0; k < a->nb; ++k) {
        int ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
        double v[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c < d; ++c) v[c] = xyz[ja * d + c] - xyz[jb * d + c];
        double L = kin__norm(d, v);
        const int *p = s->pos + (size_t)k * 2 * d;
        for (int c = 0; c < d; ++c) {
            if (p[c] >= 0) s->Ax[p[c]] = v[c] / L;
            if (p[d + c] >= 0) s->Ax[p[d + c]] = -v[c] / L;
        }
    }
    for (int j = 0; j < nf; ++j) {
        double *col = s->Ax + s->Ap[j + 1] - s->nbr;
        col[0] = b[j];
        for (int r = 1; r < s->nbr; ++r) col[r] = R[j + (size_t)(r - 1) * nf];
    }
}

/* The nested-dissection order (METIS, through CHOLMOD) of the columns of J
 * for the pattern of C^T C (coordinates linked by a bar; the dense border
 * rows left out, as COLAMD leaves them out): Q receives nf entries. Returns
 * 1, or 0 when CHOLMOD/METIS gives no order (the caller keeps COLAMD's). */
static int nd_order(const kin_assembly *a, int *Q)
{
    int nf = a->nf, nb = a->nb, d = a->dim;
    cholmod_common cc;
    cholmod_start(&cc);
    cc.print = 0;
    cc.error_handler = NULL;
    int ok = 0;
    /* C^T: nf rows, one column per bar holding the free coordinates of its ends */
    cholmod_sparse *A = cholmod_allocate_sparse((size_t)nf, (size_t)nb, (size_t)nb * 2 * (size_t)d, 0, 1, 0,
                                                CHOLMOD_PATTERN, &cc);
    if (A) {
        int *Cp = A->p, *Ci = A->i, nz = 0;
        for (int k = 0; k < nb; ++k) {
            Cp[k] = nz;
            for (int e = 0; e < 2; ++e)
                for (int c = 0; c < d; ++c) {
                    int col = a->free_index[a->bars[2 * k + e] * d + c];
                    if (col >= 0) Ci[nz++] = col;
                }
        }
        Cp[nb] = nz;
        /* orders A A^T = C^T C */
        ok = cholmod_metis(A, NULL, 0, 1, Q, &cc) && cc.status == CHOLMOD_OK;
        cholmod_free_sparse(&A, &cc);
    }
    cholmod_finish(&cc);
    return ok;
}

/* entries of the L and U factors */
static double factor_entries(const klu_numeric *num) { return num ? (double)num->lnz + (double)num->unz : INFINITY; }

int kin__sparse_prepare(kin_assembly *a)
{
    if (a->sp) return KIN_OK;
    int nf = a->nf, nb = a->nb, d = a->dim, nbr = nf - nb;
    if (nbr < 1 || nbr > 1 + a->nrig) return KIN_OK; /* J is never square: the dense routes */
    struct kin_sparse *s = calloc(1, sizeof *s);
    if (!s) return kin__fail(a, KIN_ENOMEM, "sparse mode: handle");
    a->sp = s;
    s->n = nf;
    s->nbr = nbr;
    size_t npos = (size_t)nb * 2 * (size_t)d;
    s->Ap = calloc((size_t)nf + 1, sizeof *s->Ap);
    s->pos = malloc(npos * sizeof *s->pos);
    if (!s->Ap || !s->pos) goto nomem;
    /* count: every free end of a bar, plus the border rows of each column */
    for (int k = 0; k < nb; ++k)
        for (int e = 0; e < 2; ++e)
            for (int c = 0; c < d; ++c) {
                int col = a->free_index[a->bars[2 * k + e] * d + c];
                if (col >= 0) s->Ap[col + 1]++;
            }
    for (int j = 0; j < nf; ++j) s->Ap[j + 1] += s->Ap[j] + nbr;
    size_t nnz = (size_t)s->Ap[nf];
    s->Ai = malloc(nnz * sizeof *s->Ai);
    s->Ax = calloc(nnz, sizeof *s->Ax);
    int *next = malloc((size_t)nf * sizeof *next);
    if (!s->Ai || !s->Ax || !next) {
        free(next);
        goto nomem;
    }
    memcpy(next, s->Ap, (size_t)nf * sizeof *next);
    for (int k = 0; k < nb; ++k) /* ascending k: sorted bar rows in every column */
        for (int e = 0; e < 2; ++e)
            for (int c = 0; c < d; ++c) {
                int col = a->free_index[a->bars[2 * k + e] * d + c];
                size_t at = (size_t)k * 2 * d + (size_t)e * d + c;
                s->pos[at] = col >= 0 ? next[col] : -1;
                if (col >= 0) s->Ai[next[col]++] = k;
            }
    for (int j = 0; j < nf; ++j)
        for (int r = 0; r < nbr; ++r) s->Ai[next[j]++] = nb + r;
    free(next);
    klu_defaults(&s->common);
    s->common.halt_if_singular = 1;
    /* COLAMD orders the columns for any row pivoting (J's pattern is
     * unsymmetric: AMD on J + J^T, KLU's default, made 2-3 times the fill),
     * no BTF (the dense rows make J one irreducible block; its matching
     * only perturbed the order), strict partial pivoting (the default
     * threshold 0.001 left pivot growths of 1e-6..1e-15 on the sails, and
     * klu_refactor's reuse of such an order failed). Measured on
     * sail:24:14 (1045 free coordinates): factors of 1.1e5 entries, every
     * refactorization kept, 12 ms per step against 55 ms with the
     * defaults. */
    s->common.ordering = 1;
    s->common.btf = 0;
    s->common.tol = 1.0;
    s->sym = a->fault == KIN__FAULT_SPARSE_NOMEM ? NULL : klu_analyze(nf, s->Ap, s->Ai, &s->common);
    if (!s->sym) {
        int st = s->common.status;
        kin__sparse_free(a);
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU symbolic analysis failed (status %d)", st);
    }
    /* first numeric factorizations, with pseudo-random border rows: they
     * fix a pivot order (and allocate the factors) outside the stepping
     * loop; a structurally singular J leaves the slots empty (every point
     * then pivots afresh or falls back, as a singular J does) */
    double *border = malloc((size_t)nf * (size_t)nbr * sizeof *border);
    int *Q = malloc((size_t)nf * sizeof *Q);
    if (!border || !Q) {
        free(border);
        free(Q);
        goto nomem;
    }
    unsigned long long seed = FIRST_BORDER_SEED;
    for (size_t i = 0; i < (size_t)nf * (size_t)nbr; ++i)
        border[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53 - 0.5;
    fill(a, a->xyz, border, border + nf);
    free(border);
    s->num[0] = klu_factor(s->Ap, s->Ai, s->Ax, s->sym, &s->common);
    if (!s->num[0] && s->common.status == KLU_OUT_OF_MEMORY) {
        free(Q);
        goto nomem;
    }
    /* The column order: COLAMD (minimum degree) suits small and nearly
     * one-dimensional structures, nested dissection (METIS) large 2D and 3D
     * ones, where COLAMD's factors fill in (the 13^3 lattice block: 19 % of
     * a dense matrix). Rather than guess from the shape, both are tried on
     * the same matrix, once per handle, and the one with the fewer factor
     * entries is kept (a second analysis and factorization at creation of
     * the mode, none in the stepping loop). */
    s->entries[0] = factor_entries(s->num[0]);
    s->entries[1] = INFINITY;
    if (a->fault != KIN__FAULT_SPARSE_NO_ND && nd_order(a, Q)) {
        klu_symbolic *sym = klu_analyze_given(nf, s->Ap, s->Ai, NULL, Q, &s->common);
        klu_numeric *num = sym ? klu_factor(s->Ap, s->Ai, s->Ax, sym, &s->common) : NULL;
        s->entries[1] = factor_entries(num);
        if (num && s->entries[1] < s->entries[0]) {
            if (s->num[0]) klu_free_numeric(&s->num[0], &s->common);
            klu_free_symbolic(&s->sym, &s->common);
            s->sym = sym;
            s->num[0] = num;
            s->nested_dissection = 1;
        } else {
            if (num) klu_free_numeric(&num, &s->common);
            if (sym) klu_free_symbolic(&sym, &s->common);
        }
    }
    free(Q);
    s->num[1] = klu_factor(s->Ap, s->Ai, s->Ax, s->sym, &s->common);
    if (!s->num[1] && s->common.status == KLU_OUT_OF_MEMORY) goto nomem;
    return KIN_OK;
nomem:
    kin__sparse_free(a);
    return kin__fail(a, KIN_ENOMEM, "sparse mode: workspace for %d free coordinates", nf);
}

int kin__sparse_factor(kin_assembly *a, int slot, const double *xyz, const double *b, const double *R,
                       int mr, int *singular)
{
    struct kin_sparse *s = a->sp;
    *singular = 0;
    if (!kin__sparse_usable(a, mr)) return kin__fail(a, KIN_ESTATE, "sparse mode: J is not square here");
    fill(a, xyz, b, R);
    a->nfact++;
    int ok = 0;
    if (a->fault == KIN__FAULT_SPARSE_SINGULAR) {
        *singular = 1; /* test hook: as klu_factor on a singular J */
        return KIN_OK;
    }
    if (a->fault == KIN__FAULT_SPARSE_FACTOR_NOMEM)
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU factorization failed (test fault)");
    if (s->num[slot]) {
        ok = a->fault != KIN__FAULT_SPARSE_REPIVOT &&
             klu_refactor(s->Ap, s->Ai, s->Ax, s->sym, s->num[slot], &s->common) && s->common.status == KLU_OK &&
             klu_rgrowth(s->Ap, s->Ai, s->Ax, s->sym, s->num[slot], &s->common) &&
             s->common.rgrowth >= RGROWTH_MIN;
        if (!ok) klu_free_numeric(&s->num[slot], &s->common);
    }
    if (!ok) {
        s->num[slot] = klu_factor(s->Ap, s->Ai, s->Ax, s->sym, &s->common);
        if (!s->num[slot]) {
            if (s->common.status == KLU_SINGULAR) {
                *singular = 1;
                return KIN_OK;
            }
            return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU factorization failed (status %d)", s->common.status);
        }
    }
    return KIN_OK;
}

int kin__sparse_solve(kin_assembly *a, int slot, int trans, double *v)
{
    struct kin_sparse *s = a->sp;
    if (!s || !s->num[slot]) return kin__fail(a, KIN_ESTATE, "sparse mode: no factors in slot %d", slot);
    int ok = trans ? klu_tsolve(s->sym, s->num[slot], s->n, 1, v, &s->common)
                   : klu_solve(s->sym, s->num[slot], s->n, 1, v, &s->common);
    if (!ok) return kin__fail(a, KIN_ESTATE, "sparse mode: KLU solve failed (status %d)", s->common.status);
    return KIN_OK;
}

int kin__sparse_order(const kin_assembly *a, double *entries_colamd, double *entries_nd)
{
    const struct kin_sparse *s = a ? a->sp : NULL;
    *entries_colamd = s ? s->entries[0] : INFINITY;
    *entries_nd = s ? s->entries[1] : INFINITY;
    return s ? s->nested_dissection : 0;
}

void kin__sparse_C(const kin_assembly *a, const double *x, double *y)
{
    const struct kin_sparse *s = a->sp;
    for (int k = 0; k < a->nb; ++k) y[k] = 0.0;
    for (int j = 0; j < s->n; ++j)
        for (int p = s->Ap[j]; p < s->Ap[j + 1] - s->nbr; ++p) y[s->Ai[p]] += s->Ax[p] * x[j];
}

void kin__sparse_CT(const kin_assembly *a, const double *y, double *x)
{
    const struct kin_sparse *s = a->sp;
    for (int j = 0; j < s->n; ++j) {
        double v = 0.0;
        for (int p = s->Ap[j]; p < s->Ap[j + 1] - s->nbr; ++p) v += s->Ax[p] * y[s->Ai[p]];
        x[j] = v;
    }
}
