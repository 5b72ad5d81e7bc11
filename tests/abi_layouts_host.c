/* A host built against the first layout of every size-prefixed struct
 * (docs/abi.md), linked with today's shared library (ctest abi_layouts_host).
 * Each struct is declared as that host has it (model/abi_layouts.h,
 * generated from the headers by tools/gen_abi.py), placed in a buffer
 * followed by guard bytes, and handed to the plain *_default() symbols (what
 * a binary built before the sized forms calls) and to every call that writes
 * into a caller's struct. The guards must stay untouched and the fields the
 * host has must be set. Also: the sized *_init() forms accept exactly the
 * published layout sizes, and a first-layout kin_options carries
 * step_control in its tail padding (a 0.3.0 host's): honoured when valid,
 * refused when garbage. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "model/abi_layouts.h"

#define GUARD 0xAB

/* a struct of `size` bytes followed by guard bytes the library must not touch */
typedef union {
    unsigned char bytes[1024];
    double align_d;
    long long align_ll;
    void *align_p;
} guarded;

static void *fresh(guarded *g, size_t size)
{
    memset(g->bytes, GUARD, sizeof g->bytes);
    memcpy(g->bytes, &size, sizeof size);
    return g->bytes;
}

static int untouched(const guarded *g, size_t from)
{
    for (size_t i = from; i < sizeof g->bytes; ++i)
        if (g->bytes[i] != GUARD) return 0;
    return 1;
}

static size_t size_of(const guarded *g)
{
    size_t s;
    memcpy(&s, g->bytes, sizeof s);
    return s;
}

/* the plain *_default symbols, as a binary built before the macros calls them */
static void defaults_symbols(void)
{
    guarded g;
    memset(g.bytes, GUARD, sizeof g.bytes);
    (kin_options_default)((kin_options *)g.bytes);
    CHECK(untouched(&g, sizeof(kin__kin_options_layout1)));
    CHECK(size_of(&g) == sizeof(kin__kin_options_layout1));
    kin__kin_options_layout1 o;
    memcpy(&o, g.bytes, sizeof o);
    CHECK(o.rank_tol == 1e-9 && o.corrector_max_iter == 60 && o.factorization == KIN_STEP_SVD);

    memset(g.bytes, GUARD, sizeof g.bytes);
    (kin_locate_options_default)((kin_locate_options *)g.bytes);
    CHECK(untouched(&g, sizeof(kin__kin_locate_options_layout1)));
    CHECK(size_of(&g) == sizeof(kin__kin_locate_options_layout1));
    kin__kin_locate_options_layout1 lo;
    memcpy(&lo, g.bytes, sizeof lo);
    CHECK(lo.method == KIN_LOCATE_FAST && lo.max_steps == 1000 && lo.use_switch_rule == 1);

    memset(g.bytes, GUARD, sizeof g.bytes);
    (kin_follow_options_default)((kin_follow_options *)g.bytes);
    CHECK(untouched(&g, sizeof(kin__kin_follow_options_layout1)));
    CHECK(size_of(&g) == sizeof(kin__kin_follow_options_layout1));
    kin__kin_follow_options_layout1 fo;
    memcpy(&fo, g.bytes, sizeof fo);
    CHECK(fo.vr_tol == 1e-10 && fo.max_steps == 1000 && fo.branch_cos == 0.99);

    memset(g.bytes, GUARD, sizeof g.bytes);
    (kin_homotopy_options_default)((kin_homotopy_options *)g.bytes);
    CHECK(untouched(&g, sizeof(kin__kin_homotopy_options_layout1)));
    CHECK(size_of(&g) == sizeof(kin__kin_homotopy_options_layout1));
    kin__kin_homotopy_options_layout1 ho;
    memcpy(&ho, g.bytes, sizeof ho);
    CHECK(ho.seed == 1 && ho.max_paths == KIN_HOMOTOPY_MAX_PATHS && ho.progress == NULL);

    memset(g.bytes, GUARD, sizeof g.bytes);
    (kin_sail_params_default)((kin_sail_params *)g.bytes, 6, 2);
    CHECK(untouched(&g, sizeof(kin__kin_sail_params_layout1)));
    CHECK(size_of(&g) == sizeof(kin__kin_sail_params_layout1));
    kin__kin_sail_params_layout1 sp;
    memcpy(&sp, g.bytes, sizeof sp);
    CHECK(sp.n_sides == 6 && sp.n_loops == 2 && sp.side == 1.0 && sp.widths == NULL);

    (kin_options_default)(NULL); /* does nothing */
}

