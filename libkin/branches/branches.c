/* Finite paths out of a bifurcation (paper 3.4, eq. 21-22). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "model/internal.h"
#include "branches/branches_internal.h"

/* the first step is this fraction of the largest step: small enough that its
 * chord shows the direction the path leaves in */
static const double FIRST_STEP_FRACTION = 1e-3;
/* the first chord must be parallel to U_m*beta to this |cos| */
static const double TANGENT_COS_TOL = 0.99;
/* eq. 22: two displacements T_i, T_j are one path if cos >= 1 - this */
static const double SAME_PATH_TOL = 1e-6;
/* step budget per path, in largest steps per unit of l_target / step */
enum { PATH_STEP_FACTOR = 20 };
/* l_target is at most this many largest steps (a bound on the work of a
 * call, and on the step budget: PATH_STEP_FACTOR times this fits a long) */
static const double MAX_TARGET_STEPS = 1e6;

/* Follow one candidate on a clone of a0. Progress goes to a0's callback as
 * done0 + the fraction of l_target covered, out of total, before every step;
 * returns KIN_ECANCELLED if it cancels. */
static int follow_one(const kin_assembly *a0, const double *dir, double l_target, double done0, double total,
                      kin_branch_path *p, double *xyz_out)
{
    if (kin__progress(a0, done0, total)) return KIN_ECANCELLED;
    kin_assembly *a = NULL;
    int rc = kin_assembly_clone(a0, &a);
    if (rc) return rc;
    p->exists = p->tangent_ok = 0;
    p->length = 0.0;
    p->tangent_cos = 0.0;
    double dmax = a->opt.step_fraction * a->rms_length;
    /* l_target counts from the bifurcation: the clone carries the path
     * length of however the caller reached it (also the progress base) */
    double l_start = kin_path_length(a);
    kin_step_info info = {.size = sizeof info};
    if (kin__leave_bifurcation(a, dir, FIRST_STEP_FRACTION, &info, &p->tangent_cos) != KIN_OK) goto done;
    p->tangent_ok = p->tangent_cos >= TANGENT_COS_TOL;
    long budget = (long)(PATH_STEP_FACTOR * (l_target / dmax + 10)); /* l_target <= MAX_TARGET_STEPS * dmax */
    while (kin_path_length(a) - l_start < l_target && budget-- > 0) {
        if (kin__progress(a0, done0 + fmin(1.0, fmax(0.0, kin_path_length(a) - l_start) / l_target), total)) {
            rc = KIN_ECANCELLED;
            break;
        }
        double d = fmin(dmax, l_target - (kin_path_length(a) - l_start));
        if (kin_step(a, d, &info) != KIN_OK) break;
    }
    p->length = kin_path_length(a) - l_start;
    p->exists = 1;
    if (xyz_out) memcpy(xyz_out, a->xyz, sizeof(double) * (size_t)(a->nj * a->dim));
done:
    if (xyz_out && !p->exists) memcpy(xyz_out, a0->xyz, sizeof(double) * (size_t)(a0->nj * a0->dim));
    kin_assembly_free(a);
    return rc;
}

int kin__leave_bifurcation(kin_assembly *a, const double *dir, double fraction, kin_step_info *info, double *cos)
{
    int nf = a->nf, rc = kin_path_set_direction(a, dir, nf);
    *cos = 0.0;
    if (rc) return rc;
    double dmax = a->opt.step_fraction * a->rms_length;
    double *x0 = malloc(sizeof(double) * 2 * (size_t)nf);
    if (!x0) return kin__fail(a, KIN_ENOMEM, "first step scratch");
    double *x1 = x0 + nf;
    kin__gather(a, a->xyz, x1);
    rc = kin_step(a, fraction * dmax, info);
    if (rc == KIN_OK) {
        kin__gather(a, a->xyz, x0);
        for (int i = 0; i < nf; ++i) x1[i] = x0[i] - x1[i];
        double nc = kin__norm(nf, x1), nd = kin__norm(nf, dir);
        *cos = nc > 0 && nd > 0 ? kin__dot(nf, x1, dir) / (nc * nd) : 0.0;
    }
    free(x0);
    return rc;
}

/* sort key of a unit displacement: its projection on a fixed direction */
typedef struct keyed {
    double key;
    int idx;
} keyed;

