/* display.c — display profiles (prw_display.h): the display model, EOTFs, primaries, JSON profiles. */
#define _POSIX_C_SOURCE 200809L
#include "prw_display.h"
#include "prw_json_doc.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define PI 3.14159265358979323846

/* ---- transfer functions ---- */

double prw_pq_eotf(double e)
{
    /* SMPTE ST 2084 eq. 4.1: Y = (max(E^(1/m2) - c1, 0) / (c2 - c3 E^(1/m2)))^(1/m1), L = 10000 Y */
    if (!(e > 0)) e = 0;
    if (e > 1) e = 1;
    double p = pow(e, 1.0 / PRW_PQ_M2);
    double num = p - PRW_PQ_C1;
    if (num < 0) num = 0;
    return 10000.0 * pow(num / (PRW_PQ_C2 - PRW_PQ_C3 * p), 1.0 / PRW_PQ_M1);
}

double prw_pq_inverse(double cd_m2)
{
    /* ST 2084 eq. 5.2: E = ((c1 + c2 Y^m1) / (1 + c3 Y^m1))^m2, Y = L / 10000 */
    double y = cd_m2 / 10000.0;
    if (!(y > 0)) y = 0;
    if (y > 1) y = 1;
    double p = pow(y, PRW_PQ_M1);
    return pow((PRW_PQ_C1 + PRW_PQ_C2 * p) / (1.0 + PRW_PQ_C3 * p), PRW_PQ_M2);
}

double prw_srgb_decode(double v)
{
    if (!(v > 0)) return 0;
    if (v > 1) v = 1;
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

double prw_srgb_encode(double x)
{
    if (!(x > 0)) return 0;
    if (x > 1) x = 1;
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1.0 / 2.4) - 0.055;
}

/* ---- the display model ---- */

double prw_display_reflection(const prw_display *d) { return d->reflectivity / PI * d->ambient; }
double prw_display_min(const prw_display *d) { return d->black + prw_display_reflection(d); }
double prw_display_max(const prw_display *d) { return d->peak; }

void prw_display_bt1886(const prw_display *d, double *a, double *b)
{
    *a = *b = 0;
    if (d->eotf != PRW_EOTF_BT1886) return;
    /* BT.1886 Annex 1: a = (Lw^(1/g) - Lb^(1/g))^g, b = Lb^(1/g) / (Lw^(1/g) - Lb^(1/g)) */
    double w = pow(d->peak, 1.0 / d->gamma), k = pow(d->black, 1.0 / d->gamma);
    *a = pow(w - k, d->gamma);
    *b = k / (w - k);
}

double prw_display_luminance(const prw_display *d, double v)
{
    if (!(v > 0)) v = 0;
    if (v > 1) v = 1;
    double refl = prw_display_reflection(d);
    switch (d->eotf) {
    case PRW_EOTF_SRGB: return (d->peak - d->black) * prw_srgb_decode(v) + d->black + refl;
    case PRW_EOTF_GAMMA: return (d->peak - d->black) * pow(v, d->gamma) + d->black + refl;
    case PRW_EOTF_BT1886: {
        double a, b;
        prw_display_bt1886(d, &a, &b);
        return a * pow(fmax(v + b, 0.0), d->gamma) + refl;
    }
    case PRW_EOTF_PQ: {
        double l = prw_pq_eotf(v);
        return fmin(fmax(l, d->black), d->peak) + refl;
    }
    }
    return 0;
}

double prw_display_signal(const prw_display *d, double cd_m2)
{
    double lo = prw_display_min(d), hi = prw_display_max(d);
    double l = isnan(cd_m2) ? lo : fmin(fmax(cd_m2, lo), hi);
    double refl = prw_display_reflection(d);
    switch (d->eotf) {
    case PRW_EOTF_SRGB: return prw_srgb_encode((l - d->black - refl) / (d->peak - d->black));
    case PRW_EOTF_GAMMA: {
        double x = (l - d->black - refl) / (d->peak - d->black);
        return x > 0 ? pow(fmin(x, 1.0), 1.0 / d->gamma) : 0.0;
    }
    case PRW_EOTF_BT1886: {
        double a, b;
        prw_display_bt1886(d, &a, &b);
        double v = pow(fmax(l - refl, 0.0) / a, 1.0 / d->gamma) - b;
        return fmin(fmax(v, 0.0), 1.0);
    }
    case PRW_EOTF_PQ: return prw_pq_inverse(l - refl);
    }
    return 0;
}

/* ---- primaries ---- */

