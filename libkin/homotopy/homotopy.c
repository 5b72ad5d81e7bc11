/* The complete solver's public entry points: kin_quadrics_homotopy,
 * kin_quadrics_homotopy_ex and kin_quadrics_homotopy_range.
 * A complete solver for beta^T Q_j beta = 0 (j < s), beta in P^s:
 * total-degree homotopy continuation. Every one of the 2^s paths from the
 * start system x_j^2 - x_0^2 = 0 is tracked in a random complex affine
 * chart a.x = 1 with the gamma trick,
 *     H(x, t) = (1 - t) gamma G(x) + t F(x),
 * and its endpoint certified and classified: real, complex, singular (a
 * multiple root, a point of a positive-dimensional component, Figure
 * 5(c)-(d), or a root too ill-conditioned to certify), or failed. The tracker
 * and the certificate are in track/homotopy_track.c; the set-up and the
 * runs of paths on the threads (each thread HOM_BATCH paths at a time in
 * lockstep, track/homotopy_batch.c) in solver/homotopy_solver.c; the checks
 * of the endpoints against what total-degree homotopy guarantees, the
 * re-tracks and the accounting in solver/homotopy_merge.c, with
 * kin__hom_solve (the first pass and the merge, the symmetric routes' too).
 *
 * Files call downwards only: homotopy.c -> homotopy_merge.c ->
 * homotopy_solver.c -> homotopy_pool.c, homotopy_batch.c, homotopy_track.c.
 *
 * The folder: the files directly in homotopy/ are its entry points (this
 * one; homotopy_sym_route.c, the solver with symmetry; homotopy_orbit_range.c,
 * the equivariant form and orbit ranges for shards), above its subfolders,
 * lowest first: track/ (one path), then param/ (parameter homotopies) and
 * solver/ (set-up, threads, checks, merge), then symmetric/ (the solver with
 * a symmetry group). Each subfolder's main header says what it holds; no
 * file uses a higher subfolder (tools/architecture.py, C_SUBLAYERS). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/solver/homotopy_solver.h"
#include "model/internal.h"

int kin_quadrics_homotopy(int m, int s, const double *Q, unsigned long seed, int nthreads, double *betas,
                          int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.seed = seed;
    o.nthreads = nthreads < 1 ? -1 : nthreads; /* 0 means "all processors" only in the options */
    return kin_quadrics_homotopy_ex(m, s, Q, &o, betas, maxsol, nsol, multiplicity, info);
}

/* range over every path, then the merge: the one path of every result */
static int homotopy_impl(int m, int s, const double *Q, const kin_homotopy_options *o, double *betas, int maxsol,
                         int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (nsol) *nsol = 0;
    if (!Q || !betas || !nsol || !info) return KIN_ENULL;
    if (maxsol < 1) return KIN_EINVAL;
    if (m >= 2 && s == m - 1 && m <= HOM_MAX_M && o->max_paths >= 1 && (1L << s) > o->max_paths) {
        /* refused before anything is allocated, unless the arguments are wrong anyway */
        for (size_t i = 0; i < (size_t)m * m * s; ++i)
            if (!isfinite(Q[i])) return KIN_EINVAL;
        if (o->nthreads < 0) return KIN_EINVAL;
        return KIN_ELIMIT;
    }
    hom_solver H;
    long tracked = 0;
    int rc = kin__hom_solver_init(&H, m, s, Q, o, m >= 2 && m <= HOM_MAX_M ? 1L << (m - 1) : 1);
    if (!rc) rc = kin__hom_solve(&H, NULL, H.npaths, o, betas, maxsol, nsol, multiplicity, info, &tracked);
    if (rc) {
        memset(info, 0, sizeof *info);
        *nsol = 0;
    }
    kin__hom_solver_free(&H);
    return rc;
}

int kin_quadrics_homotopy_ex(int m, int s, const double *Q, const kin_homotopy_options *opt, double *betas,
                             int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    kin_homotopy_options o;
    int rc = kin__hom_entry(opt, &o, info, nsol);
    if (rc) return rc;
    kin_homotopy_info local = {.size = sizeof local};
    rc = homotopy_impl(m, s, Q, &o, betas, maxsol, nsol, multiplicity, &local);
    kin__abi_write(info, &local, KIN__ABI(kin_homotopy_info));
    return rc;
}

int kin_quadrics_homotopy_range(int m, int s, const double *Q, const kin_homotopy_options *opt, long first_path,
                                long npaths, kin_homotopy_endpoint *ends, double *z)
{
    if (!Q || !ends || !z) return KIN_ENULL;
    if (ends[0].size != KIN_HOMOTOPY_ENDPOINT_SIZE || sizeof *ends != KIN_HOMOTOPY_ENDPOINT_SIZE) return KIN_EINVAL;
    kin_homotopy_options o;
    if (kin__hom_options(opt, &o)) return KIN_EINVAL;
    if (m < 2 || s != m - 1 || o.nthreads < 0 || o.max_paths < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE;
    if (first_path < 0 || npaths < 1 || first_path > (1L << s) - npaths) return KIN_ERANGE;
    kin__hom_zero_records(ends, npaths);
    if (npaths > o.max_paths) {
        for (size_t i = 0; i < (size_t)m * m * s; ++i)
            if (!isfinite(Q[i])) return KIN_EINVAL;
        return KIN_ELIMIT;
    }
    hom_solver H;
    int rc = kin__hom_solver_init(&H, m, s, Q, &o, npaths);
    int n = (int)npaths, first = (int)first_path;
    hom_endset E = {NULL, NULL, NULL};
    if (!rc) rc = kin__hom_endset_alloc(&E, n, m);
    if (!rc) {
        hom_report R = {o.progress, o.user, 0.0, (double)n, 0.0, 0};
        kin__hom_report_start(&R);
        if (!R.cancelled)
            rc = kin__hom_run(&H, &kin__hom_base_settings, NULL, first, n, first, E.ends, E.zr, E.zi, &R);
        if (!rc && R.cancelled) rc = KIN_ECANCELLED;
        if (!rc) {
            for (int i = 0; i < n; ++i)
                kin__hom_export(m, first + i, &E.ends[i], E.zr + (size_t)i * m, E.zi + (size_t)i * m, &ends[i],
                                z + (size_t)2 * m * i);
            if (R.fn) R.fn(R.user, R.total, R.total); /* finished: its answer no longer matters */
        }
    }
    kin__hom_endset_free(&E);
    kin__hom_solver_free(&H);
    return rc;
}
