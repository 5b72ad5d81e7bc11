/* The complete solver (kin_quadrics_homotopy) against the paper's root scan
 * (kin_quadrics_scan). Not a test: prints tables and writes CSV for
 * bench/plot_homotopy.py.
 *  1. time and path accounting of the complete solver on random systems of
 *     s quadrics in m = s + 1 unknowns (symmetric Gaussian matrices,
 *     orthonormalised as eq. 18 does), s = 2 .. smax -> bench_homotopy.csv;
 *  2. the same for the hexagonal sail's flat state (s = 15, 32768 paths),
 *     `hexruns` times (the machine may be shared: report best and spread),
 *     each run followed by the symmetric solver (kin_quadrics_homotopy_sym
 *     with the group of kin_mechanism_group, its finding timed too: the
 *     equivariant start system, 10944 paths);
 *  3. completeness against time -> bench_completeness.csv: the fraction of
 *     the complete solver's real solutions that the root scan finds from
 *     2^6 .. 2^scanmax starting points, and its time, on the square sail's
 *     flat state (16 real solutions), the hexagonal sail's R^B (8) and its
 *     flat state; every scan solution is matched to one of the complete
 *     solver's (a cross-check of both: "unmatched" must be 0).
 * Wall-clock seconds and process CPU seconds (all threads) are both given.
 * usage: bench_homotopy [outdir (.)] [smax (15)] [hexruns (1)] [scanmax (14; 0: skip part 3)] */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "model/internal.h"
#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

enum { THREADS = 2, SCAN_MIN_LOG2 = 6, SCAN_SEED = 11, HOMOTOPY_SEED = 1, MAX_GROUP = 64 };

static double cpu(void) { return (double)clock() / CLOCKS_PER_SEC; }

/* the complete solver on one system: a table row and a CSV row; returns
 * the number of distinct real solutions (-1 on error), *sec its time.
 * sym (an assembly whose second-order system Q is): the symmetric solver
 * with the group from kin_mechanism_group, found inside the timing. */
static int homotopy_sym(FILE *csv, const char *name, int run, int m, int s, const double *Q, kin_assembly *sym,
                        double *sec)
{
    int maxsol = 1 << s, nsol = 0, ng = 0;
    double *betas = malloc(sizeof(double) * (size_t)m * maxsol);
    double *R = sym ? malloc(sizeof(double) * (size_t)m * m * MAX_GROUP) : NULL;
    kin_homotopy_info h = {.size = sizeof h};
    kin_homotopy_sym_info si = {.size = sizeof si};
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.seed = HOMOTOPY_SEED, o.nthreads = THREADS;
    double t0 = now(), c0 = cpu();
    int rc = !betas || (sym && !R) ? KIN_ENOMEM : KIN_OK;
    if (!rc && sym) rc = kin_mechanism_group(sym, MAX_GROUP, R, &ng);
    if (!rc)
        rc = sym ? kin_quadrics_homotopy_sym(m, s, Q, ng, R, &o, betas, maxsol, &nsol, NULL, &h, &si, NULL, 0)
                 : kin_quadrics_homotopy(m, s, Q, HOMOTOPY_SEED, THREADS, betas, maxsol, &nsol, NULL, &h);
    free(R);
    double wall = now() - t0, cs = cpu() - c0;
    free(betas);
    *sec = wall;
    if (rc) {
        printf("%-10s s = %2d: %s\n", name, s, kin_strerror(rc));
        return -1;
    }
    printf("%-10s %3d %6d %8.3f %8.3f %6d %6d %6d %5d %5d %6.1f %4.1f %5d %4d %4d %5d %8.1e %8.1e\n", name, s,
           h.paths, wall, cs, h.real, h.real_distinct, h.nonreal, h.singular, h.failed, (double)h.steps / h.paths,
           (double)h.rejected / h.paths, h.retracked, h.duplicates, h.unpaired, h.uncertified, h.max_residual,
           h.max_cond);
    fprintf(csv, "%s,%d,%d,%d,%.6f,%.6f,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%.3g,%.3g\n", name, run, s, h.paths, wall,
            cs, h.real, h.real_distinct, h.nonreal, h.singular, h.failed, THREADS, h.steps, h.rejected, h.retracked,
            h.duplicates, h.unpaired, h.uncertified, h.max_residual, h.max_cond);
    if (sym) printf("           (group %d, %d paths tracked: one per orbit of start roots, %d monodromy paths)\n",
                    si.group, si.final_paths, si.monodromy_paths);
    fflush(stdout);
    fflush(csv);
    return h.real_distinct;
}

static int homotopy(FILE *csv, const char *name, int run, int m, int s, const double *Q, double *sec)
{
    return homotopy_sym(csv, name, run, m, s, Q, NULL, sec);
}

static void header(void)
{
    printf("%-10s %3s %6s %8s %8s %6s %6s %6s %5s %5s %6s %4s %5s %4s %4s %5s %8s %8s\n", "system", "s", "paths",
           "wall[s]", "cpu[s]", "real", "dist", "cmplx", "sing", "fail", "steps", "rej", "retrk", "dup", "unp",
           "uncrt", "resid", "maxcond");
}

