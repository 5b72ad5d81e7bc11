/* Private: the path tracker and endpoint certificate behind
 * kin_quadrics_homotopy (homotopy.c). Complex vectors are kept as separate
 * real and imaginary arrays (the matrices Q_j are real, so Q x costs two
 * real matrix-vector products and no complex arithmetic library calls). */
#ifndef KIN_HOMOTOPY_TRACK_H
#define KIN_HOMOTOPY_TRACK_H

enum {
    HOM_MAX_M = 24,
    HOM_LANES = 4,  /* the equations j < s are padded to a multiple of this (sp) */
    HOM_QBLOCK = 8, /* rows of Q per block in hom_problem.Qb */
    /* m*sp rounded up to whole blocks, at most: */
    HOM_MAX_ROWS = (HOM_MAX_M * HOM_MAX_M + HOM_QBLOCK - 1) / HOM_QBLOCK * HOM_QBLOCK
};

/* s rounded up to whole lanes: the stride of the interleaved rows of Q */
static inline int kin__hom_sp(int s) { return (s + HOM_LANES - 1) / HOM_LANES * HOM_LANES; }
/* rows of hom_problem.Qb (zero-padded to whole blocks) */
static inline int kin__hom_rows(int m, int s)
{
    return (m * kin__hom_sp(s) + HOM_QBLOCK - 1) / HOM_QBLOCK * HOM_QBLOCK;
}

/* rows of hom_problem.Qs: m*s rounded up to whole blocks of HOM_SBLOCK */
enum { HOM_SBLOCK = 4 };
static inline int kin__hom_srows(int m, int s) { return (m * s + HOM_SBLOCK - 1) / HOM_SBLOCK * HOM_SBLOCK; }

/* endpoint classes */
enum { HOM_REAL = 0, HOM_NONREAL = 1, HOM_SINGULAR = 2, HOM_FAILED = 3 };

/* The homotopy H(x, t) = (1 - t) gamma G(x) + t F(x), G_j = x_{j+1}^2 - x_0^2,
 * F_j = x^T Q_j x (j < s), in the affine chart a.x = 1 (m = s + 1). */
typedef struct hom_problem {
    int m, s, sp;                        /* sp = kin__hom_sp(s) */
    const double *Qr;                    /* s*m rows of m: row j*m + r is row r of Q_j / |Q_j|_F */
    const double *Qb;                    /* the same interleaved, row r*sp + j is row r of Q_j (rows
                                            j >= s zero: Q x then has equation j fastest, so sums
                                            over equations vectorise), in blocks of HOM_QBLOCK rows
                                            (kin__hom_rows, zero-padded), column-major within a block */
    const double *Qs;                    /* the lockstep kernels' copy: row r*s + j is row r of Q_j (no
                                            padding), in blocks of HOM_SBLOCK rows (kin__hom_srows,
                                            zero-padded), column-major within a block */
    double gr, gi;                       /* gamma, |gamma| = 1 */
    double ar[HOM_MAX_M], ai[HOM_MAX_M]; /* the random chart */
    double normF, normG;                 /* |F[u,v]| <= normF |u||v| (2-norms); same for G */
} hom_problem;

/* tracking tolerances (tightened when a path is tracked again) */
typedef struct hom_settings {
    double pred_rel;  /* predictor error target relative to |x| */
    double pred_sep;  /* predictor error target as a fraction of the separation radius */
    double corr_sep;  /* largest first Newton correction accepted, fraction of the separation radius */
    double sigma_end; /* a path still not at t = 1 when 1 - t falls below this is classified there */
} hom_settings;

/* what tracking one path produced */
typedef struct hom_end {
    int kind;      /* HOM_REAL .. HOM_FAILED */
    int chart;     /* k: the endpoint z is stored in the chart z_k = 1 (|z_k| largest) */
    int steps;     /* accepted predictor-corrector steps */
    int rejected;  /* rejected steps */
    int recharts;  /* changes of affine chart (the path neared the chart's infinity) */
    int converged; /* Newton at t = 1 converged (a singular endpoint with 0 here is one the
                      refinement could not reach to rounding level) */
    double rminus; /* certified endpoints: a root lies within rminus of z (chart coordinates) */
    double rplus;  /* ... and no other root within rplus */
    double cond;   /* |J|_F |J^-1|_F at the endpoint (chart z_k = 1), inf if singular */
    double sigma;  /* 1 - t where tracking stopped (0: reached t = 1) */
} hom_end;

/* per-thread workspace, allocated once per thread */
typedef struct hom_ws hom_ws;
hom_ws *kin__hom_ws_new(void);
void kin__hom_ws_free(hom_ws *w);

/* Track start solution number `path` (its bits pick the signs of
 * x_j = +-x_0) from t = 0 to 1 and certify the endpoint; zr/zi (m each)
 * receive the endpoint in its chart. */
void kin__hom_track(const hom_problem *P, const hom_settings *S, hom_ws *w, int path, double *zr, double *zi,
                    hom_end *e);

/* ---- lockstep tracking (homotopy_batch.c) ---- */
enum {
    HOM_BATCH = 4,        /* paths tracked at once, one per lane */
    HOM_BATCH_STOP = -2   /* hom_batch_sink.next: abandon the paths in flight */
};
/* where the batch tracker gets its paths and leaves their endpoints */
typedef struct hom_batch_sink {
    void *ctx;
    /* the next path to track, -1 when there is none, HOM_BATCH_STOP to stop
     * at once (the paths in flight are abandoned: not passed to done) */
    int (*next)(void *ctx);
    /* path's endpoint (zr, zi: m each, in e->chart) and record */
    void (*done)(void *ctx, int path, const double *zr, const double *zi, const hom_end *e);
} hom_batch_sink;
/* per-thread workspace of the batch tracker, allocated once per thread */
typedef struct hom_bws hom_bws;
hom_bws *kin__hom_bws_new(void);
void kin__hom_bws_free(hom_bws *b);
/* Track every path K->next hands out, HOM_BATCH at a time, each exactly as
 * kin__hom_track would (the same endpoint and record, bit for bit); w is
 * the one-path workspace for the endpoints' certificates. */
void kin__hom_track_batch(const hom_problem *P, const hom_settings *S, hom_bws *B, hom_ws *w,
                          const hom_batch_sink *K);

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
#include "libkin/kin_branch.h"

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

/* the orbits of the start roots under a symmetry of the homotopy
 * (homotopy_equi.h) */
typedef struct hom_orbits hom_orbits;

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
 * orbits), then kin__hom_merge: the whole solve of H's system. Progress
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
 * multiplicity, *nsol. KIN_OK or KIN_ENOMEM. */
int kin__hom_tally(const hom_solver *H, const hom_end *ends, const double *zr, const double *zi, int *parent,
                   hom_checks ck, int retracked, double *betas, int maxsol, int *nsol, int *multiplicity,
                   kin_homotopy_info *info);

/* Refine the approximate root (xr, xi) of F (any scale, not near the
 * chart's infinity) at t = 1 by Newton in the chart z_k = 1 (k: its
 * largest entry) and certify it (the certificate of kin__hom_track);
 * zr, zi (m each) receive the refined root. */
void kin__hom_certify(const hom_problem *P, hom_ws *w, const double *xr, const double *xi, double *zr, double *zi,
                      hom_end *e);

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

#endif /* KIN_HOMOTOPY_TRACK_H */
