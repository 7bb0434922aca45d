/* glTF material features drawn by the rasterizer and compared with the path tracer (issue "Real inputs
 * and hardening"): every case writes its own small .gltf (+ .bin + .png textures), imports it and
 * renders it at 96 x 64 with 4x MSAA against the reference's direct light (`--filter direct`).
 * Comparisons are noise-aware: means over regions of pixels classified by the reference's primary hits
 * (what is seen there), with a tolerance of a few per cent plus 4 sigma of the reference's own mean.
 *  - cutout:     an alpha-MASK panel (left half cut by its texture) over a floor under a sun: the floor
 *                seen through the cut, the light through the cut on the floor, the kept half's shadow;
 *                the same quad as BLEND with the same binary alpha gives the same image; control: OPAQUE.
 *  - transform:  KHR_texture_transform (offset, rotation, scale) on an emissive and on a lit base-colour
 *                texture, the latter read from TEXCOORD_1: each pixel in the middle of a texture block
 *                shows the block that prw_tex_transform_apply (engine/scene, not the shared rule)
 *                puts there, in both renderers; controls: the untransformed lookup does not, and the
 *                raster drawn without the transforms (same uv sets) is seen to be wrong.
 *  - normal_transform: a constant tilted normal map through a rotation / scale: the frame rule of a
 *                transformed normal map, quad means against the reference; control: no transform.
 *  - clearcoat:  clear-coated spheres under a point light, one with a transformed coat-weight texture and
 *                a coat normal map: region means (sphere, highlight, rest) and FLIP against the
 *                reference's noise; control: the raster spheres without their coat.
 *  - clearcoat_rect: the same spheres under a rect light (the coated rect-light terms): region means;
 *                control: the raster without the coats fails the same comparisons.
 *  - blend:      two BLEND quads drawn in the wrong order in the file, over an emissive wall: the
 *                "over" composite of each region (front only, back only, both) against the reference's
 *                stochastic transparency; control: the composite in the wrong order.
 *  - views_gbuffer: the MASK / BLEND panel in two-view frames: with stereo_reuse=reproject both eyes
 *                are shaded (bit-identical to mono renders; control: the OPAQUE panel is reprojected),
 *                with the multiview backend each eye's region means within 3 % of mono (not bit for bit:
 *                lavapipe's multiview defect, test_stereo_gpu.c; control: OPAQUE); G-buffer ids
 *                through the cut and over the kept half (control: OPAQUE shows the panel in both).
 *  - reproject_ext: the coated, transformed spheres with stereo_reuse=reproject (holes shaded by the
 *                extension shaders): right eye LDR-FLIP vs fully shaded <= 0.05; control: the left eye.
 *  - nurbs:      a NURBS box with MASK (kept / cut, with its shadow) and BLEND materials in front of a lit
 *                emissive wall, against closed forms within 0.5 %; control: OPAQUE judged as the cut MASK.
 * Environment: PRW_GLTFM_OUT=DIR writes each case's raster and reference EXRs there.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_bake_scene.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_strbuf.h"
#include "prw_test.h"
#include "gltf_writer.h"

#define W 96u
#define H 64u
/* Shadow maps of the stereo, G-buffer and reprojection cases: those compare frames of one renderer
 * configuration with each other (mono vs two-view, ids), so they do not need the 2048 texels of the
 * cases judged against the path tracer; lavapipe spends most of this test clearing and rasterizing
 * shadow maps. */
#define SHADOW_VIEWS 512u
#define SPP ((uint64_t)prw_test_scale(32, 4)) /* light mode (sanitizers): 8; the tolerances are noise-aware */

static prw_gpu *g_gpu;

/* ---- rendering ---- */

typedef struct images {
    prw_view v;
    prw_image raster;
    float *ref, *var;   /* reference mean and variance of the mean (rgba) */
    prw_ref_hit *hit;   /* per pixel centre: the reference's primary hit */
    bool *hit_ok;
} images;

static void images_free(images *im)
{
    prw_image_free(&im->raster);
    free(im->ref), free(im->var), free(im->hit), free(im->hit_ok);
    memset(im, 0, sizeof *im);
}

/* EXR and, for looking at, PNG through the metric tone map (white at 1.2 x 2^ev100 cd/m^2). */
static void write_one(const char *dir, const char *name, const prw_image *im, double ev100)
{
    char path[4096];
    prw_error e;
    snprintf(path, sizeof path, "%s/%s.exr", dir, name);
    if (!prw_exr_write(path, im, NULL, 0, &e)) fprintf(stderr, "%s\n", e.msg);
    prw_image tm = {0};
    if (!prw_metric_tonemap(im, ev100, &tm, &e)) return;
    uint8_t *px = prw_malloc((size_t)tm.width * tm.height * 3);
    for (size_t i = 0; i < (size_t)tm.width * tm.height; i++)
        for (int c = 0; c < 3; c++) {
            float v = tm.rgba[i * 4 + c];
            px[i * 3 + c] = (uint8_t)lrintf(255.0f * (v < 0 ? 0 : v > 1 ? 1 : v));
        }
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    if (!prw_png_write8(path, tm.width, tm.height, 3, px, &e)) fprintf(stderr, "%s\n", e.msg);
    free(px);
    prw_image_free(&tm);
}

static void write_out(const char *name, const images *im)
{
    const char *dir = getenv("PRW_GLTFM_OUT");
    if (!dir || !*dir) return;
    char n[256];
    snprintf(n, sizeof n, "%s_raster", name);
    write_one(dir, n, &im->raster, 1.0);
    if (!im->ref) return;
    prw_image r = {.width = (int)W, .height = (int)H, .rgba = im->ref};
    snprintf(n, sizeof n, "%s_ref", name);
    write_one(dir, n, &r, 1.0);
}

static bool load(const char *path, prw_scene **out, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    if (!prw_scene_import_gltf(s, path, -1, e)) {
        prw_scene_destroy(s);
        return false;
    }
    *out = s;
    return true;
}

/* Raster (4x MSAA, validation on; unless !raster) and reference (direct light, spp, seed; spp 0: none) of the
 * scene's camera. */
static bool render_both(const prw_scene *s, uint64_t seed, uint64_t spp, bool raster, images *im, prw_error *e)
{
    memset(im, 0, sizeof *im);
    if (!prw_ref_view_for_camera(s, NULL, W, H, &im->v, e)) return false;
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = W, .height = H, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 2048;
    bool ok = !raster || (prw_renderer_create(g_gpu, s, &rd, &r, e) && prw_renderer_render(r, &im->v, 1, NULL, e) &&
                          prw_renderer_read_hdr(r, 0, &im->raster, e));
    prw_renderer_destroy(r);
    if (!ok || !spp) return ok;
    prw_ref_renderer *ref = NULL;
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = PRW_REF_DIRECT}, .threads = 2};
    ok = prw_ref_create(s, im->v.eye, 2, &ref, e) && prw_ref_render(ref, &im->v, &d, &acc, &st, e) &&
         prw_ref_acc_images(&acc, &im->ref, &im->var, e);
    if (ok) {
        im->hit = prw_calloc((size_t)W * H, sizeof *im->hit);
        im->hit_ok = prw_calloc((size_t)W * H, sizeof *im->hit_ok);
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++)
                im->hit_ok[y * W + x] = prw_ref_primary_hit(ref, &im->v, x + 0.5, y + 0.5, &im->hit[y * W + x]);
    }
    prw_ref_acc_free(&acc);
    prw_ref_destroy(ref);
    return ok;
}

/* Mean radiance (channel c) over the pixels of mask, in the raster and the reference, with the
 * reference mean's standard deviation; returns the pixel count. */
typedef struct region {
    int n;
    double raster, ref, sigma;
} region;

static region region_mean(const images *im, const bool *mask, int c)
{
    region g = {0};
    double var = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (!mask[i]) continue;
        g.n++;
        g.raster += im->raster.rgba[4 * i + c];
        if (im->ref) g.ref += im->ref[4 * i + c], var += im->var[4 * i + c];
    }
    if (g.n) {
        g.raster /= g.n, g.ref /= g.n;
        g.sigma = sqrt(var) / g.n;
    }
    return g;
}

/* raster = reference over a region within rel x scale + 4 sigma (scale: a typical radiance of the
 * image, so dark regions are judged absolutely).  control: the raster is a control that must NOT
 * agree; the line then says "detected" (disagrees) or "MISSED". */
static bool region_check(const char *what, region g, double rel, double scale, bool control)
{
    double tol = rel * fmax(fabs(g.ref), scale) + 4 * g.sigma;
    bool ok = g.n > 0 && fabs(g.raster - g.ref) <= tol;
    printf("  %-36s %4d px: raster %.5f ref %.5f (sigma %.5f) |diff| %.5f tol %.5f %s\n", what, g.n, g.raster, g.ref,
           g.sigma, fabs(g.raster - g.ref), tol, control ? (ok ? "MISSED" : "detected") : ok ? "ok" : "FAIL");
    return ok;
}

static bool region_agrees(const char *what, region g, double rel, double scale)
{
    return region_check(what, g, rel, scale, false);
}

