/* Internal helpers shared by the runtimes: messages, checked size arithmetic, allocation, the state byte
 * writer/reader and small dense linear algebra. Not part of the public API. */
#ifndef WEC_COMMON_H
#define WEC_COMMON_H

#include <stddef.h>
#include <stdint.h>

#include "wec_data.h"
#include "wec_error.h"

#if defined(_MSC_VER)
#define WEC_THREAD_LOCAL __declspec(thread)
#else
#define WEC_THREAD_LOCAL _Thread_local
#endif

#if defined(__GNUC__)
#define WEC_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define WEC_PRINTF(a, b)
#endif

/* ------------------------------------------------------------------------------------------------ messages */
/* printf into message[0, size), always NUL-terminated, truncated if long; returns status (convenience). */
int wec_fail(char *message, size_t size, int status, const char *format, ...) WEC_PRINTF(4, 5);

/* ----------------------------------------------------------------------------------- checked size arithmetic */
/* *out = a * b (or a + b); 0 on overflow of size_t (then *out is unchanged). */
int wec_mul(size_t a, size_t b, size_t *out);
int wec_add(size_t a, size_t b, size_t *out);

/* calloc of count doubles / int64 / bytes (zeroed); NULL on overflow or failure; count 0 allocates one. */
double *wec_alloc_f64(size_t count);
int64_t *wec_alloc_i64(size_t count);

/* ---------------------------------------------------------------------------------- state writer and reader */
/* Little-endian byte stream. A writer with buffer NULL only counts (its pos is the size needed); writing past
 * size sets failed. A reader reading past size sets failed and returns zeros. */
typedef struct wec_writer {
    unsigned char *buffer;
    size_t size, pos;
    int failed;
} wec_writer;

typedef struct wec_reader {
    const unsigned char *buffer;
    size_t size, pos;
    int failed;
} wec_reader;

void wec_put_bytes(wec_writer *w, const void *bytes, size_t n);
void wec_put_u64(wec_writer *w, uint64_t value);
void wec_put_i64(wec_writer *w, int64_t value);
void wec_put_f64(wec_writer *w, double value);
void wec_put_f64s(wec_writer *w, const double *values, size_t n);

void wec_get_bytes(wec_reader *r, void *bytes, size_t n);
uint64_t wec_get_u64(wec_reader *r);
int64_t wec_get_i64(wec_reader *r);
double wec_get_f64(wec_reader *r);
void wec_get_f64s(wec_reader *r, double *values, size_t n);

/* ---------------------------------------------------------------------------------------- linear algebra */
/* Workspace of wec_expm for matrices up to order n: wec_expm_workspace_size(n) doubles and n int64. */
size_t wec_expm_workspace_size(size_t n);

/* exp(a) (n x n, row-major) into out by scaling and squaring with a diagonal Pade approximant of degree 3, 5, 7,
 * 9 or 13 (Higham 2005, "The scaling and squaring method for the matrix exponential revisited": backward error
 * below the unit round-off for every 1-norm; the degree-13 approximant after scaling by 2^-s so that the scaled
 * norm is at most 5.37). Returns 0, or 1 if a is not finite or the Pade denominator is singular. */
int wec_expm(const double *a, size_t n, double *out, double *work, int64_t *pivots);

/* LU factorisation with partial pivoting of a (n x n, row-major, in place) and the solution of a x = b for m
 * right-hand sides b (n x m, row-major, overwritten by x). Returns 1 if a pivot is exactly zero. */
int wec_lu_solve(double *a, size_t n, double *b, size_t m, int64_t *pivots);

#endif
