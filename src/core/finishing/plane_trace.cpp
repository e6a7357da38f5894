// Level sets of one coordinate of the ball centre over a face's offset:
// sampling lattice, marching squares, exact vertices (see plane_trace.h).
#include "finishing/plane_trace.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <unordered_map>

namespace isocam {
namespace {

// Root of f on the bracket [a, b] (f(a) = fa and f(b) = fb of opposite
// signs, or one of them zero) by the Illinois variant of regula falsi:
// superlinear on smooth f, never leaves the bracket. Stops when |f| <= ftol
// or the bracket no longer shrinks in floating point.
double illinois(const std::function<double(double)>& f, double a, double fa, double b, double fb,
                double ftol) {
  for (int it = 0; it < 200; ++it) {
    if (std::abs(fb) <= ftol) return b;
    if (std::abs(fa) <= ftol) return a;
    double s = b - fb * (b - a) / (fb - fa);
    if (!(s > std::min(a, b) && s < std::max(a, b))) s = 0.5 * (a + b);
    if (s == a || s == b) break;
    const double fs = f(s);
    if ((fs < 0) != (fb < 0)) {
      a = b;
      fa = fb;
    } else {
      fa *= 0.5;
    }
    b = s;
    fb = fs;
  }
  return std::abs(fa) < std::abs(fb) ? a : b;
}

// Evaluation accuracy of a centre coordinate; coordinates are some 1e3 mm
// at most, evaluated to about 1e-13 of that.
constexpr double kLevelTol = 1e-10;

}  // namespace

namespace {

// Marching squares over the cells of one plane. Edge ids: 2 node for the
// lattice edge from node (a, b) along u, 2 node + 1 along v.
class PlaneTracer {
 public:
  PlaneTracer(const OffsetLattice& l, int axis, double level) : l_(l), axis_(axis), level_(level) {}

  std::vector<LevelCurve> trace(const std::vector<int>& cells, int plane) {
    for (int cell : cells) add_cell(cell % l_.cells_u(), cell / l_.cells_u());
    std::vector<LevelCurve> out;
    std::vector<char> done(segs_.size(), 0);
    // Open chains first (they end at an edge seen by one cell: the lattice
    // boundary or an unused cell), then what is left is closed loops.
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t s = 0; s < segs_.size(); ++s) {
        if (done[s]) continue;
        long start = segs_[s][0];
        if (pass == 0) {
          if (count(segs_[s][1]) == 1)
            start = segs_[s][1];
          else if (count(start) != 1)
            continue;
        }
        LevelCurve c = chain(static_cast<int>(s), start, &done);
        c.plane = plane;
        c.closed = pass == 1;
        if (c.pts.size() >= 2) out.push_back(std::move(c));
      }
    }
    return out;
  }

 private:
  double g(int a, int b) const { return axis_coord(l_.centre(a, b), axis_) - level_; }
  long edge(int a, int b, bool along_v) const {
    return 2L * (a + long(l_.cells_u() + 1) * b) + (along_v ? 1 : 0);
  }
  int count(long e) const {
    const auto it = links_.find(e);
    return it == links_.end() ? 0 : (it->second[1] >= 0 ? 2 : 1);
  }

  void add_cell(int a, int b) {
    const double g00 = g(a, b), g10 = g(a + 1, b), g11 = g(a + 1, b + 1), g01 = g(a, b + 1);
    const bool s00 = g00 >= 0, s10 = g10 >= 0, s11 = g11 >= 0, s01 = g01 >= 0;
    const long bottom = edge(a, b, false), right = edge(a + 1, b, true);
    const long top = edge(a, b + 1, false), left = edge(a, b, true);
    std::array<long, 4> cross;
    int n = 0;
    if (s00 != s10) cross[static_cast<std::size_t>(n++)] = bottom;
    if (s10 != s11) cross[static_cast<std::size_t>(n++)] = right;
    if (s11 != s01) cross[static_cast<std::size_t>(n++)] = top;
    if (s01 != s00) cross[static_cast<std::size_t>(n++)] = left;
    if (n == 2) {
      add_seg(cross[0], cross[1]);
    } else if (n == 4) {
      // A saddle: the asymptotic decider (the bilinear interpolant's value
      // at its saddle point) says which pair of corners is connected.
      const double centre = (g00 * g11 - g10 * g01) / (g00 + g11 - g10 - g01);
      if ((centre >= 0) == s00) {
        add_seg(bottom, right);  // cuts off corner (a+1, b)
        add_seg(top, left);      // and corner (a, b+1)
      } else {
        add_seg(left, bottom);
        add_seg(right, top);
      }
    }
  }

