#!/bin/sh
# iges_measure_check.sh MEASURE MODEL AREA REL: iges_measure's area of MODEL is AREA (m^2) within REL.
# (assets/nurbs/sphere_rev.igs: a unit sphere of revolution, 4 pi; its poles are collapsed edges, where
# the tessellation's (u, v) fans covered 3.4e-4 too little.)
out=$("$1" "$2") || { echo "iges_measure failed on $2"; exit 1; }
echo "$out"
echo "$out" | awk -v want="$3" -v rel="$4" '$1 == "area" { d = $2 / want - 1; if (d < 0) d = -d;
  printf "area %.10g, expected %.10g: relative error %.3g (limit %g)\n", $2, want, d, rel; ok = d <= rel }
  END { exit ok ? 0 : 1 }'
