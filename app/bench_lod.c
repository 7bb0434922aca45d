/* bench_lod — `prw bench --lod [MODEL]` (issue 7, must-show 5): what NURBS LOD displays and costs.
 *
 * A benchmark, not a test: it prints numbers and asserts nothing about time.
 *   MODEL   car_shell (default), box, plate, or an .igs / .iges / .json file; the hierarchy is built
 *           with the sewing chord --chord-rel x model diagonal (default 1e-5, the "finest
 *           level at chordal error 1e-5 x diagonal") and cached in $PRW_CACHE_DIR/lod.
 * Two scenes of the same model on a floor under a directional light (shadows on), one renderer each:
 *   A  one instance;
 *   B  100 instances, a 10 x 10 grid of copies scaled by 1/10 that together cover the single instance's
 *      footprint (so both cover about the same screen area; each copy chooses its own levels).
 * The camera walks --frames poses on a circle around the model (radius 1.3 x its larger footprint
 * side, looking at it from above).  Per pose: one A frame and one B frame, interleaved (ABBA order so
 * neither always runs first), each timed as the wall time of prw_renderer_render (LOD selection +
 * slot updates + recording + submit + wait; on lavapipe the GPU is the CPU).  Printed:
 *   - full-tessellation triangles (finest level of the hierarchy) and displayed triangles of A (median
 *     over the path, min, max) and their ratio (goal <= 3 % at ½ px);
 *   - LOD selection + buffer update time per frame (median; A and B), slots re-uploaded, bytes;
 *   - frame time B / A: median of the per-pose ratios with a bootstrap 95 % interval (goal <= 1.5);
 *   - CPU, driver, threads, git hash, build type.
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_internal.h"
#include "prw_lod_node.h"
#include "prw_lod_proxy.h"
#include "prw_lod_render.h"

#define LB_RESAMPLES 4000
#define LB_SEED 1

typedef struct lod_bench_opts {
    const char *model;
    uint32_t width, height;
    long frames;
    double tol_px, chord_rel;
    bool per_pose, centre_pixel, profile, no_proxy;
    long msaa;
} lod_bench_opts;

static void lod_usage(void)
{
    printf("usage: prw bench --lod [MODEL] [--size WxH] [--frames N] [--tol-px X] [--chord-rel X]\n"
           "  MODEL          car_shell (default), box, plate, or a .igs/.iges/.json NURBS file\n"
           "  --size WxH     image size (default 1280x720)\n"
           "  --frames N     camera poses on the walk around the model (default 40)\n"
           "  --tol-px X     LOD screen-space tolerance in pixels (default 0.5)\n"
           "  --chord-rel X  finest-level error / model diagonal (default 1e-5; sewing chord: half of it)\n"
           "  --per-pose     also print every pose's times, triangles and updates\n"
           "  --centre-pixel the tolerance in pixels of the image centre (default: of the image corner,\n"
           "                 where a pixel subtends the smallest angle)\n"
           "  --msaa 1|4     samples per pixel (default 4)\n"
           "  --no-proxy     never draw a copy as a whole-model proxy level (patches only)\n"
           "  --profile      a separate run with GPU timestamps (each flushes on lavapipe, so its frame\n"
           "                 times are not the A/B figures): median per-pass times of A and B\n"
           "Prints full-tessellation vs displayed triangles, LOD selection + update time, and the frame\n"
           "time of 100 instances (10 x 10 grid over the same screen area) vs 1, interleaved.\n");
}

/* One scene: floor, light, the model (grid x grid copies at 1/grid scale over the footprint). */
/* The renderer's knobs of this bench: the default with its own MSAA. */
static prw_quality bench_lod_quality(const lod_bench_opts *o)
{
    prw_quality q = prw_quality_default();
    q.msaa = (uint32_t)o->msaa;
    q.shadow_size = 1024;
    return q;
}

