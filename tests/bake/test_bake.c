/* engine/bake and the .lod format it writes (engine/scene/prw_lod_file.h): the hierarchy cache.
 *  - round trip: parse(serialize(fresh build)) equals the fresh build in every array, bit for bit,
 *    and emits bit-identical meshes (vertices and indices) at every level and at random per-patch
 *    level mixes; serialize(parse(bytes)) == bytes;
 *  - the cache: a second prw_bake_run hits the cache (flag + the process build counter unchanged);
 *    a changed knob or changed input bytes is a different key;
 *  - a corrupted entry (one byte flipped in the middle; truncated) is reported and rebuilt, and
 *    the rewritten entry is valid;
 *  - the reader rejects every proper prefix of a small file — both as is and with the header
 *    patched to the prefix's size and checksum, so the structural checks (not only the checksum)
 *    are exercised — with a message naming the file, and never crashes;
 *  - the proxy section (format version 3): round trip bit for bit (compare_baked, serialize(parse)
 *    == bytes); a tri index = nverts, NaN / infinite coordinates, non-decreasing triangle counts,
 *    patch indices out of range, bad counts are refused with a message naming the problem;
 *  - single-byte mutations with a recomputed checksum either fail cleanly or give a hierarchy that
 *    selection and extraction walk without leaving their arrays (ASan / UBSan builds catch any
 *    stray read);
 *  - bake_scene: before prw_bake_scene an entry has nothing attached (the message the renderer and
 *    the reference give); after it, a file entry and a procedural entry carry their model and a
 *    hierarchy equal, bit for bit, to prw_bake_scene_entry's, each with one progress line (built, then
 *    from the cache for a second scene, with nothing rebuilt); a second call builds nothing and keeps
 *    the attachments; an attachment whose patch count is not the model's is refused. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bake_models.h"
#include "prw_bake.h"
#include "prw_bake_scene.h"
#include "prw_lod_orient.h"
#include "prw_lod_select.h"
#include "prw_nurbs_json.h"
#include "prw_nurbs_procedural.h"
#include "prw_test.h"

#define SAME(a, b, n) (((n) == 0) || ((a) && (b) && memcmp((a), (b), (n)) == 0))

/* Proxy levels (format version 3), bit for bit. */
static int compare_proxy(const prw_lod_proxy *px, const prw_lod_proxy *py)
{
    int diff = 0;
#define D(cond)                                                                 \
    do {                                                                        \
        if (!(cond)) {                                                          \
            if (diff++ < 5) fprintf(stderr, "  differs: %s\n", #cond);          \
        }                                                                       \
    } while (0)
    D(px->start_level == py->start_level && px->nlevels == py->nlevels &&
      memcmp(&px->eps_start, &py->eps_start, 8) == 0 && px->start_triangles == py->start_triangles &&
      px->patch_floor_triangles == py->patch_floor_triangles && px->border_edges == py->border_edges);
    for (int l = 0; l < px->nlevels && l < py->nlevels; l++) {
        const prw_lod_proxy_level *p = &px->levels[l], *q = &py->levels[l];
        D(p->stage == q->stage && memcmp(&p->err, &q->err, 8) == 0 && memcmp(&p->d_start, &q->d_start, 8) == 0 &&
          p->nverts == q->nverts && p->ntris == q->ntris);
        if (p->nverts != q->nverts || p->ntris != q->ntris) continue;
        size_t nv = (size_t)p->nverts, nt = (size_t)p->ntris;
        D(SAME(p->pos, q->pos, sizeof(double) * 3 * nv) && SAME(p->tris, q->tris, sizeof(uint32_t) * 3 * nt));
        D(SAME(p->corner_patch, q->corner_patch, sizeof(int) * 3 * nt) &&
          SAME(p->corner_uv, q->corner_uv, sizeof(double) * 6 * nt) && SAME(p->tri_patch, q->tri_patch, sizeof(int) * nt));
    }
#undef D
    return diff;
}

static int compare_baked(const prw_baked_lod *x, const prw_baked_lod *y)
{
    int diff = 0;
    const prw_seam_graph *g = &x->graph, *h = &y->graph;
    const prw_lod_model *a = &x->lod, *b = &y->lod;
#define D(cond)                                                                 \
    do {                                                                        \
        if (!(cond)) {                                                          \
            if (diff++ < 5) fprintf(stderr, "  differs: %s\n", #cond);          \
        }                                                                       \
    } while (0)
    D(g->nnodes == h->nnodes && g->nsegs == h->nsegs && g->npatches == h->npatches && g->ngids == h->ngids);
    if (diff) return diff;
    D(memcmp(&g->tol, &h->tol, 8) == 0 && memcmp(&g->chord, &h->chord, 8) == 0 && memcmp(&g->diag, &h->diag, 8) == 0);
    D(SAME(g->nodes, h->nodes, sizeof(prw_dvec3) * (size_t)g->nnodes));
    for (int s = 0; s < g->nsegs; s++) {
        const prw_seam_segment *p = &g->segs[s], *q = &h->segs[s];
        D(p->npts == q->npts && p->node[0] == q->node[0] && p->node[1] == q->node[1] && p->patch[0] == q->patch[0] &&
          p->patch[1] == q->patch[1] && p->gid0 == q->gid0 && p->min_interior == q->min_interior &&
          p->degenerate == q->degenerate);
        if (p->npts != q->npts) continue;
        D(SAME(p->pts, q->pts, sizeof(prw_dvec3) * (size_t)p->npts));
        for (int side = 0; side < 2; side++) {
            D((p->uv[side] == NULL) == (q->uv[side] == NULL));
            if (p->uv[side] && q->uv[side]) D(SAME(p->uv[side], q->uv[side], sizeof(double) * 2 * (size_t)p->npts));
        }
        D(SAME(a->seg_keep[s], b->seg_keep[s], sizeof(int) * (size_t)p->npts));
        D(SAME(a->ladder[s], b->ladder[s], sizeof(int) * (size_t)p->npts));
    }
    for (int i = 0; i < g->npatches; i++) {
        D(g->patches[i].nloops == h->patches[i].nloops && g->patches[i].skipped == h->patches[i].skipped);
        D(memcmp(&g->patches[i].lo, &h->patches[i].lo, sizeof(prw_dvec3)) == 0);
    }
    D(a->levels == b->levels && memcmp(&a->tau0, &b->tau0, 8) == 0 && a->npatches == b->npatches &&
      a->finest_triangles == b->finest_triangles && a->failed_patches == b->failed_patches);
    if (diff) return diff;
    for (int i = 0; i < a->npatches; i++) {
        const prw_lod_patch *p = &a->patches[i], *q = &b->patches[i];
        D(p->ok == q->ok && memcmp(&p->lo, &q->lo, sizeof p->lo) == 0 && memcmp(&p->hi, &q->hi, sizeof p->hi) == 0);
        if (!p->ok || !q->ok) continue;
        D(p->nverts == q->nverts && p->nbound == q->nbound && p->nrings == q->nrings);
        if (p->nverts != q->nverts || p->nbound != q->nbound || p->nrings != q->nrings) continue;
        size_t nv = (size_t)p->nverts, nb = (size_t)p->nbound;
        D(SAME(p->uv, q->uv, sizeof(double) * 2 * nv));
        D(SAME(p->pos, q->pos, sizeof(prw_dvec3) * nv));
        D(SAME(p->gid, q->gid, sizeof(int) * nv));
        D(SAME(p->removed_at, q->removed_at, sizeof(int) * nv));
        D(SAME(p->ring_start, q->ring_start, sizeof(int) * ((size_t)p->nrings + 1)));
        D(SAME(p->ring_of, q->ring_of, sizeof(int) * nb));
        D(SAME(p->ring_seg, q->ring_seg, sizeof(int) * nb));
        D(SAME(p->ring_sidx, q->ring_sidx, sizeof(int) * nb));
        D(SAME(p->ring_rev, q->ring_rev, nb));
        D(SAME(p->tri_start, q->tri_start, sizeof(int) * ((size_t)a->levels + 1)));
        if (p->tri_start[a->levels] == q->tri_start[a->levels])
            D(SAME(p->tris, q->tris, sizeof(int) * 3 * (size_t)p->tri_start[a->levels]));
        D(SAME(p->err, q->err, sizeof(double) * (size_t)a->levels));
    }
    /* culling data (format version 2) */
    const prw_lod_cull *c = &x->cull, *d = &y->cull;
    D(c->npatches == d->npatches && c->npatches == a->npatches && c->full_cones == d->full_cones &&
      c->refined == d->refined);
    if (c->npatches == d->npatches) {
        size_t np = (size_t)c->npatches;
        D(SAME(c->lo, d->lo, sizeof(prw_dvec3) * np) && SAME(c->hi, d->hi, sizeof(prw_dvec3) * np));
        D(SAME(c->centre, d->centre, sizeof(prw_dvec3) * np) && SAME(c->radius, d->radius, sizeof(double) * np));
        D(SAME(c->axis, d->axis, sizeof(prw_dvec3) * np) && SAME(c->half_angle, d->half_angle, sizeof(double) * np));
        D(SAME(c->single_sided, d->single_sided, np));
    }
    D(x->have_proxy == y->have_proxy);
    diff += compare_proxy(&x->proxy, &y->proxy);
#undef D
    return diff;
}

/* Bytes of the proxy section (format version 3), the file's last section. */
static size_t proxy_bytes(const prw_baked_lod *b)
{
    if (!b->have_proxy) return 1;
    size_t n = 1 + 4 + 8 + 4 * 4;
    for (int l = 0; l < b->proxy.nlevels; l++)
        n += 28 + 24 * (size_t)b->proxy.levels[l].nverts + 76 * (size_t)b->proxy.levels[l].ntris;
    return n;
}

/* Emits every patch at every uniform level and at `mixes` random per-patch mixes from both and
 * compares the meshes bit for bit.  Returns the number of differing meshes. */
static int compare_emit(const prw_lod_model *a, const prw_lod_model *b, int mixes, size_t *tris_out)
{
    int n = a->npatches, diff = 0;
    int *lv = prw_malloc(sizeof(int) * (size_t)n + 1), *sl = prw_malloc(sizeof(int) * (size_t)a->g->nsegs + 1);
    prw_lod_mesh ma, mb;
    memset(&ma, 0, sizeof ma);
    memset(&mb, 0, sizeof mb);
    uint64_t rng = 12345;
    size_t tris = 0;
    for (int round = 0; round < a->levels + mixes; round++) {
        for (int p = 0; p < n; p++) {
            if (round < a->levels) lv[p] = round;
            else {
                rng = rng * 6364136223846793005ull + 1442695040888963407ull;
                lv[p] = (int)((rng >> 33) % (uint64_t)a->levels);
            }
        }
        prw_lod_segment_levels(a, lv, sl);
        prw_lod_mesh_reset(&ma);
        prw_lod_mesh_reset(&mb);
        for (int p = 0; p < n; p++) {
            prw_lod_emit(a, p, lv[p], sl, &ma);
            prw_lod_emit(b, p, lv[p], sl, &mb);
        }
        tris += ma.ntris;
        bool same = ma.nverts == mb.nverts && ma.ntris == mb.ntris && ma.fans == mb.fans &&
                    SAME(ma.pos, mb.pos, sizeof(double) * 3 * ma.nverts) && SAME(ma.tris, mb.tris, sizeof(uint32_t) * 3 * ma.ntris);
        if (!same) diff++;
    }
    prw_lod_mesh_free(&ma);
    prw_lod_mesh_free(&mb);
    free(lv);
    free(sl);
    *tris_out = tris;
    return diff;
}

/* Light mode (sanitizer builds: memory errors, not power): the round trips and the cache cases bake
 * with coarse seam and LOD options (the same code paths: build, serialise, parse, cache hit, miss and
 * rebuild over a corrupt entry) instead of the defaults.  NULL (the defaults) otherwise. */
static const prw_bake_options *light_options(void)
{
    static prw_bake_options o;
    if (!prw_test_light()) return NULL;
    memset(&o, 0, sizeof o);
    o.seam.max_edge = 0.5;
    o.seam.chord = 0.02;
    o.lod.levels = 3;
    o.lod.max_cells = 2;
    return &o;
}

static void roundtrip(const char *name, bool (*make)(prw_nurbs_model *, prw_error *))
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    CHECK_OK(make(&m, &e), &e);
    prw_baked_lod *fresh, *back;
    double t0 = prw_now();
    CHECK_OK(prw_baked_lod_build(&m, light_options(), &fresh, NULL, NULL, &e), &e);
    double t1 = prw_now();
    strcpy(fresh->key, "0123456789abcdef0123456789abcdef");
    uint8_t *bytes, *bytes2;
    size_t n, n2;
    prw_lod_file_serialize(fresh, &bytes, &n);
    double t2 = prw_now();
    CHECK_OK(prw_lod_file_parse(bytes, n, name, &back, &e), &e);
    double t3 = prw_now();
    printf("  %s: build %.3f s, serialise %.4f s, parse + validate %.4f s (information, not asserted)\n", name, t1 - t0,
           t2 - t1, t3 - t2);
    CHECK(strcmp(back->key, fresh->key) == 0);
    CHECK(back->lod.g == &back->graph);
    int d = compare_baked(fresh, back);
    size_t tris = 0;
    int de = compare_emit(&fresh->lod, &back->lod, 20, &tris);
    printf("  %s: %d patches, %d levels, %zu bytes; %d array differences, %d of %d meshes differ (%zu triangles compared)\n",
           name, fresh->lod.npatches, fresh->lod.levels, n, d, de, fresh->lod.levels + 20, tris);
    printf("  %s: proxy %s, %d levels (%zu bytes of the file)\n", name, fresh->have_proxy ? "baked" : "none",
           fresh->proxy.nlevels, proxy_bytes(fresh));
    CHECK(fresh->have_proxy && back->have_proxy);
    /* what a renderer would build from the file's hierarchy (prw_lod_orient's flips, then
     * prw_lod_proxy_build) is bit for bit the baked proxy: lod_gpu may use it instead */
    unsigned char *flip = prw_calloc((size_t)back->lod.npatches + 1, 1);
    prw_lod_orient(&back->lod, &m, flip, NULL);
    prw_baked_lod *rebuilt = prw_calloc(1, sizeof *rebuilt);
    rebuilt->have_proxy = prw_lod_proxy_build(&back->lod, flip, NULL, &rebuilt->proxy, &e);
    CHECK(rebuilt->have_proxy && compare_proxy(&back->proxy, &rebuilt->proxy) == 0);
    prw_lod_proxy_free(&rebuilt->proxy);
    free(rebuilt);
    free(flip);
    CHECK(d == 0);
    CHECK(de == 0);
    CHECK(tris > 0);
    prw_lod_file_serialize(back, &bytes2, &n2);
    CHECK(n2 == n && memcmp(bytes, bytes2, n) == 0);
    /* the file is also usable through the file API */
    const char *path = prw_test_path("rt.lod");
    prw_baked_lod *fromfile;
    CHECK_OK(prw_lod_file_write(path, fresh, &e), &e);
    CHECK_OK(prw_lod_file_read(path, &fromfile, &e), &e);
    CHECK(compare_baked(fresh, fromfile) == 0);
    prw_lod_file_destroy(fromfile);
    free(bytes);
    free(bytes2);
    prw_lod_file_destroy(back);
    prw_lod_file_destroy(fresh);
    prw_nurbs_model_free(&m);
}

static bool make_two(prw_nurbs_model *m, prw_error *e)
{
    return prw_nurbs_json_parse(BAKE_TWO_PATCH_JSON, strlen(BAKE_TWO_PATCH_JSON), "two.json", m, e);
}

static void test_roundtrip_plate(void) { roundtrip("plate", prw_procedural_plate); }
static bool make_box(prw_nurbs_model *m, prw_error *e) { return prw_procedural_filleted_box(m, 0.4, 0.1, e); }
static void test_roundtrip_box(void) { roundtrip("filleted box", make_box); }
static void test_roundtrip_two(void) { roundtrip("two patches", make_two); }

static void set_cache(const char *sub)
{
    static char dir[4200];
    snprintf(dir, sizeof dir, "%s/%s", prw_test_tmpdir(), sub);
    setenv("PRW_CACHE_DIR", dir, 1);
}

static const char *write_model(const char *name)
{
    const char *path = prw_test_path(name);
    prw_test_write_file(path, BAKE_TWO_PATCH_JSON, strlen(BAKE_TWO_PATCH_JSON));
    return path;
}

static void test_cache_hit(void)
{
    set_cache("cache-hit");
    const char *model = write_model("hit.json");
    prw_error e;
    prw_bake_result r1, r2;
    prw_baked_lod *b1, *b2;
    int builds = prw_bake_build_count();
    CHECK_OK(prw_bake_run(model, light_options(), false, &b1, &r1, NULL, NULL, &e), &e);
    CHECK(r1.built && !r1.cache_hit && r1.cache_written && r1.warning[0] == '\0');
    CHECK(prw_bake_build_count() == builds + 1);
    CHECK(strstr(r1.cache_path, "/cache-hit/lod/") != NULL && strstr(r1.cache_path, r1.key) != NULL);
    CHECK_OK(prw_bake_run(model, light_options(), false, &b2, &r2, NULL, NULL, &e), &e);
    printf("  first: built %.3f s; second: cache hit %d, %.3f s; key %s\n", r1.seconds_total, r2.cache_hit,
           r2.seconds_total, r2.key);
    CHECK(r2.cache_hit && !r2.built);
    CHECK(prw_bake_build_count() == builds + 1); /* nothing rebuilt */
    CHECK(strcmp(r1.key, r2.key) == 0 && strcmp(r1.cache_path, r2.cache_path) == 0);
    CHECK(compare_baked(b1, b2) == 0);
    size_t t;
    CHECK(compare_emit(&b1->lod, &b2->lod, 5, &t) == 0);
    /* --no-cache builds again and does not touch the cache */
    prw_baked_lod *b3;
    prw_bake_result r3;
    CHECK_OK(prw_bake_run(model, light_options(), true, &b3, &r3, NULL, NULL, &e), &e);
    CHECK(r3.built && !r3.cache_hit && r3.cache_path[0] == '\0' && prw_bake_build_count() == builds + 2);
    prw_lod_file_destroy(b3);
    /* a changed knob is another key (and a miss) */
    prw_bake_options o;
    memset(&o, 0, sizeof o);
    if (light_options()) o = *light_options();
    o.lod.levels = 5;
    CHECK_OK(prw_bake_run(model, &o, false, &b3, &r3, NULL, NULL, &e), &e);
    CHECK(strcmp(r3.key, r1.key) != 0 && r3.built && !r3.cache_hit && b3->lod.levels == 5);
    prw_lod_file_destroy(b3);
    prw_lod_file_destroy(b1);
    prw_lod_file_destroy(b2);
}

static void test_key(void)
{
    const char *t = BAKE_TWO_PATCH_JSON;
    size_t n = strlen(t);
    char k0[33], k1[33];
    prw_bake_options o;
    memset(&o, 0, sizeof o);
    prw_bake_key(t, n, PRW_MODEL_JSON, &o, k0);
    prw_bake_key(t, n, PRW_MODEL_JSON, NULL, k1);
    CHECK(strcmp(k0, k1) == 0 && strlen(k0) == 32);
    int distinct = 0, cases = 0;
#define KEY_DIFFERS(stmt)                                  \
    do {                                                   \
        prw_bake_options q = o;                            \
        stmt;                                              \
        prw_bake_key(t, n, PRW_MODEL_JSON, &q, k1);        \
        cases++;                                           \
        distinct += strcmp(k0, k1) != 0;                   \
    } while (0)
    KEY_DIFFERS(q.seam.tol = 1e-5);
    KEY_DIFFERS(q.seam.chord = 1e-3);
    KEY_DIFFERS(q.seam.max_edge = 0.5);
    KEY_DIFFERS(q.lod.levels = 3);
    KEY_DIFFERS(q.lod.tau0 = 1e-4);
    KEY_DIFFERS(q.lod.max_cells = 8);
    KEY_DIFFERS(q.lod.max_patch_triangles = 100);
    KEY_DIFFERS(q.lod.finest_rel = 1e-5);
#undef KEY_DIFFERS
    CHECK(distinct == cases);
    prw_bake_key(t, n, PRW_MODEL_IGES, &o, k1);
    CHECK(strcmp(k0, k1) != 0);
    prw_bake_key(t, n - 1, PRW_MODEL_JSON, &o, k1);
    CHECK(strcmp(k0, k1) != 0);
    char *c = prw_strdup(t);
    c[n / 2] ^= 1;
    prw_bake_key(c, n, PRW_MODEL_JSON, &o, k1);
    CHECK(strcmp(k0, k1) != 0);
    free(c);
}

static void corrupt_and_rebuild(const char *what, bool truncate)
{
    set_cache(truncate ? "cache-trunc" : "cache-flip");
    const char *model = write_model(truncate ? "trunc.json" : "flip.json");
    prw_error e;
    prw_bake_result r;
    prw_baked_lod *b, *ref;
    CHECK_OK(prw_bake_run(model, light_options(), false, &ref, &r, NULL, NULL, &e), &e);
    char path[4096];
    snprintf(path, sizeof path, "%s", r.cache_path);
    char *d;
    size_t n;
    CHECK_OK(prw_read_file(path, &d, &n, &e), &e);
    if (truncate) n = n * 2 / 3;
    else d[n / 2] ^= 0x10;
    prw_test_write_file(path, d, n);
    free(d);
    int builds = prw_bake_build_count();
    CHECK_OK(prw_bake_run(model, light_options(), false, &b, &r, NULL, NULL, &e), &e);
    printf("  %s: warning \"%s\"\n", what, r.warning);
    CHECK(!r.cache_hit && r.built && r.cache_written);
    CHECK(strstr(r.warning, "corrupt cache entry rebuilt") != NULL && strstr(r.warning, path) != NULL);
    CHECK(strstr(r.warning, truncate ? "truncated" : "checksum") != NULL);
    CHECK(prw_bake_build_count() == builds + 1);
    CHECK(compare_baked(ref, b) == 0);
    prw_lod_file_destroy(b);
    /* the rewritten entry is whole again: the next run is a hit */
    CHECK_OK(prw_bake_run(model, light_options(), false, &b, &r, NULL, NULL, &e), &e);
    CHECK(r.cache_hit && r.warning[0] == '\0');
    prw_lod_file_destroy(b);
    prw_lod_file_destroy(ref);
}

static void test_corrupt_flip(void) { corrupt_and_rebuild("byte flipped", false); }
static void test_corrupt_truncated(void) { corrupt_and_rebuild("truncated", true); }

/* A tiny file: the two-patch model with few sewing points and levels. */
static void tiny_file(uint8_t **bytes, size_t *n, prw_baked_lod **b)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    *bytes = NULL;
    CHECK_OK(make_two(&m, &e), &e);
    prw_bake_options o;
    memset(&o, 0, sizeof o);
    o.seam.max_edge = 0.5;
    o.seam.chord = 0.02;
    o.lod.levels = 3;
    o.lod.max_cells = 2;
    CHECK_OK(prw_baked_lod_build(&m, &o, b, NULL, NULL, &e), &e);
    prw_lod_file_serialize(*b, bytes, n);
    prw_nurbs_model_free(&m);
}

