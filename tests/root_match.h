/* Comparing two solvers' real second-order solutions (tests and benches):
 * projective roots beta are equal up to sign. Header-only (static). */
#ifndef KIN_TEST_ROOT_MATCH_H
#define KIN_TEST_ROOT_MATCH_H

#include <math.h>

/* how many of the n roots a (m each) have no root of b within tol (max
 * norm, up to sign) */
static int unmatched_roots(int m, int n, const double *a, const double *b, double tol)
{
    int bad = 0;
    for (int i = 0; i < n; ++i) {
        int found = 0;
        for (int j = 0; j < n && !found; ++j) {
            double dp = 0.0, dm = 0.0;
            for (int c = 0; c < m; ++c) {
                dp = fmax(dp, fabs(a[i * m + c] - b[j * m + c]));
                dm = fmax(dm, fabs(a[i * m + c] + b[j * m + c]));
            }
            found = fmin(dp, dm) <= tol;
        }
        bad += !found;
    }
    return bad;
}

#endif /* KIN_TEST_ROOT_MATCH_H */
