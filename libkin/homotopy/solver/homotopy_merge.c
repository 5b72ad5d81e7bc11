/* The second half of the complete solver (homotopy_solver.c tracks the paths):
 * the endpoints are checked against what total-degree homotopy guarantees,
 * the paths concerned are tracked again, and the result is counted.
 *
 * Every non-singular root is reached by exactly one path, so two paths on
 * the same certified root means a path jumped; complex roots of a real
 * system come in conjugate pairs, so a certified non-real root whose
 * conjugate no path reached means a path was lost on the way. Paths involved
 * (and failed ones) are tracked again with tighter settings, up to
 * RETRACK_ROUNDS times; what remains is reported in kin_homotopy_info.
 * Duplicates and conjugates are found in O(n log n): endpoints are sorted by
 * a key that does not depend on the representative of the projective point
 * nor on conjugation, and only neighbours within KEY_WINDOW are compared.
 *
 * The same code serves kin_quadrics_homotopy_ex (after tracking every path)
 * and kin_quadrics_homotopy_merge (after ranges tracked elsewhere), so the
 * two give the same result. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/solver/homotopy_solver.h"
#include "homotopy/track/homotopy_control.h" /* MAX_STEPS */
#include "model/internal.h"

/* First tracking pass. The predictor error target is the smaller of
 * pred_rel |x| and pred_sep times the separation radius r (the distance to
 * the nearest other path); a first Newton correction above corr_sep r
 * rejects the step (0.2 keeps the Kantorovich quantity 2 |d| / r at <= 0.4,
 * and a jump would need a predictor error of 0.8 r, 16 times the target).
 * A path still short of t = 1 at 1 - t = sigma_end is heading for a singular
 * endpoint (the series' radius shrinks with 1 - t) and is classified there.
 * The values were chosen on the hexagonal sail's flat state (s = 15), where
 * they give the same accounting as settings 10x and 100x tighter. */
const hom_settings kin__hom_base_settings = {1e-4, 0.05, 0.2, 1e-10};
/* Each re-tracking round multiplies the three tolerances by TIGHTEN and
 * sigma_end by SIGMA_TIGHTEN. */
static const double TIGHTEN = 0.1, SIGMA_TIGHTEN = 0.01;
enum { RETRACK_ROUNDS = 3 };
/* Two endpoints approximate the same root if they are closer than
 * SAME_FRACTION times the smaller uniqueness radius (by the certificate the
 * roots in their existence balls then coincide). */
static const double SAME_FRACTION = 0.5;
/* Sort-key window: two approximations of one root differ by at most the sum
 * of their existence radii (each <= 1e-8 |z|, see homotopy_track.c), which
 * moves the key by at most 8e-8; pairs farther apart in key are distinct. */
static const double KEY_WINDOW = 1e-6;

static int key_cmp(const void *a, const void *b)
{
    const hom_key *x = a, *y = b;
    if (x->key < y->key) return -1;
    if (x->key > y->key) return 1;
    return (x->path > y->path) - (x->path < y->path);
}

int kin__hom_find(int *parent, int p)
{
    while (parent[p] != p) {
        parent[p] = parent[parent[p]];
        p = parent[p];
    }
    return p;
}

static void unite(int *parent, int p, int q)
{
    p = kin__hom_find(parent, p), q = kin__hom_find(parent, q);
    if (p < q) parent[q] = p;
    else if (q < p) parent[p] = q;
}

/* Do endpoints p and q (q conjugated if conj) approximate the same root?
 * Compared in p's chart. */
static int same_root(int m, const hom_end *ep, const double *pr, const double *pi, const hom_end *eq,
                     const double *qr, const double *qi, int conj)
{
    int k = ep->chart;
    double sg = conj ? -1.0 : 1.0, a = qr[k], b = sg * qi[k], d = a * a + b * b, dist2 = 0.0;
    if (!(d > 0.0)) return 0;
    for (int c = 0; c < m; ++c) {
        double vr = (qr[c] * a + sg * qi[c] * b) / d, vi = (sg * qi[c] * a - qr[c] * b) / d;
        dist2 += (pr[c] - vr) * (pr[c] - vr) + (pi[c] - vi) * (pi[c] - vi);
    }
    return sqrt(dist2) <= SAME_FRACTION * fmin(ep->rplus, eq->rplus);
}

