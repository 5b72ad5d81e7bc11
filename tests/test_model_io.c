/* Model files (kin_io.h): every file of the corpus tests/models/ through
 * kin_assembly_load. good/NAME.json must load, and save -> load must give the
 * same model bit for bit; bad/CODE__what.json must fail with status KIN_CODE
 * (the same verdicts python/tests/test_model_corpus.py asks of the Python
 * loader). Then the error paths of the calls themselves. */
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <stdint.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "model/internal.h" /* to plant a non-finite coordinate no public call allows */
#include "libkin.h"

#define MAX_FILES 256

static char models_dir[1024];

/* tests/models beside this source file (CMake compiles it by full path),
 * or $KIN_TEST_MODELS */
static void find_models_dir(void)
{
    const char *env = getenv("KIN_TEST_MODELS");
    if (env) {
        snprintf(models_dir, sizeof models_dir, "%s", env);
        return;
    }
    snprintf(models_dir, sizeof models_dir, "%s", __FILE__);
    char *slash = strrchr(models_dir, '/');
    if (slash)
        snprintf(slash + 1, sizeof models_dir - (size_t)(slash + 1 - models_dir), "models");
    else
        snprintf(models_dir, sizeof models_dir, "models");
}

static int cmp_names(const void *p, const void *q)
{
    return strcmp(*(char *const *)p, *(char *const *)q);
}

/* sorted *.json names of a directory; returns the count (-1 if unreadable) */
static int list_json(const char *dir, char **names, int max)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *ent;
    while ((ent = readdir(d)) && n < max) {
        size_t k = strlen(ent->d_name);
        if (k > 5 && !strcmp(ent->d_name + k - 5, ".json")) {
            names[n] = malloc(k + 1);
            if (names[n]) memcpy(names[n++], ent->d_name, k + 1);
        }
    }
    closedir(d);
    qsort(names, (size_t)n, sizeof *names, cmp_names);
    return n;
}

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *s = malloc(cap);
    while (s) {
        size_t got = fread(s + n, 1, cap - n, f);
        n += got;
        if (got == 0) break;
        if (n == cap) {
            char *t = realloc(s, cap *= 2);
            if (!t) free(s);
            s = t;
        }
    }
    fclose(f);
    if (s) *len = n;
    return s;
}

/* The same model, bit for bit: sizes, coordinates, fixity, bars (order and
 * orientation) and rest lengths. */
static int same_model(const kin_assembly *a, const kin_assembly *b)
{
    if (kin_dim(a) != kin_dim(b) || kin_njoints(a) != kin_njoints(b) || kin_nbars(a) != kin_nbars(b))
        return 0;
    size_t nc = (size_t)kin_njoints(a) * (size_t)kin_dim(a), nb = (size_t)kin_nbars(a);
    double *xa = malloc(sizeof(double) * 2 * (nc + nb)), *xb = xa + nc + nb;
    unsigned char *fa = malloc(2 * nc), *fb = fa + nc;
    int *ba = malloc(sizeof(int) * 4 * nb), *bb = ba + 2 * nb;
    int same = xa && fa && ba;
    if (same) {
        kin_get_coords(a, xa);
        kin_get_rest_lengths(a, xa + nc);
        kin_get_coords(b, xb);
        kin_get_rest_lengths(b, xb + nc);
        kin_get_fixed(a, fa);
        kin_get_fixed(b, fb);
        kin_get_bars(a, ba);
        kin_get_bars(b, bb);
        /* memcmp: bit for bit, so -0.0 must stay -0.0 */
        same = !memcmp(xa, xb, sizeof(double) * (nc + nb)) && !memcmp(fa, fb, nc) &&
               !memcmp(ba, bb, sizeof(int) * 2 * nb);
    }
    free(xa);
    free(fa);
    free(ba);
    return same;
}

/* save to text and to a file, load both back: the same model; saving the
 * reloaded model gives the same text */
static void check_round_trip(const char *what, const kin_assembly *a)
{
    char err[512], *text = NULL, *text2 = NULL;
    size_t len = 0, len2 = 0;
    kin_assembly *b = NULL, *c = NULL;
    CHECK_RC(kin_assembly_save_string(a, what, &text, &len, err, sizeof err), KIN_OK);
    if (!text) return;
    CHECK(len == strlen(text));
    CHECK_RC(kin_assembly_load_string(text, len, &b, err, sizeof err), KIN_OK);
    CHECK(b && same_model(a, b));
    if (!same_model(a, b)) fprintf(stderr, "round trip through text differs: %s\n", what);

    char path[] = "/tmp/kin_test_model_io_XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0);
    if (fd >= 0) {
        close(fd);
        CHECK_RC(kin_assembly_save(b, what, path, err, sizeof err), KIN_OK);
        CHECK_RC(kin_assembly_load(path, &c, err, sizeof err), KIN_OK);
        CHECK(c && same_model(a, c));
        unlink(path);
    }
    if (c) {
        CHECK_RC(kin_assembly_save_string(c, what, &text2, &len2, NULL, 0), KIN_OK);
        CHECK(text2 && len2 == len && !memcmp(text, text2, len));
    }
    kin_free_string(text);
    kin_free_string(text2);
    kin_assembly_free(b);
    kin_assembly_free(c);
}

