/* A proven singular configuration near a located bifurcation (issue 38
 * item 2), by the Krawczyk test on Moore's extended system (Moore 1980;
 * Werner & Spence 1984), in Arb's ball arithmetic.
 *
 * A simple bifurcation is not a regular root of the compatibility equations,
 * so no Newton-type test can prove it directly. It is a regular root of
 *     F_k     = |x_a - x_b|^2 - L0_k^2 + mu e_k = 0   (each bar k not between fixed joints)
 *     F_nb+i  = (A(x) phi)_i = 0                       (phi a self-stress in force densities)
 *     F_N     = e . phi - 1 = 0                         (normalisation)
 * in z = (x, phi, mu): N = nf + nb + 1 equations and unknowns, A the
 * unnormalised equilibrium matrix (column k: x_a - x_b at joint a, minus it
 * at b), e the point's unit self-stress. Its Jacobian is regular where the
 * point has one self-stress, no rigid mechanism (those are gauged away:
 * gauge() below), and the stress's quadratic
 * form on the mechanisms, U_m^T K(phi) U_m, is regular (two branches
 * crossing transversally): for a kernel vector (dx, dphi, dmu), phi* . (2 A^T dx
 * + e dmu) = dmu (A phi* = 0, e . phi* = 1), so dmu = 0 and dx is a mechanism;
 * U_m^T K dx = 0 makes it zero; then A dphi = 0 and e . dphi = 0 make dphi
 * zero. A tangency or a point of
 * several self-stresses is not regular: no proof.
 *
 * The test (as homotopy_prove.c's, real): centre y (doubles after Newton in
 * double), Y ~ J(y)^-1 (doubles), max norm, and bounds in balls
 *     eta >= |Y F(y)|, rho >= |I - Y J(y)|, L >= max_a sum_j |Y_aj| S_j,
 * S_j >= the row sums of |J(z) - J(y)| / |z - y| (J is affine in z: 4 times
 * the free coordinates of a bar row, 4 times the bars at the joint of an
 * equilibrium row). If eta + (rho + L r) r < r, z -> z - Y F(z) maps the
 * ball B(y, r) into itself and contracts: exactly one solution z* there
 * (and Y is invertible, so F has no other zero in the ball).
 *
 * The theorem (a backward-error statement): the structure whose squared bar
 * lengths are L0^2 - mu* e is exactly singular (self-stress phi*) at x*,
 * |x* - x|_inf <= distance, |L* - L0| <= |mu*| |e_k| / L0_k. mu* = 0 is not
 * proven (that would need the symmetry argument of Werner & Spence), only
 * bounded. Coordinates are scaled by a power of two near the RMS bar length
 * (exact), so that the max norm mixes comparable units. Assumption: Arb's
 * balls contain the exact results. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <arb.h>

#include "locate/sing_proof.h"
#include "model/lapack.h"

enum { PREC = 64, NEWTON_MAX = 12 };
/* the proof is attempted for extended systems up to this size (N^2 doubles
 * twice) and this many ball multiply-adds for rho (N times J's entries):
 * about a second (the hexagonal sail: 92 and 1.1e5) */
enum { MAX_N = 4000 };
static const double MAX_WORK = 3e7;
/* Newton may move the configuration this far (relative to the scale): farther
 * is no singular point near the given one */
static const double MAX_MOVE = 1e-4;

typedef struct sp_ws {
    int nf, nb, N, dim; /* nf: the unknown coordinates (the free ones less the gauge's) */
    int *fi;        /* nj dim: a coordinate's unknown, or -1 (fixed, or fixed by the gauge) */
    int *coord;     /* nf: an unknown's coordinate (j dim + c) */
    int *bar;       /* nb: the bars used (not between fixed joints) */
    double s2;      /* scale: a power of two near the RMS rest length */
    double *xyz;    /* nj dim: scaled coordinates (fixed ones as given) */
    double *e;      /* nb: e = the normalisation vector */
    double *L0sq;   /* nb: (L0 / s2)^2 to double (Newton only) */
    double *x0;     /* nf: the given point, scaled */
    double *z, *F, *J, *Y, *dz, *work;
    int *ipiv;
    int lwork;
} sp_ws;

