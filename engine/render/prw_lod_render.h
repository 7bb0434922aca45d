/* prw_lod_render — trimmed-NURBS models with per-frame seam-graph LOD on the GPU (issue 7).
 *
 * prw_lod_gpu: ONE hierarchy (a prw_lod_model built on a prw_nurbs_model) drawn as `instances`
 * copies.  Promises:
 *  - Layout: every instance owns a vertex and an index buffer (host-visible, written in place) with
 *    one fixed slot per patch.  The slots are sized for the instance's level floor L (the finest
 *    level its layout can hold): a patch's capacity is its largest emission at any level >= L with
 *    every segment at L (a segment is drawn at the finer of its two patches' levels, both >= L, and
 *    emission only grows with finer segments).  The part of a slot its emission does not use holds
 *    degenerate triangles (three times the slot's first vertex), so consecutive drawn patches are
 *    ONE draw (indices are relative to the instance's buffer) and the shadow pass draws an instance
 *    in one call — 100 distant copies cost 100 draws, not 100 x patches.  A new layout (fresh
 *    buffers, every slot written; counted in `relayouts`) is made only when a selected level drops
 *    below the floor, or when every level is more than 3 levels above it (the copy moved away: its
 *    slots shrink back); its floor is one level below the finest level then selected (hysteresis).
 *  - Vertices: position relative to the model's box centre (float; the draw matrix adds the centre
 *    back in double, and the renderer makes it camera-relative), the exact surface normal at the
 *    vertex's (u, v) (prw_nurbs_surface_normal), (u, v) as texture coordinates and the unit tangent
 *    along S_u.  The (u, v) of a patch vertex comes from prw_lod_mesh.map, the emitter's local ->
 *    emitted index map read right after prw_lod_emit; a fan centre (not in the map) takes the mean
 *    (u, v) of its fan's rim, which lies inside the replaced triangle.  Orientation: a model's patches need not agree (the procedural box's fillets
 *    and corners have S_u x S_v inward), so each patch may be flipped (reversed winding, negated
 *    normal, cone axis negated for culling): across every G1 seam (exact normals at the segment's
 *    middle with |cos| > 0.3) neighbours agree, and each connected component is outward (positive
 *    enclosed volume) when closed, else keeps its majority's orientation.  Front faces (counter-
 *    clockwise) are then on the normal's side.
 *  - Per frame and instance (prw_lod_gpu_update): one level choice for the whole view set
 *    (prw_lod_select_drawn with the view set's eyes, <= 2: the nearer-eye rule; culling by the union
 *    of the frusta and, with single_sided, by normal cones; a set of more than 2 views selects from
 *    its first two eyes without frustum culling), made in MODEL space: the eyes and frustum
 *    planes are mapped by the inverse instance matrix and the pixel angle is scaled by
 *    s_min / s_max of the matrix's axis lengths (conservative under non-uniform scale).  The pixel
 *    angle is the smallest angle a pixel subtends anywhere in the image (at the corner farthest
 *    from the axis), so the ½-px tolerance holds across the image, not only at its centre.  Then
 *    each patch moves to the coarsest level whose stored bound is no larger than that of the level
 *    chosen: where the finest level binds, prw_lod_select takes level 0, but a bound set by the
 *    patch's boundary (a trim chord) is often the same at much coarser levels (the car shell's
 *    window patch: 6229 triangles at level 0, 21 at level 7, both 4.2 mm).
 *  - Update minimality: between layouts, a patch slot is rewritten ONLY when its emitted triangles
 *    changed — its own level changed or a segment's display level changed (candidates), confirmed by
 *    comparing a 64-bit hash of the slot's new contents with the stored one (plus the degenerate
 *    fill of what the previous emission used beyond the new one).  `uploaded` flags say which slots
 *    were written in the last update.
 *  - Culled patches keep their (stale) level and their slot contents (prw_lod_select.h: they are
 *    needed for crack-free neighbours and come back into view without an upload); the base pass
 *    draws only the drawn patches' ranges, the shadow pass draws all patches (a patch outside the
 *    camera's frustum or facing away from it still casts shadows into the view).
 *  - Whole-model proxy levels (lod/prw_lod_proxy.h, built at create from the hierarchy with the
 *    patches' orientation (lod/prw_lod_orient.h) unless options.proxy gives prebuilt ones; none
 *    with no_proxy): after the patch selection, an instance is drawn as ONE
 *    proxy level instead of its patches when some level's measured bound, projected from the nearer
 *    eye at the nearest point of the model's box (the same conservative distance and corner pixel
 *    angle as the patches), is within the tolerance and the level has fewer triangles than the
 *    drawn patches; the one with the fewest triangles is taken.  A copy is never part proxy, part
 *    patches, so no crack can open between the two.  The proxy levels live in one shared buffer pair
 *    (per-corner vertices: exact normals at the corner's (patch, u, v)); the instance's patch slots
 *    are left untouched meanwhile.  An instance with every patch culled is not drawn either way.
 *  - Each instance chooses its levels independently: instances differ in distance and screen size,
 *    and one shared choice would have to take, per patch, the finest level any instance needs.
 *  - Reports: drawn / culled patches, triangles drawn (base pass), slots re-uploaded, bytes written,
 *    CPU time of the selection and of the buffer update.
 *
 * prw_lod_scene: the scene's NURBS entries (prw_scene.h, prw_scene_nurbs) for a renderer: each entry's
 * model and hierarchy are the ones the baker attached to the scene (engine/bake's prw_bake_scene,
 * read with prw_scene_nurbs_baked: nothing is loaded or built here, and the renderer does not link
 * the baker), borrowed for the renderer's life; one prw_lod_gpu serves its instance grid.
 */
