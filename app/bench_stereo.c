/* bench_stereo — `prw bench --views 2` (issue 5, must-show 4): what a stereo frame costs.
 *
 * Three configurations interleaved frame by frame in one process (timestamps off), the order rotating
 * through all six permutations so none always runs first:
 *   mono    one view (the path's centre camera) on a one-view renderer;
 *   naive   two complete single-view renders (left eye, then right eye) on that renderer: shadow maps,
 *           tone-map statistics and everything else twice;
 *   shared  one two-view frame (desktop off-axis eyes, the path's IPD, screen at 0.7 m) on a two-view
 *           renderer: eye-independent passes once, per-view passes per eye (the chosen views backend).
 * At least 30 frames each (the path's frames, repeated when shorter).  Reported: medians and paired
 * bootstrap 95 % intervals of T_stereo / T_mono and T_stereo / T_naive.  Then a separate timestamped
 * mono run: T_shared = GPU time of the once-per-frame passes (shadow, tm_stats), T_eye = GPU time of
 * the per-view passes (base, downsample, tonemap, extra_work), T_fixed = median frame time - both
 * (recording, submit, wait: once per frame); f_eye = T_eye / T_mono and the ideal stereo ratio
 * (T_fixed + T_shared + 2 T_eye) / T_mono.  Goals: T_stereo <= 0.9 T_naive and <= 1.05 x ideal.
 * With the knob stereo_reuse=reproject (`--stereo-reuse reproject` or in --preset) the shared renderer
 * reuses the left eye's colour in the right eye (engine/render/pass_reproject.c), which changes pixels:
 * every interleaved frame then also reads back the shared frame's right eye and the naive run's right
 * eye (a mono render from the right eye = the fully shaded right eye of a per-view-loop stereo frame,
 * must-show 2) outside the timed regions and reports their LDR-FLIP (the project's metric: metric tone
 * map at the view's EV100, prw_flip_ldr_encoded at 67 ppd, mean per frame) and the share of the right
 * eye's pixels that were shaded rather than reused (resolved alpha of the marked right eye).
 * Writes stereo.csv (frame times) and stereo.json in --out.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "prw_stereo.h"

#define ST_MIN_FRAMES 30
#define ST_RESAMPLES 4000
#define ST_SEED 1
#define ST_SCREEN_DISTANCE 0.7

static bool frame_views(const bench_ctx *c, uint32_t frame, prw_view *centre, prw_view eyes[2], prw_error *e)
{
    if (!bench_frame_view(c, frame, centre, e)) return false;
    prw_camera_sample s = prw_camera_path_eval(&c->path, prw_camera_path_frame_time(&c->path, frame));
    return prw_stereo_desktop(centre, s.ipd_m, ST_SCREEN_DISTANCE, eyes, e);
}

static bool timed(prw_renderer *r, const prw_view *v, uint32_t n, double *ms, prw_error *e)
{
    double t0 = prw_now();
    if (!prw_renderer_render(r, v, n, NULL, e)) return false;
    *ms = (prw_now() - t0) * 1000.0;
    return true;
}

/* LDR-FLIP (mean) of the reprojected right eye (test) against the fully shaded one (ref), and the
 * shaded share (mean alpha of the marked test image).  Frees both images. */
static bool reuse_error(prw_image *test, prw_image *ref, double ev100, double *flip, double *shaded, prw_error *e)
{
    prw_image tt = {0}, rt = {0};
    size_t n = (size_t)ref->width * ref->height;
    float *map = prw_malloc(n * sizeof *map);
    bool ok = prw_metric_tonemap(test, ev100, &tt, e) && prw_metric_tonemap(ref, ev100, &rt, e) &&
              prw_flip_ldr_encoded(&tt, &rt, PRW_FLIP_DEFAULT_PPD, map, e);
    if (ok) {
        prw_flip_stats st;
        prw_flip_pool(map, n, &st);
        *flip = st.mean;
        double a = 0;
        for (size_t i = 0; i < n; i++) a += test->rgba[i * 4 + 3];
        *shaded = a / (double)n;
    }
    free(map);
    prw_image_free(test);
    prw_image_free(ref);
    prw_image_free(&tt);
    prw_image_free(&rt);
    return ok;
}

