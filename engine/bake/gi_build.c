/* gi_build.c — the indirect-diffuse bake (prw_gi.h): instance modes, flat-chart unwrapping and shelf
 * packing, texel rasterisation, gathering through prw_ref_trace_rays, dilation, lookups. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_brdf.h"
#include "prw_bsdf.h"
#include "prw_gi.h"
#include "prw_image.h"
#include "prw_reference.h"

#define CHART_COS 0.999    /* triangles join a chart within ~2.6 degrees of its first triangle */
#define RAY_OFFSET 2e-4    /* metres along the normal */
#define CHUNK_POINTS 512

/* ---- material weights (prw_gi.h) ---- */

static double e_ds(const prw_material *m, double mu)
{
    float r = m->roughness, s = fminf(fmaxf(m->specular, 0.0f), 1.0f);
    float fms = prw_F_ms(s * PRW_DIELECTRIC_F_AVG, prw_ggx_Ec_avg(r));
    float mo = (float)fmin(fmax(mu, 1e-6), 1.0);
    return s * prw_ggx_Ed(mo, r) + fms * prw_ggx_Ec(mo, r);
}

double prw_gi_weight(const prw_material *m, double mu) { return 1.0 - e_ds(m, mu); }

void prw_gi_radiance(const prw_material *m, const double base[3], double mu_o, const float E[3], double out[3])
{
    float r = m->roughness, s = fminf(fmaxf(m->specular, 0.0f), 1.0f);
    float fms = prw_F_ms(s * PRW_DIELECTRIC_F_AVG, prw_ggx_Ec_avg(r));
    double e_avg = s * prw_ggx_Ed_avg(r) + fms * prw_ggx_Ec_avg(r);
    double k = mu_o > 0 ? (1.0 - fmin(fmax(m->metallic, 0.0f), 1.0f)) / PRW_PI * (1.0 - e_ds(m, mu_o)) / (1.0 - e_avg) : 0;
    for (int c = 0; c < 3; c++) out[c] = k * base[c] * E[c];
}

/* ---- helpers ---- */

static void dsub(const double a[3], const double b[3], double o[3])
{
    for (int c = 0; c < 3; c++) o[c] = a[c] - b[c];
}
static double ddot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void dcross(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* World data of one instance. */
typedef struct winst {
    const prw_mesh *m;
    const prw_material *mat;
    double *p;    /* 3 per vertex, world */
    double *ng;   /* 3 per triangle: unit geometric normal of the front face (0 for degenerate) */
    double *area; /* per triangle */
    double *vn;   /* 3 per vertex: world shading normal (VERTEX mode) */
    bool flip;
} winst;

static void winst_make(const prw_scene *s, const prw_node *nd, const prw_mesh *m, winst *w)
{
    memset(w, 0, sizeof *w);
    w->m = m;
    w->mat = &s->materials[m->material];
    w->p = prw_calloc((size_t)m->vertex_count * 3, sizeof(double));
    w->vn = prw_calloc((size_t)m->vertex_count * 3, sizeof(double));
    uint32_t nt = m->index_count / 3;
    w->ng = prw_calloc((size_t)nt * 3 + 1, sizeof(double));
    w->area = prw_calloc((size_t)nt + 1, sizeof(double));
    const double *M = nd->world.m;
    double det = M[0] * (M[5] * M[10] - M[9] * M[6]) - M[4] * (M[1] * M[10] - M[9] * M[2]) +
                 M[8] * (M[1] * M[6] - M[5] * M[2]);
    w->flip = det < 0;
    prw_dmat4 inv;
    bool have_inv = prw_dm4_inverse(nd->world, &inv);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        prw_dvec3 q = prw_dm4_point(nd->world, prw_v3(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]));
        w->p[3 * v] = q.x, w->p[3 * v + 1] = q.y, w->p[3 * v + 2] = q.z;
        const float *n = m->normals + 3 * v;
        double o[3] = {0, 0, 0};
        for (int i = 0; i < 3 && have_inv; i++)
            for (int j = 0; j < 3; j++) o[i] += inv.m[i * 4 + j] * n[j]; /* inverse transpose */
        double l = sqrt(ddot(o, o));
        for (int c = 0; c < 3; c++) w->vn[3 * v + c] = l > 0 ? o[c] / l : 0;
    }
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *ix = m->indices + 3 * t;
        double a[3], b[3], c[3];
        dsub(w->p + 3 * ix[1], w->p + 3 * ix[0], a);
        dsub(w->p + 3 * ix[2], w->p + 3 * ix[0], b);
        dcross(a, b, c);
        double l = sqrt(ddot(c, c));
        w->area[t] = 0.5 * l;
        for (int k = 0; k < 3; k++) w->ng[3 * t + k] = l > 1e-20 ? (w->flip ? -c[k] : c[k]) / l : 0;
    }
}

static void winst_free(winst *w)
{
    free(w->p);
    free(w->vn);
    free(w->ng);
    free(w->area);
}

/* ---- charts ---- */

typedef struct chart {
    uint32_t inst;
    uint32_t *tris;
    uint32_t tri_count;
    double *xy;      /* 6 per chart triangle: corners in chart texel coordinates (padding included) */
    uint32_t w, h;   /* texels, padding included */
    uint32_t atlas, x0, y0;
} chart;

typedef struct edge_rec {
    uint32_t a, b, tri;
} edge_rec;

static int cmp_edge(const void *x, const void *y)
{
    const edge_rec *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    if (p->b != q->b) return p->b < q->b ? -1 : 1;
    return p->tri < q->tri ? -1 : p->tri > q->tri;
}

typedef struct weld_rec {
    int64_t k[3];
    uint32_t v;
} weld_rec;

static int cmp_weld(const void *x, const void *y)
{
    const weld_rec *p = x, *q = y;
    for (int c = 0; c < 3; c++)
        if (p->k[c] != q->k[c]) return p->k[c] < q->k[c] ? -1 : 1;
    return p->v < q->v ? -1 : p->v > q->v;
}

