/* walk_measure — "how far off is what I see": the walkthrough's current pose rendered by the
 * rasterizer (the walk's own quality settings) and by the reference path tracer at a small size,
 * compared with the project's metrics (LDR-FLIP with the frozen metric tone map at the view's
 * exposure).  Two independent references of spp samples each (seeds 1 and 2), as `prw compare REF1
 * TEST --ref2 REF2` takes them: the error is the raster against the first, the noise the second
 * against the first, so the HUD can say how far the error is beyond the reference's own noise.
 * Blocking (seconds); the walk triggers it on demand ([R] or a script's key R). */
#ifndef PRW_WALK_MEASURE_H
#define PRW_WALK_MEASURE_H

#include "prw_render.h"

typedef struct walk_measure {
    bool have;
    uint32_t width, height; /* measured image */
    uint64_t spp;           /* reference samples per pixel (each of the two) */
    double ldr_flip;        /* raster vs reference (seed 1), mean LDR-FLIP */
    double noise_flip;      /* reference seed 2 vs seed 1: the reference's noise */
    double beyond_noise;    /* max(0, ldr_flip - noise_flip) */
    bool below_noise;       /* ldr_flip < 2 noise_flip ("below reference noise", as prw compare says) */
    double seconds;         /* wall time of the measurement */
    double when;            /* prw_now() when it finished */
} walk_measure;

/* v: the current view (any size; measured at `width` pixels wide, same frustum); desc: the walk's
 * render settings (size ignored); threads: the --threads budget (0 = prw_threads_get()). */
bool walk_measure_run(prw_gpu *gpu, const prw_scene *scene, const prw_view *v, const prw_render_desc *desc,
                      uint32_t width, uint64_t spp, int threads, walk_measure *out, prw_error *e);

#endif