static void ws_free(sp_ws *w)
{
    free(w->bar), free(w->xyz), free(w->e), free(w->L0sq), free(w->x0), free(w->fi), free(w->coord);
    free(w->z), free(w->F), free(w->J), free(w->Y), free(w->dz), free(w->work), free(w->ipiv);
}

static int ws_alloc(const kin_assembly *a, sp_ws *w, int nb, int mr)
{
    memset(w, 0, sizeof *w);
    w->nf = a->nf - mr, w->nb = nb, w->dim = a->dim, w->N = w->nf + nb + 1;
    size_t N = (size_t)w->N;
    w->lwork = 64 * w->N;
    w->bar = malloc(sizeof(int) * (size_t)(nb + 1));
    w->xyz = malloc(sizeof(double) * (size_t)a->nj * a->dim);
    w->e = malloc(sizeof(double) * (size_t)(nb + 1));
    w->L0sq = malloc(sizeof(double) * (size_t)(nb + 1));
    w->x0 = malloc(sizeof(double) * (size_t)(a->nf + 1));
    w->fi = malloc(sizeof(int) * (size_t)a->nj * a->dim), w->coord = malloc(sizeof(int) * (size_t)(a->nf + 1));
    w->z = malloc(sizeof(double) * N), w->F = malloc(sizeof(double) * N), w->dz = malloc(sizeof(double) * N);
    size_t big = N * N > (size_t)a->nf * (mr + 1) ? N * N : (size_t)a->nf * (mr + 1); /* also gauge()'s scratch */
    w->J = malloc(sizeof(double) * big), w->Y = malloc(sizeof(double) * big);
    w->work = malloc(sizeof(double) * (size_t)w->lwork), w->ipiv = malloc(sizeof(int) * N);
    if (!w->bar || !w->xyz || !w->e || !w->L0sq || !w->x0 || !w->fi || !w->coord || !w->z || !w->F || !w->dz || !w->J || !w->Y ||
        !w->work || !w->ipiv) {
        ws_free(w);
        return 0;
    }
    return 1;
}

/* scaled full coordinates of the configuration part of z */
static void put_x(const kin_assembly *a, sp_ws *w, const double *z)
{
    for (int i = 0; i < a->nj * a->dim; ++i) w->xyz[i] = a->xyz[i] / w->s2;
    for (int i = 0; i < w->nf; ++i) w->xyz[w->coord[i]] = z[i];
}

/* F(z) and its Jacobian (dense, column-major N x N) in double */
static void eval_double(const kin_assembly *a, sp_ws *w, const double *z, double *F, double *J)
{
    int nf = w->nf, nb = w->nb, N = w->N, dim = w->dim;
    size_t ld = (size_t)N;
    put_x(a, w, z);
    memset(F, 0, sizeof(double) * ld);
    memset(J, 0, sizeof(double) * ld * ld);
    double mu = z[N - 1];
    F[N - 1] = -1.0;
    for (int q = 0; q < nb; ++q) {
        int k = w->bar[q], ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
        double phi = z[nf + q], sq = 0.0;
        for (int c = 0; c < dim; ++c) {
            double d = w->xyz[ja * dim + c] - w->xyz[jb * dim + c];
            int ra = w->fi[ja * dim + c], rb = w->fi[jb * dim + c];
            sq += d * d;
            if (ra >= 0) {
                J[q + ra * ld] += 2.0 * d;
                F[nb + ra] += phi * d;
                J[(nb + ra) + (nf + q) * ld] += d;
                J[(nb + ra) + ra * ld] += phi;
                if (rb >= 0) J[(nb + ra) + rb * ld] -= phi;
            }
            if (rb >= 0) {
                J[q + rb * ld] -= 2.0 * d;
                F[nb + rb] -= phi * d;
                J[(nb + rb) + (nf + q) * ld] -= d;
                J[(nb + rb) + rb * ld] += phi;
                if (ra >= 0) J[(nb + rb) + ra * ld] -= phi;
            }
        }
        F[q] = sq - w->L0sq[q] + mu * w->e[q];
        J[q + (ld - 1) * ld] = w->e[q];
        F[N - 1] += w->e[q] * phi;
        J[(N - 1) + (nf + q) * ld] = w->e[q];
    }
}

