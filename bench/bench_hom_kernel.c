/* The complete solver's per-path cost on a range of paths (the tracker's
 * kernels, for profiling with callgrind or perf): tracks paths
 * first .. first + n - 1 of one system with kin_quadrics_homotopy_range on
 * one thread and prints the time per path and per accepted step; optionally
 * writes the endpoint records to a file, or compares them with such a file
 * (same classes, endpoints within a relative tolerance) to check that a
 * change of the kernels leaves the results unchanged.
 * Systems: "rand<s>" (s random quadrics in s + 1 unknowns, as
 * bench_homotopy), "hexflat" (the hexagonal sail's flat state, s = 15),
 * "hexrb" (its R^B, s = 3), "oct" (the octagonal 2-loop sail's flat state,
 * s = 20).
 * "onepath" instead of write/compare tracks the same paths with the one-path
 * reference tracker (kin__hom_track) instead of the solver's lockstep
 * tracker: the ratio of the two times is what the lockstep tracking gains.
 * usage: bench_hom_kernel system first n [write|compare file | onepath] */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "homotopy/solver/homotopy_solver.h"
#include "model/internal.h"
#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

static double *sail_system(int hexrb, int sides, int *m, int *s)
{
    kin_assembly *a = test_sail(sides, 2);
    kin_analysis an = {.size = sizeof an};
    double *Q = NULL;
    if (a && (!hexrb || test_hex_to_RB(a) == KIN_OK) && kin_analyse(a, &an) == KIN_OK) {
        *m = an.m_internal;
        Q = malloc(sizeof(double) * (size_t)*m * *m * an.s);
        if (Q && kin_second_order(a, KIN_Q_EXACT, 1, Q, *m * *m * an.s, s) != KIN_OK) {
            free(Q);
            Q = NULL;
        }
    }
    kin_assembly_free(a);
    return Q;
}

int main(int argc, char **argv)
{
    print_blas();
    if (argc < 4) {
        fprintf(stderr, "usage: bench_hom_kernel rand<s>|hexflat|hexrb|oct first n [write|compare file]\n");
        return 2;
    }
    int m = 0, s = 0;
    double *Q = NULL;
    if (!strncmp(argv[1], "rand", 4)) {
        s = atoi(argv[1] + 4);
        m = s + 1;
        Q = s >= 1 && s <= 23 ? malloc(sizeof(double) * (size_t)m * m * s) : NULL;
        if (Q) random_system(m, s, 1000 + (unsigned long long)s, Q);
    } else if (!strcmp(argv[1], "hexflat") || !strcmp(argv[1], "hexrb")) {
        Q = sail_system(!strcmp(argv[1], "hexrb"), 6, &m, &s);
    } else if (!strcmp(argv[1], "oct")) {
        Q = sail_system(0, 8, &m, &s);
    }
    long first = atol(argv[2]), n = atol(argv[3]);
    if (!Q || n < 1) {
        fprintf(stderr, "bad system or range\n");
        return 2;
    }
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = 1;
    kin_homotopy_endpoint *e = calloc((size_t)n, sizeof *e);
    double *z = malloc(sizeof(double) * 2 * (size_t)m * n);
    if (!e || !z) return 1;
    e[0].size = sizeof *e;
    double t0 = now();
    int rc = KIN_OK;
    if (argc >= 5 && !strcmp(argv[4], "onepath")) {
        /* the one-path reference tracker on the same paths (the solver runs
         * the lockstep tracker, which must give the same records) */
        hom_solver H;
        rc = kin__hom_solver_init(&H, m, s, Q, &o, n);
        for (long i = 0; rc == KIN_OK && i < n; ++i) {
            hom_end he;
            double *zr = z + 2 * (size_t)m * i, *zi = zr + m;
            kin__hom_track(&H.P, &kin__hom_base_settings, kin__hom_pool_ws(&H, 0), (int)(first + i), zr, zi, &he);
            e[i].steps = he.steps, e[i].rejected = he.rejected, e[i].kind = he.kind;
        }
        kin__hom_solver_free(&H);
        argc = 4; /* no write / compare: the records are only partly filled */
    } else {
        rc = kin_quadrics_homotopy_range(m, s, Q, &o, first, n, e, z);
    }
    double sec = now() - t0;
    if (rc) {
        printf("%s\n", kin_strerror(rc));
        return 1;
    }
    long steps = 0, rej = 0, kinds[4] = {0};
    for (long i = 0; i < n; ++i) steps += e[i].steps, rej += e[i].rejected, kinds[e[i].kind & 3]++;
    printf("%s m = %d s = %d paths %ld..%ld: %.3f s, %.1f us/path, %.2f us/step; steps/path %.1f rejected/path "
           "%.2f; real %ld nonreal %ld singular %ld failed %ld\n",
           argv[1], m, s, first, first + n - 1, sec, 1e6 * sec / n, 1e6 * sec / (steps + rej), (double)steps / n,
           (double)rej / n, kinds[0], kinds[1], kinds[2], kinds[3]);
    if (argc >= 6 && !strcmp(argv[4], "write")) {
        FILE *f = fopen(argv[5], "wb");
        if (!f || fwrite(e, sizeof *e, (size_t)n, f) != (size_t)n ||
            fwrite(z, sizeof(double) * 2 * (size_t)m, (size_t)n, f) != (size_t)n)
            return 1;
        fclose(f);
    } else if (argc >= 6 && !strcmp(argv[4], "compare")) {
        kin_homotopy_endpoint *e0 = calloc((size_t)n, sizeof *e0);
        double *z0 = malloc(sizeof(double) * 2 * (size_t)m * n);
        FILE *f = fopen(argv[5], "rb");
        if (!e0 || !z0 || !f || fread(e0, sizeof *e0, (size_t)n, f) != (size_t)n ||
            fread(z0, sizeof(double) * 2 * (size_t)m, (size_t)n, f) != (size_t)n)
            return 1;
        fclose(f);
        long kind_diff = 0, chart_diff = 0, step_diff = 0;
        double worst = 0.0; /* relative difference of endpoints of certified paths of the same class and chart */
        for (long i = 0; i < n; ++i) {
            kind_diff += e0[i].kind != e[i].kind;
            step_diff += e0[i].steps != e[i].steps || e0[i].rejected != e[i].rejected;
            if (e0[i].chart != e[i].chart) {
                chart_diff++;
                continue;
            }
            if (e[i].kind > 1 || e0[i].kind != e[i].kind) continue;
            double d = 0.0, nz = 0.0;
            for (int c = 0; c < 2 * m; ++c) {
                double a = z[2 * m * i + c], b = z0[2 * m * i + c];
                d += (a - b) * (a - b), nz += b * b;
            }
            if (sqrt(d / nz) > worst) worst = sqrt(d / nz);
        }
        printf("compare: %ld class changes, %ld chart changes, %ld paths with other step counts, largest relative "
               "endpoint difference %.2e\n",
               kind_diff, chart_diff, step_diff, worst);
        free(e0);
        free(z0);
    }
    free(e);
    free(z);
    free(Q);
    return 0;
}
