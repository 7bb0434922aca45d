/* No seam or leak at light-map chart borders (issue 16, must-show 4): a box room written here as a
 * manifest (an inward box, its floor and back wall each covered by two coplanar quads that meet in
 * the middle — chart borders across a flat surface —, a box standing on the floor — contact edges —,
 * one point light), baked through the library (no cache), drawn by the base pass with only the
 * light maps' term (prw_render_desc.terms = PRW_TERM_INDIRECT_DIFFUSE, `prw render --term
 * indirect-diffuse`) at 160x90, 4x MSAA, validation layer on, against the reference's
 * indirect-diffuse-last term with seeds 1 (A) and 2 (B).  The references are rendered only at the
 * pixels the criteria below read (both pixels of each border pair, the contact pixels: some 5 % of
 * the image), bit-identical there to whole-image renders.
 *
 * Chart borders are found from the bake itself: per pixel, the pixel-centre ray is intersected with
 * the baked instances' triangles (brute force, world space); the hit triangle's chart is its class
 * under "shares a corner with the same world position AND the same light-map uv" (one chart's
 * triangles share their corners' uvs, two charts never do).  A border pair is two horizontally or
 * vertically adjacent pixels whose centres hit different charts, whose hit points lie within 8 pixel
 * footprints of each other (a shared edge in the world: flat seams, the room's corners, the box's
 * edges and contact; not silhouettes) and whose 3x3 sub-pixel rays hit only those two charts.
 * Per pair, on luminance:  d = (R_p - R_q) - (A_p - A_q)   (the raster's jump across the border
 * beyond the reference's), and the reference's own pair noise n = (B_p - B_q) - (A_p - A_q).  Per border
 * (pair of charts, at least MIN_PAIRS pairs): the seam is the mean of d (a systematic jump: noise and
 * the raster's MSAA coverage average out), its standard error se = sqrt(mean(n^2) / 2 / pairs) from
 * the reference's pair noise; the border passes when |mean d| <= SEAM_K se (4: eleven borders are
 * judged, and the light map's own noise, not in se, moves a border's mean jump by up to ~3 se between
 * bakes that differ only in their random numbers).
 * Leak: the pixels whose centre hits the floor within LEAK_BAND of the box's foot print (outside it)
 * or the box's sides within LEAK_BAND above the floor: mean(R - A) <= LEAK_K x the standard deviation
 * of that mean (from B - A), i.e. not brighter than the reference beyond its noise.
 *
 * Texel placement (noise-free, on the bake alone): on the floor quads' charts every texel whose centre
 * lies in a triangle must be hidden exactly when the world point of that centre lies under the box
 * (placement() below): a bake that gathers texels elsewhere than at the centres the renderer's uvs
 * assume (e.g. half a texel off) hides the wrong texels along the box's outline.
 * Controls, rendered every run from the same bake:
 *  - "no dilation": every texel the baker did not sample (dilated or unused) set to 0, as if
 *    dilation were off: must FAIL the seam criterion;
 *  - "half-texel offset": every atlas uv moved by half a texel in u and v (lookups off by half a
 *    texel against where the texels were gathered): printed only — at the default texel size the
 *    shifted maps differ from the right ones by less than the reference's noise at 128 spp (dilation
 *    extends every chart by constants, so a shift shows only where the irradiance bends: contact);
 *    the placement check above is what catches a half-texel offset in the bake.
 * Bake: the default texel size (radiosity_size of prw_quality_default()) and filter radius, 32
 * samples (the default is PRW_GI_DEFAULT_SAMPLES, 128: a noisier light map, same layout);
 * PRW_SEAM_RADIOSITY / PRW_SEAM_SAMPLES / PRW_SEAM_FILTER override them, PRW_SEAM_SPP the reference's
 * samples per pixel (default 128), PRW_SEAM_OUT=DIR writes the images (EXR and PNG) and charts.exr.
 * Light mode (sanitizers): a tiny bake and reference; figures printed, only the no-dilation control,
 * the border and contact counts, the texel placement and finiteness checked, and the no-dilation
 * control must read worse than the light maps. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gltf_writer.h"
#include "lightmaps.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_metrics.h"
#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"
#include "prw_test_gpu.h"
#include "prw_test_ref.h"
#include "prw_view.h"

#define W 160u
#define H 90u
#define MIN_PAIRS 6
#define MIN_COS 0.2 /* pixels seeing their surface at more than ~78 degrees from its normal are left out */
#define SEAM_K 4.0 /* standard errors: 11 borders, and the light map's own noise is not in the error bars */
#define LEAK_BAND 0.06 /* metres */
#define LEAK_K 3.0

