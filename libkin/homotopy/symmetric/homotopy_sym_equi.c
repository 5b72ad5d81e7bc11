/* The symmetric complete solver's equivariant route (homotopy_sym.h): the
 * plain solver's total-degree homotopy in coordinates where a cyclic
 * subgroup of the symmetry permutes coordinates and equations alike
 * (homotopy_equi.c), one path per orbit of start roots. Every one of the
 * 2^s endpoints is stored (the others are the representative's permuted,
 * each refined and certified on its own), so the plain solver's checks,
 * re-tracks (of the suspects' representatives) and accounting apply
 * unchanged; the real solutions are then taken back to beta = U x.
 *
 * On the hexagonal sail's flat state (C3 permuting 5 triples of
 * mechanisms and of self-stresses) that is 10944 paths instead of 32768;
 * on the octagonal two-loop sail's (C4, 5 cycles of 4) 262416 instead of
 * 1048576.
 *
 * Also here: the plain route (every path of the caller's system), which the
 * solver takes when no subgroup qualifies and the group is too small for
 * the monodromy to pay off. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/symmetric/homotopy_equi.h"
#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"

/* the real solutions x -> beta = U x, unit and with the largest entry
 * positive as the tally leaves them; the largest residual of the returned
 * ones in the caller's scaled system (Qr) */
static double to_beta(int m, int s, const double *U, const double *Qr, double *betas, int n)
{
    double res = 0.0;
    for (int i = 0; i < n; ++i) {
        double *b = betas + (size_t)i * m, y[HOM_MAX_M];
        for (int r = 0; r < m; ++r) {
            double v = 0.0;
            for (int c = 0; c < m; ++c) v += U[c * m + r] * b[c];
            y[r] = v;
        }
        kin__hom_unit_beta(m, y);
        memcpy(b, y, sizeof(double) * (size_t)m);
        res = fmax(res, kin__hom_residual(m, s, Qr, b));
    }
    return res;
}

int kin__sym_equi_solve(const hom_solver *H0, const sym_group *G, const kin_homotopy_options *o, double *betas,
                        int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *si,
                        int *used)
{
    int m = H0->P.m, s = H0->P.s;
    *used = 0;
    hom_equi E;
    int rc = kin__equi_plan(&E, m, s, H0->Qr, G, (unsigned long long)o->seed);
    if (rc || E.k == 0) return rc;
    *used = 1;
    hom_orbits O;
    hom_solver H;
    memset(&H, 0, sizeof H);
    long tracked = 0;
    if ((rc = kin__orbits_init(&O, m, E.perm))) goto done;
    if ((rc = kin__hom_solver_init(&H, m, s, E.Qt, o, O.nreps))) goto done;
    H.orb = &O;
    H.Qin = H0->Qin, H.U = E.U; /* proven on the caller's system */
    rc = kin__hom_solve(&H, O.reps, O.nreps, o, betas, maxsol, nsol, multiplicity, info, &tracked);
    if (rc) goto done;
    info->max_residual = fmax(info->max_residual, to_beta(m, s, E.U, H0->Qr, betas, *nsol));
    si->group = G->n;
    si->orbits = O.nreps;
    si->found = H.npaths;
    si->monodromy_paths = 0;
    si->final_paths = (int)tracked;
done:
    kin__hom_solver_free(&H);
    kin__orbits_free(&O);
    kin__equi_free(&E);
    return rc;
}

int kin__sym_plain_solve(hom_solver *H, const sym_group *G, const kin_homotopy_options *o, double *betas,
                         int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info, kin_homotopy_sym_info *si)
{
    long tracked = 0;
    int rc = kin__hom_solve(H, NULL, H->npaths, o, betas, maxsol, nsol, multiplicity, info, &tracked);
    if (rc) return rc;
    si->group = G->n;
    si->orbits = H->npaths;
    si->found = H->npaths;
    si->monodromy_paths = 0;
    si->final_paths = (int)tracked;
    return KIN_OK;
}
