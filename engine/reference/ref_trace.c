/* ref_trace.c — one path sample: unidirectional path tracing with next-event estimation, MIS
 * (power heuristic) for every emitter that can also be hit, Russian roulette, light-path filters.
 * Conventions are listed in prw_reference.h.
 *
 * Random dimensions are laid out per scattering vertex (not consumed in sequence), so skipping work
 * a filter does not need never shifts the numbers later decisions use:
 *   camera: 0, 1;  vertex k >= 1: base = 2 + (k - 1) * S, S = 9 + 2 * rects, with offsets
 *   0..2 BSDF sample, 3 Russian roulette, 4..6 emissive triangle, 7..8 environment, 9 + 2i rect i. */
#include <math.h>
#include <string.h>

#include "prw_brdf.h"
#include "prw_bsdf.h"
#include "prw_shading.h"
#include "ref_internal.h"

#define RR_START 3
#define RR_MAX_SURVIVAL 0.95
#define SAFETY_DEPTH 65536

typedef struct surf {
    double p[3];      /* hit point, camera-relative */
    double ng[3];     /* geometric normal, on the side of the incoming ray (after two-sided flip) */
    double ns[3];     /* shading normal */
    double eps;       /* ray offset for this point */
    bool front;
    const ref_inst *in;
    uint32_t prim;
    double uv[2];
    double bary[3];   /* weights of the triangle's vertices 0, 1, 2 */
    double t;
} surf;

static inline double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline void norm3(double a[3])
{
    double l = sqrt(dot3(a, a));
    if (l > 0) a[0] /= l, a[1] /= l, a[2] /= l;
}
static inline void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}
static inline double maxabs3(const double a[3]) { return fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2]))); }

static inline double power_heuristic(double a, double b)
{
    double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0 ? a2 / (a2 + b2) : 0;
}

/* ---- filters ---- */

/* Whether a light path with k scattering vertices ending on an emitter (env: the environment) counts. */
static bool accept_path(prw_ref_filter f, int k, bool env)
{
    switch (f.kind) {
    case PRW_REF_EMISSION: return k == 0;
    case PRW_REF_DIRECT: return k <= 1;
    case PRW_REF_INDIRECT: return k >= 2;
    case PRW_REF_DEPTH: return k == f.depth;
    case PRW_REF_MAX_DEPTH: return k <= f.depth;
    case PRW_REF_MIN_DEPTH: return k >= f.depth;
    case PRW_REF_DIFFUSE_LAST:
    case PRW_REF_GLOSSY_LAST: return k >= 1;
    case PRW_REF_INDIRECT_DIFFUSE_LAST:
    case PRW_REF_INDIRECT_GLOSSY_LAST: return k >= 2;
    case PRW_REF_ENVIRONMENT_DIRECT: return k == 1 && env;
    default: return true;
    }
}

/* Whether some emitter of a path with k scattering vertices may count (gates the next-event work). */
static bool accept(prw_ref_filter f, int k)
{
    return accept_path(f, k, false) || accept_path(f, k, true);
}

static int max_depth(prw_ref_filter f)
{
    switch (f.kind) {
    case PRW_REF_EMISSION: return 0;
    case PRW_REF_DIRECT:
    case PRW_REF_ENVIRONMENT_DIRECT: return 1;
    case PRW_REF_DEPTH:
    case PRW_REF_MAX_DEPTH: return f.depth;
    default: return SAFETY_DEPTH;
    }
}

/* ---- textures ---- */

void ref_tex_sample(const prw_ref_renderer *r, const prw_texture *t, const double uv[2], double out[4])
{
    double x = uv[0] * t->width - 0.5, y = uv[1] * t->height - 0.5;
    if (!isfinite(x) || !isfinite(y)) x = y = 0;
    double fx0 = floor(x), fy0 = floor(y);
    double fx = x - fx0, fy = y - fy0;
    long ix = (long)fmod(fx0, (double)t->width), iy = (long)fmod(fy0, (double)t->height);
    if (ix < 0) ix += t->width;
    if (iy < 0) iy += t->height;
    long ix1 = (ix + 1) % t->width, iy1 = (iy + 1) % t->height;
    const long xs[2] = {ix, ix1}, ys[2] = {iy, iy1};
    const double wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy};
    out[0] = out[1] = out[2] = out[3] = 0;
    for (int b = 0; b < 2; b++)
        for (int a = 0; a < 2; a++) {
            const uint8_t *px = t->rgba8 + 4 * ((size_t)ys[b] * t->width + xs[a]);
            double w = wx[a] * wy[b];
            for (int c = 0; c < 4; c++) {
                double v = (t->srgb && c < 3) ? r->srgb_lut[px[c]] : px[c] / 255.0;
                out[c] += w * v;
            }
        }
}

const prw_texture *ref_tex_of(const prw_ref_renderer *r, int idx)
{
    return idx >= 0 && (uint32_t)idx < r->scene->texture_count && r->scene->textures[idx].rgba8 ? &r->scene->textures[idx]
                                                                                               : NULL;
}

/* Whether slot reads something other than uv set 0 unchanged. */
static bool slot_moves(const prw_material *mt, int slot)
{
    const prw_tex_transform *t = &mt->tex_xf[slot];
    return t->tex_coord != 0 || !prw_tex_transform_is_identity(t);
}

/* uv of slot at the vertex weights w3 of triangle prim (prw_shading.h: uv set, then the transform). */
static void slot_uv_w(const ref_inst *in, int slot, uint32_t prim, const double w3[3], double out[2])
{
    const prw_mesh *m = in->mesh;
    const prw_tex_transform *t = &in->mat->tex_xf[slot];
    const float *uvs = t->tex_coord == 1 && m->uvs1 ? m->uvs1 : m->uvs;
    const uint32_t *ix = m->indices + 3 * prim;
    double u = 0, v = 0;
    for (int k = 0; k < 3; k++) {
        u += w3[k] * uvs[2 * ix[k]];
        v += w3[k] * uvs[2 * ix[k] + 1];
    }
    double c = cos((double)t->rotation), sn = sin((double)t->rotation);
    out[0] = prw_uv_xf_u(u, v, t->offset[0], c, sn, t->scale[0], t->scale[1]);
    out[1] = prw_uv_xf_v(u, v, t->offset[1], c, sn, t->scale[0], t->scale[1]);
}

