/* libFuzzer harness: kin_quadrics_homotopy_merge on endpoint records and
 * z made from the bytes (records as shards would hand them over, possibly
 * corrupt: wrong sizes, paths, kinds, charts, non-finite z), for s = 1..3.
 * It must return a status, never crash or read out of bounds. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "libkin.h"

/* Records corrupted from real ones (the seeds: fuzz_seeds.c) send the merge
 * re-tracking every path with tighter settings: 0.4 s for s = 3 in a plain
 * build, 17 s here under the sanitizers, beyond libFuzzer's -timeout. A
 * merge that schedules more than this many re-tracks is cancelled through
 * its progress callback (deterministic: counted, not timed), which runs the
 * cancel path as well. */
enum { MAX_RETRACKS = 2 };

static int retrack_budget(void *user, double done, double total)
{
    (void)user;
    (void)done;
    return total > MAX_RETRACKS;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2) return 0;
    int s = 1 + data[0] % 3, m = s + 1;
    size_t npaths = (size_t)1 << s, nz = 2 * (size_t)m * npaths, nq = (size_t)s * m * m;
    data++, size--;
    double *Q = calloc(nq, sizeof *Q), *z = calloc(nz, sizeof *z);
    kin_homotopy_endpoint *ends = calloc(npaths, sizeof *ends);
    double *betas = calloc(npaths * (size_t)m, sizeof *betas);
    int *mult = calloc(npaths, sizeof *mult);
    /* a symmetric, well-formed Q_j by default; the bytes overwrite what they reach */
    for (int j = 0; j < s; ++j)
        for (int i = 0; i < m; ++i) Q[(size_t)j * m * m + (size_t)i * m + i] = (i == j) ? 1.0 : (i == j + 1 ? -1.0 : 0.1);
    for (size_t p = 0; p < npaths; ++p) {
        ends[p].size = KIN_HOMOTOPY_ENDPOINT_SIZE;
        ends[p].path = (int)p;
    }
    size_t take = size < npaths * sizeof *ends ? size : npaths * sizeof *ends;
    memcpy(ends, data, take);
    data += take, size -= take;
    take = size < nz * sizeof *z ? size : nz * sizeof *z;
    memcpy(z, data, take);
    data += take, size -= take;
    take = size < nq * sizeof *Q ? size : nq * sizeof *Q;
    memcpy(Q, data, take);
    kin_homotopy_options opt;
    kin_homotopy_options_default(&opt);
    opt.nthreads = 1;
    opt.progress = retrack_budget;
    kin_homotopy_info info = {.size = sizeof info};
    int nsol = 0;
    (void)kin_quadrics_homotopy_merge(m, s, Q, &opt, ends, z, betas, (int)npaths, &nsol, mult, &info);
    free(Q);
    free(z);
    free(ends);
    free(betas);
    free(mult);
    return 0;
}