static double vlen(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* ---- cut-out (alpha MASK) ---- */

enum { CUT_LIT_THROUGH, CUT_SHADOW, CUT_SEE_THROUGH, CUT_KEPT, CUT_FLOOR_LIT, CUT_REGIONS };

/* Regions from the primary hits.  The panel lies at y = 1 over x, z in [-0.6, 0.6], its left half
 * (x < 0) cut; the sun travels along (1, -1, 0), so the floor point (x, 0, z) is in the shadow of
 * panel point (x - 1, 1, z).  Regions (0.05 m away from every edge): the floor whose panel point is in
 * the cut half (lit through the cut) or in the kept half (its shadow); pixels whose ray crosses the
 * panel's plane in its cut half and then hits the floor (seen through the cut); the kept half; the
 * open floor in front (z > 0.9). */
static void cut_regions(const images *im, bool *m[CUT_REGIONS])
{
    for (size_t i = 0; i < (size_t)W * H; i++) {
        for (int k = 0; k < CUT_REGIONS; k++) m[k][i] = false;
        if (!im->hit_ok[i]) continue;
        prw_dvec3 p = im->hit[i].position;
        bool floor = fabs(p.y) < 1e-3;
        if (floor && fabs(p.z) < 0.55) {
            m[CUT_LIT_THROUGH][i] = p.x - 1 > -0.55 && p.x - 1 < -0.05;
            m[CUT_SHADOW][i] = p.x - 1 > 0.05 && p.x - 1 < 0.55;
        }
        if (floor) {
            double t = (im->v.eye.y - 1) / (im->v.eye.y - p.y); /* where the ray crosses y = 1 */
            double x = im->v.eye.x + t * (p.x - im->v.eye.x), z = im->v.eye.z + t * (p.z - im->v.eye.z);
            m[CUT_SEE_THROUGH][i] = x > -0.55 && x < -0.05 && fabs(z) < 0.55;
        }
        m[CUT_KEPT][i] = fabs(p.y - 1) < 1e-3 && p.x > 0.05 && p.x < 0.55 && fabs(p.z) < 0.55;
        m[CUT_FLOOR_LIT][i] = floor && p.z > 0.9 && fabs(p.x) < 1.5;
    }
}

static const char *cut_file(const char *mode, const char *name)
{
    /* 16 x 16 base-colour texture: alpha 0 in its left half (u < 0.5), 255 in its right half */
    static uint8_t tex[16 * 16 * 4];
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            uint8_t *p = tex + 4 * (y * 16 + x);
            p[0] = p[1] = p[2] = 255;
            p[3] = x < 8 ? 0 : 255;
        }
    gltfw_png("cut_alpha.png", 16, 16, tex);
    static char mats[1024];
    snprintf(mats, sizeof mats,
             "{\"name\":\"floor\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.8,0.8,1],\"metallicFactor\":0,"
             "\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}},"
             "{\"name\":\"cut\",\"alphaMode\":\"%s\",\"alphaCutoff\":0.5,\"doubleSided\":true,\"pbrMetallicRoughness\":{"
             "\"baseColorFactor\":[0.8,0.3,0.2,1],\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0,"
             "\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}}",
             mode);
    gfile f = {.materials = mats, .images = {"cut_alpha.png"}, .image_count = 1,
               .eye = {0.3, 3, 3}, .target = {0.4, 0, 0}, .yfov = 0.9,
               .light = 1, .light_at = {-2, 3, 0}, .light_to = {-1, 2, 0}, .intensity = 10};
    const double c0[3] = {0, 0, 0}, fu[3] = {2.5, 0, 0}, fv[3] = {0, 0, -2.5};
    const double c1[3] = {0, 1, 0}, qu[3] = {0.6, 0, 0}, qv[3] = {0, 0, -0.6};
    f.mesh[0] = gltfw_quad(c0, fu, fv, 0);
    f.mesh[1] = gltfw_quad(c1, qu, qv, 1);
    f.mesh_count = 2;
    const char *p = gltfw_write(name, &f, (double)W / H);
    gltfw_mesh_free(&f.mesh[0]), gltfw_mesh_free(&f.mesh[1]);
    return p;
}

static void test_cutout(void)
{
    prw_error e = {{0}};
    prw_scene *s = NULL;
    images im = {0}, bl = {0}, op = {0};
    CHECK_OK(load(cut_file("MASK", "cutout_mask"), &s, &e), &e);
    CHECK_OK(render_both(s, 11, SPP, true, &im, &e), &e);
    prw_scene_destroy(s);
    CHECK_OK(load(cut_file("BLEND", "cutout_blend"), &s, &e), &e);
    CHECK_OK(render_both(s, 12, SPP, true, &bl, &e), &e);
    prw_scene_destroy(s);
    CHECK_OK(load(cut_file("OPAQUE", "cutout_opaque"), &s, &e), &e);
    CHECK_OK(render_both(s, 13, 0, true, &op, &e), &e);
    prw_scene_destroy(s);
    write_out("cutout_mask", &im);
    write_out("cutout_blend", &bl);
    write_out("cutout_opaque", &op);

    bool *m[CUT_REGIONS];
    for (int k = 0; k < CUT_REGIONS; k++) m[k] = prw_calloc((size_t)W * H, sizeof(bool));
    cut_regions(&im, m);
    const char *names[CUT_REGIONS] = {"floor lit through the cut", "floor in the kept half's shadow",
                                      "floor seen through the cut", "the kept half", "open floor"};
    double lit = region_mean(&im, m[CUT_FLOOR_LIT], 1).ref;
    printf("cut-out quad (alpha MASK), open floor %.4f cd/m^2 (green):\n", lit);
    for (int k = 0; k < CUT_REGIONS; k++) {
        CHECK_MSG(region_mean(&im, m[k], 0).n >= 6, "region '%s' has too few pixels", names[k]);
        for (int c = 0; c < 3; c += 2) { /* red and blue: the floor is grey, the panel red */
            char what[64];
            snprintf(what, sizeof what, "%s (%c)", names[k], "RGB"[c]);
            CHECK(region_agrees(what, region_mean(&im, m[k], c), 0.03, 0.05 * lit));
        }
    }
    /* the scene is what it claims: light through the cut, shadow behind the kept half */
    region through = region_mean(&im, m[CUT_LIT_THROUGH], 1), shadow = region_mean(&im, m[CUT_SHADOW], 1);
    CHECK(through.ref > 0.8 * lit && shadow.ref < 0.1 * lit);
    printf("the same quad as alpha BLEND with the same (binary) alpha:\n");
    for (int k = 0; k < CUT_REGIONS; k++) CHECK(region_agrees(names[k], region_mean(&bl, m[k], 1), 0.03, 0.05 * lit));
    /* control: the OPAQUE quad hides the floor behind its cut half and shadows it */
    region ctl_see = region_mean(&op, m[CUT_SEE_THROUGH], 1), ctl_lit = region_mean(&op, m[CUT_LIT_THROUGH], 1);
    region see = region_mean(&im, m[CUT_SEE_THROUGH], 1);
    printf("control (OPAQUE, raster): seen through the cut %.4f (MASK ref %.4f), lit through the cut %.4f (MASK ref "
           "%.4f)\n",
           ctl_see.raster, see.ref, ctl_lit.raster, through.ref);
    CHECK(fabs(ctl_see.raster - see.ref) > 0.2 * lit);
    CHECK(ctl_lit.raster < 0.1 * lit);
    for (int k = 0; k < CUT_REGIONS; k++) free(m[k]);
    images_free(&im), images_free(&bl), images_free(&op);
}

/* ---- KHR_texture_transform ---- */

/* 4 x 4 blocks of 8 x 8 texels, block (bx, by) with a colour of its own (sRGB bytes). */
static void block_colour(int bx, int by, uint8_t out[3])
{
    out[0] = (uint8_t)(40 + 60 * bx);
    out[1] = (uint8_t)(40 + 60 * by);
    out[2] = (uint8_t)(((bx + by) & 1) ? 230 : 30);
}

