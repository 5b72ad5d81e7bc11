/* A complete solver for beta^T Q_j beta = 0 (j < s), beta in P^s: total-degree
 * homotopy continuation. Every one of the 2^s paths from the start system
 * x_j^2 - x_0^2 = 0 is tracked in a random complex affine chart a.x = 1 with
 * the gamma trick,
 *     H(x, t) = (1 - t) gamma G(x) + t F(x),
 * by an Euler predictor and Newton corrector with step control, and its
 * endpoint classified: real, complex, singular (a multiple root or a point
 * of a positive-dimensional component, Figure 5(c)-(d)), or failed. Paths are
 * independent; threads take them by index, so the result does not depend on
 * the thread count. */
#include <complex.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

typedef double complex cplx;

enum { HOM_MAX_M = 24 };
/* step control of the tracker */
static const double T_STEP_INIT = 0.02, T_STEP_MAX = 0.05, T_STEP_MIN = 1e-13;
static const double NEWTON_TOL = 1e-11;   /* relative Newton correction on the path */
static const int NEWTON_MAX = 4;
/* endpoint classification */
static const double END_TOL = 1e-13;      /* relative residual of F after refinement */
static const double SINGULAR_COND = 1e8;  /* pivot ratio above which an endpoint is singular */
static const double REAL_TOL = 1e-8;      /* max |imag| / |x| of a real endpoint */
static const double SAME_ROOT_TOL = 1e-8; /* eq. 20 */
/* a path that stalls beyond this t, with a Jacobian condition above
 * STALL_COND, ends on a singular solution rather than being lost */
static const double ENDGAME_T = 0.9, STALL_COND = 1e6;

typedef struct hom_problem {
    int m, s;
    const double *Q;
    cplx gamma;
    cplx a[HOM_MAX_M];
} hom_problem;

/* solve A x = b (n x n, row-major, destroyed) by Gaussian elimination with
 * partial pivoting; returns the ratio max/min pivot magnitude (inf if singular) */
