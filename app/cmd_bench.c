/* prw bench — a scripted camera path through a scene: frame times, per-pass times, memory, and the
 * error against path-traced references at sampled frames (DESIGN.md §5, "Timing" and "Metrics").
 *
 * Phases, in this order (references are never rendered while frames are timed):
 *   1. references of the sampled frames, in a child process (bench_ref.c), cached by content;
 *   2. the timed run per configuration (timestamps off);
 *   3. a separate timestamped run per configuration: per-pass GPU times, and the raster HDR image at
 *      the sampled frames, compared with the reference (FLIP, HDR-FLIP, PSNR, SSIM) next to the
 *      reference noise;
 *   4. frames.csv, passes.csv, summary.json and plots in --out.
 * A/B mode (--vs) replaces 2-4 by two renderers interleaved frame by frame (bench_ab.c).
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "prw_demo_path.h"

static void bench_usage(void)
{
    char knobs[4096];
    prw_quality_describe(knobs, sizeof knobs);
    printf("usage: prw bench [SCENE] [PATH.json | --path demo] [options]\n"
           "  SCENE                  manifest (.json), a model (.gltf, .glb, .igs, .iges) or 'demo' (default)\n"
           "  PATH.json, --path P    camera path file, or 'demo': the built-in 60-frame demo walk (default);\n"
           "                         a file with the \"prw_camera_path\" key is a path also alone or before SCENE\n"
           "  --preset NAME          low | medium | high | ultra (default high), optionally followed by\n"
           "                         knobs: \"high;tonemap=selective\"\n"
           "  --sweep SPEC           knob ranges over the preset, e.g. \"msaa=1,4;shadow_size=512,1024,2048\"\n"
           "  --vs CONFIG            A/B mode: the preset (A) against CONFIG (B: a preset or knob list such as\n"
           "                         \"msaa=1\"), interleaved frame by frame, >= 30 frames each; prints the median\n"
           "                         ratio B/A of frame times with a bootstrap 95 %% interval\n"
           "  --size WxH             image size (default 1280x720)\n"
           "  --views N              views per frame: 1, or 2 for the stereo benchmark (mono, naive stereo =\n"
           "                         two single-view renders, shared stereo = one two-view frame, interleaved;\n"
           "                         T_stereo/T_mono, T_stereo/T_naive, f_eye and the ideal ratio; no references)\n"
           "  --views-backend B      with --views 2: loop, multiview or auto (default auto)\n"
           "  --lod [MODEL]          NURBS LOD benchmark (its own options: prw bench --lod --help)\n"
           "  --stereo-reuse R       with --views 2: off or reproject (knob stereo_reuse): shared stereo reuses\n"
           "                         the left eye's colour in the right eye; also prints the mean LDR-FLIP of\n"
           "                         the reprojected right eye against the fully shaded one over the path\n"
           "  --reference-every K    reference at every K-th frame (default: 5 references along the path)\n"
           "  --ref-spp N            reference samples per pixel (default 64); a second reference with another\n"
           "                         seed at the same spp gives the reference noise\n"
           "  --out DIR              output directory (default prw-out/bench)\n"
           "  --frames-limit N       only the first N frames of the path\n"
           "  --warmup N             untimed frames before timing (default 2)\n"
           "  --shard i/n            only frames with index %% n == i (and their references); join the\n"
           "                         shards' output directories with prw bench-merge\n"
           "  --no-ref-cache         do not read the reference cache (references go to DIR/refs)\n"
           "  --no-bake              render without indirect light (no GI light maps); otherwise the scene's\n"
           "                         indirect-diffuse light maps (of the first config's radiosity_size) are\n"
           "                         drawn, baked first when the cache has none\n"
           "Quality knobs (--sweep, --vs):\n%s"
           "Outputs: frames.csv (per frame; machine facts in '#' lines), passes.csv (timestamped run, one\n"
           "column per pass, empty = skipped), summary.json, frame_time.png, error.png, pareto.png (sweep).\n"
           "Reference cache: $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else ~/.cache/prw; subdirectory refs/.\n",
           knobs);
}

static void merge_usage(void)
{
    printf("usage: prw bench-merge DIR1 DIR2 ... --out DIR\n"
           "  Joins the output directories of `prw bench --shard i/n` runs (all i of one n, same scene, path,\n"
           "  size, configs and git hash): frame rows sorted by index, summary recomputed from the rows.\n");
}

bool bench_frame_view(const bench_ctx *c, uint32_t frame, prw_view *out, prw_error *e)
{
    return prw_camera_path_frame_view(&c->path, frame, c->o.width, c->o.height, c->znear, c->ev100, 0, out, e);
}

static bool parse_shard(const char *s, long *i, long *n, prw_error *e)
{
    char *end = NULL;
    long a = strtol(s, &end, 10);
    if (end == s || *end != '/' || s[0] == '-') goto bad;
    const char *b = end + 1;
    long c = strtol(b, &end, 10);
    if (end == b || *end != '\0' || b[0] == '-' || c < 1 || c > 100000 || a < 0 || a >= c) goto bad;
    *i = a, *n = c;
    return true;
bad:
    return prw_fail(e, "--shard '%s': expected i/n with 0 <= i < n (e.g. 0/4)", s);
}

/* Options into c->o; false with e set (usage errors). */
static bool parse_options(prw_args *a, bench_opts *o, prw_error *e)
{
    bool bad = false;
    const char *v;
    *o = (bench_opts){.width = 1280, .height = 720, .views = 1, .ref_spp = 64, .warmup = 2,
                      .out_dir = "prw-out/bench", .shard_n = 1};
    o->path_spec = prw_args_value(a, "path", e, &bad);
    o->preset = prw_args_value(a, "preset", e, &bad);
    o->sweep = prw_args_value(a, "sweep", e, &bad);
    o->vs = prw_args_value(a, "vs", e, &bad);
    o->views_backend = prw_args_value(a, "views-backend", e, &bad);
    o->stereo_reuse = prw_args_value(a, "stereo-reuse", e, &bad);
    if ((v = prw_args_value(a, "out", e, &bad))) o->out_dir = v;
    o->ref_child = prw_args_value(a, "ref-child", e, &bad);
    o->ref_dir = prw_args_value(a, "ref-dir", e, &bad);
    o->no_ref_cache = prw_args_flag(a, "no-ref-cache");
    o->no_bake = prw_args_flag(a, "no-bake");
    if (bad) return false;
    if ((v = prw_args_value(a, "size", e, &bad)) && !prw_parse_size(v, &o->width, &o->height, e)) return false;
    if ((v = prw_args_value(a, "views", e, &bad)) && !prw_parse_int(v, "--views", 1, PRW_MAX_VIEWS, &o->views, e))
        return false;
    if ((v = prw_args_value(a, "reference-every", e, &bad)) &&
        !prw_parse_int(v, "--reference-every", 1, 1000000, &o->reference_every, e))
        return false;
    if ((v = prw_args_value(a, "ref-spp", e, &bad)) && !prw_parse_int(v, "--ref-spp", 1, 1000000, &o->ref_spp, e))
        return false;
    if ((v = prw_args_value(a, "frames-limit", e, &bad)) &&
        !prw_parse_int(v, "--frames-limit", 1, 10000000, &o->frames_limit, e))
        return false;
    if ((v = prw_args_value(a, "warmup", e, &bad)) && !prw_parse_int(v, "--warmup", 0, 10000, &o->warmup, e))
        return false;
    if ((v = prw_args_value(a, "shard", e, &bad)) && !parse_shard(v, &o->shard_i, &o->shard_n, e)) return false;
    if (bad || !prw_args_finish(a, e)) return false;
    /* positionals: [SCENE] [PATH.json]; a camera path (recognised by its "prw_camera_path" key) may
     * also come alone (the demo scene) or first */
    int np = a->positional_count;
    if (np > 2) return prw_fail(e, "bench takes [SCENE] [PATH.json], got %d arguments", np);
    const char *p0 = np >= 1 ? a->positional[0] : NULL, *p1 = np == 2 ? a->positional[1] : NULL;
    if (p0 && prw_camera_path_sniff(p0)) {
        if (p1 && prw_camera_path_sniff(p1))
            return prw_fail(e, "%s and %s are both camera paths: bench takes [SCENE] [PATH.json]", p0, p1);
        const char *t = p0;
        p0 = p1, p1 = t;
    }
    o->scene_path = p0;
    if (p1) {
        if (o->path_spec) return prw_fail(e, "give the camera path either as an argument or with --path, not both");
        o->path_spec = p1;
    }
    if (!o->path_spec) o->path_spec = "demo";
    if (o->views > 2) return prw_fail(e, "--views %ld: 1 (mono) or 2 (the stereo benchmark)", o->views);
    if (o->views == 2 && (o->vs || o->sweep || o->shard_n > 1))
        return prw_fail(e, "--views 2 is its own interleaved comparison: no --vs, --sweep or --shard");
    if (o->views_backend && o->views != 2) return prw_fail(e, "--views-backend needs --views 2");
    if (o->stereo_reuse && o->views != 2) return prw_fail(e, "--stereo-reuse needs --views 2");
    double sr;
    if (o->stereo_reuse && !prw_stereo_reuse_parse(o->stereo_reuse, &sr))
        return prw_fail(e, "--stereo-reuse '%s': expected off or reproject", o->stereo_reuse);
    if (o->preset && o->vs && strchr(o->vs, '=') == NULL && strcmp(o->preset, o->vs) == 0)
        return prw_fail(e, "--vs %s: the same configuration as --preset", o->vs);
    if (o->sweep && o->vs) return prw_fail(e, "--sweep and --vs exclude each other");
    if (o->vs && o->shard_n > 1) return prw_fail(e, "--vs runs both configurations in one process: no --shard");
    return true;
}

