/* ref_nurbs — the scene's trimmed-NURBS models in the reference path tracer (issue 7: "the
 * reference renders the finest tessellation ... with normals from the exact surface").
 *
 * Each entry's model and hierarchy are the ones the baker attached to the scene (engine/bake's
 * prw_bake_scene; read with prw_scene_nurbs_baked, nothing is loaded or built here, and the reference
 * does not link the baker) — the same level 0 the rasterizer's LOD models refine to — and level 0
 * with every segment at level 0 (all sewing points:
 * watertight) becomes one prw_mesh per entry: positions in model metres, normals evaluated on the
 * exact surface at each vertex's (u, v) (prw_nurbs_surface_normal, defined at poles), (u, v) as
 * texture coordinates.  Between vertices the normal is interpolated; the tessellation's error bound
 * (the hierarchy's level-0 bound, metres) is kept so prw_ref_render can report it in pixels for the
 * rendered view (prw_ref_stats.tess_px).
 * Orientation: patches of one model need not agree (S_u x S_v may point inward on some), so NURBS
 * instances are two-sided in the tracer: the shading normal is turned to the side the ray arrives
 * from.  For a closed model seen from outside that is its outside; open models are lit on both sides.
 * Instances: the entry's grid, copy (i, j) moved by (i spacing[0], 0, j spacing[1]) in world space,
 * as the rasterizer places them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_node.h"
#include "ref_internal.h"

/* Level 0 of patch p appended to the mesh arrays (grown as needed). */
static void append_patch(const prw_lod_model *lm, const prw_nurbs_surface *surf, int p, int *seg0, prw_lod_mesh *em,
                         prw_mesh *out, uint32_t *vcap, uint32_t *icap)
{
    prw_lod_mesh_reset(em);
    prw_lod_emit(lm, p, 0, seg0, em);
    const prw_lod_patch *pa = &lm->patches[p];
    uint32_t base = out->vertex_count;
    if (base + em->nverts > *vcap) {
        while (base + em->nverts > *vcap) *vcap = *vcap ? *vcap * 2 : 4096;
        out->positions = prw_realloc(out->positions, (size_t)*vcap * 3 * sizeof(float));
        out->normals = prw_realloc(out->normals, (size_t)*vcap * 3 * sizeof(float));
        out->uvs = prw_realloc(out->uvs, (size_t)*vcap * 2 * sizeof(float));
    }
    /* (u, v) of each emitted vertex: map[local] = emitted index; fan centres (not at level 0 with
     * every segment at level 0, but kept general) take the mean (u, v) of the patch's vertices */
    double *uv = prw_calloc(em->nverts ? em->nverts : 1, 2 * sizeof(double));
    unsigned char *have = prw_calloc(em->nverts ? em->nverts : 1, 1);
    double mu = 0, mv = 0;
    for (int l = 0; l < pa->nverts; l++) {
        mu += pa->uv[2 * l] / pa->nverts, mv += pa->uv[2 * l + 1] / pa->nverts;
        int k = l < em->mapcap ? em->map[l] : -1;
        if (k >= 0 && (size_t)k < em->nverts) uv[2 * k] = pa->uv[2 * l], uv[2 * k + 1] = pa->uv[2 * l + 1], have[k] = 1;
    }
    for (size_t k = 0; k < em->nverts; k++) {
        double u = have[k] ? uv[2 * k] : mu, v = have[k] ? uv[2 * k + 1] : mv;
        prw_normal_kind kind;
        prw_dvec3 n = prw_nurbs_surface_normal(surf, u, v, &kind);
        if (!(isfinite(n.x) && isfinite(n.y) && isfinite(n.z)) || prw_v3_len(n) < 0.5) n = prw_v3(0, 0, 1);
        size_t o = base + k;
        for (int c = 0; c < 3; c++) out->positions[3 * o + c] = (float)em->pos[3 * k + c];
        out->normals[3 * o] = (float)n.x, out->normals[3 * o + 1] = (float)n.y, out->normals[3 * o + 2] = (float)n.z;
        out->uvs[2 * o] = (float)u, out->uvs[2 * o + 1] = (float)v;
    }
    free(uv);
    free(have);
    out->vertex_count += (uint32_t)em->nverts;
    for (size_t t = 0; t < em->ntris; t++) {
        const uint32_t *ix = em->tris + 3 * t;
        const double *a = em->pos + 3 * ix[0], *b = em->pos + 3 * ix[1], *c = em->pos + 3 * ix[2];
        prw_dvec3 ab = prw_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]), ac = prw_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
        if (!(prw_v3_len(prw_v3_cross(ab, ac)) > 0)) continue; /* pole copies joined: not a surface */
        if (out->index_count + 3 > *icap) {
            *icap = *icap ? *icap * 2 : 12288;
            out->indices = prw_realloc(out->indices, (size_t)*icap * sizeof(uint32_t));
        }
        for (int k = 0; k < 3; k++) out->indices[out->index_count++] = base + ix[k];
    }
}

