/* The start system of kin_quadrics_homotopy_sym: random members of the
 * equivariant family (the Reynolds projection of random complex systems)
 * and the correction of P0 that makes chosen points roots, one in each
 * stratum of roots the monodromy cannot leave. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "homotopy/symmetric/homotopy_sym.h"
#include "model/internal.h"
#include "model/lapack.h"

double kin__sym_uniform(unsigned long long *st) { return (kin__splitmix(st) >> 11) * 0x1.0p-53; }

void kin__sym_gaussian2(unsigned long long *st, double *a, double *b)
{
    double u = kin__sym_uniform(st), v = kin__sym_uniform(st), r = sqrt(-2.0 * log(u > 0.0 ? u : 0x1.0p-53));
    *a = r * cos(6.283185307179586 * v), *b = r * sin(6.283185307179586 * v);
}

/* a random complex member of E (stacked), total Frobenius norm sqrt(s) */
void kin__sym_random_member(sym_ctx *C, unsigned long long *st, double *zr, double *zi, double *pr, double *pi)
{
    int m = C->m, s = C->s, sm = C->sm;
    for (int j = 0; j < s; ++j)
        for (int r = 0; r < m; ++r)
            for (int c = 0; c <= r; ++c) {
                double a, b;
                kin__sym_gaussian2(st, &a, &b);
                zr[(size_t)c * sm + r * s + j] = zr[(size_t)r * sm + c * s + j] = a;
                zi[(size_t)c * sm + r * s + j] = zi[(size_t)r * sm + c * s + j] = b;
            }
    kin__sym_reynolds(&C->G, zr, zi, pr, pi);
    double n2 = 0.0;
    for (size_t i = 0; i < C->nsys; ++i) n2 += pr[i] * pr[i] + pi[i] * pi[i];
    double f = sqrt((double)s / n2);
    for (size_t i = 0; i < C->nsys; ++i) pr[i] *= f, pi[i] *= f;
}

/* q_P(b), s complex values */
static void evaluate(const sym_ctx *C, const double *Pr, const double *Pi, const double *br, const double *bi,
                     double *qr, double *qi, double *yr, double *yi)
{
    int m = C->m;
    kin__hpar_matvec(C->sm, m, Pr, Pi, br, bi, yr, yi);
    for (int j = 0; j < C->s; ++j) {
        double a = 0.0, b = 0.0;
        for (int r = 0; r < m; ++r) {
            a += br[r] * yr[r * C->s + j] - bi[r] * yi[r * C->s + j];
            b += br[r] * yi[r * C->s + j] + bi[r] * yr[r * C->s + j];
        }
        qr[j] = a, qi[j] = b;
    }
}

/* Seeds: points to force as roots of P0, one for each stratum of roots
 * the monodromy cannot leave (a root fixed by R_g up to scale stays so
 * along every path in E): a random point (free orbits) and a random point
 * of each eigenspace V of each R_g (eigenvalue lambda, dimension d) on
 * which the system keeps exactly d - 1 equations, e = dim ker(S_g -
 * lambda^2) = d - 1 (q(v) lies in that kernel for v in V): there the
 * generic member of E has isolated roots. Returns the number of seeds
 * (-1: out of memory). */
