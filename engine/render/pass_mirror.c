/* pass_mirror — planar mirrors (DESIGN.md §4: the specular term of a reflector of roughness ~0), two
 * passes per view, three with a glossy reflector:
 *   mirror      the scene's drawables re-rendered from the view reflected in the reflector's plane
 *               (camera-relative to the reflected eye, double until then), winding flipped, with a user
 *               clip plane just in front of the mirror (gl_ClipDistance: what lies behind it is not
 *               seen in it), into "mirror_hdr" + "mirror_depth" (the view's internal size times the knob
 *               mirror_scale, one sample; a glossy reflector only into its top-left part, the knob
 *               glossy_scale's fraction of it);
 *               emission left out (globals params.z): a light seen in the mirror is carried by the
 *               direct term's specular lobe at the mirror (k = 1 paths), so the image holds k >= 2:
 *               direct light at the reflected surfaces and, with light maps, their baked indirect diffuse
 *               (the recipe is `lightmapped`: the base pass's PRW_PIPE_GI pipelines with the clip plane).
 *   mirror_glossy  for a glossy reflector (roughness above 0.05): on that part's grid, the mirror image
 *               convolved by the reflected GGX lobe (DESIGN.md §4: radius 2 z_r tan(theta_h), z_r from
 *               "mirror_depth", kernel_taps taps importance-sampled from D_GGX cos over the cone holding
 *               99.5 % of it; mirror_glossy.frag) into "mirror_glossy", in the texels mirror_add reads.
 *   mirror_add  full screen, additive into the base pass's radiance: in the pixels whose G-buffer
 *               material id is the reflector's, Fresnel(n.v) x the mirror image (mirror_add.frag; at
 *               mirror_scale < 1 looked up bilinearly); for a glossy reflector "mirror_glossy" (bilinear)
 *               times the split-sum reflectance F0 A + B (prw_env_dfg) instead.
 * So the final image = base pass + this term.
 *
 * Reflectors (found when the graph is built): the drawn meshes of a material of roughness <= 0.05 (or up to
 * the glossy_max_roughness knob)
 * without roughness or normal textures, opaque, with a specular lobe (metallic > 0 or specular > 0),
 * every triangle of which lies in one plane (within 1e-5 of the extent).  A material drawn on two
 * planes or curved is not a reflector.  Up to the max_reflectors knob are rendered per view, those
 * covering the most of the view's pixels (a bounding-rectangle estimate), each into its own mirror image
 * ("mirror_hdr"/"mirror_depth" for the first, "mirror_hdrK"/"mirror_depthK" for the K+1-th: graph images,
 * kept across frames) and added in its own pixels (G-buffer id); the others show only their direct term.
 * Not in the graph: no reflector, mirror_recursion = 0, supersampling (the G-buffer size), a single term
 * drawn (prw_render_desc.terms: direct or indirect diffuse, which hold no reflection).  needed() is
 * false in multiview and reprojected stereo frames (not yet), and for a view when the reflector is
 * behind the eye, outside the frustum, seen edge-on or from its back, or its footprint holds no pixel
 * centre (the rectangle bounding its vertices' projections, clipped to the view, tested against the
 * pixel centres: a conservative test — a vertex behind the eye counts the whole view as covered). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_types.h"
#include "lightmap_gpu.h"
#include "prw_brdf.h"
#include "prw_env.h"
#include "pipes.h"
#include "prw_shaders.h"
#include "scene_gpu.h"
#include "view_globals.h"

#define MIRROR_MAX_ROUGHNESS 0.05
#define MIRROR_MAX_REFLECTORS 8
#define MIRROR_MAX_DRAWN 4 /* mirror images per view (the max_reflectors knob's upper bound) */
#define MIRROR_MAX_CORNERS 64 /* more vertices: the corners of their bounding box in the plane's frame */
#define MIRROR_PLANARITY 1e-5 /* of the reflector's extent */
#define MIRROR_CLIP_OFFSET 1e-4 /* metres in front of the mirror: the mirror's own surface is clipped */
#define MIRROR_DFG_COUNT 32     /* split-sum table entries over mu = n.v (entry i at (i + 0.5) / count) */

typedef struct reflector {
    int material;
    uint32_t slot;      /* material slot (G-buffer id - 1) */
    prw_dvec3 n;        /* unit normal (the front faces' side) */
    double d;           /* plane n.x = d */
    bool two_sided;
    prw_dvec3 corners[MIRROR_MAX_CORNERS];
    uint32_t corner_count;
    float dfg[MIRROR_DFG_COUNT][4]; /* glossy: A, B of the split sum at mu_i (unused for sharp mirrors) */
    prw_dvec3 lo, hi;   /* world bounds of its triangles */
    double rho_d;       /* luminance of its diffuse albedo, (1 - metallic) x base colour (the factor) */
    double rho_seen;    /* the largest albedo luminance of the other materials (base colour factors): what it
                           may reflect, for the skip rule */
} reflector;

typedef struct reflector_set {
    reflector r[MIRROR_MAX_REFLECTORS];
    uint32_t count;
    double skip; /* the knob reflection_skip */
} reflector_set;

static bool mirror_like(const prw_material *m, double max_roughness)
{
    return m->kind == 0 && m->roughness <= fmax(max_roughness, MIRROR_MAX_ROUGHNESS) && m->metal_rough_tex < 0 && m->normal_tex < 0 &&
           m->alpha_mode == PRW_ALPHA_OPAQUE && (m->metallic > 0 || m->specular > 0);
}