/* The box room: 4 x 2.5 x 3 m; the box x 0.4..1.2, y 0..0.7, z -0.6..0.2. */
static const double BOX_LO[3] = {0.4, 0.0, -0.6}, BOX_HI[3] = {1.2, 0.7, 0.2};
/* The room; the first %s: the box mesh entry (or empty), the second: a "gltf" section (or empty). */
static const char *k_manifest_fmt =
    "{\n"
    "  \"prw_manifest\": 1,\n"
    "  \"materials\": [\n"
    "    {\"name\": \"white\", \"base_color\": [0.75, 0.75, 0.72], \"metallic\": 0, \"roughness\": 0.9},\n"
    "    {\"name\": \"floor\", \"base_color\": [0.55, 0.45, 0.35], \"metallic\": 0, \"roughness\": 0.9},\n"
    "    {\"name\": \"red\", \"base_color\": [0.65, 0.12, 0.08], \"metallic\": 0, \"roughness\": 0.9}\n"
    "  ],\n"
    "  \"meshes\": [\n"
    "    {\"name\": \"room\", \"box\": {\"min\": [-2, 0, -1.5], \"max\": [2, 2.5, 1.5], \"inward\": true}, \"material\": "
    "\"white\"},\n"
    "    {\"name\": \"floor left\", \"quad\": {\"centre\": [-1, 0.001, 0], \"half_u\": [0, 0, 1.5], \"half_v\": [1, 0, 0]}, "
    "\"material\": \"floor\"},\n"
    "    {\"name\": \"floor right\", \"quad\": {\"centre\": [1, 0.001, 0], \"half_u\": [0, 0, 1.5], \"half_v\": [1, 0, 0]}, "
    "\"material\": \"floor\"},\n"
    "    {\"name\": \"back left\", \"quad\": {\"centre\": [-1, 1.25, -1.499], \"half_u\": [1, 0, 0], \"half_v\": [0, 1.25, 0]}, "
    "\"material\": \"white\"},\n"
    "    {\"name\": \"back right\", \"quad\": {\"centre\": [1, 1.25, -1.499], \"half_u\": [1, 0, 0], \"half_v\": [0, 1.25, 0]}, "
    "\"material\": \"white\"}%s\n"
    "  ],\n%s"
    "  \"lights\": [\n"
    "    {\"type\": \"point\", \"name\": \"lamp\", \"position\": [-0.6, 2.2, 0.3], \"intensity\": 400, \"unit\": \"cd\"}\n"
    "  ],\n"
    "  \"cameras\": [\n"
    "    {\"name\": \"main\", \"position\": [-1.5, 1.7, 1.1], \"target\": [0.5, 0.35, -0.9], \"up\": [0, 1, 0], "
    "\"yfov_deg\": 62, \"znear\": 0.05, \"ev100\": 6}\n"
    "  ]\n"
    "}\n";

static unsigned long env_u(const char *name, unsigned long def)
{
    const char *v = getenv(name);
    return v && *v ? strtoul(v, NULL, 10) : def;
}

static double luma(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

static bool render_raster(const prw_scene *s, const prw_view *v, const prw_lightmaps *lm, prw_image *hdr, prw_error *e)
{
    prw_render_desc rd = {.width = W, .height = H, .quality = prw_quality_default(), .lightmaps = lm,
                          .terms = PRW_TERM_INDIRECT_DIFFUSE};
    rd.quality.msaa = 4;
    return prw_test_render(s, &rd, v, 1, hdr, NULL, e);
}

/* Reference A or B at the pixels `need` marks (NULL: every pixel; prw_test_ref.h: bit-identical there to
 * a whole-image render, NaN elsewhere). */
static bool render_ref(prw_ref_renderer *ref, const prw_view *v, uint64_t spp, uint64_t seed, const uint8_t *need,
                       prw_image *out, prw_error *e)
{
    prw_ref_desc d = {.s0 = 0, .s1 = spp, .seed = seed, .filter = {.kind = PRW_REF_INDIRECT_DIFFUSE_LAST}};
    double t0 = prw_now();
    size_t pixels = 0;
    if (!prw_test_ref_pixels(ref, v, &d, need, out, &pixels, e)) return false;
    printf("reference indirect-diffuse-last seed %llu: %llu spp at %zu of %u pixels in %.1f s\n", (unsigned long long)seed,
           (unsigned long long)spp, pixels, W * H, prw_now() - t0);
    return true;
}

/* ---- the bake's charts, per pixel ---- */

typedef struct wtri {
    double p[3][3];
    uint32_t chart; /* global chart id */
    uint32_t mesh;  /* scene mesh */
} wtri;

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

/* The world triangles of the ATLAS instances with their chart ids (see the header). */
static wtri *chart_triangles(const prw_scene *s, const prw_gi_bake *b, uint32_t *count)
{
    uint32_t total = 0;
    for (uint32_t i = 0; i < b->instance_count; i++)
        if (b->inst[i].mode == PRW_GI_ATLAS) total += b->inst[i].triangle_count;
    wtri *t = prw_calloc((size_t)total + 1, sizeof *t);
    uint32_t *parent = prw_calloc((size_t)total + 1, sizeof *parent);
    for (uint32_t k = 0; k < total; k++) parent[k] = k;
    uint32_t base = 0;
    for (uint32_t i = 0; i < b->instance_count; i++) {
        const prw_gi_instance *in = &b->inst[i];
        if (in->mode != PRW_GI_ATLAS) continue;
        const prw_mesh *m = &s->meshes[in->mesh];
        const prw_node *nd = &s->nodes[in->node];
        for (uint32_t k = 0; k < in->triangle_count; k++)
            for (int c = 0; c < 3; c++) {
                const float *q = m->positions + 3 * m->indices[3 * k + c];
                prw_dvec3 w = prw_dm4_point(nd->world, prw_v3(q[0], q[1], q[2]));
                t[base + k].p[c][0] = w.x, t[base + k].p[c][1] = w.y, t[base + k].p[c][2] = w.z;
                t[base + k].mesh = in->mesh;
            }
        for (uint32_t k = 0; k < in->triangle_count; k++)
            for (uint32_t l = k + 1; l < in->triangle_count; l++)
                for (int a = 0; a < 3; a++)
                    for (int c = 0; c < 3; c++) {
                        const float *ua = in->uv + 6 * (size_t)k + 2 * a, *uc = in->uv + 6 * (size_t)l + 2 * c;
                        double dd = 0;
                        for (int x = 0; x < 3; x++) dd += fabs(t[base + k].p[a][x] - t[base + l].p[c][x]);
                        if (dd < 1e-6 && ua[0] == uc[0] && ua[1] == uc[1])
                            parent[uf_find(parent, base + k)] = uf_find(parent, base + l);
                    }
        base += in->triangle_count;
    }
    for (uint32_t k = 0; k < total; k++) t[k].chart = uf_find(parent, k);
    free(parent);
    *count = total;
    return t;
}

/* Nearest hit of the ray (o, d) among the triangles (both faces): its chart and point; false on a miss. */
static bool ray_chart(const wtri *t, uint32_t n, prw_dvec3 o, prw_dvec3 d, uint32_t *chart, double hit[3], double *cosv)
{
    double best = INFINITY;
    const double O[3] = {o.x, o.y, o.z}, D[3] = {d.x, d.y, d.z};
    for (uint32_t k = 0; k < n; k++) {
        double e1[3], e2[3], pv[3], tv[3], qv[3];
        for (int c = 0; c < 3; c++) e1[c] = t[k].p[1][c] - t[k].p[0][c], e2[c] = t[k].p[2][c] - t[k].p[0][c];
        pv[0] = D[1] * e2[2] - D[2] * e2[1], pv[1] = D[2] * e2[0] - D[0] * e2[2], pv[2] = D[0] * e2[1] - D[1] * e2[0];
        double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
        if (fabs(det) < 1e-14) continue;
        for (int c = 0; c < 3; c++) tv[c] = O[c] - t[k].p[0][c];
        double u = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
        if (u < 0 || u > 1) continue;
        qv[0] = tv[1] * e1[2] - tv[2] * e1[1], qv[1] = tv[2] * e1[0] - tv[0] * e1[2], qv[2] = tv[0] * e1[1] - tv[1] * e1[0];
        double v = (D[0] * qv[0] + D[1] * qv[1] + D[2] * qv[2]) / det;
        if (v < 0 || u + v > 1) continue;
        double tt = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
        if (tt > 1e-6 && tt < best) {
            best = tt;
            *chart = t[k].chart;
            for (int c = 0; c < 3; c++) hit[c] = O[c] + tt * D[c];
            double nn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
            double ln = sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]), ld = sqrt(D[0] * D[0] + D[1] * D[1] + D[2] * D[2]);
            *cosv = fabs(nn[0] * D[0] + nn[1] * D[1] + nn[2] * D[2]) / (ln * ld);
        }
    }
    return isfinite(best);
}

