/* Path following: cost and accuracy of the two factorization modes of
 * kin_step (kin_options.factorization: KIN_STEP_SVD, the default, and
 * KIN_STEP_LU). Not a test: prints tables and writes CSV files for
 * bench/plot_step.py.
 *
 *  scaling  sail family members of growing size (hub n = 6..24, loops
 *           1..20, 28..1045 free coordinates) at a generic point: seconds
 *           per step in both modes and of one dgesdd of the same H (jobz 'A',
 *           what the SVD mode does) and one dgetrf of the same-size bordered
 *           matrix, measured back to back in each of `reps` rounds; ratios
 *           per round; factorizations per step; the largest difference
 *           between the two modes' points after the same steps.
 *           -> bench_step_scaling.csv
 *  pareto   out and back along the path (step fraction x corrector tol) in
 *           both modes on the hexagonal sail and one larger member: seconds
 *           per unit path length (best of `reps` runs and the spread), max
 *           bar strain, closure error, max distance between the two modes'
 *           points after the same steps. -> bench_step_pareto.csv
 *
 * usage: bench_step [OUTDIR [REPS [all|scaling|pareto|quick]]]   (REPS
 * default 3; quick: the smaller members and the hexagonal sail only). Run
 * with OPENBLAS_NUM_THREADS=1 on a shared machine (see docs/performance.md). */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

/* The hexagonal sail's generic point of the earlier benchmark: lift the free
 * nodes pseudo-randomly and relax; try smaller lifts until the relaxed point
 * has a single internal mechanism. */
static int generic(kin_assembly *a, double amp)
{
    const double amps[] = {amp, amp / 3, amp / 6, amp / 15};
    kin_assembly *flat = NULL;
    if (kin_assembly_clone(a, &flat)) return KIN_ENOMEM;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)kin_njoints(a));
    int rc = KIN_ENOTCONVERGED;
    for (size_t i = 0; xyz && i < sizeof amps / sizeof amps[0]; ++i) {
        kin_analysis an = {.size = sizeof an};
        kin_get_coords(flat, xyz);
        kin_set_coords(a, xyz);
        if (test_make_generic(a, amps[i]) == KIN_OK && kin_analyse(a, &an) == KIN_OK && an.m_internal == 1) {
            rc = KIN_OK;
            break;
        }
    }
    free(xyz);
    kin_assembly_free(flat);
    return rc;
}

/* *pa replaced by its dome member (bench_common.h, dome_lengths) if that is a
 * regular point (m_internal = 1): for timing, a member of the same topology
 * and matrix sizes is just as representative as the degenerate flat state. */
static int generic_by_lengths(kin_assembly **pa, double amp)
{
    kin_assembly *b = dome_lengths(*pa, amp);
    if (!b) return KIN_ENOMEM;
    kin_analysis an = {.size = sizeof an};
    if (kin_analyse(b, &an) == KIN_OK && an.m_internal == 1) {
        kin_assembly_free(*pa);
        *pa = b;
        return KIN_OK;
    }
    kin_assembly_free(b);
    return KIN_ENOMECH;
}

static kin_assembly *copy_in_mode(const kin_assembly *a, int mode)
{
    kin_assembly *b = NULL;
    if (kin_assembly_clone(a, &b)) return NULL;
    kin_options o = {.size = sizeof o};
    kin_get_options(b, &o);
    o.factorization = mode;
    /* the SVD mode's step amplitudes in both modes: this program compares
     * the modes' points after the same steps (the LU modes' own control is
     * measured by bench_step_sparse.c) */
    o.step_control = KIN_STEP_CONTROL_SHARED;
    kin_set_options(b, &o);
    return b;
}

