/* manifest.c — the JSON scene manifest (format: manifest.md), parsed with cJSON.
 *
 * Every error is one line "<file>:<place>: <reason>": <place> is line:column for syntax errors and
 * a JSON path (lights[2].intensity) for semantic ones.  Unknown keys are errors at every level (they
 * are almost always typos).  Loading is all-or-nothing: on failure the scene is rolled back. */
#define _POSIX_C_SOURCE 200809L
#include "scene_internal.h"
#include "prw_json_doc.h"
#include "prw_lod_node.h"

#include <cJSON.h>
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include <sys/stat.h>

#define PLACE_MAX 160
#define COORD_LIMIT 1e9       /* metres */
#define INTENSITY_LIMIT 1e15  /* cd, lm, lux or cd/m^2 */
#define EMISSION_LIMIT 1e12   /* cd/m^2 */

typedef struct ctx {
    prw_scene *s;
    const char *file;
    char dir[1024];           /* manifest directory with trailing '/', or "" */
    prw_error *e;
    prw_json_ctx j;           /* {file, e} for the shared JSON helpers */
    uint32_t first_material;  /* materials added by this manifest start here */
    int default_material;     /* -1 until a mesh without "material" needs it */
} ctx;

/* Errors at a place in the manifest: prw_json_fail_at on the context's file. */
#define fail_at(c, ...) prw_json_fail_at(&(c)->j, __VA_ARGS__)

static const cJSON *item(const cJSON *obj, const char *key) { return cJSON_GetObjectItemCaseSensitive(obj, key); }

/* Number in [lo, hi] (open ends when lo_open / hi_open).  Absent: *out untouched unless required. */
static bool get_num(ctx *c, const cJSON *obj, const char *key, const char *place, double *out, bool required,
                    double lo, bool lo_open, double hi, bool hi_open)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    if (!v) return required ? fail_at(c, p, "missing (required)") : true;
    double x = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    bool ok = isfinite(x) && (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi);
    if (!ok)
        return fail_at(c, p, "must be a finite number %s %g and %s %g", lo_open ? ">" : ">=", lo,
                       hi_open ? "<" : "<=", hi);
    *out = x;
    return true;
}

static bool get_int(ctx *c, const cJSON *obj, const char *key, const char *place, int *out, int lo, int hi)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    if (!v) return true;
    double x = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    if (!(x >= lo && x <= hi) || x != floor(x)) return fail_at(c, p, "must be an integer in [%d, %d]", lo, hi);
    *out = (int)x;
    return true;
}

/* Array of n numbers, each in [lo, hi]; n_alt (0: none) is a second accepted length. */
static bool get_vec(ctx *c, const cJSON *obj, const char *key, const char *place, double *out, int n, int n_alt,
                    bool required, double lo, double hi, bool *present)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    if (present) *present = v != NULL;
    if (!v) return required ? fail_at(c, p, "missing (required)") : true;
    int len = cJSON_IsArray(v) ? cJSON_GetArraySize(v) : -1;
    bool ok = len == n || (n_alt && len == n_alt);
    double tmp[4] = {0, 0, 0, 0};
    int i = 0;
    for (const cJSON *it = ok ? v->child : NULL; it && ok; it = it->next, i++) {
        double x = cJSON_IsNumber(it) ? it->valuedouble : NAN;
        ok = isfinite(x) && x >= lo && x <= hi;
        tmp[i] = x;
    }
    if (!ok) {
        char lens[16] = "";
        if (n_alt) snprintf(lens, sizeof lens, " or %d", n_alt);
        if (lo == -hi) return fail_at(c, p, "must be an array of %d%s finite numbers with |x| <= %g", n, lens, hi);
        return fail_at(c, p, "must be an array of %d%s finite numbers in [%g, %g]", n, lens, lo, hi);
    }
    for (int k = 0; k < len; k++) out[k] = tmp[k];
    return true;
}

static bool get_v3(ctx *c, const cJSON *obj, const char *key, const char *place, prw_dvec3 *out, bool required,
                   bool *present)
{
    double v[3] = {out->x, out->y, out->z};
    if (!get_vec(c, obj, key, place, v, 3, 0, required, -COORD_LIMIT, COORD_LIMIT, present)) return false;
    *out = prw_v3(v[0], v[1], v[2]);
    return true;
}

static bool get_str(ctx *c, const cJSON *obj, const char *key, const char *place, const char **out, bool required)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    if (!v) return required ? fail_at(c, p, "missing (required)") : true;
    if (!cJSON_IsString(v) || !v->valuestring) return fail_at(c, p, "must be a string");
    *out = v->valuestring;
    return true;
}

static bool get_bool(ctx *c, const cJSON *obj, const char *key, const char *place, bool *out)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, key);
    const cJSON *v = item(obj, key);
    if (!v) return true;
    if (!cJSON_IsBool(v)) return fail_at(c, p, "must be true or false");
    *out = cJSON_IsTrue(v);
    return true;
}

