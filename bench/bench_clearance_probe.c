/* Where the clearance check's time goes, by member size (a probe for
 * docs/contact.md "Cost"; bench_clearance.c is the benchmark of record).
 * For each sail member (dome-lifted, bar triangles as panels, as
 * bench_clearance.c builds them) after one LU step (LIBKIN_PROBE_STEPS:
 * more): the margin check
 * (cutoff 0.01 x shortest bar) and the global one, timed in thread CPU
 * time, the median and the least of `reps` checks, in three states:
 *   warm     checks repeated at one configuration;
 *   cold     before each check 8 MB of memory written (the caches emptied
 *            of the check's data, as a large step leaves them; the size in
 *            MB from LIBKIN_PROBE_EVICT_MB: 64 empties the 32 MB L3 too);
 * and (last column) with the tree built again before each check;
 *   cold+br  as cold, plus 200,000 data-dependent random branches (the
 *            branch predictor's history of the walk overwritten, as a step
 *            does).
 * Usage: bench_clearance_probe [reps] [hub:K ...] (default: all ten members
 * of bench_clearance.c). With reps <= 3 it only runs the tree's build and
 * reps margin checks (for valgrind --tool=callgrind --toggle-collect=kin_clearance --cache-sim=yes
 * --branch-sim=yes). Prints a table. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "libkin.h"

static int cmp_dbl(const void *p, const void *q)
{
    double x = *(const double *)p, y = *(const double *)q;
    return (x > y) - (x < y);
}

static size_t EVICT = 8u << 20; /* LIBKIN_PROBE_EVICT_MB */
static volatile unsigned long long sink;

/* the caches emptied (8 MB written and read), and with br the branch
 * predictor's history overwritten by random data-dependent branches */
static void pollute(unsigned char *buf, int br, unsigned long long *st)
{
    for (size_t i = 0; i < EVICT; i += 64) buf[i] = (unsigned char)(buf[i] + 1);
    unsigned long long s = 0;
    for (size_t i = 0; i < EVICT; i += 64) s += buf[i];
    if (br)
        for (int i = 0; i < 200000; ++i) {
            unsigned long long r = kin__splitmix(st);
            if (r & 1) s += r;
            else s ^= r >> 3;
            if (r & 4) s *= 3;
        }
    sink = s;
}

