/* tests/node/node_driver.c — clients of a server node for behaviours the
 * examples cannot show:
 *   replies ADDR   draws a scene through "pack server=ADDR" and through a
 *                  local "render" chain, asks both the same questions
 *                  (GetIntegerv(VIEWPORT), GenLists, GenTextures,
 *                  IsEnabled(DEPTH_TEST), GetString(VENDOR,
 *                  RENDERER, VERSION), GetFloatv(COLOR_CLEAR_VALUE),
 *                  ReadPixels) and fails unless every answer is equal
 *   replies-chain CHAIN   the same with CHAIN (e.g. "replicate servers=A,B")
 *                  as the remote chain
 *   garbage ADDR   connects as 'garbage-client' and sends a buffer whose
 *                  header lies about its length; succeeds when the server
 *                  answers with an error message and closes
 *   busy ADDR MS   through "pack server=ADDR timeout_ms=1000": draws and
 *                  swaps a frame, computes for MS ms without a GL call (the
 *                  in-situ case: only the stream client's I/O thread is
 *                  there to answer the server's heartbeats), then draws,
 *                  swaps and glFinish()es; pack exits non-zero if either
 *                  side took the busy application for a dead one
 * Owns only its scene; expected values come from the local chain, never
 * from constants. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <GL/gl.h>

#include "tessera/dev/net.h"
#include "tessera/dev/protocol.h"
#include "tessera/chain.h"
#include "tessera/glapi.h"
#include "tessera/gltsr_gen.h"
#include "tessera/dev/wire.h"

#define WIDTH 67 /* odd sizes catch row-stride mistakes */
#define HEIGHT 43

typedef struct answers {
    GLint viewport[4];
    GLuint lists;
    GLuint textures[2];
    GLboolean depth_enabled;
    char vendor[256], renderer[256], version[256];
    GLfloat clear[4];
    GLenum error;
    unsigned char pixels[WIDTH * HEIGHT * 4 + 3]; /* +3: the odd row length packs to 1 */
} answers;

static void copy_string(char *dst, size_t size, GLenum name)
{
    const GLubyte *s = glGetString(name);
    snprintf(dst, size, "%s", s ? (const char *)s : "(null)");
}

/* Draws and asks; the chain's table must be current. */
static void ask(answers *a)
{
    glWindowCreateTSR(0, WIDTH, HEIGHT);
    glClearColor(0.25f, 0.5f, 0.125f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glViewport(3, 2, WIDTH - 5, HEIGHT - 4);
    glBegin(GL_TRIANGLES);
    glColor3f(1.0f, 0.2f, 0.3f);
    glVertex3f(-0.9f, -0.8f, 0.0f);
    glColor3f(0.1f, 0.9f, 0.3f);
    glVertex3f(0.8f, -0.6f, 0.0f);
    glColor3f(0.2f, 0.3f, 1.0f);
    glVertex3f(-0.1f, 0.9f, 0.0f);
    glEnd();
    glGetIntegerv(GL_VIEWPORT, a->viewport);
    a->lists = glGenLists(3);
    glGenTextures(2, a->textures);
    glEnable(GL_DEPTH_TEST);
    a->depth_enabled = glIsEnabled(GL_DEPTH_TEST);
    copy_string(a->vendor, sizeof a->vendor, GL_VENDOR);
    copy_string(a->renderer, sizeof a->renderer, GL_RENDERER);
    copy_string(a->version, sizeof a->version, GL_VERSION);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, a->clear);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, WIDTH, HEIGHT, GL_RGBA, GL_UNSIGNED_BYTE, a->pixels);
    a->error = glGetError();
    glWindowDestroyTSR(0);
}

static int run_chain(const char *text, answers *a)
{
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(text, &err);
    if (!chain) {
        fprintf(stderr, "node_driver: chain '%s': %s\n", text, err.message);
        return 1;
    }
    /* A sentinel the reply must overwrite. */
    memset(a, 0xA5, sizeof *a);
    tsr_gl_make_current(tsr_chain_head(chain));
    ask(a);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    return 0;
}

static int replies(const char *text)
{
    static answers remote, local;
    if (run_chain(text, &remote) || run_chain("render", &local))
        return 1;
    int bad = 0;
    if (memcmp(remote.viewport, local.viewport, sizeof local.viewport)) {
        fprintf(stderr, "FAIL: viewport %d %d %d %d, local %d %d %d %d\n", remote.viewport[0], remote.viewport[1],
                remote.viewport[2], remote.viewport[3], local.viewport[0], local.viewport[1], local.viewport[2],
                local.viewport[3]);
        bad = 1;
    }
    if (remote.lists != local.lists) {
        fprintf(stderr, "FAIL: GenLists %u, local %u\n", remote.lists, local.lists);
        bad = 1;
    }
    if (memcmp(remote.textures, local.textures, sizeof local.textures) || remote.depth_enabled != local.depth_enabled) {
        fprintf(stderr, "FAIL: GenTextures %u %u / IsEnabled %d, local %u %u / %d\n", remote.textures[0],
                remote.textures[1], remote.depth_enabled, local.textures[0], local.textures[1], local.depth_enabled);
        bad = 1;
    }
    const char *names[] = {"VENDOR", "RENDERER", "VERSION"};
    const char *r[] = {remote.vendor, remote.renderer, remote.version};
    const char *l[] = {local.vendor, local.renderer, local.version};
    for (int i = 0; i < 3; i++)
        if (strcmp(r[i], l[i])) {
            fprintf(stderr, "FAIL: GetString(%s) '%s', local '%s'\n", names[i], r[i], l[i]);
            bad = 1;
        }
    if (memcmp(remote.clear, local.clear, sizeof local.clear)) {
        fprintf(stderr, "FAIL: COLOR_CLEAR_VALUE differs\n");
        bad = 1;
    }
    if (remote.error != local.error) {
        fprintf(stderr, "FAIL: GetError 0x%x, local 0x%x\n", remote.error, local.error);
        bad = 1;
    }
    size_t differ = 0, first = 0;
    for (size_t i = 0; i < sizeof local.pixels; i++)
        if (remote.pixels[i] != local.pixels[i] && differ++ == 0)
            first = i;
    if (differ) {
        fprintf(stderr, "FAIL: ReadPixels: %zu of %zu bytes differ, first at %zu (%u vs %u)\n", differ,
                sizeof local.pixels, first, remote.pixels[first], local.pixels[first]);
        bad = 1;
    }
    /* The scene must have drawn something, or the comparison proves little. */
    size_t lit = 0;
    for (size_t i = 0; i + 3 < (size_t)WIDTH * HEIGHT * 4; i += 4)
        lit += local.pixels[i] > 200;
    if (lit == 0) {
        fprintf(stderr, "FAIL: the local scene has no red pixels; the test draws nothing\n");
        bad = 1;
    }
    printf("textures %u %u, depth test %d, ", remote.textures[0], remote.textures[1], remote.depth_enabled);
    printf("viewport %d %d %d %d, lists %u, vendor '%s', renderer '%s', version '%s', %zu red pixels: %s\n",
           remote.viewport[0], remote.viewport[1], remote.viewport[2], remote.viewport[3], remote.lists, remote.vendor,
           remote.renderer, remote.version, lit, bad ? "DIFFERENT" : "equal to local");
    return bad;
}