  void add_seg(long e0, long e1) {
    const int s = static_cast<int>(segs_.size());
    segs_.push_back({e0, e1});
    for (long e : {e0, e1}) {
      auto it = links_.try_emplace(e, std::array<int, 2>{-1, -1}).first;
      it->second[it->second[0] < 0 ? 0 : 1] = s;
    }
  }

  LevelCurve chain(int s, long start, std::vector<char>* done) {
    LevelCurve c;
    long e = start;
    for (;;) {
      push_vertex(&c, e);
      (*done)[static_cast<std::size_t>(s)] = 1;
      e = segs_[static_cast<std::size_t>(s)][0] == e ? segs_[static_cast<std::size_t>(s)][1]
                                                     : segs_[static_cast<std::size_t>(s)][0];
      const std::array<int, 2>& on = links_.at(e);
      int next = -1;
      for (int k : on)
        if (k >= 0 && !(*done)[static_cast<std::size_t>(k)]) next = k;
      if (next < 0) break;
      s = next;
    }
    push_vertex(&c, e);
    return c;
  }

  void push_vertex(LevelCurve* c, long e) {
    const OffsetPoint p = crossing(e);
    // A root exactly on a lattice node is shared by the node's edges.
    if (!c->pts.empty() && c->pts.back().uv.u == p.uv.u && c->pts.back().uv.v == p.uv.v) return;
    c->pts.push_back(p);
  }

  // The exact point where F = level on lattice edge e (the lattice values
  // at its nodes bracket the level).
  OffsetPoint crossing(long e) {
    const auto hit = vertices_.find(e);
    if (hit != vertices_.end()) return hit->second;
    const long nodes = e / 2;
    const int a = static_cast<int>(nodes % (l_.cells_u() + 1));
    const int b = static_cast<int>(nodes / (l_.cells_u() + 1));
    const int a1 = a + ((e & 1) ? 0 : 1), b1 = b + ((e & 1) ? 1 : 0);
    auto point = [&](double s) { return l_.at(a + (a1 - a) * s, b + (b1 - b) * s); };
    auto f = [&](double s) { return axis_coord(point(s).centre, axis_) - level_; };
    const double s = illinois(f, 0.0, g(a, b), 1.0, g(a1, b1), kLevelTol);
    OffsetPoint p = point(s);
    (axis_ == 0 ? p.centre.SetX(level_) : p.centre.SetY(level_));
    vertices_.emplace(e, p);
    return p;
  }

  const OffsetLattice& l_;
  int axis_;
  double level_;
  std::vector<std::array<long, 2>> segs_;
  std::unordered_map<long, std::array<int, 2>> links_;  // edge -> its segments
  std::unordered_map<long, OffsetPoint> vertices_;
};

}  // namespace

