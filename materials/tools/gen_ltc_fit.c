/* gen_ltc_fit — writes materials/prw_ltc_table.h, the linearly transformed cosines (LTC; Heitz, Dupuy,
 * Hill & Neubelt 2016, "Real-time polygonal-light shading with linearly transformed cosines") that the
 * rasterizer's rect lights can use for the single-scattering GGX specular (shaders/ltc.glsl with
 * PRW_RECT_LTC, materials/prw_ltc.h).  Fitted here to OUR lobe: D_GGX * V_SmithGGXCorrelated * (n.l) of prw_brdf.h
 * (restated below in double precision: float loses the lobe's shape at alpha 0.002), F = 1.
 *
 *   cc -O2 -std=c17 materials/tools/gen_ltc_fit.c -lm -o gen_ltc_fit
 *   ./gen_ltc_fit > materials/prw_ltc_table.h   (~2.5 min with -fopenmp on 2 cores; prints the worst fit error
 *   on stderr, LTC_VERBOSE=1 each cell's parameters and L1 distance between the normalised lobes)
 * (or build the CMake target prw_gen_ltc_fit and run build/materials/prw_gen_ltc_fit).
 *
 * Table: PRW_LTC_N x PRW_LTC_N cells over perceptual roughness r = i / (N - 1) (alpha as
 * prw_alpha_from_roughness) and t = sqrt(1 - n.v) = j / (N - 1) (n.v clamped to >= 1e-3 for the fit).
 * Local frame: n = z, v = (sin theta, 0, cos theta).  Per cell:
 *   A = int D V (n.l) dl                          (the lobe's albedo with F = 1)
 *   B = int (1 - v.h)^5 D V (n.l) dl / A          (Schlick's Fresnel weight: F0 + (1 - F0) B)
 *   C = int F_dielectric(v.h) D V (n.l) dl / A    (the exact dielectric's, IOR 1.5)
 *   M: the 3x3 matrix whose transformed clamped cosine D_o(M^-1 l / |M^-1 l|) |det M^-1| / |M^-1 l|^3,
 *      D_o(w) = max(w.z, 0) / pi, is closest to D V (n.l) / A.
 * M = R S, R the rotation about y taking z to the lobe's mean direction (its first moment, computed),
 * S = [[a, 0, b], [0, c, 0], [0, 0, 1]]; (a, b, c) minimise the L3 distance between the two
 * distributions over the sphere, estimated with multiple importance sampling (balance heuristic) of the
 * GGX lobe (reflected D-sampled half vectors) and of the LTC itself, 16 x 16 stratified samples each
 * with fixed jitter (so the objective is deterministic), by Nelder-Mead started from the neighbouring
 * cell's solution (cells visited from n.v = 1 towards grazing) and from an isotropic lobe (a = c = alpha,
 * b = 0) at the mean direction, keeping the better; the lobe's direction stays above the horizon.
 * Stored: M^-1 scaled so that its middle element is 1 (the distribution does not depend on the scale):
 * (m00, m02, m20, m22), and (A, B, C, 0).  A, B, C by 256 x 256 midpoint samples of the reflected D-sampled half vector.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef N
#define N 64
#endif
#define NS 16    /* stratified samples per axis for the fit objective */
#define NA 256   /* per axis for A, B, C */
#define PI 3.14159265358979323846

typedef struct {
    double x, y, z;
} v3;
static v3 mk(double x, double y, double z) { return (v3){x, y, z}; }
static double dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static v3 scl(v3 a, double s) { return mk(a.x * s, a.y * s, a.z * s); }
static v3 add(v3 a, v3 b) { return mk(a.x + b.x, a.y + b.y, a.z + b.z); }
static v3 unit(v3 a) { return scl(a, 1.0 / sqrt(dot(a, a))); }

/* prw_brdf.h's definitions in double */
static double alpha_of(double r) { return fmax(r * r, 0.002); }
static double D_ggx(double NoH, double a)
{
    double a2 = a * a, d = NoH * NoH * (a2 - 1) + 1;
    return a2 / (PI * d * d);
}
static double V_smith(double NoV, double NoL, double a)
{
    double a2 = a * a;
    double gv = NoL * sqrt(NoV * NoV * (1 - a2) + a2), gl = NoV * sqrt(NoL * NoL * (1 - a2) + a2);
    return 0.5 / fmax(gv + gl, 1e-300);
}
static double F_diel(double c)
{
    c = fmin(fmax(c, 0), 1);
    double eta = 1.5, g = sqrt(eta * eta - 1 + c * c);
    double a = (g - c) / (g + c), b = (c * (g + c) - 1) / (c * (g - c) + 1);
    return 0.5 * a * a * (1 + b * b);
}

