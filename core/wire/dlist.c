/* core/wire/dlist.c — the display-list recorder (dlist.h): bodies packed by our
 * own packer into wire buffers, kept per list name in a name map
 * (core/util/map.h), replayed by unpackers (one per nesting level, because
 * a handler of level d starts level d+1 while level d's unpacker is still
 * running). Owns the bodies, its packer and unpackers; never executes a
 * compiled command itself or keeps a host pointer in a body. */
#include "tessera/dev/dlist.h"

#include <stdlib.h>
#include <string.h>

#include "tessera/dev/pack.h"
#include "tessera/dev/pixel.h"
#include "util/map.h"
#include "tessera/dev/unpack.h"

/* Bodies are stored as a sequence of chunks: u64 size, then one wire
 * buffer of that size, padded to 8. 64 KiB buffers: lists are usually
 * small, and a larger command gets a buffer of its own (tessera/dev/pack.h). */
#define BODY_BUFFER (64u * 1024u)

typedef struct body {
    uint8_t *bytes;
    size_t len, cap;
    int pixels_touched;  /* contains PixelStore calls (prefix or the app's) */
    int buffers_touched; /* contains BindBuffer calls */
    uint64_t seq;        /* when it was defined: lists are defined again in that order */
} body;

struct tsr_dlist_store {
    tsr_dispatch live; /* what tsr_dlist_table returns: pass or rec */
    tsr_dispatch next; /* the caller's table, copied */
    tsr_dispatch pass; /* outside a list: next + our list commands */
    tsr_dispatch rec;  /* inside a list: the packer, immediate commands to next */
    tsr_dispatch ptab; /* the recorder packer's own table */
    tsr_dispatch nop;
    uint8_t immediate[TSR_DISPATCH_COUNT];
    int *immediate_slots;
    size_t immediate_count;
    tsr_packer *packer;
    tsr_pixel_store pixels; /* the stream's pixel store (every PixelStore seen) */
    /* the list being recorded */
    GLenum mode;
    GLuint name;
    body cur;
    int failed;         /* out of memory while recording: the body is dropped */
    tsr_name_map lists; /* name -> body (malloc'ed) */
    uint64_t bytes;
    uint64_t defined; /* bodies ended so far (their seq) */
    /* replay */
    tsr_unpacker *level[TSR_DLIST_MAX_NESTING];
    tsr_dispatch *filtered[TSR_DLIST_MAX_NESTING];
    const tsr_dispatch *filtered_from[TSR_DLIST_MAX_NESTING]; /* the `out` it was built from */
    int depth;
};

/* Commands GL runs at once even while compiling a list (OpenGL 2.1 section
 * 5.4), besides every Get* and Is* query, every *Pointer and every
 * tessera *TSR command. Names the spec lacks are skipped. */
static const char *const immediate_names[] = {
    "GenLists",
    "DeleteLists",
    "FeedbackBuffer",
    "SelectBuffer",
    "RenderMode",
    "ClientActiveTexture",
    "InterleavedArrays",
    "EnableClientState",
    "DisableClientState",
    "EnableVertexAttribArray",
    "DisableVertexAttribArray",
    "PushClientAttrib",
    "PopClientAttrib",
    "PixelStoref",
    "PixelStorei",
    "ReadPixels",
    "GenTextures",
    "DeleteTextures",
    "AreTexturesResident",
    "GenQueries",
    "DeleteQueries",
    "GenBuffers",
    "DeleteBuffers",
    "BindBuffer",
    "BufferData",
    "BufferSubData",
    "MapBuffer",
    "UnmapBuffer",
    "MapBufferRange", /* GL 3.0 section 5.4 */
    "FlushMappedBufferRange",
    "CreateProgram",
    "CreateShader",
    "DeleteProgram",
    "DeleteShader",
    "AttachShader",
    "DetachShader",
    "BindAttribLocation",
    "CompileShader",
    "ShaderSource",
    "LinkProgram",
    "ValidateProgram",
    "Finish",
    "Flush",
    "NewList",
    "EndList",
};

static const GLenum pixel_pnames[] = {
    GL_UNPACK_SWAP_BYTES, GL_UNPACK_LSB_FIRST,   GL_UNPACK_ROW_LENGTH,  GL_UNPACK_IMAGE_HEIGHT,
    GL_UNPACK_SKIP_ROWS,  GL_UNPACK_SKIP_PIXELS, GL_UNPACK_SKIP_IMAGES, GL_UNPACK_ALIGNMENT,
    GL_PACK_SWAP_BYTES,   GL_PACK_LSB_FIRST,     GL_PACK_ROW_LENGTH,    GL_PACK_IMAGE_HEIGHT,
    GL_PACK_SKIP_ROWS,    GL_PACK_SKIP_PIXELS,   GL_PACK_SKIP_IMAGES,   GL_PACK_ALIGNMENT,
};
#define UNPACK_PNAMES 8

