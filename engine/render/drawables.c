/* drawables — the drawable table: one line per geometry kind, drawn in this order. */
#include "prw_draw.h"

extern const prw_drawable prw_drawable_mesh, prw_drawable_light_quad, prw_drawable_nurbs;

const prw_drawable *const prw_drawables_default[] = {
    &prw_drawable_mesh,       /* the scene's meshes (draw_mesh.c) */
    &prw_drawable_light_quad, /* rect lights' emitting surfaces (draw_light_quad.c) */
    &prw_drawable_nurbs,      /* trimmed-NURBS models with LOD (draw_nurbs.c) */
    NULL,
};
