/* KIN_STEP_SPARSE: the square bordered matrix J = [C; b^T; R^T] of a point
 * (C: nb x nf, at most 2 * dim entries per row; b^T, R^T: 1 + m_rigid DENSE
 * border rows), solved through SuiteSparse KLU. This file: J's pattern
 * and the set-up (first stand-ins, column order, first factorizations);
 * sparse_matrix.c: J's values and the products with C; sparse_border.c:
 * the stand-ins' re-choice, the factorizations and the solves.
 *
 * Bordering: KLU factorizes J0 = [C; e_k1^T; ...], J with each dense border
 * row replaced by a unit row at a "stand-in" coordinate, and solves with the
 * true J by the Sherman-Morrison-Woodbury correction of the rank-nbr
 * difference J - J0 = sum_r e_(nb+r) (w_r - e_kr)^T (w_r: border row r):
 * per factorization nbr extra solves give Z = J0^-1 [e_nb ...] (a basis of
 * null(C), Z[k_s, r] = delta_rs) and the nbr x nbr capacitance
 * S = I + V^T Z (V = [w_r - e_kr]); each solve with J (or J^T) is then one
 * solve with J0 (J0^T) plus O(nbr * nf). Why: a dense row makes J^T J full,
 * and partial pivoting fills the factors of slender 3D structures (masts)
 * super-linearly (measured: 70-1230 entries per column growing with n)
 * where C with a sparse row factors in linear fill (12-13 entries per
 * column; docs/performance.md, "deployable masts"). Measured with the
 * bordering: the masts' step grows as n^1.0 (8-12 ms at 10^4 coordinates,
 * 30-159 ms with the dense row), the 10^4 lattice block's factors hold 9x
 * fewer entries and its step is 14-17x faster, the sails' 2-2.5x.
 *
 * The stand-in coordinates are chosen by complete pivoting on a basis of
 * null(C) (at set-up: from a factorization of J with pseudo-random border
 * rows), so J0 is as well conditioned as C's null space allows and the
 * entries of Z stay near 1. Their pattern is part of the symbolic analysis,
 * so they are kept along the path and re-chosen (new analysis, with the
 * column order kept at set-up; allocates) only when a factorization shows
 * they went bad: J0 singular, or an entry of Z above ZGROWTH_MAX (the
 * null space moved away from the stand-ins: re-chosen from Z itself). Each
 * lu[] slot has its own stand-in pattern, so a re-choice never disturbs the
 * other slot's factors, which may still be in use. Where J0 is singular, or
 * the capacitance is ill-conditioned (equilibrated reciprocal condition
 * below RCOND_MIN: the border rows nearly miss null(C), so J itself is
 * nearly singular), that point is factorized with the dense rows in the
 * matrix, the scheme used before the bordering (COLAMD ignores dense rows
 * when ordering, partial pivoting takes them where needed), and the
 * stand-in is re-chosen from J's null basis; a J singular to KLU is
 * reported singular as before. Either way the solve is with the true J.
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

#include "model/internal.h"
#include "path/sparse_internal.h"

/* Seed of the pseudo-random border rows of the first factorization (any
 * fixed value: runs are repeatable). */
static const unsigned long long FIRST_BORDER_SEED = 0xb0dea5ULL;

static void free_slot(struct kin_sparse *s, struct kin_slot *sl)
{
    if (sl->num) klu_free_numeric(&sl->num, &s->common);
    if (sl->dnum) klu_free_numeric(&sl->dnum, &s->common);
    if (sl->sym) klu_free_symbolic(&sl->sym, &s->common);
    free(sl->Ap);
    free(sl->Ai);
    free(sl->Ax);
    free(sl->k);
    free(sl->W);
    free(sl->Z);
    free(sl->S);
    free(sl->piv);
}

