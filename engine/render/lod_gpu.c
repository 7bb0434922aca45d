/* lod_gpu — one LOD hierarchy on the GPU: per-instance buffers with per-patch slots, per-frame
 * selection, minimal slot updates and merged draws (prw_lod_render.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_orient.h"
#include "prw_lod_proxy.h"
#include "prw_lod_render.h"

#define VF 12 /* floats per vertex: position 3, normal 3, uv 2, tangent 4 (the base pipeline's layout) */
#define FLOOR_MARGIN 1  /* a new layout's floor: one level below the finest level selected */
#define SHRINK_LEVELS 3 /* re-layout to a coarser floor once every level is more than this above it */

struct prw_lod_gpu {
    prw_gpu *gpu;
    const prw_lod_model *lm;
    const prw_nurbs_model *m;
    prw_lod_gpu_options o;
    prw_lod_cull cull;
    bool have_cull;
    prw_dvec3 centre;
    uint32_t ninst;
    int np, nsegs, nlevels;
    /* slot capacity of patch p under level floor L ([p * nlevels + L]): the largest emission at any
     * level >= L with every segment at L (segments are drawn at the finer of two levels >= L, and
     * emission only grows with finer segments) */
    uint32_t *capv, *capi;
    unsigned char *cap_done; /* per L: computed (lazily, at the first layout with that floor) */
    int *pseg_start, *pseg; /* segments of each patch */
    /* per instance */
    int *lfloor; /* the layout's level floor (-1: no layout yet) */
    prw_buffer *vbuf, *ibuf;
    uint64_t *relayouts;
    /* per instance x patch / segment */
    uint32_t *vslot, *islot, *icap;
    int *plev, *seg_levels;
    unsigned char *drawn, *uploaded;
    uint32_t *nverts, *nidx;
    uint64_t *hash;
    prw_lod_range *ranges_drawn, *ranges_all;
    uint32_t *nr_drawn, *nr_all;
    /* scratch */
    prw_lod_mesh mesh;
    float *vtmp;
    uint32_t *itmp;
    double *uvtmp;
    int *segtmp;
    size_t tmpcap_v, tmpcap_i;
    unsigned char *flip; /* per patch: emit with reversed winding and normals (consistent orientation) */
    int orient_conflicts;
    /* whole-model proxy levels (prw_lod_proxy.h), one shared buffer pair: per corner vertices */
    prw_lod_proxy proxy;     /* built at create when no prebuilt one was given */
    const prw_lod_proxy *px; /* the levels used: &proxy or the borrowed o.proxy; NULL: none */
    bool have_proxy, own_proxy;
    prw_buffer pvbuf, pibuf;
    uint32_t *pfirst;        /* per proxy level: first index */
    int *use_proxy;          /* per instance: proxy level drawn, or -1 (the patches) */
    prw_lod_range *prange;   /* per instance: the proxy level's range */
    prw_dvec3 mlo, mhi;      /* box of every usable patch (control hulls and sewing points) */
};

static int clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }

static void ensure_tmp(prw_lod_gpu *g, size_t nv, size_t ni)
{
    if (nv > g->tmpcap_v) {
        g->tmpcap_v = nv * 2;
        g->vtmp = prw_realloc(g->vtmp, g->tmpcap_v * VF * sizeof(float));
        g->uvtmp = prw_realloc(g->uvtmp, g->tmpcap_v * 3 * sizeof(double));
    }
    if (ni > g->tmpcap_i) {
        g->tmpcap_i = ni * 2;
        g->itmp = prw_realloc(g->itmp, g->tmpcap_i * sizeof(uint32_t));
    }
}

/* Exact normal and tangent at (u, v) of surface p; (0, 0, 0) normal when undefined. */
static void surface_frame(const prw_nurbs_surface *s, double u, double v, prw_dvec3 *n, prw_dvec3 *t)
{
    prw_normal_kind kind;
    *n = prw_nurbs_surface_normal(s, u, v, &kind);
    prw_dvec3 d[4];
    prw_nurbs_surface_derivs(s, u, v, 1, d);
    prw_dvec3 su = d[2]; /* skl[k*(nd+1)+l]: k = 1, l = 0 */
    su = prw_v3_sub(su, prw_v3_scale(*n, prw_v3_dot(su, *n)));
    double l = prw_v3_len(su);
    if (!(l > 1e-300) || !isfinite(l)) {
        /* any unit vector orthogonal to n */
        prw_dvec3 a = fabs(n->x) < 0.9 ? prw_v3(1, 0, 0) : prw_v3(0, 1, 0);
        su = prw_v3_cross(*n, a);
        l = prw_v3_len(su);
        if (!(l > 1e-300)) su = prw_v3(1, 0, 0), l = 1;
    }
    *t = prw_v3_scale(su, 1.0 / l);
}

