/* The cost of the interval certificates (issue 38 item 3): the complete
 * solver with symmetry (kin_quadrics_homotopy_sym, the route it chooses) on
 * a sail's flat state, without proofs (kin_homotopy_options.prove = 0) and
 * with them, on 2 threads: wall and CPU seconds (this process's CPU time,
 * the fairer number on a loaded machine: the load average is printed), the
 * ratio of the two runs, and the proven counts.
 * Optionally the plain solver (kin_quadrics_homotopy_ex) as well.
 * Both proof routes run: prove = 2 (the default: Arb and FLINT only, exact
 * integer products, Arb's balls and mags) and prove = 1 (the
 * double-precision test with a-priori rounding bounds first).
 * Each run with proofs also splits its own CPU time: the proofs start when
 * the tracking (re-tracks included) has reported every path done for the
 * last time (the progress callback, every 50 ms: the split is good to
 * ~0.1 s); "split" as the 5th argument runs only that (for the octagonal
 * sail, whose solve takes minutes).
 * The 6th argument picks the routes: "12" (both; the default, but "2", the
 * library's default route, with "split"), "1" or "2".
 * usage: bench_prove [n_sides (6)] [loops (2)] [runs (1)] [sym|plain|both (sym)] [split|all] [12|1|2] */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "libkin.h"
#include "bench_common.h"
#include "sail_states.h"

enum { THREADS = 2, MAXG = 64 };

static double cpu(void) { return (double)clock() / CLOCKS_PER_SEC; }

/* the CPU time when the tracking last reached done == total */
typedef struct split {
    double total, at;
    int equal;
} split;

static int on_progress(void *user, double done, double total)
{
    split *sp = user;
    if (total != sp->total) sp->total = total, sp->equal = 0;
    if (done >= total && !sp->equal) sp->equal = 1, sp->at = cpu();
    if (done < total) sp->equal = 0;
    return 0;
}

/* one solve; 0 on success, times in w, c */
static int solve(int plain, int prove, int m, int s, const double *Q, int ng, const double *R, double *b, int N,
                 kin_homotopy_info *h, double *w, double *c, split *sp)
{
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = THREADS;
    o.prove = prove;
    o.progress = on_progress;
    o.user = sp;
    kin_homotopy_sym_info si = {.size = sizeof si};
    int n = 0;
    char err[256] = "";
    double t0 = now(), c0 = cpu();
    int rc = plain ? kin_quadrics_homotopy_ex(m, s, Q, &o, b, N, &n, NULL, h)
                   : kin_quadrics_homotopy_sym(m, s, Q, ng, R, &o, b, N, &n, NULL, h, &si, err, sizeof err);
    *w = now() - t0, *c = cpu() - c0;
    if (rc) printf("%s: %s %s\n", plain ? "plain" : "sym", kin_strerror(rc), err);
    return rc;
}

static void row(const char *name, int prove, double w, double c, const kin_homotopy_info *h)
{
    printf("%-6s %5d %8.2f %8.2f %7d %6d %6d %5d %5d | %7d %7d %7d %4d %7d %7d %7d %7d\n", name, prove, w, c, h->paths,
           h->real, h->nonreal, h->singular, h->failed, h->proven_real, h->proven_nonreal, h->unproven, h->proven_all,
           h->proven_refined, h->proven_overlap, h->unproven_nopoint, h->unproven_refused);
}

int main(int argc, char **argv)
{
    int sides = argc > 1 ? atoi(argv[1]) : 6, loops = argc > 2 ? atoi(argv[2]) : 2;
    int runs = argc > 3 ? atoi(argv[3]) : 1;
    const char *which = argc > 4 ? argv[4] : "sym";
    int only_split = argc > 5 && !strcmp(argv[5], "split");
    const char *routes = argc > 6 ? argv[6] : only_split ? "2" : "12";
    if (strcmp(which, "sym") && strcmp(which, "plain") && strcmp(which, "both")) {
        fprintf(stderr, "usage: bench_prove [n_sides] [loops] [runs] [sym|plain|both] [split|all] [12|1|2]\n");
        return 1;
    }
    kin_assembly *a = test_sail(sides, loops);
    kin_analysis an = {.size = sizeof an};
    if (!a || kin_analyse(a, &an)) return 1;
    int m = an.m_internal, s = 0, ng = 0;
    double *Q = malloc(sizeof(double) * m * m * an.s);
    double *R = malloc(sizeof(double) * MAXG * m * m);
    if (kin_second_order(a, KIN_Q_EXACT, 1, Q, m * m * an.s, &s) || s != m - 1) return 1;
    if (kin_mechanism_group(a, MAXG, R, &ng)) return 1;
    int N = 1 << s;
    double *b = malloc(sizeof(double) * m * N);
    const char *core = getenv("OPENBLAS_CORETYPE");
    /* the proofs use Arb, no BLAS; the tracking's kernels are libkin's own */
    printf("sail %d,%d flat: m = %d, s = %d, %d paths, %d symmetries, %d threads; OPENBLAS_CORETYPE %s; load: ", sides,
           loops, m, s, N, ng, THREADS, core ? core : "(unset)");
    fflush(stdout);
    if (system("cat /proc/loadavg")) printf("\n");
    printf("%-6s %5s %8s %8s %7s %6s %6s %5s %5s | %7s %7s %7s %4s %7s %7s %7s %7s\n", "solver", "prove", "wall[s]",
           "cpu[s]", "paths", "real", "cmplx", "sing", "fail", "p.real", "p.cmplx", "unprov", "all", "refined",
           "overlap", "nopoint", "refused");
    for (int run = 0; run < runs; ++run)
        for (int plain = 0; plain < 2; ++plain) {
            if ((plain && !strcmp(which, "sym")) || (!plain && !strcmp(which, "plain"))) continue;
            const char *name = plain ? "plain" : "sym";
            kin_homotopy_info h0 = {.size = sizeof h0}, h1 = {.size = sizeof h1};
            double w0 = 0, c0 = 0, w1, c1, t0 = cpu();
            split sp = {-1.0, 0.0, 0}, sp0 = sp;
            if (!only_split) {
                if (solve(plain, 0, m, s, Q, ng, R, b, N, &h0, &w0, &c0, &sp0)) continue;
                row(name, 0, w0, c0, &h0);
            }
            for (int prove = 1; prove <= 2; ++prove) {
                if (!strchr(routes, '0' + prove)) continue;
                sp = (split){-1.0, 0.0, 0};
                t0 = cpu();
                if (solve(plain, prove, m, s, Q, ng, R, b, N, &h1, &w1, &c1, &sp)) continue;
                row(name, prove, w1, c1, &h1);
                double track = sp.at - t0, proofs = c1 - track;
                printf("%s, prove %d: tracking %.2f s CPU, then proofs %.2f s CPU (%.1f us per path): proving adds "
                       "%.1f %% CPU\n", name, prove, track, proofs, 1e6 * proofs / h1.paths, 100.0 * proofs / track);
                if (!only_split)
                    printf("%s, prove %d: proving adds %.1f %% wall, %.1f %% CPU (ratio with/without: wall %.3f, CPU "
                           "%.3f)\n", name, prove, 100.0 * (w1 - w0) / w0, 100.0 * (c1 - c0) / c0, w1 / w0, c1 / c0);
                fflush(stdout);
            }
        }
    free(Q), free(R), free(b);
    kin_assembly_free(a);
    return 0;
}
