/* rect_quad_study — how accurate the rasterizer's rect-light specular quadrature is (shaders/lights.glsl,
 * rect_specular_single), in double precision against a converged quadrature.  A study, not a test: it
 * re-states the shader's two node rules in C (the GLSL is not compiled here), so it answers "which rule
 * and how many nodes", not "is the shader right" (test_raster_vs_ref checks the shader end to end);
 * it evaluates each node's tan directly in double, not the shader's float tangent recurrence.  It also
 * prints the error of the linearly transformed cosines (shaders/ltc.glsl) through their float C twin
 * (materials/prw_ltc.c, the table materials/prw_ltc_table.h), with F = 1 (the table's albedo times the
 * LTC's integral over the rectangle).
 *
 *   cc -O2 -std=c17 -Imaterials materials/tools/rect_quad_study.c materials/prw_ltc.c -lm -o rect_quad_study
 *   ./rect_quad_study [M] [k] [--mapped-only]    (default M 10, k 3; ~20 s)
 *
 * Integrand on the light (radiance 1): D(n.h) V(n.v, n.l) (n.l) cos_light / d^2, GGX with the
 * height-correlated Smith V, as prw_brdf.h.  Random configurations: light half sizes 0.1-1.5 m,
 * receiver 0.3-5.3 m away in front of it, random normal (mostly facing the light) and view, perceptual
 * roughness uniform in [sqrt(0.002), 1].  Error: |I - I_ref| / (I_ref + 0.02) (0.02: a hundredth of a
 * typical albedo, so configurations whose value is negligible do not dominate).
 *  - old rule: midpoint grid, cells of at most alpha / 2 seen from the receiver, at most 32 x 32;
 *  - new rule: the old grid while it has at most M cells per axis, else M x M nodes mapped per axis by
 *    x = x* + s tan(t) (x* the mirror ray's hit on the light's plane, s = k alpha times its length),
 *    the old grid when the mirror ray misses the plane;
 *  - reference: midpoint grid of cells alpha / 64, at most 3000 x 3000. */
#define _DEFAULT_SOURCE
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_ltc.h"

typedef struct {
    double x, y, z;
} v3;

static v3 mk(double x, double y, double z) { return (v3){x, y, z}; }
static v3 add(v3 a, v3 b) { return mk(a.x + b.x, a.y + b.y, a.z + b.z); }
static v3 sub(v3 a, v3 b) { return mk(a.x - b.x, a.y - b.y, a.z - b.z); }
static v3 scl(v3 a, double s) { return mk(a.x * s, a.y * s, a.z * s); }
static double dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double len(v3 a) { return sqrt(dot(a, a)); }
static v3 unit(v3 a) { return scl(a, 1.0 / len(a)); }

static unsigned long long rng = 88172645463325252ull;
static double rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static v3 rnd_dir(void)
{
    for (;;) {
        v3 d = mk(2 * rnd() - 1, 2 * rnd() - 1, 2 * rnd() - 1);
        double l = dot(d, d);
        if (l > 1e-4 && l < 1) return scl(d, 1 / sqrt(l));
    }
}

typedef struct {
    v3 p, n, v, c, du, dv, ln; /* receiver, normal, towards the eye; light centre, half axes, emitting +ln */
    double a;                  /* GGX alpha */
    double r;                  /* perceptual roughness */
} config;

static double ltc_rule(const config *g)
{
    float p[3] = {(float)g->p.x, (float)g->p.y, (float)g->p.z}, n[3] = {(float)g->n.x, (float)g->n.y, (float)g->n.z};
    float v[3] = {(float)g->v.x, (float)g->v.y, (float)g->v.z}, c[3] = {(float)g->c.x, (float)g->c.y, (float)g->c.z};
    float du[3] = {(float)g->du.x, (float)g->du.y, (float)g->du.z}, dv[3] = {(float)g->dv.x, (float)g->dv.y, (float)g->dv.z};
    float f[4];
    return prw_ltc_rect_ggx(p, n, v, c, du, dv, (float)g->r, f);
}

static double integrand(const config *g, v3 x)
{
    v3 d = sub(x, g->p);
    double d2 = dot(d, d);
    v3 l = scl(d, 1 / sqrt(d2));
    double NoL = dot(g->n, l), cl = -dot(l, g->ln), NoV = dot(g->n, g->v);
    if (NoL <= 0 || cl <= 0) return 0;
    double NoH = dot(g->n, unit(add(g->v, l))), a2 = g->a * g->a;
    double dd = NoH * NoH * (a2 - 1) + 1;
    double D = a2 / (M_PI * dd * dd);
    double gv = NoL * sqrt(NoV * NoV * (1 - a2) + a2), gl = NoV * sqrt(NoL * NoL * (1 - a2) + a2);
    return D * (0.5 / (gv + gl)) * NoL * cl / d2;
}

static void grid(const config *g, double f, int cap, int *nu, int *nv)
{
    double cell = f * g->a * fmax(len(sub(g->c, g->p)), 1e-4);
    *nu = (int)fmin(fmax(ceil(2 * len(g->du) / cell), 1), cap);
    *nv = (int)fmin(fmax(ceil(2 * len(g->dv) / cell), 1), cap);
}

