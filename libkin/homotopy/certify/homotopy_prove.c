/* The Krawczyk test of one endpoint of the complete solver, in Arb's ball
 * arithmetic (issue 38; homotopy_prove.h).
 *
 * In the chart x_k = 1 the system is f: C^s -> C^s, f_j(y) = x^T Q_j x with
 * x = (y, 1 at k); its Jacobian J(y)_{j,i} = 2 (Q_j x)_{c(i)} is affine in
 * y (f is quadratic). Take a centre y (exact: the midpoints of balls), Y
 * any matrix (a floating inverse of J(y)), the max norm |.| on C^s (the
 * complex modulus of each coordinate) and its operator norm (the largest
 * row sum of moduli), and bound, rigorously in ball arithmetic,
 *     eta >= |Y f(y)|,  rho >= |I - Y J(y)|,
 *     L   >= 2 max_a sum_j |Y_aj| S_j,  S_j >= sum_{r,c} |Q_j(r,c)|,
 * so that |I - Y J(z)| <= rho + L |z - y| for every z (J(z) - J(y) is
 * 2 Q_j (z - y), entry by entry at most 2 S_j |z - y| in row sum). On the
 * closed polydisc B = B(y, r) the Krawczyk operator of g(z) = z - Y f(z)
 * then lies in B(y, eta + (rho + L r) r): when that radius is < r, g maps B
 * into its interior and is a contraction there (rho + L r < 1), so g has
 * exactly one fixed point in B (Banach); Y is invertible (|I - Y J(y)| < 1),
 * so that point is the only solution of f in B, and J is invertible there:
 * a simple root. r = 2 eta / (1 - rho) satisfies the test whenever
 * 4 L eta < (1 - rho)^2.
 * A box centred on a real y is its own conjugate; Q is real, so the
 * conjugate of its one solution is a solution in the box too, hence the
 * same one: it is real. A box that misses the real line in some coordinate
 * (|Im y_c| > r) holds no real point: its solution is non-real.
 * The proof rests on Arb's enclosures being correct (its balls contain the
 * exact results; Arb's documented rounding) and on nothing computed in
 * floating point: Y and y are exact numbers whatever their accuracy. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <acb.h>
#include <acb_mat.h>

#include "homotopy/certify/homotopy_prove.h"
#include "homotopy/certify/homotopy_prove_exact.h"
#include "homotopy/certify/homotopy_prove_fast.h"

struct hom_prover {
    int m, s;
    arb_ptr Q;          /* s m m: Q[(j m + r) m + c], the symmetric part of Q_j (enclosed) */
    mag_ptr S;          /* s: S_j >= sum_{r,c} |Q_j(r,c)| */
    acb_ptr x;          /* m: the centre, exact (zero radii); x_k = 1 */
    acb_ptr u;          /* s m: Q_j x */
    acb_ptr f;          /* s: f(x) */
    acb_ptr J;          /* s s, row-major: J[j s + i] = df_j / dx_{c(i)} */
    acb_mat_t Jm, Y;    /* s x s: J's midpoints, their approximate inverse */
    acb_mat_t B, D;     /* s x 1: f's midpoints, the Newton step */
    acb_t one, t;
    mag_t eta, rho, L, r, tm, row, lhs;
    hom_fast *fast;     /* the test in double precision, tried first if use_fast */
    hom_exact *exact;   /* the bounds by exact integer products, tried next */
    int use_fast;       /* 0: no double-precision test (Arb and FLINT only) */
    double cr[HOM_PROVE_MAX_M], ci[HOM_PROVE_MAX_M]; /* the centre as doubles */
};

/* the free coordinate i of chart k */
static int col(int k, int i) { return i < k ? i : i + 1; }

