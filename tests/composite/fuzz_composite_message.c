/* tests/composite/fuzz_composite_message.c — what one fuzz input exercises:
 * the bounds-checked image-message decoder and, on what it accepts, the
 * sparse-image operations and every encoder. Owns nothing between calls. */
#include "fuzz_composite_message.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "tessera/dev/composite.h"

static const char *const CODECS[] = {"none", "rle", "erle", "yuv420", "depth16", "depth24", "erle+depth24"};

static void must(int ok, const char *what)
{
    if (!ok) {
        fprintf(stderr, "fuzz_composite_message: invariant broken: %s\n", what);
        abort();
    }
}

int fuzz_composite_message_one(const uint8_t *data, size_t size)
{
    tsr_error err;
    tsr_composite_sparse s = {0}, half = {0}, blank = {0}, merged = {0}, again = {0};
    if (tsr_composite_message_decode(data, size, NULL, &s, &err) != TSR_OK) {
        must(err.message[0] != 0, "a rejection without a message");
        tsr_composite_sparse_free(&s);
        return 1;
    }
    uint64_t pixels = 0, active = 0;
    for (uint32_t r = 0; r < s.nruns; r++) {
        pixels += (uint64_t)s.runs[2 * r] + s.runs[2 * r + 1];
        active += s.runs[2 * r + 1];
    }
    must(pixels == s.count && active == s.active, "runs disagree with the counts");
    must(tsr_composite_sparse_split(&s, s.start + s.count / 3, s.count / 2, &half, &err) == TSR_OK, "split");
    must(tsr_composite_sparse_blank(&blank, s.window_width, s.window_height, s.start, s.count, s.mode, s.color_format,
                                    s.depth_format, s.rank + s.rank_count, s.frame, &err) == TSR_OK,
         "blank");
    must(tsr_composite_sparse_merge(&s, &blank, &merged, &err) == TSR_OK, "merge with blank");
    must(merged.active == s.active, "merge with blank changed the active pixels");
    /* assemble into the rows the range touches, when that is small */
    uint32_t w = (uint32_t)s.window_width, y0 = s.start / w, y1 = s.count ? (s.start + s.count - 1) / w + 1 : y0;
    if ((uint64_t)(y1 - y0) * w <= (1u << 20) && s.count) {
        tsr_composite_image d = {0};
        must(tsr_composite_image_init(&d, s.window_width, s.window_height, 0, (int)y0, s.window_width, (int)(y1 - y0),
                                      s.color_format, s.depth_format, &err) == TSR_OK,
             "frame");
        static const float bg[4] = {0, 0, 0, 0};
        must(tsr_composite_sparse_to_dense(&merged, bg, &d, &err) == TSR_OK, "to dense");
        tsr_composite_image_free(&d);
    }
    if (s.count <= (1u << 20))
        for (size_t c = 0; c < sizeof CODECS / sizeof *CODECS; c++) {
            tsr_composite_codec codec;
            tsr_composite_codec_parse(CODECS[c], &codec, &err);
            size_t cap = tsr_composite_message_max_size(s.count, s.color_format, s.depth_format, codec), len = 0;
            uint8_t *buf = malloc(cap);
            must(buf != NULL, "memory");
            int rc = tsr_composite_message_encode(&s, codec, buf, cap, &len, &err);
            must(rc == TSR_OK || rc == TSR_EUNSUPPORTED, "re-encode");
            if (rc == TSR_OK) {
                must(len <= cap, "an encoding above its worst case");
                must(tsr_composite_message_decode(buf, len, NULL, &again, &err) == TSR_OK, "re-decode");
                must(again.count == s.count && (!codec.runs || again.active == s.active),
                     "re-decode changed the image");
            }
            free(buf);
        }
    tsr_composite_sparse_free(&s);
    tsr_composite_sparse_free(&half);
    tsr_composite_sparse_free(&blank);
    tsr_composite_sparse_free(&merged);
    tsr_composite_sparse_free(&again);
    return 0;
}

#ifdef TSR_FUZZ_MAIN
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_composite_message_one(data, size);
    return 0;
}
#endif
