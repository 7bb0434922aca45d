/* Scene transforms, bounds, builders, hash and add_* validation. */
#include <stdlib.h>
#include <string.h>

#include "prw_scene.h"
#include "prw_test.h"

static prw_dquat quat_axis(prw_dvec3 axis, double angle)
{
    prw_dvec3 a = prw_v3_norm(axis);
    double s = sin(angle / 2);
    prw_dquat q = {a.x * s, a.y * s, a.z * s, cos(angle / 2)};
    return q;
}

static void check_mat(const prw_dmat4 *a, const double *expect, double tol)
{
    for (int i = 0; i < 16; i++) CHECK_NEAR(a->m[i], expect[i], tol);
}

static void check_v3(prw_dvec3 a, prw_dvec3 b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

static void test_trs_composition(void)
{
    prw_scene *s = prw_scene_create();
    prw_node n = prw_node_default();
    n.translation = prw_v3(1, 2, 3);
    n.rotation = quat_axis(prw_v3(0, 0, 1), PRW_PI / 2); /* x -> y, y -> -x */
    n.scale = prw_v3(2, 3, 4);
    CHECK(prw_scene_add_node(s, &n) == 0);
    prw_scene_update(s);
    /* column-major T*R*S by hand: columns R*(2,0,0) = (0,2,0), R*(0,3,0) = (-3,0,0), (0,0,4), t */
    const double expect[16] = {0, 2, 0, 0, -3, 0, 0, 0, 0, 0, 4, 0, 1, 2, 3, 1};
    check_mat(&s->nodes[0].world, expect, 1e-12);
    /* a non-unit quaternion is normalised by update */
    s->nodes[0].rotation.x *= 3, s->nodes[0].rotation.y *= 3, s->nodes[0].rotation.z *= 3, s->nodes[0].rotation.w *= 3;
    prw_scene_update(s);
    check_mat(&s->nodes[0].world, expect, 1e-12);
    prw_scene_destroy(s);
}

static void test_hierarchy(void)
{
    prw_scene *s = prw_scene_create();
    prw_node p = prw_node_default();
    p.translation = prw_v3(10, 0, 0);
    p.rotation = quat_axis(prw_v3(0, 0, 1), PRW_PI / 2);
    p.scale = prw_v3(1, 2, 1); /* non-uniform: scales the child's offset along parent-local y */
    int pi = prw_scene_add_node(s, &p);
    prw_node c = prw_node_default();
    c.parent = pi;
    c.translation = prw_v3(0, 1, 0);
    c.rotation = quat_axis(prw_v3(1, 0, 0), PRW_PI / 2); /* y -> z, z -> -y */
    int ci = prw_scene_add_node(s, &c);
    prw_node g = prw_node_default();
    g.parent = ci;
    g.translation = prw_v3(0, 0, 1);
    int gi = prw_scene_add_node(s, &g);
    CHECK(pi == 0 && ci == 1 && gi == 2);
    prw_node bad = prw_node_default();
    bad.parent = 7;
    CHECK(prw_scene_add_node(s, &bad) == -1);
    prw_scene_update(s);
    /* child origin: parent maps (0,1,0) -> scale (0,2,0) -> rotate (-2,0,0) -> +(10,0,0) */
    prw_dvec3 o = prw_dm4_point(s->nodes[ci].world, prw_v3(0, 0, 0));
    check_v3(o, prw_v3(8, 0, 0), 1e-12);
    /* grandchild origin: child-local (0,0,1) -> Rx90 -> (0,-1,0) -> +(0,1,0) = (0,0,0) in parent ->
     * parent origin (10,0,0) */
    check_v3(prw_dm4_point(s->nodes[gi].world, prw_v3(0, 0, 0)), prw_v3(10, 0, 0), 1e-12);
    /* a child-local x unit: Rx keeps x; parent S keeps x; Rz maps to y */
    check_v3(prw_dm4_dir(s->nodes[gi].world, prw_v3(1, 0, 0)), prw_v3(0, 1, 0), 1e-12);
    /* child-local y -> (Rx) z -> parent z -> (Rz) z */
    check_v3(prw_dm4_dir(s->nodes[gi].world, prw_v3(0, 1, 0)), prw_v3(0, 0, 1), 1e-12);
    /* child-local z -> (Rx) -y -> (S) -2y -> (Rz) (2,0,0) */
    check_v3(prw_dm4_dir(s->nodes[gi].world, prw_v3(0, 0, 1)), prw_v3(2, 0, 0), 1e-12);
    /* world = parent.world * local */
    prw_dmat4 lc = prw_dm4_trs(c.translation, c.rotation, c.scale);
    prw_dmat4 w = prw_dm4_mul(s->nodes[pi].world, lc);
    check_mat(&s->nodes[ci].world, w.m, 1e-12);
    prw_scene_destroy(s);
}

static void test_inverse(void)
{
    prw_dmat4 m = prw_dm4_trs(prw_v3(3, -4, 5), quat_axis(prw_v3(1, 2, 3), 0.7), prw_v3(2, 0.5, -3));
    prw_dmat4 inv;
    CHECK(prw_dm4_inverse(m, &inv));
    prw_dmat4 id = prw_dm4_mul(m, inv);
    prw_dmat4 e = prw_dm4_identity();
    check_mat(&id, e.m, 1e-12);
    prw_dmat4 sing = prw_dm4_trs(prw_v3(0, 0, 0), quat_axis(prw_v3(0, 1, 0), 0.3), prw_v3(1, 0, 1));
    CHECK(!prw_dm4_inverse(sing, &inv));
}

static void test_decompose(void)
{
    prw_dvec3 ts[3] = {{1, 2, 3}, {-1e5, 0.5, 7}, {0, 0, 0}};
    prw_dvec3 ss[3] = {{1, 1, 1}, {2, 0.5, 3}, {-2, 1, 4}};
    prw_dvec3 axes[3] = {{0, 1, 0}, {1, 2, 3}, {-1, 0.1, 0.3}};
    for (int i = 0; i < 3; i++) {
        prw_dmat4 m = prw_dm4_trs(ts[i], quat_axis(axes[i], 0.4 + i), ss[i]);
        prw_dvec3 t, sc;
        prw_dquat q;
        CHECK(prw_decompose_trs(m, &t, &q, &sc));
        prw_dmat4 r = prw_dm4_trs(t, q, sc);
        check_mat(&r, m.m, 1e-9);
        CHECK_NEAR(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w, 1.0, 1e-12);
    }
    /* zero scale on one axis: still recomposes */
    prw_dmat4 flat = prw_dm4_trs(prw_v3(1, 1, 1), quat_axis(prw_v3(0, 0, 1), 0.5), prw_v3(2, 0, 1));
    prw_dvec3 t, sc;
    prw_dquat q;
    CHECK(prw_decompose_trs(flat, &t, &q, &sc));
    prw_dmat4 r = prw_dm4_trs(t, q, sc);
    check_mat(&r, flat.m, 1e-9);
    /* shear and projective rows are rejected */
    prw_dmat4 shear = prw_dm4_identity();
    shear.m[4] = 0.5;
    CHECK(!prw_decompose_trs(shear, &t, &q, &sc));
    prw_dmat4 proj = prw_dm4_identity();
    proj.m[3] = 0.1;
    CHECK(!prw_decompose_trs(proj, &t, &q, &sc));
}

static void test_look_at(void)
{
    prw_node n = prw_node_look_at("cam", prw_v3(1, 2, 3), prw_v3(4, 6, 3), prw_v3(0, 1, 0));
    prw_dvec3 fwd = prw_dm4_dir(n.world, prw_v3(0, 0, -1));
    check_v3(fwd, prw_v3(0.6, 0.8, 0), 1e-12);
    prw_dvec3 x = prw_dm4_dir(n.world, prw_v3(1, 0, 0));
    CHECK_NEAR(x.y, 0.0, 1e-12); /* horizontal right vector */
    CHECK_NEAR(prw_v3_dot(x, fwd), 0.0, 1e-12);
    CHECK(strcmp(n.name, "cam") == 0);
    /* straight down with up = +Y: falls back to another up, still looks down */
    prw_node d = prw_node_look_at("down", prw_v3(0, 5, 0), prw_v3(0, 0, 0), prw_v3(0, 1, 0));
    check_v3(prw_dm4_dir(d.world, prw_v3(0, 0, -1)), prw_v3(0, -1, 0), 1e-12);
    /* same in the scene after update */
    prw_scene *s = prw_scene_create();
    prw_scene_add_node(s, &n);
    prw_scene_update(s);
    check_v3(prw_dm4_dir(s->nodes[0].world, prw_v3(0, 0, -1)), prw_v3(0.6, 0.8, 0), 1e-12);
    prw_scene_destroy(s);
}

/* A little scene: a box under a rotated parent, a sphere, a quad; root offset by `off`. */
static prw_scene *build_scene(prw_dvec3 off)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    prw_material m = prw_material_default();
    int mat = prw_scene_add_material(s, &m);
    prw_node root = prw_node_default();
    root.translation = off;
    int r = prw_scene_add_node(s, &root);
    prw_node p = prw_node_default();
    p.parent = r;
    p.translation = prw_v3(1, 2, 3);
    p.rotation = quat_axis(prw_v3(1, 1, 0), 0.6);
    p.scale = prw_v3(1.5, 1.5, 1.5);
    int pi = prw_scene_add_node(s, &p);
    int b = prw_scene_add_box(s, "box", prw_v3(-1, 0, -2), prw_v3(1, 3, 2), mat, false, &e);
    int sp = prw_scene_add_sphere(s, "ball", prw_v3(4, 1, 0), 0.5, 16, 8, mat, &e);
    int q = prw_scene_add_quad(s, "floor", prw_v3(0, 0, 0), prw_v3(5, 0, 0), prw_v3(0, 0, -5), mat, &e);
    CHECK(b >= 0 && sp >= 0 && q >= 0);
    if (b < 0 || sp < 0 || q < 0) return s;
    s->nodes[b].parent = pi; /* builders make roots; re-parent (parents still precede children) */
    s->nodes[sp].parent = r;
    s->nodes[q].parent = r;
    prw_scene_update(s);
    return s;
}