void ref_slot_uv(const ref_inst *in, int slot, uint32_t prim, double b1, double b2, double out[2])
{
    const double w3[3] = {1 - b1 - b2, b1, b2};
    slot_uv_w(in, slot, prim, w3, out);
}

double ref_alpha_at(const prw_ref_renderer *r, const ref_inst *in, uint32_t prim, double b1, double b2)
{
    const prw_material *mt = in->mat;
    const prw_texture *t = ref_tex_of(r, mt->base_color_tex);
    double texel = 1;
    if (t) {
        double uv[2], tx[4];
        ref_slot_uv(in, PRW_TEX_BASE_COLOR, prim, b1, b2, uv);
        ref_tex_sample(r, t, uv, tx);
        texel = tx[3];
    }
    return prw_alpha_from(mt->base_color[3], texel);
}

double ref_coverage_at(const prw_ref_renderer *r, const ref_inst *in, uint32_t prim, double b1, double b2)
{
    switch (in->mat->alpha_mode) {
    case PRW_ALPHA_MASK: return prw_alpha_mask_keeps(ref_alpha_at(r, in, prim, b1, b2), in->mat->alpha_cutoff) ? 1 : 0;
    case PRW_ALPHA_BLEND: return fmin(fmax(ref_alpha_at(r, in, prim, b1, b2), 0.0), 1.0);
    default: return 1;
    }
}

/* A slot's texel at a surface point. */
static void surf_texel(const prw_ref_renderer *r, const ref_inst *in, const double uv0[2], uint32_t prim,
                       const double w3[3], int slot, const prw_texture *t, double out[4])
{
    double uv[2] = {uv0[0], uv0[1]};
    if (slot_moves(in->mat, slot)) slot_uv_w(in, slot, prim, w3, uv);
    ref_tex_sample(r, t, uv, out);
}

/* The key of one ray of a path: camera ray (k = 0) and the BSDF ray leaving vertex k (tag 0), the
 * next-event rays of vertex k (tag 1 + light slot); BLEND coverage is decided from it. */
static uint64_t ray_key(const ref_rng *rng, int k, uint32_t tag)
{
    return ref_splitmix(rng->key ^ ref_splitmix(((uint64_t)(uint32_t)k << 32) | tag) ^ 0x6a09e667f3bcc909ull);
}
enum { TAG_BSDF = 0, TAG_DELTA = 1, TAG_RECT = 0x10000, TAG_ETRI = 0x20000, TAG_ENV = 0x20001 };

/* ---- ray queries ---- */

static bool isect(const prw_ref_renderer *r, const double o[3], const double d[3], double tnear, uint64_t key,
                  bool blend_invisible, struct RTCRayHit *rh)
{
    ref_ray_ctx ctx = {.key = key, .blend_invisible = blend_invisible};
    rtcInitIntersectContext(&ctx.ctx);
    memset(rh, 0, sizeof *rh);
    rh->ray.org_x = (float)o[0];
    rh->ray.org_y = (float)o[1];
    rh->ray.org_z = (float)o[2];
    rh->ray.dir_x = (float)d[0];
    rh->ray.dir_y = (float)d[1];
    rh->ray.dir_z = (float)d[2];
    rh->ray.tnear = (float)tnear;
    rh->ray.tfar = INFINITY;
    rh->ray.mask = 0xffffffffu;
    rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(r->rtc, &ctx.ctx, rh);
    return rh->hit.geomID != RTC_INVALID_GEOMETRY_ID;
}

/* Closest front-facing rect light along the ray with t in (tmin, tmax); -1 if none. */
static int rect_hit(const prw_ref_renderer *r, const double o[3], const double d[3], double tmin, double tmax,
                    double *t_out, int skip)
{
    int best = -1;
    for (uint32_t i = 0; i < r->rect_count; i++) {
        if ((int)i == skip) continue;
        const ref_rect *q = &r->rects[i];
        double de = dot3(d, q->emit);
        if (!(de < 0)) continue; /* back face or parallel: invisible */
        double cmo[3] = {q->c[0] - o[0], q->c[1] - o[1], q->c[2] - o[2]};
        double t = dot3(cmo, q->np) / dot3(d, q->np);
        if (!(t > tmin && t < tmax)) continue;
        double rel[3] = {o[0] + t * d[0] - q->c[0], o[1] + t * d[1] - q->c[1], o[2] + t * d[2] - q->c[2]};
        double a = dot3(rel, q->dx), b = dot3(rel, q->dy);
        if (fabs(a) > 1 || fabs(b) > 1) continue;
        tmax = t;
        best = (int)i;
    }
    *t_out = tmax;
    return best;
}

/* True when the segment from o along d (unit) up to tmax is blocked by a surface or a rect light
 * (other than rect `skip`). */
static bool occluded(const prw_ref_renderer *r, const double o[3], const double d[3], double tmax, int skip,
                     uint64_t key, uint64_t *rays)
{
    (*rays)++;
    double tr;
    if (rect_hit(r, o, d, 0, tmax, &tr, skip) >= 0) return true;
    ref_ray_ctx ctx = {.key = key};
    rtcInitIntersectContext(&ctx.ctx);
    struct RTCRay ray;
    memset(&ray, 0, sizeof ray);
    ray.org_x = (float)o[0];
    ray.org_y = (float)o[1];
    ray.org_z = (float)o[2];
    ray.dir_x = (float)d[0];
    ray.dir_y = (float)d[1];
    ray.dir_z = (float)d[2];
    ray.tnear = 0.0f;
    ray.tfar = isfinite(tmax) ? (float)tmax : INFINITY;
    ray.mask = 0xffffffffu;
    rtcOccluded1(r->rtc, &ctx.ctx, &ray);
    return ray.tfar < 0;
}

