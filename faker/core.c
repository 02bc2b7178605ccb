/* faker/core.c — the faker's contexts, surfaces and current state (see
 * faker_gl.h). SPU chains are made from $TESSERA_CHAIN (default "render"),
 * one per *stream*: every application context is a tessera context of one
 * stream (ContextCreateTSR at its first MakeCurrent), every surface a
 * tessera window of each stream that draws into it (WindowCreateTSR with
 * the drawable's size, read over the faker's own xcb connection, which
 * also selects StructureNotify on the window for itself; the
 * ConfigureNotify events that have arrived are read without a round trip
 * at every glViewport, swap and MakeCurrent — a glViewport of another size
 * than the window's also asks the server, at most once a frame, in case
 * that event is still on its way — and a new size becomes WindowSizeTSR).
 * A context's table is its stream's chain head's with glGetString answered
 * here (renderer naming tessera, version 2.1, the spec's extensions).
 *
 * Threads (docs/architecture.md, "The faker"): a chain is driven by one
 * thread at a time. A context joins a stream at its first MakeCurrent:
 * its share list's stream, else the first stream no other thread has a
 * context current on (so a program with one drawing thread has exactly
 * one stream, as before), else a new one. Two threads drawing at once
 * into contexts that share nothing therefore draw into two chains, each
 * with its own renderer, framebuffer and windows, with no lock on the
 * call path. Contexts of one share group are one stream whatever thread
 * draws (their objects live in that stream's renderer): when two threads
 * use it at once the stream becomes *shared* and its contexts call
 * through their locked tables, every slot hooked to hold the faker's
 * lock around the call and to send this thread's MakeCurrentTSR first
 * when another thread's call came last, so the chain sees one stream of
 * whole calls in the order they were made, as a server sees several
 * clients' contexts. A thread still calling its plain table when another
 * thread's MakeCurrent makes the stream shared moves to the locked one at
 * its next check point (glClear, glFlush, glFinish, glViewport, a swap or
 * a MakeCurrent); the MakeCurrent waits for that, at most
 * FAKER_SWITCH_WAIT_MS, and fails (one log line) if it does not come. */
#include <errno.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <xcb/xcb.h>

#include "faker_gl.h"
#include "tessera/chain.h"
#include "tessera/dev/native.h"
#include "tessera/glapi.h"
#include "tessera/image.h"
#include "tessera/log.h"

#ifndef TESSERA_VERSION
#define TESSERA_VERSION "0"
#endif

/* One stream: a chain and what was sent into it. */
typedef struct faker_stream {
    int number; /* from 0; "{stream}" in the chain text */
    tsr_chain *chain;
    const char *extensions; /* GL_EXTENSIONS of its chain (offered.c) */
    int next_window_id;     /* tessera window ids of this stream, from 0 */
    int current_threads;    /* threads with a context of it current */
    /* Several threads call in at once (contexts of one share group, or a
     * context made current while another thread draws into the stream):
     * every context of the stream then calls through its locked table.
     * Set once, never cleared; read without the lock by the check points. */
    bool shared;
    int direct_threads;          /* threads whose current context of it calls its plain table */
    int chain_ctx, chain_window; /* what the chain was last made current to (chain_ctx 0: unknown) */
    struct faker_stream *next;
} faker_stream;

/* A surface as one stream knows it. */
typedef struct faker_window {
    faker_stream *stream;
    int window;        /* tessera window id in that stream */
    int width, height; /* what that stream was told */
} faker_window;

#define FAKER_SURFACE_STREAMS 8
#define FAKER_SWITCH_WAIT_MS 3000

/* Contexts made with each other as share lists: one stream for all. */
typedef struct faker_group {
    faker_stream *stream; /* NULL until one of them is first made current */
    int refs;
} faker_group;

struct tsr_faker_context {
    int id;               /* tessera context id, from 1 */
    faker_stream *stream; /* NULL until its first MakeCurrent */
    faker_group *group;   /* its share group (refcounted) */
    bool on_stream;       /* ContextCreateTSR was sent */
    bool destroy_pending; /* destroyed while current somewhere */
    int current_on;       /* threads it is current on (0 or 1) */
    tsr_dispatch table;   /* its stream's chain head's, GetString answered here */
    /* `table` with every slot hooked by the faker's lock (and the
     * MakeCurrentTSR of this thread's context and window when another
     * thread's call came last): what a shared stream's threads call. */
    tsr_dispatch locked;
    tsr_hook *hooks;    /* TSR_DISPATCH_COUNT, made with `locked` */
    bool locked_now;    /* its thread calls `locked` (once set, for good) */
    char renderer[256]; /* "tessera (downstream renderer)" */
    tsr_faker_context *next;
};

