/* prw tmbench — selective vs full local tone mapping (issue 6, must-show 3) on the tone-mapping passes
 * alone: HDR frames of the demo path (rendered once, exposure tone map) and procedural stills of 2,
 * 4 and 6 decades are each uploaded once; then local and selective run alternately (interleaved,
 * rep by rep) on the same input.  Prints per image SSIM / mean LDR-FLIP of selective against local,
 * the marked-tile fraction, the seam measures and the median times; and the ratio of the whole set's
 * time (local / selective) as a median with a paired bootstrap 95 % interval. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "prw_demo.h"
#include "prw_demo_path.h"
#include "prw_metrics.h"
#include "prw_render.h"
#include "prw_stats.h"

static void tmbench_usage(void)
{
    printf("usage: prw tmbench [options]\n"
           "  --size WxH         image size (default 1024x1024)\n"
           "  --frames N         demo-path frames, spread over the 60-frame path (default 10)\n"
           "  --reps N           timed runs per operator and image, interleaved (default 7)\n"
           "  --threshold X      selective Sobel threshold, log10 units per pixel (default 0.1)\n"
           "  --tile N           selective tile size, a multiple of 16 (default 16)\n"
           "  --display PROFILE  display profile (default srgb; SSIM/FLIP read the signal as sRGB)\n"
           "Times are host wall clock around submit + wait of the tone-mapping passes only (stats,\n"
           "classification, global, local); on lavapipe the GPU is the CPU.  Local is timed twice: the\n"
           "separable full-image passes (the reference speed) and the tiled kernel selective uses, on every block.\n");
}

typedef struct tmb_opts {
    uint32_t w, h;
    long frames, reps, tile;
    double threshold;
    const char *display;
} tmb_opts;

static double median_of(const double *x, size_t n)
{
    double *c = prw_malloc(n * sizeof *c);
    memcpy(c, x, n * sizeof *c);
    double m = prw_stats_median(c, n);
    free(c);
    return m;
}

/* One image: quality of selective vs local, and reps interleaved timings into tl (local, separable
 * full-image passes), tt (local, tiled kernel on every block) and ts (selective). */
static bool bench_image(prw_renderer *r, const prw_display *d, const tmb_opts *o, const prw_image *hdr,
                        const char *name, double *tl, double *tt, double *ts, prw_error *e)
{
    prw_tm_session *s = NULL;
    prw_tonemap_settings loc = {.op = PRW_TM_LOCAL}, til = {.op = PRW_TM_LOCAL, .local_tiled = true},
                         sel = {.op = PRW_TM_SELECTIVE, .sel_threshold = o->threshold, .sel_tile = (uint32_t)o->tile};
    prw_image il = {0}, is = {0};
    prw_tm_report rep = {0};
    float *map = NULL;
    bool ok = prw_tm_session_create(r, hdr, &s, e) && prw_renderer_set_tonemap(r, d, &loc, e) &&
              prw_tm_session_run(s, 7.0, NULL, &il, NULL, NULL, e) && prw_renderer_set_tonemap(r, d, &sel, e) &&
              prw_tm_session_run(s, 7.0, NULL, &is, NULL, &rep, e);
    for (long k = 0; ok && k < o->reps; k++)
        ok = prw_renderer_set_tonemap(r, d, &loc, e) && prw_tm_session_run(s, 7.0, &tl[k], NULL, NULL, NULL, e) &&
             prw_renderer_set_tonemap(r, d, &til, e) && prw_tm_session_run(s, 7.0, &tt[k], NULL, NULL, NULL, e) &&
             prw_renderer_set_tonemap(r, d, &sel, e) && prw_tm_session_run(s, 7.0, &ts[k], NULL, NULL, NULL, e);
    double ssim = 0, flip = 0;
    if (ok) {
        map = prw_malloc(sizeof(float) * (size_t)hdr->width * (size_t)hdr->height);
        ok = prw_ssim_encoded(&is, &il, &ssim, e) && prw_flip_ldr_encoded(&is, &il, 67.0, map, e);
    }
    if (ok) {
        size_t n = (size_t)hdr->width * (size_t)hdr->height;
        for (size_t i = 0; i < n; i++) flip += map[i];
        flip /= (double)n;
        int T = (int)o->tile;
        double gs = prw_tm_border_gradient(&is, T), gl = prw_tm_border_gradient(&il, T);
        double js = prw_tm_border_jump(&is, T), jl = prw_tm_border_jump(&il, T);
        double ml = median_of(tl, (size_t)o->reps), mt = median_of(tt, (size_t)o->reps),
               ms = median_of(ts, (size_t)o->reps);
        printf("%-14s SSIM %.4f  FLIP %.4f  marked %5.1f %% (local on %5.1f %% of blocks)  seams: border "
               "gradient %+.4f, jump %+.4f vs local  local %8.2f ms (tiled %8.2f)  selective %8.2f ms  x%.2f "
               "(x%.2f vs tiled)\n",
               name, ssim, flip, 100.0 * (double)rep.tiles_marked / (double)(rep.tiles ? rep.tiles : 1),
               100.0 * (double)rep.blocks_local / (double)(rep.blocks ? rep.blocks : 1), gs - gl, js - jl, ml, mt, ms,
               ml / ms, mt / ms);
        fflush(stdout);
    }
    free(map);
    prw_image_free(&il);
    prw_image_free(&is);
    prw_tm_session_destroy(s);
    return ok;
}

