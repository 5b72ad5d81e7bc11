/* libkin: the paths out of a bifurcation point (paper 3.3-3.4).
 *
 * At a bifurcation the assembly has m >= 2 internal mechanisms U_m and
 * s >= 1 self-stresses W_s. A first-order motion U_m*beta extends to second
 * order only if beta^T Q_j beta = 0 for j = 1..s, with (derived from the
 * exact bar-length relation, eq. 12)
 *     Q_j = sum_i (t_ij / L_i) D_i^T D_i,
 * D_i (dim x m) the rows of U_m at bar i's end A minus those at end B (fixed
 * coordinates contribute nothing), t_ij = W_s(i, j), L_i the bar length.
 * The paper's printed eq. 14/17 drops the 1/L_i; that changes the answer
 * whenever bar lengths differ (the sails), see docs/branches.md. */
#ifndef KIN_BRANCH_H
#define KIN_BRANCH_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"
#include "kin_progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Which weighting of the second-order matrices. */
enum kin_q_weighting {
    KIN_Q_EXACT = 0,     /* t_ij / L_i: from eq. 12 (default, correct) */
    KIN_Q_PAPER_EQ17 = 1 /* t_ij as printed in eq. 17 (for comparison only) */
};

/* Second-order compatibility matrices at the current point, from the last
 * analysis (kin_analyse: the SVD's, or in KIN_STEP_SPARSE mode the sparse
 * analysis's bases of the internal mechanisms and self-stresses, the same
 * matrices up to those bases' orthogonal freedom). Q receives one m x m
 * matrix (m = m_internal) per self-stress that the second order uses,
 * column-major, one after another (Q[j*m*m + r + c*m]): the s - s_trivial
 * self-stresses with no force in the bars between fixed joints
 * (kin_analysis.s_trivial; with none, the analysis' own W_s), since such a
 * bar's own self-stress gives 0 = 0; nq must be >= m*m*(s - s_trivial).
 * normalise != 0 applies eq. 18: the matrices, as vectors of length m^2,
 * are orthonormalised by modified Gram-Schmidt (twice), a matrix whose part
 * outside the previous ones' span is below 1e-10 times the largest Q_j
 * dropped as dependent; *s_out receives how many remain (< s - s_trivial
 * if some Q_j are dependent or zero). Without normalisation *s_out = s -
 * s_trivial. On failure *s_out = 0 (if s_out is not NULL) and Q is not
 * written.
 * Returns KIN_OK, KIN_ENULL, KIN_ESTATE (no current analysis), KIN_EINVAL
 * (weighting, or not a bifurcation: m_internal < 2 or s - s_trivial < 1),
 * KIN_ERANGE (nq < m*m*(s - s_trivial), counted in size_t: it may exceed
 * INT_MAX), KIN_ENOMEM. */
KIN_API int kin_second_order(const kin_assembly *a, int weighting, int normalise, double *Q, int nq,
                             int *s_out);

/* What a quadric solve found. */
typedef struct kin_solve_info {
    size_t size; /* sizeof(kin_solve_info) as the caller compiled it (docs/abi.md) */
    int starts;      /* starting points tried */
    int converged;   /* starts that converged to a root */
    int distinct;    /* distinct real solutions (beta and -beta counted once) */
    int gsl_errors;  /* starts GSL gave up on */
    double max_residual; /* max_j |beta^T Q_j beta| over the solutions */
} kin_solve_info;

/* The paper's root scan (3.3.1): solve beta^T Q_j beta = 0 (j < s),
 * |beta| = 1, with m = s + 1 unknowns, by GSL's hybridsj solver with the
 * analytic Jacobian from `starts` points spread over the unit sphere
 * (normalised Gaussian draws from a fixed generator seeded by `seed`: the
 * result is deterministic). Duplicates are dropped by eq. 20 (|beta_i .
 * beta_j| ~ 1). Solutions go to betas (m x maxsol, column-major), each with
 * its largest-magnitude entry positive; *nsol receives their number (at most
 * maxsol; info->distinct may be larger). Q is as from kin_second_order:
 * finite, and scaled like the normalised matrices (the root test is an
 * absolute residual of 1e-12). info may be NULL.
 * On every failure, including the first argument checks, *nsol = 0 and *info
 * is zeroed (those that are not NULL); betas is not written.
 * GSL's error handler (process-wide) is never changed. The call avoids every
 * GSL error that would invoke it but one: if malloc fails inside
 * gsl_multiroot_fdfsolver_alloc (about 3 m^2 + 16 m doubles), GSL raises
 * GSL_ENOMEM through the application's current handler (GSL's default
 * aborts; install another with gsl_set_error_handler if that matters) and the
 * call then returns KIN_ENOMEM if the handler returns.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (m != s+1, m < 2, starts < 1,
 * maxsol < 1, a NaN or infinite entry of Q), KIN_ERANGE (m > 256),
 * KIN_ENOMEM. */
