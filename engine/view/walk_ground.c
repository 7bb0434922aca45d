/* walk_ground — "what is under my feet" for walk mode: world-space triangles in a uniform XZ grid,
 * queried with a vertical line (contract in prw_walk.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_walk.h"

typedef struct ground_tri {
    double x[3], y[3], z[3];
    double det; /* of the XZ edge matrix; 0 for vertical triangles (skipped) */
} ground_tri;

struct prw_walk_ground {
    ground_tri *tris;
    size_t count;
    double min_x, min_z, cell;
    uint32_t nx, nz;
    uint32_t *cell_start; /* nx*nz+1 offsets into cell_items */
    uint32_t *cell_items;
};

static void cell_range(const prw_walk_ground *g, const ground_tri *t, uint32_t *x0, uint32_t *x1, uint32_t *z0,
                       uint32_t *z1)
{
    double ax = fmin(t->x[0], fmin(t->x[1], t->x[2])), bx = fmax(t->x[0], fmax(t->x[1], t->x[2]));
    double az = fmin(t->z[0], fmin(t->z[1], t->z[2])), bz = fmax(t->z[0], fmax(t->z[1], t->z[2]));
    double fx0 = floor((ax - g->min_x) / g->cell), fx1 = floor((bx - g->min_x) / g->cell);
    double fz0 = floor((az - g->min_z) / g->cell), fz1 = floor((bz - g->min_z) / g->cell);
    *x0 = (uint32_t)fmax(0, fmin(g->nx - 1, fx0));
    *x1 = (uint32_t)fmax(0, fmin(g->nx - 1, fx1));
    *z0 = (uint32_t)fmax(0, fmin(g->nz - 1, fz0));
    *z1 = (uint32_t)fmax(0, fmin(g->nz - 1, fz1));
}

bool prw_walk_ground_create(const double *v, size_t tri_count, prw_walk_ground **out, prw_error *e)
{
    *out = NULL;
    if (tri_count > 50000000u) return prw_fail(e, "walk ground: %zu triangles (limit 5e7)", tri_count);
    prw_walk_ground *g = prw_calloc(1, sizeof *g);
    g->tris = prw_calloc(tri_count ? tri_count : 1, sizeof *g->tris);
    double min_x = INFINITY, max_x = -INFINITY, min_z = INFINITY, max_z = -INFINITY;
    for (size_t i = 0; i < tri_count; i++) {
        const double *p = v + 9 * i;
        for (int k = 0; k < 9; k++)
            if (!isfinite(p[k])) {
                prw_walk_ground_destroy(g);
                return prw_fail(e, "walk ground: triangle %zu has a non-finite vertex", i);
            }
        ground_tri t = {{p[0], p[3], p[6]}, {p[1], p[4], p[7]}, {p[2], p[5], p[8]}, 0};
        t.det = (t.x[1] - t.x[0]) * (t.z[2] - t.z[0]) - (t.x[2] - t.x[0]) * (t.z[1] - t.z[0]);
        double scale = fmax(fabs(t.x[1] - t.x[0]) + fabs(t.z[1] - t.z[0]), fabs(t.x[2] - t.x[0]) + fabs(t.z[2] - t.z[0]));
        if (fabs(t.det) <= 1e-12 * scale * scale) continue; /* vertical (a wall) or degenerate */
        g->tris[g->count++] = t;
        for (int k = 0; k < 3; k++) {
            min_x = fmin(min_x, t.x[k]), max_x = fmax(max_x, t.x[k]);
            min_z = fmin(min_z, t.z[k]), max_z = fmax(max_z, t.z[k]);
        }
    }
    if (g->count == 0) {
        min_x = min_z = 0;
        max_x = max_z = 1;
    }
    /* about 4 triangles per cell on average, at most 1024 x 1024 cells */
    double ex = fmax(max_x - min_x, 1e-6), ez = fmax(max_z - min_z, 1e-6);
    double cells = fmin(1024.0 * 1024.0, fmax(1.0, (double)g->count / 4.0));
    g->cell = sqrt(ex * ez / cells);
    g->cell = fmax(g->cell, fmax(ex, ez) / 1024.0);
    g->min_x = min_x;
    g->min_z = min_z;
    /* Grid entries (triangle x covered cell): many large overlapping triangles could make them
     * explode, so the cells are coarsened until there are at most 16 per triangle (+ 1M). */
    size_t total, limit = 16 * g->count + (1u << 20);
    for (;;) {
        g->nx = (uint32_t)fmin(1024, fmax(1, ceil(ex / g->cell)));
        g->nz = (uint32_t)fmin(1024, fmax(1, ceil(ez / g->cell)));
        total = 0;
        for (size_t i = 0; i < g->count; i++) {
            uint32_t x0, x1, z0, z1;
            cell_range(g, &g->tris[i], &x0, &x1, &z0, &z1);
            total += (size_t)(x1 - x0 + 1) * (z1 - z0 + 1);
        }
        if (total <= limit || (g->nx == 1 && g->nz == 1)) break;
        g->cell *= 2;
    }
    if (total > 0xffffffffu) {
        prw_walk_ground_destroy(g);
        return prw_fail(e, "walk ground: too many grid entries (%zu)", total);
    }
    size_t ncell = (size_t)g->nx * g->nz;
    g->cell_start = prw_calloc(ncell + 1, sizeof *g->cell_start);
    for (size_t i = 0; i < g->count; i++) { /* count per cell */
        uint32_t x0, x1, z0, z1;
        cell_range(g, &g->tris[i], &x0, &x1, &z0, &z1);
        for (uint32_t z = z0; z <= z1; z++)
            for (uint32_t x = x0; x <= x1; x++) g->cell_start[(size_t)z * g->nx + x + 1]++;
    }
    for (size_t c = 0; c < ncell; c++) g->cell_start[c + 1] += g->cell_start[c];
    g->cell_items = prw_calloc(total ? total : 1, sizeof *g->cell_items);
    uint32_t *fill = prw_calloc(ncell, sizeof *fill);
    for (size_t i = 0; i < g->count; i++) {
        uint32_t x0, x1, z0, z1;
        cell_range(g, &g->tris[i], &x0, &x1, &z0, &z1);
        for (uint32_t z = z0; z <= z1; z++)
            for (uint32_t x = x0; x <= x1; x++) {
                size_t c = (size_t)z * g->nx + x;
                g->cell_items[g->cell_start[c] + fill[c]++] = (uint32_t)i;
            }
    }
    free(fill);
    *out = g;
    return true;
}

