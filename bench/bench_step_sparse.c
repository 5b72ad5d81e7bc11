/* Path following past the dense floor: the sparse LU mode (KIN_STEP_SPARSE)
 * against the dense LU mode (KIN_STEP_LU), and the LU modes' step control.
 * Not a test: one command, several tables (and bench_step_sparse.csv):
 *
 *  sails     sail family members n = 24, loops 6..20 at the dome point of
 *            bench_step.c: mean automatic step of the dense LU and sparse
 *            modes (seconds, factorizations, halvings), one dgesdd of the
 *            same H, the largest difference between the two modes' points;
 *            growth exponents of the step cost against nfree; the sparse
 *            handle's factor entries (J0 and J with its dense rows, at
 *            set-up), stand-in re-choices and dense-row points.
 *  lattice   generated 3D truss mechanisms (blocks of the face-centred cubic
 *            lattice, every joint braced to three earlier neighbours: rigid
 *            and isostatic; one bar taken out: one internal mechanism; no
 *            supports: six rigid mechanisms, seven dense border rows) of
 *            1095 to 10290 free coordinates, followed in sparse mode from a fresh handle (no
 *            SVD anywhere); one dense dgetrf of the same size where it is
 *            affordable; resident and virtual memory of the process;
 *            factor entries, re-choices and dense-row points as for sails.
 *  order     the sparse mode's column order: COLAMD alone against the
 *            order kept at set-up (COLAMD or METIS nested dissection,
 *            whichever factors with fewer entries), on the sails and the
 *            lattices: factor entries, mean step, growth exponents
 *            (COLAMD alone at 10^4 free coordinates only in order-full).
 *  mast      generated deployable masts (triangular and square section,
 *            84 to 1180 bays, 1008 to 10620 free coordinates, base ring
 *            fixed, one face diagonal of the middle bay left out: one
 *            internal mechanism), followed in sparse mode from a fresh
 *            handle, 10 automatic steps, with the kept order and with
 *            COLAMD only; the SVD's verdict (m_internal, s, v_r / v_max)
 *            where affordable, factor entries of both orders (of J0, the
 *            matrix sparse.c factorizes: C with a unit stand-in row), of
 *            COLAMD with a three-entry border row, and of J with its dense
 *            row (set-up, "L+U rows"), stand-in re-choices and points
 *            factorized with the dense row (both runs), strain after the steps, the dense LU
 *            mode's step on the same path (<= 3000 free coordinates),
 *            memory; growth exponents.
 *  control   the LU mode's mean step on sail:24:12 and sail:24:14 with the
 *            shared step control (the SVD mode's amplitudes, libkin <=
 *            0.3.0) and with the LU modes' own (KIN_STEP_CONTROL_MODE), in
 *            dgesdd-equivalents (mean step seconds / one dgesdd of the same
 *            H, measured back to back) and per unit path length.
 *
 * usage: bench_step_sparse [OUTDIR [all|sails|lattice|control|order|order-full|mast|quick]]
 * Every table is measured once (the machine may be shared: `uptime` is
 * printed with every table); run with OPENBLAS_NUM_THREADS=1. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "model/internal.h"
#include "path/path.h"
#include "model/lapack.h"
#include "libkin.h"
#include "bench_common.h"
#include "lattice_model.h"
#include "mast_model.h"

#include <suitesparse/klu.h>

/* resident and virtual size of this process, MB (Linux /proc) */
static void memory_mb(double *rss, double *vsz)
{
    *rss = *vsz = NAN;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        double kb;
        if (sscanf(line, "VmRSS: %lf", &kb) == 1) *rss = kb / 1024.0;
        if (sscanf(line, "VmSize: %lf", &kb) == 1) *vsz = kb / 1024.0;
    }
    fclose(f);
}

/* least-squares slope of log y against log x */
static double loglog_slope(int n, const double *x, const double *y)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (x[i] > 0 && y[i] > 0 && isfinite(y[i])) {
            double lx = log(x[i]), ly = log(y[i]);
            sx += lx;
            sy += ly;
            sxx += lx * lx;
            sxy += lx * ly;
            ++k;
        }
    return k >= 2 ? (k * sxy - sx * sy) / (k * sxx - sx * sx) : NAN;
}

/* the sail member with the bar lengths of a dome lift (bench_common.h's
 * dome_lengths): strain-free by construction; checked regular by SVD
 * when check is set */
