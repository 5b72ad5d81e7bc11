/* The bounds of homotopy_prove.c's Krawczyk test at 53 bits, computed
 * exactly where Arb would round: the centre x and the midpoints of Q are
 * integers times powers of two (fixed point), so f(x) = x^T Q_j x is an
 * exact integer product (FLINT), and Y, J's midpoint (from Q and x
 * without their last 34 bits) and f's midpoint are rounded to 27-28-bit
 * integers so that Y J and Y f are exact small integer products: no
 * floating-point rounding enters a bound. What is not exact is bounded in
 * Arb: Q's uncertainty (each entry of Q_j within R_j of its fixed-point
 * midpoint, R_j a mag covering the ball of homotopy_prove.c and the exact
 * difference to the midpoint), the truncations (floor: below one unit of
 * the last place, by definition; f's remainders exactly, in arf), the sums
 * of moduli (mag arithmetic, rounded up; |Y| times those errors as one
 * integer product of them rounded up by mag_get_fmpz). The bounds hold for
 * the Y formed here, an exact matrix whatever its accuracy (a double
 * Gauss-Jordan inverse, rounded to 27 bits a row): its accuracy only
 * decides whether rho < 1; a root too ill-conditioned for it is retried
 * with arb_dot balls (homotopy_prove.c). Arb's arb_mat_mul_block multiplies
 * the same way (integer blocks, then balls); done here once per endpoint
 * it is ~7 times cheaper than arb_dot at every entry.
 * The products: FLINT 2.9's exported _fmpz_mat_mul_small_1 (one-word
 * inputs and sums), _small_2b (one-word inputs, three-word sums) and
 * _fmpz_mat_mul_double_word_internal (inputs below 2^127, sums below
 * 2^bits), whose contracts the fixed-point formats guarantee; fmpz_mat_mul
 * would rescan Q's entries for their size at every endpoint (a third of
 * the time). J's columns share one scale so that each row of |I - Y J| is
 * one integer sum (a root with very unequal columns then needs balls). */
#include <math.h>
#include <stdlib.h>

#include <acb.h>
#include <flint/fmpz_mat.h>

#include "homotopy/certify/homotopy_prove.h"
#include "homotopy/certify/homotopy_prove_exact.h"

enum { MM = HOM_PROVE_MAX_M, MS = HOM_PROVE_MAX_M - 1 };
enum { FX = 60, YB = 27, LO = 34 }; /* the centre in units of 2^-60; Y and J as 27-bit integers; J from
                                      Q and X without their last 34 bits */

struct hom_exact {
    int m, s;
    fmpz_mat_t Q;              /* s m x m: row j m + r holds Q_j(r, .) / 2^qe[j] */
    slong qe[MS];
    mag_ptr R, S;              /* s: Q_j's entries within R_j of Q; S of kin__exact_new */
    fmpz_mat_t Ql;             /* Q / 2^34 floored: 27-bit integers for J */
    mag_ptr G;                 /* s: G_j >= 2^(qe_j + 8) max_r sum_c |Ql_j(r,c)| */
    fmpz_mat_t Qp;             /* s x m(m+1)/2: Q_j(r,r), Q_j(r,c) + Q_j(c,r) (r < c), as Q */
    fmpz_mat_t X1, X2;         /* the centre (m x 1 real, m x 2 complex) */
    fmpz_mat_t XX1, XX2, F1, F2; /* the products x_r x_c (r <= c; re, im), f = Qp XX */
    fmpz_mat_t Xs, B3, F3;     /* real x = h 2^31 + l (m x 2); x_r x_c as 2^62 hh + 2^31 (hl + lh) + ll
                                  (one-word: m(m+1)/2 x 3), Qp B3 (s x 3) */
    fmpz_mat_t L1, V1, L2, V2; /* X / 2^34 floored, V = Ql L */
    fmpz_mat_t Jr, Ji, Yr, Yi, Pr, Pi, T; /* s x s */
    fmpz_mat_t Ya, DS, W;      /* |Yr| + |Yi| (s x s); D, S, E rounded up to integers (s x 3); W = Ya DS */
    slong ds, ss, es;          /* DS's columns in units of 2^-ds, 2^-ss, 2^-es */
    fmpz_mat_t Fm, A, B;       /* f's midpoints (re, im) in units of 2^ef (s x 2); Yr Fm, Yi Fm */
    slong ef;
    mag_ptr E;                 /* s: E_j >= |f_j - Fm_j 2^ef| */
    arf_t ma, md;
    int bad;                   /* the centre is not a chart's point: no bounds */
    slong ec[MS], ya[MS];      /* J's column i in units of 2^(ec_i - 27), Y's row a of 2^-ya */
    slong yr[MS * MS], yi[MS * MS];
    double Ar[MS * 2 * MS], Ai[MS * 2 * MS]; /* Gauss-Jordan's [J | I] */
    arb_ptr fr, fi;            /* s: f(x) */
    mag_ptr D;                 /* s: D_j >= sum_i |J_ji - J's integer midpoint| */
    fmpz_t t, v;
    mag_t xn, tm, u, row;
};

