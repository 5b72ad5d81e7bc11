/* libkin: symbol export control.
 *
 * The library is built with hidden visibility by default; only declarations
 * marked KIN_API are exported from the shared object. KIN_BUILDING is defined
 * only while compiling the library itself. */
#ifndef KIN_EXPORT_H
#define KIN_EXPORT_H

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#  if defined(KIN_STATIC)
#    define KIN_API
#  elif defined(KIN_BUILDING)
#    define KIN_API __declspec(dllexport)
#  else
#    define KIN_API __declspec(dllimport)
#  endif
#elif defined(__GNUC__) && __GNUC__ >= 4
#  define KIN_API __attribute__((visibility("default")))
#else
#  define KIN_API
#endif

#ifdef __cplusplus
}
#endif

#endif /* KIN_EXPORT_H */
