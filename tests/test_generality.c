/* Any structure: frameworks the library used to refuse or misclassify.
 * Under-braced ones with more free coordinates than bars + 1 + rigid
 * motions (creation failed on a LAPACK workspace query), joints on one line
 * (a rotation about the line that moves no joint was counted as a rigid
 * mode), coplanar frameworks in 3D, over-braced ones with a dangling chain;
 * and stepping along a mechanism with two internal degrees of freedom. */
#include <string.h>

#include "check.h"
#include "libkin.h"

enum { MAXJ = 16, MAXB = 24 };

typedef struct expect {
    int rank, m_rigid, m_internal, s;
} expect;

/* Create, analyse and compare the counts; returns the handle (or NULL). */
static kin_assembly *make(const char *name, int dim, int nj, const double *xyz,
                          const unsigned char *fixed, int nb, const int *bars, expect want)
{
    kin_assembly *a = NULL;
    char err[256];
    int rc = kin_assembly_create(dim, nj, xyz, fixed, nb, bars, NULL, &a, err, sizeof err);
    if (rc != KIN_OK) {
        fprintf(stderr, "%s: create returned %s (%s)\n", name, kin_status_name(rc), err);
        ++check_failures_;
        return NULL;
    }
    kin_analysis an = {.size = sizeof an};
    rc = kin_analyse(a, &an);
    if (rc != KIN_OK) {
        fprintf(stderr, "%s: analyse returned %s (%s)\n", name, kin_status_name(rc), kin_last_error(a));
        ++check_failures_;
        kin_assembly_free(a);
        return NULL;
    }
    if (an.rank != want.rank || an.m_rigid != want.m_rigid || an.m_internal != want.m_internal ||
        an.s != want.s) {
        fprintf(stderr, "%s: rank %d m_rigid %d m_internal %d s %d, want %d %d %d %d\n", name, an.rank,
                an.m_rigid, an.m_internal, an.s, want.rank, want.m_rigid, want.m_internal, want.s);
        ++check_failures_;
    }
    CHECK(an.m == an.m_rigid + an.m_internal);
    CHECK(an.rank + an.m == kin_nfree(a));
    CHECK(an.rank + an.s == kin_nbars(a));
    return a;
}

static void check_counts(const char *name, int dim, int nj, const double *xyz,
                         const unsigned char *fixed, int nb, const int *bars, expect want)
{
    kin_assembly_free(make(name, dim, nj, xyz, fixed, nb, bars, want));
}

/* joints 0..nj-1 joined in a chain */
static void chain_bars(int nj, int *bars)
{
    for (int k = 0; k + 1 < nj; ++k) {
        bars[2 * k] = k;
        bars[2 * k + 1] = k + 1;
    }
}

/* a zig-zag of nj joints in the plane (no three on a line) */
static void zigzag(int dim, int nj, double *xyz)
{
    for (int j = 0; j < nj; ++j) {
        xyz[j * dim] = 1.0 * j + 0.1 * (j % 3);
        xyz[j * dim + 1] = (j % 2 ? 0.7 : 0.0) + 0.05 * j * j;
        if (dim == 3) xyz[j * dim + 2] = 0.3 * (j % 3) - 0.1 * j;
    }
}

static void under_braced(void)
{
    double xyz[MAXJ * 3];
    int bars[2 * MAXB];
    unsigned char fixed[MAXJ * 3];
    /* planar 4-bar open chain, no supports: 10 free coordinates, 4 bars */
    zigzag(2, 5, xyz);
    chain_bars(5, bars);
    check_counts("open 4-bar chain (2D)", 2, 5, xyz, NULL, 4, bars, (expect){4, 3, 3, 0});
    /* 6-joint chain pinned at one end: the whole chain turning about the
     * pin is a rigid mode; 2D and 3D */
    for (int dim = 2; dim <= 3; ++dim) {
        zigzag(dim, 6, xyz);
        chain_bars(6, bars);
        memset(fixed, 0, sizeof fixed);
        for (int k = 0; k < dim; ++k) fixed[k] = 1;
        /* 3D: the rotations about the three axes through the pin */
        expect want = dim == 2 ? (expect){5, 1, 4, 0} : (expect){5, 3, 7, 0};
        check_counts(dim == 2 ? "chain pinned at one end (2D)" : "chain pinned at one end (3D)", dim, 6,
                     xyz, fixed, 5, bars, want);
    }
    /* three free joints and one bar: the third joint moves on its own */
    zigzag(2, 3, xyz);
    const int one_bar[2] = {0, 1};
    check_counts("3 joints, 1 bar (2D)", 2, 3, xyz, NULL, 1, one_bar, (expect){1, 3, 2, 0});
    zigzag(3, 3, xyz);
    check_counts("3 joints, 1 bar (3D)", 3, 3, xyz, NULL, 1, one_bar, (expect){1, 6, 2, 0});
}

