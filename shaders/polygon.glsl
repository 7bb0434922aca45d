// polygon.glsl — Lambert's formula for the cosine-weighted solid angle of a convex polygon clipped to a
// hemisphere (the rect lights' irradiance in lights.glsl, the LTC integral in ltc.glsl).
// materials/prw_ltc.c restates lambert_edge and clip_edge in C (the LTC's twin): keep them in step.
#ifndef PRW_POLYGON_GLSL
#define PRW_POLYGON_GLSL

// Lambert's formula for one edge a -> b of a polygon seen from the origin: the angle it subtends times
// the unit normal of the plane through it.
vec3 lambert_edge(vec3 a, vec3 b)
{
    vec3 v0 = normalize(a), v1 = normalize(b);
    vec3 cr = cross(v0, v1);
    float l = length(cr);
    return l > 1e-9 ? atan(l, dot(v0, v1)) * (cr / l) : vec3(0.0);
}

// The edge a -> b of a convex polygon (relative to the receiver) clipped to the hemisphere of n: adds the
// part above the horizon to sum and records where the polygon leaves (exit_pt) or re-enters (entry_pt)
// the hemisphere, so the caller closes it along the horizon.  (No local array: lavapipe makes a
// dynamically indexed one cost ~300 ms a frame at 1280x720 even when the code never runs.  One
// lambert_edge call on the clipped ends, chosen by selects: lavapipe runs every branch, and a call per
// case cost three of them per edge.)
void clip_edge(vec3 a, vec3 b, vec3 n, inout vec3 sum, inout vec3 exit_pt, inout vec3 entry_pt, inout int above)
{
    float da = dot(n, a), db = dot(n, b);
    bool ua = da > 0.0, ub = db > 0.0;
    vec3 cut = a + (b - a) * (da / (da - db)); // used only when exactly one end is above
    if (ua) above++;
    if (ua && !ub) exit_pt = cut;
    if (!ua && ub) entry_pt = cut;
    if (ua || ub) sum += lambert_edge(ua ? a : cut, ub ? b : cut);
}

// The quad a..d (relative to the receiver, convex, planar) clipped to the hemisphere of n: the sum of its
// edges' Lambert terms (E / L = 1/2 |n . sum|); false when nothing is above the horizon.
bool quad_edge_sum(vec3 a, vec3 b, vec3 c, vec3 d, vec3 n, out vec3 sum)
{
    sum = vec3(0.0);
    vec3 exit_pt = vec3(0.0), entry_pt = vec3(0.0);
    int above = 0;
    clip_edge(a, b, n, sum, exit_pt, entry_pt, above);
    clip_edge(b, c, n, sum, exit_pt, entry_pt, above);
    clip_edge(c, d, n, sum, exit_pt, entry_pt, above);
    clip_edge(d, a, n, sum, exit_pt, entry_pt, above);
    if (above == 0) return false;
    if (above < 4) sum += lambert_edge(exit_pt, entry_pt); // along the horizon
    return true;
}

#endif
