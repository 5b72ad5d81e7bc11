/* Panels, thickness and clearance (kin_contact.h): the exact cases on
 * purpose (exactly touching, parallel segments, coplanar triangles, a
 * zero-area panel, a bar through a panel), adjacency, thickness, 2D, the
 * tree against all pairs on a sail, the same answer bit for bit from trees
 * built at different configurations, on a sheet of long tilted parts and on
 * two tilted sheets of long triangles side by side, the near-pair list
 * of checks with a cutoff (moves, jumps, a growing cutoff, its cap met),
 * clone, and every error path. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "contact/contact_internal.h"
#include "libkin.h"

static kin_assembly *make(int dim, int nj, const double *xyz, int nb, const int *bars)
{
    kin_assembly *a = NULL;
    char err[256];
    int rc = kin_assembly_create(dim, nj, xyz, NULL, nb, bars, NULL, &a, err, sizeof err);
    if (rc) fprintf(stderr, "create: %s\n", err);
    return a;
}

static double clr(kin_assembly *a, int *parts, double *pts)
{
    double c = NAN;
    CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, parts, pts), KIN_OK);
    return c;
}

#define TOL (64 * DBL_EPSILON)

static void bars_cases(void)
{
    /* two skew bars crossing at height h */
    double h = 0.25;
    double x[] = {-1, 0, 0, 1, 0, 0, 0, -1, h, 0, 1, h};
    int b[] = {0, 1, 2, 3};
    kin_assembly *a = make(3, 4, x, 2, b);
    int parts[4];
    double pts[6];
    CHECK_CLOSE(clr(a, parts, pts), h, TOL);
    CHECK(parts[0] == KIN_PART_BAR && parts[1] == 0 && parts[2] == KIN_PART_BAR && parts[3] == 1);
    CHECK_CLOSE(pts[0], 0.0, TOL);
    CHECK_CLOSE(pts[5], h, TOL);
    /* with thickness: radius 0.1 each -> h - 0.2; the default t0 = 0.2 */
    CHECK_RC(kin_set_thickness(a, 0.2, NULL, NULL), KIN_OK);
    CHECK_CLOSE(clr(a, NULL, NULL), h - 0.2, TOL);
    double rb[2] = {0.05, -1.0};
    CHECK_RC(kin_set_thickness(a, 0.2, rb, NULL), KIN_OK);
    CHECK_CLOSE(clr(a, NULL, NULL), h - 0.15, TOL);
    double got[2], t0;
    CHECK_RC(kin_get_thickness(a, &t0, got, NULL), KIN_OK);
    CHECK(t0 == 0.2 && got[0] == 0.05 && got[1] == 0.1);
    CHECK(kin_has_contact_model(a) == 1);
    /* crossing exactly (h = 0): clearance 0, then -(r_a + r_b) */
    double x0[] = {-1, 0, 0, 1, 0, 0, 0, -1, 0, 0, 1, 0};
    double c;
    CHECK_RC(kin_clearance(a, x0, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, -0.15, TOL);
    kin_assembly_free(a);

    /* parallel bars, overlapping, at distance 0.5; then collinear, touching end to end */
    double xp[] = {0, 0, 0, 2, 0, 0, 1, 0.5, 0, 3, 0.5, 0};
    a = make(3, 4, xp, 2, b);
    CHECK_CLOSE(clr(a, NULL, NULL), 0.5, TOL);
    double xc[] = {0, 0, 0, 1, 0, 0, 1, 0, 0, 2, 0, 0};
    CHECK_RC(kin_clearance(a, xc, INFINITY, &c, NULL, pts), KIN_OK);
    CHECK(c == 0.0);
    CHECK(pts[0] == 1.0 && pts[3] == 1.0);
    /* collinear with a gap of 0.5 */
    double xg[] = {0, 0, 0, 1, 0, 0, 1.5, 0, 0, 2, 0, 0};
    CHECK_RC(kin_clearance(a, xg, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.5, TOL);
    kin_assembly_free(a);

    /* two bars at a joint: adjacent, never compared */
    double xj[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    int bj[] = {0, 1, 0, 2};
    a = make(3, 3, xj, 2, bj);
    CHECK(isinf(clr(a, parts, NULL)) && parts[0] == -1);
    CHECK(kin_has_contact_model(a) == 0);
    kin_assembly_free(a);
}

/* a triangle panel (0,1,2) with its bars, and a bar (3,4) */
static void panel_cases(void)
{
    double x[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, -1, 0.5, 0.5, 1};
    int b[] = {0, 1, 1, 2, 2, 0, 3, 4};
    kin_assembly *a = make(3, 5, x, 4, b);
    int off[] = {0, 3}, pj[] = {0, 1, 2};
    CHECK_RC(kin_set_panels(a, 1, off, pj), KIN_OK);
    CHECK(kin_npanels(a) == 1);
    int parts[4];
    double pts[6];
    /* the bar passes through the panel at (0.5, 0.5, 0) */
    CHECK(clr(a, parts, pts) == 0.0);
    CHECK(parts[0] == KIN_PART_BAR && parts[1] == 3 && parts[2] == KIN_PART_PANEL && parts[3] == 0);
    CHECK_CLOSE(pts[0], 0.5, TOL);
    CHECK_CLOSE(pts[2], 0.0, TOL);
    CHECK_CLOSE(pts[5], 0.0, TOL);
    /* the bar lifted above the panel, ending at height 0.3: the endpoint's distance */
    double xu[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, 0.3, 0.5, 0.5, 1};
    double c;
    CHECK_RC(kin_clearance(a, xu, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.3, TOL);
    /* exactly touching: the endpoint on the panel */
    double xt[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, 0, 0.5, 0.5, 1};
    CHECK_RC(kin_clearance(a, xt, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK(c == 0.0);
    /* panel thickness 0.1, bar radius default 0.05 (t0 = 0.1) */
    double tp = 0.1;
    CHECK_RC(kin_set_thickness(a, 0.1, NULL, &tp), KIN_OK);
    CHECK_RC(kin_clearance(a, xu, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.3 - 0.05 - 0.05, TOL);
    /* a clone keeps panels and thickness */
    kin_assembly *b2 = NULL;
    CHECK_RC(kin_assembly_clone(a, &b2), KIN_OK);
    CHECK(kin_npanels(b2) == 1);
    CHECK_RC(kin_clearance(b2, xu, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.2, TOL);
    int o2[2], j2[3];
    CHECK_RC(kin_get_panels(b2, o2, j2), KIN_OK);
    CHECK(o2[1] == 3 && j2[2] == 2);
    kin_assembly_free(b2);
    /* a zero-area panel (collinear joints): its sides; the bar through its middle */
    double xd[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 1, -1, 0.25, 1, 1, 0.25};
    CHECK_RC(kin_set_thickness(a, 0.0, NULL, NULL), KIN_OK);
    CHECK_RC(kin_clearance(a, xd, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.25, TOL);
    double xd0[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 1, -1, 0, 1, 1, 0};
    CHECK_RC(kin_clearance(a, xd0, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK(c == 0.0);
    /* removing the panels */
    CHECK_RC(kin_set_panels(a, 0, NULL, NULL), KIN_OK);
    CHECK(kin_npanels(a) == 0);
    kin_assembly_free(a);
}

/* two triangles: coplanar overlapping, coplanar apart, stacked, crossing, sharing an edge */
static void triangle_cases(void)
{
    double x[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, 0, 3, 0.5, 0, 0.5, 3, 0};
    int b[] = {0, 1, 1, 2, 2, 0, 3, 4, 4, 5, 5, 3};
    kin_assembly *a = make(3, 6, x, 6, b);
    int off[] = {0, 3, 6}, pj[] = {0, 1, 2, 3, 4, 5};
    CHECK_RC(kin_set_panels(a, 2, off, pj), KIN_OK);
    int parts[4];
    double c;
    /* coplanar overlapping */
    CHECK(clr(a, parts, NULL) == 0.0);
    /* coplanar apart by 1 along x */
    double xa[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, 0};
    CHECK_RC(kin_clearance(a, xa, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 1.0, TOL);
    /* stacked parallel, 0.5 apart: triangle-triangle (and bars) */
    double xs[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.5, 1, 0, 0.5, 0, 1, 0.5};
    CHECK_RC(kin_clearance(a, xs, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.5, TOL);
    double tp[2] = {0.2, 0.4};
    CHECK_RC(kin_set_thickness(a, 0.0, NULL, tp), KIN_OK);
    CHECK_RC(kin_clearance(a, xs, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.5 - 0.1 - 0.2, TOL);
    CHECK(parts[0] == KIN_PART_PANEL && parts[2] == KIN_PART_PANEL);
    CHECK_RC(kin_set_thickness(a, 0.0, NULL, NULL), KIN_OK);
    /* crossing: the second triangle stands through the first */
    double xx[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, -1, 0.6, 0.5, 1, 0.5, 0.6, 1};
    CHECK_RC(kin_clearance(a, xx, INFINITY, &c, parts, NULL), KIN_OK);
    CHECK(c == 0.0);
    kin_assembly_free(a);

    /* a quad panel and a triangle sharing its edge (1, 2): adjacent; a far bar */
    double xq[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0.5, 0, 2, 0.5, 3, 2, 0.5, 4};
    int bq[] = {0, 1, 1, 2, 2, 3, 3, 0, 1, 4, 2, 4, 5, 6};
    a = make(3, 7, xq, 7, bq);
    int oq[] = {0, 4, 7}, jq[] = {0, 1, 2, 3, 1, 4, 2};
    CHECK_RC(kin_set_panels(a, 2, oq, jq), KIN_OK);
    c = clr(a, parts, NULL);
    /* the panels share the edge (1, 2) and are not compared; the nearest
     * non-adjacent pair is bar 0 (joints 0, 1) and bar 5 (joints 2, 4),
     * or by symmetry bar 2 (2, 3) and bar 4 (1, 4) */
    double dmin = 2.0 / sqrt(5.0);
    CHECK(parts[0] == KIN_PART_BAR && parts[2] == KIN_PART_BAR);
    CHECK_CLOSE(c, dmin, TOL * 8);
    kin_assembly_free(a);
}

static void plane_cases(void)
{
    /* 2D: a triangle panel and a bar crossing its side; then apart */
    double x[] = {0, 0, 2, 0, 0, 2, 0.2, 1.5, 3, 1.5};
    int b[] = {0, 1, 1, 2, 2, 0, 3, 4};
    kin_assembly *a = make(2, 5, x, 4, b);
    int off[] = {0, 3}, pj[] = {0, 1, 2};
    CHECK_RC(kin_set_panels(a, 1, off, pj), KIN_OK);
    int parts[4];
    double pts[4], c;
    CHECK(clr(a, parts, pts) == 0.0);
    double xa[] = {0, 0, 2, 0, 0, 2, 2, 2, 3, 2};
    CHECK_RC(kin_clearance(a, xa, INFINITY, &c, parts, pts), KIN_OK);
    CHECK_CLOSE(c, sqrt(2.0), TOL * 4);
    CHECK_CLOSE(pts[2], 2.0, TOL);
    CHECK_CLOSE(pts[0], 1.0, TOL * 4);
    kin_assembly_free(a);
}

/* the tree's boxes are floats: rounded to nearest, two bars end to end
 * 0.2 float ulps apart would have boxes a whole ulp apart and be dropped
 * under a margin between the two; rounded outward they are kept */
static void float_boxes(void)
{
    double u = 0x1p-23, d = 0.2 * u;
    double x[] = {0, 0, 0, 1 + 0.4 * u, 0, 0, 1 + 0.6 * u, 0, 0, 2, 0, 0};
    int b[] = {0, 1, 2, 3};
    kin_assembly *a = make(3, 4, x, 2, b);
    double c;
    CHECK_RC(kin_clearance(a, NULL, 0.5 * (d + u), &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, d, 4 * DBL_EPSILON);
    CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, d, 4 * DBL_EPSILON);
    kin_assembly_free(a);
}

/* the smallest clearance over all pairs of non-adjacent parts of a model of
 * bars and triangle panels pj (np of them) at y, by brute force; the
 * clearance of the pair of parts (pa, pb) into *dab (if pa >= 0) */
static double all_pairs(const kin_assembly *a, const double *y, const int *bars, const int *pj, int np, int pa,
                        int pb, double *dab)
{
    int nb = kin_nbars(a);
    double best = INFINITY, cp[3], cq[3];
    double r0, *rb = malloc(sizeof(double) * (size_t)nb), *tp = malloc(sizeof(double) * (size_t)np);
    kin_get_thickness(a, &r0, rb, tp);
    int npart = nb + np, nj = kin_njoints(a);
    /* the distances on y scaled by a power of two to a unit size (exact; at
     * 1e-300 their products of four lengths underflow, as kin_clearance's
     * own tests scale them too), scaled back */
    double m = 0.0, *ys = malloc(sizeof(double) * 3 * (size_t)nj);
    for (int i = 0; i < 3 * nj; ++i) m = fmax(m, fabs(y[i]));
    int k = m > 0.0 ? ilogb(m) : 0;
    for (int i = 0; i < 3 * nj; ++i) ys[i] = ldexp(y[i], -k);
    y = ys;
    for (int s = 0; s < npart; ++s)
        for (int t = s + 1; t < npart; ++t) {
            const int *js = s < nb ? bars + 2 * s : pj + 3 * (s - nb);
            const int *jt = t < nb ? bars + 2 * t : pj + 3 * (t - nb);
            int ns = s < nb ? 2 : 3, nt = t < nb ? 2 : 3, adj = 0;
            for (int i = 0; i < ns; ++i)
                for (int j = 0; j < nt; ++j) adj |= js[i] == jt[j];
            if (adj) continue;
            double d;
            const double *S[3] = {y + 3 * js[0], y + 3 * js[1], ns == 3 ? y + 3 * js[2] : NULL};
            const double *T[3] = {y + 3 * jt[0], y + 3 * jt[1], nt == 3 ? y + 3 * jt[2] : NULL};
            if (ns == 2 && nt == 2) d = kin__dist_seg_seg(S[0], S[1], T[0], T[1], cp, cq);
            else if (ns == 2) d = kin__dist_seg_tri(S[0], S[1], T[0], T[1], T[2], cp, cq);
            else d = kin__dist_tri_tri(S, T, cp, cq);
            d = ldexp(d, k);
            d -= (s < nb ? rb[s] : 0.5 * tp[s - nb]) + (t < nb ? rb[t] : 0.5 * tp[t - nb]);
            best = fmin(best, d);
            if (s == pa && t == pb) *dab = d;
        }
    free(rb), free(tp), free(ys);
    return best;
}

/* kin_clearance at y with cutoff against all pairs: the value, and the
 * parts it names are a pair at that clearance */
static void check_against_all(kin_assembly *a, const double *y, double cutoff, const int *bars, const int *pj, int np,
                              double scale)
{
    int nb = kin_nbars(a), parts[4];
    double c, dab = NAN;
    /* the reference knows parts, not hinges (test_hinges.c checks those) */
    CHECK_RC(kin_set_hinge_contact(a, 0), KIN_OK);
    CHECK_RC(kin_clearance(a, y, cutoff, &c, parts, NULL), KIN_OK);
    int pa = parts[0] == KIN_PART_BAR ? parts[1] : nb + parts[1], pb = parts[2] == KIN_PART_BAR ? parts[3] : nb + parts[3];
    double best = all_pairs(a, y, bars, pj, np, pa, pb, &dab), tol = 16 * DBL_EPSILON * scale;
    /* within rounding of the cutoff (the same distance computed with the
     * operands in another order), either answer is right */
    if (best < cutoff - tol || (best <= cutoff + tol && c < INFINITY)) {
        CHECK_CLOSE(c, best, tol);
        CHECK(parts[0] >= 0 && pa < pb);
        CHECK_CLOSE(dab, c, tol);
    } else {
        CHECK(c == INFINITY && parts[0] == -1);
    }
}

/* a sail's bar triangles as panels (np of them: offsets *off, joints *pj,
 * allocated here) */
static void sail_triangles(int nb, const int *bars, int *npan, int **offp, int **pjp)
{
    int cap = 4 * nb, np = 0;
    int *off = malloc(sizeof(int) * ((size_t)cap + 1)), *pj = malloc(sizeof(int) * 3 * (size_t)cap);
    off[0] = 0;
    for (int k = 0; k < nb; ++k)
        for (int m = k + 1; m < nb; ++m) {
            int p0 = bars[2 * k], p1 = bars[2 * k + 1], q0 = bars[2 * m], q1 = bars[2 * m + 1];
            int shared = p0 == q0 || p0 == q1 ? p0 : (p1 == q0 || p1 == q1 ? p1 : -1);
            if (shared < 0) continue;
            int u = p0 == shared ? p1 : p0, v = q0 == shared ? q1 : q0;
            if (u > shared || v > shared || u >= v) continue; /* each triangle once: shared the largest */
            for (int r = 0; r < nb; ++r)
                if ((bars[2 * r] == u && bars[2 * r + 1] == v) || (bars[2 * r] == v && bars[2 * r + 1] == u)) {
                    if (np < cap) pj[3 * np] = u, pj[3 * np + 1] = v, pj[3 * np + 2] = shared, off[np + 1] = 3 * (np + 1), ++np;
                }
        }
    *npan = np, *offp = off, *pjp = pj;
}

/* on a folded-ish sail: the tree's answer equals the smallest over all
 * pairs, call after call on one handle (the tree is refitted, and built
 * again when the configuration has moved far), along a path of small moves,
 * with cutoffs, and at scales beyond the range of a float (its boxes are
 * floats rounded outward: they must stay conservative) */
static void sail_vs_all_pairs(void)
{
    kin_sail_params p;
    kin_sail_params_default(&p, 6, 2);
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_sail(&p, &a, NULL, 0), KIN_OK);
    if (!a) return;
    int nb = kin_nbars(a), nj = kin_njoints(a);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj), *y = malloc(sizeof(double) * 3 * (size_t)nj);
    kin_get_bars(a, bars);
    kin_get_coords(a, xyz);
    /* panels: the bar triangles */
    int np = 0, *off = NULL, *pj = NULL;
    sail_triangles(nb, bars, &np, &off, &pj);
    CHECK(np > 0);
    CHECK_RC(kin_set_panels(a, np, off, pj), KIN_OK);
    unsigned long long seed = 7;
    for (int trial = 0; trial < 40; ++trial) {
        double amp = trial < 20 ? 0.05 : 0.6;
        for (int i = 0; i < 3 * nj; ++i)
            y[i] = xyz[i] + amp * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5);
        if (trial % 3 == 0) kin_set_thickness(a, 0.01 * trial, NULL, NULL);
        check_against_all(a, y, INFINITY, bars, pj, np, 1.0);
        /* a contact margin: the same answer below it, none above */
        double c;
        CHECK_RC(kin_clearance(a, y, INFINITY, &c, NULL, NULL), KIN_OK);
        check_against_all(a, y, c + 0.01, bars, pj, np, 1.0);
        check_against_all(a, y, c, bars, pj, np, 1.0);
    }
    /* a path of small moves from a crumpled configuration (refits), then back */
    double *dir = malloc(sizeof(double) * 3 * (size_t)nj);
    for (int i = 0; i < 3 * nj; ++i) dir[i] = (double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5;
    kin_set_thickness(a, 0.0, NULL, NULL);
    for (int t = 0; t <= 30; ++t) {
        double s = t <= 15 ? t / 15.0 : (30 - t) / 15.0;
        for (int i = 0; i < 3 * nj; ++i) y[i] = xyz[i] + 0.4 * s * dir[i];
        check_against_all(a, y, t % 2 ? INFINITY : 0.05, bars, pj, np, 1.0);
    }
    /* beyond the float range, and below its normal range */
    double scales[] = {1e45, 1e-42, 1e-300};
    for (int m = 0; m < 3; ++m) {
        for (int i = 0; i < 3 * nj; ++i) y[i] = scales[m] * (xyz[i] + 0.3 * dir[i]);
        check_against_all(a, y, INFINITY, bars, pj, np, scales[m]);
    }
    free(dir), free(bars), free(xyz), free(y), free(off), free(pj);
    kin_assembly_free(a);
}

/* long thin parts tilted in a nearly flat sheet (what the lane tests of
 * the x + y and x - y slabs and of a primitive's own axes are for): long
 * bars and slivers at many angles just above a grid of short bars, far
 * from the origin (rounding of the slabs' sums), with and without
 * thickness: the tree's answer equals the smallest over all pairs, with
 * cutoffs at it, just above it and at a contact margin */
static void sheet_vs_all_pairs(void)
{
    enum { G = 6, NL = 9, NS = 6 };
    const double X0 = 3e5, Y0 = -7e5; /* |x + y| ~ 4e5, |x - y| ~ 1e6 */
    int nj = (G + 1) * (G + 1) + 2 * NL + 3 * NS, nb = 2 * G * (G + 1) + NL + 3 * NS, np = NS;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj), *y = malloc(sizeof(double) * 3 * (size_t)nj);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb), off[NS + 1], pj[3 * NS];
    int j = 0, k = 0;
    for (int r = 0; r <= G; ++r)
        for (int q = 0; q <= G; ++q, ++j) xyz[3 * j] = X0 + q, xyz[3 * j + 1] = Y0 + r, xyz[3 * j + 2] = 0.0;
    for (int r = 0; r <= G; ++r)
        for (int q = 0; q < G; ++q) {
            bars[2 * k] = r * (G + 1) + q, bars[2 * k + 1] = r * (G + 1) + q + 1, ++k;
            bars[2 * k] = q * (G + 1) + r, bars[2 * k + 1] = (q + 1) * (G + 1) + r, ++k;
        }
    unsigned long long seed = 11;
    double *ang = malloc(sizeof(double) * (NL + NS));
    for (int m = 0; m < NL + NS; ++m) ang[m] = 3.14159265358979 * m / (NL + NS) + 0.01 * m;
    off[0] = 0;
    unsigned char *fixed = calloc(3 * (size_t)nj, 1);
    int j0 = j;
    (void)j0;
    /* the long parts: placed in each trial below (two joints a bar, three a sliver) */
    for (int m = 0; m < NL; ++m, j += 2) bars[2 * k] = j, bars[2 * k + 1] = j + 1, ++k;
    for (int m = 0; m < NS; ++m, j += 3) {
        bars[2 * k] = j, bars[2 * k + 1] = j + 1, ++k;
        bars[2 * k] = j + 1, bars[2 * k + 1] = j + 2, ++k;
        bars[2 * k] = j + 2, bars[2 * k + 1] = j, ++k;
        pj[3 * m] = j, pj[3 * m + 1] = j + 1, pj[3 * m + 2] = j + 2, off[m + 1] = 3 * (m + 1);
    }
    CHECK(j == nj && k == nb);
    for (int trial = 0; trial < 24; ++trial) {
        double h = trial < 8 ? 0.002 : (trial < 16 ? 0.02 : 0.2); /* heights above the grid */
        j = (G + 1) * (G + 1);
        for (int m = 0; m < NL + NS; ++m) {
            double a = ang[m] + 0.3 * trial, c = cos(a), sn = sin(a), L = 2.5 + 0.3 * m;
            double cx = X0 + 0.5 * G + 0.7 * ((double)(kin__splitmix(&seed) >> 11) * 0x1p-53 - 0.5);
            double cy = Y0 + 0.5 * G + 0.7 * ((double)(kin__splitmix(&seed) >> 11) * 0x1p-53 - 0.5);
            double z = h * (1 + m % 3) * ((m + trial) % 2 ? 1 : -1);
            double P[3][3] = {{cx - L * c, cy - L * sn, z}, {cx + L * c, cy + L * sn, z + 0.1 * h}, {cx + 0.05 * sn, cy - 0.05 * c, z}};
            int nv = m < NL ? 2 : 3;
            for (int q = 0; q < nv; ++q, ++j)
                for (int d = 0; d < 3; ++d) xyz[3 * j + d] = P[q][d];
        }
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(3, nj, xyz, fixed, nb, bars, NULL, &a, NULL, 0), KIN_OK);
        if (!a) break;
        CHECK_RC(kin_set_panels(a, np, off, pj), KIN_OK);
        if (trial % 2) CHECK_RC(kin_set_thickness(a, 0.5 * h, NULL, NULL), KIN_OK);
        memcpy(y, xyz, sizeof(double) * 3 * (size_t)nj);
        double c;
        check_against_all(a, y, INFINITY, bars, pj, np, 1e6);
        CHECK_RC(kin_clearance(a, y, INFINITY, &c, NULL, NULL), KIN_OK);
        check_against_all(a, y, c, bars, pj, np, 1e6);
        check_against_all(a, y, c + 0.01 * h, bars, pj, np, 1e6);
        check_against_all(a, y, 0.004, bars, pj, np, 1e6);
        /* the same at the origin, turned about z (tilts relative to the slabs) */
        for (int q = 0; q < nj; ++q) {
            double u = xyz[3 * q] - X0, v = xyz[3 * q + 1] - Y0, t = 0.4 + 0.1 * trial;
            y[3 * q] = cos(t) * u - sin(t) * v, y[3 * q + 1] = sin(t) * u + cos(t) * v, y[3 * q + 2] = xyz[3 * q + 2];
        }
        check_against_all(a, y, INFINITY, bars, pj, np, 1.0);
        CHECK_RC(kin_clearance(a, y, INFINITY, &c, NULL, NULL), KIN_OK);
        check_against_all(a, y, c, bars, pj, np, 1.0);
        check_against_all(a, y, 0.004, bars, pj, np, 1.0);
        kin_assembly_free(a);
    }
    /* two bars along x - y, apart across it by d (to rounding), bare and
     * with radius r: found at a cutoff just above d - 2 r, not just below
     * it (1e-6: above the rounding of the bounds in double at coordinates
     * of 1e6, below any rounding to float there); at x + y = 2^19 + 0.02 the two slabs' bounds are 0.3 and 0.8
     * float ulps above a float (rounded to nearest, the gap between them
     * would grow from 0.45 to 1 ulp and drop the pair); near the origin
     * the slabs are fine enough to show the radius across them (r sqrt 2) */
    for (int m = 0; m < 6; ++m) {
        double d = 0.02, e = d / sqrt(2.0), r = m % 2 ? 0.002 : 0.0;
        double bx = m < 2 ? X0 : (m < 4 ? 0x1p18 + 0.01 : 0.3), by = m < 2 ? Y0 : (m < 4 ? 0x1p18 + 0.01 : -0.2);
        double x2[] = {bx, by, 0, bx + 4, by - 4, 0, bx + e, by + e, 0, bx + 4 + e, by - 4 + e, 0};
        int b2[] = {0, 1, 2, 3};
        kin_assembly *a = make(3, 4, x2, 2, b2);
        if (!a) break;
        CHECK_RC(kin_set_thickness(a, 2 * r, NULL, NULL), KIN_OK);
        double c, cd;
        CHECK_RC(kin_clearance(a, NULL, INFINITY, &cd, NULL, NULL), KIN_OK);
        CHECK_CLOSE(cd, d - 2 * r, 1e6 * 16 * DBL_EPSILON);
        /* the thickness set again: the tree is built afresh, without the
         * last answer's pair to try first */
        CHECK_RC(kin_set_thickness(a, 2 * r, NULL, NULL), KIN_OK);
        CHECK_RC(kin_clearance(a, NULL, cd + 1e-6, &c, NULL, NULL), KIN_OK);
        CHECK(c == cd);
        CHECK_RC(kin_set_thickness(a, 2 * r, NULL, NULL), KIN_OK);
        CHECK_RC(kin_clearance(a, NULL, cd - 1e-6, &c, NULL, NULL), KIN_OK);
        CHECK(c == INFINITY);
        kin_assembly_free(a);
    }
    free(xyz), free(y), free(bars), free(ang), free(fixed);
}

/* long thin triangles side by side in two parallel tilted sheets (a sail's
 * outer loops: what each leaf's own axis, across its parts in their plane,
 * is for): strips along a direction none of the fixed slabs follows, all
 * 1 apart across the strips but two at d, and the other sheet h above;
 * near the origin and far from it (rounding of the float projections), bare
 * and thick: the tree's answer equals the smallest over all pairs, at
 * cutoffs just above and just below the smallest clearance, with the tree
 * built afresh (no last answer to try first), then refitted as the sheets
 * move and the near pair changes from call to call */
static void tilted_sheets(double *xyz, int nt, int ns, int near, double th, double tilt, double d, double h, double X0,
                          double Y0, double dz)
{
    const double L = 20.0, wd = 0.05;
    /* the strips' direction u (30 deg + a bit from x), the sheets' normal
     * n (tilted), v = n x u across the strips in the plane */
    double n[3] = {sin(tilt) * sin(th + 1.0), -sin(tilt) * cos(th + 1.0), cos(tilt)}, u0[3] = {cos(th), sin(th), 0};
    double un = u0[0] * n[0] + u0[1] * n[1] + u0[2] * n[2], u[3], v[3], uu = 0.0;
    for (int k = 0; k < 3; ++k) u[k] = u0[k] - un * n[k], uu += u[k] * u[k];
    for (int k = 0; k < 3; ++k) u[k] /= sqrt(uu);
    v[0] = n[1] * u[2] - n[2] * u[1], v[1] = n[2] * u[0] - n[0] * u[2], v[2] = n[0] * u[1] - n[1] * u[0];
    for (int t = 0; t < nt; ++t) {
        int sheet = t / ns, k = t % ns;
        double s = k * (wd + 1.0) - (k > near ? 1.0 - d : 0.0) + 0.37 * sheet, z = sheet * h;
        double a = 0.3 * (k % 3) - 0.3; /* along: staggered ends */
        /* the sliver's third corner across it, to one side or the other */
        double P[3][2] = {{a - 0.5 * L, s + (k % 2) * wd}, {a + 0.5 * L, s + (k % 2) * wd}, {a + 0.1 * L, s + (1 - k % 2) * wd}};
        for (int q = 0; q < 3; ++q)
            for (int c = 0; c < 3; ++c)
                xyz[3 * (3 * t + q) + c] = (c == 0 ? X0 : c == 1 ? Y0 : 0.0) + P[q][0] * u[c] + P[q][1] * v[c] + z * n[c] +
                                           (c == 2 ? dz * ((3 * t + q) % 5) : 0.0);
    }
}
static void tilted_sheets_vs_all_pairs(void)
{
    enum { NS = 14 }; /* strips per sheet */
    int nt = 2 * NS, nj = 3 * nt, nb = 3 * nt, np = nt;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb), *off = malloc(sizeof(int) * ((size_t)np + 1)),
        *pj = malloc(sizeof(int) * 3 * (size_t)np);
    unsigned char *fixed = calloc(3 * (size_t)nj, 1);
    off[0] = 0;
    for (int t = 0; t < nt; ++t) {
        for (int q = 0; q < 3; ++q) {
            pj[3 * t + q] = 3 * t + q;
            bars[2 * (3 * t + q)] = 3 * t + q, bars[2 * (3 * t + q) + 1] = 3 * t + (q + 1) % 3;
        }
        off[t + 1] = 3 * (t + 1);
    }
    for (int trial = 0; trial < 24; ++trial) {
        double th = 0.5236 + 0.05 * trial, tilt = 0.35 + 0.02 * trial, d = trial % 4 < 3 ? 0.01 + 0.001 * trial : 0.3;
        double h = trial % 2 ? 0.6 : 5.0, r = trial % 8 < 4 ? 0.0 : 0.002;
        double X0 = trial < 8 ? 0.0 : 3e5 + 0.37 * trial, Y0 = trial < 8 ? 0.0 : -2e5, scale = X0 > 0.0 ? 1e6 : 1.0;
        double e1 = X0 > 0.0 ? 1e-6 : 1e-9; /* above the rounding in double there */
        tilted_sheets(xyz, nt, NS, 6, th, tilt, d, h, X0, Y0, 0.0);
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(3, nj, xyz, fixed, nb, bars, NULL, &a, NULL, 0), KIN_OK);
        if (!a) break;
        CHECK_RC(kin_set_panels(a, np, off, pj), KIN_OK);
        CHECK_RC(kin_set_thickness(a, 2 * r, NULL, NULL), KIN_OK);
        double c;
        check_against_all(a, xyz, INFINITY, bars, pj, np, scale);
        CHECK_RC(kin_clearance(a, xyz, INFINITY, &c, NULL, NULL), KIN_OK);
        CHECK(c <= fmin(d + 0.05, h) - 2 * r + 1e-9 * scale); /* the slivers narrow away from their third corner */
        double cut[] = {c + e1, c - e1, c + 1e-3, c - 1e-3, 0.004};
        for (int e = 0; e < 5; ++e) {
            CHECK_RC(kin_set_thickness(a, 2 * r, NULL, NULL), KIN_OK); /* a new tree: no pair to try first */
            check_against_all(a, xyz, cut[e], bars, pj, np, scale);
        }
        /* moved a little each call, the near pair alternating between
         * strips 6, 7 and 3, 4: refits, the last answer's pair no longer the nearest */
        for (int m = 0; m < 8; ++m) {
            tilted_sheets(xyz, nt, NS, m % 2 ? 3 : 6, th, tilt, d, h, X0, Y0, 0.002 * m);
            double cm = m % 3 == 0 ? INFINITY : m % 3 == 1 ? fmin(d, h) - 2 * r + 1e-3 : 0.004;
            check_against_all(a, xyz, cm, bars, pj, np, scale);
        }
        kin_assembly_free(a);
    }
    free(xyz), free(bars), free(off), free(pj), free(fixed);
}

/* the answer does not depend on the tree: on sail members (crumpled out of
 * their plane, every bar and panel of its own thickness), the answer at a
 * configuration from a tree built at another one and refitted equals, bit
 * for bit (clearance, parts, closest points), the answer from a tree built
 * there, which hands the pairs' primitives to the exact test in other
 * orders (so a pair's exact test must not depend on that order: the radii
 * subtracted in another order can change the last bit); and the tree's
 * split (by the least surface measure, along the node's own directions
 * too) keeps the answer of all pairs */
static void tree_independent_answers(void)
{
    const int members[][2] = {{6, 5}, {8, 4}};
    unsigned long long seed = 11;
    int differ = 0; /* trials where the two trees differ (the test is not void) */
    for (int m = 0; m < 2; ++m) {
        kin_sail_params p;
        kin_sail_params_default(&p, members[m][0], members[m][1]);
        kin_assembly *a = NULL;
        CHECK_RC(kin_model_sail(&p, &a, NULL, 0), KIN_OK);
        if (!a) return;
        int nb = kin_nbars(a), nj = kin_njoints(a), np = 0;
        int *bars = malloc(sizeof(int) * 2 * (size_t)nb), *off = NULL, *pj = NULL;
        double *xyz = malloc(sizeof(double) * 3 * (size_t)nj), *x1 = malloc(sizeof(double) * 3 * (size_t)nj),
               *x2 = malloc(sizeof(double) * 3 * (size_t)nj);
        kin_get_bars(a, bars);
        kin_get_coords(a, xyz);
        sail_triangles(nb, bars, &np, &off, &pj);
        CHECK(np > 0);
        CHECK_RC(kin_set_panels(a, np, off, pj), KIN_OK);
        double *rb = malloc(sizeof(double) * (size_t)nb), *tp = malloc(sizeof(double) * (size_t)np);
        /* radii of many sizes: (d - r1) - r2 and (d - r2) - r1 often differ in the last bit */
        for (int k = 0; k < nb; ++k) rb[k] = 0.001 + 0.1 * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0);
        for (int k = 0; k < np; ++k) tp[k] = 0.002 + 0.2 * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0);
        for (int trial = 0; trial < 16; ++trial) {
            for (int i = 0; i < 3 * nj; ++i) {
                double amp = i % 3 == 2 ? 0.4 : 0.03;
                double u1 = (double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5;
                double u2 = (double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5;
                x1[i] = xyz[i] + amp * u1, x2[i] = xyz[i] + amp * (trial % 2 ? u2 : 0.9 * u1 + 0.1 * u2);
            }
            double cut = INFINITY;
            for (int e = 0; e < 2; ++e) {
                double c1, c2, p1[6], p2[6], c0;
                int q1[4], q2[4];
                CHECK_RC(kin_set_thickness(a, 0.0, rb, tp), KIN_OK); /* a new tree */
                CHECK_RC(kin_clearance(a, x1, INFINITY, &c0, NULL, NULL), KIN_OK); /* built at x1 */
                CHECK_RC(kin_clearance(a, x2, cut, &c1, q1, p1), KIN_OK);          /* refitted to x2 */
                size_t no = sizeof(int) * (size_t)a->ct->nprim;
                int *o1 = malloc(no);
                memcpy(o1, a->ct->order, no);
                CHECK_RC(kin_set_thickness(a, 0.0, rb, tp), KIN_OK);
                CHECK_RC(kin_clearance(a, x2, cut, &c2, q2, p2), KIN_OK); /* built at x2 */
                differ += memcmp(o1, a->ct->order, no) != 0; /* another tree */
                free(o1);
                CHECK(memcmp(&c1, &c2, sizeof c1) == 0);
                CHECK(memcmp(q1, q2, sizeof q1) == 0);
                if (c1 < INFINITY) CHECK(memcmp(p1, p2, sizeof p1) == 0);
                if (e == 0) check_against_all(a, x2, INFINITY, bars, pj, np, 1.0);
                cut = c2 + 0.01; /* then a contact margin above it */
            }
        }
        free(bars), free(off), free(pj), free(xyz), free(x1), free(x2), free(rb), free(tp);
        kin_assembly_free(a);
    }
    CHECK(differ > 0);
}

/* the near-pair list (contact/near_list.c): checks with a cutoff
 * reuse the leaf pairs listed at an earlier configuration while no leaf has
 * moved more than its skin. Its answers equal the smallest over all pairs:
 * along a path of small moves (the list serves most checks), when one joint
 * jumps onto a far part (a list that ignored the moves would miss it), when
 * the cutoff grows past the one the list was made for (it would miss the
 * pairs between), and when the walk meets more leaf pairs than the list
 * holds (no list, the walk alone) */
static void near_list_cases(void)
{
    kin_sail_params p;
    kin_sail_params_default(&p, 6, 2);
    kin_assembly *a = NULL;
    CHECK_RC(kin_model_sail(&p, &a, NULL, 0), KIN_OK);
    if (!a) return;
    int nb = kin_nbars(a), nj = kin_njoints(a), np = 0, *off = NULL, *pj = NULL;
    int *bars = malloc(sizeof(int) * 2 * (size_t)nb);
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj), *y = malloc(sizeof(double) * 3 * (size_t)nj),
           *dir = malloc(sizeof(double) * 3 * (size_t)nj);
    kin_get_bars(a, bars);
    kin_get_coords(a, xyz);
    sail_triangles(nb, bars, &np, &off, &pj);
    CHECK_RC(kin_set_panels(a, np, off, pj), KIN_OK);
    /* every bar a part (the joint moved below is the centre, on the
     * spokes, which the built-in sail marks as devices) */
    CHECK_RC(kin_set_device_bars(a, 0, NULL), KIN_OK);
    unsigned long long seed = 23;
    for (int i = 0; i < 3 * nj; ++i) {
        double u = (double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5;
        xyz[i] += i % 3 == 2 ? 0.3 * u : 0.02 * u; /* out of the plane: parts near, not adjacent */
        dir[i] = (double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5;
    }
    /* a path of small moves, with and without thickness */
    for (int th = 0; th < 2; ++th) {
        CHECK_RC(kin_set_thickness(a, 0.02 * th, NULL, NULL), KIN_OK);
        unsigned long used = a->ct ? a->ct->vl_used : 0;
        for (int t = 0; t <= 80; ++t) {
            for (int i = 0; i < 3 * nj; ++i) y[i] = xyz[i] + 0.002 * t * dir[i];
            check_against_all(a, y, 0.05, bars, pj, np, 1.0);
            check_against_all(a, y, 0.05, bars, pj, np, 1.0); /* the same point again: the list holds */
        }
        CHECK(a->ct->vl_used - used >= 81); /* the list served (the test is not void) */
    }
    /* a joint jumps onto a bar some way off, with the list in force: the
     * tree is only refitted (no leaf pair of the two is listed), the list
     * must not serve */
    CHECK(a->ct->vl_ok);
    int j = bars[0], far = -1;
    double dfar = INFINITY;
    for (int k = 0; k < nb; ++k) {
        double d = 0.0;
        for (int q = 0; q < 3; ++q) {
            double m = 0.5 * (y[3 * bars[2 * k] + q] + y[3 * bars[2 * k + 1] + q]) - y[3 * j + q];
            d += m * m;
        }
        d = sqrt(d);
        if (d > 1.5 && d < dfar) dfar = d, far = k; /* the nearest bar beyond 1.5 */
    }
    CHECK(far >= 0);
    if (far < 0) far = 0;
    size_t no = sizeof(int) * (size_t)a->ct->nprim;
    int *o1 = malloc(no);
    memcpy(o1, a->ct->order, no);
    unsigned long used = a->ct->vl_used;
    for (int q = 0; q < 3; ++q) y[3 * j + q] = 0.5 * (y[3 * bars[2 * far] + q] + y[3 * bars[2 * far + 1] + q]);
    double c;
    CHECK_RC(kin_clearance(a, y, 0.05, &c, NULL, NULL), KIN_OK);
    CHECK(memcmp(o1, a->ct->order, no) == 0); /* the same tree */
    CHECK(a->ct->vl_used == used);
    free(o1);
    CHECK(c <= 0.0);
    check_against_all(a, y, 0.05, bars, pj, np, 1.0);
    /* the list's cap met: no list, the same answers */
    for (int i = 0; i < 3 * nj; ++i) y[i] = xyz[i];
    CHECK_RC(kin_set_thickness(a, 0.0, NULL, NULL), KIN_OK);
    int cap = a->ct->vl_cap;
    a->ct->vl_cap = 1;
    check_against_all(a, y, 0.05, bars, pj, np, 1.0);
    CHECK(!a->ct->vl_ok);
    check_against_all(a, y, 0.05, bars, pj, np, 1.0);
    a->ct->vl_cap = cap;
    free(bars), free(xyz), free(y), free(dir), free(off), free(pj);
    kin_assembly_free(a);

    /* bars on a grid, each drifting its own way (leaves apart, so the skins
     * decide which leaf pairs are listed): pairs come within the cutoff
     * while the list holds, and must be found */
    {
        enum { G = 16, NG = G * G };
        double *Z = malloc(sizeof(double) * 6 * NG), *V = malloc(sizeof(double) * 6 * NG), *Y = malloc(sizeof(double) * 6 * NG);
        int *GB = malloc(sizeof(int) * 2 * NG);
        for (int k = 0; k < NG; ++k) {
            double th = 6.283185307179586 * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0);
            double cx = k % G, cy = k / G, cz = 0.1 * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0);
            double f = (k % G) < G / 2 ? 0.2 : 1.0; /* one half slower: leaves' skins differ */
            double vx = f * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5);
            double vy = f * ((double)(kin__splitmix(&seed) >> 11) / 9007199254740992.0 - 0.5);
            for (int e = 0; e < 2; ++e) {
                double sgn = e ? 0.45 : -0.45;
                Z[6 * k + 3 * e] = cx + sgn * cos(th), Z[6 * k + 3 * e + 1] = cy + sgn * sin(th), Z[6 * k + 3 * e + 2] = cz;
                V[6 * k + 3 * e] = vx, V[6 * k + 3 * e + 1] = vy, V[6 * k + 3 * e + 2] = 0.0;
            }
            GB[2 * k] = 2 * k, GB[2 * k + 1] = 2 * k + 1;
        }
        kin_assembly *g = make(3, 2 * NG, Z, NG, GB);
        if (g) {
            int found = 0, served = 0;
            for (int t = 0; t <= 60; ++t) {
                for (int i = 0; i < 6 * NG; ++i) Y[i] = Z[i] + 0.015 * t * V[i];
                unsigned long u0 = g->ct ? g->ct->vl_used : 0;
                check_against_all(g, Y, 0.1, GB, NULL, 0, 1.0);
                CHECK_RC(kin_clearance(g, Y, 0.1, &c, NULL, NULL), KIN_OK);
                served += g->ct->vl_used - u0 == 2, found += g->ct->vl_used - u0 == 2 && c < 0.1;
            }
            CHECK(served >= 20 && found >= 10); /* the list served, with pairs within the cutoff */
            kin_assembly_free(g);
        }
        free(Z), free(V), free(Y), free(GB);
    }

    /* a cutoff above the list's: 24 parallel bars in a row, 1 apart but
     * 0.5 between the 8th and 9th (the first leaf's 8 and the next); no
     * two are within 0.25, so a list made for 0.25 holds no two leaves; at
     * a cutoff of 2 the answer is that pair */
    enum { NR = 24 };
    double X[4 * NR * 3] = {0};
    int B[2 * NR];
    for (int k = 0; k < NR; ++k) {
        double x = k < 8 ? k : k - 0.5;
        X[6 * k] = x, X[6 * k + 1] = 0.0, X[6 * k + 3] = x, X[6 * k + 4] = 1.0;
        B[2 * k] = 2 * k, B[2 * k + 1] = 2 * k + 1;
    }
    kin_assembly *r = make(3, 2 * NR, X, NR, B);
    if (!r) return;
    int parts[4];
    for (int rep = 0; rep < 2; ++rep) {
        CHECK_RC(kin_clearance(r, NULL, 0.25, &c, parts, NULL), KIN_OK);
        CHECK(c == INFINITY);
    }
    CHECK(r->ct->vl_ok);
    CHECK_RC(kin_clearance(r, NULL, 2.0, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 0.5, TOL);
    CHECK(parts[1] == 7 && parts[3] == 8);
    kin_assembly_free(r);
}

static void errors(void)
{
    double x[] = {-1, 0, 0, 1, 0, 0, 0, -1, 1, 0, 1, 1};
    int b[] = {0, 1, 2, 3};
    kin_assembly *a = make(3, 4, x, 2, b);
    double c;
    int off[] = {0, 3}, pj[] = {0, 1, 2};
    CHECK_RC(kin_set_panels(NULL, 1, off, pj), KIN_ENULL);
    CHECK_RC(kin_set_panels(a, 1, NULL, pj), KIN_ENULL);
    CHECK_RC(kin_set_panels(a, -1, off, pj), KIN_EINVAL);
    int off_bad0[] = {1, 3};
    CHECK_RC(kin_set_panels(a, 1, off_bad0, pj), KIN_EINVAL);
    int off2[] = {0, 2};
    CHECK_RC(kin_set_panels(a, 1, off2, pj), KIN_EINVAL);
    int pj_rep[] = {0, 1, 0};
    CHECK_RC(kin_set_panels(a, 1, off, pj_rep), KIN_EINVAL);
    int pj_out[] = {0, 1, 9};
    CHECK_RC(kin_set_panels(a, 1, off, pj_out), KIN_EJOINT);
    CHECK(kin_npanels(a) == 0);
    CHECK(kin_npanels(NULL) == -1);
    CHECK(kin_has_contact_model(NULL) == -1);
    CHECK_RC(kin_get_panels(NULL, NULL, NULL), KIN_ENULL);
    CHECK_RC(kin_set_thickness(NULL, 0, NULL, NULL), KIN_ENULL);
    CHECK_RC(kin_set_thickness(a, -1.0, NULL, NULL), KIN_EGEOM);
    CHECK_RC(kin_set_thickness(a, NAN, NULL, NULL), KIN_EGEOM);
    double rb[2] = {INFINITY, 0};
    CHECK_RC(kin_set_thickness(a, 0.0, rb, NULL), KIN_EGEOM);
    CHECK_RC(kin_get_thickness(NULL, NULL, NULL, NULL), KIN_ENULL);
    CHECK_RC(kin_clearance(NULL, NULL, INFINITY, &c, NULL, NULL), KIN_ENULL);
    CHECK_RC(kin_clearance(a, NULL, INFINITY, NULL, NULL, NULL), KIN_ENULL);
    CHECK_RC(kin_clearance(a, NULL, NAN, &c, NULL, NULL), KIN_EINVAL);
    /* a cutoff: below the clearance (1) nothing is resolved; above, the same answer */
    int parts[4];
    CHECK_RC(kin_clearance(a, NULL, 0.5, &c, parts, NULL), KIN_OK);
    CHECK(isinf(c) && parts[0] == -1);
    CHECK_RC(kin_clearance(a, NULL, 1.5, &c, parts, NULL), KIN_OK);
    CHECK_CLOSE(c, 1.0, TOL);
    CHECK(parts[0] == KIN_PART_BAR);
    double xn[] = {-1, 0, 0, 1, 0, 0, 0, -1, NAN, 0, 1, 1};
    CHECK_RC(kin_clearance(a, xn, INFINITY, &c, NULL, NULL), KIN_EGEOM);
    /* after the failures the handle is unchanged: no panels, zero thickness */
    CHECK(kin_has_contact_model(a) == 0);
    CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, NULL, NULL), KIN_OK);
    CHECK_CLOSE(c, 1.0, TOL);
    kin_assembly_free(a);
}

/* the JSON model: panels, thickness and radii load, save and load back; every bad field is KIN_EFORMAT */
static void json_cases(void)
{
    const char *head = "{\"dimension\": 3, \"joints\": [{\"xyz\": [0,0,0]}, {\"xyz\": [1,0,0]}, {\"xyz\": [0,1,0]},"
                       " {\"xyz\": [0.2,0.2,-1]}, {\"xyz\": [0.2,0.2,1]}], \"bars\": [{\"joints\": [0,1]}, {\"joints\": [1,2]},"
                       " {\"joints\": [2,0]}, {\"joints\": [3,4]%s}]%s}";
    const char *good[2] = {", \"radius\": 0.002", ", \"thickness\": 0.01, \"panels\": [{\"joints\": [0,1,2], \"thickness\": 0.02}]"};
    char text[1024], err[512];
    snprintf(text, sizeof text, head, good[0], good[1]);
    kin_assembly *a = NULL, *b = NULL;
    CHECK_RC(kin_assembly_load_string(text, strlen(text), &a, err, sizeof err), KIN_OK);
    if (a) {
        double c, c2, t0, rb[4], tp[1];
        CHECK(kin_npanels(a) == 1);
        CHECK_RC(kin_get_thickness(a, &t0, rb, tp), KIN_OK);
        CHECK(t0 == 0.01 && rb[0] == 0.005 && rb[3] == 0.002 && tp[0] == 0.02);
        CHECK_RC(kin_clearance(a, NULL, INFINITY, &c, NULL, NULL), KIN_OK);
        CHECK_CLOSE(c, -0.012, TOL);
        char *out = NULL;
        size_t n = 0;
        CHECK_RC(kin_assembly_save_string(a, NULL, &out, &n, err, sizeof err), KIN_OK);
        CHECK_RC(kin_assembly_load_string(out, n, &b, err, sizeof err), KIN_OK);
        if (b) {
            CHECK_RC(kin_clearance(b, NULL, INFINITY, &c2, NULL, NULL), KIN_OK);
            CHECK(c2 == c && kin_npanels(b) == 1);
        }
        kin_free_string(out);
        kin_assembly_free(b);
    }
    kin_assembly_free(a);
    const char *bad[][2] = {
        {"", ", \"panels\": 3"},
        {"", ", \"panels\": [3]"},
        {"", ", \"panels\": [{\"joints\": [0,1]}]"},
        {"", ", \"panels\": [{\"joints\": [0,1,1]}]"},
        {"", ", \"panels\": [{\"joints\": [0,1,9]}]"},
        {"", ", \"panels\": [{\"joints\": [0,1,2.5]}]"},
        {"", ", \"panels\": [{\"joints\": [0,1,2], \"index\": 1}]"},
        {"", ", \"panels\": [{\"joints\": [0,1,2], \"thickness\": -1}]"},
        {"", ", \"thickness\": -0.5"},
        {"", ", \"thickness\": \"thick\""},
        {", \"radius\": -1", ""},
        {", \"radius\": true", ""},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        snprintf(text, sizeof text, head, bad[i][0], bad[i][1]);
        CHECK_RC(kin_assembly_load_string(text, strlen(text), &a, err, sizeof err), KIN_EFORMAT);
        CHECK(a == NULL);
    }
}

/* contact as an event of kin_follow_event: a parallelogram swings into a
 * fixed bar; the first contact is at 30 degrees, where joint 1 reaches x = -0.5 */
static void follow_cases(void)
{
    double x[] = {0, 0, 0, 1, 1, 1, 1, 0, -0.5, 0.5, -0.5, 2};
    unsigned char fixed[] = {1, 1, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
    int b[] = {0, 1, 1, 2, 2, 3, 4, 5};
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(2, 6, x, fixed, 4, b, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return;
    kin_assembly *off = NULL;
    CHECK_RC(kin_assembly_clone(a, &off), KIN_OK);
    double dir[] = {-1, 0, -1, 0}, c, pts[4], br;
    int parts[4];
    CHECK_RC(kin_last_contact(a, &c, parts, pts, &br), KIN_ESTATE);
    CHECK_RC(kin_set_contact_events(a, 1, 0.0), KIN_EINVAL);
    CHECK_RC(kin_set_contact_events(NULL, 1, 1e-9), KIN_ENULL);
    CHECK_RC(kin_set_contact_events(a, 1, 1e-9), KIN_OK);
    kin_follow_info info = {.size = sizeof info};
    CHECK_RC(kin_follow_event(a, dir, NULL, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT);
    /* the length to the located contact: two joints on unit circles, 30 degrees */
    CHECK(info.length <= sqrt(2.0) * acos(-1.0) / 6 && info.length >= sqrt(2.0) * acos(-1.0) / 6 * (1 - 2e-3));
    CHECK_RC(kin_last_contact(a, &c, parts, pts, &br), KIN_OK);
    CHECK(c <= 64 * DBL_EPSILON * 1.2 && br <= 1e-9 * 1.2);
    CHECK((parts[1] == 3 || parts[3] == 3) && parts[0] == KIN_PART_BAR && parts[2] == KIN_PART_BAR);
    double y[12];
    kin_get_coords(a, y);
    CHECK_CLOSE(y[2], -0.5, 1e-8);
    CHECK_CLOSE(y[3], sqrt(0.75), 1e-8);
    CHECK(kin_max_strain(a) < 1e-10);
    /* the same path without contact events runs on to its bifurcation (flat, at 90 degrees) */
    kin_follow_info info2 = {.size = sizeof info2};
    CHECK_RC(kin_follow_event(off, dir, NULL, &info2), KIN_OK);
    CHECK(info2.event == KIN_FOLLOW_BIFURCATION);
    CHECK_RC(kin_last_contact(off, &c, NULL, NULL, NULL), KIN_ESTATE);
    /* a follow that starts in contact is followed as before (no event) */
    kin_follow_info info3 = {.size = sizeof info3};
    CHECK_RC(kin_follow_event(a, dir, NULL, &info3), KIN_OK);
    CHECK(info3.event != KIN_FOLLOW_CONTACT);
    kin_assembly_free(off);
    kin_assembly_free(a);
}

/* two bare bars in 3D that pass through each other touch only at an
 * instant, between two steps: joint P swings on the circle x = 0, (y - 0)^2 +
 * (z - 1)^2 = 1 (bars to the fixed O1 = (-1, 0, 1) and O2 = (1, 0, 1)), and the
 * middle of bar O1-P passes through the fixed vertical bar x = -0.5, y = 0.3
 * where sin(theta) = 0.6: P = (0, 0.6, 0.2) */
static void crossing_cases(void)
{
    double x[] = {-1, 0, 1, 1, 0, 1, 0, 0, 0, -0.5, 0.3, -1, -0.5, 0.3, 2};
    unsigned char fixed[] = {1, 1, 1, 1, 1, 1, 0, 0, 0, 1, 1, 1, 1, 1, 1};
    int b[] = {0, 2, 1, 2, 3, 4};
    kin_assembly *a = NULL, *off = NULL;
    CHECK_RC(kin_assembly_create(3, 5, x, fixed, 3, b, NULL, &a, NULL, 0), KIN_OK);
    if (!a) return;
    CHECK_RC(kin_assembly_clone(a, &off), KIN_OK);
    double dir[] = {0, 1, 0}, c = NAN, pts[6], br = NAN, y[15];
    int parts[4] = {-1, -1, -1, -1};
    CHECK_RC(kin_set_contact_events(a, 1, 1e-9), KIN_OK);
    kin_follow_info info = {.size = sizeof info};
    CHECK_RC(kin_follow_event(a, dir, NULL, &info), KIN_OK);
    CHECK(info.event == KIN_FOLLOW_CONTACT);
    /* the length to the located contact (a sum of chords: a little short
     * of the arc theta = asin 0.6 of P's unit circle) */
    CHECK(info.length <= asin(0.6) && info.length >= asin(0.6) * (1 - 2e-3));
    CHECK_RC(kin_last_contact(a, &c, parts, pts, &br), KIN_OK);
    CHECK(parts[0] == KIN_PART_BAR && parts[2] == KIN_PART_BAR);
    CHECK((parts[1] == 0 && parts[3] == 2) || (parts[1] == 2 && parts[3] == 0));
    /* located to 1e-9 x the RMS bar length (sqrt(13/3)); the bars' distance
     * there is at most the bracket's (a joint moves at most as far) */
    double rms = sqrt(13.0 / 3.0);
    CHECK(br <= 1e-9 * rms && c >= 0.0 && c <= br);
    kin_get_coords(a, y);
    CHECK_CLOSE(y[7], 0.6, 1e-8);
    CHECK_CLOSE(y[8], 0.2, 1e-8);
    CHECK(kin_max_strain(a) < 1e-10);
    /* with a radius the same bars touch before they cross: where the distance
     * of O1-P's middle to the vertical bar is 2 r */
    CHECK_RC(kin_set_thickness(off, 0.02, NULL, NULL), KIN_OK);
    CHECK_RC(kin_set_contact_events(off, 1, 1e-9), KIN_OK);
    kin_follow_info info2 = {.size = sizeof info2};
    CHECK_RC(kin_follow_event(off, dir, NULL, &info2), KIN_OK);
    CHECK(info2.event == KIN_FOLLOW_CONTACT);
    CHECK_RC(kin_last_contact(off, &c, parts, pts, &br), KIN_OK);
    CHECK((parts[1] == 0 && parts[3] == 2) || (parts[1] == 2 && parts[3] == 0));
    CHECK(br <= 1e-9 * rms && c <= 64 * DBL_EPSILON * rms && c >= -2.0 * br);
    kin_get_coords(off, y);
    /* O1-P is 2 r = 0.02 from the vertical line: seen from above, the line
     * from (-1, 0) along (1, y) passes 0.02 from (-0.5, 0.3):
     * (0.3 - 0.5 y)^2 = 0.0004 (1 + y^2), the smaller root */
    double qa = 0.25 - 0.0004, qb = -0.3, qc = 0.09 - 0.0004;
    CHECK_CLOSE(y[7], (-qb - sqrt(qb * qb - 4 * qa * qc)) / (2 * qa), 1e-8);
    /* events off: the same follow passes through and goes on */
    CHECK_RC(kin_set_contact_events(off, 0, 1e-9), KIN_OK);
    CHECK_RC(kin_set_coords(off, x), KIN_OK);
    kin_follow_info info3 = {.size = sizeof info3};
    CHECK_RC(kin_follow_event(off, dir, NULL, &info3), KIN_OK);
    CHECK(info3.event != KIN_FOLLOW_CONTACT);
    kin_assembly_free(off);
    kin_assembly_free(a);
}

/* pairs tied up to rounding are named canonically: npairs pairs of
 * parallel bars at the same distance d, far apart along x; coordinates moved
 * by a few ulps (as another BLAS kernel or thread count moves a located
 * point) make another pair the exact minimum, and the pair named must be
 * the smallest, (0, 1), every time, with the clearance the exact minimum.
 * 2 pairs: the ties the walk keeps; 40: more than it keeps (KIN__TIES_MAX),
 * named by the second walk */
static void ties_named_canonically(int npairs)
{
    const double d = 0.3;
    int nj = 4 * npairs, nb = 2 * npairs;
    double *x0 = malloc(sizeof(double) * 3 * (size_t)nj), *x = malloc(sizeof(double) * 3 * (size_t)nj);
    int *b = malloc(sizeof(int) * 2 * (size_t)nb);
    for (int k = 0; k < npairs; ++k) {
        const double u[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 0, d}, {1, 0, d}};
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 3; ++i) x0[3 * (4 * k + j) + i] = u[j][i] + (i == 0 ? 5.0 * k : 0.0);
        b[4 * k] = 4 * k, b[4 * k + 1] = 4 * k + 1, b[4 * k + 2] = 4 * k + 2, b[4 * k + 3] = 4 * k + 3;
    }
    kin_assembly *a = make(3, nj, x0, nb, b);
    unsigned long long seed = 5;
    int other_exact = 0; /* trials where another pair is the exact minimum: the test is not void */
    for (int trial = 0; a && trial < 64; ++trial) {
        for (int i = 0; i < 3 * nj; ++i) {
            int k = (int)(kin__splitmix(&seed) % 5) - 2;
            x[i] = x0[i] + ldexp((double)k, -52) * fmax(fabs(x0[i]), 1.0);
        }
        double c, pts[6], m0 = INFINITY, mo = INFINITY;
        int parts[4];
        CHECK_RC(kin_clearance(a, x, INFINITY, &c, parts, pts), KIN_OK);
        /* the exact minimum of each pair (parallel bars: at an end) */
        for (int k = 0; k < npairs; ++k)
            for (int e = 0; e < 2; ++e)
                for (int f = 0; f < 2; ++f) {
                    const double *p = x + 3 * (4 * k + e), *q = x + 3 * (4 * k + 2 + f);
                    double dk = kin__dist_seg_seg(p, p, q, q, pts, pts + 3);
                    if (k == 0) m0 = fmin(m0, dk);
                    else mo = fmin(mo, dk);
                }
        other_exact += mo < m0;
        CHECK(parts[0] == KIN_PART_BAR && parts[1] == 0 && parts[2] == KIN_PART_BAR && parts[3] == 1);
        CHECK_CLOSE(c, fmin(m0, mo), 16 * DBL_EPSILON * 5.0 * npairs);
    }
    CHECK(other_exact > 0);
    kin_assembly_free(a);
    free(x0), free(x), free(b);
}

int main(void)
{
    ties_named_canonically(2);
    ties_named_canonically(40);
    crossing_cases();
    follow_cases();
    json_cases();
    bars_cases();
    panel_cases();
    triangle_cases();
    plane_cases();
    float_boxes();
    sail_vs_all_pairs();
    tree_independent_answers();
    sheet_vs_all_pairs();
    tilted_sheets_vs_all_pairs();
    near_list_cases();
    errors();
    TEST_REPORT("test_contact");
}