struct tsr_faker_surface {
    unsigned long xid;                      /* X drawable, 0: pbuffer */
    int width, height;                      /* its size when made (pbuffers keep it) */
    int x_width, x_height;                  /* the X window's, from ConfigureNotify */
    bool asked;                             /* its size was asked this frame (glViewport) */
    bool double_buffered;                   /* its config is (tsr_faker_surface_set_config) */
    int samples;                            /* its config's (0: single-sampled) */
    faker_window on[FAKER_SURFACE_STREAMS]; /* the streams it is a window of */
    int non;
    tsr_faker_surface *next;
};

/* Recursive: a shared stream's hooked call holds it while the faker's own
 * entries of the table (glViewport, glNewList) take it again. */
static pthread_mutex_t lock = PTHREAD_RECURSIVE_MUTEX_INITIALIZER_NP;
static pthread_cond_t switched = PTHREAD_COND_INITIALIZER; /* a thread left its plain table */
static faker_stream *streams;                              /* newest first */
static int nstreams;
static bool chain_failed;
static pid_t chain_pid; /* the process that made the chain (chain_at_exit) */
static int next_context_id = 1;
static tsr_faker_context *contexts;
static tsr_faker_surface *surfaces;
static xcb_connection_t *xconn;
static char xconn_name[256];

static _Thread_local tsr_faker_context *cur_ctx;
static _Thread_local tsr_faker_surface *cur_surface;
static _Thread_local faker_window *cur_window; /* cur_surface in cur_ctx's stream */
static _Thread_local bool refused_busy;        /* the last MakeCurrent failed so */

void tsr_faker_log(int level, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    tsr_log((tsr_log_level)level, "faker: %s", msg);
}

void tsr_faker_unsupported(const char *name)
{
    tsr_faker_log(TSR_LOG_WARN, "%s is not supported by tessera: ignored (logged once)", name);
}

void (*tsr_faker_lookup(const tsr_faker_proc *table, size_t n, const char *name))(void)
{
    if (!name)
        return NULL;
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = (lo + hi) / 2;
        int c = strcmp(table[mid].name, name);
        if (c == 0)
            return table[mid].proc;
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return NULL;
}

void (*tsr_faker_gl_proc(const char *name))(void)
{
    return tsr_faker_lookup(tsr_faker_gl_procs, tsr_faker_gl_proc_count, name);
}

/* --- chain --------------------------------------------------------------- */

/* A program that returns from main or calls exit() ends its stream as a
 * tessera program does: the chain is destroyed (network SPUs send FINISH
 * and wait until their servers drew every buffer), so a graph run sees the
 * application end cleanly instead of a dropped connection. An atexit
 * handler made with the chain, not a destructor: it runs before the
 * libraries' destructors (the SPUs' OSMesa must still be there). */
static void chain_at_exit(void)
{
    /* A forked child that calls exit() (xscreensaver's hacks fork to exec
     * xscreensaver-getimage and exit(1) when it is not installed) shares
     * the parent's sockets and capture files: ending the chain there would
     * send on the parent's connections (the server then counts credits
     * that were never granted) and finish its capture file. The chain is
     * the parent's; the child leaves it alone. */
    if (getpid() != chain_pid)
        return;
    pthread_mutex_lock(&lock);
    faker_stream *list = streams;
    streams = NULL;
    pthread_mutex_unlock(&lock);
    tsr_gl_make_current(NULL);
    while (list) {
        faker_stream *next = list->next;
        tsr_chain_destroy(list->chain);
        free(list);
        list = next;
    }
}

/* The chain text of stream `number`: $TESSERA_CHAIN with every "{stream}"
 * replaced by the number, so the streams of a program with several
 * drawing threads can write their own files. */
static void chain_text(int number, char *out, size_t size)
{
    const char *text = getenv("TESSERA_CHAIN");
    if (!text || !text[0])
        text = "render";
    size_t n = 0;
    for (const char *p = text; *p && n + 1 < size;) {
        if (!strncmp(p, "{stream}", 8)) {
            int w = snprintf(out + n, size - n, "%d", number);
            n = w < 0 || (size_t)w >= size - n ? size - 1 : n + (size_t)w;
            p += 8;
        } else {
            out[n++] = *p++;
        }
    }
    out[n] = '\0';
}