/* Q_j's midpoints to fixed point and R_j (module comment) */
static void fix_q(hom_exact *F, arb_srcptr Q)
{
    int m = F->m, s = F->s;
    arf_t a, d;
    arf_init(a), arf_init(d);
    for (int j = 0; j < s; ++j) {
        arb_srcptr q = Q + (size_t)j * m * m;
        slong e = 0;
        for (int rc = 0; rc < m * m; ++rc)
            if (!arf_is_zero(arb_midref(q + rc))) e = FLINT_MAX(e, arf_abs_bound_lt_2exp_si(arb_midref(q + rc)));
        F->qe[j] = e - FX;
        for (int rc = 0; rc < m * m; ++rc) {
            fmpz *z = fmpz_mat_entry(F->Q, j * m + rc / m, rc % m);
            arf_get_fmpz_fixed_si(z, arb_midref(q + rc), F->qe[j]);
            arf_set_fmpz(a, z);
            arf_mul_2exp_si(a, a, F->qe[j]);
            arf_sub(d, arb_midref(q + rc), a, ARF_PREC_EXACT, ARF_RND_DOWN); /* exact */
            arf_get_mag(F->tm, d);
            mag_add(F->tm, F->tm, arb_radref(q + rc));
            mag_max(F->R + j, F->R + j, F->tm);
            fmpz_fdiv_q_2exp(fmpz_mat_entry(F->Ql, j * m + rc / m, rc % m), z, LO);
        }
        for (int r = 0; r < m; ++r) {
            fmpz_zero(F->t);
            for (int c = 0; c < m; ++c) {
                fmpz_abs(F->v, fmpz_mat_entry(F->Ql, j * m + r, c));
                fmpz_add(F->t, F->t, F->v);
            }
            mag_set_fmpz(F->tm, F->t);
            mag_max(F->G + j, F->G + j, F->tm);
        }
        mag_mul_2exp_si(F->G + j, F->G + j, F->qe[j] + LO - (FX - LO));
        for (int r = 0, n = 0; r < m; ++r)
            for (int c = r; c < m; ++c, ++n) {
                fmpz *z = fmpz_mat_entry(F->Qp, j, n);
                fmpz_set(z, fmpz_mat_entry(F->Q, j * m + r, c));
                if (c > r) fmpz_add(z, z, fmpz_mat_entry(F->Q, j * m + c, r));
            }
    }
    arf_clear(a), arf_clear(d);
}

/* column p of DS: ceil(v_j 2^e) (Arb's mag_get_fmpz rounds up) with e
 * such that every one is at most 2^28; returns e, or WORD_MIN if some v_j
 * is beyond a double's range */
