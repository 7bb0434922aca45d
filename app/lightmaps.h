/* lightmaps — the baked indirect diffuse of a scene for the drawing commands (app/lightmaps.c; also
 * linked by tests/render): which scenes get a bake, bake on a cache miss with progress on stderr, and
 * the conversion of the baker's result (engine/bake/prw_gi.h) into what the renderer takes
 * (engine/render/prw_lightmap.h).
 *
 * A scene gets a bake when it has static meshes and something emits light (a light, an emissive
 * material, an environment); the bake's options are the quality's radiosity_size with the baker's
 * defaults otherwise — the cache entry `prw bake SCENE --gi` makes. */
#ifndef PRW_APP_LIGHTMAPS_H
#define PRW_APP_LIGHTMAPS_H

#include <stddef.h>

#include "prw_env_file.h"
#include "prw_gi.h"
#include "prw_lightmap.h"
#include "prw_probe.h"
#include "prw_probe_gpu.h"
#include "prw_quality.h"
#include "prw_scene.h"

typedef struct prw_app_lightmaps prw_app_lightmaps;
/* Whether s gets a bake; why: a short reason either way. */
bool prw_app_lightmaps_wanted(const prw_scene *s, const char **why);
/* Whether the bake of s for q is in the cache (path: its file either way, when the cache has a place). */
bool prw_app_lightmaps_cached(const prw_scene *s, const prw_quality *q, char *path, size_t cap);
/* For the command `cmd`: *out = NULL with no_bake (one line on stderr saying so) or for a scene without
 * a bake; else the cached bake, or one built first with a progress bar on stderr. */
bool prw_app_lightmaps_prepare(const char *cmd, const prw_scene *s, const prw_quality *q, bool no_bake,
                               prw_app_lightmaps **out, prw_error *e);
/* Takes ownership of b (freed on failure too). */
bool prw_app_lightmaps_from_bake(const prw_scene *s, prw_gi_bake *b, prw_app_lightmaps **out, prw_error *e);
/* What prw_render_desc.lightmaps takes (NULL for NULL or no GI bake); valid while a lives. */
const prw_lightmaps *prw_app_lightmaps_get(const prw_app_lightmaps *a);
/* What prw_render_desc.environment takes: the scene's environment precomputation (materials/env, through
 * the "env" cache at the quality's envmap_size; prepare makes it with the GI bake, and skips it with
 * no_bake / PRW_NO_BAKE), NULL when none; valid while a lives. */
const prw_env_data *prw_app_lightmaps_env(const prw_app_lightmaps *a);
/* What prw_render_desc.probes takes: the reflection probes (engine/bake/prw_probe.h, the "probe" cache; prepare
 * bakes them after the light maps unless the quality's probe_count is 0), NULL when none; valid while a lives. */
const prw_probes *prw_app_lightmaps_probes(const prw_app_lightmaps *a);
/* The probe bake's options for quality q (what `prw bake SCENE --gi` and prepare use). */
prw_probe_options prw_app_probe_options(const prw_quality *q);
/* The renderer's view of a probe bake (pointing into b: valid while b lives). */
void prw_app_probes_from_bake(const prw_probe_bake *b, prw_probes *out);
void prw_app_lightmaps_destroy(prw_app_lightmaps *a);

#endif