static bool pass_is_shared(const char *name) { return strcmp(name, "shadow") == 0 || strcmp(name, "tm_stats") == 0; }

bool bench_run_stereo(bench_ctx *c, prw_gpu *gpu, const prw_quality *q, const char *views_backend, prw_error *e)
{
    bench_machine_meta(&c->res.meta, gpu);
    double sr = q->stereo_reuse;
    if (c->o.stereo_reuse && !prw_stereo_reuse_parse(c->o.stereo_reuse, &sr))
        return prw_fail(e, "--stereo-reuse '%s': expected off or reproject", c->o.stereo_reuse);
    bool reuse = sr == PRW_STEREO_REUSE_REPROJECT;
    prw_views_backend backend;
    /* the reprojection exists for the per-view loop only: auto means loop then */
    if (!prw_views_backend_resolve(gpu, reuse && !views_backend ? "loop" : views_backend, &backend, e)) return false;
    prw_render_desc d1 = bench_desc(c, q);
    d1.lightmaps = NULL; /* as prw render --stereo: the light maps have no multiview / reprojection variant, so
                            mono and stereo frames are compared without them */
    d1.max_views = 1;
    prw_render_desc d2 = d1;
    d2.max_views = 2;
    d2.views_backend = backend;
    d2.quality.stereo_reuse = (uint32_t)sr;
    prw_render_debug mark = {.reproject_mark = reuse}; /* alpha only: counts the shaded share, colour unchanged */
    d2.debug = &mark;
    prw_render_desc dts = d1;
    dts.timestamps = true;
    prw_renderer *mono = NULL, *shared = NULL, *ts = NULL;
    uint32_t n = c->nframes > ST_MIN_FRAMES ? c->nframes : ST_MIN_FRAMES;
    double *tm = prw_calloc(n, sizeof *tm), *tn = prw_calloc(n, sizeof *tn), *tsh = prw_calloc(n, sizeof *tsh);
    uint32_t *fr = prw_calloc(n, sizeof *fr);
    double *flip = prw_calloc(n, sizeof *flip), *shaded = prw_calloc(n, sizeof *shaded);
    prw_image full_right = {0}, reused_right = {0};
    bool ok = prw_renderer_create(gpu, c->scene, &d1, &mono, e) && prw_renderer_create(gpu, c->scene, &d2, &shared, e);
    prw_view centre, eyes[2];
    if (ok) ok = frame_views(c, c->frames[0], &centre, eyes, e);
    double dummy;
    for (long w = 0; ok && w < (c->o.warmup > 0 ? c->o.warmup : 1); w++)
        ok = timed(mono, &centre, 1, &dummy, e) && timed(shared, eyes, 2, &dummy, e);
    fprintf(stderr, "bench --views 2: mono / naive stereo / shared stereo (%s backend, stereo_reuse=%s), %ux%u per eye%s\n",
            prw_views_backend_name(backend), reuse ? "reproject" : "off", c->o.width, c->o.height,
            c->lightmaps ? ", without the GI light maps" : "");
    static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    for (uint32_t i = 0; ok && i < n; i++) {
        fr[i] = c->frames[i % c->nframes];
        ok = frame_views(c, fr[i], &centre, eyes, e);
        for (int k = 0; ok && k < 3; k++) {
            int which = perm[i % 6][k];
            if (which == 0) {
                ok = timed(mono, &centre, 1, &tm[i], e);
            } else if (which == 1) {
                double a = 0, b = 0;
                ok = timed(mono, &eyes[0], 1, &a, e) && timed(mono, &eyes[1], 1, &b, e);
                tn[i] = a + b;
                /* untimed: the naive run's right eye = the fully shaded right eye (must-show 2) */
                if (ok && reuse) ok = prw_renderer_read_hdr(mono, 0, &full_right, e);
            } else {
                ok = timed(shared, eyes, 2, &tsh[i], e);
                if (ok && reuse) ok = prw_renderer_read_hdr(shared, 1, &reused_right, e); /* untimed */
            }
        }
        if (ok && reuse) ok = reuse_error(&reused_right, &full_right, eyes[1].ev100, &flip[i], &shaded[i], e);
        fprintf(stderr, "\rframes: %u/%u   ", i + 1, n);
        fflush(stderr);
    }
    fprintf(stderr, "\n");
    prw_image_free(&full_right);
    prw_image_free(&reused_right);
    prw_renderer_destroy(shared);
    shared = NULL;
    /* the separate timestamped mono run */
    uint32_t nts = n < 12 ? n : 12;
    double *ts_frame = prw_calloc(nts, sizeof *ts_frame), *ts_shared = prw_calloc(nts, sizeof *ts_shared),
           *ts_eye = prw_calloc(nts, sizeof *ts_eye);
    char shared_names[256] = "", eye_names[256] = "";
    if (ok) ok = prw_renderer_create(gpu, c->scene, &dts, &ts, e);
    if (ok) ok = frame_views(c, c->frames[0], &centre, eyes, e) && timed(ts, &centre, 1, &dummy, e);
    for (uint32_t i = 0; ok && i < nts; i++) {
        prw_frame_stats st;
        ok = frame_views(c, c->frames[i % c->nframes], &centre, eyes, e);
        double t0 = prw_now();
        ok = ok && prw_renderer_render(ts, &centre, 1, &st, e);
        ts_frame[i] = (prw_now() - t0) * 1000.0;
        for (uint32_t p = 0; ok && p < st.pass_count; p++) {
            if (st.passes[p].skipped || st.passes[p].gpu_ms < 0) continue;
            bool sh = pass_is_shared(st.passes[p].name);
            (sh ? ts_shared : ts_eye)[i] += st.passes[p].gpu_ms;
            if (i == 0) {
                char *list = sh ? shared_names : eye_names;
                size_t len = strlen(list);
                snprintf(list + len, 256 - len, "%s%s", len ? "+" : "", st.passes[p].name);
            }
        }
    }
    prw_renderer_destroy(ts);
    prw_renderer_destroy(mono);
    prw_stats_ratio r_mono, r_naive;
    if (ok && (!prw_stats_bootstrap_median_ratio(tm, n, tsh, n, true, ST_RESAMPLES, ST_SEED, &r_mono) ||
               !prw_stats_bootstrap_median_ratio(tn, n, tsh, n, true, ST_RESAMPLES, ST_SEED, &r_naive)))
        ok = prw_fail(e, "bench --views 2: no ratio (zero frame times)");
    if (ok && prw_gpu_validation_count(gpu) != 0)
        ok = prw_fail(e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
    if (ok) {
        double t_mono_ts = prw_stats_median(ts_frame, nts), t_shared = prw_stats_median(ts_shared, nts);
        double t_eye = prw_stats_median(ts_eye, nts);
        double t_fixed = fmax(0.0, t_mono_ts - t_shared - t_eye);
        double f_eye = t_eye / t_mono_ts, ideal = (t_fixed + t_shared + 2.0 * t_eye) / t_mono_ts;
        double mm = prw_stats_median(tm, n), mn = prw_stats_median(tn, n), ms = prw_stats_median(tsh, n);
        printf("stereo bench: %u interleaved frames each (rotating order), %ux%u per eye, desktop off-axis eyes, "
               "views backend %s\n",
               n, c->o.width, c->o.height, prw_views_backend_name(backend));
        printf("median frame time: mono %.2f ms, naive stereo %.2f ms, shared stereo %.2f ms\n", mm, mn, ms);
        printf("T_stereo/T_mono  = %.3f, 95 %% interval [%.3f, %.3f]\n", r_mono.ratio, r_mono.lo, r_mono.hi);
        printf("T_stereo/T_naive = %.3f, 95 %% interval [%.3f, %.3f] (goal <= 0.9: %s)\n", r_naive.ratio, r_naive.lo,
               r_naive.hi, r_naive.ratio <= 0.9 ? "met" : "NOT met");
        double flip_mean = 0, flip_max = 0, shaded_mean = 0;
        for (uint32_t i = 0; i < n; i++) {
            flip_mean += flip[i] / n;
            flip_max = fmax(flip_max, flip[i]);
            shaded_mean += shaded[i] / n;
        }
        if (reuse)
            printf("stereo_reuse=reproject: right eye vs fully shaded right eye: mean LDR-FLIP %.4f (worst frame %.4f) "
                   "over %u frames; %.1f %% of right-eye pixels shaded, %.1f %% reused\n",
                   flip_mean, flip_max, n, 100.0 * shaded_mean, 100.0 * (1.0 - shaded_mean));
        printf("timestamped mono run (%u frames): T_mono %.2f ms = T_shared %.2f ms (%s) + T_eye %.2f ms (%s) + "
               "T_fixed %.2f ms\n",
               nts, t_mono_ts, t_shared, shared_names[0] ? shared_names : "none", t_eye, eye_names, t_fixed);
        printf("f_eye = %.3f; ideal (T_fixed + T_shared + 2 T_eye)/T_mono = %.3f; T_stereo/T_mono / ideal = %.3f "
               "(goal <= 1.05: %s)\n",
               f_eye, ideal, r_mono.ratio / ideal, r_mono.ratio <= 1.05 * ideal ? "met" : "NOT met");
        char path[4200];
        bench_join(path, sizeof path, c->o.out_dir, "stereo.csv");
        FILE *f = fopen(path, "w");
        if (!f) {
            ok = prw_fail(e, "%s: cannot write", path);
        } else {
            for (int i = 0; i < c->res.meta.count; i++)
                fprintf(f, "# %s: %s\n", c->res.meta.key[i], c->res.meta.value[i]);
            fprintf(f, "i,frame,mono_ms,naive_ms,shared_ms%s\n", reuse ? ",right_ldr_flip,right_shaded" : "");
            for (uint32_t i = 0; i < n; i++) {
                fprintf(f, "%u,%u,%.17g,%.17g,%.17g", i, fr[i], tm[i], tn[i], tsh[i]);
                if (reuse) fprintf(f, ",%.17g,%.17g", flip[i], shaded[i]);
                fprintf(f, "\n");
            }
            ok = fclose(f) == 0 ? true : prw_fail(e, "%s: write failed", path);
        }
        bench_join(path, sizeof path, c->o.out_dir, "stereo.json");
        f = ok ? fopen(path, "w") : NULL;
        if (ok && !f) ok = prw_fail(e, "%s: cannot write", path);
        if (f) {
            fprintf(f,
                    "{\"prw_bench_stereo\": 1, \"frames\": %u, \"width\": %u, \"height\": %u, \"views_backend\": \"%s\", "
                    "\"median_ms\": {\"mono\": %.17g, \"naive\": %.17g, \"shared\": %.17g}, "
                    "\"stereo_over_mono\": [%.17g, %.17g, %.17g], \"stereo_over_naive\": [%.17g, %.17g, %.17g], "
                    "\"timestamped\": {\"frames\": %u, \"t_mono_ms\": %.17g, \"t_shared_ms\": %.17g, \"t_eye_ms\": %.17g, "
                    "\"t_fixed_ms\": %.17g}, \"f_eye\": %.17g, \"ideal\": %.17g, \"resamples\": %d, \"seed\": %d, "
                    "\"stereo_reuse\": \"%s\", \"right_ldr_flip_mean\": %.17g, \"right_ldr_flip_max\": %.17g, "
                    "\"right_shaded_share\": %.17g}\n",
                    n, c->o.width, c->o.height, prw_views_backend_name(backend), mm, mn, ms, r_mono.ratio, r_mono.lo,
                    r_mono.hi, r_naive.ratio, r_naive.lo, r_naive.hi, nts, t_mono_ts, t_shared, t_eye, t_fixed, f_eye,
                    ideal, ST_RESAMPLES, ST_SEED, reuse ? "reproject" : "off", flip_mean, flip_max,
                    reuse ? shaded_mean : 1.0);
            ok = fclose(f) == 0 ? true : prw_fail(e, "%s: write failed", path);
        }
        if (ok) printf("wrote %s/stereo.csv, %s/stereo.json\n", c->o.out_dir, c->o.out_dir);
    }
    free(tm);
    free(tn);
    free(tsh);
    free(fr);
    free(flip);
    free(shaded);
    free(ts_frame);
    free(ts_shared);
    free(ts_eye);
    return ok;
}
