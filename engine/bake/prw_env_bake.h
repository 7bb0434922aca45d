/* prw_env_bake — the environment-light bake step of a scene: decodes the scene's environment
 * (prw_environment: an equirectangular EXR, or a uniform radiance) and gets its precomputation
 * (materials/env/prw_env_file.h: SH irradiance, prefiltered specular levels, split-sum table) from
 * the cache, kind "env", building and storing it on a miss.
 *
 * Promises:
 *  - The EXR is read with non-finite pixels rejected (prw_exr_read_opts.reject_nonfinite); its bytes'
 *    hash (prw_environment.file_hash, set by the loader), scale, rotation and envmap_size (the
 *    quality knob, engine/render/prw_quality.h: the levels' height) are in the key, with the
 *    algorithm and format versions.
 *  - A uniform environment (file "") is baked from a 64 x 32 map of its radiance (scale 1), keyed by
 *    the hash of its three floats.
 *  - A scene without an environment is an error ("scene has no environment"): callers skip the step.
 *  - Cache trouble is a warning in `warning` (may be NULL), never a failure.  Nothing prints.
 */
#ifndef PRW_ENV_BAKE_H
#define PRW_ENV_BAKE_H

#include "prw_env_file.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

bool prw_env_bake(const prw_environment *env, uint32_t envmap_size, prw_env_data *out, bool *from_cache, char *warning,
                  size_t warning_cap, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