void kin__sparse_free(kin_assembly *a)
{
    if (!a || !a->sp) return;
    struct kin_sparse *s = a->sp;
    for (int f = 0; f < 2; ++f) free_slot(s, &s->slot[f]);
    if (s->dsym) klu_free_symbolic(&s->dsym, &s->common);
    free(s->Ap);
    free(s->Ai);
    free(s->Ax);
    free(s->pos);
    free(s->Q);
    free(s->k);
    free(s->B);
    free(s->h);
    free(s);
    a->sp = NULL;
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

/* the slot's arrays; KIN_OK or KIN_ENOMEM (the caller frees) */
static int alloc_slot(struct kin_sparse *s, struct kin_slot *sl, size_t nnz0)
{
    size_t n = (size_t)s->n, nbr = (size_t)s->nbr;
    sl->Ap = malloc((n + 1) * sizeof *sl->Ap);
    sl->Ai = malloc(nnz0 * sizeof *sl->Ai);
    sl->Ax = calloc(nnz0, sizeof *sl->Ax);
    sl->k = malloc(nbr * sizeof *sl->k);
    sl->W = calloc(n * nbr, sizeof *sl->W);
    sl->Z = calloc(n * nbr, sizeof *sl->Z);
    sl->S = calloc(nbr * nbr, sizeof *sl->S);
    sl->piv = calloc(nbr, sizeof *sl->piv);
    sl->gen = -1;
    return sl->Ap && sl->Ai && sl->Ax && sl->k && sl->W && sl->Z && sl->S && sl->piv ? KIN_OK : KIN_ENOMEM;
}

int kin__sparse_prepare(kin_assembly *a)
{
    if (a->sp) return KIN_OK;
    int nf = a->nf, nb = a->nb, d = a->dim, nbr = nf - nb;
    if (nbr < 1 || nbr > 1 + a->nrig) return KIN_OK; /* J is never square: the dense routes */
    struct kin_sparse *s = calloc(1, sizeof *s);
    if (!s) return kin__fail(a, KIN_ENOMEM, "sparse mode: handle");
    a->sp = s;
    a->sp_free = kin__sparse_free;
    a->sp_prepare = kin__sparse_prepare;
    s->n = nf;
    s->nb = nb;
    s->nbr = nbr;
    size_t npos = (size_t)nb * 2 * (size_t)d;
    s->Ap = calloc((size_t)nf + 1, sizeof *s->Ap);
    s->pos = malloc(npos * sizeof *s->pos);
    s->Q = malloc((size_t)nf * sizeof *s->Q);
    s->k = malloc((size_t)nbr * sizeof *s->k);
    s->B = malloc((size_t)nf * (size_t)nbr * sizeof *s->B);
    s->h = malloc((size_t)nbr * (size_t)(nbr + 2) * sizeof *s->h);
    if (!s->Ap || !s->pos || !s->Q || !s->k || !s->B || !s->h) goto nomem;
    /* count: every free end of a bar, plus the border rows of each column */
    for (int k = 0; k < nb; ++k)
        for (int e = 0; e < 2; ++e)
            for (int c = 0; c < d; ++c) {
                int col = a->free_index[a->bars[2 * k + e] * d + c];
                if (col >= 0) s->Ap[col + 1]++;
            }
    for (int j = 0; j < nf; ++j) s->Ap[j + 1] += s->Ap[j] + nbr;
    size_t nnz = (size_t)s->Ap[nf], nnz0 = nnz - (size_t)nf * nbr + (size_t)nbr;
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
    for (int f = 0; f < 2; ++f)
        if (alloc_slot(s, &s->slot[f], nnz0)) goto nomem;
    klu_defaults(&s->common);
    s->common.halt_if_singular = 1;
    /* COLAMD orders the columns for any row pivoting (J's pattern is
     * unsymmetric: AMD on J + J^T, KLU's default, made 2-3 times the fill),
     * no BTF (the dense rows make J one irreducible block; its matching
     * only perturbed the order), strict partial pivoting (the default
     * threshold 0.001 left pivot growths of 1e-6..1e-15 on the sails, and
     * klu_refactor's reuse of such an order failed). Measured on
     * sail:24:14 (1045 free coordinates), before the bordering: factors of
     * 1.1e5 entries, every refactorization kept, 12 ms per step against
     * 55 ms with the defaults. */
    s->common.ordering = 1;
    s->common.btf = 0;
    s->common.tol = 1.0;
    /* The column order: COLAMD (minimum degree) suits small and nearly
     * one-dimensional structures, nested dissection (METIS) large 2D and 3D
     * ones, where COLAMD's factors fill in (the 13^3 lattice block: 19 % of
     * a dense matrix). Rather than guess from the shape, both are tried on
     * the same matrix J0, once per handle, and the one with the fewer
     * factor entries is kept (no cost in the stepping loop). */
    int *Qnd = malloc((size_t)nf * sizeof *Qnd);
    double *border = malloc((size_t)nf * (size_t)nbr * sizeof *border);
    if (!Qnd || !border) {
        free(Qnd);
        free(border);
        goto nomem;
    }
    int have_nd = a->fault != KIN__FAULT_SPARSE_NO_ND && nd_order(a, Qnd);
    /* J with its dense rows (the fallback): analysed with nested dissection
     * where METIS gives an order (fewer entries on large structures) */
    if (a->fault != KIN__FAULT_SPARSE_NOMEM)
        s->dsym = have_nd ? klu_analyze_given(nf, s->Ap, s->Ai, NULL, Qnd, &s->common)
                          : klu_analyze(nf, s->Ap, s->Ai, &s->common);
    if (!s->dsym) {
        int st = s->common.status;
        free(Qnd);
        free(border);
        kin__sparse_free(a);
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU symbolic analysis failed (status %d)", st);
    }
    /* the first stand-ins: from null(C) at the current configuration, the
     * last columns of the inverse of J with pseudo-random border rows (the
     * one factorization with the dense rows at set-up); a structurally
     * singular J leaves the slots empty (every point then pivots afresh or
     * falls back, as a singular J does) */
    unsigned long long seed = FIRST_BORDER_SEED;
    for (size_t i = 0; i < (size_t)nf * (size_t)nbr; ++i)
        border[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53 - 0.5;
    kin__sparse_fill(a, a->xyz, border, border + nf);
    klu_numeric *dnum = klu_factor(s->Ap, s->Ai, s->Ax, s->dsym, &s->common);
    s->entries_dense = factor_entries(dnum);
    int rc = KIN_OK;
    if (dnum) {
        rc = kin__standin_from_dense(a, dnum);
        klu_free_numeric(&dnum, &s->common);
    } else if (s->common.status == KLU_OUT_OF_MEMORY) {
        rc = KIN_ENOMEM;
    } else {
        memcpy(s->B, border, sizeof(double) * (size_t)nf * (size_t)nbr);
        kin__standin_choose(s, s->B);
    }
    free(border);
    if (rc) {
        free(Qnd);
        goto nomem;
    }
    /* J0 under COLAMD and under nested dissection, the fewer entries kept */
    struct kin_slot *s0 = &s->slot[0];
    kin__standin_pattern(s, s0);
    kin__standin_values(s, s0);
    s0->sym = klu_analyze(nf, s0->Ap, s0->Ai, &s->common);
    if (!s0->sym) {
        free(Qnd);
        goto nomem;
    }
    s0->num = klu_factor(s0->Ap, s0->Ai, s0->Ax, s0->sym, &s->common);
    if (!s0->num && s->common.status == KLU_OUT_OF_MEMORY) {
        free(Qnd);
        goto nomem;
    }
    s->entries[0] = factor_entries(s0->num);
    s->entries[1] = INFINITY;
    memcpy(s->Q, s0->sym->Q, sizeof(int) * (size_t)nf);
    if (have_nd) {
        klu_symbolic *sym = klu_analyze_given(nf, s0->Ap, s0->Ai, NULL, Qnd, &s->common);
        klu_numeric *num = sym ? klu_factor(s0->Ap, s0->Ai, s0->Ax, sym, &s->common) : NULL;
        s->entries[1] = factor_entries(num);
        if (num && s->entries[1] < s->entries[0]) {
            if (s0->num) klu_free_numeric(&s0->num, &s->common);
            klu_free_symbolic(&s0->sym, &s->common);
            s0->sym = sym;
            s0->num = num;
            s->nested_dissection = 1;
            memcpy(s->Q, Qnd, sizeof(int) * (size_t)nf);
        } else {
            if (num) klu_free_numeric(&num, &s->common);
            if (sym) klu_free_symbolic(&sym, &s->common);
        }
    }
    free(Qnd);
    struct kin_slot *s1 = &s->slot[1];
    if (kin__standin_analyse(a, s1)) goto nomem;
    kin__standin_values(s, s1);
    s1->num = klu_factor(s1->Ap, s1->Ai, s1->Ax, s1->sym, &s->common);
    if (!s1->num && s->common.status == KLU_OUT_OF_MEMORY) goto nomem;
    return KIN_OK;
nomem:
    kin__sparse_free(a);
    return kin__fail(a, KIN_ENOMEM, "sparse mode: workspace for %d free coordinates", nf);
}

int kin__sparse_order(const kin_assembly *a, double *entries_colamd, double *entries_nd)
{
    const struct kin_sparse *s = a ? a->sp : NULL;
    *entries_colamd = s ? s->entries[0] : INFINITY;
    *entries_nd = s ? s->entries[1] : INFINITY;
    return s ? s->nested_dissection : 0;
}

void kin__sparse_stats(const kin_assembly *a, double *entries, double *entries_dense, long *rechoices,
                       long *dense_points)
{
    const struct kin_sparse *s = a ? a->sp : NULL;
    *entries = s ? fmin(s->entries[0], s->entries[1]) : INFINITY;
    *entries_dense = s ? s->entries_dense : INFINITY;
    *rechoices = s ? s->rechoices : 0;
    *dense_points = s ? s->dense_points : 0;
}


