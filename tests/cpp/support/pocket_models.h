// Pocket regions built in code for the pocketing tests: simple shapes with
// known offsets, the topological cases of Suh & Lee's Figure 2.3, random
// free-form regions, and faces with B-spline boundaries.
#pragma once

#include <TopoDS_Face.hxx>
#include <random>
#include <vector>

#include "isocam/profile2d.h"

namespace isocam::test {

// Axis-aligned rectangle, counter-clockwise (an outer profile).
Loop rect(double x0, double y0, double x1, double y1);
// Circle as two half arcs; ccw = outer profile, cw = island.
Loop circle(double cx, double cy, double r, bool ccw);
// Two squares of side `side` joined by a corridor `neck` wide and `len` long.
Loop dumbbell(double side, double neck, double len);
// A U: w x h with a slot `slot` wide and `depth` deep cut from the top.
Loop u_shape(double w, double h, double slot, double depth);
// A star-like outer profile of lines and arcs with up to three islands
// (circles and polygons, possibly overlapping each other or the boundary).
std::vector<Loop> random_region(std::mt19937& rng);

// Planar faces (z = 0) for the pocket engine's B-rep input:
// a rectangle with circular and B-spline islands, islands that merge, an
// island that meets the boundary, a neck, a boundary of B-splines only.
TopoDS_Face face_with_islands(const std::vector<Loop>& outer_and_islands);
TopoDS_Face bspline_blob_face(double cx, double cy, double r, int lobes, double amp);
TopoDS_Face bspline_islands_face();   // 160 x 100 rectangle, 2 B-spline islands
TopoDS_Face bspline_boundary_face();  // outer profile of 4 B-spline curves, 1 circle island

// Suh & Lee's case study (section 3) rebuilt: a pocket of about 200 x 200
// mm bounded by twelve curves (lines, circular arcs, an ellipse arc and
// B-splines), with an island of eight curves, as a planar face at z = 0
// (its outline is the plan view of the pocket).
TopoDS_Face case_study_outline();
// Its floor: a smooth convex bicubic Bezier patch over [-20, 220]^2 whose
// x and y are linear in u and v (x = -20 + 240 u, y = -20 + 240 v), about
// 22 mm high in the middle.
TopoDS_Face case_study_floor();
double case_study_floor_z(double x, double y);

}  // namespace isocam::test