hom_checks kin__hom_check(int m, int npaths, const hom_end *ends, const double *zr, const double *zi, const double *w,
                          hom_key *keys, int *parent, unsigned char *paired)
{
    hom_checks c = {0, 0};
    int n = 0;
    for (int p = 0; p < npaths; ++p) {
        parent[p] = p;
        paired[p] = 0;
        if (ends[p].kind != HOM_REAL && ends[p].kind != HOM_NONREAL) continue;
        const double *xr = zr + (size_t)p * m, *xi = zi + (size_t)p * m;
        double wr = 0.0, wi = 0.0, nz = 0.0;
        for (int i = 0; i < m; ++i) {
            wr += w[i] * xr[i], wi += w[i] * xi[i];
            nz += xr[i] * xr[i] + xi[i] * xi[i];
        }
        keys[n++] = (hom_key){(wr * wr + wi * wi) / nz, p};
    }
    qsort(keys, (size_t)n, sizeof *keys, key_cmp);
    for (int i = 0; i < n; ++i) {
        int p = keys[i].path;
        const double *pr = zr + (size_t)p * m, *pi = zi + (size_t)p * m;
        for (int j = i + 1; j < n && keys[j].key - keys[i].key <= KEY_WINDOW; ++j) {
            int q = keys[j].path;
            const double *qr = zr + (size_t)q * m, *qi = zi + (size_t)q * m;
            if (same_root(m, &ends[p], pr, pi, &ends[q], qr, qi, 0)) unite(parent, p, q);
            if (ends[p].kind == HOM_NONREAL && ends[q].kind == HOM_NONREAL &&
                same_root(m, &ends[p], pr, pi, &ends[q], qr, qi, 1))
                paired[p] = paired[q] = 1;
        }
    }
    for (int i = 0; i < n; ++i) {
        int p = keys[i].path;
        if (kin__hom_find(parent, p) != p) c.duplicates++;
        if (ends[p].kind == HOM_NONREAL && !paired[p]) c.unpaired++;
    }
    return c;
}

/* the accounting of the checked endpoints (parent: kin__hom_check's
 * grouping; size: npaths ints of scratch) */
void kin__hom_unit_beta(int m, double *b)
{
    double nb = kin__norm(m, b);
    int big = 0;
    for (int i = 0; i < m; ++i) {
        b[i] /= nb;
        if (fabs(b[i]) > fabs(b[big])) big = i;
    }
    if (b[big] < 0)
        for (int i = 0; i < m; ++i) b[i] = -b[i];
}

double kin__hom_residual(int m, int s, const double *Qr, const double *b)
{
    size_t mm = (size_t)m * m;
    double res = 0.0;
    for (int j = 0; j < s; ++j) {
        const double *q = Qr + (size_t)j * mm;
        double v = 0.0;
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c) v += b[r] * q[(size_t)r * m + c] * b[c];
        res = fmax(res, fabs(v));
    }
    return res;
}

static void tally(const hom_solver *H, const hom_end *ends, const double *zr, const double *zi, int *parent,
                  int *size, hom_checks ck, int retracked, double *betas, int maxsol, int *nsol, int *multiplicity,
                  kin_homotopy_info *info)
{
    int m = H->P.m, s = H->P.s, npaths = H->npaths;
    const double *Qr = H->Qr;
    (void)zi;
    memset(info, 0, sizeof *info);
    info->paths = npaths;
    info->retracked = retracked;
    info->duplicates = ck.duplicates;
    info->unpaired = ck.unpaired;
    memset(size, 0, sizeof(int) * (size_t)npaths);
    for (int p = 0; p < npaths; ++p) {
        const hom_end *e = &ends[p];
        info->steps_total += e->steps;
        info->rejected_total += e->rejected;
        switch (e->kind) {
        case HOM_REAL: info->real++; break;
        case HOM_NONREAL: info->nonreal++; break;
        case HOM_SINGULAR:
            info->singular++;
            if (e->converged) info->uncertified++;
            continue;
        default: info->failed++; continue;
        }
        if (e->cond > info->max_cond) info->max_cond = e->cond;
        if (e->kind == HOM_REAL) size[kin__hom_find(parent, p)]++;
    }
    int nd = 0;
    for (int p = 0; p < npaths; ++p) {
        if (ends[p].kind != HOM_REAL || kin__hom_find(parent, p) != p) continue;
        double b[HOM_MAX_M];
        memcpy(b, zr + (size_t)p * m, sizeof(double) * (size_t)m);
        kin__hom_unit_beta(m, b);
        info->max_residual = fmax(info->max_residual, kin__hom_residual(m, s, Qr, b));
        if (nd < maxsol) {
            memcpy(betas + (size_t)nd * m, b, sizeof(double) * (size_t)m);
            if (multiplicity) multiplicity[nd] = size[p];
        }
        ++nd;
    }
    info->real_distinct = nd;
    /* the int counters of the first layout saturate; the 64-bit ones do not */
    info->steps = info->steps_total > INT_MAX ? INT_MAX : (int)info->steps_total;
    info->rejected = info->rejected_total > INT_MAX ? INT_MAX : (int)info->rejected_total;
    *nsol = nd < maxsol ? nd : maxsol;
}