/* The reflector of material mi, if its drawn triangles are coplanar. */
static bool reflector_of(const prw_scene *s, int mi, reflector *out)
{
    memset(out, 0, sizeof *out);
    out->material = mi;
    bool have_plane = false;
    uint32_t tri = 0;
    prw_dvec3 lo = prw_v3(DBL_MAX, DBL_MAX, DBL_MAX), hi = prw_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    /* two sweeps: the plane from the largest triangle, then every vertex against it */
    double best = 0;
    for (int sweep = 0; sweep < 2; sweep++)
        for (uint32_t ni = 0; ni < s->node_count; ni++) {
            const prw_node *nd = &s->nodes[ni];
            if (nd->mesh_group < 0) continue;
            const prw_mesh_group *g = &s->groups[nd->mesh_group];
            bool flip = prw_draw_mirrors(nd->world);
            for (uint32_t k = g->first; k < g->first + g->count; k++) {
                const prw_mesh *me = &s->meshes[k];
                if (me->material != mi) continue;
                for (uint32_t t = 0; t + 2 < me->index_count; t += 3) {
                    prw_dvec3 p[3];
                    for (int j = 0; j < 3; j++) {
                        const float *q = &me->positions[3 * me->indices[t + j]];
                        p[j] = prw_dm4_point(nd->world, prw_v3(q[0], q[1], q[2]));
                    }
                    if (sweep == 0) {
                        prw_dvec3 c = prw_v3_cross(prw_v3_sub(p[1], p[0]), prw_v3_sub(p[2], p[0]));
                        double a = prw_v3_len(c);
                        if (a > best) {
                            best = a;
                            out->n = prw_v3_scale(c, (flip ? -1.0 : 1.0) / a);
                            out->d = prw_v3_dot(out->n, p[0]);
                            have_plane = true;
                        }
                        for (int j = 0; j < 3; j++) lo = prw_v3_min(lo, p[j]), hi = prw_v3_max(hi, p[j]);
                        tri++;
                    } else {
                        double tol = MIRROR_PLANARITY * fmax(prw_v3_len(prw_v3_sub(hi, lo)), 1e-9);
                        for (int j = 0; j < 3; j++) {
                            if (fabs(prw_v3_dot(out->n, p[j]) - out->d) > tol) return false;
                            if (out->corner_count < MIRROR_MAX_CORNERS) out->corners[out->corner_count] = p[j];
                            out->corner_count++;
                        }
                    }
                }
            }
        }
    if (!have_plane || tri == 0) return false;
    out->lo = lo, out->hi = hi;
    if (out->corner_count > MIRROR_MAX_CORNERS) { /* the world box's corners: conservative */
        out->corner_count = 8;
        for (int c = 0; c < 8; c++)
            out->corners[c] = prw_v3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    }
    out->two_sided = s->materials[mi].double_sided;
    out->slot = prw_scene_gpu_slot(s, mi);
    if (s->materials[mi].roughness > MIRROR_MAX_ROUGHNESS)
        for (uint32_t i = 0; i < MIRROR_DFG_COUNT; i++) {
            double A, B;
            prw_env_dfg((i + 0.5) / MIRROR_DFG_COUNT, s->materials[mi].roughness, &A, &B);
            out->dfg[i][0] = (float)A, out->dfg[i][1] = (float)B;
        }
    return true;
}

static double luma(const float *c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

/* lit: the base pass draws light maps (the skip rule's estimate needs the reflector's indirect light) */
static void reflectors_find(const prw_scene *s, const prw_quality *q, bool lit, reflector_set *set)
{
    set->count = 0;
    set->skip = lit ? q->reflection_skip : 0;
    for (uint32_t mi = 0; mi < s->material_count && set->count < MIRROR_MAX_REFLECTORS; mi++)
        if (mirror_like(&s->materials[mi], q->glossy_max_roughness) && reflector_of(s, (int)mi, &set->r[set->count])) {
            reflector *r = &set->r[set->count++];
            const prw_material *m = &s->materials[mi];
            r->rho_d = (1.0 - m->metallic) * luma(m->base_color);
            r->rho_seen = 0;
            for (uint32_t k = 0; k < s->material_count; k++) /* a plane never reflects itself */
                if (k != mi) r->rho_seen = fmax(r->rho_seen, luma(s->materials[k].base_color));
        }
}

/* The skip rule (Meseth §11.3; knob reflection_skip): an estimate, from the materials and the view alone,
 * of the reflection's share of the reflector's own radiance at its most grazing visible point.  Assumes
 * what it reflects is lit like itself (no lighting or GPU read-back is used): the reflection is then
 * F x rho_seen x E / pi against (1 - F) x rho_d x E / pi of its diffuse lobe, F its specular
 * reflectance at the smallest n.v among the footprint's candidate points (the reflector's corners in the
 * frustum and the plane's hits along the view's border inside its bounds: the farthest visible point,
 * where F is largest, is one of them), rho_seen the brightest other material's albedo.  A metal (no
 * diffuse lobe) is never skipped, and nothing is skipped without light maps (the reflector's own radiance
 * then lacks its indirect light: in its shadowed parts the reflection measured up to ~1000 x the rest).
 * Not conservative where the reflected scene is lit more brightly than the reflector (a shaded floor
 * reflecting a sunlit wall). */
static double reflection_share(const reflector *r, const prw_scene *s, const prw_view *v)
{
    const prw_material *m = &s->materials[r->material];
    if (r->rho_d <= 0) return INFINITY;
    double mu = 1.0;
    const double *vm = v->view.m; /* camera axes: rows of the view matrix */
    prw_dvec3 ax = prw_v3(vm[0], vm[4], vm[8]), ay = prw_v3(vm[1], vm[5], vm[9]), az = prw_v3(vm[2], vm[6], vm[10]);
    double pad = 1e-6 * fmax(prw_v3_len(prw_v3_sub(r->hi, r->lo)), 1.0);
    bool any = false;
    for (uint32_t k = 0; k < r->corner_count; k++) { /* corners in front of the eye, inside the frustum */
        prw_dvec3 d = prw_v3_sub(r->corners[k], v->eye);
        double z = -prw_v3_dot(d, az);
        if (z <= 0) continue;
        double tx = prw_v3_dot(d, ax) / z, ty = prw_v3_dot(d, ay) / z;
        if (tx < v->tan_left || tx > v->tan_right || ty < v->tan_bottom || ty > v->tan_top) continue;
        double l = prw_v3_len(d);
        if (l > 0) mu = fmin(mu, fabs(prw_v3_dot(r->n, d)) / l), any = true;
    }
    enum { STEPS = 32 }; /* the view's border, 4 x STEPS rays */
    for (int e = 0; e < 4; e++)
        for (int i = 0; i <= STEPS; i++) {
            double t = (double)i / STEPS;
            double tx = e < 2 ? v->tan_left + (v->tan_right - v->tan_left) * t : e == 2 ? v->tan_left : v->tan_right;
            double ty = e >= 2 ? v->tan_bottom + (v->tan_top - v->tan_bottom) * t : e == 0 ? v->tan_bottom : v->tan_top;
            prw_dvec3 d = prw_v3_add(prw_v3_add(prw_v3_scale(ax, tx), prw_v3_scale(ay, ty)), prw_v3_scale(az, -1.0));
            double dn = prw_v3_dot(r->n, d);
            if (fabs(dn) < 1e-12) continue;
            double h = (r->d - prw_v3_dot(r->n, v->eye)) / dn;
            if (h <= 0) continue;
            prw_dvec3 p = prw_v3_add(v->eye, prw_v3_scale(d, h));
            if (p.x < r->lo.x - pad || p.y < r->lo.y - pad || p.z < r->lo.z - pad || p.x > r->hi.x + pad ||
                p.y > r->hi.y + pad || p.z > r->hi.z + pad)
                continue;
            mu = fmin(mu, fabs(dn) / prw_v3_len(d)), any = true;
        }
    if (!any) return INFINITY; /* no candidate point: never skipped */
    float f[3];
    for (int c = 0; c < 3; c++)
        f[c] = m->metallic * prw_F_schlick(m->base_color[c], (float)mu) +
               (1.0f - m->metallic) * m->specular * prw_F_dielectric((float)mu);
    double F = fmin(luma(f), 1.0);
    return F >= 1.0 ? INFINITY : F * r->rho_seen / ((1.0 - F) * r->rho_d);
}

/* The rectangle [b0, b2) x [b1, b3) in view pixels (y down, as the base pass draws) bounding the
 * projection of the reflector's corners' convex hull (its part in front of the eye), clipped to the view.
 * false with why when no pixel can show the reflector's front. */
static bool reflector_bounds(const reflector *r, const prw_view *v, double b[4], const char **why)
{
    double s = prw_v3_dot(r->n, v->eye) - r->d;
    double extent = 0;
    for (uint32_t k = 1; k < r->corner_count; k++)
        extent = fmax(extent, prw_v3_len(prw_v3_sub(r->corners[k], r->corners[0])));
    if (fabs(s) <= 1e-9 * fmax(extent, 1.0)) return (*why = "eye in the mirror's plane"), false;
    if (s < 0 && !r->two_sided) return (*why = "mirror seen from its back"), false;
    prw_dmat4 vp = prw_dm4_mul(prw_view_proj(v), v->view); /* absolute world -> clip */
    double x0 = DBL_MAX, y0 = DBL_MAX, x1 = -DBL_MAX, y1 = -DBL_MAX;
    double c[MIRROR_MAX_CORNERS][3]; /* clip x, y, w */
    const double wmin = v->znear * 1e-3;
    uint32_t behind = 0;
    for (uint32_t k = 0; k < r->corner_count; k++) {
        prw_dvec3 p = r->corners[k];
        const double *m = vp.m;
        c[k][0] = m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12];
        c[k][1] = m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13];
        c[k][2] = m[3] * p.x + m[7] * p.y + m[11] * p.z + m[15];
        if (c[k][2] <= wmin) {
            behind++;
            continue;
        }
        double px = (c[k][0] / c[k][2] * 0.5 + 0.5) * v->width, py = (c[k][1] / c[k][2] * 0.5 + 0.5) * v->height;
        x0 = fmin(x0, px), x1 = fmax(x1, px), y0 = fmin(y0, py), y1 = fmax(y1, py);
    }
    if (behind == r->corner_count) return (*why = "mirror behind the eye"), false;
    /* it crosses the eye's plane: the part of the corners' convex hull in front of w = wmin is the hull of
     * the corners there and of the points where the segments between a corner in front and one behind
     * cross it (projected, far out in their direction; clipped to the view below) */
    for (uint32_t a = 0; behind && a < r->corner_count; a++)
        for (uint32_t k = 0; c[a][2] > wmin && k < r->corner_count; k++) {
            if (c[k][2] > wmin) continue;
            double t = (c[a][2] - wmin) / (c[a][2] - c[k][2]);
            double cx = c[a][0] + t * (c[k][0] - c[a][0]), cy = c[a][1] + t * (c[k][1] - c[a][1]);
            double px = (cx / wmin * 0.5 + 0.5) * v->width, py = (cy / wmin * 0.5 + 0.5) * v->height;
            x0 = fmin(x0, px), x1 = fmax(x1, px), y0 = fmin(y0, py), y1 = fmax(y1, py);
        }
    b[0] = fmax(x0, 0), b[1] = fmax(y0, 0), b[2] = fmin(x1, v->width), b[3] = fmin(y1, v->height);
    return true;
}

