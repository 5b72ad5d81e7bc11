/* kin_quadrics_homotopy_sym (kin_branch.h): the arguments, the group, and
 * the route: the equivariant start system where a cyclic subgroup permutes
 * mechanisms and equations alike (homotopy_sym_equi.c), else every path
 * for a small group, else the monodromy (homotopy_sym.c). */
#include <math.h>
#include <string.h>

#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"

static int sym_impl(int route, int m, int s, const double *Q, int ngroup, const double *R,
                    const kin_homotopy_options *o, double *betas, int maxsol, int *nsol, int *multiplicity,
                    kin_homotopy_info *info, kin_homotopy_sym_info *si, char *err, size_t errlen)
{
    if (!Q || !betas || !nsol || (ngroup > 0 && !R)) return KIN_ENULL;
    if (maxsol < 1 || ngroup < 0 || m < 2 || s != m - 1 || o->nthreads < 0 || o->max_paths < 1)
        return kin__failbuf(err, errlen, KIN_EINVAL, "bad size or option (m = %d, s = %d, ngroup = %d, maxsol = %d)",
                          m, s, ngroup, maxsol);
    if (m > HOM_MAX_M) return kin__failbuf(err, errlen, KIN_ERANGE, "m = %d > %d", m, HOM_MAX_M);
    for (size_t i = 0; i < (size_t)m * m * s; ++i)
        if (!isfinite(Q[i])) return kin__failbuf(err, errlen, KIN_EINVAL, "Q has a NaN or infinite entry");
    if ((1L << s) > o->max_paths) return kin__failbuf(err, errlen, KIN_ELIMIT, "2^%d paths > max_paths", s);
    sym_ctx C;
    memset(&C, 0, sizeof C);
    C.fn = o->progress, C.user = o->user;
    int rc = kin__hom_solver_init(&C.H, m, s, Q, o, 1L << (m - 1));
    if (!rc) rc = kin__sym_group_init(&C.G, m, s, C.H.Qr, ngroup, R, err, errlen);
    if (!rc && route == KIN__SYM_AUTO) {
        /* the equivariant start system where a subgroup allows it; else,
         * for a small group, every path (the monodromy would cost more) */
        int used = 0;
        rc = kin__sym_equi_solve(&C.H, &C.G, o, betas, maxsol, nsol, multiplicity, info, si, &used);
        if (!rc && !used && C.G.n < SYM_MONODROMY_MIN_GROUP) {
            used = 1;
            rc = kin__sym_plain_solve(&C.H, &C.G, o, betas, maxsol, nsol, multiplicity, info, si);
        }
        if (rc == KIN_ECANCELLED) kin__failbuf(err, errlen, rc, "cancelled");
        else if (rc) kin__failbuf(err, errlen, rc, "%s", kin_strerror(rc));
        if (rc || used) {
            if (rc) memset(info, 0, sizeof *info), *nsol = 0;
            kin__sym_ctx_free(&C);
            return rc;
        }
    }
    if (!rc) rc = kin__sym_monodromy_solve(&C, o, betas, maxsol, nsol, multiplicity, info, si, err, errlen);
    else if (rc != KIN_ENOTCONVERGED) memset(info, 0, sizeof *info), *nsol = 0;
    kin__sym_ctx_free(&C);
    return rc;
}

int kin__quadrics_homotopy_sym_route(int route, int m, int s, const double *Q, int ngroup, const double *R,
                                     const kin_homotopy_options *opt, double *betas, int maxsol, int *nsol,
                                     int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *sinfo,
                                     char *err, size_t errlen)
{
    if (err && errlen > 0) err[0] = '\0';
    if (nsol) *nsol = 0;
    if (!info) return kin__failbuf(err, errlen, KIN_ENULL, "info is NULL");
    if (kin__abi_check(info, KIN__ABI(kin_homotopy_info)))
        return kin__failbuf(err, errlen, KIN_EINVAL, "info->size");
    kin__abi_zero(info);
    if (sinfo) {
        if (kin__abi_check(sinfo, KIN__ABI(kin_homotopy_sym_info)))
            return kin__failbuf(err, errlen, KIN_EINVAL, "sinfo->size");
        kin__abi_zero(sinfo);
    }
    kin_homotopy_options o;
    if (kin__hom_options(opt, &o)) return kin__failbuf(err, errlen, KIN_EINVAL, "opt->size");
    kin_homotopy_info local = {.size = sizeof local};
    kin_homotopy_sym_info slocal = {.size = sizeof slocal};
    int rc = sym_impl(route, m, s, Q, ngroup, R, &o, betas, maxsol, nsol, multiplicity, &local, &slocal, err, errlen);
    if (rc && rc != KIN_ENOTCONVERGED) memset(&slocal, 0, sizeof slocal), slocal.size = sizeof slocal;
    local.size = sizeof local;
    kin__abi_write(info, &local, KIN__ABI(kin_homotopy_info));
    if (sinfo) kin__abi_write(sinfo, &slocal, KIN__ABI(kin_homotopy_sym_info));
    return rc;
}

int kin_quadrics_homotopy_sym(int m, int s, const double *Q, int ngroup, const double *R,
                              const kin_homotopy_options *opt, double *betas, int maxsol, int *nsol,
                              int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *sinfo, char *err,
                              size_t errlen)
{
    return kin__quadrics_homotopy_sym_route(KIN__SYM_AUTO, m, s, Q, ngroup, R, opt, betas, maxsol, nsol,
                                            multiplicity, info, sinfo, err, errlen);
}
