/* kin_analyse in the sparse mode (KIN_STEP_SPARSE: model/analysis_sparse.c,
 * no dense SVD) against the dense SVD analysis (KIN_STEP_SVD) of the same
 * configuration: the counts equal, v_max and v_r close, the mechanism,
 * rigid, internal and self-stress subspaces equal to principal-angle
 * tolerance; and its error paths.
 *
 * Tolerances. Both analyses are backward stable: each is exact for an H
 * perturbed by a few eps v_max (the dense SVD by construction; the sparse
 * one's Ritz values are computed from products with H itself, on subspaces
 * that the KLU solves make exact for a nearby augmented matrix). So
 *  - v_max and v_r differ by at most c eps v_max;
 *  - an invariant subspace moves by (perturbation) / (gap): the null spaces
 *    by c eps v_max / v_r, so the sine of their largest principal angle is
 *    checked against c eps v_max / v_r (rigid and internal subspaces, split
 *    by the same code from the two null spaces, likewise).
 * c = 128: measured at most 7.4 (v_max), 0.9 (v_r) and 5.5 (sines) on the
 * models below (printed), so the room is 17x for the sqrt(n) growth of
 * rounding on other BLAS and sizes; the Lanczos stop (GKL_TOL = 1e-12 of
 * v_max as a residual bound) allows more for v_max only in principle, the
 * largest Ritz value converging quadratically in it. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "lattice_model.h"
#include "libkin.h"
#include "mast_model.h"
#include "model/internal.h"
#include "sail_states.h"

static const double C_ROUND = 128.0;

static void set_mode(kin_assembly *a, int mode, double rank_tol)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = mode;
    if (rank_tol > 0) o.rank_tol = rank_tol;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
    /* the sparse analysis itself, not the dense route it hands over to
     * where that is cheaper (test_sparse_limits) */
    kin__set_fault(a, mode == KIN_STEP_SPARSE ? KIN__FAULT_DENSE_UNAFFORDABLE : KIN__FAULT_NONE);
}

/* sine of the largest principal angle between span(A) and span(B) (n x k,
 * orthonormal), bounded above by the Frobenius norm of B - A A^T B */
static double subspace_sine(int n, int k, const double *A, const double *B)
{
    double sum = 0.0;
    double *c = malloc(sizeof(double) * (size_t)k), *r = malloc(sizeof(double) * (size_t)n);
    for (int j = 0; j < k; ++j) {
        const double *b = B + (size_t)j * n;
        for (int i = 0; i < k; ++i) {
            double s = 0.0;
            for (int q = 0; q < n; ++q) s += A[q + (size_t)i * n] * b[q];
            c[i] = s;
        }
        for (int q = 0; q < n; ++q) {
            double s = b[q];
            for (int i = 0; i < k; ++i) s -= A[q + (size_t)i * n] * c[i];
            sum += s * s;
        }
    }
    free(c);
    free(r);
    return sqrt(sum);
}

/* orthonormality defect max |Q^T Q - I| */
static double ortho_defect(int n, int k, const double *Q)
{
    double e = 0.0;
    for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
            double s = 0.0;
            for (int q = 0; q < n; ++q) s += Q[q + (size_t)i * n] * Q[q + (size_t)j * n];
            e = fmax(e, fabs(s - (i == j)));
        }
    return e;
}

static double *basis(kin_assembly *a, int kind, int rows, int cols)
{
    double *U = calloc((size_t)rows * (size_t)(cols > 0 ? cols : 1), sizeof *U);
    if (kind < 0) CHECK_RC(kin_get_self_stresses(a, U, rows, cols), KIN_OK);
    else CHECK_RC(kin_get_mechanisms(a, kind, U, rows, cols), KIN_OK);
    return U;
}

/* the sparse and the dense analysis of a's configuration; returns the
 * sparse one's counts in *out */