static kin_assembly *sail_dome(int n, int loops, int check)
{
    kin_sail_params p = {.size = sizeof p};
    kin_sail_params_default(&p, n, loops);
    kin_assembly *a = NULL;
    if (kin_model_sail(&p, &a, NULL, 0)) return NULL;
    kin_assembly *b = dome_lengths(a, 0.3);
    kin_assembly_free(a);
    kin_analysis an = {.size = sizeof an};
    if (b && check && !(kin_analyse(b, &an) == KIN_OK && an.m_internal == 1)) {
        kin_assembly_free(b);
        return NULL;
    }
    return b;
}

static void set_mode(kin_assembly *a, int mode, int control)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = mode;
    o.step_control = control;
    if (kin_set_options(a, &o)) printf("  (set_options: %s)\n", kin_last_error(a));
}

typedef struct run {
    double seconds, length;
    long fact, halvings, fallbacks;
    int steps, ok;
} run;

/* nsteps automatic steps; xs (may be NULL) receives every point */
static run follow(kin_assembly *a, int nsteps, double *xs)
{
    run r = {0.0, 0.0, 0, 0, 0, 0, 1};
    int n = kin_njoints(a) * kin_dim(a);
    double l0 = kin_path_length(a);
    kin_step_info info = {.size = sizeof info};
    for (; r.steps < nsteps; ++r.steps) {
        double t0 = now();
        int rc = kin_step(a, 0.0, &info);
        r.seconds += now() - t0;
        if (rc) {
            printf("  (step %d: %s)\n", r.steps, kin_last_error(a));
            r.ok = 0;
            break;
        }
        r.fact += info.factorizations;
        r.halvings += info.halvings;
        kin_analysis an = {.size = sizeof an};
        if (kin_get_analysis(a, &an) == KIN_OK) r.fallbacks++;
        if (xs) kin_get_coords(a, xs + (size_t)r.steps * n);
    }
    r.length = kin_path_length(a) - l0;
    return r;
}

/* seconds of one dgesdd (jobz 'A') of the current H */
static double dgesdd_seconds(kin_assembly *a)
{
    int nf = a->nf, nb = a->nb, info = 0;
    kin__build_H(a, a->xyz, a->A, nf);
    double t0 = now();
    dgesdd_("A", &nf, &nb, a->A, &nf, a->fac[0].sv, a->fac[0].U, &nf, a->fac[0].VT, &nb, a->work, &a->lwork,
            a->iwork, &info, 1);
    return now() - t0;
}

/* seconds of one dgetrf of an nf x nf matrix (H with random columns to make
 * it square: the size of the dense LU mode's bordered matrix) */
static double dgetrf_seconds(kin_assembly *a)
{
    int nf = a->nf, nb = a->nb, info = 0;
    double *M = malloc(sizeof(double) * (size_t)nf * (size_t)nf);
    int *ipiv = malloc(sizeof(int) * (size_t)nf);
    double t = NAN;
    if (M && ipiv) {
        kin__build_H(a, a->xyz, M, nf);
        unsigned long long st = 7;
        for (size_t i = (size_t)nf * (size_t)nb; i < (size_t)nf * (size_t)nf; ++i)
            M[i] = (double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5;
        double t0 = now();
        dgetrf_(&nf, &nf, M, &nf, ipiv, &info);
        t = now() - t0;
    }
    free(M);
    free(ipiv);
    return t;
}

static double max_abs_diff(size_t n, const double *x, const double *y)
{
    double m = 0.0;
    for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(x[i] - y[i]));
    return m;
}

/* ---- sails: dense LU against sparse -------------------------------------- */