bool prw_lod_gpu_emit(prw_lod_gpu *g, int p, int level, const int *seg_level, const float **verts, uint32_t *nverts,
                      const uint32_t **idx, uint32_t *nidx, prw_error *e)
{
    const prw_lod_model *lm = g->lm;
    if (p < 0 || p >= g->np) return prw_fail(e, "lod: no patch %d (of %d)", p, g->np);
    const prw_lod_patch *lp = &lm->patches[p];
    prw_lod_mesh *o = &g->mesh;
    prw_lod_mesh_reset(o);
    level = clampi(level, 0, lm->levels - 1);
    prw_lod_emit(lm, p, level, seg_level, o);
    size_t nv = o->nverts, nt = o->ntris;
    ensure_tmp(g, nv + 1, 3 * nt + 1);
    /* (u, v) of every emitted vertex: patch vertices through the emitter's map (local -> emitted);
     * fan centres (not mapped; first vertex of each of their fan triangles) get the mean (u, v) of
     * their fan's rim */
    double *uvw = g->uvtmp; /* u, v, weight (-1: a patch vertex) */
    for (size_t i = 0; i < nv; i++) uvw[3 * i] = uvw[3 * i + 1] = uvw[3 * i + 2] = 0;
    if (lp->ok && o->map && o->mapcap >= lp->nverts)
        for (int v = 0; v < lp->nverts; v++) {
            int k = o->map[v];
            if (k < 0 || (size_t)k >= nv) continue;
            uvw[3 * k] = lp->uv[2 * v];
            uvw[3 * k + 1] = lp->uv[2 * v + 1];
            uvw[3 * k + 2] = -1;
        }
    for (size_t t = 0; t < nt; t++) {
        uint32_t c = o->tris[3 * t];
        if (uvw[3 * c + 2] < 0) continue;
        for (int k = 1; k < 3; k++) {
            uint32_t a = o->tris[3 * t + k];
            if (uvw[3 * a + 2] >= 0) continue; /* rim vertices are patch vertices */
            uvw[3 * c] += uvw[3 * a];
            uvw[3 * c + 1] += uvw[3 * a + 1];
            uvw[3 * c + 2] += 1;
        }
    }
    const prw_nurbs_surface *surf = &g->m->surfaces[p].surface;
    float *vd = g->vtmp;
    for (size_t i = 0; i < nv; i++) {
        double u = uvw[3 * i], v = uvw[3 * i + 1], w = uvw[3 * i + 2];
        if (w > 0) u /= w, v /= w;
        else if (w == 0) { /* a fan centre left without triangles (not drawn): any parameter */
            double u0, u1, v0, v1;
            prw_nurbs_surface_domain(&g->m->surfaces[p].surface, &u0, &u1, &v0, &v1);
            u = 0.5 * (u0 + u1), v = 0.5 * (v0 + v1);
        }
        prw_dvec3 n, t;
        surface_frame(surf, u, v, &n, &t);
        /* a reversed patch: its winding below and its normal here, so the two agree */
        if (g->flip && g->flip[p]) n = prw_v3_scale(n, -1);
        float *d = vd + i * VF;
        d[0] = (float)(o->pos[3 * i] - g->centre.x);
        d[1] = (float)(o->pos[3 * i + 1] - g->centre.y);
        d[2] = (float)(o->pos[3 * i + 2] - g->centre.z);
        d[3] = (float)n.x, d[4] = (float)n.y, d[5] = (float)n.z;
        d[6] = (float)u, d[7] = (float)v;
        d[8] = (float)t.x, d[9] = (float)t.y, d[10] = (float)t.z, d[11] = g->flip && g->flip[p] ? -1.0f : 1.0f;
        uvw[3 * i + 2] = n.x == 0 && n.y == 0 && n.z == 0; /* 1: undefined exact normal */
    }
    /* undefined exact normals (zero-area patch): the area-weighted face normal instead */
    for (size_t t = 0; t < nt; t++) {
        const uint32_t *tr = o->tris + 3 * t;
        if (uvw[3 * tr[0] + 2] == 0 && uvw[3 * tr[1] + 2] == 0 && uvw[3 * tr[2] + 2] == 0) continue;
        prw_dvec3 a = prw_v3(o->pos[3 * tr[0]], o->pos[3 * tr[0] + 1], o->pos[3 * tr[0] + 2]);
        prw_dvec3 b = prw_v3(o->pos[3 * tr[1]], o->pos[3 * tr[1] + 1], o->pos[3 * tr[1] + 2]);
        prw_dvec3 c = prw_v3(o->pos[3 * tr[2]], o->pos[3 * tr[2] + 1], o->pos[3 * tr[2] + 2]);
        prw_dvec3 f = prw_v3_cross(prw_v3_sub(b, a), prw_v3_sub(c, a));
        if (g->flip && g->flip[p]) f = prw_v3_scale(f, -1);
        for (int k = 0; k < 3; k++) {
            if (uvw[3 * tr[k] + 2] == 0) continue;
            float *d = vd + tr[k] * VF;
            d[3] += (float)f.x, d[4] += (float)f.y, d[5] += (float)f.z;
        }
    }
    for (size_t i = 0; i < nv; i++) {
        float *d = vd + i * VF;
        float l = sqrtf(d[3] * d[3] + d[4] * d[4] + d[5] * d[5]);
        if (!(l > 0) || !isfinite(l)) d[3] = 0, d[4] = 0, d[5] = 1, l = 1;
        d[3] /= l, d[4] /= l, d[5] /= l;
    }
    memcpy(g->itmp, o->tris, 3 * nt * sizeof(uint32_t));
    if (g->flip && g->flip[p])
        for (size_t t = 0; t < nt; t++) {
            g->itmp[3 * t + 1] = o->tris[3 * t + 2];
            g->itmp[3 * t + 2] = o->tris[3 * t + 1];
        }
    *verts = vd;
    *nverts = (uint32_t)nv;
    *idx = g->itmp;
    *nidx = (uint32_t)(3 * nt);
    return true;
}