typedef struct pixinfo {
    bool hit;
    uint32_t chart, other; /* other: a second chart among the sub-pixel rays (UINT32_MAX: none) */
    bool mixed3;           /* three or more charts in the pixel */
    double p[3];
    double foot; /* the pixel's footprint at the hit, metres */
    double cosv; /* |cos| between the view ray and the surface's normal */
} pixinfo;

static void pixel_charts(const wtri *t, uint32_t n, const prw_view *v, pixinfo *pi)
{
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            pixinfo *q = &pi[(size_t)y * W + x];
            q->other = UINT32_MAX;
            q->hit = ray_chart(t, n, v->eye, prw_view_ray_dir(v, x + 0.5, y + 0.5), &q->chart, q->p, &q->cosv);
            double de = sqrt((q->p[0] - v->eye.x) * (q->p[0] - v->eye.x) + (q->p[1] - v->eye.y) * (q->p[1] - v->eye.y) +
                             (q->p[2] - v->eye.z) * (q->p[2] - v->eye.z));
            q->foot = de * (v->tan_top - v->tan_bottom) / H;
            for (int j = 0; j < 9 && q->hit; j++) {
                uint32_t c;
                double h[3], cv;
                if (!ray_chart(t, n, v->eye, prw_view_ray_dir(v, x + 0.05 + 0.45 * (j % 3), y + 0.05 + 0.45 * (j / 3)), &c, h, &cv))
                    q->mixed3 = true;
                else if (c != q->chart && q->other == UINT32_MAX) q->other = c;
                else if (c != q->chart && c != q->other) q->mixed3 = true;
            }
        }
}

/* ---- the criteria ---- */

typedef struct border {
    uint32_t c1, c2; /* c1 < c2 */
    uint32_t pairs;
    double sum_d, sum_d2, sum_n2, sum_level;
} border;

typedef struct seam_result {
    uint32_t borders, checked, failed, pairs;
    double worst; /* largest |mean d| / sigma over the checked borders */
} seam_result;

/* Adjacent pixels p, q form a border pair (the header): different charts, no third chart in either,
 * not grazing, and their hit points within 8 pixel footprints (a shared edge, not a silhouette). */
static bool border_pair(const pixinfo *p, const pixinfo *q)
{
    if (!p->hit || !q->hit || p->chart == q->chart || p->mixed3 || q->mixed3) return false;
    if (p->cosv < MIN_COS || q->cosv < MIN_COS) return false; /* grazing: the pixel spans many texels */
    if ((p->other != UINT32_MAX && p->other != q->chart) || (q->other != UINT32_MAX && q->other != p->chart))
        return false;
    double dist = 0;
    for (int c = 0; c < 3; c++) dist += (p->p[c] - q->p[c]) * (p->p[c] - q->p[c]);
    return !(sqrt(dist) > 8 * p->foot);
}

