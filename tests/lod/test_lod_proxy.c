/* Whole-model proxy levels (lod/prw_lod_proxy.h) on the filleted box, the plate with holes and the
 * car shell:
 *  - per level: finite data, every edge used once (border) or twice in opposite directions (the
 *    per-patch flips are computed here from the coarsest patch emission, so the box's inward-facing
 *    patches agree), border edges <= M_s's, no zero-area triangle; triangle counts strictly
 *    decreasing; the car shell's coarsest level <= 1/3 of the patches' coarsest levels together;
 *  - bound honesty: an independent dense oracle against the EXACT trimmed surfaces
 *    (lod_two_sided_model: not M_s, not the build's BVH) is <= err on every level;
 *  - teeth: the same check fails on a copy of a level with one vertex moved by 3 x err along its
 *    normal;
 *  - corners: the exact surface point at each corner's (patch, u, v) lies within 1e-9 x diag of the
 *    vertex: every proxy vertex is an M_s vertex, and an M_s vertex is a patch vertex evaluated at
 *    its own (u, v) — except display fan centres of M_s (mean of a triangle's corners, (u, v) = the
 *    mean of its fan's rim), which are only counted (none on these three models: at one uniform
 *    level the two sides of a seam show the same sewing points) and held to a loose 0.05 x diag;
 *  - options: a small query budget (max_samples) drops only the finest levels, the others
 *    bit-identical; a smaller max_start_triangles starts at a coarser k_s.
 * `test_lod_proxy --bench` instead prints the car shell at the bench setting (finest_rel 1e-5, seam
 * chord 0.5e-5 x diagonal). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lod_distance.h"
#include "lod_fixture.h"
#include "prw_lod_proxy.h"
#include "prw_nurbs_procedural.h"
#include "prw_test.h"

/* Light mode (sanitizer builds: memory errors, not power; 127 s in full there) only the coarsest level
 * meets the dense oracle (test code; every level's mesh checks still run) besides the teeth control,
 * and the option rebuilds are skipped. */
#define ORACLE_LIGHT (prw_test_light() ? 1 : 0)

typedef struct ekey {
    uint32_t a, b;
    int fwd, back; /* uses a->b and b->a */
} ekey;

static int ecmp(const void *x, const void *y)
{
    const ekey *p = x, *q = y;
    return p->a != q->a ? (p->a < q->a ? -1 : 1) : p->b != q->b ? (p->b < q->b ? -1 : 1) : 0;
}

/* Per-patch flips: on the welded coarsest emission (crack-free), two patches sharing an edge must
 * traverse it in opposite directions; breadth-first from patch 0 of each component. */