static void test_bounds(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    prw_material m = prw_material_default();
    int mat = prw_scene_add_material(s, &m);
    int b = prw_scene_add_box(s, "cube", prw_v3(-1, -1, -1), prw_v3(1, 1, 1), mat, false, &e);
    CHECK_MSG(b >= 0, "%s", e.msg);
    if (b < 0) return;
    s->nodes[b].rotation = quat_axis(prw_v3(0, 1, 0), PRW_PI / 4);
    s->nodes[b].translation = prw_v3(5, 0, 0);
    prw_node parent = prw_node_default();
    parent.translation = prw_v3(0, 10, 0);
    int pi = prw_scene_add_node(s, &parent);
    CHECK(pi == 1);
    /* rebuild: the parent must precede the child, so add the box again under it */
    prw_node child = s->nodes[b];
    child.parent = pi;
    int ci = prw_scene_add_node(s, &child);
    prw_scene_update(s);
    double r2 = sqrt(2.0);
    CHECK(s->nodes[b].has_bounds);
    check_v3(s->nodes[b].world_min, prw_v3(5 - r2, -1, -r2), 1e-12);
    check_v3(s->nodes[b].world_max, prw_v3(5 + r2, 1, r2), 1e-12);
    /* propagated to the ancestor, and the scene bounds cover both */
    CHECK(s->nodes[pi].has_bounds);
    check_v3(s->nodes[pi].world_min, prw_v3(5 - r2, 9, -r2), 1e-12);
    check_v3(s->nodes[ci].world_max, prw_v3(5 + r2, 11, r2), 1e-12);
    CHECK(s->has_bounds);
    check_v3(s->bounds_min, prw_v3(5 - r2, -1, -r2), 1e-12);
    check_v3(s->bounds_max, prw_v3(5 + r2, 11, r2), 1e-12);
    /* a node without meshes below it has no bounds */
    prw_node empty = prw_node_default();
    int ei = prw_scene_add_node(s, &empty);
    prw_scene_update(s);
    CHECK(!s->nodes[ei].has_bounds);
    prw_scene_destroy(s);

    /* the same scene 1e5 m away: world bounds shift exactly, in double precision */
    prw_dvec3 off = prw_v3(1e5, -1e5, 1e5);
    prw_scene *a = build_scene(prw_v3(0, 0, 0)), *far = build_scene(off);
    CHECK(a->has_bounds && far->has_bounds);
    double ext = prw_v3_len(prw_v3_sub(a->bounds_max, a->bounds_min));
    CHECK(ext > 1);
    check_v3(prw_v3_sub(far->bounds_min, off), a->bounds_min, 1e-9 * ext);
    check_v3(prw_v3_sub(far->bounds_max, off), a->bounds_max, 1e-9 * ext);
    for (uint32_t i = 0; i < a->node_count; i++) {
        CHECK(a->nodes[i].has_bounds == far->nodes[i].has_bounds);
        if (!a->nodes[i].has_bounds) continue;
        check_v3(prw_v3_sub(far->nodes[i].world_min, off), a->nodes[i].world_min, 1e-9 * ext);
        check_v3(prw_v3_sub(far->nodes[i].world_max, off), a->nodes[i].world_max, 1e-9 * ext);
    }
    prw_scene_destroy(a);
    prw_scene_destroy(far);
}

