/* prw render — a headless still: EXR of linear radiance (cd/m^2) and PNG of the displayed image. */
#define _XOPEN_SOURCE 700
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <limits.h>
#include <sys/stat.h>

#include "app.h"
#include "prw_image.h"
#include "prw_render.h"
#include "prw_view.h"

#ifndef PRW_GIT_HASH
#define PRW_GIT_HASH "unknown"
#endif

static void render_usage(void)
{
    printf("usage: prw render [SCENE] [options]\n"
           "  SCENE              manifest (.json) or 'demo' (default)\n"
           "  --out FILE.exr     linear HDR output in cd/m^2 (default prw-out/render.exr)\n"
           "  --png FILE.png     display-encoded output (default: --out with .png)\n"
           "  --size WxH         image size (default 1280x720)\n"
           "  --camera NAME      scene camera (default: the first)\n"
           "  --msaa 1|4         samples per pixel, resolved in linear HDR (default 4)\n"
           "  --ev100 X          exposure override (default: the camera's)\n"
           "  --frames N         render N timed frames after one warm-up and report the median (default 1)\n"
           "  --shadow-size N    shadow-map resolution (default 1024)\n"
           "  --ss N             N x N supersampling for stills, box-filtered in linear HDR (default 1)\n"
           "  --display PROFILE  display profile: a built-in name (srgb, office-lcd, default-lcd, bright-lcd,\n"
           "                     hdr10-1000, hmd-lcd) or a .json file (default srgb: the ideal sRGB display)\n"
           "  --tonemap OP       exposure, reinhard, neutral, adaptive or absolute (default exposure);\n"
           "                     absolute prints the fractions below black / above peak / out of gamut\n"
           "  --tm-overlay       paint those pixels (below black blue, above peak red, out of gamut magenta)\n"
           "  --pass-times       time each pass with GPU timestamps (a separate measurement: each\n"
           "                     timestamp flushes on lavapipe, so frame times then include that cost)\n");
}

typedef struct render_job {
    const char *scene_path, *out, *png, *camera;
    const char *display, *tonemap; /* NULL: srgb, exposure */
    bool tm_overlay;
    uint32_t width, height, msaa, shadow_size, supersample;
    long frames;
    bool has_ev, pass_times;
    double ev100;
} render_job;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void ensure_parent_dir(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash || slash == path) return;
    char dir[1024];
    size_t n = (size_t)(slash - path);
    if (n >= sizeof dir) return;
    memcpy(dir, path, n);
    dir[n] = '\0';
    mkdir(dir, 0755); /* one level: prw-out/ and the like; errors surface at the write */
}

