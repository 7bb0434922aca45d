/* view_globals — the per-view uniform block (shaders/common.glsl prw_globals) for a view drawn
 * relative to `origin`: camera-relative view-projection and eye, the plan's lights (shadow_plan.h: the
 * scene's, then emissive meshes' area lights) in its slot order (positions relative to origin;
 * rect-light axes and shape; shadow layers) and the shadow matrices (camera-relative world -> light clip).  Pure CPU, deterministic. */
#ifndef PRW_VIEW_GLOBALS_H
#define PRW_VIEW_GLOBALS_H

#include "gpu_types.h"
#include "prw_view.h"
#include "shadow_plan.h"

void prw_view_globals_fill(const prw_scene *s, const prw_shadow_plan *plan, uint32_t shadow_size,
                           const prw_view *v, prw_dvec3 origin, prw_gpu_globals *g);
/* The view-projection of v relative to origin (the one in the globals). */
prw_mat4 prw_view_globals_view_proj(const prw_view *v, prw_dvec3 origin);

#endif
