/* libkin: following a path to its next event (docs/follow.md).
 *
 * One call follows a path, from a regular point or out of a bifurcation
 * along a chosen branch, until something happens, and says what:
 *   - a bifurcation, located (kin_locate_next with the fast method) to
 *     vr_tol, or, where rounding puts vr_tol out of reach at that point, to
 *     the best accuracy reached there (the tolerance is relaxed tenfold at a
 *     time up to vr_floor, and the accuracy reached is reported);
 *   - a near miss: v_r has a non-zero minimum (a near-singular but regular
 *     configuration);
 *   - a closed loop: the path returns to the start configuration;
 *   - a budget: the path length or the number of steps allowed;
 *   - a contact between two parts, if asked for (kin_set_contact_events);
 *   - a failure (a step that cannot be taken, the branch direction not
 *     leading anywhere, a cancel), with its status and kin_last_error(). */
#ifndef KIN_FOLLOW_H
#define KIN_FOLLOW_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"
#include "kin_progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How a follow ended. */
enum kin_follow_event {
    KIN_FOLLOW_NONE = 0,         /* nothing followed (argument errors: info zeroed) */
    KIN_FOLLOW_BIFURCATION = 1,  /* a bifurcation located; the assembly sits on it (analysed:
                                    m, s, U_m, W_s readable, counted at the accuracy reached) */
    KIN_FOLLOW_NEAR_MISS = 2,    /* v_r has a minimum the locator could not bring below
                                    vr_floor: the assembly is at that minimum of v_r / v_max
                                    along the path where min_located (v_r_rel its value, which
                                    can lie below vr_floor: a bifurcation that could not be
                                    pinned), else at the regular point before it */
    KIN_FOLLOW_CLOSED_LOOP = 3,  /* the path came back to the start configuration (within
                                    loop_tol, with a parallel tangent): the assembly is at the
                                    first point of the path past that return */
    KIN_FOLLOW_LENGTH_LIMIT = 4, /* path length max_length reached: the assembly at the
                                    first point beyond it */
    KIN_FOLLOW_STEP_LIMIT = 5,   /* max_steps steps taken without an event */
    KIN_FOLLOW_FAILED = 6,       /* the call failed after it started following: status and
                                    kin_last_error() say why; the assembly is at the last
                                    regular point reached (stepping can resume) */
    KIN_FOLLOW_CONTACT = 7,      /* two parts that share no joint touched (only with
                                    kin_set_contact_events, kin_contact.h): the assembly at
                                    the first point in contact, located to the tolerance set
                                    there; kin_last_contact names the parts */
    /* with hold_hinges (HELD HINGES below): */
    KIN_FOLLOW_HINGE_CLOSED = 8, /* a hinge closed (located as a contact) and is now held
                                    closed; the held structure still moves (held_m >= 1):
                                    the next follow goes on with it held */
    KIN_FOLLOW_HELD_RIGID = 9,   /* a hinge closed and the structure with its closed
                                    hinges held has no motion (held_m = 0), or a follow
                                    from a held state whose only motion presses a held
                                    hinge through (nothing moved) */
    KIN_FOLLOW_HINGE_REOPENED = 10 /* the motion along a held path opened a held hinge (on
                                    its own side): located where its gap passes the closed
                                    threshold; the hold released */
};

/* HELD HINGES (kin_follow_options.hold_hinges, docs/contact.md "Held
 * hinges"). With contact events and hinge contact on (kin_contact.h), a
 * follow that reaches a point where hinges close (a contact event, or a
 * bifurcation, with a hinge's gap at most 1e-6 x the RMS rest length and
 * its fold side tracked) holds them closed there: the membrane cannot pass
 * through, it stays closed. The hold is the unilateral constraint
 * delta_h >= 0 on the angle between the hinge's panels, linearised by the
 * gradient of its signed volume (the far-corner distance, a bar, is
 * stationary at closure: no first-order constraint). The held structure's
 * first-order motions are the mechanisms (singular values up to 1e-3
 * v_max, so that a bifurcation the closure was located next to counts)
 * along which no held hinge's angle moves: info->held_m of them (0: rigid,
 * event HELD_RIGID). A later follow from there with hold_hinges (the holds
 * kept with the configuration, as kin_hinge_sides) decides by the rate
 * of each held hinge's angle along its direction (dir, else the held
 * motion where there is one, else the path's tangent): opening on its own
 * side releases the hold (the motion reopens it: info->reopened);
 * pressing it through refuses the direction (at a bifurcation KIN_EINVAL,
 * at a regular point event HELD_RIGID, nothing moved); zero (to
 * hold_rate_tol) follows with it held: each step checks that it stays
 * closed, and where the path opens it the follow ends with
 * HINGE_REOPENED, where it would pass through with CONTACT. */