KIN_API int kin_quadrics_scan(int m, int s, const double *Q, int starts, unsigned long seed,
                              double *betas, int maxsol, int *nsol, kin_solve_info *info);

/* Accounting of the complete solver: every one of the 2^s paths ends
 * in exactly one class, paths = real + nonreal + singular + failed.
 * Fields after `failed` report the checks (see kin_quadrics_homotopy). */
typedef struct kin_homotopy_info {
    size_t size; /* sizeof(kin_homotopy_info) as the caller compiled it (docs/abi.md) */
    int paths;         /* 2^s */
    int real;          /* certified real simple roots reached (counted with multiplicity) */
    int real_distinct; /* distinct real solutions */
    int nonreal;       /* certified non-real simple roots reached */
    int singular;      /* not certified: multiple roots, points of positive-dimensional
                          components, or roots too ill-conditioned to certify */
    int failed;        /* paths the tracker lost */
    int uncertified;   /* of `singular`: endpoints where Newton at t = 1 converged but the
                          certificate failed (a root too ill-conditioned to certify) */
    int retracked;     /* path re-trackings with tighter settings after a check failed */
    int duplicates;    /* paths on a certified root another path also reached (0 when the
                          result is consistent: a simple root is reached by one path) */
    int unpaired;      /* non-real roots whose complex conjugate no path reached (0 when
                          consistent) */
    int steps;         /* accepted predictor-corrector steps over all paths (final tracks) */
    int rejected;      /* rejected steps (final tracks) */
    double max_residual; /* max_j |beta^T Q_j beta| / |Q_j|_F over the distinct real solutions
                            (unit beta) */
    double max_cond;     /* largest condition number |J|_F |J^-1|_F of a certified root */
    /* layout 2 (docs/abi.md): a host compiled without these fields does not get them */
    long long steps_total;    /* `steps` summed in 64 bits (`steps` saturates at INT_MAX) */
    long long rejected_total; /* `rejected` summed in 64 bits (`rejected` saturates at INT_MAX) */
    int rechecks_failed;      /* kin_quadrics_homotopy_merge: imported certified records whose root
                                 did not certify again against Q, of the same kind and within the
                                 record's radius (their paths are tracked again); 0 elsewhere */
    /* layout 3: the interval certificates (proofs by exact integer arithmetic (FLINT) and
       outward-rounded arithmetic (Arb); with kin_homotopy_options.prove = 1 first a
       double-precision test with a priori rounding bounds; docs/branches.md "What certified
       means"). A path's endpoint is proven when a Krawczyk test shows that a
       box around it (in an affine chart, on the caller's Q) holds exactly one solution, a
       simple one, real (the box is its own conjugate) or non-real (the box misses the reals),
       and the box is shown disjoint from every other proven box */
    int proven_real;    /* distinct real solutions proven so */
    int proven_nonreal; /* distinct non-real solutions proven so */
    int unproven;       /* paths whose endpoint is not proven: 2^s - proven_real - proven_nonreal */
    int proven_all;     /* 1 when unproven = 0: 2^s distinct simple solutions proven, so by
                           Bezout's bound these are all the solutions (none singular, no curve) */
    int proven_refined; /* of the proven: boxes that needed 128 or 256-bit balls */
    int proven_overlap; /* boxes proven but not shown disjoint from another proven box (two paths
                           on one root): counted in unproven */
    int unproven_nopoint; /* of unproven: paths with no point to test (lost by the tracker, or
                             singular where Newton did not converge) */
    int unproven_refused; /* of unproven: endpoints every test refused (53-bit double, exact
                             integer and ball, then 128 and 256 bits after Newton steps): singular or too
                             ill-conditioned roots, or not near a root at all.
                             unproven = unproven_nopoint + unproven_refused + proven_overlap */
} kin_homotopy_info;

