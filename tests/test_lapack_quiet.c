/* LAPACK never speaks for libkin (issue 39 item 7): a model whose rest
 * length no bar can reach (one bar's rest length tiny, down to the smallest
 * accepted, 1e-150) drives relax towards coincident joints, where the
 * equilibrium matrix is undefined (0/0); the library used to hand that NaN
 * matrix to dgelsd, which printed "On entry to DLASCL parameter number 4
 * had an illegal value" (xerbla) and failed. Every call must return a
 * status that names the geometry (never KIN_ELAPACK_*), leave the handle as
 * it was, and write nothing to stdout or stderr. The calls run in a child
 * process whose fds 1 and 2 go to a file, so what a Fortran LAPACK buffers
 * is flushed at its exit and seen too. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "libkin.h"

static void not_lapack(int rc)
{
    CHECK(rc != KIN_ELAPACK_ARG && rc != KIN_ELAPACK_CONV);
}

/* a four-bar (2D) or a braced quadrilateral (3D): joints 0, 1 fixed, bar 1
 * (joints 1-2) with rest length `tiny`, the others their lengths */
static void unreachable_rest_length(int dim, double scale, double tiny)
{
    double x2[] = {0, 0, 1, 0, 1.2, 1, 0, 1}, x3[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0.3};
    double xyz[12];
    int n = 4 * dim;
    for (int i = 0; i < n; ++i) xyz[i] = scale * (dim == 2 ? x2[i] : x3[i]);
    int bars[] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    int nb = dim == 2 ? 4 : 5;
    unsigned char fixed[12] = {0};
    for (int i = 0; i < 2 * dim; ++i) fixed[i] = 1;
    double rest[5];
    for (int k = 0; k < nb; ++k) {
        const double *p = xyz + bars[2 * k] * dim, *q = xyz + bars[2 * k + 1] * dim;
        double s = 0.0;
        for (int c = 0; c < dim; ++c) s += (p[c] - q[c]) * (p[c] - q[c]);
        rest[k] = sqrt(s);
    }
    rest[1] = tiny;
    kin_assembly *a = NULL;
    char err[256];
    CHECK_RC(kin_assembly_create(dim, 4, xyz, fixed, nb, bars, rest, &a, err, sizeof err), KIN_OK);
    if (!a) return;
    kin_analysis an = {.size = sizeof an};
    not_lapack(kin_analyse(a, &an));
    kin_step_info info = {.size = sizeof info};
    for (int i = 0; i < 3; ++i) not_lapack(kin_step(a, 0.0, &info));
    double before[12], after[12], res = 0.0;
    CHECK_RC(kin_get_coords(a, before), KIN_OK);
    int rc = kin_relax(a, 100, &res);
    not_lapack(rc);
    if (tiny < 1e-3 * scale) CHECK(rc != KIN_OK); /* bar 1 cannot shrink that far with its joints apart */
    CHECK_RC(kin_get_coords(a, after), KIN_OK);
    if (rc != KIN_OK) CHECK(memcmp(before, after, sizeof(double) * (size_t)n) == 0); /* a failed relax moves nothing */
    kin_locate_options lo;
    kin_locate_options_default(&lo);
    kin_locate_info li = {.size = sizeof li};
    not_lapack(kin_locate_next(a, &lo, &li));
    not_lapack(kin_analyse(a, &an));
    kin_assembly_free(a);
}

static int scenarios(void)
{
    const double tiny[] = {1e-150, 1e-149, 1e-100, 1e-75};
    const double scale[] = {1.0, 1e-75, 1e100};
    for (int dim = 2; dim <= 3; ++dim)
        for (size_t s = 0; s < sizeof scale / sizeof *scale; ++s)
            for (size_t t = 0; t < sizeof tiny / sizeof *tiny; ++t) unreachable_rest_length(dim, scale[s], tiny[t]);
    return check_failures_;
}

int main(void)
{
    char path[] = "/tmp/kin_lapack_quiet.XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd < 0) return 1;
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    CHECK(pid >= 0);
    if (pid == 0) {
        dup2(fd, 1);
        dup2(fd, 2);
        exit(scenarios() ? 1 : 0); /* exit, not _exit: the Fortran runtime flushes its units */
    }
    int status = 0;
    waitpid(pid, &status, 0);
    CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    char text[4096];
    ssize_t got = pread(fd, text, sizeof text - 1, 0);
    close(fd);
    unlink(path);
    CHECK(got == 0); /* not a byte on stdout or stderr */
    if (got > 0) {
        text[got] = '\0';
        fprintf(stderr, "the calls wrote:\n%s", text);
    }
    return check_failures_ ? 1 : 0;
}
