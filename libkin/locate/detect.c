/* Detection (paper Section 4.1): the signed test function tau (the sign of
 * det of the bordered matrix times v_r), and the helpers the detector loop
 * (locate.c) and the three locators share: where the vanishing singular
 * values are, when a point counts as the bifurcation, a forward
 * calculation, progress and cancel. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "locate/locate_internal.h"

/* The sign of det(P^T R) for two orthonormal bases P (the previous point's
 * rigid mechanisms, as oriented there) and R (this point's, as the SVD gave
 * them) of nearby mr-dimensional spans: +1 when R has P's orientation, -1
 * when it has the other one, 0 when the spans are too far apart to tell.
 *
 * Why a determinant and not column-by-column signs: det [C; t^T; R^T]
 * becomes det(Q) det [C; t^T; R^T] when R is replaced by R Q, so the test
 * function's sign depends on R only through the orientation of the rigid
 * span, never on which basis of it the SVD returns. With several rigid
 * mechanisms (a free body in 3D has 6) the SVD's basis turns freely inside
 * the span from one point to the next, so matching columns one by one
 * (the sign of each dot product) flips the orientation where nothing
 * happens. det(P^T R) is exactly the orientation of R relative to P: its
 * sign is that of the rotation the orthogonal Procrustes problem (carrying
 * P forward as the polar factor of P^T R) would pick, since the polar
 * decomposition P^T R = W S has det S > 0; carrying the basis forward would
 * only add a re-orthonormalisation and its rounding. For mr = 1 it is the
 * sign of the one dot product, as before. */
static int rigid_orientation(int nf, int mr, const double *P, const double *R)
{
    double M[36];
    int piv[6], info = 0, sg = 1;
    for (int i = 0; i < mr; ++i)
        for (int j = 0; j < mr; ++j) M[i + j * mr] = kin__dot(nf, P + (size_t)i * nf, R + (size_t)j * nf);
    dgetrf_(&mr, &mr, M, &mr, piv, &info);
    if (info != 0) return 0;
    for (int i = 0; i < mr; ++i) {
        if (M[i + i * mr] < 0.0) sg = -sg;
        if (piv[i] != i + 1) sg = -sg;
    }
    return sg;
}

