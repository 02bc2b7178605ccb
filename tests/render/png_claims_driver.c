/* tests/render/png_claims_driver.c — writes a small PNG file whose header claims
 * WIDTH x HEIGHT pixels (RGBA8) but whose image data is a few bytes: what
 * a crafted file costs a reader that trusts its header (issue 10, defect
 * 11). Every chunk's CRC is right, so only the size is a lie.
 * usage: png_claims OUT.png WIDTH HEIGHT */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

static uint32_t crc32_of(const uint8_t *p, size_t n)
{
    uint32_t c = 0xffffffffu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

static void put_u32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* length, type, data, CRC over type and data */
static void chunk(FILE *f, const char *type, const uint8_t *data, uint32_t len)
{
    uint8_t buf[64];
    REQUIRE(len + 8 <= sizeof buf);
    put_u32(buf, len);
    memcpy(buf + 4, type, 4);
    if (len)
        memcpy(buf + 8, data, len);
    uint8_t crc[4];
    put_u32(crc, crc32_of(buf + 4, len + 4));
    fwrite(buf, 1, len + 8, f);
    fwrite(crc, 1, 4, f);
}

int main(int argc, char **argv)
{
    REQUIRE(argc == 4, "usage: png_claims OUT.png WIDTH HEIGHT");
    uint32_t w = (uint32_t)strtoul(argv[2], NULL, 10), h = (uint32_t)strtoul(argv[3], NULL, 10);
    FILE *f = fopen(argv[1], "wb");
    REQUIRE(f, "cannot create %s", argv[1]);
    static const uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    fwrite(sig, 1, sizeof sig, f);
    uint8_t ihdr[13];
    put_u32(ihdr, w);
    put_u32(ihdr + 4, h);
    ihdr[8] = 8;  /* bit depth */
    ihdr[9] = 6;  /* RGBA */
    ihdr[10] = 0; /* deflate */
    ihdr[11] = 0; /* adaptive filtering */
    ihdr[12] = 0; /* not interlaced */
    chunk(f, "IHDR", ihdr, sizeof ihdr);
    /* a zlib stream holding one stored block of one zero byte: far less
     * than the rows claimed */
    static const uint8_t idat[] = {0x78, 0x01, 0x01, 0x01, 0x00, 0xfe, 0xff, 0x00, 0x00, 0x01, 0x00, 0x01};
    chunk(f, "IDAT", idat, sizeof idat);
    chunk(f, "IEND", NULL, 0);
    REQUIRE(fclose(f) == 0, "writing %s failed", argv[1]);
    return 0;
}
