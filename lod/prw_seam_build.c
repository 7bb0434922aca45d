/* Seam-graph setup, part 2: nodes, piece matching, segments, sewing points, patch loops
 * (see prw_seam.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_seam_internal.h"

static double dist3(prw_dvec3 a, prw_dvec3 b) { return prw_v3_len(prw_v3_sub(a, b)); }

static double seg_dist(prw_dvec3 p, prw_dvec3 a, prw_dvec3 b)
{
    prw_dvec3 ab = prw_v3_sub(b, a), ap = prw_v3_sub(p, a);
    double l2 = prw_v3_dot(ab, ab), t = l2 > 0 ? prw_v3_dot(ap, ab) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return dist3(p, prw_v3_add(a, prw_v3_scale(ab, t)));
}

static double piece_length(const seam_ctx *cx, const seam_piece *p)
{
    const seam_curve *c = &cx->curves[p->curve];
    prw_dvec3 prev = seam_curve_eval(c, p->ta);
    double l = 0;
    for (int i = 0; i < c->n; i++) {
        if (c->t[i] <= p->ta || c->t[i] >= p->tb) continue;
        l += dist3(c->x[i], prev);
        prev = c->x[i];
    }
    return l + dist3(seam_curve_eval(c, p->tb), prev);
}

/* ---- nodes: piece ends clustered within tol (union-find over an x-sorted sweep) ---- */

static int uf_find(int *par, int i)
{
    while (par[i] != i) i = par[i] = par[par[i]];
    return i;
}

typedef struct endpt {
    prw_dvec3 p;
    int id;
} endpt;

static int cmp_endpt(const void *a, const void *b)
{
    double x = ((const endpt *)a)->p.x, y = ((const endpt *)b)->p.x;
    return (x > y) - (x < y);
}

static void build_nodes(seam_ctx *cx, prw_seam_graph *g)
{
    int n = 2 * cx->npieces;
    endpt *ep = prw_malloc(sizeof(endpt) * (size_t)n + 1);
    prw_dvec3 *pos = prw_malloc(sizeof(prw_dvec3) * (size_t)n + 1);
    int *par = prw_malloc(sizeof(int) * (size_t)n + 1);
    for (int i = 0; i < cx->npieces; i++) {
        const seam_curve *c = &cx->curves[cx->pieces[i].curve];
        pos[2 * i] = seam_curve_eval(c, cx->pieces[i].ta);
        pos[2 * i + 1] = seam_curve_eval(c, cx->pieces[i].tb);
    }
    for (int i = 0; i < n; i++) {
        ep[i].p = pos[i];
        ep[i].id = i;
        par[i] = i;
    }
    qsort(ep, (size_t)n, sizeof(endpt), cmp_endpt);
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n && ep[j].p.x - ep[i].p.x <= cx->tol; j++)
            if (dist3(ep[i].p, ep[j].p) <= cx->tol) {
                int a = uf_find(par, ep[i].id), b = uf_find(par, ep[j].id);
                if (a != b) par[a < b ? b : a] = a < b ? a : b; /* root = smallest id */
            }
    int *node_of_root = prw_malloc(sizeof(int) * (size_t)n + 1);
    for (int i = 0; i < n; i++) node_of_root[i] = -1;
    g->nodes = prw_malloc(sizeof(prw_dvec3) * (size_t)n + 1);
    g->nnodes = 0;
    for (int i = 0; i < n; i++) {
        int r = uf_find(par, i);
        if (node_of_root[r] < 0) {
            node_of_root[r] = g->nnodes;
            g->nodes[g->nnodes++] = pos[r];
        }
        cx->pieces[i / 2].node[i % 2] = node_of_root[r];
    }
    free(node_of_root);
    free(par);
    free(pos);
    free(ep);
}

/* ---- matching ---- */

static bool same_pair(const seam_piece *a, const seam_piece *b)
{
    return (a->node[0] == b->node[0] && a->node[1] == b->node[1]) || (a->node[0] == b->node[1] && a->node[1] == b->node[0]);
}

static void match_pieces(seam_ctx *cx)
{
    for (int i = 0; i < cx->npieces; i++) {
        seam_piece *p = &cx->pieces[i];
        if (p->degenerate || p->label < 0 || p->match >= 0) continue;
        const seam_curve *cp = &cx->curves[p->curve];
        prw_dvec3 mid = seam_curve_eval(cp, 0.5 * (p->ta + p->tb));
        for (int j = i + 1; j < cx->npieces; j++) {
            seam_piece *q = &cx->pieces[j];
            if (q->curve != p->label || q->label != p->curve || q->match >= 0 || q->degenerate || !same_pair(p, q)) continue;
            double t;
            if (seam_curve_project(&cx->curves[q->curve], mid, q->ta, q->tb, &t) > 2 * cx->tol) continue;
            p->match = j;
            q->match = i;
            break;
        }
    }
}

