/* Planar mirrors (issue 16, must-shows 3 and 6): the mirror term of pass_mirror against the path
 * tracer, on assets/scenes/gi-room.json (its mirror: metallic 1, roughness 0, on the back wall),
 * 128x72, 4x MSAA, shadow map 2048, validation layer on, with the light maps of a reduced bake made by
 * the test (term_bake: radiosity_size 64, 32 samples) in the base pass and in the mirror image.
 *
 * The term: raster(mirror_recursion=1) - raster(mirror_recursion=0), i.e. what the passes add, with the
 * default quality (glossy_max_roughness 0.3, max_reflectors 2): the view sees the glossy floor too, which
 * the reflector estimate ranks first, so the mirror is reflected only because two reflectors are (with
 * max_reflectors=1 the mirror's term is 0 and the criteria fail).  Which reference filter is the same
 * term (DESIGN.md §4, prw_reference.h): the mirror's pixels see k >= 2 paths only through its specular
 * lobe (metallic 1: the diffuse share is 0), so there indirect-glossy-last = indirect (k >= 2); k = 1 (a
 * light seen in the mirror) is the direct term's, which is why the mirror image leaves emission out.  The
 * mirror image holds, at the reflected surfaces, emission-free direct light (the k = 2 paths) plus the
 * light maps' indirect diffuse (the k >= 3 paths whose vertex after the mirror scatters diffusely): the
 * filter is `indirect-glossy-last` over the mirror's pixels.  What the term still leaves out of it: the
 * k >= 3 paths through the reflected surfaces' specular lobes (mirror_recursion 1: the glossy floor's
 * own reflection as seen in the mirror, and the reflected surfaces' specular lobe under indirect light),
 * a small part here.
 * Control (GI in the mirror off): the same term from frames without light maps (the passes' addition
 * does not depend on the base pass's light maps, so this is the mirror image without its indirect
 * diffuse, the state before the light maps reached the mirror) must fail the criteria.
 *
 * Mirror pixels: the pixels whose four corners' rays all hit the mirror quad with nothing in front of it
 * (the camera is chosen so nothing stands between it and the mirror; the rays are cast analytically
 * against the quad of the manifest).  The camera "mirror view" faces the mirror from 3 m so that the
 * mirror shows the window-lit part of the room (camera main sees in the mirror mostly the window
 * wall, which direct light does not reach: its term is nearly 0 in the rasterizer today).
 *
 * Criteria over the mirror pixels (issue: <= 0.05 each): relMSE beyond the reference noise (seed 2
 * against seed 1) and LDR-FLIP beyond noise, on the metric tone map at the term's own exposure (the
 * EV100 mapping the reference term's mean luminance over the mirror pixels to 0.18).  Without the pass
 * (the term is 0) the same criteria must fail.
 * Outside the mirror's pixels the passes change only the floor's (the rays of the pixel's corners hitting
 * the floor quad), and they do change the floor (its reflection is added in the same frame).
 * Case finite: no NaN/Inf in the frame with the camera in the mirror's plane, the mirror seen edge-on
 * from 1e-6 m in front of its plane, and at grazing angles; with the floor a reflector (default quality)
 * and without it (glossy_max_roughness 0: then the mirror pass runs or is skipped for the mirror alone,
 * which the case checks), the latter with the mirror images at 1/8 of the view's size (mirror_scale).
 *
 * Environment: PRW_MIR_SPP (default 96) reference samples per pixel; PRW_MIR_OUT=DIR writes the
 * images (EXR) for `prw compare`.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lightmaps.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_ref.h"
#include "prw_test_gpu.h"
#include "term_error.h"

#define W 128u
#define H 72u
#define BOUND 0.05
#define PI 3.14159265358979323846

/* the gi-room mirror quad (assets/scenes/gi-room.json) */
static const double MIR_C[3] = {1.7, 1.5, -2.499}, MIR_HU = 0.8, MIR_HV = 0.8;
/* its floor quad: y = 0.001 over the room, |x| < 3, |z| < 2.5 */
static const double FLOOR_Y = 0.001, FLOOR_HX = 3.0, FLOOR_HZ = 2.5;

