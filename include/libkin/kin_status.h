/* libkin: status codes.
 *
 * Every fallible call returns an int status. 0 (KIN_OK) is success; every
 * other value is one of the codes below. The list is written once, as an
 * X-macro, and the enum and the messages of kin_strerror() are both made from
 * it. Handles also keep a last-error message with detail (kin_last_error()). */
#ifndef KIN_STATUS_H
#define KIN_STATUS_H

#include "kin_export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* X(name, value, message) */
#define KIN_STATUS_LIST(X)                                                                     \
    X(KIN_OK, 0, "success")                                                                    \
    X(KIN_ENULL, 1, "a required pointer argument is NULL")                                     \
    X(KIN_EINVAL, 2, "invalid argument")                                                       \
    X(KIN_EDIM, 3, "dimension must be 2 or 3")                                                 \
    X(KIN_EJOINT, 4, "joint index out of range")                                               \
    X(KIN_ESELFBAR, 5, "bar connects a joint to itself")                                       \
    X(KIN_EDUPBAR, 6, "duplicate bar")                                                         \
    X(KIN_EGEOM, 7, "coordinate or length non-finite, out of range, or zero")                  \
    X(KIN_ENOFREE, 8, "assembly has no free coordinates")                                      \
    X(KIN_ENOMEM, 9, "out of memory")                                                          \
    X(KIN_ELAPACK_ARG, 10, "LAPACK rejected an argument (info < 0): internal error")           \
    X(KIN_ELAPACK_CONV, 11, "LAPACK factorization did not converge (info > 0)")                \
    X(KIN_ENOTCONVERGED, 12, "iteration did not converge")                                     \
    X(KIN_EPATHJUMP, 13, "step would leave the path: mechanism direction jumped")              \
    X(KIN_EBIFURCATION, 14, "assembly is at a bifurcation: choose a direction first")          \
    X(KIN_ENOMECH, 15, "assembly has no internal mechanism: it cannot move")                   \
    X(KIN_ERANGE, 16, "size or index out of range")                                            \
    X(KIN_ESTATE, 17, "operation not valid in the current state")                              \
    X(KIN_ENOTFOUND, 18, "no bifurcation located: locator gave up")                            \
    X(KIN_EGSL, 19, "GSL reported an error")                                                  \
    X(KIN_ECANCELLED, 20, "cancelled by the caller's progress callback")                       \
    X(KIN_EMULTIDOF, 21, "several internal mechanisms at a regular point: choose a direction")  \
    X(KIN_ELIMIT, 22, "problem larger than the limit set for this call")                       \
    X(KIN_EIO, 23, "file could not be opened, read or written")                                \
    X(KIN_EFORMAT, 24, "malformed model file")

#define KIN_STATUS_ENUM_ITEM_(name, value, msg) name = value,
enum kin_status { KIN_STATUS_LIST(KIN_STATUS_ENUM_ITEM_) KIN_STATUS_COUNT_ };
#undef KIN_STATUS_ENUM_ITEM_

/* Message for a status code, without a handle. Returns a static string;
 * unknown codes give "unknown status". Thread-safe. */
KIN_API const char *kin_strerror(int status);

/* Symbolic name of a status code ("KIN_EINVAL"), or "KIN_UNKNOWN". */
KIN_API const char *kin_status_name(int status);

#ifdef __cplusplus
}
#endif

#endif /* KIN_STATUS_H */
