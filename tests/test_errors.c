/* Every error code of the core, provoked on purpose; a failed call leaves the
 * assembly exactly as it was. (KIN_ENOTFOUND and KIN_EGSL belong to the
 * locator and branch tests.) */
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "libkin.h"

static const double tri_xyz[6] = {0, 0, 1, 0, 0, 1};
static const int tri_bars[6] = {0, 1, 1, 2, 2, 0};

static void creation_errors(void)
{
    kin_assembly *a = (kin_assembly *)&a; /* must be reset to NULL on failure */
    char msg[256];
    CHECK_RC(kin_assembly_create(2, 3, NULL, NULL, 3, tri_bars, NULL, &a, msg, sizeof msg), KIN_ENULL);
    CHECK(a == NULL);
    CHECK(strstr(msg, "xyz") != NULL);
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 3, NULL, NULL, &a, msg, sizeof msg), KIN_ENULL);
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 3, tri_bars, NULL, NULL, msg, sizeof msg), KIN_ENULL);
    CHECK_RC(kin_assembly_create(4, 3, tri_xyz, NULL, 3, tri_bars, NULL, &a, msg, sizeof msg), KIN_EDIM);
    CHECK(strstr(msg, "dim = 4") != NULL);
    CHECK_RC(kin_assembly_create(1, 3, tri_xyz, NULL, 3, tri_bars, NULL, &a, NULL, 0), KIN_EDIM);
    CHECK_RC(kin_assembly_create(2, 1, tri_xyz, NULL, 3, tri_bars, NULL, &a, msg, sizeof msg), KIN_EINVAL);
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 0, tri_bars, NULL, &a, msg, sizeof msg), KIN_EINVAL);
    const int out_of_range[2] = {0, 3};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 1, out_of_range, NULL, &a, msg, sizeof msg), KIN_EJOINT);
    CHECK(strstr(msg, "bar 0") != NULL);
    const int negative[2] = {-1, 1};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 1, negative, NULL, &a, msg, sizeof msg), KIN_EJOINT);
    const int self[4] = {0, 1, 2, 2};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 2, self, NULL, &a, msg, sizeof msg), KIN_ESELFBAR);
    CHECK(strstr(msg, "bar 1") != NULL);
    const int dup[6] = {0, 1, 1, 2, 1, 0};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 3, dup, NULL, &a, msg, sizeof msg), KIN_EDUPBAR);
    CHECK(strstr(msg, "bars 0 and 2") != NULL);
    double nan_xyz[6] = {0, 0, 1, 0, 0, NAN};
    CHECK_RC(kin_assembly_create(2, 3, nan_xyz, NULL, 3, tri_bars, NULL, &a, msg, sizeof msg), KIN_EGEOM);
    double coincident[6] = {0, 0, 0, 0, 0, 1};
    CHECK_RC(kin_assembly_create(2, 3, coincident, NULL, 3, tri_bars, NULL, &a, msg, sizeof msg), KIN_EGEOM);
    CHECK(strstr(msg, "zero length") != NULL);
    const double bad_rest[3] = {1, -1, 1};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, NULL, 3, tri_bars, bad_rest, &a, msg, sizeof msg), KIN_EGEOM);
    const unsigned char all_fixed[6] = {1, 1, 1, 1, 1, 1};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, all_fixed, 3, tri_bars, NULL, &a, msg, sizeof msg), KIN_ENOFREE);
    /* 200000 free joints need a 600000^2 SVD workspace, past LAPACK's int
     * sizes: the handle is made (the sparse mode needs no dense matrix),
     * its dense analysis is refused with KIN_ENOMEM, at once */
    int nbig = 200000;
    double *big = calloc((size_t)nbig * 3, sizeof *big);
    if (big) {
        for (int j = 0; j < nbig; ++j) big[3 * j] = j;
        const int bar01[2] = {0, 1};
        CHECK_RC(kin_assembly_create(3, nbig, big, NULL, 1, bar01, NULL, &a, msg, sizeof msg), KIN_OK);
        kin_analysis an = {.size = sizeof an};
        if (a) CHECK_RC(kin_analyse(a, &an), KIN_ENOMEM);
        kin_assembly_free(a);
        a = NULL;
        free(big);
    }
    kin_assembly_free(NULL); /* no-op */
}

