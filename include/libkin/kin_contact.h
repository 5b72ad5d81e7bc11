/* libkin: parts that can touch. Panels (faces), thicknesses, and the
 * clearance between parts that do not share a joint (docs/contact.md).
 *
 * PARTS. Every bar is a part (a segment between its joints; with a radius r
 * it is a capsule, the points within r of the segment). A model may also
 * carry panels: each panel is a loop of 3 or more distinct joints (as FOLD's
 * faces_vertices), taken as the fan of triangles (j0, j_i, j_i+1) from its
 * first joint (exact for planar convex panels; a non-planar panel is that
 * fan of triangles); with a thickness t it is a slab, the points within t/2
 * of the panel. In 2D a panel is the polygon in the plane (same fan).
 * Parts are numbered bars first: part p < nbars is bar p, part nbars + i is
 * panel i.
 * THICKNESS. One model-wide default thickness t0 >= 0: a bar's radius is
 * t0/2 and a panel's thickness t0 unless set part by part.
 * ADJACENCY. Two parts that share a joint (a bar and a panel it borders, two
 * panels with a common edge or corner, two bars at a joint) are not
 * compared as parts; two panels on a common edge are a hinge, seen by its
 * angle (HINGES below). Bars marked as devices are no parts (DEVICES).
 * Two parts whose exact distance is within 256 DBL_EPSILON x their largest
 * |coordinate| of zero touch (distance 0): a bar crossing a panel in its
 * plane is in contact, not 1e-17 away.
 * CLEARANCE of two parts = the distance between their centre geometries
 * (segments, triangles) minus r_a + r_b (a panel's r = t/2). Where the
 * centre geometries intersect (a bar through a panel, two panels crossing)
 * the distance is 0 and the clearance -(r_a + r_b): with zero thickness,
 * plain intersection is clearance 0. Clearance <= 0 is contact. (It is not
 * the penetration depth of thick parts that overlap without their centres
 * meeting: there it is distance - r_a - r_b, negative.) */
#ifndef KIN_CONTACT_H
#define KIN_CONTACT_H

#include "kin_assembly.h"
#include "kin_export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The kinds of part that kin_clearance names. */
enum kin_part_kind { KIN_PART_BAR = 0, KIN_PART_PANEL = 1 };

/* The largest number of joints of one panel. */
#define KIN_PANEL_MAX_JOINTS 1024

/* Set the model's panels, replacing any it had (npanels = 0 removes them).
 *  offsets  npanels + 1 increasing offsets into joints, offsets[0] = 0:
 *           panel i is joints[offsets[i] .. offsets[i+1]-1], 3 to
 *           KIN_PANEL_MAX_JOINTS distinct joint indices in loop order.
 *  joints   offsets[npanels] joint indices 0..njoints-1.
 * Panel thicknesses are reset to the default. The workspace of
 * kin_clearance (O(nbars + triangles)) is allocated here, once.
 * Returns KIN_OK; KIN_ENULL (a, or the arrays with npanels > 0), KIN_EINVAL
 * (npanels < 0, bad offsets, a panel of fewer than 3 or repeated joints),
 * KIN_EJOINT, KIN_ENOMEM (nothing changed on any failure). */
KIN_API int kin_set_panels(kin_assembly *a, int npanels, const int *offsets, const int *joints);

/* Number of panels (0 if none), or -1 for a NULL handle. */
KIN_API int kin_npanels(const kin_assembly *a);

/* Copy the panels out: offsets (npanels + 1) and joints (offsets[npanels]
 * entries); either may be NULL (not written). Returns KIN_OK, KIN_ENULL. */
KIN_API int kin_get_panels(const kin_assembly *a, int *offsets, int *joints);

/* Set thicknesses. t_default >= 0 (finite) is the model-wide thickness;
 * bar_radius (nbars entries or NULL) the radius of each bar, panel_thickness
 * (npanels entries or NULL) the thickness of each panel; an entry < 0 (or a
 * NULL array) means "the default" (t_default/2 for a bar, t_default for a
 * panel). Allocates the clearance workspace if not yet made.
 * Returns KIN_OK, KIN_ENULL, KIN_EGEOM (a non-finite value or t_default < 0
 * or > 1e150), KIN_ENOMEM (nothing changed on failure). */
KIN_API int kin_set_thickness(kin_assembly *a, double t_default, const double *bar_radius,
                              const double *panel_thickness);