static void sails(FILE *csv, int quick)
{
    const int loops[] = {6, 8, 10, 12, 14, 20};
    int nm = quick ? 3 : (int)(sizeof loops / sizeof loops[0]);
    double xs[8], yl[8], ys[8];
    int np = 0;
    print_load("before the sail table");
    printf("\nsail n = 24 family, dome point, %s automatic steps per mode (own step control), measured once\n",
           "12");
    printf("%4s %5s %9s | %9s %5s %5s %3s %6s | %9s %5s %5s %3s %6s | %8s | %9s %9s %4s %4s\n", "lp", "nfree",
           "dgesdd[s]", "LU st[s]", "fact", "half", "fb", "/sdd", "SP st[s]", "fact", "half", "fb", "/sdd", "|dx|", "L+U",
           "L+U rows", "rech", "dpts");
    for (int i = 0; i < nm; ++i) {
        kin_assembly *a = sail_dome(24, loops[i], 1);
        if (!a) {
            printf("%4d: no regular dome point\n", loops[i]);
            continue;
        }
        kin_step_info info = {.size = sizeof info};
        kin_step(a, 0.0, &info); /* from a point reached by a step */
        int nsteps = 12, n = 3 * kin_njoints(a), nf = kin_nfree(a);
        double *x[2] = {malloc(sizeof(double) * (size_t)n * nsteps), malloc(sizeof(double) * (size_t)n * nsteps)};
        run r[2];
        double ent = NAN, ent_rows = NAN;
        long rech = 0, dpts = 0;
        for (int m = 0; m < 2; ++m) {
            kin_assembly *b = NULL;
            kin_assembly_clone(a, &b);
            set_mode(b, m ? KIN_STEP_SPARSE : KIN_STEP_LU, KIN_STEP_CONTROL_MODE);
            kin_step(b, 0.0, &info); /* untimed: the mode's own factors at the start */
            r[m] = follow(b, nsteps, x[m]);
            if (m) kin__sparse_stats(b, &ent, &ent_rows, &rech, &dpts);
            kin_assembly_free(b);
        }
        double sdd = dgesdd_seconds(a);
        int common = r[0].steps < r[1].steps ? r[0].steps : r[1].steps;
        double dx = common ? max_abs_diff((size_t)n * common, x[0], x[1]) : NAN;
        double st[2];
        for (int m = 0; m < 2; ++m) st[m] = r[m].steps ? r[m].seconds / r[m].steps : NAN;
        printf("%4d %5d %9.3e | %9.3e %5.2f %5.2f %3ld %6.3f | %9.3e %5.2f %5.2f %3ld %6.3f | %8.1e | %9.3e %9.3e %4ld "
               "%4ld\n",
               loops[i], nf, sdd, st[0], (double)r[0].fact / r[0].steps, (double)r[0].halvings / r[0].steps,
               r[0].fallbacks, st[0] / sdd, st[1], (double)r[1].fact / r[1].steps, (double)r[1].halvings / r[1].steps,
               r[1].fallbacks, st[1] / sdd, dx, ent, ent_rows, rech, dpts);
        fprintf(csv, "sails,%d,%d,%d,%.6e,%.6e,%.3f,%.3f,%ld,%.6e,%.3f,%.3f,%ld,%.3e,NAN,NAN,NAN\n", 24, loops[i], nf,
                sdd, st[0], (double)r[0].fact / r[0].steps, (double)r[0].halvings / r[0].steps, r[0].fallbacks, st[1],
                (double)r[1].fact / r[1].steps, (double)r[1].halvings / r[1].steps, r[1].fallbacks, dx);
        fflush(stdout);
        fflush(csv);
        if (r[0].ok && r[1].ok && np < 8) {
            xs[np] = nf;
            yl[np] = st[0];
            ys[np] = st[1];
            ++np;
        }
        free(x[0]);
        free(x[1]);
        kin_assembly_free(a);
    }
    printf("growth exponent of the mean step (time ~ nfree^p, log-log fit over %d members): dense LU %.2f, sparse "
           "%.2f\n",
           np, loglog_slope(np, xs, yl), loglog_slope(np, xs, ys));
    print_load("after the sail table");
}

