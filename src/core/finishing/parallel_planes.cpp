// The parallel-plane baseline: plane curves of each face's offset (traced by
// plane_trace.cpp), linearised, trimmed to the face, cut for clearance, the
// axis chosen and the pieces put in zig-zag order for link_pieces().
#include "finishing/parallel_planes.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <unordered_map>

#include "finishing/face_failure.h"
#include "finishing/plane_trace.h"
#include "finishing/task_pool.h"
#include "isocam/errors.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

// Ball centres along part of a plane curve, with the curve parameter of each.
using Run = CentrePolyline;

// The plane pieces of one face along one axis.
struct FaceCut {
  std::vector<std::pair<int, CutPiece>> pieces;  // (plane index, piece)
  int curves = 0;
  double unreachable = 0.0, max_factor = 0.0, length = 0.0;
  double from_above = 0.0;  // of unreachable: the column above not clear
};

// On a closed curve, the last run ending at its end and the first starting
// at its start are one run across the start: join them (the first run's
// parameters shifted by a period so that they keep increasing).
template <class R>
void join_across_start(std::vector<R>* runs, double t_start, double t_end, double period) {
  if (runs->size() < 2) return;
  R& first = runs->front();
  R& last = runs->back();
  if (first.t.front() != t_start || last.t.back() != t_end) return;
  for (std::size_t i = 1; i < first.pts.size(); ++i) {
    last.pts.push_back(first.pts[i]);
    last.t.push_back(first.t[i] + period);
  }
  runs->erase(runs->begin());
}

class CurveCutter {
 public:
  CurveCutter(const OffsetLattice& lattice, const TrimDomain& trim, const LevelCurve& curve,
              int axis, double level, const IsoParams& p, const ClearanceModel& model)
      : trim_(trim),
        curve_(curve),
        map_(lattice, curve, axis, level),
        axis_(axis),
        level_(level),
        tol_(p.chord_tolerance),
        model_(model),
        clearance_(model.query_distance(p.ball_radius - p.chord_tolerance - p.gouge_tolerance)) {}

  void cut(FaceCut* out) {
    linearise();
    std::vector<Run> runs = inside_runs();
    if (curve_.closed) join_across_start(&runs, t_.front(), t_.back(), map_.last());
    for (const Run& run : runs) {
      const double full = run.length();
      if (full <= 1e-6) continue;
      ++out->curves;
      std::vector<CutPiece> pieces =
          clear_pieces(run.pts, run.t, centre_fn(), model_, clearance_, tol_, &out->from_above);
      const bool whole = curve_.closed && run.t.front() == t_.front() && run.t.back() == t_.back();
      if (whole && pieces.size() == 1 && pieces[0].t.front() == run.t.front() &&
          pieces[0].t.back() == run.t.back()) {
        start_at_least_along(&pieces[0]);
      } else if (whole) {
        // A whole closed curve cut by the clearance: the pieces meet across
        // its start.
        join_across_start(&pieces, run.t.front(), run.t.back(), map_.last());
      }
      double kept = 0.0;
      for (CutPiece& piece : pieces) {
        kept += piece.length();
        piece.front_normal = map_.at(piece.t.front()).p.normal;
        piece.back_normal = map_.at(piece.t.back()).p.normal;
        out->max_factor = std::max(out->max_factor, pass_factor(piece));
        piece.level = level_;
        out->pieces.emplace_back(curve_.plane, std::move(piece));
      }
      out->unreachable += full - kept;
      out->length += kept;
    }
  }

 private:
  std::function<gp_Pnt(double)> centre_fn() const {
    return [this](double t) { return map_.at(t).p.centre; };
  }

