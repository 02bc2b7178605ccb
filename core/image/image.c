/* core/image/image.c — RGBA8 images: PNG I/O through libpng, compare, row flip.
 * Owns the libpng setjmp/longjmp boundary: every libpng call happens in a
 * function whose locals are not touched after setjmp, and libpng errors
 * become tsr_error values naming the file. Owns the tsr_image_pending
 * table's code; the table itself, and the signal handler that empties it,
 * belong to the program (tsr_image_set_pending). Never prints, exits,
 * aborts or installs a signal handler. */
#include "tessera/image.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Shared by a libpng call and its error callback. Lives in the caller of
 * the function that runs setjmp, so nothing it holds is an automatic
 * variable of that function (those are indeterminate after longjmp). */
typedef struct png_job {
    const char *path;
    FILE *file;
    char message[256]; /* libpng's error text */
    /* reading */
    tsr_image *out; /* NULL: the header only */
    png_bytep *rows;
    uint64_t max_pixels;
    uint32_t width_read, height_read;
    bool over_limit;
    /* writing */
    const uint8_t *pixels;
    int width, height;
    size_t stride;
    bool bottom_up;
    bool opaque; /* write RGB: each pixel's fourth byte is dropped */
} png_job;

static void png_job_error(png_structp png, png_const_charp msg)
{
    png_job *job = png_get_error_ptr(png);
    snprintf(job->message, sizeof job->message, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}

static void png_job_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* warnings (e.g. a bad sRGB chunk) do not change the pixels we use */
}

int tsr_image_alloc(tsr_image *img, int width, int height, tsr_error *err)
{
    memset(img, 0, sizeof *img);
    if (width < 1 || height < 1 || width > TSR_IMAGE_MAX_SIDE || height > TSR_IMAGE_MAX_SIDE)
        return tsr_error_set(err, TSR_EINVAL, "image size %dx%d out of range (1..%d per side)", width, height,
                             TSR_IMAGE_MAX_SIDE);
    size_t stride = (size_t)width * 4;
    uint8_t *pixels = calloc((size_t)height, stride);
    if (!pixels)
        return tsr_error_set(err, TSR_ENOMEM, "out of memory for a %dx%d image", width, height);
    img->width = width;
    img->height = height;
    img->stride = stride;
    img->pixels = pixels;
    return TSR_OK;
}

void tsr_image_free(tsr_image *img)
{
    if (!img)
        return;
    free(img->pixels);
    memset(img, 0, sizeof *img);
}

/* --- reading ------------------------------------------------------------ */

/* All libpng reading happens here. Returns 0, or -1 with job->message set.
 * Every object touched after setjmp lives in `job` (caller's frame). */
static int read_png_guarded(png_structp png, png_infop info, png_job *job)
{
    if (setjmp(png_jmpbuf(png)))
        return -1;
    png_init_io(png, job->file);
    png_set_sig_bytes(png, 8);
    /* PNG's own bound (2^31 - 1 per side): the limits are checked below,
     * so the error can name them. */
    png_set_user_limits(png, 0x7fffffff, 0x7fffffff);
    png_read_info(png, info);
    job->width_read = png_get_image_width(png, info);
    job->height_read = png_get_image_height(png, info);
    if (job->width_read > TSR_IMAGE_MAX_SIDE || job->height_read > TSR_IMAGE_MAX_SIDE ||
        (uint64_t)job->width_read * job->height_read > job->max_pixels) {
        job->over_limit = true;
        return -1;
    }
    if (!job->out)
        return 0;

    png_byte color_type = png_get_color_type(png, info);
    png_byte bit_depth = png_get_bit_depth(png, info);
    if (color_type == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS))
        png_set_tRNS_to_alpha(png);
    if (bit_depth == 16)
        png_set_strip_16(png);
    if (color_type == PNG_COLOR_TYPE_GRAY || color_type == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER); /* no-op when alpha exists */
    png_set_interlace_handling(png);
    png_read_update_info(png, info);

    png_uint_32 w = png_get_image_width(png, info);
    png_uint_32 h = png_get_image_height(png, info);
    if (png_get_rowbytes(png, info) != (size_t)w * 4) {
        snprintf(job->message, sizeof job->message, "unexpected row layout after RGBA conversion");
        return -1;
    }
    tsr_error alloc_err;
    if (tsr_image_alloc(job->out, (int)w, (int)h, &alloc_err) != TSR_OK) {
        snprintf(job->message, sizeof job->message, "%.200s", alloc_err.message);
        return -1;
    }
    job->rows = malloc((size_t)h * sizeof *job->rows);
    if (!job->rows) {
        snprintf(job->message, sizeof job->message, "out of memory for row pointers");
        return -1;
    }
    for (png_uint_32 y = 0; y < h; y++)
        job->rows[y] = job->out->pixels + (size_t)y * job->out->stride;
    png_read_image(png, job->rows);
    png_read_end(png, NULL);
    return 0;
}

