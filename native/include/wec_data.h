/* The runtime input container: plain, versioned binary data of named typed arrays (docs/runtime.md).
 *
 * Layout (every integer little-endian):
 *
 *     offset  size        content
 *     0       8           magic "WECRTDAT"
 *     8       4           uint32 format version (WEC_DATA_VERSION)
 *     12      4           uint32 number of arrays C
 *     16      16          kind, ASCII, NUL-padded ("hydro", later "mbd")
 *     32      8           uint64 total size of the container in bytes (must equal the buffer's)
 *     40      8           reserved, 0
 *     48      128 C       directory, one entry per array:
 *                           64 bytes name (ASCII letters, digits, '_' and '.', NUL-padded, at least one NUL)
 *                           1 byte dtype (1 float64, 2 int64, 3 uint8), 1 byte ndim (0..4), 6 bytes 0,
 *                           4 x uint64 shape (unused dimensions 0), uint64 offset from the container's start
 *                           (a multiple of 8), uint64 size in bytes, 8 bytes 0
 *     ...                 array data, C order, little-endian, each at its offset
 *
 * The reader trusts nothing: wec_data_open checks every field against the buffer's length and against the other
 * entries (sizes without integer overflow, offsets inside the buffer and past the directory, no two arrays
 * overlapping, names unique) before any array is used, and the typed getters check dtype, rank, shape and (on
 * request) that the values are finite. Every refusal names the array and the problem. */
#ifndef WEC_DATA_H
#define WEC_DATA_H

#include <stddef.h>
#include <stdint.h>

#include "wec_error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define WEC_DATA_VERSION 1
#define WEC_DATA_HEADER_SIZE 48
#define WEC_DATA_ENTRY_SIZE 128
#define WEC_DATA_NAME_SIZE 64
#define WEC_DATA_KIND_SIZE 16
#define WEC_DATA_MAX_DIMS 4

typedef enum wec_dtype { WEC_F64 = 1, WEC_I64 = 2, WEC_U8 = 3 } wec_dtype;

typedef struct wec_array {
    char name[WEC_DATA_NAME_SIZE];
    int dtype;
    int ndim;
    uint64_t shape[WEC_DATA_MAX_DIMS];
    uint64_t count;             /* number of elements (1 for a scalar) */
    const unsigned char *bytes; /* inside the caller's buffer: read with the wec_array_* functions */
    size_t nbytes;
} wec_array;

typedef struct wec_data {
    const unsigned char *buffer;
    size_t size;
    char kind[WEC_DATA_KIND_SIZE + 1];
    uint32_t version;
    size_t count;
    wec_array *arrays;
} wec_data;

/* Reads and checks the container in buffer[0, size) of the given kind; on failure returns an error status with
 * the reason in message[0, message_size). The arrays point into the buffer, which must outlive the wec_data. */
int wec_data_open(wec_data *data, const void *buffer, size_t size, const char *kind, char *message,
                  size_t message_size);
void wec_data_close(wec_data *data);

/* The array called name, or NULL. */
const wec_array *wec_data_find(const wec_data *data, const char *name);

/* Checked access: the array must have the dtype, rank ndim and the shape given (-1: any extent). With finite set,
 * every float64 value must be finite. A missing array is an error when required, else *out is NULL and WEC_OK. */
int wec_data_get(const wec_data *data, const char *name, int dtype, int ndim, const int64_t *shape, int required,
                 int finite, const wec_array **out, char *message, size_t message_size);

/* Element i of an array (no alignment assumed). */
double wec_array_f64(const wec_array *array, size_t i);
int64_t wec_array_i64(const wec_array *array, size_t i);

/* A copy of a float64 / int64 array in newly allocated memory (NULL only on allocation failure; a zero-length
 * array gives a valid one-element allocation). */
double *wec_array_copy_f64(const wec_array *array);
int64_t *wec_array_copy_i64(const wec_array *array);

/* A 64-bit hash of the container's bytes: what a saved state records to refuse being loaded into another model. */
uint64_t wec_data_hash(const void *buffer, size_t size);

#ifdef __cplusplus
}
#endif
#endif
