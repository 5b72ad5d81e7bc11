/* libFuzzer harness: kin_assembly_create on arrays made from the bytes (any
 * counts, coordinates, bars, fixity and rest lengths: fuzz_create_format.h),
 * then, on a model that was accepted, its analysis, a step at a regular
 * point, and as the last byte asks: a short locate, the second order, root
 * scan and paths at a bifurcation, the symmetry group, a short follow, the
 * clearance, a JSON round trip. Sizes
 * are kept small (up to 23 joints, 63 bars) so each input runs in about a
 * millisecond. fuzz_seeds.c writes the built-in and shared models in this
 * format (valid structures reach far more code than bytes alone). */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "libkin.h"

#include "fuzz_create_format.h"

/* at a bifurcation: the second-order matrices, their real roots, the paths */
static void branches(kin_assembly *a, const kin_analysis *an)
{
    int m = an->m_internal, s = an->s, ns = 0, nsol = 0, nd = 0;
    if (m < 2 || s < 1 || m > 6 || s > 4 || m != s + 1) return;
    double Q[4 * 36], betas[6 * 4];
    if (kin_second_order(a, KIN_Q_EXACT, 1, Q, (int)(sizeof Q / sizeof *Q), &ns) != KIN_OK || ns != s) return;
    kin_solve_info si = {.size = sizeof si};
    if (kin_quadrics_scan(m, s, Q, 8, 1ul, betas, 4, &nsol, &si) != KIN_OK || nsol < 1) return;
    kin_branch_path paths[8];
    for (int i = 0; i < 8; ++i) paths[i] = (kin_branch_path){.size = sizeof paths[i]};
    (void)kin_branch_paths(a, betas, nsol, 0.05, paths, NULL, &nd);
}

/* a short follow: along the path at a regular point, along the first
 * internal mechanism at a bifurcation */
static void follow(kin_assembly *a, const kin_analysis *an)
{
    int nf = kin_nfree(a), m = an->m_internal;
    if (m < 1 || nf < 1) return;
    double *u = malloc(sizeof(double) * (size_t)nf * (size_t)m);
    if (u && (m == 1 || kin_get_mechanisms(a, KIN_MECH_INTERNAL, u, nf, m) == KIN_OK)) {
        kin_follow_options fo;
        kin_follow_options_default(&fo);
        fo.max_steps = 6;
        fo.max_iter = 8;
        kin_follow_info fi = {.size = sizeof fi};
        (void)kin_follow_event(a, m == 1 ? NULL : u, &fo, &fi);
    }
    free(u);
}

static void more_calls(kin_assembly *a, int ops)
{
    kin_analysis an = {.size = sizeof an};
    if (kin_analyse(a, &an) != KIN_OK) return;
    if (an.m_internal == 1) {
        kin_step_info info = {.size = sizeof info};
        (void)kin_step(a, 0.0, &info);
        if (ops & FUZZ_CREATE_LOCATE) {
            kin_locate_options lo;
            kin_locate_options_default(&lo);
            lo.max_steps = 4;
            lo.max_iter = 8;
            kin_locate_info li = {.size = sizeof li};
            (void)kin_locate_next(a, &lo, &li);
        }
    } else if (ops & FUZZ_CREATE_BRANCHES) {
        branches(a, &an);
    }
    if (ops & FUZZ_CREATE_SYMMETRY) {
        int nsym = 0;
        (void)kin_symmetries(a, 48, NULL, NULL, NULL, &nsym);
    }
    if ((ops & FUZZ_CREATE_FOLLOW) && kin_analyse(a, &an) == KIN_OK) follow(a, &an);
    if (ops & FUZZ_CREATE_CLEARANCE) {
        double c = 0.0, pts[6];
        int parts[4];
        (void)kin_clearance(a, NULL, 1e300, &c, parts, pts);
    }
    if (ops & FUZZ_CREATE_SAVE) {
        char *text = NULL;
        size_t len = 0;
        if (kin_assembly_save_string(a, "fuzz", &text, &len, NULL, 0) == KIN_OK) {
            kin_assembly *b = NULL;
            /* what the library wrote, it must read */
            if (kin_assembly_load_string(text, len, &b, NULL, 0) != KIN_OK) __builtin_trap();
            kin_assembly_free(b);
            kin_free_string(text);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_model m;
    if (fuzz_create_decode(data, size, &m) == 0) {
        kin_assembly *a = NULL;
        char err[256];
        int rc = kin_assembly_create(m.dim, m.nj, m.xyz, m.fixed, m.nb, m.bars, m.with_rest ? m.rest : NULL, &a,
                                     err, sizeof err);
        if ((rc == KIN_OK) != (a != NULL)) __builtin_trap();
        if (a) {
            more_calls(a, m.ops);
            kin_assembly_free(a);
        }
    }
    fuzz_model_free(&m);
    return 0;
}
