/* The sparse mode's bordering (libkin/path/sparse.c): KLU factorizes J0, J with
 * its dense border rows replaced by unit stand-in rows, and the true J is
 * applied by a Sherman-Morrison-Woodbury correction. Checked: on a slender
 * mast the factors of J0 have far fewer entries than J's with the dense row
 * (linear fill); stand-ins made bad on purpose (a coordinate the mechanism
 * does not move: J0 singular; one it barely moves: Z grows; rigid-body rows
 * on coordinates that cannot see all six rigid motions) are re-chosen and
 * the steps give the dense LU mode's points; an ill-conditioned capacitance
 * (fault hook) takes the dense-row route with the same points; the test
 * hook's invalid inputs. No timing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "path/path.h"
#include "libkin.h"
#include "sail_states.h"
#include "mast_model.h"
#include "step_compare.h"

/* the triangular mast of mast_model.h (one internal mechanism, one dense
 * border row) */
static kin_assembly *mast(int nbays)
{
    kin_assembly *a = test_mast(3, nbays, NULL);
    CHECK(a != NULL);
    return a;
}

/* The free-floating chain of tetrahedra of test_step_sparse.c (one bar
 * taken out: one internal and six rigid mechanisms, seven border rows) */
static kin_assembly *tetra_chain(int nj, unsigned long long seed)
{
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nj);
    int *bars = malloc(sizeof(int) * 2 * 3 * (size_t)nj), nb = 0;
    for (int i = 0; i < 3 * nj; ++i) xyz[i] = (double)(kin__splitmix(&seed) >> 11) * 0x1.0p-53;
    int skip = 3 * (nj / 2);
    for (int j = 1; j < nj; ++j)
        for (int b = 1; b <= 3 && j - b >= 0; ++b) {
            if (nb == skip) {
                skip = -1;
                continue;
            }
            bars[2 * nb] = j - b;
            bars[2 * nb + 1] = j;
            ++nb;
        }
    kin_assembly *a = NULL;
    CHECK_RC(kin_assembly_create(3, nj, xyz, NULL, nb, bars, NULL, &a, NULL, 0), KIN_OK);
    free(xyz);
    free(bars);
    kin_analysis an = {.size = sizeof an};
    CHECK(a && kin_analyse(a, &an) == KIN_OK && an.m_internal == 1 && an.m_rigid == 6 && kin_nfree(a) == kin_nbars(a) + 7);
    return a;
}

static void set_mode(kin_assembly *a, int mode)
{
    kin_options o = {.size = sizeof o};
    kin_get_options(a, &o);
    o.factorization = mode;
    o.step_control = KIN_STEP_CONTROL_SHARED;
    CHECK_RC(kin_set_options(a, &o), KIN_OK);
}

/* Follow a in sparse mode and a clone in dense LU mode for `steps` steps,
 * after `prepare` (may be NULL) has spoilt the sparse handle's stand-ins
 * (or set a fault): the same points to the corrector tolerance carried
 * along the path. Returns the sparse handle's re-choices; *dense_points
 * the points it factorized with the dense rows. */
static long follow_both(const kin_assembly *a, int steps, const int *standins, int fault, long *dense_points)
{
    kin_assembly *h[2] = {NULL, NULL};
    for (int m = 0; m < 2; ++m) {
        CHECK_RC(kin_assembly_clone(a, &h[m]), KIN_OK);
        if (!h[m]) return -1;
        set_mode(h[m], m ? KIN_STEP_SPARSE : KIN_STEP_LU);
    }
    if (standins) CHECK_RC(kin__sparse_set_standins(h[1], standins), KIN_OK);
    kin__set_fault(h[1], fault);
    int n = kin_njoints(a) * kin_dim(a);
    double *x = malloc(sizeof(double) * 2 * (size_t)n), worst = 0.0;
    for (int k = 0; k < steps; ++k) {
        kin_step_info info = {.size = sizeof info};
        for (int m = 0; m < 2; ++m) {
            CHECK_RC(kin_step(h[m], 0.0, &info), KIN_OK);
            kin_get_coords(h[m], x + (size_t)m * n);
        }
        worst = fmax(worst, max_diff(n, x, x + n));
        CHECK(max_diff(n, x, x + n) <= path_tol(a, k + 1));
        CHECK(kin_max_strain(h[1]) <= a->opt.corrector_tol);
    }
    double e = 0.0, ed = 0.0;
    long rechoices = 0;
    kin__sparse_stats(h[1], &e, &ed, &rechoices, dense_points);
    printf("  %d steps: max |x_sparse - x_LU| %.1e (allowed %.1e), %ld re-choices, %ld dense-row points\n", steps,
           worst, path_tol(a, steps), rechoices, *dense_points);
    free(x);
    for (int m = 0; m < 2; ++m) kin_assembly_free(h[m]);
    return rechoices;
}

/* linear fill on a mast: J0 against J with its dense row */
static void mast_fill(void)
{
    kin_assembly *a = mast(60);
    CHECK(a != NULL);
    if (!a) return;
    set_mode(a, KIN_STEP_SPARSE);
    double e = 0.0, ed = 0.0;
    long rc = -1, dp = -1;
    kin__sparse_stats(a, &e, &ed, &rc, &dp);
    int nf = kin_nfree(a);
    printf("mast, %d free coordinates: factor entries %.0f with stand-in rows, %.0f with the dense row\n", nf, e, ed);
    CHECK(e <= 16.0 * nf); /* measured 12-13 per column at every size */
    CHECK(e * 3.0 < ed);
    CHECK(rc == 0 && dp == 0);
    kin_assembly_free(a);
}