/* The pixels of view v the reflector may cover (bounding rectangle of its projected vertices, clipped to
 * the view); 0 when none (behind the eye, outside, edge-on, its back seen, or between pixel centres). */
static double reflector_pixels(const reflector *r, const prw_view *v, const char **why)
{
    double b[4];
    if (!reflector_bounds(r, v, b, why)) return 0;
    /* pixel centres i + 0.5 inside [x0, x1) */
    double nx = ceil(b[2] - 0.5) - ceil(b[0] - 0.5), ny = ceil(b[3] - 0.5) - ceil(b[1] - 0.5);
    if (nx <= 0 || ny <= 0) return (*why = "mirror off-screen or covering no pixel"), 0;
    return nx * ny;
}

/* The reflector's bounds grown by pad view pixels, in the pixels of a w x h image covering the view: the
 * scissor of the draws that only its pixels (and the glossy kernel around them) read. */
static VkRect2D reflector_rect(const reflector *r, const prw_view *v, double pad, uint32_t w, uint32_t h)
{
    double b[4];
    const char *why;
    VkRect2D full = {{0, 0}, {w, h}};
    if (!reflector_bounds(r, v, b, &why)) return full;
    double sx = (double)w / v->width, sy = (double)h / v->height;
    double x0 = floor((b[0] - pad) * sx) - 1, y0 = floor((b[1] - pad) * sy) - 1;
    double x1 = ceil((b[2] + pad) * sx) + 1, y1 = ceil((b[3] + pad) * sy) + 1;
    x0 = fmax(x0, 0), y0 = fmax(y0, 0), x1 = fmin(x1, w), y1 = fmin(y1, h);
    if (x1 <= x0 || y1 <= y0) return full;
    return (VkRect2D){{(int32_t)x0, (int32_t)y0}, {(uint32_t)(x1 - x0), (uint32_t)(y1 - y0)}};
}

/* The reflectors rendered for view v: up to max of those covering pixels and not skipped by the skip rule,
 * most pixels first (ties: the first found), their indices into set in pick[]; returns how many (0: why
 * set). */
