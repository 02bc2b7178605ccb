/* core/spu/native.c — tessera/dev/native.h: a table of native windows
 * behind tessera window ids, one per chain. A short list under a mutex: a
 * program has a handful of windows, the faker's thread writes the table
 * and an SPU's thread reads it once a frame. Owns the table's entries;
 * never any process-wide state. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tessera/dev/native.h"

typedef struct native_window {
    int window;
    unsigned long xid;
    char display[256];
    struct native_window *next;
} native_window;

struct tsr_native_windows {
    pthread_mutex_t lock;
    native_window *list;
};

tsr_native_windows *tsr_native_windows_create(void)
{
    tsr_native_windows *t = calloc(1, sizeof *t);
    if (t && pthread_mutex_init(&t->lock, NULL) != 0) {
        free(t);
        t = NULL;
    }
    return t;
}

void tsr_native_windows_destroy(tsr_native_windows *windows)
{
    if (!windows)
        return;
    while (windows->list) {
        native_window *dead = windows->list;
        windows->list = dead->next;
        free(dead);
    }
    pthread_mutex_destroy(&windows->lock);
    free(windows);
}

int tsr_native_window_set(tsr_native_windows *windows, int window, const char *x_display, unsigned long xid)
{
    if (!windows)
        return -1;
    int rc = 0;
    pthread_mutex_lock(&windows->lock);
    native_window **p = &windows->list;
    while (*p && (*p)->window != window)
        p = &(*p)->next;
    if (!xid) {
        if (*p) {
            native_window *dead = *p;
            *p = dead->next;
            free(dead);
        }
    } else {
        if (!*p && (*p = calloc(1, sizeof **p)) != NULL)
            (*p)->window = window;
        if (*p) {
            (*p)->xid = xid;
            snprintf((*p)->display, sizeof(*p)->display, "%s", x_display ? x_display : "");
        } else {
            rc = -1;
        }
    }
    pthread_mutex_unlock(&windows->lock);
    return rc;
}

int tsr_native_window_get(tsr_native_windows *windows, int window, char *x_display, size_t n, unsigned long *xid)
{
    if (!windows)
        return 0;
    int found = 0;
    pthread_mutex_lock(&windows->lock);
    for (native_window *w = windows->list; w; w = w->next) {
        if (w->window == window) {
            if (x_display && n)
                snprintf(x_display, n, "%s", w->display);
            if (xid)
                *xid = w->xid;
            found = 1;
            break;
        }
    }
    pthread_mutex_unlock(&windows->lock);
    return found;
}