/* seconds of one dgesdd (jobz = 'A') of the current H, best of reps */
static double svd_seconds(kin_assembly *a, int reps)
{
    int nf = a->nf, nb = a->nb, info = 0;
    double best = 1e300;
    for (int r = 0; r < reps; ++r) {
        kin__build_H(a, a->xyz, a->A, nf);
        double t0 = now();
        dgesdd_("A", &nf, &nb, a->A, &nf, a->fac[0].sv, a->fac[0].U, &nf, a->fac[0].VT, &nb, a->work,
                &a->lwork, a->iwork, &info, 1);
        best = fmin(best, now() - t0);
    }
    return best;
}

/* seconds of one dgetrf of an nf x nf bordered matrix [H, t, R] of the
 * current point (R: rigid mechanisms; random columns make up the size when
 * the matrix would not be square), best of reps */
static double lu_seconds(kin_assembly *a, int reps)
{
    int nf = a->nf, nb = a->nb, info = 0, mr = 0;
    double best = 1e300;
    double *M = malloc(sizeof(double) * (size_t)nf * (size_t)nf);
    int *ipiv = malloc(sizeof(int) * (size_t)nf);
    unsigned long long st = 7;
    if (!M || !ipiv || kin__rigid_basis(a, a->xyz, a->luR, &mr)) reps = 0;
    for (int r = 0; r < reps; ++r) {
        int cols = nb < nf ? nb : nf;
        kin__build_H(a, a->xyz, a->A, nf);
        memcpy(M, a->A, sizeof(double) * (size_t)nf * (size_t)cols);
        for (int c = cols; c < nf; ++c)
            for (int i = 0; i < nf; ++i)
                M[i + (size_t)c * nf] = c == cols ? a->t[i]
                                        : c - cols - 1 < mr ? a->luR[i + (size_t)(c - cols - 1) * nf]
                                                            : (double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5;
        double t0 = now();
        dgetrf_(&nf, &nf, M, &nf, ipiv, &info);
        best = fmin(best, now() - t0);
    }
    free(M);
    free(ipiv);
    return reps ? best : NAN;
}

typedef struct run_stats {
    double seconds, max_strain;
    long fact, iters, fallbacks, halvings;
    int steps, ok;
    double reg_seconds; /* steps with one factorization and no halving */
    int reg_steps;
} run_stats;

/* nsteps default steps of b; xs (3*nj*nsteps, may be NULL) receives the
 * point after every step */
static run_stats follow(kin_assembly *b, int nsteps, double *xs)
{
    run_stats s = {0.0, 0.0, 0, 0, 0, 0, 0, 1, 0.0, 0};
    int n = kin_njoints(b) * kin_dim(b);
    kin_step_info info = {.size = sizeof info};
    for (; s.steps < nsteps; ++s.steps) {
        double t0 = now();
        int rc = kin_step(b, 0.0, &info);
        double dt = now() - t0;
        s.seconds += dt;
        if (rc) {
            s.ok = 0;
            break;
        }
        if (info.factorizations == 1 && info.halvings == 0) {
            s.reg_seconds += dt;
            s.reg_steps++;
        }
        s.halvings += info.halvings;
        s.fact += info.factorizations;
        s.iters += info.iterations;
        s.max_strain = fmax(s.max_strain, kin_max_strain(b));
        /* a fallback leaves the SVD analysis current (LU mode) */
        kin_analysis an = {.size = sizeof an};
        if (b->opt.factorization == KIN_STEP_LU && kin_get_analysis(b, &an) == KIN_OK) s.fallbacks++;
        if (xs) kin_get_coords(b, xs + (size_t)s.steps * n);
    }
    return s;
}

static double max_abs_diff(size_t n, const double *x, const double *y)
{
    double m = 0.0;
    for (size_t i = 0; i < n; ++i) m = fmax(m, fabs(x[i] - y[i]));
    return m;
}

/* least-squares slope of log y against log x over points with x >= xmin */
static double loglog_slope(int n, const double *x, const double *y, double xmin)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int k = 0;
    for (int i = 0; i < n; ++i)
        if (x[i] >= xmin && y[i] > 0 && isfinite(y[i])) {
            double lx = log(x[i]), ly = log(y[i]);
            sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly;
            ++k;
        }
    return k >= 2 ? (k * sxy - sx * sy) / (k * sxx - sx * sx) : NAN;
}

