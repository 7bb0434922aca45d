/* btf_eval.c — direction tables (the hull triangulation of prw_btf_interp.h) and the CPU evaluation. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_btf_eval.h"

#define PRW_BTF_DT_PARAMS const prw_btf_dirtab *dt,
#define PRW_BTF_DT_ARGS dt,
#define PRW_BTF_TRI_INV(i) (dt->tri_inv[(i)])
#define PRW_BTF_TRI_VERT(i) (dt->tri_vert[(i)])
#define PRW_BTF_DIR_COS(i) (dt->cos_theta[(i)])
#define PRW_BTF_GRID(i) (dt->grid ? dt->grid[(i)] : 0u)
#include "prw_btf_interp.h"

#define DEG (3.14159265358979323846 / 180.0)

typedef struct tri_list {
    uint32_t *v; /* 3 per triangle: point indices */
    uint32_t n, cap;
} tri_list;

static void tri_push(tri_list *t, uint32_t a, uint32_t b, uint32_t c)
{
    if (t->n == t->cap) {
        t->cap = t->cap ? 2 * t->cap : 256;
        t->v = prw_realloc(t->v, sizeof(uint32_t) * 3 * t->cap);
    }
    t->v[3 * t->n] = a, t->v[3 * t->n + 1] = b, t->v[3 * t->n + 2] = c;
    t->n++;
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The hull facets of points P (n of them, the origin strictly inside), coplanar sets fanned from their
 * lowest index in angular order (so each facet is triangulated once, the same way every time). */
static void hull(const double (*P)[3], uint32_t n, tri_list *out)
{
    const double eps = 1e-9;
    uint32_t *set = prw_malloc(sizeof(uint32_t) * n);
    double *ang = prw_malloc(sizeof(double) * n);
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = i + 1; j < n; j++)
            for (uint32_t k = j + 1; k < n; k++) {
                double a[3], b[3], nr[3];
                for (int c = 0; c < 3; c++) a[c] = P[j][c] - P[i][c], b[c] = P[k][c] - P[i][c];
                cross3(a, b, nr);
                double len = sqrt(dot3(nr, nr));
                if (!(len > 1e-12)) continue;
                for (int c = 0; c < 3; c++) nr[c] /= len;
                double off = dot3(nr, P[i]);
                if (off < 0) {
                    for (int c = 0; c < 3; c++) nr[c] = -nr[c];
                    off = -off;
                }
                if (!(off > eps)) continue; /* plane through the centre: not a facet */
                uint32_t ns = 0;
                bool facet = true, first = true;
                for (uint32_t m = 0; m < n && facet; m++) {
                    double h = dot3(nr, P[m]) - off;
                    if (h > eps) facet = false;
                    else if (h > -eps) {
                        if (m < k && m != i && m != j) first = false; /* handled from a lower triple */
                        set[ns++] = m;
                    }
                }
                if (!facet || !first) continue;
                if (ns == 3) {
                    tri_push(out, i, j, k);
                    continue;
                }
                /* coplanar: order around the centroid, fan from the lowest index (set[0] = i) */
                double cen[3] = {0, 0, 0}, e1[3], e2[3];
                for (uint32_t q = 0; q < ns; q++)
                    for (int c = 0; c < 3; c++) cen[c] += P[set[q]][c] / ns;
                for (int c = 0; c < 3; c++) e1[c] = P[i][c] - cen[c];
                cross3(nr, e1, e2);
                for (uint32_t q = 0; q < ns; q++) {
                    double r[3] = {P[set[q]][0] - cen[0], P[set[q]][1] - cen[1], P[set[q]][2] - cen[2]};
                    double an = atan2(dot3(r, e2), dot3(r, e1));
                    ang[q] = an < -1e-12 ? an + 2 * 3.14159265358979323846 : fmax(an, 0.0);
                }
                for (uint32_t q = 1; q < ns; q++) /* insertion sort by angle; set[0] (angle 0) stays first */
                    for (uint32_t p = q; p > 1 && ang[p - 1] > ang[p]; p--) {
                        double ta = ang[p];
                        ang[p] = ang[p - 1], ang[p - 1] = ta;
                        uint32_t ts = set[p];
                        set[p] = set[p - 1], set[p - 1] = ts;
                    }
                for (uint32_t q = 1; q + 1 < ns; q++) tri_push(out, set[0], set[q], set[q + 1]);
            }
    free(set), free(ang);
}

