/* mothership/util.h — small helpers the mothership, its node side and the
 * CLI share: mkdir -p, a number from a flat JSON object
 * (the network SPUs' TESSERA_STATS_FILE) and an environment for execve.
 * Internal to mothership/ and cli/. */
#ifndef TSR_MOTHERSHIP_UTIL_H
#define TSR_MOTHERSHIP_UTIL_H

/* mkdir -p; 0, or -1 with errno set. */
int tsr_ms_mkdirs(const char *path);
/* The number after "key": in a flat JSON object; 0 when found, -1 not. */
int tsr_ms_json_number(const char *json, const char *key, double *out);
/* A copy of the environment for execve in a forked child, built before
 * fork (the child of a threaded process must not call setenv or malloc).
 * `changes`: "KEY=VALUE" to set, "KEY" to remove; NULL-terminated. The
 * array is malloc'd (free it), its strings are borrowed. NULL: no memory. */
char **tsr_ms_environ(const char *const *changes);

#endif
