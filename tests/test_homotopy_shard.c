/* The complete solver in shards: ranges of paths tracked separately and
 * merged give exactly the result of one call (kin_quadrics_homotopy_range,
 * kin_quadrics_homotopy_merge in kin_branch.h). */
#include <limits.h>
#include <math.h>
#include <string.h>

#include "check.h"
#include "libkin.h"
#include "sail_states.h"

/* random symmetric Gaussian matrices from a small deterministic generator */
static void random_q(int m, int s, unsigned long long st, double *Q)
{
    for (int j = 0; j < s; ++j)
        for (int r = 0; r < m; ++r)
            for (int c = r; c < m; ++c) {
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                double u = ((st >> 11) + 0.5) * 0x1.0p-53;
                st = st * 6364136223846793005ull + 1442695040888963407ull;
                double v = ((st >> 11) + 0.5) * 0x1.0p-53;
                Q[j * m * m + r + c * m] = Q[j * m * m + c + r * m] = sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
            }
}

/* One call against three uneven ranges + merge, root by root. */
static void compare(const char *name, int m, int s, const double *Q, unsigned long seed)
{
    long n = 1L << s;
    int maxsol = (int)n;
    double *b1 = malloc(sizeof(double) * m * n), *b2 = malloc(sizeof(double) * m * n);
    double *z = malloc(sizeof(double) * 2 * m * n);
    int *m1 = malloc(sizeof(int) * n), *m2 = malloc(sizeof(int) * n), n1 = 0, n2 = 0;
    kin_homotopy_endpoint *ends = calloc((size_t)n, sizeof *ends);
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.seed = seed;
    o.nthreads = 1;
    kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
    CHECK_RC(kin_quadrics_homotopy_ex(m, s, Q, &o, b1, maxsol, &n1, m1, &h1), KIN_OK);
    /* uneven ranges, the middle one on 2 threads */
    long cut[4] = {0, n / 7 + 1, n - n / 3, n};
    if (cut[1] >= cut[2]) cut[1] = cut[2] - 1 > 0 ? cut[2] - 1 : 1;
    for (int r = 0; r < 3; ++r) {
        if (cut[r + 1] <= cut[r]) continue;
        ends[cut[r]].size = sizeof *ends;
        o.nthreads = r == 1 ? 2 : 1;
        CHECK_RC(kin_quadrics_homotopy_range(m, s, Q, &o, cut[r], cut[r + 1] - cut[r], ends + cut[r],
                                             z + 2 * m * cut[r]),
                 KIN_OK);
    }
    int ok_paths = 1;
    for (long p = 0; p < n; ++p) ok_paths &= ends[p].path == p && ends[p].size == KIN_HOMOTOPY_ENDPOINT_SIZE;
    CHECK(ok_paths);
    o.nthreads = 2;
    CHECK_RC(kin_quadrics_homotopy_merge(m, s, Q, &o, ends, z, b2, maxsol, &n2, m2, &h2), KIN_OK);
    printf("%-16s s = %2d: %d real (%d distinct), %d complex, %d singular, %d failed, %d re-tracked; "
           "sharded == one call: %s\n",
           name, s, h1.real, h1.real_distinct, h1.nonreal, h1.singular, h1.failed, h1.retracked,
           n1 == n2 && !memcmp(&h1, &h2, sizeof h1) ? "yes" : "NO");
    CHECK(n1 == n2 && memcmp(&h1, &h2, sizeof h1) == 0);
    CHECK(memcmp(b1, b2, sizeof(double) * m * n1) == 0 && memcmp(m1, m2, sizeof(int) * n1) == 0);
    CHECK(h1.real + h1.nonreal + h1.singular + h1.failed == h1.paths && h1.paths == n);
    /* counts from the records alone match the first pass of the accounting */
    int real = 0;
    for (long p = 0; p < n; ++p) real += ends[p].kind == KIN_HOM_END_REAL;
    CHECK(h1.retracked > 0 || real == h1.real);
    free(b1), free(b2), free(z), free(m1), free(m2), free(ends);
}

static void random_systems(void)
{
    for (int s = 8; s <= 9; ++s) {
        int m = s + 1;
        double *Q = malloc(sizeof(double) * m * m * s);
        random_q(m, s, 77 + s, Q);
        compare("random", m, s, Q, 3);
        free(Q);
    }
}

