/* bake_scene.c — the hierarchies of a scene's NURBS entries (prw_bake_scene.h). */
#include "prw_bake_scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* "lod: <name>: hierarchy from the cache" (seconds < 0) or "... built in <seconds> s" */
static void say(prw_bake_progress_fn progress, void *user, const char *name, double seconds)
{
    if (!progress) return;
    char line[1400];
    if (seconds < 0) snprintf(line, sizeof line, "lod: %s: hierarchy from the cache", name);
    else snprintf(line, sizeof line, "lod: %s: hierarchy built in %.2f s", name, seconds);
    progress(user, line);
}

static void warn(prw_bake_progress_fn progress, void *user, const char *name, const char *w)
{
    if (!progress || !w[0]) return;
    char line[1400];
    snprintf(line, sizeof line, "lod: %s: %.1300s", name, w);
    progress(user, line);
}

/* "lod: <name>: N of M patches could not be tessellated and are not drawn (first: ...)": a model
 * drawn in part says so (a user would otherwise see a piece missing without a word). */
static void say_failed(prw_bake_progress_fn progress, void *user, const char *name, const prw_lod_model *lm)
{
    int failed = 0;
    for (int p = 0; p < lm->npatches; p++) failed += !lm->patches[p].ok;
    if (!progress || failed == 0) return;
    char line[1400];
    snprintf(line, sizeof line, "lod: %s: %d of %d patches could not be tessellated and are not drawn%s%.300s%s", name,
             failed, lm->npatches, lm->first_problem[0] ? " (first: " : "", lm->first_problem,
             lm->first_problem[0] ? ")" : "");
    progress(user, line);
}

/* A procedural model's hierarchy: cache key from its content hash (kind JSON: it is hand-made). */
static bool procedural_hierarchy(const prw_scene_nurbs *n, const prw_nurbs_model *m, const prw_bake_options *o,
                                 prw_bake_progress_fn progress, void *user, prw_baked_lod **out, prw_error *e)
{
    char input[64], key[33], path[4200], warning[1024];
    snprintf(input, sizeof input, "procedural:%016llx", (unsigned long long)prw_scene_nurbs_model_hash(m));
    prw_bake_key(input, strlen(input), PRW_MODEL_JSON, o, key);
    prw_baked_lod *b = NULL;
    if (prw_bake_cache_load(key, &b, path, sizeof path, warning, sizeof warning)) {
        if (b->lod.npatches == (int)m->count) {
            *out = b;
            say(progress, user, n->name, -1);
            say_failed(progress, user, n->name, &b->lod);
            return true;
        }
        snprintf(warning, sizeof warning, "corrupt cache entry rebuilt: %.900s: %d patches, the model %zu surfaces",
                 path, b->lod.npatches, m->count);
        prw_lod_file_destroy(b);
    }
    warn(progress, user, n->name, warning);
    double t0 = prw_now();
    if (!prw_baked_lod_build(m, o, out, NULL, NULL, e))
        return prw_fail_wrap(e, "procedural NURBS model '%s'", n->procedural);
    snprintf((*out)->key, sizeof (*out)->key, "%s", key);
    say(progress, user, n->name, prw_now() - t0);
    say_failed(progress, user, n->name, &(*out)->lod);
    prw_error ce;
    if (path[0] && !prw_bake_cache_store(key, *out, NULL, 0, &ce)) {
        snprintf(warning, sizeof warning, "cache not written: %.900s", ce.msg);
        warn(progress, user, n->name, warning);
    }
    return true;
}

/* prw_bake_run's stage lines, prefixed with the entry's name, so a long build of a directly opened
 * model shows its stages as they finish (the reader's warnings and the cache lines are said once, by
 * the scene loader and by say()). */
typedef struct stage_relay {
    prw_bake_progress_fn progress;
    void *user;
    const char *name;
} stage_relay;

static void relay_stage(void *user, const char *line)
{
    const stage_relay *r = user;
    static const char *const stages[] = {"seam graph:", "hierarchy:", "culling data:", "proxy:"};
    for (size_t i = 0; i < sizeof stages / sizeof stages[0]; i++)
        if (strncmp(line, stages[i], strlen(stages[i])) == 0) {
            char out[1400];
            snprintf(out, sizeof out, "lod: %s: %.1300s", r->name, line);
            r->progress(r->user, out);
            return;
        }
}

bool prw_bake_scene_entry(const prw_scene_nurbs *n, const prw_nurbs_model *m, prw_bake_progress_fn progress,
                          void *user, prw_baked_lod **out, prw_error *e)
{
    *out = NULL;
    prw_dvec3 lo, hi;
    prw_nurbs_model_bounds(m, &lo, &hi);
    double diag = prw_v3_len(prw_v3_sub(hi, lo));
    prw_bake_options o;
    memset(&o, 0, sizeof o);
    o.seam.chord = (n->chord_rel > 0 ? n->chord_rel : 2e-4) * diag;
    if (n->finest_rel > 0) {
        o.lod.finest_rel = n->finest_rel;
        o.seam.chord = fmin(o.seam.chord, 0.5 * n->finest_rel * diag);
    }
    if (!n->file[0]) return procedural_hierarchy(n, m, &o, progress, user, out, e);
    prw_bake_result br;
    stage_relay relay = {progress, user, n->name};
    if (!prw_bake_run(n->file, &o, false, out, &br, progress ? relay_stage : NULL, &relay, e)) return false;
    warn(progress, user, n->name, br.warning);
    say(progress, user, n->name, br.cache_hit ? -1 : br.seconds_total);
    say_failed(progress, user, n->name, &(*out)->lod);
    int np = (*out)->lod.npatches;
    if (np != (int)m->count) {
        prw_lod_file_destroy(*out);
        *out = NULL;
        return prw_fail(e, "%s: hierarchy has %d patches, the model %zu surfaces", n->file, np, m->count);
    }
    return true;
}

bool prw_bake_scene(prw_scene *s, prw_bake_progress_fn progress, void *user, prw_error *e)
{
    for (uint32_t i = 0; i < s->nurbs_count; i++) {
        if (prw_scene_nurbs_baked(s, i, NULL, NULL, NULL)) continue; /* already attached */
        const prw_scene_nurbs *n = &s->nurbs[i];
        prw_nurbs_model m;
        prw_baked_lod *b = NULL;
        /* the reader's messages name the file; after it, the path is added (the entry's name is often
         * only its basename) */
        const char *lp = n->file[0] ? " (" : "", *rp = n->file[0] ? ")" : "";
        if (!prw_scene_nurbs_load(n, &m, e)) return prw_fail_wrap(e, "NURBS model '%s'", n->name);
        if (!prw_bake_scene_entry(n, &m, progress, user, &b, e)) {
            prw_nurbs_model_free(&m);
            return prw_fail_wrap(e, "NURBS model '%s'%s%s%s", n->name, lp, n->file, rp);
        }
        if (!prw_scene_nurbs_attach(s, i, &m, b, e)) return false; /* both freed */
    }
    return true;
}
