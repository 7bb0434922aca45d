/* btf_synth.c — synthetic BTFs measured by the path tracer (prw_btf_synth.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_synth.h"
#include "prw_math.h"
#include "prw_reference.h"
#include "prw_scene.h"

static const char *const names[PRW_BTF_SYNTH_COUNT] = {"fabric", "leather", "flakes", "brushed"};

bool prw_btf_synth_parse(const char *name, prw_btf_synth_kind *out)
{
    for (int k = 0; k < PRW_BTF_SYNTH_COUNT; k++)
        if (strcmp(name, names[k]) == 0) return (*out = (prw_btf_synth_kind)k), true;
    return false;
}

const char *prw_btf_synth_name(prw_btf_synth_kind k) { return k < PRW_BTF_SYNTH_COUNT ? names[k] : "?"; }

/* ---- the micro-geometry, in texel units (x, y on the plane, h up) ---- */

#define FABRIC_P 8.0 /* weave period, texels */

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static double hash01(uint64_t seed, int64_t a, int64_t b)
{
    return (double)(mix64(seed ^ mix64((uint64_t)a * 0x9E3779B97F4A7C15ull ^ (uint64_t)b)) >> 11) * 0x1.0p-53;
}

typedef struct geo {
    prw_btf_synth_kind kind;
    uint64_t seed;
    uint32_t size;   /* the tile the texture repeats with (texels) */
    double top;      /* highest point, texels */
} geo;

/* plain weave: the highest yarn surface at (x, y) and which yarn family it is (0 warp, 1 weft) */
static double fabric_h(double x, double y, int *mat)
{
    const double P = FABRIC_P, A = P / 8, a = P / 4, b = P / 4;
    double best = -1e30;
    int which = 0;
    for (int k = -1; k <= 2; k++) { /* warp yarns along y, centres at x = P/4 + k P/2 */
        double xc = P / 4 + k * P / 2, dx = fmod(x, P) - xc;
        if (fabs(dx) >= a) continue;
        double z = A * cos(2 * PRW_PI * (y - P / 4) / P) * ((k & 1) ? -1 : 1) + b / a * sqrt(a * a - dx * dx);
        if (z > best) best = z, which = 0;
    }
    for (int j = -1; j <= 2; j++) { /* weft yarns along x, centres at y = P/4 + j P/2 */
        double yc = P / 4 + j * P / 2, dy = fmod(y, P) - yc;
        if (fabs(dy) >= a) continue;
        double z = -A * cos(2 * PRW_PI * (x - P / 4) / P) * ((j & 1) ? -1 : 1) + b / a * sqrt(a * a - dy * dy);
        if (z > best) best = z, which = 1;
    }
    if (mat) *mat = which;
    return best > -1e29 ? best : -A;
}

/* periodic value noise: cell size `cell` texels, period `per` texels, smoothstep interpolation */
static double noise(uint64_t seed, double x, double y, double cell, int64_t per_cells)
{
    double fx = x / cell, fy = y / cell;
    int64_t ix = (int64_t)floor(fx), iy = (int64_t)floor(fy);
    double tx = fx - (double)ix, ty = fy - (double)iy;
    tx = tx * tx * (3 - 2 * tx), ty = ty * ty * (3 - 2 * ty);
    int64_t x0 = ((ix % per_cells) + per_cells) % per_cells, y0 = ((iy % per_cells) + per_cells) % per_cells;
    int64_t x1 = (x0 + 1) % per_cells, y1 = (y0 + 1) % per_cells;
    double a = hash01(seed, x0, y0), b = hash01(seed, x1, y0), c = hash01(seed, x0, y1), d = hash01(seed, x1, y1);
    return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
}