/* p = origin + u * dir: points on a skew line */
static void on_line(int dim, int nj, const double *origin, const double *dir, const double *u, double *xyz)
{
    for (int j = 0; j < nj; ++j)
        for (int k = 0; k < dim; ++k) xyz[j * dim + k] = origin[k] + u[j] * dir[k];
}

static void collinear(void)
{
    const double o[3] = {0.3, -0.2, 0.5}, d[3] = {0.267, 0.534, 0.802}, u[5] = {0.0, 1.1, 1.9, 3.2, 4.0};
    double xyz[15];
    int bars[8];
    unsigned char fixed[9] = {1, 1, 1, 0, 0, 0, 1, 1, 1};
    /* three joints on a skew line, the end ones pinned: the rotation about
     * the line moves nothing, so there is no rigid mode; joint 1 can move in
     * the two directions normal to the line (one self-stress) */
    on_line(3, 3, o, d, u, xyz);
    chain_bars(3, bars);
    check_counts("skew-line chain, ends pinned (3D)", 3, 3, xyz, fixed, 2, bars, (expect){1, 0, 2, 1});
    /* the same chain free: 3 translations and 2 rotations; the middle joint's
     * two normal motions are internal */
    check_counts("skew-line chain, free (3D)", 3, 3, xyz, NULL, 2, bars, (expect){2, 5, 2, 0});
    /* a collinear 4-bar chain in the plane: 10 free coordinates */
    on_line(2, 5, o, d, u, xyz);
    chain_bars(5, bars);
    check_counts("collinear 4-bar chain (2D)", 2, 5, xyz, NULL, 4, bars, (expect){4, 3, 3, 0});
}

/* Joints a tiny distance off a line that carries the supports (3D): the
 * rotation about the line moves them by that distance. Where the rank counts
 * the offset (the counts equal the clearly non-collinear ones), that rotation
 * is a rigid mode, not an internal mechanism: one tolerance decides both. */
static void near_line(void)
{
    const double o[3] = {0.3, -0.2, 0.5}, d[3] = {0.267, 0.534, 0.802};
    /* two unit normals of d */
    const double n1[3] = {0.894427190999916, -0.447213595499958, 0.0};
    double n2[3] = {d[1] * n1[2] - d[2] * n1[1], d[2] * n1[0] - d[0] * n1[2], d[0] * n1[1] - d[1] * n1[0]};
    double nn = sqrt(n2[0] * n2[0] + n2[1] * n2[1] + n2[2] * n2[2]);
    for (int k = 0; k < 3; ++k) n2[k] /= nn;
    const double u[5] = {0.0, 1.0, 2.1, 2.9, 4.0};
    const double c1[5] = {0.0, 1.0, -0.6, 0.8, 0.0}, c2[5] = {0.0, 0.3, 0.9, -0.5, 0.0};
    const int bars[14] = {0, 1, 1, 2, 2, 3, 3, 4, 0, 2, 1, 3, 2, 4};
    unsigned char fixed[15] = {0};
    for (int k = 0; k < 3; ++k) fixed[k] = fixed[12 + k] = 1;
    /* relative offsets: clearly off the line, then inside the window where
     * the rank counts the offset and the rigid test used to drop the
     * rotation (4e-9 .. 1.5e-8 of the size); then far below what the rank
     * resolves, where the joints are on the line and the rotation no motion */
    const double eps[6] = {1e-3, 4e-9, 6e-9, 1e-8, 1.5e-8, 1e-14};
    const double size = 4.0;
    expect clear = {0, 0, 0, 0};
    for (int e = 0; e < 6; ++e) {
        double xyz[15];
        for (int j = 0; j < 5; ++j)
            for (int k = 0; k < 3; ++k)
                xyz[j * 3 + k] = o[k] + u[j] * d[k] / 1.0 + eps[e] * size * (c1[j] * n1[k] + c2[j] * n2[k]);
        char err[256];
        kin_assembly *a = NULL;
        CHECK_RC(kin_assembly_create(3, 5, xyz, fixed, 7, bars, NULL, &a, err, sizeof err), KIN_OK);
        if (!a) return;
        kin_analysis an = {.size = sizeof an};
        CHECK_RC(kin_analyse(a, &an), KIN_OK);
        if (e == 0) {
            clear = (expect){an.rank, an.m_rigid, an.m_internal, an.s};
            CHECK(an.m_rigid == 1); /* the rotation about the line */
        } else if (an.rank == clear.rank) {
            if (an.m_rigid != clear.m_rigid || an.m_internal != clear.m_internal)
                fprintf(stderr, "near line, offset %.3g: rank %d m_rigid %d m_internal %d, want %d %d %d\n",
                        eps[e], an.rank, an.m_rigid, an.m_internal, clear.rank, clear.m_rigid,
                        clear.m_internal);
            CHECK(an.m_rigid == clear.m_rigid && an.m_internal == clear.m_internal);
        } else {
            CHECK(e == 5); /* inside the window the rank counts the offset */
            CHECK(an.m_rigid == 0);
        }
        kin_assembly_free(a);
    }
}