#ifndef ABI_HOST_OLD_SYMBOLS
/* the sized forms: exactly the published layout sizes. (Built with
 * -DABI_HOST_OLD_SYMBOLS the host calls only functions an older library
 * has, to run it against one.) */
static void sized_init(void)
{
    guarded g;
    const size_t sizes[2] = {sizeof(kin__kin_options_layout1), sizeof(kin_options)};
    for (int i = 0; i < 2; ++i) {
        memset(g.bytes, GUARD, sizeof g.bytes);
        CHECK_RC(kin_options_init((kin_options *)g.bytes, sizes[i]), KIN_OK);
        CHECK(untouched(&g, sizes[i]) && size_of(&g) == sizes[i]);
    }
    kin_options o;
    memset(&o, 0x7F, sizeof o);
    CHECK_RC(kin_options_init(&o, sizeof o), KIN_OK);
    CHECK(o.size == sizeof o && o.rank_tol == 1e-9 && o.step_control == KIN_STEP_CONTROL_MODE);
    /* not a layout: the end of layout 1's fields (inside its padding), a size
     * from newer headers, 0 */
    const size_t bad[3] = {offsetof(kin__kin_options_layout1, factorization) + sizeof(int),
                           sizeof(kin_options) + 8, 0};
    for (int i = 0; i < 3; ++i) {
        memset(g.bytes, GUARD, sizeof g.bytes);
        if (bad[i] == sizeof(kin__kin_options_layout1)) continue; /* no padding on this platform */
        CHECK_RC(kin_options_init((kin_options *)g.bytes, bad[i]), KIN_EINVAL);
        CHECK(untouched(&g, 0));
    }
    CHECK_RC(kin_options_init(NULL, sizeof o), KIN_ENULL);

    kin_locate_options lo;
    CHECK_RC(kin_locate_options_init(&lo, sizeof lo), KIN_OK);
    CHECK(lo.size == sizeof lo && lo.method == KIN_LOCATE_FAST);
    CHECK_RC(kin_locate_options_init(&lo, sizeof lo + 8), KIN_EINVAL);
    kin_follow_options fo;
    CHECK_RC(kin_follow_options_init(&fo, sizeof fo), KIN_OK);
    CHECK(fo.size == sizeof fo && fo.vr_floor == 1e-6);
    CHECK_RC(kin_follow_options_init(&fo, 1), KIN_EINVAL);
    kin_homotopy_options ho;
    CHECK_RC(kin_homotopy_options_init(&ho, sizeof ho), KIN_OK);
    CHECK(ho.size == sizeof ho && ho.seed == 1);
    CHECK_RC(kin_homotopy_options_init(&ho, sizeof ho - 1), KIN_EINVAL);
    kin_sail_params sp;
    CHECK_RC(kin_sail_params_init(&sp, sizeof sp, 4, 1), KIN_OK);
    CHECK(sp.size == sizeof sp && sp.n_sides == 4 && sp.n_loops == 1);
    CHECK_RC(kin_sail_params_init(&sp, sizeof sp + 8, 4, 1), KIN_EINVAL);
    /* the macro: a recompiled host gets every field */
    kin_options m;
    memset(&m, 0x7F, sizeof m);
    kin_options_default(&m);
    CHECK(m.size == sizeof m && m.step_control == KIN_STEP_CONTROL_MODE);
}
#endif

#include "abi_host030.h"


/* layout 1's tail padding: step_control of a 0.3.0 host is honoured, zero
 * (the earlier 0.3.0 headers, whose padding kin_options_default() zeroes) is
 * the default, anything else is refused (KIN_EINVAL, nothing changes), never
 * silently dropped */
