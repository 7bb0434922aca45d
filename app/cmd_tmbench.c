/* prw tmbench — selective vs full local tone mapping (issue 6, must-show 3) on the tone-mapping passes
 * alone: HDR frames of the demo path (rendered once, exposure tone map) and procedural stills of 2,
 * 4 and 6 decades are each uploaded once; then local and selective run alternately (interleaved,
 * rep by rep) on the same input.  Prints per image SSIM / mean LDR-FLIP of selective against local,
 * the marked-tile fraction, the seam measures and the median times; and the ratio of the whole set's
 * time (local / selective) as a median with a paired bootstrap 95 % interval, and the bound the
 * fraction of blocks the local operator must cover puts on that ratio (selective timed with nothing
 * marked gives its global part).  --profile: per-pass times (prefix differences, prw_tm_profile). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

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
           "  --tiled            also time local as the tiled shared-memory kernel (tonemap_local.comp) on every block\n"
           "  --profile          also print per-pass GPU times (timestamps) of one run per operator and image\n"
           "  --vs-copy          instead: the tone-mapping stage against a vkCmdCopyImage of the same image\n"
           "                     (the demo's first frame as RGBA16F, default 1280x720): the exposure tone map (apply\n"
           "                     only, as in the demo), the same with the statistics (counting on: computed in the\n"
           "                     apply pass itself), Reinhard (a statistics pass before the apply), and the\n"
           "                     copy, interleaved for --reps runs (default 30); prints medians and the ratios\n"
           "                     stage/copy with bootstrap 95 %% intervals; and the yardsticks (floors of one pass\n"
           "                     over the image: compute dispatch, read, stores to images and buffers, a fragment\n"
           "                     pass writing colour attachments), interleaved with them\n"
           "Times are host wall clock around submit + wait of the tone-mapping passes only (stats,\n"
           "classification, global, local); on lavapipe the GPU is the CPU.  Local: the separable full-image\n"
           "passes.  Selective is also timed with no tile marked (its global part c_global), which gives the\n"
           "bound c_full / (c_global + f c_full) on the speed-up for the fraction f of blocks the local\n"
           "operator must cover (marked tiles and their blend band).\n");
}

typedef struct tmb_opts {
    uint32_t w, h;
    long frames, reps, tile;
    double threshold;
    const char *display;
    bool profile, tiled, vs_copy;
} tmb_opts;

/* One profiled run of the current settings: prints "label: scope ms, ..." and the total. */
static bool profile_run(prw_tm_session *s, const char *label, prw_error *e)
{
    prw_tm_profile pr;
    if (!prw_tm_session_profile(s, 7.0, 4, &pr, e)) return false;
    double tot = pr.base_ms, bh = 0, bv = 0;
    printf("    %-9s (none %.1f)", label, pr.base_ms);
    for (int i = 0; i < pr.count; i++) {
        size_t n = strlen(pr.names[i]);
        if (strncmp(pr.names[i], "blur", 4) == 0) *(pr.names[i][n - 1] == 'h' ? &bh : &bv) += pr.ms[i];
        else printf(" %s %.1f", pr.names[i], pr.ms[i]);
        tot += pr.ms[i];
    }
    printf(" blur-h %.1f blur-v %.1f = %.1f ms (wall, prefix differences, best of 4)\n", bh, bv, tot);
    return true;
}

static double median_of(const double *x, size_t n)
{
    double *c = prw_malloc(n * sizeof *c);
    memcpy(c, x, n * sizeof *c);
    double m = prw_stats_median(c, n);
    free(c);
    return m;
}

/* Per image: medians (ms) of local, selective and selective with no tile marked (its global part:
 * stats + classification + compaction + global curve on every block), and the fractions of marked
 * tiles and of blocks the local operator runs on. */
typedef struct tmb_img {
    double ml, ms, mg, f_marked, f_needed;
} tmb_img;

/* The speed-up selective could reach if its local part cost exactly the full local operator's time
 * per pixel on the fraction f of the image (no halo, no overhead): c_full / (c_global + f c_full). */
static double bound_of(const tmb_img *im, int n, bool needed)
{
    double a = 0, b = 0;
    for (int i = 0; i < n; i++) {
        a += im[i].ml;
        b += im[i].mg + (needed ? im[i].f_needed : im[i].f_marked) * im[i].ml;
    }
    return b > 0 ? a / b : 0;
}

/* One image: quality of selective vs local, and reps interleaved timings into tl (local, separable
 * full-image passes), ts (selective), tg (selective, no tile marked) and, with --tiled, tt (local,
 * tiled kernel on every block). */
