/* cli/cmd_replay.c — `tessera replay FILE [--chain CHAIN | --graph GRAPH]
 * [--loop N] [--frames A-B] [--exact-answers]` and `tessera replay --info
 * FILE`: feeds a capture file (the capture SPU's, spus/capture/capfile.h)
 * into an SPU chain as if the captured program were running, or runs a
 * graph whose application is this replay. Owns argument parsing, the frame
 * range and loop, the comparison of the chain's answers with the recorded
 * ones (counted by the request that asked), and the --info report; the
 * capture file's reader checks the bytes, the unpacker decodes the
 * buffers, and the chain does the rest.
 * Never knows an SPU by name (the default chain is cli/CMakeLists.txt's). */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "capfile.h"
#include "commands.h"
#include "tessera/chain.h"
#include "tessera/dev/unpack.h"
#include "tessera/dev/wireloop.h"
#include "tessera/dispatch.h"
#include "tessera/graph.h"

#ifndef TESSERA_EXEC_DEFAULT_CHAIN
#error "TESSERA_EXEC_DEFAULT_CHAIN is defined by cli/CMakeLists.txt"
#endif

static void replay_usage(FILE *out)
{
    fprintf(out,
            "usage: tessera replay FILE [--chain CHAIN] [--loop N] [--frames A-B] [--exact-answers]\n"
            "       tessera replay FILE --graph GRAPH [--loop N] [--frames A-B] [--exact-answers]\n"
            "                      [RUN OPTIONS]\n"
            "       tessera replay --info FILE\n\n"
            "Feeds a capture file, written by the capture SPU (e.g. --chain \"capture\n"
            "file=run.tsrcap ! render\"), into an SPU chain as if the captured program were\n"
            "running: the same wire buffers, in order, decoded into the chain's first SPU.\n"
            "The file holds the replies the program received, so nothing has to answer:\n"
            "the replay compares the chain's answers with them and prints, at the end,\n"
            "\"answers: N compared, D differ; by request: glReadPixels 4, ...\".\n\n"
            "options:\n"
            "  --chain CHAIN   the SPU chain (default: $TESSERA_CHAIN, else\n"
            "                  \"%s\", {out} = out/NAME-%%04d.png,\n"
            "                  NAME the capture file's name without its extension)\n"
            "  --graph GRAPH   run the graph (as tessera run does) with this replay as its\n"
            "                  application: the graph must have exactly one app node, whose\n"
            "                  exec is replaced; RUN OPTIONS (--out DIR, --stats FILE,\n"
            "                  --timeout-ms MS, --join-timeout-ms MS, --token T, --progress,\n"
            "                  --no-progress) are tessera run's\n"
            "  --frames A-B    only frames A to B (from 0, both included; A alone: A-A):\n"
            "                  frames before A are fed without their SwapBuffersTSR, so\n"
            "                  their state is set but nothing is shown, and the chain's\n"
            "                  first output frame is frame A; nothing after B is fed\n"
            "  --loop N        feed the frames (all, or A-B) N times in a row (default 1);\n"
            "                  windows and contexts the stream creates are created once,\n"
            "                  and the stream's end (after its last frame) is fed once, after\n"
            "                  the last pass\n"
            "  --exact-answers an answer of the chain that differs from the recorded one is\n"
            "                  a failure (exit status 1 after the whole replay)\n"
            "  --info          print the header, frames, commands, bytes, the calls used\n"
            "                  (count per command, as a chain receives them) and the\n"
            "                  replies by the request they answer, and check every buffer\n"
            "  -h, --help      show this help\n\n"
            "A malformed file (truncated, another version, lying lengths) is refused with\n"
            "one line naming the file and the byte offset.\n"
            "Exit codes: 0 ok, 1 runtime failure, 2 usage error or bad capture file.\n",
            TESSERA_EXEC_DEFAULT_CHAIN);
}

/* --- the replay ----------------------------------------------------------- */

#define REPLAY_MAX_IDS 256

