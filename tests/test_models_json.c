/* The built-in models equal the cross-check copies in examples/models/NAME.json
 * (joints in the same order with the same coordinates and fixity; the same
 * bars, in any order, with the same rest lengths). The folder comes from
 * $KIN_SHARED_DIR (set by tests/CMakeLists.txt; "../shared" if unset); the
 * test skips (exit 0 with a note) when its models are absent. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"

typedef struct model {
    int dim, nj, nb;
    double xyz[64 * 3];
    int fixed[64 * 3];
    int bars[128 * 2];
    double len[128];
} model;

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) { free(s); s = NULL; }
    if (s) s[n] = '\0';
    fclose(f);
    return s;
}

/* numbers of the JSON array that follows key at or after *p */
static int read_array(const char **p, const char *key, double *out, int max)
{
    const char *q = strstr(*p, key);
    if (!q) return -1;
    q = strchr(q, '[');
    int n = 0;
    for (++q; *q && *q != ']';) {
        while (*q == ' ' || *q == ',') ++q;
        if (*q == ']') break;
        if (n >= max) return -1;
        if (!strncmp(q, "true", 4)) { out[n++] = 1; q += 4; }
        else if (!strncmp(q, "false", 5)) { out[n++] = 0; q += 5; }
        else { char *e; out[n++] = strtod(q, &e); if (e == q) return -1; q = e; }
    }
    *p = q;
    return n;
}

static int parse(const char *text, model *m)
{
    const char *p = strstr(text, "\"dimension\"");
    if (!p) return -1;
    m->dim = atoi(strchr(p, ':') + 1);
    const char *joints = strstr(text, "\"joints\""), *bars = strstr(text, "\"bars\"");
    m->nj = m->nb = 0;
    p = joints;
    double v[3];
    while ((p = strstr(p, "\"xyz\"")) && p < bars) {
        if (read_array(&p, "\"xyz\"", v, 3) != m->dim) return -1;
        memcpy(m->xyz + m->dim * m->nj, v, sizeof(double) * m->dim);
        if (read_array(&p, "\"free\"", v, 3) != m->dim) return -1;
        for (int c = 0; c < m->dim; ++c) m->fixed[m->dim * m->nj + c] = v[c] == 0;
        m->nj++;
    }
    p = bars;
    while ((p = strstr(p, "\"joints\""))) {
        if (read_array(&p, "\"joints\"", v, 2) != 2) return -1;
        m->bars[2 * m->nb] = (int)v[0];
        m->bars[2 * m->nb + 1] = (int)v[1];
        const char *l = strstr(p, "\"length\"");
        if (!l) return -1;
        m->len[m->nb++] = strtod(strchr(l, ':') + 1, NULL);
    }
    return 0;
}

/* JSON files carry 12 significant digits */
static const double JSON_DIGITS = 1e-11;

static void compare(const char *dir, const char *file, kin_assembly *a)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/models/%s", dir, file);
    char *text = slurp(path);
    CHECK(text != NULL);
    if (!text) return;
    static model m;
    CHECK(parse(text, &m) == 0);
    free(text);
    CHECK(m.dim == kin_dim(a) && m.nj == kin_njoints(a) && m.nb == kin_nbars(a));
    if (m.dim != kin_dim(a) || m.nj != kin_njoints(a) || m.nb != kin_nbars(a)) return;
    double xyz[64 * 3], L0[128];
    int bars[256];
    unsigned char fixed[64 * 3];
    kin_get_coords(a, xyz);
    kin_get_fixed(a, fixed);
    kin_get_bars(a, bars);
    kin_get_rest_lengths(a, L0);
    int bad = 0;
    for (int i = 0; i < m.nj * m.dim; ++i) {
        bad += fabs(xyz[i] - m.xyz[i]) > JSON_DIGITS * 10;
        bad += fixed[i] != m.fixed[i];
    }
    for (int k = 0; k < m.nb; ++k) {
        int found = 0;
        for (int q = 0; q < m.nb && !found; ++q)
            if ((bars[2 * q] == m.bars[2 * k] && bars[2 * q + 1] == m.bars[2 * k + 1]) ||
                (bars[2 * q] == m.bars[2 * k + 1] && bars[2 * q + 1] == m.bars[2 * k]))
                found = fabs(L0[q] - m.len[k]) <= JSON_DIGITS * 10 * m.len[k];
        bad += !found;
    }
    printf("%-20s %2d joints %2d bars: %s\n", file, m.nj, m.nb, bad ? "DIFFERS" : "equal");
    CHECK(bad == 0);
}

int main(void)
{
    const char *dir = getenv("KIN_SHARED_DIR");
    char probe[1024];
    snprintf(probe, sizeof probe, "%s/models/hex_sail.json", dir ? dir : "../shared");
    FILE *f = fopen(probe, "r");
    if (!f) {
        printf("test_models_json: %s not found, cross-check skipped\n", probe);
        return 0;
    }
    fclose(f);
    if (!dir) dir = "../shared";
    const char *three[3] = {"threebar_RA.json", "threebar_RB.json", "threebar_RC.json"};
    for (int s = 0; s < 3; ++s) {
        kin_assembly *a = NULL;
        CHECK_RC(kin_model_threebar(s, &a), KIN_OK);
        compare(dir, three[s], a);
        kin_assembly_free(a);
    }
    kin_sail_params p;
    kin_assembly *a = NULL;
    kin_sail_params_default(&p, 4, 1);
    CHECK_RC(kin_model_sail(&p, &a, NULL, 0), KIN_OK);
    compare(dir, "square_sail.json", a);
    kin_assembly_free(a);
    kin_sail_params_default(&p, 6, 2);
    CHECK_RC(kin_model_sail(&p, &a, NULL, 0), KIN_OK);
    compare(dir, "hex_sail.json", a);
    kin_assembly_free(a);
    TEST_REPORT("test_models_json");
}
