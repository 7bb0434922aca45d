/* prw_env — SH irradiance, split-sum prefilter, DFG terms (see prw_env.h). */
#include "prw_env.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "prw_brdf.h"

#define ENV_PI 3.14159265358979323846

void prw_env_uv_to_dir(double u, double v, double d[3])
{
    double phi = (u - 0.5) * 2 * ENV_PI, th = v * ENV_PI;
    double s = sin(th);
    d[0] = s * sin(phi);
    d[1] = cos(th);
    d[2] = -s * cos(phi);
}

void prw_env_dir_to_uv(const double d[3], double *u, double *v)
{
    *u = 0.5 + atan2(d[0], -d[2]) / (2 * ENV_PI);
    *v = acos(fmax(-1.0, fmin(1.0, d[1]))) / ENV_PI;
}

void prw_env_lookup(const float *rgb, uint32_t w, uint32_t h, const double d[3], float out[3])
{
    double u, v;
    prw_env_dir_to_uv(d, &u, &v);
    int64_t i = (int64_t)floor(u * w), j = (int64_t)floor(v * h);
    i = ((i % (int64_t)w) + (int64_t)w) % (int64_t)w;
    j = j < 0 ? 0 : j >= (int64_t)h ? (int64_t)h - 1 : j;
    const float *p = rgb + 3 * ((size_t)j * w + (size_t)i);
    out[0] = p[0];
    out[1] = p[1];
    out[2] = p[2];
}

double prw_env_pixel_solid_angle(uint32_t w, uint32_t h, uint32_t j)
{
    return 2 * ENV_PI / w * (cos(ENV_PI * j / h) - cos(ENV_PI * (j + 1) / h));
}

void prw_env_sh_basis(const double d[3], double y[PRW_ENV_SH_COUNT])
{
    double x = d[0], yy = d[1], z = d[2];
    y[0] = 0.282094791773878143;
    y[1] = 0.488602511902919922 * yy;
    y[2] = 0.488602511902919922 * z;
    y[3] = 0.488602511902919922 * x;
    y[4] = 1.09254843059207907 * x * yy;
    y[5] = 1.09254843059207907 * yy * z;
    y[6] = 0.315391565252520050 * (3 * z * z - 1);
    y[7] = 1.09254843059207907 * x * z;
    y[8] = 0.546274215296039535 * (x * x - yy * yy);
}

static bool env_check_source(const float *rgb, uint32_t w, uint32_t h, prw_error *e)
{
    if (!rgb || w < 2 || h < 1 || w > (1u << 16) || h > (1u << 16))
        return prw_fail(e, "environment map: size %ux%u out of range (2..65536 x 1..65536)", w, h);
    for (size_t k = 0, n = (size_t)w * h * 3; k < n; k++)
        if (!isfinite(rgb[k]))
            return prw_fail(e, "environment map: pixel (%zu, %zu) channel %zu is not finite", (k / 3) % w, (k / 3) / w,
                            k % 3);
    return true;
}

bool prw_env_sh_project(const float *rgb, uint32_t w, uint32_t h, float sh[PRW_ENV_SH_COUNT][3], prw_error *e)
{
    if (!env_check_source(rgb, w, h, e)) return false;
    /* The map is constant over a pixel, so its coefficient is L times the integral of the basis over
     * the pixel: a midpoint rule on ENV_SH_SUB x ENV_SH_SUB sub-pixels with their exact solid angles. */
    enum { ENV_SH_SUB = 4 };
    double acc[PRW_ENV_SH_COUNT][3] = {{0}};
    double *ybuf = prw_malloc((size_t)w * PRW_ENV_SH_COUNT * sizeof(double));
    for (uint32_t j = 0; j < h; j++) {
        memset(ybuf, 0, (size_t)w * PRW_ENV_SH_COUNT * sizeof(double));
        for (int sj = 0; sj < ENV_SH_SUB; sj++) {
            double v0 = (j + (double)sj / ENV_SH_SUB) / h, v1 = (j + (sj + 1.0) / ENV_SH_SUB) / h;
            double dw = 2 * ENV_PI / ((double)w * ENV_SH_SUB) * (cos(ENV_PI * v0) - cos(ENV_PI * v1));
            for (uint32_t i = 0; i < w; i++)
                for (int si = 0; si < ENV_SH_SUB; si++) {
                    double d[3], y[PRW_ENV_SH_COUNT];
                    prw_env_uv_to_dir((i + (si + 0.5) / ENV_SH_SUB) / w, 0.5 * (v0 + v1), d);
                    prw_env_sh_basis(d, y);
                    for (int k = 0; k < PRW_ENV_SH_COUNT; k++) ybuf[(size_t)i * PRW_ENV_SH_COUNT + k] += y[k] * dw;
                }
        }
        for (uint32_t i = 0; i < w; i++) {
            const float *p = rgb + 3 * ((size_t)j * w + i);
            for (int k = 0; k < PRW_ENV_SH_COUNT; k++)
                for (int c = 0; c < 3; c++) acc[k][c] += ybuf[(size_t)i * PRW_ENV_SH_COUNT + k] * p[c];
        }
    }
    free(ybuf);
    for (int k = 0; k < PRW_ENV_SH_COUNT; k++)
        for (int c = 0; c < 3; c++) sh[k][c] = (float)acc[k][c];
    return true;
}

