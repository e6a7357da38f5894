// Planar profiles made of line segments and circular arcs, and their exact
// offsets (Suh & Lee, "NC Tool Path Generation of Arbitrarily Shaped
// Pockets", sections 2.1-2.2).
//
// A Loop is a closed chain of segments (segs[i].b == segs[i+1].a). A set of
// loops describes the region of the points whose winding number is >= 1:
// an outer profile runs counter-clockwise, an island (hole) clockwise, so the
// region is always on the left of every segment. (Suh & Lee direct the
// boundary clockwise and remove counter-clockwise loops; this is the same
// rule with the other sign.)
//
// Offsets are exact for lines and arcs: the offset of an arc is an arc with
// the same centre. Each loop becomes a "raw" offset curve (offset2d.cpp:
// every piece moved by d along its left normal, an arc of radius d about
// every corner turning right -- Suh & Lee's Figure 2.7(c) -- and a path
// through the corner where it turns left), and the raw curves of all loops
// are resolved together by the positive-winding rule (boolean2d.cpp). That
// one step removes the self-loops of a profile (section 2.2, Figure 2.8,
// including the nested case of Figure 2.10), joins a shrunk boundary and a
// grown island into "lakes" (Figure 2.3(c)-(d)), merges grown islands
// (Figure 2.3(e)-(f)) and splits a region at a neck; a profile that
// vanishes simply yields no loop. The result is exactly the set of points
// of the region farther than d from its boundary (up to the snapping
// distance, 1e-7 of the model size).
#pragma once

#include <cstdint>
#include <vector>

namespace isocam {

struct P2 {
  double x = 0.0, y = 0.0;
};

enum class SegKind : std::uint8_t { Line = 0, Arc = 1 };

// A line from a to b, or an arc from a to b about c of radius r that starts
// at angle a0 and sweeps `sweep` radians (> 0 counter-clockwise, < 0
// clockwise, |sweep| <= 2 pi). For an arc, a and b are its end points as
// shared with the neighbouring segments; they lie within the snapping
// distance (about 1e-7 of the model size) of c + r (cos, sin)(angle).
struct Seg {
  SegKind kind = SegKind::Line;
  P2 a, b;
  P2 c;
  double r = 0.0;
  double a0 = 0.0;
  double sweep = 0.0;

  static Seg line(P2 from, P2 to);
  static Seg arc(P2 centre, double radius, double start_angle, double sweep);
  // Arc from `from` to `to` about `centre`, sweeping in the given direction
  // (the sweep is in (0, 2 pi] for ccw, [-2 pi, 0) for cw).
  static Seg arc_between(P2 centre, P2 from, P2 to, bool ccw);

  double length() const;
  P2 at(double t) const;       // t in [0, 1]
  P2 tangent(double t) const;  // unit tangent along the direction of travel
  Seg reversed() const;
  Seg sub(double t0, double t1) const;  // the part between two parameters
};

using Loop = std::vector<Seg>;

// Signed area (> 0 counter-clockwise), exact for lines and arcs (eq. 4 of
// Suh & Lee for the polygon part plus the circular segments).
double signed_area(const Loop& loop);
double loop_length(const Loop& loop);
Loop reversed(const Loop& loop);

// Winding number of the loops around p (p not on a loop).
int winding_number(const std::vector<Loop>& loops, P2 p);

// Offsets `loops` (a region, see above) by d >= 0 to the left of every
// segment: the region shrinks by d (its boundary moves inward, its islands
// grow). Returns the loops of the offset region, each with the region on
// its left; empty when the region vanishes. `snap` is the distance below
// which two points are taken to be one (0: 1e-7 of the loops' size).
std::vector<Loop> offset_region(const std::vector<Loop>& loops, double d, double snap = 0.0);

// The region of the winding number >= 1 of arbitrary closed loops
// (self-intersecting, overlapping, nested), as loops with it on their left.
std::vector<Loop> resolve_loops(const std::vector<Loop>& loops, double snap = 0.0);

// The region grown by d >= 0 (Minkowski sum with a disk of radius d).
std::vector<Loop> dilate_region(const std::vector<Loop>& loops, double d, double snap = 0.0);

// Loops of a region grouped into connected components: the outer loop
// first, then the islands inside it.
std::vector<std::vector<Loop>> region_components(const std::vector<Loop>& loops);

// Area of a region (sum of the signed areas of its loops).
double region_area(const std::vector<Loop>& loops);

// Distance from p to the nearest point of the loops, with that point's
// loop, segment and parameter.
struct NearestOnLoops {
  double distance = 0.0;
  int loop = -1, seg = -1;
  double t = 0.0;
  P2 point;
};
NearestOnLoops nearest_on_loops(const std::vector<Loop>& loops, P2 p);

}  // namespace isocam
