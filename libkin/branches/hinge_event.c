/* Hinges as part of the contact event (kin_contact.h HINGES,
 * docs/contact.md "Hinges"): contact_event.c calls these. A hinge (two
 * panels on one fold line, contact/hinge.c) closes where its panels lie
 * on each other, and passes through where its fold side (the sign sigma of
 * the signed volume of its edge and far joints) changes while it is folded
 * past 90 degrees (delta < pi/2): the panels then penetrate each other. So
 * each hinge's side is tracked along the path, step by step: while delta <
 * pi/2 it is the sigma the hinge had there; beyond (a hinge wider open,
 * where sigma changes through flat open, which is no contact) it is
 * unknown. The side is kept on the handle with the configuration it
 * belongs to, so that the next follow from there (the branches out of the
 * bifurcation a follow reached) knows on which side a hinge closed there
 * lies, and a hinge closed at a start that opens on the other side is a
 * pass-through at the start. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "branches/hinge_event.h"
#include "contact/contact_internal.h"

static const double HALF_PI = 1.57079632679489661923;

/* a hinge closed at a follow's start: gap at most this x the RMS rest
 * length (a bifurcation where a hinge closes is located to far better) */
static const double CLOSED_AT_START = 1e-6;

/* the sides a follow tracked hold for a start within this x the RMS rest
 * length of where it ended (every coordinate) */
static const double SIDES_NEAR = 1e-3;

/* a panel's half thickness */
static double half_t(const struct kin_contact *c, int p)
{
    return 0.5 * (c->tpan && c->tpan[p] >= 0.0 ? c->tpan[p] : c->t0);
}

/* contact: clearance at most 64 eps x the RMS rest length (as the parts') */
static double touch(const kin_assembly *a) { return 64.0 * DBL_EPSILON * a->rms_length; }

double kin__hinge_signed_clearance(const kin_assembly *a, const double *xyz, int h, int side)
{
    const struct kin_contact *c = a->ct;
    const int *g = c->hg + 6 * h;
    double delta;
    int sigma;
    double gap = kin__hinge_measure(xyz, g, &delta, &sigma, NULL);
    if (side != 0 && sigma != 0 && sigma != side && delta < HALF_PI) gap = -gap; /* through flat-folded */
    return gap - half_t(c, g[4]) - half_t(c, g[5]);
}

void kin__hinge_event_arm(kin_assembly *a)
{
    struct kin_contact *c = a->ct;
    c->ev_hinge = -1;
    c->ev_reopen = 0;
    c->hg_armed = c->ev_on && c->hinge_on && c->nh > 0;
    if (!c->hg_armed) return;
    int n = a->nj * a->dim;
    int known = c->hg_side_ok;
    double closed = CLOSED_AT_START * a->rms_length;
    /* the sides tracked to this configuration: the end of the follow that
     * reached it (a clone of that handle), or a point near it (a contact
     * located just before a bifurcation where hinges close, and the
     * bifurcation itself: 7.6e-7 to 2e-6 apart on the sails) */
    double near = SIDES_NEAR * a->rms_length;
    for (int i = 0; known && i < n; ++i)
        if (!(fabs(a->xyz[i] - c->hg_x[i]) <= near)) known = 0;
    for (int h = 0; h < c->nh; ++h) {
        double delta;
        int sigma;
        double gap = kin__hinge_measure(a->xyz, c->hg + 6 * h, &delta, &sigma, NULL);
        c->hg_c0[h] = gap <= closed;
        if (c->hg_c0[h]) c->hg_side[h] = known ? c->hg_side[h] : 0;
        else c->hg_side[h] = delta < HALF_PI ? (signed char)sigma : 0;
    }
}

int kin__hinge_event_check(kin_assembly *a)
{
    struct kin_contact *c = a->ct;
    if (!c->hg_armed) return 0;
    c->ev_hinge = -1;
    double closed = CLOSED_AT_START * a->rms_length, eps = touch(a);
    /* the first hinge (in order) that closed or passed through: the event */
    for (int h = 0; h < c->nh; ++h) {
        double delta;
        int sigma;
        double gap = kin__hinge_measure(a->xyz, c->hg + 6 * h, &delta, &sigma, NULL);
        int s = c->hg_side[h];
        if (c->hg_c0[h]) {
            /* closed at the start: watched once it opens */
            if (gap <= closed) continue;
            if (s != 0 && sigma != s && delta < HALF_PI) {
                c->ev_hinge = h;
                return 1;
            }
            if (c->hold_on && c->hg_held[h]) {
                /* a held hinge the path opened on its own side: reopened */
                c->ev_hinge = h;
                c->ev_reopen = 1;
                return 1;
            }
            continue;
        }
        if (s != 0 && kin__hinge_signed_clearance(a, a->xyz, h, s) <= eps) {
            c->ev_hinge = h;
            return 1;
        }
    }
    return 0;
}

void kin__hinge_event_advance(kin_assembly *a)
{
    struct kin_contact *c = a->ct;
    if (!c->hg_armed) return;
    double closed = CLOSED_AT_START * a->rms_length;
    for (int h = 0; h < c->nh; ++h) {
        double delta;
        int sigma;
        double gap = kin__hinge_measure(a->xyz, c->hg + 6 * h, &delta, &sigma, NULL);
        if (c->hg_c0[h]) {
            if (gap <= closed) continue;
            c->hg_c0[h] = 0;
        }
        c->hg_side[h] = delta < HALF_PI ? (signed char)(sigma ? sigma : c->hg_side[h]) : 0;
    }
}

int kin__hinge_event_reached(const kin_assembly *a)
{
    const struct kin_contact *c = a->ct;
    int h = c->ev_hinge;
    if (h >= 0 && c->ev_reopen) {
        /* reopened: its gap past the closed threshold */
        double delta;
        int sigma;
        return kin__hinge_measure(a->xyz, c->hg + 6 * h, &delta, &sigma, NULL) > CLOSED_AT_START * a->rms_length;
    }
    return h >= 0 && kin__hinge_signed_clearance(a, a->xyz, h, c->hg_side[h]) <= touch(a);
}

void kin__hinge_event_finish(kin_assembly *a)
{
    struct kin_contact *c = a->ct;
    if (!c || !c->hg_armed) return;
    memcpy(c->hg_x, a->xyz, sizeof(double) * (size_t)a->nj * (size_t)a->dim);
    c->hg_side_ok = 1;
    c->hg_armed = 0;
}
