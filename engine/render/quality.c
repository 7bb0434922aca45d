/* quality — the knob table, presets, config / sweep parsing and validation (prw_quality.h). */
#define _POSIX_C_SOURCE 200809L
#include "prw_quality.h"

#include "prw_constants.h"
#include "prw_tonemap.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define U32(field, lo, hi, impl, text) {#field, PRW_KNOB_U32, offsetof(prw_quality, field), lo, hi, impl, false, text}
#define F64(field, lo, hi, impl, text) {#field, PRW_KNOB_F64, offsetof(prw_quality, field), lo, hi, impl, false, text}

static const prw_knob_info g_knobs[] = {
    U32(msaa, 1, 4, true, "samples per pixel, 1 or 4 (resolved in linear HDR)"),
    U32(shadow_size, 16, 8192, true, "shadow-map resolution, texels a side"),
    U32(soft_shadows, 0, 8, true,
        "rect-light shadows: 0 = hard (one shadow-map lookup, 3x3 PCF), 2..8 = soft: N x N blocker search and "
        "max(2, N-1)^2 filter taps sized by the rectangle (penumbra); costs base-pass time"),
    U32(supersample, 1, 8, true, "N x N supersampling, box-filtered in linear HDR"),
    U32(tonemap, 0, PRW_TM_OP_COUNT - 1, true,
        "tone-mapping operator: exposure, reinhard, neutral, adaptive, absolute, local, selective (or 0-6)"),
    U32(stereo_reuse, 0, 1, true,
        "stereo: off (0) or reproject (1): the right eye reuses the left eye's colour where both see the same "
        "surface (changes pixels; per-view loop backend)"),
    U32(radiance_bits, 16, 32, true,
        "radiance targets: 32 = float32 (no clipping), 16 = half float (clips above 65504 cd/m^2)"),
    F64(lod_pixel_tolerance, 0.01, 100, true,
        "NURBS LOD screen-space error, pixels (models whose manifest entry sets no tol_px)"),
    U32(emissive_lights, 0, PRW_MAX_LIGHTS, true,
        "emissive meshes: at most this many area lights (polygons; beyond, merged into rectangles); 0 = no light"),
    U32(mirror_recursion, 0, 1, true, "planar mirrors: reflection bounces rendered (0 = off; deeper not implemented)"),
    F64(glossy_max_roughness, 0, 1, true,
        "planar reflectors: largest roughness reflected via the convolved mirror image (<= 0.05: sharp mirrors only)"),
    U32(btf_clusters, 1, 65536, false, "BTF clusters"),
    U32(btf_components, 1, 1024, false, "BTF components per cluster"),
    U32(ssdo_samples, 0, 1024, false, "SSDO samples per pixel"),
    F64(ssdo_radius, 0, 100, false, "SSDO radius, metres"),
    U32(vpl_count, 0, 1u << 20, false, "VPL count"),
    U32(ism_size, 0, 16384, false, "imperfect shadow map size, texels a side"),
    U32(kernel_taps, 1, 1024, true, "taps of the glossy planar reflectors' convolution of the mirror image"),
    U32(max_reflectors, 1, 4, true,
        "planar reflectors reflected per view (those covering the most pixels; one mirror image each)"),
    F64(mirror_scale, 0.125, 1, true,
        "planar reflectors: mirror image resolution as a fraction of the view's (1, 0.5, 0.25; upsampled when added)"),
    F64(glossy_scale, 0.125, 1, true,
        "glossy planar reflectors: their mirror image and convolution at this fraction of mirror_scale's resolution"),
    F64(reflection_skip, 0, 1, true,
        "planar reflectors: skipped in a view when the estimated reflection is below this share of the surface's own "
        "radiance (0 = never)"),
    U32(gi_lookups, 0, 1, true,
        "base pass GI lookups: 1 = baked light maps and environment term; 0 = neither (as --no-bake without the "
        "environment; with mirror_recursion=0 the frame without GI)"),
    U32(probe_count, 0, 8, true, "reflection probes: at most this many curved glossy objects get one (0 = off)"),
    U32(probe_size, 8, 512, true, "reflection probes: rows of a probe's gathered equirectangular map (width 2x)"),
    U32(envmap_size, 1, 16384, false, "environment map height, texels"),
    F64(billboard_error, 0, 1000, false, "billboard cloud error, pixels"),
    U32(radiosity_size, 1, 16384, false, "radiosity texture size, texels a side"),
    {"extra_gpu_work", PRW_KNOB_F64, offsetof(prw_quality, extra_gpu_work), 0, 16, true, true,
     "test knob: extra GPU work as a fraction of the base pass (image unchanged)"},
};

