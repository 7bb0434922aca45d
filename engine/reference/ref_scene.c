/* ref_scene.c — prepares a prw_scene for path tracing: Embree triangle geometry (world space,
 * camera-relative float), emissive-triangle sampler, rect and delta light tables, environment map
 * distribution.  Positions are transformed in double and the origin is subtracted before the
 * conversion to float, so scenes far from the world origin stay precise near the camera. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_image.h"
#include "ref_internal.h"

static double lum(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static void set3(double d[3], prw_dvec3 v)
{
    d[0] = v.x;
    d[1] = v.y;
    d[2] = v.z;
}

/* ---- environment ---- */

void ref_env_free(ref_env *env)
{
    free(env->rgb);
    free(env->marg);
    free(env->cond);
    free(env->pdf_uv);
    memset(env, 0, sizeof *env);
}

bool ref_env_build(const prw_environment *se, ref_env *env, prw_error *e)
{
    memset(env, 0, sizeof *env);
    if (!se->present) return true;
    env->cr = cos(se->rotation);
    env->sr = sin(se->rotation);
    if (!se->file[0]) {
        for (int k = 0; k < 3; k++) env->uniform[k] = isfinite(se->uniform[k]) && se->uniform[k] > 0 ? se->uniform[k] : 0;
        env->kind = lum(env->uniform) > 0 ? 1 : 0;
        return true;
    }
    prw_image img = {0};
    /* the sampling tables below (rgb 12 + conditional CDF 8 + pdf 8 bytes per pixel) count against
     * the memory budget with the image, before it is read */
    prw_exr_read_opts opts = {.reject_nonfinite = false, .extra_bytes_per_pixel = 28};
    if (!prw_exr_read(se->file, &opts, &img, e)) return false; /* "<file>: <place>: <reason>" */
    int w = img.width, h = img.height;
    env->w = w;
    env->h = h;
    env->rgb = prw_malloc((size_t)w * h * 3 * sizeof(float));
    env->marg = prw_calloc((size_t)h + 1, sizeof(double));
    env->cond = prw_calloc((size_t)h * (w + 1), sizeof(double));
    env->pdf_uv = prw_calloc((size_t)w * h, sizeof(double));
    double scale = isfinite(se->scale) && se->scale > 0 ? se->scale : 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        for (int k = 0; k < 3; k++) {
            double x = (double)img.rgba[4 * i + k] * scale;
            env->rgb[3 * i + k] = (float)(isfinite(x) && x > 0 ? x : 0);
        }
    prw_image_free(&img);
    /* weights: luminance x sin(theta) at the row centre; CDFs per row and over rows */
    double total = 0;
    for (int j = 0; j < h; j++) {
        double st = sin(PRW_PI * (j + 0.5) / h);
        double *c = env->cond + (size_t)j * (w + 1);
        c[0] = 0;
        for (int i = 0; i < w; i++) {
            const float *p = env->rgb + 3 * ((size_t)j * w + i);
            double pl[3] = {p[0], p[1], p[2]};
            double wgt = lum(pl) * st;
            env->pdf_uv[(size_t)j * w + i] = wgt;
            c[i + 1] = c[i] + wgt;
        }
        env->marg[j + 1] = env->marg[j] + c[w];
        total += c[w];
    }
    if (!(total > 0) || !isfinite(total)) {
        ref_env_free(env); /* black map: nothing to see or sample */
        return true;
    }
    for (size_t i = 0; i < (size_t)w * h; i++) env->pdf_uv[i] *= (double)w * h / total;
    env->kind = 2;
    return true;
}

/* Map direction <-> world direction (prw_scene.h): d' = R_y(-rot) d. */
static void env_to_map(const ref_env *env, const double d[3], double m[3])
{
    m[0] = env->cr * d[0] - env->sr * d[2];
    m[1] = d[1];
    m[2] = env->sr * d[0] + env->cr * d[2];
}

