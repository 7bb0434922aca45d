/* mat_testutil.h — helpers shared by the material tests: a deterministic RNG, Gauss-Legendre
 * quadrature, and an INDEPENDENT double-precision GGX (D, Smith masking, exact Fresnel written here
 * from the formulas, not taken from prw_brdf.h) for the albedo and furnace checks. */
#ifndef MAT_TESTUTIL_H
#define MAT_TESTUTIL_H

#include <math.h>
#include <stdint.h>

#define MT_PI 3.14159265358979323846

typedef struct mt_rng {
    uint64_t s;
} mt_rng;

/* splitmix64 (Steele et al. 2014), top 53 bits as a double in [0, 1). */
static inline double mt_rand(mt_rng *r)
{
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* 8-node Gauss-Legendre on [-1, 1]: roots of P_8 by Newton iteration, weights 2/((1-x^2) P_8'^2). */
typedef struct mt_gl {
    double x[8], w[8];
} mt_gl;

static inline mt_gl mt_gl8(void)
{
    mt_gl g;
    for (int i = 0; i < 8; i++) {
        double x = cos(MT_PI * (i + 0.75) / 8.5), dp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = x;
            for (int k = 2; k <= 8; k++) {
                double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = 8 * (x * p1 - p0) / (x * x - 1);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16) break;
        }
        g.x[i] = x, g.w[i] = 2 / ((1 - x * x) * dp * dp);
    }
    return g;
}

/* GGX NDF (Trowbridge & Reitz 1975; Walter et al. 2007): written in terms of tan(theta_m). */
static inline double mt_D(double cos_m, double alpha)
{
    if (cos_m <= 0) return 0;
    double c2 = cos_m * cos_m, t2 = (1 - c2) / c2, a2 = alpha * alpha;
    double k = a2 + t2;
    return a2 / (MT_PI * c2 * c2 * k * k);
}

/* Smith Lambda for GGX (Heitz 2014, eq. 72). */
static inline double mt_lambda(double mu, double alpha)
{
    double t2 = (1 - mu * mu) / (mu * mu);
    return 0.5 * (sqrt(1 + alpha * alpha * t2) - 1);
}

/* Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(o) + Lambda(i)) (Heitz 2014, eq. 99). */
static inline double mt_G2(double mu_o, double mu_i, double alpha)
{
    return 1 / (1 + mt_lambda(mu_o, alpha) + mt_lambda(mu_i, alpha));
}

/* Exact Fresnel reflectance via Snell's law and the s/p amplitude coefficients (Born & Wolf),
 * unpolarised: (rs^2 + rp^2)/2, from outside into relative IOR eta. */
static inline double mt_fresnel(double cos_i, double eta)
{
    double sin_t = sqrt(fmax(0.0, 1 - cos_i * cos_i)) / eta, cos_t = sqrt(fmax(0.0, 1 - sin_t * sin_t));
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

/* int f(wo, wi) dwi for wo = (sqrt(1 - mu^2), 0, mu), over the upper hemisphere of wi (upper_only)
 * or over every wi = reflect(wo, wm) with wm in the upper hemisphere and wo.wm > 0 (the support of
 * the reflected GGX sampler), written over the half vector wm (dwi = 4 (wo.wm) dwm).  wm in polar
 * coordinates: theta_m in [0, tc] through tan(theta_m) = alpha tan(pi v / 2) (resolves the GGX peak),
 * theta_m in [tc, pi/2] uniformly, tc = atan(8 alpha); phi in [0, pi] doubled (f must be symmetric in
 * wi.y).  Composite 8-node Gauss-Legendre: `panels` panels in each of v, theta and phi. */
typedef double (*mt_integrand)(const double wo[3], const double wi[3], void *ctx);
static inline double mt_integrate_wm(double mu, double alpha, int panels, int upper_only, mt_integrand fn, void *ctx)
{
    mt_gl g = mt_gl8();
    double wo[3] = {sqrt(fmax(0.0, 1 - mu * mu)), 0, mu};
    double tc = atan(8 * alpha), vc = 2 / MT_PI * atan(8.0);
    double sum = 0;
    for (int region = 0; region < 2; region++)
        for (int pa = 0; pa < panels; pa++)
            for (int ia = 0; ia < 8; ia++) {
                double t = (pa + 0.5 + 0.5 * g.x[ia]) / panels, w = 0.5 * g.w[ia] / panels, th, dth;
                if (region == 0) {
                    double v = t * vc, tv = tan(MT_PI * v / 2);
                    th = atan(alpha * tv);
                    dth = vc * alpha * (MT_PI / 2) * (1 + tv * tv) / (1 + alpha * alpha * tv * tv);
                } else {
                    th = tc + t * (MT_PI / 2 - tc);
                    dth = MT_PI / 2 - tc;
                }
                double st = sin(th), ct = cos(th);
                for (int pp = 0; pp < panels; pp++)
                    for (int ip = 0; ip < 8; ip++) {
                        double ph = MT_PI * (pp + 0.5 + 0.5 * g.x[ip]) / panels, wp = MT_PI * 0.5 * g.w[ip] / panels;
                        double m[3] = {st * cos(ph), st * sin(ph), ct};
                        double om = wo[0] * m[0] + wo[2] * m[2];
                        if (om <= 0) continue;
                        double wi[3] = {2 * om * m[0] - wo[0], 2 * om * m[1] - wo[1], 2 * om * m[2] - wo[2]};
                        if (upper_only && wi[2] <= 0) continue;
                        sum += w * dth * wp * st * 4 * om * fn(wo, wi, ctx);
                    }
            }
    return 2 * sum;
}

/* int f(wo, wi) (wi.z) dwi over the upper hemisphere (f without the cosine). */
typedef struct mt_cos_ctx {
    mt_integrand fn;
    void *ctx;
} mt_cos_ctx;
static inline double mt_times_cos(const double wo[3], const double wi[3], void *ctx)
{
    const mt_cos_ctx *c = ctx;
    return wi[2] * c->fn(wo, wi, c->ctx);
}
static inline double mt_integrate_halfvector(double mu, double alpha, int panels, mt_integrand fn, void *ctx)
{
    mt_cos_ctx c = {fn, ctx};
    return mt_integrate_wm(mu, alpha, panels, 1, mt_times_cos, &c);
}

/* The independent single-scattering GGX albedo: F = 1 (fresnel = 0) or the exact dielectric (1). */
typedef struct mt_ggx_ctx {
    double alpha;
    int fresnel;
} mt_ggx_ctx;

static inline double mt_ggx_f(const double wo[3], const double wi[3], void *ctx)
{
    const mt_ggx_ctx *c = ctx;
    double h[3] = {wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]};
    double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    double cos_m = h[2] / hl, oh = (wo[0] * h[0] + wo[1] * h[1] + wo[2] * h[2]) / hl;
    double F = c->fresnel ? mt_fresnel(oh, 1.5) : 1.0;
    return mt_D(cos_m, c->alpha) * mt_G2(wo[2], wi[2], c->alpha) * F / (4 * wo[2] * wi[2]);
}

static inline double mt_ggx_albedo(double mu, double alpha, int fresnel, int panels)
{
    mt_ggx_ctx c = {alpha, fresnel};
    return mt_integrate_halfvector(mu, alpha, panels, mt_ggx_f, &c);
}

#endif