static int run(const tmb_opts *o)
{
    prw_error e = {{0}};
    prw_gpu *gpu = NULL;
    prw_scene *scene = NULL;
    prw_renderer *r = NULL;
    prw_camera_path path = {0};
    bool have_path = false;
    int rc = 1;
    long nimg = o->frames + 3;
    double *tl = prw_calloc((size_t)(nimg * o->reps), sizeof *tl), *ts = prw_calloc((size_t)(nimg * o->reps), sizeof *ts);
    double *tt = prw_calloc((size_t)(nimg * o->reps), sizeof *tt);
    prw_display disp;
    if (!prw_display_resolve(o->display ? o->display : "srgb", &disp, &e)) goto done;
    if (!prw_app_load_scene(NULL, &scene, &e) || !prw_app_create_gpu(false, &gpu, &e)) goto done;
    prw_render_desc rd = {.width = o->w, .height = o->h, .msaa = 1, .shadow_size = 1024, .max_views = 1};
    if (!prw_renderer_create(gpu, scene, &rd, &r, &e)) goto done;
    if (!prw_demo_path_build(&path, prw_v3(0, 0, 0), &e)) goto done;
    have_path = true;
    printf("prw tmbench: %ux%u, %ld demo-path frames + 3 stills, %ld interleaved runs per operator and image, "
           "threshold %g, tile %ld, display %s, device %s\n",
           o->w, o->h, o->frames, o->reps, o->threshold > 0 ? o->threshold : PRW_TM_SEL_THRESHOLD, o->tile,
           disp.name, prw_gpu_device_name(gpu));
    long img = 0;
    for (long f = 0; f < o->frames; f++, img++) {
        uint64_t k = (uint64_t)(f * PRW_DEMO_PATH_FRAMES / o->frames);
        prw_view v;
        prw_image hdr = {0};
        prw_tonemap_settings ex = {.op = PRW_TM_EXPOSURE};
        if (!prw_renderer_set_tonemap(r, &disp, &ex, &e) ||
            !prw_camera_path_frame_view(&path, k, o->w, o->h, 0.05, 7.0, 0, &v, &e) ||
            !prw_renderer_render(r, &v, 1, NULL, &e) || !prw_renderer_read_hdr(r, 0, &hdr, &e))
            goto done;
        char name[32];
        snprintf(name, sizeof name, "demo frame %llu", (unsigned long long)k);
        bool ok = bench_image(r, &disp, o, &hdr, name, tl + img * o->reps, tt + img * o->reps, ts + img * o->reps, &e);
        prw_image_free(&hdr);
        if (!ok) goto done;
    }
    for (int di = 0; di < 3; di++, img++) {
        prw_image hdr = {0};
        double dr = 2.0 * (di + 1);
        if (prw_tm_field(&hdr, (int)o->w, (int)o->h, dr, 21u + (unsigned)di) == 0) {
            prw_fail(&e, "tmbench: out of memory for a %ux%u still", o->w, o->h);
            goto done;
        }
        char name[32];
        snprintf(name, sizeof name, "still dr %.0f", dr);
        bool ok = bench_image(r, &disp, o, &hdr, name, tl + img * o->reps, tt + img * o->reps, ts + img * o->reps, &e);
        prw_image_free(&hdr);
        if (!ok) goto done;
    }
    /* the whole set per rep: paired (rep k of every image) */
    double *sl = prw_calloc((size_t)o->reps, sizeof *sl), *ss = prw_calloc((size_t)o->reps, sizeof *ss),
           *st = prw_calloc((size_t)o->reps, sizeof *st);
    for (long k = 0; k < o->reps; k++)
        for (long i = 0; i < nimg; i++) {
            sl[k] += tl[i * o->reps + k];
            st[k] += tt[i * o->reps + k];
            ss[k] += ts[i * o->reps + k];
        }
    prw_stats_ratio ratio, rt;
    if (prw_stats_bootstrap_median_ratio(ss, (size_t)o->reps, sl, (size_t)o->reps, true, 2000, 12345, &ratio) &&
        prw_stats_bootstrap_median_ratio(ss, (size_t)o->reps, st, (size_t)o->reps, true, 2000, 12346, &rt))
        printf("set of %ld images: local %.1f ms (tiled %.1f ms), selective %.1f ms per pass (medians); speed-up "
               "local/selective x%.2f (95 %% bootstrap interval %.2f .. %.2f); tiled local/selective x%.2f (%.2f .. "
               "%.2f)\n",
               nimg, median_of(sl, (size_t)o->reps), median_of(st, (size_t)o->reps), median_of(ss, (size_t)o->reps),
               ratio.ratio, ratio.lo, ratio.hi, rt.ratio, rt.lo, rt.hi);
    free(sl);
    free(ss);
    free(st);
    rc = 0;
done:
    if (rc) fprintf(stderr, "prw tmbench: error: %s\n", e.msg);
    if (have_path) prw_camera_path_free(&path);
    prw_renderer_destroy(r);
    prw_scene_destroy(scene);
    prw_gpu_destroy(gpu);
    free(tl);
    free(ts);
    free(tt);
    return rc;
}

