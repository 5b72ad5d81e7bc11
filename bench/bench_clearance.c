/* The clearance check (kin_clearance) per step, as a fraction of the step's
 * own cost (kin_step in the LU mode), on sail members of about 100 to 1,500
 * free coordinates (hexagonal and octagonal hubs), with their bar triangles
 * as panels; and the growth exponent of the check (least squares of log time
 * on log free coordinates). Two checks: the global smallest clearance
 * (cutoff INFINITY) and a contact margin (cutoff 0.01 x the shortest bar:
 * what a check per step asks). A dome lift of each flat member gives a
 * generic, strain-free state (bench_common.h).
 * The tree is built by an untimed first check (a follow's check at its
 * start point builds it), then 12 steps for every member (a least over
 * fewer samples is biased up, which would tilt the exponent). Each check
 * is timed in this thread's CPU time (the machine is shared: a check
 * preempted halfway is not charged for the wait; the wall times give the
 * exponents marked so):
 *  after step  the first check right after a kin_step, as a follow makes it
 *              (the step has been through the caches and the branch
 *              predictor): the margin check after the even steps, the
 *              global one after the odd ones (6 samples each: the least,
 *              the median and, for the margin check, the mean, which counts
 *              the checks that walk the tree and make a new near-pair list
 *              with those the list serves; docs/contact.md "Round 7");
 *  repeated    20 more checks at the same configuration (warm: for the
 *              smallest members the whole walk then sits in the first-level
 *              cache and the branch predictor has learnt it, which no step
 *              leaves it; the larger members cannot profit so), the least.
 * The step's time is the least over the steps (wall: the LU may use BLAS
 * threads), and that step's time per factorization (the step control may
 * factorize many times in one step: a step of one factorization is the
 * cheapest a step can be). Steps and checks alternate, so the shared
 * machine's load falls on both alike. Not a test: prints a table. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>

#include "bench_common.h"
#include "libkin.h"

static int cmp_dbl(const void *p, const void *q)
{
    double x = *(const double *)p, y = *(const double *)q;
    return (x > y) - (x < y);
}

/* the median of n samples (sorted in place) */
static double median(double *t, int n)
{
    qsort(t, (size_t)n, sizeof *t, cmp_dbl);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

int main(void)
{
    print_blas();
    const int members[][2] = {{6, 5}, {8, 4}, {6, 10}, {8, 8}, {6, 20}, {8, 15}, {6, 40}, {8, 30}, {6, 60}, {8, 61}};
    const int nm = (int)(sizeof members / sizeof members[0]);
    double lx[16], ly[9][16], last_ratio = NAN; /* margin after step / step, the last member */
    int nfit = 0;
    print_load("at start");
    printf("member     nfree  panels  step_LU_ms  per_fact_ms | global_ms: after_step (least, median)  repeated  ratio | margin_ms: "
           "after_step (least, median, mean)  repeated  ratio  ratio_fact   (checks in CPU ms, step in wall ms; ratio: after step / step; "
           "ratio_fact: margin after step / one factorization; margin 0.01 x shortest bar)\n");
    for (int i = 0; i < nm; ++i) {
        kin_assembly *a = bench_clearance_member(members[i][0], members[i][1]);
        if (!a) continue;
        kin_step_info info = {.size = sizeof info};
        if (kin_step(a, 0.0, &info)) {
            printf("%d:%d warm-up step failed: %s\n", members[i][0], members[i][1], kin_last_error(a));
            kin_assembly_free(a);
            continue;
        }
        int nsteps = 12, reps = 20; /* the same for every member (see above) */
        double sm[12], sg2[12]; /* the after-step checks, for their medians */
        int nsm = 0, nsg = 0;
        double ts = INFINITY, tg = INFINITY, tgr = INFINITY, tm = INFINITY, tmr = INFINITY, cl = 0.0, sh = INFINITY;
        double wg = INFINITY, wm = INFINITY; /* wall, after step */
        double tf = INFINITY;                 /* the least step's time per factorization */
        {
            int nb = kin_nbars(a);
            double *L = malloc(sizeof(double) * (size_t)nb);
            kin_get_rest_lengths(a, L);
            for (int k = 0; k < nb; ++k) sh = L[k] < sh ? L[k] : sh; /* the shortest rest length (the hub's scale) */
            free(L);
        }
        /* the tree is built by a first check (as a follow's check at its
         * start point does); only the checks after steps are timed */
        kin_clearance(a, NULL, INFINITY, &cl, NULL, NULL);
        int ok = 0;
        for (int s = 0; s < nsteps; ++s) {
            double t0 = now();
            if (kin_step(a, 0.0, &info)) break;
            double t1 = now();
            if (t1 - t0 < ts) ts = t1 - t0, tf = (t1 - t0) / (info.factorizations > 0 ? info.factorizations : 1);
            /* the first check after the step */
            double cut = s % 2 ? INFINITY : 0.01 * sh;
            double c1 = thread_cpu_now();
            kin_clearance(a, NULL, cut, &cl, NULL, NULL);
            double c2 = thread_cpu_now(), t2 = now();
            if (s % 2) tg = fmin(tg, c2 - c1), wg = fmin(wg, t2 - t1), sg2[nsg++] = c2 - c1;
            else tm = fmin(tm, c2 - c1), wm = fmin(wm, t2 - t1), sm[nsm++] = c2 - c1;
            for (int r = 0; r < reps; ++r) {
                double u0 = thread_cpu_now();
                kin_clearance(a, NULL, INFINITY, &cl, NULL, NULL);
                double u1 = thread_cpu_now();
                kin_clearance(a, NULL, 0.01 * sh, &cl, NULL, NULL);
                double u2 = thread_cpu_now();
                tgr = fmin(tgr, u1 - u0);
                tmr = fmin(tmr, u2 - u1);
            }
            ++ok;
        }
        if (ok < 2) {
            kin_assembly_free(a);
            continue;
        }
        double am = 0.0; /* the mean: the checks that made a new near-pair list too */
        for (int k = 0; k < nsm; ++k) am += sm[k] / nsm;
        double mm = median(sm, nsm), mg = median(sg2, nsg);
        printf("sail:%d:%-3d %6d  %6d  %10.3f  %11.3f | %10.4f %9.4f  %8.4f  %.4f | %10.4f %9.4f %9.4f  %8.4f  %.4f  %10.4f\n",
               members[i][0], members[i][1], kin_nfree(a), kin_npanels(a), 1e3 * ts, 1e3 * tf, 1e3 * tg, 1e3 * mg,
               1e3 * tgr, tg / ts, 1e3 * tm, 1e3 * mm, 1e3 * am, 1e3 * tmr, tm / ts, tm / tf);
        lx[nfit] = log((double)kin_nfree(a));
        ly[0][nfit] = log(tg), ly[1][nfit] = log(tgr), ly[2][nfit] = log(tm), ly[3][nfit] = log(tmr);
        ly[4][nfit] = log(wg), ly[5][nfit] = log(wm);
        ly[6][nfit] = log(mg), ly[7][nfit] = log(mm), ly[8][nfit] = log(am);
        last_ratio = tm / ts;
        ++nfit;
        kin_assembly_free(a);
    }
    const char *name[9] = {"global, after step", "global, repeated", "margin, after step", "margin, repeated",
                           "global, after step (wall)", "margin, after step (wall)",
                           "global, after step median", "margin, after step median", "margin, after step mean"};
    double ex[9];
    for (int m = 0; m < 9; ++m) {
        const double *y = ly[m];
        double mx = 0, my = 0, sxx = 0, sxy = 0;
        for (int k = 0; k < nfit; ++k) mx += lx[k] / nfit, my += y[k] / nfit;
        for (int k = 0; k < nfit; ++k) sxx += (lx[k] - mx) * (lx[k] - mx), sxy += (lx[k] - mx) * (y[k] - my);
        ex[m] = sxx > 0 ? sxy / sxx : NAN;
        printf("%-26s growth exponent (log-log fit over %d members) %.3f\n", name[m], nfit, ex[m]);
    }
    printf("issue 23 item 7: growth exponent of the margin check after a step at most 1.2: least %.3f, median %.3f, "
           "mean %.3f (ratio to 1.2: %.3f, %.3f, %.3f); margin check / LU step at the largest member %.5f (target 0.2)\n",
           ex[2], ex[7], ex[8], ex[2] / 1.2, ex[7] / 1.2, ex[8] / 1.2, last_ratio);
    print_load("at end");
    return 0;
}
