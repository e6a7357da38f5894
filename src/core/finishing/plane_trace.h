// Internal: the curves where a plane of constant x (or y) meets the offset
// S + r N of one face, traced in the face's parameter domain. Used by the
// parallel-plane baseline (parallel_planes.cpp).
//
// The coordinate F = (S + r N)[axis] is sampled on a lattice of the face's
// parameters (every Bezier span boundary is a lattice line, the spans are
// subdivided so that a cell is about r/4 across, a crease gets a strip where
// the ball rolls around it), marching squares give the topology of F = c,
// and every vertex is then moved onto the exact level set by root finding
// along its lattice edge; between vertices the curve is found across their
// chord, with vertices added where it bulges away. Features of the level set
// smaller than a cell (a closed curve around an extremum of F that fits in
// one cell) can be missed; a cell of r/4 keeps that to spots narrower than
// the ball. Where the curve cannot be found between two vertices (rare: a
// turn of the level set the lattice joined wrongly) the caller leaves a gap.
#pragma once

#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <vector>

#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"
#include "isocam/progress.h"

namespace isocam {

struct UV {
  double u = 0.0, v = 0.0;
};

// A ball centre on the offset: where (lattice coordinates, see
// OffsetLattice, and the grid parameters of the contact point), the centre
// and the unit normal it is offset along.
struct OffsetPoint {
  UV lc;
  UV uv;
  gp_Pnt centre;
  gp_Vec normal;
};

// Coordinate `axis` (0: x, 1: y) of a point.
inline double axis_coord(const gp_Pnt& p, int axis) { return axis == 0 ? p.X() : p.Y(); }

// The face's offset sampled on a lattice of its grid parameters, and
// evaluated continuously in the lattice's coordinates: (x, y) in
// [0, cells_u()] x [0, cells_v()], node (a, b) at integer coordinates, each
// cell a unit square. Every Bezier span boundary is a lattice line. Where
// the face has a crease (a span boundary across which the normal jumps) the
// lattice has a strip of zero width in the parameters there: across it the
// contact point stays on the crease and the normal turns from one side's to
// the other's, the ball rolling around the crease (at a concave crease this
// strip is inside the offsets, and the clearance check cuts it away). So the
// offset is continuous in lattice coordinates even where it is not in (u, v).
class OffsetLattice {
 public:
  // Cells wholly outside the trimmed face (TrimDomain::classify_rect) are
  // marked unused: no curve is traced through them.
  OffsetLattice(const PatchGrid& grid, const TrimDomain& trim, double r);

  int cells_u() const { return static_cast<int>(us_.size()); }
  int cells_v() const { return static_cast<int>(vs_.size()); }
  const gp_Pnt& centre(int a, int b) const { return centres_[node(a, b)]; }
  bool used(int a, int b) const { return used_[static_cast<std::size_t>(a + cells_u() * b)] != 0; }
  // Range of the centre's coordinate over the nodes of used cells; false if
  // no cell is used.
  bool range(int axis, double* lo, double* hi) const;
  // The offset at lattice coordinates (x, y), clamped to the lattice.
  OffsetPoint at(double x, double y) const;

  // A strip between two adjacent lattice lines: parameters p0..p1 within
  // span `span`, or a crease strip (hi >= 0): p0 == p1, the break between
  // span `span` below and span `hi` above.
  struct Strip {
    double p0 = 0.0, p1 = 0.0;
    int span = 0, hi = -1;
  };

 private:
  std::size_t node(int a, int b) const { return static_cast<std::size_t>(a + (cells_u() + 1) * b); }
  gp_Vec normal_on(int iu, int jv, double u, double v, gp_Pnt* p) const;

  const PatchGrid* grid_;
  double r_;
  std::vector<Strip> us_, vs_;
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
// strays from the straight chord between two of them in lattice coordinates
// by more than a quarter of its length (a bulge the lattice did not see); t
// in [i, i+1] then runs from vertex i to vertex i+1, each point found where
// F = c on the line across their chord (perpendicular to it, in lattice
// coordinates, within one chord length). t is taken modulo the last vertex
// index on a closed curve. Where no root is in reach (an extremum of F
// between the vertices) the point is on the straight chord between the two
// centres instead (still in the plane); `exact` says which.
class LevelCurveMap {
 public:
  LevelCurveMap(const OffsetLattice& lattice, const LevelCurve& curve, int axis, double level);

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
  // The root of F = c nearest to the point at s along the lattice chord
  // a-b, on the line across it within `reach` chord lengths: its offset
  // along that line (in chord lengths) and the point.
  bool across(const OffsetPoint& a, const OffsetPoint& b, double s, double reach, double* w,
              OffsetPoint* out) const;

  const OffsetLattice* lattice_;
  std::vector<OffsetPoint> pts_;
  bool closed_;
  int axis_;
  double level_;
};

}  // namespace isocam
