/* libkin: the assembly handle, its model, and the first-order analysis
 * (paper section 3.1).
 *
 * CONVENTIONS (stated once, used by every libkin call)
 *  - Joint coordinates are joint-major: xyz[j*dim + k] is coordinate k
 *    (0 = x, 1 = y, 2 = z) of joint j. Indices are 0-based.
 *  - Free coordinates are the unknowns: taken joint by joint, and within a
 *    joint in the order x, y, z, skipping fixed ones. Free coordinate i is
 *    row i of the equilibrium matrix H and entry i of every mechanism vector.
 *    kin_free_index() maps (joint, axis) to that row.
 *  - Matrices are column-major and are passed as (ptr, ld, rows, cols): entry
 *    (i, k) is ptr[i + k*ld], ld >= rows. H has nfree rows and nbars columns;
 *    column k belongs to bar k. A mechanism matrix has nfree rows, a
 *    self-stress matrix nbars rows; one column per vector.
 *  - Lengths are in the user's units; singular values scale like H (unitless
 *    direction cosines), so relative tolerances are relative to v_max.
 *
 *  - Options and info structs start with `size_t size`: the size of the
 *    struct the caller compiled against (docs/abi.md). Set it before a call,
 *    with the struct's *_default() macro or *_init(p, sizeof *p) function
 *    (options) or an initializer `kin_step_info info = {.size = sizeof info};`
 *    (outputs; for an array of kin_branch_path, element 0's size). The size
 *    names one of the struct's published layouts and the library reads and
 *    writes only that layout's fields, so a host built against older
 *    headers keeps working when a struct grows at its end; a size that is no
 *    layout's (0, garbage, newer headers) gives KIN_EINVAL before anything
 *    is read or written.
 *    On failure an output struct is zeroed (its size kept).
 *
 * OWNERSHIP: libkin copies every array passed in; it never keeps, frees or
 * changes caller memory except the output arrays a call is documented to fill.
 * THREADS: a handle is used by one thread at a time; separate handles are
 * independent (the library has no mutable global state). */
#ifndef KIN_ASSEMBLY_H
#define KIN_ASSEMBLY_H

#include <stddef.h>
#include "kin_export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct kin_assembly kin_assembly;

/* Create an assembly in its initial configuration.
 *  dim          2 or 3.
 *  njoints      number of joints, >= 2, with njoints*dim <= INT_MAX.
 *  xyz          njoints*dim coordinates (joint-major); finite, |x| <= 1e150.
 *  fixed        njoints*dim flags, nonzero = that coordinate is fixed (a
 *               support); NULL = every coordinate free.
 *  nbars        number of bars, >= 1, with 2*nbars <= INT_MAX.
 *  bars         2*nbars joint indices: bar k joins bars[2k] and bars[2k+1].
 *               Every bar's initial length must be >= 1e-150.
 *  rest_lengths nbars lengths to keep (finite, 1e-150..1e151); NULL = the
 *               initial lengths.
 *  out          receives the new handle; set to NULL on every failure
 *               (unless out itself is NULL).
 *  errbuf       optional (may be NULL): on failure receives a message with
 *               detail (naming the joint or bar at fault), NUL-terminated,
 *               truncated to errlen bytes.
 * The length bounds keep every square of a length a normal double (the
 * extensions and eq. 12 square lengths): the library works in any unit in
 * which the structure's lengths lie within them.
 * Any such framework is accepted, whatever the counts: fewer or more bars
 * than free coordinates, several internal degrees of freedom, joints on one
 * line or (3D) in one plane (see docs/generality.md).
 * The counts are checked before any array is read. Allocates the workspace
 * every mode needs (O(njoints + nbars)); the dense workspace of the SVD
 * analysis and the dense LU (O(nfree^2 + nbars^2), with LAPACK's work
 * arrays, queried then) is made once, by the first call that needs it
 * (kin_analyse, a step in the SVD or LU mode, a dense fallback of the
 * sparse mode), which returns KIN_ENOMEM before allocating anything if it
 * would exceed the machine's physical memory, or if a dense matrix of
 * the analysis (nfree^2, nbars^2, nfree*(nbars+7) entries) would not fit
 * LAPACK's int sizes (such a model is still made: the sparse mode,
 * KIN_STEP_SPARSE, analyses and steps it without them). Nothing is
 * half-built: on failure everything allocated is released.
 * Returns KIN_OK, or KIN_ENULL, KIN_EDIM, KIN_EINVAL (njoints < 2 or
 * nbars < 1), KIN_ERANGE (njoints*dim or 2*nbars exceed INT_MAX), KIN_EJOINT,
 * KIN_ESELFBAR, KIN_EDUPBAR, KIN_EGEOM (a non-finite or too large coordinate,
 * a bar shorter than 1e-150, a rest length out of range), KIN_ENOFREE,
 * KIN_ENOMEM (allocation failed, or the supports' LAPACK workspace would
 * exceed INT_MAX entries), KIN_ELAPACK_ARG. */
