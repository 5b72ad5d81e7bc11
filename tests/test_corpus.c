/* Property-based corpus: thousands of random frameworks (seeded, the same on
 * every run) from several families -- chains and rings, random graphs from
 * under- to over-braced, near-complete graphs, joints on one line, joints
 * on one plane in 3D -- with no supports, pinned joints or random
 * per-coordinate supports, each checked by invariants that hold whatever
 * the numerics:
 *  - creation and analysis succeed; r + m = nfree, r + s = nbars,
 *    m = m_rigid + m_internal;
 *  - |H^T u| <= sqrt(m) rank_tol v_max for every mechanism, |H w| likewise
 *    for every self-stress; each set orthonormal;
 *  - every rigid mechanism is an infinitesimal rigid motion t + w x X of
 *    the whole assembly that keeps every support fixed (a least-squares
 *    fit over all coordinates, the fixed ones being zero); internal ones
 *    are orthogonal to them; and m_rigid = rank(G) - rank(G_fixed), G the
 *    rigid motion fields of all coordinates and G_fixed its fixed rows;
 *  - rank, counts and singular values unchanged by a relabelling of joints
 *    and bars (with bar ends swapped), by a translation, and by a rotation
 *    where no support breaks the symmetry (no supports, or only fully
 *    pinned joints, which rotate with the rest);
 *  - a step from the framework (SVD and LU modes) ends in a documented
 *    status: KIN_ENOMECH without internal mechanism, KIN_EMULTIDOF /
 *    KIN_EBIFURCATION with several and no direction (EMULTIDOF where every
 *    self-stress is a bar's between fixed joints, s = s_trivial), and with a direction
 *    KIN_OK (strain within tolerance) or a reported failure (not converged,
 *    path jump, no mechanism where the attempts got to); never a LAPACK
 *    error; KIN_OK from every regular point (no self-stress).
 * Rank decisions depend on the geometry only where singular values sit
 * between the thresholds; random coordinates put them far apart (the zero
 * ones at rounding level). A framework whose singular values are not well
 * separated (a gap below 1e6) skips the checks that compare counts, and
 * such frameworks must stay rare.
 * On failure the test prints the case's seed and the framework, shrunk by
 * dropping bars and joints while it still fails.
 * KIN_CORPUS_SEED and KIN_CORPUS_N override the seed and the count;
 * KIN_CORPUS_DEBUG=1 prints every step that was not accepted, with why. */
#include <string.h>

#include "check.h"
#include "model/internal.h"
#include "model/lapack.h"
#include "libkin.h"

enum { MAXJ = 9, MAXB = MAXJ * (MAXJ - 1) / 2, MAXC = MAXJ * 3 };
enum { DEFAULT_COUNT = 2400 };
static const unsigned long long DEFAULT_SEED = 0xC0FFEE2026ULL;

enum family { F_CHAIN, F_RANDOM, F_DENSE, F_COLLINEAR, F_COPLANAR, NFAMILY };
static const char *const FAMILY[NFAMILY] = {"chain/ring", "random graph", "near-complete",
                                             "collinear", "coplanar (3D)"};
enum supports { S_NONE, S_PINNED, S_COORDS, NSUPPORT };
static const char *const SUPPORT[NSUPPORT] = {"none", "pinned joints", "random coordinates"};

typedef struct fw {
    int dim, nj, nb, family, supports;
    double xyz[MAXC];
    unsigned char fixed[MAXC];
    int bars[2 * MAXB];
} fw;

/* ---- random numbers ---------------------------------------------------- */

static double uniform(unsigned long long *s) { return (double)(kin__splitmix(s) >> 11) * 0x1.0p-53; }
static int below(unsigned long long *s, int n) { return (int)(kin__splitmix(s) % (unsigned long long)n); }

static void random_unit(unsigned long long *s, int dim, double *v)
{
    double n;
    do {
        n = 0.0;
        for (int k = 0; k < dim; ++k) {
            v[k] = 2.0 * uniform(s) - 1.0;
            n += v[k] * v[k];
        }
    } while (n < 0.01 || n > 1.0);
    for (int k = 0; k < dim; ++k) v[k] /= sqrt(n);
}

/* ---- generation ---------------------------------------------------------- */