static bool load_path(bench_ctx *c, prw_error *e)
{
    if (strcmp(c->o.path_spec, "demo") == 0) {
        if (c->o.scene_path && strcmp(c->o.scene_path, "demo") != 0)
            prw_log(PRW_LOG_WARN, "bench: the demo path is made for the demo scene, not %s", c->o.scene_path);
        if (!prw_demo_path_build(&c->path, prw_v3(0, 0, 0), e)) return false;
    } else if (!prw_camera_path_load(c->o.path_spec, &c->path, e)) {
        return false;
    }
    uint64_t n = prw_camera_path_frame_count(&c->path);
    if (c->o.frames_limit > 0 && (uint64_t)c->o.frames_limit < n) n = (uint64_t)c->o.frames_limit;
    if (n > 10000000) return prw_fail(e, "%s: %llu frames is too many", c->o.path_spec, (unsigned long long)n);
    c->frame_count = (uint32_t)n;
    return true;
}

/* Exposure and near plane from the scene's first camera (defaults without one). */
static void camera_settings(bench_ctx *c)
{
    c->znear = 0.05;
    c->ev100 = 0;
    if (c->scene->camera_count) {
        c->znear = c->scene->cameras[0].znear > 0 ? c->scene->cameras[0].znear : 0.05;
        c->ev100 = c->scene->cameras[0].ev100;
    }
}

