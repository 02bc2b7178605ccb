/* spus/tilesort/queries.c — occlusion queries on a wall. Each server
 * counts the samples that pass in its own tiles (drawing is scissored to
 * them, tessera/dev/protocol.h TilesTSR), and the tiles do not overlap, so
 * the window's count is the sum of the servers' counts; a result is
 * available when every server has it. Drawing into a program FBO is not
 * divided (fbo.c: every server draws all of it), so a query that counted
 * while an FBO was bound for drawing is answered by the first live server
 * alone (piglit's occlusion-query-discard under -fbo, where piglit draws
 * into an FBO of its own once GL_ARB_framebuffer_object is offered, summed
 * four servers' counts on the 2x2 wall). A query that counted both in the
 * window and in an FBO is answered so too, which is not exact (its window
 * part is then the first server's tiles' only). glBeginQuery/glEndQuery
 * and the object commands reach every server (untracked state:
 * tilesort.c's broadcast route, kept: this file only watches them);
 * glGenQueries and glIsQuery are answered by the first live server.
 *
 * Owns the instance's query_active and fbo_queries. Never answers before
 * the geometry drawn inside the query has reached the servers it
 * touches. */
#include <stdlib.h>

#include "instance.h"

static int counted_in_fbo(const tilesort *t, GLuint id)
{
    for (size_t i = 0; i < t->nfbo_queries; i++)
        if (t->fbo_queries[i] == id)
            return 1;
    return 0;
}

static void forget(tilesort *t, GLuint id)
{
    for (size_t i = 0; i < t->nfbo_queries; i++)
        if (t->fbo_queries[i] == id)
            t->fbo_queries[i--] = t->fbo_queries[--t->nfbo_queries];
}

/* The active query counts drawing every server makes whole. */
void ts_queries_fbo_bound(tilesort *t)
{
    if (!t->query_active || counted_in_fbo(t, t->query_active))
        return;
    if (t->nfbo_queries == t->fbo_queries_cap) {
        size_t cap = t->fbo_queries_cap ? 2 * t->fbo_queries_cap : 8;
        GLuint *p = realloc(t->fbo_queries, cap * sizeof *p);
        if (!p)
            return; /* then summed, as before */
        t->fbo_queries = p;
        t->fbo_queries_cap = cap;
    }
    t->fbo_queries[t->nfbo_queries++] = t->query_active;
}

static void query_begun(void *self, GLenum target, GLuint id)
{
    tilesort *t = self;
    if (target != GL_SAMPLES_PASSED)
        return;
    forget(t, id);
    t->query_active = id;
    if (t->app_fb)
        ts_queries_fbo_bound(t);
}

static void query_ended(void *self, GLenum target)
{
    tilesort *t = self;
    if (target == GL_SAMPLES_PASSED)
        t->query_active = 0;
}

/* glBeginQuery and glEndQuery keep their route and are watched after it. */
void ts_queries_install(tilesort *t)
{
    int begin = tsr_dispatch_slot("BeginQuery"), end = tsr_dispatch_slot("EndQuery");
    t->query_tees[0] = (tsr_tee){.first = t->normal.slots[begin], .second = {(tsr_proc)query_begun, t}};
    t->query_tees[1] = (tsr_tee){.first = t->normal.slots[end], .second = {(tsr_proc)query_ended, t}};
    tsr_dispatch_tee(&t->normal, begin, &t->query_tees[0]);
    tsr_dispatch_tee(&t->normal, end, &t->query_tees[1]);
}

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
    int first_only = pname == GL_QUERY_RESULT && counted_in_fbo(t, id);
    for (size_t i = 0; i < t->nservers; i++) {
        if (tsr_stream_client_server_failed(t->client, i) || (first_only && &t->srv[i] != first))
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
