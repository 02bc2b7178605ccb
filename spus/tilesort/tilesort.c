/* spus/tilesort/tilesort.c — the "tilesort" SPU: sort-first. One
 * application stream, many tile servers; each server gets only the
 * geometry that touches its tiles, preceded by exactly the state it lacks.
 *
 * Routing (set up once per instance from the spec's categories):
 *   - state and object commands the tracker (tessera/dev/state.h) implements go
 *     to the tracker only; before each one, pending geometry is flushed,
 *     because the diffs that precede geometry are taken from the tracker;
 *   - geometry is packed once into the geometry buffer while the packer
 *     keeps its object-space box; current attributes (glColor, ...) go to
 *     the buffer and to the tracker; on flush (buffer full, state change,
 *     frame command) the buffer goes to the servers its box touches, each
 *     after what it lacks (send.c); array draws are sorted primitive by
 *     primitive instead (arrays.c), display lists compiled and sent lazily
 *     (lists.c);
 *   - commands whose effect on the window is unknown (untracked state such
 *     as RasterPos, glRect, glBitmap, glDrawPixels, lists that change
 *     state, anything while a vertex shader is in use, boxes crossing the
 *     eye plane or holding NaN/Inf) make the buffer go to every server;
 *     frame commands (Clear, Finish, swap, barriers, semaphores, windows)
 *     go to every server and are flushed at once (frame.c);
 *   - the program's framebuffer objects are rendered whole on every
 *     server: their commands go to all, and while one is bound so does
 *     everything drawn (fbo.c);
 *   - gets are answered by the tracker where the value is client-known,
 *     otherwise by the first live server (after its diff; gets.c);
 *     glReadPixels is gathered from every server whose tiles meet the
 *     rectangle (frame.c), and so is the source of glCopyPixels and
 *     glCopyTex(Sub)Image, then drawn or uploaded (copy.c).
 *
 * Owns, per instance (instance.h): the stream client (tessera/dev/client.h, one
 * connection per server), the tracker with one context and one shadow per
 * server, the geometry packer, one small packer per server (diffs, tiles,
 * lists, requests), the tiling, the display lists, the statistics. No
 * globals. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "tessera/dev/util.h"

#include "instance.h"
#include "tessera/image.h"
#include "tessera/log.h"
#include "tessera/spu.h"

/* What the routing does around a slot (see the header). */
enum {
    R_DEFAULT,   /* geometry buffer only */
    R_STATE,     /* tracker only, pending geometry flushed first */
    R_BROADCAST, /* geometry buffer, and that buffer goes to every server */
    R_FRAME,     /* like R_BROADCAST, flushed at once */
    R_SERVER,    /* sent to the first live server (gets) */
};

void ts_report(tilesort *t, const tsr_error *e)
{
    if (!t->error.code && e->code) {
        t->error = *e;
        tsr_log(TSR_LOG_ERROR, "%s: %s", t->name, e->message);
    }
}

/* --- statistics --------------------------------------------------------------- */

/* Per-frame bytes per server, for the statistics (the first
 * TS_STATS_FRAMES frames; totals cover every frame). */
#define TS_STATS_FRAMES 100000
void ts_keep_frame_row(tilesort *t)
{
    if (t->frames_kept == TS_STATS_FRAMES)
        return;
    if (t->frames_kept == t->frames_cap) {
        size_t cap = t->frames_cap ? 2 * t->frames_cap : 64;
        uint64_t *n = realloc(t->frame_rows, cap * t->nservers * sizeof *n);
        if (!n)
            return;
        t->frame_rows = n;
        uint64_t *g = realloc(t->frame_geometry_rows, cap * t->nservers * sizeof *g);
        if (!g)
            return;
        t->frame_geometry_rows = g;
        double *secs = realloc(t->frame_seconds, cap * sizeof *secs);
        if (!secs)
            return;
        t->frame_seconds = secs;
        double *costs = realloc(t->frame_costs, cap * t->nservers * sizeof *costs);
        if (!costs)
            return;
        t->frame_costs = costs;
        double *faults = realloc(t->frame_fault_costs, cap * t->nservers * sizeof *faults);
        if (!faults)
            return;
        t->frame_fault_costs = faults;
        uint64_t *pixels = realloc(t->frame_pixels, cap * t->nservers * sizeof *pixels);
        if (!pixels)
            return;
        t->frame_pixels = pixels;
        t->frames_cap = cap;
    }
    double now = tsr_now_seconds();
    t->frame_seconds[t->frames_kept] = now - t->last_swap;
    t->last_swap = now;
    for (size_t i = 0; i < t->nservers; i++) {
        size_t at = t->frames_kept * t->nservers + i;
        t->frame_rows[at] = t->srv[i].frame_bytes;
        t->frame_geometry_rows[at] = t->frame_geometry[i];
        t->frame_costs[at] = -1;
        t->frame_fault_costs[at] = -1;
        t->frame_pixels[at] = 0;
        for (size_t k = 0; k < t->tiling.ntiles[i]; k++)
            t->frame_pixels[at] += (uint64_t)t->tiling.tiles[i][k].w * (uint64_t)t->tiling.tiles[i][k].h;
    }
    t->frames_kept++;
}

