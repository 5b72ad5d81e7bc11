/* Private: homotopy/solver/, the plain complete solver between the tracker
 * (track/) and the entry points (homotopy/homotopy.c): the set-up of one
 * call (the options, the scaled problem and its threads' workspaces,
 * hom_solver) and the runs of paths on the one thread pool of every
 * threaded route, each thread HOM_BATCH paths at a time in lockstep
 * (homotopy_solver.c, homotopy_pool.c); then the checks of the endpoints
 * against what total-degree homotopy guarantees, the re-tracks and the
 * accounting (homotopy_merge.c, which also merges ranges tracked
 * elsewhere). It uses track/ only; the symmetric solver (symmetric/) runs
 * its paths on the same pool and checks, re-certifies and counts its
 * endpoints with the same code.
 *
 * This header: the solver's state, runs, checks and merge. */
#ifndef KIN_HOMOTOPY_SOLVER_H
#define KIN_HOMOTOPY_SOLVER_H

#include "homotopy/track/homotopy_track.h"
#include "libkin/kin_branch.h"

/* ---- checks on the endpoints (homotopy_merge.c) ---- */
typedef struct hom_key {
    double key;
    int path;
} hom_key;

typedef struct hom_checks {
    int duplicates; /* endpoints beyond the first on a certified root */
    int unpaired;   /* non-real endpoints without an endpoint on the conjugate root */
} hom_checks;

/* Group the certified (real and non-real) endpoints of npaths paths by root
 * (parent: union-find over paths, the root's representative is its
 * smallest path index; see kin__hom_find) and mark non-real ones whose
 * conjugate root was reached (paired). w: a unit vector (m) for the sort
 * key; keys, parent, paired: npaths each. */
hom_checks kin__hom_check(int m, int npaths, const hom_end *ends, const double *zr, const double *zi, const double *w,
                          hom_key *keys, int *parent, unsigned char *paired);
int kin__hom_find(int *parent, int p);

/* ---- the solver: set-up and runs of paths on the threads
 * (homotopy_solver.c), below the checks, re-tracks and accounting
 * (homotopy_merge.c) and the public entry points (homotopy.c) ---- */

/* the first pass's tracking tolerances (homotopy_merge.c) */
extern const hom_settings kin__hom_base_settings;

/* the caller's progress callback and what it has been told */
typedef struct hom_report {
    kin_progress_fn fn;
    void *user;
    double base;  /* paths tracked in earlier runs */
    double total; /* paths scheduled so far */
    double last;  /* time of the last call (seconds, monotonic) */
    int cancelled;
} hom_report;

/* The orbits of the 2^s start roots under a symmetry P of the homotopy that
 * permutes the coordinates (path b's bit j - 1 is the sign of x_j; P maps
 * it to path next[b]): made by kin__orbits_init
 * (symmetric/homotopy_equi.h), read by kin__hom_run. */
typedef struct hom_orbits {
    int npaths, nreps, m;
    int perm[HOM_MAX_M];
    int *next;           /* the path P maps b to */
    int *rep;            /* the orbit's representative: its smallest path */
    int *reps;           /* the representatives, ascending (nreps) */
    int *list;           /* kin__hom_run's scratch: npaths */
    unsigned char *mark; /* kin__hom_run's scratch: npaths */
    int *slot;           /* NULL: path p's endpoint is stored at index p; else at slot[p] (a
                            range of orbits stored compactly, kin_quadrics_homotopy_orbit_range) */
} hom_orbits;

/* the scaled problem, the sort-key direction and the worker threads'
 * workspaces of one call */
typedef struct hom_solver {
    hom_problem P;
    double *Qr, *Qb, *Qs;
    double w[HOM_MAX_M]; /* unit vector of the duplicate checks' sort key */
    int npaths;          /* 2^s */
    int nthreads;
    struct hom_pool *pool; /* the worker threads (homotopy_pool.h) */
    hom_ws **ws;         /* per thread: the one-path tracker's and certificate's workspace */
    hom_bws **bws;       /* per thread: the lockstep tracker's workspace */
    hom_orbits *orb;     /* NULL, or the start roots' orbits: kin__hom_run then tracks one path
                            per orbit and stores every member's endpoint (the representative's
                            permuted, refined and certified) */
    const double *Qin;   /* the caller's system (not owned), which the interval certificates
                            prove the endpoints of (kin__hom_prove) */
    int prove;           /* kin_homotopy_options.prove: 0 none, 1 fast test then Arb, 2 Arb only (default) */
    const double *U;     /* NULL, or the endpoints x are those of Qin at beta = U x (column-major
                            m x m: the equivariant route's rotated system) */
} hom_solver;

/* Check m, s, Q, the options (nthreads >= 0, max_paths >= 1) and set up the
 * solver for calls that track at most `work` paths at once (the thread
 * count is clamped to it). KIN_OK, KIN_EINVAL, KIN_ERANGE, KIN_ENOMEM. */
