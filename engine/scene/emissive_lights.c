/* emissive_lights — drawn emissive meshes as area lights (prw_emissive.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_emissive.h"

/* Planes and corners are compared relative to the source's size. */
#define COPLANAR_COS 0.999999
#define PLANE_REL 1e-6
#define KEY_REL 1e-7
#define RIGHT_ANGLE_COS 1e-6
#define COLLINEAR_SIN 1e-7

typedef struct tri {
    prw_dvec3 p[3]; /* emitting-side winding: counter-clockwise seen from +n */
    prw_dvec3 n;
    double d, area;
} tri;

/* A polygon: a convex loop of corners (counter-clockwise seen from +n), or one triangle. */
typedef struct poly {
    prw_dvec3 *p;
    uint32_t count;
    prw_dvec3 n;
    double area, flux; /* flux: relative (luminance x area) */
    uint32_t source;
    uint32_t lights;   /* exact lights it needs */
    int mode;          /* 0 exact, 1 merged into a rectangle, 2 dropped, 3 in its direction cluster */
} poly;

typedef struct edge_rec {
    int64_t k[6]; /* quantised ends, the smaller first */
    uint32_t tri;
} edge_rec;

static int edge_cmp(const void *a, const void *b)
{
    const edge_rec *x = a, *y = b;
    for (int i = 0; i < 6; i++)
        if (x->k[i] != y->k[i]) return x->k[i] < y->k[i] ? -1 : 1;
    return x->tri < y->tri ? -1 : x->tri > y->tri;
}

