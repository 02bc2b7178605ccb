/* spus/tilesort/queries.c — occlusion queries on a wall. Each server
 * counts the samples that pass in its own tiles (drawing is scissored to
 * them, tessera/dev/protocol.h TilesTSR), and the tiles do not overlap, so
 * the window's count is the sum of the servers' counts; a result is
 * available when every server has it. glBeginQuery/glEndQuery and the
 * object commands reach every server (untracked state: tilesort.c's
 * broadcast route); glGenQueries and glIsQuery are answered by the first
 * live server.
 *
 * Owns nothing. Never answers before the geometry drawn inside the query
 * has reached the servers it touches. */
#include "instance.h"

/* The sum (GL_QUERY_RESULT) or the conjunction (GL_QUERY_RESULT_AVAILABLE)
 * of every live server's answer; other pnames: the first live server's. */
static GLuint merged(tilesort *t, GLuint id, GLenum pname)
{
    ts_server *first = ts_to_server(t); /* flushes the geometry */
    if (pname != GL_QUERY_RESULT && pname != GL_QUERY_RESULT_AVAILABLE) {
        GLuint v = 0;
        tsr_call_GetQueryObjectuiv(&first->table, id, pname, &v);
        return v;
    }
    GLuint sum = 0, available = 1;
    for (size_t i = 0; i < t->nservers; i++) {
        if (tsr_stream_client_server_failed(t->client, i))
            continue;
        ts_server *s = &t->srv[i];
        ts_prepare_server(t, s, 0);
        GLuint v = 0;
        tsr_call_GetQueryObjectuiv(&s->table, id, pname, &v);
        sum += v;
        available = available && v;
    }
    return pname == GL_QUERY_RESULT ? sum : available;
}

void ts_GetQueryObjectuiv(void *self, GLuint id, GLenum pname, GLuint *params)
{
    if (params)
        *params = merged(self, id, pname);
}

void ts_GetQueryObjectiv(void *self, GLuint id, GLenum pname, GLint *params)
{
    if (params) {
        GLuint v = merged(self, id, pname);
        *params = v > 0x7fffffffu ? 0x7fffffff : (GLint)v; /* GL clamps the signed form */
    }
}
