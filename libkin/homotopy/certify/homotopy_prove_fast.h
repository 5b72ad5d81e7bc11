/* Private to homotopy/certify/: the Krawczyk test of homotopy_prove.c in
 * double precision with a priori rounding bounds (homotopy_prove_fast.c),
 * tried first at every endpoint; what it cannot prove goes to Arb's balls. */
#ifndef KIN_HOMOTOPY_PROVE_FAST_H
#define KIN_HOMOTOPY_PROVE_FAST_H

typedef struct hom_fast hom_fast;

/* the system of kin__prove_new; S: s upper bounds of sum_{r,c} |Q_j(r,c)|
 * of the exact symmetric parts (from Arb). NULL if out of memory. */
hom_fast *kin__fast_new(int m, int s, const double *Q, const double *S);
void kin__fast_free(hom_fast *F);

/* The test at the centre x = xr + i xi (m doubles, exact; x_k = 1, xi all 0
 * if real): 1 and *r (the radius of a box holding exactly one solution,
 * an upper bound) when it proves one, else 0. */
int kin__fast_krawczyk(hom_fast *F, const double *xr, const double *xi, int k, int real, double *r);

#endif /* KIN_HOMOTOPY_PROVE_FAST_H */