static double height(const geo *g, double x, double y, int *mat)
{
    if (mat) *mat = 0;
    switch (g->kind) {
    case PRW_BTF_SYNTH_FABRIC: return fabric_h(x, y, mat);
    case PRW_BTF_SYNTH_LEATHER: {
        int64_t n16 = (int64_t)((g->size + 15) / 16), n4 = (int64_t)((g->size + 3) / 4);
        return 0.45 * noise(g->seed, x, y, 16.0, n16 ? n16 : 1) + 0.15 * noise(g->seed + 1, x, y, 4.0, n4 ? n4 : 1);
    }
    case PRW_BTF_SYNTH_BRUSHED: {
        int64_t row = (int64_t)floor(y);
        double depth = 0.15 * hash01(g->seed, 7, ((row % (int64_t)g->size) + (int64_t)g->size) % (int64_t)g->size);
        double s = sin(PRW_PI * (y - (double)row));
        return -depth * s * s;
    }
    default: return 0;
    }
}

/* ---- building the scene ---- */

typedef struct mesh_buf {
    float *pos, *nrm, *uv;
    uint32_t *idx;
    uint32_t nv, ni, cap_v, cap_i;
} mesh_buf;

static uint32_t add_vertex(mesh_buf *m, const double p[3], const double n[3])
{
    if (m->nv == m->cap_v) {
        m->cap_v = m->cap_v ? 2 * m->cap_v : 1024;
        m->pos = prw_realloc(m->pos, sizeof(float) * 3 * m->cap_v);
        m->nrm = prw_realloc(m->nrm, sizeof(float) * 3 * m->cap_v);
        m->uv = prw_realloc(m->uv, sizeof(float) * 2 * m->cap_v);
    }
    for (int k = 0; k < 3; k++) m->pos[3 * m->nv + k] = (float)p[k], m->nrm[3 * m->nv + k] = (float)n[k];
    m->uv[2 * m->nv] = m->uv[2 * m->nv + 1] = 0;
    return m->nv++;
}

static void add_tri(mesh_buf *m, uint32_t a, uint32_t b, uint32_t c)
{
    if (m->ni + 3 > m->cap_i) {
        m->cap_i = m->cap_i ? 2 * m->cap_i : 3072;
        m->idx = prw_realloc(m->idx, sizeof(uint32_t) * m->cap_i);
    }
    m->idx[m->ni++] = a, m->idx[m->ni++] = b, m->idx[m->ni++] = c;
}

static void buf_free(mesh_buf *m) { free(m->pos), free(m->nrm), free(m->uv), free(m->idx); }

/* frame (x, y, h) in texels -> world metres (x, h, -y) */
static void to_world(double x, double y, double h, double tau, double out[3])
{
    out[0] = x * tau, out[1] = h * tau, out[2] = -y * tau;
}

/* A height-field grid over [x0, x1] x [y0, y1] texels, r vertices per texel, split into nmat meshes by
 * the material at each triangle's centroid. */
static void height_field(const geo *g, double x0, double x1, double y0, double y1, int r, double tau, mesh_buf *bufs,
                         int nmat)
{
    uint32_t nx = (uint32_t)((x1 - x0) * r) + 1, ny = (uint32_t)((y1 - y0) * r) + 1;
    uint32_t *vid = prw_malloc(sizeof(uint32_t) * nx * ny * (size_t)nmat);
    for (int m = 0; m < nmat; m++)
        for (size_t i = 0; i < (size_t)nx * ny; i++) vid[(size_t)m * nx * ny + i] = UINT32_MAX;
    double d = 1.0 / (4.0 * r);
    for (uint32_t j = 0; j + 1 < ny; j++)
        for (uint32_t i = 0; i + 1 < nx; i++) {
            double cx = x0 + (i + 0.5) / r, cy = y0 + (j + 0.5) / r;
            int mat = 0;
            height(g, cx, cy, &mat);
            if (mat >= nmat) mat = 0;
            uint32_t c[4];
            const uint32_t ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
            for (int q = 0; q < 4; q++) {
                size_t key = (size_t)mat * nx * ny + (size_t)cj[q] * nx + ci[q];
                if (vid[key] == UINT32_MAX) {
                    double x = x0 + (double)ci[q] / r, y = y0 + (double)cj[q] / r;
                    double h = height(g, x, y, NULL);
                    double hx = (height(g, x + d, y, NULL) - height(g, x - d, y, NULL)) / (2 * d);
                    double hy = (height(g, x, y + d, NULL) - height(g, x, y - d, NULL)) / (2 * d);
                    double p[3], n[3] = {-hx, 1, hy}, l = sqrt(hx * hx + 1 + hy * hy);
                    for (int k = 0; k < 3; k++) n[k] /= l;
                    to_world(x, y, h, tau, p);
                    vid[key] = add_vertex(&bufs[mat], p, n);
                }
                c[q] = vid[key];
            }
            /* (i, j) -> (i + 1, j) -> (i + 1, j + 1): counter-clockwise seen from +Y */
            add_tri(&bufs[mat], c[0], c[1], c[2]);
            add_tri(&bufs[mat], c[0], c[2], c[3]);
        }
    free(vid);
}

