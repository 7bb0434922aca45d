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
    prw_ref_acc half[2] = {{0}}, all = {0};
    prw_image raster = {0}, ref = {0}, ref_a = {0}, ref_b = {0};
    bool ok = prw_renderer_create(gpu, scene, &d, &r, e) && prw_renderer_render(r, &sv, 1, NULL, e) &&
              prw_renderer_read_hdr(r, 0, &raster, e) && prw_ref_create(scene, sv.eye, threads, &rr, e);
    for (int k = 0; k < 2 && ok; k++) {
        prw_ref_desc rd = {.s0 = k ? spp / 2 : 0, .s1 = k ? spp : spp / 2, .seed = 1, .threads = threads};
        ok = prw_ref_render(rr, &sv, &rd, &half[k], NULL, e);
    }
    if (ok) {
        const prw_ref_acc *in[2] = {&half[0], &half[1]};
        ok = prw_ref_acc_merge(in, NULL, 2, &all, e) && mean_image(&all, &ref, e) && mean_image(&half[0], &ref_a, e) &&
             mean_image(&half[1], &ref_b, e);
    }
    prw_compare_opts o = {.ev100 = sv.ev100};
    prw_compare_metrics m, noise;
    if (ok) ok = prw_compare_images(&raster, &ref, &o, &m, NULL, NULL, e) &&
                 prw_compare_images(&ref_a, &ref_b, &o, &noise, NULL, NULL, e);
    if (ok) {
        out->have = true;
        out->width = sv.width;
        out->height = sv.height;
        out->spp = spp;
        out->ldr_flip = m.ldr_flip.mean;
        out->noise_flip = noise.ldr_flip.mean;
        out->when = prw_now();
        out->seconds = out->when - t0;
    }
    prw_image_free(&raster);
    prw_image_free(&ref);
    prw_image_free(&ref_a);
    prw_image_free(&ref_b);
    prw_ref_acc_free(&half[0]);
    prw_ref_acc_free(&half[1]);
    prw_ref_acc_free(&all);
    prw_ref_destroy(rr);
    prw_renderer_destroy(r);
    return ok;
}
