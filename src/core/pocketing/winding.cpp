// Winding numbers of closed line/arc loops, by signed ray crossings.
//
// Each segment is cut into y-monotone pieces (arcs at their top and bottom
// points). The ray from p towards +x crosses a piece when y0 <= p.y < y1
// (half-open, so that consecutive pieces sharing an end count it once) and
// the piece's x at p.y is > p.x; an upward piece counts +1, a downward one
// -1. Pieces are bucketed in horizontal bands so a query only looks at the
// pieces of its band.
#include <algorithm>
#include <cmath>

#include "pocketing/geom2d.h"

namespace isocam {

using namespace pocket;

int winding_number(const std::vector<Loop>& loops, P2 p) {
  std::vector<Seg> segs;
  for (const Loop& l : loops) segs.insert(segs.end(), l.begin(), l.end());
  return WindingIndex(segs).at(p);
}

namespace pocket {

WindingIndex::WindingIndex(const std::vector<Seg>& segs) {
  auto add_piece = [&](P2 s, P2 e, const Seg* arc, bool right) {
    if (s.y == e.y) return;  // horizontal: never crossed by a horizontal ray
    Piece pc{};
    pc.dir = e.y > s.y ? 1 : -1;
    pc.y0 = std::min(s.y, e.y);
    pc.y1 = std::max(s.y, e.y);
    pc.xa = s.x;
    pc.ya = s.y;
    pc.xb = e.x;
    pc.yb = e.y;
    pc.arc = arc != nullptr;
    if (arc) {
      pc.cx = arc->c.x;
      pc.cy = arc->c.y;
      pc.r = arc->r;
      pc.right = right;
    }
    pieces_.push_back(pc);
  };
  for (const Seg& s : segs) {
    if (s.kind == SegKind::Line) {
      add_piece(s.a, s.b, nullptr, false);
      continue;
    }
    if (s.sweep == 0.0 || s.r <= 0.0) continue;
    // Split at the angles pi/2 + k pi (top and bottom of the circle).
    std::vector<double> cuts;
    const double lo = std::min(s.a0, s.a0 + s.sweep), hi = std::max(s.a0, s.a0 + s.sweep);
    for (double k = std::floor((lo - 0.5 * kPi) / kPi) + 1.0;; k += 1.0) {
      const double ang = 0.5 * kPi + k * kPi;
      if (ang >= hi) break;
      if (ang > lo) cuts.push_back(ang);
    }
    if (s.sweep < 0) std::reverse(cuts.begin(), cuts.end());
    double prev_ang = s.a0;
    P2 prev = s.a;
    for (std::size_t i = 0; i <= cuts.size(); ++i) {
      const bool last = i == cuts.size();
      const double ang = last ? s.a0 + s.sweep : cuts[i];
      const P2 next = last ? s.b : s.c + s.r * polar(ang);
      add_piece(prev, next, &s, std::cos(0.5 * (prev_ang + ang)) > 0.0);
      prev_ang = ang;
      prev = next;
    }
  }
  if (pieces_.empty()) return;
  double ymin = 1e300, ymax = -1e300;
  for (const Piece& pc : pieces_) {
    ymin = std::min(ymin, pc.y0);
    ymax = std::max(ymax, pc.y1);
  }
  const std::size_t nb = std::clamp<std::size_t>(pieces_.size() / 4, 1, 4096);
  ymin_ = ymin;
  band_h_ = std::max((ymax - ymin) / static_cast<double>(nb), 1e-300);
  bands_.assign(nb, {});
  for (std::size_t i = 0; i < pieces_.size(); ++i) {
    const auto b0 = static_cast<std::size_t>(
        std::clamp((pieces_[i].y0 - ymin_) / band_h_, 0.0, static_cast<double>(nb - 1)));
    const auto b1 = static_cast<std::size_t>(
        std::clamp((pieces_[i].y1 - ymin_) / band_h_, 0.0, static_cast<double>(nb - 1)));
    for (std::size_t b = b0; b <= b1; ++b) bands_[b].push_back(static_cast<int>(i));
  }
}

double WindingIndex::x_at(const Piece& pc, double y) const {
  if (!pc.arc) {
    const double t = (y - pc.ya) / (pc.yb - pc.ya);
    return pc.xa + t * (pc.xb - pc.xa);
  }
  const double dy = y - pc.cy;
  const double dx = std::sqrt(std::max(0.0, pc.r * pc.r - dy * dy));
  return pc.right ? pc.cx + dx : pc.cx - dx;
}

int WindingIndex::at(P2 p) const {
  if (bands_.empty()) return 0;
  const double fb = (p.y - ymin_) / band_h_;
  if (fb < 0.0 || fb > static_cast<double>(bands_.size())) return 0;
  const auto b = std::min(static_cast<std::size_t>(fb), bands_.size() - 1);
  int w = 0;
  for (int i : bands_[b]) {
    const Piece& pc = pieces_[static_cast<std::size_t>(i)];
    if (p.y < pc.y0 || p.y >= pc.y1) continue;
    if (x_at(pc, p.y) > p.x) w += pc.dir;
  }
  return w;
}

}  // namespace pocket
}  // namespace isocam
