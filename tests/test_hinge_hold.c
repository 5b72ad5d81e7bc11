/* Held hinges (kin_follow_options.hold_hinges, docs/contact.md "Held
 * hinges"): a hinge that closes is held closed; the follow goes on with it
 * held where the structure still moves, ends HELD_RIGID where it does not,
 * and releases the hold only along a motion that opens it.
 *
 * 1. One hinge (test_hinges.c's): panels (0, 1, 2), (0, 1, 3) on the edge
 *    0-1, joint 3 on a circle about it; one motion, which closes the hinge
 *    transversally: held rigid there; a direction pressing it through is
 *    refused (rigid, nothing moved); the opposite one reopens it, and
 *    round the circle it closes again from the other side.
 * 2. A square sheet folded in half and in half again: a degree-4 vertex of
 *    four right triangles (C, E1, E2), (C, E2, E3), (C, E3, E4), (C, E4,
 *    E1) around C, folds C-E1 and C-E3 on one line, C-E2 and C-E4 on the
 *    other. Folding along the first line closes its two hinges where the
 *    second line's halves meet again (a bifurcation): held, the follow
 *    goes on along the second line (the held motion) with the first two
 *    hinges closed all the way, and ends held rigid where the other two
 *    close (four layers); back along the second line reopens those two,
 *    along the first the first two. The outer bars are devices (at zero
 *    thickness the stacked layers' edges touch: contacts of their own). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"

static const double PI = 3.14159265358979323846;

static kin_follow_options hold_options(void)
{
    kin_follow_options o;
    kin_follow_options_default(&o);
    o.hold_hinges = 1;
    return o;
}

static void one_hinge(void)
{
    double x[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, 0, 1};
    unsigned char fixed[] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 0, 0, 0};
    int b[] = {0, 3, 1, 3}, off[] = {0, 3, 6}, pj[] = {0, 1, 2, 0, 1, 3};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(3, 4, x, fixed, 2, b, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return;
    CHECK_RC(kin_set_panels(a, 2, off, pj), KIN_OK);
    CHECK_RC(kin_set_contact_events(a, 1, 1e-9), KIN_OK);
    kin_follow_options o = hold_options();
    kin_follow_info fi = {.size = sizeof fi};
    /* joint 3 from (0.5, 0, 1) towards (0.5, 1, 0): the hinge closes */
    double close_dir[] = {0, 1, -1}, open_dir[] = {0, -1, 1}, psi, y[12];
    CHECK_RC(kin_follow_event(a, close_dir, &o, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_HELD_RIGID && fi.hinge == 0 && fi.held == 1 && fi.held_m == 0);
    CHECK_RC(kin_hinge_angles(a, NULL, &psi), KIN_OK);
    CHECK(fabs(psi) > PI - 1e-6);
    /* pressing on: refused as rigid, nothing moved */
    kin_get_coords(a, x);
    CHECK_RC(kin_follow_event(a, close_dir, &o, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_HELD_RIGID && fi.held == 1 && fi.held_m == 0);
    kin_get_coords(a, y);
    CHECK(memcmp(x, y, sizeof x) == 0);
    /* back: the motion opens it, the hold is released, and the follow goes
     * round the circle (through flat open) back to the start, a closed loop
     * just before the hinge closes again from the other side: held rigid
     * there, on that side (no pass-through: each closure from its own side) */
    double psi0 = psi;
    CHECK_RC(kin_follow_event(a, open_dir, &o, &fi), KIN_OK);
    CHECK(fi.reopened == 1 && fi.event == KIN_FOLLOW_CLOSED_LOOP && fi.held == 0 && fi.held_m == -1);
    CHECK(fi.length > PI);
    CHECK_RC(kin_follow_event(a, NULL, &o, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_HELD_RIGID && fi.hinge == 0 && fi.held == 1 && fi.held_m == 0);
    int side;
    CHECK_RC(kin_hinge_sides(a, &side), KIN_OK);
    CHECK_RC(kin_hinge_angles(a, NULL, &psi), KIN_OK);
    CHECK(fabs(psi) > PI - 1e-6 && psi * psi0 < 0.0 && side != 0);
    /* without the option: the plain contact event, no holds */
    kin_follow_options plain;
    kin_follow_options_default(&plain);
    CHECK(plain.hold_hinges == 0 && plain.hold_rate_tol == 1e-6);
    o.hold_rate_tol = 0.0;
    CHECK_RC(kin_follow_event(a, open_dir, &o, &fi), KIN_EINVAL);
    /* holds need contact events: without them the option changes nothing */
    o.hold_rate_tol = 1e-6;
    CHECK_RC(kin_set_contact_events(a, 0, 1e-9), KIN_OK);
    CHECK_RC(kin_follow_event(a, close_dir, &o, &fi), KIN_OK);
    CHECK(fi.event != KIN_FOLLOW_HELD_RIGID && fi.event != KIN_FOLLOW_HINGE_CLOSED && fi.held == 0 &&
          fi.held_m == -1 && fi.hinge == -1);
    kin_assembly_free(a);
}

/* the vertex folded along its first line by rho */
static kin_assembly *vertex(double rho)
{
    double x[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -cos(rho), -sin(rho)};
    unsigned char fixed[15] = {1, 1, 1, 0, 1, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0};
    int b[] = {0, 1, 0, 2, 0, 3, 0, 4, 1, 2, 2, 3, 3, 4, 4, 1};
    int off[] = {0, 3, 6, 9, 12}, pj[] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1}, dev[] = {4, 5, 6, 7};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(3, 5, x, fixed, 8, b, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return NULL;
    CHECK_RC(kin_set_panels(a, 4, off, pj), KIN_OK);
    CHECK_RC(kin_set_device_bars(a, 4, dev), KIN_OK);
    CHECK_RC(kin_set_contact_events(a, 1, 1e-9), KIN_OK);
    return a;
}

/* along the samples: held hinges (mask) stay closed, the far corners of the
 * first line's hinges (E2, E4) together to rounding, and no hinge passes
 * through flat-folded (psi never jumps between +-pi while open) */
static void check_path(kin_assembly *a, const double *s, int n, unsigned mask)
{
    double prev[4] = {0, 0, 0, 0}, psi[4];
    for (int k = 0; k < n; ++k) {
        const double *x = s + 15 * k;
        CHECK_RC(kin_hinge_angles(a, x, psi), KIN_OK);
        for (int h = 0; h < 4; ++h) {
            if (mask >> h & 1) CHECK(PI - fabs(psi[h]) <= 1e-6);
            if (k > 0 && PI - fabs(psi[h]) > 1e-6) CHECK(fabs(psi[h] - prev[h]) < PI);
            prev[h] = psi[h];
        }
        if (mask & 1) {
            double d = 0.0;
            for (int i = 0; i < 3; ++i) d += (x[6 + i] - x[12 + i]) * (x[6 + i] - x[12 + i]);
            CHECK(sqrt(d) <= 64 * DBL_EPSILON);
        }
    }
}

static void folded_twice(void)
{
    kin_assembly *a = vertex(PI / 2);
    if (!a) return;
    kin_follow_options o = hold_options();
    kin_follow_info fi = {.size = sizeof fi};
    enum { CAP = 64 };
    double *s = malloc(sizeof(double) * 15 * CAP), sl[CAP];
    int ns = 0;
    if (!s) return;
    /* hinges: 0 = C-E1, 1 = C-E2, 2 = C-E3, 3 = C-E4 (edges sorted) */
    CHECK(kin_nhinges(a) == 4);
    CHECK_RC(kin_follow_event_ex(a, NULL, &o, NULL, 0, s, sl, CAP, &ns, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_HINGE_CLOSED && fi.held == 2 && fi.held_m == 1);
    CHECK(fi.hinge == 0 || fi.hinge == 2);
    check_path(a, s, ns, 0);
    /* the held motion: along the second line, the first line's hinges
     * closed, to four layers */
    CHECK_RC(kin_follow_event_ex(a, NULL, &o, NULL, 0, s, sl, CAP, &ns, &fi), KIN_OK);
    CHECK(fi.event == KIN_FOLLOW_HELD_RIGID && fi.held == 4 && fi.held_m == 0 && fi.reopened == 0);
    CHECK(ns > 4 && fi.length > 3.0);
    check_path(a, s, ns, 0x5);
    double x[15], psi[4];
    kin_get_coords(a, x);
    CHECK(fabs(x[9] - 1.0) <= 1e-6); /* E3 onto E1 */
    /* pressing the four layers on along the second line: refused */
    double on[9] = {0}, back2[9] = {0}, back1[9] = {0};
    on[5] = -1.0, back2[5] = 1.0, back1[8] = -1.0; /* E3's z (free coordinate 5), E4's z (8) */
    CHECK_RC(kin_follow_event(a, on, &o, &fi), KIN_EINVAL);
    /* back along the second line: its two hinges reopen, the first line's
     * stay held; the follow stops at the half-folded bifurcation */
    CHECK_RC(kin_follow_event_ex(a, back2, &o, NULL, 0, s, sl, CAP, &ns, &fi), KIN_OK);
    CHECK(fi.reopened == 2 && fi.event == KIN_FOLLOW_BIFURCATION && fi.held == 2 && fi.held_m == 1);
    check_path(a, s, ns, 0x5);
    /* back along the first line: reopened, unfolded flat */
    CHECK_RC(kin_follow_event_ex(a, back1, &o, NULL, 0, s, sl, CAP, &ns, &fi), KIN_OK);
    CHECK(fi.reopened == 2 && fi.event == KIN_FOLLOW_BIFURCATION && fi.held == 0 && fi.held_m == -1);
    check_path(a, s, ns, 0);
    CHECK_RC(kin_hinge_angles(a, NULL, psi), KIN_OK);
    for (int h = 0; h < 4; ++h) CHECK(fabs(psi[h]) <= 1e-6);
    free(s);
    kin_assembly_free(a);
}

int main(void)
{
    one_hinge();
    folded_twice();
    TEST_REPORT("test_hinge_hold");
}
