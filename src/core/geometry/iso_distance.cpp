#include "geometry/iso_distance.h"

#include <algorithm>
#include <cmath>

namespace isocam {
namespace {

struct SpanCoords {
  Bernstein x, y, z, w;
};

SpanCoords coords(const H4* cps, int degree, double s0, double s1) {
  std::vector<double> x, y, z, w;
  for (int i = 0; i <= degree; ++i) {
    x.push_back(cps[i].x);
    y.push_back(cps[i].y);
    z.push_back(cps[i].z);
    w.push_back(cps[i].w);
  }
  return {Bernstein(x).restricted(s0, s1), Bernstein(y).restricted(s0, s1),
          Bernstein(z).restricted(s0, s1), Bernstein(w).restricted(s0, s1)};
}

bool all_unit(const Bernstein& w) {
  for (double c : w.coeffs())
    if (std::abs(c - 1.0) > 1e-14) return false;
  return true;
}

}  // namespace

std::vector<IsoDistancePiece> iso_distance_squared(const PiecewiseBezier& c1,
                                                   const PiecewiseBezier& c2, double a, double b) {
  std::vector<IsoDistancePiece> out;
  const int first = c1.span_of(a), last = c1.span_of(b);
  for (int i = first; i <= last; ++i) {
    const double ta = c1.breaks[static_cast<std::size_t>(i)];
    const double tb = c1.breaks[static_cast<std::size_t>(i) + 1];
    const double lo = std::max(a, ta), hi = std::min(b, tb);
    if (!(hi > lo)) continue;
    const double s0 = (lo - ta) / (tb - ta), s1 = (hi - ta) / (tb - ta);
    const SpanCoords p = coords(c1.span(i), c1.degree, s0, s1);
    const SpanCoords q = coords(c2.span(i), c2.degree, s0, s1);
    IsoDistancePiece piece;
    piece.a = lo;
    piece.b = hi;
    if (all_unit(p.w) && all_unit(q.w)) {
      const Bernstein dx = p.x - q.x, dy = p.y - q.y, dz = p.z - q.z;
      piece.num = dx * dx + dy * dy + dz * dz;
      piece.den = Bernstein::constant(1.0, 0);
    } else {
      const Bernstein dx = p.x * q.w - q.x * p.w;
      const Bernstein dy = p.y * q.w - q.y * p.w;
      const Bernstein dz = p.z * q.w - q.z * p.w;
      const Bernstein ww = p.w * q.w;
      piece.num = dx * dx + dy * dy + dz * dz;
      piece.den = ww * ww;
    }
    out.push_back(std::move(piece));
  }
  return out;
}

std::vector<Interval> exceeding(const std::vector<IsoDistancePiece>& pieces, double delta) {
  return exceeding(pieces, std::vector<double>(pieces.size(), delta));
}

std::vector<Interval> exceeding(const std::vector<IsoDistancePiece>& pieces,
                                const std::vector<double>& deltas) {
  std::vector<Interval> out;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const IsoDistancePiece& p = pieces[k];
    const double d2 = deltas[k] * deltas[k];
    const Bernstein f = p.num - d2 * p.den;
    const double slack = 1e-9 * d2 * p.den.max_coeff();
    for (const Interval& iv : positive_intervals(f, 1e-10, slack)) {
      const Interval g{p.a + (p.b - p.a) * iv.lo, p.a + (p.b - p.a) * iv.hi};
      if (!out.empty() && g.lo <= out.back().hi) {
        out.back().hi = std::max(out.back().hi, g.hi);
      } else {
        out.push_back(g);
      }
    }
  }
  return out;
}

double max_iso_distance(const std::vector<IsoDistancePiece>& pieces) {
  double m = 0.0;
  for (const IsoDistancePiece& p : pieces) m = std::max(m, max_ratio(p.num, p.den, 1e-9));
  return std::sqrt(std::max(m, 0.0));
}

std::vector<Interval> complement(const std::vector<Interval>& holes, double a, double b) {
  std::vector<Interval> out;
  double cur = a;
  for (const Interval& h : holes) {
    if (h.lo > cur) out.push_back({cur, std::min(h.lo, b)});
    cur = std::max(cur, h.hi);
  }
  if (cur < b) out.push_back({cur, b});
  return out;
}

}  // namespace isocam
