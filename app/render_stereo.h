/* render_stereo — `prw render --stereo` / `prw render --hmd PROFILE` (issue 5): both eyes of one
 * frame as a view set, written as left and right EXR (linear HDR, cd/m^2) plus the composed image
 * (side-by-side for desktop stereo and the HMD debug view, pre-distorted panel for --hmd) as EXR and
 * PNG.  Both eyes share the LOD choice, exposure, shadow maps and tone-map statistics. */
#ifndef PRW_APP_RENDER_STEREO_H
#define PRW_APP_RENDER_STEREO_H

#include "prw_core.h"
#include "prw_quality.h"

typedef struct prw_stereo_job {
    const char *scene_path, *out, *camera; /* out: FILE.exr -> FILE-left.exr, -right, -composed.{exr,png} */
    const char *hmd;                       /* NULL: desktop stereo */
    const char *display, *tonemap;         /* NULL: srgb (desktop) / hmd-lcd with the profile's peak, exposure */
    const char *views_backend;             /* loop | multiview | auto (NULL = auto) */
    bool sbs_debug;                        /* --hmd: compose side by side without distortion */
    uint32_t width, height;                /* desktop: per eye; --hmd: panel (0 = the profile's) */
    prw_quality q;                         /* the knobs (stereo_reuse: the right eye reuses the left's colour) */
    double ipd, screen_distance;           /* desktop; ipd < 0: default */
    bool has_ev;
    double ev100;
} prw_stereo_job;

int prw_stereo_job_run(const prw_stereo_job *job);

#endif
