// Internal: the curves where a plane of constant x (or y) meets the offset
// S + r N of one face, traced in the face's parameter domain. Used by the
// parallel-plane baseline (parallel_planes.cpp).
//
// The coordinate F(u, v) = (S + r N)(u, v)[axis] is sampled on a lattice of
// the face's parameters (every Bezier span boundary is a lattice line, the
// spans are subdivided so that a cell is about r/4 across), marching squares
// give the topology of F = c, and every vertex is then moved onto the exact
// level set by root finding along its lattice edge. Features of the level
// set smaller than a cell (a closed curve around an extremum of F that fits
// in one cell) can be missed; a cell of r/4 keeps that to spots narrower
// than the ball.
#pragma once

#include <vector>

#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"
#include "isocam/progress.h"

namespace isocam {

struct UV {
  double u = 0.0, v = 0.0;
};

// The ball centre S + r N at (u, v) of the grid, and the unit normal N.
struct OffsetPoint {
  UV uv;
  gp_Pnt centre;
  gp_Vec normal;
};
OffsetPoint offset_point(const PatchGrid& g, double u, double v, double r);

// Coordinate `axis` (0: x, 1: y) of a point.
inline double axis_coord(const gp_Pnt& p, int axis) { return axis == 0 ? p.X() : p.Y(); }

// The face's offset sampled on a lattice of its grid parameters.
class OffsetLattice {
 public:
  // Cells wholly outside the trimmed face (TrimDomain::classify_rect) are
  // marked unused: no curve is traced through them.
  OffsetLattice(const PatchGrid& grid, const TrimDomain& trim, double r);

  const PatchGrid& grid() const { return *grid_; }
  double radius() const { return r_; }
  int cells_u() const { return static_cast<int>(us_.size()) - 1; }
  int cells_v() const { return static_cast<int>(vs_.size()) - 1; }
  double u(int a) const { return us_[static_cast<std::size_t>(a)]; }
  double v(int b) const { return vs_[static_cast<std::size_t>(b)]; }
  const gp_Pnt& centre(int a, int b) const { return centres_[node(a, b)]; }
  bool used(int a, int b) const { return used_[static_cast<std::size_t>(a + cells_u() * b)] != 0; }
  // Range of the centre's coordinate over the nodes of used cells; false if
  // no cell is used.
  bool range(int axis, double* lo, double* hi) const;

 private:
  std::size_t node(int a, int b) const { return static_cast<std::size_t>(a + (cells_u() + 1) * b); }

  const PatchGrid* grid_;
  double r_;
  std::vector<double> us_, vs_;
  std::vector<gp_Pnt> centres_;
  std::vector<char> used_;
};

// One connected curve of the level set F = c: vertices (where it crosses the
// lattice edges) exactly on it, the coordinate set to c exactly. A closed
// curve repeats its first vertex at the end.
struct LevelCurve {
  int plane = 0;  // index k of the plane c = c0 + k delta
  std::vector<OffsetPoint> pts;
  bool closed = false;
};

// The curves of the planes c0 + k delta, 0 <= k < count, through the used
// cells of the lattice.
std::vector<LevelCurve> trace_levels(const OffsetLattice& lattice, int axis, double c0,
                                     double delta, int count, const ProgressSlice& progress);

// The exact level curve between its vertices, as a function of a parameter
// t. The vertices are the curve's, with more inserted where the curve
// strays from the straight parameter chord between two of them by more than
// a quarter of its length (a bulge the lattice did not see); t in [i, i+1]
// then runs from vertex i to vertex i+1, each point found where F = c on the
// line across their parameter chord (perpendicular to it, in the grid's
// parameters, within one chord length). t is taken modulo the last vertex
// index on a closed curve. Where no root is in reach (an extremum of F
// between the vertices) the point is on the straight chord between the two
// centres instead (still in the plane); `exact` says which.
class LevelCurveMap {
 public:
  LevelCurveMap(const PatchGrid& grid, const LevelCurve& curve, int axis, double level, double r);

  struct Point {
    OffsetPoint p;
    bool exact = true;
  };
  Point at(double t) const;
  double last() const { return double(pts_.size() - 1); }
  const std::vector<OffsetPoint>& vertices() const { return pts_; }
  bool closed() const { return closed_; }

 private:
  void refine(const OffsetPoint& a, const OffsetPoint& b, int depth);
  // The root of F = c nearest to the point at s along the parameter chord
  // a-b, on the line across it within `reach` chord lengths: its offset
  // along that line (in chord lengths) and the point.
  bool across(const OffsetPoint& a, const OffsetPoint& b, double s, double reach, double* w,
              OffsetPoint* out) const;

  const PatchGrid* grid_;
  std::vector<OffsetPoint> pts_;
  bool closed_;
  int axis_;
  double level_, r_;
};

}  // namespace isocam