void prw_env_sh_irradiance(const float sh[PRW_ENV_SH_COUNT][3], const double n[3], float out[3])
{
    static const double A[PRW_ENV_SH_COUNT] = {ENV_PI,         2 * ENV_PI / 3, 2 * ENV_PI / 3,
                                               2 * ENV_PI / 3, ENV_PI / 4,     ENV_PI / 4,
                                               ENV_PI / 4,     ENV_PI / 4,     ENV_PI / 4};
    double y[PRW_ENV_SH_COUNT];
    prw_env_sh_basis(n, y);
    for (int c = 0; c < 3; c++) {
        double s = 0;
        for (int k = 0; k < PRW_ENV_SH_COUNT; k++) s += A[k] * sh[k][c] * y[k];
        out[c] = (float)s;
    }
}

void prw_env_hammersley(uint32_t i, uint32_t n, double *x1, double *x2)
{
    uint32_t b = i;
    b = (b << 16) | (b >> 16);
    b = ((b & 0x55555555u) << 1) | ((b & 0xAAAAAAAAu) >> 1);
    b = ((b & 0x33333333u) << 2) | ((b & 0xCCCCCCCCu) >> 2);
    b = ((b & 0x0F0F0F0Fu) << 4) | ((b & 0xF0F0F0F0u) >> 4);
    b = ((b & 0x00FF00FFu) << 8) | ((b & 0xFF00FF00u) >> 8);
    *x1 = (i + 0.5) / n;
    *x2 = b * 2.3283064365386963e-10;
}

double prw_env_level_roughness(uint32_t k, uint32_t levels)
{
    return levels <= 1 ? 0.0 : (double)k / (levels - 1);
}

/* GGX half vector (local frame, z = normal) for the sample (x1, x2). */
static void ggx_half(double alpha, double x1, double x2, double hl[3])
{
    double a2 = alpha * alpha;
    double c2 = (1 - x1) / (1 + (a2 - 1) * x1);
    double ct = sqrt(fmax(c2, 0)), st = sqrt(fmax(1 - c2, 0)), ph = 2 * ENV_PI * x2;
    hl[0] = st * cos(ph);
    hl[1] = st * sin(ph);
    hl[2] = ct;
}

static void frame(const double n[3], double t[3], double b[3])
{
    double up[3] = {0, 1, 0};
    if (fabs(n[1]) > 0.999) up[0] = 1, up[1] = 0;
    t[0] = up[1] * n[2] - up[2] * n[1];
    t[1] = up[2] * n[0] - up[0] * n[2];
    t[2] = up[0] * n[1] - up[1] * n[0];
    double l = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int k = 0; k < 3; k++) t[k] /= l;
    b[0] = n[1] * t[2] - n[2] * t[1];
    b[1] = n[2] * t[0] - n[0] * t[2];
    b[2] = n[0] * t[1] - n[1] * t[0];
}

typedef struct pf_job {
    const float *rgb;
    uint32_t w, h, out_h, levels, samples, nthreads, tid;
    float *out;
} pf_job;