enum { MAX_MEMBERS = 32 };

static void scaling(FILE *csv, int reps, int quick)
{
    const int members[][2] = {{6, 1},   {6, 2},  {8, 2},  {6, 4},   {12, 2},  {8, 5},
                              {12, 4},  {16, 4}, {12, 8}, {6, 20},  {16, 8},  {24, 6},
                              {20, 10}, {12, 20}, {24, 12}, {24, 14}};
    int nmem = (int)(sizeof members / sizeof members[0]);
    if (quick) nmem = 8;
    /* for the growth exponents: nfree, and per mode the mean step and the
     * regular step (one factorization, no halving); dgesdd */
    double xs[MAX_MEMBERS], y[5][MAX_MEMBERS];
    int np = 0;
    printf("\nstep cost against one dgesdd of the same H (generic dome point, default step; best of %d rounds; "
           "ratio: mean step / dgesdd (range over rounds); reg: regular steps only)\n", reps);
    printf("%3s %3s %5s %9s | %9s %5s %4s %4s %11s %5s | %9s %5s %4s %3s %11s %5s | %9s %7s %7s %8s %7s\n", "n", "lp",
           "nfree", "dgesdd[s]", "SVD st[s]", "fact", "half", "iter", "ratio", "reg", "LU st[s]", "fact", "half", "fb",
           "ratio", "reg", "dgetrf[s]", "|dx|", "strain", "vr/vmax", "vr err");
    fprintf(csv, "n,loops,nfree,nbars,steps,reps,dgesdd_s,dgesdd_spread,dgetrf_s,svd_step_s,svd_step_spread,"
                 "lu_step_s,lu_step_spread,ratio_svd,ratio_svd_min,ratio_svd_max,ratio_lu,ratio_lu_min,"
                 "ratio_lu_max,reg_ratio_svd,reg_ratio_lu,reg_steps_svd,reg_steps_lu,fact_svd,fact_lu,"
                 "halvings_svd,halvings_lu,iter_svd,iter_lu,fallbacks_lu,max_dx,strain_svd,strain_lu,"
                 "vr_rel_start,vr_estimate_relerr\n");
    for (int i = 0; i < nmem; ++i) {
        kin_sail_params p = {.size = sizeof p};
        kin_sail_params_default(&p, members[i][0], members[i][1]);
        kin_assembly *a = NULL;
        if (kin_model_sail(&p, &a, NULL, 0)) continue;
        if (generic_by_lengths(&a, 0.3) != KIN_OK) {
            printf("%3d %3d: could not build a generic state\n", members[i][0], members[i][1]);
            kin_assembly_free(a);
            continue;
        }
        kin_step_info info = {.size = sizeof info};
        /* warm-up: one step, so that every timed step starts from a point
         * reached by a step */
        if (kin_step(a, 0.0, &info)) {
            printf("%3d %3d: warm-up step failed: %s\n", members[i][0], members[i][1], kin_last_error(a));
            kin_assembly_free(a);
            continue;
        }
        kin_analysis an = {.size = sizeof an};
        kin_analyse(a, &an);
        double vr_rel = an.v_r / an.v_max;
        int nf = kin_nfree(a), nsteps = nf > 600 ? 6 : nf > 250 ? 12 : 30;
        size_t n = 3 * (size_t)kin_njoints(a);
        double *x_svd = malloc(sizeof(double) * n * (size_t)nsteps), *x_lu = malloc(sizeof(double) * n * (size_t)nsteps);
        /* per mode (0 SVD, 1 LU): best and worst mean step, ratio range, best regular step */
        double best[2] = {1e300, 1e300}, worst[2] = {0, 0}, rmin[2] = {1e300, 1e300}, rmax[2] = {0, 0};
        double reg[2] = {1e300, 1e300}, best_sdd = 1e300, worst_sdd = 0, lu_fact_s = NAN;
        run_stats st[2];
        memset(st, 0, sizeof st);
        for (int r = 0; r < reps; ++r) {
            /* each mode from its own copy; one untimed step gives the LU
             * mode the bordered factors of its start point (a's SVD would
             * make its first timed step use the SVD chord) */
            kin_assembly *b[2] = {copy_in_mode(a, KIN_STEP_SVD), copy_in_mode(a, KIN_STEP_LU)};
            double per[2];
            for (int mode = 0; mode < 2; ++mode) {
                kin_step(b[mode], 0.0, &info);
                run_stats t = follow(b[mode], nsteps, r == 0 ? (mode ? x_lu : x_svd) : NULL);
                if (r == 0) st[mode] = t;
                per[mode] = t.steps ? t.seconds / t.steps : NAN;
                if (t.reg_steps) reg[mode] = fmin(reg[mode], t.reg_seconds / t.reg_steps);
            }
            double sdd = svd_seconds(b[0], nf > 600 ? 1 : 3);
            if (r == 0) lu_fact_s = lu_seconds(b[0], nf > 600 ? 1 : 3);
            best_sdd = fmin(best_sdd, sdd);
            worst_sdd = fmax(worst_sdd, sdd);
            for (int mode = 0; mode < 2; ++mode) {
                best[mode] = fmin(best[mode], per[mode]);
                worst[mode] = fmax(worst[mode], per[mode]);
                rmin[mode] = fmin(rmin[mode], per[mode] / sdd);
                rmax[mode] = fmax(rmax[mode], per[mode] / sdd);
            }
            kin_assembly_free(b[0]);
            kin_assembly_free(b[1]);
        }
        int common = st[0].steps < st[1].steps ? st[0].steps : st[1].steps;
        double dx = common ? max_abs_diff(n * (size_t)common, x_svd, x_lu) : NAN;
        /* the LU mode's v_r estimate against the SVD of the same points
         * (untimed: a copy is analysed after every step) */
        double vr_err = 0.0;
        {
            kin_assembly *b = copy_in_mode(a, KIN_STEP_LU);
            for (int k = 0; k < 6 && kin_step(b, 0.0, &info) == KIN_OK; ++k) {
                kin_assembly *c = NULL;
                if (k == 0 || kin_get_analysis(b, &an) == KIN_OK || kin_assembly_clone(b, &c)) {
                    kin_assembly_free(c);
                    continue;
                }
                if (kin_analyse(c, &an) == KIN_OK) vr_err = fmax(vr_err, fabs(info.v_r / an.v_r - 1.0));
                kin_assembly_free(c);
            }
            kin_assembly_free(b);
        }
        double fs[2], hs[2], is[2], rr[2];
        for (int mode = 0; mode < 2; ++mode) {
            int k = st[mode].steps;
            fs[mode] = k ? (double)st[mode].fact / k : NAN;
            hs[mode] = k ? (double)st[mode].halvings / k : NAN;
            is[mode] = k ? (double)st[mode].iters / k : NAN;
            rr[mode] = reg[mode] < 1e300 ? reg[mode] / best_sdd : NAN;
        }
        printf("%3d %3d %5d %9.3e | %9.3e %5.2f %4.2f %4.1f %5.2f-%-5.2f%s %5.2f | %9.3e %5.2f %4.2f %3ld %5.2f-%-5.2f%s "
               "%5.2f | %9.3e %7.1e %7.1e %8.1e %7.1e\n",
               members[i][0], members[i][1], nf, best_sdd, best[0], fs[0], hs[0], is[0], rmin[0], rmax[0],
               st[0].ok ? " " : "!", rr[0], best[1], fs[1], hs[1], st[1].fallbacks, rmin[1], rmax[1],
               st[1].ok ? " " : "!", rr[1], lu_fact_s, dx, fmax(st[0].max_strain, st[1].max_strain), vr_rel, vr_err);
        fprintf(csv, "%d,%d,%d,%d,%d,%d,%.6e,%.4f,%.6e,%.6e,%.4f,%.6e,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,"
                     "%d,%d,%.3f,%.3f,%.3f,%.3f,%.2f,%.2f,%ld,%.3e,%.3e,%.3e,%.3e,%.3e\n",
                members[i][0], members[i][1], nf, kin_nbars(a), common, reps, best_sdd, worst_sdd / best_sdd,
                lu_fact_s, best[0], worst[0] / best[0], best[1], worst[1] / best[1], best[0] / best_sdd, rmin[0],
                rmax[0], best[1] / best_sdd, rmin[1], rmax[1], rr[0], rr[1], st[0].reg_steps, st[1].reg_steps, fs[0],
                fs[1], hs[0], hs[1], is[0], is[1], st[1].fallbacks, dx, st[0].max_strain, st[1].max_strain, vr_rel, vr_err);
        fflush(stdout);
        fflush(csv);
        if (np < MAX_MEMBERS) {
            xs[np] = nf;
            y[0][np] = best[0];
            y[1][np] = best[1];
            y[2][np] = reg[0] < 1e300 ? reg[0] : NAN;
            y[3][np] = reg[1] < 1e300 ? reg[1] : NAN;
            y[4][np] = best_sdd;
            ++np;
        }
        free(x_svd);
        free(x_lu);
        kin_assembly_free(a);
    }
    printf("growth exponents p (time ~ nfree^p, least-squares line on log-log) for nfree >= 100 [all members]:\n"
           "  mean step SVD mode %.2f [%.2f], LU mode %.2f [%.2f]; regular step SVD mode %.2f [%.2f], LU mode %.2f "
           "[%.2f]; dgesdd %.2f [%.2f]\n",
           loglog_slope(np, xs, y[0], 100), loglog_slope(np, xs, y[0], 0), loglog_slope(np, xs, y[1], 100),
           loglog_slope(np, xs, y[1], 0), loglog_slope(np, xs, y[2], 100), loglog_slope(np, xs, y[2], 0),
           loglog_slope(np, xs, y[3], 100), loglog_slope(np, xs, y[3], 0), loglog_slope(np, xs, y[4], 100),
           loglog_slope(np, xs, y[4], 0));
}