typedef struct replay {
    tsr_capfile file;
    const tsr_dispatch *chain;
    /* What the unpacker calls: every slot forwards to the chain's head as
     * it is at that call (an SPU may switch its own table while it runs,
     * as tilesort does while it records a display list, so a copy of the
     * head would go stale), and the five slots below come first. */
    tsr_dispatch filter;
    tsr_hook live[TSR_DISPATCH_COUNT];
    tsr_unpacker *unpacker;
    long first, last; /* frames fed with their swap */
    long pass;
    long frame;                         /* index in the stream of the next swap */
    int stop;                           /* frame `last` was swapped */
    uint64_t start_offset, start_index; /* the record frame `first` starts at */
    GLint windows[REPLAY_MAX_IDS], contexts[REPLAY_MAX_IDS];
    size_t nwindows, ncontexts;
    tsr_reply_slot reply; /* the chain's last answer */
    uint64_t replies, differ, frames_out;
    uint32_t first_differ;
    /* The answers by the request that asked (the last call fed before a
     * reply: a buffer with a request ends with it); -1: none yet. */
    int last_slot;
    uint64_t asked[TSR_DISPATCH_COUNT], asked_differ[TSR_DISPATCH_COUNT];
    uint64_t unattributed, unattributed_differ;
} replay;

static void rp_live(void *ctx, int slot)
{
    replay *r = ctx;
    r->live[slot].next = r->chain->slots[slot];
    r->last_slot = slot;
}

static void rp_SwapBuffersTSR(void *self, GLint window, GLbitfield flags)
{
    replay *r = self;
    long f = r->frame++;
    if (f < r->first) {
        if (f == r->first - 1) {
            r->start_offset = r->file.pos;
            r->start_index = r->file.index;
        }
        return;
    }
    tsr_call_SwapBuffersTSR(r->chain, window, flags);
    r->frames_out++;
    if (f == r->last) {
        r->stop = 1;
        tsr_unpacker_yield(r->unpacker);
    }
}

static int id_seen(GLint *ids, size_t *n, GLint id, int add)
{
    for (size_t i = 0; i < *n; i++)
        if (ids[i] == id) {
            if (add < 0)
                ids[i] = ids[--*n];
            return 1;
        }
    if (add > 0 && *n < REPLAY_MAX_IDS)
        ids[(*n)++] = id;
    return 0;
}

static void rp_WindowCreateTSR(void *self, GLint window, GLsizei width, GLsizei height)
{
    replay *r = self;
    if (!id_seen(r->windows, &r->nwindows, window, 1) || r->pass == 0)
        tsr_call_WindowCreateTSR(r->chain, window, width, height);
}

static void rp_WindowDestroyTSR(void *self, GLint window)
{
    replay *r = self;
    id_seen(r->windows, &r->nwindows, window, -1);
    tsr_call_WindowDestroyTSR(r->chain, window);
}

static void rp_ContextCreateTSR(void *self, GLint context)
{
    replay *r = self;
    if (!id_seen(r->contexts, &r->ncontexts, context, 1) || r->pass == 0)
        tsr_call_ContextCreateTSR(r->chain, context);
}

static void rp_ContextDestroyTSR(void *self, GLint context)
{
    replay *r = self;
    id_seen(r->contexts, &r->ncontexts, context, -1);
    tsr_call_ContextDestroyTSR(r->chain, context);
}

static int rp_reply(void *ctx, uint32_t id, const uint8_t *data, size_t size, tsr_error *err)
{
    replay *r = ctx;
    return tsr_reply_slot_store(&r->reply, id, data, size, err);
}

static void compare_reply(replay *r, const tsr_capfile_record *rec)
{
    r->replies++;
    int same = r->reply.full && r->reply.id == rec->id && r->reply.size == rec->size &&
               (rec->size == 0 || memcmp(r->reply.data, rec->data, rec->size) == 0);
    if (!same && r->differ++ == 0)
        r->first_differ = rec->id;
    if (r->last_slot < 0) {
        r->unattributed++;
        r->unattributed_differ += !same;
    } else {
        r->asked[r->last_slot]++;
        r->asked_differ[r->last_slot] += !same;
    }
    r->last_slot = -1;
    r->reply.full = 0;
}

typedef struct named_count {
    const char *name;
    uint64_t count, extra;
} named_count;

static int by_count(const void *a, const void *b)
{
    const named_count *x = a, *y = b;
    if (x->count != y->count)
        return x->count < y->count ? 1 : -1;
    return strcmp(x->name, y->name);
}

/* "answers: N compared, D differ; by request: glReadPixels 4, glGetError
 * 12 (1 differs), ..." on stdout: what a script checks a replay by. */