static void lattices(FILE *csv, int quick)
{
    const int dims[][3] = {{9, 9, 9}, {11, 11, 11}, {13, 13, 13}, {15, 15, 15}, {19, 19, 19}};
    int nm = quick ? 2 : (int)(sizeof dims / sizeof dims[0]);
    double xs[8], ys[8], yd[8];
    int np = 0, nd = 0;
    print_load("before the lattice table");
    printf("\n3D lattice mechanisms (one internal, six rigid mechanisms), sparse mode from a fresh handle, %d automatic "
           "steps, measured once\n", 10);
    printf("%10s %6s %6s | %9s %9s %5s %5s %3s %6s | %9s | %8s %8s | %9s %9s %4s %4s\n", "grid", "nfree", "nbars",
           "start[s]", "SP st[s]", "fact", "half", "fb", "strain", "dgetrf[s]", "RSS[MB]", "VM[MB]", "L+U", "L+U rows",
           "rech", "dpts");
    for (int i = 0; i < nm; ++i) {
        kin_assembly *a = lattice(dims[i][0], dims[i][1], dims[i][2]);
        if (!a) continue;
        int nf = kin_nfree(a);
        double t0 = now();
        set_mode(a, KIN_STEP_SPARSE, KIN_STEP_CONTROL_MODE);
        kin_step_info info = {.size = sizeof info};
        int rc = kin_step(a, 0.0, &info); /* sparse start + first step */
        double start = now() - t0;
        run r = {0.0, 0.0, 0, 0, 0, 0, 0};
        if (rc == KIN_OK) r = follow(a, 10, NULL);
        else printf("  (first step: %s)\n", kin_last_error(a));
        double rss, vsz, ent = NAN, ent_rows = NAN;
        long rech = 0, dpts = 0;
        memory_mb(&rss, &vsz);
        kin__sparse_stats(a, &ent, &ent_rows, &rech, &dpts);
        /* a dense LU of the same size where it is affordable (<= 5200) */
        double lu = nf <= 5200 ? dgetrf_seconds(a) : NAN;
        double st = r.steps ? r.seconds / r.steps : NAN;
        char grid[32];
        snprintf(grid, sizeof grid, "%dx%dx%d", dims[i][0], dims[i][1], dims[i][2]);
        printf("%10s %6d %6d | %9.3e %9.3e %5.2f %5.2f %3ld %6.0e | %9.3e | %8.0f %8.0f | %9.3e %9.3e %4ld %4ld\n", grid,
               nf, kin_nbars(a), start, st, r.steps ? (double)r.fact / r.steps : NAN,
               r.steps ? (double)r.halvings / r.steps : NAN, r.fallbacks, kin_max_strain(a), lu, rss, vsz, ent,
               ent_rows, rech, dpts);
        fprintf(csv, "lattice,%d,%d,%d,NAN,NAN,NAN,NAN,0,%.6e,%.3f,%.3f,%ld,NAN,%.6e,%.0f,%.0f\n", dims[i][0],
                dims[i][1] * dims[i][2], nf, st, r.steps ? (double)r.fact / r.steps : NAN,
                r.steps ? (double)r.halvings / r.steps : NAN, r.fallbacks, lu, rss, vsz);
        fflush(stdout);
        fflush(csv);
        if (r.ok && r.steps && np < 8) {
            xs[np] = nf;
            ys[np] = st;
            ++np;
        }
        if (isfinite(lu) && nd < 8) yd[nd++] = lu;
        kin_assembly_free(a);
    }
    printf("growth exponent (log-log fit over %d sizes): sparse mean step %.2f; dense dgetrf %.2f (%d sizes)\n", np,
           loglog_slope(np, xs, ys), loglog_slope(nd, xs, yd), nd);
    print_load("after the lattice table");
}

/* ---- the LU mode's step control, before and after ------------------------- */

static void control(FILE *csv)
{
    const int loops[] = {12, 14};
    print_load("before the control table");
    printf("\nLU mode (dense), sail n = 24, dome point, 24 automatic steps: shared step control (before) and the LU "
           "modes' own (after), measured once\n");
    printf("%4s %5s %9s | %-7s %5s %5s %9s %7s %9s\n", "lp", "nfree", "dgesdd[s]", "control", "fact", "half",
           "step[s]", "/sdd", "/sdd/len");
    for (int i = 0; i < 2; ++i) {
        kin_assembly *a = sail_dome(24, loops[i], 1);
        if (!a) continue;
        kin_step_info info = {.size = sizeof info};
        kin_step(a, 0.0, &info);
        for (int c = 0; c < 2; ++c) {
            kin_assembly *b = NULL;
            kin_assembly_clone(a, &b);
            set_mode(b, KIN_STEP_LU, c ? KIN_STEP_CONTROL_MODE : KIN_STEP_CONTROL_SHARED);
            kin_step(b, 0.0, &info);
            run r = follow(b, 24, NULL);
            double sdd = dgesdd_seconds(b); /* back to back with the run */
            double st = r.seconds / r.steps;
            printf("%4d %5d %9.3e | %-7s %5.2f %5.2f %9.3e %7.3f %9.3f\n", loops[i], kin_nfree(a), sdd,
                   c ? "own" : "shared", (double)r.fact / r.steps, (double)r.halvings / r.steps, st, st / sdd,
                   r.seconds / sdd / r.length);
            fprintf(csv, "control_%s,24,%d,%d,%.6e,%.6e,%.3f,%.3f,%ld,NAN,NAN,NAN,0,NAN,NAN,NAN,%.6e\n",
                    c ? "own" : "shared", loops[i], kin_nfree(a), sdd, st, (double)r.fact / r.steps,
                    (double)r.halvings / r.steps, r.fallbacks, r.seconds / sdd / r.length);
            fflush(stdout);
            kin_assembly_free(b);
        }
        kin_assembly_free(a);
    }
    print_load("after the control table");
}

