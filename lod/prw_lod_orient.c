/* prw_lod_orient — see prw_lod_orient.h (moved here from engine/render/lod_gpu.c, same rule). */
#include "prw_lod_orient.h"

#include <stdlib.h>
#include <string.h>

void prw_lod_orient(const prw_lod_model *lm, const prw_nurbs_model *m, unsigned char *flip, int *conflicts)
{
    const prw_seam_graph *sg = lm->g;
    int np = lm->npatches, nsegs = sg->nsegs, nconf = 0;
    memset(flip, 0, (size_t)np);
    if (conflicts) *conflicts = 0;
    if (np <= 0) return;
    prw_dvec3 lo, hi;
    if (!prw_nurbs_model_bounds(m, &lo, &hi)) lo = hi = prw_v3(0, 0, 0);
    prw_dvec3 centre = prw_v3_scale(prw_v3_add(lo, hi), 0.5);
    /* segments of each patch (from its boundary ring, first occurrence order) */
    int *pseg_start = prw_calloc((size_t)np + 1, sizeof(int));
    int total = 0;
    for (int p = 0; p < np; p++) total += lm->patches[p].ok ? lm->patches[p].nbound : 0;
    int *pseg = prw_malloc(sizeof(int) * (size_t)(total + 1));
    int k = 0;
    for (int p = 0; p < np; p++) {
        pseg_start[p] = k;
        const prw_lod_patch *lp = &lm->patches[p];
        for (int v = 0; lp->ok && v < lp->nbound; v++) {
            int s = lp->ring_seg[v];
            bool seen = false;
            for (int j = pseg_start[p]; j < k && !seen; j++) seen = pseg[j] == s;
            if (!seen && s >= 0 && s < nsegs) pseg[k++] = s;
        }
    }
    pseg_start[np] = k;
    /* the signed volume of each patch's finest emission (every segment at level 0) */
    double *volume = prw_calloc((size_t)np + 1, sizeof(double));
    int *segtmp = prw_calloc((size_t)nsegs + 1, sizeof(int));
    prw_lod_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    for (int p = 0; p < np; p++) {
        if (!lm->patches[p].ok) continue;
        prw_lod_mesh_reset(&mesh);
        prw_lod_emit(lm, p, 0, segtmp, &mesh);
        for (size_t t = 0; t < mesh.ntris; t++) {
            const double *P = mesh.pos;
            const uint32_t *tr = mesh.tris + 3 * t;
            prw_dvec3 a = prw_v3_sub(prw_v3(P[3 * tr[0]], P[3 * tr[0] + 1], P[3 * tr[0] + 2]), centre);
            prw_dvec3 b = prw_v3_sub(prw_v3(P[3 * tr[1]], P[3 * tr[1] + 1], P[3 * tr[1] + 2]), centre);
            prw_dvec3 c = prw_v3_sub(prw_v3(P[3 * tr[2]], P[3 * tr[2] + 1], P[3 * tr[2] + 2]), centre);
            volume[p] += prw_v3_dot(a, prw_v3_cross(b, c)) / 6.0;
        }
    }
    prw_lod_mesh_free(&mesh);
    free(segtmp);
    int *comp = prw_malloc(sizeof(int) * ((size_t)np + 1)), *queue = prw_malloc(sizeof(int) * ((size_t)np + 1));
    /* adjacency from segments: per segment a relation (same = +1, opposite = -1, none = 0) */
    signed char *rel = prw_calloc((size_t)nsegs + 1, 1);
    for (int si = 0; si < nsegs; si++) {
        const prw_seam_segment *sgm = &sg->segs[si];
        int a = sgm->patch[0], b = sgm->patch[1];
        if (a < 0 || b < 0 || a == b || a >= np || b >= np || sgm->npts < 2 || sgm->degenerate) continue;
        if (!sgm->uv[0] || !sgm->uv[1]) continue;
        int i0 = (sgm->npts - 1) / 2, i1 = sgm->npts / 2;
        prw_dvec3 n[2];
        for (int side = 0; side < 2; side++) {
            const double *uv = sgm->uv[side];
            double u = 0.5 * (uv[2 * i0] + uv[2 * i1]), v = 0.5 * (uv[2 * i0 + 1] + uv[2 * i1 + 1]);
            prw_normal_kind kind;
            n[side] = prw_nurbs_surface_normal(&m->surfaces[sgm->patch[side]].surface, u, v, &kind);
        }
        double c = prw_v3_dot(n[0], n[1]);
        rel[si] = c > 0.3 ? 1 : c < -0.3 ? -1 : 0;
    }
    for (int p = 0; p < np; p++) comp[p] = -1;
    int ncomp = 0;
    for (int start = 0; start < np; start++) {
        if (comp[start] >= 0) continue;
        int head = 0, tail = 0, members = 0, flipped = 0;
        bool closed = true;
        double vol = 0;
        comp[start] = ncomp;
        queue[tail++] = start;
        while (head < tail) {
            int p = queue[head++];
            members++;
            flipped += flip[p];
            vol += flip[p] ? -volume[p] : volume[p];
            for (int j = pseg_start[p]; j < pseg_start[p + 1]; j++) {
                const prw_seam_segment *sgm = &sg->segs[pseg[j]];
                int q = sgm->patch[0] == p ? sgm->patch[1] : sgm->patch[0];
                if (q < 0 || q >= np) {
                    closed = closed && sgm->degenerate;
                    continue;
                }
                if (!rel[pseg[j]] || q == p) continue;
                unsigned char want = (unsigned char)(flip[p] ^ (rel[pseg[j]] < 0));
                if (comp[q] < 0) {
                    comp[q] = ncomp;
                    flip[q] = want;
                    queue[tail++] = q;
                } else if (flip[q] != want) {
                    nconf++;
                }
            }
        }
        bool invert = closed ? vol < 0 : 2 * flipped > members;
        if (invert)
            for (int j = 0; j < tail; j++) flip[queue[j]] ^= 1;
        ncomp++;
    }
    if (conflicts) *conflicts = nconf;
    free(rel);
    free(comp);
    free(queue);
    free(volume);
    free(pseg);
    free(pseg_start);
}
