/* Private: the assembly structure and helpers shared by the library's files.
 * Not installed. */
#ifndef KIN_INTERNAL_H
#define KIN_INTERNAL_H

#include <stdarg.h>
#include <stddef.h>

#include "libkin.h"
#include "model/abi_layouts.h"

#define KIN_ERRLEN 512

/* One factorization of H and everything derived from it. The handle keeps
 * two, `cur` and `trial`, and swaps them when a trial configuration is
 * accepted, so a rejected step leaves the current analysis untouched. */
typedef struct kin_factor {
    int valid;      /* analysis matches the configuration it was made for */
    kin_analysis an;
    double *sv;     /* min(nf, nb) singular values, descending */
    double *U;      /* nf x nf left singular vectors (ld nf) */
    double *VT;     /* nb x nb right singular vectors, transposed (ld nb) */
    double *Uint;   /* nf x m_internal internal mechanisms (ld nf) */
    double *Urig;   /* nf x m_rigid rigid-body mechanisms (ld nf) */
} kin_factor;

/* The first-order analysis of the sparse mode (model/analysis_sparse.c):
 * what kin_analyse finds in KIN_STEP_SPARSE mode without the dense SVD
 * (the counts, v_max, v_r and orthonormal bases of the null spaces), kept
 * beside fac[] and current while the configuration and the rank tolerance
 * are those it was made with (kin__sparse_an_current). */
typedef struct kin_sparse_an {
    int valid;
    kin_analysis an;
    double tol;     /* the rank tolerance it counted with */
    double *xyz;    /* nj*dim: the configuration it was made at */
    double *Um;     /* nf x m: every mechanism (ld nf) */
    double *Urig;   /* nf x m_rigid */
    double *Uint;   /* nf x m_internal */
    double *Ws;     /* nb x s: the self-stresses (ld nb) */
    size_t cap_m, cap_s; /* columns allocated in Um/Uint (and Urig) and Ws */
} kin_sparse_an;

/* LU mode (kin_options.factorization == KIN_STEP_LU): one factorization of
 * the bordered matrix J = [C; b^T; R^T] of a configuration, where b is the
 * tangent of the step that reached it and R its rigid mechanisms. Stored as
 * the factors of J^T = [H, b, R] (nf x rows, ld nf): LU (dgetrf) when
 * rows == nf, LQ (dgelqf, i.e. a QR of J) when rows > nf (redundant bars).
 * Valid only for the configuration in xyz. The handle keeps two, swapped
 * when a step is accepted, like fac[]. */
/* The LU mode keeps (J^T)^-1 with a point's factors (kin_lufactor.Jinv)
 * only up to this many free coordinates, and only where a->lu_inverse asks
 * (the follower, whose cheap stretches solve about 15 times per point). It
 * is made by Gauss-Jordan elimination (path/gauss_jordan.c), n^3
 * multiply-adds less the zeros of J^T's bar columns: on the hexagonal
 * sail's 46 x 46 J^T 6.7 us, less than dgetrf alone (10.2 us) and a quarter
 * of dgetrf + dgetri; on a dense 46 x 46 matrix 14.7 us (bench_lu_point).
 * The cost grows as n^3 while a solve by dgetrs grows as n^2. */
enum { KIN__LU_INVERSE_MAX_NF = 64 };

typedef struct kin_lufactor {
    int valid;        /* factors of a regular point (estimated m_internal = 1) */
    int rows;         /* nb + 1 + m_rigid */
    int sparse;       /* factors live in the KLU slot of the same index (sparse.c), not in JT */
    double *JT;       /* nf x (nb + 1 + nrig) factors (unused where inv); NULL, like ipiv and tq, where no route applies */
    int *ipiv;        /* nf pivots (LU; NULL unless nf - nb - 1 is in 0..nrig) */
    double *tq;       /* nf Householder scalars (LQ; NULL unless nb + 1 + nrig > nf) */
    double *Jinv;     /* nf x nf: (J^T)^-1 (NULL where LU does not apply), current where inv */
    int inv;          /* Jinv holds the inverse; JT and ipiv then hold no factors (path/gauss_jordan.c) */
    int det_sign;     /* sign of det(J^T) where rows == nf and the factors are valid; else 0 */
    double *xyz;      /* nj*dim configuration the factors belong to */
    double *vr_vec;   /* nf: inverse-iteration vector of v_r (unit) */
    double *vmax_vec; /* nf: power-iteration vector of v_max (unit) */
    double v_r, v_max;/* estimates at xyz */
} kin_lufactor;