void ref_env_eval(const ref_env *env, const double d[3], double L[3], double *pdf)
{
    L[0] = L[1] = L[2] = 0;
    *pdf = 0;
    if (env->kind == 1) {
        for (int k = 0; k < 3; k++) L[k] = env->uniform[k];
        *pdf = 1.0 / (4 * PRW_PI);
        return;
    }
    if (env->kind != 2) return;
    double m[3];
    env_to_map(env, d, m);
    double u = 0.5 + atan2(m[0], -m[2]) / (2 * PRW_PI);
    double cy = fmax(-1.0, fmin(1.0, m[1]));
    double v = acos(cy) / PRW_PI;
    int i = (int)floor(u * env->w), j = (int)floor(v * env->h);
    i = ((i % env->w) + env->w) % env->w;
    j = j < 0 ? 0 : j >= env->h ? env->h - 1 : j;
    const float *p = env->rgb + 3 * ((size_t)j * env->w + i);
    for (int k = 0; k < 3; k++) L[k] = p[k];
    double st = sqrt(fmax(0.0, 1 - cy * cy));
    *pdf = st > 0 ? env->pdf_uv[(size_t)j * env->w + i] / (2 * PRW_PI * PRW_PI * st) : 0;
}

/* Largest index k in [0, n) with cdf[k] <= x (cdf has n + 1 entries, increasing). */
static int find_interval(const double *cdf, int n, double x)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (cdf[mid] <= x) lo = mid;
        else hi = mid - 1;
    }
    return lo;
}

bool ref_env_sample(const ref_env *env, double u1, double u2, double d[3], double L[3], double *pdf)
{
    if (env->kind == 1) {
        double z = 1 - 2 * u1, r = sqrt(fmax(0.0, 1 - z * z)), ph = 2 * PRW_PI * u2;
        d[0] = r * cos(ph);
        d[1] = z;
        d[2] = r * sin(ph);
        for (int k = 0; k < 3; k++) L[k] = env->uniform[k];
        *pdf = 1.0 / (4 * PRW_PI);
        return true;
    }
    if (env->kind != 2) return false;
    int w = env->w, h = env->h;
    double x = u1 * env->marg[h];
    int j = find_interval(env->marg, h, x);
    while (j > 0 && env->marg[j + 1] == env->marg[j]) j--; /* never a zero-weight row */
    double rw = env->marg[j + 1] - env->marg[j];
    if (!(rw > 0)) return false;
    double fv = fmin(fmax((x - env->marg[j]) / rw, 0.0), 0.999999999);
    const double *c = env->cond + (size_t)j * (w + 1);
    double y = u2 * c[w];
    int i = find_interval(c, w, y);
    double cw = c[i + 1] - c[i];
    if (!(cw > 0)) return false;
    double fu = fmin(fmax((y - c[i]) / cw, 0.0), 0.999999999);
    double u = (i + fu) / w, v = (j + fv) / h;
    double th = PRW_PI * v, ph = 2 * PRW_PI * (u - 0.5);
    double st = sin(th);
    if (!(st > 0)) return false;
    double m[3] = {st * sin(ph), cos(th), -st * cos(ph)};
    /* world = R_y(rot) m */
    d[0] = env->cr * m[0] + env->sr * m[2];
    d[1] = m[1];
    d[2] = -env->sr * m[0] + env->cr * m[2];
    const float *p = env->rgb + 3 * ((size_t)j * w + i);
    for (int k = 0; k < 3; k++) L[k] = p[k];
    *pdf = env->pdf_uv[(size_t)j * w + i] / (2 * PRW_PI * PRW_PI * st);
    return *pdf > 0;
}

/* ---- scene ---- */

static void embree_error(void *user, enum RTCError code, const char *str)
{
    (void)user;
    prw_log(PRW_LOG_ERROR, "embree: error %d: %s", (int)code, str ? str : "");
}

void prw_ref_destroy(prw_ref_renderer *r)
{
    if (!r) return;
    if (r->rtc) rtcReleaseScene(r->rtc);
    if (r->dev) rtcReleaseDevice(r->dev);
    for (uint32_t i = 0; i < r->inst_count; i++) free(r->inst[i].pos), free(r->inst[i].tri);
    free(r->inst);
    free(r->etri_inst);
    free(r->etri_prim);
    free(r->etri_cdf);
    free(r->rects);
    free(r->deltas);
    ref_env_free(&r->env);
    ref_nurbs_free(r);
    ref_btf_free(r);
    free(r);
}