static uint32_t reflectors_pick(const reflector_set *set, const prw_scene *s, const prw_view *v, uint32_t max,
                                int *pick, const char **why)
{
    double px[MIRROR_MAX_REFLECTORS];
    uint32_t n = 0;
    *why = "no reflector";
    if (max > MIRROR_MAX_DRAWN) max = MIRROR_MAX_DRAWN;
    for (uint32_t k = 0; k < set->count; k++) {
        double p = reflector_pixels(&set->r[k], v, why);
        if (p <= 0) continue;
        if (set->skip > 0 && reflection_share(&set->r[k], s, v) < set->skip) {
            *why = "reflection below reflection_skip of the surface (estimate)";
            continue;
        }
        uint32_t at = n < max ? n : max; /* insertion into the sorted list, dropping beyond max */
        while (at > 0 && px[at - 1] < p) at--;
        if (at >= max) continue;
        uint32_t end = n < max ? n : max - 1;
        for (uint32_t j = end; j > at; j--) px[j] = px[j - 1], pick[j] = pick[j - 1];
        px[at] = p, pick[at] = (int)k;
        if (n < max) n++;
    }
    return n;
}

static uint32_t max_drawn(const prw_render_env *env)
{
    uint32_t n = env->desc->quality.max_reflectors;
    return n < 1 ? 1 : n > MIRROR_MAX_DRAWN ? MIRROR_MAX_DRAWN : n;
}

/* graph image names of mirror image k */
static const char *const HDR_NAMES[MIRROR_MAX_DRAWN] = {"mirror_hdr", "mirror_hdr1", "mirror_hdr2", "mirror_hdr3"};
static const char *const DEPTH_NAMES[MIRROR_MAX_DRAWN] = {"mirror_depth", "mirror_depth1", "mirror_depth2",
                                                          "mirror_depth3"};
/* the glossy convolution of mirror image k (pass mirror_glossy; declared when a reflector is glossy) */
static const char *const GLOSSY_NAMES[MIRROR_MAX_DRAWN] = {"mirror_glossy", "mirror_glossy1", "mirror_glossy2",
                                                           "mirror_glossy3"};

static bool is_glossy(const prw_scene *s, const reflector *r)
{
    return s->materials[r->material].roughness > MIRROR_MAX_ROUGHNESS;
}

/* Whether the scene has a glossy reflector (then the graph holds the mirror_glossy images and pass). */
static bool any_glossy(const prw_render_env *env)
{
    reflector_set *set = prw_calloc(1, sizeof *set);
    reflectors_find(env->scene, &env->desc->quality, false, set);
    bool any = false;
    for (uint32_t k = 0; k < set->count; k++) any = any || is_glossy(env->scene, &set->r[k]);
    free(set);
    return any;
}

/* The mirror images' declaration (knob mirror_scale: a smaller image, upsampled by mirror_add). */
static prw_image_decl mirror_decl(const prw_render_env *env)
{
    prw_image_decl hdr = {.format = prw_pipes_radiance_format(env), .size = PRW_SIZE_INTERNAL};
    double scale = env->desc->quality.mirror_scale;
    if (scale > 0 && scale < 1) {
        hdr.size = PRW_SIZE_FIXED;
        hdr.width = (uint32_t)fmax(1.0, round(env->desc->width * scale));
        hdr.height = (uint32_t)fmax(1.0, round(env->desc->height * scale));
    }
    return hdr;
}

/* The glossy reflectors' part of a mirror image of w x h (knob glossy_scale): its top-left sw x sh, the
 * mirror_glossy images' size. */
static void glossy_size(const prw_render_env *env, uint32_t w, uint32_t h, uint32_t *sw, uint32_t *sh)
{
    double g = env->desc->quality.glossy_scale;
    if (!(g > 0 && g < 1)) g = 1;
    *sw = (uint32_t)fmin(w, fmax(1.0, round(w * g)));
    *sh = (uint32_t)fmin(h, fmax(1.0, round(h * g)));
}

/* The mirror images the graph holds (0: the passes are not in the graph, skip reason given). */
static uint32_t in_graph(prw_setup *s)
{
    const prw_render_env *env = prw_setup_env(s);
    reflector_set *set = prw_calloc(1, sizeof *set);
    reflectors_find(env->scene, &env->desc->quality, false, set); /* only the count */
    uint32_t count = set->count;
    free(set);
    if (count == 0) return prw_setup_skip(s, "no planar mirror in the scene"), 0;
    if (env->desc->quality.mirror_recursion == 0) return prw_setup_skip(s, "mirror_recursion=0"), 0;
    if (env->desc->quality.supersample > 1) return prw_setup_skip(s, "not with supersampling yet"), 0;
    /* one term drawn (prw render --term): the reflections are the specular term, k >= 2 paths through the
     * reflector's specular lobe, in neither the direct nor the indirect-diffuse one */
    if (env->desc->terms != 0 && env->desc->terms != PRW_TERM_ALL)
        return prw_setup_skip(s, "one term drawn (--term): reflections are the specular term"), 0;
    return count < max_drawn(env) ? count : max_drawn(env);
}

/* ---- mirror: the reflected view ---- */

/* View v reflected in r's plane n.x = d: x' = x - 2 (n.x - d) n, in double. */
static prw_view mirrored_view(const reflector *r, const prw_view *v)
{
    prw_dmat4 R = prw_dm4_identity();
    double nn[3] = {r->n.x, r->n.y, r->n.z};
    for (int col = 0; col < 3; col++)
        for (int row = 0; row < 3; row++) R.m[col * 4 + row] -= 2 * nn[row] * nn[col];
    for (int row = 0; row < 3; row++) R.m[12 + row] = 2 * r->d * nn[row];
    prw_view mv = *v;
    mv.view = prw_dm4_mul(v->view, R);
    double s = prw_v3_dot(r->n, v->eye) - r->d;
    mv.eye = prw_v3_sub(v->eye, prw_v3_scale(r->n, 2 * s));
    return mv;
}

typedef struct mirror_state {
    reflector_set set;
    uint32_t images; /* mirror images in the graph */
    prw_pipe_recipe recipe; /* the base recipe at one sample */
    prw_buffer globals[PRW_MAX_VIEWS][MIRROR_MAX_DRAWN];
    VkDescriptorSet sets[PRW_MAX_VIEWS][MIRROR_MAX_DRAWN];
} mirror_state;

static void mirror_setup(prw_setup *s)
{
    uint32_t n = in_graph(s);
    if (!n) return;
    const prw_render_env *env = prw_setup_env(s);
    prw_image_decl hdr = mirror_decl(env);
    prw_image_decl depth = hdr;
    depth.format = PRW_DEPTH_FORMAT;
    for (uint32_t k = 0; k < n; k++) {
        prw_setup_image(s, HDR_NAMES[k], &hdr);
        prw_setup_image(s, DEPTH_NAMES[k], &depth);
        prw_setup_use(s, HDR_NAMES[k], PRW_USE_COLOR);
        prw_setup_use(s, DEPTH_NAMES[k], PRW_USE_DEPTH);
    }
    prw_setup_use(s, "shadow_map", PRW_USE_SAMPLED);
}

