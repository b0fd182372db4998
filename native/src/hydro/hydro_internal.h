/* Internal structures of the hydrodynamics runtime: the shared read-only model data, the per-handle state, and
 * the functions of each concept (one source file each). Not part of the public API. */
#ifndef WEC_HYDRO_INTERNAL_H
#define WEC_HYDRO_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "../common/wec_common.h"
#include "wec_hydro.h"

#define HYDRO_MAGIC 0x57454348u /* "WECH": a live handle */
#define HYDRO_DEAD 0x44454144u  /* "DEAD": a freed handle */
#define HYDRO_MSG_SIZE WEC_MESSAGE_SIZE

/* Methods, as the data encode them (docs/runtime.md). */
enum { EXCITATION_NONE = 0, EXCITATION_SUPERPOSITION = 1, EXCITATION_CONVOLUTION = 2 };
enum { RADIATION_NONE = 0, RADIATION_CONVOLUTION = 1, RADIATION_STATE_SPACE = 2 };
enum { HYDROSTATICS_NONE = 0, HYDROSTATICS_LINEAR = 1, HYDROSTATICS_NONLINEAR = 2 };
enum { ROW_TOTAL = 0, ROW_EXCITATION = 1, ROW_RADIATION = 2, ROW_HYDROSTATIC = 3, ROW_VISCOUS = 4 };

#define PHASOR_REFRESH 32        /* exact exponentials again after this many products (hydro_fmu.waves.PhasorClock) */
#define STATE_SPACE_CACHE 8      /* step sizes whose discretisation is kept */
#define TANGENT_DELTA 1e-6       /* central differences of the nonlinear pressure forces in x (m, rad) */
#define RATE_DELTA 1e-4          /* central differences in time (s) of time-only functions */

/* ------------------------------------------------------------------------------------------- shared data */
typedef struct hydro_shared {
    int refs;      /* handles using these data (one thread at a time per family of clones) */
    uint64_t hash; /* of the input data: a saved state names the data it belongs to */
    size_t n, bodies;
    int64_t *body_of, *dof_of; /* (n): body index and DOF (0 surge .. 5 yaw) of each selected DOF */
    double dt;                 /* radiation grid step (s) and time tolerance unit */
    double ramp;               /* ramp duration (s; <= 0: none) */
    int excitation, radiation, hydrostatics, froude_krylov;
    double *added_mass_inf; /* (n, n) or NULL */
    /* waves */
    size_t k;
    double *omega, *amp_re, *amp_im; /* (K) components at the origin */
    double *kx, *ky, *wavenumber;    /* (K) wave vectors (spreading.c), when the incident field is needed */
    /* superposition: (K, columns) complex, columns = n + 1 with coefficients (elevation last), else 1 */
    size_t columns;
    double *table_re, *table_im;
    /* excitation convolution */
    size_t taus;
    double *tau, *kernel_ex;          /* (L), (L, n) trapezoid-weighted */
    double *transfer_re, *transfer_im; /* (K, n): the weighted kernel's transfer per component (synthetic sea) */
    /* elevation record */
    size_t samples;
    double record_dt, *record;
    /* radiation convolution */
    size_t m, blocks;
    double *weights; /* (n, m n): weight of the velocity at lag m-1-j of DOF l at [i][j n + l] */
    /* state space */
    size_t r;
    double *ss_a, *ss_b, *ss_c;
    /* hydrostatics, viscous */
    double *restoring; /* -C (n, n) */
    int viscous;
    double *linear, *quadratic;
    /* pressure (nonlinear hydrostatics and Froude-Krylov) */
    double rho, g, depth; /* depth: +inf for deep water */
    double *cg;           /* (bodies, 3) */
    size_t faces;
    double *corners;      /* (faces, 3, 3) relative to the centre of gravity at equilibrium */
    size_t *first_face;   /* (bodies + 1) */
    double *equilibrium;  /* (bodies, 6) still-water buoyancy at the equilibrium pose */
} hydro_shared;

