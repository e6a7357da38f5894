// Elber & Cohen, Algorithm 1 (adaptive isocurve extraction), with the
// guards and the face/direction orchestration around it.
#include "isocam/adaptive_isocurve.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <Standard_Failure.hxx>

#include "finishing/coverage.h"
#include "geometry/iso_distance.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"

namespace isocam {

std::string face_label(int face) {
  return "face " + std::to_string(face) + " (Face" + std::to_string(face + 1) + ")";
}

double stepover_for_scallop(double r, double h) { return 2.0 * std::sqrt(2.0 * r * h - h * h); }

double scallop_for_stepover(double r, double delta) {
  const double half = 0.5 * delta;
  return half >= r ? r : r - std::sqrt(r * r - half * half);
}

namespace {

struct Level {
  double v;
  PiecewiseBezier curve;
};

class AdaptiveRecursion {
 public:
  AdaptiveRecursion(const PatchGrid& g, int face, IsoDirection dir, double delta,
                    const IsoParams& p, const ProgressSlice& progress)
      : g_(g), face_(face), dir_(dir), delta_(delta), params_(p), progress_(progress),
        area_((g.umax() - g.umin()) * (g.vmax() - g.vmin())) {}

  FaceCoverage run() {
    Level c1{g_.vmin(), g_.iso_v(g_.vmin())};
    Level c2{g_.vmax(), g_.iso_v(g_.vmax())};
    out_.curves.push_back({face_, dir_, c1.v, g_.umin(), g_.umax()});
    out_.curves.push_back({face_, dir_, c2.v, g_.umin(), g_.umax()});
    aux(c1, c2, {{g_.umin(), g_.umax()}}, 1);
    return std::move(out_);
  }

 private:
  // AdapIsoCurveAux over all parts of the common domain at once: the pieces
  // of one pair that exceed delta share one middle isocurve level.
  void aux(const Level& c1, const Level& c2, const std::vector<Interval>& domain, int depth) {
    progress_.check();
    std::vector<Interval> exceed;
    for (const Interval& d : domain) {
      const auto pieces = iso_distance_squared(c1.curve, c2.curve, d.lo, d.hi);
      const std::vector<Interval> e = exceeding(pieces, delta_);
      for (const Interval& ok : complement(e, d.lo, d.hi)) {
        accept(c1, c2, ok, e.empty() ? &pieces : nullptr);
      }
      exceed.insert(exceed.end(), e.begin(), e.end());
    }
    if (exceed.empty()) return;
    if (depth >= params_.max_depth) {
      throw GeometryError(face_label(face_) + ": Algorithm 1 needs more than max_depth = " +
                          std::to_string(params_.max_depth) + " levels of middle isocurves near v = " +
                          std::to_string(c1.v));
    }
    if (c2.v - c1.v < params_.min_param_gap * (g_.vmax() - g_.vmin())) {
      throw GeometryError(face_label(face_) +
                          ": isocurves closer than min_param_gap in parameter are still more than "
                          "delta apart near v = " + std::to_string(c1.v) +
                          " (the surface is singular there)");
    }
    const double vm = 0.5 * (c1.v + c2.v);
    const Level mid{vm, g_.iso_v(vm)};
    for (const Interval& e : exceed) out_.curves.push_back({face_, dir_, vm, e.lo, e.hi});
    aux(c1, mid, exceed, depth + 1);
    aux(mid, c2, exceed, depth + 1);
  }

  // A part of the domain where the pair is within delta: record the largest
  // iso-distance left and the progress.
  void accept(const Level& c1, const Level& c2, const Interval& ok,
              const std::vector<IsoDistancePiece>* whole) {
    const double m = whole ? max_iso_distance(*whole)
                           : max_iso_distance(iso_distance_squared(c1.curve, c2.curve, ok.lo, ok.hi));
    out_.max_iso_distance = std::max(out_.max_iso_distance, m);
    done_ += (c2.v - c1.v) * (ok.hi - ok.lo);
    progress_.report(std::min(1.0, done_ / area_));
  }