static void patch_header(uint8_t *d, size_t n)
{
    uint64_t payload = n - PRW_LOD_HEADER_SIZE, sum = prw_hash64(d + PRW_LOD_HEADER_SIZE, payload, 0);
    for (int i = 0; i < 8; i++) {
        d[16 + i] = (uint8_t)(payload >> (8 * i));
        d[24 + i] = (uint8_t)(sum >> (8 * i));
    }
}

static void test_prefixes(void)
{
    uint8_t *full;
    size_t n;
    prw_baked_lod *b;
    tiny_file(&full, &n, &b);
    if (!full) return;
    prw_baked_lod *x;
    prw_error e;
    CHECK_OK(prw_lod_file_parse(full, n, "tiny.lod", &x, &e), &e);
    prw_lod_file_destroy(x);
    int rejected = 0, rejected_fixed = 0, named = 0;
    for (size_t len = 0; len < n; len++) {
        uint8_t *c = prw_malloc(len + 1);
        memcpy(c, full, len);
        if (!prw_lod_file_parse(c, len, "tiny.lod", &x, &e)) {
            rejected++;
            named += strncmp(e.msg, "tiny.lod: ", 10) == 0;
        } else prw_lod_file_destroy(x);
        if (len >= PRW_LOD_HEADER_SIZE) {
            patch_header(c, len);
            if (!prw_lod_file_parse(c, len, "tiny.lod", &x, &e)) {
                rejected_fixed++;
                named += strncmp(e.msg, "tiny.lod: ", 10) == 0;
            } else prw_lod_file_destroy(x);
        }
        free(c);
    }
    size_t fixed = n - PRW_LOD_HEADER_SIZE;
    printf("  %zu-byte file: %d of %zu prefixes rejected; with a consistent header: %d of %zu; %d messages name the file\n",
           n, rejected, n, rejected_fixed, fixed, named);
    CHECK((size_t)rejected == n);
    CHECK((size_t)rejected_fixed == fixed);
    CHECK((size_t)named == n + fixed);
    free(full);
    prw_lod_file_destroy(b);
}

