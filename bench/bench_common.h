/* What the benchmark programs share: a monotonic clock, the random
 * second-order systems of the complete-solver benchmarks, and the "dome"
 * member of a sail family used to time stepping. Include after defining
 * _POSIX_C_SOURCE (clock_gettime). */
#ifndef KIN_BENCH_COMMON_H
#define KIN_BENCH_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include <dlfcn.h>

#include "model/internal.h"

/* wall-clock seconds, monotonic */
/* the load average, printed with the benchmark's figures (a shared machine) */
static inline void print_load(const char *when)
{
    double l[3] = {NAN, NAN, NAN};
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf %lf %lf", &l[0], &l[1], &l[2]) != 3) l[0] = NAN;
        fclose(f);
    }
    printf("[load average %s: %.2f %.2f %.2f]\n", when, l[0], l[1], l[2]);
}

/* the BLAS the program runs on, printed with its figures: times (and the
 * last digits of results) depend on OpenBLAS's kernel and threads
 * (OPENBLAS_CORETYPE, OPENBLAS_NUM_THREADS), so a table says which it had.
 * Looked up at run time, so the same program reports the reference BLAS
 * (no kernel) when update-alternatives or LD_LIBRARY_PATH selects it. */
static inline void print_blas(void)
{
    void *h = dlopen(NULL, RTLD_NOW);
    void *core = h ? dlsym(h, "openblas_get_corename") : NULL;
    void *config = h ? dlsym(h, "openblas_get_config") : NULL;
    void *threads = h ? dlsym(h, "openblas_get_num_threads") : NULL;
    if (core) {
        char *(*corename)(void), *(*cfg)(void);
        int (*nth)(void);
        *(void **)&corename = core;
        *(void **)&cfg = config;
        *(void **)&nth = threads;
        printf("[BLAS: OpenBLAS, kernel %s, %d thread(s)%s%s]\n", corename(), nth ? nth() : -1,
               cfg ? "; " : "", cfg ? cfg() : "");
    } else {
        printf("[BLAS: not OpenBLAS (reference BLAS or another: no kernel name)]\n");
    }
    if (h) dlclose(h);
}

