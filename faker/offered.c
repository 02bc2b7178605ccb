/* faker/offered.c — the GL_EXTENSIONS string one stream's chain offers:
 * the generated list (tsr_faker_gl_extensions), less the extensions whose
 * commands some SPU of the chain does not carry yet.
 *
 * The framebuffer object extensions (`fbo_exts`): render draws a
 * program's framebuffer objects and blits (spus/render/appfbo.c); pack,
 * capture and the SPUs that only pass commands on carry them to one, and
 * a tilesort wall renders them whole on every server and gathers a blit's
 * source from the window's tiles (spus/tilesort/fbo.c, blit.c). A chain
 * with any SPU outside `carries_fbo` (one that would route an FBO's
 * drawing by the window, or drop its commands) offers none of them.
 *
 * Owns: the two strings (made once). Never: offers an extension the
 * generated list lacks. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "faker_gl.h"

static const char *const carries_fbo[] = {"render", "pack", "capture", "tilesort", "passthrough", "print", "loopback"};

static const char *const fbo_exts[] = {"GL_EXT_framebuffer_object", "GL_ARB_framebuffer_object",
                                       "GL_EXT_framebuffer_blit", "GL_EXT_framebuffer_multisample"};

static bool is_fbo_ext(const char *name, size_t len)
{
    for (size_t i = 0; i < sizeof fbo_exts / sizeof fbo_exts[0]; i++)
        if (strlen(fbo_exts[i]) == len && !strncmp(fbo_exts[i], name, len))
            return true;
    return false;
}

/* Whether every SPU of chain text `text` ("a k=v ! b ! c") is one of
 * carries_fbo. */
static bool chain_carries_fbo(const char *text)
{
    for (const char *p = text; *p;) {
        while (*p == ' ' || *p == '\t' || *p == '!')
            p++;
        if (!*p)
            break;
        size_t n = strcspn(p, " \t!");
        bool known = false;
        for (size_t i = 0; i < sizeof carries_fbo / sizeof carries_fbo[0]; i++)
            if (strlen(carries_fbo[i]) == n && !strncmp(carries_fbo[i], p, n))
                known = true;
        if (!known)
            return false;
        /* skip the options, quoted values included, to the next '!' */
        for (bool quoted = false; *p && (quoted || *p != '!'); p++) {
            if (*p == '\\' && quoted && p[1])
                p++;
            else if (*p == '"')
                quoted = !quoted;
        }
    }
    return true;
}

const char *tsr_faker_offered_extensions(const char *chain_text)
{
    static char *without_fbo; /* made once, kept for the process */
    if (chain_carries_fbo(chain_text))
        return tsr_faker_gl_extensions;
    if (!without_fbo) {
        const char *all = tsr_faker_gl_extensions;
        char *s = malloc(strlen(all) + 1);
        if (!s)
            return "";
        size_t n = 0;
        for (const char *p = all; *p;) {
            size_t len = strcspn(p, " ");
            if (!is_fbo_ext(p, len)) {
                memcpy(s + n, p, len);
                n += len;
                s[n++] = ' ';
            }
            p += len;
            while (*p == ' ')
                p++;
        }
        s[n] = '\0';
        without_fbo = s;
    }
    return without_fbo;
}
