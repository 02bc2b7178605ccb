/* core/spu/native.c — tessera/dev/native.h: the process's table of native
 * windows behind tessera window ids. A short list under a mutex: a program
 * has a handful of windows and the table is read once a frame. */
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

static pthread_mutex_t native_lock = PTHREAD_MUTEX_INITIALIZER;
static native_window *native_windows;

int tsr_native_window_set(int window, const char *x_display, unsigned long xid)
{
    int rc = 0;
    pthread_mutex_lock(&native_lock);
    native_window **p = &native_windows;
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
    pthread_mutex_unlock(&native_lock);
    return rc;
}

int tsr_native_window_get(int window, char *x_display, size_t n, unsigned long *xid)
{
    int found = 0;
    pthread_mutex_lock(&native_lock);
    for (native_window *w = native_windows; w; w = w->next) {
        if (w->window == window) {
            if (x_display && n)
                snprintf(x_display, n, "%s", w->display);
            if (xid)
                *xid = w->xid;
            found = 1;
            break;
        }
    }
    pthread_mutex_unlock(&native_lock);
    return found;
}