static slong to_column(hom_exact *F, mag_srcptr v, int p)
{
    mag_zero(F->tm);
    for (int j = 0; j < F->s; ++j) mag_max(F->tm, F->tm, v + j);
    int ex;
    double mx = mag_get_d(F->tm); /* >= max v (mag_get_d rounds up) */
    if (!(mx <= 1e300)) return WORD_MIN;
    frexp(mx, &ex); /* max v < 2^ex */
    slong e = 28 - ex;
    for (int j = 0; j < F->s; ++j) {
        mag_mul_2exp_si(F->u, v + j, e);
        mag_get_fmpz(fmpz_mat_entry(F->DS, j, p), F->u);
    }
    return e;
}

hom_exact *kin__exact_new(int m, int s, arb_srcptr Q, mag_srcptr S)
{
    if (m < 2 || m > MM || s != m - 1) return NULL;
    hom_exact *F = calloc(1, sizeof *F);
    if (!F) return NULL;
    F->m = m, F->s = s;
    fmpz_mat_init(F->Q, s * m, m), fmpz_mat_init(F->Ql, s * m, m);
    fmpz_mat_init(F->L1, m, 1), fmpz_mat_init(F->V1, s * m, 1);
    fmpz_mat_init(F->L2, m, 2), fmpz_mat_init(F->V2, s * m, 2);
    F->G = _mag_vec_init(s);
    fmpz_mat_init(F->Qp, s, m * (m + 1) / 2), fmpz_mat_init(F->X1, m, 1), fmpz_mat_init(F->X2, m, 2);
    fmpz_mat_init(F->XX1, m * (m + 1) / 2, 1), fmpz_mat_init(F->XX2, m * (m + 1) / 2, 2);
    fmpz_mat_init(F->F1, s, 1), fmpz_mat_init(F->F2, s, 2);
    fmpz_mat_init(F->Xs, m, 2), fmpz_mat_init(F->B3, m * (m + 1) / 2, 3), fmpz_mat_init(F->F3, s, 3);
    fmpz_mat_init(F->Jr, s, s), fmpz_mat_init(F->Ji, s, s), fmpz_mat_init(F->Yr, s, s), fmpz_mat_init(F->Yi, s, s);
    fmpz_mat_init(F->Pr, s, s), fmpz_mat_init(F->Pi, s, s), fmpz_mat_init(F->T, s, s);
    fmpz_mat_init(F->Ya, s, s), fmpz_mat_init(F->DS, s, 3), fmpz_mat_init(F->W, s, 3);
    fmpz_mat_init(F->Fm, s, 2), fmpz_mat_init(F->A, s, 2), fmpz_mat_init(F->B, s, 2);
    F->E = _mag_vec_init(s);
    arf_init(F->ma), arf_init(F->md);
    F->R = _mag_vec_init(s), F->S = _mag_vec_init(s), F->D = _mag_vec_init(s);
    F->fr = _arb_vec_init(s), F->fi = _arb_vec_init(s);
    fmpz_init(F->t), fmpz_init(F->v);
    mag_init(F->xn), mag_init(F->tm), mag_init(F->u), mag_init(F->row);
    for (int j = 0; j < s; ++j) mag_set(F->S + j, S + j);
    F->ss = to_column(F, F->S, 1);
    fix_q(F, Q);
    return F;
}

