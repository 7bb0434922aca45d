/* prw_bake — the LOD-hierarchy baker behind `prw bake` and prw_bake_scene: builds a model's
 * hierarchy (prw_baked_lod, engine/scene/prw_lod_file.h: the .lod format and its reader live beside
 * the loaders) and keeps it in the content-addressed cache (core/prw_cache.h, kind "lod").
 *
 * Layering: engine/bake is ABOVE the renderer and the reference (DESIGN.md §3): they only use
 * hierarchies baked before (prw_bake_scene.h attaches them to the scene); nothing in engine/render or
 * engine/reference links this library (the ctest `layering` checks the link graph).
 *
 * prw_baked_lod_build: seam graph + LOD model + culling data (default options) + the whole-model proxy
 * levels (lod/prw_lod_proxy.h; ~2 s for the car shell, so built once here instead of at every
 * renderer creation) from an in-memory model; not fatal when only the proxy fails (have_proxy false).
 *
 * Cache (prw_bake_run): key = prw_cache_key over the header (tag "prw-lod-key", .lod format version,
 * PRW_BAKE_ALGO_VERSION, input kind (IGES / JSON), every seam and LOD knob as given (finest_rel
 * included), input length) and the input file's bytes (32 hex digits).  Entry:
 * <cache>/lod/<key>.lod (core/prw_cache.h: $PRW_CACHE_DIR, else $XDG_CACHE_HOME/prw, else
 * $HOME/.cache/prw), written atomically.  An entry that fails to read (checksum, truncation, other
 * key) is reported in result.warning and rebuilt; a cache that cannot be created or written is a
 * warning too.  PRW_BAKE_ALGO_VERSION must be bumped when lod/ changes what it builds.
 * Nothing here prints: progress lines go to the optional callback.
 */
#ifndef PRW_BAKE_H
#define PRW_BAKE_H

#include <stddef.h>
#include <stdint.h>

#include "prw_lod_file.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_BAKE_ALGO_VERSION "lod-2026-12-01d" /* b: pole combs, flips in the level-0 refinement; d: target valence cap;
                                                    c: whole-model proxy levels in the file */

typedef struct prw_bake_options {
    prw_seam_options seam; /* zeros: the seam graph's defaults */
    prw_lod_options lod;   /* zeros: the LOD defaults */
} prw_bake_options;

typedef void (*prw_bake_progress_fn)(void *user, const char *line);

/* Builds a hierarchy from an in-memory model (seam graph + LOD + culling + proxy levels); *out is
 * destroyed with prw_lod_file_destroy.  key is left "". */
bool prw_baked_lod_build(const prw_nurbs_model *m, const prw_bake_options *o, prw_baked_lod **out,
                         prw_bake_progress_fn progress, void *user, prw_error *e);

#define PRW_BAKE_CACHE_KIND "lod" /* <cache>/lod/<key>.lod */
typedef enum prw_model_kind { PRW_MODEL_JSON = 1, PRW_MODEL_IGES = 2 } prw_model_kind;
/* From the file name: .igs / .iges / .json (case-insensitive); false otherwise. */
bool prw_model_kind_from_path(const char *path, prw_model_kind *kind);
/* The cache key of a model's input bytes (a file's content, or a procedural model's content tag). */
void prw_bake_key(const void *input, size_t n, prw_model_kind kind, const prw_bake_options *o, char key[33]);
/* The cache entry of key: true with *out when <cache>/lod/<key>.lod exists and reads back holding that
 * key.  false when it is absent (warning "") or unreadable (warning says why; the caller rebuilds and
 * stores over it), or when there is no cache directory (warning "cache disabled: ...", path "").
 * path gets the entry's path. */
bool prw_bake_cache_load(const char *key, prw_baked_lod **out, char *path, size_t path_cap, char *warning,
                         size_t warning_cap);
/* Stores b as the entry of key (atomically, directory created); path (may be NULL) gets its path.
 * Callers treat a failure as a warning: the cache is an optimisation. */
bool prw_bake_cache_store(const char *key, const prw_baked_lod *b, char *path, size_t path_cap, prw_error *e);

typedef struct prw_bake_result {
    char key[33];
    char cache_path[4096]; /* "" with no_cache */
    bool cache_hit;        /* loaded from the cache, nothing built */
    bool built;            /* the hierarchy was built in this call */
    bool cache_written;
    char warning[1024];    /* corrupt entry rebuilt / cache not writable; "" when none */
    int surfaces;
    double seconds_read, seconds_build, seconds_total;
} prw_bake_result;

/* Loads MODEL (IGES or JSON), returns its hierarchy from the cache or builds (and caches) it.
 * Errors name the file. */
bool prw_bake_run(const char *model_path, const prw_bake_options *o, bool no_cache, prw_baked_lod **out,
                  prw_bake_result *r, prw_bake_progress_fn progress, void *user, prw_error *e);
/* Hierarchies built by this process (prw_baked_lod_build calls that succeeded), for tests. */
int prw_bake_build_count(void);

#ifdef __cplusplus
}
#endif
#endif
