/* prw btf-bench — the cost of the BTF material kind in the base pass (issue "BTF materials",
 * must-show 5): one view of a scene rendered with its BTF materials and with each
 * BTF material replaced by the analytic material of its file's fitted average BRDF (the scale rule's
 * average), two renderers in one process interleaved frame by frame (BTF first on even pairs,
 * analytic first on odd ones), timestamps off.  Prints the median over pairs of the frame-time ratio BTF / analytic with a
 * bootstrap 95 % interval over pairs (prw_stats_bootstrap_pair_ratio), and the share of the pixels
 * the BTF materials cover.  `--only btf|analytic` renders one variant's frames (for callgrind). */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "prw_btf_codec.h"
#include "prw_image.h"
#include "prw_render.h"
#include "prw_stats.h"

#define BB_RESAMPLES 4000
#define BB_SEED 1

static void help(void)
{
    printf("usage: prw btf-bench [SCENE] [options]\n"
           "  Frame time of SCENE's view with its BTF materials over the same view with each BTF material\n"
           "  replaced by its file's fitted average BRDF (analytic), interleaved frame by frame in one process:\n"
           "    btf-bench: BTF / analytic = R (median of pair ratios), 95 %% interval [L, H] ...\n"
           "  SCENE: a manifest with BTF materials (default assets/scenes/demo-btf.json).\n"
           "  --size WxH        (default 1280x720)\n"
           "  --camera NAME     (default: the scene's first)\n"
           "  --pairs N         timed pairs (default 30)\n"
           "  --warmup N        untimed frames per renderer first (default 2)\n"
           "  --only V          btf | analytic: render --pairs frames of one variant, untimed (for callgrind)\n"
           "No GI light maps; the default quality preset.\n");
}

/* Each BTF material of s becomes the analytic material of its file's fitted average (errors name the
 * material when its file has none). */
static bool to_analytic(prw_scene *s, prw_error *e)
{
    for (uint32_t i = 0; i < s->material_count; i++) {
        prw_material *m = &s->materials[i];
        if (m->kind != PRW_MATERIAL_BTF) continue;
        prw_btf_packed p;
        if (!prw_btf_packed_read(m->btf_file, &p, e)) return false;
        bool has = p.has_average;
        prw_btf_average a = p.average;
        prw_btf_packed_free(&p);
        if (!has) return prw_fail(e, "%s: material '%s': %s has no fitted average", s->source, m->name, m->btf_file);
        m->kind = PRW_MATERIAL_GLTF_MR;
        memcpy(m->base_color, (float[4]){a.base[0], a.base[1], a.base[2], 1.0f}, sizeof m->base_color);
        m->metallic = a.metallic, m->roughness = a.roughness, m->specular = a.specular;
    }
    return true;
}

/* The coverage variant: BTF materials emit 1 cd/m^2, everything else is black (no reflection). */
static void to_mask(prw_scene *s)
{
    for (uint32_t i = 0; i < s->material_count; i++) {
        prw_material *m = &s->materials[i];
        bool btf = m->kind == PRW_MATERIAL_BTF;
        m->kind = PRW_MATERIAL_GLTF_MR;
        memset(m->base_color, 0, 3 * sizeof(float));
        m->base_color_tex = m->metal_rough_tex = m->emissive_tex = -1;
        m->metallic = 0, m->specular = 0, m->clearcoat = 0;
        m->emission[0] = m->emission[1] = m->emission[2] = btf ? 1.0f : 0.0f;
    }
}

static bool timed(prw_renderer *r, const prw_view *v, double *ms, prw_error *e)
{
    double t0 = prw_now();
    if (!prw_renderer_render(r, v, 1, NULL, e)) return false;
    *ms = (prw_now() - t0) * 1000.0;
    return true;
}

/* Share of the pixels whose HDR luminance is >= 0.5 in the coverage variant. */
static bool coverage(prw_gpu *gpu, const prw_scene *s, const prw_render_desc *rd, const prw_view *v, double *share,
                     prw_error *e)
{
    prw_renderer *r = NULL;
    prw_image img = {0};
    bool ok = prw_renderer_create(gpu, s, rd, &r, e) && prw_renderer_render(r, v, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, &img, e);
    if (ok) {
        const float *p = img.rgba;
        size_t n = (size_t)img.width * (size_t)img.height, c = 0;
        for (size_t i = 0; i < n; i++) c += 0.2126f * p[4 * i] + 0.7152f * p[4 * i + 1] + 0.0722f * p[4 * i + 2] >= 0.5f;
        *share = (double)c / (double)n;
    }
    prw_image_free(&img);
    prw_renderer_destroy(r);
    return ok;
}

