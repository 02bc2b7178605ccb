/* tests/node/budget_driver.c — a hostile client of a server node for the
 * per-client budgets (server/README.md, "Budgets"; issue 10, defects 5
 * and 6): connects as 'budget-driver' with real netlib, announcing a huge
 * max_message_bytes and credit window, packs one attack with the real
 * packer and sends it, never reading what comes back for a second; then
 * waits (bounded) for the node's ERROR message and prints it.
 *   readpixels ADDR     4 x glReadPixels 16384x16384 RGBA, no reply read
 *   readpixels-small ADDR  8 x glReadPixels 256x256 RGBA, no reply read
 *   readpixels-many ADDR   400 x glReadPixels 62x64 RGBA (15,872 bytes), no
 *                       reply read: any 64 of them fit a 1 MiB pending
 *                       budget, 400 do not (the node must count them all)
 *   teximage ADDR       4 x glTexImage2D 16384x16384 RGBA NULL, one buffer
 *   draw-arrays ADDR    glDrawArrays(first 2^31-1, count 2^31-1), no arrays
 *   vbo-arrays ADDR     the same from a 72-byte vertex buffer object
 *   vbo-elements ADDR   glDrawElements(count 2^31-1) from a 72-byte index
 *                       buffer (vertices in a 72-byte buffer)
 *   window ADDR         a 16384x16384 window and a swap
 * Exit 0 when the node answered with an ERROR (the line is printed),
 * 1 otherwise (no error within 60 s, or the connection just ended).
 * Owns only its connection. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <GL/gl.h>
#include <GL/glext.h>

#include "tessera/dev/net.h"
#include "tessera/dev/pack.h"
#include "tessera/dev/protocol.h"
#include "tessera/dev/wire.h"
#include "tessera/dispatch.h"

#define HUGE_SIDE 16384
#define INT_MAX_GL 2147483647

static int send_buffer(void *ctx, const uint8_t *buf, size_t size, tsr_error *err)
{
    return tsr_net_send(ctx, TSR_NODE_MSG_BUFFER, buf, size, 30000, err);
}

/* The attacker never reads a reply: the packer goes on without it. */
static int no_reply(void *ctx, uint32_t id, const uint8_t **data, size_t *size, tsr_error *err)
{
    (void)ctx, (void)data, (void)size;
    return tsr_error_set(err, TSR_EIO, "budget_driver: reply %u not read (on purpose)", id);
}

