/* Nonlinear hydrostatic and Froude-Krylov forces over the instantaneous wetted hull
 * (hydro_fmu.nonlinear_hydrostatics.BodyPressureModel):
 *
 *     F_hs(x) = -int_{S_w} p_s n dS - F_hs(0),  p_s = -rho g z;     F_FK(x, t) = -int_{S_w} p_d n dS,
 *
 * moments about the current centre of gravity, world frame. Pose: the displacement (x1, x2, x3, r1, r2, r3) moves
 * the centre of gravity by (x1, x2, x3) and rotates the body about it by R = exp([r]x) (Rodrigues; r a world
 * rotation vector). S_w is the mesh below z = 0 (hydrostatics alone) or below the incident wave surface (when the
 * Froude-Krylov force is nonlinear, for both parts), cut by mesh_clip.c. Each wetted triangle is integrated by the
 * three-point edge-midpoint rule (exact for quadratic integrands: the hydrostatic force and moment are exact on a
 * flat-panel mesh; the Froude-Krylov pressure to second order in the panel size). F_hs(0), the buoyancy at the
 * equilibrium pose in still water, is computed at creation and subtracted. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hydro_internal.h"

int hydro_load_pressure(hydro_shared *s, const wec_data *d, char *msg)
{
    int needed = s->hydrostatics == HYDROSTATICS_NONLINEAR || s->froude_krylov;
    if (!needed)
        return WEC_OK;
    const wec_array *rho, *g, *depth, *cg, *corners, *faces;
    int st;
    if ((st = wec_data_get(d, "environment.rho", WEC_F64, 0, NULL, 1, 1, &rho, msg, HYDRO_MSG_SIZE)) != WEC_OK ||
        (st = wec_data_get(d, "environment.g", WEC_F64, 0, NULL, 1, 1, &g, msg, HYDRO_MSG_SIZE)) != WEC_OK ||
        (st = wec_data_get(d, "environment.depth", WEC_F64, 0, NULL, 1, 0, &depth, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->rho = wec_array_f64(rho, 0);
    s->g = wec_array_f64(g, 0);
    s->depth = wec_array_f64(depth, 0);
    if (!(s->rho > 0) || !(s->g > 0))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'environment.rho' and 'environment.g' must "
                        "be positive");
    if (!(s->depth > 0) || (isinf(s->depth) && s->depth < 0))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'environment.depth' must be positive "
                        "(+inf for deep water)");
    int64_t shape_cg[2] = {(int64_t)s->bodies, 3}, shape_corners[3] = {-1, 3, 3}, shape_faces[1] = {(int64_t)s->bodies};
    if ((st = wec_data_get(d, "bodies.cg", WEC_F64, 2, shape_cg, 1, 1, &cg, msg, HYDRO_MSG_SIZE)) != WEC_OK ||
        (st = wec_data_get(d, "mesh.corners", WEC_F64, 3, shape_corners, 1, 1, &corners, msg, HYDRO_MSG_SIZE)) !=
            WEC_OK ||
        (st = wec_data_get(d, "mesh.faces", WEC_I64, 1, shape_faces, 1, 0, &faces, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->faces = (size_t)corners->shape[0];
    s->cg = wec_array_copy_f64(cg);
    s->corners = wec_array_copy_f64(corners);
    s->first_face = calloc(s->bodies + 1, sizeof(size_t));
    s->equilibrium = wec_alloc_f64(6 * s->bodies);
    if (!s->cg || !s->corners || !s->first_face || !s->equilibrium)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t b = 0; b < s->bodies; b++) {
        int64_t count = wec_array_i64(faces, b);
        if (count < 0 || (uint64_t)count > s->faces - s->first_face[b])
            return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'mesh.faces' gives body %zu %lld faces: "
                            "the counts must be non-negative and add up to the %zu faces of 'mesh.corners'", b,
                            (long long)count, s->faces);
        s->first_face[b + 1] = s->first_face[b] + (size_t)count;
    }
    if (s->first_face[s->bodies] != s->faces)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'mesh.faces' adds up to %zu faces, "
                        "'mesh.corners' holds %zu", s->first_face[s->bodies], s->faces);
    return WEC_OK;
}

int pressure_scratch_init(pressure_scratch *p, const hydro_shared *s)
{
    memset(p, 0, sizeof(*p));
    if (s->faces == 0)
        return WEC_OK;
    p->world = wec_alloc_f64(9 * s->faces);
    p->surface = wec_alloc_f64(3 * s->faces);
    p->wet = wec_alloc_f64(18 * s->faces);
    return p->world && p->surface && p->wet ? WEC_OK : WEC_ERR_MEMORY;
}

void pressure_scratch_free(pressure_scratch *p)
{
    free(p->world);
    free(p->surface);
    free(p->wet);
}

/* exp([theta]x) (hydro_fmu.meshes.rotation_matrix) */
static void rotation(const double *theta, double r[9])
{
    double angle = sqrt(theta[0] * theta[0] + theta[1] * theta[1] + theta[2] * theta[2]);
    double k[9];
    if (angle < 1e-12) {
        double kk[9] = {0, -theta[2], theta[1], theta[2], 0, -theta[0], -theta[1], theta[0], 0};
        for (int i = 0; i < 9; i++)
            r[i] = kk[i] + (i % 4 == 0 ? 1.0 : 0.0);
        return;
    }
    double ax = theta[0] / angle, ay = theta[1] / angle, az = theta[2] / angle;
    double kk[9] = {0, -az, ay, az, 0, -ax, -ay, ax, 0};
    memcpy(k, kk, sizeof(k));
    double sa = sin(angle), ca = 1 - cos(angle);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double k2 = k[3 * i + 0] * k[0 + j] + k[3 * i + 1] * k[3 + j] + k[3 * i + 2] * k[6 + j];
            r[3 * i + j] = (i == j ? 1.0 : 0.0) + sa * k[3 * i + j] + ca * k2;
        }
}