static int nfree(const fw *f)
{
    int n = 0;
    for (int i = 0; i < f->nj * f->dim; ++i) n += !f->fixed[i];
    return n;
}

/* bars: nb distinct pairs out of all of them, in random order */
static void random_pairs(unsigned long long *s, fw *f, int nb)
{
    int pairs[2 * MAXB], np = 0;
    for (int p = 0; p < f->nj; ++p)
        for (int q = p + 1; q < f->nj; ++q) {
            pairs[2 * np] = p;
            pairs[2 * np + 1] = q;
            ++np;
        }
    if (nb > np) nb = np;
    for (int k = 0; k < nb; ++k) {
        int r = k + below(s, np - k), a = pairs[2 * r], b = pairs[2 * r + 1];
        pairs[2 * r] = pairs[2 * k];
        pairs[2 * r + 1] = pairs[2 * k + 1];
        pairs[2 * k] = a;
        pairs[2 * k + 1] = b;
    }
    memcpy(f->bars, pairs, sizeof(int) * 2 * (size_t)nb);
    f->nb = nb;
}

static void generate(unsigned long long seed, fw *f)
{
    unsigned long long s = seed;
    memset(f, 0, sizeof *f);
    f->family = below(&s, NFAMILY);
    f->dim = f->family == F_COPLANAR ? 3 : 2 + below(&s, 2);
    f->nj = 2 + below(&s, MAXJ - 1);
    int nj = f->nj, d = f->dim, all = nj * (nj - 1) / 2;
    /* geometry */
    double o[3], e1[3], e2[3];
    random_unit(&s, d, e1);
    for (int k = 0; k < d; ++k) o[k] = 2.0 * uniform(&s) - 1.0;
    if (d == 3) {
        /* e2: a unit vector normal to e1 */
        random_unit(&s, 3, e2);
        double p = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
        for (int k = 0; k < 3; ++k) e2[k] -= p * e1[k];
        double n = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
        for (int k = 0; k < 3; ++k) e2[k] /= n;
    }
    for (int j = 0; j < nj; ++j) {
        double *x = f->xyz + j * d;
        if (f->family == F_COLLINEAR) {
            double u = 4.0 * uniform(&s) - 2.0;
            for (int k = 0; k < d; ++k) x[k] = o[k] + u * e1[k];
        } else if (f->family == F_COPLANAR) {
            double u = 4.0 * uniform(&s) - 2.0, v = 4.0 * uniform(&s) - 2.0;
            for (int k = 0; k < 3; ++k) x[k] = o[k] + u * e1[k] + v * e2[k];
        } else {
            for (int k = 0; k < d; ++k) x[k] = 4.0 * uniform(&s) - 2.0;
        }
    }
    /* bars */
    switch (f->family) {
    case F_CHAIN: {
        int ring = nj >= 3 && below(&s, 2);
        f->nb = ring ? nj : nj - 1;
        for (int k = 0; k < f->nb; ++k) {
            f->bars[2 * k] = k;
            f->bars[2 * k + 1] = (k + 1) % nj;
        }
        break;
    }
    case F_DENSE: random_pairs(&s, f, all - below(&s, all / 4 + 1)); break;
    default: random_pairs(&s, f, 1 + below(&s, all)); break;
    }
    /* supports */
    f->supports = below(&s, NSUPPORT);
    do {
        memset(f->fixed, 0, sizeof f->fixed);
        if (f->supports == S_PINNED) {
            int np = 1 + below(&s, nj);
            for (int j = 0; j < np; ++j) {
                int jj = below(&s, nj);
                for (int k = 0; k < d; ++k) f->fixed[jj * d + k] = 1;
            }
        } else if (f->supports == S_COORDS) {
            for (int i = 0; i < nj * d; ++i) f->fixed[i] = uniform(&s) < 0.3;
        }
    } while (nfree(f) == 0);
}

static void describe(const fw *f, unsigned long long seed)
{
    fprintf(stderr, "  seed 0x%llx: %s, %s, dim %d, %d joints, %d bars, %d free coordinates\n", seed,
            FAMILY[f->family], SUPPORT[f->supports], f->dim, f->nj, f->nb, nfree(f));
    for (int j = 0; j < f->nj; ++j) {
        fprintf(stderr, "    joint %d:", j);
        for (int k = 0; k < f->dim; ++k)
            fprintf(stderr, " %.17g%s", f->xyz[j * f->dim + k], f->fixed[j * f->dim + k] ? "(fixed)" : "");
        fprintf(stderr, "\n");
    }
    fprintf(stderr, "    bars:");
    for (int k = 0; k < f->nb; ++k) fprintf(stderr, " %d-%d", f->bars[2 * k], f->bars[2 * k + 1]);
    fprintf(stderr, "\n");
}

