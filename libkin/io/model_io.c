/* Model files: the JSON model format (docs/model_format.md) read into a new
 * assembly and written from one, through jansson. The rules checked here
 * are the Python loader's (python/src/libkin/model_json.py), in its order,
 * so both report the same status for the same file; what only
 * kin_assembly_create() checks (self and duplicate bars, zero-length bars,
 * too few joints, no free coordinate) is left to it. */
#define _XOPEN_SOURCE 700 /* mkstemp, fsync, realpath; open flags, fstat */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <jansson.h>

#include "model/internal.h"

/* ---- errors ------------------------------------------------------------ */

/* Where messages go: the caller's buffer, prefixed with the file's path when
 * the model came from a file. */
typedef struct io_err {
    char *buf;
    size_t len;
    const char *path; /* NULL for text in memory */
} io_err;

static int io_fail(const io_err *e, int code, const char *fmt, ...)
{
    char msg[KIN_ERRLEN];
    va_list ap;
    va_start(ap, fmt);
    kin__failv(msg, sizeof msg, code, fmt, ap);
    va_end(ap);
    if (e->buf && e->len > 0) {
        if (e->path)
            snprintf(e->buf, e->len, "%s: %s", e->path, msg);
        else
            snprintf(e->buf, e->len, "%s", msg);
    }
    return code;
}

/* "got ..." part of a message: the JSON type found instead */
static const char *json_kind(const json_t *v)
{
    if (!v) return "nothing (missing)";
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "a list";
    case JSON_STRING: return "a string";
    case JSON_INTEGER: return "an integer";
    case JSON_REAL: return "a real number";
    case JSON_TRUE: return "true";
    case JSON_FALSE: return "false";
    case JSON_NULL: return "null";
    }
    return "an unknown value";
}

/* ---- load: one document into arrays, then kin_assembly_create ------------ */

/* The arrays kin_assembly_create takes, owned by the loader. */
typedef struct model_arrays {
    int dim, nj, nb;
    double *xyz;          /* nj*dim */
    unsigned char *fixed; /* nj*dim */
    int *bars;            /* 2*nb */
    double *lengths;      /* nb */
    int have_lengths;     /* every bar gave a length */
    /* contact (kin_contact.h): thickness, bar radii (< 0: default), panels */
    double t0;
    double *radius;       /* nb */
    int np;
    int *poff, *pj;       /* np + 1, poff[np] */
    double *tpan;         /* np (< 0: default) */
    int *device;          /* the bars marked "device": true (kin_set_device_bars) */
    int ndev;
} model_arrays;

static void arrays_free(model_arrays *m)
{
    free(m->xyz);
    free(m->fixed);
    free(m->bars);
    free(m->lengths);
    free(m->radius);
    free(m->poff);
    free(m->pj);
    free(m->tpan);
    free(m->device);
}

/* An optional "index" must equal the element's position. */
static int check_index(const io_err *e, const json_t *obj, const char *list, size_t pos)
{
    const json_t *v = json_object_get(obj, "index");
    if (!v || (json_is_integer(v) && json_integer_value(v) == (json_int_t)pos)) return KIN_OK;
    if (json_is_integer(v))
        return io_fail(e, KIN_EFORMAT, "%s[%zu].index: expected %zu, got %lld", list, pos, pos,
                       (long long)json_integer_value(v));
    return io_fail(e, KIN_EFORMAT, "%s[%zu].index: expected %zu, got %s", list, pos, pos,
                   json_kind(v));
}

/* an optional thickness-like number: absent (-1 into *out), or finite >= 0 */
static int read_thickness(const io_err *e, const json_t *v, const char *what, size_t k, double *out)
{
    *out = -1.0;
    if (!v) return KIN_OK;
    if (!json_is_number(v) || !isfinite(json_number_value(v)) || json_number_value(v) < 0.0 ||
        json_number_value(v) > 1e150)
        return io_fail(e, KIN_EFORMAT, what, k, json_kind(v));
    *out = json_number_value(v);
    return KIN_OK;
}

/* "panels" (a list of {"joints": [3+ distinct joint indices], "thickness"})
 * and "thickness", after the joints and bars are read */
