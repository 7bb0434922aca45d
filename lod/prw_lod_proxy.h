/* prw_lod_proxy — whole-model coarse levels above the per-patch hierarchy ("patches can vanish",
 * Meseth §6.2), for copies so small on screen that every patch is already at its coarsest level.
 *
 * Why: a patch's coarsest level keeps its boundary nodes, so a model of P patches never drops below
 * about 2-3 P triangles (the car shell: ~330 for 120 patches).  A copy a few dozen pixels wide needs
 * far fewer.  A proxy level is ONE mesh for the whole model, so it may merge across seams; it is
 * drawn instead of the patches for a whole instance (never mixed with patches of the same copy, so
 * no crack can open between a proxy and a patch).
 *
 * Build (prw_lod_proxy_build):
 *  - Start mesh M_s: every usable patch at level k_s (segments at k_s: prw_lod_segment_levels, so
 *    crack-free), where k_s is the finest level whose emission has <= o->max_start_triangles
 *    (0: 16384) triangles (the coarsest level when none has); eps_s = max over patches of err[k_s].
 *    Welded by bit-identical positions (triangles that weld to fewer than 3 vertices dropped).
 *    Each patch's triangles take its `flip` (reversed winding) so the welded mesh is consistently
 *    oriented where the renderer's per-patch orientation is.
 *  - Greedy half-edge collapses v -> w (w an existing vertex: the thesis's rule — no new positions,
 *    so every vertex keeps a (patch, u, v) on the exact surface) from a binary heap (one entry per
 *    vertex: its cheapest allowed target; rebuilt at the start of each stage, stale entries
 *    re-evaluated when popped), in stages of rising budget, PRW_PROXY_STEPS per octave (finer
 *    steps than the patch levels' octaves, so a copy finds a level near its tolerance): stage k
 *    (PRW_PROXY_STEPS (k_s + 1) <= k < PRW_PROXY_STEPS lm->levels) allows collapses while the
 *    estimated error stays <= tau - eps_s, tau = lm->tau0 * 2^(k / PRW_PROXY_STEPS).  Estimated
 *    error (directed, as prw_lod_build's cost): the larger of the largest distance of v to the
 *    planes of the triangles that replace its own (for a border vertex also to the new border
 *    edge) and the error stored at v (the thesis adds the two; the max gave 10-25 % fewer
 *    triangles at equal MEASURED error, and only the measured bound is promised); after the collapse w stores max(its own, that cost).  Validity: v's star is
 *    one disc or half-disc of <= 64 neighbours; link condition (the common neighbours of v and w
 *    are exactly the edge's opposite vertices); border vertices move only along a border edge (so
 *    the border is kept within the budget); vertices of non-manifold edges (> 2 triangles) of M_s
 *    never move; no new triangle duplicating an existing one, flipped (new normal within 90
 *    degrees of the old) or with area < 1e-12 x diag^2; an isolated triangle is never removed.
 *  - A snapshot at the end of each stage that removed triangles (and leaves fewer than the last
 *    snapshot).  Each level's bound is MEASURED, not estimated: err = eps_s + d, d = an upper
 *    bound of the two-sided distance between the level and M_s, both directions by one rule: for
 *    a triangle (or sub-triangle) S and ANY one triangle T of the other mesh, the distance from
 *    every point of S to the other mesh is <= the largest of S's three corner distances to T
 *    (distance to a convex set is convex).  T = the better of the triangle nearest to S's centroid
 *    and the one used for S's parent (a BVH with an exact point-triangle distance); S is split in
 *    4 (at most 8 times) while its bound is above the running maximum and more than 5 % above its
 *    centroid's own distance.  The running maximum starts at the largest vertex distance (a lower
 *    bound of d, so nothing needs refining below it), and the second direction starts at the
 *    first's result.  Plus 1e-12 x diag for rounding.  o->max_samples (0: 2e6) caps the
 *    nearest-triangle queries per level; levels are measured coarse to fine and the first level
 *    that runs out of queries (or would, by the previous level's count scaled by its triangle
 *    count) is dropped with every finer one (too fine to be worth a proxy).  Since every point of
 *    M_s is within eps_s of the exact surface and vice versa, err bounds the two-sided distance
 *    between the level and the exact surface (tests/lod/test_lod_proxy.c checks it against an
 *    independent dense oracle on the exact surface).
 *  - Levels are kept only if they have fewer triangles than the previous kept level and more than
 *    o->max_level_triangles are dropped unmeasured; then only the Pareto front is kept: ordered
 *    fine to coarse, triangles strictly decreasing and err strictly increasing.
 *  - No output (errors through prw_error).  Measured (test_lod_proxy --bench: the car shell at the
 *    bench setting, finest_rel 1e-5, seam chord 0.5e-5 x diag; M_s 12,127 triangles at k_s 3; prw
 *    bench --lod prints the same): 18 levels from 503 triangles (err 1.45e-3 x diag) through 216
 *    (2.9e-3) and 149 (4.5e-3) to 34 (0.126), built in 2.1-2.7 s on one core of a 2-core EPYC,
 *    RelWithDebInfo.  (The patches' own floor, every patch at its coarsest level: 295 triangles.)
 *
 * Per-corner data: a triangle keeps the patch it came from; each corner has (patch, u, v) of its
 * vertex on the triangle's own patch when the vertex lies on that patch (seam vertices lie on
 * several), else on the vertex's first patch — so normals from the exact surface stay on the right
 * side of a crease wherever the triangle still lies on its own patch.  A vertex that is a display
 * fan centre of M_s (only where two patches' boundary sets differ at k_s; none on the procedural
 * box, plate and car shell) is the mean of a triangle's corners, NOT on the surface; its (u, v) is
 * the mean of its fan's rim, as in engine/render/lod_gpu.c.  Every other corner's (patch, u, v)
 * evaluates to its position (within rounding: 1e-9 x diag is checked).
 */
