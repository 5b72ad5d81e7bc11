/* libkin: options and predictor-corrector path following (paper 3.2).
 *
 * A step moves the assembly along its single internal mechanism:
 *   predictor  R' = R + t*delta                      (eq. 9)
 *   corrector  d = -sum_{i<=r} (w_i^T e / v_i) u_i   (eq. 11), repeated
 * until max_k |L_k - L0_k| / L0_k <= corrector_tol (or the strain floor of
 * rounded input, STRAIN FLOOR below). The corrector first
 * iterates with the factorization of the start point (a chord method: no new
 * factorization); if that contracts too slowly (near a bifurcation) it
 * switches to Newton on the bordered system [C(R); t^T] d = [-e; 0], which
 * refactorizes each iteration. Both keep the correction orthogonal to t.
 * The new configuration is then analysed (one SVD), its internal mechanism
 * oriented so that it continues the motion (eq. 10, checked against the
 * chord of the step), and the step is accepted only if
 *  - the corrector converged,
 *  - the correction stayed small next to the step (|d| <= max_correction*|delta|),
 *  - the new mechanism agrees with the chord: |t_new . chord|/|chord| >= direction_tol.
 * STRAIN FLOOR: the strain the input allows. A file's coordinates are
 * rounded (6 decimals, say), and rest lengths taken from them are off by up
 * to sqrt(dim) * coord_resolution; where the structure is a mechanism only
 * thanks to special geometry (an overconstrained one: a self-stress along
 * the path, as in most rigid origami), the rounded structure has no
 * strain-free motion at all, only one whose strain grows as it moves, up to
 * that bound. So the corrector's tolerance in effect is
 *   max(corrector_tol, strain_floor),
 *   strain_floor = max(start strain, sqrt(dim) * coord_resolution / min L0),
 * the start strain being max |L-L0|/L0 where the path started (measured at
 * the first step after the handle was made, kin_set_coords(), kin_relax()
 * or kin_path_reset()). kin_step_info reports both; kin_relax() uses the
 * coordinate part only. The same rounding moves the entries of H (direction
 * cosines) by up to sqrt(dim) * coord_resolution / min L0, so the rank test
 * counts singular values up to max(rank_tol, that) * v_max as zero: the
 * rounded structure keeps the self-stress (and the mechanism) it was given
 * with, to the input's accuracy.
 * A failed attempt is retried with delta halved, up to max_halvings times;
 * if every attempt fails the call returns a status and the assembly,
 * its analysis and its path state are exactly as before the call.
 *
 * FACTORIZATION MODES (kin_options.factorization)
 *  KIN_STEP_SVD (default): as above; every accepted step leaves the full SVD
 *   analysis of the new point current (kin_get_analysis() and the other
 *   getters of kin_assembly.h work without a new factorization).
 *  KIN_STEP_LU: the new point is not analysed by an SVD. The step factorizes
 *   the square bordered matrix J = [C; t^T; R^T] there (C = H^T, t the
 *   tangent of the step, R the rigid-body mechanisms, which need no SVD)
 *   with LU (dgetrf), or with a QR (LQ of J^T, dgelqf) when J is tall
 *   (redundant bars: nbars + 1 + m_rigid > nfree). The new tangent is the
 *   normalised solution of J tau = e_(nbars+1), oriented and checked
 *   against the chord as above; the next step's chord corrector solves with
 *   the same factors (then removes the component along the tangent, which
 *   makes the correction the same minimum-norm one as eq. 11's), and the
 *   corrector's Newton iterations, if the chord stalls, factorize
 *   [C; t^T; R^T] by LU too (QR, dgels, when it is not square); v_r and
 *   v_max are estimated from the factors (two inverse-iteration passes and
 *   one power-iteration pass, warm-started from the previous point). When
 *   the estimate v_r / v_max falls below 1000 * rank_tol (near a
 *   bifurcation), J is singular, or J would be wide (more mechanisms than
 *   one internal one can explain), the step falls back to the full SVD
 *   analysis of the SVD mode at that point, so m_internal and the tangent
 *   choice at a bifurcation are the SVD's. Points agree with the SVD mode's
 *   to rounding times the conditioning (the same predictor, the same
 *   corrections in exact arithmetic). After a step without fallback the
 *   analysis is not current: kin_get_analysis(), kin_get_singular_values(),
 *   kin_get_mechanisms() and kin_get_self_stresses() return KIN_ESTATE
 *   until kin_analyse() is called (which does not disturb the path);
 *   kin_get_tangent() and kin_step() work. kin_locate_next() needs the SVD
 *   at every point and must be run in SVD mode.
 *  KIN_STEP_SPARSE: the LU mode with a sparse LU (SuiteSparse KLU) of the
 *   square bordered matrix J, built in compressed-column form from the bars
 *   (C has at most 2*dim non-zeros per row). The 1 + m_rigid border rows
 *   are dense: KLU factorizes J with each replaced by a unit row at a
 *   stand-in coordinate (chosen where the mechanisms move most), and every
 *   solve with the true J adds a Sherman-Morrison-Woodbury correction (one
 *   extra solve per border row and factorization), so the factors keep the
 *   sparsity of C (linear fill on slender structures such as masts); when
 *   the stand-ins go bad along the path they are chosen again, and a point
 *   whose correction is ill-conditioned is factorized with the dense rows.
 *   It pays on sail-like and slender structures; compact 3D blocks still
 *   fill in (docs/performance.md). The symbolic
 *   analysis and a first numeric factorization are made when the mode is
 *   set (kin_set_options, which may then return KIN_ENOMEM); each new point
 *   refactorizes with the same pivot order (klu_refactor), and pivots again
 *   only when that order has become unstable (reciprocal pivot growth below
 *   1e-8) or singular. Where J is not square (redundant bars: J tall; or
 *   nf - nb - 1 outside 0..m_rigid) a point is handled as in KIN_STEP_LU
 *   (dense LQ, or the SVD). A start point without factors (a new handle,
 *   after kin_set_coords() or kin_relax()) is factorized sparsely too, with
 *   a fixed pseudo-random border row (or the previous tangent), its
 *   tangent oriented like the SVD's (largest entry positive), so a large
 *   structure is followed without any dense factorization unless a point
 *   comes near a bifurcation. Everything else (estimates, fallback to the
 *   SVD, the analysis not being current) is as in KIN_STEP_LU, except where
 *   the dense workspace does not fit (half the physical memory, or LAPACK's
 *   int sizes): there a point whose estimates fall within the fallback's
 *   margin is decided by the sparse analysis (kin_analyse's, at that point;
 *   one internal mechanism: regular, stepped on from its KLU factors, and
 *   the analysis is current there), so the 10^4-joint mast is stepped at
 *   the default rank_tol (about 2 s a step); a point it finds singular, or
 *   cannot decide, is refused with its status and message. The dense
 *   workspace of the SVD and of the dense LU (O(nf^2 + nb^2) doubles) is
 *   made only when such a fallback first needs it, so a sparse-mode handle
 *   of 10^4 joints stays within O(nf + nb) memory besides its KLU factors;
 *   a fallback whose dense workspace exceeds the machine's memory returns
 *   KIN_ENOMEM before allocating it.
 *  STEP CONTROL in KIN_STEP_LU and KIN_STEP_SPARSE: an automatic step
 *   (delta == 0) whose chord corrector stalls is halved instead of being
 *   finished by Newton (each Newton iteration is a new factorization, a
 *   failed chord attempt costs only solves); after 3 such halvings in one
 *   call Newton is used as in the SVD mode, and then (the chord did not
 *   converge even on shorter steps: close to a bifurcation) the next 4
 *   automatic steps use Newton at the full amplitude. Explicit amplitudes are
 *   corrected as in the SVD mode, so the modes give the same points; with
 *   kin_options.step_control = KIN_STEP_CONTROL_SHARED automatic steps do
 *   too (the SVD mode's amplitudes).
 *
 * SEVERAL INTERNAL MECHANISMS (m_internal >= 2)
 *  At a bifurcation of a path, and at any point of a mechanism with several
 *  internal degrees of freedom (an open chain, an under-braced framework),
 *  the motion is not determined by the assembly alone: kin_step() needs a
 *  direction from kin_path_set_direction() and otherwise returns
 *  KIN_EMULTIDOF when the point has no self-stress (s == 0: H^T has full
 *  row rank, so the strain-free set is smooth here with m_internal internal
 *  degrees of freedom; a multi-DOF mechanism, not a bifurcation) or
 *  KIN_EBIFURCATION when it has one (a bifurcation, or a multi-DOF point
 *  with a self-stress somewhere, which the first-order analysis cannot tell
 *  apart). Once a direction is set, each step follows the continuation
 *  nearest to it: while the new point has as many internal mechanisms as
 *  the start point, its tangent is the previous tangent projected on the
 *  new internal mechanisms (normalised, oriented along the motion), and it
 *  stays chosen, so kin_step() can be called again without a new
 *  direction. When the count changes the step is still accepted; with one
 *  internal mechanism the path continues as usual, with more (a
 *  bifurcation reached) the next step needs a direction again: kin_step()
 *  and kin_get_tangent() return KIN_EMULTIDOF or KIN_EBIFURCATION as
 *  above. A point with several internal mechanisms is always analysed by
 *  SVD, in KIN_STEP_LU mode too (the bordered matrix is not square there),
 *  so the analysis stays current. kin_path_reset(), kin_set_coords() and
 *  kin_relax() forget the direction. See docs/generality.md. */
