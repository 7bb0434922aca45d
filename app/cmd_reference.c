/* prw reference — the path-traced reference image (engine/reference); prw reference-merge — joins
 * accumulation files (tiles, sample ranges) into one reference EXR. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "app.h"
#include "prw_image.h"
#include "prw_reference.h"
#include "prw_view.h"

static void reference_usage(void)
{
    printf("usage: prw reference [SCENE] [options]\n"
           "  SCENE                manifest (.json), a model (.gltf, .glb, .igs, .iges) or 'demo' (default)\n"
           "  --camera NAME        scene camera (default: the first)\n"
           "  --spp N              samples per pixel, 1..10000000 (default 64): samples [0, N)\n"
           "  --out FILE.exr       mean radiance, linear cd/m^2 (default prw-out/reference.exr unless --acc);\n"
           "                       the variance of the mean goes to FILE.var.exr (A = sample count)\n"
           "  --size WxH           image size (default 1280x720)\n"
           "  --seed S             random seed (default 1); the same seed gives bit-identical output\n"
           "  --time-limit SEC     stop after the sample batch during which SEC runs out (records the real spp)\n"
           "  --filter F           light paths: all | emission | direct | indirect | diffuse-last | glossy-last |\n"
           "                       indirect-diffuse-last | indirect-glossy-last | environment-direct |\n"
           "                       depth:N | maxdepth:N (N scattering events between eye and emitter; default all;\n"
           "                       definitions in engine/reference/prw_reference.h)\n"
           "  --tile x0,y0,x1,y1   render only pixels [x0,x1) x [y0,y1) (needs --acc unless it is the whole image)\n"
           "  --samples s0,s1      render samples [s0, s1) instead of [0, spp)\n"
           "  --acc FILE.acc       also write the exact fixed-point accumulation; join them with\n"
           "                       prw reference-merge A.acc B.acc ... --out ref.exr\n"
           "  --against REF.exr    a higher-spp reference of the same scene, camera, size and filter (with its\n"
           "                       REF.var.exr): also prints CPU-s x (MSE - REF's own variance), the error\n"
           "                       this run reaches per CPU-second (lower is better)\n"
           "Threads: the global --threads budget (Embree/TBB and the tracer's workers).  Prints the samples\n"
           "per pixel per CPU-second (process CPU time of the render, all threads).\n");
}

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* REF.exr and REF.var.exr (--against), read before the render so that a bad one costs no work. */
static bool load_against(const char *ref_path, uint32_t width, uint32_t height, prw_image *ref, prw_image *rv,
                         prw_error *e)
{
    char vp[2048];
    prw_ref_var_path(ref_path, vp, sizeof vp);
    if (!prw_exr_read(ref_path, NULL, ref, e) || !prw_exr_read(vp, NULL, rv, e))
        return prw_fail_wrap(e, "--against %s", ref_path);
    if (ref->width != (int)width || ref->height != (int)height || rv->width != ref->width || rv->height != ref->height)
        return prw_fail(e, "--against %s: %dx%d (variance %dx%d), this run is %ux%u", ref_path, ref->width,
                        ref->height, rv->width, rv->height, width, height);
    return true;
}

/* MSE of this run's mean against ref over pixels and RGB, and ref's mean variance of the mean. */
static bool error_against(const prw_ref_acc *acc, const prw_image *ref, const prw_image *rv, double *mse,
                          double *ref_var, prw_error *e)
{
    float *mean = NULL, *var = NULL;
    if (!prw_ref_acc_images(acc, &mean, &var, e)) return false;
    double se = 0, sv = 0;
    size_t n = (size_t)ref->width * ref->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)mean[4 * i + c] - ref->rgba[4 * i + c];
            se += d * d;
            sv += rv->rgba[4 * i + c];
        }
    *mse = se / (3.0 * (double)n);
    *ref_var = sv / (3.0 * (double)n);
    free(mean);
    free(var);
    return true;
}

static void merge_usage(void)
{
    printf("usage: prw reference-merge A.acc B.acc ... --out ref.exr [--acc merged.acc]\n"
           "  Joins accumulations of the same scene, seed, filter and image size (any tiles, disjoint\n"
           "  sample ranges; every pixel must end with the same sample count); bit-exact in any order.\n");
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
    prw_error ignored; /* a failure surfaces at the write */
    prw_mkdirs(dir, &ignored);
}