KIN_API int kin_assembly_create(int dim, int njoints, const double *xyz,
                                const unsigned char *fixed, int nbars, const int *bars,
                                const double *rest_lengths, kin_assembly **out,
                                char *errbuf, size_t errlen);

/* Deep copy of an assembly: model, current configuration, options and path
 * state. *out is NULL on failure. Returns KIN_OK, KIN_ENULL or KIN_ENOMEM. */
KIN_API int kin_assembly_clone(const kin_assembly *a, kin_assembly **out);

/* Release a handle. kin_assembly_free(NULL) does nothing. */
KIN_API void kin_assembly_free(kin_assembly *a);

/* Message with detail about the last failed call on this handle ("" if
 * none). Valid until the next call on the handle. Never NULL (a NULL handle
 * gives a static message). */
KIN_API const char *kin_last_error(const kin_assembly *a);

/* Sizes. Return -1 for a NULL handle. */
KIN_API int kin_dim(const kin_assembly *a);
KIN_API int kin_njoints(const kin_assembly *a);
KIN_API int kin_nbars(const kin_assembly *a);
KIN_API int kin_nfree(const kin_assembly *a);

/* Row of H (index into mechanism vectors) of coordinate `axis` of `joint`,
 * or -1 if that coordinate is fixed or the arguments are out of range. */
KIN_API int kin_free_index(const kin_assembly *a, int joint, int axis);

/* Copy the bar list (2*nbars ints) / rest lengths (nbars) / fixity flags
 * (njoints*dim, 1 = fixed) into caller arrays. Return KIN_OK or KIN_ENULL. */
KIN_API int kin_get_bars(const kin_assembly *a, int *bars);
KIN_API int kin_get_rest_lengths(const kin_assembly *a, double *lengths);
KIN_API int kin_get_fixed(const kin_assembly *a, unsigned char *fixed);

/* Current joint coordinates, njoints*dim, joint-major. KIN_OK or KIN_ENULL. */
KIN_API int kin_get_coords(const kin_assembly *a, double *xyz);

/* Move the assembly to new coordinates (njoints*dim, joint-major, finite,
 * |x| <= 1e150 as for kin_assembly_create). Fixed coordinates must equal
 * their current values (supports do not move). Resets the path state (path
 * length, orientation, step count) and invalidates the analysis. Rest
 * lengths are unchanged: the new configuration may be strained. Returns
 * KIN_OK, KIN_ENULL, KIN_EGEOM (a coordinate non-finite or too large, or a
 * bar shorter than 1e-150 but not zero), or KIN_EINVAL (a fixed coordinate
 * changed, or a bar collapsed to zero length); on error the assembly is
 * unchanged (but for kin_last_error()). */
KIN_API int kin_set_coords(kin_assembly *a, const double *xyz);

/* Current bar lengths (nbars). KIN_OK or KIN_ENULL. */
KIN_API int kin_get_lengths(const kin_assembly *a, double *lengths);

/* Largest relative bar strain max_k |L_k - L0_k| / L0_k now, or -1 if a is
 * NULL. */