void prw_btf_dirtab_free(prw_btf_dirtab *t)
{
    free(t->tri_inv), free(t->tri_vert), free(t->cos_theta), free(t->grid);
    memset(t, 0, sizeof *t);
}

bool prw_btf_dirtab_build(const float *dirs, uint32_t n, prw_btf_dirtab *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    if (n == 0 || n > PRW_BTF_DIRS_MAX) return prw_fail(e, "btf directions: %u directions (1..%u)", n, PRW_BTF_DIRS_MAX);
    double thmax = 0;
    for (uint32_t i = 0; i < n; i++) {
        double th = dirs[2 * i], ph = dirs[2 * i + 1];
        if (!isfinite(th) || !isfinite(ph) || th < 0 || th > 89.9 * DEG)
            return prw_fail(e, "btf directions: direction %u (theta %g, phi %g rad): theta must be in [0, 89.9] degrees", i,
                            th, ph);
        thmax = fmax(thmax, th);
    }
    /* points: measured, horizon, south pole */
    uint32_t cap = 2 * n + 9;
    double (*P)[3] = prw_malloc(sizeof(double) * 3 * cap);
    uint32_t *src = prw_malloc(sizeof(uint32_t) * cap); /* per point: its measured index (| HORIZON) */
    for (uint32_t i = 0; i < n; i++) {
        prw_btf_dir_vector(dirs[2 * i], dirs[2 * i + 1], P[i]);
        src[i] = i;
        for (uint32_t j = 0; j < i; j++)
            if (dot3(P[i], P[j]) > 1 - 1e-10) {
                free(P), free(src);
                return prw_fail(e, "btf directions: directions %u and %u are the same", j, i);
            }
    }
    uint32_t np = n;
    /* horizon: the outermost ring's azimuths (directions within 0.06 degrees of the largest theta) */
    for (uint32_t i = 0; i < n && thmax > 1e-3; i++) {
        if (dirs[2 * i] < thmax - 1e-3) continue;
        double h[3] = {cos(dirs[2 * i + 1]), sin(dirs[2 * i + 1]), 0};
        bool dup = false;
        for (uint32_t q = n; q < np; q++) dup = dup || dot3(h, P[q]) > 1 - 1e-10;
        if (dup) continue;
        memcpy(P[np], h, sizeof h);
        src[np++] = i | PRW_BTF_HORIZON;
    }
    /* too few or one-sided: 8 azimuths, each standing for the nearest measured direction */
    bool gap = np - n < 3;
    for (uint32_t q = n; q < np && !gap; q++) {
        /* a gap of 180 degrees or more leaves the centre outside the hull */
        double best = 7;
        for (uint32_t r = n; r < np; r++) {
            if (r == q) continue;
            double d = atan2(P[r][1], P[r][0]) - atan2(P[q][1], P[q][0]);
            while (d <= 0) d += 2 * 3.14159265358979323846;
            best = fmin(best, d);
        }
        gap = best >= 179 * DEG;
    }
    if (gap) {
        np = n;
        for (int k = 0; k < 8; k++) {
            double h[3] = {cos(k * 45 * DEG), sin(k * 45 * DEG), 0};
            uint32_t nb = 0;
            for (uint32_t i = 1; i < n; i++)
                if (dot3(h, P[i]) > dot3(h, P[nb])) nb = i;
            memcpy(P[np], h, sizeof h);
            src[np++] = nb | PRW_BTF_HORIZON;
        }
    }
    P[np][0] = 0, P[np][1] = 0, P[np][2] = -1;
    uint32_t pole = np++;
    tri_list tl = {0};
    hull((const double (*)[3])P, np, &tl);
    uint32_t nt = 0;
    for (uint32_t t = 0; t < tl.n; t++)
        if (tl.v[3 * t] != pole && tl.v[3 * t + 1] != pole && tl.v[3 * t + 2] != pole) nt++;
    out->count = n;
    out->tri_count = nt;
    out->cos_theta = prw_malloc(sizeof(float) * n);
    for (uint32_t i = 0; i < n; i++) out->cos_theta[i] = (float)P[i][2];
    out->tri_inv = prw_malloc(sizeof(float) * 9 * (nt ? nt : 1));
    out->tri_vert = prw_malloc(sizeof(uint32_t) * 3 * (nt ? nt : 1));
    uint32_t o = 0;
    for (uint32_t t = 0; t < tl.n; t++) {
        const uint32_t *v = tl.v + 3 * t;
        if (v[0] == pole || v[1] == pole || v[2] == pole) continue;
        /* inverse of the matrix with columns A, B, C: rows (B x C, C x A, A x B) / det */
        double r0[3], r1[3], r2[3];
        cross3(P[v[1]], P[v[2]], r0);
        cross3(P[v[2]], P[v[0]], r1);
        cross3(P[v[0]], P[v[1]], r2);
        double det = dot3(P[v[0]], r0);
        for (int c = 0; c < 3; c++) {
            out->tri_inv[9 * o + c] = (float)(r0[c] / det);
            out->tri_inv[9 * o + 3 + c] = (float)(r1[c] / det);
            out->tri_inv[9 * o + 6 + c] = (float)(r2[c] / det);
        }
        for (int k = 0; k < 3; k++) out->tri_vert[3 * o + k] = src[v[k]];
        o++;
    }
    free(tl.v), free(P), free(src);
    if (nt == 0) {
        prw_btf_dirtab_free(out);
        return prw_fail(e, "btf directions: the %u directions give no triangulation", n);
    }
    /* the lookup grid: per cell the triangles holding a 9 x 9 lattice of its directions (edges included),
     * found without the grid, the most frequent first (prw_btf_interp.h) */
    uint32_t *grid = prw_calloc(PRW_BTF_GRID_WORDS, sizeof(uint32_t));
    for (uint32_t i = 0; i < PRW_BTF_GRID_T; i++)
        for (uint32_t j = 0; j < PRW_BTF_GRID_P; j++) {
            uint32_t tri[81], cnt[81], nd = 0;
            for (int si = 0; si <= 8; si++)
                for (int sj = 0; sj <= 8; sj++) {
                    double th = (i + si / 8.0) / PRW_BTF_GRID_T * 1.5707963267948966;
                    double ph = -3.14159265358979 + (j + sj / 8.0) / PRW_BTF_GRID_P * 6.283185307179586;
                    th = fmin(th, 1.5707963267948966 - 1e-6);
                    float d[3] = {(float)(sin(th) * cos(ph)), (float)(sin(th) * sin(ph)), (float)cos(th)};
                    uint32_t best = 0;
                    float bm = -3e38f;
                    for (uint32_t t = 0; t < nt; t++) {
                        const float *m = out->tri_inv + 9 * t;
                        float a = m[0] * d[0] + m[1] * d[1] + m[2] * d[2], b = m[3] * d[0] + m[4] * d[1] + m[5] * d[2],
                              c = m[6] * d[0] + m[7] * d[1] + m[8] * d[2], s = a + b + c;
                        if (!(s > 0)) continue;
                        float mn = fminf(a, fminf(b, c)) / s;
                        if (mn > bm) bm = mn, best = t;
                    }
                    uint32_t q = 0;
                    while (q < nd && tri[q] != best) q++;
                    if (q == nd) tri[nd] = best, cnt[nd++] = 0;
                    cnt[q] += si == 4 && sj == 4 ? 1000 : 1; /* the centre's triangle first */
                }
            uint32_t pick[PRW_BTF_GRID_C];
            for (uint32_t k = 0; k < PRW_BTF_GRID_C; k++) {
                uint32_t bq = 0;
                for (uint32_t q = 1; q < nd; q++)
                    if (cnt[q] > cnt[bq]) bq = q;
                pick[k] = cnt[bq] ? tri[bq] : pick[0]; /* fewer than PRW_BTF_GRID_C: repeat the first */
                cnt[bq] = 0;
            }
            uint32_t cell = i * PRW_BTF_GRID_P + j;
            grid[2 * cell] = pick[0] | pick[1] << 16;
            grid[2 * cell + 1] = pick[2] | pick[3] << 16;
        }
    out->grid = grid;
    return true;
}

