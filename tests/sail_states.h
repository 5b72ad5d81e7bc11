/* Test helpers: special states of the sails used by several tests. */
#ifndef KIN_TEST_SAIL_STATES_H
#define KIN_TEST_SAIL_STATES_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "libkin.h"

static inline kin_assembly *test_sail(int n, int loops)
{
    kin_sail_params p = {.size = sizeof p};
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

/* U_m * beta (internal mechanisms of the last analysis of a, m columns)
 * into dir (nfree entries) */
static inline void test_mechanism(kin_assembly *a, const double *beta, int m, double *dir)
{
    int nf = kin_nfree(a);
    double *U = malloc(sizeof(double) * (size_t)nf * (size_t)m);
    if (!U) return;
    kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, nf, m);
    for (int i = 0; i < nf; ++i) {
        dir[i] = 0;
        for (int k = 0; k < m; ++k) dir[i] += U[i + (size_t)nf * k] * beta[k];
    }
    free(U);
}

/* Follow a (a regular point) with steps of delta until the signed test
 * function changes sign; *before receives a copy of the last point before
 * the change. Returns 1 if it changed within max_steps. */
static inline int test_follow_to_sign_change(kin_assembly *a, double delta, int max_steps, kin_assembly **before)
{
    double t0 = 0, t1 = 0;
    if (kin_test_function(a, &t0)) return 0;
    for (int k = 0; k < max_steps; ++k) {
        kin_assembly *p = NULL;
        if (kin_assembly_clone(a, &p)) return 0;
        if (kin_step(a, delta, NULL) || kin_test_function(a, &t1)) {
            kin_assembly_free(p);
            return 0;
        }
        if ((t0 > 0) != (t1 > 0)) {
            *before = p;
            return 1;
        }
        kin_assembly_free(p);
        t0 = t1;
    }
    return 0;
}

/* The fold of the hexagonal sail between its flat state R^A and R^B. Of the
 * 16 directed paths out of R^B (8 second-order solutions, complete solver)
 * the one that reaches a bifurcation with m = 16 (the flat state) is the
 * folding path. Returns, as new handles: *rb_start, R^B moved 1e-3 along
 * that path towards R^A; *ra_start, the flat state moved 1e-3 along the
 * same path reversed (the chord of the last step before R^A), towards R^B;
 * and optionally R^B and the flat state's coordinates (57 each). */
static inline int test_hex_fold(kin_assembly **rb_start, kin_assembly **ra_start, double *rb_xyz, double *flat_xyz)
{
    kin_assembly *a = test_sail(6, 2), *flat = test_sail(6, 2);
    int rc = a && flat ? KIN_OK : KIN_ENOMEM, found = 0;
    double xflat[57], Q[48], betas[32], dir[46];
    kin_analysis an = {.size = sizeof an};
    if (!rc) kin_get_coords(flat, xflat);
    if (!rc) rc = test_hex_to_RB(a);
    if (!rc) rc = kin_analyse(a, &an);
    int s = 0, nsol = 0;
    kin_homotopy_info hi = {.size = sizeof hi};
    if (!rc) rc = kin_second_order(a, KIN_Q_EXACT, 1, Q, 48, &s);
    if (!rc) rc = kin_quadrics_homotopy(an.m_internal, s, Q, 1, 1, betas, 8, &nsol, NULL, &hi);
    if (rb_xyz && !rc) kin_get_coords(a, rb_xyz);
    if (flat_xyz) memcpy(flat_xyz, xflat, sizeof xflat);
    for (int k = 0; !rc && k < 2 * nsol && !found; ++k) {
        double beta[4];
        for (int i = 0; i < 4; ++i) beta[i] = (k % 2 ? -1.0 : 1.0) * betas[4 * (k / 2) + i];
        kin_assembly *b = NULL, *start = NULL, *before = NULL, *ra = NULL;
        test_mechanism(a, beta, an.m_internal, dir);
        if (kin_assembly_clone(a, &b) || kin_path_set_direction(b, dir, 46) || kin_step(b, 1e-3, NULL) ||
            kin_assembly_clone(b, &start) || !test_follow_to_sign_change(b, 0.0, 400, &before) ||
            kin_assembly_clone(before, &ra)) {
            kin_assembly_free(b);
            kin_assembly_free(start);
            kin_assembly_free(before);
            continue;
        }
        kin_locate_info info = {.size = sizeof info};
        if (kin_locate_next(ra, NULL, &info) == KIN_OK && info.m_internal == 16) {
            double xb[57], d[46];
            kin_get_coords(before, xb);
            for (int j = 0, i = 0; j < 19; ++j)
                for (int c = 0; c < 3; ++c)
                    if (kin_free_index(flat, j, c) >= 0) d[i++] = xb[3 * j + c] - xflat[3 * j + c];
            if (kin_path_set_direction(flat, d, 46) == KIN_OK && kin_step(flat, 1e-3, NULL) == KIN_OK) {
                found = 1;
                *rb_start = start;
                *ra_start = flat;
                start = flat = NULL;
            }
        }
        kin_assembly_free(ra);
        kin_assembly_free(b);
        kin_assembly_free(start);
        kin_assembly_free(before);
    }
    kin_assembly_free(a);
    kin_assembly_free(flat);
    return rc ? rc : found ? KIN_OK : KIN_ENOTFOUND;
}