static bool entry_mesh(const prw_scene *s, uint32_t i, prw_mesh *out, double *err, prw_error *e)
{
    const prw_scene_nurbs *n = &s->nurbs[i];
    const prw_nurbs_model *m;
    const prw_baked_lod *b;
    if (!prw_scene_nurbs_baked(s, i, &m, &b, e)) return prw_fail_wrap(e, "reference");
    const prw_lod_model *lm = &b->lod;
    int nseg = lm->g->nsegs;
    int *seg0 = prw_calloc(nseg > 0 ? (size_t)nseg : 1, sizeof(int));
    prw_lod_mesh em;
    memset(&em, 0, sizeof em);
    memset(out, 0, sizeof *out);
    snprintf(out->name, sizeof out->name, "%s", n->name);
    out->material = n->material;
    uint32_t vcap = 0, icap = 0;
    *err = 0;
    for (int p = 0; p < lm->npatches; p++) {
        if (!lm->patches[p].ok) continue;
        append_patch(lm, &m->surfaces[p].surface, p, seg0, &em, out, &vcap, &icap);
        *err = fmax(*err, lm->patches[p].err[0]);
    }
    prw_lod_mesh_free(&em);
    free(seg0);
    if (out->index_count == 0) return prw_fail(e, "reference: NURBS model '%s': no triangles at level 0", n->name);
    prw_mesh_generate_tangents(out);
    prw_dvec3 lo = prw_v3(INFINITY, INFINITY, INFINITY), hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t v = 0; v < out->vertex_count; v++) {
        prw_dvec3 q = prw_v3(out->positions[3 * v], out->positions[3 * v + 1], out->positions[3 * v + 2]);
        lo = prw_v3(fmin(lo.x, q.x), fmin(lo.y, q.y), fmin(lo.z, q.z));
        hi = prw_v3(fmax(hi.x, q.x), fmax(hi.y, q.y), fmax(hi.z, q.z));
    }
    out->bounds_min = lo, out->bounds_max = hi;
    return true;
}

static void mesh_free(prw_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->uvs);
    free(m->tangents);
    free(m->indices);
}

uint32_t ref_nurbs_instance_count(const prw_scene *s)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < s->nurbs_count; i++) n += (uint32_t)(s->nurbs[i].grid[0] * s->nurbs[i].grid[1]);
    return n;
}