static bool make_scene(const lod_bench_opts *o, int grid, prw_scene **out, prw_dvec3 *centre, double *radius,
                       prw_error *e)
{
    prw_scene_nurbs nb;
    memset(&nb, 0, sizeof nb);
    bool procedural = prw_scene_nurbs_procedural_known(o->model);
    if (procedural) snprintf(nb.procedural, sizeof nb.procedural, "%s", o->model);
    else if (snprintf(nb.file, sizeof nb.file, "%s", o->model) >= (int)sizeof nb.file)
        return prw_fail(e, "%s: path too long", o->model);
    prw_nurbs_model m;
    if (!prw_scene_nurbs_load(&nb, &m, e)) return false;
    prw_nurbs_model_bounds(&m, &nb.model_min, &nb.model_max);
    prw_nurbs_model_free(&m);
    /* the shells are height fields over x-y (height +z): stand them on the floor (height -> +y) */
    bool z_up = procedural && strcmp(o->model, "box") != 0;
    prw_node n = prw_node_default();
    if (z_up) n.rotation = (prw_dquat){-sqrt(0.5), 0, 0, sqrt(0.5)};
    /* rotated model box (no translation, unit scale) */
    prw_dvec3 lo = prw_v3(1e300, 1e300, 1e300), hi = prw_v3(-1e300, -1e300, -1e300);
    for (int c = 0; c < 8; c++) {
        prw_dvec3 p = prw_v3(c & 1 ? nb.model_max.x : nb.model_min.x, c & 2 ? nb.model_max.y : nb.model_min.y,
                             c & 4 ? nb.model_max.z : nb.model_min.z);
        if (z_up) p = prw_v3(p.x, p.z, -p.y);
        lo = prw_v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
        hi = prw_v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
    }
    double s = 1.0 / grid, w = hi.x - lo.x, d = hi.z - lo.z;
    /* footprint [-w/2, w/2] x [-d/2, d/2] on the floor y = 0 */
    n.scale = prw_v3(s, s, s);
    n.translation = prw_v3(-0.5 * w - s * lo.x, -s * lo.y, -0.5 * d - s * lo.z);
    snprintf(n.name, sizeof n.name, "model");
    prw_scene *sc = prw_scene_create();
    prw_material paint = prw_material_default();
    snprintf(paint.name, sizeof paint.name, "paint");
    paint.base_color[0] = 0.6f, paint.base_color[1] = 0.1f, paint.base_color[2] = 0.08f;
    paint.roughness = 0.35f;
    paint.double_sided = !(strcmp(o->model, "box") == 0); /* open shells are seen from both sides */
    prw_material floor = prw_material_default();
    snprintf(floor.name, sizeof floor.name, "floor");
    floor.base_color[0] = floor.base_color[1] = floor.base_color[2] = 0.5f;
    floor.roughness = 0.8f;
    nb.material = prw_scene_add_material(sc, &paint);
    int fm = prw_scene_add_material(sc, &floor);
    nb.node = prw_scene_add_node(sc, &n);
    nb.grid[0] = nb.grid[1] = grid;
    nb.spacing[0] = w / grid;
    nb.spacing[1] = d / grid;
    nb.tol_px = o->tol_px;
    nb.chord_rel = o->chord_rel;
    nb.finest_rel = o->chord_rel; /* level 0 refined to it (lod/ finest_rel), sewing at half */
    nb.single_sided = !paint.double_sided;
    snprintf(nb.name, sizeof nb.name, "%s", procedural ? o->model : "model");
    double big = 2.0 * fmax(w, d);
    bool ok = nb.node >= 0 && prw_scene_add_nurbs(sc, &nb) >= 0 &&
              prw_scene_add_box(sc, "floor", prw_v3(-big, -0.05, -big), prw_v3(big, 0, big), fm, false, e) >= 0;
    prw_light l = {.type = PRW_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = 20000, .cast_shadows = true};
    prw_node ln = prw_node_look_at("sun", prw_v3(0.4, 1, 0.3), prw_v3(0, 0, 0), prw_v3(0, 0, 1));
    l.node = prw_scene_add_node(sc, &ln);
    ok = ok && l.node >= 0 && prw_scene_add_light(sc, &l) >= 0;
    if (!ok) {
        prw_scene_destroy(sc);
        return e->msg[0] ? false : prw_fail(e, "bench --lod: cannot build the scene");
    }
    prw_scene_update(sc);
    *centre = prw_v3(0, 0.5 * (hi.y - lo.y), 0); /* the single instance's centre, for both scenes */
    *radius = 1.3 * fmax(w, d);
    *out = sc;
    return true;
}

