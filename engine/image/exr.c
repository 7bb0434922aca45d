/* exr.c — EXR read/write through the OpenEXR 3.1 C API (openexr.h).
 *
 * All I/O goes through our own callbacks (exr_io): reads come from a file descriptor (pread) or a
 * memory block, writes go to a growable memory buffer that is then stored with
 * prw_write_file_atomic ("<path>.tmp-<pid>" + rename), so no partial file is ever left at path.
 * The library's error messages are captured by an error handler into exr_io.msg instead of being
 * printed to stderr.
 */
#define _POSIX_C_SOURCE 200809L
#include "prw_image.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct exr_io {
    const char *name; /* path or caller-given name, for messages */
    /* read source: memory block or file descriptor */
    bool is_mem;
    const uint8_t *mem;
    int fd;
    int64_t size;
    /* write sink */
    uint8_t *out;
    size_t out_size, out_cap;
    /* first library message since the last io_clear() */
    char msg[512];
} exr_io;

static void io_clear(exr_io *io) { io->msg[0] = '\0'; }

static void io_error_cb(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (!ctxt || exr_get_user_data(ctxt, &ud) != EXR_ERR_SUCCESS || !ud) return;
    exr_io *io = ud;
    if (io->msg[0]) return; /* keep the root cause */
    snprintf(io->msg, sizeof io->msg, "%s", msg ? msg : exr_get_default_error_message(code));
    /* one clean line: the library quotes names read from the file, control bytes included */
    for (char *p = io->msg; *p; p++)
        if ((unsigned char)*p < 0x20 || *p == 0x7f) *p = '?';
}

static int64_t io_read(exr_const_context_t ctxt, void *ud, void *buffer, uint64_t sz, uint64_t offset,
                       exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    if (io->is_mem) {
        if (offset >= (uint64_t)io->size) return 0;
        uint64_t n = (uint64_t)io->size - offset;
        if (n > sz) n = sz;
        memcpy(buffer, io->mem + offset, (size_t)n);
        return (int64_t)n;
    }
    uint64_t done = 0;
    while (done < sz) {
        if (offset + done > (uint64_t)INT64_MAX) break;
        ssize_t r = pread(io->fd, (uint8_t *)buffer + done, (size_t)(sz - done), (off_t)(offset + done));
        if (r < 0) {
            if (errno == EINTR) continue;
            if (error_cb) error_cb(ctxt, EXR_ERR_READ_IO, "read failed: %s", strerror(errno));
            return -1;
        }
        if (r == 0) break;
        done += (uint64_t)r;
    }
    return (int64_t)done;
}

static int64_t io_size(exr_const_context_t ctxt, void *ud)
{
    (void)ctxt;
    return ((exr_io *)ud)->size;
}

static int64_t io_write(exr_const_context_t ctxt, void *ud, const void *buffer, uint64_t sz, uint64_t offset,
                        exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = ud;
    uint64_t end = offset + sz;
    if (end < offset || end > (uint64_t)1 << 40) {
        if (error_cb) error_cb(ctxt, EXR_ERR_WRITE_IO, "write beyond 1 TiB requested");
        return -1;
    }
    if (end > io->out_cap) {
        size_t cap = io->out_cap ? io->out_cap : 65536;
        while (cap < end) cap *= 2;
        io->out = prw_realloc(io->out, cap);
        io->out_cap = cap;
    }
    if (offset > io->out_size) memset(io->out + io->out_size, 0, (size_t)(offset - io->out_size));
    memcpy(io->out + offset, buffer, (size_t)sz);
    if (end > io->out_size) io->out_size = (size_t)end;
    return (int64_t)sz;
}

/* "<name>: <place>: <library message> (<EXR_ERR_...>)" */
static bool exr_fail(exr_io *io, prw_error *e, const char *place, exr_result_t rv)
{
    const char *why = io->msg[0] ? io->msg : exr_get_default_error_message(rv);
    return prw_fail(e, "%s: %s: %s (%s)", io->name, place, why, exr_get_error_code_as_string(rv));
}

#define EXR_TRY(call, place)                                                                 \
    do {                                                                                     \
        io_clear(io);                                                                        \
        exr_result_t rv_ = (call);                                                           \
        if (rv_ != EXR_ERR_SUCCESS) return exr_fail(io, e, (place), rv_);                   \
    } while (0)

static exr_context_initializer_t io_init(exr_io *io)
{
    exr_context_initializer_t ci = EXR_DEFAULT_CONTEXT_INITIALIZER;
    ci.error_handler_fn = io_error_cb;
    ci.user_data = io;
    ci.read_fn = io_read;
    ci.size_fn = io_size;
    ci.write_fn = io_write;
    ci.max_image_width = (int)PRW_IMAGE_MAX_PIXELS;
    ci.max_image_height = (int)PRW_IMAGE_MAX_PIXELS;
    /* A corrupt offset table is an error, not something to guess around. */
    ci.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    return ci;
}

