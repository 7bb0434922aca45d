/* walk_measure.c — see walk_measure.h. */
#include "walk_measure.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_metrics.h"
#include "prw_reference.h"

static bool mean_image(const prw_ref_acc *a, prw_image *out, prw_error *e)
{
    float *mean = NULL, *var = NULL;
    if (!prw_ref_acc_images(a, &mean, &var, e)) return false;
    free(var);
    out->width = (int)a->width;
    out->height = (int)a->height;
    out->rgba = mean;
    return true;
}

bool walk_measure_run(prw_gpu *gpu, const prw_scene *scene, const prw_view *v, const prw_render_desc *desc,
                      uint32_t width, uint64_t spp, int threads, walk_measure *out, prw_error *e)
{
    double t0 = prw_now();
    memset(out, 0, sizeof *out);
    if (width < 16 || spp < 2) return prw_fail(e, "measure: need width >= 16 and spp >= 2 (got %u, %llu)", width,
                                               (unsigned long long)spp);
    prw_view sv = *v;
    sv.width = width;
    sv.height = (uint32_t)fmax(8.0, floor((double)width * v->height / v->width + 0.5));
    prw_render_desc d = *desc;
    d.width = sv.width;
    d.height = sv.height;
    d.max_views = 1;
    if (d.quality.supersample) d.quality.supersample = 1; /* (all-zero quality means the default) */
    d.timestamps = false;
    prw_renderer *r = NULL;
    prw_ref_renderer *rr = NULL;
    prw_ref_acc acc[2] = {{0}};
    prw_image raster = {0}, ref_a = {0}, ref_b = {0};
    bool ok = prw_renderer_create(gpu, scene, &d, &r, e) && prw_renderer_render(r, &sv, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, &raster, e) && prw_ref_create(scene, sv.eye, threads, &rr, e);
    for (int k = 0; k < 2 && ok; k++) { /* two independent references (seeds 1, 2), each of spp samples */
        prw_ref_desc rd = {.s0 = 0, .s1 = spp, .seed = (uint64_t)k + 1, .threads = threads};
        ok = prw_ref_render(rr, &sv, &rd, &acc[k], NULL, e);
    }
    if (ok) ok = mean_image(&acc[0], &ref_a, e) && mean_image(&acc[1], &ref_b, e);
    prw_compare_opts o = {.ev100 = sv.ev100};
    prw_compare_metrics m, noise;
    if (ok) ok = prw_compare_images(&raster, &ref_a, &o, &m, NULL, NULL, e) &&
                 prw_compare_images(&ref_b, &ref_a, &o, &noise, NULL, NULL, e);
    if (ok) {
        out->have = true;
        out->width = sv.width;
        out->height = sv.height;
        out->spp = spp;
        out->ldr_flip = m.ldr_flip.mean;
        out->noise_flip = noise.ldr_flip.mean;
        out->beyond_noise = fmax(0.0, out->ldr_flip - out->noise_flip);
        out->below_noise = out->ldr_flip < 2.0 * out->noise_flip; /* prw compare's rule */
        out->when = prw_now();
        out->seconds = out->when - t0;
    }
    prw_image_free(&raster);
    prw_image_free(&ref_a);
    prw_image_free(&ref_b);
    prw_ref_acc_free(&acc[0]);
    prw_ref_acc_free(&acc[1]);
    prw_ref_destroy(rr);
    prw_renderer_destroy(r);
    return ok;
}
