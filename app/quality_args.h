/* quality_args — the quality knobs on the command line of every rendering command (render, walk,
 * bench): one syntax everywhere.
 *   --preset CONFIG   a preset name and/or knob list in prw_quality.h syntax ("low", "ultra;msaa=1",
 *                     "lod_pixel_tolerance=2"), applied to the default (preset "high")
 *   --msaa N, --shadow-size N, --ss N, --stereo-reuse off|reproject, --lod-tolerance PX
 *                     shorthands for one knob each (msaa, shadow_size, supersample, stereo_reuse,
 *                     lod_pixel_tolerance), applied after --preset
 * Errors name the option and the accepted values (prw_error; *bad set). */
#ifndef PRW_APP_QUALITY_ARGS_H
#define PRW_APP_QUALITY_ARGS_H

#include "app.h"
#include "prw_quality.h"

/* Reads the options above from a into *q (starting from prw_quality_default()). */
void prw_quality_args_read(prw_args *a, prw_quality *q, bool *bad, prw_error *e);
/* Help lines for the options above (each starts with two spaces, ends with a newline). */
const char *prw_quality_args_help(void);

#endif
