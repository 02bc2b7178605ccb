/* tests/graph/graph_limits_test.c — hostile graph files against the real
 * `tessera check` and `tessera dot` binaries, run as child processes:
 * long chains of edges (no recursion to overflow the stack), many tiles
 * and many nodes (checks in n log n), and the limits on nesting, node
 * count, anchors, alias expansion and file size, each refused with exit 2
 * and one line naming the limit. Every file is generated here. Time is
 * bounded by the ctest TIMEOUT only; nothing here measures it.
 * usage: graph_limits_test TESSERA CASE
 * Owns: its temporary folder. Never: reads a graph it did not write. */
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"

static const char *tessera;
static char dir[] = "/tmp/tessera-graph-limits-XXXXXX";

typedef struct result {
    int status;    /* exit status, or 128 + signal */
    long max_rss;  /* KiB */
    char *out;     /* stdout, whole */
    char *err;     /* stderr, whole */
    int err_lines; /* lines on stderr */
} result;

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    REQUIRE(f, "cannot open %s", path);
    size_t cap = 4096, len = 0;
    char *s = malloc(cap);
    REQUIRE(s);
    for (size_t got; (got = fread(s + len, 1, cap - len - 1, f)) > 0;) {
        len += got;
        if (cap - len - 1 == 0) {
            cap *= 2;
            s = realloc(s, cap);
            REQUIRE(s);
        }
    }
    fclose(f);
    s[len] = '\0';
    return s;
}

/* Runs `tessera COMMAND [FLAG] FILE`, its output in files of the folder. */
static result run(const char *command, const char *flag, const char *file)
{
    char out_path[256], err_path[256];
    snprintf(out_path, sizeof out_path, "%s/stdout", dir);
    snprintf(err_path, sizeof err_path, "%s/stderr", dir);
    fflush(NULL);
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        int out = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int err = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (out < 0 || err < 0)
            _exit(120);
        dup2(out, STDOUT_FILENO);
        dup2(err, STDERR_FILENO);
        if (flag)
            execl(tessera, tessera, command, flag, file, (char *)NULL);
        else
            execl(tessera, tessera, command, file, (char *)NULL);
        _exit(121);
    }
    int status;
    struct rusage usage;
    REQUIRE(wait4(pid, &status, 0, &usage) == pid);
    result r = {0};
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.max_rss = usage.ru_maxrss;
    r.out = slurp(out_path);
    r.err = slurp(err_path);
    for (const char *p = r.err; *p; p++)
        r.err_lines += *p == '\n';
    printf("tessera %s%s%s %s: exit %d, max RSS %ld KiB, stderr: %s", command, flag ? " " : "", flag ? flag : "", file,
           r.status, r.max_rss, r.err[0] ? r.err : "(none)\n");
    return r;
}

static void result_free(result *r)
{
    free(r->out);
    free(r->err);
}

static char *path_of(const char *name)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return path;
}

static FILE *create(const char *name)
{
    FILE *f = fopen(path_of(name), "w");
    REQUIRE(f, "cannot create %s: %s", path_of(name), strerror(errno));
    return f;
}

/* The graph is refused by check and dot: exit 2, one line on stderr that
 * names the file and contains `text`, nothing on stdout. */
static void expect_refused(const char *name, const char *flag, const char *text)
{
    static const char *const commands[] = {"check", "dot"};
    for (size_t c = 0; c < 2; c++) {
        result r = run(commands[c], flag, path_of(name));
        CHECK(r.status == 2, "exit %d", r.status);
        CHECK(r.err_lines == 1, "%d lines on stderr", r.err_lines);
        CHECK(!r.out[0], "stdout: %s", r.out);
        CHECK_CONTAINS(r.err, path_of(name));
        CHECK_CONTAINS(r.err, text);
        result_free(&r);
    }
}

/* The graph is accepted by check (its summary contains `summary`) and
 * drawn by dot (its output contains `dot_text`). */
static void expect_accepted(const char *name, const char *flag, const char *summary, const char *dot_text)
{
    result r = run("check", flag, path_of(name));
    CHECK(r.status == 0, "exit %d", r.status);
    CHECK_CONTAINS(r.out, summary);
    result_free(&r);
    r = run("dot", flag, path_of(name));
    CHECK(r.status == 0, "exit %d", r.status);
    CHECK_CONTAINS(r.out, dot_text);
    result_free(&r);
}

/* app -> n1 -> n2 -> ... -> nN: every server but the last relays with a
 * network SPU, so the edges form one path as long as the graph. */
static void chain_of_20000_nodes_is_checked_and_drawn(void)
{
    const int n = 20000;
    FILE *f = create("chain.yaml");
    fprintf(f, "version: 1\nnodes:\n  n0:\n    exec: bin/spheres\n    chain: [pack]\n    to: n1\n");
    for (int i = 1; i < n; i++)
        fprintf(f, "  n%d:\n    chain: [pack]\n    to: n%d\n", i, i + 1);
    fprintf(f, "  n%d:\n    chain: [render]\n", n);
    fclose(f);
    expect_accepted("chain.yaml", NULL, "ok: 20001 nodes, 20000 edges", "\"n19999\" -> \"n20000\"");
}

