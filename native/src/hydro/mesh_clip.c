/* The wetted part of a triangle mesh (hydro_fmu.nonlinear_hydrostatics.clip_below): each triangle is cut where
 * the linear interpolant of z - surface along its edges vanishes (the surface taken linear between the corner
 * heights). Fully wet triangles are kept; one wet corner gives the triangle (c0, p01, p02); two wet corners give
 * the quadrilateral (c0, c1, p12, p20) as two triangles; orientation (the outward normal) is kept. At most two
 * triangles per face. */
#include <string.h>

#include "hydro_internal.h"

static void cut(const double *p, const double *q, double dp, double dq, double *out)
{
    double f = dp / (dp - dq);
    for (int i = 0; i < 3; i++)
        out[i] = p[i] + (q[i] - p[i]) * f;
}

static void put(double *wet, size_t index, const double *a, const double *b, const double *c)
{
    double *t = wet + 9 * index;
    memcpy(t, a, 3 * sizeof(double));
    memcpy(t + 3, b, 3 * sizeof(double));
    memcpy(t + 6, c, 3 * sizeof(double));
}

size_t mesh_clip_below(const double *corners, const double *surface, size_t faces, double *wet)
{
    size_t count = 0;
    for (size_t f = 0; f < faces; f++) {
        const double *c = corners + 9 * f;
        double d[3];
        int below[3], wet_corners = 0;
        for (int j = 0; j < 3; j++) {
            d[j] = c[3 * j + 2] - surface[3 * f + (size_t)j];
            below[j] = d[j] < 0;
            wet_corners += below[j];
        }
        if (wet_corners == 3) {
            memcpy(wet + 9 * count++, c, 9 * sizeof(double));
        } else if (wet_corners == 1) {
            int s = below[0] ? 0 : (below[1] ? 1 : 2); /* the wet corner first */
            const double *c0 = c + 3 * s, *c1 = c + 3 * ((s + 1) % 3), *c2 = c + 3 * ((s + 2) % 3);
            double d0 = d[s], d1 = d[(s + 1) % 3], d2 = d[(s + 2) % 3], p01[3], p02[3];
            cut(c0, c1, d0, d1, p01);
            cut(c0, c2, d0, d2, p02);
            put(wet, count++, c0, p01, p02);
        } else if (wet_corners == 2) {
            int dry = !below[0] ? 0 : (!below[1] ? 1 : 2);
            int s = (dry + 1) % 3; /* the dry corner last */
            const double *c0 = c + 3 * s, *c1 = c + 3 * ((s + 1) % 3), *c2 = c + 3 * ((s + 2) % 3);
            double d0 = d[s], d1 = d[(s + 1) % 3], d2 = d[(s + 2) % 3], p12[3], p20[3];
            cut(c1, c2, d1, d2, p12);
            cut(c2, c0, d2, d0, p20);
            put(wet, count++, c0, c1, p12);
            put(wet, count++, c0, p12, p20);
        }
    }
    return count;
}
