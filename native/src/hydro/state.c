/* The model state (everything that changes as the model runs) as bytes, for FMU states and checkpoints:
 *
 *     "WECHSTAT", uint64 version, uint64 hash of the model's data, uint64 n, K, m, B, r (sizes, checked), then
 *     start time, elapsed time and its compensation; the phasor clock (time, step, count, phasors, rotation);
 *     the convolution memory (steps, gap, block, ring, last velocity, block history); the state-space memory
 *     (pending step, state and velocities); the work account; the memory rate of the linearised interface.
 *
 * Every number little-endian, doubles bit for bit: a save and a load give the model back exactly. A load checks
 * the header against the model and every integer against the sizes (so that no later index can leave its array),
 * reads into a scratch instance and copies it in only when all of it is good: a refused state leaves the model
 * as it was. The last evaluated point is not state (it is evaluated again after a load). */
#include <stdlib.h>
#include <string.h>

#include "hydro_internal.h"

#define STATE_VERSION 1

static void write_all(const wec_hydro *h, wec_writer *w)
{
    const hydro_shared *s = h->shared;
    size_t n = s->n, k = s->k;
    wec_put_bytes(w, "WECHSTAT", 8);
    wec_put_u64(w, STATE_VERSION);
    wec_put_u64(w, s->hash);
    wec_put_u64(w, n);
    wec_put_u64(w, k);
    wec_put_u64(w, s->m);
    wec_put_u64(w, s->blocks);
    wec_put_u64(w, s->r);
    wec_put_f64(w, h->start_time);
    wec_put_f64(w, h->elapsed);
    wec_put_f64(w, h->elapsed_error);
    wec_put_f64(w, h->clock.t);
    wec_put_f64(w, h->clock.delta);
    wec_put_i64(w, h->clock.count);
    wec_put_f64s(w, h->clock.re, k);
    wec_put_f64s(w, h->clock.im, k);
    wec_put_f64s(w, h->clock.rot_re, k);
    wec_put_f64s(w, h->clock.rot_im, k);
    wec_put_i64(w, h->conv.steps);
    wec_put_i64(w, h->conv.gap);
    for (int i = 0; i < 4; i++)
        wec_put_i64(w, h->conv.block[i]);
    if (s->radiation == RADIATION_CONVOLUTION) {
        wec_put_f64s(w, h->conv.ring, 2 * s->m * n);
        wec_put_f64s(w, h->conv.last, n);
        wec_put_f64s(w, h->conv.history, s->blocks * n);
    }
    wec_put_f64(w, h->ss.pending);
    if (s->radiation == RADIATION_STATE_SPACE)
        wec_put_f64s(w, h->ss.w, s->r + 2 * n);
    wec_put_f64s(w, h->work.committed, WEC_HYDRO_COMPONENTS);
    wec_put_f64s(w, h->work.last_power, WEC_HYDRO_COMPONENTS);
    wec_put_f64(w, h->work.last_time);
    wec_put_i64(w, h->work.has_last);
    wec_put_i64(w, h->rate.has_previous);
    wec_put_i64(w, h->rate.has_latest);
    wec_put_f64(w, h->rate.t_previous);
    wec_put_f64(w, h->rate.t_latest);
    wec_put_f64s(w, h->rate.previous, n);
    wec_put_f64s(w, h->rate.latest, n);
}

size_t hydro_state_size(const wec_hydro *h)
{
    wec_writer counter = {NULL, 0, 0, 0};
    write_all(h, &counter);
    return counter.pos;
}

int hydro_state_write(const wec_hydro *h, wec_writer *w)
{
    write_all(h, w);
    return w->failed ? WEC_ERR_ARGUMENT : WEC_OK;
}

static int flag(int64_t value) { return value == 0 || value == 1; }

