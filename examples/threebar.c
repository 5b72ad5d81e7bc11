/* The paper's three-bar linkage (Figure 1, Section 5): its analysis at the
 * bifurcation R^C (eq. 27-28) and one lap of the parallelogram mode P1 from
 * a regular point, printing the path length, v_r and the bar strain. */
#include <math.h>
#include <stdio.h>

#include "libkin.h"

#define PI 3.14159265358979323846

static int report(int rc, const kin_assembly *a, const char *what)
{
    if (rc) fprintf(stderr, "%s: %s\n", what, a ? kin_last_error(a) : kin_strerror(rc));
    return rc;
}

int main(void)
{
    kin_assembly *a = NULL;
    kin_analysis an = {.size = sizeof an};
    double xyz0[8];
    int rc = kin_model_threebar(KIN_THREEBAR_RC, &a);
    if (report(rc, NULL, "create")) return 1;
    if (report(kin_analyse(a, &an), a, "analyse")) return 1;
    double sv[3], Um[8], Ws[3];
    kin_get_singular_values(a, sv, 3);
    kin_get_mechanisms(a, KIN_MECH_INTERNAL, Um, 4, 2);
    kin_get_self_stresses(a, Ws, 3, 1);
    printf("libkin %s: three-bar linkage at R^C (J1 = (1,0), J2 = (2,0))\n", kin_version_string());
    printf("  H is %d x %d; singular values %.4f %.4f (paper eq. 27: 1.7321, 1)\n", kin_nfree(a),
           kin_nbars(a), sv[0], sv[1]);
    printf("  r = %d, m = %d (internal %d, rigid %d), s = %d\n", an.rank, an.m, an.m_internal,
           an.m_rigid, an.s);
    printf("  U_m (rows J1x J1y J2x J2y):\n");
    for (int i = 0; i < 4; ++i) printf("    % .4f % .4f\n", Um[i] + 0.0, Um[i + 4] + 0.0);
    printf("  W_s: % .4f % .4f % .4f (eq. 28: 0.5774 0.5774 -0.5774, up to sign)\n", Ws[0], Ws[1],
           Ws[2]);

    /* the paths out of R^C (eq. 29-33), each followed for l = 1 */
    double Q[4], betas[4];
    int s, nsol, nd;
    kin_solve_info si = {.size = sizeof si};
    kin_branch_path paths[4] = {{.size = sizeof(kin_branch_path)}};
    if (report(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4, &s), a, "second order") ||
        report(kin_quadrics_scan(2, s, Q, 64, 1, betas, 2, &nsol, &si), NULL, "scan") ||
        report(kin_branch_paths(a, betas, nsol, 1.0, paths, NULL, &nd), a, "paths"))
        return 1;
    printf("  second order: %d real solutions (eq. 33), %d distinct directed paths:\n", nsol, nd);
    for (int k = 0; k < nsol; ++k) {
        double d1 = Um[1] * betas[2 * k] + Um[5] * betas[2 * k + 1], d2 = Um[3] * betas[2 * k] + Um[7] * betas[2 * k + 1];
        printf("    beta %d: (dJ1y, dJ2y) = (% .4f, % .4f)  %s\n", k, d1 + 0.0, d2 + 0.0,
               fabs(d1) < 1e-9 ? "J1 held at S2 (Figure 1(d))" : "parallelogram P1 (Figure 1(b))");
    }

    /* Section 5: follow P1 from R^C to R^A and locate it */
    const double p1[4] = {0.0, 1.0, 0.0, 1.0};
    kin_locate_options lo = {.size = sizeof lo};
    kin_locate_info li = {.size = sizeof li};
    kin_locate_options_default(&lo);
    lo.delta = 0.1;
    if (report(kin_path_set_direction(a, p1, 4), a, "direction") || report(kin_step(a, 1e-3, NULL), a, "step") ||
        report(kin_locate_next(a, &lo, &li), a, "locate"))
        return 1;
    kin_get_coords(a, xyz0);
    printf("  along P1 to the next bifurcation: %d steps, then located with %d factorizations:\n", li.steps,
           li.factorizations);
    printf("    J1 = (% .6f, % .6f), J2 = (% .6f, % .6f): R^A, vanishing v_r / v_max = %.1e, m = %d, s = %d\n",
           xyz0[0] + 0.0, xyz0[1] + 0.0, xyz0[2] + 0.0, xyz0[3] + 0.0, li.v_r_rel < 1e-14 ? 0.0 : li.v_r_rel,
           li.m_internal, li.s);
    kin_assembly_free(a);

    /* a lap of the parallelogram mode from J1 at 60 degrees */
    if (report(kin_model_threebar(KIN_THREEBAR_RC, &a), NULL, "create")) return 1;
    double xyz[8];
    kin_get_coords(a, xyz);
    xyz[0] = cos(PI / 3); xyz[1] = sin(PI / 3); xyz[2] = xyz[0] + 1.0; xyz[3] = xyz[1];
    if (report(kin_set_coords(a, xyz), a, "set_coords")) return 1;
    double x0[8], lap = 2.0 * sqrt(2.0) * PI; /* J1 and J2 both travel 2*pi */
    kin_get_coords(a, x0);
    int nsteps = 0, nfact = 0;
    double worst = 0.0, vrmin = 1e300;
    printf("\nlap of the parallelogram mode, starting at J1 = (0.5, 0.866):\n");
    printf("  %5s %10s %10s %10s %12s\n", "step", "l", "theta", "v_r", "strain");
    kin_step_info info = {.size = sizeof info};
    while (kin_path_length(a) < lap - 0.15) {
        rc = kin_step(a, 0.1, &info);
        if (report(rc, a, "step")) return 1;
        ++nsteps;
        nfact += info.factorizations;
        double s = kin_max_strain(a);
        if (s > worst) worst = s;
        if (info.v_r < vrmin) vrmin = info.v_r;
        kin_get_coords(a, xyz);
        if (nsteps % 10 == 0)
            printf("  %5d %10.5f %10.5f %10.3e %12.3e\n", nsteps, info.l,
                   atan2(xyz[1], xyz[0]) * 180 / PI, info.v_r, s);
    }
    /* land on the start: aim along the tangent */
    for (int k = 0; k < 3; ++k) {
        double t[4], d = 0.0;
        kin_get_tangent(a, t, 4);
        kin_get_coords(a, xyz);
        for (int i = 0; i < 4; ++i) d += t[i] * (x0[i] - xyz[i]);
        if (fabs(d) < 1e-15 || kin_step(a, d, &info)) break;
        ++nsteps;
        nfact += info.factorizations;
    }
    kin_get_coords(a, xyz);
    double closure = 0.0;
    for (int i = 0; i < 4; ++i) closure = fmax(closure, fabs(xyz[i] - x0[i]));
    printf("  %d steps, %d factorizations, path length %.6f (2*sqrt(2)*pi = %.6f)\n", nsteps,
           nfact, kin_path_length(a), lap);
    printf("  max bar strain %.1e (tolerance 1e-12), smallest v_r %.3e, closure error %s 1e-12\n", worst,
           vrmin, closure < 1e-12 ? "below" : "ABOVE");
    kin_assembly_free(a);
    return 0;
}
