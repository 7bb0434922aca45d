/* flip.c — LDR-FLIP and HDR-FLIP, implemented from the published definitions:
 *   [F20] Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild 2020, "FLIP: A Difference
 *         Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2).
 *   [F21] Andersson, Nilsson, Shirley, Akenine-Möller 2021, "Visualizing Errors in Rendered High
 *         Dynamic Range Images", Eurographics short papers (HDR-FLIP).
 *
 * LDR-FLIP of display-linear RGB in [0,1] ([F20] Sec. 3-4):
 *  colour:  linear RGB -> XYZ (D65) -> YCxCz (Yy = 116 Y/Yn - 16, Cx = 500 (X/Xn - Y/Yn),
 *           Cz = 200 (Y/Yn - Z/Zn)) -> spatial CSF filter per channel -> linear RGB, clamp [0,1]
 *           -> CIELAB -> Hunt adjustment (a, b *= 0.01 L) -> HyAB distance (|dL| + ||(da, db)||)
 *           -> ^qc (qc = 0.7) -> redistribution to [0,1] with cmax = HyAB(green, blue)^qc,
 *           pc = 0.4, pt = 0.95.
 *  feature: on Y/Yn of the unfiltered image; edges and points from first / second derivatives of
 *           a Gaussian with sigma = 0.5 w ppd, w = 0.082 degrees, radius ceil(3 sigma);
 *           dEf = ((1/sqrt 2) max(|d edge|, |d point|))^qf, qf = 0.5.
 *  combined: dE = dEc^(1 - dEf).
 * CSF filters ([F20] Sec. 3.1): S(x) = a1 sqrt(pi/b1) exp(-pi^2 x^2/b1) + a2 sqrt(pi/b2)
 * exp(-pi^2 x^2/b2), x the distance in degrees (pixels / ppd), with
 *   achromatic:  a1 = 1,    b1 = 0.0047, a2 = 0,    b2 = 1e-5
 *   red-green:   a1 = 1,    b1 = 0.0053, a2 = 0,    b2 = 1e-5
 *   blue-yellow: a1 = 34.1, b1 = 0.04,   a2 = 13.5, b2 = 0.025
 * one radius for all three, r = ceil(3 sqrt(b_max / (2 pi^2)) ppd), b_max = 0.04, and each kernel
 * normalised to sum 1 (so a flat image is unchanged).
 * Borders (a prw choice; [F20] does not fix one): clamp-to-edge for every convolution.
 *
 * Colour matrices: the IEC 61966-2-1 (sRGB) RGB->XYZ matrix with its published 4 decimals; the
 * inverse is the exact double-precision inverse of that matrix, so RGB -> XYZ -> RGB round-trips.
 * Reference white = XYZ of RGB (1,1,1) = (0.9505, 1.0000, 1.0890).
 *
 * HDR-FLIP ([F21] Sec. 3): exposures start = log2(x85 / Ymax), stop = log2(x85 / Ymedian) with x85
 * the tone-mapper input giving 0.85; N = max(2, ceil(stop - start)) exposures evenly spaced;
 * each exposure c: LDR-FLIP of clamp(t(2^c * rgb)) per channel; the result is the per-pixel max.
 * Tone mapper t: the ACES fit of Narkowicz 2015 ("ACES Filmic Tone Mapping Curve") applied to
 * 0.6 x, the tone mapper [F21] uses.
 *
 * Checked (2026-12-01) against the authors' reference implementation (NVlabs/flip, src/cpp/FLIP.h,
 * read, not copied): the constants qc 0.7, pc 0.4, pt 0.95, w 0.082, qf 0.5; the CSF terms and the
 * filter radius from the largest b; the separable blue-yellow normalisation (2-D kernel sums to 1);
 * the clamp to [0,1] in linear RGB after CSF filtering; feature input (Y + 16) / 116 of the
 * unfiltered image; feature kernels (Gaussian sums to 1, derivative lobes to +1 / -1); feature error
 * (max(|d edge|, |d point|) / sqrt 2)^qf and colour^(1 - feature); the ACES coefficients with 0.6
 * pre-exposure, per-channel tone map + clamp, N = max(2, ceil(stop - start)).  Differences: the
 * RGB->XYZ matrix and reference white here are the 4-digit sRGB ones (FLIP.h uses exact
 * fractions; the difference is < 1e-4 relative).
 */
