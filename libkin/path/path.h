/* Private: what the path layer (paper Section 3.2: predictor-corrector
 * following, its LU and sparse step modes) offers the layers above it
 * (locate/, branches/) and the tests. Not installed. */
#ifndef KIN__LAYER_PATH_H
#define KIN__LAYER_PATH_H

#include "model/internal.h"

/* min-norm least-squares solve of the bordered Newton system at xyz:
 * [C(xyz); t^T] d = [-e; 0]; d has nf entries */
int kin__bordered_solve(kin_assembly *a, const double *xyz, const double *t, const double *e,
                        double *d);

/* The strain the input allows (STRAIN FLOOR in kin_path.h): max(the
 * start's own strain, measured here at the first call after the path state
 * was reset, and sqrt(dim) * coord_resolution / min L0) */
double kin__strain_floor(kin_assembly *a);
/* The corrector's strain tolerance in effect: max(corrector_tol, the floor) */
double kin__corrector_tol(kin_assembly *a);

/* kin_step with an explicit predictor: pred (nf free coordinates) must
 * satisfy t.(pred - x0) = delta for the current oriented tangent t; one
 * attempt, no clamping or halving (the locator's forward calculations) */
int kin__step_predicted(kin_assembly *a, double delta, const double *pred, kin_step_info *info);

/* ---- the cheap stretches of a follow (step_lu.c; branches/follow.c) ---- */
/* The sign of det [C; t^T; R^T] at the current point (t its oriented
 * tangent, R the rigid-body basis of kin__rigid_basis: continuous along a
 * path, the same at every point), from the LU-mode factors the last step
 * left: their border row was the step's tangent t_prev, and det is linear in
 * the border's component along the null vector, so the sign is
 * sign(det J) * sign(t_prev . t). *sign = 0 where there are no square dense
 * factors of this point (or J is exactly singular). */
void kin__lu_det_sign(const kin_assembly *a, const double *t_prev, int *sign);
/* The same sign at the current point by one LU of [C; t^T; R^T] built here
 * (a start point analysed by SVD). *sign = 0 where J is not square. */
int kin__border_det_sign(kin_assembly *a, int *sign);
/* v_r / v_max of the current point as the LU mode estimated it (valid
 * factors), or the SVD's (a current analysis), or -1 */
double kin__lu_rel_estimate(const kin_assembly *a);

/* The vanishing singular triple (H w = v u, the lowest non-zero singular
 * value) of the current point from its LU-mode factors: subspace iteration
 * on pinv(C) pinv(C)^T with k vectors (1 <= k <= KIN__VR_BLOCK_MAX), the
 * first the LU mode's vector, the others the Ritz vectors of the last call
 * where *warm (else fixed pseudo-random ones), and Rayleigh-Ritz after every
 * pass, until the Ritz vector of v_r moves by less than tol between passes
 * (*converged = 1) or after max_passes. The Ritz vector converges at
 * (v_r / v_(r-k))^2 per pass, not (v_r / v_(r-1))^2 as one vector does: the
 * next singular values may be close. block: room for 2 k nf (the first k nf
 * keep the Ritz vectors for the next call, *warm set). u: nf entries, w: nb,
 * v > 0. KIN_ESTATE without square dense factors of this point. */
enum { KIN__VR_BLOCK_MAX = 4 };
/* The LU mode's factors of the current point again (a point restored by
 * kin__path_restore, whose factors were made with border row `border`, the
 * tangent before the step that reached it): bordered factors, estimates and
 * (with a->lu_inverse) (J^T)^-1 into the current slot; the tangent stays
 * a->t. *regular = 0 where the SVD must decide (the factors are then not
 * kept). The same factors as the step made, where the estimates' start
 * vectors are the same. */
int kin__lu_refactor(kin_assembly *a, const double *border, int *regular);
/* The current point has usable square dense LU-mode factors of
 * J = [C; t_prev^T] (no rigid mechanisms: nb + 1 = nf) */