/* x = origin + a*e1 + b*e2: points of the plane spanned by e1, e2 */
static void coplanar_3d(void)
{
    const double o[3] = {0.2, 0.1, -0.4};
    const double e1[3] = {0.6, 0.0, 0.8}, e2[3] = {0.48, 0.6, -0.36};
    const double ab[8] = {0.0, 0.0, 1.0, 0.1, 1.2, 0.9, 0.1, 1.1};
    double xyz[12];
    for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 3; ++k) xyz[j * 3 + k] = o[k] + ab[2 * j] * e1[k] + ab[2 * j + 1] * e2[k];
    /* a quadrilateral in a tilted plane: 12 free coordinates, 4 bars; the
     * in-plane four-bar motion and one out-of-plane fold are internal */
    const int quad[8] = {0, 1, 1, 2, 2, 3, 3, 0};
    check_counts("coplanar quadrilateral (3D)", 3, 4, xyz, NULL, 4, quad, (expect){4, 6, 2, 0});
    /* with a diagonal: two triangles folding about it */
    const int braced[10] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2};
    check_counts("coplanar braced quadrilateral (3D)", 3, 4, xyz, NULL, 5, braced, (expect){5, 6, 1, 0});
}

static void over_braced(void)
{
    /* a fully braced quadrilateral (one self-stress) with a 4-bar chain
     * hanging from it, no supports: 16 free coordinates, 10 bars */
    double xyz[16];
    zigzag(2, 8, xyz);
    const int bars[20] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2, 1, 3, 3, 4, 4, 5, 5, 6, 6, 7};
    check_counts("braced quadrilateral with a chain (2D)", 2, 8, xyz, NULL, 10, bars, (expect){9, 3, 4, 1});
    /* the braced quadrilateral alone, pinned and on a roller: rigid */
    unsigned char fixed[8] = {1, 1, 0, 1, 0, 0, 0, 0};
    check_counts("braced quadrilateral, supported (2D)", 2, 4, xyz, fixed, 6, bars, (expect){5, 0, 0, 1});
}

/* ---- stepping along a 2-DOF mechanism ---------------------------------- */

/* P v / |P v| for P the projection on the columns of U (nf x m, ld nf) */
static void project_unit(int nf, const double *U, int m, const double *v, double *out)
{
    double n2 = 0.0;
    for (int i = 0; i < nf; ++i) out[i] = 0.0;
    for (int c = 0; c < m; ++c) {
        double p = 0.0;
        for (int i = 0; i < nf; ++i) p += U[i + c * nf] * v[i];
        for (int i = 0; i < nf; ++i) out[i] += p * U[i + c * nf];
    }
    for (int i = 0; i < nf; ++i) n2 += out[i] * out[i];
    for (int i = 0; i < nf; ++i) out[i] /= sqrt(n2);
}

/* A planar open chain of three bars pinned at joint 0: m_internal = 2 (the
 * chain turning about the pin is the rigid mode), no self-stress. */
