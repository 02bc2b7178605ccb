/* tessera/log.h — one-line diagnostics to stderr, filtered by level
 * (TESSERA_LOG=debug|info|warn|error, default warn). */
#ifndef TESSERA_LOG_H
#define TESSERA_LOG_H

#include "tessera/export.h"

typedef enum tsr_log_level {
    TSR_LOG_DEBUG = 0,
    TSR_LOG_INFO = 1,
    TSR_LOG_WARN = 2,
    TSR_LOG_ERROR = 3,
} tsr_log_level;

TSR_API void tsr_log(tsr_log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
TSR_API int tsr_log_enabled(tsr_log_level level);

#endif
