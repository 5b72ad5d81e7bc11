/* libkin: kinematic paths and bifurcations of pin-jointed bar assemblies.
 *
 * Umbrella header. The conventions (coordinate order, matrix layout,
 * ownership, threads) are stated once, in libkin/kin_assembly.h. */
#ifndef LIBKIN_H
#define LIBKIN_H

#include "libkin/kin_export.h"
#include "libkin/kin_version.h"
#include "libkin/kin_status.h"
#include "libkin/kin_assembly.h"
#include "libkin/kin_progress.h"
#include "libkin/kin_path.h"
#include "libkin/kin_models.h"
#include "libkin/kin_branch.h"
#include "libkin/kin_locate.h"
#include "libkin/kin_follow.h"
#include "libkin/kin_io.h"
#include "libkin/kin_symmetry.h"
#include "libkin/kin_contact.h"

/* C linkage for C++ callers: each header above has its own guard, and
 * anything declared here goes between these lines. */
#ifdef __cplusplus
extern "C" {
#endif

#ifdef __cplusplus
}
#endif

#endif /* LIBKIN_H */