/* The complete solver: total-degree homotopy continuation for
 * beta^T Q_j beta = 0 (j < s) in projective space P^s (m = s + 1), from the
 * start system x_j^2 = x_0^2, in a random complex affine chart with a random
 * complex gamma (both drawn from `seed`: deterministic). Paths are tracked
 * by a Taylor-series predictor (order 8, exact coefficients from the
 * corrector's LU factors) and a Newton corrector, the step limited by the
 * series' truncation error and by a fraction of the separation radius
 * 1 / (|J^-1| |H''|) (a lower bound on the distance to any other path); the
 * chart is changed when a path nears its hyperplane at infinity; a path
 * heading for a singular endpoint is stopped at 1 - t = 1e-10. Each endpoint
 * is refined at t = 1 and certified as a simple root by the Kantorovich
 * theorem (in floating point with a rounding bound for the residual, not
 * interval arithmetic); certified roots are real (the conjugate root lies in
 * the root's uniqueness ball) or non-real (the existence ball misses the
 * reals); everything else is singular. Then every endpoint is proven (unless
 * kin_homotopy_options.prove = 0) by a Krawczyk test on Q in outward-rounded
 * arithmetic (info->proven_*, docs/branches.md "What certified means").
 * Checks: two paths on the same certified root (a path jumped), or a
 * non-real root whose conjugate no path reached (a path was lost), send the
 * paths concerned and failed ones to be tracked again with tolerances 10x
 * tighter, up to 3 rounds; what remains is reported in info->duplicates and
 * info->unpaired. When real + nonreal = 2^s with both 0, every solution is
 * found and simple (Bezout's bound is attained). Duplicates and conjugates
 * are found by sorting, O(2^s log 2^s).
 * nthreads >= 1 threads share the paths, at most one per online processor
 * and at most 2^s (a larger count is clamped); the result is the same for
 * any thread count. Distinct real solutions go to betas (m x maxsol, unit,
 * largest entry positive; in the order of the first path reaching them),
 * their path counts to multiplicity (optional, maxsol ints; 1 unless a
 * duplicate remained). Q must be finite (each Q_j is scaled to unit
 * Frobenius norm, computed without overflow). Memory: about (16 m + 85)
 * bytes per path (2^20 paths at m = 21: 450 MB), and 49 more while the
 * endpoints are proven (prove != 0); time about 1.3 ms per path
 * and core at s = 15. On every failure, including the first argument
 * checks, *nsol = 0 and *info is zeroed (those that are not NULL); betas
 * and multiplicity are not written.
 * This entry point has the defaults of kin_homotopy_options (no progress,
 * at most KIN_HOMOTOPY_MAX_PATHS paths); see kin_quadrics_homotopy_ex.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (m != s+1, m < 2, maxsol < 1,
 * nthreads < 1, a NaN or infinite entry of Q), KIN_ERANGE (m > 24),
 * KIN_ELIMIT (2^s > 2^20), KIN_ENOMEM. */
KIN_API int kin_quadrics_homotopy(int m, int s, const double *Q, unsigned long seed, int nthreads,
                                  double *betas, int maxsol, int *nsol, int *multiplicity,
                                  kin_homotopy_info *info);

/* Default limit on the number of paths (2^s) of the complete solver. */
#define KIN_HOMOTOPY_MAX_PATHS (1L << 20)

/* Settings of kin_quadrics_homotopy_ex. Start from
 * kin_homotopy_options_default() and change what you need. */
