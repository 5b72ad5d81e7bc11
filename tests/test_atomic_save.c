/* kin_assembly_save() is atomic: a fault while writing (a full disk at the
 * 1st, 2nd, ... write, at the fsync or at the rename, injected through the
 * io test hook of model/internal.h) returns KIN_EIO and leaves the file saved
 * before byte for byte, with no temporary file beside it (issue 22 item 1). */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "model/internal.h"
#include "libkin.h"

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *p = malloc(cap);
    size_t r;
    while (p && (r = fread(p + n, 1, cap - n, f)) > 0) {
        n += r;
        if (n == cap) {
            char *q = realloc(p, cap *= 2);
            if (!q) free(p);
            p = q;
        }
    }
    fclose(f);
    *len = n;
    return p;
}

/* entries of dir other than . and .. */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    if (!d) return -1;
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) ++n;
    closedir(d);
    return n;
}

int main(void)
{
    char dir[] = "/tmp/kin_atomic_XXXXXX";
    char path[256], err[512];
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    snprintf(path, sizeof path, "%s/model.json", dir);

    kin_sail_params p = {.size = sizeof p};
    kin_sail_params_default(&p, 12, 6);
    kin_assembly *good = NULL, *other = NULL;
    CHECK_RC(kin_model_sail(&p, &good, NULL, 0), KIN_OK);
    kin_sail_params_default(&p, 10, 4);
    CHECK_RC(kin_model_sail(&p, &other, NULL, 0), KIN_OK);
    if (!good || !other) return 1;

    CHECK_RC(kin_assembly_save(good, "good", path, err, sizeof err), KIN_OK);
    size_t n0 = 0;
    char *before = slurp(path, &n0);
    CHECK(before != NULL && n0 > 2 * KIN__IO_CHUNK); /* several writes per save */

    char *text = NULL;
    size_t n_other = 0;
    CHECK_RC(kin_assembly_save_string(other, "other", &text, &n_other, NULL, 0), KIN_OK);
    kin_free_string(text);
    CHECK(n_other > 2 * KIN__IO_CHUNK);

    /* each fault: the nth write (1, 2, 3 and the last), the fsync, the rename */
    struct { int op, nth; } faults[] = {{KIN__IO_FAULT_WRITE, 1}, {KIN__IO_FAULT_WRITE, 2},
                                        {KIN__IO_FAULT_WRITE, 3}, {KIN__IO_FAULT_WRITE, 0},
                                        {KIN__IO_FAULT_FSYNC, 1}, {KIN__IO_FAULT_RENAME, 1}};
    int nfaults = (int)(sizeof faults / sizeof faults[0]), tried = 0;
    for (int i = 0; i < nfaults; ++i) {
        int nth = faults[i].nth ? faults[i].nth : (int)((n_other + KIN__IO_CHUNK - 1) / KIN__IO_CHUNK);
        for (int err_i = 0; err_i < 2; ++err_i) {
            int code = err_i ? EIO : ENOSPC;
            kin__set_io_fault(faults[i].op, nth, code);
            CHECK_RC(kin_assembly_save(other, "other", path, err, sizeof err), KIN_EIO);
            kin__set_io_fault(KIN__IO_FAULT_NONE, 0, 0);
            size_t n1 = 0;
            char *after = slurp(path, &n1);
            CHECK(after != NULL && n1 == n0 && memcmp(after, before, n0) == 0);
            free(after);
            CHECK(entries(dir) == 1); /* no temporary file left */
            ++tried;
        }
    }
    printf("test_atomic_save: %d injected faults into saves of %zu bytes, the saved file kept each time\n", tried, n0);

    /* without a fault the new model replaces the old one whole */
    CHECK_RC(kin_assembly_save(other, "other", path, err, sizeof err), KIN_OK);
    kin_assembly *back = NULL;
    CHECK_RC(kin_assembly_load(path, &back, err, sizeof err), KIN_OK);
    CHECK(back && kin_njoints(back) == kin_njoints(other));
    CHECK(entries(dir) == 1);

    /* a folder that does not exist: KIN_EIO, nothing created */
    char missing[300];
    snprintf(missing, sizeof missing, "%s/no/model.json", dir);
    CHECK_RC(kin_assembly_save(good, "good", missing, err, sizeof err), KIN_EIO);
    CHECK(entries(dir) == 1);

    kin_assembly_free(back);
    kin_assembly_free(good);
    kin_assembly_free(other);
    free(before);
    unlink(path);
    rmdir(dir);
    TEST_REPORT("test_atomic_save");
}