static prw_scene *load_room(prw_error *e)
{
    prw_scene *s = prw_scene_create();
    if (!s || !prw_scene_load_manifest(s, PRW_SOURCE_DIR "/assets/scenes/gi-room.json", e)) {
        if (s) prw_scene_destroy(s);
        return NULL;
    }
    prw_scene_update(s);
    return s;
}

/* The n views v[] (one size) rendered in turn by one renderer into hdr[]; status[k] (status may be NULL):
 * "ran" or the mirror pass's reason for skipping in view k.  skip: the knob reflection_skip, or < 0 for
 * the default; scale: the knob mirror_scale (0: the default). */
static bool render_views_scaled(const prw_scene *s, const prw_view *v, size_t n, const prw_lightmaps *lm,
                                uint32_t recursion, bool floor_too, double skip, double scale, prw_image *hdr,
                                char (*status)[96], prw_error *e)
{
    prw_render_desc rd = {.width = v[0].width, .height = v[0].height, .quality = prw_quality_default(), .lightmaps = lm};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 2048;
    rd.quality.mirror_recursion = recursion;
    if (!floor_too) rd.quality.glossy_max_roughness = 0; /* the mirror alone */
    if (skip >= 0) rd.quality.reflection_skip = skip;
    if (scale > 0) rd.quality.mirror_scale = scale;
    prw_frame_stats *st = prw_calloc(n, sizeof *st);
    bool ok = prw_test_render(s, &rd, v, n, hdr, st, e);
    for (size_t k = 0; ok && status && k < n; k++) {
        snprintf(status[k], 96, "not in the frame");
        for (uint32_t p = 0; p < st[k].pass_count; p++)
            if (st[k].passes[p].name && strcmp(st[k].passes[p].name, "mirror") == 0)
                snprintf(status[k], 96, "%s", st[k].passes[p].skipped ? st[k].passes[p].reason : "ran");
    }
    free(st);
    return ok;
}

static bool render_views(const prw_scene *s, const prw_view *v, size_t n, const prw_lightmaps *lm, uint32_t recursion,
                         bool floor_too, double skip, prw_image *hdr, char (*status)[96], prw_error *e)
{
    return render_views_scaled(s, v, n, lm, recursion, floor_too, skip, 0, hdr, status, e);
}

static bool render_raster(const prw_scene *s, const prw_view *v, const prw_lightmaps *lm, uint32_t recursion,
                          bool floor_too, prw_image *hdr, char *status, prw_error *e)
{
    return render_views(s, v, 1, lm, recursion, floor_too, -1, hdr, (char(*)[96])status, e);
}

/* The reference at the mask's pixels (the only ones the test reads; prw_test_ref.h: bit-identical there
 * to a whole-image render, NaN elsewhere), or at every pixel when PRW_MIR_OUT asks for the images. */
static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t spp, uint64_t seed, prw_ref_filter f,
                       const unsigned char *mask, prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = f};
    const char *dir = getenv("PRW_MIR_OUT");
    return prw_test_ref_pixels(ref, v, &d, dir && *dir ? NULL : mask, out, NULL, e);
}

/* The ray direction from the eye through image point (x, y) (pixels, y down). */
static prw_dvec3 ray_dir(const prw_view *v, prw_dvec3 f, prw_dvec3 r, prw_dvec3 u, double x, double y)
{
    double tx = v->tan_left + (v->tan_right - v->tan_left) * x / v->width;
    double ty = v->tan_top - (v->tan_top - v->tan_bottom) * y / v->height;
    return prw_v3_add(f, prw_v3_add(prw_v3_scale(r, tx), prw_v3_scale(u, ty)));
}

/* Whether the ray through image point (x, y) hits the floor quad (occluders not considered). */
static bool hits_floor(const prw_view *v, prw_dvec3 f, prw_dvec3 r, prw_dvec3 u, double x, double y)
{
    prw_dvec3 d = ray_dir(v, f, r, u, x, y);
    if (d.y > -1e-12) return false;
    double t = (FLOOR_Y - v->eye.y) / d.y;
    return fabs(v->eye.x + t * d.x) < FLOOR_HX && fabs(v->eye.z + t * d.z) < FLOOR_HZ;
}

