/* libkin: progress reports and cancellation of long calls.
 *
 * Calls that can run for seconds or hours (the complete solver
 * kin_quadrics_homotopy_ex, kin_locate_next, kin_branch_paths, the SVD of
 * kin_analyse on a large model) report
 * progress through a callback of this type and stop when it asks them to:
 *   - it is called only from the thread that made the library call (worker
 *     threads of the complete solver never call it), so it may use that
 *     thread's state, e.g. a Python interpreter's pending signals;
 *   - done and total are in units of work the call defines (paths, steps);
 *     0 <= done <= total, done never decreases, total never decreases (it
 *     grows when the call finds more work, e.g. paths tracked again);
 *   - the first call comes before any work (done = 0) and, on success, the
 *     last one has done == total (its return value is then ignored); in
 *     between it is called at least every ~0.1 s of work where a unit of work
 *     is shorter than that (the complete solver: every 50 ms; the handle
 *     loops: after every step);
 *   - a nonzero return cancels the call: it stops at the next boundary (a
 *     path, a step) and returns KIN_ECANCELLED, its outputs in the state its
 *     contract describes for that code;
 *   - it must not call libkin on the handle being worked on. */
#ifndef KIN_PROGRESS_H
#define KIN_PROGRESS_H

#include "kin_export.h"
#include "kin_assembly.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Progress callback: nonzero return = cancel. user is the caller's pointer,
 * passed through unchanged. */
typedef int (*kin_progress_fn)(void *user, double done, double total);

/* Install (fn != NULL) or remove (fn == NULL) the progress callback of the
 * handle's long loops: kin_locate_next (done: path-following steps plus
 * forward calculations while locating, total: max_steps + max_iter; a
 * successful call ends with done = total) and kin_branch_paths (done:
 * directed paths followed, fractions for the one under way; total: their
 * number) and kin_analyse (done: 0, 1, 2 of total 2 around its SVD). The handle stores fn and user and does not own user. A clone
 * (kin_assembly_clone) starts without a callback: user is often per-call
 * state, and a clone may be used on another thread. Returns KIN_OK,
 * KIN_ENULL (a == NULL). */
KIN_API int kin_set_progress(kin_assembly *a, kin_progress_fn fn, void *user);

#ifdef __cplusplus
}
#endif

#endif /* KIN_PROGRESS_H */
