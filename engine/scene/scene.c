/* scene.c — scene storage: growable arrays, add_*, update (world matrices + bounds), hash,
 * camera lookup, builder helpers (box, quad, sphere), TRS decomposition, rollback. */
#include "scene_internal.h"

#include <stdarg.h>
#include <stdio.h>

#include "prw_lod_node.h"

#include <stdlib.h>
#include <string.h>

/* ---- storage ---- */

/* Arrays grow when the count reaches a power of two, so capacity is implicit (no extra field). */
static void *grow(void *p, uint32_t count, size_t elem)
{
    if (count == 0 || (count & (count - 1)) == 0) {
        size_t cap = count ? (size_t)count * 2 : 1;
        p = prw_realloc(p, cap * elem);
    }
    return p;
}

void prw_copy_name(char dst[PRW_NAME_MAX], const char *src)
{
    if (!src) src = "";
    size_t n = strlen(src);
    if (n > PRW_NAME_MAX - 1) n = PRW_NAME_MAX - 1;
    /* control characters would break one-line messages and logs */
    for (size_t i = 0; i < n; i++) dst[i] = ((unsigned char)src[i] < 0x20 || src[i] == 0x7f) ? '?' : src[i];
    dst[n] = '\0';
}

prw_scene *prw_scene_create(void)
{
    prw_scene *s = prw_calloc(1, sizeof *s);
    return s;
}

static void free_mesh(prw_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->uvs);
    free(m->tangents);
    free(m->uvs1);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

void prw_scene_destroy(prw_scene *s)
{
    if (!s) return;
    for (uint32_t i = 0; i < s->mesh_count; i++) free_mesh(&s->meshes[i]);
    for (uint32_t i = 0; i < s->texture_count; i++) free(s->textures[i].rgba8);
    free(s->meshes);
    free(s->groups);
    free(s->materials);
    free(s->textures);
    free(s->nodes);
    free(s->cameras);
    free(s->lights);
    for (uint32_t i = 0; i < s->nurbs_count; i++) prw_scene_nurbs_baked_free(&s->nurbs_baked[i]);
    free(s->nurbs);
    free(s->nurbs_baked);
    free(s->warnings);
    free(s);
}

prw_scene_mark prw_scene_mark_get(const prw_scene *s)
{
    prw_scene_mark m = {s->mesh_count, s->group_count, s->material_count, s->texture_count,
                        s->node_count, s->camera_count, s->light_count, s->nurbs_count, s->warning_count};
    return m;
}

void prw_scene_rollback(prw_scene *s, prw_scene_mark m)
{
    for (uint32_t i = m.meshes; i < s->mesh_count; i++) free_mesh(&s->meshes[i]);
    for (uint32_t i = m.textures; i < s->texture_count; i++) {
        free(s->textures[i].rgba8);
        s->textures[i].rgba8 = NULL;
    }
    if (m.meshes < s->mesh_count) s->mesh_count = m.meshes;
    if (m.groups < s->group_count) s->group_count = m.groups;
    if (m.materials < s->material_count) s->material_count = m.materials;
    if (m.textures < s->texture_count) s->texture_count = m.textures;
    if (m.nodes < s->node_count) s->node_count = m.nodes;
    if (m.cameras < s->camera_count) s->camera_count = m.cameras;
    if (m.lights < s->light_count) s->light_count = m.lights;
    for (uint32_t i = m.nurbs; i < s->nurbs_count; i++) prw_scene_nurbs_baked_free(&s->nurbs_baked[i]);
    if (m.nurbs < s->nurbs_count) s->nurbs_count = m.nurbs;
    if (m.warnings < s->warning_count) s->warning_count = m.warnings;
}

/* ---- warnings ---- */

int prw_scene_add_warning(prw_scene *s, prw_warning_kind kind, const char *fmt, ...)
{
    s->warnings = grow(s->warnings, s->warning_count, sizeof *s->warnings);
    prw_scene_warning *w = &s->warnings[s->warning_count];
    memset(w, 0, sizeof *w);
    w->kind = kind;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->msg, sizeof w->msg, fmt, ap);
    va_end(ap);
    for (char *c = w->msg; *c; c++) /* one line, printable */
        if ((unsigned char)*c < 0x20 || *c == 0x7f) *c = *c == '\n' ? ';' : '?';
    return (int)s->warning_count++;
}

int prw_scene_find_warning(const prw_scene *s, prw_warning_kind kind)
{
    for (uint32_t i = 0; i < s->warning_count; i++)
        if (s->warnings[i].kind == kind) return (int)i;
    return -1;
}

/* Something emits light: a light, an emissive material used by a mesh or NURBS model, or an environment. */
static bool scene_has_light(const prw_scene *s)
{
    if (s->light_count || s->environment.present) return true;
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        int mi = s->meshes[i].material;
        if (mi < 0 || (uint32_t)mi >= s->material_count) continue;
        const float *em = s->materials[mi].emission;
        if (em[0] > 0 || em[1] > 0 || em[2] > 0) return true;
    }
    for (uint32_t i = 0; i < s->nurbs_count; i++) {
        int mi = s->nurbs[i].material;
        if (mi < 0 || (uint32_t)mi >= s->material_count) continue;
        const float *em = s->materials[mi].emission;
        if (em[0] > 0 || em[1] > 0 || em[2] > 0) return true;
    }
    return false;
}

