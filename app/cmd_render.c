/* prw render — a headless still: EXR of linear radiance (cd/m^2) and PNG of the displayed image. */
#define _XOPEN_SOURCE 700
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <limits.h>
#include <sys/stat.h>

#include "app.h"
#include "lightmaps.h"
#include "prw_build_info.h"
#include "prw_image.h"
#include "prw_render.h"
#include "prw_view.h"
#include "quality_args.h"
#include "render_stereo.h"
#ifdef PRW_HAVE_GLARE
#include "prw_glare.h"
#endif


static void render_usage(void)
{
    printf("usage: prw render [SCENE] [options]\n"
           "  SCENE              manifest (.json), a model (.gltf, .glb, .igs, .iges) or 'demo' (default)\n"
           "  --out FILE.exr     linear HDR output in cd/m^2 (default prw-out/render.exr)\n"
           "  --png FILE.png     display-encoded output (default: --out with .png)\n"
           "  --size WxH         image size (default 1280x720)\n"
           "  --camera NAME      scene camera (default: the first)\n"
           "  --ev100 X          exposure override (default: the camera's)\n"
           "  --frames N         render N timed frames after one warm-up and report the median (default 1)\n"
           "  --no-bake          render without indirect light (no GI light maps); otherwise a scene with static\n"
           "                     meshes and a light source is drawn with its indirect-diffuse light maps, baked\n"
           "                     first (progress on stderr) when the cache has none (prw bake SCENE --gi), and\n"
           "                     with its environment's precomputation (SH, prefiltered maps; cached too);\n"
           "                     the environment variable PRW_NO_BAKE=1 does the same for render, walk and bench\n"
           "  --term T           draw one term only, to compare with prw reference --filter: direct (emission +\n"
           "                     direct light), indirect-diffuse (the light maps' indirect diffuse; --filter\n"
           "                     indirect-diffuse-last) or environment (the environment light, occluded by the\n"
           "                     light maps' visibility; --filter environment-direct), probes (the reflection\n"
           "                     probes on curved glossy objects; --filter indirect-glossy-last there),\n"
           "                     indirect-glossy (the light maps through the specular lobe of rough surfaces\n"
           "                     without a probe), or a comma-separated list of them; default: all\n"
           "%s"
           "  --display PROFILE  display profile: a built-in name (srgb, office-lcd, default-lcd, bright-lcd,\n"
           "                     hdr10-1000, hmd-lcd) or a .json file (default srgb: the ideal sRGB display)\n"
           "  --tonemap OP       exposure, reinhard, neutral, adaptive, absolute, local or selective (default\n"
           "                     exposure); absolute prints the fractions below black / above peak / out of\n"
           "                     gamut, selective the fraction of tiles given the local operator\n"
           "  --tm-threshold X   selective: Sobel threshold in log10 units per pixel (default 0.1)\n"
           "  --tm-tile N        selective: tile size, 16, 32, 48 ... 256 pixels (default 16)\n"
           "  --display-exr FILE linear display-referred light (cd/m^2 through the display model, display\n"
           "                     primaries in the chromaticities attribute) as EXR; on a PQ Rec.2020 display\n"
           "                     (hdr10-1000) the PNG is HDR10: 16-bit PQ with cICP, MaxCLL/MaxFALL in PNG.json\n"
           "  --glare            temporal glare (eye PSF: pupil, lens, lashes; by FFT) on the HDR image before\n"
           "                     tone mapping the PNG / display EXR (the scene EXR stays unglared); off by default\n"
           "  --tm-overlay       paint those pixels (below black blue, above peak red, out of gamut magenta)\n"
           "  --pass-times       time each pass with GPU timestamps (a separate measurement: each\n"
           "                     timestamp flushes on lavapipe, so frame times then include that cost); also\n"
           "                     runs the base pass's floor (its draws with a constant shader) in every frame\n"
           "                     and prints 'floor ms, base ms, base/floor' (medians over --frames)\n"
           "stereo (both eyes as one view set; writes FILE-left.exr, FILE-right.exr, FILE-composed.exr/.png):\n"
           "  --stereo           desktop stereo: off-axis frusta, --size per eye, composed side by side\n"
           "  --ipd M            eye separation in metres (default 0.063)\n"
           "  --screen-distance M  distance of the screen (zero parallax) in metres (default 0.7)\n"
           "  --hmd PROFILE      HMD mode: 'dk2' or a profile .json (assets/hmd/); parallel axes, per-eye\n"
           "                     FOVs, composed panel with barrel pre-distortion and chromatic pre-correction;\n"
           "                     --size sets the panel (default: the profile's)\n"
           "  --sbs              with --hmd: the side-by-side debug view (no distortion)\n"
           "  --views-backend B  loop, multiview or auto (default auto: loop on lavapipe)\n"
           "  --stereo-reuse R   off (default) or reproject: the right eye reuses the left eye's colour where\n"
           "                     both see the same surface (changes pixels; per-view loop backend)\n",
           prw_quality_args_help());
}

