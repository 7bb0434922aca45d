/* prw bake — build a trimmed-NURBS model's LOD hierarchy into the content-addressed cache
 * (engine/bake/prw_bake.h) and optionally write it to a .lod file. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <string.h>

#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "app.h"
#include "bake_curve.h"
#include "prw_bake.h"
#include "lightmaps.h"
#include "prw_gi.h"
#include "prw_probe.h"
#include "quality_args.h"

static void progress(void *user, const char *line)
{
    (void)user;
    fprintf(stderr, "prw bake: %s\n", line);
    fflush(stderr);
}

static void help(void)
{
    printf("usage: prw bake MODEL.(igs|iges|json) [--out FILE.lod] [knobs] [--no-cache]\n"
           "       prw bake SCENE --gi [...]   indirect-diffuse light maps (prw bake --gi --help)\n"
           "  Builds the seam graph and per-patch LOD hierarchies of a trimmed-NURBS model (IGES 5.3 or\n"
           "  the JSON form, lod/nurbs_json.md), or loads them from the cache, and prints the cache key,\n"
           "  patch / level / triangle counts, the time and the cache path.  Progress goes to stderr.\n"
           "  Cache: $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else ~/.cache/prw; subdirectory lod/,\n"
           "  entries <key>.lod; the key hashes the file bytes, the format version and every knob\n"
           "  ('prw cache clear lod' empties it).\n"
           "options:\n"
           "  --out FILE.lod             also write the hierarchy here (atomically)\n"
           "  --no-cache                 neither read nor write the cache\n"
           "knobs (metres; 0 or absent: the default):\n"
           "  --tolerance X              sewing chordal tolerance (default 1e-3 x model diagonal)\n"
           "  --adjacency X              patch adjacency tolerance (default 1e-6 x diagonal)\n"
           "  --max-edge X               longest sewing edge (default diagonal / 40)\n"
           "  --levels N                 hierarchy levels, 1..%d (default 14)\n"
           "  --tau0 X                   finest-level error target (default: the sewing tolerance)\n"
           "  --finest-rel R             finest-level error target R x model diagonal (e.g. 1e-5; lifts the\n"
           "                             per-patch triangle cap; sewing tolerance default: half of it)\n"
           "  --max-cells N              finest tessellation grid cap per direction (default 48)\n"
           "  --max-patch-triangles N    level-0 refinement cap per patch (default 2 x initial + 4096)\n",
           PRW_LOD_MAX_LEVELS);
}

/* ---- prw bake SCENE --gi ---- */

typedef struct gi_bar {
    double last;
    bool tty;
} gi_bar;

static void gi_progress(void *user, double f, const char *line)
{
    gi_bar *b = user;
    double now = prw_now();
    if (f < 1 && now - b->last < 0.25) return;
    b->last = now;
    char bar[33];
    int n = (int)(f * 32 + 0.5);
    for (int i = 0; i < 32; i++) bar[i] = i < n ? '#' : '.';
    bar[32] = 0;
    fprintf(stderr, "%sprw bake: [%s] %3.0f%% %s%s", b->tty ? "\r" : "", bar, f * 100, line, b->tty ? "" : "\n");
    if (b->tty && f >= 1) fprintf(stderr, "\n");
    fflush(stderr);
}