KIN_API double kin_max_strain(const kin_assembly *a);

/* Equilibrium matrix H at the current configuration into (H, ldh, nfree,
 * nbars). Column k is bar k's direction cosines: +(X_A - X_B)/L at A's free
 * rows, -(X_A - X_B)/L at B's, for bar k = (A, B). H^T = C is the
 * compatibility matrix (C d = e). Returns KIN_OK, KIN_ENULL, KIN_ERANGE
 * (ldh < nfree). */
KIN_API int kin_get_equilibrium_matrix(const kin_assembly *a, double *H, int ldh);

/* ---- First-order analysis (paper 3.1) -------------------------------- */

typedef struct kin_analysis {
    size_t size; /* sizeof(kin_analysis) as the caller compiled it (docs/abi.md) */
    int rank;       /* r: singular values > rank_tol * v_max */
    int m;          /* nfree - r: all infinitesimal mechanisms */
    int m_rigid;    /* rigid-body mechanisms allowed by the supports */
    int m_internal; /* m - m_rigid: 1 on a path, >= 2 at a bifurcation or
                       on a mechanism with several degrees of freedom */
    int s;          /* nbars - r: states of self-stress */
    double v_max;   /* largest singular value */
    double v_r;     /* lowest non-zero singular value (v_r of the paper) */
    /* layout 2 (docs/abi.md): a host compiled without this field does not get it */
    int s_trivial;  /* of the s, those of the bars with no free coordinate at
                       either end (each alone in tension, a zero column of H
                       at every configuration): the second order, branches and
                       the path's classification use the s - s_trivial others
                       (docs/generality.md, "Bars between fixed joints") */
} kin_analysis;

/* Factorize H at the current configuration (LAPACK dgesdd, falling back to
 * dgesvd if dgesdd fails; in KIN_STEP_SPARSE mode without the dense SVD,
 * see SPARSE MODE below), count rank, mechanisms and self-stresses, and
 * split the mechanisms into rigid-body ones (infinitesimal rigid motions of
 * the whole assembly that keep every fixed coordinate fixed; Pellegrino &
 * Calladine 1986) and internal ones (the orthonormal complement of the rigid
 * ones within the null space). A rigid motion counts only if it moves the
 * free joints by more than rank_tol (the rank's own tolerance) times the
 * size of a unit rigid motion of the whole assembly (sqrt(njoints),
 * coordinates measured from the centroid in units of their RMS radius): a
 * rotation about a line through every joint moves nothing and is not a
 * mechanism, and one about a line the joints are off by more than the rank
 * resolves is rigid, not internal. out may be NULL. The results
 * stay readable through the getters below until the configuration changes.
 * Progress (kin_set_progress): done = 0 of total = 2 before the SVD, 1 after
 * it, 2 at the end; a callback that asks to cancel at 0 or 1 makes the call
 * return KIN_ECANCELLED with the previous analysis kept.
 * SPARSE MODE (kin_options.factorization == KIN_STEP_SPARSE): nothing of
 * size nfree x nbars is made (a 10^4-joint mast: 5 s, 140 MB). v_max is
 * bracketed to a few rounding units (Lanczos, then a Cholesky factorization
 * of mu^2 I - H^T H decides mu > v_max); the singular vectors at the small
 * end come from subspace iteration with one KLU factorization of the
 * augmented matrix [tau I, H; H^T, -tau I] (tau = rank_tol * v_max) and
 * Ritz values of H itself: the same rank rule, counts, v_r and orthonormal
 * bases of the mechanisms (rigid, internal, all) and self-stresses as the
 * dense SVD to rounding (test_analysis_sparse). The decision is checked: a
 * count is answered once the gap at rank_tol * v_max is clear on both
 * sides of it (v_r is then the Ritz value, within its residual of a
 * singular value of H); a singular value within its uncertainty of
 * rank_tol * v_max, or an iteration that does not settle, gives
 * KIN_ENOTCONVERGED. Where the dense workspace fits in half the memory
 * (and LAPACK's int sizes), the sparse analysis stops once its work (counted
 * in operations, not timed) would pass the dense SVD's predicted cost, or at
 * its limit of 1020 mechanisms or self-stresses, and the dense SVD answers
 * (kin_get_analysis_route says which route did); where it does not fit,
 * more than 1020 mechanisms or self-stresses give KIN_ELIMIT (at once where
 * nfree - nbars or nbars - nfree says so). A sparse answer has no full
 * spectrum: kin_get_singular_values then returns KIN_ESTATE. Progress:
 * 0 of 2 before the factorizations, 1 after them, 2 at the end (again from
 * 0 where the dense route takes over). The library's own loops (locating,
 * second order, following) still analyse with the dense SVD (KIN_ENOMEM,
 * saying so, where it cannot be had); kin_step in this mode confirms a
 * point its LU estimates cannot call regular with the sparse analysis when
 * the dense workspace does not fit (kin_path.h).
 * Returns KIN_OK, KIN_ENULL, KIN_ENOMEM (the dense workspace, made at the
 * first analysis, cannot be had; or, sparse mode, a factorization),
 * KIN_ELAPACK_ARG, KIN_ELAPACK_CONV, KIN_ECANCELLED; sparse mode also
 * KIN_ENOTCONVERGED, KIN_ELIMIT. */