int prw_cmd_btf_bench(int argc, char **argv)
{
    prw_error e = {0};
    prw_args a;
    if (!prw_args_init(&a, argc, argv, &e)) return fprintf(stderr, "prw btf-bench: error: %s\n", e.msg), 2;
    if (prw_args_flag(&a, "help")) {
        help();
        prw_args_free(&a);
        return 0;
    }
    bool bad = false;
    const char *size = prw_args_value(&a, "size", &e, &bad), *camera = prw_args_value(&a, "camera", &e, &bad);
    const char *pairs_s = prw_args_value(&a, "pairs", &e, &bad), *warm_s = prw_args_value(&a, "warmup", &e, &bad);
    const char *only = prw_args_value(&a, "only", &e, &bad);
    uint32_t w = 1280, h = 720;
    long pairs = 30, warm = 2;
    if (!bad && size && !prw_parse_size(size, &w, &h, &e)) bad = true;
    if (!bad && pairs_s && !prw_parse_int(pairs_s, "--pairs", 1, 100000, &pairs, &e)) bad = true;
    if (!bad && warm_s && !prw_parse_int(warm_s, "--warmup", 0, 1000, &warm, &e)) bad = true;
    if (!bad && only && strcmp(only, "btf") != 0 && strcmp(only, "analytic") != 0)
        bad = true, prw_fail(&e, "--only '%s': expected btf or analytic", only);
    if (!bad && a.positional_count > 1) bad = true, prw_fail(&e, "btf-bench: one scene at most");
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    const char *path = a.positional_count ? a.positional[0] : "assets/scenes/demo-btf.json";
    prw_args_free(&a);
    if (bad) return fprintf(stderr, "prw btf-bench: error: %s\n", e.msg), 2;

    prw_scene *sb = NULL, *sa = NULL, *sm = NULL;
    prw_gpu *gpu = NULL;
    prw_renderer *rb = NULL, *ra = NULL;
    double *tb = prw_calloc((size_t)pairs, sizeof *tb), *ta = prw_calloc((size_t)pairs, sizeof *ta);
    int rc = 1;
    uint32_t nbtf = 0;
    if (!prw_app_load_renderable(path, &sb, &e)) goto done;
    for (uint32_t i = 0; i < sb->material_count; i++) nbtf += sb->materials[i].kind == PRW_MATERIAL_BTF;
    if (!nbtf) {
        prw_fail(&e, "%s: no BTF material", sb->source);
        goto done;
    }
    prw_log_level lvl = prw_log_get_level(); /* the two copies: the loader's notes once is enough */
    if (lvl > PRW_LOG_WARN) prw_log_set_level(PRW_LOG_WARN);
    bool loaded = prw_app_load_renderable(path, &sa, &e) && prw_app_load_renderable(path, &sm, &e);
    prw_log_set_level(lvl);
    if (!loaded) goto done;
    if (!to_analytic(sa, &e)) goto done;
    to_mask(sm);
    int cam = prw_scene_find_camera(sb, camera);
    if (cam < 0) {
        prw_fail(&e, "%s: no camera named '%s'", sb->source, camera ? camera : "(first)");
        goto done;
    }
    prw_view v;
    if (!prw_view_from_camera(sb, cam, w, h, &v, &e) || !prw_app_bake_scene(sb, &e) || !prw_app_bake_scene(sa, &e) ||
        !prw_app_bake_scene(sm, &e) || !prw_app_create_gpu(false, &gpu, &e))
        goto done;
    prw_render_desc rd = {.width = w, .height = h};
    if (only) {
        bool btf = strcmp(only, "btf") == 0;
        if (!prw_renderer_create(gpu, btf ? sb : sa, &rd, &rb, &e)) goto done;
        double t0 = prw_now();
        for (long i = 0; i < pairs; i++)
            if (!prw_renderer_render(rb, &v, 1, NULL, &e)) goto done;
        printf("btf-bench: %ld frames of the %s variant at %ux%u, %.1f ms per frame (pipeline JIT included)\n", pairs,
               only, w, h, (prw_now() - t0) * 1000.0 / (double)pairs);
        rc = 0;
        goto done;
    }
    double share = 0;
    if (!coverage(gpu, sm, &rd, &v, &share, &e)) goto done;
    if (!prw_renderer_create(gpu, sb, &rd, &rb, &e) || !prw_renderer_create(gpu, sa, &rd, &ra, &e)) goto done;
    for (long i = 0; i < warm; i++)
        if (!prw_renderer_render(rb, &v, 1, NULL, &e) || !prw_renderer_render(ra, &v, 1, NULL, &e)) goto done;
    for (long i = 0; i < pairs; i++) {
        bool ok = i % 2 == 0 ? timed(rb, &v, &tb[i], &e) && timed(ra, &v, &ta[i], &e)
                             : timed(ra, &v, &ta[i], &e) && timed(rb, &v, &tb[i], &e);
        if (!ok) goto done;
        fprintf(stderr, "\rbtf-bench: %ld/%ld pairs   ", i + 1, pairs);
        fflush(stderr);
    }
    fprintf(stderr, "\n");
    prw_stats_ratio r;
    if (!prw_stats_bootstrap_pair_ratio(ta, tb, (size_t)pairs, BB_RESAMPLES, BB_SEED, &r)) {
        prw_fail(&e, "btf-bench: no ratio (zero frame times)");
        goto done;
    }
    if (prw_gpu_validation_count(gpu) != 0) {
        prw_fail(&e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
        goto done;
    }
    printf("btf-bench: BTF / analytic = %.3f (median of pair ratios), 95 %% interval [%.3f, %.3f]; median frame "
           "BTF %.1f ms, analytic %.1f ms; %ld interleaved pairs at %ux%u, camera '%s'; BTF on %.1f %% of the pixels "
           "(%u BTF materials); bootstrap over pairs, %d resamples, seed %d\n",
           r.ratio, r.lo, r.hi, prw_stats_median(tb, (size_t)pairs), prw_stats_median(ta, (size_t)pairs), pairs, w, h,
           sb->cameras[cam].name, 100.0 * share, nbtf, BB_RESAMPLES, BB_SEED);
    rc = 0;
done:
    if (rc) fprintf(stderr, "prw btf-bench: error: %s\n", e.msg);
    prw_renderer_destroy(rb);
    prw_renderer_destroy(ra);
    if (gpu) prw_gpu_destroy(gpu);
    prw_scene_destroy(sb);
    prw_scene_destroy(sa);
    prw_scene_destroy(sm);
    free(tb);
    free(ta);
    return rc;
}