#ifndef KIN_PATH_H
#define KIN_PATH_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Tunable tolerances. Get the defaults with kin_options_default(). */
typedef struct kin_options {
    size_t size; /* sizeof(kin_options) as the caller compiled it (docs/abi.md) */
    double rank_tol;        /* singular values <= rank_tol*v_max count as zero. Default 1e-9 */
    double corrector_tol;   /* target max |L-L0|/L0 of a step. Default 1e-12 */
    int corrector_max_iter; /* chord + Newton iterations per attempt. Default 60 */
    double step_fraction;   /* largest |delta| = step_fraction * RMS rest length. Default 0.1 */
    int max_halvings;       /* retries of a failed step with delta/2. Default 12 */
    double direction_tol;   /* minimum |cos| between new mechanism and chord. Default 0.9 */
    double max_correction;  /* largest |correction| / |delta| accepted. Default 0.5 */
    int factorization;      /* enum kin_step_factorization. Default KIN_STEP_SVD */
    /* layout 2 (docs/abi.md): a host compiled without these fields gets their defaults */
    int step_control;       /* enum kin_step_control. Default KIN_STEP_CONTROL_MODE */
    double coord_resolution; /* how finely the input coordinates were given (length
                                unit; e.g. 1e-6 for 6 decimals), 0 = exact. Rest
                                lengths taken from rounded coordinates are each
                                off by up to sqrt(dim)*coord_resolution, so the
                                corrector does not ask for less strain than that,
                                nor the rank test for smaller singular values
                                (STRAIN FLOOR above). Default 0 */
} kin_options;

