/* Private: shared by the files of the branch layer (branches.c, follow.c).
 * Not installed. */
#ifndef KIN_BRANCHES_INTERNAL_H
#define KIN_BRANCHES_INTERNAL_H

#include "model/internal.h"

/* Leave a bifurcation along dir (nf entries): choose it
 * (kin_path_set_direction) and take one step of `fraction` x the largest
 * step; *cos receives the cosine between that step's chord and dir. Returns
 * the status of the two calls (a failed step leaves the point unchanged, the
 * direction chosen). */
int kin__leave_bifurcation(kin_assembly *a, const double *dir, double fraction, kin_step_info *info, double *cos);

#endif /* KIN_BRANCHES_INTERNAL_H */
