/* prw_btf — a BTF in memory as values: linear RGB (float) of every texel for every pair of a view
 * direction and a light direction (CPU only).  The codecs, the synthetic generator and the renderers'
 * uploads read this form; the file formats convert into it (prw_btf_from_ubo, prw_btf_read_image_set).
 *
 * Promises:
 *  - Layout: channel c of texel (x, y) at view v, light l is
 *      rgb[((((size_t)v * lights + l) * height + y) * width + x) * 3 + c]
 *    (one RGB image per direction pair, rows top to bottom).
 *  - Directions are (theta, phi) in radians in the sample's frame: theta from the normal (+z), phi from
 *    +x towards +y; prw_btf_dir_vector gives (sin t cos p, sin t sin p, cos t).
 *  - prw_btf_create checks the size against the memory budget (prw_mem_check) before allocating and
 *    zero-fills; every other function leaves *out empty on failure.
 *  - prw_btf_dirs_ubo81: the 81 directions of the Bonn measurements (UBO2003 and its successors):
 *    rings at theta 0, 15, 30, 45, 60, 75 degrees holding 1, 6, 12, 18, 20, 24 directions, phi from 0
 *    in equal steps, ring by ring.
 *  - prw_btf_read_image_set: a UBO2003-style image set, one image per pair, named
 *    tl<TTT>_pl<PPP>_tv<TTT>_pv<PPP>.<ext> (angles in whole degrees, 3 digits) in the directory or
 *    in its subdirectory tv<TTT>_pv<PPP>/, over the 81 x 81 directions; the images are decoded by
 *    the caller's loader (this module knows no image format); all must have one size.  A missing
 *    image is named in the error.
 */
#ifndef PRW_BTF_H
#define PRW_BTF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "prw_btf_ubo.h"
#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_btf {
    uint32_t width, height, views, lights;
    float *view_dirs;  /* 2 per view: theta, phi */
    float *light_dirs; /* 2 per light */
    float *rgb;
} prw_btf;

#define PRW_BTF_UBO81 81u

bool prw_btf_create(uint32_t width, uint32_t height, uint32_t views, uint32_t lights, prw_btf *out, prw_error *e);
void prw_btf_free(prw_btf *b);

static inline size_t prw_btf_at(const prw_btf *b, uint32_t v, uint32_t l, uint32_t x, uint32_t y)
{
    return ((((size_t)v * b->lights + l) * b->height + y) * b->width + x) * 3;
}

void prw_btf_dir_vector(float theta, float phi, double out[3]);
/* dirs receives 2 * 81 floats. */
void prw_btf_dirs_ubo81(float *dirs);

/* Decodes a Bonn binary (colour model or dynamic-range expansion applied; 3 channels only). */
bool prw_btf_from_ubo(const prw_btf_ubo *u, prw_btf *out, prw_error *e);

/* The raw dump (prw btf-compress --save-btf / --btf: a synthesised BTF kept for later codec runs):
 * "PRWBTFR1", u32 width, height, views, lights, then the view and light (theta, phi) floats and the
 * rgb floats as laid out above, in the host's byte order.  The writer goes through "<path>.tmp" and
 * a rename (no partial file); the reader checks the header's sizes against the file's length and the
 * memory budget before allocating and refuses non-finite values, naming the file. */
bool prw_btf_write_raw(const char *path, const prw_btf *b, prw_error *e);
bool prw_btf_read_raw(const char *path, prw_btf *out, prw_error *e);

/* Loads one image as linear RGB floats (width * height * 3, malloc'd, caller frees), or fails naming it. */
typedef bool (*prw_btf_image_loader)(void *user, const char *path, uint32_t *width, uint32_t *height, float **rgb,
                                     prw_error *e);
/* exts: the extensions to try in order (e.g. {"png", "exr", "jpg"}), count n. */
bool prw_btf_read_image_set(const char *dir, const char *const *exts, int n, prw_btf_image_loader load, void *user,
                            prw_btf *out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
