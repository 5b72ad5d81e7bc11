/* libFuzzer harness: kin_assembly_create on arrays made from the bytes (any
 * counts, coordinates, bars, fixity and rest lengths), then an analysis and
 * one step of a model that was accepted. Sizes are kept small so each input
 * runs in microseconds. */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "libkin.h"

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static uint8_t byte(reader *r)
{
    if (!r->n) return 0;
    --r->n;
    return *r->p++;
}

static double number(reader *r)
{
    double v = 0.0;
    if (r->n > sizeof v && (byte(r) & 1)) {
        memcpy(&v, r->p, sizeof v); /* any bit pattern: NaN, inf, huge, subnormal */
        r->p += sizeof v;
        r->n -= sizeof v;
        return v;
    }
    return (double)(int8_t)byte(r) / 8.0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r = {data, size};
    int dim = 2 + (byte(&r) & 1), nj = byte(&r) % 12, nb = byte(&r) % 24;
    if (byte(&r) == 255) dim = (int)(int8_t)byte(&r); /* a bad dimension now and then */
    int with_rest = byte(&r) & 1;
    double *xyz = calloc((size_t)(nj > 0 ? nj : 1) * 3, sizeof *xyz);
    unsigned char *fixed = calloc((size_t)(nj > 0 ? nj : 1) * 3, 1);
    int *bars = calloc((size_t)(nb > 0 ? nb : 1) * 2, sizeof *bars);
    double *rest = calloc((size_t)(nb > 0 ? nb : 1), sizeof *rest);
    int ncoord = (dim == 2 || dim == 3) ? nj * dim : 0;
    for (int i = 0; i < ncoord; ++i) {
        xyz[i] = number(&r);
        fixed[i] = byte(&r) < 64;
    }
    for (int k = 0; k < nb; ++k) {
        bars[2 * k] = (int)(int8_t)byte(&r) % 14;
        bars[2 * k + 1] = (int)(int8_t)byte(&r) % 14;
        rest[k] = number(&r);
    }
    kin_assembly *a = NULL;
    char err[256];
    int rc = kin_assembly_create(dim, nj, xyz, fixed, nb, bars, with_rest ? rest : NULL, &a, err, sizeof err);
    if ((rc == KIN_OK) != (a != NULL)) __builtin_trap();
    if (a) {
        kin_analysis an = {.size = sizeof an};
        if (kin_analyse(a, &an) == KIN_OK && an.m_internal == 1) {
            kin_step_info info = {.size = sizeof info};
            (void)kin_step(a, 0.0, &info);
        }
        kin_assembly_free(a);
    }
    free(xyz);
    free(fixed);
    free(bars);
    free(rest);
    return 0;
}