/* ---- small dense helpers ------------------------------------------------- */

/* singular values of the rows x cols matrix A (column-major, ld rows) */
static int singular_values(int rows, int cols, const double *A, double *sv)
{
    double a[MAXC * 6], work[2048], dum = 0.0;
    int one = 1, lwork = 2048, info = 0;
    if (rows == 0) return 0;
    memcpy(a, A, sizeof(double) * (size_t)rows * (size_t)cols);
    dgesvd_("N", "N", &rows, &cols, a, &rows, sv, &dum, &one, &dum, &one, work, &lwork, &info, 1, 1);
    return info;
}

/* numerical rank of a small matrix; *separated = 0 if a singular value lies
 * between 1e-6 and 1e-12 of the largest (the rank is then uncertain) */
static int small_rank(int rows, int cols, const double *A, int *separated)
{
    double sv[6];
    if (rows == 0 || singular_values(rows, cols, A, sv)) return 0;
    int n = rows < cols ? rows : cols, r = 0;
    for (int i = 0; i < n; ++i) {
        if (sv[i] > 1e-9 * sv[0]) ++r;
        if (sv[i] < 1e-6 * sv[0] && sv[i] > 1e-12 * sv[0]) *separated = 0;
    }
    return r;
}

/* G: rigid motion fields at every coordinate (nj*dim x nrig), as in
 * infinitesimal motions t + w x (X - c) */
static int rigid_fields(const fw *f, double *G)
{
    int d = f->dim, n = f->nj * d, nr = d == 2 ? 3 : 6;
    memset(G, 0, sizeof(double) * (size_t)n * (size_t)nr);
    for (int j = 0; j < f->nj; ++j) {
        const double *x = f->xyz + j * d;
        for (int k = 0; k < d; ++k) G[j * d + k + k * n] = 1.0;
        if (d == 2) {
            G[j * 2 + 2 * n] = -x[1];
            G[j * 2 + 1 + 2 * n] = x[0];
        } else {
            /* w x x for w = e_x, e_y, e_z */
            G[j * 3 + 1 + 3 * n] = -x[2];
            G[j * 3 + 2 + 3 * n] = x[1];
            G[j * 3 + 0 + 4 * n] = x[2];
            G[j * 3 + 2 + 4 * n] = -x[0];
            G[j * 3 + 0 + 5 * n] = -x[1];
            G[j * 3 + 1 + 5 * n] = x[0];
        }
    }
    return nr;
}

/* |v - P v| for P the orthogonal projection on the columns of A (n x k):
 * Gram-Schmidt twice, dropping dependent columns */
static double residual_off_span(int n, const double *A, int k, const double *v)
{
    double Q[MAXC * 6], r[MAXC];
    int q = 0;
    for (int c = 0; c < k; ++c) {
        double *x = Q + q * n, before = 0.0, after = 0.0;
        memcpy(x, A + c * n, sizeof(double) * (size_t)n);
        for (int i = 0; i < n; ++i) before += x[i] * x[i];
        for (int pass = 0; pass < 2; ++pass)
            for (int p = 0; p < q; ++p) {
                double dot = 0.0;
                for (int i = 0; i < n; ++i) dot += Q[p * n + i] * x[i];
                for (int i = 0; i < n; ++i) x[i] -= dot * Q[p * n + i];
            }
        for (int i = 0; i < n; ++i) after += x[i] * x[i];
        if (after <= 1e-20 * before || after == 0.0) continue;
        for (int i = 0; i < n; ++i) x[i] /= sqrt(after);
        ++q;
    }
    memcpy(r, v, sizeof(double) * (size_t)n);
    for (int pass = 0; pass < 2; ++pass)
        for (int p = 0; p < q; ++p) {
            double dot = 0.0;
            for (int i = 0; i < n; ++i) dot += Q[p * n + i] * r[i];
            for (int i = 0; i < n; ++i) r[i] -= dot * Q[p * n + i];
        }
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += r[i] * r[i];
    return sqrt(s);
}

