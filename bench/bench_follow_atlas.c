/* Every directed branch out of a bifurcation followed to its next event
 * with kin_follow_event (kin_follow.h): counts by event and time per branch,
 * each branch followed twice, alternately first: with the default cheap
 * steps (LU on regular stretches) and with KIN_FOLLOW_STEPS_SVD (an SVD at
 * every step, the follower before 0.4); per-branch CPU (median, mean) of
 * both, the ratio, and the comparison (events equal, end distance against
 * the atlas's identification tolerance, located accuracy).
 *   bench_follow_atlas rb           R^B of the hexagonal sail (16) and the
 *                                   first R^C (m = 6) reached from it (all)
 *   bench_follow_atlas flat N [th [cache [k...]]]  N branches spread
 *                                   evenly over the flat state's directed
 *                                   branches (2 x the real second-order
 *                                   solutions); cache: a file keeping the
 *                                   solutions between runs; k...: only those
 * Environment: BENCH_FOLLOW_CHEAP_ONLY=1 follows with the cheap steps only
 * (for profiling); BENCH_FOLLOW_DUMP=file writes each branch's result (the
 * cheap follower's) to compare two builds with follow_dump_compare.py;
 * BENCH_FOLLOW_BRANCHES=1 follows returns again with the branch directions.
 * Not a test: prints a summary. */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <stdlib.h>

#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

static const char *event_name(int e)
{
    static const char *n[] = {"none", "bifurcation", "near-miss", "closed-loop", "length", "steps", "failed"};
    return e >= 0 && e <= 6 ? n[e] : "?";
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp_double(const void *p, const void *q)
{
    double a = *(const double *)p, b = *(const double *)q;
    return a < b ? -1 : a > b;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n ? (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2])) : 0.0;
}

/* one follow on a copy of a: its info, end coordinates (xe, nj*dim) and CPU seconds */
static int follow_once(const kin_assembly *a, const double *dir, const kin_follow_options *o, kin_follow_info *fi,
                       double *xe, double *cpu, kin_assembly **keep)
{
    kin_assembly *b = NULL;
    if (kin_assembly_clone(a, &b)) return -1;
    fi->size = sizeof *fi;
    double t = cpu_now();
    int rc = kin_follow_event(b, dir, o, fi);
    *cpu = cpu_now() - t;
    kin_get_coords(b, xe);
    if (rc && fi->event != KIN_FOLLOW_FAILED) printf("  follow: %s: %s\n", kin_status_name(rc), kin_last_error(b));
    if (keep) *keep = b;
    else kin_assembly_free(b);
    return rc;
}

/* follow `want` of the directed branches out of a (all if want <= 0);
 * optionally keep a clone of the first end with m_internal == keep_m */
static const char *cache = NULL; /* optional file of the solutions (flat state: saves the solver's minutes) */
static const int *only = NULL;    /* optional list of branch indices, -1 terminated */

/* the flat state's run, and issue 24's numbers for it: the median CPU a
 * branch when the issue was filed, and its target */
static const char *const FLAT_NAME = "hex sail flat state R^A";
static const double ISSUE24_MEDIAN_MS = 19.0, TARGET_MEDIAN_MS = 3.0;

