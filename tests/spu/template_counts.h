/* tests/spu/template_counts.h — drives a chain holding the `template` SPU
 * with a known stream and checks the summary line it writes, shared by the
 * in-tree two-instance test and the out-of-tree driver. Owns nothing.
 * Never: hard-codes counts; the expected numbers come from what was sent. */
#ifndef TSR_TESTS_TEMPLATE_COUNTS_H
#define TSR_TESTS_TEMPLATE_COUNTS_H

#include <stdio.h>
#include <string.h>

#include "tessera/chain.h"

typedef struct template_expect {
    unsigned long long vertices, primitives, swaps;
} template_expect;

/* Sends `frames` frames of `triangles` triangles (Vertex2f, Vertex3f and
 * Vertex3fv, one of each per triangle) and counts what it sent. */
static void template_send_frames(const tsr_dispatch *head, int frames, int triangles, template_expect *sent)
{
    for (int f = 0; f < frames; f++) {
        for (int t = 0; t < triangles; t++) {
            const GLfloat v[3] = {(GLfloat)t, 1.0f, 0.5f};
            tsr_call_Begin(head, GL_TRIANGLES);
            tsr_call_Vertex2f(head, 0.0f, (GLfloat)t);
            tsr_call_Vertex3f(head, 1.0f, (GLfloat)t, 0.0f);
            tsr_call_Vertex3fv(head, v);
            tsr_call_End(head);
            sent->primitives++;
            sent->vertices += 3;
        }
        tsr_call_SwapBuffersTSR(head, 0, 0);
        sent->swaps++;
    }
}

/* Reads the summary line the template instance wrote to `path` and checks
 * it against `sent`; returns 0 when it matches. */
static int template_check_summary(const char *path, const char *instance, const template_expect *sent)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "no summary written to %s\n", path);
        return 1;
    }
    char line[256] = "";
    if (!fgets(line, sizeof line, f))
        line[0] = '\0';
    fclose(f);
    char expected[256];
    snprintf(expected, sizeof expected, "%s: vertices=%llu primitives=%llu swaps=%llu\n", instance, sent->vertices,
             sent->primitives, sent->swaps);
    if (strcmp(line, expected)) {
        fprintf(stderr, "%s:\n  got:      %s  expected: %s", path, line, expected);
        return 1;
    }
    return 0;
}

#endif