  const PatchGrid& g_;
  int face_;
  IsoDirection dir_;
  double delta_;
  const IsoParams& params_;
  ProgressSlice progress_;
  double area_;
  double done_ = 0.0;
  FaceCoverage out_;
};

// True if every adjacent pair of complete isocurves at `n` equal steps is
// within delta; fills `max_dist` with the largest iso-distance when it is.
bool uniform_ok(const PatchGrid& g, int n, double delta, double* max_dist,
                const ProgressSlice& progress) {
  const double dv = (g.vmax() - g.vmin()) / n;
  PiecewiseBezier prev = g.iso_v(g.vmin());
  double m = 0.0;
  for (int k = 1; k <= n; ++k) {
    progress.check();
    PiecewiseBezier next = g.iso_v(k == n ? g.vmax() : g.vmin() + k * dv);
    const auto pieces = iso_distance_squared(prev, next, g.umin(), g.umax());
    if (!exceeding(pieces, delta).empty()) return false;
    m = std::max(m, max_iso_distance(pieces));
    prev = std::move(next);
  }
  *max_dist = m;
  return true;
}

void validate(const IsoParams& p) {
  auto bad = [](const std::string& s) { throw InvalidArgument(s); };
  if (!(p.ball_radius > 0) || !std::isfinite(p.ball_radius))
    bad("ball_radius must be > 0 mm (got " + std::to_string(p.ball_radius) + ")");
  if (!(p.scallop_height > 0) || !(p.scallop_height < p.ball_radius))
    bad("scallop_height must be > 0 and < the ball radius " + std::to_string(p.ball_radius) +
        " mm (got " + std::to_string(p.scallop_height) + ")");
  if (!(p.chord_tolerance > 0) || !std::isfinite(p.chord_tolerance))
    bad("chord_tolerance must be > 0 mm (got " + std::to_string(p.chord_tolerance) + ")");
  if (p.max_depth < 1) bad("max_depth must be >= 1 (got " + std::to_string(p.max_depth) + ")");
  if (!(p.min_param_gap > 0) || !(p.min_param_gap < 1))
    bad("min_param_gap must be in (0, 1) (got " + std::to_string(p.min_param_gap) + ")");
  if (!std::isfinite(p.safe_z)) bad("safe_z must be a finite height");
}

struct FaceResult {
  Toolpath path;
  FaceCoverage coverage;
  IsoDirection dir;
  int emitted = 0;
};

FaceResult face_in_direction(const PatchGrid& grid, int face, IsoDirection dir, double delta,
                             const IsoParams& p, const ProgressSlice& progress) {
  const PatchGrid g = dir == IsoDirection::U ? grid.transposed() : grid;
  FaceResult r;
  r.dir = dir;
  r.coverage = p.pattern == IsoPattern::Uniform
                   ? uniform_coverage(g, face, dir, delta, p, progress)
                   : adaptive_coverage(g, face, dir, delta, p, progress);
  r.path = face_toolpath(g, r.coverage.curves, p, &r.emitted);
  return r;
}

}  // namespace

FaceCoverage adaptive_coverage(const PatchGrid& grid, int face, IsoDirection dir,
                               double delta, const IsoParams& params,
                               const ProgressSlice& progress) {
  return AdaptiveRecursion(grid, face, dir, delta, params, progress).run();
}

FaceCoverage uniform_coverage(const PatchGrid& g, int face, IsoDirection dir, double delta,
                              const IsoParams& params, const ProgressSlice& progress) {
  // Doubling then bisection on the number of steps; the answer is verified,
  // so the guarantee holds even where validity is not monotone in n.
  double m = 0.0;
  int hi = 1;
  while (!uniform_ok(g, hi, delta, &m, progress)) {
    hi *= 2;
    if (hi > (1 << 20) || g.vmax() - g.vmin() < params.min_param_gap * hi * (g.vmax() - g.vmin()))
      throw GeometryError(face_label(face) + ": no uniform isocurve spacing reaches delta");
  }
  int lo = hi / 2;  // lo fails (or is 0)
  double best_m = m;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (uniform_ok(g, mid, delta, &m, progress)) {
      hi = mid;
      best_m = m;
    } else {
      lo = mid;
    }
  }
  FaceCoverage c;
  c.max_iso_distance = best_m;
  const double dv = (g.vmax() - g.vmin()) / hi;
  for (int k = 0; k <= hi; ++k) {
    c.curves.push_back({face, dir, k == hi ? g.vmax() : g.vmin() + k * dv, g.umin(), g.umax()});
  }
  return c;
}