void prw_btf_dirtab_weights(const prw_btf_dirtab *t, const double d[3], bool light, uint32_t idx[3], float w[3])
{
    double l = sqrt(dot3(d, d));
    if (!(l > 0)) l = 1;
    prw_btf_interp_dir(t, (float)(d[0] / l), (float)(d[1] / l), (float)(d[2] / l), t->tri_count, idx, w);
    if (light) prw_btf_interp_light(t, (float)(d[2] / l), idx, w);
}

/* The 4 texels around continuous texel coordinates (x, y) (wrapped in double first). */
static void texels(double x, double y, uint32_t W, uint32_t H, uint32_t tx[2], uint32_t ty[2], float wx[2], float wy[2])
{
    double fx = x - 0.5, fy = y - 0.5;
    if (!isfinite(fx) || !isfinite(fy)) fx = fy = 0;
    double x0 = floor(fx), y0 = floor(fy);
    wx[1] = (float)(fx - x0), wx[0] = 1 - wx[1];
    wy[1] = (float)(fy - y0), wy[0] = 1 - wy[1];
    x0 = fmod(x0, (double)W), y0 = fmod(y0, (double)H);
    if (x0 < 0) x0 += W;
    if (y0 < 0) y0 += H;
    tx[0] = (uint32_t)x0 % W, ty[0] = (uint32_t)y0 % H;
    tx[1] = (tx[0] + 1) % W, ty[1] = (ty[0] + 1) % H;
}