/* ---- sewing points on the owner piece ---- */

typedef struct tlist {
    double *t;
    int n, cap;
} tlist;

static void tpush(tlist *l, double t)
{
    if (l->n == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 32;
        l->t = prw_realloc(l->t, sizeof(double) * (size_t)l->cap);
    }
    l->t[l->n++] = t;
}

static void sample_piece(const seam_ctx *cx, const seam_curve *c, double ta, double tb, int min_interior, tlist *out)
{
    double st[64][2];
    int sp = 0;
    st[sp][0] = ta, st[sp][1] = tb, sp++;
    while (sp > 0) {
        sp--;
        double a = st[sp][0], b = st[sp][1];
        prw_dvec3 xa = seam_curve_eval(c, a), xb = seam_curve_eval(c, b);
        bool ok = dist3(xa, xb) <= cx->max_edge;
        for (int k = 1; k <= 3 && ok; k++) ok = seg_dist(seam_curve_eval(c, a + (b - a) * k / 4), xa, xb) <= cx->chord;
        if (!ok && sp < 62 && b - a > 1e-12 * (c->t1 - c->t0)) {
            double m = 0.5 * (a + b);
            st[sp][0] = m, st[sp][1] = b, sp++;
            st[sp][0] = a, st[sp][1] = m, sp++;
            continue;
        }
        tpush(out, a);
    }
    tpush(out, tb);
    /* enough interior points for the coarsest level: split the longest parameter intervals */
    while (out->n - 2 < min_interior + 1) {
        int best = 0;
        for (int i = 1; i + 1 < out->n; i++)
            if (out->t[i + 1] - out->t[i] > out->t[best + 1] - out->t[best]) best = i;
        tpush(out, 0);
        memmove(out->t + best + 2, out->t + best + 1, sizeof(double) * (size_t)(out->n - best - 2));
        out->t[best + 1] = 0.5 * (out->t[best] + out->t[best + 2]);
    }
}

static void add_use(prw_seam_loop *l, int seg, bool rev, int side)
{
    l->uses = prw_realloc(l->uses, sizeof(prw_seam_use) * (size_t)(l->count + 1));
    l->uses[l->count].seg = seg;
    l->uses[l->count].reversed = rev;
    l->uses[l->count].side = side;
    l->count++;
}

