/* The built-in models equal the cross-check copies in examples/models/NAME.json
 * (joints in the same order with the same coordinates and fixity; the same
 * bars, in any order, with the same rest lengths), read with
 * kin_assembly_load. The folder comes from $KIN_SHARED_DIR (set by
 * tests/CMakeLists.txt; "../shared" if unset); the test skips (exit 0 with
 * a note) when its models are absent. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"

/* JSON files carry 12 significant digits */
static const double JSON_DIGITS = 1e-11;

static void compare(const char *dir, const char *file, kin_assembly *a)
{
    char path[1024], err[512];
    snprintf(path, sizeof path, "%s/models/%s", dir, file);
    kin_assembly *m = NULL;
    CHECK_RC(kin_assembly_load(path, &m, err, sizeof err), KIN_OK);
    if (!m) {
        fprintf(stderr, "%s\n", err);
        return;
    }
    int dim = kin_dim(m), nj = kin_njoints(m), nb = kin_nbars(m);
    CHECK(dim == kin_dim(a) && nj == kin_njoints(a) && nb == kin_nbars(a));
    if (dim != kin_dim(a) || nj != kin_njoints(a) || nb != kin_nbars(a)) {
        kin_assembly_free(m);
        return;
    }
    size_t nc = (size_t)nj * (size_t)dim;
    double *xyz = malloc(sizeof(double) * 2 * (nc + (size_t)nb));
    double *mxyz = xyz + nc, *L0 = mxyz + nc, *mL0 = L0 + nb;
    int *bars = malloc(sizeof(int) * 4 * (size_t)nb), *mbars = bars + 2 * nb;
    unsigned char *fixed = malloc(2 * nc), *mfixed = fixed + nc;
    CHECK(xyz && bars && fixed);
    if (!xyz || !bars || !fixed) {
        free(xyz);
        free(bars);
        free(fixed);
        kin_assembly_free(m);
        return;
    }
    kin_get_coords(a, xyz);
    kin_get_fixed(a, fixed);
    kin_get_bars(a, bars);
    kin_get_rest_lengths(a, L0);
    kin_get_coords(m, mxyz);
    kin_get_fixed(m, mfixed);
    kin_get_bars(m, mbars);
    kin_get_rest_lengths(m, mL0);
    int bad = 0;
    for (size_t i = 0; i < nc; ++i) {
        bad += fabs(xyz[i] - mxyz[i]) > JSON_DIGITS * 10;
        bad += fixed[i] != mfixed[i];
    }
    for (int k = 0; k < nb; ++k) {
        int found = 0;
        for (int q = 0; q < nb && !found; ++q)
            if ((bars[2 * q] == mbars[2 * k] && bars[2 * q + 1] == mbars[2 * k + 1]) ||
                (bars[2 * q] == mbars[2 * k + 1] && bars[2 * q + 1] == mbars[2 * k]))
                found = fabs(L0[q] - mL0[k]) <= JSON_DIGITS * 10 * mL0[k];
        bad += !found;
    }
    printf("%-20s %2d joints %2d bars: %s\n", file, nj, nb, bad ? "DIFFERS" : "equal");
    CHECK(bad == 0);
    free(xyz);
    free(bars);
    free(fixed);
    kin_assembly_free(m);
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
    kin_sail_params p = {.size = sizeof p};
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