static int atlas(const char *name, kin_assembly *a, int want, int threads, int keep_m, kin_assembly **kept)
{
    kin_analysis an = {.size = sizeof an};
    if (getenv("BENCH_FOLLOW_STEP_FRACTION")) {
        /* the largest step (kin_options.step_fraction) for this run */
        kin_options ko;
        kin_options_default(&ko);
        if (kin_get_options(a, &ko)) return 1;
        ko.step_fraction = atof(getenv("BENCH_FOLLOW_STEP_FRACTION"));
        if (kin_set_options(a, &ko)) return 1;
    }
    if (kin_analyse(a, &an)) return 1;
    int m = an.m_internal, s = 0, maxsol = 1 << an.s, nsol = 0, nf = kin_nfree(a);
    double *Q = malloc(sizeof(double) * (size_t)m * m * an.s), *betas = malloc(sizeof(double) * (size_t)m * maxsol);
    double *U = malloc(sizeof(double) * (size_t)nf * m), *dir = malloc(sizeof(double) * (size_t)nf);
    if (!Q || !betas || !U || !dir || kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s)) return 1;
    kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, nf, m);
    kin_homotopy_info hi = {.size = sizeof hi};
    double t0 = now();
    FILE *fc = cache ? fopen(cache, "rb") : NULL;
    if (fc) {
        if (fread(&nsol, sizeof nsol, 1, fc) != 1 || nsol > maxsol ||
            fread(betas, sizeof(double) * (size_t)m, (size_t)nsol, fc) != (size_t)nsol)
            return 1;
        fclose(fc);
    } else {
        if (kin_quadrics_homotopy(m, s, Q, 1, threads, betas, maxsol, &nsol, NULL, &hi)) return 1;
        if (cache && (fc = fopen(cache, "wb"))) {
            fwrite(&nsol, sizeof nsol, 1, fc);
            fwrite(betas, sizeof(double) * (size_t)m, (size_t)nsol, fc);
            fclose(fc);
        }
    }
    int total = 2 * nsol, n = want > 0 && want < total ? want : total;
    if (only) for (n = 0; only[n] >= 0; ++n) {}
    printf("%s: m = %d, s = %d, %d real solutions (%.1f s): following %d of %d directed branches\n", name, m, s,
           nsol, now() - t0, n, total);
    int counts[7] = {0}, tols[8] = {0}, mhist[64] = {0}, back = 0, same_event = 0, same_end = 0, ends = 0;
    int same_acc = 0, cheap = 0, steps = 0, hand = 0, same_steps = 0, nc = kin_njoints(a) * kin_dim(a);
    double nm_lo = INFINITY, nm_hi = 0.0, worst_rel = 0.0, nm_width = 0.0;
    int nm_located = 0, nm_evals = 0; /* near misses ended at their located minimum; points computed for them */
    double t1 = now(), worst = 0.0;
    double *cn = malloc(sizeof(double) * (size_t)n), *co = malloc(sizeof(double) * (size_t)n);
    double *xn = malloc(sizeof(double) * (size_t)nc), *xo = malloc(sizeof(double) * (size_t)nc);
    double *x0 = malloc(sizeof(double) * (size_t)nc);
    if (!cn || !co || !xn || !xo || !x0) return 1;
    kin_get_coords(a, x0);
    double mean[3] = {0, 0, 0}, scale = 0.0;
    for (int j = 0; j < nc; ++j) mean[j % kin_dim(a)] += x0[j] / kin_njoints(a);
    for (int j = 0; j < nc; ++j) scale = fmax(scale, fabs(x0[j] - mean[j % kin_dim(a)]));
    scale = fmax(1.0, scale);
    kin_follow_options o, oo;
    kin_follow_options_default(&o);
    kin_follow_options_default(&oo);
    o.steps_mode = KIN_FOLLOW_STEPS_CHEAP;
    oo.steps_mode = KIN_FOLLOW_STEPS_SVD;
    int no_svd = getenv("BENCH_FOLLOW_CHEAP_ONLY") != NULL;
    /* BENCH_FOLLOW_DUMP=file: per branch the cheap follower's event, accuracy,
     * m, s, steps and end coordinates, one line each, to compare two builds
     * (bench/follow_dump_compare.py) */
    FILE *dump = getenv("BENCH_FOLLOW_DUMP") ? fopen(getenv("BENCH_FOLLOW_DUMP"), "w") : NULL;
    /* BENCH_FOLLOW_CPU=file: per branch its event, steps (all, LU only),
     * handovers and CPU seconds (where the time goes, by kind of branch) */
    FILE *cpu_dump = getenv("BENCH_FOLLOW_CPU") ? fopen(getenv("BENCH_FOLLOW_CPU"), "w") : NULL;
    /* BENCH_FOLLOW_BRANCHES: returns to the start followed again with every
     * real branch direction (kin_follow_event_ex) */
    double *lines = NULL;
    int loops_before = 0, loops_after = 0;
    if (getenv("BENCH_FOLLOW_BRANCHES")) {
        lines = malloc(sizeof(double) * (size_t)nf * (size_t)nsol);
        if (!lines) return 1;
        for (int q = 0; q < nsol; ++q)
            for (int r = 0; r < nf; ++r) {
                double v = 0.0;
                for (int c = 0; c < m; ++c) v += U[r + (size_t)nf * c] * betas[(size_t)m * q + c];
                lines[r + (size_t)nf * q] = v;
            }
    }
    for (int i = 0; i < n; ++i) {
        int k = only ? only[i] : (int)((long long)i * total / n);
        if (k >= total) continue;
        double sg = k % 2 ? -1.0 : 1.0;
        for (int r = 0; r < nf; ++r) {
            double v = 0.0;
            for (int c = 0; c < m; ++c) v += U[r + (size_t)nf * c] * betas[(size_t)m * (k / 2) + c];
            dir[r] = sg * v;
        }
        kin_follow_info fi = {.size = sizeof fi}, fo = {.size = sizeof fo};
        kin_assembly *b = NULL;
        int rc;
        if (no_svd) { /* profiling the cheap follower alone */
            rc = follow_once(a, dir, &o, &fi, xn, &cn[i], &b);
            fo = fi;
            co[i] = cn[i];
            memcpy(xo, xn, sizeof(double) * (size_t)nc);
        } else if (i % 2) {
            rc = follow_once(a, dir, &o, &fi, xn, &cn[i], &b);
            (void)follow_once(a, dir, &oo, &fo, xo, &co[i], NULL);
        } else {
            (void)follow_once(a, dir, &oo, &fo, xo, &co[i], NULL);
            rc = follow_once(a, dir, &o, &fi, xn, &cn[i], &b);
        }
        if (!b) return 1;
        if (dump) {
            fprintf(dump, "%d %d %d %.17g %.17g %d %d %d", k, fi.event, fi.at_start, fi.vr_tol_used, fi.v_r_rel,
                    fi.m_internal, fi.s, fi.steps);
            for (int j = 0; j < nc; ++j) fprintf(dump, " %.17g", xn[j]);
            fprintf(dump, "\n");
        }
        if (cpu_dump)
            fprintf(cpu_dump, "%d %d %d %d %d %.9g\n", k, fi.event, fi.steps, fi.cheap_steps, fi.handovers, cn[i]);
        double tb = cn[i];
        if (tb > worst) worst = tb;
        cheap += fi.cheap_steps;
        steps += fi.steps;
        hand += fi.handovers;
        /* the comparison with the SVD follower */
        double dist = 0.0;
        for (int j = 0; j < nc; ++j) dist = fmax(dist, fabs(xn[j] - xo[j]));
        int bif = fi.event == KIN_FOLLOW_BIFURCATION && fo.event == KIN_FOLLOW_BIFURCATION;
        double tol = scale * fmax(1e-6, 10.0 * sqrt(fmax(fi.vr_tol_used, fo.vr_tol_used)));
        int ev = fi.event == fo.event, end_ok = !bif || dist <= tol;
        int acc_ok = !bif || (fi.vr_tol_used <= fo.vr_tol_used && fi.m_internal == fo.m_internal && fi.s == fo.s);
        same_event += ev;
        ends += bif;
        same_end += bif && end_ok;
        same_acc += acc_ok;
        same_steps += fi.steps == fo.steps;
        if (bif) worst_rel = fmax(worst_rel, dist / tol);
        if (!ev || !end_ok || !acc_ok)
            printf("  branch %d differs: %s (v_r %.2g to %.0e, m %d, s %d) vs SVD steps %s (v_r %.2g to %.0e, m %d, s %d); "
                   "end distance %.2g (tolerance %.2g); steps %d vs %d\n",
                   k, event_name(fi.event), fi.v_r_rel, fi.vr_tol_used, fi.m_internal, fi.s, event_name(fo.event),
                   fo.v_r_rel, fo.vr_tol_used, fo.m_internal, fo.s, dist, tol, fi.steps, fo.steps);
        counts[fi.event >= 0 && fi.event <= 6 ? fi.event : 0]++;
        back += fi.event == KIN_FOLLOW_BIFURCATION && fi.at_start;
        if (fi.event == KIN_FOLLOW_NEAR_MISS) {
            if (fi.v_r_rel < 1e-3) printf("  branch %d: near miss at v_r / v_max %.2g after %d steps\n", k, fi.v_r_rel, fi.steps);
            nm_lo = fmin(nm_lo, fi.v_r_rel);
            nm_hi = fmax(nm_hi, fi.v_r_rel);
            nm_located += fi.min_located;
            nm_evals += fi.min_evals;
            if (fi.min_located) nm_width = fmax(nm_width, fi.min_width);
            if (!fi.min_located) printf("  branch %d: near miss not at a located minimum (%d points)\n", k, fi.min_evals);
        }
        if (fi.event == KIN_FOLLOW_BIFURCATION) {
            int e = 0;
            for (double t = o.vr_tol; t < fi.vr_tol_used * 0.5 && e < 7; t *= 10) ++e;
            tols[e]++;
            mhist[fi.m_internal < 63 ? fi.m_internal : 63]++;
            if (kept && !*kept && fi.m_internal == keep_m) kin_assembly_clone(b, kept);
        }
        if (fi.event == KIN_FOLLOW_FAILED || fi.event == KIN_FOLLOW_STEP_LIMIT || fi.event == KIN_FOLLOW_NONE)
            printf("  branch %d: %s (%s): %s\n", k, event_name(fi.event), kin_status_name(rc), kin_last_error(b));
        kin_assembly_free(b);
        if (lines && (fi.event == KIN_FOLLOW_CLOSED_LOOP || (fi.event == KIN_FOLLOW_BIFURCATION && fi.at_start))) {
            /* issue 24 item 2: the same branch with every real branch of the start given */
            kin_assembly *e = NULL;
            if (kin_assembly_clone(a, &e)) return 1;
            kin_follow_info fx = {.size = sizeof fx};
            (void)kin_follow_event_ex(e, dir, &o, lines, nsol, NULL, NULL, 0, NULL, &fx);
            printf("  branch %d: %s%s without the branch directions, %s%s with them (returns along branch %d, "
                   "its own %d; angle %.2g, next %.2g farther); v_r/v_max at the end %.2g -> %.2g\n",
                   k, event_name(fi.event), fi.at_start ? " at the start" : "", event_name(fx.event),
                   fx.at_start ? " at the start" : "", fx.return_branch, k / 2, fx.return_angle, fx.return_gap,
                   fi.v_r_rel, fx.v_r_rel);
            loops_before += fi.event == KIN_FOLLOW_CLOSED_LOOP;
            loops_after += fx.event == KIN_FOLLOW_CLOSED_LOOP;
            kin_assembly_free(e);
        }
    }
    if (lines) {
        printf("  closed loops: %d without the branch directions, %d with them\n", loops_before, loops_after);
        free(lines);
    }
    {
        double mn = 0.0, mo = 0.0;
        for (int i = 0; i < n; ++i) mn += cn[i], mo += co[i];
        mn /= n;
        mo /= n;
        double dn = median(cn, n), dd = median(co, n);
        printf("  CPU per branch: cheap steps median %.2f ms, mean %.2f ms; SVD steps median %.2f ms, mean %.2f ms; "
               "ratio SVD / cheap: median %.1f, mean %.1f\n",
               1e3 * dn, 1e3 * mn, 1e3 * dd, 1e3 * mo, dd / dn, mo / mn);
        if (!strcmp(name, FLAT_NAME))
            /* issue 24's numbers for the flat state (200 branches, kin_follow_event alone, one BLAS
             * thread): 19 ms median CPU a branch; its target 3 ms */
            printf("  against issue 24: median %.2f ms = 1/%.1f of its 19 ms, %.2f of its 3 ms target\n", 1e3 * dn,
                   ISSUE24_MEDIAN_MS / (1e3 * dn), 1e3 * dn / TARGET_MEDIAN_MS);
        printf("  same event %d / %d; same end node %d / %d bifurcations (worst distance %.2g of the tolerance); "
               "same located accuracy, m and s %d / %d\n",
               same_event, n, same_end, ends, worst_rel, same_acc, n);
        printf("  steps %d, of them LU only %d (%.0f%%); handovers to the SVD locator %d (%.2f per branch); "
               "the same number of steps as the SVD follower on %d / %d\n", steps,
               cheap, 100.0 * cheap / (steps ? steps : 1), hand, (double)hand / n, same_steps, n);
    }
    if (dump) fclose(dump);
    if (cpu_dump) fclose(cpu_dump);
    free(cn); free(co); free(xn); free(xo); free(x0);
    double t2 = now();
    printf("  events:");
    for (int e = 0; e < 7; ++e)
        if (counts[e]) printf(" %s %d", event_name(e), counts[e]);
    printf("\n  bifurcations back at the start: %d; near misses at v_r / v_max %.2g .. %.2g",
           back, counts[KIN_FOLLOW_NEAR_MISS] ? nm_lo : 0.0, nm_hi);
    printf("\n  near misses ended at their located minimum: %d / %d (to %.2g of the RMS length at worst), %.1f points "
           "each",
           nm_located, counts[KIN_FOLLOW_NEAR_MISS], nm_width,
           counts[KIN_FOLLOW_NEAR_MISS] ? (double)nm_evals / counts[KIN_FOLLOW_NEAR_MISS] : 0.0);
    printf("\n  bifurcations located to vr_tol x 10^k, k = 0..:");
    for (int e = 0; e < 8; ++e) printf(" %d", tols[e]);
    printf("\n  m_internal at the located bifurcations:");
    for (int q = 0; q < 64; ++q)
        if (mhist[q]) printf(" m=%d: %d", q, mhist[q]);
    printf("\n  %.3f s per branch (worst %.3f s), %.1f s in all\n", (t2 - t1) / n, worst, t2 - t1);
    free(Q); free(betas); free(U); free(dir);
    return 0;
}

int main(int argc, char **argv)
{
    print_blas();
    const char *mode = argc > 1 ? argv[1] : "rb";
    if (!strcmp(mode, "rb")) {
        kin_assembly *a = test_sail(6, 2), *rc = NULL;
        if (!a || test_hex_to_RB(a)) return 1;
        if (atlas("hex sail R^B", a, 0, 1, 6, &rc)) return 1;
        if (rc && atlas("hex sail R^C", rc, 0, 1, 0, NULL)) return 1;
        kin_assembly_free(a);
        kin_assembly_free(rc);
        return 0;
    }
    int n = argc > 2 ? atoi(argv[2]) : 200, threads = argc > 3 ? atoi(argv[3]) : 2;
    cache = argc > 4 ? argv[4] : NULL;
    int list[64];
    if (argc > 5) {
        int k = 0;
        for (int i = 5; i < argc && k < 63; ++i) list[k++] = atoi(argv[i]);
        list[k] = -1;
        only = list;
    }
    kin_assembly *a = test_sail(6, 2);
    if (!a) return 1;
    int rc = atlas(FLAT_NAME, a, n, threads, 0, NULL);
    kin_assembly_free(a);
    return rc;
}