/* The seam criterion of the header for raster image r; verbose: one line per border. */
static seam_result seams(const pixinfo *pi, const prw_image *r, const prw_image *a, const prw_image *b, bool verbose)
{
    border *bd = NULL;
    uint32_t nb = 0, cap = 0;
    seam_result out = {0};
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++)
            for (int dir = 0; dir < 2; dir++) {
                uint32_t x2 = x + (dir == 0), y2 = y + (dir == 1);
                if (x2 >= W || y2 >= H) continue;
                size_t i = (size_t)y * W + x, j = (size_t)y2 * W + x2;
                const pixinfo *p = &pi[i], *q = &pi[j];
                if (!border_pair(p, q)) continue;
                uint32_t c1 = p->chart < q->chart ? p->chart : q->chart, c2 = p->chart ^ q->chart ^ c1;
                double sgn = p->chart == c1 ? 1 : -1;
                double d = sgn * ((luma(r->rgba + 4 * i) - luma(r->rgba + 4 * j)) - (luma(a->rgba + 4 * i) - luma(a->rgba + 4 * j)));
                double nn = (luma(b->rgba + 4 * i) - luma(b->rgba + 4 * j)) - (luma(a->rgba + 4 * i) - luma(a->rgba + 4 * j));
                uint32_t k = 0;
                while (k < nb && !(bd[k].c1 == c1 && bd[k].c2 == c2)) k++;
                if (k == nb) {
                    if (nb == cap) cap = cap ? 2 * cap : 16, bd = prw_realloc(bd, cap * sizeof *bd);
                    bd[nb++] = (border){c1, c2, 0, 0, 0, 0, 0};
                }
                bd[k].pairs++;
                bd[k].sum_d += d, bd[k].sum_d2 += d * d, bd[k].sum_n2 += nn * nn;
                bd[k].sum_level += 0.5 * (luma(a->rgba + 4 * i) + luma(a->rgba + 4 * j));
                out.pairs++;
            }
    out.borders = nb;
    for (uint32_t k = 0; k < nb; k++) {
        const border *q = &bd[k];
        double md = q->sum_d / q->pairs, sigma = sqrt(q->sum_n2 / q->pairs / 2), level = q->sum_level / q->pairs;
        double rms = sqrt(q->sum_d2 / q->pairs);
        bool checked = q->pairs >= MIN_PAIRS;
        double se = sigma / sqrt((double)q->pairs); /* the reference noise of the mean jump */
        bool pass = !checked || fabs(md) <= SEAM_K * se;
        if (checked) {
            out.checked++;
            out.failed += !pass;
            if (se > 0 && fabs(md) / se > out.worst) out.worst = fabs(md) / se;
        }
        if (verbose)
            printf("  border charts %3u|%-3u %4u pairs  mean jump %+8.4f = %+5.1f se (%+5.1f %% of the level %.4f)  pair "
                   "noise sigma %.4f  %s\n",
                   q->c1, q->c2, q->pairs, md, se > 0 ? md / se : 0, 100 * md / level, level, sigma,
                   !checked ? "(too few pairs)" : pass ? "ok" : "SEAM");
        (void)rms;
    }
    free(bd);
    return out;
}

/* Texel placement, noise-free: on the floor quads' charts, every texel whose centre (by the bake's uvs:
 * texel (i, j) centred at ((i + 0.5) / width, (j + 0.5) / height)) lies in a triangle is gathered at
 * that centre's world point, so it must be hidden (not sampled: the point is inside the box, whose
 * faces its rays meet from behind) exactly when that point lies under the box's foot print.  Texels
 * within EDGE_EPS texels of the foot print's outline are not judged.  Returns the texels judged and
 * counts the disagreements. */
