/* Private to libkin/branches/: contact as an event of kin_follow_event
 * (contact_event.c; the setting is kin_set_contact_events, kin_contact.h). */
#ifndef KIN_CONTACT_EVENT_H
#define KIN_CONTACT_EVENT_H

#include "model/internal.h"

/* At the start of a follow: forget the last contact, and watch for one only
 * if contact events are on and the start point is free of contact. */
void kin__contact_event_arm(kin_assembly *a);

/* After an accepted step (the assembly at its new point; xprev the free
 * coordinates of the point before it): 1 if contact events are watched and
 * the new point is in contact (the step is kept for the location), else 0. */
int kin__contact_event_check(kin_assembly *a, const double *xprev);

/* After the follow stopped at a contact: locate its first point along the
 * last step (kin_set_contact_events' tolerance), leave the assembly there
 * and keep the parts for kin_last_contact. A status (KIN_OK, or what
 * kin_set_coords / kin_clearance returned). */
int kin__contact_event_locate(kin_assembly *a);

/* After kin__contact_event_locate: how much shorter the path is to the
 * located point than to the end of the last step (along its chord). */
double kin__contact_event_back(const kin_assembly *a);

/* However a follow ended: keep the hinges' tracked sides with the
 * configuration reached (kin_hinge_sides). */
void kin__contact_event_finish(kin_assembly *a);

#endif /* KIN_CONTACT_EVENT_H */