int kin__hom_tally(const hom_solver *H, const hom_end *ends, double *zr, double *zi, int *parent,
                   hom_checks ck, int retracked, double *betas, int maxsol, int *nsol, int *multiplicity,
                   kin_homotopy_info *info)
{
    int *size = calloc((size_t)H->npaths, sizeof(int));
    if (!size) return KIN_ENOMEM;
    tally(H, ends, zr, zi, parent, size, ck, retracked, betas, maxsol, nsol, multiplicity, info);
    free(size);
    return kin__hom_prove(H, ends, zr, zi, NULL, info);
}

int kin__hom_merge(hom_solver *H, hom_end *ends, double *zr, double *zi, hom_report *R, double *betas, int maxsol,
                   int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    int m = H->P.m, npaths = H->npaths, rc = KIN_OK;
    const double *w = H->w;
    hom_key *keys = malloc(sizeof(hom_key) * (size_t)npaths);
    int *parent = malloc(sizeof(int) * (size_t)npaths), *list = malloc(sizeof(int) * (size_t)npaths);
    int *size = calloc((size_t)npaths, sizeof(int));
    unsigned char *paired = malloc((size_t)npaths);
    hom_settings S = kin__hom_base_settings;
    if (!keys || !parent || !list || !size || !paired) {
        rc = KIN_ENOMEM;
        goto done;
    }
    hom_checks ck = kin__hom_check(m, npaths, ends, zr, zi, w, keys, parent, paired);
    int retracked = 0;
    for (int round = 1; round <= RETRACK_ROUNDS; ++round) {
        /* the suspects: failed paths, every path on a root reached more than
         * once, non-real endpoints without a conjugate and, from the second
         * round on while conjugates are missing, the singular endpoints (a
         * lost conjugate may have been taken for one) */
        memset(size, 0, sizeof(int) * (size_t)npaths);
        for (int p = 0; p < npaths; ++p)
            if (ends[p].kind == HOM_REAL || ends[p].kind == HOM_NONREAL) size[kin__hom_find(parent, p)]++;
        int n = 0;
        for (int p = 0; p < npaths; ++p) {
            int k = ends[p].kind;
            int sus = k == HOM_FAILED || ((k == HOM_REAL || k == HOM_NONREAL) && size[kin__hom_find(parent, p)] > 1) ||
                      (k == HOM_NONREAL && !paired[p]) || (k == HOM_SINGULAR && round >= 2 && ck.unpaired > 0);
            if (sus) list[n++] = p;
        }
        if (!n) break;
        S.pred_rel *= TIGHTEN, S.pred_sep *= TIGHTEN, S.corr_sep *= TIGHTEN;
        S.sigma_end *= SIGMA_TIGHTEN;
        R->total += n;
        if ((rc = kin__hom_run(H, &S, list, 0, n, 0, ends, zr, zi, R))) goto done;
        if (R->cancelled) goto cancelled;
        retracked += n;
        ck = kin__hom_check(m, npaths, ends, zr, zi, w, keys, parent, paired);
    }

    tally(H, ends, zr, zi, parent, size, ck, retracked, betas, maxsol, nsol, multiplicity, info);
    if ((rc = kin__hom_prove(H, ends, zr, zi, R, info))) {
        if (rc == KIN_ECANCELLED) goto cancelled;
        goto done;
    }
    if (R->fn) R->fn(R->user, R->total, R->total); /* finished: its answer no longer matters */
    goto done;

cancelled:
    memset(info, 0, sizeof *info);
    *nsol = 0;
    rc = KIN_ECANCELLED;
done:
    free(paired), free(size), free(list), free(parent), free(keys);
    return rc;
}

/* the first pass, then the merge (homotopy_solver.h): the whole solve of
 * kin_quadrics_homotopy_ex and of the symmetric solver's equivariant and
 * plain routes */