/* How kin_step() factorizes at each new point (see the top of this file). */
enum kin_step_factorization {
    KIN_STEP_SVD = 0, /* full SVD of H at every point (dgesdd) */
    KIN_STEP_LU = 1,  /* LU/QR of the bordered matrix; SVD only near a bifurcation */
    KIN_STEP_SPARSE = 2 /* KIN_STEP_LU with a sparse LU (SuiteSparse KLU) of the
                           square bordered matrix: for large structures */
};

/* How automatic steps (delta == 0) choose their amplitude (STEP CONTROL at
 * the top of this file). */
enum kin_step_control {
    KIN_STEP_CONTROL_MODE = 0,  /* LU modes halve a stalling chord before Newton */
    KIN_STEP_CONTROL_SHARED = 1 /* every mode takes the SVD mode's amplitudes (the
                                   same points as the SVD mode, at more
                                   factorizations per step in the LU modes) */
};

/* Fill *o with the defaults above, for a struct of `size` bytes: pass
 * sizeof(kin_options) (the macro kin_options_default below does). size must be the sizeof
 * of one of kin_options's published layouts (docs/abi.md); then exactly size bytes
 * are written (o->size = size) and KIN_OK is returned; otherwise nothing is
 * written and KIN_EINVAL is returned. KIN_ENULL if o is NULL. */