/* max |X^T Y - (same ? I : 0)| for X (n x a), Y (n x b) */
static double gram_error(int n, const double *X, int a, const double *Y, int b, int same)
{
    double worst = 0.0;
    for (int i = 0; i < a; ++i)
        for (int j = 0; j < b; ++j) {
            double s = 0.0;
            for (int r = 0; r < n; ++r) s += X[i * n + r] * Y[j * n + r];
            worst = fmax(worst, fabs(s - (same && i == j ? 1.0 : 0.0)));
        }
    return worst;
}

/* ---- the invariants ------------------------------------------------------ */

typedef struct summary {
    int ok;          /* created and analysed */
    kin_analysis an;
    double sv[MAXC];
    int nsv;
    int separated;   /* singular values of H and of the rigid fields well apart */
} summary;

#define FAIL_IF(cond, ...)                                                                 \
    do {                                                                                   \
        if (cond) {                                                                        \
            if (!quiet) {                                                                  \
                fprintf(stderr, "  corpus invariant failed: ");                           \
                fprintf(stderr, __VA_ARGS__);                                              \
                fprintf(stderr, "\n");                                                     \
            }                                                                              \
            ++bad;                                                                         \
        }                                                                                  \
    } while (0)

/* analyse one framework and check the invariants that hold for it alone */
static int analyse_checked(const fw *f, summary *out, int quiet)
{
    int bad = 0, d = f->dim, n = f->nj * d;
    out->ok = 0;
    out->separated = 1;
    kin_assembly *a = NULL;
    char err[256];
    int rc = kin_assembly_create(d, f->nj, f->xyz, f->fixed, f->nb, f->bars, NULL, &a, err, sizeof err);
    FAIL_IF(rc != KIN_OK, "create: %s (%s)", kin_status_name(rc), err);
    if (rc) return bad;
    kin_analysis an = {.size = sizeof an};
    rc = kin_analyse(a, &an);
    FAIL_IF(rc != KIN_OK, "analyse: %s (%s)", kin_status_name(rc), kin_last_error(a));
    if (rc) {
        kin_assembly_free(a);
        return bad;
    }
    int nf = kin_nfree(a), nb = f->nb, mn = nf < nb ? nf : nb;
    FAIL_IF(an.rank + an.m != nf, "r + m = %d + %d != nfree = %d", an.rank, an.m, nf);
    FAIL_IF(an.rank + an.s != nb, "r + s = %d + %d != nbars = %d", an.rank, an.s, nb);
    {
        /* s_trivial: the bars with no free coordinate at either end, each a
         * zero column of H and a self-stress of its own */
        int dim = kin_dim(a), nfixed_bars = 0, *bars = malloc(sizeof(int) * 2 * (size_t)nb);
        unsigned char *fx = malloc((size_t)kin_njoints(a) * (size_t)dim);
        if (bars && fx && kin_get_bars(a, bars) == KIN_OK && kin_get_fixed(a, fx) == KIN_OK)
            for (int k = 0; k < nb; ++k) {
                int all = 1;
                for (int c = 0; c < dim; ++c) all &= fx[bars[2 * k] * dim + c] && fx[bars[2 * k + 1] * dim + c];
                nfixed_bars += all;
            }
        FAIL_IF(an.s_trivial != nfixed_bars || an.s_trivial > an.s, "s_trivial = %d, %d bars between fixed joints, s = %d",
                an.s_trivial, nfixed_bars, an.s);
        free(bars);
        free(fx);
    }
    FAIL_IF(an.m_rigid < 0 || an.m_internal < 0 || an.m_rigid + an.m_internal != an.m,
            "m_rigid %d + m_internal %d != m %d", an.m_rigid, an.m_internal, an.m);
    kin_options o;
    kin_options_default(&o); /* sets o.size */
    kin_get_options(a, &o);
    static double H[MAXC * MAXB], U[MAXC * MAXC], Ur[MAXC * 6], Ui[MAXC * MAXC], W[MAXB * MAXB];
    kin_get_equilibrium_matrix(a, H, nf);
    kin_get_singular_values(a, out->sv, mn);
    out->nsv = mn;
    double vmax = an.v_max;
    /* rank decision well away from the threshold? */
    if (an.rank > 0 && out->sv[an.rank - 1] < 1e-6 * vmax) out->separated = 0;
    if (an.rank < mn && out->sv[an.rank] > 1e-12 * vmax) out->separated = 0;
    rc = kin_get_mechanisms(a, KIN_MECH_ALL, U, nf, an.m) | kin_get_mechanisms(a, KIN_MECH_RIGID, Ur, nf, an.m_rigid) |
         kin_get_mechanisms(a, KIN_MECH_INTERNAL, Ui, nf, an.m_internal) | kin_get_self_stresses(a, W, nb, an.s);
    FAIL_IF(rc != KIN_OK, "getters of the analysis failed");
    /* |H^T u| for every mechanism (all, rigid, internal), |H w| per self-stress */
    double tol = (sqrt((double)(an.m > 1 ? an.m : 1)) * o.rank_tol + 64 * DBL_EPSILON) * vmax;
    const double *sets[3] = {U, Ur, Ui};
    const int counts[3] = {an.m, an.m_rigid, an.m_internal};
    for (int s = 0; s < 3; ++s) {
        for (int c = 0; c < counts[s]; ++c)
            for (int k = 0; k < nb; ++k) {
                double v = 0.0;
                for (int i = 0; i < nf; ++i) v += H[i + k * nf] * sets[s][i + c * nf];
                FAIL_IF(!(fabs(v) <= tol), "|H^T u| = %.3g for mechanism %d of set %d (tol %.3g)", fabs(v),
                        c, s, tol);
            }
        FAIL_IF(!(gram_error(nf, sets[s], counts[s], sets[s], counts[s], 1) <= 1e-12),
                "mechanism set %d not orthonormal", s);
    }
    for (int c = 0; c < an.s; ++c)
        for (int i = 0; i < nf; ++i) {
            double v = 0.0;
            for (int k = 0; k < nb; ++k) v += H[i + k * nf] * W[k + c * nb];
            FAIL_IF(!(fabs(v) <= tol), "|H w| = %.3g for self-stress %d", fabs(v), c);
        }
    FAIL_IF(!(gram_error(nb, W, an.s, W, an.s, 1) <= 1e-12), "self-stresses not orthonormal");
    FAIL_IF(!(gram_error(nf, Ur, an.m_rigid, Ui, an.m_internal, 0) <= 1e-10),
            "internal mechanisms not orthogonal to the rigid ones");
    /* rigid mechanisms are rigid motions of the whole assembly with the
     * supports at rest: the full displacement (0 at fixed coordinates) lies
     * in the span of the rigid fields */
    double G[MAXC * 6], D[MAXC];
    int nr = rigid_fields(f, G);
    for (int c = 0; c < an.m_rigid; ++c) {
        for (int i = 0; i < n; ++i) {
            int row = kin_free_index(a, i / d, i % d);
            D[i] = row >= 0 ? Ur[row + c * nf] : 0.0;
        }
        double res = residual_off_span(n, G, nr, D);
        FAIL_IF(!(res <= 1e-9), "rigid mechanism %d is %.3g off the rigid motions keeping the supports", c, res);
    }
    /* m_rigid = rank(G) - rank(G at the fixed coordinates) */
    double Gfix[MAXC * 6];
    int nfix = n - nf, r = 0;
    for (int i = 0; i < n; ++i)
        if (f->fixed[i]) {
            for (int c = 0; c < nr; ++c) Gfix[r + c * nfix] = G[i + c * n];
            ++r;
        }
    int sep = 1, want = small_rank(n, nr, G, &sep) - small_rank(nfix, nr, Gfix, &sep);
    if (!sep) out->separated = 0;
    if (sep) FAIL_IF(an.m_rigid != want, "m_rigid = %d, rigid motions keeping the supports: %d", an.m_rigid, want);
    out->an = an;
    out->ok = 1;
    kin_assembly_free(a);
    return bad;
}

