/* core/util/text.c — text from a peer made safe to print (tessera/dev/util.h):
 * a server's ERROR reason, a node's DONE message, names from a handshake
 * or a JOIN reach terminals and logs, where ESC, BEL or a C1 control would
 * be acted on (clear the screen, retitle the window, ring). Every byte a
 * terminal could act on, and every byte that is not valid UTF-8, becomes a
 * visible escape; valid UTF-8 text is kept as it is. Owns nothing; never
 * allocates. */
#include "tessera/dev/util.h"

#include <stdint.h>
#include <stdio.h>

/* Length of the valid UTF-8 sequence at p (at most `left` bytes), or 0:
 * shortest form only, no surrogates, nothing above U+10FFFF. */
static size_t utf8_length(const unsigned char *p, size_t left)
{
    unsigned char c = p[0];
    size_t n;
    uint32_t cp;
    if (c >= 0xc2 && c <= 0xdf) {
        n = 2;
        cp = c & 0x1fu;
    } else if (c >= 0xe0 && c <= 0xef) {
        n = 3;
        cp = c & 0x0fu;
    } else if (c >= 0xf0 && c <= 0xf4) {
        n = 4;
        cp = c & 0x07u;
    } else {
        return 0;
    }
    if (left < n)
        return 0;
    for (size_t i = 1; i < n; i++) {
        if ((p[i] & 0xc0) != 0x80)
            return 0;
        cp = (cp << 6) | (p[i] & 0x3fu);
    }
    if ((n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10ffff)) || (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    /* C1 controls (U+0080..U+009F): some terminals act on them too. */
    if (cp >= 0x80 && cp <= 0x9f)
        return 0;
    return n;
}

size_t tsr_text_sanitize(char *out, size_t size, const void *in, size_t len)
{
    if (!size)
        return 0;
    const unsigned char *p = in;
    size_t used = 0;
    for (size_t i = 0; p && i < len;) {
        unsigned char c = p[i];
        size_t n = c >= 0x20 && c < 0x7f ? 1 : c >= 0x80 ? utf8_length(p + i, len - i) : 0;
        if (n) {
            if (used + n >= size)
                break;
            for (size_t k = 0; k < n; k++)
                out[used++] = (char)p[i + k];
            i += n;
            continue;
        }
        /* A control byte, DEL, or a byte of no valid sequence: \xNN
         * (a C1 control's two bytes become two escapes). */
        if (used + 4 >= size)
            break;
        snprintf(out + used, 5, "\\x%02x", c);
        used += 4;
        i++;
    }
    out[used] = '\0';
    return used;
}
