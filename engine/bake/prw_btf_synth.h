/* prw_btf_synth — synthetic BTFs with exact ground truth (issue "BTF materials"): a procedural
 * micro-geometry (a height field, or flakes over a plane, with the project's analytic materials)
 * measured by the project's path tracer (prw_ref_trace_rays: self-shadowing, masking and
 * interreflection) on the Bonn 81 x 81 directions (prw_btf_dirs_ubo81).
 *
 * Measurement (what a value means): the sample lies in the plane z = 0 of its frame (x, y along the
 * texture, z the normal; in the scene x -> world X, z -> world Y, y -> world -Z), one texel = `texel_m`
 * metres.  For view v and light l, texel (x, y) holds the radiance leaving the micro-geometry towards
 * direction v, averaged over the texel's square on the reference plane (orthographic rays through
 * stratified points of the square, `rays` x `rays` of them, `spp` samples each), under a directional
 * light from direction l of 1 lux at normal incidence, with nothing else in the world: a reflectance
 * factor in 1/sr that includes the cosine of the light's angle (the renderer multiplies it by the
 * light's normal illuminance).  Rays that leave the modelled patch (the tile plus a margin that holds
 * every shadow and view ray of 75 degrees) see black.
 *
 * Presets (fixed: the must-show 0):
 *  - fabric:  plain weave, period 8 texels, round yarns of width and height half the period (the relief
 *             is half the period), warp red, weft beige, rough dielectric; periodic, so one period is
 *             measured and tiled (exact: the geometry repeats);
 *  - leather: smooth bumps (periodic value noise of 16- and 4-texel scales, relief 0.6 texel), brown,
 *             roughness 0.45;
 *  - flakes:  a dark blue coated paint (clear coat, GGX alpha 0.05) with 2 % of the texels holding a
 *             1-texel metallic flake tilted up to 15 degrees from the normal, under the same coat
 *             (the coat follows each facet: no refraction through a flat coat layer);
 *  - brushed: aluminium (metallic 1, roughness 0.25) with grooves along x (one per texel row, random
 *             depth 0..0.15 texel).
 * prw_btf_synthesize is deterministic (seed) and independent of the thread count.
 */
#ifndef PRW_BTF_SYNTH_H
#define PRW_BTF_SYNTH_H

#include <stdbool.h>
#include <stdint.h>

#include "prw_btf.h"
#include "prw_core.h"
#include "prw_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum prw_btf_synth_kind {
    PRW_BTF_SYNTH_FABRIC = 0,
    PRW_BTF_SYNTH_LEATHER,
    PRW_BTF_SYNTH_FLAKES,
    PRW_BTF_SYNTH_BRUSHED,
    PRW_BTF_SYNTH_COUNT
} prw_btf_synth_kind;

typedef struct prw_btf_synth_params {
    prw_btf_synth_kind kind;
    uint32_t size;     /* texels a side (>= 1) */
    uint32_t rays;     /* stratified positions per texel side (0: 1, the texel centre) */
    uint32_t spp;      /* samples per position (0: 1; direct light is exact per sample) */
    uint32_t dirs;     /* 81: the Bonn set; fewer: its first `dirs` directions (tests) */
    double texel_m;    /* texel size in metres (default 1e-4) */
    uint64_t seed;
    int threads;       /* 0: prw_threads_get() */
    void (*progress)(void *user, double fraction);
    void *user;
} prw_btf_synth_params;

/* "fabric" ... "brushed" -> kind; false for another name. */
bool prw_btf_synth_parse(const char *name, prw_btf_synth_kind *out);
const char *prw_btf_synth_name(prw_btf_synth_kind k);

bool prw_btf_synthesize(const prw_btf_synth_params *p, prw_btf *out, prw_error *e);

/* The micro-geometry prw_btf_synthesize measures (preset kind, tile `size` texels, `seed`), as a scene
 * of meshes and materials only (no light, no camera): the texels [x0, x1] x [y0, y1] of the sample's
 * frame at texel_m metres each (x -> world X, y -> world -Z, height -> world Y; the reference plane is
 * Y = 0).  For rendering it directly (the BTF kind's test against its own micro-geometry). */
bool prw_btf_synth_scene(prw_btf_synth_kind kind, uint32_t size, double texel_m, uint64_t seed, double x0, double x1,
                         double y0, double y1, prw_scene **out, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
