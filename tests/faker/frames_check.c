/* tests/faker/frames_check.c — faker_frames [--some-blank] DIR PREFIX MIN: the
 * PNG frames DIR/PREFIX0000.png, PREFIX0001.png, ... a faker run wrote. At
 * least MIN of them, in sequence from 0, must read as PNGs, each with more
 * than one colour, and not all the same picture. With --some-blank, frames
 * of one colour are allowed (programs that fade in from black) and MIN
 * counts the others. Only the newest file may be unreadable: the program
 * was ended by SIGTERM, possibly mid-write. The frames judged are those
 * there when the check starts: a program still running writes more, and a
 * reader that followed them never ended while they came faster than it
 * decoded (glxgears under pack wrote 75,000 frames at 250 a second while
 * the sweep's check, at load 16, chased them until the test's 300 s). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "tessera/image.h"

int main(int argc, char **argv)
{
    bool some_blank = argc > 1 && !strcmp(argv[1], "--some-blank");
    if (some_blank)
        argc--, argv++;
    if (argc != 4) {
        fprintf(stderr, "usage: faker_frames [--some-blank] DIR PREFIX MIN\n");
        return 2;
    }
    setvbuf(stdout, NULL, _IOLBF, 0); /* in order with the reports on stderr */
    int min = atoi(argv[3]), good = 0, blank = 0, distinct = 0, width = 0, height = 0;
    char path[4096];
    int count = 0;
    for (;; count++) {
        snprintf(path, sizeof path, "%s/%s%04d.png", argv[1], argv[2], count);
        if (access(path, F_OK) != 0)
            break;
    }
    tsr_image first = {0};
    for (int i = 0; i < count; i++) {
        snprintf(path, sizeof path, "%s/%s%04d.png", argv[1], argv[2], i);
        tsr_image img = {0};
        tsr_error err = {0};
        if (tsr_image_read_png(&img, path, &err) != TSR_OK) {
            REQUIRE(i == count - 1, "%s", err.message);
            break; /* the newest file, cut off by SIGTERM or still being written */
        }
        int colours = 1;
        for (size_t k = 1; k < (size_t)img.width * (size_t)img.height && colours == 1; k++)
            if (memcmp(img.pixels + 4 * k, img.pixels, 4) != 0)
                colours = 2;
        if (colours == 1 && some_blank) {
            blank++;
            tsr_image_free(&img);
            continue;
        }
        REQUIRE(colours > 1, "%s is all one colour (RGBA %u %u %u %u)", path, img.pixels[0], img.pixels[1],
                img.pixels[2], img.pixels[3]);
        if (!first.pixels) {
            first = img;
            width = img.width;
            height = img.height;
        } else {
            REQUIRE(img.width == width && img.height == height, "%s is %dx%d, frame 0 %dx%d", path, img.width,
                    img.height, width, height);
            if (memcmp(img.pixels, first.pixels, (size_t)width * (size_t)height * 4) != 0)
                distinct++;
            tsr_image_free(&img);
        }
        good++;
    }
    tsr_image_free(&first);
    if (some_blank)
        printf("%d readable frames of %dx%d not of one colour, %d of one colour, %d differing from the first\n", good,
               width, height, blank, distinct);
    else
        printf("%d readable frames of %dx%d, none of one colour, %d differing from frame 0\n", good, width, height,
               distinct);
    CHECK(good >= min, "fewer than %d frames", min);
    CHECK(distinct > 0, "every frame is the same picture");
    return harness_failures ? 1 : 0;
}