/* A server's TSR_NODE_MSG_COST (tessera/dev/client.h): to the balancer
 * and the statistics. */
static void take_cost(void *ctx, size_t server, const tsr_frame_cost *cost)
{
    tilesort *t = ctx;
    ts_tiling_report(&t->tiling, server, cost->frame, cost->seconds, cost->fault_seconds);
    if (cost->frame < t->frames_kept && server < t->nservers) {
        t->frame_costs[(size_t)cost->frame * t->nservers + server] = cost->seconds;
        t->frame_fault_costs[(size_t)cost->frame * t->nservers + server] = cost->fault_seconds;
    }
}

static const char *bucket_name(ts_bucket_mode m)
{
    return m == TS_BROADCAST ? "broadcast"
           : m == TS_TILES   ? "tiles"
           : m == TS_KD      ? "kd"
           : m == TS_UNION   ? "union"
                             : "grid";
}

/* `,"NAME":[[...],...]`: one row of nservers counts per kept frame. */
static void write_count_rows(FILE *f, const char *name, const tilesort *t, const uint64_t *rows)
{
    fprintf(f, ",\"%s\":[", name);
    for (size_t r = 0; r < t->frames_kept; r++) {
        fprintf(f, "%s[", r ? "," : "");
        for (size_t i = 0; i < t->nservers; i++)
            fprintf(f, "%s%llu", i ? "," : "", (unsigned long long)rows[r * t->nservers + i]);
        fprintf(f, "]");
    }
    fprintf(f, "]");
}

/* Rows of seconds per frame and server, null where none came. */
static void write_second_rows(FILE *f, const char *name, const tilesort *t, const double *rows)
{
    fprintf(f, ",\"%s\":[", name);
    for (size_t r = 0; r < t->frames_kept; r++) {
        fprintf(f, "%s[", r ? "," : "");
        for (size_t i = 0; i < t->nservers; i++) {
            double v = rows[r * t->nservers + i];
            fprintf(f, v >= 0 ? "%s%.9f" : "%snull", i ? "," : "", v);
        }
        fprintf(f, "]");
    }
    fprintf(f, "]");
}

/* The sort-first members of the statistics file (tessera/dev/client.h):
 *   "sort_first":{"bucket":"grid","servers":4,"stream_bytes":N,
 *     "bytes_out":N,"overlap":X,"imbalance":X,"server_bytes":[...],
 *     "frame_seconds":[...],"frames":[[bytes to server 0, 1, ...], ...]}
 * stream_bytes: the geometry buffers and display lists, packed once, and
 * the state diffs one server getting all of them would need (what
 * one server of a 1x1 configuration gets, without its state diffs);
 * overlap = bytes_out / stream_bytes; imbalance = max / mean of the
 * servers' bytes (1 is perfect); frame_seconds: the application's time
 * from one swap to the next (the first from the SPU's creation).
 * Then "frames_geometry" (per frame and server, the part of "frames"
 * that is geometry buffers and display lists: the rest is state diffs,
 * tiles and window and frame commands, which every server gets),
 * "server_seconds" (per frame, the render
 * time each server measured and reported, null when none came),
 * "server_fault_seconds" (the part of it the server put down to minor
 * page faults: its faults that frame at its measured cost of one),
 * "server_pixels" (per frame, the pixels of each server's region) and
 * "time_imbalance" (per frame, max / mean of server_seconds; null unless
 * every server reported that frame) and, in the balanced modes,
 * "cost_model" (the coefficients the last fit reached, or the priors
 * when "fits" is 0). */
