/* The split of the mechanisms into rigid-body and internal ones
 * (Pellegrino & Calladine 1986), shared by the dense analysis (analysis.c)
 * and the sparse one (analysis_sparse.c), and the rigid-body basis the LU
 * modes border with (kin__rigid_basis). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"

/* Rigid motions that move a support are not mechanisms; a rigid motion is
 * "zero at the supports" when its singular value there is below this
 * fraction of the largest. The motions are built from centred coordinates
 * scaled by their RMS radius, so this is a relative, unit-free test. */
static const double RIGID_SUPPORT_TOL = 1e-10;
/* A rigid-motion candidate is never trusted below this many rounding units
 * of the centred coordinates (two Gram-Schmidt passes make the remaining
 * norm accurate to a few of them). */
static const double GS_ROUNDING_UNITS = 64.0;

/* Orthonormalise column j of X (n rows, ld) against columns 0..k-1 (two
 * passes of modified Gram-Schmidt) and normalise it; returns its norm after
 * orthogonalisation relative to before. */
double kin__gs_column(int n, const double *X, int ld, int k, double *v)
{
    double before = kin__norm(n, v);
    if (before == 0.0) return 0.0;
    for (int pass = 0; pass < 2; ++pass)
        for (int c = 0; c < k; ++c) {
            const double *q = X + (size_t)c * ld;
            double p = kin__dot(n, q, v);
            for (int i = 0; i < n; ++i) v[i] -= p * q[i];
        }
    double after = kin__norm(n, v);
    if (after > 0.0)
        for (int i = 0; i < n; ++i) v[i] /= after;
    return after / before;
}

/* Make the largest-magnitude entry of v positive: a deterministic sign. */
static void orient(int n, double *v)
{
    int im = 0;
    for (int i = 1; i < n; ++i)
        if (fabs(v[i]) > fabs(v[im]) * (1.0 + 1e-12)) im = i;
    if (v[im] < 0.0)
        for (int i = 0; i < n; ++i) v[i] = -v[i];
}

/* Rigid-body motion fields of the whole assembly, evaluated at every
 * coordinate (nj*dim rows, ld nj*dim), into a->G. Returns the rounding
 * error of the fields, relative: DBL_EPSILON times the largest coordinate
 * over the RMS radius (the centring loses that much). */
static double rigid_fields(kin_assembly *a, const double *xyz, double *c, double *rho_out)
{
    int d = a->dim, nj = a->nj, n = nj * d;
    double rho = 0.0;
    c[0] = c[1] = c[2] = 0.0;
    for (int j = 0; j < nj; ++j)
        for (int k = 0; k < d; ++k) c[k] += xyz[j * d + k] / nj;
    for (int j = 0; j < nj; ++j)
        for (int k = 0; k < d; ++k) rho += (xyz[j * d + k] - c[k]) * (xyz[j * d + k] - c[k]);
    rho = sqrt(rho / nj);
    if (!(rho > 0.0)) rho = 1.0;
    double big = 0.0;
    for (int i = 0; i < n; ++i) big = fmax(big, fabs(xyz[i]));
    memset(a->G, 0, sizeof(double) * (size_t)n * (size_t)a->nrig);
    for (int j = 0; j < nj; ++j) {
        double p[3] = {0, 0, 0};
        for (int k = 0; k < d; ++k) p[k] = (xyz[j * d + k] - c[k]) / rho;
        for (int k = 0; k < d; ++k) a->G[j * d + k + (size_t)k * n] = 1.0; /* translations */
        double *rot = a->G + (size_t)d * n;
        if (d == 2) {
            rot[j * 2 + 0] = -p[1];
            rot[j * 2 + 1] = p[0];
        } else {
            /* rotations about x, y, z: omega x p */
            rot[j * 3 + 1] = -p[2]; rot[j * 3 + 2] = p[1];
            rot += n;
            rot[j * 3 + 0] = p[2]; rot[j * 3 + 2] = -p[0];
            rot += n;
            rot[j * 3 + 0] = -p[1]; rot[j * 3 + 1] = p[0];
        }
    }
    *rho_out = rho;
    return DBL_EPSILON * (1.0 + big / rho);
}

