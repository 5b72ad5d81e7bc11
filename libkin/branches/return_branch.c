/* The branch a return to a bifurcation start comes back along (the
 * follower's closed-loop test, follow_watch.c), decided from the start's
 * second-order equations (paper 3.3, eq. 18), not from a step through the
 * start.
 *
 * Why. A step back through a many-fold bifurcation (the hexagonal sail's
 * flat state: m = 16, 29,828 branch lines, the closest 6e-4 rad apart) can
 * land on a neighbouring branch, and the direction measured there named the
 * wrong branch (issue 36 item 2: 6 returns along another branch were called
 * loops along their own, and the label moved with the step size). Here the
 * direction the path arrives along, t0 (measured on the arriving side:
 * the secant from the last point before the start, or the tangent at the
 * point within loop_tol), is projected on the start's mechanisms,
 * beta0 = U_m^T t0 / |U_m^T t0|, and Newton on the square system
 *     beta^T Q_j beta = 0 (j < s),  (beta^T beta - 1) / 2 = 0   (m = s + 1)
 * brings it to an exact second-order solution r: a branch direction U_m r
 * that does not depend on where the steps fell. The return branch is the
 * caller's line that U_m r is (within RETURN_ROOT_MATCH); the decision is
 * made only when it is clear: the root is on a line, t0 is nearest that
 * same line and nearer it than any other line by branch_margin. Anything
 * else (Newton not converging, a root on no line, a root t0 is not clearly
 * nearest, an arrival not in the mechanism space) is undecided, and the
 * follower does not call it a loop. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "branches/follow_internal.h"
#include "model/lapack.h"

/* the arrival direction must lie in the start's mechanism space to this
 * fraction of its length (a path arriving at the start is tangent to a
 * branch: |U^T t0| / |t0| = 1 - O(distance x curvature)) */
static const double RETURN_IN_MECHANISMS = 0.9;
/* Newton: at most this many iterations; converged when the step is below
 * RETURN_NEWTON_STEP and the residual (the Q_j are orthonormal in the
 * Frobenius norm, beta is a unit vector: the equations are of order 1) below
 * RETURN_NEWTON_RESIDUAL, the certified roots' own test (kin_quadrics_scan) */
enum { RETURN_NEWTON_MAX = 40 };
static const double RETURN_NEWTON_STEP = 1e-12;
static const double RETURN_NEWTON_RESIDUAL = 1e-12;
/* U_m r is the caller's line when within this angle (radians) of it: the
 * lines are certified roots (1e-12 residual), the closest pair at the flat
 * state 6e-4 rad apart */
static const double RETURN_ROOT_MATCH = 1e-6;

/* angle (radians, in [0, pi/2]) between the lines of u and v (n entries):
 * atan2 of the sine and |cosine|, accurate for nearly parallel lines */
static double line_angle(int n, const double *u, const double *v)
{
    double uu = kin__dot(n, u, u), vv = kin__dot(n, v, v), uv = kin__dot(n, u, v);
    if (!(uu > 0.0 && vv > 0.0)) return HALF_PI;
    double s2 = 0.0, k = uv / vv;
    for (int i = 0; i < n; ++i) s2 += (u[i] - k * v[i]) * (u[i] - k * v[i]);
    return atan2(sqrt(s2 / uu), fabs(uv) / sqrt(uu * vv));
}

/* the branch nearest the line of t: its index, angle, and the gap to the
 * next nearest (INFINITY with one branch) */
int kin__follow_nearest_branch(const follow_ctx *c, const double *t, double *angle, double *gap)
{
    int nf = c->a->nf, best = -1;
    double b1 = INFINITY, b2 = INFINITY;
    for (int j = 0; j < c->x->nbranch; ++j) {
        double g = line_angle(nf, t, c->x->branches + (size_t)j * nf);
        if (g < b1) {
            b2 = b1;
            b1 = g;
            best = j;
        } else if (g < b2) {
            b2 = g;
        }
    }
    *angle = b1;
    *gap = b2 - b1;
    return best;
}

int kin__return_open(follow_ctx *c)
{
    const kin_assembly *a = c->a;
    const kin_factor *f = kin__cur(a);
    c->ret_m = 0;
    if (!f->valid) return KIN_OK; /* no SVD analysis at the start: the arrival direction alone decides */
    int m = f->an.m_internal, nf = a->nf;
    if (f->an.s != m - 1) return KIN_OK; /* no isolated second-order solutions to converge to */
    size_t mm = (size_t)m * (size_t)m;
    /* U (nf x m), Q (s m m), the Jacobian (m m), F, Q_j beta, beta (m
     * each), U beta (nf), the pivots (m) */
    c->ret_U = malloc(sizeof(double) * ((size_t)nf * (size_t)m + mm * (size_t)m + 3 * (size_t)m + (size_t)nf) +
                      sizeof(int) * (size_t)m);
    if (!c->ret_U) return kin__fail(c->a, KIN_ENOMEM, "follow: the start's second-order equations");
    c->ret_Q = c->ret_U + (size_t)nf * m;
    c->ret_J = c->ret_Q + mm * (size_t)(m - 1);
    c->ret_F = c->ret_J + mm;
    c->ret_qb = c->ret_F + m;
    c->ret_beta = c->ret_qb + m;
    c->ret_tr = c->ret_beta + m;
    c->ret_ipiv = (int *)(c->ret_tr + nf);
    int s = 0;
    if (kin_second_order(a, KIN_Q_EXACT, 1, c->ret_Q, (int)(mm * (size_t)(m - 1)), &s) != KIN_OK || s != m - 1) {
        free(c->ret_U);
        c->ret_U = NULL;
        return KIN_OK;
    }
    memcpy(c->ret_U, f->Uint, sizeof(double) * (size_t)nf * (size_t)m);
    c->ret_m = m;
    return KIN_OK;
}