static void plan_frames(bench_ctx *c)
{
    uint32_t n = c->frame_count;
    c->ref_every = c->o.reference_every > 0 ? (uint32_t)c->o.reference_every : (n + 4) / 5;
    if (c->ref_every < 1) c->ref_every = 1;
    c->is_ref = prw_calloc(n, sizeof *c->is_ref);
    c->frames = prw_calloc(n, sizeof *c->frames);
    for (uint32_t k = 0; k < n; k++) {
        c->is_ref[k] = k % c->ref_every == 0;
        if (k % (uint32_t)c->o.shard_n == (uint32_t)c->o.shard_i) c->frames[c->nframes++] = k;
    }
}

static bool build_configs(bench_ctx *c, prw_error *e)
{
    prw_quality base = prw_quality_default();
    const char *base_name = c->o.preset ? c->o.preset : "high";
    /* a preset name, or a config: a preset followed by knobs, e.g. "high;tonemap=selective" */
    if (c->o.preset && !prw_quality_parse_config(c->o.preset, &base, &base, e)) return false;
    prw_quality *list = NULL;
    uint32_t n = 1;
    if (c->o.sweep) {
        if (!prw_quality_parse_sweep(c->o.sweep, &base, &list, &n, e)) return false;
    } else {
        list = prw_malloc(sizeof *list);
        list[0] = base;
    }
    bench_result *r = &c->res;
    r->configs = prw_calloc(n, sizeof *r->configs);
    r->config_count = n;
    for (uint32_t i = 0; i < n; i++) {
        bench_config *bc = &r->configs[i];
        bc->q = list[i];
        char diff[512];
        prw_quality_format_diff(&list[i], &base, diff, sizeof diff);
        if (c->o.sweep) snprintf(bc->label, sizeof bc->label, "%s %s", base_name, diff[0] ? diff : "(preset)");
        else snprintf(bc->label, sizeof bc->label, "%s", base_name);
        prw_quality_format(&list[i], bc->knobs, sizeof bc->knobs);
    }
    free(list);
    return true;
}

