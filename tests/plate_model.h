/* Test and benchmark helper: a flat triangulated plate (issue 24's analysis
 * at scale: bench_analysis). */
#ifndef KIN_TEST_PLATE_MODEL_H
#define KIN_TEST_PLATE_MODEL_H

#include <stdlib.h>

#include "libkin.h"

/* A flat triangulated plate in the plane z = 0 (3D, no supports): nx x ny
 * joints on a unit grid, each cell split by one diagonal. In its plane it
 * is rigid (rank 2J - 3; over-braced: s = bars - (2J - 3)), out of it every
 * joint's z is a first-order mechanism: nf = 3J, m = J + 3 (6 rigid,
 * J - 3 internal). 26 x 31 joints: nf = 2,418, m = 809 (issue 24's plate).
 * NULL if it cannot be made. */
static inline kin_assembly *test_plate(int nx, int ny)
{
    int nj = nx * ny, nb = 0;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    int *bars = malloc(sizeof(int) * 2 * 3 * (size_t)nj);
    kin_assembly *a = NULL;
    if (!xyz || !bars) goto done;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            int p = j * nx + i;
            xyz[3 * p] = i;
            xyz[3 * p + 1] = j;
            xyz[3 * p + 2] = 0.0;
            if (i + 1 < nx) bars[2 * nb] = p, bars[2 * nb + 1] = p + 1, ++nb;
            if (j + 1 < ny) bars[2 * nb] = p, bars[2 * nb + 1] = p + nx, ++nb;
            if (i + 1 < nx && j + 1 < ny) bars[2 * nb] = p, bars[2 * nb + 1] = p + nx + 1, ++nb;
        }
    if (kin_assembly_create(3, nj, xyz, NULL, nb, bars, NULL, &a, NULL, 0) != KIN_OK) a = NULL;
done:
    free(xyz);
    free(bars);
    return a;
}

#endif
