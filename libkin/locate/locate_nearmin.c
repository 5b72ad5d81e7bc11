/* A near miss located at its minimum (locate.h, kin__locate_near_minimum;
 * docs/follow.md): v_r / v_max minimised along the path over the bracketing
 * step in which the detector saw v_r turn, by GSL's Brent minimiser on the
 * path parameter z = t0.(x - x0) (t0, x0: tangent and point at the
 * bracket's start; along one step z is the arc length to within the
 * tangent's turn, cos > 0.99). Each trial point is brought onto the path as
 * the fast locator brings its nodes: a forward calculation from the start
 * whose predictor is the cubic Hermite interpolant of the path through the
 * bracket's two ends. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_min.h>

#include "model/internal.h"
#include "path/path.h"
#include "locate/locate.h"
#include "locate/locate_internal.h"

/* the minimum's position is wanted to this fraction of the RMS rest length:
 * 100x below the explorer's identification tolerance (SAME_TOL, 1e-6), so
 * that a near miss and its image under a symmetry end at mapped points */
static const double NEAR_MIN_XTOL = 1e-8;
/* at most this many Brent iterations (one forward calculation and one SVD each) */
enum { NEAR_MIN_MAX_ITER = 60 };
/* a trial point that lands farther than this fraction of the bracket from
 * its predictor has left the path (as the locator's NODE_JUMP_FRACTION) */
static const double NEAR_MIN_JUMP = 0.25;
/* where the first guess (the cubic's minimum) is not below both ends: these
 * fractions of the bracket are tried */
static const double NEAR_MIN_PROBES[] = {0.5, 0.25, 0.75, 0.125, 0.875};
/* ... and where none is, the bracket moves a step the way v_r falls, at
 * most this many times */
enum { NEAR_MIN_EXTEND = 3 };
/* a minimum not clearly above the floor a crossing would leave at Brent's
 * width (kin__near_min.floor: its value not NEAR_MIN_MARGIN x above) is
 * narrowed further by golden sections, to this fraction of the RMS rest
 * length: a crossing (v_r linear in the distance to it) then shows v_r at
 * the strict tolerance, a smooth minimum keeps its value (issue 35 item 4) */
static const double NEAR_MIN_FINE = 1e-13;
static const double NEAR_MIN_MARGIN = 10.0;
enum { NEAR_MIN_FINE_ITER = 80 };
/* the relative accuracy of a computed v_r / v_max (the SVD's rounding):
 * the floor is never taken below it */
static const double NEAR_MIN_NOISE = 64.0 * 2.220446049250313e-16;

typedef struct nm_ctx {
    kin_assembly *start, *trial;
    const double *x0, *t0, *x1, *d1; /* nf each: the ends and their tangents dx/dz */
    double *pred, *xs;              /* nf each */
    double *sv;                     /* min(nf, nb): a trial's singular values */
    double z1, bad;                 /* the bracket's end; the value a failed trial gets */
    int nf, evals, failed;
} nm_ctx;

/* the cubic Hermite interpolant of the path at z (0 <= z <= z1) into out */
static void path_at(const nm_ctx *c, double z, double *out)
{
    double s = z / c->z1, h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
    double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
    for (int i = 0; i < c->nf; ++i)
        out[i] = h00 * c->x0[i] + h10 * c->z1 * c->t0[i] + h01 * c->x1[i] + h11 * c->z1 * c->d1[i];
}

/* v_r / v_max at the analysed state st (the vanishing singular value) */
static double rel_vr(const kin_assembly *st)
{
    double vmax = kin__cur(st)->an.v_max;
    return vmax > 0.0 ? kin__loc_vanishing_sv(st) / vmax : NAN;
}

/* c->trial := the path's point at z, analysed by SVD; its v_r / v_max (or
 * c->bad, with c->failed set, where the forward calculation fails) */
static double trial_value(double z, void *user)
{
    nm_ctx *c = user;
    c->evals++;
    path_at(c, z, c->pred);
    kin__copy_state(c->trial, c->start);
    /* the LU mode's factors at the trial (the SVD where it is not regular),
     * and its singular values alone (no vectors: a trial needs none) */
    kin_assembly *w = c->trial;
    w->opt.factorization = KIN_STEP_LU;
    w->lu_inverse = w->lu_predicted = 1;
    int rc = kin__step_predicted(w, z, c->pred, NULL);
    w->opt.factorization = KIN_STEP_SVD;
    w->lu_inverse = w->lu_predicted = 0;
    double jump = 0.0, f = NAN;
    if (rc == KIN_OK) {
        kin__gather(w, w->xyz, c->xs);
        for (int i = 0; i < c->nf; ++i) jump = fmax(jump, fabs(c->xs[i] - c->pred[i]));
        if (kin__cur(w)->valid) {
            f = rel_vr(w);
        } else if ((rc = kin__singular_values(w, w->xyz, c->sv)) == KIN_OK) {
            int k = kin__loc_vanishing_index(w);
            f = k >= 0 && c->sv[0] > 0.0 ? c->sv[k] / c->sv[0] : NAN;
        }
    }
    if (rc != KIN_OK || jump > NEAR_MIN_JUMP * fabs(c->z1) || !isfinite(f)) {
        c->failed = 1;
        return c->bad;
    }
    return f;
}