static void run_meta(bench_ctx *c)
{
    bench_meta *m = &c->res.meta;
    bench_meta_add(m, "scene", "%s (hash %016llx)", c->scene->source, (unsigned long long)prw_scene_hash(c->scene));
    bench_meta_add(m, "path", "%s (%u frames at %.17g fps)", c->o.path_spec, c->frame_count,
                   prw_camera_path_fps(&c->path));
    bench_meta_add(m, "size", "%ux%u", c->o.width, c->o.height);
    bench_meta_add(m, "exposure", "EV100 %.17g (scene camera; the metric tone map of LDR-FLIP and SSIM)", c->ev100);
    bench_meta_add(m, "reference", "every %u frames, %ld spp, seeds %u (errors) and %u (noise), filter all",
                   c->ref_every, c->o.ref_spp, BENCH_REF_SEED_A, BENCH_REF_SEED_B);
    bench_meta_add(m, "warmup", "%ld frames", c->o.warmup);
    bench_meta_add(m, "gi", "%s", c->lightmaps ? "baked indirect-diffuse light maps (radiosity_size of config 0)"
                                  : c->o.no_bake ? "none (--no-bake)" : "none (nothing to bake)");
    for (uint32_t i = 0; i < c->res.config_count; i++) {
        char key[32];
        snprintf(key, sizeof key, "config %u", i);
        bench_meta_add(m, key, "%s | %s", c->res.configs[i].label, c->res.configs[i].knobs);
    }
    bench_meta_add(m, "shard", "%ld/%ld", c->o.shard_i, c->o.shard_n);
}

static void bench_ctx_free(bench_ctx *c)
{
    if (c->ref_a)
        for (uint32_t k = 0; k < c->frame_count; k++) prw_image_free(&c->ref_a[k]);
    free(c->ref_a);
    free(c->noise);
    free(c->frames);
    free(c->is_ref);
    prw_camera_path_free(&c->path);
    prw_app_lightmaps_destroy(c->lightmaps);
    prw_scene_destroy(c->scene);
    bench_result_free(&c->res);
}

static int run_ab(bench_ctx *c, prw_gpu *gpu, prw_error *e)
{
    prw_quality a = c->res.configs[0].q, b;
    if (!prw_quality_parse_config(c->o.vs, &a, &b, e)) return 2;
    return bench_run_ab(c, gpu, &a, &b, c->o.vs, e) ? 0 : 1;
}