static int good_files(void)
{
    char dir[1100], path[1400], err[512], *names[MAX_FILES];
    snprintf(dir, sizeof dir, "%s/good", models_dir);
    int n = list_json(dir, names, MAX_FILES);
    CHECK(n >= 10);
    for (int f = 0; f < n; ++f) {
        snprintf(path, sizeof path, "%s/%s", dir, names[f]);
        kin_assembly *a = NULL;
        int rc = kin_assembly_load(path, &a, err, sizeof err);
        CHECK_RC(rc, KIN_OK);
        if (rc) fprintf(stderr, "%s: %s\n", names[f], err);
        /* the same text from memory gives the same model */
        size_t len = 0;
        char *text = slurp(path, &len);
        kin_assembly *b = NULL;
        CHECK(text != NULL);
        if (text) CHECK_RC(kin_assembly_load_string(text, len, &b, err, sizeof err), KIN_OK);
        if (a && b) CHECK(same_model(a, b));
        if (a) check_round_trip(names[f], a);
        free(text);
        kin_assembly_free(a);
        kin_assembly_free(b);
        free(names[f]);
    }
    return n > 0 ? n : 0;
}

static int bad_files(void)
{
    char dir[1100], path[1400], err[512], *names[MAX_FILES];
    snprintf(dir, sizeof dir, "%s/bad", models_dir);
    int n = list_json(dir, names, MAX_FILES);
    CHECK(n >= 20);
    for (int f = 0; f < n; ++f) {
        /* the expected status is named before "__" */
        char want[64] = "KIN_";
        const char *sep = strstr(names[f], "__");
        CHECK(sep != NULL && sep - names[f] < 50);
        if (!sep || sep - names[f] >= 50) continue;
        strncat(want, names[f], (size_t)(sep - names[f]));
        snprintf(path, sizeof path, "%s/%s", dir, names[f]);
        kin_assembly *a = (kin_assembly *)&want; /* must be reset to NULL */
        err[0] = '\0';
        int rc = kin_assembly_load(path, &a, err, sizeof err);
        if (strcmp(kin_status_name(rc), want) != 0)
            fprintf(stderr, "%s: got %s (%s)\n", names[f], kin_status_name(rc), err);
        CHECK(!strcmp(kin_status_name(rc), want));
        CHECK(a == NULL);
        CHECK(err[0] != '\0');
        /* from memory: the same status */
        size_t len = 0;
        char *text = slurp(path, &len);
        CHECK(text != NULL);
        if (text) {
            rc = kin_assembly_load_string(text, len, &a, NULL, 0);
            CHECK(!strcmp(kin_status_name(rc), want) && a == NULL);
        }
        free(text);
        kin_assembly_free(a);
        free(names[f]);
    }
    return n > 0 ? n : 0;
}

/* A strained configuration with digits that need all 17: the sail moved
 * off its initial state by kin_set_coords. */
static void strained_round_trip(void)
{
    kin_sail_params p = {.size = sizeof p};
    kin_assembly *a = NULL;
    kin_sail_params_default(&p, 6, 2);
    CHECK_RC(kin_model_sail(&p, &a, NULL, 0), KIN_OK);
    if (!a) return;
    int nc = kin_njoints(a) * kin_dim(a);
    double *xyz = malloc(sizeof(double) * (size_t)nc);
    unsigned char *fixed = malloc((size_t)nc);
    kin_get_coords(a, xyz);
    kin_get_fixed(a, fixed);
    unsigned long long s = 12345;
    for (int i = 0; i < nc; ++i) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        if (!fixed[i]) xyz[i] += 1e-3 * ((double)(s >> 11) / 9007199254740992.0 - 0.5);
    }
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK);
    CHECK(kin_max_strain(a) > 0);
    check_round_trip("strained hex sail", a);
    /* a name that needs escaping */
    check_round_trip("a \"quoted\" \\ name\twith\ncontrol characters and \xc3\xa9", a);
    check_round_trip(NULL, a);
    free(xyz);
    free(fixed);
    kin_assembly_free(a);
}

