/* Reflection probes (issue 16, must-show 3's "probe-lit sphere"): the base pass's probe term against the
 * path tracer's indirect-glossy-last term on gi-room, camera main, 128x72, 4x MSAA, validation layer on.
 *
 * The raster image is the base pass with only the probe term drawn (prw_render_desc.terms =
 * PRW_TERM_PROBES, what `prw render --term probes` draws), from probes baked here (no cache) with the
 * default knobs (probe_count 4, probe_size 64, 16 rays per texel, seed 7): gi-room gets two, the gold and
 * the blue sphere.  Pixels: those whose four sub-pixel camera rays (at 0.2 / 0.8 of the pixel) all hit a
 * probed material (the spheres' insides; their rims mix in the floor and walls, whose glossy terms are
 * other passes'), and where the filtered reference's luminance exceeds 1 % of the full reference's.  The
 * references (indirect-glossy-last with seeds 1 and 2 for the noise, the unfiltered image with seed 3)
 * are rendered over the tile holding those pixels only.  Over them, at the term's own metric exposure
 * (the mean luminance of reference A mapped to 0.18):
 *   LDR-FLIP beyond noise = FLIP(raster, A) - FLIP(B, A),  relMSE beyond noise = relMSE(raster, A) - relMSE(B, A) / 2,
 * both <= the bounds below.  Controls that must exceed a bound: the probes x 0.8, the probes without parallax
 * correction (the parallax box at 10 km), the probes off (a zero term).
 *
 * Environment: PRW_PROBE_SPP (reference samples per pixel, default 256), PRW_PROBE_SIZE / PRW_PROBE_RAYS (the
 * probes' map rows and rays per texel, for the error-against-bake-time sweep), PRW_PROBE_OUT=DIR writes
 * raster.exr, ref_a.exr, ref_b.exr there (and PNGs at the metric exposure). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lightmaps.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_probe.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"
#include "term_error.h"

#define W 128u
#define H 72u
#define FLIP_BOUND 0.05 /* the goal */
#define REL_BOUND 0.05

static unsigned long env_u(const char *name, unsigned long def)
{
    const char *v = getenv(name);
    return v && *v ? strtoul(v, NULL, 10) : def;
}