/* Read thicknesses back: *t_default (0 unless set), and the effective
 * radius of each bar and thickness of each panel (defaults resolved); any
 * output may be NULL. Returns KIN_OK, KIN_ENULL. */
KIN_API int kin_get_thickness(const kin_assembly *a, double *t_default, double *bar_radius,
                              double *panel_thickness);

/* 1 if the model carries panels or any nonzero thickness (the parts can
 * touch in a way a bare framework's centre lines would not show), 0 if not,
 * -1 for NULL. */
KIN_API int kin_has_contact_model(const kin_assembly *a);

/* The smallest clearance between two parts that share no joint, at the
 * configuration xyz (njoints*dim, joint-major; NULL = the handle's current
 * one), if it is below cutoff (INFINITY: the smallest, wherever it is; a
 * finite cutoff, such as a contact margin, lets the tree skip every pair
 * that is at least that far apart, which is what makes a check per step
 * cheap). Writes:
 *  clearance  the smallest clearance (see CLEARANCE above); +INFINITY when
 *             no pair is below cutoff (or every pair is adjacent).
 *  parts      (may be NULL) 4 ints: kind and index of the first part, kind
 *             and index of the second (enum kin_part_kind; index among the
 *             bars or among the panels); -1s when clearance is +INFINITY.
 *  points     (may be NULL) 2*dim doubles: the closest point on the first
 *             part's centre geometry, then on the second's (equal when they
 *             intersect).
 * Exact up to rounding (segment-segment, segment-triangle and
 * triangle-triangle distances); a bounding-volume tree over bars and panel
 * triangles, built at the first call and refitted to each later
 * configuration in O(n) (built again when it has grown loose), prunes
 * pairs. Of the pairs within rounding of the smallest clearance (at most
 * 4 DBL_EPSILON x the largest |coordinate| above it), the smallest pair of
 * parts (first, then second) is named, with the points of its smallest
 * pair of primitives (bars, then panels' fan triangles, in order), whatever
 * the calls before, the tree and the last bits of xyz; clearance is the
 * smallest itself. (Naming costs a second, bounded walk, only when parts
 * or points is given.)
 * No allocation (the workspace is made by kin_set_panels or
 * kin_set_thickness, or here, the first time, for a model that has
 * neither).
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (cutoff NaN), KIN_EGEOM (a
 * non-finite coordinate, or |x| > 1e150, the range kin_assembly_create
 * accepts), KIN_ENOMEM (first call only). */
KIN_API int kin_clearance(kin_assembly *a, const double *xyz, double cutoff, double *clearance, int *parts,
                          double *points);

/* Contact as an event of kin_follow_event (kin_follow.h): on != 0 makes
 * every later follow of this handle stop at the first point of its path
 * where two parts that share no joint have clearance <= 0, with event
 * KIN_FOLLOW_CONTACT, provided the follow's start point is free of contact
 * (a start in contact is followed as before). Contact here is clearance
 * <= 64 DBL_EPSILON x the RMS rest length (segments that cross in a plane,
 * or a bar through a panel, are at distance zero only up to rounding). The
 * check is made at each accepted step: two zero-thickness bars in 3D that
 * pass through each other touch only at an instant and can be missed
 * between two steps (give them a radius to catch it); parts that overlap
 * over an interval of the path shorter than a step can be missed too. The contact is located along
 * the path by bisection of the last step's chord, each trial point brought
 * back onto the path by kin_relax, until the bracket is at most tol x the
 * RMS rest length (free coordinates); the assembly is left at the first
 * point in contact found (its path state reset, as by kin_relax). Off by
 * default (nothing changes for a handle that never calls this). A clone
 * keeps the setting. With hinge contact on (HINGES below), the follow also
 * stops where a hinge closes (its clearance <= 0 on the side it was
 * tracked on) or passes through flat-folded (its fold side changes while
 * it is folded past 90 degrees), located as any contact; a hinge closed at
 * the start (its gap at most 1e-6 x the RMS rest length) is watched from
 * where it opens, on the side it was tracked on by the follow that
 * reached the start (kin_hinge_sides), else on the side it opens to. Returns KIN_OK, KIN_ENULL, KIN_EINVAL (tol not in
 * (0, 1]), KIN_ENOMEM. */
KIN_API int kin_set_contact_events(kin_assembly *a, int on, double tol);

/* The contact the last follow located (event KIN_FOLLOW_CONTACT): its
 * clearance (<= 0), parts and closest points (as kin_clearance), and the
 * bracket left (free-coordinate distance between the last point free of
 * contact and the point reported). Any output may be NULL. Returns KIN_OK,
 * KIN_ENULL, KIN_ESTATE (no contact located by the last follow). */