/* Before any work: the outputs can be written (EXR, its variance twin, the accumulation). */
static bool outputs_writable(const char *exr, const char *acc, prw_error *e)
{
    char vp[2048];
    if (exr) prw_ref_var_path(exr, vp, sizeof vp);
    return (!exr || (prw_check_writable(exr, true, e) && prw_check_writable(vp, true, e))) &&
           (!acc || prw_check_writable(acc, true, e));
}

static void progress_cb(void *user, const prw_ref_progress *p)
{
    (void)user;
    double pct = p->total ? 100.0 * (double)p->done / (double)p->total : 100.0;
    char eta[32] = "?";
    if (p->eta_s >= 0) snprintf(eta, sizeof eta, "%.0f s", p->eta_s);
    fprintf(stderr, "\rreference: %5.1f %%  %llu spp done  elapsed %.1f s  ETA %s   ", pct,
            (unsigned long long)p->spp_done, p->elapsed_s, eta);
    fflush(stderr);
}

static bool parse_pair(const char *s, const char *what, uint64_t out[2], prw_error *e)
{
    char *end = NULL;
    unsigned long long a = strtoull(s, &end, 10);
    if (end == s || *end != ',') return prw_fail(e, "%s '%s': expected s0,s1", what, s);
    const char *b = end + 1;
    unsigned long long c = strtoull(b, &end, 10);
    if (end == b || *end != '\0' || s[0] == '-' || b[0] == '-') return prw_fail(e, "%s '%s': expected s0,s1", what, s);
    out[0] = a, out[1] = c;
    return true;
}

static bool parse_tile(const char *s, uint32_t t[4], prw_error *e)
{
    long v[4];
    const char *p = s;
    for (int i = 0; i < 4; i++) {
        char *end = NULL;
        v[i] = strtol(p, &end, 10);
        if (end == p || v[i] < 0 || v[i] > 1000000 || (i < 3 ? *end != ',' : *end != '\0'))
            return prw_fail(e, "--tile '%s': expected x0,y0,x1,y1 (pixels, x1 > x0, y1 > y0)", s);
        p = end + 1;
    }
    if (v[2] <= v[0] || v[3] <= v[1]) return prw_fail(e, "--tile '%s': expected x1 > x0 and y1 > y0", s);
    for (int i = 0; i < 4; i++) t[i] = (uint32_t)v[i];
    return true;
}

