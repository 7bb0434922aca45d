/* prw_lod — per-patch LOD hierarchies on the seam graph (Meseth ch. 6.2), crack-free at any mix of
 * per-patch levels, and their extraction.
 *
 * Levels: level 0 is the finest tessellation (prw_tess_fixed with the sewing points as the fixed
 * boundary, chord = the seam graph's chord, then edge flips that remove 3-D slivers and move toward
 * the 3-D Delaunay criterion, then refinement: every triangle whose error bound (below) exceeds
 * tau0 has its longest non-boundary edge — lengths in (u, v) scaled by the patch's mean |S_u|,
 * |S_v| — split at the (u, v) midpoint together with the triangle across it (2 -> 4, conforming),
 * followed by Lawson flips around the new vertex toward the 3-D Delaunay criterion; when the
 * triangle across is a sliver (its apex within 1/8 of the edge's length from it) the edge is
 * flipped instead of split (the ear clipping leaves long fans of slivers along the boundary whose
 * bisected halves fail the 3-D tests: this was what stalled the refinement at fine tolerances),
 * until every level-0 bound is <= max(tau0, the part due to the boundary alone: the sewing chords
 * against the exact trim curve and against the surface along the straight (u, v) edge).  Sewing
 * points are never added, so watertightness is untouched.  Poles: a collapsed ring edge (two
 * consecutive ring copies of one node whose straight (u, v) edge maps to that point — sphere
 * poles, box corners) is first given a "comb": the ear-clipped fan around it is re-triangulated
 * with one more copy of the node (same global id, bit-identical position, an interior vertex) on
 * the edge per neighbouring chain edge, so every drawn triangle there has its copy beside the part
 * of the surface it covers; the refinement then also splits collapsed edges (the new vertex being
 * another copy), and when it stalls at a pole (an interior vertex fanned to copies far from it
 * along the edge: every split of its edges would invert a triangle) the pole is combed again from
 * its refined chain and the refinement goes on (at most 3 rounds).  Triangles joining two copies are not drawn but carry their (u, v) error like any
 * other (their region's surface is at most that far from the shared node-to-vertex edge).  In the
 * hierarchy an interior copy only merges into another copy of its node.  Limits: no split that
 * would give a vertex valence > 24 or an invalid triangle, none beyond max_patch_triangles;
 * refused_splits counts the level-0 triangles left above max(tau0, boundary part) at the end.
 * Level k >= 1 targets tau_k = tau0 · 2^k (tau0 = the sewing chord tolerance, or finest_rel x the
 * model diagonal).  Measured (tests/lod/lod_finest_bench, finest_rel 1e-5, sewing chord ½ of it):
 * every level-0 bound <= 1e-5 x diagonal with no triangle left above on the box, the plate and the
 * car shell — level-0 triangles / hierarchy build on a shared 2-core EPYC, RelWithDebInfo: box
 * 543,944 / 34-63 s (load), plate 20,914 / 2-3 s, shell 128,602 / 12-16 s.  NOT robust at every
 * tolerance: the thin boundary strips the ear clipping leaves between the sewing points and the
 * first full grid row hold fans of slivers whose splits fail the 3-D tests; at 2e-5 x diagonal the
 * shell keeps 1,412 triangles above (bound 3.9e-4 x diagonal) — refused_splits reports it.  The
 * cure is a better strip triangulation (constrained Delaunay of the strip), not done.
 *
 * Segment ladders (prw_lod_ladder.c): per segment, nested subsets of its sewing points — level k
 * drops points greedily (smallest error first) while the polyline stays within ½·tau_k of the
 * exact curve (sampled: every finer sewing point and PRW_SEAM_DENSE exact points per edge), never
 * below the segment's min_interior.  keep[i] = the coarsest level still holding point i; a
 * coarser polyline is a subset of every finer one.
 *
 * Patch hierarchy (prw_lod_build.c): greedy half-edge collapses v → w ordered by the thesis cost
 * (max distance of v to the new edges (w, v_i) + the error stored at v), each checked, then
 * accepted if every new triangle's error bound is <= tau_k.  Dependency / validity rules:
 *  - nodes (segment ends) never move; an interior sewing point only collapses into its active
 *    neighbour along its own boundary ring (so along its own segment), and only at a level where
 *    the segment's ladder has dropped it;
 *  - link condition on the welded mesh (sewing points with equal global id — the copies of a
 *    node on a collapsed edge — count as one vertex); an interior node copy only merges into
 *    another copy of its node (the welded mesh then loses only undrawn triangles);
 *  - every new triangle keeps positive (u, v) orientation (exact predicate), a 3-D normal within
 *    90° of the exact surface normal at its (u, v) centroid and non-zero 3-D area (triangles joining
 *    two copies of one node are degenerate by construction and dropped at output);
 *  - a collapse target has fewer than 96 triangles (bounds the 2-ring re-evaluation each collapse
 *    costs), and a level's search stops after 2000 x (vertices + 64) candidates (capped_levels);
 *  - a triangle joining two copies of one node (not drawn) may not have a boundary edge that skips
 *    sewing points (it could not draw their fan);
 *  - a triangle with boundary edges must admit the centroid fan used at display time (below) with
 *    ALL finest sewing points between its boundary vertices: the fan is star-shaped from the (u, v)
 *    centroid, which implies (exactly) that every subset is too.
 * Error bound of a triangle (measured directly against the exact surface, so nothing accumulates):
 * max of (a) |L_T(u,v) − S(u,v)| over 28 barycentric samples (L_T = linear interpolation of the
 * vertex positions; this bounds both one-sided distances over the triangle's (u, v) region), (b)
 * the same for the finest centroid fan, (c) the distance of the exact boundary-curve samples
 * between its boundary vertices to the chord; times 1.1, plus 1e-9 x the model diagonal (sampling
 * and inversion noise).  A level's bound is the max over its triangles (those joining two copies
 * of one node included, though not drawn).
 *
 * Display rule (prw_lod_emit): a segment is drawn at the FINER of its two patches' levels
 * (thesis §6.3: the trim error stays below the acceptable error of every adjacent patch), using
 * the points of the union of its ladder and both patches' active boundary sets at that level
 * (`seg_keep`).  A patch triangle whose boundary edge misses some of those points is replaced by a
 * fan from its (u, v) centroid (3-D position = mean of its corners) through them.  Both patches
 * therefore draw the same sewing points, bit-identical, on every shared segment.
 */