void kin__exact_free(hom_exact *F)
{
    if (!F) return;
    int s = F->s;
    fmpz_mat_clear(F->Q), fmpz_mat_clear(F->Ql);
    fmpz_mat_clear(F->L1), fmpz_mat_clear(F->V1), fmpz_mat_clear(F->L2), fmpz_mat_clear(F->V2);
    _mag_vec_clear(F->G, s);
    fmpz_mat_clear(F->Qp), fmpz_mat_clear(F->X1), fmpz_mat_clear(F->X2);
    fmpz_mat_clear(F->XX1), fmpz_mat_clear(F->XX2), fmpz_mat_clear(F->F1), fmpz_mat_clear(F->F2);
    fmpz_mat_clear(F->Xs), fmpz_mat_clear(F->B3), fmpz_mat_clear(F->F3);
    fmpz_mat_clear(F->Jr), fmpz_mat_clear(F->Ji), fmpz_mat_clear(F->Yr), fmpz_mat_clear(F->Yi);
    fmpz_mat_clear(F->Pr), fmpz_mat_clear(F->Pi), fmpz_mat_clear(F->T);
    fmpz_mat_clear(F->Ya), fmpz_mat_clear(F->DS), fmpz_mat_clear(F->W);
    fmpz_mat_clear(F->Fm), fmpz_mat_clear(F->A), fmpz_mat_clear(F->B);
    _mag_vec_clear(F->E, s);
    arf_clear(F->ma), arf_clear(F->md);
    _mag_vec_clear(F->R, s), _mag_vec_clear(F->S, s), _mag_vec_clear(F->D, s);
    _arb_vec_clear(F->fr, s), _arb_vec_clear(F->fi, s);
    fmpz_clear(F->t), fmpz_clear(F->v);
    mag_clear(F->xn), mag_clear(F->tm), mag_clear(F->u), mag_clear(F->row);
    free(F);
}

int kin__exact_centre(hom_exact *F, double *vr, double *vi, int real, acb_ptr x)
{
    F->bad = 0;
    for (int c = 0; c < F->m; ++c)
        if (!(fabs(vr[c]) < 2.0) || !(real || fabs(vi[c]) < 2.0)) {
            F->bad = 1;
            return 0;
        }
    for (int c = 0; c < F->m; ++c) {
        fmpz *re = fmpz_mat_entry(F->X2, c, 0), *im = fmpz_mat_entry(F->X2, c, 1);
        /* truncated: the centre is any exact point (scaling by 2^60 is exact
         * in double; the doubles are only for the other test) */
        fmpz_set_d(re, vr[c] * 0x1p60);
        if (real) fmpz_zero(im);
        else fmpz_set_d(im, vi[c] * 0x1p60);
        vr[c] = trunc(vr[c] * 0x1p60) * 0x1p-60;
        vi[c] = real ? 0.0 : trunc(vi[c] * 0x1p60) * 0x1p-60;
        fmpz_set(fmpz_mat_entry(F->X1, c, 0), re);
        fmpz_fdiv_q_2exp(fmpz_mat_entry(F->L2, c, 0), re, LO);
        fmpz_fdiv_q_2exp(fmpz_mat_entry(F->L2, c, 1), im, LO);
        fmpz_set(fmpz_mat_entry(F->L1, c, 0), fmpz_mat_entry(F->L2, c, 0));
        fmpz_fdiv_q_2exp(fmpz_mat_entry(F->Xs, c, 0), re, 31); /* |h| <= 2^30 */
        fmpz_fdiv_r_2exp(fmpz_mat_entry(F->Xs, c, 1), re, 31); /* 0 <= l < 2^31 */
        arb_set_fmpz(acb_realref(x + c), re);
        arb_mul_2exp_si(acb_realref(x + c), acb_realref(x + c), -FX);
        arb_set_fmpz(acb_imagref(x + c), im);
        arb_mul_2exp_si(acb_imagref(x + c), acb_imagref(x + c), -FX);
    }
    return 1;
}

static int col(int k, int i) { return i < k ? i : i + 1; }

/* f(x) = sum_{r <= c} Qp_j x_r x_c exactly (in units of 2^(qe_j - 120)),
 * its balls widened by Q's uncertainty: each part of x^T dQ_j x within
 * nc R_j |x|_1^2 (|dQ_j| <= R_j entrywise). J's midpoint comes from
 * V = Ql L (Q and x without their last 34
 * bits: Q_j = Ql_j 2^(qe_j+34) + a + dQ, x = L 2^-26 + b, 0 <= a <
 * 2^(qe_j+34), |dQ| <= R_j, 0 <= b < 2^-26 in each part), so each part of
 * (Q_j x)_r is within eJ = G_j + (2^(qe_j+34) + R_j) |x|_1 of V's, and D_j
 * gets 2 eJ in each of nc parts of s entries. nc: 1 real, 2 complex */