static void make_segment(seam_ctx *cx, prw_seam_graph *g, int pi, int min_interior)
{
    seam_piece *p = &cx->pieces[pi];
    prw_seam_segment *s = &g->segs[g->nsegs];
    memset(s, 0, sizeof *s);
    p->seg = g->nsegs;
    p->side = 0;
    p->reversed = false;
    const seam_curve *c = &cx->curves[p->curve];
    s->node[0] = p->node[0];
    s->node[1] = p->node[1];
    s->patch[0] = c->patch;
    s->patch[1] = -1;
    s->loop[0] = c->loop;
    s->loop[1] = -1;
    s->degenerate = p->degenerate;
    s->min_interior = min_interior;
    tlist tl = {0};
    if (p->degenerate) {
        tpush(&tl, p->ta);
        tpush(&tl, p->tb);
    } else {
        sample_piece(cx, c, p->ta, p->tb, min_interior, &tl);
    }
    s->npts = tl.n;
    s->pts = prw_malloc(sizeof(prw_dvec3) * (size_t)tl.n);
    s->uv[0] = prw_malloc(sizeof(double) * 2 * (size_t)tl.n);
    for (int i = 0; i < tl.n; i++) {
        s->pts[i] = i == 0 ? g->nodes[p->node[0]] : i == tl.n - 1 ? g->nodes[p->node[1]] : seam_curve_eval(c, tl.t[i]);
        seam_curve_uv(c, tl.t[i], s->uv[0] + 2 * i);
    }
    /* exact-curve samples between the sewing points, and the chord error */
    s->dense = prw_malloc(sizeof(prw_dvec3) * (size_t)(tl.n - 1) * PRW_SEAM_DENSE + 1);
    for (int i = 0; i + 1 < tl.n; i++) {
        for (int k = 0; k < PRW_SEAM_DENSE; k++) {
            double t = tl.t[i] + (tl.t[i + 1] - tl.t[i]) * (k + 1) / (PRW_SEAM_DENSE + 1);
            prw_dvec3 x = p->degenerate ? s->pts[0] : seam_curve_eval(c, t);
            s->dense[i * PRW_SEAM_DENSE + k] = x;
            s->chord_err = fmax(s->chord_err, seg_dist(x, s->pts[i], s->pts[i + 1]));
        }
        s->length += dist3(s->pts[i], s->pts[i + 1]);
    }
    /* partner side */
    if (p->match >= 0) {
        seam_piece *q = &cx->pieces[p->match];
        const seam_curve *qc = &cx->curves[q->curve];
        q->seg = g->nsegs;
        q->side = 1;
        s->patch[1] = qc->patch;
        s->loop[1] = qc->loop;
        if (p->node[0] != p->node[1]) {
            q->reversed = q->node[0] != p->node[0];
        } else { /* closed: compare directions */
            prw_dvec3 q1 = seam_curve_eval(qc, q->ta + 0.25 * (q->tb - q->ta));
            q->reversed = dist3(q1, seam_curve_eval(c, p->ta + 0.75 * (p->tb - p->ta))) <
                          dist3(q1, seam_curve_eval(c, p->ta + 0.25 * (p->tb - p->ta)));
        }
        s->uv[1] = prw_malloc(sizeof(double) * 2 * (size_t)tl.n);
        double lo = q->ta, hi = q->tb;
        for (int i = 0; i < tl.n; i++) {
            double t;
            if (i == 0 || i == tl.n - 1) {
                bool at_start = (i == 0) != q->reversed;
                t = at_start ? q->ta : q->tb;
            } else {
                seam_curve_project(qc, s->pts[i], lo, hi, &t);
                /* keep the partner parameters monotone along the segment */
                if (q->reversed) hi = t;
                else lo = t;
            }
            seam_curve_uv(qc, t, s->uv[1] + 2 * i);
            double gap = dist3(prw_nurbs_surface_eval(qc->surf, s->uv[1][2 * i], s->uv[1][2 * i + 1]), s->pts[i]);
            s->gap = fmax(s->gap, gap);
        }
        g->max_shared_gap = fmax(g->max_shared_gap, s->gap);
        g->shared++;
    } else if (p->degenerate) {
        g->degenerate++;
    } else {
        g->open++;
        /* largest distance to the nearest other (parallel) boundary, capped at 100 tol */
        double worst = 0;
        for (int i = 0; i + 1 < tl.n && isfinite(worst); i++) {
            prw_dvec3 x = s->dense[i * PRW_SEAM_DENSE + PRW_SEAM_DENSE / 2];
            double d;
            int other = seam_nearest_curve(cx, x, prw_v3_sub(s->pts[i + 1], s->pts[i]), p->curve, 100 * cx->tol, &d);
            worst = other < 0 ? INFINITY : fmax(worst, d);
        }
        s->gap = worst;
        if (p->label >= 0) {
            g->unmatched++;
            if (!g->first_problem[0])
                snprintf(g->first_problem, sizeof g->first_problem,
                         "patch %d: a boundary piece near patch %d has no matching piece (gap %.3g)", c->patch,
                         cx->curves[p->label].patch, s->gap);
        }
    }
    free(tl.t);
    g->nsegs++;
}