static double max_abs(int n, const double *v)
{
    double m = 0.0;
    for (int i = 0; i < n; ++i) m = fmax(m, fabs(v[i]));
    return m;
}

/* Newton in double from z; then Y := J(z)^-1. 1 if it stayed within
 * MAX_MOVE of the given point and Y was formed */
static int newton(const kin_assembly *a, sp_ws *w)
{
    int N = w->N, one = 1, info = 0;
    double prev = INFINITY;
    for (int it = 0; it < NEWTON_MAX; ++it) {
        eval_double(a, w, w->z, w->F, w->J);
        dgetrf_(&N, &N, w->J, &N, w->ipiv, &info);
        if (info) return 0;
        for (int i = 0; i < N; ++i) w->dz[i] = -w->F[i];
        dgetrs_("N", &N, &one, w->J, &N, w->ipiv, w->dz, &N, &info, 1);
        double step = max_abs(N, w->dz);
        if (!isfinite(step) || (it >= 3 && step > prev)) break;
        for (int i = 0; i < N; ++i) w->z[i] += w->dz[i];
        prev = step;
        if (step <= 4.0 * DBL_EPSILON * fmax(1.0, max_abs(N, w->z))) break;
    }
    for (int i = 0; i < w->nf; ++i)
        if (!(fabs(w->z[i] - w->x0[i]) <= MAX_MOVE)) return 0;
    eval_double(a, w, w->z, w->F, w->Y);
    dgetrf_(&N, &N, w->Y, &N, w->ipiv, &info);
    if (info) return 0;
    dgetri_(&N, w->Y, &N, w->ipiv, w->work, &w->lwork, &info);
    return info == 0;
}

/* the non-trivial self-stress in force densities (H's columns are A's over
 * the lengths), unit, on the bars used: the null vector of H (the lowest
 * singular value's where there is none) with the most weight off the bars
 * between fixed joints */
static int pick_stress(const kin_assembly *a, sp_ws *w)
{
    const kin_factor *f = kin__cur(a);
    int nb = a->nb, p = a->nf < nb ? a->nf : nb, r0 = f->an.s > 0 ? f->an.rank : p - 1;
    double best = -1.0;
    if (r0 < 0) return 0;
    for (int row = r0; row < nb; ++row) {
        double n2 = 0.0;
        for (int q = 0; q < w->nb; ++q) {
            double v = f->VT[row + (size_t)w->bar[q] * nb];
            n2 += v * v;
        }
        if (n2 <= best) continue;
        best = n2;
        double n = 0.0;
        for (int q = 0; q < w->nb; ++q) {
            int k = w->bar[q], ja = a->bars[2 * k], jb = a->bars[2 * k + 1];
            double L = 0.0;
            for (int c = 0; c < a->dim; ++c) {
                double d = a->xyz[ja * a->dim + c] - a->xyz[jb * a->dim + c];
                L += d * d;
            }
            w->e[q] = f->VT[row + (size_t)k * nb] / sqrt(L);
            n += w->e[q] * w->e[q];
        }
        n = sqrt(n);
        if (!(n > 0.0)) return 0;
        for (int q = 0; q < w->nb; ++q) w->e[q] /= n;
    }
    return best > 0.0;
}