/* ---- the sparse mode's column order: COLAMD against nested dissection ---- */

/* one structure in sparse mode with the order kin__sparse_prepare keeps
 * (nd_allowed) or with COLAMD only: factor entries, start, mean step */
typedef struct order_run {
    int nested;
    double entries_colamd, entries_nd, start, step;
    run r;
} order_run;

static order_run order_follow(kin_assembly *a, int nd_allowed, int nsteps)
{
    order_run o = {0, NAN, NAN, NAN, NAN, {0.0, 0.0, 0, 0, 0, 0, 0}};
    kin_assembly *b = NULL;
    if (kin_assembly_clone(a, &b)) return o;
    if (!nd_allowed) kin__set_fault(b, KIN__FAULT_SPARSE_NO_ND);
    double t0 = now();
    set_mode(b, KIN_STEP_SPARSE, KIN_STEP_CONTROL_MODE);
    kin_step_info info = {.size = sizeof info};
    int rc = kin_step(b, 0.0, &info);
    o.start = now() - t0;
    o.nested = kin__sparse_order(b, &o.entries_colamd, &o.entries_nd);
    if (rc == KIN_OK) o.r = follow(b, nsteps, NULL);
    o.step = o.r.steps ? o.r.seconds / o.r.steps : NAN;
    kin_assembly_free(b);
    return o;
}

static void orders(FILE *csv, int quick, int full)
{
    const int loops[] = {6, 8, 10, 12, 14, 20};
    const int dims[][3] = {{9, 9, 9}, {11, 11, 11}, {13, 13, 13}, {15, 15, 15}, {19, 19, 19}};
    int ns = quick ? 2 : 6, nl = quick ? 2 : 5;
    double xs[16], yc[16], yk[16];
    print_load("before the order table");
    printf("\nsparse mode, column order: COLAMD only against the order kept at set-up (COLAMD or METIS nested "
           "dissection, whichever has fewer factor entries); 10 automatic steps each, measured once\n");
    printf("%-14s %6s | %10s %10s %5s | %9s %9s | %9s %9s | %6s\n", "structure", "nfree", "L+U colamd", "L+U nd",
           "kept", "COL st[s]", "kept st[s]", "COL start", "kept strt", "speedup");
    for (int fam = 0; fam < 2; ++fam) {
        int n = fam ? nl : ns, np = 0;
        for (int i = 0; i < n; ++i) {
            kin_assembly *a = fam ? lattice(dims[i][0], dims[i][1], dims[i][2]) : sail_dome(24, loops[i], 1);
            if (!a) continue;
            if (!fam) {
                kin_step_info info = {.size = sizeof info};
                kin_step(a, 0.0, &info);
            }
            int nf = kin_nfree(a);
            /* COLAMD alone at 10^4 free coordinates costs minutes: only with
             * `order-full` */
            int big = fam && nf > 6000 && !full;
            order_run c = big ? (order_run){0, NAN, NAN, NAN, NAN, {0.0, 0.0, 0, 0, 0, 0, 0}} : order_follow(a, 0, 10);
            order_run k = order_follow(a, 1, 10);
            char name[32];
            if (fam) snprintf(name, sizeof name, "lattice %d^3", dims[i][0]);
            else snprintf(name, sizeof name, "sail 24x%d", loops[i]);
            printf("%-14s %6d | %10.3e %10.3e %5s | %9.3e %9.3e | %9.3e %9.3e | %6.2f\n", name, nf, k.entries_colamd,
                   k.entries_nd, k.nested ? "ND" : "COL", c.step, k.step, c.start, k.start, c.step / k.step);
            fprintf(csv, "order_%s,%d,%d,%d,NAN,%.6e,%.6e,%.0f,%d,%.6e,%.6e,NAN,0,NAN,NAN,NAN,NAN\n",
                    fam ? "lattice" : "sails", fam ? dims[i][0] : 24, fam ? dims[i][0] : loops[i], nf, c.step,
                    k.entries_colamd, k.entries_nd, k.nested, k.step, k.start);
            fflush(stdout);
            fflush(csv);
            if (k.r.ok && k.r.steps && np < 16) {
                xs[np] = nf;
                yk[np] = k.step;
                yc[np] = c.step;
                ++np;
            }
            kin_assembly_free(a);
        }
        int npc = np;
        while (npc > 0 && !isfinite(yc[npc - 1])) --npc;
        printf("growth exponent of the mean step, %s (log-log fit): COLAMD only %.2f (%d sizes), kept order %.2f (%d "
               "sizes)\n",
               fam ? "lattices" : "sails", loglog_slope(npc, xs, yc), npc, loglog_slope(np, xs, yk), np);
    }
    print_load("after the order table");
}

