/* Hinges, devices and touching in a plane (kin_contact.h, docs/contact.md
 * "Hinges"): two panels on one fold line are in contact where the hinge
 * closes, and a hinge that passes through flat-folded is a penetration the
 * contact event stops at; bars marked as devices are no parts; a bar that
 * crosses a panel or a bar in their plane is in contact.
 *
 * The hinge: panels (0, 1, 2) and (0, 1, 3) on the edge 0-1 along x; joints
 * 0, 1, 2 fixed, joint 3 = (0.5, cos t, sin t) on a unit circle about the
 * edge (bars 0-3, 1-3), so the angle between the panels is delta = |t|
 * and the fold angle psi = sign(sin t) (pi - |t|) for t in (-pi, pi). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"

static const double PI = 3.14159265358979323846;

static kin_assembly *hinge_at(double t)
{
    double x[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, cos(t), sin(t)};
    unsigned char fixed[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0};
    int b[] = {0, 3, 1, 3}, off[] = {0, 3, 6}, pj[] = {0, 1, 2, 0, 1, 3};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(3, 4, x, fixed, 2, b, NULL, &a, NULL, 0), KIN_OK);
    if (a) CHECK_RC(kin_set_panels(a, 2, off, pj), KIN_OK);
    return a;
}

/* joint 3's angle t on its circle */
static double angle_of(const kin_assembly *a)
{
    double y[12];
    kin_get_coords(a, y);
    return atan2(y[11], y[10]);
}

