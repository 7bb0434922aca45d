/* prw_lod_file — the ".lod" file: a baked LOD hierarchy on disk (written by engine/bake, loaded by
 * whoever draws it).
 *
 * A baked model (prw_baked_lod, the in-memory form of one .lod file, made by prw_lod_file_parse /
 * _read or by the baker engine/bake's prw_baked_lod_build; destroyed by prw_lod_file_destroy) owns a
 * seam graph, the prw_lod_model built on it (lod.g == &graph) and the per-patch culling data
 * (prw_lod_cull, built with the default options: every patch two-sided — set cull.single_sided[] per
 * view — 16 sampling cells), i.e. everything prw_lod_select / prw_lod_segment_levels / prw_lod_emit
 * need, culling included, without the NURBS model, and the whole-model proxy levels
 * (lod/prw_lod_proxy.h).
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
 * Writing is deterministic: the same hierarchy and key always give the same bytes; prw_lod_file_write
 * is atomic (prw_write_file_atomic).  Nothing here prints.
 */
#ifndef PRW_LOD_FILE_H
#define PRW_LOD_FILE_H

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

typedef struct prw_baked_lod {
    prw_seam_graph graph;
    prw_lod_model lod; /* lod.g == &graph */
    prw_lod_cull cull; /* per patch (cull.npatches == lod.npatches) */
    prw_lod_proxy proxy; /* whole-model proxy levels (prw_lod_proxy.h), built at bake time with the
                            flips of prw_lod_orient (lod/prw_lod_orient.h); build_s is 0 after reading */
    bool have_proxy;     /* false: the proxy build failed (no usable patch) — a renderer builds its own */
    char key[33];      /* cache key ("" when unknown) */
} prw_baked_lod;

void prw_lod_file_destroy(prw_baked_lod *b); /* NULL is fine */

/* Serialisation.  *data is malloc'd; the caller frees it. */
void prw_lod_file_serialize(const prw_baked_lod *b, uint8_t **data, size_t *size);
bool prw_lod_file_parse(const void *data, size_t size, const char *name, prw_baked_lod **out, prw_error *e);
bool prw_lod_file_write(const char *path, const prw_baked_lod *b, prw_error *e);
bool prw_lod_file_read(const char *path, prw_baked_lod **out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