#include "prw_metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- colour ------------------------------------------------------------------------------ */

static const double M_RGB2XYZ[9] = {0.4124, 0.3576, 0.1805, 0.2126, 0.7152, 0.0722, 0.0193, 0.1192, 0.9505};
static const double M_XYZ2RGB[9] = {3.240625477320054,   -1.5372079722103185,  -0.4986285986982478,
                                    -0.9689307147293196, 1.8757560608852413,   0.04151752384295395,
                                    0.05571012044551063, -0.20402105059848671, 1.0569959422543882};
/* Reference white: row sums of M_RGB2XYZ. */
#define WHITE_X (0.4124 + 0.3576 + 0.1805)
#define WHITE_Y (0.2126 + 0.7152 + 0.0722)
#define WHITE_Z (0.0193 + 0.1192 + 0.9505)

#define FLIP_PI 3.14159265358979323846
#define FLIP_QC 0.7  /* [F20] colour exponent */
#define FLIP_PC 0.4  /* [F20] redistribution breakpoint (fraction of cmax) */
#define FLIP_PT 0.95 /* [F20] redistribution value at the breakpoint */
#define FLIP_QF 0.5  /* [F20] feature exponent */
#define FLIP_W 0.082 /* [F20] feature width in degrees; sigma = 0.5 w ppd */

static void mat3(const double m[9], const double v[3], double out[3])
{
    for (int i = 0; i < 3; i++) out[i] = m[i * 3] * v[0] + m[i * 3 + 1] * v[1] + m[i * 3 + 2] * v[2];
}

void prw_flip_linrgb_to_xyz(const float rgb[3], float xyz[3])
{
    double v[3] = {rgb[0], rgb[1], rgb[2]}, o[3];
    mat3(M_RGB2XYZ, v, o);
    for (int i = 0; i < 3; i++) xyz[i] = (float)o[i];
}

void prw_flip_xyz_to_linrgb(const float xyz[3], float rgb[3])
{
    double v[3] = {xyz[0], xyz[1], xyz[2]}, o[3];
    mat3(M_XYZ2RGB, v, o);
    for (int i = 0; i < 3; i++) rgb[i] = (float)o[i];
}

static void rgb_to_ycxcz_d(const double rgb[3], double out[3])
{
    double xyz[3];
    mat3(M_RGB2XYZ, rgb, xyz);
    double xn = xyz[0] / WHITE_X, yn = xyz[1] / WHITE_Y, zn = xyz[2] / WHITE_Z;
    out[0] = 116.0 * yn - 16.0;
    out[1] = 500.0 * (xn - yn);
    out[2] = 200.0 * (yn - zn);
}

static void ycxcz_to_rgb_d(const double ycc[3], double rgb[3])
{
    double yn = (ycc[0] + 16.0) / 116.0;
    double xyz[3] = {(ycc[1] / 500.0 + yn) * WHITE_X, yn * WHITE_Y, (yn - ycc[2] / 200.0) * WHITE_Z};
    mat3(M_XYZ2RGB, xyz, rgb);
}

void prw_flip_linrgb_to_ycxcz(const float rgb[3], float ycxcz[3])
{
    double v[3] = {rgb[0], rgb[1], rgb[2]}, o[3];
    rgb_to_ycxcz_d(v, o);
    for (int i = 0; i < 3; i++) ycxcz[i] = (float)o[i];
}