/* ------------------------------------------------------------------------------------------- state parts */
typedef struct phasor_clock {
    double t, delta;
    int64_t count;
    double *re, *im, *rot_re, *rot_im; /* (K) */
} phasor_clock;

typedef struct conv_memory {
    double *ring;    /* (2 m, n): grid point s at rows s % m and s % m + m */
    double *last;    /* (n) velocity at the last committed grid point */
    int64_t steps;   /* grid points committed */
    int64_t gap;     /* grid steps from the last committed point to the current time */
    double *history; /* (B, n) history sums of the current block */
    int64_t block[4]; /* valid, start, stride, count */
} conv_memory;

typedef struct ss_entry {
    int used;
    double h;
    double *update; /* (r, r + 2n): [Phi, G0 - G1, G1] */
    double *output; /* (n, r + 2n): C times it */
} ss_entry;

typedef struct ss_memory {
    double *w;      /* (r + 2n): state at the last committed point, velocity there, current velocity */
    double pending; /* s since the last committed point */
    ss_entry cache[STATE_SPACE_CACHE];
    size_t next;    /* round-robin slot */
    double *aug, *expm_out, *expm_work; /* workspace (r + 2n)^2, (r + 2n)^2, 8 (r + 2n)^2 */
    int64_t *pivots;
} ss_memory;

typedef struct work_account {
    double committed[WEC_HYDRO_COMPONENTS], last_power[WEC_HYDRO_COMPONENTS];
    double last_time;
    int64_t has_last;
} work_account;

typedef struct memory_rate {
    int64_t has_previous, has_latest;
    double t_previous, t_latest;
    double *previous, *latest; /* (n) */
} memory_rate;

typedef struct pressure_scratch {
    double *world;   /* (faces, 3, 3) corners in the current pose */
    double *surface; /* (faces, 3) surface height above each corner */
    double *wet;     /* (2 faces, 3, 3) wetted triangles */
} pressure_scratch;

struct wec_hydro {
    uint32_t magic;
    hydro_shared *shared;
    char error[HYDRO_MSG_SIZE];
    double start_time, elapsed, elapsed_error;
    phasor_clock clock;
    conv_memory conv;
    ss_memory ss;
    work_account work;
    memory_rate rate;
    /* the last evaluated point: its inputs, force rows (5, n), powers and work */
    int cached;
    double cache_t;
    double *cache_x, *cache_v, *block;
    double power[WEC_HYDRO_COMPONENTS], work_value[WEC_HYDRO_COMPONENTS], eta;
    /* scratch */
    double *scratch_n;   /* (4 n) */
    double *scratch_nn;  /* (2 n n) */
    double *eta_window;  /* (L) */
    pressure_scratch pressure;
};

