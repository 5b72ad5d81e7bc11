/* All branches at a bifurcation (paper 3.3-3.4) on the solar sails:
 * - square sail, flat state: the 2^4 = 16 real solutions (the paper's scan
 *   found 15), each extending into a finite path in both directions, the 32
 *   directed paths pairwise distinct at l = 1.75;
 * - the printed eq. 17 (no 1/L_i) gives "solutions" that are not paths;
 * - hexagonal sail at R^B: m = 4, s = 3, its real solutions and paths. */
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

typedef struct outcome {
    int real, paths_ok, distinct;
} outcome;

static outcome branches(kin_assembly *a, int weighting, int starts, double l)
{
    outcome o = {0, 0, 0};
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    int m = an.m_internal, s = 0;
    double *Q = malloc(sizeof(double) * m * m * an.s), *betas = malloc(sizeof(double) * m * 256);
    CHECK_RC(kin_second_order(a, weighting, 1, Q, m * m * an.s, &s), KIN_OK);
    CHECK(s == an.s && m == s + 1);
    int nsol = 0;
    kin_solve_info info = {.size = sizeof info};
    CHECK_RC(kin_quadrics_scan(m, s, Q, starts, 3, betas, 256, &nsol, &info), KIN_OK);
    o.real = nsol;
    kin_branch_path *p = calloc(2 * (size_t)(nsol ? nsol : 1), sizeof *p);
    if (p) p[0].size = sizeof *p;
    if (nsol) {
        double *before = malloc(sizeof(double) * 3 * kin_njoints(a)), *after = malloc(sizeof(double) * 3 * kin_njoints(a));
        kin_get_coords(a, before);
        CHECK_RC(kin_branch_paths(a, betas, nsol, l, p, NULL, &o.distinct), KIN_OK);
        kin_get_coords(a, after);
        CHECK(memcmp(before, after, sizeof(double) * 3 * kin_njoints(a)) == 0); /* caller's state kept */
        /* lengths count from the bifurcation, not from where the assembly's
         * own path began (R^B is reached at l = 3.39 from the flat state) */
        for (int k = 0; k < 2 * nsol; ++k)
            o.paths_ok += p[k].exists && p[k].tangent_ok && p[k].length >= l - 1e-12 && p[k].length < 2.0 * l;
        free(before);
        free(after);
    }
    free(p);
    free(Q);
    free(betas);
    return o;
}

int main(void)
{
    kin_assembly *a = test_sail(4, 1);
    outcome sq = branches(a, KIN_Q_EXACT, 1024, 1.75);
    printf("square sail flat: %d real solutions, %d of %d directed paths exist with the right tangent, %d distinct\n",
           sq.real, sq.paths_ok, 2 * sq.real, sq.distinct);
    CHECK(sq.real == 16);
    CHECK(sq.paths_ok == 32);
    CHECK(sq.distinct == 32);
    outcome pe = branches(a, KIN_Q_PAPER_EQ17, 1024, 1.75);
    printf("square sail flat, printed eq. 17 (no 1/L): %d 'solutions', %d directed paths with the right tangent\n",
           pe.real, pe.paths_ok);
    CHECK(pe.paths_ok == 0);
    kin_assembly_free(a);

    a = test_sail(6, 2);
    CHECK_RC(test_hex_to_RB(a), KIN_OK);
    outcome rb = branches(a, KIN_Q_EXACT, 512, 0.5);
    printf("hexagonal sail R^B: %d real solutions, %d of %d directed paths exist with the right tangent, %d distinct\n",
           rb.real, rb.paths_ok, 2 * rb.real, rb.distinct);
    CHECK(rb.real == 8);
    CHECK(rb.paths_ok == 2 * rb.real);
    CHECK(rb.distinct == 2 * rb.real);
    kin_assembly_free(a);

    /* errors */
    a = test_sail(4, 1);
    kin_branch_path p[2] = {{.size = sizeof(kin_branch_path)}};
    double beta[5] = {1, 0, 0, 0, 0};
    int nd;
    CHECK_RC(kin_branch_paths(a, beta, 1, 1.0, p, NULL, &nd), KIN_ESTATE);
    kin_analysis an = {.size = sizeof an};
    kin_analyse(a, &an);
    CHECK_RC(kin_branch_paths(a, beta, 0, 1.0, p, NULL, &nd), KIN_EINVAL);
    CHECK_RC(kin_branch_paths(a, beta, 1, -1.0, p, NULL, &nd), KIN_EINVAL);
    CHECK_RC(kin_branch_paths(a, NULL, 1, 1.0, p, NULL, &nd), KIN_ENULL);
    kin_assembly_free(a);
    TEST_REPORT("test_branches");
}
