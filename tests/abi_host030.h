/* kin_options as the 0.3.0 headers of 2026-11-23 to 2026-11-26 had it
 * (117529c..c185a3e), written out here, not taken from the generated header
 * or today's kin_path.h: step_control appended after factorization, inside
 * layout 1's tail padding, so such a host passes layout 1's size (72, as the
 * earlier 0.3.0 headers without it) with step_control set. Shared by
 * abi_layouts_host.c and test_abi_fields.c. */
#ifndef KIN_TESTS_ABI_HOST030_H
#define KIN_TESTS_ABI_HOST030_H
#include <stddef.h>

struct host030_options {
    size_t size;
    double rank_tol;
    double corrector_tol;
    int corrector_max_iter;
    double step_fraction;
    int max_halvings;
    double direction_tol;
    double max_correction;
    int factorization;
    int step_control;
};

#endif
