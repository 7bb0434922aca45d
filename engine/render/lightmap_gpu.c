/* lightmap_gpu — the light maps on the GPU (lightmap_gpu.h). */
#include "lightmap_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_constants.h"

static bool group_of(const prw_scene *s, uint32_t node, uint32_t *first, uint32_t *count)
{
    int gi = s->nodes[node].mesh_group;
    *first = *count = 0;
    if (gi < 0 || (uint32_t)gi >= s->group_count) return false;
    *first = s->groups[gi].first;
    *count = s->groups[gi].count;
    return true;
}

static bool finite_nonneg(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]) || v[i] < 0.0f) return false;
    return true;
}

/* prw_lightmap.h's promises for instance i. */
static bool unit_range(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!(v[i] >= 0.0f && v[i] <= 1.0f)) return false;
    return true;
}

static bool check_instance(const prw_scene *s, const prw_lightmaps *lm, uint32_t i, prw_error *e)
{
    const prw_lightmap_instance *in = &lm->inst[i];
    if (in->mode == PRW_LIGHTMAP_NONE) return true;
    if (in->mode != PRW_LIGHTMAP_ATLAS && in->mode != PRW_LIGHTMAP_VERTEX)
        return prw_fail(e, "light maps: instance %u: mode %u unknown", i, in->mode);
    uint32_t first, count;
    if (in->node >= s->node_count || !group_of(s, in->node, &first, &count) || in->mesh < first ||
        in->mesh >= first + count || in->mesh >= s->mesh_count)
        return prw_fail(e, "light maps: instance %u: node %u / mesh %u is not drawn by the scene", i, in->node, in->mesh);
    const prw_mesh *m = &s->meshes[in->mesh];
    if (!in->vertex_count || (!in->source && in->vertex_count != m->vertex_count))
        return prw_fail(e, "light maps: instance %u: %u vertices for mesh '%s' of %u", i, in->vertex_count, m->name,
                        m->vertex_count);
    if (in->index_count != m->index_count)
        return prw_fail(e, "light maps: instance %u: %u indices, mesh '%s' has %u", i, in->index_count, m->name,
                        m->index_count);
    for (uint32_t k = 0; in->source && k < in->vertex_count; k++)
        if (in->source[k] >= m->vertex_count) return prw_fail(e, "light maps: instance %u: source vertex out of range", i);
    const uint32_t *idx = in->indices ? in->indices : m->indices;
    for (uint32_t k = 0; k < in->index_count; k++)
        if (idx[k] >= in->vertex_count) return prw_fail(e, "light maps: instance %u: index out of range", i);
    if (in->mode == PRW_LIGHTMAP_ATLAS) {
        if (in->atlas >= lm->atlas_count || !in->uv)
            return prw_fail(e, "light maps: instance %u: atlas %u of %u", i, in->atlas, lm->atlas_count);
        for (size_t k = 0; k < 2 * (size_t)in->vertex_count; k++)
            if (!(in->uv[k] >= 0.0f && in->uv[k] <= 1.0f))
                return prw_fail(e, "light maps: instance %u: uv outside [0, 1]", i);
    } else if (!in->rgb || !finite_nonneg(in->rgb, 3 * (size_t)in->vertex_count))
        return prw_fail(e, "light maps: instance %u: vertex values missing, negative or not finite", i);
    else if (in->vis && !unit_range(in->vis, in->vertex_count))
        return prw_fail(e, "light maps: instance %u: a vertex visibility is outside [0, 1]", i);
    for (size_t k = 0; in->mode == PRW_LIGHTMAP_VERTEX && in->cone && k < in->vertex_count; k++)
        if (!isfinite(in->cone[4 * k]) || !isfinite(in->cone[4 * k + 1]) || !isfinite(in->cone[4 * k + 2]) ||
            !(in->cone[4 * k + 3] >= 0.0f && in->cone[4 * k + 3] <= 1.0f))
            return prw_fail(e, "light maps: instance %u: vertex open cone %zu not finite or outside [0, 1]", i, k);
    return true;
}

