/* Private to the follower of libkin/branches/ (kin_follow_event, follow.c):
 * what its three files share. follow.c is the call (its options, its
 * stages from the start to the classified end); follow_cheap.c the cheap
 * stretches of LU steps between events and the handovers to and from the
 * SVD locator; follow_watch.c the checks after every accepted step, in
 * both (the hook the locator calls too). Calls go one way only, so that no
 * two files call each other: follow.c -> follow_cheap.c, follow_watch.c;
 * follow_cheap.c -> follow_watch.c; return_branch.c (the branch a return
 * comes back along) is called by follow.c and follow_watch.c. The tuning
 * constants are here, in one place, with the measurements behind them. */
#ifndef KIN_FOLLOW_INTERNAL_H
#define KIN_FOLLOW_INTERNAL_H

#include "model/internal.h"
#include "path/path.h"

/* a return to the start counts only with the tangent parallel to the
 * start's to this |cos| (another path through a nearby point does not),
 * where the caller gave no branch directions */
static const double LOOP_TANGENT_COS = 0.9;
/* a return's arrival direction: the secants to the start from the point
 * before the closing chord (or the newest earlier one outside the loop_tol
 * ball; at d1) and from the newest point before it at ARRIVAL_SPREAD d1
 * or farther (of the last ARRIVAL_KEEP), extrapolated
 * linearly to the start. On 25 of the hexagonal flat state's returns the
 * nearer secant alone was 0.001-0.11 rad from the branch it led to (with the
 * step 10% longer one return named another branch than at 0.9 and 1.0);
 * extrapolated, docs/follow.md (bench/bench_return_labels.py) */
static const double ARRIVAL_SPREAD = 1.25;
enum { ARRIVAL_KEEP = 8 };
/* each relaxation of the location tolerance multiplies it by this */
static const double RELAX_FACTOR = 10.0;
/* cheap stretches hand over to the SVD locator where the estimated
 * v_r / v_max is below this multiple of switch_eps, and LU steps resume
 * only above it. The detector's turn rule fires on any turn of v_r whose
 * tangent lines meet below switch_eps, however shallow; the LU estimates
 * (an upper bound, a few 1e-3 relative) cannot show such a dip (the
 * hexagonal sail's R^C: 3 of 64 near misses at v_r / v_max 0.0054 missed
 * with 0.1 here), so below the threshold, with a margin, every step is an
 * SVD step. */
static const double CHEAP_NEAR_FACTOR = 3.0;
/* below it the slope of the vanishing singular value is computed as the SVD
 * detector does (kin__sv_derivative), from the singular vectors by inverse
 * iteration with the LU factors: at most this many passes, until the unit
 * vector moves less than this (else the SVD takes over) */
enum { SLOPE_PASSES = 40 };
/* ... by subspace iteration with this many vectors (kin__lu_vr_triple): the
 * flat state's lowest singular values come in close groups, where one
 * vector converges at (v_r / v_(r-1))^2 per pass: on the 200-branch
 * benchmark 11.6 passes per point, 1% of points not converged in 40 (each a
 * handover), 12% of the cheap follower's time. With 2 vectors 5.4 passes
 * (each about 1.6x the cost of one vector's) and every point converged;
 * 3 and 4 vectors take 4.8 and 4.4 passes at 2.3x and 2.6x the cost. */
enum { SLOPE_BLOCK = 2 };
static const double SLOPE_VECTOR_TOL = 1e-9;
/* a slope below this x v_max / RMS length is too flat to tell its sign:
 * the SVD takes over */
static const double SLOPE_ZERO = 1e-6;
/* the turn rule's threshold, switch_eps x v_max, with this margin for the
 * lower-bound estimate of v_max */
static const double SLOPE_TURN_MARGIN = 1.5;
/* the LU steps count singular values as zero (and fall back to the SVD)
 * below 1000 x this fraction of vr_tol, as the locator's steps do */
static const double CHEAP_RANK_FRACTION = 1e-3;
/* after a handover the SVD locator steps at least this many steps, and up
 * to the point where the cheap stretch stopped (a step that failed: past
 * it, and 2 steps), before LU steps resume. The detectors have then seen
 * the suspect step with the SVD: resuming at its end, not a step later,
 * saves an SVD step per handover that finds nothing (2 before) */
enum { RESUME_AFTER = 1, RESUME_AFTER_FAILED = 2 };
/* ... and, where v_r / v_max is below CHEAP_NEAR_FACTOR x switch_eps, only
 * once v_r is at most RESUME_GAP of the singular value SLOPE_BLOCK above it
 * (the slope's subspace converges at their ratio squared per pass) and at
 * most RESUME_PAIR_GAP of the next one (the Ritz vector of v_r within the
 * subspace needs that gap: at R^B, without it, the iteration did not
 * converge in 40 passes and the SVD took over again at the next step, 5.6
 * handovers a branch instead of 1.3). Measured against the earlier rule
 * (RESUME_GAP of the next singular value): LU-only steps 90% -> 94% on the
 * flat state's 200 branches, 62% -> 73% at R^B, the same events and points */
static const double RESUME_GAP = 0.5;
static const double RESUME_PAIR_GAP = 0.9;
/* follow_ctx.reason: the SVD locator handed back to LU steps */
enum { REASON_RESUME = -1 };
static const double HALF_PI = 1.5707963267948966;

/* the caller's extras (kin_follow_event_ex) */
typedef struct follow_extra {
    const double *branches; /* nbranch x nf, or NULL */
    int nbranch;
    double *samples, *sample_length; /* capacity entries, or NULL */
    int capacity;
    /* the record behind them: room for 2 capacity + 4 points, their path
     * indices and lengths (SAMPLES, follow_watch.c) */
    double *rec, *rec_len;
    int *rec_idx, rec_room;
} follow_extra;