static unsigned char *patch_flips(const prw_lod_model *lm)
{
    int np = lm->npatches, top = lm->levels - 1;
    int *pl = calloc((size_t)np + 1, sizeof(int)), *sl = malloc(sizeof(int) * ((size_t)lm->g->nsegs + 1));
    for (int p = 0; p < np; p++) pl[p] = top;
    prw_lod_segment_levels(lm, pl, sl);
    prw_lod_mesh m;
    memset(&m, 0, sizeof m);
    int *tp = NULL;
    size_t tcap = 0;
    for (int p = 0; p < np; p++) {
        size_t before = m.ntris;
        prw_lod_emit(lm, p, top, sl, &m);
        if (m.ntris > tcap) tcap = 2 * m.ntris, tp = realloc(tp, sizeof(int) * tcap);
        for (size_t t = before; t < m.ntris; t++) tp[t] = p;
    }
    /* weld by exact position: sort vertex ids by position */
    size_t nv = m.nverts;
    uint32_t *rep = malloc(sizeof(uint32_t) * (nv + 1));
    {
        size_t hs = 1;
        while (hs < 2 * nv + 2) hs *= 2;
        int64_t *h = malloc(sizeof(int64_t) * hs);
        for (size_t i = 0; i < hs; i++) h[i] = -1;
        for (size_t i = 0; i < nv; i++) {
            uint64_t x = 1469598103934665603ull, b;
            for (int k = 0; k < 3; k++) memcpy(&b, m.pos + 3 * i + k, 8), x = (x ^ b) * 1099511628211ull, x ^= x >> 31;
            size_t s = x & (hs - 1);
            while (h[s] >= 0 && memcmp(m.pos + 3 * h[s], m.pos + 3 * i, 24)) s = (s + 1) & (hs - 1);
            if (h[s] < 0) h[s] = (int64_t)i;
            rep[i] = (uint32_t)h[s];
        }
        free(h);
    }
    size_t ne = 3 * m.ntris;
    ekey *E = malloc(sizeof(ekey) * (ne + 1));
    for (size_t t = 0; t < m.ntris; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = rep[m.tris[3 * t + k]], b = rep[m.tris[3 * t + (k + 1) % 3]];
            ekey *x = &E[3 * t + k];
            x->a = a < b ? a : b, x->b = a < b ? b : a;
            x->fwd = a < b, x->back = (int)t; /* fwd: direction; back: triangle (reused field) */
        }
    qsort(E, ne, sizeof(ekey), ecmp);
    /* relation graph between patches: +1 same, -1 opposite (as listed per shared edge) */
    int(*rel)[3] = malloc(sizeof(int[3]) * (ne + 1));
    size_t nr = 0;
    for (size_t i = 0; i + 1 < ne; i++)
        if (E[i].a == E[i + 1].a && E[i].b == E[i + 1].b &&
            (i + 2 >= ne || E[i + 2].a != E[i].a || E[i + 2].b != E[i].b)) {
            int p = tp[E[i].back], q = tp[E[i + 1].back];
            if (p == q) continue;
            rel[nr][0] = p, rel[nr][1] = q, rel[nr][2] = E[i].fwd == E[i + 1].fwd ? -1 : 1;
            nr++;
        }
    unsigned char *flip = calloc((size_t)np + 1, 1), *seen = calloc((size_t)np + 1, 1);
    /* propagate until stable (np is small) */
    for (int p0 = 0; p0 < np; p0++) {
        if (seen[p0]) continue;
        seen[p0] = 1;
        for (bool changed = true; changed;) {
            changed = false;
            for (size_t r = 0; r < nr; r++) {
                int p = rel[r][0], q = rel[r][1];
                if (seen[p] && !seen[q])
                    seen[q] = 1, flip[q] = rel[r][2] > 0 ? flip[p] : !flip[p], changed = true;
                else if (seen[q] && !seen[p])
                    seen[p] = 1, flip[p] = rel[r][2] > 0 ? flip[q] : !flip[q], changed = true;
            }
        }
    }
    free(seen);
    free(rel);
    free(E);
    free(rep);
    free(tp);
    free(pl);
    free(sl);
    prw_lod_mesh_free(&m);
    return flip;
}

static void level_mesh(const prw_lod_proxy_level *L, prw_lod_mesh *m)
{
    memset(m, 0, sizeof *m);
    m->pos = L->pos, m->nverts = (size_t)L->nverts;
    m->tris = L->tris, m->ntris = (size_t)L->ntris;
}