static int u64_cmp(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static uint32_t uf_find(uint32_t *parent, uint32_t i)
{
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
}

static void quantise(prw_dvec3 p, double q, int64_t out[3])
{
    out[0] = llround(p.x / q), out[1] = llround(p.y / q), out[2] = llround(p.z / q);
}

static bool key_less(const int64_t *a, const int64_t *b)
{
    for (int i = 0; i < 3; i++)
        if (a[i] != b[i]) return a[i] < b[i];
    return false;
}

static bool key_eq(const int64_t *a, const int64_t *b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }

typedef struct poly_list {
    poly *v;
    uint32_t count, cap;
} poly_list;

static void push_poly(poly_list *l, const prw_dvec3 *p, uint32_t count, prw_dvec3 n, uint32_t source, double lum)
{
    if (l->count == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 16;
        l->v = prw_realloc(l->v, l->cap * sizeof *l->v);
    }
    poly *o = &l->v[l->count++];
    memset(o, 0, sizeof *o);
    o->p = prw_malloc(count * sizeof *o->p);
    memcpy(o->p, p, count * sizeof *p);
    o->count = count;
    o->n = n;
    o->source = source;
    double a = 0;
    for (uint32_t i = 1; i + 1 < count; i++)
        a += 0.5 * prw_v3_dot(prw_v3_cross(prw_v3_sub(p[i], p[0]), prw_v3_sub(p[i + 1], p[0])), n);
    o->area = fabs(a);
    o->flux = o->area * lum;
    bool para = count == 4 && prw_v3_len(prw_v3_sub(prw_v3_add(p[0], p[2]), prw_v3_add(p[1], p[3]))) <=
                                  1e-9 * (prw_v3_len(prw_v3_sub(p[2], p[0])) + prw_v3_len(prw_v3_sub(p[3], p[1])));
    o->lights = para ? 1 : count - 2;
}

/* A directed edge of a component: its ends' keys and its start corner. */
typedef struct dedge {
    int64_t a[3], b[3];
    prw_dvec3 pa;
    bool inner;
} dedge;

static int key_cmp(const int64_t *x, const int64_t *y)
{
    for (int i = 0; i < 3; i++)
        if (x[i] != y[i]) return x[i] < y[i] ? -1 : 1;
    return 0;
}

/* by the undirected key (smaller end first, then the larger) */
static int dedge_undirected_cmp(const void *x, const void *y)
{
    const dedge *p = x, *q = y;
    const int64_t *p0 = key_less(p->a, p->b) ? p->a : p->b, *p1 = key_less(p->a, p->b) ? p->b : p->a;
    const int64_t *q0 = key_less(q->a, q->b) ? q->a : q->b, *q1 = key_less(q->a, q->b) ? q->b : q->a;
    int c = key_cmp(p0, q0);
    return c ? c : key_cmp(p1, q1);
}

static int dedge_start_cmp(const void *x, const void *y) { return key_cmp(((const dedge *)x)->a, ((const dedge *)y)->a); }

/* The boundary of one component as a convex loop (counter-clockwise about n, collinear corners
 * dropped) in out (capacity cap); returns its corner count, 0 when the boundary is not one convex loop.
 * An edge shared by exactly two of the component's triangles in opposite directions is inner. */
static uint32_t component_loop(const tri *t, const uint32_t *members, uint32_t m, double q, prw_dvec3 n,
                               prw_dvec3 *out, uint32_t cap)
{
    uint32_t ne = 3 * m;
    dedge *d = prw_malloc(ne * sizeof *d);
    for (uint32_t i = 0; i < m; i++)
        for (int c = 0; c < 3; c++) {
            dedge *o = &d[3 * i + (uint32_t)c];
            quantise(t[members[i]].p[c], q, o->a);
            quantise(t[members[i]].p[(c + 1) % 3], q, o->b);
            o->pa = t[members[i]].p[c];
            o->inner = false;
        }
    qsort(d, ne, sizeof *d, dedge_undirected_cmp);
    for (uint32_t i = 0; i < ne;) {
        uint32_t j = i + 1;
        while (j < ne && dedge_undirected_cmp(&d[i], &d[j]) == 0) j++;
        if (j - i == 2 && key_eq(d[i].a, d[i + 1].b) && key_eq(d[i].b, d[i + 1].a)) d[i].inner = d[i + 1].inner = true;
        i = j;
    }
    /* the boundary edges sorted by their start: each corner of a simple loop starts exactly one */
    uint32_t nb = 0;
    for (uint32_t i = 0; i < ne; i++)
        if (!d[i].inner) d[nb++] = d[i];
    qsort(d, nb, sizeof *d, dedge_start_cmp);
    bool ok = nb >= 3 && nb <= cap;
    for (uint32_t i = 0; ok && i + 1 < nb; i++)
        if (key_eq(d[i].a, d[i + 1].a)) ok = false; /* a corner where the boundary meets itself */
    uint32_t count = 0, e = 0;
    while (ok && count < nb) {
        out[count++] = d[e].pa;
        /* the edge starting where this one ends */
        uint32_t lo = 0, hi = nb;
        while (lo < hi) {
            uint32_t mid = (lo + hi) / 2;
            if (key_cmp(d[mid].a, d[e].b) < 0) lo = mid + 1;
            else hi = mid;
        }
        if (lo == nb || !key_eq(d[lo].a, d[e].b)) ok = false;
        else e = lo;
        if (ok && e == 0 && count < nb) ok = false; /* closed before using every boundary edge: several loops */
    }
    ok = ok && e == 0;
    free(d);
    if (!ok) return 0;
    /* drop collinear corners, then check convexity */
    uint32_t k = 0;
    for (uint32_t i = 0; i < count; i++) {
        prw_dvec3 a = out[(i + count - 1) % count], b = out[i], c = out[(i + 1) % count];
        prw_dvec3 ab = prw_v3_sub(b, a), bc = prw_v3_sub(c, b);
        double s = prw_v3_dot(prw_v3_cross(ab, bc), n);
        if (fabs(s) <= COLLINEAR_SIN * prw_v3_len(ab) * prw_v3_len(bc) && prw_v3_dot(ab, bc) > 0) continue;
        out[k++] = b;
    }
    count = k;
    if (count < 3) return 0;
    for (uint32_t i = 0; i < count; i++) {
        prw_dvec3 a = out[i], b = out[(i + 1) % count], c = out[(i + 2) % count];
        if (prw_v3_dot(prw_v3_cross(prw_v3_sub(b, a), prw_v3_sub(c, b)), n) <= 0) return 0;
    }
    return count;
}

/* The polygons of one side (n_sign +1: front) of a source's triangles. */
static void side_polygons(const tri *t, uint32_t nt, double size, uint32_t source, double lum, poly_list *out)
{
    double q = KEY_REL * size;
    uint32_t *parent = prw_malloc((nt ? nt : 1) * sizeof *parent);
    for (uint32_t i = 0; i < nt; i++) parent[i] = i;
    /* undirected edges sorted by their quantised ends: neighbours are runs of equal keys */
    edge_rec *er = prw_malloc((3 * (size_t)nt + 1) * sizeof *er);
    for (uint32_t i = 0; i < nt; i++)
        for (int c = 0; c < 3; c++) {
            int64_t a[3], b[3];
            quantise(t[i].p[c], q, a);
            quantise(t[i].p[(c + 1) % 3], q, b);
            edge_rec *r = &er[3 * i + (uint32_t)c];
            const int64_t *lo = key_less(a, b) ? a : b, *hi = key_less(a, b) ? b : a;
            memcpy(r->k, lo, sizeof a);
            memcpy(r->k + 3, hi, sizeof b);
            r->tri = i;
        }
    qsort(er, 3 * (size_t)nt, sizeof *er, edge_cmp);
    for (size_t i = 0; i + 1 < 3 * (size_t)nt; i++) {
        size_t j = i + 1;
        if (memcmp(er[i].k, er[j].k, sizeof er[i].k) != 0) continue;
        const tri *a = &t[er[i].tri], *b = &t[er[j].tri];
        if (prw_v3_dot(a->n, b->n) >= COPLANAR_COS && fabs(a->d - b->d) <= PLANE_REL * size) {
            uint32_t ra = uf_find(parent, er[i].tri), rb = uf_find(parent, er[j].tri);
            if (ra != rb) parent[ra < rb ? rb : ra] = ra < rb ? ra : rb;
        }
    }
    free(er);
    /* components: triangles sorted by their root */
    uint64_t *by_root = prw_malloc((nt ? nt : 1) * sizeof *by_root);
    for (uint32_t i = 0; i < nt; i++) by_root[i] = (uint64_t)uf_find(parent, i) << 32 | i;
    qsort(by_root, nt, sizeof *by_root, u64_cmp);
    uint32_t *members = prw_malloc((nt ? nt : 1) * sizeof *members);
    prw_dvec3 *loop = prw_malloc((3 * (size_t)nt + 3) * sizeof *loop);
    for (uint32_t i = 0; i < nt;) {
        uint32_t m = 0, root = (uint32_t)(by_root[i] >> 32);
        while (i < nt && (uint32_t)(by_root[i] >> 32) == root) members[m++] = (uint32_t)by_root[i++];
        const tri *first = &t[members[0]];
        uint32_t c = m > 1 ? component_loop(t, members, m, q, first->n, loop, 3 * m + 3) : 0;
        if (c) {
            push_poly(out, loop, c, first->n, source, lum);
        } else {
            for (uint32_t j = 0; j < m; j++) push_poly(out, t[members[j]].p, 3, t[members[j]].n, source, lum);
        }
    }
    free(by_root);
    free(parent);
    free(members);
    free(loop);
}

/* The mean coverage of a MASK or BLEND material (1 for OPAQUE), as the path tracer weights an emitter's
 * light by its coverage at the point: base_color alpha x the base-colour texture's alpha (linear),
 * MASK kept where alpha >= cutoff (prw_shading.h prw_alpha_mask_keeps), BLEND clamped to [0, 1]. */
static double mean_coverage(const prw_scene *s, const prw_material *m)
{
    if (m->alpha_mode == PRW_ALPHA_OPAQUE) return 1.0;
    const prw_texture *t = m->base_color_tex >= 0 && (uint32_t)m->base_color_tex < s->texture_count &&
                                   s->textures[m->base_color_tex].rgba8
                               ? &s->textures[m->base_color_tex]
                               : NULL;
    size_t n = t ? (size_t)t->width * (size_t)t->height : 1;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        double a = m->base_color[3] * (t ? t->rgba8[4 * i + 3] / 255.0 : 1.0);
        sum += m->alpha_mode == PRW_ALPHA_MASK ? (a >= m->alpha_cutoff ? 1.0 : 0.0) : fmin(fmax(a, 0.0), 1.0);
    }
    double c = n ? sum / (double)n : 1.0;
    return isfinite(c) ? c : 0.0;
}