/* Out along the path by L and back to the start: back until the path length
 * is ~0, then aim along the tangent at the start (up to 3 steps). xs (may be
 * NULL, room for max_pts points) receives every point. */
static run_stats out_and_back(kin_assembly *a, double L, double frac, const double *x0, double *xs, int max_pts,
                              double *closure)
{
    run_stats s = {0.0, 0.0, 0, 0, 0, 0, 0, 1, 0.0, 0};
    int n = kin_njoints(a) * kin_dim(a);
    kin_step_info info = {.size = sizeof info};
    double t0 = now();
    int phase = 0, aim = 0;
    while (s.ok) {
        double d;
        if (phase == 0) {
            if (kin_path_length(a) >= L) phase = 1;
            d = 0.0;
        }
        if (phase == 1) {
            if (kin_path_length(a) <= 1e-3 * frac) phase = 2;
            d = -fmin(kin_path_length(a), frac * a->rms_length);
        }
        if (phase == 2) {
            /* land on the start: aim along the tangent at x0 */
            double *t = a->d, *xs0 = a->chord, *xc = a->xp;
            kin_get_tangent(a, t, a->nf);
            kin__gather(a, x0, xs0);
            kin__gather(a, a->xyz, xc);
            d = 0.0;
            for (int i = 0; i < a->nf; ++i) d += t[i] * (xs0[i] - xc[i]);
            /* no closer than the corrector's position tolerance */
            if (fabs(d) <= a->opt.corrector_tol * a->rms_length || aim++ >= 3) break;
        }
        if (kin_step(a, d, &info)) {
            s.ok = 0;
            printf("    (%s mode, phase %d, l = %.3f: %s)\n", a->opt.factorization ? "LU" : "SVD", phase,
                   kin_path_length(a), kin_last_error(a));
            break;
        }
        s.fact += info.factorizations;
        s.iters += info.iterations;
        kin_analysis an = {.size = sizeof an};
        if (a->opt.factorization == KIN_STEP_LU && kin_get_analysis(a, &an) == KIN_OK) s.fallbacks++;
        s.max_strain = fmax(s.max_strain, kin_max_strain(a));
        if (xs && s.steps < max_pts) kin_get_coords(a, xs + (size_t)s.steps * n);
        ++s.steps;
    }
    s.seconds = now() - t0;
    double *x1 = malloc(sizeof(double) * (size_t)n);
    kin_get_coords(a, x1);
    *closure = max_abs_diff((size_t)n, x0, x1);
    free(x1);
    return s;
}

