/* core/util/error.c — error values with a one-line message (tessera/error.h).
 * Owns: formatting into a caller-owned tsr_error and the code names.
 * Never: exits, aborts or keeps any state of its own. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "tessera/error.h"

int tsr_error_set(tsr_error *err, int code, const char *fmt, ...)
{
    if (!err)
        return code;
    err->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    /* Messages are one line by contract: a value quoted into a message may
     * carry a newline, which would split log output and confuse callers. */
    for (char *c = err->message; *c; c++)
        if (*c == '\n' || *c == '\r')
            *c = ' ';
    return code;
}

void tsr_error_clear(tsr_error *err)
{
    if (!err)
        return;
    err->code = TSR_OK;
    err->message[0] = '\0';
}

const char *tsr_error_name(int code)
{
    switch (code) {
    case TSR_OK: return "OK";
    case TSR_EINVAL: return "EINVAL";
    case TSR_ENOENT: return "ENOENT";
    case TSR_ENOMEM: return "ENOMEM";
    case TSR_EIO: return "EIO";
    case TSR_EPROTO: return "EPROTO";
    case TSR_EUNSUPPORTED: return "EUNSUPPORTED";
    case TSR_ETIMEDOUT: return "ETIMEDOUT";
    case TSR_ESTATE: return "ESTATE";
    default: return "EUNKNOWN";
    }
}