/* kin_follow_info.return_branch of a return to the start whose branch is not
 * clear (no arrival direction measured before the start, the arrival
 * direction not nearer one branch than any other by branch_margin, or Newton
 * on the second-order equations not reaching that branch's exact solution):
 * never a closed loop. */
enum { KIN_FOLLOW_RETURN_UNDECIDED = -2 };

/* kin_follow_options.return_fn: the start's branch lines held by the caller
 * (kin_follow_event_ex). Called at each return to the start with t, the
 * direction (nfree entries, not normalised) the path comes back along. It
 * returns the index (>= 0) of the caller's line nearest the line of t, and
 * sets *angle to the angle (radians, in [0, pi/2]) between the two lines and
 * *gap (>= 0; INFINITY with one line) to how much farther the next nearest
 * line is: what the follower computes itself from `branches`. A negative
 * return stops the follow (event FAILED, KIN_ECANCELLED). */
typedef int (*kin_follow_return_fn)(void *user, const double *t, int nfree, double *angle, double *gap);

/* Settings. Start from kin_follow_options_default() and change what you need. */
typedef struct kin_follow_options {
    size_t size;        /* sizeof(kin_follow_options) as the caller compiled it (docs/abi.md) */
    double vr_tol;      /* a bifurcation is located when v_r <= vr_tol * v_max. Default 1e-10 */
    double vr_floor;    /* largest tolerance accepted where vr_tol is out of reach (the
                           located point is then only that exact). Default 1e-6 */
    double switch_eps;  /* detection threshold of the locator (kin_locate_options). Default 1e-2 */
    double delta;       /* step amplitude while following; 0 = automatic. Default 0 */
    int max_steps;      /* step budget (following steps). Default 1000 */
    int max_iter;       /* location iterations per attempt. Default 60 */
    double max_length;  /* path-length budget (length units), > 0, or 0 = none. Default 0 */
    double loop_tol;    /* closed loop: the path passes within loop_tol * RMS rest length of
                           the start configuration after having been 2 loop_tol away.
                           Default 1e-2 */
    double first_step;  /* at a bifurcation: the first step, as a fraction of the largest
                           step (step_fraction * RMS rest length), in (0, 1]; made ten
                           times as long (up to the largest step) while the point it
                           reaches still counts as a bifurcation. Default 1e-3 */
    double branch_cos;  /* at a bifurcation: the first chord must be parallel to the branch
                           direction to this |cos|. Default 0.99 */
    /* layout 2 (docs/abi.md): a host compiled without these fields gets their defaults */
    int steps_mode;     /* enum kin_follow_steps: how regular stretches are stepped.
                           Default KIN_FOLLOW_STEPS_CHEAP */
    double branch_margin; /* kin_follow_event_ex with the start's branch directions: a
                           return to the start is a closed loop only if its direction is
                           nearer its own departure branch than any other branch by this
                           angle (radians); else it is located like a bifurcation.
                           Default 0.05 */
    /* layout 3 (docs/abi.md): a host compiled without these fields gets their defaults */
    kin_follow_return_fn return_fn; /* at a bifurcation, instead of kin_follow_event_ex's
                           `branches` (give one or the other): the caller finds the
                           branch nearest a return's direction among its lines (many
                           lines checked once by the caller, not at every call).
                           Default NULL (none) */
    void *return_user;  /* passed to return_fn unchanged. Default NULL */
    int return_own;     /* with return_fn: the index (>= 0) of dir's own branch among the
                           caller's lines (the one nearest dir). Default -1 */
    /* layout 4 (docs/abi.md): a host compiled without these fields gets their defaults */
    int hold_hinges;    /* 1: hold closed hinges closed (HELD HINGES above; needs contact
                           events with hinge contact on); 0: no holds. Default 0 */
    double hold_rate_tol; /* a held hinge's angle rate (radians per unit of free-coordinate
                           motion, x the RMS rest length) below this is zero: the motion
                           keeps it closed. Default 1e-6 */
} kin_follow_options;

/* How kin_follow_event steps between events (kin_follow_options.steps_mode). */
enum kin_follow_steps {
    KIN_FOLLOW_STEPS_SVD = 0,   /* an SVD at every step (the follower of 0.3) */
    KIN_FOLLOW_STEPS_CHEAP = 1  /* default: LU steps (KIN_STEP_LU, the SVD mode's amplitudes)
                                   on regular stretches, watched by the sign of
                                   det [C; t^T; R^T] from their factors, the estimated
                                   v_r / v_max and, where that is small, the SVD detector's
                                   own turn rule on the slope of the vanishing singular
                                   value (vectors by inverse iteration); the SVD locator's
                                   steps from one or two points before anything its
                                   detectors could fire on, and LU steps again past it:
                                   the SVD follower's events and points (docs/follow.md) */
};