/* Flat charts of instance w (index ii) appended to *charts. */
static void make_charts(const winst *w, uint32_t ii, double texel, chart **charts, uint32_t *count, uint32_t *cap)
{
    const prw_mesh *m = w->m;
    uint32_t nv = m->vertex_count, nt = m->index_count / 3;
    /* weld by quantised position */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < nv; v++)
        for (int c = 0; c < 3; c++) lo[c] = fmin(lo[c], w->p[3 * v + c]), hi[c] = fmax(hi[c], w->p[3 * v + c]);
    double diag = 0;
    for (int c = 0; c < 3; c++) diag = fmax(diag, hi[c] - lo[c]);
    double q = fmax(diag * 1e-7, 1e-9);
    weld_rec *wr = prw_calloc((size_t)nv + 1, sizeof *wr);
    for (uint32_t v = 0; v < nv; v++) {
        for (int c = 0; c < 3; c++) wr[v].k[c] = (int64_t)llround((w->p[3 * v + c] - lo[c]) / q);
        wr[v].v = v;
    }
    qsort(wr, nv, sizeof *wr, cmp_weld);
    uint32_t *wid = prw_calloc((size_t)nv + 1, sizeof *wid);
    uint32_t id = 0;
    for (uint32_t i = 0; i < nv; i++) {
        if (i > 0 && memcmp(wr[i].k, wr[i - 1].k, sizeof wr[i].k) != 0) id++;
        wid[wr[i].v] = id;
    }
    free(wr);
    /* edges -> neighbours (CSR) */
    edge_rec *er = prw_calloc((size_t)nt * 3 + 1, sizeof *er);
    for (uint32_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = wid[m->indices[3 * t + k]], b = wid[m->indices[3 * t + (k + 1) % 3]];
            er[3 * t + k] = (edge_rec){a < b ? a : b, a < b ? b : a, t};
        }
    qsort(er, (size_t)nt * 3, sizeof *er, cmp_edge);
    uint32_t *deg = prw_calloc((size_t)nt + 1, sizeof *deg);
    size_t ne = (size_t)nt * 3;
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && er[j].a == er[i].a && er[j].b == er[i].b) j++;
        for (size_t x = i; x < j; x++) deg[er[x].tri] += (uint32_t)(j - i - 1);
        i = j;
    }
    uint32_t *off = prw_calloc((size_t)nt + 1, sizeof *off);
    for (uint32_t t = 0; t < nt; t++) off[t + 1] = off[t] + deg[t];
    uint32_t *adj = prw_calloc((size_t)off[nt] + 1, sizeof *adj);
    memset(deg, 0, sizeof *deg * nt);
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && er[j].a == er[i].a && er[j].b == er[i].b) j++;
        for (size_t x = i; x < j; x++)
            for (size_t y = i; y < j; y++)
                if (x != y) adj[off[er[x].tri] + deg[er[x].tri]++] = er[y].tri;
        i = j;
    }
    free(er);
    free(wid);
    /* flood fill */
    int32_t *owner = prw_calloc((size_t)nt + 1, sizeof *owner);
    for (uint32_t t = 0; t < nt; t++) owner[t] = -1;
    uint32_t *queue = prw_calloc((size_t)nt + 1, sizeof *queue);
    for (uint32_t seed = 0; seed < nt; seed++) {
        if (owner[seed] >= 0) continue;
        if (*count == *cap) {
            *cap = *cap ? 2 * *cap : 64;
            *charts = prw_realloc(*charts, sizeof **charts * *cap);
        }
        uint32_t ci = (*count)++;
        chart *ch = &(*charts)[ci];
        memset(ch, 0, sizeof *ch);
        ch->inst = ii;
        const double *n0 = w->ng + 3 * seed;
        uint32_t qh = 0, qt = 0;
        queue[qt++] = seed;
        owner[seed] = (int32_t)ci;
        while (qh < qt) {
            uint32_t t = queue[qh++];
            for (uint32_t k = off[t]; k < off[t + 1]; k++) {
                uint32_t u = adj[k];
                if (owner[u] >= 0 || !(ddot(w->ng + 3 * u, n0) >= CHART_COS)) continue;
                owner[u] = (int32_t)ci;
                queue[qt++] = u;
            }
        }
        ch->tri_count = qt;
        ch->tris = prw_calloc(qt, sizeof(uint32_t));
        memcpy(ch->tris, queue, qt * sizeof(uint32_t));
        /* projection on the plane of the first triangle */
        double n[3] = {n0[0], n0[1], n0[2]}, tx[3], ty[3];
        if (!(ddot(n, n) > 0.5)) n[0] = 0, n[1] = 0, n[2] = 1;
        prw_frame_from_normal(n, tx, ty);
        ch->xy = prw_calloc((size_t)qt * 6, sizeof(double));
        double umin = INFINITY, vmin = INFINITY, umax = -INFINITY, vmax = -INFINITY;
        for (uint32_t i = 0; i < qt; i++)
            for (int k = 0; k < 3; k++) {
                const double *p = w->p + 3 * m->indices[3 * ch->tris[i] + k];
                double u = ddot(p, tx) / texel, v = ddot(p, ty) / texel;
                ch->xy[6 * i + 2 * k] = u, ch->xy[6 * i + 2 * k + 1] = v;
                umin = fmin(umin, u), umax = fmax(umax, u), vmin = fmin(vmin, v), vmax = fmax(vmax, v);
            }
        for (uint32_t i = 0; i < 3 * qt; i++) {
            ch->xy[2 * i] += PRW_GI_PAD - umin;
            ch->xy[2 * i + 1] += PRW_GI_PAD - vmin;
        }
        ch->w = (uint32_t)ceil(fmax(umax - umin, 1e-9)) + 2 * PRW_GI_PAD;
        ch->h = (uint32_t)ceil(fmax(vmax - vmin, 1e-9)) + 2 * PRW_GI_PAD;
    }
    free(queue);
    free(owner);
    free(adj);
    free(off);
    free(deg);
}

/* The mesh's own light-map layout (glTF TEXCOORD_1) as one chart: uv1 scaled to the texel size by
 * the ratio of world to uv1 area, 2 texels of padding around its bounding box.  false (nothing
 * added) without uvs1 or with a degenerate layout (zero uv1 area, non-finite uvs). */
