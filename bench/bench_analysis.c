/* The first-order analysis at scale.
 *
 *  sparse  (issue 22 item 5) kin_analyse in the sparse mode (no dense SVD:
 *          model/analysis_sparse.c) against the dense SVD on deployable
 *          masts of a few sizes: time, ratio, equal counts.
 *  big     the 10^4-joint mast (30,000 free coordinates) analysed in the
 *          sparse mode: time and the process's peak RSS (run it alone: the
 *          peak is the process's).
 *  split   (issue 24 item 3) the rigid/internal split of the mechanisms:
 *          the Householder QR against the rigid fields (kin__split_basis,
 *          O(nf m m_rigid)) against the pivoted Gram-Schmidt over every unit
 *          vector it replaced (O(m^4); kept below as old_complement, run
 *          where m <= OLD_MAX_M or with --old), on flat triangulated plates
 *          (26 x 31 joints: nf = 2,418, m = 809, issue 24's plate) and a
 *          sail with m > 300. The split's subspaces are compared (sine of
 *          the largest principal angle between the old and new internal
 *          mechanisms).
 *
 * usage: bench_analysis [sparse|big|split|all] [--old]
 * Run with OPENBLAS_NUM_THREADS=1 on an idle machine; the load average is
 * printed with every table. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "libkin.h"
#include "bench_common.h"
#include "mast_model.h"
#include "plate_model.h"
#include "sail_states.h"

/* the old split runs by default only up to this m (its cost grows as m^4:
 * about 30 s of CPU at m = 403, 500 s at m = 809) */
static const int OLD_MAX_M = 420;
/* kin_analyse of the 26 x 31 plate with main's build (old split), measured
 * once (see docs/performance.md, "the rigid/internal split") */
static const double OLD_PLATE_ANALYSE_CPU = 505.6; /* s CPU, one BLAS thread, 2026-11-26 */

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void set_mode(kin_assembly *a, int mode, double rank_tol)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = mode;
    if (rank_tol > 0) o.rank_tol = rank_tol;
    kin_set_options(a, &o);
}

static void sparse_table(void)
{
    print_load("before the sparse/dense table");
    printf("\nkin_analyse, sparse mode against the dense SVD (rank_tol 1e-11), masts (sides x bays), CPU s\n");
    printf("%-10s %7s %7s %5s %4s  %10s %10s %8s  %s\n", "mast", "nfree", "nbars", "m", "s", "sparse s", "dense s",
           "ratio", "counts equal");
    int masts[][2] = {{3, 100}, {6, 100}, {10, 100}, {10, 150}};
    for (size_t k = 0; k < sizeof masts / sizeof masts[0]; ++k) {
        kin_assembly *a = test_mast(masts[k][0], masts[k][1], NULL), *b = NULL;
        if (!a || kin_assembly_clone(a, &b) != KIN_OK) return;
        set_mode(a, KIN_STEP_SPARSE, 1e-11);
        set_mode(b, KIN_STEP_SVD, 1e-11);
        kin_analysis as = {.size = sizeof as}, ad = {.size = sizeof ad};
        double t0 = cpu_now();
        int rs = kin_analyse(a, &as);
        double ts = cpu_now() - t0;
        t0 = cpu_now();
        int rd = kin_analyse(b, &ad);
        double td = cpu_now() - t0;
        int same = rs == KIN_OK && rd == KIN_OK && as.rank == ad.rank && as.m == ad.m && as.s == ad.s &&
                   as.m_rigid == ad.m_rigid;
        printf("%3dx%-6d %7d %7d %5d %4d  %10.3f %10.3f %8.1f  %s\n", masts[k][0], masts[k][1], kin_nfree(a),
               kin_nbars(a), as.m, as.s, ts, td, td / ts, same ? "yes" : "NO");
        fflush(stdout);
        kin_assembly_free(a);
        kin_assembly_free(b);
    }
    print_load("after");
}

static void big(void)
{
    print_load("before the 10^4-joint mast");
    kin_assembly *a = test_mast(10, 1000, NULL);
    if (!a) return;
    set_mode(a, KIN_STEP_SPARSE, 1e-11);
    kin_analysis an = {.size = sizeof an};
    double t0 = now(), c0 = cpu_now();
    int rc = kin_analyse(a, &an);
    double t = now() - t0, c = cpu_now() - c0;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    printf("\nmast 10x1000: %d joints, %d free coordinates, %d bars, sparse kin_analyse: %s, rank %d m %d s %d "
           "v_r/v_max %.3e; %.2f s wall, %.2f s CPU, peak RSS %.0f MB\n",
           kin_njoints(a), kin_nfree(a), kin_nbars(a), kin_status_name(rc), an.rank, an.m, an.s,
           an.v_r / an.v_max, t, c, ru.ru_maxrss / 1024.0);
    kin_assembly_free(a);
    print_load("after");
}

/* The split's internal part as before issue 24: the complement of
 * span(U_m^T Urig) in R^m by pivoted Gram-Schmidt over every unit vector
 * (each new column the unit vector with the most left), then
 * Uint = U_m Z[:, kept:]. O(m^4). */
