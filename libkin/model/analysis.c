/* First-order analysis (paper 3.1): SVD of H, rank, mechanisms and
 * self-stresses (the split of the mechanisms into rigid-body and internal
 * ones is mechanism_split.c's; the sparse mode's analysis is
 * analysis_sparse.c's), and the getters of either analysis. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"

/* Split U_m (the last m columns of f->U) into rigid and internal parts. */
static int split_mechanisms(kin_assembly *a, const double *xyz, kin_factor *f)
{
    int m = f->an.m, kept = 0;
    f->an.m_rigid = 0;
    f->an.m_internal = m;
    int rc = kin__split_basis(a, xyz, f->U + (size_t)f->an.rank * a->nf, m, f->Urig, f->Uint, &kept, a->mwork);
    if (rc) return rc;
    f->an.m_rigid = kept;
    f->an.m_internal = m - kept;
    return KIN_OK;
}

/* The SVD of H at xyz into fac[idx] (singular values and vectors only: not
 * yet valid; kin__reclassify completes it) */
static int factorize(kin_assembly *a, const double *xyz, int idx)
{
    int rc = kin__dense_ready(a);
    if (rc) return rc;
    kin_factor *f = &a->fac[idx];
    int nf = a->nf, nb = a->nb, info = 0;
    f->valid = 0;
    if ((rc = kin__check_bars(a, xyz))) return rc;
    kin__build_H(a, xyz, a->H, nf);
    memcpy(a->A, a->H, sizeof(double) * (size_t)nf * (size_t)nb);
    a->nfact++;
    dgesdd_("A", &nf, &nb, a->A, &nf, f->sv, f->U, &nf, f->VT, &nb, a->work, &a->lwork, a->iwork,
            &info, 1);
    if (a->fault == KIN__FAULT_SVD_ARG) info = -4;
    if (a->fault == KIN__FAULT_SVD_CONV || a->fault == KIN__FAULT_SDD_CONV) info = 1;
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgesdd info = %d", info);
    if (info > 0) {
        /* dgesdd's divide and conquer failed; the QR-iteration SVD may not */
        memcpy(a->A, a->H, sizeof(double) * (size_t)nf * (size_t)nb);
        a->nfact++;
        dgesvd_("A", "A", &nf, &nb, a->A, &nf, f->sv, f->U, &nf, f->VT, &nb, a->work, &a->lwork,
                &info, 1, 1);
        if (a->fault == KIN__FAULT_SVD_CONV) info = 1;
        if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgesvd info = %d", info);
        if (info > 0)
            return kin__fail(a, KIN_ELAPACK_CONV, "dgesdd and dgesvd failed (dgesvd info = %d)",
                             info);
    }
    return KIN_OK;
}

int kin__singular_values(kin_assembly *a, const double *xyz, double *sv)
{
    int rc = kin__dense_ready(a);
    if (rc) return rc;
    int nf = a->nf, nb = a->nb, info = 0, one = 1;
    double dummy = 0.0;
    if ((rc = kin__check_bars(a, xyz))) return rc;
    kin__build_H(a, xyz, a->H, nf);
    memcpy(a->A, a->H, sizeof(double) * (size_t)nf * (size_t)nb);
    /* not counted in nfact: the caller counts the point once, whether or
     * not it analyses it in full after this */
    /* the workspace queried for jobz = 'A' covers 'N' */
    dgesdd_("N", &nf, &nb, a->A, &nf, sv, &dummy, &one, &dummy, &one, a->work, &a->lwork, a->iwork, &info, 1);
    /* the same injected faults as factorize's */
    if (a->fault == KIN__FAULT_SVD_ARG) info = -4;
    if (a->fault == KIN__FAULT_SVD_CONV || a->fault == KIN__FAULT_SDD_CONV) info = 1;
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgesdd info = %d", info);
    if (info > 0) {
        memcpy(a->A, a->H, sizeof(double) * (size_t)nf * (size_t)nb);
        dgesvd_("N", "N", &nf, &nb, a->A, &nf, sv, &dummy, &one, &dummy, &one, a->work, &a->lwork, &info, 1, 1);
        if (a->fault == KIN__FAULT_SVD_CONV) info = 1;
        if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgesvd info = %d", info);
        if (info > 0) return kin__fail(a, KIN_ELAPACK_CONV, "dgesdd and dgesvd failed (dgesvd info = %d)", info);
    }
    return KIN_OK;
}

