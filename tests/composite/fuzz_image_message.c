/* tests/composite/fuzz_image_message.c — what one fuzz input exercises:
 * the bounds-checked image-message decoder and, on what it accepts, the
 * sparse-image operations and every encoder. Owns nothing between calls. */
#include "fuzz_image_message.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "tessera/dev/composite.h"

static const char *const CODECS[] = {"none", "rle", "erle", "yuv420", "depth16", "depth24", "erle+depth24"};

static void must(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_image_message: invariant broken: %s\n", what);
        abort();
    }
}

int fuzz_image_message_one(const uint8_t *data, size_t size)
{
    tsr_error err;
    tsr_sparse_image s = {0}, half = {0}, blank = {0}, merged = {0}, again = {0};
    if (tsr_image_message_decode(data, size, NULL, &s, &err) != TSR_OK) {
        must(err.message[0] != 0, "a rejection without a message");
        tsr_sparse_image_free(&s);
        return 1;
    }
    uint64_t pixels = 0, active = 0;
    for (uint32_t r = 0; r < s.nruns; r++) {
        pixels += (uint64_t)s.runs[2 * r] + s.runs[2 * r + 1];
        active += s.runs[2 * r + 1];
    }
    must(pixels == s.count && active == s.active, "runs disagree with the counts");
    must(tsr_sparse_image_split(&s, s.start + s.count / 3, s.count / 2, &half, &err) == TSR_OK, "split");
    must(tsr_sparse_image_blank(&blank, s.window_width, s.window_height, s.start, s.count, s.mode, s.color_format,
                                s.depth_format, s.rank + s.rank_count, s.frame, &err) == TSR_OK,
         "blank");
    must(tsr_sparse_image_merge(&s, &blank, &merged, &err) == TSR_OK, "merge with blank");
    must(merged.active == s.active, "merge with blank changed the active pixels");
    /* assemble into the rows the range touches, when that is small */
    uint32_t w = (uint32_t)s.window_width, y0 = s.start / w, y1 = s.count ? (s.start + s.count - 1) / w + 1 : y0;
    if ((uint64_t)(y1 - y0) * w <= (1u << 20) && s.count) {
        tsr_cimage d = {0};
        must(tsr_cimage_init(&d, s.window_width, s.window_height, 0, (int)y0, s.window_width, (int)(y1 - y0),
                             s.color_format, s.depth_format, &err) == TSR_OK,
             "frame");
        static const float bg[4] = {0, 0, 0, 0};
        must(tsr_sparse_image_to_dense(&merged, bg, &d, &err) == TSR_OK, "to dense");
        tsr_cimage_free(&d);
    }
    if (s.count <= (1u << 20))
        for (size_t c = 0; c < sizeof CODECS / sizeof *CODECS; c++) {
            tsr_image_codec codec;
            tsr_image_codec_parse(CODECS[c], &codec, &err);
            size_t cap = tsr_image_message_max_size(s.count, s.color_format, s.depth_format, codec), len = 0;
            uint8_t *buf = malloc(cap);
            must(buf != NULL, "memory");
            int rc = tsr_image_message_encode(&s, codec, buf, cap, &len, &err);
            must(rc == TSR_OK || rc == TSR_EUNSUPPORTED, "re-encode");
            if (rc == TSR_OK) {
                must(len <= cap, "an encoding above its worst case");
                must(tsr_image_message_decode(buf, len, NULL, &again, &err) == TSR_OK, "re-decode");
                must(again.count == s.count && (!codec.runs || again.active == s.active),
                     "re-decode changed the image");
            }
            free(buf);
        }
    tsr_sparse_image_free(&s);
    tsr_sparse_image_free(&half);
    tsr_sparse_image_free(&blank);
    tsr_sparse_image_free(&merged);
    tsr_sparse_image_free(&again);
    return 0;
}

#ifdef TSR_FUZZ_MAIN
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_image_message_one(data, size);
    return 0;
}
#endif
