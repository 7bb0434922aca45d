/* NURBS LOD in the renderer (issue 7: GPU integration).  Render tests (lavapipe, validation on, 128²):
 *  - scene_renders: a manifest with a procedural car shell (a "nurbs" entry) renders through the base
 *    and shadow passes without validation messages, NaN or Inf, and the model covers pixels.
 *  - update_minimal: along a camera path of small moves the re-uploaded patch slots are EXACTLY the
 *    patches whose emitted triangles changed, found independently by re-emitting every patch on the
 *    CPU at the old and the new levels and comparing; every slot then equals a fresh emission; small
 *    moves change few patches.
 *  - crack_free_box: the closed filleted box (single-sided, emissive, black background) at a mixed
 *    LOD: every pixel whose ray passes through the EXACT solid (cube ⊕ ball, closed form) deeper than
 *    the allowed geometric error (the tolerance, or the worst projected error where the finest level
 *    binds) + 1.5 px is fully model-coloured in the 4x MSAA HDR image, from two views (patches only).  Control: one
 *    triangle in 16 of one drawn patch made degenerate in the GPU buffer (it stays: nothing is
 *    re-uploaded) must be seen as leaking pixels.  (Cracks from unshared segment levels are no usable
 *    control on this box: its seams are planar sections along the normals, so such slivers stand
 *    perpendicular to the surface and show only at grazing angles.)
 *  - flip_vs_finest: the lit car shell at the selected LOD (½ px) against the finest level: mean
 *    LDR-FLIP printed and bounded by 0.03 (reasoning at the check); control: the coarsest level
 *    scores at least 1.5x worse.
 *  - view_set: one choice for two eyes that see different parts of the box: the patches drawn for the
 *    pair are exactly the union of those drawn for each eye alone, and a patch drawn for both eyes
 *    takes the finer of the two single-eye levels (the nearer eye decides).
 *  - proxy_far_copies: a 6 x 6 grid of car shells at 1/10 scale seen from a few metres: most copies
 *    are drawn as a whole-model proxy level (lod/prw_lod_proxy.h), every drawn error (proxies
 *    included) projects within ½ px, far fewer triangles than the patches alone, and the image is
 *    within mean LDR-FLIP 0.03 of the patches-only image; control: proxies chosen at 8 px score at
 *    least 1.5x worse.
 *  - far_from_origin: the box 1e5 m from the origin (camera and light moved with it) selects the same
 *    levels and renders the same image (camera-relative floats; an absolute-float mesh would not).
 *  - unbaked: the renderer builds no hierarchy (engine/bake is above it): a scene whose NURBS entry
 *    was not baked (prw_bake_scene) fails renderer creation with one message naming the entry.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_bake_scene.h"
#include "prw_image.h"
#include "prw_lod_node.h"
#include "prw_lod_render.h"
#include "prw_metrics.h"
#include "prw_render.h"
#include "prw_test.h"

static prw_gpu *g_gpu;

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

/* The car shell lies in x-y with its height along +z: rotated -90 degrees about X it stands on the
 * floor (height -> +y). */
static const char *k_shell_scene =
    "{\"prw_manifest\": 1,\n"
    " \"materials\": [{\"name\": \"paint\", \"base_color\": [0.6, 0.1, 0.08], \"roughness\": 0.35, \"double_sided\": true},\n"
    "                {\"name\": \"floor\", \"base_color\": [0.5, 0.5, 0.5], \"roughness\": 0.8}],\n"
    " \"meshes\": [{\"name\": \"floor\", \"box\": {\"min\": [-3, -0.1, -5], \"max\": [7, 0, 3]}, \"material\": \"floor\"}],\n"
    " \"nurbs\": [{\"name\": \"shell\", \"procedural\": \"car_shell\", \"rotation\": [-0.7071067811865476, 0, 0, 0.7071067811865476],\n"
    "             \"material\": \"paint\"}],\n"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.4, -1, -0.3], \"intensity\": 20000}],\n"
    " \"cameras\": [{\"name\": \"main\", \"position\": [2, 2.2, 3.2], \"target\": [2, 0.2, -0.9], \"yfov_deg\": 50, \"ev100\": 12}]}\n";

static const char *k_box_scene =
    "{\"prw_manifest\": 1,\n"
    " \"materials\": [{\"name\": \"glow\", \"base_color\": [0, 0, 0], \"specular\": 0, \"emission_cd_m2\": [100, 100, 100]}],\n"
    " \"nurbs\": [{\"name\": \"box\", \"procedural\": \"box\", \"material\": \"glow\", \"single_sided\": true, \"tol_px\": 1}],\n"
    " \"cameras\": [{\"name\": \"main\", \"position\": [2.6, 1.9, 3.3], \"target\": [0, 0, 0], \"yfov_deg\": 55, \"ev100\": 6}]}\n";