static int read_contact(const io_err *e, const json_t *doc, model_arrays *m)
{
    const json_t *t = json_object_get(doc, "thickness");
    if (t && (!json_is_number(t) || !isfinite(json_number_value(t)) || json_number_value(t) < 0.0 ||
              json_number_value(t) > 1e150))
        return io_fail(e, KIN_EFORMAT, "thickness: expected a finite number >= 0, got %s", json_kind(t));
    m->t0 = t ? json_number_value(t) : 0.0;
    int rc;
    const json_t *panels = json_object_get(doc, "panels");
    if (!panels) return KIN_OK;
    if (!json_is_array(panels))
        return io_fail(e, KIN_EFORMAT, "panels: expected a list, got %s", json_kind(panels));
    size_t np = json_array_size(panels), total = 0;
    if (np > (size_t)INT_MAX / KIN_PANEL_MAX_JOINTS)
        return io_fail(e, KIN_EFORMAT, "panels: %zu panels, too many", np);
    for (size_t i = 0; i < np; ++i) {
        const json_t *p = json_array_get(panels, i);
        if (!json_is_object(p))
            return io_fail(e, KIN_EFORMAT, "panels[%zu]: expected an object, got %s", i, json_kind(p));
        rc = check_index(e, p, "panels", i);
        if (rc) return rc;
        const json_t *js = json_object_get(p, "joints");
        if (!json_is_array(js) || json_array_size(js) < 3 || json_array_size(js) > KIN_PANEL_MAX_JOINTS)
            return io_fail(e, KIN_EFORMAT, "panels[%zu].joints: expected a list of 3 to %d joint indices, got %s", i,
                           KIN_PANEL_MAX_JOINTS, json_kind(js));
        total += json_array_size(js);
    }
    m->np = (int)np;
    m->poff = malloc(sizeof(int) * (np + 1));
    m->pj = malloc(sizeof(int) * (total ? total : 1));
    m->tpan = malloc(sizeof(double) * (np ? np : 1));
    if (!m->poff || !m->pj || !m->tpan) return io_fail(e, KIN_ENOMEM, "panels: %zu panels", np);
    m->poff[0] = 0;
    for (size_t i = 0; i < np; ++i) {
        const json_t *p = json_array_get(panels, i), *js = json_object_get(p, "joints");
        size_t n = json_array_size(js);
        for (size_t q = 0; q < n; ++q) {
            const json_t *v = json_array_get(js, q);
            if (!json_is_integer(v))
                return io_fail(e, KIN_EFORMAT, "panels[%zu].joints[%zu]: expected a joint index, got %s", i, q,
                               json_kind(v));
            json_int_t j = json_integer_value(v);
            if (j < 0 || j >= m->nj)
                return io_fail(e, KIN_EFORMAT, "panels[%zu].joints[%zu]: joint %lld out of range 0..%d", i, q,
                               (long long)j, m->nj - 1);
            for (size_t r = 0; r < q; ++r)
                if (m->pj[m->poff[i] + (int)r] == (int)j)
                    return io_fail(e, KIN_EFORMAT, "panels[%zu].joints[%zu]: joint %lld repeated", i, q,
                                   (long long)j);
            m->pj[m->poff[i] + (int)q] = (int)j;
        }
        m->poff[i + 1] = m->poff[i] + (int)n;
        rc = read_thickness(e, json_object_get(p, "thickness"),
                            "panels[%zu].thickness: expected a finite number >= 0, got %s", i, &m->tpan[i]);
        if (rc) return rc;
    }
    return KIN_OK;
}

static int read_joint(const io_err *e, const json_t *j, size_t i, model_arrays *m)
{
    if (!json_is_object(j))
        return io_fail(e, KIN_EFORMAT, "joints[%zu]: expected an object, got %s", i, json_kind(j));
    int rc = check_index(e, j, "joints", i);
    if (rc) return rc;
    const size_t dim = (size_t)m->dim;
    const json_t *xyz = json_object_get(j, "xyz");
    if (!json_is_array(xyz) || json_array_size(xyz) != dim)
        return io_fail(e, KIN_EFORMAT, "joints[%zu].xyz: expected a list of %zu numbers, got %s%s",
                       i, dim, json_kind(xyz), json_is_array(xyz) ? " of another length" : "");
    for (size_t c = 0; c < dim; ++c) {
        const json_t *v = json_array_get(xyz, c);
        /* jansson refuses non-finite literals and overflow, so a number here
         * is finite; the check stays for the contract's sake */
        if (!json_is_number(v) || !isfinite(json_number_value(v)))
            return io_fail(e, KIN_EFORMAT, "joints[%zu].xyz[%zu]: expected a finite number, got %s",
                           i, c, json_kind(v));
        m->xyz[i * dim + c] = json_number_value(v);
    }
    const json_t *free_flags = json_object_get(j, "free");
    if (free_flags) {
        if (!json_is_array(free_flags) || json_array_size(free_flags) != dim)
            return io_fail(e, KIN_EFORMAT, "joints[%zu].free: expected a list of %zu booleans, got %s%s",
                           i, dim, json_kind(free_flags),
                           json_is_array(free_flags) ? " of another length" : "");
        for (size_t c = 0; c < dim; ++c) {
            const json_t *v = json_array_get(free_flags, c);
            if (!json_is_boolean(v))
                return io_fail(e, KIN_EFORMAT, "joints[%zu].free[%zu]: expected true or false, got %s",
                               i, c, json_kind(v));
            m->fixed[i * dim + c] = json_is_false(v);
        }
    }
    const json_t *label = json_object_get(j, "label");
    if (label && !json_is_string(label))
        return io_fail(e, KIN_EFORMAT, "joints[%zu].label: expected a string, got %s", i,
                       json_kind(label));
    return KIN_OK;
}