static void call_errors(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_assembly_free(a);
    a = (kin_assembly *)&a; /* a failed call must set the output to NULL */
    CHECK_RC(kin_model_threebar(7, &a), KIN_EINVAL);
    CHECK(a == NULL);
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, NULL), KIN_ENULL);
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    double sv[3], U[8], W[3], xyz[8], before[8];
    CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE);
    CHECK_RC(kin_get_singular_values(a, sv, 3), KIN_ESTATE);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, U, 4, 2), KIN_ESTATE);
    CHECK_RC(kin_get_self_stresses(a, W, 3, 1), KIN_ESTATE);
    CHECK_RC(kin_analyse(NULL, &an), KIN_ENULL);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK_RC(kin_get_singular_values(a, sv, 2), KIN_ERANGE);
    CHECK_RC(kin_get_singular_values(a, NULL, 3), KIN_ENULL);
    CHECK_RC(kin_get_mechanisms(a, 9, U, 4, 2), KIN_EINVAL);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, U, 3, 2), KIN_ERANGE);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, U, 4, 1), KIN_ERANGE);
    CHECK_RC(kin_get_self_stresses(a, W, 2, 1), KIN_ERANGE);
    CHECK_RC(kin_get_equilibrium_matrix(a, U, 3), KIN_ERANGE);
    CHECK_RC(kin_get_coords(NULL, xyz), KIN_ENULL);
    CHECK(kin_nfree(NULL) == -1 && kin_free_index(a, 0, 2) == -1 && kin_free_index(a, 2, 0) == -1);
    CHECK(kin_free_index(a, 1, 1) == 3);

    /* at R^C: a bifurcation, no direction chosen */
    CHECK_RC(kin_step(a, 0.01, NULL), KIN_EBIFURCATION);
    CHECK(strstr(kin_last_error(a), "2 internal mechanisms") != NULL);
    CHECK_RC(kin_step(a, NAN, NULL), KIN_EINVAL);
    const double notmech[4] = {1, 0, 0, 0};
    CHECK_RC(kin_path_set_direction(a, notmech, 4), KIN_EINVAL);
    const double nanmech[4] = {0, NAN, 0, 0};
    CHECK_RC(kin_path_set_direction(a, nanmech, 4), KIN_EGEOM);
    CHECK_RC(kin_path_set_direction(a, notmech, 3), KIN_ERANGE);
    CHECK_RC(kin_path_set_direction(a, NULL, 4), KIN_ENULL);

    /* options are validated and nothing changes on error */
    kin_options o = {.size = sizeof o}, keep = {.size = sizeof keep};
    kin_get_options(a, &keep);
    o = keep; o.rank_tol = 0.0;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep; o.corrector_tol = NAN;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep; o.corrector_max_iter = 0;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep; o.step_fraction = -1;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep; o.max_halvings = -1;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep; o.direction_tol = 1.0;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    o = keep; o.max_correction = 0.0;
    CHECK_RC(kin_set_options(a, &o), KIN_EINVAL);
    CHECK_RC(kin_set_options(a, NULL), KIN_ENULL);
    kin_get_options(a, &o);
    CHECK(memcmp(&o, &keep, sizeof o) == 0);

    /* supports cannot move; NaN rejected; the assembly is unchanged */
    kin_get_coords(a, before);
    memcpy(xyz, before, sizeof xyz);
    xyz[6] = 1.5;
    CHECK_RC(kin_set_coords(a, xyz), KIN_EINVAL);
    xyz[6] = before[6]; xyz[1] = NAN;
    CHECK_RC(kin_set_coords(a, xyz), KIN_EGEOM);
    xyz[1] = before[1]; xyz[0] = 0.0; xyz[1] = 0.0; /* J1 onto S1: bar 1 collapses */
    CHECK_RC(kin_set_coords(a, xyz), KIN_EINVAL);
    kin_get_coords(a, xyz);
    CHECK(memcmp(xyz, before, sizeof xyz) == 0);
    CHECK_RC(kin_relax(a, 0, NULL), KIN_EINVAL);

    /* LAPACK failures map to two different codes; dgesvd rescues dgesdd */
    kin__set_fault(a, KIN__FAULT_SVD_ARG);
    CHECK_RC(kin_analyse(a, &an), KIN_ELAPACK_ARG);
    kin__set_fault(a, KIN__FAULT_SVD_CONV);
    CHECK_RC(kin_analyse(a, &an), KIN_ELAPACK_CONV);
    CHECK(strstr(kin_last_error(a), "dgesvd") != NULL);
    kin__set_fault(a, KIN__FAULT_SDD_CONV);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.rank == 2 && an.s == 1);
    kin__set_fault(a, KIN__FAULT_NONE);
    kin_assembly_free(a);
}