static int cmp_keyed(const void *p, const void *q)
{
    double a = ((const keyed *)p)->key, b = ((const keyed *)q)->key;
    return a < b ? -1 : a > b;
}

static int find_root(int *parent, int i)
{
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

/* Eq. 22 over n candidate ends (ends: n x nc full coordinates, made into
 * displacements T = R - R0 here): existing paths whose T agree in direction
 * to cos >= 1 - SAME_PATH_TOL share a path_id (ids by first index). Two unit
 * vectors that close differ by at most sqrt(2 SAME_PATH_TOL) in every
 * projection, so sorting by one projection and comparing neighbours within
 * that window finds every pair in O(n log n + n k). */
static int group_paths(const kin_assembly *a, double *ends, int n, kin_branch_path *paths, int *ndistinct)
{
    int nc = a->nj * a->dim;
    size_t bytes; /* n x nc doubles: the same size as the caller's ends, allocated already */
    double *unit = kin__mul_size3((size_t)nc, (size_t)n, sizeof(double), &bytes) ? malloc(bytes) : NULL;
    double *w = malloc(sizeof(double) * (size_t)nc);
    keyed *ks = malloc(sizeof(keyed) * (size_t)n);
    int *parent = malloc(sizeof(int) * (size_t)n), *id = malloc(sizeof(int) * (size_t)n);
    if (!unit || !w || !ks || !parent || !id) {
        free(unit); free(w); free(ks); free(parent); free(id);
        return KIN_ENOMEM;
    }
    unsigned long long st = 0x5EED5EEDull;
    for (int c = 0; c < nc; ++c) w[c] = (double)(kin__splitmix(&st) >> 11) * 0x1.0p-53 - 0.5;
    int nk = 0;
    for (int i = 0; i < n; ++i) {
        parent[i] = i;
        if (!paths[i].exists) continue;
        double *T = ends + (size_t)i * nc, *u = unit + (size_t)i * nc;
        for (int c = 0; c < nc; ++c) T[c] -= a->xyz[c];
        double nt = kin__norm(nc, T);
        if (!(nt > 0.0)) continue; /* a path that did not move is its own */
        for (int c = 0; c < nc; ++c) u[c] = T[c] / nt;
        ks[nk].key = kin__dot(nc, u, w) / kin__norm(nc, w);
        ks[nk++].idx = i;
    }
    qsort(ks, (size_t)nk, sizeof *ks, cmp_keyed);
    double win = sqrt(2.0 * SAME_PATH_TOL);
    for (int p = 0; p < nk; ++p)
        for (int q = p + 1; q < nk && ks[q].key - ks[p].key <= win; ++q) {
            int i = ks[p].idx, j = ks[q].idx;
            if (kin__dot(nc, unit + (size_t)i * nc, unit + (size_t)j * nc) >= 1.0 - SAME_PATH_TOL) {
                int ri = find_root(parent, i), rj = find_root(parent, j);
                if (ri != rj) parent[ri > rj ? ri : rj] = ri < rj ? ri : rj;
            }
        }
    int nd = 0;
    for (int i = 0; i < n; ++i) {
        id[i] = -1;
        if (!paths[i].exists) {
            paths[i].path_id = -1;
            continue;
        }
        int r = find_root(parent, i);
        if (id[r] < 0) id[r] = nd++;
        paths[i].path_id = id[r];
    }
    *ndistinct = nd;
    free(unit); free(w); free(ks); free(parent); free(id);
    return KIN_OK;
}

/* every entry finite */
static int all_finite(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static int branch_paths_impl(const kin_assembly *a, const double *betas, int nbeta, double l_target,
                             kin_branch_path *paths, double *final_xyz, int *ndistinct)
{
    if (ndistinct) *ndistinct = 0;
    if (!a || !betas || !paths || !ndistinct) return KIN_ENULL;
    if (nbeta < 1) return KIN_EINVAL;
    if (nbeta > INT_MAX / 2) return KIN_ERANGE; /* 2*nbeta paths are counted in int */
    int rc = KIN_OK, nd = 0;
    double *dir = NULL, *ends = NULL;
    const kin_factor *f = kin__cur(a);
    int m = f->an.m_internal, nf = a->nf, nc = a->nj * a->dim;
    size_t bytes;
    if (!f->valid && kin__sparse_an_current(a))
        rc = kin__fail((kin_assembly *)a, KIN_ESTATE,
                       "the current analysis is the sparse mode's: the branches need the SVD analysis (KIN_STEP_SVD)");
    else if (!f->valid) rc = KIN_ESTATE;
    else if (m < 2 || !(l_target > 0.0 && isfinite(l_target)) || !all_finite(betas, (size_t)m * (size_t)nbeta))
        rc = KIN_EINVAL;
    else if (!(l_target <= MAX_TARGET_STEPS * a->opt.step_fraction * a->rms_length))
        rc = KIN_ERANGE;
    else if (!(dir = malloc(sizeof(double) * (size_t)nf)) ||
             !kin__mul_size3((size_t)nc * 2, (size_t)nbeta, sizeof(double), &bytes) || !(ends = malloc(bytes)))
        rc = KIN_ENOMEM;
    for (int b = 0; b < nbeta && rc == KIN_OK; ++b)
        for (int sg = 0; sg < 2 && rc == KIN_OK; ++sg) {
            kin_branch_path *p = &paths[2 * b + sg];
            p->beta = b;
            p->sign = sg ? -1 : 1;
            p->path_id = -1;
            for (int i = 0; i < nf; ++i) {
                double v = 0.0;
                for (int k = 0; k < m; ++k) v += f->Uint[i + (size_t)k * nf] * betas[(size_t)b * m + k];
                dir[i] = p->sign * v;
            }
            rc = follow_one(a, dir, l_target, 2.0 * b + sg, 2.0 * nbeta, p, ends + (size_t)(2 * b + sg) * nc);
        }
    if (rc == KIN_ECANCELLED) /* a defined state: nothing followed */
        for (int i = 0; i < 2 * nbeta; ++i) {
            memset(&paths[i], 0, sizeof paths[i]);
            paths[i].path_id = -1;
        }
    /* group coinciding paths: T = R - R0 (eq. 21), cos >= 1 - tol (eq. 22) */
    if (rc == KIN_OK) rc = group_paths(a, ends, 2 * nbeta, paths, &nd);
    if (rc == KIN_OK && final_xyz)
        for (int i = 0; i < 2 * nbeta; ++i)
            for (int c = 0; c < nc; ++c)
                final_xyz[(size_t)i * nc + c] = ends[(size_t)i * nc + c] + (paths[i].exists ? a->xyz[c] : 0.0);
    if (rc == KIN_OK) {
        *ndistinct = nd;
        (void)kin__progress(a, 2.0 * nbeta, 2.0 * nbeta);
    } else {
        /* no half-written results */
        memset(paths, 0, sizeof *paths * 2 * (size_t)nbeta);
        for (int i = 0; i < 2 * nbeta; ++i) paths[i].path_id = -1;
    }
    free(dir);
    free(ends);
    return rc;
}

/* The caller's array holds elements of paths[0].size bytes (the
 * kin_branch_path it was compiled with); results are made in a full-size
 * array and copied element by element. */
int kin_branch_paths(const kin_assembly *a, const double *betas, int nbeta, double l_target,
                     kin_branch_path *paths, double *final_xyz, int *ndistinct)
{
    if (!paths) return branch_paths_impl(a, betas, nbeta, l_target, NULL, final_xyz, ndistinct);
    if (kin__abi_check(paths, KIN__ABI(kin_branch_path))) {
        if (ndistinct) *ndistinct = 0;
        return KIN_EINVAL;
    }
    /* a count it refuses: the checks return before any element is written */
    if (nbeta < 1 || nbeta > INT_MAX / 2) return branch_paths_impl(a, betas, nbeta, l_target, paths, final_xyz, ndistinct);
    size_t stride = kin__abi_size(paths);
    kin_branch_path *full = calloc(2 * (size_t)nbeta, sizeof *full);
    if (!full) {
        if (ndistinct) *ndistinct = 0;
        return KIN_ENOMEM;
    }
    int rc = branch_paths_impl(a, betas, nbeta, l_target, full, final_xyz, ndistinct);
    for (size_t i = 0; i < 2 * (size_t)nbeta; ++i) {
        kin_branch_path *dst = (kin_branch_path *)((char *)paths + i * stride);
        memcpy(dst, &stride, sizeof stride);
        kin__abi_write(dst, &full[i], KIN__ABI(kin_branch_path));
    }
    free(full);
    return rc;
}