static bool mat3_inverse(const double a[9], double out[9])
{
    double det = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) +
                 a[2] * (a[3] * a[7] - a[4] * a[6]);
    if (!(fabs(det) > 0) || !isfinite(det)) return false;
    double id = 1.0 / det;
    out[0] = (a[4] * a[8] - a[5] * a[7]) * id;
    out[1] = (a[2] * a[7] - a[1] * a[8]) * id;
    out[2] = (a[1] * a[5] - a[2] * a[4]) * id;
    out[3] = (a[5] * a[6] - a[3] * a[8]) * id;
    out[4] = (a[0] * a[8] - a[2] * a[6]) * id;
    out[5] = (a[2] * a[3] - a[0] * a[5]) * id;
    out[6] = (a[3] * a[7] - a[4] * a[6]) * id;
    out[7] = (a[1] * a[6] - a[0] * a[7]) * id;
    out[8] = (a[0] * a[4] - a[1] * a[3]) * id;
    return true;
}

/* MASK and BLEND materials: a hit where the surface is not (MASK below the cutoff; BLEND with the
 * probability 1 - alpha, decided by a hash of the ray's key and the triangle, so the decision is
 * the same however often Embree reports the hit) is rejected and the ray goes on. */
static void alpha_filter(const struct RTCFilterFunctionNArguments *args)
{
    const ref_inst *in = args->geometryUserPtr;
    const ref_ray_ctx *rc = (const ref_ray_ctx *)args->context;
    for (unsigned i = 0; i < args->N; i++) {
        if (args->valid[i] != -1) continue;
        /* RTCHitN is structure-of-arrays: Ng x, y, z, u, v, primID, geomID (rtcore_ray.h; its accessors are C++) */
        const float *hf = (const float *)args->hit;
        const unsigned *hu = (const unsigned *)args->hit;
        uint32_t prim = hu[5 * args->N + i];
        double b1 = hf[3 * args->N + i], b2 = hf[4 * args->N + i];
        bool keep;
        if (in->mat->alpha_mode == PRW_ALPHA_BLEND && rc->blend_invisible) {
            keep = false;
        } else if (in->mat->alpha_mode == PRW_ALPHA_BLEND) {
            uint64_t h = ref_splitmix(rc->key ^ ref_splitmix(((uint64_t)in->geom << 32) | prim));
            keep = (double)(h >> 11) * 0x1.0p-53 < ref_coverage_at(in->r, in, prim, b1, b2);
        } else {
            keep = ref_coverage_at(in->r, in, prim, b1, b2) > 0;
        }
        if (!keep) args->valid[i] = 0;
    }
}

bool ref_add_instance(prw_ref_renderer *r, const prw_node *n, const prw_mesh *m, prw_error *e)
{
    const prw_scene *s = r->scene;
    ref_inst *in = &r->inst[r->inst_count];
    memset(in, 0, sizeof *in);
    in->mesh = m;
    in->mat = &s->materials[m->material];
    in->nurbs_entry = -1;
    const double *w = n->world.m;
    for (int row = 0; row < 3; row++)
        for (int col = 0; col < 3; col++) in->lmat[row * 3 + col] = w[col * 4 + row];
    double inv[9];
    if (!mat3_inverse(in->lmat, inv)) return true; /* degenerate (zero scale): invisible, like the rasterizer */
    for (int row = 0; row < 3; row++)
        for (int col = 0; col < 3; col++) in->nmat[row * 3 + col] = inv[col * 3 + row];
    double det = in->lmat[0] * (in->lmat[4] * in->lmat[8] - in->lmat[5] * in->lmat[7]) -
                 in->lmat[1] * (in->lmat[3] * in->lmat[8] - in->lmat[5] * in->lmat[6]) +
                 in->lmat[2] * (in->lmat[3] * in->lmat[7] - in->lmat[4] * in->lmat[6]);
    in->flip = det < 0;
    in->pos = prw_malloc(((size_t)m->vertex_count * 3 + 1) * sizeof(float));
    in->pos[(size_t)m->vertex_count * 3] = 0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        prw_dvec3 p = prw_dm4_point(n->world, prw_v3(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]));
        p = prw_v3_sub(p, r->origin);
        in->pos[3 * v] = (float)p.x;
        in->pos[3 * v + 1] = (float)p.y;
        in->pos[3 * v + 2] = (float)p.z;
    }
    uint32_t nt = m->index_count / 3;
    in->tri = prw_malloc(((size_t)nt ? (size_t)nt : 1) * 4 * sizeof(double));
    for (uint32_t t = 0; t < nt; t++) ref_tri_geometry(in, t, in->tri + 4 * (size_t)t);
    RTCGeometry g = rtcNewGeometry(r->dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, in->pos, 0, 3 * sizeof(float),
                               m->vertex_count);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m->indices, 0, 3 * sizeof(uint32_t),
                               m->index_count / 3);
    in->r = r;
    in->geom = r->inst_count;
    if (in->mat->alpha_mode == PRW_ALPHA_MASK || in->mat->alpha_mode == PRW_ALPHA_BLEND) {
        rtcSetGeometryUserData(g, in);
        rtcSetGeometryIntersectFilterFunction(g, alpha_filter);
        rtcSetGeometryOccludedFilterFunction(g, alpha_filter);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(r->rtc, g, r->inst_count);
    rtcReleaseGeometry(g);
    if (rtcGetDeviceError(r->dev) != RTC_ERROR_NONE)
        return prw_fail(e, "reference: embree: cannot add mesh '%s' of node '%s'", m->name, n->name);
    r->inst_count++;
    return true;
}

