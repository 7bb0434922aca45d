/* prw_emissive — the drawn emissive meshes as area lights for the rasterizer (issue 16).
 *
 * Promises:
 *  - Emission of a material = emission (cd/m^2, linear RGB) x the emissive texture's mean (sRGB decoded)
 *    when it has one: the texture's variation is not in the light (prw_emissive_source.textured says so);
 *    a MASK or BLEND material's times its mean coverage (the path tracer weights emission by the
 *    coverage at the point), so a cut-out or half-transparent emitter sends its mean light.
 *  - Emitting sides as in the path tracer (engine/reference): a single-sided material emits towards the
 *    front (counter-clockwise winding in world space, flipped by a mirroring node transform); a
 *    double-sided one emits to both sides, each side its own lights.
 *  - Each drawn (node, mesh) with an emissive material is one source.  Its triangles are merged into
 *    polygons: edge-adjacent (shared corner positions) and coplanar triangles; a component whose
 *    boundary is one convex loop becomes one polygon (collinear corners dropped), any other component
 *    keeps its triangles as polygons of their own (Lambert's formula is additive, so that is exact, only
 *    dearer).
 *  - A polygon becomes lights of three shapes, all with corners centre - u - v, centre + u - v,
 *    centre + u + v and (not a triangle) centre - u + v, emitting towards `normal`:
 *    a rectangle (u, v orthogonal: the rect-light shading of prw_light), a parallelogram, or a fan of
 *    triangles (n - 2 for n corners).  Together the lights cover exactly the polygon.
 *  - Budget: at most `max_lights` lights in all.  When the exact lights need more, polygons are
 *    merged, those with the most lights first, each into one rectangle of the same area, centroid and
 *    principal axes (same flux; the shape is approximate); when one light per polygon is still too many,
 *    sources (the largest saving first) become one square per direction cluster — their polygons
 *    binned by the normal's dominant axis (+-x, +-y, +-z), the square at the cluster's area centroid,
 *    facing its area-weighted mean normal, of its total area (same flux, pi L A); when that is still
 *    too many, the lights of least flux are dropped (their polygons counted as dropped).
 *    max_lights 0: no lights at all.
 *  - Deterministic: the same scene and budget give the same lights in the same order (source order =
 *    node order, then mesh order).
 */
#ifndef PRW_EMISSIVE_H
#define PRW_EMISSIVE_H

#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_area_shape {
    PRW_AREA_RECT = 0,          /* u and v orthogonal */
    PRW_AREA_PARALLELOGRAM = 1, /* u and v not orthogonal */
    PRW_AREA_TRIANGLE = 2,      /* corners centre - u - v, centre + u - v, centre + u + v */
} prw_area_shape;

typedef struct prw_area_light {
    prw_area_shape shape;
    prw_dvec3 centre, half_u, half_v; /* world, metres */
    prw_dvec3 normal;                 /* unit: emits towards +normal only */
    prw_dvec3 centroid;               /* of the area (a triangle's centre is an edge's midpoint) */
    float radiance[3];                /* cd/m^2, linear RGB */
    uint32_t source;                  /* index into prw_emissive_lights.sources */
    bool merged;                      /* an equal-area rectangle standing for a polygon */
} prw_area_light;

typedef struct prw_emissive_source {
    int node;
    uint32_t mesh;
    uint32_t triangles;     /* emitting (non-degenerate) triangles */
    uint32_t polygons;      /* polygons after merging, per emitting side */
    uint32_t rects, parallelograms, triangle_lights; /* lights made, by shape (exact ones) */
    uint32_t merged;        /* polygons (all sides) replaced by one equal-area rectangle each (over the budget) */
    uint32_t clustered;     /* polygons (all sides) in direction clusters (over the budget) */
    uint32_t cluster_lights;/* the clusters' rectangles */
    uint32_t dropped;       /* polygons (all sides) with no light (over the budget) */
    bool two_sided, textured;
    float coverage;         /* mean alpha coverage (MASK / BLEND; 1 for OPAQUE), in radiance */
    float radiance[3];      /* cd/m^2 */
    double area;            /* m^2, one side */
} prw_emissive_source;

typedef struct prw_emissive_lights {
    prw_area_light *lights;
    uint32_t count;
    prw_emissive_source *sources;
    uint32_t source_count;
    uint32_t max_lights;    /* the budget it was built with */
} prw_emissive_lights;

/* Builds the lights of the scene's drawn emissive meshes (call after prw_scene_update); out is
 * overwritten (free it with prw_emissive_lights_free). */
void prw_emissive_lights_build(const prw_scene *s, uint32_t max_lights, prw_emissive_lights *out);
void prw_emissive_lights_free(prw_emissive_lights *l);

/* A material's emitted radiance (cd/m^2, linear RGB): emission x the emissive texture's mean (sRGB
 * decoded); false when it emits nothing (black, negative or not finite). */
bool prw_material_emitted_rgb(const prw_scene *s, const prw_material *m, double rgb[3]);

#ifdef __cplusplus
}
#endif
#endif
