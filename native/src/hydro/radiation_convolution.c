/* Radiation memory by convolution (hydro_fmu.radiation.RadiationMemory, the blocked sums of the compiled pass):
 *
 *     mu(t_c) = sum_{j=0}^{m-1} w_j K(j dt) v(t_c - j dt)
 *
 * the trapezoidal rule on the grid of step dt over the kernel's m samples (second order in dt; w_j = dt except
 * dt/2 at both ends; no stability limit of its own: an explicit sum over past velocities). Velocities between two
 * communication points (a step of q grid steps) are interpolated linearly onto the grid (still second order).
 * The current velocity enters with the weight K(0) dt / 2 plus its share of the interpolated points: the force
 * has direct feedthrough from v. Velocities before the start are zero.
 *
 * Layout: the velocities of the last m grid points are one contiguous (m, n) window of a double-length ring
 * (grid point s at rows s % m and s % m + m), the weights one (n, m n) matrix (lags m-1 .. 0, oldest first).
 *
 * Blocked sums: the lags of the next B points that reach only into velocities committed before a block's start s0
 * do not depend on the velocities to come, so one pass over the weights at the block's first point computes that
 * history part for the block's next points (each weight row streamed once per block), and each point then adds its
 * own b = c - s0 + 1 most recent lags: the same products as the direct sum in another order (equal to round-off),
 * the weights streamed once per B points instead of at every point. A point outside the block (past its end, an
 * offset the block does not hold because the step changed, no block yet) starts a new one at its own s0 = steps
 * with stride gap. The block belongs to the ring and step count it was computed from: it is part of the state. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../common/dot.h"
#include "hydro_internal.h"

#define MAX_BLOCK_POINTS 1024

int hydro_load_radiation_convolution(hydro_shared *s, const wec_data *d, char *msg)
{
    if (s->radiation != RADIATION_CONVOLUTION)
        return WEC_OK;
    const wec_array *kernel, *points;
    size_t n = s->n;
    int64_t shape[3] = {-1, (int64_t)n, (int64_t)n};
    int st = wec_data_get(d, "radiation.kernel", WEC_F64, 3, shape, 1, 1, &kernel, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    if ((st = wec_data_get(d, "radiation.block_points", WEC_I64, 0, NULL, 1, 0, &points, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->m = (size_t)kernel->shape[0];
    int64_t b = wec_array_i64(points, 0);
    if (s->m < 2)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'radiation.kernel' needs at least two "
                        "samples (it has %zu)", s->m);
    if (b < 1 || b > MAX_BLOCK_POINTS)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'radiation.block_points' is %lld, expected "
                        "1 to %d", (long long)b, MAX_BLOCK_POINTS);
    s->blocks = (size_t)b;
    size_t m = s->m, mn = m * n; /* m n n is the kernel's count: no overflow */
    if (!(s->weights = wec_alloc_f64(n * mn)))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    double dt = s->dt;
    for (size_t lag = 0; lag < m; lag++) {
        double w = (lag == 0 || lag == m - 1) ? dt / 2 : dt;
        size_t column = (m - 1 - lag) * n;
        for (size_t i = 0; i < n; i++)
            for (size_t l = 0; l < n; l++)
                s->weights[i * mn + column + l] = wec_array_f64(kernel, (lag * n + i) * n + l) * w;
    }
    return WEC_OK;
}

int conv_memory_init(conv_memory *c, const hydro_shared *s)
{
    memset(c, 0, sizeof(*c));
    c->gap = 1;
    if (s->radiation != RADIATION_CONVOLUTION)
        return WEC_OK;
    c->ring = wec_alloc_f64(2 * s->m * s->n);
    c->last = wec_alloc_f64(s->n);
    c->history = wec_alloc_f64(s->blocks * s->n);
    return c->ring && c->last && c->history ? WEC_OK : WEC_ERR_MEMORY;
}

void conv_memory_free(conv_memory *c)
{
    free(c->ring);
    free(c->last);
    free(c->history);
}

void conv_memory_copy(conv_memory *to, const conv_memory *from, const hydro_shared *s)
{
    to->steps = from->steps;
    to->gap = from->gap;
    memcpy(to->block, from->block, sizeof(to->block));
    if (s->radiation != RADIATION_CONVOLUTION)
        return;
    memcpy(to->ring, from->ring, 2 * s->m * s->n * sizeof(double));
    memcpy(to->last, from->last, s->n * sizeof(double));
    memcpy(to->history, from->history, s->blocks * s->n * sizeof(double));
}

/* velocities of the grid points after the last committed one up to the current one: linear from last to v */
static void write_pending(conv_memory *c, const hydro_shared *s, const double *v)
{
    size_t m = s->m, n = s->n;
    int64_t current = c->steps - 1 + c->gap, gap = c->gap;
    if (gap == 1) {
        size_t row = (size_t)(current % (int64_t)m);
        memcpy(c->ring + row * n, v, n * sizeof(double));
        memcpy(c->ring + (row + m) * n, v, n * sizeof(double));
        return;
    }
    int64_t lags = gap < (int64_t)m ? gap : (int64_t)m;
    for (int64_t lag = lags - 1; lag >= 0; lag--) {
        size_t row = (size_t)((current - lag) % (int64_t)m);
        double f = (double)lag / (double)gap;
        for (size_t i = 0; i < n; i++) {
            double value = v[i] + f * (c->last[i] - v[i]);
            c->ring[row * n + i] = value;
            c->ring[(row + m) * n + i] = value;
        }
    }
}

