/* Private to the clearance (kin_clearance) of libkin/contact/: what its
 * files share. A check fits the bounding-volume tree to the configuration
 * (tree.c) and asks the pair walk for the closest pair (walk.c); the walk
 * tests two leaves a row at a time against 8 lanes (lanes.h), walks only
 * the near-pair list where that holds (near_list.c), and hands the pairs
 * the lanes keep to the exact primitive tests (primitives.c, which uses
 * distance.c). Calls go one way only, so that no two files call each
 * other: contact.c -> tree.c, walk.c; walk.c -> near_list.c, primitives.c;
 * primitives.c -> distance.c. Not for branches/ (contact_internal.h is). */
#ifndef KIN_CONTACT_CLEARANCE_H
#define KIN_CONTACT_CLEARANCE_H

#include <float.h>
#include <math.h>

#include "contact/contact_internal.h"

/* the split's fixed directions (tree.c): x, y, z and the slabs' x + y,
 * x - y; c->cen holds 3 doubles a direction for each primitive */
#define KIN__SPLIT_NDIR 5
#define KIN__CEN (3 * KIN__SPLIT_NDIR)

static inline double dmin(double x, double y) { return x < y ? x : y; }
static inline double dmax(double x, double y) { return x > y ? x : y; }

/* A double bound rounded outward to float: lo down, hi up. The slack
 * (2^-23 relative, 2^-140 absolute) is more than the rounding to nearest of
 * the conversion and of the double arithmetic before it; the clamp keeps a
 * bound beyond the float range on its own side (lo <= FLT_MAX, hi >=
 * -FLT_MAX), so box gaps are never inf - inf. */
static inline float f_down(double x) { return (float)dmin(x - fabs(x) * 0x1p-23 - 0x1p-140, FLT_MAX); }
static inline float f_up(double x) { return (float)dmax(x + fabs(x) * 0x1p-23 + 0x1p-140, -FLT_MAX); }

/* a pair of parts (fa < fb, primitives qa, qb, closest points p, q) at
 * clearance d, kept as a possible tie for the name (kin__tie_name) */
typedef struct kin__tie {
    double d, p[3], q[3];
    int fa, fb, qa, qb;
} kin__tie;
#define KIN__TIES_MAX 32

/* One call's pair search (walk.c): the best pair so far (clearance best,
 * parts ba < bb, their primitives' numbers bxa, bxb, closest points bp,
 * bq), the seed pair tested first (tree positions sx, sy) and the walk's
 * float slacks. Pairs are pruned above prune = min(best + band, cutoff),
 * so every pair within band of the closest is met, and kept in ties
 * (while there is room: tie_full when not). naming: best is a fixed bound and the search keeps the smallest
 * pair (parts, then primitives) with clearance at most best, its clearance
 * in named (kin__name_pair). */
typedef struct kin__pair_search {
    kin_assembly *a;
    struct kin_contact *c;
    double best, prune, cutoff, band, named, bp[3], bq[3];
    int ba, bb, bxa, bxb, sx, sy, naming, nties, tie_full;
    kin__tie ties[KIN__TIES_MAX];
    float slack, rmax_f;
} kin__pair_search;

/* tree.c: the tree fitted to the configuration xyz (njoints*dim), its
 * joints loaded into c->pts in tree order */
void kin__tree_fit(const kin_assembly *a, struct kin_contact *c, const double *xyz);

/* walk.c: the closest pair of parts that share no joint with clearance at
 * most cutoff (w->ba < 0: none) at the points c->pts of the fitted tree,
 * meeting every pair within band of it (w->second); KIN_OK, or KIN_ERANGE
 * (kin__fail) where the walk went deeper than planned */
int kin__closest_pair(kin_assembly *a, struct kin_contact *c, double cutoff, double band, kin__pair_search *w);

/* walk.c: of the pairs of parts that share no joint with clearance at most
 * bound, the smallest pair of parts (then of primitives), whatever the walk
 * (w->ba < 0: none); its clearance in w->named. Makes no near-pair list
 * (uses one that holds). kin_clearance names its pair so, with bound its
 * closest clearance plus rounding, so that pairs tied up to rounding are
 * named the same on every machine. KIN_OK or KIN_ERANGE as above */
int kin__name_pair(kin_assembly *a, struct kin_contact *c, double bound, kin__pair_search *w);

/* walk.c: of a search's ties (w->tie_full == 0) with clearance at most
 * bound, the one kin__name_pair would name: its index, or -1 if none */
int kin__tie_name(const kin__pair_search *w, double bound);

/* near_list.c: whether the near-pair list holds at c->pts for this cutoff
 * (1), does not (0), or there is none for it (-1); a walk's list: start
 * (returns whether this walk makes one; moves: the last check computed the
 * leaves' moves, kin__near_list_holds returned 0), add a leaf pair (returns
 * 0 when the list is full: no list, nor for this cutoff or more until the
 * tree is new), done (the list holds from here) */
int kin__near_list_holds(struct kin_contact *c, int nj, double cutoff);
int kin__near_list_start(struct kin_contact *c, double cutoff, int moves);
int kin__near_list_add(struct kin_contact *c, int u, int v, double cutoff);
void kin__near_list_done(struct kin_contact *c, double cutoff, int nj);

/* primitives.c: parts pa and pb share a joint (or are one part); a cheap
 * bound shows primitives Lp and Lq (radii sum rr) apart by more than best;
 * the exact clearance of the primitives at tree positions x, y and their
 * closest points */
int kin__adjacent_parts(const kin_assembly *a, int pa, int pb);
int kin__prim_far(const struct kin_contact *c, const kin__leafprim *Lp, const kin__leafprim *Lq, double rr,
                  double best);
double kin__prim_clearance(const struct kin_contact *c, int x, int y, double *cp, double *cq);

#endif /* KIN_CONTACT_CLEARANCE_H */
