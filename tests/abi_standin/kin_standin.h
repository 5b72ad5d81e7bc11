/* A stand-in for libkin's public ABI (tests/abi_mutations.sh): two structs
 * named like libkin's, a size-prefixed one (kin_step_info, in
 * abi/libkin.suppr) and a fixed record (kin_homotopy_endpoint, not), and a
 * few functions. MUTATION selects one deliberate change of the baseline. */
#ifndef KIN_STANDIN_H
#define KIN_STANDIN_H
#include <stddef.h>
#define KIN_API __attribute__((visibility("default")))

typedef struct kin_step_info {
    size_t size;
#if MUTATION == 2 /* swap two members */
    double delta;
    double l;
#else
    double l;
    double delta;
#endif
#if MUTATION == 4 /* insert a member in the middle */
    double inserted;
#endif
    int iterations;
    int halvings;
#if MUTATION == 1 /* append a member: compatible */
    double appended;
#endif
} kin_step_info;

typedef struct kin_homotopy_endpoint {
    size_t size;
    int path;
    int kind;
    double cond;
#if MUTATION == 5 /* append to a struct that does not carry a layout size */
    double appended;
#endif
} kin_homotopy_endpoint;

KIN_API int kin_step(void *a, double delta, kin_step_info *info);
KIN_API int kin_quadrics_homotopy_merge(const kin_homotopy_endpoint *ends, long n);
#if MUTATION != 3 /* remove a function */
KIN_API int kin_path_reset(void *a);
#endif
#if MUTATION == 6 /* add a function: compatible */
KIN_API int kin_added(void *a);
#endif
#endif