/* A new stream (its chain made now); NULL when the chain cannot be made
 * (logged once; every later context fails too). */
static faker_stream *stream_new_locked(void)
{
    if (chain_failed)
        return NULL;
    char text[4096];
    chain_text(nstreams, text, sizeof text);
    faker_stream *st = calloc(1, sizeof *st);
    tsr_error err = {0};
    tsr_chain *c = st ? tsr_chain_create(text, &err) : NULL;
    if (!c) {
        chain_failed = true;
        tsr_faker_log(TSR_LOG_ERROR, "cannot make the SPU chain \"%s\": %s", text, st ? err.message : "out of memory");
        free(st);
        return NULL;
    }
    if (!streams) {
        chain_pid = getpid();
        atexit(chain_at_exit);
    }
    st->number = nstreams++;
    st->chain = c;
    st->extensions = tsr_faker_offered_extensions(text);
    st->next = streams;
    streams = st;
    if (st->number == 0)
        tsr_faker_log(TSR_LOG_INFO, "SPU chain \"%s\"", text);
    else
        tsr_faker_log(TSR_LOG_INFO, "SPU chain \"%s\" for stream %d (another thread draws at the same time)", text,
                      st->number);
    if (st->number == 1 && !strstr(getenv("TESSERA_CHAIN") ? getenv("TESSERA_CHAIN") : "", "{stream}"))
        tsr_faker_log(TSR_LOG_WARN, "the chain text has no {stream}: the streams' outputs have the same names");
    return st;
}

/* --- glGetString --------------------------------------------------------- */

static const GLubyte *faker_GetString(void *self, GLenum name)
{
    tsr_faker_context *c = self;
    switch (name) {
    case GL_VENDOR: return (const GLubyte *)"tessera";
    case GL_RENDERER:
        if (!c->renderer[0]) {
            const tsr_dispatch *head = tsr_chain_head(c->stream->chain);
            const GLubyte *down = tsr_call_GetString(head, GL_RENDERER);
            snprintf(c->renderer, sizeof c->renderer, "tessera (%s)",
                     down && down[0] ? (const char *)down : "no renderer");
        }
        return (const GLubyte *)c->renderer;
    case GL_VERSION: return (const GLubyte *)"2.1 tessera " TESSERA_VERSION;
    case GL_SHADING_LANGUAGE_VERSION: return (const GLubyte *)"1.20";
    case GL_EXTENSIONS: return (const GLubyte *)(c->stream ? c->stream->extensions : tsr_faker_gl_extensions);
    default: return NULL;
    }
}

static void follow_size_locked(tsr_faker_surface *s, faker_window *w, const tsr_dispatch *t);
static bool moved_to_locked(tsr_faker_context *c);
static void poll_locked(void);
static bool drawable_size_locked(unsigned long xid, int *w, int *h);

/* glViewport: where programs react to a resize, so a new size reaches the
 * stream before the frame drawn at it (checked again at every swap). */
static void faker_Viewport(void *self, GLint x, GLint y, GLsizei width, GLsizei height)
{
    tsr_faker_context *c = self;
    if (moved_to_locked(c)) {
        tsr_call_Viewport(&c->locked, x, y, width, height);
        return;
    }
    const tsr_dispatch *head = tsr_chain_head(c->stream->chain);
    tsr_faker_surface *sf = cur_surface;
    if (sf && sf->xid) {
        pthread_mutex_lock(&lock);
        poll_locked();
        /* The faker's ConfigureNotify may still be on its way when the
         * program, woken by its own, sets the new viewport: a viewport of
         * another size than the window's asks the server, once a frame. */
        if ((width != sf->x_width || height != sf->x_height) && !sf->asked) {
            int w, h;
            if (drawable_size_locked(sf->xid, &w, &h)) {
                sf->x_width = w;
                sf->x_height = h;
            }
            sf->asked = true;
        }
        follow_size_locked(sf, cur_window, head);
        pthread_mutex_unlock(&lock);
    }
    tsr_call_Viewport(head, x, y, width, height);
}

static const tsr_dispatch *head_of(void *self) { return tsr_chain_head(((tsr_faker_context *)self)->stream->chain); }

/* --- contexts ------------------------------------------------------------ */

static void faker_NewList(void *self, GLuint list, GLenum mode);
static void faker_EndList(void *self);
static void faker_Clear(void *self, GLbitfield mask);
static void faker_Flush(void *self);
static void faker_Finish(void *self);