/* Reads `path` into job->out, or only its header when that is NULL. */
static int read_png(png_job *job, tsr_error *err)
{
    const char *path = job->path;
    job->file = fopen(path, "rb");
    if (!job->file)
        return tsr_error_set(err, errno == ENOENT ? TSR_ENOENT : TSR_EIO, "%s: %s", path, strerror(errno));
    unsigned char sig[8];
    size_t got = fread(sig, 1, sizeof sig, job->file);
    if (got != sizeof sig || png_sig_cmp(sig, 0, sizeof sig) != 0) {
        fclose(job->file);
        return tsr_error_set(err, TSR_EINVAL, "%s: not a PNG file", path);
    }
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, job, png_job_error, png_job_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_read_struct(&png, NULL, NULL);
        fclose(job->file);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for libpng", path);
    }
    int rc = read_png_guarded(png, info, job);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(job->file);
    free(job->rows);
    if (rc != 0 && job->out)
        tsr_image_free(job->out);
    if (job->over_limit && (job->width_read > TSR_IMAGE_MAX_SIDE || job->height_read > TSR_IMAGE_MAX_SIDE))
        return tsr_error_set(err, TSR_EINVAL, "%s: claims %ux%u pixels, more than the limit of %d per side", path,
                             job->width_read, job->height_read, TSR_IMAGE_MAX_SIDE);
    if (job->over_limit)
        return tsr_error_set(err, TSR_EINVAL, "%s: claims %ux%u = %llu pixels, more than the limit of %llu pixels",
                             path, job->width_read, job->height_read,
                             (unsigned long long)job->width_read * job->height_read,
                             (unsigned long long)job->max_pixels);
    if (rc != 0)
        return tsr_error_set(err, TSR_EINVAL, "%s: bad PNG: %s", path, job->message);
    return TSR_OK;
}

int tsr_image_read_png_limited(tsr_image *img, const char *path, uint64_t max_pixels, tsr_error *err)
{
    memset(img, 0, sizeof *img);
    png_job job = {.path = path, .out = img, .max_pixels = max_pixels};
    return read_png(&job, err);
}

int tsr_image_read_png(tsr_image *img, const char *path, tsr_error *err)
{
    return tsr_image_read_png_limited(img, path, (uint64_t)TSR_IMAGE_MAX_SIDE * TSR_IMAGE_MAX_SIDE, err);
}

int tsr_image_read_png_size(const char *path, uint64_t max_pixels, int *width, int *height, tsr_error *err)
{
    png_job job = {.path = path, .max_pixels = max_pixels};
    int rc = read_png(&job, err);
    *width = rc == TSR_OK ? (int)job.width_read : 0;
    *height = rc == TSR_OK ? (int)job.height_read : 0;
    return rc;
}

/* --- writing ------------------------------------------------------------ */