static bool bench_image(prw_renderer *r, const prw_display *d, const tmb_opts *o, const prw_image *hdr,
                        const char *name, double *tl, double *tt, double *ts, double *tg, tmb_img *im, prw_error *e)
{
    prw_tm_session *s = NULL;
    prw_tonemap_settings loc = {.op = PRW_TM_LOCAL}, til = {.op = PRW_TM_LOCAL, .local_tiled = true},
                         sel = {.op = PRW_TM_SELECTIVE, .sel_threshold = o->threshold, .sel_tile = (uint32_t)o->tile};
    prw_tonemap_settings glo = sel;
    glo.sel_threshold = 1e30; /* nothing marked: the selective framework's fixed cost */
    prw_image il = {0}, is = {0};
    prw_tm_report rep = {0};
    float *map = NULL;
    bool ok = prw_tm_session_create(r, hdr, &s, e) && prw_renderer_set_tonemap(r, d, &loc, e) &&
              prw_tm_session_run(s, 7.0, NULL, &il, NULL, NULL, e) && prw_renderer_set_tonemap(r, d, &sel, e) &&
              prw_tm_session_run(s, 7.0, NULL, &is, NULL, &rep, e);
    for (long k = 0; ok && k < o->reps; k++)
        ok = prw_renderer_set_tonemap(r, d, &loc, e) && prw_tm_session_run(s, 7.0, &tl[k], NULL, NULL, NULL, e) &&
             (!o->tiled ||
              (prw_renderer_set_tonemap(r, d, &til, e) && prw_tm_session_run(s, 7.0, &tt[k], NULL, NULL, NULL, e))) &&
             prw_renderer_set_tonemap(r, d, &sel, e) && prw_tm_session_run(s, 7.0, &ts[k], NULL, NULL, NULL, e) &&
             prw_renderer_set_tonemap(r, d, &glo, e) && prw_tm_session_run(s, 7.0, &tg[k], NULL, NULL, NULL, e);
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
        double ml = median_of(tl, (size_t)o->reps), ms = median_of(ts, (size_t)o->reps),
               mg = median_of(tg, (size_t)o->reps);
        *im = (tmb_img){ml, ms, mg, (double)rep.tiles_marked / (double)(rep.tiles ? rep.tiles : 1),
                        (double)rep.blocks_local / (double)(rep.blocks ? rep.blocks : 1)};
        printf("%-14s SSIM %.4f  FLIP %.4f  marked %5.1f %% (local on %5.1f %% of blocks)  seams: border "
               "gradient %+.4f, jump %+.4f vs local  local %8.2f ms  selective %8.2f ms (global part %.2f)  x%.2f "
               "(bound x%.2f)",
               name, ssim, flip, 100.0 * im->f_marked, 100.0 * im->f_needed, gs - gl, js - jl, ml, ms, mg, ml / ms,
               bound_of(im, 1, true));
        if (o->tiled) printf("  tiled local %8.2f ms x%.2f", median_of(tt, (size_t)o->reps), median_of(tt, (size_t)o->reps) / ms);
        printf("\n");
        fflush(stdout);
    }
    if (ok && o->profile)
        ok = prw_renderer_set_tonemap(r, d, &loc, e) && profile_run(s, "local", e) &&
             prw_renderer_set_tonemap(r, d, &sel, e) && profile_run(s, "selective", e);
    free(map);
    prw_image_free(&il);
    prw_image_free(&is);
    prw_tm_session_destroy(s);
    return ok;
}

/* --vs-copy (issue "Speed", must-show 3): the tone-mapping stage at memory speed?  Series, interleaved
 * rep by rep: the copy, the stage (exposure apply; statistics + apply) and the yardsticks
 * (prw_tm_session_time_floor: what a pass over the image costs at least on this device). */
enum { VS_COPY, VS_APPLY, VS_STATS, VS_REIN, VS_FLOOR0, VS_COUNT = VS_FLOOR0 + PRW_TM_FLOOR_COUNT };

/* CPU time of the process (every lavapipe thread), ms: less sensitive to other processes' load than
 * the wall clock, which the must-show ratio uses. */
static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

static void print_vs(const char *label, const double *t, const double *cpu, const double *tc, size_t n, uint64_t seed)
{
    prw_stats_ratio r;
    printf("  %-36s %7.2f ms (cpu %7.2f ms)", label, median_of(t, n), median_of(cpu, n));
    if (prw_stats_bootstrap_median_ratio(tc, n, t, n, true, 2000, seed, &r))
        printf("  x%6.2f copy (95 %% bootstrap interval %.2f .. %.2f)", r.ratio, r.lo, r.hi);
    printf("\n");
}

