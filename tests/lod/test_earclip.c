/* Ear clipping (lod/prw_earclip.h) and its cell grid (lod/prw_cellgrid.h).
 *  - closed forms: a square with a square hole (area 3/4, 8 triangles), a regular 1000-gon;
 *  - properties of random polygons with holes (star-shaped loops, nested islands, loops given in
 *    either orientation) and of random polyominoes with holes (collinear runs, loops touching at a
 *    corner): every triangle counter-clockwise (exact orientation), the triangles' area equals the
 *    even-odd area of the loops to 1e-12 relative, no input vertex strictly inside a triangle
 *    (brute force), and the triangles tile the region (each boundary edge used once in the
 *    region's direction, each other edge twice in opposite directions: with every triangle
 *    positive this means every point of the region is covered exactly once);
 *  - the cover of prw_cellgrid: the cell of every point in a random triangle or segment (vertices,
 *    exact edge points, interior points; offset and flat boxes) is listed;
 *  - big loops (60k points: a thin band like a long trimmed face's boundary strip, and a star)
 *    checked the same way, except the brute-force vertex test; their CPU time is printed, not
 *    asserted. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "prw_cellgrid.h"
#include "prw_earclip.h"
#include "prw_math.h"
#include "prw_predicates.h"
#include "prw_test.h"

/* ---- a polygon set under construction ---- */
typedef struct poly {
    double *xy;
    int *idx, *start;
    int *depth; /* per loop: nesting depth as generated (even: outer boundary) */
    int np, nl, capp, capl;
} poly;

static void poly_free(poly *p)
{
    free(p->xy);
    free(p->idx);
    free(p->start);
    free(p->depth);
    memset(p, 0, sizeof *p);
}

static int poly_pt(poly *p, double x, double y)
{
    if (p->np == p->capp) {
        p->capp = p->capp ? 2 * p->capp : 256;
        p->xy = realloc(p->xy, sizeof(double) * 2 * (size_t)p->capp);
        p->idx = realloc(p->idx, sizeof(int) * (size_t)p->capp);
    }
    p->xy[2 * p->np] = x;
    p->xy[2 * p->np + 1] = y;
    p->idx[p->np] = p->np;
    return p->np++;
}

/* Closes the loop made of the points added since the last call. */
static void poly_close(poly *p, int depth)
{
    if (p->nl + 2 > p->capl) {
        p->capl = p->capl ? 2 * p->capl : 16;
        p->start = realloc(p->start, sizeof(int) * (size_t)(p->capl + 1));
        p->depth = realloc(p->depth, sizeof(int) * (size_t)p->capl);
    }
    if (p->nl == 0) p->start[0] = 0;
    p->depth[p->nl] = depth;
    p->start[++p->nl] = p->np;
}

/* Reverses loop l in place (its points keep their indices). */
static void poly_reverse(poly *p, int l)
{
    for (int i = p->start[l], j = p->start[l + 1] - 1; i < j; i++, j--) {
        int t = p->idx[i];
        p->idx[i] = p->idx[j];
        p->idx[j] = t;
    }
}

/* Areas are summed in long double: sliver triangles far from the origin lose ~1e-12 of a 60k-point
 * band's area in double. */
static long double tri_area2(const double *a, const double *b, const double *c)
{
    long double ax = a[0], ay = a[1];
    return ((long double)b[0] - ax) * ((long double)c[1] - ay) - ((long double)b[1] - ay) * ((long double)c[0] - ax);
}

static double loop_area2(const poly *p, int l)
{
    long double s = 0;
    const double *o = p->xy + 2 * p->idx[p->start[l]];
    for (int i = p->start[l]; i < p->start[l + 1]; i++) {
        int j = i + 1 < p->start[l + 1] ? i + 1 : p->start[l];
        s += tri_area2(o, p->xy + 2 * p->idx[i], p->xy + 2 * p->idx[j]);
    }
    return (double)s;
}

