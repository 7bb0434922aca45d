/* hmd — HMD profiles (JSON), the radial lens model and its inverse, and the C reference of the
 * panel composition; see prw_hmd.h. */
#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "prw_hmd.h"
#include "prw_json_doc.h"

/* ---- built-in preset (the same tuple as assets/hmd/dk2.json; a test checks they agree) ----
 * Panel and optics of the Oculus Rift DK2 as the Oculus SDK 0.4 sources give them
 * (OVR_Stereo.cpp: ScreenSizeInMeters 0.12576 x 0.07074, LensSeparationInMeters 0.0635,
 * 1920 x 1080, MetersPerTanAngleAtCenter 0.036); the polynomial distortion and chromatic
 * coefficients are the published Rift SDK 0.2 values (DistortionK 1.0, 0.22, 0.24, 0.0;
 * ChromaAbCorrection 0.996, -0.004, 1.014, 0.0): the DK2's own SDK used a spline instead.
 * IPD: the SDK default 0.064 m.  Peak luminance 100 cd/m^2 is an assumption (low-persistence
 * OLED; no published figure), matching assets/displays/hmd-lcd.json. */
static const prw_hmd k_dk2 = {
    .name = "dk2",
    .panel_width = 1920,
    .panel_height = 1080,
    .screen_width = 0.12576,
    .screen_height = 0.07074,
    .eye_to_screen = 0.036,
    .lens_separation = 0.0635,
    .ipd = 0.064,
    .k = {0.22, 0.24, 0.0, 0.0},
    .ca = {0.996, -0.004, 1.014, 0.0},
    .eye_buffer_scale = 1.0,
    .peak_luminance = 100.0,
};

bool prw_hmd_builtin(const char *name, prw_hmd *out)
{
    if (name && strcmp(name, "dk2") == 0) {
        *out = k_dk2;
        return true;
    }
    return false;
}

/* ---- lens model ---- */

static double poly_d(const prw_hmd *h, double r2)
{
    return 1.0 + r2 * (h->k[0] + r2 * (h->k[1] + r2 * (h->k[2] + r2 * h->k[3])));
}
static double poly_d_dr2(const prw_hmd *h, double r2) /* dD / d(r^2) */
{
    return h->k[0] + r2 * (2.0 * h->k[1] + r2 * (3.0 * h->k[2] + r2 * 4.0 * h->k[3]));
}
static double chroma(const prw_hmd *h, int c, double r2)
{
    return c == 0 ? h->ca[0] + h->ca[1] * r2 : c == 2 ? h->ca[2] + h->ca[3] * r2 : 1.0;
}
static double chroma_dr2(const prw_hmd *h, int c) { return c == 0 ? h->ca[1] : c == 2 ? h->ca[3] : 0.0; }

double prw_lens_radius_scale(const prw_hmd *h, int channel, double r2) { return poly_d(h, r2) * chroma(h, channel, r2); }

/* g(r) = r D(r) s(r) and g'(r) */
static double lens_g(const prw_hmd *h, int c, double r, double *dg)
{
    double r2 = r * r, d = poly_d(h, r2), s = chroma(h, c, r2);
    /* d/dr [r D s] = D s + r (dD/dr s + D ds/dr), d/dr = 2 r d/d(r^2) */
    *dg = d * s + 2.0 * r2 * (poly_d_dr2(h, r2) * s + d * chroma_dr2(h, c));
    return r * d * s;
}

void prw_lens_forward(const prw_hmd *h, int channel, double px, double py, double *qx, double *qy)
{
    double s = prw_lens_radius_scale(h, channel, px * px + py * py);
    *qx = px * s;
    *qy = py * s;
}

double prw_hmd_lens_unit(const prw_hmd *h) { return 0.25 * h->screen_width; }

double prw_hmd_lens_centre_x(const prw_hmd *h, int eye) { return (eye ? 0.5 : -0.5) * h->lens_separation; }

double prw_hmd_corner_radius(const prw_hmd *h)
{
    double R = prw_hmd_lens_unit(h);
    /* left eye: half spans x in [-W/2, 0] around its lens centre at -sep/2 */
    double xo = fabs(-0.5 * h->screen_width + 0.5 * h->lens_separation), xi = 0.5 * h->lens_separation;
    double x = fmax(xo, xi), y = 0.5 * h->screen_height;
    return sqrt(x * x + y * y) / R;
}

double prw_hmd_lens_circle(const prw_hmd *h)
{
    double R = prw_hmd_lens_unit(h);
    double xo = fabs(-0.5 * h->screen_width + 0.5 * h->lens_separation), xi = 0.5 * h->lens_separation;
    return fmin(fmin(xo, xi), 0.5 * h->screen_height) / R;
}