/* Whether the ray through image point (x, y) hits the mirror quad. */
static bool hits_mirror(const prw_view *v, prw_dvec3 f, prw_dvec3 r, prw_dvec3 u, double x, double y)
{
    prw_dvec3 d = ray_dir(v, f, r, u, x, y);
    if (fabs(d.z) < 1e-12) return false;
    double t = (MIR_C[2] - v->eye.z) / d.z;
    if (t <= 0) return false;
    double px = v->eye.x + t * d.x - MIR_C[0], py = v->eye.y + t * d.y - MIR_C[1];
    return fabs(px) < MIR_HU && fabs(py) < MIR_HV;
}

static size_t mirror_mask(const prw_view *v, prw_dvec3 target, unsigned char *mask)
{
    prw_dvec3 f = prw_v3_norm(prw_v3_sub(target, v->eye));
    prw_dvec3 r = prw_v3_norm(prw_v3_cross(f, prw_v3(0, 1, 0)));
    prw_dvec3 u = prw_v3_cross(r, f);
    size_t n = 0;
    for (uint32_t j = 0; j < v->height; j++)
        for (uint32_t i = 0; i < v->width; i++) {
            bool in = true;
            for (int c = 0; c < 4 && in; c++) in = hits_mirror(v, f, r, u, i + (c & 1), j + (c >> 1));
            mask[j * v->width + i] = in;
            n += in;
        }
    return n;
}

/* mask[i] = 1 where a ray through one of pixel i's corners hits the floor quad */
static void floor_touch_mask(const prw_view *v, prw_dvec3 target, unsigned char *mask)
{
    prw_dvec3 f = prw_v3_norm(prw_v3_sub(target, v->eye));
    prw_dvec3 r = prw_v3_norm(prw_v3_cross(f, prw_v3(0, 1, 0)));
    prw_dvec3 u = prw_v3_cross(r, f);
    for (uint32_t j = 0; j < v->height; j++)
        for (uint32_t i = 0; i < v->width; i++) {
            bool any = false;
            for (int c = 0; c < 4 && !any; c++) any = hits_floor(v, f, r, u, i + (c & 1), j + (c >> 1));
            mask[j * v->width + i] = any;
        }
}

static void write_if(const char *name, const prw_image *im)
{
    const char *dir = getenv("PRW_MIR_OUT");
    if (!dir || !*dir) return;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.exr", dir, name);
    prw_error e;
    if (!prw_exr_write(path, im, NULL, 0, &e)) fprintf(stderr, "%s\n", e.msg);
    else printf("wrote %s\n", path);
}