void prw_flip_ycxcz_to_linrgb(const float ycxcz[3], float rgb[3])
{
    double v[3] = {ycxcz[0], ycxcz[1], ycxcz[2]}, o[3];
    ycxcz_to_rgb_d(v, o);
    for (int i = 0; i < 3; i++) rgb[i] = (float)o[i];
}

/* CIELAB f(t): t^(1/3) above (6/29)^3, else t / (3 (6/29)^2) + 4/29 (CIE 15:2004). */
static double lab_f(double t)
{
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

static void rgb_to_lab_d(const double rgb[3], double lab[3])
{
    double xyz[3];
    mat3(M_RGB2XYZ, rgb, xyz);
    double fx = lab_f(xyz[0] / WHITE_X), fy = lab_f(xyz[1] / WHITE_Y), fz = lab_f(xyz[2] / WHITE_Z);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

static void hunt_d(double lab[3])
{
    lab[1] *= 0.01 * lab[0];
    lab[2] *= 0.01 * lab[0];
}

static double hyab_d(const double p[3], const double q[3])
{
    double da = p[1] - q[1], db = p[2] - q[2];
    return fabs(p[0] - q[0]) + sqrt(da * da + db * db);
}

void prw_flip_linrgb_to_lab(const float rgb[3], float lab[3])
{
    double v[3] = {rgb[0], rgb[1], rgb[2]}, o[3];
    rgb_to_lab_d(v, o);
    for (int i = 0; i < 3; i++) lab[i] = (float)o[i];
}

void prw_flip_hunt(float lab[3])
{
    float l = lab[0];
    lab[1] *= 0.01f * l;
    lab[2] *= 0.01f * l;
}

double prw_flip_hyab(const float lab1[3], const float lab2[3])
{
    double p[3] = {lab1[0], lab1[1], lab1[2]}, q[3] = {lab2[0], lab2[1], lab2[2]};
    return hyab_d(p, q);
}

double prw_flip_color_cmax(void)
{
    double green[3] = {0, 1, 0}, blue[3] = {0, 0, 1}, lg[3], lb[3];
    rgb_to_lab_d(green, lg);
    rgb_to_lab_d(blue, lb);
    hunt_d(lg);
    hunt_d(lb);
    return pow(hyab_d(lg, lb), FLIP_QC);
}

double prw_flip_color_redistribute(double x, double cmax)
{
    double b = FLIP_PC * cmax;
    double v = x < b ? (FLIP_PT / b) * x : FLIP_PT + ((x - b) / (cmax - b)) * (1.0 - FLIP_PT);
    return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

static double color_error_d(const double t[3], const double r[3], double cmax)
{
    double lt[3], lr[3];
    rgb_to_lab_d(t, lt);
    rgb_to_lab_d(r, lr);
    hunt_d(lt);
    hunt_d(lr);
    return prw_flip_color_redistribute(pow(hyab_d(lt, lr), FLIP_QC), cmax);
}

double prw_flip_color_error(const float rgb_test[3], const float rgb_ref[3])
{
    double t[3], r[3];
    for (int i = 0; i < 3; i++) {
        t[i] = rgb_test[i] < 0.0f ? 0.0 : rgb_test[i] > 1.0f ? 1.0 : rgb_test[i];
        r[i] = rgb_ref[i] < 0.0f ? 0.0 : rgb_ref[i] > 1.0f ? 1.0 : rgb_ref[i];
    }
    return color_error_d(t, r, prw_flip_color_cmax());
}

/* ---- separable convolution with clamp-to-edge ------------------------------------------------ */

/* dst = src * k along x (axis 0) or y (axis 1); src and dst are distinct w*h planes, k has 2r+1
 * taps.  Borders clamp to the edge.  Accumulates in double. */
static void convolve_axis(const float *src, float *dst, int w, int h, const double *k, int r, int axis)
{
    if (axis == 0) {
        double *row = prw_malloc(((size_t)w + 2 * (size_t)r) * sizeof(double));
        for (int y = 0; y < h; y++) {
            const float *s = src + (size_t)y * (size_t)w;
            for (int i = -r; i < w + r; i++) row[i + r] = s[i < 0 ? 0 : i >= w ? w - 1 : i];
            float *d = dst + (size_t)y * (size_t)w;
            for (int x = 0; x < w; x++) {
                const double *p = row + x;
                double acc = 0.0;
                for (int t = 0; t <= 2 * r; t++) acc += k[t] * p[t];
                d[x] = (float)acc;
            }
        }
        free(row);
    } else {
        double *acc = prw_malloc((size_t)w * sizeof(double));
        for (int y = 0; y < h; y++) {
            for (int x = 0; x < w; x++) acc[x] = 0.0;
            for (int t = -r; t <= r; t++) {
                int yy = y + t;
                yy = yy < 0 ? 0 : yy >= h ? h - 1 : yy;
                const float *s = src + (size_t)yy * (size_t)w;
                double kt = k[t + r];
                for (int x = 0; x < w; x++) acc[x] += kt * s[x];
            }
            float *d = dst + (size_t)y * (size_t)w;
            for (int x = 0; x < w; x++) d[x] = (float)acc[x];
        }
        free(acc);
    }
}

/* ---- CSF ------------------------------------------------------------------------------------- */

static const double CSF[3][4] = {
    /* a1, b1, a2, b2 — [F20] Sec. 3.1 */
    {1.0, 0.0047, 0.0, 1e-5},
    {1.0, 0.0053, 0.0, 1e-5},
    {34.1, 0.04, 13.5, 0.025},
};
#define CSF_BMAX 0.04

int prw_flip_csf_radius(double ppd)
{
    return (int)ceil(3.0 * sqrt(CSF_BMAX / (2.0 * FLIP_PI * FLIP_PI)) * ppd);
}

/* The two Gaussian terms of a channel as 1-D factors e_i(d) = exp(-pi^2 (d/ppd)^2 / b_i) with
 * weights c_i = a_i sqrt(pi / b_i) / S, S the 2-D sum, so K(dx, dy) = sum_i c_i e_i(dx) e_i(dy)
 * sums to 1.  Returns the number of terms (1 or 2). */
static int csf_terms(int channel, double ppd, int r, double *e1, double *e2, double c[2])
{
    int n = 0;
    double *es[2] = {e1, e2};
    double sums[2] = {0, 0};
    for (int t = 0; t < 2; t++) {
        double a = CSF[channel][t * 2], b = CSF[channel][t * 2 + 1];
        if (a == 0.0) continue;
        double *e = es[n];
        for (int d = -r; d <= r; d++) {
            double x = (double)d / ppd;
            e[d + r] = exp(-FLIP_PI * FLIP_PI * x * x / b);
            sums[n] += e[d + r];
        }
        c[n] = a * sqrt(FLIP_PI / b);
        n++;
    }
    double total = 0.0;
    for (int t = 0; t < n; t++) total += c[t] * sums[t] * sums[t];
    for (int t = 0; t < n; t++) c[t] /= total;
    return n;
}

int prw_flip_csf_kernel(int channel, double ppd, double *k)
{
    int r = prw_flip_csf_radius(ppd), taps = 2 * r + 1;
    if (!k) return r;
    double *e1 = prw_malloc((size_t)taps * sizeof(double)), *e2 = prw_malloc((size_t)taps * sizeof(double)), c[2];
    int n = csf_terms(channel, ppd, r, e1, e2, c);
    for (int y = 0; y < taps; y++)
        for (int x = 0; x < taps; x++)
            k[y * taps + x] = c[0] * e1[x] * e1[y] + (n > 1 ? c[1] * e2[x] * e2[y] : 0.0);
    free(e1);
    free(e2);
    return r;
}

void prw_flip_csf_filter(float *ycxcz, int w, int h, double ppd)
{
    int r = prw_flip_csf_radius(ppd), taps = 2 * r + 1;
    size_t n = (size_t)w * (size_t)h;
    double *e[2] = {prw_malloc((size_t)taps * sizeof(double)), prw_malloc((size_t)taps * sizeof(double))};
    float *tmp = prw_malloc(n * sizeof(float)), *acc = prw_malloc(n * sizeof(float));
    float *term = prw_malloc(n * sizeof(float)), *plane = prw_malloc(n * sizeof(float));
    for (int ch = 0; ch < 3; ch++) {
        double c[2];
        int terms = csf_terms(ch, ppd, r, e[0], e[1], c);
        for (size_t i = 0; i < n; i++) plane[i] = ycxcz[i * 3 + ch];
        for (int t = 0; t < terms; t++) {
            convolve_axis(plane, tmp, w, h, e[t], r, 0);
            convolve_axis(tmp, term, w, h, e[t], r, 1);
            for (size_t i = 0; i < n; i++) acc[i] = (float)((t ? acc[i] : 0.0) + c[t] * term[i]);
        }
        for (size_t i = 0; i < n; i++) ycxcz[i * 3 + ch] = acc[i];
    }
    free(e[0]);
    free(e[1]);
    free(tmp);
    free(acc);
    free(term);
    free(plane);
}

/* ---- features -------------------------------------------------------------------------------- */

int prw_flip_feature_radius(double ppd) { return (int)ceil(3.0 * 0.5 * FLIP_W * ppd); }

/* Scales positive weights to sum 1 and negative weights to sum -1. */
static void normalize_pos_neg(double *k, int taps)
{
    double pos = 0.0, neg = 0.0;
    for (int i = 0; i < taps; i++) {
        if (k[i] > 0) pos += k[i];
        else neg -= k[i];
    }
    for (int i = 0; i < taps; i++) {
        if (k[i] > 0) k[i] /= pos;
        else if (k[i] < 0) k[i] /= neg;
    }
}

int prw_flip_feature_kernels(double ppd, double *gauss, double *edge, double *point)
{
    double sigma = 0.5 * FLIP_W * ppd;
    int r = prw_flip_feature_radius(ppd), taps = 2 * r + 1;
    double gs = 0.0;
    for (int d = -r; d <= r; d++) {
        double x = d, g = exp(-x * x / (2.0 * sigma * sigma));
        gauss[d + r] = g;
        gs += g;
        edge[d + r] = -x * g;
        point[d + r] = (x * x / (sigma * sigma) - 1.0) * g;
    }
    for (int i = 0; i < taps; i++) gauss[i] /= gs;
    normalize_pos_neg(edge, taps);
    normalize_pos_neg(point, taps);
    return r;
}

void prw_flip_features(const float *achromatic, int w, int h, double ppd, float *edge, float *point)
{
    int r = prw_flip_feature_radius(ppd), taps = 2 * r + 1;
    size_t n = (size_t)w * (size_t)h;
    double *g = prw_malloc((size_t)taps * sizeof(double)), *d1 = prw_malloc((size_t)taps * sizeof(double));
    double *d2 = prw_malloc((size_t)taps * sizeof(double));
    prw_flip_feature_kernels(ppd, g, d1, d2);
    float *tmp = prw_malloc(n * sizeof(float)), *gx = prw_malloc(n * sizeof(float));
    float *gy = prw_malloc(n * sizeof(float));
    const double *kernels[2] = {d1, d2};
    float *outs[2] = {edge, point};
    for (int f = 0; f < 2; f++) {
        /* x derivative: derivative along x, Gaussian along y; y derivative: the transpose. */
        convolve_axis(achromatic, tmp, w, h, kernels[f], r, 0);
        convolve_axis(tmp, gx, w, h, g, r, 1);
        convolve_axis(achromatic, tmp, w, h, g, r, 0);
        convolve_axis(tmp, gy, w, h, kernels[f], r, 1);
        for (size_t i = 0; i < n; i++) outs[f][i] = (float)sqrt((double)gx[i] * gx[i] + (double)gy[i] * gy[i]);
    }
    free(g);
    free(d1);
    free(d2);
    free(tmp);
    free(gx);
    free(gy);
}

double prw_flip_feature_error(double edge_test, double edge_ref, double point_test, double point_ref)
{
    double m = fmax(fabs(edge_test - edge_ref), fabs(point_test - point_ref));
    return pow(m / sqrt(2.0), FLIP_QF);
}

double prw_flip_combine(double color_error, double feature_error) { return pow(color_error, 1.0 - feature_error); }

/* ---- LDR-FLIP ------------------------------------------------------------------------------ */

static bool same_size(const prw_image *a, const prw_image *b, const char *who, prw_error *e)
{
    if (a->width != b->width || a->height != b->height)
        return prw_fail(e, "%s: size: test %dx%d differs from reference %dx%d", who, a->width, a->height, b->width,
                        b->height);
    if (a->width <= 0 || a->height <= 0) return prw_fail(e, "%s: size: empty image", who);
    return true;
}

/* Core on two display-linear RGB planes (w*h*3, values in [0,1]). */
static void flip_ldr_planes(const float *test, const float *ref, int w, int h, double ppd, float *map)
{
    size_t n = (size_t)w * (size_t)h;
    float *ycc[2] = {prw_malloc(n * 3 * sizeof(float)), prw_malloc(n * 3 * sizeof(float))};
    float *ach[2] = {prw_malloc(n * sizeof(float)), prw_malloc(n * sizeof(float))};
    float *edge[2] = {prw_malloc(n * sizeof(float)), prw_malloc(n * sizeof(float))};
    float *point[2] = {prw_malloc(n * sizeof(float)), prw_malloc(n * sizeof(float))};
    const float *src[2] = {test, ref};
    for (int k = 0; k < 2; k++) {
        for (size_t i = 0; i < n; i++) {
            double rgb[3] = {src[k][i * 3], src[k][i * 3 + 1], src[k][i * 3 + 2]}, o[3];
            rgb_to_ycxcz_d(rgb, o);
            for (int c = 0; c < 3; c++) ycc[k][i * 3 + c] = (float)o[c];
            ach[k][i] = (float)((o[0] + 16.0) / 116.0); /* = Y / Yn of the unfiltered image */
        }
        prw_flip_csf_filter(ycc[k], w, h, ppd);
        prw_flip_features(ach[k], w, h, ppd, edge[k], point[k]);
    }
    double cmax = prw_flip_color_cmax();
    for (size_t i = 0; i < n; i++) {
        double rgb[2][3];
        for (int k = 0; k < 2; k++) {
            double v[3] = {ycc[k][i * 3], ycc[k][i * 3 + 1], ycc[k][i * 3 + 2]};
            ycxcz_to_rgb_d(v, rgb[k]);
            for (int c = 0; c < 3; c++) rgb[k][c] = rgb[k][c] < 0.0 ? 0.0 : rgb[k][c] > 1.0 ? 1.0 : rgb[k][c];
        }
        double dc = color_error_d(rgb[0], rgb[1], cmax);
        double df = prw_flip_feature_error(edge[0][i], edge[1][i], point[0][i], point[1][i]);
        map[i] = (float)prw_flip_combine(dc, df);
    }
    for (int k = 0; k < 2; k++) {
        free(ycc[k]);
        free(ach[k]);
        free(edge[k]);
        free(point[k]);
    }
}

static float clamp01f(float v) { return v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; /* NaN -> 0 */ }

static bool valid_ppd(double ppd, prw_error *e)
{
    if (!(ppd > 0.0) || !isfinite(ppd) || ppd > 1000.0)
        return prw_fail(e, "flip: ppd: %g is not in (0, 1000] pixels per degree", ppd);
    return true;
}

bool prw_flip_ldr_linear(const prw_image *test, const prw_image *ref, double ppd, float *map, prw_error *e)
{
    if (!same_size(test, ref, "ldr-flip", e) || !valid_ppd(ppd, e)) return false;
    size_t n = (size_t)ref->width * (size_t)ref->height;
    float *t = prw_malloc(n * 3 * sizeof(float)), *r = prw_malloc(n * 3 * sizeof(float));
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            t[i * 3 + c] = clamp01f(test->rgba[i * 4 + c]);
            r[i * 3 + c] = clamp01f(ref->rgba[i * 4 + c]);
        }
    flip_ldr_planes(t, r, ref->width, ref->height, ppd, map);
    free(t);
    free(r);
    return true;
}

bool prw_flip_ldr_encoded(const prw_image *test_enc, const prw_image *ref_enc, double ppd, float *map,
                          prw_error *e)
{
    if (!same_size(test_enc, ref_enc, "ldr-flip", e) || !valid_ppd(ppd, e)) return false;
    size_t n = (size_t)ref_enc->width * (size_t)ref_enc->height;
    float *t = prw_malloc(n * 3 * sizeof(float)), *r = prw_malloc(n * 3 * sizeof(float));
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            t[i * 3 + c] = prw_srgb_eotf(test_enc->rgba[i * 4 + c]);
            r[i * 3 + c] = prw_srgb_eotf(ref_enc->rgba[i * 4 + c]);
        }
    flip_ldr_planes(t, r, ref_enc->width, ref_enc->height, ppd, map);
    free(t);
    free(r);
    return true;
}

/* ---- HDR-FLIP -------------------------------------------------------------------------------- */

/* Narkowicz 2015 ACES fit f(y) = y (2.51 y + 0.03) / (y (2.43 y + 0.59) + 0.14) at y = 0.6 x. */
#define TM_A (2.51 * 0.36)
#define TM_B (0.03 * 0.6)
#define TM_C (2.43 * 0.36)
#define TM_D (0.59 * 0.6)
#define TM_F 0.14

double prw_hdrflip_tonemap(double x)
{
    if (!(x > 0.0)) return 0.0;
    double v = (TM_A * x * x + TM_B * x) / (TM_C * x * x + TM_D * x + TM_F);
    return v > 1.0 ? 1.0 : v;
}

double prw_hdrflip_tonemap_inverse(double y)
{
    /* (A - yC) x^2 + (B - yD) x - yF = 0, the positive root */
    double qa = TM_A - y * TM_C, qb = TM_B - y * TM_D, qc = -y * TM_F;
    if (y <= 0.0) return 0.0;
    if (fabs(qa) < 1e-15) return -qc / qb;
    double disc = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0) return NAN;
    return (-qb + sqrt(disc)) / (2.0 * qa);
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* numpy.median: linear interpolation between order statistics at position 0.5 (n - 1). */
static double median_sorted(const float *v, size_t n)
{
    if (n == 0) return 0.0;
    double pos = 0.5 * (double)(n - 1);
    size_t lo = (size_t)floor(pos);
    size_t hi = lo + 1 < n ? lo + 1 : lo;
    double f = pos - (double)lo;
    return (double)v[lo] + f * ((double)v[hi] - (double)v[lo]);
}

void prw_hdrflip_exposures(const prw_image *ref, prw_flip_exposures *out)
{
    size_t n = (size_t)ref->width * (size_t)ref->height;
    float *y = prw_malloc((n ? n : 1) * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        const float *p = ref->rgba + i * 4;
        y[i] = (float)(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]);
    }
    qsort(y, n, sizeof(float), cmp_float);
    double ymax = n ? y[n - 1] : 0.0;
    double ymed = median_sorted(y, n);
    if (!(ymed > 0.0) && ymax > 0.0) {
        size_t first = 0;
        while (first < n && !(y[first] > 0.0f)) first++;
        ymed = median_sorted(y + first, n - first);
    }
    free(y);
    out->y_max = ymax;
    out->y_median = ymed;
    if (!(ymax > 0.0)) {
        out->start = out->stop = 0.0;
    } else {
        double x85 = prw_hdrflip_tonemap_inverse(0.85);
        out->start = log2(x85 / ymax);
        out->stop = log2(x85 / ymed);
    }
    int count = (int)ceil(out->stop - out->start);
    out->count = count > 2 ? count : 2;
}

