/* The symmetries of an assembly in its current configuration
 * (kin_symmetries) and their action on the internal mechanisms
 * (kin_mechanism_group); include/libkin/kin_symmetry.h has the contract.
 *
 * Candidates are the automorphisms of the bar graph (symmetry_graph.c)
 * coloured by what every symmetry keeps: a joint's number of fixed
 * coordinates and its distance from the centroid (an isometry permuting
 * the joints fixes their centroid), a bar's rest length and current
 * length. Values are grouped into colours by gaps: sorted, a new class
 * starts where two neighbours differ by more than the tolerance, so values
 * within it never land in different classes (classes may only merge,
 * which gives more candidates, never fewer). Each candidate is then tested
 * geometrically by an orthogonal Procrustes fit, as in Python's
 * libkin.automorphisms (the same tolerances). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "model/lapack.h"
#include "symmetry/symmetry_graph.h"

/* coordinates agree when they differ by at most 100 REL_TOL x the model
 * size (the largest centred coordinate); a direction is missing from the joints' span when its singular
 * value is at most REL_TOL x size x njoints (Python's _REL_TOL) */
static const double REL_TOL = 1e-9;
/* colour classes: centroid distances and current lengths within
 * GEOM_CLASS_TOL x size, rest lengths within REST_CLASS_TOL x the longest,
 * share a class (far above the fit's tolerance) */
static const double GEOM_CLASS_TOL = 1e-6, REST_CLASS_TOL = 1e-7;
/* |R^T R - I| (largest entry) above this: not a symmetry of the mechanisms
 * (the tolerance kin_quadrics_homotopy_sym checks) */
static const double ORTH_TOL = 1e-8;

typedef struct sym_list {
    int n, cap, nj, dim;
    int *perm;   /* nj per symmetry */
    double *Q;   /* dim*dim per symmetry, column-major */
    double *t;   /* dim per symmetry */
} sym_list;

static void sym_list_free(sym_list *s)
{
    free(s->perm), free(s->Q), free(s->t);
    memset(s, 0, sizeof *s);
}

static int sym_list_push(sym_list *s, const int *perm, const double *Q, const double *t)
{
    int d = s->dim;
    if (s->n == s->cap) {
        int cap = s->cap ? 2 * s->cap : 8;
        int *p = realloc(s->perm, sizeof(int) * (size_t)cap * s->nj);
        if (!p) return KIN_ENOMEM;
        s->perm = p;
        double *q = realloc(s->Q, sizeof(double) * (size_t)cap * d * d);
        if (!q) return KIN_ENOMEM;
        s->Q = q;
        double *tt = realloc(s->t, sizeof(double) * (size_t)cap * d);
        if (!tt) return KIN_ENOMEM;
        s->t = tt;
        s->cap = cap;
    }
    memcpy(s->perm + (size_t)s->n * s->nj, perm, sizeof(int) * (size_t)s->nj);
    memcpy(s->Q + (size_t)s->n * d * d, Q, sizeof(double) * (size_t)d * d);
    memcpy(s->t + (size_t)s->n * d, t, sizeof(double) * (size_t)d);
    s->n++;
    return KIN_OK;
}

typedef struct ranked {
    double v;
    int i;
} ranked;

static int cmp_ranked(const void *pa, const void *pb)
{
    const ranked *a = pa, *b = pb;
    return (a->v > b->v) - (a->v < b->v);
}

/* class[i] for values v[0..n-1], grouped by gaps larger than tol; r is
 * n entries of scratch */
static void gap_classes(int n, const double *v, double tol, ranked *r, int *cls)
{
    for (int i = 0; i < n; ++i) r[i].v = v[i], r[i].i = i;
    qsort(r, (size_t)n, sizeof(ranked), cmp_ranked);
    int c = 0;
    for (int k = 0; k < n; ++k) {
        if (k > 0 && r[k].v - r[k - 1].v > tol) ++c;
        cls[r[k].i] = c;
    }
}

/* everything the geometric test needs, computed once */
typedef struct sym_ctx {
    kin_assembly *a;
    int nj, d;
    double c[3];     /* centroid */
    double *Xc;      /* nj x d, column-major: centred coordinates */
    double scale;    /* largest centred coordinate: the model size */
    double null[9];  /* directions the joints do not span, rows of d */
    int nnull;
    double *Yc;      /* nj x d scratch */
    double *work;    /* dgesvd workspace */
    int lwork;
} sym_ctx;