/* --------------------------------------------------------------------------------------------- concepts */
/* each load function reads its arrays from the data into the shared struct (checked; message on refusal) */
int hydro_load_model(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_waves(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_spreading(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_excitation(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_excitation_convolution(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_record(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_radiation_convolution(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_state_space(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_hydrostatics(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_viscous(hydro_shared *s, const wec_data *d, char *msg);
int hydro_load_pressure(hydro_shared *s, const wec_data *d, char *msg);
void hydro_shared_free(hydro_shared *s);

/* ramp.c */
double hydro_ramp(double duration, double t);
double hydro_ramp_rate(double duration, double t);

/* phasor_clock.c */
int phasor_clock_init(phasor_clock *c, size_t k);
void phasor_clock_free(phasor_clock *c);
void phasor_clock_copy(phasor_clock *to, const phasor_clock *from, size_t k);
void phasor_clock_at(phasor_clock *c, const double *omega, size_t k, double t);

/* excitation.c: superposition of the combined table (forces of the n DOFs and, last, the elevation) */
void excitation_superposition(const hydro_shared *s, const phasor_clock *c, double ramp, double *exc, double *eta);
void excitation_superposition_rate(const hydro_shared *s, const phasor_clock *c, double t, double *rate);

/* excitation_convolution.c */
int excitation_convolution_prepare(hydro_shared *s, char *msg);
void excitation_convolution(const hydro_shared *s, double t, double *eta_window, double *exc);
void excitation_convolution_rate(const hydro_shared *s, double t, double *eta_window, double *rate, double *tmp);

/* record.c */
double record_elevation(const hydro_shared *s, double t);

/* elevation.c: the incident elevation at the origin (record or components), unramped then ramped */
double hydro_elevation(wec_hydro *h, double t);

/* incident_wave.c: elevation and dynamic pressure of the components at points */
double incident_elevation(const hydro_shared *s, double ramp, double t, double x, double y);
double incident_pressure(const hydro_shared *s, double ramp, double t, const double *p);

/* radiation_convolution.c */
int conv_memory_init(conv_memory *c, const hydro_shared *s);
void conv_memory_free(conv_memory *c);
void conv_memory_copy(conv_memory *to, const conv_memory *from, const hydro_shared *s);
void conv_memory_force(conv_memory *c, const hydro_shared *s, const double *v, double *mu);
void conv_memory_damping(const conv_memory *c, const hydro_shared *s, double *d);
int conv_memory_step(conv_memory *c, const hydro_shared *s, const double *v, double h, char *msg);

/* state_space.c */
int ss_memory_init(ss_memory *m, const hydro_shared *s);
void ss_memory_free(ss_memory *m);
void ss_memory_copy(ss_memory *to, const ss_memory *from, const hydro_shared *s);
int ss_memory_force(ss_memory *m, const hydro_shared *s, const double *v, double *mu, char *msg);
int ss_memory_damping(ss_memory *m, const hydro_shared *s, double *d, char *msg);
int ss_memory_step(ss_memory *m, const hydro_shared *s, const double *v, double h, char *msg);

/* hydrostatics.c, viscous.c */
void hydrostatics_linear(const hydro_shared *s, const double *x, double *f);
double viscous_force(const hydro_shared *s, size_t i, double v);
double viscous_tangent(const hydro_shared *s, size_t i, double v);

/* mesh_clip.c */
size_t mesh_clip_below(const double *corners, const double *surface, size_t faces, double *wet);

/* pressure.c */
int pressure_scratch_init(pressure_scratch *p, const hydro_shared *s);
void pressure_scratch_free(pressure_scratch *p);
void pressure_equilibrium(hydro_shared *s, pressure_scratch *scratch);
void pressure_forces(wec_hydro *h, double t, const double *x, double *hs, double *fk);

/* linearised.c */
int hydro_linearise(wec_hydro *h, double t, const double *x, const double *v, const unsigned char *stiffness_mask,
                    const unsigned char *damping_mask, double *f0, double *rate, double *dfdx, double *dfdv);
int memory_rate_init(memory_rate *r, size_t n);
void memory_rate_free(memory_rate *r);
void memory_rate_copy(memory_rate *to, const memory_rate *from, size_t n);

/* work.c */
void work_powers(const double *block, const double *v, size_t n, double *power);
void work_value(const work_account *w, double t, const double *power, double *out);
void work_commit(work_account *w, double t, const double *power, const double *value);

/* evaluate.c: the point's forces into h->block and its elevation (the cache updated) */
int hydro_evaluate(wec_hydro *h, double t, const double *x, const double *v, char *msg);

/* state.c */
size_t hydro_state_size(const wec_hydro *h);
int hydro_state_write(const wec_hydro *h, wec_writer *w);
int hydro_state_read(wec_hydro *h, wec_reader *r, char *msg);

/* model.c */
static inline int hydro_live(const wec_hydro *h) { return h != NULL && h->magic == HYDRO_MAGIC; }
int hydro_instance_init(wec_hydro *h, hydro_shared *s);
void hydro_instance_free(wec_hydro *h);

#endif
