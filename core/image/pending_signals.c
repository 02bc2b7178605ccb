/* core/image/pending_signals.c — the opt-in a program calls so that the
 * temporaries of PNGs being written (tessera/image.h) are removed when
 * SIGTERM, SIGINT or SIGHUP end it. Owns, once it is called, the
 * process's table of pending PNGs and the handlers over those signals'
 * default actions. Never installs anything unless the program asks, and
 * never replaces a handler installed before. */
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <string.h>

#include "tessera/image.h"

/* Set once, by the first call; read by the handler. */
static tsr_image_pending *program_table;

/* Removes the listed temporaries, then lets the signal end the process as
 * before: SA_RESETHAND restored the default action. */
static void remove_temporaries_and_die(int sig)
{
    int saved_errno = errno;
    tsr_image_pending_remove_all(program_table);
    errno = saved_errno;
    raise(sig);
}

static void install_once(void)
{
    static const int signals[] = {SIGTERM, SIGINT, SIGHUP};
    program_table = tsr_image_pending_create();
    if (!program_table)
        return;
    tsr_image_set_pending(program_table);
    for (size_t i = 0; i < sizeof signals / sizeof signals[0]; i++) {
        struct sigaction old, sa;
        if (sigaction(signals[i], NULL, &old) != 0 || (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL)
            continue; /* the program's own handler: left alone */
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = remove_temporaries_and_die;
        sa.sa_flags = SA_RESETHAND;
        sigfillset(&sa.sa_mask);
        sigaction(signals[i], &sa, NULL);
    }
}

int tsr_image_pending_remove_on_signals(tsr_error *err)
{
    static pthread_once_t once = PTHREAD_ONCE_INIT;
    pthread_once(&once, install_once);
    if (!program_table)
        return tsr_error_set(err, TSR_ENOMEM, "PNG temporaries: out of memory for the table");
    return 0;
}
