/* bake_curve — see bake_curve.h. */
#define _XOPEN_SOURCE 700
#define _DEFAULT_SOURCE
#include <ftw.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "app.h"
#include "bake_curve.h"
#include "lightmaps.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"

#define MAX_SETTINGS 32

static double cpu_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0;
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

static int rm_entry(const char *path, const struct stat *sb, int flag, struct FTW *ftw)
{
    (void)sb, (void)flag, (void)ftw;
    return remove(path);
}

/* A fresh cache: a new temporary directory made $PRW_CACHE_DIR (the previous value kept in old). */
static bool fresh_cache(char dir[4096], char **old, prw_error *e)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, 4096, "%s/prw-curve-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir)) return prw_fail(e, "%s: cannot create a temporary cache directory", dir);
    const char *prev = getenv("PRW_CACHE_DIR");
    *old = prev ? prw_strdup(prev) : NULL;
    setenv("PRW_CACHE_DIR", dir, 1);
    return true;
}

static void drop_cache(const char *dir, char *old)
{
    nftw(dir, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
    if (old) setenv("PRW_CACHE_DIR", old, 1);
    else unsetenv("PRW_CACHE_DIR");
    free(old);
}

typedef struct setting {
    uint32_t radiosity, samples;
} setting;

static int parse_settings(const char *list, setting *out)
{
    int n = 0;
    const char *p = list;
    while (*p && n < MAX_SETTINGS) {
        char *end = NULL;
        long r = strtol(p, &end, 10);
        if (end == p || *end != ':' || r < 1 || r > 16384) return -1;
        p = end + 1;
        long s = strtol(p, &end, 10);
        if (end == p || s < 1 || s > 65536 || (*end && *end != ',')) return -1;
        out[n++] = (setting){(uint32_t)r, (uint32_t)s};
        p = *end ? end + 1 : end;
    }
    return *p ? -1 : n;
}

static double luma(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

typedef struct masked {
    double flip, relmse;
} masked;

/* Mean LDR-FLIP (metric tone map at ev) and relMSE of test against ref over the mask. */
static bool masked_metrics(const prw_image *test, const prw_image *ref, const uint8_t *mask, double ev, masked *out,
                           prw_error *e)
{
    size_t np = (size_t)ref->width * ref->height, n = 0;
    prw_image te = {0}, re = {0};
    float *map = prw_malloc(np * sizeof(float));
    bool ok = prw_metric_tonemap(test, ev, &te, e) && prw_metric_tonemap(ref, ev, &re, e) &&
              prw_flip_ldr_encoded(&te, &re, PRW_FLIP_DEFAULT_PPD, map, e);
    double f = 0, rel = 0;
    for (size_t i = 0; ok && i < np; i++) {
        if (!mask[i]) continue;
        f += map[i];
        for (int c = 0; c < 3; c++) {
            double r = ref->rgba[4 * i + c], t = test->rgba[4 * i + c];
            rel += (t - r) * (t - r) / (r * r + PRW_RELMSE_EPSILON);
        }
        n++;
    }
    out->flip = n ? f / (double)n : 0;
    out->relmse = n ? rel / (3.0 * (double)n) : 0;
    free(map);
    prw_image_free(&te);
    prw_image_free(&re);
    return ok;
}

static bool render_ref(const prw_scene *s, const prw_view *v, uint64_t spp, uint64_t seed, prw_ref_filter_kind k,
                       prw_image *out, prw_error *e)
{
    prw_ref_renderer *ref = NULL;
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = k}};
    prw_ref_acc acc = {0};
    prw_ref_stats st;
    float *mean = NULL, *var = NULL;
    double c0 = cpu_now();
    bool ok = prw_ref_create(s, v->eye, g_prw_opts.threads, &ref, e) && prw_ref_render(ref, v, &d, &acc, &st, e) &&
              prw_ref_acc_images(&acc, &mean, &var, e) && prw_image_alloc(out, v->width, v->height, e);
    if (ok) {
        memcpy(out->rgba, mean, (size_t)v->width * v->height * 4 * sizeof(float));
        fprintf(stderr, "prw bake: reference %s seed %llu: %llu spp in %.1f s (%.1f CPU-s)\n",
                k == PRW_REF_ALL ? "all" : "indirect-diffuse-last", (unsigned long long)seed,
                (unsigned long long)st.spp, st.seconds, cpu_now() - c0);
    }
    free(mean);
    free(var);
    prw_ref_acc_free(&acc);
    prw_ref_destroy(ref);
    return ok;
}

static bool render_term(prw_gpu *gpu, const prw_scene *s, const prw_view *v, const prw_quality *q,
                        const prw_lightmaps *lm, prw_image *hdr, prw_error *e)
{
    prw_renderer *r = NULL;
    prw_render_desc rd = {.width = v->width, .height = v->height, .quality = *q, .lightmaps = lm,
                          .terms = PRW_TERM_INDIRECT_DIFFUSE};
    bool ok = prw_renderer_create(gpu, s, &rd, &r, e) && prw_renderer_render(r, v, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, hdr, e);
    prw_renderer_destroy(r);
    if (ok && prw_gpu_validation_count(gpu) != 0)
        ok = prw_fail(e, "%u Vulkan validation messages", prw_gpu_validation_count(gpu));
    return ok;
}