static int run_vs_copy(const tmb_opts *o)
{
    prw_error e = {{0}};
    prw_gpu *gpu = NULL;
    prw_scene *scene = NULL;
    prw_renderer *r = NULL;
    prw_tm_session *s = NULL;
    prw_image hdr = {0};
    int rc = 1;
    size_t n = (size_t)o->reps;
    double *t[VS_COUNT], *cpu[VS_COUNT];
    for (int i = 0; i < VS_COUNT; i++) t[i] = prw_calloc(n, sizeof *t[i]), cpu[i] = prw_calloc(n, sizeof *cpu[i]);
    prw_display disp;
    if (!prw_display_resolve(o->display ? o->display : "srgb", &disp, &e)) goto done;
    if (!prw_app_load_scene(NULL, &scene, &e) || !prw_app_create_gpu(false, &gpu, &e)) goto done;
    prw_render_desc rd = {.width = o->w, .height = o->h, .max_views = 1, .quality = prw_quality_default()};
    if (!prw_renderer_create(gpu, scene, &rd, &r, &e)) goto done;
    prw_view v;
    prw_tonemap_settings ex = {.op = PRW_TM_EXPOSURE}, exs = {.op = PRW_TM_EXPOSURE, .report = true},
                         rein = {.op = PRW_TM_REINHARD};
    int cam = prw_scene_find_camera(scene, "main");
    if (cam < 0) cam = 0;
    if (!prw_view_from_camera(scene, cam, o->w, o->h, &v, &e) || !prw_renderer_set_tonemap(r, &disp, &ex, &e) ||
        !prw_renderer_render(r, &v, 1, NULL, &e) || !prw_renderer_read_hdr(r, 0, &hdr, &e) ||
        !prw_tm_session_create_half(r, &hdr, &s, &e))
        goto done;
    printf("prw tmbench --vs-copy: %ux%u RGBA16F (the demo, camera main), display %s, %zu interleaved runs, device %s\n",
           o->w, o->h, disp.name, n, prw_gpu_device_name(gpu));
    /* rep -1: warm-up (pipelines built, pages touched) */
    for (long k = -1; k < (long)n; k++) {
        double w, wc, *dst[VS_COUNT], *dc[VS_COUNT], c0;
        for (int i = 0; i < VS_COUNT; i++) dst[i] = k < 0 ? &w : &t[i][k], dc[i] = k < 0 ? &wc : &cpu[i][k];
        c0 = cpu_ms();
        if (!prw_tm_session_time_copy(s, dst[VS_COPY], &e)) goto done;
        *dc[VS_COPY] = cpu_ms() - c0;
        if (!prw_renderer_set_tonemap(r, &disp, &ex, &e)) goto done;
        c0 = cpu_ms();
        if (!prw_tm_session_run(s, v.ev100, dst[VS_APPLY], NULL, NULL, NULL, &e)) goto done;
        *dc[VS_APPLY] = cpu_ms() - c0;
        if (!prw_renderer_set_tonemap(r, &disp, &exs, &e)) goto done;
        c0 = cpu_ms();
        if (!prw_tm_session_run(s, v.ev100, dst[VS_STATS], NULL, NULL, NULL, &e)) goto done;
        *dc[VS_STATS] = cpu_ms() - c0;
        if (!prw_renderer_set_tonemap(r, &disp, &rein, &e)) goto done;
        c0 = cpu_ms();
        if (!prw_tm_session_run(s, v.ev100, dst[VS_REIN], NULL, NULL, NULL, &e)) goto done;
        *dc[VS_REIN] = cpu_ms() - c0;
        for (int f = 0; f < PRW_TM_FLOOR_COUNT; f++) {
            c0 = cpu_ms();
            if (!prw_tm_session_time_floor(s, (prw_tm_floor)f, dst[VS_FLOOR0 + f], &e)) goto done;
            *dc[VS_FLOOR0 + f] = cpu_ms() - c0;
        }
    }
    prw_stats_ratio ra, rs;
    printf("copy %.2f ms, tone map (apply) %.2f ms, tone map (statistics + apply) %.2f ms (medians)\n",
           median_of(t[VS_COPY], n), median_of(t[VS_APPLY], n), median_of(t[VS_STATS], n));
    if (prw_stats_bootstrap_median_ratio(t[VS_COPY], n, t[VS_APPLY], n, true, 2000, 12347, &ra) &&
        prw_stats_bootstrap_median_ratio(t[VS_COPY], n, t[VS_STATS], n, true, 2000, 12348, &rs))
        printf("tone map / copy: apply x%.2f (95 %% bootstrap interval %.2f .. %.2f), statistics + apply x%.2f "
               "(%.2f .. %.2f)\n",
               ra.ratio, ra.lo, ra.hi, rs.ratio, rs.lo, rs.hi);
    printf("medians of the wall time (and of the process CPU time around the call, all threads); wall-time ratios "
           "to the copy (paired by rep) with bootstrap 95 %% intervals:\n");
    print_vs("copy (vkCmdCopyImage, RGBA16F)", t[VS_COPY], cpu[VS_COPY], t[VS_COPY], n, 12340);
    print_vs("tone map: exposure apply", t[VS_APPLY], cpu[VS_APPLY], t[VS_COPY], n, 12347);
    print_vs("tone map: statistics + apply", t[VS_STATS], cpu[VS_STATS], t[VS_COPY], n, 12348);
    print_vs("tone map: reinhard (stats + apply)", t[VS_REIN], cpu[VS_REIN], t[VS_COPY], n, 12349);
    printf(" yardsticks (floors of one pass over the image):\n");
    for (int f = 0; f < PRW_TM_FLOOR_COUNT; f++)
        print_vs(prw_tm_floor_name((prw_tm_floor)f), t[VS_FLOOR0 + f], cpu[VS_FLOOR0 + f], t[VS_COPY], n,
                 12350 + (uint64_t)f);
    rc = 0;
done:
    if (rc) fprintf(stderr, "prw tmbench: error: %s\n", e.msg);
    prw_image_free(&hdr);
    prw_tm_session_destroy(s);
    prw_renderer_destroy(r);
    prw_scene_destroy(scene);
    prw_gpu_destroy(gpu);
    for (int i = 0; i < VS_COUNT; i++) free(t[i]), free(cpu[i]);
    return rc;
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
    double *tg = prw_calloc((size_t)(nimg * o->reps), sizeof *tg);
    tmb_img *im = prw_calloc((size_t)nimg, sizeof *im);
    prw_display disp;
    if (!prw_display_resolve(o->display ? o->display : "srgb", &disp, &e)) goto done;
    if (!prw_app_load_scene(NULL, &scene, &e) || !prw_app_create_gpu(false, &gpu, &e)) goto done;
    prw_render_desc rd = {.width = o->w, .height = o->h, .max_views = 1, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
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
        bool ok = bench_image(r, &disp, o, &hdr, name, tl + img * o->reps, tt + img * o->reps, ts + img * o->reps,
                              tg + img * o->reps, &im[img], &e);
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
        bool ok = bench_image(r, &disp, o, &hdr, name, tl + img * o->reps, tt + img * o->reps, ts + img * o->reps,
                              tg + img * o->reps, &im[img], &e);
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
    double fm = 0, fn = 0, sg = 0;
    for (long i = 0; i < nimg; i++) {
        fm += im[i].f_marked / (double)nimg;
        fn += im[i].f_needed / (double)nimg;
        sg += im[i].mg;
    }
    if (prw_stats_bootstrap_median_ratio(ss, (size_t)o->reps, sl, (size_t)o->reps, true, 2000, 12345, &ratio)) {
        printf("set of %ld images: local %.1f ms, selective %.1f ms per pass (medians); speed-up local/selective "
               "x%.2f (95 %% bootstrap interval %.2f .. %.2f)\n",
               nimg, median_of(sl, (size_t)o->reps), median_of(ss, (size_t)o->reps), ratio.ratio, ratio.lo, ratio.hi);
        printf("bound: mean marked fraction %.3f, local on %.3f of blocks (marked tiles + blend band), global part "
               "%.1f ms of local %.1f ms; speed-up <= c_full / (c_global + f c_full) = x%.2f with f = blocks the "
               "local operator must cover (x%.2f if it covered only the marked tiles)\n",
               fm, fn, sg, median_of(sl, (size_t)o->reps), bound_of(im, (int)nimg, true), bound_of(im, (int)nimg, false));
    }
    if (o->tiled && prw_stats_bootstrap_median_ratio(ss, (size_t)o->reps, st, (size_t)o->reps, true, 2000, 12346, &rt))
        printf("tiled local %.1f ms: tiled local/selective x%.2f (%.2f .. %.2f)\n", median_of(st, (size_t)o->reps),
               rt.ratio, rt.lo, rt.hi);
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
    free(tg);
    free(im);
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
    o.profile = prw_args_flag(&a, "profile");
    o.tiled = prw_args_flag(&a, "tiled");
    o.vs_copy = prw_args_flag(&a, "vs-copy");
    if (!bad && a.positional_count > 0) bad = !prw_fail(&e, "unexpected argument '%s'", a.positional[0]);
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    prw_args_free(&a);
    if (bad) {
        fprintf(stderr, "prw tmbench: error: %s\n", e.msg);
        return 2;
    }
    if (o.vs_copy) {
        bool sized = false, reps = false;
        for (int i = 0; i < argc; i++) sized |= strcmp(argv[i], "--size") == 0, reps |= strcmp(argv[i], "--reps") == 0;
        if (!sized) o.w = 1280, o.h = 720;
        if (!reps) o.reps = 30;
        return run_vs_copy(&o);
    }
    return run(&o);
}
