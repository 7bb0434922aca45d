/* Independent oracle: GLU's NURBS tessellator (Mesa libGLU, GLU_NURBS_TESSELLATOR mode, no GL
 * context, single precision).  A second map GL_MAP2_TEXTURE_COORD_2 (bilinear, identity on the
 * domain) makes GLU report the (u, v) of every vertex it emits, so each GLU point is compared with
 * our evaluation at the same (u, v): |P_glu − P_ours| <= 1e-5 × the control-hull diagonal.  The
 * surfaces are rounded to float first so both sides evaluate the same data.  Trimming: GLU trims
 * by gluPwlCurve loops (outer CCW, inner CW); every vertex it emits must lie in our trimmed region
 * (within 1e-5 of the boundary), and some must lie near the hole (it did trim). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "prw_nurbs_make.h"
#include "prw_test.h"
#include "prw_trim.h"

#ifndef PRW_HAVE_GLU
int main(void)
{
    printf("skipped: GLU (libglu1-mesa-dev) not available at build time\n");
    return 77;
}
#else
#include <GL/glu.h>

typedef struct glu_out {
    float *xyz, *uv;
    int n, cap;
    float cur_uv[2];
    int errors;
} glu_out;

static glu_out G;

static void GLAPIENTRY on_tex(GLfloat *t)
{
    G.cur_uv[0] = t[0];
    G.cur_uv[1] = t[1];
}

static void GLAPIENTRY on_vertex(GLfloat *v)
{
    if (G.n == G.cap) {
        G.cap = G.cap ? 2 * G.cap : 1024;
        G.xyz = realloc(G.xyz, sizeof(float) * 3 * (size_t)G.cap);
        G.uv = realloc(G.uv, sizeof(float) * 2 * (size_t)G.cap);
    }
    memcpy(G.xyz + 3 * G.n, v, 3 * sizeof(float));
    memcpy(G.uv + 2 * G.n, G.cur_uv, 2 * sizeof(float));
    G.n++;
}

static void GLAPIENTRY on_error(GLenum e)
{
    fprintf(stderr, "GLU error %u: %s\n", e, (const char *)gluErrorString(e));
    G.errors++;
}

/* Rounds the surface to float (knots, homogeneous points) in place and runs GLU on it. */
static void glu_tessellate(prw_nurbs_surface *s, const prw_trim_region *trim, int steps)
{
    int nku = s->nu + s->degree_u + 1, nkv = s->nv + s->degree_v + 1;
    GLfloat *ku = malloc(sizeof(GLfloat) * (size_t)nku), *kv = malloc(sizeof(GLfloat) * (size_t)nkv);
    GLfloat *cp = malloc(sizeof(GLfloat) * 4 * (size_t)s->nu * (size_t)s->nv);
    for (int i = 0; i < nku; i++) s->knots_u[i] = ku[i] = (GLfloat)s->knots_u[i];
    for (int i = 0; i < nkv; i++) s->knots_v[i] = kv[i] = (GLfloat)s->knots_v[i];
    for (int i = 0; i < 4 * s->nu * s->nv; i++) s->pw[i] = cp[i] = (GLfloat)s->pw[i];
    double u0, u1, v0, v1;
    prw_nurbs_surface_domain(s, &u0, &u1, &v0, &v1);
    GLfloat tk_u[4] = {(GLfloat)u0, (GLfloat)u0, (GLfloat)u1, (GLfloat)u1};
    GLfloat tk_v[4] = {(GLfloat)v0, (GLfloat)v0, (GLfloat)v1, (GLfloat)v1};
    GLfloat tc[8] = {(GLfloat)u0, (GLfloat)v0, (GLfloat)u1, (GLfloat)v0, (GLfloat)u0, (GLfloat)v1, (GLfloat)u1, (GLfloat)v1};
    G.n = 0;
    GLUnurbs *nb = gluNewNurbsRenderer();
    gluNurbsProperty(nb, GLU_NURBS_MODE, GLU_NURBS_TESSELLATOR);
    gluNurbsProperty(nb, GLU_AUTO_LOAD_MATRIX, GL_FALSE);
    gluNurbsProperty(nb, GLU_SAMPLING_METHOD, GLU_DOMAIN_DISTANCE);
    gluNurbsProperty(nb, GLU_U_STEP, (GLfloat)steps);
    gluNurbsProperty(nb, GLU_V_STEP, (GLfloat)steps);
    gluNurbsCallback(nb, GLU_NURBS_VERTEX, (void (*)(void))on_vertex);
    gluNurbsCallback(nb, GLU_NURBS_TEXTURE_COORD, (void (*)(void))on_tex);
    gluNurbsCallback(nb, GLU_NURBS_ERROR, (void (*)(void))on_error);
    gluBeginSurface(nb);
    gluNurbsSurface(nb, nku, ku, nkv, kv, 4, 4 * s->nu, cp, s->degree_u + 1, s->degree_v + 1, GL_MAP2_VERTEX_4);
    gluNurbsSurface(nb, 4, tk_u, 4, tk_v, 2, 4, tc, 2, 2, GL_MAP2_TEXTURE_COORD_2);
    if (trim)
        for (int l = 0; l < trim->count; l++) {
            const prw_trim_polygon *p = &trim->loops[l];
            /* GLU: outer loops counter-clockwise, holes clockwise; loop 0 is the outer one here */
            bool ccw = prw_trim_polygon_area(p) > 0;
            bool want_ccw = l == 0;
            GLfloat *pts = malloc(sizeof(GLfloat) * 2 * (size_t)(p->n + 1));
            for (int k = 0; k <= p->n; k++) {
                int src = (ccw == want_ccw) ? k % p->n : (p->n - k) % p->n;
                pts[2 * k] = (GLfloat)p->uv[2 * src];
                pts[2 * k + 1] = (GLfloat)p->uv[2 * src + 1];
            }
            gluBeginTrim(nb);
            gluPwlCurve(nb, p->n + 1, pts, 2, GLU_MAP1_TRIM_2);
            gluEndTrim(nb);
            free(pts);
        }
    gluEndSurface(nb);
    gluDeleteNurbsRenderer(nb);
    free(ku);
    free(kv);
    free(cp);
}