const prw_knob_info *prw_quality_knobs(uint32_t *count)
{
    *count = (uint32_t)PRW_ARRAY_LEN(g_knobs);
    return g_knobs;
}

const prw_knob_info *prw_quality_find_knob(const char *name)
{
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_knobs); i++)
        if (strcmp(g_knobs[i].name, name) == 0) return &g_knobs[i];
    return NULL;
}

double prw_quality_get(const prw_quality *q, const prw_knob_info *k)
{
    const char *p = (const char *)q + k->offset;
    if (k->type == PRW_KNOB_U32) return (double)*(const uint32_t *)(const void *)p;
    return *(const double *)(const void *)p;
}

bool prw_quality_set(prw_quality *q, const prw_knob_info *k, double value, prw_error *e)
{
    if (!(value >= k->min && value <= k->max))
        return prw_fail(e, "knob %s=%g: out of range [%g, %g]", k->name, value, k->min, k->max);
    char *p = (char *)q + k->offset;
    if (k->type == PRW_KNOB_U32) {
        if (value != floor(value)) return prw_fail(e, "knob %s=%g: expected an integer", k->name, value);
        if (strcmp(k->name, "msaa") == 0 && value != 1 && value != 4)
            return prw_fail(e, "knob msaa=%g: lavapipe offers 1 or 4", value);
        if (strcmp(k->name, "radiance_bits") == 0 && value != 16 && value != 32)
            return prw_fail(e, "knob radiance_bits=%g: 16 or 32", value);
        if (strcmp(k->name, "soft_shadows") == 0 && value == 1)
            return prw_fail(e, "knob soft_shadows=1: 0 (hard) or 2..8 taps a side");
        *(uint32_t *)(void *)p = (uint32_t)value;
    } else {
        *(double *)(void *)p = value;
    }
    return true;
}

/* Presets: points in the knob space.  Unimplemented knobs get plausible values so the presets are
 * already ordered along every axis.  "high" is every command's default: 4x MSAA, 1024^2 shadow maps,
 * 0.5 px LOD error (the renderer's own defaults before the knobs reached it), float32 radiance, hard
 * rect-light shadows (soft_shadows costs base-pass time: only "ultra" turns it on). */
static const struct {
    const char *name;
    prw_quality q;
} g_presets[] = {
    {"low", {.gi_lookups = 1, .mirror_recursion = 1, .glossy_max_roughness = 0.3, .max_reflectors = 2, .mirror_scale = 1, .glossy_scale = 0.5, .reflection_skip = 0.05, .probe_count = 4, .probe_size = 64, .emissive_lights = 4, .msaa = 1, .shadow_size = 256, .supersample = 1, .radiance_bits = 16, .lod_pixel_tolerance = 4, .btf_clusters = 8,
             .btf_components = 2, .ssdo_samples = 4, .ssdo_radius = 0.25, .vpl_count = 64, .ism_size = 64,
             .kernel_taps = 8, .envmap_size = 128, .billboard_error = 8, .radiosity_size = 64}},
    {"medium", {.gi_lookups = 1, .mirror_recursion = 1, .glossy_max_roughness = 0.3, .max_reflectors = 2, .mirror_scale = 1, .glossy_scale = 0.5, .reflection_skip = 0.05, .probe_count = 4, .probe_size = 64, .emissive_lights = 8, .msaa = 4, .shadow_size = 512, .supersample = 1, .radiance_bits = 32, .lod_pixel_tolerance = 2, .btf_clusters = 16,
                .btf_components = 4, .ssdo_samples = 8, .ssdo_radius = 0.5, .vpl_count = 256, .ism_size = 128,
                .kernel_taps = 16, .envmap_size = 256, .billboard_error = 4, .radiosity_size = 128}},
    {"high", {.gi_lookups = 1, .mirror_recursion = 1, .glossy_max_roughness = 0.3, .max_reflectors = 2, .mirror_scale = 1, .glossy_scale = 0.5, .reflection_skip = 0.05, .probe_count = 4, .probe_size = 64, .emissive_lights = 16, .msaa = 4, .shadow_size = 1024, .supersample = 1, .radiance_bits = 32, .lod_pixel_tolerance = 0.5, .btf_clusters = 32,
              .btf_components = 8, .ssdo_samples = 16, .ssdo_radius = 0.5, .vpl_count = 1024, .ism_size = 256,
              .kernel_taps = 32, .envmap_size = 512, .billboard_error = 2, .radiosity_size = 256}},
    {"ultra", {.gi_lookups = 1, .mirror_recursion = 1, .glossy_max_roughness = 0.3, .max_reflectors = 2, .mirror_scale = 1, .glossy_scale = 1, .reflection_skip = 0.05, .probe_count = 4, .probe_size = 64, .emissive_lights = 16, .msaa = 4, .shadow_size = 4096, .soft_shadows = 4, .supersample = 2, .radiance_bits = 32, .lod_pixel_tolerance = 0.25, .btf_clusters = 64,
               .btf_components = 16, .ssdo_samples = 32, .ssdo_radius = 1, .vpl_count = 4096, .ism_size = 512,
               .kernel_taps = 64, .envmap_size = 1024, .billboard_error = 1, .radiosity_size = 512}},
};

