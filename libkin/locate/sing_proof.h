/* Private: the proof that an exactly singular configuration lies near the
 * current point (issue 38 item 2; sing_proof.c). Not installed. */
#ifndef KIN_SING_PROOF_H
#define KIN_SING_PROOF_H

#include "model/internal.h"

/* why no proof (kin__sing_proof.reason) */
enum kin__sing_reason {
    KIN__SING_PROVEN = 0,
    KIN__SING_NO_SVD = 1,    /* no current dense analysis at the point */
    KIN__SING_RIGID = 2,     /* rigid-body mechanisms without a basis to gauge them by */
    KIN__SING_CORANK = 3,    /* more than one non-trivial self-stress: the system is not square */
    KIN__SING_FAR = 4,       /* Newton on the extended system left the neighbourhood or failed */
    KIN__SING_KRAWCZYK = 5,  /* the test did not pass (not a simple bifurcation, or ill-conditioned) */
    KIN__SING_TOO_LARGE = 6  /* the extended system is larger than the proof is attempted for */
};

typedef struct kin__sing_proof {
    int proven;      /* 1: the theorem of sing_proof.c holds with the bounds below */
    int corank;      /* non-trivial self-stresses at the point (s - s_trivial) */
    int reason;      /* enum kin__sing_reason */
    double distance; /* >= max_i |x*_i - x_i| over the free coordinates (model units) */
    double dlength;  /* >= max_k |L*_k - L0_k|: the bar lengths the singular structure has */
    double unique;   /* no other solution of the extended system within this max-norm radius
                        of the proof's centre (model units; phi and mu scaled alike) */
} kin__sing_proof;

/* Prove, in Arb's ball arithmetic, that a structure whose squared bar
 * lengths differ from L0^2 by mu* e (e the point's unit self-stress in
 * force densities) is exactly singular at a configuration x* near the
 * current one, and bound |x* - x| and |L* - L0|. Uses the current dense
 * analysis (made if not current). *p is always written; returns KIN_OK,
 * KIN_ENOMEM, or the analysis's code. */
int kin__sing_prove(kin_assembly *a, kin__sing_proof *p);

/* As kin__sing_prove; where proven and centre is not NULL, also the proof's
 * centre (nj dim coordinates, model units): a configuration within
 * p->distance of the exactly singular x*, whose bar lengths are within
 * p->dlength of the given ones to the rounding of its coordinates (the
 * follower ends a crossing broken by rounding there; follow.c). */
int kin__sing_prove_centre(kin_assembly *a, kin__sing_proof *p, double *centre);

#endif /* KIN_SING_PROOF_H */