static bool mirror_describe(const prw_pipe_recipe *r, const prw_render_env *env, const prw_pipe_key *k,
                            prw_graphics_desc *d, prw_error *e)
{
    if (!prw_pipes_describe_base(env, k, r->layout, d, e)) return false;
    d->samples = VK_SAMPLE_COUNT_1_BIT;
    return true;
}

static bool mirror_create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    mirror_state *m = prw_calloc(1, sizeof *m);
    *state = m;
    reflectors_find(env->scene, &env->desc->quality, env->lm->active, &m->set);
    m->images = m->set.count < max_drawn(env) ? m->set.count : max_drawn(env);
    /* lightmapped: the reflected surfaces carry their baked indirect diffuse as in the base pass */
    m->recipe = (prw_pipe_recipe){.name = "mirror", .layout = env->pipes->base_layout, .describe = mirror_describe,
                                  .lightmapped = true};
    prw_gpu_image *shadow = prw_graph_image(in->graph, "shadow_map", 0);
    for (uint32_t v = 0; v < env->desc->max_views; v++)
        for (uint32_t k = 0; k < m->images; k++) { /* one globals block per mirror image: each is its own view */
            VkDescriptorSet ds;
            if (!prw_buffer_create(env->gpu, sizeof(prw_gpu_globals), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                   PRW_MEM_UPLOAD, &m->globals[v][k], e) ||
                !prw_desc_alloc(env->gpu, env->pool, env->pipes->globals_layout, &m->sets[v][k], e))
                return false;
            ds = m->sets[v][k];
            prw_desc_write_buffer(env->gpu, ds, 0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &m->globals[v][k], 0,
                                  sizeof(prw_gpu_globals));
            prw_pipes_write_globals(env->pipes, ds);
            prw_desc_write_image(env->gpu, ds, 1, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow->view,
                                 prw_gpu_sampler(env->gpu, PRW_SAMPLER_SHADOW),
                                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            prw_desc_write_image(env->gpu, ds, 2, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, shadow->view,
                                 prw_gpu_sampler(env->gpu, PRW_SAMPLER_SHADOW_DEPTH),
                                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        }
    return true;
}

static void mirror_destroy(const prw_pass_init *in, void *state)
{
    mirror_state *m = state;
    if (!m) return;
    prw_pipes_forget(in->env->pipes, &m->recipe);
    for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++)
        for (uint32_t k = 0; k < MIRROR_MAX_DRAWN; k++) prw_buffer_destroy(in->env->gpu, &m->globals[v][k]);
    free(m);
}

static bool mirror_needed(const prw_pass_ctx *c, const char **why)
{
    const mirror_state *m = c->state;
    if (c->frame->mode != PRW_FRAME_LOOP) return (*why = "multiview and reprojected stereo frames not yet"), false;
    int pick[MIRROR_MAX_DRAWN];
    return reflectors_pick(&m->set, c->env->scene, &c->frame->views[c->view], m->images, pick, why) > 0;
}

/* Mirror image k of view c->view: the scene reflected in r. */
static bool mirror_record_one(prw_pass_ctx *c, mirror_state *m, const reflector *r, uint32_t k, prw_error *e)
{
    const prw_render_env *env = c->env;
    const prw_view *v = &c->frame->views[c->view];
    prw_view mv = mirrored_view(r, v);
    double s = prw_v3_dot(r->n, v->eye) - r->d;
    prw_gpu_image *hdr = prw_pass_image(c, HDR_NAMES[k]), *depth = prw_pass_image(c, DEPTH_NAMES[k]);
    /* a glossy reflector's image fills the top-left part the knob glossy_scale gives (mirror_glossy reads it) */
    bool glossy = is_glossy(env->scene, r);
    uint32_t w = hdr->width, h = hdr->height;
    if (glossy) glossy_size(env, hdr->width, hdr->height, &w, &h);
    mv.width = w, mv.height = h;
    prw_gpu_globals g;
    prw_view_globals_fill(env->scene, env->shadows, env->desc->quality.shadow_size, &mv, mv.eye, &g);
    g.params[2] = 1.0f; /* no emission in the mirror image */
    memcpy(m->globals[c->view][k].mapped, &g, sizeof g);
    /* keep what lies on the real eye's side, MIRROR_CLIP_OFFSET in front of the mirror (camera-relative to
     * the reflected eye, whose distance to the plane is -s) */
    double sign = s >= 0 ? 1.0 : -1.0;
    prw_draw_view dv = {.origin = mv.eye, .eye = mv.eye, .globals = m->sets[c->view][k], .mirrored = true,
                        .clip = true};
    dv.clip_plane[0] = (float)(sign * r->n.x), dv.clip_plane[1] = (float)(sign * r->n.y);
    dv.clip_plane[2] = (float)(sign * r->n.z);
    dv.clip_plane[3] = (float)(sign * (prw_v3_dot(r->n, mv.eye) - r->d) - MIRROR_CLIP_OFFSET);
    VkRenderingAttachmentInfo ca = prw_pipes_color_attachment(hdr, NULL, VK_RESOLVE_MODE_NONE, 0);
    VkRenderingAttachmentInfo da = prw_pipes_depth_attachment(depth);
    /* only the part of the mirror image that mirror_add reads: the reflector's pixels, and for a glossy one
     * its kernel's reach (mirror_glossy.frag caps the radius at a quarter of the view's height) around the
     * texels mirror_glossy computes (one texel beyond the reflector's pixels) */
    double texel = (double)v->width / w;
    VkRect2D area = reflector_rect(r, v, glossy ? 0.25 * v->height + 2 + 2 * texel : 2, w, h);
    VkRenderingInfo rinfo = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                             .renderArea = area,
                             .layerCount = 1,
                             .colorAttachmentCount = 1,
                             .pColorAttachments = &ca,
                             .pDepthAttachment = &da};
    prw_draw_ctx dc = {.cmd = c->cmd, .kind = PRW_DRAW_COLOR, .view = &dv, .pipes = env->pipes, .recipe = &m->recipe,
                       .sg = env->sg, .layout = env->pipes->base_layout};
    prw_pass_begin_rendering(c, &rinfo);
    prw_cmd_viewport(c->cmd, w, h);
    vkCmdSetScissor(c->cmd, 0, 1, &area);
    vkCmdPushConstants(c->cmd, env->pipes->base_layout, VK_SHADER_STAGE_ALL, PRW_CLIP_PUSH_OFFSET, 16, dv.clip_plane);
    prw_drawables_record(env->drawables, env, &dc);
    if (prw_drawables_have(env->drawables, env, PRW_DRAW_BLEND)) { /* blended surfaces, sorted from the reflected eye */
        dc.kind = PRW_DRAW_BLEND;
        prw_drawables_record(env->drawables, env, &dc);
    }
    prw_pass_end_rendering(c);
    return !dc.failed || prw_fail(e, "%s", dc.err.msg);
}