static double compare(const prw_nurbs_surface *s, const char *what)
{
    prw_dvec3 lo, hi;
    prw_nurbs_surface_bounds(s, &lo, &hi);
    double diag = prw_v3_len(prw_v3_sub(hi, lo)), worst = 0;
    for (int i = 0; i < G.n; i++) {
        prw_dvec3 p = prw_nurbs_surface_eval(s, G.uv[2 * i], G.uv[2 * i + 1]);
        prw_dvec3 q = prw_v3(G.xyz[3 * i], G.xyz[3 * i + 1], G.xyz[3 * i + 2]);
        worst = fmax(worst, prw_v3_len(prw_v3_sub(p, q)) / diag);
    }
    printf("  %s: %d GLU vertices, max |P_glu - P_ours| / diagonal = %.3g\n", what, G.n, worst);
    return worst;
}

static void test_surfaces(void)
{
    prw_error e;
    prw_nurbs_surface s[3];
    CHECK_OK(prw_nurbs_make_sphere(&s[0], prw_v3(0.5, -1, 2), 1.5, &e), &e);
    CHECK_OK(prw_nurbs_make_torus(&s[1], prw_v3(0, 0, 0), 2, 0.6, &e), &e);
    CHECK_OK(prw_nurbs_surface_alloc(&s[2], 3, 2, 6, 4, &e), &e);
    double U[10] = {0, 0, 0, 0, 0.25, 0.625, 1, 1, 1, 1}, V[7] = {0, 0, 0, 0.5, 1, 1, 1};
    memcpy(s[2].knots_u, U, sizeof U);
    memcpy(s[2].knots_v, V, sizeof V);
    unsigned seed = 17;
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 6; i++) {
            seed = seed * 1664525u + 1013904223u;
            double r = (seed >> 8) / 16777216.0;
            prw_nurbs_surface_set(&s[2], i, j, prw_v3(i, j, sin(i + 2.0 * j)), 0.25 + 3 * r);
        }
    const char *names[3] = {"sphere", "torus", "rational bicubic/quadratic"};
    for (int k = 0; k < 3; k++) {
        glu_tessellate(&s[k], NULL, 24);
        CHECK(G.errors == 0);
        CHECK(G.n > 500);
        CHECK(compare(&s[k], names[k]) <= 1e-5);
        prw_nurbs_surface_free(&s[k]);
    }
}

static void test_trimmed(void)
{
    prw_error e;
    prw_trimmed_surface t;
    memset(&t, 0, sizeof t);
    CHECK_OK(prw_nurbs_make_torus(&t.surface, prw_v3(0, 0, 0), 2, 0.6, &e), &e);
    t.natural_outer = false;
    prw_dvec3 sq[5] = {prw_v3(0.05, 0.05, 0), prw_v3(0.95, 0.1, 0), prw_v3(0.9, 0.9, 0), prw_v3(0.1, 0.95, 0), prw_v3(0.05, 0.05, 0)};
    prw_nurbs_curve c;
    CHECK_OK(prw_nurbs_make_polyline(&c, 2, sq, 5, &e), &e);
    prw_trim_loop_add(prw_trimmed_surface_add_loop(&t), &c, NULL);
    CHECK_OK(prw_nurbs_make_arc(&c, 2, prw_v3(0.5, 0.5, 0), prw_v3(1, 0, 0), prw_v3(0, 1, 0), 0.25, 0, 2 * PRW_PI, &e), &e);
    prw_trim_loop_add(prw_trimmed_surface_add_loop(&t), &c, NULL);
    prw_trim_region r;
    CHECK_OK(prw_trim_region_build(&t, 1e-4, &r, &e), &e);
    glu_tessellate(&t.surface, &r, 40);
    CHECK(G.errors == 0);
    CHECK(G.n > 500);
    CHECK(compare(&t.surface, "trimmed torus") <= 1e-5);
    int outside = 0, near_hole = 0;
    for (int i = 0; i < G.n; i++) {
        double u = G.uv[2 * i], v = G.uv[2 * i + 1];
        if (!prw_trim_inside(&r, u, v, 1e-5)) outside++;
        double d = hypot(u - 0.5, v - 0.5);
        near_hole += d > 0.25 - 1e-3 && d < 0.25 + 0.05;
    }
    printf("  trimmed torus: %d GLU vertices outside our region (tolerance 1e-5), %d near the hole\n", outside, near_hole);
    CHECK(outside == 0);
    CHECK(near_hole > 20);
    prw_trim_region_free(&r);
    prw_trimmed_surface_free(&t);
}

int main(int argc, char **argv)
{
    static const prw_test_case cases[] = {{"surfaces", test_surfaces}, {"trimmed", test_trimmed}};
    int rc = prw_test_main(argc, argv, cases, (int)PRW_ARRAY_LEN(cases));
    free(G.xyz);
    free(G.uv);
    return rc;
}
#endif