KIN_API int kin_analyse(kin_assembly *a, kin_analysis *out);

/* Last analysis, if current. KIN_ESTATE if kin_analyse() has not been run
 * since the configuration last changed (kin_step() keeps it current in the
 * default KIN_STEP_SVD mode; in KIN_STEP_LU mode only after a step that fell
 * back to the SVD, see kin_path.h). The same holds for the getters below. */
KIN_API int kin_get_analysis(const kin_assembly *a, kin_analysis *out);

/* Which computation answered the current analysis (kin_get_analysis_route). */
enum kin_analysis_route {
    KIN_ROUTE_DENSE = 0, /* the dense SVD of H (every mode; in KIN_STEP_SPARSE
                            mode where it fits in memory and costs less) */
    KIN_ROUTE_SPARSE = 1 /* the sparse analysis (KIN_STEP_SPARSE mode) */
};

/* *route := the enum kin_analysis_route of the current analysis (the one
 * kin_get_analysis returns). KIN_OK, KIN_ENULL, KIN_ESTATE (no current
 * analysis; *route untouched). */
KIN_API int kin_get_analysis_route(const kin_assembly *a, int *route);

/* All min(nfree, nbars) singular values, descending, into sv[0..n-1];
 * n must be >= min(nfree, nbars). KIN_OK, KIN_ENULL, KIN_ERANGE, KIN_ESTATE
 * (no current analysis; or the current one is a sparse-mode analysis,
 * which has v_max and v_r (kin_get_analysis) but not the spectrum: nothing
 * is written, kin_last_error says so). */
KIN_API int kin_get_singular_values(const kin_assembly *a, double *sv, int n);

/* Which mechanisms kin_get_mechanisms() returns. */
enum kin_mech_kind {
    KIN_MECH_INTERNAL = 0, /* m_internal columns, orthonormal */
    KIN_MECH_RIGID = 1,    /* m_rigid columns, orthonormal */
    KIN_MECH_ALL = 2       /* m columns: U_m of the SVD, orthonormal */
};

/* Mechanisms of the last analysis into (U, ldu, nfree, cols); cols must be
 * >= the count of that kind (extra columns are left untouched).
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (kind), KIN_ERANGE, KIN_ESTATE. */
KIN_API int kin_get_mechanisms(const kin_assembly *a, int kind, double *U, int ldu, int cols);

/* States of self-stress W_s of the last analysis into (W, ldw, nbars, cols),
 * cols >= s, orthonormal columns. KIN_OK, KIN_ENULL, KIN_ERANGE, KIN_ESTATE. */
KIN_API int kin_get_self_stresses(const kin_assembly *a, double *W, int ldw, int cols);

#ifdef __cplusplus
}
#endif

#endif /* KIN_ASSEMBLY_H */