static void *pf_run(void *arg)
{
    const pf_job *jb = arg;
    uint32_t ow = 2 * jb->out_h;
    for (uint32_t row = jb->tid; row < jb->levels * jb->out_h; row += jb->nthreads) {
        uint32_t k = row / jb->out_h, j = row % jb->out_h;
        double alpha = prw_alpha_from_roughness((float)prw_env_level_roughness(k, jb->levels));
        float *dst = jb->out + 3 * ((size_t)row * ow);
        for (uint32_t i = 0; i < ow; i++) {
            double d[3], t[3], b[3];
            prw_env_uv_to_dir((i + 0.5) / ow, (j + 0.5) / jb->out_h, d);
            frame(d, t, b);
            double acc[3] = {0, 0, 0}, wsum = 0;
            for (uint32_t s = 0; s < jb->samples; s++) {
                double x1, x2, hl[3];
                prw_env_hammersley(s, jb->samples, &x1, &x2);
                ggx_half(alpha, x1, x2, hl);
                double hw[3], l[3];
                for (int c = 0; c < 3; c++) hw[c] = hl[0] * t[c] + hl[1] * b[c] + hl[2] * d[c];
                double dh = hl[2];
                for (int c = 0; c < 3; c++) l[c] = 2 * dh * hw[c] - d[c];
                double nl = d[0] * l[0] + d[1] * l[1] + d[2] * l[2];
                if (nl <= 0) continue;
                double ln = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
                for (int c = 0; c < 3; c++) l[c] /= ln;
                float L[3];
                prw_env_lookup(jb->rgb, jb->w, jb->h, l, L);
                for (int c = 0; c < 3; c++) acc[c] += L[c] * nl;
                wsum += nl;
            }
            for (int c = 0; c < 3; c++) dst[3 * i + c] = wsum > 0 ? (float)(acc[c] / wsum) : 0.0f;
        }
    }
    return NULL;
}

bool prw_env_prefilter(const float *rgb, uint32_t w, uint32_t h, uint32_t out_h, uint32_t levels, uint32_t samples,
                       float *out, prw_error *e)
{
    if (!env_check_source(rgb, w, h, e)) return false;
    if (out_h < 1 || out_h > 16384 || levels < 1 || levels > 64 || samples < 1 || samples > (1u << 20) || !out)
        return prw_fail(e, "environment prefilter: out of range: height %u (1..16384), levels %u (1..64), samples %u "
                           "(1..1048576)",
                        out_h, levels, samples);
    int nt = prw_threads_get();
    if (nt < 1) nt = 1;
    if (nt > 64) nt = 64;
    pf_job jobs[64];
    pthread_t th[64];
    bool started[64] = {false};
    for (int t = 0; t < nt; t++) {
        jobs[t] = (pf_job){rgb, w, h, out_h, levels, samples, (uint32_t)nt, (uint32_t)t, out};
        if (t > 0) started[t] = pthread_create(&th[t], NULL, pf_run, &jobs[t]) == 0;
    }
    pf_run(&jobs[0]);
    for (int t = 1; t < nt; t++) {
        if (started[t])
            pthread_join(th[t], NULL);
        else
            pf_run(&jobs[t]); /* no thread to be had: the same rows on this one */
    }
    return true;
}

void prw_env_dfg(double mu, double roughness, double *A, double *B)
{
    mu = fmin(fmax(mu, 1e-4), 1.0);
    double alpha = prw_alpha_from_roughness((float)roughness);
    double v[3] = {sqrt(1 - mu * mu), 0, mu};
    double a = 0, b = 0;
    for (uint32_t s = 0; s < PRW_ENV_DFG_SAMPLES; s++) {
        double x1, x2, hl[3];
        prw_env_hammersley(s, PRW_ENV_DFG_SAMPLES, &x1, &x2);
        ggx_half(alpha, x1, x2, hl);
        double vh = v[0] * hl[0] + v[2] * hl[2];
        if (vh <= 0) continue;
        double nl = 2 * vh * hl[2] - v[2];
        if (nl <= 0) continue;
        double nh = hl[2];
        /* pdf(l) = D nh / (4 vh): f cos / pdf = V 4 vh nl / nh */
        double w = prw_V_smith_ggx((float)mu, (float)nl, (float)alpha) * 4 * vh * nl / nh;
        double fc = pow(1 - vh, 5);
        a += w * (1 - fc);
        b += w * fc;
    }
    *A = a / PRW_ENV_DFG_SAMPLES;
    *B = b / PRW_ENV_DFG_SAMPLES;
}
