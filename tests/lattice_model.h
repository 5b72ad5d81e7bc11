/* A generated 3D truss mechanism for the sparse mode's benchmarks and
 * tests (bench/bench_step_sparse.c, tests/test_step_sparse.c): a block of
 * the face-centred cubic lattice braced as a Henneberg construction, one bar
 * taken out. Header-only (static), like sail_states.h. */
#ifndef KIN_TEST_LATTICE_MODEL_H
#define KIN_TEST_LATTICE_MODEL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "libkin.h"

static int cmp_key(const void *p, const void *q)
{
    double a = *(const double *)p, b = *(const double *)q;
    return a < b ? -1 : a > b;
}

/* A block of the face-centred cubic lattice (the points of an
 * nx x ny x nz cube grid with x + y + z even), 5 % noise. The joints are
 * numbered by the generic height x + 2.3 y + 5.3 z; each one is braced to
 * three of its nearest lattice neighbours numbered before it (the first
 * not coplanar with the ones already chosen), so each adds three bars: a
 * Henneberg construction (rigid, isostatic). The middle joint's last bar is
 * then taken out: one internal mechanism. No supports: six rigid
 * mechanisms. */
static kin_assembly *lattice(int nx, int ny, int nz)
{
    int cap = nx * ny * nz, nj = 0;
    double *key = malloc(sizeof(double) * 2 * (size_t)cap);
    int *at = malloc(sizeof(int) * (size_t)cap); /* grid cell -> joint, or -1 */
    double *xyz = malloc(sizeof(double) * 3 * (size_t)cap);
    int *bars = malloc(sizeof(int) * 2 * 3 * (size_t)cap), nb = 0, removed = -1;
    kin_assembly *a = NULL;
    if (!key || !at || !xyz || !bars) goto done;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x)
                if ((x + y + z) % 2 == 0) {
                    key[2 * nj] = x + 2.3 * y + 5.3 * z;
                    key[2 * nj + 1] = x + nx * (y + ny * z);
                    ++nj;
                }
    qsort(key, (size_t)nj, 2 * sizeof(double), cmp_key);
    for (int c = 0; c < cap; ++c) at[c] = -1;
    for (int j = 0; j < nj; ++j) at[(int)key[2 * j + 1]] = j;
    unsigned long long st = 99;
    for (int j = 0; j < nj; ++j) {
        int c = (int)key[2 * j + 1], x = c % nx, y = (c / nx) % ny, z = c / (nx * ny);
        const int g[3] = {x, y, z};
        for (int k = 0; k < 3; ++k)
            xyz[3 * j + k] = g[k] + 0.1 * ((double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5);
    }
    for (int j = 0; j < nj; ++j) {
        int c = (int)key[2 * j + 1], x = c % nx, y = (c / nx) % ny, z = c / (nx * ny), got = 0;
        int off[3][3];
        /* nearest lattice neighbours first: squared distance 2 (the 12
         * nearest), then 4, 6, 8 (next shells, at the block's faces) */
        for (int pass = 0; pass < 4 && got < 3; ++pass)
            for (int u = -2; u <= 2 && got < 3; ++u)
                for (int v = -2; v <= 2 && got < 3; ++v)
                    for (int w = -2; w <= 2 && got < 3; ++w) {
                        int n2 = u * u + v * v + w * w;
                        if (n2 != 2 * (pass + 1)) continue;
                        int X = x + u, Y = y + v, Z = z + w;
                        if (X < 0 || Y < 0 || Z < 0 || X >= nx || Y >= ny || Z >= nz) continue;
                        int k = at[X + nx * (Y + ny * Z)];
                        if (k < 0 || k >= j) continue;
                        int o[3] = {u, v, w};
                        if (got == 1) { /* not parallel to the first */
                            int cx = off[0][1] * o[2] - off[0][2] * o[1], cy = off[0][2] * o[0] - off[0][0] * o[2],
                                cz = off[0][0] * o[1] - off[0][1] * o[0];
                            if (cx == 0 && cy == 0 && cz == 0) continue;
                        }
                        if (got == 2) { /* not coplanar with the first two */
                            int det = off[0][0] * (off[1][1] * o[2] - off[1][2] * o[1]) -
                                      off[0][1] * (off[1][0] * o[2] - off[1][2] * o[0]) +
                                      off[0][2] * (off[1][0] * o[1] - off[1][1] * o[0]);
                            if (det == 0) continue;
                        }
                        memcpy(off[got], o, sizeof o);
                        bars[2 * nb] = k;
                        bars[2 * nb + 1] = j;
                        ++nb;
                        ++got;
                    }
        /* near the first joints: the nearest earlier joints in space that
         * keep the bars well spread (first joints: all earlier ones) */
        for (double spread = 0.2; got < 3 && got < j && spread > 1e-4;) {
            int pick = -1;
            double best = INFINITY;
            for (int k = 0; k < j; ++k) {
                double o[3], d = 0.0;
                int dup = 0;
                for (int b = nb - got; b < nb; ++b) dup |= bars[2 * b] == k;
                if (dup) continue;
                for (int q = 0; q < 3; ++q) {
                    o[q] = xyz[3 * k + q] - xyz[3 * j + q];
                    d += o[q] * o[q];
                }
                if (got == 2 && j >= 3) {
                    const double *p0 = xyz + 3 * bars[2 * (nb - 2)], *p1 = xyz + 3 * bars[2 * (nb - 1)];
                    double a0[3], a1[3];
                    for (int q = 0; q < 3; ++q) {
                        a0[q] = p0[q] - xyz[3 * j + q];
                        a1[q] = p1[q] - xyz[3 * j + q];
                    }
                    double det = a0[0] * (a1[1] * o[2] - a1[2] * o[1]) - a0[1] * (a1[0] * o[2] - a1[2] * o[0]) +
                                 a0[2] * (a1[0] * o[1] - a1[1] * o[0]);
                    if (fabs(det) < spread * sqrt(d * (a0[0] * a0[0] + a0[1] * a0[1] + a0[2] * a0[2]) *
                                               (a1[0] * a1[0] + a1[1] * a1[1] + a1[2] * a1[2])))
                        continue;
                }
                if (d < best) {
                    best = d;
                    pick = k;
                }
            }
            if (pick < 0) {
                spread *= 0.1;
                continue;
            }
            bars[2 * nb] = pick;
            bars[2 * nb + 1] = j;
            ++nb;
            ++got;
        }
        if (j == nj / 2) removed = nb - 1;
    }
    if (removed >= 0) {
        memmove(bars + 2 * removed, bars + 2 * removed + 2, sizeof(int) * 2 * (size_t)(nb - removed - 1));
        --nb;
    }
    int rc = kin_assembly_create(3, nj, xyz, NULL, nb, bars, NULL, &a, NULL, 0);
    if (rc) printf("  (lattice %dx%dx%d: create returned %d)\n", nx, ny, nz, rc);
done:
    free(key);
    free(at);
    free(xyz);
    free(bars);
    return a;
}

#endif /* KIN_TEST_LATTICE_MODEL_H */