/* relabel joints and bars (and swap bar ends) */
static void relabel(const fw *f, unsigned long long *s, fw *g)
{
    int perm[MAXJ], bp[MAXB], d = f->dim;
    *g = *f;
    for (int j = 0; j < f->nj; ++j) perm[j] = j;
    for (int j = f->nj - 1; j > 0; --j) {
        int r = below(s, j + 1), t = perm[j];
        perm[j] = perm[r];
        perm[r] = t;
    }
    for (int k = 0; k < f->nb; ++k) bp[k] = k;
    for (int k = f->nb - 1; k > 0; --k) {
        int r = below(s, k + 1), t = bp[k];
        bp[k] = bp[r];
        bp[r] = t;
    }
    for (int j = 0; j < f->nj; ++j)
        for (int k = 0; k < d; ++k) {
            g->xyz[perm[j] * d + k] = f->xyz[j * d + k];
            g->fixed[perm[j] * d + k] = f->fixed[j * d + k];
        }
    for (int k = 0; k < f->nb; ++k) {
        int swap = below(s, 2);
        g->bars[2 * bp[k]] = perm[f->bars[2 * k + swap]];
        g->bars[2 * bp[k] + 1] = perm[f->bars[2 * k + 1 - swap]];
    }
}

/* a rigid transformation: rotation (if allowed) and translation */
static void move(const fw *f, unsigned long long *s, int rotate, fw *g)
{
    int d = f->dim;
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3];
    *g = *f;
    if (rotate && d == 2) {
        double th = 6.283185307179586 * uniform(s);
        R[0] = cos(th);
        R[1] = -sin(th);
        R[3] = sin(th);
        R[4] = cos(th);
    } else if (rotate) {
        double q[4], n = 0.0;
        for (int k = 0; k < 4; ++k) {
            q[k] = 2.0 * uniform(s) - 1.0;
            n += q[k] * q[k];
        }
        n = sqrt(n);
        double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
        double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                       2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                       2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
        memcpy(R, M, sizeof R);
    }
    for (int k = 0; k < d; ++k) t[k] = 6.0 * uniform(s) - 3.0;
    for (int j = 0; j < f->nj; ++j)
        for (int r = 0; r < d; ++r) {
            double v = t[r];
            for (int c = 0; c < d; ++c) v += R[r * 3 + c] * f->xyz[j * d + c];
            g->xyz[j * d + r] = v;
        }
}

