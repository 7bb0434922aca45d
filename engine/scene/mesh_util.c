/* mesh_util.c — per-vertex tangent frames from uvs.
 *
 * Convention (glTF): tangent.xyz = direction of increasing u; bitangent = cross(normal, tangent.xyz)
 * * w points towards DECREASING v (uv (0,0) is the top-left of the image, so that is "up" in the
 * texture, the +Y of a glTF normal map).  A standard, unmirrored mapping therefore gets w = +1. */
#include "scene_internal.h"

#include <stdlib.h>
#include <string.h>

/* Deterministic unit vector orthogonal to unit n (used where uvs give no direction). */
static prw_dvec3 fallback_tangent(prw_dvec3 n)
{
    prw_dvec3 a = fabs(n.x) < 0.9 ? prw_v3(1, 0, 0) : prw_v3(0, 1, 0);
    return prw_v3_norm(prw_v3_sub(a, prw_v3_scale(n, prw_v3_dot(a, n))));
}

void prw_mesh_generate_tangents(prw_mesh *m)
{
    size_t nv = m->vertex_count;
    if (!m->tangents) m->tangents = prw_malloc((nv ? nv : 1) * 4 * sizeof(float));
    /* per vertex: accumulated T (dP/du) and B (-dP/dv), each triangle weighted by its area */
    double *acc = prw_calloc((nv ? nv : 1) * 6, sizeof *acc);
    if (m->positions && m->uvs && m->indices) {
        for (uint32_t t = 0; t + 2 < m->index_count; t += 3) {
            uint32_t i[3] = {m->indices[t], m->indices[t + 1], m->indices[t + 2]};
            if (i[0] >= nv || i[1] >= nv || i[2] >= nv) continue;
            prw_dvec3 p[3];
            double u[3], v[3];
            for (int k = 0; k < 3; k++) {
                const float *q = m->positions + 3 * (size_t)i[k];
                p[k] = prw_v3(q[0], q[1], q[2]);
                u[k] = m->uvs[2 * (size_t)i[k]];
                v[k] = m->uvs[2 * (size_t)i[k] + 1];
            }
            prw_dvec3 e1 = prw_v3_sub(p[1], p[0]), e2 = prw_v3_sub(p[2], p[0]);
            double du1 = u[1] - u[0], dv1 = v[1] - v[0], du2 = u[2] - u[0], dv2 = v[2] - v[0];
            double det = du1 * dv2 - du2 * dv1;
            double area = 0.5 * prw_v3_len(prw_v3_cross(e1, e2));
            double uvscale = fmax(fmax(fabs(du1), fabs(dv1)), fmax(fabs(du2), fabs(dv2)));
            if (!(fabs(det) > 1e-12 * uvscale * uvscale) || !(area > 0) || !isfinite(det)) continue;
            prw_dvec3 T = prw_v3_scale(prw_v3_sub(prw_v3_scale(e1, dv2), prw_v3_scale(e2, dv1)), 1.0 / det);
            prw_dvec3 B = prw_v3_scale(prw_v3_sub(prw_v3_scale(e2, du1), prw_v3_scale(e1, du2)), -1.0 / det);
            /* unit directions weighted by area: a tiny uv island must not dominate */
            T = prw_v3_scale(prw_v3_norm(T), area);
            B = prw_v3_scale(prw_v3_norm(B), area);
            if (!isfinite(T.x + T.y + T.z + B.x + B.y + B.z)) continue;
            for (int k = 0; k < 3; k++) {
                double *a = acc + 6 * (size_t)i[k];
                a[0] += T.x;
                a[1] += T.y;
                a[2] += T.z;
                a[3] += B.x;
                a[4] += B.y;
                a[5] += B.z;
            }
        }
    }
    for (size_t vi = 0; vi < nv; vi++) {
        prw_dvec3 n = prw_v3(0, 0, 1);
        if (m->normals) n = prw_v3(m->normals[3 * vi], m->normals[3 * vi + 1], m->normals[3 * vi + 2]);
        if (!(prw_v3_len(n) > 0) || !isfinite(prw_v3_len(n))) n = prw_v3(0, 0, 1);
        n = prw_v3_norm(n);
        const double *a = acc + 6 * vi;
        prw_dvec3 T = prw_v3(a[0], a[1], a[2]), B = prw_v3(a[3], a[4], a[5]);
        prw_dvec3 t = prw_v3_sub(T, prw_v3_scale(n, prw_v3_dot(n, T))); /* Gram-Schmidt */
        double w = 1.0;
        if (prw_v3_len(t) > 1e-9 * (prw_v3_len(T) + 1e-300) && prw_v3_len(T) > 0) {
            t = prw_v3_norm(t);
            w = prw_v3_dot(prw_v3_cross(n, t), B) < 0 ? -1.0 : 1.0;
        } else {
            t = fallback_tangent(n);
        }
        float *o = m->tangents + 4 * vi;
        o[0] = (float)t.x;
        o[1] = (float)t.y;
        o[2] = (float)t.z;
        o[3] = (float)w;
    }
    free(acc);
}
