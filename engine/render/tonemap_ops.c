/* tonemap_ops.c — the C reference of the tone-mapping operators (prw_tonemap.h).  Double precision;
 * shaders/tonemap_apply.comp mirrors it line by line in float. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_tonemap.h"

static const char *const k_names[PRW_TM_OP_COUNT] = {"exposure", "reinhard", "neutral", "adaptive",
                                                     "absolute", "local",    "selective"};

const char *prw_tm_op_name(prw_tm_op op) { return (unsigned)op < PRW_TM_OP_COUNT ? k_names[op] : "?"; }
const char *prw_tm_op_list(void) { return "exposure, reinhard, neutral, adaptive, absolute, local, selective"; }

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
    p->sel_threshold = s->sel_threshold > 0 ? s->sel_threshold : PRW_TM_SEL_THRESHOLD;
    p->sel_tile = s->sel_tile > 0 ? (int)s->sel_tile : PRW_TM_SEL_TILE;
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

double prw_tm_adapt_step(double la, double target, double dt, double tau_bright, double tau_dark)
{
    if (!(dt > 0)) return la;
    double tau = target > la ? tau_bright : tau_dark;
    if (!(tau > 0)) return target;
    return target + (la - target) * exp(-dt / tau);
}

void prw_tm_set_adaptation(prw_tm_params *p, double la)
{
    p->adapt_la = la > 0 && isfinite(la) ? fmax(la, PRW_TM_LOG_DELTA) : 0.0;
    if (p->adapt_la > 0 && (p->op == PRW_TM_EXPOSURE || p->op == PRW_TM_NEUTRAL || p->op == PRW_TM_ADAPTIVE))
        p->exposure = p->key / p->adapt_la;
}

void prw_tm_derive(const prw_tm_params *p, const prw_tm_stats *st, prw_tm_frame *f)
{
    memset(f, 0, sizeof *f);
    double lavg = fmax(p->adapt_la > 0 ? p->adapt_la : st->log_avg, PRW_TM_LOG_DELTA);
    f->rh_scale = p->key / lavg;
    double w = p->white > 0 ? p->white : PRW_TM_WHITE_HEADROOM * f->rh_scale * st->max_lum;
    f->rh_white2 = fmax(w * w, 1e-12);
    /* adaptive shoulder over u in [0, U], U = ln(largest L' / W) = ln(exposure * max) */
    double U = log(fmax(PRW_TM_WHITE_HEADROOM * p->exposure * st->max_lum, 1e-30));
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
    case PRW_TM_LOCAL:
    case PRW_TM_SELECTIVE: return x / (1.0 + x);
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

static unsigned finish(const prw_tm_params *p, const double r[3], double ry, unsigned flags, double v[3]);

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
    case PRW_TM_LOCAL:
    case PRW_TM_SELECTIVE: { /* no neighbourhood: the global curve Ld = L / (1 + L) */
        double ls = f->rh_scale * L;
        return prw_tm_pixel_ratio(p, rgb_in, ls / (1.0 + ls), v);
    }
    default: r[0] = r[1] = r[2] = ry = 0; break;
    }
    return finish(p, r, ry, flags, v);
}

unsigned prw_tm_pixel_ratio(const prw_tm_params *p, const float rgb_in[3], double ld, double v[3])
{
    double c[3] = {sanitize(rgb_in[0]), sanitize(rgb_in[1]), sanitize(rgb_in[2])};
    double L = lum3(c), r[3];
    unsigned flags = 0;
    if (!(ld <= 1.0)) { /* also NaN */
        flags |= PRW_TM_ABOVE;
        ld = 1.0;
    }
    ld = fmax(ld, 0.0);
    double k = L > 0 ? ld / L : 0.0;
    for (int i = 0; i < 3; i++) r[i] = c[i] * k;
    return finish(p, r, ld, flags, v);
}

