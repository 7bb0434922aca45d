#!/usr/bin/env python3
"""SSIM oracle: compares prw's SSIM (through prw_metric_tool) with scikit-image's
structural_similarity(gaussian_weights=True, sigma=1.5, use_sample_covariance=False,
data_range=1) on synthetic pairs (noise, blur, shift, contrast change, ...).  Tolerance 1e-4.

usage: ssim_oracle.py PRW_METRIC_TOOL WORKDIR
Exit 77 (ctest: skipped) when scikit-image is not importable."""
import os
import subprocess
import sys

try:
    import numpy as np
    from scipy import ndimage
    from skimage.metrics import structural_similarity
    import skimage.io
except ImportError:
    print("skipped: python3-skimage not installed")
    sys.exit(77)

TOL = 1e-4


def skimage_ssim(a, b):
    # a is the test image, b the reference; SSIM is symmetric anyway.
    return structural_similarity(a.astype(np.float64), b.astype(np.float64), gaussian_weights=True,
                                 sigma=1.5, use_sample_covariance=False, data_range=1.0)


def run_tool(tool, *args):
    out = subprocess.run([tool, *args], check=True, capture_output=True, text=True)
    return float(out.stdout.strip())


def main():
    tool, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    rng = np.random.default_rng(20240611)
    failures = 0
    worst = 0.0

    def check(name, ours, theirs):
        nonlocal failures, worst
        d = abs(ours - theirs)
        worst = max(worst, d)
        ok = d <= TOL
        print(f"{'ok  ' if ok else 'FAIL'} {name:28s} prw {ours:.9f}  skimage {theirs:.9f}  |d| {d:.2e}")
        if not ok:
            failures += 1

    # --- single-channel float pairs, through the raw path (tests the SSIM core) -------------
    def smooth(h, w, s=2.0):
        x = ndimage.gaussian_filter(rng.random((h, w)), s)
        x = (x - x.min()) / (x.max() - x.min())
        return 0.1 + 0.8 * x

    base = smooth(96, 128)
    odd = smooth(37, 23, 1.0)
    cases = {
        "noise": (np.clip(base + rng.normal(0, 0.05, base.shape), 0, 1), base),
        "strong noise": (np.clip(base + rng.normal(0, 0.3, base.shape), 0, 1), base),
        "blur": (ndimage.gaussian_filter(base, 1.5), base),
        "shift 2 px": (np.roll(base, (2, -1), axis=(0, 1)), base),
        "contrast 0.6": (0.5 + 0.6 * (base - 0.5), base),
        "brightness +0.1": (base + 0.1, base),
        "odd size 37x23 noise": (np.clip(odd + rng.normal(0, 0.1, odd.shape), 0, 1), odd),
        "uniform random": (rng.random((64, 64)), rng.random((64, 64))),
        "11x11 single window": (rng.random((11, 11)), rng.random((11, 11))),
    }
    for name, (t, r) in cases.items():
        t32, r32 = t.astype(np.float32), r.astype(np.float32)
        pt, pr = os.path.join(work, "t.f32"), os.path.join(work, "r.f32")
        t32.tofile(pt)
        r32.tofile(pr)
        h, w = t.shape
        check(name, run_tool(tool, "ssim-raw", str(w), str(h), pt, pr), skimage_ssim(t32, r32))

    # --- RGB PNG pairs (tests the luma: Y' = 0.2126 R' + 0.7152 G' + 0.0722 B') -----------------
    def luma(rgb8):
        v = rgb8.astype(np.float64) / 255.0
        return 0.2126 * v[..., 0] + 0.7152 * v[..., 1] + 0.0722 * v[..., 2]

    rgb = np.stack([smooth(80, 100), smooth(80, 100), smooth(80, 100)], axis=-1)
    rgb_cases = {
        "rgb noise": np.clip(rgb + rng.normal(0, 0.08, rgb.shape), 0, 1),
        "rgb blur": ndimage.gaussian_filter(rgb, (1.2, 1.2, 0)),
        "rgb channel swap": rgb[..., ::-1],
    }
    r8 = np.round(rgb * 255).astype(np.uint8)
    pr = os.path.join(work, "r.png")
    skimage.io.imsave(pr, r8, check_contrast=False)
    for name, t in rgb_cases.items():
        t8 = np.round(t * 255).astype(np.uint8)
        pt = os.path.join(work, "t.png")
        skimage.io.imsave(pt, t8, check_contrast=False)
        check(name, run_tool(tool, "ssim", pt, pr), skimage_ssim(luma(t8), luma(r8)))

    print(f"max |prw - skimage| = {worst:.3e} (tolerance {TOL:g})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