void prw_scene_note_missing(prw_scene *s, const char *file)
{
    if (!scene_has_light(s) && prw_scene_find_warning(s, PRW_WARN_NO_LIGHT) < 0)
        prw_scene_add_warning(s, PRW_WARN_NO_LIGHT, "%s: no light (no light source, emissive material or environment)",
                              file);
    if (s->camera_count == 0 && prw_scene_find_warning(s, PRW_WARN_NO_CAMERA) < 0)
        prw_scene_add_warning(s, PRW_WARN_NO_CAMERA, "%s: no camera", file);
}

/* ---- texture transforms ---- */

void prw_tex_transform_apply(const prw_tex_transform *t, const float uv[2], float out[2])
{
    double c = cos((double)t->rotation), sn = sin((double)t->rotation);
    double su = (double)t->scale[0] * uv[0], sv = (double)t->scale[1] * uv[1];
    double u = t->offset[0] + c * su + sn * sv, v = t->offset[1] - sn * su + c * sv;
    out[0] = (float)u;
    out[1] = (float)v;
}

bool prw_tex_transform_is_identity(const prw_tex_transform *t)
{
    return t->offset[0] == 0.0f && t->offset[1] == 0.0f && t->rotation == 0.0f && t->scale[0] == 1.0f &&
           t->scale[1] == 1.0f;
}

/* ---- meshes ---- */

static bool all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

static float *dup_floats(const float *v, size_t n)
{
    float *d = prw_malloc(n * sizeof *d);
    memcpy(d, v, n * sizeof *d);
    return d;
}

/* Area-weighted vertex normals (the cross product of two edges is twice the area times the unit
 * normal); vertices touched only by degenerate triangles get +Z. */
static void compute_normals(const prw_mesh *m, double *acc /* 3 per vertex, zeroed */)
{
    for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
        uint32_t i[3] = {m->indices[t], m->indices[t + 1], m->indices[t + 2]};
        prw_dvec3 p[3];
        for (int k = 0; k < 3; k++)
            p[k] = prw_v3(m->positions[3 * i[k]], m->positions[3 * i[k] + 1], m->positions[3 * i[k] + 2]);
        prw_dvec3 c = prw_v3_cross(prw_v3_sub(p[1], p[0]), prw_v3_sub(p[2], p[0]));
        for (int k = 0; k < 3; k++) {
            acc[3 * i[k]] += c.x;
            acc[3 * i[k] + 1] += c.y;
            acc[3 * i[k] + 2] += c.z;
        }
    }
}

int prw_scene_add_mesh(prw_scene *s, const prw_mesh *m, prw_error *e)
{
    char nm[PRW_NAME_MAX];
    prw_copy_name(nm, m->name[0] ? m->name : "(unnamed)");
    if (!m->positions || !m->indices || m->vertex_count == 0 || m->index_count == 0) {
        prw_fail(e, "mesh '%s': needs positions and indices (%u vertices, %u indices)", nm,
                 m->vertex_count, m->index_count);
        return -1;
    }
    if (m->index_count % 3 != 0) {
        prw_fail(e, "mesh '%s': index count %u is not a multiple of 3", nm, m->index_count);
        return -1;
    }
    if (m->material < 0 || (uint32_t)m->material >= s->material_count) {
        prw_fail(e, "mesh '%s': material %d does not exist (%u materials)", nm, m->material,
                 s->material_count);
        return -1;
    }
    for (uint32_t i = 0; i < m->index_count; i++) {
        if (m->indices[i] >= m->vertex_count) {
            prw_fail(e, "mesh '%s': index %u at position %u is out of range (vertex count %u)", nm,
                     m->indices[i], i, m->vertex_count);
            return -1;
        }
    }
    size_t nv = m->vertex_count;
    if (!all_finite(m->positions, 3 * nv)) return prw_fail(e, "mesh '%s': positions are not finite", nm), -1;
    if (m->normals && !all_finite(m->normals, 3 * nv)) return prw_fail(e, "mesh '%s': normals are not finite", nm), -1;
    if (m->uvs && !all_finite(m->uvs, 2 * nv)) return prw_fail(e, "mesh '%s': uvs are not finite", nm), -1;
    if (m->tangents && !all_finite(m->tangents, 4 * nv)) return prw_fail(e, "mesh '%s': tangents are not finite", nm), -1;
    if (m->uvs1 && !all_finite(m->uvs1, 2 * nv)) return prw_fail(e, "mesh '%s': uvs (set 1) are not finite", nm), -1;

    prw_mesh d;
    memset(&d, 0, sizeof d);
    prw_copy_name(d.name, m->name);
    d.vertex_count = m->vertex_count;
    d.index_count = m->index_count;
    d.material = m->material;
    d.positions = dup_floats(m->positions, 3 * nv);
    d.indices = prw_malloc((size_t)m->index_count * sizeof *d.indices);
    memcpy(d.indices, m->indices, (size_t)m->index_count * sizeof *d.indices);
    d.uvs = m->uvs ? dup_floats(m->uvs, 2 * nv) : prw_calloc(2 * nv, sizeof(float));
    d.uvs1 = m->uvs1 ? dup_floats(m->uvs1, 2 * nv) : NULL;

    /* Normals: given ones are renormalised; missing or zero-length ones are area-weighted. */
    d.normals = prw_malloc(3 * nv * sizeof(float));
    double *acc = NULL;
    for (size_t v = 0; v < nv; v++) {
        prw_dvec3 n = prw_v3(0, 0, 0);
        if (m->normals) n = prw_v3(m->normals[3 * v], m->normals[3 * v + 1], m->normals[3 * v + 2]);
        double len = prw_v3_len(n);
        if (!(len > 1e-20)) {
            if (!acc) {
                acc = prw_calloc(3 * nv, sizeof *acc);
                compute_normals(&d, acc);
            }
            n = prw_v3(acc[3 * v], acc[3 * v + 1], acc[3 * v + 2]);
            len = prw_v3_len(n);
            if (!(len > 0) || !isfinite(len)) n = prw_v3(0, 0, 1), len = 1;
        }
        d.normals[3 * v] = (float)(n.x / len);
        d.normals[3 * v + 1] = (float)(n.y / len);
        d.normals[3 * v + 2] = (float)(n.z / len);
    }
    free(acc);

    /* Tangents: given ones are renormalised (w -> +-1) unless any is unusable; else generated. */
    bool regenerate = m->tangents == NULL;
    if (!regenerate) {
        d.tangents = dup_floats(m->tangents, 4 * nv);
        for (size_t v = 0; v < nv && !regenerate; v++) {
            float *t = d.tangents + 4 * v;
            double len = sqrt((double)t[0] * t[0] + (double)t[1] * t[1] + (double)t[2] * t[2]);
            if (!(len > 1e-20)) {
                regenerate = true;
                break;
            }
            t[0] = (float)(t[0] / len);
            t[1] = (float)(t[1] / len);
            t[2] = (float)(t[2] / len);
            t[3] = t[3] < 0 ? -1.0f : 1.0f;
        }
    }
    if (regenerate) {
        free(d.tangents);
        d.tangents = NULL;
        prw_mesh_generate_tangents(&d);
    }

    prw_dvec3 lo = prw_v3(INFINITY, INFINITY, INFINITY), hi = prw_v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t v = 0; v < nv; v++) {
        prw_dvec3 p = prw_v3(d.positions[3 * v], d.positions[3 * v + 1], d.positions[3 * v + 2]);
        lo = prw_v3_min(lo, p);
        hi = prw_v3_max(hi, p);
    }
    d.bounds_min = lo;
    d.bounds_max = hi;

    s->meshes = grow(s->meshes, s->mesh_count, sizeof *s->meshes);
    s->meshes[s->mesh_count] = d;
    return (int)s->mesh_count++;
}

