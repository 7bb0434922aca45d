#!/usr/bin/python3
"""Outside oracle for IGES shape: surface area and bounding box from gmsh (its OpenCASCADE kernel,
Debian python3-gmsh; GPL, used only as an outside oracle, never linked, never needed by ctest)
against prw's (tests/lod/iges_measure: the trimmed area integral and the box of points on the
trimmed faces).

usage: /usr/bin/python3 scripts/oracle_iges_gmsh.py DIR [FILE ...] [--measure PATH] [--timeout S]
Each file runs in its own process (a hang or crash of either side is reported, not fatal); FILE
names limit the run to those files of DIR.  The faces column is prw's surfaces ("N-F": F of them
failed to tessellate and are not counted), gmsh its OCC faces.
Relative differences: area |prw - gmsh| / gmsh (OCC's exact BRepGProp integral); box: the largest
corner coordinate difference divided by gmsh's box diagonal, for two gmsh boxes:
  d box:    the TIGHT box of points on OCC's faces: every boundary edge of every face sampled at
            2049 parameters, plus each face's interior extremes (a 97 x 97 (u, v) grid, candidates
            beyond the box tried with OCC's face classifier, refined around the first inside one);
            from the inside, so it can only be smaller than the true box (by the sampling, ~1e-6);
  d boxSTL: gmsh's model box (Geometry.OCCBoundsUseStl: BRepBndLib over the STL), which is what
            this script used to report.  It is loose: BRepBndLib widens the box of each face,
            edge and vertex by its triangulation deflection plus its tolerance (gmsh takes the
            deflection back off, not the tolerance, which IGES imports carry up to the file's
            resolution and more after OCC's repairs), and gmsh's model box covers every entity,
            free curves and points included.
OCC works in millimetres, prw in metres.
"""
import argparse
import math
import os
import subprocess
import sys

