/* A full lap of the three-bar linkage's parallelogram mode P1: it passes the
 * bifurcations R^C and R^A without switching path, keeps every bar length to
 * 1e-12 relative, and closes on its start within 1e-9. */
#include <string.h>

#include "check.h"
#include "libkin.h"

#define PI 3.14159265358979323846

static double angle_of(const double *xyz) { return atan2(xyz[1], xyz[0]); }

static void lap(double delta, int backwards)
{
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_threebar(KIN_THREEBAR_RC, &a), KIN_OK);
    double xyz[8], x0[8];
    kin_get_coords(a, xyz);
    xyz[0] = cos(PI / 3); xyz[1] = sin(PI / 3); xyz[2] = xyz[0] + 1.0; xyz[3] = xyz[1];
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK);
    kin_get_coords(a, x0);
    double sgn = backwards ? -1.0 : 1.0, turned = 0.0, prev = angle_of(x0), worst = 0.0;
    kin_step_info info = {.size = sizeof info};
    int steps = 0, ok = 1;
    /* follow until the joint angle has turned by just under 2*pi */
    while (fabs(turned) < 2 * PI - 2 * delta && steps < 10000) {
        int rc = kin_step(a, sgn * delta, &info);
        CHECK_RC(rc, KIN_OK);
        if (rc) { ok = 0; break; }
        ++steps;
        kin_get_coords(a, xyz);
        /* the path stays the parallelogram: J2 = J1 + (1, 0) */
        CHECK_CLOSE(xyz[2] - xyz[0], 1.0, 1e-11);
        CHECK_CLOSE(xyz[3] - xyz[1], 0.0, 1e-11);
        double th = angle_of(xyz), dth = th - prev;
        if (dth > PI) dth -= 2 * PI;
        if (dth < -PI) dth += 2 * PI;
        turned += dth;
        prev = th;
        if (info.residual > worst) worst = info.residual;
        CHECK(kin_max_strain(a) <= 1e-12);
    }
    if (ok) {
        /* close the lap: aim the last steps at the start along the tangent */
        for (int k = 0; k < 3; ++k) {
            double t[4], x[4], s[4];
            kin_get_tangent(a, t, 4);
            kin_get_coords(a, xyz);
            for (int i = 0; i < 4; ++i) { x[i] = xyz[i]; s[i] = x0[i]; }
            double d = 0;
            for (int i = 0; i < 4; ++i) d += t[i] * (s[i] - x[i]);
            if (fabs(d) < 1e-14) break;
            CHECK_RC(kin_step(a, d, &info), KIN_OK);
        }
        kin_get_coords(a, xyz);
        double closure = 0;
        for (int i = 0; i < 8; ++i) closure = fmax(closure, fabs(xyz[i] - x0[i]));
        printf("lap delta=%.3f %s: %d steps, path length %.12f (exact %.12f), max residual %.2e, closure %.2e\n",
               delta, backwards ? "backwards" : "forwards", steps, kin_path_length(a),
               sgn * 2 * sqrt(2.0) * PI, worst, closure);
        CHECK(closure <= 1e-9);
        CHECK(kin_max_strain(a) <= 1e-12);
        /* the chord sum approximates the arc length 2*sqrt(2)*pi to O(delta^2) */
        CHECK_CLOSE(fabs(kin_path_length(a)), 2 * sqrt(2.0) * PI, 2e-3);
    }
    kin_assembly_free(a);
}

int main(void)
{
    lap(0.1, 0);
    lap(0.1, 1);
    lap(0.0371, 0); /* an awkward step size: no step lands on R^A or R^C */
    TEST_REPORT("test_lap");
}