  // The curve within the chord tolerance, vertex to vertex of the lattice
  // crossings, remembering the parameters (u, v) of every point kept.
  void linearise() {
    std::unordered_map<double, std::pair<UV, bool>> seen;  // parameters, usable()
    auto f = [&](double t) {
      const LevelCurveMap::Point q = map_.at(t);
      seen[t] = {q.p.uv, usable(q)};
      return q.p.centre;
    };
    const std::size_t n = map_.vertices().size();
    for (std::size_t i = 0; i + 1 < n; ++i) {
      std::vector<double> ts;
      const std::vector<gp_Pnt> seg = linearize(f, double(i), double(i + 1), tol_, {}, 1, &ts);
      for (std::size_t k = i == 0 ? 0 : 1; k < seg.size(); ++k) {
        pts_.push_back(seg[k]);
        t_.push_back(ts[k]);
        uv_.push_back(seen.at(ts[k]).first);
        ok_.push_back(seen.at(ts[k]).second);
      }
    }
  }

  // A point is cut if it is inside the trimmed face and on the level curve:
  // where the map found no exact point (see LevelCurveMap) a gap is left
  // rather than a chord that may leave the offset.
  bool usable(const LevelCurveMap::Point& q) const {
    return q.exact && trim_.contains(q.p.uv.u, q.p.uv.v);
  }

  // Parameter of the end of the usable part between t_in (usable) and
  // t_out, by bisection to 1e-4 of the chord tolerance in space.
  double boundary(double t_in, double t_out) const {
    for (int it = 0; it < 60; ++it) {
      if (map_.at(t_in).p.centre.Distance(map_.at(t_out).p.centre) <= 1e-4 * tol_) break;
      const double m = 0.5 * (t_in + t_out);
      (usable(map_.at(m)) ? t_in : t_out) = m;
    }
    return t_in;
  }

  // The usable runs of the linearised curve (inside the trimmed face). A
  // chord whose parameter box may meet the face boundary is also tested at
  // 7 interior points (a hole can lie between two vertices inside).
  std::vector<Run> inside_runs() const {
    std::vector<Run> runs;
    Run cur;
    const std::size_t n = pts_.size();
    const std::vector<char>& in = ok_;
    if (in[0]) cur.push(pts_[0], t_[0]);
    for (std::size_t j = 0; j + 1 < n; ++j) {
      const UV& a = uv_[j];
      const UV& b = uv_[j + 1];
      std::vector<std::pair<double, bool>> samples;
      const TrimDomain::RectClass state = trim_.classify_rect(
          std::min(a.u, b.u), std::max(a.u, b.u), std::min(a.v, b.v), std::max(a.v, b.v));
      if (state == TrimDomain::RectClass::Boundary) {
        const int m = 8;
        for (int q = 1; q < m; ++q) {
          const double t = t_[j] + (t_[j + 1] - t_[j]) * q / m;
          samples.emplace_back(t, usable(map_.at(t)));
        }
      }
      samples.emplace_back(t_[j + 1], in[j + 1] != 0);
      double tp = t_[j];
      bool sp = in[j] != 0;
      for (const auto& [tq, sq] : samples) {
        if (sp && !sq) {
          const double tb = boundary(tp, tq);
          if (tb != cur.t.back()) cur.push(map_.at(tb).p.centre, tb);
          if (cur.pts.size() > 1) runs.push_back(std::move(cur));
          cur = Run();
        } else if (!sp && sq) {
          const double tb = boundary(tq, tp);
          cur.push(map_.at(tb).p.centre, tb);
        }
        tp = tq;
        sp = sq;
      }
      if (in[j + 1] && t_[j + 1] != cur.t.back()) cur.push(pts_[j + 1], t_[j + 1]);
    }
    if (cur.pts.size() > 1) runs.push_back(std::move(cur));
    return runs;
  }