/* Gamut mapping and encoding of display-relative r (working primaries) with luminance ry. */
static unsigned finish(const prw_tm_params *p, const double r[3], double ry, unsigned flags, double v[3])
{
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

/* ---- procedural HDR stills ---- */

double prw_tm_field(prw_image *img, int w, int h, double dr, unsigned seed)
{
    prw_error e;
    if (!prw_image_alloc(img, w, h, &e)) return 0;
    double ph = seed * 1.7;
    double lo = 1e30, hi = -1e30;
    int n = w * h;
    /* raw smooth field, then normalised to [0, 1] so the range is exactly dr decades */
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double x = (i + 0.5) / w, y = (j + 0.5) / h;
            double f = sin(6.1 * x + ph) * cos(4.3 * y - 0.5 * ph) + 0.6 * sin(13.7 * (x + y) + 2 * ph) +
                       0.3 * cos(29.0 * x * y + ph);
            img->rgba[4 * (j * w + i)] = (float)f;
            lo = fmin(lo, f);
            hi = fmax(hi, f);
        }
    double sum = 0;
    for (int k = 0; k < n; k++) {
        double t = (img->rgba[4 * k] - lo) / (hi - lo);
        double Y = 50.0 * pow(10.0, dr * (t - 0.5));
        /* chroma from position: mix of a hue and white, luminance preserved */
        double hue = 6.2831853 * (k % w) / (double)w + ph, s = 0.5;
        double c[3] = {1 + s * cos(hue), 1 + s * cos(hue - 2.094), 1 + s * cos(hue + 2.094)};
        double cy = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
        for (int q = 0; q < 3; q++) img->rgba[4 * k + q] = (float)(Y * c[q] / cy);
        img->rgba[4 * k + 3] = 1.0f;
        sum += log(1e-6 + Y);
    }
    return 0.18 / exp(sum / n);
}

/* ---- local operator (Reinhard et al. 2002 eqs. 5-9) and the selective framework ---- */

double prw_tm_local_sigma(int level)
{
    /* alpha_1 s_j / sqrt 2 with alpha_1 = 1 / (2 sqrt 2), s_j = 1.6^j: 0.25 * 1.6^j */
    return 0.25 * pow(1.6, level);
}

int prw_tm_local_radius(int level)
{
    int r = (int)ceil(3.0 * prw_tm_local_sigma(level) - 1e-9);
    return r < 1 ? 1 : r;
}

/* Normalised kernel weights k[0..R] (symmetric). */
static void gauss_kernel(int level, double *k)
{
    double sg = prw_tm_local_sigma(level), sum = 0;
    int R = prw_tm_local_radius(level);
    for (int i = 0; i <= R; i++) {
        k[i] = exp(-(double)(i * i) / (2.0 * sg * sg));
        sum += i ? 2 * k[i] : k[i];
    }
    for (int i = 0; i <= R; i++) k[i] /= sum;
}

static int clampi(int v, int lo, int hi) { return v < lo ? lo : v > hi ? hi : v; }

bool prw_tm_local_ld(const double *L, int w, int h, double key, double *ld, double *margin, prw_error *e)
{
    size_t n = (size_t)w * (size_t)h;
    double *tmp = malloc(n * sizeof *tmp), *v1 = malloc(n * sizeof *v1), *v2 = malloc(n * sizeof *v2);
    double *chosen = malloc(n * sizeof *chosen);
    unsigned char *done = calloc(n, 1);
    if (!tmp || !v1 || !v2 || !chosen || !done) {
        free(tmp), free(v1), free(v2), free(chosen), free(done);
        return prw_fail(e, "tonemap: out of memory for the local operator (%dx%d)", w, h);
    }
    double k[64];
    for (int lev = 0; lev <= PRW_TM_LOCAL_SCALES; lev++) {
        int R = prw_tm_local_radius(lev);
        gauss_kernel(lev, k);
        double *dst = lev == 0 ? v1 : v2; /* v1 = level lev - 1, v2 = level lev */
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                double s = 0;
                for (int q = -R; q <= R; q++) s += k[abs(q)] * L[(size_t)y * w + clampi(x + q, 0, w - 1)];
                tmp[(size_t)y * w + x] = s;
            }
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                double s = 0;
                for (int q = -R; q <= R; q++) s += k[abs(q)] * tmp[(size_t)clampi(y + q, 0, h - 1) * w + x];
                dst[(size_t)y * w + x] = s;
            }
        if (lev == 0) {
            memcpy(chosen, v1, n * sizeof *chosen);
            if (margin)
                for (size_t i = 0; i < n; i++) margin[i] = INFINITY;
            continue;
        }
        double sc = pow(1.6, lev - 1), den0 = pow(2.0, PRW_TM_LOCAL_PHI) * key / (sc * sc);
        for (size_t i = 0; i < n; i++) {
            if (done[i]) continue;
            double vv = (v1[i] - v2[i]) / (den0 + v1[i]);
            if (margin) margin[i] = fmin(margin[i], fabs(fabs(vv) - PRW_TM_LOCAL_EPS));
            if (fabs(vv) < PRW_TM_LOCAL_EPS) chosen[i] = v1[i];
            else done[i] = 1;
        }
        memcpy(v1, v2, n * sizeof *v1);
    }
    for (size_t i = 0; i < n; i++) ld[i] = L[i] / (1.0 + chosen[i]);
    free(tmp), free(v1), free(v2), free(chosen), free(done);
    return true;
}