/* second-order matrices at the assembly's current state; *m, *s set */
static double *second_order(kin_assembly *a, int *m, int *s)
{
    kin_analysis an = {.size = sizeof an};
    if (!a || kin_analyse(a, &an) != KIN_OK) return NULL;
    *m = an.m_internal;
    double *Q = malloc(sizeof(double) * (size_t)*m * *m * an.s);
    if (Q && kin_second_order(a, KIN_Q_EXACT, 1, Q, *m * *m * an.s, s) != KIN_OK) {
        free(Q);
        Q = NULL;
    }
    return Q;
}

/* A set of real projective solutions (unit vectors, either sign), sorted by
 * the sign-free key (w . b)^2 for nearest-neighbour queries. */
typedef struct rootset {
    int n, m;
    const double *b;
    double w[64];
    double *key;
    int *idx;
} rootset;

static const rootset *sort_ctx_;
static int by_key(const void *x, const void *y)
{
    double a = sort_ctx_->key[*(const int *)x], b = sort_ctx_->key[*(const int *)y];
    return (a > b) - (a < b);
}

static double keyof(const rootset *R, const double *b)
{
    double d = 0.0;
    for (int i = 0; i < R->m; ++i) d += R->w[i] * b[i];
    return d * d;
}

static int rootset_init(rootset *R, int n, int m, const double *b)
{
    R->n = n, R->m = m, R->b = b;
    unsigned long long st = 77;
    double nw = 0.0;
    for (int i = 0; i < m; ++i) R->w[i] = gauss(&st), nw += R->w[i] * R->w[i];
    for (int i = 0; i < m; ++i) R->w[i] /= sqrt(nw);
    R->key = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    R->idx = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    if (!R->key || !R->idx) return 0;
    for (int i = 0; i < n; ++i) R->key[i] = keyof(R, b + (size_t)i * m), R->idx[i] = i;
    sort_ctx_ = R;
    qsort(R->idx, (size_t)n, sizeof(int), by_key);
    return 1;
}

/* index of the member with |b . q| >= 1 - tol closest to q, -1 if none
 * (|b - q| <= sqrt(2 tol) moves the key by at most 2 sqrt(2 tol)) */
static int rootset_match(const rootset *R, const double *q, double tol)
{
    double kq = keyof(R, q), win = 2.0 * sqrt(2.0 * tol), best = 1.0 - tol;
    int lo = 0, hi = R->n, found = -1;
    while (lo < hi) { /* first index with key >= kq - win */
        int mid = (lo + hi) / 2;
        if (R->key[R->idx[mid]] < kq - win) lo = mid + 1;
        else hi = mid;
    }
    for (int k = lo; k < R->n && R->key[R->idx[k]] <= kq + win; ++k) {
        const double *b = R->b + (size_t)R->idx[k] * R->m;
        double d = 0.0;
        for (int i = 0; i < R->m; ++i) d += b[i] * q[i];
        if (fabs(d) >= best) best = fabs(d), found = R->idx[k];
    }
    return found;
}

/* part 3 on one state: the complete solver once, then the scan. The scan
 * runs in batches of at most SCAN_BATCH starts (one growing scan, read off
 * at 2^6 .. 2^k starts); each solution it finds is matched to the complete
 * solver's nearest real solution by eq. 20 (|b . q| >= 1 - 1e-8), and
 * "found" counts the complete solver's solutions hit at least once. */
enum { SCAN_BATCH = 4096 };
static const double MATCH_TOL = 1e-8;