static double uniform_rule(const config *g, int nu, int nv)
{
    double s = 0;
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            double su = 2 * (i + 0.5) / nu - 1, sv = 2 * (j + 0.5) / nv - 1;
            s += integrand(g, add(g->c, add(scl(g->du, su), scl(g->dv, sv))));
        }
    return s * 4 * len(g->du) * len(g->dv) / (nu * nv);
}

/* The new rule; *cells receives the node count. */
static double new_rule(const config *g, int M, double k, int *cells)
{
    int nu, nv;
    grid(g, 0.5, 32, &nu, &nv);
    v3 r = sub(scl(g->n, 2 * dot(g->n, g->v)), g->v);
    double rl = dot(r, g->ln), tr = dot(sub(g->c, g->p), g->ln) / rl;
    if ((nu <= M && nv <= M) || !(rl < 0 && tr > 0)) {
        *cells = nu * nv;
        return uniform_rule(g, nu, nv);
    }
    double lu = len(g->du), lv = len(g->dv);
    v3 eu = scl(g->du, 1 / lu), ev = scl(g->dv, 1 / lv), hit = sub(add(g->p, scl(r, tr)), g->c);
    double xu = dot(hit, eu), xv = dot(hit, ev), s = k * g->a * tr;
    double a0 = atan((-lu - xu) / s), a1 = atan((lu - xu) / s), b0 = atan((-lv - xv) / s), b1 = atan((lv - xv) / s);
    double sum = 0;
    for (int j = 0; j < M; j++) {
        double tv = b0 + (b1 - b0) * (j + 0.5) / M, cv = cos(tv);
        double y = xv + s * tan(tv), wy = s / (cv * cv) * (b1 - b0) / M;
        for (int i = 0; i < M; i++) {
            double tu = a0 + (a1 - a0) * (i + 0.5) / M, cu = cos(tu);
            double x = xu + s * tan(tu), wx = s / (cu * cu) * (a1 - a0) / M;
            sum += integrand(g, add(g->c, add(scl(eu, x), scl(ev, y)))) * wx * wy;
        }
    }
    *cells = M * M;
    return sum;
}

static int cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

int main(int argc, char **argv)
{
    int M = 10, pos = 0;
    double k = 3.0;
    int mapped_only = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--mapped-only") == 0) mapped_only = 1;
        else if (pos++ == 0) M = atoi(argv[i]);
        else k = atof(argv[i]);
    }
    if (M < 1 || M > 64 || !(k > 0)) {
        fprintf(stderr, "usage: rect_quad_study [M 1..64] [k > 0] [--mapped-only]\n");
        return 2;
    }
    enum { N = 600 };
    static double e_old[N], e_new[N], e_ltc[N];
    double c_old = 0, c_new = 0;
    int n = 0;
    while (n < N) {
        config g = {.c = mk(0, 0, 0), .ln = mk(0, 0, 1)};
        g.du = mk(0.1 + 1.4 * rnd(), 0, 0);
        g.dv = mk(0, 0.1 + 1.4 * rnd(), 0);
        v3 dir = rnd_dir();
        if (dir.z < 0.05) continue;
        g.p = scl(dir, 0.3 + 5 * rnd());
        g.n = rnd_dir();
        if (dot(g.n, dir) > 0.2) g.n = scl(g.n, -1); /* mostly facing the light */
        g.v = rnd_dir();
        if (dot(g.v, g.n) <= 0.02) continue;
        double r = 0.0447 + (1 - 0.0447) * rnd();
        g.a = fmax(r * r, 0.002);
        g.r = r;
        int nu, nv, cells;
        grid(&g, 1.0 / 64, 3000, &nu, &nv);
        double ref = uniform_rule(&g, nu, nv);
        if (!(ref > 1e-4)) continue;
        int ou, ov;
        grid(&g, 0.5, 32, &ou, &ov);
        if (mapped_only && ou <= M && ov <= M) continue;
        double a = uniform_rule(&g, ou, ov), b = new_rule(&g, M, k, &cells);
        e_old[n] = fabs(a - ref) / (ref + 0.02);
        e_new[n] = fabs(b - ref) / (ref + 0.02);
        e_ltc[n] = fabs(ltc_rule(&g) - ref) / (ref + 0.02);
        c_old += ou * ov;
        c_new += cells;
        n++;
        if (n % 100 == 0) fprintf(stderr, "\r%d / %d configurations", n, N);
    }
    fprintf(stderr, "\n");
    qsort(e_old, N, sizeof(double), cmp);
    qsort(e_new, N, sizeof(double), cmp);
    qsort(e_ltc, N, sizeof(double), cmp);
    printf("%d configurations%s, M %d, k %.2f\n", N, mapped_only ? " (only where the new rule maps)" : "", M, k);
    printf("  old rule: %6.1f cells on average, error median %.4f p90 %.4f p99 %.4f max %.4f\n", c_old / N, e_old[N / 2],
           e_old[N * 9 / 10], e_old[N * 99 / 100], e_old[N - 1]);
    printf("  new rule: %6.1f cells on average, error median %.4f p90 %.4f p99 %.4f max %.4f\n", c_new / N, e_new[N / 2],
           e_new[N * 9 / 10], e_new[N * 99 / 100], e_new[N - 1]);
    printf("  LTC:      %2d x %2d table,       error median %.4f p90 %.4f p99 %.4f max %.4f\n", PRW_LTC_N, PRW_LTC_N,
           e_ltc[N / 2], e_ltc[N * 9 / 10], e_ltc[N * 99 / 100], e_ltc[N - 1]);
    return 0;
}
