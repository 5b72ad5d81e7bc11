/* Private: the step control shared by the one-path tracker
 * (homotopy_track.c) and the lockstep tracker (homotopy_batch.c), which
 * follow every path through the same operations and so must use the same
 * constants. */
#ifndef KIN_HOMOTOPY_CONTROL_H
#define KIN_HOMOTOPY_CONTROL_H

#include "homotopy/track/homotopy_lu.h"
#include "homotopy/track/homotopy_pade.h"
#include "homotopy/track/homotopy_track.h"

/* The hottest kernels are compiled twice where the compiler and the
 * platform support function multiversioning (GCC or Clang on x86-64 ELF):
 * for AVX2 (4 doubles per vector register) and for the baseline, picked at
 * load time by the CPU. The AVX2 target has no FMA instructions, so no
 * product-sum is contracted whatever the -ffp-contract setting, and both
 * versions round identically (the results are bit-identical); the
 * x86-64-v4 clones of the lockstep kernels have FMA, and CMakeLists.txt
 * builds with -ffp-contract=off (GCC's default in ISO C mode, not Clang's).
 *
 * A cloned function is static, called only from the file that defines it;
 * other files call a plain function there that calls it. The compilers
 * name the dispatcher differently: GCC gives it the function's own name,
 * Clang before 18 names it `name.ifunc` and calls it only where the
 * declaration in view carries the same target_clones (and Clang 14 with the
 * attribute on a declaration alone calls the resolver instead), so a call
 * from another file through a plain prototype does not link with Clang. */
#if defined(__x86_64__) && defined(__ELF__) && defined(__has_attribute) && !defined(KIN_NO_MULTIVERSION)
#if __has_attribute(target_clones)
#define HOM_KERNEL __attribute__((target_clones("avx2", "default")))
#define HOM_MULTIVERSION 1
/* The lockstep kernels (homotopy_lanes.c, homotopy_param_lanes.c) have an
 * AVX-512 clone as well: x86-64-v4 with GCC. Clang (14) dispatches an
 * `arch=` clone by CPU name (__builtin_cpu_is), knows no CPU "x86-64-v4"
 * and so never picks that clone, on an AVX-512 machine either; with Clang
 * the clone is named by its feature, avx512f, dispatched by CPUID. */
#if defined(__clang__)
#define HOM_KERNEL_WIDE __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define HOM_KERNEL_WIDE __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#endif
#endif
#endif
#ifndef HOM_KERNEL
#define HOM_KERNEL
#endif
/* inner loops of the kernels, inlined so that each version gets its own */
#if defined(__GNUC__)
#define HOM_INLINE static inline __attribute__((always_inline))
#else
#define HOM_INLINE static inline
#endif

enum { HOM_ORDER = 8 }; /* Taylor order of the predictor */
enum {
    HOM_NY = HOM_ORDER / 2 + 1,   /* Q x_i needed for i <= HOM_ORDER / 2 */
    NEWTON_MAX = 3,               /* corrector iterations per step */
    HAGER_ITERS = 1,              /* iterations of the |J^-1|_1 estimator */
    REFINE_MAX = 12,              /* Newton iterations at t = 1 */
    MAX_STEPS = 20000             /* accepted + rejected steps before a path counts as lost */
};

/* The error model is calibrated along each path by the ratio of the actual
 * predictor error (the first Newton correction) to its estimate (a running
 * geometric mean), kept within [CALIB_MIN, CALIB_MAX]: the model is usually
 * pessimistic by a factor 3-10, and trusting it more than 10x is not safe. */
static const double CALIB_MIN = 0.1, CALIB_MAX = 4.0;
/* The series' F[x_0, x_k] terms are recovered from J x_k = r_k (see
 * taylor) when t >= T_RECOVER; below, the division by t would amplify
 * rounding by more than 1/T_RECOVER, and they are computed directly. */
static const double T_RECOVER = 1e-3;
/* The predictor's step is at most this fraction of the estimated radius of
 * convergence of the series (beyond it the truncation-error model fails). */
static const double RADIUS_FRACTION = 0.7;
/* A step is accepted when a Newton correction d after the first leaves an
 * error (about |d|^2 / r, r the separation radius, by Newton's quadratic
 * convergence) below NEWTON_TOL |x|, or d itself is below it: the next
 * predictor starts from there, and 1e-9 is far below any predictor error
 * (the endpoint is refined to rounding level anyway). A correction that
 * does not shrink by CONTRACTION means the convergence estimate was wrong,
 * and the step is rejected. */
static const double NEWTON_TOL = 1e-9, CONTRACTION = 0.5;
/* The first correction may not exceed this fraction of |x| whatever the
 * separation radius says (guards a grossly wrong predictor). */
static const double CORR_REL_MAX = 1e-2;
/* After a rejection the step shrinks by REJECT_SHRINK; after an accepted
 * step the cap grows by ACCEPT_GROW (prevents reject/accept oscillation). */
static const double REJECT_SHRINK = 0.5, ACCEPT_GROW = 2.0;
/* For the chart a.x = 1, |a||x| >= 1 measures how far x tilts from it (a
 * random chart gives about sqrt(m)); beyond CHART_TILT sqrt(m) the chart is
 * replaced by the one orthogonal to x. */
static const double CHART_TILT = 8.0;
/* Steps below H_MIN cannot be resolved in t in double precision. */
static const double H_MIN = 1e-14;
/* Newton's corrections cannot fall below rounding noise, about
 * eps |x| / r relative to |x| (r: the separation radius, small where J is
 * nearly singular); the acceptance tolerance is NOISE_FACTOR times that when
 * it exceeds NEWTON_TOL. */
static const double NOISE_FACTOR = 100.0;
/* A path that stalls (step below H_MIN) within SIGMA_STALL of t = 1 is
 * approaching a singular endpoint closer than double precision can follow
 * (near a positive-dimensional component the separation radius shrinks like
 * 1 - t) and goes to the endpoint classification; one that stalls earlier
 * is lost. */
static const double SIGMA_STALL = 1e-3;
/* The predictor's step for the error target from the norms n[1..HOM_ORDER]
 * of the Taylor coefficients; *rho and *tail receive the error model
 * (error(h) ~ tail (h / rho)^(HOM_ORDER+1)) for kin__hom_series_error. */
double kin__hom_series_step(const double *n, double target, double *rho, double *tail);
/* the error model's estimate for step h */
double kin__hom_series_error(double rho, double tail, double h);

/* The rational predictor (homotopy_pade.h) of the series c[0..HOM_ORDER]
 * (m coordinates). */
void kin__hom_pade_setup(int m, const double (*cr)[HOM_MAX_M], const double (*ci)[HOM_MAX_M], hom_pade *pd);

#endif /* KIN_HOMOTOPY_CONTROL_H */
