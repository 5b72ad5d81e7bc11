/* Cost of a path-following step against one LAPACK SVD of the same H, over
 * sail family members of growing size (hub n = 6..24, loops 1..20), and the
 * speed/accuracy trade-off of step size and corrector tolerance on the
 * hexagonal sail. Not a test: prints tables and writes CSV files
 * (bench_step_scaling.csv, bench_step_pareto.csv) for bench/plot_step.py. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "internal.h"
#include "lapack.h"
#include "libkin.h"
#include "sail_states.h"

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* a generic strain-free configuration: lift free nodes pseudo-randomly and
 * relax; larger members are near-singular close to the flat state, so try
 * smaller lifts until the relaxed point has a single internal mechanism */
static int lift_and_relax(kin_assembly *a, double amp);
static int generic(kin_assembly *a, double amp)
{
    const double amps[] = {amp, amp / 3, amp / 6, amp / 15};
    kin_assembly *flat = NULL;
    if (kin_assembly_clone(a, &flat)) return KIN_ENOMEM;
    for (size_t i = 0; i < sizeof amps / sizeof amps[0]; ++i) {
        kin_analysis an;
        double *xyz = malloc(sizeof(double) * 3 * kin_njoints(a));
        kin_get_coords(flat, xyz);
        kin_set_coords(a, xyz);
        free(xyz);
        if (lift_and_relax(a, amps[i]) == KIN_OK && kin_analyse(a, &an) == KIN_OK &&
            an.m_internal == 1) {
            kin_assembly_free(flat);
            return KIN_OK;
        }
    }
    kin_assembly_free(flat);
    return KIN_ENOTCONVERGED;
}

static int lift_and_relax(kin_assembly *a, double amp) { return test_make_generic(a, amp); }

/* The large members' flat states are so degenerate that lifting and relaxing
 * does not reach a regular point. For timing, a member of the same topology
 * (same bars, supports and matrix sizes) with the bar lengths of a lifted
 * configuration is just as representative, and strain-free by construction:
 * *pa is replaced by it. */
