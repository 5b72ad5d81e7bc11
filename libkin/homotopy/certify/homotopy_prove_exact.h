/* Private to homotopy/certify/: the bounds eta, rho, L of the Krawczyk test
 * of homotopy_prove.c computed with exact integer products (64-bit
 * integers, FLINT's limb arithmetic) and Arb's mags (homotopy_prove_exact.c),
 * tried before arb_dot balls at every endpoint (after the double-precision
 * test where prove = 1); what it cannot prove goes to the balls. */
#ifndef KIN_HOMOTOPY_PROVE_EXACT_H
#define KIN_HOMOTOPY_PROVE_EXACT_H

#include <acb.h>

typedef struct hom_exact hom_exact;

/* the system of kin__prove_new: Q its enclosures (s m m balls,
 * Q[(j m + r) m + c]), S (s) upper bounds of sum_{r,c} |Q_j(r,c)| over
 * every system in them. NULL if out of memory. */
hom_exact *kin__exact_new(int m, int s, arb_srcptr Q, mag_srcptr S);
void kin__exact_free(hom_exact *F);

/* The centre x_c = vr_c + i vi_c (vi all 0 if real), |vr_c|, |vi_c| < 1.25
 * (a chart of the largest coordinate: |x_c| <= 1 up to rounding): vr, vi
 * are truncated in place to multiples of 2^-60 (still doubles, for
 * homotopy_prove_fast.c's test), kept for the next kin__exact_bounds, and
 * written to x exactly (from the integers, in Arb). 0 (x untouched, no
 * bounds) if some |vr_c| or |vi_c| is not below 1.25 or is NaN. */
int kin__exact_centre(hom_exact *F, double *vr, double *vi, int real, acb_ptr x);

/* At that centre in chart k: upper bounds eta >= |Y f(x)|,
 * rho >= |I - Y J(x)|, L >= 2 max_a sum_j |Y_aj| S_j for an exact Y of its
 * choice (homotopy_prove.c); 0 if Y could not be formed (J numerically
 * singular or not finite). */
int kin__exact_bounds(hom_exact *F, int k, int real, mag_t eta, mag_t rho, mag_t L);

#endif /* KIN_HOMOTOPY_PROVE_EXACT_H */
