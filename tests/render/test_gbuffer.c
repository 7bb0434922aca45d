/* The base pass's kept depth and G-buffer normal against the path tracer's primary hits (issue "Render
 * core", must-show 3).
 *
 * A scene of boxes, spheres and a tilted quad, some double-sided and seen from inside, is rendered at
 * 1x MSAA (the raster samples each pixel at its centre) with "depth" and "gbuf_normal" kept
 * (prw_render_debug.exports).  For every pixel the camera ray through the pixel centre is traced by the
 * reference (prw_ref_primary_hit, double precision, the same triangles): where both see the same
 * material (the G-buffer id), the raster position reconstructed from the reversed-Z depth through the
 * inverse view-projection must lie within 1e-4 relative (to the hit distance) of the reference hit, and
 * the G-buffer shading normal within 0.5 degrees of the reference's.  Pixels whose centre lies within
 * 1/64 px of an edge or crease (reference rays moved by 1/64 px see another material, or hit points off
 * the line through their neighbours by more than 1e-5 of the distance: the rasterizer's 1/256-px
 * subpixel grid may take either side) and
 * pixels where the two renderers see different materials are counted: edge pixels must stay under
 * 2 % (about 0.5 % here), mismatches away from edges under 0.5 % (none here).
 * Control: the same comparison against rays through a point 0.5 px off the centre must fail the
 * position bound on many pixels, so the test can see a half-pixel error.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_reference.h"
#include "prw_render.h"
#include "prw_test.h"

#define W 96u
#define H 64u
#define POS_TOL 1e-4
#define NORMAL_TOL_DEG 0.5
#define EDGE_PX (1.0 / 64) /* lavapipe rasterizes with 8 subpixel bits: 1/256 px, plus vertex rounding */