/* The supports admit no rigid motion wherever they did at the remembered
 * centre and radius (a->sup_*), with the fixed coordinates unchanged, and
 * the rank test cannot tell otherwise. The fields at centre c and radius
 * rho are those at (c0, rho0) times T = [I, X; 0, s I] (s = rho0 / rho, X
 * the cross product with d = (c0 - c) / rho: a rotation about another centre
 * is the same rotation plus a translation), so their singular values at the
 * supports change by at most the factors ||T|| <= max(1, s) + |d| and
 * ||T^-1|| <= max(1, 1/s) + |d| / s. A smallest / largest ratio that stays
 * SUPPORT_KEEP_MARGIN above RIGID_SUPPORT_TOL after both is full rank for
 * the SVD as well (its values are accurate to a few rounding units of the
 * largest): the SVD's answer, without the SVD (it was 5% of a follow on the
 * hexagonal sail, where every LU step builds its rigid basis). */
static const double SUPPORT_KEEP_MARGIN = 1e4;

static int supports_still_full(const kin_assembly *a, const double *xyz, const double *c, double rho)
{
    if (!a->sup_full) return 0;
    int r = 0, n = a->nj * a->dim;
    for (int i = 0; i < n; ++i)
        if (a->fixed[i] && xyz[i] != a->sup_fix[r++]) return 0;
    double dd = 0.0;
    for (int k = 0; k < a->dim; ++k) dd += (a->sup_c[k] - c[k]) * (a->sup_c[k] - c[k]);
    double s = a->sup_rho / rho, dn = sqrt(dd) / rho;
    double kappa = (fmax(1.0, s) + dn) * (fmax(1.0, 1.0 / s) + dn / s);
    return isfinite(kappa) && a->sup_ratio / kappa > SUPPORT_KEEP_MARGIN * RIGID_SUPPORT_TOL;
}

/* Combinations alpha of the rigid motions in a->G that keep every fixed
 * coordinate: the null space of G restricted to the fixed rows, as rows
 * 0..*nnull-1 of the nr x nr matrix a->Gs (ld nr). */