static void push_light(prw_emissive_lights *o, uint32_t *cap, const prw_area_light *l)
{
    if (o->count == *cap) {
        *cap = *cap ? 2 * *cap : 16;
        o->lights = prw_realloc(o->lights, *cap * sizeof *o->lights);
    }
    o->lights[o->count++] = *l;
}

/* Area centroid and in-plane second moments of a convex polygon (fan of triangles). */
static prw_dvec3 poly_centroid(const poly *p)
{
    prw_dvec3 c = prw_v3(0, 0, 0);
    double a = 0;
    for (uint32_t i = 1; i + 1 < p->count; i++) {
        double w = fabs(prw_v3_dot(prw_v3_cross(prw_v3_sub(p->p[i], p->p[0]), prw_v3_sub(p->p[i + 1], p->p[0])), p->n));
        c = prw_v3_add(c, prw_v3_scale(prw_v3_add(p->p[0], prw_v3_add(p->p[i], p->p[i + 1])), w / 3.0));
        a += w;
    }
    return a > 0 ? prw_v3_scale(c, 1.0 / a) : p->p[0];
}

/* The rectangle of the polygon's area, centroid and principal axes (second moments of area). */
static void merged_rect(const poly *p, prw_area_light *l)
{
    prw_dvec3 c = poly_centroid(p), n = p->n;
    prw_dvec3 e1 = prw_v3_norm(prw_v3_sub(p->p[1], p->p[0]));
    prw_dvec3 e2 = prw_v3_cross(n, e1);
    double sxx = 0, syy = 0, sxy = 0; /* integral of x^2, y^2, xy over the area (x, y along e1, e2) */
    for (uint32_t i = 1; i + 1 < p->count; i++) {
        prw_dvec3 v[3] = {prw_v3_sub(p->p[0], c), prw_v3_sub(p->p[i], c), prw_v3_sub(p->p[i + 1], c)};
        double x[3], y[3], sx = 0, sy = 0;
        for (int k = 0; k < 3; k++) x[k] = prw_v3_dot(v[k], e1), y[k] = prw_v3_dot(v[k], e2), sx += x[k], sy += y[k];
        double a = 0.5 * fabs((x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]));
        double xx = sx * sx, yy = sy * sy, xy = sx * sy;
        for (int k = 0; k < 3; k++) xx += x[k] * x[k], yy += y[k] * y[k], xy += x[k] * y[k];
        sxx += a / 12.0 * xx, syy += a / 12.0 * yy, sxy += a / 12.0 * xy;
    }
    double th = 0.5 * atan2(2 * sxy, sxx - syy);
    prw_dvec3 a1 = prw_v3_add(prw_v3_scale(e1, cos(th)), prw_v3_scale(e2, sin(th)));
    prw_dvec3 a2 = prw_v3_cross(n, a1);
    double l1 = 0, l2 = 0; /* second moments along a1, a2 */
    double ct = cos(th), st = sin(th);
    l1 = ct * ct * sxx + 2 * ct * st * sxy + st * st * syy;
    l2 = st * st * sxx - 2 * ct * st * sxy + ct * ct * syy;
    double ratio = l2 > 0 && l1 > 0 ? sqrt(l1 / l2) : 1.0; /* a rectangle 2h1 x 2h2 has moments ~ h^2 */
    double h1 = sqrt(p->area / 4.0 * ratio), h2 = h1 > 0 ? p->area / (4.0 * h1) : 0;
    l->shape = PRW_AREA_RECT;
    l->centre = l->centroid = c;
    l->half_u = prw_v3_scale(a1, h1);
    l->half_v = prw_v3_scale(a2, h2);
    l->merged = true;
}

