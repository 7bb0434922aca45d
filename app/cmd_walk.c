/* prw walk — the desktop walkthrough: a GLFW window loop around the pure simulation
 * (engine/view/prw_walk.h), the shared input handlers (walk_input.h), input scripts
 * (walk_script.h), the HUD (walk_hud.h), recording and replay of camera paths, screenshots and
 * dynamic resolution.
 *
 * Frame loop: poll window events (GLFW callbacks -> walk_input) -> frame clock (wall clock, or
 * frame / --fps for a deterministic render rate) -> fixed simulation steps up to the clock, script
 * events delivered before the step they are due at -> record the pose at the simulation time ->
 * render at the dynamic-resolution level -> screenshot (full size) -> HUD -> present.
 * Dynamic resolution keeps one renderer per scale level (0.5, 0.625, 0.75, 0.875, 1.0 of --size),
 * created on first use, and blits the chosen level's display image to the window.
 */
#define _XOPEN_SOURCE 700
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "app.h"
#include "lightmaps.h"
#include "quality_args.h"
#include "prw_build_info.h"
#include "prw_camera_path.h"
#include "prw_image.h"
#include "prw_lod_render.h"
#include "prw_render.h"
#include "prw_swapchain.h"
#include "prw_view.h"
#include "prw_walk.h"
#include "walk_hud.h"
#include "walk_input.h"
#include "walk_measure.h"
#include "walk_script.h"


#define PI 3.14159265358979323846
#define LEVELS 5
#define HUD_ROWS 8
static const double level_scale[LEVELS] = {0.5, 0.625, 0.75, 0.875, 1.0};

static void walk_usage(void)
{
    printf("usage: prw walk [SCENE] [options]\n"
           "  --size WxH          render size at scale 1 (default 1280x720; the window scales it)\n"
           "  --camera NAME       start camera (default: the first)\n"
           "  --frames N          exit after N frames (0 = run until closed; default 0)\n"
           "%s"
           "  --display PROFILE   display profile: built-in name or .json file (default srgb)\n"
           "  --tonemap OP        exposure, reinhard, neutral, adaptive or absolute (default exposure)\n"
           "  --mode fly|walk     start mode (default fly); walk follows the ground at 1.7 m eye height\n"
           "  --speed M/S         start speed (default 1.5)\n"
           "  --fps N             deterministic frame clock: frame k is at time k/N s (default: wall clock)\n"
           "  --target-ms X       dynamic resolution: scale the render size in 0.5..1 to reach X ms\n"
           "  --input-script F    timed input events fed to the same handlers as the keyboard/mouse\n"
           "  --record PATH.json  record the walk (the pose at each frame) as a camera path (prw bench input)\n"
           "  --replay PATH.json  play a camera path instead of walking\n"
           "  --shot-dir DIR      screenshot folder (default prw-out)\n"
           "  --no-hud            start with the HUD hidden (H toggles it)\n"
           "  --no-pass-times     no GPU timestamps (the HUD then shows no per-pass times)\n"
           "  --no-bake           render without indirect light (no GI light maps); otherwise the scene's\n"
           "                      indirect-diffuse light maps are drawn, baked first when the cache has none\n"
           "  --adapt             temporal adaptation of the tone mapper (one state; auto-exposure operators)\n"
           "  --adapt-up-s S      its time constant towards brighter scenes (default 0.4; implies --adapt)\n"
           "  --adapt-down-s S    its time constant towards darker scenes (default 4; implies --adapt)\n"
           "  --measure-width W   [R] measures at W pixels wide (default 160)\n"
           "  --measure-spp N     reference samples per pixel for [R] (default 32)\n"
           "  controls: WASD move, Q/E down/up, right mouse drag to look, +/- or wheel speed, F fly/walk,\n"
           "            H HUD, F12 screenshot (EXR + PNG), R measure the error of the current view against\n"
           "            the reference path tracer (blocking; shown on the HUD and printed), Esc quits\n",
           prw_quality_args_help());
}

typedef struct walk_opts {
    const char *scene, *camera, *display, *tonemap, *script, *record, *replay, *shot_dir;
    uint32_t w, h, measure_width, measure_spp;
    prw_quality q; /* the knobs (--preset and shorthands) */
    long frames;
    double fps, target_ms, speed, adapt_up_s, adapt_down_s;
    bool walk_mode, hud, pass_times, adapt;
    bool no_bake;
} walk_opts;