/* the ball of one term: add sign * x * y to z */
static void addmul_dd(arb_t z, double x, const arb_t y, int sign, arb_t t)
{
    arb_set_d(t, x);
    arb_mul(t, t, y, PREC);
    if (sign > 0) arb_add(z, z, t, PREC);
    else arb_sub(z, z, t, PREC);
}

/* J(y)'s entries as (row, column, ball) triplets (repeated positions add up) */
typedef struct trip {
    int n, cap;
    int *row, *col;
    arb_ptr val;
} trip;

static void trip_add(trip *t, int r, int c, const arb_t v, int sign)
{
    t->row[t->n] = r, t->col[t->n] = c;
    if (sign > 0) arb_set(t->val + t->n, v);
    else arb_neg(t->val + t->n, v);
    t->n++;
}

/* F(y) in balls (Fb, N) and J(y)'s entries as triplets, y exact (doubles);
 * S (N): the row Lipschitz constants of J */
static void eval_balls(const kin_assembly *a, sp_ws *w, const arb_t *L0sq, arb_ptr Fb, trip *t, double *S)
{
    int nf = w->nf, nb = w->nb, N = w->N, dim = w->dim;
    arb_t d, phi, sq, tmp, two_d, u;
    arb_init(d), arb_init(phi), arb_init(sq), arb_init(tmp), arb_init(two_d), arb_init(u);
    put_x(a, w, w->z);
    _arb_vec_zero(Fb, N);
    for (int i = 0; i < N; ++i) S[i] = 0.0;
    arb_set_si(Fb + N - 1, -1);
    t->n = 0;
    for (int q = 0; q < nb; ++q) {
        int k = w->bar[q], ja = a->bars[2 * k], jb = a->bars[2 * k + 1], nfree = 0;
        arb_set_d(phi, w->z[nf + q]);
        arb_zero(sq);
        for (int c = 0; c < dim; ++c) {
            arb_set_d(d, w->xyz[ja * dim + c]);
            arb_set_d(u, w->xyz[jb * dim + c]);
            arb_sub(d, d, u, PREC);
            arb_addmul(sq, d, d, PREC);
            arb_mul_2exp_si(two_d, d, 1);
            int r[2] = {w->fi[ja * dim + c], w->fi[jb * dim + c]};
            for (int end = 0; end < 2; ++end) {
                if (r[end] < 0) continue;
                int sg = end ? -1 : 1, row = nb + r[end];
                nfree++;
                S[row] += 4.0;
                trip_add(t, q, r[end], two_d, sg);
                addmul_dd(Fb + row, w->z[nf + q], d, sg, tmp);
                trip_add(t, row, nf + q, d, sg);
                trip_add(t, row, r[end], phi, 1);
                if (r[1 - end] >= 0) trip_add(t, row, r[1 - end], phi, -1);
            }
        }
        arb_sub(sq, sq, L0sq[q], PREC);
        arb_set_d(tmp, w->z[N - 1]);
        arb_set_d(u, w->e[q]);
        arb_mul(tmp, tmp, u, PREC);
        arb_add(Fb + q, sq, tmp, PREC);
        S[q] = 4.0 * nfree;
        arb_set_d(tmp, w->e[q]);
        trip_add(t, q, N - 1, tmp, 1);
        trip_add(t, N - 1, nf + q, tmp, 1);
        arb_set_d(u, w->z[nf + q]);
        arb_addmul(Fb + N - 1, u, tmp, PREC);
    }
    arb_clear(d), arb_clear(phi), arb_clear(sq), arb_clear(tmp), arb_clear(two_d), arb_clear(u);
}

