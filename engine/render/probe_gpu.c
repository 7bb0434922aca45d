/* probe_gpu — reflection probes on the GPU (prw_probe_gpu.h). */
#include "prw_probe_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_env.h"
#include "prw_env_gpu.h"
#include "scene_gpu.h"

#define DFG_N 32u

static bool check(const prw_scene *s, const prw_probes *d, prw_error *e)
{
    if (d->count > PRW_GPU_MAX_PROBES || d->levels < 2 || d->levels > 64 || d->height < 1 || d->height > 1024 ||
        !d->levels_rgb)
        return prw_fail(e, "probes: %u probes of %u levels of height %u out of range", d->count, d->levels, d->height);
    for (int c = 0; c < 3; c++)
        if (!isfinite(d->parallax_min[c]) || !isfinite(d->parallax_max[c])) return prw_fail(e, "probes: parallax box not finite");
    for (uint32_t i = 0; i < d->count; i++) {
        const prw_probe_desc *p = &d->probe[i];
        if (p->material < 0 || (uint32_t)p->material >= s->material_count)
            return prw_fail(e, "probes: probe %u names material %d (scene has %u)", i, p->material, s->material_count);
        for (int c = 0; c < 3; c++)
            if (!isfinite(p->centre[c]) || !isfinite(p->box_min[c]) || !isfinite(p->box_max[c]))
                return prw_fail(e, "probes: probe %u: a position is not finite", i);
    }
    size_t n = (size_t)d->count * d->levels * d->height * 2 * d->height * 3;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(d->levels_rgb[i]) || d->levels_rgb[i] < 0) return prw_fail(e, "probes: a texel is not finite or negative");
    return true;
}

bool prw_probe_gpu_create(prw_gpu *gpu, const prw_scene *s, const prw_probes *d, uint32_t max_count,
                          prw_probe_gpu **out, prw_error *e)
{
    prw_probe_gpu *g = prw_calloc(1, sizeof *g);
    *out = g;
    if (d && d->count == 0) d = NULL;
    if (d && !check(s, d, e)) return false;
    uint32_t count = d ? (d->count < max_count ? d->count : max_count) : 0;
    if (count == 0) d = NULL;
    prw_gpu_probes u;
    memset(&u, 0, sizeof u);
    if (d) {
        u.head[0] = (float)count, u.head[1] = (float)d->levels, u.head[2] = (float)d->height;
        for (int c = 0; c < 3; c++) u.pmin[c] = d->parallax_min[c], u.pmax[c] = d->parallax_max[c];
        for (uint32_t i = 0; i < count; i++) {
            const prw_probe_desc *p = &d->probe[i];
            for (int c = 0; c < 3; c++)
                u.p[i][0][c] = p->centre[c], u.p[i][1][c] = p->box_min[c], u.p[i][2][c] = p->box_max[c];
            u.p[i][0][3] = (float)(prw_scene_gpu_slot(s, p->material) + 1); /* material_gltf.glsl mat.extra.y */
        }
    }
    uint32_t H = d ? d->height : 1, W = 2 * H, layers = d ? count * d->levels : 1, N = d ? DFG_N : 1;
    if (!prw_buffer_create(gpu, sizeof u, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           PRW_MEM_GPU, &g->buf, e) ||
        !prw_buffer_upload(gpu, &g->buf, 0, &u, sizeof u, e) ||
        !prw_env_gpu_rgb_layers(gpu, W, H, layers, d ? d->levels_rgb : NULL, &g->levels, e) ||
        !prw_env_gpu_rg_image(gpu, N, N, &g->dfg, e))
        return prw_fail_wrap(e, "probes");
    bool ok = true;
    float *tab = prw_calloc((size_t)N * N * 2, sizeof(float));
    for (uint32_t j = 0; d && j < N; j++) /* texel (x = i: mu, y = j: roughness), as prw_env_gpu.h */
        for (uint32_t i = 0; i < N; i++) {
            double A, B;
            prw_env_dfg((i + 0.5) / N, (double)j / (N - 1), &A, &B);
            tab[2 * ((size_t)j * N + i)] = (float)A, tab[2 * ((size_t)j * N + i) + 1] = (float)B;
        }
    ok = ok && prw_image_upload(gpu, &g->dfg, 0, tab, (size_t)N * N * 2 * sizeof(float), e);
    free(tab);
    g->active = ok && d != NULL;
    g->count = g->active ? count : 0;
    return ok;
}

void prw_probe_gpu_destroy(prw_gpu *gpu, prw_probe_gpu *g)
{
    if (!g) return;
    prw_buffer_destroy(gpu, &g->buf);
    prw_image_destroy(gpu, &g->levels);
    prw_image_destroy(gpu, &g->dfg);
    free(g);
}