/* What a follow did and where it ended. */
typedef struct kin_follow_info {
    size_t size;         /* sizeof(kin_follow_info) as the caller compiled it (docs/abi.md) */
    int event;           /* enum kin_follow_event */
    int status;          /* the call's return value (KIN_OK for every event but FAILED) */
    int steps;           /* path-following steps taken (the first step off a bifurcation
                            included) */
    int forward;         /* forward calculations while locating */
    int factorizations;  /* factorizations while locating */
    int attempts;        /* location attempts (1 + the relaxations of vr_tol) */
    double length;       /* path length travelled (sum of chords, >= 0) */
    double vr_tol_used;  /* BIFURCATION: the tolerance it was located to (vr_tol ... vr_floor;
                            vr_tol for one vanishing singular value: a corank-1 point that
                            only a relaxed tolerance accepts is decided at the minimum of
                            v_r instead, as a NEAR_MISS or a BIFURCATION at v_r_rel <= vr_tol).
                            NEAR_MISS with min_located: the floor, the v_r / v_max a crossing
                            inside the minimum's final interval could still show (the secant
                            slope x the width, >= 64 eps); a minimum not 10 x above it is
                            undecided (docs/follow.md). 0 otherwise */
    double v_r_rel;      /* at the end point: the vanishing singular values' largest / v_max
                            (kin_locate_info.v_r_rel); NEAR_MISS: v_r / v_max there (at the
                            minimum where min_located) */
    int m_internal, s;   /* analysis at the end point */
    int zero_order;      /* BIFURCATION: 1 a crossing, 2 a tangency, 0 not estimated */
    int path_kept;       /* BIFURCATION: the location stayed on the path (eq. 26) */
    int at_start;        /* the path came back to the start configuration: CLOSED_LOOP, or
                            BIFURCATION within loop_tol of a start that is a bifurcation */
    double start_distance; /* |end - start| (free coordinates) / RMS rest length */
    double tangent_cos;  /* at a bifurcation: cos between the first chord and dir (else 1) */
    /* layout 2 (docs/abi.md): a host compiled without these fields does not get them */
    int cheap_steps;     /* of `steps`, those taken with LU factors only (no SVD); steps
                            stepped again by the SVD locator after a handover count once,
                            as SVD steps */
    int handovers;       /* times the cheap steps handed over to the SVD locator */
    int samples;         /* kin_follow_event_ex: configurations written to its buffer */
    int return_branch;   /* kin_follow_event_ex with branch directions, at a return to the
                            start: the index of the branch it came back along (the exact
                            second-order solution Newton reaches from the arrival direction,
                            docs/follow.md; with return_fn, in the caller's numbering);
                            KIN_FOLLOW_RETURN_UNDECIDED where that is not clear; else -1 */
    double return_angle; /* that return: angle (radians) between the arrival direction and
                            the branch nearest it; the next nearest is return_gap farther
                            (both NaN where no arrival direction could be measured) */
    double return_gap;
    /* layout 3 (docs/abi.md): a host compiled without these fields does not get them */
    double min_width;    /* NEAR_MISS with min_located: the interval of path length (/ RMS
                            rest length) the minimum of v_r / v_max was located to (<= 1e-8);
                            v_r_rel is the value there. 0 otherwise */
    int min_located;     /* NEAR_MISS: 1 when the end is the located minimum of v_r / v_max
                            along the path (Brent's method over the step where v_r turned),
                            0 when it is the regular point before the dip */
    int min_evals;       /* NEAR_MISS: points computed to locate that minimum */
    /* layout 4 (docs/abi.md): a host compiled without these fields does not get them */
    int hinge;           /* HINGE_CLOSED / HELD_RIGID: the first hinge held there;
                            HINGE_REOPENED: the hinge reopened; else -1 */
    int held;            /* hinges held at the end point (hold_hinges) */
    int held_m;          /* motions of the structure with them held, at the end point (0:
                            rigid); -1 where none is held or it was not analysed (no dense
                            analysis, or more than 16 near-zero singular values) */
    int reopened;        /* holds released at the start: dir opens those hinges */
} kin_follow_info;

/* Fill *o with the defaults above, for a struct of `size` bytes: pass
 * sizeof(kin_follow_options) (the macro kin_follow_options_default below does). size must be the sizeof
 * of one of kin_follow_options's published layouts (docs/abi.md); then exactly size bytes
 * are written (o->size = size) and KIN_OK is returned; otherwise nothing is
 * written and KIN_EINVAL is returned. KIN_ENULL if o is NULL. */
