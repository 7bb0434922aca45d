/* drawables — the drawable table (one line per geometry kind, drawn in this order) and the list of a
 * renderer's drawables with their states (prw_draw.h). */
#include <string.h>

#include "prw_draw.h"

extern const prw_drawable prw_drawable_mesh, prw_drawable_light_quad, prw_drawable_nurbs;

const prw_drawable *const prw_drawables_default[] = {
    &prw_drawable_mesh,       /* the scene's meshes (draw_mesh.c) */
    &prw_drawable_light_quad, /* rect lights' emitting surfaces (draw_light_quad.c) */
    &prw_drawable_nurbs,      /* trimmed-NURBS models with LOD (draw_nurbs.c) */
    NULL,
};

bool prw_drawables_create(prw_drawables *d, const prw_drawable *const *table, const prw_render_env *env,
                          prw_error *e)
{
    memset(d, 0, sizeof *d);
    for (uint32_t i = 0; table[i]; i++) {
        if (d->count == PRW_MAX_DRAWABLES) return prw_fail(e, "render: more than %d drawables", PRW_MAX_DRAWABLES);
        d->kind[d->count] = table[i];
        d->count++;
        if (table[i]->create && !table[i]->create(env, &d->state[d->count - 1], e))
            return prw_fail_wrap(e, "drawable '%s'", table[i]->name);
    }
    return true;
}

void prw_drawables_destroy(prw_drawables *d, const prw_render_env *env)
{
    for (uint32_t i = d->count; i-- > 0;)
        if (d->kind[i]->destroy) d->kind[i]->destroy(env, d->state[i]);
    memset(d, 0, sizeof *d);
}

bool prw_drawables_update(prw_drawables *d, const prw_render_env *env, const prw_view *views, uint32_t count,
                          prw_error *e)
{
    for (uint32_t i = 0; i < d->count; i++)
        if (d->kind[i]->update && !d->kind[i]->update(d->state[i], env, views, count, e)) return false;
    return true;
}

void prw_drawables_record(const prw_drawables *d, const prw_render_env *env, prw_draw_ctx *c)
{
    for (uint32_t i = 0; i < d->count && !c->failed; i++) d->kind[i]->record(d->state[i], env, c);
}

bool prw_drawables_have(const prw_drawables *d, const prw_render_env *env, prw_draw_kind kind)
{
    for (uint32_t i = 0; i < d->count; i++)
        if (!d->kind[i]->has || d->kind[i]->has(d->state[i], env, kind)) return true;
    return false;
}

void *prw_drawables_state(const prw_drawables *d, const char *name)
{
    for (uint32_t i = 0; i < d->count; i++)
        if (strcmp(d->kind[i]->name, name) == 0) return d->state[i];
    return NULL;
}