int prw_tm_classify(const prw_image *hdr, int tile, double threshold, uint8_t *marks, double *grad)
{
    int w = hdr->width, h = hdr->height, tx = (w + tile - 1) / tile, ty = (h + tile - 1) / tile;
    double *lg = malloc((size_t)w * h * sizeof *lg), *tg = calloc((size_t)tx * ty, sizeof *tg);
    if (!lg || !tg) {
        free(lg), free(tg);
        return -1;
    }
    for (int i = 0; i < w * h; i++) lg[i] = log10(PRW_TM_LOG_DELTA + prw_tm_input_lum(hdr->rgba + 4 * i));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int xm = clampi(x - 1, 0, w - 1), xp = clampi(x + 1, 0, w - 1);
            int ym = clampi(y - 1, 0, h - 1), yp = clampi(y + 1, 0, h - 1);
#define LG(i, j) lg[(size_t)(j) * w + (i)]
            double gx = (LG(xp, ym) + 2 * LG(xp, y) + LG(xp, yp)) - (LG(xm, ym) + 2 * LG(xm, y) + LG(xm, yp));
            double gy = (LG(xm, yp) + 2 * LG(x, yp) + LG(xp, yp)) - (LG(xm, ym) + 2 * LG(x, ym) + LG(xp, ym));
#undef LG
            double g = sqrt(gx * gx + gy * gy) / 8.0;
            double *t = &tg[(y / tile) * tx + x / tile];
            *t = fmax(*t, g);
        }
    int count = 0;
    for (int i = 0; i < tx * ty; i++) {
        marks[i] = tg[i] > threshold;
        count += marks[i];
        if (grad) grad[i] = tg[i];
    }
    free(lg), free(tg);
    return count;
}

double prw_tm_sel_weight(const uint8_t *marks, int w, int h, int tile, int x, int y)
{
    int tx = (w + tile - 1) / tile, ty = (h + tile - 1) / tile, cx = x / tile, cy = y / tile;
    double px = x + 0.5, py = y + 0.5, d2 = INFINITY;
    for (int j = cy - 1; j <= cy + 1; j++)
        for (int i = cx - 1; i <= cx + 1; i++) {
            if (i < 0 || j < 0 || i >= tx || j >= ty || !marks[j * tx + i]) continue;
            double dx = fmax(fmax((double)i * tile - px, px - (double)(i + 1) * tile), 0.0);
            double dy = fmax(fmax((double)j * tile - py, py - (double)(j + 1) * tile), 0.0);
            d2 = fmin(d2, dx * dx + dy * dy);
        }
    if (!(d2 < INFINITY)) return 0.0;
    double t = fmin(fmax(1.0 - sqrt(d2) / tile, 0.0), 1.0);
    return t * t * (3.0 - 2.0 * t);
}

static double border_measure(const prw_image *img, int tile, bool jump)
{
    int w = img->width, h = img->height;
    double worst = 0;
    for (int dir = 0; dir < 2; dir++)
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                int along = dir == 0 ? x : y, n = dir == 0 ? w : h;
                if (along == 0 || along % tile != 0) continue;
                ptrdiff_t st = dir == 0 ? 4 : 4 * (ptrdiff_t)w;
                const float *b = img->rgba + 4 * ((size_t)y * w + x), *a = b - st;
                for (int c = 0; c < 3; c++) {
                    double d = fabs((double)b[c] - (double)a[c]);
                    if (jump) {
                        double nb = 0;
                        if (along >= 2) nb = fmax(nb, fabs((double)a[c] - (double)a[c - st]));
                        if (along + 1 < n) nb = fmax(nb, fabs((double)b[c + st] - (double)b[c]));
                        d -= nb;
                    }
                    worst = fmax(worst, d);
                }
            }
    return worst;
}

