/* mothership/stats.c — the run's statistics: the imbalance between
 * render servers, the statistics file (JSON) and the summary line.
 * Owns nothing past a call. Never: fails a run that succeeded because the
 * statistics could not be written without saying so. */
#include <errno.h>
#include <ftw.h>
#include <limits.h>
#include <libgen.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "tessera/dev/util.h"
#include "ms_internal.h"
#include "tessera/dev/net.h"
#include "control.h"
#include "tessera/spu.h"
#include "util.h"

/* Load imbalance of the servers' render time: max / mean of their busy
 * seconds (1: even; 0 without servers). */
static double render_imbalance(const ms *m)
{
    double max = 0, sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < m->count; i++)
        if (m->nodes[i].server) {
            max = m->nodes[i].busy > max ? m->nodes[i].busy : max;
            sum += m->nodes[i].busy;
            n++;
        }
    return n && sum > 0 ? max / (sum / (double)n) : 0.0;
}

int ms_write_stats(ms *m, int ok, double wall, tsr_error *err)
{
    FILE *f = fopen(m->cfg->stats_path, "w");
    if (!f)
        return tsr_error_set(err, TSR_EIO, "--stats %s: %s", m->cfg->stats_path, strerror(errno));
    fprintf(f, "{\n  \"graph\": ");
    tsr_json_string(f, tsr_graph_file(m->graph));
    fprintf(f, ",\n  \"status\": \"%s\",\n  \"failure\": ", ok ? "ok" : "failed");
    if (ok)
        fprintf(f, "null");
    else
        tsr_json_string(f, m->fail_message);
    fprintf(f, ",\n  \"wall_seconds\": %.3f,\n  \"nodes\": [\n", wall);
    for (size_t i = 0; i < m->count; i++) {
        const ms_node *n = &m->nodes[i];
        fprintf(f, "    {\"name\": ");
        tsr_json_string(f, n->g->name);
        fprintf(f, ", \"role\": \"%s\", \"host\": ", n->server ? "server" : "app");
        tsr_json_string(f, n->host[0] ? n->host : n->g->host);
        fprintf(f, ", \"state\": \"%s\", \"seconds\": %.3f",
                n->state == N_DONE ? (n->done_status ? "failed" : "done") : "unfinished", n->elapsed);
        if (n->server || n->app_stats == 1) {
            fprintf(f, ", \"frames\": %.0f, \"buffers\": %.0f, \"bytes_in\": %.0f, \"bytes_out\": %.0f", n->frames,
                    n->buffers, n->bytes_in, n->bytes_out);
        } else {
            /* The application's network SPU wrote no TESSERA_STATS_FILE
             * (not every chain has one): unknown, not zero. */
            fprintf(f, ", \"frames\": null, \"buffers\": null, \"bytes_in\": null, \"bytes_out\": null");
        }
        if (n->server) {
            fprintf(f, ", \"address\": ");
            tsr_json_string(f, n->address);
            fprintf(f, ", \"render_seconds\": %.6f, \"blocked_seconds\": null, \"clients\": %u}", n->busy, n->clients);
        } else if (n->app_stats == 1)
            fprintf(f, ", \"render_seconds\": null, \"blocked_seconds\": %.6f, \"app_stats\": \"found\"%s%s}",
                    n->blocked, n->sort_first ? ", \"sort_first\": " : "", n->sort_first ? n->sort_first : "");
        else
            fprintf(f, ", \"render_seconds\": null, \"blocked_seconds\": null, \"app_stats\": \"missing\"}");
        fprintf(f, "%s\n", i + 1 < m->count ? "," : "");
    }
    fprintf(f, "  ],\n  \"server_render_imbalance\": %.6f\n}\n", render_imbalance(m));
    if (fclose(f))
        return tsr_error_set(err, TSR_EIO, "--stats %s: %s", m->cfg->stats_path, strerror(errno));
    return TSR_OK;
}

void ms_summary(ms *m, double wall)
{
    FILE *f = m->cfg->summary;
    if (!f)
        return;
    fprintf(f, "%s: %s in %.2f s\n", m->cfg->who, tsr_graph_file(m->graph), wall);
    for (size_t i = 0; i < m->count; i++) {
        const ms_node *n = &m->nodes[i];
        double secs = n->elapsed > 0 ? n->elapsed : wall;
        if (n->server)
            fprintf(f,
                    "  %-12s server: %.0f frames, %.1f frames/s, %.2f MB in (%.1f MB/s), render %.3f s, %u client%s\n",
                    n->g->name, n->frames, n->frames / secs, n->bytes_in / 1e6, n->bytes_in / 1e6 / secs, n->busy,
                    n->clients, n->clients == 1 ? "" : "s");
        else if (n->app_stats == 1)
            fprintf(f,
                    "  %-12s app:    %.0f frames, %.1f frames/s, %.2f MB out (%.1f MB/s), blocked on credits %.3f s\n",
                    n->g->name, n->frames, n->frames / secs, n->bytes_out / 1e6, n->bytes_out / 1e6 / secs, n->blocked);
        else
            fprintf(f, "  %-12s app:    ran %.2f s (no network statistics from its chain)\n", n->g->name, secs);
        double overlap, imbalance;
        if (n->sort_first && tsr_ms_json_number(n->sort_first, "overlap", &overlap) == 0 &&
            tsr_ms_json_number(n->sort_first, "imbalance", &imbalance) == 0)
            fprintf(f,
                    "  %-12s sort-first: overlap %.3f (bytes sent / stream), imbalance %.3f (max / mean "
                    "server bytes), server render time imbalance %.3f\n",
                    "", overlap, imbalance, render_imbalance(m));
    }
    fflush(f);
}
