/* quality_args — presets and knob shorthands on the command line (quality_args.h). */
#include "quality_args.h"

#include <stdio.h>
#include <string.h>

static void shorthand(prw_args *a, const char *opt, const char *knob, prw_quality *q, bool *bad, prw_error *e)
{
    const char *v = prw_args_value(a, opt, e, bad);
    if (!v || *bad) return;
    char cfg[256];
    snprintf(cfg, sizeof cfg, "%s=%s", knob, v);
    prw_error ke = {{0}};
    if (!prw_quality_parse_config(cfg, q, q, &ke)) {
        *bad = true;
        const char *why = ke.msg, *colon = strstr(ke.msg, ": "); /* "knob x=v: why" -> "why" */
        if (strncmp(ke.msg, "knob ", 5) == 0 && colon) why = colon + 2;
        prw_fail(e, "--%s '%s': %s", opt, v, why);
    }
}

void prw_quality_args_read(prw_args *a, prw_quality *q, bool *bad, prw_error *e)
{
    *q = prw_quality_default();
    const char *preset = prw_args_value(a, "preset", e, bad);
    if (preset && !*bad && !prw_quality_parse_config(preset, q, q, e)) *bad = true;
    shorthand(a, "msaa", "msaa", q, bad, e);
    shorthand(a, "shadow-size", "shadow_size", q, bad, e);
    shorthand(a, "ss", "supersample", q, bad, e);
    shorthand(a, "stereo-reuse", "stereo_reuse", q, bad, e);
    shorthand(a, "lod-tolerance", "lod_pixel_tolerance", q, bad, e);
}

const char *prw_quality_args_help(void)
{
    return "  --preset CONFIG    quality: a preset (low, medium, high, ultra; default high) and/or knobs,\n"
           "                     e.g. \"low\", \"ultra;msaa=1\", \"lod_pixel_tolerance=2\" (knobs: prw bench --help)\n"
           "  --msaa 1|4         samples per pixel, resolved in linear HDR (knob msaa; default 4)\n"
           "  --shadow-size N    shadow-map resolution (knob shadow_size; default 1024)\n"
           "  --ss N             N x N supersampling, box-filtered in linear HDR (knob supersample; default 1)\n"
           "  --lod-tolerance PX NURBS LOD screen-space error (knob lod_pixel_tolerance; default 0.5)\n";
}