static double srgb_decode(uint8_t v)
{
    double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* The block under uv (repeat wrap) and whether uv is at least `margin` texels inside it. */
static bool block_at(const float uv[2], double margin, int *bx, int *by)
{
    double u = uv[0] - floor(uv[0]), v = uv[1] - floor(uv[1]);
    double tu = u * 32, tv = v * 32;
    *bx = (int)(tu / 8), *by = (int)(tv / 8);
    if (*bx > 3) *bx = 3;
    if (*by > 3) *by = 3;
    double fu = tu - 8 * *bx, fv = tv - 8 * *by;
    return fu >= margin && fu <= 8 - margin && fv >= margin && fv <= 8 - margin;
}

static void test_transform(void)
{
    static uint8_t tex[32 * 32 * 4];
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            uint8_t *p = tex + 4 * (y * 32 + x);
            block_colour(x / 8, y / 8, p);
            p[3] = 255;
        }
    CHECK(gltfw_png("blocks.png", 32, 32, tex));
    /* left quad: emissive texture, offset + rotation + scale; right quad: lit base colour from
     * TEXCOORD_1 (uv1 = (v, u): a transposed mapping) with another transform */
    const char *mats =
        "{\"name\":\"emissive\",\"emissiveTexture\":{\"index\":0,\"extensions\":{\"KHR_texture_transform\":"
        "{\"offset\":[0.3,-0.2],\"rotation\":0.6,\"scale\":[1.7,1.3]}}},\"emissiveFactor\":[1,1,1],"
        "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,1],\"metallicFactor\":0,\"roughnessFactor\":1},"
        "\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}},"
        "{\"name\":\"lit\",\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,\"texCoord\":0,\"extensions\":"
        "{\"KHR_texture_transform\":{\"offset\":[-0.1,0.45],\"rotation\":-1.1,\"scale\":[1.2,2.1],\"texCoord\":1}}},"
        "\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}}";
    gfile f = {.materials = mats, .images = {"blocks.png"}, .image_count = 1, .ext_used = "\"KHR_texture_transform\"",
               .eye = {0, 0, 3}, .target = {0, 0, 0}, .yfov = 0.7,
               .light = 1, .light_at = {0, 0, 5}, .light_to = {0, 0, 0}, .intensity = PRW_PI};
    const double cl[3] = {-0.82, 0, 0}, cr[3] = {0.82, 0, 0}, hu[3] = {0.78, 0, 0}, hv[3] = {0, 0.78, 0};
    f.mesh[0] = gltfw_quad(cl, hu, hv, 0);
    f.mesh[1] = gltfw_quad(cr, hu, hv, 1);
    f.mesh[1].uv1 = malloc(8 * sizeof(float));
    for (int v = 0; v < 4; v++) f.mesh[1].uv1[2 * v] = f.mesh[1].uv[2 * v + 1], f.mesh[1].uv1[2 * v + 1] = f.mesh[1].uv[2 * v];
    f.mesh_count = 2;
    const char *path = gltfw_write("transform", &f, (double)W / H);
    gltfw_mesh_free(&f.mesh[0]), gltfw_mesh_free(&f.mesh[1]);
    prw_error e = {{0}};
    prw_scene *s = NULL;
    images im = {0};
    CHECK_OK(load(path, &s, &e), &e);
    CHECK(s->mesh_count == 2 && s->meshes[1].uvs1 != NULL);
    CHECK_OK(render_both(s, 21, SPP, true, &im, &e), &e);
    write_out("transform", &im);
    /* control (raster only): the same slots and uv sets without their transforms */
    const prw_tex_transform xf[2] = {s->materials[0].tex_xf[PRW_TEX_EMISSIVE], s->materials[1].tex_xf[PRW_TEX_BASE_COLOR]};
    images ctl = {0};
    for (int q = 0; q < 2; q++) {
        prw_tex_transform *t = &s->materials[q].tex_xf[q ? PRW_TEX_BASE_COLOR : PRW_TEX_EMISSIVE];
        *t = (prw_tex_transform){.scale = {1, 1}, .tex_coord = t->tex_coord};
    }
    CHECK_OK(render_both(s, 22, 0, true, &ctl, &e), &e);
    write_out("transform_control", &ctl);
    /* per pixel: the quad hit, its (u, v) from the position, the transformed uv by the loader's own
     * prw_tex_transform_apply, the block there; compared in chromaticity-free form: the radiance
     * divided by the block's linear colour must be the same constant on every block (emission 1 x
     * texel; Lambert: texel / pi x pi lux = texel) */
    int tested[2] = {0, 0}, bad_raster[2] = {0, 0}, bad_ref[2] = {0, 0}, bad_ident[2] = {0, 0}, bad_ctl[2] = {0, 0};
    double worst_r = 0, worst_f = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (!im.hit_ok[i]) continue;
        prw_dvec3 p = im.hit[i].position;
        int q = p.x < 0 ? 0 : 1;
        const double *c = q ? cr : cl;
        float uv0[2] = {(float)(0.5 + 0.5 * (p.x - c[0]) / 0.78), (float)(0.5 - 0.5 * (p.y - c[1]) / 0.78)};
        if (uv0[0] < 0.02f || uv0[0] > 0.98f || uv0[1] < 0.02f || uv0[1] > 0.98f) continue;
        const prw_tex_transform *t = &xf[q];
        float uvs[2] = {uv0[0], uv0[1]};
        if (t->tex_coord == 1) uvs[0] = uv0[1], uvs[1] = uv0[0];
        float uvt[2];
        prw_tex_transform_apply(t, uvs, uvt);
        int bx, by, ix, iy;
        /* the pixel's footprint: ~1/60 of the quad in uv0, times the scale ~2 -> ~1 texel; 2 texels margin */
        if (!block_at(uvt, 2.0, &bx, &by)) continue;
        tested[q]++;
        uint8_t col[3];
        block_colour(bx, by, col);
        bool ident_same = block_at(uvs, 0.0, &ix, &iy) && ix == bx && iy == by;
        double dr = 0, df = 0, di = 0, dc = 0;
        uint8_t ic[3];
        block_colour(ix, iy, ic);
        for (int k = 0; k < 3; k++) {
            double want = srgb_decode(col[k]);
            dr = fmax(dr, fabs(im.raster.rgba[4 * i + k] - want) / fmax(want, 0.05));
            df = fmax(df, fabs(im.ref[4 * i + k] - want) / fmax(want, 0.05));
            di = fmax(di, fabs(srgb_decode(ic[k]) - want) / fmax(want, 0.05));
            dc = fmax(dc, fabs(ctl.raster.rgba[4 * i + k] - want) / fmax(want, 0.05));
        }
        worst_r = fmax(worst_r, dr), worst_f = fmax(worst_f, df);
        bad_raster[q] += dr > 0.03;
        bad_ref[q] += df > 0.03;
        bad_ident[q] += !ident_same && di > 0.03;
        bad_ctl[q] += dc > 0.03;
    }
    for (int q = 0; q < 2; q++) {
        printf("%s: %d pixels in the middle of a block: beyond 3 %% of the block colour: raster %d, reference %d; "
               "the untransformed lookup would be wrong on %d; control (raster without the transform) wrong on %d\n",
               q ? "lit base colour, TEXCOORD_1 + transform" : "emissive texture + transform", tested[q], bad_raster[q],
               bad_ref[q], bad_ident[q], bad_ctl[q]);
        CHECK(tested[q] >= 100);
        CHECK(bad_raster[q] == 0 && bad_ref[q] == 0);
        CHECK(bad_ident[q] > tested[q] / 2); /* the test would see a missing transform */
        CHECK(bad_ctl[q] > tested[q] / 2);   /* and does see it */
    }
    printf("  worst relative colour error: raster %.4f, reference %.4f\n", worst_r, worst_f);
    prw_scene_destroy(s);
    images_free(&im), images_free(&ctl);
}

/* A normal map read through a transform: its frame turns with the rotation and the scale (prw_shading.h,
 * prw_normal_xf_t / _b).  A constant map (every texel the normal tilted 30 degrees towards +x), so the
 * uv transform itself changes nothing and only the frame rule shows: left quad rotation pi/2, right
 * quad rotation 0.6 and scale (2, 0.5), Lambert under an oblique sun.  Each quad's mean against the
 * reference within 1 % + 4 sigma; control: the raster with both transforms removed. */
static void test_normal_transform(void)
{
    static uint8_t tex[4 * 4 * 4];
    for (int i = 0; i < 16; i++) tex[4 * i] = 191, tex[4 * i + 1] = 128, tex[4 * i + 2] = 238, tex[4 * i + 3] = 255;
    CHECK(gltfw_png("tilt.png", 4, 4, tex));
    const char *mats =
        "{\"name\":\"a\",\"normalTexture\":{\"index\":0,\"extensions\":{\"KHR_texture_transform\":{\"rotation\":1.5707963267948966}}},"
        "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.8,0.8,1],\"metallicFactor\":0,\"roughnessFactor\":1},"
        "\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}},"
        "{\"name\":\"b\",\"normalTexture\":{\"index\":0,\"extensions\":{\"KHR_texture_transform\":{\"rotation\":0.6,"
        "\"scale\":[2,0.5]}}},"
        "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.8,0.8,0.8,1],\"metallicFactor\":0,\"roughnessFactor\":1},"
        "\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}}";
    gfile f = {.materials = mats, .images = {"tilt.png"}, .image_count = 1, .ext_used = "\"KHR_texture_transform\"",
               .eye = {0, 0, 3}, .target = {0, 0, 0}, .yfov = 0.7,
               .light = 1, .light_at = {-1, 1.5, 2}, .light_to = {0, 0, 0}, .intensity = PRW_PI};
    const double cl[3] = {-0.82, 0, 0}, cr[3] = {0.82, 0, 0}, hu[3] = {0.78, 0, 0}, hv[3] = {0, 0.78, 0};
    f.mesh[0] = gltfw_quad(cl, hu, hv, 0);
    f.mesh[1] = gltfw_quad(cr, hu, hv, 1);
    f.mesh_count = 2;
    const char *path = gltfw_write("normal_xf", &f, (double)W / H);
    gltfw_mesh_free(&f.mesh[0]), gltfw_mesh_free(&f.mesh[1]);
    prw_error e = {{0}};
    prw_scene *s = NULL;
    images im = {0}, ctl = {0};
    CHECK_OK(load(path, &s, &e), &e);
    if (!s) return;
    CHECK_OK(render_both(s, 61, SPP, true, &im, &e), &e);
    for (int q = 0; q < 2; q++) s->materials[q].tex_xf[PRW_TEX_NORMAL] = (prw_tex_transform){.scale = {1, 1}};
    CHECK_OK(render_both(s, 62, 0, true, &ctl, &e), &e);
    write_out("normal_transform", &im);
    write_out("normal_transform_control", &ctl);
    bool *m[2];
    for (int q = 0; q < 2; q++) {
        m[q] = prw_calloc((size_t)W * H, sizeof(bool));
        const double *c = q ? cr : cl;
        for (size_t i = 0; i < (size_t)W * H; i++)
            m[q][i] = im.hit_ok && im.hit_ok[i] && fabs(im.hit[i].position.x - c[0]) < 0.7 && fabs(im.hit[i].position.y) < 0.7;
    }
    printf("constant tilted normal map through a transform (left: rotation pi/2; right: rotation 0.6, scale 2 x 0.5):\n");
    double scale = region_mean(&im, m[0], 0).ref;
    for (int q = 0; q < 2; q++) {
        char what[64];
        snprintf(what, sizeof what, "%s quad (R)", q ? "right" : "left");
        CHECK(region_agrees(what, region_mean(&im, m[q], 0), 0.01, 0.05 * scale));
        region g = region_mean(&ctl, m[q], 0), r = region_mean(&im, m[q], 0);
        g.ref = r.ref, g.sigma = r.sigma;
        snprintf(what, sizeof what, "control: %s quad untransformed (R)", q ? "right" : "left");
        CHECK(!region_check(what, g, 0.01, 0.05 * scale, true));
    }
    for (int q = 0; q < 2; q++) free(m[q]);
    prw_scene_destroy(s);
    images_free(&im), images_free(&ctl);
}

