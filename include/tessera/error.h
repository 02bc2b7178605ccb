/* tessera/error.h — error values with a message.
 * Library code never exits or aborts on bad input: it fills a tsr_error and
 * returns a failure value; the caller decides what to do. */
#ifndef TESSERA_ERROR_H
#define TESSERA_ERROR_H

#include "tessera/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Error codes (negative, like libuv). */
enum {
    TSR_OK = 0,
    TSR_EINVAL = -1, /* bad argument or bad input (graph, option, chain) */
    TSR_ENOENT = -2, /* something named does not exist (SPU, file) */
    TSR_ENOMEM = -3,
    TSR_EIO = -4,          /* file or device I/O failed */
    TSR_EPROTO = -5,       /* malformed or malicious stream data */
    TSR_EUNSUPPORTED = -6, /* valid, but not implemented here */
    TSR_ETIMEDOUT = -7,
    TSR_ESTATE = -8, /* call not valid in the current state */
};

typedef struct tsr_error {
    int code;          /* TSR_OK when no error */
    char message[512]; /* one line, names the culprit */
} tsr_error;

/* Sets code and a printf-style message; `err` may be NULL (then ignored).
 * Returns `code` so callers can write `return tsr_error_set(err, ...)`. */
TSR_API int tsr_error_set(tsr_error *err, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
TSR_API void tsr_error_clear(tsr_error *err);
/* Short name of a code ("EINVAL"). */
TSR_API const char *tsr_error_name(int code);

#ifdef __cplusplus
}
#endif
#endif