typedef struct kin_homotopy_options {
    size_t size; /* sizeof(kin_homotopy_options) as the caller compiled it (docs/abi.md) */
    unsigned long seed;  /* random chart and gamma (the result is deterministic for a seed).
                            Default 1 */
    int nthreads;        /* worker threads, >= 0; 0 = one per online processor; more than
                            the online processors are clamped to their number. Default 0 */
    long max_paths;      /* refuse (KIN_ELIMIT) problems with more than this many paths
                            2^s, >= 1. Default KIN_HOMOTOPY_MAX_PATHS = 2^20 (s <= 20);
                            s = 23 (8.4 million paths) takes hours and ~4 GB */
    kin_progress_fn progress; /* optional (NULL: none): done = paths tracked, total = 2^s plus
                                 the paths scheduled for re-tracking so far; called
                                 from the calling thread every 50 ms of tracking */
    void *user;          /* passed to progress */
    /* layout 2 (docs/abi.md) */
    int prove;           /* 2: prove every endpoint with an interval certificate
                            (kin_homotopy_info.proven_*): a Krawczyk test with exact integer
                            products (FLINT) and Arb's mags, then for what it cannot prove
                            Arb's balls (53, 128, 256 bits), so that no hand-derived rounding
                            bound decides a proof (~+12-14 % CPU on the hexagonal sail's flat
                            state); 1: a double-precision test with a priori rounding bounds
                            first, then those two for what it cannot prove (~+9-10 % CPU
                            there; the proofs then also rest on IEEE 754 rounding and those
                            bounds); 0: no proofs (those fields stay 0). The same counts either
                            way there. Default 2 (it was 1 while the exact test cost ~+20 %) */
} kin_homotopy_options;

/* Fill *o with the defaults above, for a struct of `size` bytes: pass
 * sizeof(kin_homotopy_options) (the macro kin_homotopy_options_default below does). size must be the sizeof
 * of one of kin_homotopy_options's published layouts (docs/abi.md); then exactly size bytes
 * are written (o->size = size) and KIN_OK is returned; otherwise nothing is
 * written and KIN_EINVAL is returned. KIN_ENULL if o is NULL. */
KIN_API int kin_homotopy_options_init(kin_homotopy_options *o, size_t size);

/* The same with size = sizeof(kin_homotopy_options): a C or C++ host compiled with this
 * header calls kin_homotopy_options_init through the macro. The function itself is
 * for programs built before the macro existed: it writes only the first
 * layout (o->size = its sizeof, docs/abi.md), which is all an old program
 * can have room for. Does nothing if o is NULL. */
KIN_API void kin_homotopy_options_default(kin_homotopy_options *o);
#define kin_homotopy_options_default(o) ((void)kin_homotopy_options_init((o), sizeof(kin_homotopy_options)))

/* kin_quadrics_homotopy with settings (opt NULL: the defaults). The calling
 * thread tracks paths too and calls opt->progress; a nonzero return stops
 * every thread at its next path boundary (within a few milliseconds per
 * thread at s <= 20) and the call returns KIN_ECANCELLED with *info zeroed,
 * *nsol = 0 and betas and multiplicity not written. A problem over
 * opt->max_paths is refused before anything is allocated or tracked.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (m != s+1, m < 2, maxsol < 1,
 * nthreads < 0, max_paths < 1), KIN_ERANGE (m > 24), KIN_ELIMIT,
 * KIN_ECANCELLED, KIN_ENOMEM. */
KIN_API int kin_quadrics_homotopy_ex(int m, int s, const double *Q, const kin_homotopy_options *opt,
                                     double *betas, int maxsol, int *nsol, int *multiplicity,
                                     kin_homotopy_info *info);

/* ---- The complete solver in shards ----
 * kin_quadrics_homotopy_ex is kin_quadrics_homotopy_range over every path
 * followed by kin_quadrics_homotopy_merge: the 2^s paths can be tracked in
 * any number of ranges (on other threads, processes or machines: the ranges
 * are independent and deterministic for a seed) and merged into exactly the
 * result of one call.
 *
 * ENDPOINT RECORDS (an ABI: records may be written to files by one build
 * and read by another). One record per path: a kin_homotopy_endpoint and 2m
 * doubles of coordinates in a separate array.
 *  - kin_homotopy_endpoint, in arrays with stride sizeof(kin_homotopy_endpoint)
 *    = KIN_HOMOTOPY_ENDPOINT_SIZE (72 bytes where size_t is 8 bytes and int
 *    4, e.g. every LP64 and LLP64 platform); element 0's `size` must equal it
 *    (set it before range; merge checks it). The fields below, in order,
 *    native byte order, no padding on those platforms.
 *  - coordinates: z[2*m*i + c] (real part) and z[2*m*i + m + c] (imaginary)
 *    for record i, c < m: the endpoint in projective coordinates,
 *    normalised so that coordinate `chart` is 1. */
#define KIN_HOMOTOPY_ENDPOINT_SIZE 72