static double csolve(int n, cplx *A, cplx *b)
{
    double pmax = 0.0, pmin = INFINITY;
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (cabs(A[i * n + k]) > cabs(A[p * n + k])) p = i;
        if (p != k) {
            for (int j = 0; j < n; ++j) { cplx t = A[k * n + j]; A[k * n + j] = A[p * n + j]; A[p * n + j] = t; }
            cplx t = b[k]; b[k] = b[p]; b[p] = t;
        }
        double piv = cabs(A[k * n + k]);
        if (piv > pmax) pmax = piv;
        if (piv < pmin) pmin = piv;
        if (piv == 0.0) return INFINITY;
        for (int i = k + 1; i < n; ++i) {
            cplx f = A[i * n + k] / A[k * n + k];
            if (f == 0.0) continue;
            for (int j = k; j < n; ++j) A[i * n + j] -= f * A[k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (int k = n - 1; k >= 0; --k) {
        cplx v = b[k];
        for (int j = k + 1; j < n; ++j) v -= A[k * n + j] * b[j];
        b[k] = v / A[k * n + k];
    }
    return pmax / pmin;
}

/* H and its derivatives at (x, t): rows 0..s-1 the homotopy, row s the chart.
 * J (m x m row-major) = dH/dx, Ht = dH/dt, Hv = H. */
static void eval(const hom_problem *P, const cplx *x, double t, cplx *Hv, cplx *J, cplx *Ht)
{
    int m = P->m, s = P->s;
    for (int j = 0; j < s; ++j) {
        const double *Qj = P->Q + (size_t)j * m * m;
        cplx f = 0.0;
        for (int c = 0; c < m; ++c) {
            cplx row = 0.0; /* (Q x)_c, Q symmetric */
            for (int r = 0; r < m; ++r) row += Qj[r + (size_t)c * m] * x[r];
            f += row * x[c];
            if (J) J[j * m + c] = t * 2.0 * row;
        }
        cplx g = x[j + 1] * x[j + 1] - x[0] * x[0];
        if (Hv) Hv[j] = (1.0 - t) * P->gamma * g + t * f;
        if (Ht) Ht[j] = f - P->gamma * g;
        if (J) {
            J[j * m + 0] += (1.0 - t) * P->gamma * (-2.0 * x[0]);
            J[j * m + j + 1] += (1.0 - t) * P->gamma * (2.0 * x[j + 1]);
        }
    }
    cplx ch = -1.0;
    for (int c = 0; c < m; ++c) {
        ch += P->a[c] * x[c];
        if (J) J[s * m + c] = P->a[c];
    }
    if (Hv) Hv[s] = ch;
    if (Ht) Ht[s] = 0.0;
}

static double cnorm(int n, const cplx *x)
{
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += creal(x[i]) * creal(x[i]) + cimag(x[i]) * cimag(x[i]);
    return sqrt(s);
}

/* Newton at fixed t; returns 1 if the correction fell below tol */
static int newton(const hom_problem *P, cplx *x, double t, int iters, double tol, double *cond)
{
    int m = P->m;
    cplx J[HOM_MAX_M * HOM_MAX_M], h[HOM_MAX_M];
    for (int it = 0; it < iters; ++it) {
        eval(P, x, t, h, J, NULL);
        double c = csolve(m, J, h);
        if (cond) *cond = c;
        if (!isfinite(c)) return 0;
        for (int i = 0; i < m; ++i) x[i] -= h[i];
        if (cnorm(m, h) <= tol * (1.0 + cnorm(m, x))) return 1;
    }
    return 0;
}

enum { END_REAL = 0, END_COMPLEX = 1, END_SINGULAR = 2, END_FAILED = 3 };

static int track(const hom_problem *P, cplx *x)
{
    int m = P->m;
    double t = 0.0, dt = T_STEP_INIT;
    cplx J[HOM_MAX_M * HOM_MAX_M], v[HOM_MAX_M], x1[HOM_MAX_M];
    while (t < 1.0) {
        if (dt < T_STEP_MIN) {
            /* the tracker stalls where the Jacobian becomes singular: at the
             * end of the path that is a multiple root or a point of a
             * positive-dimensional component (Figure 5(c)-(d)) */
            cplx Jc[HOM_MAX_M * HOM_MAX_M], h[HOM_MAX_M];
            eval(P, x, t, h, Jc, NULL);
            double cond = csolve(m, Jc, h);
            return t > ENDGAME_T && !(cond < STALL_COND) ? END_SINGULAR : END_FAILED;
        }
        double t1 = fmin(1.0, t + dt);
        /* Euler predictor: dx/dt = -J^{-1} H_t */
        eval(P, x, t, NULL, J, v);
        if (!isfinite(csolve(m, J, v))) return END_FAILED;
        for (int i = 0; i < m; ++i) x1[i] = x[i] - (t1 - t) * v[i];
        if (newton(P, x1, t1, NEWTON_MAX, NEWTON_TOL, NULL)) {
            memcpy(x, x1, sizeof(cplx) * (size_t)m);
            t = t1;
            dt = fmin(T_STEP_MAX, dt * 1.5);
        } else {
            dt *= 0.5;
        }
    }
    /* endgame: refine on F (t = 1) and classify */
    double cond = INFINITY;
    int ok = newton(P, x, 1.0, 10, END_TOL, &cond);
    if (!ok || cond > SINGULAR_COND) return END_SINGULAR;
    /* real? scale by the largest entry */
    int k = 0;
    for (int i = 1; i < m; ++i)
        if (cabs(x[i]) > cabs(x[k])) k = i;
    cplx sc = x[k];
    double im = 0.0, nx = 0.0;
    for (int i = 0; i < m; ++i) {
        x[i] /= sc;
        im = fmax(im, fabs(cimag(x[i])));
        nx = fmax(nx, cabs(x[i]));
    }
    return im <= REAL_TOL * nx ? END_REAL : END_COMPLEX;
}

typedef struct hom_job {
    const hom_problem *P;
    int npaths, nthreads, tid;
    int *kind;
    double *ends; /* m real parts per path */
} hom_job;

static void *worker(void *arg)
{
    hom_job *J = arg;
    const hom_problem *P = J->P;
    int m = P->m;
    for (int p = J->tid; p < J->npaths; p += J->nthreads) {
        cplx x[HOM_MAX_M], ax = 0.0;
        x[0] = 1.0;
        for (int j = 1; j < m; ++j) x[j] = (p >> (j - 1)) & 1 ? -1.0 : 1.0;
        for (int i = 0; i < m; ++i) ax += P->a[i] * x[i];
        for (int i = 0; i < m; ++i) x[i] /= ax;
        J->kind[p] = track(P, x);
        for (int i = 0; i < m; ++i) J->ends[(size_t)p * m + i] = creal(x[i]);
    }
    return NULL;
}

static cplx unit_random(unsigned long long *s)
{
    double th = 6.283185307179586 * ((kin__splitmix(s) >> 11) / 9007199254740992.0);
    return cos(th) + I * sin(th);
}

int kin_quadrics_homotopy(int m, int s, const double *Q, unsigned long seed, int nthreads, double *betas,
                          int maxsol, int *nsol, int *multiplicity, kin_homotopy_info *info)
{
    if (!Q || !betas || !nsol || !info) return KIN_ENULL;
    if (m < 2 || s != m - 1 || maxsol < 1 || nthreads < 1) return KIN_EINVAL;
    if (m > HOM_MAX_M) return KIN_ERANGE;
    hom_problem P;
    P.m = m;
    P.s = s;
    P.Q = Q;
    unsigned long long st = (unsigned long long)seed * 0x2545F4914F6CDD1Dull + 7u;
    P.gamma = unit_random(&st);
    for (int i = 0; i < m; ++i) P.a[i] = unit_random(&st);
    int npaths = 1 << s;
    int *kind = malloc(sizeof(int) * (size_t)npaths);
    double *ends = malloc(sizeof(double) * (size_t)npaths * (size_t)m);
    hom_job *jobs = malloc(sizeof(hom_job) * (size_t)nthreads);
    pthread_t *th = malloc(sizeof(pthread_t) * (size_t)nthreads);
    if (!kind || !ends || !jobs || !th) {
        free(kind); free(ends); free(jobs); free(th);
        return KIN_ENOMEM;
    }
    /* thread 0 is this one; a thread that cannot be started does its share here */
    int *running = calloc((size_t)nthreads, sizeof(int));
    for (int t = 0; t < nthreads; ++t) jobs[t] = (hom_job){&P, npaths, nthreads, t, kind, ends};
    for (int t = 1; t < nthreads; ++t)
        if (running) running[t] = pthread_create(&th[t], NULL, worker, &jobs[t]) == 0;
    worker(&jobs[0]);
    for (int t = 1; t < nthreads; ++t) {
        if (running && running[t]) pthread_join(th[t], NULL);
        else worker(&jobs[t]);
    }
    free(running);
    memset(info, 0, sizeof *info);
    info->paths = npaths;
    int nd = 0;
    for (int p = 0; p < npaths; ++p) {
        switch (kind[p]) {
        case END_COMPLEX: info->nonreal++; continue;
        case END_SINGULAR: info->singular++; continue;
        case END_FAILED: info->failed++; continue;
        default: info->real++;
        }
        double b[HOM_MAX_M];
        memcpy(b, ends + (size_t)p * m, sizeof(double) * (size_t)m);
        double nb = kin__norm(m, b);
        int big = 0;
        for (int i = 0; i < m; ++i) {
            b[i] /= nb;
            if (fabs(b[i]) > fabs(b[big]) * (1.0 + 1e-12)) big = i;
        }
        if (b[big] < 0)
            for (int i = 0; i < m; ++i) b[i] = -b[i];
        int dup = -1;
        for (int i = 0; i < nd && i < maxsol && dup < 0; ++i)
            if (fabs(kin__dot(m, betas + (size_t)i * m, b)) > 1.0 - SAME_ROOT_TOL) dup = i;
        if (dup >= 0) {
            if (multiplicity) multiplicity[dup]++;
            continue;
        }
        if (nd < maxsol) {
            memcpy(betas + (size_t)nd * m, b, sizeof(double) * (size_t)m);
            if (multiplicity) multiplicity[nd] = 1;
        }
        ++nd;
    }
    info->real_distinct = nd;
    *nsol = nd < maxsol ? nd : maxsol;
    free(kind); free(ends); free(jobs); free(th);
    return KIN_OK;
}
