// Intersections of lines and circular arcs (the splitting step of Suh &
// Lee's section 2.2: "the intersection between the curves ... split the
// intersecting curves at those points").
//
// Contract: every point where the two segments cross or touch within `eps`
// is reported with its parameter on each. Tangency is decided with the
// tolerance `eps` (a touching point is reported once); overlapping collinear
// lines or co-circular arcs report the ends of the common part, so that both
// segments are split there and the common pieces can be matched later.
#include <algorithm>
#include <cmath>

#include "pocketing/geom2d.h"

namespace isocam::pocket {
namespace {

bool in_range(double t, double eps_t) { return t >= -eps_t && t <= 1.0 + eps_t; }
double clamp01(double t) { return std::clamp(t, 0.0, 1.0); }

// Parameter of point p on segment s (p assumed on its carrier), or a value
// outside the tolerance if it is not within the segment.
double param_on(const Seg& s, P2 p, double eps) {
  if (s.kind == SegKind::Line) {
    const P2 d = s.b - s.a;
    const double l2 = dot(d, d);
    return l2 > 0 ? dot(p - s.a, d) / l2 : 0.0;
  }
  return arc_param_of_angle(s, angle_of(p - s.c), eps / std::max(s.length(), 1e-300));
}

void add_hit(const Seg& s1, const Seg& s2, P2 p, double eps, std::vector<Hit>& out) {
  const double l1 = std::max(s1.length(), 1e-300), l2 = std::max(s2.length(), 1e-300);
  const double t1 = param_on(s1, p, eps), t2 = param_on(s2, p, eps);
  if (!in_range(t1, eps / l1) || !in_range(t2, eps / l2)) return;
  out.push_back({clamp01(t1), clamp01(t2), p});
}

void line_line(const Seg& s1, const Seg& s2, double eps, std::vector<Hit>& out) {
  const P2 d1 = s1.b - s1.a, d2 = s2.b - s2.a;
  const double l1 = norm(d1), l2 = norm(d2);
  if (l1 <= 0 || l2 <= 0) return;
  const double den = cross(d1, d2);
  const double off = cross(d1, s2.a - s1.a) / l1;  // distance of s2.a from line 1
  if (std::abs(den) <= 1e-12 * l1 * l2) {
    // Parallel: overlapping only when collinear within eps.
    if (std::abs(off) > eps) return;
    for (P2 p : {s2.a, s2.b}) add_hit(s1, s2, p, eps, out);
    for (P2 p : {s1.a, s1.b}) add_hit(s1, s2, p, eps, out);
    return;
  }
  const double t = cross(s2.a - s1.a, d2) / den;
  const double u = cross(s2.a - s1.a, d1) / den;
  if (!in_range(t, eps / l1) || !in_range(u, eps / l2)) return;
  out.push_back({clamp01(t), clamp01(u), s1.a + clamp01(t) * d1});
}

// Line s1 with circle of arc s2 (or the reverse when `swapped`).
void line_arc(const Seg& ln, const Seg& arc, double eps, bool swapped, std::vector<Hit>& out) {
  const P2 d = ln.b - ln.a;
  const double l = norm(d);
  if (l <= 0) return;
  const P2 u = (1.0 / l) * d;
  const double s_foot = dot(arc.c - ln.a, u);  // arc length along the line to the foot
  const P2 foot = ln.a + s_foot * u;
  const double h = dist(foot, arc.c);
  if (h > arc.r + eps) return;
  // Within eps of tangency the two crossings merge into the foot point.
  const double half = std::sqrt(std::max(0.0, arc.r * arc.r - h * h));
  std::vector<P2> pts;
  if (half <= eps) {
    pts.push_back(foot);
  } else {
    pts.push_back(foot - half * u);
    pts.push_back(foot + half * u);
  }
  std::vector<Hit> hits;
  for (P2 p : pts) {
    if (swapped)
      add_hit(arc, ln, p, eps, hits);
    else
      add_hit(ln, arc, p, eps, hits);
  }
  out.insert(out.end(), hits.begin(), hits.end());
}

void arc_arc(const Seg& s1, const Seg& s2, double eps, std::vector<Hit>& out) {
  const double d = dist(s1.c, s2.c);
  if (d <= eps && std::abs(s1.r - s2.r) <= eps) {
    // Co-circular: the ends of the common part(s).
    for (P2 p : {s2.a, s2.b}) add_hit(s1, s2, p, eps, out);
    for (P2 p : {s1.a, s1.b}) add_hit(s1, s2, p, eps, out);
    return;
  }
  if (d <= 0.0) return;  // concentric, different radii
  if (d > s1.r + s2.r + eps || d < std::abs(s1.r - s2.r) - eps) return;
  const P2 e = (1.0 / d) * (s2.c - s1.c);
  const double a = (d * d + s1.r * s1.r - s2.r * s2.r) / (2.0 * d);
  const double h2 = s1.r * s1.r - a * a;
  const P2 m = s1.c + a * e;
  if (h2 <= eps * eps) {
    add_hit(s1, s2, m, eps, out);  // tangent within eps
    return;
  }
  const double h = std::sqrt(h2);
  add_hit(s1, s2, m + h * left_normal(e), eps, out);
  add_hit(s1, s2, m - h * left_normal(e), eps, out);
}

}  // namespace

void intersect_segs(const Seg& s1, const Seg& s2, double eps, std::vector<Hit>& out) {
  if (s1.kind == SegKind::Line && s2.kind == SegKind::Line)
    line_line(s1, s2, eps, out);
  else if (s1.kind == SegKind::Line)
    line_arc(s1, s2, eps, false, out);
  else if (s2.kind == SegKind::Line)
    line_arc(s2, s1, eps, true, out);
  else
    arc_arc(s1, s2, eps, out);
}

}  // namespace isocam::pocket