bool prw_walk_ground_create_scene(const prw_scene *s, prw_walk_ground **out, prw_error *e)
{
    size_t n = 0;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *nd = &s->nodes[i];
        if (nd->mesh_group < 0 || (uint32_t)nd->mesh_group >= s->group_count) continue;
        const prw_mesh_group *gr = &s->groups[nd->mesh_group];
        for (uint32_t m = gr->first; m < gr->first + gr->count && m < s->mesh_count; m++) n += s->meshes[m].index_count / 3;
    }
    double *v = prw_malloc((n ? n : 1) * 9 * sizeof(double));
    size_t k = 0;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *nd = &s->nodes[i];
        if (nd->mesh_group < 0 || (uint32_t)nd->mesh_group >= s->group_count) continue;
        const prw_mesh_group *gr = &s->groups[nd->mesh_group];
        for (uint32_t m = gr->first; m < gr->first + gr->count && m < s->mesh_count; m++) {
            const prw_mesh *mesh = &s->meshes[m];
            for (uint32_t t = 0; t + 2 < mesh->index_count; t += 3)
                for (int c = 0; c < 3; c++) {
                    const float *p = mesh->positions + 3 * (size_t)mesh->indices[t + (uint32_t)c];
                    prw_dvec3 w = prw_dm4_point(nd->world, prw_v3(p[0], p[1], p[2]));
                    v[k++] = w.x, v[k++] = w.y, v[k++] = w.z;
                }
        }
    }
    bool ok = prw_walk_ground_create(v, k / 9, out, e);
    free(v);
    return ok;
}

void prw_walk_ground_destroy(prw_walk_ground *g)
{
    if (!g) return;
    free(g->tris);
    free(g->cell_start);
    free(g->cell_items);
    free(g);
}

size_t prw_walk_ground_triangle_count(const prw_walk_ground *g) { return g ? g->count : 0; }

bool prw_walk_ground_height(const prw_walk_ground *g, double x, double z, double y_max, double *height)
{
    if (!g || g->count == 0 || !isfinite(x) || !isfinite(z)) return false;
    double fx = floor((x - g->min_x) / g->cell), fz = floor((z - g->min_z) / g->cell);
    if (fx < 0 || fz < 0 || fx >= g->nx || fz >= g->nz) {
        /* points on the far boundary belong to the last cell */
        if (fx == g->nx) fx = g->nx - 1;
        if (fz == g->nz) fz = g->nz - 1;
        if (fx < 0 || fz < 0 || fx >= g->nx || fz >= g->nz) return false;
    }
    size_t c = (size_t)fz * g->nx + (size_t)fx;
    bool found = false;
    double best = -INFINITY;
    for (uint32_t k = g->cell_start[c]; k < g->cell_start[c + 1]; k++) {
        const ground_tri *t = &g->tris[g->cell_items[k]];
        /* barycentrics in XZ */
        double b1 = ((x - t->x[0]) * (t->z[2] - t->z[0]) - (t->x[2] - t->x[0]) * (z - t->z[0])) / t->det;
        double b2 = ((t->x[1] - t->x[0]) * (z - t->z[0]) - (x - t->x[0]) * (t->z[1] - t->z[0])) / t->det;
        double b0 = 1.0 - b1 - b2;
        const double eps = -1e-12;
        if (b0 < eps || b1 < eps || b2 < eps) continue;
        double y = b0 * t->y[0] + b1 * t->y[1] + b2 * t->y[2];
        if (y <= y_max && y > best) {
            best = y;
            found = true;
        }
    }
    if (found) *height = best;
    return found;
}
