/* Test and benchmark helper: a deployable mast (bench_step_sparse's mast
 * table, test_sparse_border). */
#ifndef KIN_TEST_MAST_MODEL_H
#define KIN_TEST_MAST_MODEL_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "libkin.h"

/* A mast of nbays bays on a regular `sides`-gon section (side 1, bay height
 * 1), the base ring fixed: each bay adds a ring of `sides` joints and
 * 3 * sides bars (longerons, battens round the new ring, one diagonal per
 * side face, handedness alternating from bay to bay), so each bay is rigid
 * and statically determinate on the one below (a triangulated prism on a
 * rigid base). The middle bay's first face diagonal is left out (a bay
 * halfway through deployment, its diagonal still slack): one internal
 * finite mechanism, the bay shearing and the mast above it swinging as one
 * body; no rigid mechanisms (one dense border row). The joints of the
 * removed diagonal go to *ends (may be NULL): their distance measures the
 * motion. Only the bars the structure needs are built.
 * NULL if it cannot be made. */
static inline kin_assembly *test_mast(int sides, int nbays, int ends[2])
{
    int nj = sides * (nbays + 1), nb = 0, mid = nbays / 2;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    unsigned char *fixed = calloc((size_t)nj * 3, 1);
    int *bars = malloc(sizeof(int) * 2 * 3 * (size_t)sides * (size_t)nbays);
    kin_assembly *a = NULL;
    if (!xyz || !fixed || !bars) goto done;
    double pi = acos(-1.0), r = 0.5 / sin(pi / sides); /* circumradius of a unit-side polygon */
    for (int l = 0; l <= nbays; ++l)
        for (int i = 0; i < sides; ++i) {
            double th = 2.0 * pi * i / sides;
            int j = l * sides + i;
            xyz[3 * j] = r * cos(th);
            xyz[3 * j + 1] = r * sin(th);
            xyz[3 * j + 2] = l;
            if (l == 0) fixed[3 * j] = fixed[3 * j + 1] = fixed[3 * j + 2] = 1;
        }
    for (int l = 1; l <= nbays; ++l)
        for (int i = 0; i < sides; ++i) {
            int i1 = (i + 1) % sides, bot = (l - 1) * sides, top = l * sides;
            int add[3][2] = {{bot + i, top + i}, /* longeron */
                             {top + i, top + i1}, /* batten */
                             {l % 2 ? bot + i : bot + i1, l % 2 ? top + i1 : top + i}}; /* face diagonal */
            for (int k = 0; k < 3; ++k) {
                if (k == 2 && l == mid && i == 0) {
                    if (ends) memcpy(ends, add[k], sizeof add[k]);
                    continue;
                }
                bars[2 * nb] = add[k][0];
                bars[2 * nb + 1] = add[k][1];
                ++nb;
            }
        }
    if (kin_assembly_create(3, nj, xyz, fixed, nb, bars, NULL, &a, NULL, 0) != KIN_OK) a = NULL;
done:
    free(xyz);
    free(fixed);
    free(bars);
    return a;
}

#endif
