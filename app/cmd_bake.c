/* prw bake — build a trimmed-NURBS model's LOD hierarchy into the content-addressed cache
 * (engine/bake/prw_bake.h) and optionally write it to a .lod file. */
#include <stdio.h>
#include <string.h>

#include "app.h"
#include "prw_bake.h"

static void progress(void *user, const char *line)
{
    (void)user;
    fprintf(stderr, "prw bake: %s\n", line);
    fflush(stderr);
}

static void help(void)
{
    printf("usage: prw bake MODEL.(igs|iges|json) [--out FILE.lod] [knobs] [--no-cache]\n"
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

int prw_cmd_bake(int argc, char **argv)
{
    prw_args a;
    prw_error e = {{0}};
    if (!prw_args_init(&a, argc, argv, &e)) {
        fprintf(stderr, "prw bake: error: %s\n", e.msg);
        return 2;
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