/* The symmetries of a sail with 3-fold symmetry about the z axis through
 * the centroid (the hexagonal sails) at its current state, acting on the
 * internal-mechanism coordinates: for the maps x -> T x (rotations by 0,
 * 120, 240 degrees, each with and without z -> -z) that permute the joints,
 * R = U^T P U (P: T's action on free coordinates; U: nfree x m internal
 * mechanisms, column-major). Writes at most maxg m x m matrices (column-
 * major) to R and returns how many (-1: out of memory). Written by hand
 * for these sails: tests/test_mechanism_group.c checks kin_mechanism_group
 * (which finds the group of any assembly) against it. */
static inline int test_rotation_group(kin_assembly *a, int m, const double *U, double *R, int maxg)
{
    int nj = kin_njoints(a), nf = kin_nfree(a), ng = 0;
    double *X = malloc(sizeof(double) * 3 * nj), *P = malloc(sizeof(double) * nf * nf), c[3] = {0, 0, 0};
    double *PU = malloc(sizeof(double) * nf * m);
    if (!X || !P || !PU) {
        free(X), free(P), free(PU);
        return -1;
    }
    kin_get_coords(a, X);
    for (int j = 0; j < nj; ++j)
        for (int k = 0; k < 3; ++k) c[k] += X[3 * j + k] / nj;
    for (int rot = 0; rot < 3; ++rot)
        for (int mir = 0; mir < 2; ++mir) {
            double th = 2.0 * 3.14159265358979323846 * rot / 3.0, cs = cos(th), sn = sin(th);
            double T[9] = {cs, -sn, 0, sn, cs, 0, 0, 0, mir ? -1.0 : 1.0};
            memset(P, 0, sizeof(double) * nf * nf);
            int ok = 1;
            for (int i = 0; i < nj && ok; ++i) {
                double y[3];
                for (int r = 0; r < 3; ++r) {
                    y[r] = c[r];
                    for (int k = 0; k < 3; ++k) y[r] += T[3 * r + k] * (X[3 * i + k] - c[k]);
                }
                int to = -1;
                for (int j = 0; j < nj && to < 0; ++j)
                    if (fabs(X[3 * j] - y[0]) + fabs(X[3 * j + 1] - y[1]) + fabs(X[3 * j + 2] - y[2]) < 1e-9) to = j;
                if (to < 0) ok = 0;
                for (int ax = 0; ax < 3 && ok; ++ax) {
                    int fi = kin_free_index(a, i, ax);
                    if (fi < 0) continue;
                    for (int b = 0; b < 3; ++b) {
                        int fj = kin_free_index(a, to, b);
                        if (fabs(T[3 * b + ax]) > 1e-12) {
                            if (fj < 0) ok = 0;
                            else P[(size_t)fi * nf + fj] = T[3 * b + ax];
                        }
                    }
                }
            }
            if (!ok || ng == maxg) continue;
            for (int k = 0; k < m; ++k) /* PU = P U (column-major, nf rows) */
                for (int r = 0; r < nf; ++r) {
                    double v = 0.0;
                    for (int q = 0; q < nf; ++q) v += P[(size_t)q * nf + r] * U[(size_t)k * nf + q];
                    PU[(size_t)k * nf + r] = v;
                }
            double *Rg = R + (size_t)ng * m * m;
            for (int k = 0; k < m; ++k)
                for (int r = 0; r < m; ++r) {
                    double v = 0.0;
                    for (int q = 0; q < nf; ++q) v += U[(size_t)r * nf + q] * PU[(size_t)k * nf + q];
                    Rg[(size_t)k * m + r] = v;
                }
            ng++;
        }
    free(X), free(P), free(PU);
    return ng;
}


#endif
