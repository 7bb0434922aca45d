/* IGES B-rep faces (510 with loops 508 of edges from edge lists 504; vertex-only edges from 502
 * are degenerate and dropped) and bounded surfaces (143 with boundaries 141), as trimmed
 * surfaces: each boundary's model-space curves, oriented as the loop uses them, are projected onto
 * the surface (prw_invert, seams unwrapped: prw_trim_wrap) and kept on the trim segments for the
 * seam graph.  Orientation: a face whose normal is opposite its surface's (the shell's face flag,
 * the solid's shell flag) gets its surface reversed in u, trims mirrored with it (exact). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "prw_iges_internal.h"
#include "prw_trim_wrap.h"

#define MAX_ITEMS 10000000

/* Curve pieces of model-space curve entity `ck`, reversed (order and direction) when !same. */
static bool oriented_curves(iges_ctx *x, int ck, bool same, iges_clist *out)
{
    prw_dmat4 id = prw_dm4_identity();
    iges_clist l = {0};
    if (!iges_curves(x, ck, 3, &id, &l)) {
        iges_clist_free(&l);
        return false;
    }
    for (int i = 0; i < l.n; i++) {
        int j = same ? i : l.n - 1 - i;
        if (!same) prw_nurbs_curve_reverse(&l.c[j]);
        iges_clist_push(out, &l.c[j]);
    }
    iges_clist_free(&l);
    return true;
}

/* The model-space curve of edge `ndx` (1-based) of edge list `ek` (504). */
static bool edge_curve(iges_ctx *x, const iges_de *loop, int param, int ek, int ndx, int *ck)
{
    const iges_de *d = &x->f->de[ek];
    if (d->type != 504)
        return iges_fail(x->f, loop, param, x->e, "edge list pointer is entity %d, not 504", d->type);
    int n;
    if (!iges_int(x->f, d, 1, 0, &n, x->e)) return false;
    if (n < 1 || n > MAX_ITEMS) return iges_fail(x->f, d, 1, x->e, "%d edges", n);
    if (ndx < 1 || ndx > n) return iges_fail(x->f, loop, param + 1, x->e, "edge index %d outside the list's 1..%d", ndx, n);
    if (!iges_need(x->f, d, 1 + 5 * n, x->e)) return false;
    return iges_ptr(x->f, d, 2 + 5 * (ndx - 1), false, ck, x->e);
}

/* Loop 508: its edges' curves in loop order. */
static bool loop_508(iges_ctx *x, int k, iges_clist *out)
{
    const iges_de *d = &x->f->de[k];
    if (d->type != 508) return iges_fail(x->f, d, 0, x->e, "face loop must be a 508, not entity %d", d->type);
    int n;
    if (!iges_int(x->f, d, 1, 0, &n, x->e)) return false;
    if (n < 1 || n > MAX_ITEMS) return iges_fail(x->f, d, 1, x->e, "%d edges in a loop", n);
    int i = 2; /* parameter index of the next edge tuple: TYPE, EDGE, NDX, OF, K, K x (ISOP, CURV) */
    for (int e = 0; e < n; e++) {
        int type, ek, ndx, of, kk;
        if (!iges_need(x->f, d, i + 4, x->e) || !iges_int(x->f, d, i, 0, &type, x->e) ||
            !iges_ptr(x->f, d, i + 1, false, &ek, x->e) || !iges_int(x->f, d, i + 2, 1, &ndx, x->e) ||
            !iges_int(x->f, d, i + 3, 1, &of, x->e) || !iges_int(x->f, d, i + 4, 0, &kk, x->e))
            return false;
        if (type != 0 && type != 1) return iges_fail(x->f, d, i, x->e, "edge type %d is not 0 (edge) or 1 (vertex)", type);
        if (of != 0 && of != 1) return iges_fail(x->f, d, i + 3, x->e, "edge orientation flag %d is not 0 or 1", of);
        if (kk < 0 || kk > 1000) return iges_fail(x->f, d, i + 4, x->e, "%d parameter-space curves", kk);
        if (type == 0) { /* a vertex-only edge (a pole) has no curve */
            int ck;
            if (!edge_curve(x, d, i + 1, ek, ndx, &ck) || !oriented_curves(x, ck, of == 1, out)) return false;
        } else if (x->f->de[ek].type != 502) {
            return iges_fail(x->f, d, i + 1, x->e, "vertex list pointer is entity %d, not 502", x->f->de[ek].type);
        }
        i += 5 + 2 * kk;
    }
    return true;
}

/* Boundary 141: its model-space curves with their senses (1 agrees, 2 reversed). */
static bool boundary_141(iges_ctx *x, int k, iges_clist *out)
{
    const iges_de *d = &x->f->de[k];
    if (d->type != 141) return iges_fail(x->f, d, 0, x->e, "a bounded surface's boundary must be a 141, not entity %d", d->type);
    int n;
    if (!iges_need(x->f, d, 4, x->e) || !iges_int(x->f, d, 4, 0, &n, x->e)) return false;
    if (n < 1 || n > MAX_ITEMS) return iges_fail(x->f, d, 4, x->e, "%d boundary curves", n);
    int i = 5; /* CRVPT, SENSE, K, K x PSCPT */
    for (int c = 0; c < n; c++) {
        int ck, sense, kk;
        if (!iges_need(x->f, d, i + 2, x->e) || !iges_ptr(x->f, d, i, false, &ck, x->e) ||
            !iges_int(x->f, d, i + 1, 1, &sense, x->e) || !iges_int(x->f, d, i + 2, 0, &kk, x->e))
            return false;
        if (sense != 1 && sense != 2) return iges_fail(x->f, d, i + 1, x->e, "sense %d is not 1 or 2", sense);
        if (kk < 0 || kk > 1000) return iges_fail(x->f, d, i + 2, x->e, "%d parameter-space curves", kk);
        if (!oriented_curves(x, ck, sense == 1, out)) return false;
        i += 3 + kk;
    }
    return true;
}

