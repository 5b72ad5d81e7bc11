/* The paper's root scan (3.3.1): Newton-type solves of the quadrics
 * beta^T Q_j beta = 0 with |beta| = 1 from many starting points, by GSL's
 * hybridsj solver with the analytic Jacobian. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>

#include "model/internal.h"

/* a root: max residual of the s + 1 equations */
static const double ROOT_TOL = 1e-12;
static const int ROOT_MAX_ITER = 200;
/* eq. 20: two unit solutions are the same line if |beta_i . beta_j| > 1 - this */
static const double SAME_ROOT_TOL = 1e-8;
/* the scan keeps a solution, a start and a residual on the stack */
enum { SCAN_MAX_M = 256 };

typedef struct quadrics {
    int m, s;
    const double *Q;
} quadrics;

static int f_eval(const gsl_vector *x, void *p, gsl_vector *f)
{
    const quadrics *q = p;
    int m = q->m;
    for (int j = 0; j < q->s; ++j) {
        const double *Qj = q->Q + (size_t)j * m * m;
        double v = 0.0;
        for (int c = 0; c < m; ++c) {
            double row = 0.0;
            for (int r = 0; r < m; ++r) row += Qj[r + (size_t)c * m] * gsl_vector_get(x, r);
            v += row * gsl_vector_get(x, c);
        }
        gsl_vector_set(f, j, v);
    }
    double n2 = 0.0;
    for (int r = 0; r < m; ++r) n2 += gsl_vector_get(x, r) * gsl_vector_get(x, r);
    gsl_vector_set(f, q->s, n2 - 1.0);
    return GSL_SUCCESS;
}

static int df_eval(const gsl_vector *x, void *p, gsl_matrix *J)
{
    const quadrics *q = p;
    int m = q->m;
    for (int j = 0; j < q->s; ++j) {
        const double *Qj = q->Q + (size_t)j * m * m;
        for (int c = 0; c < m; ++c) {
            double v = 0.0; /* d/dbeta_c of beta^T Q beta = 2 (Q beta)_c for symmetric Q */
            for (int r = 0; r < m; ++r) v += (Qj[c + (size_t)r * m] + Qj[r + (size_t)c * m]) * gsl_vector_get(x, r);
            gsl_matrix_set(J, j, c, v);
        }
    }
    for (int c = 0; c < m; ++c) gsl_matrix_set(J, q->s, c, 2.0 * gsl_vector_get(x, c));
    return GSL_SUCCESS;
}

static int fdf_eval(const gsl_vector *x, void *p, gsl_vector *f, gsl_matrix *J)
{
    f_eval(x, p, f);
    return df_eval(x, p, J);
}

/* a standard normal draw (Box-Muller) from the caller's generator state */
static double gauss(unsigned long long *s)
{
    double u1 = ((kin__splitmix(s) >> 11) + 0.5) / 9007199254740992.0;
    double u2 = ((kin__splitmix(s) >> 11) + 0.5) / 9007199254740992.0;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* every entry of the s matrices m x m finite */
static int all_finite(const double *Q, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(Q[i])) return 0;
    return 1;
}

/* GSL's error handler is process-wide state that belongs to the
 * application: this file never changes it, and avoids every GSL error that
 * would call it (GSL calls it only for errors raised with GSL_ERROR, not for
 * status codes returned). Of the calls below (GSL 2.7 sources), the hybridsj
 * set and iterate steps, their QR factorization and updates, the residual
 * test, vector views and gsl_vector_get/set raise only for inconsistent
 * sizes, an index out of range or a negative tolerance, none of which can
 * happen here (every size is m, indices < m, the tolerance positive); a
 * singular or non-finite Jacobian is not an error to hybridsj (the dogleg
 * step proceeds; lack of progress comes back as GSL_ENOPROG/ENOPROGJ from
 * iterate). What remains is gsl_multiroot_fdfsolver_alloc, which raises
 * GSL_ENOMEM if malloc fails; x and f are views on stack arrays, so that is
 * the call's one GSL allocation (about 3 m^2 + 16 m doubles). */
