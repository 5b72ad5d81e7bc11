/* Private to the sparse mode: sparse_matrix.c (J's values, products with
 * C), sparse_border.c (the stand-in rows, factorization and solves with the
 * bordering correction) and sparse.c (J's pattern, set-up, column order). */
#ifndef KIN_SPARSE_INTERNAL_H
#define KIN_SPARSE_INTERNAL_H

#include <klu.h>

#include "path/path.h"

/* one lu[] slot's factors */
struct kin_slot {
    int *Ap, *Ai;         /* J0 = [C; stand-in rows] in compressed columns */
    double *Ax;
    int *k;               /* its stand-in coordinates (nbr) */
    int gen;              /* the stand-in generation its pattern was built for */
    klu_symbolic *sym;    /* J0's analysis (the kept column order) */
    klu_numeric *num;     /* J0's factors */
    klu_numeric *dnum;    /* J's factors with the dense rows, where J0 failed */
    int dense;            /* the last factorization is dnum's */
    double *W;            /* nf x nbr: the true border rows [b, R] */
    double *Z;            /* nf x nbr: J0^-1 [e_nb ... e_(nf-1)] */
    double *S;            /* nbr x nbr: LU of the capacitance (dgetrf) */
    int *piv;             /* its pivots */
};

struct kin_sparse {
    int n;       /* nf: J is n x n */
    int nb;      /* bar rows */
    int nbr;     /* border rows: n - nb (1 + m_rigid) */
    int *Ap;     /* J with its dense rows: n + 1 column pointers */
    int *Ai;     /* row indices: bar rows ascending, then the border rows nb..n-1 */
    double *Ax;  /* values of the last factorization */
    int *pos;    /* nb * 2 * dim: Ax index of bar k, end e, axis c (or -1: fixed) */
    int *Q;      /* the kept column order (n) */
    int *k;      /* the current stand-in coordinates (nbr) */
    int gen;     /* their generation: +1 at every re-choice */
    klu_common common;
    klu_symbolic *dsym;    /* J with its dense rows: analysis made at set-up */
    struct kin_slot slot[2];
    double *B;             /* nf x nbr scratch: the basis the stand-ins are chosen from */
    double *h;             /* nbr * (nbr + 1) scratch */
    int nested_dissection; /* the column order is METIS's (1) or COLAMD's (0) */
    double entries[2];     /* J0's factor entries at set-up: COLAMD, METIS */
    double entries_dense;  /* J's (dense rows) at set-up */
    long rechoices;        /* stand-in re-choices since set-up */
    long dense_points;     /* factorizations made with the dense rows since set-up */
};

/* sparse_matrix.c: the values of J(xyz) with its dense border rows b and R
 * (nbr - 1 columns, ld nf) into s->Ax */
void kin__sparse_fill(const kin_assembly *a, const double *xyz, const double *b, const double *R);

/* sparse_border.c */
/* Choose the stand-in coordinates s->k from the basis B (nf x nbr, ld nf;
 * overwritten): each slot re-analyses at its next factorization. */
void kin__standin_choose(struct kin_sparse *s, double *B);
/* J0's pattern (slot sl's stand-ins := s->k) and its values */
void kin__standin_pattern(struct kin_sparse *s, struct kin_slot *sl);
void kin__standin_values(const struct kin_sparse *s, struct kin_slot *sl);
/* New pattern and analysis of slot sl (kept column order; allocates).
 * KIN_OK or KIN_ENOMEM. */
int kin__standin_analyse(kin_assembly *a, struct kin_slot *sl);
/* Stand-ins chosen from null(C) as given by the dense-row factors num.
 * KIN_OK or KIN_ENOMEM. */
int kin__standin_from_dense(kin_assembly *a, klu_numeric *num);

#endif /* KIN_SPARSE_INTERNAL_H */