int prw_cmd_reference(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        reference_usage();
        prw_args_free(&a);
        return 0;
    }
    const char *v, *out = NULL, *acc_path = NULL, *camera = NULL;
    uint32_t width = 1280, height = 720, tile[4] = {0, 0, 0, 0};
    long n;
    uint64_t spp = 64, seed = 1, samples[2] = {0, 0};
    bool has_spp = false, has_samples = false, has_tile = false;
    double time_limit = 0;
    prw_ref_filter filter = {PRW_REF_ALL, 0};
    out = prw_args_value(&a, "out", &e, &bad);
    acc_path = prw_args_value(&a, "acc", &e, &bad);
    camera = prw_args_value(&a, "camera", &e, &bad);
    const char *against = prw_args_value(&a, "against", &e, &bad);
    if ((v = prw_args_value(&a, "size", &e, &bad)) && !prw_parse_size(v, &width, &height, &e)) bad = true;
    if (!bad && (v = prw_args_value(&a, "spp", &e, &bad))) {
        if (!prw_parse_int(v, "--spp", 1, (long)PRW_REF_MAX_SPP, &n, &e)) bad = true;
        spp = (uint64_t)n;
        has_spp = true;
    }
    if (!bad && (v = prw_args_value(&a, "seed", &e, &bad))) {
        char *end = NULL;
        unsigned long long s = strtoull(v, &end, 10);
        if (end == v || *end != '\0' || v[0] == '-') bad = true, prw_fail(&e, "--seed '%s': expected an unsigned integer", v);
        seed = s;
    }
    if (!bad && (v = prw_args_value(&a, "time-limit", &e, &bad)) &&
        !prw_parse_double(v, "--time-limit", 0.001, 1e7, &time_limit, &e))
        bad = true;
    if (!bad && (v = prw_args_value(&a, "filter", &e, &bad)) && !prw_ref_filter_parse(v, &filter, &e)) bad = true;
    if (!bad && (v = prw_args_value(&a, "tile", &e, &bad))) {
        if (!parse_tile(v, tile, &e)) bad = true;
        has_tile = true;
    }
    if (!bad && (v = prw_args_value(&a, "samples", &e, &bad))) {
        if (!parse_pair(v, "--samples", samples, &e)) bad = true;
        else if (!(samples[1] > samples[0]) || samples[1] - samples[0] > PRW_REF_MAX_SPP)
            bad = true, prw_fail(&e, "--samples '%s': expected s0 < s1 with s1 - s0 <= %llu", v,
                                 (unsigned long long)PRW_REF_MAX_SPP);
        has_samples = true;
    }
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count > 1) bad = true, prw_fail(&e, "reference takes one SCENE, got %d", a.positional_count);
    if (!bad && has_spp && has_samples) bad = true, prw_fail(&e, "give either --spp or --samples, not both");
    if (!bad && has_tile && (tile[2] > width || tile[3] > height))
        bad = true, prw_fail(&e, "--tile %u,%u,%u,%u lies outside the %ux%u image", tile[0], tile[1], tile[2], tile[3],
                             width, height);
    bool whole = !has_tile || (tile[0] == 0 && tile[1] == 0 && tile[2] == width && tile[3] == height);
    if (!bad && !whole && out) bad = true, prw_fail(&e, "--out needs the whole image; write tiles with --acc and merge them");
    if (!bad && !whole && against) bad = true, prw_fail(&e, "--against needs the whole image");
    if (!bad && !whole && !acc_path) bad = true, prw_fail(&e, "--tile needs --acc FILE (tiles are merged with reference-merge)");
    if (bad) {
        fprintf(stderr, "prw reference: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    if (!out && !acc_path) out = "prw-out/reference.exr";
    const char *scene_path = a.positional_count ? a.positional[0] : NULL;
    uint64_t tile_px = whole ? (uint64_t)width * height : (uint64_t)(tile[2] - tile[0]) * (tile[3] - tile[1]);
    char who[64];
    snprintf(who, sizeof who, "--size %ux%u", width, height);
    if (!prw_mem_check(prw_ref_memory_bytes(width, height, tile_px, out != NULL), who, "the reference", &e) ||
        !outputs_writable(out, acc_path, &e)) {
        fprintf(stderr, "prw reference: error: %s\n", e.msg);
        prw_args_free(&a);
        return 1;
    }

    int rc = 1;
    prw_scene *scene = NULL;
    prw_ref_renderer *r = NULL;
    prw_ref_acc acc = {0};
    prw_view view;
    prw_image ref_img = {0}, ref_var_img = {0};
    if (against && !load_against(against, width, height, &ref_img, &ref_var_img, &e)) goto done;
    if (!prw_app_load_renderable(scene_path, &scene, &e)) goto done;
    if (!prw_ref_view_for_camera(scene, camera, width, height, &view, &e)) goto done;
    if (!prw_app_bake_scene(scene, &e)) goto done;
    double t0 = prw_now();
    if (!prw_ref_create(scene, view.eye, prw_threads_get(), &r, &e)) goto done;
    double t_build = prw_now() - t0;
    prw_ref_desc d = {.s0 = has_samples ? samples[0] : 0, .s1 = has_samples ? samples[1] : spp, .seed = seed,
                      .filter = filter, .time_limit_s = time_limit, .progress = progress_cb};
    if (has_tile) d.x0 = tile[0], d.y0 = tile[1], d.x1 = tile[2], d.y1 = tile[3];
    prw_ref_stats st;
    double c0 = cpu_seconds();
    bool ok = prw_ref_render(r, &view, &d, &acc, &st, &e);
    double cpu = cpu_seconds() - c0;
    fprintf(stderr, "\n");
    if (!ok) goto done;
    if (acc_path) {
        ensure_parent_dir(acc_path);
        if (!prw_ref_acc_write(acc_path, &acc, &e)) goto done;
        printf("wrote %s (accumulation: tile %u,%u,%u,%u, samples [%llu, %llu))\n", acc_path, acc.x0, acc.y0, acc.x1,
               acc.y1, (unsigned long long)acc.s0, (unsigned long long)acc.s1);
    }
    if (out) {
        const char *extra[] = {"prw:scene", scene->source, "prw:camera", camera ? camera : scene->cameras[0].name};
        ensure_parent_dir(out);
        if (!prw_ref_write_exr(out, &acc, extra, 2, &e)) goto done;
        char vp[2048];
        prw_ref_var_path(out, vp, sizeof vp);
        printf("wrote %s (mean radiance, cd/m^2) and %s (variance of the mean)\n", out, vp);
    }
    char fname[32];
    prw_ref_filter_name(filter, fname, sizeof fname);
    printf("reference: %llu spp%s, %ux%u, filter %s, seed %llu, %.2f s (+ %.2f s scene build), %.2f Mrays/s, %d threads\n",
           (unsigned long long)st.spp, st.time_limited ? " (time limit)" : "", width, height, fname,
           (unsigned long long)seed, st.seconds, t_build, (double)st.rays / fmax(st.seconds, 1e-9) * 1e-6,
           prw_threads_get());
    printf("reference: %.3f samples per pixel per CPU-second (%.2f CPU-s for %llu spp)\n",
           cpu > 0 ? (double)st.spp / cpu : 0.0, cpu, (unsigned long long)st.spp);
    if (filter.kind == PRW_REF_ENVIRONMENT_DIRECT && !scene->environment.present)
        printf("reference: %s has no environment (manifest \"environment\"): environment-direct is 0 everywhere\n",
               scene->source);
    if (against) {
        double mse, rvar;
        if (!error_against(&acc, &ref_img, &ref_var_img, &mse, &rvar, &e)) goto done;
        printf("reference: against %s: MSE %.6g, its own variance %.6g, CPU-s x (MSE - variance) %.6g "
               "((cd/m^2)^2 s)\n",
               against, mse, rvar, cpu * (mse - rvar));
    }
    if (acc.nonfinite) printf("reference: warning: %llu non-finite samples dropped\n", (unsigned long long)acc.nonfinite);
    if (scene->nurbs_count)
        printf("reference: NURBS tessellation error %.3g px at this view (finest level, exact normals)%s\n", st.tess_px,
               st.tess_px > 0.01 ? "; above 0.01 px: lower the entries' chord_rel for a predictive reference" : "");
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw reference: error: %s\n", e.msg[0] ? e.msg : "failed");
    prw_ref_acc_free(&acc);
    prw_image_free(&ref_img);
    prw_image_free(&ref_var_img);
    prw_ref_destroy(r);
    prw_scene_destroy(scene);
    prw_args_free(&a);
    return rc;
}

int prw_cmd_reference_merge(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    bool bad = false;
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "help")) {
        merge_usage();
        prw_args_free(&a);
        return 0;
    }
    const char *out = prw_args_value(&a, "out", &e, &bad);
    const char *acc_out = prw_args_value(&a, "acc", &e, &bad);
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count < 1) bad = true, prw_fail(&e, "no accumulation files given");
    if (!bad && !out && !acc_out) bad = true, prw_fail(&e, "give --out FILE.exr and/or --acc FILE.acc");
    if (bad) {
        fprintf(stderr, "prw reference-merge: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    if (!outputs_writable(out, acc_out, &e)) {
        fprintf(stderr, "prw reference-merge: error: %s\n", e.msg);
        prw_args_free(&a);
        return 1;
    }
    int n = a.positional_count, rc = 1, loaded = 0;
    prw_ref_acc *accs = prw_calloc((size_t)n, sizeof *accs);
    const prw_ref_acc **ptrs = prw_calloc((size_t)n, sizeof *ptrs);
    prw_ref_acc merged = {0};
    for (; loaded < n; loaded++) {
        if (!prw_ref_acc_read(a.positional[loaded], &accs[loaded], &e)) goto done;
        ptrs[loaded] = &accs[loaded];
    }
    if (!prw_ref_acc_merge(ptrs, (const char *const *)a.positional, n, &merged, &e)) goto done;
    if (acc_out) {
        ensure_parent_dir(acc_out);
        if (!prw_ref_acc_write(acc_out, &merged, &e)) goto done;
        printf("wrote %s (merged accumulation)\n", acc_out);
    }
    if (out) {
        ensure_parent_dir(out);
        if (!prw_ref_write_exr(out, &merged, NULL, 0, &e)) goto done;
        char vp[2048];
        prw_ref_var_path(out, vp, sizeof vp);
        printf("wrote %s and %s (%llu spp from %d files)\n", out, vp, (unsigned long long)(merged.s1 - merged.s0), n);
    }
    rc = 0;
done:
    if (rc != 0) fprintf(stderr, "prw reference-merge: error: %s\n", e.msg[0] ? e.msg : "failed");
    for (int i = 0; i < loaded; i++) prw_ref_acc_free(&accs[i]);
    prw_ref_acc_free(&merged);
    free(accs);
    free(ptrs);
    prw_args_free(&a);
    return rc;
}
