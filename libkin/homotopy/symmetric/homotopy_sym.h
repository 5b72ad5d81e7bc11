/* Private: homotopy/symmetric/, the complete solver for a system with a
 * symmetry group (kin_quadrics_homotopy_sym; its entry point and the choice
 * of route are homotopy/homotopy_sym_route.c): the group and the root sets
 * (homotopy_sym_group.c); the monodromy route, which finds the roots of a
 * random equivariant start system by loops of parameter homotopies and
 * tracks one root per orbit to the caller's system (homotopy_sym.c, start
 * systems homotopy_sym_start.c, on param/'s trackers); the equivariant
 * route, the plain solver's homotopy with one path per orbit of start roots
 * in coordinates where a cyclic subgroup permutes coordinates and equations
 * alike (homotopy_equi.c, homotopy_sym_equi.c, on solver/'s runs), and the
 * plain route. Every route ends in solver/'s certificate, checks and
 * accounting. Above param/, solver/ and track/; below the entry points.
 *
 * This header: the symmetry group and the root sets of the symmetric
 * complete solver (homotopy_sym.c, homotopy_sym_group.c), its state and
 * routes. */
#ifndef KIN_HOMOTOPY_SYM_H
#define KIN_HOMOTOPY_SYM_H

#include <stddef.h>

#include "homotopy/param/homotopy_param.h"
#include "homotopy/solver/homotopy_solver.h"

/* The group acting on beta: its projectively distinct elements (R_g and
 * -R_g act alike on P^s and on the quadrics), with the matrices S_g of
 * q(R_g b) = S_g q(b) and their inverses. */
typedef struct sym_group {
    int m, s, n;   /* n: distinct elements */
    double *R;     /* n m x m column-major */
    double *Sinv;  /* n s x s column-major: S_g^-1 */
    double *S;     /* n s x s column-major */
} sym_group;

/* Check the caller's ngroup matrices R (orthogonal, a group up to sign, the
 * system q_j(b) = b^T Q_j b equivariant; Qr: the scaled symmetric rows of
 * homotopy_solver.h) and set up G. KIN_OK, KIN_EINVAL (with a message in
 * err), KIN_ENOMEM. */
int kin__sym_group_init(sym_group *G, int m, int s, const double *Qr, int ngroup, const double *R, char *err,
                        size_t errlen);
void kin__sym_group_free(sym_group *G);

/* The Reynolds projection onto the equivariant family E: P_j = (1/|G|)
 * sum_g sum_i (S_g^-1)_ji R_g^T Z_i R_g for a complex system Z (stacked,
 * homotopy_param.h). P must not alias Z. */
void kin__sym_reynolds(const sym_group *G, const double *Zr, const double *Zi, double *Pr, double *Pi);

/* y = R_g x (complex) */
void kin__sym_apply(const sym_group *G, int g, const double *xr, const double *xi, double *yr, double *yi);

/* A set of points of P^s (complex), each stored normalised by a fixed
 * random linear form (w.x = 1), looked up by a hashed scalar key. */
typedef struct sym_set {
    int m, n, cap;
    double *xr, *xi;   /* cap points of m */
    int *rep, *elem;   /* point i = R_elem[i] (point rep[i]) (the orbit's representative) */
    long long *bucket; /* key bucket of each point */
    int *next, *head;  /* hash chains; head has hsize entries */
    int hsize;
    const double *wr, *wi, *key; /* the normalising form and the key's direction (m each) */
} sym_set;

int kin__sym_set_init(sym_set *S, int m, int cap, const double *wr, const double *wi, const double *key);
void kin__sym_set_free(sym_set *S);
/* index of the point x (any scale) in S, or -1 */
int kin__sym_set_find(const sym_set *S, const double *xr, const double *xi);
/* Add the orbit of the new point x (not in S): its distinct images under
 * the group; x becomes its representative. Returns the representative's
 * index, -1 if the set is full (nothing added) or x normalises badly. */
int kin__sym_set_add_orbit(sym_set *S, const sym_group *G, const double *xr, const double *xi);

/* ---- the solver's state (homotopy_sym.c) ---- */
enum { NODES = 3 }; /* P0 and the two helper systems of the monodromy */