/* A context's table is a copy of the chain head's, and an SPU may change
 * its head table while the stream runs (tilesort compiles display lists
 * through a recording table from glNewList to glEndList): the copy is
 * taken again after those calls, so the context follows the change. */
static void context_table(tsr_faker_context *c, const tsr_dispatch *head)
{
    c->table = *head;
    tsr_set_GetString(&c->table, faker_GetString, c);
    tsr_set_Viewport(&c->table, faker_Viewport, c);
    tsr_set_NewList(&c->table, faker_NewList, c);
    tsr_set_EndList(&c->table, faker_EndList, c);
    tsr_set_Clear(&c->table, faker_Clear, c);
    tsr_set_Flush(&c->table, faker_Flush, c);
    tsr_set_Finish(&c->table, faker_Finish, c);
    if (c->hooks)
        for (int i = 0; i < TSR_DISPATCH_COUNT; i++)
            c->hooks[i].next = c->table.slots[i];
}

static void faker_NewList(void *self, GLuint list, GLenum mode)
{
    const tsr_dispatch *head = head_of(self);
    tsr_call_NewList(head, list, mode);
    context_table(self, head);
}

static void faker_EndList(void *self)
{
    const tsr_dispatch *head = head_of(self);
    tsr_call_EndList(head);
    context_table(self, head);
}

/* --- shared streams ------------------------------------------------------ */

/* The table the thread `c` is current on calls. */
static const tsr_dispatch *table_of(const tsr_faker_context *c) { return c->locked_now ? &c->locked : &c->table; }

/* Around every call of a locked table: the chain is this thread's for
 * the call, made current to this thread's context and window first when
 * another's call came last. The window is the calling thread's (the hook
 * runs on the thread the context is current on). */
static void locked_before(void *ctx, int slot)
{
    (void)slot;
    tsr_faker_context *c = ctx;
    pthread_mutex_lock(&lock);
    faker_stream *st = c->stream;
    int win = cur_window ? cur_window->window : -1;
    if (st->chain_ctx != c->id || st->chain_window != win) {
        tsr_call_MakeCurrentTSR(tsr_chain_head(st->chain), win, c->id);
        st->chain_ctx = c->id;
        st->chain_window = win;
    }
}

static void locked_after(void *ctx, int slot)
{
    (void)ctx;
    (void)slot;
    pthread_mutex_unlock(&lock);
}

/* Makes `c`'s locked table (once); false: out of memory (logged). */
static bool locked_table_locked(tsr_faker_context *c)
{
    if (c->hooks)
        return true;
    c->hooks = calloc(TSR_DISPATCH_COUNT, sizeof *c->hooks);
    if (!c->hooks) {
        tsr_faker_log(TSR_LOG_ERROR, "context %d: out of memory for its locked table", c->id);
        return false;
    }
    c->locked = c->table;
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++) {
        c->hooks[i].before = locked_before;
        c->hooks[i].after = locked_after;
        c->hooks[i].ctx = c;
        tsr_dispatch_hook(&c->locked, i, &c->hooks[i]);
    }
    return true;
}

/* `c`, current on the calling thread or on none (and not inside a call into the
 * chain), calls its locked table from now on. */
static void go_locked_locked(tsr_faker_context *c)
{
    if (c->locked_now || !locked_table_locked(c))
        return;
    c->locked_now = true;
    if (c->current_on && cur_ctx == c) {
        c->stream->direct_threads--;
        tsr_gl_make_current(&c->locked);
        pthread_cond_broadcast(&switched);
    }
}

/* A check point of a plain table: true when another thread made the
 * stream shared and `c` has just moved to its locked table (the call is
 * then made again through it). */
static bool moved_to_locked(tsr_faker_context *c)
{
    if (c->locked_now || cur_ctx != c || !__atomic_load_n(&c->stream->shared, __ATOMIC_ACQUIRE))
        return false;
    pthread_mutex_lock(&lock);
    go_locked_locked(c);
    pthread_mutex_unlock(&lock);
    return c->locked_now;
}

static void mark_shared_locked(faker_stream *st)
{
    if (st && !st->shared) {
        __atomic_store_n(&st->shared, true, __ATOMIC_RELEASE);
        tsr_faker_log(TSR_LOG_INFO,
                      "stream %d: contexts of one share group are used by several threads: every call "
                      "of that stream now takes the faker's lock",
                      st->number);
    }
}

/* The check points: where a plain table's thread notices that the stream
 * became shared (a program draws a frame with at least one of them). */
