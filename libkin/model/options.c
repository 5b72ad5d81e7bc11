/* The options of a handle (kin_options, kin_path.h): defaults, the
 * caller's struct read as far as its size goes (docs/abi.md), and the range
 * checks. Applying them (kin_set_options) belongs to the path layer, which
 * also prepares the sparse workspace a mode needs (path/path.c). */
#include <math.h>
#include <string.h>

#include "model/internal.h"

/* the defaults, in one table (fields not named are zero) */
static const kin_options DEFAULTS = {
    .size = sizeof(kin_options),
    .rank_tol = 1e-9,
    .corrector_tol = 1e-12,
    .corrector_max_iter = 60,
    .step_fraction = 0.1,
    .max_halvings = 12,
    .direction_tol = 0.9,
    .max_correction = 0.5,
    .factorization = KIN_STEP_SVD,
    .step_control = KIN_STEP_CONTROL_MODE,
    .coord_resolution = 0.0,
};

int kin_options_init(kin_options *o, size_t size)
{
    return kin__abi_init(o, size, &DEFAULTS, KIN__ABI(kin_options));
}

/* for binaries built before the macro: the first layout only (docs/abi.md) */
void (kin_options_default)(kin_options *o)
{
    if (o) kin__abi_init(o, KIN__ABI(kin_options)->size[0], &DEFAULTS, KIN__ABI(kin_options));
}

static int unit_open(double v) { return isfinite(v) && v > 0.0 && v < 1.0; }

int kin__options_read(kin_assembly *a, const kin_options *user, kin_options *o)
{
    if (kin__abi_check(user, KIN__ABI(kin_options)))
        return kin__fail(a, KIN_EINVAL, "options.size = %zu: not set by kin_options_default() of this libkin",
                         kin__abi_size(user));
    kin_options_default(o); /* fields an older caller does not have keep their defaults */
    kin__abi_read(o, user, KIN__ABI(kin_options));
    if (!unit_open(o->rank_tol)) return kin__fail(a, KIN_EINVAL, "rank_tol = %g, need 0 < tol < 1", o->rank_tol);
    if (!unit_open(o->corrector_tol))
        return kin__fail(a, KIN_EINVAL, "corrector_tol = %g, need 0 < tol < 1", o->corrector_tol);
    if (o->corrector_max_iter < 1 || o->corrector_max_iter > 100000)
        return kin__fail(a, KIN_EINVAL, "corrector_max_iter = %d, need 1..100000", o->corrector_max_iter);
    if (!(isfinite(o->step_fraction) && o->step_fraction > 0.0))
        return kin__fail(a, KIN_EINVAL, "step_fraction = %g, need finite > 0", o->step_fraction);
    if (o->max_halvings < 0 || o->max_halvings > 60)
        return kin__fail(a, KIN_EINVAL, "max_halvings = %d, need 0..60", o->max_halvings);
    if (!(isfinite(o->direction_tol) && o->direction_tol >= 0.0 && o->direction_tol < 1.0))
        return kin__fail(a, KIN_EINVAL, "direction_tol = %g, need 0 <= tol < 1", o->direction_tol);
    if (!(isfinite(o->max_correction) && o->max_correction > 0.0))
        return kin__fail(a, KIN_EINVAL, "max_correction = %g, need finite > 0", o->max_correction);
    if (o->factorization != KIN_STEP_SVD && o->factorization != KIN_STEP_LU &&
        o->factorization != KIN_STEP_SPARSE)
        return kin__fail(a, KIN_EINVAL,
                         "factorization = %d, need KIN_STEP_SVD (0), KIN_STEP_LU (1) or KIN_STEP_SPARSE (2)",
                         o->factorization);
    if (o->step_control != KIN_STEP_CONTROL_MODE && o->step_control != KIN_STEP_CONTROL_SHARED)
        return kin__fail(a, KIN_EINVAL, "step_control = %d, need KIN_STEP_CONTROL_MODE (0) or "
                         "KIN_STEP_CONTROL_SHARED (1)", o->step_control);
    if (!(isfinite(o->coord_resolution) && o->coord_resolution >= 0.0))
        return kin__fail(a, KIN_EINVAL, "coord_resolution = %g, need finite >= 0", o->coord_resolution);
    return KIN_OK;
}

/* The strain that coordinates rounded to coord_resolution leave in rest
 * lengths taken from them: each endpoint is off by up to half the
 * resolution per coordinate, so a length by up to sqrt(dim) * resolution;
 * relative to the shortest bar. An exact mechanism's configurations, in a
 * structure built from its rounded coordinates, have at most this strain
 * (the corrector's floor, STRAIN FLOOR in kin_path.h), and the rounding
 * moves the entries of H (direction cosines) by as much relative to v_max's
 * scale: singular values below it are zero to the input's accuracy. */
double kin__resolution_strain(const kin_assembly *a)
{
    if (!(a->opt.coord_resolution > 0.0) || a->nb == 0) return 0.0;
    return sqrt((double)a->dim) * a->opt.coord_resolution / a->min_length;
}

double kin__rank_tolerance(const kin_assembly *a) { return fmax(a->opt.rank_tol, kin__resolution_strain(a)); }

int kin_get_options(const kin_assembly *a, kin_options *o)
{
    if (!a || !o) return KIN_ENULL;
    if (kin__abi_check(o, KIN__ABI(kin_options))) return KIN_EINVAL;
    kin__abi_write(o, &a->opt, KIN__ABI(kin_options));
    return KIN_OK;
}