#ifndef PRW_LOD_RENDER_H
#define PRW_LOD_RENDER_H

#include "prw_gpu.h"
#include "prw_lod_file.h"
#include "prw_lod_select.h"
#include "prw_scene.h"
#include "prw_view.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_lod_gpu prw_lod_gpu;

typedef struct prw_lod_gpu_options {
    double tol_px;       /* screen-space tolerance; 0: 0.5 */
    double floor_frac;   /* error floor / sewing error; 0: 0.1 */
    size_t tri_budget;   /* per instance; 0: none */
    bool single_sided;   /* closed outward model: normal-cone back-face culling */
    bool no_cull;        /* no culling at all (every patch drawn) */
    bool centre_pixel;   /* pixel angle at the image centre (lod/'s tests) instead of the corner's */
    bool force;          /* every patch at force_level (clamped), none culled: reference images */
    int force_level;
    bool no_proxy;       /* at create: no whole-model proxy levels (always the patches) */
    /* at create: prebuilt proxy levels (the .lod file's, engine/bake), borrowed — must outlive the
     * prw_lod_gpu and have been built from this hierarchy with prw_lod_orient's flips; NULL: built
     * at create (~2 s for the car shell) */
    const struct prw_lod_proxy *proxy;
} prw_lod_gpu_options;

typedef struct prw_lod_frame_report {
    uint32_t instances;
    uint64_t drawn_patches, culled_patches;
    uint64_t triangles;  /* drawn by the base pass (all instances, one view) */
    uint64_t reuploaded; /* patch slots rewritten */
    uint64_t bytes;      /* bytes written to the GPU buffers */
    double select_ms, update_ms;
    uint64_t relayouts;  /* instances that got a new layout this frame (all their slots written) */
    uint64_t draws;      /* base-pass draw calls (runs of consecutive drawn patches) */
    int floor_binds, finest_binds, budget_binds;
    double max_px; /* worst projected error of a drawn patch at its level (pixels; 0 when forced) */
    uint64_t proxy_instances; /* instances drawn as a whole-model proxy level */
} prw_lod_frame_report;

typedef struct prw_lod_range {
    uint32_t first_index, index_count; /* in the instance's index buffer; vertex offset 0 */
    uint32_t triangles;                /* real (non-degenerate) triangles in the range */
    uint32_t pad;
} prw_lod_range;

/* lm and m are borrowed and must outlive the object; lm must be built from m (same patch order). */
bool prw_lod_gpu_create(prw_gpu *gpu, const prw_lod_model *lm, const prw_nurbs_model *m, uint32_t instances,
                        const prw_lod_gpu_options *o, prw_lod_gpu **out, prw_error *e);
void prw_lod_gpu_destroy(prw_lod_gpu *g);
void prw_lod_gpu_set_options(prw_lod_gpu *g, const prw_lod_gpu_options *o);
/* Selects instance `inst`'s levels for views[0..count) (world matrix of the instance: model metres ->
 * world) and rewrites the slots whose triangles changed.  Adds to *rep (the caller zeroes it).  Call
 * only while the GPU does not read the buffers (prw_renderer_render waits for each frame). */
bool prw_lod_gpu_update(prw_lod_gpu *g, uint32_t inst, prw_dmat4 world, const prw_view *views, uint32_t count,
                        prw_lod_frame_report *rep, prw_error *e);
/* The matrix to draw instance geometry with: world x translate(model centre). */
prw_dmat4 prw_lod_gpu_draw_matrix(const prw_lod_gpu *g, prw_dmat4 world);
VkBuffer prw_lod_gpu_vertex_buffer(const prw_lod_gpu *g, uint32_t inst);
VkBuffer prw_lod_gpu_index_buffer(const prw_lod_gpu *g, uint32_t inst);
/* Draw ranges of instance inst after its last update: the drawn patches (all = false) or every
 * patch (all = true, for shadows).  Empty ranges are left out. */
