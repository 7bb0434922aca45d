/* render_internal — the renderer object, shared by renderer.c and the public calls implemented next to
 * what they drive (tonemap_gpu.c).  Passes never see it: they get prw_render_env and the frame. */
#ifndef PRW_RENDER_INTERNAL_H
#define PRW_RENDER_INTERNAL_H

#include "gpu_types.h"
#include "graph.h"
#include "lightmap_gpu.h"
#include "prw_env_gpu.h"
#include "prw_probe_gpu.h"
#include "pipes.h"
#include "prw_glare.h"
#include "prw_render.h"
#include "scene_gpu.h"
#include "shadow_plan.h"
#include "tonemap_gpu.h"

struct prw_renderer {
    prw_gpu *gpu;
    const prw_scene *scene;
    prw_render_desc desc;
    prw_render_debug debug; /* a copy of *desc.debug (desc.debug points here) */
    prw_compose_params compose; /* a copy of *desc.compose (desc.compose points here) */
    prw_glare_settings glare;   /* a copy of *desc.glare */
    prw_render_env env;
    prw_desc_pool *pool;
    prw_pipes *pipes;
    prw_scene_gpu *sg;
    prw_lightmap_gpu *lm;
    prw_env_gpu *envlight; /* the environment light (prw_env_gpu.h), never NULL after create */
    prw_probe_gpu *probes; /* the reflection probes (prw_probe_gpu.h), never NULL after create */
    prw_shadow_plan plan;
    prw_emissive_lights emissive; /* the emissive meshes' area lights (the plan takes them while slots are left) */
    prw_tm_gpu *tm;
    prw_drawables drawables;
    prw_graph *graph;
    /* per-view globals (shaders/common.glsl), written by the host before each frame */
    prw_buffer globals[PRW_MAX_VIEWS];
    VkDescriptorSet globals_set[PRW_MAX_VIEWS];
    prw_timer *timer;
    prw_frame_stats last;
};

#endif
