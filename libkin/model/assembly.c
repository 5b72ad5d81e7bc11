/* The assembly handle: validation, workspace, getters, geometry. */
#define _POSIX_C_SOURCE 200809L /* sysconf */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "model/internal.h"
#include "model/lapack.h"

/* ---- small helpers --------------------------------------------------- */

double kin__dot(int n, const double *x, const double *y)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += x[i] * y[i];
    return s;
}

double kin__norm(int n, const double *x)
{
    /* scaled to avoid overflow/underflow, like BLAS dnrm2 */
    double scale = 0.0, ssq = 1.0;
    for (int i = 0; i < n; ++i) {
        double v = fabs(x[i]);
        if (v == 0.0) continue;
        if (scale < v) {
            ssq = 1.0 + ssq * (scale / v) * (scale / v);
            scale = v;
        } else {
            ssq += (v / scale) * (v / scale);
        }
    }
    return scale * sqrt(ssq);
}

void kin__gather(const kin_assembly *a, const double *xyz, double *x)
{
    for (int i = 0; i < a->nf; ++i) x[i] = xyz[a->free_coord[i]];
}

void kin__scatter(const kin_assembly *a, const double *x, double *xyz)
{
    for (int i = 0; i < a->nf; ++i) xyz[a->free_coord[i]] = x[i];
}

static double bar_length(const kin_assembly *a, const double *xyz, int k)
{
    const double *pa = xyz + a->bars[2 * k] * a->dim, *pb = xyz + a->bars[2 * k + 1] * a->dim;
    double v[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < a->dim; ++c) v[c] = pa[c] - pb[c];
    return kin__norm(a->dim, v);
}

double kin__lengths(const kin_assembly *a, const double *xyz, double *len)
{
    double worst = 0.0;
    for (int k = 0; k < a->nb; ++k) {
        double L = bar_length(a, xyz, k);
        double r = fabs(L - a->L0[k]) / a->L0[k];
        if (len) len[k] = L;
        if (!(r <= worst)) worst = r; /* propagates NaN */
    }
    return worst;
}

/* Error-free transformations: a + b = s + t and a * b = p + q exactly
 * (Knuth's TwoSum; the product's error from fma, which C99 rounds once). */
static inline void two_sum(double a, double b, double *s, double *t)
{
    double x = a + b, z = x - a;
    *s = x;
    *t = (a - (x - z)) + (b - z);
}

static inline void two_prod(double a, double b, double *p, double *q)
{
    double x = a * b;
    *p = x;
    *q = fma(a, b, -x);
}

/* (hi, lo) += (a, b), double-double */
static inline void dd_add(double *hi, double *lo, double a, double b)
{
    double s, t;
    two_sum(*hi, a, &s, &t);
    t += *lo + b;
    two_sum(s, t, hi, lo);
}

/* The extensions are the corrector's residual, evaluated at every
 * iteration of every step (10% of a cheap follow on the hexagonal flat
 * state, most of it in libm's fma called through the PLT: the x86-64
 * baseline has no FMA instruction). A clone for CPUs with FMA makes each
 * fma one instruction; fma rounds once on either path, and the file is
 * built with -ffp-contract=off, so both clones give the same bits. Static
 * and called through the plain function below (homotopy_control.h: Clang
 * before 18 dispatches clones only from their own file). */
#if defined(__x86_64__) && defined(__ELF__) && defined(__has_attribute) && !defined(KIN_NO_MULTIVERSION)
#if __has_attribute(target_clones)
#define EXT_KERNEL __attribute__((target_clones("fma", "default")))
#endif
#endif
#ifndef EXT_KERNEL
#define EXT_KERNEL
#endif

EXT_KERNEL static double extensions_kernel(const kin_assembly *a, const double *xyz, double *e)
{
    /* e = L - L0 = (L^2 - L0^2) / (L + L0), with L^2 - L0^2 formed in
     * double-double from the exact coordinate differences: e is then
     * accurate to a few ulps of itself, not of L. Near a bifurcation a
     * corrector fixes a point only to |e| / v_min; rounding e at eps * L
     * would cap that at eps * L / v_min. */
    double worst = 0.0;
    for (int k = 0; k < a->nb; ++k) {
        const double *pa = xyz + a->bars[2 * k] * a->dim;
        const double *pb = xyz + a->bars[2 * k + 1] * a->dim;
        double L0 = a->L0[k], hi, lo;
        two_prod(L0, L0, &hi, &lo);
        hi = -hi;
        lo = -lo;
        double L2 = 0.0;
        for (int c = 0; c < a->dim; ++c) {
            double dh, dl, p, q;
            two_sum(pa[c], -pb[c], &dh, &dl);
            two_prod(dh, dh, &p, &q);
            dd_add(&hi, &lo, p, q + 2.0 * dh * dl);
            L2 += (dh + dl) * (dh + dl);
        }
        double L = sqrt(L2);
        e[k] = (hi + lo) / (L + L0);
        double r = fabs(e[k]) / L0;
        if (!(r <= worst)) worst = r;
    }
    return worst;
}

/* The same strain in plain double: accurate to about eps x L, not to a few
 * ulps of e; for points where v_r is far from zero (a->plain_extensions:
 * the follower's cheap stretches), where that rounding moves a corrected
 * point by eps x L / v_r only (docs/follow.md, "Round 30"). */