/* The term of frames on and off (on - off, alpha 1); counts non-finite values of on. */
static size_t term_of(const prw_image *on, const prw_image *off, prw_image *term)
{
    prw_error e = {{0}};
    size_t nonfinite = 0;
    if (!prw_image_alloc(term, W, H, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        exit(1);
    }
    for (size_t i = 0; i < (size_t)W * H * 4; i++) {
        if (!isfinite(on->rgba[i])) nonfinite++;
        term->rgba[i] = (i & 3) == 3 ? 1.0f : on->rgba[i] - off->rgba[i];
    }
    return nonfinite;
}

static void test_term(void)
{
    prw_error e = {{0}};
    prw_scene *s = load_room(&e);
    CHECK_MSG(s != NULL, "%s", e.msg);
    prw_dvec3 eye = prw_v3(1.7, 1.5, 0.5), target = prw_v3(1.7, 1.35, -2.5);
    prw_view v = prw_view_look_at(eye, target, prw_v3(0, 1, 0), 60.0 * PI / 180.0, 0.05, W, H, 7.0);
    unsigned char *mask = calloc((size_t)W * H, 1);
    CHECK(mask != NULL);
    size_t nm = mirror_mask(&v, target, mask);
    CHECK_MSG(nm > 500, "%zu mirror pixels", nm);
    unsigned char *fmask = calloc((size_t)W * H, 1);
    CHECK(fmask != NULL);
    floor_touch_mask(&v, target, fmask);

    prw_app_lightmaps *lms = NULL;
    term_bake(s, 64, 32, &lms);
    const prw_lightmaps *lm = prw_app_lightmaps_get(lms);
    prw_image on = {0}, off = {0}, term = {0}, on0 = {0}, off0 = {0}, term0 = {0};
    char status[96];
    CHECK_OK(render_raster(s, &v, lm, 1, true, &on, status, &e), &e);
    CHECK_MSG(strcmp(status, "ran") == 0, "mirror pass: %s", status);
    CHECK_OK(render_raster(s, &v, lm, 0, true, &off, NULL, &e), &e);
    CHECK_OK(render_raster(s, &v, NULL, 1, true, &on0, NULL, &e), &e); /* the control: no light maps */
    CHECK_OK(render_raster(s, &v, NULL, 0, true, &off0, NULL, &e), &e);
    size_t nonfinite = term_of(&on, &off, &term) + term_of(&on0, &off0, &term0);
    size_t outside = 0, nfloor = 0, floor_lit = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        /* the passes add only in the reflectors' pixels (their G-buffer ids): elsewhere the frames agree
         * (the edge pixels of the mirror quad, partly covered, are outside the mask but may differ) */
        bool near_mask = false;
        uint32_t x = (uint32_t)(i % W), y = (uint32_t)(i / W);
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int xx = (int)x + dx, yy = (int)y + dy;
                if (xx >= 0 && yy >= 0 && xx < (int)W && yy < (int)H && mask[yy * W + xx]) near_mask = true;
            }
        if (!near_mask && !fmask[i])
            for (int c = 0; c < 3; c++) outside += term.rgba[4 * i + c] != 0.0f;
        if (!near_mask && fmask[i]) {
            nfloor++;
            floor_lit += term.rgba[4 * i] + term.rgba[4 * i + 1] + term.rgba[4 * i + 2] > 0.0f;
        }
    }
    printf("floor pixels (a corner's ray on the floor quad) %zu, of which the passes brightened %zu\n", nfloor,
           floor_lit);
    CHECK_MSG(nonfinite == 0, "%zu non-finite values", nonfinite);
    CHECK_MSG(outside == 0, "the mirror passes changed %zu values away from the mirror and the floor", outside);
    CHECK_MSG(nfloor > 200 && floor_lit * 4 > nfloor, "the floor's reflection is missing: %zu of %zu floor pixels",
              floor_lit, nfloor);

    const char *spp_env = getenv("PRW_MIR_SPP");
    uint64_t spp = spp_env ? strtoull(spp_env, NULL, 10) : 96;
    if (spp < 1) spp = 1;
    if (prw_test_light() && spp > 32) spp = 32;
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &ref, &e), &e);
    prw_image r1 = {0}, r2 = {0};
    prw_ref_filter igl = {.kind = PRW_REF_INDIRECT_GLOSSY_LAST};
    CHECK_OK(render_ref(ref, &v, spp, 1, igl, mask, &r1, &e), &e);
    CHECK_OK(render_ref(ref, &v, spp, 2, igl, mask, &r2, &e), &e);
    prw_ref_destroy(ref);
    write_if("raster_on", &on), write_if("raster_off", &off), write_if("term", &term), write_if("term_no_gi", &term0);
    write_if("ref_igl_s1", &r1), write_if("ref_igl_s2", &r2);

    /* the term's own exposure: its mean luminance over the mirror -> 0.18 */
    double lum = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        if (mask[i]) lum += 0.2126 * r1.rgba[4 * i] + 0.7152 * r1.rgba[4 * i + 1] + 0.0722 * r1.rgba[4 * i + 2];
    lum /= (double)nm;
    CHECK_MSG(lum > 0, "reference mirror term mean luminance %g", lum);
    double ev = log2(lum / (0.18 * 1.2));
    double mt[3] = {0, 0, 0}, m0[3] = {0, 0, 0}, mr[3] = {0, 0, 0};
    for (size_t i = 0; i < (size_t)W * H; i++)
        if (mask[i])
            for (int c = 0; c < 3; c++)
                mt[c] += term.rgba[4 * i + c], m0[c] += term0.rgba[4 * i + c], mr[c] += r1.rgba[4 * i + c];
    term_err err, noise, none, nogi;
    masked_error(&term, &r1, mask, ev, &err);
    masked_error(&r2, &r1, mask, ev, &noise);
    masked_error(&term0, &r1, mask, ev, &nogi);
    prw_image zero = {0};
    CHECK_OK(prw_image_alloc(&zero, W, H, &e), &e);
    memset(zero.rgba, 0, (size_t)W * H * 4 * sizeof(float));
    masked_error(&zero, &r1, mask, ev, &none);
    printf("gi-room, camera 'mirror view' (1.7, 1.5, 0.5) -> (1.7, 1.35, -2.5), %ux%u, 4x MSAA, shadow map 2048, "
           "%zu mirror pixels, reference indirect-glossy-last %llu spp, term exposure EV100 %.3f:\n",
           W, H, nm, (unsigned long long)spp, ev);
    printf("  mean over the mirror, raster term (%.4g %.4g %.4g), without GI in the mirror (%.4g %.4g %.4g), "
           "reference (%.4g %.4g %.4g) cd/m^2\n",
           mt[0] / nm, mt[1] / nm, mt[2] / nm, m0[0] / nm, m0[1] / nm, m0[2] / nm, mr[0] / nm, mr[1] / nm, mr[2] / nm);
    printf("  relMSE   raster %.4f, reference noise %.4f, beyond noise %.4f (limit %.2f)\n", err.relmse, noise.relmse,
           err.relmse - noise.relmse, BOUND);
    printf("  LDR-FLIP raster %.4f, reference noise %.4f, beyond noise %.4f (limit %.2f)\n", err.flip, noise.flip,
           err.flip - noise.flip, BOUND);
    printf("  without GI in the mirror image (control, must fail): relMSE %.4f, LDR-FLIP %.4f beyond noise\n",
           nogi.relmse - noise.relmse, nogi.flip - noise.flip);
    printf("  without the pass (must fail): relMSE %.4f, LDR-FLIP %.4f beyond noise\n", none.relmse - noise.relmse,
           none.flip - noise.flip);
    if (prw_test_light()) { /* sanitizers: a tiny bake and references; the bounds are not checked */
        printf("  light mode: only the controls are checked\n");
        CHECK_MSG(nogi.flip > err.flip && none.flip > err.flip, "the controls are not worse than the term");
    } else {
        CHECK_MSG(err.relmse - noise.relmse <= BOUND, "relMSE beyond noise %.4f", err.relmse - noise.relmse);
        CHECK_MSG(err.flip - noise.flip <= BOUND, "LDR-FLIP beyond noise %.4f", err.flip - noise.flip);
        CHECK_MSG(nogi.relmse - noise.relmse > BOUND || nogi.flip - noise.flip > BOUND,
                  "the criteria pass without GI in the mirror image: they cannot tell");
        CHECK_MSG(none.relmse - noise.relmse > BOUND || none.flip - noise.flip > BOUND,
                  "the criteria pass without the mirror pass: they cannot tell");
    }
    prw_image_free(&on), prw_image_free(&off), prw_image_free(&term), prw_image_free(&zero);
    prw_image_free(&on0), prw_image_free(&off0), prw_image_free(&term0);
    prw_image_free(&r1), prw_image_free(&r2);
    free(mask), free(fmask);
    prw_app_lightmaps_destroy(lms);
    prw_scene_destroy(s);
}