int kin__hom_solve(hom_solver *H, const int *list, int n, const kin_homotopy_options *o, double *betas, int maxsol,
                   int *nsol, int *multiplicity, kin_homotopy_info *info, long *tracked)
{
    hom_endset E = {NULL, NULL, NULL};
    hom_report R = {o->progress, o->user, 0.0, (double)n, 0.0, 0};
    int rc = kin__hom_endset_alloc(&E, H->npaths, H->P.m);
    if (!rc) {
        kin__hom_report_start(&R);
        if (!R.cancelled) rc = kin__hom_run(H, &kin__hom_base_settings, list, 0, n, 0, E.ends, E.zr, E.zi, &R);
        if (!rc && R.cancelled) rc = KIN_ECANCELLED;
        if (!rc) rc = kin__hom_merge(H, E.ends, E.zr, E.zi, &R, betas, maxsol, nsol, multiplicity, info);
    }
    *tracked = (long)R.base;
    kin__hom_endset_free(&E);
    return rc;
}

/* a record as range writes it: its path, a class, a chart, finite z (certified
 * roots) and radii */
static int import_record(int m, int path, const kin_homotopy_endpoint *r, const double *z, hom_end *e, double *zr,
                         double *zi)
{
    if (r->path != path || r->kind < KIN_HOM_END_REAL || r->kind > KIN_HOM_END_FAILED || r->chart < 0 ||
        r->chart >= m || isnan(r->rminus) || isnan(r->rplus) || isnan(r->cond) || isnan(r->sigma))
        return KIN_EINVAL;
    /* a certified root has a uniqueness ball (a zeroed record has none) */
    if ((r->kind == KIN_HOM_END_REAL || r->kind == KIN_HOM_END_NONREAL) && !(r->rplus > 0.0)) return KIN_EINVAL;
    for (int c = 0; c < 2 * m; ++c)
        if (!isfinite(z[c]) && r->kind != KIN_HOM_END_FAILED && r->kind != KIN_HOM_END_SINGULAR) return KIN_EINVAL;
    /* counters a tracker can have made (a path stops at MAX_STEPS) */
    if (r->steps < 0 || r->rejected < 0 || r->recharts < 0 || r->steps > MAX_STEPS - r->rejected)
        return KIN_EINVAL;
    /* z = 0 is no point of projective space: only a lost path may have it */
    if (r->kind != KIN_HOM_END_FAILED) {
        int nonzero = 0;
        for (int c = 0; c < 2 * m; ++c) nonzero |= z[c] != 0.0;
        if (!nonzero) return KIN_EINVAL;
    }
    memset(e, 0, sizeof *e);
    e->kind = r->kind;
    e->chart = r->chart;
    e->steps = r->steps;
    e->rejected = r->rejected;
    e->recharts = r->recharts;
    e->converged = r->converged;
    e->rminus = r->rminus;
    e->rplus = r->rplus;
    e->cond = r->cond;
    e->sigma = r->sigma;
    memcpy(zr, z, sizeof(double) * (size_t)m);
    memcpy(zi, z + m, sizeof(double) * (size_t)m);
    return KIN_OK;
}

/* A record from a shard claims a certified root of Q; it may come from
 * another system, another seed or a damaged file. Its root is refined and
 * certified again here: it must come out of the same kind (real or
 * non-real), and the refined root must lie within the two existence radii
 * of the record's (the same root). 1 if it does. */
static int recheck(const hom_problem *P, hom_ws *w, const hom_end *e, const double *zr, const double *zi)
{
    int m = P->m, k = e->chart;
    double r2[HOM_MAX_M], i2[HOM_MAX_M];
    hom_end f;
    memset(&f, 0, sizeof f);
    kin__hom_certify(P, w, zr, zi, r2, i2, &f);
    if (f.kind != e->kind) return 0;
    /* both in the record's chart (z_k = 1): z2 / z2_k */
    double ar = r2[k], ai = i2[k], a2 = ar * ar + ai * ai, d2 = 0.0;
    if (!(a2 > 0.0)) return 0;
    for (int c = 0; c < m; ++c) {
        double ur = (r2[c] * ar + i2[c] * ai) / a2, ui = (i2[c] * ar - r2[c] * ai) / a2;
        d2 += (ur - zr[c]) * (ur - zr[c]) + (ui - zi[c]) * (ui - zi[c]);
    }
    return sqrt(d2) <= e->rminus + f.rminus;
}

/* Qin, U: NULL, or the proofs are about Qin's roots at beta = U x (the
 * equivariant form's merge, kin_quadrics_homotopy_merge_equivariant) */