/* 2 % of the tile's texels (those of the lowest hashes, exactly round(0.02 N)) hold a flake: a
 * 1-texel quad tilted up to 15 degrees, 0.15 texel above the base plane; the flakes repeat with the
 * tile over the margin. */
static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static void flakes(const geo *g, double x0, double x1, double y0, double y1, double tau, mesh_buf *m)
{
    uint64_t n = (uint64_t)g->size * g->size, want = (uint64_t)llround(0.02 * (double)n);
    uint64_t *key = prw_malloc(sizeof(uint64_t) * n);
    for (uint64_t t = 0; t < n; t++) key[t] = mix64(g->seed ^ mix64(t + 11)) & ~0xffffffffull, key[t] |= t;
    qsort(key, n, sizeof *key, cmp_u64);
    for (uint64_t f = 0; f < want; f++) {
        uint64_t t = key[f] & 0xffffffffull;
        double cos_max = cos(15.0 * PRW_PI / 180.0);
        double ct = 1 - hash01(g->seed, 12, (int64_t)t) * (1 - cos_max), st = sqrt(1 - ct * ct);
        double ph = 2 * PRW_PI * hash01(g->seed, 13, (int64_t)t);
        double nf[3] = {st * cos(ph), st * sin(ph), ct}; /* frame (x, y, z) */
        /* tangent a = normalize((1, 0, 0) projected on the flake), b = n x a */
        double a[3] = {1 - nf[0] * nf[0], -nf[0] * nf[1], -nf[0] * nf[2]}, la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (int k = 0; k < 3; k++) a[k] /= la;
        double b[3] = {nf[1] * a[2] - nf[2] * a[1], nf[2] * a[0] - nf[0] * a[2], nf[0] * a[1] - nf[1] * a[0]};
        for (int64_t oy = -1; oy <= 1; oy++)
            for (int64_t ox = -1; ox <= 1; ox++) {
                double cx = (double)(t % g->size) + 0.5 + (double)ox * g->size, cy = (double)(t / g->size) + 0.5 + (double)oy * g->size;
                if (cx < x0 - 1 || cx > x1 + 1 || cy < y0 - 1 || cy > y1 + 1) continue;
                uint32_t v[4];
                const double sa[4] = {-0.5, 0.5, 0.5, -0.5}, sb[4] = {-0.5, -0.5, 0.5, 0.5};
                double wn[3] = {nf[0], nf[2], -nf[1]};
                for (int q = 0; q < 4; q++) {
                    double px = cx + sa[q] * a[0] + sb[q] * b[0], py = cy + sa[q] * a[1] + sb[q] * b[1];
                    double ph2 = 0.15 + sa[q] * a[2] + sb[q] * b[2], p[3];
                    to_world(px, py, ph2, tau, p);
                    v[q] = add_vertex(m, p, wn);
                }
                /* a x b = n (frame, right-handed): counter-clockwise seen along -n */
                add_tri(m, v[0], v[1], v[2]);
                add_tri(m, v[0], v[2], v[3]);
            }
    }
    free(key);
}