static int is_immediate(const char *name)
{
    size_t n = strlen(name);
    if (!strncmp(name, "Get", 3) || !strncmp(name, "Is", 2) || (n > 3 && !strcmp(name + n - 3, "TSR")) ||
        (n > 7 && !strcmp(name + n - 7, "Pointer")))
        return 1;
    for (size_t i = 0; i < sizeof immediate_names / sizeof immediate_names[0]; i++)
        if (!strcmp(name, immediate_names[i]))
            return 1;
    return 0;
}

/* --- the map ------------------------------------------------------------ */
static void body_free(body *b)
{
    free(b->bytes);
    memset(b, 0, sizeof *b);
}

/* Installs `b` as the body of `name` (taking its bytes), replacing any old one. */
static int map_put(tsr_dlist_store *s, GLuint name, body *b)
{
    body *old = tsr_name_map_get(&s->lists, name);
    body *nb = old ? old : malloc(sizeof *nb);
    if (!nb || (!old && tsr_name_map_put(&s->lists, name, nb) != 0)) {
        free(nb);
        return -1;
    }
    if (old) {
        s->bytes -= old->len;
        body_free(old);
    }
    *nb = *b;
    s->bytes += b->len;
    memset(b, 0, sizeof *b);
    return 0;
}

static void map_del(tsr_dlist_store *s, GLuint name)
{
    body *b = tsr_name_map_del(&s->lists, name);
    if (b) {
        s->bytes -= b->len;
        body_free(b);
        free(b);
    }
}

/* --- recording ------------------------------------------------------------ */
static int body_append(body *b, const uint8_t *buf, size_t size)
{
    size_t need = b->len + 8 + ((size + 7) & ~(size_t)7);
    if (need > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < need)
            cap *= 2;
        uint8_t *p = realloc(b->bytes, cap);
        if (!p)
            return -1;
        b->bytes = p;
        b->cap = cap;
    }
    uint64_t n = size;
    memcpy(b->bytes + b->len, &n, 8);
    memcpy(b->bytes + b->len + 8, buf, size);
    memset(b->bytes + b->len + 8 + size, 0, need - b->len - 8 - size);
    b->len = need;
    return 0;
}

static int sink_flush(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    tsr_dlist_store *s = ctx;
    if (body_append(&s->cur, buf, size) != 0) {
        s->failed = 1;
        return tsr_error_set(err, TSR_ENOMEM, "display list %u: out of memory", s->name);
    }
    return TSR_OK;
}

/* Only immediate commands have replies, and they never reach the packer. */
static int sink_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)ctx, (void)data, (void)size;
    return tsr_error_set(err, TSR_ESTATE, "display-list recorder: request %u has no reply", id);
}

static void pass_NewList(void *self, GLuint list, GLenum mode)
{
    tsr_dlist_store *s = self;
    if (list && (mode == GL_COMPILE || mode == GL_COMPILE_AND_EXECUTE)) {
        s->mode = mode;
        s->name = list;
        s->failed = 0;
        memset(&s->cur, 0, sizeof s->cur);
        /* A fresh mirror for each body: it decodes from GL's defaults. */
        tsr_pixel_store_init(&s->packer->pixels);
        memset(&s->packer->arrays, 0, sizeof s->packer->arrays);
        s->packer->stack_depth = 0;
        tsr_packer_clear_error(s->packer);
        tsr_pixel_store defaults;
        tsr_pixel_store_init(&defaults);
        for (int i = 0; i < UNPACK_PNAMES; i++) {
            int32_t v = tsr_pixel_store_get(&s->pixels, pixel_pnames[i]);
            if (v != tsr_pixel_store_get(&defaults, pixel_pnames[i])) {
                tsr_call_PixelStorei(&s->ptab, pixel_pnames[i], v);
                s->cur.pixels_touched = 1;
            }
        }
        s->live = s->rec;
    }
    tsr_call_NewList(&s->next, list, mode);
}

static void rec_NewList(void *self, GLuint list, GLenum mode)
{
    /* glNewList inside a list: GL_INVALID_OPERATION, nothing changes. */
    (void)self, (void)list, (void)mode;
}

