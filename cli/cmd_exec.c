/* cli/cmd_exec.c — `tessera exec [--chain CHAIN | --graph GRAPH [--node
 * NAME]] [--out PATTERN|DIR] -- PROGRAM ARGS...`: runs an unmodified OpenGL
 * program under the faker (faker/: libGL.so.1, libEGL.so.1,
 * libOpenGL.so.0). With a chain it puts the faker's directory first in
 * LD_LIBRARY_PATH, sets TESSERA_CHAIN and then exec()s the program in place
 * of itself: no process stays between the user and the program, so its
 * exit status, the signal that ends it, its standard input, output and
 * error are exactly the program's own. With a graph it is `tessera run
 * GRAPH` with the program as the exec of the app node (--node, or the
 * graph's only one); the node runs it under the faker (mothership/faker.h).
 * Its end passes through there too when it is the run's verdict (it
 * exited non-zero or died by a signal before any node failed): this
 * process exits with its status or dies by its signal; a node's failure
 * gives 1 and the line naming it, as `tessera run` does, and a SIGINT or
 * SIGTERM to this process stops the run and then ends this process by it. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "commands.h"

#ifndef TESSERA_BUILD_FAKER_DIR
#define TESSERA_BUILD_FAKER_DIR ""
#endif
#ifndef TESSERA_INSTALL_FAKER_DIR
#define TESSERA_INSTALL_FAKER_DIR ""
#endif
/* The chain without --chain or TESSERA_CHAIN, {out} the quoted pattern:
 * set with the SPUs (spus/CMakeLists.txt), so this file names none. */
#ifndef TESSERA_EXEC_DEFAULT_CHAIN
#error "TESSERA_EXEC_DEFAULT_CHAIN is defined by cli/CMakeLists.txt"
#endif

static void exec_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera exec [--chain CHAIN] [--out PATTERN] -- PROGRAM [ARGS...]\n"
            "       tessera exec --graph GRAPH [--node NAME] [--out DIR] -- PROGRAM [ARGS...]\n\n"
            "Runs an unmodified OpenGL program (GLX or EGL, e.g. glxgears) with tessera's\n"
            "faker libGL.so.1 / libGLX.so.0 / libEGL.so.1 / libOpenGL.so.0 (and stand-ins\n"
            "for libGLdispatch.so.0 / libGLESv2.so.2) in place of the system's, so no system\n"
            "GL library is loaded: its GL calls enter an SPU chain in its own process; a GL\n"
            "call with no current context does nothing and is logged once. The program\n"
            "replaces this command (exec), so its exit status, signals and standard output\n"
            "and error are its own.\n\n"
            "options:\n"
            "  --chain CHAIN    the SPU chain (default: $TESSERA_CHAIN, else\n"
            "                   \"%s\", {out} = PATTERN)\n"
            "  --out PATTERN    PNG per frame of the default chain, one %%d for the frame\n"
            "                   number (default out/PROGRAM-%%04d.png; out/ is created)\n"
            "  --graph GRAPH    run the graph (as tessera run) with PROGRAM ARGS as the exec\n"
            "                   of its app node; --out DIR is then the run's directory\n"
            "  --node NAME      that app node (default: the graph's only app node)\n"
            "                   With --graph the program's exit status and the signal that\n"
            "                   killed it pass through as well; a failing node (a server,\n"
            "                   a lost connection) gives 1 and one line naming it; SIGINT\n"
            "                   or SIGTERM to tessera exec stops the run, then ends it by\n"
            "                   that signal. Any app\n"
            "                   node whose program is not linked to libtessera_gl runs\n"
            "                   under the faker, also in tessera run.\n"
            "  -h, --help       show this help\n\n"
            "environment: TESSERA_FAKER_DIR overrides where the faker's libraries are\n"
            "(built: %s, installed: %s).\n",
            TESSERA_EXEC_DEFAULT_CHAIN, TESSERA_BUILD_FAKER_DIR, TESSERA_INSTALL_FAKER_DIR);
}

static int has_faker(const char *dir)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/libGL.so.1", dir);
    return dir[0] && access(path, R_OK) == 0;
}

const char *tsr_cli_faker_dir(void)
{
    const char *dir = getenv("TESSERA_FAKER_DIR");
    if (!dir || !dir[0])
        dir = has_faker(TESSERA_BUILD_FAKER_DIR) ? TESSERA_BUILD_FAKER_DIR : TESSERA_INSTALL_FAKER_DIR;
    return has_faker(dir) ? dir : "";
}

void tsr_cli_export_faker_dir(void)
{
    const char *dir = tsr_cli_faker_dir();
    if (dir[0] && !getenv("TESSERA_FAKER_DIR"))
        setenv("TESSERA_FAKER_DIR", dir, 1);
}