/* Renders and writes the files; prints paths and the frame time. */
static int prw_render_job_run(const render_job *job)
{
    prw_error e = {{0}};
    prw_scene *scene = NULL;
    prw_gpu *gpu = NULL;
    prw_renderer *r = NULL;
    prw_image hdr = {0};
    uint8_t *ldr = NULL;
    double *times = NULL;
    int rc = 1;
    if (!prw_app_load_scene(job->scene_path, &scene, &e)) goto done;
    int cam = prw_scene_find_camera(scene, job->camera);
    if (cam < 0) {
        prw_fail(&e, "%s: no camera named '%s'", scene->source, job->camera ? job->camera : "(first)");
        goto done;
    }
    prw_view view;
    if (!prw_view_from_camera(scene, cam, job->width, job->height, &view, &e)) goto done;
    if (job->has_ev) view.ev100 = job->ev100;
    if (!prw_app_create_gpu(false, &gpu, &e)) goto done;
    prw_render_desc rd = {.width = job->width, .height = job->height, .msaa = job->msaa,
                          .shadow_size = job->shadow_size, .supersample = job->supersample,
                          .timestamps = job->pass_times};
    if (!prw_renderer_create(gpu, scene, &rd, &r, &e)) goto done;
    prw_display disp;
    prw_tonemap_settings tms = {.op = PRW_TM_EXPOSURE, .overlay = job->tm_overlay};
    if (!prw_display_resolve(job->display ? job->display : "srgb", &disp, &e) ||
        (job->tonemap && !prw_tm_op_parse(job->tonemap, &tms.op, &e)) || !prw_renderer_set_tonemap(r, &disp, &tms, &e))
        goto done;
    prw_frame_stats st;
    if (!prw_renderer_render(r, &view, 1, &st, &e)) goto done; /* warm-up: pipelines JIT here */
    times = prw_calloc((size_t)job->frames, sizeof(double));
    for (long f = 0; f < job->frames; f++) {
        if (!prw_renderer_render(r, &view, 1, &st, &e)) goto done;
        times[f] = st.cpu_ms;
    }
    qsort(times, (size_t)job->frames, sizeof(double), cmp_double);
    double median = times[job->frames / 2];
    if (!prw_renderer_read_hdr(r, 0, &hdr, &e)) goto done;
    ldr = prw_malloc((size_t)job->width * job->height * 4);
    if (!prw_renderer_read_ldr(r, 0, ldr, &e)) goto done;
    char ev[32], spp[16];
    snprintf(ev, sizeof ev, "%.4f", view.ev100);
    snprintf(spp, sizeof spp, "%u", job->msaa);
    prw_kv attrs[] = {
        {"prw:git", PRW_GIT_HASH}, {"prw:scene", scene->source}, {"prw:camera", scene->cameras[cam].name},
        {"prw:ev100", ev},         {"prw:msaa", spp},            {"prw:units", "cd/m^2, linear Rec.709"},
    };
    if (prw_gpu_validation_count(gpu) != 0) { /* a wrong image is not written */
        prw_fail(&e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
        goto done;
    }
    ensure_parent_dir(job->out);
    ensure_parent_dir(job->png);
    if (!prw_exr_write(job->out, &hdr, attrs, (int)PRW_ARRAY_LEN(attrs), &e)) goto done;
    if (!prw_png_write8(job->png, (int)job->width, (int)job->height, 4, ldr, &e)) {
        remove(job->out); /* no partial output: both files or none */
        goto done;
    }
    char abs_out[PATH_MAX], abs_png[PATH_MAX];
    printf("wrote %s (linear HDR, cd/m^2)\n", realpath(job->out, abs_out) ? abs_out : job->out);
    printf("wrote %s (display-encoded for %s, %s %s, tone map %s, EV100 %.2f)\n",
           realpath(job->png, abs_png) ? abs_png : job->png, disp.name, prw_eotf_name(disp.eotf),
           prw_primaries_name(disp.primaries), prw_tm_op_name(tms.op), view.ev100);
    prw_tm_report rep;
    if (prw_renderer_tonemap_report(r, NULL, &rep) && rep.pixels)
        printf("display range %.3g..%.4g cd/m^2: %.2f %% below black, %.2f %% above peak, %.2f %% out of gamut\n",
               prw_display_min(&disp), prw_display_max(&disp), 100.0 * (double)rep.below_black / (double)rep.pixels,
               100.0 * (double)rep.above_peak / (double)rep.pixels, 100.0 * (double)rep.out_of_gamut / (double)rep.pixels);
    printf("frame time %.2f ms (median of %ld, %ux%u, %ux MSAA, %ux%u supersampling, %llu triangles, device %s)\n",
           median, job->frames, job->width, job->height, job->msaa, job->supersample, job->supersample,
           (unsigned long long)st.triangles, prw_gpu_device_name(gpu));
    for (uint32_t i = 0; i < st.pass_count; i++) {
        if (st.passes[i].skipped) printf("  pass %-10s skipped\n", st.passes[i].name);
        else if (st.passes[i].gpu_ms >= 0) printf("  pass %-10s %8.3f ms (GPU timestamps)\n", st.passes[i].name, st.passes[i].gpu_ms);
        else printf("  pass %-10s ran\n", st.passes[i].name);
    }
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw: error: %s\n", e.msg[0] ? e.msg : "render failed");
    free(times);
    free(ldr);
    prw_image_free(&hdr);
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

static char *png_path_for(const char *exr)
{
    size_t n = strlen(exr);
    char *p = prw_malloc(n + 5);
    memcpy(p, exr, n + 1);
    if (n > 4 && strcmp(p + n - 4, ".exr") == 0) p[n - 4] = '\0';
    strcat(p, ".png");
    return p;
}

int prw_cmd_render(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        render_usage();
        prw_args_free(&a);
        return 0;
    }
    render_job job = {.out = "prw-out/render.exr", .width = 1280, .height = 720, .msaa = 4, .frames = 1};
    const char *v;
    long n;
    if ((v = prw_args_value(&a, "out", &e, &bad))) job.out = v;
    job.png = prw_args_value(&a, "png", &e, &bad);
    job.camera = prw_args_value(&a, "camera", &e, &bad);
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &job.width, &job.height, &e)) bad = true;
    if ((v = prw_args_value(&a, "msaa", &e, &bad))) {
        if (!prw_parse_int(v, "--msaa", 1, 4, &n, &e) || (n != 1 && n != 4))
            bad = true, prw_fail(&e, "--msaa '%s': lavapipe offers 1 or 4", v);
        job.msaa = (uint32_t)n;
    }
    if ((v = prw_args_value(&a, "ev100", &e, &bad))) {
        job.has_ev = prw_parse_double(v, "--ev100", -20, 40, &job.ev100, &e);
        bad = bad || !job.has_ev;
    }
    if ((v = prw_args_value(&a, "frames", &e, &bad)) && !prw_parse_int(v, "--frames", 1, 100000, &job.frames, &e))
        bad = true;
    job.shadow_size = 1024;
    if ((v = prw_args_value(&a, "shadow-size", &e, &bad))) {
        if (!prw_parse_int(v, "--shadow-size", 16, 8192, &n, &e)) bad = true;
        job.shadow_size = (uint32_t)n;
    }
    job.pass_times = prw_args_flag(&a, "pass-times");
    job.supersample = 1;
    if ((v = prw_args_value(&a, "ss", &e, &bad))) {
        if (!prw_parse_int(v, "--ss", 1, 8, &n, &e)) bad = true;
        job.supersample = (uint32_t)n;
    }
    job.display = prw_args_value(&a, "display", &e, &bad);
    job.tonemap = prw_args_value(&a, "tonemap", &e, &bad);
    job.tm_overlay = prw_args_flag(&a, "tm-overlay");
    {
        prw_display d;
        prw_tm_op op;
        if (!bad && ((job.display && !prw_display_resolve(job.display, &d, &e)) ||
                     (job.tonemap && !prw_tm_op_parse(job.tonemap, &op, &e))))
            bad = true;
    }
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count > 1) bad = true, prw_fail(&e, "render takes one SCENE, got %d", a.positional_count);
    if (bad) {
        fprintf(stderr, "prw render: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    job.scene_path = a.positional_count ? a.positional[0] : NULL;
    char *png = job.png ? NULL : png_path_for(job.out);
    if (png) job.png = png;
    int rc = prw_render_job_run(&job);
    free(png);
    prw_args_free(&a);
    return rc;
}

int prw_run_demo(void)
{
    const char *display = getenv("DISPLAY");
    const char *wayland = getenv("WAYLAND_DISPLAY");
    if ((display && display[0]) || (wayland && wayland[0])) {
        char *argv[] = {NULL};
        return prw_cmd_walk(0, argv);
    }
    printf("prw: no display: rendering the demo headless\n");
    render_job job = {.out = "prw-out/demo.exr", .png = "prw-out/demo.png", .width = 1280, .height = 720,
                      .msaa = 4, .frames = 5, .shadow_size = 1024, .supersample = 1};
    return prw_render_job_run(&job);
}
