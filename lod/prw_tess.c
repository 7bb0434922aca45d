/* Grid + boundary-strip tessellation of one trimmed surface (see prw_tess.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_earclip.h"
#include "prw_tess.h"
#include "prw_trim.h"

typedef struct pts {
    double *xy;
    int n, cap;
} pts;

static int add_pt(pts *p, double u, double v)
{
    if (p->n == p->cap) {
        p->cap = p->cap ? 2 * p->cap : 256;
        p->xy = prw_realloc(p->xy, sizeof(double) * 2 * (size_t)p->cap);
    }
    p->xy[2 * p->n] = u;
    p->xy[2 * p->n + 1] = v;
    return p->n++;
}

typedef struct ilist {
    int *v;
    int n, cap;
} ilist;

static void ipush(ilist *l, int x)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->v = prw_realloc(l->v, sizeof(int) * (size_t)l->cap);
    }
    l->v[l->n++] = x;
}

static int clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }

/* Cells in one direction from sampled second derivatives: h = sqrt(8 tol / |S''|). */
static void choose_cells(const prw_trimmed_surface *t, const prw_tess_options *o, double tol, int *cu, int *cv)
{
    const prw_nurbs_surface *s = &t->surface;
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    int su = 0, sv = 0;
    for (int i = s->degree_u; i < s->nu; i++) su += s->knots_u[i] < s->knots_u[i + 1];
    for (int i = s->degree_v; i < s->nv; i++) sv += s->knots_v[i] < s->knots_v[i + 1];
    int ns = 4 * (su + sv) + 8;
    if (ns > 64) ns = 64;
    double muu = 0, mvv = 0;
    for (int a = 0; a <= ns; a++)
        for (int b = 0; b <= ns; b++) {
            prw_dvec3 d[9];
            prw_nurbs_surface_derivs(s, u0 + (u1 - u0) * a / ns, v0 + (v1 - v0) * b / ns, 2, d);
            double x = prw_v3_len(d[2 * 3 + 0]), y = prw_v3_len(d[0 * 3 + 2]);
            if (isfinite(x)) muu = fmax(muu, x);
            if (isfinite(y)) mvv = fmax(mvv, y);
        }
    int mn = o->min_cells > 0 ? o->min_cells : 4, mx = o->max_cells > 0 ? o->max_cells : 256;
    if (mx < mn) mx = mn;
    double nu = muu > 0 ? (u1 - u0) / sqrt(8 * tol / muu) : 1;
    double nv = mvv > 0 ? (v1 - v0) / sqrt(8 * tol / mvv) : 1;
    *cu = clampi((int)fmin(ceil(nu), 1e6), su > mn ? su : mn, mx);
    *cv = clampi((int)fmin(ceil(nv), 1e6), sv > mn ? sv : mn, mx);
    if (*cu < su) *cu = su > mx ? mx : su;
    if (*cv < sv) *cv = sv > mx ? mx : sv;
}

void prw_tess_mesh_free(prw_tess_mesh *m)
{
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->tris);
    memset(m, 0, sizeof *m);
}