const prw_lod_range *prw_lod_gpu_ranges(const prw_lod_gpu *g, uint32_t inst, bool all, uint32_t *count);
/* The whole-model proxy level instance inst was drawn with in its last update (-1: the patches), and
 * the proxy levels (NULL when built with no_proxy). */
int prw_lod_gpu_proxy_level(const prw_lod_gpu *g, uint32_t inst);
const struct prw_lod_proxy *prw_lod_gpu_proxy(const prw_lod_gpu *g);
/* Introspection for tests: per-patch levels, drawn and uploaded flags of instance inst (npatches),
 * and how many layouts the instance has had. */
const int *prw_lod_gpu_levels(const prw_lod_gpu *g, uint32_t inst);
const unsigned char *prw_lod_gpu_drawn(const prw_lod_gpu *g, uint32_t inst);
const unsigned char *prw_lod_gpu_uploaded(const prw_lod_gpu *g, uint32_t inst);
uint64_t prw_lod_gpu_relayouts(const prw_lod_gpu *g, uint32_t inst);
/* Patch p's slot of instance inst: its vertices (12 floats each), its used indices (in the mapped
 * buffer, relative to the instance: subtract *vertex_base for the emission's patch-local indices). */
void prw_lod_gpu_slot(const prw_lod_gpu *g, uint32_t inst, int p, const float **verts, uint32_t *nverts,
                      uint32_t **idx, uint32_t *nidx, uint32_t *vertex_base);
/* The CPU emission a slot holds: patch p at `level` with segments at seg_level, converted to the slot's
 * vertex format (the function the update uses; tests compare slots with it). *verts / *idx are
 * scratch owned by g, valid until the next call. */
bool prw_lod_gpu_emit(prw_lod_gpu *g, int p, int level, const int *seg_level, const float **verts, uint32_t *nverts,
                      const uint32_t **idx, uint32_t *nidx, prw_error *e);
/* Patches drawn flipped (see Orientation) and seams that contradicted the walk. */
int prw_lod_gpu_flipped(const prw_lod_gpu *g, int *conflicts);
/* Bytes of GPU memory (vertex + index) held. */
size_t prw_lod_gpu_memory(const prw_lod_gpu *g);
/* The model-space view set prw_lod_gpu_update selects with (exposed for tests). */
void prw_lod_gpu_model_view(const prw_lod_gpu *g, prw_dmat4 world, const prw_view *views, uint32_t count,
                            prw_lod_view *out);

/* ---- the scene's NURBS models ---- */
typedef struct prw_lod_scene prw_lod_scene;

/* One prw_lod_gpu per entry of s->nurbs, on the model and hierarchy attached to the scene (s must be
 * baked: prw_bake_scene; otherwise fails with "NURBS entry '<name>' has no baked hierarchy: ...").
 * s must outlive *out.  An entry without its own tol_px uses tol_px (the renderer passes its knob
 * lod_pixel_tolerance; 0: 0.5).  *out is NULL (and true) for a scene without NURBS models. */
bool prw_lod_scene_create(prw_gpu *gpu, const prw_scene *s, double tol_px, prw_lod_scene **out, prw_error *e);
void prw_lod_scene_destroy(prw_lod_scene *ls);
/* Per frame: every instance of every model for the view set; the report is also kept (last_report). */
bool prw_lod_scene_update(prw_lod_scene *ls, const prw_view *views, uint32_t count, prw_error *e);
const prw_lod_frame_report *prw_lod_scene_last_report(const prw_lod_scene *ls);
uint32_t prw_lod_scene_model_count(const prw_lod_scene *ls);
prw_lod_gpu *prw_lod_scene_model(prw_lod_scene *ls, uint32_t i);
const prw_baked_lod *prw_lod_scene_hierarchy(const prw_lod_scene *ls, uint32_t i);
/* Model i's scene entry, instance count and instance world matrix (model metres -> world). */
const prw_scene_nurbs *prw_lod_scene_entry(const prw_lod_scene *ls, uint32_t i);
uint32_t prw_lod_scene_instances(const prw_lod_scene *ls, uint32_t i);
prw_dmat4 prw_lod_scene_instance_world(const prw_lod_scene *ls, uint32_t i, uint32_t inst);
/* Options for every model (e.g. force the finest level for a reference image). */
void prw_lod_scene_set_options(prw_lod_scene *ls, const prw_lod_gpu_options *o);
/* Sum over models of finest-level triangles x instances. */
uint64_t prw_lod_scene_finest_triangles(const prw_lod_scene *ls);

#ifdef __cplusplus
}
#endif
#endif
