/* spus/render/scissor.c — tiles and the scissor (docs/render.md, "Tiles"):
 * a tile server owns some rectangles of the window; render draws only
 * there by fitting the real GL scissor to the tiles' bounding rectangle,
 * while the application's own scissor (box, test, attribute stack,
 * display lists that change it) is recorded per context and is what
 * glGet and glIsEnabled answer. The tiles are the window's: while the
 * program has a framebuffer object of its own bound (appfbo.c), the real
 * scissor is the application's, since a wall renders such an FBO whole on
 * every server (docs/walls.md, "Framebuffer objects").
 *
 * Owns: the tiles, their bounds and generation, each context's scissor
 * record (render_scissor).
 *
 * Never: moves the application's viewport or projection (only the
 * scissor changes), lets a compiled display list capture a fitted
 * scissor, answers a query with the fitted values. */
#include <stdlib.h>

#include "tessera/log.h"

#include "instance.h"

/* --- tiles: the scissor ---------------------------------------------------- */

/* The scissor state of the context commands go to now. */
render_scissor *render_current_scissor(render_spu *r) { return r->shared ? &r->contexts[r->current].sc : &r->solo_sc; }

render_box render_box_intersect(render_box a, render_box b)
{
    long long x0 = a.x > b.x ? a.x : b.x, y0 = a.y > b.y ? a.y : b.y;
    long long x1 = (long long)a.x + a.w, y1 = (long long)a.y + a.h;
    long long bx1 = (long long)b.x + b.w, by1 = (long long)b.y + b.h;
    if (bx1 < x1)
        x1 = bx1;
    if (by1 < y1)
        y1 = by1;
    if (x1 <= x0 || y1 <= y0)
        return (render_box){0, 0, 0, 0};
    return (render_box){(int)x0, (int)y0, (int)(x1 - x0), (int)(y1 - y0)};
}

/* Whether the real scissor is fitted to tiles now: there are tiles and
 * the program draws into the window, not into a framebuffer object of its
 * own (its coordinates are the FBO's, which no tile divides). */
static bool tiled(render_spu *r) { return r->ntiles > 0 && !render_app_fb_bound(r); }

/* Real scissor := the application's own (inside a display list, whose
 * scissor commands GL runs unseen by us). */
static void scissor_set_raw(render_spu *r, const render_scissor *s)
{
    r->gl.Scissor(s->box.x, s->box.y, s->box.w, s->box.h);
    if (s->enabled)
        r->gl.Enable(GL_SCISSOR_TEST);
    else
        r->gl.Disable(GL_SCISSOR_TEST);
}

/* Sets the current context's real scissor: the application's when there
 * are no tiles; else always enabled, on the application's box (when its
 * test is enabled) intersected with the tiles' bounding rectangle. Not
 * while a list is compiled (it would be compiled too): EndList does it. */
static void scissor_apply(render_spu *r, render_scissor *s)
{
    if (s->list_mode)
        return;
    s->applied = r->tiles_gen;
    s->fitted = tiled(r);
    if (!s->fitted) {
        scissor_set_raw(r, s);
        return;
    }
    render_box e = s->enabled ? render_box_intersect(s->box, r->bounds) : r->bounds;
    r->gl.Enable(GL_SCISSOR_TEST);
    r->gl.Scissor(e.x, e.y, e.w, e.h);
}

/* Reads the application's scissor back from GL (below). */
static void scissor_sync(render_spu *r, render_scissor *s);

/* Catches up with tiles that changed while this context was not current,
 * and with a change of framebuffer (the window's tiles, or a program FBO
 * of none). Unfitted, display lists run unwatched (no cost per CallList),
 * so the record is read back from GL before it is fitted to tiles. */
void render_scissor_refresh(render_spu *r, render_scissor *s)
{
    if ((s->applied == r->tiles_gen && s->fitted == tiled(r)) || s->list_mode)
        return;
    if (!s->fitted && tiled(r))
        scissor_sync(r, s);
    scissor_apply(r, s);
}

/* Reads the application's scissor back from GL after GL ran commands we
 * did not see (a display list's), while the real state was the raw one. */
