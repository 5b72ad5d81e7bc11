/* The rational (Pade) predictor of the complete solvers' trackers: the
 * plain solver's (homotopy_track.c and, operation for operation,
 * homotopy_batch.c) and the symmetric solver's (homotopy_param.c and
 * homotopy_param_batch.c), whose series differ only in their order.
 *
 * Why: on clustered systems (the sails' flat states) the Taylor series of
 * a path has a small radius of convergence rho, set by the nearest complex
 * singularity of the path (a branch point where it nears another path),
 * and its truncation error grows like (h / rho)^(K+1): the step stays at
 * about rho / 2. An approximant with a denominator models that singularity
 * and is typically ten times more accurate at the same step and usable
 * further (measured in docs/performance.md). Its error has no simple
 * model, but the difference between the approximants of two consecutive
 * orders estimates it step by step; the estimate is calibrated along the
 * path like the Taylor model. Safety does not depend on it: the corrector's
 * test (the first correction a small fraction of the separation radius) is
 * the same whatever the predictor. See homotopy_pade.h for the
 * formulas. */
#include <math.h>

#include "homotopy/track/homotopy_control.h"

/* h^(K - 1) by multiplications (pow is costly, and this is exact enough: a
 * few roundings) */
static double hpow(int K, double h)
{
    double p = 1.0;
    for (int k = 0; k < K - 1; ++k) p *= h;
    return p;
}

void kin__hom_pade_setup(int m, const double (*cr)[HOM_MAX_M], const double (*ci)[HOM_MAX_M], hom_pade *pd)
{
    kin__hom_pade_setup_order(HOM_ORDER, m, cr, ci, pd);
}

void kin__hom_pade_setup_order(int K, int m, const double (*cr)[HOM_MAX_M], const double (*ci)[HOM_MAX_M],
                               hom_pade *pd)
{
    const double *ar = cr[K - 2], *ai = ci[K - 2], *br = cr[K - 1], *bi = ci[K - 1], *dr = cr[K], *di = ci[K];
    double g1 = 0.0, g2 = 0.0, g12r = 0.0, g12i = 0.0, g1dr = 0.0, g1di = 0.0;
    for (int c = 0; c < m; ++c) {
        g2 += ar[c] * ar[c] + ai[c] * ai[c];
        g1 += br[c] * br[c] + bi[c] * bi[c];
        g12r += ar[c] * br[c] + ai[c] * bi[c]; /* conj(c_{K-2}) c_{K-1} */
        g12i += ar[c] * bi[c] - ai[c] * br[c];
        g1dr += br[c] * dr[c] + bi[c] * di[c]; /* conj(c_{K-1}) c_K */
        g1di += br[c] * di[c] - bi[c] * dr[c];
    }
    pd->g1 = g1, pd->g2 = g2, pd->g12r = g12r, pd->g12i = g12i, pd->order = K;
    pd->ok = g1 > 0.0 && g2 > 0.0 && isfinite(g1) && isfinite(g2) && isfinite(g1dr + g1di) && isfinite(g12r + g12i);
    pd->qr = pd->ok ? g1dr / g1 : 0.0, pd->qi = pd->ok ? g1di / g1 : 0.0;
    pd->q2r = pd->ok ? g12r / g2 : 0.0, pd->q2i = pd->ok ? g12i / g2 : 0.0;
    pd->qabs = sqrt(pd->qr * pd->qr + pd->qi * pd->qi);
}

double kin__hom_pade_error(const hom_pade *pd, double h)
{
    if (!pd->ok || !(pd->qabs * h <= PADE_POLE)) return INFINITY;
    /* a = 1 / (1 - q h), b = q' / (1 - q' h) */
    double dr = 1.0 - pd->qr * h, di = -pd->qi * h, d2 = dr * dr + di * di;
    double ar = dr / d2, ai = -di / d2;
    double er = 1.0 - pd->q2r * h, ei = -pd->q2i * h, e2 = er * er + ei * ei;
    double br = (pd->q2r * er + pd->q2i * ei) / e2, bi = (pd->q2i * er - pd->q2r * ei) / e2;
    /* |a c_{K-1} - b c_{K-2}|^2 = |a|^2 g1 + |b|^2 g2 - 2 Re(a conj(b) g12) */
    double abr = ar * br + ai * bi, abi = ai * br - ar * bi;
    double s = (ar * ar + ai * ai) * pd->g1 + (br * br + bi * bi) * pd->g2 - 2.0 * (abr * pd->g12r - abi * pd->g12i);
    double e = hpow(pd->order, h) * sqrt(fmax(s, 0.0));
    return isfinite(e) && d2 > 0.0 && e2 > 0.0 ? e : INFINITY;
}

double kin__hom_pade_extend(const hom_pade *pd, double h, double lim, double sigma, double tol, double *err)
{
    while (h < sigma) {
        double h2 = h * PADE_GROW;
        if (!(h2 <= lim)) break;
        if (h2 > sigma) h2 = sigma;
        double e2 = kin__hom_pade_error(pd, h2);
        if (!(e2 <= tol)) break;
        h = h2, *err = e2;
    }
    return h;
}

void kin__hom_pade_predict(int m, const double (*cr)[HOM_MAX_M], const double (*ci)[HOM_MAX_M], const hom_pade *pd,
                           double h, double *xr, double *xi)
{
    const int K = pd->order;
    /* w = h^{K-1} / (1 - q h) */
    double dr = 1.0 - pd->qr * h, di = -pd->qi * h, d2 = dr * dr + di * di, hp = hpow(K, h);
    double wr = hp * dr / d2, wi = -hp * di / d2;
    for (int c = 0; c < m; ++c) {
        double vr = cr[K - 2][c], vi = ci[K - 2][c];
        for (int k = K - 3; k >= 0; --k) {
            vr = vr * h + cr[k][c];
            vi = vi * h + ci[k][c];
        }
        xr[c] = vr + (wr * cr[K - 1][c] - wi * ci[K - 1][c]);
        xi[c] = vi + (wr * ci[K - 1][c] + wi * cr[K - 1][c]);
    }
}
