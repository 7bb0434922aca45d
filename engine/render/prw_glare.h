/* prw_glare — temporal glare: the scattering in the viewer's eye as a point-spread function applied
 * to the linear HDR image before tone mapping (issue 6).  After Ritschel, Ihrke, Frisvad, Coppens,
 * Myszkowski, Seidel 2009, "Temporal Glare: Real-Time Dynamic Simulation of the Scattering in the
 * Human Eye" (Ritschel's thesis ch. 8; notes seed-000-ritschel.md §2.5), simplified:
 *  - pupil diameter from the adaptation luminance La (cd/m^2), Moon & Spencer (thesis eq. 8.2, log10):
 *    p = 4.9 - 3 tanh(0.4 (log10 La + 1)) mm, with hippus (eq. 8.1)
 *    h(t, p) = p + noise(t / p) (p_max / p) sqrt(1 - p / p_max), p_max = 9 mm, noise a 3-octave value
 *    noise in [-0.5, 0.5] scaled by PRW_GLARE_HIPPUS;
 *  - aperture transmission A on an n x n grid spanning PRW_GLARE_APERTURE_MM: the pupil disc, lens
 *    particles (PRW_GLARE_PARTICLES opaque discs, positions from the seed, drifting slowly in t),
 *    lens-fibre gratings (PRW_GLARE_GRATINGS thin radial lines of transmittance 0.8) and eyelashes
 *    (PRW_GLARE_LASHES dark near-vertical lines from the upper lid);
 *  - Fraunhofer diffraction: PSF at wavelength lambda and visual angle theta = |FFT(A)|^2 at spatial
 *    frequency theta / lambda (one FFT at the grid, resampled per band: bin k lies at the angle
 *    k lambda / D), binned into image pixels of 1 / ppd degrees, normalised to sum 1 per band;
 *  - PRW_GLARE_BANDS spectral bands over 400-700 nm (the thesis uses 32 samples), each PSF normalised,
 *    summed into the R, G, B channels with weights from the CIE 1931 colour-matching functions
 *    (analytic fit) taken to linear Rec.709, negative parts dropped, normalised per channel — so
 *    each channel's PSF is the spectral average over the wavelengths it stands for (the coloured
 *    ciliary-corona fringes come from this spread, not from three single lines);
 *  - convolution of each channel with its band's PSF by FFT (kissfft, float, zero padding: light is
 *    not wrapped around), negative float noise clamped to 0.
 * Off by default and off in every accuracy comparison: only `prw render --glare` uses it.
 * Excluded: cornea/vitreous/retina scattering terms, the lens mass-spring deformation, blinking.
 */
#ifndef PRW_GLARE_H
#define PRW_GLARE_H

#include "prw_core.h"
#include "prw_image.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PRW_GLARE_APERTURE_MM 10.0
#define PRW_GLARE_PUPIL_MAX_MM 9.0
#define PRW_GLARE_HIPPUS 0.25
#define PRW_GLARE_PARTICLES 400
#define PRW_GLARE_GRATINGS 120
#define PRW_GLARE_LASHES 9
#define PRW_GLARE_BANDS 24
#define PRW_GLARE_LAMBDA_MIN_NM 400.0
#define PRW_GLARE_LAMBDA_MAX_NM 700.0

typedef struct prw_glare_settings {
    int n;            /* aperture / FFT grid, a power of two in [64, 2048]; 0 -> 512 */
    double ppd;       /* image pixels per degree of visual angle; 0 -> 40 */
    double time;      /* s: hippus and particle drift */
    uint32_t seed;
} prw_glare_settings;

/* Moon & Spencer mean pupil diameter (mm) for adaptation luminance la (cd/m^2; guarded at 1e-6). */
double prw_glare_pupil_mm(double la);
/* With hippus at time t (s). */
double prw_glare_pupil_hippus_mm(double la, double t, uint32_t seed);

/* Aperture transmission, n x n floats in [0, 1] (row-major, centre at (n/2, n/2)). */
void prw_glare_aperture(const prw_glare_settings *s, double pupil_mm, float *ap);

/* Band centres (nm, ascending, uniform in [MIN, MAX]) and each band's weight in R, G, B (each
 * channel's weights sum to 1). */
void prw_glare_spectral_weights(double lambda_nm[PRW_GLARE_BANDS], double w[PRW_GLARE_BANDS][3]);

/* The PSF of each channel: *radius gets R, psf 3 images of (2R+1)^2 floats (channel c at c (2R+1)^2),
 * each summing to 1; the caller frees *psf.  Fails on a bad grid size or when out of memory. */
bool prw_glare_psf(const prw_glare_settings *s, double pupil_mm, float **psf, int *radius, prw_error *e);

/* Convolves the RGB channels of img (in place) with the band PSFs (A is kept). */
bool prw_glare_apply(prw_image *img, const float *psf, int radius, prw_error *e);

#ifdef __cplusplus
}
#endif
#endif
