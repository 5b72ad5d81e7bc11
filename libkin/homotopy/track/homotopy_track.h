/* Private: homotopy/track/, one path of the complete solver's total-degree
 * homotopy and what every tracker of homotopy/ shares, the lowest of its
 * subfolders (it uses no other): the one-path tracker and the endpoint
 * certificate (homotopy_track.c, the reference), its kernels with the one
 * complex LU (homotopy_kernels.c, homotopy_lu.h), the step control
 * (homotopy_control.h), the rational predictor (homotopy_pade.c) and the
 * lockstep tracker, HOM_BATCH paths at once, each bit for bit as the
 * one-path tracker follows it (homotopy_batch.c, kernels homotopy_lanes.c).
 * The parameter trackers (param/) reuse its LU, predictor and lane
 * kernels; the solver (solver/) runs its trackers on the threads.
 *
 * This header: the path tracker and endpoint certificate behind
 * kin_quadrics_homotopy. Complex vectors are kept as separate real and
 * imaginary arrays (the matrices Q_j are real, so Q x costs two real
 * matrix-vector products and no complex arithmetic library calls). */
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

/* ---- the endpoint certificate (homotopy_track.c), also of the lockstep
 * tracker, the merge (solver/) and the symmetric solver ---- */
/* Refine the approximate root (xr, xi) of F (any scale, not near the
 * chart's infinity) at t = 1 by Newton in the chart z_k = 1 (k: its
 * largest entry) and certify it (the certificate of kin__hom_track);
 * zr, zi (m each) receive the refined root. */
void kin__hom_certify(const hom_problem *P, hom_ws *w, const double *xr, const double *xi, double *zr, double *zi,
                      hom_end *e);

#endif /* KIN_HOMOTOPY_TRACK_H */