hom_prover *kin__prove_new(int m, int s, const double *Q)
{
    if (m < 2 || m > HOM_PROVE_MAX_M || s != m - 1) return NULL;
    hom_prover *w = calloc(1, sizeof *w);
    if (!w) return NULL;
    size_t mm = (size_t)m * m;
    w->m = m, w->s = s;
    w->use_fast = 0; /* kin_homotopy_options.prove's default: Arb and FLINT only */
    w->Q = _arb_vec_init((slong)(mm * s));
    w->S = _mag_vec_init(s);
    w->x = _acb_vec_init(m);
    w->u = _acb_vec_init((slong)s * m);
    w->f = _acb_vec_init(s);
    w->J = _acb_vec_init((slong)s * s);
    acb_mat_init(w->Jm, s, s), acb_mat_init(w->Y, s, s);
    acb_mat_init(w->B, s, 1), acb_mat_init(w->D, s, 1);
    acb_init(w->one), acb_init(w->t);
    acb_one(w->one);
    mag_init(w->eta), mag_init(w->rho), mag_init(w->L), mag_init(w->r);
    mag_init(w->tm), mag_init(w->row), mag_init(w->lhs);
    arb_t a, b;
    arb_init(a), arb_init(b);
    for (int j = 0; j < s; ++j) {
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c) {
                arb_ptr q = w->Q + ((size_t)j * m + r) * m + c;
                arb_set_d(a, Q[j * mm + r + (size_t)c * m]);
                arb_set_d(b, Q[j * mm + c + (size_t)r * m]);
                arb_add(q, a, b, 128); /* exact for doubles of close exponents; else a ball */
                arb_mul_2exp_si(q, q, -1);
                arb_get_mag(w->tm, q);
                mag_add(w->S + j, w->S + j, w->tm);
            }
        /* the input's own uncertainty (HOM_PROVE_Q_WIDTH): every entry a
         * ball of that radius more, S_j enlarged to cover it */
        mag_set_d(w->tm, HOM_PROVE_Q_WIDTH);
        mag_mul(w->row, w->S + j, w->tm);
        for (size_t e = 0; e < mm; ++e) arb_add_error_mag(w->Q + (size_t)j * mm + e, w->row);
        mag_mul_2exp_si(w->tm, w->row, 0);
        for (size_t e = 0; e < mm; ++e) mag_add(w->S + j, w->S + j, w->tm);
    }
    arb_clear(a), arb_clear(b);
    double S[HOM_PROVE_MAX_M];
    for (int j = 0; j < s; ++j) S[j] = mag_get_d(w->S + j); /* an upper bound */
    if (!(w->fast = kin__fast_new(m, s, Q, S)) || !(w->exact = kin__exact_new(m, s, w->Q, w->S))) {
        kin__prove_free(w);
        return NULL;
    }
    return w;
}

void kin__prove_use_fast(hom_prover *w, int on) { w->use_fast = on != 0; }

void kin__prove_thread_end(void) { flint_cleanup(); }

void kin__prove_free(hom_prover *w)
{
    if (!w) return;
    int m = w->m, s = w->s;
    _arb_vec_clear(w->Q, (slong)m * m * s);
    _mag_vec_clear(w->S, s);
    _acb_vec_clear(w->x, m);
    _acb_vec_clear(w->u, (slong)s * m);
    _acb_vec_clear(w->f, s);
    _acb_vec_clear(w->J, (slong)s * s);
    acb_mat_clear(w->Jm), acb_mat_clear(w->Y), acb_mat_clear(w->B), acb_mat_clear(w->D);
    acb_clear(w->one), acb_clear(w->t);
    mag_clear(w->eta), mag_clear(w->rho), mag_clear(w->L), mag_clear(w->r);
    mag_clear(w->tm), mag_clear(w->row), mag_clear(w->lhs);
    kin__fast_free(w->fast);
    kin__exact_free(w->exact);
    free(w);
}

/* u = Q_j x, f(x) and J(x) enclosed at prec bits (x exact) */
static void eval(hom_prover *w, int k, slong prec)
{
    int m = w->m, s = w->s;
    arb_srcptr xr = (arb_srcptr)w->x, xi = xr + 1; /* an acb is its real then imaginary arb */
    for (int j = 0; j < s; ++j) {
        for (int r = 0; r < m; ++r) {
            arb_srcptr q = w->Q + ((size_t)j * m + r) * m;
            acb_ptr u = w->u + (size_t)j * m + r;
            arb_dot(acb_realref(u), NULL, 0, q, 1, xr, 2, m, prec);
            arb_dot(acb_imagref(u), NULL, 0, q, 1, xi, 2, m, prec);
        }
        acb_dot(w->f + j, NULL, 0, w->x, 1, w->u + (size_t)j * m, 1, m, prec);
        for (int i = 0; i < s; ++i) acb_mul_2exp_si(w->J + (size_t)j * s + i, w->u + (size_t)j * m + col(k, i), 1);
    }
}

/* Newton steps x -= J^-1 f in approximate arithmetic at prec bits (x stays
 * exact; real x stays real). 0 if J is numerically singular. */