EXT_KERNEL static double extensions_plain(const kin_assembly *a, const double *xyz, double *e)
{
    double worst = 0.0;
    for (int k = 0; k < a->nb; ++k) {
        const double *pa = xyz + a->bars[2 * k] * a->dim;
        const double *pb = xyz + a->bars[2 * k + 1] * a->dim;
        double L0 = a->L0[k], L2 = 0.0;
        for (int c = 0; c < a->dim; ++c) {
            double d = pa[c] - pb[c];
            L2 += d * d;
        }
        double L = sqrt(L2);
        e[k] = (L2 - L0 * L0) / (L + L0);
        double r = fabs(e[k]) / L0;
        if (!(r <= worst)) worst = r;
    }
    return worst;
}

double kin__extensions(const kin_assembly *a, const double *xyz, double *e)
{
    if (a->plain_extensions) return extensions_plain(a, xyz, e);
    return extensions_kernel(a, xyz, e);
}

void kin__build_H(const kin_assembly *a, const double *xyz, double *H, int ldh)
{
    for (int k = 0; k < a->nb; ++k) {
        double *col = H + (size_t)k * ldh;
        for (int i = 0; i < a->nf; ++i) col[i] = 0.0;
        int ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
        double L = bar_length(a, xyz, k);
        for (int c = 0; c < a->dim; ++c) {
            double dc = (xyz[ja * a->dim + c] - xyz[jb * a->dim + c]) / L;
            int ra = a->free_index[ja * a->dim + c], rb = a->free_index[jb * a->dim + c];
            if (ra >= 0) col[ra] += dc;
            if (rb >= 0) col[rb] -= dc;
        }
    }
}

int kin__check_bars(kin_assembly *a, const double *xyz)
{
    for (int k = 0; k < a->nb; ++k) {
        double L = bar_length(a, xyz, k);
        if (!(L > 0.0 && isfinite(L)))
            return kin__fail(a, KIN_EGEOM,
                             "bar %d (joints %d-%d) has length %g at this configuration: its direction, and "
                             "the equilibrium matrix, are undefined",
                             k, a->bars[2 * k], a->bars[2 * k + 1], L);
    }
    return KIN_OK;
}

/* ---- validation ------------------------------------------------------- */

static int cmp_pair(const void *p, const void *q)
{
    const int *x = p, *y = q;
    if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
    if (x[1] != y[1]) return x[1] < y[1] ? -1 : 1;
    return 0;
}

/* Geometry the library can square without overflow or underflow: eq. 12,
 * the extensions (L^2 - L0^2) / (L + L0) and the RMS length all square
 * lengths, so coordinates, rest lengths and bar lengths are kept where their
 * squares (times a few) are normal doubles. */
static const double COORD_MAX = 1e150;   /* largest |coordinate| */
static const double LENGTH_MAX = 1e151;  /* longest rest length (> any bar between valid joints) */
static const double LENGTH_MIN = 1e-150; /* shortest bar (initial or rest length) */

/* Joint count and bar count against the int indices used everywhere (checked
 * before any caller array is read: its size is only known from them). */
static int check_counts(int dim, int nj, int nb, char *eb, size_t el)
{
    if (nj > INT_MAX / dim)
        return kin__failbuf(eb, el, KIN_ERANGE, "njoints = %d: %d x %d coordinates exceed INT_MAX", nj, nj,
                       dim);
    if (nb > INT_MAX / 2)
        return kin__failbuf(eb, el, KIN_ERANGE, "nbars = %d: 2 x %d joint indices exceed INT_MAX", nb, nb);
    return KIN_OK;
}

/* |x| within COORD_MAX for every coordinate; the first offender named */
static int check_coords(int n, int dim, const double *xyz, char *eb, size_t el)
{
    for (int i = 0; i < n; ++i) {
        if (!isfinite(xyz[i]))
            return kin__failbuf(eb, el, KIN_EGEOM, "coordinate %d of joint %d is not finite", i % dim, i / dim);
        if (!(fabs(xyz[i]) <= COORD_MAX))
            return kin__failbuf(eb, el, KIN_EGEOM, "coordinate %d of joint %d is %g; |coordinate| must be <= %g",
                           i % dim, i / dim, xyz[i], COORD_MAX);
    }
    return KIN_OK;
}

/* length of the segment p-q (dim coordinates each), overflow-safe */
static double segment_length(int dim, const double *p, const double *q)
{
    double v[3] = {0.0, 0.0, 0.0};
    for (int c = 0; c < dim; ++c) v[c] = p[c] - q[c];
    return kin__norm(dim, v);
}