static void compare(const char *name, const kin_assembly *a, double rank_tol, kin_analysis *out)
{
    kin_assembly *d = NULL, *s = NULL;
    CHECK_RC(kin_assembly_clone(a, &d), KIN_OK);
    CHECK_RC(kin_assembly_clone(a, &s), KIN_OK);
    if (!d || !s) return;
    set_mode(d, KIN_STEP_SVD, rank_tol);
    set_mode(s, KIN_STEP_SPARSE, rank_tol);
    kin_analysis ad = {.size = sizeof ad}, as = {.size = sizeof as}, ag = {.size = sizeof ag};
    CHECK_RC(kin_analyse(d, &ad), KIN_OK);
    CHECK_RC(kin_analyse(s, &as), KIN_OK);
    CHECK(s->H == NULL); /* no dense workspace was made */
    CHECK_RC(kin_get_analysis(s, &ag), KIN_OK);
    CHECK(memcmp(&ag, &as, sizeof ag) == 0);
    CHECK(as.rank == ad.rank && as.m == ad.m && as.m_rigid == ad.m_rigid && as.m_internal == ad.m_internal &&
          as.s == ad.s);
    double tv = C_ROUND * DBL_EPSILON * ad.v_max;
    CHECK_CLOSE(as.v_max, ad.v_max, tv);
    /* v_r: the sparse analysis's Rayleigh quotient on its null-space block
     * against the dense SVD: each backward stable, to a few eps ||H||
     * times the square root of the block's size (the braced K12, 36
     * self-stresses: 162 eps v_max under OpenBLAS's Haswell and Zen kernels) */
    int nblk = as.s > as.m ? as.s : as.m;
    CHECK_CLOSE(as.v_r, ad.v_r, tv * fmax(1.0, sqrt((double)nblk)));
    int nf = kin_nfree(a), nb = kin_nbars(a);
    double ta = ad.v_r > 0 ? C_ROUND * DBL_EPSILON * ad.v_max / ad.v_r : 0.0, worst = 0.0;
    int kinds[4] = {KIN_MECH_ALL, KIN_MECH_RIGID, KIN_MECH_INTERNAL, -1};
    int cols[4] = {ad.m, ad.m_rigid, ad.m_internal, ad.s};
    for (int k = 0; k < 4 && as.m == ad.m && as.s == ad.s && as.m_rigid == ad.m_rigid; ++k) {
        int rows = kinds[k] < 0 ? nb : nf;
        double *Bd = basis(d, kinds[k], rows, cols[k]), *Bs = basis(s, kinds[k], rows, cols[k]);
        double sine = subspace_sine(rows, cols[k], Bd, Bs);
        worst = fmax(worst, sine);
        CHECK(sine <= ta);
        CHECK(ortho_defect(rows, cols[k], Bs) <= 64 * DBL_EPSILON * sqrt((double)rows));
        if (sine > ta) fprintf(stderr, "%s: kind %d: sine %.3g > %.3g\n", name, kinds[k], sine, ta);
        free(Bd);
        free(Bs);
    }
    printf("test_analysis_sparse: %-22s nf %5d nb %5d rank %5d m %3d (rigid %d, internal %d) s %4d  "
           "v_r/v_max %.3e  |dv_max| %.1e |dv_r| %.1e (eps v_max)  sine %.1e (eps v_max/v_r)\n",
           name, nf, nb, as.rank, as.m, as.m_rigid, as.m_internal, as.s, ad.v_r / ad.v_max,
           fabs(as.v_max - ad.v_max) / (DBL_EPSILON * ad.v_max), fabs(as.v_r - ad.v_r) / (DBL_EPSILON * ad.v_max),
           ad.v_r > 0 ? worst / (DBL_EPSILON * ad.v_max / ad.v_r) : 0.0);
    if (out) *out = as;
    kin_assembly_free(d);
    kin_assembly_free(s);
}

/* every joint of n braced to every other (3D, no supports): s = n(n-1)/2 - (3n - 6) */
static kin_assembly *complete_graph(int n)
{
    double *xyz = malloc(sizeof(double) * 3 * (size_t)n);
    int nb = n * (n - 1) / 2, *bars = malloc(sizeof(int) * 2 * (size_t)nb), k = 0;
    unsigned long long seed = 7;
    for (int i = 0; i < 3 * n; ++i) xyz[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53;
    for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j) {
            bars[2 * k] = i;
            bars[2 * k + 1] = j;
            ++k;
        }
    kin_assembly *a = NULL;
    if (kin_assembly_create(3, n, xyz, NULL, nb, bars, NULL, &a, NULL, 0) != KIN_OK) a = NULL;
    free(xyz);
    free(bars);
    return a;
}