static prw_view pose(const lod_bench_opts *o, prw_dvec3 centre, double radius, long k)
{
    double a = 2.0 * PRW_PI * (double)k / (double)o->frames;
    prw_dvec3 eye = prw_v3(radius * cos(a), 0.45 * radius, radius * sin(a));
    return prw_view_look_at(eye, centre, prw_v3(0, 1, 0), 50.0 * PRW_PI / 180.0, 0.05, o->width, o->height, 12);
}

static bool timed_frame(prw_renderer *r, const prw_view *v, double *ms, prw_lod_frame_report *rep, prw_error *e)
{
    double t0 = prw_now();
    if (!prw_renderer_render(r, v, 1, NULL, e)) return false;
    *ms = 1e3 * (prw_now() - t0);
    *rep = *prw_lod_scene_last_report(prw_renderer_lod(r));
    return true;
}

/* --profile: per pose, the per-pass GPU times of A and B (renderers created with timestamps). */
static void profile_pose(prw_renderer *r, double (*pass_ms)[PRW_MAX_PASSES], long k, const char **names,
                         uint32_t *count)
{
    prw_frame_stats st;
    prw_renderer_last_passes(r, &st);
    *count = st.pass_count;
    for (uint32_t i = 0; i < st.pass_count && i < PRW_MAX_PASSES; i++) {
        names[i] = st.passes[i].name;
        pass_ms[k][i] = st.passes[i].skipped ? 0 : st.passes[i].gpu_ms;
    }
}

static void profile_print(const char *label, double (*pass_ms)[PRW_MAX_PASSES], long n, const char **names,
                          uint32_t count)
{
    double *col = prw_calloc((size_t)n, sizeof(double));
    printf("profile %s:", label);
    for (uint32_t i = 0; i < count; i++) {
        for (long k = 0; k < n; k++) col[k] = pass_ms[k][i];
        prw_stats_summary s;
        prw_stats_summarize(col, (size_t)n, &s);
        printf(" %s %.1f ms", names[i], s.p50);
    }
    printf(" (medians over %ld poses)\n", n);
    free(col);
}