static void write_sort_first_stats(void *ctx, FILE *f)
{
    tilesort *t = ctx;
    uint64_t total = 0, max = 0;
    for (size_t i = 0; i < t->nservers; i++) {
        uint64_t b = t->srv[i].bytes + t->srv[i].frame_bytes;
        total += b;
        max = b > max ? b : max;
    }
    double mean = (double)total / (double)t->nservers;
    fprintf(f,
            ",\"sort_first\":{\"bucket\":\"%s\",\"servers\":%zu,\"stream_bytes\":%llu,\"bytes_out\":%llu,"
            "\"overlap\":%.6f,\"imbalance\":%.6f,\"server_bytes\":[",
            bucket_name(t->tiling.mode), t->nservers, (unsigned long long)t->stream_bytes, (unsigned long long)total,
            t->stream_bytes ? (double)total / (double)t->stream_bytes : 0.0, mean > 0 ? (double)max / mean : 0.0);
    for (size_t i = 0; i < t->nservers; i++)
        fprintf(f, "%s%llu", i ? "," : "", (unsigned long long)(t->srv[i].bytes + t->srv[i].frame_bytes));
    fprintf(f, "],\"frame_seconds\":[");
    for (size_t r = 0; r < t->frames_kept; r++)
        fprintf(f, "%s%.6f", r ? "," : "", t->frame_seconds[r]);
    fprintf(f, "]");
    write_count_rows(f, "frames", t, t->frame_rows);
    write_count_rows(f, "frames_geometry", t, t->frame_geometry_rows);
    write_second_rows(f, "server_seconds", t, t->frame_costs);
    write_second_rows(f, "server_fault_seconds", t, t->frame_fault_costs);
    write_count_rows(f, "server_pixels", t, t->frame_pixels);
    fprintf(f, ",\"time_imbalance\":[");
    for (size_t r = 0; r < t->frames_kept; r++) {
        double sum = 0, max = 0;
        int all = 1;
        for (size_t i = 0; i < t->nservers; i++) {
            double v = t->frame_costs[r * t->nservers + i];
            all &= v >= 0;
            sum += v;
            max = v > max ? v : max;
        }
        if (all && sum > 0)
            fprintf(f, "%s%.6f", r ? "," : "", max * (double)t->nservers / sum);
        else
            fprintf(f, "%snull", r ? "," : "");
    }
    fprintf(f, "]");
    if (TS_BALANCED(t->tiling.mode)) {
        const ts_cost *c = &t->tiling.cost;
        fprintf(f,
                ",\"cost_model\":{\"fits\":%llu,\"fixed_seconds\":%.6g,\"seconds_per_byte\":%.6g,"
                "\"seconds_per_box_pixel\":%.6g,\"seconds_per_region_pixel\":%.6g}",
                (unsigned long long)c->fits, c->coef[TS_TERM_FIXED], c->coef[TS_TERM_BYTES], c->coef[TS_TERM_FILL],
                c->coef[TS_TERM_AREA]);
    }
    fprintf(f, "}");
}

/* The solo packer's sink: what one server of a 1x1 configuration would
 * get besides the stream is counted, never sent. */
static int count_solo(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tilesort *t = ctx;
    (void)buf;
    (void)err;
    t->stream_bytes += size;
    return TSR_OK;
}

/* --- hooks ----------------------------------------------------------------- */

static void hook_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    switch (t->route[slot]) {
    case R_STATE: ts_flush_before_state(t); break;
    case R_BROADCAST:
    case R_FRAME: ts_broadcast_next(t); break;
    case R_SERVER: ts_to_server(t); break;
    default: break;
    }
}

static void hook_after(void *ctx, int slot)
{
    tilesort *t = ctx;
    if (t->route[slot] == R_FRAME && !t->in_begin)
        ts_flush_geometry(t);
    if (t->route[slot] == R_STATE && !tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

/* A command inside glNewList that a box cannot place. */
static void rec_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    if (t->recording) {
        t->recording->unknown = 1;
        t->recording->has_state = 1;
        /* pixel data was packed under the compile-time unpack modes */
        const char *name = tsr_dispatch_name(slot);
        if (t->route[slot] != R_STATE || strstr(name, "TexImage") || strstr(name, "TexSubImage") ||
            !strcmp(name, "PolygonStipple"))
            t->recording->unexpandable = 1;
    }
}

/* Geometry inside glNewList: the list draws by itself. */
static void rec_geometry_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    (void)slot;
    if (t->recording)
        t->recording->geometry = 1;
}

/* A current attribute inside glNewList: the list's calls change the
 * current values, so they are replayed into the tracker (the box still
 * places the list). */
static void rec_current_before(void *ctx, int slot)
{
    tilesort *t = ctx;
    (void)slot;
    if (t->recording)
        t->recording->has_state = 1;
}

/* --- commands with their own code ------------------------------------------- */

/* Programs are tracked (core/state/state_glsl.c) and reach each server in its
 * diff, the first time it draws with them. While the current program has
 * a vertex shader, positions are the shader's: buffers go to every server. */
static void ts_UseProgram(void *self, GLuint program)
{
    tilesort *t = self;
    ts_flush_before_state(t);
    tsr_call_UseProgram(&t->track_table, program);
    t->program = tsr_state_program_has_vertex_shader(t->ctx);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

/* glEnable/glDisable of a client array is glEnable/DisableClientState
 * (Mesa takes both): the geometry packer's mirror and the tracker's, as
 * the client route has it, never a state change for the servers. Any
 * other cap takes the state route. */
static void enable(tilesort *t, GLenum cap, int on)
{
    if (tsr_wire_is_client_array(cap)) {
        if (on)
            tsr_call_EnableClientState(&t->normal, cap);
        else
            tsr_call_DisableClientState(&t->normal, cap);
        return;
    }
    ts_flush_before_state(t);
    if (on)
        tsr_call_Enable(&t->track_table, cap);
    else
        tsr_call_Disable(&t->track_table, cap);
    if (!tsr_packer_pending(t->geo))
        ts_snapshot(t);
}

static void ts_Enable(void *self, GLenum cap) { enable(self, cap, 1); }
static void ts_Disable(void *self, GLenum cap) { enable(self, cap, 0); }

static void ts_PixelStorei(void *self, GLenum pname, GLint value)
{
    tilesort *t = self;
    ts_flush_before_state(t);
    tsr_packer_mirror_PixelStore(t->geo, pname, value);
    tsr_call_PixelStorei(&t->track_table, pname, value);
}

static void ts_PixelStoref(void *self, GLenum pname, GLfloat value)
{
    tilesort *t = self;
    ts_flush_before_state(t);
    tsr_packer_mirror_PixelStore(t->geo, pname, value);
    tsr_call_PixelStoref(&t->track_table, pname, value);
}

static void ts_BindBuffer(void *self, GLenum target, GLuint buffer)
{
    tilesort *t = self;
    ts_flush_before_state(t);
    tsr_packer_mirror_BindBuffer(t->geo, target, buffer);
    tsr_call_BindBuffer(&t->track_table, target, buffer);
}

static void ts_DeleteBuffers(void *self, GLsizei n, const GLuint *buffers)
{
    tilesort *t = self;
    ts_flush_before_state(t);
    tsr_packer_mirror_DeleteBuffers(t->geo, n, buffers);
    tsr_call_DeleteBuffers(&t->track_table, n, buffers);
}

/* --- set-up -------------------------------------------------------------------- */

/* The reply callback of the packers that only send (geometry, lists):
 * requests go to a server's own packer, never through these. */
static int no_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)data;
    (void)size;
    tilesort *t = ctx;
    return tsr_error_set(err, TSR_ESTATE, "%s: request %u reached a packer that only sends", t->name, id);
}

