/* bake_curve — `prw bake SCENE --gi --curve`: the light maps' error against their bake time (issue 16,
 * must-show 4), a benchmark (it prints figures; it asserts nothing).
 *
 * For each setting (radiosity_size : samples, the baker's default filter radius) the scene is loaded
 * and baked from a FRESH cache (a new temporary $PRW_CACHE_DIR, removed afterwards: the NURBS LOD bake
 * of prw_app_bake_scene and the GI bake with its cache write, as `render` does on a first run), timed
 * in wall and process CPU seconds; then the base pass draws only the light maps' term (`--term
 * indirect-diffuse`) at the given size, camera and quality, and is compared with the reference's
 * indirect-diffuse-last term (seeds 1 and 2 at ref_spp; the full reference at ref_spp / 4 for the mask:
 * the pixels where the term exceeds 1 % of it), at the term's own metric exposure:
 *   LDR-FLIP beyond noise = FLIP(raster, A) - FLIP(B, A),  relMSE beyond noise = relMSE(raster, A) -
 *   relMSE(B, A) / 2  (as tests/render/test_gi_raster.c).
 * One CSV row per setting (the file is removed when the run fails); the plot (gnuplot, optional) shows
 * both errors against bake CPU seconds.
 * The row whose setting is the renderer's default bake (the quality's radiosity_size,
 * PRW_GI_DEFAULT_SAMPLES) is printed again at the end with the machine's load average. */
#ifndef PRW_APP_BAKE_CURVE_H
#define PRW_APP_BAKE_CURVE_H

#include <stdint.h>

#include "prw_quality.h"

typedef struct bake_curve_opts {
    const char *scene;    /* path or "demo" */
    const char *camera;   /* NULL: the first */
    const char *settings; /* "R:S,R:S,..."; NULL: the default list */
    uint32_t width, height;
    uint32_t ref_spp;
    uint64_t seed;        /* the bakes' seed */
    const char *csv, *png;
    prw_quality q;        /* the renderer's quality (its radiosity_size is the default bake's) */
} bake_curve_opts;

/* Process exit code: 0, 1 (a failure, one line on stderr), 2 (bad settings). */
int bake_curve_run(const bake_curve_opts *o);

#endif