int kin__analyse_into(kin_assembly *a, const double *xyz, int idx)
{
    int rc = factorize(a, xyz, idx);
    return rc ? rc : kin__reclassify(a, xyz, idx);
}

int kin__reclassify(kin_assembly *a, const double *xyz, int idx)
{
    kin_factor *f = &a->fac[idx];
    int nf = a->nf, nb = a->nb, mn = nf < nb ? nf : nb;
    f->valid = 0;
    kin_analysis *an = &f->an;
    an->v_max = mn > 0 ? f->sv[0] : 0.0;
    an->rank = 0;
    double tol = kin__rank_tolerance(a);
    for (int i = 0; i < mn; ++i)
        if (f->sv[i] > tol * an->v_max) an->rank++;
    an->m = nf - an->rank;
    an->s = nb - an->rank;
    /* a zero column of H adds nothing to the rank: each fixed bar is one of
     * the s self-stresses (the min guards a rank decision that counted a
     * rounding-level singular value of a zero column) */
    an->s_trivial = a->nfixed_bars < an->s ? a->nfixed_bars : an->s;
    an->v_r = an->rank > 0 ? f->sv[an->rank - 1] : 0.0;
    int rc = split_mechanisms(a, xyz, f);
    if (rc) return rc;
    f->valid = 1;
    return KIN_OK;
}

void kin__set_fault(kin_assembly *a, int fault) { a->fault = fault; }

static int analysis_out_ok(const kin_analysis *out)
{
    return kin__abi_check(out, KIN__ABI(kin_analysis));
}

/* kin_analyse with or without the progress reports: the public call
 * reports (0, 2) before the SVD, (1, 2) after it, (2, 2) at the end, and
 * stops with KIN_ECANCELLED (the current analysis untouched) where the
 * callback asks; the library's own loops call it without reports (their
 * own progress counts steps) */
static int analyse_pinned(kin_assembly *a, kin_analysis *out, int report);

static int analyse(kin_assembly *a, kin_analysis *out, int report)
{
    /* small matrices: one BLAS thread for the SVD (model/blas_threads.c), as
     * follow and locate do, the caller's setting restored: the same
     * singular vectors (the mechanism basis) with any OPENBLAS_NUM_THREADS */
    int token = kin__blas_threads_small(a);
    int rc = analyse_pinned(a, out, report);
    kin__blas_threads_restore(token);
    return rc;
}

static int analyse_pinned(kin_assembly *a, kin_analysis *out, int report)
{
    if (out) {
        if (analysis_out_ok(out)) return a ? kin__fail(a, KIN_EINVAL, "out->size = %zu: set it to sizeof(kin_analysis)",
                                                          kin__abi_size(out))
                                           : KIN_EINVAL;
        kin__abi_zero(out);
    }
    if (!a) return KIN_ENULL;
    if (report && a->opt.factorization == KIN_STEP_SPARSE) {
        /* the public call in the sparse mode: no dense SVD (analysis_sparse.c)
         * unless the dense route fits in memory and costs less: the sparse
         * analysis stops where its work would pass the dense one's predicted
         * cost, or at its block limit, and the dense SVD answers instead */
        int affordable = kin__dense_affordable(a), over = 0;
        double budget = affordable ? kin__dense_analysis_flops(a) : INFINITY;
        int rc = kin__analyse_sparse(a, a->xyz, 1, budget, &over);
        if (rc == KIN_OK && out) kin__abi_write(out, &a->san->an, KIN__ABI(kin_analysis));
        if (rc == KIN_OK || !(over && affordable)) return rc;
        if (a->san) a->san->valid = 0;
    }
    if (report && kin__progress(a, 0.0, 2.0)) return kin__fail(a, KIN_ECANCELLED, "analysis cancelled before the SVD");
    int trial = 1 - a->cur;
    int rc = factorize(a, a->xyz, trial);
    if (rc) return rc;
    if (report && kin__progress(a, 1.0, 2.0)) return kin__fail(a, KIN_ECANCELLED, "analysis cancelled after the SVD");
    rc = kin__reclassify(a, a->xyz, trial);
    if (rc) return rc;
    a->cur = trial;
    if (a->san) a->san->valid = 0; /* the newer analysis of this point is the dense one */
    if (report) (void)kin__progress(a, 2.0, 2.0);
    /* a tangent chosen or inherited at this very point stays valid */
    if (out) kin__abi_write(out, &a->fac[a->cur].an, KIN__ABI(kin_analysis));
    return KIN_OK;
}

int kin_analyse(kin_assembly *a, kin_analysis *out) { return analyse(a, out, 1); }