static void tri_verts(const ref_inst *in, uint32_t prim, double v[3][3])
{
    const uint32_t *ix = in->mesh->indices + 3 * prim;
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) v[k][c] = in->pos[3 * ix[k] + c];
}

static double offset_eps(const double p[3], double tri_max) { return 2e-6 * (1.0 + fmax(maxabs3(p), tri_max)); }

/* Geometric normal (front side, winding flipped for mirrored instances), unit; returns tri max |coord|. */
static double tri_normal(const ref_inst *in, const double v[3][3], double ng[3])
{
    double a[3], b[3];
    for (int c = 0; c < 3; c++) a[c] = v[1][c] - v[0][c], b[c] = v[2][c] - v[0][c];
    cross3(a, b, ng);
    norm3(ng);
    if (in->flip) ng[0] = -ng[0], ng[1] = -ng[1], ng[2] = -ng[2];
    return fmax(maxabs3(v[0]), fmax(maxabs3(v[1]), maxabs3(v[2])));
}

void ref_tri_geometry(const ref_inst *in, uint32_t prim, double out[4])
{
    double v[3][3];
    tri_verts(in, prim, v);
    out[3] = tri_normal(in, v, out);
}

/* The cached ref_tri_geometry: ng, returns the vertices' max |coordinate|. */
static double tri_ng(const ref_inst *in, uint32_t prim, double ng[3])
{
    const double *t = in->tri + 4 * (size_t)prim;
    ng[0] = t[0], ng[1] = t[1], ng[2] = t[2];
    return t[3];
}

static void fill_surf(const prw_ref_renderer *r, const struct RTCRayHit *rh, const double d[3], surf *s)
{
    const ref_inst *in = &r->inst[rh->hit.geomID];
    s->in = in;
    s->prim = rh->hit.primID;
    double v[3][3];
    tri_verts(in, s->prim, v);
    double bu = rh->hit.u, bv = rh->hit.v, bw = 1 - bu - bv;
    for (int c = 0; c < 3; c++) s->p[c] = bw * v[0][c] + bu * v[1][c] + bv * v[2][c];
    double tm = tri_ng(in, s->prim, s->ng);
    s->eps = offset_eps(s->p, tm);
    s->front = dot3(s->ng, d) < 0;
    const prw_mesh *m = in->mesh;
    const uint32_t *ix = m->indices + 3 * s->prim;
    double w3[3] = {bw, bu, bv};
    memcpy(s->bary, w3, sizeof w3);
    double no[3] = {0, 0, 0};
    s->uv[0] = s->uv[1] = 0;
    for (int k = 0; k < 3; k++) {
        for (int c = 0; c < 3; c++) no[c] += w3[k] * m->normals[3 * ix[k] + c];
        s->uv[0] += w3[k] * m->uvs[2 * ix[k]];
        s->uv[1] += w3[k] * m->uvs[2 * ix[k] + 1];
    }
    for (int row = 0; row < 3; row++)
        s->ns[row] = in->nmat[row * 3] * no[0] + in->nmat[row * 3 + 1] * no[1] + in->nmat[row * 3 + 2] * no[2];
    norm3(s->ns);
    if (!(dot3(s->ns, s->ns) > 0.5)) memcpy(s->ns, s->ng, sizeof s->ns);
    s->t = rh->ray.tfar;
}

/* Emitted radiance of the surface (material emission x emissive texture). */
static bool surf_emission(const prw_ref_renderer *r, const surf *s, double Le[3])
{
    const prw_material *mt = s->in->mat;
    if (!(mt->emission[0] > 0 || mt->emission[1] > 0 || mt->emission[2] > 0)) return false;
    for (int c = 0; c < 3; c++) Le[c] = mt->emission[c];
    const prw_texture *t = ref_tex_of(r, mt->emissive_tex);
    if (t) {
        double tx[4];
        surf_texel(r, s->in, s->uv, s->prim, s->bary, PRW_TEX_EMISSIVE, t, tx);
        for (int c = 0; c < 3; c++) Le[c] *= tx[c];
    }
    return Le[0] > 0 || Le[1] > 0 || Le[2] > 0;
}

/* ---- shading ---- */

typedef struct shade {
    prw_bsdf b;
    double t[3], bt[3], n[3]; /* local frame, n = shading normal (BTF kind: the BTF's frame, t along dP/du) */
    double wo[3];             /* local */
    prw_bsdf_lobes lobes;     /* prw_bsdf_lobes_at(b, wo): shared by the BSDF sample and the MIS pdfs */
    const prw_btf_material *btf; /* the BTF kind: evaluated at texel coordinates xy; NULL: the glTF model */
    double xy[2];
} shade;

/* ---- the BTF kind beside the glTF model: its value, the sampling density, a sample ----
 * The BTF stores f cos theta_l itself (prw_btf_synth.h: radiance per lux of normal illuminance), so its
 * value replaces f * cos; it is sampled cosine-weighted (density cos theta_i / pi, positive wherever the
 * BTF can be non-zero, so the estimator stays unbiased; the path weight is value * pi / cos theta_i). */
static void btf_fcos(const shade *sh, const double wl[3], double fc[3])
{
    float v[3];
    prw_btf_material_eval(sh->btf, sh->xy[0], sh->xy[1], sh->wo, wl, v);
    for (int c = 0; c < 3; c++) fc[c] = fmax((double)v[c], 0.0); /* codec ringing below 0: no light */
}

static double shade_pdf(const shade *sh, const double wl[3])
{
    if (sh->btf) return prw_pdf_cosine(wl);
    return prw_bsdf_pdf_at(&sh->b, &sh->lobes, sh->wo, wl);
}

static bool shade_sample(const shade *sh, const double u[3], double wl[3], double *pdf)
{
    if (sh->btf) { /* the shared cosine sampler (prw_bsdf.h; its chi-square test is in tests/materials) */
        prw_sample_cosine(u, wl);
        *pdf = prw_pdf_cosine(wl);
        return true;
    }
    return prw_bsdf_sample_at(&sh->b, &sh->lobes, sh->wo, u, wl, pdf);
}

