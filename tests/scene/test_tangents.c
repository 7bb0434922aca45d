/* Tangent generation on planes with known uv orientation. */
#include <stdlib.h>
#include <string.h>

#include "prw_scene.h"
#include "prw_test.h"

#define N 4 /* grid of N x N vertices */

/* A grid plane through the origin spanned by unit axes ex, ey (normal = ex x ey); uv = f(x, y). */
typedef struct grid {
    float pos[N * N * 3], nrm[N * N * 3], uv[N * N * 2];
    uint32_t idx[(N - 1) * (N - 1) * 6];
    prw_mesh m;
} grid;

/* u = uu . (x, y), v = vv . (x, y) + 1 for grid coordinates x, y in [0, 1] along ex, ey. */
static void make_grid(grid *g, prw_dvec3 ex, prw_dvec3 ey, const double uu[2], const double vv[2])
{
    prw_dvec3 n = prw_v3_norm(prw_v3_cross(ex, ey));
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            int k = j * N + i;
            double x = i / (double)(N - 1), y = j / (double)(N - 1);
            prw_dvec3 p = prw_v3_add(prw_v3_scale(ex, x), prw_v3_scale(ey, y));
            g->pos[3 * k] = (float)p.x, g->pos[3 * k + 1] = (float)p.y, g->pos[3 * k + 2] = (float)p.z;
            g->nrm[3 * k] = (float)n.x, g->nrm[3 * k + 1] = (float)n.y, g->nrm[3 * k + 2] = (float)n.z;
            g->uv[2 * k] = (float)(uu[0] * x + uu[1] * y);
            g->uv[2 * k + 1] = (float)(vv[0] * x + vv[1] * y + 1);
        }
    int t = 0;
    for (int j = 0; j + 1 < N; j++)
        for (int i = 0; i + 1 < N; i++) {
            uint32_t a = (uint32_t)(j * N + i), b = a + 1, c = a + N + 1, d = a + N;
            uint32_t tri[6] = {a, b, c, a, c, d};
            memcpy(g->idx + t, tri, sizeof tri);
            t += 6;
        }
    memset(&g->m, 0, sizeof g->m);
    strcpy(g->m.name, "grid");
    g->m.vertex_count = N * N;
    g->m.index_count = (uint32_t)t;
    g->m.positions = g->pos;
    g->m.normals = g->nrm;
    g->m.uvs = g->uv;
    g->m.indices = g->idx;
}

static void check_all(const prw_mesh *m, prw_dvec3 t_expect, float w_expect)
{
    int bad = 0;
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *t = m->tangents + 4 * v, *n = m->normals + 3 * v;
        double len = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        double dn = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
        double dt = t[0] * t_expect.x + t[1] * t_expect.y + t[2] * t_expect.z;
        if (fabs(len - 1) > 1e-5 || fabs(dn) > 1e-5 || fabs(dt - 1) > 1e-5 || t[3] != w_expect) {
            if (bad++ < 3)
                fprintf(stderr, "vertex %u: t = (%g %g %g, w %g), expected (%g %g %g, w %g)\n", v, t[0], t[1], t[2], t[3],
                        t_expect.x, t_expect.y, t_expect.z, w_expect);
        }
    }
    CHECK_MSG(bad == 0, "%d vertices wrong", bad);
}

static void test_standard_mapping(void)
{
    /* xy plane, normal +z; u = x, v = 1 - y (glTF: v runs down the image, so +y is "up"):
     * tangent +x, bitangent cross(n, t) = +y = towards decreasing v -> w = +1 */
    grid g;
    double uu[2] = {1, 0}, vv[2] = {0, -1};
    make_grid(&g, prw_v3(1, 0, 0), prw_v3(0, 1, 0), uu, vv);
    prw_mesh_generate_tangents(&g.m);
    check_all(&g.m, prw_v3(1, 0, 0), 1.0f);
    free(g.m.tangents);
}