static int read_bar(const io_err *e, const json_t *b, size_t k, model_arrays *m, int *has_length)
{
    if (!json_is_object(b))
        return io_fail(e, KIN_EFORMAT, "bars[%zu]: expected an object, got %s", k, json_kind(b));
    int rc = check_index(e, b, "bars", k);
    if (rc) return rc;
    const json_t *ends = json_object_get(b, "joints");
    if (!json_is_array(ends) || json_array_size(ends) != 2)
        return io_fail(e, KIN_EFORMAT, "bars[%zu].joints: expected two joint indices, got %s%s", k,
                       json_kind(ends), json_is_array(ends) ? " of another length" : "");
    for (size_t s = 0; s < 2; ++s)
        if (!json_is_integer(json_array_get(ends, s)))
            return io_fail(e, KIN_EFORMAT, "bars[%zu].joints[%zu]: expected a joint index, got %s",
                           k, s, json_kind(json_array_get(ends, s)));
    for (size_t s = 0; s < 2; ++s) {
        json_int_t v = json_integer_value(json_array_get(ends, s));
        if (v < 0 || v >= m->nj)
            return io_fail(e, KIN_EFORMAT, "bars[%zu].joints[%zu]: joint %lld out of range 0..%d",
                           k, s, (long long)v, m->nj - 1);
        m->bars[2 * k + s] = (int)v;
    }
    const json_t *len = json_object_get(b, "length");
    *has_length = len != NULL;
    if (len) {
        if (!json_is_number(len) || !isfinite(json_number_value(len)))
            return io_fail(e, KIN_EFORMAT, "bars[%zu].length: expected a finite number, got %s", k,
                           json_kind(len));
        double L = json_number_value(len);
        if (!(L > 0.0))
            return io_fail(e, KIN_EFORMAT, "bars[%zu].length: expected > 0, got %.17g", k, L);
        m->lengths[k] = L;
    }
    const json_t *dev = json_object_get(b, "device");
    if (dev && !json_is_boolean(dev))
        return io_fail(e, KIN_EFORMAT, "bars[%zu].device: expected true or false, got %s", k, json_kind(dev));
    if (dev && json_is_true(dev)) m->device[m->ndev++] = (int)k;
    return read_thickness(e, json_object_get(b, "radius"), "bars[%zu].radius: expected a finite number >= 0, got %s",
                          k, &m->radius[k]);
}

/* Check the document against the schema and fill m (m's arrays are
 * allocated here and released by the caller). */
static int read_model(const io_err *e, const json_t *doc, model_arrays *m)
{
    if (!json_is_object(doc))
        return io_fail(e, KIN_EFORMAT, "model: expected a JSON object, got %s", json_kind(doc));
    const json_t *dim = json_object_get(doc, "dimension");
    if (json_is_integer(dim) && json_integer_value(dim) != 2 && json_integer_value(dim) != 3)
        return io_fail(e, KIN_EFORMAT, "dimension: expected 2 or 3, got %lld",
                       (long long)json_integer_value(dim));
    if (!json_is_integer(dim))
        return io_fail(e, KIN_EFORMAT, "dimension: expected 2 or 3, got %s", json_kind(dim));
    m->dim = (int)json_integer_value(dim);

    const json_t *joints = json_object_get(doc, "joints");
    if (!json_is_array(joints) || json_array_size(joints) == 0)
        return io_fail(e, KIN_EFORMAT, "joints: expected a non-empty list, got %s%s",
                       json_kind(joints), json_is_array(joints) ? " (empty)" : "");
    size_t nj = json_array_size(joints);
    if (nj > INT_MAX / 3)
        return io_fail(e, KIN_EFORMAT, "joints: %zu joints, at most %d supported", nj, INT_MAX / 3);
    m->nj = (int)nj;
    m->xyz = malloc(sizeof(double) * nj * (size_t)m->dim);
    m->fixed = calloc(nj * (size_t)m->dim, 1); /* "free" defaults to all true */
    if (!m->xyz || !m->fixed) return io_fail(e, KIN_ENOMEM, "joints: %zu joints", nj);
    for (size_t i = 0; i < nj; ++i) {
        int rc = read_joint(e, json_array_get(joints, i), i, m);
        if (rc) return rc;
    }

    const json_t *bars = json_object_get(doc, "bars");
    if (!json_is_array(bars) || json_array_size(bars) == 0)
        return io_fail(e, KIN_EFORMAT, "bars: expected a non-empty list, got %s%s", json_kind(bars),
                       json_is_array(bars) ? " (empty)" : "");
    size_t nb = json_array_size(bars);
    if (nb > INT_MAX / 2)
        return io_fail(e, KIN_EFORMAT, "bars: %zu bars, at most %d supported", nb, INT_MAX / 2);
    m->nb = (int)nb;
    m->bars = malloc(sizeof(int) * 2 * nb);
    m->lengths = malloc(sizeof(double) * nb);
    m->radius = malloc(sizeof(double) * nb);
    m->device = malloc(sizeof(int) * nb);
    if (!m->bars || !m->lengths || !m->radius || !m->device) return io_fail(e, KIN_ENOMEM, "bars: %zu bars", nb);
    size_t with_length = 0, first_with = 0, first_without = 0;
    for (size_t k = 0; k < nb; ++k) {
        int has_length = 0;
        int rc = read_bar(e, json_array_get(bars, k), k, m, &has_length);
        if (rc) return rc;
        if (has_length && with_length == 0) first_with = k;
        if (!has_length && with_length == k) first_without = k; /* every bar before k had one */
        with_length += (size_t)has_length;
    }
    if (with_length != 0 && with_length != nb)
        return io_fail(e, KIN_EFORMAT,
                       "bars: give a length for every bar or for none (bar %zu has one, bar %zu has not)",
                       first_with, first_without);
    m->have_lengths = with_length == nb;

    const json_t *name = json_object_get(doc, "name");
    if (name && !json_is_string(name))
        return io_fail(e, KIN_EFORMAT, "name: expected a string, got %s", json_kind(name));
    return read_contact(e, doc, m);
}

