// Ordering, offsetting, linearisation and linking of one face's coverage.
#include <algorithm>
#include <cmath>

#include "finishing/coverage.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

// Ball centre on the exact offset S + r N at parameters (t, level) of the
// working grid (t along the curve).
struct OffsetSurface {
  const PatchGrid& g;
  double r;
  gp_Pnt centre(double t, double level) const {
    const SurfaceDerivs d = g.d1(t, level);
    return d.p.Translated(g.normal(t, level, &d) * r);
  }
};

struct Piece {
  SubIsocurve c;
  bool forward = true;
  std::vector<gp_Pnt> pts;  // ball centres
  double start() const { return forward ? c.t0 : c.t1; }
  double end() const { return forward ? c.t1 : c.t0; }
};

double polyline_length(const std::vector<gp_Pnt>& pts) {
  double s = 0;
  for (std::size_t i = 1; i < pts.size(); ++i) s += pts[i - 1].Distance(pts[i]);
  return s;
}

bool overlap(const SubIsocurve& a, const SubIsocurve& b) {
  return std::min(a.t1, b.t1) > std::max(a.t0, b.t0);
}

}  // namespace

Toolpath face_toolpath(const PatchGrid& g, std::vector<SubIsocurve> curves,
                       const IsoParams& params, int* emitted_curves) {
  // Cross-iso order (Definition 3 adjacency follows from it: consecutive
  // curves whose domains overlap have nothing between them).
  std::sort(curves.begin(), curves.end(), [](const SubIsocurve& a, const SubIsocurve& b) {
    return a.level < b.level || (a.level == b.level && a.t0 < b.t0);
  });
  const OffsetSurface off{g, params.ball_radius};
  const double tol = params.chord_tolerance;
  std::vector<Piece> pieces;
  for (const SubIsocurve& c : curves) {
    Piece p;
    p.c = c;
    p.forward = pieces.size() % 2 == 0;  // zig-zag
    p.pts = linearize([&](double t) { return off.centre(t, c.level); }, p.start(), p.end(), tol,
                      g.ubreaks());
    // A boundary collapsed to a pole offsets to a single point: nothing to cut.
    if (polyline_length(p.pts) > 1e-6) pieces.push_back(std::move(p));
  }
  if (emitted_curves) *emitted_curves = static_cast<int>(pieces.size());

  Toolpath path;
  const double r = params.ball_radius, safe = params.safe_z;
  auto tip = [&](MoveKind k, const gp_Pnt& c) { path.add(k, c.X(), c.Y(), c.Z() - r); };
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Piece& p = pieces[i];
    const bool linked = i > 0 && overlap(pieces[i - 1].c, p.c);
    if (linked) {
      // Feed link on the offset surface along the straight parameter segment.
      const Piece& q = pieces[i - 1];
      const double t0 = q.end(), v0 = q.c.level, t1 = p.start(), v1 = p.c.level;
      const auto link = linearize(
          [&](double s) { return off.centre(t0 + (t1 - t0) * s, v0 + (v1 - v0) * s); }, 0.0, 1.0,
          tol, {}, 2);
      for (std::size_t k = 1; k < link.size(); ++k) tip(MoveKind::Feed, link[k]);
    } else {
      if (i > 0) path.add(MoveKind::Rapid, path.x.back(), path.y.back(), safe);
      path.add(MoveKind::Rapid, p.pts.front().X(), p.pts.front().Y(), safe);
      tip(MoveKind::Plunge, p.pts.front());
    }
    for (std::size_t k = 1; k < p.pts.size(); ++k) tip(MoveKind::Feed, p.pts[k]);
  }
  if (!path.empty()) path.add(MoveKind::Rapid, path.x.back(), path.y.back(), safe);
  return path;
}

}  // namespace isocam