static int run(const lod_bench_opts *o, prw_error *e)
{
    prw_scene *sa = NULL, *sb = NULL;
    prw_gpu *gpu = NULL;
    prw_renderer *ra = NULL, *rb = NULL;
    int rc = 1;
    long n = o->frames;
    double *ta = prw_calloc((size_t)n, sizeof(double)), *tb = prw_calloc((size_t)n, sizeof(double));
    double *lod_a = prw_calloc((size_t)n, sizeof(double)), *lod_b = prw_calloc((size_t)n, sizeof(double));
    double *tri_a = prw_calloc((size_t)n, sizeof(double)), *tri_b = prw_calloc((size_t)n, sizeof(double));
    double *up_a = prw_calloc((size_t)n, sizeof(double)), *bytes_a = prw_calloc((size_t)n, sizeof(double));
    double *culled_a = prw_calloc((size_t)n, sizeof(double)), *maxpx_a = prw_calloc((size_t)n, sizeof(double));
    double *draws_a = prw_calloc((size_t)n, sizeof(double)), *draws_b = prw_calloc((size_t)n, sizeof(double));
    double *prox_a = prw_calloc((size_t)n, sizeof(double)), *prox_b = prw_calloc((size_t)n, sizeof(double));
    uint64_t relayouts_a = 0, relayouts_b = 0;
    double(*prof_a)[PRW_MAX_PASSES] = NULL, (*prof_b)[PRW_MAX_PASSES] = NULL;
    prw_dvec3 centre;
    double radius, wall0 = prw_now();
    if (!make_scene(o, 1, &sa, &centre, &radius, e) || !make_scene(o, 10, &sb, &centre, &radius, e)) goto done;
    if (!prw_app_create_gpu(false, &gpu, e)) goto done;
    bench_meta meta = {0};
    bench_machine_meta(&meta, gpu);
    printf("bench --lod: %s at %ux%u, %ld poses, tolerance %.3g px (pixel size at the image %s), finest chord %.3g x "
           "diagonal\n",
           o->model, o->width, o->height, n, o->tol_px, o->centre_pixel ? "centre" : "corner", o->chord_rel);
    for (int i = 0; i < meta.count; i++) printf("  %-8s %s\n", meta.key[i], meta.value[i]);
    prw_render_desc rd = {.width = o->width, .height = o->height, .quality = bench_lod_quality(o),
                          .timestamps = o->profile};
    if (o->profile) {
        prof_a = prw_calloc((size_t)n, sizeof *prof_a);
        prof_b = prw_calloc((size_t)n, sizeof *prof_b);
    }
    const char *pass_names[PRW_MAX_PASSES] = {0};
    uint32_t pass_count_a = 0, pass_count_b = 0;
    double tc = prw_now();
    if (!prw_app_bake_scene(sa, e)) goto done;
    double t_bake_a = prw_now() - tc;
    tc = prw_now();
    if (!prw_app_bake_scene(sb, e)) goto done;
    double t_bake_b = prw_now() - tc;
    tc = prw_now();
    if (!prw_renderer_create(gpu, sa, &rd, &ra, e)) goto done;
    double t_create_a = prw_now() - tc;
    tc = prw_now();
    if (!prw_renderer_create(gpu, sb, &rd, &rb, e)) goto done;
    double t_create_b = prw_now() - tc;
    if (o->centre_pixel || o->no_proxy) {
        prw_lod_gpu_options go = {.tol_px = o->tol_px, .centre_pixel = o->centre_pixel, .no_proxy = o->no_proxy};
        prw_lod_scene_set_options(prw_renderer_lod(ra), &go);
        prw_lod_scene_set_options(prw_renderer_lod(rb), &go);
    }
    const prw_baked_lod *h = prw_lod_scene_hierarchy(prw_renderer_lod(ra), 0);
    double worst0 = 0;
    for (int p = 0; p < h->lod.npatches; p++)
        if (h->lod.patches[p].ok) worst0 = fmax(worst0, h->lod.patches[p].err[0]);
    printf("hierarchy: %d patches, %d levels, sewing chord %.3g m (diagonal %.3g m), finest-level error bound "
           "%.3g m = %.2g x diagonal (refused splits %d); bake (build or cache) A %.2f s, B %.2f s; renderer create "
           "A %.2f s, B %.2f s\n",
           h->lod.npatches, h->lod.levels, h->graph.chord, h->graph.diag, worst0, worst0 / h->graph.diag,
           h->lod.refused_splits, t_bake_a, t_bake_b, t_create_a, t_create_b);
    /* warm-up (pipelines, first full uploads): the first pose, both */
    prw_view v0 = pose(o, centre, radius, 0);
    double ms;
    prw_lod_frame_report rep;
    if (!timed_frame(ra, &v0, &ms, &rep, e) || !timed_frame(rb, &v0, &ms, &rep, e)) goto done;
    for (long k = 0; k < n; k++) {
        prw_view v = pose(o, centre, radius, k);
        prw_lod_frame_report rpa, rpb;
        bool ok = (k & 1) ? timed_frame(rb, &v, &tb[k], &rpb, e) && timed_frame(ra, &v, &ta[k], &rpa, e)
                          : timed_frame(ra, &v, &ta[k], &rpa, e) && timed_frame(rb, &v, &tb[k], &rpb, e);
        if (!ok) goto done;
        if (o->profile) {
            profile_pose(ra, prof_a, k, pass_names, &pass_count_a);
            profile_pose(rb, prof_b, k, pass_names, &pass_count_b);
        }
        lod_a[k] = rpa.select_ms + rpa.update_ms;
        lod_b[k] = rpb.select_ms + rpb.update_ms;
        tri_a[k] = (double)rpa.triangles;
        tri_b[k] = (double)rpb.triangles;
        up_a[k] = (double)rpa.reuploaded;
        bytes_a[k] = (double)rpa.bytes;
        culled_a[k] = (double)rpa.culled_patches;
        maxpx_a[k] = rpa.max_px;
        draws_a[k] = (double)rpa.draws;
        draws_b[k] = (double)rpb.draws;
        prox_a[k] = (double)rpa.proxy_instances;
        prox_b[k] = (double)rpb.proxy_instances;
        relayouts_a += rpa.relayouts;
        relayouts_b += rpb.relayouts;
        if (o->per_pose)
            printf("pose %3ld: A %8.1f ms %6.0f tris %3.0f slots %3.0f draws %.3f ms | B %8.1f ms %6.0f tris %4.0f draws "
                   "%3.0f proxies %.3f ms | B/A %.3f\n",
                   k, ta[k], tri_a[k], up_a[k], draws_a[k], lod_a[k], tb[k], tri_b[k], draws_b[k], prox_b[k], lod_b[k],
                   tb[k] / ta[k]);
    }
    prw_stats_summary sa_tri, sa_lod, sb_lod, sb_tri, s_up, s_bytes, s_cul, s_px, s_ta, s_tb;
    prw_stats_summarize(tri_a, (size_t)n, &sa_tri);
    prw_stats_summarize(lod_a, (size_t)n, &sa_lod);
    prw_stats_summarize(lod_b, (size_t)n, &sb_lod);
    prw_stats_summarize(tri_b, (size_t)n, &sb_tri);
    prw_stats_summarize(up_a, (size_t)n, &s_up);
    prw_stats_summarize(bytes_a, (size_t)n, &s_bytes);
    prw_stats_summarize(culled_a, (size_t)n, &s_cul);
    prw_stats_summarize(maxpx_a, (size_t)n, &s_px);
    prw_stats_summarize(ta, (size_t)n, &s_ta);
    prw_stats_summarize(tb, (size_t)n, &s_tb);
    double finest = (double)h->lod.finest_triangles;
    printf("full tessellation (finest level): %.0f triangles\n", finest);
    printf("displayed (1 instance, median over the path): %.0f triangles (min %.0f, max %.0f) = %.2f %% of the "
           "finest (goal <= 3 %% at 0.5 px); culled patches median %.0f of %d; worst projected error median "
           "%.2f px, max %.2f px\n",
           sa_tri.p50, sa_tri.min, sa_tri.max, 100.0 * sa_tri.p50 / finest, s_cul.p50, h->lod.npatches, s_px.p50,
           s_px.max);
    printf("LOD selection + buffer update per frame: 1 instance median %.3f ms (max %.3f); 100 instances median "
           "%.3f ms (max %.3f); re-uploaded slots per frame (1 instance) median %.0f, max %.0f; bytes median "
           "%.0f, max %.0f\n",
           sa_lod.p50, sa_lod.max, sb_lod.p50, sb_lod.max, s_up.p50, s_up.max, s_bytes.p50, s_bytes.max);
    prw_stats_summary s_da, s_db;
    prw_stats_summarize(draws_a, (size_t)n, &s_da);
    prw_stats_summarize(draws_b, (size_t)n, &s_db);
    prw_stats_summary s_pa, s_pb;
    prw_stats_summarize(prox_a, (size_t)n, &s_pa);
    prw_stats_summarize(prox_b, (size_t)n, &s_pb);
    printf("100 instances: displayed triangles median %.0f (%.2f x one instance's); base-pass LOD draws median "
           "%.0f (1 instance: %.0f); new layouts during the walk: 1 instance %llu, 100 instances %llu\n",
           sb_tri.p50, sb_tri.p50 / sa_tri.p50, s_db.p50, s_da.p50, (unsigned long long)relayouts_a,
           (unsigned long long)relayouts_b);
    const struct prw_lod_proxy *px = prw_lod_gpu_proxy(prw_lod_scene_model(prw_renderer_lod(ra), 0));
    if (px && !o->no_proxy) {
        char when[48];
        if (px->build_s > 0) snprintf(when, sizeof when, "built in %.2f s", px->build_s);
        else snprintf(when, sizeof when, "from the bake cache");
        printf("whole-model proxy: %d levels from level %d (%d triangles, bound %.3g m), %s:", px->nlevels,
               px->start_level, px->start_triangles, px->eps_start, when);
        for (int l = 0; l < px->nlevels; l++) printf(" %d tris / %.3g m", px->levels[l].ntris, px->levels[l].err);
        printf("\n  copies drawn as a proxy per frame: 1 instance median %.0f, 100 instances median %.0f (max %.0f)\n",
               s_pa.p50, s_pb.p50, s_pb.max);
    } else {
        printf("whole-model proxy: off (--no-proxy)\n");
    }
    printf("slot memory after the walk: 1 instance %.2f MB, 100 instances %.2f MB\n",
           prw_lod_gpu_memory(prw_lod_scene_model(prw_renderer_lod(ra), 0)) / 1e6,
           prw_lod_gpu_memory(prw_lod_scene_model(prw_renderer_lod(rb), 0)) / 1e6);
    prw_stats_ratio ratio;
    if (!prw_stats_bootstrap_pair_ratio(ta, tb, (size_t)n, LB_RESAMPLES, LB_SEED, &ratio)) {
        prw_fail(e, "bench --lod: no frame-time ratio (empty or zero times)");
        goto done;
    }
    printf("frame time: 1 instance median %.1f ms, 100 instances median %.1f ms; B/A (median of %ld per-pose "
           "ratios) = %.3f, 95 %% [%.3f, %.3f] (goal <= 1.5)\n",
           s_ta.p50, s_tb.p50, n, ratio.ratio, ratio.lo, ratio.hi);
    if (o->profile && pass_count_a == pass_count_b) {
        profile_print("A (1 instance)", prof_a, n, pass_names, pass_count_a);
        profile_print("B (100 instances)", prof_b, n, pass_names, pass_count_b);
        printf("profile: GPU timestamps flush on lavapipe; these frame times are not the A/B figures above\n");
    }
    if (prw_gpu_validation_count(gpu) != 0) {
        prw_fail(e, "%u Vulkan validation messages (see above)", prw_gpu_validation_count(gpu));
        goto done;
    }
    printf("bench --lod: wall time %.1f s\n", prw_now() - wall0);
    rc = 0;
done:
    prw_renderer_destroy(ra);
    prw_renderer_destroy(rb);
    if (gpu) prw_gpu_destroy(gpu);
    prw_scene_destroy(sa);
    prw_scene_destroy(sb);
    free(ta), free(tb), free(lod_a), free(lod_b), free(tri_a), free(tri_b);
    free(prof_a), free(prof_b);
    free(up_a), free(bytes_a), free(culled_a), free(maxpx_a), free(draws_a), free(draws_b), free(prox_a), free(prox_b);
    return rc;
}

