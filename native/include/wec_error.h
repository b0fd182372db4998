/* Status codes and the export macro shared by every wec-cosim runtime (hydrodynamics now, multibody later).
 *
 * Every function of a runtime's C API returns one of these codes (WEC_OK on success). On any other code the
 * handle's last error message (e.g. wec_hydro_last_error) says what was wrong and what to do; a create function
 * returns NULL instead and its message is fetched with the runtime's create-error function. Messages are plain
 * UTF-8 text, at most WEC_MESSAGE_SIZE - 1 bytes, never NULL. */
#ifndef WEC_ERROR_H
#define WEC_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define WEC_API __declspec(dllexport)
#elif defined(__GNUC__)
#define WEC_API __attribute__((visibility("default")))
#else
#define WEC_API
#endif

typedef enum wec_status {
    WEC_OK = 0,
    WEC_ERR_HANDLE = 1,   /* the handle is NULL or not a live handle of this runtime */
    WEC_ERR_ARGUMENT = 2, /* a pointer, size or value passed to the call is wrong */
    WEC_ERR_DATA = 3,     /* the runtime input data were refused (create) */
    WEC_ERR_STATE = 4,    /* a saved state was refused (it belongs to another model, or is corrupt) */
    WEC_ERR_STEP = 5,     /* a step the model cannot take (time or step size inconsistent with the model) */
    WEC_ERR_MEMORY = 6    /* an allocation failed */
} wec_status;

#define WEC_MESSAGE_SIZE 512

/* The name of a status code ("WEC_OK", "WEC_ERR_DATA", ...; "unknown status" otherwise). */
WEC_API const char *wec_status_name(int status);

/* Version of the runtime library (major * 10000 + minor * 100 + patch) and of the data format it reads. */
WEC_API int wec_runtime_version(void);
WEC_API int wec_data_format_version(void);

#ifdef __cplusplus
}
#endif
#endif
