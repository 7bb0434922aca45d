/* prw_bake.c — building hierarchies and their cache entries (prw_bake.h). */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "prw_bake.h"
#include "prw_cache.h"
#include "prw_iges.h"
#include "prw_lod_orient.h"
#include "prw_nurbs_json.h"

static int g_builds;

int prw_bake_build_count(void) { return g_builds; }

static void say(prw_bake_progress_fn fn, void *user, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void say(prw_bake_progress_fn fn, void *user, const char *fmt, ...)
{
    if (!fn) return;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    fn(user, line);
}

bool prw_baked_lod_build(const prw_nurbs_model *m, const prw_bake_options *o, prw_baked_lod **out,
                         prw_bake_progress_fn progress, void *user, prw_error *e)
{
    *out = NULL;
    if (m->count == 0) return prw_fail(e, "model has no surfaces");
    prw_bake_options opt = o ? *o : (prw_bake_options){0};
    if (opt.lod.finest_rel > 0 && opt.seam.chord == 0) {
        /* the boundary part of a bound cannot be refined away: sew at half the finest target */
        prw_dvec3 lo, hi;
        prw_nurbs_model_bounds(m, &lo, &hi);
        opt.seam.chord = 0.5 * opt.lod.finest_rel * prw_v3_len(prw_v3_sub(hi, lo));
    }
    prw_baked_lod *b = prw_calloc(1, sizeof *b);
    double t0 = prw_now();
    if (!prw_seam_build(m, &opt.seam, &b->graph, e)) {
        free(b);
        return false;
    }
    const prw_seam_graph *g = &b->graph;
    say(progress, user, "seam graph: %d patches, %d segments (%d shared, %d open), %d sewing vertices, %.2f s",
        g->npatches, g->nsegs, g->shared, g->open, g->ngids, prw_now() - t0);
    t0 = prw_now();
    if (!prw_lod_build(m, &b->graph, &opt.lod, &b->lod, e)) {
        prw_seam_free(&b->graph);
        free(b);
        return false;
    }
    say(progress, user, "hierarchy: %d levels, %zu finest triangles, %d failed patches, %.2f s", b->lod.levels,
        b->lod.finest_triangles, b->lod.failed_patches, prw_now() - t0);
    t0 = prw_now();
    if (!prw_lod_cull_build(m, NULL, &b->cull, e)) {
        prw_lod_free(&b->lod);
        prw_seam_free(&b->graph);
        free(b);
        return false;
    }
    say(progress, user, "culling data: %d patches, %d full normal cones, %.2f s", b->cull.npatches, b->cull.full_cones,
        prw_now() - t0);
    /* whole-model proxy levels with the renderer's orientation (not fatal: a renderer builds its own) */
    t0 = prw_now();
    unsigned char *flip = prw_calloc((size_t)b->lod.npatches + 1, 1);
    int conflicts = 0;
    prw_lod_orient(&b->lod, m, flip, &conflicts);
    prw_error pe;
    b->have_proxy = prw_lod_proxy_build(&b->lod, flip, NULL, &b->proxy, &pe);
    free(flip);
    if (b->have_proxy)
        say(progress, user, "proxy: %d levels from %d start triangles (%d orientation conflicts), %.2f s",
            b->proxy.nlevels, b->proxy.start_triangles, conflicts, prw_now() - t0);
    else
        say(progress, user, "proxy: none (%.400s)", pe.msg);
    g_builds++;
    *out = b;
    return true;
}

bool prw_model_kind_from_path(const char *path, prw_model_kind *kind)
{
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/')) return false;
    if (strcasecmp(dot, ".igs") == 0 || strcasecmp(dot, ".iges") == 0) *kind = PRW_MODEL_IGES;
    else if (strcasecmp(dot, ".json") == 0) *kind = PRW_MODEL_JSON;
    else return false;
    return true;
}

void prw_bake_key(const void *input, size_t n, prw_model_kind kind, const prw_bake_options *o, char key[33])
{
    prw_bake_options opt = o ? *o : (prw_bake_options){0};
    prw_cache_key k;
    prw_cache_key_begin(&k, "prw-lod-key");
    prw_cache_key_add_u64(&k, PRW_LOD_FILE_VERSION);
    prw_cache_key_add_str(&k, PRW_BAKE_ALGO_VERSION);
    prw_cache_key_add_u64(&k, (uint64_t)kind);
    prw_cache_key_add_f64(&k, opt.seam.tol);
    prw_cache_key_add_f64(&k, opt.seam.chord);
    prw_cache_key_add_f64(&k, opt.seam.max_edge);
    prw_cache_key_add_u64(&k, (uint64_t)(int64_t)opt.lod.levels);
    prw_cache_key_add_f64(&k, opt.lod.tau0);
    prw_cache_key_add_u64(&k, (uint64_t)(int64_t)opt.lod.max_cells);
    prw_cache_key_add_u64(&k, (uint64_t)(int64_t)opt.lod.max_patch_triangles);
    prw_cache_key_add_f64(&k, opt.lod.finest_rel);
    prw_cache_key_add_u64(&k, (uint64_t)n);
    prw_cache_key_finish(&k, input, n, key);
}

bool prw_bake_cache_load(const char *key, prw_baked_lod **out, char *path, size_t path_cap, char *warning, size_t wcap)
{
    *out = NULL;
    warning[0] = '\0';
    prw_error e;
    if (!prw_cache_path(PRW_BAKE_CACHE_KIND, key, "lod", false, path, path_cap, &e)) {
        snprintf(warning, wcap, "cache disabled: %.900s", e.msg);
        path[0] = '\0';
        return false;
    }
    struct stat st;
    if (stat(path, &st) != 0) return false; /* a miss */
    prw_baked_lod *b;
    if (!prw_lod_file_read(path, &b, &e)) {
        snprintf(warning, wcap, "corrupt cache entry rebuilt: %.900s", e.msg);
        return false;
    }
    if (strcmp(b->key, key) != 0) {
        snprintf(warning, wcap, "corrupt cache entry rebuilt: %.900s: holds key %.32s", path, b->key);
        prw_lod_file_destroy(b);
        return false;
    }
    *out = b;
    return true;
}

bool prw_bake_cache_store(const char *key, const prw_baked_lod *b, char *path, size_t path_cap, prw_error *e)
{
    uint8_t *d;
    size_t n;
    prw_lod_file_serialize(b, &d, &n);
    bool ok = prw_cache_store(PRW_BAKE_CACHE_KIND, key, "lod", d, n, path, path_cap, e);
    free(d);
    return ok;
}

static bool parse_model(const char *path, prw_model_kind kind, const char *data, size_t n, prw_nurbs_model *m,
                        prw_bake_progress_fn progress, void *user, prw_error *e)
{
    prw_nurbs_model_init(m);
    if (kind == PRW_MODEL_IGES) {
        prw_iges_info info;
        memset(&info, 0, sizeof info);
        if (!prw_iges_parse(data, n, path, m, &info, e)) return false;
        if (info.warning[0]) say(progress, user, "%s: %s", path, info.warning);
        return true;
    }
    return prw_nurbs_json_parse(data, n, path, m, e);
}

bool prw_bake_run(const char *model_path, const prw_bake_options *o, bool no_cache, prw_baked_lod **out,
                  prw_bake_result *r, prw_bake_progress_fn progress, void *user, prw_error *e)
{
    *out = NULL;
    memset(r, 0, sizeof *r);
    double t_start = prw_now();
    prw_model_kind kind;
    if (!prw_model_kind_from_path(model_path, &kind))
        return prw_fail(e, "%s: unknown model type (expected .igs, .iges or .json)", model_path);
    char *data;
    size_t n;
    if (!prw_read_file(model_path, &data, &n, e)) return false;
    prw_bake_key(data, n, kind, o, r->key);
    bool use_cache = !no_cache;
    if (use_cache) {
        prw_baked_lod *b;
        bool hit = prw_bake_cache_load(r->key, &b, r->cache_path, sizeof r->cache_path, r->warning, sizeof r->warning);
        if (hit) {
            free(data);
            r->cache_hit = true;
            r->surfaces = b->graph.npatches;
            r->seconds_total = prw_now() - t_start;
            say(progress, user, "cache hit: %s", r->cache_path);
            *out = b;
            return true;
        }
        use_cache = r->cache_path[0] != '\0';
    }
    double t0 = prw_now();
    prw_nurbs_model m;
    bool ok = parse_model(model_path, kind, data, n, &m, progress, user, e);
    free(data);
    if (!ok) return false;
    r->seconds_read = prw_now() - t0;
    r->surfaces = (int)m.count;
    if (m.count == 0) {
        prw_nurbs_model_free(&m);
        return prw_fail(e, "%s: the model has no surfaces", model_path);
    }
    say(progress, user, "read %s: %zu surfaces, %.2f s", model_path, m.count, r->seconds_read);
    t0 = prw_now();
    prw_baked_lod *b;
    ok = prw_baked_lod_build(&m, o, &b, progress, user, e);
    prw_nurbs_model_free(&m);
    if (!ok) return prw_fail_wrap(e, "%s", model_path);
    r->seconds_build = prw_now() - t0;
    r->built = true;
    memcpy(b->key, r->key, sizeof b->key);
    if (use_cache) {
        prw_error we;
        if (prw_bake_cache_store(r->key, b, r->cache_path, sizeof r->cache_path, &we)) {
            r->cache_written = true;
            say(progress, user, "cached: %s", r->cache_path);
        } else {
            snprintf(r->warning + strlen(r->warning), sizeof r->warning - strlen(r->warning), "%scache not written: %.500s",
                     r->warning[0] ? "; " : "", we.msg);
        }
    }
    r->seconds_total = prw_now() - t_start;
    *out = b;
    return true;
}
