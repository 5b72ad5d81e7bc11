/* Size-prefixed structs (docs/abi.md): a struct whose `size` is not one this
 * library knows is refused before anything is read or written, the library
 * never writes past the caller's `size`, and options from the *_default()
 * functions are accepted. */
#include <string.h>

#include "check.h"
#include "libkin.h"

/* a caller's struct followed by bytes the library must not touch */
typedef union {
    unsigned char bytes[512];
    double align_d;
    long long align_ll;
    void *align_p;
} guarded;

static int untouched(const guarded *g, size_t from)
{
    for (size_t i = from; i < sizeof g->bytes; ++i)
        if (g->bytes[i] != 0xAB) return 0;
    return 1;
}

static void set_size(guarded *g, size_t size)
{
    memset(g->bytes, 0xAB, sizeof g->bytes);
    memcpy(g->bytes, &size, sizeof size);
}

static void outputs(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RA, &a), KIN_OK);
    guarded g;
    /* a size of 0 (a struct nobody initialised) and one from newer headers
     * (each struct's own: another struct's size + 8 can be a valid layout) */
    for (int i = 0; i < 2; ++i) {
        set_size(&g, i ? sizeof(kin_analysis) + 8 : 0);
        CHECK_RC(kin_analyse(a, (kin_analysis *)g.bytes), KIN_EINVAL);
        CHECK(untouched(&g, sizeof(size_t)));
        set_size(&g, i ? sizeof(kin_step_info) + 8 : 0);
        CHECK_RC(kin_step(a, 0.01, (kin_step_info *)g.bytes), KIN_EINVAL);
        CHECK(untouched(&g, sizeof(size_t)));
        set_size(&g, i ? sizeof(kin_options) + 8 : 0);
        CHECK_RC(kin_get_options(a, (kin_options *)g.bytes), KIN_EINVAL);
        CHECK(untouched(&g, sizeof(size_t)));
        set_size(&g, i ? sizeof(kin_options) + 8 : 0);
        CHECK_RC(kin_set_options(a, (const kin_options *)g.bytes), KIN_EINVAL);
    }
    /* the right size: written exactly up to it */
    set_size(&g, sizeof(kin_analysis));
    CHECK_RC(kin_analyse(a, (kin_analysis *)g.bytes), KIN_OK);
    CHECK(untouched(&g, sizeof(kin_analysis)));
    kin_analysis an = {.size = sizeof an};
    memcpy(&an, g.bytes, sizeof an);
    CHECK(an.size == sizeof an && an.m_internal == 2 && an.s == 1);
    set_size(&g, sizeof(kin_options));
    CHECK_RC(kin_get_options(a, (kin_options *)g.bytes), KIN_OK);
    CHECK(untouched(&g, sizeof(kin_options)));
    kin_options o = {.size = sizeof o};
    memcpy(&o, g.bytes, sizeof o);
    CHECK(o.size == sizeof o && o.rank_tol > 0.0);
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    kin_assembly_free(a);
}

static void handle_free(void)
{
    /* the solvers check sizes before anything else */
    const double Q[4] = {1, 0, 0, -1};
    double beta[4];
    int nsol = -1;
    guarded g;
    set_size(&g, 3);
    CHECK_RC(kin_quadrics_scan(2, 1, Q, 4, 1, beta, 1, &nsol, (kin_solve_info *)g.bytes), KIN_EINVAL);
    CHECK(untouched(&g, sizeof(size_t)));
    set_size(&g, 3);
    CHECK_RC(kin_quadrics_homotopy(2, 1, Q, 1, 1, beta, 1, &nsol, NULL, (kin_homotopy_info *)g.bytes), KIN_EINVAL);
    CHECK(untouched(&g, sizeof(size_t)));
    set_size(&g, sizeof(kin_homotopy_info));
    CHECK_RC(kin_quadrics_homotopy(2, 1, Q, 1, 1, beta, 2, &nsol, NULL, (kin_homotopy_info *)g.bytes), KIN_OK);
    CHECK(untouched(&g, sizeof(kin_homotopy_info)));
    kin_homotopy_info h = {.size = sizeof h};
    memcpy(&h, g.bytes, sizeof h);
    CHECK(h.paths == 2 && h.real == 2 && h.real_distinct == 2 && nsol == 2);

    kin_sail_params p = {.size = 0};
    int nj = -1, nb = -1;
    CHECK_RC(kin_sail_size(&p, &nj, &nb), KIN_EINVAL);
    kin_sail_params_default(&p, 6, 2);
    CHECK(p.size == sizeof p);
    CHECK_RC(kin_sail_size(&p, &nj, &nb), KIN_OK);
    CHECK(nj == 19 && nb == 45);
    kin_locate_options lo = {.size = sizeof lo};
    kin_locate_options_default(&lo);
    CHECK(lo.size == sizeof lo);
}

static void branch_array(void)
{
    /* the element size of the caller's array is paths[0].size */
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    CHECK_RC(kin_analyse(a, NULL), KIN_OK);
    const double betas[2] = {1.0, 0.0};
    int nd = -1;
    kin_branch_path paths[2] = {{.size = 0}};
    CHECK_RC(kin_branch_paths(a, betas, 1, 0.1, paths, NULL, &nd), KIN_EINVAL);
    paths[0].size = sizeof paths[0];
    CHECK_RC(kin_branch_paths(a, betas, 1, 0.1, paths, NULL, &nd), KIN_OK);
    CHECK(paths[1].size == sizeof paths[1] && paths[0].sign == 1 && paths[1].sign == -1);
    kin_assembly_free(a);
}

int main(void)
{
    outputs();
    handle_free();
    branch_array();
    TEST_REPORT("test_abi");
}