KIN_API int kin_options_init(kin_options *o, size_t size);

/* The same with size = sizeof(kin_options): a C or C++ host compiled with this
 * header calls kin_options_init through the macro. The function itself is
 * for programs built before the macro existed: it writes only the first
 * layout (o->size = its sizeof, docs/abi.md), which is all an old program
 * can have room for. Does nothing if o is NULL. */
KIN_API void kin_options_default(kin_options *o);
#define kin_options_default(o) ((void)kin_options_init((o), sizeof(kin_options)))

/* Replace the handle's options. Validated first (tolerances finite and in
 * (0,1), counts >= 0 (iterations >= 1), step_fraction > 0, factorization one
 * of enum kin_step_factorization, step_control one of enum
 * kin_step_control); on KIN_EINVAL nothing changes. Changing rank_tol
 * invalidates the analysis (and the LU mode's factors). Switching the
 * factorization mode keeps the path state. The first switch to
 * KIN_STEP_SPARSE builds the sparse pattern, its KLU analysis and first
 * factors (KIN_ENOMEM if that fails; then nothing changes).
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL, KIN_ENOMEM. */
KIN_API int kin_set_options(kin_assembly *a, const kin_options *o);

/* Copy the handle's options. KIN_OK or KIN_ENULL. */
KIN_API int kin_get_options(const kin_assembly *a, kin_options *o);

/* What one step did. */
typedef struct kin_step_info {
    size_t size; /* sizeof(kin_step_info) as the caller compiled it (docs/abi.md) */
    double l;           /* signed path length after the step (sum of chords) */
    double delta;       /* amplitude actually used (after clamping/halving) */
    double v_r;         /* lowest non-zero singular value at the new point; in
                           LU mode an estimate (an upper bound from inverse
                           iteration) unless the step fell back to an SVD */
    double residual;    /* final max |L-L0|/L0 */
    double cos_turn;    /* |t_new . chord| / |chord| */
    int iterations;     /* corrector iterations of the accepted attempt */
    int halvings;       /* failed attempts before the accepted one */
    int factorizations; /* SVD/LU/least-squares factorizations in this call */
    int m_internal;     /* internal mechanisms at the new point (1 on a path;
                           in LU mode 1 unless the step fell back to an SVD) */
    /* layout 2 (docs/abi.md): a host compiled without these fields does not get them */
    double strain_floor; /* the strain the input allows (STRAIN FLOOR at the top) */
    double tol_used;     /* the corrector's strain tolerance in effect:
                            max(corrector_tol, strain_floor) */
} kin_step_info;