static void two_dof_chain(int factorization)
{
    double xyz[8];
    zigzag(2, 4, xyz);
    int bars[6];
    chain_bars(4, bars);
    unsigned char fixed[8] = {1, 1, 0, 0, 0, 0, 0, 0};
    kin_assembly *a = make("2-DOF chain", 2, 4, xyz, fixed, 3, bars, (expect){3, 1, 2, 0});
    if (!a) return;
    kin_options o;
    kin_options_default(&o);
    o.factorization = factorization;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    enum { NF = 6 };
    double t[NF], t0[NF], want[NF], U[NF * 2], L0[3], L[3];
    kin_get_rest_lengths(a, L0);
    /* without a direction the step is refused, with the reason */
    CHECK_RC(kin_step(a, 0.0, NULL), KIN_EMULTIDOF);
    CHECK_RC(kin_get_tangent(a, t, NF), KIN_EMULTIDOF);
    /* a direction: the last joint moving normal to the last bar */
    double dir[NF] = {0, 0, 0, 0, -(xyz[7] - xyz[5]), xyz[6] - xyz[4]};
    CHECK_RC(kin_path_set_direction(a, dir, NF), KIN_OK);
    CHECK_RC(kin_get_tangent(a, t, NF), KIN_OK);
    kin_step_info info = {.size = sizeof info};
    for (int k = 0; k < 12; ++k) {
        CHECK_RC(kin_get_tangent(a, t0, NF), KIN_OK);
        int rc = kin_step(a, 0.05, &info);
        CHECK_RC(rc, KIN_OK);
        if (rc != KIN_OK) break;
        CHECK(info.m_internal == 2);
        CHECK(kin_max_strain(a) <= 1e-12);
        kin_get_lengths(a, L);
        for (int b = 0; b < 3; ++b) CHECK_CLOSE(L[b], L0[b], 1e-11 * L0[b]);
        /* the new tangent is the previous one projected on the new point's
         * internal mechanisms (an analysis is current in both modes: every
         * multi-DOF point is analysed by SVD) */
        kin_analysis an = {.size = sizeof an};
        CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
        CHECK(an.m_internal == 2 && an.m_rigid == 1);
        CHECK_RC(kin_get_mechanisms(a, KIN_MECH_INTERNAL, U, NF, 2), KIN_OK);
        project_unit(NF, U, 2, t0, want);
        CHECK_RC(kin_get_tangent(a, t, NF), KIN_OK);
        for (int i = 0; i < NF; ++i) CHECK_CLOSE(t[i], want[i], 64 * DBL_EPSILON);
    }
    CHECK_CLOSE(kin_path_length(a), 0.6, 0.01);
    /* the pin does not move */
    kin_get_coords(a, xyz);
    CHECK(xyz[0] == 0.0 && xyz[1] == 0.0);
    /* backwards along the same continuation */
    CHECK_RC(kin_step(a, -0.05, &info), KIN_OK);
    CHECK(kin_path_length(a) < 0.6);
    /* forgetting the path forgets the direction */
    CHECK_RC(kin_path_reset(a), KIN_OK);
    CHECK_RC(kin_step(a, 0.0, NULL), KIN_EMULTIDOF);
    kin_assembly_free(a);
}

/* a multi-DOF point with a self-stress is refused as a possible
 * bifurcation: the first-order analysis cannot tell the two apart */
static void multidof_with_self_stress(void)
{
    double xyz[16];
    zigzag(2, 8, xyz);
    const int bars[20] = {0, 1, 1, 2, 2, 3, 3, 0, 0, 2, 1, 3, 3, 4, 4, 5, 5, 6, 6, 7};
    kin_assembly *a = make("braced + chain", 2, 8, xyz, NULL, 10, bars, (expect){9, 3, 4, 1});
    if (!a) return;
    CHECK_RC(kin_step(a, 0.0, NULL), KIN_EBIFURCATION);
    kin_assembly_free(a);
}

/* The supports' rank is remembered between analyses (mechanism_split.c)
 * only while the rank test could not tell otherwise: two pins 1e-5 apart
 * hold every rigid motion of a unit-sized structure, but with the free
 * joints 1e6 away the rotation about the pins moves them by less than the
 * rank test resolves. The same handle, analysed there after the first
 * configuration, must count what a new handle counts. */
static void remembered_supports(void)
{
    const double near[] = {0.0, 0.0, 1e-5, 0.0, 0.3, 0.9, 0.8, 1.1};
    const double far[] = {0.0, 0.0, 1e-5, 0.0, 0.3e6, 0.9e6, 0.8e6, 1.1e6};
    const unsigned char fixed[] = {1, 1, 1, 1, 0, 0, 0, 0};
    const int bars[] = {0, 2, 2, 3, 3, 1};
    kin_assembly *a = NULL, *b = NULL;
    kin_analysis an = {.size = sizeof an}, bn = {.size = sizeof bn};
    CHECK(kin_assembly_create(2, 4, near, fixed, 3, bars, NULL, &a, NULL, 0) == KIN_OK);
    CHECK(kin_assembly_create(2, 4, far, fixed, 3, bars, NULL, &b, NULL, 0) == KIN_OK);
    if (!a || !b) goto out;
    CHECK(kin_analyse(a, &an) == KIN_OK);
    CHECK(an.m_rigid == 0);
    CHECK(kin_set_coords(a, far) == KIN_OK);
    CHECK(kin_analyse(a, &an) == KIN_OK);
    CHECK(kin_analyse(b, &bn) == KIN_OK);
    CHECK(an.m_rigid == bn.m_rigid && an.m_internal == bn.m_internal && an.rank == bn.rank);
    CHECK(bn.m_rigid == 1); /* the case the remembered rank must not hide */
out:
    kin_assembly_free(a);
    kin_assembly_free(b);
}

int main(void)
{
    remembered_supports();
    under_braced();
    collinear();
    near_line();
    coplanar_3d();
    over_braced();
    two_dof_chain(KIN_STEP_SVD);
    two_dof_chain(KIN_STEP_LU);
    multidof_with_self_stress();
    TEST_REPORT("test_generality");
}