#define EDGE_EPS 0.05
static uint32_t placement(const prw_scene *s, const prw_gi_bake *b, uint32_t *bad)
{
    uint32_t judged = 0;
    *bad = 0;
    for (uint32_t ii = 0; ii < b->instance_count; ii++) {
        const prw_gi_instance *in = &b->inst[ii];
        if (in->mode != PRW_GI_ATLAS || strncmp(s->meshes[in->mesh].name, "floor", 5) != 0) continue;
        const prw_gi_atlas *A = &b->atlases[in->atlas];
        const prw_mesh *m = &s->meshes[in->mesh];
        for (uint32_t t = 0; t < in->triangle_count; t++) {
            double X[3], Y[3], P[3][3];
            for (int k = 0; k < 3; k++) {
                X[k] = in->uv[6 * t + 2 * k] * A->width - 0.5, Y[k] = in->uv[6 * t + 2 * k + 1] * A->height - 0.5;
                const float *q = m->positions + 3 * m->indices[3 * t + k];
                prw_dvec3 w = prw_dm4_point(s->nodes[in->node].world, prw_v3(q[0], q[1], q[2]));
                P[k][0] = w.x, P[k][1] = w.y, P[k][2] = w.z;
            }
            double det = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
            if (!(fabs(det) > 1e-9)) continue;
            int x0 = (int)floor(fmin(X[0], fmin(X[1], X[2]))), x1 = (int)ceil(fmax(X[0], fmax(X[1], X[2])));
            int y0 = (int)floor(fmin(Y[0], fmin(Y[1], Y[2]))), y1 = (int)ceil(fmax(Y[0], fmax(Y[1], Y[2])));
            double texel_m = b->texel_size;
            for (int j = y0 > 0 ? y0 : 0; j <= y1 && j < (int)A->height; j++)
                for (int i = x0 > 0 ? x0 : 0; i <= x1 && i < (int)A->width; i++) {
                    double b1 = ((i - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (j - Y[0])) / det;
                    double b2 = ((X[1] - X[0]) * (j - Y[0]) - (i - X[0]) * (Y[1] - Y[0])) / det, b0 = 1 - b1 - b2;
                    if (b0 < 1e-6 || b1 < 1e-6 || b2 < 1e-6) continue; /* centre inside, off the triangle's edges */
                    double px = b0 * P[0][0] + b1 * P[1][0] + b2 * P[2][0], pz = b0 * P[0][2] + b1 * P[1][2] + b2 * P[2][2];
                    /* signed distance to the foot print's outline (negative inside) */
                    double dx = fmax(BOX_LO[0] - px, px - BOX_HI[0]), dz = fmax(BOX_LO[2] - pz, pz - BOX_HI[2]);
                    double d = dx > 0 || dz > 0 ? sqrt(fmax(dx, 0) * fmax(dx, 0) + fmax(dz, 0) * fmax(dz, 0)) : fmax(dx, dz);
                    if (fabs(d) < EDGE_EPS * texel_m) continue;
                    bool sampled = A->state[(size_t)j * A->width + i] == 1;
                    judged++;
                    if (sampled != (d > 0)) (*bad)++;
                }
        }
    }
    return judged;
}

typedef struct leak_result {
    uint32_t pixels;
    double excess, sigma, level; /* mean(R - A), the standard deviation of that mean, mean(A) */
} leak_result;

/* The pixels next to the box's contact with the floor (see the header). */
static bool contact_pixel(const pixinfo *p)
{
    if (!p->hit) return false;
    const double *h = p->p;
    if (h[1] < 0.01) { /* the floor: outside the box's foot print, within the band */
        double dx = fmax(fmax(BOX_LO[0] - h[0], h[0] - BOX_HI[0]), 0), dz = fmax(fmax(BOX_LO[2] - h[2], h[2] - BOX_HI[2]), 0);
        double dd = sqrt(dx * dx + dz * dz);
        return dd > 0 && dd <= LEAK_BAND;
    }
    bool side = (fabs(h[0] - BOX_LO[0]) < 1e-4 || fabs(h[0] - BOX_HI[0]) < 1e-4 || fabs(h[2] - BOX_LO[2]) < 1e-4 ||
                 fabs(h[2] - BOX_HI[2]) < 1e-4) &&
                h[0] >= BOX_LO[0] - 1e-4 && h[0] <= BOX_HI[0] + 1e-4 && h[2] >= BOX_LO[2] - 1e-4 && h[2] <= BOX_HI[2] + 1e-4;
    return side && h[1] <= LEAK_BAND;
}

static leak_result leaks(const pixinfo *pi, const prw_image *r, const prw_image *a, const prw_image *b)
{
    leak_result out = {0};
    double sum = 0, n2 = 0, lev = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        if (!contact_pixel(&pi[i])) continue;
        double la = luma(a->rgba + 4 * i);
        sum += luma(r->rgba + 4 * i) - la;
        n2 += (luma(b->rgba + 4 * i) - la) * (luma(b->rgba + 4 * i) - la);
        lev += la;
        out.pixels++;
    }
    if (out.pixels) {
        out.excess = sum / out.pixels;
        out.sigma = sqrt(n2 / out.pixels / 2 / out.pixels);
        out.level = lev / out.pixels;
    }
    return out;
}

/* The pixels the criteria read from the references: both pixels of every border pair, and the contact
 * pixels. */
static uint8_t *criteria_pixels(const pixinfo *pi)
{
    uint8_t *need = prw_calloc((size_t)W * H, 1);
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            if (contact_pixel(&pi[i])) need[i] = 1;
            if (x + 1 < W && border_pair(&pi[i], &pi[i + 1])) need[i] = need[i + 1] = 1;
            if (y + 1 < H && border_pair(&pi[i], &pi[i + W])) need[i] = need[i + W] = 1;
        }
    return need;
}

