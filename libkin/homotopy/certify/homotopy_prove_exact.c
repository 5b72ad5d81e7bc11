/* The bounds of homotopy_prove.c's Krawczyk test at 53 bits, computed
 * exactly where Arb would round: the centre x and the midpoints of Q are
 * integers times powers of two (fixed point), so u = Q_j x and
 * f(x) = x^T u are exact integers (two and three words), J's midpoint is
 * 2 u truncated to 27-bit integers, and Y (a double Gauss-Jordan inverse,
 * rounded to 27 bits a row) and f's midpoint (28 bits) are integers too,
 * so that Y J, Y f and |Y| times the error columns are exact one-word
 * integer products: no floating-point rounding enters a bound. What is not
 * exact is bounded in Arb: Q's uncertainty (each entry of Q_j within R_j
 * of its fixed-point midpoint, R_j a mag covering the ball of
 * homotopy_prove.c and the exact difference to the midpoint), the
 * truncations (towards zero: below one unit of the last place, by
 * definition), the sums of moduli (mag arithmetic, rounded up; |Y| times
 * the errors as one integer product of them rounded up by mag_get_fmpz).
 * The bounds hold for the Y formed here, an exact matrix whatever its
 * accuracy: its accuracy only decides whether rho < 1; a root too
 * ill-conditioned for it is retried with arb_dot balls (homotopy_prove.c).
 * Arb's arb_mat_mul_block multiplies the same way (integer blocks, then
 * balls); done here once per endpoint it is ~15 times cheaper than
 * arb_dot at every entry.
 * The integer arithmetic: one-word products and sums in C's 64-bit signed
 * integers, and the two- and three-word ones with FLINT's limb primitives
 * (longlong.h: smul_ppmm, umul_ppmm, add_ssaaaa, add_sssaaaaaa,
 * sub_dddmmmsss), each with the bound that keeps it exact stated where it
 * is used (the formats guarantee them: |Q| <= 2^60, |x| < 1.25 2^60,
 * |J|, |Y| < 2^27, |f's midpoint| and the error columns <= 2^28, s <= 23).
 * This replaced fmpz_mat products (FLINT's _fmpz_mat_mul_small_*, with the
 * same contracts): the fmpz entries' handling cost as much as the products.
 * J's columns share one scale so that each row of |I - Y J| is one integer
 * sum (a root with very unequal columns then needs balls). */
#include <math.h>
#include <stdlib.h>

#include <acb.h>
#include <flint/fmpz.h>
#include <flint/longlong.h>

#include "homotopy/certify/homotopy_prove.h"
#include "homotopy/certify/homotopy_prove_exact.h"

enum { MM = HOM_PROVE_MAX_M, MS = HOM_PROVE_MAX_M - 1 };
enum { FX = 60, YB = 27 }; /* the centre in units of 2^-60; Y and J as 27-bit integers */

struct hom_exact {
    int m, s;
    slong *Q;                  /* s m m: Q[(j m + r) m + c] = Q_j(r, c) / 2^qe[j], |.| <= 2^60 */
    slong qe[MS];
    mag_ptr R, S;              /* s: Q_j's entries within R_j of Q; S of kin__exact_new */
    slong x[2][MM];            /* the centre (re, im) in units of 2^-60, |.| < 1.25 2^60 */
    ulong uh[2][MS * MM], ul[2][MS * MM]; /* u = Q_j x (re, im) exactly: two-word integers (high, low)
                                             in units of 2^(qe_j - 60), |.| < 2^125 */
    slong J[2][MS * MS];       /* J's integer midpoint (re, im), row-major: |.| < 2^27 */
    slong P[2][MS * MS];       /* Y J (re, im) exactly */
    slong DS[MS * 3];          /* D, S, E rounded up to integers, <= 2^28 (row j: D_j, S_j, E_j) */
    slong ds, ss, es;          /* DS's columns in units of 2^-ds, 2^-ss, 2^-es */
    slong Fm[MS * 2];          /* f's midpoints (re, im) in units of 2^ef, |.| <= 2^28 */
    slong ef;
    mag_ptr E;                 /* s: E_j >= |f_j - Fm_j 2^ef| */
    int bad;                   /* the centre is not a chart's point: no bounds */
    slong ec[MS], ya[MS];      /* J's column i in units of 2^(ec_i - 27), Y's row a of 2^-ya */
    slong yr[MS * MS], yi[MS * MS];
    double Ar[MS * 2 * MS], Ai[MS * 2 * MS]; /* Gauss-Jordan's [J | I] */
    ulong fa[MS][2][3];        /* f(x) (re, im) exactly: three-word integers (low word first) in units
                                  of 2^(qe_j - 120) */
    slong ub[MS];              /* the bits of row j's largest free |u| (re or im) */
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
            arf_get_fmpz_fixed_si(F->t, arb_midref(q + rc), F->qe[j]); /* |.| <= 2^60: one word */
            F->Q[(size_t)j * m * m + rc] = fmpz_get_si(F->t);
            arf_set_fmpz(a, F->t);
            arf_mul_2exp_si(a, a, F->qe[j]);
            arf_sub(d, arb_midref(q + rc), a, ARF_PREC_EXACT, ARF_RND_DOWN); /* exact */
            arf_get_mag(F->tm, d);
            mag_add(F->tm, F->tm, arb_radref(q + rc));
            mag_max(F->R + j, F->R + j, F->tm);
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
        mag_get_fmpz(F->t, F->u);
        F->DS[j * 3 + p] = fmpz_get_si(F->t);
    }
    return e;
}