int kin__analyse(kin_assembly *a, kin_analysis *out) { return analyse(a, out, 0); }

static int need_analysis(const kin_assembly *a)
{
    return !kin__cur(a)->valid ? KIN_ESTATE : KIN_OK;
}

int kin_get_analysis(const kin_assembly *a, kin_analysis *out)
{
    if (!a || !out) return KIN_ENULL;
    if (analysis_out_ok(out)) return KIN_EINVAL;
    kin__abi_zero(out);
    const kin_sparse_an *sa = kin__sparse_an_current(a);
    if (sa) {
        kin__abi_write(out, &sa->an, KIN__ABI(kin_analysis));
        return KIN_OK;
    }
    if (need_analysis(a)) return KIN_ESTATE;
    kin__abi_write(out, &kin__cur(a)->an, KIN__ABI(kin_analysis));
    return KIN_OK;
}

int kin_get_analysis_route(const kin_assembly *a, int *route)
{
    if (!a || !route) return KIN_ENULL;
    if (kin__sparse_an_current(a)) *route = KIN_ROUTE_SPARSE;
    else if (!need_analysis(a)) *route = KIN_ROUTE_DENSE;
    else return KIN_ESTATE;
    return KIN_OK;
}

int kin_get_singular_values(const kin_assembly *a, double *sv, int n)
{
    if (!a || !sv) return KIN_ENULL;
    if (kin__sparse_an_current(a))
        return kin__fail((kin_assembly *)a, KIN_ESTATE,
                         "the sparse analysis (KIN_STEP_SPARSE) computes v_max and the singular values at the rank "
                         "decision only (kin_get_analysis); analyse in KIN_STEP_SVD mode for all of them");
    if (need_analysis(a)) return KIN_ESTATE;
    int mn = a->nf < a->nb ? a->nf : a->nb;
    if (n < mn) return KIN_ERANGE;
    memcpy(sv, kin__cur(a)->sv, sizeof(double) * (size_t)mn);
    return KIN_OK;
}

static int copy_cols(const double *src, int rows, int cols, double *dst, int ld, int dcols)
{
    if (ld < rows || dcols < cols) return KIN_ERANGE;
    for (int c = 0; c < cols; ++c)
        memcpy(dst + (size_t)c * ld, src + (size_t)c * rows, sizeof(double) * (size_t)rows);
    return KIN_OK;
}

int kin_get_mechanisms(const kin_assembly *a, int kind, double *U, int ldu, int cols)
{
    if (!a || !U) return KIN_ENULL;
    const kin_sparse_an *sa = kin__sparse_an_current(a);
    if (sa) switch (kind) {
        case KIN_MECH_INTERNAL: return copy_cols(sa->Uint, a->nf, sa->an.m_internal, U, ldu, cols);
        case KIN_MECH_RIGID: return copy_cols(sa->Urig, a->nf, sa->an.m_rigid, U, ldu, cols);
        case KIN_MECH_ALL: return copy_cols(sa->Um, a->nf, sa->an.m, U, ldu, cols);
        default: return KIN_EINVAL;
        }
    if (need_analysis(a)) return KIN_ESTATE;
    const kin_factor *f = kin__cur(a);
    switch (kind) {
    case KIN_MECH_INTERNAL: return copy_cols(f->Uint, a->nf, f->an.m_internal, U, ldu, cols);
    case KIN_MECH_RIGID: return copy_cols(f->Urig, a->nf, f->an.m_rigid, U, ldu, cols);
    case KIN_MECH_ALL:
        return copy_cols(f->U + (size_t)f->an.rank * a->nf, a->nf, f->an.m, U, ldu, cols);
    default: return KIN_EINVAL;
    }
}

int kin_get_self_stresses(const kin_assembly *a, double *W, int ldw, int cols)
{
    if (!a || !W) return KIN_ENULL;
    const kin_sparse_an *sa = kin__sparse_an_current(a);
    if (sa) return copy_cols(sa->Ws, a->nb, sa->an.s, W, ldw, cols);
    if (need_analysis(a)) return KIN_ESTATE;
    const kin_factor *f = kin__cur(a);
    int nb = a->nb, s = f->an.s, r = f->an.rank;
    if (ldw < nb || cols < s) return KIN_ERANGE;
    /* W_s = rows r..nb-1 of VT, transposed */
    for (int c = 0; c < s; ++c)
        for (int k = 0; k < nb; ++k) W[k + (size_t)c * ldw] = f->VT[(r + c) + (size_t)k * nb];
    return KIN_OK;
}
