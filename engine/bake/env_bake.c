/* prw_env_bake — the scene's environment through the "env" cache (see the header). */
#include "prw_env_bake.h"

#include <stdlib.h>
#include <string.h>

#include "prw_image.h"

bool prw_env_bake(const prw_environment *env, uint32_t envmap_size, prw_env_data *out, bool *from_cache, char *warning,
                  size_t warning_cap, prw_error *e)
{
    memset(out, 0, sizeof *out);
    *from_cache = false;
    if (!env->present) return prw_fail(e, "environment bake: scene has no environment");
    prw_env_params p = {envmap_size, 0, 0, 0};
    if (!env->file[0]) {
        /* 64 x 32: the SH projection's midpoint rule makes E = pi L to 3e-5 there */
        float *rgb = prw_malloc(64 * 32 * 3 * sizeof(float));
        for (int k = 0; k < 64 * 32; k++)
            for (int c = 0; c < 3; c++) rgb[3 * k + c] = env->uniform[c];
        uint64_t h = prw_hash64(env->uniform, sizeof env->uniform, 0x756e69666f726dull);
        bool ok = prw_env_cached(rgb, 64, 32, 1.0, 0.0, h, &p, out, from_cache, warning, warning_cap, e);
        free(rgb);
        return ok;
    }
    prw_exr_read_opts o = {0};
    o.reject_nonfinite = true;
    o.extra_bytes_per_pixel = 3 * sizeof(float);
    prw_image img = {0};
    if (!prw_exr_read(env->file, &o, &img, e)) return false;
    uint32_t w = (uint32_t)img.width, h = (uint32_t)img.height;
    size_t np = (size_t)w * h;
    float *rgb = prw_malloc(np * 3 * sizeof(float));
    for (size_t k = 0; k < np; k++)
        for (int c = 0; c < 3; c++) rgb[3 * k + c] = img.rgba[4 * k + c];
    prw_image_free(&img);
    bool ok = prw_env_cached(rgb, w, h, env->scale, env->rotation, env->file_hash,
                             &p, out, from_cache, warning, warning_cap, e);
    free(rgb);
    if (!ok) return prw_fail_wrap(e, "%s", env->file);
    return true;
}
