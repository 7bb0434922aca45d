/* Grid + boundary-strip triangulation with fixed boundary points (see prw_tess_fixed.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_earclip.h"
#include "prw_tess_fixed.h"
#include "prw_trim.h"

typedef struct ivec {
    int *v;
    int n, cap;
} ivec;

static void ip(ivec *l, int x)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->v = prw_realloc(l->v, sizeof(int) * (size_t)l->cap);
    }
    l->v[l->n++] = x;
}

static int cmp_dbl(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }

static void cells_for(const prw_nurbs_surface *s, double chord, int mx, double u0, double u1, double v0, double v1, int *cu,
                      int *cv)
{
    int ns = 16;
    double muu = 0, mvv = 0;
    for (int a = 0; a <= ns; a++)
        for (int b = 0; b <= ns; b++) {
            prw_dvec3 d[9];
            prw_nurbs_surface_derivs(s, u0 + (u1 - u0) * a / ns, v0 + (v1 - v0) * b / ns, 2, d);
            double x = prw_v3_len(d[6]), y = prw_v3_len(d[2]);
            if (isfinite(x)) muu = fmax(muu, x);
            if (isfinite(y)) mvv = fmax(mvv, y);
        }
    double nu = muu > 0 ? (u1 - u0) / sqrt(8 * chord / muu) : 1, nv = mvv > 0 ? (v1 - v0) / sqrt(8 * chord / mvv) : 1;
    *cu = clampi((int)fmin(ceil(nu), 1e6), 2, mx);
    *cv = clampi((int)fmin(ceil(nv), 1e6), 2, mx);
}

void prw_tess_fixed_free(prw_tess_fixed_mesh *m)
{
    free(m->uv);
    free(m->tris);
    memset(m, 0, sizeof *m);
}

bool prw_tess_fixed(const prw_nurbs_surface *s, const double *buv, const int *start, int nloops, double chord,
                    int max_cells, double cell_scale, prw_tess_fixed_mesh *m, prw_error *e)
{
    memset(m, 0, sizeof *m);
    if (nloops < 1) return prw_fail(e, "fixed tessellation: no boundary loop");
    int nb = start[nloops];
    for (int l = 0; l < nloops; l++)
        if (start[l + 1] - start[l] < 3) return prw_fail(e, "fixed tessellation: loop %d has %d points", l, start[l + 1] - start[l]);
    /* the region as prw_trim polygons (for the inside test and the area) */
    prw_trim_region reg;
    memset(&reg, 0, sizeof reg);
    reg.loops = prw_malloc(sizeof(prw_trim_polygon) * (size_t)nloops);
    reg.count = nloops;
    double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (int l = 0; l < nloops; l++) {
        reg.loops[l].uv = (double *)(buv + 2 * start[l]);
        reg.loops[l].n = start[l + 1] - start[l];
    }
    for (int i = 0; i < nb; i++) {
        u0 = fmin(u0, buv[2 * i]), u1 = fmax(u1, buv[2 * i]);
        v0 = fmin(v0, buv[2 * i + 1]), v1 = fmax(v1, buv[2 * i + 1]);
    }
    double region_area = prw_trim_region_area(&reg);
    if (!(u1 > u0) || !(v1 > v0) || !(region_area > 0)) {
        free(reg.loops);
        return prw_fail(e, "fixed tessellation: boundary has no area");
    }
    int cu, cv, mx = max_cells > 0 ? max_cells : 64;
    cells_for(s, chord, mx, u0, u1, v0, v1, &cu, &cv);
    /* cells no larger than the boundary spacing (median edge along each direction), so that the
     * strip between the boundary and the full cells stays narrow */
    {
        double *hu = prw_malloc(sizeof(double) * (size_t)nb + 1), *hv = prw_malloc(sizeof(double) * (size_t)nb + 1);
        int nu = 0, nv = 0;
        for (int l = 0; l < nloops; l++)
            for (int i = start[l]; i < start[l + 1]; i++) {
                int j = i + 1 == start[l + 1] ? start[l] : i + 1;
                double du = fabs(buv[2 * j] - buv[2 * i]), dv = fabs(buv[2 * j + 1] - buv[2 * i + 1]);
                if (du > dv) hu[nu++] = du;
                else if (dv > 0) hv[nv++] = dv;
            }
        qsort(hu, (size_t)nu, sizeof(double), cmp_dbl);
        qsort(hv, (size_t)nv, sizeof(double), cmp_dbl);
        if (nu && hu[nu / 2] > 0) cu = clampi((int)fmin(ceil((u1 - u0) / hu[nu / 2]), 1e6), cu, mx);
        if (nv && hv[nv / 2] > 0) cv = clampi((int)fmin(ceil((v1 - v0) / hv[nv / 2]), 1e6), cv, mx);
        free(hu);
        free(hv);
        if (cell_scale > 0 && cell_scale != 1) {
            cu = clampi((int)ceil(cu * cell_scale), 2, mx);
            cv = clampi((int)ceil(cv * cell_scale), 2, mx);
        }
    }
    m->cells_u = cu, m->cells_v = cv;
    double du = (u1 - u0) / cu, dv = (v1 - v0) / cv;
    double *gu = prw_malloc(sizeof(double) * (size_t)(cu + 1)), *gv = prw_malloc(sizeof(double) * (size_t)(cv + 1));
    for (int i = 0; i <= cu; i++) gu[i] = i == cu ? u1 : u0 + du * i;
    for (int j = 0; j <= cv; j++) gv[j] = j == cv ? v1 : v0 + dv * j;
    size_t nc = (size_t)cu * (size_t)cv;
    unsigned char *full = prw_calloc(nc, 1);
    for (int l = 0; l < nloops; l++) {
        const prw_trim_polygon *pl = &reg.loops[l];
        for (int i = 0, k = pl->n - 1; i < pl->n; k = i++) {
            const double *a = pl->uv + 2 * k, *b = pl->uv + 2 * i;
            int ia = clampi((int)floor((fmin(a[0], b[0]) - 0.25 * du - u0) / du), 0, cu - 1);
            int ib = clampi((int)floor((fmax(a[0], b[0]) + 0.25 * du - u0) / du), 0, cu - 1);
            int ja = clampi((int)floor((fmin(a[1], b[1]) - 0.25 * dv - v0) / dv), 0, cv - 1);
            int jb = clampi((int)floor((fmax(a[1], b[1]) + 0.25 * dv - v0) / dv), 0, cv - 1);
            for (int jj = ja; jj <= jb; jj++)
                for (int ii = ia; ii <= ib; ii++) full[(size_t)jj * cu + ii] = 2; /* touched */
        }
    }
    for (int j = 0; j < cv; j++)
        for (int i = 0; i < cu; i++) {
            unsigned char *f = &full[(size_t)j * cu + i];
            *f = *f != 2 && prw_trim_classify(&reg, 0.5 * (gu[i] + gu[i + 1]), 0.5 * (gv[j] + gv[j + 1])) == PRW_TRIM_INSIDE;
        }
