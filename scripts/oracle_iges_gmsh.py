#!/usr/bin/python3
"""Outside oracle for IGES shape: surface area and bounding box from gmsh (its OpenCASCADE kernel,
Debian python3-gmsh; GPL, used only as an outside oracle, never linked, never needed by ctest)
against prw's (tests/lod/iges_measure: the trimmed area integral and the box of points on the
trimmed faces).

usage: /usr/bin/python3 scripts/oracle_iges_gmsh.py DIR [--measure PATH] [--timeout S]
Each file runs in its own process (a hang or crash of either side is reported, not fatal).
Relative differences: area |prw - gmsh| / gmsh; box: the largest corner coordinate difference
divided by gmsh's box diagonal.  gmsh's box uses its STL bounds (Geometry.OCCBoundsUseStl), so it
carries OCC's triangulation tolerance.  OCC works in millimetres, prw in metres.
"""
import argparse
import math
import os
import subprocess
import sys

GMSH = r'''
import gmsh, sys
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setNumber("Geometry.OCCBoundsUseStl", 1)
gmsh.open(sys.argv[1])
s = gmsh.model.getEntities(2)
a = sum(gmsh.model.occ.getMass(2, t) for d, t in s)
b = gmsh.model.getBoundingBox(-1, -1) if s else (0,) * 6
print("GMSH", len(s), a, *b)
'''


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('dir')
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument('--measure', default=os.path.join(here, '..', 'build', 'tests', 'lod', 'iges_measure'))
    ap.add_argument('--timeout', type=float, default=120)
    a = ap.parse_args()
    files = sorted(f for f in os.listdir(a.dir) if f.lower().endswith(('.igs', '.iges')))
    print('%-40s %5s %5s %14s %14s %9s %9s' % ('file', 'faces', 'gmsh', 'area prw m2', 'area gmsh m2', 'd area', 'd box'))
    worst_a = worst_b = 0
    n = 0
    for name in files:
        path = os.path.join(a.dir, name)
        try:
            p = subprocess.run([a.measure, path], capture_output=True, text=True, timeout=a.timeout)
            w = p.stdout.split()
            prw = None
            if p.returncode in (0, 3) and w and w[0] == 'area':
                prw = (float(w[1]), [float(x) for x in w[3:9]], int(w[10]))
        except subprocess.TimeoutExpired:
            prw = None
        try:
            g = subprocess.run(['/usr/bin/python3', '-c', GMSH, path], capture_output=True, text=True, timeout=a.timeout)
            gl = [l for l in g.stdout.splitlines() if l.startswith('GMSH')]
            gm = [float(x) for x in gl[0].split()[1:]] if gl else None
        except subprocess.TimeoutExpired:
            gm = None
        if not prw or not gm or gm[0] == 0 or prw[0] == 0:
            print('%-40s %5s %5s %14s %14s   (not compared: %s)' % (name[:40], prw[2] if prw else '-', int(gm[0]) if gm else '-',
                  '%.6g' % prw[0] if prw else '-', '%.6g' % (gm[1] * 1e-6) if gm else '-',
                  'prw has no faces' if not prw or prw[0] == 0 else 'gmsh has no surfaces'))
            continue
        ga = gm[1] * 1e-6
        gb = [x * 1e-3 for x in gm[2:8]]
        da = abs(prw[0] - ga) / ga
        diag = math.dist(gb[0:3], gb[3:6])
        db = max(abs(prw[1][k] - gb[k]) for k in range(6)) / diag if diag > 0 else 0
        worst_a, worst_b, n = max(worst_a, da), max(worst_b, db), n + 1
        print('%-40s %5d %5d %14.6g %14.6g %8.3f%% %8.3f%%' % (name[:40], prw[2], int(gm[0]), prw[0], ga, 100 * da, 100 * db),
              flush=True)
    print('\n%d files compared: largest area difference %.3f %%, largest box difference %.3f %%' %
          (n, 100 * worst_a, 100 * worst_b))


if __name__ == '__main__':
    sys.exit(main())