typedef struct walk_ctx {
    const walk_opts *o;
    prw_gpu *gpu;
    prw_scene *scene;
    prw_display disp;
    prw_tonemap_settings tms;
    prw_renderer *level[LEVELS];
    walk_script script;
    bool have_script;
    walk_input in;
    int shots;
    walk_measure measure; /* the last [R] measurement */
    prw_app_lightmaps *lightmaps; /* the scene's GI bake (NULL: none, or --no-bake) */
} walk_ctx;

/* The renderer of scale level lv, created on first use (*created: this call made it). */
static bool get_renderer(walk_ctx *c, int lv, prw_renderer **out, bool *created, prw_error *e)
{
    *created = !c->level[lv];
    if (!c->level[lv]) {
        prw_render_desc rd = {.width = prw_dynres_size(c->o->w, level_scale[lv]),
                              .height = prw_dynres_size(c->o->h, level_scale[lv]),
                              .quality = c->o->q,
                              .timestamps = c->o->pass_times,
                              .lightmaps = prw_app_lightmaps_get(c->lightmaps),
                              .environment = prw_app_lightmaps_env(c->lightmaps),
                              .probes = prw_app_lightmaps_probes(c->lightmaps)};
        if (!prw_renderer_create(c->gpu, c->scene, &rd, &c->level[lv], e)) return false;
        if (!prw_renderer_set_tonemap(c->level[lv], &c->disp, &c->tms, e)) return false;
    }
    *out = c->level[lv];
    return true;
}

static void blit_to(VkCommandBuffer cmd, prw_gpu_image *src, prw_gpu_image *dst)
{
    prw_cmd_transition(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    prw_cmd_transition(cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkImageBlit2 region = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_BLIT_2,
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .srcOffsets = {{0, 0, 0}, {(int32_t)src->width, (int32_t)src->height, 1}},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstOffsets = {{0, 0, 0}, {(int32_t)dst->width, (int32_t)dst->height, 1}},
    };
    VkBlitImageInfo2 info = {
        .sType = VK_STRUCTURE_TYPE_BLIT_IMAGE_INFO_2,
        .srcImage = src->image,
        .srcImageLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
        .dstImage = dst->image,
        .dstImageLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
        .regionCount = 1,
        .pRegions = &region,
        .filter = VK_FILTER_LINEAR,
    };
    vkCmdBlitImage2(cmd, &info);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ---------------------------------------------------------------- GLFW callbacks -> walk_input */
static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode, (void)mods;
    walk_input_key(glfwGetWindowUserPointer(w), key, action);
}
static void on_cursor(GLFWwindow *w, double x, double y) { walk_input_cursor(glfwGetWindowUserPointer(w), x, y); }
static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    (void)mods;
    walk_input_button(glfwGetWindowUserPointer(w), button, action);
}
static void on_scroll(GLFWwindow *w, double dx, double dy) { walk_input_scroll(glfwGetWindowUserPointer(w), dx, dy); }

/* before each fixed step: script events due by the step's start time */
static void before_step(void *user, prw_walk_sim *s, double t)
{
    (void)s;
    walk_ctx *c = user;
    if (c->have_script) walk_script_deliver(&c->script, t, &c->in);
}

/* ---------------------------------------------------------------- screenshots */
static bool ensure_dir(const char *dir, prw_error *e)
{
    struct stat st;
    if (stat(dir, &st) == 0) return S_ISDIR(st.st_mode) ? true : prw_fail(e, "--shot-dir %s: not a directory", dir);
    prw_error me;
    if (!prw_mkdirs(dir, &me)) return prw_fail(e, "--shot-dir %s: cannot create it (%s)", dir, me.msg);
    return true;
}