static int validate(int dim, int nj, const double *xyz, const unsigned char *fixed, int nb,
                    const int *bars, const double *rest, char *eb, size_t el)
{
    if (!xyz) return kin__failbuf(eb, el, KIN_ENULL, "xyz is NULL");
    if (!bars) return kin__failbuf(eb, el, KIN_ENULL, "bars is NULL");
    if (dim != 2 && dim != 3) return kin__failbuf(eb, el, KIN_EDIM, "dim = %d", dim);
    if (nj < 2) return kin__failbuf(eb, el, KIN_EINVAL, "njoints = %d, need at least 2", nj);
    if (nb < 1) return kin__failbuf(eb, el, KIN_EINVAL, "nbars = %d, need at least 1", nb);
    int rc = check_counts(dim, nj, nb, eb, el);
    if (rc) return rc;
    if ((rc = check_coords(nj * dim, dim, xyz, eb, el))) return rc;
    for (int k = 0; k < nb; ++k) {
        int p = bars[2 * k], q = bars[2 * k + 1];
        if (p < 0 || p >= nj || q < 0 || q >= nj)
            return kin__failbuf(eb, el, KIN_EJOINT, "bar %d joins joints %d and %d; valid are 0..%d", k,
                           p, q, nj - 1);
        if (p == q) return kin__failbuf(eb, el, KIN_ESELFBAR, "bar %d joins joint %d to itself", k, p);
        double L = segment_length(dim, xyz + (size_t)p * dim, xyz + (size_t)q * dim);
        if (!(L > 0.0))
            return kin__failbuf(eb, el, KIN_EGEOM, "bar %d (joints %d-%d) has zero length", k, p, q);
        if (!(L >= LENGTH_MIN))
            return kin__failbuf(eb, el, KIN_EGEOM, "bar %d (joints %d-%d) has length %g, below %g", k, p, q, L,
                           LENGTH_MIN);
        if (rest && !(isfinite(rest[k]) && rest[k] >= LENGTH_MIN && rest[k] <= LENGTH_MAX))
            return kin__failbuf(eb, el, KIN_EGEOM, "rest length of bar %d is %g; need finite, %g..%g", k,
                           rest[k], LENGTH_MIN, LENGTH_MAX);
    }
    int nf = 0;
    for (int i = 0; i < nj * dim; ++i) nf += !(fixed && fixed[i]);
    if (nf == 0) return kin__failbuf(eb, el, KIN_ENOFREE, "every coordinate is fixed");
    /* no limit from the dense matrices here: the sparse mode never makes
     * them (kin__dense_ready checks their sizes when they are needed) */
    /* duplicates: sort normalised pairs */
    size_t npair;
    int *pairs = kin__mul_size3(3, (size_t)nb, sizeof(int), &npair) ? malloc(npair) : NULL;
    if (!pairs) return kin__failbuf(eb, el, KIN_ENOMEM, "bar check");
    for (int k = 0; k < nb; ++k) {
        int p = bars[2 * k], q = bars[2 * k + 1];
        pairs[3 * (size_t)k] = p < q ? p : q;
        pairs[3 * (size_t)k + 1] = p < q ? q : p;
        pairs[3 * (size_t)k + 2] = k;
    }
    qsort(pairs, (size_t)nb, 3 * sizeof(int), cmp_pair);
    for (size_t k = 1; k < (size_t)nb; ++k)
        if (pairs[3 * k] == pairs[3 * k - 3] && pairs[3 * k + 1] == pairs[3 * k - 2]) {
            int b1 = pairs[3 * k - 1] < pairs[3 * k + 2] ? pairs[3 * k - 1] : pairs[3 * k + 2];
            int b2 = pairs[3 * k - 1] < pairs[3 * k + 2] ? pairs[3 * k + 2] : pairs[3 * k - 1];
            rc = kin__failbuf(eb, el, KIN_EDUPBAR, "bars %d and %d both join joints %d and %d", b1, b2,
                         pairs[3 * k], pairs[3 * k + 1]);
            break;
        }
    free(pairs);
    return rc;
}

/* ---- workspace ---------------------------------------------------------- */

/* The LU mode factorizes the bordered matrix J = [C; t^T; R^T] of a point
 * (nb + 1 + mr rows, nf columns, mr <= nrig the rigid mechanisms there) only
 * when it is square (LU) or tall (LQ of J^T): a point with fewer rows has at
 * least two internal mechanisms and is analysed by SVD instead. Whether a
 * route can ever apply follows from the sizes alone. */
static int lu_route(const kin_assembly *a)
{
    int extra = a->nf - a->nb - 1; /* the mr that makes J square */
    return extra >= 0 && extra <= a->nrig;
}

static int lq_route(const kin_assembly *a) { return a->nb + 1 + a->nrig > a->nf; }

