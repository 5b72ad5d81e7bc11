/* Private: what the bifurcation detector (detect.c, locate.c) shares with its three
 * locators, one file each: the fast Hermite method (locate_hermite.c),
 * Illinois on the signed test function (locate_illinois.c) and the paper's
 * quadratic (locate_paper.c). Not installed. */
#ifndef KIN_LOCATE_INTERNAL_H
#define KIN_LOCATE_INTERNAL_H

#include "model/internal.h"
#include "path/path.h"
#include "locate/locate.h"

/* Developer trace of the locators: build with -DKIN_LOCATE_TRACE. */
#ifdef KIN_LOCATE_TRACE
#include <stdio.h>
#define TRACE(...) fprintf(stderr, __VA_ARGS__)
#else
#define TRACE(...) ((void)0)
#endif

typedef struct hermite_ws hermite_ws;

typedef struct loc_ctx {
    kin_assembly *a, *prev, *work, *probe;
    kin_assembly *tb0, *tb1; /* fast method: a test-function bracket kept while looking ahead */
    const kin_locate_options *o;
    kin_locate_info *info;
    hermite_ws *hw;
    kin__step_hook hook; /* optional: may stop following after any accepted step */
    void *hook_user;
    /* the fast method gave up on a non-zero minimum of v_r: the lowest
     * v_r / v_max it saw (0 otherwise) */
    double nonzero_min;
    int lu_nodes; /* kin__locate_ws.lu_nodes */
    kin__locate_ws *ws; /* the caller's working copies, or NULL */
} loc_ctx;

/* eq. 26: the path is kept if the new tangent agrees with the old one to this |cos| */
#define KIN__PATH_KEPT_COS 0.9

/* ---- shared helpers (detect.c) ---- */
/* v_r / v_max at the analysed state a */
double kin__loc_rel(const kin_assembly *a);
/* index of the singular value that vanishes at a bifurcation, or -1 */
int kin__loc_vanishing_index(const kin_assembly *a);
/* that singular value (v_r where there is none) */
double kin__loc_vanishing_sv(const kin_assembly *a);
/* the largest of the singular values that vanish together there */
double kin__loc_group_top(const kin_assembly *a, double tol);
/* the same from singular values alone (descending, v_max = sv[0]; k the
 * vanishing index, >= 0) */
double kin__loc_group_top_sv(const double *sv, int k, double tol);
/* every vanishing singular value is at most tol * v_max */
int kin__loc_at_bifurcation(const kin_assembly *a, double tol);
/* forward calculation: dst := base moved by delta along its tangent; *used the amplitude taken */
int kin__loc_forward(loc_ctx *c, const kin_assembly *base, kin_assembly *dst, double delta, double *used);
/* progress through the caller's callback; 1 when the caller cancels */
int kin__loc_cancelled(const loc_ctx *c);
/* the paper's overshoot probe, a working copy made at its first use (a
 * clone of the handle; the caller's from then on where it gave a
 * kin__locate_ws): most locations never need it. NULL: out of memory. */
kin_assembly *kin__loc_probe(loc_ctx *c);
/* |t_x . t_y| of the two states' tangents */
double kin__loc_tangent_cos(const kin_assembly *x, const kin_assembly *y);

/* ---- the locators ---- */
/* kin__locate_hermite's answer when the vanishing singular value does not
 * turn within the bracketing step (the caller may fall back on the test
 * function) */
enum { KIN__HERMITE_NO_BRACKET = -1 };
hermite_ws *kin__hermite_alloc(const kin_assembly *a);
void kin__hermite_free(hermite_ws *h);
/* 2 * njoints * dim doubles of h the detector may use between locator calls */
double *kin__hermite_scratch(hermite_ws *h);
int kin__locate_hermite(loc_ctx *c);
/* the vanishing singular value v of st, a point with square LU-mode factors
 * and no SVD, and its slope *sl along dir * t, from those factors (subspace
 * iteration, in h's workspace); 0 where the iteration does not converge */
int kin__hermite_lu_vanishing(hermite_ws *h, kin_assembly *st, double dir, double *v, double *sl);
/* the corank-k Newton (locate_corank.c): its workspace, made with the
 * Hermite one, for groups of at most CORANK_MAX_Q singular values: as many
 * as the Hermite method's groups (MAX_GROUP + 1 in locate_hermite.c). It was
 * 8, and paths returning to the hexagonal sail's flat state (15 vanishing
 * together) then stopped 2e-6..2e-5 short of it as near misses */
enum { CORANK_MAX_Q = 32 };
typedef struct kin__corank_ws kin__corank_ws;
kin__corank_ws *kin__corank_alloc(const kin_assembly *a);
void kin__corank_free(kin__corank_ws *cw);
/* one Gauss-Newton step on the k x k block of the group (the lowest
 * non-zero singular value of the analysed a and the grp above it) within
 * its null directions and the tangent: x (a's free coordinates) moved, the
 * step's max-norm in *step. A status. */
int kin__corank_step(const kin_assembly *a, int grp, kin__corank_ws *cw, double *x, double *step);
/* Illinois on tau(delta) over [0, hi] from c->prev (tau_lo there) */
int kin__locate_illinois(loc_ctx *c, double hi, double tau_lo, double tau_hi);
/* the paper's quadratic (eq. 23-26) from the history (hl, hv) of nh points */
int kin__locate_paper(loc_ctx *c, double *hl, double *hv, int nh, double step);

#endif /* KIN_LOCATE_INTERNAL_H */
