/* glare.c — temporal glare (prw_glare.h): pupil, aperture, PSF by FFT (kissfft), convolution. */
#include "prw_glare.h"

#include <kiss_fftnd.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- noise ---- */

static uint64_t mix64(uint64_t x)
{
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

static double lattice(int64_t i, uint32_t seed) /* in [-0.5, 0.5) */
{
    return (double)(mix64((uint64_t)i * 0x100000001B3ull ^ seed) >> 11) / 9007199254740992.0 - 0.5;
}

/* 1D value noise, 3 octaves (weights 1, 1/2, 1/4, normalised), smoothstep interpolation. */
static double value_noise(double t, uint32_t seed)
{
    double sum = 0, norm = 0, amp = 1, f = 1;
    for (int o = 0; o < 3; o++) {
        double x = t * f, fl = floor(x), u = x - fl;
        u = u * u * (3 - 2 * u);
        int64_t i = (int64_t)fl;
        sum += amp * (lattice(i, seed + 17u * (uint32_t)o) * (1 - u) + lattice(i + 1, seed + 17u * (uint32_t)o) * u);
        norm += amp;
        amp *= 0.5;
        f *= 2;
    }
    return sum / norm;
}

static double urand(uint64_t *st) { return (double)(mix64((*st)++) >> 11) / 9007199254740992.0; }

/* ---- pupil ---- */

double prw_glare_pupil_mm(double la)
{
    double l = la > 1e-6 && isfinite(la) ? la : (la > 1e-6 ? 1e12 : 1e-6);
    return 4.9 - 3.0 * tanh(0.4 * (log10(l) + 1.0));
}

double prw_glare_pupil_hippus_mm(double la, double t, uint32_t seed)
{
    double p = prw_glare_pupil_mm(la), pm = PRW_GLARE_PUPIL_MAX_MM;
    double h = p + PRW_GLARE_HIPPUS * value_noise(t / p, seed) * (pm / p) * sqrt(fmax(1.0 - p / pm, 0.0));
    return fmin(fmax(h, 1.0), pm);
}

/* ---- aperture ---- */

static int grid_n(const prw_glare_settings *s) { return s->n > 0 ? s->n : 512; }

void prw_glare_aperture(const prw_glare_settings *s, double pupil_mm, float *ap)
{
    int n = grid_n(s);
    double D = PRW_GLARE_APERTURE_MM, dx = D / n, r = 0.5 * pupil_mm;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double x = (i - n / 2) * dx, y = (j - n / 2) * dx;
            ap[(size_t)j * n + i] = x * x + y * y <= r * r ? 1.0f : 0.0f;
        }
    uint64_t st = mix64(s->seed + 1);
    /* lens fibre gratings: thin radial lines from 0.3 r to r, transmittance 0.8 */
    for (int g = 0; g < PRW_GLARE_GRATINGS; g++) {
        double phi = 6.283185307179586 * urand(&st), c = cos(phi), sn = sin(phi);
        for (double q = 0.3 * r; q <= r; q += 0.5 * dx) {
            int i = (int)lrint(q * c / dx) + n / 2, j = (int)lrint(q * sn / dx) + n / 2;
            if (i >= 0 && j >= 0 && i < n && j < n) ap[(size_t)j * n + i] *= 0.8f;
        }
    }
    /* lens particles: opaque discs of radius 0.02-0.06 mm in the lens (radius 4.5 mm), drifting */
    for (int k = 0; k < PRW_GLARE_PARTICLES; k++) {
        double rr = 4.5 * sqrt(urand(&st)), phi = 6.283185307179586 * urand(&st), rad = 0.02 + 0.04 * urand(&st);
        double px = rr * cos(phi) + 0.05 * value_noise(0.3 * s->time + k, s->seed + 5),
               py = rr * sin(phi) + 0.05 * value_noise(0.3 * s->time + k + 1000, s->seed + 5);
        int i0 = (int)floor((px - rad) / dx) + n / 2, i1 = (int)ceil((px + rad) / dx) + n / 2;
        int j0 = (int)floor((py - rad) / dx) + n / 2, j1 = (int)ceil((py + rad) / dx) + n / 2;
        for (int j = j0; j <= j1; j++)
            for (int i = i0; i <= i1; i++) {
                if (i < 0 || j < 0 || i >= n || j >= n) continue;
                double x = (i - n / 2) * dx - px, y = (j - n / 2) * dx - py;
                if (x * x + y * y <= rad * rad) ap[(size_t)j * n + i] = 0.0f;
            }
    }
    /* eyelashes: dark near-vertical lines (0.08 mm) from the top of the grid down to 0.4 r above the centre */
    for (int k = 0; k < PRW_GLARE_LASHES; k++) {
        double x0 = (urand(&st) - 0.5) * 1.6 * r, slope = (urand(&st) - 0.5) * 0.6, half = 0.04;
        for (int j = 0; j < n; j++) {
            double y = (j - n / 2) * dx;
            if (y > -0.4 * r) break;
            double xc = x0 + slope * (y + D / 2);
            for (int i = (int)floor((xc - half) / dx) + n / 2; i <= (int)ceil((xc + half) / dx) + n / 2; i++)
                if (i >= 0 && i < n && fabs((i - n / 2) * dx - xc) <= half) ap[(size_t)j * n + i] = 0.0f;
        }
    }
}