static void eval(hom_exact *F, int nc)
{
    int m = F->m, s = F->s;
    fmpz_mat_struct *X = nc == 1 ? F->X1 : F->X2, *XX = nc == 1 ? F->XX1 : F->XX2, *Fx = nc == 1 ? F->F1 : F->F2;
    if (nc == 1) { /* three one-word parts (below 2^60, 2^62, 2^62) and one three-word product */
        for (int r = 0, n = 0; r < m; ++r)
            for (int c = r; c < m; ++c, ++n) {
                const fmpz *hr = fmpz_mat_entry(F->Xs, r, 0), *lr = fmpz_mat_entry(F->Xs, r, 1);
                const fmpz *hc = fmpz_mat_entry(F->Xs, c, 0), *lc = fmpz_mat_entry(F->Xs, c, 1);
                fmpz_mul(fmpz_mat_entry(F->B3, n, 0), hr, hc);
                fmpz_mul(fmpz_mat_entry(F->B3, n, 1), hr, lc);
                fmpz_addmul(fmpz_mat_entry(F->B3, n, 1), lr, hc);
                fmpz_mul(fmpz_mat_entry(F->B3, n, 2), lr, lc);
            }
        _fmpz_mat_mul_small_2b(F->F3, F->Qp, F->B3); /* |Qp| <= 2^61: sums < 300 2^123 < 2^132 */
        for (int j = 0; j < s; ++j) {
            fmpz *z = fmpz_mat_entry(Fx, j, 0);
            fmpz_mul_2exp(z, fmpz_mat_entry(F->F3, j, 0), 31);
            fmpz_add(z, z, fmpz_mat_entry(F->F3, j, 1));
            fmpz_mul_2exp(z, z, 31);
            fmpz_add(z, z, fmpz_mat_entry(F->F3, j, 2));
        }
    }
    for (int r = 0, n = 0; r < m && nc == 2; ++r) /* re x_r x_c and im, below 2^123 */
        for (int c = r; c < m; ++c, ++n) {
            fmpz_mul(fmpz_mat_entry(XX, n, 0), fmpz_mat_entry(X, r, 0), fmpz_mat_entry(X, c, 0));
            if (nc == 1) continue;
            fmpz_submul(fmpz_mat_entry(XX, n, 0), fmpz_mat_entry(X, r, 1), fmpz_mat_entry(X, c, 1));
            fmpz_mul(fmpz_mat_entry(XX, n, 1), fmpz_mat_entry(X, r, 0), fmpz_mat_entry(X, c, 1));
            fmpz_addmul(fmpz_mat_entry(XX, n, 1), fmpz_mat_entry(X, r, 1), fmpz_mat_entry(X, c, 0));
        }
    /* FLINT's contract: |Qp| <= 2^61, |XX| < 2^123 below 2^127; |f| < m(m+1)/2 2^184 */
    if (nc == 2)
        _fmpz_mat_mul_double_word_internal(Fx, F->Qp, XX, 1, 185 + FLINT_BIT_COUNT((ulong)(m * (m + 1) / 2)));
    fmpz_zero(F->t);
    for (int c = 0; c < m; ++c)
        for (int p = 0; p < nc; ++p) {
            fmpz_abs(F->v, fmpz_mat_entry(X, c, p));
            fmpz_add(F->t, F->t, F->v);
        }
    mag_set_fmpz(F->xn, F->t);
    mag_mul_2exp_si(F->xn, F->xn, -FX); /* >= sum_c |x_c| */
    for (int j = 0; j < s; ++j) {
        for (int p = 0; p < nc; ++p) {
            arb_ptr f = p ? F->fi + j : F->fr + j;
            arb_set_round_fmpz(f, fmpz_mat_entry(Fx, j, p), 64); /* a ball (Arb rounds) */
            arb_mul_2exp_si(f, f, F->qe[j] - 2 * FX);
        }
        if (nc == 1) arb_zero(F->fi + j);
        mag_mul(F->u, F->R + j, F->xn);
        mag_mul(F->tm, F->u, F->xn);
        mag_mul_2exp_si(F->tm, F->tm, nc - 1);
        arb_add_error_mag(F->fr + j, F->tm);
        if (nc == 2) arb_add_error_mag(F->fi + j, F->tm);
        mag_set_ui_2exp_si(F->tm, 1, F->qe[j] + LO);
        mag_add(F->tm, F->tm, F->R + j);
        mag_mul(F->tm, F->tm, F->xn);
        mag_add(F->tm, F->tm, F->G + j);
        mag_mul_ui(F->D + j, F->tm, (ulong)(2 * s * nc));
    }
}

