/* Seed corpora of valid structures for the libFuzzer targets (issue 39
 * item 7: from bytes alone they reach a fraction of the code a valid input
 * reaches). Written at run time, not stored: the merge records are native
 * structs, and the models are those of this build.
 *   fuzz_create: every built-in model (the three-bar linkage at R^A, R^B,
 *     R^C; sails of 4, 6 and 8 sides, one loop) and every model file given, as the
 *     bytes fuzz_create.c reads back into the same counts, coordinates,
 *     supports, bars and rest lengths; each also a few steps along its path.
 *   fuzz_load: the built-in models saved as JSON (the files given are
 *     already JSON: the stored corpus has them).
 *   fuzz_merge: the endpoint records of real runs (kin_quadrics_homotopy_range
 *     over every path, the harness's options), s = 1 from the three-bar
 *     linkage's Q at R^C, s = 2 and 3 from fixed well-posed Q_j, as the bytes
 *     fuzz_merge.c reads.
 * Each seed is checked before it is written: fuzz_create's reader gives back
 * the model and kin_assembly_create accepts it; the records merge into the
 * result of one kin_quadrics_homotopy_ex call. Exit 1 otherwise, which fails
 * run.sh (ctest fuzz_short).
 * usage: fuzz_seeds OUTDIR [MODEL.json ...]  (OUTDIR/fuzz_create/ etc. must exist) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "libkin.h"

#include "fuzz_create_format.h"

static int write_file(const char *dir, const char *target, const char *name, const void *data, size_t n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s/seed_%s", dir, target, name);
    FILE *f = fopen(path, "wb");
    if (!f) {
        perror(path);
        return 1;
    }
    int bad = fwrite(data, 1, n, f) != n;
    bad |= fclose(f) != 0;
    if (bad) perror(path);
    return bad;
}

/* the handle's model as fuzz_create's bytes (fuzz_create_format.h) */
static int seed_create(const char *dir, const char *name, const kin_assembly *a)
{
    int dim = kin_dim(a), nj = kin_njoints(a), nb = kin_nbars(a);
    if (nj >= FUZZ_CREATE_MAX_JOINTS || nb >= FUZZ_CREATE_MAX_BARS) {
        fprintf(stderr, "fuzz_seeds: %s has %d joints and %d bars, more than fuzz_create reads: left out\n", name,
                nj, nb);
        return 0;
    }
    double *xyz = malloc(sizeof(double) * (size_t)(nj * dim)), *rest = malloc(sizeof(double) * (size_t)nb);
    unsigned char *fixed = malloc((size_t)(nj * dim)), *out = malloc(16 + (size_t)(nj * dim) * 10 + (size_t)nb * 11);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    size_t n = 0;
    int rc = !(xyz && rest && fixed && out && bars);
    if (!rc) rc = kin_get_coords(a, xyz) || kin_get_fixed(a, fixed) || kin_get_bars(a, bars) ||
                  kin_get_rest_lengths(a, rest);
    if (!rc) {
        out[n++] = (unsigned char)(dim - 2);
        out[n++] = (unsigned char)nj;
        out[n++] = (unsigned char)nb;
        out[n++] = 0; /* not 255: the dimension stands */
        out[n++] = 1; /* rest lengths given */
        for (int i = 0; i < nj * dim; ++i) {
            out[n++] = 1; /* a raw double follows */
            memcpy(out + n, xyz + i, sizeof(double));
            n += sizeof(double);
            out[n++] = fixed[i] ? 0 : 255; /* < 64: fixed */
        }
        for (int k = 0; k < nb; ++k) {
            out[n++] = (unsigned char)bars[2 * k];
            out[n++] = (unsigned char)bars[2 * k + 1];
            out[n++] = 1;
            memcpy(out + n, rest + k, sizeof(double));
            n += sizeof(double);
        }
        out[n++] = 0xFF; /* every further call of the harness */
        /* the harness must read back this very model, and create it */
        fuzz_model m;
        kin_assembly *b = NULL;
        rc = fuzz_create_decode(out, n, &m) != 0 || m.dim != dim || m.nj != nj || m.nb != nb || !m.with_rest ||
             memcmp(m.xyz, xyz, sizeof(double) * (size_t)(nj * dim)) != 0 ||
             memcmp(m.bars, bars, sizeof(int) * 2 * (size_t)nb) != 0 ||
             memcmp(m.rest, rest, sizeof(double) * (size_t)nb) != 0 ||
             kin_assembly_create(m.dim, m.nj, m.xyz, m.fixed, m.nb, m.bars, m.rest, &b, NULL, 0) != KIN_OK;
        for (int i = 0; i < nj * dim && !rc; ++i) rc = !m.fixed[i] != !fixed[i];
        kin_assembly_free(b);
        fuzz_model_free(&m);
        if (rc) fprintf(stderr, "fuzz_seeds: %s: fuzz_create would not read back the model\n", name);
        if (!rc) rc = write_file(dir, "fuzz_create", name, out, n);
    }
    free(xyz);
    free(rest);
    free(fixed);
    free(out);
    free(bars);
    return rc;
}