static int query_lwork(kin_assembly *a, int *lwork, int *liwork)
{
    int nf = a->nf, nb = a->nb, info = 0, m1 = nb + 1, one = 1, ld;
    double w = 0.0, dummy = 0.0, rcond = -1.0;
    int iw = 0, rank = 0, q = -1;
    double best = 1.0;
    int ibest = 8 * (nf > nb + 1 ? nf : nb + 1);
    /* dgesdd and dgesvd, jobz = 'A', on H (nf x nb) */
    dgesdd_("A", &nf, &nb, &dummy, &nf, &dummy, &dummy, &nf, &dummy, &nb, &w, &q, &iw, &info, 1);
    if (info < 0) return KIN_ELAPACK_ARG;
    if (w > best) best = w;
    dgesvd_("A", "A", &nf, &nb, &dummy, &nf, &dummy, &dummy, &nf, &dummy, &nb, &w, &q, &info, 1, 1);
    if (info < 0) return KIN_ELAPACK_ARG;
    if (w > best) best = w;
    /* dgesvd on the fixed-coordinate rigid motions (nfix x nrig), jobvt = 'A' */
    {
        int mf = a->nfix > 0 ? a->nfix : 1, nr = a->nrig;
        dgesvd_("N", "A", &mf, &nr, &dummy, &mf, &dummy, &dummy, &one, &dummy, &nr, &w, &q, &info,
                1, 1);
        if (info < 0) return KIN_ELAPACK_ARG;
        if (w > best) best = w;
    }
    /* dgelsd on the bordered system ((nb+1) x nf) */
    ld = m1 > nf ? m1 : nf;
    dgelsd_(&m1, &nf, &one, &dummy, &m1, &dummy, &ld, &dummy, &rcond, &rank, &w, &q, &iw, &info);
    if (info < 0) return KIN_ELAPACK_ARG;
    if (w > best) best = w;
    if (iw > ibest) ibest = iw;
    /* dgels (QR/LQ) on the same bordered system */
    dgels_("N", &m1, &nf, &one, &dummy, &m1, &dummy, &ld, &w, &q, &info, 1);
    if (info < 0) return KIN_ELAPACK_ARG;
    if (w > best) best = w;
    /* LU mode with redundant bars: LQ of J^T = [H, t, R] (nf x rows) and Q
     * applied to one vector of length rows. That route is taken only when
     * rows = nb + 1 + m_rigid > nf for some m_rigid <= nrig; otherwise
     * (more free coordinates: several internal mechanisms) it never runs,
     * and dormlq would reject K = nf > M = rows. */
    if (lq_route(a)) {
        int rows = nb + 1 + a->nrig;
        dgelqf_(&nf, &rows, &dummy, &nf, &dummy, &w, &q, &info);
        if (info < 0) return KIN_ELAPACK_ARG;
        if (w > best) best = w;
        dormlq_("L", "N", &rows, &one, &nf, &dummy, &nf, &dummy, &dummy, &rows, &w, &q, &info, 1, 1);
        if (info < 0) return KIN_ELAPACK_ARG;
        if (w > best) best = w;
    }
    if (!(best < (double)INT_MAX - 1.0)) return KIN_ENOMEM; /* LAPACK counts workspace in int */
    *lwork = (int)best + 1;
    *liwork = ibest;
    return KIN_OK;
}

static void release(kin_assembly *a)
{
    if (!a) return;
    double **dp[] = {&a->xyz, &a->L0, &a->H, &a->A, &a->work, &a->G, &a->Gs, &a->sup_fix, &a->mwork, &a->B,
                     &a->rhs, &a->svB, &a->t, &a->x0, &a->x, &a->xp, &a->d, &a->y, &a->e,
                     &a->len, &a->chord, &a->xyz_trial, &a->Rref};
    for (size_t i = 0; i < sizeof dp / sizeof dp[0]; ++i) free(*dp[i]);
    for (int f = 0; f < 2; ++f) {
        free(a->fac[f].sv);
        free(a->fac[f].U);
        free(a->fac[f].VT);
        free(a->fac[f].Uint);
        free(a->fac[f].Urig);
    }
    free(a->fixed);
    free(a->bars);
    free(a->free_index);
    free(a->free_coord);
    free(a->iwork);
    for (int f = 0; f < 2; ++f) {
        kin_lufactor *L = &a->lu[f];
        free(L->JT);
        free(L->ipiv);
        free(L->tq);
        free(L->Jinv);
        free(L->xyz);
        free(L->vr_vec);
        free(L->vmax_vec);
    }
    free(a->luR);
    free(a->luw);
    free(a->luw2);
    if (a->sp_free) a->sp_free(a);
    if (a->san) { /* the sparse mode's analysis (analysis_sparse.c) */
        free(a->san->xyz), free(a->san->Um), free(a->san->Urig), free(a->san->Uint), free(a->san->Ws);
        free(a->san);
    }
    if (a->ct_free) a->ct_free(a);
    free(a);
}

void kin_assembly_free(kin_assembly *a) { release(a); }

/* 1 if the allocation failed, as an int: the results are combined with `|`
 * on purpose (every allocation is attempted; release() frees what succeeded),
 * which Clang's -Wbitwise-instead-of-logical flags for boolean operands */
#define ALLOC_(p, n) ((int)(((p) = calloc((size_t)(n) > 0 ? (size_t)(n) : 1, sizeof *(p))) == NULL))

/* allocate the arrays of a handle whose sizes (dim, nj, nb, nf, nfix) are
 * set that every mode needs: O(nj + nb) each, and a few of nf x 6. The dense
 * analysis workspace comes later (kin__dense_ready). */