/* the hexagonal sail's R^B and R^C (reached from R^B with kin_follow_event) */
static void hex_states(void)
{
    kin_assembly *a = test_sail(6, 2);
    CHECK(a != NULL && test_hex_to_RB(a) == KIN_OK);
    kin_analysis an = {.size = sizeof an};
    double Q[6 * 6 * 5], betas[6 * 32], dir[46];
    int s = 0, nsol = 0;
    CHECK_RC(kin_analyse(a, &an), KIN_OK);
    CHECK_RC(kin_second_order(a, KIN_Q_EXACT, 1, Q, 4 * 4 * 3, &s), KIN_OK);
    compare("hex sail R^B", an.m_internal, s, Q, 1);
    kin_homotopy_info hi = {.size = sizeof hi};
    CHECK_RC(kin_quadrics_homotopy(4, 3, Q, 1, 1, betas, 8, &nsol, NULL, &hi), KIN_OK);
    int found = 0;
    for (int k = 0; k < 2 * nsol && !found; ++k) {
        double beta[4];
        for (int i = 0; i < 4; ++i) beta[i] = (k % 2 ? -1.0 : 1.0) * betas[4 * (k / 2) + i];
        test_mechanism(a, beta, 4, dir);
        kin_assembly *b = NULL;
        CHECK_RC(kin_assembly_clone(a, &b), KIN_OK);
        kin_follow_info fi = {.size = sizeof fi};
        if (kin_follow_event(b, dir, NULL, &fi) == KIN_OK && fi.event == KIN_FOLLOW_BIFURCATION && fi.m_internal == 6) {
            found = 1;
            CHECK_RC(kin_analyse(b, &an), KIN_OK);
            CHECK(an.m_internal == 6);
            CHECK_RC(kin_second_order(b, KIN_Q_EXACT, 1, Q, 6 * 6 * 5, &s), KIN_OK);
            compare("hex sail R^C", 6, s, Q, 1);
        }
        kin_assembly_free(b);
    }
    CHECK(found);
    kin_assembly_free(a);
}

static int cancel_now(void *user, double done, double total)
{
    (void)user, (void)done, (void)total;
    return 1;
}

static void errors(void)
{
    enum { M = 4, S = 3, N = 8 };
    double Q[M * M * S], z[2 * M * N], b[M * N];
    int nsol = 7;
    random_q(M, S, 5, Q);
    kin_homotopy_endpoint ends[N];
    memset(ends, 0, sizeof ends);
    ends[0].size = sizeof ends[0];
    CHECK(sizeof ends[0] == KIN_HOMOTOPY_ENDPOINT_SIZE);
    CHECK_RC(kin_quadrics_homotopy_range(M, S, NULL, NULL, 0, N, ends, z), KIN_ENULL);
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, NULL, 0, N + 1, ends, z), KIN_ERANGE);
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, NULL, -1, 2, ends, z), KIN_ERANGE);
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, NULL, 3, 0, ends, z), KIN_ERANGE);
    CHECK_RC(kin_quadrics_homotopy_range(M, S + 1, Q, NULL, 0, N, ends, z), KIN_EINVAL);
    CHECK_RC(kin_quadrics_homotopy_range(30, 29, Q, NULL, 0, N, ends, z), KIN_ERANGE);
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.max_paths = 4;
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, &o, 0, N, ends, z), KIN_ELIMIT);
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, &o, 4, 4, ends, z), KIN_OK); /* the limit is per range */
    kin_homotopy_options_default(&o);
    o.progress = cancel_now;
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, &o, 0, N, ends, z), KIN_ECANCELLED);
    CHECK(ends[0].size == KIN_HOMOTOPY_ENDPOINT_SIZE && ends[0].path == 0 && ends[1].path == 0);
    ends[0].size = 8;
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, NULL, 0, N, ends, z), KIN_EINVAL);
    ends[0].size = sizeof ends[0];
    Q[5] = NAN;
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, NULL, 0, N, ends, z), KIN_EINVAL);
    random_q(M, S, 5, Q);
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, NULL, 0, N, ends, z), KIN_OK);
    kin_homotopy_info h = {.size = sizeof h};
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h), KIN_OK);
    CHECK(h.paths == N);
    /* records out of order, a bad class, a bad chart, a wrong size */
    kin_homotopy_endpoint keep = ends[3];
    ends[3].path = 4;
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h), KIN_EINVAL);
    CHECK(nsol == 0 && h.paths == 0);
    ends[3] = keep;
    ends[3].kind = 9;
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h), KIN_EINVAL);
    ends[3] = keep;
    ends[3].chart = M;
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h), KIN_EINVAL);
    ends[3] = keep;
    ends[0].size = 0;
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h), KIN_EINVAL);
    ends[0].size = sizeof ends[0];
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, NULL, z, b, N, &nsol, NULL, &h), KIN_ENULL);
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, 0, &nsol, NULL, &h), KIN_EINVAL);
    ends[3].rplus = 0.0; /* a certified root without its uniqueness ball */
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h),
             keep.kind == KIN_HOM_END_REAL || keep.kind == KIN_HOM_END_NONREAL ? KIN_EINVAL : KIN_OK);
    ends[3] = keep;
    o.progress = cancel_now;
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, &o, ends, z, b, N, &nsol, NULL, &h), KIN_ECANCELLED);
    /* the zeroed records of a cancelled range are refused */
    kin_homotopy_options_default(&o);
    o.progress = cancel_now;
    CHECK_RC(kin_quadrics_homotopy_range(M, S, Q, &o, 0, N, ends, z), KIN_ECANCELLED);
    CHECK_RC(kin_quadrics_homotopy_merge(M, S, Q, NULL, ends, z, b, N, &nsol, NULL, &h), KIN_EINVAL);
    CHECK(nsol == 0 && h.paths == 0);
}