static void to_local(const shade *sh, const double w[3], double l[3])
{
    l[0] = dot3(w, sh->t);
    l[1] = dot3(w, sh->bt);
    l[2] = dot3(w, sh->n);
}

static void to_world(const shade *sh, const double l[3], double w[3])
{
    for (int c = 0; c < 3; c++) w[c] = sh->t[c] * l[0] + sh->bt[c] * l[1] + sh->n[c] * l[2];
}

/* A normal map (texture t of slot `slot`, xy scale `scale`) applied to the normal n in place, in the
 * interpolated tangent frame of the mesh (prw_shading.h: decode, frame of a transformed slot). */
static void apply_normal_map(const prw_ref_renderer *r, const surf *s, const prw_texture *t, int slot, double scale,
                             double n[3])
{
    const prw_mesh *m = s->in->mesh;
    const uint32_t *ix = m->indices + 3 * s->prim;
    double tg[3] = {0, 0, 0}, sign = 0;
    const double *area = s->bary;
    for (int k = 0; k < 3; k++) {
        const float *tt = m->tangents + 4 * ix[k];
        for (int c = 0; c < 3; c++) tg[c] += area[k] * tt[c];
        sign += area[k] * tt[3];
    }
    double tw[3];
    for (int row = 0; row < 3; row++)
        tw[row] = s->in->lmat[row * 3] * tg[0] + s->in->lmat[row * 3 + 1] * tg[1] + s->in->lmat[row * 3 + 2] * tg[2];
    double dn = dot3(tw, n);
    for (int c = 0; c < 3; c++) tw[c] -= n[c] * dn;
    double tl = sqrt(dot3(tw, tw));
    if (!(tl > 1e-8)) return;
    for (int c = 0; c < 3; c++) tw[c] /= tl;
    double bw[3];
    cross3(n, tw, bw);
    if (sign < 0) bw[0] = -bw[0], bw[1] = -bw[1], bw[2] = -bw[2];
    double tx[4];
    surf_texel(r, s->in, s->uv, s->prim, s->bary, slot, t, tx);
    double x = prw_normal_texel(tx[0], scale), y = prw_normal_texel(tx[1], scale), z = prw_normal_texel(tx[2], 1.0);
    const prw_tex_transform *xf = &s->in->mat->tex_xf[slot];
    if (!prw_tex_transform_is_identity(xf)) {
        double c = cos((double)xf->rotation), sn = sin((double)xf->rotation);
        double xt = prw_normal_xf_t(x, y, c, sn, xf->scale[0], xf->scale[1]);
        double yb = prw_normal_xf_b(x, y, c, sn, xf->scale[0], xf->scale[1]);
        x = xt, y = yb;
    }
    for (int c = 0; c < 3; c++) n[c] = tw[c] * x + bw[c] * y + n[c] * z;
    norm3(n);
}

/* bend a shading normal facing away from the viewer back (prw_shading.h) */
static void bend_normal(double n[3], const double wo[3])
{
    double bend = prw_normal_bend(dot3(n, wo));
    if (bend > 0) {
        for (int c = 0; c < 3; c++) n[c] += wo[c] * bend;
        norm3(n);
    }
}

/* The BTF kind's frame and texel coordinates (prw_scene.h, prw_material.btf_file): the triangle's dP/du and
 * dP/dv (world metres per uv unit, uv set 0) give x = dP/du made tangent to the shading normal, y = n x x
 * turned towards dP/dv, and texel (u |dP/du|, v |dP/dv|) / texel size.  A triangle without a usable uv
 * mapping keeps the arbitrary frame and texel (0.5, 0.5). */
static void btf_frame(const surf *s, shade *sh, const double wo[3])
{
    const prw_mesh *m = s->in->mesh;
    const uint32_t *ix = m->indices + 3 * s->prim;
    double v[3][3], uv[3][2];
    tri_verts(s->in, s->prim, v);
    for (int k = 0; k < 3; k++) uv[k][0] = m->uvs[2 * ix[k]], uv[k][1] = m->uvs[2 * ix[k] + 1];
    double e1[3], e2[3], du1 = uv[1][0] - uv[0][0], dv1 = uv[1][1] - uv[0][1], du2 = uv[2][0] - uv[0][0],
                         dv2 = uv[2][1] - uv[0][1];
    for (int c = 0; c < 3; c++) e1[c] = v[1][c] - v[0][c], e2[c] = v[2][c] - v[0][c];
    double det = du1 * dv2 - du2 * dv1, texel = s->in->mat->btf_texel_m;
    sh->xy[0] = sh->xy[1] = 0.5;
    double dpu[3], dpv[3];
    for (int c = 0; c < 3; c++) {
        dpu[c] = (e1[c] * dv2 - e2[c] * dv1) / det;
        dpv[c] = (e2[c] * du1 - e1[c] * du2) / det;
    }
    double lu = sqrt(dot3(dpu, dpu)), lv = sqrt(dot3(dpv, dpv));
    if (!(fabs(det) > 1e-20) || !isfinite(lu) || !isfinite(lv) || !(lu > 0) || !(lv > 0)) return;
    double t[3], dn = dot3(dpu, sh->n);
    for (int c = 0; c < 3; c++) t[c] = dpu[c] - sh->n[c] * dn;
    double tl = sqrt(dot3(t, t));
    if (!(tl > 1e-12 * lu)) return;
    for (int c = 0; c < 3; c++) t[c] /= tl;
    double b[3];
    cross3(sh->n, t, b);
    if (dot3(b, dpv) < 0) b[0] = -b[0], b[1] = -b[1], b[2] = -b[2];
    memcpy(sh->t, t, sizeof t);
    memcpy(sh->bt, b, sizeof b);
    to_local(sh, wo, sh->wo);
    sh->xy[0] = s->uv[0] * lu / texel;
    sh->xy[1] = s->uv[1] * lv / texel;
}

