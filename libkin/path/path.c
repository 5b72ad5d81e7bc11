/* Options and predictor-corrector path following (paper 3.2). */
#include <math.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "path/path.h"
#include "path/step_lu.h"

/* The chord corrector (factorization of the start point) hands over to
 * Newton when an iteration reduces the residual by less than this factor:
 * near a bifurcation the start point's Jacobian is a poor model. */
static const double CHORD_MIN_CONTRACTION = 0.7;
/* Corrections that shrink by less than this factor have reached the
 * rounding floor: the corrector stops there (once the strain is met). */
static const double CORRECTION_STALL = 0.5;
/* Newton reuses its last factorization while each iteration reduces the
 * residual by this factor or better. */
static const double NEWTON_REUSE_CONTRACTION = 0.25;
/* A corrector whose residual grows beyond this multiple of the predictor's
 * diverges (measured: Newton from a bad predictor reaching 1e82 after its 60
 * iterations); the attempt fails at once. */
static const double CORRECTOR_DIVERGENCE = 1e6;
/* Newton from a predictor inside its basin converges in a handful of
 * iterations; an attempt that needs more fresh factorizations than this
 * fails, and the step is halved. */
enum { NEWTON_MAX_FACTORIZATIONS = 8 };
/* LU modes: an automatic step whose chord corrector stalls is halved up to
 * this many times before Newton finishes it. The chord costs solves with
 * the start point's factors; each Newton iteration a new factorization
 * (measured on sail:24:14: 6.7 factorizations per step when Newton
 * finished stalled chords, against 1.0 at a step short enough for the
 * chord). */
enum { CHORD_ONLY_HALVINGS = 3 };
/* ... and when even that did not let the chord converge (measured on the
 * hexagonal sail's generic point, close to a bifurcation: the chord stalls
 * down to delta / 500), the next this many automatic steps use Newton at
 * the full amplitude before shorter steps are tried again. */
enum { CHORD_RETRY_STEPS = 4 };
/* Automatic steps (delta == 0) grow by this factor after an easy step, up
 * to the largest step. */
static const double STEP_GROWTH = 1.5;
/* Projections of a requested direction onto the internal mechanisms shorter
 * than this (relative to |dir|) mean "not a first-order mechanism". */
static const double DIRECTION_MIN_PROJECTION = 1e-6;
/* kin_relax halves a Gauss-Newton correction at most this many times. */
enum { RELAX_MAX_BACKTRACK = 30 };

double kin__strain_floor(kin_assembly *a)
{
    if (!a->have_start_strain) {
        /* the start's own residual: measured once, where the path starts */
        a->start_strain = kin__lengths(a, a->xyz, NULL);
        if (!isfinite(a->start_strain)) a->start_strain = 0.0;
        a->have_start_strain = 1;
    }
    return fmax(a->start_strain, kin__resolution_strain(a));
}

double kin__corrector_tol(kin_assembly *a)
{
    return fmax(a->opt.corrector_tol, kin__strain_floor(a));
}

/* the LU modes: dense or sparse bordered factors, the SVD only where needed */
static int lu_mode(const kin_assembly *a)
{
    return a->opt.factorization == KIN_STEP_LU || a->opt.factorization == KIN_STEP_SPARSE;
}

int kin_set_options(kin_assembly *a, const kin_options *user)
{
    if (!a) return KIN_ENULL;
    if (!user) return kin__fail(a, KIN_ENULL, "options pointer is NULL");
    kin_options opts;
    int rc = kin__options_read(a, user, &opts);
    if (rc) return rc;
    const kin_options *o = &opts;
    if (o->factorization == KIN_STEP_SPARSE) {
        /* the sparse pattern, its analysis and first factors: once, here,
         * not in the stepping loop */
        rc = kin__sparse_prepare(a);
        if (rc) return rc;
    }
    if (o->rank_tol != a->opt.rank_tol || o->coord_resolution != a->opt.coord_resolution) {
        a->fac[0].valid = a->fac[1].valid = 0;
        kin__lu_invalidate(a);
    }
    a->opt = *o;
    return KIN_OK;
}