/* may a rotation be applied? only if every joint is either free or pinned */
static int rotation_invariant(const fw *f)
{
    for (int j = 0; j < f->nj; ++j) {
        int nfix = 0;
        for (int k = 0; k < f->dim; ++k) nfix += f->fixed[j * f->dim + k];
        if (nfix != 0 && nfix != f->dim) return 0;
    }
    return 1;
}

static int same_counts(const summary *x, const summary *y)
{
    if (x->an.rank != y->an.rank || x->an.m_rigid != y->an.m_rigid || x->an.m_internal != y->an.m_internal ||
        x->an.s != y->an.s || x->nsv != y->nsv)
        return 0;
    for (int i = 0; i < x->nsv; ++i)
        if (!(fabs(x->sv[i] - y->sv[i]) <= 1e-12 * x->an.v_max)) return 0;
    return 1;
}

/* One step in one mode: the status must be the documented one. */
static int step_checked(const fw *f, const summary *base, int mode, unsigned long long *s, int quiet,
                        int *tried, int *stepped)
{
    int bad = 0;
    kin_assembly *a = NULL;
    if (kin_assembly_create(f->dim, f->nj, f->xyz, f->fixed, f->nb, f->bars, NULL, &a, NULL, 0)) return 1;
    kin_options o;
    kin_options_default(&o); /* sets o.size */
    kin_get_options(a, &o);
    o.factorization = mode;
    kin_set_options(a, &o);
    const kin_analysis *an = &base->an;
    int rc = kin_step(a, 0.0, NULL);
    if (an->m_internal == 0) {
        FAIL_IF(rc != KIN_ENOMECH, "step without mechanism: %s", kin_status_name(rc));
    } else if (an->m_internal >= 2) {
        /* the self-stresses of bars between fixed joints constrain nothing */
        int want = an->s == an->s_trivial ? KIN_EMULTIDOF : KIN_EBIFURCATION;
        FAIL_IF(rc != want, "step with %d internal mechanisms, s = %d, no direction: %s", an->m_internal, an->s,
                kin_status_name(rc));
        /* a direction: a random combination of the internal mechanisms */
        static double Ui[MAXC * MAXC], dir[MAXC];
        int nf = kin_nfree(a);
        kin_analyse(a, NULL);
        kin_get_mechanisms(a, KIN_MECH_INTERNAL, Ui, nf, an->m_internal);
        memset(dir, 0, sizeof dir);
        for (int c = 0; c < an->m_internal; ++c) {
            double w = 2.0 * uniform(s) - 1.0;
            for (int i = 0; i < nf; ++i) dir[i] += w * Ui[i + c * nf];
        }
        rc = kin_path_set_direction(a, dir, nf);
        FAIL_IF(rc != KIN_OK, "set_direction: %s", kin_status_name(rc));
        rc = kin_step(a, 0.0, NULL);
    }
    if (an->m_internal >= 1) {
        ++*tried;
        if (rc && !quiet)
            fprintf(stderr, "  step (mode %d, m_internal %d, s %d): %s: %s\n", mode, an->m_internal, an->s,
                    kin_status_name(rc), kin_last_error(a));
        /* every attempt failed: the reason of the last one, which may be
         * that its point had no internal mechanism (an infinitesimal one) */
        FAIL_IF(rc != KIN_OK && rc != KIN_ENOTCONVERGED && rc != KIN_EPATHJUMP && rc != KIN_ENOMECH, "step: %s (%s)",
                kin_status_name(rc), kin_last_error(a));
        /* no self-stress: the strain-free set is smooth here, and a short
         * enough step (halving) stays on it, unless H is close to losing
         * rank (then the path may turn within any step the halvings reach),
         * or the joints are on one line: moving off it, a rotation about
         * the line becomes a rigid mode, the internal mechanisms lose a
         * dimension, and the step may be refused as a jump */
        FAIL_IF(an->s == 0 && an->v_r > 1e-3 * an->v_max && f->family != F_COLLINEAR && rc != KIN_OK,
                "step from a regular point (s = 0, v_r / v_max = %.3g): %s", an->v_r / an->v_max,
                kin_status_name(rc));
        if (rc == KIN_OK) {
            ++*stepped;
            FAIL_IF(!(kin_max_strain(a) <= o.corrector_tol), "strain %.3g after a step", kin_max_strain(a));
        }
    }
    kin_assembly_free(a);
    return bad;
}

