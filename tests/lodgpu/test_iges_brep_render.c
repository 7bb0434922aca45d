/* IGES B-rep solids in the renderer against the path tracer (issue 14, must-show 2).
 *
 * The box, the cylinder and the trimmed free-form solid that tests/lod/iges_models.c writes as MSBO
 * (186) files are loaded through a manifest exactly as a user's file would be (units mm -> m),
 * SINGLE-SIDED, so a face whose orientation flag were ignored would be culled and the image would
 * show the background through the solid.  Each is lit by two directional lights (hard shadows in
 * both renderers) and seen from a camera framing its trimmed bounds.  The rasterizer (4x MSAA, its
 * LOD at the default ½ px, direct light only) is compared with the reference path tracer's direct
 * filter, as tests/render/test_raster_vs_ref.c does for the demo: two references with different
 * seeds give the reference's own noise and the raster must be within
 *   mean LDR-FLIP(raster, ref A) - mean LDR-FLIP(ref B, ref A) <= 0.03
 * (the bound test_lodgpu's flip_vs_finest puts on the NURBS LOD; FLIP at 67 ppd on the metric tone
 * map).  The solid must cover a good part of the image, and the raster's covered pixels must agree
 * with the reference's within 2 % (a culled face shows the black background through the solid).
 * Control: the box's raster image at twice its radiance exceeds the bound. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "iges_models.h"
#include "prw_bake_scene.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"

#define SIZE 128u
#define SPP ((uint64_t)prw_test_scale(32, 4)) /* light mode (sanitizers): 8; the bound is beyond the reference noise */
#define FLIP_BOUND 0.03

static prw_gpu *g_gpu;
static char g_dir[64];

static bool gpu_up(void)
{
    if (g_gpu) return true;
    prw_error e;
    prw_gpu_desc d = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&d, &g_gpu, &e)) {
        fprintf(stderr, "gpu: %s\n", e.msg);
        return false;
    }
    return true;
}

static bool write_file(const char *path, const char *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(data, 1, len, f) == len;
    return fclose(f) == 0 && ok;
}

/* The manifest around an IGES file: the model stood up (IGES z -> world y), single-sided, a grey
 * GGX material, two directional lights; `camera` is "" (none) or a "cameras" entry. */