double prw_hdrflip_exposure(const prw_flip_exposures *x, int i)
{
    return x->start + (double)i * (x->stop - x->start) / (double)(x->count - 1);
}

bool prw_flip_hdr(const prw_image *test, const prw_image *ref, double ppd, float *map,
                  prw_flip_exposures *exposures, prw_error *e)
{
    if (!same_size(test, ref, "hdr-flip", e) || !valid_ppd(ppd, e)) return false;
    prw_flip_exposures x;
    prw_hdrflip_exposures(ref, &x);
    if (exposures) *exposures = x;
    size_t n = (size_t)ref->width * (size_t)ref->height;
    float *t = prw_malloc(n * 3 * sizeof(float)), *r = prw_malloc(n * 3 * sizeof(float));
    float *m = prw_malloc(n * sizeof(float));
    for (size_t i = 0; i < n; i++) map[i] = 0.0f;
    for (int k = 0; k < x.count; k++) {
        double s = exp2(prw_hdrflip_exposure(&x, k));
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++) {
                t[i * 3 + c] = (float)prw_hdrflip_tonemap(s * test->rgba[i * 4 + c]);
                r[i * 3 + c] = (float)prw_hdrflip_tonemap(s * ref->rgba[i * 4 + c]);
            }
        flip_ldr_planes(t, r, ref->width, ref->height, ppd, m);
        for (size_t i = 0; i < n; i++)
            if (m[i] > map[i]) map[i] = m[i];
    }
    free(t);
    free(r);
    free(m);
    return true;
}