static void rec_EndList(void *self)
{
    tsr_dlist_store *s = self;
    GLuint name = s->name;
    GLenum mode = s->mode;
    s->cur.seq = s->defined++;
    if (tsr_packer_flush(s->packer) != TSR_OK || s->failed || map_put(s, name, &s->cur) != 0)
        body_free(&s->cur); /* out of memory: the list is lost here (not on the renderers) */
    s->mode = 0;
    s->name = 0;
    s->live = s->pass;
    tsr_call_EndList(&s->next);
    if (mode == GL_COMPILE_AND_EXECUTE) {
        tsr_error ignored = {0};
        tsr_dlist_call(s, name, &s->next, &ignored);
    }
}

static void any_DeleteLists(void *self, GLuint list, GLsizei range)
{
    tsr_dlist_store *s = self;
    if (range > 0) {
        if ((uint64_t)range > s->lists.n) {
            /* Names first: deleting moves the map's entries. */
            GLuint *doomed = malloc((s->lists.n ? s->lists.n : 1) * sizeof *doomed);
            size_t n = 0;
            for (size_t i = 0; doomed && i < s->lists.cap; i++) {
                GLuint k = s->lists.keys[i];
                if (k && k >= list && (uint64_t)(k - list) < (uint64_t)range)
                    doomed[n++] = k;
            }
            for (size_t i = 0; i < n; i++)
                map_del(s, doomed[i]);
            free(doomed);
        } else {
            for (GLsizei i = 0; i < range; i++)
                map_del(s, list + (GLuint)i);
        }
    }
    tsr_call_DeleteLists(&s->next, list, range);
}

static void pass_PixelStoref(void *self, GLenum pname, GLfloat value)
{
    tsr_dlist_store *s = self;
    tsr_pixel_store_set(&s->pixels, pname, value);
    tsr_call_PixelStoref(&s->next, pname, value);
}

static void pass_PixelStorei(void *self, GLenum pname, GLint value)
{
    tsr_dlist_store *s = self;
    tsr_pixel_store_set(&s->pixels, pname, value);
    tsr_call_PixelStorei(&s->next, pname, value);
}

/* Inside a list, immediate commands the recorder packer must also see
 * (its mirrors size the payloads of the commands that follow). */
static void rec_PixelStoref(void *self, GLenum pname, GLfloat value)
{
    tsr_dlist_store *s = self;
    s->cur.pixels_touched = 1;
    tsr_call_PixelStoref(&s->ptab, pname, value);
    pass_PixelStoref(self, pname, value);
}

static void rec_PixelStorei(void *self, GLenum pname, GLint value)
{
    tsr_dlist_store *s = self;
    s->cur.pixels_touched = 1;
    tsr_call_PixelStorei(&s->ptab, pname, value);
    pass_PixelStorei(self, pname, value);
}

static void rec_BindBuffer(void *self, GLenum target, GLuint buffer)
{
    tsr_dlist_store *s = self;
    s->cur.buffers_touched = 1;
    tsr_call_BindBuffer(&s->ptab, target, buffer);
    tsr_call_BindBuffer(&s->next, target, buffer);
}

static void rec_EnableClientState(void *self, GLenum cap)
{
    tsr_dlist_store *s = self;
    tsr_call_EnableClientState(&s->ptab, cap);
    tsr_call_EnableClientState(&s->next, cap);
}

static void rec_DisableClientState(void *self, GLenum cap)
{
    tsr_dlist_store *s = self;
    tsr_call_DisableClientState(&s->ptab, cap);
    tsr_call_DisableClientState(&s->next, cap);
}

static void rec_ClientActiveTexture(void *self, GLenum texture)
{
    tsr_dlist_store *s = self;
    tsr_call_ClientActiveTexture(&s->ptab, texture);
    tsr_call_ClientActiveTexture(&s->next, texture);
}