hom_exact *kin__exact_new(int m, int s, arb_srcptr Q, mag_srcptr S)
{
    if (m < 2 || m > MM || s != m - 1) return NULL;
    hom_exact *F = calloc(1, sizeof *F);
    if (!F) return NULL;
    F->m = m, F->s = s;
    if (!(F->Q = malloc(sizeof *F->Q * (size_t)(s * m * m)))) {
        free(F);
        return NULL;
    }
    F->E = _mag_vec_init(s);
    F->R = _mag_vec_init(s), F->S = _mag_vec_init(s), F->D = _mag_vec_init(s);
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
    free(F->Q);
    _mag_vec_clear(F->E, s);
    _mag_vec_clear(F->R, s), _mag_vec_clear(F->S, s), _mag_vec_clear(F->D, s);
    fmpz_clear(F->t), fmpz_clear(F->v);
    mag_clear(F->xn), mag_clear(F->tm), mag_clear(F->u), mag_clear(F->row);
    free(F);
}

int kin__exact_centre(hom_exact *F, double *vr, double *vi, int real, acb_ptr x)
{
    F->bad = 0;
    for (int c = 0; c < F->m; ++c)
        if (!(fabs(vr[c]) < 1.25) || !(real || fabs(vi[c]) < 1.25)) {
            F->bad = 1;
            return 0;
        }
    for (int c = 0; c < F->m; ++c) {
        /* truncated: the centre is any exact point (scaling by 2^60 is exact
         * in double, and so is the conversion of its integer part to slong;
         * the doubles are only for the other test) */
        F->x[0][c] = (slong)(vr[c] * 0x1p60);
        F->x[1][c] = real ? 0 : (slong)(vi[c] * 0x1p60);
        vr[c] = trunc(vr[c] * 0x1p60) * 0x1p-60;
        vi[c] = real ? 0.0 : trunc(vi[c] * 0x1p60) * 0x1p-60;
        for (int p = 0; p < 2; ++p) {
            arb_ptr z = p ? acb_imagref(x + c) : acb_realref(x + c);
            arb_set_si(z, F->x[p][c]);
            arb_mul_2exp_si(z, z, -FX);
        }
    }
    return 1;
}

static int col(int k, int i) { return i < k ? i : i + 1; }

/* a[2..0] += x u or -= x u (neg): x one word, u two (high, low), a three,
 * all two's complement; exact (FLINT's limb arithmetic, longlong.h) */
static void mac3(ulong *a, slong x, ulong uh, ulong ul, int neg)
{
    ulong ax = x < 0 ? -(ulong)x : (ulong)x, p2, p1, p0, q1;
    neg ^= x < 0;
    if ((slong)uh < 0) { /* |u| */
        sub_ddmmss(uh, ul, 0, 0, uh, ul);
        neg ^= 1;
    }
    umul_ppmm(p1, p0, ax, ul);
    umul_ppmm(p2, q1, ax, uh);
    add_ssaaaa(p2, p1, p2, p1, 0, q1); /* |x u| = p2 2^128 + p1 2^64 + p0 */
    if (neg) sub_dddmmmsss(a[2], a[1], a[0], a[2], a[1], a[0], p2, p1, p0);
    else add_sssaaaaaa(a[2], a[1], a[0], a[2], a[1], a[0], p2, p1, p0);
}

/* sum_c q_c x_c exactly as a two-word two's complement integer (high, low)
 * when it is below 2^127 in modulus (eval; the sums wrap modulo 2^128); two
 * accumulators (even and odd c) halve the add-with-carry chain */