static void test_mutations(void)
{
    uint8_t *full;
    size_t n;
    prw_baked_lod *b;
    tiny_file(&full, &n, &b);
    if (!full) return;
    uint8_t *c = prw_malloc(n);
    uint64_t rng = 99;
    int parsed = 0, rejected = 0, bad_msg = 0;
    static const uint8_t xors[] = {0x01, 0x80, 0xff, 0x7f};
    for (size_t i = PRW_LOD_HEADER_SIZE; i < n; i++) {
        for (int k = 0; k < 2; k++) {
            memcpy(c, full, n);
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            c[i] ^= xors[(rng >> 40) % 4];
            patch_header(c, n);
            prw_baked_lod *x;
            prw_error e;
            if (!prw_lod_file_parse(c, n, "m.lod", &x, &e)) {
                rejected++;
                bad_msg += strncmp(e.msg, "m.lod: ", 7) != 0;
                continue;
            }
            parsed++;
            /* walk it as a renderer would, with the file's culling data (single-sided, so the cones
             * are used) */
            prw_lod_view v = {.eye = {{0.5, -3, 1}}, .neyes = 1, .pixel_angle = 1e-3, .cull = &x->cull};
            for (int p = 0; p < x->cull.npatches; p++) x->cull.single_sided[p] = 1;
            int *lv = prw_malloc(sizeof(int) * (size_t)x->lod.npatches + 1);
            int *sl = prw_malloc(sizeof(int) * (size_t)x->graph.nsegs + 1);
            prw_lod_select_report rep;
            prw_lod_select(&x->lod, &v, lv, &rep);
            prw_lod_mesh mesh;
            memset(&mesh, 0, sizeof mesh);
            for (int lev = 0; lev < x->lod.levels; lev++) {
                for (int p = 0; p < x->lod.npatches; p++) lv[p] = lev;
                prw_lod_segment_levels(&x->lod, lv, sl);
                for (int p = 0; p < x->lod.npatches; p++) prw_lod_emit(&x->lod, p, lev, sl, &mesh);
            }
            prw_lod_mesh_free(&mesh);
            free(lv);
            free(sl);
            prw_lod_file_destroy(x);
        }
    }
    printf("  %zu single-byte mutations (checksum recomputed): %d rejected, %d parsed and walked\n",
           2 * (n - PRW_LOD_HEADER_SIZE), rejected, parsed);
    CHECK(bad_msg == 0);
    CHECK(rejected > 0);
    free(c);
    free(full);
    prw_lod_file_destroy(b);
}