typedef struct sym_ctx { /* one call of kin_quadrics_homotopy_sym */
    int m, s, N, sm;
    hom_solver H; /* the scaled Q, certificate workspaces, threads */
    sym_group G;
    size_t nsys;  /* doubles per stacked system */
    double *Qr0;  /* zeros (imaginary part of Q) */
    double *Qst;  /* Q stacked */
    double *sys[NODES][2];
    double *dif[NODES][NODES][2]; /* sys[b] - sys[a] */
    double *dq[2];                /* Q - sys[0] */
    double *tmp[4];               /* scratch systems */
    double *scr;                  /* scratch, 2 s m */
    double seeds[2 * 64 * HOM_MAX_M]; /* points forced to be roots of P0 */
    sym_set set[NODES];
    int *queue[NODES][2], nq[NODES][2];
    double wr[HOM_MAX_M], wi[HOM_MAX_M], key[HOM_MAX_M], ar[HOM_MAX_M], ai[HOM_MAX_M];
    hpar_ws **pw;  /* per thread: the one-path tracker (the seeds) */
    hpar_bws **pb; /* per thread: the lockstep tracker (loops, the leg to Q) */
    /* progress */
    kin_progress_fn fn;
    void *user;
    double last;
    long done, queued;
    int cancelled;
    double lsteps, lrej; /* monodromy steps */
    unsigned long long st; /* the random stream (from opt->seed) */
} sym_ctx;

/* ---- the start system (homotopy_sym_start.c) ---- */
double kin__sym_uniform(unsigned long long *st); /* uniform in [0, 1) */
void kin__sym_gaussian2(unsigned long long *st, double *a, double *b); /* two standard normals */
/* a random complex member of E (stacked) of total Frobenius norm sqrt(s);
 * zr, zi: scratch systems */
void kin__sym_random_member(sym_ctx *C, unsigned long long *st, double *zr, double *zi, double *pr, double *pi);
/* points to force as roots of P0 (m complex each, at most maxseeds); the
 * count, -1 if out of memory */
int kin__sym_seeds(sym_ctx *C, unsigned long long *st, double *br, double *bi, int maxseeds);
/* correct C->sys[0] so that the K points are roots; 0 if impossible. zr,
 * zi: scratch systems */
int kin__sym_force_roots(sym_ctx *C, unsigned long long *st, int K, const double *br, const double *bi, double *zr,
                         double *zi);

/* release what C holds (a zeroed or partly set up C too) */
void kin__sym_ctx_free(sym_ctx *C);
/* The monodromy route (homotopy_sym.c), C->H and C->G set up: results as
 * kin_quadrics_homotopy_sym's. KIN_OK, KIN_ENOTCONVERGED (info->paths set,
 * si filled, *nsol = 0), KIN_ECANCELLED, KIN_ENOMEM. */
int kin__sym_monodromy_solve(sym_ctx *C, const kin_homotopy_options *o, double *betas, int maxsol, int *nsol,
                             int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *si, char *err,
                             size_t errlen);

/* ---- the routes of kin_quadrics_homotopy_sym ---- */
enum {
    KIN__SYM_AUTO = 0,     /* the equivariant start system where a cyclic subgroup allows it, else
                              the monodromy if the group has at least SYM_MONODROMY_MIN_GROUP
                              projectively distinct elements, else every path (the plain solver) */
    KIN__SYM_MONODROMY = 1 /* the monodromy always (tests compare the two) */
};
/* The monodromy costs about 12 plain paths per orbit (4 loop paths and
 * the leg to Q, each step ~2.5x a plain step; docs/performance.md): below
 * this group order tracking all 2^s paths is faster. */
enum { SYM_MONODROMY_MIN_GROUP = 12 };
/* kin_quadrics_homotopy_sym by the given route */
int kin__quadrics_homotopy_sym_route(int route, int m, int s, const double *Q, int ngroup, const double *R,
                                     const kin_homotopy_options *opt, double *betas, int maxsol, int *nsol,
                                     int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *sinfo,
                                     char *err, size_t errlen);

/* The equivariant route (homotopy_sym_equi.c): if a cyclic subgroup of G
 * acts by permutations (homotopy_equi.h), solve with one total-degree path
 * per orbit of start roots and *used = 1; else *used = 0 and nothing is
 * written. H0: the caller's scaled problem (its Qr). Results as
 * kin_quadrics_homotopy_sym's (si: group, orbits, found, final_paths).
 * KIN_OK, KIN_ECANCELLED, KIN_ENOMEM, KIN_ELAPACK_*. */
int kin__sym_equi_solve(const hom_solver *H0, const sym_group *G, const kin_homotopy_options *o, double *betas,
                        int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *si,
                        int *used);

/* The plain route (homotopy_sym_equi.c): all 2^s paths of H's system, as
 * kin_quadrics_homotopy_ex, with si filled (orbits = 2^s, no monodromy). */
int kin__sym_plain_solve(hom_solver *H, const sym_group *G, const kin_homotopy_options *o, double *betas,
                         int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *si);

#endif /* KIN_HOMOTOPY_SYM_H */
