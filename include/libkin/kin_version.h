/* libkin: version. CMake reads the numbers below, so this is the one place
 * the version (and the ABI version) is written. */
#ifndef KIN_VERSION_H
#define KIN_VERSION_H

#include "kin_export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define KIN_VERSION_MAJOR 0
#define KIN_VERSION_MINOR 3
#define KIN_VERSION_PATCH 0
#define KIN_VERSION_NUMBER (KIN_VERSION_MAJOR * 10000 + KIN_VERSION_MINOR * 100 + KIN_VERSION_PATCH)
#define KIN_VERSION_STRING "0.3.0"

/* ABI version: the N of the shared library's soname libkin.so.N. It changes
 * only when the ABI changes incompatibly (docs/abi.md); the release version
 * above changes with every release. CMake reads it from here too. */
#define KIN_ABI_VERSION 1

/* Version of the library actually linked, as KIN_VERSION_NUMBER.
 * Compare with KIN_VERSION_NUMBER to detect a header/library mismatch. */
KIN_API int kin_version_number(void);

/* Version of the library actually linked, as "MAJOR.MINOR.PATCH".
 * Returns a static string; never NULL. */
KIN_API const char *kin_version_string(void);

#ifdef __cplusplus
}
#endif

#endif /* KIN_VERSION_H */