/* ---- KHR_materials_clearcoat ---- */

/* Two clear-coated spheres: left, a plain coat; right, its weight from a striped clearcoatTexture
 * through a transform (scale 6 x 1: six stripe pairs around) and its normal from a gently bumped
 * clearcoatNormalTexture (scale 0.6).  coat: clearcoatFactor of both. */
static const char *coat_file(double coat, const char *name)
{
    static uint8_t stripes[16 * 16 * 4], bumps[32 * 32 * 4];
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++) {
            uint8_t *p = stripes + 4 * (y * 16 + x);
            p[0] = x < 8 ? 255 : 96, p[1] = p[2] = 0, p[3] = 255;
        }
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            double n[3] = {0.25 * sin(2 * PRW_PI * 2 * (x + 0.5) / 32), 0.25 * sin(2 * PRW_PI * 2 * (y + 0.5) / 32), 1};
            double l = vlen(n);
            uint8_t *p = bumps + 4 * (y * 32 + x);
            for (int k = 0; k < 3; k++) p[k] = (uint8_t)lrint(255 * (0.5 + 0.5 * n[k] / l));
            p[3] = 255;
        }
    gltfw_png("coat_stripes.png", 16, 16, stripes);
    gltfw_png("coat_bumps.png", 32, 32, bumps);
    static char mats[2048];
    snprintf(mats, sizeof mats,
             "{\"name\":\"paint\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.6,0.08,0.04,1],\"metallicFactor\":0,"
             "\"roughnessFactor\":0.55},\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":%g,"
             "\"clearcoatRoughnessFactor\":0.3}}},"
             "{\"name\":\"textured\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.1,0.2,0.6,1],\"metallicFactor\":0,"
             "\"roughnessFactor\":0.55},\"extensions\":{\"KHR_materials_clearcoat\":{\"clearcoatFactor\":%g,"
             "\"clearcoatRoughnessFactor\":0.3,\"clearcoatTexture\":{\"index\":0,\"extensions\":{\"KHR_texture_transform\":"
             "{\"scale\":[6,1]}}},\"clearcoatNormalTexture\":{\"index\":1,\"scale\":0.6}}}}",
             coat, coat);
    gfile f = {.materials = mats, .images = {"coat_stripes.png", "coat_bumps.png"}, .image_count = 2,
               .ext_used = "\"KHR_materials_clearcoat\",\"KHR_texture_transform\"", .eye = {0, 0.3, 2.6},
               .target = {0, 0, 0}, .yfov = 0.6, .light = 2, .light_at = {1.2, 1.6, 1.8}, .light_to = {0, 0, 0},
               .intensity = 12};
    const double cl[3] = {-0.55, 0, 0}, cr[3] = {0.55, 0, 0};
    f.mesh[0] = gltfw_sphere(cl, 0.45, 96, 48, 0);
    f.mesh[1] = gltfw_sphere(cr, 0.45, 96, 48, 1);
    f.mesh_count = 2;
    const char *p = gltfw_write(name, &f, (double)W / H);
    gltfw_mesh_free(&f.mesh[0]), gltfw_mesh_free(&f.mesh[1]);
    return p;
}

/* Pixels within r (Chebyshev distance) of a pixel of core. */
static bool *grow(const bool *core, int r)
{
    bool *out = prw_calloc((size_t)W * H, sizeof(bool));
    for (int y = 0; y < (int)H; y++)
        for (int x = 0; x < (int)W; x++)
            for (int dy = -r; dy <= r && !out[y * W + x]; dy++)
                for (int dx = -r; dx <= r; dx++) {
                    int xx = x + dx, yy = y + dy;
                    if (xx >= 0 && yy >= 0 && xx < (int)W && yy < (int)H && core[yy * W + xx]) {
                        out[y * W + x] = true;
                        break;
                    }
                }
    return out;
}

static void test_clearcoat(void)
{
    prw_error e = {{0}};
    prw_scene *s = NULL;
    images im = {0}, im2 = {0}, ctl = {0};
    CHECK_OK(load(coat_file(1.0, "coat"), &s, &e), &e);
    CHECK(s->material_count == 2 && s->materials[0].clearcoat == 1.0f && s->materials[1].clearcoat_normal_tex >= 0);
    CHECK_OK(render_both(s, 31, 4 * SPP, true, &im, &e), &e);
    CHECK_OK(render_both(s, 32, 4 * SPP, false, &im2, &e), &e); /* the reference's own noise */
    /* control (raster only): the left sphere without its coat, the right one without its coat textures */
    s->materials[0].clearcoat = 0;
    s->materials[1].clearcoat_tex = s->materials[1].clearcoat_normal_tex = -1;
    CHECK_OK(render_both(s, 33, 0, true, &ctl, &e), &e);
    prw_scene_destroy(s);
    write_out("clearcoat", &im);
    write_out("clearcoat_control", &ctl);
    /* regions per sphere: all of it; its highlight (reference pixels with more than 0.35 of the sphere's
     * largest green: the coat's white highlight) grown by one pixel, so it holds the highlight's whole
     * energy in both renderers; the rest of it, three pixels away from the highlight */
    size_t np = (size_t)W * H;
    bool *all[2], *core[2], *hi[2], *rest[2];
    for (int q = 0; q < 2; q++) {
        all[q] = prw_calloc(np, sizeof(bool)), core[q] = prw_calloc(np, sizeof(bool)), rest[q] = prw_calloc(np, sizeof(bool));
        for (size_t i = 0; i < np; i++) all[q][i] = im.hit_ok[i] && (im.hit[i].position.x > 0) == (q == 1);
        double gmax = 0;
        for (size_t i = 0; i < np; i++)
            if (all[q][i]) gmax = fmax(gmax, im.ref[4 * i + 1]);
        for (size_t i = 0; i < np; i++) core[q][i] = all[q][i] && im.ref[4 * i + 1] > 0.35 * gmax;
        hi[q] = grow(core[q], 1);
        bool *far = grow(core[q], 3);
        for (size_t i = 0; i < np; i++) rest[q][i] = all[q][i] && !far[i];
        free(far);
    }
    printf("clear-coated spheres under a point light (coat 1, coat roughness 0.3; left over a red dielectric r = "
           "0.55, right over a blue one with a striped weight texture (transformed) and a coat normal map):\n");
    double scale = region_mean(&im, all[0], 0).ref;
    bool ok = true;
    for (int q = 0; q < 2; q++)
        for (int c = 0; c < 3; c++) {
            char what[64];
            snprintf(what, sizeof what, "%s sphere (%c)", q ? "right" : "left", "RGB"[c]);
            ok &= region_agrees(what, region_mean(&im, all[q], c), 0.02, 0.02 * scale);
            snprintf(what, sizeof what, "%s highlight (%c)", q ? "right" : "left", "RGB"[c]);
            ok &= region_agrees(what, region_mean(&im, hi[q], c), 0.05, 0.02 * scale);
            snprintf(what, sizeof what, "%s, outside the highlight (%c)", q ? "right" : "left", "RGB"[c]);
            ok &= region_agrees(what, region_mean(&im, rest[q], c), 0.02, 0.02 * scale);
        }
    CHECK(ok);
    CHECK(region_mean(&im, hi[0], 1).n >= 4 && region_mean(&im, hi[1], 1).n >= 4);
    /* FLIP against the reference's noise */
    prw_image ra = {.width = (int)W, .height = (int)H, .rgba = im.ref}, rb = {.width = (int)W, .height = (int)H, .rgba = im2.ref};
    prw_compare_opts o = {.ev100 = 0.0}; /* white at 1.2 cd/m^2: the diffuse red about mid grey */
    prw_compare_metrics err, noise, cm;
    CHECK_OK(prw_compare_images(&im.raster, &ra, &o, &err, NULL, NULL, &e), &e);
    CHECK_OK(prw_compare_images(&rb, &ra, &o, &noise, NULL, NULL, &e), &e);
    CHECK_OK(prw_compare_images(&ctl.raster, &ra, &o, &cm, NULL, NULL, &e), &e);
    printf("  LDR-FLIP mean: raster vs reference %.4f, reference noise %.4f, beyond noise %.4f (limit 0.03); "
           "control beyond noise %.4f\n",
           err.ldr_flip.mean, noise.ldr_flip.mean, err.ldr_flip.mean - noise.ldr_flip.mean,
           cm.ldr_flip.mean - noise.ldr_flip.mean);
    CHECK(err.ldr_flip.mean - noise.ldr_flip.mean <= 0.03);
    CHECK(cm.ldr_flip.mean - noise.ldr_flip.mean > 0.03);
    /* the control differs where the test looks: no highlight without the coat and a brighter base (no coat
     * to pass); the right highlight moves without the coat's normal map and weight */
    region c_hi = region_mean(&ctl, hi[0], 1), c_rest = region_mean(&ctl, rest[0], 0), f_rest = region_mean(&im, rest[0], 0);
    region c_hr = region_mean(&ctl, hi[1], 1), f_hr = region_mean(&im, hi[1], 1);
    printf("  control: left highlight (G) %.4f vs coated reference %.4f; left outside it (R) %.4f vs %.4f; right "
           "highlight (G) without the coat textures %.4f vs %.4f\n",
           c_hi.raster, region_mean(&im, hi[0], 1).ref, c_rest.raster, f_rest.ref, c_hr.raster, f_hr.ref);
    CHECK(c_hi.raster < 0.5 * region_mean(&im, hi[0], 1).ref);
    CHECK(fabs(c_rest.raster - f_rest.ref) > 0.02 * fmax(f_rest.ref, 0.02 * scale) + 4 * f_rest.sigma);
    CHECK(fabs(c_hr.raster - f_hr.ref) > 0.05 * fmax(f_hr.ref, 0.02 * scale) + 4 * f_hr.sigma);
    for (int q = 0; q < 2; q++) free(all[q]), free(core[q]), free(hi[q]), free(rest[q]);
    images_free(&im), images_free(&im2), images_free(&ctl);
}