bool prw_lens_inverse(const prw_hmd *h, int channel, double qx, double qy, double *px, double *py)
{
    double rho = sqrt(qx * qx + qy * qy);
    if (rho == 0.0) {
        *px = *py = 0.0;
        return true;
    }
    double rmax = 1.1 * prw_hmd_corner_radius(h), dg;
    if (rho > lens_g(h, channel, rmax, &dg)) return false;
    /* Newton on g(r) = rho, safeguarded by bisection on [0, rmax] (g increases strictly there) */
    double lo = 0.0, hi = rmax, r = fmin(rho, rmax);
    for (int it = 0; it < 100; it++) {
        double f = lens_g(h, channel, r, &dg) - rho;
        if (f > 0) hi = r;
        else lo = r;
        double next = dg > 0 ? r - f / dg : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (fabs(next - r) <= 1e-15 * fmax(1.0, r)) {
            r = next;
            break;
        }
        r = next;
    }
    double k = r / rho;
    *px = qx * k;
    *py = qy * k;
    return true;
}

void prw_hmd_eye_fov(const prw_hmd *h, int eye, prw_fov *out)
{
    double R = prw_hmd_lens_unit(h), d = h->eye_to_screen;
    double xo = fabs(-0.5 * h->screen_width + 0.5 * h->lens_separation), xi = 0.5 * h->lens_separation;
    double y = 0.5 * h->screen_height;
    double edge[3] = {xo, xi, y}, tan_edge[3];
    for (int k = 0; k < 3; k++) {
        double r = edge[k] / R, r2 = r * r, s = 1.0;
        for (int c = 0; c < 3; c++) s = fmax(s, prw_lens_radius_scale(h, c, r2));
        tan_edge[k] = edge[k] / d * s;
    }
    /* left eye: outer edge to the left; right eye mirrored */
    double t_left = eye ? tan_edge[1] : tan_edge[0], t_right = eye ? tan_edge[0] : tan_edge[1];
    out->angle_left = -atan(t_left);
    out->angle_right = atan(t_right);
    out->angle_up = atan(tan_edge[2]);
    out->angle_down = -atan(tan_edge[2]);
}

void prw_hmd_eye_size(const prw_hmd *h, uint32_t panel_w, uint32_t panel_h, uint32_t *w, uint32_t *h_out)
{
    if (!panel_w) panel_w = h->panel_width;
    if (!panel_h) panel_h = h->panel_height;
    prw_fov f;
    prw_hmd_eye_fov(h, 0, &f);
    /* tangent per panel pixel at the lens centre = pitch / eye_to_screen */
    double px = h->screen_width / panel_w / h->eye_to_screen, py = h->screen_height / panel_h / h->eye_to_screen;
    double ew = (tan(f.angle_right) - tan(f.angle_left)) / px * h->eye_buffer_scale;
    double eh = (tan(f.angle_up) - tan(f.angle_down)) / py * h->eye_buffer_scale;
    *w = (uint32_t)fmax(1.0, ceil(ew - 1e-9));
    *h_out = (uint32_t)fmax(1.0, ceil(eh - 1e-9));
}

/* ---- validation ---- */