/* eta >= |Y F(y)|, rho >= |I - Y J(y)|, L >= max_a sum_j |Y_aj| S_j (max norm) */
static void krawczyk_bounds(const sp_ws *w, arb_srcptr Fb, const trip *t, const double *S, mag_t eta, mag_t rho,
                            mag_t L)
{
    int N = w->N;
    size_t ld = (size_t)N;
    arb_ptr row = _arb_vec_init(N);
    arb_t s, y;
    arb_init(s), arb_init(y);
    mag_t m, acc, sj;
    mag_init(m), mag_init(acc), mag_init(sj);
    mag_zero(eta), mag_zero(rho), mag_zero(L);
    for (int a = 0; a < N; ++a) {
        arb_zero(s);
        for (int i = 0; i < N; ++i) {
            arb_set_d(y, w->Y[a + i * ld]);
            arb_addmul(s, y, Fb + i, PREC);
        }
        arb_get_mag(m, s);
        mag_max(eta, eta, m);
        _arb_vec_zero(row, N);
        for (int n = 0; n < t->n; ++n) {
            arb_set_d(y, w->Y[a + (size_t)t->row[n] * ld]);
            arb_addmul(row + t->col[n], y, t->val + n, PREC);
        }
        arb_sub_ui(row + a, row + a, 1, PREC);
        mag_zero(acc);
        for (int j = 0; j < N; ++j) {
            arb_get_mag(m, row + j);
            mag_add(acc, acc, m);
        }
        mag_max(rho, rho, acc);
        mag_zero(acc);
        for (int j = 0; j < N; ++j)
            if (S[j] > 0.0) {
                mag_set_d(m, fabs(w->Y[a + j * ld]));
                mag_set_d(sj, S[j]);
                mag_addmul(acc, m, sj);
            }
        mag_max(L, L, acc);
    }
    mag_clear(m), mag_clear(acc), mag_clear(sj);
    arb_clear(s), arb_clear(y);
    _arb_vec_clear(row, N);
}

/* the Krawczyk test on the ball of radius r (rounded up to a mag, *r_out its
 * value): 1 if eta + (rho + L r) r < r */
static int contracts(const mag_t eta, const mag_t rho, const mag_t L, double r, double *r_out)
{
    mag_t rr, lhs, t;
    mag_init(rr), mag_init(lhs), mag_init(t);
    mag_set_d(rr, r);
    mag_mul(t, L, rr);
    mag_add(t, t, rho);
    mag_mul(lhs, t, rr);
    mag_add(lhs, lhs, eta);
    int ok = r > 0.0 && isfinite(r) && mag_cmp(lhs, rr) < 0;
    *r_out = mag_get_d(rr);
    mag_clear(rr), mag_clear(lhs), mag_clear(t);
    return ok;
}

/* the proven bounds in model units from the centre y and the radius r */
static void report(const kin_assembly *a, const sp_ws *w, double r, double r_unique, kin__sing_proof *p)
{
    int nf = w->nf, N = w->N, e2 = (int)lround(log2(w->s2));
    arb_t d, u;
    arb_init(d), arb_init(u);
    mag_t m, dist, mu, q;
    mag_init(m), mag_init(dist), mag_init(mu), mag_init(q);
    for (int i = 0; i < nf; ++i) { /* |y_i - x_i| */
        arb_set_d(d, w->z[i]);
        arb_set_d(u, w->x0[i]);
        arb_sub(d, d, u, PREC);
        arb_get_mag(m, d);
        mag_max(dist, dist, m);
    }
    mag_set_d(m, r);
    mag_add(dist, dist, m);
    mag_mul_2exp_si(dist, dist, e2);
    p->distance = mag_get_d(dist);
    mag_set_d(mu, fabs(w->z[N - 1])); /* |mu*| <= |y_mu| + r, in squared model units */
    mag_add(mu, mu, m);
    mag_mul_2exp_si(mu, mu, 2 * e2);
    mag_zero(dist);
    for (int k = 0; k < w->nb; ++k) { /* |L* - L0| = |mu e_k| / (L* + L0) <= |mu e_k| / L0 */
        mag_set_d(m, fabs(w->e[k]));
        mag_set_d_lower(q, a->L0[w->bar[k]]);
        mag_div(m, m, q);
        mag_max(dist, dist, m);
    }
    mag_mul(dist, dist, mu);
    p->dlength = mag_get_d(dist);
    p->unique = ldexp(r_unique, e2);
    mag_clear(m), mag_clear(dist), mag_clear(mu), mag_clear(q);
    arb_clear(d), arb_clear(u);
}