int kin__sym_seeds(sym_ctx *C, unsigned long long *st, double *br, double *bi, int maxseeds)
{
    int m = C->m, s = C->s, n = 1, maxorder = 2 * C->G.n + 2;
    for (int c = 0; c < m; ++c) kin__sym_gaussian2(st, &br[c], &bi[c]);
    size_t mm = (size_t)m * m, ss = (size_t)s * s;
    double *Rp = malloc(sizeof(double) * mm * (size_t)(maxorder + 1));
    double *Sp = malloc(sizeof(double) * ss * (size_t)(maxorder + 1));
    if (!Rp || !Sp) {
        free(Rp), free(Sp);
        return -1;
    }
    for (int g = 1; g < C->G.n; ++g) {
        const double *R = C->G.R + g * mm, *S = C->G.S + g * ss;
        int order = 0; /* linear order: R^order = I */
        memset(Rp, 0, sizeof(double) * mm), memset(Sp, 0, sizeof(double) * ss);
        for (int i = 0; i < m; ++i) Rp[i * m + i] = 1.0;
        for (int i = 0; i < s; ++i) Sp[i * s + i] = 1.0;
        for (int j = 1; j <= maxorder && !order; ++j) {
            double *Rn = Rp + j * mm, *Sn = Sp + j * ss, dev = 0.0;
            for (int c = 0; c < m; ++c)
                for (int r = 0; r < m; ++r) {
                    double v = 0.0;
                    for (int k = 0; k < m; ++k) v += R[k * m + r] * Rp[(j - 1) * mm + c * m + k];
                    Rn[c * m + r] = v;
                    dev = fmax(dev, fabs(v - (r == c)));
                }
            for (int c = 0; c < s; ++c)
                for (int r = 0; r < s; ++r) {
                    double v = 0.0;
                    for (int k = 0; k < s; ++k) v += S[k * s + r] * Sp[(j - 1) * ss + c * s + k];
                    Sn[c * s + r] = v;
                }
            if (dev <= 1e-6) order = j;
        }
        for (int k = 0; k < order && n < maxseeds; ++k) {
            /* projectors onto the lambda-eigenspace of R and the lambda^2 one
             * of S, lambda = exp(2 pi i k / order) */
            double d = 0.0, e = 0.0, *xr = br + n * m, *xi = bi + n * m;
            double ur[HOM_MAX_M], ui[HOM_MAX_M];
            for (int c = 0; c < m; ++c) kin__sym_gaussian2(st, &ur[c], &ui[c]), xr[c] = xi[c] = 0.0;
            for (int j = 0; j < order; ++j) {
                double th = -6.283185307179586 * k * j / order, cr = cos(th), ci = sin(th), c2 = cos(2.0 * th);
                const double *Rj = Rp + j * mm, *Sj = Sp + j * ss;
                for (int i = 0; i < m; ++i) d += cr * Rj[i * m + i];
                for (int i = 0; i < s; ++i) e += c2 * Sj[i * s + i];
                for (int c = 0; c < m; ++c)
                    for (int r = 0; r < m; ++r) {
                        double a = Rj[c * m + r] / order;
                        xr[r] += a * (cr * ur[c] - ci * ui[c]), xi[r] += a * (cr * ui[c] + ci * ur[c]);
                    }
            }
            int dd = (int)lround(d / order), ee = (int)lround(e / order);
            if (dd >= 1 && ee == dd - 1) n++;
        }
    }
    free(Rp), free(Sp);
    return n;
}

/* Make the K seeds b_k roots of P0: P0 -= Reynolds(sum_l c_l (x) u_l u_l^T)
 * (random u_l) with the c_l (s each) solving, in the least-squares sense
 * (the constraints at a seed in an eigenspace are dependent),
 * q_correction(b_k) = q_P0(b_k); the correction's values at b_k are
 * sum_l M_kl c_l, M_kl = (1/|G|) sum_g (u_l . R_g b_k)^2 S_g^-1. 0 if the
 * constraints cannot be met. */
