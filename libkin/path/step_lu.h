/* Private: the LU modes' factorizations and corrections (step_lu.c), used
 * by kin_step (path.c). Not installed. */
#ifndef KIN_STEP_LU_H
#define KIN_STEP_LU_H

#include "path/path.h"

/* the current point's bordered factors are usable: made at this very
 * configuration, judged regular, with the tangent known */
int kin__lu_current(const kin_assembly *a);

/* chord correction with the current point's factors: d solves
 * [C; b^T; R^T] d = [e; 0; 0], minus its component along the tangent (the
 * minimum-norm correction of eq. 11) */
int kin__lu_chord_correction(kin_assembly *a, const double *e, double *d);

/* Newton correction at xyz: s solves [C(xyz); t^T; R^T] s = [-e; 0; 0]
 * (factorized into the trial slot; *reusable = 1 when those factors can
 * serve kin__lu_newton_reuse), or kin__bordered_solve's where J is not
 * square or is singular */
int kin__lu_newton_solve(kin_assembly *a, const double *xyz, const double *e, double *s, int *reusable);
int kin__lu_newton_reuse(kin_assembly *a, const double *e, double *s);

/* a corrected trial point xyz: factors into the trial slot, unoriented unit
 * tangent in a->d, estimates; *regular = 0 when the SVD must decide */
int kin__lu_new_point(kin_assembly *a, const double *xyz, int *regular);

/* KIN_STEP_SPARSE: factorize the current point itself (no SVD) when it has
 * no factors: border row the previous tangent, or a fixed pseudo-random
 * row; the tangent goes to a->t oriented like the SVD's (or along the
 * previous tangent). *started = 1 when the point is regular and the step
 * can go on from these factors; 0: the caller analyses by SVD. */
int kin__lu_start(kin_assembly *a, int *started);

/* A := A^-1 in place (n x n, column major) by Gauss-Jordan elimination with
 * partial pivoting (gauss_jordan.c); perm and cols (n ints each) and col (n
 * doubles) are workspace. Returns 0 and *sign = the sign of det(A), or
 * k + 1 when the k-th pivot is exactly zero or not finite (A is then
 * overwritten, *sign 0). */
int kin__gauss_jordan_inverse(int n, double *A, int *perm, int *cols, double *col, int *sign);

#endif /* KIN_STEP_LU_H */