int prw_scene_add_group(prw_scene *s, const char *name, uint32_t first, uint32_t count)
{
    if ((uint64_t)first + count > s->mesh_count) return -1;
    prw_mesh_group g;
    memset(&g, 0, sizeof g);
    prw_copy_name(g.name, name);
    g.first = first;
    g.count = count;
    s->groups = grow(s->groups, s->group_count, sizeof *s->groups);
    s->groups[s->group_count] = g;
    return (int)s->group_count++;
}

int prw_scene_add_material(prw_scene *s, const prw_material *m)
{
    s->materials = grow(s->materials, s->material_count, sizeof *s->materials);
    prw_material *d = &s->materials[s->material_count];
    *d = *m;
    prw_copy_name(d->name, m->name);
    return (int)s->material_count++;
}

int prw_scene_add_texture(prw_scene *s, const prw_texture *t)
{
    if (t->width <= 0 || t->height <= 0 || !t->rgba8) return -1;
    size_t n = (size_t)t->width * (size_t)t->height * 4;
    s->textures = grow(s->textures, s->texture_count, sizeof *s->textures);
    prw_texture *d = &s->textures[s->texture_count];
    *d = *t;
    prw_copy_name(d->name, t->name);
    d->rgba8 = prw_malloc(n);
    memcpy(d->rgba8, t->rgba8, n);
    return (int)s->texture_count++;
}

int prw_scene_add_node(prw_scene *s, const prw_node *n)
{
    if (n->parent < -1 || (n->parent >= 0 && (uint32_t)n->parent >= s->node_count)) return -1;
    s->nodes = grow(s->nodes, s->node_count, sizeof *s->nodes);
    prw_node *d = &s->nodes[s->node_count];
    *d = *n;
    prw_copy_name(d->name, n->name);
    d->world = prw_dm4_trs(d->translation, d->rotation, d->scale);
    d->has_bounds = false;
    return (int)s->node_count++;
}

int prw_scene_add_camera(prw_scene *s, const prw_camera *c)
{
    s->cameras = grow(s->cameras, s->camera_count, sizeof *s->cameras);
    prw_camera *d = &s->cameras[s->camera_count];
    *d = *c;
    prw_copy_name(d->name, c->name);
    return (int)s->camera_count++;
}

int prw_scene_add_nurbs(prw_scene *s, const prw_scene_nurbs *n)
{
    if (n->node < 0 || (uint32_t)n->node >= s->node_count || n->material < 0 ||
        (uint32_t)n->material >= s->material_count || n->grid[0] < 1 || n->grid[1] < 1)
        return -1;
    s->nurbs = grow(s->nurbs, s->nurbs_count, sizeof *s->nurbs);
    s->nurbs_baked = grow(s->nurbs_baked, s->nurbs_count, sizeof *s->nurbs_baked); /* same capacity */
    memset(&s->nurbs_baked[s->nurbs_count], 0, sizeof *s->nurbs_baked);
    s->nurbs[s->nurbs_count] = *n;
    prw_copy_name(s->nurbs[s->nurbs_count].name, n->name);
    return (int)s->nurbs_count++;
}

int prw_scene_add_light(prw_scene *s, const prw_light *l)
{
    s->lights = grow(s->lights, s->light_count, sizeof *s->lights);
    prw_light *d = &s->lights[s->light_count];
    *d = *l;
    prw_copy_name(d->name, l->name);
    /* Chromaticity normalised to luminance Y = 1; black, negative or non-finite -> white. */
    double c[3];
    for (int i = 0; i < 3; i++) c[i] = isfinite(l->color[i]) && l->color[i] > 0 ? l->color[i] : 0.0;
    double y = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    if (!(y > 1e-30)) c[0] = c[1] = c[2] = y = 1.0;
    for (int i = 0; i < 3; i++) d->color[i] = (float)(c[i] / y);
    return (int)s->light_count++;
}

