/* The paper's locator (Section 4, eq. 23-26): a quadratic in l through the
 * last three v_r, the path check of eq. 26 and the overshoot probe, delta
 * halved on a failed check (kin_locate.h, KIN_LOCATE_PAPER). */
#include <math.h>

#include "model/internal.h"
#include "locate/locate_internal.h"

/* overshoot probe of the paper's method, as a fraction of the trial delta */
static const double PROBE_FRACTION = 1e-3;
/* the paper's method gives up when delta has shrunk below this fraction of
 * the step without reaching the tolerance: v_r has a non-zero minimum */
static const double GIVE_UP_FRACTION = 1e-9;

/* A non-zero minimum of v_r, by the paper's own model (eq. 23): among the
 * sampled points (l[i], v[i]) find the lowest one with a higher neighbour on
 * each side along the path (a bracketed minimum) and fit the quadratic
 * through it and its neighbours. Near a bifurcation v_r is V-shaped (a
 * crossing: the fitted vertex lies at most half as high as the lowest sample,
 * usually below zero) or touches zero (a tangency, Figure 7(b): the vertex is
 * near zero); a near-singular regular point is a smooth minimum that the
 * quadratic fits, its vertex within NEAR_MISS_FIT of the lowest sample. Only
 * minima above NEAR_MISS_FLOOR x the tolerance count, where rounding cannot
 * fake that agreement. */
static const double NEAR_MISS_FIT = 0.9;
static const double NEAR_MISS_FLOOR = 100.0;
static int nonzero_minimum(double *l, double *v, int n, double v_tol, double *v_min)
{
    for (int i = 1; i < n; ++i) /* insertion sort by l: n <= 4 */
        for (int k = i; k > 0 && l[k] < l[k - 1]; --k) {
            double tl = l[k], tv = v[k];
            l[k] = l[k - 1]; v[k] = v[k - 1];
            l[k - 1] = tl; v[k - 1] = tv;
        }
    int best = -1;
    for (int i = 1; i + 1 < n; ++i)
        if (v[i] < v[i - 1] && v[i] < v[i + 1] && l[i - 1] < l[i] && l[i] < l[i + 1] &&
            (best < 0 || v[i] < v[best]))
            best = i;
    if (best < 0 || !(v[best] > NEAR_MISS_FLOOR * v_tol)) return 0;
    double x0 = l[best - 1], x1 = l[best], x2 = l[best + 1];
    double d01 = (v[best] - v[best - 1]) / (x1 - x0), d12 = (v[best + 1] - v[best]) / (x2 - x1);
    double A = (d12 - d01) / (x2 - x0);
    if (!(A > 0.0)) return 0;
    double B = d01 - A * (x0 + x1), C = v[best - 1] - A * x0 * x0 - B * x0;
    *v_min = C - B * B / (4 * A);
    TRACE("near-miss fit: %.6g %.6g | %.6g %.6g | %.6g %.6g -> vertex %.6g at %.6g\n", x0, v[best - 1], x1, v[best], x2,
          v[best + 1], *v_min, -B / (2 * A));
    return *v_min >= NEAR_MISS_FIT * v[best];
}