/* ---- deployable masts: long, slender 3D trusses ---------------------------- */


/* Factor entries of the mast's J under COLAMD with the KLU settings of
 * sparse.c, but with the dense border row replaced by a sparse one (random
 * entries at the last three free coordinates, the top joint's, which the
 * mechanism moves): how much of the fill the dense border row causes. NAN
 * when KLU fails (a singular J). */
static double entries_sparse_border(const kin_assembly *a)
{
    int nf = a->nf, nb = a->nb, nz = 0;
    int *Ap = calloc((size_t)nf + 1, sizeof *Ap), *Ai = malloc(sizeof(int) * ((size_t)nb * 6 + 3));
    double *Ax = malloc(sizeof(double) * ((size_t)nb * 6 + 3)), e = NAN;
    if (!Ap || !Ai || !Ax) goto done;
    /* columns are free coordinates: gather each column's bar rows */
    for (int j = 0; j < a->nj; ++j)
        for (int c = 0; c < 3; ++c) {
            int col = a->free_index[3 * j + c];
            if (col < 0) continue;
            Ap[col] = nz;
            for (int k = 0; k < nb; ++k) {
                int ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
                if (ja != j && jb != j) continue;
                double v[3];
                for (int q = 0; q < 3; ++q) v[q] = a->xyz[3 * ja + q] - a->xyz[3 * jb + q];
                Ai[nz] = k;
                Ax[nz++] = (ja == j ? 1.0 : -1.0) * v[c] / kin__norm(3, v);
            }
            if (col >= nf - 3) {
                Ai[nz] = nb;
                Ax[nz++] = 0.25 + 0.5 * (nf - col);
            }
        }
    Ap[nf] = nz;
    klu_common cm;
    klu_defaults(&cm);
    cm.ordering = 1;
    cm.btf = 0;
    cm.tol = 1.0;
    klu_symbolic *sym = klu_analyze(nf, Ap, Ai, &cm);
    klu_numeric *num = sym ? klu_factor(Ap, Ai, Ax, sym, &cm) : NULL;
    if (num) e = (double)num->lnz + (double)num->unz;
    if (num) klu_free_numeric(&num, &cm);
    if (sym) klu_free_symbolic(&sym, &cm);
done:
    free(Ap);
    free(Ai);
    free(Ax);
    return e;
}

/* The slender-structure setting of the mast table: a mast's v_r / v_max
 * falls as bays^-2 (measured: 4.6e-5 at 112 bays by SVD,
 * 4.3e-7 estimated at 1180), under the LU modes' default SVD threshold
 * (1000 * rank_tol = 1e-6) from ~750 bays on, although nowhere near a
 * bifurcation; 1e-11 moves the threshold to 1e-8. */
static const double MAST_RANK_TOL = 1e-11;

static void set_mast_options(kin_assembly *a, int mode)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.rank_tol = MAST_RANK_TOL;
    o.factorization = mode;
    o.step_control = KIN_STEP_CONTROL_MODE;
    if (kin_set_options(a, &o)) printf("  (set_options: %s)\n", kin_last_error(a));
}