prw_node prw_node_default(void)
{
    prw_node n;
    memset(&n, 0, sizeof n);
    n.parent = -1;
    n.rotation.w = 1.0;
    n.scale = prw_v3(1, 1, 1);
    n.mesh_group = n.camera = n.light = -1;
    n.world = prw_dm4_identity();
    return n;
}

prw_material prw_material_default(void)
{
    prw_material m;
    memset(&m, 0, sizeof m);
    prw_copy_name(m.name, "default");
    for (int i = 0; i < 4; i++) m.base_color[i] = 1.0f;
    m.base_color_tex = m.metal_rough_tex = m.normal_tex = m.emissive_tex = -1;
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.specular = 1.0f;
    m.normal_scale = 1.0f;
    m.alpha_mode = PRW_ALPHA_OPAQUE;
    m.alpha_cutoff = 0.5f;
    for (int i = 0; i < PRW_TEX_SLOT_COUNT; i++) m.tex_xf[i].scale[0] = m.tex_xf[i].scale[1] = 1.0f;
    m.clearcoat_tex = m.clearcoat_roughness_tex = m.clearcoat_normal_tex = -1;
    m.clearcoat_normal_scale = 1.0f;
    return m;
}

/* ---- rotations ---- */

prw_dquat prw_quat_from_axes(prw_dvec3 x, prw_dvec3 y, prw_dvec3 z)
{
    /* mRC = row R, column C of the rotation whose columns are x, y, z. */
    double m00 = x.x, m10 = x.y, m20 = x.z;
    double m01 = y.x, m11 = y.y, m21 = y.z;
    double m02 = z.x, m12 = z.y, m22 = z.z;
    double tr = m00 + m11 + m22;
    prw_dquat q;
    if (tr > 0) {
        double S = sqrt(tr + 1.0) * 2;
        q.w = 0.25 * S;
        q.x = (m21 - m12) / S;
        q.y = (m02 - m20) / S;
        q.z = (m10 - m01) / S;
    } else if (m00 > m11 && m00 > m22) {
        double S = sqrt(1.0 + m00 - m11 - m22) * 2;
        q.w = (m21 - m12) / S;
        q.x = 0.25 * S;
        q.y = (m01 + m10) / S;
        q.z = (m02 + m20) / S;
    } else if (m11 > m22) {
        double S = sqrt(1.0 + m11 - m00 - m22) * 2;
        q.w = (m02 - m20) / S;
        q.x = (m01 + m10) / S;
        q.y = 0.25 * S;
        q.z = (m12 + m21) / S;
    } else {
        double S = sqrt(1.0 + m22 - m00 - m11) * 2;
        q.w = (m10 - m01) / S;
        q.x = (m02 + m20) / S;
        q.y = (m12 + m21) / S;
        q.z = 0.25 * S;
    }
    double l = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(l > 0) || !isfinite(l)) {
        prw_dquat id = {0, 0, 0, 1};
        return id;
    }
    double sgn = q.w < 0 ? -1.0 : 1.0; /* canonical hemisphere, for deterministic output */
    q.x *= sgn / l;
    q.y *= sgn / l;
    q.z *= sgn / l;
    q.w *= sgn / l;
    return q;
}

/* A unit vector orthogonal to unit n, chosen deterministically. */
static prw_dvec3 any_perpendicular(prw_dvec3 n)
{
    prw_dvec3 a = fabs(n.x) < 0.9 ? prw_v3(1, 0, 0) : prw_v3(0, 1, 0);
    return prw_v3_norm(prw_v3_sub(a, prw_v3_scale(n, prw_v3_dot(a, n))));
}

bool prw_decompose_trs(prw_dmat4 m, prw_dvec3 *t, prw_dquat *r, prw_dvec3 *scale)
{
    for (int i = 0; i < 16; i++)
        if (!isfinite(m.m[i])) return false;
    if (fabs(m.m[3]) > 1e-9 || fabs(m.m[7]) > 1e-9 || fabs(m.m[11]) > 1e-9 || fabs(m.m[15] - 1.0) > 1e-9)
        return false;
    prw_dvec3 c[3] = {prw_v3(m.m[0], m.m[1], m.m[2]), prw_v3(m.m[4], m.m[5], m.m[6]),
                      prw_v3(m.m[8], m.m[9], m.m[10])};
    double len[3], maxlen = 0;
    for (int i = 0; i < 3; i++) {
        len[i] = prw_v3_len(c[i]);
        maxlen = fmax(maxlen, len[i]);
    }
    bool zero[3];
    int nzero = 0;
    for (int i = 0; i < 3; i++) {
        zero[i] = !(len[i] > 1e-12 * maxlen) || len[i] == 0;
        if (zero[i]) nzero++;
        else c[i] = prw_v3_scale(c[i], 1.0 / len[i]);
    }
    if (nzero == 3) {
        for (int i = 0; i < 3; i++) c[i] = prw_v3(i == 0, i == 1, i == 2);
    } else if (nzero == 2) {
        int k = zero[0] ? (zero[1] ? 2 : 1) : 0;
        int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        c[k1] = any_perpendicular(c[k]);
        c[k2] = prw_v3_cross(c[k], c[k1]);
    } else if (nzero == 1) {
        int k = zero[0] ? 0 : (zero[1] ? 1 : 2);
        c[k] = prw_v3_norm(prw_v3_cross(c[(k + 1) % 3], c[(k + 2) % 3]));
    }
    for (int i = 0; i < 3; i++)
        if (fabs(prw_v3_dot(c[i], c[(i + 1) % 3])) > 1e-4) return false; /* shear */
    double sx = len[0], sy = len[1], sz = len[2];
    if (prw_v3_dot(prw_v3_cross(c[0], c[1]), c[2]) < 0) {
        sx = -sx;
        c[0] = prw_v3_scale(c[0], -1.0);
    }
    *t = prw_v3(m.m[12], m.m[13], m.m[14]);
    *scale = prw_v3(sx, sy, sz);
    *r = prw_quat_from_axes(c[0], c[1], c[2]);
    return true;
}