static bool chart_uv1(const winst *w, uint32_t ii, double texel, chart **charts, uint32_t *count, uint32_t *cap)
{
    const prw_mesh *m = w->m;
    if (!m->uvs1) return false;
    uint32_t nt = m->index_count / 3;
    double uv_area = 0, world_area = 0, umin = INFINITY, vmin = INFINITY, umax = -INFINITY, vmax = -INFINITY;
    for (uint32_t t = 0; t < nt; t++) {
        const uint32_t *ix = m->indices + 3 * t;
        const float *a = m->uvs1 + 2 * ix[0], *b = m->uvs1 + 2 * ix[1], *c = m->uvs1 + 2 * ix[2];
        uv_area += 0.5 * fabs((double)(b[0] - a[0]) * (c[1] - a[1]) - (double)(c[0] - a[0]) * (b[1] - a[1]));
        world_area += w->area[t];
        for (int k = 0; k < 3; k++) {
            const float *q = m->uvs1 + 2 * ix[k];
            umin = fmin(umin, q[0]), umax = fmax(umax, q[0]), vmin = fmin(vmin, q[1]), vmax = fmax(vmax, q[1]);
        }
    }
    if (!(uv_area > 1e-12 && world_area > 0 && isfinite(umin + umax + vmin + vmax))) return false;
    double k = sqrt(world_area / uv_area) / texel; /* texels per uv1 unit */
    if (!(k * (umax - umin) < 1e7 && k * (vmax - vmin) < 1e7)) return false;
    if (*count == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        *charts = prw_realloc(*charts, sizeof **charts * *cap);
    }
    chart *ch = &(*charts)[(*count)++];
    memset(ch, 0, sizeof *ch);
    ch->inst = ii;
    ch->tri_count = nt;
    ch->tris = prw_calloc(nt + 1, sizeof(uint32_t));
    ch->xy = prw_calloc((size_t)nt * 6 + 1, sizeof(double));
    for (uint32_t t = 0; t < nt; t++) {
        ch->tris[t] = t;
        for (int c = 0; c < 3; c++) {
            const float *q = m->uvs1 + 2 * m->indices[3 * t + c];
            ch->xy[6 * t + 2 * c] = (q[0] - umin) * k + PRW_GI_PAD;
            ch->xy[6 * t + 2 * c + 1] = (q[1] - vmin) * k + PRW_GI_PAD;
        }
    }
    ch->w = (uint32_t)ceil(fmax((umax - umin) * k, 1e-9)) + 2 * PRW_GI_PAD;
    ch->h = (uint32_t)ceil(fmax((vmax - vmin) * k, 1e-9)) + 2 * PRW_GI_PAD;
    return true;
}

typedef struct chart_order {
    uint32_t h, w, idx;
} chart_order;

/* Tallest first, then widest, then creation order: a deterministic shelf packing. */
static int cmp_chart_h(const void *x, const void *y)
{
    const chart_order *a = x, *b = y;
    if (a->h != b->h) return a->h > b->h ? -1 : 1;
    if (a->w != b->w) return a->w > b->w ? -1 : 1;
    return a->idx < b->idx ? -1 : a->idx > b->idx;
}

/* ---- the bake ---- */

void prw_gi_bake_destroy(prw_gi_bake *b)
{
    if (!b) return;
    for (uint32_t i = 0; i < b->atlas_count; i++) {
        free(b->atlases[i].rgb);
        free(b->atlases[i].var);
        free(b->atlases[i].vis);
        free(b->atlases[i].cone);
        free(b->atlases[i].state);
    }
    for (uint32_t i = 0; i < b->instance_count; i++) {
        free(b->inst[i].uv);
        free(b->inst[i].vertex_rgb);
        free(b->inst[i].vertex_var);
        free(b->inst[i].vertex_vis);
        free(b->inst[i].vertex_cone);
    }
    free(b->atlases);
    free(b->inst);
    free(b);
}

/* A gather point. */
typedef struct gpoint {
    double p[3], n[3];
    const prw_material *mat;
    float *rgb, *var; /* where E and its variance go */
    float *vis;       /* where the environment visibility goes */
    float *cone;      /* where the open cone goes */
    uint8_t *state;   /* the texel's state (NULL for vertices): set to 0 when the point is hidden */
} gpoint;

/* The next free gather point of the growing array (*pts, *np used of *cap). */
static gpoint *push_point(gpoint **pts, size_t *np, size_t *cap)
{
    if (*np == *cap) {
        *cap = *cap ? 2 * *cap : 4096;
        *pts = prw_realloc(*pts, *cap * sizeof **pts);
    }
    return &(*pts)[(*np)++];
}

static double radical_inverse2(uint32_t i)
{
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
    return i * 0x1.0p-32;
}

static uint64_t mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

/* The scene's environment radiance as the path tracer sees it (engine/reference/ref_scene.c: the file's
 * values x scale, negatives and non-finite as 0, nearest texel; uniform: its radiance), for the
 * visibility V of prw_gi.h. */
typedef struct env_map {
    int kind; /* 0 none or black, 1 uniform, 2 map */
    float uniform[3];
    float *rgb;
    int w, h;
    double cr, sr;
} env_map;