static void error_paths(void)
{
    char err[512], small[8];
    kin_assembly *a = NULL, *b = NULL;
    char *text = NULL;
    const char *ok = "{\"dimension\": 2, \"joints\": [{\"xyz\": [0, 0], \"free\": [false, false]},"
                     " {\"xyz\": [1, 0]}], \"bars\": [{\"joints\": [0, 1]}]}";

    /* a buffer longer than the model (a Fortran CHARACTER variable): only
     * len bytes count */
    char padded[256];
    snprintf(padded, sizeof padded, "%s   }}} garbage", ok);
    CHECK_RC(kin_assembly_load_string(padded, strlen(ok), &a, err, sizeof err), KIN_OK);
    CHECK_RC(kin_assembly_load_string(padded, strlen(padded), &b, err, sizeof err), KIN_EFORMAT);
    CHECK(b == NULL);

    /* NULL arguments */
    CHECK_RC(kin_assembly_load(NULL, &b, err, sizeof err), KIN_ENULL);
    CHECK_RC(kin_assembly_load("x.json", NULL, err, sizeof err), KIN_ENULL);
    CHECK_RC(kin_assembly_load_string(NULL, 3, &b, err, sizeof err), KIN_ENULL);
    CHECK_RC(kin_assembly_load_string(ok, strlen(ok), NULL, err, sizeof err), KIN_ENULL);
    CHECK_RC(kin_assembly_save(NULL, NULL, "/tmp/x.json", err, sizeof err), KIN_ENULL);
    CHECK_RC(kin_assembly_save(a, NULL, NULL, err, sizeof err), KIN_ENULL);
    CHECK_RC(kin_assembly_save_string(NULL, NULL, &text, NULL, err, sizeof err), KIN_ENULL);
    CHECK(text == NULL);
    CHECK_RC(kin_assembly_save_string(a, NULL, NULL, NULL, err, sizeof err), KIN_ENULL);
    kin_free_string(NULL);

    /* empty text; a zero-length buffer */
    CHECK_RC(kin_assembly_load_string("", 0, &b, err, sizeof err), KIN_EFORMAT);

    /* files that cannot be read or written */
    CHECK_RC(kin_assembly_load("/nonexistent/dir/model.json", &b, err, sizeof err), KIN_EIO);
    CHECK(b == NULL);
    char dirpath[1100];
    snprintf(dirpath, sizeof dirpath, "%s/good", models_dir);
    CHECK_RC(kin_assembly_load(dirpath, &b, err, sizeof err), KIN_EIO);
    CHECK_RC(kin_assembly_save(a, "m", "/nonexistent/dir/model.json", err, sizeof err), KIN_EIO);
    CHECK_RC(kin_assembly_save(a, "m", dirpath, err, sizeof err), KIN_EIO);
    struct stat st;
    if (stat("/dev/full", &st) == 0) /* a device that is always full: the write fails */
        CHECK_RC(kin_assembly_save(a, "m", "/dev/full", err, sizeof err), KIN_EIO);

    /* messages are truncated to errlen, NULL errbuf is allowed */
    CHECK_RC(kin_assembly_load("/nonexistent/dir/model.json", &b, small, sizeof small), KIN_EIO);
    CHECK(strlen(small) < sizeof small);
    CHECK_RC(kin_assembly_load("/nonexistent/dir/model.json", &b, NULL, 0), KIN_EIO);
    CHECK_RC(kin_assembly_load_string("{", 1, &b, small, 1), KIN_EFORMAT);
    CHECK(small[0] == '\0');

    /* a non-finite number cannot be written (a valid handle never holds one) */
    kin_assembly *broken = NULL;
    CHECK_RC(kin_assembly_clone(a, &broken), KIN_OK);
    if (broken) {
        broken->xyz[1] = NAN;
        CHECK_RC(kin_assembly_save_string(broken, NULL, &text, NULL, err, sizeof err), KIN_EGEOM);
        CHECK(text == NULL);
        broken->xyz[1] = 0.0;
        broken->L0[0] = INFINITY;
        CHECK_RC(kin_assembly_save(broken, NULL, "/tmp/never_written.json", err, sizeof err), KIN_EGEOM);
        kin_assembly_free(broken);
    }

    /* success clears the caller's buffer */
    strcpy(err, "old");
    CHECK_RC(kin_assembly_load_string(ok, strlen(ok), &b, err, sizeof err), KIN_OK);
    CHECK(err[0] == '\0');
    kin_assembly_free(b);
    kin_assembly_free(a);
}

int main(void)
{
    find_models_dir();
    int ngood = good_files();
    int nbad = bad_files();
    printf("test_model_io: %s: %d good, %d bad files\n", models_dir, ngood, nbad);
    strained_round_trip();
    error_paths();
    TEST_REPORT("test_model_io");
}