/* px_m: the pixel footprint across the ray at the hit, metres (0: none) */
static void setup_shade(const prw_ref_renderer *r, const surf *s, const double d[3], double px_m, shade *sh)
{
    const prw_material *mt = s->in->mat;
    memset(&sh->b, 0, sizeof sh->b);
    double base[4] = {mt->base_color[0], mt->base_color[1], mt->base_color[2], mt->base_color[3]};
    const prw_texture *tb = ref_tex_of(r, mt->base_color_tex);
    if (tb) {
        double tx[4];
        surf_texel(r, s->in, s->uv, s->prim, s->bary, PRW_TEX_BASE_COLOR, tb, tx);
        for (int c = 0; c < 4; c++) base[c] *= tx[c];
    }
    double metallic = mt->metallic, rough = mt->roughness;
    const prw_texture *tm = ref_tex_of(r, mt->metal_rough_tex);
    if (tm) {
        double tx[4];
        surf_texel(r, s->in, s->uv, s->prim, s->bary, PRW_TEX_METAL_ROUGH, tm, tx);
        rough = prw_roughness_from(rough, tx[1]);
        metallic = prw_metallic_from(metallic, tx[2]);
    }
    for (int c = 0; c < 3; c++) sh->b.base[c] = base[c];
    sh->b.metallic = metallic;
    sh->b.roughness = rough;
    sh->b.specular = mt->specular;

    double n[3];
    memcpy(n, s->ns, sizeof n);
    /* single-sided back faces never get here (passed through or black) */
    if (prw_normal_flips(mt->double_sided || s->in->two_sided, s->front)) n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    double nc[3]; /* the clear coat's normal: the surface's, or its own normal map (prw_shading.h) */
    memcpy(nc, n, sizeof nc);
    const prw_texture *tn = ref_tex_of(r, mt->normal_tex);
    if (tn) apply_normal_map(r, s, tn, PRW_TEX_NORMAL, mt->normal_scale, n);
    double wo[3] = {-d[0], -d[1], -d[2]};
    bend_normal(n, wo);
    memcpy(sh->n, n, sizeof n);
    prw_frame_from_normal(sh->n, sh->t, sh->bt);
    to_local(sh, wo, sh->wo);
    if (mt->clearcoat > 0) {
        double cc = mt->clearcoat, rc = mt->clearcoat_roughness, tx[4];
        const prw_texture *t = ref_tex_of(r, mt->clearcoat_tex);
        if (t) {
            surf_texel(r, s->in, s->uv, s->prim, s->bary, PRW_TEX_CLEARCOAT, t, tx);
            cc = prw_clearcoat_from(cc, tx[0]);
        }
        t = ref_tex_of(r, mt->clearcoat_roughness_tex);
        if (t) {
            surf_texel(r, s->in, s->uv, s->prim, s->bary, PRW_TEX_CLEARCOAT_ROUGHNESS, t, tx);
            rc = prw_clearcoat_roughness_from(rc, tx[1]);
        }
        t = ref_tex_of(r, mt->clearcoat_normal_tex);
        if (t) apply_normal_map(r, s, t, PRW_TEX_CLEARCOAT_NORMAL, mt->clearcoat_normal_scale, nc);
        bend_normal(nc, wo);
        sh->b.clearcoat = cc;
        sh->b.clearcoat_roughness = rc;
        to_local(sh, nc, sh->b.coat_n);
        norm3(sh->b.coat_n);
    }
    sh->lobes = prw_bsdf_lobes_at(&sh->b, sh->wo);
    sh->btf = ref_btf_of(r, s->in);
    if (sh->btf && mt->btf_scale_rule && sh->btf->p.has_average && px_m > 0 &&
        px_m > mt->btf_texel_m * fabs(sh->wo[2])) {
        /* the scale rule: the texel is below the pixel footprint (px_m / |cos theta_v|): the fitted average */
        const prw_btf_average *av = &sh->btf->p.average;
        sh->btf = NULL;
        memset(&sh->b, 0, sizeof sh->b);
        for (int c = 0; c < 3; c++) sh->b.base[c] = av->base[c];
        sh->b.metallic = av->metallic, sh->b.roughness = av->roughness, sh->b.specular = av->specular;
        sh->lobes = prw_bsdf_lobes_at(&sh->b, sh->wo);
    }
    if (sh->btf) btf_frame(s, sh, wo);
}

/* Class weight per channel for the (indirect-)diffuse-last / glossy-last filters: the diffuse lobe's share
 * (prw_brdf_diffuse_channel of the shared model) of the BSDF value fv for direction wl (local). */
static void class_weight(prw_ref_filter f, const shade *sh, const double wl[3], const double fv[3], double cw[3])
{
    bool diffuse = f.kind == PRW_REF_DIFFUSE_LAST || f.kind == PRW_REF_INDIRECT_DIFFUSE_LAST;
    bool glossy = f.kind == PRW_REF_GLOSSY_LAST || f.kind == PRW_REF_INDIRECT_GLOSSY_LAST;
    if (!diffuse && !glossy) { /* the other filters weigh every class 1: no diffuse evaluation */
        cw[0] = cw[1] = cw[2] = 1;
        return;
    }
    double kd[3];
    if (sh->btf) memcpy(kd, fv, sizeof kd); /* a BTF has no lobes: it counts as diffuse */
    else prw_bsdf_eval_diffuse_at(&sh->b, &sh->lobes, sh->wo, wl, kd);
    for (int c = 0; c < 3; c++) {
        double x = fv[c] > 0 ? kd[c] / fv[c] : 0;
        x = fmin(fmax(x, 0.0), 1.0);
        cw[c] = diffuse ? x : 1 - x;
    }
}

typedef struct path {
    const prw_ref_renderer *r;
    prw_ref_filter f;
    ref_rng *rng;
    uint64_t *rays;
    double beta[3]; /* throughput (filter-independent) */
    double cls[3];  /* filter class weights fixed at the eye vertex */
    double L[3];
    int k;          /* scattering vertices so far */
} path;