/* Take one predictor-corrector step of amplitude delta along the oriented
 * internal mechanism: delta > 0 forwards, delta < 0 backwards, delta == 0
 * an automatic step forwards: the largest step (step_fraction*RMS rest
 * length) unless the last automatic step on this path needed halving, then
 * that step's amplitude, growing by 1.5 after each easy step (one that
 * needed no factorization but the new point's). |delta| is clamped to
 * step_fraction*RMS rest length.
 * If the current point has several internal mechanisms (m_internal >= 2: a
 * bifurcation or a multi-DOF mechanism) a direction must have been given
 * with kin_path_set_direction(), and steps then follow the continuation
 * nearest to it (SEVERAL INTERNAL MECHANISMS, top of this file). info may
 * be NULL.
 * In KIN_STEP_LU mode a step's chord corrector uses the start point's SVD
 * analysis when that is current (the first step, after a fallback to the
 * SVD, kin_analyse() or kin_path_set_direction()) and otherwise the bordered
 * factors the previous step left; a start point with neither (after
 * kin_set_coords(), kin_relax() or kin_path_reset()) is analysed by SVD.
 * Returns KIN_OK; KIN_ENULL; KIN_EINVAL (non-finite delta);
 * KIN_ENOMECH (m_internal == 0 here, or at the points every attempt
 * reached: an infinitesimal mechanism only; state unchanged);
 * KIN_EMULTIDOF (m_internal >= 2, no self-stress, no direction chosen);
 * KIN_EBIFURCATION (m_internal >= 2 with a self-stress, no direction
 * chosen); KIN_ENOTCONVERGED or KIN_EPATHJUMP (every attempt failed: the
 * reason of the last attempt; state unchanged); LAPACK codes. */
KIN_API int kin_step(kin_assembly *a, double delta, kin_step_info *info);

/* Choose the direction of motion: dir (nfree entries, finite, nonzero) is
 * projected on the internal mechanisms of the current point. At a regular
 * point of a path it only orients the mechanism (t.dir > 0); where there are
 * several internal mechanisms the normalised projection is the predictor
 * direction of the next step (at a bifurcation e.g. U_m*beta from the
 * second-order analysis; on a multi-DOF mechanism the start of the
 * continuation the following steps keep). Runs kin_analyse() if needed.
 * Returns KIN_OK, KIN_ENULL, KIN_ERANGE (n != nfree), KIN_EGEOM (non-finite),
 * KIN_EINVAL (projection vanishes: dir is not a first-order mechanism),
 * KIN_ENOMECH, LAPACK codes. */
KIN_API int kin_path_set_direction(kin_assembly *a, const double *dir, int n);

/* Oriented tangent (unit, nfree entries) that the next step will use.
 * KIN_OK, KIN_ENULL, KIN_ERANGE, KIN_ESTATE (no analysis yet),
 * KIN_EMULTIDOF / KIN_EBIFURCATION (several internal mechanisms, no direction
 * chosen: as kin_step()), KIN_ENOMECH. */
KIN_API int kin_get_tangent(const kin_assembly *a, double *t, int n);

/* Signed path length travelled since creation, kin_set_coords() or
 * kin_path_reset(); 0 for NULL. */
KIN_API double kin_path_length(const kin_assembly *a);

/* Forget the orientation and the path length (the configuration is kept).
 * KIN_OK or KIN_ENULL. */
KIN_API int kin_path_reset(kin_assembly *a);

/* Move the free coordinates to a nearby strain-free configuration
 * (Gauss-Newton with minimum-norm least-squares corrections, one
 * factorization per iteration) until max |L-L0|/L0 <= corrector_tol (or
 * sqrt(dim) * coord_resolution / min L0 if larger), e.g. to
 * clean up coordinates typed in or imported with few digits. Resets the
 * path state. residual (may be NULL) receives the final max |L-L0|/L0.
 * It stops where no damped step lowers the strain. Returns KIN_OK;
 * KIN_ENULL; KIN_EINVAL (max_iter < 1); KIN_ENOTCONVERGED (assembly
 * unchanged); KIN_EGEOM (assembly unchanged) when the iteration reaches a
 * bar of zero length (a rest length the bars cannot take pulls its joints
 * together: the bar has no direction there, and nothing goes to LAPACK);
 * LAPACK codes. */
KIN_API int kin_relax(kin_assembly *a, int max_iter, double *residual);

#ifdef __cplusplus
}
#endif

#endif /* KIN_PATH_H */
