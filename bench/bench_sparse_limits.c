/* The sparse mode's limits (issue 36 item 4, issue 39 item 5), measured.
 *
 *  table   kin_analyse in the sparse mode on models where the sparse
 *          analysis has many mechanisms or self-stresses, or a band of
 *          singular values above tau: its status, which route answered
 *          (kin_get_analysis_route) and CPU time, against the dense SVD
 *          (KIN_STEP_SVD) and against the sparse analysis alone (the dense
 *          route judged unaffordable, as on a model too big for memory:
 *          the fault hook KIN__FAULT_DENSE_UNAFFORDABLE).
 *  mast    the 10^4-joint mast (30,000 free coordinates) with the default
 *          options in the sparse mode: analysis, two steps, and the calls
 *          that need the dense SVD (locate, follow: refused at once), with
 *          statuses, CPU times and the peak RSS (run it alone: the peak is
 *          the process's).
 *
 * usage: bench_sparse_limits [table|mast|all]
 * Run with OPENBLAS_NUM_THREADS=1 on an idle machine; the BLAS kernel
 * (OpenBLAS's core name, where the BLAS is OpenBLAS) and the load average
 * are printed with every table. */
#define _POSIX_C_SOURCE 199309L
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "bench_common.h"
#include "libkin.h"
#include "mast_model.h"
#include "model/internal.h"
#include "plate_model.h"

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static kin_assembly *chain(int dim, int n)
{
    double *xyz = malloc(sizeof(double) * 3 * (size_t)n);
    int *bars = malloc(sizeof(int) * 2 * (size_t)n);
    unsigned char *fixed = calloc(3 * (size_t)n, 1);
    kin_assembly *a = NULL;
    if (xyz && bars && fixed) {
        for (int i = 0; i < n; ++i) {
            xyz[dim * i] = i;
            xyz[dim * i + 1] = (i % 7) * 0.25;
            if (dim == 3) xyz[3 * i + 2] = (i % 5) * 0.3;
        }
        if (dim == 3) fixed[0] = fixed[1] = fixed[2] = 1; /* 2D: free-floating */
        for (int k = 0; k < n - 1; ++k) bars[2 * k] = k, bars[2 * k + 1] = k + 1;
        if (kin_assembly_create(dim, n, xyz, fixed, n - 1, bars, NULL, &a, NULL, 0) != KIN_OK) a = NULL;
    }
    free(xyz);
    free(bars);
    free(fixed);
    return a;
}

static kin_assembly *sail(int n, int loops)
{
    kin_sail_params p;
    kin_sail_params_default(&p, n, loops);
    kin_assembly *a = NULL;
    return kin_model_sail(&p, &a, NULL, 0) == KIN_OK ? a : NULL;
}

/* one analysis of a clone of a in the given mode; its status, counts,
 * route and CPU time */
static int run(const kin_assembly *a, int mode, int unaffordable, kin_analysis *an, int *route, double *t)
{
    kin_assembly *b = NULL;
    *route = -1;
    *t = NAN;
    if (kin_assembly_clone(a, &b) != KIN_OK) return KIN_ENOMEM;
    kin_options o = {.size = sizeof o};
    kin_get_options(b, &o);
    o.factorization = mode;
    kin_set_options(b, &o);
    if (unaffordable) kin__set_fault(b, KIN__FAULT_DENSE_UNAFFORDABLE);
    an->size = sizeof *an;
    double t0 = cpu_now();
    int rc = kin_analyse(b, an);
    *t = cpu_now() - t0;
    if (rc == KIN_OK) kin_get_analysis_route(b, route);
    kin_assembly_free(b);
    return rc;
}

static const char *route_name(int r) { return r == KIN_ROUTE_SPARSE ? "sparse" : r == KIN_ROUTE_DENSE ? "dense" : "-"; }