static void scissor_sync(render_spu *r, render_scissor *s)
{
    GLint box[4] = {0, 0, 0, 0}, depth = 0;
    r->gl.GetIntegerv(GL_SCISSOR_BOX, box);
    s->box = (render_box){box[0], box[1], box[2], box[3]};
    s->enabled = r->gl.IsEnabled(GL_SCISSOR_TEST) == GL_TRUE;
    /* A list may push or pop attributes: follow GL's depth. What a list
     * pushed is unknown here; it is recorded as saving no scissor state. */
    r->gl.GetIntegerv(GL_ATTRIB_STACK_DEPTH, &depth);
    if (depth > RENDER_ATTRIB_DEPTH)
        depth = RENDER_ATTRIB_DEPTH;
    while (s->depth > depth)
        s->depth--;
    while (s->depth < depth)
        s->stack[s->depth++] = (scissor_saved){.mask = 0};
}

/* --- tiles: ownership --------------------------------------------------------- */

/* Takes `tiles` (malloc'ed; ownership passes here; NULL/0 = the whole
 * window). The first tiles put the instance in shared mode (FBOs: OSMesa's
 * window buffer would be copied whole at every glFinish: docs/render.md,
 * "Memory"),
 * and renderbuffers allocated before any tiles are allocated again so the
 * pages outside the tiles are given back (their pixels are lost: tiles
 * come before the first frame). */
int render_set_tiles(render_spu *r, tsr_tile *tiles, size_t count, tsr_error *err)
{
    free(r->tiles);
    r->tiles = tiles;
    r->ntiles = count;
    r->tiles_gen++;
    if (count) {
        long long x0 = tiles[0].x, y0 = tiles[0].y, x1 = x0, y1 = y0;
        for (size_t i = 0; i < count; i++) {
            long long tx1 = (long long)tiles[i].x + tiles[i].width;
            long long ty1 = (long long)tiles[i].y + tiles[i].height;
            x0 = tiles[i].x < x0 ? tiles[i].x : x0;
            y0 = tiles[i].y < y0 ? tiles[i].y : y0;
            x1 = tx1 > x1 ? tx1 : x1;
            y1 = ty1 > y1 ? ty1 : y1;
        }
        r->bounds = (render_box){(int)x0, (int)y0, (int)(x1 - x0), (int)(y1 - y0)};
        if (!r->shared) {
            if (render_shared_enter(r, err) != TSR_OK)
                return err->code;
        } else if (!r->released) {
            int w = r->width, h = r->height;
            r->width = r->height = 0; /* force the allocation */
            if (render_shared_resize(r, w, h, err) != TSR_OK)
                return err->code;
        }
    }
    render_scissor_refresh(r, render_current_scissor(r));
    return TSR_OK;
}

static void render_TilesTSR(void *self, GLint window, GLsizei count, const GLint *rects)
{
    render_spu *r = self;
    if (window == r->window) {
        tsr_tile *tiles = NULL;
        const char *bad = NULL;
        GLsizei i = 0;
        if (count < 0 || (count > 0 && !rects))
            bad = "bad count";
        else if (count > 0 && !(tiles = calloc((size_t)count, sizeof *tiles)))
            bad = "out of memory";
        for (; !bad && i < count; i++) {
            const GLint *q = rects + 4 * i;
            if (q[0] < 0 || q[1] < 0 || q[2] < 1 || q[3] < 1 || q[0] >= TSR_TILES_MAX_SIDE ||
                q[1] >= TSR_TILES_MAX_SIDE || q[2] > TSR_TILES_MAX_SIDE || q[3] > TSR_TILES_MAX_SIDE)
                bad = "x, y must be 0..16383 and width, height 1..16384";
            else
                tiles[i] = (tsr_tile){.x = q[0], .y = q[1], .width = q[2], .height = q[3]};
        }
        tsr_error err = {0};
        if (bad) {
            free(tiles);
            if (i > 0)
                tsr_log(TSR_LOG_ERROR, "%s: TilesTSR(%d, %d): rectangle %d [%d, %d, %d, %d]: %s, ignored", r->name,
                        (int)window, (int)count, (int)i - 1, rects[4 * (i - 1)], rects[4 * (i - 1) + 1],
                        rects[4 * (i - 1) + 2], rects[4 * (i - 1) + 3], bad);
            else
                tsr_log(TSR_LOG_ERROR, "%s: TilesTSR(%d, %d): %s, ignored", r->name, (int)window, (int)count, bad);
        } else if (render_set_tiles(r, tiles, (size_t)count, &err) != TSR_OK) {
            tsr_log(TSR_LOG_ERROR, "%s: TilesTSR: %s", r->name, err.message);
        }
    }
    tsr_call_TilesTSR(r->child, window, count, rects);
}

