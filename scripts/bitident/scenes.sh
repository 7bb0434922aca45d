# The scene set of scripts/bitident.sh: manifests written into $1 (the render tests' scenes as
# manifests, so any commit's `prw render` can render them).  Sourced, not run.
bitident_write_scenes() {
  local d=$1 a=$2   # d: output directory, a: the repository's assets/ directory
  cat > "$d/point_plane.json" <<'JSON'
{"prw_manifest": 1,
 "materials": [{"name": "lambert", "base_color": [0.5, 0.5, 0.5], "roughness": 1, "specular": 0}],
 "meshes": [{"name": "plane", "quad": {"centre": [0, 0, 0], "half_u": [0, 0, 5], "half_v": [5, 0, 0]}, "material": "lambert"}],
 "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 100, "shadows": false}],
 "cameras": [{"name": "top", "position": [0, 1, 0], "target": [0, 0, 0], "up": [0, 0, -1], "yfov_deg": 28.6479, "ev100": 0}]}
JSON
  cat > "$d/shadows.json" <<'JSON'
{"prw_manifest": 1,
 "materials": [{"name": "wall", "base_color": [0.7, 0.7, 0.7], "roughness": 0.9, "double_sided": true},
               {"name": "ball", "base_color": [0.8, 0.3, 0.2], "roughness": 0.3},
               {"name": "gold", "base_color": [1.0, 0.78, 0.34], "metallic": 1, "roughness": 0.25}],
 "meshes": [{"name": "room", "box": {"min": [-3, 0, -4], "max": [3, 3, 4], "inward": true}, "material": "wall"},
            {"name": "ball", "sphere": {"centre": [0.4, 0.6, -1], "radius": 0.6, "slices": 24, "stacks": 12}, "material": "ball"},
            {"name": "gold", "sphere": {"centre": [-0.9, 0.5, -0.4], "radius": 0.5}, "material": "gold"}],
 "lights": [{"type": "point", "position": [-1, 2.6, 0], "intensity": 200, "shadows": true},
            {"type": "spot", "position": [1.5, 2.8, 1], "direction": [-0.3, -1, -0.4], "intensity": 800,
             "inner_cone_deg": 20, "outer_cone_deg": 35, "shadows": true},
            {"type": "directional", "direction": [0.2, -1, 0.1], "intensity": 50, "shadows": true}],
 "cameras": [{"name": "main", "position": [0, 1.6, 2], "target": [0.2, 1.0, -2], "yfov_deg": 57.3, "ev100": 5}]}
JSON
  cat > "$d/far.json" <<'JSON'
{"prw_manifest": 1,
 "materials": [{"name": "m", "base_color": [0.6, 0.6, 0.5], "roughness": 0.5}],
 "meshes": [{"name": "floor", "box": {"min": [99990, -0.1, -100010], "max": [100010, 0, -99990]}, "material": "m"},
            {"name": "ball", "sphere": {"centre": [100000, 1, -100000], "radius": 1}, "material": "m"}],
 "lights": [{"type": "spot", "position": [100002, 4, -99998], "direction": [-0.4, -1, -0.4], "intensity": 3000,
             "outer_cone_deg": 40, "shadows": true}],
 "cameras": [{"name": "main", "position": [100000, 2, -99995], "target": [100000, 1, -100000], "yfov_deg": 50, "ev100": 6}]}
JSON
  cat > "$d/nurbs_shell.json" <<'JSON'
{"prw_manifest": 1,
 "materials": [{"name": "paint", "base_color": [0.6, 0.1, 0.08], "roughness": 0.35, "double_sided": true},
               {"name": "floor", "base_color": [0.5, 0.5, 0.5], "roughness": 0.8}],
 "meshes": [{"name": "floor", "box": {"min": [-3, -0.1, -5], "max": [7, 0, 3]}, "material": "floor"}],
 "nurbs": [{"name": "shell", "procedural": "car_shell", "rotation": [-0.7071067811865476, 0, 0, 0.7071067811865476],
            "material": "paint"}],
 "lights": [{"type": "directional", "direction": [-0.4, -1, -0.3], "intensity": 20000, "shadows": true}],
 "cameras": [{"name": "main", "position": [2, 2.2, 3.2], "target": [2, 0.2, -0.9], "yfov_deg": 50, "ev100": 12}]}
JSON
  cat > "$d/nurbs_box.json" <<'JSON'
{"prw_manifest": 1,
 "materials": [{"name": "glow", "base_color": [0, 0, 0], "specular": 0, "emission_cd_m2": [100, 100, 100]}],
 "nurbs": [{"name": "box", "procedural": "box", "material": "glow", "single_sided": true, "tol_px": 1}],
 "cameras": [{"name": "main", "position": [2.6, 1.9, 3.3], "target": [0, 0, 0], "yfov_deg": 55, "ev100": 6}]}
JSON
  cat > "$d/nurbs_mirror.json" <<'JSON'
{"prw_manifest": 1,
 "materials": [{"name": "paint", "base_color": [0.1, 0.3, 0.6], "roughness": 0.3}],
 "nurbs": [{"name": "box", "procedural": "box", "material": "paint", "single_sided": true},
           {"name": "mirrored", "procedural": "box", "material": "paint", "single_sided": true,
            "translation": [3.2, 0, 0], "scale": [-1, 1, 1]}],
 "lights": [{"type": "spot", "position": [1.6, 5, 4], "target": [1.6, 0, 0], "intensity": 4000, "outer_cone_deg": 50}],
 "cameras": [{"name": "main", "position": [1.6, 2.5, 7], "target": [1.6, 0, 0], "yfov_deg": 50, "ev100": 7}]}
JSON
  cat > "$d/nurbs_files.json" <<JSON
{"prw_manifest": 1,
 "materials": [{"name": "m", "base_color": [0.7, 0.7, 0.75], "roughness": 0.4, "double_sided": true}],
 "nurbs": [{"name": "sphere", "file": "$a/nurbs/sphere_rev.igs", "material": "m"},
           {"name": "plate", "file": "$a/nurbs/trimmed_plate.igs", "material": "m", "translation": [3, 0, 0]}],
 "lights": [{"type": "point", "position": [2, 5, 4], "intensity": 500, "shadows": true}],
 "cameras": [{"name": "main", "position": [1.5, 2, 8], "target": [1.5, 0, 0], "yfov_deg": 50, "ev100": 4}]}
JSON
}

# The render runs: "name|prw render arguments (scene first)"; stereo runs write -left/-right/-composed.
BITIDENT_RUNS=(
  "demo|demo"
  "demo_stereo|demo --stereo"
  "demo_hmd|demo --hmd dk2"
  "demo_ss2|demo --ss 2"
  "demo_msaa1|demo --msaa 1"
  "demo_reuse|demo --stereo --stereo-reuse reproject"
  "demo_reuse1|demo --stereo --stereo-reuse reproject --msaa 1"
  "demo_multiview|demo --stereo --views-backend multiview"
  "demo_local|demo --tonemap local"
  "point_plane|@point_plane.json --camera top"
  "shadows|@shadows.json"
  "far|@far.json"
  "nurbs_shell|@nurbs_shell.json"
  "nurbs_box|@nurbs_box.json"
  "nurbs_mirror|@nurbs_mirror.json"
  "nurbs_files|@nurbs_files.json"
)