static void faker_Clear(void *self, GLbitfield mask)
{
    if (moved_to_locked(self)) {
        tsr_faker_context *c = self;
        tsr_call_Clear(&c->locked, mask);
        return;
    }
    tsr_call_Clear(head_of(self), mask);
}

static void faker_Flush(void *self)
{
    if (moved_to_locked(self)) {
        tsr_faker_context *c = self;
        tsr_call_Flush(&c->locked);
        return;
    }
    tsr_call_Flush(head_of(self));
}

static void faker_Finish(void *self)
{
    if (moved_to_locked(self)) {
        tsr_faker_context *c = self;
        tsr_call_Finish(&c->locked);
        return;
    }
    tsr_call_Finish(head_of(self));
}

/* The first stream is made with the first context, so a chain that cannot
 * be made fails context creation (the program's own error path). */
tsr_faker_context *tsr_faker_context_create(tsr_faker_context *share)
{
    /* The program does not know its chains write PNGs: the faker opts in
     * for it (tessera/image.h), at the first context, over the default
     * actions only; only the first call acts. */
    tsr_image_pending_remove_on_signals(NULL);
    pthread_mutex_lock(&lock);
    bool ok = streams || stream_new_locked();
    tsr_faker_context *c = ok ? calloc(1, sizeof *c) : NULL;
    if (c) {
        c->id = next_context_id++;
        /* A stream's renderer holds its contexts in one share group, so
         * a context shares objects by joining its share list's stream. */
        c->group = share ? share->group : calloc(1, sizeof *c->group);
        if (!c->group) {
            free(c);
            pthread_mutex_unlock(&lock);
            return NULL;
        }
        c->group->refs++;
        c->next = contexts;
        contexts = c;
        /* A share group that already draws: its stream becomes shared now
         * (the new context may be made current on another thread while
         * the group's draws), and the calling thread's own current context
         * of it moves to its locked table at once, so a program that makes
         * its loader's context on the drawing thread never waits. */
        if (share && c->group->stream) {
            mark_shared_locked(c->group->stream);
            if (cur_ctx && cur_ctx->stream == c->group->stream)
                go_locked_locked(cur_ctx);
        }
    }
    pthread_mutex_unlock(&lock);
    return c;
}


static void context_free_locked(tsr_faker_context *ctx)
{
    for (tsr_faker_context **p = &contexts; *p; p = &(*p)->next)
        if (*p == ctx) {
            *p = ctx->next;
            break;
        }
    if (--ctx->group->refs == 0)
        free(ctx->group);
    if (ctx->on_stream && ctx->stream && streams) {
        tsr_call_ContextDestroyTSR(tsr_chain_head(ctx->stream->chain), ctx->id);
        ctx->stream->chain_ctx = 0; /* the renderer may have switched: say it again */
    }
    free(ctx->hooks);
    free(ctx);
}

void tsr_faker_context_destroy(tsr_faker_context *ctx)
{
    if (!ctx)
        return;
    pthread_mutex_lock(&lock);
    if (ctx->current_on)
        ctx->destroy_pending = true;
    else
        context_free_locked(ctx);
    pthread_mutex_unlock(&lock);
}

/* --- surfaces ------------------------------------------------------------ */

/* The drawable's size over the faker's own connection; false if unknown. */
static bool drawable_size_locked(unsigned long xid, int *w, int *h)
{
    if (!xconn)
        return false;
    xcb_generic_error_t *e = NULL;
    xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(xconn, xcb_get_geometry(xconn, (xcb_drawable_t)xid), &e);
    free(e);
    if (!g)
        return false;
    *w = g->width;
    *h = g->height;
    free(g);
    return true;
}

/* Reads the ConfigureNotify events of the faker's own connection that have
 * arrived (no round trip): the new sizes of its windows. */
static void poll_locked(void)
{
    if (!xconn)
        return;
    xcb_generic_event_t *ev;
    while ((ev = xcb_poll_for_event(xconn))) {
        if ((ev->response_type & 0x7f) == XCB_CONFIGURE_NOTIFY) {
            const xcb_configure_notify_event_t *c = (const xcb_configure_notify_event_t *)ev;
            for (tsr_faker_surface *s = surfaces; s; s = s->next)
                if (s->xid == c->window) {
                    s->x_width = c->width;
                    s->x_height = c->height;
                }
        }
        free(ev);
    }
}