static void write_if(const char *dir, const char *name, const prw_image *im, double ev100)
{
    if (!dir || !*dir) return;
    char path[4096], ev[64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(ev, sizeof ev, "%.17g", ev100);
    prw_kv kv[] = {{"prw:ev100", ev}};
    prw_error e;
    if (prw_exr_write(path, im, kv, 1, &e)) printf("wrote %s\n", path);
    else fprintf(stderr, "%s\n", e.msg);
    prw_image tm = {0}; /* and the metric tone map as PNG, for looking at */
    if (!prw_metric_tonemap(im, ev100, &tm, &e)) return;
    uint8_t *px = prw_malloc((size_t)tm.width * tm.height * 3);
    for (size_t i = 0; i < (size_t)tm.width * tm.height; i++)
        for (int c = 0; c < 3; c++) px[i * 3 + c] = (uint8_t)lrintf(255.0f * fminf(fmaxf(tm.rgba[i * 4 + c], 0.0f), 1.0f));
    size_t n = strlen(path);
    memcpy(path + n - 4, ".png", 4);
    if (prw_png_write8(path, tm.width, tm.height, 3, px, &e)) printf("wrote %s\n", path);
    free(px);
    prw_image_free(&tm);
}

/* A copy of b (through its file encoding). */
static prw_gi_bake *bake_clone(const prw_gi_bake *b, prw_error *e)
{
    uint8_t *data = NULL;
    size_t size = 0;
    prw_gi_bake *c = NULL;
    char key[33];
    if (prw_gi_encode(b, "0123456789abcdef0123456789abcdef", &data, &size, e))
        if (!prw_gi_decode(data, size, "clone", &c, key, e)) c = NULL;
    free(data);
    return c;
}

static const char *k_box_entry =
    ",\n    {\"name\": \"box\", \"box\": {\"min\": [0.4, 0, -0.6], \"max\": [1.2, 0.7, 0.2]}, \"material\": \"red\"}";

static void run_room(const char *name, const char *box_entry, const char *gltf_section)
{
    bool light = prw_test_light();
    prw_error e = {{0}};
    const char *path = prw_test_path(name);
    char manifest[8192];
    snprintf(manifest, sizeof manifest, k_manifest_fmt, box_entry, gltf_section);
    prw_test_write_file(path, manifest, strlen(manifest));
    prw_scene *s = prw_scene_create();
    CHECK_OK(prw_scene_load_manifest(s, path, &e), &e);
    prw_scene_update(s);
    prw_view v;
    CHECK_OK(prw_ref_view_for_camera(s, "main", W, H, &v, &e), &e);

    uint32_t rs_default = light ? 128 : prw_quality_default().radiosity_size;
    prw_gi_options o = {.radiosity_size = (uint32_t)env_u("PRW_SEAM_RADIOSITY", rs_default),
                        .samples = (uint32_t)env_u("PRW_SEAM_SAMPLES", light ? 8 : 32), .seed = 3,
                        .filter_radius = (uint32_t)env_u("PRW_SEAM_FILTER", PRW_GI_DEFAULT_FILTER_RADIUS)};
    prw_gi_bake *b = NULL;
    prw_gi_result gr;
    CHECK_OK(prw_gi_run(s, &o, true, NULL, NULL, &b, &gr, &e), &e);
    printf("bake: radiosity_size %u, %u samples, filter radius %u, texel %.4f m, %llu charts, %llu texels (%llu hidden) "
           "+ %llu vertices, %.1f s\n",
           o.radiosity_size, o.samples, o.filter_radius, b->texel_size, (unsigned long long)b->charts,
           (unsigned long long)b->sampled_texels, (unsigned long long)b->hidden_texels,
           (unsigned long long)b->sampled_vertices, gr.seconds_total);
    uint32_t misplaced = 0, judged = placement(s, b, &misplaced);
    printf("texel placement on the floor: %u texels judged, %u hidden where their centre is not under the box or "
           "sampled where it is\n", judged, misplaced);
    CHECK_MSG(judged > 1000, "only %u floor texels judged", judged);
    CHECK_MSG(misplaced == 0, "%u floor texels gathered elsewhere than at their centres", misplaced);
    uint32_t nt = 0;
    wtri *tris = chart_triangles(s, b, &nt);
    pixinfo *pi = prw_calloc((size_t)W * H, sizeof *pi);
    pixel_charts(tris, nt, &v, pi);
    for (uint32_t k = 0; k < nt; k++) { /* the charts seen, named, for reading the border lines */
        bool seen = false, first = true;
        for (size_t i = 0; i < (size_t)W * H && !seen; i++) seen = pi[i].hit && pi[i].chart == tris[k].chart;
        for (uint32_t l = 0; l < k && first; l++) first = tris[l].chart != tris[k].chart;
        if (!seen || !first) continue;
        double e1[3], e2[3], n[3];
        for (int c = 0; c < 3; c++) e1[c] = tris[k].p[1][c] - tris[k].p[0][c], e2[c] = tris[k].p[2][c] - tris[k].p[0][c];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1], n[1] = e1[2] * e2[0] - e1[0] * e2[2], n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        printf("  chart %3u: mesh '%s', normal (%+.0f %+.0f %+.0f)\n", tris[k].chart, s->meshes[tris[k].mesh].name,
               n[0] / l, n[1] / l, n[2] / l);
    }
    free(tris);

    /* the no-dilation control's bake: every dilated texel black */
    prw_gi_bake *nod = bake_clone(b, &e);
    CHECK_OK(nod != NULL, &e);
    for (uint32_t a = 0; a < nod->atlas_count; a++)
        for (size_t t = 0; t < (size_t)nod->atlases[a].width * nod->atlases[a].height; t++)
            if (nod->atlases[a].state[t] != 1) memset(nod->atlases[a].rgb + 3 * t, 0, 3 * sizeof(float));
    prw_app_lightmaps *lms = NULL, *lms_nod = NULL;
    CHECK_OK(prw_app_lightmaps_from_bake(s, b, &lms, &e), &e);
    CHECK_OK(prw_app_lightmaps_from_bake(s, nod, &lms_nod, &e), &e);
    const prw_lightmaps *lm = prw_app_lightmaps_get(lms);
    /* the half-texel control: every atlas uv moved by half a texel */
    prw_lightmap_instance *inst = prw_calloc(lm->instance_count + 1, sizeof *inst);
    float **uvs = prw_calloc(lm->instance_count + 1, sizeof *uvs);
    for (uint32_t i = 0; i < lm->instance_count; i++) {
        inst[i] = lm->inst[i];
        if (inst[i].mode != PRW_LIGHTMAP_ATLAS) continue;
        const prw_lightmap_atlas *A = &lm->atlases[inst[i].atlas];
        uvs[i] = prw_malloc(2 * (size_t)inst[i].vertex_count * sizeof(float));
        for (size_t k = 0; k < (size_t)inst[i].vertex_count; k++) {
            uvs[i][2 * k] = inst[i].uv[2 * k] + 0.5f / (float)A->width;
            uvs[i][2 * k + 1] = inst[i].uv[2 * k + 1] + 0.5f / (float)A->height;
        }
        inst[i].uv = uvs[i];
    }
    prw_lightmaps half = *lm;
    half.inst = inst;

    prw_image raster = {0}, r_nod = {0}, r_half = {0}, ra = {0}, rb = {0};
    CHECK_OK(render_raster(s, &v, lm, &raster, &e), &e);
    CHECK_OK(render_raster(s, &v, prw_app_lightmaps_get(lms_nod), &r_nod, &e), &e);
    CHECK_OK(render_raster(s, &v, &half, &r_half, &e), &e);
    uint64_t spp = env_u("PRW_SEAM_SPP", light ? 32 : 128);
    prw_ref_renderer *ref = NULL;
    CHECK_OK(prw_ref_create(s, v.eye, 0, &ref, &e), &e);
    /* only the pixels the criteria read (PRW_SEAM_OUT: every pixel, for the images) */
    const char *dir = getenv("PRW_SEAM_OUT");
    uint8_t *need = dir && *dir ? NULL : criteria_pixels(pi);
    bool ok = render_ref(ref, &v, spp, 1, need, &ra, &e) && render_ref(ref, &v, spp, 2, need, &rb, &e);
    free(need);
    prw_ref_destroy(ref);
    CHECK_OK(ok, &e);
    for (size_t i = 0; i < (size_t)W * H; i++)
        for (int c = 0; c < 3; c++) CHECK(isfinite(raster.rgba[4 * i + c]) && raster.rgba[4 * i + c] >= 0);

    printf("box room, %ux%u, 4x MSAA, term indirect-diffuse vs reference indirect-diffuse-last %llu spp (seeds 1, 2):\n",
           W, H, (unsigned long long)spp);
    seam_result sr = seams(pi, &raster, &ra, &rb, true);
    seam_result sn = seams(pi, &r_nod, &ra, &rb, false);
    seam_result sh = seams(pi, &r_half, &ra, &rb, false);
    leak_result lr = leaks(pi, &raster, &ra, &rb), ln = leaks(pi, &r_nod, &ra, &rb), lh = leaks(pi, &r_half, &ra, &rb);
    printf("  seams: %u pairs over %u borders, %u checked (>= %d pairs), %u with |mean jump| > %.1f se (worst %.2f se)\n",
           sr.pairs, sr.borders, sr.checked, MIN_PAIRS, sr.failed, SEAM_K, sr.worst);
    printf("  control no dilation:       %u of %u borders fail (worst %.2f se)\n", sn.failed, sn.checked, sn.worst);
    printf("  control half-texel offset: %u of %u borders fail (worst %.2f se)\n", sh.failed, sh.checked, sh.worst);
    printf("  contact (%u pixels within %.2f m of the box's foot): mean(raster - A) %+.5f (%.1f sigma of the mean, "
           "%+.2f %% of A's %.5f)\n",
           lr.pixels, LEAK_BAND, lr.excess, lr.sigma > 0 ? lr.excess / lr.sigma : 0, 100 * lr.excess / lr.level, lr.level);
    printf("  contact controls: no dilation %+.1f sigma, half-texel offset %+.1f sigma\n",
           ln.sigma > 0 ? ln.excess / ln.sigma : 0, lh.sigma > 0 ? lh.excess / lh.sigma : 0);
    CHECK_MSG(sr.checked >= 8, "only %u borders with enough pairs: the scene or camera no longer shows them", sr.checked);
    CHECK_MSG(lr.pixels >= 20, "only %u contact pixels", lr.pixels);
    if (light) /* the small bake and reference: the control only has to read worse than the light maps */
        CHECK_MSG(sn.worst > sr.worst, "the no-dilation control (worst %.2f se) is not worse than the light maps (%.2f se)",
                  sn.worst, sr.worst);
    else
        CHECK_MSG(sn.failed > 0, "the no-dilation control passes the seam criterion");
    if (!light) {
        CHECK_MSG(sr.failed == 0, "%u of %u chart borders show a seam (worst %.2f se)", sr.failed, sr.checked, sr.worst);
        CHECK_MSG(lr.excess <= LEAK_K * lr.sigma, "light leaks at the contact: %+.5f > %.1f x %.5f", lr.excess, LEAK_K,
                  lr.sigma);
    }
    double ev = dir && *dir ? prw_compare_derive_ev100(&ra, NULL) : 0;
    write_if(dir, "raster.exr", &raster, ev);
    write_if(dir, "nodilate.exr", &r_nod, ev);
    write_if(dir, "halftexel.exr", &r_half, ev);
    write_if(dir, "ref_a.exr", &ra, ev);
    write_if(dir, "ref_b.exr", &rb, ev);
    if (dir && *dir) { /* the chart ids, for looking at */
        prw_image ids = {0};
        if (prw_image_alloc(&ids, W, H, &e)) {
            for (size_t i = 0; i < (size_t)W * H; i++)
                for (int c = 0; c < 3; c++)
                    ids.rgba[4 * i + c] = pi[i].hit ? (float)((pi[i].chart * (c == 0 ? 37u : c == 1 ? 91u : 53u)) % 97u) / 97.0f : 0;
            write_if(dir, "charts.exr", &ids, 0);
            prw_image_free(&ids);
        }
    }
    for (uint32_t i = 0; i < lm->instance_count; i++) free(uvs[i]);
    free(uvs);
    free(inst);
    free(pi);
    prw_image_free(&raster);
    prw_image_free(&r_nod);
    prw_image_free(&r_half);
    prw_image_free(&ra);
    prw_image_free(&rb);
    prw_app_lightmaps_destroy(lms);
    prw_app_lightmaps_destroy(lms_nod);
    prw_scene_destroy(s);
}