typedef struct stats {
    int cases, separated, rotated, steps, stepped, multidof, family[NFAMILY], under, over, fixed_bars;
} stats;

/* every invariant of one framework; returns the number of failures */
static int check_case(const fw *f, unsigned long long seed, int quiet, stats *st)
{
    int bad = 0;
    unsigned long long s = seed ^ 0x7A11ULL;
    summary base, other;
    bad += analyse_checked(f, &base, quiet);
    if (!base.ok) return bad + 1;
    fw g;
    relabel(f, &s, &g);
    bad += analyse_checked(&g, &other, quiet);
    int rot = rotation_invariant(f);
    if (base.separated && other.separated)
        FAIL_IF(!same_counts(&base, &other), "relabelling changed the analysis (rank %d -> %d)", base.an.rank,
                other.an.rank);
    move(f, &s, rot, &g);
    bad += analyse_checked(&g, &other, quiet);
    if (base.separated && other.separated)
        FAIL_IF(!same_counts(&base, &other), "a %s changed the analysis (rank %d -> %d, m_rigid %d -> %d)",
                rot ? "rotation and translation" : "translation", base.an.rank, other.an.rank,
                base.an.m_rigid, other.an.m_rigid);
    /* steps on one framework in three, in both modes */
    int steps = seed % 3 == 0, tried = 0, stepped = 0;
    if (steps) {
        int q = quiet && !getenv("KIN_CORPUS_DEBUG");
        bad += step_checked(f, &base, KIN_STEP_SVD, &s, q, &tried, &stepped);
        bad += step_checked(f, &base, KIN_STEP_LU, &s, q, &tried, &stepped);
    }
    if (st) {
        st->cases++;
        st->separated += base.separated;
        st->rotated += rot;
        st->steps += tried;
        st->stepped += stepped;
        st->multidof += base.an.m_internal >= 2;
        st->family[f->family]++;
        st->under += nfree(f) > f->nb + 1 + (f->dim == 2 ? 3 : 6);
        st->over += base.an.s > 0;
        st->fixed_bars += base.an.s_trivial > 0;
    }
    return bad;
}