/* The same spheres under a rect light (the coated rect-light terms of lights.glsl: the base's under the
 * coat's transmission, the coat's lobe by the same quadrature and polygon formula as an uncoated
 * surface's): region means per sphere; control: the raster without either coat, judged by the same
 * comparisons, must fail them. */
static void test_clearcoat_rect(void)
{
    prw_error e = {{0}};
    prw_scene *s = NULL;
    images im = {0}, ctl = {0};
    CHECK_OK(load(coat_file(1.0, "coat_rect"), &s, &e), &e);
    CHECK(s->light_count == 1);
    /* the point light's node becomes a 0.6 m x 0.4 m panel facing the spheres (-Z of the node) */
    s->lights[0].type = PRW_LIGHT_RECT;
    s->lights[0].width = 0.6, s->lights[0].height = 0.4;
    s->lights[0].intensity = 50; /* cd/m^2: about the point light's illuminance */
    prw_scene_update(s);
    CHECK_OK(render_both(s, 51, 4 * SPP, true, &im, &e), &e);
    s->materials[0].clearcoat = 0, s->materials[1].clearcoat = 0;
    CHECK_OK(render_both(s, 52, 0, true, &ctl, &e), &e);
    prw_scene_destroy(s);
    write_out("clearcoat_rect", &im);
    write_out("clearcoat_rect_control", &ctl);
    size_t np = (size_t)W * H;
    bool *all[2], *core[2], *hi[2], *rest[2];
    for (int q = 0; q < 2; q++) {
        all[q] = prw_calloc(np, sizeof(bool)), core[q] = prw_calloc(np, sizeof(bool)), rest[q] = prw_calloc(np, sizeof(bool));
        for (size_t i = 0; i < np; i++) all[q][i] = im.hit_ok[i] && (im.hit[i].position.x > 0) == (q == 1);
        double gmax = 0;
        for (size_t i = 0; i < np; i++)
            if (all[q][i]) gmax = fmax(gmax, im.ref[4 * i + 1]);
        for (size_t i = 0; i < np; i++) core[q][i] = all[q][i] && im.ref[4 * i + 1] > 0.35 * gmax;
        hi[q] = grow(core[q], 1);
        bool *far = grow(core[q], 3);
        for (size_t i = 0; i < np; i++) rest[q][i] = all[q][i] && !far[i];
        free(far);
    }
    printf("the clear-coated spheres under a 0.6 x 0.4 m rect light (50 cd/m^2):\n");
    double scale = region_mean(&im, all[0], 0).ref;
    bool ok = true;
    int ctl_fails = 0;
    for (int pass = 0; pass < 2; pass++) {
        const images *r = pass ? &ctl : &im;
        if (pass) printf("control: the raster without the coats, same comparisons:\n");
        for (int q = 0; q < 2; q++)
            for (int c = 0; c < 3; c++) {
                region g[3] = {region_mean(r, all[q], c), region_mean(r, hi[q], c), region_mean(r, rest[q], c)};
                if (pass) /* the reference's figures: the raster's regions over the coated reference */
                    for (int k = 0; k < 3; k++) {
                        const bool *mk = k == 0 ? all[q] : k == 1 ? hi[q] : rest[q];
                        region f = region_mean(&im, mk, c);
                        g[k].ref = f.ref, g[k].sigma = f.sigma;
                    }
                const char *names[3] = {"sphere", "highlight", "outside the highlight"};
                const double rel[3] = {0.02, 0.05, 0.02};
                for (int k = 0; k < 3; k++) {
                    char what[64];
                    snprintf(what, sizeof what, "%s %s (%c)", q ? "right" : "left", names[k], "RGB"[c]);
                    bool a = region_check(what, g[k], rel[k], 0.02 * scale, pass == 1);
                    if (pass) ctl_fails += !a;
                    else ok &= a;
                }
            }
    }
    printf("  the control is detected by %d of 18 comparisons\n", ctl_fails);
    CHECK(ok);
    CHECK(region_mean(&im, hi[0], 1).n >= 4 && region_mean(&im, hi[1], 1).n >= 4);
    CHECK(ctl_fails >= 6);
    for (int q = 0; q < 2; q++) free(all[q]), free(core[q]), free(hi[q]), free(rest[q]);
    images_free(&im), images_free(&ctl);
}

/* ---- alpha BLEND ---- */

static void test_blend(void)
{
    /* an emissive wall (black base: its shading does not depend on shadows), a lit red quad of alpha
     * 0.45 in front and an emissive green quad of alpha 0.6 behind it, overlapping; in the file the
     * front quad comes first (an unsorted renderer would draw it first) */
    const char *mats =
        "{\"name\":\"wall\",\"emissiveFactor\":[0.3,0.3,0.6],\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,1],"
        "\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}},"
        "{\"name\":\"front\",\"alphaMode\":\"BLEND\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.9,0.1,0.1,0.45],"
        "\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}},"
        "{\"name\":\"back\",\"alphaMode\":\"BLEND\",\"doubleSided\":true,\"emissiveFactor\":[0.1,0.9,0.2],"
        "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,0.6],\"metallicFactor\":0,\"roughnessFactor\":1},"
        "\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}}";
    gfile f = {.materials = mats, .eye = {0, 0, 3}, .target = {0, 0, 0}, .yfov = 0.7,
               .light = 1, .light_at = {0, 0, 5}, .light_to = {0, 0, 0}, .intensity = PRW_PI};
    const double cw[3] = {0, 0, -1}, wu[3] = {3, 0, 0}, wv[3] = {0, 2, 0};
    const double cf[3] = {-0.25, 0.1, 0.4}, fu[3] = {0.5, 0, 0}, fv[3] = {0, 0.45, 0};
    const double cb[3] = {0.25, -0.1, 0}, bu[3] = {0.55, 0, 0}, bv[3] = {0, 0.5, 0};
    f.mesh[0] = gltfw_quad(cf, fu, fv, 1);
    f.mesh[1] = gltfw_quad(cb, bu, bv, 2);
    f.mesh[2] = gltfw_quad(cw, wu, wv, 0);
    f.mesh_count = 3;
    const char *path = gltfw_write("blend", &f, (double)W / H);
    for (int i = 0; i < 3; i++) gltfw_mesh_free(&f.mesh[i]);
    prw_error e = {{0}};
    prw_scene *s = NULL;
    images im = {0};
    CHECK_OK(load(path, &s, &e), &e);
    CHECK_OK(render_both(s, 41, SPP, true, &im, &e), &e);
    write_out("blend", &im);
    /* regions from where each pixel's ray crosses the planes z = 0.4 (front) and z = 0 (back) */
    enum { B_WALL, B_FRONT, B_BACK, B_BOTH, B_N };
    bool *m[B_N];
    for (int k = 0; k < B_N; k++) m[k] = prw_calloc((size_t)W * H, sizeof(bool));
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            prw_dvec3 d = prw_view_ray_dir(&im.v, x + 0.5, y + 0.5);
            double dd[3] = {d.x, d.y, d.z}, l = vlen(dd);
            (void)l;
            bool in[2];
            const double *cs[2] = {cf, cb}, *us[2] = {fu, bu}, *vs[2] = {fv, bv};
            bool edge = false;
            for (int q = 0; q < 2; q++) {
                double t = (cs[q][2] - im.v.eye.z) / d.z;
                double px = im.v.eye.x + t * d.x - cs[q][0], py = im.v.eye.y + t * d.y - cs[q][1];
                double a = fabs(px) / us[q][0], b = fabs(py) / vs[q][1];
                in[q] = a < 1 && b < 1;
                edge = edge || (fabs(a - 1) < 0.08 || fabs(b - 1) < 0.08); /* keep away from every edge */
            }
            if (edge) continue;
            size_t i = (size_t)y * W + x;
            int k = in[0] && in[1] ? B_BOTH : in[0] ? B_FRONT : in[1] ? B_BACK : B_WALL;
            m[k][i] = true;
        }
    printf("two BLEND quads (front: lit red, alpha 0.45; back: emissive green, alpha 0.6) over an emissive wall:\n");
    const char *names[B_N] = {"wall", "front quad only", "back quad only", "front over back"};
    double scale = region_mean(&im, m[B_WALL], 2).ref;
    for (int k = 0; k < B_N; k++)
        for (int c = 0; c < 3; c++) {
            char what[64];
            snprintf(what, sizeof what, "%s (%c)", names[k], "RGB"[c]);
            CHECK(region_agrees(what, region_mean(&im, m[k], c), 0.03, 0.03 * scale));
        }
    /* the reference's regions compose as "over" in the right order, and not in the wrong one */
    for (int c = 0; c < 3; c++) {
        double wall = region_mean(&im, m[B_WALL], c).ref, fo = region_mean(&im, m[B_FRONT], c).ref;
        double bo = region_mean(&im, m[B_BACK], c).ref, both = region_mean(&im, m[B_BOTH], c).ref;
        double Lf = (fo - 0.55 * wall) / 0.45, Lb = (bo - 0.4 * wall) / 0.6; /* each layer's own radiance */
        double right = 0.45 * Lf + 0.55 * (0.6 * Lb + 0.4 * wall), wrong = 0.6 * Lb + 0.4 * (0.45 * Lf + 0.55 * wall);
        double rast = region_mean(&im, m[B_BOTH], c).raster;
        printf("  %c: overlap raster %.4f, reference %.4f, over in order %.4f, in the wrong order %.4f\n", "RGB"[c], rast,
               both, right, wrong);
        CHECK(fabs(both - right) <= 0.03 * fmax(both, scale));
        if (c < 2) CHECK(fabs(rast - wrong) > 3 * fabs(rast - right) + 0.01 * scale);
    }
    for (int k = 0; k < B_N; k++) free(m[k]);
    prw_scene_destroy(s);
    images_free(&im);
}