/* the bracket [st, end] into c: its ends, tangents and parameter; 0 where it is not a forward step */
static int set_bracket(nm_ctx *c, kin_assembly *st, const kin_assembly *end, double *x0, double *x1, double *d1)
{
    int nf = c->nf;
    c->start = st;
    c->t0 = st->t;
    kin__gather(st, st->xyz, x0);
    kin__gather(end, end->xyz, x1);
    double tt = kin__dot(nf, st->t, end->t), t00 = kin__dot(nf, st->t, st->t);
    c->z1 = 0.0;
    for (int i = 0; i < nf; ++i) c->z1 += st->t[i] * (x1[i] - x0[i]);
    if (!(fabs(tt) > 0.0) || !(fabs(t00 - 1.0) < 1e-6) || !(c->z1 > 0.0)) return 0;
    for (int i = 0; i < nf; ++i) d1[i] = end->t[i] / tt;
    return 1;
}

/* the floor at the minimum (zm, fm) located to the width w, in the bracket
 * [0, z1] with end values f0, f1: the v_r / v_max a crossing within w of zm
 * could still show there. A crossing's v_r is linear in the distance to it
 * (|z - z*| times a slope that the secants from the bracket's ends to zm
 * bound), so it shows at most the steeper secant x w; never below the
 * rounding of v_r */
static double near_floor(double z1, double f0, double f1, double zm, double fm, double w)
{
    double slope = 0.0;
    if (zm > 0.0 && isfinite(f0)) slope = fmax(slope, (f0 - fm) / zm);
    if (z1 > zm && isfinite(f1)) slope = fmax(slope, (f1 - fm) / (z1 - zm));
    return fmax(slope * w, NEAR_MIN_NOISE);
}

/* golden sections of [*lo, *hi] about its lowest point (*zm, *fm) down to
 * the width xtol, or until the minimum is NEAR_MIN_MARGIN x above its floor
 * (f0, f1: the bracket [0, c->z1]'s end values): where the minimum may be a
 * crossing Brent could not resolve (its steps stop at sqrt(eps) |z|) */
static void golden_refine(nm_ctx *c, double f0, double f1, double xtol, double *lo, double *zm, double *fm,
                          double *hi)
{
    const double g = 0.3819660112501051;
    for (int it = 0; it < NEAR_MIN_FINE_ITER && *hi - *lo > xtol; ++it) {
        if (near_floor(c->z1, f0, f1, *zm, *fm, *hi - *lo) * NEAR_MIN_MARGIN < *fm) break;
        int right = *hi - *zm > *zm - *lo;
        double x = right ? *zm + g * (*hi - *zm) : *zm - g * (*zm - *lo);
        if (!(x > *lo && x < *hi) || x == *zm) break; /* the bracket at the resolution of z */
        double fx = trial_value(x, c);
        if (fx < *fm) {
            *(right ? lo : hi) = *zm;
            *zm = x;
            *fm = fx;
        } else {
            *(right ? hi : lo) = x;
        }
    }
}

