/* JSON reader for trimmed-NURBS models (format: nurbs_json.md), on cJSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "prw_nurbs_json.h"
#include "prw_nurbs_make.h"

typedef struct jctx {
    const char *name;
    prw_error *e;
    double scale; /* metres per unit */
} jctx;

/* JSON paths are for messages: truncation is harmless. */
static void jpath(char *out, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void jpath(char *out, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(out, 256, fmt, ap);
    va_end(ap);
}

#define JFAIL(c, path, ...) jfail((c), (path), __VA_ARGS__)

static bool jfail(jctx *c, const char *path, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static bool jfail(jctx *c, const char *path, const char *fmt, ...)
{
    char reason[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(reason, sizeof reason, fmt, ap);
    va_end(ap);
    return prw_fail(c->e, "%s:%s: %s", c->name, path, reason);
}

static bool get_num(jctx *c, const cJSON *j, const char *path, double *out)
{
    if (!cJSON_IsNumber(j) || !isfinite(j->valuedouble)) return JFAIL(c, path, "expected a finite number");
    *out = j->valuedouble;
    return true;
}

static bool get_int(jctx *c, const cJSON *j, const char *path, int lo, int hi, int *out)
{
    double d = 0;
    if (!get_num(c, j, path, &d)) return false;
    if (d != floor(d) || d < lo || d > hi) return JFAIL(c, path, "expected an integer in %d..%d", lo, hi);
    *out = (int)d;
    return true;
}

static bool get_vec(jctx *c, const cJSON *j, const char *path, int nmin, int nmax, double *out, int *n)
{
    int cnt = cJSON_GetArraySize(j);
    if (!cJSON_IsArray(j) || cnt < nmin || cnt > nmax)
        return JFAIL(c, path, "expected an array of %d..%d numbers", nmin, nmax);
    char p[256];
    for (int i = 0; i < cnt; i++) {
        jpath(p, "%s[%d]", path, i);
        if (!get_num(c, cJSON_GetArrayItem(j, i), p, &out[i])) return false;
    }
    if (n) *n = cnt;
    return true;
}

static bool get_knots(jctx *c, const cJSON *j, const char *path, int count, double *out)
{
    if (!cJSON_IsArray(j) || cJSON_GetArraySize(j) != count)
        return JFAIL(c, path, "expected %d knots, got %d", count, cJSON_IsArray(j) ? cJSON_GetArraySize(j) : -1);
    char p[256];
    int i = 0;
    for (const cJSON *k = j->child; k; k = k->next, i++) {
        jpath(p, "%s[%d]", path, i);
        if (!get_num(c, k, p, &out[i])) return false;
    }
    return true;
}

static const cJSON *member(const cJSON *o, const char *k) { return cJSON_GetObjectItemCaseSensitive(o, k); }

/* {"degree": p, "knots": [...], "points": [[u,v(,w)]...]} or {"polyline": [[u,v]...]} */
static bool parse_segment(jctx *c, const cJSON *j, const char *path, prw_nurbs_curve *out)
{
    char p[256];
    memset(out, 0, sizeof *out);
    if (!cJSON_IsObject(j)) return JFAIL(c, path, "expected an object with \"polyline\" or \"curve\"");
    const cJSON *pl = member(j, "polyline"), *cv = member(j, "curve");
    if (pl) {
        int n = cJSON_GetArraySize(pl);
        if (!cJSON_IsArray(pl) || n < 2 || n > PRW_NURBS_MAX_CTRL)
            return JFAIL(c, path, "polyline: expected an array of at least 2 points");
        prw_dvec3 *pts = prw_malloc(sizeof(prw_dvec3) * (size_t)n);
        int i = 0;
        for (const cJSON *q = pl->child; q; q = q->next, i++) {
            double xy[2];
            jpath(p, "%s.polyline[%d]", path, i);
            if (!get_vec(c, q, p, 2, 2, xy, NULL)) {
                free(pts);
                return false;
            }
            pts[i] = prw_v3(xy[0], xy[1], 0);
        }
        jpath(p, "%s.polyline", path);
        bool ok = prw_nurbs_make_polyline(out, 2, pts, n, c->e);
        free(pts);
        return ok || prw_fail_wrap(c->e, "%s:%s", c->name, p);
    }
    if (!cv || !cJSON_IsObject(cv)) return JFAIL(c, path, "expected \"polyline\" or \"curve\"");
    int deg = 1, n = cJSON_GetArraySize(member(cv, "points"));
    jpath(p, "%s.curve.degree", path);
    if (!get_int(c, member(cv, "degree"), p, 1, PRW_NURBS_MAX_DEGREE, &deg)) return false;
    jpath(p, "%s.curve.points", path);
    if (!cJSON_IsArray(member(cv, "points")) || n < deg + 1 || n > PRW_NURBS_MAX_CTRL)
        return JFAIL(c, p, "expected at least degree + 1 = %d points", deg + 1);
    if (!prw_nurbs_curve_alloc(out, 2, deg, n, c->e)) return prw_fail_wrap(c->e, "%s:%s", c->name, p);
    int i = 0;
    for (const cJSON *q = member(cv, "points")->child; q; q = q->next, i++) {
        double xyw[3] = {0, 0, 1};
        jpath(p, "%s.curve.points[%d]", path, i);
        if (!get_vec(c, q, p, 2, 3, xyw, NULL)) goto fail;
        if (!(xyw[2] > 0)) {
            JFAIL(c, p, "weight %g is not positive", xyw[2]);
            goto fail;
        }
        prw_nurbs_curve_set(out, i, prw_v3(xyw[0], xyw[1], 0), xyw[2]);
    }
    jpath(p, "%s.curve.knots", path);
    if (!get_knots(c, member(cv, "knots"), p, n + deg + 1, out->knots)) goto fail;
    if (!prw_nurbs_curve_validate(out, c->e)) {
        prw_fail_wrap(c->e, "%s:%s.curve", c->name, path);
        goto fail;
    }
    return true;
fail:
    prw_nurbs_curve_free(out);
    return false;
}

static bool parse_loop(jctx *c, const cJSON *j, const char *path, prw_trimmed_surface *t)
{
    if (!cJSON_IsArray(j) || cJSON_GetArraySize(j) < 1) return JFAIL(c, path, "expected a non-empty array of segments");
    prw_trim_loop *l = prw_trimmed_surface_add_loop(t);
    char p[256];
    int i = 0;
    for (const cJSON *s = j->child; s; s = s->next, i++) {
        prw_nurbs_curve cv;
        jpath(p, "%s[%d]", path, i);
        if (!parse_segment(c, s, p, &cv)) return false;
        prw_trim_loop_add(l, &cv, NULL);
    }
    return true;
}

static bool parse_nurbs(jctx *c, const cJSON *j, const char *path, prw_nurbs_surface *s)
{
    char p[256];
    double deg[2], cnt[2];
    jpath(p, "%s.degree", path);
    if (!get_vec(c, member(j, "degree"), p, 2, 2, deg, NULL)) return false;
    jpath(p, "%s.count", path);
    if (!get_vec(c, member(j, "count"), p, 2, 2, cnt, NULL)) return false;
    for (int k = 0; k < 2; k++)
        if (deg[k] != floor(deg[k]) || cnt[k] != floor(cnt[k]) || deg[k] < 1 || deg[k] > PRW_NURBS_MAX_DEGREE ||
            cnt[k] < deg[k] + 1 || cnt[k] > PRW_NURBS_MAX_CTRL)
            return JFAIL(c, path, "degree %g x %g with %g x %g control points is not valid", deg[0], deg[1], cnt[0], cnt[1]);
    /* the points the counts claim must be in the file before the net is allocated */
    const cJSON *pts = member(j, "points");
    jpath(p, "%s.points", path);
    if (!cJSON_IsArray(pts) || (double)cJSON_GetArraySize(pts) != cnt[0] * cnt[1])
        return JFAIL(c, p, "expected count[0] x count[1] = %g points", cnt[0] * cnt[1]);
    jpath(p, "%s", path);
    if (!prw_nurbs_surface_alloc(s, (int)deg[0], (int)deg[1], (int)cnt[0], (int)cnt[1], c->e))
        return prw_fail_wrap(c->e, "%s:%s", c->name, p);
    int i = 0;
    for (const cJSON *q = pts->child; q; q = q->next, i++) {
        double xyzw[4] = {0, 0, 0, 1};
        jpath(p, "%s.points[%d]", path, i);
        if (!get_vec(c, q, p, 3, 4, xyzw, NULL)) goto fail;
        if (!(xyzw[3] > 0)) {
            JFAIL(c, p, "weight %g is not positive", xyzw[3]);
            goto fail;
        }
        prw_nurbs_surface_set(s, i % s->nu, i / s->nu, prw_v3(xyzw[0], xyzw[1], xyzw[2]), xyzw[3]);
    }
    jpath(p, "%s.knots_u", path);
    if (!get_knots(c, member(j, "knots_u"), p, s->nu + s->degree_u + 1, s->knots_u)) goto fail;
    jpath(p, "%s.knots_v", path);
    if (!get_knots(c, member(j, "knots_v"), p, s->nv + s->degree_v + 1, s->knots_v)) goto fail;
    if (!prw_nurbs_surface_validate(s, c->e)) {
        prw_fail_wrap(c->e, "%s:%s", c->name, path);
        goto fail;
    }
    return true;
fail:
    prw_nurbs_surface_free(s);
    return false;
}

static bool parse_surface(jctx *c, const cJSON *j, int index, prw_trimmed_surface *t)
{
    char path[128], p[256];
    snprintf(path, sizeof path, "surfaces[%d]", index);
    if (!cJSON_IsObject(j)) return JFAIL(c, path, "expected an object");
    t->source = index;
    const cJSON *x;
    bool have = false;
    if ((x = member(j, "nurbs"))) {
        jpath(p, "%s.nurbs", path);
        if (!cJSON_IsObject(x)) return JFAIL(c, p, "expected an object");
        if (!parse_nurbs(c, x, p, &t->surface)) return false;
        have = true;
    } else if ((x = member(j, "sphere"))) {
        double ctr[3], r = 0;
        jpath(p, "%s.sphere.centre", path);
        if (!get_vec(c, member(x, "centre"), p, 3, 3, ctr, NULL)) return false;
        jpath(p, "%s.sphere.radius", path);
        if (!get_num(c, member(x, "radius"), p, &r)) return false;
        if (!prw_nurbs_make_sphere(&t->surface, prw_v3(ctr[0], ctr[1], ctr[2]), r, c->e))
            return prw_fail_wrap(c->e, "%s:%s", c->name, p);
        have = true;
    } else if ((x = member(j, "torus"))) {
        double ctr[3], R = 0, r = 0;
        jpath(p, "%s.torus.centre", path);
        if (!get_vec(c, member(x, "centre"), p, 3, 3, ctr, NULL)) return false;
        jpath(p, "%s.torus.major", path);
        if (!get_num(c, member(x, "major"), p, &R)) return false;
        jpath(p, "%s.torus.minor", path);
        if (!get_num(c, member(x, "minor"), p, &r)) return false;
        if (!prw_nurbs_make_torus(&t->surface, prw_v3(ctr[0], ctr[1], ctr[2]), R, r, c->e))
            return prw_fail_wrap(c->e, "%s:%s.torus", c->name, path);
        have = true;
    }
    if (!have) return JFAIL(c, path, "expected one of \"nurbs\", \"sphere\", \"torus\"");
    if ((x = member(j, "colour"))) {
        double rgb[3];
        jpath(p, "%s.colour", path);
        if (!get_vec(c, x, p, 3, 3, rgb, NULL)) return false;
        for (int k = 0; k < 3; k++) t->colour[k] = (float)fmin(fmax(rgb[k], 0), 1);
        t->has_colour = true;
    }
    if ((x = member(j, "outer"))) {
        jpath(p, "%s.outer", path);
        if (!parse_loop(c, x, p, t)) return false;
        t->natural_outer = false;
    }
    if ((x = member(j, "inner"))) {
        jpath(p, "%s.inner", path);
        if (!cJSON_IsArray(x)) return JFAIL(c, p, "expected an array of loops");
        int i = 0;
        for (const cJSON *l = x->child; l; l = l->next, i++) {
            jpath(p, "%s.inner[%d]", path, i);
            if (!parse_loop(c, l, p, t)) return false;
        }
    }
    prw_dmat4 sc = prw_dm4_identity();
    sc.m[0] = sc.m[5] = sc.m[10] = c->scale;
    prw_nurbs_surface_transform(&t->surface, &sc);
    return true;
}

static const struct {
    const char *name;
    double metres;
} units[] = {{"m", 1}, {"mm", 1e-3}, {"cm", 1e-2}, {"km", 1e3}, {"um", 1e-6}, {"in", 0.0254}, {"ft", 0.3048}};

bool prw_nurbs_json_parse(const char *text, size_t len, const char *name, prw_nurbs_model *out, prw_error *e)
{
    jctx c = {name, e, 1.0};
    prw_nurbs_model_init(out);
    cJSON *root = cJSON_ParseWithLength(text, len);
    if (!root) return prw_fail(e, "%s:%ld: not valid JSON", name, (long)(cJSON_GetErrorPtr() ? cJSON_GetErrorPtr() - text : 0));
    bool ok = false;
    const cJSON *x;
    if (!cJSON_IsObject(root) || !cJSON_IsNumber(member(root, "prw_nurbs")) || member(root, "prw_nurbs")->valuedouble != 1) {
        JFAIL(&c, "prw_nurbs", "expected \"prw_nurbs\": 1");
        goto done;
    }
    if ((x = member(root, "unit"))) {
        bool found = false;
        for (size_t i = 0; i < PRW_ARRAY_LEN(units) && cJSON_IsString(x); i++)
            if (!strcmp(x->valuestring, units[i].name)) c.scale = units[i].metres, found = true;
        if (!found) {
            JFAIL(&c, "unit", "expected one of m, mm, cm, km, um, in, ft");
            goto done;
        }
    }
    if ((x = member(root, "scale"))) {
        double s = 0;
        if (!get_num(&c, x, "scale", &s)) goto done;
        if (!(s > 0)) {
            JFAIL(&c, "scale", "must be positive");
            goto done;
        }
        c.scale *= s;
    }
    x = member(root, "surfaces");
    if (!cJSON_IsArray(x)) {
        JFAIL(&c, "surfaces", "expected an array");
        goto done;
    }
    int i = 0;
    for (const cJSON *s = x->child; s; s = s->next, i++) {
        prw_trimmed_surface *t = prw_nurbs_model_add(out);
        if (!parse_surface(&c, s, i, t)) {
            prw_nurbs_model_pop(out);
            goto done;
        }
    }
    ok = true;
done:
    cJSON_Delete(root);
    if (!ok) prw_nurbs_model_free(out);
    return ok;
}

bool prw_nurbs_json_load(const char *path, prw_nurbs_model *out, prw_error *e)
{
    char *data;
    size_t size;
    if (!prw_read_file_bounded(path, 0, PRW_JSON_MEMORY_PER_BYTE, "a NURBS JSON model", &data, &size, e)) return false;
    bool ok = prw_nurbs_json_parse(data, size, path, out, e);
    free(data);
    return ok;
}