/* ---- the extension pipelines in two-view frames and with G-buffer outputs ---- */

/* A two-view frame of `s` (eyes 6.5 cm apart) with the backend and stereo reuse given; each eye against a
 * mono render from it: the number of differing floats and the relative L1; whether the reproject pass ran. */
typedef struct eyes_result {
    size_t diff[2];
    double rel[2];
    double cut[2][2], kept[2][2]; /* [eye][mono, two-view frame]: green means through the cut / over the kept half */
    bool reprojected;
} eyes_result;

static int panel_half(const prw_view *v, uint32_t x, uint32_t y);

static bool eyes_vs_mono(const prw_scene *s, prw_views_backend backend, uint32_t reuse, eyes_result *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    prw_view eyes[2];
    for (int k = 0; k < 2; k++)
        eyes[k] = prw_view_look_at(prw_v3(0.3 + 0.065 * k, 3, 3), prw_v3(0.4 + 0.065 * k, 0, 0), prw_v3(0, 1, 0), 0.9,
                                   0.05, W, H, 1.0);
    prw_render_desc d2 = {.width = W, .height = H, .max_views = 2, .views_backend = backend, .quality = prw_quality_default()};
    d2.quality.msaa = 4;
    d2.quality.shadow_size = SHADOW_VIEWS;
    d2.quality.stereo_reuse = reuse;
    prw_render_desc d1 = d2;
    d1.max_views = 1, d1.views_backend = PRW_VIEWS_LOOP, d1.quality.stereo_reuse = PRW_STEREO_REUSE_OFF;
    prw_renderer *r2 = NULL, *r1 = NULL;
    prw_frame_stats fs;
    prw_image eye[2] = {{0}}, mono = {0};
    bool ok = prw_renderer_create(g_gpu, s, &d2, &r2, e) && prw_renderer_create(g_gpu, s, &d1, &r1, e) &&
              prw_renderer_render(r2, eyes, 2, &fs, e) && prw_renderer_read_hdr(r2, 0, &eye[0], e) &&
              prw_renderer_read_hdr(r2, 1, &eye[1], e);
    if (ok)
        for (uint32_t i = 0; i < fs.pass_count; i++)
            if (strcmp(fs.passes[i].name, "reproject") == 0 && !fs.passes[i].skipped) out->reprojected = true;
    for (int k = 0; k < 2 && ok; k++) {
        ok = prw_renderer_render(r1, &eyes[k], 1, NULL, e) && prw_renderer_read_hdr(r1, 0, &mono, e);
        if (!ok) break;
        double sum = 0, sum_d = 0;
        for (size_t i = 0; i < (size_t)W * H * 4; i++) {
            out->diff[k] += memcmp(&mono.rgba[i], &eye[k].rgba[i], sizeof(float)) != 0;
            sum += fabs(mono.rgba[i]);
            sum_d += fabs((double)mono.rgba[i] - eye[k].rgba[i]);
        }
        out->rel[k] = sum > 0 ? sum_d / sum : INFINITY;
        int n[2] = {0, 0};
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                int h = panel_half(&eyes[k], x, y);
                if (h < 0) continue;
                size_t i = 4 * ((size_t)y * W + x) + 1;
                double *m = h ? out->kept[k] : out->cut[k];
                m[0] += mono.rgba[i], m[1] += eye[k].rgba[i], n[h]++;
            }
        for (int j = 0; j < 2; j++) out->cut[k][j] /= n[0] ? n[0] : 1, out->kept[k][j] /= n[1] ? n[1] : 1;
        prw_image_free(&mono);
    }
    prw_image_free(&eye[0]), prw_image_free(&eye[1]);
    prw_renderer_destroy(r2), prw_renderer_destroy(r1);
    return ok;
}

/* The G-buffer material id (slot + 1) of every pixel of the camera view, 1x MSAA. */
static bool gbuffer_ids(const prw_scene *s, prw_view *v, uint32_t **ids, prw_error *e)
{
    static const char *const exports[] = {"gbuf_normal", "gbuf_id", NULL}; /* both: the G-buffer is written */
    prw_render_debug dbg = {.exports = exports};
    prw_render_desc rd = {.width = W, .height = H, .debug = &dbg, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = SHADOW_VIEWS;
    prw_renderer *r = NULL;
    uint32_t w = 0, h = 0;
    *ids = NULL;
    bool ok = prw_view_from_camera(s, 0, W, H, v, e) && prw_renderer_create(g_gpu, s, &rd, &r, e) &&
              prw_renderer_render(r, v, 1, NULL, e) && prw_renderer_read_image(r, "gbuf_id", 0, (void **)ids, &w, &h, e);
    prw_renderer_destroy(r);
    if (ok && (w != W || h != H)) ok = prw_fail(e, "gbuf_id is %ux%u", w, h);
    return ok;
}

/* Whether the ray through pixel (x, y) crosses the panel's plane (y = 1) in its cut half (0) or its kept
 * half (1), 0.05 m away from every edge (then it reaches the floor); -1: neither. */
static int panel_half(const prw_view *v, uint32_t x, uint32_t y)
{
    prw_dvec3 d = prw_view_ray_dir(v, x + 0.5, y + 0.5);
    if (!(d.y < 0)) return -1;
    double t = (1 - v->eye.y) / d.y, px = v->eye.x + t * d.x, pz = v->eye.z + t * d.z;
    if (!(fabs(pz) < 0.55)) return -1;
    return px > -0.55 && px < -0.05 ? 0 : px > 0.05 && px < 0.55 ? 1 : -1;
}

/* Over the two halves: counts of G-buffer ids 1 (floor) and 2 (panel). */
static void id_counts(const prw_view *v, const uint32_t *ids, int floor_id[2], int panel_id[2], int n[2])
{
    for (int k = 0; k < 2; k++) floor_id[k] = panel_id[k] = n[k] = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            int k = panel_half(v, x, y);
            if (k < 0) continue;
            uint32_t id = ids[y * W + x];
            n[k]++, floor_id[k] += id == 1, panel_id[k] += id == 2;
        }
}