prw_quality prw_quality_default(void) { return g_presets[2].q; }

bool prw_quality_validate(const prw_quality *q, prw_error *e)
{
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_knobs); i++) {
        prw_quality probe = *q;
        if (!prw_quality_set(&probe, &g_knobs[i], prw_quality_get(q, &g_knobs[i]), e))
            return prw_fail_wrap(e, "quality");
    }
    return true;
}

bool prw_quality_preset(const char *name, prw_quality *out, prw_error *e)
{
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_presets); i++)
        if (strcmp(g_presets[i].name, name) == 0) {
            *out = g_presets[i].q;
            return true;
        }
    return prw_fail(e, "preset '%s': unknown (presets: low, medium, high, ultra)", name);
}

bool prw_stereo_reuse_parse(const char *text, double *out)
{
    if (strcmp(text, "off") == 0) *out = PRW_STEREO_REUSE_OFF;
    else if (strcmp(text, "reproject") == 0) *out = PRW_STEREO_REUSE_REPROJECT;
    else return false;
    return true;
}

static bool parse_value(const prw_knob_info *k, const char *text, double *out, prw_error *e)
{
    char *end = NULL;
    prw_tm_op op;
    if (strcmp(k->name, "tonemap") == 0 && prw_tm_op_parse(text, &op, NULL)) { /* by name */
        *out = (double)op;
        return true;
    }
    if (strcmp(k->name, "stereo_reuse") == 0 && prw_stereo_reuse_parse(text, out)) return true; /* by name */
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(v)) {
        if (strcmp(k->name, "tonemap") == 0)
            return prw_fail(e, "knob tonemap='%s': expected an operator (%s) or its number", text, prw_tm_op_list());
        if (strcmp(k->name, "stereo_reuse") == 0)
            return prw_fail(e, "knob stereo_reuse='%s': expected off or reproject (or 0, 1)", text);
        return prw_fail(e, "knob %s='%s': expected a number", k->name, text);
    }
    *out = v;
    return true;
}

static void knob_list(char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_knobs) && n < cap; i++)
        if (!g_knobs[i].hidden) n += (size_t)snprintf(buf + n, cap - n, "%s%s", n ? ", " : "", g_knobs[i].name);
}

static const prw_knob_info *find_or_fail(const char *name, prw_error *e)
{
    const prw_knob_info *k = prw_quality_find_knob(name);
    if (!k) {
        char list[512];
        knob_list(list, sizeof list);
        prw_fail(e, "unknown knob '%s' (knobs: %s)", name, list);
    }
    return k;
}

bool prw_quality_parse_config(const char *text, const prw_quality *base, prw_quality *out, prw_error *e)
{
    prw_quality q = *base;
    char *copy = prw_strdup(text), *save = NULL;
    bool ok = true, first = true;
    if (!copy[0]) ok = prw_fail(e, "config '': empty (give a preset name or knob=value list)");
    for (char *tok = strtok_r(copy, ";,", &save); ok && tok; tok = strtok_r(NULL, ";,", &save), first = false) {
        char *eq = strchr(tok, '=');
        if (!eq) {
            if (!first) ok = prw_fail(e, "config '%s': '%s' is not knob=value (a preset name must come first)", text, tok);
            else ok = prw_quality_preset(tok, &q, e);
            continue;
        }
        *eq = '\0';
        const prw_knob_info *k = find_or_fail(tok, e);
        double v;
        ok = k && parse_value(k, eq + 1, &v, e) && prw_quality_set(&q, k, v, e);
    }
    free(copy);
    if (ok) *out = q;
    return ok;
}

#define MAX_SWEEP 4096

