/* walk_measure — "how far off is what I see": the walkthrough's current pose rendered by the
 * rasterizer (the walk's own quality settings) and by the reference path tracer at a small size,
 * compared with the project's metrics (LDR-FLIP with the frozen metric tone map at the view's
 * exposure).  The reference is two independent halves of the sample budget; their FLIP against each
 * other bounds the reference's own noise, so the HUD can say whether an error is above noise.
 * Blocking (seconds); the walk triggers it on demand ([R] or a script's key R). */
#ifndef PRW_WALK_MEASURE_H
#define PRW_WALK_MEASURE_H

#include "prw_render.h"

typedef struct walk_measure {
    bool have;
    uint32_t width, height; /* measured image */
    uint64_t spp;           /* reference samples per pixel (both halves) */
    double ldr_flip;        /* raster vs reference, mean LDR-FLIP */
    double noise_flip;      /* half vs half of the reference: its noise at spp/2 (an upper bound) */
    double seconds;         /* wall time of the measurement */
    double when;            /* prw_now() when it finished */
} walk_measure;

/* v: the current view (any size; measured at `width` pixels wide, same frustum); desc: the walk's
 * render settings (size ignored); threads: the --threads budget (0 = prw_threads_get()). */
bool walk_measure_run(prw_gpu *gpu, const prw_scene *scene, const prw_view *v, const prw_render_desc *desc,
                      uint32_t width, uint64_t spp, int threads, walk_measure *out, prw_error *e);

#endif