/* J = 2 V 2^(qe_j + 8) at the free coordinates, each part floored to an
 * integer in units of 2^(ec_i - 27) (|that| < 2^ec_i: at most 28 bits),
 * its doubles into Gauss-Jordan's left half; D_j gains the floors' error
 * (below one unit in each of nc parts) */
static void fix_j(hom_exact *F, int k, int nc)
{
    int m = F->m, s = F->s, w = 2 * s;
    fmpz_mat_struct *V = nc == 1 ? F->V1 : F->V2;
    _fmpz_mat_mul_small_1(V, F->Ql, nc == 1 ? F->L1 : F->L2); /* |Ql| <= 2^26, |L| <= 2^27: sums < 2^58 */
    mag_zero(F->row);
    slong e = WORD_MIN; /* one scale for every column: |I - Y J|'s rows summed as integers */
    for (int i = 0; i < s; ++i)
        for (int j = 0; j < s; ++j)
            for (int p = 0; p < nc; ++p) {
                const fmpz *z = fmpz_mat_entry(V, j * m + col(k, i), p);
                if (!fmpz_is_zero(z)) e = FLINT_MAX(e, (slong)fmpz_bits(z) + F->qe[j] + 2 * LO - FX + 1);
            }
    if (e == WORD_MIN) e = 0;
    for (int i = 0; i < s; ++i) {
        int c = col(k, i);
        F->ec[i] = e;
        double sc = ldexp(1.0, (int)(e - YB));
        for (int j = 0; j < s; ++j)
            for (int p = 0; p < nc; ++p) {
                const fmpz *z = fmpz_mat_entry(V, j * m + c, p);
                fmpz *J = fmpz_mat_entry(p ? F->Ji : F->Jr, j, i);
                slong sh = F->qe[j] + 2 * LO - FX + 1 + YB - e;
                if (sh >= 0) fmpz_mul_2exp(J, z, (ulong)sh);
                else fmpz_fdiv_q_2exp(J, z, (ulong)-sh);
                (p ? F->Ai : F->Ar)[j * w + i] = (double)fmpz_get_si(J) * sc;
            }
        mag_set_ui_2exp_si(F->tm, (ulong)nc, e - YB);
        mag_add(F->row, F->row, F->tm);
    }
    for (int j = 0; j < s; ++j) mag_add(F->D + j, F->D + j, F->row);
}

/* Y ~ J^-1 (any accuracy: module comment) from J in the left half of
 * [J | I]; nc = 1: real, the imaginary parts ignored */
static int invert(hom_exact *F, int nc) { return kin__prove_gauss_jordan(F->s, F->Ar, F->Ai, nc == 2); }

/* Y from the right half: row a as integers yr + i yi (< 2^27) in units of
 * 2^-ya_a; then P = Y J exactly. 0 if an entry is not finite or a row 0 */
