/* Writes the seed corpus of fuzz_gi (not a test): gi_corpus_gen <dir>
 * Small light-map files built by hand (an atlas with sampled / dilated / unused texels, an ATLAS,
 * a VERTEX and a NONE instance; an empty bake) through prw_gi_encode, and a text file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_gi.h"

static int put(const char *dir, const char *name, const void *d, size_t n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(d, 1, n, f) != n) {
        fprintf(stderr, "gi_corpus_gen: cannot write %s\n", path);
        if (f) fclose(f);
        return 1;
    }
    fclose(f);
    return 0;
}

static int put_bake(const char *dir, const char *name, const prw_gi_bake *b)
{
    uint8_t *d = NULL;
    size_t n = 0;
    prw_error e = {{0}};
    if (!prw_gi_encode(b, "0123456789abcdef0123456789abcdef", &d, &n, &e)) return 1;
    int rc = put(dir, name, d, n);
    free(d);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: gi_corpus_gen DIR\n");
        return 2;
    }
    float rgb[4 * 3 * 3], var[4 * 3 * 3], uv[12] = {0.1f, 0.1f, 0.9f, 0.1f, 0.1f, 0.9f, 0.9f, 0.1f, 0.9f, 0.9f, 0.1f, 0.9f};
    uint8_t state[12] = {0, 1, 1, 2, 2, 1, 1, 0, 0, 2, 2, 0};
    for (int i = 0; i < 36; i++) rgb[i] = 0.25f * (float)i, var[i] = 0.01f * (float)(i % 5);
    float vrgb[9] = {1, 2, 3, 4, 5, 6, 7, 8, 9}, vvar[9] = {0}, vvis[3] = {1, 0.5f, 0};
    float vis[12], vcone[12] = {0, 1, 0, 1, 0.5f, 0, 0, 0.5f, 0, 0, 0, 0};
    for (int i = 0; i < 12; i++) vis[i] = (float)i / 11.0f;
    float cone[48];
    for (int i = 0; i < 12; i++) cone[4 * i] = 0, cone[4 * i + 1] = 0.5f, cone[4 * i + 2] = 0, cone[4 * i + 3] = vis[i];
    prw_gi_atlas atlas = {.width = 4, .height = 3, .rgb = rgb, .var = var, .vis = vis, .cone = cone, .state = state};
    prw_gi_instance inst[3] = {
        {.node = 0, .mesh = 0, .mode = PRW_GI_ATLAS, .atlas = 0, .triangle_count = 2, .uv = uv},
        {.node = 1, .mesh = 1, .mode = PRW_GI_VERTEX, .vertex_count = 3, .vertex_rgb = vrgb, .vertex_var = vvar,
         .vertex_vis = vvis, .vertex_cone = vcone},
        {.node = 2, .mesh = 2, .mode = PRW_GI_NONE},
    };
    prw_gi_bake b = {.texel_size = 0.05, .samples = 16, .atlas_count = 1, .atlases = &atlas, .instance_count = 3, .inst = inst};
    int rc = put_bake(argv[1], "small.gi", &b);
    prw_gi_bake empty = {.texel_size = 1, .samples = 1};
    rc |= put_bake(argv[1], "empty.gi", &empty);
    const char *txt = "not a light map\n";
    rc |= put(argv[1], "garbage.txt", txt, strlen(txt));
    return rc;
}
