/* core/wire/pack_draws.c — glDrawRangeElements, glMultiDrawArrays and
 * glMultiDrawElements for a packer: each is sent as the glDrawElements or
 * the sequence of glDrawArrays/glDrawElements GL defines it to be (GL 2.1
 * section 2.8), in the same buffer, so a receiver needs nothing new and
 * a display list being compiled keeps the arrays' values of that time.
 * Their opcodes never travel: the unpacker refuses them (here too).
 *
 * Owns nothing. Never sends part of a call GL refuses: its error is
 * checked first, as Mesa checks it, and becomes the packer's local error
 * (glGetError answers it before the receiver's). */
#include <GL/gl.h>
#include <GL/glext.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/wire.h"
#include "wire_gen.h"
#include "wire_internal.h"

/* Modes a compatibility context of Mesa takes (GL_POINTS .. GL_POLYGON,
 * the adjacency modes, GL_PATCHES); the receiver's GL judges the rest. */
static int mode_known(GLenum mode) { return mode <= GL_PATCHES; }

static int index_type_known(GLenum type)
{
    return type == GL_UNSIGNED_BYTE || type == GL_UNSIGNED_SHORT || type == GL_UNSIGNED_INT;
}

static int refuse(tsr_packer *p, GLenum error)
{
    tsr_packer_local_error(p, error);
    return -1;
}

int tsr_packer_check_DrawRangeElements(tsr_packer *p, GLenum mode, GLuint start, GLuint end, GLsizei count, GLenum type)
{
    if (end < start || count < 0)
        return refuse(p, GL_INVALID_VALUE);
    if (!mode_known(mode) || !index_type_known(type))
        return refuse(p, GL_INVALID_ENUM);
    return 0;
}

int tsr_packer_check_MultiDraw(tsr_packer *p, GLenum mode, const GLsizei *count, GLenum type, GLsizei drawcount)
{
    if (drawcount < 0)
        return refuse(p, GL_INVALID_VALUE);
    if (!mode_known(mode) || (type && !index_type_known(type)))
        return refuse(p, GL_INVALID_ENUM);
    for (GLsizei i = 0; i < drawcount; i++)
        if (count[i] < 0)
            return refuse(p, GL_INVALID_VALUE);
    return 0;
}

/* The range only promises which indices the draw reads: the indices
 * themselves still decide what is sent (pack.c's DrawElements). */
void tsr_packer_custom_DrawRangeElements(tsr_packer *p, GLenum mode, GLuint start, GLuint end, GLsizei count,
                                         GLenum type, const void *indices)
{
    if (tsr_packer_check_DrawRangeElements(p, mode, start, end, count, type) == 0)
        tsr_packer_custom_DrawElements(p, mode, count, type, indices);
}

void tsr_packer_custom_MultiDrawArrays(tsr_packer *p, GLenum mode, const GLint *first, const GLsizei *count,
                                       GLsizei drawcount)
{
    if (tsr_packer_check_MultiDraw(p, mode, count, 0, drawcount) != 0)
        return;
    for (GLsizei i = 0; i < drawcount; i++)
        if (count[i] > 0)
            tsr_packer_custom_DrawArrays(p, mode, first[i], count[i]);
}

void tsr_packer_custom_MultiDrawElements(tsr_packer *p, GLenum mode, const GLsizei *count, GLenum type,
                                         const void *const *indices, GLsizei drawcount)
{
    if (tsr_packer_check_MultiDraw(p, mode, count, type, drawcount) != 0)
        return;
    for (GLsizei i = 0; i < drawcount; i++)
        if (count[i] > 0)
            tsr_packer_custom_DrawElements(p, mode, count[i], type, indices[i]);
}

static int never_sent(const char *name, size_t pos, tsr_error *err)
{
    return tsr_error_set(err, TSR_EPROTO,
                         "command %s at data offset %zu: never sent (a packer sends the DrawElements or "
                         "DrawArrays it stands for)",
                         name, pos);
}

int tsr_unpack_custom_DrawRangeElements(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                        size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("DrawRangeElements", *pos, err);
}

int tsr_unpack_custom_MultiDrawArrays(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                      size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("MultiDrawArrays", *pos, err);
}

int tsr_unpack_custom_MultiDrawElements(struct tsr_unpacker *u, const tsr_dispatch *d, const uint8_t *b, size_t len,
                                        size_t *pos, tsr_error *err)
{
    (void)u, (void)d, (void)b, (void)len;
    return never_sent("MultiDrawElements", *pos, err);
}