/* The exact lights of a convex polygon: one rectangle or parallelogram, or a fan of triangles. */
static void exact_lights(const poly *p, prw_area_light proto, prw_emissive_lights *o, uint32_t *cap)
{
    if (p->lights == 1 && p->count == 4) {
        prw_dvec3 u = prw_v3_scale(prw_v3_sub(p->p[1], p->p[0]), 0.5), v = prw_v3_scale(prw_v3_sub(p->p[2], p->p[1]), 0.5);
        proto.centre = proto.centroid = prw_v3_scale(prw_v3_add(p->p[0], p->p[2]), 0.5);
        proto.half_u = u;
        proto.half_v = v;
        bool right = fabs(prw_v3_dot(u, v)) <= RIGHT_ANGLE_COS * prw_v3_len(u) * prw_v3_len(v);
        proto.shape = right ? PRW_AREA_RECT : PRW_AREA_PARALLELOGRAM;
        push_light(o, cap, &proto);
        return;
    }
    for (uint32_t i = 1; i + 1 < p->count; i++) {
        prw_dvec3 a = p->p[0], b = p->p[i], c = p->p[i + 1];
        proto.shape = PRW_AREA_TRIANGLE;
        proto.centre = prw_v3_scale(prw_v3_add(a, c), 0.5);
        proto.half_u = prw_v3_scale(prw_v3_sub(b, a), 0.5);
        proto.half_v = prw_v3_scale(prw_v3_sub(c, b), 0.5);
        proto.centroid = prw_v3_scale(prw_v3_add(a, prw_v3_add(b, c)), 1.0 / 3.0);
        push_light(o, cap, &proto);
    }
}