static double lum3(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static bool env_load(const prw_environment *se, env_map *m, prw_error *e)
{
    memset(m, 0, sizeof *m);
    if (!se->present) return true;
    m->cr = cos(se->rotation), m->sr = sin(se->rotation);
    if (!se->file[0]) {
        for (int k = 0; k < 3; k++) m->uniform[k] = isfinite(se->uniform[k]) && se->uniform[k] > 0 ? se->uniform[k] : 0;
        m->kind = m->uniform[0] + m->uniform[1] + m->uniform[2] > 0 ? 1 : 0;
        return true;
    }
    prw_exr_read_opts opts = {.reject_nonfinite = false, .extra_bytes_per_pixel = 12};
    prw_image img = {0};
    if (!prw_exr_read(se->file, &opts, &img, e)) return false;
    m->w = img.width, m->h = img.height;
    m->rgb = prw_malloc((size_t)m->w * m->h * 3 * sizeof(float));
    double scale = isfinite(se->scale) && se->scale > 0 ? se->scale : 0;
    for (size_t i = 0; i < (size_t)m->w * m->h; i++)
        for (int k = 0; k < 3; k++) {
            double x = (double)img.rgba[4 * i + k] * scale;
            m->rgb[3 * i + k] = (float)(isfinite(x) && x > 0 ? x : 0);
        }
    prw_image_free(&img);
    m->kind = 2;
    return true;
}

static void env_eval(const env_map *m, const double d[3], double L[3])
{
    L[0] = L[1] = L[2] = 0;
    if (m->kind == 1)
        for (int k = 0; k < 3; k++) L[k] = m->uniform[k];
    if (m->kind != 2) return;
    double x = m->cr * d[0] - m->sr * d[2], y = d[1], z = m->sr * d[0] + m->cr * d[2];
    double u = 0.5 + atan2(x, -z) / (2 * PRW_PI), v = acos(fmax(-1.0, fmin(1.0, y))) / PRW_PI;
    int i = (int)floor(u * m->w), j = (int)floor(v * m->h);
    i = ((i % m->w) + m->w) % m->w;
    j = j < 0 ? 0 : j >= m->h ? m->h - 1 : j;
    for (int k = 0; k < 3; k++) L[k] = m->rgb[3 * ((size_t)j * m->w + i) + k];
}

static bool gather(const prw_scene *s, const prw_gi_options *o, uint32_t N, gpoint *pts, size_t np,
                   prw_gi_progress_fn progress, void *user, double *seconds, uint64_t *hidden, prw_error *e)
{
    if (np == 0) return true;
    double lo[3] = {s->bounds_min.x, s->bounds_min.y, s->bounds_min.z};
    double hi[3] = {s->bounds_max.x, s->bounds_max.y, s->bounds_max.z};
    prw_dvec3 centre = s->has_bounds ? prw_v3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2) : prw_v3(0, 0, 0);
    env_map env;
    if (!env_load(&s->environment, &env, e)) return false;
    prw_ref_renderer *r = NULL;
    if (!prw_ref_create(s, centre, o->threads, &r, e)) {
        free(env.rgb);
        return false;
    }
    size_t chunk = CHUNK_POINTS;
    prw_ref_ray *rays = prw_calloc(chunk * N, sizeof *rays);
    prw_ref_ray_result *res = prw_calloc(chunk * N, sizeof *res);
    prw_ref_ray_result *emi = env.kind ? prw_calloc(chunk * N, sizeof *emi) : NULL;
    double *w = prw_calloc(chunk * N, sizeof *w);
    double t0 = prw_now();
    bool ok = true;
    for (size_t c0 = 0; c0 < np && ok; c0 += chunk) {
        size_t c1 = PRW_MIN(c0 + chunk, np);
        for (size_t i = c0; i < c1; i++) {
            const gpoint *g = &pts[i];
            double tx[3], ty[3];
            prw_frame_from_normal(g->n, tx, ty);
            uint64_t h = mix64(o->seed ^ mix64(i));
            double r1 = (h >> 11) * 0x1.0p-53, r2 = (mix64(h) >> 11) * 0x1.0p-53;
            for (uint32_t j = 0; j < N; j++) {
                double u1 = fmod((j + 0.5) / N + r1, 1.0), u2 = fmod(radical_inverse2(j) + r2, 1.0);
                double rr = sqrt(u1), ph = 2 * PRW_PI * u2, mu = sqrt(fmax(0.0, 1 - u1));
                double lx = rr * cos(ph), ly = rr * sin(ph);
                prw_ref_ray *q = &rays[(i - c0) * N + j];
                double d[3];
                for (int c = 0; c < 3; c++) d[c] = tx[c] * lx + ty[c] * ly + g->n[c] * mu;
                q->origin = prw_v3(g->p[0] + g->n[0] * RAY_OFFSET, g->p[1] + g->n[1] * RAY_OFFSET,
                                   g->p[2] + g->n[2] * RAY_OFFSET);
                q->dir = prw_v3(d[0], d[1], d[2]);
                q->tnear = 0;
                w[(i - c0) * N + j] = prw_gi_weight(g->mat, mu);
            }
        }
        prw_ref_ray_desc d = {.first_index = (uint64_t)c0 * N, .s0 = 0, .s1 = 1, .seed = o->seed,
                              .filter = {PRW_REF_MIN_DEPTH, 1}, .camera = false, .threads = o->threads};
        ok = prw_ref_trace_rays(r, rays, (c1 - c0) * N, &d, res, NULL, NULL, e);
        if (ok && env.kind) { /* the same rays, what they see directly: the environment when they escape */
            prw_ref_ray_desc de = d;
            de.filter = (prw_ref_filter){PRW_REF_EMISSION, 0};
            ok = prw_ref_trace_rays(r, rays, (c1 - c0) * N, &de, emi, NULL, NULL, e);
        }
        for (size_t i = c0; i < c1 && ok; i++) {
            /* a texel whose rays mostly start under or inside closed geometry (the floor under a box,
               a face covered by another) is not a visible surface: left to the dilation */
            uint64_t backs = 0;
            for (uint32_t j = 0; j < N; j++) backs += res[(i - c0) * N + j].back_faces;
            if (pts[i].state && backs * 4 > N) {
                *pts[i].state = 0;
                (*hidden)++;
                continue;
            }
            for (int c = 0; c < 3; c++) {
                double sum = 0, sq = 0;
                for (uint32_t j = 0; j < N; j++) {
                    double v = PRW_PI * w[(i - c0) * N + j] * res[(i - c0) * N + j].mean[c];
                    sum += v;
                    sq += v * v;
                }
                double mean = sum / N;
                double var = N > 1 ? fmax(sq / N - mean * mean, 0.0) / (N - 1) : 0;
                pts[i].rgb[c] = (float)mean;
                pts[i].var[c] = (float)var;
            }
            double seen = 0, all = 0, open = 0, bsum[3] = {0, 0, 0};
            for (uint32_t j = 0; j < N && env.kind; j++) {
                const prw_ref_ray *q = &rays[(i - c0) * N + j];
                double dir[3] = {q->dir.x, q->dir.y, q->dir.z}, L[3];
                env_eval(&env, dir, L);
                const double *got = emi[(i - c0) * N + j].mean;
                bool escaped = true;
                for (int c = 0; c < 3; c++) escaped = escaped && fabs(got[c] - L[c]) <= 1e-5 * L[c] + 1e-9; /* fixed point: 2^-32 */
                double y = lum3(L);
                all += y;
                if (escaped) {
                    seen += y;
                    open += 1;
                    for (int c = 0; c < 3; c++) bsum[c] += dir[c];
                }
            }
            *pts[i].vis = all > 0 ? (float)fmin(1.0, seen / all) : 1.0f;
            if (pts[i].cone) {
                for (int c = 0; c < 3; c++) pts[i].cone[c] = env.kind ? (float)(bsum[c] / N) : (float)pts[i].n[c];
                pts[i].cone[3] = env.kind ? (float)(open / N) : 1.0f;
            }
        }
        if (progress && ok) {
            char line[160];
            double el = prw_now() - t0, f = (double)c1 / (double)np;
            snprintf(line, sizeof line, "gi: %zu of %zu points, %.1f s, eta %.1f s", c1, np, el, el / f - el);
            progress(user, f, line);
        }
    }
    *seconds = prw_now() - t0;
    free(rays);
    free(res);
    free(emi);
    free(env.rgb);
    free(w);
    prw_ref_destroy(r);
    return ok;
}

