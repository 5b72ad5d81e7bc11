/* KIN_STEP_SPARSE: the bordered matrix J = [C; b^T; R^T] itself, in
 * compressed columns with its dense border rows (the pattern is made once by
 * sparse.c): its values at a configuration and the products with C. The
 * lowest file of the sparse mode: sparse_border.c (factorizations, solves)
 * and sparse.c (set-up) build on it. */
#include "path/sparse_internal.h"

int kin__sparse_usable(const kin_assembly *a, int mr)
{
    return a->sp && a->sp->dsym && a->nb + 1 + mr == a->nf;
}

void kin__sparse_fill(const kin_assembly *a, const double *xyz, const double *b, const double *R)
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