int kin__locate_near_minimum(kin_assembly *a, kin__locate_ws *ws, kin__near_min *out)
{
    memset(out, 0, sizeof *out);
    if (!ws || !ws->near_bracket || !ws->work || !ws->prev) return KIN_OK;
    int nf = a->nf, rc;
    kin_assembly *st = ws->prev, *end = ws->work;
    if (!ws->probe && kin_assembly_clone(a, &ws->probe)) return kin__fail(a, KIN_ENOMEM, "near-miss minimum: a working copy");
    int mn = nf < a->nb ? nf : a->nb;
    if (!ws->near_buf && !(ws->near_buf = malloc(sizeof(double) * (6 * (size_t)nf + (size_t)mn))))
        return kin__fail(a, KIN_ENOMEM, "near-miss minimum: workspace");
    if (!ws->near_min && !(ws->near_min = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent)))
        return kin__fail(a, KIN_ENOMEM, "near-miss minimum: the minimiser");
    /* the bracket's start (the handle), its end and the trial copy: the
     * handle's options; the ends analysed by SVD, the trials in the LU mode
     * for the duration of their forward calculation (trial_value) */
    kin__copy_state(st, a);
    kin_assembly *cp[3] = {st, end, ws->probe};
    for (int k = 0; k < 3; ++k) {
        cp[k]->opt = a->opt;
        cp[k]->opt.factorization = KIN_STEP_SVD;
        cp[k]->lu_inverse = 0;
    }
    double *x0 = ws->near_buf, *x1 = x0 + nf, *d1 = x1 + nf;
    nm_ctx c = {st, ws->probe, x0, st->t, x1, d1, d1 + nf, d1 + 2 * nf, d1 + 4 * nf, 0.0, 0.0, nf, 0, 0};
    double zm = NAN, fm = INFINITY, f0 = NAN, f1 = NAN, *xo = d1 + 3 * nf;
    int have_mid = 0; /* after a move: the old end inside the bracket, (zm, fm) */
    for (int ext = 0;; ++ext) {
        if (!kin__cur(st)->valid && (rc = kin__analyse(st, NULL)) != KIN_OK) return KIN_OK;
        if (!kin__cur(end)->valid && (rc = kin__analyse(end, NULL)) != KIN_OK) return KIN_OK;
        if (!set_bracket(&c, st, end, x0, x1, d1)) return KIN_OK; /* not a forward step */
        f0 = rel_vr(st);
        f1 = rel_vr(end);
        if (!isfinite(f0) || !isfinite(f1)) return KIN_OK;
        c.bad = 2.0 * fmax(f0, fmax(f1, have_mid ? fm : 0.0)) + 1.0;
        if (have_mid) {
            zm = 0.0;
            for (int i = 0; i < nf; ++i) zm += st->t[i] * (xo[i] - x0[i]);
            if (!(zm > 0.0 && zm < c.z1)) return KIN_OK;
            if (fm < f0 && fm < f1) break;
        } else {
            /* a first point below both ends: the middle of the bracket, then the probes */
            zm = NAN;
            fm = INFINITY;
            for (size_t k = 0; k < sizeof NEAR_MIN_PROBES / sizeof *NEAR_MIN_PROBES; ++k) {
                double z = NEAR_MIN_PROBES[k] * c.z1, f = trial_value(z, &c);
                if (f < fm) {
                    fm = f;
                    zm = z;
                }
                if (fm < f0 && fm < f1) break;
            }
            if (fm < f0 && fm < f1) break;
        }
        out->evals = c.evals;
        if (ext == NEAR_MIN_EXTEND) return KIN_OK; /* not found: the end stays at the regular point before the dip */
        /* the minimum lies at or past the lower end (a sign change of the
         * test function kept while v_r still fell, or a turn next to the
         * step's end): a bracket around that end, from the probe next to
         * it to a step of the same length beyond it, the end its middle */
        double len = c.z1;
        int fwd = f1 < f0;
        double zp = (fwd ? NEAR_MIN_PROBES[4] : NEAR_MIN_PROBES[3]) * c.z1;
        memcpy(xo, fwd ? x1 : x0, sizeof(double) * (size_t)nf);
        fm = fwd ? f1 : f0;
        if (!(trial_value(zp, &c) < c.bad)) return KIN_OK;
        if (fwd) {
            kin__copy_state(st, end);
            rc = kin_step(st, len, NULL);
            if (rc == KIN_OK) kin__copy_state(end, st);
            kin__copy_state(st, c.trial);
        } else {
            kin__copy_state(end, c.trial);
            rc = kin_step(st, -len, NULL);
        }
        if (rc) return KIN_OK;
        have_mid = 1;
    }
    gsl_function F = {trial_value, &c};
    gsl_min_fminimizer *s = ws->near_min;
    /* the library's error handler is not called: the values are finite and bracket a minimum */
    if (gsl_min_fminimizer_set_with_values(s, &F, zm, fm, 0.0, f0, c.z1, f1) != GSL_SUCCESS) return KIN_OK;
    double xtol = NEAR_MIN_XTOL * a->rms_length, lo = 0.0, hi = c.z1;
    int it = 0, conv = 0;
    for (; it < NEAR_MIN_MAX_ITER; ++it) {
        if (gsl_min_fminimizer_iterate(s) != GSL_SUCCESS) break;
        lo = gsl_min_fminimizer_x_lower(s);
        hi = gsl_min_fminimizer_x_upper(s);
        if (gsl_min_test_interval(lo, hi, xtol, 0.0) == GSL_SUCCESS) {
            conv = 1;
            break;
        }
    }
    zm = gsl_min_fminimizer_x_minimum(s);
    fm = gsl_min_fminimizer_f_minimum(s);
    golden_refine(&c, f0, f1, NEAR_MIN_FINE * a->rms_length, &lo, &zm, &fm, &hi);
    conv = conv || hi - lo <= xtol;
    out->floor = near_floor(c.z1, f0, f1, zm, fm, hi - lo);
    fm = trial_value(zm, &c); /* the trial copy onto the minimum */
    if (c.failed && !(fm < c.bad)) return KIN_OK;
    /* the end analysed in full, as the handle's points are (its value from that analysis) */
    if (!kin__cur(c.trial)->valid && kin__analyse(c.trial, NULL) != KIN_OK) return KIN_OK;
    fm = rel_vr(c.trial);
    kin__copy_state(a, c.trial); /* a keeps its own options */
    out->located = conv;
    out->z = zm;
    out->width = (hi - lo) / a->rms_length;
    out->v_rel = fm;
    out->evals = c.evals;
    return KIN_OK;
}
