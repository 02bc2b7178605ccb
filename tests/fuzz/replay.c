/* tests/fuzz/replay.c — runs every file of a fuzz corpus once through the
 * same entry point the libFuzzer target uses, without libFuzzer, so any
 * compiler (and the ASan build) replays the corpus in the normal suite.
 * Built once per target: the unpacker's (fuzz_unpack_explain) by default,
 * any other target's fuzz_target_explain (fuzz_target.h) when compiled
 * with TSR_FUZZ_TARGET.
 * Owns only its file reading; never skips a file it cannot read (that is a
 * failure). Seeds named ok-* (valid packed streams) must decode and bad-*
 * (known malformations) must be rejected (each target says what valid
 * means); any other file (inputs libFuzzer
 * found) only has to return without a crash or sanitizer report.
 * Usage: fuzz_corpus_replay DIR|FILE...  (exit 0 when every input behaved) */
#ifdef TSR_FUZZ_TARGET
#include "fuzz_target.h"
#define replay_explain fuzz_target_explain
#else
#include "fuzz_unpack.h"
#define replay_explain fuzz_unpack_explain
#endif

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static int read_file(const char *path, uint8_t **data, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "fuzz_corpus_replay: %s: %s\n", path, strerror(errno));
        return -1;
    }
    size_t cap = 4096, n = 0;
    uint8_t *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, f);
        if (n < cap)
            break;
        uint8_t *bigger = realloc(buf, cap * 2);
        if (!bigger) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = bigger;
        cap *= 2;
    }
    int failed = ferror(f) || !buf;
    fclose(f);
    if (failed) {
        fprintf(stderr, "fuzz_corpus_replay: %s: read failed\n", path);
        free(buf);
        return -1;
    }
    *data = buf;
    *size = n;
    return 0;
}

static int replay_file(const char *path, size_t *count)
{
    uint8_t *data = NULL;
    size_t size = 0;
    if (read_file(path, &data, &size) != 0)
        return -1;
    /* An exact-size heap copy, so ASan catches a read one byte past the end. */
    uint8_t *exact = malloc(size ? size : 1);
    if (!exact) {
        free(data);
        return -1;
    }
    memcpy(exact, data, size);
    free(data);
    char why[512] = "";
    int rc = replay_explain(exact, size, why, sizeof why);
    free(exact);
    (*count)++;
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    if (strncmp(base, "ok-", 3) == 0 && rc != 0) {
        fprintf(stderr, "fuzz_corpus_replay: %s: a valid stream was rejected: %s\n", path, why);
        return -1;
    }
    if (strncmp(base, "bad-", 4) == 0 && rc == 0) {
        fprintf(stderr, "fuzz_corpus_replay: %s: a malformed stream was accepted\n", path);
        return -1;
    }
    return 0;
}

static int name_cmp(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static int replay_dir(const char *dir, size_t *count)
{
    DIR *d = opendir(dir);
    if (!d) {
        fprintf(stderr, "fuzz_corpus_replay: %s: %s\n", dir, strerror(errno));
        return -1;
    }
    char **names = NULL;
    size_t n = 0, cap = 0;
    int rc = 0;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (ent->d_name[0] == '.')
            continue;
        if (n == cap) {
            cap = cap ? cap * 2 : 64;
            char **bigger = realloc(names, cap * sizeof *names);
            if (!bigger) {
                rc = -1;
                break;
            }
            names = bigger;
        }
        size_t len = strlen(dir) + strlen(ent->d_name) + 2;
        names[n] = malloc(len);
        if (!names[n]) {
            rc = -1;
            break;
        }
        snprintf(names[n], len, "%s/%s", dir, ent->d_name);
        n++;
    }
    closedir(d);
    /* Sorted, so a failure names the same file on every machine. */
    if (n)
        qsort(names, n, sizeof *names, name_cmp);
    for (size_t i = 0; i < n; i++) {
        if (rc == 0) {
            struct stat st;
            if (stat(names[i], &st) == 0 && S_ISREG(st.st_mode))
                rc = replay_file(names[i], count);
        }
        free(names[i]);
    }
    free(names);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s DIR|FILE...\n", argv[0]);
        return 2;
    }
    size_t count = 0;
    for (int i = 1; i < argc; i++) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            fprintf(stderr, "fuzz_corpus_replay: %s: %s\n", argv[i], strerror(errno));
            return 1;
        }
        int rc = S_ISDIR(st.st_mode) ? replay_dir(argv[i], &count) : replay_file(argv[i], &count);
        if (rc != 0)
            return 1;
    }
    if (count == 0) {
        fprintf(stderr, "fuzz_corpus_replay: no inputs found\n");
        return 1;
    }
    printf("fuzz_corpus_replay: %zu inputs replayed\n", count);
    return 0;
}