static void tail_padding(kin_assembly *a)
{
    CHECK(sizeof(struct host030_options) == sizeof(kin__kin_options_layout1));
    CHECK(offsetof(struct host030_options, step_control) == offsetof(kin_options, step_control));
    guarded g;
    struct host030_options *h = fresh(&g, sizeof(struct host030_options));
    (kin_options_default)((kin_options *)h);
    CHECK(untouched(&g, sizeof *h) && h->step_control == KIN_STEP_CONTROL_MODE);
    h->step_control = KIN_STEP_CONTROL_SHARED;
    h->factorization = KIN_STEP_LU;
    CHECK_RC(kin_set_options(a, (kin_options *)h), KIN_OK);
    kin_options full = {.size = sizeof full};
    CHECK_RC(kin_get_options(a, &full), KIN_OK);
    CHECK(full.step_control == KIN_STEP_CONTROL_SHARED && full.factorization == KIN_STEP_LU);
    h = fresh(&g, sizeof(struct host030_options));
    CHECK_RC(kin_get_options(a, (kin_options *)h), KIN_OK);
    CHECK(untouched(&g, sizeof *h) && h->step_control == KIN_STEP_CONTROL_SHARED);

    (kin_options_default)((kin_options *)h);
    size_t end = offsetof(kin__kin_options_layout1, factorization) + sizeof(int);
    memset(g.bytes + end, 0x7F, sizeof(kin__kin_options_layout1) - end); /* garbage: refused */
    CHECK_RC(kin_set_options(a, (kin_options *)h), KIN_EINVAL);
    CHECK_RC(kin_get_options(a, &full), KIN_OK);
    CHECK(full.step_control == KIN_STEP_CONTROL_SHARED && full.factorization == KIN_STEP_LU);
    memset(g.bytes + end, 0, sizeof(kin__kin_options_layout1) - end); /* zero: the default */
    CHECK_RC(kin_set_options(a, (kin_options *)h), KIN_OK);
    CHECK_RC(kin_get_options(a, &full), KIN_OK);
    CHECK(full.step_control == KIN_STEP_CONTROL_MODE && full.factorization == KIN_STEP_SVD && full.rank_tol == 1e-9);
}

/* a regular point of the three-bar linkage: the parallelogram at 1 rad */
static kin_assembly *parallelogram(void)
{
    const double xyz[8] = {cos(1.0), sin(1.0), cos(1.0) + 1, sin(1.0), 0, 0, 1, 0};
    const unsigned char fixed[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    const int bars[6] = {2, 0, 0, 1, 1, 3};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 4, xyz, fixed, 3, bars, NULL, &a, NULL, 0), KIN_OK);
    return a;
}

static void outputs_on_handle(void)
{
    kin_assembly *a = parallelogram();
    guarded g;
    tail_padding(a);

    kin_options *op = fresh(&g, sizeof(kin__kin_options_layout1));
    CHECK_RC(kin_get_options(a, op), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_options_layout1)));
    CHECK(op->rank_tol == 1e-9 && op->corrector_max_iter == 60);
    CHECK_RC(kin_set_options(a, op), KIN_OK);

    kin_analysis *an = fresh(&g, sizeof(kin__kin_analysis_layout1));
    CHECK_RC(kin_analyse(a, an), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_analysis_layout1)) && an->m_internal == 1);
    an = fresh(&g, sizeof(kin__kin_analysis_layout1));
    CHECK_RC(kin_get_analysis(a, an), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_analysis_layout1)) && an->m_internal == 1 && an->v_r > 0.0);

    kin_step_info *si = fresh(&g, sizeof(kin__kin_step_info_layout1));
    CHECK_RC(kin_step(a, 0.01, si), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_step_info_layout1)) && si->m_internal == 1 && si->delta > 0.0);

    /* locate with first-layout options and info */
    guarded go;
    kin_locate_options *lo = fresh(&go, sizeof(kin__kin_locate_options_layout1));
    (kin_locate_options_default)(lo);
    kin_locate_info *li = fresh(&g, sizeof(kin__kin_locate_info_layout1));
    kin_assembly *b = NULL;
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    CHECK_RC(kin_locate_next(b, lo, li), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_locate_info_layout1)) && untouched(&go, sizeof(kin__kin_locate_options_layout1)));
    CHECK(li->located == 1 && li->m_internal == 2 && li->s == 1);
    kin_assembly_free(b);

    /* follow likewise */
    kin_follow_options *fo = fresh(&go, sizeof(kin__kin_follow_options_layout1));
    (kin_follow_options_default)(fo);
    kin_follow_info *fi = fresh(&g, sizeof(kin__kin_follow_info_layout1));
    CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
    CHECK_RC(kin_follow_event(b, NULL, fo, fi), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_follow_info_layout1)) && untouched(&go, sizeof(kin__kin_follow_options_layout1)));
    CHECK(fi->event == KIN_FOLLOW_BIFURCATION && fi->m_internal == 2);

    /* the bifurcation b sits on: branch paths into an array of first-layout elements */
    const double betas[2] = {1.0, 0.0};
    int nd = -1;
    size_t es = sizeof(kin__kin_branch_path_layout1);
    kin_branch_path *bp = fresh(&g, es);
    CHECK_RC(kin_branch_paths(b, betas, 1, 0.1, bp, NULL, &nd), KIN_OK);
    CHECK(untouched(&g, 2 * es));
    kin__kin_branch_path_layout1 p1;
    memcpy(&p1, g.bytes + es, sizeof p1);
    CHECK(p1.size == es && p1.sign == -1 && bp->sign == 1);
    kin_assembly_free(b);
    kin_assembly_free(a);
}

