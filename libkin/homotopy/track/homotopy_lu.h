/* Private: the one complex LU factorisation of the one-path trackers, in
 * homotopy_kernels.c: the complete solver's tracker and certificate
 * (homotopy_track.c) and the symmetric solver's parameter tracker
 * (homotopy_param.c). Their lockstep twins (homotopy_lanes.c, used by
 * homotopy_batch.c and homotopy_param_lanes.c) give every lane exactly
 * these operations. */
#ifndef KIN_HOMOTOPY_LU_H
#define KIN_HOMOTOPY_LU_H

#include "homotopy/track/homotopy_track.h"

enum { HOM_MM = HOM_MAX_M * HOM_MAX_M };

/* Complex n x n matrices are column-major with the column stride
 * np = n rounded up to whole lanes (entry (i, j) at j*np + i, rows n..np-1
 * zero): the factorisation's updates and both substitutions run down
 * contiguous columns in whole groups of HOM_LANES rows (independent
 * updates the compiler puts in vector registers), the rows outside the
 * range being multiplied by stored zeros. Every entry in the range receives
 * the same operations in the same order as in a row-oriented elimination. */
typedef struct hom_lu {
    double r[HOM_MM], i[HOM_MM];     /* J; after factoring, U strictly above the diagonal (zeros on
                                        and below it) */
    double lr[HOM_MM], li[HOM_MM];   /* after factoring, L strictly below the diagonal (zeros on
                                        and above it; the unit diagonal is implied) */
    double dr[HOM_MAX_M], di[HOM_MAX_M]; /* 1 / U_kk */
    int piv[HOM_MAX_M];
} hom_lu;

/* n rounded up to whole lanes: the column stride of hom_lu */
static inline int kin__hom_lanes_up(int n) { return (n + HOM_LANES - 1) / HOM_LANES * HOM_LANES; }
/* LU with partial pivoting (the first largest |re| + |im|) in place; 0 if
 * a pivot is zero or not finite */
int kin__hom_lu_factor(int n, hom_lu *F);
/* b <- A^-1 b (b: n rounded up to HOM_LANES entries, the last ones scratch) */
void kin__hom_lu_solve(int n, const hom_lu *F, double *restrict br, double *restrict bi);
/* the Hager-Higham estimate of |A^-1|_1 (a lower bound, usually exact) */
double kin__hom_inv_norm1(int n, const hom_lu *F);

#endif /* KIN_HOMOTOPY_LU_H */