static int allocate(kin_assembly *a)
{
    size_t nj = (size_t)a->nj, d = (size_t)a->dim, nb = (size_t)a->nb, nf = (size_t)a->nf;
    size_t m1 = nb + 1, ldb = m1 > nf ? m1 : nf;
    int bad = ALLOC_(a->xyz, nj * d) | ALLOC_(a->fixed, nj * d) | ALLOC_(a->bars, 2 * nb) |
              ALLOC_(a->L0, nb) | ALLOC_(a->free_index, nj * d) | ALLOC_(a->free_coord, nf) |
              ALLOC_(a->G, nj * d * 6) | ALLOC_(a->Gs, 6 * 6 + 6 + 6 * nf + nj * d * 6) | ALLOC_(a->sup_fix, a->nfix) |
              ALLOC_(a->rhs, ldb) | ALLOC_(a->t, nf) | ALLOC_(a->x0, nf) | ALLOC_(a->x, nf) |
              ALLOC_(a->xp, nf) | ALLOC_(a->d, nf) | ALLOC_(a->y, nf + nb) | ALLOC_(a->e, nb) |
              ALLOC_(a->len, nb) | ALLOC_(a->chord, nf) | ALLOC_(a->xyz_trial, nj * d) | ALLOC_(a->Rref, nf * 6);
    for (int f = 0; f < 2; ++f) bad |= ALLOC_(a->fac[f].Urig, nf * 6);
    size_t rows = nb + 1 + (size_t)a->nrig;
    for (int f = 0; f < 2; ++f) {
        kin_lufactor *L = &a->lu[f];
        bad |= ALLOC_(L->xyz, nj * d) | ALLOC_(L->vr_vec, nf) | ALLOC_(L->vmax_vec, nf);
    }
    bad |= ALLOC_(a->luR, nf * 6) | ALLOC_(a->luw, rows > nf ? rows : nf) | ALLOC_(a->luw2, nf);
    return bad ? KIN_ENOMEM : KIN_OK;
}

/* Bytes of the dense analysis workspace (SVD of H: H, its copy, U, VT and
 * the internal mechanisms of both factor slots, the mechanism split's
 * scratch, the bordered system; the LU mode's dense factors), without the
 * LAPACK workspace; 0 if the count overflows size_t. */
static size_t dense_bytes(const kin_assembly *a)
{
    size_t nb = (size_t)a->nb, nf = (size_t)a->nf, mn = nf < nb ? nf : nb, m1 = nb + 1;
    size_t rows = nb + 1 + (size_t)a->nrig, nfnf, nfnb, nbnb, nfm1, nfrows, total = 0, part;
    if (!kin__mul_size(nf, nf, &nfnf) || !kin__mul_size(nf, nb, &nfnb) || !kin__mul_size(nb, nb, &nbnb) ||
        !kin__mul_size(nf, m1, &nfm1) || !kin__mul_size(nf, rows, &nfrows))
        return 0;
    /* doubles: H, A; 2 x (sv, U, VT, Uint); mwork; B, svB; 2 x JT; 2 x Jinv (small) */
    size_t ninv = nf <= KIN__LU_INVERSE_MAX_NF ? nfnf : 0;
    size_t terms[] = {nfnb, nfnb, mn, nfnf, nbnb, nfnf, mn, nfnf, nbnb, nfnf, nfnf, nfnf, nfnf, 8 * nf,
                      nfm1, m1 < nf ? m1 : nf, nfrows, nfrows, ninv, ninv};
    for (size_t i = 0; i < sizeof terms / sizeof terms[0]; ++i) {
        if (total > (size_t)-1 - terms[i]) return 0;
        total += terms[i];
    }
    if (!kin__mul_size(total, sizeof(double), &total)) return 0;
    /* ints: 2 x (ipiv, tq as doubles) */
    if (!kin__mul_size(4 * sizeof(double), nf, &part) || total > (size_t)-1 - part) return 0;
    return total + part;
}

/* Every dense matrix of the workspace (H and its copy: nf x nb; U: nf x nf;
 * VT: nb x nb; the bordered systems: nf x (nb + 1 + nrig)) must have at
 * most INT_MAX entries: LAPACK takes sizes and workspace lengths as int. */
static int product_fits_int(size_t a, size_t b)
{
    size_t e;
    return kin__mul_size(a, b, &e) && e <= (size_t)INT_MAX;
}

static int dense_sizes_fit(const kin_assembly *a)
{
    size_t nfs = (size_t)a->nf, nbs = (size_t)a->nb, cols = nbs + 1 + (size_t)a->nrig;
    return product_fits_int(nfs, nfs) && product_fits_int(nbs, nbs) && product_fits_int(nfs, cols) &&
           product_fits_int(nfs, nbs);
}

/* physical memory of this machine in bytes (0 if unknown) */
static size_t physical_bytes(void)
{
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    size_t b;
    if (pages > 0 && page > 0 && kin__mul_size((size_t)pages, (size_t)page, &b)) return b;
#endif
    return 0;
}

/* the dense workspace of a handle that could not have all of it (the small
 * LAPACK workspace of create stays) */
static void release_dense(kin_assembly *a)
{
    double **dp[] = {&a->H, &a->A, &a->mwork, &a->B, &a->svB};
    for (size_t i = 0; i < sizeof dp / sizeof dp[0]; ++i) {
        free(*dp[i]);
        *dp[i] = NULL;
    }
    free(a->iwork);
    a->iwork = NULL;
    for (int f = 0; f < 2; ++f) {
        kin_factor *F = &a->fac[f];
        free(F->sv), free(F->U), free(F->VT), free(F->Uint);
        F->sv = F->U = F->VT = F->Uint = NULL;
        F->valid = 0;
        kin_lufactor *L = &a->lu[f];
        free(L->JT), free(L->ipiv), free(L->tq), free(L->Jinv);
        L->JT = L->tq = L->Jinv = NULL;
        L->inv = 0;
        L->ipiv = NULL;
        if (!L->sparse) L->valid = 0;
    }
}