static void test_mirrored_and_rotated(void)
{
    /* u mirrored (u = -x): tangent -x, and the frame is mirrored -> w = -1 */
    grid g;
    double uu[2] = {-1, 0}, vv[2] = {0, -1};
    make_grid(&g, prw_v3(1, 0, 0), prw_v3(0, 1, 0), uu, vv);
    prw_mesh_generate_tangents(&g.m);
    check_all(&g.m, prw_v3(-1, 0, 0), -1.0f);
    free(g.m.tangents);
    /* v mirrored (v = y): tangent +x, w = -1 */
    double uu2[2] = {1, 0}, vv2[2] = {0, 1};
    make_grid(&g, prw_v3(1, 0, 0), prw_v3(0, 1, 0), uu2, vv2);
    prw_mesh_generate_tangents(&g.m);
    check_all(&g.m, prw_v3(1, 0, 0), -1.0f);
    free(g.m.tangents);
    /* uv rotated 90 degrees: u = y, v = x -> tangent +y; cross(z, y) = -x = decreasing v -> w = +1 */
    double uu3[2] = {0, 2}, vv3[2] = {3, 0}; /* anisotropic scales do not matter */
    make_grid(&g, prw_v3(1, 0, 0), prw_v3(0, 1, 0), uu3, vv3);
    prw_mesh_generate_tangents(&g.m);
    check_all(&g.m, prw_v3(0, 1, 0), 1.0f);
    free(g.m.tangents);
    /* a tilted plane: axes ex = (1,1,0)/sqrt2, ey = (0,0,-1); standard mapping -> t = ex, w = +1 */
    double s2 = sqrt(0.5);
    make_grid(&g, prw_v3(s2, s2, 0), prw_v3(0, 0, -1), (double[2]){1, 0}, (double[2]){0, -1});
    prw_mesh_generate_tangents(&g.m);
    check_all(&g.m, prw_v3(s2, s2, 0), 1.0f);
    free(g.m.tangents);
}

static void test_gram_schmidt(void)
{
    /* normals tilted away from the face normal: the tangent stays orthogonal to the given normal */
    grid g;
    double uu[2] = {1, 0}, vv[2] = {0, -1};
    make_grid(&g, prw_v3(1, 0, 0), prw_v3(0, 1, 0), uu, vv);
    prw_dvec3 n = prw_v3_norm(prw_v3(0.5, 0, 1));
    for (int k = 0; k < N * N; k++) g.nrm[3 * k] = (float)n.x, g.nrm[3 * k + 1] = 0, g.nrm[3 * k + 2] = (float)n.z;
    prw_mesh_generate_tangents(&g.m);
    /* x projected off n: (1,0,0) - n * n.x, normalised */
    prw_dvec3 t = prw_v3_norm(prw_v3_sub(prw_v3(1, 0, 0), prw_v3_scale(n, n.x)));
    check_all(&g.m, t, 1.0f);
    free(g.m.tangents);
}

static void test_degenerate(void)
{
    /* all uvs equal: any unit tangent orthogonal to the normal, deterministic, w = +1 */
    grid g;
    double z[2] = {0, 0};
    make_grid(&g, prw_v3(0, 1, 0), prw_v3(0, 0, 1), z, z); /* normal +x */
    prw_mesh_generate_tangents(&g.m);
    float first[4];
    memcpy(first, g.m.tangents, sizeof first);
    for (uint32_t v = 0; v < g.m.vertex_count; v++) {
        const float *t = g.m.tangents + 4 * v;
        CHECK_NEAR(t[0] * t[0] + t[1] * t[1] + t[2] * t[2], 1.0, 1e-6);
        CHECK_NEAR(t[0], 0.0, 1e-6); /* orthogonal to +x */
        CHECK(t[3] == 1.0f);
        CHECK(memcmp(t, first, sizeof first) == 0);
    }
    float *again = g.m.tangents;
    g.m.tangents = NULL;
    prw_mesh_generate_tangents(&g.m);
    CHECK(memcmp(again, g.m.tangents, 4 * sizeof(float) * g.m.vertex_count) == 0);
    free(again);
    free(g.m.tangents);
}

static void test_add_mesh_generates(void)
{
    /* prw_scene_add_mesh without tangents (and without normals) generates both */
    prw_scene *s = prw_scene_create();
    prw_material mat = prw_material_default();
    prw_scene_add_material(s, &mat);
    grid g;
    double uu[2] = {1, 0}, vv[2] = {0, -1};
    make_grid(&g, prw_v3(1, 0, 0), prw_v3(0, 0, -1), uu, vv); /* xz plane, normal +y */
    g.m.normals = NULL;
    prw_error e;
    int mi = prw_scene_add_mesh(s, &g.m, &e);
    CHECK_MSG(mi == 0, "%s", e.msg);
    if (mi == 0) {
        CHECK_NEAR(s->meshes[0].normals[1], 1.0, 1e-6);
        check_all(&s->meshes[0], prw_v3(1, 0, 0), 1.0f);
    }
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"standard_mapping", test_standard_mapping},
        {"mirrored_and_rotated", test_mirrored_and_rotated},
        {"gram_schmidt", test_gram_schmidt},
        {"degenerate", test_degenerate},
        {"add_mesh_generates", test_add_mesh_generates},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
