/* prw_lod_select — per-frame CPU choice of each patch's level (Meseth §6.3), with per-patch
 * frustum and normal-cone back-face culling.
 *
 * Promises:
 *  - d = distance from the NEARER eye to the patch's bounding box (control hull ∪ sewing points,
 *    which contains the exact patch): a conservative (small) distance, so the projected error
 *    err / (d · pixel_angle) over-estimates what any point of the patch shows.
 *  - Acceptable error ε = max(tol_px · pixel_angle · d, floor_frac · sewing error); the level is
 *    the coarsest whose stored bound is <= ε.  Where the floor raised ε above the pixel tolerance
 *    and the chosen level's error projects above tol_px, the patch counts in floor_binds; where
 *    even level 0 exceeds ε, level 0 is taken and the patch counts in finest_binds.
 *  - One choice serves both eyes.  Segments then follow prw_lod_segment_levels (the finer side).
 *  - Optional triangle budget: while the sum of the DRAWN patches' level triangle counts exceeds
 *    it, the drawn patch whose next coarser level projects the smallest error is coarsened
 *    (priority order); budget_binds / budget_steps report it and max_px is the worst projected
 *    error of the drawn patches afterwards.
 *
 * Culling (only when view.cull != NULL; otherwise every patch is selected, as before):
 *  - Per patch, built once from the exact surfaces (prw_lod_cull_build; patch i = model surface i,
 *    the indexing of prw_lod_build): the control-hull box and a bounding sphere (centre = box centre,
 *    radius = largest distance to a control point; the patch lies in the convex hull of its
 *    control points since weights > 0, so inside both), and a normal cone (axis, half-angle) of the
 *    exact unit normals (prw_nurbs_surface_normal, oriented Su × Sv) over the WHOLE (u, v) domain
 *    (a superset of the trimmed region).  The cone is sampled, not proven: every non-empty knot
 *    span is sampled on a grid (ends moved inward by 1e-9 of the span, so the two sides of a C0
 *    crease are both seen; >= `samples` cells per direction), the half-angle is the largest angle of
 *    a sample to the mean axis PLUS a margin = the largest angle between two corners of one grid
 *    cell (the normal inside a cell cannot leave the cell's corner set by more than that while it
 *    varies smoothly at the grid scale).  The margin is then verified: the normal at every cell
 *    centre must be within (sampled half-angle + margin / 2) of the axis; otherwise the grid is
 *    doubled (up to 256 cells per direction) and, failing that, the cone is the full sphere (never
 *    back-face culled).  An undefined normal (zero-area patch) or a mean normal shorter than 1e-6
 *    also gives the full cone.  Control-net cones (hodographs) were not used: they are not a
 *    difference net for rational patches and span 180° at collapsed edges.
 *  - Per frame, for the eye set (1 or 2 eyes), eye e REJECTS patch p when
 *      (a) frustum: view.frustum_cull and the box (or the sphere) is entirely outside one of eye e's
 *          six planes (prw_lod_frustum_planes; the usual test: conservative, never rejects a box
 *          that meets the frustum), or
 *      (b) back-face: the patch is single-sided (prw_lod_cull_options.single_sided, per patch in
 *          prw_lod_cull.single_sided[]) and the angle between the cone axis and the direction from
 *          the sphere centre to e exceeds half-angle + 90° + asin(radius / distance) (+1e-9): then
 *          every normal of the patch makes more than 90° with the direction from every point of
 *          the sphere to e, so the patch shows only back faces to e.  An eye inside the sphere
 *          never rejects by (b).
 *    A patch is CULLED when every eye rejects it (for (a) alone: outside the union of the frusta;
 *    for (b) alone: back-facing for both eyes; mixed: e.g. outside the left frustum and back-facing
 *    for the right eye — still invisible in both images).  culled = culled_frustum (outside every
 *    frustum) + culled_backface (inside some frustum, back-facing for every eye) + culled_mixed.
 *  - A culled patch is not drawn (drawn[p] = 0) and KEEPS the level it had on input (levels[] is
 *    in/out: keep it between frames and initialise it once, e.g. to levels - 1; values outside
 *    [0, levels-1] are clamped), so coming back into view changes nothing on the GPU side unless
 *    the level really changes.  Its triangles do not count in `triangles` nor in the budget.
 *  - Cracks: culling cannot open a crack between two drawn patches.  A segment is drawn at the
 *    finer of its TWO patches' levels (prw_lod_segment_levels with the full levels[] array, stale
 *    levels of culled patches included), so a segment between drawn patches A and B depends only
 *    on A's and B's levels — unchanged by culling — and nodes never move.  A segment between drawn
 *    A and culled C is drawn by A alone at min(level A, stale level C): never coarser than A's own
 *    choice (A's error bound still holds); at worst finer (more boundary points than needed) while
 *    C stays culled.  What does open is the hole where C is missing, which the culling test says
 *    no eye can see (outside every frustum, or facing away on a single-sided closed model).
 */