static bool mirror_record(prw_pass_ctx *c, prw_error *e)
{
    mirror_state *m = c->state;
    const char *why;
    int pick[MIRROR_MAX_DRAWN];
    uint32_t n = reflectors_pick(&m->set, c->env->scene, &c->frame->views[c->view], m->images, pick, &why);
    if (n == 0) return prw_fail(e, "mirror: %s", why);
    for (uint32_t k = 0; k < n; k++)
        if (!mirror_record_one(c, m, &m->set.r[pick[k]], k, e)) return false;
    return true;
}

const prw_pass prw_pass_mirror = {
    .name = "mirror",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_VIEW,
    .setup = mirror_setup,
    .create = mirror_create,
    .destroy = mirror_destroy,
    .needed = mirror_needed,
    .record = mirror_record,
};

/* ---- mirror_glossy: the glossy reflectors' convolution, on the mirror image's grid ---- */

typedef struct glossy_push {
    float inv_view_proj[16];
    float plane[4];  /* xyz: the reflector's unit normal, w: its material id (slot + 1) */
    float glossy[4]; /* alpha, |eye - plane| in m, f_px = H / (2 tan(fov_y / 2)) in view pixels, taps */
    float fwd[4];    /* xyz: the view axis (unit, world orientation), w: near plane distance */
    float size[4];   /* the view's width, height; the mirror image's */
} glossy_push;

typedef struct glossy_state {
    reflector_set set;
    uint32_t images; /* mirror images in the graph */
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipe;
    VkDescriptorSet sets[PRW_MAX_VIEWS][MIRROR_MAX_DRAWN]; /* mirror image k's */
} glossy_state;

static void glossy_setup(prw_setup *s)
{
    uint32_t n = in_graph(s);
    if (!n) return;
    const prw_render_env *env = prw_setup_env(s);
    if (!any_glossy(env)) {
        prw_setup_skip(s, "no glossy planar reflector in the scene");
        return;
    }
    prw_image_decl d = mirror_decl(env);
    uint32_t w = d.width, h = d.height;
    if (d.size == PRW_SIZE_INTERNAL) w = env->desc->width, h = env->desc->height;
    d.size = PRW_SIZE_FIXED;
    glossy_size(env, w, h, &d.width, &d.height);
    d.clear_at_create = true; /* mirror_add binds it also in frames that reflect only sharp mirrors */
    for (uint32_t k = 0; k < n; k++) {
        prw_setup_image(s, GLOSSY_NAMES[k], &d);
        prw_setup_use(s, GLOSSY_NAMES[k], PRW_USE_COLOR);
        prw_setup_use(s, HDR_NAMES[k], PRW_USE_SAMPLED);
        prw_setup_use(s, DEPTH_NAMES[k], PRW_USE_SAMPLED);
    }
    prw_setup_use(s, "gbuf_id", PRW_USE_SAMPLED);
}

static bool glossy_create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    glossy_state *gs = prw_calloc(1, sizeof *gs);
    *state = gs;
    reflectors_find(env->scene, &env->desc->quality, env->lm->active, &gs->set);
    gs->images = gs->set.count < max_drawn(env) ? gs->set.count : max_drawn(env);
    VkDescriptorSetLayoutBinding b[3] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    if (!prw_desc_layout_create(env->gpu, b, 3, &gs->set_layout, e) ||
        !prw_pipeline_layout_create(env->gpu, &gs->set_layout, 1, sizeof(glossy_push), &gs->layout, e))
        return false;
    prw_graphics_desc d = {
        .vs = prw_shader_tonemap_fs_vert(),
        .fs = prw_shader_mirror_glossy_frag(),
        .layout = gs->layout,
        .color_formats = {prw_pipes_radiance_format(env)},
        .color_count = 1,
    };
    if (!prw_pipeline_graphics(env->gpu, &d, &gs->pipe, e)) return false;
    for (uint32_t v = 0; v < env->desc->max_views; v++)
        for (uint32_t i = 0; i < gs->images; i++) {
            if (!prw_desc_alloc(env->gpu, env->pool, gs->set_layout, &gs->sets[v][i], e)) return false;
            const char *names[3] = {HDR_NAMES[i], DEPTH_NAMES[i], "gbuf_id"};
            for (uint32_t k = 0; k < 3; k++) {
                prw_gpu_image *img = prw_graph_image(in->graph, names[k], v);
                if (!img) return prw_fail(e, "mirror_glossy: graph image %s missing", names[k]);
                prw_desc_write_image(env->gpu, gs->sets[v][i], k, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                     img->view,
                                     prw_gpu_sampler(env->gpu, k == 0 ? PRW_SAMPLER_LINEAR_CLAMP : PRW_SAMPLER_NEAREST_CLAMP),
                                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            }
        }
    return true;
}

static void glossy_destroy(const prw_pass_init *in, void *state)
{
    glossy_state *gs = state;
    if (!gs) return;
    VkDevice dev = prw_gpu_device(in->env->gpu);
    if (gs->pipe) prw_pipeline_release(in->env->gpu, gs->pipe);
    if (gs->layout) vkDestroyPipelineLayout(dev, gs->layout, NULL);
    if (gs->set_layout) vkDestroyDescriptorSetLayout(dev, gs->set_layout, NULL);
    free(gs);
}

static bool glossy_needed(const prw_pass_ctx *c, const char **why)
{
    const glossy_state *gs = c->state;
    if (c->frame->mode != PRW_FRAME_LOOP) return (*why = "multiview and reprojected stereo frames not yet"), false;
    int pick[MIRROR_MAX_DRAWN];
    uint32_t n = reflectors_pick(&gs->set, c->env->scene, &c->frame->views[c->view], gs->images, pick, why);
    for (uint32_t k = 0; k < n; k++)
        if (is_glossy(c->env->scene, &gs->set.r[pick[k]])) return true;
    if (n) *why = "no glossy reflector reflected in the view";
    return false;
}

