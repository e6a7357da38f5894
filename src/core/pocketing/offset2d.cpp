// Exact offsets of line/arc profiles (Suh & Lee, section 2.1, "Profile
// offset"), and the region operations built on them.
//
// The raw offset of a loop by d to its left is the loop plus, for every
// piece of it, the clockwise boundary of the "cell" swept by its left
// normals of length d:
//   - a line: the rectangle on its left; its offset is the line moved by d;
//   - an arc turning right (centre on the right): the annular sector out
//     to radius R + d; its offset is the arc of radius R + d (arcs stay arcs);
//   - an arc turning left with R > d: the sector ring down to R - d;
//   - an arc turning left with R <= d: the whole sector down to the centre
//     (its "offset" is the path through the centre);
//   - a corner turning right: the circular sector of radius d about it, the
//     arc of Figure 2.7(c);
//   - a corner turning left: nothing; the two offsets are joined through
//     the corner itself (the legs lie inside the cells of the neighbours).
// Chained together, this is a closed curve whose winding number is that of
// the loop minus the number of cells covering the point. A point of the
// region farther than d from every loop lies in no cell and keeps winding
// 1; a point of the region within d of its boundary lies in the cell of its
// nearest boundary point (an edge's, or a right-turning corner's) and drops
// to <= 0; points outside stay <= 0. So the positive-winding resolution of
// the raw curves of all loops is exactly the offset region, whatever the
// offset distance (self loops, Figure 2.10's nesting, lakes, merges,
// vanishing profiles). Arcs about the corners are exact, as are the arcs
// of the profile.
#include <algorithm>
#include <cmath>

#include "pocketing/geom2d.h"

namespace isocam {

using namespace pocket;

namespace {

// Signed turning angle from tangent t0 to tangent t1, in [-pi, pi].
double turning(P2 t0, P2 t1) {
  const double c = cross(t0, t1), dt = dot(t0, t1);
  if (c == 0.0 && dt < 0.0) return kPi;  // a cusp: turn left by convention
  return std::atan2(c, dt);
}

Loop drop_tiny(const Loop& loop, double snap) {
  Loop out;
  for (const Seg& s : loop)
    if (s.length() > snap) out.push_back(s);
  // Re-close the chain where a tiny segment was dropped.
  for (std::size_t i = 0; i < out.size(); ++i) {
    Seg& next = out[(i + 1) % out.size()];
    if (dist(out[i].b, next.a) > 0.0) next.a = out[i].b;
  }
  return out;
}

// Builds a chain of segments from successive points and arcs.
class Chain {
 public:
  explicit Chain(double snap) : snap_(snap) {}
  bool empty() const { return !started_; }
  P2 last() const { return last_; }
  void start(P2 p) {
    last_ = p;
    started_ = true;
  }
  // Points within snap of the current one are not moved to (the chain
  // stays exactly closed).
  void line_to(P2 p) {
    if (dist(p, last_) <= snap_) return;
    out_.push_back(Seg::line(last_, p));
    last_ = p;
  }
  // Arc about c of radius r from the current point, sweeping `sweep`.
  void arc_to(P2 c, double r, double sweep, P2 end) {
    if (dist(end, last_) <= snap_) return;
    Seg a = Seg::arc(c, r, angle_of(last_ - c), sweep);
    a.a = last_;
    a.b = end;
    out_.push_back(a);
    last_ = end;
  }
  void seg(const Seg& s) {
    if (dist(s.a, last_) > snap_) line_to(s.a);
    Seg t = s;
    t.a = last_;
    if (dist(t.a, t.b) <= snap_ && t.length() <= snap_) return;
    out_.push_back(t);
    last_ = t.b;
  }
  Loop close() {
    if (!out_.empty()) {
      if (dist(out_.front().a, last_) > snap_) line_to(out_.front().a);
      out_.back().b = out_.front().a;
    }
    return std::move(out_);
  }

