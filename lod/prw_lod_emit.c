/* Extraction of a patch at a level with its segments at their display levels: boundary edges that
 * miss displayed sewing points become centroid fans (see prw_lod.h). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "prw_lod_internal.h"

void prw_lod_segment_levels(const prw_lod_model *lm, const int *patch_level, int *seg_level)
{
    const prw_seam_graph *g = lm->g;
    for (int s = 0; s < g->nsegs; s++) {
        int l = INT32_MAX;
        for (int side = 0; side < 2; side++) {
            int p = g->segs[s].patch[side];
            if (p >= 0 && lm->patches[p].ok && patch_level[p] < l) l = patch_level[p];
        }
        seg_level[s] = l == INT32_MAX ? 0 : l;
    }
}

int prw_lod_patch_triangles(const prw_lod_model *lm, int patch, int level)
{
    const prw_lod_patch *p = &lm->patches[patch];
    return p->ok ? p->tri_start[level + 1] - p->tri_start[level] : 0;
}

static uint32_t add_vertex(prw_lod_mesh *o, prw_dvec3 x)
{
    if (o->nverts == o->vcap) {
        o->vcap = o->vcap ? 2 * o->vcap : 1024;
        o->pos = prw_realloc(o->pos, sizeof(double) * 3 * o->vcap);
    }
    o->pos[3 * o->nverts] = x.x;
    o->pos[3 * o->nverts + 1] = x.y;
    o->pos[3 * o->nverts + 2] = x.z;
    return (uint32_t)o->nverts++;
}

static void add_tri(prw_lod_mesh *o, uint32_t a, uint32_t b, uint32_t c)
{
    if (o->ntris == o->tcap) {
        o->tcap = o->tcap ? 2 * o->tcap : 1024;
        o->tris = prw_realloc(o->tris, sizeof(uint32_t) * 3 * o->tcap);
    }
    o->tris[3 * o->ntris] = a;
    o->tris[3 * o->ntris + 1] = b;
    o->tris[3 * o->ntris + 2] = c;
    o->ntris++;
}

static uint32_t vid(const prw_lod_patch *p, prw_lod_mesh *o, int v)
{
    if (o->map[v] < 0) o->map[v] = (int)add_vertex(o, p->pos[v]);
    return (uint32_t)o->map[v];
}

static bool dup(const prw_lod_patch *p, int a, int b) { return p->gid[a] >= 0 && p->gid[a] == p->gid[b]; }

void prw_lod_emit(const prw_lod_model *lm, int patch, int level, const int *seg_level, prw_lod_mesh *o)
{
    const prw_lod_patch *p = &lm->patches[patch];
    if (!p->ok) return;
    if (o->mapcap < p->nverts) {
        o->mapcap = p->nverts;
        o->map = prw_realloc(o->map, sizeof(int) * (size_t)o->mapcap);
    }
    for (int v = 0; v < p->nverts; v++) o->map[v] = -1;
    lod_ivec span = {0}, seq = {0};
    for (int t = p->tri_start[level]; t < p->tri_start[level + 1]; t++) {
        const int *tr = p->tris + 3 * t;
        if (dup(p, tr[0], tr[1]) || dup(p, tr[1], tr[2]) || dup(p, tr[2], tr[0])) continue;
        seq.n = 0;
        int extra = 0;
        for (int k = 0; k < 3; k++) {
            int x = tr[k], y = tr[(k + 1) % 3];
            lod_ipush(&seq, x);
            if (!lod_span(p, x, y, NULL, level, &span)) continue;
            for (int i = 0; i < span.n; i++) {
                int q = span.v[i], s = p->ring_seg[q];
                if (lm->seg_keep[s][p->ring_sidx[q]] >= seg_level[s]) {
                    lod_ipush(&seq, q);
                    extra++;
                }
            }
        }
        if (!extra) {
            add_tri(o, vid(p, o, tr[0]), vid(p, o, tr[1]), vid(p, o, tr[2]));
            continue;
        }
        o->fans++;
        double cuv[2];
        prw_dvec3 cx;
        lod_centroid(p, tr[0], tr[1], tr[2], cuv, &cx);
        uint32_t c = add_vertex(o, cx);
        for (int i = 0; i < seq.n; i++) {
            int a = seq.v[i], b = seq.v[(i + 1) % seq.n];
            if (dup(p, a, b)) continue;
            add_tri(o, c, vid(p, o, a), vid(p, o, b));
        }
    }
    free(span.v);
    free(seq.v);
}

void prw_lod_mesh_reset(prw_lod_mesh *o)
{
    o->nverts = 0;
    o->ntris = 0;
    o->fans = 0;
}

void prw_lod_mesh_free(prw_lod_mesh *o)
{
    free(o->pos);
    free(o->tris);
    free(o->map);
    memset(o, 0, sizeof *o);
}