static bool make_atlas(prw_gpu *gpu, const prw_lightmaps *lm, bool active, uint32_t *W, uint32_t *H,
                       prw_gpu_image *out, prw_error *e)
{
    uint32_t n = active ? lm->atlas_count : 0, w = 1, h = 1;
    for (uint32_t i = 0; i < n; i++) {
        const prw_lightmap_atlas *a = &lm->atlases[i];
        if (!a->width || !a->height || a->width > 4096 || a->height > 4096 || !a->rgb)
            return prw_fail(e, "light maps: atlas %u: size %ux%u (1..4096 a side) or no texels", i, a->width, a->height);
        if (!finite_nonneg(a->rgb, 3 * (size_t)a->width * a->height))
            return prw_fail(e, "light maps: atlas %u: a texel is negative or not finite", i);
        if (a->vis && !unit_range(a->vis, (size_t)a->width * a->height))
            return prw_fail(e, "light maps: atlas %u: a visibility is outside [0, 1]", i);
        for (size_t t = 0; a->cone && t < (size_t)a->width * a->height; t++)
            if (!isfinite(a->cone[4 * t]) || !isfinite(a->cone[4 * t + 1]) || !isfinite(a->cone[4 * t + 2]) ||
                !(a->cone[4 * t + 3] >= 0.0f && a->cone[4 * t + 3] <= 1.0f))
                return prw_fail(e, "light maps: atlas %u: open cone %zu not finite or its fraction outside [0, 1]", i, t);
        w = a->width > w ? a->width : w;
        h = a->height > h ? a->height : h;
    }
    *W = w, *H = h;
    prw_image_desc d = {.width = w, .height = h, .layers = n ? 2 * n : 1, .format = VK_FORMAT_R32G32B32A32_SFLOAT,
                        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                        .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    if (!prw_image_create(gpu, &d, out, e)) return false;
    size_t texels = (size_t)w * h;
    float *px = prw_calloc(texels, 4 * sizeof(float));
    bool ok = true;
    for (uint32_t l = 0; ok && l < (n ? 2 * n : 1); l++) {
        memset(px, 0, texels * 4 * sizeof(float));
        if (l >= n && n) { /* the open cones */
            const prw_lightmap_atlas *a = &lm->atlases[l - n];
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++) {
                    float *p = px + 4 * ((size_t)y * w + x);
                    if (a->cone && x < a->width && y < a->height)
                        memcpy(p, a->cone + 4 * ((size_t)y * a->width + x), 4 * sizeof(float));
                    else
                        p[3] = -1.0f;
                }
        } else if (n) {
            const prw_lightmap_atlas *a = &lm->atlases[l];
            for (uint32_t y = 0; y < a->height; y++)
                for (uint32_t x = 0; x < a->width; x++) {
                    float *p = px + 4 * ((size_t)y * w + x);
                    memcpy(p, a->rgb + 3 * ((size_t)y * a->width + x), 3 * sizeof(float));
                    p[3] = a->vis ? a->vis[(size_t)y * a->width + x] : 1.0f; /* environment visibility */
                }
        }
        ok = prw_image_upload(gpu, out, l, px, texels * 4 * sizeof(float), e);
    }
    free(px);
    return ok;
}

static bool upload(prw_gpu *gpu, prw_buffer *b, VkBufferUsageFlags usage, const void *data, size_t bytes, prw_error *e)
{
    return prw_buffer_create(gpu, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, PRW_MEM_GPU, b, e) &&
           prw_buffer_upload(gpu, b, 0, data, bytes, e);
}