/* the paper's method: quadratic through the last three (l, v_r) */
int kin__locate_paper(loc_ctx *c, double *hl, double *hv, int nh, double step)
{
    kin_assembly *base = c->prev;
    double delta = 0.0, shrink = 1.0;
    for (int it = 0; it < c->o->max_iter; ++it) {
        if (kin__loc_cancelled(c)) return KIN_ECANCELLED;
        double ln;
        if (nh >= 3) {
            /* Lagrange quadratic v = A l^2 + B l + C through the last three points */
            double x0 = hl[nh - 3], x1 = hl[nh - 2], x2 = hl[nh - 1];
            double y0 = hv[nh - 3], y1 = hv[nh - 2], y2 = hv[nh - 1];
            double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
            double A = (d12 - d01) / (x2 - x0), B = d01 - A * (x0 + x1), C = y0 - A * x0 * x0 - B * x0;
            double disc = B * B - 4 * A * C;
            if (A != 0.0 && disc >= 0.0) {
                double r1 = (-B + sqrt(disc)) / (2 * A), r2 = (-B - sqrt(disc)) / (2 * A);
                /* Figure 7(a), and (b) translated down: the root nearest l_{n-1} ahead */
                double best = NAN;
                if ((r1 - x2) * (x2 - x1) > 0) best = r1;
                if ((r2 - x2) * (x2 - x1) > 0 && (isnan(best) || fabs(r2 - x2) < fabs(best - x2))) best = r2;
                ln = isnan(best) ? x2 + (x2 - x1) : best;
            } else if (A > 0.0) {
                ln = -B / (2 * A); /* Figure 7(b) translated up: the minimum */
                if ((ln - x2) * (x2 - x1) <= 0) ln = x2 + 0.5 * (x2 - x1);
            } else {
                ln = x2 + (x2 - x1);
            }
        } else {
            double x1 = hl[nh - 2], x2 = hl[nh - 1], y1 = hv[nh - 2], y2 = hv[nh - 1];
            ln = y2 < y1 ? x2 + y2 * (x2 - x1) / (y1 - y2) : x2 + (x2 - x1);
        }
        double dir = hl[nh - 1] >= hl[nh - 2] ? 1.0 : -1.0;
        delta = dir * fabs(ln - hl[nh - 1]) * shrink;
        if (fabs(delta) < GIVE_UP_FRACTION * step)
            return kin__fail(c->a, KIN_ENOTFOUND,
                             "v_r has a non-zero minimum (%.3g relative) here: a near-singular but regular configuration",
                             kin__loc_rel(base));
        double used;
        int rc = kin__loc_forward(c, base, c->work, delta, &used);
        if (rc != KIN_OK) { shrink *= 0.5; continue; }
        if (kin__loc_at_bifurcation(c->work, c->o->vr_tol)) {
            if (kin__loc_tangent_cos(c->work, base) >= KIN__PATH_KEPT_COS || kin__cur(c->work)->an.m_internal >= 2) return KIN_OK;
        }
        /* eq. 26: still on the same path? */
        if (kin__cur(c->work)->an.m_internal == 1 && kin__loc_tangent_cos(c->work, base) < KIN__PATH_KEPT_COS) {
            shrink *= 0.5;
            continue;
        }
        /* overshoot probe: a small extra step; v_r growing means we crossed */
        if (!kin__loc_probe(c)) return kin__fail(c->a, KIN_ENOMEM, "locator working copies");
        rc = kin__loc_forward(c, c->work, c->probe, PROBE_FRACTION * delta, NULL);
        if (rc == KIN_OK) {
            /* the samples so far bracket a smooth non-zero minimum: no bifurcation here */
            double sl[4] = {base->l, c->work->l, c->probe->l, 0.0};
            double sv[4] = {kin__cur(base)->an.v_r, kin__cur(c->work)->an.v_r, kin__cur(c->probe)->an.v_r, 0.0};
            int ns = 3;
            if (nh >= 2) { sl[3] = hl[nh - 2]; sv[3] = hv[nh - 2]; ns = 4; }
            double v_min, v_max = kin__cur(base)->an.v_max;
            if (nonzero_minimum(sl, sv, ns, c->o->vr_tol * v_max, &v_min))
                return kin__fail(c->a, KIN_ENOTFOUND,
                                 "v_r has a non-zero minimum (%.3g relative, from the quadratic of eq. 23) "
                                 "here: a near-singular but regular configuration",
                                 v_min / v_max);
        }
        if (rc != KIN_OK || kin__cur(c->probe)->an.v_r > kin__cur(c->work)->an.v_r) {
            shrink *= 0.5;
            continue;
        }
        /* accept: the window moves on */
        kin__copy_state(base, c->work);
        if (nh >= 3) {
            hl[0] = hl[1]; hv[0] = hv[1];
            hl[1] = hl[2]; hv[1] = hv[2];
            nh = 2;
        }
        hl[nh] = base->l;
        hv[nh] = kin__cur(base)->an.v_r;
        ++nh;
        shrink = 1.0;
    }
    return kin__fail(c->a, KIN_ENOTFOUND, "paper's method: v_r %.3g relative after %d forward calculations",
                     kin__loc_rel(base), c->o->max_iter);
}
