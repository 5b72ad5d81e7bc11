/* Gauss-Jordan elimination with partial pivoting (by |re| + |im|) in
 * double precision, shared by the proofs' 53-bit tests
 * (homotopy_prove_fast.c, homotopy_prove_exact.c): both need only *some*
 * matrix Y close to J^-1, whose accuracy does not enter the proof (Y is an
 * exact number however it was computed), so a plain elimination will do.
 * In place (the inverse built over J's columns, s^3 multiply-adds rather
 * than [J | I]'s 1.5 s^3; a sixth of an endpoint's exact test), then its
 * columns unscrambled from the row interchanges and copied to the right half. */
#include <math.h>

#include "homotopy/certify/homotopy_prove.h"

/* row r -= g row p over the s columns (real or complex); rows r != p are
 * distinct (restrict lets the compiler vectorize) */
static void eliminate(int s, int w, double *Ar, double *Ai, int r, int p, int cx)
{
    double gr = Ar[r * w + p], gi = cx ? Ai[r * w + p] : 0.0;
    if (gr == 0.0 && gi == 0.0) return;
    Ar[r * w + p] = 0.0, Ai[r * w + p] = 0.0;
    double *restrict dr = Ar + r * w, *restrict di = Ai + r * w;
    const double *restrict sr = Ar + p * w, *restrict si = Ai + p * w;
    if (cx)
        for (int c = 0; c < s; ++c) dr[c] -= gr * sr[c] - gi * si[c], di[c] -= gr * si[c] + gi * sr[c];
    else
        for (int c = 0; c < s; ++c) dr[c] -= gr * sr[c];
}

int kin__prove_gauss_jordan(int s, double *Ar, double *Ai, int cx)
{
    int w = 2 * s, perm[HOM_PROVE_MAX_M];
    for (int p = 0; p < s; ++p) {
        int best = p;
        for (int r = p + 1; r < s; ++r)
            if (fabs(Ar[r * w + p]) + (cx ? fabs(Ai[r * w + p]) : 0.0) >
                fabs(Ar[best * w + p]) + (cx ? fabs(Ai[best * w + p]) : 0.0))
                best = r;
        perm[p] = best;
        if (best != p)
            for (int c = 0; c < s; ++c) {
                double t = Ar[p * w + c];
                Ar[p * w + c] = Ar[best * w + c], Ar[best * w + c] = t;
                t = Ai[p * w + c];
                Ai[p * w + c] = Ai[best * w + c], Ai[best * w + c] = t;
            }
        double pr = Ar[p * w + p], pi = cx ? Ai[p * w + p] : 0.0, d = pr * pr + pi * pi;
        if (!(d > 0.0) || !isfinite(d)) return 0;
        double ir = pr / d, ii = -pi / d; /* 1 / pivot */
        Ar[p * w + p] = 1.0, Ai[p * w + p] = 0.0; /* the pivot's column becomes the inverse's */
        for (int c = 0; c < s; ++c) {
            double a = Ar[p * w + c], b = cx ? Ai[p * w + c] : 0.0;
            Ar[p * w + c] = a * ir - b * ii, Ai[p * w + c] = a * ii + b * ir;
        }
        for (int r = 0; r < s; ++r)
            if (r != p) eliminate(s, w, Ar, Ai, r, p, cx);
    }
    for (int p = s - 1; p >= 0; --p) /* undo the interchanges on the inverse's columns */
        if (perm[p] != p)
            for (int r = 0; r < s; ++r) {
                double t = Ar[r * w + p];
                Ar[r * w + p] = Ar[r * w + perm[p]], Ar[r * w + perm[p]] = t;
                t = Ai[r * w + p];
                Ai[r * w + p] = Ai[r * w + perm[p]], Ai[r * w + perm[p]] = t;
            }
    for (int r = 0; r < s; ++r)
        for (int c = 0; c < s; ++c) Ar[r * w + s + c] = Ar[r * w + c], Ai[r * w + s + c] = cx ? Ai[r * w + c] : 0.0;
    return 1;
}
