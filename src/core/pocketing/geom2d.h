// Small 2D helpers shared by the pocketing files (not public API).
#pragma once

#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "isocam/profile2d.h"

namespace isocam::pocket {

constexpr double kPi = 3.14159265358979323846;
constexpr double kTwoPi = 2.0 * kPi;

inline P2 operator+(P2 a, P2 b) { return {a.x + b.x, a.y + b.y}; }
inline P2 operator-(P2 a, P2 b) { return {a.x - b.x, a.y - b.y}; }
inline P2 operator*(double s, P2 a) { return {s * a.x, s * a.y}; }
inline double dot(P2 a, P2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(P2 a, P2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(P2 a) { return std::hypot(a.x, a.y); }
inline double dist(P2 a, P2 b) { return norm(a - b); }
inline P2 unit(P2 a) {
  const double n = norm(a);
  return n > 0 ? (1.0 / n) * a : P2{1.0, 0.0};
}
inline P2 left_normal(P2 t) { return {-t.y, t.x}; }
inline P2 polar(double angle) { return {std::cos(angle), std::sin(angle)}; }
inline double angle_of(P2 v) { return std::atan2(v.y, v.x); }

// Angle in [0, 2 pi).
inline double wrap_2pi(double a) {
  a = std::fmod(a, kTwoPi);
  return a < 0 ? a + kTwoPi : a;
}
// Angle in (-pi, pi].
inline double wrap_pi(double a) {
  a = wrap_2pi(a);
  return a > kPi ? a - kTwoPi : a;
}

struct Box2 {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  void add(P2 p) {
    x0 = std::min(x0, p.x);
    y0 = std::min(y0, p.y);
    x1 = std::max(x1, p.x);
    y1 = std::max(y1, p.y);
  }
  void add(const Box2& b) {
    x0 = std::min(x0, b.x0);
    y0 = std::min(y0, b.y0);
    x1 = std::max(x1, b.x1);
    y1 = std::max(y1, b.y1);
  }
  bool empty() const { return x0 > x1; }
  bool overlaps(const Box2& b, double eps) const {
    return x0 <= b.x1 + eps && b.x0 <= x1 + eps && y0 <= b.y1 + eps && b.y0 <= y1 + eps;
  }
  double size() const { return empty() ? 0.0 : std::max(x1 - x0, y1 - y0); }
};

Box2 seg_box(const Seg& s);
Box2 loops_box(const std::vector<Loop>& loops);

// The snapping distance used when `snap` is 0: 1e-7 of the size, at least 1e-9.
double default_snap(const std::vector<Loop>& loops);

// Parameter of the point of an arc at angle `theta`, allowing `eps_t`
// beyond either end (returns a value outside [-eps_t, 1 + eps_t] if the
// angle is not on the arc).
double arc_param_of_angle(const Seg& arc, double theta, double eps_t);

// Nearest point of a segment to p: parameter and distance.
struct SegNearest {
  double t = 0.0, d = 0.0;
  P2 p;
};
SegNearest nearest_on_seg(const Seg& s, P2 p);

// Tangent (unit) at the start/end, and curvature signed (> 0 turning left).
P2 start_tangent(const Seg& s);
P2 end_tangent(const Seg& s);

// A point a short arc length `h` (< length) from the start of `s`, or from
// its end going backwards.
P2 point_near_start(const Seg& s, double h);
P2 point_near_end(const Seg& s, double h);

// Points within `snap` of each other share one index.
class VertexSet {
 public:
  explicit VertexSet(double snap) : snap_(snap), cell_(4.0 * snap) {}
  int insert(P2 p);
  const P2& operator[](int i) const { return pts_[static_cast<std::size_t>(i)]; }
  int size() const { return static_cast<int>(pts_.size()); }

 private:
  std::int64_t key(std::int64_t i, std::int64_t j) const { return i * 73856093LL ^ j * 19349663LL; }
  double snap_, cell_;
  std::vector<P2> pts_;
  std::unordered_map<std::int64_t, std::vector<int>> grid_;
};

// Nearest segment queries on a uniform grid of segment bounding boxes.
class SegGrid {
 public:
  SegGrid(const std::vector<Seg>& segs, double cell);
  // Distance from p to the nearest segment (1e300 if there is none).
  double distance(P2 p) const;
  const std::vector<Seg>& segs() const { return segs_; }

 private:
  std::vector<Seg> segs_;
  double x0_ = 0, y0_ = 0, cell_ = 1;
  long nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> cells_;
};

// Intersections of two segments. Each hit gives the parameters on both and
// the point. Overlapping collinear lines or co-circular arcs give the ends
// of the overlap. Hits within `eps` (a length) of an end are clamped to it.
struct Hit {
  double t1 = 0.0, t2 = 0.0;
  P2 p;
};
void intersect_segs(const Seg& s1, const Seg& s2, double eps, std::vector<Hit>& out);

// The raw offset curve of one closed loop by d to the left (offset2d.cpp).
Loop raw_offset(const Loop& loop, double d, double snap);

// Winding numbers of a fixed set of segments (closed loops) by counting
// signed crossings of the ray from p towards +x with y-monotone pieces.
class WindingIndex {
 public:
  explicit WindingIndex(const std::vector<Seg>& segs);
  int at(P2 p) const;

 private:
  struct Piece {
    double y0, y1;          // y0 < y1
    double xa, ya, xb, yb;  // line: end points; arc: unused except ya/yb
    double cx, cy, r;       // arc
    bool arc, right;        // arc on the half x >= cx
    int dir;                // +1 going up, -1 going down
  };
  double x_at(const Piece& pc, double y) const;
  std::vector<Piece> pieces_;
  std::vector<std::vector<int>> bands_;
  double ymin_ = 0.0, band_h_ = 1.0;
};

}  // namespace isocam::pocket