/* dgesvd of the m x n matrix A (destroyed), jobu/jobvt as LAPACK's */
static int svd(sym_ctx *x, const char *jobu, const char *jobvt, int m, int n, double *A, double *s, double *U,
               double *VT)
{
    int info = 0, ldu = m > 1 ? m : 1, ldvt = n;
    dgesvd_(jobu, jobvt, &m, &n, A, &m, s, U, &ldu, VT, &ldvt, x->work, &x->lwork, &info, 1, 1);
    if (info < 0) return kin__fail(x->a, KIN_ELAPACK_ARG, "symmetries: dgesvd info = %d", info);
    if (info > 0) return kin__fail(x->a, KIN_ELAPACK_CONV, "symmetries: dgesvd did not converge (info = %d)", info);
    return KIN_OK;
}

static int ctx_init(sym_ctx *x, kin_assembly *a)
{
    memset(x, 0, sizeof *x);
    x->a = a;
    int nj = a->nj, d = a->dim;
    x->nj = nj, x->d = d;
    x->Xc = malloc(sizeof(double) * (size_t)nj * d);
    x->Yc = malloc(sizeof(double) * (size_t)nj * d);
    /* dgesvd's minimum for nj x d with jobu 'N' and for d x d, generously */
    x->lwork = 5 * (nj > 3 ? nj : 3) + 64;
    x->work = malloc(sizeof(double) * (size_t)x->lwork);
    double *A = malloc(sizeof(double) * (size_t)nj * d);
    if (!x->Xc || !x->Yc || !x->work || !A) {
        free(A);
        return kin__fail(a, KIN_ENOMEM, "symmetries: out of memory");
    }
    for (int k = 0; k < d; ++k) {
        double c = 0.0;
        for (int j = 0; j < nj; ++j) c += a->xyz[j * d + k];
        x->c[k] = c / nj;
    }
    x->scale = 0.0;
    for (int j = 0; j < nj; ++j)
        for (int k = 0; k < d; ++k) {
            double v = a->xyz[j * d + k] - x->c[k];
            x->Xc[j + (size_t)k * nj] = v;
            if (fabs(v) > x->scale) x->scale = fabs(v);
        }
    /* > 0: some bar has length >= 1e-150 (kin_assembly_create), and the
     * tolerances are relative to it in any unit (Python's _scale floors it
     * at 1, an absolute tolerance for models smaller than a unit) */
    if (!(x->scale > 0.0)) x->scale = 1.0;
    /* missing directions: right singular vectors of Xc with (near) zero
     * singular values, including those beyond min(nj, d) */
    memcpy(A, x->Xc, sizeof(double) * (size_t)nj * d);
    double s[3] = {0, 0, 0}, VT[9];
    int rc = svd(x, "N", "A", nj, d, A, s, NULL, VT);
    free(A);
    if (rc) return rc;
    double tol = REL_TOL * x->scale * (nj > 1 ? nj : 1);
    for (int k = 0; k < d; ++k)
        if (s[k] <= tol) { /* s beyond min(nj, d) stays 0 */
            for (int c = 0; c < d; ++c) x->null[x->nnull * d + c] = VT[k + c * d];
            x->nnull++;
        }
    return KIN_OK;
}

static void ctx_free(sym_ctx *x)
{
    free(x->Xc), free(x->Yc), free(x->work);
}

/* Q (d x d, column-major) maps every fixed axis of joint i into fixed axes
 * of perm[i] */
static int keeps_supports(const kin_assembly *a, const int *perm, const double *Q)
{
    int d = a->dim;
    for (int i = 0; i < a->nj; ++i)
        for (int ax = 0; ax < d; ++ax) {
            if (!a->fixed[i * d + ax]) continue;
            for (int b = 0; b < d; ++b)
                if (!a->fixed[perm[i] * d + b] && fabs(Q[b + ax * d]) > REL_TOL) return 0;
        }
    return 1;
}

/* the joints' images under x -> Q x + t match perm */
static int keeps_configuration(const sym_ctx *x, const int *perm, const double *Q, const double *t)
{
    int d = x->d;
    const double *X = x->a->xyz;
    for (int i = 0; i < x->nj; ++i)
        for (int r = 0; r < d; ++r) {
            double y = t[r];
            for (int k = 0; k < d; ++k) y += Q[r + k * d] * X[i * d + k];
            if (!(fabs(y - X[perm[i] * d + r]) <= 100 * REL_TOL * x->scale)) return 0;
        }
    return 1;
}