int prw_cmd_bench(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    prw_args_init(&a, argc, argv, &e);
    if (prw_args_flag(&a, "lod")) { /* NURBS LOD benchmark (bench_lod.c, issue 7): its own options */
        int lrc = bench_lod_main(&a);
        prw_args_free(&a);
        return lrc;
    }
    if (prw_args_flag(&a, "help")) {
        bench_usage();
        prw_args_free(&a);
        return 0;
    }
    bench_ctx *c = prw_calloc(1, sizeof *c);
    prw_gpu *gpu = NULL;
    int rc = 2;
    if (!parse_options(&a, &c->o, &e)) goto done;
    if (!build_configs(c, &e)) goto done;
    if (c->o.vs) {
        prw_quality probe;
        if (!prw_quality_parse_config(c->o.vs, &c->res.configs[0].q, &probe, &e)) goto done;
    }
    rc = 1;
    if (!prw_app_load_renderable(c->o.scene_path, &c->scene, &e)) goto done;
    if (!load_path(c, &e)) goto done;
    if (!prw_app_bake_scene(c->scene, &e)) goto done; /* before the reference children: they hit the cache */
    camera_settings(c);
    plan_frames(c);
    if (c->o.ref_child) {
        rc = bench_ref_child(c);
        goto done;
    }
    if (c->nframes == 0) {
        prw_fail(&e, "--shard %ld/%ld: no frames (the path has %u)", c->o.shard_i, c->o.shard_n, c->frame_count);
        goto done;
    }
    if (!bench_mkdirs(c->o.out_dir, &e)) goto done;
    if (!prw_app_lightmaps_prepare("bench", c->scene, &c->res.configs[0].q, c->o.no_bake, &c->lightmaps, &e)) goto done;
    double t0 = prw_now();
    if (!c->o.vs && c->o.views == 1 && !bench_references(c, &e)) goto done; /* before the GPU: nothing timed yet */
    if (!prw_app_create_gpu(false, &gpu, &e)) goto done;
    if (c->o.vs) {
        rc = run_ab(c, gpu, &e);
        goto done;
    }
    if (c->o.views == 2) {
        rc = bench_run_stereo(c, gpu, &c->res.configs[0].q, c->o.views_backend, &e) ? 0 : 1;
        goto done;
    }
    bench_machine_meta(&c->res.meta, gpu);
    run_meta(c);
    if (!bench_run_timed(c, gpu, &e) || !bench_run_timestamped(c, gpu, &e)) goto done;
    if (prw_gpu_validation_count(gpu) != 0) {
        prw_fail(&e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
        goto done;
    }
    bench_result_sort(&c->res);
    if (!bench_write_outputs(&c->res, c->o.out_dir, &e)) goto done;
    bench_plots(&c->res, c->o.out_dir);
    bench_print_base_floor(&c->res);
    printf("bench: %u frames x %u configs, %u reference frames, wall time %.1f s; results in %s\n", c->nframes,
           c->res.config_count, (c->frame_count + c->ref_every - 1) / c->ref_every, prw_now() - t0, c->o.out_dir);
    rc = 0;
done:
    if (rc != 0 && e.msg[0]) fprintf(stderr, "prw bench: error: %s\n", e.msg);
    if (gpu) prw_gpu_destroy(gpu);
    bench_ctx_free(c);
    free(c);
    prw_args_free(&a);
    return rc;
}

int prw_cmd_bench_merge(int argc, char **argv)
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
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count < 1) bad = true, prw_fail(&e, "no shard directories given");
    if (!bad && !out) bad = true, prw_fail(&e, "give --out DIR");
    if (bad) {
        fprintf(stderr, "prw bench-merge: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    int rc = bench_merge_dirs(a.positional, a.positional_count, out, &e) ? 0 : 1;
    if (rc) fprintf(stderr, "prw bench-merge: error: %s\n", e.msg);
    prw_args_free(&a);
    return rc;
}