bool prw_gi_build(const prw_scene *s, const prw_gi_options *opt, prw_gi_progress_fn progress, void *user,
                  prw_gi_bake **out, prw_error *e)
{
    *out = NULL;
    prw_gi_options o = *opt;
    if (o.radiosity_size == 0) o.radiosity_size = PRW_GI_DEFAULT_RADIOSITY_SIZE;
    if (o.samples == 0) o.samples = PRW_GI_DEFAULT_SAMPLES;
    if (o.samples > 65536 || o.radiosity_size > 16384 || o.filter_radius > 8)
        return prw_fail(e, "gi bake: samples %u (1..65536), radiosity_size %u (1..16384) or filter radius %u (0..8) out "
                           "of range", o.samples, o.radiosity_size, o.filter_radius);
    /* instances */
    uint32_t ni = 0;
    for (uint32_t n = 0; n < s->node_count; n++)
        if (s->nodes[n].mesh_group >= 0) ni += s->groups[s->nodes[n].mesh_group].count;
    if (ni == 0) return prw_fail(e, "%s: gi bake: the scene has no mesh to bake", s->source[0] ? s->source : "(scene)");
    prw_gi_bake *b = prw_calloc(1, sizeof *b);
    b->inst = prw_calloc(ni, sizeof *b->inst);
    b->instance_count = ni;
    winst *wi = prw_calloc(ni, sizeof *wi);
    uint32_t k = 0;
    double area_all = 0;
    for (uint32_t n = 0; n < s->node_count; n++) {
        const prw_node *nd = &s->nodes[n];
        if (nd->mesh_group < 0) continue;
        const prw_mesh_group *g = &s->groups[nd->mesh_group];
        for (uint32_t mi = g->first; mi < g->first + g->count; mi++, k++) {
            const prw_mesh *m = &s->meshes[mi];
            prw_gi_instance *in = &b->inst[k];
            in->node = n, in->mesh = mi;
            winst_make(s, nd, m, &wi[k]);
            const prw_material *mt = wi[k].mat;
            bool diffuse = mt->metallic < 1 && fmaxf(mt->base_color[0], fmaxf(mt->base_color[1], mt->base_color[2])) > 0;
            /* with an environment every surface needs its visibility (prw_gi.h) */
            in->mode = (diffuse || s->environment.present) && m->index_count >= 3 ? PRW_GI_ATLAS : PRW_GI_NONE;
            if (in->mode)
                for (uint32_t t = 0; t < m->index_count / 3; t++) area_all += wi[k].area[t];
        }
    }
    if (!(area_all > 0)) {
        for (uint32_t i = 0; i < ni; i++) winst_free(&wi[i]);
        free(wi);
        prw_gi_bake_destroy(b);
        return prw_fail(e, "%s: gi bake: no diffuse surface to bake", s->source[0] ? s->source : "(scene)");
    }
    double t0 = sqrt(area_all) / o.radiosity_size, area_atlas = 0;
    for (uint32_t i = 0; i < ni; i++) {
        if (!b->inst[i].mode) continue;
        double a = 0;
        for (uint32_t t = 0; t < wi[i].m->index_count / 3; t++) a += wi[i].area[t];
        if (!wi[i].m->uvs1 && sqrt(a / wi[i].m->vertex_count) <= t0) b->inst[i].mode = PRW_GI_VERTEX;
        else area_atlas += a;
    }
    double texel = area_atlas > 0 ? sqrt(area_atlas) / o.radiosity_size : t0;
    b->texel_size = texel;
    b->samples = o.samples;
    /* charts */
    chart *charts = NULL;
    uint32_t nch = 0, cap = 0;
    for (uint32_t i = 0; i < ni; i++)
        if (b->inst[i].mode == PRW_GI_ATLAS && !chart_uv1(&wi[i], i, texel, &charts, &nch, &cap))
            make_charts(&wi[i], i, texel, &charts, &nch, &cap);
    b->charts = nch;
    /* shelf packing */
    chart_order *order = prw_calloc((size_t)nch + 1, sizeof *order);
    for (uint32_t i = 0; i < nch; i++) order[i] = (chart_order){charts[i].h, charts[i].w, i};
    qsort(order, nch, sizeof *order, cmp_chart_h);
    uint32_t atlas = 0, x = 0, y = 0, shelf = 0;
    uint32_t heights[PRW_GI_MAX_ATLASES] = {0};
    bool ok = true;
    for (uint32_t oi = 0; oi < nch && ok; oi++) {
        chart *c = &charts[order[oi].idx];
        if (c->w > PRW_GI_ATLAS_W || c->h > PRW_GI_ATLAS_W) {
            ok = prw_fail(e, "%s: gi bake: a chart of mesh '%s' is %ux%u texels, more than the %ux%u atlas (texel size "
                             "%.4g m: lower radiosity_size)", s->source[0] ? s->source : "(scene)",
                          s->meshes[b->inst[c->inst].mesh].name, c->w, c->h, PRW_GI_ATLAS_W, PRW_GI_ATLAS_W, texel);
            break;
        }
        if (x + c->w > PRW_GI_ATLAS_W) y += shelf, x = 0, shelf = 0;
        if (y + c->h > PRW_GI_ATLAS_W) {
            atlas++, x = 0, y = 0, shelf = 0;
            if (atlas >= PRW_GI_MAX_ATLASES) {
                ok = prw_fail(e, "%s: gi bake: the light maps need more than %d atlases of %ux%u (texel size %.4g m: "
                                 "lower radiosity_size)", s->source[0] ? s->source : "(scene)", PRW_GI_MAX_ATLASES,
                              PRW_GI_ATLAS_W, PRW_GI_ATLAS_W, texel);
                break;
            }
        }
        c->atlas = atlas, c->x0 = x, c->y0 = y;
        x += c->w;
        shelf = PRW_MAX(shelf, c->h);
        heights[atlas] = PRW_MAX(heights[atlas], y + c->h);
    }
    free(order);
    gpoint *pts = NULL;
    size_t np = 0;
    if (ok && nch) {
        b->atlas_count = atlas + 1;
        b->atlases = prw_calloc(b->atlas_count, sizeof *b->atlases);
        uint64_t texels = 0;
        for (uint32_t a = 0; a < b->atlas_count; a++) texels += (uint64_t)PRW_GI_ATLAS_W * heights[a];
        ok = prw_mem_check(prw_mul_sat(texels, 25), "gi bake", "the light-map atlases", e);
        for (uint32_t a = 0; a < b->atlas_count && ok; a++) {
            prw_gi_atlas *A = &b->atlases[a];
            A->width = PRW_GI_ATLAS_W, A->height = heights[a];
            A->rgb = prw_calloc((size_t)A->width * A->height * 3, sizeof(float));
            A->var = prw_calloc((size_t)A->width * A->height * 3, sizeof(float));
            A->vis = prw_calloc((size_t)A->width * A->height, sizeof(float));
            A->cone = prw_calloc((size_t)A->width * A->height * 4, sizeof(float));
            A->state = prw_calloc((size_t)A->width * A->height, 1);
        }
    }
    /* light-map uvs and sampled texels */
    size_t pcap = 0;
    for (uint32_t ci = 0; ci < nch && ok; ci++) {
        chart *c = &charts[ci];
        prw_gi_instance *in = &b->inst[c->inst];
        const winst *w = &wi[c->inst];
        prw_gi_atlas *A = &b->atlases[c->atlas];
        in->atlas = c->atlas;
        if (!in->uv) {
            in->triangle_count = w->m->index_count / 3;
            in->uv = prw_calloc((size_t)in->triangle_count * 6, sizeof(float));
        }
        for (uint32_t i = 0; i < c->tri_count; i++)
            for (int kk = 0; kk < 3; kk++) {
                in->uv[6 * c->tris[i] + 2 * kk] = (float)((c->x0 + c->xy[6 * i + 2 * kk]) / A->width);
                in->uv[6 * c->tris[i] + 2 * kk + 1] = (float)((c->y0 + c->xy[6 * i + 2 * kk + 1]) / A->height);
            }
        size_t first = np;
        double best_area = -1;
        uint32_t best = 0;
        for (uint32_t i = 0; i < c->tri_count; i++) {
            const double *q = c->xy + 6 * i;
            uint32_t t = c->tris[i];
            if (w->area[t] > best_area) best_area = w->area[t], best = i;
            double det = (q[2] - q[0]) * (q[5] - q[1]) - (q[4] - q[0]) * (q[3] - q[1]);
            if (!(fabs(det) > 1e-12)) continue;
            int xa = (int)floor(fmin(q[0], fmin(q[2], q[4]))), xb = (int)ceil(fmax(q[0], fmax(q[2], q[4])));
            int ya = (int)floor(fmin(q[1], fmin(q[3], q[5]))), yb = (int)ceil(fmax(q[1], fmax(q[3], q[5])));
            for (int ty = PRW_MAX(ya, 0); ty < PRW_MIN(yb, (int)c->h); ty++)
                for (int tx = PRW_MAX(xa, 0); tx < PRW_MIN(xb, (int)c->w); tx++) {
                    double px = tx + 0.5, py = ty + 0.5;
                    double b1 = ((px - q[0]) * (q[5] - q[1]) - (q[4] - q[0]) * (py - q[1])) / det;
                    double b2 = ((q[2] - q[0]) * (py - q[1]) - (px - q[0]) * (q[3] - q[1])) / det;
                    double b0 = 1 - b1 - b2;
                    if (b0 < -1e-9 || b1 < -1e-9 || b2 < -1e-9) continue;
                    size_t ti = (size_t)(c->y0 + ty) * A->width + c->x0 + tx;
                    if (A->state[ti]) continue;
                    A->state[ti] = 1;
                    gpoint *g = push_point(&pts, &np, &pcap);
                    const uint32_t *ix = w->m->indices + 3 * t;
                    for (int cc = 0; cc < 3; cc++) {
                        g->p[cc] = b0 * w->p[3 * ix[0] + cc] + b1 * w->p[3 * ix[1] + cc] + b2 * w->p[3 * ix[2] + cc];
                        g->n[cc] = w->ng[3 * t + cc];
                    }
                    g->mat = w->mat;
                    g->rgb = A->rgb + 3 * ti;
                    g->var = A->var + 3 * ti;
                    g->vis = A->vis + ti;
                    g->cone = A->cone + 4 * ti;
                    g->state = A->state + ti;
                }
        }
        if (np == first) { /* no texel centre inside: one sample at the largest triangle's centroid */
            const double *q = c->xy + 6 * best;
            int tx = PRW_MIN((int)((q[0] + q[2] + q[4]) / 3), (int)c->w - 1);
            int ty = PRW_MIN((int)((q[1] + q[3] + q[5]) / 3), (int)c->h - 1);
            size_t ti = (size_t)(c->y0 + ty) * A->width + c->x0 + tx;
            if (!A->state[ti] && w->area[c->tris[best]] > 0) {
                A->state[ti] = 1;
                gpoint *g = push_point(&pts, &np, &pcap);
                const uint32_t *ix = w->m->indices + 3 * c->tris[best];
                for (int cc = 0; cc < 3; cc++) {
                    g->p[cc] = (w->p[3 * ix[0] + cc] + w->p[3 * ix[1] + cc] + w->p[3 * ix[2] + cc]) / 3;
                    g->n[cc] = w->ng[3 * c->tris[best] + cc];
                }
                g->mat = w->mat;
                g->rgb = A->rgb + 3 * ti;
                g->var = A->var + 3 * ti;
                g->vis = A->vis + ti;
                g->cone = A->cone + 4 * ti;
                g->state = A->state + ti;
            }
        }
    }
    b->sampled_texels = np;
    /* vertices */
    for (uint32_t i = 0; i < ni && ok; i++) {
        prw_gi_instance *in = &b->inst[i];
        if (in->mode != PRW_GI_VERTEX) continue;
        in->vertex_count = wi[i].m->vertex_count;
        in->vertex_rgb = prw_calloc((size_t)in->vertex_count * 3, sizeof(float));
        in->vertex_var = prw_calloc((size_t)in->vertex_count * 3, sizeof(float));
        in->vertex_vis = prw_calloc((size_t)in->vertex_count, sizeof(float));
        in->vertex_cone = prw_calloc((size_t)in->vertex_count * 4, sizeof(float));
        for (uint32_t v = 0; v < in->vertex_count; v++) {
            gpoint *g = push_point(&pts, &np, &pcap);
            memcpy(g->p, wi[i].p + 3 * v, sizeof g->p);
            memcpy(g->n, wi[i].vn + 3 * v, sizeof g->n);
            if (!(ddot(g->n, g->n) > 0.5)) g->n[0] = 0, g->n[1] = 1, g->n[2] = 0;
            g->mat = wi[i].mat;
            g->rgb = in->vertex_rgb + 3 * v;
            g->var = in->vertex_var + 3 * v;
            g->vis = in->vertex_vis + v;
            g->cone = in->vertex_cone + 4 * v;
            g->state = NULL;
            b->sampled_vertices++;
        }
    }
    if (ok) ok = gather(s, &o, o.samples, pts, np, progress, user, &b->seconds_gather, &b->hidden_texels, e);
    free(pts);
    /* optional box filter over the sampled texels of each chart */
    for (uint32_t ci = 0; ci < nch && ok && o.filter_radius > 0; ci++) {
        chart *c = &charts[ci];
        prw_gi_atlas *A = &b->atlases[c->atlas];
        size_t cn = (size_t)c->w * c->h;
        float *src = prw_calloc(cn * 11 + 1, sizeof(float));
        for (uint32_t ty = 0; ty < c->h; ty++)
            for (uint32_t tx = 0; tx < c->w; tx++) {
                size_t ti = (size_t)(c->y0 + ty) * A->width + c->x0 + tx, li = (size_t)ty * c->w + tx;
                memcpy(src + 11 * li, A->rgb + 3 * ti, 3 * sizeof(float));
                memcpy(src + 11 * li + 3, A->var + 3 * ti, 3 * sizeof(float));
                src[11 * li + 6] = A->vis[ti];
                memcpy(src + 11 * li + 7, A->cone + 4 * ti, 4 * sizeof(float));
            }
        int R = (int)o.filter_radius;
        for (int ty = 0; ty < (int)c->h; ty++)
            for (int tx = 0; tx < (int)c->w; tx++) {
                size_t ti = (size_t)(c->y0 + ty) * A->width + c->x0 + tx;
                if (A->state[ti] != 1) continue;
                double sum[3] = {0, 0, 0}, var[3] = {0, 0, 0}, vis = 0, cone[4] = {0, 0, 0, 0};
                int n = 0;
                for (int dy = -R; dy <= R; dy++)
                    for (int dx = -R; dx <= R; dx++) {
                        int x = tx + dx, y = ty + dy;
                        if (x < 0 || y < 0 || x >= (int)c->w || y >= (int)c->h) continue;
                        if (A->state[(size_t)(c->y0 + y) * A->width + c->x0 + x] != 1) continue;
                        const float *q = src + 11 * ((size_t)y * c->w + x);
                        for (int k2 = 0; k2 < 3; k2++) sum[k2] += q[k2], var[k2] += q[3 + k2];
                        vis += q[6];
                        for (int k2 = 0; k2 < 4; k2++) cone[k2] += q[7 + k2];
                        n++;
                    }
                for (int k2 = 0; k2 < 3; k2++) {
                    A->rgb[3 * ti + k2] = (float)(sum[k2] / n);
                    A->var[3 * ti + k2] = (float)(var[k2] / ((double)n * n));
                }
                A->vis[ti] = (float)(vis / n);
                for (int k2 = 0; k2 < 4; k2++) A->cone[4 * ti + k2] = (float)(cone[k2] / n);
            }
        free(src);
    }
    /* dilation: per chart, breadth-first from its sampled texels over its rectangle (8-neighbours) */
    uint32_t *queue = NULL;
    size_t qcap = 0;
    for (uint32_t ci = 0; ci < nch && ok; ci++) {
        chart *c = &charts[ci];
        prw_gi_atlas *A = &b->atlases[c->atlas];
        size_t need = (size_t)c->w * c->h;
        if (need > qcap) {
            free(queue);
            qcap = need;
            queue = prw_calloc(qcap, sizeof *queue);
        }
        size_t qh = 0, qt = 0;
        for (uint32_t ty = 0; ty < c->h; ty++)
            for (uint32_t tx = 0; tx < c->w; tx++)
                if (A->state[(size_t)(c->y0 + ty) * A->width + c->x0 + tx] == 1) queue[qt++] = ty * c->w + tx;
        while (qh < qt) {
            uint32_t cur = queue[qh++], cx = cur % c->w, cy = cur / c->w;
            size_t src = (size_t)(c->y0 + cy) * A->width + c->x0 + cx;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int nx = (int)cx + dx, ny = (int)cy + dy;
                    if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= (int)c->w || ny >= (int)c->h) continue;
                    size_t dst = (size_t)(c->y0 + ny) * A->width + c->x0 + nx;
                    if (A->state[dst]) continue;
                    A->state[dst] = 2;
                    memcpy(A->rgb + 3 * dst, A->rgb + 3 * src, 3 * sizeof(float));
                    memcpy(A->var + 3 * dst, A->var + 3 * src, 3 * sizeof(float));
                    A->vis[dst] = A->vis[src];
                    memcpy(A->cone + 4 * dst, A->cone + 4 * src, 4 * sizeof(float));
                    queue[qt++] = (uint32_t)(ny * c->w + nx);
                }
        }
    }
    free(queue);
    for (uint32_t ci = 0; ci < nch; ci++) {
        free(charts[ci].tris);
        free(charts[ci].xy);
    }
    free(charts);
    for (uint32_t i = 0; i < ni; i++) winst_free(&wi[i]);
    free(wi);
    if (!ok) {
        prw_gi_bake_destroy(b);
        return false;
    }
    *out = b;
    return true;
}

