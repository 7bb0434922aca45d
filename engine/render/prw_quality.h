/* prw_quality — the ONE quality-knob struct of DESIGN.md §5, its named presets, and the parsers of
 * `--preset NAME`, `--vs CONFIG` and `--sweep SPEC`.
 *
 * Promises:
 *  - Every knob has a name (the spelling on the command line), a range, and a flag saying whether
 *    the renderer uses it yet.  Knobs marked "no effect yet" are carried through configs, sweeps and
 *    output files unchanged, so later issues only have to switch them on.
 *  - Presets low / medium / high / ultra are points in this space (prw_quality_preset()); the
 *    default (prw_quality_default()) is "high".
 *  - A config string is an optional preset name followed by knob assignments, separated by ';' or
 *    ',': "ultra", "msaa=1", "low;shadow_size=2048", "msaa=1,shadow_size=512".
 *  - A sweep spec is knob ranges separated by ';', values by ',': "msaa=1,4;shadow_size=512,1024,2048";
 *    it expands to the Cartesian product, the first knob varying slowest, applied to a base config.
 *  - Errors are one line in prw_error naming the offending text and the accepted values.
 *  - The renderer takes the struct as it is (prw_render_desc.quality); the commands build it with
 *    the same syntax everywhere (app/: --preset CONFIG and the knob shorthands).
 */
#ifndef PRW_QUALITY_H
#define PRW_QUALITY_H

#include "prw_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Pixel-changing reuse between the eyes of a two-view frame (issue 5; the knob stereo_reuse). */
typedef enum prw_stereo_reuse {
    PRW_STEREO_REUSE_OFF = 0,       /* both eyes fully shaded */
    PRW_STEREO_REUSE_REPROJECT = 1, /* right eye reuses the left eye's colour where the left eye saw the same
                                       surface; only the rest is shaded (pass_reproject.c; per-view loop only) */
} prw_stereo_reuse;
/* "off" -> 0, "reproject" -> 1 (the knob stereo_reuse by name); false for anything else. */
bool prw_stereo_reuse_parse(const char *text, double *out);

typedef struct prw_quality {
    /* used by the renderer */
    uint32_t msaa;             /* 1 or 4 samples per pixel, resolved in linear HDR */
    uint32_t shadow_size;      /* shadow-map resolution, texels a side */
    uint32_t soft_shadows;     /* rect lights' shadows: 0 = hard (one 3x3 PCF lookup at the rectangle's centre);
                                  N = 2..8: soft (shadows.glsl: N x N blocker-search gathers and max(2, N - 1)^2
                                  filter taps sized by the rectangle and the blocker / receiver depths) */
    uint32_t supersample;      /* N x N supersampling (box filter in linear HDR) */
    uint32_t tonemap;          /* tone-mapping operator (prw_tm_op; on the command line also by name) */
    uint32_t stereo_reuse;     /* prw_stereo_reuse: off (0) | reproject (1); changes pixels, FLIP reported by
                                  `prw bench --views 2` (issue 5) */
    uint32_t radiance_bits;     /* 32: radiance targets in float32 (no clipping at 65504 cd/m^2: 1e-4 .. 1e9+ in one
                                   view); 16: half floats (cheaper, clips) */
    double lod_pixel_tolerance; /* NURBS LOD: screen-space geometric error, pixels, of every model whose
                                   manifest entry sets no tol_px */
    uint32_t emissive_lights;   /* emissive meshes: at most this many area lights (polygons; more are merged
                                   into rectangles or dropped, engine/scene/prw_emissive.h); 0: they light nothing */
    uint32_t mirror_recursion;  /* planar mirrors (pass_mirror.c): reflection bounces rendered; 0: the pass is off,
                                   1: one (mirrors seen in a mirror show no reflection of their own) */
    double glossy_max_roughness; /* planar reflectors (pass_mirror.c): the largest roughness of a planar material
                                   reflected through the mirror image convolved by its GGX lobe; at or below
                                   0.05 only sharp mirrors are reflected */
    uint32_t kernel_taps;       /* taps of the glossy reflectors' convolution (pass_mirror.c) */
    uint32_t max_reflectors;    /* planar reflectors (pass_mirror.c): at most this many reflected per view, those
                                   covering the most pixels, each with its own mirror image (1..4) */
    double mirror_scale;        /* planar reflectors (pass_mirror.c): the mirror images' resolution as a fraction of
                                   the view's (1, 0.5, 0.25, ...; 0.125..1), upsampled bilinearly where added */
    double glossy_scale;        /* glossy planar reflectors (pass_mirror.c): their mirror image and its convolution
                                   at this fraction of mirror_scale's resolution (0.125..1), the convolved image
                                   upsampled bilinearly where added; sharp mirrors keep mirror_scale's */
    double reflection_skip;     /* planar reflectors (pass_mirror.c): a reflector is not reflected in a view when its
                                   estimated reflection is below this share of its own radiance (Meseth §11.3:
                                   0.05); 0: always reflected */
    uint32_t gi_lookups;        /* 1: the base pass reads the baked light maps, the environment term and the
                                   reflection probes when the renderer is given them; 0: it is given none of them
                                   (pipelines, images and the sky exactly as without them): with mirror_recursion
                                   0, the frame without GI */
    uint32_t probe_count;       /* reflection probes (engine/bake/prw_probe.h): at most this many curved glossy
                                   objects get one (0: none, the probe term off) */
    uint32_t probe_size;        /* reflection probes: rows of a probe's gathered map (width 2x; the prefiltered
                                   levels have half as many) */
    /* no effect yet (the features arrive with later issues) */
    uint32_t btf_clusters;      /* BTF: clusters */
    uint32_t btf_components;    /* BTF: components per cluster */
    uint32_t ssdo_samples;      /* SSDO: samples per pixel */
    double ssdo_radius;         /* SSDO: radius, metres */
    uint32_t vpl_count;         /* VPLs for indirect light */
    uint32_t ism_size;          /* imperfect shadow map size, texels a side */
    uint32_t envmap_size;       /* environment map size, texels (height) */
    double billboard_error;     /* billboard clouds: error, pixels */
    uint32_t radiosity_size;    /* radiosity texture size, texels a side */
    /* hidden test knob: extra GPU work as a fraction of the frame (A/B calibration); 0 = off */
    double extra_gpu_work;
} prw_quality;

