/* wec-cosim hydrodynamics runtime: the step-time physics of the hydro model as a flat C API.
 *
 * A model is created from the runtime input data that the Python preparation writes (hydro_fmu/runtime.py,
 * layout in wec_data.h and docs/runtime.md). For the n selected degrees of freedom of the hydrodynamic bodies it
 * computes, at a communication point t with displacement x and velocity v (world frame, about each body's centre
 * of gravity; SI units, radians),
 *
 *     F = F_exc(t) - mu(t) + F_hs(x) + F_visc(v)
 *
 * (excitation by superposition or impulse-response convolution, plus a nonlinear Froude-Krylov force over the
 * wetted hull if asked; radiation memory by convolution or state space; linear or nonlinear hydrostatics;
 * viscous drag), the incident wave elevation at the origin, the power and work of each part, and the linearised
 * force F ~ F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v over the next step. The infinite-frequency added mass is
 * not in F (wec_hydro_added_mass_inf gives it for the multibody mass matrix).
 *
 * Use, per communication point: set nothing, call wec_hydro_outputs (any number of times, with any inputs: the
 * result depends only on the committed history and the inputs) and, if wanted, wec_hydro_linearise; then
 * wec_hydro_do_step (commits the work at the point and the velocity to the memory) or wec_hydro_advance (the
 * memory only) with the step to the next point (or wec_hydro_commit_work at the point's own time, then
 * wec_hydro_advance at the host's: a host whose time differs in the last bits then changes nothing but the check).
 *
 * Model of the API: MoorDyn's C API. The handle is opaque; wec_hydro_create returns NULL on bad input and
 * wec_hydro_create_error says why; every other function checks its handle and its sizes and returns a
 * wec_status (wec_error.h), the reason of a failure in wec_hydro_last_error. A model and its clones share their
 * read-only data (reference counted); each handle must be used by one thread at a time. */
#ifndef WEC_HYDRO_H
#define WEC_HYDRO_H

#include <stddef.h>
#include <stdint.h>

#include "wec_error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct wec_hydro wec_hydro;

/* Force rows of wec_hydro_outputs: total, excitation, radiation (memory only), hydrostatic, viscous. */
#define WEC_HYDRO_ROWS 5
/* Work and power components: excitation, radiation, hydrostatic, viscous (W, J). */
#define WEC_HYDRO_COMPONENTS 4

/* A model from the runtime input data[0, size) (copied what it keeps: the buffer may be freed after the call).
 * NULL if the data are refused or memory runs out: wec_hydro_create_error() then says why. */
WEC_API wec_hydro *wec_hydro_create(const void *data, size_t size);

/* Why the last wec_hydro_create or wec_hydro_clone of this thread returned NULL ("" if it did not). */
WEC_API const char *wec_hydro_create_error(void);

/* The message of the last failed call on this handle ("" if none; a fixed text for an invalid handle). */
WEC_API const char *wec_hydro_last_error(const wec_hydro *model);

/* An independent copy (same data, shared; same state). NULL on failure (wec_hydro_create_error). */
WEC_API wec_hydro *wec_hydro_clone(const wec_hydro *model);

/* Frees the handle (NULL is allowed). */
WEC_API void wec_hydro_free(wec_hydro *model);

/* Number of selected degrees of freedom n (the length of x, v and of each force row). */
WEC_API int wec_hydro_dofs(wec_hydro *model, size_t *n);

/* The infinite-frequency added mass (n x n, row-major, kg, kg m, kg m^2) into a[0, size), size >= n * n. */
WEC_API int wec_hydro_added_mass_inf(wec_hydro *model, double *a, size_t size);

/* Time of the first communication point (s; default 0). Only before the first step. */
WEC_API int wec_hydro_set_start_time(wec_hydro *model, double start_time);

/* Everything a communication point publishes for inputs x, v (each n values) at time t (s):
 * forces: n_rows x n values, row k the force row rows[k] (0..4, WEC_HYDRO_ROWS order); rows NULL: all five
 *         rows in order (n_rows must then be 5);
 * power, work: WEC_HYDRO_COMPONENTS values each (NULL: not wanted): the power F_c . v of each part (W) and its
 *         work since the start (J; trapezoidal rule over the committed points);
 * elevation: the incident wave elevation at the world origin (m; NULL: not wanted). */
WEC_API int wec_hydro_outputs(wec_hydro *model, double t, const double *x, const double *v, size_t n,
                              const int64_t *rows, size_t n_rows, double *forces, double *power, double *work,
                              double *elevation);

/* The incident wave elevation at the world origin at time t (m). */
WEC_API int wec_hydro_elevation(wec_hydro *model, double t, double *elevation);

/* The force as an affine model over the next step about (t, x, v): f0, f0_rate (n each), df_dx, df_dv (n x n,
 * row-major: force row, motion column). Entries outside the masks (n x n bytes, nonzero = published; NULL = all)
 * are 0 in the matrices and their share stays in f0. Call it at every communication point: f0_rate holds the
 * backward difference of the memory between the last two points at which it was called. */
WEC_API int wec_hydro_linearise(wec_hydro *model, double t, const double *x, const double *v, size_t n,
                                const unsigned char *stiffness_mask, const unsigned char *damping_mask, double *f0,
                                double *f0_rate, double *df_dx, double *df_dv);

/* Commits the velocity v at the current point t to the radiation memory and moves on by h (s): for the
 * convolution a whole number of its steps, any h > 0 for the state space. t must be the current point. */
WEC_API int wec_hydro_advance(wec_hydro *model, double t, double h, const double *v, size_t n);

/* Commits the work at the point t for inputs x, v (wec_hydro_outputs evaluated there if it was not): the work
 * account's trapezoidal sum goes on from this point. */
WEC_API int wec_hydro_commit_work(wec_hydro *model, double t, const double *x, const double *v, size_t n);

/* The FMU's step: wec_hydro_commit_work(t, x, v), then wec_hydro_advance(t, h, v); a refused step commits
 * nothing. */
WEC_API int wec_hydro_do_step(wec_hydro *model, double t, double h, const double *x, const double *v, size_t n);

/* The model state (everything that changes as it runs) as bytes: its size, a copy into buffer[0, size) and a
 * load from bytes saved by a model of the same data (checked: a state of other data, another version or a corrupt
 * buffer is refused and the model is left unchanged). A save and load give the model back bit for bit. */
WEC_API int wec_hydro_state_size(wec_hydro *model, size_t *size);
WEC_API int wec_hydro_state_save(wec_hydro *model, void *buffer, size_t size);
WEC_API int wec_hydro_state_load(wec_hydro *model, const void *buffer, size_t size);

/* Copies the state of `from` into `to` (both of the same data, e.g. a clone): FMI get/set FMU state. */
WEC_API int wec_hydro_copy_state(wec_hydro *to, wec_hydro *from);

#ifdef __cplusplus
}
#endif
#endif
