/* Segment ladders: nested subsets of the sewing points chosen by their Hausdorff error to the
 * exact curve (see prw_lod.h). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "prw_lod.h"

static double seg_dist(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ap = prw_v3_sub(p, a);
    double l2 = prw_v3_dot(ab, ab), t = l2 > 0 ? prw_v3_dot(ap, ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return prw_v3_len(prw_v3_sub(p, prw_v3_add(a, prw_v3_scale(ab, t))));
}

/* Error of the chord (i, j): every sewing point and dense sample strictly between. */
static double chord_error(const prw_seam_segment *s, int i, int j)
{
    double e = 0;
    for (int k = i; k < j; k++) {
        if (k > i) e = fmax(e, seg_dist(s->pts[k], s->pts[i], s->pts[j]));
        for (int d = 0; d < PRW_SEAM_DENSE; d++) e = fmax(e, seg_dist(s->dense[k * PRW_SEAM_DENSE + d], s->pts[i], s->pts[j]));
    }
    return e;
}

void prw_lod_ladders(const prw_seam_graph *g, int levels, double tau0, int **ladder)
{
    for (int si = 0; si < g->nsegs; si++) {
        const prw_seam_segment *s = &g->segs[si];
        int n = s->npts;
        int *keep = ladder[si];
        int *prev = prw_malloc(sizeof(int) * (size_t)n), *next = prw_malloc(sizeof(int) * (size_t)n);
        for (int i = 0; i < n; i++) {
            keep[i] = (i == 0 || i == n - 1) ? INT32_MAX : levels - 1;
            prev[i] = i - 1;
            next[i] = i + 1;
        }
        int interior = n - 2;
        for (int k = 1; k < levels && !s->degenerate; k++) {
            double thr = 0.5 * tau0 * ldexp(1.0, k);
            for (;;) {
                if (interior <= s->min_interior) break;
                int best = -1;
                double be = INFINITY;
                for (int i = next[0]; i < n - 1; i = next[i]) {
                    double er = chord_error(s, prev[i], next[i]);
                    if (er < be) {
                        be = er;
                        best = i;
                    }
                }
                if (best < 0 || be > thr) break;
                keep[best] = k - 1;
                next[prev[best]] = next[best];
                prev[next[best]] = prev[best];
                interior--;
            }
        }
        free(prev);
        free(next);
    }
}