int kin__lu_square_current(const kin_assembly *a);
/* The minimum-norm chord correction d (nf) of the strain residual e (nb)
 * with the current point's LU-mode factors: C d = e, d orthogonal to the
 * tangent and the rigid mechanisms (pinv(C) e, as the SVD's chord
 * correction over the non-zero singular values). KIN_ESTATE without
 * current factors. */
int kin__lu_pinv_correction(kin_assembly *a, const double *e, double *d);
int kin__lu_vr_triple(kin_assembly *a, int max_passes, double tol, int k, double *block, int *warm, double *u,
                      double *w, double *v, int *converged);

/* A point of a path, kept cheaply (no factors): what a step needs to resume
 * from it. kin__path_restore puts the handle back there with no analysis
 * (the next step or kin__analyse makes one). */
typedef struct kin__path_point {
    double *xyz, *t; /* nj*dim and nf entries, the caller's storage */
    double l, step_hint, start_strain;
    int have_start_strain, chord_hopeless;
} kin__path_point;
void kin__path_save(const kin_assembly *a, kin__path_point *p);
void kin__path_restore(kin_assembly *a, const kin__path_point *p);

/* ---- sparse bordered factorization (path/sparse*.c, KIN_STEP_SPARSE) ----
 * J = [C; b^T; R^T] (nf x nf, nb bar rows then nf - nb dense border rows)
 * in compressed-column form, solved through KLU's factors of J0 (the border
 * rows replaced by unit stand-in rows) and a bordering correction, per slot
 * 0 or 1 (the slots of a->lu[]); sparse.c's header has the details. */
/* Build the pattern, the symbolic analysis and both slots' first numeric
 * factorization at the current configuration, once per handle (a no-op when
 * done, or when J can never be square: then a->sp stays NULL). KIN_OK or
 * KIN_ENOMEM. */
int kin__sparse_prepare(kin_assembly *a);
void kin__sparse_free(kin_assembly *a);
/* 1 when the square sparse route is ready for a point with mr rigid mechanisms */
int kin__sparse_usable(const kin_assembly *a, int mr);
/* Factorize J(xyz) with border rows b (nf) and R (nf x mr, ld nf) into slot;
 * *singular = 1 when J is singular (exactly, to KLU). Counts in a->nfact.
 * KIN_OK, KIN_ENOMEM (a re-pivoting factorization could not allocate). */
int kin__sparse_factor(kin_assembly *a, int slot, const double *xyz, const double *b, const double *R,
                       int mr, int *singular);
/* trans = 0: v := J^-1 v; trans = 1: v := J^-T v (nf entries) with slot's factors */
int kin__sparse_solve(kin_assembly *a, int slot, int trans, double *v);
/* y (nb) := C x and x (nf) := C^T y with the values of slot's last factorization */
void kin__sparse_C(const kin_assembly *a, const double *x, double *y);
void kin__sparse_CT(const kin_assembly *a, const double *y, double *x);
/* The column order kept by kin__sparse_prepare (1: METIS nested dissection,
 * 0: COLAMD) and the factor entries (L + U) of each order tried at the
 * first factorization (INFINITY where not tried or failed). 0 without
 * sparse factors. */
int kin__sparse_order(const kin_assembly *a, double *entries_colamd, double *entries_nd);
/* The factor entries (L + U) of J0 (the stand-in rows, kept order) and of J
 * with its dense rows, both at set-up; the stand-in re-choices and the
 * factorizations made with the dense rows since (INFINITY, 0 without sparse
 * factors). */
void kin__sparse_stats(const kin_assembly *a, double *entries, double *entries_dense, long *rechoices,
                       long *dense_points);
/* Test hook: make k (1 + m_rigid distinct free coordinates) the stand-in
 * coordinates; each slot re-analyses at its next factorization. KIN_OK,
 * KIN_ESTATE (no sparse factors), KIN_EINVAL. */
int kin__sparse_set_standins(kin_assembly *a, const int *k);

#endif /* KIN__LAYER_PATH_H */