int kin__dense_affordable(const kin_assembly *a)
{
    if (a->fault == KIN__FAULT_DENSE_UNAFFORDABLE) return 0;
    if (a->H) return 1;
    size_t need = dense_bytes(a), phys = physical_bytes();
    return dense_sizes_fit(a) && need > 0 && (phys == 0 || need <= phys / 2);
}

/* what the refusal of the dense workspace tells the caller to do: outside
 * the sparse mode, use it; inside it, what it covers and what it does not */
static const char *dense_refusal_hint(const kin_assembly *a)
{
    if (a->opt.factorization != KIN_STEP_SPARSE) return "the sparse mode, KIN_STEP_SPARSE, analyses and steps without it";
    return "this call needs the dense SVD of H even in the sparse mode, which analyses (kin_analyse), steps "
           "between regular points and gives the second order without it; locating, following and stepping "
           "through a point the sparse analysis finds singular do not";
}

int kin__dense_ready(kin_assembly *a)
{
    if (a->H) return KIN_OK;
    size_t need = dense_bytes(a), phys = physical_bytes();
    if (a->fault == KIN__FAULT_DENSE_UNAFFORDABLE) phys = need / 2; /* the test hook: too big for memory */
    if (need == 0 || !dense_sizes_fit(a))
        return kin__fail(a, KIN_ENOMEM,
                         "dense workspace for %d free coordinates x %d bars: a dense matrix of the analysis would "
                         "have more than INT_MAX entries (LAPACK's limit); %s",
                         a->nf, a->nb, dense_refusal_hint(a));
    if (phys > 0 && need > phys)
        return kin__fail(a, KIN_ENOMEM,
                         "dense workspace for %d free coordinates x %d bars needs %.3g GB, more than the "
                         "%.3g GB of memory; %s",
                         a->nf, a->nb, (double)need / 1e9, (double)phys / 1e9, dense_refusal_hint(a));
    size_t nb = (size_t)a->nb, nf = (size_t)a->nf, mn = nf < nb ? nf : nb, m1 = nb + 1;
    int bad = ALLOC_(a->H, nf * nb) | ALLOC_(a->A, nf * nb) | ALLOC_(a->mwork, 3 * nf * nf + 8 * nf) |
              ALLOC_(a->B, m1 * nf) | ALLOC_(a->svB, m1 < nf ? m1 : nf);
    for (int f = 0; f < 2; ++f)
        bad |= ALLOC_(a->fac[f].sv, mn) | ALLOC_(a->fac[f].U, nf * nf) | ALLOC_(a->fac[f].VT, nb * nb) |
               ALLOC_(a->fac[f].Uint, nf * nf);
    /* LU mode: J^T = [H, t, R] has at most nb + 1 + nrig columns; its
     * factors only exist where the LU or LQ route can apply (else NULL) */
    size_t rows = nb + 1 + (size_t)a->nrig;
    int lu = lu_route(a), lq = lq_route(a);
    for (int f = 0; f < 2; ++f) {
        kin_lufactor *L = &a->lu[f];
        if (lu || lq) bad |= ALLOC_(L->JT, nf * rows);
        if (lu) bad |= ALLOC_(L->ipiv, nf);
        if (lu && nf <= KIN__LU_INVERSE_MAX_NF) bad |= ALLOC_(L->Jinv, nf * nf);
        if (lq) bad |= ALLOC_(L->tq, nf);
    }
    int lwork = a->lwork_dense, rc = KIN_OK;
    if (bad) rc = KIN_ENOMEM;
    else if (lwork > 0) a->lwork_i = a->lwork_dense_i; /* a clone's: its source's sizes */
    else rc = query_lwork(a, &lwork, &a->lwork_i);
    double *work = NULL;
    if (rc == KIN_OK && (ALLOC_(work, lwork) | ALLOC_(a->iwork, a->lwork_i))) rc = KIN_ENOMEM;
    if (rc == KIN_OK) {
        /* the full workspace replaces the small one of the supports' SVD */
        free(a->work);
        a->work = work;
        a->lwork = a->lwork_dense = lwork;
        a->lwork_dense_i = a->lwork_i;
    } else {
        free(work);
        release_dense(a);
        return kin__fail(a, rc, "dense workspace for %d free coordinates x %d bars (%.3g GB)", a->nf, a->nb,
                         (double)need / 1e9);
    }
    return KIN_OK;
}