/* ---- PSF ---- */

/* CIE 1931 2-degree colour-matching functions, the multi-lobe Gaussian fit of Wyman, Sloan and Shirley
 * (JCGT 2013, "Simple analytic approximations to the CIE XYZ color matching functions"). */
static double g_lobe(double l, double mu, double s1, double s2)
{
    double t = (l - mu) / (l < mu ? s1 : s2);
    return exp(-0.5 * t * t);
}

void prw_glare_spectral_weights(double lambda_nm[PRW_GLARE_BANDS], double w[PRW_GLARE_BANDS][3])
{
    double sum[3] = {0, 0, 0};
    for (int m = 0; m < PRW_GLARE_BANDS; m++) {
        double l = PRW_GLARE_LAMBDA_MIN_NM + (PRW_GLARE_LAMBDA_MAX_NM - PRW_GLARE_LAMBDA_MIN_NM) * (m + 0.5) /
                                                 PRW_GLARE_BANDS;
        lambda_nm[m] = l;
        double x = 1.056 * g_lobe(l, 599.8, 37.9, 31.0) + 0.362 * g_lobe(l, 442.0, 16.0, 26.7) -
                   0.065 * g_lobe(l, 501.1, 20.4, 26.2);
        double y = 0.821 * g_lobe(l, 568.8, 46.9, 40.5) + 0.286 * g_lobe(l, 530.9, 16.3, 31.1);
        double z = 1.217 * g_lobe(l, 437.0, 11.8, 36.0) + 0.681 * g_lobe(l, 459.0, 26.0, 13.8);
        /* XYZ -> linear Rec.709; the negative lobes (outside the gamut) carry no light here */
        double rgb[3] = {3.2406 * x - 1.5372 * y - 0.4986 * z, -0.9689 * x + 1.8758 * y + 0.0415 * z,
                         0.0557 * x - 0.2040 * y + 1.0570 * z};
        for (int c = 0; c < 3; c++) {
            w[m][c] = rgb[c] > 0 ? rgb[c] : 0;
            sum[c] += w[m][c];
        }
    }
    for (int m = 0; m < PRW_GLARE_BANDS; m++)
        for (int c = 0; c < 3; c++) w[m][c] /= sum[c];
}

bool prw_glare_psf(const prw_glare_settings *s, double pupil_mm, float **psf_out, int *radius, prw_error *e)
{
    int n = grid_n(s);
    *psf_out = NULL;
    *radius = 0;
    if (n < 64 || n > 2048 || (n & (n - 1)))
        return prw_fail(e, "glare: grid size %d is not a power of two in [64, 2048]", n);
    double ppd = s->ppd > 0 ? s->ppd : 40.0;
    double apx = (3.141592653589793 / 180.0) / ppd; /* rad per image pixel */
    double D = PRW_GLARE_APERTURE_MM * 1e-3;
    double lambda_nm[PRW_GLARE_BANDS], w[PRW_GLARE_BANDS][3];
    prw_glare_spectral_weights(lambda_nm, w);
    int R = (int)lrint((n / 2 - 1) * lambda_nm[PRW_GLARE_BANDS - 1] * 1e-9 / (D * apx));
    if (R < 1) R = 1;
    if (R > 512) return prw_fail(e, "glare: PSF radius %d pixels at %g ppd is too large", R, ppd);
    size_t nn = (size_t)n * n, side = 2 * (size_t)R + 1;
    float *ap = malloc(nn * sizeof *ap);
    kiss_fft_cpx *in = malloc(nn * sizeof *in), *out = malloc(nn * sizeof *out);
    double *band = calloc(side * side, sizeof *band), *acc = calloc(3 * side * side, sizeof *acc);
    int dims[2] = {n, n};
    kiss_fftnd_cfg cfg = kiss_fftnd_alloc(dims, 2, 0, NULL, NULL);
    float *psf = malloc(3 * side * side * sizeof *psf);
    bool ok = ap && in && out && band && acc && cfg && psf;
    if (ok) {
        prw_glare_aperture(s, pupil_mm, ap);
        for (size_t i = 0; i < nn; i++) in[i].r = ap[i], in[i].i = 0;
        kiss_fftnd(cfg, in, out);
        /* one FFT; the PSF at wavelength l puts bin k at the angle k l / D, so each band resamples the
         * same power spectrum; bands are normalised, then summed into R, G, B by their weights */
        for (int m = 0; m < PRW_GLARE_BANDS; m++) {
            double c = lambda_nm[m] * 1e-9 / (D * apx), total = 0;
            memset(band, 0, side * side * sizeof *band);
            for (int v = 0; v < n; v++) {
                int kv = v < n / 2 ? v : v - n;
                if (kv == -n / 2) continue; /* Nyquist: no mirror bin, keep the PSF point-symmetric */
                long py = lrint(kv * c);
                if (labs(py) > R) continue;
                for (int u = 0; u < n; u++) {
                    int ku = u < n / 2 ? u : u - n;
                    if (ku == -n / 2) continue;
                    long px = lrint(ku * c);
                    if (labs(px) > R) continue;
                    const kiss_fft_cpx *f = &out[(size_t)v * n + u];
                    double pw = (double)f->r * f->r + (double)f->i * f->i;
                    band[(size_t)(py + R) * side + (size_t)(px + R)] += pw;
                    total += pw;
                }
            }
            if (!(total > 0)) band[side * side / 2] = total = 1; /* opaque aperture: a delta */
            for (int ch = 0; ch < 3; ch++) {
                if (w[m][ch] == 0) continue;
                double k = w[m][ch] / total;
                double *a = acc + (size_t)ch * side * side;
                for (size_t i = 0; i < side * side; i++) a[i] += k * band[i];
            }
        }
        for (size_t i = 0; i < 3 * side * side; i++) psf[i] = (float)acc[i];
    }
    free(ap);
    free(in);
    free(out);
    free(band);
    free(acc);
    kiss_fft_free(cfg);
    if (!ok) {
        free(psf);
        return prw_fail(e, "glare: out of memory for a %d^2 grid", n);
    }
    *psf_out = psf;
    *radius = R;
    return true;
}

