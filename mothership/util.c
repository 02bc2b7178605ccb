/* mothership/util.c — the helpers of util.h. Owns nothing. */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "mothership.h"
#include "util.h"

int tsr_ms_mkdirs(const char *path)
{
    char buf[PATH_MAX];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf) {
        errno = ENAMETOOLONG;
        return -1;
    }
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0777) && errno != EEXIST)
            return -1;
        *p = '/';
    }
    if (mkdir(buf, 0777) && errno != EEXIST)
        return -1;
    return 0;
}

int tsr_ms_json_number(const char *json, const char *key, double *out)
{
    char quoted[80];
    snprintf(quoted, sizeof quoted, "\"%s\"", key);
    const char *p = strstr(json, quoted);
    if (!p)
        return -1;
    p += strlen(quoted);
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    if (*p++ != ':')
        return -1;
    char *end;
    double v = strtod(p, &end);
    if (end == p)
        return -1;
    *out = v;
    return 0;
}

char **tsr_ms_environ(const char *const *changes)
{
    extern char **environ;
    size_t n = 0, c = 0;
    while (environ[n])
        n++;
    while (changes[c])
        c++;
    char **env = malloc((n + c + 1) * sizeof *env);
    if (!env)
        return NULL;
    size_t used = 0;
    for (size_t i = 0; i < n; i++) {
        int replaced = 0;
        for (size_t k = 0; k < c && !replaced; k++) {
            size_t klen = strcspn(changes[k], "=");
            replaced = !strncmp(environ[i], changes[k], klen) && environ[i][klen] == '=';
        }
        if (!replaced)
            env[used++] = environ[i];
    }
    for (size_t k = 0; k < c; k++)
        if (strchr(changes[k], '='))
            env[used++] = (char *)changes[k];
    env[used] = NULL;
    return env;
}