int kin_assembly_create(int dim, int nj, const double *xyz, const unsigned char *fixed, int nb,
                        const int *bars, const double *rest, kin_assembly **out, char *eb,
                        size_t el)
{
    if (eb && el) eb[0] = '\0';
    if (!out) return kin__failbuf(eb, el, KIN_ENULL, "out is NULL");
    *out = NULL;
    int rc = validate(dim, nj, xyz, fixed, nb, bars, rest, eb, el);
    if (rc) return rc;
    kin_assembly *a = calloc(1, sizeof *a);
    if (!a) return kin__failbuf(eb, el, KIN_ENOMEM, "handle");
    a->dim = dim;
    a->nj = nj;
    a->nb = nb;
    a->nrig = dim == 2 ? 3 : 6;
    for (int i = 0; i < nj * dim; ++i) {
        if (fixed && fixed[i]) a->nfix++;
        else a->nf++;
    }
    if (allocate(a) != KIN_OK) {
        int nf = a->nf; /* a is gone after release() */
        release(a);
        return kin__failbuf(eb, el, KIN_ENOMEM, "workspace for %d free coordinates x %d bars", nf, nb);
    }
    memcpy(a->xyz, xyz, sizeof(double) * (size_t)(nj * dim));
    memcpy(a->bars, bars, sizeof(int) * 2 * (size_t)nb);
    for (int i = 0, r = 0; i < nj * dim; ++i) {
        a->fixed[i] = (unsigned char)(fixed && fixed[i]);
        a->free_index[i] = a->fixed[i] ? -1 : r;
        if (!a->fixed[i]) a->free_coord[r++] = i;
    }
    for (int k = 0; k < nb; ++k) a->nfixed_bars += kin__bar_fixed(a, k);
    double ss = 0.0;
    a->min_length = INFINITY;
    for (int k = 0; k < nb; ++k) {
        a->L0[k] = rest ? rest[k] : bar_length(a, xyz, k);
        ss += a->L0[k] * a->L0[k];
        a->min_length = fmin(a->min_length, a->L0[k]);
    }
    a->rms_length = sqrt(ss / nb);
    kin_options_default(&a->opt);
    /* LAPACK workspace of what every mode does (the SVD of the supports'
     * rigid motions, nfix x nrig); kin__dense_ready makes it larger */
    {
        int mf = a->nfix > 0 ? a->nfix : 1, nr = a->nrig, one = 1, q = -1, info = 0;
        double w = 0.0, dummy = 0.0;
        dgesvd_("N", "A", &mf, &nr, &dummy, &mf, &dummy, &dummy, &one, &dummy, &nr, &w, &q, &info, 1, 1);
        a->lwork = info == 0 && w < (double)INT_MAX - 1.0 ? (int)w + 1 : 0;
        if (a->lwork == 0 || ALLOC_(a->work, a->lwork)) {
            release(a);
            return kin__failbuf(eb, el, info ? KIN_ELAPACK_ARG : KIN_ENOMEM, "LAPACK workspace of the supports");
        }
    }
    *out = a;
    return KIN_OK;
}

void kin__copy_state(kin_assembly *a, const kin_assembly *src)
{
    size_t nf = (size_t)src->nf, nb = (size_t)src->nb, mn = nf < nb ? nf : nb;
    memcpy(a->xyz, src->xyz, sizeof(double) * (size_t)(src->nj * src->dim));
    if (a->san) a->san->valid = 0; /* a sparse analysis is not copied */
    /* src's dense analysis needs dst's dense workspace (made once; if it
     * cannot be had, dst keeps no analysis and makes its own when asked) */
    int dense = src->H != NULL && kin__dense_ready(a) == KIN_OK;
    /* only the current point's factors: the other slot of each pair is a
     * step's trial workspace, always written before it is read (path.c,
     * step_lu.c). The locator copies states at every SVD step, check and
     * node; both slots were 3.5% of a cheap follow on the flat state */
    for (int f = 0; f < 2; ++f) {
        const kin_factor *s = &src->fac[f];
        kin_factor *t = &a->fac[f];
        t->valid = s->valid && dense && f == src->cur;
        t->an = s->an;
        if (!t->valid) continue;
        memcpy(t->sv, s->sv, sizeof(double) * mn);
        memcpy(t->U, s->U, sizeof(double) * nf * nf);
        memcpy(t->VT, s->VT, sizeof(double) * nb * nb);
        memcpy(t->Uint, s->Uint, sizeof(double) * nf * nf);
        memcpy(t->Urig, s->Urig, sizeof(double) * nf * 6);
    }
    a->cur = src->cur;
    /* LU mode factors: copied only when valid (SVD-mode handles never pay) */
    size_t rows = nb + 1 + (size_t)src->nrig, ncoord = (size_t)(src->nj * src->dim);
    for (int f = 0; f < 2; ++f) {
        const kin_lufactor *s = &src->lu[f];
        kin_lufactor *t = &a->lu[f];
        /* sparse factors live in src's KLU objects: not copied (dst factorizes
         * its point again when it steps) */
        t->valid = s->valid && !s->sparse && dense && f == src->lu_cur;
        t->sparse = 0;
        if (!t->valid) continue;
        t->rows = s->rows;
        t->v_r = s->v_r;
        t->v_max = s->v_max;
        memcpy(t->JT, s->JT, sizeof(double) * nf * rows);
        if (s->ipiv) memcpy(t->ipiv, s->ipiv, sizeof(int) * nf); /* only where a route applies */
        if (s->tq) memcpy(t->tq, s->tq, sizeof(double) * nf);
        t->inv = s->inv && s->Jinv && t->Jinv;
        if (t->inv) memcpy(t->Jinv, s->Jinv, sizeof(double) * nf * nf);
        else if (s->inv) t->valid = 0; /* the inverse was its only factors */
        t->det_sign = s->det_sign;
        memcpy(t->xyz, s->xyz, sizeof(double) * ncoord);
        memcpy(t->vr_vec, s->vr_vec, sizeof(double) * nf);
        memcpy(t->vmax_vec, s->vmax_vec, sizeof(double) * nf);
    }
    a->lu_cur = src->lu_cur;
    memcpy(a->t, src->t, sizeof(double) * nf);
    memcpy(a->Rref, src->Rref, sizeof(double) * nf * 6);
    a->have_Rref = src->have_Rref;
    a->have_t = src->have_t;
    a->t_chosen = src->t_chosen;
    a->l = src->l;
    a->step_hint = src->step_hint;
    a->start_strain = src->start_strain;
    a->have_start_strain = src->have_start_strain;
    a->chord_hopeless = src->chord_hopeless;
}

