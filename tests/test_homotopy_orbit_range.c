/* The complete solver with symmetry in shards: kin_quadrics_equivariant_form,
 * kin_quadrics_homotopy_orbit_range over ranges of orbits, and the plain
 * merge on the form, against the one call kin_quadrics_homotopy_sym on the
 * flat state of the hexagonal sail with one loop (C3: 176 orbits of 512
 * paths); a group that does not qualify; every error path. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "root_match.h"
#include "sail_states.h"

enum { MAXG = 6 };

static int cancel_now(void *user, double done, double total)
{
    (void)done, (void)total;
    ++*(int *)user;
    return 1;
}

/* the real solutions x of the form back to beta = U x, unit, largest entry positive */
static void to_beta(int m, const double *U, double *b, int n)
{
    for (int i = 0; i < n; ++i) {
        double y[32] = {0}, ny = 0.0;
        int big = 0;
        for (int r = 0; r < m; ++r) {
            y[r] = 0.0;
            for (int c = 0; c < m; ++c) y[r] += U[c * m + r] * b[i * m + c];
            ny += y[r] * y[r];
        }
        for (int r = 0; r < m; ++r)
            if (fabs(y[r]) > fabs(y[big])) big = r;
        double sc = (y[big] < 0 ? -1.0 : 1.0) / sqrt(ny);
        for (int r = 0; r < m; ++r) b[i * m + r] = sc * y[r];
    }
}