void kin__return_close(follow_ctx *c)
{
    free(c->ret_U);
    c->ret_U = NULL;
}

/* Newton on eq. 18 with |beta| = 1 from beta (m entries, unit), in place:
 * 1 converged to a root, 0 not */
static int newton_root(follow_ctx *c, double *beta)
{
    int m = c->ret_m, s = m - 1, one = 1, info = 0;
    double *J = c->ret_J, *F = c->ret_F, *qb = c->ret_qb;
    int *ipiv = c->ret_ipiv;
    for (int it = 0; it < RETURN_NEWTON_MAX; ++it) {
        double res = 0.0;
        for (int j = 0; j < s; ++j) {
            const double *Q = c->ret_Q + (size_t)j * m * m;
            double fj = 0.0;
            for (int p = 0; p < m; ++p) {
                double v = 0.0;
                for (int q = 0; q < m; ++q) v += Q[p + (size_t)q * m] * beta[q];
                qb[p] = v;
                fj += beta[p] * v;
            }
            F[j] = -fj;
            for (int p = 0; p < m; ++p) J[j + (size_t)p * m] = 2.0 * qb[p];
            res = fmax(res, fabs(fj));
        }
        F[s] = -0.5 * (kin__dot(m, beta, beta) - 1.0);
        res = fmax(res, fabs(F[s]));
        for (int p = 0; p < m; ++p) J[s + (size_t)p * m] = beta[p];
        dgetrf_(&m, &m, J, &m, ipiv, &info);
        if (info != 0) return 0; /* a singular Jacobian: not a simple root here */
        dgetrs_("N", &m, &one, J, &m, ipiv, F, &m, &info, 1);
        if (info != 0) return 0;
        double step = sqrt(kin__dot(m, F, F));
        for (int p = 0; p < m; ++p) beta[p] += F[p];
        if (!isfinite(step)) return 0;
        if (step <= RETURN_NEWTON_STEP) return res <= RETURN_NEWTON_RESIDUAL;
    }
    return 0;
}

/* the caller's line nearest the line of t (its lines, or o->return_fn):
 * its index, or < 0 when return_fn failed (c->hook_rc set) */
static int nearest_line(follow_ctx *c, const double *t, double *ang, double *gap)
{
    int nf = c->a->nf;
    if (!c->o->return_fn) return kin__follow_nearest_branch(c, t, ang, gap);
    *ang = *gap = NAN;
    int j = c->o->return_fn(c->o->return_user, t, nf, ang, gap);
    if (j < 0) {
        c->hook_rc = kin__fail(c->a, KIN_ECANCELLED, "follow: return_fn stopped the follow (returned %d)", j);
        return -1;
    }
    if (!(*ang >= 0.0 && *ang <= HALF_PI * (1.0 + 1e-12)) || !(*gap >= 0.0)) {
        c->hook_rc = kin__fail(c->a, KIN_EINVAL, "follow: return_fn gave angle %g, gap %g", *ang, *gap);
        return -1;
    }
    return j;
}

int kin__return_branch(follow_ctx *c, const double *t0, double *angle, double *gap)
{
    int nf = c->a->nf, m = c->ret_m;
    double a0 = 0.0, g0 = 0.0;
    int j0 = nearest_line(c, t0, &a0, &g0);
    if (j0 < 0) return -1;
    *angle = a0;
    *gap = g0;
    if (!(g0 >= c->o->branch_margin)) return KIN_FOLLOW_RETURN_UNDECIDED; /* t0 is not clearly near one line */
    if (m == 0) return j0; /* no second-order equations at the start: the arrival direction decides */
    double *beta = c->ret_beta, *tr = c->ret_tr;
    for (int p = 0; p < m; ++p) beta[p] = kin__dot(nf, c->ret_U + (size_t)p * nf, t0);
    double nb = sqrt(kin__dot(m, beta, beta)), nt = sqrt(kin__dot(nf, t0, t0));
    if (!(nb >= RETURN_IN_MECHANISMS * nt)) return KIN_FOLLOW_RETURN_UNDECIDED;
    for (int p = 0; p < m; ++p) beta[p] /= nb;
    if (!newton_root(c, beta)) return KIN_FOLLOW_RETURN_UNDECIDED;
    for (int i = 0; i < nf; ++i) {
        double v = 0.0;
        for (int p = 0; p < m; ++p) v += c->ret_U[i + (size_t)p * nf] * beta[p];
        tr[i] = v;
    }
    double ar = 0.0, gr = 0.0;
    int j = nearest_line(c, tr, &ar, &gr);
    if (j < 0) return -1;
    /* the root must be the caller's line that t0 is clearly nearest: else
     * Newton went to another root (or to one not among the lines) */
    return j == j0 && ar <= RETURN_ROOT_MATCH ? j : KIN_FOLLOW_RETURN_UNDECIDED;
}
