/* Detecting and converging onto bifurcation points (paper section 4) with a
 * signed test function; see kin_locate.h. */
#include <math.h>
#include <string.h>

#include "internal.h"
#include "lapack.h"

/* eq. 26: the path is kept if the new tangent agrees with the old one to this |cos| */
static const double PATH_KEPT_COS = 0.9;
/* overshoot probe of the paper's method, as a fraction of the trial delta */
static const double PROBE_FRACTION = 1e-3;
/* the paper's method gives up when delta has shrunk below this fraction of
 * the step without reaching the tolerance: v_r has a non-zero minimum */
static const double GIVE_UP_FRACTION = 1e-9;
/* while locating, singular values count as zero only below this fraction of
 * the target tolerance, so that the test function keeps its sign (and the
 * analysis its single mechanism) until the target is met */
static const double LOCATE_RANK_FRACTION = 1e-3;

void kin_locate_options_default(kin_locate_options *o)
{
    if (!o) return;
    o->method = KIN_LOCATE_FAST;
    o->vr_tol = 1e-10;
    o->switch_eps = 1e-2;
    o->delta = 0.0;
    o->max_steps = 1000;
    o->max_iter = 60;
    o->use_switch_rule = 1;
}

int kin_test_function(kin_assembly *a, double *tau)
{
    if (!a || !tau) return KIN_ENULL;
    if (!kin__cur(a)->valid) {
        int rc = kin_analyse(a, NULL);
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
    for (int c = 0; c < mr; ++c) {
        const double *r = f->Urig + (size_t)c * nf;
        double sg = a->have_Rref && kin__dot(nf, r, R + (size_t)c * nf) < 0.0 ? -1.0 : 1.0;
        for (int i = 0; i < nf; ++i) R[i + (size_t)c * nf] = sg * r[i];
    }
    a->have_Rref = 1;
    if (nb + 1 + mr != nf) {
        /* redundant bars on the path (s > 0): no square border, no sign */
        *tau = f->an.v_r;
        return KIN_OK;
    }
    double *B = a->mwork;
    int *ipiv = a->iwork, info = 0;
    kin__build_H(a, a->xyz, a->H, nf);
    for (int k = 0; k < nb; ++k)
        for (int i = 0; i < nf; ++i) B[k + (size_t)i * nf] = a->H[i + (size_t)k * nf];
    for (int i = 0; i < nf; ++i) B[nb + (size_t)i * nf] = t[i];
    for (int c = 0; c < mr; ++c)
        for (int i = 0; i < nf; ++i) B[nb + 1 + c + (size_t)i * nf] = R[i + (size_t)c * nf];
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

typedef struct loc_ctx {
    kin_assembly *a, *prev, *work, *probe;
    const kin_locate_options *o;
    kin_locate_info *info;
} loc_ctx;

static double rel(const kin_assembly *a) { return kin__cur(a)->an.v_r / kin__cur(a)->an.v_max; }

/* the singular value that vanishes at a bifurcation: index r_path - 1, where
 * a point on a path has rank r_path = nfree - 1 - m_rigid */
static double vanishing_sv(const kin_assembly *a)
{
    const kin_factor *f = kin__cur(a);
    int mn = a->nf < a->nb ? a->nf : a->nb, k = a->nf - 2 - f->an.m_rigid;
    return k >= 0 && k < mn ? f->sv[k] : f->an.v_r;
}

static int at_bifurcation(const kin_assembly *a, double tol)
{
    const kin_factor *f = kin__cur(a);
    return vanishing_sv(a) <= tol * f->an.v_max;
}

/* forward calculation: work := base moved by delta along its tangent */
static int forward(loc_ctx *c, const kin_assembly *base, kin_assembly *dst, double delta, double *used)
{
    kin__copy_state(dst, base);
    kin_step_info si;
    c->info->forward++;
    int rc = kin_step(dst, delta, &si);
    if (used) *used = rc == KIN_OK ? si.delta : 0.0;
    return rc;
}

static double tangent_cos(const kin_assembly *x, const kin_assembly *y)
{
    return fabs(kin__dot(x->nf, x->t, y->t));
}

/* Illinois iteration on tau(delta) over [0, hi] from prev (tau_lo there) */
static int locate_fast(loc_ctx *c, double hi, double tau_lo, double tau_hi)
{
    double lo = 0.0, width0 = fabs(hi);
    int side = 0;
    for (int it = 0; it < c->o->max_iter; ++it) {
        if (fabs(hi - lo) < GIVE_UP_FRACTION * width0) {
            /* the bracket has collapsed but v_r stays finite: tau changed sign
             * without a zero, i.e. the step crossed a near-singular but
             * regular configuration onto a neighbouring sheet of the path */
            return kin__fail(c->a, KIN_ENOTFOUND,
                             "no bifurcation: the test function changed sign but v_r stays at %.3g relative "
                             "(a near-singular regular configuration; take smaller steps here)",
                             rel(c->work));
        }
        double d = hi - tau_hi * (hi - lo) / (tau_hi - tau_lo);
        if (!(d > fmin(lo, hi) && d < fmax(lo, hi))) d = 0.5 * (lo + hi);
        double used;
        int rc = forward(c, c->prev, c->work, d, &used);
        if (rc != KIN_OK || used != d) {
            d = 0.5 * (lo + hi);
            rc = forward(c, c->prev, c->work, d, &used);
            if (rc != KIN_OK) return rc;
        }
        if (at_bifurcation(c->work, c->o->vr_tol)) return KIN_OK;
        double tau;
        rc = kin_test_function(c->work, &tau);
        if (rc) return rc;
        if (tau == 0.0) return KIN_OK;
        if ((tau > 0) == (tau_hi > 0)) {
            hi = used;
            tau_hi = tau;
            if (side == 1) tau_lo *= 0.5; /* Illinois: halve the stale end */
            side = 1;
        } else {
            lo = used;
            tau_lo = tau;
            if (side == -1) tau_hi *= 0.5;
            side = -1;
        }
    }
    return kin__fail(c->a, KIN_ENOTFOUND, "signed test function: no convergence in %d iterations",
                     c->o->max_iter);
}

/* the paper's method: quadratic through the last three (l, v_r) */
static int locate_paper(loc_ctx *c, double *hl, double *hv, int nh, double step)
{
    kin_assembly *base = c->prev;
    double delta = 0.0, shrink = 1.0;
    for (int it = 0; it < c->o->max_iter; ++it) {
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
                             rel(base));
        double used;
        int rc = forward(c, base, c->work, delta, &used);
        if (rc != KIN_OK) { shrink *= 0.5; continue; }
        if (at_bifurcation(c->work, c->o->vr_tol)) {
            if (tangent_cos(c->work, base) >= PATH_KEPT_COS || kin__cur(c->work)->an.m_internal >= 2) return KIN_OK;
        }
        /* eq. 26: still on the same path? */
        if (kin__cur(c->work)->an.m_internal == 1 && tangent_cos(c->work, base) < PATH_KEPT_COS) {
            shrink *= 0.5;
            continue;
        }
        /* overshoot probe: a small extra step; v_r growing means we crossed */
        rc = forward(c, c->work, c->probe, PROBE_FRACTION * delta, NULL);
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
                     rel(base), c->o->max_iter);
}

int kin_locate_next(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info)
{
    if (!a) return KIN_ENULL;
    kin_locate_options o;
    if (opt) o = *opt;
    else kin_locate_options_default(&o);
    if ((o.method != KIN_LOCATE_PAPER && o.method != KIN_LOCATE_FAST) || !(o.vr_tol > 0 && o.vr_tol < 1) ||
        !(o.switch_eps > 0 && o.switch_eps < 1) || !isfinite(o.delta) || o.max_steps < 1 || o.max_iter < 1)
        return kin__fail(a, KIN_EINVAL, "locate options out of range");
    kin_locate_info dummy;
    if (!info) info = &dummy;
    memset(info, 0, sizeof *info);
    int rc = kin__cur(a)->valid ? KIN_OK : kin_analyse(a, NULL);
    if (rc) return rc;
    if (kin__cur(a)->an.m_internal >= 2)
        return kin__fail(a, KIN_EBIFURCATION, "already at a bifurcation (m_internal = %d)",
                         kin__cur(a)->an.m_internal);
    loc_ctx c = {a, NULL, NULL, NULL, &o, info};
    kin_options user = a->opt;
    double fine = fmin(user.rank_tol, LOCATE_RANK_FRACTION * o.vr_tol);
    a->opt.rank_tol = fine;
    if (kin_assembly_clone(a, &c.prev) || kin_assembly_clone(a, &c.work) || kin_assembly_clone(a, &c.probe)) {
        a->opt = user;
        kin_assembly_free(c.prev);
        kin_assembly_free(c.work);
        kin_assembly_free(c.probe);
        return kin__fail(a, KIN_ENOMEM, "locator working copies");
    }
    double tau0, tau1, hl[4], hv[4];
    int nh = 0;
    rc = kin_test_function(a, &tau0);
    hl[nh] = a->l;
    hv[nh++] = kin__cur(a)->an.v_r;
    kin_step_info si;
    long fa = 0, fw = 0, fp = 0, fpv = 0;
    while (rc == KIN_OK && info->steps < o.max_steps) {
        kin__copy_state(c.prev, a);
        rc = kin_step(a, o.delta, &si);
        if (rc) break;
        info->steps++;
        if (si.m_internal >= 2) {
            info->event = KIN_EVENT_LANDED;
            break;
        }
        rc = kin_test_function(a, &tau1);
        if (rc) break;
        double vr = kin__cur(a)->an.v_r, vmax = kin__cur(a)->an.v_max;
        if (tau0 != 0.0 && tau1 != 0.0 && (tau0 > 0) != (tau1 > 0)) {
            info->event = KIN_EVENT_SIGN_CHANGE;
            break;
        }
        if (nh == 4) { memmove(hl, hl + 1, 3 * sizeof *hl); memmove(hv, hv + 1, 3 * sizeof *hv); nh = 3; }
        hl[nh] = a->l;
        hv[nh++] = vr;
        if (o.method == KIN_LOCATE_PAPER && o.use_switch_rule && vr < o.switch_eps * vmax && vr < hv[nh - 2]) {
            info->event = KIN_EVENT_SWITCH_RULE;
            kin__copy_state(c.prev, a);
            break;
        }
        if (o.method == KIN_LOCATE_FAST && nh >= 3 && hv[nh - 2] < o.switch_eps * vmax &&
            hv[nh - 2] < hv[nh - 3] && vr > hv[nh - 2]) {
            /* v_r passed a small minimum without tau changing sign: an even
             * number of singular values crossed zero, or a non-zero minimum.
             * Fall back to the paper's method from the point before. */
            info->event = KIN_EVENT_SWITCH_RULE;
            nh--;
            break;
        }
        tau0 = tau1;
    }
    fa = a->nfact;
    fw = c.work->nfact;
    fp = c.probe->nfact;
    fpv = c.prev->nfact;
    if (rc == KIN_OK && info->event == KIN_EVENT_NONE)
        rc = kin__fail(a, KIN_ENOTFOUND, "no bifurcation within %d steps", o.max_steps);
    if (rc == KIN_OK && info->event != KIN_EVENT_LANDED) {
        double step = o.delta != 0.0 ? fabs(o.delta) : a->opt.step_fraction * a->rms_length;
        if (info->event == KIN_EVENT_SIGN_CHANGE && o.method == KIN_LOCATE_FAST) {
            rc = locate_fast(&c, si.delta, tau0, tau1);
        } else {
            /* the paper's method; also the fallback when tau does not change sign */
            /* the history ends at c.prev, the last point before the bifurcation */
            rc = nh >= 2 ? locate_paper(&c, hl, hv, nh, step) : kin__fail(a, KIN_ENOTFOUND, "too little history");
        }
        if (rc == KIN_OK) {
            /* eq. 26: the move from the last regular point must continue its
             * tangent, or the search slid onto a neighbouring path */
            double *ch = c.probe->chord, *x1 = c.probe->x;
            kin__gather(a, c.prev->xyz, ch);
            kin__gather(a, c.work->xyz, x1);
            for (int i = 0; i < a->nf; ++i) ch[i] = x1[i] - ch[i];
            double n = kin__norm(a->nf, ch);
            info->path_kept = n == 0.0 || fabs(kin__dot(a->nf, ch, c.prev->t)) >= PATH_KEPT_COS * n;
            /* move the caller's assembly onto the located point */
            double dist = 0.0;
            for (int i = 0; i < a->nj * a->dim; ++i) dist += (c.work->xyz[i] - a->xyz[i]) * (c.work->xyz[i] - a->xyz[i]);
            info->distance = sqrt(dist);
            long keep = a->nfact;
            kin__copy_state(a, c.work);
            a->nfact = keep;
        } else if (rc == KIN_ENOTFOUND) {
            /* leave the assembly at the best regular point: the base of the search */
            kin__copy_state(a, c.prev);
        }
    }
    if (rc == KIN_OK && info->event == KIN_EVENT_LANDED)
        info->path_kept = 1; /* an ordinary step landed there: its direction check applied */
    /* back to the caller's rank tolerance: analyse the final point afresh */
    a->opt = user;
    {
        int rc2 = kin_analyse(a, NULL);
        if (rc == KIN_OK) rc = rc2;
    }
    info->factorizations = (int)((a->nfact - fa) + (c.work->nfact - fw) + (c.probe->nfact - fp) + (c.prev->nfact - fpv));
    info->located = rc == KIN_OK;
    info->v_r = vanishing_sv(a);
    info->v_r_rel = kin__cur(a)->an.v_max > 0 ? info->v_r / kin__cur(a)->an.v_max : 0.0;
    info->m_internal = kin__cur(a)->an.m_internal;
    info->s = kin__cur(a)->an.s;
    kin_assembly_free(c.prev);
    kin_assembly_free(c.work);
    kin_assembly_free(c.probe);
    return rc;
}
