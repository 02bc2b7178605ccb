/* tests/node/text_sanitize_test.c — tsr_text_sanitize, the one function
 * every place that prints a peer's text goes through (issue 10, defect
 * 10): control bytes, C1 controls and invalid UTF-8 become \xNN, valid
 * UTF-8 stays, the output is always terminated and cut at a whole escape. */
#include <string.h>

#include "harness.h"
#include "tessera/dev/util.h"

static const char *safe(const char *in, size_t len)
{
    static char out[256];
    tsr_text_sanitize(out, sizeof out, in, len);
    return out;
}

#define SAFE(s) safe(s, sizeof s - 1)

int main(void)
{
    CHECK_STR(SAFE("\x1b[2J\x07pwned"), "\\x1b[2J\\x07pwned");
    CHECK_STR(SAFE("a\nb\rc\td\x7f"), "a\\x0ab\\x0dc\\x09d\\x7f");
    CHECK_STR(SAFE("caf\xc3\xa9 \xe6\x97\xa5 \xf0\x9f\x98\x80"), "caf\xc3\xa9 \xe6\x97\xa5 \xf0\x9f\x98\x80");
    CHECK_STR(SAFE("\xc2\x9b"
                   "31m"),
              "\\xc2\\x9b31m");                                                    /* C1 CSI */
    CHECK_STR(SAFE("\xff\xc0\xaf\xed\xa0\x80"), "\\xff\\xc0\\xaf\\xed\\xa0\\x80"); /* bad, overlong, surrogate */
    CHECK_STR(SAFE("\xe6\x97"), "\\xe6\\x97");                                     /* cut sequence */
    CHECK_STR(safe("a\0b", 3), "a\\x00b");
    CHECK_STR(safe("back\\slash", 10), "back\\slash");
    char small[6];
    CHECK(tsr_text_sanitize(small, sizeof small,
                            "ab\x1b"
                            "cd",
                            5) == 2 &&
              !strcmp(small, "ab"),
          "cut inside an escape: '%s'", small);
    CHECK(tsr_text_sanitize(small, sizeof small, NULL, 0) == 0 && small[0] == '\0');
    return harness_failures ? 1 : 0;
}