/* Degenerate views of the mirror: every value of the frame finite; and the views where the pass must
 * be skipped (needed() false) say so. */
static void test_finite(void)
{
    prw_error e = {{0}};
    prw_scene *s = load_room(&e);
    CHECK_MSG(s != NULL, "%s", e.msg);
    const double z = MIR_C[2];
    struct {
        const char *what;
        prw_dvec3 eye, target;
        int runs; /* 1: the mirror pass must run, 0: must be skipped, -1: either */
    } cases[] = {
        {"eye in the mirror's plane, looking along it", prw_v3(0.5, 1.5, z), prw_v3(2.5, 1.5, z), 0},
        {"eye in the mirror's plane, on the mirror", prw_v3(1.7, 1.5, z), prw_v3(1.7, 1.5, 2.0), 0},
        {"edge-on from 1e-6 m in front", prw_v3(0.5, 1.5, z + 1e-6), prw_v3(2.5, 1.5, z + 1e-6), -1},
        {"1 mm in front, looking across it", prw_v3(1.0, 1.5, z + 1e-3), prw_v3(3.0, 1.5, z - 0.5), 1},
        {"grazing, 1 degree", prw_v3(-2.5, 1.5, z + 5.0 * tan(PI / 180.0)), prw_v3(2.5, 1.5, z), -1},
        {"grazing, 10 degrees", prw_v3(-2.5, 1.5, z + 5.0 * tan(10.0 * PI / 180.0)), prw_v3(2.5, 1.5, z), 1},
        {"close up, facing it", prw_v3(1.7, 1.5, z + 0.06), prw_v3(1.7, 1.5, z), 1},
        {"mirror behind the camera", prw_v3(1.7, 1.5, 0.5), prw_v3(1.7, 1.5, 2.5), 0},
        {"mirror outside the frustum", prw_v3(-2.6, 1.5, 2.2), prw_v3(-3.0, 1.0, 0.0), 0},
        {"mirror seen from its back", prw_v3(1.7, 1.5, -2.6), prw_v3(1.7, 1.5, 2.0), 0},
    };
    enum { N = PRW_ARRAY_LEN(cases) };
    prw_view v[N];
    for (size_t k = 0; k < N; k++)
        v[k] = prw_view_look_at(cases[k].eye, cases[k].target, prw_v3(0, 1, 0), 60.0 * PI / 180.0, 0.05, 64, 36, 7.0);
    for (int config = 0; config < 2; config++) { /* one renderer for every view; 1: mirror images at 1/8 */
        bool floor_too = config > 0;
        prw_image on[N];
        char status[N][96];
        memset(on, 0, sizeof on);
        CHECK_OK(render_views_scaled(s, v, N, NULL, 1, floor_too, -1, config == 1 ? 0.125 : 0, on, status, &e), &e);
        for (size_t ci = 0; ci < N; ci++) {
            size_t bad = 0;
            for (size_t i = 0; i < (size_t)64 * 36 * 4; i++) bad += !isfinite(on[ci].rgba[i]);
            printf("%-44s %-7s mirror pass: %-40s %zu non-finite values\n", cases[ci].what,
                   floor_too ? "+fl 1/8" : "mirror", status[ci], bad);
            bool ran = strcmp(status[ci], "ran") == 0;
            /* with the floor a reflector too, the pass also runs for the floor: only "must run" holds */
            CHECK_MSG(cases[ci].runs < 0 || (floor_too ? !(cases[ci].runs == 1) || ran : ran == (cases[ci].runs == 1)),
                      "%s: mirror pass %s", cases[ci].what, status[ci]);
            CHECK_MSG(bad == 0, "%s: %zu non-finite values", cases[ci].what, bad);
            prw_image_free(&on[ci]);
        }
    }
    prw_scene_destroy(s);
}