static void gi_bar(void *user, double f, const char *line)
{
    double *last = user, now = prw_now();
    if (f < 1 && now - *last < 2.0) return;
    *last = now;
    fprintf(stderr, "prw bake: %3.0f%% %s\n", f * 100, line);
}

extern char **environ;

static bool plot(const char *csv, const char *png, const char *scene)
{
    char cmd[12288];
    snprintf(cmd, sizeof cmd,
             "set terminal png size 900,560; set output '%s'; set datafile separator ','; set logscale x; set grid; "
             "set key top right; set xlabel 'bake CPU seconds from a fresh cache (all threads)'; set ytics nomirror; "
             "set y2tics; set ylabel 'LDR-FLIP beyond reference noise'; set y2label 'relMSE beyond reference noise'; "
             "set title \"prw bake --gi --curve: %s (labels: radiosity_size:samples)\" noenhanced; "
             "plot '%s' every ::1 using 10:13 with points pt 7 ps 1.5 title 'LDR-FLIP beyond noise', "
             "'' every ::1 using 10:16 axes x1y2 with points pt 5 ps 1.5 title 'relMSE beyond noise (right axis)', "
             "'' every ::1 using 10:13:(sprintf('%%d:%%d', $2, $3)) with labels offset 0,1 font ',9' notitle, "
             "0 with lines lt 0 notitle",
             png, scene, csv);
    char *argv[] = {"gnuplot", "-e", cmd, NULL};
    pid_t pid;
    if (posix_spawnp(&pid, "gnuplot", NULL, NULL, argv, environ) != 0) return false;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return false;
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

int bake_curve_run(const bake_curve_opts *o)
{
    setting set[MAX_SETTINGS];
    char defaults[64];
    snprintf(defaults, sizeof defaults, "64:32,128:32,128:128,%u:32,%u:64,%u:%u,%u:256", o->q.radiosity_size,
             o->q.radiosity_size, o->q.radiosity_size, PRW_GI_DEFAULT_SAMPLES, o->q.radiosity_size);
    const char *list = o->settings ? o->settings : defaults;
    int ns = parse_settings(list, set);
    if (ns <= 0) {
        fprintf(stderr, "prw bake: error: --settings '%s': expected radiosity_size:samples pairs, e.g. 128:32,256:128\n",
                list);
        return 2;
    }
    prw_error e = {{0}};
    FILE *f = o->csv ? fopen(o->csv, "w") : stdout;
    if (!f) {
        fprintf(stderr, "prw bake: error: %s: cannot write\n", o->csv);
        return 1;
    }
    fprintf(f, "scene,radiosity_size,samples,filter_radius,texel_m,texels,vertices,load_lod_s,bake_wall_s,bake_cpu_s,"
               "flip,flip_noise,flip_beyond,relmse,relmse_noise,relmse_beyond\n");
    fflush(f);
    prw_gpu *gpu = NULL;
    prw_image ra = {0}, rb = {0}, rall = {0};
    uint8_t *mask = NULL;
    double ev = 0;
    masked noise = {0};
    int rc = 1, def_row = -1;
    double def_wall = 0, def_cpu = 0, def_load = 0;
    size_t nm = 0;
    char cam_name[128] = "";
    if (!prw_app_create_gpu(false, &gpu, &e)) goto done;
    for (int k = 0; k < ns; k++) {
        char dir[4096], *old = NULL;
        if (!fresh_cache(dir, &old, &e)) goto done;
        prw_scene *s = NULL;
        prw_gi_bake *b = NULL;
        prw_app_lightmaps *lms = NULL;
        prw_gi_result gr;
        prw_image hdr = {0};
        prw_view v;
        double last = 0;
        prw_gi_options go = {.radiosity_size = set[k].radiosity, .samples = set[k].samples, .seed = o->seed,
                             .filter_radius = PRW_GI_DEFAULT_FILTER_RADIUS};
        /* timed: the scene made ready (NURBS LOD from the fresh cache) and the GI bake with its cache write */
        double w0 = prw_now();
        bool ok = prw_app_load_renderable(o->scene, &s, &e) && prw_app_bake_scene(s, &e);
        double w1 = prw_now(), c1 = cpu_now();
        ok = ok && prw_gi_run(s, &go, false, gi_bar, &last, &b, &gr, &e);
        double w2 = prw_now(), c2 = cpu_now();
        drop_cache(dir, old);
        int cam = ok ? prw_scene_find_camera(s, o->camera) : -1;
        if (ok && cam < 0) ok = prw_fail(&e, "%s: no camera named '%s'", s->source, o->camera ? o->camera : "(first)");
        ok = ok && prw_view_from_camera(s, cam, o->width, o->height, &v, &e);
        if (ok) snprintf(cam_name, sizeof cam_name, "%s", s->cameras[cam].name);
        uint64_t texels = ok ? b->sampled_texels : 0, verts = ok ? b->sampled_vertices : 0;
        double texel = ok ? b->texel_size : 0;
        if (ok && k == 0) { /* the references, once */
            ok = render_ref(s, &v, o->ref_spp, 1, PRW_REF_INDIRECT_DIFFUSE_LAST, &ra, &e) &&
                 render_ref(s, &v, o->ref_spp, 2, PRW_REF_INDIRECT_DIFFUSE_LAST, &rb, &e) &&
                 render_ref(s, &v, o->ref_spp > 4 ? o->ref_spp / 4 : 1, 3, PRW_REF_ALL, &rall, &e);
            if (ok) {
                mask = prw_calloc((size_t)o->width * o->height, 1);
                for (size_t i = 0; i < (size_t)o->width * o->height; i++) {
                    mask[i] = luma(ra.rgba + 4 * i) > 0.01 * luma(rall.rgba + 4 * i);
                    nm += mask[i];
                }
                ev = prw_compare_derive_ev100(&ra, NULL);
                ok = masked_metrics(&rb, &ra, mask, ev, &noise, &e);
            }
        }
        ok = ok && prw_app_lightmaps_from_bake(s, b, &lms, &e);
        b = NULL; /* owned by lms (or freed) */
        masked m = {0};
        ok = ok && render_term(gpu, s, &v, &o->q, prw_app_lightmaps_get(lms), &hdr, &e) &&
             masked_metrics(&hdr, &ra, mask, ev, &m, &e);
        if (ok) {
            double fb = m.flip - noise.flip, rb2 = m.relmse - noise.relmse / 2;
            fprintf(f, "%s,%u,%u,%u,%.5f,%llu,%llu,%.3f,%.3f,%.3f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f\n", s->source,
                    set[k].radiosity, set[k].samples, go.filter_radius, texel, (unsigned long long)texels,
                    (unsigned long long)verts, w1 - w0, w2 - w1, c2 - c1, m.flip, noise.flip, fb, m.relmse,
                    noise.relmse, rb2);
            fflush(f);
            fprintf(stderr,
                    "prw bake: %u:%u  texel %.4f m, %llu texels + %llu vertices; scene + LOD %.2f s; GI bake %.2f s "
                    "(%.2f CPU-s); LDR-FLIP beyond noise %.4f, relMSE beyond noise %.4f\n",
                    set[k].radiosity, set[k].samples, texel, (unsigned long long)texels, (unsigned long long)verts,
                    w1 - w0, w2 - w1, c2 - c1, fb, rb2);
            if (set[k].radiosity == o->q.radiosity_size && set[k].samples == PRW_GI_DEFAULT_SAMPLES)
                def_row = k, def_wall = w2 - w1, def_cpu = c2 - c1, def_load = w1 - w0;
        }
        prw_gi_bake_destroy(b);
        prw_app_lightmaps_destroy(lms);
        prw_image_free(&hdr);
        prw_scene_destroy(s);
        if (!ok) goto done;
    }
    rc = 0;
    printf("%s, camera %s, %ux%u, term indirect-diffuse vs reference indirect-diffuse-last %u spp (seeds 1, 2), "
           "%zu of %u pixels where the term > 1 %% of the full reference, metric EV100 %.3f (the term's own); "
           "reference noise: LDR-FLIP %.4f, relMSE %.4f\n",
           o->scene, cam_name, o->width, o->height, o->ref_spp, nm, o->width * o->height, ev,
           noise.flip, noise.relmse);
    double la[3] = {0, 0, 0};
    int nla = getloadavg(la, 3);
    if (def_row >= 0)
        printf("default bake (radiosity_size %u, %u samples, filter radius %u) from a fresh cache: %.2f s wall, %.2f "
               "CPU-s, %d threads (+ scene load and NURBS LOD %.2f s); load average %.2f %.2f %.2f\n",
               o->q.radiosity_size, PRW_GI_DEFAULT_SAMPLES, PRW_GI_DEFAULT_FILTER_RADIUS, def_wall, def_cpu,
               prw_threads_get(), def_load, nla > 0 ? la[0] : -1, nla > 1 ? la[1] : -1, nla > 2 ? la[2] : -1);
    else
        printf("(the default bake %u:%u is not among the settings)\n", o->q.radiosity_size, PRW_GI_DEFAULT_SAMPLES);
done:
    if (rc) fprintf(stderr, "prw bake: error: %s\n", e.msg);
    if (o->csv) fclose(f);
    if (rc != 0 && o->csv) remove(o->csv); /* no partial file */
    if (rc == 0 && o->png) {
        if (plot(o->csv, o->png, o->scene)) fprintf(stderr, "prw bake: wrote %s\n", o->png);
        else fprintf(stderr, "prw bake: warning: %s not written (gnuplot missing or failed; the CSV is complete)\n", o->png);
    }
    free(mask);
    prw_image_free(&ra);
    prw_image_free(&rb);
    prw_image_free(&rall);
    if (gpu) prw_gpu_destroy(gpu);
    return rc;
}