bool prw_tess_surface(const prw_trimmed_surface *t, const prw_tess_options *opt, prw_tess_mesh *m, prw_error *e)
{
    memset(m, 0, sizeof *m);
    prw_tess_options o = opt ? *opt : (prw_tess_options){0};
    const prw_nurbs_surface *s = &t->surface;
    if (!prw_nurbs_surface_validate(s, e)) return false;
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    prw_dvec3 lo, hi;
    prw_nurbs_surface_bounds(s, &lo, &hi);
    double diag = prw_v3_len(prw_v3_sub(hi, lo));
    double chord = o.chord_tol > 0 ? o.chord_tol : 1e-3 * diag;
    if (!(chord > 0)) chord = 1e-300;
    double ttol = o.trim_tol > 0 ? o.trim_tol : 1e-4 * fmax(u1 - u0, v1 - v0);

    prw_trim_region reg;
    if (!prw_trim_region_build(t, ttol, &reg, e)) return false;
    if (reg.count == 0) {
        prw_trim_region_free(&reg);
        return prw_fail(e, "trimmed surface %d: no trim loop with positive area", t->source);
    }
    int cu, cv;
    choose_cells(t, &o, chord, &cu, &cv);
    m->cells_u = cu;
    m->cells_v = cv;
    double du = (u1 - u0) / cu, dv = (v1 - v0) / cv;
    double *gu = prw_malloc(sizeof(double) * (size_t)(cu + 1)), *gv = prw_malloc(sizeof(double) * (size_t)(cv + 1));
    for (int i = 0; i <= cu; i++) gu[i] = i == cu ? u1 : u0 + du * i;
    for (int j = 0; j <= cv; j++) gv[j] = j == cv ? v1 : v0 + dv * j;

    /* 3. full cells: not touched by any loop edge (within a quarter cell), centre inside */
    unsigned char *touched = prw_calloc((size_t)cu * (size_t)cv, 1);
    bool natural_only = t->natural_outer && t->nloops == 0 && reg.count == 1;
    if (!natural_only)
        for (int l = 0; l < reg.count; l++) {
            const prw_trim_polygon *pl = &reg.loops[l];
            for (int i = 0, k = pl->n - 1; i < pl->n; k = i++) {
                const double *a = pl->uv + 2 * k, *b = pl->uv + 2 * i;
                double eu = 0.25 * du, ev = 0.25 * dv;
                int ia = clampi((int)floor((fmin(a[0], b[0]) - eu - u0) / du), 0, cu - 1);
                int ib = clampi((int)floor((fmax(a[0], b[0]) + eu - u0) / du), 0, cu - 1);
                int ja = clampi((int)floor((fmin(a[1], b[1]) - ev - v0) / dv), 0, cv - 1);
                int jb = clampi((int)floor((fmax(a[1], b[1]) + ev - v0) / dv), 0, cv - 1);
                for (int jj = ja; jj <= jb; jj++)
                    for (int ii = ia; ii <= ib; ii++) touched[(size_t)jj * cu + ii] = 1;
            }
        }
    unsigned char *full = prw_calloc((size_t)cu * (size_t)cv, 1);
    for (int j = 0; j < cv; j++)
        for (int i = 0; i < cu; i++)
            full[(size_t)j * cu + i] =
                !touched[(size_t)j * cu + i] &&
                (natural_only ||
                 prw_trim_classify(&reg, 0.5 * (gu[i] + gu[i + 1]), 0.5 * (gv[j] + gv[j + 1])) == PRW_TRIM_INSIDE);
    free(touched);
#define FULL(i, j) ((i) >= 0 && (j) >= 0 && (i) < cu && (j) < cv && full[(size_t)(j) * cu + (i)])
    /* remove diagonal-only contacts (pinch vertices of the staircase boundary) */
    for (bool changed = true; changed;) {
        changed = false;
        for (int j = 0; j + 1 < cv; j++)
            for (int i = 0; i + 1 < cu; i++) {
                bool a = FULL(i, j), b = FULL(i + 1, j), c = FULL(i, j + 1), d = FULL(i + 1, j + 1);
                if (a && d && !b && !c) full[(size_t)j * cu + i] = 0, changed = true;
                else if (b && c && !a && !d) full[(size_t)j * cu + i + 1] = 0, changed = true;
            }
    }

    /* points: grid vertices used by full cells or the staircase, then loop vertices */
    pts P = {0};
    int *gid = prw_malloc(sizeof(int) * (size_t)(cu + 1) * (size_t)(cv + 1));
    for (size_t k = 0; k < (size_t)(cu + 1) * (size_t)(cv + 1); k++) gid[k] = -1;
#define GID(i, j) gid[(size_t)(j) * (cu + 1) + (i)]
    ilist tris = {0};
    int nfull = 0;
    for (int j = 0; j < cv; j++)
        for (int i = 0; i < cu; i++) {
            if (!FULL(i, j)) continue;
            nfull++;
            int c[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
            int id[4];
            for (int k = 0; k < 4; k++) {
                int *g = &GID(c[k][0], c[k][1]);
                if (*g < 0) *g = add_pt(&P, gu[c[k][0]], gv[c[k][1]]);
                id[k] = *g;
            }
            ipush(&tris, id[0]), ipush(&tris, id[1]), ipush(&tris, id[2]);
            ipush(&tris, id[0]), ipush(&tris, id[2]), ipush(&tris, id[3]);
        }
    m->full_cells = nfull;

    /* 4. the strip: loops = trim loops + staircase loops */
    ilist idx = {0}, start = {0};
    ipush(&start, 0);
    if (!natural_only || nfull < cu * cv) {
        for (int l = 0; l < reg.count; l++) {
            /* loop vertices, plus points on edges longer than a cell so that boundary triangles
             * stay cell-sized (a domain-rectangle edge would otherwise be one chord) */
            const prw_trim_polygon *pl = &reg.loops[l];
            for (int k = 0; k < pl->n; k++) {
                const double *a = pl->uv + 2 * k, *b = pl->uv + 2 * ((k + 1) % pl->n);
                ipush(&idx, add_pt(&P, a[0], a[1]));
                double steps = fmax(fabs(b[0] - a[0]) / du, fabs(b[1] - a[1]) / dv);
                int ns = steps > 1 ? (int)fmin(ceil(steps), 4096) : 1;
                for (int q = 1; q < ns; q++)
                    ipush(&idx, add_pt(&P, a[0] + (b[0] - a[0]) * q / ns, a[1] + (b[1] - a[1]) * q / ns));
            }
            ipush(&start, idx.n);
        }
        /* staircase: directed edges with the full cell on the left; out[v] = next vertex */
        int *out = prw_malloc(sizeof(int) * (size_t)(cu + 1) * (size_t)(cv + 1));
        for (size_t k = 0; k < (size_t)(cu + 1) * (size_t)(cv + 1); k++) out[k] = -1;
#define VI(i, j) ((int)((j) * (cu + 1) + (i)))
        for (int j = 0; j < cv; j++)
            for (int i = 0; i < cu; i++) {
                if (!FULL(i, j)) continue;
                if (!FULL(i, j - 1)) out[VI(i, j)] = VI(i + 1, j);
                if (!FULL(i + 1, j)) out[VI(i + 1, j)] = VI(i + 1, j + 1);
                if (!FULL(i, j + 1)) out[VI(i + 1, j + 1)] = VI(i, j + 1);
                if (!FULL(i - 1, j)) out[VI(i, j + 1)] = VI(i, j);
            }
        for (int v = 0; v < (cu + 1) * (cv + 1); v++) {
            if (out[v] < 0) continue;
            int w = v;
            while (out[w] >= 0) {
                int nx = out[w];
                out[w] = -1;
                int gi = w % (cu + 1), gj = w / (cu + 1);
                int *g = &GID(gi, gj);
                if (*g < 0) *g = add_pt(&P, gu[gi], gv[gj]);
                ipush(&idx, *g);
                w = nx;
            }
            ipush(&start, idx.n);
        }
        free(out);
        int *st = NULL, nst = 0;
        prw_earclip_stats es;
        if (!prw_earclip(P.xy, idx.v, start.v, start.n - 1, &st, &nst, &es, e)) {
            free(gu), free(gv), free(full), free(gid), free(P.xy), free(tris.v), free(idx.v), free(start.v);
            prw_trim_region_free(&reg);
            return prw_fail_wrap(e, "trimmed surface %d", t->source);
        }
        m->forced_ears = es.forced;
        for (int k = 0; k < 3 * nst; k++) ipush(&tris, st[k]);
        free(st);
    }
    free(idx.v);
    free(start.v);
    free(full);
    free(gid);
    free(gu);
    free(gv);

    /* area check in (u, v): the triangles must cover the region exactly once */
    double area = 0;
    for (int k = 0; k < tris.n; k += 3) {
        const double *a = P.xy + 2 * tris.v[k], *b = P.xy + 2 * tris.v[k + 1], *c = P.xy + 2 * tris.v[k + 2];
        area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    m->uv_area = area;
    m->region_area = natural_only ? (u1 - u0) * (v1 - v0) : prw_trim_region_area(&reg);
    prw_trim_region_free(&reg);
    if (!(fabs(area - m->region_area) <= 1e-9 * (u1 - u0) * (v1 - v0))) {
        free(P.xy);
        free(tris.v);
        return prw_fail(e,
                        "trimmed surface %d: trim loops cross or overlap (triangulated area %.17g, region area %.17g)",
                        t->source, area, m->region_area);
    }

    /* 5. positions, normals; drop triangles that are degenerate in 3-D */
    m->nverts = (size_t)P.n;
    m->pos = prw_malloc(sizeof(double) * 3 * m->nverts + 1);
    m->nrm = prw_malloc(sizeof(double) * 3 * m->nverts + 1);
    m->uv = P.xy ? P.xy : prw_malloc(1);
    for (int i = 0; i < P.n; i++) {
        prw_dvec3 p = prw_nurbs_surface_eval(s, P.xy[2 * i], P.xy[2 * i + 1]);
        prw_normal_kind kind;
        prw_dvec3 n = prw_nurbs_surface_normal(s, P.xy[2 * i], P.xy[2 * i + 1], &kind);
        m->normal_limit += kind == PRW_NORMAL_LIMIT;
        m->normal_nearby += kind == PRW_NORMAL_NEARBY;
        m->normal_undefined += kind == PRW_NORMAL_UNDEFINED;
        if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) {
            free(tris.v);
            prw_tess_mesh_free(m);
            return prw_fail(e, "trimmed surface %d: non-finite surface point", t->source);
        }
        memcpy(m->pos + 3 * i, &p, sizeof p);
        memcpy(m->nrm + 3 * i, &n, sizeof n);
    }
    m->tris = prw_malloc(sizeof(uint32_t) * (size_t)tris.n + 1);
    size_t nt = 0;
    for (int k = 0; k < tris.n; k += 3) {
        const double *a = m->pos + 3 * tris.v[k], *b = m->pos + 3 * tris.v[k + 1], *c = m->pos + 3 * tris.v[k + 2];
        prw_dvec3 ab = prw_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        prw_dvec3 ac = prw_v3(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
        prw_dvec3 bc = prw_v3(c[0] - b[0], c[1] - b[1], c[2] - b[2]);
        double l2 = fmax(prw_v3_dot(ab, ab), fmax(prw_v3_dot(ac, ac), prw_v3_dot(bc, bc)));
        double cr = prw_v3_len(prw_v3_cross(ab, ac));
        if (!(cr > 1e-14 * l2)) {
            m->dropped_degenerate++;
            continue;
        }
        for (int q = 0; q < 3; q++) m->tris[3 * nt + q] = (uint32_t)tris.v[k + q];
        nt++;
    }
    m->ntris = nt;
    free(tris.v);
    if (nt == 0) {
        prw_tess_mesh_free(m);
        return prw_fail(e, "trimmed surface %d: zero-area patch (every triangle is degenerate)", t->source);
    }
    return true;
}