static void models(void)
{
    kin_analysis an = {.size = sizeof an};
    for (int st = 0; st < 3; ++st) {
        kin_assembly *a = NULL;
        CHECK_RC(kin_model_threebar(st, &a), KIN_OK);
        char name[32];
        snprintf(name, sizeof name, "threebar state %d", st);
        if (a) compare(name, a, 0, NULL);
        kin_assembly_free(a);
    }
    int sails[][2] = {{4, 2}, {6, 2}, {6, 4}, {8, 3}};
    for (size_t k = 0; k < sizeof sails / sizeof sails[0]; ++k) {
        kin_assembly *a = test_sail(sails[k][0], sails[k][1]);
        CHECK(a != NULL);
        char name[32];
        snprintf(name, sizeof name, "sail %d:%d", sails[k][0], sails[k][1]);
        if (a) compare(name, a, 0, NULL);
        kin_assembly_free(a);
    }
    /* the hexagonal sail at R^B (paper section 6): a bifurcation, m_internal >= 2, s > 0 */
    kin_assembly *h = test_sail(6, 2);
    CHECK(h && test_hex_to_RB(h) == KIN_OK);
    if (h) compare("hexagonal sail at R^B", h, 0, &an);
    CHECK(an.m_internal >= 2 && an.s > 0);
    kin_assembly_free(h);
    /* masts of a few hundred joints (rank_tol 1e-11, as the masts need) */
    int masts[][2] = {{3, 100}, {4, 80}, {6, 50}};
    for (size_t k = 0; k < sizeof masts / sizeof masts[0]; ++k) {
        kin_assembly *a = test_mast(masts[k][0], masts[k][1], NULL);
        CHECK(a != NULL);
        char name[32];
        snprintf(name, sizeof name, "mast %dx%d", masts[k][0], masts[k][1]);
        if (a) compare(name, a, 1e-11, NULL);
        kin_assembly_free(a);
    }
    kin_assembly *l = lattice(5, 5, 5);
    CHECK(l != NULL);
    if (l) compare("fcc lattice 5^3", l, 0, NULL);
    kin_assembly_free(l);
    /* many self-stresses: a braced complete graph */
    kin_assembly *c = complete_graph(12);
    CHECK(c != NULL);
    if (c) compare("complete graph K12", c, 0, &an);
    CHECK(an.s == 66 - 30);
    kin_assembly_free(c);
}

static int cancel_at(void *user, double done, double total)
{
    (void)total;
    return done >= *(double *)user;
}