typedef struct render_job render_job;
static bool write_display_files(prw_renderer *r, const render_job *job, const prw_display *d, const uint8_t *ldr,
                                const prw_image *hdr, double ev100, prw_error *e);
static void ensure_parent_dir(const char *path);

struct render_job {
    const char *scene_path, *out, *png, *camera;
    const char *display, *tonemap; /* NULL: srgb, exposure */
    bool tm_overlay;
    bool glare; /* temporal glare before tone mapping (display outputs only) */
    double tm_threshold; /* 0: default */
    const char *display_exr; /* display-referred EXR (NULL: none) */
    long tm_tile;        /* 0: default */
    uint32_t width, height;
    prw_quality q; /* the knobs (--preset and shorthands) */
    long frames;
    bool has_ev, pass_times;
    bool no_bake;   /* --no-bake */
    uint32_t terms; /* --term: PRW_TERM_* (0: all) */
    double ev100;
};

/* The display-encoded PNG (HDR10 16-bit PQ + cICP + MaxCLL/MaxFALL sidecar on a PQ Rec.2020 display,
 * else 8-bit) and the optional display-referred EXR; on failure none of them is left. */

static bool write_display_files(prw_renderer *r, const render_job *job, const prw_display *d, const uint8_t *ldr,
                                const prw_image *hdr, double ev100, prw_error *e)
{
    prw_image sig = {0}, light = {0};
    bool hdr10 = d->eotf == PRW_EOTF_PQ && d->primaries == PRW_PRIMARIES_REC2020;
    bool ok = true, png_done = false;
    (void)hdr, (void)ev100;
    /* with --glare the graph's glare stage already glared the display outputs (ldr, signal) */
    if (hdr10 || job->display_exr) ok = prw_renderer_read_signal(r, 0, &sig, e);
    if (ok) {
        ok = hdr10 ? prw_tm_write_hdr10_png(job->png, d, &sig, e)
                   : prw_png_write8(job->png, (int)job->width, (int)job->height, 4, ldr, e);
        png_done = ok;
    }
    if (ok && job->display_exr) {
        float chroma[8];
        prw_tm_display_chroma(d, chroma);
        prw_kv attrs[] = {{"prw:units", "cd/m^2 displayed (display-referred, display primaries)"},
                          {"prw:display", d->name}};
        ensure_parent_dir(job->display_exr);
        ok = prw_tm_display_light(d, &sig, &light, e) &&
             prw_exr_write_chroma(job->display_exr, &light, chroma, attrs, (int)PRW_ARRAY_LEN(attrs), e);
    }
    if (!ok && png_done) {
        char side[PATH_MAX];
        remove(job->png);
        if (hdr10 && snprintf(side, sizeof side, "%s.json", job->png) < (int)sizeof side) remove(side);
    }
    if (ok && job->display_exr) {
        char abs[PATH_MAX];
        printf("wrote %s (display-referred cd/m^2, %s primaries)\n",
               realpath(job->display_exr, abs) ? abs : job->display_exr, prw_primaries_name(d->primaries));
    }
    if (ok && hdr10) {
        double cll, fall;
        prw_tm_light_levels(&sig, &cll, &fall);
        printf("HDR10 PNG: 16-bit PQ, cICP 9/16/0/1, MaxCLL %.0f cd/m^2, MaxFALL %.0f cd/m^2 (sidecar %s.json)\n", cll,
               fall, job->png);
    }
    prw_image_free(&sig);
    prw_image_free(&light);
    return ok;
}

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
    prw_error ignored; /* errors surface at the write */
    prw_mkdirs(dir, &ignored);
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
    double *times = NULL, *bf = NULL;
    prw_app_lightmaps *lms = NULL;
    int rc = 1;
    /* before any work: every output can be written */
    if (!prw_check_writable(job->out, true, &e) || !prw_check_writable(job->png, true, &e) ||
        (job->display_exr && !prw_check_writable(job->display_exr, true, &e)))
        goto done;
    if (!prw_app_load_renderable(job->scene_path, &scene, &e)) goto done;
    int cam = prw_scene_find_camera(scene, job->camera);
    if (cam < 0) {
        prw_fail(&e, "%s: no camera named '%s'", scene->source, job->camera ? job->camera : "(first)");
        goto done;
    }
    prw_view view;
    if (!prw_view_from_camera(scene, cam, job->width, job->height, &view, &e)) goto done;
    if (!prw_app_bake_scene(scene, &e)) goto done;
    if (!prw_app_lightmaps_prepare("render", scene, &job->q, job->no_bake, &lms, &e)) goto done;
    if (job->terms == PRW_TERM_INDIRECT_DIFFUSE && !lms) {
        prw_fail(&e, "--term indirect-diffuse: %s has no light maps (--no-bake, or nothing to bake)", scene->source);
        goto done;
    }
    if (job->terms == PRW_TERM_INDIRECT_GLOSSY && !lms) {
        prw_fail(&e, "--term indirect-glossy: %s has no light maps (--no-bake, or nothing to bake)", scene->source);
        goto done;
    }
    if (job->terms == PRW_TERM_PROBES && !prw_app_lightmaps_probes(lms)) {
        prw_fail(&e, "--term probes: %s has no reflection probes (--no-bake, probe_count=0, or no curved glossy object)",
                 scene->source);
        goto done;
    }
    if (job->has_ev) view.ev100 = job->ev100;
    if (!prw_app_create_gpu(false, &gpu, &e)) goto done;
    prw_display disp;
    if (!prw_display_resolve(job->display ? job->display : "srgb", &disp, &e)) goto done;
    prw_glare_settings gs = {.n = 512, .ppd = disp.ppd > 0 ? disp.ppd : 40.0};
    bool hdr10 = disp.eotf == PRW_EOTF_PQ && disp.primaries == PRW_PRIMARIES_REC2020; /* as write_display_files */
    prw_render_desc rd = {.width = job->width, .height = job->height, .quality = job->q,
                          .timestamps = job->pass_times, .glare = job->glare ? &gs : NULL,
                          .display_signal = hdr10 || job->display_exr,
                          .lightmaps = prw_app_lightmaps_get(lms), .environment = prw_app_lightmaps_env(lms),
                          .probes = prw_app_lightmaps_probes(lms),
                          .terms = job->terms};
    if (!prw_renderer_create(gpu, scene, &rd, &r, &e)) goto done;
    prw_tonemap_settings tms = {.op = (prw_tm_op)job->q.tonemap, .overlay = job->tm_overlay,
                                .sel_threshold = job->tm_threshold, .sel_tile = (uint32_t)job->tm_tile};
    if ((job->tonemap && !prw_tm_op_parse(job->tonemap, &tms.op, &e)) || !prw_renderer_set_tonemap(r, &disp, &tms, &e))
        goto done;
    prw_frame_stats st;
    if (!prw_renderer_render(r, &view, 1, &st, &e)) goto done; /* warm-up: pipelines JIT here */
    times = prw_calloc((size_t)job->frames, sizeof(double));
    bf = prw_calloc(3 * (size_t)job->frames, sizeof(double)); /* per frame: base, floor, base/floor */
    long nbf = 0;
    for (long f = 0; f < job->frames; f++) {
        if (!prw_renderer_render(r, &view, 1, &st, &e)) goto done;
        times[f] = st.cpu_ms;
        double b, fl;
        if (prw_frame_stats_base_floor(&st, &b, &fl) && fl > 0) {
            bf[nbf] = b, bf[job->frames + nbf] = fl, bf[2 * job->frames + nbf] = b / fl;
            nbf++;
        }
    }
    qsort(times, (size_t)job->frames, sizeof(double), cmp_double);
    double median = times[job->frames / 2];
    if (!prw_renderer_read_hdr(r, 0, &hdr, &e)) goto done;
    ldr = prw_malloc((size_t)job->width * job->height * 4);
    if (!prw_renderer_read_ldr(r, 0, ldr, &e)) goto done;
    char ev[32], spp[16];
    snprintf(ev, sizeof ev, "%.4f", view.ev100);
    snprintf(spp, sizeof spp, "%u", job->q.msaa);
    prw_kv attrs[] = {
        {"prw:git", prw_build_git_hash()}, {"prw:scene", scene->source}, {"prw:camera", scene->cameras[cam].name},
        {"prw:ev100", ev},         {"prw:msaa", spp},            {"prw:units", "cd/m^2, linear Rec.709"},
    };
    if (prw_gpu_validation_count(gpu) != 0) { /* a wrong image is not written */
        prw_fail(&e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
        goto done;
    }
    ensure_parent_dir(job->out);
    ensure_parent_dir(job->png);
    if (!prw_exr_write(job->out, &hdr, attrs, (int)PRW_ARRAY_LEN(attrs), &e)) goto done;
    if (!write_display_files(r, job, &disp, ldr, &hdr, view.ev100, &e)) {
        remove(job->out); /* no partial output: all files or none */
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
    if (tms.op == PRW_TM_SELECTIVE && rep.tiles)
        printf("selective tone mapping: %llu of %llu tiles marked, local operator on %llu of %llu 16x16 blocks\n",
               (unsigned long long)rep.tiles_marked, (unsigned long long)rep.tiles,
               (unsigned long long)rep.blocks_local, (unsigned long long)rep.blocks);
    if (st.glare_pupil_mm > 0)
        printf("glare: pupil %.2f mm, PSF radius %d px at %.0f ppd (a host stage of the graph)\n", st.glare_pupil_mm,
               st.glare_psf_radius, gs.ppd);
    printf("frame time %.2f ms (median of %ld, %ux%u, %ux MSAA, %ux%u supersampling, %llu triangles, device %s)\n",
           median, job->frames, job->width, job->height, job->q.msaa, job->q.supersample, job->q.supersample,
           (unsigned long long)st.triangles, prw_gpu_device_name(gpu));
    for (uint32_t i = 0; i < st.pass_count; i++) {
        if (st.passes[i].skipped) printf("  pass %-10s skipped (%s)\n", st.passes[i].name, st.passes[i].reason);
        else if (st.passes[i].gpu_ms >= 0)
            printf("  pass %-10s %8.3f ms (%s)\n", st.passes[i].name, st.passes[i].gpu_ms,
                   st.passes[i].host_clock ? "host clock, own submit" : "GPU timestamps");
        else printf("  pass %-10s ran\n", st.passes[i].name);
    }
    if (nbf > 0) {
        /* floor and base run in the same frames: the ratio's median is over per-frame ratios */
        for (int k = 0; k < 3; k++) qsort(bf + k * job->frames, (size_t)nbf, sizeof(double), cmp_double);
        printf("floor ms %.3f, base ms %.3f, base/floor %.2f (medians of %ld frames, both in every frame%s)\n",
               bf[job->frames + nbf / 2], bf[nbf / 2], bf[2 * job->frames + nbf / 2], nbf,
               nbf < 30 ? "; --frames 30 or more for a figure" : "");
    }
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw: error: %s\n", e.msg[0] ? e.msg : "render failed");
    free(times);
    free(bf);
    free(ldr);
    prw_image_free(&hdr);
    prw_renderer_destroy(r);
    prw_app_lightmaps_destroy(lms);
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
    render_job job = {.out = "prw-out/render.exr", .width = 1280, .height = 720, .frames = 1};
    const char *v;
    if ((v = prw_args_value(&a, "out", &e, &bad))) job.out = v;
    job.png = prw_args_value(&a, "png", &e, &bad);
    job.camera = prw_args_value(&a, "camera", &e, &bad);
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &job.width, &job.height, &e)) bad = true;
    prw_quality_args_read(&a, &job.q, &bad, &e);
    if ((v = prw_args_value(&a, "ev100", &e, &bad))) {
        job.has_ev = prw_parse_double(v, "--ev100", -20, 40, &job.ev100, &e);
        bad = bad || !job.has_ev;
    }
    if ((v = prw_args_value(&a, "frames", &e, &bad)) && !prw_parse_int(v, "--frames", 1, 100000, &job.frames, &e))
        bad = true;
    job.pass_times = prw_args_flag(&a, "pass-times");
    job.no_bake = prw_args_flag(&a, "no-bake");
    if ((v = prw_args_value(&a, "term", &e, &bad))) { /* a comma-separated list */
        char list[256];
        snprintf(list, sizeof list, "%s", v);
        for (char *save = NULL, *t = strtok_r(list, ",", &save); t && !bad; t = strtok_r(NULL, ",", &save)) {
            if (!strcmp(t, "direct")) job.terms |= PRW_TERM_DIRECT;
            else if (!strcmp(t, "indirect-diffuse")) job.terms |= PRW_TERM_INDIRECT_DIFFUSE;
            else if (!strcmp(t, "environment")) job.terms |= PRW_TERM_ENVIRONMENT;
            else if (!strcmp(t, "probes")) job.terms |= PRW_TERM_PROBES;
            else if (!strcmp(t, "indirect-glossy")) job.terms |= PRW_TERM_INDIRECT_GLOSSY;
            else if (!strcmp(t, "all")) job.terms |= PRW_TERM_ALL;
            else bad = true, prw_fail(&e, "--term '%s': expected direct, indirect-diffuse, environment, probes, "
                                   "indirect-glossy or all",
                                   t);
        }
    }
    if (!bad && job.no_bake && job.terms == PRW_TERM_INDIRECT_DIFFUSE)
        bad = true, prw_fail(&e, "--term indirect-diffuse needs the light maps: not with --no-bake");
    if (!bad && job.no_bake && job.terms == PRW_TERM_INDIRECT_GLOSSY)
        bad = true, prw_fail(&e, "--term indirect-glossy needs the light maps: not with --no-bake");
    job.display = prw_args_value(&a, "display", &e, &bad);
    job.tonemap = prw_args_value(&a, "tonemap", &e, &bad);
    job.tm_overlay = prw_args_flag(&a, "tm-overlay");
    job.display_exr = prw_args_value(&a, "display-exr", &e, &bad);
    job.glare = prw_args_flag(&a, "glare");
    if ((v = prw_args_value(&a, "tm-threshold", &e, &bad)) &&
        !prw_parse_double(v, "--tm-threshold", 1e-6, 100, &job.tm_threshold, &e))
        bad = true;
    if ((v = prw_args_value(&a, "tm-tile", &e, &bad)) &&
        (!prw_parse_int(v, "--tm-tile", 16, 256, &job.tm_tile, &e) ||
         (job.tm_tile % 16 && !prw_fail(&e, "--tm-tile %ld: must be a multiple of 16", job.tm_tile))))
        bad = true;
    {
        prw_display d;
        prw_tm_op op;
        if (!bad && ((job.display && !prw_display_resolve(job.display, &d, &e)) ||
                     (job.tonemap && !prw_tm_op_parse(job.tonemap, &op, &e))))
            bad = true;
        if (!bad && job.tonemap) job.q.tonemap = op; /* --tonemap is the knob tonemap too */
    }
    /* stereo (issue 5) */
    prw_stereo_job sj = {.ipd = -1};
    bool stereo = prw_args_flag(&a, "stereo");
    bool size_given = false;
    for (int i = 1; i < argc; i++) size_given = size_given || strncmp(argv[i], "--size", 6) == 0;
    sj.hmd = prw_args_value(&a, "hmd", &e, &bad);
    sj.sbs_debug = prw_args_flag(&a, "sbs");
    sj.views_backend = prw_args_value(&a, "views-backend", &e, &bad);
    bool reuse = job.q.stereo_reuse != PRW_STEREO_REUSE_OFF;
    if ((v = prw_args_value(&a, "ipd", &e, &bad)) && !prw_parse_double(v, "--ipd", 0, 0.2, &sj.ipd, &e)) bad = true;
    if ((v = prw_args_value(&a, "screen-distance", &e, &bad)) &&
        !prw_parse_double(v, "--screen-distance", 0.06, 1e4, &sj.screen_distance, &e))
        bad = true;
    if (!bad && stereo && sj.hmd) bad = true, prw_fail(&e, "--stereo and --hmd exclude each other");
    if (!bad && !stereo && !sj.hmd && (sj.ipd >= 0 || sj.screen_distance > 0 || sj.sbs_debug || sj.views_backend))
        bad = true, prw_fail(&e, "--ipd, --screen-distance, --sbs and --views-backend need --stereo or --hmd");
    if (!bad && !stereo && !sj.hmd && reuse) bad = true, prw_fail(&e, "--stereo-reuse needs --stereo or --hmd");
    if (!bad && sj.hmd && (sj.ipd >= 0 || sj.screen_distance > 0))
        bad = true, prw_fail(&e, "--ipd and --screen-distance are for --stereo; --hmd takes them from the profile");
    if (!bad && !sj.hmd && sj.sbs_debug) bad = true, prw_fail(&e, "--sbs is for --hmd (desktop stereo is always side by side)");
    if (!bad && sj.views_backend && strcmp(sj.views_backend, "loop") && strcmp(sj.views_backend, "multiview") &&
        strcmp(sj.views_backend, "auto"))
        bad = true, prw_fail(&e, "--views-backend '%s': expected loop, multiview or auto", sj.views_backend);
    if (!bad && (stereo || sj.hmd) && (job.q.supersample > 1 || job.frames > 1 || job.pass_times || job.png ||
                                        job.tm_overlay))
        bad = true, prw_fail(&e, "--ss, --frames, --pass-times, --png and --tm-overlay are not available with --stereo/--hmd");
    if (!bad && sj.hmd && size_given && job.width % 2)
        bad = true, prw_fail(&e, "--size %ux%u: the HMD panel needs an even width", job.width, job.height);
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count > 1) bad = true, prw_fail(&e, "render takes one SCENE, got %d", a.positional_count);
    if (bad) {
        fprintf(stderr, "prw render: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    job.scene_path = a.positional_count ? a.positional[0] : NULL;
    if (stereo || sj.hmd) {
        sj.scene_path = job.scene_path;
        sj.out = job.out;
        sj.camera = job.camera;
        sj.display = job.display;
        sj.tonemap = job.tonemap;
        sj.width = sj.hmd && !size_given ? 0 : job.width;
        sj.height = sj.hmd && !size_given ? 0 : job.height;
        sj.q = job.q;
        sj.has_ev = job.has_ev;
        sj.ev100 = job.ev100;
        int rc = prw_stereo_job_run(&sj);
        prw_args_free(&a);
        return rc;
    }
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
                      .frames = 5, .q = prw_quality_default()};
    return prw_render_job_run(&job);
}