static void test_bad_header(void)
{
    uint8_t *full;
    size_t n;
    prw_baked_lod *b, *x;
    tiny_file(&full, &n, &b);
    if (!full) return;
    prw_error e;
    uint8_t *c = prw_malloc(n + 8);
    memcpy(c, full, n);
    c[0] = 'X';
    CHECK(!prw_lod_file_parse(c, n, "h.lod", &x, &e) && strstr(e.msg, "magic"));
    memcpy(c, full, n);
    c[8] = 1; /* a version-1 file (no culling data) */
    CHECK(!prw_lod_file_parse(c, n, "h.lod", &x, &e) && strstr(e.msg, "version 1"));
    memcpy(c, full, n);
    memset(c + n, 0, 8);
    CHECK(!prw_lod_file_parse(c, n + 8, "h.lod", &x, &e) && strstr(e.msg, "trailing"));
    memcpy(c, full, n);
    c[n - 1] ^= 1;
    CHECK(!prw_lod_file_parse(c, n, "h.lod", &x, &e) && strstr(e.msg, "checksum"));
    /* absurd count with a valid checksum: the node count (after key, 4 doubles, 6 ints, f64, string) */
    memcpy(c, full, n);
    size_t at = PRW_LOD_HEADER_SIZE + 32 + 4 * 8 + 6 * 4 + 8;
    uint32_t sl = (uint32_t)c[at] | (uint32_t)c[at + 1] << 8 | (uint32_t)c[at + 2] << 16 | (uint32_t)c[at + 3] << 24;
    at += 4 + sl;
    c[at] = 0xff, c[at + 1] = 0xff, c[at + 2] = 0xff, c[at + 3] = 0x0f;
    patch_header(c, n);
    CHECK(!prw_lod_file_parse(c, n, "h.lod", &x, &e) && strstr(e.msg, "node count"));
    printf("  absurd node count: %s\n", e.msg);
    CHECK(!prw_lod_file_read(prw_test_path("no-such.lod"), &x, &e) && strstr(e.msg, "no-such.lod"));
    free(c);
    free(full);
    prw_lod_file_destroy(b);
}