double prw_tm_border_gradient(const prw_image *img, int tile) { return border_measure(img, tile, false); }
double prw_tm_border_jump(const prw_image *img, int tile) { return border_measure(img, tile, true); }

/* Ld of the local / selective operators for a whole image (scaled luminance from the statistics). */
static bool local_field(const prw_tm_params *p, const prw_tm_frame *f, const prw_image *hdr, double *ld,
                        prw_tm_report *rep, prw_error *e)
{
    int w = hdr->width, h = hdr->height;
    size_t n = (size_t)w * h;
    double *L = malloc(n * sizeof *L);
    if (!L) return prw_fail(e, "tonemap: out of memory (%dx%d)", w, h);
    for (size_t i = 0; i < n; i++) L[i] = f->rh_scale * prw_tm_input_lum(hdr->rgba + 4 * i);
    bool ok = prw_tm_local_ld(L, w, h, p->key, ld, NULL, e);
    if (ok && p->op == PRW_TM_SELECTIVE) {
        int T = p->sel_tile, tx = (w + T - 1) / T, ty = (h + T - 1) / T;
        uint8_t *marks = malloc((size_t)tx * ty);
        int cnt = marks ? prw_tm_classify(hdr, T, p->sel_threshold, marks, NULL) : -1;
        if (cnt < 0) ok = prw_fail(e, "tonemap: out of memory (%dx%d)", w, h);
        for (int y = 0; ok && y < h; y++)
            for (int x = 0; x < w; x++) {
                size_t i = (size_t)y * w + x;
                double wt = prw_tm_sel_weight(marks, w, h, T, x, y), lg = L[i] / (1.0 + L[i]);
                ld[i] = wt * ld[i] + (1.0 - wt) * lg;
            }
        if (ok && rep) {
            int bx = (w + 15) / 16, by = (h + 15) / 16, sub = T / 16;
            rep->tiles = (uint64_t)tx * ty;
            rep->tiles_marked = (uint64_t)cnt;
            rep->blocks = (uint64_t)bx * by;
            for (int j = 0; j < by; j++)
                for (int i = 0; i < bx; i++) {
                    int ci = i / sub, cj = j / sub, need = 0;
                    for (int b = cj - 1; b <= cj + 1; b++)
                        for (int a = ci - 1; a <= ci + 1; a++)
                            if (a >= 0 && b >= 0 && a < tx && b < ty && marks[b * tx + a]) need = 1;
                    rep->blocks_local += (uint64_t)need;
                }
        }
        free(marks);
    }
    free(L);
    return ok;
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
    double *ld = NULL;
    if (p->op == PRW_TM_LOCAL || p->op == PRW_TM_SELECTIVE) {
        ld = malloc(n * sizeof *ld);
        if (!ld || !local_field(p, &f, hdr, ld, &r, e)) {
            free(ld);
            prw_image_free(out);
            return ld ? false : prw_fail(e, "tonemap: out of memory (%dx%d)", hdr->width, hdr->height);
        }
    }
    for (size_t i = 0; i < n; i++) {
        double v[3];
        unsigned fl = ld ? prw_tm_pixel_ratio(p, hdr->rgba + 4 * i, ld[i], v) : prw_tm_pixel(p, &f, hdr->rgba + 4 * i, v);
        for (int c = 0; c < 3; c++) out->rgba[4 * i + c] = (float)v[c];
        out->rgba[4 * i + 3] = 1.0f;
        r.below_black += (fl & PRW_TM_BELOW) != 0;
        r.above_peak += (fl & PRW_TM_ABOVE) != 0;
        r.out_of_gamut += (fl & PRW_TM_GAMUT) != 0;
    }
    free(ld);
    r.pixels = n;
    if (rep) *rep = r;
    return true;
}

/* ---- output files ---- */