  // A closed loop starts where the marching squares happened to begin it:
  // start it where it is least along the passes' direction instead, so that
  // the loops of adjacent planes start next to each other (short links).
  void start_at_least_along(CutPiece* loop) const {
    const std::size_t n = loop->pts.size();
    std::size_t j = 0;
    for (std::size_t k = 1; k + 1 < n; ++k)
      if (along(loop->pts[k]) < along(loop->pts[j])) j = k;
    if (j == 0) return;
    std::vector<gp_Pnt> pts(loop->pts.begin() + static_cast<std::ptrdiff_t>(j), loop->pts.end());
    std::vector<double> t(loop->t.begin() + static_cast<std::ptrdiff_t>(j), loop->t.end());
    for (std::size_t k = 1; k <= j; ++k) {
      pts.push_back(loop->pts[k]);
      t.push_back(loop->t[k] + map_.last());
    }
    loop->pts = std::move(pts);
    loop->t = std::move(t);
  }
  double along(const gp_Pnt& p) const { return axis_ == 0 ? p.Y() : p.X(); }

  // delta / (distance between adjacent passes) at the lattice crossings of
  // the piece, and its ends: 1 / sqrt(1 - n_a^2), n_a the normal's
  // component along the plane axis (see IsoMetrics for ParallelPlanes).
  double pass_factor(const CutPiece& piece) const {
    auto factor = [&](const gp_Vec& n) {
      const double na = axis_ == 0 ? n.X() : n.Y();
      return 1.0 / std::sqrt(std::max(1.0 - na * na, 1e-12));
    };
    double f = std::max(factor(map_.at(piece.t.front()).p.normal),
                        factor(map_.at(piece.t.back()).p.normal));
    const double period = map_.last();
    for (double t = std::ceil(piece.t.front()); t <= piece.t.back(); t += 1.0) {
      const double k = curve_.closed ? std::fmod(t, period) : t;
      f = std::max(f, factor(map_.vertices()[static_cast<std::size_t>(k)].normal));
    }
    return f;
  }

  const TrimDomain& trim_;
  const LevelCurve& curve_;
  LevelCurveMap map_;
  int axis_;
  double level_, tol_;
  const ClearanceModel& model_;
  double clearance_;
  std::vector<gp_Pnt> pts_;
  std::vector<double> t_;
  std::vector<UV> uv_;
  std::vector<char> ok_;  // usable()
};

// Planes c0 + k delta, 0 <= k < count, centred over [lo, hi]: every value
// of the range is within delta/2 of a plane.
struct Planes {
  double c0 = 0.0;
  int count = 0;
};
Planes planes_over(double lo, double hi, double delta) {
  const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / delta - 1e-9)));
  return {0.5 * (lo + hi) - 0.5 * (n - 1) * delta, n};
}

// Zig-zag: planes in order, the pieces of one plane ordered and oriented
// along the other horizontal axis, forward on even planes and backward on
// odd ones. link_pieces() then starts at the first piece and links greedily.
std::vector<CutPiece> zig_zag(std::vector<std::pair<int, CutPiece>> pieces, int axis) {
  auto along = [&](const gp_Pnt& p) { return axis == 0 ? p.Y() : p.X(); };
  for (auto& [plane, piece] : pieces) {
    const bool forward = plane % 2 == 0;
    if ((along(piece.pts.back()) < along(piece.pts.front())) == forward) piece.reverse();
  }
  std::stable_sort(pieces.begin(), pieces.end(), [&](const auto& x, const auto& y) {
    if (x.first != y.first) return x.first < y.first;
    const double ax = along(x.second.pts.front()), ay = along(y.second.pts.front());
    return x.first % 2 == 0 ? ax < ay : ax > ay;
  });
  std::vector<CutPiece> out;
  out.reserve(pieces.size());
  for (auto& pp : pieces) out.push_back(std::move(pp.second));
  return out;
}

struct AxisCut {
  std::vector<FaceCut> faces;
  double length = 0.0;
};

}  // namespace

