/* Bars between fixed joints (docs/generality.md, "Bars between fixed
 * joints"): the paper's three-bar linkage at its bifurcation R^C with a
 * fourth bar S1-S2 between its two supports. That bar is a zero column of H
 * at every configuration and a self-stress of its own (s = 2, s_trivial =
 * 1); everything kinematic must be the three-bar linkage's: the
 * second-order matrices, the branches, the paths followed from them to
 * their next events, the signed test function along a path, and a point
 * with two freedoms and only that self-stress is a multi-DOF mechanism, not
 * a bifurcation. A bar whose column of H is zero only because its free
 * coordinates are perpendicular to it is not trivial: it still constrains
 * at second order. */
#include <string.h>

#include "check.h"
#include "libkin.h"

enum { NJ = 4, NF = 4 };
/* joints J1, J2 (free), S1 = (0,0), S2 = (1,0) (fixed) */
static const unsigned char FIXED[2 * NJ] = {0, 0, 0, 0, 1, 1, 1, 1};
static const int BARS[2 * 4] = {2, 0, 0, 1, 1, 3, 2, 3}; /* the last: S1-S2 */
static const double LEN[4] = {1.0, 1.0, 1.0, 1.0};

/* the linkage at J1 = (cos th, sin th) on the branch J2 = S2 + (J1 - S1)
 * (the parallelogram, through R^C at th = 0), with or without S1-S2 */
static kin_assembly *linkage(double th, int with_fixed_bar)
{
    double xyz[2 * NJ] = {cos(th), sin(th), 1.0 + cos(th), sin(th), 0.0, 0.0, 1.0, 0.0};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, NJ, xyz, FIXED, with_fixed_bar ? 4 : 3, BARS, LEN, &a, NULL, 0), KIN_OK);
    return a;
}

/* the quadratic form of the one normalised Q in free coordinates,
 * U Q U^T (independent of the SVD's mechanism basis), up to sign: made
 * positive at the J1y-J1y entry's sign */
static void coordinate_form(kin_assembly *a, double *F)
{
    double U[NF * 2], Q[4 * 2];
    int s = -1;
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, NF, 2), KIN_OK);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 8, &s), KIN_OK);
    CHECK(s == 1);
    for (int i = 0; i < NF; ++i)
        for (int j = 0; j < NF; ++j) {
            double v = 0.0;
            for (int p = 0; p < 2; ++p)
                for (int q = 0; q < 2; ++q) v += U[i + p * NF] * Q[p + q * 2] * U[j + q * NF];
            F[i + j * NF] = v;
        }
    double sg = F[1 + 1 * NF] < 0.0 ? -1.0 : 1.0;
    for (int i = 0; i < NF * NF; ++i) F[i] *= sg;
}

/* the branch directions U beta (unit, largest entry positive) of the root scan */
static int directions(kin_assembly *a, double *dirs)
{
    double U[NF * 2], Q[8], betas[2 * 8];
    int s = 0, n = 0;
    kin_solve_info info = {.size = sizeof info};
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, NF, 2), KIN_OK);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 8, &s), KIN_OK);
    CHECK_RC(kin_quadrics_scan(2, s, Q, 64, 1, betas, 8, &n, &info), KIN_OK);
    for (int k = 0; k < n; ++k) {
        double *d = dirs + k * NF, big = 0.0;
        for (int i = 0; i < NF; ++i) d[i] = U[i] * betas[2 * k] + U[i + NF] * betas[2 * k + 1];
        for (int i = 0; i < NF; ++i)
            if (fabs(d[i]) > fabs(big)) big = d[i];
        for (int i = 0; i < NF; ++i) d[i] /= big < 0.0 ? -1.0 : 1.0;
    }
    return n;
}

/* the same unit vector to rounding, up to sign */
static int same_direction(const double *x, const double *y)
{
    double c = 0.0, nx = 0.0, ny = 0.0;
    for (int i = 0; i < NF; ++i) c += x[i] * y[i], nx += x[i] * x[i], ny += y[i] * y[i];
    return fabs(fabs(c) / sqrt(nx * ny) - 1.0) <= 64 * DBL_EPSILON;
}