int bench_lod_main(prw_args *a)
{
    prw_error e = {{0}};
    bool bad = false;
    const char *v;
    lod_bench_opts o = {.model = "car_shell", .width = 1280, .height = 720, .frames = 40, .msaa = 4, .tol_px = 0.5,
                        .chord_rel = 1e-5};
    if (prw_args_flag(a, "help")) {
        lod_usage();
        return 0;
    }
    o.per_pose = prw_args_flag(a, "per-pose");
    o.centre_pixel = prw_args_flag(a, "centre-pixel");
    o.profile = prw_args_flag(a, "profile");
    o.no_proxy = prw_args_flag(a, "no-proxy");
    if ((v = prw_args_value(a, "size", &e, &bad)) && !prw_parse_size(v, &o.width, &o.height, &e)) bad = true;
    if (!bad && (v = prw_args_value(a, "frames", &e, &bad)) && !prw_parse_int(v, "--frames", 2, 100000, &o.frames, &e))
        bad = true;
    if (!bad && (v = prw_args_value(a, "msaa", &e, &bad)) && !prw_parse_int(v, "--msaa", 1, 4, &o.msaa, &e)) bad = true;
    if (!bad && o.msaa != 1 && o.msaa != 4) bad = true, prw_fail(&e, "--msaa: 1 or 4, got %ld", o.msaa);
    if (!bad && (v = prw_args_value(a, "tol-px", &e, &bad)) && !prw_parse_double(v, "--tol-px", 0.01, 100, &o.tol_px, &e))
        bad = true;
    if (!bad && (v = prw_args_value(a, "chord-rel", &e, &bad)) &&
        !prw_parse_double(v, "--chord-rel", 1e-7, 0.1, &o.chord_rel, &e))
        bad = true;
    if (!bad && !prw_args_finish(a, &e)) bad = true;
    if (!bad && a->positional_count > 1) bad = true, prw_fail(&e, "bench --lod takes one MODEL, got %d", a->positional_count);
    if (!bad && a->positional_count == 1) o.model = a->positional[0];
    if (bad) {
        fprintf(stderr, "prw bench --lod: error: %s\n", e.msg);
        return 2;
    }
    int rc = run(&o, &e);
    if (rc) fprintf(stderr, "prw bench --lod: error: %s\n", e.msg);
    return rc;
}