static int generic_by_lengths(kin_assembly **pa, double amp)
{
    kin_assembly *a = *pa, *b = NULL;
    int nj = kin_njoints(a), nb = kin_nbars(a), rc = KIN_ENOMEM;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    unsigned char *fixed = malloc(3 * (size_t)nj);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    if (xyz && fixed && bars) {
        kin_get_coords(a, xyz);
        kin_get_fixed(a, fixed);
        kin_get_bars(a, bars);
        unsigned long long st = 2024;
        for (int i = 0; i < 3 * nj; ++i)
            if (!fixed[i]) xyz[i] += (i % 3 == 2 ? amp : 0.1 * amp) * ((double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5);
        rc = kin_assembly_create(3, nj, xyz, fixed, nb, bars, NULL, &b, NULL, 0);
    }
    free(xyz);
    free(fixed);
    free(bars);
    kin_analysis an;
    if (rc == KIN_OK && kin_analyse(b, &an) == KIN_OK && an.m_internal == 1) {
        kin_assembly_free(a);
        *pa = b;
        return KIN_OK;
    }
    kin_assembly_free(b);
    return rc ? rc : KIN_ENOMECH;
}

/* seconds of one dgesdd (jobz = 'A') of the current H, best of reps */
static double svd_seconds(kin_assembly *a, int reps)
{
    int nf = a->nf, nb = a->nb, info = 0;
    double best = 1e300;
    for (int r = 0; r < reps; ++r) {
        kin__build_H(a, a->xyz, a->A, nf);
        double t0 = now();
        dgesdd_("A", &nf, &nb, a->A, &nf, a->fac[0].sv, a->fac[0].U, &nf, a->fac[0].VT, &nb,
                a->work, &a->lwork, a->iwork, &info, 1);
        double t = now() - t0;
        if (t < best) best = t;
    }
    return best;
}

static void scaling(FILE *csv)
{
    const int members[][2] = {{6, 1}, {6, 2}, {8, 2}, {6, 4}, {12, 2}, {8, 5}, {12, 4}, {16, 4},
                              {12, 8}, {24, 4}, {16, 8}, {24, 6}, {20, 10}, {24, 14}};
    printf("\nstep cost against one SVD of the same H (generic point, default step)\n");
    printf("%4s %5s %6s %6s %10s %10s %8s %8s %8s %8s\n", "n", "loops", "nfree", "nbars", "step [s]",
           "SVD [s]", "ratio", "fact/st", "iter/st", "state");
    fprintf(csv, "n,loops,nfree,nbars,step_s,svd_s,ratio,fact_per_step,iter_per_step,state\n");
    for (size_t i = 0; i < sizeof members / sizeof members[0]; ++i) {
        kin_sail_params p;
        kin_sail_params_default(&p, members[i][0], members[i][1]);
        kin_assembly *a = NULL;
        const char *state = "relaxed";
        if (kin_model_sail(&p, &a, NULL, 0)) continue;
        if (generic(a, 0.3) != KIN_OK) {
            state = "lengths";
            if (generic_by_lengths(&a, 0.3) != KIN_OK) {
                printf("%4d %5d: could not build a generic state\n", members[i][0], members[i][1]);
                kin_assembly_free(a);
                continue;
            }
        }
        int nf = kin_nfree(a), nsteps = nf > 600 ? 6 : nf > 250 ? 12 : 30;
        kin_step_info info;
        kin_step(a, 0.0, &info); /* warm-up */
        long fact = 0, iters = 0;
        int done = 0;
        double t0 = now();
        for (; done < nsteps; ++done) {
            if (kin_step(a, 0.0, &info)) break;
            fact += info.factorizations;
            iters += info.iterations;
        }
        double per_step = done ? (now() - t0) / done : NAN;
        double svd = svd_seconds(a, nf > 600 ? 2 : 5);
        printf("%4d %5d %6d %6d %10.3e %10.3e %8.2f %8.2f %8.1f %8s\n", members[i][0], members[i][1], nf,
               kin_nbars(a), per_step, svd, per_step / svd, done ? (double)fact / done : NAN,
               done ? (double)iters / done : NAN, state);
        fprintf(csv, "%d,%d,%d,%d,%.6e,%.6e,%.4f,%.3f,%.2f,%s\n", members[i][0], members[i][1], nf,
                kin_nbars(a), per_step, svd, per_step / svd, done ? (double)fact / done : NAN,
                done ? (double)iters / done : NAN, state);
        fflush(stdout);
        kin_assembly_free(a);
    }
}

/* forward over a path length L and back to the start point */
static void pareto(FILE *csv)
{
    const double fractions[] = {0.02, 0.05, 0.1, 0.2, 0.4};
    const double tols[] = {1e-6, 1e-9, 1e-12};
    const double L = 2.0;
    printf("\nhexagonal sail, generic start: forward %.1f along the path and back\n", L);
    printf("%8s %8s %10s %10s %10s %8s\n", "step", "tol", "s/length", "maxstrain", "closure", "steps");
    fprintf(csv, "step_fraction,corrector_tol,seconds_per_length,max_strain,closure,steps\n");
    for (size_t f = 0; f < sizeof fractions / sizeof fractions[0]; ++f)
        for (size_t t = 0; t < sizeof tols / sizeof tols[0]; ++t) {
            kin_sail_params p;
            kin_sail_params_default(&p, 6, 2);
            kin_assembly *a = NULL;
            if (kin_model_sail(&p, &a, NULL, 0) || generic(a, 0.3)) return;
            kin_options o;
            kin_get_options(a, &o);
            o.step_fraction = fractions[f];
            o.corrector_tol = tols[t];
            kin_set_options(a, &o);
            int nj = kin_njoints(a), steps = 0, ok = 1;
            double *x0 = malloc(sizeof(double) * 3 * nj), *x1 = malloc(sizeof(double) * 3 * nj);
            kin_get_coords(a, x0);
            double worst = 0.0, t0 = now();
            kin_step_info info;
            while (ok && kin_path_length(a) < L) {
                ok = kin_step(a, 0.0, &info) == KIN_OK;
                worst = fmax(worst, kin_max_strain(a));
                ++steps;
            }
            while (ok && kin_path_length(a) > 1e-3 * fractions[f]) {
                double d = -fmin(kin_path_length(a), o.step_fraction * a->rms_length);
                ok = kin_step(a, d, &info) == KIN_OK;
                worst = fmax(worst, kin_max_strain(a));
                ++steps;
            }
            /* land on the start: aim along the tangent at x0 */
            for (int k = 0; ok && k < 3; ++k) {
                double *t = a->d, *xs = a->chord, *xc = a->xp;
                kin_get_tangent(a, t, a->nf);
                kin__gather(a, x0, xs);
                kin__gather(a, a->xyz, xc);
                double d = 0.0;
                for (int i = 0; i < a->nf; ++i) d += t[i] * (xs[i] - xc[i]);
                if (fabs(d) < 1e-15) break;
                ok = kin_step(a, d, &info) == KIN_OK;
                ++steps;
            }
            double sec = now() - t0;
            kin_get_coords(a, x1);
            double closure = 0.0;
            for (int i = 0; i < 3 * nj; ++i) closure = fmax(closure, fabs(x1[i] - x0[i]));
            printf("%8.2f %8.0e %10.3e %10.2e %10.2e %8d%s\n", fractions[f], tols[t], sec / (2 * L),
                   worst, closure, steps, ok ? "" : "  (failed)");
            fprintf(csv, "%.3f,%.1e,%.6e,%.6e,%.6e,%d\n", fractions[f], tols[t], sec / (2 * L), worst,
                    closure, steps);
            free(x0);
            free(x1);
            kin_assembly_free(a);
        }
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : ".";
    char path[1024];
    snprintf(path, sizeof path, "%s/bench_step_scaling.csv", dir);
    FILE *c1 = fopen(path, "w");
    snprintf(path, sizeof path, "%s/bench_step_pareto.csv", dir);
    FILE *c2 = fopen(path, "w");
    if (!c1 || !c2) {
        fprintf(stderr, "cannot write CSV files in %s\n", dir);
        return 1;
    }
    pareto(c2);
    scaling(c1);
    fclose(c1);
    fclose(c2);
    return 0;
}