static prw_material mat(float r, float g, float b, float metallic, float rough, float coat)
{
    prw_material m = prw_material_default();
    m.base_color[0] = r, m.base_color[1] = g, m.base_color[2] = b, m.base_color[3] = 1;
    m.metallic = metallic, m.roughness = rough;
    m.clearcoat = coat;
    m.clearcoat_roughness = coat > 0 ? (float)sqrt(0.05) : 0; /* GGX alpha 0.05 = roughness^2 */
    return m;
}

static bool add_buf(prw_scene *s, mesh_buf *b, int material, const char *name, prw_error *e)
{
    if (!b->ni) return true;
    prw_mesh m = {0};
    snprintf(m.name, sizeof m.name, "%s", name);
    m.vertex_count = b->nv, m.index_count = b->ni;
    m.positions = b->pos, m.normals = b->nrm, m.uvs = b->uv, m.indices = b->idx, m.material = material;
    int mi = prw_scene_add_mesh(s, &m, e);
    if (mi < 0) return false;
    prw_node n = prw_node_default();
    snprintf(n.name, sizeof n.name, "%s", name);
    n.mesh_group = prw_scene_add_group(s, name, (uint32_t)mi, 1);
    return prw_scene_add_node(s, &n) >= 0 || prw_fail(e, "btf synth: cannot add node %s", name);
}