/* the model, and the model a few steps along its path, or at a bifurcation
 * along its first internal mechanism (where it can move) */
static int seed_model(const char *dir, const char *name, kin_assembly *a)
{
    int rc = seed_create(dir, name, a);
    kin_analysis an = {.size = sizeof an};
    if (!rc && kin_analyse(a, &an) == KIN_OK && an.m_internal >= 1) {
        kin_step_info info = {.size = sizeof info};
        int ok = 1, nf = kin_nfree(a);
        double *u = malloc(sizeof(double) * (size_t)nf * (size_t)an.m_internal);
        if (an.m_internal > 1)
            ok = u && kin_get_mechanisms(a, KIN_MECH_INTERNAL, u, nf, an.m_internal) == KIN_OK &&
                 kin_path_set_direction(a, u, nf) == KIN_OK;
        free(u);
        for (int i = 0; i < 5 && ok; ++i) ok = kin_step(a, 0.0, &info) == KIN_OK;
        char moved[256];
        snprintf(moved, sizeof moved, "%s_stepped", name);
        if (ok) rc = seed_create(dir, moved, a);
    }
    return rc;
}

static int seed_load(const char *dir, const char *name, const kin_assembly *a)
{
    char *text = NULL;
    if (kin_assembly_save_string(a, name, &text, NULL, NULL, 0) != KIN_OK) return 1;
    char file[256];
    snprintf(file, sizeof file, "%s.json", name);
    int rc = write_file(dir, "fuzz_load", file, text, strlen(text));
    kin_free_string(text);
    return rc;
}

/* endpoint records of every path for (m = s + 1, s, Q) as fuzz_merge's bytes:
 * a byte choosing s, the records, z, Q */