int hydro_state_read(wec_hydro *h, wec_reader *r, char *msg)
{
    const hydro_shared *s = h->shared;
    size_t n = s->n, k = s->k;
    char magic[8];
    wec_get_bytes(r, magic, 8);
    if (r->failed || memcmp(magic, "WECHSTAT", 8) != 0)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STATE, "state: not a saved state of the hydrodynamics runtime "
                        "(no \"WECHSTAT\" magic)");
    uint64_t version = wec_get_u64(r);
    if (version != STATE_VERSION)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STATE, "state: version %llu, this runtime reads %d",
                        (unsigned long long)version, STATE_VERSION);
    if (wec_get_u64(r) != s->hash)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STATE, "state: saved by a model of other data (another scene, "
                        "database, sea or settings); it cannot be loaded into this one");
    uint64_t sizes[5], expected[5] = {n, k, s->m, s->blocks, s->r};
    for (int i = 0; i < 5; i++)
        sizes[i] = wec_get_u64(r);
    if (r->failed || memcmp(sizes, expected, sizeof(sizes)) != 0)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STATE, "state: its sizes do not match the model's (corrupt)");
    wec_hydro t;
    memset(&t, 0, sizeof(t));
    if (hydro_instance_init(&t, (hydro_shared *)s) != WEC_OK) {
        hydro_instance_free(&t);
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "state: out of memory");
    }
    t.start_time = wec_get_f64(r);
    t.elapsed = wec_get_f64(r);
    t.elapsed_error = wec_get_f64(r);
    t.clock.t = wec_get_f64(r);
    t.clock.delta = wec_get_f64(r);
    t.clock.count = wec_get_i64(r);
    wec_get_f64s(r, t.clock.re, k);
    wec_get_f64s(r, t.clock.im, k);
    wec_get_f64s(r, t.clock.rot_re, k);
    wec_get_f64s(r, t.clock.rot_im, k);
    t.conv.steps = wec_get_i64(r);
    t.conv.gap = wec_get_i64(r);
    for (int i = 0; i < 4; i++)
        t.conv.block[i] = wec_get_i64(r);
    if (s->radiation == RADIATION_CONVOLUTION) {
        wec_get_f64s(r, t.conv.ring, 2 * s->m * n);
        wec_get_f64s(r, t.conv.last, n);
        wec_get_f64s(r, t.conv.history, s->blocks * n);
    }
    t.ss.pending = wec_get_f64(r);
    if (s->radiation == RADIATION_STATE_SPACE)
        wec_get_f64s(r, t.ss.w, s->r + 2 * n);
    wec_get_f64s(r, t.work.committed, WEC_HYDRO_COMPONENTS);
    wec_get_f64s(r, t.work.last_power, WEC_HYDRO_COMPONENTS);
    t.work.last_time = wec_get_f64(r);
    t.work.has_last = wec_get_i64(r);
    t.rate.has_previous = wec_get_i64(r);
    t.rate.has_latest = wec_get_i64(r);
    t.rate.t_previous = wec_get_f64(r);
    t.rate.t_latest = wec_get_f64(r);
    wec_get_f64s(r, t.rate.previous, n);
    wec_get_f64s(r, t.rate.latest, n);
    const int64_t *b = t.conv.block;
    int64_t limit = (int64_t)1 << 60;
    const char *problem = NULL;
    if (r->failed)
        problem = "it is shorter than a state of this model";
    else if (r->pos != r->size)
        problem = "it is longer than a state of this model";
    else if (t.clock.count < 0 || t.clock.count > PHASOR_REFRESH)
        problem = "the phasor clock's count is out of range";
    else if (t.conv.steps < 0 || t.conv.steps > limit || t.conv.gap < 1 || t.conv.gap > limit)
        problem = "the radiation memory's step counts are out of range";
    else if (!flag(b[0]) || (b[0] == 1 && (s->radiation != RADIATION_CONVOLUTION || b[1] < 0 ||
                                           b[1] > t.conv.steps || b[2] < 1 || b[3] < 1 ||
                                           b[3] > (int64_t)s->blocks || b[2] > (int64_t)s->m ||
                                           b[3] * b[2] > (int64_t)s->m - 1)))
        problem = "the radiation memory's block is inconsistent";
    else if (!flag(t.work.has_last) || !flag(t.rate.has_previous) || !flag(t.rate.has_latest) ||
             (t.rate.has_previous && !t.rate.has_latest))
        problem = "a flag is neither 0 nor 1";
    if (problem != NULL) {
        hydro_instance_free(&t);
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STATE, "state: corrupt (%s)", problem);
    }
    t.cached = 0;
    wec_hydro_copy_state(h, &t);
    h->cached = 0;
    hydro_instance_free(&t);
    return WEC_OK;
}