double kin_path_length(const kin_assembly *a) { return a ? a->l : 0.0; }

int kin_path_reset(kin_assembly *a)
{
    if (!a) return KIN_ENULL;
    a->l = 0.0;
    a->have_t = a->t_chosen = 0;
    a->step_hint = 0.0;
    a->have_start_strain = 0;
    a->chord_hopeless = 0;
    return KIN_OK;
}

static int ensure_analysis(kin_assembly *a)
{
    if (kin__cur(a)->valid) return KIN_OK;
    int rc = kin__analyse_into(a, a->xyz, a->cur);
    return rc;
}

/* Default tangent of a regular point: its (deterministically oriented)
 * internal mechanism. */
static void ensure_tangent(kin_assembly *a)
{
    const kin_factor *f = kin__cur(a);
    if (!a->have_t && f->valid && f->an.m_internal == 1) {
        memcpy(a->t, f->Uint, sizeof(double) * (size_t)a->nf);
        a->have_t = 1;
    }
}

/* v := projection of v on span(Uint[:, 0..mi-1]); returns its norm */
static double project_internal(const kin_assembly *a, const kin_factor *f, double *v, double *c)
{
    int nf = a->nf, mi = f->an.m_internal;
    for (int k = 0; k < mi; ++k) c[k] = kin__dot(nf, f->Uint + (size_t)k * nf, v);
    for (int i = 0; i < nf; ++i) {
        double s = 0.0;
        for (int k = 0; k < mi; ++k) s += f->Uint[i + (size_t)k * nf] * c[k];
        v[i] = s;
    }
    return kin__norm(nf, v);
}