struct kin_assembly {
    int dim, nj, nb, nf;
    double *xyz;             /* nj*dim current coordinates */
    unsigned char *fixed;    /* nj*dim, 1 = fixed */
    int *bars;               /* 2*nb */
    double *L0;              /* nb rest lengths */
    int *free_index;         /* nj*dim -> row of H or -1 */
    int *free_coord;         /* nf -> j*dim + k */
    double rms_length;       /* RMS of rest lengths: the step scale */
    double min_length;       /* shortest rest length: the strain that coordinate rounding allows
                                (kin__resolution_strain) divides by it; rest lengths never change */
    kin_options opt;
    char err[KIN_ERRLEN];

    /* factorizations */
    kin_factor fac[2];
    int cur;                 /* index of the current factor in fac[] */
    double *H;               /* nf x nb equilibrium matrix scratch */
    double *A;               /* nf x nb copy destroyed by LAPACK */
    double *work;            /* LAPACK workspace, lwork doubles */
    int lwork;
    int *iwork;              /* lwork_i ints */
    /* the dense workspace's sizes once queried (query_lwork: 6 LAPACK
     * queries, a function of the dimensions alone); a clone takes its
     * source's instead of asking again (4 clones in a follow) */
    int lwork_dense, lwork_dense_i;
    int lwork_i;
    long nfact;              /* factorizations made by this handle, ever */
    int nrig;                /* 3 (2D) or 6 (3D) rigid motions */
    int nfix;                /* number of fixed coordinates */
    int nfixed_bars;         /* bars with no free coordinate at either end (kin__bar_fixed): a zero
                                column of H at every configuration, a self-stress of its own
                                (kin_analysis.s_trivial) */
    double *G;               /* (nj*dim) x nrig rigid motions (ld nj*dim) */
    double *Gs;              /* small scratch: nrig*nrig + nrig + nrig*nf */
    /* mechanism_split.c: the supports admit no rigid motion, measured at
     * centre sup_c, radius sup_rho with smallest / largest singular value
     * sup_ratio, the fixed coordinates then in sup_fix (nfix) */
    double *sup_fix;
    double sup_c[3], sup_rho, sup_ratio;
    int sup_full;
    double *mwork;           /* scratch for the mechanism split: 2*nf*nf */

    /* bordered Newton system [C; t^T] ((nb+1) x nf, ld = max(nb+1, nf)) */
    double *B;
    double *rhs;             /* max(nb+1, nf) */
    double *svB;             /* min(nb+1, nf) */

    /* path state */
    double *t;               /* oriented tangent, nf */
    int have_t;              /* t is valid for the current point */
    int t_chosen;            /* t was set by kin_path_set_direction at a bifurcation */
    double l;                /* signed path length */
    double step_hint;        /* amplitude the next automatic step starts from (0: the largest) */
    double start_strain;     /* max |L-L0|/L0 where the path started (STRAIN FLOOR, kin_path.h) */
    int have_start_strain;   /* start_strain measured; 0 after creation, kin_set_coords, kin_relax,
                                kin_path_reset: the next step measures it */
    int chord_hopeless;      /* LU modes: automatic steps left before the chord-only control is tried
                                again (shorter steps did not let the chord converge) */

    /* step scratch, each nf or nb */
    double *x0, *x, *xp, *d, *y, *e, *len, *chord;
    double *xyz_trial;       /* nj*dim full coordinates of a trial point */

    /* locator: continuously oriented rigid mechanisms for the test function */
    double *Rref;            /* nf x 6 */
    int have_Rref;           /* columns of Rref + 1 (0: none yet) */

    /* test hook: makes LAPACK report failures (enum kin__fault) */
    int fault;

    /* LU mode: factors of the current point (lu[lu_cur]) and a trial one */
    kin_lufactor lu[2];
    int lu_cur;
    double *luR;             /* nf x 6 rigid mechanisms of a trial point */
    double *luw;             /* max(nf, nb + 1 + nrig) solve vector */
    double *luw2;            /* nf: the product with (J^T)^-1 */
    int lu_inverse;          /* LU mode: keep (J^T)^-1 with the factors (the follower's cheap stretches) */
    int plain_extensions;    /* kin__extensions in plain double, not double-double (the follower's cheap stretches) */
    int lu_svd_start;        /* SVD mode: a point with current square LU-mode factors and no SVD starts a
                              * step with them (its chord corrector); the new point is analysed by SVD
                              * (the locator started where the follower's LU steps handed over) */
    int lu_predicted;        /* LU mode: forward calculations with a predictor (kin__step_predicted) get
                              * bordered factors too, the SVD only where they are not regular (the
                              * follower's Hermite nodes); else those are always analysed by SVD */