/* --- life cycle ------------------------------------------------------------ */
tsr_dlist_store *tsr_dlist_create(const tsr_dispatch *next, tsr_error *err)
{
    tsr_dlist_store *s = calloc(1, sizeof *s);
    if (!s) {
        tsr_error_set(err, TSR_ENOMEM, "display-list recorder: out of memory");
        return NULL;
    }
    s->next = *next;
    tsr_dispatch_fill_nop(&s->nop);
    tsr_pixel_store_init(&s->pixels);
    tsr_pack_sink sink = {.flush = sink_flush, .reply = sink_reply, .ctx = s};
    s->packer = tsr_packer_create(BODY_BUFFER, &sink, err);
    s->immediate_slots = malloc(TSR_DISPATCH_COUNT * sizeof *s->immediate_slots);
    if (!s->packer || !s->immediate_slots) {
        if (s->packer)
            tsr_error_set(err, TSR_ENOMEM, "display-list recorder: out of memory");
        tsr_dlist_destroy(s);
        return NULL;
    }
    tsr_packer_fill_dispatch(s->packer, &s->ptab);
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++) {
        const char *name = tsr_dispatch_name(i);
        s->immediate[i] = (uint8_t)(name && is_immediate(name));
        if (s->immediate[i])
            s->immediate_slots[s->immediate_count++] = i;
        s->rec.slots[i] = s->immediate[i] ? s->next.slots[i] : s->ptab.slots[i];
    }
    /* Immediate commands the recorder's mirrors need reach both. The
     * vertex-array pointers reach only the recorder: their values are
     * host addresses of the decoded buffer, meaningless to `next`. */
    tsr_set_VertexPointer(&s->rec, (tsr_fn_VertexPointer)s->ptab.VertexPointer.fn, s->packer);
    tsr_set_NormalPointer(&s->rec, (tsr_fn_NormalPointer)s->ptab.NormalPointer.fn, s->packer);
    tsr_set_ColorPointer(&s->rec, (tsr_fn_ColorPointer)s->ptab.ColorPointer.fn, s->packer);
    tsr_set_TexCoordPointer(&s->rec, (tsr_fn_TexCoordPointer)s->ptab.TexCoordPointer.fn, s->packer);
    tsr_set_EdgeFlagPointer(&s->rec, (tsr_fn_EdgeFlagPointer)s->ptab.EdgeFlagPointer.fn, s->packer);
    tsr_set_VertexAttribPointer(&s->rec, (tsr_fn_VertexAttribPointer)s->ptab.VertexAttribPointer.fn, s->packer);
    tsr_set_SecondaryColorPointer(&s->rec, (tsr_fn_SecondaryColorPointer)s->ptab.SecondaryColorPointer.fn, s->packer);
    tsr_set_FogCoordPointer(&s->rec, (tsr_fn_FogCoordPointer)s->ptab.FogCoordPointer.fn, s->packer);
    tsr_set_IndexPointer(&s->rec, (tsr_fn_IndexPointer)s->ptab.IndexPointer.fn, s->packer);
    s->rec.EnableVertexAttribArray = s->ptab.EnableVertexAttribArray;
    s->rec.DisableVertexAttribArray = s->ptab.DisableVertexAttribArray;
    tsr_set_EnableClientState(&s->rec, rec_EnableClientState, s);
    tsr_set_DisableClientState(&s->rec, rec_DisableClientState, s);
    tsr_set_ClientActiveTexture(&s->rec, rec_ClientActiveTexture, s);
    tsr_set_PixelStoref(&s->rec, rec_PixelStoref, s);
    tsr_set_PixelStorei(&s->rec, rec_PixelStorei, s);
    tsr_set_BindBuffer(&s->rec, rec_BindBuffer, s);
    tsr_set_NewList(&s->rec, rec_NewList, s);
    tsr_set_EndList(&s->rec, rec_EndList, s);
    tsr_set_DeleteLists(&s->rec, any_DeleteLists, s);

    s->pass = s->next;
    tsr_set_NewList(&s->pass, pass_NewList, s);
    tsr_set_DeleteLists(&s->pass, any_DeleteLists, s);
    tsr_set_PixelStoref(&s->pass, pass_PixelStoref, s);
    tsr_set_PixelStorei(&s->pass, pass_PixelStorei, s);
    s->live = s->pass;
    return s;
}

void tsr_dlist_destroy(tsr_dlist_store *s)
{
    if (!s)
        return;
    for (size_t i = 0; i < s->lists.cap; i++)
        if (s->lists.keys[i]) {
            body_free(s->lists.vals[i]);
            free(s->lists.vals[i]);
        }
    tsr_name_map_free(&s->lists);
    body_free(&s->cur);
    for (int d = 0; d < TSR_DLIST_MAX_NESTING; d++) {
        tsr_unpacker_destroy(s->level[d]);
        free(s->filtered[d]);
    }
    tsr_packer_destroy(s->packer);
    free(s->immediate_slots);
    free(s);
}

const tsr_dispatch *tsr_dlist_table(tsr_dlist_store *s) { return &s->live; }
GLenum tsr_dlist_recording(const tsr_dlist_store *s) { return s->mode; }
size_t tsr_dlist_count(const tsr_dlist_store *s) { return s->lists.n; }
int tsr_dlist_has(const tsr_dlist_store *s, GLuint list) { return tsr_name_map_get(&s->lists, list) != NULL; }
uint64_t tsr_dlist_bytes(const tsr_dlist_store *s) { return s->bytes; }