static void print_answers(const replay *r, const char *path)
{
    named_count used[TSR_DISPATCH_COUNT];
    size_t n = 0;
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++)
        if (r->asked[i])
            used[n++] = (named_count){tsr_dispatch_name(i), r->asked[i], r->asked_differ[i]};
    qsort(used, n, sizeof used[0], by_count);
    printf("tessera replay: %s: answers: %llu compared, %llu differ", path, (unsigned long long)r->replies,
           (unsigned long long)r->differ);
    for (size_t i = 0; i < n; i++) {
        printf("%sgl%s %llu", i ? ", " : "; by request: ", used[i].name, (unsigned long long)used[i].count);
        if (used[i].extra)
            printf(" (%llu differ%s)", (unsigned long long)used[i].extra, used[i].extra == 1 ? "s" : "");
    }
    if (r->unattributed)
        printf("%s%llu after no call (%llu differ)", n ? ", " : "; by request: ", (unsigned long long)r->unattributed,
               (unsigned long long)r->unattributed_differ);
    printf("\n");
}

/* Feeds records until the end of the file, or until frame r->last was
 * swapped when `to_last`. */
static int feed(replay *r, int to_last, tsr_error *err)
{
    tsr_capfile_record rec;
    for (;;) {
        int got = tsr_capfile_next(&r->file, &rec, err);
        if (got <= 0)
            return got;
        if (rec.kind == TSR_CAPFILE_REPLY) {
            compare_reply(r, &rec);
            continue;
        }
        tsr_error why = {0};
        int rc = tsr_unpacker_run(r->unpacker, rec.data, rec.size, &why);
        if (rc < 0)
            return tsr_error_set(err, TSR_EPROTO, "%s: byte %llu: %s", r->file.name,
                                 (unsigned long long)rec.offset + TSR_CAPFILE_RECORD_HEADER, why.message);
        if (to_last && r->stop)
            return 0;
    }
}

static int run_replay(const char *path, const char *chain_text, long first, long last, long loops, int exact_answers)
{
    replay *r = calloc(1, sizeof *r);
    if (!r) {
        fprintf(stderr, "tessera replay: out of memory\n");
        return TSR_EXIT_FAIL;
    }
    tsr_error err = {0};
    int code = TSR_EXIT_OK;
    tsr_chain *chain = NULL;
    if (tsr_capfile_open(&r->file, path, &err) != TSR_OK) {
        fprintf(stderr, "tessera replay: %s\n", err.message);
        free(r);
        return err.code == TSR_EPROTO || err.code == TSR_ENOENT || err.code == TSR_EINVAL ? TSR_EXIT_USAGE
                                                                                          : TSR_EXIT_FAIL;
    }
    long frames = (long)r->file.header.frames;
    if (first >= 0 && last >= frames) {
        fprintf(stderr, "tessera replay: --frames %ld-%ld: %s has %ld frames (0-%ld)\n", first, last, path, frames,
                frames - 1);
        code = TSR_EXIT_USAGE;
        goto out;
    }
    r->first = first >= 0 ? first : 0;
    r->last = first >= 0 ? last : frames - 1;
    r->start_offset = TSR_CAPFILE_HEADER_SIZE;
    r->last_slot = -1;
    chain = tsr_chain_create(chain_text, &err);
    if (!chain) {
        fprintf(stderr, "tessera replay: %s\n", err.message);
        code = err.code == TSR_ENOMEM || err.code == TSR_EIO ? TSR_EXIT_FAIL : TSR_EXIT_USAGE;
        goto out;
    }
    r->chain = tsr_chain_head(chain);
    tsr_dispatch_fill_nop(&r->filter);
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++) {
        r->live[i] = (tsr_hook){.before = rp_live, .ctx = r};
        tsr_dispatch_hook(&r->filter, i, &r->live[i]);
    }
    tsr_set_SwapBuffersTSR(&r->filter, rp_SwapBuffersTSR, r);
    tsr_set_WindowCreateTSR(&r->filter, rp_WindowCreateTSR, r);
    tsr_set_WindowDestroyTSR(&r->filter, rp_WindowDestroyTSR, r);
    tsr_set_ContextCreateTSR(&r->filter, rp_ContextCreateTSR, r);
    tsr_set_ContextDestroyTSR(&r->filter, rp_ContextDestroyTSR, r);
    r->unpacker = tsr_unpacker_create(&r->filter, rp_reply, r, &err);
    if (!r->unpacker) {
        fprintf(stderr, "tessera replay: %s\n", err.message);
        code = TSR_EXIT_FAIL;
        goto out;
    }
    int rc = TSR_OK;
    for (r->pass = 0; rc == TSR_OK && r->pass < loops && frames > 0; r->pass++) {
        if (r->pass > 0) {
            tsr_capfile_rewind(&r->file, r->start_offset, r->start_index);
            r->frame = r->first;
        }
        r->stop = 0;
        rc = feed(r, 1, &err);
        if (rc == TSR_OK && !r->stop)
            rc = tsr_error_set(&err, TSR_EPROTO, "%s: byte 24: the header says %ld frames, the stream has %ld", path,
                               frames, r->frame);
    }
    /* The stream's end (or all of a stream without frames), once. */
    if (rc == TSR_OK && r->last == frames - 1)
        rc = feed(r, 0, &err);
    if (rc != TSR_OK) {
        fprintf(stderr, "tessera replay: %s\n", err.message);
        code = err.code == TSR_EPROTO ? TSR_EXIT_USAGE : TSR_EXIT_FAIL;
        goto out;
    }
    if (r->differ)
        fprintf(stderr,
                "tessera replay: note: %llu of %llu answers of this chain differ from the ones the program got "
                "(first: request %u); the stream carries what the program did with its own\n",
                (unsigned long long)r->differ, (unsigned long long)r->replies, r->first_differ);
    printf("tessera replay: %s: %llu frames fed (%ld pass%s)\n", path, (unsigned long long)r->frames_out, loops,
           loops == 1 ? "" : "es");
    print_answers(r, path);
    if (exact_answers && r->differ) {
        fprintf(stderr, "tessera replay: %s: --exact-answers: %llu answers differ\n", path,
                (unsigned long long)r->differ);
        code = TSR_EXIT_FAIL;
    }