static void run(const char *name, bool (*make)(prw_nurbs_model *, prw_error *), double chord_rel, bool car)
{
    prw_nurbs_model m;
    prw_seam_graph g;
    prw_lod_model lm;
    prw_error e;
    double diag;
    if (!lod_fixture(make, chord_rel, NULL, &m, &g, &lm, &diag, NULL, &e)) {
        CHECK_MSG(false, "%s", e.msg);
        return;
    }
    CHECK(lm.failed_patches == 0);
    unsigned char *flip = patch_flips(&lm);
    prw_lod_proxy px;
    CHECK_OK(prw_lod_proxy_build(&lm, flip, NULL, &px, &e), &e);
    int patch_coarse = 0;
    for (int p = 0; p < lm.npatches; p++) patch_coarse += prw_lod_patch_triangles(&lm, p, lm.levels - 1);
    printf("%s: %d patches, k_s %d (eps_s %.3g = %.3g diag), M_s %d triangles, %d border edges, %d proxy levels, "
           "build %.2f s; patches' coarsest levels %d triangles\n",
           name, lm.npatches, px.start_level, px.eps_start, px.eps_start / diag, px.start_triangles, px.border_edges,
           px.nlevels, px.build_s, patch_coarse);
    CHECK(px.nlevels >= 2);
    int prev = px.start_triangles;
    for (int l = 0; l < px.nlevels; l++) {
        const prw_lod_proxy_level *L = &px.levels[l];
        CHECK(L->ntris < prev);
        prev = L->ntris;
        CHECK(L->err >= px.eps_start && L->d_start >= 0 && isfinite(L->err));
        /* finite data */
        bool fin = true;
        for (int i = 0; i < 3 * L->nverts; i++) fin = fin && isfinite(L->pos[i]);
        for (int i = 0; i < 6 * L->ntris; i++) fin = fin && isfinite(L->corner_uv[i]);
        CHECK(fin);
        /* edges */
        ekey *E = malloc(sizeof(ekey) * (3 * (size_t)L->ntris + 1));
        int zero = 0;
        for (int t = 0; t < L->ntris; t++) {
            const uint32_t *tr = L->tris + 3 * t;
            CHECK(tr[0] < (uint32_t)L->nverts && tr[1] < (uint32_t)L->nverts && tr[2] < (uint32_t)L->nverts);
            for (int k = 0; k < 3; k++) {
                uint32_t a = tr[k], b = tr[(k + 1) % 3];
                E[3 * t + k] = (ekey){a < b ? a : b, a < b ? b : a, (a < b), (a > b)};
            }
            prw_dvec3 A = prw_v3(L->pos[3 * tr[0]], L->pos[3 * tr[0] + 1], L->pos[3 * tr[0] + 2]);
            prw_dvec3 B = prw_v3(L->pos[3 * tr[1]], L->pos[3 * tr[1] + 1], L->pos[3 * tr[1] + 2]);
            prw_dvec3 C = prw_v3(L->pos[3 * tr[2]], L->pos[3 * tr[2] + 1], L->pos[3 * tr[2] + 2]);
            double le =
                fmax(prw_v3_len(prw_v3_sub(B, A)), fmax(prw_v3_len(prw_v3_sub(C, B)), prw_v3_len(prw_v3_sub(A, C))));
            zero += prw_v3_len(prw_v3_cross(prw_v3_sub(B, A), prw_v3_sub(C, A))) <= 1e-12 * le * le;
        }
        size_t ne = 3 * (size_t)L->ntris;
        qsort(E, ne, sizeof(ekey), ecmp);
        int border = 0, bad = 0, misoriented = 0;
        for (size_t i = 0; i < ne;) {
            size_t j = i;
            int f = 0, b = 0;
            while (j < ne && E[j].a == E[i].a && E[j].b == E[i].b) f += E[j].fwd, b += E[j].back, j++;
            if (j - i == 1)
                border++;
            else if (j - i == 2)
                misoriented += f != 1;
            else
                bad++;
            i = j;
        }
        free(E);
        CHECK(bad == 0);
        CHECK(misoriented == 0);
        CHECK(border <= px.border_edges);
        CHECK(zero == 0);
        /* corners */
        int off = 0;
        double worst_on = 0, worst_off = 0;
        for (int t = 0; t < L->ntris; t++)
            for (int k = 0; k < 3; k++) {
                int p = L->corner_patch[3 * t + k];
                CHECK(p >= 0 && p < lm.npatches);
                const uint32_t v = L->tris[3 * t + k];
                prw_dvec3 s = prw_nurbs_surface_eval(&m.surfaces[p].surface, L->corner_uv[6 * t + 2 * k],
                                                     L->corner_uv[6 * t + 2 * k + 1]);
                double d = prw_v3_len(prw_v3_sub(s, prw_v3(L->pos[3 * v], L->pos[3 * v + 1], L->pos[3 * v + 2])));
                if (d <= 1e-9 * diag)
                    worst_on = fmax(worst_on, d);
                else
                    off++, worst_off = fmax(worst_off, d);
            }
        /* the only vertices not on the surface are M_s fan centres: mean of a level-k_s triangle's
         * corners, evaluated at the mean (u, v) of its fan's rim; both lie within that triangle's
         * (u, v) region, so the gap is bounded by eps_s plus the surface's variation over it —
         * checked loosely against 0.05 x diag (a wrong patch or (u, v) is off by far more) */
        CHECK(worst_off <= 0.05 * diag);
        /* bound honesty against the exact surface */
        prw_lod_mesh lmsh;
        level_mesh(L, &lmsh);
        bool check = !ORACLE_LIGHT || l + 1 == px.nlevels;
        double meas = check ? lod_two_sided_model(&m, &lmsh, 32, 6) : 0;
        printf("  level %d (stage %d): %6d triangles %6d vertices, err %.4g (%.3g diag, d_start %.3g), measured %.4g = "
               "%.3f err; corners off-surface %d (worst %.2g diag), border %d\n",
               l, L->stage, L->ntris, L->nverts, L->err, L->err / diag, L->d_start, meas, meas / L->err, off,
               worst_off / diag, border);
        CHECK(meas <= L->err);
    }
    /* teeth: one vertex of the middle level moved by 3 x err along its normal */
    {
        const prw_lod_proxy_level *L = &px.levels[px.nlevels / 2];
        double *pos = malloc(sizeof(double) * 3 * (size_t)L->nverts);
        memcpy(pos, L->pos, sizeof(double) * 3 * (size_t)L->nverts);
        uint32_t v = L->tris[0];
        prw_dvec3 n = prw_v3(0, 0, 0);
        for (int t = 0; t < L->ntris; t++) {
            const uint32_t *tr = L->tris + 3 * t;
            if (tr[0] != v && tr[1] != v && tr[2] != v) continue;
            prw_dvec3 A = prw_v3(pos[3 * tr[0]], pos[3 * tr[0] + 1], pos[3 * tr[0] + 2]);
            prw_dvec3 B = prw_v3(pos[3 * tr[1]], pos[3 * tr[1] + 1], pos[3 * tr[1] + 2]);
            prw_dvec3 C = prw_v3(pos[3 * tr[2]], pos[3 * tr[2] + 1], pos[3 * tr[2] + 2]);
            n = prw_v3_add(n, prw_v3_cross(prw_v3_sub(B, A), prw_v3_sub(C, A)));
        }
        n = prw_v3_norm(n);
        for (int k = 0; k < 3; k++) pos[3 * v + k] += 3 * L->err * (&n.x)[k];
        prw_lod_mesh bad;
        memset(&bad, 0, sizeof bad);
        bad.pos = pos, bad.nverts = (size_t)L->nverts, bad.tris = L->tris, bad.ntris = (size_t)L->ntris;
        double meas = lod_two_sided_model(&m, &bad, 32, 6);
        printf("  control: level %d with vertex %u moved by 3 err: measured %.4g = %.3f err (must exceed 1)\n",
               px.nlevels / 2, v, meas, meas / L->err);
        CHECK(meas > L->err);
        free(pos);
    }
    /* options: a small query budget drops the finest levels only (the rest identical); a smaller
     * start mesh starts at a coarser k_s (6-8 more builds: not under ASan, where the same code runs
     * in the main build above) */
    if (!ORACLE_LIGHT) {
        prw_lod_proxy p2;
        /* the smallest budgets first that still keep a level (the models differ in size) */
        static const double budgets[] = {6e4, 2e4, 6e3, 2e3, 600};
        double used = 0;
        for (size_t b = 0; b < PRW_ARRAY_LEN(budgets); b++) {
            CHECK_OK(prw_lod_proxy_build(&lm, flip, &(prw_lod_proxy_options){.max_samples = budgets[b]}, &p2, &e), &e);
            used = budgets[b];
            if (p2.nlevels < px.nlevels || b + 1 == PRW_ARRAY_LEN(budgets)) break;
            prw_lod_proxy_free(&p2);
        }
        printf("  max_samples %.0f: %d levels (of %d)\n", used, p2.nlevels, px.nlevels);
        CHECK(p2.nlevels < px.nlevels);
        for (int l = 0; l < p2.nlevels; l++) {
            const prw_lod_proxy_level *A = &p2.levels[l], *B = &px.levels[px.nlevels - p2.nlevels + l];
            CHECK(A->ntris == B->ntris && A->err == B->err && A->stage == B->stage);
        }
        prw_lod_proxy_free(&p2);
        /* a triangle cap below the finest level's: no level above it (the stages before the cap is
         * reached run in whole octaves, so the levels below it may differ) */
        if (px.nlevels > 1) {
            CHECK_OK(prw_lod_proxy_build(&lm, flip, &(prw_lod_proxy_options){.max_level_triangles = px.levels[0].ntris - 1},
                                         &p2, &e),
                     &e);
            printf("  max_level_triangles %d: %d levels (of %d)\n", px.levels[0].ntris - 1, p2.nlevels, px.nlevels);
            CHECK(p2.nlevels >= 1 && p2.levels[0].ntris <= px.levels[0].ntris - 1);
            prw_lod_proxy_free(&p2);
        }
        CHECK_OK(prw_lod_proxy_build(&lm, flip, &(prw_lod_proxy_options){.max_start_triangles = px.start_triangles - 1},
                                     &p2, &e),
                 &e);
        printf("  max_start_triangles %d: k_s %d, M_s %d triangles, %d levels\n", px.start_triangles - 1,
               p2.start_level, p2.start_triangles, p2.nlevels);
        CHECK(p2.start_level > px.start_level && p2.start_triangles < px.start_triangles);
        prw_lod_proxy_free(&p2);
    }
    if (car) {
        int coarsest = px.levels[px.nlevels - 1].ntris;
        printf("  car shell: coarsest proxy %d triangles vs patches' coarsest %d (%.3f)\n", coarsest, patch_coarse,
               (double)coarsest / patch_coarse);
        CHECK(3 * coarsest <= patch_coarse);
    }
    free(flip);
    prw_lod_proxy_free(&px);
    lod_fixture_free(&m, &g, &lm);
}

