/* Private: Fortran LAPACK/BLAS prototypes (the only place they are written).
 *
 * Fortran passes everything by reference; CHARACTER arguments carry a hidden
 * length appended after the last argument (size_t with gfortran >= 8, which
 * is what reference LAPACK and OpenBLAS on Debian are built with). */
#ifndef KIN_LAPACK_H
#define KIN_LAPACK_H

#include <stddef.h>

typedef size_t kin_fstrlen;

void dgesdd_(const char *jobz, const int *m, const int *n, double *a, const int *lda, double *s,
             double *u, const int *ldu, double *vt, const int *ldvt, double *work,
             const int *lwork, int *iwork, int *info, kin_fstrlen jobz_len);

void dgesvd_(const char *jobu, const char *jobvt, const int *m, const int *n, double *a,
             const int *lda, double *s, double *u, const int *ldu, double *vt, const int *ldvt,
             double *work, const int *lwork, int *info, kin_fstrlen jobu_len,
             kin_fstrlen jobvt_len);

void dgelsd_(const int *m, const int *n, const int *nrhs, double *a, const int *lda, double *b,
             const int *ldb, double *s, const double *rcond, int *rank, double *work,
             const int *lwork, int *iwork, int *info);

void dgels_(const char *trans, const int *m, const int *n, const int *nrhs, double *a,
            const int *lda, double *b, const int *ldb, double *work, const int *lwork, int *info,
            kin_fstrlen trans_len);

void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);

void dgetri_(const int *n, double *a, const int *lda, const int *ipiv, double *work, const int *lwork, int *info);

void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a, const int *lda,
             const int *ipiv, double *b, const int *ldb, int *info, kin_fstrlen trans_len);

void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda, double *w,
            double *work, const int *lwork, int *info, kin_fstrlen jobz_len, kin_fstrlen uplo_len);

void dgelqf_(const int *m, const int *n, double *a, const int *lda, double *tau, double *work,
             const int *lwork, int *info);

void dormlq_(const char *side, const char *trans, const int *m, const int *n, const int *k,
             const double *a, const int *lda, const double *tau, double *c, const int *ldc,
             double *work, const int *lwork, int *info, kin_fstrlen side_len,
             kin_fstrlen trans_len);

void dtrtrs_(const char *uplo, const char *trans, const char *diag, const int *n, const int *nrhs,
             const double *a, const int *lda, double *b, const int *ldb, int *info,
             kin_fstrlen uplo_len, kin_fstrlen trans_len, kin_fstrlen diag_len);

void dgemv_(const char *trans, const int *m, const int *n, const double *alpha, const double *a,
            const int *lda, const double *x, const int *incx, const double *beta, double *y,
            const int *incy, kin_fstrlen trans_len);

void dgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k,
            const double *alpha, const double *a, const int *lda, const double *b,
            const int *ldb, const double *beta, double *c, const int *ldc, kin_fstrlen ta_len,
            kin_fstrlen tb_len);

void dgeqrf_(const int *m, const int *n, double *a, const int *lda, double *tau, double *work,
             const int *lwork, int *info);

void dorgqr_(const int *m, const int *n, const int *k, double *a, const int *lda, const double *tau,
             double *work, const int *lwork, int *info);

void dgeqr2_(const int *m, const int *n, double *a, const int *lda, double *tau, double *work, int *info);

void dorm2r_(const char *side, const char *trans, const int *m, const int *n, const int *k,
             const double *a, const int *lda, const double *tau, double *c, const int *ldc,
             double *work, int *info, kin_fstrlen side_len, kin_fstrlen trans_len);

#endif /* KIN_LAPACK_H */
