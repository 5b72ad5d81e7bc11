/* Private: the automorphism group of an assembly's coloured bar graph
 * (nauty's Traces), enumerated element by element. */
#ifndef KIN_SYMMETRY_GRAPH_H
#define KIN_SYMMETRY_GRAPH_H

/* Every permutation of the nj joints that maps bars to bars of the same
 * colour and joints to joints of the same colour (jcolour: nj, bcolour: nb,
 * any ints; bars: 2*nb joint indices, no duplicates). *perms receives a
 * malloc'ed array of *count permutations, nj ints each (perm[k*nj + i] =
 * image of joint i), the identity first; the caller frees it. More than
 * max_count automorphisms: KIN_ELIMIT with *count = the group order, or
 * INT_MAX if it is larger (nothing allocated). Returns KIN_OK, KIN_ELIMIT,
 * KIN_ENOMEM. */
int kin__graph_automorphisms(int nj, int nb, const int *bars, const int *jcolour, const int *bcolour,
                             int max_count, int **perms, int *count);

#endif /* KIN_SYMMETRY_GRAPH_H */
