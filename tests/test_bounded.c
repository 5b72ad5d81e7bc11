/* Bounded input and memory (issue 22 item 5): the model loader refuses a file
 * above its size limit (the default and a raised one), never blocks on a
 * FIFO whose writer never closes nor reads an endless device; kin_analyse
 * stops when its progress callback asks; a model whose dense workspace
 * cannot fit in memory fails with KIN_ENOMEM at once. */
#define _POSIX_C_SOURCE 200809L
#include <fcntl.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "libkin.h"
#include "mast_model.h"

static const char *small_model =
    "{\"dimension\": 2, \"joints\": [{\"xyz\": [0, 0], \"free\": [false, false]},"
    " {\"xyz\": [1, 0]}, {\"xyz\": [1, 1]}, {\"xyz\": [0, 1], \"free\": [false, false]}],"
    " \"bars\": [{\"joints\": [0, 1]}, {\"joints\": [1, 2]}, {\"joints\": [2, 3]}]}";

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

static void size_limits(const char *dir)
{
    char path[512], err[256];
    kin_assembly *a = NULL;
    snprintf(path, sizeof path, "%s/small.json", dir);
    write_text(path, small_model);
    size_t n = strlen(small_model);
    CHECK_RC(kin_assembly_load(path, &a, err, sizeof err), KIN_OK);
    kin_assembly_free(a);
    CHECK_RC(kin_assembly_load_limited(path, n, &a, err, sizeof err), KIN_OK);
    kin_assembly_free(a);
    CHECK_RC(kin_assembly_load_limited(path, n - 1, &a, err, sizeof err), KIN_ELIMIT);
    CHECK(a == NULL);
    /* one byte over the default limit (a sparse file: nothing is written) */
    snprintf(path, sizeof path, "%s/big.json", dir);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    CHECK(fd >= 0);
    if (fd >= 0) {
        CHECK(ftruncate(fd, (off_t)KIN_LOAD_MAX_BYTES + 1) == 0);
        close(fd);
        double t0 = now();
        CHECK_RC(kin_assembly_load(path, &a, err, sizeof err), KIN_ELIMIT);
        CHECK(now() - t0 < 1.0); /* refused before reading */
        CHECK(a == NULL);
        /* a raised limit reads it (zero bytes: not JSON) */
        CHECK_RC(kin_assembly_load_limited(path, (size_t)KIN_LOAD_MAX_BYTES + 1, &a, err, sizeof err),
                 KIN_EFORMAT);
        unlink(path);
    }
}

/* A FIFO whose writer writes forever and never closes, and /dev/zero: both
 * refused at once. The alarm turns a hang into a failure. */
static void endless_streams(const char *dir)
{
    char path[512], err[256];
    kin_assembly *a = NULL;
    snprintf(path, sizeof path, "%s/fifo.json", dir);
    unlink(path);
    CHECK(mkfifo(path, 0600) == 0);
    pid_t child = fork();
    if (child == 0) {
        int fd = open(path, O_WRONLY); /* blocks until a reader opens */
        static const char chunk[] = "[[[[[[[[[[[[[[[[";
        alarm(30);
        while (fd >= 0 && write(fd, chunk, sizeof chunk - 1) > 0) {}
        _exit(0);
    }
    alarm(20);
    double t0 = now();
    int rc = kin_assembly_load(path, &a, err, sizeof err);
    CHECK(rc == KIN_EIO || rc == KIN_ELIMIT);
    CHECK(a == NULL);
    CHECK(now() - t0 < 5.0);
    /* the same with a writer already attached: open the FIFO ourselves */
    int keep = open(path, O_RDONLY | O_NONBLOCK); /* lets the child's open return */
    nanosleep(&(struct timespec){0, 100000000L}, NULL);
    rc = kin_assembly_load(path, &a, err, sizeof err);
    CHECK(rc == KIN_EIO || rc == KIN_ELIMIT);
    if (keep >= 0) close(keep);
    kill(child, SIGKILL);
    waitpid(child, NULL, 0);
    unlink(path);
    t0 = now();
    rc = kin_assembly_load("/dev/zero", &a, err, sizeof err);
    CHECK(rc == KIN_EIO || rc == KIN_ELIMIT);
    CHECK(now() - t0 < 5.0);
    alarm(0);
}

static int cancel_at;
static int calls;
static int cancel_cb(void *user, double done, double total)
{
    (void)user;
    CHECK(done >= 0.0 && done <= total);
    ++calls;
    return done == (double)cancel_at;
}

static void analyse_cancel(void)
{
    kin_assembly *a = NULL;
    char err[256];
    CHECK_RC(kin_assembly_load_string(small_model, strlen(small_model), &a, err, sizeof err), KIN_OK);
    if (!a) return;
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_set_progress(a, cancel_cb, NULL), KIN_OK);
    for (cancel_at = 0; cancel_at <= 1; ++cancel_at) {
        calls = 0;
        CHECK_RC(kin_analyse(a, &an), KIN_ECANCELLED);
        CHECK(calls == cancel_at + 1);
        CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE); /* nothing analysed */
    }
    cancel_at = -1;
    calls = 0;
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(calls == 3);
    CHECK(an.m_internal == 1);
    kin_assembly_free(a);
}

/* A chain of n free joints in 2D (2n free coordinates, n - 1 bars... plus a
 * pinned end): its dense analysis needs O(n^2) doubles. */