void prw_btf_eval(const prw_btf *b, const prw_btf_dirtab *views, const prw_btf_dirtab *lights, double x, double y,
                  const double wv[3], const double wl[3], float rgb[3])
{
    uint32_t vi[3], li[3], tx[2], ty[2];
    float vw[3], lw[3], wx[2], wy[2];
    prw_btf_dirtab_weights(views, wv, false, vi, vw);
    prw_btf_dirtab_weights(lights, wl, true, li, lw);
    texels(x, y, b->width, b->height, tx, ty, wx, wy);
    float s[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 3; c++) {
            float w = vw[a] * lw[c];
            if (!(w > 0)) continue;
            for (int j = 0; j < 2; j++)
                for (int i = 0; i < 2; i++) {
                    const float *px = b->rgb + prw_btf_at(b, vi[a], li[c], tx[i], ty[j]);
                    float wt = w * wx[i] * wy[j];
                    for (int k = 0; k < 3; k++) s[k] += wt * px[k];
                }
        }
    memcpy(rgb, s, sizeof s);
}

void prw_btf_material_eval(const prw_btf_material *m, double x, double y, const double wv[3], const double wl[3],
                           float rgb[3])
{
    const prw_btf_packed *p = &m->p;
    uint32_t vi[3], li[3], tx[2], ty[2];
    float vw[3], lw[3], wx[2], wy[2];
    prw_btf_dirtab_weights(&m->views, wv, false, vi, vw);
    prw_btf_dirtab_weights(m->shared ? &m->views : &m->lights, wl, true, li, lw);
    texels(x, y, p->width, p->height, tx, ty, wx, wy);
    float s[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++)
        for (int c = 0; c < 3; c++) {
            float w = vw[a] * lw[c];
            if (!(w > 0)) continue;
            for (int j = 0; j < 2; j++)
                for (int i = 0; i < 2; i++) {
                    float wt = w * wx[i] * wy[j];
                    if (!(wt > 0)) continue;
                    for (uint32_t k = 0; k < 3; k++) s[k] += wt * prw_btf_packed_value(p, vi[a], li[c], tx[i], ty[j], k);
                }
        }
    memcpy(rgb, s, sizeof s);
}

bool prw_btf_material_from_packed(prw_btf_packed *p, const char *name, prw_btf_material *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    out->p = *p;
    memset(p, 0, sizeof *p);
    prw_error e2;
    if (!prw_btf_dirtab_build(out->p.view_dirs, out->p.views, &out->views, &e2)) {
        prw_btf_material_free(out);
        return prw_fail(e, "%s: view %s", name, e2.msg);
    }
    out->shared = out->p.views == out->p.lights &&
                  memcmp(out->p.view_dirs, out->p.light_dirs, sizeof(float) * 2 * out->p.views) == 0;
    if (!out->shared && !prw_btf_dirtab_build(out->p.light_dirs, out->p.lights, &out->lights, &e2)) {
        prw_btf_material_free(out);
        return prw_fail(e, "%s: light %s", name, e2.msg);
    }
    return true;
}

bool prw_btf_material_load(const char *path, prw_btf_material *out, prw_error *e)
{
    memset(out, 0, sizeof *out);
    prw_btf_packed p;
    if (!prw_btf_packed_read(path, &p, e)) return false;
    return prw_btf_material_from_packed(&p, path, out, e);
}

void prw_btf_material_free(prw_btf_material *m)
{
    prw_btf_packed_free(&m->p);
    prw_btf_dirtab_free(&m->views);
    prw_btf_dirtab_free(&m->lights);
    memset(m, 0, sizeof *m);
}