/* The proxy levels as one vertex buffer of per-corner vertices (the slot vertex format; normal and
 * tangent from the exact surface at the corner's (patch, u, v), as prw_lod_gpu_emit writes them) and
 * one index buffer 0, 1, 2, ... so a level is one indexed range. */
static bool upload_proxy(prw_lod_gpu *g, prw_error *e)
{
    const prw_lod_proxy *px = g->px;
    size_t corners = 0;
    for (int l = 0; l < px->nlevels; l++) corners += 3 * (size_t)px->levels[l].ntris;
    if (!corners || corners > UINT32_MAX / 4) return true;
    if (!prw_buffer_create(g->gpu, corners * VF * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, PRW_MEM_UPLOAD,
                           &g->pvbuf, e) ||
        !prw_buffer_create(g->gpu, corners * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, PRW_MEM_UPLOAD,
                           &g->pibuf, e))
        return false;
    if (!g->pvbuf.mapped || !g->pibuf.mapped) return prw_fail(e, "lod: upload buffers are not host-mapped");
    float *vd = g->pvbuf.mapped;
    uint32_t *id = g->pibuf.mapped;
    g->pfirst = prw_calloc((size_t)px->nlevels + 1, sizeof(uint32_t));
    size_t c = 0;
    for (int l = 0; l < px->nlevels; l++) {
        const prw_lod_proxy_level *pl = &px->levels[l];
        g->pfirst[l] = (uint32_t)c;
        for (int t = 0; t < pl->ntris; t++) {
            /* the triangle's own orientation is already consistent (the builder applied the flips) */
            for (int k = 0; k < 3; k++, c++) {
                int patch = pl->corner_patch[3 * t + k];
                if (patch < 0 || patch >= g->np) patch = pl->tri_patch[t] >= 0 && pl->tri_patch[t] < g->np ? pl->tri_patch[t] : 0;
                double u = pl->corner_uv[6 * t + 2 * k], v = pl->corner_uv[6 * t + 2 * k + 1];
                const double *x = pl->pos + 3 * (size_t)pl->tris[3 * t + k];
                prw_dvec3 n, tg;
                surface_frame(&g->m->surfaces[patch].surface, u, v, &n, &tg);
                if (g->flip && g->flip[patch]) n = prw_v3_scale(n, -1); /* as the triangle's winding */
                if (n.x == 0 && n.y == 0 && n.z == 0) { /* undefined exact normal: the face's */
                    const double *a = pl->pos + 3 * (size_t)pl->tris[3 * t], *b = pl->pos + 3 * (size_t)pl->tris[3 * t + 1],
                                 *cc = pl->pos + 3 * (size_t)pl->tris[3 * t + 2];
                    n = prw_v3_cross(prw_v3(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                                     prw_v3(cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]));
                    double ln = prw_v3_len(n);
                    n = ln > 0 && isfinite(ln) ? prw_v3_scale(n, 1.0 / ln) : prw_v3(0, 0, 1);
                }
                float *d = vd + c * VF;
                d[0] = (float)(x[0] - g->centre.x);
                d[1] = (float)(x[1] - g->centre.y);
                d[2] = (float)(x[2] - g->centre.z);
                d[3] = (float)n.x, d[4] = (float)n.y, d[5] = (float)n.z;
                d[6] = (float)u, d[7] = (float)v;
                d[8] = (float)tg.x, d[9] = (float)tg.y, d[10] = (float)tg.z;
                d[11] = g->flip && g->flip[patch] ? -1.0f : 1.0f;
                id[c] = (uint32_t)c;
            }
        }
    }
    return true;
}

