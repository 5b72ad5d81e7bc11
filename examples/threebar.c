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
    kin_analysis an;
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
    kin_step_info info;
    while (kin_path_length(a) < lap - 1e-9) {
        double remaining = lap - kin_path_length(a);
        rc = kin_step(a, remaining < 0.1 ? remaining : 0.1, &info);
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
    kin_get_coords(a, xyz);
    double closure = 0.0;
    for (int i = 0; i < 4; ++i) closure = fmax(closure, fabs(xyz[i] - x0[i]));
    printf("  %d steps, %d factorizations, path length %.12f (2*sqrt(2)*pi = %.12f)\n", nsteps,
           nfact, kin_path_length(a), lap);
    printf("  max bar strain %.3e, smallest v_r %.3e, closure error %.3e\n", worst, vrmin, closure);
    kin_assembly_free(a);
    return 0;
}