/* Lists and objects nest at most this deep (the document is depth 1); the
 * Python loader has the same limit (model_json.MAX_DEPTH). */
enum { MAX_DEPTH = 64 };

/* 1 if v nests no deeper than MAX_DEPTH counting from `depth`; recursion
 * stops at MAX_DEPTH + 1 levels */
static int depth_ok(json_t *v, int depth)
{
    if (!json_is_object(v) && !json_is_array(v)) return 1;
    if (depth > MAX_DEPTH) return 0;
    if (json_is_array(v)) {
        for (size_t i = 0; i < json_array_size(v); ++i)
            if (!depth_ok(json_array_get(v, i), depth + 1)) return 0;
        return 1;
    }
    const char *key;
    json_t *val;
    json_object_foreach(v, key, val) {
        if (!depth_ok(val, depth + 1)) return 0;
    }
    return 1;
}

/* The offset of the first byte of s[0..n) that is not valid UTF-8 (RFC
 * 3629: no overlong forms, surrogates or code points past U+10FFFF, the
 * rules jansson applies), or n when all of it is. */
static size_t utf8_invalid_at(const unsigned char *s, size_t n)
{
    size_t i = 0;
    while (i < n) {
        unsigned c = s[i];
        size_t k;
        unsigned lo = 0x80, hi = 0xBF; /* the second byte's range */
        if (c < 0x80) {
            ++i;
            continue;
        } else if (c >= 0xC2 && c <= 0xDF) {
            k = 1;
        } else if (c >= 0xE0 && c <= 0xEF) {
            k = 2;
            if (c == 0xE0) lo = 0xA0;
            if (c == 0xED) hi = 0x9F;
        } else if (c >= 0xF0 && c <= 0xF4) {
            k = 3;
            if (c == 0xF0) lo = 0x90;
            if (c == 0xF4) hi = 0x8F;
        } else {
            return i;
        }
        if (n - i <= k || s[i + 1] < lo || s[i + 1] > hi) return i;
        for (size_t j = 2; j <= k; ++j)
            if ((s[i + j] & 0xC0) != 0x80) return i;
        i += k + 1;
    }
    return n;
}

/* Parse text, check it, create the assembly. */
static int load_text(const io_err *e, const char *text, size_t len, kin_assembly **out)
{
    json_error_t jerr;
    /* JSON_ALLOW_NUL: a "\u0000" inside a label is valid JSON (Python reads it) */
    json_t *doc = json_loadb(text, len, JSON_ALLOW_NUL, &jerr);
    size_t bad = doc ? len : utf8_invalid_at((const unsigned char *)text, len);
    if (!doc && bad < len)
        return io_fail(e, KIN_EFORMAT,
                       "JSON text is not valid UTF-8 (byte 0x%02x at offset %zu, line %d): a name or any other "
                       "string must be UTF-8", (unsigned)(unsigned char)text[bad], bad, jerr.line);
    if (!doc)
        return io_fail(e, KIN_EFORMAT, "JSON syntax: line %d, column %d: %s", jerr.line,
                       jerr.column, jerr.text);
    if (!depth_ok(doc, 1)) {
        json_decref(doc);
        return io_fail(e, KIN_EFORMAT, "JSON text: lists or objects nested deeper than %d", MAX_DEPTH);
    }
    model_arrays m = {0, 0, 0, NULL, NULL, NULL, NULL, 0, 0.0, NULL, 0, NULL, NULL, NULL, NULL, 0};
    int rc = read_model(e, doc, &m);
    json_decref(doc);
    if (rc == KIN_OK) {
        char msg[KIN_ERRLEN];
        rc = kin_assembly_create(m.dim, m.nj, m.xyz, m.fixed, m.nb, m.bars,
                                 m.have_lengths ? m.lengths : NULL, out, msg, sizeof msg);
        /* panels and thicknesses: checked above, so only memory can fail */
        int any_r = 0;
        for (int k = 0; k < m.nb; ++k) any_r |= m.radius[k] >= 0.0;
        if (rc == KIN_OK && (m.np > 0 || any_r || m.t0 > 0.0)) {
            rc = kin_set_panels(*out, m.np, m.np ? m.poff : NULL, m.pj);
            if (rc == KIN_OK) rc = kin_set_thickness(*out, m.t0, m.radius, m.np ? m.tpan : NULL);
        }
        if (rc == KIN_OK && m.ndev > 0) rc = kin_set_device_bars(*out, m.ndev, m.device);
        if (*out && rc) {
            snprintf(msg, sizeof msg, "%s", kin_last_error(*out));
            kin_assembly_free(*out);
            *out = NULL;
        }
        if (rc && e->buf && e->len > 0) {
            if (e->path)
                snprintf(e->buf, e->len, "%s: %s", e->path, msg);
            else
                snprintf(e->buf, e->len, "%s", msg);
        }
    }
    arrays_free(&m);
    return rc;
}