    /* KIN_STEP_SPARSE: KLU pattern, symbolic analysis and one numeric
     * factorization per lu[] slot (path/sparse.c); NULL until the mode is
     * set. The workspace belongs to the path layer: the handle keeps only
     * the two calls that free it and make it again for a clone, set by
     * path/sparse.c with it, so that model/ never calls up into path/. */
    struct kin_sparse *sp;
    void (*sp_free)(kin_assembly *a);
    int (*sp_prepare)(kin_assembly *a);

    /* the sparse mode's analysis (model/analysis_sparse.c); NULL until the
     * first one, not copied by kin_assembly_clone */
    kin_sparse_an *san;
    /* Panels, thicknesses and the clearance workspace (contact/); NULL until
     * kin_set_panels, kin_set_thickness or kin_clearance makes it. Owned by
     * the contact layer, freed and copied (for a clone) through the two
     * calls it sets, so that model/ never calls up. */
    struct kin_contact *ct;
    void (*ct_free)(kin_assembly *a);
    int (*ct_clone)(kin_assembly *dst, const kin_assembly *src);

    /* progress callback of the long loops (kin_set_progress); not copied
     * by kin_assembly_clone nor kin__copy_state */
    kin_progress_fn progress;
    void *progress_user;
};

/* Fault injection for the tests (not exported): the SVD of the next analyses
 * reports info < 0, info > 0 in both dgesdd and dgesvd, or info > 0 in dgesdd
 * only (exercising the dgesvd fallback). */
enum kin__fault { KIN__FAULT_NONE = 0, KIN__FAULT_SVD_ARG, KIN__FAULT_SVD_CONV, KIN__FAULT_SDD_CONV,
                  /* sparse.c: the KLU analysis or a factorization cannot
                   * allocate; every numeric factorization reports a singular
                   * J; every refactorization is rejected (pivot again);
                   * no nested-dissection order (as when METIS fails) */
                  KIN__FAULT_SPARSE_NOMEM, KIN__FAULT_SPARSE_FACTOR_NOMEM, KIN__FAULT_SPARSE_SINGULAR,
                  KIN__FAULT_SPARSE_REPIVOT, KIN__FAULT_SPARSE_NO_ND,
                  /* symmetry.c: the action of each symmetry on the internal
                   * mechanisms is disturbed (R_g not orthogonal) */
                  KIN__FAULT_SYM_NOT_ORTHOGONAL,
                  /* sparse.c: every capacitance of the bordering is judged
                   * ill-conditioned (each point factorized with the dense rows) */
                  KIN__FAULT_SPARSE_CAPACITANCE,
                  /* locate.c: a location on the bracket the follower's LU
                   * steps hand over (kin__locate_ws.direct_prev) fails, as
                   * if the Hermite method had not converged there */
                  KIN__FAULT_LOCATE_DIRECT,
                  /* assembly.c: the dense workspace is judged too big for
                   * memory (kin__dense_affordable 0, kin__dense_ready
                   * KIN_ENOMEM unless it exists): the sparse mode's analysis
                   * never hands over to the dense route, and its steps
                   * confirm points with it */
                  KIN__FAULT_DENSE_UNAFFORDABLE };
void kin__set_fault(kin_assembly *a, int fault);

/* Fault injection for the tests (io/model_io.c, not exported): the nth
 * write (of KIN__IO_CHUNK bytes), fsync or rename of the next file saves
 * fails once with errno err (ENOSPC: a full disk); op NONE clears it. */
enum kin__io_fault { KIN__IO_FAULT_NONE = 0, KIN__IO_FAULT_WRITE, KIN__IO_FAULT_FSYNC, KIN__IO_FAULT_RENAME };
#define KIN__IO_CHUNK 4096
void kin__set_io_fault(int op, int nth, int err);

