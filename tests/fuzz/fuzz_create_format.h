/* The bytes fuzz_create.c reads, shared with the seed writer fuzz_seeds.c:
 *   dim byte (2 + bit 0), joint count byte (% FUZZ_CREATE_MAX_JOINTS), bar
 *   count byte (% FUZZ_CREATE_MAX_BARS), a byte that is 255 for a bad
 *   dimension (then a byte: the dimension), a byte whose bit 0 says rest
 *   lengths are given; per coordinate a number and a fixity byte (< 64:
 *   fixed); per bar two joint index bytes (int8 % (njoints + 2): out of range
 *   now and then) and a number; last, a byte of which calls to make on an
 *   accepted model (FUZZ_CREATE_*).
 *   A number: a byte, then, if its bit 0 is set and 8 bytes follow, those
 *   bytes as a double (any bit pattern); else the byte as int8 / 8. */
#ifndef KIN_FUZZ_CREATE_FORMAT_H
#define KIN_FUZZ_CREATE_FORMAT_H

/* the sails of 3 to 6 sides and the shared models fit (hex_sail: 19 joints,
 * 45 bars); an analysis of that size takes a fraction of a millisecond */
#define FUZZ_CREATE_MAX_JOINTS 24
#define FUZZ_CREATE_MAX_BARS 64

enum {
    FUZZ_CREATE_LOCATE = 1,    /* kin_locate_next, a few steps, at a regular point */
    FUZZ_CREATE_BRANCHES = 2,  /* second order, root scan and paths at a bifurcation */
    FUZZ_CREATE_CLEARANCE = 4, /* the bar-bar clearance */
    FUZZ_CREATE_SAVE = 8,      /* saved as JSON and loaded again */
    FUZZ_CREATE_SYMMETRY = 16, /* the symmetry group (nauty) */
    FUZZ_CREATE_FOLLOW = 32    /* kin_follow_event, a few steps, from where the model is */
};

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct fuzz_reader {
    const uint8_t *p;
    size_t n;
} fuzz_reader;

static uint8_t fuzz_byte(fuzz_reader *r)
{
    if (!r->n) return 0;
    --r->n;
    return *r->p++;
}

static double fuzz_number(fuzz_reader *r)
{
    double v = 0.0;
    if (r->n > sizeof v && (fuzz_byte(r) & 1)) {
        memcpy(&v, r->p, sizeof v); /* any bit pattern: NaN, inf, huge, subnormal */
        r->p += sizeof v;
        r->n -= sizeof v;
        return v;
    }
    return (double)(int8_t)fuzz_byte(r) / 8.0;
}

/* what the bytes describe: kin_assembly_create's arguments and the calls */
typedef struct fuzz_model {
    int dim, nj, nb, with_rest, ops;
    double *xyz, *rest;
    unsigned char *fixed;
    int *bars;
} fuzz_model;

static void fuzz_model_free(fuzz_model *m)
{
    free(m->xyz);
    free(m->fixed);
    free(m->bars);
    free(m->rest);
}

/* 0, or -1 when an array could not be allocated */
static int fuzz_create_decode(const uint8_t *data, size_t size, fuzz_model *m)
{
    fuzz_reader r = {data, size};
    m->dim = 2 + (fuzz_byte(&r) & 1);
    m->nj = fuzz_byte(&r) % FUZZ_CREATE_MAX_JOINTS;
    m->nb = fuzz_byte(&r) % FUZZ_CREATE_MAX_BARS;
    if (fuzz_byte(&r) == 255) m->dim = (int)(int8_t)fuzz_byte(&r); /* a bad dimension now and then */
    m->with_rest = fuzz_byte(&r) & 1;
    m->xyz = calloc((size_t)(m->nj > 0 ? m->nj : 1) * 3, sizeof *m->xyz);
    m->fixed = calloc((size_t)(m->nj > 0 ? m->nj : 1) * 3, 1);
    m->bars = calloc((size_t)(m->nb > 0 ? m->nb : 1) * 2, sizeof *m->bars);
    m->rest = calloc((size_t)(m->nb > 0 ? m->nb : 1), sizeof *m->rest);
    if (!(m->xyz && m->fixed && m->bars && m->rest)) return -1;
    int ncoord = (m->dim == 2 || m->dim == 3) ? m->nj * m->dim : 0;
    for (int i = 0; i < ncoord; ++i) {
        m->xyz[i] = fuzz_number(&r);
        m->fixed[i] = fuzz_byte(&r) < 64;
    }
    for (int k = 0; k < m->nb; ++k) {
        m->bars[2 * k] = (int)(int8_t)fuzz_byte(&r) % (m->nj + 2);
        m->bars[2 * k + 1] = (int)(int8_t)fuzz_byte(&r) % (m->nj + 2);
        m->rest[k] = fuzz_number(&r);
    }
    m->ops = fuzz_byte(&r);
    return 0;
}

#endif