/* The same path closed into a cycle at its far end. */
static void cycle_through_20000_nodes_is_named(void)
{
    const int n = 20000;
    FILE *f = create("cycle.yaml");
    fprintf(f, "version: 1\nnodes:\n  n0:\n    exec: bin/spheres\n    chain: [pack]\n    to: n1\n");
    for (int i = 1; i < n; i++)
        fprintf(f, "  n%d:\n    chain: [pack]\n    to: n%d\n", i, i + 1);
    fprintf(f, "  n%d:\n    chain: [pack]\n    to: n1\n", n);
    fclose(f);
    expect_refused("cycle.yaml", NULL, "node 'n20000': 'to' closes a cycle: n1 -> n2 -> ");
}

/* 512x256 one-pixel tiles on one server: 131,072 tiles, none overlapping;
 * then the same with one more tile that covers another. */
static void write_tiles(const char *name, bool extra)
{
    FILE *f = create(name);
    fprintf(f, "version: 1\nwindow: {width: 512, height: 256}\nnodes:\n"
               "  app:\n    exec: bin/spheres\n    chain: [tilesort]\n    to: wall\n"
               "  wall:\n    chain: [render]\n    tiles:\n");
    for (int y = 0; y < 256; y++)
        for (int x = 0; x < 512; x++)
            fprintf(f, "      - [%d, %d, 1, 1]\n", x, y);
    if (extra)
        fprintf(f, "      - [300, 200, 2, 1]\n");
    fclose(f);
}

static void tiles_131072_one_pixel_are_checked(void)
{
    write_tiles("tiles.yaml", false);
    expect_accepted("tiles.yaml", NULL, "ok: 2 nodes, 1 edge, window 512x256", "\"wall\"");
    write_tiles("tiles_overlap.yaml", true);
    expect_refused("tiles_overlap.yaml", NULL,
                   "node 'wall': 'tiles': tile 131073 [300, 200, 2, 1] overlaps tile 102701 [300, 200, 1, 1]");
}