static prw_scene *load(const char *igs, const char *camera, prw_error *e)
{
    char text[4096];
    snprintf(text, sizeof text,
             "{\"prw_manifest\": 1,\n"
             " \"materials\": [{\"name\": \"grey\", \"base_color\": [0.7, 0.7, 0.7], \"roughness\": 0.5}],\n"
             " \"nurbs\": [{\"name\": \"solid\", \"file\": \"%s\", \"material\": \"grey\", \"single_sided\": true,\n"
             "             \"rotation\": [-0.7071067811865476, 0, 0, 0.7071067811865476]}],\n"
             " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.3, -1, -0.5], \"intensity\": 1000},\n"
             "            {\"type\": \"directional\", \"direction\": [-0.9, -0.3, 0.2], \"intensity\": 300}]%s%s}\n",
             igs, camera[0] ? ",\n" : "", camera);
    prw_scene *s = prw_scene_create();
    if (!prw_scene_parse_manifest(s, text, strlen(text), "iges-brep-render.json", e)) {
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

/* The scene with a camera on the diagonal (+x, +y, +z) of the trimmed bounds, baked. */
static prw_scene *load_framed(const char *igs, prw_error *e)
{
    prw_scene *s = load(igs, "", e);
    if (!s) return NULL;
    prw_dvec3 lo = s->bounds_min, hi = s->bounds_max;
    prw_scene_destroy(s);
    prw_dvec3 c = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    double r = 0.5 * prw_v3_len(prw_v3_sub(hi, lo));
    prw_dvec3 dir = prw_v3_norm(prw_v3(0.55, 0.5, 0.75));
    prw_dvec3 eye = prw_v3_add(c, prw_v3_scale(dir, r / sin(0.5 * 40.0 * PRW_PI / 180.0) * 1.05));
    char cam[512];
    snprintf(cam, sizeof cam,
             " \"cameras\": [{\"name\": \"main\", \"position\": [%.17g, %.17g, %.17g], \"target\": [%.17g, %.17g, "
             "%.17g], \"yfov_deg\": 40, \"ev100\": 8}]",
             eye.x, eye.y, eye.z, c.x, c.y, c.z);
    s = load(igs, cam, e);
    if (s && !prw_bake_scene(s, NULL, NULL, e)) {
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

static bool render_raster(const prw_scene *s, const prw_view *v, prw_image *hdr, prw_error *e)
{
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = SIZE, .height = SIZE, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 2048;
    bool ok = prw_renderer_create(g_gpu, s, &rd, &r, e) && prw_renderer_render(r, v, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, hdr, e);
    prw_renderer_destroy(r);
    return ok;
}

static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t seed, prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = SPP, .seed = seed, .filter = {.kind = PRW_REF_DIRECT}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    bool ok = prw_ref_render(ref, v, &d, &acc, &st, e) && prw_ref_acc_images(&acc, &mean, &var, e) &&
              prw_image_alloc(out, SIZE, SIZE, e);
    if (ok) memcpy(out->rgba, mean, (size_t)SIZE * SIZE * 4 * sizeof(float));
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    return ok;
}

/* Pixels with any radiance (the background is black: no environment). */
static size_t covered(const prw_image *im)
{
    size_t n = 0;
    for (size_t i = 0; i < (size_t)im->width * im->height; i++)
        n += im->rgba[4 * i] + im->rgba[4 * i + 1] + im->rgba[4 * i + 2] > 0;
    return n;
}

static bool finite_image(const prw_image *im)
{
    for (size_t i = 0; i < (size_t)im->width * im->height * 4; i++)
        if (!isfinite(im->rgba[i])) return false;
    return true;
}

static double flip_mean(const prw_image *a, const prw_image *b, double ev100)
{
    prw_error e;
    prw_compare_opts o = {.ev100 = ev100};
    prw_compare_metrics m;
    if (!prw_compare_images(a, b, &o, &m, NULL, NULL, &e)) {
        CHECK_MSG(false, "compare: %s", e.msg);
        return 1;
    }
    return m.ldr_flip.mean;
}

/* Renders `igs` both ways; the raster image into *raster (caller frees) for the controls; the
 * reference A and the noise into *ref_a / *noise. */
static bool compare_model(const char *what, char *(*model)(size_t *), prw_image *raster, prw_image *ref_a, double *noise,
                          double *ev100, char *igs_path, size_t igs_cap)
{
    prw_error e = {{0}};
    size_t len = 0;
    char *data = model(&len);
    snprintf(igs_path, igs_cap, "%s/%s.igs", g_dir, what);
    CHECK(data && write_file(igs_path, data, len));
    free(data);
    prw_scene *s = load_framed(igs_path, &e);
    CHECK_MSG(s != NULL, "%s: %s", what, e.msg);
    if (!s) return false;
    prw_view v;
    if (!prw_ref_view_for_camera(s, "main", SIZE, SIZE, &v, &e)) {
        CHECK_MSG(false, "%s: %s", what, e.msg);
        prw_scene_destroy(s);
        return false;
    }
    *ev100 = v.ev100;
    prw_image rb = {0};
    prw_ref_renderer *ref = NULL;
    bool ok = render_raster(s, &v, raster, &e) && prw_ref_create(s, v.eye, 0, &ref, &e) &&
              render_ref(ref, &v, 1, ref_a, &e) && render_ref(ref, &v, 2, &rb, &e);
    prw_ref_destroy(ref);
    prw_scene_destroy(s);
    CHECK_MSG(ok, "%s: %s", what, e.msg);
    if (!ok) {
        prw_image_free(&rb);
        return false;
    }
    CHECK(finite_image(raster));
    *noise = flip_mean(&rb, ref_a, v.ev100);
    double err = flip_mean(raster, ref_a, v.ev100);
    size_t cr = covered(raster), cf = covered(ref_a);
    printf("%s: raster vs direct reference (%u spp) mean LDR-FLIP %.4f, reference noise %.4f, beyond noise %.4f "
           "(bound %.2f); covered pixels raster %zu, reference %zu\n",
           what, (unsigned)SPP, err, *noise, err - *noise, FLIP_BOUND, cr, cf);
    CHECK_MSG(err - *noise <= FLIP_BOUND, "%s: FLIP beyond noise %.4f > %.2f", what, err - *noise, FLIP_BOUND);
    CHECK(cf > SIZE * SIZE / 8);                   /* the solid fills a good part of the image */
    CHECK(fabs((double)cr - (double)cf) <= 0.02 * (double)cf); /* silhouettes: a few edge pixels */
    prw_image_free(&rb);
    return true;
}

static void test_box(void)
{
    if (!gpu_up()) {
        CHECK(false);
        return;
    }
    prw_image raster = {0}, ra = {0};
    double noise = 0, ev = 0;
    char path[256];
    if (compare_model("box", iges_model_brep_box, &raster, &ra, &noise, &ev, path, sizeof path)) {
        /* control 1: one stop too bright must fail the bound */
        prw_image wrong = {0};
        prw_error e;
        CHECK_OK(prw_image_alloc(&wrong, SIZE, SIZE, &e), &e);
        for (size_t i = 0; i < (size_t)SIZE * SIZE * 4; i++)
            wrong.rgba[i] = raster.rgba[i] * ((i & 3) == 3 ? 1.0f : 2.0f);
        double bad = flip_mean(&wrong, &ra, ev) - noise;
        printf("box control: raster x2 is %.4f beyond noise\n", bad);
        CHECK(bad > FLIP_BOUND);
        prw_image_free(&wrong);
    }
    prw_image_free(&raster);
    prw_image_free(&ra);
}

static void test_cylinder(void)
{
    if (!gpu_up()) {
        CHECK(false);
        return;
    }
    prw_image raster = {0}, ra = {0};
    double noise = 0, ev = 0;
    char path[256];
    compare_model("cylinder", iges_model_brep_cylinder, &raster, &ra, &noise, &ev, path, sizeof path);
    prw_image_free(&raster);
    prw_image_free(&ra);
}

static void test_freeform(void)
{
    if (!gpu_up()) {
        CHECK(false);
        return;
    }
    prw_image raster = {0}, ra = {0};
    double noise = 0, ev = 0;
    char path[256];
    compare_model("freeform", iges_model_brep_freeform, &raster, &ra, &noise, &ev, path, sizeof path);
    prw_image_free(&raster);
    prw_image_free(&ra);
}

int main(int argc, char **argv)
{
    snprintf(g_dir, sizeof g_dir, "/tmp/prw-brep-XXXXXX");
    if (!mkdtemp(g_dir)) {
        perror("mkdtemp");
        return 1;
    }
    static const prw_test_case cases[] = {
        {"box", test_box}, {"cylinder", test_cylinder}, {"freeform", test_freeform}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    if (g_gpu) {
        prw_gpu_destroy(g_gpu);
        uint32_t msgs = prw_gpu_validation_total();
        if (msgs) {
            fprintf(stderr, "%u validation messages\n", msgs);
            rc = 1;
        }
    }
    const char *names[] = {"box", "cylinder", "freeform"};
    for (int i = 0; i < 3; i++) {
        char p[128];
        snprintf(p, sizeof p, "%s/%s.igs", g_dir, names[i]);
        unlink(p);
    }
    rmdir(g_dir);
    return rc;
}
