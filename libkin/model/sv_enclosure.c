/* Rigorous enclosures of the singular values of the equilibrium matrix H at
 * the current configuration (issue 38 item 2), in Arb's ball arithmetic.
 *
 * H is the exact matrix at the current (double) coordinates: its entries
 * (x_a - x_b)_c / L with L the exact bar length, enclosed as balls. The
 * dense analysis gave H ~ U S V^T in floating point (U, V square). Write
 * H' = U S V^T (the exact product of the computed factors). Weyl:
 * |sigma_i(H) - sigma_i(H')| <= |H - H'|_2 <= |H - H'|_F = delta. And
 * sigma_min(U) sigma_min(V) s_i <= sigma_i(H') <= |U|_2 |V|_2 s_i, with
 * |U|_2^2 <= 1 + eU, sigma_min(U)^2 >= 1 - eU for eU = |U^T U - I|_F (the
 * same for V). So
 *     s_i sqrt((1 - eU)(1 - eV)) - delta <= sigma_i(H) <= s_i sqrt((1 + eU)(1 + eV)) + delta,
 * every quantity an upper or lower bound from Arb (its balls contain the
 * exact values: the assumption). Cost O(nf nb min(nf, nb) + nf^3 + nb^3)
 * ball operations: milliseconds for the sails; refused above MAX_WORK. */
#include <math.h>

#include <arb.h>

#include "model/internal.h"

/* ball multiply-adds beyond which no enclosure is attempted (seconds) */
static const double MAX_WORK = 3e8;
enum { PREC = 64 };

/* z = x + d, x - d for a double d */
static void add_d(arb_t z, const arb_t x, double d, int sign)
{
    arb_t t;
    arb_init(t);
    arb_set_d(t, d);
    if (sign > 0) arb_add(z, x, t, PREC);
    else arb_sub(z, x, t, PREC);
    arb_clear(t);
}

/* H as balls (nf x nb, column-major) */
static void exact_H(const kin_assembly *a, arb_ptr H)
{
    int nf = a->nf, dim = a->dim;
    arb_t L, d, t;
    arb_init(L), arb_init(d), arb_init(t);
    for (int k = 0; k < a->nb; ++k) {
        arb_ptr col = H + (size_t)k * nf;
        int ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
        arb_zero(L);
        for (int c = 0; c < dim; ++c) {
            arb_set_d(d, a->xyz[ja * dim + c]);
            arb_set_d(t, a->xyz[jb * dim + c]);
            arb_sub(d, d, t, PREC);
            arb_addmul(L, d, d, PREC);
        }
        arb_sqrt(L, L, PREC);
        for (int c = 0; c < dim; ++c) {
            arb_set_d(d, a->xyz[ja * dim + c]);
            arb_set_d(t, a->xyz[jb * dim + c]);
            arb_sub(d, d, t, PREC);
            arb_div(d, d, L, PREC);
            int ra = a->free_index[ja * dim + c], rb = a->free_index[jb * dim + c];
            if (ra >= 0) arb_add(col + ra, col + ra, d, PREC);
            if (rb >= 0) arb_sub(col + rb, col + rb, d, PREC);
        }
    }
    arb_clear(L), arb_clear(d), arb_clear(t);
}

/* |Q^T Q - I|_F for Q n x n (column-major, ld n): an upper bound */
static double orthogonality(const double *Q, int n, int transposed)
{
    arb_ptr x = _arb_vec_init(n), y = _arb_vec_init(n);
    arb_t t, sum;
    arb_init(t), arb_init(sum);
    mag_t m;
    mag_init(m);
    for (int i = 0; i < n; ++i)
        for (int j = i; j < n; ++j) {
            for (int r = 0; r < n; ++r) {
                /* columns i, j of Q (rows if transposed: Q holds V^T) */
                arb_set_d(x + r, transposed ? Q[i + (size_t)r * n] : Q[r + (size_t)i * n]);
                arb_set_d(y + r, transposed ? Q[j + (size_t)r * n] : Q[r + (size_t)j * n]);
            }
            arb_dot(t, NULL, 0, x, 1, y, 1, n, PREC);
            if (i == j) arb_sub_ui(t, t, 1, PREC);
            arb_sqr(t, t, PREC);
            if (i != j) arb_mul_2exp_si(t, t, 1);
            arb_add(sum, sum, t, PREC);
        }
    arb_sqrt(sum, sum, PREC);
    arb_get_mag(m, sum);
    double e = mag_get_d(m);
    mag_clear(m);
    arb_clear(t), arb_clear(sum);
    _arb_vec_clear(x, n), _arb_vec_clear(y, n);
    return e;
}

