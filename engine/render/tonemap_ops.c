/* tonemap_ops.c — the C reference of the tone-mapping operators (prw_tonemap.h).  Double precision;
 * shaders/tonemap_apply.comp mirrors it line by line in float. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_tonemap.h"

static const char *const k_names[PRW_TM_OP_COUNT] = {"exposure", "reinhard", "neutral", "adaptive", "absolute"};

const char *prw_tm_op_name(prw_tm_op op) { return (unsigned)op < PRW_TM_OP_COUNT ? k_names[op] : "?"; }
const char *prw_tm_op_list(void) { return "exposure, reinhard, neutral, adaptive, absolute"; }

bool prw_tm_op_parse(const char *name, prw_tm_op *out, prw_error *e)
{
    for (int i = 0; i < PRW_TM_OP_COUNT; i++)
        if (name && strcmp(name, k_names[i]) == 0) {
            *out = (prw_tm_op)i;
            return true;
        }
    return prw_fail(e, "tone-mapping operator '%s' unknown (one of %s)", name ? name : "", prw_tm_op_list());
}

/* Rec.709 / sRGB luminance weights (the working primaries, D65). */
static double lum3(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static double sanitize(float x)
{
    if (isnan(x) || !(x > 0)) return 0.0;
    return x > PRW_TM_INPUT_MAX ? PRW_TM_INPUT_MAX : (double)x;
}

double prw_tm_input_lum(const float rgb[3])
{
    double c[3] = {sanitize(rgb[0]), sanitize(rgb[1]), sanitize(rgb[2])};
    return lum3(c);
}

/* ---- PBR Neutral (Khronos, 2024), from the published formula ---- */

void prw_tm_pbr_neutral(const double in[3], double out[3])
{
    const double start = 0.8 - 0.04, desat = 0.15;
    double c[3] = {in[0], in[1], in[2]};
    double x = fmin(c[0], fmin(c[1], c[2]));
    double offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    for (int i = 0; i < 3; i++) c[i] -= offset;
    double peak = fmax(c[0], fmax(c[1], c[2]));
    if (peak < start) {
        memcpy(out, c, sizeof c);
        return;
    }
    double d = 1.0 - start;
    double np = 1.0 - d * d / (peak + d - start);
    for (int i = 0; i < 3; i++) c[i] *= np / peak;
    double g = 1.0 - 1.0 / (desat * (peak - np) + 1.0);
    for (int i = 0; i < 3; i++) out[i] = c[i] * (1.0 - g) + np * g;
}

static double neutral_grey(double v)
{
    double c[3] = {v, v, v}, o[3];
    prw_tm_pbr_neutral(c, o);
    return o[0];
}

/* ---- parameters ---- */

void prw_tm_prepare(const prw_tonemap_settings *s, const prw_display *d, double exposure, prw_tm_params *p)
{
    memset(p, 0, sizeof *p);
    p->op = s->op;
    p->eotf = d->eotf;
    p->overlay = s->overlay;
    p->exposure = exposure > 0 && isfinite(exposure) ? exposure : 1.0;
    p->lmin = prw_display_min(d);
    p->lmax = prw_display_max(d);
    p->dl = p->lmax - p->lmin;
    p->black = d->black;
    p->peak = d->peak;
    p->refl = prw_display_reflection(d);
    p->gamma = d->gamma > 0 ? d->gamma : 2.2;
    p->enc_scale = p->dl / (d->peak - d->black);
    prw_display_bt1886(d, &p->bt_a, &p->bt_b);
    p->white_cd = d->ref_white;
    double wr = (d->ref_white - p->lmin) / p->dl; /* reference white, display-relative */
    if (s->op == PRW_TM_EXPOSURE) {
        p->gain = wr;
    } else if (s->op == PRW_TM_NEUTRAL) {
        double target = fmin(wr, 0.98), lo = 1e-6, hi = 1e6;
        for (int i = 0; i < 200; i++) { /* neutral_grey is increasing: bisection in log g */
            double mid = sqrt(lo * hi);
            if (neutral_grey(mid) < target) lo = mid;
            else hi = mid;
        }
        p->gain = sqrt(lo * hi);
    }
    p->key = s->key > 0 ? s->key : 0.18;
    p->white = s->white > 0 ? s->white : 0.0;
    /* adaptive toe: K = min(4 L_min, W / 2); none on a display without black or reflection */
    p->knee = p->lmin > 0 ? fmin(4.0 * p->lmin, 0.5 * p->white_cd) : 0.0;
    p->toe_p = p->knee > 0 ? p->knee / (p->knee - p->lmin) : 1.0;
    prw_display_matrix(d, p->m);
}

void prw_tm_stats_image(const prw_image *hdr, prw_tm_stats *out)
{
    size_t n = (size_t)hdr->width * (size_t)hdr->height;
    double sum = 0, mx = 0;
    for (size_t i = 0; i < n; i++) {
        double y = prw_tm_input_lum(hdr->rgba + 4 * i);
        sum += log(PRW_TM_LOG_DELTA + y);
        mx = fmax(mx, y);
    }
    out->count = n;
    out->log_avg = n ? exp(sum / (double)n) : PRW_TM_LOG_DELTA;
    out->max_lum = mx;
}

void prw_tm_derive(const prw_tm_params *p, const prw_tm_stats *st, prw_tm_frame *f)
{
    memset(f, 0, sizeof *f);
    double lavg = fmax(st->log_avg, PRW_TM_LOG_DELTA);
    f->rh_scale = p->key / lavg;
    double w = p->white > 0 ? p->white : f->rh_scale * st->max_lum;
    f->rh_white2 = fmax(w * w, 1e-12);
    /* adaptive shoulder over u in [0, U], U = ln(largest L' / W) = ln(exposure * max) */
    double U = log(fmax(p->exposure * st->max_lum, 1e-30));
    double V = log(p->lmax / p->white_cd);
    f->sh_v = V;
    if (V > 0 && U > V * (1.0 + 1e-6)) {
        double lam = PRW_TM_SHOULDER_LAMBDA;
        f->sh_on = 1;
        f->sh_m = lam * V / U;
        f->sh_a = 1.0 - f->sh_m;
        f->sh_b = (f->sh_a * U / ((1.0 - lam) * V) - 1.0) / U;
    }
}

/* Adaptive: L' = W x (cd/m^2) -> display-relative luminance. */
static double adaptive_rel(const prw_tm_params *p, const prw_tm_frame *f, double lp)
{
    if (p->knee > 0 && lp < p->knee) return (p->knee - p->lmin) / p->dl * pow(lp / p->knee, p->toe_p);
    if (lp <= p->white_cd || f->sh_on == 0) return (fmin(lp, p->lmax) - p->lmin) / p->dl;
    double u = log(lp / p->white_cd);
    double v = fmin(f->sh_a * u / (1.0 + f->sh_b * u) + f->sh_m * u, f->sh_v);
    return (p->white_cd * exp(v) - p->lmin) / p->dl;
}

double prw_tm_grey(const prw_tm_params *p, const prw_tm_frame *f, double x)
{
    switch (p->op) {
    case PRW_TM_EXPOSURE: return fmin(fmax(p->gain * x, 0.0), 1.0);
    case PRW_TM_REINHARD: return x / (1.0 + x) * (1.0 + x / f->rh_white2);
    case PRW_TM_NEUTRAL: return neutral_grey(p->gain * x);
    case PRW_TM_ADAPTIVE: return adaptive_rel(p, f, p->white_cd * x);
    case PRW_TM_ABSOLUTE: {
        double l = x / p->exposure;
        return (fmin(fmax(l, p->lmin), p->lmax) - p->lmin) / p->dl;
    }
    default: return 0;
    }
}

double prw_tm_encode(const prw_tm_params *p, double r)
{
    r = fmin(fmax(r, 0.0), 1.0);
    switch (p->eotf) {
    case PRW_EOTF_SRGB: return prw_srgb_encode(r * p->enc_scale);
    case PRW_EOTF_GAMMA: {
        double x = r * p->enc_scale;
        return x > 0 ? pow(x, 1.0 / p->gamma) : 0.0;
    }
    case PRW_EOTF_BT1886: {
        double em = p->black + r * p->dl; /* emitted = total - reflection */
        return fmin(fmax(pow(em / p->bt_a, 1.0 / p->gamma) - p->bt_b, 0.0), 1.0);
    }
    case PRW_EOTF_PQ: return prw_pq_inverse(p->black + r * p->dl);
    }
    return 0;
}

unsigned prw_tm_pixel(const prw_tm_params *p, const prw_tm_frame *f, const float rgb_in[3], double v[3])
{
    double c[3] = {sanitize(rgb_in[0]), sanitize(rgb_in[1]), sanitize(rgb_in[2])};
    double L = lum3(c);
    double r[3], ry;
    unsigned flags = 0;
    switch (p->op) {
    case PRW_TM_EXPOSURE:
        for (int i = 0; i < 3; i++) {
            double x = p->gain * p->exposure * c[i];
            if (x > 1.0) flags |= PRW_TM_ABOVE;
            r[i] = fmin(x, 1.0);
        }
        ry = lum3(r);
        break;
    case PRW_TM_REINHARD: {
        double ls = f->rh_scale * L;
        double ld = ls / (1.0 + ls) * (1.0 + ls / f->rh_white2);
        if (ld > 1.0) {
            flags |= PRW_TM_ABOVE;
            ld = 1.0;
        }
        double k = L > 0 ? ld / L : 0.0;
        for (int i = 0; i < 3; i++) r[i] = c[i] * k;
        ry = ld;
        break;
    }
    case PRW_TM_NEUTRAL: {
        double x[3];
        for (int i = 0; i < 3; i++) x[i] = p->gain * p->exposure * c[i];
        prw_tm_pbr_neutral(x, r);
        ry = lum3(r);
        break;
    }
    case PRW_TM_ADAPTIVE:
    case PRW_TM_ABSOLUTE: {
        double yt; /* target total luminance, cd/m^2 */
        if (p->op == PRW_TM_ADAPTIVE) {
            ry = adaptive_rel(p, f, p->white_cd * p->exposure * L);
        } else {
            if (L < p->lmin) flags |= PRW_TM_BELOW;
            if (L > p->lmax) flags |= PRW_TM_ABOVE;
            ry = (fmin(fmax(L, p->lmin), p->lmax) - p->lmin) / p->dl;
        }
        yt = p->lmin + ry * p->dl;
        /* keep the scene's chromaticity at the target luminance: c * yt / L, made display-relative */
        for (int i = 0; i < 3; i++) r[i] = L > 0 ? ry + yt / p->dl * (c[i] / L - 1.0) : ry;
        break;
    }
    default: r[0] = r[1] = r[2] = ry = 0; break;
    }
    ry = fmin(fmax(ry, 0.0), 1.0);
    /* gamut: working -> display primaries, desaturate towards (ry, ry, ry) until inside [0, 1] */
    double d[3], t = 1.0, lim_val = 0.0;
    int lim = -1; /* the channel that limits t lands exactly on its bound (0 or 1), not a rounding of it:
                   * the inverse of a power-law EOTF has infinite slope at 0 */
    for (int i = 0; i < 3; i++) d[i] = p->m[3 * i] * r[0] + p->m[3 * i + 1] * r[1] + p->m[3 * i + 2] * r[2];
    for (int i = 0; i < 3; i++) {
        if (d[i] > 1.0 + PRW_TM_GAMUT_EPS && (1.0 - ry) / (d[i] - ry) < t) {
            t = (1.0 - ry) / (d[i] - ry);
            lim = i;
            lim_val = 1.0;
        }
        if (d[i] < -PRW_TM_GAMUT_EPS && ry / (ry - d[i]) < t) {
            t = ry / (ry - d[i]);
            lim = i;
            lim_val = 0.0;
        }
    }
    if (t < 1.0) flags |= PRW_TM_GAMUT;
    /* at L_min (and L_max) the display can only show grey: exactly, so float noise in r cannot reach
     * the infinite slope of a power-law inverse EOTF at 0 */
    if (ry <= 0.0 || ry >= 1.0) t = 0.0, lim = -1;
    for (int i = 0; i < 3; i++) v[i] = prw_tm_encode(p, i == lim ? lim_val : ry + t * (d[i] - ry));
    if (p->overlay && flags) {
        /* below black: blue; above peak: red; out of gamut only: magenta (signal values) */
        v[0] = (flags & (PRW_TM_ABOVE | PRW_TM_GAMUT)) && !(flags & PRW_TM_BELOW) ? 1.0 : 0.0;
        v[1] = 0.0;
        v[2] = (flags & (PRW_TM_BELOW | PRW_TM_GAMUT)) && !(flags & PRW_TM_ABOVE) ? 1.0 : 0.0;
    }
    return flags;
}

bool prw_tm_apply(const prw_tm_params *p, const prw_tm_stats *stats, const prw_image *hdr, prw_image *out,
                  prw_tm_report *rep, prw_error *e)
{
    prw_tm_stats st;
    if (stats) st = *stats;
    else prw_tm_stats_image(hdr, &st);
    prw_tm_frame f;
    prw_tm_derive(p, &st, &f);
    if (!prw_image_alloc(out, hdr->width, hdr->height, e)) return false;
    prw_tm_report r = {0};
    size_t n = (size_t)hdr->width * (size_t)hdr->height;
    for (size_t i = 0; i < n; i++) {
        double v[3];
        unsigned fl = prw_tm_pixel(p, &f, hdr->rgba + 4 * i, v);
        for (int c = 0; c < 3; c++) out->rgba[4 * i + c] = (float)v[c];
        out->rgba[4 * i + 3] = 1.0f;
        r.below_black += (fl & PRW_TM_BELOW) != 0;
        r.above_peak += (fl & PRW_TM_ABOVE) != 0;
        r.out_of_gamut += (fl & PRW_TM_GAMUT) != 0;
    }
    r.pixels = n;
    if (rep) *rep = r;
    return true;
}
