/* prw_bake — LOD hierarchies on disk: the ".lod" file format and the content-addressed cache
 * behind `prw bake`.
 *
 * A baked model (prw_baked_lod) owns a seam graph, the prw_lod_model built on it
 * (lod.g == &graph) and the per-patch culling data (prw_lod_cull, built with the default options:
 * every patch two-sided — set cull.single_sided[] per view — 16 sampling cells), i.e. everything
 * prw_lod_select / prw_lod_segment_levels / prw_lod_emit need, culling included, without the
 * NURBS model, and the whole-model proxy levels (lod/prw_lod_proxy.h; ~2 s for the car shell, so
 * built once here instead of at every renderer creation).
 *
 * File format (PRW_LOD_FILE_VERSION 3; every number little-endian, doubles as IEEE-754 bits):
 *   header (32 bytes): "PRWLOD01" | u32 format version | u32 flags (0) | u64 payload size |
 *                      u64 prw_hash64(payload, seed 0)
 *   payload: the 32-character cache key; the seam graph (scalars, report, nodes, per segment its
 *            ends, patches, loops, flags, sewing points and both (u, v) arrays — NOT the dense
 *            exact-curve samples, which only the build uses: segs[s].dense is NULL after reading;
 *            per patch its loops and box); the LOD model (levels, tau0, report, per patch every
 *            array of prw_lod_patch, per segment seg_keep and ladder); since version 2 the culling
 *            data (patch count, full_cones, refined, then per patch box, sphere, cone axis and
 *            half-angle, single_sided); since version 3 the proxy section: u8 have_proxy,
 *            then when 1: i32 start level, f64 eps_start, i32 start triangles, i32
 *            patch_floor_triangles, i32 border_edges, i32 level count, then per level i32 stage,
 *            f64 err, f64 d_start, i32 nverts, i32 ntris, pos (3 f64 per vertex), tris (3 u32 per
 *            triangle), corner_patch (3 i32), corner_uv (6 f64), tri_patch (1 i32).  Version 1
 *            and 2 files are refused (the cache rebuilds them).
 * Promises of the reader (prw_lod_file_parse / _read):
 *  - never trusts a size: every count is checked against the bytes that remain (and against
 *    absolute limits) before anything is allocated; truncated, corrupt (checksum) or absurd input
 *    (wrong magic / version, trailing bytes, indices out of range, non-monotonic offsets, NaN or
 *    infinite coordinates, a cone half-angle outside [0, π] or an axis that is neither unit nor
 *    zero-with-the-full-cone, an inverted box, a negative radius; in the proxy section a start
 *    level outside the hierarchy's levels, a negative or non-finite eps_start / err / d_start, a
 *    level without triangles or with fewer than 3 vertices, a triangle index >= nverts, a
 *    corner_patch or tri_patch outside [0, npatches), a non-finite position or corner (u, v),
 *    levels whose triangle counts do not strictly decrease) fails with "<name>: <reason>"
 *    and allocates nothing that survives;
 *  - a file that parses is safe for prw_lod_select / prw_lod_emit (every index they follow is
 *    range-checked) and equals, bit for bit, the hierarchy that was written.
 * Writing is deterministic: the same hierarchy and key always give the same bytes.
 *
 * Cache (prw_bake_run): key = two 64-bit FNV-1a hashes (32 hex digits) of (key tag, file format
 * version, PRW_BAKE_ALGO_VERSION, input kind (IGES / JSON), every seam and LOD knob as given
 * (finest_rel included),
 * input file bytes).  Entry: <cache>/lod/<key>.lod, <cache> = $PRW_CACHE_DIR, else
 * $XDG_CACHE_HOME/prw, else $HOME/.cache/prw; written atomically (prw_write_file_atomic).  An
 * entry that fails to read (checksum, truncation, other key) is reported in result.warning and
 * rebuilt.  PRW_BAKE_ALGO_VERSION must be bumped when lod/ changes what it builds.
 * Nothing here prints: progress lines go to the optional callback.
 */
#ifndef PRW_BAKE_H
#define PRW_BAKE_H

#include <stddef.h>
#include <stdint.h>

#include "prw_lod.h"
#include "prw_lod_proxy.h"
#include "prw_lod_select.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_LOD_FILE_MAGIC "PRWLOD01"
#define PRW_LOD_FILE_VERSION 3u
#define PRW_LOD_HEADER_SIZE 32u
#define PRW_BAKE_ALGO_VERSION "lod-2026-12-01d" /* b: pole combs, flips in the level-0 refinement; d: target valence cap;
                                                    c: whole-model proxy levels in the file */

typedef struct prw_baked_lod {
    prw_seam_graph graph;
    prw_lod_model lod; /* lod.g == &graph */
    prw_lod_cull cull; /* per patch (cull.npatches == lod.npatches) */
    prw_lod_proxy proxy; /* whole-model proxy levels (prw_lod_proxy.h), built at bake time with the
                            flips of prw_lod_orient (lod/prw_lod_orient.h); build_s is 0 after reading */
    bool have_proxy;     /* false: the proxy build failed (no usable patch) — a renderer builds its own */
    char key[33];      /* cache key ("" when unknown) */
} prw_baked_lod;

typedef struct prw_bake_options {
    prw_seam_options seam; /* zeros: the seam graph's defaults */
    prw_lod_options lod;   /* zeros: the LOD defaults */
} prw_bake_options;

typedef void (*prw_bake_progress_fn)(void *user, const char *line);

/* Builds a hierarchy from an in-memory model (seam graph + LOD). */
bool prw_baked_lod_build(const prw_nurbs_model *m, const prw_bake_options *o, prw_baked_lod **out,
                         prw_bake_progress_fn progress, void *user, prw_error *e);
void prw_baked_lod_destroy(prw_baked_lod *b);

/* Serialisation.  *data is malloc'd; the caller frees it. */
void prw_lod_file_serialize(const prw_baked_lod *b, uint8_t **data, size_t *size);
bool prw_lod_file_parse(const void *data, size_t size, const char *name, prw_baked_lod **out, prw_error *e);
bool prw_lod_file_write(const char *path, const prw_baked_lod *b, prw_error *e);
bool prw_lod_file_read(const char *path, prw_baked_lod **out, prw_error *e);

/* "<cache>/lod" (created when create is true). */
bool prw_bake_cache_dir(char *buf, size_t cap, bool create, prw_error *e);
typedef enum prw_model_kind { PRW_MODEL_JSON = 1, PRW_MODEL_IGES = 2 } prw_model_kind;
/* From the file name: .igs / .iges / .json (case-insensitive); false otherwise. */
bool prw_model_kind_from_path(const char *path, prw_model_kind *kind);
void prw_bake_key(const void *input, size_t n, prw_model_kind kind, const prw_bake_options *o, char key[33]);

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