static void gi_help(void)
{
    printf("usage: prw bake SCENE --gi [--samples N] [--seed N] [--preset CONFIG] [--out FILE.gi] [--no-cache]\n"
           "       prw bake SCENE --gi --sweep [--samples-list A,B,..] [--ref-samples N] [--preset CONFIG] [--csv FILE]\n"
           "            [--png FILE]\n"
           "       prw bake SCENE --gi --curve [--settings R:S,..] [--size WxH] [--camera NAME] [--ref-spp N]\n"
           "            [--preset CONFIG] [--csv FILE] [--png FILE]\n"
           "  Bakes the indirect-diffuse light maps of SCENE (engine/bake/prw_gi.h): at every light-map texel\n"
           "  (flat charts of our own unwrapper, packed into atlases) and at the vertices of dense meshes, the\n"
           "  irradiance of light that scattered at least once (never direct light), gathered by the reference\n"
           "  path tracer with cosine-weighted rays.  The texel size follows the quality knob radiosity_size\n"
           "  (--preset \"radiosity_size=N\": about N x N sampled texels in all).  Progress on stderr.\n"
           "  Cache: $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else ~/.cache/prw; subdirectory gi/; the key\n"
           "  hashes the static geometry, materials, textures, lights, environment, the knobs and the algorithm\n"
           "  version (not the cameras).\n"
           "  Then the reflection probes (engine/bake/prw_probe.h; subdirectory probe/): one per curved glossy\n"
           "  object (non-planar, roughness <= 0.5), at most the knob probe_count, the radiance leaving the\n"
           "  surfaces around it gathered at its centre on a 2N x N map (N: the knob probe_size), prefiltered per\n"
           "  roughness; printed with their place.  probe_count=0: none.\n"
           "options:\n"
           "  --samples N        gather rays per texel / vertex, 1..65536 (default %d)\n"
           "  --seed N           random-number seed (default 0)\n"
           "  --filter-radius R  box filter over R texels within each chart after gathering, 0..8 (default %d; 0: off)\n"
           "  --out FILE.gi      also write the light maps here (atomically)\n"
           "  --no-cache         neither read nor write the cache\n"
           "  --sweep            benchmark: error against bake time over sample counts (CSV: samples, seconds,\n"
           "                     cpu_seconds, rel_rms_error, rel_noise, filter_radius; the counts run\n"
           "                     unfiltered, then with the filter radius unless it is 0); the error is\n"
           "                     against an unfiltered bake with --ref-samples (default 2048) and another\n"
           "                     seed at the same texels; nothing is cached\n"
           "  --samples-list L   the sweep's sample counts (default 16,32,64,128,256)\n"
           "  --csv FILE         the sweep's CSV (default: stdout)\n"
           "  --png FILE         the sweep's / curve's plot (error against CPU seconds; needs --csv and gnuplot)\n"
           "  --curve            benchmark: per setting radiosity_size:samples, the scene loaded and baked from a\n"
           "                     fresh (temporary) cache, timed (wall, CPU), then the base pass's light-map term\n"
           "                     against the reference's indirect-diffuse-last term (two seeds): LDR-FLIP and\n"
           "                     relMSE beyond noise (CSV: one row per setting); ends with the default bake's time\n"
           "  --settings L       the curve's settings (default 64:32,128:32,128:128,Q:32,Q:64,Q:%d,Q:256, Q the\n"
           "                     preset's radiosity_size)\n"
           "  --size WxH         the curve's image size (default 128x72)\n"
           "  --camera NAME      the curve's camera (default: the first)\n"
           "  --ref-spp N        the curve's reference samples per pixel (default 512)\n"
           "%s",
           PRW_GI_DEFAULT_SAMPLES, PRW_GI_DEFAULT_FILTER_RADIUS, PRW_GI_DEFAULT_SAMPLES, prw_quality_args_help());
}

/* Relative RMS difference of the sampled texels / vertices of a against ref (same layout), over
 * the channel mean; noise: the RMS of a's own standard error, relative the same way. */
