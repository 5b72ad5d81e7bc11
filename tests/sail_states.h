/* Test helpers: special states of the sails used by several tests. */
#ifndef KIN_TEST_SAIL_STATES_H
#define KIN_TEST_SAIL_STATES_H

#include <math.h>
#include <stdlib.h>

#include "libkin.h"

static inline kin_assembly *test_sail(int n, int loops)
{
    kin_sail_params p;
    kin_sail_params_default(&p, n, loops);
    kin_assembly *a = NULL;
    return kin_model_sail(&p, &a, NULL, 0) == KIN_OK ? a : NULL;
}

/* The hexagonal sail's R^B: hub flat, A_k = V_k +- w e_z alternating
 * (w = tan(pi/6)), loop 2 relaxed to its rest lengths with only the B nodes
 * free. Returns KIN_OK with a moved to R^B. */
static inline int test_hex_to_RB(kin_assembly *a)
{
    int nj = kin_njoints(a), nb = kin_nbars(a);
    double xyz[57], L0[45];
    int bars[90];
    unsigned char fixed[57];
    if (nj != 19 || nb != 45) return KIN_EINVAL;
    kin_get_coords(a, xyz);
    kin_get_bars(a, bars);
    kin_get_rest_lengths(a, L0);
    double w = tan(3.14159265358979323846 / 6);
    for (int k = 0; k < 6; ++k) {
        int A = 7 + k, V = 1 + k, B = 13 + k;
        double sgn = k % 2 ? -1.0 : 1.0;
        xyz[3 * A] = xyz[3 * V];
        xyz[3 * A + 1] = xyz[3 * V + 1];
        xyz[3 * A + 2] = sgn * w;
        xyz[3 * B + 2] = sgn * w;
    }
    for (int j = 0; j < nj; ++j)
        for (int c = 0; c < 3; ++c) fixed[3 * j + c] = j < 13;
    kin_assembly *loop2 = NULL;
    int rc = kin_assembly_create(3, nj, xyz, fixed, nb, bars, L0, &loop2, NULL, 0);
    if (!rc) rc = kin_relax(loop2, 100, NULL);
    if (!rc) kin_get_coords(loop2, xyz);
    kin_assembly_free(loop2);
    return rc ? rc : kin_set_coords(a, xyz);
}

/* A generic strain-free configuration near the current one: lift the free
 * nodes' z by a deterministic pseudo-random amount and relax. */
static inline int test_make_generic(kin_assembly *a, double amp)
{
    int nj = kin_njoints(a);
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    if (!xyz) return KIN_ENOMEM;
    kin_get_coords(a, xyz);
    unsigned s = 12345u;
    for (int j = 0; j < nj; ++j)
        if (kin_free_index(a, j, 2) >= 0) {
            s = s * 1103515245u + 12345u;
            xyz[3 * j + 2] += amp * ((double)(s >> 8) / (1u << 24) - 0.5);
        }
    int rc = kin_set_coords(a, xyz);
    double res = 0.0;
    if (!rc) rc = kin_relax(a, 100, &res);
    free(xyz);
    return rc;
}

#endif
