/* The minimum-norm least-squares Newton correction of the bordered system
 * [C; t^T] d = [-e; 0] by the SVD (LAPACK): the corrector of the SVD mode
 * (path.c) and the fallback of the LU modes where J is singular
 * (step_lu.c). Its own file because both build on it. */
#include <math.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "path/path.h"

int kin__bordered_solve(kin_assembly *a, const double *xyz, const double *t, const double *e,
                        double *d)
{
    int nf = a->nf, nb = a->nb, m1 = t ? nb + 1 : nb, ldr = nb + 1 > nf ? nb + 1 : nf;
    int one = 1, rank = 0, info = kin__dense_ready(a);
    if (info) return info;
    if ((info = kin__check_bars(a, xyz))) return info;
    for (int k = 0; k < nb; ++k)
        if (!isfinite(e[k])) return kin__fail(a, KIN_EGEOM, "the extension of bar %d is not finite", k);
    /* B = [C; t^T] (or just C when t is NULL), C = H^T built row by row (ld m1) */
    kin__build_H(a, xyz, a->H, nf);
    for (int k = 0; k < nb; ++k)
        for (int i = 0; i < nf; ++i) a->B[k + (size_t)i * m1] = a->H[i + (size_t)k * nf];
    if (t)
        for (int i = 0; i < nf; ++i) a->B[nb + (size_t)i * m1] = t[i];
    for (int k = 0; k < nb; ++k) a->rhs[k] = -e[k];
    for (int k = nb; k < ldr; ++k) a->rhs[k] = 0.0;
    double rcond = a->opt.rank_tol;
    a->nfact++;
    if (t) {
        /* the bordered system is square (or wide, with rigid mechanisms) and
         * of full rank off a bifurcation: a QR/LQ factorization (dgels) costs
         * a fraction of an SVD. Exactly singular: fall through to dgelsd. */
        dgels_("N", &m1, &nf, &one, a->B, &m1, a->rhs, &ldr, a->work, &a->lwork, &info, 1);
        if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgels info = %d", info);
        if (info == 0) {
            memcpy(d, a->rhs, sizeof(double) * (size_t)nf);
            return KIN_OK;
        }
        for (int k = 0; k < nb; ++k)
            for (int i = 0; i < nf; ++i) a->B[k + (size_t)i * m1] = a->H[i + (size_t)k * nf];
        for (int i = 0; i < nf; ++i) a->B[nb + (size_t)i * m1] = t[i];
        for (int k = 0; k < nb; ++k) a->rhs[k] = -e[k];
        for (int k = nb; k < ldr; ++k) a->rhs[k] = 0.0;
    }
    dgelsd_(&m1, &nf, &one, a->B, &m1, a->rhs, &ldr, a->svB, &rcond, &rank, a->work, &a->lwork,
            a->iwork, &info);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgelsd info = %d", info);
    if (info > 0) return kin__fail(a, KIN_ELAPACK_CONV, "dgelsd info = %d", info);
    memcpy(d, a->rhs, sizeof(double) * (size_t)nf);
    return KIN_OK;
}