static int current_slots(uint8_t *is_current)
{
    const char *name, *category;
    for (size_t i = 0; tsr_state_spec_command(i, &name, &category); i++)
        if (!strcmp(category, "current")) {
            int slot = tsr_dispatch_slot(name);
            if (slot >= 0)
                is_current[slot] = 1;
        }
    return 0;
}

/* Commands GL executes at once instead of compiling into a list (GL 2.1
 * section 5.4), beyond gets, client state and the calls that answer
 * (glMapBuffer, glUnmapBuffer). */
static int immediate_in_list(const char *name)
{
    static const char *const names[] = {
        "PixelStorei",      "PixelStoref",      "Finish",           "Flush",           "GenLists",
        "DeleteLists",      "GenTextures",      "DeleteTextures",   "GenBuffers",      "DeleteBuffers",
        "BindBuffer",       "BufferData",       "BufferSubData",    "RenderMode",      "FeedbackBuffer",
        "SelectBuffer",     "NewList",          "EndList",          "WindowCreateTSR", "WindowSizeTSR",
        "WindowDestroyTSR", "WindowBuffersTSR", "WindowSamplesTSR", "SwapBuffersTSR",  "CreateShader",
        "CreateShaderTSR",  "ShaderSource",     "CompileShader",    "DeleteShader",    "CreateProgram",
        "CreateProgramTSR", "DeleteProgram",    "AttachShader",     "DetachShader",    "BindAttribLocation",
        "LinkProgram",      "ValidateProgram"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (!strcmp(names[i], name))
            return 1;
    /* GL 3.0 section 5.4 lists the FBO commands and glFlushMappedBufferRange too */
    return ts_fbo_command(name) || !strcmp(name, "FlushMappedBufferRange");
}

static int is_boxed_geometry(const char *name, unsigned flags)
{
    return (flags & TSR_CMD_POSITION) || !strcmp(name, "Begin") || !strcmp(name, "End") ||
           !strcmp(name, "DrawArrays") || !strcmp(name, "DrawElements") || !strcmp(name, "MultiDrawArrays") ||
           !strcmp(name, "MultiDrawElements") || !strcmp(name, "DrawRangeElements");
}

#define SET(name) tsr_set_##name(&t->normal, ts_##name, t)

static void build_tables(tilesort *t)
{
    /* What the tracker implements: the slots it changes in a no-op table. */
    tsr_dispatch nops, tracked;
    tsr_dispatch_fill_nop(&nops);
    tracked = nops;
    tsr_state_fill_dispatch(t->ctx, &tracked);
    t->track_table = tracked;
    tsr_set_CallList(&t->track_table, ts_replay_CallList, t);
    tsr_set_CallLists(&t->track_table, ts_replay_CallLists, t);
    uint8_t is_current[TSR_DISPATCH_COUNT] = {0};
    current_slots(is_current);

    t->normal = t->geo_table;
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        const char *name = tsr_dispatch_name(slot);
        int cat = tsr_dispatch_category(slot);
        unsigned flags = tsr_dispatch_flags(slot);
        int by_tracker = tracked.slots[slot].fn != nops.slots[slot].fn;
        t->route[slot] = R_DEFAULT;
        if (is_current[slot] || (by_tracker && (cat == TSR_CAT_CLIENT || (flags & TSR_CMD_LOCAL)))) {
            /* geometry buffer (or the packer's mirrors) and tracker */
            t->tees[slot] = (tsr_tee){.first = t->geo_table.slots[slot], .second = tracked.slots[slot]};
            tsr_dispatch_tee(&t->normal, slot, &t->tees[slot]);
            continue;
        }
        if (by_tracker && cat != TSR_CAT_GET) {
            t->route[slot] = R_STATE;
            t->normal.slots[slot] = tracked.slots[slot];
        } else if (by_tracker) {
            t->normal.slots[slot] = tracked.slots[slot]; /* Is*, Gen* that always answer */
            continue;
        } else if (cat == TSR_CAT_FRAME) {
            t->route[slot] = R_FRAME;
        } else if (flags & TSR_CMD_OUTPUT) {
            /* the hook's before() readies the first live server: assumed
             * to be server 0 (with on_error=drop and server 0 gone, such
             * gets are answered by nobody) */
            t->route[slot] = R_SERVER;
            t->normal.slots[slot] = t->srv[0].table.slots[slot];
        } else if ((cat == TSR_CAT_GEOMETRY && is_boxed_geometry(name, flags)) || (flags & TSR_CMD_LOCAL)) {
            continue; /* packed with its box, or only the packer's mirrors */
        } else if (cat == TSR_CAT_SPECIAL || ts_fbo_command(name)) {
            t->route[slot] = R_FRAME;
        } else {
            t->route[slot] = R_BROADCAST;
        }
        t->hooks[slot] = (tsr_hook){.before = hook_before, .after = hook_after, .ctx = t};
        tsr_dispatch_hook(&t->normal, slot, &t->hooks[slot]);
    }
    /* own code (after the generic routes, which they replace) */
    SET(Begin);
    SET(End);
    SET(DrawArrays);
    SET(DrawElements);
    SET(DrawRangeElements);
    SET(MultiDrawArrays);
    SET(MultiDrawElements);
    SET(WindowCreateTSR);
    SET(WindowSizeTSR);
    SET(SwapBuffersTSR);
    SET(UseProgram);
    SET(Materialf);
    SET(Materialfv);
    SET(Materiali);
    SET(Materialiv);
    SET(PixelStorei);
    SET(Enable);
    SET(Disable);
    SET(PixelStoref);
    SET(BindBuffer);
    SET(DeleteBuffers);
    SET(CallList);
    SET(CallLists);
    SET(NewList);
    SET(EndList);
    SET(DeleteLists);
    SET(GetBooleanv);
    SET(GetIntegerv);
    SET(RenderMode);
    SET(GetFloatv);
    SET(GetDoublev);
    SET(GetLightfv);
    SET(GetMaterialfv);
    SET(GetTexEnvfv);
    SET(GetTexGenfv);
    SET(GetTexParameterfv);
    SET(GetTexParameterIivEXT);
    SET(GetTexParameterIuivEXT);
    SET(GetTexLevelParameteriv);
    SET(GetClipPlane);
    SET(GetPolygonStipple);
    SET(GetTexImage);
    SET(GetCompressedTexImage);
    SET(GetPixelMapfv);
    SET(GetPixelMapuiv);
    SET(GetPixelMapusv);
    SET(GetBufferParameteriv);
    SET(IsEnabled);
    SET(GetError);
    SET(ReadPixels);
    SET(GetShaderiv);
    SET(GetProgramiv);
    SET(GetShaderInfoLog);
    SET(GetProgramInfoLog);
    SET(GetUniformLocation);
    SET(GetUniformfv);
    SET(GetUniformiv);
    SET(GetAttribLocation);
    SET(GetActiveAttrib);
    SET(GetActiveUniform);
    SET(GetAttachedShaders);
    SET(GetShaderSource);
    SET(IsShader);
    SET(IsProgram);
    SET(GetQueryObjectuiv);
    SET(GetQueryObjectiv);
    SET(ActiveTexture);
    SET(TexImage1D);
    SET(TexImage2D);
    SET(TexImage3D);
    SET(BindFramebufferEXT);
    SET(DeleteFramebuffersEXT);
    SET(FramebufferTexture1DEXT);
    SET(FramebufferTexture2DEXT);
    SET(FramebufferTexture3DEXT);
    SET(BindFramebuffer);
    SET(DeleteFramebuffers);
    SET(FramebufferTexture1D);
    SET(FramebufferTexture2D);
    SET(FramebufferTexture3D);
    SET(FramebufferTextureLayer);
    SET(BlitFramebuffer);
    SET(GenerateMipmapEXT);
    SET(GenerateMipmap);
    SET(DrawBuffer);
    SET(DrawBuffers);
    SET(ReadBuffer);
    SET(CopyPixels);
    SET(CopyTexImage1D);
    SET(CopyTexImage2D);
    SET(CopyTexSubImage1D);
    SET(CopyTexSubImage2D);
    SET(CopyTexSubImage3D);
    ts_queries_install(t); /* after the generic routes, which it keeps */

    /* While compiling a list: compiled commands go to the list packer;
     * what GL runs at once takes the normal route (client state also
     * updates the list packer's mirrors). */
    t->record = t->list_table;
    for (int slot = 0; slot < TSR_DISPATCH_COUNT; slot++) {
        const char *name = tsr_dispatch_name(slot);
        int cat = tsr_dispatch_category(slot);
        unsigned flags = tsr_dispatch_flags(slot);
        if (cat == TSR_CAT_CLIENT || (flags & TSR_CMD_LOCAL)) {
            t->rec_tees[slot] = (tsr_tee){.first = t->list_table.slots[slot], .second = t->normal.slots[slot]};
            tsr_dispatch_tee(&t->record, slot, &t->rec_tees[slot]);
        } else if (cat == TSR_CAT_GET || (flags & TSR_CMD_OUTPUT) || immediate_in_list(name)) {
            t->record.slots[slot] = t->normal.slots[slot];
        } else if (!is_current[slot] && !(cat == TSR_CAT_GEOMETRY && is_boxed_geometry(name, flags))) {
            t->rec_hooks[slot] = (tsr_hook){.before = rec_before, .ctx = t};
            tsr_dispatch_hook(&t->record, slot, &t->rec_hooks[slot]);
        } else if (!is_current[slot]) {
            t->rec_hooks[slot] = (tsr_hook){.before = rec_geometry_before, .ctx = t};
            tsr_dispatch_hook(&t->record, slot, &t->rec_hooks[slot]);
        } else if (is_current[slot]) {
            t->rec_hooks[slot] = (tsr_hook){.before = rec_current_before, .ctx = t};
            tsr_dispatch_hook(&t->record, slot, &t->rec_hooks[slot]);
        }
    }
    tsr_set_CallList(&t->record, ts_rec_CallList, t);
    tsr_set_CallLists(&t->record, ts_rec_CallLists, t);
    tsr_set_BindTexture(&t->record, ts_rec_BindTexture, t);
    tsr_set_EndList(&t->record, ts_EndList, t);
}