prw_node prw_node_look_at(const char *name, prw_dvec3 position, prw_dvec3 target, prw_dvec3 up)
{
    prw_node n = prw_node_default();
    prw_copy_name(n.name, name);
    n.translation = position;
    prw_dvec3 z = prw_v3_sub(position, target); /* the node looks down -Z */
    if (!(prw_v3_len(z) > 0)) z = prw_v3(0, 0, 1);
    z = prw_v3_norm(z);
    prw_dvec3 x = prw_v3_cross(up, z);
    if (!(prw_v3_len(x) > 1e-9 * (prw_v3_len(up) + 1e-300))) {
        prw_dvec3 alt = fabs(z.y) < 0.9 ? prw_v3(0, 1, 0) : prw_v3(0, 0, -1);
        x = prw_v3_cross(alt, z);
    }
    x = prw_v3_norm(x);
    prw_dvec3 y = prw_v3_cross(z, x);
    n.rotation = prw_quat_from_axes(x, y, z);
    n.world = prw_dm4_trs(n.translation, n.rotation, n.scale);
    return n;
}

/* ---- update ---- */

static prw_dmat4 node_local(const prw_node *n)
{
    prw_dquat q = n->rotation;
    double l = sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (l > 0 && isfinite(l)) {
        q.x /= l;
        q.y /= l;
        q.z /= l;
        q.w /= l;
    } else {
        q.x = q.y = q.z = 0;
        q.w = 1;
    }
    return prw_dm4_trs(n->translation, q, n->scale);
}

static void merge_bounds(bool *has, prw_dvec3 *lo, prw_dvec3 *hi, prw_dvec3 a, prw_dvec3 b)
{
    if (!*has) {
        *lo = a;
        *hi = b;
        *has = true;
    } else {
        *lo = prw_v3_min(*lo, a);
        *hi = prw_v3_max(*hi, b);
    }
}

void prw_scene_update(prw_scene *s)
{
    for (uint32_t i = 0; i < s->node_count; i++) {
        prw_node *n = &s->nodes[i];
        prw_dmat4 local = node_local(n);
        /* parents precede children (add order); anything else is treated as a root */
        if (n->parent >= 0 && (uint32_t)n->parent < i) n->world = prw_dm4_mul(s->nodes[n->parent].world, local);
        else n->world = local;
        n->has_bounds = false;
        if (n->mesh_group < 0 || (uint32_t)n->mesh_group >= s->group_count) continue;
        const prw_mesh_group *g = &s->groups[n->mesh_group];
        for (uint32_t k = g->first; k < g->first + g->count && k < s->mesh_count; k++) {
            const prw_mesh *m = &s->meshes[k];
            for (int c = 0; c < 8; c++) {
                prw_dvec3 p = prw_v3(c & 1 ? m->bounds_max.x : m->bounds_min.x,
                                     c & 2 ? m->bounds_max.y : m->bounds_min.y,
                                     c & 4 ? m->bounds_max.z : m->bounds_min.z);
                p = prw_dm4_point(n->world, p);
                merge_bounds(&n->has_bounds, &n->world_min, &n->world_max, p, p);
            }
        }
    }
    /* children follow their parents, so a reverse sweep folds each subtree into its root */
    for (uint32_t i = s->node_count; i-- > 0;) {
        prw_node *n = &s->nodes[i];
        if (!n->has_bounds || n->parent < 0 || (uint32_t)n->parent >= i) continue;
        prw_node *p = &s->nodes[n->parent];
        merge_bounds(&p->has_bounds, &p->world_min, &p->world_max, n->world_min, n->world_max);
    }
    s->has_bounds = false;
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *n = &s->nodes[i];
        if (n->has_bounds) merge_bounds(&s->has_bounds, &s->bounds_min, &s->bounds_max, n->world_min, n->world_max);
    }
    /* NURBS models (issue 7): every instance's model box, transformed */
    for (uint32_t i = 0; i < s->nurbs_count; i++) {
        const prw_scene_nurbs *nb = &s->nurbs[i];
        if (nb->node < 0 || (uint32_t)nb->node >= s->node_count) continue;
        for (int gi = 0; gi < nb->grid[0]; gi++)
            for (int gj = 0; gj < nb->grid[1]; gj++)
                for (int c = 0; c < 8; c++) {
                    prw_dvec3 p = prw_v3(c & 1 ? nb->model_max.x : nb->model_min.x,
                                         c & 2 ? nb->model_max.y : nb->model_min.y,
                                         c & 4 ? nb->model_max.z : nb->model_min.z);
                    p = prw_dm4_point(s->nodes[nb->node].world, p);
                    p.x += gi * nb->spacing[0];
                    p.z += gj * nb->spacing[1];
                    merge_bounds(&s->has_bounds, &s->bounds_min, &s->bounds_max, p, p);
                }
    }
    if (!s->has_bounds) s->bounds_min = s->bounds_max = prw_v3(0, 0, 0);
}