static void dot2(const slong *q, const slong *x, int m, ulong *hi, ulong *lo)
{
    ulong h0 = 0, l0 = 0, h1 = 0, l1 = 0, ph, pl;
    int c = 0;
    for (; c + 1 < m; c += 2) {
        smul_ppmm(ph, pl, (ulong)q[c], (ulong)x[c]);
        add_ssaaaa(h0, l0, h0, l0, ph, pl);
        smul_ppmm(ph, pl, (ulong)q[c + 1], (ulong)x[c + 1]);
        add_ssaaaa(h1, l1, h1, l1, ph, pl);
    }
    if (c < m) {
        smul_ppmm(ph, pl, (ulong)q[c], (ulong)x[c]);
        add_ssaaaa(h0, l0, h0, l0, ph, pl);
    }
    add_ssaaaa(h0, l0, h0, l0, h1, l1);
    *hi = h0, *lo = l0;
}

/* |v| of a two-word two's complement v (high, low) into mh, ml; 1 if v < 0 */
static int abs2(ulong vh, ulong vl, ulong *mh, ulong *ml)
{
    int neg = (slong)vh < 0;
    if (neg) sub_ddmmss(vh, vl, 0, 0, vh, vl);
    *mh = vh, *ml = vl;
    return neg;
}

static slong bits2(ulong mh, ulong ml) { return mh ? 64 + (slong)FLINT_BIT_COUNT(mh) : (slong)FLINT_BIT_COUNT(ml); }

/* u = Q_j x exactly (|Q| <= 2^60, |x| < 1.25 2^60 < 2^60.33: each product
 * below 2^120.33, m <= 24 of them below 2^125: two words, signed), then
 * f(x) = x^T u exactly in units of 2^(qe_j - 120) (each x_r u_r below
 * 2^185.33, 2 m <= 48 of them below 2^191: three words, signed). Q's
 * uncertainty: each part of x^T dQ_j x within nc R_j |x|_1^2 (|dQ_j| <= R_j
 * entrywise), E_j's start (fix_f adds the truncation); each part of
 * (dQ_j x)_r within R_j |x|_1, so D_j gets 2 R_j |x|_1 in each of nc parts
 * of s entries of J = 2 u. Also the bits of J's largest entry in row j
 * (chart k's coordinate left out). nc: 1 real, 2 complex */
static void eval(hom_exact *F, int k, int nc)
{
    int m = F->m, s = F->s;
    ulong nh = 0, nl = 0;
    for (int c = 0; c < m; ++c)
        for (int p = 0; p < nc; ++p) add_ssaaaa(nh, nl, nh, nl, 0, (ulong)labs(F->x[p][c]));
    fmpz_set_uiui(F->t, nh, nl);
    mag_set_fmpz(F->xn, F->t);
    mag_mul_2exp_si(F->xn, F->xn, -FX); /* >= sum_c |x_c| */
    for (int j = 0; j < s; ++j) {
        ulong *a0 = F->fa[j][0], *a1 = F->fa[j][1]; /* f's parts (low word first) */
        a0[0] = a0[1] = a0[2] = a1[0] = a1[1] = a1[2] = 0;
        F->ub[j] = 0;
        for (int r = 0; r < m; ++r) {
            const slong *q = F->Q + ((size_t)j * m + r) * m;
            ulong h0, l0, h1 = 0, l1 = 0, mh, ml;
            dot2(q, F->x[0], m, &h0, &l0);
            if (nc == 2) dot2(q, F->x[1], m, &h1, &l1);
            F->uh[0][j * m + r] = h0, F->ul[0][j * m + r] = l0;
            F->uh[1][j * m + r] = h1, F->ul[1][j * m + r] = l1;
            mac3(a0, F->x[0][r], h0, l0, 0); /* re: xr ur - xi ui, im: xr ui + xi ur */
            if (nc == 2) {
                mac3(a0, F->x[1][r], h1, l1, 1);
                mac3(a1, F->x[0][r], h1, l1, 0);
                mac3(a1, F->x[1][r], h0, l0, 0);
            }
            if (r == k) continue;
            abs2(h0, l0, &mh, &ml);
            F->ub[j] = FLINT_MAX(F->ub[j], bits2(mh, ml));
            abs2(h1, l1, &mh, &ml);
            F->ub[j] = FLINT_MAX(F->ub[j], bits2(mh, ml));
        }
        mag_mul(F->u, F->R + j, F->xn);
        mag_mul(F->tm, F->u, F->xn);
        mag_mul_ui(F->E + j, F->tm, (ulong)(nc * nc)); /* nc parts of nc R_j |x|_1^2 */
        mag_mul_ui(F->D + j, F->u, (ulong)(2 * s * nc));
    }
}

