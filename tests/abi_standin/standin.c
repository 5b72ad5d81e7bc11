/* The stand-in library of tests/abi_mutations.sh (see kin_standin.h). */
#include "kin_standin.h"

int kin_step(void *a, double delta, kin_step_info *info)
{
    if (info) info->delta = delta;
    return a ? 0 : 1;
}

int kin_quadrics_homotopy_merge(const kin_homotopy_endpoint *ends, long n) { return ends && n > 0 ? ends->kind : 1; }

#if MUTATION != 3
int kin_path_reset(void *a) { return a ? 0 : 1; }
#endif
#if MUTATION == 6
int kin_added(void *a) { return a ? 0 : 1; }
#endif