/* A scene from manifest text, baked (its NURBS entries' hierarchies attached) unless bake is false. */
static prw_scene *load_scene_baked(const char *text, bool bake)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    if (!prw_scene_parse_manifest(s, text, strlen(text), "lodgpu-test.json", &e)) {
        fprintf(stderr, "manifest: %s\n", e.msg);
        prw_scene_destroy(s);
        return NULL;
    }
    if (bake && !prw_bake_scene(s, NULL, NULL, &e)) {
        fprintf(stderr, "bake: %s\n", e.msg);
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

static prw_scene *load_scene(const char *text) { return load_scene_baked(text, true); }

static bool finite_image(const prw_image *im)
{
    for (size_t i = 0; i < (size_t)im->width * im->height * 4; i++)
        if (!isfinite(im->rgba[i])) return false;
    return true;
}

/* The GPU and a scene from manifest text; NULL (a failed check) when either is missing. */
static prw_scene *setup(const char *text)
{
    prw_scene *s = gpu_up() ? load_scene(text) : NULL;
    CHECK(s != NULL);
    return s;
}

static void test_scene_renders(void)
{
    if (!gpu_up()) {
        CHECK(false);
        return;
    }
    prw_scene *s = load_scene(k_shell_scene);
    CHECK(s != NULL);
    if (!s) return;
    CHECK(s->nurbs_count == 1);
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_view v;
    prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 512;
    CHECK_OK(prw_view_from_camera(s, 0, 128, 128, &v, &e), &e);
    CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
    prw_frame_stats st;
    prw_image hdr = {0};
    CHECK_OK(prw_renderer_render(r, &v, 1, &st, &e), &e);
    CHECK_OK(prw_renderer_read_hdr(r, 0, &hdr, &e), &e);
    const prw_lod_frame_report *rep = prw_lod_scene_last_report(prw_renderer_lod(r));
    printf("scene_renders: drawn %llu culled %llu patches, %llu triangles (finest %llu), %llu slots / %llu bytes "
           "uploaded, select %.2f ms, update %.2f ms; frame triangles %llu\n",
           (unsigned long long)rep->drawn_patches, (unsigned long long)rep->culled_patches,
           (unsigned long long)rep->triangles,
           (unsigned long long)prw_lod_scene_finest_triangles(prw_renderer_lod(r)),
           (unsigned long long)rep->reuploaded, (unsigned long long)rep->bytes, rep->select_ms, rep->update_ms,
           (unsigned long long)st.triangles);
    CHECK(rep->drawn_patches > 0 && rep->triangles > 0);
    CHECK(st.triangles >= rep->triangles + 12); /* floor box + model */
    CHECK(finite_image(&hdr));
    /* the model covers pixels: the paint's red dominates somewhere in the image centre */
    int red = 0;
    for (int y = 32; y < 96; y++)
        for (int x = 16; x < 112; x++) {
            const float *p = hdr.rgba + 4 * ((size_t)y * 128 + x);
            red += p[0] > 2.5f * p[1] && p[0] > 0;
        }
    printf("scene_renders: %d red pixels in the centre region\n", red);
    CHECK(red > 500);
    /* a second frame from the same camera uploads nothing */
    CHECK_OK(prw_renderer_render(r, &v, 1, &st, &e), &e);
    CHECK(prw_lod_scene_last_report(prw_renderer_lod(r))->reuploaded == 0);
    /* close up (finer than the layout's floor: a new layout), then far away (the slots shrink back):
     * both frames render with the validation layer watching the buffer swaps.  Patches only: far away
     * the whole-model proxy would be drawn instead (proxy_far_copies). */
    prw_lod_gpu_options no_px = {.no_proxy = true};
    prw_lod_scene_set_options(prw_renderer_lod(r), &no_px);
    prw_lod_gpu *g = prw_lod_scene_model(prw_renderer_lod(r), 0);
    uint64_t layouts0 = prw_lod_gpu_relayouts(g, 0);
    prw_view near_v = prw_view_look_at(prw_v3(2, 0.9, -0.4), prw_v3(2, 0.45, -0.9), prw_v3(0, 1, 0), 50 * PRW_PI / 180,
                                       0.05, 128, 128, 12);
    prw_view far_v = prw_view_look_at(prw_v3(2, 20, 40), prw_v3(2, 0.2, -0.9), prw_v3(0, 1, 0), 50 * PRW_PI / 180, 0.05,
                                      128, 128, 12);
    CHECK_OK(prw_renderer_render(r, &near_v, 1, &st, &e), &e);
    uint64_t layouts1 = prw_lod_gpu_relayouts(g, 0);
    CHECK_OK(prw_renderer_render(r, &far_v, 1, &st, &e), &e);
    uint64_t layouts2 = prw_lod_gpu_relayouts(g, 0);
    prw_image_free(&hdr);
    CHECK_OK(prw_renderer_read_hdr(r, 0, &hdr, &e), &e);
    CHECK(finite_image(&hdr));
    printf("scene_renders: layouts: first frame %llu, close-up +%llu, far away +%llu\n", (unsigned long long)layouts0,
           (unsigned long long)(layouts1 - layouts0), (unsigned long long)(layouts2 - layouts1));
    CHECK(layouts1 == layouts0 + 1 && layouts2 == layouts1 + 1);
    prw_image_free(&hdr);
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
}

/* ---- update minimality ---- */

typedef struct emission {
    float *v;
    uint32_t *i;
    uint32_t nv, ni;
} emission;

static void emit_all(prw_lod_gpu *g, const prw_lod_model *lm, const int *levels, emission *out, prw_error *e)
{
    int *seg = prw_malloc(sizeof(int) * (size_t)(lm->g->nsegs + 1));
    prw_lod_segment_levels(lm, levels, seg);
    for (int p = 0; p < lm->npatches; p++) {
        const float *v;
        const uint32_t *ix;
        uint32_t nv = 0, ni = 0;
        free(out[p].v);
        free(out[p].i);
        memset(&out[p], 0, sizeof out[p]);
        if (!lm->patches[p].ok) continue;
        if (!prw_lod_gpu_emit(g, p, levels[p], seg, &v, &nv, &ix, &ni, e)) {
            CHECK_MSG(false, "%s", e->msg);
            break;
        }
        out[p].v = prw_malloc(sizeof(float) * 12 * (nv + 1));
        out[p].i = prw_malloc(sizeof(uint32_t) * (ni + 1));
        memcpy(out[p].v, v, sizeof(float) * 12 * nv);
        memcpy(out[p].i, ix, sizeof(uint32_t) * ni);
        out[p].nv = nv;
        out[p].ni = ni;
    }
    free(seg);
}

static bool same(const emission *a, const emission *b)
{
    return a->nv == b->nv && a->ni == b->ni && !memcmp(a->v, b->v, sizeof(float) * 12 * a->nv) &&
           !memcmp(a->i, b->i, sizeof(uint32_t) * a->ni);
}

static void test_update_minimal(void)
{
    prw_scene *s = setup(k_shell_scene);
    if (!s) return;
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = 256;
    CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
    prw_lod_scene *ls = prw_renderer_lod(r);
    prw_lod_gpu *g = prw_lod_scene_model(ls, 0);
    const prw_lod_model *lm = &prw_lod_scene_hierarchy(ls, 0)->lod;
    int np = lm->npatches;
    emission *prev = prw_calloc((size_t)np, sizeof *prev), *cur = prw_calloc((size_t)np, sizeof *cur);
    int *lev = prw_malloc(sizeof(int) * (size_t)np);
    int frames = 40, changed_total = 0, frames_changed = 0, max_changed = 0, mismatches = 0, slot_bad = 0;
    int relayout_frames = 0;
    uint64_t culled_max = 0;
    uint64_t relayouts = prw_lod_gpu_relayouts(g, 0);
    prw_dvec3 target = prw_v3(2, 0.2, -0.9);
    for (int f = 0; f < frames; f++) {
        /* a slow approach with a sideways drift: 1.5 % of the distance per frame */
        double k = pow(0.985, f);
        prw_dvec3 eye = prw_v3_add(target, prw_v3(0.1 * f * 0.02 + 0.0, 2.0 * k, 4.1 * k));
        prw_view v = prw_view_look_at(eye, target, prw_v3(0, 1, 0), 50 * PRW_PI / 180, 0.05, 128, 128, 12);
        if (f == frames - 1) {
            prw_frame_stats st;
            CHECK_OK(prw_renderer_render(r, &v, 1, &st, &e), &e); /* the same update, inside a frame */
        } else {
            CHECK_OK(prw_lod_scene_update(ls, &v, 1, &e), &e);
        }
        memcpy(lev, prw_lod_gpu_levels(g, 0), sizeof(int) * (size_t)np);
        if (prw_lod_scene_last_report(ls)->culled_patches > culled_max) culled_max = prw_lod_scene_last_report(ls)->culled_patches;
        emit_all(g, lm, lev, cur, &e);
        const unsigned char *up = prw_lod_gpu_uploaded(g, 0);
        /* a new layout (the level floor moved) rewrites every slot by design: counted, not compared */
        bool relayout = prw_lod_gpu_relayouts(g, 0) != relayouts;
        relayouts = prw_lod_gpu_relayouts(g, 0);
        relayout_frames += f > 0 && relayout;
        int changed = 0;
        for (int p = 0; p < np; p++) {
            bool ch = f == 0 ? lm->patches[p].ok : !same(&prev[p], &cur[p]);
            changed += ch;
            if (f > 0 && !relayout && (bool)up[p] != ch) {
                mismatches++;
                fprintf(stderr, "frame %d patch %d: uploaded %d, emission changed %d\n", f, p, up[p], ch);
            }
            const float *sv;
            uint32_t *si, snv, sni, vb;
            prw_lod_gpu_slot(g, 0, p, &sv, &snv, &si, &sni, &vb);
            uint32_t *local = prw_malloc(sizeof(uint32_t) * (sni + 1));
            for (uint32_t j = 0; j < sni; j++) local[j] = si[j] - vb;
            emission se = {(float *)sv, local, snv, sni};
            slot_bad += lm->patches[p].ok && !same(&se, &cur[p]);
            free(local);
        }
        if (f > 0 && !relayout) {
            changed_total += changed;
            frames_changed += changed > 0;
            if (changed > max_changed) max_changed = changed;
        }
        emission *t = prev;
        prev = cur;
        cur = t;
    }
    printf("update_minimal: %d frames, %d patches; frames with changes %d, changed slots total %d, max per frame "
           "%d; upload/emission mismatches %d, slots differing from a fresh emission %d; frames with a new layout "
           "%d; culled patches up to %llu\n",
           frames - 1, np, frames_changed, changed_total, max_changed, mismatches, slot_bad, relayout_frames,
           (unsigned long long)culled_max);
    CHECK(relayout_frames <= 2); /* the floor moves by whole levels: rare */
    CHECK(mismatches == 0);
    CHECK(slot_bad == 0);
    CHECK(frames_changed >= 3);      /* the path does change levels (else the test proves nothing) */
    CHECK(max_changed <= np / 4);    /* a 1.5 % move touches few patches */
    for (int p = 0; p < np; p++) {
        free(prev[p].v), free(prev[p].i), free(cur[p].v), free(cur[p].i);
    }
    free(prev);
    free(cur);
    free(lev);
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
}

/* ---- crack freedom ---- */

/* Distance from p to the cube [-1, 1]^3. */
static double cube_dist(prw_dvec3 p)
{
    double dx = fmax(fabs(p.x) - 1, 0), dy = fmax(fabs(p.y) - 1, 0), dz = fmax(fabs(p.z) - 1, 0);
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Smallest distance of the ray to the cube (convex in t: golden-section search on [0, 20]). */
static double ray_cube(prw_dvec3 o, prw_dvec3 d, double *t_at)
{
    double a = 0, b = 20, gr = 0.5 * (sqrt(5.0) - 1);
    for (int it = 0; it < 200; it++) {
        double c = b - gr * (b - a), dd = a + gr * (b - a);
        if (cube_dist(prw_v3_add(o, prw_v3_scale(d, c))) < cube_dist(prw_v3_add(o, prw_v3_scale(d, dd)))) b = dd;
        else a = c;
    }
    *t_at = 0.5 * (a + b);
    return cube_dist(prw_v3_add(o, prw_v3_scale(d, *t_at)));
}

/* Renders the box scene; returns the number of deep-inside pixels that are not model-coloured. */
static int box_leaks(prw_renderer *r, const prw_view *v, double tol_px, int *inside, int *levels_used, double *margin_px)
{
    prw_error e = {{0}};
    prw_frame_stats st;
    prw_image hdr = {0};
    if (!prw_renderer_render(r, v, 1, &st, &e) || !prw_renderer_read_hdr(r, 0, &hdr, &e)) {
        CHECK_MSG(false, "%s", e.msg);
        return -1;
    }
    prw_lod_gpu *g = prw_lod_scene_model(prw_renderer_lod(r), 0);
    const prw_lod_model *lm = &prw_lod_scene_hierarchy(prw_renderer_lod(r), 0)->lod;
    const int *lev = prw_lod_gpu_levels(g, 0);
    const unsigned char *drawn = prw_lod_gpu_drawn(g, 0);
    unsigned used = 0;
    for (int p = 0; p < lm->npatches; p++)
        if (drawn[p]) used |= 1u << lev[p];
    *levels_used = __builtin_popcount(used);
    /* the geometric error allowed: the tolerance, or more where the finest level binds (the box's
     * corner patches keep an ear-clipped fan at their poles, lod/prw_lod.h), + 1.5 px of rasterisation */
    double max_px = prw_lod_scene_last_report(prw_renderer_lod(r))->max_px;
    *margin_px = fmax(tol_px, max_px) + 1.5;
    double pa = (v->tan_top - v->tan_bottom) / v->height;
    int bad = 0;
    *inside = 0;
    for (uint32_t y = 0; y < v->height; y++)
        for (uint32_t x = 0; x < v->width; x++) {
            prw_dvec3 d = prw_view_ray_dir(v, x + 0.5, y + 0.5);
            double t;
            double dist = ray_cube(v->eye, d, &t);
            double margin = *margin_px * pa * t; /* metres at the closest approach */
            if (!(dist < 0.3 - margin)) continue;
            (*inside)++;
            const float *px = hdr.rgba + 4 * ((size_t)y * v->width + x);
            if (!(fabs(px[0] - 100.0) <= 0.1 && fabs(px[1] - 100.0) <= 0.1 && fabs(px[2] - 100.0) <= 0.1)) bad++;
        }
    CHECK(finite_image(&hdr));
    prw_image_free(&hdr);
    return bad;
}

static void test_crack_free_box(void)
{
    prw_scene *s = setup(k_box_scene);
    if (!s) return;
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_view v;
    prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 256;
    CHECK_OK(prw_view_from_camera(s, 0, 128, 128, &v, &e), &e);
    CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
    prw_lod_gpu *g = prw_lod_scene_model(prw_renderer_lod(r), 0);
    int conflicts, flipped = prw_lod_gpu_flipped(g, &conflicts);
    printf("crack_free_box: %d patches flipped to the outward orientation, %d seam conflicts\n", flipped, conflicts);
    CHECK(flipped == 10 || flipped == 16); /* the 6 fillets + 4 corners disagree with the rest */
    CHECK(conflicts == 0);
    {
        /* a reversed patch's normals are reversed with its winding: every triangle's vertex normals
         * lie on its front side (they did not: flipped patches were shaded from behind) */
        const prw_lod_model *lm0 = &prw_lod_scene_hierarchy(prw_renderer_lod(r), 0)->lod;
        int *lv = prw_calloc((size_t)lm0->npatches + 1, sizeof(int));
        emission *em = prw_calloc((size_t)lm0->npatches + 1, sizeof(emission));
        emit_all(g, lm0, lv, em, &e);
        long tris = 0, against = 0;
        for (int p = 0; p < lm0->npatches; p++)
            for (uint32_t t = 0; t + 2 < em[p].ni; t += 3) {
                const float *a = em[p].v + 12 * em[p].i[t], *b = em[p].v + 12 * em[p].i[t + 1],
                            *c = em[p].v + 12 * em[p].i[t + 2];
                double u[3], w[3], f[3];
                for (int k = 0; k < 3; k++) u[k] = b[k] - a[k], w[k] = c[k] - a[k];
                f[0] = u[1] * w[2] - u[2] * w[1], f[1] = u[2] * w[0] - u[0] * w[2], f[2] = u[0] * w[1] - u[1] * w[0];
                double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
                if (!(fl > 1e-12)) continue;
                tris++;
                for (int k = 0; k < 3; k++) {
                    const float *x = k == 0 ? a : k == 1 ? b : c;
                    if ((f[0] * x[3] + f[1] * x[4] + f[2] * x[5]) / fl < 0) {
                        against++;
                        break;
                    }
                }
            }
        printf("crack_free_box: %ld of %ld level-0 triangles have a vertex normal behind them\n", against, tris);
        CHECK(tris > 100 && against == 0);
        for (int p = 0; p < lm0->npatches; p++) free(em[p].v), free(em[p].i);
        free(em);
        free(lv);
    }
    /* two views: the box's corner, and closer to it (more levels in use) */
    prw_view views[2] = {v, prw_view_look_at(prw_v3(1.9, 1.75, 1.6), prw_v3(0.6, 0.6, 0.6), prw_v3(0, 1, 0),
                                             55 * PRW_PI / 180, 0.05, 128, 128, 6)};
    /* patches only (mixed levels): the proxies' closedness is test_lod_proxy's (every edge of a
     * level used twice in opposite directions on the closed box); at the tolerances where the box
     * takes a proxy (~8 px: the filleted corners keep it coarse only at large errors) the margin
     * would swallow the 0.3 m fillets this check relies on */
    prw_lod_gpu_options no_px = {.no_proxy = true};
    prw_lod_scene_set_options(prw_renderer_lod(r), &no_px);
    for (int k = 0; k < 2; k++) {
        int inside, used;
        double margin;
        int bad = box_leaks(r, &views[k], 1.0, &inside, &used, &margin);
        const prw_lod_frame_report *rep = prw_lod_scene_last_report(prw_renderer_lod(r));
        printf("crack_free_box: view %d: %d levels in use, %llu drawn / %llu culled patches, %llu triangles, worst "
               "projected error %.2f px (finest binds %d); %d pixels deeper than %.2f px inside the exact solid, "
               "%d not model-coloured\n",
               k, used, (unsigned long long)rep->drawn_patches, (unsigned long long)rep->culled_patches,
               (unsigned long long)rep->triangles, rep->max_px, rep->finest_binds, inside, margin, bad);
        CHECK(used >= 3);     /* a mixed LOD */
        CHECK(inside > 2000); /* the box fills a good part of the 128² image */
        CHECK(bad == 0);
        CHECK(rep->culled_patches > 0); /* back-facing patches of the single-sided box */
    }
    /* control: a hole punched into the drawn mesh must be seen.  One triangle in 16 of the drawn patch
     * with the most triangles is made degenerate in the GPU buffer; the next frame re-uploads nothing
     * (the levels did not change), so the hole stays. */
    const prw_lod_model *lm = &prw_lod_scene_hierarchy(prw_renderer_lod(r), 0)->lod;
    const unsigned char *drawn = prw_lod_gpu_drawn(g, 0);
    int best = -1;
    uint32_t best_n = 0;
    for (int p = 0; p < lm->npatches; p++) {
        const float *sv;
        uint32_t *si, nv, ni, vb;
        prw_lod_gpu_slot(g, 0, p, &sv, &nv, &si, &ni, &vb);
        if (drawn[p] && ni > best_n) best = p, best_n = ni;
    }
    CHECK(best >= 0);
    if (best >= 0) {
        const float *sv;
        uint32_t *w, nv, ni, vb; /* w: the mapped index buffer */
        prw_lod_gpu_slot(g, 0, best, &sv, &nv, &w, &ni, &vb);
        for (uint32_t t = 0; t < ni / 3; t += 16) w[3 * t + 1] = w[3 * t + 2] = w[3 * t];
        int inside, used;
        double margin;
        int bad_ctl = box_leaks(r, &views[1], 1.0, &inside, &used, &margin);
        printf("crack_free_box: control (1 in 16 triangles of patch %d removed): %d leaking pixels, %llu slots "
               "re-uploaded\n",
               best, bad_ctl, (unsigned long long)prw_lod_scene_last_report(prw_renderer_lod(r))->reuploaded);
        CHECK(bad_ctl > 0);
    }
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
}

/* ---- FLIP against the finest level ---- */

static bool render_ldr(prw_renderer *r, const prw_view *v, prw_image *out)
{
    prw_error e = {{0}};
    prw_frame_stats st;
    uint8_t *ldr = prw_malloc(128 * 128 * 4);
    bool ok = prw_renderer_render(r, v, 1, &st, &e) && prw_renderer_read_ldr(r, 0, ldr, &e) &&
              prw_image_alloc(out, 128, 128, &e);
    if (ok)
        for (size_t i = 0; i < 128 * 128 * 4; i++) out->rgba[i] = ldr[i] / 255.0f;
    else
        CHECK_MSG(false, "%s", e.msg);
    free(ldr);
    return ok;
}

static double mean_flip(const prw_image *a, const prw_image *b)
{
    float *map = prw_malloc(sizeof(float) * 128 * 128);
    prw_error e = {{0}};
    double m = -1;
    if (prw_flip_ldr_encoded(a, b, 67.0, map, &e)) {
        m = 0;
        for (int i = 0; i < 128 * 128; i++) m += map[i];
        m /= 128 * 128;
    } else {
        CHECK_MSG(false, "%s", e.msg);
    }
    free(map);
    return m;
}

static void test_flip_vs_finest(void)
{
    prw_scene *s = setup(k_shell_scene);
    if (!s) return;
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_view v;
    prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 1024;
    (void)v;
    /* close to the shell (about 1.9 m from the roof), so the levels matter at 128² */
    v = prw_view_look_at(prw_v3(2.3, 1.0, 0.74), prw_v3(2, 0.2, -0.9), prw_v3(0, 1, 0), 50 * PRW_PI / 180, 0.05, 128,
                         128, 12);
    CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
    prw_lod_scene *ls = prw_renderer_lod(r);
    prw_image sel = {0}, fine = {0}, coarse = {0};
    if (!render_ldr(r, &v, &sel)) return;
    uint64_t tri_sel = prw_lod_scene_last_report(ls)->triangles;
    prw_lod_gpu_options o = {.force = true, .force_level = 0};
    prw_lod_scene_set_options(ls, &o);
    if (!render_ldr(r, &v, &fine)) return;
    uint64_t tri_fine = prw_lod_scene_last_report(ls)->triangles;
    o.force_level = 1000; /* clamped to the coarsest */
    prw_lod_scene_set_options(ls, &o);
    if (!render_ldr(r, &v, &coarse)) return;
    double f_sel = mean_flip(&sel, &fine), f_coarse = mean_flip(&coarse, &fine);
    printf("flip_vs_finest: selected LOD (0.5 px, %llu triangles) vs finest (%llu triangles): mean LDR-FLIP %.5f; "
           "coarsest level vs finest: %.5f\n",
           (unsigned long long)tri_sel, (unsigned long long)tri_fine, f_sel, f_coarse);
    /* Tolerance: the selected mesh is within ½ px of the exact surface, so silhouettes and shadow edges
     * move by less than a pixel, and its vertex normals are exact; what FLIP still sees is those
     * sub-pixel edge shifts and the linear interpolation of the normals across the larger triangles in
     * the glossy highlight (measured 0.0158 here; 0.0086 with a diffuse paint).  0.03 is below the
     * 0.05 budget the project uses for raster vs reference (issue 3), and the coarsest level (0.042
     * here) must score clearly worse, so the bound is not vacuous. */
    CHECK(f_sel >= 0 && f_sel <= 0.03);
    CHECK(f_coarse > 1.5 * f_sel);
    prw_image_free(&sel);
    prw_image_free(&fine);
    prw_image_free(&coarse);
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
}

/* ---- whole-model proxy levels for small copies ---- */

static void test_proxy_far_copies(void)
{
    static const char *scene =
        "{\"prw_manifest\": 1,\n"
        " \"materials\": [{\"name\": \"paint\", \"base_color\": [0.6, 0.1, 0.08], \"roughness\": 0.6, \"double_sided\": true},\n"
        "                {\"name\": \"floor\", \"base_color\": [0.5, 0.5, 0.5], \"roughness\": 0.8}],\n"
        " \"meshes\": [{\"name\": \"floor\", \"box\": {\"min\": [-1, -0.1, -1], \"max\": [4, 0, 3]}, \"material\": \"floor\"}],\n"
        " \"nurbs\": [{\"name\": \"shells\", \"procedural\": \"car_shell\", \"scale\": [0.1, 0.1, 0.1],\n"
        "             \"rotation\": [-0.7071067811865476, 0, 0, 0.7071067811865476], \"material\": \"paint\",\n"
        "             \"instances\": {\"grid\": [6, 6], \"spacing\": [0.55, 0.45]}}],\n"
        " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.4, -1, -0.3], \"intensity\": 20000}],\n"
        " \"cameras\": [{\"name\": \"main\", \"position\": [1.4, 1.6, 3.6], \"target\": [1.4, 0, 1.0], \"yfov_deg\": 50, \"ev100\": 12}]}\n";
    prw_scene *s = setup(scene);
    if (!s) return;
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_view v;
    prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
    rd.quality.msaa = 4;
    rd.quality.shadow_size = 512;
    CHECK_OK(prw_view_from_camera(s, 0, 128, 128, &v, &e), &e);
    CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
    prw_lod_scene *ls = prw_renderer_lod(r);
    prw_image img_proxy = {0}, img_patches = {0}, img_coarse = {0};
    if (!render_ldr(r, &v, &img_proxy)) return;
    prw_lod_frame_report rp = *prw_lod_scene_last_report(ls);
    prw_lod_gpu_options o = {.no_proxy = true};
    prw_lod_scene_set_options(ls, &o);
    if (!render_ldr(r, &v, &img_patches)) return;
    prw_lod_frame_report rq = *prw_lod_scene_last_report(ls);
    o = (prw_lod_gpu_options){.tol_px = 8};
    prw_lod_scene_set_options(ls, &o);
    if (!render_ldr(r, &v, &img_coarse)) return;
    prw_lod_frame_report rc = *prw_lod_scene_last_report(ls);
    double f = mean_flip(&img_proxy, &img_patches), fc = mean_flip(&img_coarse, &img_patches);
    printf("proxy_far_copies: %llu of %u copies as proxies, %llu triangles (patches only: %llu), worst %.3f px; "
           "mean LDR-FLIP vs patches only %.5f; proxies at 8 px: %llu copies, %llu triangles, FLIP %.5f\n",
           (unsigned long long)rp.proxy_instances, rp.instances, (unsigned long long)rp.triangles,
           (unsigned long long)rq.triangles, rp.max_px, f, (unsigned long long)rc.proxy_instances,
           (unsigned long long)rc.triangles, fc);
    CHECK(rq.proxy_instances == 0);
    CHECK(rp.proxy_instances * 2 >= rp.instances);
    CHECK(rp.triangles * 2 <= rq.triangles);
    CHECK(rp.max_px <= 0.5 + 1e-9);
    CHECK(finite_image(&img_proxy));
    /* the same ½-px reasoning as flip_vs_finest: both meshes are within ½ px of the exact surface with
     * exact vertex normals; the control (8 px) must be clearly worse, so the bound is not vacuous.
     * A rougher paint than flip_vs_finest's: measured 0.020 here (0.028 with its glossy 0.35, where
     * the normals' interpolation across the proxies' larger triangles shows in the highlight) */
    CHECK(f >= 0 && f <= 0.03);
    CHECK(fc > 1.5 * f);
    prw_image_free(&img_proxy);
    prw_image_free(&img_patches);
    prw_image_free(&img_coarse);
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
}

/* ---- camera-relative floats: the same box 1e5 m from the origin ---- */

static void test_far_from_origin(void)
{
    if (!gpu_up()) {
        CHECK(false);
        return;
    }
    static const char *fmt =
        "{\"prw_manifest\": 1,\n"
        " \"materials\": [{\"name\": \"m\", \"base_color\": [0.7, 0.7, 0.7], \"roughness\": 0.4}],\n"
        " \"nurbs\": [{\"procedural\": \"box\", \"material\": \"m\", \"single_sided\": true, \"translation\": [%.1f, 0, %.1f]}],\n"
        " \"lights\": [{\"type\": \"point\", \"position\": [%.1f, 4, %.1f], \"intensity\": 300, \"shadows\": false}],\n"
        " \"cameras\": [{\"position\": [%.1f, 1.9, %.1f], \"target\": [%.1f, 0, %.1f], \"ev100\": 6}]}\n";
    prw_image img[2] = {{0}, {0}};
    int levels[2][64];
    for (int k = 0; k < 2; k++) {
        double o = k ? 1e5 : 0;
        char text[2048];
        snprintf(text, sizeof text, fmt, o, o, o + 2, o + 1, o + 2.6, o + 3.3, o, o);
        prw_scene *s = load_scene(text);
        if (!s) {
            CHECK(false);
            return;
        }
        prw_error e = {{0}};
        prw_renderer *r = NULL;
        prw_view v;
        prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
        rd.quality.msaa = 4;
        rd.quality.shadow_size = 256;
        CHECK_OK(prw_view_from_camera(s, 0, 128, 128, &v, &e), &e);
        CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
        CHECK_OK(prw_renderer_render(r, &v, 1, NULL, &e), &e);
        CHECK_OK(prw_renderer_read_hdr(r, 0, &img[k], &e), &e);
        memcpy(levels[k], prw_lod_gpu_levels(prw_lod_scene_model(prw_renderer_lod(r), 0), 0), sizeof(int) * 26);
        prw_renderer_destroy(r);
        prw_scene_destroy(s);
    }
    CHECK(memcmp(levels[0], levels[1], sizeof(int) * 26) == 0);
    double worst = 0;
    for (size_t i = 0; i < 128 * 128 * 4; i++) worst = fmax(worst, fabs(img[0].rgba[i] - img[1].rgba[i]));
    printf("far_from_origin: same levels %s; largest pixel difference at 1e5 m %.3g cd/m^2\n",
           memcmp(levels[0], levels[1], sizeof(int) * 26) ? "no" : "yes", worst);
    CHECK(worst <= 1e-3);
    prw_image_free(&img[0]);
    prw_image_free(&img[1]);
}

/* ---- one choice for a view set ---- */

static void test_view_set(void)
{
    prw_scene *s = setup(k_box_scene);
    if (!s) return;
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = 128, .height = 128, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = 256;
    CHECK_OK(prw_renderer_create(g_gpu, s, &rd, &r, &e), &e);
    prw_lod_scene *ls = prw_renderer_lod(r);
    const prw_lod_model *lm = &prw_lod_scene_hierarchy(ls, 0)->lod;
    prw_nurbs_model m;
    CHECK_OK(prw_scene_nurbs_load(prw_lod_scene_entry(ls, 0), &m, &e), &e);
    prw_lod_gpu *g = NULL;
    prw_lod_gpu_options o = {.single_sided = true};
    CHECK_OK(prw_lod_gpu_create(g_gpu, lm, &m, 3, &o, &g, &e), &e);
    /* two eyes 0.5 m apart looking past the box on either side: each sees a different part */
    prw_view v[2] = {prw_view_look_at(prw_v3(-0.25, 0.8, 3.2), prw_v3(-1.6, 0, 0), prw_v3(0, 1, 0), 40 * PRW_PI / 180, 0.05,
                                      128, 128, 6),
                     prw_view_look_at(prw_v3(0.25, 0.8, 3.2), prw_v3(1.6, 0, 0), prw_v3(0, 1, 0), 40 * PRW_PI / 180, 0.05,
                                      128, 128, 6)};
    prw_dmat4 id = prw_dm4_identity();
    prw_lod_frame_report rep[3] = {{0}, {0}, {0}};
    CHECK_OK(prw_lod_gpu_update(g, 0, id, &v[0], 1, &rep[0], &e), &e);
    CHECK_OK(prw_lod_gpu_update(g, 1, id, &v[1], 1, &rep[1], &e), &e);
    CHECK_OK(prw_lod_gpu_update(g, 2, id, v, 2, &rep[2], &e), &e);
    const unsigned char *d0 = prw_lod_gpu_drawn(g, 0), *d1 = prw_lod_gpu_drawn(g, 1), *d2 = prw_lod_gpu_drawn(g, 2);
    const int *l0 = prw_lod_gpu_levels(g, 0), *l1 = prw_lod_gpu_levels(g, 1), *l2 = prw_lod_gpu_levels(g, 2);
    int union_bad = 0, level_bad = 0, only_one = 0, compared = 0;
    for (int p = 0; p < lm->npatches; p++) {
        union_bad += d2[p] != (d0[p] || d1[p]);
        only_one += d0[p] != d1[p];
        if (d0[p] && d1[p] && d2[p]) { /* drawn for both eyes alone: the pair takes the finer choice */
            compared++;
            level_bad += l2[p] != (l0[p] < l1[p] ? l0[p] : l1[p]);
        }
    }
    printf("view_set: drawn left %llu, right %llu, pair %llu; %d patches seen by one eye only; pair != union: %d; "
           "pair level != finer single-eye level: %d of %d\n",
           (unsigned long long)rep[0].drawn_patches, (unsigned long long)rep[1].drawn_patches,
           (unsigned long long)rep[2].drawn_patches, only_one, union_bad, level_bad, compared);
    CHECK(only_one > 0); /* the eyes do see different parts */
    CHECK(union_bad == 0);
    CHECK(compared > 0 && level_bad == 0);
    prw_lod_gpu_destroy(g);
    prw_nurbs_model_free(&m);
    prw_renderer_destroy(r);
    prw_scene_destroy(s);
}

static void test_unbaked(void)
{
    prw_scene *s = gpu_up() ? load_scene_baked(k_box_scene, false) : NULL;
    CHECK(s != NULL);
    if (!s) return;
    prw_error e = {{0}};
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = 64, .height = 64, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
    rd.quality.shadow_size = 256;
    CHECK(!prw_renderer_create(g_gpu, s, &rd, &r, &e) && r == NULL);
    printf("unbaked: %s\n", e.msg);
    CHECK(strstr(e.msg, "NURBS entry 'box' has no baked hierarchy: call prw_bake_scene") != NULL);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"scene_renders", test_scene_renders},
        {"update_minimal", test_update_minimal},
        {"crack_free_box", test_crack_free_box},
        {"flip_vs_finest", test_flip_vs_finest},
        {"proxy_far_copies", test_proxy_far_copies},
        {"far_from_origin", test_far_from_origin},
        {"view_set", test_view_set},
        {"unbaked", test_unbaked},
    };
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    if (g_gpu) {
        prw_gpu_destroy(g_gpu);
        g_gpu = NULL;
        uint32_t n = prw_gpu_validation_total();
        if (n) {
            fprintf(stderr, "validation: %u messages\n", n);
            rc = 1;
        }
    }
    return rc;
}