static void tilesort_destroy(void *instance)
{
    tilesort *t = instance;
    if (!t)
        return;
    if (t->geo)
        ts_flush_geometry(t);
    if (t->client)
        tsr_stream_client_destroy(t->client);
    for (size_t i = 0; t->srv && i < t->nservers; i++) {
        tsr_packer_destroy(t->srv[i].packer);
        free(t->srv[i].lists);
        ts_batch_free(&t->srv[i].sorted);
    }
    for (size_t i = 0; i < t->nlists; i++)
        ts_list_clear(&t->lists[i]);
    free(t->lists);
    tsr_unpacker_destroy(t->replay);
    tsr_unpacker_destroy(t->expand);
    tsr_packer_destroy(t->list_packer);
    tsr_packer_destroy(t->geo);
    tsr_packer_destroy(t->solo_packer);
    tsr_state_tracker_destroy(t->tracker); /* destroys the context and shadows */
    ts_split_destroy(t->split);
    ts_tiling_free(&t->tiling);
    free(t->srv);
    free(t->frame_geometry);
    free(t->hit);
    free(t->targets);
    free(t->buffer_lists);
    ts_batch_free(&t->compact);
    free(t->gathered);
    free(t->materials);
    free(t->fbo_queries);
    free(t->frame_rows);
    free(t->frame_geometry_rows);
    free(t->frame_costs);
    free(t->frame_fault_costs);
    free(t->frame_pixels);
    free(t->frame_seconds);
    free(t->assemble);
    free(t);
}