bool prw_lod_gpu_create(prw_gpu *gpu, const prw_lod_model *lm, const prw_nurbs_model *m, uint32_t instances,
                        const prw_lod_gpu_options *o, prw_lod_gpu **out, prw_error *e)
{
    *out = NULL;
    if ((size_t)lm->npatches != m->count)
        return prw_fail(e, "lod: hierarchy has %d patches, the model %zu surfaces", lm->npatches, m->count);
    if (instances == 0 || instances > 100000) return prw_fail(e, "lod: %u instances (1 .. 100000)", instances);
    prw_lod_gpu *g = prw_calloc(1, sizeof *g);
    g->gpu = gpu;
    g->lm = lm;
    g->m = m;
    if (o) g->o = *o;
    g->ninst = instances;
    g->np = lm->npatches;
    g->nsegs = lm->g->nsegs;
    g->nlevels = lm->levels;
    prw_dvec3 lo, hi;
    if (!prw_nurbs_model_bounds(m, &lo, &hi)) lo = hi = prw_v3(0, 0, 0);
    g->centre = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    int np = g->np, nl = g->nlevels;
    /* segments of each patch (from its boundary ring) */
    g->pseg_start = prw_calloc((size_t)np + 1, sizeof(int));
    int total = 0;
    for (int p = 0; p < np; p++) total += lm->patches[p].ok ? lm->patches[p].nbound : 0;
    g->pseg = prw_malloc(sizeof(int) * (size_t)(total + 1));
    int k = 0;
    for (int p = 0; p < np; p++) {
        g->pseg_start[p] = k;
        const prw_lod_patch *lp = &lm->patches[p];
        for (int v = 0; lp->ok && v < lp->nbound; v++) {
            int s = lp->ring_seg[v];
            bool seen = false;
            for (int j = g->pseg_start[p]; j < k && !seen; j++) seen = g->pseg[j] == s;
            if (!seen && s >= 0 && s < g->nsegs) g->pseg[k++] = s;
        }
    }
    g->pseg_start[np] = k;
    /* capacities come later, per floor */
    g->segtmp = prw_calloc((size_t)g->nsegs + 1, sizeof(int));
    g->capv = prw_calloc((size_t)np * (size_t)nl, sizeof(uint32_t));
    g->capi = prw_calloc((size_t)np * (size_t)nl, sizeof(uint32_t));
    g->cap_done = prw_calloc((size_t)nl, 1);
    g->flip = prw_calloc((size_t)np + 1, 1);
    prw_lod_orient(lm, m, g->flip, &g->orient_conflicts);
    size_t ni = (size_t)instances * (size_t)np, ns = (size_t)instances * (size_t)(g->nsegs + 1);
    g->lfloor = prw_malloc(sizeof(int) * instances);
    for (uint32_t i = 0; i < instances; i++) g->lfloor[i] = -1;
    g->vbuf = prw_calloc(instances, sizeof(prw_buffer));
    g->ibuf = prw_calloc(instances, sizeof(prw_buffer));
    g->relayouts = prw_calloc(instances, sizeof(uint64_t));
    g->vslot = prw_calloc(ni, sizeof(uint32_t));
    g->islot = prw_calloc(ni, sizeof(uint32_t));
    g->icap = prw_calloc(ni, sizeof(uint32_t));
    g->plev = prw_malloc(sizeof(int) * ni);
    for (size_t i = 0; i < ni; i++) g->plev[i] = nl - 1; /* coarsest until selected */
    g->seg_levels = prw_calloc(ns, sizeof(int));
    g->drawn = prw_calloc(ni, 1);
    g->uploaded = prw_calloc(ni, 1);
    g->nverts = prw_calloc(ni, sizeof(uint32_t));
    g->nidx = prw_calloc(ni, sizeof(uint32_t));
    g->hash = prw_calloc(ni, sizeof(uint64_t));
    g->ranges_drawn = prw_calloc(ni + 1, sizeof(prw_lod_range));
    g->ranges_all = prw_calloc(ni + 1, sizeof(prw_lod_range));
    g->nr_drawn = prw_calloc(instances, sizeof(uint32_t));
    g->nr_all = prw_calloc(instances, sizeof(uint32_t));
    prw_lod_cull_options co = {.single_sided = g->o.single_sided};
    bool ok = prw_lod_cull_build(m, &co, &g->cull, e);
    g->have_cull = ok;
    for (int p = 0; ok && p < np && p < g->cull.npatches; p++)
        if (g->flip[p]) g->cull.axis[p] = prw_v3_scale(g->cull.axis[p], -1); /* the drawn side */
    /* the model's box (distance of an instance for the proxy choice) */
    g->mlo = prw_v3(DBL_MAX, DBL_MAX, DBL_MAX), g->mhi = prw_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    for (int p = 0; p < np; p++) {
        if (!lm->patches[p].ok) continue;
        g->mlo = prw_v3(fmin(g->mlo.x, lm->patches[p].lo.x), fmin(g->mlo.y, lm->patches[p].lo.y), fmin(g->mlo.z, lm->patches[p].lo.z));
        g->mhi = prw_v3(fmax(g->mhi.x, lm->patches[p].hi.x), fmax(g->mhi.y, lm->patches[p].hi.y), fmax(g->mhi.z, lm->patches[p].hi.z));
    }
    g->use_proxy = prw_malloc(sizeof(int) * instances);
    for (uint32_t i = 0; i < instances; i++) g->use_proxy[i] = -1;
    g->prange = prw_calloc(instances, sizeof(prw_lod_range));
    if (ok && !g->o.no_proxy) {
        if (g->o.proxy) {
            g->px = g->o.proxy;
        } else {
            ok = prw_lod_proxy_build(lm, g->flip, NULL, &g->proxy, e);
            g->own_proxy = ok;
            if (ok) g->px = &g->proxy;
        }
        g->have_proxy = ok;
        ok = ok && upload_proxy(g, e);
    }
    g->o.proxy = NULL; /* borrowed only for create */
    if (!ok) {
        prw_lod_gpu_destroy(g);
        return false;
    }
    *out = g;
    return true;
}

void prw_lod_gpu_destroy(prw_lod_gpu *g)
{
    if (!g) return;
    for (uint32_t i = 0; g->vbuf && i < g->ninst; i++) {
        prw_buffer_destroy(g->gpu, &g->vbuf[i]);
        prw_buffer_destroy(g->gpu, &g->ibuf[i]);
    }
    if (g->have_cull) prw_lod_cull_free(&g->cull);
    if (g->own_proxy) prw_lod_proxy_free(&g->proxy);
    prw_buffer_destroy(g->gpu, &g->pvbuf);
    prw_buffer_destroy(g->gpu, &g->pibuf);
    free(g->pfirst);
    free(g->use_proxy);
    free(g->prange);
    prw_lod_mesh_free(&g->mesh);
    void *ptrs[] = {g->capv,  g->capi, g->cap_done,     g->pseg_start, g->pseg,         g->lfloor,     g->vbuf,     g->ibuf,
                    g->relayouts, g->vslot, g->islot,     g->icap,         g->plev,       g->seg_levels, g->drawn,
                    g->uploaded, g->nverts, g->nidx,      g->hash,         g->ranges_drawn, g->ranges_all,
                    g->nr_drawn, g->nr_all, g->vtmp,      g->itmp,         g->uvtmp,      g->segtmp,   g->flip};
    for (size_t i = 0; i < sizeof ptrs / sizeof ptrs[0]; i++) free(ptrs[i]);
    free(g);
}