GMSH = r'''
import gmsh, math, sys
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setNumber("Geometry.OCCBoundsUseStl", 1)
gmsh.open(sys.argv[1])
s = gmsh.model.getEntities(2)
a = sum(gmsh.model.occ.getMass(2, t) for d, t in s)
b = gmsh.model.getBoundingBox(-1, -1) if s else (0,) * 6
print("GMSH", len(s), a, *b, flush=True)
# The tight box: points on the faces only.  Each face's boundary edges sampled along their
# parameter, then interior extremes: a grid over the face's (u, v) bounds, the points that would
# grow the box tried from the farthest on with OCC's face classifier (isInside), the first inside
# one refined by shrinking grids around it.
lo, hi = [math.inf] * 3, [-math.inf] * 3
def grow(xyz):
    for i in range(0, len(xyz), 3):
        for k in range(3):
            lo[k] = min(lo[k], xyz[i + k]); hi[k] = max(hi[k], xyz[i + k])
curves = set()
for d, t in s:
    for dd, c in gmsh.model.getBoundary([(2, t)], combined=False, oriented=False):
        curves.add(abs(c))
for c in sorted(curves):
    try:
        c0, c1 = gmsh.model.getParametrizationBounds(1, c)
        n = 2048
        grow(gmsh.model.getValue(1, c, [c0[0] + (c1[0] - c0[0]) * i / n for i in range(n + 1)]))
    except Exception:
        pass
def grid(u0, u1, v0, v1, n):
    return [x for i in range(n + 1) for j in range(n + 1) for x in (u0 + (u1 - u0) * i / n, v0 + (v1 - v0) * j / n)]
def interior(t):
    fb = list(gmsh.model.getBoundingBox(2, t))  # OCC's box of the face (STL based: widened here)
    m = 0.02 * math.dist(fb[0:3], fb[3:6]) + 0.1
    fb = [fb[k] - m for k in range(3)] + [fb[k] + m for k in range(3, 6)]
    if all(fb[k] >= lo[k] and fb[k + 3] <= hi[k] for k in range(3)):
        return
    (u0, v0), (u1, v1) = gmsh.model.getParametrizationBounds(2, t)
    n = 96
    uv = grid(u0, u1, v0, v1, n)
    xyz = gmsh.model.getValue(2, t, uv)
    for k in range(3):
        for sign in (-1, 1):
            ext = hi[k] if sign > 0 else -lo[k]
            if (fb[k + 3] if sign > 0 else -fb[k]) <= ext:
                continue
            cand = sorted((sign * xyz[3 * i + k], i) for i in range(len(xyz) // 3) if sign * xyz[3 * i + k] > ext)
            best = None
            for val, i in reversed(cand[-64:]):
                if gmsh.model.isInside(2, t, uv[2 * i:2 * i + 2]):
                    best = (uv[2 * i], uv[2 * i + 1])
                    break
            if best is None:
                continue
            hu, hv = (u1 - u0) / n, (v1 - v0) / n
            for it in range(6):
                g = grid(max(u0, best[0] - hu), min(u1, best[0] + hu), max(v0, best[1] - hv), min(v1, best[1] + hv), 8)
                gx = gmsh.model.getValue(2, t, g)
                for val, i in sorted(((sign * gx[3 * i + k], i) for i in range(len(gx) // 3)), reverse=True)[:16]:
                    if gmsh.model.isInside(2, t, g[2 * i:2 * i + 2]):
                        best = (g[2 * i], g[2 * i + 1])
                        grow(gx[3 * i:3 * i + 3])
                        break
                hu, hv = hu / 4, hv / 4
failed = 0
for d, t in sorted(s, key=lambda e: -math.dist(gmsh.model.getBoundingBox(2, e[1])[0:3], gmsh.model.getBoundingBox(2, e[1])[3:6])):
    try:
        interior(t)
    except Exception:
        failed += 1
if s and lo[0] <= hi[0]:
    print("TIGHT", *(lo + hi), failed, flush=True)
'''


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('dir')
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument('--measure', default=os.path.join(here, '..', 'build', 'tests', 'lod', 'iges_measure'))
    ap.add_argument('--timeout', type=float, default=120)
    ap.add_argument('files', nargs='*', help='only these file names of DIR')
    a = ap.parse_intermixed_args()
    files = sorted(f for f in os.listdir(a.dir) if f.lower().endswith(('.igs', '.iges')) and (not a.files or f in a.files))
    print('%-40s %5s %5s %14s %14s %9s %9s %9s' % ('file', 'faces', 'gmsh', 'area prw m2', 'area gmsh m2', 'd area',
                                                   'd box', 'd boxSTL'))
    worst_a = worst_b = 0
    n = over = 0
    for name in files:
        path = os.path.join(a.dir, name)
        try:
            p = subprocess.run([a.measure, path], capture_output=True, text=True, timeout=a.timeout)
            w = p.stdout.split()
            prw = None
            if p.returncode in (0, 3) and w and w[0] == 'area':
                prw = (float(w[1]), [float(x) for x in w[3:9]], int(w[10]), int(w[12]))
            why = 'prw: ' + (p.stderr.strip().splitlines() or ['exit %d' % p.returncode])[-1][:60]
        except subprocess.TimeoutExpired:
            prw, why = None, 'prw: timeout'
        try:
            g = subprocess.run(['/usr/bin/python3', '-c', GMSH, path], capture_output=True, text=True, timeout=a.timeout)
            gl = [l for l in g.stdout.splitlines() if l.startswith('GMSH')]
            tl = [l for l in g.stdout.splitlines() if l.startswith('TIGHT')]
            gm = [float(x) for x in gl[0].split()[1:]] if gl else None
            tight = [float(x) for x in tl[0].split()[1:7]] if tl else None
            gwhy = 'gmsh: ' + ('signal %d' % -g.returncode if g.returncode < 0 else
                               (g.stderr.strip().splitlines() or ['exit %d' % g.returncode])[-1][:60])
        except subprocess.TimeoutExpired:
            gm = tight = None
            gwhy = 'gmsh: timeout'
        if not prw or not gm or gm[0] == 0 or prw[0] == 0:
            print('%-40s %5s %5s %14s %14s   (not compared: %s)' % (name[:40], prw[2] if prw else '-', int(gm[0]) if gm else '-',
                  '%.6g' % prw[0] if prw else '-', '%.6g' % (gm[1] * 1e-6) if gm else '-',
                  (why if not prw else 'prw has no faces') if not prw or prw[0] == 0 else
                  gwhy if gm is None else 'gmsh: no surfaces'), flush=True)
            continue
        ga = gm[1] * 1e-6

        def dbox(box):
            gb = [x * 1e-3 for x in box]
            diag = math.dist(gb[0:3], gb[3:6])
            return max(abs(prw[1][k] - gb[k]) for k in range(6)) / diag if diag > 0 else 0
        da = abs(prw[0] - ga) / ga
        db_stl = dbox(gm[2:8])
        db = dbox(tight) if tight else db_stl
        worst_a, worst_b, n = max(worst_a, da), max(worst_b, db), n + 1
        over += da > 0.005 or db > 0.005
        print('%-40s %5s %5d %14.6g %14.6g %8.3f%% %8.3f%% %8.3f%%%s' % (
            name[:40], '%d' % prw[2] if not prw[3] else '%d-%d' % (prw[2], prw[3]), int(gm[0]), prw[0], ga, 100 * da,
            100 * db, 100 * db_stl, '' if tight else ' (no tight box: STL)'), flush=True)
    print('\n%d files compared: largest area difference %.3f %%, largest box difference %.3f %%; %d over 0.5 %%' %
          (n, 100 * worst_a, 100 * worst_b, over))


if __name__ == '__main__':
    sys.exit(main())