/* The array under `key` (absent: *out = NULL); every element must be an object. */
static bool get_obj_array(ctx *c, const cJSON *root, const char *key, const cJSON **out)
{
    *out = NULL;
    const cJSON *v = item(root, key);
    if (!v) return true;
    if (!cJSON_IsArray(v)) return fail_at(c, key, "must be an array of objects");
    int i = 0;
    for (const cJSON *it = v->child; it; it = it->next, i++) {
        if (!cJSON_IsObject(it)) {
            char p[PLACE_MAX];
            snprintf(p, sizeof p, "%s[%d]", key, i);
            return fail_at(c, p, "must be an object");
        }
    }
    *out = v;
    return true;
}

static bool name_ok(ctx *c, const char *name, const char *place)
{
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, place, "name");
    if (strlen(name) >= PRW_NAME_MAX) return fail_at(c, p, "longer than %d bytes", PRW_NAME_MAX - 1);
    for (const char *q = name; *q; q++)
        if ((unsigned char)*q < 0x20 || *q == 0x7f) return fail_at(c, p, "must not contain control characters");
    return true;
}

/* Orientation input shared by lights and cameras: "target" or "direction" (exactly one). */
static bool get_aim(ctx *c, const cJSON *o, const char *place, prw_dvec3 pos, prw_dvec3 *target, bool required)
{
    bool has_t = false, has_d = false;
    prw_dvec3 t = prw_v3(0, 0, 0), d = prw_v3(0, 0, 0);
    if (!get_v3(c, o, "target", place, &t, false, &has_t)) return false;
    if (!get_v3(c, o, "direction", place, &d, false, &has_d)) return false;
    if (has_t && has_d) return fail_at(c, place, "give either 'target' or 'direction', not both");
    if (!has_t && !has_d) return required ? fail_at(c, place, "needs 'target' or 'direction'") : true;
    if (has_d) {
        if (!(prw_v3_len(d) > 0)) {
            char p[PLACE_MAX];
            prw_json_join(p, PLACE_MAX, place, "direction");
            return fail_at(c, p, "must not be zero");
        }
        t = prw_v3_add(pos, prw_v3_norm(d));
    } else if (!(prw_v3_len(prw_v3_sub(t, pos)) > 1e-9 * (1 + prw_v3_len(pos)))) {
        char p[PLACE_MAX];
        prw_json_join(p, PLACE_MAX, place, "target");
        return fail_at(c, p, "must differ from 'position'");
    }
    *target = t;
    return true;
}

/* Adds a node carrying a light or camera; returns the node index. */
static int add_aimed_node(ctx *c, const char *name, prw_dvec3 pos, prw_dvec3 target, prw_dvec3 up, bool aimed)
{
    prw_node n = aimed ? prw_node_look_at(name, pos, target, up) : prw_node_default();
    prw_copy_name(n.name, name);
    n.translation = pos;
    return prw_scene_add_node(c->s, &n);
}

static bool up_ok(ctx *c, const char *place, prw_dvec3 pos, prw_dvec3 target, prw_dvec3 up)
{
    prw_dvec3 f = prw_v3_norm(prw_v3_sub(target, pos));
    double lu = prw_v3_len(up);
    if (!(lu > 0) || prw_v3_len(prw_v3_cross(f, prw_v3_scale(up, 1.0 / lu))) < 1e-6) {
        char p[PLACE_MAX];
        prw_json_join(p, PLACE_MAX, place, "up");
        return fail_at(c, p, "must be non-zero and not parallel to the view direction");
    }
    return true;
}

/* ---- sections ---- */

/* "btf" (a PRWBTFC1 file, relative to the manifest) and "btf_texel_m" (metres per texel): the BTF kind. */
static bool parse_material_btf(ctx *c, const cJSON *o, const char *pl, prw_material *m)
{
    const char *file = NULL;
    double texel = 0;
    bool has_texel = item(o, "btf_texel_m") != NULL, rule = false;
    if (!get_str(c, o, "btf", pl, &file, false) || !get_bool(c, o, "btf_scale_rule", pl, &rule)) return false;
    if (!file && item(o, "btf_scale_rule")) return fail_at(c, pl, "'btf_scale_rule' needs 'btf'");
    if (!file) return has_texel ? fail_at(c, pl, "'btf_texel_m' needs 'btf'") : true;
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, pl, "btf");
    if (!file[0]) return fail_at(c, p, "must not be empty");
    if (!has_texel) return fail_at(c, pl, "'btf' needs 'btf_texel_m' (metres per BTF texel)");
    if (!get_num(c, o, "btf_texel_m", pl, &texel, true, 0, true, 1, false)) return false;
    int n = file[0] == '/' ? snprintf(m->btf_file, sizeof m->btf_file, "%s", file)
                           : snprintf(m->btf_file, sizeof m->btf_file, "%s%s", c->dir, file);
    if (n < 0 || (size_t)n >= sizeof m->btf_file) return fail_at(c, p, "path longer than %zu bytes", sizeof m->btf_file - 1);
    prw_error fe;
    if (!prw_scene_btf_check(m->btf_file, &m->btf_hash, &fe)) return fail_at(c, p, "%s", fe.msg);
    m->kind = PRW_MATERIAL_BTF;
    m->btf_texel_m = texel;
    m->btf_scale_rule = rule;
    return true;
}

