/* Regenerates the binary seed corpora of the reader fuzz targets (not a test):
 *   readers_corpus_gen <tests/fuzz_readers>
 * corpus_acc/: accumulation files (whole image, a tile, a depth filter, a truncated and a
 * wrong-revision copy); corpus_envmap/: small environment maps (float ZIP, half PIZ, tiled, Y only,
 * black, a header claiming 16384^2). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "exr_gen.h"
#include "prw_image.h"
#include "prw_reference.h"

static void acc(const char *dir, const char *name, uint32_t w, uint32_t h, uint32_t x0, uint32_t y0, uint32_t x1,
                uint32_t y1, prw_ref_filter f)
{
    prw_ref_acc a;
    memset(&a, 0, sizeof a);
    a.width = w, a.height = h, a.x0 = x0, a.y0 = y0, a.x1 = x1, a.y1 = y1;
    a.s0 = 0, a.s1 = 4, a.seed = 1, a.scene_hash = 0x1234, a.material_hash = prw_ref_material_hash();
    a.filter = f, a.ev100 = 7.5;
    size_t n = 3 * (size_t)(x1 - x0) * (y1 - y0);
    a.sum = calloc(n, sizeof *a.sum);
    a.sq = calloc(n, sizeof *a.sq);
    for (size_t i = 0; i < n; i++) {
        double v = 0.25 * (double)(i % 7);
        a.sum[i] = (prw_ref_fixed)(4 * v * PRW_REF_SUM_SCALE);
        a.sq[i] = (prw_ref_fixed)(4 * v * v * PRW_REF_SQ_SCALE);
    }
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    prw_error e;
    if (!prw_ref_acc_write(p, &a, &e)) fprintf(stderr, "%s\n", e.msg);
    free(a.sum);
    free(a.sq);
}

static void damaged(const char *dir, const char *from, const char *to, long cut, int at, char byte)
{
    char p[1024], q[1024];
    snprintf(p, sizeof p, "%s/%s", dir, from);
    snprintf(q, sizeof q, "%s/%s", dir, to);
    char *d = NULL;
    size_t n = 0;
    prw_error e;
    if (!prw_read_file(p, &d, &n, &e)) return;
    if (at >= 0 && (size_t)at < n) d[at] = byte;
    FILE *f = fopen(q, "wb");
    fwrite(d, 1, cut >= 0 && (size_t)cut < n ? (size_t)cut : n, f);
    fclose(f);
    free(d);
}

static float sky(int x, int y, char c, void *u)
{
    (void)u;
    float v = 1.0f + (float)y * 2.0f + (x == 3 && y == 1 ? 500.0f : 0.0f);
    return c == 'B' ? v * 1.5f : c == 'A' ? 1.0f : v;
}

static void gen(const char *dir, const char *name, exr_gen_opts o)
{
    uint8_t *bytes = NULL;
    size_t size = 0;
    char err[256], p[1024];
    if (!exr_gen_write(&o, sky, NULL, &bytes, &size, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", name, err);
        return;
    }
    snprintf(p, sizeof p, "%s/%s", dir, name);
    FILE *f = fopen(p, "wb");
    fwrite(bytes, 1, size, f);
    fclose(f);
    free(bytes);
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: readers_corpus_gen <tests/fuzz_readers>\n");
        return 2;
    }
    char a[900], v[900];
    snprintf(a, sizeof a, "%s/corpus_acc", argv[1]);
    snprintf(v, sizeof v, "%s/corpus_envmap", argv[1]);
    mkdir(a, 0755);
    mkdir(v, 0755);
    acc(a, "whole_3x2.acc", 3, 2, 0, 0, 3, 2, (prw_ref_filter){PRW_REF_ALL, 0});
    acc(a, "tile_of_8x6.acc", 8, 6, 2, 1, 5, 3, (prw_ref_filter){PRW_REF_DIRECT, 0});
    acc(a, "depth2_2x2.acc", 2, 2, 0, 0, 2, 2, (prw_ref_filter){PRW_REF_DEPTH, 2});
    damaged(a, "whole_3x2.acc", "truncated.acc", 300, -1, 0);
    damaged(a, "whole_3x2.acc", "revision.acc", -1, 7, '\n');
    damaged(a, "whole_3x2.acc", "bad_checksum.acc", -1, 200, 0x55);

    gen(v, "sky_float_zip.exr", (exr_gen_opts){.width = 8, .height = 4, .type = EXR_PIXEL_FLOAT, .channels = "RGB",
                                              .compression = EXR_COMPRESSION_ZIP});
    gen(v, "sky_half_piz.exr", (exr_gen_opts){.width = 16, .height = 8, .type = EXR_PIXEL_HALF, .channels = "RGBA",
                                             .compression = EXR_COMPRESSION_PIZ});
    gen(v, "sky_tiled_rle.exr", (exr_gen_opts){.width = 8, .height = 4, .type = EXR_PIXEL_HALF, .channels = "RGB",
                                              .tiled = true, .tile_w = 4, .tile_h = 4,
                                              .compression = EXR_COMPRESSION_RLE});
    gen(v, "sky_y_none.exr", (exr_gen_opts){.width = 4, .height = 2, .type = EXR_PIXEL_FLOAT, .channels = "Y",
                                           .compression = EXR_COMPRESSION_NONE});
    prw_image black;
    prw_error e;
    char p[1024];
    if (prw_image_alloc(&black, 4, 2, &e)) {
        snprintf(p, sizeof p, "%s/black.exr", v);
        prw_exr_write(p, &black, NULL, 0, &e);
        prw_image_free(&black);
    }
    /* a header that claims 16384 x 16384 in a few hundred bytes */
    char *d = NULL;
    size_t n = 0;
    snprintf(p, sizeof p, "%s/black.exr", v);
    if (prw_read_file(p, &d, &n, &e)) {
        const char key[] = "dataWindow\0box2i";
        for (size_t i = 0; i + sizeof key + 20 <= n; i++)
            if (memcmp(d + i, key, sizeof key) == 0) {
                const int32_t box[4] = {0, 0, 16383, 16383};
                memcpy(d + i + sizeof key + 4, box, 16);
            }
        snprintf(p, sizeof p, "%s/claim_16384.exr", v);
        FILE *f = fopen(p, "wb");
        fwrite(d, 1, n, f);
        fclose(f);
        free(d);
    }
    return 0;
}