/* A new layout for instance inst with level floor L: slots sized by capv/capi[., L], fresh buffers,
 * every slot's index range filled with degenerate triangles (its first vertex), vertices zeroed.
 * Every slot is then written by the caller (all hashes are reset). */
static void compute_capacities(prw_lod_gpu *g, int L)
{
    const prw_lod_model *lm = g->lm;
    int np = g->np, nl = g->nlevels;
    int *seg = prw_malloc(sizeof(int) * (size_t)(g->nsegs + 1));
    for (int si = 0; si < g->nsegs; si++) seg[si] = L;
    for (int p = 0; p < np; p++) {
        size_t mv = 0, mt = 0;
        for (int l = L; lm->patches[p].ok && l < nl; l++) {
            prw_lod_mesh_reset(&g->mesh);
            prw_lod_emit(lm, p, l, seg, &g->mesh);
            if (g->mesh.nverts > mv) mv = g->mesh.nverts;
            if (g->mesh.ntris > mt) mt = g->mesh.ntris;
        }
        g->capv[(size_t)p * nl + L] = (uint32_t)mv;
        g->capi[(size_t)p * nl + L] = (uint32_t)(3 * mt);
    }
    free(seg);
    g->cap_done[L] = 1;
}

static bool relayout(prw_lod_gpu *g, uint32_t inst, int L, prw_error *e)
{
    int np = g->np, nl = g->nlevels;
    if (!g->cap_done[L]) compute_capacities(g, L);
    size_t base = (size_t)inst * np;
    uint64_t tv = 0, ti = 0;
    for (int p = 0; p < np; p++) {
        g->vslot[base + p] = (uint32_t)tv;
        g->islot[base + p] = (uint32_t)ti;
        g->icap[base + p] = g->capi[(size_t)p * nl + L];
        tv += g->capv[(size_t)p * nl + L];
        ti += g->capi[(size_t)p * nl + L];
        g->nverts[base + p] = g->nidx[base + p] = 0;
        g->hash[base + p] = 0;
    }
    if (tv > INT32_MAX || ti > UINT32_MAX / 4) return prw_fail(e, "lod: %llu vertices do not fit one buffer", (unsigned long long)tv);
    prw_gpu_wait_idle(g->gpu, e); /* the old buffers may still be referenced by a finished frame's command buffer */
    prw_buffer_destroy(g->gpu, &g->vbuf[inst]);
    prw_buffer_destroy(g->gpu, &g->ibuf[inst]);
    if (!prw_buffer_create(g->gpu, (tv ? tv : 1) * VF * sizeof(float), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, PRW_MEM_UPLOAD,
                           &g->vbuf[inst], e) ||
        !prw_buffer_create(g->gpu, (ti ? ti : 3) * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, PRW_MEM_UPLOAD,
                           &g->ibuf[inst], e))
        return false;
    if (!g->vbuf[inst].mapped || !g->ibuf[inst].mapped) return prw_fail(e, "lod: upload buffers are not host-mapped");
    memset(g->vbuf[inst].mapped, 0, (tv ? tv : 1) * VF * sizeof(float));
    uint32_t *im = g->ibuf[inst].mapped;
    memset(im, 0, (ti ? ti : 3) * sizeof(uint32_t));
    for (int p = 0; p < np; p++)
        for (uint32_t j = 0; j < g->icap[base + p]; j++) im[g->islot[base + p] + j] = g->vslot[base + p];
    g->lfloor[inst] = L;
    g->relayouts[inst]++;
    return true;
}
void prw_lod_gpu_set_options(prw_lod_gpu *g, const prw_lod_gpu_options *o)
{
    bool ss = g->o.single_sided;
    g->o = *o;
    g->o.single_sided = o->single_sided;
    if (g->have_cull && ss != o->single_sided)
        for (int p = 0; p < g->cull.npatches; p++) g->cull.single_sided[p] = o->single_sided;
}

prw_dmat4 prw_lod_gpu_draw_matrix(const prw_lod_gpu *g, prw_dmat4 world)
{
    prw_dmat4 t = prw_dm4_identity();
    t.m[12] = g->centre.x;
    t.m[13] = g->centre.y;
    t.m[14] = g->centre.z;
    return prw_dm4_mul(world, t);
}