bool prw_quality_parse_sweep(const char *spec, const prw_quality *base, prw_quality **out, uint32_t *count,
                             prw_error *e)
{
    *out = NULL;
    *count = 0;
    const prw_knob_info *knobs[32];
    double *values[32];
    uint32_t nvalues[32], nk = 0;
    char *copy = prw_strdup(spec), *save = NULL;
    bool ok = true;
    uint64_t total = 1;
    for (char *tok = strtok_r(copy, ";", &save); ok && tok; tok = strtok_r(NULL, ";", &save)) {
        char *eq = strchr(tok, '=');
        if (!eq || eq == tok || !eq[1]) {
            ok = prw_fail(e, "--sweep '%s': '%s' is not knob=v1,v2,...", spec, tok);
            break;
        }
        *eq = '\0';
        const prw_knob_info *k = find_or_fail(tok, e);
        if (!k) {
            ok = false;
            break;
        }
        for (uint32_t i = 0; i < nk; i++)
            if (knobs[i] == k) ok = prw_fail(e, "--sweep '%s': knob %s given twice", spec, k->name);
        if (!ok) break;
        if (nk == 32) {
            ok = prw_fail(e, "--sweep '%s': more than 32 knobs", spec);
            break;
        }
        values[nk] = NULL;
        nvalues[nk] = 0;
        char *save2 = NULL;
        for (char *v = strtok_r(eq + 1, ",", &save2); ok && v; v = strtok_r(NULL, ",", &save2)) {
            double x;
            prw_quality probe = *base;
            if (!parse_value(k, v, &x, e) || !prw_quality_set(&probe, k, x, e)) {
                ok = false;
                break;
            }
            values[nk] = prw_realloc(values[nk], (nvalues[nk] + 1) * sizeof(double));
            values[nk][nvalues[nk]++] = x;
        }
        knobs[nk++] = k;
        if (ok) total *= nvalues[nk - 1];
        if (ok && total > MAX_SWEEP) ok = prw_fail(e, "--sweep '%s': more than %d configurations", spec, MAX_SWEEP);
    }
    if (ok && nk == 0) ok = prw_fail(e, "--sweep '%s': no knobs (expected e.g. msaa=1,4;shadow_size=512,1024)", spec);
    if (ok) {
        prw_quality *list = prw_calloc((size_t)total, sizeof *list);
        for (uint64_t c = 0; c < total; c++) {
            prw_quality q = *base;
            uint64_t rest = c;
            for (uint32_t i = nk; i-- > 0;) { /* last knob varies fastest */
                (void)prw_quality_set(&q, knobs[i], values[i][rest % nvalues[i]], e);
                rest /= nvalues[i];
            }
            list[c] = q;
        }
        *out = list;
        *count = (uint32_t)total;
    }
    for (uint32_t i = 0; i < nk; i++) free(values[i]);
    free(copy);
    return ok;
}

static size_t format_knob(const prw_quality *q, const prw_knob_info *k, char *buf, size_t cap, bool sep)
{
    double v = prw_quality_get(q, k);
    if (strcmp(k->name, "tonemap") == 0)
        return (size_t)snprintf(buf, cap, "%s%s=%s", sep ? ";" : "", k->name, prw_tm_op_name((prw_tm_op)v));
    if (strcmp(k->name, "stereo_reuse") == 0)
        return (size_t)snprintf(buf, cap, "%s%s=%s", sep ? ";" : "", k->name, v == 1 ? "reproject" : "off");
    if (k->type == PRW_KNOB_U32) return (size_t)snprintf(buf, cap, "%s%s=%u", sep ? ";" : "", k->name, (uint32_t)v);
    return (size_t)snprintf(buf, cap, "%s%s=%.17g", sep ? ";" : "", k->name, v);
}

void prw_quality_format(const prw_quality *q, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_knobs) && n < cap; i++) {
        if (g_knobs[i].hidden && prw_quality_get(q, &g_knobs[i]) == 0) continue;
        n += format_knob(q, &g_knobs[i], buf + n, cap - n, n > 0);
    }
}

void prw_quality_format_diff(const prw_quality *q, const prw_quality *base, char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_knobs) && n < cap; i++)
        if (prw_quality_get(q, &g_knobs[i]) != prw_quality_get(base, &g_knobs[i]))
            n += format_knob(q, &g_knobs[i], buf + n, cap - n, n > 0);
}

void prw_quality_describe(char *buf, size_t cap)
{
    size_t n = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < PRW_ARRAY_LEN(g_knobs) && n < cap; i++) {
        const prw_knob_info *k = &g_knobs[i];
        if (k->hidden) continue;
        n += (size_t)snprintf(buf + n, cap - n, "    %-20s %s [%g, %g]%s\n", k->name, k->help, k->min, k->max,
                              k->implemented ? "" : " (no effect yet)");
    }
}