static int support_nullspace(kin_assembly *a, const double *xyz, const double *c, double rho, int *nnull_out)
{
    int nf = a->nf, nr = a->nrig, n = a->nj * a->dim;
    double *Gfix = a->Gs + 6 * 6 + 6 + 6 * (size_t)nf; /* nfix x nr */
    double *vt = a->Gs, *svg = a->Gs + 36;
    int nnull = 0;
    if (a->nfix > 0 && supports_still_full(a, xyz, c, rho)) {
        *nnull_out = 0;
        return KIN_OK;
    }
    if (a->nfix == 0) {
        memset(vt, 0, sizeof(double) * 36);
        for (int i = 0; i < nr; ++i) vt[i + i * nr] = 1.0;
        nnull = nr; /* rows 0..nr-1 of vt are all null */
    } else {
        int r = 0, mf = a->nfix, one = 1, info = 0;
        for (int i = 0; i < n; ++i)
            if (a->fixed[i]) {
                for (int c = 0; c < nr; ++c) Gfix[r + (size_t)c * mf] = a->G[i + (size_t)c * n];
                ++r;
            }
        double udum = 0.0;
        dgesvd_("N", "A", &mf, &nr, Gfix, &mf, svg, &udum, &one, vt, &nr, a->work, &a->lwork, &info,
                1, 1);
        if (info < 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgesvd (supports) info = %d", info);
        if (info > 0) return kin__fail(a, KIN_ELAPACK_CONV, "dgesvd (supports) info = %d", info);
        int ns = mf < nr ? mf : nr, rk = 0;
        for (int i = 0; i < ns; ++i)
            if (svg[i] > RIGID_SUPPORT_TOL * svg[0]) ++rk;
        /* null rows are rk..nr-1 of vt; move them to the front */
        for (int i = rk; i < nr; ++i)
            for (int c = 0; c < nr; ++c) vt[(i - rk) + (size_t)c * nr] = vt[i + (size_t)c * nr];
        nnull = nr - rk;
        /* remembered where no rigid motion keeps the supports */
        a->sup_full = 0;
        if (nnull == 0 && ns == nr) {
            int q = 0;
            for (int i = 0; i < n; ++i)
                if (a->fixed[i]) a->sup_fix[q++] = xyz[i];
            for (int k = 0; k < 3; ++k) a->sup_c[k] = c[k];
            a->sup_rho = rho;
            a->sup_ratio = svg[nr - 1] / svg[0];
            a->sup_full = 1;
        }
    }
    *nnull_out = nnull;
    return KIN_OK;
}

/* Rigid-body mechanisms of configuration xyz: the rigid motions G alpha
 * that keep every fixed coordinate (alpha in the support null space),
 * restricted to the free coordinates, projected on the columns of Um (nf x
 * m, ld nf) when Um is not NULL, and reduced to an orthonormal basis R (nf x
 * *mr, ld nf) by Gram-Schmidt with column pivoting (the largest remaining
 * candidate first). A candidate counts only while what remains of it moves
 * some coordinate by more than rank_tol times the shortest bar (the
 * candidates are in units of the RMS radius rho: |c_i| rho / min_length >
 * rank_tol). That is the rank test's scale: moving a joint by d turns its
 * bars by d / L, which changes H by as much, and the rank counts a change of
 * H when it exceeds rank_tol times v_max (a few units for a bar framework).
 * So a rotation about a line the supports are on, joints a little off it,
 * is rigid wherever the rank counts those joints' offset, and no motion
 * where it moves them by less, as the rank sees them on the line. Measured
 * against the RMS radius instead (as before issue 36), the two scales part
 * with the number of joints: on a chain of n joints along the line the rank
 * resolves offsets ~n times smaller than the radius-based test, and the
 * rotation came out as an internal mechanism (1 and 2 of 75 chains at
 * n = 48 and 100; python/tests/test_chain_near_line.py).
 * Relative to the candidate's own norm the test would depend on rounding
 * luck: a rotation about a line through every joint moves nothing, and its
 * candidate is rounding noise that normalises to any direction; below
 * GS_ROUNDING_UNITS rounding units (of the generator's size sqrt(nj)) no
 * candidate counts.
 * Scratch: a->Gs (support null space, candidates) and, to project, m
 * doubles of proj. */
static int rigid_mechanisms(kin_assembly *a, const double *xyz, const double *Um, int m, double *R,
                            int *mr, double *proj)
{
    int nf = a->nf, nr = a->nrig, n = a->nj * a->dim, nnull = 0, kept = 0;
    *mr = 0;
    double cen[3], rho = 1.0;
    double rounding = rigid_fields(a, xyz, cen, &rho);
    int rc = support_nullspace(a, xyz, cen, rho, &nnull);
    if (rc) return rc;
    const double *vt = a->Gs;
    double *C = a->Gs + 42; /* nf x nnull candidates */
    for (int q = 0; q < nnull; ++q) {
        double *c = C + (size_t)q * nf;
        for (int i = 0; i < nf; ++i) {
            double s = 0.0;
            for (int k = 0; k < nr; ++k) s += a->G[a->free_coord[i] + (size_t)k * n] * vt[q + (size_t)k * nr];
            c[i] = s;
        }
        if (Um) {
            /* c := U_m (U_m^T c) */
            double *p = proj;
            for (int k = 0; k < m; ++k) p[k] = kin__dot(nf, Um + (size_t)k * nf, c);
            for (int i = 0; i < nf; ++i) {
                double s = 0.0;
                for (int k = 0; k < m; ++k) s += Um[i + (size_t)k * nf] * p[k];
                c[i] = s;
            }
        }
    }
    /* the rank's scale (above): a displacement counts when it exceeds
     * rank_tol times the shortest bar; the candidates are in units of rho */
    double tol = kin__rank_tolerance(a), floor_ = GS_ROUNDING_UNITS * rounding * sqrt((double)a->nj);
    double unit = a->min_length > 0.0 ? rho / a->min_length : 1.0;
    int cap = Um ? m : nf, left = nnull, idx[6], order[6];
    for (int q = 0; q < nnull; ++q) idx[q] = q;
    while (kept < cap && left > 0) {
        /* pivot: the candidate with the most left after the kept directions */
        int best = 0;
        double bestn = -1.0;
        for (int q = 0; q < left; ++q) {
            double nq = kin__norm(nf, C + (size_t)q * nf);
            if (nq > bestn) {
                bestn = nq;
                best = q;
            }
        }
        double *v = R + (size_t)kept * nf;
        memcpy(v, C + (size_t)best * nf, sizeof(double) * (size_t)nf);
        /* the pivot leaves the candidate list (the last one takes its place) */
        --left;
        order[kept] = idx[best];
        idx[best] = idx[left];
        if (best != left) memcpy(C + (size_t)best * nf, C + (size_t)left * nf, sizeof(double) * (size_t)nf);
        /* a second pass against the kept directions (the candidates had
         * one, below) makes the remaining norm accurate to rounding */
        double ratio = kin__gs_column(nf, R, nf, kept, v), big = 0.0;
        for (int i = 0; i < nf; ++i) big = fmax(big, fabs(v[i]));
        if (!(ratio * bestn > floor_ && ratio * bestn * big * unit > tol)) break; /* nothing larger remains */
        ++kept;
        for (int q = 0; q < left; ++q) {
            double *c = C + (size_t)q * nf, p = kin__dot(nf, v, c);
            for (int i = 0; i < nf; ++i) c[i] -= p * v[i];
        }
    }
    *mr = kept;
    if (!Um && a->nfix == 0 && kept == nnull) {
        /* A free structure's basis for the LU modes' border, oriented as the
         * rigid fields in their fixed order (translations, rotations),
         * which change continuously with the configuration: Gram-Schmidt
         * keeps the orientation of the candidates in pivot order, so the
         * pivot order's parity is the basis's orientation. Without this the
         * pivoting (three translations of equal norm, rotations whose
         * norms cross) turned the border's determinant over where nothing
         * happens (issue 36 item 1). */
        int odd = 0;
        for (int i = 0; i < kept; ++i)
            for (int j = i + 1; j < kept; ++j) odd ^= order[i] > order[j];
        if (odd)
            for (int i = 0; i < nf; ++i) R[i] = -R[i];
    }
    return KIN_OK;
}

int kin__rigid_basis(kin_assembly *a, const double *xyz, double *R, int *mr)
{
    return rigid_mechanisms(a, xyz, NULL, 0, R, mr, NULL);
}

/* The split (Pellegrino & Calladine 1986): the rigid mechanisms are the
 * rigid motions that keep the supports, projected on U_m (they lie in it up
 * to rounding) and orthonormalised (rigid_mechanisms); the internal ones
 * are the orthonormal complement of span(Urig) in span(U_m), found in the
 * m-dimensional coefficient space by one Householder QR of Z = U_m^T Urig
 * (m x m_rigid, orthonormal columns): U_m Q's last m - m_rigid columns.
 * Cost O(nf m m_rigid) after the rigid fields, where the pivoted
 * Gram-Schmidt over every unit vector it replaces cost O(m^4) (issue 24,
 * docs/performance.md "the rigid/internal split"). */
int kin__split_basis(kin_assembly *a, const double *xyz, const double *Um, int m, double *Urig, double *Uint,
                     int *mr, double *work)
{
    int nf = a->nf, kept = 0, info = 0;
    *mr = 0;
    if (m == 0) return KIN_OK;
    int rc = rigid_mechanisms(a, xyz, Um, m, Urig, &kept, work);
    if (rc) return rc;
    *mr = kept;
    int mi = m - kept;
    if (mi > 0) {
        memcpy(Uint, Um, sizeof(double) * (size_t)nf * (size_t)m);
        if (kept > 0) {
            double *Z = work, *tau = Z + (size_t)6 * m, *w = tau + 6; /* m x kept, kept, max(nf, kept) */
            for (int c = 0; c < kept; ++c)
                for (int r = 0; r < m; ++r)
                    Z[r + (size_t)c * m] = kin__dot(nf, Um + (size_t)r * nf, Urig + (size_t)c * nf);
            dgeqr2_(&m, &kept, Z, &m, tau, w, &info);
            if (info == 0) dorm2r_("R", "N", &nf, &m, &kept, Z, &m, tau, Uint, &nf, w, &info, 1, 1);
            if (info != 0) return kin__fail(a, KIN_ELAPACK_ARG, "dgeqr2/dorm2r (mechanism split) info = %d", info);
            memmove(Uint, Uint + (size_t)kept * nf, sizeof(double) * (size_t)nf * (size_t)mi);
        }
        for (int c = 0; c < mi; ++c) orient(nf, Uint + (size_t)c * nf);
    }
    for (int c = 0; c < kept; ++c) orient(nf, Urig + (size_t)c * nf);
    return KIN_OK;
}