/* Tells the stream of `w` (through `t`) about a changed size of `s`. */
static void follow_size_locked(tsr_faker_surface *s, faker_window *w, const tsr_dispatch *t)
{
    poll_locked();
    if (s && w && s->xid && (s->x_width != w->width || s->x_height != w->height)) {
        s->width = w->width = s->x_width;
        s->height = w->height = s->x_height;
        tsr_call_WindowSizeTSR(t, w->window, w->width, w->height);
    }
}

/* `s` as stream `st` knows it, or NULL. */
static faker_window *window_in(tsr_faker_surface *s, const faker_stream *st)
{
    for (int i = 0; s && i < s->non; i++)
        if (s->on[i].stream == st)
            return &s->on[i];
    return NULL;
}

static bool connect_locked(const char *display_name)
{
    const char *name = display_name ? display_name : "";
    if (xconn && !strcmp(name, xconn_name))
        return true;
    if (xconn) {
        tsr_faker_log(TSR_LOG_ERROR, "a second X display (%s after %s) is not supported", name, xconn_name);
        return false;
    }
    xcb_connection_t *c = xcb_connect(name[0] ? name : NULL, NULL);
    if (xcb_connection_has_error(c)) {
        xcb_disconnect(c);
        tsr_faker_log(TSR_LOG_ERROR, "cannot connect to X display \"%s\"", name);
        return false;
    }
    xconn = c;
    snprintf(xconn_name, sizeof xconn_name, "%s", name);
    return true;
}

tsr_faker_surface *tsr_faker_surface_find(unsigned long xid)
{
    pthread_mutex_lock(&lock);
    tsr_faker_surface *s = surfaces;
    while (s && !(xid && s->xid == xid))
        s = s->next;
    pthread_mutex_unlock(&lock);
    return s;
}

static tsr_faker_surface *surface_add_locked(unsigned long xid, int w, int h)
{
    tsr_faker_surface *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->xid = xid;
    s->width = w;
    s->height = h;
    s->next = surfaces;
    surfaces = s;
    return s;
}

tsr_faker_surface *tsr_faker_surface_window(const char *display_name, unsigned long xid)
{
    tsr_faker_surface *s = tsr_faker_surface_find(xid);
    if (s)
        return s;
    pthread_mutex_lock(&lock);
    int w = 0, h = 0;
    if (!connect_locked(display_name)) {
        pthread_mutex_unlock(&lock);
        return NULL;
    }
    /* StructureNotify for the faker's own connection (event masks are per
     * client: the application's is untouched), then the size. */
    const uint32_t mask = XCB_EVENT_MASK_STRUCTURE_NOTIFY;
    xcb_void_cookie_t ck = xcb_change_window_attributes_checked(xconn, (xcb_window_t)xid, XCB_CW_EVENT_MASK, &mask);
    free(xcb_request_check(xconn, ck)); /* a pixmap: no events, sizes fixed */
    if (!drawable_size_locked(xid, &w, &h)) {
        tsr_faker_log(TSR_LOG_ERROR, "drawable 0x%lx: cannot read its size (no such drawable?)", xid);
    } else {
        s = surface_add_locked(xid, w, h);
        if (s) {
            s->x_width = w;
            s->x_height = h;
        }
    }
    pthread_mutex_unlock(&lock);
    return s;
}

bool tsr_faker_drawable_geometry(const char *display_name, unsigned long xid, int *width, int *height, int *depth)
{
    pthread_mutex_lock(&lock);
    bool ok = false;
    if (connect_locked(display_name)) {
        xcb_generic_error_t *e = NULL;
        xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(xconn, xcb_get_geometry(xconn, (xcb_drawable_t)xid), &e);
        free(e);
        if (g) {
            *width = g->width;
            *height = g->height;
            *depth = g->depth;
            ok = true;
            free(g);
        }
    }
    pthread_mutex_unlock(&lock);
    return ok;
}

tsr_faker_surface *tsr_faker_surface_pbuffer(int width, int height)
{
    pthread_mutex_lock(&lock);
    tsr_faker_surface *s = surface_add_locked(0, width > 0 ? width : 1, height > 0 ? height : 1);
    if (s) {
        s->x_width = s->width;
        s->x_height = s->height;
    }
    pthread_mutex_unlock(&lock);
    return s;
}