/* The first checks of a load: the caller's message buffer emptied, *out
 * NULL until a model is made, out and the source (`what`) not NULL */
static int load_entry(io_err *e, kin_assembly **out, const void *source, const char *what)
{
    if (e->buf && e->len > 0) e->buf[0] = '\0';
    if (out) *out = NULL;
    if (!out) return io_fail(e, KIN_ENULL, "out is NULL");
    if (!source) return io_fail(e, KIN_ENULL, "%s is NULL", what);
    return KIN_OK;
}

int kin_assembly_load_string(const char *text, size_t len, kin_assembly **out, char *errbuf,
                             size_t errlen)
{
    io_err e = {errbuf, errlen, NULL};
    int rc = load_entry(&e, out, text, "text");
    return rc ? rc : load_text(&e, text, len, out);
}

/* The whole file into a malloc'd buffer, at most max_bytes of it. Only a
 * regular file is read: it is opened without blocking (a FIFO with no writer
 * would block the open) and a FIFO, a device (/dev/zero, a terminal) or a
 * directory is refused before any read, so an endless stream cannot hang
 * the call or fill memory. A file larger than max_bytes (by its size, or by
 * what a read finds if it grows meanwhile) gives KIN_ELIMIT. */
static int read_file(const io_err *e, const char *path, size_t max_bytes, char **text, size_t *len)
{
#ifdef O_CLOEXEC
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
#else
    int fd = open(path, O_RDONLY | O_NONBLOCK);
#endif
    if (fd < 0) return io_fail(e, KIN_EIO, "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int err = errno;
        close(fd);
        return io_fail(e, KIN_EIO, "cannot stat: %s", strerror(err));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return io_fail(e, KIN_EIO, "not a regular file (a FIFO, device or directory is not read)");
    }
    if (st.st_size < 0 || (unsigned long long)st.st_size > (unsigned long long)max_bytes) {
        close(fd);
        return io_fail(e, KIN_ELIMIT, "file of %lld bytes is larger than the limit of %zu bytes",
                       (long long)st.st_size, max_bytes);
    }
    /* regular files never block; clear the flag all the same */
    int fl = fcntl(fd, F_GETFL);
    if (fl >= 0) (void)fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
    /* one byte more than the limit tells a file that grew past it */
    size_t cap = (size_t)st.st_size + 1, n = 0;
    char *buf = malloc(cap + 1);
    int rc = buf ? KIN_OK : io_fail(e, KIN_ENOMEM, "read buffer of %zu bytes", cap + 1);
    while (rc == KIN_OK) {
        if (n == cap) {
            if (cap > max_bytes) {
                rc = io_fail(e, KIN_ELIMIT, "file grew past the limit of %zu bytes while read", max_bytes);
                break;
            }
            size_t want = cap <= max_bytes / 2 ? cap * 2 : max_bytes + 1;
            char *bigger = realloc(buf, want + 1);
            if (!bigger) {
                rc = io_fail(e, KIN_ENOMEM, "read buffer of %zu bytes", want + 1);
                break;
            }
            buf = bigger;
            cap = want;
        }
        ssize_t got = read(fd, buf + n, cap - n);
        if (got < 0) {
            if (errno == EINTR) continue;
            rc = io_fail(e, KIN_EIO, "cannot read: %s", strerror(errno));
            break;
        }
        if (got == 0) break;
        n += (size_t)got;
        if (n > max_bytes) {
            rc = io_fail(e, KIN_ELIMIT, "file grew past the limit of %zu bytes while read", max_bytes);
            break;
        }
    }
    close(fd);
    if (rc) {
        free(buf);
        return rc;
    }
    *text = buf;
    *len = n;
    return KIN_OK;
}

int kin_assembly_load_limited(const char *path, size_t max_bytes, kin_assembly **out, char *errbuf,
                              size_t errlen)
{
    io_err e = {errbuf, errlen, NULL};
    int rc = load_entry(&e, out, path, "path");
    if (rc) return rc;
    e.path = path;
    if (max_bytes == 0) max_bytes = KIN_LOAD_MAX_BYTES;
    char *text = NULL;
    size_t len = 0;
    rc = read_file(&e, path, max_bytes, &text, &len);
    if (rc) return rc;
    rc = load_text(&e, text, len, out);
    free(text);
    return rc;
}

