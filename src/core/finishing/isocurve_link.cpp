// Ordering and linking of cut pieces into one path.
#include <algorithm>
#include <cmath>
#include <limits>

#include "finishing/coverage.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

// A feed link from the end of `a` to the start of `b`, or an empty vector if
// none keeps the ball clear of the model. Between pieces of one face the
// link follows the offset surface along the straight parameter segment (the
// ball stays tangent to the face); otherwise (other faces, or pieces with
// no grid such as parallel-plane curves) it is a straight move.
std::vector<gp_Pnt> feed_link(const CutPiece& a, const CutPiece& b, const IsoParams& params,
                              const ClearanceModel& model, double clearance) {
  std::vector<gp_Pnt> link;
  if (a.grid && a.grid == b.grid) {
    const PatchGrid& g = *a.grid;
    const double r = params.ball_radius;
    const double t0 = a.t.back(), v0 = a.level, t1 = b.t.front(), v1 = b.level;
    link = linearize(
        [&](double s) {
          const double t = t0 + (t1 - t0) * s, v = v0 + (v1 - v0) * s;
          const SurfaceDerivs d = g.d1(t, v);
          return d.p.Translated(g.normal(t, v, &d) * r);
        },
        0.0, 1.0, params.chord_tolerance, {}, 2);
    link.front() = a.pts.back();
    link.back() = b.pts.front();
  } else {
    link = {a.pts.back(), b.pts.front()};
  }
  for (std::size_t k = 1; k < link.size(); ++k)
    if (!model.clear(link[k - 1], link[k], clearance)) return {};
  return link;
}

struct Candidate {
  double distance;
  std::size_t piece;
  bool reversed;
};

}  // namespace

Toolpath link_pieces(std::vector<CutPiece> pieces, const IsoParams& params,
                     const ClearanceModel& model) {
  Toolpath path;
  if (pieces.empty()) return path;
  const double r = params.ball_radius, safe = params.safe_z;
  const double clearance =
      model.query_distance(r - params.chord_tolerance - params.gouge_tolerance);
  const double max_link = 4.0 * r;
  auto tip = [&](MoveKind k, const gp_Pnt& p) { path.add(k, p.X(), p.Y(), p.Z() - r); };
  auto enter = [&](const CutPiece& p) {
    if (!path.empty()) path.add(MoveKind::Rapid, path.x.back(), path.y.back(), safe);
    path.add(MoveKind::Rapid, p.pts.front().X(), p.pts.front().Y(), safe);
    tip(MoveKind::Plunge, p.pts.front());
  };
  auto cut = [&](const CutPiece& p) {
    for (std::size_t k = 1; k < p.pts.size(); ++k) tip(MoveKind::Feed, p.pts[k]);
  };

  std::vector<char> used(pieces.size(), 0);
  std::size_t cur = 0;
  used[0] = 1;
  enter(pieces[0]);
  cut(pieces[0]);
  std::vector<Candidate> cands;
  for (std::size_t step = 1; step < pieces.size(); ++step) {
    const gp_Pnt& end = pieces[cur].pts.back();
    cands.clear();
    for (std::size_t j = 0; j < pieces.size(); ++j) {
      if (used[j]) continue;
      cands.push_back({end.Distance(pieces[j].pts.front()), j, false});
      cands.push_back({end.Distance(pieces[j].pts.back()), j, true});
    }
    // The 8 nearest, in order (ties by piece, then end): only they are tried.
    const std::size_t tries = std::min<std::size_t>(8, cands.size());
    std::partial_sort(cands.begin(), cands.begin() + static_cast<std::ptrdiff_t>(tries), cands.end(),
                      [](const Candidate& x, const Candidate& y) {
                        if (x.distance != y.distance) return x.distance < y.distance;
                        if (x.piece != y.piece) return x.piece < y.piece;
                        return x.reversed < y.reversed;
                      });
    std::vector<gp_Pnt> link;
    Candidate chosen = cands.front();
    for (std::size_t k = 0; k < tries && cands[k].distance <= max_link; ++k) {
      CutPiece& next = pieces[cands[k].piece];
      if (cands[k].reversed) next.reverse();
      link = feed_link(pieces[cur], next, params, model, clearance);
      if (cands[k].reversed) next.reverse();
      if (!link.empty()) {
        chosen = cands[k];
        break;
      }
    }
    CutPiece& next = pieces[chosen.piece];
    if (chosen.reversed) next.reverse();
    if (link.empty()) {
      enter(next);
    } else {
      for (std::size_t k = 1; k < link.size(); ++k) tip(MoveKind::Feed, link[k]);
    }
    cut(next);
    used[chosen.piece] = 1;
    cur = chosen.piece;
  }
  path.add(MoveKind::Rapid, path.x.back(), path.y.back(), safe);
  return path;
}

}  // namespace isocam
