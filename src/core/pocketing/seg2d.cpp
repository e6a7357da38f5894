// Segments (lines and circular arcs): evaluation, bounds, nearest points.
#include <algorithm>
#include <cmath>

#include "pocketing/geom2d.h"

namespace isocam {

using namespace pocket;

Seg Seg::line(P2 from, P2 to) {
  Seg s;
  s.kind = SegKind::Line;
  s.a = from;
  s.b = to;
  return s;
}

Seg Seg::arc(P2 centre, double radius, double start_angle, double sw) {
  Seg s;
  s.kind = SegKind::Arc;
  s.c = centre;
  s.r = radius;
  s.a0 = start_angle;
  s.sweep = sw;
  s.a = centre + radius * polar(start_angle);
  s.b = centre + radius * polar(start_angle + sw);
  return s;
}

Seg Seg::arc_between(P2 centre, P2 from, P2 to, bool ccw) {
  const double t0 = angle_of(from - centre), t1 = angle_of(to - centre);
  double sw = ccw ? wrap_2pi(t1 - t0) : -wrap_2pi(t0 - t1);
  if (sw == 0.0) sw = ccw ? kTwoPi : -kTwoPi;  // from == to: a full circle
  Seg s = arc(centre, 0.5 * (dist(from, centre) + dist(to, centre)), t0, sw);
  s.a = from;
  s.b = to;
  return s;
}

double Seg::length() const { return kind == SegKind::Line ? dist(a, b) : r * std::abs(sweep); }

P2 Seg::at(double t) const {
  if (t <= 0.0) return a;
  if (t >= 1.0) return b;
  if (kind == SegKind::Line) return a + t * (b - a);
  return c + r * polar(a0 + t * sweep);
}

P2 Seg::tangent(double t) const {
  if (kind == SegKind::Line) return unit(b - a);
  const P2 u = polar(a0 + t * sweep);
  return sweep > 0 ? left_normal(u) : (-1.0) * left_normal(u);
}

Seg Seg::reversed() const {
  Seg s = *this;
  std::swap(s.a, s.b);
  if (kind == SegKind::Arc) {
    s.a0 = a0 + sweep;
    s.sweep = -sweep;
  }
  return s;
}

Seg Seg::sub(double t0, double t1) const {
  Seg s = *this;
  s.a = at(t0);
  s.b = at(t1);
  if (kind == SegKind::Arc) {
    s.a0 = a0 + t0 * sweep;
    s.sweep = (t1 - t0) * sweep;
  }
  return s;
}

double signed_area(const Loop& loop) {
  double area = 0.0;
  for (const Seg& s : loop) {
    area += 0.5 * cross(s.a, s.b);
    if (s.kind == SegKind::Arc) area += 0.5 * s.r * s.r * (s.sweep - std::sin(s.sweep));
  }
  return area;
}

double loop_length(const Loop& loop) {
  double len = 0.0;
  for (const Seg& s : loop) len += s.length();
  return len;
}

Loop reversed(const Loop& loop) {
  Loop out;
  out.reserve(loop.size());
  for (auto it = loop.rbegin(); it != loop.rend(); ++it) out.push_back(it->reversed());
  return out;
}

double region_area(const std::vector<Loop>& loops) {
  double a = 0.0;
  for (const Loop& l : loops) a += signed_area(l);
  return a;
}

NearestOnLoops nearest_on_loops(const std::vector<Loop>& loops, P2 p) {
  NearestOnLoops best;
  best.distance = 1e300;
  for (std::size_t i = 0; i < loops.size(); ++i)
    for (std::size_t j = 0; j < loops[i].size(); ++j) {
      const SegNearest n = nearest_on_seg(loops[i][j], p);
      if (n.d < best.distance) {
        best.distance = n.d;
        best.loop = static_cast<int>(i);
        best.seg = static_cast<int>(j);
        best.t = n.t;
        best.point = n.p;
      }
    }
  return best;
}

namespace pocket {

Box2 seg_box(const Seg& s) {
  Box2 b;
  b.add(s.a);
  b.add(s.b);
  if (s.kind == SegKind::Arc) {
    // The axis-extreme points of the circle that the arc passes.
    for (int k = 0; k < 4; ++k) {
      const double ang = k * 0.5 * kPi;
      const double t = arc_param_of_angle(s, ang, 0.0);
      if (t > 0.0 && t < 1.0) b.add(s.c + s.r * polar(ang));
    }
  }
  return b;
}

Box2 loops_box(const std::vector<Loop>& loops) {
  Box2 b;
  for (const Loop& l : loops)
    for (const Seg& s : l) b.add(seg_box(s));
  return b;
}

double default_snap(const std::vector<Loop>& loops) {
  const Box2 b = loops_box(loops);
  return std::max(1e-9, 1e-7 * b.size());
}

double arc_param_of_angle(const Seg& arc, double theta, double eps_t) {
  const double span = std::abs(arc.sweep);
  if (span <= 0.0) return -1.0;
  double s = arc.sweep > 0 ? wrap_2pi(theta - arc.a0) : wrap_2pi(arc.a0 - theta);
  // Near the start from below wraps to just under 2 pi.
  if (s > span + eps_t * span && s > kTwoPi - eps_t * span) s -= kTwoPi;
  return s / span;
}

SegNearest nearest_on_seg(const Seg& s, P2 p) {
  SegNearest n;
  if (s.kind == SegKind::Line) {
    const P2 d = s.b - s.a;
    const double l2 = dot(d, d);
    n.t = l2 > 0 ? std::clamp(dot(p - s.a, d) / l2, 0.0, 1.0) : 0.0;
    n.p = s.at(n.t);
  } else {
    const double t = arc_param_of_angle(s, angle_of(p - s.c), 0.0);
    if (t >= 0.0 && t <= 1.0 && dist(p, s.c) > 0.0) {
      n.t = t;
      n.p = s.at(t);
    } else {
      n.t = dist(p, s.a) <= dist(p, s.b) ? 0.0 : 1.0;
      n.p = n.t == 0.0 ? s.a : s.b;
    }
  }
  n.d = dist(p, n.p);
  return n;
}

P2 start_tangent(const Seg& s) { return s.tangent(0.0); }
P2 end_tangent(const Seg& s) { return s.tangent(1.0); }

P2 point_near_start(const Seg& s, double h) {
  const double len = s.length();
  if (len <= 0) return s.a;
  return s.at(std::min(0.5, h / len));
}

P2 point_near_end(const Seg& s, double h) {
  const double len = s.length();
  if (len <= 0) return s.b;
  return s.at(1.0 - std::min(0.5, h / len));
}

SegGrid::SegGrid(const std::vector<Seg>& segs, double cell) : segs_(segs) {
  Box2 b;
  for (const Seg& s : segs_) b.add(seg_box(s));
  if (b.empty()) return;
  cell_ = std::max(cell, 1e-3 * b.size());
  x0_ = b.x0;
  y0_ = b.y0;
  nx_ = static_cast<long>((b.x1 - b.x0) / cell_) + 1;
  ny_ = static_cast<long>((b.y1 - b.y0) / cell_) + 1;
  cells_.assign(static_cast<std::size_t>(nx_ * ny_), {});
  for (std::size_t k = 0; k < segs_.size(); ++k) {
    const Box2 sb = seg_box(segs_[k]);
    for (long j = static_cast<long>((sb.y0 - y0_) / cell_);
         j <= static_cast<long>((sb.y1 - y0_) / cell_); ++j)
      for (long i = static_cast<long>((sb.x0 - x0_) / cell_);
           i <= static_cast<long>((sb.x1 - x0_) / cell_); ++i)
        cells_[static_cast<std::size_t>(std::min(j, ny_ - 1) * nx_ + std::min(i, nx_ - 1))]
            .push_back(static_cast<int>(k));
  }
}

double SegGrid::distance(P2 p) const {
  if (cells_.empty()) return 1e300;
  const long ci = std::clamp(static_cast<long>(std::floor((p.x - x0_) / cell_)), 0L, nx_ - 1);
  const long cj = std::clamp(static_cast<long>(std::floor((p.y - y0_) / cell_)), 0L, ny_ - 1);
  // Distance from p to the nearest point of the grid's rectangle.
  const double ox = std::max({0.0, x0_ - p.x, p.x - (x0_ + static_cast<double>(nx_) * cell_)});
  const double oy = std::max({0.0, y0_ - p.y, p.y - (y0_ + static_cast<double>(ny_) * cell_)});
  const double outside = std::hypot(ox, oy);
  double best = 1e300;
  const long kmax = std::max(nx_, ny_);
  for (long k = 0; k <= kmax; ++k) {
    // Cells of ring k are at least (k - 1) cells away from p.
    if (best < outside + static_cast<double>(k - 1) * cell_) break;
    for (long j = cj - k; j <= cj + k; ++j) {
      if (j < 0 || j >= ny_) continue;
      const bool edge_row = j == cj - k || j == cj + k;
      for (long i = ci - k; i <= ci + k; i += (edge_row ? 1 : 2 * std::max(k, 1L))) {
        if (i < 0 || i >= nx_) continue;
        for (int s : cells_[static_cast<std::size_t>(j * nx_ + i)])
          best = std::min(best, nearest_on_seg(segs_[static_cast<std::size_t>(s)], p).d);
      }
    }
  }
  return best;
}

int VertexSet::insert(P2 p) {
  const auto ci = static_cast<std::int64_t>(std::floor(p.x / cell_));
  const auto cj = static_cast<std::int64_t>(std::floor(p.y / cell_));
  int best = -1;
  double best_d = snap_;
  for (std::int64_t di = -1; di <= 1; ++di)
    for (std::int64_t dj = -1; dj <= 1; ++dj) {
      auto it = grid_.find(key(ci + di, cj + dj));
      if (it == grid_.end()) continue;
      for (int id : it->second) {
        const double d = dist(pts_[static_cast<std::size_t>(id)], p);
        if (d <= best_d) {
          best_d = d;
          best = id;
        }
      }
    }
  if (best >= 0) return best;
  pts_.push_back(p);
  const int id = static_cast<int>(pts_.size()) - 1;
  grid_[key(ci, cj)].push_back(id);
  return id;
}

}  // namespace pocket
}  // namespace isocam