/* the history sums of a block: history[k] for the point (k + 1) stride grid steps after its start, the sum over the
 * lags it shares with the block's start, sum_f row[f] window[shift_k + f] for f < size - shift_k. The weights are
 * read from memory once for all the block's points and the window once for all the rows: a chunk of lags (4 kB of
 * each weight row) at a time, against the window at every point's shift (kept in the first-level cache), each
 * chunk's sum by wec_dot, the chunks added in order. */
#define HISTORY_CHUNK 512

static void block_history(const hydro_shared *s, const double *window, size_t stride, size_t count, double *history)
{
    size_t n = s->n, size = s->m * n, step = stride * n;
    for (size_t k = 0; k < count * n; k++)
        history[k] = 0.0;
    for (size_t start = 0; start < size; start += HISTORY_CHUNK) {
        size_t end = size - start < HISTORY_CHUNK ? size : start + HISTORY_CHUNK;
        for (size_t i = 0; i < n; i++) {
            const double *row = s->weights + i * size;
            for (size_t k = 0; k < count; k++) {
                size_t shift = (k + 1) * step, limit = size - shift; /* count stride < m: shift < size */
                if (start >= limit)
                    break; /* the later points' shifts are larger still */
                size_t stop = end < limit ? end : limit;
                history[k * n + i] += wec_dot(row + start, window + shift + start, stop - start);
            }
        }
    }
}

void conv_memory_force(conv_memory *c, const hydro_shared *s, const double *v, double *mu)
{
    size_t m = s->m, n = s->n, size = m * n;
    write_pending(c, s, v);
    int64_t steps = c->steps, gap = c->gap, cur = steps - 1 + gap;
    int64_t k = -1;
    if (c->block[0] == 1 && steps >= c->block[1]) {
        int64_t b = cur - c->block[1] + 1;
        if (b % c->block[2] == 0 && b / c->block[2] <= c->block[3])
            k = b / c->block[2] - 1;
    }
    if (k < 0) {
        int64_t count = ((int64_t)m - 1) / gap;
        if (count > (int64_t)s->blocks)
            count = (int64_t)s->blocks;
        if (count == 0) { /* a step as long as the kernel: nothing to share */
            c->block[0] = 0;
            const double *window = c->ring + (size_t)((cur + 1) % (int64_t)m) * n;
            for (size_t i = 0; i < n; i++)
                mu[i] = wec_dot(s->weights + i * size, window, size);
            return;
        }
        block_history(s, c->ring + (size_t)(steps % (int64_t)m) * n, (size_t)gap, (size_t)count, c->history);
        c->block[0] = 1;
        c->block[1] = steps;
        c->block[2] = gap;
        c->block[3] = count;
        k = 0;
    }
    int64_t b = cur - c->block[1] + 1;
    const double *window = c->ring + (size_t)((cur + 1) % (int64_t)m) * n;
    size_t low = (m - (size_t)b) * n;
    for (size_t i = 0; i < n; i++)
        mu[i] = c->history[(size_t)k * n + i] + wec_dot(s->weights + i * size + low, window + low, size - low);
}

void conv_memory_damping(const conv_memory *c, const hydro_shared *s, double *d)
{
    size_t m = s->m, n = s->n, size = m * n;
    int64_t q = c->gap, lags = q < (int64_t)m ? q : (int64_t)m;
    for (size_t i = 0; i < n; i++)
        for (size_t l = 0; l < n; l++)
            d[i * n + l] = s->weights[i * size + (m - 1) * n + l];
    for (int64_t lag = 1; lag < lags; lag++) {
        double f = 1.0 - (double)lag / (double)q;
        size_t column = (m - 1 - (size_t)lag) * n;
        for (size_t i = 0; i < n; i++)
            for (size_t l = 0; l < n; l++)
                d[i * n + l] += f * s->weights[i * size + column + l];
    }
}

int conv_memory_step(conv_memory *c, const hydro_shared *s, const double *v, double h, char *msg)
{
    double ratio = h / s->dt;
    double q = nearbyint(ratio);
    if (!(q >= 1) || !(q < 4e15) || fabs(h - q * s->dt) > 1e-9 * s->dt)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STEP, "communication step %g s is not a whole multiple of the "
                        "radiation convolution step %g s; set the hydro FMU parameter radiation.dt to the master's "
                        "(smallest) macro step, or use the state-space radiation model, which takes any step", h,
                        s->dt);
    write_pending(c, s, v);
    c->steps += c->gap;
    memcpy(c->last, v, s->n * sizeof(double));
    c->gap = (int64_t)q;
    return WEC_OK;
}