/* index of the free coordinate whose |t| relative to max |t| lies in
 * (lo, hi], the smallest such ratio; -1 if none */
static int coordinate_moving(const kin_assembly *a, double lo, double hi)
{
    kin_assembly *c = NULL;
    CHECK_RC(kin_assembly_clone(a, &c), KIN_OK);
    int nf = kin_nfree(a), best = -1;
    double *t = malloc(sizeof(double) * (size_t)nf), tmax = 0.0;
    kin_analysis an = {.size = sizeof an};
    CHECK_RC(kin_analyse(c, &an), KIN_OK);
    CHECK_RC(kin_get_tangent(c, t, nf), KIN_OK);
    for (int i = 0; i < nf; ++i) tmax = fmax(tmax, fabs(t[i]));
    for (int i = 0; i < nf; ++i) {
        double q = fabs(t[i]) / tmax;
        if (q > lo && q <= hi && (best < 0 || q < fabs(t[best]) / tmax)) best = i;
    }
    free(t);
    kin_assembly_free(c);
    return best;
}

/* stand-ins made bad on purpose are re-chosen; the points stay right */
static void rechoice(void)
{
    kin_assembly *a = mast(12);
    CHECK(a != NULL);
    if (!a) return;
    long dp = 0;
    /* untouched: no re-choice, no dense-row point */
    printf("mast, %d free coordinates, stand-in as chosen:\n", kin_nfree(a));
    CHECK(follow_both(a, 6, NULL, KIN__FAULT_NONE, &dp) == 0 && dp == 0);
    /* a coordinate the mechanism does not move (the joints below the slack
     * bay): J0 is singular, the point is solved with the dense row and the
     * stand-in re-chosen from its null space */
    int still = coordinate_moving(a, -1.0, 1e-14);
    CHECK(still >= 0);
    printf("stand-in at a coordinate the mechanism does not move:\n");
    if (still >= 0) CHECK(follow_both(a, 6, &still, KIN__FAULT_NONE, &dp) >= 1);
    /* every capacitance judged ill-conditioned: each point with the dense row */
    printf("capacitance always rejected (fault hook):\n");
    CHECK(follow_both(a, 4, NULL, KIN__FAULT_SPARSE_CAPACITANCE, &dp) == 0 && dp >= 4);
    kin_assembly_free(a);
    /* a coordinate the mechanism barely moves (on the generic hexagonal
     * sail): J0 regular but Z's entries large: re-chosen from Z */
    kin_assembly *g = test_sail(6, 2);
    CHECK(g != NULL && test_make_generic(g, 0.3) == KIN_OK);
    if (!g) return;
    int slow = coordinate_moving(g, 1e-10, 1e-3);
    CHECK(slow >= 0);
    printf("hexagonal sail, stand-in at a coordinate the mechanism barely moves:\n");
    if (slow >= 0) CHECK(follow_both(g, 6, &slow, KIN__FAULT_NONE, &dp) >= 1);
    kin_assembly_free(g);
    /* seven border rows on stand-ins that are all x coordinates: the
     * y and z translations and rotations are invisible there (J0 singular) */
    kin_assembly *b = tetra_chain(12, 42);
    CHECK(b != NULL);
    if (!b) return;
    int xs[7];
    for (int r = 0; r < 7; ++r) xs[r] = 3 * (r + 2);
    printf("free-floating chain, seven stand-ins on x coordinates:\n");
    CHECK(follow_both(b, 8, xs, KIN__FAULT_NONE, &dp) >= 1);
    printf("free-floating chain, stand-ins as chosen:\n");
    CHECK(follow_both(b, 8, NULL, KIN__FAULT_NONE, &dp) == 0 && dp == 0);
    kin_assembly_free(b);
}

/* the test hook's own checks */
static void hook_errors(void)
{
    kin_assembly *a = mast(4);
    CHECK(a != NULL);
    if (!a) return;
    int k = 0;
    CHECK_RC(kin__sparse_set_standins(a, &k), KIN_ESTATE); /* not in sparse mode yet */
    set_mode(a, KIN_STEP_SPARSE);
    k = -1;
    CHECK_RC(kin__sparse_set_standins(a, &k), KIN_EINVAL);
    k = kin_nfree(a);
    CHECK_RC(kin__sparse_set_standins(a, &k), KIN_EINVAL);
    kin_assembly_free(a);
    kin_assembly *b = tetra_chain(8, 3);
    CHECK(b != NULL);
    if (!b) return;
    set_mode(b, KIN_STEP_SPARSE);
    int twice[7] = {0, 1, 2, 3, 4, 5, 0};
    CHECK_RC(kin__sparse_set_standins(b, twice), KIN_EINVAL);
    double e = 0.0, ed = 0.0;
    long rc = -1, dp = -1;
    kin__sparse_stats(NULL, &e, &ed, &rc, &dp);
    CHECK(e == INFINITY && ed == INFINITY && rc == 0 && dp == 0);
    kin_assembly_free(b);
}

int main(void)
{
    (void)threebar_at;
    mast_fill();
    rechoice();
    hook_errors();
    TEST_REPORT("test_sparse_border");
}