/* Renders the view at full size and writes <dir>/<name>.exr (linear HDR) and .png atomically. */
static bool screenshot(walk_ctx *c, const prw_view *v_in, double sim_t, prw_error *e)
{
    prw_renderer *r;
    bool created;
    if (!get_renderer(c, LEVELS - 1, &r, &created, e)) return false;
    prw_view v = *v_in;
    prw_frame_stats st;
    if (!prw_renderer_render(r, &v, 1, &st, e)) return false;
    char name[96], exr[PATH_MAX], png[PATH_MAX];
    if (c->in.screenshot_name[0]) snprintf(name, sizeof name, "%s", c->in.screenshot_name);
    else snprintf(name, sizeof name, "walk-%lld-%03d", (long long)time(NULL), c->shots);
    c->shots++;
    if (!ensure_dir(c->o->shot_dir, e)) return false;
    snprintf(exr, sizeof exr, "%s/%s.exr", c->o->shot_dir, name);
    snprintf(png, sizeof png, "%s/%s.png", c->o->shot_dir, name);
    prw_image hdr = {0};
    uint8_t *ldr = prw_malloc((size_t)v.width * v.height * 4);
    bool ok = prw_renderer_read_hdr(r, 0, &hdr, e) && prw_renderer_read_ldr(r, 0, ldr, e);
    char ev[32], tt[32];
    snprintf(ev, sizeof ev, "%.4f", v.ev100);
    snprintf(tt, sizeof tt, "%.6f", sim_t);
    prw_kv attrs[] = {{"prw:git", prw_build_git_hash()}, {"prw:scene", c->scene->source}, {"prw:ev100", ev},
                      {"prw:walk_time_s", tt},   {"prw:units", "cd/m^2, linear Rec.709"}};
    if (ok && prw_gpu_validation_count(c->gpu) != 0)
        ok = prw_fail(e, "%u Vulkan validation messages (see above); screenshot not written", prw_gpu_validation_count(c->gpu));
    ok = ok && prw_exr_write(exr, &hdr, attrs, (int)PRW_ARRAY_LEN(attrs), e);
    if (ok && !prw_png_write8(png, (int)v.width, (int)v.height, 4, ldr, e)) {
        remove(exr); /* both files or none */
        ok = false;
    }
    if (ok) {
        char a1[PATH_MAX], a2[PATH_MAX];
        printf("screenshot: wrote %s (linear HDR, cd/m^2) and %s (t = %.3f s)\n", realpath(exr, a1) ? a1 : exr,
               realpath(png, a2) ? a2 : png, sim_t);
        fflush(stdout);
    }
    free(ldr);
    prw_image_free(&hdr);
    c->in.screenshot = false;
    c->in.screenshot_name[0] = '\0';
    return ok;
}