/* Q = Q (I - N N^T) + N N^T for the missing directions N: the fit fixes Q
 * on the joints' span only, and on the rest dgesvd's bases are arbitrary
 * (two joints in 3D: any rotation about the bar), so the products of
 * reflections below would miss the identity. Identity there, they give it. */
static void fix_null_space(const sym_ctx *x, double *Q)
{
    int d = x->d;
    if (x->nnull == 0) return;
    double P[9], T[9]; /* P = N N^T */
    for (int r = 0; r < d; ++r)
        for (int c = 0; c < d; ++c) {
            double v = 0.0;
            for (int b = 0; b < x->nnull; ++b) v += x->null[b * d + r] * x->null[b * d + c];
            P[r + c * d] = v;
        }
    for (int r = 0; r < d; ++r)
        for (int c = 0; c < d; ++c) {
            double v = P[r + c * d];
            for (int k = 0; k < d; ++k) v += Q[r + k * d] * ((k == c) - P[k + c * d]);
            T[r + c * d] = v;
        }
    memcpy(Q, T, sizeof(double) * (size_t)d * d);
}

/* The symmetries realising the candidate perm: the Procrustes fit Q = V U^T
 * of H = Xc^T Yc = U S V^T (Yc = Xc Q^T when it fits), times each product
 * of reflections through the missing directions. */
static int test_candidate(sym_ctx *x, const int *perm, sym_list *out)
{
    int nj = x->nj, d = x->d;
    for (int j = 0; j < nj; ++j)
        for (int k = 0; k < d; ++k) x->Yc[j + (size_t)k * nj] = x->Xc[perm[j] + (size_t)k * nj];
    double H[9], s[3], U[9], VT[9], Q[9];
    for (int r = 0; r < d; ++r)
        for (int c = 0; c < d; ++c) H[r + c * d] = kin__dot(nj, x->Xc + (size_t)r * nj, x->Yc + (size_t)c * nj);
    int rc = svd(x, "A", "A", d, d, H, s, U, VT);
    if (rc) return rc;
    for (int r = 0; r < d; ++r) /* Q = V U^T */
        for (int c = 0; c < d; ++c) {
            double v = 0.0;
            for (int k = 0; k < d; ++k) v += VT[k + r * d] * U[c + k * d];
            Q[r + c * d] = v;
        }
    fix_null_space(x, Q);
    for (int j = 0; j < nj; ++j) /* Xc Q^T = Yc ? */
        for (int r = 0; r < d; ++r) {
            double y = 0.0;
            for (int k = 0; k < d; ++k) y += Q[r + k * d] * x->Xc[j + (size_t)k * nj];
            if (!(fabs(y - x->Yc[j + (size_t)r * nj]) <= 100 * REL_TOL * x->scale)) return KIN_OK;
        }
    for (int combo = 0; combo < (1 << x->nnull); ++combo) {
        double F[9], Rf[9], T[9];
        for (int r = 0; r < d; ++r) /* Rf = product of I - 2 n n^T over the combo */
            for (int c = 0; c < d; ++c) Rf[r + c * d] = r == c;
        for (int b = 0; b < x->nnull; ++b) {
            if (!(combo >> b & 1)) continue;
            const double *n = x->null + b * d;
            for (int r = 0; r < d; ++r)
                for (int c = 0; c < d; ++c) {
                    double v = 0.0;
                    for (int k = 0; k < d; ++k) v += Rf[r + k * d] * ((k == c) - 2.0 * n[k] * n[c]);
                    T[r + c * d] = v;
                }
            memcpy(Rf, T, sizeof(double) * (size_t)d * d);
        }
        for (int r = 0; r < d; ++r)
            for (int c = 0; c < d; ++c) {
                double v = 0.0;
                for (int k = 0; k < d; ++k) v += Q[r + k * d] * Rf[k + c * d];
                F[r + c * d] = fabs(v) < 1e-12 ? 0.0 : v; /* exact zeros: cleaner P */
            }
        if (!keeps_supports(x->a, perm, F)) continue;
        double t[3];
        for (int r = 0; r < d; ++r) {
            t[r] = x->c[r];
            for (int k = 0; k < d; ++k) t[r] -= F[r + k * d] * x->c[k];
        }
        if (!keeps_configuration(x, perm, F, t)) continue;
        if ((rc = sym_list_push(out, perm, F, t))) return kin__fail(x->a, rc, "symmetries: out of memory");
    }
    return KIN_OK;
}