static int newton(hom_prover *w, int k, slong prec, int steps, int real)
{
    int s = w->s;
    for (int it = 0; it < steps; ++it) {
        eval(w, k, prec);
        for (int j = 0; j < s; ++j) {
            for (int i = 0; i < s; ++i) acb_get_mid(acb_mat_entry(w->Jm, j, i), w->J + (size_t)j * s + i);
            acb_get_mid(acb_mat_entry(w->B, j, 0), w->f + j);
        }
        if (!acb_mat_approx_solve(w->D, w->Jm, w->B, prec)) return 0;
        for (int i = 0; i < s; ++i) {
            acb_ptr xc = w->x + col(k, i);
            acb_sub(xc, xc, acb_mat_entry(w->D, i, 0), prec);
            acb_get_mid(xc, xc);
            if (real) arb_zero(acb_imagref(xc));
        }
    }
    return 1;
}

/* the test on w->eta, rho, L (module comment): 1 and w->r, or 0 */
static int conclude(hom_prover *w, slong prec)
{
    if (mag_cmp_2exp_si(w->rho, 0) >= 0) return 0; /* rho >= 1 */
    mag_one(w->tm);
    mag_sub_lower(w->tm, w->tm, w->rho); /* <= 1 - rho */
    if (mag_is_zero(w->tm)) return 0;
    if (mag_is_zero(w->eta)) mag_set_ui_2exp_si(w->eta, 1, -2 * prec); /* an exact root: any small box */
    mag_mul_2exp_si(w->r, w->eta, 1);
    mag_div(w->r, w->r, w->tm); /* r = 2 eta / (1 - rho), rounded up: any r will do */
    /* eta + rho r + L r^2 < r */
    mag_mul(w->lhs, w->L, w->r);
    mag_add(w->lhs, w->lhs, w->rho);
    mag_mul(w->lhs, w->lhs, w->r);
    mag_add(w->lhs, w->lhs, w->eta);
    return mag_cmp(w->lhs, w->r) < 0;
}

/* The Krawczyk test at x (module comment): 1 and w->r = the radius of a
 * box holding exactly one solution, or 0. */
static int krawczyk(hom_prover *w, int k, slong prec)
{
    int s = w->s;
    eval(w, k, prec);
    for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) acb_get_mid(acb_mat_entry(w->Jm, j, i), w->J + (size_t)j * s + i);
    if (!acb_mat_approx_inv(w->Y, w->Jm, prec)) return 0;
    mag_zero(w->eta), mag_zero(w->rho), mag_zero(w->L);
    for (int a = 0; a < s; ++a) {
        acb_srcptr ya = acb_mat_entry(w->Y, a, 0);
        for (int j = 0; j < s; ++j) acb_get_mid(acb_mat_entry(w->Y, a, j), acb_mat_entry(w->Y, a, j));
        acb_dot(w->t, NULL, 0, ya, 1, w->f, 1, s, prec); /* (Y f)_a */
        acb_get_mag(w->tm, w->t);
        mag_max(w->eta, w->eta, w->tm);
        mag_zero(w->row);
        for (int i = 0; i < s; ++i) { /* (I - Y J)_ai */
            acb_dot(w->t, a == i ? w->one : NULL, 1, ya, 1, w->J + i, s, s, prec);
            acb_get_mag(w->tm, w->t);
            mag_add(w->row, w->row, w->tm);
        }
        mag_max(w->rho, w->rho, w->row);
        mag_zero(w->row);
        for (int j = 0; j < s; ++j) { /* sum_j |Y_aj| S_j */
            acb_get_mag(w->tm, ya + j);
            mag_mul(w->tm, w->tm, w->S + j);
            mag_add(w->row, w->row, w->tm);
        }
        mag_max(w->L, w->L, w->row);
    }
    mag_mul_2exp_si(w->L, w->L, 1);
    return conclude(w, prec);
}

/* the centre from the endpoint, in chart k (real: its real part), made a
 * multiple of 2^-60 and written to x exactly (kin__exact_centre) */
