/* core/util/log.c — one-line diagnostics on stderr (tessera/log.h), filtered by
 * TESSERA_LOG=debug|info|warn|error (default warn). Owns: the level, read
 * once per process. Never: writes partial lines or more than one line per call. */
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "tessera/log.h"

static pthread_once_t log_level_once = PTHREAD_ONCE_INIT;
/* Written once under log_level_once, read-only afterwards. */
static tsr_log_level log_threshold = TSR_LOG_WARN;

static void read_log_level(void)
{
    const char *env = getenv("TESSERA_LOG");
    if (!env || !*env)
        return;
    static const struct {
        const char *name;
        tsr_log_level level;
    } names[] = {
        {"debug", TSR_LOG_DEBUG},  {"info", TSR_LOG_INFO},   {"warn", TSR_LOG_WARN},
        {"warning", TSR_LOG_WARN}, {"error", TSR_LOG_ERROR},
    };
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcasecmp(env, names[i].name)) {
            log_threshold = names[i].level;
            return;
        }
    fprintf(stderr, "tessera: TESSERA_LOG='%s' is not one of debug|info|warn|error; using warn\n", env);
}

int tsr_log_enabled(tsr_log_level level)
{
    pthread_once(&log_level_once, read_log_level);
    return level >= log_threshold;
}

void tsr_log(tsr_log_level level, const char *fmt, ...)
{
    if (!tsr_log_enabled(level))
        return;
    /* Format the whole line first and write it with one call, so lines of
     * concurrent threads never interleave. */
    char line[1024];
    static const char prefix[] = "tessera: ";
    memcpy(line, prefix, sizeof prefix - 1);
    size_t room = sizeof line - (sizeof prefix - 1) - 1; /* keep one byte for '\n' */
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line + sizeof prefix - 1, room, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    size_t len = sizeof prefix - 1 + ((size_t)n < room ? (size_t)n : room - 1);
    for (size_t i = sizeof prefix - 1; i < len; i++)
        if (line[i] == '\n' || line[i] == '\r')
            line[i] = ' ';
    line[len++] = '\n';
    fwrite(line, 1, len, stderr);
}
