/* The clearance check (kin_clearance) per step, as a fraction of the step's
 * own cost (kin_step in the LU mode), on sail members of about 100 to 1,500
 * free coordinates (hexagonal and octagonal hubs), with their bar triangles
 * as panels; and the growth exponent of the check (least squares of log time
 * on log free coordinates). Two checks: the global smallest clearance
 * (cutoff INFINITY) and a contact margin (cutoff 0.01 x the shortest bar:
 * what a check per step asks). A dome lift of each flat member gives a
 * generic, strain-free state (bench_common.h).
 * Each check is timed two ways, in this thread's CPU time (the machine is
 * shared: a check preempted halfway is not charged for the wait; the wall
 * times give the exponents of the last lines), the least of the samples
 * each:
 *  after step  the first check right after a kin_step, as a follow makes it
 *              (the step has been through the caches and the branch
 *              predictor): the margin check after the even steps, the
 *              global one after the odd ones;
 *  repeated    20 more checks at the same configuration (warm: for the
 *              smallest members the whole walk then sits in the first-level
 *              cache and the branch predictor has learnt it, which no step
 *              leaves it; the larger members cannot profit so).
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

int main(void)
{
    const int members[][2] = {{6, 5}, {8, 4}, {6, 10}, {8, 8}, {6, 20}, {8, 15}, {6, 40}, {8, 30}, {6, 60}, {8, 61}};
    const int nm = (int)(sizeof members / sizeof members[0]);
    double lx[16], ly[6][16];
    int nfit = 0;
    print_load("at start");
    printf("member     nfree  panels  step_LU_ms  per_fact_ms | global_ms: after_step  repeated  ratio | margin_ms: "
           "after_step  repeated  ratio  ratio_fact   (checks in CPU ms, step in wall ms; ratio: after step / step; "
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
        int nsteps = kin_nfree(a) > 800 ? 6 : 24, reps = 20;
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
            if (s % 2) tg = fmin(tg, c2 - c1), wg = fmin(wg, t2 - t1);
            else tm = fmin(tm, c2 - c1), wm = fmin(wm, t2 - t1);
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
        printf("sail:%d:%-3d %6d  %6d  %10.3f  %11.3f | %21.4f  %8.4f  %.4f | %21.4f  %8.4f  %.4f  %10.4f\n",
               members[i][0], members[i][1], kin_nfree(a), kin_npanels(a), 1e3 * ts, 1e3 * tf, 1e3 * tg, 1e3 * tgr,
               tg / ts, 1e3 * tm, 1e3 * tmr, tm / ts, tm / tf);
        lx[nfit] = log((double)kin_nfree(a));
        ly[0][nfit] = log(tg), ly[1][nfit] = log(tgr), ly[2][nfit] = log(tm), ly[3][nfit] = log(tmr);
        ly[4][nfit] = log(wg), ly[5][nfit] = log(wm);
        ++nfit;
        kin_assembly_free(a);
    }
    const char *name[6] = {"global, after step", "global, repeated", "margin, after step", "margin, repeated",
                           "global, after step (wall)", "margin, after step (wall)"};
    for (int m = 0; m < 6; ++m) {
        const double *y = ly[m];
        double mx = 0, my = 0, sxx = 0, sxy = 0;
        for (int k = 0; k < nfit; ++k) mx += lx[k] / nfit, my += y[k] / nfit;
        for (int k = 0; k < nfit; ++k) sxx += (lx[k] - mx) * (lx[k] - mx), sxy += (lx[k] - mx) * (y[k] - my);
        printf("%-26s growth exponent (log-log fit over %d members) %.3f\n", name[m], nfit, sxx > 0 ? sxy / sxx : NAN);
    }
    print_load("at end");
    return 0;
}