/* --- replay ---------------------------------------------------------------- */
/* Runs every chunk of `b` through `u` (whose target is already set). */
static int run_body(tsr_unpacker *u, const body *b, tsr_error *err)
{
    for (size_t pos = 0; pos + 8 <= b->len;) {
        uint64_t size;
        memcpy(&size, b->bytes + pos, 8);
        int rc = tsr_unpacker_run(u, b->bytes + pos + 8, (size_t)size, err);
        if (rc != TSR_OK && rc != TSR_UNPACK_YIELDED)
            return rc;
        pos += 8 + (((size_t)size + 7) & ~(size_t)7);
    }
    return TSR_OK;
}

int tsr_dlist_call(tsr_dlist_store *s, GLuint list, const tsr_dispatch *out, tsr_error *err)
{
    const body *e = tsr_name_map_get(&s->lists, list);
    if (!e || s->depth >= TSR_DLIST_MAX_NESTING)
        return TSR_OK;
    int d = s->depth;
    if (!s->filtered[d])
        s->filtered[d] = malloc(sizeof *s->filtered[d]);
    if (s->filtered[d] && !s->level[d])
        s->level[d] = tsr_unpacker_create(s->filtered[d], NULL, NULL, err);
    if (!s->filtered[d] || !s->level[d])
        return err->code ? err->code : tsr_error_set(err, TSR_ENOMEM, "display list %u: out of memory", list);
    tsr_dispatch *f = s->filtered[d];
    if (s->filtered_from[d] != out) {
        /* Built once per caller table: a text renderer calls thousands of
         * lists a frame. */
        *f = *out;
        for (size_t i = 0; i < s->immediate_count; i++)
            f->slots[s->immediate_slots[i]] = s->nop.slots[s->immediate_slots[i]];
        s->filtered_from[d] = out;
    }
    tsr_unpacker *u = s->level[d];
    u->target = f;
    /* A fresh pixel mirror, as the body's recorder had. */
    tsr_pixel_store_init(&u->pixels);
    /* Copy the body: a nested call cannot change the map, but `out` could
     * (a caller defining lists from inside a call), so keep our bytes. */
    body b = *e;
    s->depth++;
    int rc = run_body(u, &b, err);
    s->depth--;
    return rc;
}

typedef struct named_body {
    GLuint name;
    const body *b;
} named_body;

static int by_seq(const void *a, const void *b)
{
    uint64_t x = ((const named_body *)a)->b->seq, y = ((const named_body *)b)->b->seq;
    return x < y ? -1 : x > y;
}

long tsr_dlist_define_all(tsr_dlist_store *s, const tsr_dispatch *out, tsr_error *err)
{
    /* In the order the application defined them: a renderer compiles each
     * list in the same context as the others did. */
    named_body *order = malloc((s->lists.n ? s->lists.n : 1) * sizeof *order);
    tsr_unpacker *u = order ? tsr_unpacker_create(out, NULL, NULL, err) : NULL;
    if (!u) {
        if (!order)
            tsr_error_set(err, TSR_ENOMEM, "display lists: out of memory");
        free(order);
        return -1;
    }
    size_t n = 0;
    for (size_t i = 0; i < s->lists.cap; i++)
        if (s->lists.keys[i])
            order[n++] = (named_body){s->lists.keys[i], s->lists.vals[i]};
    qsort(order, n, sizeof *order, by_seq);
    tsr_pixel_store defaults;
    tsr_pixel_store_init(&defaults);
    long defined = 0;
    for (size_t i = 0; i < n; i++) {
        const body *e = order[i].b;
        tsr_pixel_store_init(&u->pixels);
        tsr_call_NewList(out, order[i].name, GL_COMPILE);
        int rc = run_body(u, e, err);
        tsr_call_EndList(out);
        if (rc != TSR_OK) {
            tsr_unpacker_destroy(u);
            free(order);
            return -1;
        }
        /* Pixel store and bindings run at once even inside NewList: put
         * them back, so the next body decodes from the defaults too and
         * the renderer holds GL's initial values for the diff. */
        if (e->pixels_touched)
            for (size_t k = 0; k < sizeof pixel_pnames / sizeof pixel_pnames[0]; k++)
                tsr_call_PixelStorei(out, pixel_pnames[k], tsr_pixel_store_get(&defaults, pixel_pnames[k]));
        if (e->buffers_touched) {
            tsr_call_BindBuffer(out, GL_ARRAY_BUFFER, 0);
            tsr_call_BindBuffer(out, GL_ELEMENT_ARRAY_BUFFER, 0);
        }
        defined++;
    }
    tsr_unpacker_destroy(u);
    free(order);
    return defined;
}