std::vector<LevelCurve> trace_levels(const OffsetLattice& l, int axis, double c0, double delta,
                                     int count, const ProgressSlice& progress) {
  // Each used cell goes to the planes that separate its corners: a corner
  // is on the high side of plane c when its value is >= c, so the cell meets
  // the planes with lo < c <= hi.
  std::vector<std::vector<int>> cells(static_cast<std::size_t>(std::max(count, 0)));
  for (int b = 0; b < l.cells_v(); ++b) {
    for (int a = 0; a < l.cells_u(); ++a) {
      if (!l.used(a, b)) continue;
      double lo = 1e300, hi = -1e300;
      for (int k = 0; k < 4; ++k) {
        const double x = axis_coord(l.centre(a + (k & 1), b + (k >> 1)), axis);
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
      int k0 = static_cast<int>(std::max(0.0, std::floor((lo - c0) / delta)));
      while (k0 < count && c0 + k0 * delta <= lo) ++k0;
      for (int k = k0; k < count && c0 + k * delta <= hi; ++k)
        cells[static_cast<std::size_t>(k)].push_back(a + l.cells_u() * b);
    }
  }
  std::vector<LevelCurve> out;
  for (int k = 0; k < count; ++k) {
    progress.check();
    if (cells[static_cast<std::size_t>(k)].empty()) continue;
    PlaneTracer tracer(l, axis, c0 + k * delta);
    for (LevelCurve& c : tracer.trace(cells[static_cast<std::size_t>(k)], k))
      out.push_back(std::move(c));
    progress.report(double(k + 1) / count);
  }
  return out;
}

LevelCurveMap::LevelCurveMap(const OffsetLattice& lattice, const LevelCurve& curve, int axis,
                             double level)
    : lattice_(&lattice), closed_(curve.closed), axis_(axis), level_(level) {
  pts_.push_back(curve.pts.front());
  for (std::size_t i = 0; i + 1 < curve.pts.size(); ++i) refine(curve.pts[i], curve.pts[i + 1], 0);
}

void LevelCurveMap::refine(const OffsetPoint& a, const OffsetPoint& b, int depth) {
  // Where the curve strays from its parameter chord by more than a quarter
  // of the chord's length (it left the lattice cell through one edge and
  // came back through the same edge: two crossings the lattice cannot see),
  // its point across the chord's middle becomes a vertex.
  double w = 0.0;
  OffsetPoint q;
  if (depth < 8 && across(a, b, 0.5, 4.0, &w, &q) && std::abs(w) > 0.25) {
    refine(a, q, depth + 1);
    refine(q, b, depth + 1);
    return;
  }
  pts_.push_back(b);
}

bool LevelCurveMap::across(const OffsetPoint& a, const OffsetPoint& b, double s, double reach,
                           double* w_out, OffsetPoint* out) const {
  const UV& A = a.lc;
  const UV& B = b.lc;
  const UV m{A.u + (B.u - A.u) * s, A.v + (B.v - A.v) * s};
  const UV d{-(B.v - A.v), B.u - A.u};  // across the chord, as long as it
  // Reach along d: `reach` chord lengths either way, within the lattice.
  double lo = -reach, hi = reach;
  auto limit = [&](double x, double dx, double xmin, double xmax) {
    if (dx > 0) {
      hi = std::min(hi, (xmax - x) / dx);
      lo = std::max(lo, (xmin - x) / dx);
    } else if (dx < 0) {
      hi = std::min(hi, (xmin - x) / dx);
      lo = std::max(lo, (xmax - x) / dx);
    }
  };
  limit(m.u, d.u, 0.0, lattice_->cells_u());
  limit(m.v, d.v, 0.0, lattice_->cells_v());
  auto point = [&](double w) { return lattice_->at(m.u + d.u * w, m.v + d.v * w); };
  auto f = [&](double w) { return axis_coord(point(w).centre, axis_) - level_; };
  auto finish = [&](double w) {
    *w_out = w;
    *out = point(w);
    (axis_ == 0 ? out->centre.SetX(level_) : out->centre.SetY(level_));
    return true;
  };
  const double f0 = f(0.0);
  if (std::abs(f0) <= kLevelTol) return finish(0.0);
  if (!(lo < 0 && hi > 0)) return false;
  // The nearest root: steps doubling from a Newton step's length, on the
  // Newton side first, then the other, each side bracketed from its
  // previous step.
  const double h = std::min(1e-6, 0.5 * hi);
  const double slope = (f(h) - f0) / h;
  double step = slope != 0 ? std::abs(f0 / slope) : 0.0;
  if (!std::isfinite(step)) step = 0.0;
  step = std::clamp(step, 1e-3, reach);
  const double first = slope * f0 < 0 ? 1.0 : -1.0;  // the Newton side
  double prev[2] = {0.0, 0.0}, fprev[2] = {f0, f0};
  bool open[2] = {true, true};
  for (; open[0] || open[1]; step *= 2.0) {
    for (int side = 0; side < 2; ++side) {
      if (!open[side]) continue;
      const double dir = side == 0 ? first : -first;
      const double w = std::clamp(dir * step, lo, hi);
      const double fw = f(w);
      if ((fw < 0) != (f0 < 0) || std::abs(fw) <= kLevelTol)
        return finish(illinois(f, prev[side], fprev[side], w, fw, kLevelTol));
      if (w != dir * step) open[side] = false;  // the end of the reach
      prev[side] = w;
      fprev[side] = fw;
    }
  }
  return false;
}

LevelCurveMap::Point LevelCurveMap::at(double t) const {
  const double end = last();
  if (closed_) {
    t = std::fmod(t, end);
    if (t < 0) t += end;
  }
  t = std::clamp(t, 0.0, end);
  const std::size_t i = std::min(static_cast<std::size_t>(t), pts_.size() - 2);
  const double s = t - double(i);
  if (s <= 0) return {pts_[i], true};
  if (s >= 1) return {pts_[i + 1], true};
  Point p;
  double w;
  if (across(pts_[i], pts_[i + 1], s, 1.0, &w, &p.p)) return p;
  // No root in reach: the straight chord between the two centres.
  p.exact = false;
  const OffsetPoint q = lattice_->at(pts_[i].lc.u + (pts_[i + 1].lc.u - pts_[i].lc.u) * s,
                                     pts_[i].lc.v + (pts_[i + 1].lc.v - pts_[i].lc.v) * s);
  p.p.lc = q.lc;
  p.p.uv = q.uv;
  p.p.centre = gp_Pnt(pts_[i].centre.XYZ() * (1 - s) + pts_[i + 1].centre.XYZ() * s);
  const gp_Vec n = pts_[i].normal * (1 - s) + pts_[i + 1].normal * s;
  p.p.normal = n.Magnitude() > 1e-12 ? n.Normalized() : pts_[i].normal;
  return p;
}

}  // namespace isocam