/* J = 2 u 2^(qe_j - 60) at the free coordinates, each part truncated to an
 * integer in units of 2^(ec_i - 27) (|that| < 2^ec_i: at most 28 bits),
 * its doubles into Gauss-Jordan's left half; D_j gains the truncations'
 * error (below one unit in each of nc parts) */
static void fix_j(hom_exact *F, int k, int nc)
{
    int m = F->m, s = F->s, w = 2 * s;
    ulong mh, ml;
    slong e = WORD_MIN; /* one scale for every column: |I - Y J|'s rows summed as integers */
    for (int j = 0; j < s; ++j)
        if (F->ub[j]) e = FLINT_MAX(e, F->ub[j] + F->qe[j] - FX + 1);
    if (e == WORD_MIN) e = 0;
    double sc = ldexp(1.0, (int)(e - YB));
    for (int j = 0; j < s; ++j) {
        slong sh = F->qe[j] - FX + 1 + YB - e; /* |u| 2^sh < 2^27 (e's choice) */
        for (int i = 0; i < s; ++i)
            for (int p = 0; p < nc; ++p) {
                int neg = abs2(F->uh[p][j * m + col(k, i)], F->ul[p][j * m + col(k, i)], &mh, &ml);
                ulong v;
                if (sh >= 64) v = 0; /* |u| < 2^(27 - sh) < 1: u = 0 (a row of zeros) */
                else if (sh >= 0) v = ml << sh; /* then |u| < 2^(27 - sh): one word, no overflow */
                else if (sh <= -128) v = 0;
                else if (sh <= -64) v = mh >> (-sh - 64);
                else v = (ml >> -sh) | (mh << (64 + sh)); /* 0 < -sh < 64 */
                slong J = neg ? -(slong)v : (slong)v; /* truncated towards 0: within one unit */
                F->J[p][j * s + i] = J;
                (p ? F->Ai : F->Ar)[j * w + i] = (double)J * sc;
            }
    }
    for (int i = 0; i < s; ++i) F->ec[i] = e;
    mag_set_ui_2exp_si(F->row, (ulong)(nc * s), e - YB);
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
            F->yr[a * s + j] = (slong)(F->Ar[a * w + s + j] * sc);
            F->yi[a * s + j] = nc == 2 ? (slong)(F->Ai[a * w + s + j] * sc) : 0;
        }
    }
    /* |Y| < 2^27, |J| < 2^27: each product below 2^54, 2 s <= 46 of them
     * below 2^60, so 64-bit integer sums are exact */
    for (int a = 0; a < s; ++a) {
        slong *pr = F->P[0] + a * s, *pi = F->P[1] + a * s;
        for (int i = 0; i < s; ++i) pr[i] = pi[i] = 0;
        for (int j = 0; j < s; ++j) {
            slong yr = F->yr[a * s + j], yi = F->yi[a * s + j];
            const slong *jr = F->J[0] + j * s, *ji = F->J[1] + j * s;
            for (int i = 0; i < s; ++i) pr[i] += yr * jr[i];
            if (nc == 2) /* (yr + i yi)(jr + i ji) */
                for (int i = 0; i < s; ++i) pr[i] -= yi * ji[i], pi[i] += yr * ji[i] + yi * jr[i];
        }
    }
    return 1;
}

/* f's midpoints (eval's exact parts) truncated to integers (re, im) in
 * units of 2^ef, below 2^28; E_j gains the truncations (below one unit in
 * each part, none where exact); DS's third column from E */
