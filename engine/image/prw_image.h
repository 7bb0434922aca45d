/* prw_image — CPU images and their files.
 *
 * Promises:
 *  - prw_image is linear RGBA float, row 0 at the top (pixel (i, j) covers [i,i+1)x[j,j+1), y down).
 *  - EXR through the OpenEXR C API (openexr.h): write is float32 RGBA, ZIP-compressed, with the
 *    Rec.709/D65 chromaticities attribute and any extra string attributes; it never leaves a
 *    partial file (written to a temporary name, then renamed).  Read accepts half/float/uint
 *    R,G,B[,A] (or Y) scanline or tiled files, converts other chromaticities to Rec.709, and rejects
 *    NaN/Inf pixels only when asked (prw_exr_read_opts.reject_nonfinite).
 *  - PNG 8-bit (libpng) write/read, atomic write as above.
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

bool prw_image_alloc(prw_image *img, int width, int height, prw_error *e);
void prw_image_free(prw_image *img);

typedef struct prw_kv {
    const char *key;
    const char *value;
} prw_kv;

/* Extra string attributes (e.g. {"prw:spp","64"}) are stored as EXR string attributes. */
bool prw_exr_write(const char *path, const prw_image *img, const prw_kv *attrs, int attr_count, prw_error *e);

typedef struct prw_exr_read_opts {
    bool reject_nonfinite; /* fail with the first NaN/Inf pixel's position */
} prw_exr_read_opts;

bool prw_exr_read(const char *path, const prw_exr_read_opts *opts, prw_image *out, prw_error *e);
/* Reads one string attribute; false (no error) when absent.  value is a caller buffer. */
bool prw_exr_read_attr(const char *path, const char *key, char *value, size_t cap, prw_error *e);

/* 8-bit PNG; channels 1..4. */
bool prw_png_write8(const char *path, int width, int height, int channels, const uint8_t *pixels, prw_error *e);
/* Reads any PNG into 8-bit RGBA (caller frees *pixels). */
bool prw_png_read8(const char *path, int *width, int *height, uint8_t **pixels, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
