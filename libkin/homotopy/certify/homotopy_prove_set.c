/* Proven boxes shown pairwise disjoint (homotopy_prove.h): each box holds
 * exactly one solution, so boxes that do not meet hold distinct solutions.
 *
 * The key kappa(x) = |w.x|^2 / |x|^2 is a function on projective space (the
 * same for every representative of a point); its enclosure over each box
 * (Arb balls) is an interval, and two boxes whose intervals do not meet
 * cannot hold the same point. After a sort by the intervals' lower ends
 * only boxes whose intervals overlap are compared, box against box in the
 * first box's chart (the second box's coordinates divided, in ball
 * arithmetic, by its coordinate at that chart: a denominator ball holding 0
 * compares as overlapping). O(n log n) for boxes in general position. */
#include <stdlib.h>

#include <acb.h>

#include "homotopy/certify/homotopy_prove.h"

typedef struct key_iv {
    double lo, hi;
    int i;
} key_iv;

static int lo_cmp(const void *a, const void *b)
{
    const key_iv *x = a, *y = b;
    if (x->lo < y->lo) return -1;
    if (x->lo > y->lo) return 1;
    return (x->i > y->i) - (x->i < y->i);
}

/* box i as balls: coordinate c = centre +- r in both parts (a square
 * holding the disc) */
static void box(int m, const double *zr, const double *zi, const hom_proof *p, acb_ptr X)
{
    for (int c = 0; c < m; ++c) {
        acb_set_d_d(X + c, zr[c], zi[c]);
        if (c == p->chart) continue;
        mag_set_d(arb_radref(acb_realref(X + c)), p->r);
        mag_set_d(arb_radref(acb_imagref(X + c)), p->r);
    }
}

/* the key's interval over box X: |w.x|^2 / |x|^2 by arb_dot (wa: w as
 * exact balls), in balls at 53 bits */
static void key(int m, acb_srcptr X, arb_srcptr wa, arb_t num, arb_t den, acb_t t, key_iv *out)
{
    arf_t b;
    arf_init(b);
    arb_srcptr xr = (arb_srcptr)X, xi = xr + 1; /* an acb is its real then imaginary arb */
    arb_dot(acb_realref(t), NULL, 0, xr, 2, wa, 1, m, 53);
    arb_dot(acb_imagref(t), NULL, 0, xi, 2, wa, 1, m, 53);
    arb_dot(den, NULL, 0, xr, 2, xr, 2, m, 53);
    arb_dot(den, den, 0, xi, 2, xi, 2, m, 53);
    arb_sqr(num, acb_realref(t), 53);
    arb_addmul(num, acb_imagref(t), acb_imagref(t), 53);
    arb_div(num, num, den, 53); /* den > 0: the chart coordinate is 1 */
    arb_get_lbound_arf(b, num, 53);
    out->lo = arf_get_d(b, ARF_RND_FLOOR);
    arb_get_ubound_arf(b, num, 53);
    out->hi = arf_get_d(b, ARF_RND_CEIL);
    arf_clear(b);
}

/* 1 if boxes a and b (as balls A, B) are shown disjoint */
static int disjoint(int m, acb_srcptr A, int ka, acb_srcptr B, acb_t t)
{
    int apart = 0;
    for (int c = 0; c < m && !apart; ++c) {
        if (c == ka) continue;
        acb_div(t, B + c, B + ka, 53);
        apart = !acb_overlaps(t, A + c);
    }
    return apart;
}

int kin__prove_disjoint(int m, int n, const double *zr, const double *zi, const hom_proof *proof, const double *w,
                        unsigned char *clash)
{
    key_iv *K = malloc(sizeof *K * (size_t)(n > 0 ? n : 1));
    acb_ptr A = _acb_vec_init(2 * m), B = A + m;
    arb_ptr wa = _arb_vec_init(m);
    if (!K) {
        _acb_vec_clear(A, 2 * m);
        _arb_vec_clear(wa, m);
        return -1;
    }
    for (int c = 0; c < m; ++c) arb_set_d(wa + c, w[c]);
    arb_t num, den;
    acb_t t;
    arb_init(num), arb_init(den), acb_init(t);
    int nk = 0, flagged = 0;
    for (int i = 0; i < n; ++i) {
        clash[i] = 0;
        if (proof[i].kind == HOM_PROOF_NONE) continue;
        box(m, zr + (size_t)i * m, zi + (size_t)i * m, &proof[i], A);
        key(m, A, wa, num, den, t, &K[nk]);
        K[nk++].i = i;
    }
    qsort(K, (size_t)nk, sizeof *K, lo_cmp);
    for (int a = 0; a < nk; ++a) {
        int i = K[a].i;
        if (a + 1 < nk && K[a + 1].lo <= K[a].hi) /* some box to compare with */
            box(m, zr + (size_t)i * m, zi + (size_t)i * m, &proof[i], A);
        for (int b = a + 1; b < nk && K[b].lo <= K[a].hi; ++b) {
            int j = K[b].i;
            box(m, zr + (size_t)j * m, zi + (size_t)j * m, &proof[j], B);
            if (!disjoint(m, A, proof[i].chart, B, t)) clash[i] = clash[j] = 1;
        }
    }
    for (int i = 0; i < n; ++i) flagged += clash[i];
    arb_clear(num), arb_clear(den), acb_clear(t);
    _acb_vec_clear(A, 2 * m);
    _arb_vec_clear(wa, m);
    free(K);
    return flagged;
}
