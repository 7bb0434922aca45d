/* render_stereo — headless stereo stills; see render_stereo.h. */
#define _XOPEN_SOURCE 700
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "app.h"
#include "lightmaps.h"
#include "prw_build_info.h"
#include "prw_compose.h"
#include "prw_hmd.h"
#include "prw_image.h"
#include "prw_render.h"
#include "render_stereo.h"


static void parent_dir(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash || slash == path) return;
    char dir[1024];
    size_t n = (size_t)(slash - path);
    if (n >= sizeof dir) return;
    memcpy(dir, path, n);
    dir[n] = '\0';
    prw_error ignored; /* a failure surfaces at the write */
    prw_mkdirs(dir, &ignored);
}

/* FILE.exr -> FILE-left.exr, FILE-right.exr, FILE-composed.exr, FILE-composed.png */
static void stereo_paths(const char *out, char paths[4][1100])
{
    char base[1024];
    snprintf(base, sizeof base, "%s", out);
    size_t n = strlen(base);
    if (n > 4 && strcmp(base + n - 4, ".exr") == 0) base[n - 4] = '\0';
    static const char *const suffix[4] = {"-left.exr", "-right.exr", "-composed.exr", "-composed.png"};
    for (int i = 0; i < 4; i++) snprintf(paths[i], sizeof paths[i], "%s%s", base, suffix[i]);
}

static void quantise(const prw_image *sig, uint8_t *out)
{
    size_t n = (size_t)sig->width * sig->height * 4;
    for (size_t i = 0; i < n; i++) {
        float x = sig->rgba[i] * 255.0f + 0.5f;
        out[i] = (uint8_t)(x < 0 ? 0 : x > 255 ? 255 : x);
    }
}

/* A composed panel image of the last frame (RGBA32F, exported by the compose pass). */
static bool read_panel(prw_renderer *r, const char *name, prw_image *out, prw_error *e)
{
    void *px;
    uint32_t w, h;
    if (!prw_renderer_read_image(r, name, 0, &px, &w, &h, e)) return false;
    out->width = (int)w;
    out->height = (int)h;
    out->rgba = px;
    return true;
}