int main(void)
{
    kin_assembly *a = test_sail(6, 1);
    kin_analysis an = {.size = sizeof an};
    CHECK(a && kin_analyse(a, &an) == KIN_OK);
    int m = an.m_internal, s = 0, ng = 0, N = 1 << (m - 1);
    size_t mm = (size_t)m * m;
    double *Q = malloc(sizeof(double) * mm * an.s), *R = malloc(sizeof(double) * MAXG * mm);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, (int)mm * an.s, &s), KIN_OK);
    CHECK_RC(kin_mechanism_group(a, MAXG, R, &ng), KIN_OK);
    CHECK(m == 10 && s == 9 && ng == 6);
    double *Qt = malloc(sizeof(double) * mm * s), U[100];
    int perm[10], order = -1;
    long norbits = -1;
    char err[256];

    /* the form: C3 on three triples, (512 - 8) / 3 + 8 orbits */
    CHECK_RC(kin_quadrics_equivariant_form(m, s, Q, ng, R, 1, Qt, U, perm, &order, &norbits, err, sizeof err),
             KIN_OK);
    CHECK(order == 3 && norbits == 176 && perm[0] == 0);

    /* three shards of orbits, in a shuffled order; every path once */
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.seed = 1, o.nthreads = 2;
    kin_homotopy_endpoint *all = calloc((size_t)N, sizeof *all), *part = calloc((size_t)3 * 100, sizeof *part);
    double *zall = malloc(sizeof(double) * 2 * m * N), *zpart = malloc(sizeof(double) * 2 * m * 300);
    int *seen = calloc((size_t)N, sizeof(int)), covered = 1;
    long cuts[4] = {0, 50, 120, 176};
    int order3[3] = {2, 0, 1};
    for (int k = 0; k < 3; ++k) {
        int sh = order3[k];
        long n = cuts[sh + 1] - cuts[sh], got = -1;
        part[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE;
        CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, cuts[sh], n, 3 * n, part, zpart, &got),
                 KIN_OK);
        CHECK(got >= n && got <= 3 * n);
        for (long i = 0; i < got; ++i) {
            int p = part[i].path;
            if (p < 0 || p >= N || seen[p]++) {
                covered = 0;
                continue;
            }
            all[p] = part[i];
            memcpy(zall + (size_t)2 * m * p, zpart + (size_t)2 * m * i, sizeof(double) * 2 * m);
        }
    }
    for (int p = 0; p < N; ++p) covered &= seen[p] == 1;
    CHECK(covered);

    /* the merge on the form against the one call */
    double *b0 = malloc(sizeof(double) * m * N), *b1 = malloc(sizeof(double) * m * N);
    int n0 = 0, n1 = 0;
    kin_homotopy_info h0 = {.size = sizeof h0}, h1 = {.size = sizeof h1};
    kin_homotopy_sym_info si = {.size = sizeof si};
    CHECK_RC(kin_quadrics_homotopy_sym(m, s, Q, ng, R, &o, b0, N, &n0, NULL, &h0, &si, err, sizeof err), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy_merge(m, s, Qt, &o, all, zall, b1, N, &n1, NULL, &h1), KIN_OK);
    to_beta(m, U, b1, n1);
    printf("shards: real %d/%d nonreal %d/%d singular %d/%d failed %d dup %d unpaired %d; one call: %d orbits\n",
           h1.real, h0.real, h1.nonreal, h0.nonreal, h1.singular, h0.singular, h1.failed, h1.duplicates,
           h1.unpaired, si.orbits);
    CHECK(si.orbits == 176 && si.monodromy_paths == 0);
    CHECK(h1.paths == N && h1.real == h0.real && h1.nonreal == h0.nonreal && h1.singular == h0.singular);
    CHECK(h1.failed == 0 && h1.duplicates == 0 && h1.unpaired == 0 && n1 == n0);
    CHECK(unmatched_roots(m, n0, b0, b1, 1e-9) == 0 && unmatched_roots(m, n1, b1, b0, 1e-9) == 0);

    /* errors */
    long got = -1;
    part[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE;
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, NULL, perm, &o, 0, 1, 3, part, zpart, &got), KIN_ENULL);
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, NULL, &o, 0, 1, 3, part, zpart, &got), KIN_ENULL);
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 1, 3, part, zpart, NULL), KIN_ENULL);
    part[0].size = 8;
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 1, 3, part, zpart, &got), KIN_EINVAL);
    part[0].size = KIN_HOMOTOPY_ENDPOINT_SIZE;
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s + 1, Qt, perm, &o, 0, 1, 3, part, zpart, &got), KIN_EINVAL);
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 1, 0, part, zpart, &got), KIN_EINVAL);
    {
        int bad[10];
        memcpy(bad, perm, sizeof bad);
        bad[0] = perm[1], bad[1] = 0; /* moves x_0 */
        CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, bad, &o, 0, 1, 3, part, zpart, &got), KIN_EINVAL);
        bad[0] = 0, bad[1] = perm[2]; /* not a permutation */
        CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, bad, &o, 0, 1, 3, part, zpart, &got), KIN_EINVAL);
        double keep = Qt[5];
        Qt[5] += 1e-6; /* no longer equivariant */
        CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 1, 3, part, zpart, &got), KIN_EINVAL);
        Qt[5] = NAN;
        CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 1, 3, part, zpart, &got), KIN_EINVAL);
        Qt[5] = keep;
    }
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 170, 10, 30, part, zpart, &got), KIN_ERANGE);
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, -1, 1, 3, part, zpart, &got), KIN_ERANGE);
    /* room for fewer members than the orbits have: the count needed */
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 100, 100, part, zpart, &got), KIN_ERANGE);
    CHECK(got > 100 && got <= 300);
    o.max_paths = 5;
    CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &o, 0, 10, 30, part, zpart, &got), KIN_ELIMIT);
    o.max_paths = KIN_HOMOTOPY_MAX_PATHS;
    {
        int calls = 0;
        kin_homotopy_options oc = o;
        oc.progress = cancel_now, oc.user = &calls;
        part[3].kind = 7;
        CHECK_RC(kin_quadrics_homotopy_orbit_range(m, s, Qt, perm, &oc, 0, 10, 30, part, zpart, &got),
                 KIN_ECANCELLED);
        CHECK(calls == 1 && got == 0 && part[3].kind == 0 && part[3].size == KIN_HOMOTOPY_ENDPOINT_SIZE);
    }
    /* form: NULLs, a bad group, and a group no subgroup of which qualifies
     * (the rotations alone by 120 degrees, without their powers, are not a
     * group: refused; the identity alone: order 0) */
    CHECK_RC(kin_quadrics_equivariant_form(m, s, NULL, ng, R, 1, Qt, U, perm, &order, &norbits, err, sizeof err),
             KIN_ENULL);
    CHECK_RC(kin_quadrics_equivariant_form(m, s, Q, ng, R, 1, Qt, U, perm, NULL, &norbits, NULL, 0), KIN_ENULL);
    CHECK_RC(kin_quadrics_equivariant_form(m, s + 1, Q, ng, R, 1, Qt, U, perm, &order, &norbits, err, sizeof err),
             KIN_EINVAL);
    CHECK_RC(kin_quadrics_equivariant_form(m, s, Q, 1, R + 2 * mm, 1, Qt, U, perm, &order, &norbits, err,
                                           sizeof err),
             KIN_EINVAL);
    CHECK(order == 0 && norbits == 0);
    CHECK_RC(kin_quadrics_equivariant_form(m, s, Q, 0, NULL, 1, Qt, U, perm, &order, &norbits, err, sizeof err),
             KIN_OK);
    CHECK(order == 0 && norbits == 0);
    CHECK_RC(kin_quadrics_equivariant_form(30, 29, Q, 0, NULL, 1, Qt, U, perm, &order, &norbits, err, sizeof err),
             KIN_ERANGE);

    free(b0), free(b1), free(seen), free(zall), free(zpart), free(all), free(part), free(Qt), free(Q), free(R);
    kin_assembly_free(a);
    TEST_REPORT("test_homotopy_orbit_range");
}