/* endpoint classes */
enum kin_homotopy_end_kind {
    KIN_HOM_END_REAL = 0,     /* certified simple real root */
    KIN_HOM_END_NONREAL = 1,  /* certified simple non-real root */
    KIN_HOM_END_SINGULAR = 2, /* not certified (see kin_homotopy_info.singular) */
    KIN_HOM_END_FAILED = 3    /* the tracker lost the path */
};

typedef struct kin_homotopy_endpoint {
    size_t size;    /* KIN_HOMOTOPY_ENDPOINT_SIZE (element 0 of an array) */
    int path;       /* path index, 0 .. 2^s - 1 (its bits: the start solution's signs) */
    int kind;       /* enum kin_homotopy_end_kind */
    int chart;      /* coordinate normalised to 1 in z */
    int steps;      /* accepted predictor-corrector steps */
    int rejected;   /* rejected steps */
    int recharts;   /* changes of affine chart on the way */
    int converged;  /* Newton at t = 1 converged */
    int reserved;   /* 0 */
    double rminus;  /* certified: a root lies within rminus of z (chart coordinates) */
    double rplus;   /* ... and no other root within rplus */
    double cond;    /* |J|_F |J^-1|_F at the endpoint (inf if singular) */
    double sigma;   /* 1 - t where tracking stopped (0: reached t = 1) */
} kin_homotopy_endpoint;

/* Track paths first_path .. first_path + npaths - 1 of the complete solver
 * (kin_quadrics_homotopy_ex, same m, s, Q and options: opt->seed must be the
 * same for every range of one problem; NULL = the defaults) and write their
 * endpoints: ends (npaths records, ends[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE)
 * and z (2*m*npaths doubles), record i for path first_path + i. The work is
 * that of those paths alone; opt->nthreads threads share them; progress
 * (opt->progress): done = paths tracked, total = npaths. opt->max_paths
 * bounds npaths. On a failure after the arguments are checked (KIN_ELIMIT,
 * KIN_ECANCELLED, KIN_ENOMEM) the npaths records are zeroed (each size set);
 * z is written only on success.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (m != s+1, m < 2, a NaN or infinite
 * entry of Q, options, ends[0].size), KIN_ERANGE (m > 24; first_path < 0,
 * npaths < 1 or first_path + npaths > 2^s), KIN_ELIMIT (npaths >
 * opt->max_paths), KIN_ECANCELLED, KIN_ENOMEM. */
KIN_API int kin_quadrics_homotopy_range(int m, int s, const double *Q, const kin_homotopy_options *opt,
                                        long first_path, long npaths, kin_homotopy_endpoint *ends, double *z);

/* Merge the endpoints of every path (2^s records in path order, ends[p].path
 * == p, from any number of ranges concatenated; z likewise, 2*m*2^s
 * doubles): the duplicate and conjugate checks, the re-tracking of the paths
 * concerned (which needs Q and the options of the ranges: same seed) and the
 * accounting. Outputs exactly as kin_quadrics_homotopy_ex (betas,
 * multiplicity, *nsol, *info), which is range over all paths plus merge.
 * ends and z are not changed (re-tracks work on copies). Progress: done =
 * paths re-tracked, total = the paths scheduled for re-tracking so far (0
 * when none is: the calls are then (0, 0) before and after).
 * opt->max_paths bounds 2^s (memory: about (16 m + 85) bytes per path
 * besides the input, 49 more while proving).
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (as kin_quadrics_homotopy_ex; also
 * ends[0].size, a record whose path is not its index or whose kind, chart
 * or z is out of range), KIN_ERANGE, KIN_ELIMIT, KIN_ECANCELLED,
 * KIN_ENOMEM; on failure as kin_quadrics_homotopy_ex. */
KIN_API int kin_quadrics_homotopy_merge(int m, int s, const double *Q, const kin_homotopy_options *opt,
                                        const kin_homotopy_endpoint *ends, const double *z, double *betas,
                                        int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info);

/* ---- The complete solver with symmetry ----
 * What kin_quadrics_homotopy_sym reports besides kin_homotopy_info. */