/* Every triangle's winding agrees with its stored normals; `outward` relative to `centre`. */
static void check_winding(const prw_mesh *m, prw_dvec3 centre, int outward)
{
    int bad = 0;
    for (uint32_t t = 0; t < m->index_count; t += 3) {
        prw_dvec3 p[3], n = prw_v3(0, 0, 0);
        for (int k = 0; k < 3; k++) {
            const float *q = m->positions + 3 * m->indices[t + k];
            const float *nn = m->normals + 3 * m->indices[t + k];
            p[k] = prw_v3(q[0], q[1], q[2]);
            n = prw_v3_add(n, prw_v3(nn[0], nn[1], nn[2]));
        }
        prw_dvec3 g = prw_v3_cross(prw_v3_sub(p[1], p[0]), prw_v3_sub(p[2], p[0]));
        prw_dvec3 c = prw_v3_scale(prw_v3_add(prw_v3_add(p[0], p[1]), p[2]), 1.0 / 3);
        if (!(prw_v3_dot(g, n) > 0)) bad++;
        if (outward && !(outward * prw_v3_dot(g, prw_v3_sub(c, centre)) > 0)) bad++;
    }
    CHECK_MSG(bad == 0, "mesh '%s': %d triangles disagree", m->name, bad);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        const float *n = m->normals + 3 * v, *t = m->tangents + 4 * v;
        CHECK_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
        CHECK_NEAR(t[0] * t[0] + t[1] * t[1] + t[2] * t[2], 1.0, 1e-5);
        CHECK_NEAR(n[0] * t[0] + n[1] * t[1] + n[2] * t[2], 0.0, 1e-5);
        CHECK(t[3] == 1.0f || t[3] == -1.0f);
    }
}