static prw_scene *build_scene(prw_error *e)
{
    prw_scene *s = prw_scene_create();
    prw_material wall = prw_material_default();
    wall.double_sided = true;
    wall.base_color[0] = 0.7f, wall.base_color[1] = 0.7f, wall.base_color[2] = 0.6f;
    prw_material ball = prw_material_default();
    ball.base_color[0] = 0.8f, ball.base_color[1] = 0.3f, ball.base_color[2] = 0.2f;
    ball.roughness = 0.3f;
    prw_material metal = prw_material_default();
    metal.metallic = 1.0f, metal.roughness = 0.2f;
    int mw = prw_scene_add_material(s, &wall), mb = prw_scene_add_material(s, &ball),
        mm = prw_scene_add_material(s, &metal);
    bool ok = mw >= 0 && mb >= 0 && mm >= 0 &&
              prw_scene_add_box(s, "room", prw_v3(-3, 0, -5), prw_v3(3, 3, 3), mw, true, e) >= 0 &&
              prw_scene_add_box(s, "crate", prw_v3(-1.6, 0, -2.6), prw_v3(-0.6, 0.9, -1.6), mb, false, e) >= 0 &&
              prw_scene_add_sphere(s, "ball", prw_v3(0.7, 0.7, -1.8), 0.7, 48, 24, mb, e) >= 0 &&
              prw_scene_add_sphere(s, "chrome", prw_v3(-0.3, 1.8, -3.2), 0.45, 32, 16, mm, e) >= 0 &&
              prw_scene_add_quad(s, "panel", prw_v3(1.8, 1.5, -3.5), prw_v3(0.5, 0.6, 0.3), prw_v3(0.2, -0.3, 0.7), mw,
                                 e) >= 0;
    prw_light l = {.type = PRW_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 300, .cast_shadows = true};
    prw_node ln = prw_node_default();
    ln.translation = prw_v3(0, 2.7, 0);
    l.node = prw_scene_add_node(s, &ln);
    ok = ok && l.node >= 0 && prw_scene_add_light(s, &l) >= 0;
    prw_camera c = {.yfov = 1.0, .znear = 0.05, .ev100 = 5};
    snprintf(c.name, sizeof c.name, "main");
    prw_node cn = prw_node_look_at("cam", prw_v3(0.3, 1.5, 2.2), prw_v3(-0.1, 0.9, -2), prw_v3(0, 1, 0));
    c.node = prw_scene_add_node(s, &cn);
    ok = ok && c.node >= 0;
    if (ok) s->nodes[c.node].camera = prw_scene_add_camera(s, &c);
    prw_scene_update(s);
    if (!ok) {
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

typedef struct result {
    uint32_t compared, mismatched, edges, pos_fail, normal_fail;
    double worst_pos, worst_deg;
} result;

/* Compares the raster depth / normals with rays through (i + dx, j + 0.5). */
static result compare(const prw_view *v, const prw_ref_renderer *ref, const float *depth, const float *normal,
                      const uint32_t *id, double dx)
{
    result res = {0};
    prw_dmat4 to_eye = prw_dm4_identity();
    to_eye.m[12] = v->eye.x, to_eye.m[13] = v->eye.y, to_eye.m[14] = v->eye.z;
    prw_dmat4 vp = prw_dm4_mul(prw_view_proj(v), prw_dm4_mul(v->view, to_eye)), inv;
    CHECK(prw_dm4_inverse(vp, &inv));
    for (uint32_t j = 0; j < H; j++)
        for (uint32_t i = 0; i < W; i++) {
            size_t k = (size_t)j * W + i;
            prw_ref_hit h;
            bool hit = prw_ref_primary_hit(ref, v, i + dx, j + 0.5, &h);
            int raster_mat = (int)id[k] - 1; /* 0: nothing drawn */
            if (!hit && raster_mat < 0) continue;
            if (!hit || raster_mat != h.material) {
                res.mismatched++;
                continue;
            }
            /* within EDGE_PX of an edge or crease: rays through collinear image points hit collinear points
             * on a plane (and nearly so on the smooth spheres), not across a crease */
            bool edge = false;
            prw_dvec3 p2[4];
            static const double off[4][2] = {{EDGE_PX, 0}, {-EDGE_PX, 0}, {0, EDGE_PX}, {0, -EDGE_PX}};
            for (int q = 0; q < 4 && !edge; q++) {
                prw_ref_hit h2;
                edge = !prw_ref_primary_hit(ref, v, i + dx + off[q][0], j + 0.5 + off[q][1], &h2) ||
                       h2.material != h.material;
                p2[q] = h2.position;
            }
            for (int q = 0; q < 4 && !edge; q += 2) {
                prw_dvec3 a = p2[q], ab = prw_v3_sub(p2[q + 1], a), ap = prw_v3_sub(h.position, a);
                double l2 = prw_v3_dot(ab, ab), t = l2 > 0 ? prw_v3_dot(ap, ab) / l2 : 0;
                double dev = prw_v3_len(prw_v3_sub(ap, prw_v3_scale(ab, t)));
                edge = dev > 1e-5 * h.t;
            }
            if (edge) {
                res.edges++;
                continue;
            }
            res.compared++;
            /* NDC of the pixel centre (y down in both renderers), reversed-Z depth */
            double x = 2.0 * (i + 0.5) / W - 1.0, y = 2.0 * (j + 0.5) / H - 1.0, z = depth[k];
            const double *m = inv.m;
            double p[4];
            for (int r = 0; r < 4; r++) p[r] = m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
            prw_dvec3 pr = prw_v3(p[0] / p[3] + v->eye.x, p[1] / p[3] + v->eye.y, p[2] / p[3] + v->eye.z);
            double err = prw_v3_len(prw_v3_sub(pr, h.position)) / fmax(h.t, 1e-9);
            if (err > res.worst_pos) res.worst_pos = err;
            if (err > POS_TOL) {
                res.pos_fail++;
                if (getenv("PRW_GBUF_DEBUG"))
                    printf("  pixel (%u, %u) dx %.2f: raster (%.6f %.6f %.6f) ref (%.6f %.6f %.6f) mat %d\n", i, j, dx,
                           pr.x, pr.y, pr.z, h.position.x, h.position.y, h.position.z, h.material);
            }
            prw_dvec3 n = prw_v3_norm(prw_v3(normal[4 * k], normal[4 * k + 1], normal[4 * k + 2]));
            double c = prw_v3_dot(n, prw_v3_norm(h.normal));
            double deg = acos(fmin(1.0, fmax(-1.0, c))) * 180.0 / PRW_PI;
            if (deg > res.worst_deg) res.worst_deg = deg;
            if (deg > NORMAL_TOL_DEG) {
                res.normal_fail++;
                if (getenv("PRW_GBUF_DEBUG"))
                    printf("  pixel (%u, %u): normal raster (%.4f %.4f %.4f) ref (%.4f %.4f %.4f)\n", i, j, n.x, n.y,
                           n.z, h.normal.x, h.normal.y, h.normal.z);
            }
        }
    return res;
}

static void test_depth_normal_vs_reference(void)
{
    prw_error e = {{0}};
    prw_scene *s = build_scene(&e);
    CHECK_OK(s != NULL, &e);
    if (!s) return;
    prw_gpu *gpu = NULL;
    prw_renderer *r = NULL;
    prw_gpu_desc gd = {.device_index = -1};
    static const char *const exports[] = {"depth", "gbuf_normal", "gbuf_id", NULL};
    prw_render_debug dbg = {.exports = exports};
    prw_render_desc rd = {.width = W, .height = H,  .debug = &dbg, .quality = prw_quality_default()};
    rd.quality.msaa = 1;
    prw_view v;
    float *depth = NULL, *normal = NULL;
    uint32_t *id = NULL, w, h;
    bool ok = prw_gpu_create(&gd, &gpu, &e) && prw_renderer_create(gpu, s, &rd, &r, &e) &&
              prw_view_from_camera(s, 0, W, H, &v, &e) && prw_renderer_render(r, &v, 1, NULL, &e) &&
              prw_renderer_read_image(r, "depth", 0, (void **)&depth, &w, &h, &e) &&
              prw_renderer_read_image(r, "gbuf_normal", 0, (void **)&normal, &w, &h, &e) &&
              prw_renderer_read_image(r, "gbuf_id", 0, (void **)&id, &w, &h, &e);
    CHECK_OK(ok, &e);
    prw_ref_renderer *ref = NULL;
    if (ok) {
        CHECK_OK(prw_ref_create(s, v.eye, 2, &ref, &e), &e);
        CHECK(w == W && h == H);
    }
    if (ok && ref) {
        result a = compare(&v, ref, depth, normal, id, 0.5);
        printf("pixel centres: %u compared, %u on an edge, %u see other materials (%.2f %% together); position worst "
               "%.2e relative (%u > %g), normal worst %.3f deg (%u > %g)\n",
               a.compared, a.edges, a.mismatched, 100.0 * (a.edges + a.mismatched) / (W * H), a.worst_pos, a.pos_fail,
               POS_TOL, a.worst_deg, a.normal_fail, NORMAL_TOL_DEG);
        CHECK(a.compared > W * H * 9 / 10);
        CHECK(a.mismatched <= W * H / 200); /* different surfaces away from any edge: at most 0.5 % */
        CHECK(a.edges <= W * H / 50);       /* the 1/32-px bands around the scene's edges: about 0.5 % */
        CHECK(a.pos_fail == 0);
        CHECK(a.normal_fail == 0);
        result b = compare(&v, ref, depth, normal, id, 1.0); /* control: half a pixel off */
        printf("control (rays 0.5 px off the centre): position worst %.2e, %u of %u beyond %g\n", b.worst_pos,
               b.pos_fail, b.compared, POS_TOL);
        CHECK(b.pos_fail > b.compared / 4);
    }
    prw_ref_destroy(ref);
    free(depth);
    free(normal);
    free(id);
    prw_renderer_destroy(r);
    if (gpu) prw_gpu_destroy(gpu);
    CHECK(prw_gpu_validation_total() == 0);
    prw_scene_destroy(s);
}

static const prw_test_case cases[] = {
    {"depth_normal_vs_reference", test_depth_normal_vs_reference},
};

int main(int argc, char **argv) { return prw_test_main(argc, argv, cases, PRW_ARRAY_LEN(cases)); }