bool prw_gi_lookup(const prw_gi_bake *b, const prw_scene *s, uint32_t i, uint32_t tri, double b1, double b2,
                   double out[3])
{
    out[0] = out[1] = out[2] = 0;
    if (i >= b->instance_count) return false;
    const prw_gi_instance *in = &b->inst[i];
    double b0 = 1 - b1 - b2;
    if (in->mode == PRW_GI_ATLAS && tri < in->triangle_count && in->atlas < b->atlas_count) {
        const prw_gi_atlas *A = &b->atlases[in->atlas];
        const float *uv = in->uv + 6 * (size_t)tri;
        double u = b0 * uv[0] + b1 * uv[2] + b2 * uv[4], v = b0 * uv[1] + b1 * uv[3] + b2 * uv[5];
        double x = u * A->width - 0.5, y = v * A->height - 0.5;
        double fx0 = floor(x), fy0 = floor(y), fx = x - fx0, fy = y - fy0;
        for (int dy = 0; dy < 2; dy++)
            for (int dx = 0; dx < 2; dx++) {
                long xi = PRW_MIN(PRW_MAX((long)fx0 + dx, 0L), (long)A->width - 1);
                long yi = PRW_MIN(PRW_MAX((long)fy0 + dy, 0L), (long)A->height - 1);
                double wgt = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
                for (int c = 0; c < 3; c++) out[c] += wgt * A->rgb[3 * ((size_t)yi * A->width + xi) + c];
            }
        return true;
    }
    if (in->mode == PRW_GI_VERTEX && in->mesh < s->mesh_count) {
        const prw_mesh *m = &s->meshes[in->mesh];
        if (tri >= m->index_count / 3 || m->vertex_count != in->vertex_count) return false;
        const uint32_t *ix = m->indices + 3 * (size_t)tri;
        const double w3[3] = {b0, b1, b2};
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) out[c] += w3[k] * in->vertex_rgb[3 * ix[k] + c];
        return true;
    }
    return false;
}