static void add(path *pa, const double w3[3], const double Le[3], double w)
{
    for (int c = 0; c < 3; c++) pa->L[c] += pa->beta[c] * w3[c] * Le[c] * w;
}

/* One next-event connection from s in world direction wi (unit): Li is radiance (pdf_l > 0) or the
 * delta light's irradiance-like factor (pdf_l == 0).  target: the light point (NULL: infinitely far
 * along wi); the shadow ray runs from the offset origin to target, stopping target_eps short. */
static void connect(path *pa, const surf *s, const shade *sh, const double wi[3], const double *target,
                    double target_eps, int skip_rect, const double Li[3], double pdf_l, uint32_t tag)
{
    if (!(dot3(s->ng, wi) > 0)) return; /* below the geometric surface */
    double wl[3];
    to_local(sh, wi, wl);
    if (!(wl[2] > 0)) return;
    double fv[3]; /* the glTF kind: f; the BTF kind: f cos theta_i (what it stores) */
    if (sh->btf) btf_fcos(sh, wl, fv);
    else prw_bsdf_eval_at(&sh->b, &sh->lobes, sh->wo, wl, fv);
    if (!(fv[0] > 0 || fv[1] > 0 || fv[2] > 0)) return;
    double o[3], sd[3], tmax = INFINITY;
    for (int c = 0; c < 3; c++) o[c] = s->p[c] + s->ng[c] * s->eps;
    memcpy(sd, wi, sizeof sd);
    if (target) {
        for (int c = 0; c < 3; c++) sd[c] = target[c] - o[c];
        double dist = sqrt(dot3(sd, sd));
        if (!(dist > 0)) return;
        for (int c = 0; c < 3; c++) sd[c] /= dist;
        tmax = dist * (1 - 1e-7) - target_eps;
        if (!(tmax > 0)) return;
    }
    if (occluded(pa->r, o, sd, tmax, skip_rect, ray_key(pa->rng, pa->k, tag), pa->rays)) return;
    double w = 1;
    if (pdf_l > 0) w = power_heuristic(pdf_l, shade_pdf(sh, wl)) / pdf_l;
    double cw[3] = {1, 1, 1};
    if (pa->k == 1) class_weight(pa->f, sh, wl, fv, cw);
    if (sh->btf)
        for (int c = 0; c < 3; c++) pa->L[c] += pa->beta[c] * pa->cls[c] * cw[c] * fv[c] * Li[c] * w;
    else
        for (int c = 0; c < 3; c++) pa->L[c] += pa->beta[c] * pa->cls[c] * cw[c] * fv[c] * wl[2] * Li[c] * w;
}

static void next_event(path *pa, const surf *s, const shade *sh, uint32_t base)
{
    const prw_ref_renderer *r = pa->r;
    /* skipping a class of emitters leaves the others' random numbers alone (fixed dimensions) */
    const bool local = accept_path(pa->f, pa->k, false);
    /* delta lights */
    for (uint32_t i = 0; i < r->delta_count && local; i++) {
        const ref_delta *dl = &r->deltas[i];
        double wi[3], Li[3];
        if (dl->type == PRW_LIGHT_DIRECTIONAL) {
            for (int c = 0; c < 3; c++) wi[c] = -dl->dir[c], Li[c] = dl->I[c];
        } else {
            double dv[3] = {dl->p[0] - s->p[0], dl->p[1] - s->p[1], dl->p[2] - s->p[2]};
            double d2 = fmax(dot3(dv, dv), 1e-8), dist = sqrt(d2);
            for (int c = 0; c < 3; c++) wi[c] = dv[c] / dist;
            double E = 1.0 / d2;
            if (dl->range > 0) E *= prw_range_window(d2, dl->range);
            if (dl->type == PRW_LIGHT_SPOT) {
                double cd = -dot3(wi, dl->dir);
                E *= prw_spot_factor(cd, dl->cos_inner, dl->cos_outer);
            }
            if (!(E > 0)) continue;
            for (int c = 0; c < 3; c++) Li[c] = dl->I[c] * E;
        }
        connect(pa, s, sh, wi, dl->type == PRW_LIGHT_DIRECTIONAL ? NULL : dl->p, 0, -1, Li, 0, TAG_DELTA + i);
    }
    /* rect lights: uniform area sampling */
    for (uint32_t i = 0; i < r->rect_count && local; i++) {
        const ref_rect *q = &r->rects[i];
        pa->rng->dim = base + 9 + 2 * i;
        double a = 2 * ref_rand(pa->rng) - 1, b = 2 * ref_rand(pa->rng) - 1;
        double lp[3], dv[3];
        for (int c = 0; c < 3; c++) {
            lp[c] = q->c[c] + a * q->ax[c] + b * q->ay[c];
            dv[c] = lp[c] - s->p[c];
        }
        double d2 = dot3(dv, dv), dist = sqrt(d2);
        if (!(dist > 0)) continue;
        double wi[3] = {dv[0] / dist, dv[1] / dist, dv[2] / dist};
        double cl = -dot3(wi, q->emit);
        if (!(cl > 0)) continue;
        double pdf = d2 / (cl * q->area);
        connect(pa, s, sh, wi, lp, 0, (int)i, q->L, pdf, TAG_RECT + i);
    }
    /* emissive triangles: one sample */
    if (r->etri_count && local) {
        pa->rng->dim = base + 4;
        double u0 = ref_rand(pa->rng), u1 = ref_rand(pa->rng), u2 = ref_rand(pa->rng);
        double x = u0 * r->etri_cdf[r->etri_count];
        uint32_t lo = 0, hi = r->etri_count - 1;
        while (lo < hi) {
            uint32_t mid = (lo + hi + 1) / 2;
            if (r->etri_cdf[mid] <= x) lo = mid;
            else hi = mid - 1;
        }
        while (lo > 0 && r->etri_cdf[lo + 1] == r->etri_cdf[lo]) lo--;
        const ref_inst *in = &r->inst[r->etri_inst[lo]];
        uint32_t prim = r->etri_prim[lo];
        double v[3][3], ng[3];
        tri_verts(in, prim, v);
        double tm = tri_ng(in, prim, ng);
        double su = sqrt(u1), b0 = 1 - su, b1 = u2 * su, b2 = 1 - b0 - b1;
        double lp[3], dv[3];
        for (int c = 0; c < 3; c++) {
            lp[c] = b0 * v[0][c] + b1 * v[1][c] + b2 * v[2][c];
            dv[c] = lp[c] - s->p[c];
        }
        double d2 = dot3(dv, dv), dist = sqrt(d2);
        if (dist > 0) {
            double wi[3] = {dv[0] / dist, dv[1] / dist, dv[2] / dist};
            double cl = -dot3(wi, ng);
            if (in->mat->double_sided || in->two_sided) cl = fabs(cl);
            if (cl > 0) {
                /* emission at the sampled point (texture via its uv) */
                surf ls;
                memset(&ls, 0, sizeof ls);
                ls.in = in;
                ls.prim = prim;
                const uint32_t *ix = in->mesh->indices + 3 * prim;
                double w3[3] = {b0, b1, b2};
                for (int k = 0; k < 3; k++) {
                    ls.uv[0] += w3[k] * in->mesh->uvs[2 * ix[k]];
                    ls.uv[1] += w3[k] * in->mesh->uvs[2 * ix[k] + 1];
                }
                memcpy(ls.bary, w3, sizeof w3);
                double Le[3];
                if (surf_emission(r, &ls, Le)) {
                    /* a MASK / BLEND emitter emits where (and as much as) its surface is there */
                    if (in->mat->alpha_mode != PRW_ALPHA_OPAQUE) {
                        double cov = ref_coverage_at(r, in, prim, b1, b2);
                        for (int c = 0; c < 3; c++) Le[c] *= cov;
                    }
                    double pdf = in->emit_pdf_area * d2 / cl;
                    if (Le[0] > 0 || Le[1] > 0 || Le[2] > 0)
                        connect(pa, s, sh, wi, lp, 2 * offset_eps(lp, tm), -1, Le, pdf, TAG_ETRI);
                }
            }
        }
    }
    /* environment: one sample */
    if (r->env.kind && accept_path(pa->f, pa->k, true)) {
        pa->rng->dim = base + 7;
        double u0 = ref_rand(pa->rng), u1 = ref_rand(pa->rng);
        double wi[3], Le[3], pdf;
        if (ref_env_sample(&r->env, u0, u1, wi, Le, &pdf)) connect(pa, s, sh, wi, NULL, 0, -1, Le, pdf, TAG_ENV);
    }
}

