/* png.c — 8- and 16-bit PNG through libpng, in memory.
 *
 * Write encodes into a memory buffer and stores it with prw_write_file_atomic; read loads the whole
 * file and decodes from memory into RGBA8.  libpng reports errors by longjmp: each setjmp lives in
 * an *_inner function whose state is kept in a png_state owned by the caller's frame (never in
 * automatic variables modified after setjmp), so everything allocated is freed on either path.
 */
#include "prw_image.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct png_state {
    const char *path;
    char msg[256];
    /* read */
    const uint8_t *data;
    size_t size, pos;
    uint8_t *pixels;
    png_bytep *rows;
    /* write */
    uint8_t *out;
    size_t out_size, out_cap;
} png_state;

static void on_error(png_structp png, png_const_charp msg)
{
    png_state *s = png_get_error_ptr(png);
    snprintf(s->msg, sizeof s->msg, "%s", msg ? msg : "libpng error");
    for (char *p = s->msg; *p; p++) /* one clean line, whatever the file's bytes */
        if ((unsigned char)*p < 0x20 || *p == 0x7f) *p = '?';
    png_longjmp(png, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png; /* warnings (e.g. a bad ancillary chunk) are not failures; nothing below app/ prints */
    (void)msg;
}

static void on_read(png_structp png, png_bytep buf, size_t len)
{
    png_state *s = png_get_io_ptr(png);
    if (len > s->size - s->pos) png_error(png, "unexpected end of file (truncated PNG)");
    memcpy(buf, s->data + s->pos, len);
    s->pos += len;
}

static void on_write(png_structp png, png_bytep buf, size_t len)
{
    png_state *s = png_get_io_ptr(png);
    if (s->out_size + len > s->out_cap) {
        size_t cap = s->out_cap ? s->out_cap : 65536;
        while (cap < s->out_size + len) cap *= 2;
        s->out = prw_realloc(s->out, cap);
        s->out_cap = cap;
    }
    memcpy(s->out + s->out_size, buf, len);
    s->out_size += len;
}

static void on_flush(png_structp png) { (void)png; }

static bool write_inner(png_state *s, png_structp png, png_infop info, int w, int h, int channels, int depth,
                        const uint8_t *pixels, const prw_png_chunk *chunks, int nchunks, prw_error *e)
{
    if (setjmp(png_jmpbuf(png))) return prw_fail(e, "%s: png write: %s", s->path, s->msg);
    static const int types[4] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB,
                                 PNG_COLOR_TYPE_RGB_ALPHA};
    png_set_write_fn(png, s, on_write, on_flush);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, depth, types[channels - 1], PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (nchunks > 0) {
        /* written as unknown chunks right after IHDR (so before PLTE and IDAT); "always" so libpng
         * also writes unsafe-to-copy ones such as cICP */
        png_unknown_chunk uc[8];
        for (int i = 0; i < nchunks; i++) {
            memset(&uc[i], 0, sizeof uc[i]);
            memcpy(uc[i].name, chunks[i].name, 4);
            uc[i].data = (png_byte *)chunks[i].data;
            uc[i].size = chunks[i].size;
            uc[i].location = PNG_HAVE_IHDR;
            png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_ALWAYS, (png_const_bytep)chunks[i].name, 1);
        }
        png_set_unknown_chunks(png, info, uc, nchunks);
        for (int i = 0; i < nchunks; i++) png_set_unknown_chunk_location(png, info, i, PNG_HAVE_IHDR);
    }
    png_write_info(png, info);
    if (depth == 16) png_set_swap(png); /* rows are host-order uint16 (little endian here); PNG is big endian */
    size_t row = (size_t)w * (size_t)channels * (size_t)(depth / 8);
    for (int y = 0; y < h; y++) png_write_row(png, pixels + (size_t)y * row);
    png_write_end(png, NULL);
    return true;
}

static bool write_any(const char *path, int width, int height, int channels, int depth, const void *pixels,
                      const prw_png_chunk *chunks, int nchunks, prw_error *e)
{
    if (channels < 1 || channels > 4) return prw_fail(e, "%s: png write: %d channels (need 1..4)", path, channels);
    if (!pixels) return prw_fail(e, "%s: png write: no pixels", path);
    if (nchunks < 0 || nchunks > 8 || (nchunks > 0 && !chunks))
        return prw_fail(e, "%s: png write: %d extra chunks (at most 8)", path, nchunks);
    for (int i = 0; i < nchunks; i++)
        for (int k = 0; k < 4; k++) {
            char c = chunks[i].name[k];
            if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) || !(chunks[i].name[0] >= 'a'))
                return prw_fail(e, "%s: png write: chunk %d: name is not an ancillary chunk name", path, i);
        }
    if (!prw_image_size_ok(width, height, path, e)) return false;
    png_state s = {.path = path};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &s, on_error, on_warning);
    if (!png) return prw_fail(e, "%s: png write: cannot create libpng write struct", path);
    png_infop info = png_create_info_struct(png);
    bool ok = info ? write_inner(&s, png, info, width, height, channels, depth, pixels, chunks, nchunks, e)
                   : prw_fail(e, "%s: png write: cannot create libpng info struct", path);
    png_destroy_write_struct(&png, info ? &info : NULL);
    if (ok) ok = prw_write_file_atomic(path, s.out, s.out_size, e);
    free(s.out);
    return ok;
}