static bool glossy_record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    glossy_state *gs = c->state;
    const prw_view *v = &c->frame->views[c->view];
    const char *why;
    int pick[MIRROR_MAX_DRAWN];
    uint32_t n = reflectors_pick(&gs->set, env->scene, v, gs->images, pick, &why);
    if (n == 0) return prw_fail(e, "mirror_glossy: %s", why);
    prw_mat4 vp = prw_view_globals_view_proj(v, v->eye); /* camera-relative, as the base pass draws */
    prw_dmat4 vpd, inv;
    for (int k = 0; k < 16; k++) vpd.m[k] = vp.m[k];
    if (!prw_dm4_inverse(vpd, &inv)) return prw_fail(e, "mirror_glossy: singular view-projection");
    prw_dvec3 f = prw_v3(-v->view.m[2], -v->view.m[6], -v->view.m[10]); /* -(third row): the view axis */
    double fl = prw_v3_len(f);
    for (uint32_t k = 0; k < n; k++) {
        const reflector *r = &gs->set.r[pick[k]];
        if (!is_glossy(env->scene, r)) continue;
        prw_gpu_image *out = prw_pass_image(c, GLOSSY_NAMES[k]);
        glossy_push pc;
        for (int i = 0; i < 16; i++) pc.inv_view_proj[i] = (float)inv.m[i];
        pc.plane[0] = (float)r->n.x, pc.plane[1] = (float)r->n.y, pc.plane[2] = (float)r->n.z;
        pc.plane[3] = (float)(r->slot + 1);
        pc.glossy[0] = prw_alpha_from_roughness(env->scene->materials[r->material].roughness);
        pc.glossy[1] = (float)fabs(prw_v3_dot(r->n, v->eye) - r->d);
        pc.glossy[2] = (float)(v->height / (v->tan_top - v->tan_bottom)); /* view pixels per unit tangent */
        pc.glossy[3] = (float)env->desc->quality.kernel_taps;
        pc.fwd[0] = (float)(f.x / fl), pc.fwd[1] = (float)(f.y / fl), pc.fwd[2] = (float)(f.z / fl);
        pc.fwd[3] = (float)v->znear;
        pc.size[0] = (float)v->width, pc.size[1] = (float)v->height;
        pc.size[2] = (float)out->width, pc.size[3] = (float)out->height;
        VkRenderingAttachmentInfo ca = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = out->view,
            .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
        };
        /* the texels mirror_add reads: its reflector's pixels, one texel around */
        VkRect2D area = reflector_rect(r, v, 2, out->width, out->height);
        VkRenderingInfo rinfo = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                                 .renderArea = area,
                                 .layerCount = 1,
                                 .colorAttachmentCount = 1,
                                 .pColorAttachments = &ca};
        prw_pass_begin_rendering(c, &rinfo);
        prw_cmd_viewport(c->cmd, out->width, out->height);
        vkCmdSetScissor(c->cmd, 0, 1, &area);
        vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gs->pipe);
        vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, gs->layout, 0, 1, &gs->sets[c->view][k], 0,
                                NULL);
        vkCmdPushConstants(c->cmd, gs->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc, &pc);
        vkCmdDraw(c->cmd, 3, 1, 0, 0);
        prw_pass_end_rendering(c);
    }
    return true;
}

const prw_pass prw_pass_mirror_glossy = {
    .name = "mirror_glossy",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_VIEW,
    .setup = glossy_setup,
    .create = glossy_create,
    .destroy = glossy_destroy,
    .needed = glossy_needed,
    .record = glossy_record,
};

/* ---- mirror_add: Fresnel x the mirror image, into the radiance ---- */

typedef struct mirror_push {
    float inv_view_proj[16];
    float base[4]; /* rgb base colour, a metallic */
    float misc[4]; /* specular, id, width, height */
    float glossy[4]; /* x: alpha (0: sharp mirror) */
} mirror_push;

typedef struct mirror_dfg_ubo {
    float dfg[MIRROR_DFG_COUNT][4];
} mirror_dfg_ubo;

typedef struct add_state {
    reflector_set set;
    uint32_t images; /* mirror images in the graph */
    bool glossy;     /* the graph holds the mirror_glossy images */
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipe;
    VkDescriptorSet sets[PRW_MAX_VIEWS][MIRROR_MAX_DRAWN]; /* mirror image k's */
    prw_buffer dfg[PRW_MAX_VIEWS][MIRROR_MAX_DRAWN];
} add_state;

static const char *out_name(const prw_render_env *env) { return env->desc->quality.supersample > 1 ? "hdr_ss" : "hdr"; }

static void add_setup(prw_setup *s)
{
    uint32_t n = in_graph(s);
    if (!n) return;
    bool glossy = any_glossy(prw_setup_env(s));
    for (uint32_t k = 0; k < n; k++) {
        prw_setup_use(s, HDR_NAMES[k], PRW_USE_SAMPLED);
        if (glossy) prw_setup_use(s, GLOSSY_NAMES[k], PRW_USE_SAMPLED);
    }
    prw_setup_use(s, "gbuf_normal", PRW_USE_SAMPLED);
    prw_setup_use(s, "gbuf_id", PRW_USE_SAMPLED);
    prw_setup_use(s, out_name(prw_setup_env(s)), PRW_USE_COLOR_ADD);
}