static int write_png_guarded(png_structp png, png_infop info, png_job *job)
{
    if (setjmp(png_jmpbuf(png)))
        return -1;
    png_init_io(png, job->file);
    /* Frames are written often and read back by tests: favour speed. */
    png_set_compression_level(png, 1);
    png_set_IHDR(png, info, (png_uint_32)job->width, (png_uint_32)job->height, 8,
                 job->opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    /* The rows stay RGBA8 in memory; libpng strips the filler byte. */
    if (job->opaque)
        png_set_filler(png, 0, PNG_FILLER_AFTER);
    for (int y = 0; y < job->height; y++) {
        int src_row = job->bottom_up ? job->height - 1 - y : y;
        png_write_row(png, job->pixels + (size_t)src_row * job->stride);
    }
    png_write_end(png, NULL);
    return 0;
}

/* A PNG is written to a temporary file in its own directory and renamed
 * over its name when whole, so a reader, or a kill at any moment, never
 * sees a part of one. A terminating signal would still leave the temporary
 * behind: a program that minds lists those being written in a table it
 * owns and empties it from its own handler (tessera/image.h). Each slot's
 * path is a fixed buffer (the handler may not touch freed memory);
 * `state` is 0 free, 1 claimed, 2 listed, and `pid` keeps a forked child
 * that is signalled before its exec from removing its parent's files. */
#define PENDING_SLOTS 32
typedef struct pending_png {
    atomic_int state;
    pid_t pid;
    char path[PATH_MAX];
} pending_png;
struct tsr_image_pending {
    pending_png slots[PENDING_SLOTS];
};

/* The program's table, NULL when it gave none: the one process-wide hook
 * of this file, set only by the program (docs/architecture.md). */
static _Atomic(tsr_image_pending *) program_pending;

tsr_image_pending *tsr_image_pending_create(void) { return calloc(1, sizeof(tsr_image_pending)); }

void tsr_image_pending_destroy(tsr_image_pending *pending)
{
    tsr_image_pending *expected = pending;
    atomic_compare_exchange_strong(&program_pending, &expected, NULL);
    free(pending);
}

void tsr_image_set_pending(tsr_image_pending *pending) { atomic_store(&program_pending, pending); }

void tsr_image_pending_remove_all(tsr_image_pending *pending)
{
    if (!pending)
        return;
    pid_t self = getpid();
    for (size_t i = 0; i < PENDING_SLOTS; i++)
        if (atomic_load(&pending->slots[i].state) == 2 && pending->slots[i].pid == self)
            unlink(pending->slots[i].path);
}

/* Lists `tmp` in `pending`; returns its slot, or -1 without a table or
 * when every slot is taken (the file is then written unlisted: still whole
 * or absent, only a signal may leave the temporary). */
static int pending_add(tsr_image_pending *pending, const char *tmp)
{
    for (int i = 0; pending && i < PENDING_SLOTS; i++) {
        pending_png *slot = &pending->slots[i];
        int expected = 0;
        if (!atomic_compare_exchange_strong(&slot->state, &expected, 1))
            continue;
        snprintf(slot->path, sizeof slot->path, "%s", tmp);
        slot->pid = getpid();
        atomic_store(&slot->state, 2);
        return i;
    }
    return -1;
}

static void pending_remove(tsr_image_pending *pending, int slot)
{
    if (pending && slot >= 0)
        atomic_store(&pending->slots[slot].state, 0);
}

/* "DIR/.NAME.tmp-PID-N" for `path` "DIR/NAME": hidden, in the same
 * directory (rename is atomic only within one file system), unique per
 * process and call. */
static int temp_name(char *out, size_t size, const char *path)
{
    static atomic_uint sequence;
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    int dir_len = slash ? (int)(slash - path + 1) : 0;
    /* Keep the name under NAME_MAX (255) whatever the final name's length. */
    int n = snprintf(out, size, "%.*s.%.200s.tmp-%ld-%u", dir_len, path, base, (long)getpid(),
                     atomic_fetch_add(&sequence, 1));
    return n < 0 || (size_t)n >= size ? -1 : 0;
}

static int write_png_pixels(const uint8_t *pixels, int width, int height, size_t stride, bool bottom_up, bool opaque,
                            const char *path, tsr_error *err)
{
    if (!pixels || width < 1 || height < 1 || width > TSR_IMAGE_MAX_SIDE || height > TSR_IMAGE_MAX_SIDE ||
        stride < (size_t)width * 4)
        return tsr_error_set(err, TSR_EINVAL, "%s: cannot write a %dx%d image with stride %zu", path, width, height,
                             stride);
    char tmp[PATH_MAX];
    if (temp_name(tmp, sizeof tmp, path) != 0)
        return tsr_error_set(err, TSR_EINVAL, "%s: file name too long", path);
    png_job job = {.path = path,
                   .pixels = pixels,
                   .width = width,
                   .height = height,
                   .stride = stride,
                   .bottom_up = bottom_up,
                   .opaque = opaque};
    tsr_image_pending *pending = atomic_load(&program_pending);
    int slot = pending_add(pending, tmp);
    int fd = open(tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    job.file = fd >= 0 ? fdopen(fd, "wb") : NULL;
    if (!job.file) {
        int saved_errno = errno;
        if (fd >= 0) {
            close(fd);
            unlink(tmp);
        }
        pending_remove(pending, slot);
        return tsr_error_set(err, saved_errno == ENOENT ? TSR_ENOENT : TSR_EIO, "cannot create %s: %s", path,
                             strerror(saved_errno));
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &job, png_job_error, png_job_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_write_struct(&png, NULL);
        fclose(job.file);
        unlink(tmp);
        pending_remove(pending, slot);
        return tsr_error_set(err, TSR_ENOMEM, "%s: out of memory for libpng", path);
    }
    int rc = write_png_guarded(png, info, &job);
    png_destroy_write_struct(&png, &info);
    int close_failed = fclose(job.file) != 0;
    int saved_errno = errno;
    int renamed = rc == 0 && !close_failed && rename(tmp, path) == 0;
    if (!renamed) {
        if (rc == 0 && !close_failed)
            saved_errno = errno; /* rename's */
        unlink(tmp);
    }
    pending_remove(pending, slot);
    if (rc != 0)
        return tsr_error_set(err, TSR_EIO, "%s: writing PNG failed: %s", path, job.message);
    if (!renamed)
        return tsr_error_set(err, TSR_EIO, "%s: %s", path, strerror(saved_errno));
    return TSR_OK;
}

int tsr_image_write_png_pixels(const uint8_t *pixels, int width, int height, size_t stride, bool bottom_up,
                               bool keep_alpha, const char *path, tsr_error *err)
{
    return write_png_pixels(pixels, width, height, stride, bottom_up, !keep_alpha, path, err);
}

int tsr_image_write_png(const tsr_image *img, const char *path, tsr_error *err)
{
    return tsr_image_write_png_pixels(img->pixels, img->width, img->height, img->stride, false, true, path, err);
}

/* --- compare and flip --------------------------------------------------- */

int tsr_image_compare(const tsr_image *a, const tsr_image *b, int tolerance, tsr_image_diff *out, tsr_error *err)
{
    memset(out, 0, sizeof *out);
    if (a->width != b->width || a->height != b->height)
        return tsr_error_set(err, TSR_EINVAL, "size mismatch: %dx%d vs %dx%d", a->width, a->height, b->width,
                             b->height);
    if (tolerance < 0)
        return tsr_error_set(err, TSR_EINVAL, "tolerance %d is negative", tolerance);
    uint64_t differing = 0;
    uint64_t squared_sum = 0;
    int max_error = 0;
    for (int y = 0; y < a->height; y++) {
        const uint8_t *pa = a->pixels + (size_t)y * a->stride;
        const uint8_t *pb = b->pixels + (size_t)y * b->stride;
        for (int x = 0; x < a->width; x++, pa += 4, pb += 4) {
            int pixel_max = 0;
            for (int c = 0; c < 4; c++) {
                int d = abs((int)pa[c] - (int)pb[c]);
                squared_sum += (uint64_t)(d * d);
                if (d > pixel_max)
                    pixel_max = d;
            }
            if (pixel_max > tolerance)
                differing++;
            if (pixel_max > max_error)
                max_error = pixel_max;
        }
    }
    out->differing_pixels = differing;
    out->max_channel_error = max_error;
    if (squared_sum == 0) {
        out->psnr_db = INFINITY;
    } else {
        double mse = (double)squared_sum / ((double)a->width * a->height * 4.0);
        out->psnr_db = 10.0 * log10(255.0 * 255.0 / mse);
    }
    return TSR_OK;
}

void tsr_image_flip_rows(uint8_t *pixels, int height, size_t stride)
{
    uint8_t tmp[1024];
    for (int top = 0, bottom = height - 1; top < bottom; top++, bottom--) {
        uint8_t *rt = pixels + (size_t)top * stride;
        uint8_t *rb = pixels + (size_t)bottom * stride;
        /* swap in chunks so any width works without allocating */
        for (size_t off = 0; off < stride; off += sizeof tmp) {
            size_t n = stride - off < sizeof tmp ? stride - off : sizeof tmp;
            memcpy(tmp, rt + off, n);
            memcpy(rt + off, rb + off, n);
            memcpy(rb + off, tmp, n);
        }
    }
}

/* --- frame file names --------------------------------------------------- */

/* The integer conversions in `pattern` (0 or 1), or -1 when it holds any
 * other '%' use or more than one. */
static int frame_conversions(const char *pattern)
{
    int conversions = 0;
    for (const char *p = pattern; *p; p++) {
        if (*p != '%')
            continue;
        p++;
        if (*p == '%')
            continue;
        while (*p && strchr("0-+ ", *p))
            p++;
        int width_digits = 0;
        while (*p >= '0' && *p <= '9') {
            p++;
            width_digits++;
        }
        if ((*p != 'd' && *p != 'i') || width_digits > 2 || ++conversions > 1)
            return -1;
    }
    return conversions;
}

int tsr_image_frame_path(char *out, size_t size, const char *pattern, int frame, tsr_error *err)
{
    if (frame_conversions(pattern) < 0)
        return tsr_error_set(err, TSR_EINVAL, "bad file pattern '%s': allowed is one %%d (e.g. %%04d) and %%%%",
                             pattern);
        /* The pattern was checked above: at most one int conversion. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    int n = snprintf(out, size, pattern, frame);
#pragma GCC diagnostic pop
    if (n < 0 || (size_t)n >= size)
        return tsr_error_set(err, TSR_EINVAL, "file pattern '%s' gives a name longer than %zu bytes", pattern,
                             size - 1);
    return TSR_OK;
}

int tsr_image_check_frame_pattern(const char *who, const char *option, const char *pattern, bool overwrite,
                                  const char *overwrite_option, tsr_error *err)
{
    int conversions = frame_conversions(pattern);
    if (conversions < 0)
        return tsr_error_set(err, TSR_EINVAL,
                             "%s: option %s: bad file pattern '%s': allowed is one %%d (e.g. %%04d) and %%%%", who,
                             option, pattern);
    if (conversions == 1 || overwrite)
        return TSR_OK;
    /* The suggestion: the pattern with -%04d before its extension. */
    const char *slash = strrchr(pattern, '/');
    const char *dot = strrchr(slash ? slash : pattern, '.');
    int at = dot && dot != (slash ? slash + 1 : pattern) ? (int)(dot - pattern) : (int)strlen(pattern);
    return tsr_error_set(err, TSR_EINVAL,
                         "%s: option %s=%s has no frame number: every frame would overwrite that one file; "
                         "put one %%d in it (e.g. %.*s-%%04d%s) or give %s=1 to keep only the last frame",
                         who, option, pattern, at, pattern, pattern + at, overwrite_option);
}
