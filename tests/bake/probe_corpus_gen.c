/* Writes the seed corpus of fuzz_probe (not a test): probe_corpus_gen <dir>
 * Small probe files built by hand through prw_probe_encode (one probe of the smallest map; no probe; a keyless file) and a text file. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_probe.h"

static int put(const char *dir, const char *name, const void *d, size_t n)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(d, 1, n, f) != n) {
        fprintf(stderr, "probe_corpus_gen: cannot write %s\n", path);
        if (f) fclose(f);
        return 1;
    }
    fclose(f);
    return 0;
}

static int put_bake(const char *dir, const char *name, const prw_probe_bake *b, const char *key)
{
    uint8_t *d = NULL;
    size_t n = 0;
    prw_error e = {{0}};
    if (!prw_probe_encode(b, key, &d, &n, &e)) {
        fprintf(stderr, "probe_corpus_gen: %s\n", e.msg);
        return 1;
    }
    int rc = put(dir, name, d, n);
    free(d);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: probe_corpus_gen DIR\n");
        return 2;
    }
    /* size 8: level height 4, PRW_PROBE_LEVELS levels of 8 x 4 texels x RGB */
    enum { LEVELS = PRW_PROBE_LEVELS, H = 4 };
    static float rgb[LEVELS * H * 2 * H * 3];
    for (size_t i = 0; i < sizeof rgb / sizeof rgb[0]; i++) rgb[i] = 0.125f * (float)(i % 17);
    prw_probe_bake b = {.count = 1, .size = 8, .samples = 4, .levels = LEVELS, .level_height = H,
                        .parallax_min = {-3, 0, -2.5}, .parallax_max = {3, 3, 2.5}, .levels_rgb = rgb};
    b.probes[0] = (prw_probe_info){.node = 3, .mesh = 1, .material = 2, .centre = {0.2, 1.1, -1.2},
                                   .box_min = {-0.1, 0.8, -1.5}, .box_max = {0.5, 1.4, -0.9}, .tnear = 0.3};
    int rc = put_bake(argv[1], "one.probe", &b, "0123456789abcdef0123456789abcdef");
    rc |= put_bake(argv[1], "keyless.probe", &b, NULL);
    prw_probe_bake none = {.count = 0, .size = 64, .samples = 16, .levels = 21, .level_height = 32};
    rc |= put_bake(argv[1], "none.probe", &none, "fedcba9876543210fedcba9876543210");
    const char *txt = "not a probe file\n";
    rc |= put(argv[1], "garbage.txt", txt, strlen(txt));
    return rc;
}