static double lum4(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

/* The skip rule (knob reflection_skip, pass_mirror.c reflection_share): gi-room with a white glossy floor
 * (base 0.9, roughness 0.2) and the wall mirror made matte (not a reflector), seen from above (fov 40
 * degrees, every visible floor point within ~37 degrees of the normal: dielectric F <= 0.046, so the
 * estimated reflection 0.046 x 0.79 (gold) / (0.954 x 0.9) is below 5 %), with the light maps of a small
 * bake: the mirror passes are skipped by default, run with reflection_skip=0, run by default at a grazing
 * view (camera main: F near 1 at the far floor) and without light maps (the rule is off then).  A diffuse-only room (every specular 0, metallic 0) has no reflector: the passes are out of
 * the graph.  Every frame finite. */
static void test_skip(void)
{
    prw_error e = {{0}};
    prw_scene *s = load_room(&e);
    CHECK_MSG(s != NULL, "%s", e.msg);
    for (uint32_t k = 0; k < s->material_count; k++) {
        prw_material *m = &s->materials[k];
        if (strcmp(m->name, "oak floor") == 0)
            for (int c = 0; c < 3; c++) m->base_color[c] = 0.9f;
        if (strcmp(m->name, "mirror") == 0) {
            m->metallic = 0, m->roughness = 0.9f;
            for (int c = 0; c < 3; c++) m->base_color[c] = 0.5f;
        }
    }
    prw_scene_update(s);
    prw_view top = prw_view_look_at(prw_v3(0.5, 2.9, 1.0), prw_v3(0.5, 0.0, 1.0), prw_v3(0, 0, -1), 40.0 * PI / 180.0,
                                    0.05, 64, 36, 7.0);
    prw_view main_v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", 64, 36, &main_v, &e), &e);
    /* a small bake of this room (the rule needs light maps; their detail does not change the decision) */
    prw_gi_options o = {.radiosity_size = 16, .samples = 4, .seed = 7, .filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS};
    prw_gi_bake *b = NULL;
    prw_gi_result gr;
    CHECK_OK(prw_gi_run(s, &o, true, NULL, NULL, &b, &gr, &e), &e);
    prw_app_lightmaps *lms = NULL;
    CHECK_OK(prw_app_lightmaps_from_bake(s, b, &lms, &e), &e);
    const prw_lightmaps *lm = prw_app_lightmaps_get(lms);
    struct {
        const char *what;
        const prw_view *v;
        const prw_lightmaps *lm;
        double skip;
        bool runs;
    } cases[] = {
        {"from above, default (0.05)", &top, lm, -1, false},
        {"from above, reflection_skip=0", &top, lm, 0, true},
        {"camera main (grazing), default", &main_v, lm, -1, true},
        {"from above, no light maps, default", &top, NULL, -1, true},
    };
    enum { NC = PRW_ARRAY_LEN(cases) };
    prw_image im[NC];
    memset(im, 0, sizeof im);
    for (size_t k = 0; k < NC; k++) {
        char status[1][96];
        CHECK_OK(render_views(s, cases[k].v, 1, cases[k].lm, 1, true, cases[k].skip, &im[k], status, &e), &e);
        size_t bad = 0;
        for (size_t i = 0; i < (size_t)im[k].width * im[k].height * 4; i++) bad += !isfinite(im[k].rgba[i]);
        printf("white glossy floor, %-36s mirror pass: %s\n", cases[k].what, status[0]);
        CHECK_MSG((strcmp(status[0], "ran") == 0) == cases[k].runs, "%s: mirror pass %s", cases[k].what, status[0]);
        CHECK_MSG(bad == 0, "%s: %zu non-finite values", cases[k].what, bad);
    }
    /* for information: the share the skipped reflection really had here */
    double sum = 0, most = 0;
    size_t nd = 0, over = 0;
    for (size_t i = 0; i < (size_t)64 * 36; i++) {
        double a = lum4(&im[1].rgba[4 * i]), c = lum4(&im[0].rgba[4 * i]);
        if (a == c || !(c > 0)) continue;
        sum += (a - c) / c, most = fmax(most, (a - c) / c);
        over += (a - c) / c > 0.05;
        nd++;
    }
    printf("from above, the skipped reflection / the rest, over the %zu pixels it changes: mean %.4f, max %.4f, "
           "above 0.05 in %zu\n",
           nd, nd ? sum / (double)nd : 0.0, most, over);
    for (size_t k = 0; k < NC; k++) prw_image_free(&im[k]);
    prw_app_lightmaps_destroy(lms);
    prw_image diffuse = {0};
    for (uint32_t k = 0; k < s->material_count; k++) s->materials[k].specular = 0, s->materials[k].metallic = 0;
    prw_scene_update(s);
    char status[96];
    CHECK_OK(render_raster(s, &main_v, NULL, 1, true, &diffuse, status, &e), &e);
    printf("diffuse-only room, camera main: mirror pass: %s\n", status);
    CHECK_MSG(strcmp(status, "ran") != 0, "diffuse-only room: the mirror pass ran");
    prw_image_free(&diffuse);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"term", test_term}, {"finite", test_finite}, {"skip", test_skip}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