/* order: the identity first, then by permutation, then by Q rounded to
 * 1e-9 (Python's order) */
typedef struct sym_ref {
    const int *perm;
    const double *Q;
    int nj, d, identity, index;
} sym_ref;

static int cmp_sym_ref(const void *pa, const void *pb)
{
    const sym_ref *a = pa, *b = pb;
    if (a->identity != b->identity) return a->identity ? -1 : 1;
    for (int i = 0; i < a->nj; ++i)
        if (a->perm[i] != b->perm[i]) return a->perm[i] < b->perm[i] ? -1 : 1;
    for (int r = 0; r < a->d; ++r) /* row by row, as numpy's ravel */
        for (int c = 0; c < a->d; ++c) {
            double x = round(a->Q[r + c * a->d] * 1e9), y = round(b->Q[r + c * a->d] * 1e9);
            if (x != y) return x < y ? -1 : 1;
        }
    return (a->index > b->index) - (a->index < b->index);
}

static int is_identity(int nj, int d, const int *perm, const double *Q, const double *t)
{
    for (int i = 0; i < nj; ++i)
        if (perm[i] != i) return 0;
    for (int r = 0; r < d; ++r) {
        if (fabs(t[r]) > 1e-9) return 0;
        for (int c = 0; c < d; ++c)
            if (fabs(Q[r + c * d] - (r == c)) > 1e-9) return 0;
    }
    return 1;
}

/* the colours of symmetry_graph.c */
static int colour(kin_assembly *a, int *jcol, int *bcol, double scale, const double *c)
{
    int nj = a->nj, nb = a->nb, d = a->dim, n = nj > nb ? nj : nb;
    double *v = malloc(sizeof(double) * (size_t)n);
    ranked *r = malloc(sizeof(ranked) * (size_t)n);
    int *c1 = malloc(sizeof(int) * (size_t)n), *c2 = malloc(sizeof(int) * (size_t)n);
    if (!v || !r || !c1 || !c2) {
        free(v), free(r), free(c1), free(c2);
        return kin__fail(a, KIN_ENOMEM, "symmetries: out of memory");
    }
    for (int j = 0; j < nj; ++j) {
        double s = 0.0;
        for (int k = 0; k < d; ++k) s += (a->xyz[j * d + k] - c[k]) * (a->xyz[j * d + k] - c[k]);
        v[j] = sqrt(s);
    }
    gap_classes(nj, v, GEOM_CLASS_TOL * scale, r, c1);
    for (int j = 0; j < nj; ++j) {
        int nfix = 0;
        for (int k = 0; k < d; ++k) nfix += a->fixed[j * d + k] != 0;
        jcol[j] = c1[j] * 4 + nfix; /* nfix <= 3 */
    }
    double lmax = 0.0;
    for (int k = 0; k < nb; ++k) lmax = a->L0[k] > lmax ? a->L0[k] : lmax;
    gap_classes(nb, a->L0, REST_CLASS_TOL * lmax, r, c1);
    kin__lengths(a, a->xyz, v);
    gap_classes(nb, v, GEOM_CLASS_TOL * scale, r, c2);
    for (int k = 0; k < nb; ++k) bcol[k] = c1[k] * nb + c2[k]; /* distinct pairs, distinct colours */
    free(v), free(r), free(c1), free(c2);
    return KIN_OK;
}