void prw_lod_gpu_model_view(const prw_lod_gpu *g, prw_dmat4 world, const prw_view *views, uint32_t count,
                            prw_lod_view *lv)
{
    memset(lv, 0, sizeof *lv);
    prw_dmat4 inv;
    if (!prw_dm4_inverse(world, &inv)) inv = prw_dm4_identity();
    /* axis lengths of the instance matrix (TRS without shear: the scales) */
    double smin = DBL_MAX, smax = 0;
    for (int c = 0; c < 3; c++) {
        double l = sqrt(world.m[4 * c] * world.m[4 * c] + world.m[4 * c + 1] * world.m[4 * c + 1] +
                        world.m[4 * c + 2] * world.m[4 * c + 2]);
        smin = fmin(smin, l);
        smax = fmax(smax, l);
    }
    double scale_ratio = smax > 0 ? smin / smax : 1;
    lv->neyes = count >= 2 ? 2 : 1;
    lv->tol_px = g->o.tol_px > 0 ? g->o.tol_px : 0.5;
    lv->floor_frac = g->o.floor_frac > 0 ? g->o.floor_frac : 0.1;
    lv->tri_budget = g->o.tri_budget;
    lv->cull = g->o.no_cull || !g->have_cull ? NULL : &g->cull;
    lv->frustum_cull = lv->cull != NULL && count <= 2;
    double pa = DBL_MAX;
    for (uint32_t i = 0; i < count; i++) {
        const prw_view *v = &views[i];
        /* angle of one pixel at the image corner farthest from the axis: d(atan t) = dt / (1 + t^2) */
        double dtx = (v->tan_right - v->tan_left) / v->width, dty = (v->tan_top - v->tan_bottom) / v->height;
        double tx = fmax(fabs(v->tan_left), fabs(v->tan_right)), ty = fmax(fabs(v->tan_bottom), fabs(v->tan_top));
        double t2 = g->o.centre_pixel ? 0.0 : tx * tx + ty * ty;
        pa = fmin(pa, fmin(dtx, dty) / (1.0 + t2));
    }
    lv->pixel_angle = (count ? pa : 1e-3) * scale_ratio;
    for (uint32_t i = 0; i < count && i < 2; i++) {
        const prw_view *v = &views[i];
        lv->eye[i] = prw_dm4_point(inv, v->eye);
        if (!lv->frustum_cull) continue;
        const double *m = v->view.m; /* world -> eye; rows of the rotation: right, up, back */
        prw_dvec3 up = prw_v3(m[1], m[5], m[9]), back = prw_v3(m[2], m[6], m[10]);
        prw_lod_plane wp[6];
        prw_lod_frustum_planes(v->eye, prw_v3_scale(back, -1), up, -v->tan_left, v->tan_right, -v->tan_bottom,
                               v->tan_top, v->znear, 0, wp);
        for (int k = 0; k < 6; k++) {
            /* n.(M y + t) + d >= 0  <=>  (M^T n).y + (n.t + d) >= 0, renormalised */
            const double *w = world.m;
            prw_dvec3 n = prw_v3(w[0] * wp[k].n.x + w[1] * wp[k].n.y + w[2] * wp[k].n.z,
                                 w[4] * wp[k].n.x + w[5] * wp[k].n.y + w[6] * wp[k].n.z,
                                 w[8] * wp[k].n.x + w[9] * wp[k].n.y + w[10] * wp[k].n.z);
            double d = wp[k].d + wp[k].n.x * w[12] + wp[k].n.y * w[13] + wp[k].n.z * w[14];
            double l = prw_v3_len(n);
            if (!(l > 0)) n = prw_v3(0, 0, 0), d = 1, l = 1;
            lv->frustum[i][k].n = prw_v3_scale(n, 1.0 / l);
            lv->frustum[i][k].d = d / l;
        }
    }
}