IsoResult adaptive_isocurve(const TopoDS_Shape& shape, const std::vector<int>& faces,
                            const IsoParams& params, Progress* progress) {
  validate(params);
  if (shape.IsNull()) throw InvalidArgument("brep: the shape is empty");
  const std::vector<TopoDS_Face> all = faces_of(shape);
  if (all.empty()) throw InvalidArgument("brep: the shape has no faces");
  if (faces.empty()) throw InvalidArgument("faces: no face given");
  std::set<int> seen;
  for (int f : faces) {
    if (f < 0 || f >= static_cast<int>(all.size()))
      throw InvalidArgument("faces: index " + std::to_string(f) + " is out of range (the shape has " +
                            std::to_string(all.size()) + " faces, indices 0.." +
                            std::to_string(all.size() - 1) + ")");
    if (!seen.insert(f).second) throw InvalidArgument("faces: index " + std::to_string(f) + " given twice");
  }
  const double delta = stepover_for_scallop(params.ball_radius, params.scallop_height);
  // Algorithm 1 runs a hair inside delta so that rounding (and the 1e-9
  // tangential slack of the root finder) never lets a pair exceed delta.
  const double delta_work = delta * (1.0 - 4e-9);
  IsoResult result;
  result.metrics.delta = delta;
  double max_dist = 0.0;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const int f = faces[k];
    try {
      const PatchGrid grid = PatchGrid::from_face(all[static_cast<std::size_t>(f)], f);
      std::vector<IsoDirection> dirs{params.direction};
      if (params.direction == IsoDirection::Auto) dirs = {IsoDirection::V, IsoDirection::U};
      FaceResult best;
      double best_len = 0;
      const ProgressSlice face_progress =
          ProgressSlice(progress).sub(double(k) / double(faces.size()), double(k + 1) / double(faces.size()));
      for (std::size_t di = 0; di < dirs.size(); ++di) {
        const IsoDirection d = dirs[di];
        const double n = double(dirs.size());
        FaceResult r = face_in_direction(grid, f, d, delta_work, params,
                                         face_progress.sub(double(di) / n, double(di + 1) / n));
        const double len = measure(r.path).feed;
        if (best.path.empty() || len < best_len) {
          best = std::move(r);
          best_len = len;
        }
      }
      for (SubIsocurve& c : best.coverage.curves) result.curves.push_back(c);
      result.face_direction.push_back(best.dir);
      result.metrics.sub_isocurves += best.emitted;
      max_dist = std::max(max_dist, best.coverage.max_iso_distance);
      result.path.append(best.path);
    } catch (const Standard_Failure& e) {
      throw GeometryError(face_label(f) + ": OpenCASCADE failed: " + e.GetMessageString());
    }
    report_progress(progress, double(k + 1) / double(faces.size()));
  }
  double top = -1e300;
  for (std::size_t i = 0; i < result.path.size(); ++i)
    if (result.path.kind[i] != static_cast<std::uint8_t>(MoveKind::Rapid)) top = std::max(top, result.path.z[i]);
  if (params.safe_z < top)
    throw InvalidArgument("safe_z (" + std::to_string(params.safe_z) +
                          " mm) is below the highest cutting point of the path (" +
                          std::to_string(top) + " mm)");
  const PathLengths len = measure(result.path);
  result.metrics.cutting_length = len.feed;
  result.metrics.rapid_length = len.rapid;
  result.metrics.plunge_length = len.plunge;
  result.metrics.retracts = len.retracts;
  result.metrics.max_iso_distance = max_dist;
  result.metrics.guaranteed_scallop = scallop_for_stepover(params.ball_radius, max_dist);
  return result;
}

}  // namespace isocam