static void check_bifurcation(void)
{
    kin_assembly *p = linkage(0.0, 0), *a = linkage(0.0, 1);
    kin_analysis ap = {.size = sizeof ap}, aa = {.size = sizeof aa};
    CHECK_RC(kin_analyse(p, &ap), KIN_OK);
    CHECK_RC(kin_analyse(a, &aa), KIN_OK);
    printf("R^C: three-bar rank %d, m %d, s %d (trivial %d); with S1-S2 rank %d, m %d, s %d (trivial %d)\n", ap.rank,
           ap.m_internal, ap.s, ap.s_trivial, aa.rank, aa.m_internal, aa.s, aa.s_trivial);
    CHECK(ap.rank == 2 && ap.m_internal == 2 && ap.s == 1 && ap.s_trivial == 0);
    CHECK(aa.rank == 2 && aa.m_internal == 2 && aa.s == 2 && aa.s_trivial == 1);
    {
        /* the sparse mode's analysis counts them alike */
        kin_assembly *c = NULL;
        kin_options o = {.size = sizeof o};
        kin_analysis as = {.size = sizeof as};
        CHECK_RC(kin_assembly_clone(a, &c), KIN_OK);
        CHECK_RC(kin_get_options(c, &o), KIN_OK);
        o.factorization = KIN_STEP_SPARSE;
        CHECK_RC(kin_set_options(c, &o), KIN_OK);
        CHECK_RC(kin_analyse(c, &as), KIN_OK);
        CHECK(as.rank == 2 && as.m_internal == 2 && as.s == 2 && as.s_trivial == 1);
        kin_assembly_free(c);
    }

    /* one equation, not one per self-stress, with or without normalisation */
    double Q[8];
    int s = -1;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 0, Q, 8, &s), KIN_OK);
    CHECK(s == 1);
    double Fp[NF * NF], Fa[NF * NF], diff = 0.0;
    coordinate_form(p, Fp);
    coordinate_form(a, Fa);
    for (int i = 0; i < NF * NF; ++i) diff = fmax(diff, fabs(Fp[i] - Fa[i]));
    printf("  |U Q U^T| difference %.3g\n", diff);
    CHECK(diff <= 64 * DBL_EPSILON);

    double dp[8 * NF], da[8 * NF];
    int np = directions(p, dp), na = directions(a, da);
    CHECK(np == 2 && na == np);
    for (int k = 0; k < na; ++k) {
        int found = 0;
        for (int j = 0; j < np; ++j) found |= same_direction(da + k * NF, dp + j * NF);
        CHECK(found);
    }

    /* every directed branch exists, and is followed to the three-bar's event */
    kin_branch_path paths[16] = {{.size = sizeof(kin_branch_path)}};
    double U[NF * 2], betas[2 * 8], Qn[8];
    int n = 0, nd_a = 0, nd_p = 0;
    kin_solve_info si = {.size = sizeof si};
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, NF, 2), KIN_OK);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Qn, 8, &s), KIN_OK);
    CHECK_RC(kin_quadrics_scan(2, s, Qn, 64, 1, betas, 8, &n, &si), KIN_OK);
    CHECK_RC(kin_branch_paths(a, betas, n, 0.5, paths, NULL, &nd_a), KIN_OK);
    for (int k = 0; k < 2 * n; ++k) CHECK(paths[k].exists && paths[k].tangent_ok && paths[k].length >= 0.5 - 1e-12);
    CHECK_RC(kin_get_mechanisms(p, KIN_MECH_INTERNAL, U, NF, 2), KIN_OK);
    CHECK_RC(kin_second_order(p, KIN_Q_EXACT, 1, Qn, 8, &s), KIN_OK);
    CHECK_RC(kin_quadrics_scan(2, s, Qn, 64, 1, betas, 8, &n, &si), KIN_OK);
    kin_branch_path pp[16] = {{.size = sizeof(kin_branch_path)}};
    CHECK_RC(kin_branch_paths(p, betas, n, 0.5, pp, NULL, &nd_p), KIN_OK);
    CHECK(nd_a == nd_p && nd_a == 4);

    for (int k = 0; k < na; ++k)
        for (int sg = -1; sg <= 1; sg += 2) {
            double dir[NF], xa[2 * NJ], xp[2 * NJ];
            for (int i = 0; i < NF; ++i) dir[i] = sg * da[k * NF + i];
            kin_assembly *ca = NULL, *cp = NULL;
            CHECK_RC(kin_assembly_clone(a, &ca), KIN_OK);
            CHECK_RC(kin_assembly_clone(p, &cp), KIN_OK);
            kin_follow_info fa = {.size = sizeof fa}, fp = {.size = sizeof fp};
            CHECK_RC(kin_follow_event(ca, dir, NULL, &fa), KIN_OK);
            CHECK_RC(kin_follow_event(cp, dir, NULL, &fp), KIN_OK);
            kin_get_coords(ca, xa);
            kin_get_coords(cp, xp);
            double dx = 0.0;
            for (int i = 0; i < 2 * NJ; ++i) dx = fmax(dx, fabs(xa[i] - xp[i]));
            printf("  branch %d%c: event %d after l = %.6f (three-bar: event %d, l = %.6f), ends %.2g apart\n", k,
                   sg > 0 ? '+' : '-', fa.event, fa.length, fp.event, fp.length, dx);
            CHECK(fa.event == fp.event && fa.event != KIN_FOLLOW_FAILED);
            CHECK(fa.length > 0.1);
            CHECK(fabs(fa.length - fp.length) <= 1e-6 && dx <= 1e-6);
            kin_assembly_free(ca);
            kin_assembly_free(cp);
        }
    kin_assembly_free(p);
    kin_assembly_free(a);
}