/* One app replicating to `servers` servers: every name is looked up. */
static void write_fan_out(const char *name, int servers, bool duplicate_last)
{
    FILE *f = create(name);
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: bin/spheres\n    chain: [replicate]\n    to: [s0");
    for (int i = 1; i < servers; i++)
        fprintf(f, ", s%d", duplicate_last && i == servers - 1 ? 1 : i);
    fprintf(f, "]\n");
    for (int i = 0; i < servers; i++)
        fprintf(f, "  s%d:\n    chain: [render]\n", duplicate_last && i == servers - 1 ? 1 : i);
    fclose(f);
}

static void nodes_100002_refused_at_the_node_limit(void)
{
    write_fan_out("nodes.yaml", 100001, false);
    expect_refused("nodes.yaml", NULL, "nodes.yaml:2:1: 'nodes': 100002 nodes, more than the limit of 65536");
}

static void nodes_65536_at_the_limit_are_checked(void)
{
    write_fan_out("nodes_at_limit.yaml", 65535, false);
    expect_accepted("nodes_at_limit.yaml", NULL, "ok: 65536 nodes, 65535 edges", "\"app\" -> \"s65534\"");
    /* The last of them named twice: found, with where it was first. */
    write_fan_out("nodes_duplicate.yaml", 65535, true);
    expect_refused("nodes_duplicate.yaml", NULL, "duplicate node name 's1' (first defined at 9:3)");
}

static void nesting_100000_deep_refused_at_the_depth_limit(void)
{
    FILE *f = create("deep.yaml");
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: bin/spheres\n    chain: [render]\nx: ");
    for (int i = 0; i < 100000; i++)
        fputc('[', f);
    for (int i = 0; i < 100000; i++)
        fputc(']', f);
    fputc('\n', f);
    fclose(f);
    expect_refused("deep.yaml", NULL, "deep.yaml:6:67: lists and mappings nested more than 64 deep (the limit)");
}

/* 50 MB of graph text (a sparse file: nothing to write): refused from its
 * size before it is read, so the child never holds it. */
static void file_of_50_mb_refused_before_it_is_read(void)
{
    FILE *f = create("big.yaml");
    fprintf(f, "version: 1\nnodes:\n");
    REQUIRE(ftruncate(fileno(f), 50000000) == 0);
    fclose(f);
    expect_refused("big.yaml", NULL, "big.yaml: 50000000 bytes, more than the limit of 4194304 bytes (4 MiB)");
    result r = run("check", NULL, path_of("big.yaml"));
    CHECK(r.max_rss < 50000000 / 1024, "the child grew to %ld KiB", r.max_rss);
    result_free(&r);
}

static void anchors_257_refused_at_the_anchor_limit(void)
{
    FILE *f = create("anchors.yaml");
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: bin/spheres\n    chain: [render]\nx:\n");
    for (int i = 0; i < 257; i++)
        fprintf(f, "  - &a%d %d\n", i, i);
    fclose(f);
    expect_refused("anchors.yaml", NULL, "anchors.yaml:263:5: more than 256 anchors (&name), the limit");
}

/* A 1.2 MB list named once and used by 20 nodes expands to about 24 MB. */
static void alias_expansion_refused_past_twice_the_file_limit(void)
{
    FILE *f = create("aliases.yaml");
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: &args [bin/spheres");
    for (int i = 0; i < 200000; i++)
        fprintf(f, ", abcd");
    fprintf(f, "]\n    chain: [render]\n");
    for (int i = 0; i < 20; i++)
        fprintf(f, "  app%d: {exec: *args, chain: [render]}\n", i);
    fclose(f);
    expect_refused("aliases.yaml", NULL,
                   "aliases expand the graph past 8388608 YAML nodes and scalar bytes (the limit, twice the file "
                   "size limit)");
    /* Aliases that stay within it are fine, and so is one used inside its
     * own anchor's siblings; one inside its own anchor is not. */
    f = create("aliases_ok.yaml");
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: &args [bin/spheres, --frames, '2']\n"
               "    chain: &chain [render]\n  app2: {exec: *args, chain: *chain}\n");
    fclose(f);
    expect_accepted("aliases_ok.yaml", NULL, "ok: 2 nodes, 0 edges", "\"app2\"");
    f = create("alias_self.yaml");
    fprintf(f, "version: 1\nnodes: &all\n  app:\n    exec: [bin/spheres, *all]\n    chain: [render]\n");
    fclose(f);
    expect_refused("alias_self.yaml", NULL, "alias_self.yaml:4:25: alias *all is inside its own anchor");
}

/* What execve would refuse at run time is refused by check: one argument
 * of 128 KiB, or arguments of more than 1 MiB together. */
static void exec_arguments_execve_refuses_are_refused(void)
{
    FILE *f = create("long_argument.yaml");
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: [/bin/true, ");
    for (int i = 0; i < 131072; i++)
        fputc('x', f);
    fprintf(f, "]\n    chain: [render]\n");
    fclose(f);
    expect_refused("long_argument.yaml", NULL,
                   "long_argument.yaml:4:23: node 'app': 'exec': argument 2 is 131072 bytes, the limit is 131071");
    f = create("many_arguments.yaml");
    fprintf(f, "version: 1\nnodes:\n  app:\n    exec: /bin/true");
    for (int i = 0; i < 20; i++) {
        fputc(' ', f);
        for (int j = 0; j < 60000; j++)
            fputc('x', f);
    }
    fprintf(f, "\n    chain: [render]\n");
    fclose(f);
    expect_refused("many_arguments.yaml", NULL,
                   "many_arguments.yaml:4:11: node 'app': 'exec': 1200206 bytes of arguments, more than the limit "
                   "of 1048576");
}

static void directory_is_named_a_directory(void) { expect_refused(".", NULL, "is a directory, not a graph file"); }

static const struct {
    const char *name;
    void (*run)(void);
} cases[] = {
    {"chain_of_20000_nodes_is_checked_and_drawn", chain_of_20000_nodes_is_checked_and_drawn},
    {"cycle_through_20000_nodes_is_named", cycle_through_20000_nodes_is_named},
    {"tiles_131072_one_pixel_are_checked", tiles_131072_one_pixel_are_checked},
    {"nodes_100002_refused_at_the_node_limit", nodes_100002_refused_at_the_node_limit},
    {"nodes_65536_at_the_limit_are_checked", nodes_65536_at_the_limit_are_checked},
    {"nesting_100000_deep_refused_at_the_depth_limit", nesting_100000_deep_refused_at_the_depth_limit},
    {"file_of_50_mb_refused_before_it_is_read", file_of_50_mb_refused_before_it_is_read},
    {"anchors_257_refused_at_the_anchor_limit", anchors_257_refused_at_the_anchor_limit},
    {"alias_expansion_refused_past_twice_the_file_limit", alias_expansion_refused_past_twice_the_file_limit},
    {"exec_arguments_execve_refuses_are_refused", exec_arguments_execve_refuses_are_refused},
    {"directory_is_named_a_directory", directory_is_named_a_directory},
};

static void remove_folder(void)
{
    char command[300];
    snprintf(command, sizeof command, "rm -rf '%s'", dir);
    if (system(command) != 0)
        fprintf(stderr, "cannot remove %s\n", dir);
}

int main(int argc, char **argv)
{
    REQUIRE(argc == 3, "usage: graph_limits_test TESSERA CASE");
    tessera = argv[1];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (strcmp(argv[2], cases[i].name))
            continue;
        REQUIRE(mkdtemp(dir), "mkdtemp: %s", strerror(errno));
        cases[i].run();
        remove_folder();
        return harness_failures ? 1 : 0;
    }
    fprintf(stderr, "unknown case '%s'\n", argv[2]);
    return 2;
}
