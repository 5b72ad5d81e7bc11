/* The complete solver with symmetry in shards (kin_branch.h): the
 * equivariant form of a symmetric system (homotopy_equi.c), and ranges of
 * orbits of its start roots tracked anywhere, each writing the endpoints of
 * every member of its orbits; the plain merge (kin_quadrics_homotopy_merge
 * on the equivariant form) then gives exactly the in-process result of
 * kin_quadrics_homotopy_sym's equivariant route, in x = U^T beta. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/symmetric/homotopy_equi.h"
#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"

/* Qt is equivariant under perm within this (relative to its largest entry) */
static const double EQUIVARIANCE_TOL = 1e-12;

int kin_quadrics_equivariant_form(int m, int s, const double *Q, int ngroup, const double *R, unsigned long seed,
                                  double *Qt, double *U, int *perm, int *order, long *norbits, char *err,
                                  size_t errlen)
{
    if (err && errlen > 0) err[0] = '\0';
    if (order) *order = 0;
    if (norbits) *norbits = 0;
    if (!Q || !Qt || !U || !perm || !order || !norbits || (ngroup > 0 && !R))
        return kin__failbuf(err, errlen, KIN_ENULL, "a required pointer is NULL");
    if (m < 2 || s != m - 1 || ngroup < 0)
        return kin__failbuf(err, errlen, KIN_EINVAL, "bad size (m = %d, s = %d, ngroup = %d)", m, s, ngroup);
    if (m > HOM_MAX_M) return kin__failbuf(err, errlen, KIN_ERANGE, "m = %d > %d", m, HOM_MAX_M);
    kin_homotopy_options o;
    kin_homotopy_options_default(&o);
    o.nthreads = 1;
    hom_solver H;
    sym_group G;
    hom_equi E;
    memset(&G, 0, sizeof G);
    memset(&E, 0, sizeof E);
    int rc = kin__hom_solver_init(&H, m, s, Q, &o, 1);
    if (rc == KIN_EINVAL) kin__failbuf(err, errlen, rc, "Q has a NaN or infinite entry");
    if (!rc) rc = kin__sym_group_init(&G, m, s, H.Qr, ngroup, R, err, errlen);
    if (!rc) rc = kin__equi_plan(&E, m, s, H.Qr, &G, (unsigned long long)seed);
    if (!rc && E.k > 0) {
        memcpy(Qt, E.Qt, sizeof(double) * (size_t)m * m * s);
        memcpy(U, E.U, sizeof(double) * (size_t)m * m);
        memcpy(perm, E.perm, sizeof(int) * (size_t)m);
        *order = E.k;
        *norbits = kin__orbits_count(m, E.k, E.perm);
    }
    if (rc && err && errlen > 0 && !err[0]) kin__failbuf(err, errlen, rc, "%s", kin_strerror(rc));
    kin__equi_free(&E);
    kin__sym_group_free(&G);
    kin__hom_solver_free(&H);
    return rc;
}

/* perm a permutation with perm[0] = 0 and Qt equivariant under it:
 * Qt_{p(j)}[a][b] = Qt_j[pinv a][pinv b] within EQUIVARIANCE_TOL */
static int valid_form(int m, int s, const double *Qt, const int *perm)
{
    int pinv[HOM_MAX_M];
    for (int i = 0; i < m; ++i) pinv[i] = -1;
    for (int i = 0; i < m; ++i) {
        if (perm[i] < 0 || perm[i] >= m || pinv[perm[i]] >= 0) return 0;
        pinv[perm[i]] = i;
    }
    if (perm[0] != 0) return 0;
    size_t mm = (size_t)m * m;
    double big = 0.0, dev = 0.0;
    for (size_t x = 0; x < mm * s; ++x) big = fmax(big, fabs(Qt[x]));
    for (int j = 1; j <= s; ++j) {
        const double *a = Qt + (size_t)(j - 1) * mm, *b = Qt + (size_t)(perm[j] - 1) * mm;
        for (int c = 0; c < m; ++c)
            for (int r = 0; r < m; ++r) dev = fmax(dev, fabs(b[c * m + r] - a[pinv[c] * m + pinv[r]]));
    }
    return dev <= EQUIVARIANCE_TOL * big;
}

