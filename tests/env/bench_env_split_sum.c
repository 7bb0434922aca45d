/* bench_env_split_sum <env.exr> [spp] [points] — the split-sum approximation (prw_env_file.h's
 * formula with prw_env_data_build's SH, prefiltered levels and DFG table) against the path tracer's
 * environment-direct light (prw_ref_trace_rays, filter environment-direct) on a lone sphere lit only
 * by the map, per material.  For each of `points` Fibonacci normals n the ray comes from a view v
 * drawn around n (mu = n.v spread over (0.1, 1]), so the n = v assumption is tested too.  Prints, per
 * material, the ratio of the means (formula / reference) and the mean relative error per point, with
 * the reference's standard error.  A benchmark: exits non-zero only outside a loose bound (means within
 * 25 %), the figures are the output. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "prw_brdf.h"
#include "prw_env_file.h"
#include "prw_image.h"
#include "prw_reference.h"
#include "prw_scene.h"

#define PI 3.14159265358979323846

typedef struct mat {
    const char *name;
    float base[3], metallic, roughness;
} mat;

/* The level maps interpolated in roughness, nearest texel in each. */
static void prefiltered(const prw_env_data *d, double r, const double R[3], float out[3])
{
    double k = r * (d->levels - 1);
    uint32_t k0 = (uint32_t)floor(k), k1 = k0 + 1 < d->levels ? k0 + 1 : k0;
    double t = k - k0;
    size_t lv = (size_t)d->height * 2 * d->height * 3;
    float a[3], b[3];
    prw_env_lookup(d->maps + k0 * lv, 2 * d->height, d->height, R, a);
    prw_env_lookup(d->maps + k1 * lv, 2 * d->height, d->height, R, b);
    for (int c = 0; c < 3; c++) out[c] = (float)((1 - t) * a[c] + t * b[c]);
}

static void dfg_lookup(const prw_env_data *d, double mu, double r, double *A, double *B)
{
    uint32_t N = d->dfg_size;
    int i = (int)floor(mu * N), j = (int)lround(r * (N - 1));
    i = i < 0 ? 0 : i >= (int)N ? (int)N - 1 : i;
    *A = d->dfg[2 * ((size_t)i * N + j)];
    *B = d->dfg[2 * ((size_t)i * N + j) + 1];
}

