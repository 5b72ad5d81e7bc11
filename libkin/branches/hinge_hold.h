/* Private to libkin/branches/: held hinges (hinge_hold.c,
 * kin_follow_options.hold_hinges), called by follow.c. */
#ifndef KIN_HINGE_HOLD_H
#define KIN_HINGE_HOLD_H

#include "model/internal.h"

/* The rate at which hinge h's angle opens on side (+-1) along the joint
 * velocity v (3 nj) at the handle's point: radians per unit of v; < 0 into
 * penetration. */
double kin__hold_rate(const kin_assembly *a, int h, int side, const double *v);

/* The held analysis at the handle's point (its dense analysis current):
 * the number of near-zero internal mechanisms along which no held hinge's
 * angle moves (rate at most rate_tol), -1 where it cannot be told; with
 * dir (nf) and a count >= 1, the first of them (unit, largest component
 * positive). No allocation (the hinges' workspace). */
int kin__hold_analyse(kin_assembly *a, double rate_tol, double *dir);

/* At a follow's start (after check_start): the holds of this
 * configuration, and the direction decided on them: *use_dir the direction
 * to follow (dir, or the held motion; *at_bif set where it leaves as out
 * of a bifurcation), *event HELD_RIGID where no motion is left (nothing
 * to follow), *reopened the holds the direction releases. A status
 * (KIN_EINVAL: dir presses a held hinge through; KIN_EBIFURCATION: several
 * held motions and no dir). */
int kin__hold_start(kin_assembly *a, const kin_follow_options *o, const double *dir, int *at_bif,
                    const double **use_dir, int *event, int *reopened);

/* At a follow's end (the end point analysed): a reopening located becomes
 * HINGE_REOPENED; hinges closed at a contact or a bifurcation are held
 * (a contact becomes HINGE_CLOSED or HELD_RIGID); info's hold fields. */
void kin__hold_finish(kin_assembly *a, const kin_follow_options *o, kin_follow_info *info);

/* The held motion the follow left along is no path of the structure,
 * either sign (follow.c): the held structure is rigid at second order. */
void kin__hold_mark_rigid(kin_assembly *a);

/* A follow that ends before following (or never armed): its holds are
 * watched no more; returns the number held. */
int kin__hold_abort(kin_assembly *a);

#endif /* KIN_HINGE_HOLD_H */