static int garbage(const char *address)
{
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = "garbage-client";
    cfg.connect_timeout_ms = 3000;
    cfg.handshake_timeout_ms = 3000;
    cfg.close_timeout_ms = 3000;
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    if (!net) {
        fprintf(stderr, "node_driver: %s\n", err.message);
        return 1;
    }
    int status = 1;
    tsr_net_conn *conn = tsr_net_connect(net, address, &err);
    if (!conn) {
        fprintf(stderr, "node_driver: %s\n", err.message);
        tsr_net_destroy(net);
        return 1;
    }
    /* A header announcing 3 opcodes and 4096 data bytes, followed by 8
     * bytes: the unpacker must reject it without reading past the end. */
    uint8_t buf[TSR_WIRE_HEADER_SIZE + 8] = {0};
    tsr_wire_put_u32(buf, TSR_WIRE_MAGIC);
    tsr_wire_put_u32(buf + 4, 3);
    tsr_wire_put_u64(buf + 8, 4096);
    memset(buf + TSR_WIRE_HEADER_SIZE, 7, 8);
    if (tsr_net_send(conn, TSR_NODE_MSG_BUFFER, buf, sizeof buf, 3000, &err) != TSR_OK) {
        fprintf(stderr, "node_driver: send: %s\n", err.message);
    } else {
        tsr_net_msg m;
        int got = tsr_net_recv(conn, &m, 5000, &err);
        if (got == 1 && m.kind == TSR_NODE_MSG_ERROR) {
            printf("server answered: %.*s\n", (int)m.len, (const char *)m.data);
            status = 0;
        } else if (got == 1) {
            fprintf(stderr, "FAIL: expected an error message, got kind 0x%02x\n", m.kind);
        } else {
            fprintf(stderr, "FAIL: expected an error message, got %s\n", got == 0 ? "a clean close" : err.message);
        }
        if (got == 1)
            tsr_net_msg_release(&m);
    }
    tsr_net_conn_close(conn);
    tsr_net_destroy(net);
    return status;
}

static void draw_frame(float shade)
{
    glClearColor(shade, 0.25f, 0.5f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glBegin(GL_TRIANGLES);
    glVertex2f(-0.5f, -0.5f);
    glVertex2f(0.5f, -0.5f);
    glVertex2f(0.0f, 0.5f);
    glEnd();
    glSwapBuffersTSR(0, 0);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

static int busy(const char *address, long ms)
{
    char text[400];
    snprintf(text, sizeof text, "pack server=\"%s\" timeout_ms=1000", address);
    tsr_error err = {0};
    tsr_chain *chain = tsr_chain_create(text, &err);
    if (!chain) {
        fprintf(stderr, "node_driver: chain '%s': %s\n", text, err.message);
        return 1;
    }
    tsr_gl_make_current(tsr_chain_head(chain));
    glWindowCreateTSR(0, WIDTH, HEIGHT);
    draw_frame(0.25f);
    glFinish();
    /* Computing: no GL call for `ms` milliseconds. */
    double end = now_seconds() + ms / 1000.0;
    volatile double x = 1.0;
    while (now_seconds() < end)
        for (int i = 0; i < 100000; i++)
            x = x * 1.0000001 + 1e-9;
    printf("computed for %ld ms without a GL call\n", ms);
    draw_frame(0.75f);
    glFinish();
    glWindowDestroyTSR(0);
    tsr_gl_make_current(NULL);
    tsr_chain_destroy(chain);
    printf("both frames reached the server\n");
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 3 && !strcmp(argv[1], "replies")) {
        char text[400];
        snprintf(text, sizeof text, "pack server=\"%s\" on_error=drop", argv[2]);
        return replies(text);
    }
    if (argc == 3 && !strcmp(argv[1], "replies-chain"))
        return replies(argv[2]);
    if (argc == 3 && !strcmp(argv[1], "garbage"))
        return garbage(argv[2]);
    if (argc == 4 && !strcmp(argv[1], "busy"))
        return busy(argv[2], atol(argv[3]));
    fprintf(stderr, "usage: node_driver replies|garbage ADDRESS | replies-chain CHAIN | busy ADDRESS MS\n");
    return 2;
}