static void tri_pos(const ref_inst *in, uint32_t prim, double p[3][3])
{
    const uint32_t *ix = in->mesh->indices + 3 * prim;
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) p[k][c] = in->pos[3 * ix[k] + c];
}

static void build_emitters(prw_ref_renderer *r)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < r->inst_count; i++) {
        const float *em = r->inst[i].mat->emission;
        if (em[0] > 0 || em[1] > 0 || em[2] > 0) n += r->inst[i].mesh->index_count / 3;
    }
    if (n == 0) return;
    r->etri_inst = prw_malloc(n * sizeof(uint32_t));
    r->etri_prim = prw_malloc(n * sizeof(uint32_t));
    r->etri_cdf = prw_malloc((n + 1) * sizeof(double));
    r->etri_cdf[0] = 0;
    uint32_t k = 0;
    for (uint32_t i = 0; i < r->inst_count; i++) {
        const float *em = r->inst[i].mat->emission;
        if (!(em[0] > 0 || em[1] > 0 || em[2] > 0)) continue;
        double le[3] = {em[0], em[1], em[2]};
        double y = lum(le);
        for (uint32_t t = 0; t < r->inst[i].mesh->index_count / 3; t++) {
            double p[3][3];
            tri_pos(&r->inst[i], t, p);
            double a[3], b[3];
            for (int c = 0; c < 3; c++) a[c] = p[1][c] - p[0][c], b[c] = p[2][c] - p[0][c];
            double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2], cz = a[0] * b[1] - a[1] * b[0];
            double area = 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
            r->etri_inst[k] = i;
            r->etri_prim[k] = t;
            r->etri_cdf[k + 1] = r->etri_cdf[k] + area * y;
            k++;
        }
    }
    double total = r->etri_cdf[n];
    if (!(total > 0)) {
        free(r->etri_inst);
        free(r->etri_prim);
        free(r->etri_cdf);
        r->etri_inst = r->etri_prim = NULL;
        r->etri_cdf = NULL;
        return;
    }
    r->etri_count = n;
    for (uint32_t i = 0; i < r->inst_count; i++) {
        const float *em = r->inst[i].mat->emission;
        double le[3] = {em[0], em[1], em[2]};
        if (em[0] > 0 || em[1] > 0 || em[2] > 0) r->inst[i].emit_pdf_area = lum(le) / total;
    }
}

