/* The FMI-version-independent part of the native co-simulation FMUs (cosimulation.h). */
#include "cosimulation.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void fmu_log(fmu_instance *instance, fmu_status status, const char *category, const char *format, ...)
{
    if (instance == NULL || instance->log == NULL)
        return;
    if (status == FMU_OK && !instance->logging_on)
        return;
    char message[FMU_MESSAGE_SIZE];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    instance->log(instance, status, category, message);
}

static int hex_value(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

fmu_status fmu_set_resources(fmu_instance *instance, const char *location)
{
    if (location == NULL || location[0] == '\0') {
        fmu_log(instance, FMU_ERROR, "logError", "no resource location given: the FMU reads its model from "
                "resources/ (the host must pass the unzipped FMU's resources folder)");
        return FMU_ERROR;
    }
    const char *path = location;
    if (strncmp(path, "file://", 7) == 0) {
        path += 7;
        if (path[0] != '/') { /* file://host/path: the host must be local */
            const char *slash = strchr(path, '/');
            if (slash == NULL || (strncmp(path, "localhost/", 10) != 0 && slash != path)) {
                fmu_log(instance, FMU_ERROR, "logError", "resource location %s is not a local file URI", location);
                return FMU_ERROR;
            }
            path = slash;
        }
    } else if (strncmp(path, "file:", 5) == 0) {
        path += 5;
    }
    size_t k = 0;
    for (const char *p = path; *p != '\0'; p++) {
        char c = *p;
        if (c == '%' && hex_value(p[1]) >= 0 && hex_value(p[2]) >= 0) {
            c = (char)(hex_value(p[1]) * 16 + hex_value(p[2]));
            p += 2;
        }
        if (k + 2 >= sizeof instance->resources) {
            fmu_log(instance, FMU_ERROR, "logError", "resource location %s is too long", location);
            return FMU_ERROR;
        }
        instance->resources[k++] = c;
    }
    if (k == 0 || instance->resources[k - 1] != '/')
        instance->resources[k++] = '/';
    instance->resources[k] = '\0';
    return FMU_OK;
}

unsigned char *fmu_read_resource(fmu_instance *instance, const char *name, size_t *size)
{
    char path[FMU_PATH_SIZE + 256];
    snprintf(path, sizeof path, "%s%s", instance->resources, name);
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        fmu_log(instance, FMU_ERROR, "logError", "cannot open %s: the FMU's resources are incomplete (rebuild the "
                "FMU with wec-cosim build-fmus)", path);
        return NULL;
    }
    unsigned char *buffer = NULL;
    long length = -1;
    if (fseek(f, 0, SEEK_END) == 0)
        length = ftell(f);
    if (length >= 0 && fseek(f, 0, SEEK_SET) == 0)
        buffer = malloc(length > 0 ? (size_t)length : 1);
    if (buffer == NULL || fread(buffer, 1, (size_t)length, f) != (size_t)length) {
        fmu_log(instance, FMU_ERROR, "logError", "cannot read %s", path);
        free(buffer);
        fclose(f);
        return NULL;
    }
    fclose(f);
    *size = (size_t)length;
    return buffer;
}

void fmu_clock_start(fmu_instance *instance, double start_time)
{
    instance->start_time = start_time;
    instance->anchor = start_time;
    instance->step = 0.0;
    instance->count = 0;
    instance->time = start_time;
}

fmu_status fmu_step_request(fmu_instance *instance, double current_time, double h, int *take)
{
    *take = 0;
    if (!isfinite(h) || !isfinite(current_time) || !(h > 0)) {
        fmu_log(instance, FMU_ERROR, "logError", "doStep at t = %.17g s with step %g s: the step must be finite and "
                "positive", current_time, h);
        return FMU_ERROR;
    }
    double unit = instance->step > h ? instance->step : h;
    if (fabs(current_time - instance->time) > 1e-9 * unit + 1e-12 * fabs(instance->time)) {
        fmu_log(instance, FMU_ERROR, "logError", "doStep at t = %.17g s, but the FMU is at t = %.17g s: this FMU "
                "takes consecutive steps only (no rollback; restore an FMU state to go back)", current_time,
                instance->time);
        return FMU_ERROR;
    }
    if (instance->step > 0 && h <= 1e-9 * instance->step) {
        fmu_log(instance, FMU_OK, "logEvents", "final step of %g s (shorter than 1e-9 of the step %g s) accepted "
                "without moving the model", h, instance->step);
        return FMU_OK;
    }
    *take = 1;
    return FMU_OK;
}

void fmu_clock_advance(fmu_instance *instance, double h)
{
    if (h != instance->step) {
        instance->anchor += (double)instance->count * instance->step;
        instance->step = h;
        instance->count = 0;
    }
    instance->count++;
    instance->time = instance->anchor + (double)instance->count * instance->step;
}