typedef struct pressure_field {
    const hydro_shared *s;
    int dynamic; /* 0: hydrostatic -rho g z; 1: incident dynamic pressure */
    double ramp, t;
} pressure_field;

static double field(const pressure_field *f, const double *p)
{
    if (!f->dynamic)
        return -f->s->rho * f->s->g * p[2];
    return incident_pressure(f->s, f->ramp, f->t, p);
}

/* -int p n dS over the wetted triangles and its moment about centre, into out (6) */
static void integrate(const double *wet, size_t count, const double *centre, const pressure_field *f, double *out)
{
    for (int i = 0; i < 6; i++)
        out[i] = 0.0;
    for (size_t g = 0; g < count; g++) {
        const double *c = wet + 9 * g;
        double e1[3] = {c[3] - c[0], c[4] - c[1], c[5] - c[2]}, e2[3] = {c[6] - c[0], c[7] - c[1], c[8] - c[2]};
        double area[3] = {0.5 * (e1[1] * e2[2] - e1[2] * e2[1]), 0.5 * (e1[2] * e2[0] - e1[0] * e2[2]),
                          0.5 * (e1[0] * e2[1] - e1[1] * e2[0])};
        for (int q = 0; q < 3; q++) {
            const double *a = c + 3 * q, *b = c + 3 * ((q + 1) % 3);
            double point[3] = {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
            double p = field(f, point) / 3.0;
            double force[3] = {-p * area[0], -p * area[1], -p * area[2]};
            double arm[3] = {point[0] - centre[0], point[1] - centre[1], point[2] - centre[2]};
            out[0] += force[0];
            out[1] += force[1];
            out[2] += force[2];
            out[3] += arm[1] * force[2] - arm[2] * force[1];
            out[4] += arm[2] * force[0] - arm[0] * force[2];
            out[5] += arm[0] * force[1] - arm[1] * force[0];
        }
    }
}

/* the body's corners in the pose x (6) into scratch->world (its faces only) and the centre of gravity there */
static void place(const hydro_shared *s, size_t body, const double *x, pressure_scratch *scratch, double *centre)
{
    double r[9];
    rotation(x + 3, r);
    for (int i = 0; i < 3; i++)
        centre[i] = s->cg[3 * body + (size_t)i] + x[i];
    for (size_t f = s->first_face[body]; f < s->first_face[body + 1]; f++)
        for (int j = 0; j < 3; j++) {
            const double *p = s->corners + 9 * f + 3 * j;
            double *w = scratch->world + 9 * f + 3 * j;
            for (int i = 0; i < 3; i++)
                w[i] = (r[3 * i] * p[0] + r[3 * i + 1] * p[1] + r[3 * i + 2] * p[2]) + centre[i];
        }
}

void pressure_equilibrium(hydro_shared *s, pressure_scratch *scratch)
{
    double zero[6] = {0, 0, 0, 0, 0, 0}, centre[3];
    pressure_field still = {s, 0, 0.0, 0.0};
    for (size_t b = 0; b < s->bodies; b++) {
        size_t first = s->first_face[b], count = s->first_face[b + 1] - first;
        place(s, b, zero, scratch, centre);
        memset(scratch->surface, 0, 3 * count * sizeof(double));
        size_t wet = mesh_clip_below(scratch->world + 9 * first, scratch->surface, count, scratch->wet);
        integrate(scratch->wet, wet, centre, &still, s->equilibrium + 6 * b);
    }
}

void pressure_forces(wec_hydro *h, double t, const double *x, double *hs, double *fk)
{
    const hydro_shared *s = h->shared;
    pressure_scratch *scratch = &h->pressure;
    int want_hs = s->hydrostatics == HYDROSTATICS_NONLINEAR, want_fk = s->froude_krylov && s->k > 0;
    size_t start = 0;
    for (size_t b = 0; b < s->bodies; b++) {
        double pose[6] = {0, 0, 0, 0, 0, 0}, centre[3], f_hs[6] = {0}, f_fk[6] = {0};
        size_t end = start;
        while (end < s->n && (size_t)s->body_of[end] == b)
            end++;
        for (size_t i = start; i < end; i++)
            pose[s->dof_of[i]] = x[i];
        size_t first = s->first_face[b], count = s->first_face[b + 1] - first;
        place(s, b, pose, scratch, centre);
        const double *world = scratch->world + 9 * first;
        double *surface = scratch->surface;
        if (want_fk) {
            double ramp = hydro_ramp(s->ramp, t);
            for (size_t f = 0; f < 3 * count; f++)
                surface[f] = incident_elevation(s, ramp, t, world[3 * f], world[3 * f + 1]);
            size_t wet = mesh_clip_below(world, surface, count, scratch->wet);
            pressure_field dynamic = {s, 1, ramp, t};
            integrate(scratch->wet, wet, centre, &dynamic, f_fk);
        } else {
            memset(surface, 0, 3 * count * sizeof(double));
        }
        if (want_hs) {
            size_t wet = mesh_clip_below(world, surface, count, scratch->wet);
            pressure_field still = {s, 0, 0.0, t};
            integrate(scratch->wet, wet, centre, &still, f_hs);
            for (int i = 0; i < 6; i++)
                f_hs[i] -= s->equilibrium[6 * b + (size_t)i];
        }
        for (size_t i = start; i < end; i++) {
            hs[i] = f_hs[s->dof_of[i]];
            fk[i] = f_fk[s->dof_of[i]];
        }
        start = end;
    }
}