/* ---------------------------------------------------------------- HUD text */
static void hud_lines(char lines[HUD_ROWS][96], int *n, const walk_ctx *c, const prw_walk_sim *sim, bool replay,
                      double t, double dur, const prw_frame_stats *st, double frame_ms, uint32_t rw, uint32_t rh,
                      const prw_camera_path *rec, prw_dvec3 eye, double yaw, double pitch, const prw_lod_scene *lod)
{
    int k = 0;
    if (replay) snprintf(lines[k++], 96, "REPLAY %.2f / %.2f s   [H] HUD [F12] shot [Esc] quit", t, dur);
    else
        snprintf(lines[k++], 96, "%s %.2f m/s  t %.2f s  [F] fly/walk [H] HUD [F12] shot",
                 sim->state.mode == PRW_WALK_FLY ? "FLY" : "WALK", sim->state.speed, t);
    if (c->o->target_ms > 0)
        snprintf(lines[k++], 96, "frame %.1f ms  render %.1f ms  %ux%u (target %.0f ms)", frame_ms, st->cpu_ms, rw, rh,
                 c->o->target_ms);
    else snprintf(lines[k++], 96, "frame %.1f ms  render %.1f ms  %ux%u", frame_ms, st->cpu_ms, rw, rh);
    if (c->o->pass_times) {
        char *p = lines[k];
        size_t left = 96;
        int m = snprintf(p, left, "GPU ms:");
        for (uint32_t i = 0; i < st->pass_count && m > 0 && (size_t)m < left; i++) {
            if (st->passes[i].skipped || st->passes[i].gpu_ms < 0) continue;
            p += m, left -= (size_t)m;
            m = snprintf(p, left, " %s %.2f", st->passes[i].name, st->passes[i].gpu_ms);
        }
        k++;
    }
    snprintf(lines[k++], 96, "triangles %llu  draws %u", (unsigned long long)st->triangles, st->draws);
    if (lod) {
        const prw_lod_frame_report *lr = prw_lod_scene_last_report(lod);
        snprintf(lines[k++], 96, "LOD: %llu patches drawn %llu culled, %llu proxies, %llu tris, %llu uploads, worst %.2f px",
                 (unsigned long long)lr->drawn_patches, (unsigned long long)lr->culled_patches,
                 (unsigned long long)lr->proxy_instances, (unsigned long long)lr->triangles,
                 (unsigned long long)lr->reuploaded, lr->max_px);
    }
    snprintf(lines[k++], 96, "eye %.2f %.2f %.2f m  yaw %.1f pitch %.1f deg", eye.x, eye.y, eye.z, yaw * 180 / PI,
             pitch * 180 / PI);
    if (c->measure.have) {
        char beyond[32];
        if (c->measure.below_noise) snprintf(beyond, sizeof beyond, "below ref noise");
        else snprintf(beyond, sizeof beyond, "%.3f beyond noise", c->measure.beyond_noise);
        snprintf(lines[k++], 96, "vs ref: LDR-FLIP %.3f, noise %.3f: %s; %ux%u %llu spp, %.0f s ago [R]",
                 c->measure.ldr_flip, c->measure.noise_flip, beyond, c->measure.width, c->measure.height,
                 (unsigned long long)c->measure.spp, prw_now() - c->measure.when);
    }
    else snprintf(lines[k++], 96, "[R] measure the error against the reference path tracer");
    if (c->o->record) snprintf(lines[k++], 96, "REC %u keys -> %.60s", rec->count, c->o->record);
    *n = k;
}