static void completeness(FILE *hcsv, FILE *csv, const char *name, kin_assembly *a, int scanmax)
{
    int m = 0, s = 0;
    double *Q = second_order(a, &m, &s), sec = 0.0;
    if (!Q) {
        printf("%s: no second-order matrices\n", name);
        return;
    }
    int maxsol = 1 << s, nh = 0;
    double *truthb = malloc(sizeof(double) * (size_t)m * maxsol), *betas = malloc(sizeof(double) * (size_t)m * SCAN_BATCH);
    unsigned char *hit = calloc((size_t)maxsol, 1);
    rootset R = {0};
    header();
    kin_homotopy_info h = {.size = sizeof h};
    double t0 = now(), c0 = cpu();
    int rc = truthb && betas && hit
                 ? kin_quadrics_homotopy(m, s, Q, HOMOTOPY_SEED, THREADS, truthb, maxsol, &nh, NULL, &h)
                 : KIN_ENOMEM;
    sec = now() - t0;
    if (rc || !rootset_init(&R, nh, m, truthb)) {
        printf("%s: %s\n", name, kin_strerror(rc));
        goto out;
    }
    printf("%-10s %3d %6d %8.3f %8.3f %6d %6d %6d %5d %5d %6.1f %4.1f %5d %4d %4d %5d %8.1e %8.1e\n", name, s, h.paths,
           sec, cpu() - c0, h.real, h.real_distinct, h.nonreal, h.singular, h.failed, (double)h.steps / h.paths,
           (double)h.rejected / h.paths, h.retracked, h.duplicates, h.unpaired, h.uncertified, h.max_residual,
           h.max_cond);
    fprintf(csv, "%s,homotopy,%d,%.6f,%d,%d,0\n", name, maxsol, sec, nh, nh);
    double total = 0.0;
    int found = 0, unmatched = 0, done = 0;
    for (int k = SCAN_MIN_LOG2; k <= scanmax; ++k) {
        int starts = 1 << k;
        while (done < starts) { /* the next batch: starts done .. */
            int batch = starts - done < SCAN_BATCH ? starts - done : SCAN_BATCH, nsol = 0;
            kin_solve_info info = {.size = sizeof info};
            t0 = now();
            kin_quadrics_scan(m, s, Q, batch, SCAN_SEED + (unsigned long)done, betas, SCAN_BATCH, &nsol, &info);
            total += now() - t0;
            for (int i = 0; i < nsol; ++i) {
                int j = rootset_match(&R, betas + (size_t)i * m, MATCH_TOL);
                if (j < 0) unmatched++;
                else if (!hit[j]) hit[j] = 1, found++;
            }
            done += batch;
        }
        printf("  scan %6d starts: %6d of %d real solutions (%5.1f %%) in %8.3f s; %d not among them\n", starts,
               found, nh, nh > 0 ? 100.0 * found / nh : 0.0, total, unmatched);
        fprintf(csv, "%s,scan,%d,%.6f,%d,%d,%d\n", name, starts, total, found, nh, unmatched);
        fflush(stdout);
        fflush(csv);
    }
out:
    free(R.key), free(R.idx), free(hit), free(betas), free(truthb), free(Q);
    (void)hcsv;
}

static FILE *open_csv(const char *dir, const char *file, const char *head)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    FILE *f = fopen(path, "w");
    if (!f) fprintf(stderr, "cannot write %s\n", path);
    else fprintf(f, "%s\n", head);
    return f;
}

int main(int argc, char **argv)
{
    print_blas();
    const char *dir = argc > 1 ? argv[1] : ".";
    int smax = argc > 2 ? atoi(argv[2]) : 15, hexruns = argc > 3 ? atoi(argv[3]) : 1;
    int scanmax = argc > 4 ? atoi(argv[4]) : 14;
    FILE *hcsv = open_csv(dir, "bench_homotopy.csv",
                          "system,run,s,paths,seconds,cpu_seconds,real,real_distinct,nonreal,singular,failed,threads,"
                          "steps,rejected,retracked,duplicates,unpaired,uncertified,max_residual,max_cond");
    FILE *ccsv =
        scanmax ? open_csv(dir, "bench_completeness.csv", "model,solver,starts,seconds,found,truth,unmatched") : NULL;
    if (!hcsv || (scanmax && !ccsv)) return 1;

    printf("1. complete solver (homotopy) on random systems, %d threads\n", THREADS);
    header();
    for (int s = 2; s <= smax; ++s) {
        int m = s + 1;
        double *Q = malloc(sizeof(double) * (size_t)m * m * s), sec;
        if (!Q) return 1;
        random_system(m, s, 1000u + (unsigned)s, Q);
        homotopy(hcsv, "random", 0, m, s, Q, &sec);
        free(Q);
    }

    if (hexruns > 0) {
        printf("\n2. hexagonal sail, flat state, %d run(s)\n", hexruns);
        kin_assembly *a = test_sail(6, 2);
        int m = 0, s = 0;
        double *Q = second_order(a, &m, &s), best = INFINITY, worst = 0.0, sbest = INFINITY, sworst = 0.0, sec;
        header();
        for (int r = 0; Q && r < hexruns; ++r) { /* plain and symmetric alternately: ratios in the same minutes */
            homotopy(hcsv, "hex_flat", r, m, s, Q, &sec);
            best = fmin(best, sec), worst = fmax(worst, sec);
            double plain = sec;
            homotopy_sym(hcsv, "hex_sym", r, m, s, Q, a, &sec);
            sbest = fmin(sbest, sec), sworst = fmax(sworst, sec);
            printf("           plain / sym wall ratio %.2f\n", plain / sec);
        }
        if (Q)
            printf("plain: best %.2f s, worst %.2f s; sym (group found in the timing): best %.2f s, worst %.2f s "
                   "(wall, %d threads)\n", best, worst, sbest, sworst, THREADS);
        free(Q);
        kin_assembly_free(a);
    }

    if (scanmax) {
        printf("\n3. completeness against time: root scan (2^%d .. 2^%d starts) vs complete solver\n", SCAN_MIN_LOG2,
               scanmax);
        kin_assembly *a = test_sail(4, 1);
        completeness(hcsv, ccsv, "square flat", a, scanmax);
        kin_assembly_free(a);
        a = test_sail(6, 2);
        if (a && test_hex_to_RB(a) == KIN_OK) completeness(hcsv, ccsv, "hex R^B", a, scanmax);
        kin_assembly_free(a);
        a = test_sail(6, 2);
        completeness(hcsv, ccsv, "hex flat", a, scanmax);
        kin_assembly_free(a);
        fclose(ccsv);
    }
    fclose(hcsv);
    return 0;
}