int prw_stereo_job_run(const prw_stereo_job *job)
{
    prw_error e = {{0}};
    prw_scene *scene = NULL;
    prw_gpu *gpu = NULL;
    prw_renderer *r = NULL;
    prw_image hdr[2] = {{0}}, sig[2] = {{0}}, comp_hdr = {0}, comp_sig = {0};
    uint8_t *png = NULL;
    int rc = 1, written = 0;
    char paths[4][1100];
    prw_hmd hmd;
    prw_stereo_setup st;
    stereo_paths(job->out, paths);
    for (int i = 0; i < 4; i++) /* before any work */
        if (!prw_check_writable(paths[i], true, &e)) goto done;
    if (job->hmd && !prw_hmd_resolve(job->hmd, &hmd, &e)) goto done;
    if (!prw_app_load_renderable(job->scene_path, &scene, &e)) goto done;
    int cam = prw_scene_find_camera(scene, job->camera);
    if (cam < 0) {
        prw_fail(&e, "%s: no camera named '%s'", scene->source, job->camera ? job->camera : "(first)");
        goto done;
    }
    prw_view centre;
    uint32_t cw = job->hmd ? 64 : job->width, ch = job->hmd ? 64 : job->height;
    if (!prw_view_from_camera(scene, cam, cw, ch, &centre, &e)) goto done;
    if (!prw_app_bake_scene(scene, &e)) goto done;
    {
        const char *why;
        if (prw_app_lightmaps_wanted(scene, &why)) /* the light-map shaders have no multiview / reprojection variant */
            fprintf(stderr, "prw render: stereo: drawn without indirect light (the GI light maps are drawn in mono "
                            "renders only)\n");
    }
    if (job->has_ev) centre.ev100 = job->ev100;
    if (job->hmd) {
        if (!prw_stereo_setup_hmd(&centre, &hmd, job->width, job->height, &st, &e)) goto done;
        if (job->sbs_debug)
            prw_compose_params_sbs(st.eye_w, st.eye_h, st.compose.out_w, st.compose.out_h, &st.compose);
    } else if (!prw_stereo_setup_desktop(&centre, job->ipd >= 0 ? job->ipd : PRW_STEREO_DEFAULT_IPD_M,
                                         job->screen_distance > 0 ? job->screen_distance
                                                                  : PRW_STEREO_DEFAULT_SCREEN_DISTANCE_M,
                                         &st, &e)) {
        goto done;
    }
    if (!prw_app_create_gpu(false, &gpu, &e)) goto done;
    prw_views_backend backend;
    /* stereo_reuse=reproject exists for the per-view loop only: auto means loop then */
    const char *vb = job->q.stereo_reuse && !job->views_backend ? "loop" : job->views_backend;
    if (!prw_views_backend_resolve(gpu, vb, &backend, &e)) goto done;
    prw_render_desc rd = {.width = st.eye_w, .height = st.eye_h, .quality = job->q, .max_views = 2,
                          .views_backend = backend, .compose = &st.compose, .display_signal = true};
    if (!prw_renderer_create(gpu, scene, &rd, &r, &e)) goto done;
    prw_display disp;
    prw_tonemap_settings tms = {.op = (prw_tm_op)job->q.tonemap};
    if (job->display) {
        if (!prw_display_resolve(job->display, &disp, &e)) goto done;
    } else if (job->hmd) {
        if (!prw_display_resolve("hmd-lcd", &disp, &e)) goto done;
        snprintf(disp.name, sizeof disp.name, "hmd-lcd@%.48s", hmd.name);
        disp.peak = hmd.peak_luminance; /* the panel's peak from the HMD profile */
        disp.ref_white = 0.8 * disp.peak;
        if (!prw_display_validate(&disp, hmd.name, &e)) goto done;
    } else if (!prw_display_resolve("srgb", &disp, &e)) {
        goto done;
    }
    if ((job->tonemap && !prw_tm_op_parse(job->tonemap, &tms.op, &e)) || !prw_renderer_set_tonemap(r, &disp, &tms, &e))
        goto done;
    prw_frame_stats fs;
    if (!prw_renderer_render(r, st.eyes, 2, &fs, &e)) goto done; /* warm-up: pipelines JIT here */
    if (!prw_renderer_render(r, st.eyes, 2, &fs, &e)) goto done;
    for (uint32_t k = 0; k < 2; k++)
        if (!prw_renderer_read_hdr(r, k, &hdr[k], &e) || !prw_renderer_read_signal(r, k, &sig[k], &e)) goto done;
    /* the panel: the graph's compose stage, from both eyes' HDR images and display signals */
    if (!read_panel(r, "panel_hdr", &comp_hdr, &e) || !read_panel(r, "panel_signal", &comp_sig, &e)) goto done;
    if (prw_gpu_validation_count(gpu) != 0) {
        prw_fail(&e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
        goto done;
    }
    parent_dir(paths[0]);
    char ev[32], ipd[32], mode[160];
    snprintf(ev, sizeof ev, "%.4f", centre.ev100);
    snprintf(ipd, sizeof ipd, "%.5f", job->hmd ? hmd.ipd : (job->ipd >= 0 ? job->ipd : PRW_STEREO_DEFAULT_IPD_M));
    if (job->hmd)
        snprintf(mode, sizeof mode, "hmd %s, %s", hmd.name, job->sbs_debug ? "side-by-side debug" : "pre-distorted");
    else
        snprintf(mode, sizeof mode, "desktop off-axis, screen %.3f m",
                 job->screen_distance > 0 ? job->screen_distance : PRW_STEREO_DEFAULT_SCREEN_DISTANCE_M);
    for (int i = 0; i < 3; i++) {
        const prw_image *img = i < 2 ? &hdr[i] : &comp_hdr;
        prw_kv attrs[] = {
            {"prw:git", prw_build_git_hash()}, {"prw:scene", scene->source}, {"prw:camera", scene->cameras[cam].name},
            {"prw:ev100", ev},         {"prw:stereo", mode},          {"prw:ipd_m", ipd},
            {"prw:eye", i == 0 ? "left" : i == 1 ? "right" : "composed"},
            {"prw:units", "cd/m^2, linear Rec.709"},
        };
        if (!prw_exr_write(paths[i], img, attrs, (int)PRW_ARRAY_LEN(attrs), &e)) goto done;
        written++;
    }
    png = prw_malloc((size_t)comp_sig.width * comp_sig.height * 4);
    quantise(&comp_sig, png);
    if (!prw_png_write8(paths[3], comp_sig.width, comp_sig.height, 4, png, &e)) goto done;
    written++;
    for (int i = 0; i < 4; i++) {
        char abs_path[PATH_MAX];
        printf("wrote %s (%s)\n", realpath(paths[i], abs_path) ? abs_path : paths[i],
               i == 0   ? "left eye, linear HDR, cd/m^2"
               : i == 1 ? "right eye, linear HDR, cd/m^2"
               : i == 2 ? "composed, linear HDR, cd/m^2"
                        : "composed, display-encoded");
    }
    printf("stereo: %s, IPD %s m, eyes %ux%u, composed %ux%u, display %s, tone map %s, EV100 %.2f, views backend %s\n",
           mode, ipd, st.eye_w, st.eye_h, st.compose.out_w, st.compose.out_h, disp.name, prw_tm_op_name(tms.op),
           centre.ev100, prw_views_backend_name(backend));
    printf("frame time %.2f ms (both eyes, %ux MSAA, %llu triangles, device %s)\n", fs.cpu_ms, job->q.msaa,
           (unsigned long long)fs.triangles, prw_gpu_device_name(gpu));
    for (uint32_t i = 0; i < fs.pass_count; i++)
        printf("  pass %-10s %s\n", fs.passes[i].name, fs.passes[i].skipped ? "skipped" : "ran");
    rc = 0;
done:
    if (rc != 0) {
        for (int i = 0; i < written; i++) remove(paths[i]); /* no partial output */
        fprintf(stderr, "prw: error: %s\n", e.msg[0] ? e.msg : "stereo render failed");
    }
    free(png);
    for (int k = 0; k < 2; k++) {
        prw_image_free(&hdr[k]);
        prw_image_free(&sig[k]);
    }
    prw_image_free(&comp_hdr);
    prw_image_free(&comp_sig);
    prw_renderer_destroy(r);
    if (gpu) {
        prw_gpu_destroy(gpu);
        if (rc == 0 && prw_gpu_validation_total() != 0) {
            fprintf(stderr, "prw: error: %u Vulkan validation messages (see above)\n", prw_gpu_validation_total());
            rc = 1;
        }
    }
    prw_scene_destroy(scene);
    return rc;
}