static bool add_create(const prw_pass_init *in, void **state, prw_error *e)
{
    const prw_render_env *env = in->env;
    add_state *a = prw_calloc(1, sizeof *a);
    *state = a;
    reflectors_find(env->scene, &env->desc->quality, env->lm->active, &a->set);
    a->images = a->set.count < max_drawn(env) ? a->set.count : max_drawn(env);
    a->glossy = any_glossy(env);
    VkDescriptorSetLayoutBinding b[5] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {3, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
        {4, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, NULL},
    };
    if (!prw_desc_layout_create(env->gpu, b, 5, &a->set_layout, e) ||
        !prw_pipeline_layout_create(env->gpu, &a->set_layout, 1, sizeof(mirror_push), &a->layout, e))
        return false;
    prw_graphics_desc d = {
        .vs = prw_shader_tonemap_fs_vert(),
        .fs = prw_shader_mirror_add_frag(),
        .layout = a->layout,
        .color_formats = {prw_pipes_radiance_format(env)},
        .color_count = 1,
        .blend_additive = true,
    };
    if (!prw_pipeline_graphics(env->gpu, &d, &a->pipe, e)) return false;
    VkSampler smp = prw_gpu_sampler(env->gpu, PRW_SAMPLER_NEAREST_CLAMP);
    for (uint32_t v = 0; v < env->desc->max_views; v++)
        for (uint32_t i = 0; i < a->images; i++) {
            VkDescriptorSet ds;
            if (!prw_desc_alloc(env->gpu, env->pool, a->set_layout, &a->sets[v][i], e)) return false;
            ds = a->sets[v][i];
            /* binding 3, the convolved image, is not read without a glossy reflector: then the mirror image */
            const char *names[4] = {HDR_NAMES[i], "gbuf_normal", "gbuf_id", a->glossy ? GLOSSY_NAMES[i] : HDR_NAMES[i]};
            for (uint32_t k = 0; k < 4; k++) {
                prw_gpu_image *img = prw_graph_image(in->graph, names[k], v);
                if (!img) return prw_fail(e, "mirror_add: graph image %s missing", names[k]);
                prw_desc_write_image(env->gpu, ds, k, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, img->view,
                                     k == 0 || k == 3 ? prw_gpu_sampler(env->gpu, PRW_SAMPLER_LINEAR_CLAMP) : smp,
                                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
            }
            if (!prw_buffer_create(env->gpu, sizeof(mirror_dfg_ubo), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                   PRW_MEM_UPLOAD, &a->dfg[v][i], e))
                return false;
            prw_desc_write_buffer(env->gpu, ds, 4, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &a->dfg[v][i], 0,
                                  sizeof(mirror_dfg_ubo));
        }
    return true;
}

static void add_destroy(const prw_pass_init *in, void *state)
{
    add_state *a = state;
    if (!a) return;
    VkDevice dev = prw_gpu_device(in->env->gpu);
    if (a->pipe) prw_pipeline_release(in->env->gpu, a->pipe);
    if (a->layout) vkDestroyPipelineLayout(dev, a->layout, NULL);
    if (a->set_layout) vkDestroyDescriptorSetLayout(dev, a->set_layout, NULL);
    for (uint32_t v = 0; v < PRW_MAX_VIEWS; v++)
        for (uint32_t k = 0; k < MIRROR_MAX_DRAWN; k++) prw_buffer_destroy(in->env->gpu, &a->dfg[v][k]);
    free(a);
}

static bool add_needed(const prw_pass_ctx *c, const char **why)
{
    const add_state *a = c->state;
    if (c->frame->mode != PRW_FRAME_LOOP) return (*why = "multiview and reprojected stereo frames not yet"), false;
    int pick[MIRROR_MAX_DRAWN];
    return reflectors_pick(&a->set, c->env->scene, &c->frame->views[c->view], a->images, pick, why) > 0;
}

/* The push constants of reflector r in view v (its glossy split-sum table into dfg). */
static bool add_push(const prw_render_env *env, const reflector *r, const prw_view *v, const prw_gpu_image *out,
                     prw_buffer *dfg, mirror_push *out_pc, prw_error *e)
{
    const prw_material *mat = &env->scene->materials[r->material];
    mirror_push pc;
    prw_dmat4 inv;
    prw_mat4 vp = prw_view_globals_view_proj(v, v->eye); /* camera-relative, as the base pass draws */
    prw_dmat4 vpd;
    for (int k = 0; k < 16; k++) vpd.m[k] = vp.m[k];
    if (!prw_dm4_inverse(vpd, &inv)) return prw_fail(e, "mirror_add: singular view-projection");
    for (int k = 0; k < 16; k++) pc.inv_view_proj[k] = (float)inv.m[k];
    for (int k = 0; k < 3; k++) pc.base[k] = mat->base_color[k];
    pc.base[3] = mat->metallic;
    pc.misc[0] = mat->specular, pc.misc[1] = (float)(r->slot + 1), pc.misc[2] = (float)out->width;
    pc.misc[3] = (float)out->height;
    memset(pc.glossy, 0, sizeof pc.glossy);
    if (is_glossy(env->scene, r)) {
        pc.glossy[0] = prw_alpha_from_roughness(mat->roughness);
        memcpy(dfg->mapped, r->dfg, sizeof r->dfg);
    }
    *out_pc = pc;
    return true;
}

static bool add_record(prw_pass_ctx *c, prw_error *e)
{
    const prw_render_env *env = c->env;
    add_state *a = c->state;
    const prw_view *v = &c->frame->views[c->view];
    const char *why;
    int pick[MIRROR_MAX_DRAWN];
    uint32_t n = reflectors_pick(&a->set, env->scene, v, a->images, pick, &why);
    if (n == 0) return prw_fail(e, "mirror_add: %s", why);
    prw_gpu_image *out = prw_pass_image(c, out_name(env));
    mirror_push pc[MIRROR_MAX_DRAWN];
    for (uint32_t k = 0; k < n; k++)
        if (!add_push(env, &a->set.r[pick[k]], v, out, &a->dfg[c->view][k], &pc[k], e)) return false;
    VkRenderingAttachmentInfo ca = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = out->view,
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_LOAD,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
    };
    VkRenderingInfo rinfo = {.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                             .renderArea = {{0, 0}, {out->width, out->height}},
                             .layerCount = 1,
                             .colorAttachmentCount = 1,
                             .pColorAttachments = &ca};
    prw_pass_begin_rendering(c, &rinfo);
    prw_cmd_viewport(c->cmd, out->width, out->height);
    vkCmdBindPipeline(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, a->pipe);
    for (uint32_t k = 0; k < n; k++) { /* each only in its reflector's pixels: the sums do not overlap */
        VkRect2D area = reflector_rect(&a->set.r[pick[k]], v, 0, out->width, out->height);
        vkCmdSetScissor(c->cmd, 0, 1, &area);
        vkCmdBindDescriptorSets(c->cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, a->layout, 0, 1, &a->sets[c->view][k], 0,
                                NULL);
        vkCmdPushConstants(c->cmd, a->layout, VK_SHADER_STAGE_ALL, 0, sizeof pc[k], &pc[k]);
        vkCmdDraw(c->cmd, 3, 1, 0, 0);
    }
    prw_pass_end_rendering(c);
    return true;
}

const prw_pass prw_pass_mirror_add = {
    .name = "mirror_add",
    .flags = PRW_PASS_RADIANCE,
    .scope = PRW_SCOPE_VIEW,
    .setup = add_setup,
    .create = add_create,
    .destroy = add_destroy,
    .needed = add_needed,
    .record = add_record,
};
