/* exr_gen — test-only EXR writer on the OpenEXR C API, for files prw_exr_write never makes
 * (half/uint channels, Y, tiles, data window offsets, other chromaticities, other compressions). */
#ifndef EXR_GEN_H
#define EXR_GEN_H

#include <openexr.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct exr_gen_opts {
    int width, height;
    int min_x, min_y;          /* data window origin */
    exr_pixel_type_t type;     /* all channels */
    const char *channels;      /* one letter per channel, e.g. "RGBA", "RGB", "Y" (written sorted by the library) */
    bool tiled;
    int tile_w, tile_h;
    exr_compression_t compression;
    const exr_attr_chromaticities_t *chroma; /* NULL: no attribute */
} exr_gen_opts;

/* value(x, y, channel letter) in output coordinates (0..width-1); converted to the pixel type
 * (half by truncation: use exactly representable values). */
typedef float (*exr_gen_value_fn)(int x, int y, char channel, void *user);

/* Returns malloc'ed file bytes in *data / *size; on failure false and a message in err. */
bool exr_gen_write(const exr_gen_opts *o, exr_gen_value_fn value, void *user, uint8_t **data, size_t *size,
                   char *err, size_t err_cap);

uint16_t exr_gen_float_to_half(float f);

#endif