static void gi_compare(const prw_gi_bake *a, const prw_gi_bake *ref, double *rel_rms, double *rel_noise)
{
    double d2 = 0, v = 0, m = 0;
    uint64_t n = 0;
    for (uint32_t i = 0; i < a->atlas_count && i < ref->atlas_count; i++) {
        const prw_gi_atlas *A = &a->atlases[i], *R = &ref->atlases[i];
        size_t t = (size_t)A->width * A->height;
        if (R->width != A->width || R->height != A->height) continue;
        for (size_t k = 0; k < t; k++) {
            if (A->state[k] != 1) continue;
            for (int c = 0; c < 3; c++) {
                double d = A->rgb[3 * k + c] - R->rgb[3 * k + c];
                d2 += d * d;
                v += A->var[3 * k + c];
                m += R->rgb[3 * k + c];
                n++;
            }
        }
    }
    for (uint32_t i = 0; i < a->instance_count && i < ref->instance_count; i++) {
        const prw_gi_instance *A = &a->inst[i], *R = &ref->inst[i];
        if (A->mode != PRW_GI_VERTEX || R->mode != PRW_GI_VERTEX || A->vertex_count != R->vertex_count) continue;
        for (size_t k = 0; k < 3 * (size_t)A->vertex_count; k++) {
            double d = A->vertex_rgb[k] - R->vertex_rgb[k];
            d2 += d * d;
            v += A->vertex_var[k];
            m += R->vertex_rgb[k];
            n++;
        }
    }
    m = n ? m / n : 0;
    *rel_rms = n && m > 0 ? sqrt(d2 / n) / m : 0;
    *rel_noise = n && m > 0 ? sqrt(v / n) / m : 0;
}

extern char **environ;

/* The sweep's plot: relative RMS error against CPU seconds, log-log, through gnuplot (-e, no
 * script file).  false when gnuplot is missing or fails. */
