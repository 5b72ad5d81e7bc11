/* The Krawczyk test of homotopy_prove.c in double precision: the same
 * quantities eta >= |Y f(y)|, rho >= |I - Y J(y)|, L, the same test
 * eta + rho r + L r^2 < r, but f, J and I - Y J computed in floating point
 * and their rounding errors bounded a priori (Higham, Accuracy and
 * Stability of Numerical Algorithms, 2nd ed., sec. 3.1-3.6: a real dot
 * product of length n in round-to-nearest has error at most
 * gamma_n sum |a_i b_i| + n 2^-1075 with gamma_n = n u / (1 - n u),
 * u = 2^-53, the last term for products that underflow; a complex one is
 * a real one of length 2n in each part). Every bound is a sum of
 * non-negative terms, evaluated in floating point and then enlarged by
 * SLACK (far more than the relative rounding of a few thousand such
 * operations) and by TINY (far more than their underflow). It assumes
 * IEEE 754 binary64 arithmetic rounding to nearest, without contraction
 * into fused multiply-adds (the library is compiled with
 * -ffp-contract=off) and without extended precision (x86-64 SSE2).
 * Y (a Gauss-Jordan inverse of J's midpoint, here with partial pivoting)
 * and the centre are exact numbers whatever their accuracy, as in the Arb
 * test. It needs ~20 times less time than Arb's balls; an endpoint it
 * cannot prove is tested in Arb (homotopy_prove.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/certify/homotopy_prove.h"
#include "homotopy/certify/homotopy_prove_fast.h"

enum { MM = HOM_PROVE_MAX_M, MS = HOM_PROVE_MAX_M - 1 };

/* gamma_n with room: n u / (1 - n u) <= 1.01 n u while n u <= 0.0099 */
#define GAM(n) ((double)(n) * 0x1p-53 * 1.01)
static const double SLACK = 1.0 + 0x1p-20; /* relative rounding of the bounds' own sums */
static const double TINY = 0x1p-1000;       /* underflow: at most ~1e4 terms of 2^-1075 */

struct hom_fast {
    int m, s;
    double *Q;                      /* s m m: Q[(j m + r) m + c] = fl((q_rc + q_cr) / 2) */
    double S[MS];                   /* >= sum_{r,c} |Qsym_j(r,c)| */
    double ur[MS * MM], ui[MS * MM]; /* U = Q_j x */
    double eU[MS * MM];             /* bound on each part's error of U */
    double Jr[MS * MS], Ji[MS * MS]; /* J = 2 U at the free coordinates */
    double Ja[MS], eJ[MS];          /* row j: sum_i |J_ji|_1, sum_i (bound on |J_ji error|) */
    double fr[MS], fi[MS], ef[MS];  /* f and its error bound */
    double Yr[MS * MS], Yi[MS * MS]; /* approximate inverse of J */
    double Ar[MS * 2 * MS], Ai[MS * 2 * MS]; /* Gauss-Jordan's [J | I] */
};

hom_fast *kin__fast_new(int m, int s, const double *Q, const double *S)
{
    if (m < 2 || m > MM || s != m - 1) return NULL;
    hom_fast *F = calloc(1, sizeof *F);
    size_t mm = (size_t)m * m;
    if (!F || !(F->Q = malloc(sizeof(double) * mm * s))) {
        free(F);
        return NULL;
    }
    F->m = m, F->s = s;
    for (int j = 0; j < s; ++j) {
        F->S[j] = S[j];
        for (int r = 0; r < m; ++r)
            for (int c = 0; c < m; ++c)
                F->Q[((size_t)j * m + r) * m + c] = 0.5 * (Q[j * mm + r + (size_t)c * m] + Q[j * mm + c + (size_t)r * m]);
    }
    return F;
}

void kin__fast_free(hom_fast *F)
{
    if (F) free(F->Q);
    free(F);
}

static int col(int k, int i) { return i < k ? i : i + 1; }

/* U, J, f at x and their error bounds (the true values are those of the
 * exact symmetric parts at the exact x) */