bool prw_hmd_validate(const prw_hmd *h, const char *file, prw_error *e)
{
    const char *f = file ? file : "(hmd)";
    if (h->panel_width < 2 || h->panel_width > 16384 || h->panel_height < 1 || h->panel_height > 16384 ||
        h->panel_width % 2)
        return prw_fail(e, "%s:panel: %ux%u must be an even width in 2..16384 and a height in 1..16384", f,
                        h->panel_width, h->panel_height);
    if (!(h->screen_width > 0.001 && h->screen_width < 2 && h->screen_height > 0.001 && h->screen_height < 2))
        return prw_fail(e, "%s:screen_size_m: must be in (0.001, 2) metres", f);
    if (!(h->eye_to_screen > 0.001 && h->eye_to_screen < 1))
        return prw_fail(e, "%s:eye_to_screen_m: must be in (0.001, 1) metres", f);
    if (!(h->lens_separation > 0 && h->lens_separation < h->screen_width))
        return prw_fail(e, "%s:lens_separation_m: must be in (0, screen width %g)", f, h->screen_width);
    if (!(h->ipd >= 0.03 && h->ipd <= 0.09)) return prw_fail(e, "%s:ipd_m: must be in [0.03, 0.09] metres", f);
    if (!(h->eye_buffer_scale >= 0.1 && h->eye_buffer_scale <= 4))
        return prw_fail(e, "%s:eye_buffer_scale: must be in [0.1, 4]", f);
    if (!(h->peak_luminance >= 1 && h->peak_luminance <= 10000))
        return prw_fail(e, "%s:peak_luminance: must be in [1, 10000] cd/m^2", f);
    for (int i = 0; i < 4; i++)
        if (!(fabs(h->k[i]) <= 10)) return prw_fail(e, "%s:distortion_k[%d]: must be finite, |k| <= 10", f, i);
    if (!(h->ca[0] >= 0.8 && h->ca[0] <= 1.2 && h->ca[2] >= 0.8 && h->ca[2] <= 1.2 && fabs(h->ca[1]) <= 0.2 &&
          fabs(h->ca[3]) <= 0.2))
        return prw_fail(e, "%s:chromatic: scales [0] and [2] must be in [0.8, 1.2], slopes [1] and [3] in [-0.2, 0.2]",
                        f);
    /* the inverse must be unique: g_c(r) = r D(r) s_c(r) strictly increasing up to 1.1 x the corner */
    double rmax = 1.1 * prw_hmd_corner_radius(h);
    static const char *const ch[3] = {"red", "green", "blue"};
    for (int c = 0; c < 3; c++)
        for (int i = 0; i <= 2000; i++) {
            double r = rmax * i / 2000.0, dg;
            lens_g(h, c, r, &dg);
            if (!(dg > 0) || !(prw_lens_radius_scale(h, c, r * r) > 0))
                return prw_fail(e, "%s:distortion_k: the lens model folds over (%s channel, r = %.3f of the panel's %.3f): "
                                "no unique inverse", f, ch[c], r, rmax / 1.1);
        }
    return true;
}

/* ---- JSON ---- */

typedef prw_json_ctx ctx;

static const cJSON *item(const cJSON *o, const char *k) { return cJSON_GetObjectItemCaseSensitive(o, k); }

static bool get_num(ctx *c, const cJSON *o, const char *key, double *out)
{
    const cJSON *v = item(o, key);
    if (!v) return prw_json_fail_at(c, key, "missing (required)");
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) return prw_json_fail_at(c, key, "must be a finite number");
    *out = v->valuedouble;
    return true;
}

static bool get_array(ctx *c, const cJSON *o, const char *key, int n, double *out)
{
    const cJSON *v = item(o, key);
    if (!v) return prw_json_fail_at(c, key, "missing (required)");
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n) return prw_json_fail_at(c, key, "must be an array of %d numbers", n);
    int i = 0;
    for (const cJSON *it = v->child; it; it = it->next, i++) {
        if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble)) {
            char place[80];
            snprintf(place, sizeof place, "%s[%d]", key, i);
            return prw_json_fail_at(c, place, "must be a finite number");
        }
        out[i] = it->valuedouble;
    }
    return true;
}

static bool parse_root(ctx *c, const cJSON *root, prw_hmd *h)
{
    static const char *const keys[] = {"prw_hmd",        "name",          "description",       "panel",
                                       "screen_size_m",  "eye_to_screen_m", "lens_separation_m", "ipd_m",
                                       "distortion_k",   "chromatic",     "eye_buffer_scale",  "peak_luminance"};
    if (!cJSON_IsObject(root)) return prw_json_fail_at(c, "", "top level must be a JSON object");
    if (!prw_json_check_keys(c, root, "", keys, (int)PRW_ARRAY_LEN(keys))) return false;
    const cJSON *v = item(root, "prw_hmd");
    if (!v) return prw_json_fail_at(c, "prw_hmd", "missing (required; this reader understands version 1)");
    if (!cJSON_IsNumber(v) || v->valuedouble != 1.0)
        return prw_json_fail_at(c, "prw_hmd", "unsupported version (this reader understands 1)");
    memset(h, 0, sizeof *h);
    v = item(root, "name");
    if (!cJSON_IsString(v) || !v->valuestring[0] || strlen(v->valuestring) >= sizeof h->name)
        return prw_json_fail_at(c, "name", "must be a non-empty string shorter than %zu bytes", sizeof h->name);
    snprintf(h->name, sizeof h->name, "%s", v->valuestring);
    v = item(root, "description");
    if (v && !cJSON_IsString(v)) return prw_json_fail_at(c, "description", "must be a string");
    double panel[2], size[2];
    if (!get_array(c, root, "panel", 2, panel)) return false;
    for (int i = 0; i < 2; i++)
        if (!(panel[i] >= 1 && panel[i] <= 16384 && panel[i] == floor(panel[i])))
            return prw_json_fail_at(c, i ? "panel[1]" : "panel[0]", "must be an integer in [1, 16384]");
    h->panel_width = (uint32_t)panel[0];
    h->panel_height = (uint32_t)panel[1];
    if (!get_array(c, root, "screen_size_m", 2, size) || !get_num(c, root, "eye_to_screen_m", &h->eye_to_screen) ||
        !get_num(c, root, "lens_separation_m", &h->lens_separation) || !get_num(c, root, "ipd_m", &h->ipd) ||
        !get_array(c, root, "distortion_k", 4, h->k) || !get_array(c, root, "chromatic", 4, h->ca) ||
        !get_num(c, root, "eye_buffer_scale", &h->eye_buffer_scale) ||
        !get_num(c, root, "peak_luminance", &h->peak_luminance))
        return false;
    h->screen_width = size[0];
    h->screen_height = size[1];
    return prw_hmd_validate(h, c->file, c->e);
}