static void table(void)
{
    print_blas();
    print_load("before the table");
    printf("\nkin_analyse at the default rank_tol, CPU s; \"sparse only\": the dense route judged unaffordable\n");
    printf("| model | nfree | nbars | m | s | sparse mode: status | route | CPU s | dense SVD CPU s | sparse only: "
           "status | CPU s |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    struct {
        const char *name;
        kin_assembly *a;
    } rows[] = {
        {"plate 26 x 26", test_plate(26, 26)}, {"sail:24:40", sail(24, 40)}, {"2D chain, 597 joints", chain(2, 597)},
        {"3D chain, 500 joints", chain(3, 500)}, {"3D chain, 1000 joints", chain(3, 1000)},
        {"mast 10 x 100", test_mast(10, 100, NULL)},
    };
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
        kin_assembly *a = rows[k].a;
        if (!a) continue;
        kin_analysis as, ad, ao;
        int rs_route, rd_route, ro_route;
        double ts, td, to;
        int rs = run(a, KIN_STEP_SPARSE, 0, &as, &rs_route, &ts);
        int rd = run(a, KIN_STEP_SVD, 0, &ad, &rd_route, &td);
        int ro = run(a, KIN_STEP_SPARSE, 1, &ao, &ro_route, &to);
        printf("| %s | %d | %d | %d | %d | %s | %s | %.2f | %.2f | %s | %.2f |\n", rows[k].name, kin_nfree(a),
               kin_nbars(a), rd == KIN_OK ? ad.m : -1, rd == KIN_OK ? ad.s : -1, kin_status_name(rs),
               route_name(rs_route), ts, td, kin_status_name(ro), to);
        if (rs == KIN_OK && rd == KIN_OK && (as.m != ad.m || as.s != ad.s)) printf("  COUNTS DIFFER\n");
        if (ro == KIN_OK && rd == KIN_OK && (ao.m != ad.m || ao.s != ad.s)) printf("  COUNTS DIFFER (sparse only)\n");
        fflush(stdout);
        kin_assembly_free(a);
    }
    print_load("after");
}

static void mast(void)
{
    print_blas();
    print_load("before the 10^4-joint mast");
    kin_assembly *a = test_mast(10, 1000, NULL);
    if (!a) return;
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = KIN_STEP_SPARSE;
    double t0 = cpu_now();
    int rc = kin_set_options(a, &o);
    printf("\nmast 10x1000, %d free coordinates, default options (rank_tol %g), sparse mode\n", kin_nfree(a),
           o.rank_tol);
    printf("| call | status | CPU s |\n|---|---|---|\n| set options | %s | %.2f |\n", kin_status_name(rc),
           cpu_now() - t0);
    kin_analysis an = {.size = sizeof an};
    t0 = cpu_now();
    rc = kin_analyse(a, &an);
    printf("| kin_analyse (m %d, s %d, v_r/v_max %.3g) | %s | %.2f |\n", an.m, an.s, an.v_r / an.v_max,
           kin_status_name(rc), cpu_now() - t0);
    for (int k = 0; k < 2; ++k) {
        kin_step_info info = {.size = sizeof info};
        t0 = cpu_now();
        rc = kin_step(a, 0.0, &info);
        printf("| kin_step %d | %s | %.2f |\n", k + 1, kin_status_name(rc), cpu_now() - t0);
    }
    kin_locate_options lo;
    kin_locate_options_default(&lo);
    kin_locate_info li = {.size = sizeof li};
    t0 = cpu_now();
    rc = kin_locate_next(a, &lo, &li);
    printf("| kin_locate_next | %s | %.2f |\n", kin_status_name(rc), cpu_now() - t0);
    kin_follow_options fo;
    kin_follow_options_default(&fo);
    kin_follow_info fi = {.size = sizeof fi};
    t0 = cpu_now();
    rc = kin_follow_event(a, NULL, &fo, &fi);
    printf("| kin_follow_event | %s | %.2f |\n", kin_status_name(rc), cpu_now() - t0);
    printf("(message: %s)\n", kin_last_error(a));
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("peak RSS %.0f MB\n", ru.ru_maxrss / 1024.0);
    kin_assembly_free(a);
    print_load("after");
}

int main(int argc, char **argv)
{
    const char *what = argc > 1 ? argv[1] : "all";
    int all = strcmp(what, "all") == 0;
    if (all || strcmp(what, "mast") == 0) mast();
    if (all || strcmp(what, "table") == 0) table();
    return 0;
}