int prw_scene_find_camera(const prw_scene *s, const char *name)
{
    if (s->camera_count == 0) return -1;
    if (!name || !name[0]) return 0;
    for (uint32_t i = 0; i < s->camera_count; i++)
        if (strncmp(s->cameras[i].name, name, PRW_NAME_MAX) == 0) return (int)i;
    return -1;
}

/* ---- hash (field by field: struct padding must not leak into the hash) ---- */

#define H(h, v) ((h) = prw_hash64(&(v), sizeof(v), (h)))
#define HA(h, p, n) ((h) = (p) ? prw_hash64((p), (n), (h)) : prw_hash64("", 1, (h)))

static uint64_t hash_v3(uint64_t h, prw_dvec3 v)
{
    H(h, v.x);
    H(h, v.y);
    H(h, v.z);
    return h;
}

/* The material fields no renderer reads yet: hashed only when one differs from the default, so the
 * hashes (and reference cache keys) of scenes that do not use them stay as they were. */
static uint64_t hash_material_extra(uint64_t h, const prw_material *m)
{
    prw_material d = prw_material_default();
    bool plain = m->kind == PRW_MATERIAL_GLTF_MR && m->alpha_mode == d.alpha_mode && m->alpha_cutoff == d.alpha_cutoff && m->clearcoat == 0.0f &&
                 m->clearcoat_tex == -1 && m->clearcoat_roughness == 0.0f && m->clearcoat_roughness_tex == -1 &&
                 m->clearcoat_normal_tex == -1 && m->clearcoat_normal_scale == 1.0f;
    for (int i = 0; i < PRW_TEX_SLOT_COUNT && plain; i++)
        plain = prw_tex_transform_is_identity(&m->tex_xf[i]) && m->tex_xf[i].tex_coord == 0;
    if (plain) return h;
    int kind = (int)m->kind, am = (int)m->alpha_mode;
    H(h, kind);
    H(h, am);
    H(h, m->alpha_cutoff);
    for (int i = 0; i < PRW_TEX_SLOT_COUNT; i++) {
        const prw_tex_transform *t = &m->tex_xf[i];
        HA(h, t->offset, sizeof t->offset);
        H(h, t->rotation);
        HA(h, t->scale, sizeof t->scale);
        H(h, t->tex_coord);
    }
    H(h, m->clearcoat);
    H(h, m->clearcoat_tex);
    H(h, m->clearcoat_roughness);
    H(h, m->clearcoat_roughness_tex);
    H(h, m->clearcoat_normal_tex);
    H(h, m->clearcoat_normal_scale);
    if (m->kind == PRW_MATERIAL_BTF) {
        H(h, m->btf_hash);
        H(h, m->btf_texel_m);
        H(h, m->btf_scale_rule);
    }
    return h;
}

uint64_t prw_scene_hash(const prw_scene *s)
{
    uint64_t h = 0x7072772d7363656eull; /* "prw-scen" */
    H(h, s->mesh_count);
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const prw_mesh *m = &s->meshes[i];
        size_t nv = m->vertex_count;
        H(h, m->vertex_count);
        H(h, m->index_count);
        HA(h, m->positions, 3 * nv * sizeof(float));
        HA(h, m->normals, 3 * nv * sizeof(float));
        HA(h, m->uvs, 2 * nv * sizeof(float));
        HA(h, m->tangents, 4 * nv * sizeof(float));
        HA(h, m->indices, (size_t)m->index_count * sizeof(uint32_t));
        H(h, m->material);
        if (m->uvs1) HA(h, m->uvs1, 2 * nv * sizeof(float)); /* only when present (older hashes unchanged) */
    }
    H(h, s->group_count);
    for (uint32_t i = 0; i < s->group_count; i++) {
        H(h, s->groups[i].first);
        H(h, s->groups[i].count);
    }
    H(h, s->material_count);
    for (uint32_t i = 0; i < s->material_count; i++) {
        const prw_material *m = &s->materials[i];
        HA(h, m->base_color, sizeof m->base_color);
        H(h, m->base_color_tex);
        H(h, m->metallic);
        H(h, m->roughness);
        H(h, m->specular);
        H(h, m->metal_rough_tex);
        H(h, m->normal_tex);
        H(h, m->normal_scale);
        HA(h, m->emission, sizeof m->emission);
        H(h, m->emissive_tex);
        uint8_t ds = m->double_sided;
        H(h, ds);
        h = hash_material_extra(h, m);
    }
    H(h, s->texture_count);
    for (uint32_t i = 0; i < s->texture_count; i++) {
        const prw_texture *t = &s->textures[i];
        H(h, t->width);
        H(h, t->height);
        uint8_t srgb = t->srgb;
        H(h, srgb);
        if (t->width > 0 && t->height > 0) HA(h, t->rgba8, (size_t)t->width * (size_t)t->height * 4);
    }
    H(h, s->node_count);
    for (uint32_t i = 0; i < s->node_count; i++) {
        const prw_node *n = &s->nodes[i];
        H(h, n->parent);
        h = hash_v3(h, n->translation);
        H(h, n->rotation.x);
        H(h, n->rotation.y);
        H(h, n->rotation.z);
        H(h, n->rotation.w);
        h = hash_v3(h, n->scale);
        H(h, n->mesh_group);
        H(h, n->camera);
        H(h, n->light);
    }
    H(h, s->camera_count);
    for (uint32_t i = 0; i < s->camera_count; i++) {
        const prw_camera *c = &s->cameras[i];
        H(h, c->node);
        H(h, c->yfov);
        H(h, c->znear);
        H(h, c->aspect);
        H(h, c->ev100);
    }
    H(h, s->light_count);
    for (uint32_t i = 0; i < s->light_count; i++) {
        const prw_light *l = &s->lights[i];
        int type = (int)l->type;
        H(h, type);
        H(h, l->node);
        HA(h, l->color, sizeof l->color);
        H(h, l->intensity);
        H(h, l->range);
        H(h, l->inner_cone);
        H(h, l->outer_cone);
        H(h, l->width);
        H(h, l->height);
        uint8_t sh = l->cast_shadows;
        H(h, sh);
    }
    /* NURBS models (issue 7): only when present (older hashes unchanged); the file by path */
    for (uint32_t i = 0; i < s->nurbs_count; i++) {
        const prw_scene_nurbs *nb = &s->nurbs[i];
        HA(h, nb->file, strlen(nb->file));
        HA(h, nb->procedural, strlen(nb->procedural));
        H(h, nb->node);
        H(h, nb->material);
        HA(h, nb->grid, sizeof nb->grid);
        HA(h, nb->spacing, sizeof nb->spacing);
        H(h, nb->chord_rel);
        H(h, nb->finest_rel);
        H(h, nb->tol_px);
        uint8_t ss = nb->single_sided;
        H(h, ss);
    }
    /* only when present, so hashes of scenes without an environment stay as they were */
    const prw_environment *env = &s->environment;
    if (env->present) {
        HA(h, env->file, strlen(env->file));
        H(h, env->file_hash);
        H(h, env->scale);
        H(h, env->rotation);
        HA(h, env->uniform, sizeof env->uniform);
    }
    return h;
}