/* error helpers: set the handle's message and return the code */
int kin__fail(kin_assembly *a, int code, const char *fmt, ...);
int kin__failv(char *buf, size_t len, int code, const char *fmt, va_list ap);
/* kin__failv with arguments: a message into a caller's buffer (NULL: none) */
int kin__failbuf(char *buf, size_t len, int code, const char *fmt, ...);

/* free coordinates <-> full coordinates */
void kin__gather(const kin_assembly *a, const double *xyz, double *x);
void kin__scatter(const kin_assembly *a, const double *x, double *xyz);

/* bar lengths of configuration xyz; returns max |L-L0|/L0 */
double kin__lengths(const kin_assembly *a, const double *xyz, double *len);
/* sqrt(dim) * opt.coord_resolution / min L0: the strain (and relative
 * singular value) that rounded input coordinates leave; 0 for exact input */
double kin__resolution_strain(const kin_assembly *a);
/* The one relative tolerance of the rank test and of the rigid-mode test
 * (model/analysis.c): rank_tol, or what the input's rounding allows if that
 * is more (coord_resolution: a singular value below what the rounding moves
 * H by is zero to the input's accuracy, a self-stress the rounding broke
 * stays one) */
double kin__rank_tolerance(const kin_assembly *a);
/* e = L - L0, computed as (L^2 - L0^2)/(L + L0) for accuracy; returns max relative */
double kin__extensions(const kin_assembly *a, const double *xyz, double *e);
/* equilibrium matrix of configuration xyz into H (ld ldh) */
/* Rigorous bounds (Arb's balls, model/sv_enclosure.c) at the current
 * configuration, from the current dense analysis (fac[cur] with its SVD):
 * *lo <= sigma_i(H) <= *hi for singular value i (descending order) and
 * *max_lo <= sigma_0(H), H the exact equilibrium matrix at the current
 * double coordinates. 1 if computed; 0 (nothing written) without a valid
 * dense SVD or for matrices too large to bound in about a second. */
int kin__sv_enclose(const kin_assembly *a, int i, double *lo, double *hi, double *max_lo);
void kin__build_H(const kin_assembly *a, const double *xyz, double *H, int ldh);
/* KIN_OK when every bar of xyz has a finite length > 0 (H finite), else
 * KIN_EGEOM naming the bar: checked before H goes to LAPACK, which would
 * print its own message for a NaN (xerbla) instead of returning a status */
int kin__check_bars(kin_assembly *a, const double *xyz);

/* Check the caller's options (read as far as its size goes, defaults for
 * the rest) into *o; KIN_OK or KIN_EINVAL with the handle's message
 * (model/options.c; kin_set_options applies them, path/path.c) */
int kin__options_read(kin_assembly *a, const kin_options *user, kin_options *o);

/* factorize the configuration xyz into fac[idx] (SVD, rank, mechanisms) */
int kin__analyse_into(kin_assembly *a, const double *xyz, int idx);
/* the singular values of H at xyz only (no vectors: about 40% of the SVD's
 * cost at the sails' sizes), descending, into sv (min(nf, nb) entries); no
 * analysis is changed and nfact is not counted (the caller counts the
 * point once) */
int kin__singular_values(kin_assembly *a, const double *xyz, double *sv);
/* kin_analyse's route in KIN_STEP_SPARSE mode (model/analysis_sparse.c):
 * the analysis of configuration xyz from sparse factorizations into
 * a->san, with the progress reports of kin_analyse when report is 1.
 * Never allocates anything of size nf x nb. budget: the floating-point
 * operations after which it stops (the dense analysis's predicted cost
 * where the dense route is affordable, INFINITY where it is not); *over
 * := 1 where it stopped on that budget or on its block limit (MAX_BLOCK
 * mechanisms or self-stresses: KIN_ELIMIT), i.e. where the dense route
 * could still answer, 0 otherwise. */
int kin__analyse_sparse(kin_assembly *a, const double *xyz, int report, double budget, int *over);
/* Predicted floating-point operations of the dense analysis (dgesdd of the
 * nf x nb matrix H with all singular vectors), the sparse analysis's
 * budget where the dense route is affordable. */
double kin__dense_analysis_flops(const kin_assembly *a);
/* a->san when it holds the analysis of the current configuration with the
 * current rank tolerance, else NULL */