static double joint_distance(const kin_assembly *a, const int ends[2])
{
    const double *p = a->xyz + 3 * ends[0], *q = a->xyz + 3 * ends[1];
    double v[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    return kin__norm(3, v);
}

/* one mast member in sparse mode from a fresh handle, with the order kept
 * at set-up (nd_allowed) or COLAMD only; the dense LU mode's mean step of
 * `dense` steps taken next on the same handle (0: none) */
typedef struct mast_run {
    order_run o;
    double strain, gap0, gap1, vr_est, rss, vsz, dense_step, entries_sb, entries_rows;
    long dense_fact, dense_fallbacks, rechoices, dense_points;
} mast_run;

static mast_run mast_follow(int sides, int nbays, int nd_allowed, int nsteps, int dense)
{
    mast_run m = {{0, NAN, NAN, NAN, NAN, {0.0, 0.0, 0, 0, 0, 0, 0}}, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN, 0, 0, 0, 0};
    int ends[2];
    kin_assembly *a = test_mast(sides, nbays, ends);
    if (!a) return m;
    if (!nd_allowed) kin__set_fault(a, KIN__FAULT_SPARSE_NO_ND);
    m.gap0 = joint_distance(a, ends);
    if (nd_allowed) m.entries_sb = entries_sparse_border(a);
    double t0 = now();
    set_mast_options(a, KIN_STEP_SPARSE);
    kin_step_info info = {.size = sizeof info};
    int rc = kin_step(a, 0.0, &info); /* sparse start + first step */
    m.o.start = now() - t0;
    m.o.nested = kin__sparse_order(a, &m.o.entries_colamd, &m.o.entries_nd);
    if (rc == KIN_OK) m.o.r = follow(a, nsteps, NULL);
    else printf("  (first step: %s)\n", kin_last_error(a));
    m.o.step = m.o.r.steps ? m.o.r.seconds / m.o.r.steps : NAN;
    double entries_kept = NAN;
    kin__sparse_stats(a, &entries_kept, &m.entries_rows, &m.rechoices, &m.dense_points);
    m.strain = kin_max_strain(a);
    m.gap1 = joint_distance(a, ends);
    const kin_lufactor *f = &a->lu[a->lu_cur];
    m.vr_est = f->valid ? f->v_r / f->v_max : NAN;
    memory_mb(&m.rss, &m.vsz);
    if (dense && m.o.r.ok) {
        set_mast_options(a, KIN_STEP_LU); /* keeps the path state */
        kin_step(a, 0.0, &info);          /* untimed: the dense factors of the start */
        run d = follow(a, dense, NULL);
        m.dense_step = d.ok && d.steps ? d.seconds / d.steps : NAN;
        m.dense_fact = d.fact;
        m.dense_fallbacks = d.fallbacks;
    }
    kin_assembly_free(a);
    return m;
}

static void masts(FILE *csv, int quick)
{
    /* 9 (triangle) and 12 (square) free coordinates per bay: ~1000 to ~10600 */
    const int bays[2][6] = {{112, 180, 288, 460, 736, 1180}, {84, 135, 216, 345, 552, 885}};
    int nm = quick ? 2 : 6;
    print_load("before the mast table");
    printf("\ndeployable masts (base ring fixed, one face diagonal of the middle bay left out: one internal "
           "mechanism), rank_tol %.0e, sparse mode from a fresh handle, 10 automatic steps, measured once\n",
           MAST_RANK_TOL);
    printf("%-5s %5s %6s | %8s %3s %3s %8s | %9s %9s %4s %9s | %8s %9s %9s %5s %5s %3s | %7s %8s %8s | %9s %5s %6s | "
           "%6s %6s | %9s %4s %4s\n",
           "mast", "bays", "nfree", "svd vr", "mi", "s", "LU vr", "L+U col", "L+U nd", "kept", "L+U sb", "start[s]", "COL st[s]",
           "kept st", "fact", "half", "fb", "strain", "gap0", "gap1", "LU st[s]", "fb", "LU/SP", "RSS", "VM[MB]", "L+U rows", "rech", "dpts");
    for (int fam = 0; fam < 2; ++fam) {
        int sides = fam ? 4 : 3, np = 0, npd = 0;
        double xs[8], yk[8], yc[8], ye[8], ys[8], xd[8], yd[8];
        for (int i = 0; i < nm; ++i) {
            int nb = bays[fam][i], nf = 3 * sides * nb;
            /* the SVD's verdict where it is affordable: one internal
             * mechanism, no self-stress, and the v_r / v_max the LU
             * estimates are checked against */
            kin_analysis an = {.size = sizeof an};
            an.m_internal = an.s = -1;
            an.v_r = NAN;
            an.v_max = 1.0;
            if (nf <= 1700) {
                kin_assembly *c = test_mast(sides, nb, NULL);
                if (!c || kin_analyse(c, &an) != KIN_OK) printf("  (analysis failed)\n");
                kin_assembly_free(c);
            }
            mast_run c = mast_follow(sides, nb, 0, 10, 0);
            mast_run k = mast_follow(sides, nb, 1, 10, nf <= 3000 ? 2 : 0);
            printf("%-5s %5d %6d | %8.1e %3d %3d %8.1e | %9.3e %9.3e %4s %9.3e | %8.3f %9.3e %9.3e %5.2f %5.2f %3ld | %7.0e "
                   "%8.5f %8.5f | %9.3e %5ld %6.1f | %6.0f %6.0f | %9.3e %4ld %4ld\n",
                   sides == 3 ? "tri" : "square", nb, nf, an.v_r / an.v_max, an.m_internal, an.s, k.vr_est,
                   k.o.entries_colamd, k.o.entries_nd, k.o.nested ? "ND" : "COL", k.entries_sb, k.o.start, c.o.step, k.o.step,
                   k.o.r.steps ? (double)k.o.r.fact / k.o.r.steps : NAN,
                   k.o.r.steps ? (double)k.o.r.halvings / k.o.r.steps : NAN, k.o.r.fallbacks + c.o.r.fallbacks,
                   k.strain, k.gap0, k.gap1, k.dense_step, k.dense_fallbacks, k.dense_step / k.o.step, k.rss, k.vsz,
                   k.entries_rows, k.rechoices + c.rechoices, k.dense_points + c.dense_points);
            /* mast rows: max_dx is the COLAMD-only mean step, dgetrf_s the
             * kept order's factor entries */
            fprintf(csv, "mast_%s,%d,%d,%d,NAN,%.6e,%.3f,NAN,%ld,%.6e,%.3f,%.3f,%ld,%.6e,%.0f,%.0f,%.0f\n",
                    sides == 3 ? "tri" : "square", sides, nb, nf, k.dense_step,
                    (double)k.dense_fact / 2, k.dense_fallbacks, k.o.step,
                    k.o.r.steps ? (double)k.o.r.fact / k.o.r.steps : NAN,
                    k.o.r.steps ? (double)k.o.r.halvings / k.o.r.steps : NAN, k.o.r.fallbacks, c.o.step,
                    k.o.nested ? k.o.entries_nd : k.o.entries_colamd, k.rss, k.vsz);
            fflush(stdout);
            fflush(csv);
            if (k.o.r.ok && k.o.r.steps == 10 && c.o.r.ok && c.o.r.steps == 10 && np < 8) {
                xs[np] = nf;
                yk[np] = k.o.step;
                yc[np] = c.o.step;
                ye[np] = k.o.nested ? k.o.entries_nd : k.o.entries_colamd;
                ys[np] = k.entries_sb;
                ++np;
            }
            if (isfinite(k.dense_step) && npd < 8) {
                xd[npd] = nf;
                yd[npd++] = k.dense_step;
            }
        }
        printf("growth exponents, %s masts (log-log fit over %d sizes): mean step, kept order %.2f, COLAMD only %.2f; "
               "L+U entries, kept %.2f, COLAMD with a sparse border row %.2f; dense LU step %.2f (%d sizes)\n",
               sides == 3 ? "triangular" : "square", np, loglog_slope(np, xs, yk), loglog_slope(np, xs, yc),
               loglog_slope(np, xs, ye), loglog_slope(np, xs, ys), loglog_slope(npd, xd, yd), npd);
    }
    print_load("after the mast table");
}

int main(int argc, char **argv)
{
    print_blas();
    const char *dir = argc > 1 ? argv[1] : ".";
    const char *what = argc > 2 ? argv[2] : "all";
    int quick = strcmp(what, "quick") == 0, all = quick || strcmp(what, "all") == 0;
    char path[1024];
    snprintf(path, sizeof path, "%s/bench_step_sparse.csv", dir);
    FILE *csv = fopen(path, "w");
    if (!csv) {
        fprintf(stderr, "cannot write %s\n", path);
        return 1;
    }
    /* columns: table, n (or nx), loops (or ny*nz), nfree, dgesdd_s, lu_step_s, lu_fact, lu_halvings,
     * lu_fallbacks, sparse_step_s, sparse_fact, sparse_halvings, sparse_fallbacks, max_dx, dgetrf_s, rss_mb,
     * vm_mb (control rows: the last column is dgesdd-equivalents per unit length; mast rows: n is the
     * number of sides, loops the number of bays, max_dx the COLAMD-only mean step, dgetrf_s the kept
     * order's factor entries) */
    fprintf(csv, "table,n,loops,nfree,dgesdd_s,lu_step_s,lu_fact,lu_halvings,lu_fallbacks,sparse_step_s,sparse_fact,"
                 "sparse_halvings,sparse_fallbacks,max_dx,dgetrf_s,rss_mb,vm_mb\n");
    if (all || strcmp(what, "control") == 0) control(csv);
    if (all || strcmp(what, "sails") == 0) sails(csv, quick);
    if (all || strcmp(what, "lattice") == 0) lattices(csv, quick);
    if (all || strncmp(what, "order", 5) == 0) orders(csv, quick, strcmp(what, "order-full") == 0);
    if (all || strcmp(what, "mast") == 0) masts(csv, quick);
    fclose(csv);
    return 0;
}