int kin_path_set_direction(kin_assembly *a, const double *dir, int n)
{
    if (!a) return KIN_ENULL;
    if (!dir) return kin__fail(a, KIN_ENULL, "dir is NULL");
    if (n != a->nf) return kin__fail(a, KIN_ERANGE, "dir has %d entries, need nfree = %d", n, a->nf);
    for (int i = 0; i < n; ++i)
        if (!isfinite(dir[i])) return kin__fail(a, KIN_EGEOM, "dir[%d] is not finite", i);
    int rc = ensure_analysis(a);
    if (rc) return rc;
    const kin_factor *f = kin__cur(a);
    if (f->an.m_internal == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism to follow");
    double nd = kin__norm(n, dir);
    memcpy(a->d, dir, sizeof(double) * (size_t)n);
    double np = project_internal(a, f, a->d, a->y);
    if (!(nd > 0.0) || !(np > DIRECTION_MIN_PROJECTION * nd))
        return kin__fail(a, KIN_EINVAL,
                         "dir is not a first-order mechanism here (|projection|/|dir| = %.3g)",
                         nd > 0.0 ? np / nd : 0.0);
    for (int i = 0; i < n; ++i) a->t[i] = a->d[i] / np;
    a->have_t = 1;
    a->t_chosen = f->an.m_internal >= 2;
    a->step_hint = 0.0; /* a new direction: start again from the largest step */
    a->chord_hopeless = 0;
    return KIN_OK;
}

int kin_get_tangent(const kin_assembly *a, double *t, int n)
{
    if (!a || !t) return KIN_ENULL;
    if (n != a->nf) return KIN_ERANGE;
    const kin_factor *f = kin__cur(a);
    if (!f->valid && !a->have_t) return KIN_ESTATE;
    if (a->have_t && (f->an.m_internal == 1 || a->t_chosen || !f->valid)) {
        memcpy(t, a->t, sizeof(double) * (size_t)n);
        return KIN_OK;
    }
    if (f->an.m_internal == 1) {
        memcpy(t, f->Uint, sizeof(double) * (size_t)n);
        return KIN_OK;
    }
    return f->an.m_internal == 0 ? KIN_ENOMECH : f->an.s == f->an.s_trivial ? KIN_EMULTIDOF : KIN_EBIFURCATION;
}

/* Chord correction with the current factor: d = sum_{i<r} u_i (w_i^T e)/v_i */
static void chord_correction(kin_assembly *a, const double *e, double *d)
{
    const kin_factor *f = kin__cur(a);
    int nf = a->nf, nb = a->nb, r = f->an.rank, inc = 1;
    double one = 1.0, zero = 0.0;
    if (r == 0) {
        memset(d, 0, sizeof(double) * (size_t)nf);
        return;
    }
    dgemv_("N", &r, &nb, &one, f->VT, &nb, e, &inc, &zero, a->y, &inc, 1);
    for (int i = 0; i < r; ++i) a->y[i] /= f->sv[i];
    dgemv_("N", &nf, &r, &one, f->U, &nf, a->y, &inc, &zero, d, &inc, 1);
}

/* One attempt at amplitude delta from x0 along t. On success the trial
 * factor holds the analysis of the new point and a->x the new free
 * coordinates. */
typedef struct attempt_result {
    int iterations;
    double residual, cos_turn, chord_len;
    int m_internal;
    int multidof; /* the new point continues a multi-DOF mechanism (see attempt) */
    int newton;   /* the corrector needed Newton (the chord stalled) */
    int lu;     /* LU mode: accepted without an SVD (a->lu trial slot) */
    double v_r; /* v_r (estimate in LU mode) at the new point */
} attempt_result;

/* chord of the step (oriented with delta) into a->chord; returns its length */
static double step_chord(kin_assembly *a, double delta)
{
    int nf = a->nf;
    double sgn = delta > 0.0 ? 1.0 : -1.0;
    for (int i = 0; i < nf; ++i) a->chord[i] = sgn * (a->x[i] - a->x0[i]);
    return kin__norm(nf, a->chord);
}

/* a->d (new mechanism, any length and sign) against the chord (length cl):
 * direction check, then a->d := the unit tangent oriented along the motion
 * (eq. 10 against the chord) */
static int orient_tangent(kin_assembly *a, double cl, attempt_result *res)
{
    int nf = a->nf;
    double nt = kin__norm(nf, a->d);
    double c = nt > 0.0 && cl > 0.0 ? kin__dot(nf, a->d, a->chord) / (nt * cl) : 0.0;
    res->cos_turn = fabs(c);
    if (fabs(c) < a->opt.direction_tol)
        return kin__fail(a, KIN_EPATHJUMP,
                         "mechanism turned: |cos| = %.3g between new mechanism and chord, need >= %.3g",
                         fabs(c), a->opt.direction_tol);
    for (int i = 0; i < nf; ++i) a->d[i] = (c < 0.0 ? -a->d[i] : a->d[i]) / nt;
    return KIN_OK;
}

/* start_mi: internal mechanisms at the start point (1 for an LU-mode point) */
/* chord_only: a stalling chord corrector fails the attempt (the caller
 * halves the step) instead of handing over to Newton */
static int attempt(kin_assembly *a, double delta, const double *pred, int use_chord, int use_lu,
                   int start_mi, int chord_only, double tol, attempt_result *res)
{
    int nf = a->nf, trial = 1 - a->cur;
    double *xyz = a->xyz_trial;
    int ncoord = a->nj * a->dim;
    memcpy(xyz, a->xyz, sizeof(double) * (size_t)ncoord);
    if (pred)
        for (int i = 0; i < nf; ++i) a->xp[i] = a->x[i] = pred[i];
    else
        for (int i = 0; i < nf; ++i) a->xp[i] = a->x[i] = a->x0[i] + delta * a->t[i];
    kin__scatter(a, a->x, xyz);
    double r = kin__extensions(a, xyz, a->e), r_start = r;
    int it = 0, chord = use_chord;
    /* Newton keeps its last factorization while it contracts the residual
     * by NEWTON_REUSE_CONTRACTION or better (a new one costs as much as the
     * rest of the step) */
    int have_newton = 0, reuse = 0, newton_factorizations = 0;
    /* converged when the strain meets the tolerance and the last correction
     * moved no coordinate by more than the tolerance times the RMS bar
     * length (near a bifurcation a small strain still allows a position
     * error of strain / v_r), or the corrections stopped shrinking: the
     * rounding floor */
    double dlast = INFINITY, dprev = INFINITY, postol = tol * a->rms_length;
    while (!(r <= tol && dlast <= postol)) {
        if (r <= tol && dlast >= CORRECTION_STALL * dprev) {
            /* corrections no longer shrink: a slow chord hands over to
             * Newton; Newton has reached the rounding floor */
            if (!chord) break;
            chord = 0;
            dlast = dprev = INFINITY;
        }
        if (it >= a->opt.corrector_max_iter || !isfinite(r)) {
            res->iterations = it;
            res->residual = r;
            return kin__fail(a, KIN_ENOTCONVERGED,
                             "corrector: residual %.3g after %d iterations (delta = %.3g)", r, it,
                             delta);
        }
        if (chord && kin__cur(a)->valid) {
            chord_correction(a, a->e, a->d);
        } else if (chord) {
            int rc = kin__lu_chord_correction(a, a->e, a->d);
            if (rc) return rc;
        } else {
            /* Newton on [C; t^T; R^T] by LU where it is square (the same
             * correction as the minimum-norm one of [C; t^T] by QR) */
            int rc;
            if (have_newton && reuse) {
                rc = kin__lu_newton_reuse(a, a->e, a->d);
            } else {
                if (++newton_factorizations > NEWTON_MAX_FACTORIZATIONS) {
                    /* quadratic convergence needs a handful; more means the
                     * predictor is outside Newton's basin: a shorter step */
                    res->iterations = it;
                    res->residual = r;
                    return kin__fail(a, KIN_ENOTCONVERGED,
                                     "corrector: Newton not converging after %d factorizations, residual %.3g "
                                     "(delta = %.3g)",
                                     NEWTON_MAX_FACTORIZATIONS, r, delta);
                }
                rc = kin__lu_newton_solve(a, xyz, a->e, a->d, &have_newton);
            }
            if (rc) return rc;
            for (int i = 0; i < nf; ++i) a->d[i] = -a->d[i];
        }
        dprev = dlast;
        dlast = 0.0;
        for (int i = 0; i < nf; ++i) {
            a->x[i] -= a->d[i];
            dlast = fmax(dlast, fabs(a->d[i]));
        }
        kin__scatter(a, a->x, xyz);
        double rn = kin__extensions(a, xyz, a->e);
        ++it;
        if (!chord) reuse = rn <= NEWTON_REUSE_CONTRACTION * r || rn <= tol;
        if (!(rn <= CORRECTOR_DIVERGENCE * fmax(r_start, tol))) {
            /* diverging: this attempt will not converge; fail it now so the
             * step can be halved (not after corrector_max_iter iterations) */
            res->iterations = it;
            res->residual = rn;
            return kin__fail(a, KIN_ENOTCONVERGED, "corrector diverges: residual %.3g from %.3g (delta = %.3g)",
                             rn, r_start, delta);
        }
        if (chord && !(rn <= CHORD_MIN_CONTRACTION * r) && rn > tol && chord_only) {
            /* LU modes' automatic step: a shorter step whose chord converges
             * costs one factorization; Newton here would cost one per
             * iteration */
            res->iterations = it;
            res->residual = rn;
            return kin__fail(a, KIN_ENOTCONVERGED, "chord corrector stalls: residual %.3g from %.3g (delta = %.3g)",
                             rn, r, delta);
        }
        if (chord && !(rn <= CHORD_MIN_CONTRACTION * r) && rn > tol) {
            /* chord stalls or diverges: restart Newton from the predictor */
            chord = 0;
            dlast = dprev = INFINITY;
            for (int i = 0; i < nf; ++i) a->x[i] = a->xp[i];
            kin__scatter(a, a->x, xyz);
            rn = kin__extensions(a, xyz, a->e);
        }
        r = rn;
    }
    res->iterations = it;
    res->residual = r;
    /* the correction must stay small next to the step */
    for (int i = 0; i < nf; ++i) a->d[i] = a->x[i] - a->xp[i];
    double corr = kin__norm(nf, a->d);
    if (corr > a->opt.max_correction * fabs(delta))
        return kin__fail(a, KIN_EPATHJUMP, "correction %.3g exceeds %.3g * |delta| = %.3g", corr,
                         a->opt.max_correction, a->opt.max_correction * fabs(delta));
    res->lu = 0;
    res->multidof = 0;
    res->newton = newton_factorizations > 0;
    if (use_lu) {
        /* LU mode: tangent and estimates from the bordered factors; the SVD
         * only where singular values matter */
        int regular = 0;
        int rc = kin__lu_new_point(a, xyz, &regular);
        if (rc) return rc;
        if (regular) {
            res->lu = 1;
            res->m_internal = 1;
            res->v_r = a->lu[1 - a->lu_cur].v_r;
            double cl = step_chord(a, delta);
            res->chord_len = cl;
            return orient_tangent(a, cl, res);
        }
    }
    int rc = kin__analyse_into(a, xyz, trial);
    if (rc) return rc;
    const kin_factor *f = &a->fac[trial];
    res->m_internal = f->an.m_internal;
    res->v_r = f->an.v_r;
    if (f->an.m_internal == 0)
        return kin__fail(a, KIN_ENOMECH, "no internal mechanism at the new point");
    double cl = step_chord(a, delta);
    res->chord_len = cl;
    /* new tangent, oriented along the motion (eq. 10 against the chord) */
    if (f->an.m_internal == 1) {
        memcpy(a->d, f->Uint, sizeof(double) * (size_t)nf);
    } else if (a->t_chosen && f->an.m_internal == start_mi) {
        /* a mechanism with as many degrees of freedom as the start point,
         * followed along a direction the caller chose: the continuation
         * nearest to it is the previous tangent projected on the new
         * internal mechanisms, and it stays chosen */
        memcpy(a->d, a->t, sizeof(double) * (size_t)nf);
        project_internal(a, f, a->d, a->y);
        res->multidof = 1;
    } else {
        /* the count changed (from a path: a bifurcation reached): the
         * chord's projection, and the caller chooses the next direction */
        memcpy(a->d, a->chord, sizeof(double) * (size_t)nf);
        project_internal(a, f, a->d, a->y);
    }
    return orient_tangent(a, cl, res);
}

/* kin_step, and the locator's forward calculations with an explicit
 * predictor (pred != NULL: free coordinates with t.(pred - x0) = delta, no
 * clamping, no halving; analysed by SVD, whatever the mode, since the
 * locator reads the singular values of the point it reaches, unless
 * a->lu_predicted asks for the LU mode's factors there) */
static int step_impl(kin_assembly *a, double delta, const double *pred, kin_step_info *info)
{
    if (!a) return KIN_ENULL;
    if (!isfinite(delta)) return kin__fail(a, KIN_EINVAL, "delta is not finite");
    long f0 = a->nfact;
    int use_lu = lu_mode(a) && (!pred || a->lu_predicted), rc = KIN_OK;
    const kin_factor *f = kin__cur(a);
    /* LU mode continues from the bordered factors of a regular point
     * without an SVD there; otherwise the point needs its analysis */
    int lu_point = (use_lu || a->lu_svd_start) && !f->valid && kin__lu_current(a);
    if (use_lu && !lu_point && !f->valid) {
        /* sparse mode: factorize the start point sparsely instead of the
         * SVD where it is regular (a no-op in the dense LU mode) */
        rc = kin__lu_start(a, &lu_point);
        if (rc) return rc;
    }
    if (!lu_point) {
        rc = ensure_analysis(a);
        if (rc) return rc;
        if (f->an.m_internal == 0) return kin__fail(a, KIN_ENOMECH, "no internal mechanism to follow");
        if (f->an.m_internal >= 2 && !a->t_chosen) {
            /* no self-stress but fixed bars': the strain-free set is smooth
             * here with m_internal internal degrees of freedom (a multi-DOF
             * mechanism, not a bifurcation); with self-stresses the
             * first-order analysis cannot tell the two apart */
            if (f->an.s == f->an.s_trivial)
                return kin__fail(a, KIN_EMULTIDOF, "%d internal mechanisms, no self-stress (set one with "
                                 "kin_path_set_direction())", f->an.m_internal);
            return kin__fail(a, KIN_EBIFURCATION,
                             "%d internal mechanisms here: choose one with kin_path_set_direction()",
                             f->an.m_internal);
        }
        ensure_tangent(a);
    }
    double dmax = a->opt.step_fraction * a->rms_length;
    int automatic = delta == 0.0 && !pred;
    /* the LU modes' own step control (kin_options.step_control) */
    int mode_control = use_lu && automatic && a->opt.step_control == KIN_STEP_CONTROL_MODE;
    if (!pred) {
        /* automatic amplitude: where the last automatic step needed halving,
         * start from what it could take instead of failing the same way */
        if (automatic) delta = a->step_hint > 0.0 ? fmin(dmax, a->step_hint) : dmax;
        if (fabs(delta) > dmax) delta = delta > 0.0 ? dmax : -dmax;
    } else if (delta == 0.0) {
        return kin__fail(a, KIN_EINVAL, "a forward calculation needs delta != 0");
    }
    kin__gather(a, a->xyz, a->x0);
    /* the start point's factorization serves as the chord corrector where
     * H^T keeps its rank nearby: a regular point of a path or of a multi-DOF
     * mechanism (no self-stress); at a bifurcation, Newton */
    int use_chord = lu_point || f->an.m_internal == 1 || f->an.s == f->an.s_trivial;
    int start_mi = lu_point ? 1 : f->an.m_internal;
    attempt_result res = {0};
    int h, tries = pred ? 0 : a->opt.max_halvings, chord_only_failed = 0;
    double sfloor = kin__strain_floor(a), tol = fmax(a->opt.corrector_tol, sfloor);
    double delta_first = delta;
    for (h = 0; h <= tries; ++h, delta *= 0.5) {
        /* LU modes, automatic step: halve a stalling chord CHORD_ONLY_HALVINGS
         * times before paying for Newton (step control that knows its mode;
         * measured on sail:24:14: 1.1 factorizations per step instead of 2.7) */
        int chord_only = mode_control && use_chord && a->chord_hopeless == 0 && h < CHORD_ONLY_HALVINGS;
        rc = attempt(a, delta, pred, use_chord, use_lu, start_mi, chord_only, tol, &res);
        if (rc == KIN_OK) break;
        chord_only_failed += chord_only;
        if (rc == KIN_ELAPACK_ARG) return rc;
    }
    if (rc != KIN_OK) {
        /* every attempt failed: the current point, analysis and tangent are untouched */
        if (info) {
            memset(info, 0, sizeof *info);
            info->l = a->l;
            info->halvings = h;
            info->factorizations = (int)(a->nfact - f0);
            info->residual = res.residual;
            info->strain_floor = sfloor;
            info->tol_used = tol;
        }
        return rc;
    }
    /* accept */
    kin__scatter(a, a->x, a->xyz);
    a->cur = 1 - a->cur;
    if (res.lu) {
        /* LU mode: the new point has bordered factors, no SVD analysis */
        a->fac[a->cur].valid = 0;
        a->lu_cur = 1 - a->lu_cur;
    } else {
        kin__lu_invalidate(a);
    }
    memcpy(a->t, a->d, sizeof(double) * (size_t)a->nf);
    a->have_t = 1;
    a->t_chosen = res.multidof;
    a->l += (delta > 0.0 ? 1.0 : -1.0) * res.chord_len;
    if (automatic) {
        /* grow after an easy step (no halving, no factorization but the new
         * point's), keep the amplitude after a hard one */
        int easy = h == 0 && a->nfact - f0 <= 1;
        a->step_hint = easy ? STEP_GROWTH * fabs(delta) : fabs(delta);
        if (mode_control) {
            /* the chord converged: the LU modes' control applies again; it
             * did not even after shorter steps (close to a bifurcation the
             * chord's contraction is set by v_r more than by the step):
             * Newton at the full amplitude, as in the SVD mode, for the
             * next CHORD_RETRY_STEPS steps or until the chord converges */
            if (!res.newton) {
                a->chord_hopeless = 0;
            } else if (chord_only_failed >= CHORD_ONLY_HALVINGS) {
                a->chord_hopeless = CHORD_RETRY_STEPS;
                a->step_hint = fabs(delta_first);
            } else if (a->chord_hopeless > 0) {
                --a->chord_hopeless; /* try the shorter steps again after a while */
            }
        }
    }
    if (info) {
        info->l = a->l;
        info->delta = delta;
        info->v_r = res.lu ? res.v_r : kin__cur(a)->an.v_r;
        info->residual = res.residual;
        info->cos_turn = res.cos_turn;
        info->iterations = res.iterations;
        info->halvings = h;
        info->factorizations = (int)(a->nfact - f0);
        info->m_internal = res.m_internal;
        info->strain_floor = sfloor;
        info->tol_used = tol;
    }
    a->err[0] = '\0';
    return KIN_OK;
}

int kin_step(kin_assembly *a, double delta, kin_step_info *info)
{
    if (!info) return step_impl(a, delta, NULL, NULL);
    if (kin__abi_check(info, KIN__ABI(kin_step_info))) {
        if (!a) return KIN_ENULL;
        return kin__fail(a, KIN_EINVAL, "info->size = %zu: set it to sizeof(kin_step_info)", kin__abi_size(info));
    }
    kin_step_info local = {.size = sizeof local};
    int rc = step_impl(a, delta, NULL, &local);
    kin__abi_write(info, &local, KIN__ABI(kin_step_info));
    return rc;
}

int kin__step_predicted(kin_assembly *a, double delta, const double *pred, kin_step_info *info)
{
    return step_impl(a, delta, pred, info);
}

int kin_relax(kin_assembly *a, int max_iter, double *residual)
{
    if (!a) return KIN_ENULL;
    if (max_iter < 1) return kin__fail(a, KIN_EINVAL, "max_iter = %d, need >= 1", max_iter);
    int nf = a->nf;
    double *xyz = a->xyz_trial;
    memcpy(xyz, a->xyz, sizeof(double) * (size_t)(a->nj * a->dim));
    kin__gather(a, xyz, a->x);
    double r = kin__extensions(a, xyz, a->e), merit = kin__norm(a->nb, a->e);
    /* the start strain is what relax removes: only the rounding floor counts */
    double tol = fmax(a->opt.corrector_tol, kin__resolution_strain(a));
    int it = 0;
    while (!(r <= tol) && it < max_iter && isfinite(r)) {
        int rc = kin__bordered_solve(a, xyz, NULL, a->e, a->d);
        if (rc) return rc;
        /* damped Gauss-Newton: halve the correction until |e| decreases, so
         * a far start does not throw the assembly away */
        memcpy(a->x0, a->x, sizeof(double) * (size_t)nf);
        double lambda = 1.0, m2 = merit, r2 = r;
        int better = 0;
        for (int k = 0; k < RELAX_MAX_BACKTRACK && !better; ++k, lambda *= 0.5) {
            for (int i = 0; i < nf; ++i) a->x[i] = a->x0[i] + lambda * a->d[i];
            kin__scatter(a, a->x, xyz);
            r2 = kin__extensions(a, xyz, a->e);
            m2 = kin__norm(a->nb, a->e);
            better = m2 < merit;
        }
        ++it;
        if (!better) {
            /* no step along d lowers |e| (a rest length the bars cannot
             * reach, joints driven together): stay at the best point, whose
             * geometry is defined, instead of iterating from a worse one */
            memcpy(a->x, a->x0, sizeof(double) * (size_t)nf);
            kin__scatter(a, a->x, xyz);
            r = kin__extensions(a, xyz, a->e);
            break;
        }
        merit = m2;
        r = r2;
    }
    if (residual) *residual = r;
    if (!(r <= tol))
        return kin__fail(a, KIN_ENOTCONVERGED, "relax: residual %.3g after %d iterations", r, it);
    kin__set_configuration(a, xyz);
    return KIN_OK;
}