static bool gi_plot(const char *csv, const char *png)
{
    char cmd[12288];
    snprintf(cmd, sizeof cmd,
             "set terminal png size 800,520; set output '%s'; set datafile separator ','; set logscale xy; "
             "set grid; set key top right; set xlabel 'bake CPU seconds (all threads)'; "
             "set ylabel 'relative RMS error per texel'; set title 'prw bake --gi: error against bake time'; "
             "plot '%s' every ::1 using 3:($6 == 0 ? $4 : 1/0) with linespoints lw 2 pt 7 title 'error vs reference bake', "
             "'' every ::1 using 3:($6 == 0 ? $5 : 1/0) with lines dt 2 title 'estimated noise (own variance)', "
             "'' every ::1 using 3:($6 > 0 ? $4 : 1/0) with linespoints lw 2 pt 5 title 'error, box filter (--filter-radius)'",
             png, csv);
    char *argv[] = {"gnuplot", "-e", cmd, NULL};
    pid_t pid;
    if (posix_spawnp(&pid, "gnuplot", NULL, NULL, argv, environ) != 0) return false;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return false;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/* CPU seconds of this process (every thread): the sweep's load-independent cost figure. */
static double cpu_seconds(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0;
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int gi_sweep(const prw_scene *s, prw_gi_options o, const char *list, uint32_t ref_samples, const char *csv,
                    const char *png)
{
    prw_error e = {{0}};
    uint32_t counts[16];
    int nc = 0;
    const char *p = list ? list : "16,32,64,128,256";
    while (*p && nc < 16) {
        char *end = NULL;
        long v = strtol(p, &end, 10);
        if (end == p || v < 1 || v > 65536 || (*end && *end != ',')) {
            fprintf(stderr, "prw bake: error: --samples-list '%s': expected comma-separated counts in 1..65536\n", list);
            return 2;
        }
        counts[nc++] = (uint32_t)v;
        p = *end ? end + 1 : end;
    }
    FILE *f = csv ? fopen(csv, "w") : stdout;
    if (!f) {
        fprintf(stderr, "prw bake: error: %s: cannot write\n", csv);
        return 1;
    }
    gi_bar bar = {0, false};
    prw_gi_options ro = o;
    ro.samples = ref_samples;
    ro.filter_radius = 0; /* the reference is the unfiltered estimate */
    ro.seed = o.seed + 1000003;
    prw_gi_bake *ref = NULL;
    fprintf(stderr, "prw bake: sweep reference: %u samples per point\n", ref_samples);
    double t0 = prw_now();
    if (!prw_gi_build(s, &ro, gi_progress, &bar, &ref, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        if (csv) fclose(f);
        return 1;
    }
    fprintf(stderr, "prw bake: reference bake %.2f s (%llu texels + %llu vertices, texel %.4g m)\n", prw_now() - t0,
            (unsigned long long)ref->sampled_texels, (unsigned long long)ref->sampled_vertices, ref->texel_size);
    fprintf(f, "samples,seconds,cpu_seconds,rel_rms_error,rel_noise,filter_radius\n");
    int rc = 0;
    /* unfiltered rows, then (with --filter-radius R) the same counts filtered */
    for (int k = 0; k < nc * (o.filter_radius ? 2 : 1) && rc == 0; k++) {
        int i = k % nc;
        prw_gi_options so = o;
        so.samples = counts[i];
        so.filter_radius = k < nc ? 0 : o.filter_radius;
        prw_gi_bake *b = NULL;
        double t1 = prw_now(), c1 = cpu_seconds();
        if (!prw_gi_build(s, &so, gi_progress, &bar, &b, &e)) {
            fprintf(stderr, "prw bake: error: %s\n", e.msg);
            rc = 1;
            break;
        }
        double secs = prw_now() - t1, cpu = cpu_seconds() - c1, err, noise;
        gi_compare(b, ref, &err, &noise);
        fprintf(f, "%u,%.3f,%.3f,%.5f,%.5f,%u\n", counts[i], secs, cpu, err, noise, so.filter_radius);
        fflush(f);
        prw_gi_bake_destroy(b);
    }
    prw_gi_bake_destroy(ref);
    if (csv) fclose(f);
    if (rc == 0 && png) {
        if (gi_plot(csv, png)) fprintf(stderr, "prw bake: wrote %s\n", png);
        else fprintf(stderr, "prw bake: warning: %s not written (gnuplot missing or failed; the CSV is complete)\n", png);
    }
    return rc;
}

static int bake_gi(prw_args *a)
{
    prw_error e = {{0}};
    if (prw_args_flag(a, "help")) {
        gi_help();
        return 0;
    }
    bool bad = false;
    prw_quality q;
    prw_quality_args_read(a, &q, &bad, &e);
    prw_gi_options o;
    memset(&o, 0, sizeof o);
    o.radiosity_size = q.radiosity_size;
    o.filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS;
    long n;
    const char *v;
    if (!bad && (v = prw_args_value(a, "samples", &e, &bad))) {
        if (prw_parse_int(v, "--samples", 1, 65536, &n, &e)) o.samples = (uint32_t)n;
        else bad = true;
    }
    if (!bad && (v = prw_args_value(a, "seed", &e, &bad))) {
        if (prw_parse_int(v, "--seed", 0, 2147483647L, &n, &e)) o.seed = (uint64_t)n;
        else bad = true;
    }
    if (!bad && (v = prw_args_value(a, "filter-radius", &e, &bad))) {
        if (prw_parse_int(v, "--filter-radius", 0, 8, &n, &e)) o.filter_radius = (uint32_t)n;
        else bad = true;
    }
    uint32_t ref_samples = 2048;
    if (!bad && (v = prw_args_value(a, "ref-samples", &e, &bad))) {
        if (prw_parse_int(v, "--ref-samples", 1, 65536, &n, &e)) ref_samples = (uint32_t)n;
        else bad = true;
    }
    const char *out = bad ? NULL : prw_args_value(a, "out", &e, &bad);
    const char *list = bad ? NULL : prw_args_value(a, "samples-list", &e, &bad);
    const char *csv = bad ? NULL : prw_args_value(a, "csv", &e, &bad);
    const char *png = bad ? NULL : prw_args_value(a, "png", &e, &bad);
    if (!bad && png && !csv) bad = !prw_fail(&e, "--png needs --csv FILE (the plot reads it)");
    if (!bad && png && (strchr(png, '\'') || strchr(csv, '\'')))
        bad = !prw_fail(&e, "--png / --csv: a path with a single quote cannot be handed to gnuplot");
    bool curve = prw_args_flag(a, "curve");
    const char *settings = bad ? NULL : prw_args_value(a, "settings", &e, &bad);
    const char *camera = bad ? NULL : prw_args_value(a, "camera", &e, &bad);
    uint32_t cw = 128, ch = 72, ref_spp = 512;
    if (!bad && (v = prw_args_value(a, "size", &e, &bad)) && !prw_parse_size(v, &cw, &ch, &e)) bad = true;
    if (!bad && (v = prw_args_value(a, "ref-spp", &e, &bad))) {
        if (prw_parse_int(v, "--ref-spp", 1, 1 << 20, &n, &e)) ref_spp = (uint32_t)n;
        else bad = true;
    }
    bool sweep = prw_args_flag(a, "sweep");
    bool no_cache = prw_args_flag(a, "no-cache");
    if (!bad && !prw_args_finish(a, &e)) bad = true;
    if (!bad && a->positional_count != 1) {
        prw_fail(&e, "expected one SCENE argument, got %d (see prw bake --gi --help)", a->positional_count);
        bad = true;
    }
    if (bad) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        return 2;
    }
    const char *path = a->positional[0];
    if (curve) {
        if (sweep || out) {
            fprintf(stderr, "prw bake: error: --curve excludes --sweep and --out\n");
            return 2;
        }
        bake_curve_opts co = {.scene = path, .camera = camera, .settings = settings, .width = cw, .height = ch,
                                  .ref_spp = ref_spp, .seed = o.seed, .csv = csv, .png = png, .q = q};
        return bake_curve_run(&co);
    }
    if (out && !prw_check_writable(out, false, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        return 1;
    }
    prw_scene *s = NULL;
    if (!prw_app_load_renderable(path, &s, &e) || !prw_app_bake_scene(s, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        prw_scene_destroy(s);
        return 1;
    }
    if (sweep) {
        int rc = gi_sweep(s, o, list, ref_samples, csv, png);
        prw_scene_destroy(s);
        return rc;
    }
    gi_bar bar = {0, isatty(fileno(stderr)) != 0};
    prw_gi_bake *b = NULL;
    prw_gi_result r;
    double cpu0 = cpu_seconds();
    if (!prw_gi_run(s, &o, no_cache, gi_progress, &bar, &b, &r, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        prw_scene_destroy(s);
        return 1;
    }
    /* the reflection probes, with the light maps (the same cache rules) */
    prw_probe_bake *pb = NULL;
    prw_probe_result pr;
    memset(&pr, 0, sizeof pr);
    prw_probe_options po = prw_app_probe_options(&q);
    double pcpu0 = cpu_seconds();
    if (q.probe_count && !prw_probe_run(s, &po, no_cache, gi_progress, &bar, &pb, &pr, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        prw_gi_bake_destroy(b);
        prw_scene_destroy(s);
        return 1;
    }
    double pcpu = cpu_seconds() - pcpu0;
    int rc = 0;
    if (out) {
        uint8_t *data = NULL;
        size_t size = 0;
        if (!prw_gi_encode(b, r.key, &data, &size, &e) || !prw_write_file_atomic(out, data, size, &e)) {
            fprintf(stderr, "prw bake: error: %s\n", e.msg);
            rc = 1;
        }
        free(data);
    }
    if (rc == 0) {
        uint32_t modes[3] = {0, 0, 0};
        for (uint32_t i = 0; i < b->instance_count; i++) modes[b->inst[i].mode < 3 ? b->inst[i].mode : 0]++;
        printf("key %s\n", r.key);
        printf("%s: gi light maps: texel %.4g m (radiosity_size %u), %u samples per point, %u atlases", path,
               b->texel_size, o.radiosity_size, b->samples, b->atlas_count);
        for (uint32_t i = 0; i < b->atlas_count; i++) printf("%s%ux%u", i ? " " : " (", b->atlases[i].width, b->atlases[i].height);
        printf("%s\n", b->atlas_count ? ")" : "");
        printf("instances: %u in atlases, %u per vertex, %u not baked (no diffuse lobe)\n", modes[1], modes[2], modes[0]);
        if (r.built)
            printf("built in %.2f s (CPU %.2f s, %d threads): %llu charts, %llu texels (%llu hidden) + %llu vertices "
                   "gathered in %.2f s, filter radius %u\n",
                   r.seconds_total, cpu_seconds() - cpu0, prw_threads_get(), (unsigned long long)b->charts,
                   (unsigned long long)b->sampled_texels, (unsigned long long)b->hidden_texels,
                   (unsigned long long)b->sampled_vertices, b->seconds_gather, o.filter_radius);
        else
            printf("cache hit (nothing built), %.3f s\n", r.seconds_total);
        if (r.warning[0]) fprintf(stderr, "prw bake: warning: %s\n", r.warning);
        if (r.cache_path[0]) printf("cache %s%s\n", r.cache_path, r.cache_hit || r.cache_written ? "" : " (not written)");
        else printf("cache not used\n");
        if (out) printf("wrote %s\n", out);
        if (pb) {
            printf("probes: %u (probe_count %u), map %ux%u, %u rays per texel, %u levels of %ux%u\n", pb->count,
                   q.probe_count, 2 * pb->size, pb->size, pb->samples, pb->levels, 2 * pb->level_height,
                   pb->level_height);
            for (uint32_t i = 0; i < pb->count; i++) {
                const prw_probe_info *p = &pb->probes[i];
                printf("  probe %u: node '%s', material '%s', centre (%.3f, %.3f, %.3f), box (%.3f, %.3f, %.3f)-(%.3f, "
                       "%.3f, %.3f)\n", i, s->nodes[p->node].name, s->materials[p->material].name, p->centre[0],
                       p->centre[1], p->centre[2], p->box_min[0], p->box_min[1], p->box_min[2], p->box_max[0],
                       p->box_max[1], p->box_max[2]);
            }
            if (pr.built) printf("probes built in %.2f s (CPU %.2f s)\n", pr.seconds_total, pcpu);
            else printf("probes: cache hit (nothing built), %.3f s\n", pr.seconds_total);
            if (pr.warning[0]) fprintf(stderr, "prw bake: warning: %s\n", pr.warning);
            if (pr.cache_path[0]) printf("probe cache %s%s\n", pr.cache_path, pr.cache_hit || pr.cache_written ? "" : " (not written)");
        }
    }
    prw_probe_bake_destroy(pb);
    prw_gi_bake_destroy(b);
    prw_scene_destroy(s);
    return rc;
}

int prw_cmd_bake(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    if (!prw_args_init(&a, argc, argv, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        return 2;
    }
    if (prw_args_flag(&a, "gi")) {
        int rc = bake_gi(&a);
        prw_args_free(&a);
        return rc;
    }
    if (prw_args_flag(&a, "help")) {
        help();
        prw_args_free(&a);
        return 0;
    }
    prw_bake_options o;
    memset(&o, 0, sizeof o);
    bool bad = false;
    const char *v, *out = prw_args_value(&a, "out", &e, &bad);
    long n;
    if (!bad && (v = prw_args_value(&a, "tolerance", &e, &bad)) && !prw_parse_double(v, "--tolerance", 0, 1e9, &o.seam.chord, &e)) bad = true;
    if (!bad && (v = prw_args_value(&a, "adjacency", &e, &bad)) && !prw_parse_double(v, "--adjacency", 0, 1e9, &o.seam.tol, &e)) bad = true;
    if (!bad && (v = prw_args_value(&a, "max-edge", &e, &bad)) && !prw_parse_double(v, "--max-edge", 0, 1e9, &o.seam.max_edge, &e)) bad = true;
    if (!bad && (v = prw_args_value(&a, "tau0", &e, &bad)) && !prw_parse_double(v, "--tau0", 0, 1e9, &o.lod.tau0, &e)) bad = true;
    if (!bad && (v = prw_args_value(&a, "finest-rel", &e, &bad)) &&
        !prw_parse_double(v, "--finest-rel", 1e-9, 0.1, &o.lod.finest_rel, &e))
        bad = true;
    if (!bad && (v = prw_args_value(&a, "levels", &e, &bad))) {
        if (prw_parse_int(v, "--levels", 1, PRW_LOD_MAX_LEVELS, &n, &e)) o.lod.levels = (int)n;
        else bad = true;
    }
    if (!bad && (v = prw_args_value(&a, "max-cells", &e, &bad))) {
        if (prw_parse_int(v, "--max-cells", 0, 4096, &n, &e)) o.lod.max_cells = (int)n;
        else bad = true;
    }
    if (!bad && (v = prw_args_value(&a, "max-patch-triangles", &e, &bad))) {
        if (prw_parse_int(v, "--max-patch-triangles", 0, 100000000, &n, &e)) o.lod.max_patch_triangles = (int)n;
        else bad = true;
    }
    bool no_cache = prw_args_flag(&a, "no-cache");
    if (!bad && !prw_args_finish(&a, &e)) bad = true;
    if (!bad && a.positional_count != 1) {
        prw_fail(&e, "expected one MODEL.(igs|iges|json) argument, got %d (see prw bake --help)", a.positional_count);
        bad = true;
    }
    if (bad) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        prw_args_free(&a);
        return 2;
    }
    const char *path = a.positional[0];
    if (out && !prw_check_writable(out, false, &e)) { /* before the bake, which can take minutes */
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        prw_args_free(&a);
        return 1;
    }
    prw_baked_lod *b;
    prw_bake_result r;
    if (!prw_bake_run(path, &o, no_cache, &b, &r, progress, NULL, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        prw_args_free(&a);
        return 1;
    }
    int rc = 0;
    if (out && !prw_lod_file_write(out, b, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        rc = 1;
    }
    if (rc == 0) {
        const prw_lod_model *lm = &b->lod;
        size_t per_level[PRW_LOD_MAX_LEVELS] = {0};
        int ok = 0;
        for (int p = 0; p < lm->npatches; p++) {
            if (!lm->patches[p].ok) continue;
            ok++;
            for (int k = 0; k < lm->levels; k++) per_level[k] += (size_t)prw_lod_patch_triangles(lm, p, k);
        }
        printf("key %s\n", r.key);
        printf("%s: %d patches (%d with a hierarchy, %d failed), %d segments, %d levels, tau0 %.4g m\n", path,
               lm->npatches, ok, lm->failed_patches, b->graph.nsegs, lm->levels, lm->tau0);
        printf("triangles per level:");
        for (int k = 0; k < lm->levels; k++) printf(" %zu", per_level[k]);
        printf("\n");
        if (lm->failed_patches && lm->first_problem[0]) printf("first problem: %s\n", lm->first_problem);
        if (r.warning[0]) fprintf(stderr, "prw bake: warning: %s\n", r.warning);
        if (r.cache_hit) printf("cache hit (nothing built), %.3f s\n", r.seconds_total);
        else printf("built in %.3f s (read %.3f s, seam graph + hierarchy %.3f s)\n", r.seconds_total, r.seconds_read,
                    r.seconds_build);
        if (r.cache_path[0]) printf("cache %s%s\n", r.cache_path, r.cache_hit || r.cache_written ? "" : " (not written)");
        else printf("cache not used\n");
        if (out) printf("wrote %s\n", out);
    }
    prw_lod_file_destroy(b);
    prw_args_free(&a);
    return rc;
}