int prw_cmd_tmbench(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        tmbench_usage();
        prw_args_free(&a);
        return 0;
    }
    tmb_opts o = {.w = 1024, .h = 1024, .frames = 10, .reps = 7, .tile = PRW_TM_SEL_TILE};
    const char *v;
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &o.w, &o.h, &e)) bad = true;
    if ((v = prw_args_value(&a, "frames", &e, &bad)) && !prw_parse_int(v, "--frames", 0, 60, &o.frames, &e))
        bad = true;
    if ((v = prw_args_value(&a, "reps", &e, &bad)) && !prw_parse_int(v, "--reps", 1, 1000, &o.reps, &e)) bad = true;
    if ((v = prw_args_value(&a, "threshold", &e, &bad)) &&
        !prw_parse_double(v, "--threshold", 1e-6, 100, &o.threshold, &e))
        bad = true;
    if ((v = prw_args_value(&a, "tile", &e, &bad)) &&
        (!prw_parse_int(v, "--tile", 16, 256, &o.tile, &e) ||
         (o.tile % 16 && !prw_fail(&e, "--tile %ld: must be a multiple of 16", o.tile))))
        bad = true;
    o.display = prw_args_value(&a, "display", &e, &bad);
    if (!bad && a.positional_count > 0) bad = !prw_fail(&e, "unexpected argument '%s'", a.positional[0]);
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    prw_args_free(&a);
    if (bad) {
        fprintf(stderr, "prw tmbench: error: %s\n", e.msg);
        return 2;
    }
    return run(&o);
}