/* |H - U S V^T|_F: an upper bound */
static double residual(const kin_assembly *a, const kin_factor *f, arb_srcptr H)
{
    int nf = a->nf, nb = a->nb, p = nf < nb ? nf : nb;
    arb_ptr u = _arb_vec_init(p), w = _arb_vec_init(p);
    arb_t t, sum;
    arb_init(t), arb_init(sum);
    for (int k = 0; k < nb; ++k) {
        for (int q = 0; q < p; ++q) { /* w_q = s_q V^T[q, k] */
            arb_set_d(w + q, f->sv[q]);
            arb_set_d(t, f->VT[q + (size_t)k * nb]);
            arb_mul(w + q, w + q, t, PREC);
        }
        for (int i = 0; i < nf; ++i) {
            for (int q = 0; q < p; ++q) arb_set_d(u + q, f->U[i + (size_t)q * nf]);
            arb_dot(t, H + (size_t)k * nf + i, 1, u, 1, w, 1, p, PREC);
            arb_addmul(sum, t, t, PREC);
        }
    }
    arb_sqrt(sum, sum, PREC);
    mag_t m;
    mag_init(m);
    arb_get_mag(m, sum);
    double e = mag_get_d(m);
    mag_clear(m);
    arb_clear(t), arb_clear(sum);
    _arb_vec_clear(u, p), _arb_vec_clear(w, p);
    return e;
}

int kin__sv_enclose(const kin_assembly *a, int i, double *lo, double *hi, double *max_lo)
{
    const kin_factor *f = kin__cur(a);
    int nf = a->nf, nb = a->nb, p = nf < nb ? nf : nb;
    if (!f->valid || !f->sv || !f->U || !f->VT || i < 0 || i >= p) return 0;
    double work = (double)nf * nb * p + (double)nf * nf * nf + (double)nb * nb * nb;
    if (work > MAX_WORK) return 0;
    arb_ptr H = _arb_vec_init((slong)nf * nb);
    exact_H(a, H);
    double delta = residual(a, f, H);
    _arb_vec_clear(H, (slong)nf * nb);
    double eU = orthogonality(f->U, nf, 0), eV = orthogonality(f->VT, nb, 1);
    if (!(eU < 0.5) || !(eV < 0.5) || !isfinite(delta)) return 0;
    /* in balls, so that the bounds are rigorous */
    arb_t s, g, t;
    arb_init(s), arb_init(g), arb_init(t);
    arf_t b;
    arf_init(b);
    /* the factors' distortion: fl <= sqrt((1 - eU)(1 - eV)), fh >= sqrt((1 + eU)(1 + eV)) */
    double fl, fh;
    arb_one(g), add_d(g, g, eU, -1), arb_one(t), add_d(t, t, eV, -1);
    arb_mul(g, g, t, PREC), arb_sqrt(g, g, PREC);
    arb_get_lbound_arf(b, g, PREC), fl = arf_get_d(b, ARF_RND_FLOOR);
    arb_one(g), add_d(g, g, eU, 1), arb_one(t), add_d(t, t, eV, 1);
    arb_mul(g, g, t, PREC), arb_sqrt(g, g, PREC);
    arb_get_ubound_arf(b, g, PREC), fh = arf_get_d(b, ARF_RND_CEIL);
    for (int k = 0; k < 2; ++k) {
        arb_set_d(s, f->sv[k ? 0 : i]);
        arb_set_d(g, fl), arb_mul(t, s, g, PREC), add_d(t, t, delta, -1);
        arb_get_lbound_arf(b, t, PREC);
        double l = arf_get_d(b, ARF_RND_FLOOR);
        arb_set_d(g, fh), arb_mul(t, s, g, PREC), add_d(t, t, delta, 1);
        arb_get_ubound_arf(b, t, PREC);
        double h = arf_get_d(b, ARF_RND_CEIL);
        if (k) *max_lo = fmax(l, 0.0);
        else *lo = fmax(l, 0.0), *hi = h;
    }
    arf_clear(b);
    arb_clear(s), arb_clear(g), arb_clear(t);
    return 1;
}