#ifndef PRW_LOD_H
#define PRW_LOD_H

#include <stdint.h>

#include "prw_seam.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_LOD_MAX_LEVELS 20

typedef struct prw_lod_options {
    int levels;    /* 0: 14 */
    double tau0;   /* 0: the seam graph's chord */
    int max_cells; /* finest tessellation grid cap per direction (start of the refinement); 0: 48 */
    int max_patch_triangles; /* level-0 refinement cap per patch; 0: 2 x the initial count + 4096 */
    double finest_rel; /* > 0: tau0 = finest_rel x the model diagonal (when tau0 is 0), the refinement cap
                          lifted (unless max_patch_triangles is set) and, when levels is 0, enough levels
                          for the coarsest to reach the diagonal (at most PRW_LOD_MAX_LEVELS); the
                          seam graph's chord should be as fine, or the sewing chords bind level 0 */
    /* optional progress: at most one line a second while patches are built (never a knob: not
       part of any cache key); NULL: silent */
    void (*progress)(void *user, const char *line);
    void *progress_user;
} prw_lod_options;

typedef struct prw_lod_patch {
    bool ok;
    int nverts, nbound; /* boundary vertices are 0 .. nbound-1 = ring positions */
    double *uv;
    prw_dvec3 *pos;
    int *gid;        /* global sewing id (>= 0) or -1 */
    int *removed_at; /* first level without the vertex (levels: never removed) */
    int nrings;
    int *ring_start;  /* nrings + 1 */
    int *ring_of;     /* per boundary vertex */
    int *ring_seg;    /* per boundary vertex: its segment (for a node: the use starting there) */
    int *ring_sidx;   /* per boundary vertex: sewing index in segment order */
    unsigned char *ring_rev; /* per boundary vertex: its use walks the segment backwards */
    int *tri_start;   /* levels + 1 offsets (in triangles) */
    int *tris;        /* 3 local vertex ids per triangle */
    double *err;      /* per level: error bound (metres) */
    prw_dvec3 lo, hi; /* control hull ∪ sewing points */
} prw_lod_patch;

typedef struct prw_lod_model {
    const prw_seam_graph *g;
    int levels;
    double tau0;
    prw_lod_patch *patches;
    int npatches;
    int **seg_keep; /* per segment, per sewing point: coarsest level displaying it (INT32_MAX at ends) */
    int **ladder;   /* per segment: the curve-only ladder (subset of seg_keep) */
    int failed_patches;
    int refused_splits; /* level-0 triangles left above tau0 by the refinement (cap / invalid split) */
    int capped_levels;  /* levels whose collapse search hit its iteration cap (2000 x (vertices + 64)
                           candidates; still valid, see first_problem); 0 after reading a .lod file */
    char first_problem[256];
    size_t finest_triangles;
} prw_lod_model;

/* Segment ladders only (also called by prw_lod_build). */
void prw_lod_ladders(const prw_seam_graph *g, int levels, double tau0, int **ladder);

bool prw_lod_build(const prw_nurbs_model *m, const prw_seam_graph *g, const prw_lod_options *o, prw_lod_model *lm,
                   prw_error *e);
void prw_lod_free(prw_lod_model *lm);

/* seg_level[s] = min over the segment's patches of patch_level (the finer). */
void prw_lod_segment_levels(const prw_lod_model *lm, const int *patch_level, int *seg_level);

typedef struct prw_lod_mesh {
    double *pos; /* 3 per vertex */
    size_t nverts, vcap;
    uint32_t *tris;
    size_t ntris, tcap;
    int *map; /* scratch */
    int mapcap;
    int fans; /* triangles replaced by fans */
} prw_lod_mesh;

/* Appends patch `patch` at `level` (its segments at seg_level) to out. */
void prw_lod_emit(const prw_lod_model *lm, int patch, int level, const int *seg_level, prw_lod_mesh *out);
void prw_lod_mesh_reset(prw_lod_mesh *out);
void prw_lod_mesh_free(prw_lod_mesh *out);
/* Triangles patch `patch` draws at `level` (before fans). */
int prw_lod_patch_triangles(const prw_lod_model *lm, int patch, int level);

#ifdef __cplusplus
}
#endif
#endif