KIN_API int kin_last_contact(const kin_assembly *a, double *clearance, int *parts, double *points, double *bracket);

/* DEVICES. Mark bars as modelling devices (a sail's spokes that hold the
 * hub's shape): they are no parts that can touch, so kin_clearance and the
 * contact event leave them out. bars: ndev bar indices (repeats allowed),
 * replacing any marked before (ndev = 0: none). The clearance workspace is
 * made again here (the panels, thicknesses and settings kept).
 * Returns KIN_OK, KIN_ENULL, KIN_EINVAL (ndev < 0 or > nbars), KIN_ERANGE
 * (a bar index out of range), KIN_ENOMEM (nothing changed on failure). */
KIN_API int kin_set_device_bars(kin_assembly *a, int ndev, const int *bars);

/* The device bars: their number into *ndev and, if bars is not NULL, their
 * indices in increasing order (room for kin_nbars). KIN_OK, KIN_ENULL. */
KIN_API int kin_get_device_bars(const kin_assembly *a, int *ndev, int *bars);

/* HINGES. In 3D, two panels that share an edge (a fold line) form a hinge;
 * they share joints, so the clearance never compares them as parts. Hinge
 * h is the edge (i < j) of panels pa < pb and the third joints a, b of the
 * fan triangles of pa and pb that hold it. Its fold angle psi in (-pi, pi]
 * is 0 where the hinge lies flat open and +-pi where it is folded flat
 * (closed: the panels on each other); its sign is the sign of the signed
 * volume of (x_i, x_j, x_a, x_b) (which side the fold goes). psi is
 * continuous through flat open and jumps from pi to -pi where the hinge
 * passes through flat-folded: the panels penetrate each other there.
 * With hinge contact on (the default), kin_clearance counts each hinge as
 * the pair (panel pa, panel pb) with clearance 2 h sin(delta/2) - (t_a +
 * t_b)/2, delta = pi - |psi| and h the smaller panel's height over the
 * edge (the distance of the points at h across the edge's middle on each
 * panel): a closed hinge is in contact. And the contact event
 * (kin_set_contact_events) tracks every hinge's fold side along the path
 * and stops where a hinge closes or passes through flat-folded (below).
 * No hinges in 2D. Hinges are found by kin_set_panels. */

/* Count hinges in the clearance and the contact event (on != 0, the
 * default) or not. A clone keeps the setting. KIN_OK, KIN_ENULL,
 * KIN_ENOMEM. */
KIN_API int kin_set_hinge_contact(kin_assembly *a, int on);

/* 1 if hinge contact is on, 0 if not, -1 for NULL. */
KIN_API int kin_get_hinge_contact(const kin_assembly *a);

/* Number of hinges (0 without panels or in 2D), or -1 for NULL. */
KIN_API int kin_nhinges(const kin_assembly *a);

/* The hinges: joints (4 per hinge: i, j, a, b) and panels (2 per hinge:
 * pa, pb); either may be NULL. KIN_OK, KIN_ENULL. */
KIN_API int kin_get_hinges(const kin_assembly *a, int *joints, int *panels);

/* The fold angle psi of every hinge (kin_nhinges entries, radians) at xyz
 * (NULL: the current configuration); NaN for a hinge one of whose panels
 * has zero height over the edge (such a hinge is never counted). KIN_OK, KIN_ENULL (fold NULL),
 * KIN_EGEOM (a non-finite coordinate of a hinge's joints). */
KIN_API int kin_hinge_angles(kin_assembly *a, const double *xyz, double *fold);

/* The fold side each hinge was tracked on by the last follow with contact
 * events (kin_nhinges entries): +1 or -1, the sign of psi while the hinge
 * was last folded past 90 degrees and open; 0 where it is unknown (open
 * wider than 90 degrees, or closed since the follow started and not yet
 * opened). A later follow from the configuration these were tracked to,
 * or one within 1e-3 x the RMS rest length of it in every coordinate (a
 * clone of it included), starts from them: a hinge closed there that opens
 * on the other side has passed through. KIN_OK, KIN_ENULL, KIN_ESTATE (no
 * follow with contact events has tracked them). */
KIN_API int kin_hinge_sides(const kin_assembly *a, int *sides);

#ifdef __cplusplus
}
#endif

#endif /* KIN_CONTACT_H */