const kin_sparse_an *kin__sparse_an_current(const kin_assembly *a);
/* Split the mechanisms Um (nf x m orthonormal, ld nf) of configuration xyz
 * into rigid-body ones Urig (nf x *mr, ld nf, room for 6) and internal ones
 * Uint (nf x (m - *mr), ld nf, room for m columns), both orthonormal and
 * oriented (model/mechanism_split.c). work: at least kin__split_work(nf, m)
 * doubles. */
int kin__split_basis(kin_assembly *a, const double *xyz, const double *Um, int m, double *Urig, double *Uint,
                     int *mr, double *work);
/* Bar k has no free coordinate at either end: its length never changes,
 * its column of H is zero at every configuration and it adds nothing to
 * the second-order equations (docs/generality.md, "Bars between fixed
 * joints"). */
static inline int kin__bar_fixed(const kin_assembly *a, int k)
{
    int ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
    for (int c = 0; c < a->dim; ++c)
        if (a->free_index[ja * a->dim + c] >= 0 || a->free_index[jb * a->dim + c] >= 0) return 0;
    return 1;
}

static inline size_t kin__split_work(int nf, int m) { return (size_t)m * 8 + (size_t)nf + 16; }
/* kin_analyse without progress reports, for the library's own loops (whose
 * callbacks count steps, not phases of one analysis) */
int kin__analyse(kin_assembly *a, kin_analysis *out);


/* dv_k = u_k^T (dH/dx . dx) w_k for singular triple k of factor f made at
 * xyz, along the free-coordinate motion dx; scratch: 2*nj*dim doubles */
double kin__sv_derivative(const kin_assembly *a, const kin_factor *f, const double *xyz, const double *dx,
                          int k, double *scratch);
/* the same for a singular triple given by its vectors: u (nf), w (nb), H w = v u */
double kin__sv_derivative_uw(const kin_assembly *a, const double *xyz, const double *dx, const double *u,
                             const double *w, double *scratch);

/* Recount rank, m, s and the rigid/internal split of fac[idx] (made at xyz)
 * with the handle's current rank_tol, without a new factorization */
int kin__reclassify(kin_assembly *a, const double *xyz, int idx);

/* Orthonormal basis (nf x *mr, ld nf) of the rigid-body mechanisms of
 * configuration xyz: the infinitesimal rigid motions of the whole assembly
 * that keep every fixed coordinate fixed, without a factorization of H (the
 * vectors split_mechanisms projects on U_m). Uses a->G and a->Gs. */
int kin__rigid_basis(kin_assembly *a, const double *xyz, double *R, int *mr);

/* LU mode: invalidate both bordered factorizations (the configuration or
 * the rank tolerance changed) */
static inline void kin__lu_invalidate(kin_assembly *a) { a->lu[0].valid = a->lu[1].valid = 0; }


static inline const kin_factor *kin__cur(const kin_assembly *a) { return &a->fac[a->cur]; }

/* Report progress through the handle's callback, if any: returns 1 when the
 * callback asks to cancel (then the caller stops and returns KIN_ECANCELLED),
 * 0 otherwise. done is clamped to [0, total]. */
int kin__progress(const kin_assembly *a, double done, double total);



/* The dense analysis workspace (H, the SVD factors of both slots, the
 * bordered system, the LU mode's dense factors, LAPACK's workspace): made
 * at the first call that needs it (an SVD analysis, a dense bordered solve
 * or LU factorization), once; the sparse mode steps without it. Its bytes
 * are counted first (overflow-checked): more than the machine's physical
 * memory gives KIN_ENOMEM (with the handle's message) before anything is
 * allocated. KIN_OK at once if it exists. */
int kin__dense_ready(kin_assembly *a);
/* 1 if the dense workspace exists, or could be made: its matrices within
 * LAPACK's int sizes and its bytes within half the physical memory (the
 * sparse mode then may take the dense route); 0 otherwise. */
int kin__dense_affordable(const kin_assembly *a);

/* A configuration set from outside a path (kin_set_coords, kin_relax):
 * xyz (nj*dim) copied in, every analysis and factorization invalidated, the
 * path forgotten (direction, length, step control, start strain) */
void kin__set_configuration(kin_assembly *a, const double *xyz);

/* BLAS threads (blas_threads.c): before the long loops on a handle whose
 * matrices are small (nfree <= KIN__BLAS_SMALL), the linked OpenBLAS (found
 * at run time; any other BLAS: nothing happens) is set to one thread; the
 * token returned goes to kin__blas_threads_restore, which puts the caller's
 * setting back when the last such call in the process ends. */