static int fix_f(hom_exact *F, int nc)
{
    int s = F->s;
    ulong mag[MS][2][3];
    int neg[MS][2];
    slong b[MS][2], ef = WORD_MIN;
    for (int j = 0; j < s; ++j)
        for (int p = 0; p < 2; ++p) {
            ulong *a = F->fa[j][p], *z = mag[j][p];
            neg[j][p] = (slong)a[2] < 0;
            z[0] = a[0], z[1] = a[1], z[2] = a[2];
            if (neg[j][p]) sub_dddmmmsss(z[2], z[1], z[0], 0, 0, 0, z[2], z[1], z[0]);
            b[j][p] = z[2] ? 128 + (slong)FLINT_BIT_COUNT(z[2]) : z[1] ? 64 + (slong)FLINT_BIT_COUNT(z[1])
                                                                     : (slong)FLINT_BIT_COUNT(z[0]);
            if (b[j][p] && p < nc) ef = FLINT_MAX(ef, b[j][p] + F->qe[j] - 2 * FX - 28);
        }
    F->ef = ef == WORD_MIN ? 0 : ef;
    for (int j = 0; j < s; ++j)
        for (int p = 0; p < 2; ++p) {
            const ulong *z = mag[j][p];
            slong n = F->ef - (F->qe[j] - 2 * FX); /* |f| 2^-n < 2^28 */
            ulong v = 0, rest = 0;
            if (p >= nc || !b[j][p]) v = 0;
            else if (n <= 0) v = z[0] << -n; /* then |f| < 2^(28 + n): one word */
            else if (n < 192) {
                int q = (int)(n / 64), r = (int)(n % 64);
                v = z[q] >> r;
                if (r && q < 2) v |= z[q + 1] << (64 - r);
                rest = r ? z[q] << (64 - r) : 0; /* the bits below 2^n, nonzero or not */
                for (int t = 0; t < q; ++t) rest |= z[t];
            }
            else rest = 1;
            F->Fm[j * 2 + p] = neg[j][p] ? -(slong)v : (slong)v; /* truncated towards 0 */
            if (rest) {
                mag_set_ui_2exp_si(F->u, 1, F->ef);
                mag_add(F->E + j, F->E + j, F->u); /* |z| <= |re| + |im| */
            }
        }
    return (F->es = to_column(F, F->E, 2)) != WORD_MIN;
}

/* row a of I - Y J: sum_i |(I - P 2^(ec_i - 27 - ya_a))_ai| (re and im),
 * exact until the mags (rounded up); |P| < 2^60, 2 s of them summed in two
 * words */
static void rho_row(hom_exact *F, int a, int nc)
{
    slong e = F->ec[0] - YB - F->ya[a]; /* one column scale (fix_j) */
    const slong *pr = F->P[0] + a * F->s, *pi = F->P[1] + a * F->s;
    ulong hi = 0, lo = 0;
    for (int i = 0; i < F->s; ++i) { /* the moduli off the diagonal (re and im), exactly */
        if (i != a) add_ssaaaa(hi, lo, hi, lo, 0, (ulong)labs(pr[i]));
        if (nc == 2) add_ssaaaa(hi, lo, hi, lo, 0, (ulong)labs(pi[i]));
    }
    fmpz_set_uiui(F->t, hi, lo);
    mag_set_fmpz(F->row, F->t);
    mag_mul_2exp_si(F->row, F->row, e);
    fmpz_set_si(F->v, pr[a]); /* 1 - p 2^e exactly */
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
    eval(F, k, nc);
    fix_j(F, k, nc);
    if (!invert(F, nc) || !fix_y(F, nc)) return 0;
    if ((F->ds = to_column(F, F->D, 0)) == WORD_MIN || !fix_f(F, nc)) return 0;
    mag_zero(eta), mag_zero(rho), mag_zero(L);
    for (int a = 0; a < s; ++a) {
        /* W = |Y| DS (|Yr| + |Yi| < 2^28, DS <= 2^28: s products below 2^61)
         * and Y Fm (re: yr fr - yi fi, im: yr fi + yi fr; 2 s products
         * below 2^55 each), all exact in 64-bit integers */
        slong W[3] = {0, 0, 0}, re = 0, im = 0;
        for (int j = 0; j < s; ++j) {
            slong yr = F->yr[a * s + j], yi = F->yi[a * s + j], ya = labs(yr) + labs(yi);
            for (int p = 0; p < 3; ++p) W[p] += ya * F->DS[j * 3 + p];
            re += yr * F->Fm[j * 2] - yi * F->Fm[j * 2 + 1];
            im += yr * F->Fm[j * 2 + 1] + yi * F->Fm[j * 2];
        }
        rho_row(F, a, nc); /* |I - Y J_mid| ... */
        /* ... + |Y| |J - J_mid| <= |Y| D, and L's |Y| S, from W */
        mag_set_ui_2exp_si(F->xn, (ulong)W[0], -F->ds - F->ya[a]);
        mag_set_ui_2exp_si(F->u, (ulong)W[1], -F->ss - F->ya[a]);
        mag_add(F->row, F->row, F->xn);
        mag_max(rho, rho, F->row);
        mag_max(L, L, F->u);
        /* |(Y f)_a| <= |re| + |im| (below 2^62), then |Y| E */
        mag_set_ui_2exp_si(F->tm, (ulong)labs(re) + (ulong)labs(im), F->ef - F->ya[a]);
        mag_set_ui_2exp_si(F->u, (ulong)W[2], -F->es - F->ya[a]);
        mag_add(F->tm, F->tm, F->u);
        mag_max(eta, eta, F->tm);
    }
    mag_mul_2exp_si(L, L, 1);
    return 1;
}