bool prw_lod_gpu_update(prw_lod_gpu *g, uint32_t inst, prw_dmat4 world, const prw_view *views, uint32_t count,
                        prw_lod_frame_report *rep, prw_error *e)
{
    if (inst >= g->ninst) return prw_fail(e, "lod: no instance %u (of %u)", inst, g->ninst);
    const prw_lod_model *lm = g->lm;
    int np = g->np, ns = g->nsegs, nl = g->nlevels;
    size_t base = (size_t)inst * np;
    int *lev = g->plev + base, *oldseg = g->seg_levels + (size_t)inst * (ns + 1);
    unsigned char *drawn = g->drawn + base, *up = g->uploaded + base;
    double t0 = prw_now();
    int *newlev = prw_malloc(sizeof(int) * (size_t)(np + 1));
    memcpy(newlev, lev, sizeof(int) * (size_t)np);
    prw_lod_select_report sr;
    prw_lod_view lv; /* model-space view set (not when forced) */
    memset(&sr, 0, sizeof sr);
    if (g->o.force) {
        for (int p = 0; p < np; p++) {
            newlev[p] = clampi(g->o.force_level, 0, nl - 1);
            drawn[p] = lm->patches[p].ok;
        }
    } else {
        prw_lod_gpu_model_view(g, world, views, count, &lv);
        prw_lod_select_drawn(lm, &lv, newlev, drawn, &sr);
        /* Where the finest level binds (even level 0's bound exceeds the acceptable error) the
         * selection takes level 0, but a patch whose bound is set by its boundary (e.g. a trim chord)
         * can have the same bound at much coarser levels: take the coarsest level whose bound is no
         * larger than the chosen one's — the same error for fewer triangles (any level mix stays
         * crack-free: segments follow prw_lod_segment_levels). */
        for (int p = 0; p < np; p++) {
            const prw_lod_patch *lp = &lm->patches[p];
            if (!lp->ok || newlev[p] < 0 || newlev[p] >= nl) continue;
            while (newlev[p] + 1 < nl && lp->err[newlev[p] + 1] <= lp->err[newlev[p]]) newlev[p]++;
        }
    }
    /* A whole-model proxy level instead of the patches (prw_lod_proxy.h): the coarsest-in-triangles
     * level whose bound projects within the tolerance from the nearer eye at the model box's nearest
     * point, when it has fewer triangles than the patches selected; the patch slots are then left as
     * they are (their levels and segments too), so going back to the patches uploads only what
     * changed since. */
    g->use_proxy[inst] = -1;
    if (!g->o.force && !g->o.no_proxy && g->have_proxy && g->px->nlevels > 0) {
        double d = DBL_MAX; /* lv: the selection's model-space view set */
        for (int k = 0; k < lv.neyes; k++) {
            prw_dvec3 x = lv.eye[k];
            double dx = fmax(0, fmax(g->mlo.x - x.x, x.x - g->mhi.x)), dy = fmax(0, fmax(g->mlo.y - x.y, x.y - g->mhi.y)),
                   dz = fmax(0, fmax(g->mlo.z - x.z, x.z - g->mhi.z));
            d = fmin(d, sqrt(dx * dx + dy * dy + dz * dz));
        }
        double eps = lv.tol_px * lv.pixel_angle * d;
        int best = -1;
        bool any_drawn = false;
        for (int p = 0; p < np && !any_drawn; p++) any_drawn = drawn[p] != 0;
        for (int l = 0; l < g->px->nlevels && any_drawn; l++) {
            const prw_lod_proxy_level *pl = &g->px->levels[l];
            if (pl->err <= eps && (uint64_t)pl->ntris < sr.triangles &&
                (best < 0 || pl->ntris < g->px->levels[best].ntris))
                best = l;
        }
        if (best >= 0) {
            const prw_lod_proxy_level *pl = &g->px->levels[best];
            g->use_proxy[inst] = best;
            g->prange[inst] = (prw_lod_range){g->pfirst[best], 3 * (uint32_t)pl->ntris, (uint32_t)pl->ntris, 0};
            free(newlev);
            memset(up, 0, (size_t)np);
            if (rep) {
                double t2 = prw_now();
                rep->instances++;
                rep->proxy_instances++;
                rep->triangles += (uint64_t)pl->ntris;
                rep->draws++;
                rep->select_ms += 1e3 * (t2 - t0);
                double px = d > 0 ? pl->err / (lv.pixel_angle * d) : 0;
                if (px > rep->max_px) rep->max_px = px;
            }
            return true;
        }
    }
    double t1 = prw_now();
    int *seg = g->segtmp;
    prw_lod_segment_levels(lm, newlev, seg);
    /* the layout's floor must not exceed any level (culled patches' stale levels included) */
    int lmin = nl - 1;
    for (int p = 0; p < np; p++)
        if (lm->patches[p].ok && newlev[p] < lmin) lmin = newlev[p];
    bool first = g->lfloor[inst] < 0 || lmin < g->lfloor[inst] || lmin > g->lfloor[inst] + SHRINK_LEVELS;
    bool ok = true;
    if (first && !relayout(g, inst, lmin > FLOOR_MARGIN ? lmin - FLOOR_MARGIN : 0, e)) ok = false;
    float *vmap = ok ? (float *)g->vbuf[inst].mapped : NULL;
    uint32_t *imap = ok ? (uint32_t *)g->ibuf[inst].mapped : NULL;
    uint64_t nup = 0, bytes = 0;
    for (int p = 0; p < np && ok; p++) {
        up[p] = 0;
        size_t slot = base + p;
        bool cand = first || newlev[p] != lev[p];
        for (int j = g->pseg_start[p]; j < g->pseg_start[p + 1] && !cand; j++)
            cand = seg[g->pseg[j]] != oldseg[g->pseg[j]];
        if (!cand || !lm->patches[p].ok) continue;
        const float *vd;
        const uint32_t *id;
        uint32_t nv, nidx;
        if (!prw_lod_gpu_emit(g, p, newlev[p], seg, &vd, &nv, &id, &nidx, e)) {
            ok = false;
            break;
        }
        if (nv > g->capv[(size_t)p * nl + g->lfloor[inst]] || nidx > g->icap[slot]) {
            ok = prw_fail(e, "lod: patch %d at level %d emits %u vertices / %u indices, slot holds %u / %u", p,
                          newlev[p], nv, nidx, g->capv[(size_t)p * nl + g->lfloor[inst]], g->icap[slot]);
            break;
        }
        uint64_t h = prw_hash64(vd, (size_t)nv * VF * sizeof(float), 0x6c6f64736c6f74ull);
        h = prw_hash64(id, (size_t)nidx * sizeof(uint32_t), h);
        h = prw_hash64(&nv, sizeof nv, h);
        if (!first && h == g->hash[slot] && nv == g->nverts[slot] && nidx == g->nidx[slot]) continue;
        uint32_t vs = g->vslot[slot], is = g->islot[slot];
        memcpy(vmap + (size_t)vs * VF, vd, (size_t)nv * VF * sizeof(float));
        for (uint32_t j = 0; j < nidx; j++) imap[is + j] = vs + id[j]; /* indices relative to the instance */
        /* the part the previous emission used beyond the new one becomes degenerate again */
        for (uint32_t j = nidx; j < g->nidx[slot]; j++) imap[is + j] = vs;
        uint32_t cleared = g->nidx[slot] > nidx ? g->nidx[slot] - nidx : 0;
        g->hash[slot] = h;
        g->nverts[slot] = nv;
        g->nidx[slot] = nidx;
        up[p] = 1;
        nup++;
        bytes += (uint64_t)nv * VF * sizeof(float) + (uint64_t)(nidx + cleared) * sizeof(uint32_t);
    }
    if (ok) {
        memcpy(lev, newlev, sizeof(int) * (size_t)np);
        memcpy(oldseg, seg, sizeof(int) * (size_t)ns);
    } else {
        g->lfloor[inst] = -1; /* slots may be partly written: a new layout next time */
    }
    free(newlev);
    /* draw ranges: runs of consecutive drawn patches (the unused ends of their slots hold degenerate
     * triangles, so a run is one draw); for shadows one run over every patch */
    uint32_t nd = 0, na = 0;
    uint64_t tris = 0, ndrawn = 0;
    prw_lod_range *rd = g->ranges_drawn + base, *ra = g->ranges_all + base;
    prw_lod_range cur = {0}, all = {0};
    bool open = false, open_all = false;
    for (int p = 0; ok && p < np; p++) {
        size_t slot = base + p;
        if (g->nidx[slot]) {
            if (!open_all) all = (prw_lod_range){g->islot[slot], 0, 0, 0}, open_all = true;
            all.index_count = g->islot[slot] + g->nidx[slot] - all.first_index;
            all.triangles += g->nidx[slot] / 3;
        }
        if (drawn[p] && g->nidx[slot]) {
            if (!open) cur = (prw_lod_range){g->islot[slot], 0, 0, 0}, open = true;
            cur.index_count = g->islot[slot] + g->nidx[slot] - cur.first_index;
            cur.triangles += g->nidx[slot] / 3;
            tris += g->nidx[slot] / 3;
            ndrawn++;
        } else if (!drawn[p] && open) {
            rd[nd++] = cur;
            open = false;
        }
    }
    if (open) rd[nd++] = cur;
    if (open_all) ra[na++] = all;
    g->nr_drawn[inst] = nd;
    g->nr_all[inst] = na;
    double t2 = prw_now();
    if (rep) {
        rep->instances++;
        rep->drawn_patches += ndrawn;
        int okp = 0;
        for (int p = 0; p < np; p++) okp += lm->patches[p].ok;
        rep->culled_patches += (uint64_t)(okp - (int)ndrawn);
        rep->triangles += tris;
        rep->reuploaded += nup;
        rep->bytes += bytes;
        rep->relayouts += first;
        rep->draws += nd;
        rep->select_ms += 1e3 * (t1 - t0);
        rep->update_ms += 1e3 * (t2 - t1);
        rep->floor_binds += sr.floor_binds;
        rep->finest_binds += sr.finest_binds;
        rep->budget_binds += sr.budget_binds;
        if (sr.max_px > rep->max_px) rep->max_px = sr.max_px;
    }
    return ok;
}