#define KIN__BLAS_SMALL 600
int kin__blas_threads_small(const kin_assembly *a);
void kin__blas_threads_restore(int token);

/* copy the configuration, analysis and path state of src into dst (same
 * model; no allocation, except dst's dense workspace the first time src
 * has one); dst keeps its own options */
void kin__copy_state(kin_assembly *dst, const kin_assembly *src);

/* Orthogonalise v (n entries) against columns 0..k-1 of X (ld) by two
 * passes of modified Gram-Schmidt and normalise it; returns its norm after
 * orthogonalisation relative to before (0 for a zero vector). */
double kin__gs_column(int n, const double *X, int ld, int k, double *v);

/* splitmix64: a small deterministic random generator whose whole state is
 * the caller's *s (no global state; seeded runs are reproducible) */
static inline unsigned long long kin__splitmix(unsigned long long *s)
{
    unsigned long long z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* *out = a * b; returns 0 (and leaves *out alone) if the product overflows
 * size_t. Every size made by multiplying caller-supplied counts goes through
 * this (or is bounded by a check made with it). */
static inline int kin__mul_size(size_t a, size_t b, size_t *out)
{
    if (b != 0 && a > (size_t)-1 / b) return 0;
    *out = a * b;
    return 1;
}

/* a * b * c, like kin__mul_size */
static inline int kin__mul_size3(size_t a, size_t b, size_t c, size_t *out)
{
    size_t ab;
    return kin__mul_size(a, b, &ab) && kin__mul_size(ab, c, out);
}

/* small dense helpers */
double kin__dot(int n, const double *x, const double *y);
double kin__norm(int n, const double *x);


/* ---- size-prefixed public structs (abi.c, docs/abi.md) ----
 * Every published layout of each struct is in the table of
 * model/abi_layouts.h (generated from the headers by tools/gen_abi.py):
 * its sizeof (the `size` a host compiled against it passes) and where its
 * fields end. A `size` that is not one of them is refused (KIN_EINVAL);
 * the library reads and writes only the fields of the layout it names.
 * KIN__ABI(T) is the table entry of struct T. */
typedef struct kin__abi_type {
    const char *name;
    int nlayouts;
    size_t size[KIN__ABI_MAX_LAYOUTS]; /* sizeof of each layout, increasing */
    size_t end[KIN__ABI_MAX_LAYOUTS];  /* where its fields end (<= its sizeof) */
} kin__abi_type;
extern const kin__abi_type kin__abi_types[KIN__ABI_NTYPES];
#define KIN__ABI(T) (&kin__abi_types[KIN__ABI_ID_##T])
size_t kin__abi_size(const void *p);
/* where the fields of t's layout of sizeof `size` end, 0 if no layout has that size */
size_t kin__abi_end(const kin__abi_type *t, size_t size);
/* KIN_OK if p->size is one of t's layout sizes, else KIN_EINVAL */
int kin__abi_check(const void *p, const kin__abi_type *t);
/* copy the caller's fields over `local` (a whole current struct already
 * holding defaults); local->size = sizeof the current struct */
void kin__abi_read(void *local, const void *user, const kin__abi_type *t);
/* copy `local` (a current struct) into the caller's (checked) struct, only
 * the fields its layout has; its size is kept */
void kin__abi_write(void *user, const void *local, const kin__abi_type *t);
/* zero every byte of a caller's (already checked) struct after its size */
void kin__abi_zero(void *user);
/* defaults into the caller's struct p of sizeof `size`: KIN_EINVAL (nothing
 * written) unless `size` is one of t's layout sizes; else `size` bytes are
 * written, the layout's fields from *defaults, the rest zero */
int kin__abi_init(void *p, size_t size, const void *defaults, const kin__abi_type *t);
/* The first checks of an entry point with an info struct and options: info
 * (NULL: none) checked against its type it and zeroed after its size; then
 * a (NULL: KIN_ENULL); then opt (NULL: keep the defaults the caller put in
 * *local) checked against ot and read over *local. KIN_OK, or KIN_EINVAL
 * with a message naming the struct. */
int kin__abi_entry(kin_assembly *a, void *info, const kin__abi_type *it, const void *opt, void *local,
                   const kin__abi_type *ot);

#endif /* KIN_INTERNAL_H */