static void test_views_gbuffer(void)
{
    prw_error e = {{0}};
    prw_scene *s = NULL, *sb = NULL, *so = NULL;
    CHECK_OK(load(cut_file("MASK", "views_mask"), &s, &e), &e);
    CHECK_OK(load(cut_file("BLEND", "views_blend"), &sb, &e), &e);
    CHECK_OK(load(cut_file("OPAQUE", "views_opaque"), &so, &e), &e);
    if (!s || !sb || !so) goto done;
    /* stereo reuse asked for: a scene with MASK / BLEND shades both eyes (bit-identical to mono renders);
     * control: the OPAQUE panel is reprojected, so its right eye differs from the mono render */
    eyes_result lm, lb, lo;
    CHECK_OK(eyes_vs_mono(s, PRW_VIEWS_LOOP, PRW_STEREO_REUSE_REPROJECT, &lm, &e), &e);
    CHECK_OK(eyes_vs_mono(sb, PRW_VIEWS_LOOP, PRW_STEREO_REUSE_REPROJECT, &lb, &e), &e);
    CHECK_OK(eyes_vs_mono(so, PRW_VIEWS_LOOP, PRW_STEREO_REUSE_REPROJECT, &lo, &e), &e);
    printf("two-view frames, stereo_reuse=reproject: MASK reprojected %d, floats differing from mono left %zu right "
           "%zu; BLEND reprojected %d, %zu / %zu; control OPAQUE reprojected %d, %zu / %zu (of %u)\n",
           lm.reprojected, lm.diff[0], lm.diff[1], lb.reprojected, lb.diff[0], lb.diff[1], lo.reprojected, lo.diff[0],
           lo.diff[1], W * H * 4);
    CHECK(!lm.reprojected && lm.diff[0] == 0 && lm.diff[1] == 0);
    CHECK(!lb.reprojected && lb.diff[0] == 0 && lb.diff[1] == 0);
    CHECK(lo.reprojected && lo.diff[1] > 0);
    /* the multiview backend draws the extension shaders' multiview variants */
    /* light mode (sanitizers) leaves the multiview part out: the stereo tests run the multiview backend
     * under the sanitizers, and the full run checks these variants */
    if (!prw_gpu_features_enabled(g_gpu)->multiview) printf("device lacks multiview: that part skipped\n");
    else if (prw_test_light()) printf("light mode: the multiview part skipped\n");
    else {
        eyes_result mm, mb;
        CHECK_OK(eyes_vs_mono(s, PRW_VIEWS_MULTIVIEW, PRW_STEREO_REUSE_OFF, &mm, &e), &e);
        CHECK_OK(eyes_vs_mono(sb, PRW_VIEWS_MULTIVIEW, PRW_STEREO_REUSE_OFF, &mb, &e), &e);
        eyes_result mo;
        CHECK_OK(eyes_vs_mono(so, PRW_VIEWS_MULTIVIEW, PRW_STEREO_REUSE_OFF, &mo, &e), &e);
        /* Not bit for bit: lavapipe's multiview defect (test_stereo_gpu.c: view 1's interpolated positions
         * are off by metres, view 0's by less on clipped triangles) hits the core shaders' OPAQUE panel as
         * much as the extension shaders' (relative L1 printed; view 1's floor then samples the shadow map
         * at wrong places).  What is checked: the green means through the cut and over the kept half within
         * 3 % of the mono render's, in the left eye on lavapipe (the right eye's printed), in both eyes on
         * other devices; control: the OPAQUE panel's frame differs from the MASK mono render through the
         * cut. */
        bool llvmpipe = strstr(prw_gpu_device_name(g_gpu), "llvmpipe") != NULL;
        printf("multiview: eyes vs mono relative L1: MASK %.3g / %.3g, BLEND %.3g / %.3g, OPAQUE (core shaders) %.3g / "
               "%.3g\n",
               mm.rel[0], mm.rel[1], mb.rel[0], mb.rel[1], mo.rel[0], mo.rel[1]);
        for (int k = 0; k < 2; k++) {
            printf("  %s eye, green through the cut / over the kept half: MASK mono %.4f / %.4f, multiview %.4f / "
                   "%.4f; BLEND mono %.4f / %.4f, multiview %.4f / %.4f; control OPAQUE multiview %.4f / %.4f\n",
                   k ? "right" : "left", mm.cut[k][0], mm.kept[k][0], mm.cut[k][1], mm.kept[k][1], mb.cut[k][0],
                   mb.kept[k][0], mb.cut[k][1], mb.kept[k][1], mo.cut[k][1], mo.kept[k][1]);
            if (k == 1 && llvmpipe) {
                printf("  (right eye not checked on llvmpipe: its multiview defect; OPAQUE relative L1 %.3g)\n",
                       mo.rel[1]);
                continue;
            }
            const eyes_result *r[2] = {&mm, &mb};
            for (int q = 0; q < 2; q++) {
                CHECK(fabs(r[q]->cut[k][1] - r[q]->cut[k][0]) <= 0.03 * r[q]->cut[k][0]);
                CHECK(fabs(r[q]->kept[k][1] - r[q]->kept[k][0]) <= 0.03 * r[q]->kept[k][0]);
            }
            CHECK(fabs(mo.cut[k][1] - mm.cut[k][0]) > 0.03 * mm.cut[k][0]);
        }
    }
    /* G-buffer ids where the rays pass the cut half and the kept half: MASK floor / panel, BLEND floor /
     * floor (blended surfaces are not in the G-buffer), control OPAQUE panel / panel */
    uint32_t *ids = NULL;
    prw_view v;
    int fl[3][2], pa[3][2], n[3][2];
    const prw_scene *sc[3] = {s, sb, so};
    for (int q = 0; q < 3; q++) {
        CHECK_OK(gbuffer_ids(sc[q], &v, &ids, &e), &e);
        if (!ids) goto done;
        id_counts(&v, ids, fl[q], pa[q], n[q]);
        free(ids);
        printf("G-buffer ids (%s): through the cut floor %d panel %d of %d; over the kept half floor %d panel %d of %d\n",
               q == 0 ? "MASK" : q == 1 ? "BLEND" : "control OPAQUE", fl[q][0], pa[q][0], n[q][0], fl[q][1], pa[q][1],
               n[q][1]);
        CHECK(n[q][0] >= 50 && n[q][1] >= 50);
    }
    CHECK(fl[0][0] == n[0][0] && pa[0][1] == n[0][1]);
    CHECK(fl[1][0] == n[1][0] && fl[1][1] == n[1][1]);
    CHECK(pa[2][0] == n[2][0]); /* the MASK check above would see a panel drawn without its cut */
done:
    prw_scene_destroy(s), prw_scene_destroy(sb), prw_scene_destroy(so);
}

/* Stereo reprojection of extension materials without alpha (the coated, transformed spheres): the
 * right eye's holes are shaded with the extension shaders (pass_reproject.c).  The reprojected right eye
 * against the fully shaded one: LDR-FLIP <= 0.05 (test_stereo_reuse's bound); control: the left eye
 * taken as the right eye is more than twice as far. */
static void test_reproject_ext(void)
{
    prw_error e = {{0}};
    prw_scene *s = NULL;
    CHECK_OK(load(coat_file(1.0, "coat_reproject"), &s, &e), &e);
    if (!s) return;
    prw_view eyes[2];
    for (int k = 0; k < 2; k++)
        eyes[k] = prw_view_look_at(prw_v3(-0.0315 + 0.063 * k, 0.3, 2.6), prw_v3(-0.0315 + 0.063 * k, 0, 0),
                                   prw_v3(0, 1, 0), 0.6, 0.05, W, H, 0.0);
    prw_render_desc d1 = {.width = W, .height = H, .max_views = 1, .quality = prw_quality_default()};
    d1.quality.msaa = 4;
    d1.quality.shadow_size = SHADOW_VIEWS;
    prw_render_desc d2 = d1;
    d2.max_views = 2, d2.quality.stereo_reuse = PRW_STEREO_REUSE_REPROJECT;
    prw_renderer *r1 = NULL, *r2 = NULL;
    prw_frame_stats fs;
    prw_image full = {0}, on[2] = {{0}};
    bool ok = prw_renderer_create(g_gpu, s, &d1, &r1, &e) && prw_renderer_create(g_gpu, s, &d2, &r2, &e) &&
              prw_renderer_render(r1, &eyes[1], 1, NULL, &e) && prw_renderer_read_hdr(r1, 0, &full, &e) &&
              prw_renderer_render(r2, eyes, 2, &fs, &e) && prw_renderer_read_hdr(r2, 0, &on[0], &e) &&
              prw_renderer_read_hdr(r2, 1, &on[1], &e);
    CHECK_OK(ok, &e);
    if (ok) {
        bool ran = false;
        for (uint32_t i = 0; i < fs.pass_count; i++)
            if (strcmp(fs.passes[i].name, "reproject") == 0 && !fs.passes[i].skipped) ran = true;
        prw_compare_opts o = {.ev100 = 0.0};
        prw_compare_metrics m, c;
        CHECK_OK(prw_compare_images(&on[1], &full, &o, &m, NULL, NULL, &e), &e);
        CHECK_OK(prw_compare_images(&on[0], &full, &o, &c, NULL, NULL, &e), &e);
        printf("coated spheres, stereo_reuse=reproject (reprojected %d): right eye LDR-FLIP vs the fully shaded "
               "one %.4f (limit 0.05); control (the left eye as the right eye) %.4f\n",
               ran, m.ldr_flip.mean, c.ldr_flip.mean);
        CHECK(ran);
        CHECK(m.ldr_flip.mean <= 0.05);
        CHECK(c.ldr_flip.mean > 2 * m.ldr_flip.mean);
    }
    prw_image_free(&full), prw_image_free(&on[0]), prw_image_free(&on[1]);
    prw_renderer_destroy(r1), prw_renderer_destroy(r2);
    prw_scene_destroy(s);
}