static void test_builders(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    prw_material m = prw_material_default();
    int mat = prw_scene_add_material(s, &m);
    int out = prw_scene_add_box(s, "out", prw_v3(0, 0, 0), prw_v3(1, 2, 3), mat, false, &e);
    int in = prw_scene_add_box(s, "room", prw_v3(-5, 0, -5), prw_v3(5, 3, 5), mat, true, &e);
    int q = prw_scene_add_quad(s, "q", prw_v3(1, 1, 1), prw_v3(2, 0, 0), prw_v3(0, 0, -1), mat, &e);
    int sp = prw_scene_add_sphere(s, "sp", prw_v3(0, 0, 0), 2, 12, 6, mat, &e);
    CHECK(out >= 0 && in >= 0 && q >= 0 && sp >= 0);
    if (out < 0 || in < 0 || q < 0 || sp < 0) return;
    prw_scene_update(s);
    const prw_mesh *mb = &s->meshes[s->groups[s->nodes[out].mesh_group].first];
    CHECK(mb->vertex_count == 24 && mb->index_count == 36);
    check_winding(mb, prw_v3(0, 0, 0), 1);
    check_v3(s->nodes[out].translation, prw_v3(0.5, 1, 1.5), 0);
    check_v3(s->nodes[out].world_min, prw_v3(0, 0, 0), 1e-12);
    check_v3(s->nodes[out].world_max, prw_v3(1, 2, 3), 1e-12);
    const prw_mesh *mr = &s->meshes[s->groups[s->nodes[in].mesh_group].first];
    check_winding(mr, prw_v3(0, 0, 0), -1);
    const prw_mesh *mq = &s->meshes[s->groups[s->nodes[q].mesh_group].first];
    check_winding(mq, prw_v3(0, 0, 0), 0);
    /* cross((2,0,0), (0,0,-1)) = (0,2,0): faces up; tangent along half_u */
    CHECK_NEAR(mq->normals[1], 1.0, 1e-6);
    CHECK_NEAR(mq->tangents[0], 1.0, 1e-6);
    CHECK(mq->tangents[3] == 1.0f);
    const prw_mesh *ms = &s->meshes[s->groups[s->nodes[sp].mesh_group].first];
    CHECK(ms->vertex_count == 13 * 7);
    CHECK(ms->index_count == 3 * 12 * (2 * 6 - 2));
    check_winding(ms, prw_v3(0, 0, 0), 1);
    check_v3(s->nodes[sp].world_max, prw_v3(2, 2, 2), 1e-6);
    /* invalid inputs */
    CHECK(prw_scene_add_box(s, "bad", prw_v3(1, 0, 0), prw_v3(0, 1, 1), mat, false, &e) == -1);
    CHECK(strstr(e.msg, "bad") != NULL);
    CHECK(prw_scene_add_quad(s, "par", prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(2, 0, 0), mat, &e) == -1);
    CHECK(prw_scene_add_sphere(s, "tiny", prw_v3(0, 0, 0), 1, 2, 2, mat, &e) == -1);
    CHECK(prw_scene_add_quad(s, "two\nlines", prw_v3(0, 0, 0), prw_v3(1, 0, 0), prw_v3(1, 0, 0), mat, &e) == -1);
    CHECK_MSG(strchr(e.msg, '\n') == NULL && strstr(e.msg, "two?lines"), "%s", e.msg); /* one-line messages */
    CHECK(prw_scene_add_sphere(s, "nan", prw_v3(0, 0, 0), NAN, 8, 8, mat, &e) == -1);
    CHECK(prw_scene_add_box(s, "nomat", prw_v3(0, 0, 0), prw_v3(1, 1, 1), 5, false, &e) == -1);
    CHECK(strstr(e.msg, "material 5") != NULL);
    uint32_t nodes = s->node_count, meshes = s->mesh_count;
    CHECK(nodes == 4 && meshes == 4);
    prw_scene_destroy(s);
}