void prw_tm_display_chroma(const prw_display *d, float c[8])
{
    /* xy of R, G, B (ITU-R BT.709, SMPTE EG 432-1 Display P3, ITU-R BT.2020) and D65, as display.c */
    static const float prim[3][6] = {{0.640f, 0.330f, 0.300f, 0.600f, 0.150f, 0.060f},
                                     {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f},
                                     {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f}};
    int i = (unsigned)d->primaries <= PRW_PRIMARIES_REC2020 ? (int)d->primaries : 0;
    memcpy(c, prim[i], sizeof prim[i]);
    c[6] = 0.3127f;
    c[7] = 0.3290f;
}

bool prw_tm_display_light(const prw_display *d, const prw_image *signal, prw_image *out, prw_error *e)
{
    if (!prw_image_alloc(out, signal->width, signal->height, e)) return false;
    size_t n = (size_t)signal->width * (size_t)signal->height;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            double v = signal->rgba[4 * i + c];
            out->rgba[4 * i + c] = (float)prw_display_luminance(d, isfinite(v) ? fmin(fmax(v, 0.0), 1.0) : 0.0);
        }
        out->rgba[4 * i + 3] = 1.0f;
    }
    return true;
}

void prw_tm_light_levels(const prw_image *signal, double *max_cll, double *max_fall)
{
    size_t n = (size_t)signal->width * (size_t)signal->height;
    double mx = 0, sum = 0;
    for (size_t i = 0; i < n; i++) {
        double m = 0;
        for (int c = 0; c < 3; c++) {
            double v = signal->rgba[4 * i + c];
            m = fmax(m, prw_pq_eotf(isfinite(v) ? fmin(fmax(v, 0.0), 1.0) : 0.0));
        }
        mx = fmax(mx, m);
        sum += m;
    }
    *max_cll = mx;
    *max_fall = n ? sum / (double)n : 0.0;
}

bool prw_tm_write_hdr10_png(const char *path, const prw_display *d, const prw_image *signal, prw_error *e)
{
    if (d->eotf != PRW_EOTF_PQ || d->primaries != PRW_PRIMARIES_REC2020)
        return prw_fail(e, "%s: HDR10 PNG: display '%s' is %s %s, not PQ Rec.2020", path, d->name,
                        prw_eotf_name(d->eotf), prw_primaries_name(d->primaries));
    size_t n = (size_t)signal->width * (size_t)signal->height;
    uint16_t *px = malloc(n * 3 * sizeof *px);
    if (!px) return prw_fail(e, "%s: HDR10 PNG: out of memory", path);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            double v = signal->rgba[4 * i + c];
            px[3 * i + c] = (uint16_t)lrint(65535.0 * (isfinite(v) ? fmin(fmax(v, 0.0), 1.0) : 0.0));
        }
    static const uint8_t cicp[4] = {9, 16, 0, 1}; /* BT.2020 primaries, PQ, identity (RGB), full range */
    prw_png_chunk ch = {"cICP", cicp, sizeof cicp};
    bool ok = prw_png_write16(path, signal->width, signal->height, 3, px, &ch, 1, e);
    free(px);
    if (!ok) return false;
    double cll, fall;
    prw_tm_light_levels(signal, &cll, &fall);
    char json[512], jpath[4096];
    int len = snprintf(json, sizeof json,
                       "{\n  \"MaxCLL\": %ld,\n  \"MaxFALL\": %ld,\n  \"MaxCLL_exact\": %.4f,\n"
                       "  \"MaxFALL_exact\": %.4f,\n  \"units\": \"cd/m^2 (CTA-861.3, from the PQ signal)\",\n"
                       "  \"cicp\": [9, 16, 0, 1],\n  \"display\": \"%s\"\n}\n",
                       lround(cll), lround(fall), cll, fall, d->name);
    if (snprintf(jpath, sizeof jpath, "%s.json", path) >= (int)sizeof jpath ||
        !prw_write_file_atomic(jpath, json, (size_t)len, e)) {
        remove(path); /* no partial output: both files or none */
        if (strlen(path) + 6 > sizeof jpath) prw_fail(e, "%s: path too long for the sidecar JSON", path);
        return false;
    }
    return true;
}
