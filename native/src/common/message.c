/* Messages and status names. */
#include <stdarg.h>
#include <stdio.h>

#include "wec_common.h"

int wec_fail(char *message, size_t size, int status, const char *format, ...)
{
    if (message != NULL && size > 0) {
        va_list args;
        va_start(args, format);
        int written = vsnprintf(message, size, format, args);
        va_end(args);
        if (written < 0)
            message[0] = '\0';
        message[size - 1] = '\0';
    }
    return status;
}

const char *wec_status_name(int status)
{
    switch (status) {
    case WEC_OK: return "WEC_OK";
    case WEC_ERR_HANDLE: return "WEC_ERR_HANDLE";
    case WEC_ERR_ARGUMENT: return "WEC_ERR_ARGUMENT";
    case WEC_ERR_DATA: return "WEC_ERR_DATA";
    case WEC_ERR_STATE: return "WEC_ERR_STATE";
    case WEC_ERR_STEP: return "WEC_ERR_STEP";
    case WEC_ERR_MEMORY: return "WEC_ERR_MEMORY";
    default: return "unknown status";
    }
}

int wec_runtime_version(void) { return 100; /* 0.1.0 */ }

int wec_data_format_version(void) { return WEC_DATA_VERSION; }