static kin_assembly *chain(int n, int extra_bars, int *rc)
{
    double *xyz = malloc(sizeof(double) * 2 * (size_t)n);
    int nb = n - 1 + extra_bars;
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    for (int i = 0; i < n; ++i) {
        xyz[2 * i] = i;
        xyz[2 * i + 1] = (i % 7) * 0.25;
    }
    for (int k = 0; k < n - 1; ++k) {
        bars[2 * k] = k;
        bars[2 * k + 1] = k + 1;
    }
    for (int k = 0; k < extra_bars; ++k) {
        bars[2 * (n - 1 + k)] = k;
        bars[2 * (n - 1 + k) + 1] = k + 2;
    }
    kin_assembly *a = NULL;
    char err[256];
    *rc = kin_assembly_create(2, n, xyz, NULL, nb, bars, NULL, &a, err, sizeof err);
    free(xyz);
    free(bars);
    return a;
}

static long peak_rss_kb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
}

static void too_big_for_memory(void)
{
    /* 40 000 free coordinates, 39 997 bars: every matrix fits LAPACK's int
     * sizes, but the dense analysis needs about 90 GB. The handle is made
     * (the sparse mode would not need that workspace); the analysis fails
     * with KIN_ENOMEM at once. The address space is limited to 8 GB while
     * this runs, so a regression fails instead of swapping. */
    struct rlimit old, lim;
    getrlimit(RLIMIT_AS, &old);
    lim = old;
    long before = peak_rss_kb();
    lim.rlim_cur = (rlim_t)8 << 30;
    if (old.rlim_max != RLIM_INFINITY && lim.rlim_cur > old.rlim_max) lim.rlim_cur = old.rlim_max;
    setrlimit(RLIMIT_AS, &lim);
    int rc = 0;
    double t0 = now();
    kin_assembly *a = chain(20000, 19998, &rc);
    CHECK_RC(rc, KIN_OK);
    if (a) {
        kin_analysis an = {.size = sizeof an};
        CHECK_RC(kin_analyse(a, &an), KIN_ENOMEM);
        CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE);
        CHECK_RC(kin_analyse(a, &an), KIN_ENOMEM); /* again: no half-made workspace */
    }
    double dt = now() - t0;
    setrlimit(RLIMIT_AS, &old);
    CHECK(dt < 2.0);
    CHECK(peak_rss_kb() - before < 200 * 1024); /* nothing large was touched */
    kin_assembly_free(a);
}

/* A deployable mast of 1 000 decagonal bays (10 010 joints, 30 000 free
 * coordinates) made, analysed and stepped in the sparse mode with the
 * default options within 3 GB: the dense workspace (about 100 GB) is never
 * made; on a machine with less memory than that, its SVD analysis is
 * refused with KIN_ENOMEM at once. At the default rank_tol (1e-9) the LU
 * estimate of v_r / v_max (2.3e-7) is within the 1000x margin where the
 * dense SVD would decide a point (before: the first step failed with
 * KIN_ENOMEM); the sparse analysis decides it (about 2 s a step). */
static void sparse_large(void)
{
    double t0 = now();
    kin_assembly *a = test_mast(10, 1000, NULL);
    CHECK(a != NULL);
    if (!a) return;
    CHECK(kin_njoints(a) >= 10000);
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = KIN_STEP_SPARSE;
    o.step_control = KIN_STEP_CONTROL_MODE;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    double t_made = now() - t0;
    /* analysed without the dense workspace (model/analysis_sparse.c): the
     * mast's one internal mechanism, no self-stress */
    kin_analysis an = {.size = sizeof an};
    double t1 = now();
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    double t_an = now() - t1;
    CHECK(an.rank == kin_nbars(a) && an.m == 1 && an.m_internal == 1 && an.m_rigid == 0 && an.s == 0);
    CHECK(an.v_r > o.rank_tol * an.v_max && an.v_max > 0.0);
    double vr_rel = an.v_r / an.v_max;
    int nf = kin_nfree(a);
    double *u = malloc(sizeof(double) * (size_t)nf);
    CHECK(u && kin_get_mechanisms(a, KIN_MECH_INTERNAL, u, nf, 1) == KIN_OK);
    free(u);
    kin_step_info info = {.size = sizeof info};
    t1 = now();
    for (int k = 0; k < 2; ++k) CHECK_RC(kin_step(a, 0.0, &info), KIN_OK);
    /* what needs the dense SVD is refused at once with its status */
    kin_locate_options lo;
    kin_locate_options_default(&lo);
    kin_locate_info li = {.size = sizeof li};
    CHECK_RC(kin_locate_next(a, &lo, &li), KIN_ENOMEM);
    double t_step = now() - t1;
    /* the dense analysis of that mast is still refused before any work */
    long phys = sysconf(_SC_PHYS_PAGES) * (sysconf(_SC_PAGESIZE) / 1024); /* KB */
    o.factorization = KIN_STEP_SVD;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    if (phys > 0 && (double)phys * 1024.0 < 40e9) CHECK_RC(kin_analyse(a, &an), KIN_ENOMEM);
    long peak = peak_rss_kb();
    printf("test_bounded: mast of %d joints, %d free coordinates, sparse mode: made in %.1f s, analysed in %.1f s "
           "(v_r/v_max %.3g), 2 steps in %.1f s, peak RSS %.0f MB\n", kin_njoints(a), nf, t_made, t_an,
           vr_rel, t_step, peak / 1024.0);
    CHECK(peak < 3L * 1024 * 1024);
    kin_assembly_free(a);
}

int main(void)
{
    char dir[] = "/tmp/kin_bounded_XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    size_limits(dir);
    endless_streams(dir);
    analyse_cancel();
    too_big_for_memory();
    sparse_large();
    rmdir(dir);
    TEST_REPORT("test_bounded");
}