static int fix_y(hom_exact *F, int nc)
{
    int s = F->s, w = 2 * s;
    for (int a = 0; a < s; ++a) {
        double mx = 0.0;
        for (int j = 0; j < s; ++j) {
            double v = fabs(F->Ar[a * w + s + j]), vi = nc == 2 ? fabs(F->Ai[a * w + s + j]) : 0.0;
            if (!(v <= 1e300) || !(vi <= 1e300)) return 0;
            mx = mx > v ? mx : v;
            mx = mx > vi ? mx : vi;
        }
        if (!(mx > 0.0)) return 0;
        int ex;
        frexp(mx, &ex); /* mx < 2^ex */
        F->ya[a] = YB - ex;
        double sc = ldexp(1.0, (int)F->ya[a]); /* any rounding: Y is whatever integers come out */
        for (int j = 0; j < s; ++j) {
            slong *yr = F->yr + a * s + j, *yi = F->yi + a * s + j;
            *yr = (slong)(F->Ar[a * w + s + j] * sc);
            fmpz_set_si(fmpz_mat_entry(F->Yr, a, j), *yr);
            if (nc == 2) {
                *yi = (slong)(F->Ai[a * w + s + j] * sc);
                fmpz_set_si(fmpz_mat_entry(F->Yi, a, j), *yi);
            }
        }
    }
    /* |Y| < 2^27, |J| <= 2^27: sums < 2^58, one-word */
    _fmpz_mat_mul_small_1(F->Pr, F->Yr, F->Jr);
    if (nc == 2) { /* (Yr + i Yi)(Jr + i Ji) */
        _fmpz_mat_mul_small_1(F->T, F->Yi, F->Ji);
        fmpz_mat_sub(F->Pr, F->Pr, F->T);
        _fmpz_mat_mul_small_1(F->Pi, F->Yr, F->Ji);
        _fmpz_mat_mul_small_1(F->T, F->Yi, F->Jr);
        fmpz_mat_add(F->Pi, F->Pi, F->T);
    }
    return 1;
}

/* f's midpoints as integers (re, im) in units of 2^ef, at most 2^28, and
 * E_j >= |f_j - Fm_j 2^ef| (the exact remainders and the balls' radii, in
 * Arb); 0 if f is beyond a double's range */
static int fix_f(hom_exact *F, int nc)
{
    int s = F->s, ex;
    mag_zero(F->tm);
    for (int j = 0; j < s; ++j) {
        arb_get_mag(F->u, F->fr + j);
        mag_max(F->tm, F->tm, F->u);
        arb_get_mag(F->u, F->fi + j);
        mag_max(F->tm, F->tm, F->u);
    }
    double mx = mag_get_d(F->tm); /* >= max |part| */
    if (!(mx <= 1e300)) return 0;
    frexp(mx, &ex);
    F->ef = ex - 28;
    for (int j = 0; j < s; ++j) {
        mag_zero(F->E + j);
        for (int p = 0; p < 2; ++p) {
            arb_srcptr f = p ? F->fi + j : F->fr + j;
            fmpz *z = fmpz_mat_entry(F->Fm, j, p);
            if (p >= nc) {
                fmpz_zero(z);
                continue;
            }
            arf_get_fmpz_fixed_si(z, arb_midref(f), F->ef);
            arf_set_fmpz(F->ma, z);
            arf_mul_2exp_si(F->ma, F->ma, F->ef);
            arf_sub(F->md, arb_midref(f), F->ma, ARF_PREC_EXACT, ARF_RND_DOWN); /* exact */
            arf_get_mag(F->u, F->md);
            mag_add(F->u, F->u, arb_radref(f));
            mag_add(F->E + j, F->E + j, F->u); /* |z| <= |re| + |im| */
        }
    }
    return (F->es = to_column(F, F->E, 2)) != WORD_MIN;
}

/* row a of I - Y J: sum_i |(I - P 2^(ec_i - 27 - ya_a))_ai| (re and im),
 * exact until the mags (rounded up); |P| < 2^59 (a slong) */