/* Pareto runs: repeated until this much time has passed (at most
 * PARETO_MAX_RUNS times); the spread reported is the median over the best */
static const double PARETO_MIN_SECONDS = 0.3;
enum { PARETO_MAX_RUNS = 25 };

static int cmp_double(const void *p, const void *q)
{
    double x = *(const double *)p, y = *(const double *)q;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static void pareto(FILE *csv, int reps, int quick)
{
    const double fractions[] = {0.02, 0.05, 0.1, 0.2, 0.4};
    const double tols[] = {1e-6, 1e-9, 1e-12};
    const double L = 2.0;
    const int models[][2] = {{6, 2}, {12, 4}};
    int nmodels = quick ? 1 : 2;
    fprintf(csv, "model,nfree,mode,step_fraction,corrector_tol,seconds_per_length,median_over_best,max_strain,closure,steps,"
                 "fact_per_step,fallbacks,max_dx_modes,ok\n");
    for (int m = 0; m < nmodels; ++m) {
        kin_assembly *base = test_sail(models[m][0], models[m][1]);
        const char *how = m == 0 ? "lifted and relaxed" : "dome";
        if (!base || (m == 0 ? generic(base, 0.3) : generic_by_lengths(&base, 0.3))) {
            printf("model %d x %d: no generic start\n", models[m][0], models[m][1]);
            kin_assembly_free(base);
            continue;
        }
        char name[32];
        snprintf(name, sizeof name, "%dx%d", models[m][0], models[m][1]);
        int n = 3 * kin_njoints(base);
        double *x0 = malloc(sizeof(double) * (size_t)n);
        kin_get_coords(base, x0);
        printf("\nsail %s (%s, %d free coordinates): forward %.1f along the path and back; best of >= %d runs "
               "(and >= %.1f s), spread = median / best\n", name, how, kin_nfree(base), L, reps, PARETO_MIN_SECONDS);
        printf("%6s %7s | %-39s | %-39s | %9s %3s %9s\n", "step", "tol", "SVD mode: s/length strain closure steps",
               "LU mode: s/length strain closure steps", "|dx| modes", "runs", "spread");
        for (size_t f = 0; f < sizeof fractions / sizeof fractions[0]; ++f)
            for (size_t t = 0; t < sizeof tols / sizeof tols[0]; ++t) {
                int max_pts = (int)(4.0 * L / (fractions[f] * base->rms_length)) + 64;
                double *traj[2] = {malloc(sizeof(double) * (size_t)n * (size_t)max_pts),
                                   malloc(sizeof(double) * (size_t)n * (size_t)max_pts)};
                run_stats st[2];
                double best[2] = {1e300, 1e300}, closure[2] = {0, 0}, times[2][PARETO_MAX_RUNS], total = 0.0;
                /* at least reps runs of each mode, more (alternating) until
                 * PARETO_MIN_SECONDS have passed: short runs are noisy */
                int runs = 0;
                for (int r = 0; r < PARETO_MAX_RUNS && (r < reps || total < PARETO_MIN_SECONDS); ++r, ++runs)
                    for (int mode = 0; mode < 2; ++mode) {
                        kin_assembly *a = copy_in_mode(base, mode ? KIN_STEP_LU : KIN_STEP_SVD);
                        kin_options o = {.size = sizeof o};
                        kin_get_options(a, &o);
                        o.step_fraction = fractions[f];
                        o.corrector_tol = tols[t];
                        kin_set_options(a, &o);
                        double cl;
                        run_stats s = out_and_back(a, L, fractions[f], x0, r == 0 ? traj[mode] : NULL, max_pts, &cl);
                        if (r == 0) {
                            st[mode] = s;
                            closure[mode] = cl;
                        }
                        double spl = s.seconds / (2 * L);
                        total += s.seconds;
                        times[mode][r] = spl;
                        best[mode] = fmin(best[mode], spl);
                        kin_assembly_free(a);
                    }
                int common = st[0].steps < st[1].steps ? st[0].steps : st[1].steps;
                if (common > max_pts) common = max_pts;
                double dx = common ? max_abs_diff((size_t)n * (size_t)common, traj[0], traj[1]) : NAN;
                double spread[2] = {median(times[0], runs) / best[0], median(times[1], runs) / best[1]};
                printf("%6.2f %7.0e | %9.2e %9.2e %9.2e%s %4d | %9.2e %9.2e %9.2e%s %4d | %9.2e %3d %4.2f %4.2f\n",
                       fractions[f], tols[t], best[0], st[0].max_strain, closure[0], st[0].ok ? " " : "!", st[0].steps,
                       best[1], st[1].max_strain, closure[1], st[1].ok ? " " : "!", st[1].steps, dx, runs, spread[0],
                       spread[1]);
                for (int mode = 0; mode < 2; ++mode)
                    fprintf(csv, "%s,%d,%s,%.3f,%.1e,%.6e,%.4f,%.6e,%.6e,%d,%.3f,%ld,%.3e,%d\n", name, kin_nfree(base),
                            mode ? "LU" : "SVD", fractions[f], tols[t], best[mode], spread[mode],
                            st[mode].max_strain, closure[mode], st[mode].steps,
                            st[mode].steps ? (double)st[mode].fact / st[mode].steps : NAN, st[mode].fallbacks, dx,
                            st[mode].ok);
                fflush(stdout);
                fflush(csv);
                free(traj[0]);
                free(traj[1]);
            }
        free(x0);
        kin_assembly_free(base);
    }
}

int main(int argc, char **argv)
{
    print_blas();
    const char *dir = argc > 1 ? argv[1] : ".";
    const char *what = argc > 3 ? argv[3] : "all";
    int reps = argc > 2 ? atoi(argv[2]) : 3, quick = strcmp(what, "quick") == 0;
    int do_pareto = strcmp(what, "scaling") != 0, do_scaling = strcmp(what, "pareto") != 0;
    if (reps < 1) reps = 1;
    char path[1024];
    FILE *c1 = NULL, *c2 = NULL;
    if (do_scaling) {
        snprintf(path, sizeof path, "%s/bench_step_scaling.csv", dir);
        c1 = fopen(path, "w");
    }
    if (do_pareto) {
        snprintf(path, sizeof path, "%s/bench_step_pareto.csv", dir);
        c2 = fopen(path, "w");
    }
    if ((do_scaling && !c1) || (do_pareto && !c2)) {
        fprintf(stderr, "cannot write CSV files in %s\n", dir);
        return 1;
    }
    if (do_pareto) pareto(c2, reps, quick);
    if (do_scaling) scaling(c1, reps, quick);
    if (c1) fclose(c1);
    if (c2) fclose(c2);
    return 0;
}