static bool make_box(prw_nurbs_model *m, prw_error *e) { return prw_procedural_filleted_box(m, 1.0, 0.3, e); }

static void bench(void)
{
    prw_nurbs_model m;
    prw_seam_graph g;
    prw_lod_model lm;
    prw_error e;
    double diag, t0 = prw_now();
    if (!lod_fixture(prw_procedural_car_shell, 0.5e-5, &(prw_lod_options){.finest_rel = 1e-5}, &m, &g, &lm, &diag, NULL,
                     &e)) {
        CHECK_MSG(false, "%s", e.msg);
        return;
    }
    double t1 = prw_now(); /* seam graph + hierarchy */
    unsigned char *flip = patch_flips(&lm);
    prw_lod_proxy px;
    CHECK_OK(prw_lod_proxy_build(&lm, flip, NULL, &px, &e), &e);
    int patch_coarse = 0;
    for (int p = 0; p < lm.npatches; p++) patch_coarse += prw_lod_patch_triangles(&lm, p, lm.levels - 1);
    printf("car shell (bench setting): diag %.4g, hierarchy %.2f s (%d levels, tau0 %.3g), proxy build %.2f s, k_s %d, "
           "eps_s %.3g (%.3g diag), M_s %d triangles, %d border edges; patches' coarsest %d triangles\n",
           diag, t1 - t0, lm.levels, lm.tau0, px.build_s, px.start_level, px.eps_start, px.eps_start / diag,
           px.start_triangles, px.border_edges, patch_coarse);
    /* the patches at one uniform level, for comparison */
    {
        int *pl = calloc((size_t)lm.npatches + 1, sizeof(int)), *sl = calloc((size_t)g.nsegs + 1, sizeof(int));
        prw_lod_mesh pm;
        memset(&pm, 0, sizeof pm);
        for (int k = 0; k < lm.levels; k++) {
            double err = 0;
            for (int p = 0; p < lm.npatches; p++) {
                pl[p] = k;
                if (lm.patches[p].ok) err = fmax(err, lm.patches[p].err[k]);
            }
            prw_lod_segment_levels(&lm, pl, sl);
            prw_lod_mesh_reset(&pm);
            for (int p = 0; p < lm.npatches; p++) prw_lod_emit(&lm, p, k, sl, &pm);
            printf("  patches all at level %2d: %7zu triangles, max err %.4g = %.3g diag\n", k, pm.ntris, err,
                   err / diag);
        }
        prw_lod_mesh_free(&pm);
        free(pl);
        free(sl);
    }
    for (int l = 0; l < px.nlevels; l++)
        printf("  level %d stage %d (tau %.3g): %6d triangles, err %.4g = %.3g diag (d_start %.3g)\n", l,
               px.levels[l].stage, lm.tau0 * exp2((double)px.levels[l].stage / PRW_PROXY_STEPS), px.levels[l].ntris, px.levels[l].err,
               px.levels[l].err / diag, px.levels[l].d_start);
    free(flip);
    prw_lod_proxy_free(&px);
    lod_fixture_free(&m, &g, &lm);
}

static void test_box(void) { run("filleted box", make_box, 2e-4, false); }
static void test_plate(void) { run("plate", prw_procedural_plate, 2e-4, false); }
static void test_car_shell(void) { run("car shell", prw_procedural_car_shell, 2e-4, true); }

int main(int argc, char **argv)
{
    if (argc > 1 && !strcmp(argv[1], "--bench")) {
        bench();
        return prw_test_failures ? 1 : 0;
    }
    static const prw_test_case cases[] = {
        {"filleted_box", test_box},
        {"plate", test_plate},
        {"car_shell", test_car_shell},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