/* ---- pooling --------------------------------------------------------------------------------- */

static double weighted_quantile(const double *hist, double total, double q)
{
    if (!(total > 0.0)) return 0.0;
    double target = q * total, cum = 0.0;
    for (int k = 0; k < PRW_FLIP_HIST_BINS; k++) {
        if (hist[k] > 0.0 && cum + hist[k] >= target) {
            double f = (target - cum) / hist[k];
            return ((double)k + f) / PRW_FLIP_HIST_BINS;
        }
        cum += hist[k];
    }
    return 1.0;
}

void prw_flip_pool(const float *map, size_t n, prw_flip_stats *out)
{
    memset(out, 0, sizeof *out);
    if (n == 0) return;
    double *hist = prw_calloc(PRW_FLIP_HIST_BINS, sizeof(double));
    double sum = 0.0, mn = INFINITY, mx = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        double v = map[i];
        sum += v;
        mn = v < mn ? v : mn;
        mx = v > mx ? v : mx;
        double c = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
        int k = (int)(c * PRW_FLIP_HIST_BINS);
        if (k >= PRW_FLIP_HIST_BINS) k = PRW_FLIP_HIST_BINS - 1;
        hist[k] += c;
    }
    double total = 0.0;
    for (int k = 0; k < PRW_FLIP_HIST_BINS; k++) total += hist[k];
    out->mean = sum / (double)n;
    out->min = mn;
    out->max = mx;
    out->weighted_q1 = weighted_quantile(hist, total, 0.25);
    out->weighted_median = weighted_quantile(hist, total, 0.5);
    out->weighted_q3 = weighted_quantile(hist, total, 0.75);
    free(hist);
}