/* tau along the parallelogram branch, oriented by dJ1/dth: the three-bar
 * linkage's, sign included (an unsigned v_r would miss the crossing's sign
 * change) */
static void check_test_function(void)
{
    double tau_p[2], tau_a[2];
    for (int side = 0; side < 2; ++side) {
        double th = side ? 0.05 : -0.05;
        double dir[NF] = {-sin(th), cos(th), -sin(th), cos(th)};
        kin_assembly *p = linkage(th, 0), *a = linkage(th, 1);
        CHECK_RC(kin_path_set_direction(p, dir, NF), KIN_OK);
        CHECK_RC(kin_path_set_direction(a, dir, NF), KIN_OK);
        CHECK_RC(kin_test_function(p, &tau_p[side]), KIN_OK);
        CHECK_RC(kin_test_function(a, &tau_a[side]), KIN_OK);
        printf("tau at th = %+.2f: three-bar %.6g, with S1-S2 %.6g\n", th, tau_p[side], tau_a[side]);
        CHECK_CLOSE(tau_a[side], tau_p[side], 64 * DBL_EPSILON);
        kin_assembly_free(p);
        kin_assembly_free(a);
    }
    CHECK(tau_p[0] * tau_p[1] < 0.0);
}

/* S1 - J1 - J2 without the bar J2-S2, with S1-S2: two freedoms and only the
 * fixed bar's self-stress, a multi-DOF mechanism; the second order refuses
 * it (nothing to solve), kin_step asks for a direction as it does for any
 * multi-DOF mechanism */
static void check_multidof(void)
{
    const double xyz[2 * NJ] = {0.6, 0.8, 1.2, 1.6, 0.0, 0.0, 1.0, 0.0};
    const int chain[6] = {2, 0, 0, 1, 2, 3}; /* S1-J1, J1-J2, S1-S2 */
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, NJ, xyz, FIXED, 3, chain, NULL, &a, NULL, 0), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.m_internal == 2 && an.s == 1 && an.s_trivial == 1);
    double Q[8], t[NF];
    int s = -1;
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 8, &s), KIN_EINVAL);
    CHECK(s == 0);
    CHECK_RC(kin_get_tangent(a, t, NF), KIN_EMULTIDOF);
    CHECK_RC(kin_step(a, 0.0, NULL), KIN_EMULTIDOF);
    kin_assembly_free(a);
}

/* A joint P = (0,0) free in x only, tied to F = (0,1) (fixed) by a bar
 * along y: a zero column of H here, but P moves, and the bar stretches at
 * second order (|dP|^2 / 2L): not trivial. A second joint R = (3,0), free in
 * x, tied to nothing, gives m = 2. Its Q is e_P e_P^T / L (normalised: the
 * P-P entry 1): it forbids P's motion and leaves R's. */
static void check_zero_column_with_free_coordinates(void)
{
    const double xyz[6] = {0.0, 0.0, 0.0, 1.0, 3.0, 0.0};
    const unsigned char fixed[6] = {0, 1, 1, 1, 0, 1};
    const int bars[2] = {0, 1};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 3, xyz, fixed, 1, bars, NULL, &a, NULL, 0), KIN_OK);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK(an.rank == 0 && an.m_internal == 2 && an.s == 1 && an.s_trivial == 0);
    double U[4], Q[4], F00 = 0.0, F11 = 0.0;
    int s = -1;
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, 2, 2), KIN_OK);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s), KIN_OK);
    CHECK(s == 1);
    for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q) {
            F00 += U[0 + p * 2] * Q[p + q * 2] * U[0 + q * 2];
            F11 += U[1 + p * 2] * Q[p + q * 2] * U[1 + q * 2];
        }
    CHECK_CLOSE(fabs(F00), 1.0, 16 * DBL_EPSILON);
    CHECK(fabs(F11) <= 16 * DBL_EPSILON);
    kin_assembly_free(a);
}

int main(void)
{
    check_bifurcation();
    check_test_function();
    check_multidof();
    check_zero_column_with_free_coordinates();
    return check_failures_ ? 1 : 0;
}
