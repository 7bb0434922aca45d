/* views_backend — the --views-backend choice (loop | multiview | auto) and the "auto" views backend (issue 5: "chosen per device by measurement").
 *
 * The choice is measured once per device and driver and kept in the project cache
 * ($PRW_CACHE_DIR/views/<key>.json, key = FNV of device name, driver string, driver version and
 * pipeline-cache UUID):
 *  1. correctness: a probe room (walls, floor and ceiling reaching behind the eye so the clipper
 *     cuts them, a sphere, a point light with shadows) is rendered as a desktop stereo pair by both
 *     backends at 96x64; multiview is acceptable only if each eye equals the loop's within relative
 *     L1 <= 1e-5 (the loop is bit-identical to mono: test_stereo_gpu).  Lavapipe 22.3 fails here
 *     (relative L1 ~1e-2: its multiview mis-interpolates clipped triangles);
 *  2. speed: 3 interleaved frames per backend at 256x144 per eye, medians of the wall time of
 *     prw_renderer_render (which waits for the frame); multiview is chosen only if correct and at
 *     least 3 % faster.
 * A cache entry that cannot be read or parsed is measured again and rewritten (atomic rename); an entry
 * that chooses multiview is trusted only after the correctness probe (1.) passes again, else the loop is
 * chosen and the entry rewritten (a forged or stale entry cannot pick a backend that is wrong here).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "prw_render.h"
#include "prw_stereo.h"

#define PROBE_TOL 1e-5

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static bool build_probe(prw_scene *s, prw_error *e)
{
    prw_material wall = prw_material_default();
    wall.double_sided = true;
    int mw = prw_scene_add_material(s, &wall);
    prw_material ball = prw_material_default();
    ball.base_color[0] = 0.8f, ball.base_color[1] = 0.3f, ball.base_color[2] = 0.2f;
    ball.roughness = 0.3f;
    int mb = prw_scene_add_material(s, &ball);
    if (mw < 0 || mb < 0) return prw_fail(e, "views backend probe: cannot add materials");
    /* a 6 x 3 x 8 m room around the eye at (0, 1.6, 2): every wall reaches behind the eye */
    if (prw_scene_add_box(s, "room", prw_v3(-3, 0, -4), prw_v3(3, 3, 4), mw, true, e) < 0 ||
        prw_scene_add_sphere(s, "ball", prw_v3(0.4, 0.6, -1), 0.6, 24, 12, mb, e) < 0)
        return false;
    prw_light l = {.type = PRW_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 200, .cast_shadows = true};
    snprintf(l.name, sizeof l.name, "probe light");
    prw_node n = prw_node_default();
    snprintf(n.name, sizeof n.name, "probe light");
    n.translation = prw_v3(-1, 2.6, 0);
    l.node = prw_scene_add_node(s, &n);
    if (l.node < 0 || prw_scene_add_light(s, &l) < 0) return prw_fail(e, "views backend probe: cannot add the light");
    prw_scene_update(s);
    return true;
}

static double rel_l1(const prw_image *a, const prw_image *b)
{
    size_t n = (size_t)a->width * a->height * 4;
    double s = 0, d = 0;
    for (size_t i = 0; i < n; i++) {
        s += fabs(a->rgba[i]);
        d += fabs((double)a->rgba[i] - b->rgba[i]);
    }
    return s > 0 ? d / s : (d > 0 ? INFINITY : 0);
}

/* Renders the probe pair with both backends; fills rel (worst eye) and, unless correctness_only, the
 * median times. */
