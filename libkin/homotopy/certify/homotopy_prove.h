/* Private: homotopy/certify/, the interval certificates of the complete
 * solver's endpoints (issue 38): proofs in Arb's ball arithmetic, not the
 * tracker's floating-point Kantorovich test (track/).
 *
 * One endpoint (homotopy_prove.c): a Krawczyk test proves that a
 * polydisc (a box of complex discs, max norm) around the endpoint, in the
 * affine chart x_k = 1 of projective space, holds exactly one solution of
 * x^T Q_j x = 0 (j < s), a simple one, and whether it is real (the box is
 * centred on a real point) or non-real (the box misses the real subspace).
 * A test that fails in 53-bit balls is repeated after Newton steps in 128
 * and then 256 bits.
 * A set of endpoints (homotopy_prove_set.c): the proven boxes are shown
 * pairwise disjoint (a sort by an enclosure of a key on projective space,
 * then box against box), so each proven box counts one distinct solution.
 *
 * Nothing here knows the tracker: endpoints come as coordinate arrays, the
 * system as the caller's matrices. Sub-layer 0 of homotopy/, beside track/;
 * solver/ runs it on its threads and counts the result. */
#ifndef KIN_HOMOTOPY_PROVE_H
#define KIN_HOMOTOPY_PROVE_H

/* the most coordinates a proof handles (HOM_MAX_M of track/) */
#define HOM_PROVE_MAX_M 24
/* Every entry of Q_j is taken as known to within HOM_PROVE_Q_WIDTH S_j
 * (S_j = sum |Q_j(r,c)|): a proof holds for every system that close. The
 * Q_j a caller computes (from an analysis at a located point, through an
 * SVD) carry rounding of about 1e-15..1e-13 S_j, so a root proven real on
 * one machine is not proven non-real on another: a double root split by
 * rounding (two roots 1e-8 apart, real or a conjugate pair by the sign of a
 * 1e-16 discriminant) is not proven at all. 2^-50 = 8.9e-16. */
#define HOM_PROVE_Q_WIDTH 0x1p-50

enum hom_proof_kind {
    HOM_PROOF_NONE = 0,    /* not proven */
    HOM_PROOF_REAL = 1,    /* a box holding exactly one solution, simple and real */
    HOM_PROOF_NONREAL = 2  /* ... simple and not real */
};

/* One endpoint's proof: the box is every x with x_chart = 1 and
 * |x_c - centre_c| <= r (complex modulus) for the other c, the centre
 * written over the endpoint's coordinates (rounded to double, r enlarged by
 * that rounding, so the stored box contains the proven one). */
typedef struct hom_proof {
    int kind;  /* enum hom_proof_kind */
    int chart;
    int prec;  /* bits of the test that succeeded (53, 128, 256; 0: none) */
    double r;  /* the box's radius (an upper bound, rounded up) */
} hom_proof;

/* a thread's workspace for one system (opaque) */
typedef struct hom_prover hom_prover;

/* The system sum_{r,c} Q[j m^2 + r + c m] x_r x_c = 0 (j < s, m = s + 1;
 * only the symmetric part counts, enclosed as balls widened by
 * HOM_PROVE_Q_WIDTH S_j); NULL if out of memory. */
hom_prover *kin__prove_new(int m, int s, const double *Q);
void kin__prove_free(hom_prover *w);
/* on: try the double-precision test with a priori rounding bounds
 * (homotopy_prove_fast.c) before the exact test and Arb's balls
 * (kin_homotopy_options.prove = 1); off (the default, prove = 2): Arb's and
 * FLINT's only */
void kin__prove_use_fast(hom_prover *w, int on);
/* a thread that ran proofs is done with them: FLINT's per-thread caches
 * are released (a pool thread then exits without leaking them) */
void kin__prove_thread_end(void);

/* Prove the endpoint zr + i zi (m coordinates, projective: any scale), if
 * `want_real` as a real solution first (centred on the real part). On
 * return *out says what was proven; zr, zi hold the centre of the box in
 * its chart (the chart coordinate 1) when out->kind != HOM_PROOF_NONE and
 * are unchanged otherwise. `max_prec`: 53, 128 or 256, the last precision
 * tried. */
void kin__prove_endpoint(hom_prover *w, double *zr, double *zi, int want_real, int max_prec, hom_proof *out);

/* Of n endpoints (proof[i].kind != NONE: a proven box, centre zr, zi: m
 * doubles each at i*m), flag the proven boxes not shown disjoint from
 * every other proven box: clash[i] = 1 (0 otherwise, and for unproven
 * ones). w: a unit vector (m) of the sort key. Returns the number of boxes
 * flagged, or -1 if out of memory. */
int kin__prove_disjoint(int m, int n, const double *zr, const double *zi, const hom_proof *proof, const double *w,
                        unsigned char *clash);

/* [J | I] (s rows of 2s doubles, real parts Ar, imaginary Ai; J in the
 * left half, the right half is set here) -> [I | Y], Y ~ J^-1, by
 * Gauss-Jordan with partial pivoting (homotopy_prove_gj.c). cx = 0: J is
 * taken as real (Ai's entries are ignored, and Ai is used as scratch). The
 * left half is left as scratch, not I. 0 if a pivot is zero or not finite. */
int kin__prove_gauss_jordan(int s, double *Ar, double *Ai, int cx);

#endif /* KIN_HOMOTOPY_PROVE_H */