/* The direction bin of a normal: its dominant axis, 2 x axis + (negative). */
static int dominant_bin(prw_dvec3 n)
{
    double ax = fabs(n.x), ay = fabs(n.y), az = fabs(n.z);
    if (ax >= ay && ax >= az) return n.x < 0;
    if (ay >= az) return 2 + (n.y < 0);
    return 4 + (n.z < 0);
}

static prw_dvec3 bin_axis(int b)
{
    double s = b % 2 ? -1.0 : 1.0;
    return b / 2 == 0 ? prw_v3(s, 0, 0) : b / 2 == 1 ? prw_v3(0, s, 0) : prw_v3(0, 0, s);
}

/* Polygons in budget order: by the lights they need (most first), then flux (least first). */
typedef struct rank {
    uint32_t lights, index;
    double flux;
} rank;

static int by_lights_then_flux(const void *a, const void *b)
{
    const rank *x = a, *y = b;
    if (x->lights != y->lights) return x->lights > y->lights ? -1 : 1;
    if (x->flux != y->flux) return x->flux < y->flux ? -1 : 1;
    return x->index < y->index ? -1 : x->index > y->index;
}

static int by_flux(const void *a, const void *b)
{
    const rank *x = a, *y = b;
    if (x->flux != y->flux) return x->flux < y->flux ? -1 : 1;
    return x->index > y->index ? -1 : x->index < y->index;
}