/* steps that fail leave the handle untouched */
static void step_errors(void)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double xyz[8], before[8], after[8];
    kin_get_coords(a, xyz);
    xyz[0] = 0.6; xyz[1] = 0.8; xyz[2] = 1.6; xyz[3] = 0.8; /* regular point of P1 */
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK);
    kin_step_info info = {.size = sizeof info};
    CHECK_RC(kin_step(a, 0.05, &info), KIN_OK);
    kin_get_coords(a, before);
    double l0 = kin_path_length(a), t0[4], t1[4], sv0[3], sv1[3];
    kin_get_tangent(a, t0, 4);
    kin_get_singular_values(a, sv0, 3);

    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    kin_options tight = o;
    tight.corrector_max_iter = 1;
    tight.max_halvings = 2;
    CHECK_RC(kin_set_options(a, &tight), KIN_OK);
    CHECK_RC(kin_step(a, 0.1, &info), KIN_ENOTCONVERGED);
    CHECK(info.halvings == 3);

    kin_options jumpy = o;
    jumpy.direction_tol = 0.999999;
    jumpy.step_fraction = 2.0;
    jumpy.max_halvings = 0;
    CHECK_RC(kin_set_options(a, &jumpy), KIN_OK);
    CHECK_RC(kin_step(a, 1.0, &info), KIN_EPATHJUMP);
    CHECK(strstr(kin_last_error(a), "turned") != NULL);

    kin_get_coords(a, after);
    kin_get_tangent(a, t1, 4);
    kin_get_singular_values(a, sv1, 3);
    CHECK(memcmp(before, after, sizeof before) == 0);
    CHECK(memcmp(t0, t1, sizeof t0) == 0);
    CHECK(memcmp(sv0, sv1, sizeof sv0) == 0);
    CHECK(kin_path_length(a) == l0);
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    CHECK_RC(kin_step(a, 0.05, &info), KIN_OK);
    kin_assembly_free(a);

    /* a rigid triangle with one free joint cannot move */
    const unsigned char fix[6] = {1, 1, 1, 1, 0, 0};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, fix, 3, tri_bars, NULL, &a, NULL, 0), KIN_OK);
    CHECK_RC(kin_step(a, 0.1, NULL), KIN_ENOMECH);
    /* rest lengths that cannot close: relax fails and changes nothing */
    kin_assembly_free(a);
    const double impossible[3] = {1.0, 1.0, 5.0};
    CHECK_RC(kin_assembly_create(2, 3, tri_xyz, fix, 3, tri_bars, impossible, &a, NULL, 0), KIN_OK);
    kin_get_coords(a, before);
    double res = 0.0;
    CHECK_RC(kin_relax(a, 20, &res), KIN_ENOTCONVERGED);
    CHECK(res > 0.1);
    kin_get_coords(a, after);
    CHECK(memcmp(before, after, 6 * sizeof(double)) == 0);
    kin_assembly_free(a);
}

int main(void)
{
    creation_errors();
    call_errors();
    step_errors();
    TEST_REPORT("test_errors");
}
