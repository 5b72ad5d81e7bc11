/* Minimal test helpers shared by the C tests. Tolerances are written as
 * multiples of DBL_EPSILON where they are about rounding. */
#ifndef KIN_TEST_CHECK_H
#define KIN_TEST_CHECK_H

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int check_failures_ = 0;

#define CHECK(cond)                                                                      \
    do {                                                                                 \
        if (!(cond)) {                                                                   \
            fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);     \
            ++check_failures_;                                                           \
        }                                                                                \
    } while (0)

#define CHECK_CLOSE(x, y, tol)                                                           \
    do {                                                                                 \
        double x_ = (x), y_ = (y), t_ = (tol);                                           \
        if (!(fabs(x_ - y_) <= t_)) {                                                    \
            fprintf(stderr, "%s:%d: CHECK_CLOSE failed: %s = %.17g, %s = %.17g, tol %.3g\n", \
                    __FILE__, __LINE__, #x, x_, #y, y_, t_);                             \
            ++check_failures_;                                                           \
        }                                                                                \
    } while (0)

#define CHECK_RC(expr, want)                                                             \
    do {                                                                                 \
        int got_ = (expr);                                                               \
        if (got_ != (want)) {                                                            \
            fprintf(stderr, "%s:%d: %s returned %s (%d), want %s\n", __FILE__, __LINE__,    \
                    #expr, kin_status_name(got_), got_, #want);                          \
            ++check_failures_;                                                           \
        }                                                                                \
    } while (0)

#define TEST_REPORT(name)                                                                \
    do {                                                                                 \
        printf("%s: %s (%d failed checks)\n", name, check_failures_ ? "FAIL" : "ok",    \
               check_failures_);                                                         \
        return check_failures_ ? 1 : 0;                                                  \
    } while (0)

#endif