VkBuffer prw_lod_gpu_vertex_buffer(const prw_lod_gpu *g, uint32_t inst)
{
    return g->use_proxy[inst] >= 0 ? g->pvbuf.buffer : g->vbuf[inst].buffer;
}
VkBuffer prw_lod_gpu_index_buffer(const prw_lod_gpu *g, uint32_t inst)
{
    return g->use_proxy[inst] >= 0 ? g->pibuf.buffer : g->ibuf[inst].buffer;
}
int prw_lod_gpu_proxy_level(const prw_lod_gpu *g, uint32_t inst) { return inst < g->ninst ? g->use_proxy[inst] : -1; }
const prw_lod_proxy *prw_lod_gpu_proxy(const prw_lod_gpu *g) { return g->have_proxy ? g->px : NULL; }

const prw_lod_range *prw_lod_gpu_ranges(const prw_lod_gpu *g, uint32_t inst, bool all, uint32_t *count)
{
    if (inst < g->ninst && g->use_proxy[inst] >= 0) {
        *count = 1;
        return &g->prange[inst];
    }
    if (inst >= g->ninst || g->lfloor[inst] < 0) {
        *count = 0;
        return NULL;
    }
    *count = all ? g->nr_all[inst] : g->nr_drawn[inst];
    return (all ? g->ranges_all : g->ranges_drawn) + (size_t)inst * g->np;
}

const int *prw_lod_gpu_levels(const prw_lod_gpu *g, uint32_t inst) { return g->plev + (size_t)inst * g->np; }
const unsigned char *prw_lod_gpu_drawn(const prw_lod_gpu *g, uint32_t inst) { return g->drawn + (size_t)inst * g->np; }
const unsigned char *prw_lod_gpu_uploaded(const prw_lod_gpu *g, uint32_t inst)
{
    return g->uploaded + (size_t)inst * g->np;
}
uint64_t prw_lod_gpu_relayouts(const prw_lod_gpu *g, uint32_t inst) { return g->relayouts[inst]; }

void prw_lod_gpu_slot(const prw_lod_gpu *g, uint32_t inst, int p, const float **verts, uint32_t *nverts,
                      uint32_t **idx, uint32_t *nidx, uint32_t *vertex_base)
{
    size_t slot = (size_t)inst * g->np + p;
    *verts = NULL;
    *idx = NULL;
    *nverts = *nidx = *vertex_base = 0;
    if (g->lfloor[inst] < 0) return;
    *verts = (const float *)g->vbuf[inst].mapped + (size_t)g->vslot[slot] * VF;
    *idx = (uint32_t *)g->ibuf[inst].mapped + g->islot[slot];
    *nverts = g->nverts[slot];
    *nidx = g->nidx[slot];
    *vertex_base = g->vslot[slot];
}

size_t prw_lod_gpu_memory(const prw_lod_gpu *g)
{
    size_t n = (size_t)g->pvbuf.size + (size_t)g->pibuf.size;
    for (uint32_t i = 0; i < g->ninst; i++) n += (size_t)g->vbuf[i].size + (size_t)g->ibuf[i].size;
    return n;
}

int prw_lod_gpu_flipped(const prw_lod_gpu *g, int *conflicts)
{
    int n = 0;
    for (int p = 0; p < g->np; p++) n += g->flip[p];
    if (conflicts) *conflicts = g->orient_conflicts;
    return n;
}
