/* Private: what the location layer (paper Section 4) offers the layers
 * above it (branches/follow.c). Not installed. */
#ifndef KIN__LAYER_LOCATE_H
#define KIN__LAYER_LOCATE_H

#include "model/internal.h"

/* kin_locate_next with a hook called after every accepted following step
 * (before the detectors look at it): KIN__HOOK_STOP stops following there
 * as if max_steps were reached (KIN_ENOTFOUND, event NONE, the assembly at
 * that point); KIN__HOOK_STOP_IDLE the same once the detectors have looked
 * at that step, if they fired on nothing and hold no bracket back (the fast
 * method's look-ahead past a sign change); 0 goes on. hook NULL:
 * kin_locate_next itself. */
enum { KIN__HOOK_GO = 0, KIN__HOOK_STOP = 1, KIN__HOOK_STOP_IDLE = 2 };
typedef int (*kin__step_hook)(void *user, const kin_assembly *a);
int kin__locate_hooked(kin_assembly *a, const kin_locate_options *opt, kin_locate_info *info, kin__step_hook hook,
                       void *hook_user);

#endif /* KIN__LAYER_LOCATE_H */
