/* lod_node — loading the NURBS model of a scene entry (prw_lod_node.h). */
#include "prw_lod_node.h"

#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "prw_iges.h"
#include "prw_nurbs_json.h"
#include "prw_nurbs_procedural.h"
#include "scene_internal.h"

bool prw_scene_nurbs_procedural_known(const char *name)
{
    return name && (!strcmp(name, "car_shell") || !strcmp(name, "box") || !strcmp(name, "plate"));
}

static bool ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

bool prw_scene_nurbs_load(const prw_scene_nurbs *n, prw_nurbs_model *m, prw_error *e)
{
    prw_nurbs_model_init(m);
    bool ok;
    if (n->file[0]) {
        if (ends_with(n->file, ".igs") || ends_with(n->file, ".iges")) {
            prw_iges_info info;
            memset(&info, 0, sizeof info);
            ok = prw_iges_load(n->file, m, &info, e);
        } else if (ends_with(n->file, ".json")) {
            ok = prw_nurbs_json_load(n->file, m, e);
        } else {
            ok = prw_fail(e, "%s: unknown NURBS model type (expected .igs, .iges or .json)", n->file);
        }
    } else if (!strcmp(n->procedural, "car_shell")) {
        ok = prw_procedural_car_shell(m, e);
    } else if (!strcmp(n->procedural, "box")) {
        ok = prw_procedural_filleted_box(m, 1.0, 0.3, e);
    } else if (!strcmp(n->procedural, "plate")) {
        ok = prw_procedural_plate(m, e);
    } else {
        ok = prw_fail(e, "procedural NURBS model '%s' unknown (car_shell, box, plate)", n->procedural);
    }
    if (ok && m->count == 0) ok = prw_fail(e, "%s: the model has no surfaces", n->file[0] ? n->file : n->procedural);
    if (!ok) prw_nurbs_model_free(m);
    return ok;
}

static uint64_t hash_curve(uint64_t h, const prw_nurbs_curve *c)
{
    h = prw_hash64(&c->dim, sizeof c->dim, h);
    h = prw_hash64(&c->degree, sizeof c->degree, h);
    h = prw_hash64(&c->n, sizeof c->n, h);
    h = prw_hash64(c->knots, sizeof(double) * (size_t)(c->n + c->degree + 1), h);
    return prw_hash64(c->pw, sizeof(double) * 4 * (size_t)c->n, h);
}

uint64_t prw_scene_nurbs_model_hash(const prw_nurbs_model *m)
{
    uint64_t h = prw_hash64("prw-nurbs-model", 15, 0);
    for (size_t i = 0; i < m->count; i++) {
        const prw_trimmed_surface *t = &m->surfaces[i];
        const prw_nurbs_surface *s = &t->surface;
        int hdr[5] = {s->degree_u, s->degree_v, s->nu, s->nv, t->nloops};
        h = prw_hash64(hdr, sizeof hdr, h);
        h = prw_hash64(s->knots_u, sizeof(double) * (size_t)(s->nu + s->degree_u + 1), h);
        h = prw_hash64(s->knots_v, sizeof(double) * (size_t)(s->nv + s->degree_v + 1), h);
        h = prw_hash64(s->pw, sizeof(double) * 4 * (size_t)s->nu * (size_t)s->nv, h);
        unsigned char flags[2] = {t->natural_outer, t->has_colour};
        h = prw_hash64(flags, 2, h);
        if (t->has_colour) h = prw_hash64(t->colour, sizeof t->colour, h);
        for (int l = 0; l < t->nloops; l++) {
            h = prw_hash64(&t->loops[l].count, sizeof(int), h);
            for (int k = 0; k < t->loops[l].count; k++) {
                const prw_trim_segment *sg = &t->loops[l].segs[k];
                h = hash_curve(h, &sg->uv);
                unsigned char has = sg->model != NULL;
                h = prw_hash64(&has, 1, h);
                if (sg->model) h = hash_curve(h, sg->model);
            }
        }
    }
    return h;
}

/* ---- attachments ---- */

void prw_scene_nurbs_baked_free(struct prw_scene_nurbs_baked *b)
{
    if (b->model) prw_nurbs_model_free(b->model);
    free(b->model);
    prw_lod_file_destroy(b->lod);
    b->model = NULL;
    b->lod = NULL;
}

bool prw_scene_nurbs_attach(prw_scene *s, uint32_t i, prw_nurbs_model *m, prw_baked_lod *lod, prw_error *e)
{
    bool ok = true;
    if (i >= s->nurbs_count) ok = prw_fail(e, "scene: no NURBS entry %u (of %u)", i, s->nurbs_count);
    else if (!lod || lod->lod.npatches != (int)m->count)
        ok = prw_fail(e, "NURBS entry '%s': hierarchy has %d patches, the model %zu surfaces", s->nurbs[i].name,
                      lod ? lod->lod.npatches : 0, m->count);
    if (!ok) {
        prw_nurbs_model_free(m);
        prw_lod_file_destroy(lod);
        return false;
    }
    struct prw_scene_nurbs_baked *b = &s->nurbs_baked[i];
    prw_scene_nurbs_baked_free(b);
    b->model = prw_malloc(sizeof *b->model);
    *b->model = *m;
    prw_nurbs_model_init(m);
    b->lod = lod;
    return true;
}

bool prw_scene_nurbs_baked(const prw_scene *s, uint32_t i, const prw_nurbs_model **m, const prw_baked_lod **lod,
                           prw_error *e)
{
    if (m) *m = NULL;
    if (lod) *lod = NULL;
    if (i >= s->nurbs_count) return prw_fail(e, "scene: no NURBS entry %u (of %u)", i, s->nurbs_count);
    const struct prw_scene_nurbs_baked *b = &s->nurbs_baked[i];
    if (!b->model || !b->lod)
        return prw_fail(e, "NURBS entry '%s' has no baked hierarchy: call prw_bake_scene (engine/bake) first",
                        s->nurbs[i].name);
    if (m) *m = b->model;
    if (lod) *lod = b->lod;
    return true;
}
