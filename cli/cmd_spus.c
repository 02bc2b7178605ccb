/* cli/cmd_spus.c — `tessera spus [NAME...]`: lists every SPU the loader
 * can find (or the named ones) with its summary, super SPU, options
 * (type, range or choices, default, help) and network role (tessera/spu.h:
 * what its node's to: means, and which options a graph run fills). Owns: output formatting only.
 * Never: creates SPU instances. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"
#include "tessera/spu.h"

#define MAX_SUPER_LEVELS 8

static void print_usage(FILE *out)
{
    fprintf(out, "usage: tessera spus [NAME...]\n\n"
                 "Lists the SPUs tessera can find (registered, TESSERA_SPU_PATH, the build tree,\n"
                 "then the install prefix), or only the named ones, with each SPU's summary,\n"
                 "super SPU and options (name, type, range or choices, default and help), and\n"
                 "its role in a graph: whether it sends to one server, several, tiled servers,\n"
                 "a display or a group of peers, and which options a graph run fills.\n"
                 "Options are given in a chain as NAME key=value (see tessera/chain.h).\n\n"
                 "  -h, --help   show this help\n\n"
                 "Exit codes: 0 ok, 1 an SPU failed to load, 2 unknown SPU or bad arguments.\n");
}

static bool is_list(tsr_option_type type)
{
    return type == TSR_OPT_INT_LIST || type == TSR_OPT_FLOAT_LIST || type == TSR_OPT_STRING_LIST;
}

static bool is_numeric(tsr_option_type type)
{
    return type == TSR_OPT_INT || type == TSR_OPT_FLOAT || type == TSR_OPT_INT_LIST || type == TSR_OPT_FLOAT_LIST;
}

/* "    width (int in [1, 16384], default 1024)\n        window width\n" */
static void print_option(const tsr_option_spec *o)
{
    printf("    %s (%s", o->name, tsr_option_type_name(o->type));
    if (o->type == TSR_OPT_ENUM)
        printf(": %s", o->choices ? o->choices : "");
    if (is_numeric(o->type) && o->min <= o->max)
        printf("%s in [%.15g, %.15g]", is_list(o->type) ? ", elements" : "", o->min, o->max);
    if (is_list(o->type))
        printf(", comma-separated");
    if (o->default_value && o->default_value[0])
        printf(", default %s", o->default_value);
    else if (o->type == TSR_OPT_STRING || is_list(o->type))
        printf(", default empty");
    else if (!o->default_value)
        printf(", no default");
    printf(")\n        %s\n", o->help && o->help[0] ? o->help : "(no help text)");
}

static bool declared_by(const tsr_spu_class *cls, const char *name)
{
    for (size_t i = 0; i < cls->option_count; i++)
        if (!strcmp(cls->options[i].name, name))
            return true;
    return false;
}

/* "  role: server (streams to ...)" and the options a graph run fills. */
static void print_role(const tsr_spu_class *cls)
{
    const tsr_spu_network *n = &cls->network;
    printf("  role: %s (%s)\n", tsr_spu_role_name(n->role), tsr_spu_role_summary(n->role));
    const struct {
        const char *option, *what;
    } filled[] = {
        {n->server, "the server's address"},   {n->servers, "the servers' addresses"},
        {n->display, "the display's address"}, {n->token, "the run's token"},
        {n->tiles, "the node's own tiles"},    {n->server_tiles, "every server's tiles"},
        {n->rank, "the node's rank"},          {n->peers, "the peers' addresses"},
    };
    size_t shown = 0;
    for (size_t i = 0; i < sizeof filled / sizeof filled[0]; i++) {
        if (!filled[i].option)
            continue;
        printf("%s%s (%s)", shown ? ", " : "  a graph run fills: ", filled[i].option, filled[i].what);
        shown++;
    }
    if (shown)
        printf("\n");
    if (n->grid)
        printf("  %s: [COLUMNS, ROWS] places the servers instead of their tiles: (one per cell)\n", n->grid);
}

static void print_class(const tsr_spu_class *cls)
{
    printf("%s", cls->name);
    if (cls->super)
        printf(" (inherits %s)", cls->super);
    printf("\n  %s\n", cls->summary && cls->summary[0] ? cls->summary : "(no summary)");
    if (cls->option_count == 0)
        printf("  options: none of its own\n");
    else
        printf("  options:\n");
    for (size_t i = 0; i < cls->option_count; i++)
        print_option(&cls->options[i]);

    /* Options a super declares are accepted too; show the ones this SPU
     * does not re-declare, nearest super first. */
    const tsr_spu_class *seen[MAX_SUPER_LEVELS + 1] = {cls};
    size_t levels = 1;
    for (const char *super = cls->super; super && levels <= MAX_SUPER_LEVELS;) {
        tsr_error err;
        tsr_error_clear(&err);
        const tsr_spu_class *s = tsr_spu_find(super, &err);
        if (!s) {
            printf("  inherited options: unavailable (%s)\n", err.message);
            break;
        }
        bool header = false;
        for (size_t i = 0; i < s->option_count; i++) {
            bool overridden = false;
            for (size_t l = 0; l < levels; l++)
                overridden |= declared_by(seen[l], s->options[i].name);
            if (overridden)
                continue;
            if (!header)
                printf("  inherited from %s:\n", s->name);
            header = true;
            print_option(&s->options[i]);
        }
        seen[levels++] = s;
        super = s->super;
    }
    print_role(cls);
}

int cmd_spus(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            print_usage(stdout);
            return TSR_EXIT_OK;
        }
        if (argv[i][0] == '-') {
            fprintf(stderr, "tessera spus: unknown option '%s' (see tessera spus --help)\n", argv[i]);
            return TSR_EXIT_USAGE;
        }
    }

    if (argc > 1) {
        int status = TSR_EXIT_OK;
        for (int i = 1; i < argc; i++) {
            tsr_error err;
            tsr_error_clear(&err);
            const tsr_spu_class *cls = tsr_spu_find(argv[i], &err);
            if (!cls) {
                fprintf(stderr, "tessera spus: %s\n", err.message);
                int code = err.code == TSR_ENOENT || err.code == TSR_EINVAL ? TSR_EXIT_USAGE : TSR_EXIT_FAIL;
                if (code > status)
                    status = code;
                continue;
            }
            if (i > 1)
                printf("\n");
            print_class(cls);
        }
        return status;
    }

    char path[8192];
    printf("search path: %s\n", tsr_spu_search_path(path, sizeof path));
    /* One listing normally suffices (each call loads and checks every
     * plugin on the path); ask again only if there were more than room. */
    size_t room = 256;
    const tsr_spu_class **classes = calloc(room, sizeof *classes);
    size_t listed = classes ? tsr_spu_list(classes, room) : 0;
    if (classes && listed > room) {
        room = listed;
        const tsr_spu_class **grown = realloc(classes, room * sizeof *grown);
        if (grown)
            classes = grown;
        listed = grown ? tsr_spu_list(classes, room) : room;
        if (listed > room)
            listed = room; /* registered meanwhile: print what fits */
    }
    if (!classes) {
        fprintf(stderr, "tessera spus: out of memory\n");
        return TSR_EXIT_FAIL;
    }
    if (listed == 0)
        printf("no SPUs found\n");
    for (size_t i = 0; i < listed; i++) {
        printf("\n");
        print_class(classes[i]);
    }
    free(classes);
    return TSR_EXIT_OK;
}
