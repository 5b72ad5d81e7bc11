/* Private: the equivariant total-degree homotopy of the symmetric complete
 * solver (homotopy_equi.c, used by homotopy_sym.c).
 *
 * When a cyclic subgroup <h> of the caller's group acts on beta like a
 * permutation of coordinates that fixes one coordinate, and on the
 * equations like the same permutation of the others, the system can be
 * written in coordinates x (beta = U x, U orthogonal) and equations
 * (orthogonal combinations of the Q_j) where h is that permutation P:
 * F(P x) = P F(x) with the equations numbered like the coordinates 1..s.
 * The start system x_j^2 - x_0^2 of the plain solver is then equivariant
 * too, so is the whole homotopy, and P maps the path from a start root to
 * the path from the permuted start root: one path per orbit of start roots
 * is tracked, its endpoint permuted gives the others'. */
#ifndef KIN_HOMOTOPY_EQUI_H
#define KIN_HOMOTOPY_EQUI_H

#include "homotopy/solver/homotopy_solver.h"
#include "homotopy/symmetric/homotopy_sym.h"
#include "homotopy/track/homotopy_track.h"

/* the change of coordinates and equations */
typedef struct hom_equi {
    int k;                           /* order of the cyclic group used (0: none qualifies) */
    int perm[HOM_MAX_M];             /* p: (P x)_i = x_{p(i)}, p(0) = 0 */
    double U[HOM_MAX_M * HOM_MAX_M]; /* beta = U x (orthogonal, column-major m x m) */
    double *Qt;                      /* the system in x: s matrices m x m (column-major, the
                                        public layout), exactly equivariant under P */
} hom_equi;

/* Look for the largest cyclic subgroup of G that qualifies (above) and
 * set E up for it. Qr: the scaled symmetric rows of the caller's system
 * (hom_solver.Qr); seed: the random intertwiners. Returns KIN_OK (E->k = 0
 * when no subgroup qualifies: the caller uses the monodromy), KIN_ENOMEM,
 * KIN_ELAPACK_ARG or KIN_ELAPACK_CONV. */
int kin__equi_plan(hom_equi *E, int m, int s, const double *Qr, const sym_group *G, unsigned long long seed);
void kin__equi_free(hom_equi *E);

/* The orbits of the 2^s start roots under P (hom_orbits,
 * solver/homotopy_solver.h: path b's bit j - 1 is the sign of x_j; P maps
 * it to path next[b]). KIN_OK or KIN_ENOMEM (O then empty) */
int kin__orbits_init(hom_orbits *O, int m, const int *perm);
/* the number of orbits without the table (Burnside's count; perm of
 * order k) */
long kin__orbits_count(int m, int k, const int *perm);
void kin__orbits_free(hom_orbits *O);

#endif /* KIN_HOMOTOPY_EQUI_H */