static int merge_impl(int m, int s, const double *Q, const double *Qin, const double *U, const kin_homotopy_options *o,
                      const kin_homotopy_endpoint *recs, const double *z, double *betas, int maxsol, int *nsol,
                      int *multiplicity, kin_homotopy_info *info)
{
    if (!Q || !recs || !z || !betas || !nsol) return KIN_ENULL;
    if (recs[0].size != KIN_HOMOTOPY_ENDPOINT_SIZE || sizeof *recs != KIN_HOMOTOPY_ENDPOINT_SIZE) return KIN_EINVAL;
    if (maxsol < 1 || m < 2 || s != m - 1 || o->nthreads < 0 || o->max_paths < 1 || o->prove < 0 || o->prove > 2)
        return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE;
    if ((1L << s) > o->max_paths) return KIN_ELIMIT;
    if (Qin) /* a system the proofs are to be about: finite, as Q */
        for (size_t i = 0; i < (size_t)s * m * m + (size_t)m * m; ++i)
            if (!isfinite(i < (size_t)s * m * m ? Qin[i] : U[i - (size_t)s * m * m])) return KIN_EINVAL;
    hom_solver H;
    int rc = kin__hom_solver_init(&H, m, s, Q, o, 1L << s);
    if (Qin) H.Qin = Qin, H.U = U; /* proven on the caller's system, as kin_quadrics_homotopy_sym */
    int npaths = H.npaths;
    hom_endset E = {NULL, NULL, NULL};
    if (!rc) rc = kin__hom_endset_alloc(&E, npaths, m);
    for (int p = 0; !rc && p < npaths; ++p)
        rc = import_record(m, p, &recs[p], z + (size_t)2 * m * p, &E.ends[p], E.zr + (size_t)p * m,
                           E.zi + (size_t)p * m);
    /* every certified record checked against this Q; one that fails is
     * treated as a lost path (the merge tracks it again) */
    int failed_checks = 0;
    for (int p = 0; !rc && p < npaths; ++p) {
        hom_end *e = &E.ends[p];
        if ((e->kind == HOM_REAL || e->kind == HOM_NONREAL) &&
            !recheck(&H.P, kin__hom_pool_ws(&H, 0), e, E.zr + (size_t)p * m, E.zi + (size_t)p * m)) {
            e->kind = HOM_FAILED;
            failed_checks++;
        }
    }
    if (!rc) {
        hom_report R = {o->progress, o->user, 0.0, 0.0, 0.0, 0};
        if (R.fn && R.fn(R.user, 0.0, 0.0)) rc = KIN_ECANCELLED;
        if (!rc) rc = kin__hom_merge(&H, E.ends, E.zr, E.zi, &R, betas, maxsol, nsol, multiplicity, info);
        if (!rc) info->rechecks_failed = failed_checks;
    }
    kin__hom_endset_free(&E);
    kin__hom_solver_free(&H);
    return rc;
}

/* the public merges' entry: options read by the caller's size, info written
 * by it, zeroed on failure. Qin, U: as merge_impl; need_u: both required */
static int merge_entry(int m, int s, const double *Q, const double *Qin, const double *U, int need_u,
                       const kin_homotopy_options *opt, const kin_homotopy_endpoint *ends, const double *z,
                       double *betas, int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    kin_homotopy_options o;
    int rc = kin__hom_entry(opt, &o, info, nsol);
    if (rc) return rc;
    kin_homotopy_info local = {.size = sizeof local};
    rc = need_u && (!Qin || !U) ? KIN_ENULL
                                : merge_impl(m, s, Q, Qin, U, &o, ends, z, betas, maxsol, nsol, multiplicity, &local);
    if (rc) {
        memset(&local, 0, sizeof local);
        local.size = sizeof local;
        if (nsol) *nsol = 0;
    }
    kin__abi_write(info, &local, KIN__ABI(kin_homotopy_info));
    return rc;
}

int kin_quadrics_homotopy_merge(int m, int s, const double *Q, const kin_homotopy_options *opt,
                                const kin_homotopy_endpoint *ends, const double *z, double *betas, int maxsol,
                                int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    return merge_entry(m, s, Q, NULL, NULL, 0, opt, ends, z, betas, maxsol, nsol, multiplicity, info);
}

int kin_quadrics_homotopy_merge_equivariant(int m, int s, const double *Q, const double *Qt, const double *U,
                                            const kin_homotopy_options *opt, const kin_homotopy_endpoint *ends,
                                            const double *z, double *betas, int maxsol, int *nsol,
                                            int *multiplicity, kin_homotopy_info *info)
{
    return merge_entry(m, s, Qt, Q, U, 1, opt, ends, z, betas, maxsol, nsol, multiplicity, info);
}