/* The surface for a face whose boundaries are `loops` (model space; a plane 108 covers them). */
static bool face_surface(iges_ctx *x, int sk, const iges_clist *loops, int nloops, prw_trimmed_surface *t)
{
    prw_dvec3 *hint = NULL;
    int nhint = 0;
    for (int l = 0; l < nloops; l++) iges_hint_points(&loops[l], &hint, &nhint);
    iges_surf S;
    memset(&S, 0, sizeof S);
    bool ok = iges_surface(x, sk, hint, nhint, &S);
    free(hint);
    iges_surf_free_map(&S);
    if (ok) t->surface = S.s;
    return ok;
}

static bool finish(iges_ctx *x, const iges_de *d, iges_clist *loops, int nloops, bool flip, prw_trimmed_surface *t)
{
    bool ok = true;
    for (int l = 0; ok && l < nloops; l++) ok = iges_project_loop(x, d, 0, &loops[l], t);
    for (int l = 0; l < nloops; l++) iges_clist_free(&loops[l]);
    free(loops);
    if (ok && t->nloops >= 2) { /* a band between two circles, each its own boundary (prw_trim_wrap.h) */
        prw_dvec3 lo, hi;
        prw_nurbs_surface_bounds(&t->surface, &lo, &hi);
        double size = prw_v3_len(prw_v3_sub(hi, lo)), u0, u1, v0, v1;
        prw_nurbs_surface_domain(&t->surface, &u0, &u1, &v0, &v1);
        bool closed[2] = {prw_nurbs_surface_closed(&t->surface, 0, 1e-9 * size),
                          prw_nurbs_surface_closed(&t->surface, 1, 1e-9 * size)};
        prw_trim_join_bands(t, closed, 1e-7 * fmax(u1 - u0, v1 - v0));
    }
    prw_dmat4 own;
    if (ok) ok = iges_own_xform(x, d, &own);
    if (ok) {
        prw_nurbs_surface_transform(&t->surface, &own);
        for (int l = 0; l < t->nloops; l++)
            for (int s = 0; s < t->loops[l].count; s++)
                if (t->loops[l].segs[s].model) prw_nurbs_curve_transform(t->loops[l].segs[s].model, &own);
        if (flip) prw_trimmed_surface_reverse_u(t);
    }
    return ok;
}

bool iges_brep_face(iges_ctx *x, int k, bool flip, prw_trimmed_surface *t)
{
    const iges_de *d = &x->f->de[k];
    int sk, n, outer;
    if (!iges_need(x->f, d, 3, x->e) || !iges_ptr(x->f, d, 1, false, &sk, x->e) || !iges_int(x->f, d, 2, 0, &n, x->e) ||
        !iges_int(x->f, d, 3, 1, &outer, x->e))
        return false;
    if (n < 1 || n > 1000000) return iges_fail(x->f, d, 2, x->e, "%d loops", n);
    if (outer != 0 && outer != 1) return iges_fail(x->f, d, 3, x->e, "outer loop flag %d is not 0 or 1", outer);
    if (!iges_need(x->f, d, 3 + n, x->e)) return false;
    iges_clist *loops = prw_calloc((size_t)n, sizeof *loops);
    bool ok = true;
    for (int l = 0; ok && l < n; l++) {
        int lk;
        ok = iges_ptr(x->f, d, 4 + l, false, &lk, x->e) && loop_508(x, lk, &loops[l]);
    }
    if (ok) ok = face_surface(x, sk, loops, n, t);
    if (!ok) {
        for (int l = 0; l < n; l++) iges_clist_free(&loops[l]);
        free(loops);
        return false;
    }
    t->natural_outer = outer == 0; /* no outer loop given: the domain is, every loop a hole */
    return finish(x, d, loops, n, flip, t);
}

bool iges_bounded_surface(iges_ctx *x, int k, prw_trimmed_surface *t)
{
    const iges_de *d = &x->f->de[k];
    int type, sk, n;
    if (!iges_need(x->f, d, 3, x->e) || !iges_int(x->f, d, 1, 0, &type, x->e) || !iges_ptr(x->f, d, 2, false, &sk, x->e) ||
        !iges_int(x->f, d, 3, 0, &n, x->e))
        return false;
    if (n < 0 || n > 1000000) return iges_fail(x->f, d, 3, x->e, "%d boundaries", n);
    if (!iges_need(x->f, d, 3 + n, x->e)) return false;
    iges_clist *loops = prw_calloc((size_t)n + 1, sizeof *loops);
    bool ok = true;
    for (int l = 0; ok && l < n; l++) {
        int bk;
        ok = iges_ptr(x->f, d, 4 + l, false, &bk, x->e) && boundary_141(x, bk, &loops[l]);
    }
    if (ok) ok = face_surface(x, sk, loops, n, t);
    if (!ok) {
        for (int l = 0; l < n; l++) iges_clist_free(&loops[l]);
        free(loops);
        return false;
    }
    t->natural_outer = n == 0; /* even-odd over the boundaries: which one is outer does not matter */
    return finish(x, d, loops, n, false, t);
}