static void *tilesort_create(const tsr_spu_init *init, tsr_error *err)
{
    size_t count = tsr_options_count(init->options, "servers");
    if (count == 0) {
        tsr_error_set(err, TSR_EINVAL,
                      "%s: option servers is required (e.g. servers=tcp://127.0.0.1:7000,tcp://127.0.0.1:7001)",
                      init->instance_name);
        return NULL;
    }
    tilesort *t = calloc(1, sizeof *t);
    if (!t) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(t->name, sizeof t->name, "%s", init->instance_name);
    t->only_target = TS_ANY_TARGET;
    t->render_mode = GL_RENDER;
    t->nservers = count;
    t->srv = calloc(count, sizeof *t->srv);
    t->frame_geometry = calloc(count, sizeof *t->frame_geometry);
    t->hit = calloc(count, 1);
    t->targets = calloc(count, sizeof *t->targets);
    const char **servers = calloc(count, sizeof *servers);
    size_t ntiles = tsr_options_count(init->options, "tiles");
    const char **tiles = calloc(ntiles ? ntiles : 1, sizeof *tiles);
    if (!t->srv || !t->frame_geometry || !t->hit || !t->targets || !servers || !tiles) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", t->name);
        goto fail;
    }
    for (size_t i = 0; i < count; i++)
        servers[i] = tsr_options_string_at(init->options, "servers", i);
    for (size_t i = 0; i < ntiles; i++)
        tiles[i] = tsr_options_string_at(init->options, "tiles", i);
    const char *bucket = tsr_options_string(init->options, "bucket");
    ts_bucket_mode mode = !strcmp(bucket, "broadcast") ? TS_BROADCAST
                          : !strcmp(bucket, "tiles")   ? TS_TILES
                          : !strcmp(bucket, "balance") ? TS_KD
                          : !strcmp(bucket, "kd")      ? TS_KD
                          : !strcmp(bucket, "union")   ? TS_UNION
                                                       : TS_GRID;
    if (tsr_options_count(init->options, "grid") != 2) {
        tsr_error_set(err, TSR_EINVAL, "%s: option grid takes two numbers (COLUMNS,ROWS)", t->name);
        goto fail;
    }
    t->grid_cols = (int)tsr_options_int_at(init->options, "grid", 0);
    t->grid_rows = (int)tsr_options_int_at(init->options, "grid", 1);
    if ((t->grid_cols == 0) != (t->grid_rows == 0) ||
        (t->grid_cols && (size_t)t->grid_cols * (size_t)t->grid_rows != count)) {
        tsr_error_set(err, TSR_EINVAL, "%s: grid=%d,%d needs %d servers, and there are %zu", t->name, t->grid_cols,
                      t->grid_rows, t->grid_cols * t->grid_rows, count);
        goto fail;
    }
    if (t->grid_cols ? ts_tiling_grid(&t->tiling, t->grid_cols, t->grid_rows, 512, 512, t->name, err) != TSR_OK
                     : ts_tiling_init(&t->tiling, mode, count, tiles, ntiles, t->name, err) != TSR_OK)
        goto fail;
    t->tiling.damping = tsr_options_float(init->options, "damping");
    t->tiling.hysteresis = tsr_options_float(init->options, "hysteresis");
    t->tiling.smoothing = tsr_options_float(init->options, "smoothing");
    t->batch_bytes = (size_t)tsr_options_int(init->options, "batch_bytes");
    const char *assemble = tsr_options_string(init->options, "assemble");
    if (assemble && assemble[0] &&
        tsr_image_check_frame_pattern(t->name, "assemble", assemble,
                                      tsr_options_bool(init->options, "assemble_overwrite"), "assemble_overwrite",
                                      err) != TSR_OK)
        goto fail;
    t->assemble_alpha = tsr_options_bool(init->options, "assemble_alpha");
    if (assemble && assemble[0] && !(t->assemble = strdup(assemble))) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", t->name);
        goto fail;
    }
    tsr_stream_client_config cfg = {.spu = "tilesort", .name = t->name, .servers = servers, .server_count = count};
    tsr_stream_client_config_from_options(&cfg, init->options);
    t->client = tsr_stream_client_connect(&cfg, err);
    if (!t->client)
        goto fail;
    tsr_stream_client_set_stats_extra(t->client, write_sort_first_stats, t);
    tsr_stream_client_set_cost_sink(t->client, take_cost, t);
    if (!(t->tracker = tsr_state_tracker_create(err)) || !(t->ctx = tsr_state_ctx_create(t->tracker, err)) ||
        !(t->split = ts_split_create(err)))
        goto fail;
    for (size_t i = 0; i < count; i++) {
        ts_server *s = &t->srv[i];
        s->ts = t;
        s->index = i;
        if (!(s->shadow = tsr_state_shadow_create(t->tracker, err)))
            goto fail;
        tsr_stream_client_server_sink(t->client, i, &s->inner);
        tsr_pack_sink sink = {.flush = ts_server_sink_flush, .reply = ts_server_sink_reply, .ctx = s};
        /* diffs, lists and requests are small: a quarter of a buffer */
        size_t size = cfg.buffer_size / 4 > TSR_PACK_MIN_BUFFER ? cfg.buffer_size / 4 : TSR_PACK_MIN_BUFFER;
        if (!(s->packer = tsr_packer_create(size, &sink, err)))
            goto fail;
        tsr_dispatch_fill_nop(&s->table);
        tsr_packer_fill_dispatch(s->packer, &s->table);
    }
    tsr_pack_sink geo_sink = {.flush = ts_geo_sink_flush, .reply = no_reply, .ctx = t};
    tsr_pack_sink solo_sink = {.flush = count_solo, .reply = no_reply, .ctx = t};
    if (!(t->solo = tsr_state_shadow_create(t->tracker, err)) ||
        !(t->solo_packer = tsr_packer_create(TSR_PACK_MIN_BUFFER, &solo_sink, err)))
        goto fail;
    tsr_dispatch_fill_nop(&t->solo_table);
    tsr_packer_fill_dispatch(t->solo_packer, &t->solo_table);
    tsr_pack_sink list_sink = {.flush = ts_list_sink_flush, .reply = no_reply, .ctx = t};
    if (!(t->geo = tsr_packer_create(t->batch_bytes, &geo_sink, err)) ||
        !(t->list_packer = tsr_packer_create(cfg.buffer_size, &list_sink, err)))
        goto fail;
    tsr_dispatch_fill_nop(&t->geo_table);
    tsr_packer_fill_dispatch(t->geo, &t->geo_table);
    tsr_dispatch_fill_nop(&t->discard);
    tsr_dispatch_fill_nop(&t->list_table);
    tsr_packer_fill_dispatch(t->list_packer, &t->list_table);
    build_tables(t);
    if (!(t->replay = tsr_unpacker_create(&t->track_table, NULL, NULL, err)) ||
        !(t->expand = tsr_unpacker_create(&t->normal, NULL, NULL, err)))
        goto fail;
    /* tiles known from the options are sent with each server's first buffer */
    if (!TS_BALANCED(mode) && ntiles)
        t->tiling_version = 1;
    ts_snapshot(t);
    t->last_swap = tsr_now_seconds();
    t->live = init->table;
    *t->live = t->normal;
    free(servers);
    free(tiles);
    return t;
