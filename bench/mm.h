/* mm.h: Matrix Market files for the peer benchmarks (bench/sysdump.c writes
 * the systems the headers build, bench/bench_sparse.c reads them back).
 * Sparse matrices are "coordinate real|complex general" with every entry
 * written (no symmetry folding, so any reader gets the whole matrix), in
 * row order; vectors are "array real|complex general" columns. Values are
 * printed with 17 significant digits, so they read back bit-exact.
 * Complex numbers are (re, im) pairs of doubles, as in zsparse.h. */
#ifndef PW_BENCH_MM_H
#define PW_BENCH_MM_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A sparse matrix in CSR with sorted columns; val holds 1 double per
 * entry, or 2 (re, im) when cplx. */
typedef struct mm_csr {
    int n, m, cplx;
    int *rowptr, *col;
    double *val;
} mm_csr;

static inline void mm_csr_free(mm_csr *A)
{
    free(A->rowptr);
    free(A->col);
    free(A->val);
    memset(A, 0, sizeof *A);
}

/* Writes A to path with `comment` (one line, no newline) after the banner. */
static inline int mm_write_csr(const char *path, const char *comment, const mm_csr *A)
{
    FILE *f = fopen(path, "w");
    int i, k, w = A->cplx ? 2 : 1;
    if (!f) return 1;
    fprintf(f, "%%%%MatrixMarket matrix coordinate %s general\n%% %s\n%d %d %d\n", A->cplx ? "complex" : "real",
            comment, A->n, A->m, A->rowptr[A->n]);
    for (i = 0; i < A->n; i++)
        for (k = A->rowptr[i]; k < A->rowptr[i + 1]; k++) {
            fprintf(f, "%d %d %.17g", i + 1, A->col[k] + 1, A->val[w * k]);
            if (A->cplx) fprintf(f, " %.17g", A->val[w * k + 1]);
            fputc('\n', f);
        }
    return fclose(f) != 0;
}

/* Writes n entries (complex: n pairs) of v as a column. */
static inline int mm_write_vec(const char *path, const double *v, int n, int cplx)
{
    FILE *f = fopen(path, "w");
    int i;
    if (!f) return 1;
    fprintf(f, "%%%%MatrixMarket matrix array %s general\n%d 1\n", cplx ? "complex" : "real", n);
    for (i = 0; i < n; i++)
        if (cplx) fprintf(f, "%.17g %.17g\n", v[2 * i], v[2 * i + 1]);
        else fprintf(f, "%.17g\n", v[i]);
    return fclose(f) != 0;
}

/* Skips the banner (checking it names `kind`, "coordinate" or "array") and
 * comments; returns 1 if complex, 0 if real, -1 on a bad file. */
static inline int mm__banner(FILE *f, const char *kind)
{
    char line[1024];
    int cplx;
    if (!fgets(line, sizeof line, f) || strncmp(line, "%%MatrixMarket matrix ", 22) || !strstr(line, kind))
        return -1;
    cplx = strstr(line, " complex ") != NULL;
    if (!cplx && !strstr(line, " real ")) return -1;
    for (;;) {
        long at = ftell(f);
        int c = fgetc(f);
        if (c != '%') {
            fseek(f, at, SEEK_SET);
            return cplx;
        }
        if (!fgets(line, sizeof line, f)) return -1;
    }
}

/* Reads a coordinate matrix into A (entries in any order; duplicates are
 * kept as separate entries, which is what CSR products sum anyway).
 * Returns 0 on success. */
static inline int mm_read_csr(const char *path, mm_csr *A)
{
    FILE *f = fopen(path, "r");
    int nnz, k, w, *row = NULL, *at = NULL, ok = 0;
    double *v = NULL;
    memset(A, 0, sizeof *A);
    if (!f) return 1;
    if ((A->cplx = mm__banner(f, "coordinate")) < 0 || fscanf(f, "%d %d %d", &A->n, &A->m, &nnz) != 3 ||
        A->n < 0 || A->m < 0 || nnz < 0)
        goto done;
    w = A->cplx ? 2 : 1;
    row = (int *)malloc(sizeof(int) * ((size_t)nnz + 1));
    at = (int *)malloc(sizeof(int) * ((size_t)nnz + 1));
    v = (double *)malloc(sizeof(double) * w * ((size_t)nnz + 1));
    A->rowptr = (int *)calloc((size_t)A->n + 1, sizeof(int));
    A->col = (int *)malloc(sizeof(int) * ((size_t)nnz + 1));
    A->val = (double *)malloc(sizeof(double) * w * ((size_t)nnz + 1));
    if (!row || !at || !v || !A->rowptr || !A->col || !A->val) goto done;
    for (k = 0; k < nnz; k++) {
        if (fscanf(f, "%d %d %lf", &row[k], &at[k], &v[w * k]) != 3) goto done;
        if (A->cplx && fscanf(f, "%lf", &v[w * k + 1]) != 1) goto done;
        if (--row[k] < 0 || row[k] >= A->n || --at[k] < 0 || at[k] >= A->m) goto done;
        A->rowptr[row[k] + 1]++;
    }
    for (k = 0; k < A->n; k++) A->rowptr[k + 1] += A->rowptr[k];
    { /* counting sort by row, then insertion sort of each (short) row by column */
        int *fill = (int *)malloc(sizeof(int) * ((size_t)A->n + 1)), i, j;
        if (!fill) goto done;
        memcpy(fill, A->rowptr, sizeof(int) * (size_t)A->n);
        for (k = 0; k < nnz; k++) {
            int d = fill[row[k]]++;
            A->col[d] = at[k];
            memcpy(A->val + w * d, v + w * k, sizeof(double) * w);
        }
        free(fill);
        for (i = 0; i < A->n; i++)
            for (k = A->rowptr[i] + 1; k < A->rowptr[i + 1]; k++)
                for (j = k; j > A->rowptr[i] && A->col[j - 1] > A->col[j]; j--) {
                    int c = A->col[j];
                    double t[2];
                    A->col[j] = A->col[j - 1], A->col[j - 1] = c;
                    memcpy(t, A->val + w * j, sizeof(double) * w);
                    memcpy(A->val + w * j, A->val + w * (j - 1), sizeof(double) * w);
                    memcpy(A->val + w * (j - 1), t, sizeof(double) * w);
                }
    }
    ok = 1;
done:
    fclose(f);
    free(row);
    free(at);
    free(v);
    if (!ok) mm_csr_free(A);
    return !ok;
}

/* Reads a column of n entries (complex as cplx says: 2n doubles) into a
 * new array; NULL on a bad file or a size other than n. */
static inline double *mm_read_vec(const char *path, int n, int cplx)
{
    FILE *f = fopen(path, "r");
    int rows, cols, i, w = cplx ? 2 : 1;
    double *v = NULL;
    if (!f) return NULL;
    if (mm__banner(f, "array") == cplx && fscanf(f, "%d %d", &rows, &cols) == 2 && rows == n && cols == 1 &&
        (v = (double *)malloc(sizeof(double) * w * ((size_t)n + 1))) != NULL)
        for (i = 0; i < w * n; i++)
            if (fscanf(f, "%lf", &v[i]) != 1) {
                free(v);
                v = NULL;
                break;
            }
    fclose(f);
    return v;
}

#endif
