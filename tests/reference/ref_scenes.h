/* Small scenes and helpers shared by the reference tests (header-only, static functions). */
#ifndef PRW_REF_TEST_SCENES_H
#define PRW_REF_TEST_SCENES_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_reference.h"
#include "prw_test.h"

static inline int lambert_material(prw_scene *s, const char *name, double albedo, double emission)
{
    prw_material m = prw_material_default();
    snprintf(m.name, sizeof m.name, "%s", name);
    for (int k = 0; k < 3; k++) m.base_color[k] = (float)albedo, m.emission[k] = (float)emission;
    m.specular = 0; /* pure Lambert */
    m.roughness = 1;
    return prw_scene_add_material(s, &m);
}

static inline void add_light_at(prw_scene *s, prw_light l, prw_dvec3 pos, prw_dvec3 target, prw_dvec3 up)
{
    prw_node n = prw_node_look_at(l.name, pos, target, up);
    int ni = prw_scene_add_node(s, &n);
    s->nodes[ni].light = (int)s->light_count;
    l.node = ni;
    prw_scene_add_light(s, &l);
}

/* Camera straight down from (0, h, 0), +Z towards the image bottom. */
static inline prw_view view_down(double h, double yfov, uint32_t w, uint32_t ht)
{
    return prw_view_look_at(prw_v3(0, h, 0), prw_v3(0, 0, 0), prw_v3(0, 0, -1), yfov, 0.01, w, ht, 0);
}

typedef struct ref_result {
    prw_ref_acc acc;
    float *mean, *var;
    prw_ref_stats st;
    double seconds;
} ref_result;

static inline bool ref_run(const prw_scene *s, const prw_view *v, uint64_t s0, uint64_t s1, uint64_t seed,
                           prw_ref_filter f, int threads, ref_result *out)
{
    memset(out, 0, sizeof *out);
    prw_error e = {{0}};
    prw_ref_renderer *r = NULL;
    double t0 = prw_now();
    if (!prw_ref_create(s, v->eye, threads, &r, &e)) {
        fprintf(stderr, "prw_ref_create: %s\n", e.msg);
        prw_test_failures++;
        return false;
    }
    prw_ref_desc d = {.s0 = s0, .s1 = s1, .seed = seed, .filter = f, .threads = threads};
    bool ok = prw_ref_render(r, v, &d, &out->acc, &out->st, &e);
    if (ok) ok = prw_ref_acc_images(&out->acc, &out->mean, &out->var, &e);
    if (!ok) {
        fprintf(stderr, "render: %s\n", e.msg);
        prw_test_failures++;
    }
    prw_ref_destroy(r);
    out->seconds = prw_now() - t0;
    return ok;
}

static inline void ref_result_free(ref_result *r)
{
    prw_ref_acc_free(&r->acc);
    free(r->mean);
    free(r->var);
}

/* Image mean of channel-average radiance and its standard error (pixels independent). */
static inline void image_mean(const ref_result *r, double *mean, double *se)
{
    size_t n = (size_t)r->acc.width * r->acc.height;
    double m = 0, v = 0;
    for (size_t i = 0; i < n; i++) {
        m += (r->mean[4 * i] + r->mean[4 * i + 1] + r->mean[4 * i + 2]) / 3.0;
        v += (r->var[4 * i] + r->var[4 * i + 1] + r->var[4 * i + 2]) / 9.0; /* channels fully correlated: upper bound below */
    }
    /* channel estimates are correlated (grey scenes: identical), so the variance of their average is
     * bounded by the average of the standard deviations squared; use that bound */
    double vb = 0;
    for (size_t i = 0; i < n; i++) {
        double sd = (sqrt(r->var[4 * i]) + sqrt(r->var[4 * i + 1]) + sqrt(r->var[4 * i + 2])) / 3.0;
        vb += sd * sd;
    }
    (void)v;
    *mean = m / (double)n;
    *se = sqrt(vb) / (double)n;
}

#endif
