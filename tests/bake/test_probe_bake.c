/* The reflection-probe baker (engine/bake/prw_probe.h): placement on gi-room (the two spheres, the
 * largest first, none with count 0, planar and rough meshes never), what a texel holds in closed form
 * (a furnace), the file's round trip and its strict reader, the cache key.
 *
 * Furnace: a closed box of Lambert walls of albedo a = 0.5 emitting Le = 10 cd/m^2 everywhere, a small
 * gold sphere (radius 0.05) in its centre.  The radiance leaving a wall is Le / (1 - a) = 20; a probe
 * holds it minus the emission: Le a / (1 - a) = 10 in every texel (the small sphere changes the walls'
 * irradiance by less than its solid angle share, < 0.1 %).  With emission wrongly included it would
 * read 20, without the bounces 0. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_probe.h"
#include "prw_test.h"

#define GI_ROOM PRW_SOURCE_DIR "/assets/scenes/gi-room.json"

static void load(const char *path, prw_scene **out)
{
    prw_error e = {{0}};
    prw_scene *s = prw_scene_create();
    *out = s;
    CHECK_OK(prw_scene_load_manifest(s, path, &e), &e);
    prw_scene_update(s);
}

static void test_select(void)
{
    prw_scene *s = NULL;
    load(GI_ROOM, &s);
    prw_probe_options o = {.count = 4, .size = 16};
    prw_probe_bake b;
    memset(&b, 0, sizeof b);
    prw_probe_select(s, &o, &b);
    CHECK_MSG(b.count == 2, "%u probes", b.count);
    CHECK(strcmp(s->materials[b.probes[0].material].name, "blue plastic") == 0); /* radius 0.35 before 0.3 */
    CHECK(strcmp(s->materials[b.probes[1].material].name, "gold") == 0);
    CHECK(fabs(b.probes[1].centre[0] - 0.2) < 1e-3 && fabs(b.probes[1].centre[1] - 1.1) < 1e-3 &&
          fabs(b.probes[1].centre[2] + 1.2) < 1e-3);
    for (int c = 0; c < 3; c++) CHECK(b.probes[1].box_min[c] < b.probes[1].centre[c] - 0.29 && b.probes[1].box_max[c] > b.probes[1].centre[c] + 0.29);
    CHECK(b.parallax_min[0] == -3 && b.parallax_max[1] == 3);
    o.count = 1;
    prw_probe_select(s, &o, &b);
    CHECK(b.count == 1 && strcmp(s->materials[b.probes[0].material].name, "blue plastic") == 0);
    o.count = 0;
    prw_probe_select(s, &o, &b);
    CHECK(b.count == 0);
    o.count = 4, o.max_roughness = 0.27; /* the gold sphere (0.3) drops out */
    prw_probe_select(s, &o, &b);
    CHECK(b.count == 1 && strcmp(s->materials[b.probes[0].material].name, "blue plastic") == 0);
    /* keys: options and content, not cameras */
    prw_probe_options k = {.count = 4, .size = 16};
    char k0[33], k1[33], k2[33];
    prw_probe_key(s, &k, k0);
    k.size = 32;
    prw_probe_key(s, &k, k1);
    CHECK(strcmp(k0, k1) != 0);
    s->nodes[s->cameras[0].node].translation.x += 0.5;
    prw_scene_update(s);
    k.size = 16;
    prw_probe_key(s, &k, k2);
    CHECK(strcmp(k0, k2) == 0);
    prw_scene_destroy(s);
}

static void test_furnace_and_file(void)
{
    const char *path = prw_test_path("furnace.json");
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    fprintf(f, "{\"prw_manifest\": 1,\n"
               " \"materials\": [{\"name\": \"wall\", \"base_color\": [0.5, 0.5, 0.5], \"metallic\": 0, \"roughness\": 1,"
               " \"specular\": 0, \"emission_cd_m2\": [10, 10, 10]},\n"
               "  {\"name\": \"gold\", \"base_color\": [1, 0.78, 0.34], \"metallic\": 1, \"roughness\": 0.3}],\n"
               " \"meshes\": [{\"name\": \"box\", \"box\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1], \"inward\": true},"
               " \"material\": \"wall\"},\n"
               "  {\"name\": \"ball\", \"sphere\": {\"centre\": [0, 0, 0], \"radius\": 0.05, \"slices\": 16, \"stacks\": 8},"
               " \"material\": \"gold\"}],\n"
               " \"cameras\": [{\"name\": \"c\", \"position\": [0.5, 0.2, 0.5], \"target\": [0, 0, 0], \"up\": [0, 1, 0],"
               " \"yfov_deg\": 60}]}\n");
    fclose(f);
    prw_scene *s = NULL;
    load(path, &s);
    prw_error e = {{0}};
    bool light = prw_test_light();
    prw_probe_options o = {.count = 4, .size = 8, .samples = light ? 4 : 256, .seed = 3};
    prw_probe_bake *b = NULL;
    prw_probe_result r;
    CHECK_OK(prw_probe_run(s, &o, true, NULL, NULL, &b, &r, &e), &e);
    CHECK(b->count == 1 && b->levels == PRW_PROBE_LEVELS && b->level_height == 4);
    /* the prefiltered levels keep the constant: mean over every texel of every level */
    size_t n = (size_t)b->levels * 4 * 8 * 3;
    double sum = 0, lo = 1e30, hi = 0;
    for (size_t i = 0; i < n; i++) sum += b->levels_rgb[i], lo = fmin(lo, b->levels_rgb[i]), hi = fmax(hi, b->levels_rgb[i]);
    double mean = sum / (double)n;
    printf("furnace: mean %.4f (expected 10: Le a / (1 - a)), texels in [%.3f, %.3f], %.2f s\n", mean, lo, hi,
           r.seconds_total);
    CHECK_MSG(fabs(mean - 10) < (light ? 2.0 : 0.3), "furnace mean %.4f", mean);
    /* file round trip, then damage */
    uint8_t *data = NULL;
    size_t size = 0;
    CHECK_OK(prw_probe_encode(b, r.key, &data, &size, &e), &e);
    prw_probe_bake *d = NULL;
    char key[33];
    CHECK_OK(prw_probe_decode(data, size, "mem.probe", &d, key, &e), &e);
    CHECK(strcmp(key, r.key) == 0 && d->count == 1 && memcmp(d->levels_rgb, b->levels_rgb, n * sizeof(float)) == 0);
    CHECK(d->probes[0].material == b->probes[0].material && d->probes[0].centre[1] == b->probes[0].centre[1]);
    prw_probe_bake_destroy(d);
    data[size / 2] ^= 1;
    CHECK(!prw_probe_decode(data, size, "mem.probe", &d, key, &e) && strstr(e.msg, "mem.probe: checksum") != NULL);
    data[size / 2] ^= 1;
    CHECK(!prw_probe_decode(data, size - 9, "mem.probe", &d, key, &e) && strstr(e.msg, "mem.probe") != NULL);
    CHECK(!prw_probe_decode(data, 20, "mem.probe", &d, key, &e) && strstr(e.msg, "mem.probe") != NULL);
    printf("damaged: %s\n", e.msg);
    free(data);
    prw_probe_options bad = o;
    bad.size = 4;
    CHECK(!prw_probe_run(s, &bad, true, NULL, NULL, &d, &r, &e) && strstr(e.msg, "size 4") != NULL);
    prw_probe_bake_destroy(b);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"select", test_select}, {"furnace_and_file", test_furnace_and_file}};
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