bool ref_nurbs_add(prw_ref_renderer *r, prw_error *e)
{
    const prw_scene *s = r->scene;
    if (!s->nurbs_count) return true;
    r->nurbs_meshes = prw_calloc(s->nurbs_count, sizeof(prw_mesh));
    r->nurbs_err = prw_calloc(s->nurbs_count, sizeof(double));
    for (uint32_t i = 0; i < s->nurbs_count; i++) {
        const prw_scene_nurbs *n = &s->nurbs[i];
        if (n->material < 0 || (uint32_t)n->material >= s->material_count || n->node < 0 ||
            (uint32_t)n->node >= s->node_count)
            return prw_fail(e, "reference: NURBS model '%s': material or node index out of range", n->name);
        if (!entry_mesh(s, i, &r->nurbs_meshes[i], &r->nurbs_err[i], e)) return false;
        r->nurbs_mesh_count = i + 1;
        for (int gj = 0; gj < n->grid[1]; gj++)
            for (int gi = 0; gi < n->grid[0]; gi++) {
                prw_node node = s->nodes[n->node];
                prw_dmat4 t = prw_dm4_identity();
                t.m[12] = gi * n->spacing[0];
                t.m[14] = gj * n->spacing[1];
                node.world = prw_dm4_mul(t, node.world);
                uint32_t k = r->inst_count;
                if (!ref_add_instance(r, &node, &r->nurbs_meshes[i], e)) return false;
                if (r->inst_count > k) {
                    r->inst[k].two_sided = true;
                    r->inst[k].nurbs_entry = (int)i;
                    r->inst[k].world = node.world;
                }
            }
    }
    return true;
}

void ref_nurbs_free(prw_ref_renderer *r)
{
    for (uint32_t i = 0; i < r->nurbs_mesh_count; i++) mesh_free(&r->nurbs_meshes[i]);
    free(r->nurbs_meshes);
    free(r->nurbs_err);
}

double ref_nurbs_px(const prw_ref_renderer *r, const prw_view *v)
{
    /* the smallest angle a pixel subtends (at the image corner farthest from the axis) */
    double tx = fmax(fabs(v->tan_left), fabs(v->tan_right)), ty = fmax(fabs(v->tan_bottom), fabs(v->tan_top));
    double pix = fmin((v->tan_right - v->tan_left) / v->width, (v->tan_top - v->tan_bottom) / v->height) /
                 (1.0 + tx * tx + ty * ty);
    double worst = 0;
    for (uint32_t k = 0; k < r->inst_count; k++) {
        const ref_inst *in = &r->inst[k];
        if (in->nurbs_entry < 0) continue;
        const prw_mesh *m = in->mesh;
        /* world box of the instance (corners of the model box) and its largest axis scale */
        prw_dvec3 lo = prw_v3(INFINITY, INFINITY, INFINITY), hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
        for (int c = 0; c < 8; c++) {
            prw_dvec3 q = prw_v3(c & 1 ? m->bounds_max.x : m->bounds_min.x, c & 2 ? m->bounds_max.y : m->bounds_min.y,
                                 c & 4 ? m->bounds_max.z : m->bounds_min.z);
            q = prw_dm4_point(in->world, q);
            lo = prw_v3(fmin(lo.x, q.x), fmin(lo.y, q.y), fmin(lo.z, q.z));
            hi = prw_v3(fmax(hi.x, q.x), fmax(hi.y, q.y), fmax(hi.z, q.z));
        }
        double sc = 0;
        for (int a = 0; a < 3; a++)
            sc = fmax(sc, sqrt(in->world.m[4 * a] * in->world.m[4 * a] + in->world.m[4 * a + 1] * in->world.m[4 * a + 1] +
                               in->world.m[4 * a + 2] * in->world.m[4 * a + 2]));
        prw_dvec3 d = prw_v3(fmax(fmax(lo.x - v->eye.x, v->eye.x - hi.x), 0), fmax(fmax(lo.y - v->eye.y, v->eye.y - hi.y), 0),
                             fmax(fmax(lo.z - v->eye.z, v->eye.z - hi.z), 0));
        double dist = fmax(prw_v3_len(d), v->znear);
        worst = fmax(worst, r->nurbs_err[in->nurbs_entry] * sc / (dist * pix));
    }
    return worst;
}