int kin_quadrics_homotopy_orbit_range(int m, int s, const double *Qt, const int *perm,
                                      const kin_homotopy_options *opt, long first_orbit, long norbits, long maxends,
                                      kin_homotopy_endpoint *ends, double *z, long *nends)
{
    if (nends) *nends = 0;
    if (!Qt || !perm || !ends || !z || !nends) return KIN_ENULL;
    if (ends[0].size != KIN_HOMOTOPY_ENDPOINT_SIZE || sizeof *ends != KIN_HOMOTOPY_ENDPOINT_SIZE) return KIN_EINVAL;
    kin_homotopy_options o;
    if (kin__hom_options(opt, &o)) return KIN_EINVAL;
    if (m < 2 || s != m - 1 || o.nthreads < 0 || o.max_paths < 1 || maxends < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE;
    for (size_t i = 0; i < (size_t)m * m * s; ++i)
        if (!isfinite(Qt[i])) return KIN_EINVAL;
    if (!valid_form(m, s, Qt, perm)) return KIN_EINVAL;
    if (first_orbit < 0 || norbits < 1) return KIN_ERANGE;
    if (norbits > o.max_paths) return KIN_ELIMIT;
    hom_orbits O;
    int rc = kin__orbits_init(&O, m, perm);
    if (rc) return rc;
    if (first_orbit > O.nreps - norbits) {
        kin__orbits_free(&O);
        return KIN_ERANGE;
    }
    /* the members of the range's orbits, in order (each orbit from its
     * representative along P) */
    int first = (int)first_orbit, n = (int)norbits;
    long total = 0;
    for (int i = first; i < first + n; ++i) {
        int r = O.reps[i], c = r;
        do ++total, c = O.next[c];
        while (c != r);
    }
    if (total > maxends) {
        *nends = total; /* what the caller needs */
        kin__orbits_free(&O);
        return KIN_ERANGE;
    }
    kin__hom_zero_records(ends, total);
    hom_solver H;
    hom_endset E = {NULL, NULL, NULL};
    int *path = malloc(sizeof(int) * (size_t)total);
    O.slot = malloc(sizeof(int) * (size_t)O.npaths);
    rc = !path || !O.slot ? KIN_ENOMEM : kin__hom_solver_init(&H, m, s, Qt, &o, n);
    if (!path || !O.slot) memset(&H, 0, sizeof H);
    if (!rc) rc = kin__hom_endset_alloc(&E, (int)total, m);
    if (!rc) {
        long k = 0;
        for (int i = first; i < first + n; ++i) {
            int r = O.reps[i], c = r;
            do path[k] = c, O.slot[c] = (int)k, ++k, c = O.next[c];
            while (c != r);
        }
        H.orb = &O;
        hom_report Rp = {o.progress, o.user, 0.0, (double)n, 0.0, 0};
        kin__hom_report_start(&Rp);
        if (Rp.cancelled) rc = KIN_ECANCELLED;
        if (!rc) rc = kin__hom_run(&H, &kin__hom_base_settings, O.reps + first, 0, n, 0, E.ends, E.zr, E.zi, &Rp);
        if (!rc && Rp.cancelled) rc = KIN_ECANCELLED;
        if (!rc) {
            for (long i = 0; i < total; ++i)
                kin__hom_export(m, path[i], &E.ends[i], E.zr + (size_t)i * m, E.zi + (size_t)i * m, &ends[i],
                                z + (size_t)2 * m * i);
            *nends = total;
            if (Rp.fn) Rp.fn(Rp.user, Rp.total, Rp.total); /* finished: its answer no longer matters */
        }
    }
    if (rc) kin__hom_zero_records(ends, total);
    kin__hom_endset_free(&E);
    kin__hom_solver_free(&H);
    free(path);
    kin__orbits_free(&O);
    return rc;
}