/* ---- convolution ---- */

static int fast_size(int m) /* smallest size >= m with factors 2, 3, 5 only */
{
    for (int k = m;; k++) {
        int x = k;
        while (x % 2 == 0) x /= 2;
        while (x % 3 == 0) x /= 3;
        while (x % 5 == 0) x /= 5;
        if (x == 1) return k;
    }
}

bool prw_glare_apply(prw_image *img, const float *psf, int R, prw_error *e)
{
    int w = img->width, h = img->height, P = fast_size(w + 2 * R), Q = fast_size(h + 2 * R);
    size_t pq = (size_t)P * Q, side = 2 * (size_t)R + 1;
    int dims[2] = {Q, P};
    kiss_fftnd_cfg fwd = kiss_fftnd_alloc(dims, 2, 0, NULL, NULL), inv = kiss_fftnd_alloc(dims, 2, 1, NULL, NULL);
    kiss_fft_cpx *a = malloc(pq * sizeof *a), *k = malloc(pq * sizeof *k), *fa = malloc(pq * sizeof *fa),
                 *fk = malloc(pq * sizeof *fk);
    bool ok = fwd && inv && a && k && fa && fk;
    for (int c = 0; ok && c < 3; c++) {
        memset(a, 0, pq * sizeof *a);
        memset(k, 0, pq * sizeof *k);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                float v = img->rgba[4 * ((size_t)y * w + x) + c];
                a[(size_t)y * P + x].r = isnan(v) || !(v > 0) ? 0.0f : fminf(v, 1e12f);
            }
        const float *ps = psf + (size_t)c * side * side;
        for (int dy = -R; dy <= R; dy++)
            for (int dx = -R; dx <= R; dx++)
                k[(size_t)((dy + Q) % Q) * P + (size_t)((dx + P) % P)].r = ps[(size_t)(dy + R) * side + (size_t)(dx + R)];
        kiss_fftnd(fwd, a, fa);
        kiss_fftnd(fwd, k, fk);
        for (size_t i = 0; i < pq; i++) {
            float re = fa[i].r * fk[i].r - fa[i].i * fk[i].i, im = fa[i].r * fk[i].i + fa[i].i * fk[i].r;
            fa[i].r = re;
            fa[i].i = im;
        }
        kiss_fftnd(inv, fa, a);
        float scale = 1.0f / (float)pq;
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                float v = a[(size_t)y * P + x].r * scale;
                img->rgba[4 * ((size_t)y * w + x) + c] = isfinite(v) && v > 0 ? v : 0.0f;
            }
    }
    free(a);
    free(k);
    free(fa);
    free(fk);
    kiss_fft_free(fwd);
    kiss_fft_free(inv);
    if (!ok) return prw_fail(e, "glare: out of memory for a %dx%d convolution", P, Q);
    return true;
}