typedef struct kin_homotopy_sym_info {
    size_t size;         /* sizeof(kin_homotopy_sym_info) as the caller compiled it (docs/abi.md) */
    int group;           /* projectively distinct group elements (R_g and -R_g count once; the
                            identity is always one) */
    int orbits;          /* orbits of the start system's roots: the paths tracked to Q (first pass) */
    int found;           /* roots of the start system known, orbits expanded; 2^s when complete */
    int monodromy_paths; /* paths tracked in the monodromy loops (0: the equivariant
                            total-degree start system was used, see below) */
    int final_paths;     /* paths tracked from the start system to Q, re-tracks included */
    double monodromy_steps; /* accepted steps of the monodromy paths */
    double monodromy_rejected; /* rejected steps of the monodromy paths */
} kin_homotopy_sym_info;

/* The complete solver for a system with symmetry: the same result as
 * kin_quadrics_homotopy_ex (every one of the 2^s roots of beta^T Q_j beta =
 * 0 in P^s, m = s + 1, certified and classified with the same certificate
 * and checks; betas, multiplicity, *nsol and *info as there, info->paths =
 * 2^s) with about |G| times fewer paths to Q.
 * R: ngroup orthogonal m x m matrices (column-major, one after the other)
 * acting on beta such that the system is equivariant, q(R_g b) = S_g q(b)
 * for some s x s S_g (found by least squares), and forming a group up to
 * sign (every product R_g R_h is +-R_k of the list or +-I); the identity may
 * be left out (it is always added), ngroup = 0 (R may be NULL) is the
 * trivial group. Tolerances: |R^T R - I| <= 1e-8 (largest entry) and
 * |R_g^T Q_j R_g - sum_i (S_g)_ji Q_i|_F <= 1e-7 with each Q_j scaled to
 * unit Frobenius norm; the Q_j must be linearly independent.
 * Method (docs/performance.md), one of two routes:
 *  - equivariant start system, when a cyclic subgroup <h> acts on beta
 *    like a permutation of coordinates that fixes one and on the equations
 *    like the same permutation of the others (decided from the characters
 *    tr R_h^j, tr S_h^j; the largest such subgroup is used): in coordinates
 *    beta = U x (U orthogonal) and orthogonal combinations of the
 *    equations where h is that permutation, the plain solver's homotopy is
 *    equivariant, so one total-degree path per orbit of start roots is
 *    tracked and its endpoint permuted gives the others' (each refined and
 *    certified on its own). The sails' flat states qualify (C3 or C4 permuting
 *    cycles of mechanisms and of self-stresses alike);
 *  - otherwise, for a group of fewer than 12 projectively distinct
 *    elements, every one of the 2^s paths as kin_quadrics_homotopy_ex (the
 *    monodromy below costs about 12 plain paths per orbit);
 *  - otherwise monodromy: a random complex start system P0 in the
 *    family E of equivariant systems (the Reynolds projection of a random
 *    system) with one root forced; monodromy through two more random members
 *    of E, tracking one root per orbit (the group commutes with every path in
 *    E) and adding whole orbits, until 2^s roots are known at P0; then one
 *    path per orbit from P0 to Q (parameter homotopy), the endpoints' orbits
 *    expanded and every one of the 2^s endpoints refined and certified.
 * Both then apply the duplicate and conjugate checks of
 * kin_quadrics_homotopy; representatives of suspect endpoints are tracked
 * again with tighter settings (3 rounds).
 * opt as for kin_quadrics_homotopy_ex (NULL: defaults): seed (the random
 * systems and charts), threads, max_paths (bounds 2^s), progress (done =
 * paths tracked, total = done + paths queued; cancel: KIN_ECANCELLED).
 * sinfo (optional, NULL: none) receives the counts above. Memory: about
 * (100 m + 160) bytes per root (2^s; 56 MB at s = 15), allocated per call.
 * Time: the equivariant route costs about 1/k of the plain solver's (k:
 * the subgroup's order; 2.6x faster on the hexagonal sail's flat state,
 * C3). The monodromy route costs ~4x the plain solver's CPU on that state
 * (about 4 monodromy paths per orbit besides the one to Q, and a step with
 * complex A + t D costs ~2.5x the plain tracker's): hence it is used for
 * groups of 12 or more projectively distinct elements only.
 * err (optional, errlen bytes) receives a message on failure.
 * If the monodromy does not reach 2^s roots within 40 * 2^s / |G| + 1000
 * paths, or the start system's roots cannot be placed (e.g. a family whose
 * generic member has fewer isolated roots), the call returns
 * KIN_ENOTCONVERGED with *info zeroed but for info->paths = 2^s and sinfo
 * filled (sinfo->found < 2^s); never an incomplete answer. The result does
 * not depend on the thread count.
 * Returns KIN_OK, KIN_ENULL (Q, betas, nsol, info; R with ngroup > 0),
 * KIN_EINVAL (as kin_quadrics_homotopy_ex; ngroup < 0; R not orthogonal,
 * not a group, or Q not equivariant; Q_j linearly dependent), KIN_ERANGE,
 * KIN_ELIMIT, KIN_ENOTCONVERGED, KIN_ECANCELLED, KIN_ENOMEM. On failure
 * *nsol = 0 and betas and multiplicity are not written. */