/* The region's area: outer loops count, holes subtract (depth parity). */
static double region_area(const poly *p)
{
    double s = 0;
    for (int l = 0; l < p->nl; l++) s += (p->depth[l] % 2 ? -0.5 : 0.5) * fabs(loop_area2(p, l));
    return s;
}

static uint64_t rng_state;
static void rng_seed(uint64_t s) { rng_state = 0x2545F4914F6CDD1DULL ^ s; }
static double rnd(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

/* A star-shaped loop around (cx, cy): n sorted random angles, radii in [r0, r1]. */
static void star_loop(poly *p, double cx, double cy, double r0, double r1, int n, int depth)
{
    double *ang = malloc(sizeof(double) * (size_t)n);
    for (int i = 0; i < n; i++) ang[i] = 2 * PRW_PI * (i + 0.1 + 0.8 * rnd()) / n;
    for (int i = 0; i < n; i++) {
        double r = r0 + (r1 - r0) * rnd();
        poly_pt(p, cx + r * cos(ang[i]), cy + r * sin(ang[i]));
    }
    free(ang);
    poly_close(p, depth);
}

/* ---- checks ---- */
typedef struct dedge {
    int a, b;
} dedge;

static int cmp_dedge(const void *x, const void *y)
{
    const dedge *p = x, *q = y;
    if (p->a != q->a) return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

static bool has_edge(const dedge *v, int n, int a, int b)
{
    dedge k = {a, b};
    return bsearch(&k, v, (size_t)n, sizeof k, cmp_dedge) != NULL;
}

typedef struct keyed {
    double x, y;
    int i;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *p = a, *q = b;
    if (p->x != q->x) return p->x < q->x ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return (p->i > q->i) - (p->i < q->i);
}

/* Per point: the smallest index of a point at the same position. */
static int *canonical(const poly *p)
{
    keyed *k = malloc(sizeof(keyed) * (size_t)(p->np + 1));
    for (int i = 0; i < p->np; i++) k[i] = (keyed){p->xy[2 * i], p->xy[2 * i + 1], i};
    qsort(k, (size_t)p->np, sizeof *k, cmp_keyed);
    int *c = malloc(sizeof(int) * (size_t)(p->np + 1));
    for (int i = 0, first = 0; i < p->np; i++) {
        if (i == 0 || k[i].x != k[i - 1].x || k[i].y != k[i - 1].y) first = k[i].i;
        c[k[i].i] = first;
    }
    free(k);
    return c;
}

/* Checks the triangulation of p; returns the number of problems (also CHECKed). */
static int check_tris(const poly *p, const int *tris, int nt, const prw_earclip_stats *st, bool brute, const char *what)
{
    int bad_orient = 0, bad_inside = 0, bad_edges = 0;
    long double area2 = 0;
    for (int k = 0; k < nt; k++) {
        const double *a = p->xy + 2 * tris[3 * k], *b = p->xy + 2 * tris[3 * k + 1], *c = p->xy + 2 * tris[3 * k + 2];
        if (prw_orient2d(a, b, c) <= 0) bad_orient++;
        area2 += tri_area2(a, b, c);
        if (!brute) continue;
        for (int i = 0; i < p->np; i++) {
            const double *q = p->xy + 2 * i;
            if (prw_orient2d(a, b, q) > 0 && prw_orient2d(b, c, q) > 0 && prw_orient2d(c, a, q) > 0) bad_inside++;
        }
    }
    /* tiling: directed edges of the triangles against the region's boundary edges, by position
     * (loops touching at a corner have a point each there) */
    int *canon = canonical(p);
    dedge *te = malloc(sizeof(dedge) * (size_t)(3 * nt + 1));
    for (int k = 0; k < nt; k++)
        for (int q = 0; q < 3; q++) te[3 * k + q] = (dedge){canon[tris[3 * k + q]], canon[tris[3 * k + (q + 1) % 3]]};
    qsort(te, (size_t)(3 * nt), sizeof *te, cmp_dedge);
    for (int i = 1; i < 3 * nt; i++) bad_edges += te[i].a == te[i - 1].a && te[i].b == te[i - 1].b; /* used twice */
    dedge *be = malloc(sizeof(dedge) * (size_t)(p->np + 1));
    int nb = 0;
    for (int l = 0; l < p->nl; l++) {
        bool ccw = loop_area2(p, l) > 0, want_ccw = p->depth[l] % 2 == 0; /* region on the left */
        for (int i = p->start[l]; i < p->start[l + 1]; i++) {
            int j = i + 1 < p->start[l + 1] ? i + 1 : p->start[l];
            int a = canon[p->idx[i]], b = canon[p->idx[j]];
            be[nb++] = ccw == want_ccw ? (dedge){a, b} : (dedge){b, a};
        }
    }
    qsort(be, (size_t)nb, sizeof *be, cmp_dedge);
    for (int i = 0; i < nb; i++) /* each boundary edge once, in the region's direction */
        bad_edges += !has_edge(te, 3 * nt, be[i].a, be[i].b) || has_edge(te, 3 * nt, be[i].b, be[i].a);
    for (int i = 0; i < 3 * nt; i++) /* every other edge has its twin */
        if (!has_edge(be, nb, te[i].a, te[i].b) && !has_edge(te, 3 * nt, te[i].b, te[i].a)) bad_edges++;
    free(te);
    free(be);
    free(canon);
    double want = region_area(p), area = (double)(area2 / 2);
    int bad = bad_orient + bad_inside + bad_edges + (st->leftover != 0) + !(fabs(area - want) <= 1e-12 * fabs(want));
    CHECK_MSG(bad == 0,
              "%s: %d points %d loops -> %d triangles: %d not CCW, %d vertices inside, %d edge faults, leftover %d, "
              "area %.17g vs %.17g",
              what, p->np, p->nl, nt, bad_orient, bad_inside, bad_edges, st->leftover, area, want);
    return bad;
}

static double cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int run(const poly *p, bool brute, const char *what, int *ntris, double *cpu)
{
    int *tris = NULL, nt = 0;
    prw_earclip_stats st;
    prw_error e = {0};
    double t0 = cpu_seconds();
    bool ok = prw_earclip(p->xy, p->idx, p->start, p->nl, &tris, &nt, &st, &e);
    if (cpu) *cpu = cpu_seconds() - t0;
    CHECK_MSG(ok, "%s: %s", what, e.msg);
    if (!ok) return 1;
    int bad = check_tris(p, tris, nt, &st, brute, what);
    CHECK_MSG(st.forced == 0, "%s: %d forced ears", what, st.forced);
    if (ntris) *ntris = nt;
    free(tris);
    return bad + st.forced;
}

/* ---- closed forms ---- */
static void test_square_hole(void)
{
    poly p = {0};
    const double o[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, h[4][2] = {{0.25, 0.25}, {0.75, 0.25}, {0.75, 0.75}, {0.25, 0.75}};
    for (int i = 0; i < 4; i++) poly_pt(&p, o[i][0], o[i][1]);
    poly_close(&p, 0);
    for (int i = 0; i < 4; i++) poly_pt(&p, h[i][0], h[i][1]); /* given CCW: the reader must flip it */
    poly_close(&p, 1);
    int nt = 0;
    run(&p, true, "square with a hole", &nt, NULL);
    CHECK_MSG(nt == 8, "%d triangles (n + 2 holes - 2 = 8)", nt);
    CHECK_NEAR(region_area(&p), 0.75, 1e-15);
    poly_free(&p);
}

static void test_regular_polygon(void)
{
    poly p = {0};
    const int n = 1000;
    for (int i = 0; i < n; i++) poly_pt(&p, cos(2 * PRW_PI * i / n), -sin(2 * PRW_PI * i / n)); /* clockwise */
    poly_close(&p, 0);
    int *tris = NULL, nt = 0;
    prw_earclip_stats st;
    prw_error e = {0};
    CHECK_OK(prw_earclip(p.xy, p.idx, p.start, p.nl, &tris, &nt, &st, &e), &e);
    double area = 0;
    for (int k = 0; k < nt; k++) {
        const double *a = p.xy + 2 * tris[3 * k], *b = p.xy + 2 * tris[3 * k + 1], *c = p.xy + 2 * tris[3 * k + 2];
        area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    CHECK(nt == n - 2);
    CHECK_NEAR(area, 0.5 * n * sin(2 * PRW_PI / n), 1e-12);
    check_tris(&p, tris, nt, &st, true, "regular 1000-gon");
    free(tris);
    poly_free(&p);
}

/* ---- random polygons ---- */
/* A star outer loop, k star holes on a ring inside it, some holes with an island; random
 * orientation per loop. */
static void test_random_stars(void)
{
    int trials = prw_test_scale(300, 10), bad = 0;
    rng_seed(1);
    for (int t = 0; t < trials; t++) {
        poly p = {0};
        /* radii 0.8..1 with angular gaps < 1.8 x 2 pi / n: the outer loop holds the disk of radius
         * 0.8 cos(0.9 x 2 pi / n), more than 0.75 (where holes end) from n = 24 on */
        int k = (int)(rnd() * 7);
        int n = (k ? 24 : 3) + (int)(rnd() * (t % 3 == 0 ? 400 : 40));
        star_loop(&p, 0, 0, 0.8, 1.0, n, 0);
        for (int h = 0; h < k; h++) {
            double a = 2 * PRW_PI * (h + 0.5) / k, r = 0.5;
            double rr = fmin(0.25, 0.7 * r * sin(PRW_PI / (k > 1 ? k : 2))); /* no hole meets another or the outer loop */
            int nh = 3 + (int)(rnd() * 30);
            star_loop(&p, r * cos(a), r * sin(a), 0.6 * rr, rr, nh, 1);
            double inner = 0.6 * rr * cos(0.9 * 2 * PRW_PI / nh); /* the hole holds this disk */
            if (nh >= 8 && rnd() < 0.5)
                star_loop(&p, r * cos(a), r * sin(a), 0.4 * inner, 0.9 * inner, 3 + (int)(rnd() * 10), 2);
        }
        for (int l = 0; l < p.nl; l++)
            if (rnd() < 0.5) poly_reverse(&p, l);
        char what[64];
        snprintf(what, sizeof what, "star trial %d", t);
        bad += run(&p, true, what, NULL, NULL) != 0;
        poly_free(&p);
    }
    printf("random stars: %d trials, %d bad\n", trials, bad);
}

/* The boundary of a random set of grid cells: unit edges (collinear runs), loops that touch at a
 * corner where two cells meet diagonally, holes. */
static void polyomino(poly *p, int w, int h, double fill)
{
    unsigned char *full = calloc((size_t)(w + 2) * (size_t)(h + 2), 1);
#define FULL(i, j) full[(size_t)((j) + 1) * (size_t)(w + 2) + (size_t)((i) + 1)]
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) FULL(i, j) = rnd() < fill;
    /* directed boundary edges with the full cell on the left; a vertex can have two out-edges
     * (diagonal contact): take the one turning left first, so loops touch instead of crossing */
    int nv = (w + 1) * (h + 1);
    int (*out)[2] = malloc(sizeof(int[2]) * (size_t)nv);
    for (int v = 0; v < nv; v++) out[v][0] = out[v][1] = -1;
#define VI(i, j) ((j) * (w + 1) + (i))
#define ADD(v, to) (out[v][out[v][0] < 0 ? 0 : 1] = (to))
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            if (!FULL(i, j)) continue;
            if (!FULL(i, j - 1)) ADD(VI(i, j), VI(i + 1, j));
            if (!FULL(i + 1, j)) ADD(VI(i + 1, j), VI(i + 1, j + 1));
            if (!FULL(i, j + 1)) ADD(VI(i + 1, j + 1), VI(i, j + 1));
            if (!FULL(i - 1, j)) ADD(VI(i, j + 1), VI(i, j));
        }
    for (int v = 0; v < nv; v++) {
        while (out[v][0] >= 0) {
            int w0 = v, prev = -1;
            do {
                int s = 0;
                if (out[w0][1] >= 0 && prev >= 0) {
                    /* two ways out: the left turn relative to the incoming direction */
                    double in[2] = {(w0 % (w + 1)) - (prev % (w + 1)), (w0 / (w + 1)) - (prev / (w + 1))};
                    int t0 = out[w0][0];
                    double d0[2] = {(t0 % (w + 1)) - (w0 % (w + 1)), (t0 / (w + 1)) - (w0 / (w + 1))};
                    s = in[0] * d0[1] - in[1] * d0[0] > 0 ? 0 : 1;
                } else if (out[w0][0] < 0) {
                    s = 1;
                }
                int nx = out[w0][s];
                out[w0][s] = -1;
                if (s == 0 && out[w0][1] >= 0) out[w0][0] = out[w0][1], out[w0][1] = -1;
                poly_pt(p, w0 % (w + 1), w0 / (w + 1));
                prev = w0;
                w0 = nx;
            } while (w0 != v);
            poly_close(p, 0); /* depth fixed below */
        }
    }
    /* depth: loops traced with the full cells on the left are outer (CCW) or holes (CW) */
    for (int l = 0; l < p->nl; l++) p->depth[l] = loop_area2(p, l) > 0 ? 0 : 1;
    free(out);
    free(full);
#undef FULL
#undef VI
#undef ADD
}

static double cells_area(const poly *p)
{
    double s = 0;
    for (int l = 0; l < p->nl; l++) s += 0.5 * loop_area2(p, l);
    return s;
}

static void test_random_polyominoes(void)
{
    int trials = prw_test_scale(200, 10), bad = 0, tried = 0;
    rng_seed(2);
    for (int t = 0; t < trials; t++) {
        poly p = {0};
        int w = 2 + (int)(rnd() * 14), h = 2 + (int)(rnd() * 14);
        polyomino(&p, w, h, 0.3 + 0.6 * rnd());
        if (p.nl == 0) {
            poly_free(&p);
            continue;
        }
        /* the even-odd area of the traced loops is the cell count (loops drawn CCW / CW) */
        double cells = cells_area(&p);
        CHECK_NEAR(region_area(&p), cells, 1e-9);
        for (int l = 0; l < p.nl; l++)
            if (rnd() < 0.5) poly_reverse(&p, l);
        char what[64];
        snprintf(what, sizeof what, "polyomino trial %d (%dx%d)", t, w, h);
        bad += run(&p, true, what, NULL, NULL) != 0;
        tried++;
        poly_free(&p);
    }
    printf("random polyominoes: %d trials, %d bad\n", tried, bad);
}

/* ---- the index changes no answer ---- */
/* lod/prw_earclip.c built with PRW_EARCLIP_SCAN_ALL (tests/lod/CMakeLists.txt) */
bool prw_earclip_scan_all(const double *xy, const int *idx, const int *start, int nloops, int **tris, int *ntris,
                          prw_earclip_stats *st, prw_error *e);

typedef struct angled {
    double ang, r;
    int x, y;
} angled;

static int cmp_angled(const void *a, const void *b)
{
    const angled *p = a, *q = b;
    if (p->ang != q->ang) return p->ang < q->ang ? -1 : 1;
    return (p->r > q->r) - (p->r < q->r);
}

/* A simple polygon through random lattice points (many collinear, vertices on would-be ear
 * diagonals): the points in angular order around a centre no lattice line passes through, kept
 * when no angular gap reaches pi (then the polygon is star-shaped from the centre).  false when
 * the draw failed. */
static bool lattice_star(poly *p, int side, int n)
{
    angled *v = malloc(sizeof(angled) * (size_t)n);
    double cx = 0.5 * side + 0.1234567, cy = 0.5 * side + 0.0567891;
    for (int i = 0; i < n; i++) {
        v[i].x = (int)(rnd() * (side + 1));
        v[i].y = (int)(rnd() * (side + 1));
        v[i].ang = atan2(v[i].y - cy, v[i].x - cx);
        v[i].r = hypot(v[i].x - cx, v[i].y - cy);
    }
    qsort(v, (size_t)n, sizeof *v, cmp_angled);
    bool ok = n >= 3;
    for (int i = 0; i < n && ok; i++) {
        double gap = (i + 1 < n ? v[i + 1].ang : v[0].ang + 2 * PRW_PI) - v[i].ang;
        if (gap >= 0.9 * PRW_PI || (i + 1 < n && v[i + 1].x == v[i].x && v[i + 1].y == v[i].y)) ok = false;
    }
    if (ok) {
        for (int i = 0; i < n; i++) poly_pt(p, v[i].x, v[i].y);
        poly_close(p, 0);
    }
    free(v);
    return ok;
}

/* Random loops of points on a small integer lattice (duplicates, collinear runs, spikes, vertices
 * on edges, crossings), simple lattice polygons, random polyominoes and stars with holes: the indexed clipper gives the
 * same triangles, in the same order, and the same counts as the one testing every ear against the
 * whole ring. */
static void test_same_as_full_scan(void)
{
    int trials = prw_test_scale(3000, 10), differ = 0, dirty_inputs = 0;
    rng_seed(5);
    for (int t = 0; t < trials; t++) {
        poly p = {0};
        int kind = t % 4;
        if (kind == 0 || kind == 1) { /* lattice loops */
            int nl = 1 + (int)(rnd() * 3), side = kind == 0 ? 4 : 12;
            for (int l = 0; l < nl; l++) {
                int n = 3 + (int)(rnd() * (kind == 0 ? 8 : 40));
                for (int i = 0; i < n; i++) poly_pt(&p, (int)(rnd() * side), (int)(rnd() * side));
                poly_close(&p, l ? 1 : 0);
            }
            dirty_inputs++;
        } else if (kind == 2) {
            polyomino(&p, 2 + (int)(rnd() * 10), 2 + (int)(rnd() * 10), 0.3 + 0.6 * rnd());
            if (p.nl == 0) {
                poly_free(&p);
                continue;
            }
        } else if (t % 8 == 3) {
            star_loop(&p, 0, 0, 0.8, 1.0, 24 + (int)(rnd() * 100), 0);
            for (int h = 0; h < 3; h++) star_loop(&p, 0.5 * cos(2.1 * h), 0.5 * sin(2.1 * h), 0.1, 0.2, 3 + (int)(rnd() * 20), 1);
        } else if (!lattice_star(&p, 6 + (int)(rnd() * 10), 8 + (int)(rnd() * 40))) {
            poly_free(&p);
            continue;
        }
        int *ta = NULL, *tb = NULL, na = 0, nb = 0;
        prw_earclip_stats sa, sb;
        prw_error e = {0};
        bool oka = prw_earclip(p.xy, p.idx, p.start, p.nl, &ta, &na, &sa, &e);
        bool okb = prw_earclip_scan_all(p.xy, p.idx, p.start, p.nl, &tb, &nb, &sb, &e);
        bool same_out = oka == okb && na == nb && sa.forced == sb.forced && sa.leftover == sb.leftover &&
                        (na == 0 || memcmp(ta, tb, sizeof(int) * 3 * (size_t)na) == 0);
        if (!same_out && differ++ < 5)
            fprintf(stderr, "trial %d (kind %d, %d points, %d loops): %d vs %d triangles, forced %d vs %d, leftover %d vs %d\n",
                    t, kind, p.np, p.nl, na, nb, sa.forced, sb.forced, sa.leftover, sb.leftover);
        free(ta);
        free(tb);
        poly_free(&p);
    }
    printf("same as the full scan: %d trials (%d on lattice points), %d differ\n", trials, dirty_inputs, differ);
    CHECK(differ == 0);
}

/* ---- prw_orient2d on axis-parallel lines (its zero-factor shortcut) ---- */
static int sgn(double x) { return (x > 0) - (x < 0); }

static void test_orient_axis_lines(void)
{
    int bad = 0;
    rng_seed(6);
    for (int t = 0; t < 20000; t++) {
        int axis = t % 2; /* the line x = X (axis 0) or y = Y */
        double X = (rnd() - 0.5) * pow(10, (int)(rnd() * 12) - 6), d = (rnd() < 0.5 ? 1 : -1);
        double a[2], b[2], c[2];
        a[axis] = b[axis] = c[axis] = X;
        a[1 - axis] = rnd() - 0.5, b[1 - axis] = rnd() - 0.5, c[1 - axis] = rnd() - 0.5;
        bad += prw_orient2d(a, b, c) != 0; /* on the line */
        /* c one ulp off it: det = delta (a1 - b1) exactly (axis 0), -delta (a0 - b0) (axis 1) */
        c[axis] = nextafter(X, d * INFINITY);
        double delta = c[axis] - X;
        int want = axis == 0 ? sgn(delta) * sgn(a[1] - b[1]) : -sgn(delta) * sgn(a[0] - b[0]);
        bad += prw_orient2d(a, b, c) != want;
        /* a and c share the line's coordinate, b does not: det = -(a1 - c1)(b0 - c0) (axis 0) */
        c[axis] = X;
        b[axis] = X + (rnd() < 0.5 ? 1 : -1) * (1 + rnd());
        want = axis == 0 ? -sgn(a[1] - c[1]) * sgn(b[0] - c[0]) : sgn(a[0] - c[0]) * sgn(b[1] - c[1]);
        bad += prw_orient2d(a, b, c) != want;
    }
    CHECK_MSG(bad == 0, "%d wrong orientations", bad);
}

/* ---- the cell grid's cover ---- */
static bool listed(const int *cells, int n, int c)
{
    for (int i = 0; i < n; i++)
        if (cells[i] == c) return true;
    return false;
}

static void test_cellgrid_cover(void)
{
    int trials = prw_test_scale(2000, 10), missed = 0, repeated = 0, checked = 0, bad_size = 0;
    rng_seed(3);
    int *cells = NULL, cap = 0;
    for (int t = 0; t < trials; t++) {
        /* boxes: unit, offset far from the origin, flat (zero height) */
        double off = t % 3 == 1 ? 1e6 : 0, sc = t % 3 == 1 ? 1e-3 : 1;
        double lo[2] = {off, off}, hi[2] = {off + sc, off + (t % 3 == 2 ? 0 : sc * (0.1 + 3 * rnd()))};
        prw_cellgrid g;
        int target = 1 + (int)(rnd() * 400);
        prw_cellgrid_init(&g, lo, hi, target);
        bad_size += !(g.nx >= 1 && g.ny >= 1 && g.nx * g.ny <= target + g.nx / 2);
        int k = 1 + t % 3;
        double v[6];
        for (int i = 0; i < k; i++) {
            v[2 * i] = lo[0] + (hi[0] - lo[0]) * rnd();
            v[2 * i + 1] = lo[1] + (hi[1] - lo[1]) * rnd();
        }
        int n = prw_cellgrid_cover(&g, v, k, &cells, &cap);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < i; j++) repeated += cells[i] == cells[j];
        /* points: the vertices, and points exactly on or in the shape (checked exactly) */
        for (int s = 0; s < 200; s++) {
            double q[2];
            if (s < k) {
                q[0] = v[2 * s], q[1] = v[2 * s + 1];
            } else {
                double l0 = rnd(), l1 = rnd() * (1 - l0), l2 = 1 - l0 - l1;
                if (k == 1) l0 = 1, l1 = l2 = 0;
                if (k == 2) l1 += l2, l2 = 0;
                const double *A = v, *B = v + 2 * (k > 1), *C = v + 2 * (k > 2 ? 2 : k > 1);
                q[0] = l0 * A[0] + l1 * B[0] + l2 * C[0];
                q[1] = l0 * A[1] + l1 * B[1] + l2 * C[1];
                bool in;
                if (k == 3) {
                    int o = prw_orient2d(A, B, C) >= 0 ? 1 : -1;
                    in = o * prw_orient2d(A, B, q) >= 0 && o * prw_orient2d(B, C, q) >= 0 && o * prw_orient2d(C, A, q) >= 0;
                } else {
                    in = prw_orient2d(A, B, q) == 0 && q[0] >= fmin(A[0], B[0]) && q[0] <= fmax(A[0], B[0]) &&
                         q[1] >= fmin(A[1], B[1]) && q[1] <= fmax(A[1], B[1]);
                }
                if (!in) continue; /* rounded off the shape */
            }
            checked++;
            missed += !listed(cells, n, prw_cellgrid_cell(&g, q));
        }
    }
    free(cells);
    printf("cell cover: %d shapes, %d points checked, %d missed, %d repeated cells\n", trials, checked, missed, repeated);
    CHECK(missed == 0);
    CHECK(repeated == 0);
    CHECK(bad_size == 0);
    CHECK(checked > trials);
}

/* ---- big loops ---- */
/* A band like a long trimmed face's boundary strip: a w x h rectangle with n/2 points on each
 * long side, around a staircase hole of full cells. */
static void band(poly *p, int n)
{
    const double w = 3.14159, h = 49.3;
    int m = n / 2, cells = 240;
    poly_pt(p, 0, 0);
    for (int i = 0; i < m; i++) poly_pt(p, w, h * i / (m - 1));
    for (int i = m - 1; i >= 1; i--) poly_pt(p, 0, h * i / (m - 1));
    poly_close(p, 0);
    /* staircase hole: cells of size h / cells, x in [w/8, 7w/8] wobbling */
    double c = h / cells;
    for (int j = 1; j < cells - 1; j++) poly_pt(p, w / 8 + 0.1 * (j % 3), j * c), poly_pt(p, w / 8 + 0.1 * (j % 3), (j + 1) * c);
    for (int j = cells - 2; j >= 1; j--) poly_pt(p, 7 * w / 8 - 0.1 * (j % 2), (j + 1) * c), poly_pt(p, 7 * w / 8 - 0.1 * (j % 2), j * c);
    poly_close(p, 1);
}

static void test_big_loops(void)
{
    const int n = 60000;
    poly p = {0};
    rng_seed(4);
    band(&p, n);
    int nt = 0;
    double cpu = 0;
    run(&p, false, "band", &nt, &cpu);
    printf("benchmark: band of %d points (%d loops) -> %d triangles in %.3f CPU s\n", p.np, p.nl, nt, cpu);
    poly_free(&p);
    /* a smooth curve (a trim loop): r = 0.75 + 0.2 sin 7t + 0.03 sin 40t */
    for (int i = 0; i < n; i++) {
        double t = 2 * PRW_PI * i / n, r = 0.75 + 0.2 * sin(7 * t) + 0.03 * sin(40 * t);
        poly_pt(&p, r * cos(t), r * sin(t));
    }
    poly_close(&p, 0);
    run(&p, false, "flower", &nt, &cpu);
    printf("benchmark: smooth loop of %d points -> %d triangles in %.3f CPU s\n", p.np, nt, cpu);
    poly_free(&p);
    /* a stress case: every edge a spike (radii random in [0.5, 1]) */
    star_loop(&p, 0, 0, 0.5, 1.0, n, 0);
    run(&p, false, "star", &nt, &cpu);
    printf("benchmark: spiky star of %d points -> %d triangles in %.3f CPU s\n", p.np, nt, cpu);
    poly_free(&p);
}

int main(int argc, char **argv)
{
    const prw_test_case cases[] = {
        {"square_hole", test_square_hole},
        {"regular_polygon", test_regular_polygon},
        {"orient_axis_lines", test_orient_axis_lines},
        {"cellgrid_cover", test_cellgrid_cover},
        {"random_stars", test_random_stars},
        {"random_polyominoes", test_random_polyominoes},
        {"same_as_full_scan", test_same_as_full_scan},
        {"big_loops", test_big_loops},
    };
    return prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
}