/* The culling section (format version 2) is validated like the rest: each mutation of patch 0's
 * record (the file's last 2 x 113 bytes; checksum recomputed) is refused with its reason. */
static void put_f64(uint8_t *d, double v)
{
    uint64_t u;
    memcpy(&u, &v, 8);
    for (int i = 0; i < 8; i++) d[i] = (uint8_t)(u >> (8 * i));
}

static void test_bad_cull(void)
{
    uint8_t *full;
    size_t n;
    prw_baked_lod *b, *x;
    tiny_file(&full, &n, &b);
    if (!full) return;
    CHECK(b->cull.npatches == 2 && b->cull.npatches == b->lod.npatches);
    size_t rec = n - proxy_bytes(b) - 2 * 113; /* patch 0: lo, hi, centre (3 x 24), radius (72), axis (80), half-angle (104), flag (112) */
    static const struct {
        size_t off;
        double v;
        const char *msg;
    } cases[] = {{0, 1e9, "inverted"}, {72, -1, "negative"}, {80, 2, "axis of length"}, {104, 4, "half-angle"},
                 {104, NAN, "half-angle"}};
    uint8_t *c = prw_malloc(n);
    prw_error e;
    for (size_t k = 0; k < PRW_ARRAY_LEN(cases); k++) {
        memcpy(c, full, n);
        put_f64(c + rec + cases[k].off, cases[k].v);
        patch_header(c, n);
        bool ok = prw_lod_file_parse(c, n, "c.lod", &x, &e);
        if (ok) prw_lod_file_destroy(x);
        CHECK(!ok && strstr(e.msg, cases[k].msg));
        printf("  culling mutation %zu: %s\n", k, ok ? "(parsed)" : e.msg);
    }
    memcpy(c, full, n);
    c[rec + 112] = 2;
    patch_header(c, n);
    CHECK(!prw_lod_file_parse(c, n, "c.lod", &x, &e) && strstr(e.msg, "single_sided"));
    memcpy(c, full, n);
    c[rec - 12] = 3; /* culling patch count 2 -> 3 */
    patch_header(c, n);
    CHECK(!prw_lod_file_parse(c, n, "c.lod", &x, &e) && strstr(e.msg, "culling"));
    printf("  culling patch count 3: %s\n", e.msg);
    free(c);
    free(full);
    prw_lod_file_destroy(b);
}

