/* shadow_plan — the shadow views of a scene's lights, computed once from the scene (absolute, double):
 * one depth layer per spot, rect and directional light that casts shadows and six per point light, at
 * most PRW_MAX_SHADOW_VIEWS layers (lights beyond that are unshadowed).  Eye-independent: shared by
 * every view of a view set (DESIGN.md §6).
 *  - spot: a perspective frustum over its outer cone (+0.05 rad, at most 1.45 rad half-angle);
 *    rect: 150 degrees of its hemisphere (grazing directions unshadowed); point: a cube of 90-degree
 *    frusta; directional: an orthographic box around the scene's bounds.  Reversed Z, near 0.02 m.
 *  - texel_per_unit: the shadow map's width in metres at unit distance (orthographic: absolute); one
 *    texel is texel_per_unit / size.
 *  - Emissive meshes' area lights (prw_emissive.h) take the slots the scene's lights leave, as rect
 *    lights that cast shadows.
 *  - GPU light slots: the order of the lights in the per-view globals (view_globals.c), grouped by
 *    shading class — shadowed rect, unshadowed rect, shadowed spot and directional (one layer),
 *    shadowed point (six), unshadowed punctual — each group in scene order.  The base shaders are
 *    specialised on the group sizes (lights.glsl, pipes.c), so a light pays only for the code of its
 *    own class. */
#ifndef PRW_SHADOW_PLAN_H
#define PRW_SHADOW_PLAN_H

#include "prw_constants.h"
#include "prw_emissive.h"
#include "prw_scene.h"

/* A light as the GPU slots and the shadow views see it (absolute world, double): the scene's lights
 * first (plan light i = scene light i), then the emissive meshes' area lights (prw_emissive.h) while
 * slots are left.  An area light of an emissive mesh is a rect light of its shape, moved 1e-4 of its
 * size along its normal so the emitting surface itself (drawn with its own emission) is behind it and
 * gets no light from it; its shadow view sits at its centroid. */
typedef struct prw_plan_light {
    prw_light_type type;
    prw_dvec3 pos, dir;       /* dir: where a spot / directional / rect light shines (unit) */
    prw_dvec3 half_u, half_v; /* rect: corners pos - u - v, + u - v, + u + v, (not a triangle) - u + v */
    int shape;                /* rect: prw_area_shape (the scene's rect lights: PRW_AREA_RECT) */
    prw_dvec3 shadow_pos;
    float radiance[3];        /* colour x intensity */
    double range, inner_cone, outer_cone;
    bool cast_shadows;
    int emissive;             /* -1: a scene light; else the index into prw_emissive_lights.lights */
} prw_plan_light;

typedef struct prw_shadow_view {
    int light;
    prw_dmat4 view_proj;   /* absolute world -> light clip */
    double texel_per_unit;
} prw_shadow_view;

typedef struct prw_shadow_plan {
    prw_shadow_view views[PRW_MAX_SHADOW_VIEWS];
    uint32_t count;
    int light_first[PRW_MAX_LIGHTS]; /* first layer of light i, -1: unshadowed */
    uint32_t slot_count;                    /* lights in the globals: min(scene lights, PRW_MAX_LIGHTS) */
    uint32_t slot_light[PRW_MAX_LIGHTS];    /* scene light of GPU slot k */
    uint32_t class_count[PRW_LIGHT_CLASSES]; /* slots per class, in slot order (PRW_LIGHT_CLASS_*) */
    prw_plan_light lights[PRW_MAX_LIGHTS];  /* the planned lights; slot_light and light_first index them */
    uint32_t light_count;
    uint32_t emissive_count;                /* of them from emissive meshes (the last ones) */
} prw_shadow_plan;

/* The scene's lights only. */
void prw_shadow_plan_make(const prw_scene *s, prw_shadow_plan *out);
/* The scene's lights, then em's lights (NULL: none) in their order while slots are left. */
void prw_shadow_plan_make_with(const prw_scene *s, const prw_emissive_lights *em, prw_shadow_plan *out);

#endif