static bool measure(prw_gpu *gpu, prw_views_choice *c, bool correctness_only, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    prw_renderer *r[2] = {NULL, NULL};
    prw_image img[2][2] = {{{0}}};
    bool ok = build_probe(s, e);
    prw_view centre = prw_view_look_at(prw_v3(0, 1.6, 2), prw_v3(0.2, 1.0, -2), prw_v3(0, 1, 0), 1.0, 0.05, 96, 64, 5.0);
    prw_view eyes[2];
    if (ok) ok = prw_stereo_desktop(&centre, 0.063, 0.7, eyes, e);
    for (int b = 0; b < 2 && ok; b++) {
        prw_render_desc d = {.width = 96, .height = 64, .max_views = 2, .quality = prw_quality_default(),
                             .views_backend = b ? PRW_VIEWS_MULTIVIEW : PRW_VIEWS_LOOP};
        d.quality.shadow_size = 256;
        ok = prw_renderer_create(gpu, s, &d, &r[b], e) && prw_renderer_render(r[b], eyes, 2, NULL, e) &&
             prw_renderer_read_hdr(r[b], 0, &img[b][0], e) && prw_renderer_read_hdr(r[b], 1, &img[b][1], e);
    }
    if (ok) {
        double a = rel_l1(&img[0][0], &img[1][0]), bb = rel_l1(&img[0][1], &img[1][1]);
        c->multiview_rel_l1 = fmax(a, bb);
        c->multiview_ok = c->multiview_rel_l1 <= PROBE_TOL;
    }
    for (int b = 0; b < 2; b++) {
        prw_renderer_destroy(r[b]);
        r[b] = NULL;
        prw_image_free(&img[b][0]);
        prw_image_free(&img[b][1]);
    }
    if (correctness_only) {
        prw_scene_destroy(s);
        return ok;
    }
    /* speed at a size where per-pixel work is visible, interleaved so load drift hits both */
    enum { FRAMES = 3 };
    double t[2][FRAMES];
    if (ok) {
        centre = prw_view_look_at(prw_v3(0, 1.6, 2), prw_v3(0.2, 1.0, -2), prw_v3(0, 1, 0), 1.0, 0.05, 256, 144, 5.0);
        ok = prw_stereo_desktop(&centre, 0.063, 0.7, eyes, e);
    }
    for (int b = 0; b < 2 && ok; b++) {
        prw_render_desc d = {.width = 256, .height = 144, .max_views = 2, .quality = prw_quality_default(),
                             .views_backend = b ? PRW_VIEWS_MULTIVIEW : PRW_VIEWS_LOOP};
        d.quality.shadow_size = 1024;
        ok = prw_renderer_create(gpu, s, &d, &r[b], e) && prw_renderer_render(r[b], eyes, 2, NULL, e); /* warm */
    }
    for (int i = 0; i < FRAMES && ok; i++)
        for (int b = 0; b < 2 && ok; b++) {
            double t0 = prw_now();
            ok = prw_renderer_render(r[b], eyes, 2, NULL, e);
            t[b][i] = (prw_now() - t0) * 1e3;
        }
    if (ok) {
        qsort(t[0], FRAMES, sizeof(double), cmp_double);
        qsort(t[1], FRAMES, sizeof(double), cmp_double);
        c->loop_ms = t[0][FRAMES / 2];
        c->multiview_ms = t[1][FRAMES / 2];
    }
    for (int b = 0; b < 2; b++) prw_renderer_destroy(r[b]);
    prw_scene_destroy(s);
    return ok;
}

static void decide(prw_views_choice *c)
{
    if (!c->multiview_ok) {
        c->backend = PRW_VIEWS_LOOP;
        snprintf(c->reason, sizeof c->reason, "multiview eyes differ from the loop's (relative L1 %.2g > %.0e)",
                 c->multiview_rel_l1, PROBE_TOL);
    } else if (c->multiview_ms < 0.97 * c->loop_ms) {
        c->backend = PRW_VIEWS_MULTIVIEW;
        snprintf(c->reason, sizeof c->reason, "multiview correct and faster (%.1f vs %.1f ms)", c->multiview_ms,
                 c->loop_ms);
    } else {
        c->backend = PRW_VIEWS_LOOP;
        snprintf(c->reason, sizeof c->reason, "multiview correct but not faster (%.1f vs %.1f ms)", c->multiview_ms,
                 c->loop_ms);
    }
}

static void cache_path(prw_gpu *gpu, const char *dir, char *buf, size_t cap)
{
    const VkPhysicalDeviceProperties *p = prw_gpu_properties(gpu);
    uint64_t h = prw_hash64(prw_gpu_device_name(gpu), strlen(prw_gpu_device_name(gpu)), 1469598103934665603ull);
    const char *drv = prw_gpu_driver_info(gpu);
    h = prw_hash64(drv, strlen(drv), h);
    h = prw_hash64(&p->driverVersion, sizeof p->driverVersion, h);
    h = prw_hash64(p->pipelineCacheUUID, VK_UUID_SIZE, h);
    snprintf(buf, cap, "%s/%016llx.json", dir, (unsigned long long)h);
}

