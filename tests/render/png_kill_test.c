/* tests/render/png_kill_test.c — a rendering node killed while it writes
 * frames leaves only whole PNGs (issue 10, defect 8).
 *
 * usage: png_kill_test BIN_DIR OUT_DIR ROUNDS
 *
 * Each round starts a real `tessera node` whose render SPU writes a
 * 1024x768 PNG per frame, streams spheres into it through the real pack
 * SPU over a Unix socket, and once frames appear kills the node (SIGKILL
 * in half the rounds, SIGTERM in the other half) after a delay that moves
 * through the frame's time, so kills land inside the PNG writer. Then
 * every f-NNNN.png in the output folder must be read whole by libpng
 * (tsr_image_read_png decodes every row and reads to the end) and end with
 * the IEND chunk; after SIGTERM no temporary file may be left (SIGKILL may
 * leave one: nothing runs after it, and it is hidden, never a frame name).
 * Owns the processes it starts; every wait is bounded. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "tessera/error.h"
#include "tessera/image.h"

static void sleep_ms(long ms)
{
    struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static pid_t spawn(char *const argv[], const char *err_path)
{
    pid_t pid = fork();
    REQUIRE(pid >= 0, "fork: %s", strerror(errno));
    if (pid == 0) {
        int fd = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
        }
        execv(argv[0], argv);
        _exit(127);
    }
    return pid;
}

/* Waits at most `ms` for `pid`; kills it (SIGKILL) if still running.
 * Returns its wait status. */
static int wait_bounded(pid_t pid, long ms)
{
    int st = 0;
    for (long waited = 0; waited < ms; waited += 10) {
        if (waitpid(pid, &st, WNOHANG) == pid)
            return st;
        sleep_ms(10);
    }
    kill(pid, SIGKILL);
    waitpid(pid, &st, 0);
    return st;
}

static int file_contains(const char *path, const char *text)
{
    char buf[4096];
    FILE *f = fopen(path, "r");
    size_t n = f ? fread(buf, 1, sizeof buf - 1, f) : 0;
    if (f)
        fclose(f);
    buf[n] = '\0';
    return strstr(buf, text) != NULL;
}

static int count_frames(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += !strncmp(e->d_name, "f-", 2);
    if (d)
        closedir(d);
    return n;
}

/* The file ends with a whole IEND chunk: length 0, "IEND", its CRC. */
static int ends_with_iend(const char *path)
{
    static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
    FILE *f = fopen(path, "rb");
    unsigned char tail[12];
    int ok = f && fseek(f, -12, SEEK_END) == 0 && fread(tail, 1, 12, f) == 12 && !memcmp(tail, iend, 12);
    if (f)
        fclose(f);
    return ok;
}

typedef struct tally {
    int pngs, temps_after_kill;
} tally;

/* Checks every file in `dir`; removes what it checked. */
static void check_folder(const char *dir, int sig, int round, tally *t)
{
    DIR *d = opendir(dir);
    REQUIRE(d, "%s: %s", dir, strerror(errno));
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (strstr(e->d_name, ".tmp-")) {
            CHECK(e->d_name[0] == '.', "round %d: temporary %s is not hidden", round, e->d_name);
            CHECK(sig == SIGKILL, "round %d (SIGTERM): temporary %s left behind", round, e->d_name);
            t->temps_after_kill++;
        } else {
            struct stat st;
            stat(path, &st);
            tsr_image img;
            tsr_error err = {0};
            int rc = tsr_image_read_png(&img, path, &err);
            CHECK(rc == TSR_OK, "round %d (%s): %s (%lld bytes) is not a whole PNG: %s", round,
                  sig == SIGKILL ? "SIGKILL" : "SIGTERM", e->d_name, (long long)st.st_size, err.message);
            if (rc == TSR_OK) {
                CHECK(img.width == 1024 && img.height == 768, "%s is %dx%d", e->d_name, img.width, img.height);
                tsr_image_free(&img);
            }
            CHECK(ends_with_iend(path), "round %d: %s does not end with IEND", round, e->d_name);
            t->pngs++;
        }
        unlink(path);
    }
    closedir(d);
}

int main(int argc, char **argv)
{
    REQUIRE(argc == 4, "usage: png_kill_test BIN_DIR OUT_DIR ROUNDS");
    const char *bin = argv[1], *out = argv[2];
    int rounds = atoi(argv[3]);
    char tessera[4096], spheres[4096], frames_dir[4096], sock[4096], log_node[4096], log_app[4096];
    snprintf(tessera, sizeof tessera, "%s/tessera", bin);
    snprintf(spheres, sizeof spheres, "%s/spheres", bin);
    snprintf(frames_dir, sizeof frames_dir, "%s/frames", out);
    snprintf(sock, sizeof sock, "unix:%s/node.sock", out);
    snprintf(log_node, sizeof log_node, "%s/node.log", out);
    snprintf(log_app, sizeof log_app, "%s/app.log", out);
    mkdir(out, 0755);
    mkdir(frames_dir, 0755);
    char render[4200], pack[4200];
    snprintf(render, sizeof render, "render output=%s/f-%%04d.png", frames_dir);
    snprintf(pack, sizeof pack, "pack server=%s", sock);

    tally kill9 = {0}, term = {0};
    for (int round = 0; round < rounds; round++) {
        int sig = round % 2 ? SIGTERM : SIGKILL;
        check_folder(frames_dir, sig, -1, &(tally){0}); /* empty it */
        unlink(sock + 5);
        unlink(log_node); /* the child truncates it only after the fork: no old line may be read */
        char *node_argv[] = {tessera,        "node",  "--listen", sock,   "--clients", "1",
                             "--timeout-ms", "10000", "--chain",  render, NULL};
        pid_t node = spawn(node_argv, log_node);
        /* Its "listening on" line comes after listen(): the socket file
         * exists from bind() on, when a connect is still refused. */
        for (int i = 0; i < 1000 && !file_contains(log_node, "listening on "); i++)
            sleep_ms(10);
        REQUIRE(file_contains(log_node, "listening on "),
                "round %d: the node did not listen on %s within 10 s (see %s)", round, sock, log_node);
        char *app_argv[] = {spheres, "--frames", "100000", "--size", "1024x768", "--chain", pack, NULL};
        pid_t app = spawn(app_argv, log_app);
        for (int i = 0; i < 2000 && count_frames(frames_dir) == 0; i++)
            sleep_ms(5);
        REQUIRE(count_frames(frames_dir) > 0, "round %d: no frame within 10 s (see %s)", round, log_node);
        /* The delay walks through a frame's time (a few tens of ms). */
        sleep_ms(5 + (round * 7) % 60);
        kill(node, sig);
        int node_status = wait_bounded(node, 10000);
        CHECK(WIFSIGNALED(node_status) && WTERMSIG(node_status) == sig,
              "round %d: the node did not die of signal %d (status 0x%x)", round, sig, node_status);
        int app_status = wait_bounded(app, 10000);
        CHECK(!(WIFEXITED(app_status) && WEXITSTATUS(app_status) == 0), "round %d: the app exited 0", round);
        check_folder(frames_dir, sig, round, sig == SIGKILL ? &kill9 : &term);
    }
    printf("%d rounds: %d whole PNGs after SIGKILL (%d temporaries left), %d after SIGTERM (none may be)\n", rounds,
           kill9.pngs, kill9.temps_after_kill, term.pngs);
    unlink(sock + 5);
    return harness_failures ? 1 : 0;
}