/* The proxy section (format version 3, the file's last) is validated like the rest: each mutation
 * (checksum recomputed) is refused with a message naming the problem. */
static void put_u32(uint8_t *d, uint32_t v)
{
    for (int i = 0; i < 4; i++) d[i] = (uint8_t)(v >> (8 * i));
}

static void test_bad_proxy(void)
{
    prw_nurbs_model m;
    prw_nurbs_model_init(&m);
    prw_error e;
    prw_baked_lod *b, *x;
    /* light mode: the two-patch model with the coarse options (2 proxy levels; the plate has 1 there) */
    if (light_options()) CHECK_OK(make_two(&m, &e), &e);
    else CHECK_OK(prw_procedural_plate(&m, &e), &e);
    CHECK_OK(prw_baked_lod_build(&m, light_options(), &b, NULL, NULL, &e), &e);
    prw_nurbs_model_free(&m);
    CHECK(b->have_proxy && b->proxy.nlevels >= 2);
    if (!b->have_proxy || b->proxy.nlevels < 2) {
        prw_lod_file_destroy(b);
        return;
    }
    uint8_t *full;
    size_t n;
    prw_lod_file_serialize(b, &full, &n);
    CHECK_OK(prw_lod_file_parse(full, n, "p.lod", &x, &e), &e);
    prw_lod_file_destroy(x);
    const prw_lod_proxy_level *l0 = &b->proxy.levels[0];
    size_t sec = n - proxy_bytes(b), lv0 = sec + 29, tris0 = lv0 + 28 + 24 * (size_t)l0->nverts,
           cp0 = tris0 + 12 * (size_t)l0->ntris, uv0 = cp0 + 12 * (size_t)l0->ntris, tp0 = uv0 + 48 * (size_t)l0->ntris,
           lv1 = tp0 + 4 * (size_t)l0->ntris;
    CHECK(full[sec] == 1);
    enum { U8, U32, F64 };
    const struct {
        size_t at;
        int kind;
        double v;
        const char *msg;
    } cases[] = {
        {tris0 + 4, U32, l0->nverts, "proxy triangle index"},   /* a tri index = nverts */
        {lv0 + 28 + 8, F64, NAN, "proxy vertex position"},      /* a NaN position */
        {lv1 + 24, U32, l0->ntris, "strictly decrease"},        /* level 1 not coarser than level 0 */
        {cp0 + 8, U32, b->lod.npatches, "proxy corner_patch"},  /* corner patch out of range */
        {tp0, U32, (uint32_t)-1, "proxy tri_patch"},            /* triangle patch -1 */
        {uv0 + 16, F64, INFINITY, "proxy corner uv"},
        {lv0 + 4, F64, -1, "negative err"},
        {lv0 + 4, F64, NAN, "proxy level err"},
        {sec + 1, U32, b->lod.levels, "start level"},
        {sec + 5, F64, -1e-3, "eps_start"},
        {sec + 25, U32, 1000000, "proxy level count"},          /* more levels than bytes */
        {lv0 + 20, U32, 2, "proxy vertex count"},               /* fewer than 3 vertices */
        {sec, U8, 2, "proxy flag"},
    };
    uint8_t *c = prw_malloc(n + 1);
    for (size_t k = 0; k < PRW_ARRAY_LEN(cases); k++) {
        memcpy(c, full, n);
        if (cases[k].kind == U8) c[cases[k].at] = (uint8_t)cases[k].v;
        else if (cases[k].kind == U32) put_u32(c + cases[k].at, (uint32_t)(int64_t)cases[k].v);
        else put_f64(c + cases[k].at, cases[k].v);
        patch_header(c, n);
        bool ok = prw_lod_file_parse(c, n, "p.lod", &x, &e);
        if (ok) prw_lod_file_destroy(x);
        CHECK(!ok && strncmp(e.msg, "p.lod: ", 7) == 0 && strstr(e.msg, cases[k].msg));
        printf("  proxy mutation %zu: %s\n", k, ok ? "(parsed)" : e.msg);
    }
    /* the section cut short, and a version-2 file (no proxy section) */
    memcpy(c, full, n);
    patch_header(c, n - 5);
    CHECK(!prw_lod_file_parse(c, n - 5, "p.lod", &x, &e) && strstr(e.msg, "truncated"));
    printf("  proxy section cut short: %s\n", e.msg);
    memcpy(c, full, n);
    c[8] = 2;
    CHECK(!prw_lod_file_parse(c, n, "p.lod", &x, &e) && strstr(e.msg, "version 2"));
    printf("  version 2: %s\n", e.msg);
    free(c);
    free(full);
    prw_lod_file_destroy(b);
}