/* every symmetry of a now, sorted, into *out */
static int find_symmetries(kin_assembly *a, sym_list *out)
{
    memset(out, 0, sizeof *out);
    out->nj = a->nj, out->dim = a->dim;
    sym_ctx x;
    int *jcol = malloc(sizeof(int) * (size_t)a->nj), *bcol = malloc(sizeof(int) * (size_t)a->nb);
    int *perms = NULL, count = 0;
    int rc = ctx_init(&x, a);
    if (!rc && (!jcol || !bcol)) rc = kin__fail(a, KIN_ENOMEM, "symmetries: out of memory");
    if (!rc) rc = colour(a, jcol, bcol, x.scale, x.c);
    if (!rc) {
        rc = kin__graph_automorphisms(a->nj, a->nb, a->bars, jcol, bcol, KIN_SYMMETRY_MAX_CANDIDATES, &perms,
                                      &count);
        if (rc == KIN_ELIMIT)
            kin__fail(a, rc,
                      "symmetries: the bar graph has %d%s automorphisms with the colours of supports and "
                      "lengths, more than the %d candidates tested at most",
                      count, count == 0x7fffffff ? " or more" : "", KIN_SYMMETRY_MAX_CANDIDATES);
        else if (rc)
            kin__fail(a, rc, "symmetries: out of memory in the graph automorphisms");
    }
    for (int k = 0; !rc && k < count; ++k) rc = test_candidate(&x, perms + (size_t)k * a->nj, out);
    if (!rc && out->n > 1) { /* sort references, then copy in that order */
        int d = a->dim, nj = a->nj;
        sym_ref *ref = malloc(sizeof(sym_ref) * (size_t)out->n);
        sym_list sorted;
        memset(&sorted, 0, sizeof sorted);
        sorted.nj = nj, sorted.dim = d;
        if (!ref) rc = KIN_ENOMEM;
        for (int k = 0; !rc && k < out->n; ++k) {
            const int *p = out->perm + (size_t)k * nj;
            const double *Q = out->Q + (size_t)k * d * d;
            sym_ref e = {p, Q, nj, d, is_identity(nj, d, p, Q, out->t + (size_t)k * d), k};
            ref[k] = e;
        }
        if (!rc) qsort(ref, (size_t)out->n, sizeof(sym_ref), cmp_sym_ref);
        for (int k = 0; !rc && k < out->n; ++k)
            rc = sym_list_push(&sorted, ref[k].perm, ref[k].Q, out->t + (size_t)ref[k].index * d);
        free(ref);
        if (rc) {
            sym_list_free(&sorted);
            rc = kin__fail(a, KIN_ENOMEM, "symmetries: out of memory");
        } else {
            sym_list_free(out);
            *out = sorted;
        }
    }
    /* the identity (first when there is one: always, but for a fit beyond
     * tolerance) exactly: Q = I, t = 0 */
    if (!rc && out->n > 0 && is_identity(out->nj, out->dim, out->perm, out->Q, out->t)) {
        int d = out->dim;
        for (int r = 0; r < d; ++r) {
            out->t[r] = 0.0;
            for (int c = 0; c < d; ++c) out->Q[r + c * d] = r == c;
        }
    }
    free(perms), free(jcol), free(bcol);
    ctx_free(&x);
    if (rc) sym_list_free(out);
    return rc;
}

int kin_symmetries(kin_assembly *a, int max_sym, int *perm, double *Q, double *t, int *nsym)
{
    if (nsym) *nsym = 0;
    if (!a) return KIN_ENULL;
    if (!nsym) return kin__fail(a, KIN_ENULL, "kin_symmetries: nsym is NULL");
    if (max_sym < 1) return kin__fail(a, KIN_EINVAL, "kin_symmetries: max_sym = %d, must be >= 1", max_sym);
    sym_list L;
    int rc = find_symmetries(a, &L), nj = a->nj, d = a->dim;
    if (rc) return rc;
    if (L.n > max_sym) {
        rc = kin__fail(a, KIN_ERANGE, "kin_symmetries: the assembly has %d symmetries, max_sym = %d", L.n, max_sym);
        *nsym = L.n;
    } else {
        if (L.n == 0) { /* never: the identity always fits; no memcpy from NULL */
            sym_list_free(&L);
            return kin__fail(a, KIN_ESTATE, "kin_symmetries: the identity did not fit the configuration");
        }
        if (perm) memcpy(perm, L.perm, sizeof(int) * (size_t)L.n * nj);
        if (Q) memcpy(Q, L.Q, sizeof(double) * (size_t)L.n * d * d);
        if (t) memcpy(t, L.t, sizeof(double) * (size_t)L.n * d);
        *nsym = L.n;
    }
    sym_list_free(&L);
    return rc;
}

/* Rg = U^T P_g U for symmetry (perm, Q); PU is nf x m scratch */
static void mechanism_action(const kin_assembly *a, const double *U, int m, const int *perm, const double *Q,
                             double *PU, double *Rg)
{
    int nf = a->nf, d = a->dim;
    memset(PU, 0, sizeof(double) * (size_t)nf * m);
    for (int i = 0; i < a->nj; ++i)
        for (int ax = 0; ax < d; ++ax) {
            int fi = a->free_index[i * d + ax];
            if (fi < 0) continue;
            for (int b = 0; b < d; ++b) {
                double q = Q[b + ax * d];
                int fj = a->free_index[perm[i] * d + b];
                if (fabs(q) <= REL_TOL || fj < 0) continue; /* keeps_supports: |q| <= REL_TOL there */
                for (int k = 0; k < m; ++k) PU[fj + (size_t)k * nf] += q * U[fi + (size_t)k * nf];
            }
        }
    double one = 1.0, zero = 0.0;
    dgemm_("T", "N", &m, &m, &nf, &one, U, &nf, PU, &nf, &zero, Rg, &m, 1, 1);
}

