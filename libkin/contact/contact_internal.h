/* Private to libkin/contact/: the contact workspace and the exact distance
 * tests (distance.c), shared with branches/contact_event.c; what the
 * clearance's own files share is clearance.h. Points are 3-vectors (2D
 * models have z = 0). */
#ifndef KIN_CONTACT_INTERNAL_H
#define KIN_CONTACT_INTERNAL_H

#include "model/internal.h"

/* Separating axes of a primitive's own (a triangle: its normal and the
 * in-plane normals of its sides; a bar: four directions across it) */
#define KIN__OWN_AXES 4

/* Primitives per leaf of the bounding-volume tree at most */
#define KIN__LEAF_MAX 8

/* A node of the bounding-volume tree: a box (lo[0..2], hi[0..2]) and two
 * slabs across x + y and x - y (lo[3..4], hi[3..4]: the projections on
 * (1, 1, 0) and (1, -1, 0)), floats rounded outward, so they contain the
 * double ones; and either two children (left,
 * right) or, for a leaf (left = -1), a run (start, count) of the primitives
 * in tree order whose boxes and joints are leaf block `right` (leaf blocks
 * numbered in pre-order, which is the order of start). Nodes are in
 * pre-order: a node's children have larger indices than it has. */
typedef struct kin__bvh_node {
    float lo[5], hi[5]; /* x, y, z and the slabs across x + y, x - y */
    int left, right, start, count;
} kin__bvh_node;

/* A leaf's primitives side by side (one lane each, lane i = primitive
 * start + i), so that a primitive is tested against all of another leaf's
 * in straight-line code (lanes.h, near_lanes and adjacent_lanes): their
 * boxes grown by their radii, floats rounded outward, and their joints in
 * tree order (a bar's third repeats its second), the joints' points and
 * the radii in float. Lanes past the leaf's count: empty boxes, joints -1,
 * points and radii 0. The slabs across x + y and x - y bound a long part
 * tilted in a nearly flat sheet (a sail) far tighter than its box does.
 * The leaf's own axis w (a unit vector across its parts: in the plane of
 * its triangles, across their long sides; tree.c, leaf_axis) and each
 * lane's interval of w . p over its points (without the radius) follow the
 * leaf's orientation, which no fixed direction does: a row is tested
 * against another leaf's lanes projected on it (orient_lanes). 816 bytes. */
typedef struct kin__leafsoa {
    float lo[5][KIN__LEAF_MAX], hi[5][KIN__LEAF_MAX]; /* x, y, z, x + y, x - y */
    int v[3][KIN__LEAF_MAX];
    float p[3][3][KIN__LEAF_MAX]; /* joint q's coordinate k, rounded to nearest */
    float r[KIN__LEAF_MAX];       /* radius, rounded up */
    float olo[KIN__LEAF_MAX], ohi[KIN__LEAF_MAX]; /* the lanes' intervals on w */
    float w[4];                   /* the leaf's axis (w[3]: 0); 0: none */
} kin__leafsoa;

/* A primitive as the exact tests use it, stored in tree order (the walk
 * reads neighbours from neighbouring memory); its joints are numbered in
 * tree order too (pts). 24 bytes. */
typedef struct kin__leafprim {
    float r;            /* radius, rounded up (the exact test reads lr) */
    int part;           /* bar k or nb + panel */
    int v[3];           /* joints in tree order (a bar's third is -1) */
    int own;            /* 1: v are all the joints of its part (a bar, a
                           triangle panel): adjacency compares v */
} kin__leafprim;

/* A bar in the sweep of contact_event.c's crossing check: its box's low x */
typedef struct kin__sweepkey {
    double x;
    int k;
} kin__sweepkey;