out:
    tsr_unpacker_destroy(r->unpacker);
    if (chain)
        tsr_chain_destroy(chain);
    tsr_capfile_close(&r->file);
    tsr_reply_slot_free(&r->reply);
    free(r);
    return code;
}

/* --- --info --------------------------------------------------------------- */

static int print_info(const char *path)
{
    tsr_capfile f;
    tsr_error err = {0};
    if (tsr_capfile_open(&f, path, &err) != TSR_OK) {
        fprintf(stderr, "tessera replay: %s\n", err.message);
        return err.code == TSR_EIO || err.code == TSR_ENOMEM ? TSR_EXIT_FAIL : TSR_EXIT_USAGE;
    }
    uint64_t counts[TSR_DISPATCH_COUNT], replies_by_request[TSR_DISPATCH_COUNT];
    tsr_capfile_stats st;
    int rc = tsr_capfile_scan(&f, &st, counts, replies_by_request, &err);
    if (rc != TSR_OK) {
        fprintf(stderr, "tessera replay: %s\n", err.message);
        tsr_capfile_close(&f);
        return rc == TSR_ENOMEM ? TSR_EXIT_FAIL : TSR_EXIT_USAGE;
    }
    printf("file: %s\n", path);
    printf("format: capture version %u, wire TSW1\n", f.header.version);
    printf("window: %ux%u\n", f.header.width, f.header.height);
    printf("frames: %llu\n", (unsigned long long)st.frames);
    printf("bytes: %zu (buffers %llu, replies %llu)\n", f.size, (unsigned long long)st.buffer_bytes,
           (unsigned long long)st.reply_bytes);
    printf("buffers: %llu\n", (unsigned long long)st.buffers);
    printf("replies: %llu\n", (unsigned long long)st.replies);
    printf("commands: %llu\n", (unsigned long long)st.commands);
    printf("calls: %llu\n", (unsigned long long)st.calls);
    named_count used[TSR_DISPATCH_COUNT];
    size_t n = 0;
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++)
        if (counts[i])
            used[n++] = (named_count){tsr_dispatch_name(i), counts[i], 0};
    qsort(used, n, sizeof used[0], by_count);
    printf("calls used: %zu\n", n);
    for (size_t i = 0; i < n; i++)
        printf("  gl%-28s %llu\n", used[i].name, (unsigned long long)used[i].count);
    n = 0;
    for (int i = 0; i < TSR_DISPATCH_COUNT; i++)
        if (replies_by_request[i])
            used[n++] = (named_count){tsr_dispatch_name(i), replies_by_request[i], 0};
    qsort(used, n, sizeof used[0], by_count);
    printf("replies by request:");
    for (size_t i = 0; i < n; i++)
        printf("%s gl%s %llu", i ? "," : "", used[i].name, (unsigned long long)used[i].count);
    if (st.replies_unattributed)
        printf("%s %llu after no call", n ? "," : "", (unsigned long long)st.replies_unattributed);
    printf("\n");
    tsr_capfile_close(&f);
    return TSR_EXIT_OK;
}

