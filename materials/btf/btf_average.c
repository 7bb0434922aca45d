/* btf_average.c — the scale rule's average BRDF: the per-direction mean over the texels fitted by the
 * material model (prw_bsdf.h).  A grid over metallic (5 values) and roughness (10), then 10 finer roughnesses
 * around the best times specular 1, 0.5, 0, with the base colour
 * solved per channel in least squares, linearised twice (the model is linear in the base colour for
 * dielectrics and nearly so for metals: the multiple-scattering Fresnel term is not). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_bsdf.h"
#include "prw_btf_codec.h"

typedef struct fit_ctx {
    uint32_t P, L;     /* pairs, lights (pair = view * L + light) */
    double *wo, *wi;   /* 3 per pair */
    double *mean;      /* 3 per pair: the texel mean of f cos theta_l */
    double *cosl;      /* per pair */
} fit_ctx;

/* f cos theta_l of the model at every pair for one base colour: out (3 per pair). */
static void model(const fit_ctx *x, double metallic, double roughness, double specular, const double base[3], double *out)
{
    prw_bsdf b;
    memset(&b, 0, sizeof b);
    for (int c = 0; c < 3; c++) b.base[c] = base[c];
    b.metallic = metallic, b.roughness = roughness, b.specular = specular;
    for (uint32_t v = 0; v < x->P / x->L; v++) {
        const double *wo = x->wo + 3 * (size_t)v * x->L;
        prw_bsdf_lobes lo = prw_bsdf_lobes_at(&b, wo); /* what depends on the view only, once */
        for (uint32_t i = v * x->L; i < (v + 1) * x->L; i++) {
            double f[3];
            prw_bsdf_eval_at(&b, &lo, wo, x->wi + 3 * i, f);
            for (int c = 0; c < 3; c++) out[3 * i + c] = f[c] * x->cosl[i];
        }
    }
}

/* The base colour for (metallic, roughness) and its squared error. */
static double solve(const fit_ctx *x, double metallic, double roughness, double specular, double *f0, double *f1,
                    double base[3])
{
    double b0[3] = {0.5, 0.5, 0.5};
    for (int round = 0; round < 2; round++) {
        double b1[3];
        for (int c = 0; c < 3; c++) b1[c] = b0[c] + (b0[c] > 0.5 ? -0.25 : 0.25);
        model(x, metallic, roughness, specular, b0, f0);
        model(x, metallic, roughness, specular, b1, f1);
        for (int c = 0; c < 3; c++) {
            /* f(b) ~ f(b0) + (b - b0) S, S the secant slope */
            double num = 0, den = 0;
            for (uint32_t i = 0; i < x->P; i++) {
                double S = (f1[3 * i + c] - f0[3 * i + c]) / (b1[c] - b0[c]);
                num += S * (x->mean[3 * i + c] - f0[3 * i + c]);
                den += S * S;
            }
            double b = den > 0 ? b0[c] + num / den : b0[c];
            b0[c] = fmin(fmax(b, 0.0), 1.0);
        }
    }
    model(x, metallic, roughness, specular, b0, f0);
    double err = 0;
    for (uint64_t i = 0; i < 3ull * x->P; i++) err += (f0[i] - x->mean[i]) * (f0[i] - x->mean[i]);
    memcpy(base, b0, sizeof b0);
    return err;
}

bool prw_btf_fit_average(const prw_btf *a, prw_btf_average *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    fit_ctx x;
    x.P = a->views * a->lights, x.L = a->lights;
    uint64_t N = (uint64_t)a->width * a->height;
    for (uint32_t i = 0; i < a->views; i++)
        if (!(a->view_dirs[2 * i] >= 0 && a->view_dirs[2 * i] < 1.5707)) return prw_fail(e, "btf average: view %u at or below the horizon", i);
    for (uint32_t i = 0; i < a->lights; i++)
        if (!(a->light_dirs[2 * i] >= 0 && a->light_dirs[2 * i] < 1.5707)) return prw_fail(e, "btf average: light %u at or below the horizon", i);
    x.wo = prw_malloc(sizeof(double) * 3 * x.P);
    x.wi = prw_malloc(sizeof(double) * 3 * x.P);
    x.mean = prw_calloc(3 * (size_t)x.P, sizeof(double));
    x.cosl = prw_malloc(sizeof(double) * x.P);
    double *f0 = prw_malloc(sizeof(double) * 3 * x.P), *f1 = prw_malloc(sizeof(double) * 3 * x.P);
    double norm = 0;
    for (uint32_t v = 0; v < a->views; v++)
        for (uint32_t l = 0; l < a->lights; l++) {
            uint32_t i = v * a->lights + l;
            prw_btf_dir_vector(a->view_dirs[2 * v], a->view_dirs[2 * v + 1], x.wo + 3 * i);
            prw_btf_dir_vector(a->light_dirs[2 * l], a->light_dirs[2 * l + 1], x.wi + 3 * i);
            x.cosl[i] = x.wi[3 * i + 2];
            const float *px = a->rgb + prw_btf_at(a, v, l, 0, 0);
            for (uint64_t t = 0; t < N; t++)
                for (int c = 0; c < 3; c++) x.mean[3 * i + c] += px[3 * t + c];
            for (int c = 0; c < 3; c++) {
                x.mean[3 * i + c] /= (double)N;
                norm += x.mean[3 * i + c] * x.mean[3 * i + c];
            }
        }
    double best = INFINITY;
    /* coarse: metallic 0, 0.25 .. 1 x roughness 0.1 .. 1 (specular 1); then around the best roughness by
     * 0.0125 x specular 1, 0.5, 0 (a dielectric's specular lobe may be weaker or absent) */
    out->specular = 1;
    for (int pass = 0; pass < 2; pass++) {
        double m0 = out->metallic, r0 = out->roughness;
        for (int mi = 0; mi <= 4; mi++)
            for (int ri = 1; ri <= 10; ri++) {
                if (pass && (mi > 2 || (mi > 0 && m0 >= 1))) continue;
                double base[3], m = pass ? m0 : mi / 4.0, r = pass ? r0 + (ri - 5.5) * 0.0125 : ri / 10.0;
                double sp = pass ? 1 - mi * 0.5 : 1;
                if (pass && (r <= 0.02 || r > 1)) continue;
                double err = solve(&x, m, r, sp, f0, f1, base);
                if (err < best) {
                    best = err;
                    for (int c = 0; c < 3; c++) out->base[c] = (float)base[c];
                    out->metallic = (float)m, out->roughness = (float)r, out->specular = (float)sp;
                }
            }
    }
    out->rms_pct = norm > 0 ? (float)(100 * sqrt(best / norm)) : 0.0f;
    free(x.wo), free(x.wi), free(x.mean), free(x.cosl), free(f0), free(f1);
    return true;
}