static int cmp_trace_desc(const void *pa, const void *pb)
{
    const ranked *a = pa, *b = pb; /* v: the trace, i: the symmetry */
    /* equal up to rounding: keep the symmetries' order (identity first) */
    if (fabs(a->v - b->v) > 1e-9) return a->v > b->v ? -1 : 1;
    return (a->i > b->i) - (a->i < b->i);
}

int kin_mechanism_group(kin_assembly *a, int max_group, double *R, int *ngroup)
{
    if (ngroup) *ngroup = 0;
    if (!a) return KIN_ENULL;
    if (!R || !ngroup) return kin__fail(a, KIN_ENULL, "kin_mechanism_group: %s is NULL", R ? "ngroup" : "R");
    if (max_group < 1)
        return kin__fail(a, KIN_EINVAL, "kin_mechanism_group: max_group = %d, must be >= 1", max_group);
    int rc;
    if (!kin__cur(a)->valid && (rc = kin__analyse(a, NULL))) return rc;
    const kin_factor *f = kin__cur(a);
    int m = f->an.m_internal, nf = a->nf;
    if (m == 0) return kin__fail(a, KIN_ENOMECH, "kin_mechanism_group: no internal mechanism");
    sym_list L;
    if ((rc = find_symmetries(a, &L))) return rc;
    if (L.n > max_group) {
        rc = kin__fail(a, KIN_ERANGE, "kin_mechanism_group: the assembly has %d symmetries, max_group = %d", L.n,
                       max_group);
        *ngroup = L.n;
        sym_list_free(&L);
        return rc;
    }
    size_t mm = (size_t)m * m;
    double *PU = malloc(sizeof(double) * (size_t)nf * m), *G = malloc(sizeof(double) * mm * (size_t)L.n);
    ranked *tr = malloc(sizeof(ranked) * (size_t)L.n);
    if (!PU || !G || !tr) rc = kin__fail(a, KIN_ENOMEM, "kin_mechanism_group: out of memory");
    for (int g = 0; !rc && g < L.n; ++g) {
        double *Rg = G + (size_t)g * mm, worst = 0.0;
        mechanism_action(a, f->Uint, m, L.perm + (size_t)g * a->nj, L.Q + (size_t)g * a->dim * a->dim, PU, Rg);
        if (a->fault == KIN__FAULT_SYM_NOT_ORTHOGONAL) Rg[0] += 0.25;
        double one = 1.0, zero = 0.0; /* |R^T R - I|, R^T R in PU (nf >= m rows) */
        dgemm_("T", "N", &m, &m, &m, &one, Rg, &m, Rg, &m, &zero, PU, &m, 1, 1);
        for (int c = 0; c < m; ++c)
            for (int r = 0; r < m; ++r) {
                double e = fabs(PU[r + (size_t)c * m] - (r == c));
                if (!(e <= worst)) worst = e; /* a NaN sticks */
            }
        if (!(worst <= ORTH_TOL))
            rc = kin__fail(a, KIN_ESTATE,
                           "kin_mechanism_group: symmetry %d does not map the internal mechanisms to themselves "
                           "(|R^T R - I| = %.3g > %.0e): near-zero singular values straddle rank_tol, or the "
                           "configuration is strained",
                           g, worst, ORTH_TOL);
        tr[g].i = g;
        tr[g].v = 0.0;
        for (int r = 0; r < m; ++r) tr[g].v += Rg[r + (size_t)r * m];
    }
    if (!rc) {
        qsort(tr, (size_t)L.n, sizeof(ranked), cmp_trace_desc);
        for (int g = 0; g < L.n; ++g) memcpy(R + (size_t)g * mm, G + (size_t)tr[g].i * mm, sizeof(double) * mm);
        *ngroup = L.n;
    }
    free(PU), free(G), free(tr);
    sym_list_free(&L);
    return rc;
}
