/* prw_btf_ubo — the BTF binary formats of the University of Bonn's BTF database (UBO2014), read and
 * written (CPU only).  A BTF is the reflectance of every texel (x, y) for every pair of a measured view
 * direction v and light direction l, per colour channel c.
 *
 * Formats (little-endian; layouts learnt from the public readers cgbonn/btflib and zeroeffects/btf,
 * no code taken from either):
 *   DFMF "!DFMF08FC" (+ "R"): per channel c a factorisation of the (view-light) x texel matrix,
 *        raw(c, v, l, x, y) = sum_k U_c[v * lights + l][k] * SxV_c[y * width + x][k], then the colour model;
 *   FMF  "!FMF12FCE" / "!FMF06FC" (+ "R"): one factorisation for all channels, U's rows are
 *        (v * lights + l) * channels + c; the "E" variant has an extra header (dynamic-range
 *        reduction flag, optional height map);
 *   BDI  "!BDIF06R2!": the whole tensor as half floats, one ABRDF (all view-light pairs) per stored
 *        texel, element c + channels * (l + lights * v), texels in scan-line order in chunks of
 *        scan_lines * width; the sparse uncompressed kind (compression 2) only, its mask saying which
 *        texels are stored.  The per-view factorisation (PVF) is not read.
 * Every format starts with the signature, a meta block (its byte size, a version, three 80-byte
 * descriptions, pixels per mm, an RGB scale; from version 2 a cosine flag, from 3 an XML string,
 * from 4 named channels), the directions (per view its (theta, phi) in radians and the light list —
 * one light set for all views is supported, others are refused by name), width and height, and
 * with "R" a list of 3 x 3 rotations.
 *
 * Promises:
 *  - prw_btf_ubo_read / _read_memory accept exactly what prw_btf_ubo_encode writes (a round trip is
 *    exact: every field and value, halves, floats and doubles kept as stored), and refuse anything
 *    else with one line "<name>: <place>: <problem>": a truncated file, counts or sizes that the
 *    remaining bytes cannot hold (checked before anything is allocated), a total beyond the memory
 *    budget (prw_mem_check), a meta block whose size disagrees with its fields, matrix shapes that
 *    disagree with the directions and the texture size, values that are not finite floats (doubles
 *    beyond the float range included: raw values then stay finite), trailing bytes.  On failure
 *    *out is empty.
 *  - Texel (x, y) is column y * width + x as stored.  (zeroeffects/btf reads the columns so and
 *    then flips y; btflib indexes them y fastest: the two public readers disagree, for square
 *    textures by a transpose.  No measured file is at hand to decide it.)
 *  - prw_btf_ubo_raw: the stored channel value before the colour model; prw_btf_ubo_rgb: after it
 *    (DFMF colour models 0, 1, 3, 4, 9, 10, 11, 12 as the public description of btflib lists them;
 *    FMF's dynamic-range reduction exp(v) - 1e-5).  Values are not clamped.
 */
#ifndef PRW_BTF_UBO_H
#define PRW_BTF_UBO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_btf_ubo_format {
    PRW_BTF_UBO_DFMF = 1,
    PRW_BTF_UBO_FMF,
    PRW_BTF_UBO_BDI,
} prw_btf_ubo_format;

/* Limits of this reader (far above the UBO2014 data: 151 x 151 directions, 400 x 400 texels). */
#define PRW_BTF_UBO_MAX_DIRS 65536u
#define PRW_BTF_UBO_MAX_SIDE 65536u
#define PRW_BTF_UBO_MAX_CHANNELS 64u

/* One factorisation: U (rows x components) and SxV (cols x components), row-major, as stored. */
typedef struct prw_btf_ubo_factors {
    uint8_t scalar_size; /* 2 (half), 4 (float) or 8 (double): what the file stores */
    uint32_t components, rows, cols;
    double *s;   /* components singular values */
    double *u;   /* rows * components */
    double *sxv; /* cols * components */
} prw_btf_ubo_factors;

