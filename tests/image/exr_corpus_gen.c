/* exr_corpus_gen <dir> — writes the small seed EXRs of tests/fuzz_image/corpus (each < 4 KB). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "exr_gen.h"
#include "prw_image.h"

static float val(int x, int y, char ch, void *u)
{
    (void)u;
    return (float)((x * 3 + y * 5 + ch) % 17) * 0.25f - 1.0f;
}

static int put(const char *dir, const char *name, const exr_gen_opts *o)
{
    uint8_t *d = NULL;
    size_t n = 0;
    char err[512], path[1024];
    if (!exr_gen_write(o, val, NULL, &d, &n, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", name, err);
        return 1;
    }
    snprintf(path, sizeof path, "%s/%s", dir, name);
    prw_error e;
    int rc = prw_write_file_atomic(path, d, n, &e) ? 0 : 1;
    if (rc) fprintf(stderr, "%s\n", e.msg);
    else printf("%s: %zu bytes\n", path, n);
    free(d);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: exr_corpus_gen <dir>\n");
        return 2;
    }
    const char *dir = argv[1];
    exr_attr_chromaticities_t rec2020 = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
    int rc = 0;
    rc |= put(dir, "scan_float_zip.exr",
              &(exr_gen_opts){.width = 5, .height = 17, .type = EXR_PIXEL_FLOAT, .channels = "RGBA", .compression = EXR_COMPRESSION_ZIP});
    rc |= put(dir, "scan_half_none.exr",
              &(exr_gen_opts){.width = 4, .height = 3, .type = EXR_PIXEL_HALF, .channels = "RGB", .compression = EXR_COMPRESSION_NONE});
    rc |= put(dir, "scan_half_piz.exr",
              &(exr_gen_opts){.width = 6, .height = 5, .type = EXR_PIXEL_HALF, .channels = "RGBA", .compression = EXR_COMPRESSION_PIZ});
    rc |= put(dir, "scan_uint_zips_offset.exr",
              &(exr_gen_opts){.width = 3, .height = 4, .min_x = -2, .min_y = -1, .type = EXR_PIXEL_UINT, .channels = "RGB",
                              .compression = EXR_COMPRESSION_ZIPS});
    rc |= put(dir, "tiled_float_rle.exr",
              &(exr_gen_opts){.width = 7, .height = 5, .min_x = 3, .min_y = -4, .type = EXR_PIXEL_FLOAT, .channels = "RGBA",
                              .tiled = true, .tile_w = 4, .tile_h = 2, .compression = EXR_COMPRESSION_RLE});
    rc |= put(dir, "tiled_half_pxr24.exr",
              &(exr_gen_opts){.width = 5, .height = 5, .type = EXR_PIXEL_HALF, .channels = "RGB", .tiled = true,
                              .tile_w = 2, .tile_h = 3, .compression = EXR_COMPRESSION_PXR24});
    rc |= put(dir, "grey_y_b44.exr",
              &(exr_gen_opts){.width = 8, .height = 4, .type = EXR_PIXEL_HALF, .channels = "Y", .compression = EXR_COMPRESSION_B44});
    rc |= put(dir, "rec2020_zip.exr",
              &(exr_gen_opts){.width = 4, .height = 4, .type = EXR_PIXEL_HALF, .channels = "RGB", .compression = EXR_COMPRESSION_ZIP,
                              .chroma = &rec2020});
    /* and one from prw_exr_write itself, with an attribute and a NaN */
    prw_image img;
    prw_error e;
    if (prw_image_alloc(&img, 3, 2, &e)) {
        img.rgba[5] = NAN;
        char path[1024];
        snprintf(path, sizeof path, "%s/prw_write_nan.exr", dir);
        prw_kv kv = {"prw:spp", "64"};
        if (!prw_exr_write(path, &img, &kv, 1, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            rc = 1;
        }
        prw_image_free(&img);
    }
    return rc;
}
