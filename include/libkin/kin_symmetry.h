/* libkin: the symmetries of an assembly, found automatically.
 *
 * A symmetry g = (perm, Q, t) of an assembly in its current configuration X
 * is a permutation of the joints with an isometry x -> Q x + t (Q
 * orthogonal, a rotation or a reflection) such that
 *  - bars go to bars of the same rest length: {i, j} -> {perm[i], perm[j]};
 *  - supports go to supports: Q maps the fixed axes of joint i onto fixed
 *    axes of joint perm[i] (free coordinates go to free coordinates);
 *  - the configuration is kept: X[perm[i]] = Q X[i] + t for every joint.
 * Such a g maps every configuration of the structure to another one and
 * every path to a path. Acting on velocities, it maps the internal
 * mechanisms U to themselves: R_g = U^T P_g U (P_g its action on free
 * coordinates) is orthogonal, and the second-order system of
 * kin_second_order is equivariant under the R_g, which is what
 * kin_quadrics_homotopy_sym (kin_branch.h) takes.
 *
 * Method (docs/branches.md): the candidates are the automorphisms of the
 * bar graph found by nauty's Traces, each bar a vertex of its own coloured
 * by its rest length (and current length), each joint coloured by its
 * number of fixed coordinates and its distance from the centroid (which
 * every symmetry keeps); the group they generate is enumerated, and a
 * candidate is kept when the orthogonal Procrustes fit of the centred
 * configurations (LAPACK dgesvd) matches them to 1e-7 x the model size
 * and maps fixed axes onto fixed axes. When the joints span fewer
 * dimensions than the space (a flat sail in 3D), the fit is not unique and
 * the reflections through the missing directions are tried too (z -> -z of
 * a flat sail is a symmetry with the identity permutation).
 * Like Python's libkin.automorphisms, which these calls reproduce. */
#ifndef KIN_SYMMETRY_H
#define KIN_SYMMETRY_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Graph automorphisms enumerated at most (the order of the group of the
 * coloured bar graph, before the geometric test); a structure with more is
 * refused with KIN_ELIMIT. */
#define KIN_SYMMETRY_MAX_CANDIDATES 20000

/* Every symmetry of a in its current configuration, the identity first,
 * then by permutation (lexicographic). For symmetry k < *nsym:
 *  perm (njoints x max_sym ints, or NULL): perm[k*njoints + i] = the joint
 *       that joint i goes to;
 *  Q    (dim*dim x max_sym, or NULL): Q + k*dim*dim, dim x dim column-major;
 *  t    (dim x max_sym, or NULL): t + k*dim.
 * The assembly is not moved; only its last-error message is written.
 * Returns KIN_OK, KIN_ENULL (a, nsym), KIN_EINVAL (max_sym < 1),
 * KIN_ERANGE (more than max_sym symmetries: *nsym receives how many there
 * are, the arrays are not written), KIN_ELIMIT (the coloured bar graph has
 * more than KIN_SYMMETRY_MAX_CANDIDATES automorphisms), KIN_ENOMEM,
 * KIN_ELAPACK_ARG, KIN_ELAPACK_CONV. On other failures *nsym = 0 (if nsym
 * is not NULL) and the arrays are not written. Memory: the candidates, at
 * most KIN_SYMMETRY_MAX_CANDIDATES x njoints ints, allocated per call.
 * nauty's own work arrays (a few ints per joint and bar) end the process
 * if they cannot be allocated: nauty's behaviour, which libkin cannot
 * change. */
KIN_API int kin_symmetries(kin_assembly *a, int max_sym, int *perm, double *Q, double *t, int *nsym);

/* The symmetry group acting on the internal-mechanism coordinates beta:
 * for each symmetry g of kin_symmetries, R_g = U^T P_g U, U the internal
 * mechanisms (kin_get_mechanisms(KIN_MECH_INTERNAL)) of the current
 * analysis (made here by kin_analyse if there is none) and P_g g's action
 * on free coordinates ((P v) is the velocity of g.X when v is that of X).
 * R receives *ngroup m x m matrices (m = m_internal, column-major, one
 * after another: R[k*m*m + r + c*m]; max_group*m*m doubles), ordered by
 * decreasing trace, the identity first. Pass them to
 * kin_quadrics_homotopy_sym with the Q of kin_second_order at the same
 * configuration. Each symmetry gives one matrix (two may coincide, or
 * differ in sign only: the z -> -z mirror of a flat sail gives -I when
 * every mechanism moves out of plane).
 * Returns KIN_OK, KIN_ENULL (a, R, ngroup), KIN_EINVAL (max_group < 1),
 * KIN_ENOMECH (m_internal = 0), KIN_ERANGE (more than max_group symmetries:
 * *ngroup receives how many, R is not written), KIN_ESTATE (an R_g is not
 * orthogonal to 1e-8: the mechanism space is not invariant, as when
 * near-zero singular values straddle rank_tol), KIN_ELIMIT, KIN_ENOMEM,
 * KIN_ELAPACK_ARG, KIN_ELAPACK_CONV (the analysis or the fits). On other
 * failures *ngroup = 0 and R is not written. */
KIN_API int kin_mechanism_group(kin_assembly *a, int max_group, double *R, int *ngroup);

#ifdef __cplusplus
}
#endif

#endif /* KIN_SYMMETRY_H */