void tsr_faker_surface_destroy(tsr_faker_surface *s)
{
    if (!s)
        return;
    pthread_mutex_lock(&lock);
    for (tsr_faker_surface **p = &surfaces; *p; p = &(*p)->next)
        if (*p == s) {
            *p = s->next;
            break;
        }
    for (int i = 0; i < s->non && streams; i++) {
        tsr_call_WindowDestroyTSR(tsr_chain_head(s->on[i].stream->chain), s->on[i].window);
        s->on[i].stream->chain_ctx = 0;
        if (s->on[i].stream->number == 0)
            tsr_native_window_set(tsr_chain_native_windows(s->on[i].stream->chain), s->on[i].window, NULL, 0);
    }
    if (cur_surface == s) {
        cur_surface = NULL;
        cur_window = NULL;
    }
    free(s);
    pthread_mutex_unlock(&lock);
}

void tsr_faker_surface_size(const tsr_faker_surface *s, int *width, int *height)
{
    *width = s ? s->width : 0;
    *height = s ? s->height : 0;
}

void tsr_faker_surface_x_size(tsr_faker_surface *s, int *width, int *height)
{
    tsr_faker_surface_size(s, width, height);
    if (!s || !s->xid)
        return;
    pthread_mutex_lock(&lock);
    int w, h;
    if (drawable_size_locked(s->xid, &w, &h)) {
        *width = w;
        *height = h;
    }
    pthread_mutex_unlock(&lock);
}


/* --- current ------------------------------------------------------------- */

/* Another thread has a context of `st` current (the calling thread's own
 * current context, `mine`, is not counted). */
static bool stream_busy_locked(const faker_stream *st, const tsr_faker_context *mine)
{
    return st->current_threads - (mine && mine->stream == st ? 1 : 0) > 0;
}

/* The stream `ctx` draws into: its share group's, else the oldest that no
 * other thread draws into, else a new one (NULL: none, logged). */
static faker_stream *stream_for_locked(tsr_faker_context *ctx)
{
    if (ctx->stream)
        return ctx->stream;
    if (ctx->group->stream)
        return ctx->group->stream;
    faker_stream *pick = NULL;
    for (faker_stream *st = streams; st; st = st->next) /* newest first: the last free is the oldest */
        if (!stream_busy_locked(st, cur_ctx))
            pick = st;
    return pick ? pick : stream_new_locked();
}

bool tsr_faker_make_current_refused_busy(void) { return refused_busy; }

/* Waits (the lock released meanwhile) until no other thread calls a plain
 * table of `st`: those threads move to their locked tables at their next
 * check point. `old`, the calling thread's current context, is not
 * waited for. false: FAKER_SWITCH_WAIT_MS passed (logged). */
static bool wait_direct_locked(faker_stream *st, const tsr_faker_context *old, int ctx_id)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += FAKER_SWITCH_WAIT_MS / 1000;
    until.tv_nsec += (long)(FAKER_SWITCH_WAIT_MS % 1000) * 1000000L;
    if (until.tv_nsec >= 1000000000L) {
        until.tv_sec++;
        until.tv_nsec -= 1000000000L;
    }
    for (;;) {
        int own = old && old->stream == st && !old->locked_now ? 1 : 0;
        if (st->direct_threads - own <= 0)
            return true;
        if (pthread_cond_timedwait(&switched, &lock, &until) == ETIMEDOUT) {
            own = old && old->stream == st && !old->locked_now ? 1 : 0;
            if (st->direct_threads - own <= 0)
                return true;
            tsr_faker_log(TSR_LOG_ERROR,
                          "context %d: another thread has a context of the same share group (stream %d) current "
                          "and made no glClear, glFlush, glFinish, glViewport, swap or MakeCurrent for %d ms, "
                          "so the stream cannot be shared with it yet",
                          ctx_id, st->number, FAKER_SWITCH_WAIT_MS);
            return false;
        }
    }
}

