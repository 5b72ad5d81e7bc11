/* KIN_STEP_SPARSE: the square bordered matrix J = [C; b^T; R^T] of a point
 * (C: nb x nf, at most 2 * dim entries per row; b^T, R^T: 1 + m_rigid DENSE
 * border rows), solved through SuiteSparse KLU.
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
 * column; docs/performance.md, "deployable masts").
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

#include "internal.h"
#include "lapack.h"

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
/* Seed of the pseudo-random border rows of the first factorization (any
 * fixed value: runs are repeatable). */
static const unsigned long long FIRST_BORDER_SEED = 0xb0dea5ULL;

/* one lu[] slot's factors */
struct kin_slot {
    int *Ap, *Ai;         /* J0 = [C; stand-in rows] in compressed columns */
    double *Ax;
    int *k;               /* its stand-in coordinates (nbr) */
    int gen;              /* the stand-in generation its pattern was built for */
    klu_symbolic *sym;    /* J0's analysis (the kept column order) */
    klu_numeric *num;     /* J0's factors */
    klu_numeric *dnum;    /* J's factors with the dense rows, where J0 failed */
    int dense;            /* the last factorization is dnum's */
    double *W;            /* nf x nbr: the true border rows [b, R] */
    double *Z;            /* nf x nbr: J0^-1 [e_nb ... e_(nf-1)] */
    double *S;            /* nbr x nbr: LU of the capacitance (dgetrf) */
    int *piv;             /* its pivots */
};

struct kin_sparse {
    int n;       /* nf: J is n x n */
    int nb;      /* bar rows */
    int nbr;     /* border rows: n - nb (1 + m_rigid) */
    int *Ap;     /* J with its dense rows: n + 1 column pointers */
    int *Ai;     /* row indices: bar rows ascending, then the border rows nb..n-1 */
    double *Ax;  /* values of the last factorization */
    int *pos;    /* nb * 2 * dim: Ax index of bar k, end e, axis c (or -1: fixed) */
    int *Q;      /* the kept column order (n) */
    int *k;      /* the current stand-in coordinates (nbr) */
    int gen;     /* their generation: +1 at every re-choice */
    klu_common common;
    klu_symbolic *dsym;    /* J with its dense rows: analysis made at set-up */
    struct kin_slot slot[2];
    double *B;             /* nf x nbr scratch: the basis the stand-ins are chosen from */
    double *h;             /* nbr * (nbr + 1) scratch */
    int nested_dissection; /* the column order is METIS's (1) or COLAMD's (0) */
    double entries[2];     /* J0's factor entries at set-up: COLAMD, METIS */
    double entries_dense;  /* J's (dense rows) at set-up */
    long rechoices;        /* stand-in re-choices since set-up */
    long dense_points;     /* factorizations made with the dense rows since set-up */
};

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

int kin__sparse_usable(const kin_assembly *a, int mr)
{
    return a->sp && a->sp->dsym && a->nb + 1 + mr == a->nf;
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

/* Choose the stand-in coordinates s->k from the basis B (nf x nbr, ld nf;
 * overwritten) by complete pivoting: the largest entry left, its column
 * eliminated from the others. The chosen rows of a basis of null(C) are then
 * a well-conditioned nbr x nbr block, which is what makes J0 regular and
 * Z's entries small. Bumps the generation: each slot re-analyses at its
 * next factorization. */
static void choose_standins(struct kin_sparse *s, double *B)
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
static void build_standin_pattern(struct kin_sparse *s, struct kin_slot *sl)
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

/* J0's values: C's from the last fill(), 1 in the stand-in rows */
static void fill_standin(const struct kin_sparse *s, struct kin_slot *sl)
{
    for (int j = 0; j < s->n; ++j) {
        int c = s->Ap[j + 1] - s->nbr - s->Ap[j];
        memcpy(sl->Ax + sl->Ap[j], s->Ax + s->Ap[j], sizeof(double) * (size_t)c);
        for (int p = sl->Ap[j] + c; p < sl->Ap[j + 1]; ++p) sl->Ax[p] = 1.0;
    }
}

/* New pattern and analysis of slot sl for the current stand-ins (the kept
 * column order; allocates). KIN_OK or KIN_ENOMEM. */
static int analyse_slot(kin_assembly *a, struct kin_slot *sl)
{
    struct kin_sparse *s = a->sp;
    if (sl->num) klu_free_numeric(&sl->num, &s->common);
    if (sl->sym) klu_free_symbolic(&sl->sym, &s->common);
    build_standin_pattern(s, sl);
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
    fill_standin(s, sl);
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
static int rechoose_from_dense(kin_assembly *a, klu_numeric *num)
{
    struct kin_sparse *s = a->sp;
    int n = s->n, nbr = s->nbr;
    memset(s->B, 0, sizeof(double) * (size_t)n * (size_t)nbr);
    for (int r = 0; r < nbr; ++r) s->B[s->nb + r + (size_t)r * n] = 1.0;
    if (!klu_solve(s->dsym, num, n, nbr, s->B, &s->common))
        return kin__fail(a, KIN_ENOMEM, "sparse mode: KLU solve failed (status %d)", s->common.status);
    choose_standins(s, s->B);
    return KIN_OK;
}

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
    fill(a, a->xyz, border, border + nf);
    klu_numeric *dnum = klu_factor(s->Ap, s->Ai, s->Ax, s->dsym, &s->common);
    s->entries_dense = factor_entries(dnum);
    int rc = KIN_OK;
    if (dnum) {
        rc = rechoose_from_dense(a, dnum);
        klu_free_numeric(&dnum, &s->common);
    } else if (s->common.status == KLU_OUT_OF_MEMORY) {
        rc = KIN_ENOMEM;
    } else {
        memcpy(s->B, border, sizeof(double) * (size_t)nf * (size_t)nbr);
        choose_standins(s, s->B);
    }
    free(border);
    if (rc) {
        free(Qnd);
        goto nomem;
    }
    /* J0 under COLAMD and under nested dissection, the fewer entries kept */
    struct kin_slot *s0 = &s->slot[0];
    build_standin_pattern(s, s0);
    fill_standin(s, s0);
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
    if (analyse_slot(a, s1)) goto nomem;
    fill_standin(s, s1);
    s1->num = klu_factor(s1->Ap, s1->Ai, s1->Ax, s1->sym, &s->common);
    if (!s1->num && s->common.status == KLU_OUT_OF_MEMORY) goto nomem;
    return KIN_OK;
nomem:
    kin__sparse_free(a);
    return kin__fail(a, KIN_ENOMEM, "sparse mode: workspace for %d free coordinates", nf);
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
    fill(a, xyz, b, R);
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
    if (sl->gen != s->gen && (rc = analyse_slot(a, sl)) != KIN_OK) return rc;
    int st = factor_standin(a, sl);
    if (st == STANDIN_GROWTH) {
        /* null(C) has moved away from the stand-ins: re-choose from Z */
        memcpy(s->B, sl->Z, sizeof(double) * (size_t)n * (size_t)s->nbr);
        choose_standins(s, s->B);
        s->rechoices++;
        if ((rc = analyse_slot(a, sl)) != KIN_OK) return rc;
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
    if ((rc = rechoose_from_dense(a, sl->dnum)) != KIN_OK) return rc;
    s->rechoices++;
    if ((rc = analyse_slot(a, sl)) != KIN_OK) return rc;
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
