/* libkin: built-in example structures (the paper's examples, made concrete in
 * docs/models.md). Each builder returns a fresh handle the caller frees with
 * kin_assembly_free(). */
#ifndef KIN_MODELS_H
#define KIN_MODELS_H

#include <stddef.h>
#include "kin_export.h"
#include "kin_assembly.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Three-bar linkage states (paper Figure 1, Section 5). */
enum kin_threebar_state {
    KIN_THREEBAR_RA = 0, /* J1 = (-1,0), J2 = (0,0) */
    KIN_THREEBAR_RB = 1, /* J1 = ( 1,0), J2 = (0,0) */
    KIN_THREEBAR_RC = 2  /* J1 = ( 1,0), J2 = (2,0) */
};

/* The planar three-bar linkage: joints J1, J2 (free), S1 = (0,0), S2 = (1,0)
 * (fixed), in that order; bars S1-J1, J1-J2, J2-S2 of length 1. Rows of H:
 * J1x, J1y, J2x, J2y. Returns KIN_OK, KIN_ENULL, KIN_EINVAL (state), or a
 * creation error. */
KIN_API int kin_model_threebar(int state, kin_assembly **out);

/* Supports of a sail's hub. */
enum kin_sail_support {
    KIN_SAIL_SUPPORT_AUTO = 0,     /* OPPOSITE for n = 4, CENTRE otherwise */
    KIN_SAIL_SUPPORT_OPPOSITE = 1, /* V0 and V(n/2) fully fixed; n even */
    KIN_SAIL_SUPPORT_CENTRE = 2    /* V0, V2, ... fixed; V1, V3, ... tied by
                                      spokes to a centre node C that moves in
                                      z only; n even */
};

/* Which diagonal braces the quadrilateral inner_k, outer_k, outer_k+1,
 * inner_k+1 of every loop. */
enum kin_sail_diagonal {
    KIN_SAIL_DIAG_FORWARD = 0, /* inner_k - outer_k+1 (the paper's) */
    KIN_SAIL_DIAG_BACKWARD = 1 /* outer_k - inner_k+1 */
};

/* The wrapping-fold solar-sail family: a regular n-gon hub of side `side`,
 * vertex V_k at angle -pi/2 - pi/n + 2*pi*k/n from the centre; from V_k a
 * straight fold perpendicular to hub edge V_k-1 V_k, pointing away from the
 * hub, carrying one node per loop at cumulative distances widths[0],
 * widths[0]+widths[1], ...; per loop and per k a fold segment, a ring bar and
 * a diagonal. All nodes start flat (z = 0). */
typedef struct kin_sail_params {
    size_t size; /* sizeof(kin_sail_params) as the caller compiled it (docs/abi.md) */
    int n_sides;          /* hub sides n, 3..64 */
    int n_loops;          /* loops of triangles, 1..64 */
    double side;          /* hub side length a, 1e-140..1e140 */
    const double *widths; /* n_loops loop widths, each 1e-140..1e140 and their sum
                             <= 1e140, or NULL: a*tan(pi/n) each */
    int support;          /* enum kin_sail_support */
    int diagonal;         /* enum kin_sail_diagonal */
} kin_sail_params;

/* Defaults: side 1, widths NULL, KIN_SAIL_SUPPORT_AUTO, forward diagonals.
 * (n, k) = (4, 1) is the paper's square-hub sail, (6, 2) the hexagonal one. */
/* Fill *p with the defaults above and n_sides, n_loops, for a struct of `size` bytes: pass
 * sizeof(kin_sail_params) (the macro kin_sail_params_default below does). size must be the sizeof
 * of one of kin_sail_params's published layouts (docs/abi.md); then exactly size bytes
 * are written (p->size = size) and KIN_OK is returned; otherwise nothing is
 * written and KIN_EINVAL is returned. KIN_ENULL if p is NULL. */
KIN_API int kin_sail_params_init(kin_sail_params *p, size_t size, int n_sides, int n_loops);

/* The same with size = sizeof(kin_sail_params): a C or C++ host compiled with this
 * header calls kin_sail_params_init through the macro. The function itself is
 * for programs built before the macro existed: it writes only the first
 * layout (p->size = its sizeof, docs/abi.md), which is all an old program
 * can have room for. Does nothing if p is NULL. */
KIN_API void kin_sail_params_default(kin_sail_params *p, int n_sides, int n_loops);
#define kin_sail_params_default(p, n_sides, n_loops) ((void)kin_sail_params_init((p), sizeof(kin_sail_params), (n_sides), (n_loops)))

/* Joint and bar counts of the sail that p describes (either pointer may be
 * NULL). Joint order: [C if CENTRE], V0..V(n-1), loop-1 nodes 0..n-1, loop-2
 * nodes, ... Bar order: [spokes C-V1, C-V3, ...], hub edges V_k-V_k+1, then
 * per loop and per k: fold, ring, diagonal. On failure the counts are 0.
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (with the reason in errbuf of
 * kin_model_sail). */
KIN_API int kin_sail_size(const kin_sail_params *p, int *njoints, int *nbars);

/* Build the sail. errbuf (optional) receives the reason of a failure; *out
 * is NULL on failure. Returns KIN_OK, KIN_ENULL, KIN_EINVAL (parameters),
 * KIN_ENOMEM, or a creation error. */
KIN_API int kin_model_sail(const kin_sail_params *p, kin_assembly **out, char *errbuf,
                           size_t errlen);

#ifdef __cplusplus
}
#endif

#endif /* KIN_MODELS_H */