static void inv3(const double m[9], double o[9])
{
    double a = m[0], b = m[1], c = m[2], d = m[3], e = m[4], f = m[5], g = m[6], h = m[7], i = m[8];
    double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    double det = a * A + b * B + c * C;
    o[0] = A / det;
    o[1] = -(b * i - c * h) / det;
    o[2] = (b * f - c * e) / det;
    o[3] = B / det;
    o[4] = (a * i - c * g) / det;
    o[5] = -(a * f - c * d) / det;
    o[6] = C / det;
    o[7] = -(a * h - b * g) / det;
    o[8] = (a * e - b * d) / det;
}

static void mul3(const double a[9], const double b[9], double o[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) o[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}

void prw_primaries_to_xyz(prw_primaries p, double m[9])
{
    /* xy chromaticities of R, G, B (ITU-R BT.709, SMPTE EG 432-1 Display P3, ITU-R BT.2020), D65 white */
    static const double xy[3][6] = {
        {0.640, 0.330, 0.300, 0.600, 0.150, 0.060},
        {0.680, 0.320, 0.265, 0.690, 0.150, 0.060},
        {0.708, 0.292, 0.170, 0.797, 0.131, 0.046},
    };
    const double wx = 0.3127, wy = 0.3290;
    int k = p == PRW_PRIMARIES_P3 ? 1 : p == PRW_PRIMARIES_REC2020 ? 2 : 0;
    double P[9];
    for (int c = 0; c < 3; c++) { /* column c: XYZ of primary c with Y = 1 */
        double x = xy[k][2 * c], y = xy[k][2 * c + 1];
        P[c] = x / y;
        P[3 + c] = 1.0;
        P[6 + c] = (1.0 - x - y) / y;
    }
    double Pi[9], W[3] = {wx / wy, 1.0, (1.0 - wx - wy) / wy}, S[3];
    inv3(P, Pi);
    for (int r = 0; r < 3; r++) S[r] = Pi[3 * r] * W[0] + Pi[3 * r + 1] * W[1] + Pi[3 * r + 2] * W[2];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) m[3 * r + c] = P[3 * r + c] * S[c];
}