static void rho_row(hom_exact *F, int a, int nc)
{
    slong e = F->ec[0] - YB - F->ya[a]; /* one column scale (fix_j) */
    fmpz_zero(F->t);
    for (int i = 0; i < F->s; ++i) { /* the moduli off the diagonal (re and im), exactly */
        if (i != a) fmpz_add_ui(F->t, F->t, (ulong)labs(fmpz_get_si(fmpz_mat_entry(F->Pr, a, i))));
        if (nc == 2) fmpz_add_ui(F->t, F->t, (ulong)labs(fmpz_get_si(fmpz_mat_entry(F->Pi, a, i))));
    }
    mag_set_fmpz(F->row, F->t);
    mag_mul_2exp_si(F->row, F->row, e);
    fmpz_set(F->v, fmpz_mat_entry(F->Pr, a, a)); /* 1 - p 2^e exactly */
    if (e <= 0) {
        fmpz_one_2exp(F->t, (ulong)-e);
        fmpz_sub(F->t, F->t, F->v);
    } else {
        fmpz_mul_2exp(F->t, F->v, (ulong)e);
        fmpz_sub_ui(F->t, F->t, 1);
        e = 0;
    }
    mag_set_fmpz(F->tm, F->t);
    mag_mul_2exp_si(F->tm, F->tm, e);
    mag_add(F->row, F->row, F->tm);
}

int kin__exact_bounds(hom_exact *F, int k, int real, mag_t eta, mag_t rho, mag_t L)
{
    int s = F->s, nc = real ? 1 : 2;
    if (F->bad || F->ss == WORD_MIN) return 0;
    eval(F, nc);
    fix_j(F, k, nc);
    if (!invert(F, nc) || !fix_y(F, nc)) return 0;
    if ((F->ds = to_column(F, F->D, 0)) == WORD_MIN || !fix_f(F, nc)) return 0;
    for (int a = 0; a < s * s; ++a)
        fmpz_set_ui(fmpz_mat_entry(F->Ya, a / s, a % s), (ulong)labs(F->yr[a]) + (nc == 2 ? (ulong)labs(F->yi[a]) : 0));
    _fmpz_mat_mul_small_1(F->W, F->Ya, F->DS); /* < 2^28 each: sums < 2^60 */
    _fmpz_mat_mul_small_1(F->A, F->Yr, F->Fm);  /* < 2^27 and <= 2^28: sums < 2^60 */
    if (nc == 2) _fmpz_mat_mul_small_1(F->B, F->Yi, F->Fm);
    mag_zero(eta), mag_zero(rho), mag_zero(L);
    for (int a = 0; a < s; ++a) {
        rho_row(F, a, nc); /* |I - Y J_mid| ... */
        /* ... + |Y| |J - J_mid| <= |Y| D, and L's |Y| S, from W */
        mag_set_ui_2exp_si(F->xn, (ulong)fmpz_get_si(fmpz_mat_entry(F->W, a, 0)), -F->ds - F->ya[a]);
        mag_set_ui_2exp_si(F->u, (ulong)fmpz_get_si(fmpz_mat_entry(F->W, a, 1)), -F->ss - F->ya[a]);
        mag_add(F->row, F->row, F->xn);
        mag_max(rho, rho, F->row);
        mag_max(L, L, F->u);
        /* (Y f)_a: re = yr fr - yi fi, im = yr fi + yi fr exactly, then |Y| E */
        fmpz_set(F->t, fmpz_mat_entry(F->A, a, 0));
        fmpz_set(F->v, fmpz_mat_entry(F->A, a, 1));
        if (nc == 2) {
            fmpz_sub(F->t, F->t, fmpz_mat_entry(F->B, a, 1));
            fmpz_add(F->v, F->v, fmpz_mat_entry(F->B, a, 0));
        }
        fmpz_abs(F->t, F->t);
        fmpz_abs(F->v, F->v);
        fmpz_add(F->t, F->t, F->v); /* |z| <= |re| + |im| */
        mag_set_fmpz(F->tm, F->t);
        mag_mul_2exp_si(F->tm, F->tm, F->ef - F->ya[a]);
        mag_set_ui_2exp_si(F->u, (ulong)fmpz_get_si(fmpz_mat_entry(F->W, a, 2)), -F->es - F->ya[a]);
        mag_add(F->tm, F->tm, F->u);
        mag_max(eta, eta, F->tm);
    }
    mag_mul_2exp_si(L, L, 1);
    return 1;
}
