/* libkin: detecting and converging onto bifurcation points (paper section 4).
 *
 * Detection uses, at every accepted step, both the paper's switch rule (v_r
 * below a threshold and decreasing) and a signed test function that a step
 * cannot jump over:
 *     tau = sign(det [C; t^T; R^T]) * v_r,
 * C = H^T without the rows of bars between fixed joints (zero at every
 * point: kin_analysis.s_trivial), t the oriented tangent, R the rigid-body
 * mechanisms (oriented continuously). Where it is not square (redundant
 * bars on the path) tau = v_r, unsigned. The bordered matrix is square and regular on a path; its
 * determinant changes sign where the path crosses another one at a simple
 * bifurcation (one extra singular value through zero). Cost: one LU
 * factorization (dgetrf) per step, about a sixth of an SVD. */
#ifndef KIN_LOCATE_H
#define KIN_LOCATE_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"
#include "kin_progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Location methods. */
enum kin_locate_method {
    KIN_LOCATE_PAPER = 0,   /* quadratic in l through the last three v_r (eq. 23-25),
                               path check (eq. 26) and overshoot probe, delta halved */
    KIN_LOCATE_FAST = 1,    /* Hermite interpolation of the path and of the signed
                               vanishing singular value over the bracketing step
                               (default; see below) */
    KIN_LOCATE_ILLINOIS = 2 /* Illinois (modified regula falsi) on the signed
                               test function over the bracketing step */
};

/* Why the detector fired / how location ended. */
enum kin_locate_event {
    KIN_EVENT_NONE = 0,        /* no bifurcation within the steps allowed */
    KIN_EVENT_SIGN_CHANGE = 1, /* tau changed sign over the last step */
    KIN_EVENT_SWITCH_RULE = 2, /* only the paper's rule fired (v_r < eps, decreasing) */
    KIN_EVENT_LANDED = 3,      /* a step landed on a bifurcation (m_internal >= 2) */
    KIN_EVENT_MINIMUM = 4      /* v_r turned from decreasing to increasing over the last
                                  step (its derivative changed sign) near zero, tau did not
                                  change sign: fast and Illinois methods only */
};

typedef struct kin_locate_options {
    size_t size; /* sizeof(kin_locate_options) as the caller compiled it (docs/abi.md) */
    int method;          /* enum kin_locate_method. Default KIN_LOCATE_FAST */
    double vr_tol;       /* located when v_r <= vr_tol * v_max (v_r: see kin_locate_info).
                            Default 1e-10 */
    double switch_eps;   /* paper's threshold: v_r < switch_eps * v_max. Default 1e-2 */
    double delta;        /* step amplitude while following; 0 = largest. Default 0 */
    int max_steps;       /* steps to look for a bifurcation. Default 1000 */
    int max_iter;        /* location iterations (forward calculations). Default 60 */
    int use_switch_rule; /* also stop on the paper's rule alone. Default 1 */
} kin_locate_options;

typedef struct kin_locate_info {
    size_t size; /* sizeof(kin_locate_info) as the caller compiled it (docs/abi.md) */
    int event;            /* enum kin_locate_event */
    int located;          /* 1 if the assembly now sits on a bifurcation */
    int steps;            /* path-following steps taken before detection */
    int factorizations;   /* SVD/QR/LU factorizations after detection */
    int forward;          /* forward calculations after detection */
    double v_r;           /* the largest singular value that vanishes at the final
                             point: those from the path's lowest one up that are at
                             most sqrt(vr_tol) * v_max (several vanish together at
                             most bifurcations; located means all are <= vr_tol * v_max) */
    double v_r_rel;       /* v_r / v_max */
    double distance;      /* distance moved during location (free coords) */
    int path_kept;        /* the final tangent agrees with the path's (eq. 26) */
    int m_internal, s;    /* analysis at the final point */
    int zero_order;       /* fast method: how v_r vanishes along the path, ~|l - l*|^p:
                             1 a crossing, 2 a tangency (Figure 7(b)); 0 not estimated */
    /* layout 2 (docs/abi.md): a rigorous enclosure of v_r at the final point, in Arb's ball
       arithmetic: H evaluated exactly at the final (double) coordinates, Weyl's bound on the
       residual of the floating SVD and on its factors' departure from orthogonality
       (docs/locate.md "Certified bifurcations"). Valid when v_r_bounded = 1 */
    double v_r_lo, v_r_hi; /* v_r_lo <= the exact singular value reported as v_r <= v_r_hi; the
                              vanishing ones below it are <= v_r_hi too */
    double v_r_rel_hi;     /* >= that singular value / the exact largest one */
    int v_r_bounded;       /* 1: the three above hold; 0: not computed (no dense SVD at the
                              final point, KIN_STEP_SPARSE, or H too large) */
    /* layout 3 (docs/abi.md): a proven exactly singular configuration near the final point
       (Krawczyk's test in Arb on Moore's extended system, docs/locate.md "Certified
       bifurcations"). A backward-error statement: where sing_proven = 1, the structure whose
       bar lengths L* differ from the given L0 by at most sing_dlength (each bar; L*^2 - L0^2 is
       a multiple of the point's self-stress in force densities) is exactly singular (a
       self-stress, one fewer rank) at a configuration x* with max_i |x*_i - x_i| <=
       sing_distance over the free coordinates x of the final point. L* = L0 is not proven. */
    double sing_distance;  /* the bound on |x* - x| (max norm, model units) */
    double sing_dlength;   /* the bound on max_k |L*_k - L0_k| (model units) */
    double sing_unique;    /* no other such singular point (with its self-stress and length
                              change) within this max-norm radius of the proof's centre */
    int sing_proven;       /* 1: the three above hold; 0: not proven (sing_corank > 1, no
                              dense SVD, or the test failed: not a simple bifurcation, e.g. a
                              tangency, or not near one). Rigid-body mechanisms are gauged by
                              holding as many coordinates; the proof then assumes they are exact
                              motions of the structure (docs/locate.md) */
    int sing_corank;       /* non-trivial self-stresses at the final point (s - s_trivial):
                              the proof needs 1 (or 0, then the lowest singular pair) */
} kin_locate_info;

