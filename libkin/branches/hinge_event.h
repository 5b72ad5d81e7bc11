/* Private to libkin/branches/: hinges in the contact event (hinge_event.c),
 * called by contact_event.c. */
#ifndef KIN_HINGE_EVENT_H
#define KIN_HINGE_EVENT_H

#include "model/internal.h"

/* At a follow's start (a->ct exists): watch the hinges if contact events
 * and hinge contact are on; each hinge's side from the start point, or,
 * for a hinge closed there, from the sides tracked to this configuration
 * (unknown without them). */
void kin__hinge_event_arm(kin_assembly *a);

/* After an accepted step: 1 with ct->ev_hinge set if a hinge closed or
 * passed through flat-folded (the step kept for the location), else 0. */
int kin__hinge_event_check(kin_assembly *a);

/* After a step that met no contact: the sides move on to the new point. */
void kin__hinge_event_advance(kin_assembly *a);

/* The location's test at the handle's point: the hinge that stopped the
 * follow is closed or through, on the side it was tracked on. */
int kin__hinge_event_reached(const kin_assembly *a);

/* Hinge h's clearance at xyz, negative by its gap where it is through
 * flat-folded from side (+-1; 0: unknown, the gap as it is). */
double kin__hinge_signed_clearance(const kin_assembly *a, const double *xyz, int h, int side);

/* At a follow's end: keep the sides with the configuration reached. */
void kin__hinge_event_finish(kin_assembly *a);

#endif /* KIN_HINGE_EVENT_H */