bool prw_lightmap_gpu_create(prw_gpu *gpu, const prw_scene *s, const prw_lightmaps *lm, prw_lightmap_gpu **out,
                             prw_error *e)
{
    prw_lightmap_gpu *g = prw_calloc(1, sizeof *g);
    *out = g;
    bool active = false;
    for (uint32_t i = 0; lm && i < lm->instance_count; i++) {
        if (!check_instance(s, lm, i, e)) return false;
        active = active || lm->inst[i].mode != PRW_LIGHTMAP_NONE;
    }
    if (lm && lm->atlas_count > PRW_LIGHTMAP_MAX_ATLASES)
        return prw_fail(e, "light maps: %u atlases, at most %d", lm->atlas_count, PRW_LIGHTMAP_MAX_ATLASES);
    uint32_t W = 1, H = 1;
    if (!make_atlas(gpu, lm, active, &W, &H, &g->atlas, e)) return false;
    g->active = active;
    if (!active) return true;
    /* per (node, mesh of its group): which draw */
    g->node_first = prw_calloc(s->node_count ? s->node_count : 1, sizeof *g->node_first);
    uint32_t slots = 0;
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        uint32_t first, count;
        group_of(s, ni, &first, &count);
        g->node_first[ni] = slots;
        slots += count;
    }
    g->node_count = s->node_count;
    g->slot_count = slots;
    g->draw_of = prw_malloc((slots ? slots : 1) * sizeof *g->draw_of);
    for (uint32_t k = 0; k < slots; k++) g->draw_of[k] = -1;
    g->draws = prw_calloc(lm->instance_count, sizeof *g->draws);
    uint64_t nv = 0, ni_ = 0;
    for (uint32_t i = 0; i < lm->instance_count; i++)
        if (lm->inst[i].mode != PRW_LIGHTMAP_NONE) nv += lm->inst[i].vertex_count, ni_ += lm->inst[i].index_count;
    if (nv > INT32_MAX || ni_ > UINT32_MAX) return prw_fail(e, "light maps: too many vertices for one buffer");
    float *vd = prw_malloc((size_t)nv * PRW_VERTEX_FLOATS * sizeof(float));
    float *uv1 = prw_malloc((size_t)nv * PRW_UV1_FLOATS * sizeof(float));
    float *st = prw_malloc((size_t)nv * PRW_LIGHTMAP_STREAM_FLOATS * sizeof(float));
    uint32_t *id = prw_malloc((size_t)(ni_ ? ni_ : 1) * sizeof(uint32_t));
    uint64_t vo = 0, io = 0;
    for (uint32_t i = 0; i < lm->instance_count; i++) {
        const prw_lightmap_instance *in = &lm->inst[i];
        if (in->mode == PRW_LIGHTMAP_NONE) continue;
        uint32_t first, count;
        group_of(s, in->node, &first, &count);
        int32_t *slot = &g->draw_of[g->node_first[in->node] + (in->mesh - first)];
        if (*slot >= 0) {
            free(vd), free(uv1), free(st), free(id);
            return prw_fail(e, "light maps: instance %u: node %u / mesh %u given twice", i, in->node, in->mesh);
        }
        *slot = (int32_t)g->instance_count;
        const prw_mesh *m = &s->meshes[in->mesh];
        float sx = in->mode == PRW_LIGHTMAP_ATLAS ? (float)lm->atlases[in->atlas].width / (float)W : 0.0f;
        float sy = in->mode == PRW_LIGHTMAP_ATLAS ? (float)lm->atlases[in->atlas].height / (float)H : 0.0f;
        for (uint32_t k = 0; k < in->vertex_count; k++) {
            uint32_t src = in->source ? in->source[k] : k;
            size_t o = (size_t)(vo + k);
            prw_scene_gpu_vertex(m, src, vd + o * PRW_VERTEX_FLOATS);
            const float *u1 = m->uvs1 ? m->uvs1 : m->uvs; /* no TEXCOORD_1: set 0 (prw_shading.h) */
            uv1[2 * o] = u1 ? u1[2 * src] : 0.0f;
            uv1[2 * o + 1] = u1 ? u1[2 * src + 1] : 0.0f;
            float *p = st + PRW_LIGHTMAP_STREAM_FLOATS * o;
            if (in->mode == PRW_LIGHTMAP_ATLAS) {
                p[0] = in->uv[2 * k] * sx;
                p[1] = in->uv[2 * k + 1] * sy;
                p[2] = (float)in->atlas;
                p[3] = 0.0f;
            } else {
                memcpy(p, in->rgb + 3 * (size_t)k, 3 * sizeof(float));
                p[3] = 1.0f + (in->vis ? in->vis[k] : 1.0f); /* VERTEX mode, and its environment visibility */
            }
            p[4] = p[5] = p[6] = 0.0f, p[7] = -1.0f;
            if (in->mode == PRW_LIGHTMAP_VERTEX && in->cone) memcpy(p + 4, in->cone + 4 * (size_t)k, 4 * sizeof(float));
        }
        memcpy(id + io, in->indices ? in->indices : m->indices, in->index_count * sizeof(uint32_t));
        g->draws[g->instance_count++] = (prw_gpu_mesh){.first_index = (uint32_t)io, .index_count = in->index_count,
                                                       .vertex_offset = (int32_t)vo, .material = m->material};
        vo += in->vertex_count;
        io += in->index_count;
    }
    VkBufferUsageFlags vb = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    bool ok = upload(gpu, &g->vertices, vb, vd, (size_t)nv * PRW_VERTEX_FLOATS * sizeof(float), e) &&
              upload(gpu, &g->uv1, vb, uv1, (size_t)nv * PRW_UV1_FLOATS * sizeof(float), e) &&
              upload(gpu, &g->stream, vb, st, (size_t)nv * PRW_LIGHTMAP_STREAM_FLOATS * sizeof(float), e) &&
              upload(gpu, &g->indices, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, id, (size_t)(ni_ ? ni_ : 1) * sizeof(uint32_t), e);
    free(vd), free(uv1), free(st), free(id);
    return ok;
}

void prw_lightmap_gpu_destroy(prw_gpu *gpu, prw_lightmap_gpu *g)
{
    if (!g) return;
    prw_image_destroy(gpu, &g->atlas);
    prw_buffer_destroy(gpu, &g->vertices);
    prw_buffer_destroy(gpu, &g->uv1);
    prw_buffer_destroy(gpu, &g->stream);
    prw_buffer_destroy(gpu, &g->indices);
    free(g->draws);
    free(g->draw_of);
    free(g->node_first);
    free(g);
}

const prw_gpu_mesh *prw_lightmap_gpu_draw(const prw_lightmap_gpu *g, const prw_scene *s, uint32_t node, uint32_t mesh)
{
    if (!g || !g->active || node >= s->node_count || node >= g->node_count) return NULL;
    uint32_t first, count;
    if (!group_of(s, node, &first, &count) || mesh < first || mesh >= first + count) return NULL;
    uint32_t slot = g->node_first[node] + (mesh - first);
    int32_t d = slot < g->slot_count ? g->draw_of[slot] : -1;
    return d >= 0 ? &g->draws[d] : NULL;
}