/* ---------------------------------------------------------------- the loop */
static int walk_run(const walk_opts *o)
{
    walk_ctx c = {.o = o};
    prw_error e = {{0}};
    int rc = 1;
    prw_swapchain *sc = NULL;
    GLFWwindow *win = NULL;
    bool glfw = false;
    prw_walk_ground *ground = NULL;
    prw_camera_path replay = {0}, rec = {0};
    walk_hud *hud = NULL;
    prw_walk_sim sim;

    /* outputs and inputs first: an unwritable output, a bad script or path fails before any window opens */
    if (!prw_check_writable_dir(o->shot_dir, true, &e) || (o->record && !prw_check_writable(o->record, false, &e)))
        goto done;
    if (o->script) {
        if (!walk_script_load(o->script, &c.script, &e)) goto done;
        c.have_script = true;
    }
    if (o->replay && !prw_camera_path_load(o->replay, &replay, &e)) goto done;
    if (!prw_app_load_renderable(o->scene, &c.scene, &e)) goto done;
    int cam = prw_scene_find_camera(c.scene, o->camera);
    if (cam < 0) {
        prw_fail(&e, "%s: no camera named '%s'", c.scene->source, o->camera ? o->camera : "(first)");
        goto done;
    }
    c.tms.op = (prw_tm_op)o->q.tonemap;
    c.tms.adapt = o->adapt;
    c.tms.tau_bright = o->adapt_up_s;
    c.tms.tau_dark = o->adapt_down_s;
    if (!prw_display_resolve(o->display ? o->display : "srgb", &c.disp, &e) ||
        (o->tonemap && !prw_tm_op_parse(o->tonemap, &c.tms.op, &e)))
        goto done;
    prw_view view;
    if (!prw_view_from_camera(c.scene, cam, o->w, o->h, &view, &e)) goto done;
    if (!prw_app_bake_scene(c.scene, &e)) goto done;
    if (!prw_app_lightmaps_prepare("walk", c.scene, &o->q, o->no_bake, &c.lightmaps, &e)) goto done;
    const double ev100 = view.ev100, yfov = c.scene->cameras[cam].yfov;
    const double znear = c.scene->cameras[cam].znear > 0 ? c.scene->cameras[cam].znear : 0.05;
    {
        const double *m = view.view.m; /* row 2 of the view matrix is +Z of the eye */
        double yaw, pitch;
        prw_walk_yaw_pitch(prw_v3(-m[2], -m[6], -m[10]), &yaw, &pitch);
        prw_walk_sim_init(&sim, NULL, view.eye, yaw, pitch, o->speed);
    }
    if (!prw_walk_ground_create_scene(c.scene, &ground, &e)) goto done;
    sim.ground = ground;
    if (o->walk_mode) sim.state.mode = PRW_WALK_GROUND;
    walk_input_init(&c.in, &sim);
    prw_camera_path_init(&rec, o->fps > 0 ? o->fps : PRW_CAMERA_PATH_DEFAULT_FPS);

    if (!glfwInit()) {
        prw_fail(&e, "walk: cannot open a window (no display? GLFW failed to initialise); use 'prw render'");
        goto done;
    }
    glfw = true;
    if (!glfwVulkanSupported()) {
        prw_fail(&e, "walk: GLFW reports no Vulkan loader");
        goto done;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    win = glfwCreateWindow((int)o->w, (int)o->h, "prw walk", NULL, NULL);
    if (!win) {
        prw_fail(&e, "walk: cannot create a %ux%u window", o->w, o->h);
        goto done;
    }
    glfwSetWindowUserPointer(win, &c.in);
    glfwSetKeyCallback(win, on_key);
    glfwSetCursorPosCallback(win, on_cursor);
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetScrollCallback(win, on_scroll);
    if (!prw_app_create_gpu(true, &c.gpu, &e)) goto done;
    if (!prw_swapchain_create(c.gpu, win, true, &sc, &e)) goto done;
    if (!walk_hud_create(c.gpu, 80, HUD_ROWS, o->w >= 1600 ? 2 : 1, &hud, &e)) goto done;

    prw_dynres dyn;
    prw_dynres_init(&dyn, o->target_ms, 0.5, 1.0);
    bool hud_on = o->hud;
    const double duration = o->replay ? prw_camera_path_duration(&replay) : 0;
    const double t_first = o->replay ? replay.keys[0].t : 0;
    double t_start = prw_now(), t_prev = t_start, frame_ms = 0, sim_t = 0, hud_t = -1;
    long frame = 0;
    uint32_t st_w = o->w, st_h = o->h;
    prw_frame_stats st = {0};
    static double render_ms[4096]; /* the first frames' render times, for the exit summary */
    static double present_s[4096]; /* and the wall clock after each present (frame rate) */
    for (;;) {
        glfwPollEvents();
        if (glfwWindowShouldClose(win)) break;
        double now = prw_now();
        double clock = o->fps > 0 ? (double)frame / o->fps : now - t_start;
        if (frame) frame_ms = frame_ms > 0 ? frame_ms + 0.1 * (1e3 * (now - t_prev) - frame_ms) : 1e3 * (now - t_prev);
        t_prev = now;

        /* advance: replay evaluates the path; walking runs fixed steps */
        prw_dvec3 eye;
        prw_dquat orient;
        double fov = yfov, yaw, pitch;
        prw_camera_sample sample = {0};
        if (o->replay) {
            sim_t = fmin(clock, duration);
            if (c.have_script) walk_script_deliver(&c.script, clock, &c.in);
            sample = prw_camera_path_eval(&replay, t_first + sim_t);
            eye = sample.position;
            orient = sample.orientation;
            fov = sample.yfov;
            prw_dmat4 m = prw_dm4_trs(prw_v3(0, 0, 0), orient, prw_v3(1, 1, 1));
            prw_walk_yaw_pitch(prw_dm4_dir(m, prw_v3(0, 0, -1)), &yaw, &pitch);
        } else {
            if (o->fps <= 0 && clock - prw_walk_time(&sim) > 0.25) { /* a stall: drop the time, do not race */
                t_start += clock - prw_walk_time(&sim) - 0.25;
                clock = now - t_start;
            }
            prw_walk_advance(&sim, clock, 0, before_step, &c);
            sim_t = prw_walk_time(&sim);
            if (c.have_script) walk_script_deliver(&c.script, sim_t, &c.in);
            eye = sim.state.eye;
            orient = prw_walk_orientation(&sim.state);
            yaw = sim.state.yaw;
            pitch = sim.state.pitch;
        }
        if (o->record && (rec.count == 0 || sim_t > rec.keys[rec.count - 1].t + 2 * PRW_CAMERA_PATH_MIN_DT))
            if (!prw_camera_path_record(&rec, sim_t, eye, orient, fov, &e)) goto done;
        if (c.in.quit) break;
        if (c.in.hud_toggle) hud_on = !hud_on, c.in.hud_toggle = false, hud_t = -1;

        /* render at the dynamic-resolution level */
        int lv = LEVELS - 1;
        if (o->target_ms > 0) {
            double best = 1e9;
            for (int i = 0; i < LEVELS; i++)
                if (fabs(level_scale[i] - dyn.scale) < best) best = fabs(level_scale[i] - dyn.scale), lv = i;
        }
        prw_renderer *r;
        bool fresh;
        if (!get_renderer(&c, lv, &r, &fresh, &e)) goto done;
        uint32_t rw = prw_dynres_size(o->w, level_scale[lv]), rh = prw_dynres_size(o->h, level_scale[lv]);
        st_w = rw, st_h = rh;
        prw_view v;
        if (o->replay) v = prw_camera_sample_view(&sample, rw, rh, znear, ev100, 0);
        else {
            prw_dvec3 f = prw_walk_forward(&sim.state);
            v = prw_view_look_at(eye, prw_v3_add(eye, f), prw_v3(0, 1, 0), fov, znear, rw, rh, ev100);
        }
        if (o->adapt) prw_renderer_tonemap_advance(r, o->fps > 0 ? 1.0 / o->fps : -1.0);
        if (!prw_renderer_render(r, &v, 1, &st, &e)) goto done;
        if (frame < (long)(sizeof render_ms / sizeof render_ms[0])) render_ms[frame] = st.cpu_ms;
        if (o->target_ms > 0 && !fresh && frame > 0) {
            /* the controller's model: cost ~ scale^2; map the level's time to its scale.  A new renderer's
             * first frame (pipeline compilation) is not a sample. */
            double q = dyn.scale / level_scale[lv];
            prw_dynres_update(&dyn, st.cpu_ms * q * q);
        }
        if (c.in.screenshot) {
            prw_view full = v;
            if (o->replay) full = prw_camera_sample_view(&sample, o->w, o->h, znear, ev100, 0);
            else full = prw_view_look_at(eye, prw_v3_add(eye, prw_walk_forward(&sim.state)), prw_v3(0, 1, 0), fov,
                                         znear, o->w, o->h, ev100);
            if (!screenshot(&c, &full, sim_t, &e)) goto done;
        }
        if (c.in.measure) {
            c.in.measure = false;
            prw_view full = v;
            if (o->replay) full = prw_camera_sample_view(&sample, o->w, o->h, znear, ev100, 0);
            prw_render_desc md = {.quality = o->q, .lightmaps = prw_app_lightmaps_get(c.lightmaps),
                                  .environment = prw_app_lightmaps_env(c.lightmaps),
                                  .probes = prw_app_lightmaps_probes(c.lightmaps)};
            fprintf(stderr, "walk: measuring the error against the reference (%u px wide, %u spp)...\n", o->measure_width,
                    o->measure_spp);
            if (!walk_measure_run(c.gpu, c.scene, &full, &md, o->measure_width, o->measure_spp, 0, &c.measure, &e))
                goto done;
            printf("walk: t %.3f s: raster vs reference LDR-FLIP %.4f, reference noise %.4f (seed 2 vs 1), beyond "
                   "noise %.4f%s, %ux%u, %llu spp each, %.1f s\n",
                   sim_t, c.measure.ldr_flip, c.measure.noise_flip, c.measure.beyond_noise,
                   c.measure.below_noise ? " (below reference noise)" : "", c.measure.width, c.measure.height,
                   (unsigned long long)c.measure.spp, c.measure.seconds);
            hud_t = -1;
            t_start += c.measure.seconds; /* the measurement is not walking time */
        }
        if (hud_on && (hud_t < 0 || now - hud_t >= 0.25 || (o->fps > 0 && frame % 8 == 0))) { /* text at ~4 Hz */
            hud_t = now;
            char lines[HUD_ROWS][96];
            const char *lp[HUD_ROWS];
            int n;
            hud_lines(lines, &n, &c, &sim, o->replay != NULL, sim_t, duration, &st, frame_ms, rw, rh, &rec, eye, yaw,
                      pitch, prw_renderer_lod(r));
            for (int i = 0; i < n; i++) lp[i] = lines[i];
            if (!walk_hud_upload(c.gpu, hud, lp, n, &e)) goto done;
        }

        VkCommandBuffer cmd;
        prw_gpu_image *target;
        bool skip = false;
        if (!prw_swapchain_begin_frame(c.gpu, sc, &cmd, &target, &skip, &e)) {
            if (!skip) goto done;
        } else {
            blit_to(cmd, prw_renderer_ldr_image(r, 0), target);
            if (hud_on) walk_hud_record(cmd, hud, target);
            if (!prw_swapchain_end_frame(c.gpu, sc, &e)) goto done;
        }
        if (frame < (long)(sizeof present_s / sizeof present_s[0])) present_s[frame] = prw_now();
        frame++;
        if (o->frames && frame >= o->frames) break;
        if (o->replay && clock >= duration) break;
    }
    if (!prw_gpu_wait_idle(c.gpu, &e)) goto done;
    printf("walk: presented %ld frames, %.3f s of %s\n", frame, sim_t, o->replay ? "replay" : "simulation");
    {
        char diff[1024];
        prw_quality def = prw_quality_default();
        prw_quality_format_diff(&o->q, &def, diff, sizeof diff);
        printf("walk: quality %s%s\n", diff[0] ? "high;" : "high (the default)", diff);
    }
    double la;
    if (o->adapt && frame > 0 && c.level[LEVELS - 1] && prw_renderer_tonemap_adaptation(c.level[LEVELS - 1], &la))
        printf("walk: adapted luminance %.4g cd/m^2 (time constants %.3g s up, %.3g s down)\n", la,
               o->adapt_up_s > 0 ? o->adapt_up_s : PRW_TM_TAU_BRIGHT, o->adapt_down_s > 0 ? o->adapt_down_s : PRW_TM_TAU_DARK);
    if (frame > 1) { /* frame 0 compiles pipelines: not counted */
        long m = frame < 4096 ? frame : 4096;
        qsort(render_ms + 1, (size_t)(m - 1), sizeof(double), cmp_double);
        printf("walk: render time median %.2f ms over %ld frames (CPU: record + submit + wait; %s)\n",
               render_ms[1 + (m - 1) / 2], m - 1, o->pass_times ? "with GPU timestamps" : "no timestamps");
    }
    if (frame > 2) { /* intervals between presents from frame 1 on (frame 0 compiles pipelines) */
        long m = frame < 4096 ? frame : 4096, k = 0;
        for (long i = 2; i < m; i++) present_s[k++] = present_s[i] - present_s[i - 1];
        qsort(present_s, (size_t)k, sizeof(double), cmp_double);
        double dt = present_s[(k - 1) / 2];
        printf("walk: frame rate median %.2f frames per second over %ld frames (wall clock between presents: "
               "render, tone map, blit, HUD, present)\n",
               dt > 0 ? 1.0 / dt : 0.0, k);
    }
    if (o->target_ms > 0)
        printf("walk: dynamic resolution to %.1f ms: scale %.3f, last frame %ux%u (render %.2f ms)\n", o->target_ms,
               dyn.scale, st_w, st_h, st.cpu_ms);
    if (o->record) {
        if (rec.count < 2) {
            prw_fail(&e, "--record %s: only %u keyframe(s) recorded (a camera path needs 2); nothing written", o->record,
                     rec.count);
            goto done;
        }
        if (!prw_camera_path_save(&rec, o->record, &e)) goto done;
        char abs[PATH_MAX];
        printf("walk: recorded %u keyframes (%.3f s) to %s\n", rec.count, prw_camera_path_duration(&rec),
               realpath(o->record, abs) ? abs : o->record);
    }
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw: error: %s\n", e.msg[0] ? e.msg : "walk failed");
    walk_hud_destroy(c.gpu, hud);
    for (int i = 0; i < LEVELS; i++) prw_renderer_destroy(c.level[i]);
    if (sc) prw_swapchain_destroy(c.gpu, sc);
    if (c.gpu) {
        prw_gpu_destroy(c.gpu);
        if (prw_gpu_validation_total() != 0) {
            fprintf(stderr, "prw: error: %u Vulkan validation messages (see above)\n", prw_gpu_validation_total());
            rc = 1;
        }
    }
    if (win) glfwDestroyWindow(win);
    if (glfw) glfwTerminate();
    prw_walk_ground_destroy(ground);
    prw_camera_path_free(&replay);
    prw_camera_path_free(&rec);
    walk_script_free(&c.script);
    prw_app_lightmaps_destroy(c.lightmaps);
    prw_scene_destroy(c.scene);
    return rc;
}

int prw_cmd_walk(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        walk_usage();
        prw_args_free(&a);
        return 0;
    }
    walk_opts o = {.w = 1280, .h = 720, .speed = 1.5, .shot_dir = "prw-out", .hud = true, .pass_times = true,
                  .measure_width = 160, .measure_spp = 32};
    long n;
    const char *v;
    o.camera = prw_args_value(&a, "camera", &e, &bad);
    o.display = prw_args_value(&a, "display", &e, &bad);
    o.tonemap = prw_args_value(&a, "tonemap", &e, &bad);
    o.script = prw_args_value(&a, "input-script", &e, &bad);
    o.record = prw_args_value(&a, "record", &e, &bad);
    o.replay = prw_args_value(&a, "replay", &e, &bad);
    if ((v = prw_args_value(&a, "shot-dir", &e, &bad))) o.shot_dir = v;
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &o.w, &o.h, &e)) bad = true;
    if ((v = prw_args_value(&a, "frames", &e, &bad)) && !prw_parse_int(v, "--frames", 0, 100000000, &o.frames, &e))
        bad = true;
    prw_quality_args_read(&a, &o.q, &bad, &e);
    if ((v = prw_args_value(&a, "fps", &e, &bad)) && !prw_parse_double(v, "--fps", 1, 1000, &o.fps, &e)) bad = true;
    if ((v = prw_args_value(&a, "target-ms", &e, &bad)) && !prw_parse_double(v, "--target-ms", 1, 10000, &o.target_ms, &e))
        bad = true;
    if ((v = prw_args_value(&a, "speed", &e, &bad)) && !prw_parse_double(v, "--speed", 0.05, 100, &o.speed, &e)) bad = true;
    if ((v = prw_args_value(&a, "mode", &e, &bad))) {
        if (strcmp(v, "walk") == 0) o.walk_mode = true;
        else if (strcmp(v, "fly") != 0) bad = true, prw_fail(&e, "--mode '%s': expected fly or walk", v);
    }
    if ((v = prw_args_value(&a, "measure-width", &e, &bad))) {
        if (!prw_parse_int(v, "--measure-width", 16, 1920, &n, &e)) bad = true;
        else o.measure_width = (uint32_t)n;
    }
    if ((v = prw_args_value(&a, "measure-spp", &e, &bad))) {
        if (!prw_parse_int(v, "--measure-spp", 2, 65536, &n, &e)) bad = true;
        else o.measure_spp = (uint32_t)n;
    }
    if (prw_args_flag(&a, "adapt")) o.adapt = true;
    if ((v = prw_args_value(&a, "adapt-up-s", &e, &bad))) {
        if (!prw_parse_double(v, "--adapt-up-s", 1e-3, 1e4, &o.adapt_up_s, &e)) bad = true;
        o.adapt = true;
    }
    if ((v = prw_args_value(&a, "adapt-down-s", &e, &bad))) {
        if (!prw_parse_double(v, "--adapt-down-s", 1e-3, 1e4, &o.adapt_down_s, &e)) bad = true;
        o.adapt = true;
    }
    if (prw_args_flag(&a, "no-hud")) o.hud = false;
    if (prw_args_flag(&a, "no-pass-times")) o.pass_times = false;
    o.no_bake = prw_args_flag(&a, "no-bake");
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (bad) {
        fprintf(stderr, "prw walk: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    o.scene = a.positional_count ? a.positional[0] : NULL;
    int rc = walk_run(&o);
    prw_args_free(&a);
    return rc;
}