int kin__sym_force_roots(sym_ctx *C, unsigned long long *st, int K, const double *br, const double *bi, double *zr,
                       double *zi)
{
    int m = C->m, s = C->s, sm = C->sm, n = s * K, n2 = 2 * n, ok = 0;
    size_t nn = (size_t)n2 * n2;
    double *ur = malloc(sizeof(double) * (size_t)m * K), *ui = malloc(sizeof(double) * (size_t)m * K);
    double *A = calloc(nn, sizeof(double)), *A0 = malloc(sizeof(double) * nn);
    double *f = malloc(sizeof(double) * (size_t)n2), *f0 = malloc(sizeof(double) * (size_t)n2);
    double *sv = malloc(sizeof(double) * (size_t)n2), *work = NULL;
    int *iw = malloc(sizeof(int) * (size_t)(64 * n2 + 64));
    if (!ur || !ui || !A || !A0 || !f || !f0 || !sv || !iw) goto done;
    for (int i = 0; i < m * K; ++i) kin__sym_gaussian2(st, &ur[i], &ui[i]);
    for (int k = 0; k < K; ++k) {
        double yr[HOM_MAX_M], yi[HOM_MAX_M];
        for (int g = 0; g < C->G.n; ++g) {
            kin__sym_apply(&C->G, g, br + k * m, bi + k * m, yr, yi);
            const double *Si = C->G.Sinv + (size_t)g * s * s;
            for (int l = 0; l < K; ++l) {
                double dr = 0.0, di = 0.0;
                for (int c = 0; c < m; ++c) {
                    dr += ur[l * m + c] * yr[c] - ui[l * m + c] * yi[c];
                    di += ur[l * m + c] * yi[c] + ui[l * m + c] * yr[c];
                }
                double wr = (dr * dr - di * di) / C->G.n, wi = 2.0 * dr * di / C->G.n;
                for (int i = 0; i < s; ++i) /* the real embedding [[Re, -Im], [Im, Re]] */
                    for (int j = 0; j < s; ++j) {
                        double v = Si[i * s + j];
                        size_t row = (size_t)k * s + j, col = (size_t)l * s + i;
                        A[col * n2 + row] += wr * v, A[(col + n) * n2 + row + n] += wr * v;
                        A[col * n2 + row + n] += wi * v, A[(col + n) * n2 + row] -= wi * v;
                    }
            }
        }
        evaluate(C, C->sys[0][0], C->sys[0][1], br + k * m, bi + k * m, f + k * s, f + n + k * s, C->scr,
                 C->scr + sm);
    }
    memcpy(A0, A, sizeof(double) * nn), memcpy(f0, f, sizeof(double) * (size_t)n2);
    int one = 1, rank = 0, info = 0, lwork = -1;
    double rcond = 1e-10, wq = 0.0;
    dgelsd_(&n2, &n2, &one, A, &n2, f, &n2, sv, &rcond, &rank, &wq, &lwork, iw, &info);
    lwork = (int)wq + 1;
    if (info || !(work = malloc(sizeof(double) * (size_t)lwork))) goto done;
    dgelsd_(&n2, &n2, &one, A, &n2, f, &n2, sv, &rcond, &rank, work, &lwork, iw, &info);
    if (info) goto done;
    double res = 0.0, nf = 0.0; /* the constraints must be met */
    for (int r = 0; r < n2; ++r) {
        double v = -f0[r];
        for (int c = 0; c < n2; ++c) v += A0[(size_t)c * n2 + r] * f[c];
        res += v * v, nf += f0[r] * f0[r];
    }
    if (!(res <= 1e-20 * nf)) goto done;
    memset(zr, 0, sizeof(double) * C->nsys), memset(zi, 0, sizeof(double) * C->nsys);
    for (int l = 0; l < K; ++l)
        for (int j = 0; j < s; ++j) {
            double cr = f[l * s + j], ci = f[n + l * s + j];
            const double *vr = ur + l * m, *vi = ui + l * m;
            for (int r = 0; r < m; ++r)
                for (int c = 0; c < m; ++c) {
                    double pr = vr[r] * vr[c] - vi[r] * vi[c], pi = vr[r] * vi[c] + vi[r] * vr[c];
                    zr[(size_t)c * sm + r * s + j] += cr * pr - ci * pi;
                    zi[(size_t)c * sm + r * s + j] += cr * pi + ci * pr;
                }
        }
    double *dr = C->tmp[0], *di = C->tmp[1];
    kin__sym_reynolds(&C->G, zr, zi, dr, di);
    for (size_t i = 0; i < C->nsys; ++i) C->sys[0][0][i] -= dr[i], C->sys[0][1][i] -= di[i];
    ok = 1;
done:
    free(ur), free(ui), free(A), free(A0), free(f), free(f0), free(sv), free(iw), free(work);
    return ok;
}