void prw_emissive_lights_build(const prw_scene *s, uint32_t max_lights, prw_emissive_lights *out)
{
    memset(out, 0, sizeof *out);
    out->max_lights = max_lights;
    poly_list polys = {0};
    uint32_t src_cap = 0;
    for (uint32_t ni = 0; ni < s->node_count; ni++) {
        const prw_node *nd = &s->nodes[ni];
        if (nd->mesh_group < 0 || (uint32_t)nd->mesh_group >= s->group_count) continue;
        const prw_mesh_group *g = &s->groups[nd->mesh_group];
        const double *w = nd->world.m;
        double det = w[0] * (w[5] * w[10] - w[6] * w[9]) - w[4] * (w[1] * w[10] - w[2] * w[9]) +
                     w[8] * (w[1] * w[6] - w[2] * w[5]);
        for (uint32_t k = g->first; k < g->first + g->count && k < s->mesh_count; k++) {
            const prw_mesh *m = &s->meshes[k];
            if (m->material < 0 || (uint32_t)m->material >= s->material_count) continue;
            const prw_material *mat = &s->materials[m->material];
            double rgb[3], cov = mean_coverage(s, mat);
            if (!prw_material_emitted_rgb(s, mat, rgb) || !(cov > 0)) continue;
            for (int c = 0; c < 3; c++) rgb[c] *= cov;
            uint32_t nt = m->index_count / 3, si = out->source_count;
            tri *t = prw_malloc((nt ? nt : 1) * sizeof *t);
            uint32_t kept = 0;
            prw_dvec3 lo = prw_v3(INFINITY, INFINITY, INFINITY), hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
            double area = 0;
            for (uint32_t i = 0; i < nt; i++) {
                tri *o = &t[kept];
                for (int c = 0; c < 3; c++) {
                    const float *v = &m->positions[3 * (size_t)m->indices[3 * i + (uint32_t)c]];
                    o->p[c] = prw_dm4_point(nd->world, prw_v3(v[0], v[1], v[2]));
                }
                if (det < 0) { /* mirrored: the front is the other winding (as the path tracer) */
                    prw_dvec3 x = o->p[1];
                    o->p[1] = o->p[2];
                    o->p[2] = x;
                }
                prw_dvec3 cr = prw_v3_cross(prw_v3_sub(o->p[1], o->p[0]), prw_v3_sub(o->p[2], o->p[0]));
                double l = prw_v3_len(cr);
                if (!(l > 0) || !isfinite(l)) continue;
                o->n = prw_v3_scale(cr, 1.0 / l);
                o->d = prw_v3_dot(o->n, o->p[0]);
                o->area = 0.5 * l;
                area += o->area;
                for (int c = 0; c < 3; c++) lo = prw_v3_min(lo, o->p[c]), hi = prw_v3_max(hi, o->p[c]);
                kept++;
            }
            if (!kept) {
                free(t);
                continue;
            }
            if (out->source_count == src_cap) {
                src_cap = src_cap ? 2 * src_cap : 8;
                out->sources = prw_realloc(out->sources, src_cap * sizeof *out->sources);
            }
            prw_emissive_source *src = &out->sources[out->source_count++];
            memset(src, 0, sizeof *src);
            src->node = (int)ni;
            src->mesh = k;
            src->triangles = kept;
            src->two_sided = mat->double_sided;
            src->textured = mat->emissive_tex >= 0;
            src->coverage = (float)cov;
            for (int c = 0; c < 3; c++) src->radiance[c] = (float)rgb[c];
            src->area = area;
            double size = fmax(prw_v3_len(prw_v3_sub(hi, lo)), 1e-12);
            double lum = 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
            uint32_t before = polys.count;
            side_polygons(t, kept, size, si, lum, &polys);
            src->polygons = polys.count - before;
            if (src->two_sided) { /* the back side: the same polygons, reversed */
                for (uint32_t i = before, end = polys.count; i < end; i++) {
                    poly *p = &polys.v[i];
                    prw_dvec3 *rev = prw_malloc(p->count * sizeof *rev);
                    for (uint32_t c = 0; c < p->count; c++) rev[c] = p->p[p->count - 1 - c];
                    push_poly(&polys, rev, p->count, prw_v3_scale(polys.v[i].n, -1.0), si, lum);
                    free(rev);
                }
            }
            free(t);
        }
    }
    /* the budget: merge the polygons needing most lights, then drop the weakest */
    uint32_t need = 0;
    for (uint32_t i = 0; i < polys.count; i++) need += polys.v[i].lights;
    rank *order = prw_malloc((polys.count ? polys.count : 1) * sizeof *order);
    for (uint32_t i = 0; i < polys.count; i++) order[i] = (rank){polys.v[i].lights, i, polys.v[i].flux};
    if (need > max_lights) {
        qsort(order, polys.count, sizeof *order, by_lights_then_flux);
        for (uint32_t i = 0; i < polys.count && need > max_lights; i++) {
            poly *p = &polys.v[order[i].index];
            if (p->lights <= 1) break;
            need -= p->lights - 1;
            p->mode = 1;
        }
    }
    /* then per source (the largest saving first) one rectangle per direction cluster: polygons binned by
     * their normal's dominant axis (+-x, +-y, +-z) */
    uint32_t nc = 6 * out->source_count;
    double *cl_area = prw_calloc(nc ? nc : 1, sizeof *cl_area), *cl_flux = prw_calloc(nc ? nc : 1, sizeof *cl_flux);
    prw_dvec3 *cl_an = prw_calloc(nc ? nc : 1, sizeof *cl_an), *cl_ac = prw_calloc(nc ? nc : 1, sizeof *cl_ac);
    bool *cl_on = prw_calloc(nc ? nc : 1, sizeof *cl_on);
    if (need > max_lights) {
        rank *saving = prw_malloc((out->source_count ? out->source_count : 1) * sizeof *saving);
        for (uint32_t i = 0; i < out->source_count; i++) saving[i] = (rank){0, i, 0.0};
        uint32_t *lights_now = prw_calloc(out->source_count ? out->source_count : 1, sizeof *lights_now);
        bool *bin_used = prw_calloc(nc ? nc : 1, sizeof *bin_used);
        for (uint32_t i = 0; i < polys.count; i++) {
            const poly *p = &polys.v[i];
            lights_now[p->source] += p->mode == 1 ? 1 : p->lights;
            bin_used[6 * p->source + (uint32_t)dominant_bin(p->n)] = true;
        }
        for (uint32_t i = 0; i < out->source_count; i++) {
            uint32_t bins = 0;
            for (int k = 0; k < 6; k++) bins += bin_used[6 * i + (uint32_t)k];
            saving[i].lights = lights_now[i] > bins ? lights_now[i] - bins : 0;
        }
        qsort(saving, out->source_count, sizeof *saving, by_lights_then_flux);
        for (uint32_t k = 0; k < out->source_count && need > max_lights && saving[k].lights > 0; k++) {
            uint32_t si = saving[k].index;
            need -= saving[k].lights;
            for (uint32_t i = 0; i < polys.count; i++) {
                poly *p = &polys.v[i];
                if (p->source != si) continue;
                p->mode = 3;
                uint32_t c = 6 * si + (uint32_t)dominant_bin(p->n);
                cl_on[c] = true;
                cl_area[c] += p->area;
                cl_flux[c] += p->flux;
                cl_an[c] = prw_v3_add(cl_an[c], prw_v3_scale(p->n, p->area));
                cl_ac[c] = prw_v3_add(cl_ac[c], prw_v3_scale(poly_centroid(p), p->area));
            }
        }
        free(saving);
        free(lights_now);
        free(bin_used);
    }
    /* last, the weakest lights go (a polygon's exact lights, its rectangle or a cluster) */
    if (need > max_lights) {
        rank *units = prw_malloc((polys.count + nc + 1) * sizeof *units);
        uint32_t nu = 0;
        for (uint32_t i = 0; i < polys.count; i++)
            if (polys.v[i].mode != 3) units[nu++] = (rank){polys.v[i].mode == 1 ? 1 : polys.v[i].lights, i, polys.v[i].flux};
        for (uint32_t c = 0; c < nc; c++)
            if (cl_on[c]) units[nu++] = (rank){1, polys.count + c, cl_flux[c]};
        qsort(units, nu, sizeof *units, by_flux);
        for (uint32_t i = 0; i < nu && need > max_lights; i++) {
            need -= units[i].lights;
            if (units[i].index < polys.count) {
                polys.v[units[i].index].mode = 2;
            } else {
                uint32_t c = units[i].index - polys.count;
                cl_on[c] = false;
                for (uint32_t j = 0; j < polys.count; j++)
                    if (polys.v[j].mode == 3 && 6 * polys.v[j].source + (uint32_t)dominant_bin(polys.v[j].n) == c)
                        polys.v[j].mode = 2;
            }
        }
        free(units);
    }
    free(order);
    uint32_t cap = 0;
    for (uint32_t i = 0; i < polys.count; i++) {
        poly *p = &polys.v[i];
        prw_emissive_source *src = &out->sources[p->source];
        prw_area_light proto = {.normal = p->n, .source = p->source};
        for (int c = 0; c < 3; c++) proto.radiance[c] = src->radiance[c];
        if (p->mode == 2) {
            src->dropped++;
        } else if (p->mode == 3) {
            src->clustered++;
        } else if (p->mode == 1) {
            merged_rect(p, &proto);
            push_light(out, &cap, &proto);
            src->merged++;
        } else {
            uint32_t first = out->count;
            exact_lights(p, proto, out, &cap);
            for (uint32_t j = first; j < out->count; j++) {
                prw_area_shape sh = out->lights[j].shape;
                if (sh == PRW_AREA_RECT) src->rects++;
                else if (sh == PRW_AREA_PARALLELOGRAM) src->parallelograms++;
                else src->triangle_lights++;
            }
        }
    }
    for (uint32_t c = 0; c < nc; c++) {
        if (!cl_on[c] || !(cl_area[c] > 0)) continue;
        prw_emissive_source *src = &out->sources[c / 6];
        prw_area_light l = {.source = c / 6, .shape = PRW_AREA_RECT, .merged = true};
        for (int k = 0; k < 3; k++) l.radiance[k] = src->radiance[k];
        double len = prw_v3_len(cl_an[c]);
        l.normal = len > 1e-6 * cl_area[c] ? prw_v3_scale(cl_an[c], 1.0 / len) : bin_axis((int)(c % 6));
        l.centre = l.centroid = prw_v3_scale(cl_ac[c], 1.0 / cl_area[c]);
        /* on the cluster's supporting plane: a curved emitter's centroid is inside the mesh, whose own
         * surface would shadow the light */
        double lift = 0;
        for (uint32_t i = 0; i < polys.count; i++) {
            const poly *p = &polys.v[i];
            if (p->mode != 3 || 6 * p->source + (uint32_t)dominant_bin(p->n) != c) continue;
            for (uint32_t k = 0; k < p->count; k++) lift = fmax(lift, prw_v3_dot(prw_v3_sub(p->p[k], l.centre), l.normal));
        }
        l.centre = l.centroid = prw_v3_add(l.centre, prw_v3_scale(l.normal, lift));
        /* a square of the cluster's area: the same flux (pi L A) */
        prw_dvec3 t = fabs(l.normal.x) < 0.9 ? prw_v3(1, 0, 0) : prw_v3(0, 1, 0);
        prw_dvec3 u = prw_v3_norm(prw_v3_cross(t, l.normal)), v = prw_v3_cross(l.normal, u);
        double h = 0.5 * sqrt(cl_area[c]);
        l.half_u = prw_v3_scale(u, h);
        l.half_v = prw_v3_scale(v, h);
        push_light(out, &cap, &l);
        src->cluster_lights++;
    }
    for (uint32_t i = 0; i < polys.count; i++) free(polys.v[i].p);
    free(cl_area);
    free(cl_flux);
    free(cl_an);
    free(cl_ac);
    free(cl_on);
    free(polys.v);
}

void prw_emissive_lights_free(prw_emissive_lights *l)
{
    if (!l) return;
    free(l->lights);
    free(l->sources);
    memset(l, 0, sizeof *l);
}