struct kin_contact {
    /* the model: panels (CSR) and thicknesses (entries < 0: the default) */
    int np;
    int *poff;         /* np + 1 */
    int *pj;           /* poff[np] */
    double t0;         /* model-wide thickness */
    double *rbar;      /* nb bar radii, < 0: t0/2 */
    double *tpan;      /* np panel thicknesses, < 0: t0 */
    /* the workspace of kin_clearance: primitives are the bars and the fan
     * triangles of the panels */
    int nprim;
    int *prim_part;    /* part of each primitive (bar k, or nb + panel) */
    int *prim_v;       /* 3 joints per primitive (a bar's third is -1) */
    double *prim_r;    /* radius (half thickness) of each primitive */
    double *cen;       /* 15 per primitive, for the split: the centres of its
                          extents along x, y, z, x + y, x - y, then the
                          extents' low ends and high ends (with the radius) */
    int *scratch;      /* 2 nprim: the split's trials */
    double *skey;      /* 2 per primitive: its centre on the node's own
                          directions, for the split */
    int *order;        /* nprim primitive indices, grouped by leaf */
    kin__bvh_node *node; /* up to 2 * (nprim / ((LEAF_MAX + 1) / 2) + 1) */
    int nnode;         /* nodes of the current tree */
    kin__leafprim *lp;   /* nprim: the primitives in tree order (order[]) */
    kin__leafsoa *leaf;  /* the leaves' boxes and joints, one block per leaf node */
    int nleaf;         /* leaf blocks of the current tree */
    double *lr;        /* nprim: their radii, in tree order */
    int *jpos;         /* nj: tree-order number of each joint */
    int tree_ok;       /* the tree (order, node, lp, leaf, jpos) exists: refit it */
    int ax_next;       /* the next leaf whose axis the refit makes anew */
    int fresh;         /* built since the last call: its quality is the reference */
    double quality0;   /* the refitted tree's quality measure just after its build */
    double rmax;       /* the largest radius */
    int seed[2];       /* tree positions of the last smallest pair found, or -1 */
    /* each primitive's own separating axes (walk.c, own_axes), made when
     * the walk first needs them in a call: KIN__OWN_AXES unit axes and the
     * primitive's interval on each (5 floats an axis), by tree position */
    float *ax;           /* 5 * KIN__OWN_AXES per primitive */
    unsigned *ax_call;   /* the call that made them */
    unsigned call;       /* calls of kin_clearance (never 0) */
    int *stack;        /* 2 * stack_cap node indices of the pair traversal */
    double *sgap;      /* stack_cap: the squared box gap of each pair on the stack */
    int stack_cap;
    double *pts;       /* nj*3 points of the configuration, joints in tree order */
    /* the near-pair list (near_list.c): leaf node pairs
     * (u, v) whose boxes were within vl_cut + their skins at the joints
     * vl_x0 */
    int *vl;           /* 2 * vl_cap */
    int vl_cap, vl_n;
    int vl_ok;         /* the list holds for the current tree */
    unsigned long vl_used; /* checks the list has served (tests read it) */
    double vl_nocut;   /* no list for cutoffs at or above (one overflowed) */
    double vl_cut;     /* the cutoff it was made for */
    double *vl_sk;     /* per node: its skin (a leaf's), or its leaves' largest */
    double *vl_dl;     /* per node: its leaf's largest move at the last check of the list */
    double *vl_dj;     /* nj scratch: each joint's move since vl_x0 */
    double *vl_x0;     /* 3 nj: the joints (tree order) when the list was made */
    /* contact as an event of kin_follow_event (branches/contact_event.c) */
    int ev_on;         /* kin_set_contact_events */
    double ev_tol;     /* location tolerance, a fraction of the RMS rest length */
    int ev_armed;      /* the follow's start point was free of contact */
    int ev_have;       /* a contact was located by the last follow */
    double *ev_prev;   /* nf: the point before the step that reached contact */
    double *ev_x;      /* 2*nf scratch */
    double *ev_xyz;    /* 2*nj*dim: the first point in contact found, and a trial */
    double ev_clearance, ev_bracket, ev_points[6];
    double ev_back;    /* chord length from the located point to the step's end */
    int ev_parts[4];
    /* bars (3D) that passed through each other within a step
     * (contact_event.c): each bar's box over the step, the sweep's keys,
     * the pair found (-1: none) and the sign of its orientation before */
    double *ev_box;      /* 6 per bar */
    kin__sweepkey *ev_key; /* nb */
    int ev_pair[2];
    double ev_side;
    /* bars a model marks as devices (kin_set_device_bars): 1 each, left out
     * of contact (no primitive, no crossing check); NULL: none */
    unsigned char *dev;
    /* hinges (hinge.c): two panels that share an edge, in 3D; 6 ints each
     * (i < j the edge, a and b the far joints of the fan triangles of
     * panels pa < pb holding it, pa, pb) */
    int hinge_on;       /* kin_set_hinge_contact: counted by the clearance and the event */
    int nh;
    int *hg;
    /* the tracked fold side of each hinge (branches/hinge_event.c): +1 or
     * -1, the sign sigma had while the hinge was last open and folded past
     * 90 degrees; 0 unknown (open wider than 90 degrees, or closed since
     * the follow started); valid at the configuration hg_x (nj*dim) when
     * hg_side_ok */
    signed char *hg_side;
    unsigned char *hg_c0; /* per hinge: closed at the follow's start and not yet opened */
    double *hg_x;
    int hg_armed;       /* the follow watches its hinges */
    int hg_side_ok;
    int ev_hinge;       /* the hinge that closed or passed through in the last step, or -1 */
    int ev_reopen;      /* ev_hinge is a held hinge the path opened (branches/hinge_hold.c) */
    /* held hinges (kin_follow_options.hold_hinges, branches/hinge_hold.c):
     * per hinge 0, or the side (+-1) it closed from and is held on; valid
     * at hg_x as the sides; the workspace of the held analysis (made here,
     * with the hinges: nothing is allocated while following) */
    signed char *hg_held;
    int hold_on;        /* the follow under way holds hinges (its option) */
    int hold_rigid;     /* ... and found the held motion no path (second order) */
    double *hg_ws;      /* kin__hold_ws_size doubles */
    double ev_hinge_cl; /* its signed clearance at the located point */
};

