/* Locating a bifurcation where several singular values vanish together,
 * unlike each other (issue 35 item 3; docs/locate.md, "Several singular
 * values vanishing ... corank k"): the hexagonal sail's collapsed-hub state,
 * reached along a symmetric path out of the flat state. There three
 * singular values of H vanish to a high order (they stay at or below 1e-8
 * of v_max over +-3e-3 of path) and a degenerate pair crosses zero linearly
 * at the same point: m_internal = 6, s = 5. The corank-1 method could not
 * pin the point (it gave up at 1e-10, and a tolerance relaxed to 1e-7 gave
 * a point 6e-3 away with the pair at 6e-4 and m = 4, s = 3); the corank-k
 * mode must bring all five to 1e-10 of v_max, from either direction and
 * with the default and a tight tolerance, and leave the point strain-free.
 * The start is a point of that path (l = 8.43 from the flat state), written
 * out as the exact doubles a follow reached; the test on the path is the
 * point it locates, not how. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

/* the joints (19 x 3) and the oriented tangent (46 free coordinates) */
static const double COLLAPSE_XYZ[57] = {
    0, 0, 0.99359869362381703,
    -0.49999999999999989, -0.86602540378443893, 0,
    2.0489195900551186e-05, -3.5488328306205399e-05, -0.0064013055365689086,
    1.0000000000000002, 0, 0,
    2.0489195900329138e-05, 3.5488328306205386e-05, -0.0064013055365689086,
    -0.49999999999999989, 0.86602540378443893, 0,
    -4.097839180081518e-05, -3.8459253727671281e-16, -0.0064013055365689086,
    -0.50448504941601469, -0.85916906420459349, 0.57729213425494985,
    0.00362298923161338, -0.0063829340584741689, -0.58370544137791947,
    0.99630476045488847, -0.0073123365208142502, 0.57729213425495751,
    0.0037162884295126896, 0.0063290677414526014, -0.58370544137791958,
    -0.49181971103946071, 0.86648140072567414, 0.57729213425495829,
    -0.0073392776611173518, 5.3866317026966401e-05, -0.58370544137791958,
    -0.52009924158712983, -0.46921037409452826, 1.0027586433291884,
    0.08767856640485143, -0.41054391773327947, -0.98734128289155521,
    0.66639772447874313, -0.21581396865578187, 1.0027586433291997,
    0.31170217892362895, 0.28120382474080491, -0.98734128289156242,
    -0.14629848289211297, 0.68502434275046764, 1.0027586433292499,
    -0.39938074532854317, 0.12934009299259919, -0.98734128289164891
};

static const double COLLAPSE_T[46] = {
    0.12605697001317401, -0.00080699489540031954, 0.0013977561602822382,
    0.12605690387446794, -0.00080699489540027813, -0.0013977561602821552,
    0.12605690387446797, 0.0016139897908008061, 5.7245874707234622e-17,
    0.12605690387446802, 0.095586989979537074, -0.13918605863071012,
    0.0023957008493174568, -0.069812380036881394, 0.12527631474202777,
    0.12426425375139658, 0.072745167637057531, 0.15237379092687864,
    0.0023957008493847641, -0.073586281040650584, -0.12309745198160228,
    0.12426425375139623, -0.16833215763364537, -0.013187732288056048,
    0.0023957008493875743, 0.14339866107761054, -0.0021788627603761819,
    0.12426425375139771, -0.39495401889197806, -0.077606289654127678,
    -0.072047215225645597, -0.17454060602190213, 0.2234611880759339,
    0.0041423976538383913, 0.26468602778368777, -0.3032370688472763,
    -0.072047215225388414, -0.10625276262723954, -0.26288719283996242,
    0.0041423976536380377, 0.13026799109350937, 0.38084335850609119,
    -0.072047215223682667, 0.28079336864707433, 0.039426004767818566,
    0.0041423976511559537
};

/* the singular values at most this fraction of v_max belong to the
 * vanishing group (the next one, 2e-2 of v_max, is far above) */
static const double GROUP_CUT = 1e-5;

/* locate from the path point, towards the state (past = 0) or after
 * stepping past it and turning back (past = 1), check the located point and
 * leave its coordinates in out (57) */
static void locate_collapse(double tol, int past, double *out)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL);
    CHECK_RC(kin_set_coords(a, COLLAPSE_XYZ), KIN_OK);
    CHECK_RC(kin_path_set_direction(a, COLLAPSE_T, 46), KIN_OK);
    if (past) {
        /* 0.2 past the state (it lies at l ~ 0.1 from the start), then back */
        for (int k = 0; k < 6; ++k) CHECK_RC(kin_step(a, 0.05, NULL), KIN_OK);
        double t[46];
        CHECK_RC(kin_get_tangent(a, t, 46), KIN_OK);
        for (int i = 0; i < 46; ++i) t[i] = -t[i];
        CHECK_RC(kin_path_set_direction(a, t, 46), KIN_OK);
    }
    kin_locate_options o = {.size = sizeof o};
    kin_locate_options_default(&o);
    o.method = KIN_LOCATE_FAST;
    o.vr_tol = tol;
    o.delta = 0.05;
    o.max_steps = 20;
    kin_locate_info info = {.size = sizeof info};
    int rc = kin_locate_next(a, &o, &info);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    double sv[45];
    CHECK_RC(kin_get_singular_values(a, sv, 45), KIN_OK);
    int group = 0;
    double top = 0.0;
    for (int i = 0; i < 45; ++i)
        if (sv[i] <= GROUP_CUT * sv[0]) {
            ++group;
            top = fmax(top, sv[i] / sv[0]);
        }
    printf("collapsed hub (tol %.0e, %s): rc %d, %d factorizations, v_r/v_max %.2e, m=%d s=%d, "
           "%d values below %.0e, the largest %.2e, strain %.2e\n",
           tol, past ? "from beyond" : "from before", rc, info.factorizations, info.v_r_rel, info.m_internal, info.s,
           group, GROUP_CUT, top, kin_max_strain(a));
    CHECK_RC(rc, KIN_OK);
    CHECK(info.located && info.v_r_rel <= tol);
    /* every one of the five (the tangent's exact zero is not in sv: 45
     * values of 46 coordinates), and the counts of the full group */
    CHECK(group == 5);
    CHECK(top <= tol);
    CHECK(info.m_internal == 6 && info.s == 5);
    CHECK(kin_max_strain(a) <= 1e3 * DBL_EPSILON);
    kin_get_coords(a, out);
    kin_assembly_free(a);
}

int main(void)
{
    double x[3][57];
    locate_collapse(1e-10, 0, x[0]);
    locate_collapse(1e-12, 0, x[1]);
    locate_collapse(1e-10, 1, x[2]);
    /* one point, whichever way it was approached: the pair's slope (0.2
     * v_max per unit length) places a point at 1e-10 to 5e-10 */
    double d = 0.0;
    for (int k = 1; k < 3; ++k)
        for (int i = 0; i < 57; ++i) d = fmax(d, fabs(x[k][i] - x[0][i]));
    printf("collapsed hub: the three located points agree to %.2e\n", d);
    CHECK(d <= 1e-8);
    TEST_REPORT("test_locate_corank");
}