static inline double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* a standard normal draw (Box-Muller on splitmix) */
static inline double gauss(unsigned long long *st)
{
    double u = ((kin__splitmix(st) >> 11) + 0.5) * 0x1.0p-53;
    double v = ((kin__splitmix(st) >> 11) + 0.5) * 0x1.0p-53;
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* s random symmetric m x m matrices, orthonormal as vectors of length m*m */
static inline void random_system(int m, int s, unsigned long long seed, double *Q)
{
    unsigned long long st = seed;
    size_t mm = (size_t)m * m;
    for (int j = 0; j < s; ++j) {
        double *q = Q + j * mm;
        for (int r = 0; r < m; ++r)
            for (int c = r; c < m; ++c) q[r + c * m] = q[c + r * m] = gauss(&st);
        for (int pass = 0; pass < 2; ++pass)
            for (int k = 0; k < j; ++k) {
                double d = kin__dot((int)mm, Q + k * mm, q);
                for (size_t i = 0; i < mm; ++i) q[i] -= d * Q[k * mm + i];
            }
        double n = kin__norm((int)mm, q);
        for (size_t i = 0; i < mm; ++i) q[i] /= n;
    }
}

/* A member of a (3D) family with the same bars and supports as a, whose rest
 * lengths are those of a smooth dome lift z += amp*(r^2 + 1% noise) of a's
 * configuration: strain-free by construction. Large flat sails are so
 * degenerate that lifting and relaxing does not reach a regular point, and
 * random lifts alone land within 1e-8 (relative v_r) of a bifurcation, where
 * every step is halved many times (measured: 90-290 factorizations per step
 * on the 12-gon, 8-loop member; the dome: 1.0). Returns the new handle, or
 * NULL (creation failed). a is not changed. */
static inline kin_assembly *dome_lengths(const kin_assembly *a, double amp)
{
    kin_assembly *b = NULL;
    int nj = kin_njoints(a), nb = kin_nbars(a);
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    unsigned char *fixed = malloc(3 * (size_t)nj);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    if (xyz && fixed && bars) {
        kin_get_coords(a, xyz);
        kin_get_fixed(a, fixed);
        kin_get_bars(a, bars);
        unsigned long long st = 2024;
        for (int j = 0; j < nj; ++j)
            if (!fixed[3 * j + 2]) {
                double r2 = xyz[3 * j] * xyz[3 * j] + xyz[3 * j + 1] * xyz[3 * j + 1];
                double noise = (double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5;
                xyz[3 * j + 2] += amp * (r2 + 0.01 * noise);
            }
        kin_assembly_create(3, nj, xyz, fixed, nb, bars, NULL, &b, NULL, 0);
    }
    free(xyz);
    free(fixed);
    free(bars);
    return b;
}

/* panels: the bar triangles (each once): bench_clearance.c and bench_clearance_probe.c */
static inline int bench_set_triangles(kin_assembly *a)
{
    int nb = kin_nbars(a), nj = kin_njoints(a);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    int *deg = calloc((size_t)nj + 1, sizeof(int)), *adj = malloc(sizeof(int) * 2 * (size_t)nb);
    int cap = 2 * nb + 8, np = 0;
    int *off = malloc(sizeof(int) * ((size_t)cap + 1)), *pj = malloc(sizeof(int) * 3 * (size_t)cap);
    kin_get_bars(a, bars);
    for (int k = 0; k < 2 * nb; ++k) deg[bars[k] + 1]++;
    for (int j = 0; j < nj; ++j) deg[j + 1] += deg[j];
    int *fill = calloc((size_t)nj, sizeof(int));
    for (int k = 0; k < nb; ++k) {
        int p = bars[2 * k], q = bars[2 * k + 1];
        adj[deg[p] + fill[p]++] = q;
        adj[deg[q] + fill[q]++] = p;
    }
    off[0] = 0;
    for (int p = 0; p < nj; ++p)
        for (int x = deg[p]; x < deg[p + 1]; ++x)
            for (int y = deg[p]; y < deg[p + 1]; ++y) {
                int q = adj[x], r = adj[y];
                if (!(p < q && q < r)) continue;
                for (int z = deg[q]; z < deg[q + 1]; ++z)
                    if (adj[z] == r && np < cap) {
                        pj[3 * np] = p, pj[3 * np + 1] = q, pj[3 * np + 2] = r;
                        off[np + 1] = 3 * (np + 1);
                        ++np;
                    }
            }
    int rc = kin_set_panels(a, np, off, pj);
    free(bars), free(deg), free(adj), free(fill), free(off), free(pj);
    return rc;
}

/* bench_clearance.c's and its probe's members: the sail hub:loops lifted into
 * a strain-free dome, stepped in the LU mode, with its bar triangles as
 * panels; NULL where any of it fails */
static inline kin_assembly *bench_clearance_member(int hub, int loops)
{
    kin_sail_params p;
    kin_sail_params_default(&p, hub, loops);
    kin_assembly *flat = NULL;
    if (kin_model_sail(&p, &flat, NULL, 0)) return NULL;
    kin_assembly *a = dome_lengths(flat, 0.3 / (loops + 1.0));
    kin_assembly_free(flat);
    if (!a) return NULL;
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = KIN_STEP_LU;
    kin_set_options(a, &o);
    if (bench_set_triangles(a) != KIN_OK) {
        kin_assembly_free(a);
        return NULL;
    }
    return a;
}

/* this thread's CPU seconds: what the single-threaded check costs, whatever
 * else the shared machine runs (a check preempted halfway is not charged for
 * the wait; the caches the other processes emptied meanwhile still are) */
static inline double thread_cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

#endif /* KIN_BENCH_COMMON_H */