static void eval(hom_fast *F, const double *xr, const double *xi, const double *xa, int k, int real)
{
    int m = F->m, s = F->s;
    /* Qs vs Qsym: <= u |Qs| (+ underflow); the dot: gamma_m; A's own rounding */
    const double gu = GAM(m + 4);
    double X = 0.0; /* sum_c |x_c| */
    for (int c = 0; c < m; ++c) X += xa[c];
    X *= SLACK;
    for (int j = 0; j < s; ++j) {
        double fr = 0.0, fi = 0.0, fa = 0.0, fe = 0.0;
        for (int r = 0; r < m; ++r) {
            const double *q = F->Q + ((size_t)j * m + r) * m;
            double a = 0.0, b = 0.0, A = 0.0;
            for (int c = 0; c < m; ++c) {
                a += q[c] * xr[c];
                A += fabs(q[c]) * xa[c];
            }
            if (!real)
                for (int c = 0; c < m; ++c) b += q[c] * xi[c];
            size_t jr = (size_t)j * m + r;
            F->ur[jr] = a, F->ui[jr] = b;
            /* + the input's uncertainty: each entry within HOM_PROVE_Q_WIDTH S_j */
            F->eU[jr] = gu * A + HOM_PROVE_Q_WIDTH * F->S[j] * X + TINY;
            fr += xr[r] * a - xi[r] * b;
            fi += xr[r] * b + xi[r] * a;
            fa += xa[r] * (fabs(a) + fabs(b));
            fe += xa[r] * F->eU[jr];
        }
        F->fr[j] = fr, F->fi[j] = fi;
        /* |x| |U error| (modulus <= 1.5 x the parts' bound) + the dot's rounding */
        F->ef[j] = SLACK * (1.5 * fe + 1.5 * GAM(2 * m) * fa) + TINY;
        double ja = 0.0, ej = 0.0;
        for (int i = 0; i < s; ++i) {
            size_t jc = (size_t)j * m + col(k, i);
            F->Jr[j * s + i] = 2.0 * F->ur[jc], F->Ji[j * s + i] = 2.0 * F->ui[jc];
            ja += fabs(F->Jr[j * s + i]) + fabs(F->Ji[j * s + i]);
            ej += 3.0 * F->eU[jc];
        }
        F->Ja[j] = SLACK * ja, F->eJ[j] = SLACK * ej;
    }
}

/* Y ~ J^-1 (kin__prove_gauss_jordan); 0 if a pivot is zero or not finite */
static int invert(hom_fast *F)
{
    int s = F->s, w = 2 * s;
    for (int r = 0; r < s; ++r)
        for (int c = 0; c < s; ++c) F->Ar[r * w + c] = F->Jr[r * s + c], F->Ai[r * w + c] = F->Ji[r * s + c];
    if (!kin__prove_gauss_jordan(s, F->Ar, F->Ai, 1)) return 0;
    for (int r = 0; r < s; ++r)
        for (int c = 0; c < s; ++c)
            F->Yr[r * s + c] = F->Ar[r * w + s + c], F->Yi[r * s + c] = F->Ai[r * w + s + c];
    return 1;
}

/* eta, rho, L over the rows of Y (module comment), then the test */
static int test(hom_fast *F, double *rout)
{
    int s = F->s;
    double eta = 0.0, rho = 0.0, L = 0.0;
    for (int a = 0; a < s; ++a) {
        const double *yr = F->Yr + a * s, *yi = F->Yi + a * s;
        double gr = 0.0, gi = 0.0, yf = 0.0, ye = 0.0, yj = 0.0, yJ = 0.0, yS = 0.0, row = 0.0;
        for (int j = 0; j < s; ++j) {
            double ya = fabs(yr[j]) + fabs(yi[j]);
            gr += yr[j] * F->fr[j] - yi[j] * F->fi[j];
            gi += yr[j] * F->fi[j] + yi[j] * F->fr[j];
            yf += ya * (fabs(F->fr[j]) + fabs(F->fi[j]));
            ye += ya * F->ef[j];
            yJ += ya * F->Ja[j];
            yj += ya * F->eJ[j];
            yS += ya * F->S[j];
        }
        for (int i = 0; i < s; ++i) { /* (I - Y J)_ai */
            double er = a == i ? 1.0 : 0.0, ei = 0.0;
            for (int j = 0; j < s; ++j) {
                double jr = F->Jr[j * s + i], ji = F->Ji[j * s + i];
                er -= yr[j] * jr - yi[j] * ji;
                ei -= yr[j] * ji + yi[j] * jr;
            }
            row += fabs(er) + fabs(ei);
        }
        double eta_a = SLACK * (fabs(gr) + fabs(gi) + 1.5 * GAM(2 * s) * yf + ye) + TINY;
        double rho_a = SLACK * (row + 1.5 * GAM(2 * s + 1) * (1.0 + yJ) + yj) + TINY;
        eta = fmax(eta, eta_a), rho = fmax(rho, rho_a), L = fmax(L, SLACK * 2.0 * yS);
    }
    if (!(rho < 1.0) || !isfinite(eta) || !isfinite(L)) return 0;
    double omr = (1.0 - rho) / SLACK; /* <= 1 - rho */
    double r = SLACK * 2.0 * fmax(eta, 0x1p-900) / omr;
    double lhs = SLACK * (eta + SLACK * (rho * r) + SLACK * SLACK * (L * r * r));
    if (!(lhs < r) || !isfinite(r)) return 0;
    *rout = r;
    return 1;
}

int kin__fast_krawczyk(hom_fast *F, const double *xr, const double *xi, int k, int real, double *r)
{
    double xa[MM], big = 0.0;
    for (int c = 0; c < F->m; ++c) {
        xa[c] = fabs(xr[c]) + fabs(xi[c]);
        big = fmax(big, xa[c]);
    }
    /* the absolute terms assume moderate coordinates (a chart of the largest one) */
    if (!(big <= 4.0) || xr[k] != 1.0 || xi[k] != 0.0) return 0;
    eval(F, xr, xi, xa, k, real);
    if (!invert(F)) return 0;
    return test(F, r);
}