#ifndef PRW_LOD_SELECT_H
#define PRW_LOD_SELECT_H

#include "prw_lod.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A half-space n·x + d >= 0 (n unit). */
typedef struct prw_lod_plane {
    prw_dvec3 n;
    double d;
} prw_lod_plane;

/* Per-patch culling data (create/destroy: prw_lod_cull_build / prw_lod_cull_free). */
typedef struct prw_lod_cull {
    int npatches;
    prw_dvec3 *lo, *hi;          /* control-hull box */
    prw_dvec3 *centre;           /* bounding sphere */
    double *radius;
    prw_dvec3 *axis;             /* normal cone (unit axis; (0,0,0) with the full cone) */
    double *half_angle;          /* radians, PRW_PI = full cone (never back-facing) */
    unsigned char *single_sided; /* back-face culling allowed (set from the options; may be edited) */
    int full_cones;              /* patches whose cone fell back to the full sphere */
    int refined;                 /* patches whose sampling grid had to be refined */
} prw_lod_cull;

typedef struct prw_lod_cull_options {
    int samples;       /* minimum grid cells per direction; 0: 16 */
    bool single_sided; /* every patch single-sided (back-face culling on); default: two-sided */
} prw_lod_cull_options;

bool prw_lod_cull_build(const prw_nurbs_model *m, const prw_lod_cull_options *o, prw_lod_cull *c, prw_error *e);
void prw_lod_cull_free(prw_lod_cull *c);

/* The six planes (left, right, bottom, top, near, far) of a possibly off-axis frustum: eye
 * position, unit forward and up (right = forward × up), tangents of the four half-angles measured
 * from the forward axis (tan_left / tan_bottom positive when the edge is left of / below the
 * axis), near > 0 and far (0: no far plane — it is then a plane that everything is inside). */
void prw_lod_frustum_planes(prw_dvec3 eye, prw_dvec3 forward, prw_dvec3 up, double tan_left, double tan_right,
                            double tan_bottom, double tan_top, double znear, double zfar, prw_lod_plane planes[6]);

typedef struct prw_lod_view {
    prw_dvec3 eye[2];
    int neyes;          /* 1 or 2 */
    double pixel_angle; /* radians per pixel */
    double tol_px;      /* 0: 0.5 */
    double floor_frac;  /* 0: 0.1 */
    size_t tri_budget;  /* 0: no budget */
    const prw_lod_cull *cull;   /* NULL: no culling at all; built from the model lm came from (a
                                   patch-count mismatch disables culling in prw_lod_select*) */
    bool frustum_cull;          /* use frustum[e] (with cull != NULL) */
    prw_lod_plane frustum[2][6]; /* per eye */
} prw_lod_view;

typedef struct prw_lod_select_report {
    int floor_binds, finest_binds;
    bool budget_binds;
    int budget_steps;
    size_t triangles; /* drawn patches only */
    double max_px;    /* drawn patches only */
    int culled, culled_frustum, culled_backface, culled_mixed;
} prw_lod_select_report;

/* Culling reasons returned by prw_lod_patch_culled. */
enum { PRW_LOD_VISIBLE = 0, PRW_LOD_CULLED_FRUSTUM = 1, PRW_LOD_CULLED_BACKFACE = 2, PRW_LOD_CULLED_MIXED = 3 };

/* Is patch `patch` culled for the view (see above)?  PRW_LOD_VISIBLE when v->cull is NULL. */
int prw_lod_patch_culled(const prw_lod_view *v, int patch);
/* Is the patch back-facing for eye `eye` by the normal-cone test (ignores single_sided)? */
bool prw_lod_cull_backfacing(const prw_lod_cull *c, int patch, prw_dvec3 eye);
/* Is the patch's box or sphere entirely outside one of the six planes? */
bool prw_lod_cull_outside(const prw_lod_cull *c, int patch, const prw_lod_plane planes[6]);

double prw_lod_patch_distance(const prw_lod_model *lm, int patch, const prw_lod_view *v);
/* Projected size in pixels of an error `err` at patch `patch`. */
double prw_lod_project(const prw_lod_model *lm, int patch, const prw_lod_view *v, double err);
/* levels: in/out (see culling above); drawn (may be NULL): 1 for a patch to draw, 0 for a culled
 * or failed one. */
void prw_lod_select_drawn(const prw_lod_model *lm, const prw_lod_view *v, int *levels, unsigned char *drawn,
                          prw_lod_select_report *r);
/* prw_lod_select_drawn without the drawn flags. */
void prw_lod_select(const prw_lod_model *lm, const prw_lod_view *v, int *levels, prw_lod_select_report *r);

#ifdef __cplusplus
}
#endif
#endif