void prw_display_matrix(const prw_display *d, double m[9])
{
    if (d->primaries == PRW_PRIMARIES_REC709) {
        static const double id[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        memcpy(m, id, sizeof id);
        return;
    }
    double a[9], b[9], bi[9];
    prw_primaries_to_xyz(PRW_PRIMARIES_REC709, a);
    prw_primaries_to_xyz(d->primaries, b);
    inv3(b, bi);
    mul3(bi, a, m);
}

const char *prw_eotf_name(prw_eotf e)
{
    static const char *const n[] = {"srgb", "gamma", "bt1886", "pq"};
    return (unsigned)e < 4 ? n[e] : "?";
}

const char *prw_primaries_name(prw_primaries p)
{
    static const char *const n[] = {"rec709", "p3", "rec2020"};
    return (unsigned)p < 3 ? n[p] : "?";
}

bool prw_display_validate(const prw_display *d, const char *who, prw_error *e)
{
    if (!(isfinite(d->peak) && d->peak > 0 && d->peak <= 10000))
        return prw_fail(e, "%s: peak %g cd/m^2 out of range (0, 10000]", who, d->peak);
    if (!(isfinite(d->black) && d->black >= 0 && d->black < d->peak))
        return prw_fail(e, "%s: black %g cd/m^2 must be in [0, peak)", who, d->black);
    if (!(isfinite(d->reflectivity) && d->reflectivity >= 0 && d->reflectivity <= 1))
        return prw_fail(e, "%s: reflectivity %g out of range [0, 1]", who, d->reflectivity);
    if (!(isfinite(d->ambient) && d->ambient >= 0 && d->ambient <= 2e5))
        return prw_fail(e, "%s: ambient %g lux out of range [0, 200000]", who, d->ambient);
    if (d->eotf != PRW_EOTF_PQ && d->eotf != PRW_EOTF_SRGB && !(isfinite(d->gamma) && d->gamma >= 1 && d->gamma <= 4))
        return prw_fail(e, "%s: gamma %g out of range [1, 4]", who, d->gamma);
    double lmin = prw_display_min(d);
    if (!(lmin < 0.5 * d->peak))
        return prw_fail(e, "%s: black + reflection %g cd/m^2 leaves no range below peak %g", who, lmin, d->peak);
    if (!(isfinite(d->ref_white) && d->ref_white > lmin && d->ref_white <= d->peak))
        return prw_fail(e, "%s: reference white %g cd/m^2 must be in (black + reflection = %g, peak = %g]", who,
                        d->ref_white, lmin, d->peak);
    if (!(d->bits == 8 || d->bits == 10 || d->bits == 12 || d->bits == 16))
        return prw_fail(e, "%s: bits %u must be 8, 10, 12 or 16", who, d->bits);
    if (!(isfinite(d->ppd) && d->ppd >= 0 && d->ppd <= 1000))
        return prw_fail(e, "%s: pixels_per_degree %g out of range [0, 1000]", who, d->ppd);
    return true;
}

/* ---- built-in profiles (the same tuples as assets/displays/NAME.json; a test checks they agree) ---- */

static const prw_display k_builtin[] = {
    {"srgb", PRW_EOTF_SRGB, PRW_PRIMARIES_REC709, 2.4, 80, 0, 0, 0, 80, 0, 8, false},
    {"office-lcd", PRW_EOTF_GAMMA, PRW_PRIMARIES_REC709, 2.2, 100, 0.8, 0.01, 400, 80, 40, 8, false},
    {"default-lcd", PRW_EOTF_GAMMA, PRW_PRIMARIES_REC709, 2.2, 200, 0.8, 0.01, 60, 160, 40, 8, false},
    {"bright-lcd", PRW_EOTF_GAMMA, PRW_PRIMARIES_REC709, 2.6, 500, 0.5, 0.01, 10, 400, 40, 8, false},
    {"hdr10-1000", PRW_EOTF_PQ, PRW_PRIMARIES_REC2020, 0, 1000, 0.005, 0.01, 5, 203, 40, 10, false},
    {"hmd-lcd", PRW_EOTF_SRGB, PRW_PRIMARIES_REC709, 2.4, 100, 0.1, 0, 0, 80, 20, 8, true},
};
static const char *const k_builtin_names[] = {"srgb",       "office-lcd", "default-lcd", "bright-lcd",
                                              "hdr10-1000", "hmd-lcd",    NULL};

const char *const *prw_display_builtin_names(void) { return k_builtin_names; }

bool prw_display_builtin(const char *name, prw_display *out)
{
    for (size_t i = 0; i < PRW_ARRAY_LEN(k_builtin); i++)
        if (name && strcmp(name, k_builtin[i].name) == 0) {
            *out = k_builtin[i];
            return true;
        }
    return false;
}

/* ---- JSON ---- */

#define PLACE_MAX 96

typedef prw_json_ctx ctx;

static const cJSON *item(const cJSON *obj, const char *key) { return cJSON_GetObjectItemCaseSensitive(obj, key); }

static bool get_num(ctx *c, const cJSON *o, const char *key, double *out, bool required, double lo, double hi)
{
    const cJSON *v = item(o, key);
    if (!v) return required ? prw_json_fail_at(c, key, "missing (required)") : true;
    double x = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    if (!(isfinite(x) && x >= lo && x <= hi)) return prw_json_fail_at(c, key, "must be a finite number in [%g, %g]", lo, hi);
    *out = x;
    return true;
}

static bool get_enum(ctx *c, const cJSON *o, const char *key, const char *const *names, int n, int *out,
                     bool required)
{
    const cJSON *v = item(o, key);
    if (!v) return required ? prw_json_fail_at(c, key, "missing (required)") : true;
    if (cJSON_IsString(v))
        for (int i = 0; i < n; i++)
            if (strcmp(v->valuestring, names[i]) == 0) {
                *out = i;
                return true;
            }
    char list[128] = "";
    for (int i = 0; i < n; i++) {
        strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
        strncat(list, names[i], sizeof list - strlen(list) - 1);
    }
    return prw_json_fail_at(c, key, "must be one of %s", list);
}

static bool parse_root(ctx *c, const cJSON *root, prw_display *d)
{
    static const char *const keys[] = {"prw_display", "name",      "description", "eotf",
                                       "gamma",       "peak",      "black",       "reflectivity",
                                       "ambient",     "primaries", "reference_white_fraction",
                                       "reference_white", "pixels_per_degree", "bits", "hmd"};
    if (!cJSON_IsObject(root)) return prw_json_fail_at(c, "", "top level must be a JSON object");
    if (!prw_json_check_keys(c, root, "", keys, (int)PRW_ARRAY_LEN(keys))) return false;
    const cJSON *v = item(root, "prw_display");
    if (!v) return prw_json_fail_at(c, "prw_display", "missing (required; this reader understands version 1)");
    if (!cJSON_IsNumber(v) || v->valuedouble != 1.0)
        return prw_json_fail_at(c, "prw_display", "unsupported version (this reader understands 1)");
    memset(d, 0, sizeof *d);
    v = item(root, "name");
    if (!cJSON_IsString(v) || !v->valuestring[0] || strlen(v->valuestring) >= sizeof d->name)
        return prw_json_fail_at(c, "name", "must be a non-empty string shorter than %zu bytes", sizeof d->name);
    snprintf(d->name, sizeof d->name, "%s", v->valuestring);
    v = item(root, "description");
    if (v && !cJSON_IsString(v)) return prw_json_fail_at(c, "description", "must be a string");
    static const char *const eotfs[] = {"srgb", "gamma", "bt1886", "pq"};
    static const char *const prims[] = {"rec709", "p3", "rec2020"};
    int eo = 0, pr = 0;
    if (!get_enum(c, root, "eotf", eotfs, 4, &eo, true) || !get_enum(c, root, "primaries", prims, 3, &pr, false))
        return false;
    d->eotf = (prw_eotf)eo;
    d->primaries = (prw_primaries)pr;
    d->gamma = d->eotf == PRW_EOTF_SRGB ? 2.4 : 0;
    if (d->eotf == PRW_EOTF_GAMMA || d->eotf == PRW_EOTF_BT1886) {
        if (!get_num(c, root, "gamma", &d->gamma, true, 1, 4)) return false;
    } else if (item(root, "gamma")) {
        return prw_json_fail_at(c, "gamma", "only for the gamma and bt1886 EOTFs");
    }
    double frac = NAN, white = NAN, bits = 0, ppd = 0;
    if (!get_num(c, root, "peak", &d->peak, true, 1e-3, 10000) || !get_num(c, root, "black", &d->black, true, 0, 1e4) ||
        !get_num(c, root, "reflectivity", &d->reflectivity, true, 0, 1) ||
        !get_num(c, root, "ambient", &d->ambient, true, 0, 2e5) ||
        !get_num(c, root, "reference_white_fraction", &frac, false, 1e-3, 1) ||
        !get_num(c, root, "reference_white", &white, false, 1e-3, 10000) ||
        !get_num(c, root, "pixels_per_degree", &ppd, false, 0, 1000) || !get_num(c, root, "bits", &bits, false, 8, 16))
        return false;
    if (isnan(frac) == isnan(white))
        return prw_json_fail_at(c, "", "give exactly one of reference_white_fraction and reference_white");
    d->ref_white = isnan(white) ? frac * d->peak : white;
    d->ppd = ppd;
    if (bits > 0 && bits != floor(bits)) return prw_json_fail_at(c, "bits", "must be an integer");
    d->bits = bits > 0 ? (uint32_t)bits : (d->eotf == PRW_EOTF_PQ ? 10u : 8u);
    v = item(root, "hmd");
    if (v && !cJSON_IsBool(v)) return prw_json_fail_at(c, "hmd", "must be true or false");
    d->hmd = v && cJSON_IsTrue(v);
    return prw_display_validate(d, c->file, c->e);
}

bool prw_display_parse(const char *text, size_t size, const char *file, prw_display *out, prw_error *e)
{
    ctx c = {file ? file : "(display)", e};
    if (!text) return prw_json_fail_at(&c, "", "no text");
    cJSON *root = prw_json_doc_parse(text, size, c.file, e);
    if (!root) return false;
    prw_display d;
    bool ok = parse_root(&c, root, &d);
    if (ok) *out = d;
    cJSON_Delete(root);
    return ok;
}

bool prw_display_load(const char *path, prw_display *out, prw_error *e)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot open: not a regular file", path);
    char *text = NULL;
    size_t size = 0;
    /* profiles are a few hundred bytes: 1 MiB is generous, and bounds the JSON tree */
    if (!prw_read_file_bounded(path, (1u << 20), PRW_JSON_MEMORY_PER_BYTE, "a display profile", &text, &size, e)) return false;
    bool ok = prw_display_parse(text, size, path, out, e);
    free(text);
    return ok;
}

bool prw_display_resolve(const char *name_or_path, prw_display *out, prw_error *e)
{
    if (!name_or_path || !name_or_path[0]) return prw_fail(e, "display: empty profile name");
    if (prw_display_builtin(name_or_path, out)) return true;
    size_t n = strlen(name_or_path);
    if (n > 5 && strcmp(name_or_path + n - 5, ".json") == 0) return prw_display_load(name_or_path, out, e);
    char list[256] = "";
    for (const char *const *p = k_builtin_names; *p; p++) {
        strncat(list, p == k_builtin_names ? "" : ", ", sizeof list - strlen(list) - 1);
        strncat(list, *p, sizeof list - strlen(list) - 1);
    }
    return prw_fail(e, "display '%s': not a built-in profile (%s) nor a .json file", name_or_path, list);
}