static void outputs_without_handle(void)
{
    const double Q[4] = {1, 0, 0, -1};
    double beta[4];
    int nsol = -1;
    guarded g, go;
    kin_solve_info *si = fresh(&g, sizeof(kin__kin_solve_info_layout1));
    CHECK_RC(kin_quadrics_scan(2, 1, Q, 4, 1, beta, 2, &nsol, si), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_solve_info_layout1)) && si->distinct == 2);

    kin_homotopy_info *hi = fresh(&g, sizeof(kin__kin_homotopy_info_layout1));
    CHECK_RC(kin_quadrics_homotopy(2, 1, Q, 1, 1, beta, 2, &nsol, NULL, hi), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_homotopy_info_layout1)) && hi->paths == 2 && hi->real_distinct == 2);

    kin_homotopy_options *ho = fresh(&go, sizeof(kin__kin_homotopy_options_layout1));
    (kin_homotopy_options_default)(ho);
    hi = fresh(&g, sizeof(kin__kin_homotopy_info_layout1));
    CHECK_RC(kin_quadrics_homotopy_ex(2, 1, Q, ho, beta, 2, &nsol, NULL, hi), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_homotopy_info_layout1)) && hi->paths == 2);

    guarded gs;
    hi = fresh(&g, sizeof(kin__kin_homotopy_info_layout1));
    kin_homotopy_sym_info *ys = fresh(&gs, sizeof(kin__kin_homotopy_sym_info_layout1));
    CHECK_RC(kin_quadrics_homotopy_sym(2, 1, Q, 0, NULL, ho, beta, 2, &nsol, NULL, hi, ys, NULL, 0), KIN_OK);
    CHECK(untouched(&g, sizeof(kin__kin_homotopy_info_layout1)) && hi->paths == 2);
    CHECK(untouched(&gs, sizeof(kin__kin_homotopy_sym_info_layout1)) && ys->group >= 1);

    kin_sail_params *sp = fresh(&go, sizeof(kin__kin_sail_params_layout1));
    (kin_sail_params_default)(sp, 6, 2);
    int nj = -1, nb = -1;
    CHECK_RC(kin_sail_size(sp, &nj, &nb), KIN_OK);
    CHECK(nj == 19 && nb == 45);
    kin_assembly *s = NULL;
    CHECK_RC(kin_model_sail(sp, &s, NULL, 0), KIN_OK);
    CHECK(untouched(&go, sizeof(kin__kin_sail_params_layout1)));
    kin_assembly_free(s);
}

int main(void)
{
    defaults_symbols();
#ifndef ABI_HOST_OLD_SYMBOLS
    sized_init();
#endif
    outputs_on_handle();
    outputs_without_handle();
    TEST_REPORT("abi_layouts_host");
}