/* The camera ray through image point (x, y): origin (camera-relative), unit direction, and the ray
 * distance of the near plane. */
void ref_camera_ray(const prw_ref_renderer *r, const prw_view *v, double x, double y, double o[3], double d[3],
                    double *tnear)
{
    prw_dvec3 dd = prw_view_ray_dir(v, x, y);
    o[0] = v->eye.x - r->origin.x, o[1] = v->eye.y - r->origin.y, o[2] = v->eye.z - r->origin.z;
    d[0] = dd.x, d[1] = dd.y, d[2] = dd.z;
    const double *m = v->view.m;
    double fwd[3] = {-m[2], -m[6], -m[10]};
    *tnear = v->znear > 0 ? v->znear / fmax(dot3(d, fwd), 1e-6) : 0;
}

void ref_trace_sample(const prw_ref_renderer *r, const prw_view *v, prw_ref_filter f, double x, double y,
                      ref_rng *rng, double out[3], uint64_t *rays)
{
    double o[3], d[3], tnear;
    ref_camera_ray(r, v, x, y, o, d, &tnear);
    /* the pixel's angular size at the image centre (the BTF scale rule) */
    double spread = v->height ? (v->tan_top - v->tan_bottom) / v->height : 0;
    ref_trace_ray_px(r, o, d, tnear, true, fabs(spread), f, rng, out, rays, NULL);
}

void ref_trace_ray(const prw_ref_renderer *r, const double o_in[3], const double d_in[3], double tnear, bool camera,
                   prw_ref_filter f, ref_rng *rng, double out[3], uint64_t *rays, bool *back_first)
{
    ref_trace_ray_px(r, o_in, d_in, tnear, camera, 0, f, rng, out, rays, back_first);
}