static void errors(void)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL);
    if (!a) return;
    set_mode(a, KIN_STEP_SPARSE, 0);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(NULL, &an), KIN_ENULL);
    kin_analysis bad = {.size = 3};
    CHECK_RC(kin_analyse(a, &bad), KIN_EINVAL);
    CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE); /* nothing analysed yet */
    CHECK_RC(kin_analyse(a, NULL), KIN_OK);
    CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
    int nf = kin_nfree(a), nb = kin_nbars(a), mn = nf < nb ? nf : nb;
    double *sv = malloc(sizeof(double) * (size_t)mn), *U = malloc(sizeof(double) * (size_t)nf * (size_t)nf);
    /* the sparse analysis has no full spectrum: a clear state error, not made-up values */
    CHECK_RC(kin_get_singular_values(a, sv, mn), KIN_ESTATE);
    CHECK(strlen(kin_last_error(a)) > 0);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, U, nf, an.m - 1), KIN_ERANGE);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, U, nf - 1, an.m), KIN_ERANGE);
    CHECK_RC(kin_get_mechanisms(a, 7, U, nf, nf), KIN_EINVAL);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, NULL, nf, nf), KIN_ENULL);
    CHECK_RC(kin_get_self_stresses(a, U, nb - 1, nb), an.s > 0 ? KIN_ERANGE : KIN_OK);
    /* a new rank tolerance, or a new configuration: the analysis is stale */
    set_mode(a, KIN_STEP_SPARSE, 1e-7);
    CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE);
    CHECK_RC(kin_get_mechanisms(a, KIN_MECH_ALL, U, nf, nf), KIN_ESTATE);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    double *xyz = malloc(sizeof(double) * 3 * (size_t)kin_njoints(a));
    kin_get_coords(a, xyz);
    for (int j = 0; j < kin_njoints(a); ++j)
        if (kin_free_index(a, j, 2) >= 0) {
            xyz[3 * j + 2] += 1e-3;
            break;
        }
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK);
    CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK_RC(kin_set_coords(a, xyz), KIN_OK); /* the same coordinates: still a new configuration (kin_set_coords) */
    CHECK_RC(kin_get_analysis(a, &an), KIN_ESTATE);
    CHECK_RC(kin_get_self_stresses(a, U, nb, nb), KIN_ESTATE);
    /* cancel before and after the factorization: the previous analysis kept */
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    kin_analysis before = an;
    for (int k = 0; k < 2; ++k) {
        double at = k;
        CHECK_RC(kin_set_progress(a, cancel_at, &at), KIN_OK);
        CHECK_RC(kin_analyse(a, &an), KIN_ECANCELLED);
        CHECK_RC(kin_set_progress(a, NULL, NULL), KIN_OK);
        CHECK_RC(kin_get_analysis(a, &an), KIN_OK);
        CHECK(an.rank == before.rank && an.v_r == before.v_r);
    }
    /* a later dense analysis of the point takes over (and has the spectrum) */
    set_mode(a, KIN_STEP_SVD, 1e-7);
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK_RC(kin_get_singular_values(a, sv, mn), KIN_OK);
    CHECK_CLOSE(sv[0], an.v_max, 0.0);
    /* a rank decision no iteration can make: rank_tol put exactly at a
     * singular value's ratio to v_max */
    int k = an.rank > 2 ? an.rank - 2 : 0;
    double tol = sv[k] / sv[0];
    set_mode(a, KIN_STEP_SPARSE, tol);
    int rc = kin_analyse(a, &an);
    CHECK(rc == KIN_ENOTCONVERGED);
    if (rc != KIN_ENOTCONVERGED) fprintf(stderr, "undecidable rank: %s\n", kin_status_name(rc));
    kin_assembly_free(a);
    /* the same where the block is not the whole space: rank_tol at v_r / v_max of a mast */
    kin_assembly *ma = test_mast(3, 100, NULL);
    CHECK(ma != NULL);
    if (ma) {
        set_mode(ma, KIN_STEP_SVD, 1e-11);
        CHECK_RC(kin_analyse(ma, &an), KIN_OK);
        set_mode(ma, KIN_STEP_SPARSE, an.v_r / an.v_max);
        rc = kin_analyse(ma, &an);
        CHECK(rc == KIN_ENOTCONVERGED);
        if (rc != KIN_ENOTCONVERGED) fprintf(stderr, "undecidable rank (mast): %s\n", kin_status_name(rc));
    }
    kin_assembly_free(ma);
    /* more self-stresses than the sparse analysis keeps: a clear limit */
    kin_assembly *c = complete_graph(50);
    CHECK(c != NULL);
    if (c) {
        set_mode(c, KIN_STEP_SPARSE, 0);
        CHECK_RC(kin_analyse(c, &an), KIN_ELIMIT);
        CHECK(strlen(kin_last_error(c)) > 0);
    }
    kin_assembly_free(c);
    free(sv);
    free(U);
    free(xyz);
}

/* what consumes an analysis, after a sparse one: the second order (from
 * its bases: test_sparse_limits compares it with the dense one's), a
 * direction (the path layer makes its own dense analysis on a model this
 * small) */
static void consumers(void)
{
    kin_assembly *h = test_sail(6, 2);
    CHECK(h && test_hex_to_RB(h) == KIN_OK);
    if (!h) return;
    set_mode(h, KIN_STEP_SPARSE, 0);
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(h, &an), KIN_OK);
    CHECK(an.m_internal >= 2 && an.s >= 1);
    int nf = kin_nfree(h), s = 0;
    double *Q = malloc(sizeof(double) * (size_t)an.m_internal * an.m_internal * an.s);
    double *U = malloc(sizeof(double) * (size_t)nf * an.m_internal);
    CHECK_RC(kin_second_order(h, KIN_Q_EXACT, 1, Q, an.m_internal * an.m_internal * an.s, &s), KIN_OK);
    CHECK(s >= 1 && s <= an.s);
    CHECK_RC(kin_get_mechanisms(h, KIN_MECH_INTERNAL, U, nf, an.m_internal), KIN_OK);
    kin__set_fault(h, KIN__FAULT_NONE); /* the dense workspace may be made */
    CHECK_RC(kin_path_set_direction(h, U, nf), KIN_OK);
    set_mode(h, KIN_STEP_SVD, 0);
    CHECK_RC(kin_analyse(h, &an), KIN_OK);
    CHECK_RC(kin_second_order(h, KIN_Q_EXACT, 1, Q, an.m_internal * an.m_internal * an.s, &s), KIN_OK);
    CHECK(s == an.s);
    free(Q);
    free(U);
    kin_assembly_free(h);
}

int main(void)
{
    models();
    errors();
    consumers();
    TEST_REPORT("test_analysis_sparse");
}
