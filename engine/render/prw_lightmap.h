/* prw_lightmap — the baked indirect-diffuse light maps as the renderer takes them (issue 16,
 * DESIGN.md §4): filled by app/ from the GI baker's result (engine/bake/prw_gi.h; the renderer never
 * links the baker), handed to prw_renderer_create through prw_render_desc.lightmaps.
 *
 * What the renderer does with it (shaders/gi_lightmap.glsl): every instance with a mode other than
 * NONE is drawn with the light-map shader variant, which adds to the base pass
 *   L_idl = (1 - metallic) base / pi x (1 - e(mu_o)) / (1 - e_avg) x E_ind
 * (prw_gi.h; prw_brdf_diffuse_terms of materials/prw_brdf.h with the incoming albedo terms 0), E_ind
 * from the atlas by a bicubic B-spline (four bilinear taps) in ATLAS mode, or interpolated from the
 * vertices in VERTEX mode.  Without light maps (desc.lightmaps NULL or no instance with a mode) the
 * base pass runs exactly the shaders of before.
 *
 * Promises (checked at prw_renderer_create, one error naming the instance or atlas):
 *  - instances refer to drawn (node, mesh) pairs of the scene (mesh in the node's group);
 *  - ATLAS: atlas < atlas_count, uv 2 per drawn vertex in [0, 1] (normalised to that atlas: texel
 *    (i, j) centred at ((i + 0.5) / width, (j + 0.5) / height)), source / indices as below;
 *  - VERTEX: rgb 3 per drawn vertex (E_ind, finite, >= 0);
 *  - drawn vertices: vertex_count, each a copy of mesh vertex source[k] (source NULL: k itself,
 *    vertex_count = the mesh's); indices: index_count = the mesh's index count, into the drawn
 *    vertices (NULL: the mesh's own indices);
 *  - atlases: RGB float per texel, finite, >= 0; at most PRW_LIGHTMAP_MAX_ATLASES, each at most
 *    4096 texels a side.  The renderer copies what it needs at create (nothing is kept).
 *  - vis (atlas texels, VERTEX vertices; NULL = 1): the environment visibility the environment term
 *    (prw_env_gpu.h) multiplies by, in [0, 1]; it rides in the atlas's alpha channel and in the
 *    VERTEX stream's w (1 + vis); the atlases' open cones in layers atlas_count.. of the same array.
 */
#ifndef PRW_LIGHTMAP_H
#define PRW_LIGHTMAP_H

#include <stdint.h>

#include "prw_constants.h"

#define PRW_LIGHTMAP_MAX_ATLASES 128

typedef enum prw_lightmap_mode {
    PRW_LIGHTMAP_NONE = 0,
    PRW_LIGHTMAP_ATLAS = 1,
    PRW_LIGHTMAP_VERTEX = 2,
} prw_lightmap_mode;

typedef struct prw_lightmap_instance {
    uint32_t node, mesh;
    uint32_t mode;            /* prw_lightmap_mode */
    uint32_t atlas;           /* ATLAS */
    uint32_t vertex_count;    /* drawn vertices */
    const uint32_t *source;   /* mesh vertex of each drawn vertex; NULL: identity */
    const float *uv;          /* ATLAS: 2 per drawn vertex */
    const float *rgb;         /* VERTEX: 3 per drawn vertex */
    const float *vis;         /* VERTEX: 1 per drawn vertex, environment visibility in [0, 1]; NULL: 1 */
    const float *cone;        /* VERTEX: 4 per drawn vertex, the open cone (b, f) (engine/bake/prw_gi.h); NULL: none */
    uint32_t index_count;     /* = the mesh's */
    const uint32_t *indices;  /* into the drawn vertices; NULL: the mesh's */
} prw_lightmap_instance;

typedef struct prw_lightmap_atlas {
    uint32_t width, height;
    const float *rgb; /* 3 per texel, row-major */
    const float *vis; /* 1 per texel, environment visibility in [0, 1] (engine/bake/prw_gi.h); NULL: 1 */
    const float *cone; /* 4 per texel, the open cone (b, f) of prw_gi.h, finite, f in [0, 1]; NULL: none (the
                          specular part then takes vis) */
} prw_lightmap_atlas;

typedef struct prw_lightmaps {
    uint32_t atlas_count;
    const prw_lightmap_atlas *atlases;
    uint32_t instance_count;
    const prw_lightmap_instance *inst;
} prw_lightmaps;

/* Which terms the base pass draws: prw_render_desc.terms, PRW_TERM_* bits of shaders/prw_constants.h
 * (0 = PRW_TERM_ALL), for comparing one term with the reference's light-path filter (`prw render --term`). */

#endif