/* --- arguments -------------------------------------------------------------- */

static int parse_long(const char *text, long min, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < min || v > INT_MAX)
        return -1;
    *out = v;
    return 0;
}

static int parse_frames(const char *text, long *first, long *last)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%s", text);
    char *dash = strchr(buf, '-');
    if (dash)
        *dash = '\0';
    if (parse_long(buf, 0, first) || (dash ? parse_long(dash + 1, 0, last) : (*last = *first, 0)) || *last < *first)
        return -1;
    return 0;
}

/* TESSERA_EXEC_DEFAULT_CHAIN with each {out} as "PATTERN". */
static void default_chain(char *out, size_t size, const char *pattern)
{
    size_t used = 0;
    for (const char *t = TESSERA_EXEC_DEFAULT_CHAIN; *t && used + 1 < size;) {
        if (!strncmp(t, "{out}", 5)) {
            int n = snprintf(out + used, size - used, "\"%s\"", pattern);
            used = n < 0 || (size_t)n >= size - used ? size - 1 : used + (size_t)n;
            t += 5;
        } else {
            out[used++] = *t++;
        }
    }
    out[used] = '\0';
}

int cmd_replay(int argc, char **argv)
{
    const char *file = NULL, *chain = NULL, *graph = NULL, *frames = NULL, *loop = NULL;
    int info = 0, exact_answers = 0;
    /* tessera run's options, passed on in graph mode. */
    const char *run_args[32];
    int nrun = 0;
    run_args[nrun++] = "replay";
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
            replay_usage(stdout);
            return TSR_EXIT_OK;
        }
        if (!strcmp(a, "--info")) {
            info = 1;
            continue;
        }
        if (!strcmp(a, "--exact-answers")) {
            exact_answers = 1;
            continue;
        }
        if (!strcmp(a, "--progress") || !strcmp(a, "--no-progress")) {
            run_args[nrun++] = a;
            continue;
        }
        int run_opt = !strcmp(a, "--out") || !strcmp(a, "--stats") || !strcmp(a, "--timeout-ms") ||
                      !strcmp(a, "--join-timeout-ms") || !strcmp(a, "--token");
        int own = !strcmp(a, "--chain") || !strcmp(a, "--graph") || !strcmp(a, "--frames") || !strcmp(a, "--loop");
        if (run_opt || own) {
            if (i + 1 >= argc) {
                fprintf(stderr, "tessera replay: %s needs a value (see --help)\n", a);
                return TSR_EXIT_USAGE;
            }
            const char *v = argv[++i];
            if (run_opt) {
                if (nrun + 3 > (int)(sizeof run_args / sizeof run_args[0])) {
                    fprintf(stderr, "tessera replay: too many options\n");
                    return TSR_EXIT_USAGE;
                }
                run_args[nrun++] = a;
                run_args[nrun++] = v;
            } else if (!strcmp(a, "--chain"))
                chain = v;
            else if (!strcmp(a, "--graph"))
                graph = v;
            else if (!strcmp(a, "--frames"))
                frames = v;
            else
                loop = v;
            continue;
        }
        if (a[0] == '-' && a[1]) {
            fprintf(stderr, "tessera replay: unknown option %s (see --help)\n", a);
            return TSR_EXIT_USAGE;
        }
        if (file) {
            fprintf(stderr, "tessera replay: one FILE at a time ('%s' and '%s')\n", file, a);
            return TSR_EXIT_USAGE;
        }
        file = a;
    }
    if (!file) {
        replay_usage(stderr);
        return TSR_EXIT_USAGE;
    }
    if (info) {
        if (chain || graph || frames || loop || exact_answers || nrun > 1) {
            fprintf(stderr, "tessera replay: --info takes only the FILE\n");
            return TSR_EXIT_USAGE;
        }
        return print_info(file);
    }
    long first = -1, last = -1, loops = 1;
    if (frames && parse_frames(frames, &first, &last)) {
        fprintf(stderr, "tessera replay: bad --frames '%s' (expected A-B with 0 <= A <= B, or A)\n", frames);
        return TSR_EXIT_USAGE;
    }
    if (loop && parse_long(loop, 1, &loops)) {
        fprintf(stderr, "tessera replay: bad --loop '%s' (expected a count >= 1)\n", loop);
        return TSR_EXIT_USAGE;
    }
    if (chain && graph) {
        fprintf(stderr, "tessera replay: --chain and --graph exclude each other (a graph gives every node its "
                        "chain)\n");
        return TSR_EXIT_USAGE;
    }
    if (!graph && nrun > 1) {
        fprintf(stderr, "tessera replay: %s applies to --graph only\n", run_args[1]);
        return TSR_EXIT_USAGE;
    }
    if (graph) {
        /* The replay is the graph's one application: checked here, so the
         * run never starts with a file that cannot be replayed. */
        tsr_capfile f;
        tsr_error err = {0};
        if (tsr_capfile_open(&f, file, &err) != TSR_OK) {
            fprintf(stderr, "tessera replay: %s\n", err.message);
            return TSR_EXIT_USAGE;
        }
        long frames_in_file = (long)f.header.frames;
        tsr_capfile_close(&f);
        if (first >= 0 && last >= frames_in_file) {
            fprintf(stderr, "tessera replay: --frames %ld-%ld: %s has %ld frames (0-%ld)\n", first, last, file,
                    frames_in_file, frames_in_file - 1);
            return TSR_EXIT_USAGE;
        }
        tsr_graph *g = tsr_graph_load(graph, 0, &err);
        if (!g) {
            fprintf(stderr, "%s\n", err.message);
            return err.code == TSR_ENOMEM ? TSR_EXIT_FAIL : TSR_EXIT_USAGE;
        }
        size_t apps = 0;
        for (size_t i = 0; i < tsr_graph_node_count(g); i++)
            apps += tsr_graph_node_at(g, i)->exec != NULL;
        tsr_graph_free(g);
        if (apps != 1) {
            fprintf(stderr, "tessera replay: %s has %zu app nodes (nodes with exec:); a replay is one application\n",
                    graph, apps);
            return TSR_EXIT_USAGE;
        }
        char self[PATH_MAX], abs_file[PATH_MAX];
        ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        if (n <= 0 || !realpath(file, abs_file)) {
            fprintf(stderr, "tessera replay: cannot resolve %s: %s\n", n <= 0 ? "/proc/self/exe" : file,
                    strerror(errno));
            return TSR_EXIT_FAIL;
        }
        self[n] = '\0';
        const char *app[10];
        int na = 0;
        app[na++] = self;
        app[na++] = "replay";
        app[na++] = abs_file;
        if (frames) {
            app[na++] = "--frames";
            app[na++] = frames;
        }
        if (loop) {
            app[na++] = "--loop";
            app[na++] = loop;
        }
        if (exact_answers)
            app[na++] = "--exact-answers";
        app[na] = NULL;
        run_args[nrun++] = graph;
        run_args[nrun] = NULL;
        return tsr_cli_run_graph_as(nrun, (char **)run_args, 1, app, "tessera replay");
    }
    char chain_buf[4300];
    if (!chain && getenv("TESSERA_CHAIN") && getenv("TESSERA_CHAIN")[0])
        chain = getenv("TESSERA_CHAIN");
    if (!chain) {
        const char *slash = strrchr(file, '/');
        const char *base = slash ? slash + 1 : file;
        const char *dot = strrchr(base, '.');
        int len = dot && dot > base ? (int)(dot - base) : (int)strlen(base);
        char pattern[4096];
        snprintf(pattern, sizeof pattern, "out/%.*s-%%04d.png", len, base);
        if (strchr(pattern, '"')) {
            fprintf(stderr, "tessera replay: the capture file's name must not contain '\"' for the default chain\n");
            return TSR_EXIT_USAGE;
        }
        if (mkdir("out", 0777) != 0 && errno != EEXIST) {
            fprintf(stderr, "tessera replay: cannot create directory out: %s\n", strerror(errno));
            return TSR_EXIT_FAIL;
        }
        default_chain(chain_buf, sizeof chain_buf, pattern);
        chain = chain_buf;
    }
    return run_replay(file, chain, first, last, loops, exact_answers);
}