static void attack(const char *what, const tsr_dispatch *d)
{
    static const GLfloat vertices[18] = {0}; /* 72 bytes */
    if (!strcmp(what, "readpixels")) {
        for (int i = 0; i < 4; i++) {
            /* Never dereferenced here: the reply is never read. */
            static unsigned char sink[16];
            tsr_call_ReadPixels(d, 0, 0, HUGE_SIDE, HUGE_SIDE, GL_RGBA, GL_UNSIGNED_BYTE, sink);
        }
    } else if (!strcmp(what, "readpixels-small")) {
        for (int i = 0; i < 8; i++) {
            static unsigned char sink[16];
            tsr_call_ReadPixels(d, 0, 0, 256, 256, GL_RGBA, GL_UNSIGNED_BYTE, sink);
        }
    } else if (!strcmp(what, "readpixels-many")) {
        for (int i = 0; i < 400; i++) {
            static unsigned char sink[16];
            tsr_call_ReadPixels(d, 0, 0, 62, 64, GL_RGBA, GL_UNSIGNED_BYTE, sink);
        }
    } else if (!strcmp(what, "teximage")) {
        GLuint names[4] = {1, 2, 3, 4};
        for (int i = 0; i < 4; i++) {
            tsr_call_BindTexture(d, GL_TEXTURE_2D, names[i]);
            tsr_call_TexImage2D(d, GL_TEXTURE_2D, 0, GL_RGBA, HUGE_SIDE, HUGE_SIDE, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
        }
    } else if (!strcmp(what, "draw-arrays")) {
        tsr_call_DrawArrays(d, GL_POINTS, INT_MAX_GL, INT_MAX_GL);
    } else if (!strcmp(what, "vbo-arrays") || !strcmp(what, "vbo-elements")) {
        tsr_call_BindBuffer(d, GL_ARRAY_BUFFER, 1);
        tsr_call_BufferData(d, GL_ARRAY_BUFFER, sizeof vertices, vertices, GL_STATIC_DRAW);
        tsr_call_VertexPointer(d, 3, GL_FLOAT, 0, NULL);
        tsr_call_EnableClientState(d, GL_VERTEX_ARRAY);
        if (!strcmp(what, "vbo-arrays")) {
            tsr_call_DrawArrays(d, GL_POINTS, INT_MAX_GL, INT_MAX_GL);
        } else {
            static const GLuint indices[18] = {0};
            tsr_call_BindBuffer(d, GL_ELEMENT_ARRAY_BUFFER, 2);
            tsr_call_BufferData(d, GL_ELEMENT_ARRAY_BUFFER, sizeof indices, indices, GL_STATIC_DRAW);
            tsr_call_DrawElements(d, GL_POINTS, INT_MAX_GL, GL_UNSIGNED_INT, NULL);
        }
    } else if (!strcmp(what, "window")) {
        tsr_call_WindowCreateTSR(d, 0, HUGE_SIDE, HUGE_SIDE);
        tsr_call_Clear(d, GL_COLOR_BUFFER_BIT);
        tsr_call_SwapBuffersTSR(d, 0, 0);
    }
}

int main(int argc, char **argv)
{
    static const char *const cases[] = {"readpixels",  "readpixels-small", "readpixels-many", "teximage",
                                        "draw-arrays", "vbo-arrays",       "vbo-elements",    "window"};
    int known = 0;
    for (size_t i = 0; argc == 3 && i < sizeof cases / sizeof cases[0]; i++)
        known |= !strcmp(argv[1], cases[i]);
    if (!known) {
        fprintf(
            stderr,
            "usage: budget_driver readpixels|readpixels-small|readpixels-many|teximage|draw-arrays|vbo-arrays|vbo-elements|window ADDR\n");
        return 2;
    }
    tsr_net_config cfg;
    tsr_net_config_defaults(&cfg);
    cfg.node_name = "budget-driver";
    cfg.max_message_bytes = (uint64_t)1 << 40; /* "send me anything" */
    cfg.credits = 1u << 20;
    tsr_error err = {0};
    tsr_net *net = tsr_net_create(&cfg, &err);
    tsr_net_conn *conn = net ? tsr_net_connect(net, argv[2], &err) : NULL;
    if (!conn) {
        fprintf(stderr, "budget_driver: %s\n", err.message);
        tsr_net_destroy(net);
        return 1;
    }
    tsr_pack_sink sink = {.flush = send_buffer, .reply = no_reply, .ctx = conn};
    /* One buffer holds the whole attack (the four TexImage2D together). */
    tsr_packer *p = tsr_packer_create(1 << 16, &sink, &err);
    tsr_dispatch *d = calloc(1, sizeof *d);
    if (!p || !d) {
        fprintf(stderr, "budget_driver: %s\n", p ? "out of memory" : err.message);
        return 1;
    }
    tsr_packer_fill_dispatch(p, d);
    attack(argv[1], d);
    tsr_packer_flush(p);
    printf("budget_driver: %s sent\n", argv[1]);
    fflush(stdout);
    struct timespec second = {1, 0};
    nanosleep(&second, NULL); /* replies, if any, stay unread meanwhile */
    int status = 1;
    /* Replies before the ERROR are read and dropped; only silence counts
     * against the 60 s. */
    for (int waited = 0; waited < 60 && status;) {
        tsr_net_msg m;
        int got = tsr_net_recv(conn, &m, 1000, &err);
        if (got == TSR_ETIMEDOUT) {
            waited++;
            continue;
        }
        if (got != 1) {
            printf("budget_driver: the connection ended without an error message: %s\n",
                   got == 0 ? "clean close" : err.message);
            break;
        }
        if (m.kind == TSR_NODE_MSG_ERROR) {
            printf("budget_driver: refused: %.*s\n", (int)m.len, (const char *)m.data);
            status = 0;
        }
        tsr_net_msg_release(&m);
    }
    if (status)
        printf("budget_driver: no error message from the node\n");
    tsr_packer_destroy(p);
    free(d);
    tsr_net_conn_close(conn);
    tsr_net_destroy(net);
    return status;
}