typedef struct prw_btf_ubo {
    prw_btf_ubo_format format;
    bool rotations_flag; /* "R" in the signature (DFMF, FMF; always for BDI) */
    bool fmf_ext;        /* FMF "!FMF12FCE" (else "!FMF06FC") */
    /* meta block */
    uint32_t meta_version; /* 1..4 */
    char measurement_setup[80], image_sensor[80], light_source[80]; /* as stored (not terminated) */
    float ppmm, rgb_scale[3];
    uint32_t cosine_flag; /* version >= 2 */
    uint32_t xml_len;     /* version >= 3 */
    char *xml;
    uint32_t channels;       /* 3 below version 4 */
    uint32_t *channel_len;   /* version >= 4: each name's length */
    char **channel_names;    /* version >= 4: as stored (not terminated) */
    /* directions and texture */
    uint32_t views, lights;
    float *view_dirs;  /* 2 per view: theta, phi */
    float *light_dirs; /* 2 per light */
    uint32_t width, height;
    uint32_t rotation_count; /* with rotations_flag */
    float *rotations;        /* 9 per rotation */
    /* DFMF */
    uint32_t dfmf_components;
    int32_t color_model;
    float color_mean[3], color_transform[9];
    prw_btf_ubo_factors *factors; /* DFMF: channels of them; FMF: one */
    /* FMF with the extra header */
    uint8_t fmf_header_version; /* 0..2 */
    uint32_t drr;               /* version >= 1: dynamic range reduced (exp(v) - 1e-5) */
    uint32_t height_map_w, height_map_h; /* version >= 2 */
    uint16_t *height_map;       /* half floats, row-major */
    uint32_t fmf_components0;   /* the first component count of the FMF block */
    /* BDI */
    uint32_t scan_lines;  /* per chunk */
    uint8_t compression;  /* 2: sparse uncompressed */
    uint8_t *mask;        /* width * height, x fastest: 1 = stored */
    uint64_t stored;      /* texels stored (mask set) */
    uint16_t *bdi;        /* stored * views * lights * channels half floats */
    uint64_t *bdi_slot;   /* per texel its stored index (the reader fills it; NULL: the mask is scanned) */
} prw_btf_ubo;

bool prw_btf_ubo_read(const char *path, prw_btf_ubo *out, prw_error *e);
/* name: what errors start with. */
bool prw_btf_ubo_read_memory(const void *data, size_t size, const char *name, prw_btf_ubo *out, prw_error *e);
/* The file's bytes (malloc'd, caller frees).  Fails on an inconsistent struct (shapes, counts). */
bool prw_btf_ubo_encode(const prw_btf_ubo *b, uint8_t **data, size_t *size, prw_error *e);
/* Encodes and writes atomically (no partial file on failure). */
bool prw_btf_ubo_write(const char *path, const prw_btf_ubo *b, prw_error *e);
void prw_btf_ubo_free(prw_btf_ubo *b);

/* Stored value of channel c at view v, light l, texel (x, y), before the colour model (BDI: 0 for a
 * texel the mask leaves out).  Indices must be in range. */
double prw_btf_ubo_raw(const prw_btf_ubo *b, uint32_t c, uint32_t v, uint32_t l, uint32_t x, uint32_t y);
/* The three channels after the colour model (DFMF) or the dynamic-range expansion (FMF); false with a
 * message for a colour model this reader does not know or a file without 3 channels. */
bool prw_btf_ubo_rgb(const prw_btf_ubo *b, uint32_t v, uint32_t l, uint32_t x, uint32_t y, double rgb[3], prw_error *e);

/* IEEE half <-> float (round to nearest even; exact for every half). */
float prw_btf_half_to_float(uint16_t h);
uint16_t prw_btf_float_to_half(float f);

#ifdef __cplusplus
}
#endif
#endif