int cmd_exec(int argc, char **argv)
{
    const char *chain = NULL, *out = NULL, *graph = NULL, *node = NULL;
    int i = 1;
    for (; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--")) {
            i++;
            break;
        }
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            exec_usage(stdout);
            return TSR_EXIT_OK;
        }
        if (!strcmp(a, "--chain") || !strcmp(a, "--out") || !strcmp(a, "--graph") || !strcmp(a, "--node")) {
            if (i + 1 >= argc) {
                fprintf(stderr, "tessera exec: %s needs a value (see --help)\n", a);
                return TSR_EXIT_USAGE;
            }
            const char **slot = !strcmp(a, "--chain")   ? &chain
                                : !strcmp(a, "--out")   ? &out
                                : !strcmp(a, "--graph") ? &graph
                                                        : &node;
            *slot = argv[++i];
            continue;
        }
        if (a[0] == '-') {
            fprintf(stderr, "tessera exec: unknown option %s (see --help)\n", a);
            return TSR_EXIT_USAGE;
        }
        break; /* the program, without "--" */
    }
    if (i >= argc) {
        fprintf(stderr, "tessera exec: no program given (see --help)\n");
        return TSR_EXIT_USAGE;
    }
    char **program = argv + i;
    if (node && !graph) {
        fprintf(stderr, "tessera exec: --node needs --graph (see --help)\n");
        return TSR_EXIT_USAGE;
    }
    if (graph) {
        if (chain) {
            fprintf(stderr, "tessera exec: --chain and --graph exclude each other: the graph gives the chains\n");
            return TSR_EXIT_USAGE;
        }
        /* The node resolves a relative path against the graph's folder
         * first: a program given on the command line is the user's. */
        char abs[4096];
        if (strchr(program[0], '/') && realpath(program[0], abs))
            program[0] = abs;
        char *run_argv[] = {"exec", (char *)graph, out ? "--out" : NULL, (char *)out, NULL};
        return tsr_cli_run_graph_exec(out ? 4 : 2, run_argv, 1, node, program);
    }

    const char *dir = tsr_cli_faker_dir();
    if (!dir[0]) {
        const char *asked = getenv("TESSERA_FAKER_DIR");
        fprintf(stderr, "tessera exec: the faker's libGL.so.1 is not in %s\n",
                asked && asked[0] ? asked : TESSERA_BUILD_FAKER_DIR);
        return TSR_EXIT_FAIL;
    }

    char default_chain[4200];
    if (!chain && getenv("TESSERA_CHAIN") && getenv("TESSERA_CHAIN")[0])
        chain = getenv("TESSERA_CHAIN");
    if (!chain) {
        char pattern[4096];
        if (out) {
            snprintf(pattern, sizeof pattern, "%s", out);
        } else {
            const char *base = strrchr(program[0], '/');
            snprintf(pattern, sizeof pattern, "out/%s-%%04d.png", base ? base + 1 : program[0]);
            if (mkdir("out", 0777) != 0 && errno != EEXIST) {
                fprintf(stderr, "tessera exec: cannot create directory out: %s\n", strerror(errno));
                return TSR_EXIT_FAIL;
            }
        }
        if (strchr(pattern, '"')) {
            fprintf(stderr, "tessera exec: --out must not contain '\"': %s\n", pattern);
            return TSR_EXIT_USAGE;
        }
        /* TESSERA_EXEC_DEFAULT_CHAIN with each {out} as "PATTERN". */
        size_t used = 0;
        for (const char *t = TESSERA_EXEC_DEFAULT_CHAIN; *t && used < sizeof default_chain - 1;) {
            if (!strncmp(t, "{out}", 5)) {
                used += (size_t)snprintf(default_chain + used, sizeof default_chain - used, "\"%s\"", pattern);
                t += 5;
            } else {
                default_chain[used++] = *t++;
            }
        }
        default_chain[used < sizeof default_chain ? used : sizeof default_chain - 1] = '\0';
        chain = default_chain;
    } else if (out) {
        fprintf(stderr, "tessera exec: --out applies to the default chain only; give output= in --chain\n");
        return TSR_EXIT_USAGE;
    }

    const char *old = getenv("LD_LIBRARY_PATH");
    size_t n = strlen(dir) + (old ? strlen(old) + 1 : 0) + 1;
    char *path = malloc(n);
    if (!path) {
        fprintf(stderr, "tessera exec: out of memory\n");
        return TSR_EXIT_FAIL;
    }
    snprintf(path, n, "%s%s%s", dir, old && old[0] ? ":" : "", old && old[0] ? old : "");
    if (setenv("LD_LIBRARY_PATH", path, 1) != 0 || setenv("TESSERA_CHAIN", chain, 1) != 0) {
        fprintf(stderr, "tessera exec: cannot set the environment: %s\n", strerror(errno));
        free(path);
        return TSR_EXIT_FAIL;
    }
    free(path);
    fflush(NULL);
    execvp(program[0], program);
    int e = errno;
    fprintf(stderr, "tessera exec: cannot run %s: %s\n", program[0], strerror(e));
    return e == ENOENT ? 127 : 126;
}
