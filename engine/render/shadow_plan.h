/* shadow_plan — the shadow views of a scene's lights, computed once from the scene (absolute, double):
 * one depth layer per spot, rect and directional light that casts shadows and six per point light, at
 * most PRW_MAX_SHADOW_VIEWS layers (lights beyond that are unshadowed).  Eye-independent: shared by
 * every view of a view set (DESIGN.md §6).
 *  - spot: a perspective frustum over its outer cone (+0.05 rad, at most 1.45 rad half-angle);
 *    rect: 150 degrees of its hemisphere (grazing directions unshadowed); point: a cube of 90-degree
 *    frusta; directional: an orthographic box around the scene's bounds.  Reversed Z, near 0.02 m.
 *  - texel_per_unit: the shadow map's width in metres at unit distance (orthographic: absolute); one
 *    texel is texel_per_unit / size.
 *  - GPU light slots: the order of the lights in the per-view globals (view_globals.c), grouped by
 *    shading class — shadowed rect, unshadowed rect, shadowed spot and directional (one layer),
 *    shadowed point (six), unshadowed punctual — each group in scene order.  The base shaders are
 *    specialised on the group sizes (lights.glsl, pipes.c), so a light pays only for the code of its
 *    own class. */
#ifndef PRW_SHADOW_PLAN_H
#define PRW_SHADOW_PLAN_H

#include "prw_constants.h"
#include "prw_scene.h"

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
} prw_shadow_plan;

void prw_shadow_plan_make(const prw_scene *s, prw_shadow_plan *out);

#endif