PlanePieces parallel_plane_pieces(const std::vector<PlaneFace>& faces, double delta,
                                  const IsoParams& params, const ClearanceModel& model,
                                  Progress* progress) {
  const ProgressSlice all(progress);
  PlanePieces out;
  out.failed.resize(faces.size());
  // A face the geometry defeats (OpenCASCADE in the trimmed domain's
  // classifier and projections, the hatcher) is left out on every axis,
  // its reason kept; the planes are those of the other faces.
  auto on_face = [&](std::size_t k, const std::function<void()>& fn) {
    if (out.failed[k]) return;
    if (std::optional<std::string> why = face_failure(faces[k].index, fn)) out.failed[k] = why;
  };
  std::vector<std::unique_ptr<OffsetLattice>> lattices(faces.size());
  for_each_index(faces.size(), params.threads, [&](std::size_t k) {
    all.check();
    on_face(k, [&] {
      lattices[k] =
          std::make_unique<OffsetLattice>(*faces[k].grid, *faces[k].trim, params.ball_radius);
    });
  });
  all.report(0.1);

  std::vector<int> axes{params.plane_axis == IsoPlaneAxis::Y ? 1 : 0};
  if (params.plane_axis == IsoPlaneAxis::Auto) axes = {0, 1};
  std::vector<AxisCut> cuts;  // per axis tried (while a face has a cell inside)
  for (std::size_t ai = 0; ai < axes.size(); ++ai) {
    const int axis = axes[ai];
    double lo = 1e300, hi = -1e300;
    for (std::size_t k = 0; k < faces.size(); ++k) {
      double a, b;
      if (!out.failed[k] && lattices[k]->range(axis, &a, &b)) {
        lo = std::min(lo, a);
        hi = std::max(hi, b);
      }
    }
    if (lo > hi) break;  // no face has a cell inside its trimmed domain
    const Planes planes = planes_over(lo, hi, delta);
    const double na = double(axes.size());
    TaskProgress tracing(all.sub(0.1 + 0.9 * double(ai) / na, 0.1 + 0.9 * double(ai + 1) / na),
                         faces.size());
    AxisCut cut;
    cut.faces.resize(faces.size());
    for_each_index(faces.size(), params.threads, [&](std::size_t k) {
      on_face(k, [&] {
        const ProgressSlice part = tracing.task(k);
        for (const LevelCurve& c :
             trace_levels(*lattices[k], axis, planes.c0, delta, planes.count, part)) {
          part.check();  // a cancel is seen between curves, not only between faces
          CurveCutter(*lattices[k], *faces[k].trim, c, axis, planes.c0 + c.plane * delta, params,
                      model)
              .cut(&cut.faces[k]);
        }
      });
    });
    cuts.push_back(std::move(cut));
  }
  // The shorter axis over the faces that did not fail on any.
  int best_axis = -1;
  for (std::size_t ai = 0; ai < cuts.size(); ++ai) {
    for (std::size_t k = 0; k < faces.size(); ++k)
      if (!out.failed[k]) cuts[ai].length += cuts[ai].faces[k].length;
    if (best_axis < 0 || cuts[ai].length < cuts[std::size_t(best_axis)].length) best_axis = int(ai);
  }
  AxisCut best = best_axis < 0 ? AxisCut{} : std::move(cuts[std::size_t(best_axis)]);
  if (best_axis >= 0) best_axis = axes[std::size_t(best_axis)];
  out.axis = best_axis == 1 ? IsoPlaneAxis::Y : IsoPlaneAxis::X;
  std::vector<std::pair<int, CutPiece>> pieces;
  out.face_pass_distance.assign(faces.size(), 0.0);
  for (std::size_t k = 0; k < best.faces.size(); ++k) {
    if (out.failed[k]) continue;
    FaceCut& f = best.faces[k];
    out.face_pass_distance[k] = delta * f.max_factor;
    out.curves += f.curves;
    out.unreachable_length += f.unreachable;
    out.unreachable_from_above += f.from_above;
    out.max_pass_distance = std::max(out.max_pass_distance, delta * f.max_factor);
    std::move(f.pieces.begin(), f.pieces.end(), std::back_inserter(pieces));
  }
  out.pieces = zig_zag(std::move(pieces), best_axis == 1 ? 1 : 0);
  return out;
}

}  // namespace isocam