bool prw_seam_build(const prw_nurbs_model *m, const prw_seam_options *o, prw_seam_graph *g, prw_error *e)
{
    memset(g, 0, sizeof *g);
    prw_dvec3 lo, hi;
    if (!prw_nurbs_model_bounds(m, &lo, &hi)) return prw_fail(e, "seam graph: empty model");
    g->diag = dist3(hi, lo);
    if (!(g->diag > 0) || !isfinite(g->diag)) return prw_fail(e, "seam graph: model has no extent");
    prw_seam_options opt = o ? *o : (prw_seam_options){0};
    g->tol = opt.tol > 0 ? opt.tol : 1e-6 * g->diag;
    g->chord = opt.chord > 0 ? opt.chord : 1e-3 * g->diag;
    g->max_edge = opt.max_edge > 0 ? opt.max_edge : g->diag / 40;
    g->npatches = (int)m->count;
    g->patches = prw_calloc(m->count + 1, sizeof(prw_seam_patch));

    seam_ctx cx;
    memset(&cx, 0, sizeof cx);
    cx.m = m;
    cx.tol = g->tol;
    cx.chord = g->chord;
    cx.max_edge = g->max_edge;
    if (!seam_curves_build(&cx, g, e)) {
        seam_ctx_free(&cx);
        prw_seam_free(g);
        return false;
    }
    seam_pieces_build(&cx);
    build_nodes(&cx, g);
    for (int i = 0; i < cx.npieces; i++) {
        seam_piece *p = &cx.pieces[i];
        if (!p->degenerate && p->node[0] == p->node[1] && piece_length(&cx, p) < 2 * cx.tol) p->degenerate = true;
    }
    match_pieces(&cx);

    /* minimum interior points: closed segments keep 2, segments sharing their node pair keep 1 */
    int *min_int = prw_calloc((size_t)cx.npieces + 1, sizeof(int));
    for (int i = 0; i < cx.npieces; i++) {
        const seam_piece *p = &cx.pieces[i];
        if (p->degenerate || (p->match >= 0 && p->match < i)) continue;
        if (p->node[0] == p->node[1]) {
            min_int[i] = 2;
            continue;
        }
        for (int j = 0; j < cx.npieces && !min_int[i]; j++) {
            const seam_piece *q = &cx.pieces[j];
            if (j == i || j == p->match || q->degenerate || (q->match >= 0 && q->match < j)) continue;
            if (same_pair(p, q)) min_int[i] = 1;
        }
    }
    g->segs = prw_malloc(sizeof(prw_seam_segment) * (size_t)cx.npieces + 1);
    for (int i = 0; i < cx.npieces; i++) {
        seam_piece *p = &cx.pieces[i];
        if (p->match >= 0 && p->match < i) continue; /* the partner side of an earlier segment */
        make_segment(&cx, g, i, min_int[i]);
    }
    free(min_int);

    /* global ids of the interior sewing points */
    g->ngids = g->nnodes;
    for (int s = 0; s < g->nsegs; s++) {
        g->segs[s].gid0 = g->ngids;
        g->ngids += g->segs[s].npts - 2;
    }

    /* patch loops: the pieces of each loop's curves in order */
    for (int pi = 0; pi < g->npatches; pi++) {
        prw_seam_patch *P = &g->patches[pi];
        prw_nurbs_surface_bounds(&m->surfaces[pi].surface, &P->lo, &P->hi);
        if (P->skipped) continue;
        int l0 = cx.patch_loop_first[pi], l1 = cx.patch_loop_first[pi + 1];
        P->nloops = l1 - l0;
        P->loops = prw_calloc((size_t)P->nloops + 1, sizeof(prw_seam_loop));
    }
    for (int i = 0; i < cx.npieces; i++) {
        const seam_piece *p = &cx.pieces[i];
        const seam_curve *c = &cx.curves[p->curve];
        prw_seam_patch *P = &g->patches[c->patch];
        add_use(&P->loops[c->loop], p->seg, p->reversed, p->side);
    }
    for (int s = 0; s < g->nsegs; s++) {
        const prw_seam_segment *sg = &g->segs[s];
        for (int side = 0; side < 2; side++) {
            if (sg->patch[side] < 0) continue;
            prw_seam_patch *P = &g->patches[sg->patch[side]];
            for (int i = 0; i < sg->npts; i++) {
                P->lo = prw_v3_min(P->lo, sg->pts[i]);
                P->hi = prw_v3_max(P->hi, sg->pts[i]);
            }
        }
    }
    seam_ctx_free(&cx);
    return true;
}

void prw_seam_free(prw_seam_graph *g)
{
    for (int s = 0; s < g->nsegs; s++) {
        free(g->segs[s].pts);
        free(g->segs[s].uv[0]);
        free(g->segs[s].uv[1]);
        free(g->segs[s].dense);
    }
    free(g->segs);
    for (int p = 0; p < g->npatches; p++) {
        for (int l = 0; l < g->patches[p].nloops; l++) free(g->patches[p].loops[l].uses);
        free(g->patches[p].loops);
    }
    free(g->patches);
    free(g->nodes);
    memset(g, 0, sizeof *g);
}

int prw_seam_point_gid(const prw_seam_graph *g, int s, int i)
{
    const prw_seam_segment *sg = &g->segs[s];
    if (i == 0) return sg->node[0];
    if (i == sg->npts - 1) return sg->node[1];
    return sg->gid0 + i - 1;
}

prw_dvec3 prw_seam_gid_pos(const prw_seam_graph *g, int gid)
{
    if (gid < g->nnodes) return g->nodes[gid];
    /* binary search the segment by gid0 */
    int lo = 0, hi = g->nsegs - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (g->segs[mid].gid0 <= gid) lo = mid;
        else hi = mid - 1;
    }
    /* segments without interior points share gid0 with the next one: step to one that has it */
    while (lo < g->nsegs && !(gid >= g->segs[lo].gid0 && gid < g->segs[lo].gid0 + g->segs[lo].npts - 2)) lo--;
    return g->segs[lo].pts[gid - g->segs[lo].gid0 + 1];
}