/* ---- builder helpers ---- */

static bool finite_v3(prw_dvec3 v, double limit)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z) && fabs(v.x) <= limit && fabs(v.y) <= limit &&
           fabs(v.z) <= limit;
}

/* Adds mesh m (already built around the node origin) + a group + a node at `at`. */
static int add_mesh_node(prw_scene *s, const char *name, const prw_mesh *m, prw_dvec3 at, prw_error *e)
{
    prw_scene_mark mark = prw_scene_mark_get(s);
    int mi = prw_scene_add_mesh(s, m, e);
    if (mi < 0) return -1;
    int gi = prw_scene_add_group(s, name, (uint32_t)mi, 1);
    prw_node n = prw_node_default();
    prw_copy_name(n.name, name);
    n.translation = at;
    n.mesh_group = gi;
    int ni = gi < 0 ? -1 : prw_scene_add_node(s, &n);
    if (ni < 0) {
        prw_scene_rollback(s, mark);
        prw_fail(e, "'%s': cannot add node", n.name);
        return -1;
    }
    return ni;
}

static void put3(float *dst, prw_dvec3 v)
{
    dst[0] = (float)v.x;
    dst[1] = (float)v.y;
    dst[2] = (float)v.z;
}

static prw_dvec3 hadamard(prw_dvec3 a, prw_dvec3 b) { return prw_v3(a.x * b.x, a.y * b.y, a.z * b.z); }

int prw_scene_add_box(prw_scene *s, const char *name_in, prw_dvec3 min, prw_dvec3 max, int material,
                      bool inward, prw_error *e)
{
    char name[PRW_NAME_MAX];
    prw_copy_name(name, name_in ? name_in : "box");
    if (!finite_v3(min, 1e9) || !finite_v3(max, 1e9) || max.x < min.x || max.y < min.y || max.z < min.z) {
        prw_fail(e, "box '%s': needs finite min <= max (|coordinate| <= 1e9 m)", name);
        return -1;
    }
    prw_dvec3 c = prw_v3_scale(prw_v3_add(min, max), 0.5), h = prw_v3_scale(prw_v3_sub(max, min), 0.5);
    static const double faces[6][6] = {/* outward normal, u axis */
                                       {1, 0, 0, 0, 0, -1}, {-1, 0, 0, 0, 0, 1}, {0, 1, 0, 1, 0, 0},
                                       {0, -1, 0, 1, 0, 0}, {0, 0, 1, 1, 0, 0},  {0, 0, -1, -1, 0, 0}};
    static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    float pos[24 * 3], nrm[24 * 3], uv[24 * 2], tan[24 * 4];
    uint32_t idx[36];
    for (int f = 0; f < 6; f++) {
        prw_dvec3 n = prw_v3(faces[f][0], faces[f][1], faces[f][2]);
        prw_dvec3 u = prw_v3(faces[f][3], faces[f][4], faces[f][5]);
        prw_dvec3 v = prw_v3_cross(n, u); /* u x v = n */
        prw_dvec3 fn = n, fu = u;
        if (inward) { /* seen from inside: normal -n, u mirrored so that fu x v = -n */
            fn = prw_v3_scale(n, -1);
            fu = prw_v3_scale(u, -1);
        }
        for (int k = 0; k < 4; k++) {
            int vi = f * 4 + k;
            double a = corner[k][0], b = corner[k][1];
            prw_dvec3 p = hadamard(prw_v3_add(n, prw_v3_add(prw_v3_scale(fu, a), prw_v3_scale(v, b))), h);
            put3(pos + 3 * vi, p);
            put3(nrm + 3 * vi, fn);
            put3(tan + 4 * vi, fu);
            tan[4 * vi + 3] = 1.0f;
            uv[2 * vi] = (float)((a + 1) * 0.5);
            uv[2 * vi + 1] = (float)((1 - b) * 0.5);
        }
        static const uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
        for (int k = 0; k < 6; k++) idx[f * 6 + k] = (uint32_t)(f * 4) + tri[k];
    }
    prw_mesh m;
    memset(&m, 0, sizeof m);
    prw_copy_name(m.name, name);
    m.vertex_count = 24;
    m.index_count = 36;
    m.positions = pos;
    m.normals = nrm;
    m.uvs = uv;
    m.tangents = tan;
    m.indices = idx;
    m.material = material;
    return add_mesh_node(s, name, &m, c, e);
}

