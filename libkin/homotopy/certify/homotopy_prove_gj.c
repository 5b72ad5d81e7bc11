/* Gauss-Jordan elimination with partial pivoting (by |re| + |im|) in
 * double precision, shared by the proofs' 53-bit tests
 * (homotopy_prove_fast.c, homotopy_prove_exact.c): both need only *some*
 * matrix Y close to J^-1, whose accuracy does not enter the proof (Y is an
 * exact number however it was computed), so a plain elimination will do. */
#include <math.h>

#include "homotopy/certify/homotopy_prove.h"

int kin__prove_gauss_jordan(int s, double *Ar, double *Ai, int cx)
{
    int w = 2 * s;
    for (int r = 0; r < s; ++r)
        for (int c = s; c < w; ++c) Ar[r * w + c] = c - s == r, Ai[r * w + c] = 0.0;
    for (int p = 0; p < s; ++p) {
        int best = p;
        for (int r = p + 1; r < s; ++r)
            if (fabs(Ar[r * w + p]) + (cx ? fabs(Ai[r * w + p]) : 0.0) >
                fabs(Ar[best * w + p]) + (cx ? fabs(Ai[best * w + p]) : 0.0))
                best = r;
        if (best != p)
            for (int c = 0; c < w; ++c) {
                double t = Ar[p * w + c];
                Ar[p * w + c] = Ar[best * w + c], Ar[best * w + c] = t;
                t = Ai[p * w + c];
                Ai[p * w + c] = Ai[best * w + c], Ai[best * w + c] = t;
            }
        double pr = Ar[p * w + p], pi = cx ? Ai[p * w + p] : 0.0, d = pr * pr + pi * pi;
        if (!(d > 0.0) || !isfinite(d)) return 0;
        double ir = pr / d, ii = -pi / d; /* 1 / pivot */
        for (int c = p; c < w; ++c) {
            double a = Ar[p * w + c], b = cx ? Ai[p * w + c] : 0.0;
            Ar[p * w + c] = a * ir - b * ii, Ai[p * w + c] = a * ii + b * ir;
        }
        for (int r = 0; r < s; ++r) {
            double gr = Ar[r * w + p], gi = cx ? Ai[r * w + p] : 0.0;
            if (r == p || (gr == 0.0 && gi == 0.0)) continue;
            if (cx) { /* columns < p: 0 in row p; rows r != p: distinct */
                double *restrict dr = Ar + r * w, *restrict di = Ai + r * w;
                const double *restrict sr = Ar + p * w, *restrict si = Ai + p * w;
                for (int c = p; c < w; ++c) dr[c] -= gr * sr[c] - gi * si[c], di[c] -= gr * si[c] + gi * sr[c];
            }
            else { /* rows r != p: distinct (restrict lets the compiler vectorize) */
                double *restrict dst = Ar + r * w;
                const double *restrict src = Ar + p * w;
                for (int c = p; c < w; ++c) dst[c] -= gr * src[c];
            }
        }
    }
    return 1;
}