/* the held analysis looks at this many near-zero singular values at most */
#define KIN__HOLD_MAX_M 16

/* the held analysis's workspace (doubles): a basis of the near-zero
 * mechanisms (nf x (MAX_M + 6), the rigid ones first), the held hinges'
 * rates on it (nh x MAX_M), their row basis and a null vector (MAX_M x
 * (MAX_M + 1)), a direction (nf) and a velocity (3 nj) */
static inline size_t kin__hold_ws_size(const kin_assembly *a, int nh)
{
    return (size_t)a->nf * (KIN__HOLD_MAX_M + 6) + (size_t)nh * KIN__HOLD_MAX_M +
           (size_t)KIN__HOLD_MAX_M * (KIN__HOLD_MAX_M + 1) + (size_t)a->nf + 3 * (size_t)a->nj;
}

/* hinge.c: the hinges of the panels of c (a 3D model; none in 2D) into
 * c->hg, c->nh, the tracked sides forgotten; KIN_OK or KIN_ENOMEM */
int kin__hinges_make(const kin_assembly *a, struct kin_contact *c);

/* hinge.c: the hinge g (6 ints) at xyz (3D): the angle delta between its
 * panels (pi flat open, 0 folded flat), sigma the sign of the signed
 * volume of (i, j, a, b) (0 where it is zero), and the gap 2 h sin(delta /
 * 2) returned (h the smaller panel's height over the edge); pts (may be
 * NULL): the two points at h across the edge's middle on each panel */
double kin__hinge_measure(const double *xyz, const int *g, double *delta, int *sigma, double *pts);

/* hinge.c: the hinge of smallest clearance (gap less the two half
 * thicknesses) at xyz, if below cutoff and below best->value (ties: the
 * smaller pair of parts), into best; nothing when hinge contact is off */
typedef struct kin__hinge_best {
    double value, pts[6];
    int pa, pb, hinge; /* parts (nb + panel), pa < 0: none */
} kin__hinge_best;
void kin__hinge_closest(const kin_assembly *a, const struct kin_contact *c, const double *xyz, double cutoff,
                        kin__hinge_best *best);

/* Make a->ct (empty: no panels, thickness 0) if it does not exist, with the
 * free and clone calls set; KIN_OK or KIN_ENOMEM. */
int kin__contact_ensure(kin_assembly *a);

/* The closest points of segments [p0,p1] and [q0,q1] into cp, cq; returns
 * their distance. Degenerate (zero-length) segments are points. */
double kin__dist_seg_seg(const double *p0, const double *p1, const double *q0, const double *q1, double *cp,
                         double *cq);
/* The closest point of triangle (a,b,c) to p into cq; returns the distance.
 * A zero-area triangle is the union of its sides. */
double kin__dist_pt_tri(const double *p, const double *a, const double *b, const double *c, double *cq);
/* Segment [p0,p1] and triangle (a,b,c): distance (0 where they meet) and
 * closest points. */
double kin__dist_seg_tri(const double *p0, const double *p1, const double *a, const double *b, const double *c,
                         double *cp, double *cq);
/* Triangles (a0,a1,a2) and (b0,b1,b2): distance (0 where they meet) and
 * closest points. */
double kin__dist_tri_tri(const double *const A[3], const double *const B[3], double *cp, double *cq);

#endif /* KIN_CONTACT_INTERNAL_H */