bool prw_hmd_parse(const char *text, size_t size, const char *file, prw_hmd *out, prw_error *e)
{
    ctx c = {file ? file : "(hmd)", e};
    if (!text) return prw_json_fail_at(&c, "", "no text");
    cJSON *root = prw_json_doc_parse(text, size, c.file, e);
    if (!root) return false;
    prw_hmd h;
    bool ok = parse_root(&c, root, &h);
    if (ok) *out = h;
    cJSON_Delete(root);
    return ok;
}

bool prw_hmd_load(const char *path, prw_hmd *out, prw_error *e)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot open: not a regular file", path);
    char *text = NULL;
    size_t size = 0;
    /* profiles are a few hundred bytes: 1 MiB is generous, and bounds the JSON tree */
    if (!prw_read_file_bounded(path, (1u << 20), PRW_JSON_MEMORY_PER_BYTE, "an HMD profile", &text, &size, e)) return false;
    bool ok = prw_hmd_parse(text, size, path, out, e);
    free(text);
    return ok;
}

bool prw_hmd_resolve(const char *name_or_path, prw_hmd *out, prw_error *e)
{
    if (!name_or_path || !name_or_path[0]) return prw_fail(e, "hmd: empty profile name");
    if (prw_hmd_builtin(name_or_path, out)) return true;
    size_t n = strlen(name_or_path);
    if (n > 5 && strcmp(name_or_path + n - 5, ".json") == 0) return prw_hmd_load(name_or_path, out, e);
    return prw_fail(e, "hmd '%s': not a built-in profile (dk2) nor a .json file", name_or_path);
}

/* ---- composition ---- */

void prw_compose_params_hmd(const prw_hmd *h, const prw_view eyes[2], uint32_t out_w, uint32_t out_h,
                            prw_compose_params *p)
{
    memset(p, 0, sizeof *p);
    p->mode = PRW_COMPOSE_HMD;
    p->out_w = out_w;
    p->out_h = out_h;
    p->eye_w = eyes[0].width;
    p->eye_h = eyes[0].height;
    p->screen_w = h->screen_width;
    p->screen_h = h->screen_height;
    p->lens_unit = prw_hmd_lens_unit(h);
    p->eye_to_screen = h->eye_to_screen;
    for (int k = 0; k < 2; k++) {
        p->lens_x[k] = prw_hmd_lens_centre_x(h, k);
        p->tan[k][0] = eyes[k].tan_left;
        p->tan[k][1] = eyes[k].tan_right;
        p->tan[k][2] = eyes[k].tan_bottom;
        p->tan[k][3] = eyes[k].tan_top;
    }
    memcpy(p->k, h->k, sizeof p->k);
    memcpy(p->ca, h->ca, sizeof p->ca);
}

void prw_compose_params_sbs(uint32_t eye_w, uint32_t eye_h, uint32_t out_w, uint32_t out_h, prw_compose_params *p)
{
    memset(p, 0, sizeof *p);
    p->mode = PRW_COMPOSE_SIDE_BY_SIDE;
    p->out_w = out_w;
    p->out_h = out_h;
    p->eye_w = eye_w;
    p->eye_h = eye_h;
}