int kin_assembly_clone(const kin_assembly *src, kin_assembly **out)
{
    if (!out) return KIN_ENULL;
    *out = NULL;
    if (!src) return KIN_ENULL;
    kin_assembly *a;
    int rc = kin_assembly_create(src->dim, src->nj, src->xyz, src->fixed, src->nb, src->bars,
                                 src->L0, &a, NULL, 0);
    if (rc) return rc;
    a->lwork_dense = src->lwork_dense; /* the same dimensions: no new workspace queries */
    a->lwork_dense_i = src->lwork_dense_i;
    kin__copy_state(a, src);
    a->opt = src->opt;
    if (src->sp && (rc = src->sp_prepare(a)) != KIN_OK) {
        kin_assembly_free(a);
        return rc;
    }
    if (src->ct && (rc = src->ct_clone(a, src)) != KIN_OK) {
        kin_assembly_free(a);
        return rc;
    }
    a->nfact = src->nfact;
    memcpy(a->err, src->err, sizeof a->err);
    *out = a;
    return KIN_OK;
}

/* ---- getters ------------------------------------------------------------ */

int kin_dim(const kin_assembly *a) { return a ? a->dim : -1; }
int kin_njoints(const kin_assembly *a) { return a ? a->nj : -1; }
int kin_nbars(const kin_assembly *a) { return a ? a->nb : -1; }
int kin_nfree(const kin_assembly *a) { return a ? a->nf : -1; }

int kin_free_index(const kin_assembly *a, int joint, int axis)
{
    if (!a || joint < 0 || joint >= a->nj || axis < 0 || axis >= a->dim) return -1;
    return a->free_index[joint * a->dim + axis];
}

int kin_get_bars(const kin_assembly *a, int *bars)
{
    if (!a || !bars) return KIN_ENULL;
    memcpy(bars, a->bars, sizeof(int) * 2 * (size_t)a->nb);
    return KIN_OK;
}

int kin_get_rest_lengths(const kin_assembly *a, double *lengths)
{
    if (!a || !lengths) return KIN_ENULL;
    memcpy(lengths, a->L0, sizeof(double) * (size_t)a->nb);
    return KIN_OK;
}

int kin_get_fixed(const kin_assembly *a, unsigned char *fixed)
{
    if (!a || !fixed) return KIN_ENULL;
    memcpy(fixed, a->fixed, (size_t)(a->nj * a->dim));
    return KIN_OK;
}

int kin_get_coords(const kin_assembly *a, double *xyz)
{
    if (!a || !xyz) return KIN_ENULL;
    memcpy(xyz, a->xyz, sizeof(double) * (size_t)(a->nj * a->dim));
    return KIN_OK;
}

int kin_get_lengths(const kin_assembly *a, double *lengths)
{
    if (!a || !lengths) return KIN_ENULL;
    kin__lengths(a, a->xyz, lengths);
    return KIN_OK;
}

double kin_max_strain(const kin_assembly *a) { return a ? kin__lengths(a, a->xyz, NULL) : -1.0; }

void kin__set_configuration(kin_assembly *a, const double *xyz)
{
    memcpy(a->xyz, xyz, sizeof(double) * (size_t)(a->nj * a->dim));
    a->fac[0].valid = a->fac[1].valid = 0;
    if (a->san) a->san->valid = 0;
    kin__lu_invalidate(a);
    a->have_t = a->t_chosen = 0;
    a->step_hint = 0.0;
    a->have_start_strain = 0;
    a->chord_hopeless = 0;
    a->l = 0.0;
}

int kin_set_coords(kin_assembly *a, const double *xyz)
{
    if (!a) return KIN_ENULL;
    if (!xyz) return kin__fail(a, KIN_ENULL, "xyz is NULL");
    int n = a->nj * a->dim;
    int rc = check_coords(n, a->dim, xyz, a->err, sizeof a->err);
    if (rc) return rc;
    for (int i = 0; i < n; ++i)
        if (a->fixed[i] && xyz[i] != a->xyz[i])
            return kin__fail(a, KIN_EINVAL, "coordinate %d of joint %d is fixed (%g) but given %g",
                             i % a->dim, i / a->dim, a->xyz[i], xyz[i]);
    for (int k = 0; k < a->nb; ++k) {
        double L = bar_length(a, xyz, k);
        if (!(L > 0.0)) return kin__fail(a, KIN_EINVAL, "bar %d would have zero length", k);
        if (!(L >= LENGTH_MIN))
            return kin__fail(a, KIN_EGEOM, "bar %d would have length %g, below %g", k, L, LENGTH_MIN);
    }
    kin__set_configuration(a, xyz);
    return KIN_OK;
}

int kin_get_equilibrium_matrix(const kin_assembly *a, double *H, int ldh)
{
    if (!a || !H) return KIN_ENULL;
    if (ldh < a->nf) return KIN_ERANGE;
    kin__build_H(a, a->xyz, H, ldh);
    return KIN_OK;
}
