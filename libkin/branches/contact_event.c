/* Contact as an event of kin_follow_event (kin_contact.h,
 * kin_set_contact_events; docs/contact.md). follow.c calls three functions:
 * arm at the start, check after every accepted step, locate when a check
 * stopped the follow. The location bisects the last step's chord in free
 * coordinates; each trial point is brought back onto the path by kin_relax
 * (a trial whose relaxation fails counts as not located further: the bracket
 * stays where it is) and tested by kin_clearance with a cutoff just above
 * zero. No allocation: the workspace is the contact record's (made by
 * kin_set_contact_events). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "branches/contact_event.h"
#include "contact/contact_internal.h"

/* Contact at the handle's configuration: clearance <= 64 eps x the RMS rest
 * length (two segments that cross in a plane, or a bar through a panel, are
 * at distance zero only up to rounding); the cutoff resolves nothing else */
static int in_contact(kin_assembly *a, double *clearance, int *parts, double *points)
{
    double c = INFINITY, eps = 64.0 * DBL_EPSILON * a->rms_length;
    if (kin_clearance(a, NULL, nextafter(eps, INFINITY), &c, parts, points) != KIN_OK) return 0;
    if (clearance) *clearance = c;
    return c <= eps;
}

void kin__contact_event_arm(kin_assembly *a)
{
    struct kin_contact *ct = a->ct;
    if (!ct) return;
    ct->ev_have = 0;
    ct->ev_armed = ct->ev_on && !in_contact(a, NULL, NULL, NULL);
}

int kin__contact_event_check(kin_assembly *a, const double *xprev)
{
    struct kin_contact *ct = a->ct;
    if (!ct || !ct->ev_armed || !in_contact(a, NULL, NULL, NULL)) return 0;
    memcpy(ct->ev_prev, xprev, sizeof(double) * (size_t)a->nf);
    return 1;
}

int kin__contact_event_locate(kin_assembly *a)
{
    struct kin_contact *ct = a->ct;
    int nf = a->nf, n = a->nj * a->dim;
    double *x0 = ct->ev_prev, *x = ct->ev_x, *x1 = ct->ev_x + nf, *hi_xyz = ct->ev_xyz, *trial = ct->ev_xyz + n;
    memcpy(hi_xyz, a->xyz, sizeof(double) * (size_t)n);
    /* the chord: x0 (free of contact) to the current point (in contact) */
    kin__gather(a, a->xyz, x1);
    double h = 0.0;
    for (int i = 0; i < nf; ++i) h += (x1[i] - x0[i]) * (x1[i] - x0[i]);
    h = sqrt(h);
    double lo = 0.0, hi = 1.0, goal = ct->ev_tol * a->rms_length;
    int rc = KIN_OK;
    for (int it = 0; it < 200 && (hi - lo) * h > goal; ++it) {
        double mid = 0.5 * (lo + hi);
        for (int i = 0; i < nf; ++i) x[i] = x0[i] + mid * (x1[i] - x0[i]);
        memcpy(trial, hi_xyz, sizeof(double) * (size_t)n);
        kin__scatter(a, x, trial);
        if (kin_set_coords(a, trial) != KIN_OK || kin_relax(a, 30, NULL) != KIN_OK) break;
        if (in_contact(a, NULL, NULL, NULL)) {
            hi = mid;
            memcpy(hi_xyz, a->xyz, sizeof(double) * (size_t)n);
        } else {
            lo = mid;
        }
    }
    /* the assembly at the first point in contact found */
    if ((rc = kin_set_coords(a, hi_xyz)) != KIN_OK) return rc;
    ct->ev_bracket = (hi - lo) * h;
    ct->ev_have = in_contact(a, &ct->ev_clearance, ct->ev_parts, ct->ev_points);
    ct->ev_armed = 0;
    return KIN_OK;
}
