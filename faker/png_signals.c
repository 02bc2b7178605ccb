/* faker/png_signals.c — the faker's stand-in for the program's own
 * handling of partial PNGs on fatal signals (tessera/image.h): it owns the
 * table of PNGs being written in the program it runs in and the handlers
 * that remove their temporaries. It must never replace a handler the
 * program installed itself. */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <string.h>

#include "faker_gl.h"
#include "tessera/image.h"

/* The program the faker runs in does not know its chains write PNGs: the
 * faker stands in for it (tessera/image.h). Temporaries of PNGs being
 * written are removed when SIGTERM, SIGINT or SIGHUP end the program,
 * over a signal's default action only, at the first context (the
 * program's own handlers, installed before, are left alone); the signal
 * then ends the process as before (SA_RESETHAND). */
static tsr_image_pending *pending_pngs;

static void remove_temporaries_and_die(int sig)
{
    int saved_errno = errno;
    tsr_image_pending_remove_all(pending_pngs);
    errno = saved_errno;
    raise(sig);
}

static void install_once(void)
{
    static const int signals[] = {SIGTERM, SIGINT, SIGHUP};
    pending_pngs = tsr_image_pending_create();
    if (!pending_pngs)
        return;
    tsr_image_set_pending(pending_pngs);
    for (size_t i = 0; i < sizeof signals / sizeof signals[0]; i++) {
        struct sigaction old, sa;
        if (sigaction(signals[i], NULL, &old) != 0 || (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL)
            continue;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = remove_temporaries_and_die;
        sa.sa_flags = SA_RESETHAND;
        sigfillset(&sa.sa_mask);
        sigaction(signals[i], &sa, NULL);
    }
}

void tsr_faker_png_signals_install(void)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, install_once);
}
