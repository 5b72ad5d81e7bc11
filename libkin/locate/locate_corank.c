/* The corank-k Newton of the fast locator (locate_hermite.c): at a point
 * near a bifurcation where k singular values of H vanish together, the
 * position inside their null directions that makes the whole k x k block
 * vanish (Govaerts' bordered form for higher corank, as MatCont's and
 * BifurcationKit's minimally augmented systems; docs/locate.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "locate/locate_internal.h"

/* LAPACK dgelsd's workspace for the largest system (CORANK_MAX_Q^2 rows,
 * CORANK_MAX_Q + 1 columns, one right-hand side), generously: its minimum
 * for 1024 x 33 is ~3e3 doubles and ~4e2 integers */
enum { LWORK = 16384, LIWORK = 2048 };
/* singular values of the Jacobian below this fraction of its largest are
 * treated as zero (the least-squares step ignores those directions) */
static const double JACOBIAN_RCOND = 1e-10;

struct kin__corank_ws {
    int nf, nb;
    double *J, *rhs, *sj, *work, *u, *wv, *dx, *scratch;
    int *iwork;
};

kin__corank_ws *kin__corank_alloc(const kin_assembly *a)
{
    kin__corank_ws *cw = calloc(1, sizeof *cw);
    if (!cw) return NULL;
    size_t q = CORANK_MAX_Q, m = q * q, n = q + 1, nf = (size_t)a->nf, nb = (size_t)a->nb;
    size_t nc = (size_t)a->nj * (size_t)a->dim;
    cw->nf = a->nf;
    cw->nb = a->nb;
    cw->J = malloc(sizeof(double) * (m * n + m + n + LWORK + q * nf + q * nb + n * nf + 2 * nc));
    cw->iwork = malloc(sizeof(int) * LIWORK);
    if (!cw->J || !cw->iwork) {
        kin__corank_free(cw);
        return NULL;
    }
    cw->rhs = cw->J + m * n;
    cw->sj = cw->rhs + m;
    cw->work = cw->sj + n;
    cw->u = cw->work + LWORK;
    cw->wv = cw->u + q * nf;
    cw->dx = cw->wv + q * nb;
    cw->scratch = cw->dx + n * nf;
    return cw;
}

void kin__corank_free(kin__corank_ws *cw)
{
    if (!cw) return;
    free(cw->J);
    free(cw->iwork);
    free(cw);
}

/* One Gauss-Newton step. With the SVD H = U S V^T of the analysed state a,
 * the group G (the lowest non-zero singular value, index k, and the grp
 * above it) has left and right vectors u_a, w_b; the block B_ab(y) =
 * u_a^T H(x + D y) w_b, with D the group's own mechanisms and the path's
 * tangent (U's columns k - grp .. k + 1), is diag(sigma) at y = 0 and
 * vanishes exactly where all q = grp + 1 values do. Its derivative
 * u_a^T dH(D_j) w_b costs O(bars) (model/sv_derivative.c); the q^2 x (q+1)
 * system dB y = -B is solved by least squares (a corank-q point makes it
 * consistent). x (nf, the free coordinates of a) is moved by D y; *step the
 * step's max-norm. KIN_EINVAL where the group is not there, a LAPACK status
 * where the solve fails. */
int kin__corank_step(const kin_assembly *a, int grp, kin__corank_ws *cw, double *x, double *step)
{
    const kin_factor *f = kin__cur(a);
    int k = kin__loc_vanishing_index(a), q = grp + 1, n = q + 1, m = q * q, nf = cw->nf, nb = cw->nb;
    if (k < grp || q > CORANK_MAX_Q || k + 1 >= nf || !f->valid) return KIN_EINVAL;
    int g0 = k - grp;
    for (int i = 0; i < q; ++i) {
        memcpy(cw->u + (size_t)i * nf, f->U + (size_t)(g0 + i) * nf, sizeof(double) * (size_t)nf);
        for (int j = 0; j < nb; ++j) cw->wv[(size_t)i * nb + j] = f->VT[(g0 + i) + (size_t)j * nb];
    }
    /* the directions: the group's mechanisms and the tangent (U's column k+1) */
    memcpy(cw->dx, f->U + (size_t)g0 * nf, sizeof(double) * (size_t)n * (size_t)nf);
    for (int j = 0; j < n; ++j)
        for (int ia = 0; ia < q; ++ia)
            for (int ib = 0; ib < q; ++ib)
                cw->J[(size_t)j * m + ia * q + ib] =
                    kin__sv_derivative_uw(a, a->xyz, cw->dx + (size_t)j * nf, cw->u + (size_t)ia * nf,
                                          cw->wv + (size_t)ib * nb, cw->scratch);
    for (int ia = 0; ia < q; ++ia)
        for (int ib = 0; ib < q; ++ib) cw->rhs[ia * q + ib] = ia == ib ? -f->sv[g0 + ia] : 0.0;
    int nrhs = 1, rank = 0, info = 0, lwork = LWORK;
    double rcond = JACOBIAN_RCOND;
    dgelsd_(&m, &n, &nrhs, cw->J, &m, cw->rhs, &m, cw->sj, &rcond, &rank, cw->work, &lwork, cw->iwork, &info);
    if (info != 0) return info < 0 ? KIN_ELAPACK_ARG : KIN_ELAPACK_CONV;
    *step = 0.0;
    for (int i = 0; i < nf; ++i) {
        double d = 0.0;
        for (int j = 0; j < n; ++j) d += cw->dx[(size_t)j * nf + i] * cw->rhs[j];
        x[i] += d;
        *step = fmax(*step, fabs(d));
    }
    return KIN_OK;
}