static void test_bad_model(void)
{
    set_cache("cache-bad");
    prw_error e;
    prw_bake_result r;
    prw_baked_lod *b;
    const char *p = prw_test_path("broken.json");
    const char *bad = "{\"prw_nurbs\": 1, \"surfaces\": [ {\"nurbs\": 3} ]}";
    prw_test_write_file(p, bad, strlen(bad));
    CHECK(!prw_bake_run(p, NULL, false, &b, &r, NULL, NULL, &e) && strstr(e.msg, "broken.json") && b == NULL);
    printf("  malformed model: %s\n", e.msg);
    CHECK(!prw_bake_run(prw_test_path("missing.igs"), NULL, false, &b, &r, NULL, NULL, &e) && strstr(e.msg, "missing.igs"));
    CHECK(!prw_bake_run(prw_test_path("model.stl"), NULL, false, &b, &r, NULL, NULL, &e) && strstr(e.msg, "unknown model type"));
}

typedef struct lines {
    char text[8][256];
    int n;
} lines;

static void collect(void *user, const char *line)
{
    lines *l = user;
    if (l->n < 8) snprintf(l->text[l->n++], sizeof l->text[0], "%s", line);
}

static prw_scene *two_entry_scene(void)
{
    static const char *text = "{\"prw_manifest\": 1,\n"
                              " \"materials\": [{\"name\": \"m\"}],\n"
                              " \"nurbs\": [{\"name\": \"two\", \"file\": \"scene-two.json\", \"material\": \"m\",\n"
                              "             \"chord_rel\": 0.02},\n" /* coarse: cheap under ASan */
                              "            {\"name\": \"plate\", \"procedural\": \"plate\", \"material\": \"m\", \"chord_rel\": 0.02}]}\n";
    write_model("scene-two.json");
    prw_scene *s = prw_scene_create();
    prw_error e;
    if (!prw_scene_parse_manifest(s, text, strlen(text), prw_test_path("scene.json"), &e)) {
        fprintf(stderr, "manifest: %s\n", e.msg);
        prw_scene_destroy(s);
        return NULL;
    }
    return s;
}