static double lum(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

static void render_raster(const prw_scene *s, const prw_view *v, const prw_probes *pr, prw_image *hdr)
{
    prw_error e = {{0}};
    prw_render_desc rd = {.width = W, .height = H, .quality = prw_quality_default(), .probes = pr,
                          .terms = PRW_TERM_PROBES};
    rd.quality.msaa = 4;
    CHECK_OK(prw_test_render(s, &rd, v, 1, hdr, NULL, &e), &e);
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (int c = 0; c < 3; c++) CHECK(isfinite(hdr->rgba[4 * i + c]) && hdr->rgba[4 * i + c] >= 0);
}

/* The reference over tile [x0,x1) x [y0,y1) into a full-size image (0 outside). */
static void render_ref(prw_ref_renderer *ref, const prw_view *v, const uint32_t tile[4], uint64_t spp, uint64_t seed,
                       prw_ref_filter_kind k, prw_image *out)
{
    prw_error e = {{0}};
    prw_ref_desc d = {.x0 = tile[0], .y0 = tile[1], .x1 = tile[2], .y1 = tile[3], .s0 = 0, .s1 = spp, .seed = seed,
                      .filter = {.kind = k}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    CHECK_OK(prw_ref_render(ref, v, &d, &acc, &st, &e), &e);
    CHECK_OK(prw_image_alloc(out, W, H, &e), &e);
    memset(out->rgba, 0, (size_t)W * H * 4 * sizeof(float));
    uint32_t tw = acc.x1 - acc.x0;
    for (uint32_t y = acc.y0; y < acc.y1; y++)
        for (uint32_t x = acc.x0; x < acc.x1; x++) {
            size_t t = (size_t)(y - acc.y0) * tw + (x - acc.x0), i = (size_t)y * W + x;
            for (int c = 0; c < 3; c++)
                out->rgba[4 * i + c] = (float)((double)acc.sum[3 * t + c] / PRW_REF_SUM_SCALE / (double)st.spp);
            out->rgba[4 * i + 3] = 1.0f;
        }
    printf("reference %s seed %llu: %llu spp over %ux%u in %.1f s\n", k == PRW_REF_ALL ? "all" : "indirect-glossy-last",
           (unsigned long long)seed, (unsigned long long)st.spp, tile[2] - tile[0], tile[3] - tile[1], st.seconds);
    prw_ref_acc_free(&acc);
}

static void write_if(const char *dir, const char *name, const prw_image *im, double ev100)
{
    if (!dir || !*dir) return;
    char path[4096], ev[64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(ev, sizeof ev, "%.17g", ev100);
    prw_kv kv[] = {{"prw:ev100", ev}};
    prw_error e;
    if (prw_exr_write(path, im, kv, 1, &e)) printf("wrote %s\n", path);
    else fprintf(stderr, "%s\n", e.msg);
}

static void test_gi_room_probes(void)
{
    prw_error e = {{0}};
    bool light = prw_test_light();
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_load_manifest(s, PRW_SOURCE_DIR "/assets/scenes/gi-room.json", &e), &e);
    prw_scene_update(s);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);

    /* the probes: the default knobs (light mode: a small map, few rays) */
    prw_quality q = prw_quality_default();
    prw_probe_options o = prw_app_probe_options(&q);
    o.seed = 7;
    if (light) o.size = 16, o.samples = 2;
    o.size = (uint32_t)env_u("PRW_PROBE_SIZE", o.size), o.samples = (uint32_t)env_u("PRW_PROBE_RAYS", o.samples);
    prw_probe_bake *b = NULL;
    prw_probe_result pr;
    clock_t c0 = clock();
    CHECK_OK(prw_probe_run(s, &o, true, NULL, NULL, &b, &pr, &e), &e);
    printf("probes: %u (size %u, %u rays per texel) in %.1f s (CPU %.1f s)\n", b->count, b->size, b->samples,
           pr.seconds_total, (double)(clock() - c0) / CLOCKS_PER_SEC);
    CHECK_MSG(b->count == 2, "gi-room: %u probes (expected the gold and the blue sphere)", b->count);
    bool probed[64] = {false};
    for (uint32_t i = 0; i < b->count; i++) {
        const prw_probe_info *p = &b->probes[i];
        printf("  probe %u: material '%s', centre (%.3f, %.3f, %.3f)\n", i, s->materials[p->material].name,
               p->centre[0], p->centre[1], p->centre[2]);
        if (p->material < 64) probed[p->material] = true;
    }
    prw_probes probes, scaled, flat;
    prw_app_probes_from_bake(b, &probes);
    size_t nl = (size_t)probes.count * probes.levels * probes.height * 2 * probes.height * 3;
    float *lv = prw_malloc(nl * sizeof(float));
    for (size_t i = 0; i < nl; i++) lv[i] = 0.8f * b->levels_rgb[i];
    scaled = probes, scaled.levels_rgb = lv;
    flat = probes;
    for (int c = 0; c < 3; c++) flat.parallax_min[c] = -1e4f, flat.parallax_max[c] = 1e4f;

    prw_image raster = {0}, r_scaled = {0}, r_flat = {0}, ra = {0}, rb = {0}, rall = {0}, zero = {0};
    render_raster(s, &v, &probes, &raster);
    render_raster(s, &v, &scaled, &r_scaled);
    render_raster(s, &v, &flat, &r_flat);
    CHECK_OK(prw_image_alloc(&zero, W, H, &e), &e);
    memset(zero.rgba, 0, (size_t)W * H * 4 * sizeof(float));

    /* the pixels inside the probed objects */
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &ref, &e), &e);
    uint8_t *mask = prw_calloc((size_t)W * H, 1);
    uint32_t tile[4] = {W, H, 0, 0};
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            bool in = true;
            for (int k = 0; k < 4 && in; k++) {
                prw_ref_hit h;
                in = prw_ref_primary_hit(ref, &v, x + (k & 1 ? 0.8 : 0.2), y + (k & 2 ? 0.8 : 0.2), &h) &&
                     h.material >= 0 && h.material < 64 && probed[h.material];
            }
            if (!in) continue;
            mask[(size_t)y * W + x] = 1;
            if (x < tile[0]) tile[0] = x;
            if (y < tile[1]) tile[1] = y;
            if (x + 1 > tile[2]) tile[2] = x + 1;
            if (y + 1 > tile[3]) tile[3] = y + 1;
        }
    CHECK_MSG(tile[2] > tile[0], "no pixel inside a probed object");
    uint64_t spp = env_u("PRW_PROBE_SPP", light ? 8 : 256);
    render_ref(ref, &v, tile, spp, 1, PRW_REF_INDIRECT_GLOSSY_LAST, &ra);
    render_ref(ref, &v, tile, spp, 2, PRW_REF_INDIRECT_GLOSSY_LAST, &rb);
    render_ref(ref, &v, tile, spp, 3, PRW_REF_ALL, &rall);
    prw_ref_destroy(ref);

    size_t nm = 0, inside = 0;
    double ml = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        inside += mask[i];
        mask[i] = mask[i] && lum(ra.rgba + 4 * i) > 0.01 * lum(rall.rgba + 4 * i);
        nm += mask[i];
        if (mask[i]) ml += lum(ra.rgba + 4 * i);
    }
    CHECK_MSG(nm > 100, "%zu pixels (of %zu inside the spheres) where the term is > 1 %% of the reference", nm, inside);
    ml /= (double)nm;
    double ev = log2(ml / (0.18 * 1.2));
    term_err err, noise, c_scaled, c_flat, c_zero;
    masked_error(&raster, &ra, mask, ev, &err);
    masked_error(&rb, &ra, mask, ev, &noise);
    masked_error(&r_scaled, &ra, mask, ev, &c_scaled);
    masked_error(&r_flat, &ra, mask, ev, &c_flat);
    masked_error(&zero, &ra, mask, ev, &c_zero);
    double fb = err.flip - noise.flip, rb_ = err.relmse - noise.relmse / 2;
    printf("gi-room, camera main, %ux%u, 4x MSAA, term probes vs indirect-glossy-last %llu spp, metric EV100 %.4f (the "
           "term's own), %zu of %zu pixels inside the spheres where the term > 1 %% of the full reference:\n",
           W, H, (unsigned long long)spp, ev, nm, inside);
    printf("  LDR-FLIP  raster vs A %.4f  noise (B vs A) %.4f  beyond noise %.4f (bound %.3f)\n", err.flip, noise.flip,
           fb, FLIP_BOUND);
    printf("  relMSE    raster vs A %.4f  noise (B vs A) %.4f  beyond noise %.4f (bound %.3f)\n", err.relmse,
           noise.relmse, rb_, REL_BOUND);
    const term_err *ctl[3] = {&c_scaled, &c_flat, &c_zero};
    const char *ctl_name[3] = {"probes x 0.8", "no parallax correction", "probes off"};
    bool ctl_fails[3];
    for (int k = 0; k < 3; k++) {
        double f = ctl[k]->flip - noise.flip, r = ctl[k]->relmse - noise.relmse / 2;
        ctl_fails[k] = f > FLIP_BOUND || r > REL_BOUND;
        printf("  control %-24s LDR-FLIP beyond noise %.4f, relMSE beyond noise %.4f: %s\n", ctl_name[k], f, r,
               ctl_fails[k] ? "fails the bounds" : "PASSES the bounds");
    }
    const char *dir = getenv("PRW_PROBE_OUT");
    write_if(dir, "raster.exr", &raster, ev);
    write_if(dir, "ref_a.exr", &ra, ev);
    write_if(dir, "ref_b.exr", &rb, ev);
    if (light) {
        printf("  light mode: the bounds are not checked at %llu spp\n", (unsigned long long)spp);
        CHECK_MSG(c_zero.flip > err.flip, "the probes-off control is not worse: %.4f vs %.4f", c_zero.flip, err.flip);
    } else {
        CHECK_MSG(fb <= FLIP_BOUND, "LDR-FLIP beyond noise %.4f > %.3f", fb, FLIP_BOUND);
        CHECK_MSG(rb_ <= REL_BOUND, "relMSE beyond noise %.4f > %.3f", rb_, REL_BOUND);
        for (int k = 0; k < 3; k++) CHECK_MSG(ctl_fails[k], "the control '%s' passes the bounds", ctl_name[k]);
    }
    free(lv);
    free(mask);
    prw_image_free(&raster), prw_image_free(&r_scaled), prw_image_free(&r_flat), prw_image_free(&zero);
    prw_image_free(&ra), prw_image_free(&rb), prw_image_free(&rall);
    prw_probe_bake_destroy(b);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"gi_room_probes", test_gi_room_probes}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases */
}
