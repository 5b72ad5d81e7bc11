/* Derivative of a singular value of H along a motion of the joints.
 *
 * For a simple singular triple H w = v u, dv = u^T dH w (first-order
 * perturbation). Column j of H holds +n_j at the free rows of end A and -n_j
 * at those of end B, n_j = (X_A - X_B)/L_j, and a motion dX changes it by
 * dn_j = (dX_AB - n_j (n_j . dX_AB)) / L_j. So
 *     dv = sum_j w_j (u_A - u_B) . dn_j
 * costs O(nbars), with no factorization. The locator uses it to turn the
 * singular value that vanishes at a bifurcation into a signed, smooth
 * function of the path parameter. */
#include <math.h>
#include <string.h>

#include "model/internal.h"

/* dv = u^T dH w for u (nf), w (nb entries at stride ws) */
static double derivative(const kin_assembly *a, const double *xyz, const double *dx, const double *uk,
                         const double *wk, int ws, double *scratch)
{
    int d = a->dim, n = a->nj * d, nf = a->nf, nb = a->nb;
    double *u = scratch, *dX = scratch + n;
    memset(scratch, 0, sizeof(double) * 2 * (size_t)n);
    for (int i = 0; i < nf; ++i) {
        u[a->free_coord[i]] = uk[i];
        dX[a->free_coord[i]] = dx[i];
    }
    double dv = 0.0;
    for (int j = 0; j < nb; ++j) {
        int A = a->bars[2 * j] * d, B = a->bars[2 * j + 1] * d;
        double nv[3] = {0, 0, 0}, dd[3] = {0, 0, 0}, L2 = 0.0, nd = 0.0;
        for (int c = 0; c < d; ++c) {
            nv[c] = xyz[A + c] - xyz[B + c];
            L2 += nv[c] * nv[c];
        }
        double L = sqrt(L2);
        for (int c = 0; c < d; ++c) {
            nv[c] /= L;
            dd[c] = dX[A + c] - dX[B + c];
            nd += nv[c] * dd[c];
        }
        double s = 0.0;
        for (int c = 0; c < d; ++c) s += (u[A + c] - u[B + c]) * (dd[c] - nv[c] * nd) / L;
        dv += wk[(size_t)j * ws] * s;
    }
    return dv;
}

double kin__sv_derivative(const kin_assembly *a, const kin_factor *f, const double *xyz, const double *dx,
                          int k, double *scratch)
{
    return derivative(a, xyz, dx, f->U + (size_t)k * a->nf, f->VT + k, a->nb, scratch);
}

double kin__sv_derivative_uw(const kin_assembly *a, const double *xyz, const double *dx, const double *u,
                             const double *w, double *scratch)
{
    return derivative(a, xyz, dx, u, w, 1, scratch);
}
