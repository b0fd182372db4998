/* Test driver of the hydrodynamics runtime for the sanitizer build (tests/test_runtime_sanitizers.py): every file
 * named on the command line is runtime input data, valid or mutated. Each is loaded; a refused one must come with a
 * message; a loaded one is driven through every entry point of the API (outputs, linearisation, steps that may be
 * refused, state size/save/load, a corrupted state, clone, copy, free). Prints one line per file ("ok ..." or
 * "refused: <message>"; "ok" lines carry a hash of every output's bits) and exits 0 unless a refusal came without a
 * message. Built with -fsanitize=address,undefined, any out-of-bounds access, leak, use after free or undefined
 * behaviour aborts; built with and without the AVX2 clones of the dot products, the hashes must be equal. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wec_hydro.h"

static unsigned char *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    fseek(f, 0, SEEK_END);
    long length = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *buffer = malloc(length > 0 ? (size_t)length : 1);
    *size = fread(buffer, 1, (size_t)length, f);
    fclose(f);
    return buffer;
}

/* FNV-1a over the bits of n doubles, into *hash: the driver's record of every output */
static void digest(uint64_t *hash, const double *values, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        uint64_t bits;
        memcpy(&bits, &values[i], 8);
        *hash = (*hash ^ bits) * 1099511628211ULL;
    }
}

static int exercise(wec_hydro *model, double step)
{
    size_t n = 0, state_size = 0;
    if (wec_hydro_dofs(model, &n) != WEC_OK || n == 0)
        return 1;
    double *x = calloc(n, sizeof(double)), *v = calloc(n, sizeof(double)), *forces = calloc(5 * n, sizeof(double));
    double *f0 = calloc(n, sizeof(double)), *rate = calloc(n, sizeof(double));
    double *dfdx = calloc(n * n, sizeof(double)), *dfdv = calloc(n * n, sizeof(double));
    double power[4], work[4], eta = 0.0, t = 0.0;
    int64_t rows[3] = {0, 4, 2};
    int refused = 0;
    uint64_t hash = 1469598103934665603ULL;
    for (int k = 0; k < 12; k++) {
        for (size_t i = 0; i < n; i++) {
            x[i] = 0.1 * (double)((k + (int)i) % 5) - 0.2;
            v[i] = 0.05 * (double)((3 * k + (int)i) % 7) - 0.15;
        }
        wec_hydro_outputs(model, t, x, v, n, NULL, 5, forces, power, work, &eta);
        wec_hydro_outputs(model, t, x, v, n, rows, 3, forces, NULL, NULL, NULL);
        if (wec_hydro_linearise(model, t, x, v, n, NULL, NULL, f0, rate, dfdx, dfdv) == WEC_OK) {
            digest(&hash, f0, n);
            digest(&hash, rate, n);
            digest(&hash, dfdx, n * n);
            digest(&hash, dfdv, n * n);
        }
        wec_hydro_elevation(model, t + 0.05, &eta);
        digest(&hash, forces, 3 * n);
        digest(&hash, &eta, 1);
        if (wec_hydro_do_step(model, t, step, x, v, n) == WEC_OK)
            t += step;
        else
            refused++;
        if (k == 5 && wec_hydro_state_size(model, &state_size) == WEC_OK) {
            unsigned char *state = malloc(state_size);
            if (wec_hydro_state_save(model, state, state_size) == WEC_OK) {
                wec_hydro *copy = wec_hydro_clone(model);
                if (copy != NULL) {
                    wec_hydro_outputs(copy, t, x, v, n, NULL, 5, forces, power, work, &eta);
                    wec_hydro_state_load(copy, state, state_size);
                    wec_hydro_state_load(copy, state, state_size / 2);     /* truncated: refused */
                    state[state_size / 3] ^= 0xFF;                         /* corrupt: refused or harmless */
                    wec_hydro_state_load(copy, state, state_size);
                    wec_hydro_copy_state(model, copy);
                    wec_hydro_free(copy);
                }
            }
            free(state);
        }
    }
    wec_hydro_outputs(model, t, x, v, n + 1, NULL, 5, forces, power, work, &eta); /* wrong size: refused */
    wec_hydro_outputs(model, t, NULL, v, n, NULL, 5, forces, power, work, &eta);  /* NULL input: refused */
    printf("ok n=%zu state=%zu refused_steps=%d outputs=%016llx\n", n, state_size, refused, (unsigned long long)hash);
    free(x);
    free(v);
    free(forces);
    free(f0);
    free(rate);
    free(dfdx);
    free(dfdv);
    return 0;
}

int main(int argc, char **argv)
{
    int failures = 0;
    if (wec_hydro_last_error(NULL)[0] == '\0' || wec_hydro_outputs(NULL, 0, NULL, NULL, 0, NULL, 0, NULL, NULL, NULL,
                                                                   NULL) != WEC_ERR_HANDLE)
        failures++;
    for (int i = 1; i < argc; i++) {
        size_t size = 0;
        unsigned char *data = read_file(argv[i], &size);
        if (data == NULL) {
            printf("unreadable: %s\n", argv[i]);
            failures++;
            continue;
        }
        wec_hydro *model = wec_hydro_create(data, size);
        free(data); /* the model keeps what it needs */
        if (model == NULL) {
            const char *message = wec_hydro_create_error();
            if (message == NULL || message[0] == '\0') {
                printf("refused without a message: %s\n", argv[i]);
                failures++;
            } else {
                printf("refused: %s\n", message);
            }
            continue;
        }
        failures += exercise(model, 0.1);
        wec_hydro_free(model);
    }
    return failures ? 1 : 0;
}