KIN_API int kin_quadrics_homotopy_sym(int m, int s, const double *Q, int ngroup, const double *R,
                                      const kin_homotopy_options *opt, double *betas, int maxsol, int *nsol,
                                      int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *sinfo,
                                      char *err, size_t errlen);

/* ---- The complete solver with symmetry, in shards ----
 * kin_quadrics_homotopy_sym's equivariant route as independent tasks:
 * kin_quadrics_equivariant_form once, kin_quadrics_homotopy_orbit_range
 * on ranges of orbits anywhere (other threads, processes, machines), then
 * kin_quadrics_homotopy_merge on the form (Qt, all 2^s records sorted by
 * path) and beta = U x for each real solution x: the same roots and
 * accounting as the one call. */

/* The equivariant form of a symmetric system (see kin_quadrics_homotopy_sym
 * for Q, ngroup, R and their checks): if a cyclic subgroup of order k >= 2
 * permutes the mechanisms and the equations alike, *order = k and
 *  Qt   (s*m*m doubles, s matrices m x m column-major as Q) receives the
 *       system in coordinates x with beta = U x, exactly equivariant under
 *       the permutation: Qt_{perm[j]} is Qt_j with rows and columns
 *       permuted (equations numbered like coordinates 1..s);
 *  U    (m*m, column-major) the orthogonal change of coordinates;
 *  perm (m ints) the permutation, (P x)_i = x_{perm[i]}, perm[0] = 0;
 *  *norbits the orbits of the 2^s start roots under it (the paths to
 *       track). seed: the random intertwiners (the one-call solver uses
 *       opt->seed: the same seed gives the same form).
 * If no subgroup qualifies, *order = 0, *norbits = 0 and Qt, U, perm are not
 * written (use kin_quadrics_homotopy_range on Q). err (optional) receives a
 * message on failure.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (sizes; R not orthogonal, not a
 * group, or Q not equivariant; Q_j linearly dependent; a NaN in Q),
 * KIN_ERANGE (m > 24), KIN_ENOMEM, KIN_ELAPACK_ARG, KIN_ELAPACK_CONV. */
KIN_API int kin_quadrics_equivariant_form(int m, int s, const double *Q, int ngroup, const double *R,
                                          unsigned long seed, double *Qt, double *U, int *perm, int *order,
                                          long *norbits, char *err, size_t errlen);

/* Track the orbit representatives first_orbit .. first_orbit + norbits - 1
 * (orbit i: the one whose smallest path is the i-th smallest
 * representative) of the start roots of the equivariant form (Qt, perm)
 * and write the endpoints of every member of those orbits, orbit after
 * orbit: ends (records, ends[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE; record
 * i's .path says which path) and z (2*m per record), *nends of them. The
 * members other than the representative are its endpoint permuted, each
 * refined and certified on its own. opt as for kin_quadrics_homotopy_range
 * (the same seed for every range and the merge); opt->max_paths bounds
 * norbits; progress: done = representatives tracked, total = norbits.
 * maxends: room in ends and z (records); an orbit has at most k members,
 * so norbits * order is always enough; if the members do not fit,
 * KIN_ERANGE with *nends = how many there are and nothing written.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (sizes, options, ends[0].size,
 * maxends < 1, perm not a permutation fixing 0, Qt not finite or not
 * equivariant under perm within 1e-12 of its largest entry), KIN_ERANGE
 * (m > 24, the orbit range outside 0 .. *norbits, members beyond maxends),
 * KIN_ELIMIT, KIN_ECANCELLED, KIN_ENOMEM (on the last two the records are
 * zeroed, each size set). Memory: about 17 bytes per path (2^s) for the
 * orbit table, plus (16 m + 85) bytes per record. */