/* Fill *o with the defaults above, for a struct of `size` bytes: pass
 * sizeof(kin_locate_options) (the macro kin_locate_options_default below does). size must be the sizeof
 * of one of kin_locate_options's published layouts (docs/abi.md); then exactly size bytes
 * are written (o->size = size) and KIN_OK is returned; otherwise nothing is
 * written and KIN_EINVAL is returned. KIN_ENULL if o is NULL. */
KIN_API int kin_locate_options_init(kin_locate_options *o, size_t size);

/* The same with size = sizeof(kin_locate_options): a C or C++ host compiled with this
 * header calls kin_locate_options_init through the macro. The function itself is
 * for programs built before the macro existed: it writes only the first
 * layout (o->size = its sizeof, docs/abi.md), which is all an old program
 * can have room for. Does nothing if o is NULL. */
KIN_API void kin_locate_options_default(kin_locate_options *o);
#define kin_locate_options_default(o) ((void)kin_locate_options_init((o), sizeof(kin_locate_options)))

/* Signed test function at the current point (tau above; *tau = 0 at a
 * bifurcation). Runs the analysis if needed. Returns KIN_OK, KIN_ENULL,
 * KIN_ENOMECH, LAPACK codes. */
KIN_API int kin_test_function(kin_assembly *a, double *tau);

/* Follow the path from the current (regular) point in the direction of the
 * sign of o->delta (forward if 0) until a bifurcation is detected, then
 * converge onto it with o->method. On success the assembly sits at the
 * bifurcation, analysed afresh (m, s, U_m, W_s readable; counted with rank
 * tolerance max(options.rank_tol, 10 vr_tol), since the point is only that
 * exact; a later kin_analyse() counts with options.rank_tol), and info says
 * how.
 * If none is detected within max_steps the assembly is left where following
 * stopped and KIN_ENOTFOUND is returned with event NONE. If location gives
 * up (a non-zero minimum of v_r: a near-singular but regular configuration)
 * the assembly is left at the best regular point found on the path, so
 * stepping can resume, and KIN_ENOTFOUND is returned with the reason in
 * kin_last_error(). Allocates its working copies of the assembly (three; five
 * for the fast method) and the interpolation workspace once per call, none
 * while stepping.
 * Progress goes to the handle's callback (kin_set_progress, kin_progress.h)
 * before every step and location iteration: done = steps + forward
 * calculations, total = max_steps + max_iter. If it cancels, the assembly is
 * left at the last regular point reached on the path (as for KIN_ENOTFOUND:
 * analysed, stepping can resume), info holds the counts of the work done
 * (located = 0; event what was detected before the cancel) and
 * KIN_ECANCELLED is returned.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (options), KIN_EBIFURCATION (already
 * at one), KIN_ENOTFOUND, KIN_ECANCELLED, KIN_ENOMEM, step and LAPACK codes. */
KIN_API int kin_locate_next(kin_assembly *a, const kin_locate_options *o, kin_locate_info *info);

/* The proof of kin_locate_info's layout-3 fields (sing_*) at the assembly's
 * current point, whatever brought it there (kin_locate_next fills them for
 * its final point itself): runs the dense analysis if it is not current,
 * and writes those five fields of *info only; info->size must be the
 * current sizeof(kin_locate_info) (an older layout has no room: KIN_EINVAL).
 * Not being provable is no error (sing_proven = 0). The configuration is not
 * changed. Cost: up to 13 LU factorizations of an N = (nf + nb + 1)-square
 * matrix and about 26 N nb ball operations in 3D (milliseconds for the
 * sails); not attempted (sing_proven = 0) above 3e7 of those (about a
 * second). Returns KIN_OK, KIN_ENULL, KIN_EINVAL, KIN_ENOMEM, analysis
 * codes. */
KIN_API int kin_prove_singular(kin_assembly *a, kin_locate_info *info);

#ifdef __cplusplus
}
#endif

#endif /* KIN_LOCATE_H */