#define FULL(i, j) ((i) >= 0 && (j) >= 0 && (i) < cu && (j) < cv && full[(size_t)(j) * cu + (i)])
    for (bool changed = true; changed;) {
        changed = false;
        for (int j = 0; j + 1 < cv; j++)
            for (int i = 0; i + 1 < cu; i++) {
                bool a = FULL(i, j), b = FULL(i + 1, j), c = FULL(i, j + 1), d = FULL(i + 1, j + 1);
                if (a && d && !b && !c) full[(size_t)j * cu + i] = 0, changed = true;
                else if (b && c && !a && !d) full[(size_t)j * cu + i + 1] = 0, changed = true;
            }
    }
    /* points: boundary first, then grid vertices on demand */
    int pcap = nb + 64, np = nb;
    double *P = prw_malloc(sizeof(double) * 2 * (size_t)pcap);
    memcpy(P, buv, sizeof(double) * 2 * (size_t)nb);
    size_t ng = (size_t)(cu + 1) * (size_t)(cv + 1);
    int *gid = prw_malloc(sizeof(int) * ng);
    for (size_t k = 0; k < ng; k++) gid[k] = -1;
#define GID(i, j) gid[(size_t)(j) * (cu + 1) + (i)]
#define GRIDPT(gi, gj)                                                                   \
    do {                                                                                 \
        int *g_ = &GID(gi, gj);                                                          \
        if (*g_ < 0) {                                                                   \
            if (np == pcap) {                                                            \
                pcap *= 2;                                                               \
                P = prw_realloc(P, sizeof(double) * 2 * (size_t)pcap);                   \
            }                                                                            \
            P[2 * np] = gu[gi], P[2 * np + 1] = gv[gj];                                  \
            *g_ = np++;                                                                  \
        }                                                                                \
    } while (0)
    ivec tris = {0};
    int nfull = 0;
    for (int j = 0; j < cv; j++)
        for (int i = 0; i < cu; i++) {
            if (!FULL(i, j)) continue;
            nfull++;
            int c[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}}, id[4];
            for (int k = 0; k < 4; k++) {
                GRIDPT(c[k][0], c[k][1]);
                id[k] = GID(c[k][0], c[k][1]);
            }
            ip(&tris, id[0]), ip(&tris, id[1]), ip(&tris, id[2]);
            ip(&tris, id[0]), ip(&tris, id[2]), ip(&tris, id[3]);
        }
    m->full_cells = nfull;
    ivec idx = {0}, st = {0};
    ip(&st, 0);
    for (int i = 0; i < nb; i++) {
        ip(&idx, i);
        for (int l = 0; l < nloops; l++)
            if (start[l + 1] == i + 1) ip(&st, idx.n);
    }
    int *out = prw_malloc(sizeof(int) * ng);
    for (size_t k = 0; k < ng; k++) out[k] = -1;
