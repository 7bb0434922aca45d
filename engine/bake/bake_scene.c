/* bake_scene.c — see prw_bake_scene.h. */
#include "prw_bake_scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "prw_lod_node.h"

static void say(prw_bake_progress_fn progress, void *user, const char *fmt, const char *a, double x)
{
    if (!progress) return;
    char line[1400];
    snprintf(line, sizeof line, fmt, a, x);
    progress(user, line);
}

/* A procedural model's hierarchy: cache key from its content hash (kind JSON: it is hand-made). */
static bool procedural_hierarchy(const prw_scene_nurbs *n, const prw_nurbs_model *m, const prw_bake_options *o,
                                 prw_bake_progress_fn progress, void *user, prw_baked_lod **out, prw_error *e)
{
    char input[64], key[33], dir[4000], path[4200];
    snprintf(input, sizeof input, "procedural:%016llx", (unsigned long long)prw_scene_nurbs_model_hash(m));
    prw_bake_key(input, strlen(input), PRW_MODEL_JSON, o, key);
    prw_error ce;
    bool cache = prw_bake_cache_dir(dir, sizeof dir, true, &ce);
    if (cache) {
        snprintf(path, sizeof path, "%s/%s.lod", dir, key);
        struct stat st;
        if (stat(path, &st) == 0) {
            prw_baked_lod *b = NULL;
            if (prw_lod_file_read(path, &b, &ce)) {
                if (strcmp(b->key, key) == 0 && b->lod.npatches == (int)m->count) {
                    *out = b;
                    say(progress, user, "lod: %s: hierarchy from the cache%.0f", n->name, 0);
                    return true;
                }
                prw_baked_lod_destroy(b); /* another key: rebuilt and overwritten below */
            }
        }
    }
    double t0 = prw_now();
    if (!prw_baked_lod_build(m, o, out, NULL, NULL, e))
        return prw_fail_wrap(e, "procedural NURBS model '%s'", n->procedural);
    snprintf((*out)->key, sizeof (*out)->key, "%s", key);
    say(progress, user, "lod: %s: hierarchy built in %.2f s", n->name, prw_now() - t0);
    if (cache) prw_lod_file_write(path, *out, &ce); /* best effort */
    return true;
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
    if (!prw_bake_run(n->file, &o, false, out, &br, NULL, NULL, e)) return false;
    say(progress, user, br.cache_hit ? "lod: %s: hierarchy from the cache%.0f" : "lod: %s: hierarchy built in %.2f s",
        n->name, br.seconds_total);
    int np = (*out)->lod.npatches;
    if (np != (int)m->count) {
        prw_baked_lod_destroy(*out);
        *out = NULL;
        return prw_fail(e, "%s: hierarchy has %d patches, the model %zu surfaces", n->file, np, m->count);
    }
    return true;
}