int main(int argc, char **argv)
{
    print_blas();
    int members[16][2] = {{6, 5}, {8, 4}, {6, 10}, {8, 8}, {6, 20}, {8, 15}, {6, 40}, {8, 30}, {6, 60}, {8, 61}};
    int nm = 10, reps = argc > 1 ? atoi(argv[1]) : 60;
    if (reps < 1) reps = 1;
    if (argc > 2) {
        nm = 0;
        for (int i = 2; i < argc && nm < 16; ++i)
            if (sscanf(argv[i], "%d:%d", &members[nm][0], &members[nm][1]) == 2) ++nm;
    }
    const char *ev = getenv("LIBKIN_PROBE_EVICT_MB");
    if (ev && atoi(ev) > 0) EVICT = (size_t)atoi(ev) << 20;
    unsigned char *buf = calloc(EVICT, 1);
    double *t = malloc(sizeof(double) * (size_t)reps);
    unsigned long long st = 7;
    double lx[16], ly[6][16];
    int nfit = 0;
    print_load("at start");
    printf("member     nfree  nprim | margin us: warm(min med)  cold(min med)  cold+br(min med) | "
           "global us: warm  cold+br | margin ns/prim: warm cold+br | margin with the tree built (us)\n");
    for (int i = 0; i < nm; ++i) {
        kin_assembly *a = bench_clearance_member(members[i][0], members[i][1]);
        if (!a) continue;
        kin_step_info info = {.size = sizeof info};
        const char *ns = getenv("LIBKIN_PROBE_STEPS");
        int nsteps = ns && atoi(ns) > 0 ? atoi(ns) : 1, bad = 0;
        for (int k = 0; k < nsteps && !bad; ++k) bad = kin_step(a, 0.0, &info) != KIN_OK;
        if (bad) {
            kin_assembly_free(a);
            continue;
        }
        double sh = INFINITY, cl;
        {
            int nb = kin_nbars(a);
            double *L = malloc(sizeof(double) * (size_t)nb);
            kin_get_rest_lengths(a, L);
            for (int k = 0; k < nb; ++k) sh = L[k] < sh ? L[k] : sh;
            free(L);
        }
        int nprim = kin_nbars(a) + kin_npanels(a);
        kin_clearance(a, NULL, INFINITY, &cl, NULL, NULL); /* build the tree */
        if (reps <= 3) {
            for (int r = 0; r < reps; ++r) kin_clearance(a, NULL, 0.01 * sh, &cl, NULL, NULL);
            printf("sail:%d:%-3d %6d %6d  (checks only)\n", members[i][0], members[i][1], kin_nfree(a), nprim);
            kin_assembly_free(a);
            continue;
        }
        double res[6][2];
        {
            /* the tree built again (a new thickness drops it) before each margin check */
            double t0 = 0.0;
            kin_get_thickness(a, &t0, NULL, NULL);
            for (int r = 0; r < reps; ++r) {
                kin_set_thickness(a, t0, NULL, NULL);
                double c0 = thread_cpu_now();
                kin_clearance(a, NULL, 0.01 * sh, &cl, NULL, NULL);
                t[r] = thread_cpu_now() - c0;
            }
            qsort(t, (size_t)reps, sizeof(double), cmp_dbl);
            res[5][0] = t[0], res[5][1] = t[reps / 2];
        }
        for (int m = 0; m < 5; ++m) {
            double cut = m < 3 ? 0.01 * sh : INFINITY;
            int state = m < 3 ? m : (m == 3 ? 0 : 2);
            for (int r = 0; r < reps; ++r) {
                if (state) pollute(buf, state == 2, &st);
                double c0 = thread_cpu_now();
                kin_clearance(a, NULL, cut, &cl, NULL, NULL);
                t[r] = thread_cpu_now() - c0;
            }
            qsort(t, (size_t)reps, sizeof(double), cmp_dbl);
            res[m][0] = t[0], res[m][1] = t[reps / 2];
        }
        printf("sail:%d:%-3d %6d %6d | %9.1f %7.1f  %7.1f %7.1f  %8.1f %7.1f | %10.1f %8.1f | %8.1f %8.1f | %8.1f\n",
               members[i][0], members[i][1], kin_nfree(a), nprim, 1e6 * res[0][0], 1e6 * res[0][1], 1e6 * res[1][0],
               1e6 * res[1][1], 1e6 * res[2][0], 1e6 * res[2][1], 1e6 * res[3][1], 1e6 * res[4][1],
               1e9 * res[0][1] / nprim, 1e9 * res[2][1] / nprim, 1e6 * res[5][1]);
        fflush(stdout);
        lx[nfit] = log((double)kin_nfree(a));
        for (int m = 0; m < 5; ++m) ly[m][nfit] = log(res[m][1]);
        ++nfit;
        kin_assembly_free(a);
    }
    const char *name[5] = {"margin warm", "margin cold", "margin cold+br", "global warm", "global cold+br"};
    for (int m = 0; m < 5 && nfit > 1; ++m) {
        double mx = 0, my = 0, sxx = 0, sxy = 0;
        for (int k = 0; k < nfit; ++k) mx += lx[k] / nfit, my += ly[m][k] / nfit;
        for (int k = 0; k < nfit; ++k) sxx += (lx[k] - mx) * (lx[k] - mx), sxy += (lx[k] - mx) * (ly[m][k] - my);
        printf("%-16s growth exponent of the median (%d members) %.3f\n", name[m], nfit, sxy / sxx);
    }
    print_load("at end");
    free(buf), free(t);
    return 0;
}