bool tsr_faker_make_current(tsr_faker_context *ctx, tsr_faker_surface *draw)
{
    refused_busy = false;
    pthread_mutex_lock(&lock);
    tsr_faker_context *old = cur_ctx;
    faker_stream *st = NULL;
    faker_window *w = NULL;
    if (ctx) {
        st = stream_for_locked(ctx);
        if (!st) {
            pthread_mutex_unlock(&lock);
            return false;
        }
        if (ctx->current_on && old != ctx) {
            tsr_faker_log(TSR_LOG_ERROR, "context %d is current on another thread", ctx->id);
            refused_busy = true;
            pthread_mutex_unlock(&lock);
            return false;
        }
        if (!ctx->stream) {
            ctx->stream = st;
            ctx->group->stream = st;
            context_table(ctx, tsr_chain_head(st->chain));
        }
        /* Several threads on one stream: each call takes the lock (see
         * the top of this file); a share group of several contexts is
         * taken as such from the start, as its contexts are made for it. */
        if (stream_busy_locked(st, old) || ctx->group->refs > 1 || st->shared) {
            mark_shared_locked(st);
            go_locked_locked(ctx); /* ctx itself may be the calling thread's current one */
            if (!ctx->locked_now) {
                pthread_mutex_unlock(&lock);
                return false;
            }
            if (!wait_direct_locked(st, old, ctx->id)) {
                refused_busy = true;
                pthread_mutex_unlock(&lock);
                return false;
            }
        }
        if (draw && !(w = window_in(draw, st)) && draw->non == FAKER_SURFACE_STREAMS) {
            tsr_faker_log(TSR_LOG_ERROR, "a surface drawn by contexts of more than %d streams is not supported",
                          FAKER_SURFACE_STREAMS);
            pthread_mutex_unlock(&lock);
            return false;
        }
    }
    if (old && old != ctx) {
        old->stream->current_threads--;
        if (!old->locked_now)
            old->stream->direct_threads--;
        old->current_on--;
        if (old->destroy_pending && !old->current_on)
            context_free_locked(old);
    }
    if (!ctx) {
        cur_ctx = NULL;
        cur_surface = NULL;
        cur_window = NULL;
        tsr_gl_make_current(NULL);
        pthread_cond_broadcast(&switched);
        pthread_mutex_unlock(&lock);
        return true;
    }
    const tsr_dispatch *head = tsr_chain_head(st->chain);
    if (draw && !w) {
        poll_locked();
        w = &draw->on[draw->non++];
        w->stream = st;
        w->window = st->next_window_id++;
        draw->width = w->width = draw->x_width;
        draw->height = w->height = draw->x_height;
        /* For SPUs of this process that draw back into the program's own
         * window (render window_output=app), before they see the window:
         * the first stream's chain only, so one chain draws into it. */
        if (draw->xid && st->number == 0)
            tsr_native_window_set(tsr_chain_native_windows(st->chain), w->window, xconn_name, draw->xid);
        tsr_call_WindowCreateTSR(head, w->window, w->width, w->height);
        /* GL_BACK and GL_FRONT are two buffers where the program asked for
         * double buffering (render's buffers.c). */
        if (draw->double_buffered)
            tsr_call_WindowBuffersTSR(head, w->window, 2);
        if (draw->samples)
            tsr_call_WindowSamplesTSR(head, w->window, draw->samples);
    } else if (draw) {
        follow_size_locked(draw, w, head);
    }
    if (!ctx->on_stream) {
        tsr_call_ContextCreateTSR(head, ctx->id);
        ctx->on_stream = true;
    }
    /* Surfaceless: the commands go to the context; window -1 is none. */
    tsr_call_MakeCurrentTSR(head, w ? w->window : -1, ctx->id);
    st->chain_ctx = ctx->id;
    st->chain_window = w ? w->window : -1;
    if (old != ctx) {
        ctx->current_on++;
        st->current_threads++;
        if (!ctx->locked_now)
            st->direct_threads++;
    }
    cur_ctx = ctx;
    cur_surface = draw;
    cur_window = w;
    tsr_gl_make_current(table_of(ctx));
    pthread_cond_broadcast(&switched);
    pthread_mutex_unlock(&lock);
    return true;
}

tsr_faker_context *tsr_faker_current_context(void) { return cur_ctx; }

void tsr_faker_surface_set_config(tsr_faker_surface *s, bool double_buffered, int samples)
{
    pthread_mutex_lock(&lock);
    if (s && !s->non) {
        s->double_buffered = double_buffered;
        s->samples = samples;
    }
    pthread_mutex_unlock(&lock);
}


void tsr_faker_swap(tsr_faker_surface *s)
{
    if (!s || !cur_ctx)
        return;
    moved_to_locked(cur_ctx);
    const tsr_dispatch *t = table_of(cur_ctx);
    pthread_mutex_lock(&lock);
    faker_window *w = s == cur_surface ? cur_window : window_in(s, cur_ctx->stream);
    pthread_mutex_unlock(&lock);
    if (!w)
        return; /* never drawn by this context's stream: no frame there */
    tsr_call_SwapBuffersTSR(t, w->window, 0);
    if (!s->xid)
        return;
    pthread_mutex_lock(&lock);
    follow_size_locked(s, w, t);
    s->asked = false;
    pthread_mutex_unlock(&lock);
}

void tsr_faker_finish(void)
{
    if (cur_ctx)
        tsr_call_Finish(table_of(cur_ctx));
}