int prw_scene_add_quad(prw_scene *s, const char *name_in, prw_dvec3 centre, prw_dvec3 half_u,
                       prw_dvec3 half_v, int material, prw_error *e)
{
    char name[PRW_NAME_MAX];
    prw_copy_name(name, name_in ? name_in : "quad");
    if (!finite_v3(centre, 1e9) || !finite_v3(half_u, 1e9) || !finite_v3(half_v, 1e9)) {
        prw_fail(e, "quad '%s': centre and half axes must be finite (|coordinate| <= 1e9 m)", name);
        return -1;
    }
    prw_dvec3 cr = prw_v3_cross(half_u, half_v);
    double lu = prw_v3_len(half_u), lv = prw_v3_len(half_v);
    if (!(lu > 0) || !(lv > 0) || !(prw_v3_len(cr) > 1e-9 * lu * lv)) {
        prw_fail(e, "quad '%s': half axes must be non-zero and not parallel", name);
        return -1;
    }
    prw_dvec3 n = prw_v3_norm(cr);
    static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    float pos[12], nrm[12], uv[8];
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 4; k++) {
        double a = corner[k][0], b = corner[k][1];
        put3(pos + 3 * k, prw_v3_add(prw_v3_scale(half_u, a), prw_v3_scale(half_v, b)));
        put3(nrm + 3 * k, n);
        uv[2 * k] = (float)((a + 1) * 0.5);
        uv[2 * k + 1] = (float)((1 - b) * 0.5);
    }
    prw_mesh m;
    memset(&m, 0, sizeof m);
    prw_copy_name(m.name, name);
    m.vertex_count = 4;
    m.index_count = 6;
    m.positions = pos;
    m.normals = nrm;
    m.uvs = uv;
    m.indices = idx;
    m.material = material;
    return add_mesh_node(s, name, &m, centre, e);
}

int prw_scene_add_sphere(prw_scene *s, const char *name_in, prw_dvec3 centre, double r, int slices,
                         int stacks, int material, prw_error *e)
{
    char name[PRW_NAME_MAX];
    prw_copy_name(name, name_in ? name_in : "sphere");
    if (!finite_v3(centre, 1e9) || !isfinite(r) || !(r > 0) || r > 1e9) {
        prw_fail(e, "sphere '%s': needs a finite centre and 0 < radius <= 1e9 m", name);
        return -1;
    }
    if (slices < 3 || slices > 4096 || stacks < 2 || stacks > 4096) {
        prw_fail(e, "sphere '%s': slices must be in [3, 4096] and stacks in [2, 4096] (got %d, %d)", name,
                 slices, stacks);
        return -1;
    }
    uint32_t cols = (uint32_t)slices + 1, rows = (uint32_t)stacks + 1;
    uint32_t nv = cols * rows;
    float *pos = prw_malloc((size_t)nv * 3 * sizeof(float));
    float *nrm = prw_malloc((size_t)nv * 3 * sizeof(float));
    float *uv = prw_malloc((size_t)nv * 2 * sizeof(float));
    float *tan = prw_malloc((size_t)nv * 4 * sizeof(float));
    uint32_t *idx = prw_malloc((size_t)slices * (size_t)stacks * 6 * sizeof(uint32_t));
    for (uint32_t i = 0; i < rows; i++) {
        double theta = PRW_PI * i / stacks; /* 0 at +Y */
        for (uint32_t j = 0; j < cols; j++) {
            double phi = 2 * PRW_PI * j / slices; /* 0 at +Z, pi/2 at +X */
            uint32_t v = i * cols + j;
            prw_dvec3 d = prw_v3(sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi));
            put3(pos + 3 * v, prw_v3_scale(d, r));
            put3(nrm + 3 * v, d);
            put3(tan + 4 * v, prw_v3(cos(phi), 0, -sin(phi))); /* dP/du direction */
            tan[4 * v + 3] = 1.0f;
            uv[2 * v] = (float)j / (float)slices;
            uv[2 * v + 1] = (float)i / (float)stacks;
        }
    }
    uint32_t ni = 0;
    for (uint32_t i = 0; i < (uint32_t)stacks; i++) {
        for (uint32_t j = 0; j < (uint32_t)slices; j++) {
            uint32_t a = i * cols + j, b = (i + 1) * cols + j, c = (i + 1) * cols + j + 1, d = i * cols + j + 1;
            if (i + 1 < (uint32_t)stacks) { /* not degenerate at the lower pole */
                idx[ni++] = a;
                idx[ni++] = b;
                idx[ni++] = c;
            }
            if (i > 0) { /* not degenerate at the upper pole */
                idx[ni++] = a;
                idx[ni++] = c;
                idx[ni++] = d;
            }
        }
    }
    prw_mesh m;
    memset(&m, 0, sizeof m);
    prw_copy_name(m.name, name);
    m.vertex_count = nv;
    m.index_count = ni;
    m.positions = pos;
    m.normals = nrm;
    m.uvs = uv;
    m.tangents = tan;
    m.indices = idx;
    m.material = material;
    int node = add_mesh_node(s, name, &m, centre, e);
    free(pos);
    free(nrm);
    free(uv);
    free(tan);
    free(idx);
    return node;
}