/* The lobe D V (n.l) at l (unnormalised, zero below the horizon). */
static double lobe(v3 v, v3 l, double a)
{
    if (l.z <= 0) return 0;
    v3 h = unit(add(v, l));
    return D_ggx(h.z, a) * V_smith(v.z, l.z, a) * l.z;
}

/* The half vector for uniform (u1, u2) distributed as D(h) (n.h), and l = reflect(-v, h) with its pdf. */
static v3 sample_lobe(v3 v, double a, double u1, double u2, double *pdf)
{
    double t2 = a * a * u1 / (1 - u1), ct = 1 / sqrt(1 + t2), st = sqrt(fmax(0, 1 - ct * ct));
    double ph = 2 * PI * u2;
    v3 h = mk(st * cos(ph), st * sin(ph), ct);
    double voh = dot(v, h);
    v3 l = add(scl(h, 2 * voh), scl(v, -1));
    *pdf = voh > 0 ? D_ggx(ct, a) * ct / (4 * voh) : 0;
    return l;
}

typedef struct {
    double m[3][3], inv[3][3], det_inv;
} ltc;

static void mat_inv(double m[3][3], double r[3][3], double *det)
{
    double d = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    r[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / d;
    r[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / d;
    r[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / d;
    r[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / d;
    r[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / d;
    r[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / d;
    r[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / d;
    r[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / d;
    r[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / d;
    *det = 1 / d;
}
static v3 mul(const double m[3][3], v3 a)
{
    return mk(m[0][0] * a.x + m[0][1] * a.y + m[0][2] * a.z, m[1][0] * a.x + m[1][1] * a.y + m[1][2] * a.z,
              m[2][0] * a.x + m[2][1] * a.y + m[2][2] * a.z);
}

/* M = R_y(phi) [[a, 0, b], [0, c, 0], [0, 0, 1]] */
static ltc make_ltc(const double p[4])
{
    ltc L;
    double cp = cos(p[3]), sp = sin(p[3]);
    double S[3][3] = {{p[0], 0, p[1]}, {0, p[2], 0}, {0, 0, 1}};
    double R[3][3] = {{cp, 0, sp}, {0, 1, 0}, {-sp, 0, cp}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 3; k++) s += R[i][k] * S[k][j];
            L.m[i][j] = s;
        }
    mat_inv(L.m, L.inv, &L.det_inv);
    return L;
}

static double ltc_eval(const ltc *L, v3 l)
{
    v3 o = mul(L->inv, l);
    double len2 = dot(o, o), len = sqrt(len2);
    double z = o.z / len;
    if (z <= 0) return 0;
    return z / PI * fabs(L->det_inv) / (len2 * len);
}

static v3 ltc_sample(const ltc *L, double u1, double u2)
{
    double r = sqrt(u1), ph = 2 * PI * u2;
    v3 o = mk(r * cos(ph), r * sin(ph), sqrt(fmax(0, 1 - u1)));
    return unit(mul(L->m, o));
}

typedef struct {
    v3 v;
    double a, A, phi;
    int l1; /* the objective is the L1 distance instead of L3 (the printed fit error) */
} cell;

static double jit[NS * NS][4];

static double objective(const cell *c, const double p[4])
{
    if (!(p[0] > 0) || !(p[2] > 0) || !(fabs(p[3]) < 0.5 * PI)) return 1e300; /* a lobe above the horizon */
    ltc L = make_ltc(p);
    double err = 0;
    for (int k = 0; k < NS * NS; k++) {
        double u1 = ((k % NS) + jit[k][0]) / NS, u2 = ((k / NS) + jit[k][1]) / NS;
        /* from the lobe */
        double pdf_b;
        v3 l = sample_lobe(c->v, c->a, u1, u2, &pdf_b);
        if (pdf_b > 0) {
            double f = lobe(c->v, l, c->a) / c->A, g = ltc_eval(&L, l);
            double pl = g;
            double d = fabs(f - g);
            err += (c->l1 ? d : d * d * d) / (pdf_b + pl);
        }
        /* from the LTC */
        double w1 = ((k % NS) + jit[k][2]) / NS, w2 = ((k / NS) + jit[k][3]) / NS;
        v3 m = ltc_sample(&L, w1, w2);
        double g = ltc_eval(&L, m), f = lobe(c->v, m, c->a) / c->A;
        v3 h = unit(add(c->v, m));
        double voh = dot(c->v, h);
        double pb = voh > 0 && h.z > 0 ? D_ggx(h.z, c->a) * h.z / (4 * voh) : 0;
        double d = fabs(f - g);
        if (pb + g > 0) err += (c->l1 ? d : d * d * d) / (pb + g);
    }
    return err / (NS * NS);
}

/* Nelder-Mead on the P parameters x from initial steps st; returns the best value. */
#define P 4
static double nelder_mead(const cell *c, double x[P], const double st[P], int iters)
{
    double s[P + 1][P], f[P + 1];
    for (int i = 0; i <= P; i++) {
        memcpy(s[i], x, sizeof s[i]);
        if (i) s[i][i - 1] += st[i - 1];
        f[i] = objective(c, s[i]);
    }
    for (int it = 0; it < iters; it++) {
        for (int i = 0; i <= P; i++) /* order by value */
            for (int j = i + 1; j <= P; j++)
                if (f[j] < f[i]) {
                    double t = f[i], tv[P];
                    f[i] = f[j];
                    f[j] = t;
                    memcpy(tv, s[i], sizeof tv);
                    memcpy(s[i], s[j], sizeof tv);
                    memcpy(s[j], tv, sizeof tv);
                }
        if (fabs(f[P] - f[0]) <= 1e-6 * fabs(f[0])) break;
        double o[P] = {0}, r[P], e[P], k[P];
        for (int i = 0; i < P; i++)
            for (int d = 0; d < P; d++) o[d] += s[i][d] / P;
        for (int d = 0; d < P; d++) r[d] = o[d] + (o[d] - s[P][d]);
        double fr = objective(c, r);
        if (fr < f[0]) {
            for (int d = 0; d < P; d++) e[d] = o[d] + 2 * (o[d] - s[P][d]);
            double fe = objective(c, e);
            memcpy(s[P], fe < fr ? e : r, sizeof e);
            f[P] = fe < fr ? fe : fr;
        } else if (fr < f[P - 1]) {
            memcpy(s[P], r, sizeof r);
            f[P] = fr;
        } else {
            int outside = fr < f[P];
            for (int d = 0; d < P; d++) k[d] = outside ? o[d] + 0.5 * (r[d] - o[d]) : o[d] + 0.5 * (s[P][d] - o[d]);
            double fk = objective(c, k);
            if (fk < (outside ? fr : f[P])) {
                memcpy(s[P], k, sizeof k);
                f[P] = fk;
            } else {
                for (int i = 1; i <= P; i++) {
                    for (int d = 0; d < P; d++) s[i][d] = s[0][d] + 0.5 * (s[i][d] - s[0][d]);
                    f[i] = objective(c, s[i]);
                }
            }
        }
    }
    int b = 0;
    for (int i = 1; i <= P; i++)
        if (f[i] < f[b]) b = i;
    memcpy(x, s[b], sizeof s[b]);
    return f[b];
}

static double rnd01(unsigned long long *st)
{
    *st ^= *st << 13;
    *st ^= *st >> 7;
    *st ^= *st << 17;
    return (double)(*st >> 11) / 9007199254740992.0;
}

static float table[2][N][N][4];

int main(void)
{
    unsigned long long st = 0x2545F4914F6CDD1Dull;
    for (int k = 0; k < NS * NS; k++)
        for (int d = 0; d < 4; d++) jit[k][d] = rnd01(&st);
    double worst = 0;
    int rows_done = 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic) reduction(max : worst)
#endif
    for (int i = 0; i < N; i++) {
        double r = (double)i / (N - 1), a = alpha_of(r);
        double p[P] = {a, 0, a, 0};
        for (int j = 0; j < N; j++) {
            double t = (double)j / (N - 1), mu = fmax(1 - t * t, 1e-3);
            cell c = {.v = mk(sqrt(1 - mu * mu), 0, mu), .a = a};
            /* A, B, C and the mean direction */
            double A = 0, B = 0, C = 0;
            v3 mean = mk(0, 0, 0);
            for (int k = 0; k < NA * NA; k++) {
                double pdf;
                v3 l = sample_lobe(c.v, a, ((k % NA) + 0.5) / NA, ((k / NA) + 0.5) / NA, &pdf);
                if (!(pdf > 0) || l.z <= 0) continue;
                double w = lobe(c.v, l, a) / pdf;
                double voh = dot(c.v, unit(add(c.v, l)));
                A += w;
                B += w * pow(1 - fmin(fmax(voh, 0), 1), 5);
                C += w * F_diel(voh);
                mean = add(mean, scl(l, w));
            }
            A /= NA * NA;
            B /= NA * NA * A;
            C /= NA * NA * A;
            c.A = A;
            c.phi = atan2(mean.x, mean.z);
            /* from the neighbouring cell's solution and from an isotropic lobe at the mean direction; the better */
            double q[P] = {a, 0, a, c.phi};
            if (j == 0 || fabs(p[3] - c.phi) > 0.3) p[3] = c.phi;
            double fp = 0, fq = 0;
            for (int pass = 0; pass < 2; pass++) {
                double *x = pass ? q : p, *fx = pass ? &fq : &fp;
                double steps[P] = {0.3 * x[0], 0.3 * fmax(x[0], 0.05), 0.3 * x[2], 0.1 * fmax(x[0], 0.05)};
                nelder_mead(&c, x, steps, 300);
                double steps2[P] = {0.1 * x[0], 0.1 * fmax(x[0], 0.05), 0.1 * x[2], 0.03 * fmax(x[0], 0.05)};
                *fx = nelder_mead(&c, x, steps2, 150);
            }
            if (fq < fp) memcpy(p, q, sizeof q);
            double f = fq < fp ? fq : fp;
            (void)f;
            c.l1 = 1;
            double l1 = objective(&c, p);
            if (l1 > worst) worst = l1;
            if (getenv("LTC_VERBOSE"))
                fprintf(stderr, "r %.3f mu %.4f phi %.3f -> %.3f abc %.4g %.4g %.4g L1 %.4f\n", r, mu, c.phi, p[3],
                        p[0], p[1], p[2], l1);
            ltc L = make_ltc(p);
            double s = L.inv[1][1];
            table[0][j][i][0] = (float)(L.inv[0][0] / s);
            table[0][j][i][1] = (float)(L.inv[0][2] / s);
            table[0][j][i][2] = (float)(L.inv[2][0] / s);
            table[0][j][i][3] = (float)(L.inv[2][2] / s);
            table[1][j][i][0] = (float)A;
            table[1][j][i][1] = (float)B;
            table[1][j][i][2] = (float)C;
            table[1][j][i][3] = 0;
        }
#ifdef _OPENMP
#pragma omp atomic
#endif
        rows_done++;
        fprintf(stderr, "\rroughness rows %d / %d", rows_done, N);
    }
    fprintf(stderr, "\nworst L1 distance (0..2) between the fitted and the true lobe: %.4f\n", worst);
    printf("/* prw_ltc_table.h — GENERATED by materials/tools/gen_ltc_fit.c; do not edit.\n"
           " * Regenerate: cc -O2 -std=c17 materials/tools/gen_ltc_fit.c -lm -o gen_ltc_fit &&\n"
           " *             ./gen_ltc_fit > materials/prw_ltc_table.h\n"
           " * Linearly transformed cosines of the single-scattering GGX lobe of prw_brdf.h (the generator says\n"
           " * how), %d x %d cells over roughness (columns) and sqrt(1 - n.v) (rows); layer 0: M^-1 as (m00, m02,\n"
           " * m20, m22) with m11 = 1; layer 1: (albedo A, Schlick weight B, dielectric Fresnel weight C, 0). */\n"
           "#ifndef PRW_LTC_TABLE_H\n#define PRW_LTC_TABLE_H\n\n#define PRW_LTC_N %d\n\n"
           "static const float prw_ltc_table_data[2 * PRW_LTC_N * PRW_LTC_N * 4] = {\n",
           N, N, N);
    for (int l = 0; l < 2; l++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                printf("   ");
                for (int d = 0; d < 4; d++) printf(" %.8g%s", (double)table[l][j][i][d], ",");
                printf("\n");
            }
    printf("};\n\n#endif\n");
    return 0;
}