/* the test at the Newton point: radii from eta, rho and L, each checked */
static int test_balls(const kin_assembly *a, sp_ws *w, kin__sing_proof *p)
{
    int N = w->N, nb = w->nb;
    trip t = {0, nb * (8 * w->dim + 2), NULL, NULL, NULL};
    t.row = malloc(sizeof(int) * (size_t)t.cap), t.col = malloc(sizeof(int) * (size_t)t.cap);
    if (!t.row || !t.col) {
        free(t.row), free(t.col);
        return KIN_ENOMEM;
    }
    t.val = _arb_vec_init(t.cap);
    arb_ptr Fb = _arb_vec_init(N), L0sq = _arb_vec_init(nb);
    for (int q = 0; q < nb; ++q) {
        arb_set_d(L0sq + q, a->L0[w->bar[q]] / w->s2); /* exact: a power of two */
        arb_sqr(L0sq + q, L0sq + q, PREC);
    }
    double *S = w->dz;
    eval_balls(a, w, (const arb_t *)L0sq, Fb, &t, S);
    mag_t eta, rho, L;
    mag_init(eta), mag_init(rho), mag_init(L);
    krawczyk_bounds(w, Fb, &t, S, eta, rho, L);
    double de = mag_get_d(eta), dr = mag_get_d(rho), dl = mag_get_d(L), om = 1.0 - dr;
    double disc = om * om - 4.0 * dl * de, r = 0.0, ru = 0.0;
    p->reason = KIN__SING_KRAWCZYK;
    if (om > 0.0 && disc > 0.0) {
        double root = om + sqrt(disc), rlo = 2.0 * de / root, rhi = dl > 0.0 ? root / (2.0 * dl) : 1.0;
        /* the smallest ball that passes (the enclosure), the largest (uniqueness) */
        if (contracts(eta, rho, L, fmax(rlo * 1.0625, 0x1p-1000), &r)) {
            if (!contracts(eta, rho, L, fmin(rhi * 0.9375, 1.0), &ru) || ru < r) ru = r;
            report(a, w, r, ru, p);
            p->proven = 1;
            p->reason = KIN__SING_PROVEN;
        }
    }
    mag_clear(eta), mag_clear(rho), mag_clear(L);
    _arb_vec_clear(Fb, N), _arb_vec_clear(L0sq, nb), _arb_vec_clear(t.val, t.cap);
    free(t.row), free(t.col);
    return KIN_OK;
}

/* The gauge of the rigid mechanisms (columns of Urig, nf x mr): mr free
 * coordinates held at their values, chosen by Gaussian elimination with row
 * pivoting on Urig (the rows where the rigid motions move most
 * independently). The structure so supported has no rigid motion; at its
 * singular point the reactions there vanish for the given structure too,
 * since r^T A(x) phi = 0 for each exact rigid field r and their mr x mr block
 * on those coordinates is regular near the point (docs/locate.md). */
