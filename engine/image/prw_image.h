/* prw_image — CPU images and their files.
 *
 * Promises:
 *  - prw_image is linear RGBA float, row 0 at the top (pixel (i, j) covers [i,i+1)x[j,j+1), y down).
 *  - EXR through the OpenEXR C API (openexr.h): write is float32 RGBA, ZIP-compressed, with the
 *    Rec.709/D65 chromaticities attribute and any extra string attributes; it never leaves a
 *    partial file (written to a temporary name, then renamed).  Read accepts half/float/uint
 *    R,G,B[,A] (or Y) scanline or tiled files, converts other chromaticities to Rec.709, and rejects
 *    NaN/Inf pixels only when asked (prw_exr_read_opts.reject_nonfinite).
 *    Read details: the result is the data window (its origin may be negative; display window
 *    ignored); only part 0 and tile level (0,0) are read; A defaults to 1; Y alone gives grey
 *    (R=G=B=Y); Y+RY+BY, deep, and subsampled channels are rejected; other channels are ignored.
 *    Chromaticities: RGB -> XYZ (from the file's primaries and white) -> Bradford adaptation to
 *    D65 when the white differs -> Rec.709 RGB; files within 1e-4 of Rec.709/D65 are left as
 *    stored (bit-exact).  Y-only files are not converted.  DWAA/DWAB files cannot be read: the
 *    OpenEXR 3.1 C API does not implement them (EXR_ERR_FEATURE_NOT_IMPLEMENTED).
 *  - Limits before allocation (every reader): the size the header claims must be backed by the
 *    file's bytes (EXR: the offset table, a chunk header per chunk and the pixel data divided by the
 *    largest ratio its compression can reach; PNG: the pixel data at deflate's 1032:1), and what
 *    the reader allocates (plus prw_exr_read_opts.extra_bytes_per_pixel) must fit the memory
 *    budget (prw_mem_check); prw_image_alloc checks the budget too.  So a 670-byte file claiming
 *    16384x16384 pixels is refused from its header, before any pixel memory exists.
 *  - PNG 8-bit (libpng) write/read, 16-bit write with extra ancillary chunks before IDAT, atomic
 *    write as above.
 *  - Every failure is one line in prw_error: "<path>: <place>: <reason>".
 */
#ifndef PRW_IMAGE_H
#define PRW_IMAGE_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_image {
    int width, height;
    float *rgba; /* width*height*4 floats, owned */
} prw_image;

/* Largest image any reader or prw_image_alloc accepts: width*height <= 2^28 pixels (4 GiB of RGBA float). */
#define PRW_IMAGE_MAX_PIXELS ((int64_t)1 << 28)

/* Zero-filled width*height RGBA image; fails (img left empty) on a size <= 0 or above the limit. */
bool prw_image_alloc(prw_image *img, int width, int height, prw_error *e);
/* Frees the pixels and empties img; safe on an empty or already freed image. */
void prw_image_free(prw_image *img);
/* The size check used by prw_image_alloc and the readers; `who` prefixes the message (a path). */
bool prw_image_size_ok(int64_t width, int64_t height, const char *who, prw_error *e);

typedef struct prw_kv {
    const char *key;
    const char *value;
} prw_kv;

/* Extra string attributes (e.g. {"prw:spp","64"}) are stored as EXR string attributes. */
bool prw_exr_write(const char *path, const prw_image *img, const prw_kv *attrs, int attr_count, prw_error *e);
/* Same with other primaries: chroma = {red x, y, green x, y, blue x, y, white x, y} is stored as the
 * chromaticities attribute (the pixels are written as given, in those primaries). */
bool prw_exr_write_chroma(const char *path, const prw_image *img, const float chroma[8], const prw_kv *attrs,
                          int attr_count, prw_error *e);
/* The chromaticities attribute of part 0 (Rec.709/D65 when absent; returns false only on errors). */
bool prw_exr_read_chroma(const char *path, float chroma[8], prw_error *e);

typedef struct prw_exr_read_opts {
    bool reject_nonfinite; /* fail with the first NaN/Inf pixel's position */
    int64_t max_pixels;    /* reject larger data windows; 0 (default) means PRW_IMAGE_MAX_PIXELS */
    /* bytes the caller will allocate per pixel after reading (e.g. an environment map's sampling
     * tables): counted with the reader's own against the memory budget before anything is read */
    uint64_t extra_bytes_per_pixel;
} prw_exr_read_opts;

bool prw_exr_read(const char *path, const prw_exr_read_opts *opts, prw_image *out, prw_error *e);
/* Same reader on an in-memory file; `name` is used only in error messages.  opts may be NULL. */
bool prw_exr_read_memory(const void *data, size_t size, const char *name, const prw_exr_read_opts *opts,
                         prw_image *out, prw_error *e);
/* Reads one string attribute of part 0 into value (NUL-terminated, cap bytes).  Returns false
 * with e->msg empty ("") when the attribute is absent, false with a message on any error
 * (unreadable file, attribute not a string, value longer than cap-1). */
bool prw_exr_read_attr(const char *path, const char *key, char *value, size_t cap, prw_error *e);

/* 8-bit PNG; channels 1..4. */
bool prw_png_write8(const char *path, int width, int height, int channels, const uint8_t *pixels, prw_error *e);
/* An extra ancillary chunk written before IDAT (e.g. cICP, which Debian's libpng 1.6.39 does not
 * know: written as an unknown chunk). */
typedef struct prw_png_chunk {
    char name[5];        /* 4 letters + NUL; must start lower case (ancillary) */
    const uint8_t *data;
    size_t size;
} prw_png_chunk;
/* 16-bit PNG; channels 1..4; pixels host-order uint16; up to 8 extra chunks (may be NULL / 0). */
bool prw_png_write16(const char *path, int width, int height, int channels, const uint16_t *pixels,
                     const prw_png_chunk *chunks, int nchunks, prw_error *e);
/* Reads any PNG into 8-bit RGBA (caller frees *pixels). */
bool prw_png_read8(const char *path, int *width, int *height, uint8_t **pixels, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