static int seed_merge(const char *dir, const char *name, int s, const double *Q)
{
    int m = s + 1;
    size_t npaths = (size_t)1 << s, nz = 2 * (size_t)m * npaths, nq = (size_t)s * m * m;
    kin_homotopy_endpoint *ends = calloc(npaths, sizeof *ends);
    double *z = calloc(nz, sizeof *z);
    size_t len = 1 + npaths * sizeof *ends + (nz + nq) * sizeof(double);
    unsigned char *out = malloc(len);
    int rc = !(ends && z && out);
    if (!rc) {
        ends[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE;
        kin_homotopy_options opt;
        kin_homotopy_options_default(&opt);
        opt.nthreads = 1; /* the harness's options: the merge re-tracks with them */
        rc = kin_quadrics_homotopy_range(m, s, Q, &opt, 0, (long)npaths, ends, z) != KIN_OK;
    }
    if (!rc) {
        /* the records merge into what one call finds (the harness's first
         * input is a valid shard set, before any mutation) */
        kin_homotopy_options opt;
        kin_homotopy_options_default(&opt);
        opt.nthreads = 1;
        double betas[2][4 * 8];
        int nsol[2] = {0, 0}, mult[2][8];
        kin_homotopy_info info[2] = {{.size = sizeof info[0]}, {.size = sizeof info[1]}};
        rc = kin_quadrics_homotopy_merge(m, s, Q, &opt, ends, z, betas[0], 8, &nsol[0], mult[0], &info[0]) != KIN_OK ||
             kin_quadrics_homotopy_ex(m, s, Q, &opt, betas[1], 8, &nsol[1], mult[1], &info[1]) != KIN_OK ||
             nsol[0] != nsol[1] || memcmp(betas[0], betas[1], sizeof(double) * (size_t)(m * nsol[0])) != 0;
        if (rc) fprintf(stderr, "fuzz_seeds: %s: the records do not merge into the one-call result\n", name);
    }
    if (!rc) {
        out[0] = (unsigned char)(s - 1);
        memcpy(out + 1, ends, npaths * sizeof *ends);
        memcpy(out + 1 + npaths * sizeof *ends, z, nz * sizeof *z);
        memcpy(out + 1 + npaths * sizeof *ends + nz * sizeof *z, Q, nq * sizeof *Q);
        rc = write_file(dir, "fuzz_merge", name, out, len);
    }
    free(ends);
    free(z);
    free(out);
    return rc;
}

/* s symmetric (s+1) x (s+1) matrices, fixed and generic enough that every
 * path ends at a simple root: entries from a small linear congruential
 * sequence (deterministic; nothing here needs good randomness) */
static void fixed_Q(int s, double *Q)
{
    int m = s + 1;
    unsigned long x = 12345u + (unsigned long)s;
    for (int j = 0; j < s; ++j)
        for (int c = 0; c < m; ++c)
            for (int r = 0; r <= c; ++r) {
                x = (x * 1103515245u + 12345u) & 0x7fffffffu;
                double v = (double)(x % 2001u) / 1000.0 - 1.0;
                Q[(size_t)j * m * m + r + (size_t)c * m] = Q[(size_t)j * m * m + c + (size_t)r * m] = v;
            }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: fuzz_seeds OUTDIR [MODEL.json ...]\n");
        return 2;
    }
    const char *dir = argv[1];
    int bad = 0;
    const int states[] = {KIN_THREEBAR_RA, KIN_THREEBAR_RB, KIN_THREEBAR_RC};
    const char *state_names[] = {"threebar_RA", "threebar_RB", "threebar_RC"};
    for (int i = 0; i < 3; ++i) {
        kin_assembly *a = NULL;
        if (kin_model_threebar(states[i], &a) != KIN_OK) return 1;
        bad |= seed_load(dir, state_names[i], a);
        if (states[i] == KIN_THREEBAR_RC) {
            /* the one second-order problem of the paper with m = s + 1 */
            kin_analysis an = {.size = sizeof an};
            double Q[4];
            int s = 0;
            bad |= kin_analyse(a, &an) != KIN_OK || kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s) != KIN_OK ||
                   s != 1 || seed_merge(dir, "threebar_RC_s1", 1, Q);
        }
        bad |= seed_model(dir, state_names[i], a);
        kin_assembly_free(a);
    }
    const int sides[] = {4, 6, 8}; /* the default supports need an even n */
    for (int i = 0; i < 3; ++i) {
        kin_sail_params p;
        kin_sail_params_default(&p, sides[i], 1);
        kin_assembly *a = NULL;
        char name[64];
        snprintf(name, sizeof name, "sail_%d_1", sides[i]);
        char err[256];
        if (kin_model_sail(&p, &a, err, sizeof err) != KIN_OK) {
            fprintf(stderr, "fuzz_seeds: %s: %s\n", name, err);
            return 1;
        }
        bad |= seed_load(dir, name, a);
        bad |= seed_model(dir, name, a);
        kin_assembly_free(a);
    }
    for (int s = 2; s <= 3; ++s) {
        double Q[3 * 16];
        char name[32];
        fixed_Q(s, Q);
        snprintf(name, sizeof name, "fixed_s%d", s);
        bad |= seed_merge(dir, name, s, Q);
    }
    for (int i = 2; i < argc; ++i) {
        kin_assembly *a = NULL;
        char err[256];
        if (kin_assembly_load(argv[i], &a, err, sizeof err) != KIN_OK) {
            fprintf(stderr, "fuzz_seeds: %s: %s\n", argv[i], err);
            bad = 1;
            continue;
        }
        const char *base = strrchr(argv[i], '/');
        char name[256];
        snprintf(name, sizeof name, "file_%s", base ? base + 1 : argv[i]);
        bad |= seed_model(dir, name, a);
        kin_assembly_free(a);
    }
    return bad;
}