static void gauge(const kin_assembly *a, sp_ws *w, const double *Urig, int mr)
{
    int nf = a->nf;
    double *M = w->J; /* scratch: nf x mr <= N x N */
    unsigned char *held = (unsigned char *)w->Y; /* scratch: nf flags */
    memset(held, 0, (size_t)nf);
    if (mr) memcpy(M, Urig, sizeof(double) * (size_t)nf * mr);
    for (int j = 0; j < mr; ++j) {
        int piv = -1;
        for (int i = 0; i < nf; ++i)
            if (!held[i] && (piv < 0 || fabs(M[i + (size_t)j * nf]) > fabs(M[piv + (size_t)j * nf]))) piv = i;
        held[piv] = 1;
        for (int k = j + 1; k < mr; ++k) {
            double f = M[piv + (size_t)k * nf] / M[piv + (size_t)j * nf];
            if (!isfinite(f)) continue;
            for (int i = 0; i < nf; ++i) M[i + (size_t)k * nf] -= f * M[i + (size_t)j * nf];
        }
    }
    for (int i = 0; i < a->nj * a->dim; ++i) w->fi[i] = -1;
    int n = 0;
    for (int i = 0; i < nf; ++i)
        if (!held[i]) {
            w->fi[a->free_coord[i]] = n;
            w->coord[n++] = a->free_coord[i];
        }
}

static int prove_ws(kin_assembly *a, sp_ws *w, kin__sing_proof *p, double *centre)
{
    int nf = w->nf, nb = w->nb, q = 0;
    for (int k = 0; k < a->nb; ++k)
        if (!kin__bar_fixed(a, k)) w->bar[q++] = k;
    w->s2 = ldexp(1.0, (int)lround(log2(a->rms_length > 0.0 ? a->rms_length : 1.0)));
    p->reason = KIN__SING_FAR;
    if (!pick_stress(a, w)) return KIN_OK;
    for (int i = 0; i < nf; ++i) w->x0[i] = a->xyz[w->coord[i]] / w->s2;
    memcpy(w->z, w->x0, sizeof(double) * (size_t)nf);
    memcpy(w->z + nf, w->e, sizeof(double) * (size_t)nb);
    w->z[w->N - 1] = 0.0;
    for (int k = 0; k < nb; ++k) {
        double l = a->L0[w->bar[k]] / w->s2;
        w->L0sq[k] = l * l;
    }
    if (!newton(a, w)) return KIN_OK;
    int rc = test_balls(a, w, p);
    if (rc == KIN_OK && p->proven && centre) { /* the centre y, in model units (the gauge's coordinates as given) */
        memcpy(centre, a->xyz, sizeof(double) * (size_t)a->nj * a->dim);
        for (int i = 0; i < nf; ++i) centre[w->coord[i]] = w->z[i] * w->s2;
    }
    return rc;
}

int kin__sing_prove(kin_assembly *a, kin__sing_proof *p) { return kin__sing_prove_centre(a, p, NULL); }

int kin__sing_prove_centre(kin_assembly *a, kin__sing_proof *p, double *centre)
{
    memset(p, 0, sizeof *p);
    p->reason = KIN__SING_NO_SVD;
    if (!kin__cur(a)->valid) {
        int rc = kin__analyse(a, NULL);
        if (rc) return rc;
    }
    const kin_factor *f = kin__cur(a);
    if (!f->valid || !f->VT || !f->sv) return KIN_OK;
    p->corank = f->an.s - f->an.s_trivial;
    int mr = f->an.m_rigid;
    if (mr > 0 && (!f->Urig || mr >= a->nf)) {
        p->reason = KIN__SING_RIGID;
        return KIN_OK;
    }
    if (p->corank > 1) {
        p->reason = KIN__SING_CORANK;
        return KIN_OK;
    }
    int nb = a->nb - a->nfixed_bars;
    int N = a->nf - mr + nb + 1;
    if (nb < 1 || N > MAX_N || (double)N * nb * (8 * a->dim + 2) > MAX_WORK) {
        p->reason = KIN__SING_TOO_LARGE;
        return KIN_OK;
    }
    sp_ws w;
    if (!ws_alloc(a, &w, nb, mr)) return KIN_ENOMEM;
    gauge(a, &w, f->Urig, mr);
    int rc = prove_ws(a, &w, p, centre);
    ws_free(&w);
    return rc;
}