static void test_gi_seam_box_room(void) { run_room("seam-room.json", k_box_entry, ""); }

/* The same room with the box as a glTF mesh carrying TEXCOORD_1: its six faces laid out by the
 * "author" as islands in a 3 x 2 grid, 0.01 uv apart (under a texel at the bake's scale), so that the
 * baker, not the layout's padding, has to keep the islands' texels apart. */
static void test_gi_seam_uv1_islands(void)
{
    static const double C[3] = {0.8, 0.35, -0.2}, HE[3] = {0.4, 0.35, 0.4};
    const double fc[6][3] = {{HE[0], 0, 0}, {-HE[0], 0, 0}, {0, HE[1], 0}, {0, -HE[1], 0}, {0, 0, HE[2]}, {0, 0, -HE[2]}};
    const double fu[6][3] = {{0, 0, -HE[2]}, {0, 0, HE[2]}, {0, 0, HE[2]}, {HE[0], 0, 0}, {HE[0], 0, 0}, {-HE[0], 0, 0}};
    const double fv[6][3] = {{0, HE[1], 0}, {0, HE[1], 0}, {HE[0], 0, 0}, {0, 0, HE[2]}, {0, HE[1], 0}, {0, HE[1], 0}};
    const double sc = 0.3 / 0.8, gap = 0.01; /* uv1 units per metre; between the islands */
    gmesh box = {.nv = 24, .ni = 36, .material = 0};
    box.pos = prw_malloc(24 * 3 * sizeof(float)), box.nrm = prw_malloc(24 * 3 * sizeof(float));
    box.uv = prw_malloc(24 * 2 * sizeof(float)), box.uv1 = prw_malloc(24 * 2 * sizeof(float));
    box.idx = prw_malloc(36 * sizeof(uint32_t));
    for (int f = 0; f < 6; f++) {
        gmesh q = gltfw_quad(fc[f], fu[f], fv[f], 0);
        double lu = 2 * sqrt(fu[f][0] * fu[f][0] + fu[f][1] * fu[f][1] + fu[f][2] * fu[f][2]);
        double lv = 2 * sqrt(fv[f][0] * fv[f][0] + fv[f][1] * fv[f][1] + fv[f][2] * fv[f][2]);
        double ou = (f % 3) * (0.3 + gap), ov = (f / 3) * (0.3 + gap);
        for (int v = 0; v < 4; v++) {
            for (int k = 0; k < 3; k++) {
                box.pos[3 * (4 * f + v) + k] = (float)(q.pos[3 * v + k] + fc[f][k]);
                box.nrm[3 * (4 * f + v) + k] = q.nrm[3 * v + k];
            }
            box.uv[2 * (4 * f + v)] = q.uv[2 * v], box.uv[2 * (4 * f + v) + 1] = q.uv[2 * v + 1];
            box.uv1[2 * (4 * f + v)] = (float)(ou + q.uv[2 * v] * lu * sc);
            box.uv1[2 * (4 * f + v) + 1] = (float)(ov + q.uv[2 * v + 1] * lv * sc);
        }
        for (int k = 0; k < 6; k++) box.idx[6 * f + k] = 4 * (uint32_t)f + q.idx[k];
        gltfw_mesh_free(&q);
    }
    for (int k = 0; k < 3; k++) box.at[k] = C[k];
    gfile g = {.mesh_count = 1,
               .materials = "{\"name\":\"red\",\"pbrMetallicRoughness\":{\"baseColorFactor\":[0.65,0.12,0.08,1],"
                            "\"metallicFactor\":0,\"roughnessFactor\":0.9}}",
               .eye = {0, 1, 3}, .target = {0, 0.5, 0}, .yfov = 1.0};
    g.mesh[0] = box;
    gltfw_write("seam-box", &g, 16.0 / 9.0);
    gltfw_mesh_free(&box);
    run_room("seam-room-uv1.json", "", "  \"gltf\": [{\"file\": \"seam-box.gltf\"}],\n");
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"gi_seam_box_room", test_gi_seam_box_room},
                                          {"gi_seam_uv1_islands", test_gi_seam_uv1_islands}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    return prw_test_gpu_finish() ? 1 : rc; /* one gpu for all cases: pipelines compiled once */
}