void prw_compose_source(const prw_compose_params *p, uint32_t i, uint32_t j, int channel, int *eye, double *u,
                        double *v)
{
    uint32_t half = p->out_w / 2;
    int k = i >= half ? 1 : 0;
    *eye = k;
    double x = (double)(i - (k ? half : 0)) + 0.5, y = (double)j + 0.5;
    if (p->mode == PRW_COMPOSE_SIDE_BY_SIDE) {
        *u = x / (double)half * (double)p->eye_w;
        *v = y / (double)p->out_h * (double)p->eye_h;
        return;
    }
    /* panel metres from the panel centre (x right, y up), then lens-centred normalised */
    double X = ((double)i + 0.5) / (double)p->out_w * p->screen_w - 0.5 * p->screen_w;
    double Y = 0.5 * p->screen_h - y / (double)p->out_h * p->screen_h;
    double px = (X - p->lens_x[k]) / p->lens_unit, py = Y / p->lens_unit, r2 = px * px + py * py;
    double d = 1.0 + r2 * (p->k[0] + r2 * (p->k[1] + r2 * (p->k[2] + r2 * p->k[3])));
    double s = channel == 0 ? p->ca[0] + p->ca[1] * r2 : channel == 2 ? p->ca[2] + p->ca[3] * r2 : 1.0;
    double f = d * s * p->lens_unit / p->eye_to_screen; /* normalised -> tangent */
    double tx = px * f, ty = py * f;
    const double *t = p->tan[k];
    *u = (tx - t[0]) / (t[1] - t[0]) * (double)p->eye_w;
    *v = (t[3] - ty) / (t[3] - t[2]) * (double)p->eye_h;
}

double prw_compose_sample(const float *rgba, uint32_t w, uint32_t h, int channel, double u, double v)
{
    if (!(u >= 0 && v >= 0 && u <= (double)w && v <= (double)h)) return 0.0;
    double x = u - 0.5, y = v - 0.5;
    double fx0 = floor(x), fy0 = floor(y);
    double fx = x - fx0, fy = y - fy0;
    int x0 = (int)fx0, y0 = (int)fy0, x1 = x0 + 1, y1 = y0 + 1;
    int wm = (int)w - 1, hm = (int)h - 1;
    x0 = x0 < 0 ? 0 : x0 > wm ? wm : x0;
    x1 = x1 < 0 ? 0 : x1 > wm ? wm : x1;
    y0 = y0 < 0 ? 0 : y0 > hm ? hm : y0;
    y1 = y1 < 0 ? 0 : y1 > hm ? hm : y1;
    double a = rgba[((size_t)y0 * w + (size_t)x0) * 4 + channel], b = rgba[((size_t)y0 * w + (size_t)x1) * 4 + channel];
    double c = rgba[((size_t)y1 * w + (size_t)x0) * 4 + channel], d = rgba[((size_t)y1 * w + (size_t)x1) * 4 + channel];
    return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy;
}

void prw_compose_cpu(const prw_compose_params *p, const float *left, const float *right, float *out)
{
    for (uint32_t j = 0; j < p->out_h; j++)
        for (uint32_t i = 0; i < p->out_w; i++) {
            float *o = out + ((size_t)j * p->out_w + i) * 4;
            for (int c = 0; c < 3; c++) {
                int eye;
                double u, v;
                prw_compose_source(p, i, j, c, &eye, &u, &v);
                o[c] = (float)prw_compose_sample(eye ? right : left, p->eye_w, p->eye_h, c, u, v);
            }
            o[3] = 1.0f;
        }
}

/* ---- stereo setup ---- */

bool prw_stereo_setup_desktop(const prw_view *centre, double ipd, double screen_distance, prw_stereo_setup *out,
                              prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (!prw_stereo_desktop(centre, ipd, screen_distance, out->eyes, e)) return false;
    out->eye_w = centre->width;
    out->eye_h = centre->height;
    prw_compose_params_sbs(out->eye_w, out->eye_h, 2 * out->eye_w, out->eye_h, &out->compose);
    return true;
}

bool prw_stereo_setup_hmd(const prw_view *centre, const prw_hmd *h, uint32_t panel_w, uint32_t panel_h,
                          prw_stereo_setup *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (!panel_w) panel_w = h->panel_width;
    if (!panel_h) panel_h = h->panel_height;
    if (panel_w < 2 || panel_w % 2 || panel_h < 1 || panel_w > 16384 || panel_h > 16384)
        return prw_fail(e, "hmd '%s': panel %ux%u must have an even width in 2..16384", h->name, panel_w, panel_h);
    prw_hmd_eye_size(h, panel_w, panel_h, &out->eye_w, &out->eye_h);
    if (out->eye_w > 16384 || out->eye_h > 16384)
        return prw_fail(e, "hmd '%s': eye buffer %ux%u too large", h->name, out->eye_w, out->eye_h);
    prw_fov fov[2];
    prw_hmd_eye_fov(h, 0, &fov[0]);
    prw_hmd_eye_fov(h, 1, &fov[1]);
    if (!prw_stereo_hmd(centre, h->ipd, fov, out->eye_w, out->eye_h, out->eyes, e)) return false;
    prw_compose_params_hmd(h, out->eyes, panel_w, panel_h, &out->compose);
    return true;
}