static int scan_impl(int m, int s, const double *Q, int starts, unsigned long seed, double *betas, int maxsol,
                     int *nsol, kin_solve_info *info)
{
    if (nsol) *nsol = 0;
    if (info) memset(info, 0, sizeof *info);
    if (!Q || !betas || !nsol) return KIN_ENULL;
    if (m < 2 || s != m - 1 || starts < 1 || maxsol < 1) return KIN_EINVAL;
    if (m > SCAN_MAX_M) return KIN_ERANGE;
    if (!all_finite(Q, (size_t)m * (size_t)m * (size_t)s)) return KIN_EINVAL;
    quadrics q = {m, s, Q};
    gsl_multiroot_function_fdf fn = {f_eval, df_eval, fdf_eval, (size_t)m, &q};
    /* every start adds at most one distinct solution: room for all of them,
     * so the duplicate test (eq. 20) sees every solution kept */
    size_t bytes;
    double *found = kin__mul_size3((size_t)m, (size_t)starts, sizeof(double), &bytes) ? malloc(bytes) : NULL;
    if (!found) return KIN_ENOMEM;
    gsl_multiroot_fdfsolver *sv = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, (size_t)m);
    if (!sv) {
        free(found);
        return KIN_ENOMEM;
    }
    double xbuf[SCAN_MAX_M], fbuf[SCAN_MAX_M];
    gsl_vector_view xview = gsl_vector_view_array(xbuf, (size_t)m), fview = gsl_vector_view_array(fbuf, (size_t)m);
    gsl_vector *x = &xview.vector, *fv = &fview.vector;
    kin_solve_info in = {.size = sizeof in, .starts = starts};
    unsigned long long state = (unsigned long long)seed * 0x2545F4914F6CDD1Dull + 1u;
    int nd = 0;
    for (int k = 0; k < starts; ++k) {
        double n2 = 0.0;
        for (int r = 0; r < m; ++r) {
            double g = gauss(&state);
            gsl_vector_set(x, r, g);
            n2 += g * g;
        }
        gsl_vector_scale(x, 1.0 / sqrt(n2));
        if (gsl_multiroot_fdfsolver_set(sv, &fn, x) != GSL_SUCCESS) {
            in.gsl_errors++;
            continue;
        }
        int status = GSL_CONTINUE, it = 0;
        while (status == GSL_CONTINUE && it++ < ROOT_MAX_ITER) {
            int e = gsl_multiroot_fdfsolver_iterate(sv);
            if (e) { status = e; break; }
            status = gsl_multiroot_test_residual(sv->f, ROOT_TOL);
        }
        if (status != GSL_SUCCESS) {
            if (status != GSL_CONTINUE) in.gsl_errors++;
            continue;
        }
        in.converged++;
        /* normalise, fix the sign, drop duplicates (eq. 20) */
        double b[SCAN_MAX_M], nb = 0.0;
        int big = 0;
        for (int r = 0; r < m; ++r) {
            b[r] = gsl_vector_get(sv->x, r);
            nb += b[r] * b[r];
        }
        nb = sqrt(nb);
        for (int r = 0; r < m; ++r) {
            b[r] /= nb;
            if (fabs(b[r]) > fabs(b[big]) * (1.0 + 1e-12)) big = r;
        }
        if (b[big] < 0)
            for (int r = 0; r < m; ++r) b[r] = -b[r];
        int dup = 0;
        for (int i = 0; i < nd && !dup; ++i) {
            double dot = 0.0;
            for (int r = 0; r < m; ++r) dot += found[(size_t)i * m + r] * b[r];
            dup = fabs(dot) > 1.0 - SAME_ROOT_TOL;
        }
        if (dup) continue;
        gsl_vector_view bv = gsl_vector_view_array(b, (size_t)m);
        f_eval(&bv.vector, &q, fv);
        for (int j = 0; j < s; ++j)
            if (fabs(gsl_vector_get(fv, j)) > in.max_residual) in.max_residual = fabs(gsl_vector_get(fv, j));
        memcpy(found + (size_t)nd * m, b, sizeof(double) * (size_t)m);
        if (nd < maxsol) memcpy(betas + (size_t)nd * m, b, sizeof(double) * (size_t)m);
        ++nd;
    }
    in.distinct = nd;
    *nsol = nd < maxsol ? nd : maxsol;
    if (info) *info = in;
    gsl_multiroot_fdfsolver_free(sv);
    free(found);
    return KIN_OK;
}

int kin_quadrics_scan(int m, int s, const double *Q, int starts, unsigned long seed, double *betas,
                      int maxsol, int *nsol, kin_solve_info *info)
{
    if (info) {
        if (kin__abi_check(info, KIN__ABI(kin_solve_info))) {
            if (nsol) *nsol = 0;
            return KIN_EINVAL;
        }
        kin__abi_zero(info);
    }
    kin_solve_info local = {.size = sizeof local};
    int rc = scan_impl(m, s, Q, starts, seed, betas, maxsol, nsol, &local);
    if (info) kin__abi_write(info, &local, KIN__ABI(kin_solve_info));
    return rc;
}