#ifndef PRW_LOD_PROXY_H
#define PRW_LOD_PROXY_H

#include <stddef.h>
#include <stdint.h>

#include "prw_lod.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_PROXY_STEPS 4 /* stages per octave of the budget */

typedef struct prw_lod_proxy_level {
    int stage;        /* k: built for tau = tau0 * 2^(k / PRW_PROXY_STEPS) */
    double err;       /* measured two-sided bound against the exact surface (metres), see above */
    double d_start;   /* the measured part: two-sided bound against M_s */
    int nverts, ntris;
    double *pos;      /* 3 per vertex, model metres (bit-identical to M_s vertices) */
    uint32_t *tris;   /* 3 per triangle */
    int *corner_patch;   /* 3 per triangle */
    double *corner_uv;   /* 6 per triangle */
    int *tri_patch;      /* per triangle */
} prw_lod_proxy_level;

typedef struct prw_lod_proxy {
    int start_level;  /* k_s */
    double eps_start; /* eps_s */
    int start_triangles;
    int nlevels;
    prw_lod_proxy_level *levels; /* fine to coarse */
    int border_edges;            /* border edges of M_s (welded): 0 for a closed model */
    double build_s;
    int patch_floor_triangles;   /* emission with every patch at its coarsest level */
} prw_lod_proxy;

typedef struct prw_lod_proxy_options {
    int max_start_triangles; /* 0: 16384 */
    double max_samples;      /* nearest-triangle queries per level; 0: 2e6 */
    int max_level_triangles; /* levels with more triangles are dropped unmeasured; 0: 2 x the
                                emission of every patch at its coarsest level (finer than that, the
                                patches' own levels do about as well) */
} prw_lod_proxy_options;

/* flip: per patch, 1 = reversed winding (NULL: none).  Fails only on allocation-size overflow or a
 * model without usable patches; a model where no level is worth keeping gets nlevels = 0. */
bool prw_lod_proxy_build(const prw_lod_model *lm, const unsigned char *flip, const prw_lod_proxy_options *o,
                         prw_lod_proxy *out, prw_error *e);
void prw_lod_proxy_free(prw_lod_proxy *p);

#ifdef __cplusplus
}
#endif
#endif