/* The sample's scene without lights: the measured window [x0, x1] x [y0, y1] plus the margin. */
static prw_scene *sample_scene(const geo *g, double x0, double x1, double y0, double y1, double tau, prw_error *e)
{
    prw_scene *s = prw_scene_create();
    mesh_buf b[2];
    memset(b, 0, sizeof b);
    bool ok = true;
    switch (g->kind) {
    case PRW_BTF_SYNTH_FABRIC: {
        prw_material mw = mat(0.55f, 0.08f, 0.07f, 0, 0.7f, 0), mf = mat(0.80f, 0.74f, 0.60f, 0, 0.7f, 0);
        int warp = prw_scene_add_material(s, &mw), weft = prw_scene_add_material(s, &mf);
        height_field(g, x0, x1, y0, y1, 4, tau, b, 2);
        ok = add_buf(s, &b[0], warp, "warp", e) && add_buf(s, &b[1], weft, "weft", e);
        break;
    }
    case PRW_BTF_SYNTH_LEATHER:
    case PRW_BTF_SYNTH_BRUSHED: { /* one material over a height field */
        bool leather = g->kind == PRW_BTF_SYNTH_LEATHER;
        prw_material m = leather ? mat(0.25f, 0.12f, 0.06f, 0, 0.45f, 0) : mat(0.91f, 0.92f, 0.92f, 1, 0.25f, 0);
        int mi = prw_scene_add_material(s, &m);
        height_field(g, x0, x1, y0, y1, leather ? 2 : 4, tau, b, 1);
        ok = add_buf(s, &b[0], mi, leather ? "leather" : "brushed", e);
        break;
    }
    case PRW_BTF_SYNTH_FLAKES: {
        prw_material base = mat(0.02f, 0.05f, 0.20f, 0, 0.3f, 1), flake = mat(0.9f, 0.9f, 0.9f, 1, 0.15f, 1);
        int mb = prw_scene_add_material(s, &base), mf = prw_scene_add_material(s, &flake);
        double p[4][3], n[3] = {0, 1, 0};
        to_world(x0, y0, 0, tau, p[0]), to_world(x1, y0, 0, tau, p[1]), to_world(x1, y1, 0, tau, p[2]), to_world(x0, y1, 0, tau, p[3]);
        for (int q = 0; q < 4; q++) add_vertex(&b[0], p[q], n);
        add_tri(&b[0], 0, 1, 2);
        add_tri(&b[0], 0, 2, 3);
        flakes(g, x0, x1, y0, y1, tau, &b[1]);
        ok = add_buf(s, &b[0], mb, "base", e) && add_buf(s, &b[1], mf, "flakes", e);
        break;
    }
    default: ok = prw_fail(e, "btf synth: unknown preset %d", (int)g->kind);
    }
    buf_free(&b[0]), buf_free(&b[1]);
    if (!ok) {
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

bool prw_btf_synthesize(const prw_btf_synth_params *p, prw_btf *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (p->kind >= PRW_BTF_SYNTH_COUNT) return prw_fail(e, "btf synth: unknown preset %d", (int)p->kind);
    uint32_t S = p->size, R = p->rays ? p->rays : 1, spp = p->spp ? p->spp : 1, nd = p->dirs ? p->dirs : PRW_BTF_UBO81;
    double tau = p->texel_m > 0 ? p->texel_m : 1e-4;
    if (S < 1 || S > 65536 || R > 64 || spp > 1u << 20 || nd > PRW_BTF_UBO81)
        return prw_fail(e, "btf synth: size %u, %u x %u rays per texel, %u spp, %u directions: out of range", S, R, R, spp, nd);
    geo g = {.kind = p->kind, .seed = p->seed, .size = S};
    /* what is measured: the fabric's weave period once (tiled after), every texel of the others */
    uint32_t M = p->kind == PRW_BTF_SYNTH_FABRIC ? (uint32_t)PRW_MIN((double)S, FABRIC_P) : S;
    g.top = p->kind == PRW_BTF_SYNTH_FABRIC ? 3.0 : p->kind == PRW_BTF_SYNTH_LEATHER ? 0.6 : p->kind == PRW_BTF_SYNTH_FLAKES ? 0.3 : 0.0;
    double relief = p->kind == PRW_BTF_SYNTH_FABRIC ? 4.0 : p->kind == PRW_BTF_SYNTH_LEATHER ? 0.6 : 0.3;
    double margin = ceil(relief * tan(75.5 * PRW_PI / 180.0)) + 2;
    if (!prw_btf_create(S, S, nd, nd, out, e)) return false;
    float dirs[2 * PRW_BTF_UBO81];
    prw_btf_dirs_ubo81(dirs);
    memcpy(out->view_dirs, dirs, sizeof(float) * 2 * nd);
    memcpy(out->light_dirs, dirs, sizeof(float) * 2 * nd);
    prw_scene *s = sample_scene(&g, -margin, M + margin, -margin, M + margin, tau, e);
    if (!s) {
        prw_btf_free(out);
        return false;
    }
    prw_light light = {.type = PRW_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = 1.0, .cast_shadows = true};
    snprintf(light.name, sizeof light.name, "measuring light");
    prw_node ln = prw_node_default();
    snprintf(ln.name, sizeof ln.name, "light");
    light.node = prw_scene_add_node(s, &ln);
    int li = prw_scene_add_light(s, &light);
    if (light.node >= 0) s->nodes[light.node].light = li;
    uint64_t nray = (uint64_t)M * M * R * R;
    prw_ref_ray *rays = prw_malloc(sizeof(prw_ref_ray) * nray);
    prw_ref_ray_result *res = prw_malloc(sizeof(prw_ref_ray_result) * nray);
    bool ok = li >= 0 || prw_fail(e, "btf synth: cannot add the light");
    prw_dvec3 centre = {M * 0.5 * tau, 0, -(M * 0.5) * tau};
    for (uint32_t l = 0; ok && l < nd; l++) {
        double wl[3], d[3];
        prw_btf_dir_vector(dirs[2 * l], dirs[2 * l + 1], wl);
        /* the light travels along -wl: the node's -Z */
        to_world(wl[0], wl[1], wl[2], 1.0, d);
        prw_node look = prw_node_look_at("light", centre, prw_v3(centre.x - d[0], centre.y - d[1], centre.z - d[2]),
                                         prw_v3(0, 0, -1));
        look.light = li;
        s->nodes[light.node] = look;
        prw_scene_update(s);
        prw_ref_renderer *r = NULL;
        if (!prw_ref_create(s, centre, p->threads, &r, e)) {
            ok = false;
            break;
        }
        for (uint32_t v = 0; ok && v < nd; v++) {
            double wv[3], w[3];
            prw_btf_dir_vector(dirs[2 * v], dirs[2 * v + 1], wv);
            to_world(wv[0], wv[1], wv[2], 1.0, w);
            double t_up = (g.top + 1.0) * tau / wv[2]; /* from above the highest point */
            for (uint32_t ty = 0; ty < M; ty++)
                for (uint32_t tx = 0; tx < M; tx++)
                    for (uint32_t q = 0; q < R * R; q++) {
                        double px = tx + ((q % R) + 0.5) / R, py = ty + ((q / R) + 0.5) / R, o[3];
                        to_world(px, py, 0, tau, o);
                        prw_ref_ray *ray = &rays[((uint64_t)ty * M + tx) * R * R + q];
                        ray->origin = prw_v3(o[0] + w[0] * t_up, o[1] + w[1] * t_up, o[2] + w[2] * t_up);
                        ray->dir = prw_v3(-w[0], -w[1], -w[2]);
                        ray->tnear = 0;
                    }
            prw_ref_ray_desc rd = {.first_index = ((uint64_t)l * nd + v) * nray, .s0 = 0, .s1 = spp, .seed = p->seed,
                                   .filter = {PRW_REF_ALL, 0}, .camera = true, .threads = p->threads};
            if (!prw_ref_trace_rays(r, rays, (size_t)nray, &rd, res, NULL, NULL, e)) {
                ok = false;
                break;
            }
            for (uint32_t ty = 0; ty < S; ty++)
                for (uint32_t tx = 0; tx < S; tx++) {
                    uint64_t t = ((uint64_t)(ty % M) * M + (tx % M)) * R * R;
                    float *dst = out->rgb + prw_btf_at(out, v, l, tx, ty);
                    for (int c = 0; c < 3; c++) {
                        double sum = 0;
                        for (uint32_t q = 0; q < R * R; q++) sum += res[t + q].mean[c];
                        dst[c] = (float)(sum / (R * R));
                    }
                }
        }
        prw_ref_destroy(r);
        if (p->progress) p->progress(p->user, (double)(l + 1) / nd);
    }
    free(rays), free(res);
    prw_scene_destroy(s);
    if (!ok) prw_btf_free(out);
    return ok;
}

bool prw_btf_synth_scene(prw_btf_synth_kind kind, uint32_t size, double texel_m, uint64_t seed, double x0, double x1,
                         double y0, double y1, prw_scene **out, prw_error *e)
{
    *out = NULL;
    if (kind >= PRW_BTF_SYNTH_COUNT) return prw_fail(e, "btf synth: unknown preset %d", (int)kind);
    if (size < 1 || !(texel_m > 0) || !(x1 > x0) || !(y1 > y0) || (x1 - x0) * (y1 - y0) > 1e6)
        return prw_fail(e, "btf synth: scene of size %u, texel %g m, window [%g, %g] x [%g, %g]: out of range", size, texel_m,
                        x0, x1, y0, y1);
    geo g = {.kind = kind, .seed = seed, .size = size};
    g.top = kind == PRW_BTF_SYNTH_FABRIC ? 3.0 : kind == PRW_BTF_SYNTH_LEATHER ? 0.6 : kind == PRW_BTF_SYNTH_FLAKES ? 0.3 : 0.0;
    *out = sample_scene(&g, x0, x1, y0, y1, texel_m, e);
    return *out != NULL;
}