/* The entry is tiny and written by us; a strict fixed-format read, anything else = re-measure. */
static bool cache_read(const char *path, prw_views_choice *c)
{
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    char text[512];
    size_t n = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    text[n] = 0;
    char name[16];
    int ok_flag;
    double rel, tl, tm;
    if (sscanf(text, "{\"prw_views_choice\": 1, \"backend\": \"%15[a-z]\", \"multiview_ok\": %d, \"multiview_rel_l1\": %lf, "
                     "\"loop_ms\": %lf, \"multiview_ms\": %lf}",
               name, &ok_flag, &rel, &tl, &tm) != 5)
        return false;
    if (!(isfinite(rel) && isfinite(tl) && isfinite(tm)) || (ok_flag != 0 && ok_flag != 1)) return false;
    c->multiview_ok = ok_flag;
    c->multiview_rel_l1 = rel;
    c->loop_ms = tl;
    c->multiview_ms = tm;
    decide(c);
    return strcmp(name, prw_views_backend_name(c->backend)) == 0; /* consistent with the rule */
}

static void cache_write(const char *path, const prw_views_choice *c)
{
    char tmp[1200];
    snprintf(tmp, sizeof tmp, "%s.%ld.tmp", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) return; /* the cache is an optimisation: a read-only cache only costs a re-measure */
    int w = fprintf(f,
                    "{\"prw_views_choice\": 1, \"backend\": \"%s\", \"multiview_ok\": %d, \"multiview_rel_l1\": %.6g, "
                    "\"loop_ms\": %.3f, \"multiview_ms\": %.3f}\n",
                    prw_views_backend_name(c->backend), c->multiview_ok ? 1 : 0, c->multiview_rel_l1, c->loop_ms,
                    c->multiview_ms);
    if (fclose(f) != 0 || w < 0 || rename(tmp, path) != 0) remove(tmp);
}

bool prw_views_backend_choose(prw_gpu *gpu, prw_views_choice *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    out->backend = PRW_VIEWS_LOOP;
    if (!prw_gpu_features_enabled(gpu)->multiview) {
        snprintf(out->reason, sizeof out->reason, "device lacks the multiview feature");
        return true;
    }
    char dir[1024], path[1100];
    prw_error ce;
    bool have_dir = prw_cache_dir("views", "views backend cache", true, dir, sizeof dir, &ce);
    if (have_dir) {
        cache_path(gpu, dir, path, sizeof path);
        if (cache_read(path, out)) {
            out->from_cache = true;
            if (out->backend != PRW_VIEWS_MULTIVIEW) return true; /* the loop is always right */
            /* anyone can write the cache: an entry choosing multiview is only trusted after the
             * correctness probe (the cheap half of the measurement) passes again on this device */
            prw_views_choice probe = *out;
            if (!measure(gpu, &probe, true, e)) return prw_fail_wrap(e, "views backend auto: checking the cache");
            if (probe.multiview_ok) return true;
            out->from_cache = false;
            out->multiview_ok = false;
            out->multiview_rel_l1 = probe.multiview_rel_l1;
            decide(out);
            snprintf(out->reason, sizeof out->reason,
                     "the cached choice multiview failed the correctness probe (relative L1 %.2g > %.0e): loop",
                     probe.multiview_rel_l1, PROBE_TOL);
            cache_write(path, out);
            return true;
        }
    }
    if (!measure(gpu, out, false, e)) return prw_fail_wrap(e, "views backend auto: measuring the backends");
    decide(out);
    if (have_dir) cache_write(path, out);
    return true;
}

/* ---- names and the --views-backend choice ---- */

const char *prw_views_backend_name(prw_views_backend b) { return b == PRW_VIEWS_MULTIVIEW ? "multiview" : "loop"; }

bool prw_views_backend_resolve(prw_gpu *gpu, const char *name, prw_views_backend *out, prw_error *e)
{
    bool has_mv = prw_gpu_features_enabled(gpu)->multiview;
    const char *dev = prw_gpu_device_name(gpu);
    if (!name || strcmp(name, "auto") == 0) {
        prw_views_choice c;
        if (!prw_views_backend_choose(gpu, &c, e)) return false;
        *out = c.backend;
        return true;
    }
    if (strcmp(name, "loop") == 0) {
        *out = PRW_VIEWS_LOOP;
        return true;
    }
    if (strcmp(name, "multiview") == 0) {
        if (!has_mv) return prw_fail(e, "views backend multiview: device '%s' lacks the multiview feature", dev);
        *out = PRW_VIEWS_MULTIVIEW;
        return true;
    }
    return prw_fail(e, "views backend '%s': expected loop, multiview or auto", name);
}