KIN_API int kin_quadrics_homotopy_orbit_range(int m, int s, const double *Qt, const int *perm,
                                              const kin_homotopy_options *opt, long first_orbit, long norbits,
                                              long maxends, kin_homotopy_endpoint *ends, double *z, long *nends);

/* kin_quadrics_homotopy_merge on the equivariant form (Qt and U of
 * kin_quadrics_equivariant_form, records of kin_quadrics_homotopy_orbit_range)
 * with the interval certificates (opt->prove) about the caller's own system
 * Q, as kin_quadrics_homotopy_sym proves them: each root x of Qt is proven
 * as a root of Q at beta = U x (Q: s*m*m doubles as for
 * kin_quadrics_homotopy_ex; U: m*m, column-major, as that function wrote
 * it). The proven counts are then a theorem about Q, whatever Qt's rounding;
 * a Q or U that does not belong to Qt leaves its roots unproven (refused),
 * never proven wrong. Everything else (betas in Qt's coordinates x, the
 * accounting, progress, memory) as kin_quadrics_homotopy_merge(m, s, Qt, ...).
 * Returns as kin_quadrics_homotopy_merge; also KIN_ENULL (Q or U NULL) and
 * KIN_EINVAL (a NaN or infinity in Q or U). */
KIN_API int kin_quadrics_homotopy_merge_equivariant(int m, int s, const double *Q, const double *Qt, const double *U,
                                                    const kin_homotopy_options *opt,
                                                    const kin_homotopy_endpoint *ends, const double *z,
                                                    double *betas, int maxsol, int *nsol, int *multiplicity,
                                                    kin_homotopy_info *info);

/* One candidate path out of a bifurcation (paper 3.4). */
typedef struct kin_branch_path {
    size_t size; /* sizeof(kin_branch_path) as the caller compiled it (docs/abi.md) */
    int beta;        /* index of the second-order solution */
    int sign;        /* +1 or -1: direction of motion along U_m*beta */
    int exists;      /* the first step converged and the path was followed */
    int tangent_ok;  /* the first small step left along U_m*beta (|cos| >= tol) */
    int path_id;     /* distinct-path id (eq. 21-22), -1 if it does not exist */
    double length;   /* path length reached, counted from the bifurcation */
    double tangent_cos; /* cos between the first chord and U_m*beta */
} kin_branch_path;

/* Follow every candidate: for each solution beta (columns of betas, m x
 * nbeta) and each sign, on a clone of a: choose U_m*beta*sign, take a small
 * first step (1e-3 x the largest step) and check its chord is parallel to
 * U_m*beta (a wrong second-order solution can still let the corrector
 * converge), then follow the path to path length l_target from a (whatever
 * path length a itself has accumulated). Paths whose
 * displacements T = R - R0 coincide (cos >= 1 - 1e-6, eq. 22 with the sign
 * kept, since +beta and -beta are different motions) share a path_id.
 * paths receives 2*nbeta entries (beta 0 +, beta 0 -, beta 1 +, ...);
 * final_xyz (optional, njoints*dim x 2*nbeta) the end configurations.
 * The caller's assembly is not changed. *ndistinct receives the number of
 * distinct paths. l_target must be finite, > 0 and at most 1e6 largest steps
 * (step_fraction x RMS rest length, kin_path.h), which bounds the work.
 * Progress goes to a's callback (kin_set_progress) before every step: done
 * = directed paths followed (plus the fraction of l_target covered by the
 * one under way), total = 2*nbeta. On every failure (a cancel included)
 * *ndistinct = 0 (if not NULL) and, once nbeta is valid, the 2*nbeta
 * entries of paths are zeroed with path_id = -1; final_xyz is written only
 * on success. Returns KIN_OK, KIN_ENULL, KIN_ESTATE, KIN_EINVAL (not a
 * bifurcation, nbeta < 1, l_target not finite or <= 0, a NaN or infinite
 * entry of betas), KIN_ERANGE (nbeta > INT_MAX/2, l_target above 1e6
 * largest steps), KIN_ECANCELLED, KIN_ENOMEM. */
KIN_API int kin_branch_paths(const kin_assembly *a, const double *betas, int nbeta, double l_target,
                             kin_branch_path *paths, double *final_xyz, int *ndistinct);

#ifdef __cplusplus
}
#endif

#endif /* KIN_BRANCH_H */