void ref_trace_ray_px(const prw_ref_renderer *r, const double o_in[3], const double d_in[3], double tnear, bool camera,
                      double spread, prw_ref_filter f, ref_rng *rng, double out[3], uint64_t *rays, bool *back_first)
{
    if (back_first) *back_first = false;
    path pa;
    memset(&pa, 0, sizeof pa);
    pa.r = r;
    pa.f = f;
    pa.rng = rng;
    pa.rays = rays;
    for (int c = 0; c < 3; c++) pa.beta[c] = pa.cls[c] = 1;
    if (f.kind == PRW_REF_ENVIRONMENT_DIRECT && !r->env.kind) {
        out[0] = out[1] = out[2] = 0; /* no environment: nothing to trace */
        return;
    }
    const int kmax = max_depth(f);
    const uint32_t S = 9 + 2 * r->rect_count;

    double o[3] = {o_in[0], o_in[1], o_in[2]}, d[3] = {d_in[0], d_in[1], d_in[2]};
    double pdf_prev = 0; /* solid-angle density of the BSDF sample that made the current ray */

    for (;;) {
        struct RTCRayHit rh;
        surf s;
        bool hit = false;
        /* camera rays pass through back faces of single-sided materials (the rasterizer culls them) */
        uint64_t key = ray_key(rng, pa.k, TAG_BSDF); /* the camera ray (k = 0) or the BSDF ray leaving vertex k */
        for (int guard = 0; guard < 256; guard++) {
            (*rays)++;
            hit = isect(r, o, d, tnear, key, false, &rh);
            if (!hit) break;
            fill_surf(r, &rh, d, &s);
            if (pa.k > 0 || !camera || s.front || (s.in->mat->double_sided || s.in->two_sided)) break;
            tnear = s.t + s.eps;
            hit = false;
            if (guard == 255) break;
        }
        double t_surf = hit ? s.t : INFINITY;
        double t_rect;
        int ri = rect_hit(r, o, d, tnear, t_surf, &t_rect, -1);
        if (ri >= 0) {
            if (accept_path(f, pa.k, false)) {
                const ref_rect *q = &r->rects[ri];
                double w = 1;
                if (pa.k > 0) {
                    double cl = -dot3(d, q->emit);
                    double pdf_l = t_rect * t_rect / (cl * q->area);
                    w = power_heuristic(pdf_prev, pdf_l);
                }
                add(&pa, pa.cls, q->L, w);
            }
            break;
        }
        if (!hit) {
            if (r->env.kind && accept_path(f, pa.k, true)) {
                double Le[3], pdf_l;
                ref_env_eval(&r->env, d, Le, &pdf_l);
                double w = pa.k > 0 ? power_heuristic(pdf_prev, pdf_l) : 1;
                add(&pa, pa.cls, Le, w);
            }
            break;
        }
        if (!s.front && !(s.in->mat->double_sided || s.in->two_sided)) { /* opaque black back face */
            if (pa.k == 0 && back_first) *back_first = true;
            break;
        }
        double Le[3];
        if (accept_path(f, pa.k, false) && surf_emission(r, &s, Le)) {
            double w = 1;
            if (pa.k > 0) {
                double cl = fabs(dot3(d, s.ng));
                double pdf_l = cl > 0 ? s.in->emit_pdf_area * s.t * s.t / cl : 0;
                w = power_heuristic(pdf_prev, pdf_l);
            }
            add(&pa, pa.cls, Le, w);
        }
        pa.k++;
        if (pa.k > kmax) break;
        if (!s.front)
            for (int c = 0; c < 3; c++) s.ng[c] = -s.ng[c];
        shade sh;
        setup_shade(r, &s, d, pa.k == 1 ? spread * s.t : 0, &sh);
        uint32_t base = 2 + (uint32_t)(pa.k - 1) * S;
        /* next-event paths from this vertex have pa.k scattering vertices */
        if (accept(f, pa.k)) next_event(&pa, &s, &sh, base);
        /* BSDF sample (its emitter hits also have pa.k scattering vertices) */
        rng->dim = base;
        double u[3] = {ref_rand(rng), ref_rand(rng), ref_rand(rng)};
        double wl[3], pdf;
        if (!shade_sample(&sh, u, wl, &pdf) || !(pdf > 0) || !(wl[2] > 0)) break;
        double wi[3];
        to_world(&sh, wl, wi);
        norm3(wi);
        if (!(dot3(s.ng, wi) > 0)) break;
        double fv[3]; /* as in connect: f, or the BTF's f cos theta_i */
        if (sh.btf) btf_fcos(&sh, wl, fv);
        else prw_bsdf_eval_at(&sh.b, &sh.lobes, sh.wo, wl, fv);
        if (!(fv[0] > 0 || fv[1] > 0 || fv[2] > 0)) break;
        if (pa.k == 1) class_weight(f, &sh, wl, fv, pa.cls);
        if (sh.btf)
            for (int c = 0; c < 3; c++) pa.beta[c] *= fv[c] / pdf;
        else
            for (int c = 0; c < 3; c++) pa.beta[c] *= fv[c] * wl[2] / pdf;
        pdf_prev = pdf;
        if (pa.k >= RR_START) {
            rng->dim = base + 3;
            double q = fmin(RR_MAX_SURVIVAL, fmax(pa.beta[0], fmax(pa.beta[1], pa.beta[2])));
            if (!(ref_rand(rng) < q)) break;
            for (int c = 0; c < 3; c++) pa.beta[c] /= q;
        }
        if (pa.k >= SAFETY_DEPTH) break;
        for (int c = 0; c < 3; c++) o[c] = s.p[c] + s.ng[c] * s.eps;
        memcpy(d, wi, sizeof d);
        tnear = 0;
    }
    for (int c = 0; c < 3; c++) out[c] = pa.L[c];
}

bool prw_ref_primary_hit(const prw_ref_renderer *r, const prw_view *v, double x, double y, prw_ref_hit *out)
{
    double o[3], d[3], tnear;
    ref_camera_ray(r, v, x, y, o, d, &tnear);
    struct RTCRayHit rh;
    surf s;
    bool hit = false;
    for (int guard = 0; guard < 256 && !hit; guard++) {
        if (!isect(r, o, d, tnear, 0, true, &rh)) break;
        fill_surf(r, &rh, d, &s);
        if (s.front || s.in->mat->double_sided || s.in->two_sided) hit = true;
        else tnear = s.t + s.eps;
    }
    double t_rect;
    int ri = rect_hit(r, o, d, tnear, hit ? s.t : INFINITY, &t_rect, -1);
    if (ri >= 0) {
        const ref_rect *q = &r->rects[ri];
        out->t = t_rect;
        out->position = prw_v3(o[0] + d[0] * t_rect + r->origin.x, o[1] + d[1] * t_rect + r->origin.y,
                               o[2] + d[2] * t_rect + r->origin.z);
        out->normal = prw_v3(-q->emit[0], -q->emit[1], -q->emit[2]);
        out->material = -1;
        return true;
    }
    if (!hit) return false;
    shade sh;
    setup_shade(r, &s, d, 0, &sh);
    out->t = s.t;
    out->position = prw_v3(s.p[0] + r->origin.x, s.p[1] + r->origin.y, s.p[2] + r->origin.z);
    out->normal = prw_v3(sh.n[0], sh.n[1], sh.n[2]);
    out->material = -2;
    for (uint32_t i = 0; i < r->scene->material_count; i++)
        if (s.in->mat == &r->scene->materials[i]) out->material = (int)i;
    return true;
}