/* --- the commands this SPU implements itself ------------------------------ */

/* The scissor commands (docs/render.md, "Tiles"): the application's state
 * is recorded, the real one is fitted to the tiles. */
void render_Scissor(void *self, GLint x, GLint y, GLsizei width, GLsizei height)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    /* Compiled into a list, or an error GL reports and ignores. */
    if (s->list_mode || width < 0 || height < 0) {
        r->gl.Scissor(x, y, width, height);
        return;
    }
    s->box = (render_box){x, y, width, height};
    if (tiled(r))
        scissor_apply(r, s);
    else
        r->gl.Scissor(x, y, width, height);
}

static void enable_cap(render_spu *r, GLenum cap, bool on)
{
    render_scissor *s = render_current_scissor(r);
    if (cap == GL_STENCIL_TEST && on)
        r->stencil_written = true; /* (also when compiled into a list: it may run) */
    if (cap != GL_SCISSOR_TEST || s->list_mode || !tiled(r)) {
        if (on)
            r->gl.Enable(cap);
        else
            r->gl.Disable(cap);
        if (cap == GL_SCISSOR_TEST && !s->list_mode)
            s->enabled = on;
        return;
    }
    s->enabled = on;
    scissor_apply(r, s);
}

static void render_Enable(void *self, GLenum cap) { enable_cap(self, cap, true); }
static void render_Disable(void *self, GLenum cap) { enable_cap(self, cap, false); }

static void render_PushAttrib(void *self, GLbitfield mask)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    r->gl.PushAttrib(mask);
    /* GL refuses a push beyond its depth (stack overflow) and so do we. */
    if (!s->list_mode && s->depth < r->max_attrib_depth)
        s->stack[s->depth++] = (scissor_saved){mask, s->box, s->enabled};
}

static void render_PopAttrib(void *self)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    r->gl.PopAttrib();
    if (s->list_mode || s->depth == 0)
        return;
    scissor_saved e = s->stack[--s->depth];
    if (e.mask & GL_SCISSOR_BIT) {
        s->box = e.box;
        s->enabled = e.enabled;
    } else if (e.mask & GL_ENABLE_BIT) {
        s->enabled = e.enabled;
    }
    /* GL restored what the real scissor was at the push, perhaps fitted
     * to other tiles: set it again. */
    if (e.mask & (GL_SCISSOR_BIT | GL_ENABLE_BIT))
        scissor_apply(r, s);
}

/* Display lists run scissor commands inside GL where we cannot see them:
 * run them on the application's own scissor and read it back after. */
static void before_list(render_spu *r, render_scissor *s)
{
    if (s->fitted)
        scissor_set_raw(r, s);
}

static void after_list(render_spu *r, render_scissor *s)
{
    scissor_sync(r, s);
    if (tiled(r) || s->applied != r->tiles_gen)
        scissor_apply(r, s);
}

/* Between glBegin and glEnd a list can hold only what GL takes there
 * (vertices, attributes, lists of those): no scissor command, and none of
 * before_list's and after_list's (each would be GL_INVALID_OPERATION:
 * piglit's gl-1.0-dlist-beginend calls a list of vertices inside glBegin). */
static void render_Begin(void *self, GLenum mode)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    if (s->list_mode != GL_COMPILE)
        s->in_begin = true;
    r->gl.Begin(mode);
}

static void render_End(void *self)
{
    render_spu *r = self;
    render_current_scissor(r)->in_begin = false;
    r->gl.End();
}

static void render_CallList(void *self, GLuint list)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    if (s->list_mode || !s->fitted || s->in_begin) {
        r->gl.CallList(list);
        return;
    }
    before_list(r, s);
    r->gl.CallList(list);
    after_list(r, s);
}

static void render_CallLists(void *self, GLsizei n, GLenum type, const void *lists)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    if (s->list_mode || !s->fitted || s->in_begin) {
        r->gl.CallLists(n, type, lists);
        return;
    }
    before_list(r, s);
    r->gl.CallLists(n, type, lists);
    after_list(r, s);
}