 private:
  double snap_;
  P2 last_;
  bool started_ = false;
  Loop out_;
};

}  // namespace

namespace pocket {

// The raw offset curve of one closed loop (see the file comment).
Loop raw_offset(const Loop& input, double d, double snap) {
  const Loop loop = drop_tiny(input, snap);
  const std::size_t n = loop.size();
  if (n == 0) return {};
  // Per piece: degenerate (a left-turning arc with R <= d) or its offset.
  std::vector<bool> through_centre(n, false);
  std::vector<Seg> off(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Seg& s = loop[i];
    if (s.kind == SegKind::Line) {
      const P2 nl = left_normal(unit(s.b - s.a));
      off[i] = Seg::line(s.a + d * nl, s.b + d * nl);
    } else if (s.sweep < 0) {
      off[i] = Seg::arc(s.c, s.r + d, s.a0, s.sweep);
    } else if (s.r - d > snap) {
      off[i] = Seg::arc(s.c, s.r - d, s.a0, s.sweep);
    } else {
      through_centre[i] = true;
    }
  }
  Chain ch(snap);
  ch.start(through_centre[0] ? loop[0].a : off[0].a);
  for (std::size_t i = 0; i < n; ++i) {
    const Seg& s = loop[i];
    if (through_centre[i]) {
      ch.line_to(s.a);
      ch.line_to(s.c);
      ch.line_to(s.b);
    } else {
      ch.seg(off[i]);
    }
    // The corner at the end of piece i.
    const std::size_t j = (i + 1) % n;
    const P2 v = s.b;
    const P2 t0 = end_tangent(s), t1 = start_tangent(loop[j]);
    const double phi = turning(t0, t1);
    const P2 from = v + d * left_normal(t0), to = v + d * left_normal(t1);
    const P2 next = through_centre[j] ? loop[j].a : off[j].a;
    if (phi < 0 && dist(from, to) > snap) {
      if (through_centre[i]) ch.line_to(from);
      ch.arc_to(v, d, phi, to);
      if (through_centre[j]) ch.line_to(v);
    } else if (dist(ch.last(), next) > snap) {
      ch.line_to(v);  // a left turn: through the corner
    }
    if (!(j == 0)) ch.line_to(next);
  }
  return ch.close();
}

}  // namespace pocket

std::vector<Loop> offset_region(const std::vector<Loop>& loops, double d, double snap) {
  if (snap <= 0.0) snap = default_snap(loops);
  if (d <= 0.0) return resolve_loops(loops, snap);
  std::vector<Loop> raw;
  raw.reserve(loops.size());
  for (const Loop& l : loops) raw.push_back(raw_offset(l, d, snap));
  return resolve_loops(raw, snap);
}

std::vector<Loop> dilate_region(const std::vector<Loop>& loops, double d, double snap) {
  if (snap <= 0.0) snap = default_snap(loops);
  if (d <= 0.0 || loops.empty()) return resolve_loops(loops, snap);
  // The complement inside a box, shrunk by d, complemented again.
  Box2 b = loops_box(loops);
  const double m = 2.0 * d + 0.1 * b.size() + 1.0;
  const P2 p0{b.x0 - m, b.y0 - m}, p1{b.x1 + m, b.y0 - m}, p2{b.x1 + m, b.y1 + m},
      p3{b.x0 - m, b.y1 + m};
  std::vector<Loop> comp{
      {Seg::line(p0, p1), Seg::line(p1, p2), Seg::line(p2, p3), Seg::line(p3, p0)}};
  for (const Loop& l : loops) comp.push_back(reversed(l));
  std::vector<Loop> shrunk = offset_region(comp, d, snap);
  std::size_t box_loop = 0;
  double best = -1e300;
  for (std::size_t i = 0; i < shrunk.size(); ++i) {
    const double a = signed_area(shrunk[i]);
    if (a > best) {
      best = a;
      box_loop = i;
    }
  }
  std::vector<Loop> out;
  for (std::size_t i = 0; i < shrunk.size(); ++i)
    if (i != box_loop) out.push_back(reversed(shrunk[i]));
  return out;
}

std::vector<std::vector<Loop>> region_components(const std::vector<Loop>& loops) {
  std::vector<std::size_t> outers, holes;
  std::vector<double> area(loops.size());
  for (std::size_t i = 0; i < loops.size(); ++i) {
    area[i] = signed_area(loops[i]);
    (area[i] > 0 ? outers : holes).push_back(i);
  }
  std::sort(outers.begin(), outers.end(),
            [&](std::size_t a, std::size_t b) { return area[a] < area[b]; });
  std::vector<std::vector<Loop>> comps(outers.size());
  for (std::size_t k = 0; k < outers.size(); ++k) comps[k].push_back(loops[outers[k]]);
  for (std::size_t h : holes) {
    // A point just inside the island (right of its longest segment).
    const Loop& hl = loops[h];
    std::size_t longest = 0;
    for (std::size_t j = 1; j < hl.size(); ++j)
      if (hl[j].length() > hl[longest].length()) longest = j;
    const Seg& s = hl[longest];
    const P2 t = s.tangent(0.5);
    const double eps = std::min(1e-6 * std::max(1.0, loops_box({hl}).size()), 0.01 * s.length());
    const P2 q = s.at(0.5) + eps * P2{t.y, -t.x};
    for (std::size_t k = 0; k < outers.size(); ++k) {  // smallest first
      if (winding_number({loops[outers[k]]}, q) != 0) {
        comps[k].push_back(hl);
        break;
      }
    }
  }
  return comps;
}

}  // namespace isocam