static void old_complement(int nf, int m, const double *Um, const double *Urig, int kept, double *Uint)
{
    double *Z = malloc(sizeof(double) * (size_t)m * m), *w = malloc(sizeof(double) * m),
           *best = malloc(sizeof(double) * m);
    for (int c = 0; c < kept; ++c)
        for (int r = 0; r < m; ++r) Z[r + (size_t)c * m] = kin__dot(nf, Um + (size_t)r * nf, Urig + (size_t)c * nf);
    for (int c = 0; c < kept; ++c) kin__gs_column(m, Z, m, c, Z + (size_t)c * m);
    for (int have = kept; have < m; ++have) {
        double bestn = -1.0;
        for (int r = 0; r < m; ++r) {
            memset(w, 0, sizeof(double) * (size_t)m);
            w[r] = 1.0;
            double nrm = kin__gs_column(m, Z, m, have, w);
            if (nrm > bestn) {
                bestn = nrm;
                memcpy(best, w, sizeof(double) * (size_t)m);
            }
        }
        memcpy(Z + (size_t)have * m, best, sizeof(double) * (size_t)m);
    }
    int mi = m - kept;
    double one = 1.0, zero = 0.0;
    if (mi > 0) dgemm_("N", "N", &nf, &mi, &m, &one, Um, &nf, Z + (size_t)kept * m, &m, &zero, Uint, &nf, 1, 1);
    free(Z);
    free(w);
    free(best);
}

/* sine of the largest principal angle between two orthonormal bases,
 * bounded above by ||B - A A^T B||_F */
static double subspace_sine(int n, int k, const double *A, const double *B)
{
    double *c = malloc(sizeof(double) * (size_t)k * k), *R = malloc(sizeof(double) * (size_t)n * k);
    double one = 1.0, zero = 0.0, mone = -1.0, sum = 0.0;
    dgemm_("T", "N", &k, &k, &n, &one, A, &n, B, &n, &zero, c, &k, 1, 1);
    memcpy(R, B, sizeof(double) * (size_t)n * k);
    dgemm_("N", "N", &n, &k, &k, &mone, A, &n, c, &k, &one, R, &n, 1, 1);
    for (size_t i = 0; i < (size_t)n * k; ++i) sum += R[i] * R[i];
    free(c);
    free(R);
    return sqrt(sum);
}

/* the new kin_analyse's CPU time on the 26 x 31 plate (split_table) */
static double plate_analyse = NAN;

static void split_row(const char *name, kin_assembly *a, int old)
{
    int nf = kin_nfree(a);
    kin_analysis an = {.size = sizeof an};
    double c0 = cpu_now();
    if (kin_analyse(a, &an) != KIN_OK) return;
    double t_an = cpu_now() - c0;
    if (nf == 2418) plate_analyse = t_an;
    int m = an.m, mr = 0;
    double *Um = malloc(sizeof(double) * (size_t)nf * m), *Urig = malloc(sizeof(double) * (size_t)nf * 6);
    double *Uint = malloc(sizeof(double) * (size_t)nf * m), *Uold = malloc(sizeof(double) * (size_t)nf * m);
    double *work = malloc(sizeof(double) * kin__split_work(nf, m));
    kin_get_mechanisms(a, KIN_MECH_ALL, Um, nf, m);
    /* the new split, repeated to a measurable time */
    int reps = 0;
    c0 = cpu_now();
    do {
        kin__split_basis(a, a->xyz, Um, m, Urig, Uint, &mr, work);
        ++reps;
    } while (cpu_now() - c0 < 0.5);
    double t_new = (cpu_now() - c0) / reps;
    double t_old = NAN, sine = NAN;
    if (old || m <= OLD_MAX_M) {
        c0 = cpu_now();
        old_complement(nf, m, Um, Urig, mr, Uold);
        t_old = cpu_now() - c0 + t_new; /* its rigid part is the new one's (unchanged) */
        sine = subspace_sine(nf, m - mr, Uold, Uint);
    }
    printf("%-16s %6d %5d %4d %5d  %10.3f  %10.5f %10.3f %9.0f  %.1e\n", name, nf, m, mr, m - mr, t_an, t_new, t_old,
           t_old / t_new, sine);
    fflush(stdout);
    free(Um), free(Urig), free(Uint), free(Uold), free(work);
}

static void split_table(int old)
{
    print_load("before the split table");
    printf("\nthe rigid/internal split (CPU s): QR against the rigid fields (new) against pivoted Gram-Schmidt "
           "over every unit vector (old)\n");
    printf("%-16s %6s %5s %4s %5s  %10s  %10s %10s %9s  %s\n", "model", "nfree", "m", "rig", "int",
           "analyse", "split new", "split old", "old/new", "sine(old, new)");
    int plates[][2] = {{13, 12}, {16, 16}, {20, 20}, {26, 31}};
    for (size_t k = 0; k < sizeof plates / sizeof plates[0]; ++k) {
        kin_assembly *a = test_plate(plates[k][0], plates[k][1]);
        char name[32];
        snprintf(name, sizeof name, "plate %dx%d", plates[k][0], plates[k][1]);
        if (a) split_row(name, a, old);
        kin_assembly_free(a);
    }
    kin_assembly *s = test_sail(24, 14);
    if (s) split_row("sail 24:14", s, old);
    kin_assembly_free(s);
    if (!old && isfinite(OLD_PLATE_ANALYSE_CPU))
        printf("plate 26x31 before (main's build, kin_analyse with the old split, measured once): %.1f s CPU; "
               "the whole analysis is %.0fx faster now\n", OLD_PLATE_ANALYSE_CPU, OLD_PLATE_ANALYSE_CPU / plate_analyse);
    print_load("after");
}

int main(int argc, char **argv)
{
    print_blas();
    const char *what = argc > 1 ? argv[1] : "all";
    int old = argc > 2 && strcmp(argv[2], "--old") == 0;
    int all = strcmp(what, "all") == 0;
    if (all || strcmp(what, "big") == 0) big();
    if (all || strcmp(what, "sparse") == 0) sparse_table();
    if (all || strcmp(what, "split") == 0) split_table(old);
    return 0;
}