/* ---- vertex split for drawing ---- */

typedef struct corner_rec {
    uint32_t v, ub, vb, corner;
} corner_rec;

static int cmp_corner(const void *x, const void *y)
{
    const corner_rec *a = x, *b = y;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    if (a->ub != b->ub) return a->ub < b->ub ? -1 : 1;
    if (a->vb != b->vb) return a->vb < b->vb ? -1 : 1;
    return a->corner < b->corner ? -1 : a->corner > b->corner;
}

void prw_gi_split_free(prw_gi_split *sp)
{
    if (!sp) return;
    free(sp->source);
    free(sp->uv);
    free(sp->indices);
    memset(sp, 0, sizeof *sp);
}

bool prw_gi_split_vertices(const prw_gi_bake *b, const prw_scene *s, uint32_t i, prw_gi_split *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (i >= b->instance_count || b->inst[i].mode != PRW_GI_ATLAS)
        return prw_fail(e, "gi: instance %u has no light-map uvs (not an atlas instance)", i);
    const prw_gi_instance *in = &b->inst[i];
    if (in->mesh >= s->mesh_count || s->meshes[in->mesh].index_count / 3 != in->triangle_count)
        return prw_fail(e, "gi: instance %u does not match the scene's mesh %u (another scene or a stale bake)", i,
                        in->mesh);
    const prw_mesh *m = &s->meshes[in->mesh];
    uint32_t nc = in->triangle_count * 3;
    corner_rec *cr = prw_calloc((size_t)nc + 1, sizeof *cr);
    for (uint32_t c = 0; c < nc; c++) {
        cr[c].v = m->indices[c];
        memcpy(&cr[c].ub, &in->uv[2 * c], 4);
        memcpy(&cr[c].vb, &in->uv[2 * c + 1], 4);
        cr[c].corner = c;
    }
    qsort(cr, nc, sizeof *cr, cmp_corner);
    out->index_count = nc;
    out->indices = prw_calloc((size_t)nc + 1, sizeof(uint32_t));
    out->source = prw_calloc((size_t)nc + 1, sizeof(uint32_t));
    out->uv = prw_calloc((size_t)nc * 2 + 2, sizeof(float));
    uint32_t nv = 0;
    for (uint32_t c = 0; c < nc; c++) {
        if (c == 0 || cmp_corner(&(corner_rec){cr[c].v, cr[c].ub, cr[c].vb, 0}, &(corner_rec){cr[c - 1].v, cr[c - 1].ub, cr[c - 1].vb, 0}) != 0) {
            out->source[nv] = cr[c].v;
            out->uv[2 * nv] = in->uv[2 * cr[c].corner];
            out->uv[2 * nv + 1] = in->uv[2 * cr[c].corner + 1];
            nv++;
        }
        out->indices[cr[c].corner] = nv - 1;
    }
    out->vertex_count = nv;
    free(cr);
    return true;
}