/* ---- shrinking a failure ------------------------------------------------- */

static int drop_bar(const fw *f, int k, fw *g)
{
    if (f->nb <= 1) return 0;
    *g = *f;
    memmove(g->bars + 2 * k, f->bars + 2 * k + 2, sizeof(int) * 2 * (size_t)(f->nb - k - 1));
    g->nb = f->nb - 1;
    return 1;
}

static int drop_joint(const fw *f, int j, fw *g)
{
    int d = f->dim;
    if (f->nj <= 2) return 0;
    *g = *f;
    g->nj = f->nj - 1;
    memmove(g->xyz + j * d, f->xyz + (j + 1) * d, sizeof(double) * (size_t)((f->nj - j - 1) * d));
    memmove(g->fixed + j * d, f->fixed + (j + 1) * d, (size_t)((f->nj - j - 1) * d));
    g->nb = 0;
    for (int k = 0; k < f->nb; ++k) {
        int p = f->bars[2 * k], q = f->bars[2 * k + 1];
        if (p == j || q == j) continue;
        g->bars[2 * g->nb] = p > j ? p - 1 : p;
        g->bars[2 * g->nb + 1] = q > j ? q - 1 : q;
        g->nb++;
    }
    return g->nb > 0 && nfree(g) > 0;
}

/* drop joints, then bars, while the framework still fails */
static void shrink(fw *f, unsigned long long seed)
{
    for (int progress = 1; progress;) {
        progress = 0;
        fw g;
        for (int j = 0; j < f->nj && !progress; ++j)
            if (drop_joint(f, j, &g) && check_case(&g, seed, 1, NULL)) {
                *f = g;
                progress = 1;
            }
        for (int k = 0; k < f->nb && !progress; ++k)
            if (drop_bar(f, k, &g) && check_case(&g, seed, 1, NULL)) {
                *f = g;
                progress = 1;
            }
    }
}

int main(void)
{
    unsigned long long seed = DEFAULT_SEED;
    int count = DEFAULT_COUNT, failed = 0;
    const char *env = getenv("KIN_CORPUS_SEED");
    if (env && *env) seed = strtoull(env, NULL, 0);
    env = getenv("KIN_CORPUS_N");
    if (env && *env) count = atoi(env);
    stats st;
    memset(&st, 0, sizeof st);
    for (int i = 0; i < count; ++i) {
        unsigned long long cs = seed + (unsigned long long)i;
        fw f;
        generate(cs, &f);
        if (check_case(&f, cs, 1, &st) == 0) continue;
        if (++failed > 3) continue; /* report the first few in full */
        fprintf(stderr, "corpus case %d (KIN_CORPUS_SEED=0x%llx KIN_CORPUS_N=1) failed:\n", i, cs);
        describe(&f, cs);
        check_case(&f, cs, 0, NULL);
        fw small = f;
        shrink(&small, cs);
        fprintf(stderr, "  shrunk to a framework that still fails:\n");
        describe(&small, cs);
        check_case(&small, cs, 0, NULL);
    }
    printf("corpus: %d frameworks (seed 0x%llx), %d failed; %d with nfree > nbars + 1 + rigid motions, "
           "%d with a self-stress (%d with bars between fixed joints), %d with several internal mechanisms; %d "
           "rotated; %d well separated; %d of %d steps accepted\n",
           st.cases, seed, failed, st.under, st.over, st.fixed_bars, st.multidof, st.rotated, st.separated, st.stepped, st.steps);
    printf("corpus families:");
    for (int k = 0; k < NFAMILY; ++k) printf(" %s %d;", FAMILY[k], st.family[k]);
    printf("\n");
    CHECK(failed == 0);
    /* the corpus is what it claims to be (only for the default count) */
    if (count >= DEFAULT_COUNT) {
        CHECK(st.cases == count);
        for (int k = 0; k < NFAMILY; ++k) CHECK(st.family[k] >= count / 10);
        CHECK(st.under >= count / 10);
        CHECK(st.over >= count / 10);
        CHECK(st.multidof >= count / 10);
        CHECK(st.rotated >= count / 10);
        CHECK(st.separated >= count - count / 20);
        CHECK(st.stepped >= st.steps / 4);
    }
    TEST_REPORT("test_corpus");
}