bool prw_png_write16(const char *path, int width, int height, int channels, const uint16_t *pixels,
                     const prw_png_chunk *chunks, int nchunks, prw_error *e)
{
    return write_any(path, width, height, channels, 16, pixels, chunks, nchunks, e);
}

bool prw_png_write8(const char *path, int width, int height, int channels, const uint8_t *pixels, prw_error *e)
{
    return write_any(path, width, height, channels, 8, pixels, NULL, 0, e);
}

static bool read_inner(png_state *s, png_structp png, png_infop info, int *width, int *height, prw_error *e)
{
    if (setjmp(png_jmpbuf(png))) return prw_fail(e, "%s: png read: %s", s->path, s->msg);
    png_set_read_fn(png, s, on_read);
    png_read_info(png, info);
    png_uint_32 w = 0, h = 0;
    int depth = 0, ctype = 0, interlace = 0;
    png_get_IHDR(png, info, &w, &h, &depth, &ctype, &interlace, NULL, NULL);
    if (!prw_image_size_ok(w, h, s->path, e)) return false;
    /* Limits before allocation: the image data (>= w*h*channels*depth bits, deflated at most 1032:1)
     * must fit in the bytes left, and the RGBA8 result and its row table in the memory budget. */
    int channels = png_get_channels(png, info);
    double raw = (double)w * (double)h * (double)(channels > 0 ? channels : 1) * (double)depth / 8.0;
    double need = floor(raw / 1100.0);
    if (need > (double)(s->size - s->pos))
        return prw_fail(e, "%s: png read: IHDR: %ux%u pixels need at least %.0f bytes of image data, %zu bytes are left",
                        s->path, (unsigned)w, (unsigned)h, need, s->size - s->pos);
    char what[64];
    snprintf(what, sizeof what, "reading the %ux%u image", (unsigned)w, (unsigned)h);
    if (!prw_mem_check(prw_add_sat(prw_mul_sat((uint64_t)w * h, 4), prw_mul_sat(h, sizeof(png_bytep))), s->path, what, e))
        return false;
    bool trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    png_set_expand(png); /* palette -> RGB, grey < 8 bit -> 8 bit, tRNS -> alpha */
    png_set_scale_16(png);
    if (!(ctype & PNG_COLOR_MASK_COLOR)) png_set_gray_to_rgb(png);
    if (!(ctype & PNG_COLOR_MASK_ALPHA) && !trns) png_set_add_alpha(png, 0xFF, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    size_t rowbytes = png_get_rowbytes(png, info);
    if (rowbytes != (size_t)w * 4)
        return prw_fail(e, "%s: png read: unexpected row size %zu after conversion to RGBA8 (width %u)", s->path,
                        rowbytes, (unsigned)w);
    s->pixels = prw_malloc((size_t)w * (size_t)h * 4);
    s->rows = prw_malloc((size_t)h * sizeof(png_bytep));
    for (png_uint_32 y = 0; y < h; y++) s->rows[y] = s->pixels + (size_t)y * rowbytes;
    png_read_image(png, s->rows);
    png_read_end(png, NULL);
    *width = (int)w;
    *height = (int)h;
    return true;
}

bool prw_png_read8(const char *path, int *width, int *height, uint8_t **pixels, prw_error *e)
{
    *pixels = NULL;
    *width = *height = 0;
    char *data = NULL;
    size_t size = 0;
    if (!prw_read_file_bounded(path, 0, 1, "a PNG file", &data, &size, e)) return false;
    png_state s = {.path = path, .data = (const uint8_t *)data, .size = size};
    bool ok;
    if (size < 8 || png_sig_cmp((png_const_bytep)data, 0, 8) != 0) {
        ok = prw_fail(e, "%s: png read: not a PNG file (bad signature)", path);
    } else {
        png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &s, on_error, on_warning);
        png_infop info = png ? png_create_info_struct(png) : NULL;
        ok = info ? read_inner(&s, png, info, width, height, e)
                  : prw_fail(e, "%s: png read: cannot create libpng read struct", path);
        png_destroy_read_struct(png ? &png : NULL, info ? &info : NULL, NULL);
    }
    free(s.rows);
    free(data);
    if (ok) {
        *pixels = s.pixels;
    } else {
        free(s.pixels);
        *width = *height = 0;
    }
    return ok;
}
