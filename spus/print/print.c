/* spus/print/print.c — the "print" SPU: writes one readable line per GL call
 * (generated tracer, enums by name) to a file, stdout or stderr, and
 * forwards every call unchanged to its child. floats=hex writes every float
 * with %a, so two traces can be compared bit for bit (%g keeps 6 digits,
 * and a matrix or light position that differs in its last bit looks equal).
 * Owns its output file; never changes, drops or reorders a call. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/spu.h"
#include "trace_gen.h"

typedef struct print_spu {
    tsr_tracer tracer;
    FILE *file;
    int owns_file;
} print_spu;

static void *print_create(const tsr_spu_init *init, tsr_error *err)
{
    const char *path = tsr_options_string(init->options, "file");
    print_spu *s = calloc(1, sizeof *s);
    if (!s) {
        tsr_error_set(err, TSR_ENOMEM, "%s: out of memory", init->instance_name);
        return NULL;
    }
    if (!path || !strcmp(path, "-") || !strcmp(path, "stderr")) {
        s->file = stderr;
    } else if (!strcmp(path, "stdout")) {
        s->file = stdout;
    } else {
        s->file = fopen(path, "w");
        if (!s->file) {
            tsr_error_set(err, TSR_EIO, "%s: cannot open file=%s: %s", init->instance_name, path, strerror(errno));
            free(s);
            return NULL;
        }
        s->owns_file = 1;
    }
    s->tracer.out = s->file;
    s->tracer.child = init->child;
    s->tracer.hex_floats = !strcmp(tsr_options_string(init->options, "floats"), "hex");
    tsr_trace_fill(init->table, &s->tracer);
    return s;
}

static void print_destroy(void *instance)
{
    print_spu *s = instance;
    if (!s)
        return;
    if (s->owns_file)
        fclose(s->file);
    else
        fflush(s->file);
    free(s);
}

static const tsr_option_spec print_options[] = {
    {.name = "file",
     .type = TSR_OPT_STRING,
     .default_value = "-",
     .min = 1,
     .max = 0,
     .help = "where to write the trace: a path, \"stdout\", or \"-\"/\"stderr\""},
    {.name = "floats",
     .type = TSR_OPT_ENUM,
     .default_value = "g",
     .choices = "g|hex",
     .min = 1,
     .max = 0,
     .help = "how floats are written: g (printf %g, 6 significant digits) or hex (printf %a: every bit, so "
             "traces compare exactly)"},
};

static const tsr_spu_class print_class = {
    .abi = TSR_SPU_ABI,
    .dispatch_count = TSR_DISPATCH_COUNT,
    .name = "print",
    .summary = "writes one line per GL call (enums by name), then forwards it",
    .options = print_options,
    .option_count = sizeof print_options / sizeof print_options[0],
    .create = print_create,
    .destroy = print_destroy,
};

TSR_SPU_EXPORT const tsr_spu_class *tsr_spu_describe(void) { return &print_class; }