typedef enum prw_knob_type { PRW_KNOB_U32 = 0, PRW_KNOB_F64 } prw_knob_type;

typedef struct prw_knob_info {
    const char *name;
    prw_knob_type type;
    size_t offset;       /* into prw_quality */
    double min, max;
    bool implemented;    /* false: "no effect yet" */
    bool hidden;         /* test knobs: accepted, not listed in help */
    const char *help;
} prw_knob_info;

/* The knob table, in struct order. */
const prw_knob_info *prw_quality_knobs(uint32_t *count);
const prw_knob_info *prw_quality_find_knob(const char *name);
double prw_quality_get(const prw_quality *q, const prw_knob_info *k);
/* Sets a knob after checking its range (and msaa in {1, 4}); value names the text for messages. */
bool prw_quality_set(prw_quality *q, const prw_knob_info *k, double value, prw_error *e);

prw_quality prw_quality_default(void); /* = preset "high": what every command uses unless told */
/* Every knob within its range (msaa 1 or 4); the error names the first one that is not. */
bool prw_quality_validate(const prw_quality *q, prw_error *e);
/* "low" | "medium" | "high" | "ultra"; false with a one-line error otherwise. */
bool prw_quality_preset(const char *name, prw_quality *out, prw_error *e);
/* Parses a config string (see above) on top of base. */
bool prw_quality_parse_config(const char *text, const prw_quality *base, prw_quality *out, prw_error *e);

/* Expands a sweep spec over base; *out (free()) receives *count configs (at most 4096). */
bool prw_quality_parse_sweep(const char *spec, const prw_quality *base, prw_quality **out, uint32_t *count,
                             prw_error *e);

/* "msaa=4;shadow_size=1024;...": every knob in table order (hidden ones only when non-zero), values
 * printed so that prw_quality_parse_config() gives back the same struct. */
void prw_quality_format(const prw_quality *q, char *buf, size_t cap);
/* Only the knobs that differ from `base` ("" when none). */
void prw_quality_format_diff(const prw_quality *q, const prw_quality *base, char *buf, size_t cap);

/* Help text: one line per visible knob with its range and "no effect yet" where true. */
void prw_quality_describe(char *buf, size_t cap);

#ifdef __cplusplus
}
#endif
#endif
