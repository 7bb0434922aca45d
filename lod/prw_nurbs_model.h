/* prw_nurbs_model — a CAD model as a list of trimmed NURBS surfaces (what the IGES and JSON
 * readers produce, and what the seam graph / LOD stages will consume).
 *
 * Promises:
 *  - Lengths are metres (readers convert units and apply transforms before returning).
 *  - A trimmed surface is its NURBS surface plus trim loops in its (u, v) domain.  loops[0] is the
 *    outer loop unless `natural_outer` is set, in which case the outer boundary is the domain
 *    rectangle and every loop is an inner loop.  Each loop is an ordered list of segments; a
 *    segment is a 2-D NURBS curve in (u, v) (a polyline is a degree-1 curve) and optionally the
 *    3-D model-space curve it came from (IGES 142 "C"), kept for the seam graph.
 *  - Loop orientation is NOT required: the inside test is even-odd (see prw_trim.h).
 *  - Every curve / surface in a model has passed validation.
 */
#ifndef PRW_NURBS_MODEL_H
#define PRW_NURBS_MODEL_H

#include "prw_nurbs.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct prw_trim_segment {
    prw_nurbs_curve uv;     /* dim 2, in the surface's (u, v) */
    prw_nurbs_curve *model; /* optional dim-3 model-space curve (metres), NULL if none */
} prw_trim_segment;

typedef struct prw_trim_loop {
    prw_trim_segment *segs;
    int count;
} prw_trim_loop;

typedef struct prw_trimmed_surface {
    prw_nurbs_surface surface;
    prw_trim_loop *loops;
    int nloops;
    bool natural_outer; /* outer boundary = domain rectangle; all loops are holes */
    bool has_colour;
    float colour[3]; /* linear 0..1 */
    int source;      /* IGES DE sequence number / JSON index, for messages and the seam graph */
} prw_trimmed_surface;

typedef struct prw_nurbs_model {
    prw_trimmed_surface *surfaces;
    size_t count, cap;
} prw_nurbs_model;

void prw_nurbs_model_init(prw_nurbs_model *m);
void prw_nurbs_model_free(prw_nurbs_model *m);
/* Appends a zeroed surface and returns it (natural_outer = true, no loops). */
prw_trimmed_surface *prw_nurbs_model_add(prw_nurbs_model *m);
/* Removes the last surface (freeing it) — for readers that fail half-way through one. */
void prw_nurbs_model_pop(prw_nurbs_model *m);
void prw_trimmed_surface_free(prw_trimmed_surface *t);
/* Appends an empty loop; returns it. */
prw_trim_loop *prw_trimmed_surface_add_loop(prw_trimmed_surface *t);
/* Appends a segment taking ownership of *uv (and of *model when not NULL; it is heap-copied). */
void prw_trim_loop_add(prw_trim_loop *l, prw_nurbs_curve *uv, prw_nurbs_curve *model);
/* Reverses the surface's u direction (knots mirrored about the domain, columns reversed) and
 * mirrors every trim curve with it, u -> u0 + u1 - u: the same trimmed face, exactly, with the
 * opposite normal Su x Sv. */
void prw_trimmed_surface_reverse_u(prw_trimmed_surface *t);
/* World-space bounding box of all surfaces (control hulls, untrimmed: what tolerances scale
 * from). false when the model is empty. */
bool prw_nurbs_model_bounds(const prw_nurbs_model *m, prw_dvec3 *lo, prw_dvec3 *hi);
/* World-space bounding box of the TRIMMED faces (prw_nurbs_model_bounds.c), for display and scene
 * bounds:
 *  - conservative: it contains every point of every face's trimmed region (the closed even-odd
 *    region of the loops closed as prw_trim closes them, within the domain): it is a union of
 *    control hulls of sub-patches cut out by knot insertion (convex hull property) over the
 *    rectangles of the domain that the trim curves — each piece enclosed with the hull of its
 *    control points — do not show to lie outside;
 *  - tight: each side exceeds the box of points on the faces by at most 1e-4 x that box's diagonal
 *    (unless a subdivision budget ran out — 200000 rectangles per face, 4e8 control-point x degree
 *    operations per model — or the depth: then the side is still conservative, only looser);
 *  - within prw_nurbs_model_bounds (sub-patch control points are convex combinations);
 *  - false when the model is empty; when no loop encloses anything, prw_nurbs_model_bounds. */
bool prw_nurbs_model_trimmed_bounds(const prw_nurbs_model *m, prw_dvec3 *lo, prw_dvec3 *hi);
/* The same with other limits than prw_nurbs_model_trimmed_bounds' (work 4e8 per model, 200000
 * trim-curve samples per face); still conservative when they run out, only looser. */
typedef struct prw_bounds_limits {
    long work;    /* control points x degrees of the cut-out patches, per model */
    long samples; /* trim-curve points per face */
} prw_bounds_limits;
bool prw_nurbs_model_trimmed_bounds_limited(const prw_nurbs_model *m, const prw_bounds_limits *lim, prw_dvec3 *lo,
                                            prw_dvec3 *hi);

#ifdef __cplusplus
}
#endif
#endif
