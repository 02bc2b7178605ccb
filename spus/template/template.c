/* spus/template — an example SPU for third parties, built out of tree
 * against the installed headers (see README.md). It counts vertices,
 * primitives and swaps, passes every call on, and writes a summary line
 * when destroyed. Owns: its counters (per instance). Never: uses globals —
 * two instances in one process count independently. */
#define _POSIX_C_SOURCE 200809L /* strdup */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <tessera/log.h>
#include <tessera/spu.h>

typedef struct template_spu {
    char name[96];             /* "template#1", for messages */
    const tsr_dispatch *child; /* where calls go next */
    char *output;              /* summary file; "" = standard error */
    bool forward;              /* pass calls to the child */
    unsigned long long vertices, primitives, swaps;
} template_spu;

/* Every function receives the instance it was registered with. */
static void template_Begin(void *self, GLenum mode)
{
    template_spu *t = self;
    t->primitives++;
    if (t->forward)
        tsr_call_Begin(t->child, mode);
}

static void template_Vertex2f(void *self, GLfloat x, GLfloat y)
{
    template_spu *t = self;
    t->vertices++;
    if (t->forward)
        tsr_call_Vertex2f(t->child, x, y);
}

static void template_Vertex3f(void *self, GLfloat x, GLfloat y, GLfloat z)
{
    template_spu *t = self;
    t->vertices++;
    if (t->forward)
        tsr_call_Vertex3f(t->child, x, y, z);
}

static void template_Vertex3fv(void *self, const GLfloat *v)
{
    template_spu *t = self;
    t->vertices++;
    if (t->forward)
        tsr_call_Vertex3fv(t->child, v);
}

static void template_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    template_spu *t = self;
    t->swaps++;
    if (t->forward)
        tsr_call_SwapBuffersTSR(t->child, window, flags);
}

static void *template_create(const tsr_spu_init *init, tsr_error *err)
{
    template_spu *t = calloc(1, sizeof *t);
    if (!t || !(t->output = strdup(tsr_options_string(init->options, "output")))) {
        free(t);
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    snprintf(t->name, sizeof t->name, "%s", init->instance_name);
    t->child = init->child;
    t->forward = tsr_options_bool(init->options, "forward");
    /* Set only what this SPU changes; every other slot is filled from the
     * child by the loader. */
    tsr_set_Begin(init->table, template_Begin, t);
    tsr_set_Vertex2f(init->table, template_Vertex2f, t);
    tsr_set_Vertex3f(init->table, template_Vertex3f, t);
    tsr_set_Vertex3fv(init->table, template_Vertex3fv, t);
    tsr_set_SwapBuffersTSR(init->table, template_SwapBuffersTSR, t);
    return t;
}

static void template_destroy(void *self)
{
    template_spu *t = self;
    FILE *out = t->output[0] ? fopen(t->output, "w") : stderr;
    if (!out) {
        /* destroy cannot fail; say what was lost */
        tsr_log(TSR_LOG_ERROR, "%s: cannot write %s; vertices=%llu primitives=%llu swaps=%llu", t->name, t->output,
                t->vertices, t->primitives, t->swaps);
    } else {
        fprintf(out, "%s: vertices=%llu primitives=%llu swaps=%llu\n", t->name, t->vertices, t->primitives, t->swaps);
        if (out != stderr)
            fclose(out);
    }
    free(t->output);
    free(t);
}

static const tsr_option_spec template_options[] = {
    {.name = "output",
     .type = TSR_OPT_STRING,
     .default_value = "",
     .min = 1,
     .max = 0,
     .help = "file the summary line is written to when the chain ends (empty: standard error)"},
    {.name = "forward",
     .type = TSR_OPT_BOOL,
     .default_value = "true",
     .min = 1,
     .max = 0,
     .help = "pass every call on to the next SPU (false: swallow counted calls)"},
};

static const tsr_spu_class template_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "template",
    .summary = "example out-of-tree SPU: counts vertices, primitives and swaps",
    .options = template_options,
    .option_count = sizeof template_options / sizeof template_options[0],
    .create = template_create,
    .destroy = template_destroy,
    /* Its role in a graph (tessera/spu.h): it sends to no node. A network
     * SPU names its role and the options a graph run fills, e.g. one that
     * streams to one server: {.role = TSR_SPU_ROLE_SERVER, .server =
     * "server", .token = "token"}. */
    .network = {.role = TSR_SPU_ROLE_NONE},
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &template_class; }
