/* iges_models — the hand-made IGES test models (also written to assets/nurbs by
 * iges_assets_gen).  Each returns a NUL-terminated file image (caller frees). */
#ifndef IGES_MODELS_H
#define IGES_MODELS_H

#include <stdbool.h>
#include <stddef.h>

/* 120: a 100 semicircle (radius 1000 mm) revolved about a 110 axis -> sphere of radius 1 m;
 * colour from a 314 (30 %, 60 %, 90 %). */
char *iges_model_sphere_rev(size_t *len);
/* The sphere of iges_model_sphere_rev (its 100 generatrix: t = the arc's angle, -pi/2 .. pi/2,
 * from y = -1 m to y = 1 m; revolved about y) trimmed by a 144 whose 142 gives only the
 * parameter-space rectangle t0..t1 x th0..th1 in IGES (t, theta). */
char *iges_model_sphere_zone(double t0, double t1, double th0, double th1, size_t *len);
/* 144 on a 100 x 100 mm 128 plate (physically dependent): outer 142 along the domain boundary
 * (102 of 110s in (u, v) + 102 of 110s in model space), inner 142 with a (u, v) circle hole at
 * (30, 50) r 15 mm, inner 142 given only in model space (circle at (70, 50) r 10 mm, projected);
 * the 144 carries a 124 translating by (10, 0, 0) mm. */
char *iges_model_trimmed_plate(size_t *len);
/* Independent 108 (bounded by a circle r 20 at z = 5), 118 (line to semicircle), 122 (quarter
 * arc extruded 30 along z), 128 (bilinear, with a 124 rotation about z by 90° and shift), an
 * independent 126 curve, a 143 without boundaries on a dependent unit-square 128, and
 * unsupported 116, 123, 212, 406, 410. */
char *iges_model_all_entities(size_t *len);
/* One 128 unit square (0..1 in x, y) written with the given unit flag / name / model scale, and
 * `subord` for its DE; `used_by_144` adds a 144 (natural outer) that references it. */
char *iges_model_units(int unit_flag, const char *unit, double scale, int subord, int used_by_144, size_t *len);

/* B-rep solids as MSBO (186) files: a shell (514, closed) of faces (510) with loops (508) of edges
 * (504) between vertices (502); every face's surface is larger than the face (really trimmed), and
 * some faces' surfaces point inward with face orientation flag 0 (exercises the flags).
 *  - box 100 x 60 x 40 mm: six bilinear 128 planes extending 10 mm beyond the faces (bottom inward);
 *  - cylinder r 30, h 80 mm about z: lateral 120 in two halves (line revolved, inward) and two 108
 *    disks bounded by two half circles each (bottom inward);
 *  - free-form: a bicubic Bézier bump (128) over 120 x 90 mm trimmed to its part over 80 x 60 mm
 *    (isoparametric 126 edges), four 118 ruled sides down to z = 0 (two inward), a 128 bottom. */
char *iges_model_brep_box(size_t *len);
/* The same box with its faces only (physically dependent 510s no shell uses, as OpenCASCADE 6.x
 * writes free faces) and/or its planes as 190 (point 116 + normal 123). */
char *iges_model_brep_box_variant(bool faces_only, bool planes_190, size_t *len);
/* The lateral surface of the cylinder r 30, h 80 mm as a bounded surface (143) whose two
 * boundaries (141) are its end circles, each on its own (as SolidWorks writes revolved faces); the
 * top circle runs against the bottom one unless same_way. */
char *iges_model_bounded_band(bool same_way, size_t *len);
/* A bounded surface (143) on a 30 x 30 mm plane whose boundary runs back along itself: the line
 * (10, 0) -> (0, 0), then a polyline from (0, 0) back along y = 0 to (4, 0), zig-zagging +-e mm
 * across that line on the way (an edge tangent to another, with inversion noise: the ground ends of
 * occt_bug22869_Spring.igs), up to (4, 10), then (10, 10) and back to (10, 0): the face is the
 * 6 x 10 mm rectangle (60 mm^2). */
char *iges_model_spike_loop(double e, size_t *len);
/* A 100 x 60 mm rectangle trimming a 190 plane (144 with a model-space 142), and a free 190. */
char *iges_model_plane190_trimmed(size_t *len);
char *iges_model_brep_cylinder(size_t *len);
char *iges_model_brep_freeform(size_t *len);

/* Exactly converted entities (iges_models_exact.c):
 *  - conics: three 144s on 100 x 100 mm 128 planes bounded by model-space 142s (projected): a whole
 *    104 ellipse (centre (50, 40), a 30, b 15, major axis at 30°); a 104 hyperbola
 *    x²/20² - y²/10² = 1 (right branch, x <= 40) and a 104 parabola y² = 20 x (x <= 20), each
 *    closed by a 110 along its chord (102);
 *  - spline114: one 114 (metres) of 2 x 2 bicubic patches, breaks u 0, 1, 2.5 and v -1, 0.5, 1,
 *    X = u, Y = v, Z = sum iges_model_spline114_z[k][l] u^k v^l, with the unused coefficients;
 *  - offsets (metres): a 140 (d 0.25) of the 108 plane z = 0 under a 144 bounded by the square
 *    0..2 x 0..1 at z = 0.25; a 140 (d 0.25) of a 120 cylinder r 1 about z (line x = 1, z 0..3);
 *    a 140 (d -0.5) of a 120 sphere r 2 (a 100 arc about y); a 140 of a 128 plane. */
extern const double iges_model_spline114_z[4][4];
char *iges_model_conics(size_t *len);
char *iges_model_spline114(size_t *len);
char *iges_model_offsets(size_t *len);

#endif
