/* Comparing two ways of following a path (the step modes' tests:
 * test_step_modes.c, test_step_sparse.c). Header-only (static), needs
 * check.h, internal.h and libkin.h first. */
#ifndef KIN_TEST_STEP_COMPARE_H
#define KIN_TEST_STEP_COMPARE_H

#include <math.h>

#define PI 3.14159265358979323846

/* Each step's corrector may stop anywhere within its position tolerance
 * (corrector_tol * RMS bar length; see kin_path.h), and a difference along
 * the path is carried by every later step: two runs of n steps may differ
 * by up to n such tolerances. */
static double path_tol(const kin_assembly *a, int steps)
{
    return steps * a->opt.corrector_tol * a->rms_length;
}

static double max_diff(int n, const double *x, const double *y)
{
    double m = 0.0;
    for (int i = 0; i < n; ++i) m = fmax(m, fabs(x[i] - y[i]));
    return m;
}

/* three-bar linkage on the parallelogram mode P1 at joint angle th */
static kin_assembly *threebar_at(double th)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double xyz[8];
    kin_get_coords(a, xyz);
    xyz[0] = cos(th);
    xyz[1] = sin(th);
    xyz[2] = xyz[0] + 1.0;
    xyz[3] = xyz[1];
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK);
    return a;
}

#endif /* KIN_TEST_STEP_COMPARE_H */