/* a point the cheap stretch may go back to, with the follower's counters there */
typedef struct kept_point {
    kin__path_point p;
    double *border; /* nf: the border row of its LU factors (the tangent before the step to it) */
    int has_border; /* it was an LU point (its factors can be made again) */
    double length;
    int left, index;
} kept_point;

/* one call of kin_follow_event_ex: its arguments, workspace and counters */
typedef struct follow_ctx {
    kin_assembly *a;
    const kin_follow_options *o;
    const follow_extra *x;
    kin_follow_info *info;
    double *xs, *ts;  /* start: free coordinates and tangent */
    double *xp, *xq;  /* the previous point and the new one */
    double *xpp;      /* the point before xp, where the path had length len_pp */
    double *tprev;    /* cheap stretch: the tangent before the step */
    double *u, *w, *scr; /* cheap stretch: singular vectors (nf, nb), scratch (2 nj dim) */
    double *blk;      /* ... the slope's subspace (2 SLOPE_BLOCK nf), its Ritz vectors kept where blk_warm */
    int blk_warm;
    /* with branch directions at a bifurcation start (return_branch.c): the
     * start's mechanisms U (nf x ret_m) and second-order matrices Q, Newton's
     * workspace; ret_m 0 where the start has no isolated second-order roots */
    double *ret_U, *ret_Q, *ret_J, *ret_F, *ret_qb, *ret_beta, *ret_tr;
    int *ret_ipiv, ret_m;
    double *tarr;     /* nf: the direction a return arrives along */
    /* the last ARRIVAL_KEEP points the steps reached before xp, newest at
     * hist_pos - 1 (a return's farther arrival points: all on the path,
     * whatever the locator or a cheap stretch's going back did to xp) */
    double *hist;
    int nhist, hist_pos;
    double scale;     /* RMS rest length */
    double length;    /* sum of chords */
    double len_pp;
    int left;         /* has been 2 loop_tol away from the start */
    int reason;       /* KIN_FOLLOW_CLOSED_LOOP / _LENGTH_LIMIT when the hook stopped */
    int at_bif;       /* the start is a bifurcation */
    int own;          /* index of dir's own branch among x->branches (or o->return_fn's lines), or -1 */
    int hook_rc;      /* o->return_fn failed: the call's status (event FAILED) */
    /* SAMPLES: the current point's index along the path (steps from the
     * start), the points recorded, every stride-th index */
    int p, nrec, stride;
    kept_point kept[2]; /* cheap stretch: the two points before the current one */
    int nkept;
    /* after a handover: SVD steps taken, the length to pass, and the exact
     * v_r / v_max at the last two SVD points */
    int watch, svd_steps, resume_after;
    double resume_len, rho_prev, rho_cur;
    /* a handover on a sign change the SVD locator would bracket at once
     * (kin__follow_cheap_stretch): the handle left at the bracket's end, kept[1] its
     * start; direct_newer: the kept point the usual handover goes back to */
    int direct, direct_newer;
    /* progress: the caller's callback, fed cumulative counts */
    kin_progress_fn user_fn;
    void *user_data;
    double done_base, total;
    int attempts;     /* location attempts: vr_tol, then relaxed tenfold up to vr_floor */
} follow_ctx;

/* ---- follow_watch.c ---- */

/* the distance of x and y (n entries) */
double kin__follow_distance(int n, const double *x, const double *y);
/* the caller's samples from the record; returns their count */
int kin__follow_deliver_samples(const follow_ctx *c);
/* the hook after every accepted step (user: the follow_ctx), of the cheap
 * stretches and of the locator: KIN__HOOK_GO, or a stop (c->reason) */
int kin__follow_after_step(void *user, const kin_assembly *a);
/* after the locator returns: the length and the points from where it left
 * the handle */
void kin__follow_resync(follow_ctx *c);

/* ---- return_branch.c ---- */

/* the branch nearest the line of t: its index, angle, and the gap to the
 * next nearest (INFINITY with one branch) */
int kin__follow_nearest_branch(const follow_ctx *c, const double *t, double *angle, double *gap);

/* at the start (a bifurcation, with branch directions): the start's U_m and
 * Q_j for the returns (c->ret_m 0 where m != s + 1 or the second order
 * cannot be had). A status (KIN_ENOMEM) */
int kin__return_open(follow_ctx *c);
void kin__return_close(follow_ctx *c);
/* the caller's line a return arriving along t0 comes back along: Newton on
 * the start's second-order equations from t0, the root matched to a line
 * (*angle, *gap: t0's angle to the nearest line, the next one gap farther);
 * KIN_FOLLOW_RETURN_UNDECIDED where that is not clear; -1: return_fn failed
 * (c->hook_rc) */
int kin__return_branch(follow_ctx *c, const double *t0, double *angle, double *gap);

/* ---- follow_cheap.c ---- */

/* LU steps from the current point until something may happen (*stop = 1:
 * the follow ends, info->event set; else the SVD locator takes over);
 * r_before: v_r / v_max at the point before. A status. */
int kin__follow_cheap_stretch(follow_ctx *c, kin_follow_info *info, double r_before, int *stop);
/* the handle back to a kept point (newer: the newer of two) */
void kin__follow_back_to_kept(follow_ctx *c, int newer);
/* the first step off a bifurcation by LU: the options for it (user: the
 * handle's own), and after it the mechanism count the SVD step would have
 * given (into si->m_internal; a status) */
void kin__follow_first_step_lu(follow_ctx *c, const kin_options *user);
int kin__follow_first_point_verdict(follow_ctx *c, kin_step_info *si);

#endif /* KIN_FOLLOW_INTERNAL_H */