int kin_assembly_load(const char *path, kin_assembly **out, char *errbuf, size_t errlen)
{
    return kin_assembly_load_limited(path, 0, out, errbuf, errlen);
}

/* ---- save: the assembly as text ------------------------------------------ */

/* A growing text buffer; `failed` latches the first allocation failure. */
typedef struct text_buf {
    char *p;
    size_t n, cap;
    int failed;
} text_buf;

static char *tb_reserve(text_buf *t, size_t extra)
{
    if (t->failed) return NULL;
    if (t->n + extra + 1 > t->cap) {
        size_t cap = t->cap ? t->cap : 4096;
        while (cap < t->n + extra + 1) cap *= 2;
        char *p = realloc(t->p, cap);
        if (!p) {
            t->failed = 1;
            return NULL;
        }
        t->p = p;
        t->cap = cap;
    }
    return t->p + t->n;
}

static void tb_puts(text_buf *t, const char *s)
{
    size_t k = strlen(s);
    char *dst = tb_reserve(t, k);
    if (!dst) return;
    memcpy(dst, s, k + 1);
    t->n += k;
}

/* Append v encoded by jansson on one line (", " and ": " separators); takes
 * v's reference. Numbers get 17 significant digits, enough to read back the
 * same double. */
static void tb_json(text_buf *t, json_t *v)
{
    const size_t flags = JSON_ENCODE_ANY | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(17);
    size_t k = v ? json_dumpb(v, NULL, 0, flags) : 0;
    char *dst = (v && k) ? tb_reserve(t, k) : NULL;
    if (dst) {
        json_dumpb(v, dst, k, flags);
        t->n += k;
        t->p[t->n] = '\0';
    } else {
        t->failed = 1;
    }
    json_decref(v);
}

/* The values of one joint / bar as a JSON object (NULL if out of memory). */
static json_t *joint_object(int i, int dim, const double *xyz, const unsigned char *fixed)
{
    json_t *o = json_object(), *pos = json_array(), *free_flags = json_array();
    int bad = !o || !pos || !free_flags;
    for (int c = 0; c < dim && !bad; ++c) {
        bad |= json_array_append_new(pos, json_real(xyz[i * dim + c])) != 0;
        bad |= json_array_append_new(free_flags, json_boolean(!fixed[i * dim + c])) != 0;
    }
    if (!bad) {
        bad |= json_object_set_new(o, "index", json_integer(i)) != 0;
        bad |= json_object_set(o, "xyz", pos) != 0;
        bad |= json_object_set(o, "free", free_flags) != 0;
    }
    json_decref(pos);
    json_decref(free_flags);
    if (bad) {
        json_decref(o);
        return NULL;
    }
    return o;
}

static json_t *bar_object(int k, const int *bars, const double *L0, const double *radius, double t0, int device)
{
    json_t *o = json_object(), *ends = json_array();
    int bad = !o || !ends;
    if (!bad) {
        bad |= json_array_append_new(ends, json_integer(bars[2 * k])) != 0;
        bad |= json_array_append_new(ends, json_integer(bars[2 * k + 1])) != 0;
        bad |= json_object_set_new(o, "index", json_integer(k)) != 0;
        bad |= json_object_set(o, "joints", ends) != 0;
        bad |= json_object_set_new(o, "length", json_real(L0[k])) != 0;
        if (radius[k] != 0.5 * t0) bad |= json_object_set_new(o, "radius", json_real(radius[k])) != 0;
        if (device) bad |= json_object_set_new(o, "device", json_true()) != 0;
    }
    json_decref(ends);
    if (bad) {
        json_decref(o);
        return NULL;
    }
    return o;
}