static void test_bake_scene(void)
{
    set_cache("bake-scene");
    prw_scene *s = two_entry_scene();
    CHECK(s != NULL);
    if (!s) return;
    prw_error e;
    const prw_nurbs_model *m[2];
    const prw_baked_lod *h[2];
    CHECK(!prw_scene_nurbs_baked(s, 0, &m[0], &h[0], &e) && m[0] == NULL && h[0] == NULL &&
          strstr(e.msg, "NURBS entry 'two' has no baked hierarchy: call prw_bake_scene"));
    int builds = prw_bake_build_count();
    lines l = {.n = 0};
    CHECK_OK(prw_bake_scene(s, collect, &l, &e), &e);
    CHECK(prw_bake_build_count() == builds + 2);
    /* the file entry says its stages as they finish (seam graph first), then its total */
    CHECK(l.n >= 4 && l.n < 8 && strstr(l.text[0], "lod: two: seam graph: ") &&
          strstr(l.text[1], "lod: two: hierarchy: ") && strstr(l.text[l.n - 2], "lod: two: hierarchy built in ") &&
          strstr(l.text[l.n - 1], "lod: plate: hierarchy built in "));
    for (uint32_t i = 0; i < 2; i++) {
        CHECK_OK(prw_scene_nurbs_baked(s, i, &m[i], &h[i], &e), &e);
        CHECK(h[i]->lod.npatches == (int)m[i]->count && strlen(h[i]->key) == 32);
        /* the same hierarchy prw_bake_scene_entry gives (now from the cache) */
        prw_baked_lod *x;
        CHECK_OK(prw_bake_scene_entry(&s->nurbs[i], m[i], NULL, NULL, &x, &e), &e);
        CHECK(compare_baked(h[i], x) == 0);
        prw_lod_file_destroy(x);
    }
    /* a second call builds nothing and keeps the attachments */
    l.n = 0;
    CHECK_OK(prw_bake_scene(s, collect, &l, &e), &e);
    const prw_baked_lod *again;
    CHECK(prw_scene_nurbs_baked(s, 1, NULL, &again, &e) && again == h[1] && l.n == 0);
    /* another scene with the same entries: both from the cache */
    prw_scene *s2 = two_entry_scene();
    CHECK(s2 != NULL);
    if (s2) {
        CHECK_OK(prw_bake_scene(s2, collect, &l, &e), &e);
        CHECK(l.n == 2 && strstr(l.text[0], "lod: two: hierarchy from the cache") &&
              strstr(l.text[1], "lod: plate: hierarchy from the cache"));
        const prw_baked_lod *h2;
        CHECK(prw_scene_nurbs_baked(s2, 0, NULL, &h2, &e) && compare_baked(h[0], h2) == 0);
        /* a hierarchy of another model is refused (and freed: the scene took it) */
        prw_nurbs_model mm;
        CHECK_OK(prw_scene_nurbs_load(&s2->nurbs[0], &mm, &e), &e);
        prw_baked_lod *plate;
        CHECK_OK(prw_bake_scene_entry(&s2->nurbs[1], m[1], NULL, NULL, &plate, &e), &e);
        CHECK(!prw_scene_nurbs_attach(s2, 0, &mm, plate, &e) && strstr(e.msg, "patches"));
        CHECK(mm.count == 0);
        prw_scene_destroy(s2);
    }
    CHECK(prw_bake_build_count() == builds + 2);
    prw_scene_destroy(s);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {
        {"roundtrip_two", test_roundtrip_two},
        {"roundtrip_plate", test_roundtrip_plate},
        {"roundtrip_box", test_roundtrip_box},
        {"key", test_key},
        {"cache_hit", test_cache_hit},
        {"corrupt_flip", test_corrupt_flip},
        {"corrupt_truncated", test_corrupt_truncated},
        {"prefixes", test_prefixes},
        {"mutations", test_mutations},
        {"bad_header", test_bad_header},
        {"bad_cull", test_bad_cull},
        {"bad_proxy", test_bad_proxy},
        {"bad_model", test_bad_model},
        {"bake_scene", test_bake_scene},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