/* ---- NURBS models with MASK / BLEND materials (closed form) ---- */

/* A NURBS filleted box (procedural "box" scaled 0.5: +-0.65 m, flat faces within +-0.5 m) with material
 * "glass" (emission Eb, black base, alpha `alpha`, mode `mode`) in front of a wall at z = -3 (emission
 * We plus a grey Lambert base lit by a sun along (0.6, 0, -1), whose shadow of the box falls at
 * x = 1.55 .. 2.85 on the wall, beside the box as seen from the camera at z = 5).  The raster's green
 * mean (a) over the box's flat front face, (b) over the wall in the box's shadow, (c) over the open wall. */
static const double k_eb[3] = {0.9, 0.2, 0.1}, k_we[3] = {0.1, 0.1, 0.2};
#define NURBS_WALL_BASE 0.5
#define NURBS_SUN 3.0

static bool nurbs_render(const char *mode, double alpha, double out[3][3], prw_error *e)
{
    char mats[1024], name[64], json[1024];
    snprintf(mats, sizeof mats,
             "{\"name\":\"wall\",\"emissiveFactor\":[%g,%g,%g],\"pbrMetallicRoughness\":{\"baseColorFactor\":[%g,%g,%g,1],"
             "\"metallicFactor\":0,\"roughnessFactor\":1},\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}},"
             "{\"name\":\"glass\",\"alphaMode\":\"%s\",\"alphaCutoff\":0.5,\"emissiveFactor\":[%g,%g,%g],"
             "\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,%g],\"metallicFactor\":0,\"roughnessFactor\":1},"
             "\"extensions\":{\"KHR_materials_specular\":{\"specularFactor\":0}}}",
             k_we[0], k_we[1], k_we[2], NURBS_WALL_BASE, NURBS_WALL_BASE, NURBS_WALL_BASE, mode, k_eb[0], k_eb[1], k_eb[2],
             alpha);
    gfile f = {.materials = mats, .eye = {0, 0, 5}, .target = {0, 0, 0}, .yfov = 0.6};
    const double cw[3] = {0, 0, -3}, wu[3] = {4, 0, 0}, wv[3] = {0, 3, 0};
    f.mesh[0] = gltfw_quad(cw, wu, wv, 0);
    f.mesh_count = 1;
    snprintf(name, sizeof name, "nurbs_%s_%02d", mode, (int)lrint(100 * alpha));
    gltfw_write(name, &f, (double)W / H);
    gltfw_mesh_free(&f.mesh[0]);
    snprintf(json, sizeof json,
             "{\"prw_manifest\":1,\"gltf\":[{\"file\":\"%s.gltf\"}],\"nurbs\":[{\"name\":\"box\",\"procedural\":\"box\","
             "\"material\":\"glass\",\"single_sided\":true,\"scale\":[0.5,0.5,0.5]}],\"lights\":[{\"type\":\"directional\","
             "\"direction\":[0.6,0,-1],\"intensity\":%g,\"shadows\":true}]}",
             name, NURBS_SUN);
    char jn[80];
    snprintf(jn, sizeof jn, "%s.json", name);
    char *path = prw_test_path(jn);
    prw_test_write_file(path, json, strlen(json));
    prw_scene *s = prw_scene_create();
    prw_renderer *r = NULL;
    prw_image im = {0};
    prw_view v = prw_view_look_at(prw_v3(0, 0, 5), prw_v3(0, 0, 0), prw_v3(0, 1, 0), 0.6, 0.05, W, H, 0.0);
    prw_render_desc rd = {.width = W, .height = H, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 2048;
    bool ok = prw_scene_load_manifest(s, path, e) && prw_bake_scene(s, NULL, NULL, e) &&
              prw_renderer_create(g_gpu, s, &rd, &r, e) && prw_renderer_render(r, &v, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, &im, e);
    if (ok) {
        char n2[80];
        snprintf(n2, sizeof n2, "%s", name);
        images tmp = {.raster = im};
        write_out(n2, &tmp);
        int n[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) out[k][0] = out[k][1] = out[k][2] = 0;
        for (uint32_t y = 0; y < H; y++)
            for (uint32_t x = 0; x < W; x++) {
                prw_dvec3 d = prw_view_ray_dir(&v, x + 0.5, y + 0.5);
                double tb = (0.65 - v.eye.z) / d.z, tw = (-3 - v.eye.z) / d.z;
                double bx = v.eye.x + tb * d.x, by = v.eye.y + tb * d.y;
                double wx = v.eye.x + tw * d.x, wy = v.eye.y + tw * d.y;
                int k = fabs(bx) < 0.4 && fabs(by) < 0.4             ? 0
                        : wx > 1.75 && wx < 2.65 && fabs(wy) < 0.45  ? 1
                        : wx < -1.2 && wx > -3.8 && fabs(wy) < 2.8   ? 2
                                                                     : -1;
                if (k < 0) continue;
                n[k]++;
                for (int c = 0; c < 3; c++) out[k][c] += im.rgba[4 * ((size_t)y * W + x) + c];
            }
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) out[k][c] /= n[k] ? n[k] : 1;
        if (!(n[0] >= 50 && n[1] >= 30 && n[2] >= 100)) ok = prw_fail(e, "nurbs regions: %d %d %d pixels", n[0], n[1], n[2]);
    }
    prw_image_free(&im);
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
    return ok;
}

static bool near3(const double a[3], const double b[3])
{
    for (int c = 0; c < 3; c++)
        if (!(fabs(a[c] - b[c]) <= 0.005 * fmax(b[c], 0.05))) return false;
    return true;
}

static void test_nurbs(void)
{
    prw_error e = {{0}};
    double lit[3], blend[3];
    const double cosl = 1 / sqrt(1.36);
    for (int c = 0; c < 3; c++) {
        lit[c] = k_we[c] + NURBS_WALL_BASE / PRW_PI * NURBS_SUN * cosl;
        blend[c] = 0.4 * k_eb[c] + 0.6 * lit[c];
    }
    double mk[3][3], mc[3][3], bl[3][3], op[3][3];
    CHECK_OK(nurbs_render("MASK", 0.7, mk, &e), &e);
    CHECK_OK(nurbs_render("MASK", 0.4, mc, &e), &e);
    CHECK_OK(nurbs_render("BLEND", 0.4, bl, &e), &e);
    CHECK_OK(nurbs_render("OPAQUE", 0.4, op, &e), &e);
    const char *rn[3] = {"box face", "wall in the box's shadow", "open wall"};
    struct { const char *what; double (*m)[3]; const double *want[3]; } rows[4] = {
        {"MASK alpha 0.7 (kept)", mk, {k_eb, k_we, lit}},
        {"MASK alpha 0.4 (cut)", mc, {lit, lit, lit}},
        {"BLEND alpha 0.4", bl, {blend, NULL, lit}}, /* its shadow: the raster's alpha >= 0.5 rule, not checked */
        {"control OPAQUE alpha 0.4, judged as the cut MASK", op, {lit, lit, lit}},
    };
    printf("NURBS box (96 x 64, closed form; R G B):\n");
    for (int q = 0; q < 4; q++)
        for (int k = 0; k < 3; k++) {
            const double *w = rows[q].want[k];
            bool ok = !w || near3(rows[q].m[k], w);
            printf("  %-48s %-26s raster %.4f %.4f %.4f", rows[q].what, rn[k], rows[q].m[k][0], rows[q].m[k][1],
                   rows[q].m[k][2]);
            if (w) printf("  closed form %.4f %.4f %.4f %s", w[0], w[1], w[2], q == 3 ? (ok ? "MISSED" : "detected") : ok ? "ok" : "FAIL");
            printf("\n");
            if (q < 3) CHECK(ok);
        }
    CHECK(!near3(op[0], lit) && !near3(op[1], lit)); /* the control fails the cut-MASK checks */
    printf("  known difference: the BLEND box's shadow is the raster's alpha >= 0.5 rule (none at 0.4); the path "
           "tracer's transmission would give %.4f %.4f %.4f there\n",
           k_we[0] + 0.6 * (lit[0] - k_we[0]), k_we[1] + 0.6 * (lit[1] - k_we[1]), k_we[2] + 0.6 * (lit[2] - k_we[2]));
}

int main(int argc, char **argv)
{
    prw_threads_set(2);
    static const prw_test_case cases[] = {
        {"cutout", test_cutout},
        {"transform", test_transform},
        {"normal_transform", test_normal_transform},
        {"clearcoat", test_clearcoat},
        {"clearcoat_rect", test_clearcoat_rect},
        {"blend", test_blend},
        {"views_gbuffer", test_views_gbuffer},
        {"reproject_ext", test_reproject_ext},
        {"nurbs", test_nurbs},
    };
    prw_error e;
    prw_gpu_desc gd = {.device_index = -1, .validation = true};
    if (!prw_gpu_create(&gd, &g_gpu, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 1;
    }
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    prw_gpu_destroy(g_gpu);
    uint32_t msgs = prw_gpu_validation_total(); /* includes leak reports made at destroy */
    if (msgs) fprintf(stderr, "%u validation messages\n", msgs);
    return rc ? rc : msgs ? 1 : 0;
}
