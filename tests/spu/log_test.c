/* tests/spu/log_test.c — tsr_log: the TESSERA_LOG level filter and the
 * one-line "tessera: " format (core/util/log.c and core/util/error.c, compiled in).
 * ctest sets TESSERA_LOG per test; the expected level is argument 1.
 * Owns nothing. Never: depends on the terminal. */
#include <unistd.h>

#include "spu_test.h"
#include "tessera/error.h"
#include "tessera/log.h"

/* Runs `emit` with stderr redirected to a file and returns what it wrote. */
static const char *capture_stderr(void (*emit)(void))
{
    static char text[4096];
    char path[] = "/tmp/tessera_log_test_XXXXXX";
    int fd = mkstemp(path);
    REQUIRE(fd >= 0);
    fflush(stderr);
    int saved = dup(STDERR_FILENO);
    REQUIRE(saved >= 0 && dup2(fd, STDERR_FILENO) >= 0);
    emit();
    fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    size_t n = (size_t)pread(fd, text, sizeof text - 1, 0);
    text[n < sizeof text ? n : 0] = '\0';
    close(fd);
    unlink(path);
    return text;
}

static void emit_all_levels(void)
{
    tsr_log(TSR_LOG_DEBUG, "debug %d", 1);
    tsr_log(TSR_LOG_INFO, "info %d", 2);
    tsr_log(TSR_LOG_WARN, "warn %d", 3);
    tsr_log(TSR_LOG_ERROR, "error %d\nsecond line", 4);
}

static void test_level_filter(void)
{
    /* argv: the lowest level that must be printed (debug|info|warn|error). */
    REQUIRE(spu_test_argc == 1);
    static const char *const names[] = {"debug", "info", "warn", "error"};
    int lowest = -1;
    for (int i = 0; i < 4; i++)
        if (!strcmp(spu_test_argv[0], names[i]))
            lowest = i;
    REQUIRE(lowest >= 0);
    char expected[512] = "";
    static const char *const lines[] = {"tessera: debug 1\n", "tessera: info 2\n", "tessera: warn 3\n",
                                        "tessera: error 4 second line\n"};
    for (int i = lowest; i < 4; i++)
        strcat(expected, lines[i]);
    CHECK_STR(capture_stderr(emit_all_levels), expected);
    for (int i = 0; i < 4; i++)
        CHECK(tsr_log_enabled((tsr_log_level)i) == (i >= lowest));
}

static void test_error_values(void)
{
    tsr_error err;
    tsr_error_clear(&err);
    CHECK(err.code == TSR_OK && err.message[0] == '\0');
    CHECK(tsr_error_set(&err, TSR_ENOENT, "no %s\nhere", "file") == TSR_ENOENT);
    CHECK_STR(err.message, "no file here");
    CHECK(tsr_error_set(NULL, TSR_EIO, "ignored") == TSR_EIO);
    CHECK_STR(tsr_error_name(TSR_EPROTO), "EPROTO");
    CHECK_STR(tsr_error_name(12345), "EUNKNOWN");
    char long_value[1000];
    memset(long_value, 'x', sizeof long_value - 1);
    long_value[sizeof long_value - 1] = '\0';
    tsr_error_set(&err, TSR_EINVAL, "value '%s'", long_value);
    CHECK(strlen(err.message) == sizeof err.message - 1); /* truncated, terminated */
}

static const spu_test_case tests[] = {
    {"spu_log_level_filter", test_level_filter},
    {"spu_error_values", test_error_values},
};

SPU_TEST_MAIN(tests)