static void centre(hom_prover *w, const double *zr, const double *zi, int k, int real)
{
    double d = zr[k] * zr[k] + zi[k] * zi[k];
    for (int c = 0; c < w->m; ++c) {
        double vr = (zr[c] * zr[k] + zi[c] * zi[k]) / d, vi = (zi[c] * zr[k] - zr[c] * zi[k]) / d;
        if (c == k) vr = 1.0, vi = 0.0;
        w->cr[c] = vr, w->ci[c] = real ? 0.0 : vi;
    }
    if (!kin__exact_centre(w->exact, w->cr, w->ci, real, w->x))
        for (int c = 0; c < w->m; ++c) /* NaN: no proof; a part >= 1.25 (rounding cannot give that in a
                                          chart of the largest coordinate): the doubles, exact, for the balls */
            acb_set_d_d(w->x + c, w->cr[c], w->ci[c]);
}

/* the proven box written out: centre rounded to doubles, r enlarged by the
 * rounding; the kind from the stored box */
static void store(hom_prover *w, int k, int real, slong prec, double *zr, double *zi, hom_proof *out)
{
    int m = w->m, misses = 0;
    arf_t e, d;
    arf_init(e), arf_init(d);
    mag_zero(w->row);
    for (int c = 0; c < m; ++c)
        for (int part = 0; part < 2; ++part) {
            arf_srcptr mid = arb_midref(part ? acb_imagref(w->x + c) : acb_realref(w->x + c));
            double v = part && real ? 0.0 : arf_get_d(mid, ARF_RND_NEAR);
            if (part) zi[c] = v;
            else zr[c] = v;
            arf_set_d(d, v);
            arf_sub(e, mid, d, prec, ARF_RND_UP); /* |e| >= |mid - v| */
            arf_get_mag(w->tm, e);
            mag_max(w->row, w->row, w->tm);
        }
    arf_clear(e), arf_clear(d);
    /* |x - d| <= sqrt(2) max(|dRe|, |dIm|) <= 2 max */
    mag_mul_2exp_si(w->row, w->row, 1);
    mag_add(w->row, w->row, w->r);
    out->r = mag_get_d(w->row);
    for (int c = 0; c < m; ++c) misses |= c != k && fabs(zi[c]) > out->r;
    out->chart = k;
    out->prec = (int)prec;
    out->kind = real ? HOM_PROOF_REAL : misses ? HOM_PROOF_NONREAL : HOM_PROOF_NONE;
}

void kin__prove_endpoint(hom_prover *w, double *zr, double *zi, int want_real, int max_prec, hom_proof *out)
{
    static const slong precs[] = {53, 128, 256};
    int m = w->m, k = 0;
    double big = -1.0, imag = 0.0;
    memset(out, 0, sizeof *out);
    for (int c = 0; c < m; ++c) {
        double a = zr[c] * zr[c] + zi[c] * zi[c];
        if (a > big) big = a, k = c;
    }
    if (!(big > 0.0) || !isfinite(big)) return;
    if (!want_real) {
        centre(w, zr, zi, k, 0);
        for (int c = 0; c < m; ++c) imag = fmax(imag, fabs(w->ci[c]));
    }
    /* a real centre only for a root within 1e-6 of the reals (in chart
     * coordinates, each at most 1 in modulus) */
    int tries[2], ntries = 0;
    if (want_real) tries[ntries++] = 1;
    tries[ntries++] = 0;
    if (!want_real && imag <= 1e-6) tries[ntries++] = 1;
    for (int t = 0; t < ntries; ++t) {
        int real = tries[t];
        centre(w, zr, zi, k, real);
        for (int p = 0; p < 3 && precs[p] <= max_prec; ++p) {
            if (p > 0 && !newton(w, k, precs[p], 3, real)) break;
            double rf;
            int ok = 0;
            if (p == 0 && w->use_fast && kin__fast_krawczyk(w->fast, w->cr, w->ci, k, real, &rf)) {
                mag_set_d(w->r, rf); /* >= rf: only stored (store()), and a larger stored box is safe */
                ok = 1;
            }
            if (!ok && p == 0)
                ok = kin__exact_bounds(w->exact, k, real, w->eta, w->rho, w->L) && conclude(w, precs[p]);
            if (!ok && !krawczyk(w, k, precs[p]))
                continue;
            hom_proof got;
            double br[HOM_PROVE_MAX_M], bi[HOM_PROVE_MAX_M];
            store(w, k, real, precs[p], br, bi, &got);
            if (got.kind == HOM_PROOF_NONE) break; /* a complex box that meets the reals: try a real centre */
            *out = got;
            memcpy(zr, br, sizeof(double) * (size_t)m);
            memcpy(zi, bi, sizeof(double) * (size_t)m);
            return;
        }
    }
}
