/* The little-endian byte writer and reader of saved states (wec_common.h). Values are written byte by byte, so a
 * state is the same on every platform and no alignment of the caller's buffer is assumed. */
#include <string.h>

#include "wec_common.h"

void wec_put_bytes(wec_writer *w, const void *bytes, size_t n)
{
    if (w->failed)
        return;
    if (w->buffer != NULL) {
        if (n > w->size - w->pos) {
            w->failed = 1;
            return;
        }
        if (n)
            memcpy(w->buffer + w->pos, bytes, n);
    }
    w->pos += n;
}

void wec_put_u64(wec_writer *w, uint64_t value)
{
    unsigned char b[8];
    for (int i = 0; i < 8; i++)
        b[i] = (unsigned char)(value >> (8 * i));
    wec_put_bytes(w, b, 8);
}

void wec_put_i64(wec_writer *w, int64_t value) { wec_put_u64(w, (uint64_t)value); }

void wec_put_f64(wec_writer *w, double value)
{
    uint64_t bits;
    memcpy(&bits, &value, 8);
    wec_put_u64(w, bits);
}

void wec_put_f64s(wec_writer *w, const double *values, size_t n)
{
    for (size_t i = 0; i < n && !w->failed; i++)
        wec_put_f64(w, values[i]);
}

void wec_get_bytes(wec_reader *r, void *bytes, size_t n)
{
    if (r->failed || n > r->size - r->pos) {
        r->failed = 1;
        memset(bytes, 0, n);
        return;
    }
    if (n)
        memcpy(bytes, r->buffer + r->pos, n);
    r->pos += n;
}

uint64_t wec_get_u64(wec_reader *r)
{
    unsigned char b[8];
    wec_get_bytes(r, b, 8);
    uint64_t value = 0;
    for (int i = 0; i < 8; i++)
        value |= (uint64_t)b[i] << (8 * i);
    return value;
}

int64_t wec_get_i64(wec_reader *r)
{
    uint64_t u = wec_get_u64(r);
    int64_t value;
    memcpy(&value, &u, 8);
    return value;
}

double wec_get_f64(wec_reader *r)
{
    uint64_t bits = wec_get_u64(r);
    double value;
    memcpy(&value, &bits, 8);
    return value;
}

void wec_get_f64s(wec_reader *r, double *values, size_t n)
{
    for (size_t i = 0; i < n; i++)
        values[i] = wec_get_f64(r);
}