/* Records are checked against the Q they are merged with: a range of
 * another system's records (a shard from another job) is tracked again,
 * never counted as certified roots of this one; a record with z = 0, or
 * with counters no tracker makes, is refused; the 64-bit step totals are
 * the records' sums and the int counters agree with them. */
static void verified_records(void)
{
    enum { VM = 7, VS = 6, VN = 1 << VS };
    double Q[VS * VM * VM], Q2[VS * VM * VM], b1[VN * VM], b2[VN * VM], z[2 * VM * VN];
    kin_homotopy_endpoint ends[VN];
    int n1 = 0, n2 = 0;
    random_q(VM, VS, 11, Q);
    random_q(VM, VS, 12, Q2);
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = 1;
    kin_homotopy_info h1 = {.size = sizeof h1}, h2 = {.size = sizeof h2};
    CHECK_RC(kin_quadrics_homotopy_ex(VM, VS, Q, &o, b1, VN, &n1, NULL, &h1), KIN_OK);
    /* the first half of the paths tracked for Q, the second for Q2 */
    ends[0].size = ends[VN / 2].size = sizeof ends[0];
    CHECK_RC(kin_quadrics_homotopy_range(VM, VS, Q, &o, 0, VN / 2, ends, z), KIN_OK);
    CHECK_RC(kin_quadrics_homotopy_range(VM, VS, Q2, &o, VN / 2, VN / 2, ends + VN / 2, z + VM * VN), KIN_OK);
    int foreign = 0;
    for (int p = VN / 2; p < VN; ++p)
        foreign += ends[p].kind == KIN_HOM_END_REAL || ends[p].kind == KIN_HOM_END_NONREAL;
    CHECK_RC(kin_quadrics_homotopy_merge(VM, VS, Q, &o, ends, z, b2, VN, &n2, NULL, &h2), KIN_OK);
    printf("a shard of another system: %d certified records of it, %d failed the check, %d paths re-tracked; "
           "result == one call: %s\n", foreign, h2.rechecks_failed, h2.retracked,
           n1 == n2 && h1.real == h2.real && h1.nonreal == h2.nonreal ? "yes" : "NO");
    CHECK(foreign > 0 && h2.rechecks_failed == foreign && h2.retracked >= foreign);
    CHECK(n1 == n2 && h1.real == h2.real && h1.real_distinct == h2.real_distinct && h1.nonreal == h2.nonreal &&
          h1.singular == h2.singular && h1.failed == h2.failed);
    double diff = 0.0;
    for (int i = 0; i < n1 * VM && n1 == n2; ++i) diff = fmax(diff, fabs(b1[i] - b2[i]));
    CHECK(diff <= 1e-10);
    /* every record of Q: nothing fails the check; the totals are the sums */
    CHECK_RC(kin_quadrics_homotopy_range(VM, VS, Q, &o, 0, VN, ends, z), KIN_OK);
    long long st = 0, rj = 0;
    for (int p = 0; p < VN; ++p) st += ends[p].steps, rj += ends[p].rejected;
    CHECK_RC(kin_quadrics_homotopy_merge(VM, VS, Q, &o, ends, z, b2, VN, &n2, NULL, &h2), KIN_OK);
    CHECK(h2.rechecks_failed == 0 && h2.retracked == 0 && h2.steps_total == st && h2.rejected_total == rj);
    CHECK(h2.steps == (int)h2.steps_total && h2.rejected == (int)h2.rejected_total);
    /* z = 0 on a certified record, and counters no tracker makes, are refused */
    int c = 0;
    while (c < VN && ends[c].kind != KIN_HOM_END_REAL) ++c;
    CHECK(c < VN);
    double keepz[2 * VM];
    memcpy(keepz, z + 2 * VM * c, sizeof keepz);
    memset(z + 2 * VM * c, 0, sizeof keepz);
    CHECK_RC(kin_quadrics_homotopy_merge(VM, VS, Q, &o, ends, z, b2, VN, &n2, NULL, &h2), KIN_EINVAL);
    memcpy(z + 2 * VM * c, keepz, sizeof keepz);
    kin_homotopy_endpoint keep = ends[1];
    ends[1].steps = INT_MAX;
    CHECK_RC(kin_quadrics_homotopy_merge(VM, VS, Q, &o, ends, z, b2, VN, &n2, NULL, &h2), KIN_EINVAL);
    ends[1].steps = keep.steps, ends[1].rejected = -1;
    CHECK_RC(kin_quadrics_homotopy_merge(VM, VS, Q, &o, ends, z, b2, VN, &n2, NULL, &h2), KIN_EINVAL);
    ends[1] = keep;
    CHECK_RC(kin_quadrics_homotopy_merge(VM, VS, Q, &o, ends, z, b2, VN, &n2, NULL, &h2), KIN_OK);
}

int main(void)
{
    errors();
    random_systems();
    verified_records();
    hex_states();
    TEST_REPORT("test_homotopy_shard");
}
