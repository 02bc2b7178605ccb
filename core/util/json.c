/* core/util/json.c — the one JSON string writer (tessera/dev/util.h), for
 * statistics files: quotes, backslashes and control bytes escaped, other
 * bytes (UTF-8 included) copied. Owns nothing; never allocates. */
#include "tessera/dev/util.h"

void tsr_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}