static bool parse_materials(ctx *c, const cJSON *arr)
{
    static const char *const keys[] = {"name", "base_color", "metallic", "roughness", "emission_cd_m2",
                                       "double_sided", "specular", "btf", "btf_texel_m", "btf_scale_rule"};
    int i = 0;
    for (const cJSON *o = arr ? arr->child : NULL; o; o = o->next, i++) {
        char pl[PLACE_MAX];
        snprintf(pl, sizeof pl, "materials[%d]", i);
        if (!prw_json_check_keys(&c->j, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
        prw_material m = prw_material_default();
        const char *name = NULL;
        double bc[4] = {1, 1, 1, 1}, em[3] = {0, 0, 0}, metal = 0, rough = 1, spec = 1;
        bool ds = false;
        if (!get_str(c, o, "name", pl, &name, true) || !name_ok(c, name, pl)) return false;
        if (!name[0]) return fail_at(c, pl, "name must not be empty");
        for (uint32_t k = c->first_material; k < c->s->material_count; k++)
            if (strcmp(c->s->materials[k].name, name) == 0) {
                char nm[80];
                prw_json_sanitize(nm, sizeof nm, name, 64);
                return fail_at(c, pl, "duplicate material name '%s'", nm);
            }
        if (!get_vec(c, o, "base_color", pl, bc, 3, 4, false, 0, 1, NULL)) return false;
        if (!get_num(c, o, "metallic", pl, &metal, false, 0, false, 1, false)) return false;
        if (!get_num(c, o, "roughness", pl, &rough, false, 0, false, 1, false)) return false;
        if (!get_num(c, o, "specular", pl, &spec, false, 0, false, 1, false)) return false;
        if (!get_vec(c, o, "emission_cd_m2", pl, em, 3, 0, false, 0, EMISSION_LIMIT, NULL)) return false;
        if (!get_bool(c, o, "double_sided", pl, &ds)) return false;
        prw_copy_name(m.name, name);
        for (int k = 0; k < 4; k++) m.base_color[k] = (float)bc[k];
        m.metallic = (float)metal;
        m.roughness = (float)rough;
        m.specular = (float)spec;
        for (int k = 0; k < 3; k++) m.emission[k] = (float)em[k];
        m.double_sided = ds;
        if (!parse_material_btf(c, o, pl, &m)) return false;
        prw_scene_add_material(c->s, &m);
    }
    return true;
}

static bool find_material(ctx *c, const cJSON *o, const char *pl, int *out)
{
    const char *name = NULL;
    if (!get_str(c, o, "material", pl, &name, false)) return false;
    if (!name) {
        if (c->default_material < 0) {
            prw_material m = prw_material_default();
            c->default_material = prw_scene_add_material(c->s, &m);
        }
        *out = c->default_material;
        return true;
    }
    for (uint32_t k = c->first_material; k < c->s->material_count; k++)
        if ((int)k != c->default_material && strcmp(c->s->materials[k].name, name) == 0) {
            *out = (int)k;
            return true;
        }
    char p[PLACE_MAX], nm[80];
    prw_json_join(p, PLACE_MAX, pl, "material");
    prw_json_sanitize(nm, sizeof nm, name, 64);
    return fail_at(c, p, "unknown material '%s' (not in \"materials\")", nm);
}

static bool parse_meshes(ctx *c, const cJSON *arr)
{
    static const char *const keys[] = {"name", "box", "quad", "sphere", "material"};
    static const char *const box_keys[] = {"min", "max", "inward"};
    static const char *const quad_keys[] = {"centre", "half_u", "half_v"};
    static const char *const sphere_keys[] = {"centre", "radius", "slices", "stacks"};
    int i = 0;
    for (const cJSON *o = arr ? arr->child : NULL; o; o = o->next, i++) {
        char pl[PLACE_MAX], sub[PLACE_MAX], defname[32];
        snprintf(pl, sizeof pl, "meshes[%d]", i);
        snprintf(defname, sizeof defname, "mesh%d", i);
        if (!prw_json_check_keys(&c->j, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
        const char *name = defname;
        int mat = -1;
        if (!get_str(c, o, "name", pl, &name, false) || !name_ok(c, name, pl)) return false;
        if (!find_material(c, o, pl, &mat)) return false;
        const cJSON *box = item(o, "box"), *quad = item(o, "quad"), *sph = item(o, "sphere");
        if ((box != NULL) + (quad != NULL) + (sph != NULL) != 1)
            return fail_at(c, pl, "needs exactly one of 'box', 'quad', 'sphere'");
        const cJSON *shape = box ? box : quad ? quad : sph;
        prw_json_join(sub, PLACE_MAX, pl, box ? "box" : quad ? "quad" : "sphere");
        if (!cJSON_IsObject(shape)) return fail_at(c, sub, "must be an object");
        int node = -1;
        if (box) {
            prw_dvec3 lo = prw_v3(0, 0, 0), hi = prw_v3(0, 0, 0);
            bool inward = false;
            if (!prw_json_check_keys(&c->j, box, sub, box_keys, 3) || !get_v3(c, box, "min", sub, &lo, true, NULL) ||
                !get_v3(c, box, "max", sub, &hi, true, NULL) || !get_bool(c, box, "inward", sub, &inward))
                return false;
            if (hi.x < lo.x || hi.y < lo.y || hi.z < lo.z) return fail_at(c, sub, "max must be >= min on every axis");
            node = prw_scene_add_box(c->s, name, lo, hi, mat, inward, c->e);
        } else if (quad) {
            prw_dvec3 ctr = prw_v3(0, 0, 0), u = prw_v3(0, 0, 0), v = prw_v3(0, 0, 0);
            if (!prw_json_check_keys(&c->j, quad, sub, quad_keys, 3) || !get_v3(c, quad, "centre", sub, &ctr, true, NULL) ||
                !get_v3(c, quad, "half_u", sub, &u, true, NULL) || !get_v3(c, quad, "half_v", sub, &v, true, NULL))
                return false;
            node = prw_scene_add_quad(c->s, name, ctr, u, v, mat, c->e);
        } else {
            prw_dvec3 ctr = prw_v3(0, 0, 0);
            double r = 1;
            int slices = 64, stacks = 32;
            if (!prw_json_check_keys(&c->j, sph, sub, sphere_keys, 4) || !get_v3(c, sph, "centre", sub, &ctr, true, NULL) ||
                !get_num(c, sph, "radius", sub, &r, true, 0, true, COORD_LIMIT, false) ||
                !get_int(c, sph, "slices", sub, &slices, 3, 1024) || !get_int(c, sph, "stacks", sub, &stacks, 2, 512))
                return false;
            node = prw_scene_add_sphere(c->s, name, ctr, r, slices, stacks, mat, c->e);
        }
        if (node < 0) return prw_fail_wrap(c->e, "%s:%s", c->file, sub);
    }
    return true;
}

typedef struct light_kind {
    const char *name;
    prw_light_type type;
    const char *units[2];   /* [0] is the native unit (the default) */
    bool positioned, aimed; /* needs position / target-or-direction */
} light_kind;

static const light_kind k_lights[] = {
    {"point", PRW_LIGHT_POINT, {"cd", "lm"}, true, false},
    {"spot", PRW_LIGHT_SPOT, {"cd", "lm"}, true, true},
    {"directional", PRW_LIGHT_DIRECTIONAL, {"lux", NULL}, false, true},
    {"rect", PRW_LIGHT_RECT, {"cd/m2", "lm"}, true, true},
};

static bool parse_lights(ctx *c, const cJSON *arr)
{
    /* keys by type: the common set, plus the type's own */
    static const char *const point_keys[] = {"type", "name", "position", "color", "intensity", "unit", "range",
                                             "shadows"};
    static const char *const spot_keys[] = {"type",  "name",    "position",       "target",        "direction",
                                            "color", "intensity", "unit",         "range",         "shadows",
                                            "inner_cone_deg", "outer_cone_deg"};
    static const char *const dir_keys[] = {"type", "name", "position", "target", "direction", "color",
                                           "intensity", "unit", "shadows"};
    static const char *const rect_keys[] = {"type", "name", "position", "target", "direction", "up", "color",
                                            "intensity", "unit", "width", "height", "shadows"};
    static const char *const *const keys_by_type[] = {point_keys, spot_keys, dir_keys, rect_keys};
    static const int nkeys_by_type[] = {(int)PRW_ARRAY_LEN(point_keys), (int)PRW_ARRAY_LEN(spot_keys),
                                        (int)PRW_ARRAY_LEN(dir_keys), (int)PRW_ARRAY_LEN(rect_keys)};
    int i = 0;
    for (const cJSON *o = arr ? arr->child : NULL; o; o = o->next, i++) {
        char pl[PLACE_MAX], defname[32], p[PLACE_MAX];
        snprintf(pl, sizeof pl, "lights[%d]", i);
        snprintf(defname, sizeof defname, "light%d", i);
        const char *type = NULL, *name = defname, *unit = NULL;
        if (!get_str(c, o, "type", pl, &type, true)) return false;
        int k = -1;
        for (int t = 0; t < (int)PRW_ARRAY_LEN(k_lights); t++)
            if (strcmp(type, k_lights[t].name) == 0) k = t;
        if (k < 0) {
            char ty[80];
            prw_json_sanitize(ty, sizeof ty, type, 64);
            prw_json_join(p, PLACE_MAX, pl, "type");
            return fail_at(c, p, "unknown light type '%s' (point, spot, directional, rect)", ty);
        }
        const light_kind *lk = &k_lights[k];
        /* a key of another light type gets a clearer message than "unknown key" */
        for (const cJSON *it = o->child; it; it = it->next) {
            bool mine = false, other = false;
            for (int t = 0; t < (int)PRW_ARRAY_LEN(k_lights); t++)
                for (int q = 0; q < nkeys_by_type[t]; q++)
                    if (it->string && strcmp(it->string, keys_by_type[t][q]) == 0) {
                        if (t == k) mine = true;
                        else other = true;
                    }
            if (other && !mine) {
                prw_json_join(p, PLACE_MAX, pl, it->string);
                return fail_at(c, p, "does not apply to %s lights", lk->name);
            }
        }
        if (!prw_json_check_keys(&c->j, o, pl, keys_by_type[k], nkeys_by_type[k])) return false;
        if (!get_str(c, o, "name", pl, &name, false) || !name_ok(c, name, pl)) return false;

        prw_light l;
        memset(&l, 0, sizeof l);
        prw_copy_name(l.name, name);
        l.type = lk->type;
        l.cast_shadows = true;
        double col[3] = {1, 1, 1}, inner = 0, outer = 45, w = 0, h = 0;
        prw_dvec3 pos = prw_v3(0, 0, 0), target = prw_v3(0, 0, -1), up = prw_v3(0, 1, 0);
        if (!get_v3(c, o, "position", pl, &pos, lk->positioned, NULL)) return false;
        if (lk->aimed && !get_aim(c, o, pl, pos, &target, true)) return false;
        if (!get_vec(c, o, "color", pl, col, 3, 0, false, 0, 1e6, NULL)) return false;
        if (!(col[0] + col[1] + col[2] > 0)) {
            prw_json_join(p, PLACE_MAX, pl, "color");
            return fail_at(c, p, "must not be black");
        }
        if (!get_num(c, o, "intensity", pl, &l.intensity, true, 0, false, INTENSITY_LIMIT, false)) return false;
        if (!get_str(c, o, "unit", pl, &unit, false)) return false;
        if (!unit) unit = lk->units[0];
        bool native = strcmp(unit, lk->units[0]) == 0, lumens = lk->units[1] && strcmp(unit, lk->units[1]) == 0;
        if (!native && !lumens) {
            char un[80];
            prw_json_sanitize(un, sizeof un, unit, 64);
            prw_json_join(p, PLACE_MAX, pl, "unit");
            return fail_at(c, p, "unit '%s' does not apply to %s lights (use %s%s%s)", un, lk->name, lk->units[0],
                           lk->units[1] ? " or " : "", lk->units[1] ? lk->units[1] : "");
        }
        if (!get_num(c, o, "range", pl, &l.range, false, 0, false, COORD_LIMIT, false)) return false;
        if (!get_bool(c, o, "shadows", pl, &l.cast_shadows)) return false;
        if (lk->type == PRW_LIGHT_SPOT) {
            if (!get_num(c, o, "inner_cone_deg", pl, &inner, false, 0, false, 90, false) ||
                !get_num(c, o, "outer_cone_deg", pl, &outer, false, 0, true, 90, false))
                return false;
            if (inner > outer) {
                prw_json_join(p, PLACE_MAX, pl, "inner_cone_deg");
                return fail_at(c, p, "must be <= outer_cone_deg (%g)", outer);
            }
            l.inner_cone = inner * PRW_PI / 180.0;
            l.outer_cone = outer * PRW_PI / 180.0;
        }
        if (lk->type == PRW_LIGHT_RECT) {
            if (!get_num(c, o, "width", pl, &w, true, 0, true, COORD_LIMIT, false) ||
                !get_num(c, o, "height", pl, &h, true, 0, true, COORD_LIMIT, false) ||
                !get_v3(c, o, "up", pl, &up, false, NULL) || !up_ok(c, pl, pos, target, up))
                return false;
            l.width = w;
            l.height = h;
        }
        /* Conversions to the stored units (manifest.md): point and spot (Filament's "spot as point")
         * I = flux / (4 pi); rect, one-sided Lambertian: L = flux / (pi * area). */
        if (lumens) l.intensity = lk->type == PRW_LIGHT_RECT ? l.intensity / (PRW_PI * w * h) : l.intensity / (4 * PRW_PI);
        if (!isfinite(l.intensity)) {
            prw_json_join(p, PLACE_MAX, pl, "intensity");
            return fail_at(c, p, "converts to a non-finite value");
        }
        for (int q = 0; q < 3; q++) l.color[q] = (float)col[q];
        int node = add_aimed_node(c, l.name, pos, target, up, lk->aimed);
        c->s->nodes[node].light = (int)c->s->light_count;
        l.node = node;
        prw_scene_add_light(c->s, &l);
    }
    return true;
}

static bool parse_cameras(ctx *c, const cJSON *arr)
{
    static const char *const keys[] = {"name", "position", "target", "direction", "up",
                                       "yfov_deg", "znear", "aspect", "ev100", "f_number", "shutter_s", "iso"};
    int i = 0;
    for (const cJSON *o = arr ? arr->child : NULL; o; o = o->next, i++) {
        char pl[PLACE_MAX], defname[32];
        snprintf(pl, sizeof pl, "cameras[%d]", i);
        snprintf(defname, sizeof defname, "camera%d", i);
        if (!prw_json_check_keys(&c->j, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
        const char *name = defname;
        prw_dvec3 pos = prw_v3(0, 0, 0), target = prw_v3(0, 0, 0), up = prw_v3(0, 1, 0);
        double yfov = 50, znear = 0.05, aspect = 0, ev100 = 0;
        if (!get_str(c, o, "name", pl, &name, false) || !name_ok(c, name, pl)) return false;
        if (!get_v3(c, o, "position", pl, &pos, true, NULL) || !get_aim(c, o, pl, pos, &target, true) ||
            !get_v3(c, o, "up", pl, &up, false, NULL) || !up_ok(c, pl, pos, target, up))
            return false;
        if (!get_num(c, o, "yfov_deg", pl, &yfov, false, 0, true, 180, true) ||
            !get_num(c, o, "znear", pl, &znear, false, 0, true, 1e6, false) ||
            !get_num(c, o, "aspect", pl, &aspect, false, 0, false, 100, false) ||
            !get_num(c, o, "ev100", pl, &ev100, false, -30, false, 40, false))
            return false;
        /* Physical exposure: EV100 = log2(N^2 / t * 100 / S), from all three settings together. */
        int settings = !!item(o, "f_number") + !!item(o, "shutter_s") + !!item(o, "iso");
        if (settings) {
            double fn = 0, t = 0, iso = 0;
            if (settings != 3) return fail_at(c, pl, "f_number, shutter_s and iso must be given together");
            if (item(o, "ev100")) return fail_at(c, pl, "give either ev100 or f_number/shutter_s/iso, not both");
            if (!get_num(c, o, "f_number", pl, &fn, true, 0.5, false, 256, false) ||
                !get_num(c, o, "shutter_s", pl, &t, true, 0, true, 3600, false) ||
                !get_num(c, o, "iso", pl, &iso, true, 1, false, 1e7, false))
                return false;
            ev100 = log2(fn * fn / t * 100.0 / iso);
        }
        prw_camera cam;
        memset(&cam, 0, sizeof cam);
        prw_copy_name(cam.name, name);
        cam.yfov = yfov * PRW_PI / 180.0;
        cam.znear = znear;
        cam.aspect = aspect;
        cam.ev100 = ev100;
        int node = add_aimed_node(c, cam.name, pos, target, up, true);
        c->s->nodes[node].camera = (int)c->s->camera_count;
        cam.node = node;
        prw_scene_add_camera(c->s, &cam);
    }
    return true;
}

static const char *basename_of(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

static bool parse_gltf(ctx *c, const cJSON *arr)
{
    static const char *const keys[] = {"file", "translation", "rotation", "scale"};
    int i = 0;
    for (const cJSON *o = arr ? arr->child : NULL; o; o = o->next, i++) {
        char pl[PLACE_MAX], p[PLACE_MAX];
        snprintf(pl, sizeof pl, "gltf[%d]", i);
        if (!prw_json_check_keys(&c->j, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
        const char *file = NULL;
        double q[4] = {0, 0, 0, 1}, sc[3] = {1, 1, 1};
        prw_node n = prw_node_default();
        if (!get_str(c, o, "file", pl, &file, true)) return false;
        if (!file[0]) {
            prw_json_join(p, PLACE_MAX, pl, "file");
            return fail_at(c, p, "must not be empty");
        }
        if (!get_v3(c, o, "translation", pl, &n.translation, false, NULL) ||
            !get_vec(c, o, "rotation", pl, q, 4, 0, false, -1e6, 1e6, NULL) ||
            !get_vec(c, o, "scale", pl, sc, 3, 0, false, -1e6, 1e6, NULL))
            return false;
        double ql = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(ql > 1e-9)) {
            prw_json_join(p, PLACE_MAX, pl, "rotation");
            return fail_at(c, p, "quaternion [x, y, z, w] must not be zero");
        }
        n.rotation = (prw_dquat){q[0] / ql, q[1] / ql, q[2] / ql, q[3] / ql};
        n.scale = prw_v3(sc[0], sc[1], sc[2]);
        char full[2048];
        if (file[0] == '/') snprintf(full, sizeof full, "%s", file);
        else snprintf(full, sizeof full, "%s%s", c->dir, file);
        prw_copy_name(n.name, basename_of(full));
        int node = prw_scene_add_node(c->s, &n);
        if (!prw_gltf_import(c->s, full, node, c->e)) return prw_fail_wrap(c->e, "%s:%s", c->file, pl);
    }
    return true;
}

/* "nurbs": trimmed-NURBS models drawn with LOD (issue 7): a file or a procedural model, a TRS, a
 * material, LOD knobs and an optional instance grid.  The model is loaded here once (validation,
 * bounds); the renderer builds its hierarchy. */
static bool parse_nurbs(ctx *c, const cJSON *arr)
{
    static const char *const keys[] = {"name", "file", "procedural", "translation", "rotation", "scale", "material",
                                       "instances", "chord_rel", "finest_rel", "tol_px", "single_sided"};
    static const char *const inst_keys[] = {"grid", "spacing"};
    int i = 0;
    for (const cJSON *o = arr ? arr->child : NULL; o; o = o->next, i++) {
        char pl[PLACE_MAX], p[PLACE_MAX];
        snprintf(pl, sizeof pl, "nurbs[%d]", i);
        if (!prw_json_check_keys(&c->j, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
        prw_scene_nurbs nb;
        memset(&nb, 0, sizeof nb);
        nb.grid[0] = nb.grid[1] = 1;
        const char *name = NULL, *file = NULL, *proc = NULL;
        char defname[32];
        snprintf(defname, sizeof defname, "nurbs%d", i);
        if (!get_str(c, o, "name", pl, &name, false) || (name && !name_ok(c, name, pl)) ||
            !get_str(c, o, "file", pl, &file, false) || !get_str(c, o, "procedural", pl, &proc, false))
            return false;
        if ((file != NULL) == (proc != NULL)) return fail_at(c, pl, "needs exactly one of 'file' and 'procedural'");
        if (file) {
            prw_json_join(p, PLACE_MAX, pl, "file");
            if (!file[0]) return fail_at(c, p, "must not be empty");
            int n = file[0] == '/' ? snprintf(nb.file, sizeof nb.file, "%s", file)
                                   : snprintf(nb.file, sizeof nb.file, "%s%s", c->dir, file);
            if (n < 0 || (size_t)n >= sizeof nb.file) return fail_at(c, p, "path longer than %zu bytes", sizeof nb.file - 1);
        } else if (!prw_scene_nurbs_procedural_known(proc)) {
            char nm[80];
            prw_json_join(p, PLACE_MAX, pl, "procedural");
            prw_json_sanitize(nm, sizeof nm, proc, 64);
            return fail_at(c, p, "unknown procedural model '%s' (car_shell, box, plate)", nm);
        } else {
            snprintf(nb.procedural, sizeof nb.procedural, "%s", proc);
        }
        double q[4] = {0, 0, 0, 1}, sc[3] = {1, 1, 1};
        prw_node n = prw_node_default();
        if (!get_v3(c, o, "translation", pl, &n.translation, false, NULL) ||
            !get_vec(c, o, "rotation", pl, q, 4, 0, false, -1e6, 1e6, NULL) ||
            !get_vec(c, o, "scale", pl, sc, 3, 0, false, -1e6, 1e6, NULL) || !find_material(c, o, pl, &nb.material) ||
            !get_num(c, o, "chord_rel", pl, &nb.chord_rel, false, 1e-7, false, 0.1, false) ||
            !get_num(c, o, "finest_rel", pl, &nb.finest_rel, false, 1e-7, false, 0.1, false) ||
            !get_num(c, o, "tol_px", pl, &nb.tol_px, false, 0.01, false, 100, false) ||
            !get_bool(c, o, "single_sided", pl, &nb.single_sided))
            return false;
        double ql = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        if (!(ql > 1e-9)) {
            prw_json_join(p, PLACE_MAX, pl, "rotation");
            return fail_at(c, p, "quaternion [x, y, z, w] must not be zero");
        }
        if (!(fabs(sc[0] * sc[1] * sc[2]) > 1e-18)) {
            prw_json_join(p, PLACE_MAX, pl, "scale");
            return fail_at(c, p, "must not be zero on any axis");
        }
        const cJSON *inst = item(o, "instances");
        if (inst) {
            prw_json_join(p, PLACE_MAX, pl, "instances");
            double g[2] = {1, 1};
            if (!cJSON_IsObject(inst)) return fail_at(c, p, "must be an object");
            if (!prw_json_check_keys(&c->j, inst, p, inst_keys, 2) || !get_vec(c, inst, "grid", p, g, 2, 0, true, 1, 1000, NULL) ||
                !get_vec(c, inst, "spacing", p, nb.spacing, 2, 0, true, -COORD_LIMIT, COORD_LIMIT, NULL))
                return false;
            if (g[0] != floor(g[0]) || g[1] != floor(g[1]) || g[0] * g[1] > 10000)
                return fail_at(c, p, "grid must be two integers >= 1 with at most 10000 instances");
            nb.grid[0] = (int)g[0];
            nb.grid[1] = (int)g[1];
        }
        n.rotation = (prw_dquat){q[0] / ql, q[1] / ql, q[2] / ql, q[3] / ql};
        n.scale = prw_v3(sc[0], sc[1], sc[2]);
        prw_copy_name(n.name, name ? name : defname);
        prw_copy_name(nb.name, n.name);
        prw_nurbs_model m;
        if (!prw_scene_nurbs_load(&nb, &m, c->e)) return prw_fail_wrap(c->e, "%s:%s", c->file, pl);
        prw_nurbs_model_trimmed_bounds(&m, &nb.model_min, &nb.model_max);
        prw_nurbs_model_free(&m);
        nb.node = prw_scene_add_node(c->s, &n);
        if (nb.node < 0 || prw_scene_add_nurbs(c->s, &nb) < 0) return fail_at(c, pl, "cannot add the model");
    }
    return true;
}

/* "environment": {"file", "scale", "rotation_deg"} or {"uniform_cd_m2"}; fills *env (present). */
static bool parse_environment(ctx *c, const cJSON *o, prw_environment *env)
{
    static const char *const keys[] = {"file", "scale", "rotation_deg", "uniform_cd_m2"};
    const char *pl = "environment";
    memset(env, 0, sizeof *env);
    if (!o) return true;
    if (!cJSON_IsObject(o)) return fail_at(c, pl, "must be an object");
    if (!prw_json_check_keys(&c->j, o, pl, keys, (int)PRW_ARRAY_LEN(keys))) return false;
    const char *file = NULL;
    double uni[3] = {0, 0, 0}, scale = 1, rot = 0;
    bool has_uni = false;
    if (!get_str(c, o, "file", pl, &file, false)) return false;
    if (!get_vec(c, o, "uniform_cd_m2", pl, uni, 3, 0, false, 0, EMISSION_LIMIT, &has_uni)) return false;
    if ((file != NULL) == has_uni) return fail_at(c, pl, "needs exactly one of 'file' and 'uniform_cd_m2'");
    if (has_uni) {
        if (item(o, "scale") || item(o, "rotation_deg"))
            return fail_at(c, pl, "'scale' and 'rotation_deg' apply to 'file' only");
        env->present = true;
        for (int k = 0; k < 3; k++) env->uniform[k] = (float)uni[k];
        return true;
    }
    if (!get_num(c, o, "scale", pl, &scale, false, 0, false, EMISSION_LIMIT, false) ||
        !get_num(c, o, "rotation_deg", pl, &rot, false, -360, false, 360, false))
        return false;
    char p[PLACE_MAX];
    prw_json_join(p, PLACE_MAX, pl, "file");
    if (!file[0]) return fail_at(c, p, "must not be empty");
    int n = file[0] == '/' ? snprintf(env->file, sizeof env->file, "%s", file)
                           : snprintf(env->file, sizeof env->file, "%s%s", c->dir, file);
    if (n < 0 || (size_t)n >= sizeof env->file) return fail_at(c, p, "path longer than %zu bytes", sizeof env->file - 1);
    struct stat st;
    if (stat(env->file, &st) == 0 && !S_ISREG(st.st_mode)) return fail_at(c, p, "%s: cannot open: not a regular file", env->file);
    char *bytes = NULL;
    size_t size = 0;
    prw_error fe;
    if (!prw_read_file_bounded(env->file, 0, 1, "an environment map", &bytes, &size, &fe)) return fail_at(c, p, "%s", fe.msg);
    env->file_hash = prw_hash64(bytes, size, 0x656e762d66696c65ull);
    free(bytes);
    env->present = true;
    env->scale = scale;
    env->rotation = rot * PRW_PI / 180.0;
    return true;
}

/* ---- entry points ---- */

bool prw_scene_parse_manifest(prw_scene *s, const char *text, size_t size, const char *path, prw_error *e)
{
    ctx c;
    memset(&c, 0, sizeof c);
    c.s = s;
    c.file = path ? path : "(manifest)";
    c.e = e;
    c.j = (prw_json_ctx){c.file, e};
    c.default_material = -1;
    c.first_material = s->material_count;
    const char *slash = strrchr(c.file, '/');
    if (slash && (size_t)(slash - c.file) + 2 <= sizeof c.dir) {
        memcpy(c.dir, c.file, (size_t)(slash - c.file) + 1);
        c.dir[slash - c.file + 1] = '\0';
    }
    if (!text) return fail_at(&c, "", "no manifest text");

    cJSON *root = prw_json_doc_parse(text, size, c.file, e);
    if (!root) return false;

    static const char *const keys[] = {"prw_manifest", "gltf", "materials", "meshes", "lights", "cameras",
                                       "environment", "nurbs"};
    prw_scene_mark mark = prw_scene_mark_get(s);
    const cJSON *gltf = NULL, *mats = NULL, *meshes = NULL, *lights = NULL, *cams = NULL, *nurbs = NULL;
    bool ok = cJSON_IsObject(root) ? true : fail_at(&c, "", "top level must be a JSON object");
    ok = ok && prw_json_check_keys(&c.j, root, "", keys, (int)PRW_ARRAY_LEN(keys));
    if (ok) {
        const cJSON *v = item(root, "prw_manifest");
        if (!v) ok = fail_at(&c, "prw_manifest", "missing (required; this reader understands version 1)");
        else if (!cJSON_IsNumber(v) || v->valuedouble != 1.0)
            ok = fail_at(&c, "prw_manifest", "unsupported version (this reader understands 1)");
    }
    ok = ok && get_obj_array(&c, root, "gltf", &gltf) && get_obj_array(&c, root, "materials", &mats) &&
         get_obj_array(&c, root, "meshes", &meshes) && get_obj_array(&c, root, "lights", &lights) &&
         get_obj_array(&c, root, "cameras", &cams) && get_obj_array(&c, root, "nurbs", &nurbs);
    /* materials first: meshes refer to them by name */
    ok = ok && parse_materials(&c, mats) && parse_gltf(&c, gltf) && parse_meshes(&c, meshes) &&
         parse_nurbs(&c, nurbs) && parse_lights(&c, lights) && parse_cameras(&c, cams);
    prw_environment env;
    memset(&env, 0, sizeof env);
    ok = ok && parse_environment(&c, item(root, "environment"), &env);
    cJSON_Delete(root);
    if (!ok) {
        prw_scene_rollback(s, mark);
        return false;
    }
    snprintf(s->source, sizeof s->source, "%s", c.file);
    if (env.present) s->environment = env; /* set only on success: all-or-nothing */
    prw_scene_update(s);
    prw_scene_note_missing(s, c.file);
    return true;
}

bool prw_scene_load_manifest(prw_scene *s, const char *path, prw_error *e)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) return prw_fail(e, "%s: cannot open: not a regular file", path);
    char *text = NULL;
    size_t size = 0;
    if (!prw_read_file_bounded(path, 0, PRW_JSON_MEMORY_PER_BYTE, "a scene manifest", &text, &size, e)) return false;
    bool ok = prw_scene_parse_manifest(s, text, size, path, e);
    free(text);
    return ok;
}