fail:
    free(servers);
    free(tiles);
    tilesort_destroy(t);
    return NULL;
}

static const tsr_option_spec tilesort_options[] = {
    {.name = "servers",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "server node addresses in order, comma-separated: tcp://HOST:PORT or unix:PATH (required; "
             "tessera run fills it from the node's to: list)"},
    {.name = "tiles",
     .type = TSR_OPT_STRING_LIST,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "the servers' tiles: SERVER:X:Y:WIDTH:HEIGHT,... (SERVER is the 0-based index in servers; "
             "window pixels, origin bottom-left; tessera run fills it from the servers' tiles:)"},
    {.name = "grid",
     .type = TSR_OPT_INT_LIST,
     .default_value = "0,0",
     .min = 0,
     .max = 256,
     .help = "COLUMNS,ROWS: the servers divide whatever window the program opens into a grid (server "
             "r*COLUMNS+c: column c, row r from the bottom), re-divided at every resize; replaces tiles; "
             "0,0: the tiles as given"},
    {.name = "bucket",
     .type = TSR_OPT_ENUM,
     .default_value = "grid",
     .choices = "grid|tiles|broadcast|kd|union|balance",
     .min = 1,
     .max = 0,
     .help =
         "how geometry finds its servers: grid (tiles form columns and rows; fastest), tiles (test "
         "every tile; any layout), broadcast (every server gets everything); load-balanced, one rectangle "
         "per server re-split every frame: kd (recursive median splits of the cost, Samanta's KD-SPLIT), "
         "union (whole cells of a cost grid, 64 to 128 cells each way, merged greedily into one rectangle per server, "
         "GRID_UNION), balance (an alias of kd). The balanced modes' cost: a per-primitive estimate "
         "(bytes and window-box area of what this frame sent, on that grid) weighted per server "
         "by the render time the servers measure (thread CPU time of their chain per frame, less its "
         "page faults' cost; a server's first frame with geometry is not learnt from) and send "
         "back after each swap; tiles= is ignored"},
    {.name = "batch_bytes",
     .type = TSR_OPT_INT,
     .default_value = "65536",
     .min = 256,
     .max = 67108864.0,
     .help = "geometry is bucketed in batches of about this many bytes (the geometry buffer's size): "
             "smaller batches reach fewer tiles, larger ones cost fewer messages; glDrawArrays/glDrawElements "
             "of points, lines, triangles and quads are sorted primitive by primitive and sent to each "
             "server in draws of about this size; a glBegin/glEnd primitive larger than a batch is cut "
             "into batches, each closed with glEnd and reopened in the next"},
    {.name = "damping",
     .type = TSR_OPT_FLOAT,
     .default_value = "1",
     .min = 0.0,
     .max = 1.0,
     .help = "bucket=kd/union: fraction of the way each split moves towards the balance of the cost per "
             "frame (1: at once)"},
    {.name = "hysteresis",
     .type = TSR_OPT_FLOAT,
     .default_value = "0.1",
     .min = 0.0,
     .max = 10.0,
     .help = "bucket=kd/union: the split is kept while its predicted imbalance (max / mean cost of the "
             "servers) is at most 1 + this, so a static scene settles, and while the servers' measured times "
             "on it are within 1 + 2 x this unless the prediction is above 1 + 3 x this"},
    {.name = "smoothing",
     .type = TSR_OPT_FLOAT,
     .default_value = "0.5",
     .min = 0.01,
     .max = 1.0,
     .help = "bucket=kd/union: weight of a server's newest measured time in its speed (seconds per "
             "estimated unit; 1: the newest only)"},
    {.name = "assemble",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "also gather every frame from the servers and write the whole window as PNG files with "
             "this pattern, one %d for the frame number, e.g. out/wall-%04d.png; each file is written whole "
             "under a temporary name and renamed; a name without %d is refused unless assemble_overwrite=1"},
    {.name = "assemble_overwrite",
     .type = TSR_OPT_BOOL,
     .default_value = "false",
     .min = 1,
     .max = 0,
     .help = "allow an assemble name without %d: every frame replaces the one file, which holds the last frame"},
    {.name = "assemble_alpha",
     .type = TSR_OPT_BOOL,
     .default_value = "false",
     .min = 1,
     .max = 0,
     .help = "write the gathered window's alpha too (RGBA PNGs); false: RGB, what the window shows"},
    TSR_NODE_CLIENT_OPTION_SPECS,
};

static const tsr_spu_class tilesort_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "tilesort",
    .summary = "sort-first: sends each tile server only the geometry that touches its tiles, with the state "
               "it lacks",
    .options = tilesort_options,
    .option_count = sizeof tilesort_options / sizeof tilesort_options[0],
    .create = tilesort_create,
    .destroy = tilesort_destroy,
    /* Tiled servers: the node's to: in order, and every server's tiles:
     * as SERVER:X:Y:W:H in `tiles`, or none and `grid` places them. */
    .network = {.role = TSR_SPU_ROLE_TILED_SERVERS,
                .servers = "servers",
                .server_tiles = "tiles",
                .grid = "grid",
                .token = TSR_NODE_CLIENT_TOKEN_OPTION},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &tilesort_class; }