#define VI(i, j) ((int)((j) * (cu + 1) + (i)))
    for (int j = 0; j < cv; j++)
        for (int i = 0; i < cu; i++) {
            if (!FULL(i, j)) continue;
            if (!FULL(i, j - 1)) out[VI(i, j)] = VI(i + 1, j);
            if (!FULL(i + 1, j)) out[VI(i + 1, j)] = VI(i + 1, j + 1);
            if (!FULL(i, j + 1)) out[VI(i + 1, j + 1)] = VI(i, j + 1);
            if (!FULL(i - 1, j)) out[VI(i, j + 1)] = VI(i, j);
        }
    for (int v = 0; v < (int)ng; v++) {
        if (out[v] < 0) continue;
        for (int w = v; out[w] >= 0;) {
            int nx = out[w];
            out[w] = -1;
            int gi = w % (cu + 1), gj = w / (cu + 1);
            GRIDPT(gi, gj);
            ip(&idx, GID(gi, gj));
            w = nx;
        }
        ip(&st, idx.n);
    }
    free(out);
    free(full);
    free(gid);
    free(gu);
    free(gv);
    int *et = NULL, net = 0;
    prw_earclip_stats es;
    bool ok = prw_earclip(P, idx.v, st.v, st.n - 1, &et, &net, &es, e);
    free(idx.v);
    free(st.v);
    if (ok) {
        m->forced_ears = es.forced;
        for (int k = 0; k < 3 * net; k++) ip(&tris, et[k]);
        free(et);
        double area = 0;
        unsigned char *used = prw_calloc((size_t)nb + 1, 1);
        for (int k = 0; k < tris.n; k += 3) {
            const double *a = P + 2 * tris.v[k], *b = P + 2 * tris.v[k + 1], *c = P + 2 * tris.v[k + 2];
            area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
            for (int q = 0; q < 3; q++)
                if (tris.v[k + q] < nb) used[tris.v[k + q]] = 1;
        }
        int unused = 0;
        for (int i = 0; i < nb; i++) unused += !used[i];
        free(used);
        if (unused) ok = prw_fail(e, "fixed tessellation: %d boundary points unused (duplicates)", unused);
        else if (!(fabs(area - region_area) <= 1e-9 * (u1 - u0) * (v1 - v0)))
            ok = prw_fail(e, "fixed tessellation: loops cross or overlap (area %.17g vs %.17g)", area, region_area);
    }
    free(reg.loops);
    if (!ok) {
        free(P);
        free(tris.v);
        return false;
    }
    m->uv = P;
    m->nverts = np;
    m->tris = tris.v ? tris.v : prw_malloc(1);
    m->ntris = tris.n / 3;
    return true;
}
