/* The runtime input container reader (wec_data.h): every field checked before use. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "wec_common.h"

static uint32_t read_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t read_u64(const unsigned char *p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v |= (uint64_t)p[i] << (8 * i);
    return v;
}

static size_t dtype_size(int dtype)
{
    switch (dtype) {
    case WEC_F64: return 8;
    case WEC_I64: return 8;
    case WEC_U8: return 1;
    default: return 0;
    }
}

static const char *dtype_name(int dtype)
{
    switch (dtype) {
    case WEC_F64: return "float64";
    case WEC_I64: return "int64";
    case WEC_U8: return "uint8";
    default: return "unknown";
    }
}

static int host_little_endian(void)
{
    const uint16_t one = 1;
    unsigned char first;
    memcpy(&first, &one, 1);
    return first == 1;
}

static int valid_name(const unsigned char *field, char *name)
{
    size_t len = 0;
    while (len < WEC_DATA_NAME_SIZE && field[len] != 0)
        len++;
    if (len == 0 || len == WEC_DATA_NAME_SIZE)
        return 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = field[i];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.';
        if (!ok)
            return 0;
    }
    for (size_t i = len; i < WEC_DATA_NAME_SIZE; i++)
        if (field[i] != 0)
            return 0;
    memcpy(name, field, len);
    name[len] = '\0';
    return 1;
}

static int by_offset(const void *a, const void *b)
{
    const wec_array *x = *(const wec_array *const *)a, *y = *(const wec_array *const *)b;
    return (x->bytes > y->bytes) - (x->bytes < y->bytes);
}

int wec_data_open(wec_data *data, const void *buffer, size_t size, const char *kind, char *message,
                  size_t message_size)
{
    memset(data, 0, sizeof(*data));
    const unsigned char *b = buffer;
    if (b == NULL)
        return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: no buffer given");
    if (!host_little_endian())
        return wec_fail(message, message_size, WEC_ERR_DATA,
                        "runtime data: this runtime reads little-endian data and runs on a big-endian machine");
    if (size < WEC_DATA_HEADER_SIZE)
        return wec_fail(message, message_size, WEC_ERR_DATA,
                        "runtime data: %zu bytes, shorter than the %d-byte header (truncated or not runtime data)",
                        size, WEC_DATA_HEADER_SIZE);
    if (memcmp(b, "WECRTDAT", 8) != 0)
        return wec_fail(message, message_size, WEC_ERR_DATA,
                        "runtime data: does not start with the magic \"WECRTDAT\" (not wec-cosim runtime data)");
    uint32_t version = read_u32(b + 8);
    if (version != WEC_DATA_VERSION)
        return wec_fail(message, message_size, WEC_ERR_DATA,
                        "runtime data: format version %u, this runtime reads version %d (rebuild the data or the "
                        "FMU with this version of wec-cosim)", (unsigned)version, WEC_DATA_VERSION);
    char found_kind[WEC_DATA_KIND_SIZE + 1];
    memcpy(found_kind, b + 16, WEC_DATA_KIND_SIZE);
    found_kind[WEC_DATA_KIND_SIZE] = '\0';
    for (size_t i = strlen(found_kind); i < WEC_DATA_KIND_SIZE; i++)
        if (b[16 + i] != 0)
            return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: malformed kind field");
    for (size_t i = 0; found_kind[i]; i++)
        if (found_kind[i] < 32 || found_kind[i] > 126)
            return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: malformed kind field");
    if (kind != NULL && strcmp(found_kind, kind) != 0)
        return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: of kind \"%s\", expected \"%s\"",
                        found_kind, kind);
    uint64_t total = read_u64(b + 32);
    if (total != (uint64_t)size)
        return wec_fail(message, message_size, WEC_ERR_DATA,
                        "runtime data: the header gives a total size of %llu bytes but the buffer holds %zu "
                        "(truncated or padded)", (unsigned long long)total, size);
    if (read_u64(b + 40) != 0)
        return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: reserved header field is not 0");
    uint32_t count = read_u32(b + 12);
    if ((size_t)count > (size - WEC_DATA_HEADER_SIZE) / WEC_DATA_ENTRY_SIZE)
        return wec_fail(message, message_size, WEC_ERR_DATA,
                        "runtime data: %u arrays announced, but the buffer holds room for the directory of at most "
                        "%zu", (unsigned)count, (size - WEC_DATA_HEADER_SIZE) / WEC_DATA_ENTRY_SIZE);
    size_t directory_end = WEC_DATA_HEADER_SIZE + (size_t)count * WEC_DATA_ENTRY_SIZE;
    wec_array *arrays = calloc(count ? count : 1, sizeof(wec_array));
    const wec_array **order = calloc(count ? count : 1, sizeof(wec_array *));
    if (arrays == NULL || order == NULL) {
        free(arrays);
        free(order);
        return wec_fail(message, message_size, WEC_ERR_MEMORY, "runtime data: out of memory reading the directory");
    }
    int status = WEC_OK;
    for (size_t k = 0; k < count && status == WEC_OK; k++) {
        const unsigned char *e = b + WEC_DATA_HEADER_SIZE + k * WEC_DATA_ENTRY_SIZE;
        wec_array *a = &arrays[k];
        if (!valid_name(e, a->name)) {
            status = wec_fail(message, message_size, WEC_ERR_DATA,
                              "runtime data: array %zu has a malformed name (1-63 characters of letters, digits, "
                              "'_' and '.', NUL-padded)", k);
            break;
        }
        a->dtype = e[64];
        a->ndim = e[65];
        size_t item = dtype_size(a->dtype);
        if (item == 0) {
            status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' has unknown dtype code %d",
                              a->name, a->dtype);
            break;
        }
        if (a->ndim > WEC_DATA_MAX_DIMS) {
            status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' has %d dimensions (at "
                              "most %d)", a->name, a->ndim, WEC_DATA_MAX_DIMS);
            break;
        }
        for (int i = 0; i < 6; i++)
            if (e[66 + i] != 0)
                status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s': reserved bytes "
                                  "are not 0", a->name);
        for (int i = 120; i < 128; i++)
            if (e[i] != 0)
                status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s': reserved bytes "
                                  "are not 0", a->name);
        if (status != WEC_OK)
            break;
        size_t elements = 1;
        for (int d = 0; d < WEC_DATA_MAX_DIMS; d++) {
            a->shape[d] = read_u64(e + 72 + 8 * d);
            if (d >= a->ndim) {
                if (a->shape[d] != 0) {
                    status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s': extent of "
                                      "unused dimension %d is not 0", a->name, d);
                    break;
                }
                continue;
            }
            if (a->shape[d] > (uint64_t)SIZE_MAX || !wec_mul(elements, (size_t)a->shape[d], &elements)) {
                status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s': its shape's "
                                  "element count overflows (a huge count)", a->name);
                break;
            }
        }
        if (status != WEC_OK)
            break;
        size_t nbytes;
        if (!wec_mul(elements, item, &nbytes)) {
            status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s': its size in bytes "
                              "overflows (a huge count)", a->name);
            break;
        }
        uint64_t offset = read_u64(e + 104), declared = read_u64(e + 112);
        if (declared != (uint64_t)nbytes) {
            status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' declares %llu bytes, "
                              "its shape and dtype make %zu", a->name, (unsigned long long)declared, nbytes);
            break;
        }
        if (offset % 8 != 0 || offset < (uint64_t)directory_end || offset > (uint64_t)size ||
            (uint64_t)nbytes > (uint64_t)size - offset) {
            status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' (%zu bytes at offset "
                              "%llu) does not lie within the data area [%zu, %zu) at an offset that is a multiple of "
                              "8", a->name, nbytes, (unsigned long long)offset, directory_end, size);
            break;
        }
        a->count = elements;
        a->nbytes = nbytes;
        a->bytes = b + offset;
        for (size_t j = 0; j < k; j++)
            if (strcmp(arrays[j].name, a->name) == 0) {
                status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' appears twice",
                                  a->name);
                break;
            }
        order[k] = a;
    }
    if (status == WEC_OK && count > 1) {
        qsort(order, count, sizeof(*order), by_offset);
        for (size_t k = 1; k < count; k++)
            if (order[k - 1]->nbytes > 0 && order[k]->bytes < order[k - 1]->bytes + order[k - 1]->nbytes) {
                status = wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: arrays '%s' and '%s' overlap",
                                  order[k - 1]->name, order[k]->name);
                break;
            }
    }
    free(order);
    if (status != WEC_OK) {
        free(arrays);
        return status;
    }
    data->buffer = b;
    data->size = size;
    memcpy(data->kind, found_kind, sizeof(found_kind));
    data->version = version;
    data->count = count;
    data->arrays = arrays;
    return WEC_OK;
}

void wec_data_close(wec_data *data)
{
    if (data != NULL) {
        free(data->arrays);
        memset(data, 0, sizeof(*data));
    }
}

const wec_array *wec_data_find(const wec_data *data, const char *name)
{
    for (size_t k = 0; k < data->count; k++)
        if (strcmp(data->arrays[k].name, name) == 0)
            return &data->arrays[k];
    return NULL;
}

double wec_array_f64(const wec_array *array, size_t i)
{
    double value;
    memcpy(&value, array->bytes + 8 * i, 8);
    return value;
}

int64_t wec_array_i64(const wec_array *array, size_t i)
{
    int64_t value;
    memcpy(&value, array->bytes + 8 * i, 8);
    return value;
}

int wec_data_get(const wec_data *data, const char *name, int dtype, int ndim, const int64_t *shape, int required,
                 int finite, const wec_array **out, char *message, size_t message_size)
{
    *out = NULL;
    const wec_array *a = wec_data_find(data, name);
    if (a == NULL) {
        if (required)
            return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' is missing", name);
        return WEC_OK;
    }
    if (a->dtype != dtype)
        return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' is %s, expected %s", name,
                        dtype_name(a->dtype), dtype_name(dtype));
    if (a->ndim != ndim)
        return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' has %d dimension(s), "
                        "expected %d", name, a->ndim, ndim);
    for (int d = 0; d < ndim; d++)
        if (shape != NULL && shape[d] >= 0 && a->shape[d] != (uint64_t)shape[d])
            return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' has extent %llu in "
                            "dimension %d, expected %lld (sizes of the arrays disagree)", name,
                            (unsigned long long)a->shape[d], d, (long long)shape[d]);
    if (finite && dtype == WEC_F64)
        for (size_t i = 0; i < a->count; i++)
            if (!isfinite(wec_array_f64(a, i)))
                return wec_fail(message, message_size, WEC_ERR_DATA, "runtime data: array '%s' holds a value that "
                                "is not finite (NaN or infinite) at element %zu", name, i);
    *out = a;
    return WEC_OK;
}

double *wec_array_copy_f64(const wec_array *array)
{
    double *out = wec_alloc_f64(array->count);
    if (out != NULL && array->count)
        memcpy(out, array->bytes, array->nbytes);
    return out;
}

int64_t *wec_array_copy_i64(const wec_array *array)
{
    int64_t *out = wec_alloc_i64(array->count);
    if (out != NULL && array->count)
        memcpy(out, array->bytes, array->nbytes);
    return out;
}

uint64_t wec_data_hash(const void *buffer, size_t size)
{
    /* FNV-1a over 64-bit words (then the tail bytes): a fingerprint, not a cryptographic hash */
    const unsigned char *b = buffer;
    uint64_t h = 1469598103934665603ULL;
    size_t i = 0;
    for (; i + 8 <= size; i += 8) {
        uint64_t word;
        memcpy(&word, b + i, 8);
        h = (h ^ word) * 1099511628211ULL;
        h ^= h >> 29;
    }
    for (; i < size; i++)
        h = (h ^ b[i]) * 1099511628211ULL;
    return h ^ (uint64_t)size;
}