/* The model as text: one joint or bar per line. */
static int render(const io_err *e, const kin_assembly *a, const char *name, text_buf *t)
{
    const int dim = kin_dim(a), nj = kin_njoints(a), nb = kin_nbars(a);
    double *xyz = malloc(sizeof(double) * ((size_t)nj * dim + nb));
    unsigned char *fixed = malloc((size_t)nj * dim);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    if (!xyz || !fixed || !bars) {
        free(xyz);
        free(fixed);
        free(bars);
        return io_fail(e, KIN_ENOMEM, "save buffers");
    }
    double *L0 = xyz + (size_t)nj * dim;
    /* contact: thickness, radii, panels */
    int np = kin_npanels(a);
    double t0 = 0.0, *radius = malloc(sizeof(double) * (size_t)nb), *tpan = malloc(sizeof(double) * (np ? (size_t)np : 1));
    int *poff = malloc(sizeof(int) * ((size_t)np + 1));
    int *pj = NULL;
    if (radius && tpan && poff) {
        kin_get_panels(a, poff, NULL);
        pj = malloc(sizeof(int) * (poff[np] ? (size_t)poff[np] : 1));
    }
    if (!radius || !tpan || !poff || !pj) {
        free(xyz), free(fixed), free(bars), free(radius), free(tpan), free(poff), free(pj);
        return io_fail(e, KIN_ENOMEM, "save buffers");
    }
    kin_get_panels(a, poff, pj);
    kin_get_thickness(a, &t0, radius, tpan);
    /* the device bars (kin_set_device_bars) as one flag a bar, in the
     * bars' buffer's room: bars[] is read below */
    int ndev = 0;
    kin_get_device_bars(a, &ndev, bars);
    unsigned char *isdev = calloc((size_t)nb + 1, 1);
    if (!isdev) {
        free(xyz), free(fixed), free(bars), free(radius), free(tpan), free(poff), free(pj);
        return io_fail(e, KIN_ENOMEM, "save buffers");
    }
    for (int q = 0; q < ndev; ++q) isdev[bars[q]] = 1;
    kin_get_coords(a, xyz);
    kin_get_fixed(a, fixed);
    kin_get_bars(a, bars);
    kin_get_rest_lengths(a, L0);
    int rc = KIN_OK;
    size_t nlen = name ? strlen(name) : 0, bad = name ? utf8_invalid_at((const unsigned char *)name, nlen) : 0;
    if (name && bad < nlen)
        rc = io_fail(e, KIN_EINVAL, "name is not valid UTF-8 (byte 0x%02x at offset %zu)",
                     (unsigned)(unsigned char)name[bad], bad);
    /* a valid handle holds finite numbers only; json_real refuses others */
    for (size_t i = 0; i < (size_t)nj * dim + nb && rc == KIN_OK; ++i)
        if (!isfinite(xyz[i]))
            rc = io_fail(e, KIN_EGEOM, "%s %zu is not finite",
                         i < (size_t)nj * dim ? "coordinate" : "rest length of bar",
                         i < (size_t)nj * dim ? i : i - (size_t)nj * dim);
    if (rc == KIN_OK) {
        char line[64];
        tb_puts(t, "{\n");
        if (name) {
            tb_puts(t, " \"name\": ");
            tb_json(t, json_string_nocheck(name)); /* bytes as given; escaped by jansson */
            tb_puts(t, ",\n");
        }
        snprintf(line, sizeof line, " \"dimension\": %d,\n \"joints\": [\n", dim);
        tb_puts(t, line);
        for (int i = 0; i < nj; ++i) {
            tb_puts(t, "  ");
            tb_json(t, joint_object(i, dim, xyz, fixed));
            tb_puts(t, i + 1 < nj ? ",\n" : "\n");
        }
        tb_puts(t, " ],\n \"bars\": [\n");
        for (int k = 0; k < nb; ++k) {
            tb_puts(t, "  ");
            tb_json(t, bar_object(k, bars, L0, radius, t0, isdev[k]));
            tb_puts(t, k + 1 < nb ? ",\n" : "\n");
        }
        tb_puts(t, " ]");
        if (t0 > 0.0) {
            tb_puts(t, ",\n \"thickness\": ");
            tb_json(t, json_real(t0));
        }
        if (np > 0) {
            tb_puts(t, ",\n \"panels\": [\n");
            for (int i = 0; i < np; ++i) {
                json_t *o = json_object(), *js = json_array();
                for (int q = poff[i]; q < poff[i + 1] && js; ++q) json_array_append_new(js, json_integer(pj[q]));
                if (o && js) {
                    json_object_set_new(o, "index", json_integer(i));
                    json_object_set(o, "joints", js);
                    if (tpan[i] != t0) json_object_set_new(o, "thickness", json_real(tpan[i]));
                }
                json_decref(js);
                tb_puts(t, "  ");
                tb_json(t, o);
                tb_puts(t, i + 1 < np ? ",\n" : "\n");
            }
            tb_puts(t, " ]");
        }
        tb_puts(t, "\n}\n");
        if (t->failed) rc = io_fail(e, KIN_ENOMEM, "model text");
    }
    free(radius), free(tpan), free(poff), free(pj), free(isdev);
    free(xyz);
    free(fixed);
    free(bars);
    return rc;
}

int kin_assembly_save_string(const kin_assembly *a, const char *name, char **text, size_t *len,
                             char *errbuf, size_t errlen)
{
    io_err e = {errbuf, errlen, NULL};
    if (errbuf && errlen > 0) errbuf[0] = '\0';
    if (text) *text = NULL;
    if (len) *len = 0;
    if (!a) return io_fail(&e, KIN_ENULL, "assembly is NULL");
    if (!text) return io_fail(&e, KIN_ENULL, "text is NULL");
    text_buf t = {NULL, 0, 0, 0};
    int rc = render(&e, a, name, &t);
    if (rc) {
        free(t.p);
        return rc;
    }
    *text = t.p;
    if (len) *len = t.n;
    return KIN_OK;
}

void kin_free_string(char *text) { free(text); }

/* ---- atomic file writes -------------------------------------------------- */

/* Fault injection for the tests (internal.h): the nth call of one operation
 * fails with errno err, once. */
static int io_fault_op = KIN__IO_FAULT_NONE, io_fault_nth = 0, io_fault_err = 0, io_fault_seen = 0;