static void test_add_mesh(void)
{
    prw_scene *s = prw_scene_create();
    prw_error e;
    prw_material mat = prw_material_default();
    prw_scene_add_material(s, &mat);
    /* an L-shaped pair of triangles, one 4x the area of the other, without normals */
    float pos[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0, 0.5f};
    uint32_t idx[] = {0, 1, 2, 0, 3, 1}; /* second triangle in the xz plane, normal +y */
    prw_mesh m;
    memset(&m, 0, sizeof m);
    strcpy(m.name, "L");
    m.positions = pos;
    m.indices = idx;
    m.vertex_count = 4;
    m.index_count = 6;
    int mi = prw_scene_add_mesh(s, &m, &e);
    CHECK_MSG(mi == 0, "%s", e.msg);
    if (mi != 0) return;
    const prw_mesh *d = &s->meshes[0];
    /* vertex 0: area-weighted (0,0,4)/2 + (0,1,0)*0.5 (areas 2 and 0.5) -> normalize (0, 0.5, 2) */
    double l = sqrt(0.25 + 4);
    CHECK_NEAR(d->normals[0], 0, 1e-6);
    CHECK_NEAR(d->normals[1], 0.5 / l, 1e-6);
    CHECK_NEAR(d->normals[2], 2 / l, 1e-6);
    CHECK_NEAR(d->normals[3 * 2 + 2], 1, 1e-6); /* vertex 2: only the xy triangle */
    CHECK(d->uvs && d->uvs[0] == 0 && d->tangents);
    check_v3(d->bounds_min, prw_v3(0, 0, 0), 0);
    check_v3(d->bounds_max, prw_v3(2, 2, 0.5), 0);
    /* the copy is deep */
    pos[0] = 99;
    CHECK(d->positions[0] == 0);

    uint32_t bad_idx[] = {0, 1, 4};
    m.indices = bad_idx;
    m.index_count = 3;
    CHECK(prw_scene_add_mesh(s, &m, &e) == -1);
    CHECK_MSG(strstr(e.msg, "mesh 'L'") && strstr(e.msg, "out of range"), "%s", e.msg);
    m.indices = idx;
    m.index_count = 5;
    CHECK(prw_scene_add_mesh(s, &m, &e) == -1);
    CHECK(strstr(e.msg, "multiple of 3") != NULL);
    m.index_count = 6;
    pos[4] = NAN;
    CHECK(prw_scene_add_mesh(s, &m, &e) == -1);
    CHECK(strstr(e.msg, "not finite") != NULL);
    pos[4] = 0;
    m.material = 3;
    CHECK(prw_scene_add_mesh(s, &m, &e) == -1);
    CHECK(s->mesh_count == 1);
    prw_scene_destroy(s);
}

