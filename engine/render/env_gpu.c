/* env_gpu — the environment light on the GPU (prw_env_gpu.h). */
#include "prw_env_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

static bool make_image(prw_gpu *gpu, uint32_t w, uint32_t h, uint32_t layers, VkFormat f, prw_gpu_image *out,
                       prw_error *e)
{
    prw_image_desc d = {.width = w, .height = h, .layers = layers, .format = f,
                        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                        .view_type = VK_IMAGE_VIEW_TYPE_2D_ARRAY};
    return prw_image_create(gpu, &d, out, e);
}

bool prw_env_gpu_rgb_layers(prw_gpu *gpu, uint32_t w, uint32_t h, uint32_t layers, const float *rgb,
                            prw_gpu_image *out, prw_error *e)
{
    if (!make_image(gpu, w, h, layers, VK_FORMAT_R32G32B32A32_SFLOAT, out, e)) return false;
    size_t texels = (size_t)w * h;
    float *px = prw_calloc(texels * 4, sizeof(float));
    bool ok = true;
    for (uint32_t k = 0; k < layers && ok; k++) {
        for (size_t t = 0; rgb && t < texels; t++) {
            memcpy(px + 4 * t, rgb + ((size_t)k * texels + t) * 3, 3 * sizeof(float));
            px[4 * t + 3] = 1.0f;
        }
        ok = prw_image_upload(gpu, out, k, px, texels * 4 * sizeof(float), e);
    }
    free(px);
    return ok;
}

bool prw_env_gpu_rg_image(prw_gpu *gpu, uint32_t w, uint32_t h, prw_gpu_image *out, prw_error *e)
{
    return make_image(gpu, w, h, 1, VK_FORMAT_R32G32_SFLOAT, out, e);
}

bool prw_env_gpu_create(prw_gpu *gpu, const prw_env_data *d, prw_env_gpu **out, prw_error *e)
{
    prw_env_gpu *g = prw_calloc(1, sizeof *g);
    *out = g;
    prw_gpu_env u;
    memset(&u, 0, sizeof u);
    if (d) {
        if (d->height < 1 || d->height > 16384 || d->levels < 1 || d->levels > 64 || d->dfg_size < 2 ||
            d->dfg_size > 256 || !d->maps || !d->dfg)
            return prw_fail(e, "environment: levels %u of height %u or table size %u out of range", d->levels,
                            d->height, d->dfg_size);
        size_t level_floats = (size_t)d->height * 2 * d->height * 3;
        if (!all_finite(&d->sh[0][0], 27) || !all_finite(d->dfg, 2 * (size_t)d->dfg_size * d->dfg_size) ||
            !all_finite(d->maps, level_floats * d->levels) || !isfinite(d->rotation))
            return prw_fail(e, "environment: a value is not finite");
        for (int i = 0; i < 9; i++)
            for (int c = 0; c < 3; c++) u.sh[i][c] = d->sh[i][c];
        u.rot[0] = (float)cos(d->rotation), u.rot[1] = (float)sin(d->rotation);
        u.rot[2] = (float)d->levels, u.rot[3] = (float)d->height;
    }
    uint32_t H = d ? d->height : 1, W = d ? 2 * d->height : 1, K = d ? d->levels : 1, N = d ? d->dfg_size : 1;
    if (!prw_buffer_create(gpu, sizeof u, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                           PRW_MEM_GPU, &g->ubo, e) ||
        !prw_buffer_upload(gpu, &g->ubo, 0, &u, sizeof u, e) ||
        !prw_env_gpu_rgb_layers(gpu, W, H, K, d ? d->maps : NULL, &g->levels, e) ||
        !prw_env_gpu_rg_image(gpu, N, N, &g->dfg, e))
        return false;
    bool ok = true;
    /* the file's table is i-major (i: mu, j: roughness): texel (x = i, y = j) */
    float *tab = prw_calloc((size_t)N * N * 2, sizeof(float));
    for (uint32_t i = 0; d && i < N; i++)
        for (uint32_t j = 0; j < N; j++) {
            tab[2 * ((size_t)j * N + i)] = d->dfg[2 * ((size_t)i * N + j)];
            tab[2 * ((size_t)j * N + i) + 1] = d->dfg[2 * ((size_t)i * N + j) + 1];
        }
    ok = ok && prw_image_upload(gpu, &g->dfg, 0, tab, (size_t)N * N * 2 * sizeof(float), e);
    free(tab);
    g->active = ok && d != NULL;
    return ok;
}

void prw_env_gpu_destroy(prw_gpu *gpu, prw_env_gpu *g)
{
    if (!g) return;
    prw_buffer_destroy(gpu, &g->ubo);
    prw_image_destroy(gpu, &g->levels);
    prw_image_destroy(gpu, &g->dfg);
    free(g);
}