static void render_NewList(void *self, GLuint list, GLenum mode)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    bool execute = mode == GL_COMPILE_AND_EXECUTE;
    if (s->list_mode) {
        r->gl.NewList(list, mode); /* GL's error: already compiling */
        return;
    }
    if (execute)
        before_list(r, s);
    r->gl.NewList(list, mode);
    GLint index = 0;
    r->gl.GetIntegerv(GL_LIST_INDEX, &index);
    if (list != 0 && (GLuint)index == list && (mode == GL_COMPILE || execute))
        s->list_mode = mode;
    else if (execute && s->fitted)
        scissor_apply(r, s); /* NewList failed: back to the fitted scissor */
}

static void render_EndList(void *self)
{
    render_spu *r = self;
    render_scissor *s = render_current_scissor(r);
    r->gl.EndList();
    GLenum mode = s->list_mode;
    s->list_mode = 0;
    if (mode == GL_COMPILE_AND_EXECUTE)
        after_list(r, s);
    else if (mode)
        render_scissor_refresh(r, s);
}

/* glGet of the scissor: the application's values, not the fitted ones
 * (inside a compile-and-execute list the real state is the application's). */
static bool scissor_query(render_spu *r, GLenum pname, double out[4], int *n)
{
    GLint buffer;
    if (render_app_fb_query(r, pname, &buffer) ||  /* appfbo.c: the program's framebuffer names */
        render_buffers_query(r, pname, &buffer)) { /* buffers.c: the window's buffer names */
        out[0] = buffer;
        *n = 1;
        return true;
    }
    render_scissor *s = render_current_scissor(r);
    if (!s->fitted || s->list_mode == GL_COMPILE_AND_EXECUTE)
        return false; /* the real state is the application's */
    if (pname == GL_SCISSOR_BOX) {
        out[0] = s->box.x;
        out[1] = s->box.y;
        out[2] = s->box.w;
        out[3] = s->box.h;
        *n = 4;
        return true;
    }
    if (pname == GL_SCISSOR_TEST) {
        out[0] = s->enabled;
        *n = 1;
        return true;
    }
    return false;
}

static void render_GetIntegerv(void *self, GLenum pname, GLint *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetIntegerv(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = (GLint)v[i];
}

static void render_GetFloatv(void *self, GLenum pname, GLfloat *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetFloatv(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = (GLfloat)v[i];
}

static void render_GetDoublev(void *self, GLenum pname, GLdouble *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetDoublev(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = v[i];
}

static void render_GetBooleanv(void *self, GLenum pname, GLboolean *data)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (!scissor_query(r, pname, v, &n)) {
        r->gl.GetBooleanv(pname, data);
        return;
    }
    for (int i = 0; i < n; i++)
        data[i] = v[i] != 0.0 ? GL_TRUE : GL_FALSE;
}

static GLboolean render_IsEnabled(void *self, GLenum cap)
{
    render_spu *r = self;
    double v[4];
    int n;
    if (cap == GL_SCISSOR_TEST && scissor_query(r, cap, v, &n))
        return v[0] != 0.0 ? GL_TRUE : GL_FALSE;
    return r->gl.IsEnabled(cap);
}

void render_scissor_install(render_spu *r, tsr_dispatch *table)
{
    tsr_set_TilesTSR(table, render_TilesTSR, r);
    tsr_set_Scissor(table, render_Scissor, r);
    tsr_set_Enable(table, render_Enable, r);
    tsr_set_Disable(table, render_Disable, r);
    tsr_set_PushAttrib(table, render_PushAttrib, r);
    tsr_set_PopAttrib(table, render_PopAttrib, r);
    tsr_set_Begin(table, render_Begin, r);
    tsr_set_End(table, render_End, r);
    tsr_set_CallList(table, render_CallList, r);
    tsr_set_CallLists(table, render_CallLists, r);
    tsr_set_NewList(table, render_NewList, r);
    tsr_set_EndList(table, render_EndList, r);
    tsr_set_GetIntegerv(table, render_GetIntegerv, r);
    tsr_set_GetFloatv(table, render_GetFloatv, r);
    tsr_set_GetDoublev(table, render_GetDoublev, r);
    tsr_set_GetBooleanv(table, render_GetBooleanv, r);
    tsr_set_IsEnabled(table, render_IsEnabled, r);
}