static void test_lights_and_cameras(void)
{
    prw_scene *s = prw_scene_create();
    prw_light l;
    memset(&l, 0, sizeof l);
    l.color[0] = 1;
    l.intensity = 5;
    int a = prw_scene_add_light(s, &l);
    CHECK_NEAR(s->lights[a].color[0], 1 / 0.2126, 1e-5);
    CHECK(s->lights[a].color[1] == 0);
    l.color[0] = 0.3f, l.color[1] = 0.6f, l.color[2] = 0.9f;
    int b = prw_scene_add_light(s, &l);
    const float *c = s->lights[b].color;
    CHECK_NEAR(0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2], 1.0, 1e-6);
    CHECK_NEAR(c[2] / c[0], 3.0, 1e-5);
    l.color[0] = l.color[1] = l.color[2] = 0;
    int k = prw_scene_add_light(s, &l);
    CHECK(s->lights[k].color[0] == 1 && s->lights[k].color[1] == 1 && s->lights[k].color[2] == 1);
    CHECK(s->lights[k].intensity == 5);

    CHECK(prw_scene_find_camera(s, NULL) == -1);
    prw_camera cam;
    memset(&cam, 0, sizeof cam);
    strcpy(cam.name, "main");
    prw_scene_add_camera(s, &cam);
    strcpy(cam.name, "side");
    prw_scene_add_camera(s, &cam);
    CHECK(prw_scene_find_camera(s, NULL) == 0);
    CHECK(prw_scene_find_camera(s, "") == 0);
    CHECK(prw_scene_find_camera(s, "side") == 1);
    CHECK(prw_scene_find_camera(s, "nope") == -1);
    prw_scene_destroy(s);
}

static void test_hash(void)
{
    prw_scene *a = build_scene(prw_v3(0, 0, 0)), *b = build_scene(prw_v3(0, 0, 0));
    CHECK(prw_scene_hash(a) == prw_scene_hash(b));
    uint64_t h0 = prw_scene_hash(a);
    a->materials[0].roughness = 0.5f;
    CHECK(prw_scene_hash(a) != h0);
    a->materials[0].roughness = 1.0f;
    CHECK(prw_scene_hash(a) == h0);
    a->materials[0].specular = 0.0f; /* every material parameter keys the reference cache */
    CHECK(prw_scene_hash(a) != h0);
    a->materials[0].specular = 1.0f;
    CHECK(prw_scene_hash(a) == h0);
    a->nodes[1].translation.x += 1e-9;
    CHECK(prw_scene_hash(a) != h0);
    a->nodes[1].translation.x = b->nodes[1].translation.x;
    a->meshes[0].positions[5] += 0.25f;
    CHECK(prw_scene_hash(a) != h0);
    a->meshes[0].positions[5] = b->meshes[0].positions[5];
    prw_light l;
    memset(&l, 0, sizeof l);
    l.intensity = 1;
    prw_scene_add_light(a, &l);
    prw_scene_add_light(b, &l);
    uint64_t h1 = prw_scene_hash(a);
    CHECK(h1 != h0 && h1 == prw_scene_hash(b));
    a->lights[0].intensity = 2;
    CHECK(prw_scene_hash(a) != h1);
    /* names do not affect the image */
    strcpy(a->lights[0].name, "renamed");
    a->lights[0].intensity = 1;
    CHECK(prw_scene_hash(a) == h1);
    prw_scene_destroy(a);
    prw_scene_destroy(b);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"trs_composition", test_trs_composition},
        {"hierarchy", test_hierarchy},
        {"inverse", test_inverse},
        {"decompose", test_decompose},
        {"look_at", test_look_at},
        {"bounds", test_bounds},
        {"builders", test_builders},
        {"add_mesh", test_add_mesh},
        {"lights_and_cameras", test_lights_and_cameras},
        {"hash", test_hash},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