KIN_API int kin_follow_options_init(kin_follow_options *o, size_t size);

/* The same with size = sizeof(kin_follow_options): a C or C++ host compiled with this
 * header calls kin_follow_options_init through the macro. The function itself is
 * for programs built before the macro existed: it writes only the first
 * layout (o->size = its sizeof, docs/abi.md), which is all an old program
 * can have room for. Does nothing if o is NULL. */
KIN_API void kin_follow_options_default(kin_follow_options *o);
#define kin_follow_options_default(o) ((void)kin_follow_options_init((o), sizeof(kin_follow_options)))

/* Follow the path from the current point to its next event (above).
 *  a     the assembly (LU steps on regular stretches and SVD steps near
 *        events, o->steps_mode; the handle's options are kept and restored).
 *  dir   NULL at a regular point (follow the current orientation: forwards
 *        along the last tangent, or the mechanism's deterministic
 *        orientation after kin_set_coords), or nfree entries: at a regular
 *        point the direction to follow (t.dir > 0), at a bifurcation the
 *        branch direction, e.g. U_m*beta for a second-order solution beta
 *        (kin_quadrics_scan / kin_quadrics_homotopy) with a sign. At a
 *        bifurcation the first step is small (first_step) and its chord
 *        must be parallel to dir (branch_cos), or the call fails with
 *        KIN_EPATHJUMP.
 *  o     options (NULL: the defaults).
 *  info  optional; receives the event and the counts.
 * The start configuration is the point at the call. Progress goes to the
 * handle's callback (kin_set_progress): done = steps + forward calculations
 * over all attempts, total = max_steps + max_iter x the attempts possible;
 * a successful call ends with done = total. A cancel returns KIN_ECANCELLED
 * with event FAILED, the assembly at the last regular point reached.
 * Returns KIN_OK for every event but FAILED (see info->event);
 * KIN_ENULL, KIN_EINVAL (options out of range, info or options size; dir
 * not finite or not a first-order mechanism), KIN_ERANGE, KIN_EBIFURCATION
 * (at a bifurcation with dir NULL), KIN_ENOMECH: before anything moved
 * (event NONE); after following started (event FAILED): KIN_EPATHJUMP,
 * KIN_ENOTCONVERGED, KIN_ECANCELLED, KIN_ENOMEM, LAPACK codes. */
KIN_API int kin_follow_event(kin_assembly *a, const double *dir, const kin_follow_options *o,
                             kin_follow_info *info);

/* kin_follow_event with two optional extras (NULL / 0 for none):
 *  branches, nbranch  the start bifurcation's branch directions (nbranch x
 *        nfree, column-major: branch j at branches + j*nfree), e.g. U_m beta
 *        for every real second-order solution beta, any sign, dir among
 *        them (up to sign and scale). A return to the start then counts as a
 *        closed loop only when it comes back along dir's own branch: its
 *        arrival direction (measured before the start) nearer that branch
 *        than any other by branch_margin, and Newton on the start's
 *        second-order equations from it reaching that branch's exact
 *        solution (docs/follow.md); along any other branch, or not clear
 *        (KIN_FOLLOW_RETURN_UNDECIDED), following goes on and the start is
 *        located like any bifurcation (info->at_start).
 *        Without them (nor o->return_fn, which gives the same decision from
 *        the caller's lines) a return with a tangent parallel to the
 *        start's (|cos| >= 0.9) is a loop. Ignored at a regular start.
 *  samples, sample_length, capacity, *nsamples  a buffer for up to
 *        capacity configurations along the path (njoints*dim coordinates
 *        each, samples + k*njoints*dim) and their path lengths: the points
 *        the following steps reached, every step until the buffer fills, then
 *        every second one of those kept and every second step, and so on, so
 *        they stay evenly spread by steps over the whole path (the end point
 *        and the start are not included). *nsamples receives the count (also
 *        info->samples). Any of samples / sample_length may be NULL.
 * Returns as kin_follow_event; KIN_EINVAL also for nbranch < 0, branches
 * not finite, branches with o->return_fn, o->return_fn without
 * o->return_own >= 0, capacity < 0, or capacity > 0 without nsamples;
 * after following started, a return_fn that returns < 0 gives event FAILED
 * with KIN_ECANCELLED, one that gives an angle outside [0, pi/2] or a
 * negative or NaN gap event FAILED with KIN_EINVAL. */
KIN_API int kin_follow_event_ex(kin_assembly *a, const double *dir, const kin_follow_options *o,
                                const double *branches, int nbranch, double *samples, double *sample_length,
                                int capacity, int *nsamples, kin_follow_info *info);

#ifdef __cplusplus
}
#endif

#endif /* KIN_FOLLOW_H */