void kin__set_io_fault(int op, int nth, int err)
{
    io_fault_op = op;
    io_fault_nth = nth;
    io_fault_err = err;
    io_fault_seen = 0;
}

/* 0, or the injected errno of this call of op */
static int io_fault(int op)
{
    if (op != io_fault_op || io_fault_op == KIN__IO_FAULT_NONE) return 0;
    if (++io_fault_seen != io_fault_nth) return 0;
    io_fault_op = KIN__IO_FAULT_NONE;
    return io_fault_err;
}

/* write n bytes to fd in chunks (a full disk may refuse any of them):
 * 0 or an errno */
static int write_all(int fd, const char *p, size_t n)
{
    while (n > 0) {
        size_t chunk = n < KIN__IO_CHUNK ? n : KIN__IO_CHUNK;
        int inj = io_fault(KIN__IO_FAULT_WRITE);
        if (inj) return inj;
        ssize_t w = write(fd, p, chunk);
        if (w < 0) {
            if (errno == EINTR) continue;
            return errno ? errno : EIO;
        }
        if (w == 0) return EIO;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* the folder of path (its text up to the last '/', or "."), into buf */
static void folder_of(const char *path, char *buf, size_t len)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(buf, len, ".");
    else if (slash == path)
        snprintf(buf, len, "/");
    else
        snprintf(buf, len, "%.*s", (int)(slash - path), path);
}

/* Write text to path so that a reader (or a crash) sees either the old file
 * or the whole new one: into <path>.tmp.XXXXXX in the same folder, fsync,
 * rename over path, fsync the folder. On failure the temporary file is
 * removed and path is untouched. A path that exists and is not a regular
 * file (a device such as /dev/stdout) is written in place. */
static int write_atomic(const io_err *e, const char *path, const char *text, size_t n)
{
    struct stat st;
    char *real = NULL;
    int rc = KIN_OK, err = 0;
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) { /* replace the link's target, not the link */
        real = realpath(path, NULL);
        if (real) path = real;
    }
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        free(real);
        return io_fail(e, KIN_EIO, "cannot write: %s", strerror(EISDIR));
    }
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        int fd = open(path, O_WRONLY | O_TRUNC);
        if (fd < 0) {
            err = errno;
            free(real);
            return io_fail(e, KIN_EIO, "cannot open for writing: %s", strerror(err));
        }
        err = write_all(fd, text, n);
        if (close(fd) != 0 && !err) err = errno ? errno : EIO;
        free(real);
        return err ? io_fail(e, KIN_EIO, "cannot write: %s", strerror(err)) : KIN_OK;
    }
    size_t plen = strlen(path);
    char *tmp = malloc(plen + 12);
    if (!tmp) {
        free(real);
        return io_fail(e, KIN_ENOMEM, "out of memory");
    }
    memcpy(tmp, path, plen);
    memcpy(tmp + plen, ".tmp.XXXXXX", 12);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        err = errno;
        rc = io_fail(e, KIN_EIO, "cannot open for writing: %s", strerror(err));
        goto done;
    }
    /* mkstemp makes the file 0600; give it the mode a new file would get (or the old file's) */
    {
        mode_t um = umask(0);
        umask(um);
        struct stat old;
        mode_t mode = stat(path, &old) == 0 ? (old.st_mode & 07777) : (0666 & ~um);
        (void)fchmod(fd, mode);
    }
    err = write_all(fd, text, n);
    if (!err) {
        err = io_fault(KIN__IO_FAULT_FSYNC);
        if (!err && fsync(fd) != 0) err = errno ? errno : EIO;
    }
    if (close(fd) != 0 && !err) err = errno ? errno : EIO; /* a full disk may show only here */
    if (!err) {
        err = io_fault(KIN__IO_FAULT_RENAME);
        if (!err && rename(tmp, path) != 0) err = errno ? errno : EIO;
    }
    if (err) {
        unlink(tmp);
        rc = io_fail(e, KIN_EIO, "cannot write: %s", strerror(err));
        goto done;
    }
    {   /* make the rename durable; a folder that cannot be opened or synced
         * (some file systems) leaves the file written all the same */
        char dir[PATH_MAX];
        folder_of(path, dir, sizeof dir);
        int dfd = open(dir, O_RDONLY);
        if (dfd >= 0) {
            (void)fsync(dfd);
            close(dfd);
        }
    }
done:
    free(tmp);
    free(real);
    return rc;
}

int kin_assembly_save(const kin_assembly *a, const char *name, const char *path, char *errbuf,
                      size_t errlen)
{
    io_err e = {errbuf, errlen, NULL};
    if (errbuf && errlen > 0) errbuf[0] = '\0';
    if (!a) return io_fail(&e, KIN_ENULL, "assembly is NULL");
    if (!path) return io_fail(&e, KIN_ENULL, "path is NULL");
    e.path = path;
    text_buf t = {NULL, 0, 0, 0};
    int rc = render(&e, a, name, &t);
    if (rc == KIN_OK) rc = write_atomic(&e, path, t.p, t.n);
    free(t.p);
    return rc;
}