int kin__hom_solver_init(hom_solver *H, int m, int s, const double *Q, const kin_homotopy_options *o, long work);
void kin__hom_solver_free(hom_solver *H);
/* the workspace of thread t < H->nthreads */
hom_ws *kin__hom_pool_ws(const hom_solver *H, int t);

/* Track the paths list[0..n-1] (list NULL: first .. first + n - 1), storing
 * path p's endpoint at index p - offset of ends, zr, zi; progress through
 * R (R->cancelled on a cancel). With H->orb (offset 0), the paths' orbit
 * representatives are tracked and every member of their orbits stored.
 * KIN_OK or KIN_ENOMEM. */
int kin__hom_run(hom_solver *H, const hom_settings *S, const int *list, int first, int n, int offset, hom_end *ends,
                 double *zr, double *zi, hom_report *R);

/* a real solution b (m) made unit with its largest entry positive, as the
 * solver returns them */
void kin__hom_unit_beta(int m, double *b);
/* max_j |b^T Q_j b| for unit b, Qr the scaled rows (hom_solver.Qr) */
double kin__hom_residual(int m, int s, const double *Qr, const double *b);

/* The first pass over list[0..n-1] (NULL: 0 .. n - 1; with H->orb, their
 * orbits), then kin__hom_merge: the whole solve of H's system
 * (homotopy_merge.c). Progress
 * through opt (total n, then the re-tracks). *tracked: the paths tracked.
 * KIN_OK, KIN_ECANCELLED, KIN_ENOMEM. */
int kin__hom_solve(hom_solver *H, const int *list, int n, const kin_homotopy_options *o, double *betas, int maxsol,
                   int *nsol, int *multiplicity, kin_homotopy_info *info, long *tracked);
/* The first progress call of a solve (R->cancelled if the caller cancels). */
void kin__hom_report_start(hom_report *R);
/* o = the defaults, then the caller's opt (NULL: none) as far as its size
 * goes: KIN_OK, or KIN_EINVAL for a bad opt->size */
int kin__hom_options(const kin_homotopy_options *opt, kin_homotopy_options *o);
/* The first checks of an entry point that fills a kin_homotopy_info: *nsol
 * (if given) := 0; info checked (KIN_ENULL, KIN_EINVAL) and zeroed after its
 * size; then kin__hom_options */
int kin__hom_entry(const kin_homotopy_options *opt, kin_homotopy_options *o, kin_homotopy_info *info, int *nsol);
/* n records zeroed, each size set */
void kin__hom_zero_records(kin_homotopy_endpoint *ends, long n);

/* The checks, re-tracks and accounting after every path has been tracked
 * once (ends, zr, zi: all 2^s, changed by the re-tracks). KIN_OK,
 * KIN_ECANCELLED (info zeroed, *nsol = 0), KIN_ENOMEM. */
int kin__hom_merge(hom_solver *H, hom_end *ends, double *zr, double *zi, hom_report *R, double *betas, int maxsol,
                   int *nsol, int *multiplicity, kin_homotopy_info *info);

/* The accounting of kin__hom_merge after the checks (ck, parent: from
 * kin__hom_check over H->npaths endpoints): fills info, betas,
 * multiplicity, *nsol, then the interval certificates (kin__hom_prove,
 * which overwrites zr, zi). KIN_OK or KIN_ENOMEM. */
int kin__hom_tally(const hom_solver *H, const hom_end *ends, double *zr, double *zi, int *parent,
                   hom_checks ck, int retracked, double *betas, int maxsol, int *nsol, int *multiplicity,
                   kin_homotopy_info *info);

/* The interval certificates of the endpoints of every path (ends, zr, zi:
 * H->npaths; homotopy_prove_run.c, on H's threads): each endpoint not lost
 * is proven by a Krawczyk test on H->Qin in ball arithmetic and the proven
 * boxes are shown disjoint; fills info's proven_real, proven_nonreal,
 * unproven, proven_all, proven_refined, proven_overlap, unproven_nopoint,
 * unproven_refused. zr, zi are
 * overwritten (by the boxes' centres, in H->Qin's coordinates). R: NULL, or
 * the solve's progress (its callback asked for a cancel every
 * HOM_POOL_REPORT seconds). KIN_OK, KIN_ECANCELLED, KIN_ENOMEM. */
int kin__hom_prove(const hom_solver *H, const hom_end *ends, double *zr, double *zi, hom_report *R,
                   kin_homotopy_info *info);

/* The endpoints of n paths: the tracker's records and their coordinates
 * (real and imaginary parts, m each). */
typedef struct hom_endset {
    hom_end *ends;
    double *zr, *zi;
} hom_endset;
/* allocate E for n paths of m coordinates: KIN_OK, or KIN_ENOMEM with E empty */
int kin__hom_endset_alloc(hom_endset *E, int n, int m);
/* release E (an empty or failed one too) */
void kin__hom_endset_free(hom_endset *E);

/* endpoint records (kin_branch.h) <-> the tracker's */
void kin__hom_export(int m, int path, const hom_end *e, const double *zr, const double *zi, kin_homotopy_endpoint *r,
                     double *z);

#endif /* KIN_HOMOTOPY_SOLVER_H */