int kin_test_function(kin_assembly *a, double *tau)
{
    if (!a || !tau) return KIN_ENULL;
    if (!kin__cur(a)->valid) {
        int rc = kin__analyse(a, NULL);
        if (rc) return rc;
    }
    const kin_factor *f = kin__cur(a);
    int nf = a->nf, nb = a->nb, mr = f->an.m_rigid;
    if (f->an.m_internal == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism");
    if (f->an.m_internal >= 2) {
        *tau = 0.0;
        return KIN_OK;
    }
    double *t = a->chord;
    if (kin_get_tangent(a, t, nf) != KIN_OK) memcpy(t, f->Uint, sizeof(double) * (size_t)nf);
    /* rigid mechanisms, oriented continuously against the previous ones */
    double *R = a->Rref;
    int flip = mr > 0 && a->have_Rref == mr + 1 && rigid_orientation(nf, mr, R, f->Urig) < 0;
    memcpy(R, f->Urig, sizeof(double) * (size_t)nf * (size_t)mr);
    if (flip)
        for (int i = 0; i < nf; ++i) R[i] = -R[i];
    a->have_Rref = mr + 1;
    /* the bars between fixed joints are zero rows of H^T at every point:
     * left out, the border is the one of the structure without them (the
     * same sign, the same detection) */
    int nbk = nb - a->nfixed_bars;
    if (nbk + 1 + mr != nf) {
        /* redundant bars on the path (s > 0): no square border, no sign */
        *tau = f->an.v_r;
        return KIN_OK;
    }
    double *B = a->mwork;
    int *ipiv = a->iwork, info = 0;
    kin__build_H(a, a->xyz, a->H, nf);
    for (int k = 0, row = 0; k < nb; ++k)
        if (!kin__bar_fixed(a, k)) {
            for (int i = 0; i < nf; ++i) B[row + (size_t)i * nf] = a->H[i + (size_t)k * nf];
            ++row;
        }
    for (int i = 0; i < nf; ++i) B[nbk + (size_t)i * nf] = t[i];
    for (int c = 0; c < mr; ++c)
        for (int i = 0; i < nf; ++i) B[nbk + 1 + c + (size_t)i * nf] = R[i + (size_t)c * nf];
    a->nfact++;
    dgetrf_(&nf, &nf, B, &nf, ipiv, &info);
    if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgetrf info = %d", info);
    double sg = 1.0;
    for (int i = 0; i < nf; ++i) {
        if (B[i + (size_t)i * nf] < 0.0) sg = -sg;
        if (ipiv[i] != i + 1) sg = -sg;
    }
    *tau = info > 0 ? 0.0 : sg * f->an.v_r;
    return KIN_OK;
}

double kin__loc_rel(const kin_assembly *a) { return kin__cur(a)->an.v_r / kin__cur(a)->an.v_max; }

/* index of the singular value that vanishes at a bifurcation: a point on a
 * path has rank nfree - 1 - m_rigid, so it is the last non-zero one there */
int kin__loc_vanishing_index(const kin_assembly *a)
{
    /* a point with LU-mode factors and no SVD (kin__locate_ws.lu_nodes):
     * its rigid mechanisms are the factors' extra border rows */
    const kin_lufactor *F = &a->lu[a->lu_cur];
    int mr = !kin__cur(a)->valid && F->valid ? F->rows - a->nb - 1 : kin__cur(a)->an.m_rigid;
    int mn = a->nf < a->nb ? a->nf : a->nb, k = a->nf - 2 - mr;
    return k >= 0 && k < mn ? k : -1;
}

double kin__loc_vanishing_sv(const kin_assembly *a)
{
    int k = kin__loc_vanishing_index(a);
    return k >= 0 ? kin__cur(a)->sv[k] : kin__cur(a)->an.v_r;
}

/* The largest of the singular values that vanish at the bifurcation being
 * located. Several vanish together at most bifurcations of the sails (15 at
 * the hexagonal sail's flat state), with different slopes: the lowest alone
 * can meet the tolerance at a point still 1e-9 away, where m and s would
 * come out wrong. The group: from the path's lowest singular value up to the
 * largest ratio gap among those at most sqrt(tol) * v_max and the first one
 * above. */
double kin__loc_group_top_sv(const double *sv, int k, double tol)
{
    double cut = sqrt(tol) * sv[0], top = sv[k], gap = 1.0;
    for (int i = k - 1; i >= 0; --i) {
        double r = sv[i + 1] > 0.0 ? sv[i] / sv[i + 1] : INFINITY;
        if (r > gap) {
            gap = r;
            top = sv[i + 1];
        }
        if (sv[i] > cut) break;
    }
    return top;
}

double kin__loc_group_top(const kin_assembly *a, double tol)
{
    const kin_factor *f = kin__cur(a);
    int k = kin__loc_vanishing_index(a);
    if (k < 0) return f->an.v_r;
    return kin__loc_group_top_sv(f->sv, k, tol);
}

int kin__loc_at_bifurcation(const kin_assembly *a, double tol)
{
    return kin__loc_group_top(a, tol) <= tol * kin__cur(a)->an.v_max;
}

kin_assembly *kin__loc_probe(loc_ctx *c)
{
    if (c->probe) return c->probe;
    if (kin_assembly_clone(c->a, &c->probe)) {
        c->probe = NULL;
        return NULL;
    }
    c->probe->nfact = 0; /* its factorizations count from here */
    if (c->ws) c->ws->probe = c->probe;
    return c->probe;
}

/* forward calculation: work := base moved by delta along its tangent */
int kin__loc_forward(loc_ctx *c, const kin_assembly *base, kin_assembly *dst, double delta, double *used)
{
    kin__copy_state(dst, base);
    kin_step_info si = {.size = sizeof si};
    c->info->forward++;
    int rc = kin_step(dst, delta, &si);
    if (used) *used = rc == KIN_OK ? si.delta : 0.0;
    return rc;
}

/* Progress through the caller's callback (kin_set_progress): steps plus
 * forward calculations, out of max_steps + max_iter. Called at the top of
 * every following step and location iteration, so a cancel takes effect
 * within one step. Returns 1 when the caller cancels. */
int kin__loc_cancelled(const loc_ctx *c)
{
    double total = (double)c->o->max_steps + (double)c->o->max_iter;
    return kin__progress(c->a, (double)c->info->steps + (double)c->info->forward, total);
}

double kin__loc_tangent_cos(const kin_assembly *x, const kin_assembly *y)
{
    return fabs(kin__dot(x->nf, x->t, y->t));
}