/* the hinge found, its fold angle, and the clearance it gives */
static void measure_cases(void)
{
    kin_assembly *a = hinge_at(PI / 2);
    if (!a) return;
    CHECK(kin_nhinges(a) == 1 && kin_nhinges(NULL) == -1);
    int j[4], p[2];
    CHECK_RC(kin_get_hinges(a, j, p), KIN_OK);
    CHECK(j[0] == 0 && j[1] == 1 && j[2] == 2 && j[3] == 3 && p[0] == 0 && p[1] == 1);
    CHECK(kin_get_hinge_contact(a) == 1 && kin_get_hinge_contact(NULL) == -1);
    double t[] = {0.3, 1.0, PI / 2, 2.5, -0.3, -2.5}, x[12], psi;
    kin_get_coords(a, x);
    for (int i = 0; i < 6; ++i) {
        x[10] = cos(t[i]), x[11] = sin(t[i]);
        CHECK_RC(kin_hinge_angles(a, x, &psi), KIN_OK);
        CHECK_CLOSE(psi, (t[i] > 0 ? 1 : -1) * (PI - fabs(t[i])), 8 * DBL_EPSILON * PI);
        /* the clearance: the hinge's gap 2 sin(delta / 2), the only pair */
        double c;
        int parts[4];
        CHECK_RC(kin_clearance(a, x, INFINITY, &c, parts, NULL), KIN_OK);
        CHECK_CLOSE(c, 2 * sin(0.5 * fabs(t[i])), 8 * DBL_EPSILON);
        CHECK(parts[0] == KIN_PART_PANEL && parts[1] == 0 && parts[2] == KIN_PART_PANEL && parts[3] == 1);
    }
    /* folded flat: in contact; with hinge contact off, no pair at all */
    x[10] = 1, x[11] = 0;
    double c;
    CHECK_RC(kin_clearance(a, x, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK(c <= 0.0);
    CHECK_RC(kin_set_hinge_contact(a, 0), KIN_OK);
    CHECK_RC(kin_clearance(a, x, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK(c == INFINITY);
    /* bad input */
    CHECK_RC(kin_hinge_angles(a, x, NULL), KIN_ENULL);
    x[9] = NAN;
    CHECK_RC(kin_hinge_angles(a, x, &psi), KIN_EGEOM);
    int sides[1];
    CHECK_RC(kin_hinge_sides(a, sides), KIN_ESTATE);
    CHECK_RC(kin_set_hinge_contact(NULL, 1), KIN_ENULL);
    kin_assembly_free(a);
}

static int follow(kin_assembly *a, double sgn, kin_follow_info *info)
{
    double y[12];
    kin_get_coords(a, y);
    /* joint 3 on its circle, t decreasing for sgn = 1 */
    double t = atan2(y[11], y[10]), dir[3] = {0, sgn * sin(t), -sgn * cos(t)};
    if (fabs(t) < 1e-6) dir[1] = 0, dir[2] = -sgn;
    memset(info, 0, sizeof *info);
    info->size = sizeof *info;
    return kin_follow_event(a, dir, NULL, info);
}

/* the contact event: a hinge that closes, one that passes through */
static void event_cases(void)
{
    /* from 120 degrees open to closed: located where t = 0 */
    kin_assembly *a = hinge_at(2 * PI / 3), *thick = NULL, *off = NULL;
    if (!a) return;
    CHECK_RC(kin_assembly_clone(a, &thick), KIN_OK);
    CHECK_RC(kin_assembly_clone(a, &off), KIN_OK);
    CHECK_RC(kin_set_contact_events(a, 1, 1e-9), KIN_OK);
    kin_follow_info info;
    CHECK_RC(follow(a, 1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT);
    double c, br, rms = 1.0; /* both bars of length 1 */
    int parts[4], side;
    CHECK_RC(kin_last_contact(a, &c, parts, NULL, &br), KIN_OK);
    CHECK(parts[0] == KIN_PART_PANEL && parts[1] == 0 && parts[2] == KIN_PART_PANEL && parts[3] == 1);
    CHECK(br <= 1e-9 * rms && c <= 64 * DBL_EPSILON * rms && c >= -2 * br);
    CHECK(fabs(angle_of(a)) <= 2e-9);
    CHECK(info.length <= 2 * PI / 3 && info.length >= 2 * PI / 3 * (1 - 2e-3));
    CHECK_RC(kin_hinge_sides(a, &side), KIN_OK);
    CHECK(side == 1); /* psi > 0 on the way: sin t > 0 */
    /* on from the closed hinge, the same way: through flat-folded at once */
    CHECK_RC(follow(a, 1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT);
    CHECK_RC(kin_last_contact(a, &c, parts, NULL, &br), KIN_OK);
    CHECK(parts[0] == KIN_PART_PANEL && parts[2] == KIN_PART_PANEL);
    CHECK(info.length <= 1e-6 && fabs(angle_of(a)) <= 1e-6);
    /* a clone keeps the sides: the same */
    kin_assembly *cl = NULL;
    CHECK_RC(kin_assembly_clone(a, &cl), KIN_OK);
    CHECK_RC(follow(cl, 1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT && info.length <= 1e-6);
    /* back the way it came: it opens on its own side, and no contact on
     * the whole turn (through flat open, where the fold side changes, is no
     * contact) until it is back where it started: a closed loop */
    CHECK_RC(follow(cl, -1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CLOSED_LOOP);
    CHECK(info.length >= 2 * PI * (1 - 2e-3));
    kin_assembly_free(cl);
    /* with thickness 0.1 the panels touch where 2 sin(t / 2) = 0.1 */
    CHECK_RC(kin_set_thickness(thick, 0.1, NULL, NULL), KIN_OK);
    CHECK_RC(kin_set_contact_events(thick, 1, 1e-9), KIN_OK);
    CHECK_RC(follow(thick, 1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT);
    CHECK_CLOSE(angle_of(thick), 2 * asin(0.05), 4e-9);
    /* hinge contact off: the same follow passes through (today's libkin) */
    CHECK_RC(kin_set_hinge_contact(off, 0), KIN_OK);
    CHECK_RC(kin_set_contact_events(off, 1, 1e-9), KIN_OK);
    kin_follow_options o;
    kin_follow_options_default(&o);
    o.max_length = 3.0;
    double dir[3] = {0, sin(2 * PI / 3), -cos(2 * PI / 3)};
    memset(&info, 0, sizeof info);
    info.size = sizeof info;
    CHECK_RC(kin_follow_event(off, dir, &o, &info), KIN_OK);
    CHECK(info.event != KIN_FOLLOW_CONTACT && angle_of(off) < -0.1);
    kin_assembly_free(off);
    kin_assembly_free(thick);
    kin_assembly_free(a);
}

/* a closed hinge at a start without tracked sides: watched from where it
 * opens, on the side it opens to */
static void closed_start_cases(void)
{
    kin_assembly *a = hinge_at(0.0);
    if (!a) return;
    CHECK_RC(kin_set_contact_events(a, 1, 1e-9), KIN_OK);
    kin_follow_info info;
    CHECK_RC(follow(a, 1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CLOSED_LOOP);
    CHECK(info.length >= 2 * PI * (1 - 2e-3));
    int side = 0;
    CHECK_RC(kin_hinge_sides(a, &side), KIN_OK);
    CHECK(side == 1); /* it came back to t = 0 from t > 0 */
    /* on, the same way: the hinge closes (the loop ended near t = 0, on
     * the side t > 0), located at t = 0 */
    double t_end = angle_of(a);
    CHECK(t_end >= 0.0 && t_end < 0.1);
    CHECK_RC(follow(a, 1, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT && fabs(angle_of(a)) <= 2e-9);
    CHECK(info.length <= t_end * (1 + 2e-3)); /* the arc, to the chords' 2e-3 */
    kin_assembly_free(a);
}

/* devices: left out of contact; set, read back, cloned, saved and loaded */
static void device_cases(void)
{
    /* a bar through the middle of a triangle it shares no joint with */
    double x[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, -1, 0.5, 0.5, 1};
    unsigned char fixed[15];
    memset(fixed, 1, sizeof fixed);
    fixed[0] = 0;
    int b[] = {0, 1, 1, 2, 2, 0, 3, 4}, off[] = {0, 3}, pj[] = {0, 1, 2};
    kin_assembly *a = NULL, *cl = NULL, *ld = NULL;
    CHECK_RC(kin_assembly_create(3, 5, x, fixed, 4, b, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return;
    CHECK_RC(kin_set_panels(a, 1, off, pj), KIN_OK);
    double c;
    int parts[4], n = -1, dev[4];
    CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK(c <= 0.0 && parts[0] == KIN_PART_BAR && parts[1] == 3);
    int bad[] = {4}, one[] = {3, 3};
    CHECK_RC(kin_set_device_bars(a, 1, bad), KIN_ERANGE);
    CHECK_RC(kin_set_device_bars(a, -1, one), KIN_EINVAL);
    CHECK_RC(kin_set_device_bars(a, 1, NULL), KIN_ENULL);
    CHECK_RC(kin_get_device_bars(a, NULL, NULL), KIN_ENULL);
    CHECK_RC(kin_get_device_bars(a, &n, dev), KIN_OK);
    CHECK(n == 0);
    CHECK_RC(kin_set_device_bars(a, 2, one), KIN_OK);
    CHECK_RC(kin_get_device_bars(a, &n, dev), KIN_OK);
    CHECK(n == 1 && dev[0] == 3 && kin_npanels(a) == 1);
    CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK(c > 0.0 && !(parts[0] == KIN_PART_BAR && parts[1] == 3) && !(parts[2] == KIN_PART_BAR && parts[3] == 3));
    CHECK_RC(kin_assembly_clone(a, &cl), KIN_OK);
    CHECK_RC(kin_get_device_bars(cl, &n, dev), KIN_OK);
    CHECK(n == 1 && dev[0] == 3);
    char *text = NULL;
    size_t tlen = 0;
    CHECK_RC(kin_assembly_save_string(a, "dev", &text, &tlen, NULL, 0), KIN_OK);
    if (text) {
        CHECK(strstr(text, "\"device\": true") != NULL);
        CHECK_RC(kin_assembly_load_string(text, strlen(text), &ld, NULL, 0), KIN_OK);
        kin_free_string(text);
    }
    if (ld) {
        CHECK_RC(kin_get_device_bars(ld, &n, dev), KIN_OK);
        CHECK(n == 1 && dev[0] == 3 && kin_npanels(ld) == 1);
    }
    /* the built-in sails' spokes */
    kin_sail_params sp;
    kin_sail_params_default(&sp, 6, 2);
    kin_assembly *s = NULL;
    CHECK_RC(kin_model_sail(&sp, &s, NULL, 0), KIN_OK);
    if (s) {
        int sb[90], ds[45];
        kin_get_bars(s, sb);
        CHECK_RC(kin_get_device_bars(s, &n, ds), KIN_OK);
        CHECK(n == 3);
        for (int q = 0; q < n; ++q) CHECK(sb[2 * ds[q]] == 0); /* on the centre node */
        kin_assembly_free(s);
    }
    kin_assembly_free(ld);
    kin_assembly_free(cl);
    kin_assembly_free(a);
}

/* a bar that crosses a panel or a bar in their plane is in contact (it
 * came out at up to 5e-14: "no contact"); planes in every direction */
static void in_plane_cases(void)
{
    unsigned long long seed = 7;
    int late = 0;
    for (int trial = 0; trial < 300; ++trial) {
        double r[12];
        for (int i = 0; i < 12; ++i) {
            seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
            r[i] = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
        }
        /* an orthonormal pair (u, v) spanning the plane, an offset o */
        double u[3] = {r[0], r[1], r[2]}, v[3] = {r[3], r[4], r[5]}, o[3] = {3 * r[6], 3 * r[7], 3 * r[8]};
        double nu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int k = 0; k < 3; ++k) u[k] /= nu;
        double d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
        for (int k = 0; k < 3; ++k) v[k] -= d * u[k];
        double nv = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        for (int k = 0; k < 3; ++k) v[k] /= nv;
        /* a triangle and a segment through its centroid in its plane */
        double P2[5][2] = {{0, 0}, {1 + r[9], 0.1}, {0.2, 1 - r[10]}, {0, 0}, {0, 0}};
        double cx = (P2[0][0] + P2[1][0] + P2[2][0]) / 3, cy = (P2[0][1] + P2[1][1] + P2[2][1]) / 3;
        double w = 3.0 * r[11];
        P2[3][0] = cx - 2 * cos(w), P2[3][1] = cy - 2 * sin(w), P2[4][0] = cx + 2 * cos(w), P2[4][1] = cy + 2 * sin(w);
        double x[15];
        unsigned char fixed[15];
        memset(fixed, 1, sizeof fixed);
        fixed[0] = 0;
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 3; ++k) x[3 * j + k] = o[k] + P2[j][0] * u[k] + P2[j][1] * v[k];
        int b[] = {0, 1, 1, 2, 2, 0, 3, 4}, off[] = {0, 3}, pj[] = {0, 1, 2};
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(3, 5, x, fixed, 4, b, NULL, &a, NULL, 0), KIN_OK);
        if (!a) continue;
        CHECK_RC(kin_set_panels(a, 1, off, pj), KIN_OK);
        double c;
        CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, NULL, NULL), KIN_OK);
        late += !(c <= 0.0);
        kin_assembly_free(a);
    }
    CHECK(late == 0);
}

int main(void)
{
    measure_cases();
    event_cases();
    closed_start_cases();
    device_cases();
    in_plane_cases();
    TEST_REPORT("test_hinges");
}