/* The header's formula (rotation 0: map space = world space). */
static void split_sum(const prw_env_data *d, const mat *m, const double n[3], const double v[3], double out[3])
{
    double nv = n[0] * v[0] + n[1] * v[1] + n[2] * v[2], mu = fmax(nv, 1e-4);
    double R[3];
    for (int c = 0; c < 3; c++) R[c] = 2 * nv * n[c] - v[c];
    float E[3], P[3];
    prw_env_sh_irradiance(d->sh, n, E);
    prefiltered(d, m->roughness, R, P);
    float r = m->roughness, ec = prw_ggx_Ec((float)mu, r), ed = prw_ggx_Ed((float)mu, r), ec_avg = prw_ggx_Ec_avg(r);
    double e_ds = ed + prw_F_ms(PRW_DIELECTRIC_F_AVG, ec_avg) * ec; /* specular = 1 */
    double A, B;
    dfg_lookup(d, mu, r, &A, &B);
    for (int c = 0; c < 3; c++) {
        double f0 = m->base[c];
        double e_m = f0 * A + B + prw_F_ms((float)((20 * f0 + 1) / 21), ec_avg) * ec;
        out[c] = (1 - m->metallic) * (m->base[c] * (1 - e_ds) * fmax(E[c], 0) / PI + e_ds * P[c]) +
                 m->metallic * e_m * P[c];
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_env_split_sum <env.exr> [spp] [points]\n");
        return 2;
    }
    char exr[1024];
    if (!realpath(argv[1], exr)) {
        fprintf(stderr, "%s: cannot resolve\n", argv[1]);
        return 1;
    }
    uint64_t spp = argc > 2 ? strtoull(argv[2], NULL, 10) : 256;
    int npts = argc > 3 ? atoi(argv[3]) : 128;
    prw_error e;
    prw_image img = {0};
    if (!prw_exr_read(exr, NULL, &img, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 1;
    }
    float *rgb = prw_malloc((size_t)img.width * img.height * 3 * sizeof(float));
    for (size_t k = 0; k < (size_t)img.width * img.height; k++)
        for (int c = 0; c < 3; c++) rgb[3 * k + c] = img.rgba[4 * k + c];
    double t0 = prw_now();
    prw_env_params p = {128, 0, 0, 0};
    prw_env_data d;
    if (!prw_env_data_build(rgb, (uint32_t)img.width, (uint32_t)img.height, 1.0, 0.0, 0, &p, &d, &e)) {
        fprintf(stderr, "%s\n", e.msg);
        return 1;
    }
    printf("env build: %dx%d source, %u levels of %ux%u, %u samples: %.2f s on %d threads\n", img.width, img.height,
           d.levels, 2 * d.height, d.height, d.samples, prw_now() - t0, prw_threads_get());
    /* The prefilter's sampling error: 32-row levels at the default sample count against 16x more. */
    {
        uint32_t oh = 32, K = PRW_ENV_DEFAULT_LEVELS, S = PRW_ENV_DEFAULT_SAMPLES;
        size_t nl = (size_t)oh * 2 * oh * 3;
        float *a = prw_malloc(K * nl * sizeof(float)), *b = prw_malloc(K * nl * sizeof(float));
        if (!prw_env_prefilter(rgb, (uint32_t)img.width, (uint32_t)img.height, oh, K, S, a, &e) ||
            !prw_env_prefilter(rgb, (uint32_t)img.width, (uint32_t)img.height, oh, K, 16 * S, b, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 1;
        }
        for (uint32_t k = 0; k < K; k++) {
            double se = 0, sb = 0;
            for (size_t q = 0; q < nl; q++) {
                double dlt = a[k * nl + q] - b[k * nl + q];
                se += dlt * dlt;
                sb += (double)b[k * nl + q] * b[k * nl + q];
            }
            printf("prefilter sampling error: level %u (roughness %.2f) %u vs %u samples: rms difference / rms value %.4f\n",
                   k, prw_env_level_roughness(k, K), S, 16 * S, sqrt(se / sb));
        }
        free(a);
        free(b);
    }
    const mat mats[] = {
        {"gold r0.3", {1.00f, 0.78f, 0.34f}, 1, 0.3f},
        {"blue plastic r0.25", {0.08f, 0.18f, 0.60f}, 0, 0.25f},
        {"white plaster r0.9", {0.70f, 0.70f, 0.68f}, 0, 0.9f},
        {"chrome r0.05", {0.95f, 0.95f, 0.95f}, 1, 0.05f},
    };
    char dir[] = "/tmp/prw-env-bench-XXXXXX";
    if (!mkdtemp(dir)) return 1;
    int bad = 0;
    for (size_t mi = 0; mi < sizeof mats / sizeof mats[0]; mi++) {
        const mat *m = &mats[mi];
        char man[1200];
        snprintf(man, sizeof man, "%s/m.json", dir);
        FILE *f = fopen(man, "w");
        fprintf(f,
                "{\"prw_manifest\": 1, \"environment\": {\"file\": \"%s\", \"scale\": 1, \"rotation_deg\": 0},\n"
                " \"materials\": [{\"name\": \"m\", \"base_color\": [%g, %g, %g], \"metallic\": %g, \"roughness\": %g}],\n"
                " \"meshes\": [{\"name\": \"s\", \"sphere\": {\"centre\": [0, 0, 0], \"radius\": 1, \"slices\": 256, "
                "\"stacks\": 128}, \"material\": \"m\"}]}\n",
                exr, m->base[0], m->base[1], m->base[2], m->metallic, m->roughness);
        fclose(f);
        prw_scene *s = prw_scene_create();
        prw_ref_renderer *rr = NULL;
        if (!prw_scene_load_manifest(s, man, &e) || !prw_ref_create(s, (prw_dvec3){0, 0, 0}, 0, &rr, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 1;
        }
        prw_ref_ray *rays = prw_malloc((size_t)npts * sizeof *rays);
        double (*nn)[3] = prw_malloc((size_t)npts * sizeof *nn), (*vv)[3] = prw_malloc((size_t)npts * sizeof *vv);
        for (int i = 0; i < npts; i++) {
            double z = 1 - 2 * (i + 0.5) / npts, rad = sqrt(1 - z * z), ph = i * 2.399963229728653;
            double n[3] = {rad * cos(ph), z, rad * sin(ph)};
            /* v: tilted from n by acos(mu), mu in (0.1, 1], about a tangent */
            double mu = 1 - 0.9 * fmod(i * 0.618034, 1.0), sn = sqrt(1 - mu * mu);
            double t[3] = {-n[2], 0, n[0]}, tl = sqrt(t[0] * t[0] + t[2] * t[2]);
            if (tl < 1e-6) t[0] = 1, t[2] = 0, tl = 1;
            for (int c = 0; c < 3; c++) {
                nn[i][c] = n[c];
                vv[i][c] = mu * n[c] + sn * t[c] / tl;
            }
            for (int c = 0; c < 3; c++) {
                double P = 1.0005 * n[c];
                (&rays[i].origin.x)[c] = P + 3 * vv[i][c];
                (&rays[i].dir.x)[c] = -vv[i][c];
            }
            rays[i].tnear = 0;
        }
        prw_ref_ray_desc rd = {0};
        rd.s0 = 0;
        rd.s1 = spp;
        rd.seed = 1;
        rd.camera = true;
        if (!prw_ref_filter_parse("environment-direct", &rd.filter, &e)) return 1;
        prw_ref_ray_result *res = prw_malloc((size_t)npts * sizeof *res);
        double t1 = prw_now();
        if (!prw_ref_trace_rays(rr, rays, (size_t)npts, &rd, res, NULL, NULL, &e)) {
            fprintf(stderr, "%s\n", e.msg);
            return 1;
        }
        double tr = prw_now() - t1;
        double sref = 0, sform = 0, srel = 0, svar = 0, rel_hi = 0, rel_lo = 0;
        int n_hi = 0, n_lo = 0;
        for (int i = 0; i < npts; i++) {
            double o[3];
            split_sum(&d, m, nn[i], vv[i], o);
            double ry = 0.2126 * res[i].mean[0] + 0.7152 * res[i].mean[1] + 0.0722 * res[i].mean[2];
            double oy = 0.2126 * o[0] + 0.7152 * o[1] + 0.0722 * o[2];
            sref += ry;
            sform += oy;
            double rel = fabs(oy - ry) / fmax(ry, 1e-6);
            srel += rel;
            double mu = nn[i][0] * vv[i][0] + nn[i][1] * vv[i][1] + nn[i][2] * vv[i][2];
            if (mu >= 0.5)
                rel_hi += rel, n_hi++;
            else
                rel_lo += rel, n_lo++;
            svar += 0.2126 * 0.2126 * res[i].var_mean[0] + 0.7152 * 0.7152 * res[i].var_mean[1] +
                    0.0722 * 0.0722 * res[i].var_mean[2];
        }
        double ratio = sform / sref, se = sqrt(svar) / sref;
        printf("split-sum vs path tracer (environment-direct), %-20s %d points x %llu spp: mean luminance "
               "ratio %.4f (reference s.e. %.4f), mean |rel. error| per point %.3f (n.v >= 0.5: %.3f, < 0.5: %.3f) "
               "(trace %.1f s)\n",
               m->name, npts, (unsigned long long)spp, ratio, se, srel / npts, rel_hi / (n_hi ? n_hi : 1),
               rel_lo / (n_lo ? n_lo : 1), tr);
        if (!(fabs(ratio - 1) < 0.25)) bad = 1;
        free(res);
        free(rays);
        free(nn);
        free(vv);
        prw_ref_destroy(rr);
        prw_scene_destroy(s);
        unlink(man);
    }
    rmdir(dir);
    prw_env_data_free(&d);
    free(rgb);
    prw_image_free(&img);
    return bad;
}