/* ---------------------------------------------------------------- colour ------------------------------------------------------ */

typedef double mat3[3][3];

static void mat3_mul(const mat3 a, const mat3 b, mat3 r)
{
    mat3 t;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) t[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
    memcpy(r, t, sizeof t);
}

static bool mat3_inv(const mat3 m, mat3 r)
{
    double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
    double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
    double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
    if (!isfinite(det) || fabs(det) < 1e-12) return false;
    double d = 1.0 / det;
    r[0][0] = c00 * d;
    r[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * d;
    r[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * d;
    r[1][0] = c01 * d;
    r[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * d;
    r[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * d;
    r[2][0] = c02 * d;
    r[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * d;
    r[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * d;
    return true;
}

static void xy_to_XYZ(double x, double y, double out[3])
{
    out[0] = x / y;
    out[1] = 1.0;
    out[2] = (1.0 - x - y) / y;
}

/* RGB -> XYZ for the given chromaticities (white maps to Y = 1). */
static bool rgb_to_xyz(const exr_attr_chromaticities_t *c, mat3 m)
{
    double xy[4][2] = {{c->red_x, c->red_y}, {c->green_x, c->green_y}, {c->blue_x, c->blue_y}, {c->white_x, c->white_y}};
    /* primaries may lie outside the spectral locus (ACES AP0 blue has y < 0), the white may not */
    for (int i = 0; i < 4; i++)
        if (!isfinite(xy[i][0]) || !isfinite(xy[i][1]) || fabs(xy[i][1]) < 1e-6) return false;
    if (xy[3][1] <= 0) return false;
    mat3 p, pi;
    for (int k = 0; k < 3; k++) {
        double v[3];
        xy_to_XYZ(xy[k][0], xy[k][1], v);
        for (int i = 0; i < 3; i++) p[i][k] = v[i];
    }
    if (!mat3_inv(p, pi)) return false;
    double w[3], s[3];
    xy_to_XYZ(xy[3][0], xy[3][1], w);
    for (int i = 0; i < 3; i++) s[i] = pi[i][0] * w[0] + pi[i][1] * w[1] + pi[i][2] * w[2];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) m[i][k] = p[i][k] * s[k];
    return true;
}

static const exr_attr_chromaticities_t rec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};

static bool chroma_is_rec709(const exr_attr_chromaticities_t *c)
{
    const float *a = &c->red_x, *b = &rec709.red_x;
    for (int i = 0; i < 8; i++)
        if (!(fabsf(a[i] - b[i]) <= 1e-4f)) return false;
    return true;
}

/* src RGB -> Rec.709/D65 RGB: XYZ(src) -> Bradford adaptation src white -> D65 -> Rec.709. */
static bool chroma_to_rec709(const exr_attr_chromaticities_t *c, mat3 out)
{
    static const mat3 bradford = {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};
    mat3 src, dst, dst_inv, bi, adapt;
    if (!rgb_to_xyz(c, src) || !rgb_to_xyz(&rec709, dst) || !mat3_inv(dst, dst_inv) || !mat3_inv(bradford, bi))
        return false;
    double ws[3], wd[3], cs[3], cd[3];
    xy_to_XYZ(c->white_x, c->white_y, ws);
    xy_to_XYZ(rec709.white_x, rec709.white_y, wd);
    for (int i = 0; i < 3; i++) {
        cs[i] = bradford[i][0] * ws[0] + bradford[i][1] * ws[1] + bradford[i][2] * ws[2];
        cd[i] = bradford[i][0] * wd[0] + bradford[i][1] * wd[1] + bradford[i][2] * wd[2];
        if (!(fabs(cs[i]) > 1e-9)) return false;
    }
    mat3 scale = {{cd[0] / cs[0], 0, 0}, {0, cd[1] / cs[1], 0}, {0, 0, cd[2] / cs[2]}};
    mat3_mul(scale, bradford, adapt);
    mat3_mul(bi, adapt, adapt);
    mat3_mul(adapt, src, out);
    mat3_mul(dst_inv, out, out);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!isfinite(out[i][j])) return false;
    return true;
}

/* ---------------------------------------------------------------- read -------------------------------------------------------- */

typedef struct exr_reader {
    exr_io *io;
    exr_context_t ctx;
    exr_attr_box2i_t dw;
    bool grey; /* Y only: decode Y into R, copy to G, B afterwards */
    exr_decode_pipeline_t dec;
    bool dec_used;
    prw_image *out;
} exr_reader;

static int output_component(const char *name, bool grey)
{
    if (!name) return -1;
    if (strcmp(name, "A") == 0) return 3;
    if (grey) return strcmp(name, "Y") == 0 ? 0 : -1;
    if (strcmp(name, "R") == 0) return 0;
    if (strcmp(name, "G") == 0) return 1;
    if (strcmp(name, "B") == 0) return 2;
    return -1;
}

static float half_to_float(uint16_t h)
{
    uint32_t sign = (uint32_t)(h & 0x8000) << 16, exp = (h >> 10) & 0x1f, mant = h & 0x3ff, bits;
    if (exp == 0x1f) {
        bits = sign | 0x7f800000u | (mant << 13);
    } else if (exp != 0) {
        bits = sign | ((exp + 112) << 23) | (mant << 13);
    } else if (mant == 0) {
        bits = sign;
    } else { /* denormal: renormalise */
        int e = -1;
        do {
            mant <<= 1;
            e++;
        } while (!(mant & 0x400));
        bits = sign | ((uint32_t)(112 - e) << 23) | ((mant & 0x3ff) << 13);
    }
    float f;
    memcpy(&f, &bits, 4);
    return f;
}

static float load_sample(const uint8_t *p, int type)
{
    if (type == EXR_PIXEL_HALF) return half_to_float((uint16_t)(p[0] | (p[1] << 8)));
    uint32_t u = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) | ((uint32_t)p[3] << 24);
    if (type == EXR_PIXEL_UINT) return (float)u;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* Decodes one chunk whose top-left pixel is (x0, y0) in output coordinates.
 *
 * The library only reads and decompresses (unpack_and_convert_fn = NULL, as openexr_decode.h
 * allows); we unpack the decompressed buffer ourselves — per line, per channel in file order,
 * `width` little-endian samples — because the specialised interleaving unpackers of OpenEXR 3.1
 * put 4-channel half data in the wrong order (seen with 3.1.5: A,B,G,R land in R,G,B,A). */
static bool decode_chunk(exr_reader *r, const exr_chunk_info_t *ci, int64_t x0, int64_t y0, prw_error *e)
{
    exr_io *io = r->io;
    prw_image *out = r->out;
    if (ci->width <= 0 || ci->height <= 0 || x0 < 0 || y0 < 0 || x0 + ci->width > out->width ||
        y0 + ci->height > out->height)
        return prw_fail(e, "%s: chunk %d: region %dx%d at (%lld, %lld) lies outside the %dx%d data window", io->name,
                        ci->idx, ci->width, ci->height, (long long)x0, (long long)y0, out->width, out->height);
    if (r->dec_used) {
        EXR_TRY(exr_decoding_update(r->ctx, 0, ci, &r->dec), "exr_decoding_update");
    } else {
        r->dec_used = true;
        EXR_TRY(exr_decoding_initialize(r->ctx, 0, ci, &r->dec), "exr_decoding_initialize");
    }
    uint64_t line_bytes = 0;
    for (int c = 0; c < r->dec.channel_count; c++) {
        exr_coding_channel_info_t *ch = &r->dec.channels[c];
        ch->decode_to_ptr = NULL; /* nothing for the library to unpack */
        if (ch->width != ci->width || ch->height != ci->height)
            return prw_fail(e, "%s: chunk %d: channel %s has %dx%d samples for a %dx%d chunk", io->name, ci->idx,
                            ch->channel_name ? ch->channel_name : "?", ch->width, ch->height, ci->width, ci->height);
        int bpe = ch->data_type == EXR_PIXEL_HALF ? 2 : 4;
        if (ch->bytes_per_element != bpe || ch->data_type >= EXR_PIXEL_LAST_TYPE)
            return prw_fail(e, "%s: chunk %d: channel %s has an invalid pixel type", io->name, ci->idx,
                            ch->channel_name ? ch->channel_name : "?");
        line_bytes += (uint64_t)ci->width * (uint64_t)bpe;
    }
    EXR_TRY(exr_decoding_choose_default_routines(r->ctx, 0, &r->dec), "exr_decoding_choose_default_routines");
    r->dec.unpack_and_convert_fn = NULL;
    char place[64];
    snprintf(place, sizeof place, "chunk %d (y %lld)", ci->idx, (long long)(y0 + r->dw.min.y));
    EXR_TRY(exr_decoding_run(r->ctx, 0, &r->dec), place);

    uint64_t need = line_bytes * (uint64_t)ci->height;
    const uint8_t *src = r->dec.unpacked_buffer;
    if (need == 0) return true;
    if (!src || ci->unpacked_size < need)
        return prw_fail(e, "%s: %s: decoded %llu bytes, expected %llu", io->name, place,
                        (unsigned long long)(src ? ci->unpacked_size : 0), (unsigned long long)need);
    for (int y = 0; y < ci->height; y++) {
        float *row = out->rgba + ((size_t)(y0 + y) * (size_t)out->width + (size_t)x0) * 4;
        for (int c = 0; c < r->dec.channel_count; c++) {
            const exr_coding_channel_info_t *ch = &r->dec.channels[c];
            int bpe = ch->bytes_per_element, comp = output_component(ch->channel_name, r->grey);
            if (comp >= 0)
                for (int x = 0; x < ci->width; x++) row[(size_t)x * 4 + (size_t)comp] = load_sample(src + (size_t)x * bpe, ch->data_type);
            src += (size_t)ci->width * (size_t)bpe;
        }
    }
    return true;
}

static bool read_scanlines(exr_reader *r, prw_error *e)
{
    exr_io *io = r->io;
    int32_t lines = 0;
    EXR_TRY(exr_get_scanlines_per_chunk(r->ctx, 0, &lines), "exr_get_scanlines_per_chunk");
    if (lines <= 0) return prw_fail(e, "%s: header: invalid scanlines per chunk %d", io->name, lines);
    for (int64_t y = r->dw.min.y; y <= r->dw.max.y; y += lines) {
        exr_chunk_info_t ci;
        char place[64];
        snprintf(place, sizeof place, "chunk table (y %lld)", (long long)y);
        EXR_TRY(exr_read_scanline_chunk_info(r->ctx, 0, (int)y, &ci), place);
        if (ci.start_y != y)
            return prw_fail(e, "%s: chunk %d: starts at y %d, expected %lld", io->name, ci.idx, ci.start_y, (long long)y);
        if (!decode_chunk(r, &ci, 0, y - r->dw.min.y, e)) return false;
    }
    return true;
}

static bool read_tiles(exr_reader *r, prw_error *e)
{
    exr_io *io = r->io;
    int32_t tw = 0, th = 0;
    EXR_TRY(exr_get_tile_sizes(r->ctx, 0, 0, 0, &tw, &th), "exr_get_tile_sizes");
    if (tw <= 0 || th <= 0) return prw_fail(e, "%s: header: invalid tile size %dx%d", io->name, tw, th);
    int64_t nx = (r->out->width + (int64_t)tw - 1) / tw, ny = (r->out->height + (int64_t)th - 1) / th;
    for (int64_t ty = 0; ty < ny; ty++)
        for (int64_t tx = 0; tx < nx; tx++) {
            exr_chunk_info_t ci;
            char place[64];
            snprintf(place, sizeof place, "tile (%lld, %lld)", (long long)tx, (long long)ty);
            EXR_TRY(exr_read_tile_chunk_info(r->ctx, 0, (int)tx, (int)ty, 0, 0, &ci), place);
            if (!decode_chunk(r, &ci, tx * tw, ty * th, e)) return false;
        }
    return true;
}

static bool check_finite(const exr_reader *r, prw_error *e)
{
    static const char *names[4] = {"R", "G", "B", "A"};
    const prw_image *o = r->out;
    for (int y = 0; y < o->height; y++)
        for (int x = 0; x < o->width; x++) {
            const float *p = o->rgba + ((size_t)y * (size_t)o->width + (size_t)x) * 4;
            for (int c = 0; c < 4; c++) {
                if (r->grey && (c == 1 || c == 2)) continue;
                if (!isfinite(p[c]))
                    return prw_fail(e, "%s: pixel (%d, %d): channel %s is %s", r->io->name, x, y,
                                    r->grey && c == 0 ? "Y" : names[c], isnan(p[c]) ? "NaN" : "Inf");
            }
        }
    return true;
}

/* Largest ratio uncompressed / compressed each compression can reach, so that the data of a chunk
 * takes at least uncompressed / ratio bytes (rounded down to be safe): NONE stores the bytes;
 * RLE codes at most 127 equal bytes in 2; deflate (ZIP, ZIPS) at most 258 bytes in 2 bits (1032:1);
 * PXR24 deflates 24-bit floats (1376:1 of the float data); B44/B44A keep >= 3 of each 32 bytes;
 * PIZ's Huffman codes runs of <= 255 + 1 values in >= 10 bits (~410:1).  DWAA/DWAB combine DCT,
 * RLE and deflate: a generous bound.  The bounds are generous by design: they only have to catch
 * headers that claim far more pixels than the file can hold. */
static double max_ratio(exr_compression_t c)
{
    switch (c) {
    case EXR_COMPRESSION_NONE: return 1;
    case EXR_COMPRESSION_RLE: return 64;
    case EXR_COMPRESSION_ZIPS:
    case EXR_COMPRESSION_ZIP: return 1100;
    case EXR_COMPRESSION_PXR24: return 1500;
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A: return 16;
    case EXR_COMPRESSION_PIZ: return 2048;
    default: return 65536;
    }
}

/* Limits before allocation: the data window the header claims must be backed by the file's bytes,
 * and what the reader will allocate must fit the memory budget.  A file holds the whole offset
 * table (8 bytes per chunk of every level) and, per chunk of level 0, a chunk header (>= 8 bytes:
 * y + size for scanlines; tiles have more) and its data (>= the uncompressed bytes / max_ratio). */
static bool check_limits(exr_reader *r, int64_t w, int64_t h, exr_storage_t storage, const exr_attr_chlist_t *cl,
                         const prw_exr_read_opts *opts, prw_error *e)
{
    exr_io *io = r->io;
    exr_compression_t comp = EXR_COMPRESSION_NONE;
    int32_t chunks_all = 0;
    EXR_TRY(exr_get_compression(r->ctx, 0, &comp), "exr_get_compression");
    EXR_TRY(exr_get_chunk_count(r->ctx, 0, &chunks_all), "exr_get_chunk_count");
    double bpp = 0; /* stored bytes per pixel, all channels */
    for (int i = 0; cl && i < cl->num_channels; i++) {
        const exr_attr_chlist_entry_t *ch = &cl->entries[i];
        double size = ch->pixel_type == EXR_PIXEL_HALF ? 2 : 4;
        double samp = (double)(ch->x_sampling > 0 ? ch->x_sampling : 1) * (ch->y_sampling > 0 ? ch->y_sampling : 1);
        bpp += size / samp;
    }
    int64_t chunks0 = 0, chunk_pixels = 0;
    if (storage == EXR_STORAGE_TILED) {
        int32_t tw = 0, th = 0;
        EXR_TRY(exr_get_tile_sizes(r->ctx, 0, 0, 0, &tw, &th), "exr_get_tile_sizes");
        if (tw <= 0 || th <= 0) return prw_fail(e, "%s: header: invalid tile size %dx%d", io->name, tw, th);
        chunks0 = ((w + tw - 1) / tw) * ((h + th - 1) / th);
        chunk_pixels = (int64_t)PRW_MIN((int64_t)tw, w) * PRW_MIN((int64_t)th, h);
    } else {
        int32_t lines = 0;
        EXR_TRY(exr_get_scanlines_per_chunk(r->ctx, 0, &lines), "exr_get_scanlines_per_chunk");
        if (lines <= 0) return prw_fail(e, "%s: header: invalid scanlines per chunk %d", io->name, lines);
        chunks0 = (h + lines - 1) / lines;
        chunk_pixels = w * PRW_MIN((int64_t)lines, h);
    }
    double need = 8.0 * PRW_MAX((double)chunks_all, (double)chunks0) + 8.0 * (double)chunks0 +
                  floor((double)w * (double)h * bpp / max_ratio(comp));
    if (chunks_all < 0 || need > (double)io->size)
    {
        static const char *const names[] = {"none", "RLE", "ZIPS", "ZIP", "PIZ", "PXR24", "B44", "B44A", "DWAA", "DWAB"};
        return prw_fail(e, "%s: header: data window %lldx%lld (%d chunks, %s compression) needs at least %.0f bytes, "
                           "the file has %lld",
                        io->name, (long long)w, (long long)h, chunks_all,
                        (unsigned)comp < PRW_ARRAY_LEN(names) ? names[comp] : "unknown", need, (long long)io->size);
    }
    /* the image (RGBA float), one chunk's packed and unpacked buffers, what the caller adds per pixel */
    uint64_t px = (uint64_t)w * (uint64_t)h;
    uint64_t per_px = 16 + (opts ? opts->extra_bytes_per_pixel : 0);
    uint64_t chunk = (uint64_t)((double)chunk_pixels * bpp) + 64;
    uint64_t bytes = prw_add_sat(prw_mul_sat(px, per_px), prw_mul_sat(chunk, 3));
    char what[96];
    snprintf(what, sizeof what, "reading the %lldx%lld image", (long long)w, (long long)h);
    return prw_mem_check(bytes, io->name, what, e);
}

static bool read_image(exr_reader *r, const prw_exr_read_opts *opts, prw_error *e)
{
    exr_io *io = r->io;
    int parts = 0;
    EXR_TRY(exr_get_count(r->ctx, &parts), "exr_get_count");
    if (parts < 1) return prw_fail(e, "%s: header: no parts", io->name);
    exr_storage_t storage;
    EXR_TRY(exr_get_storage(r->ctx, 0, &storage), "exr_get_storage");
    if (storage != EXR_STORAGE_SCANLINE && storage != EXR_STORAGE_TILED)
        return prw_fail(e, "%s: header: deep images are not supported", io->name);
    EXR_TRY(exr_get_data_window(r->ctx, 0, &r->dw), "exr_get_data_window");
    int64_t w = (int64_t)r->dw.max.x - r->dw.min.x + 1, h = (int64_t)r->dw.max.y - r->dw.min.y + 1;
    if (!prw_image_size_ok(w, h, io->name, e)) return false;
    if (opts && opts->max_pixels > 0 && w * h > opts->max_pixels)
        return prw_fail(e, "%s: image size: %lldx%lld exceeds the caller's limit of %lld pixels", io->name,
                        (long long)w, (long long)h, (long long)opts->max_pixels);

    const exr_attr_chlist_t *cl = NULL;
    EXR_TRY(exr_get_channels(r->ctx, 0, &cl), "exr_get_channels");
    bool has[7] = {false};
    static const char *wanted[7] = {"R", "G", "B", "A", "Y", "RY", "BY"};
    char found[256] = "";
    for (int i = 0; cl && i < cl->num_channels; i++) {
        const exr_attr_chlist_entry_t *ch = &cl->entries[i];
        const char *n = ch->name.str ? ch->name.str : "";
        char shown[40]; /* the name as quoted in messages: printable ASCII, the rest '?' */
        size_t k = 0;
        for (; n[k] && k + 1 < sizeof shown; k++) shown[k] = (n[k] >= 0x20 && n[k] < 0x7f) ? n[k] : '?';
        shown[k] = '\0';
        size_t len = strlen(found);
        if (len + 2 < sizeof found) snprintf(found + len, sizeof found - len, "%s%s", len ? "," : "", shown);
        for (int k = 0; k < 7; k++) {
            if (strcmp(n, wanted[k]) != 0) continue;
            has[k] = true;
            if (ch->x_sampling != 1 || ch->y_sampling != 1)
                return prw_fail(e, "%s: channel %s: subsampled channels (%dx%d) are not supported", io->name, shown,
                                ch->x_sampling, ch->y_sampling);
        }
    }
    if (has[0] && has[1] && has[2]) r->grey = false;
    else if (has[4] && !has[5] && !has[6]) r->grey = true;
    else if (has[4])
        return prw_fail(e, "%s: channels: luminance/chroma (Y, RY, BY) images are not supported", io->name);
    else
        return prw_fail(e, "%s: channels: need R, G, B (or Y alone); found: %s", io->name, found[0] ? found : "none");

    if (!check_limits(r, w, h, storage, cl, opts, e)) return false;

    exr_attr_chromaticities_t chroma = rec709;
    io_clear(io);
    exr_result_t rv = exr_attr_get_chromaticities(r->ctx, 0, "chromaticities", &chroma);
    if (rv == EXR_ERR_NO_ATTR_BY_NAME) chroma = rec709;
    else if (rv != EXR_ERR_SUCCESS) return exr_fail(io, e, "chromaticities attribute", rv);
    mat3 m;
    bool convert = !r->grey && !chroma_is_rec709(&chroma);
    if (convert && !chroma_to_rec709(&chroma, m))
        return prw_fail(e, "%s: chromaticities attribute: degenerate primaries or white point", io->name);

    if (!prw_image_alloc(r->out, (int)w, (int)h, e)) return prw_fail_wrap(e, "%s", io->name);
    size_t n = (size_t)w * (size_t)h;
    for (size_t i = 0; i < n; i++) r->out->rgba[i * 4 + 3] = 1.0f;

    if (!(storage == EXR_STORAGE_TILED ? read_tiles(r, e) : read_scanlines(r, e))) return false;
    if (opts && opts->reject_nonfinite && !check_finite(r, e)) return false;

    float *p = r->out->rgba;
    if (r->grey) {
        for (size_t i = 0; i < n; i++) p[i * 4 + 1] = p[i * 4 + 2] = p[i * 4];
    } else if (convert) {
        for (size_t i = 0; i < n; i++) {
            double c[3] = {p[i * 4], p[i * 4 + 1], p[i * 4 + 2]};
            for (int k = 0; k < 3; k++) p[i * 4 + k] = (float)(m[k][0] * c[0] + m[k][1] * c[1] + m[k][2] * c[2]);
        }
    }
    return true;
}

/* Shared by the path and memory readers: io is set up, nothing else is. */
static bool read_io(exr_io *io, const prw_exr_read_opts *opts, prw_image *out, prw_error *e)
{
    out->width = out->height = 0;
    out->rgba = NULL;
    exr_reader r = {.io = io, .out = out};
    exr_context_initializer_t ci = io_init(io);
    io_clear(io);
    exr_result_t rv = exr_start_read(&r.ctx, io->name, &ci);
    if (rv != EXR_ERR_SUCCESS) {
        exr_fail(io, e, "exr_start_read", rv);
        exr_finish(&r.ctx);
        return false;
    }
    bool ok = read_image(&r, opts, e);
    if (r.dec_used) exr_decoding_destroy(r.ctx, &r.dec);
    exr_finish(&r.ctx);
    if (!ok) prw_image_free(out);
    return ok;
}

static bool open_file(exr_io *io, const char *path, prw_error *e)
{
    io->name = path;
    io->fd = open(path, O_RDONLY | O_CLOEXEC);
    if (io->fd < 0) return prw_fail(e, "%s: open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(io->fd, &st) != 0) {
        int err = errno;
        close(io->fd);
        return prw_fail(e, "%s: stat: %s", path, strerror(err));
    }
    if (!S_ISREG(st.st_mode)) {
        close(io->fd);
        return prw_fail(e, "%s: open: not a regular file", path);
    }
    io->size = (int64_t)st.st_size;
    return true;
}

bool prw_exr_read(const char *path, const prw_exr_read_opts *opts, prw_image *out, prw_error *e)
{
    exr_io io = {0};
    if (!open_file(&io, path, e)) {
        out->width = out->height = 0;
        out->rgba = NULL;
        return false;
    }
    bool ok = read_io(&io, opts, out, e);
    close(io.fd);
    return ok;
}

bool prw_exr_read_memory(const void *data, size_t size, const char *name, const prw_exr_read_opts *opts,
                         prw_image *out, prw_error *e)
{
    exr_io io = {.name = name ? name : "<memory>", .is_mem = true, .mem = data, .size = (int64_t)size, .fd = -1};
    if (!data) size = 0, io.size = 0;
    return read_io(&io, opts, out, e);
}

bool prw_exr_read_attr(const char *path, const char *key, char *value, size_t cap, prw_error *e)
{
    if (e) e->msg[0] = '\0';
    if (cap > 0) value[0] = '\0';
    exr_io io = {0};
    if (!open_file(&io, path, e)) return false;
    exr_io *io_p = &io;
    exr_context_t ctx = NULL;
    exr_context_initializer_t ci = io_init(io_p);
    bool ok = false;
    io_clear(io_p);
    exr_result_t rv = exr_start_read(&ctx, path, &ci);
    if (rv != EXR_ERR_SUCCESS) {
        exr_fail(io_p, e, "exr_start_read", rv);
    } else {
        int32_t len = 0;
        const char *s = NULL;
        io_clear(io_p);
        rv = exr_attr_get_string(ctx, 0, key, &len, &s);
        if (rv == EXR_ERR_NO_ATTR_BY_NAME) {
            if (e) e->msg[0] = '\0';
        } else if (rv != EXR_ERR_SUCCESS) {
            char place[160];
            snprintf(place, sizeof place, "attribute \"%s\"", key);
            exr_fail(io_p, e, place, rv);
        } else if (len < 0 || (size_t)len + 1 > cap) {
            prw_fail(e, "%s: attribute \"%s\": value of %d bytes does not fit a %zu-byte buffer", path, key, len, cap);
        } else {
            if (len) memcpy(value, s, (size_t)len);
            value[len] = '\0';
            ok = true;
        }
    }
    exr_finish(&ctx);
    close(io.fd);
    return ok;
}

/* ---------------------------------------------------------------- write ------------------------------------------------------- */

static bool write_body(exr_io *io, exr_context_t ctx, const prw_image *img, const exr_attr_chromaticities_t *chroma,
                       const prw_kv *attrs, int attr_count, prw_error *e)
{
    int part = 0;
    EXR_TRY(exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part), "exr_add_part");
    EXR_TRY(exr_initialize_required_attr_simple(ctx, part, img->width, img->height, EXR_COMPRESSION_ZIP),
            "exr_initialize_required_attr_simple");
    static const char *chans[4] = {"A", "B", "G", "R"}; /* alphabetical, as stored */
    for (int c = 0; c < 4; c++)
        EXR_TRY(exr_add_channel(ctx, part, chans[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1),
                "exr_add_channel");
    EXR_TRY(exr_attr_set_chromaticities(ctx, part, "chromaticities", chroma), "exr_attr_set_chromaticities");
    for (int i = 0; i < attr_count; i++) {
        char place[160];
        snprintf(place, sizeof place, "attribute \"%s\"", attrs[i].key);
        EXR_TRY(exr_attr_set_string(ctx, part, attrs[i].key, attrs[i].value), place);
    }
    EXR_TRY(exr_write_header(ctx), "exr_write_header");

    int32_t lines = 0;
    EXR_TRY(exr_get_scanlines_per_chunk(ctx, part, &lines), "exr_get_scanlines_per_chunk");
    if (lines <= 0) return prw_fail(e, "%s: write: invalid scanlines per chunk %d", io->name, lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool enc_used = false, ok = true;
    for (int y = 0; ok && y < img->height; y += lines) {
        exr_chunk_info_t ci;
        exr_result_t rv;
        const char *place = "exr_write_scanline_chunk_info";
        io_clear(io);
        rv = exr_write_scanline_chunk_info(ctx, part, y, &ci);
        if (rv == EXR_ERR_SUCCESS) {
            place = enc_used ? "exr_encoding_update" : "exr_encoding_initialize";
            rv = enc_used ? exr_encoding_update(ctx, part, &ci, &enc) : exr_encoding_initialize(ctx, part, &ci, &enc);
            enc_used = true;
        }
        if (rv == EXR_ERR_SUCCESS) {
            for (int c = 0; c < enc.channel_count; c++) {
                exr_coding_channel_info_t *ch = &enc.channels[c];
                int comp = output_component(ch->channel_name, false);
                ch->encode_from_ptr =
                    (const uint8_t *)(img->rgba + (size_t)y * (size_t)img->width * 4 + (comp < 0 ? 0 : comp));
                ch->user_pixel_stride = 4 * (int32_t)sizeof(float);
                ch->user_line_stride = img->width * 4 * (int32_t)sizeof(float);
                ch->user_data_type = EXR_PIXEL_FLOAT;
                ch->user_bytes_per_element = (int16_t)sizeof(float);
            }
            place = "exr_encoding_choose_default_routines";
            rv = exr_encoding_choose_default_routines(ctx, part, &enc);
        }
        if (rv == EXR_ERR_SUCCESS) {
            place = "exr_encoding_run";
            rv = exr_encoding_run(ctx, part, &enc);
        }
        if (rv != EXR_ERR_SUCCESS) ok = exr_fail(io, e, place, rv);
    }
    if (enc_used) exr_encoding_destroy(ctx, &enc);
    return ok;
}

static bool write_chroma(const char *path, const prw_image *img, const exr_attr_chromaticities_t *chroma,
                         const prw_kv *attrs, int attr_count, prw_error *e);

bool prw_exr_write(const char *path, const prw_image *img, const prw_kv *attrs, int attr_count, prw_error *e)
{
    return write_chroma(path, img, &rec709, attrs, attr_count, e);
}

bool prw_exr_write_chroma(const char *path, const prw_image *img, const float c[8], const prw_kv *attrs,
                          int attr_count, prw_error *e)
{
    exr_attr_chromaticities_t ch = {c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]};
    for (int i = 0; i < 8; i++)
        if (!(c[i] > 0.0f && c[i] < 1.0f)) return prw_fail(e, "%s: write: chromaticity %d = %g not in (0, 1)", path, i, c[i]);
    return write_chroma(path, img, &ch, attrs, attr_count, e);
}

bool prw_exr_read_chroma(const char *path, float c[8], prw_error *e)
{
    exr_io io = {0};
    if (!open_file(&io, path, e)) return false;
    exr_context_t ctx = NULL;
    exr_context_initializer_t ci = io_init(&io);
    bool ok = false;
    io_clear(&io);
    exr_result_t rv = exr_start_read(&ctx, path, &ci);
    if (rv != EXR_ERR_SUCCESS) {
        exr_fail(&io, e, "exr_start_read", rv);
    } else {
        exr_attr_chromaticities_t ch = rec709;
        io_clear(&io);
        rv = exr_attr_get_chromaticities(ctx, 0, "chromaticities", &ch);
        if (rv != EXR_ERR_SUCCESS && rv != EXR_ERR_NO_ATTR_BY_NAME) {
            exr_fail(&io, e, "chromaticities attribute", rv);
        } else {
            const float v[8] = {ch.red_x, ch.red_y, ch.green_x, ch.green_y, ch.blue_x, ch.blue_y, ch.white_x, ch.white_y};
            memcpy(c, v, sizeof v);
            ok = true;
        }
    }
    exr_finish(&ctx);
    close(io.fd);
    return ok;
}

static bool write_chroma(const char *path, const prw_image *img, const exr_attr_chromaticities_t *chroma,
                         const prw_kv *attrs, int attr_count, prw_error *e)
{
    if (!img || !img->rgba) return prw_fail(e, "%s: write: image has no pixels", path);
    if (!prw_image_size_ok(img->width, img->height, path, e)) return false;
    if (attr_count < 0 || (attr_count > 0 && !attrs)) return prw_fail(e, "%s: write: invalid attribute list", path);
    for (int i = 0; i < attr_count; i++) {
        if (!attrs[i].key || !attrs[i].key[0] || !attrs[i].value)
            return prw_fail(e, "%s: write: attribute %d has an empty key or a NULL value", path, i);
        if (strcmp(attrs[i].key, "chromaticities") == 0)
            return prw_fail(e, "%s: write: attribute \"chromaticities\" is reserved", path);
    }
    exr_io io = {.name = path, .fd = -1};
    exr_context_t ctx = NULL;
    exr_context_initializer_t ci = io_init(&io);
    io_clear(&io);
    exr_result_t rv = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &ci);
    bool ok = rv == EXR_ERR_SUCCESS ? write_body(&io, ctx, img, chroma, attr_count ? attrs : NULL, attr_count, e)
                                    : exr_fail(&io, e, "exr_start_write", rv);
    if (ctx) {
        if (ok) io_clear(&io);
        rv = exr_finish(&ctx);
        if (ok && rv != EXR_ERR_SUCCESS) ok = exr_fail(&io, e, "exr_finish", rv);
    }
    if (ok) ok = prw_write_file_atomic(path, io.out, io.out_size, e);
    free(io.out);
    return ok;
}