static void build_lights(prw_ref_renderer *r)
{
    const prw_scene *s = r->scene;
    r->rects = prw_calloc(s->light_count + 1, sizeof(ref_rect));
    r->deltas = prw_calloc(s->light_count + 1, sizeof(ref_delta));
    for (uint32_t i = 0; i < s->light_count; i++) {
        const prw_light *l = &s->lights[i];
        if (l->node < 0 || (uint32_t)l->node >= s->node_count || !(l->intensity > 0)) continue;
        const double *m = s->nodes[l->node].world.m;
        prw_dvec3 pos = prw_v3_sub(prw_v3(m[12], m[13], m[14]), r->origin);
        prw_dvec3 dir = prw_v3_norm(prw_v3(-m[8], -m[9], -m[10]));
        if (l->type == PRW_LIGHT_RECT) {
            prw_dvec3 ax = prw_v3_scale(prw_v3_norm(prw_v3(m[0], m[1], m[2])), 0.5 * l->width);
            prw_dvec3 ay = prw_v3_scale(prw_v3_norm(prw_v3(m[4], m[5], m[6])), 0.5 * l->height);
            prw_dvec3 cr = prw_v3_cross(ax, ay);
            double area4 = prw_v3_len(cr);
            if (!(area4 > 0) || !isfinite(area4)) continue;
            prw_dvec3 np = prw_v3_scale(cr, 1.0 / area4);
            /* dual vectors: dot(ax, dx) = 1, dot(ay, dx) = 0 and vice versa */
            prw_dvec3 dx = prw_v3_scale(prw_v3_cross(ay, np), 1.0 / prw_v3_dot(ax, prw_v3_cross(ay, np)));
            prw_dvec3 dy = prw_v3_scale(prw_v3_cross(np, ax), 1.0 / prw_v3_dot(ay, prw_v3_cross(np, ax)));
            ref_rect *q = &r->rects[r->rect_count++];
            set3(q->c, pos);
            set3(q->ax, ax);
            set3(q->ay, ay);
            set3(q->dx, dx);
            set3(q->dy, dy);
            set3(q->np, np);
            set3(q->emit, prw_v3_dot(np, dir) >= 0 ? np : prw_v3_scale(np, -1));
            q->area = 4 * area4;
            for (int k = 0; k < 3; k++) q->L[k] = l->color[k] * l->intensity;
        } else {
            ref_delta *d = &r->deltas[r->delta_count++];
            d->type = l->type;
            set3(d->p, pos);
            set3(d->dir, dir);
            for (int k = 0; k < 3; k++) d->I[k] = l->color[k] * l->intensity;
            d->range = l->range;
            d->cos_inner = cos(l->inner_cone);
            d->cos_outer = cos(l->outer_cone);
        }
    }
}

bool prw_ref_create(const prw_scene *s, prw_dvec3 origin, int threads, prw_ref_renderer **out, prw_error *e)
{
    *out = NULL;
    if (threads <= 0) threads = prw_threads_get();
    if (threads <= 0) threads = 1;
    prw_ref_renderer *r = prw_calloc(1, sizeof *r);
    r->scene = s;
    r->origin = origin;
    r->threads = threads;
    for (int i = 0; i < 256; i++) {
        double c = i / 255.0;
        r->srgb_lut[i] = (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
    }
    char cfg[64];
    snprintf(cfg, sizeof cfg, "threads=%d", threads);
    r->dev = rtcNewDevice(cfg);
    if (!r->dev) {
        prw_ref_destroy(r);
        return prw_fail(e, "reference: embree: cannot create a device (%s)", cfg);
    }
    rtcSetDeviceErrorFunction(r->dev, embree_error, NULL);
    r->rtc = rtcNewScene(r->dev);
    rtcSetSceneBuildQuality(r->rtc, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneFlags(r->rtc, RTC_SCENE_FLAG_ROBUST);
    uint32_t cap = 0;
    for (uint32_t i = 0; i < s->node_count; i++) {
        int g = s->nodes[i].mesh_group;
        if (g >= 0 && (uint32_t)g < s->group_count) cap += s->groups[g].count;
    }
    cap += ref_nurbs_instance_count(s);
    r->inst = prw_calloc(cap + 1, sizeof(ref_inst));
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *n = &s->nodes[i];
        if (n->mesh_group < 0 || (uint32_t)n->mesh_group >= s->group_count) continue;
        const prw_mesh_group *g = &s->groups[n->mesh_group];
        for (uint32_t k = g->first; k < g->first + g->count && k < s->mesh_count; k++) {
            const prw_mesh *m = &s->meshes[k];
            if (m->material < 0 || (uint32_t)m->material >= s->material_count || m->index_count < 3) continue;
            if (!ref_add_instance(r, n, m, e)) {
                prw_ref_destroy(r);
                return false;
            }
        }
    }
    if (!ref_nurbs_add(r, e)) {
        prw_ref_destroy(r);
        return false;
    }
    rtcCommitScene(r->rtc);
    if (rtcGetDeviceError(r->dev) != RTC_ERROR_NONE) {
        prw_ref_destroy(r);
        return prw_fail(e, "reference: embree: scene build failed");
    }
    build_emitters(r);
    build_lights(r);
    if (!ref_env_build(&s->environment, &r->env, e) || !ref_btf_load(r, e)) {
        prw_ref_destroy(r);
        return false;
    }
    *out = r;
    return true;
}
