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
  // AdapIsoCurveAux over all parts of the common domain at once: the parts
  // of one pair that need refining share one middle isocurve level.
  //
  // A part needs a middle curve where the iso-distance exceeds delta (the
  // paper's test) or where the strip between the two curves may be wider
  // than 2 delta along the surface (a bound on the integral of |dS/dv|). The
  // second test is what makes Definition 1 hold where the chord is short but
  // the surface between is not, as between the two seam curves of a closed
  // surface; elsewhere it is implied by the first and costs nothing.
  void aux(const Level& c1, const Level& c2, const std::vector<Interval>& domain, int depth) {
    progress_.check();
    std::vector<Interval> refine;
    for (const Interval& d : domain) {
      const auto pieces = iso_distance_squared(c1.curve, c2.curve, d.lo, d.hi);
      const std::vector<Interval> chord = exceeding(pieces, delta_);
      const std::vector<Interval> wide = too_wide(c1.v, c2.v, d);
      const std::vector<Interval> here = merged(chord, wide);
      for (const Interval& ok : complement(here, d.lo, d.hi)) {
        accept(c1, c2, ok, here.empty() ? &pieces : nullptr);
      }
      refine.insert(refine.end(), here.begin(), here.end());
    }
    if (refine.empty()) return;
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
    for (const Interval& e : refine) out_.curves.push_back({face_, dir_, vm, e.lo, e.hi});
    aux(c1, mid, refine, depth + 1);
    aux(mid, c2, refine, depth + 1);
  }

  // Parts of d (whole parts of u-spans of the grid, clipped to d) where the
  // strip between levels v1 and v2 may be wider than 2 delta along the
  // surface.
  std::vector<Interval> too_wide(double v1, double v2, const Interval& d) const {
    std::vector<Interval> out;
    const auto& br = g_.ubreaks();
    const int parts = PatchGrid::kStripParts;
    int first = static_cast<int>(std::upper_bound(br.begin(), br.end(), d.lo) - br.begin()) - 1;
    first = std::clamp(first, 0, g_.patches_u() - 1);
    for (int i = first; i < g_.patches_u() && br[static_cast<std::size_t>(i)] < d.hi; ++i) {
      const double u0 = br[static_cast<std::size_t>(i)], u1 = br[static_cast<std::size_t>(i) + 1];
      for (int s = 0; s < parts; ++s) {
        const double w = g_.strip_width_bound(i, s, v1, v2);
        if (w <= 2.0 * delta_) continue;
        const Interval iv{std::max(d.lo, u0 + (u1 - u0) * s / parts),
                          std::min(d.hi, u0 + (u1 - u0) * (s + 1) / parts)};
        if (!(iv.hi > iv.lo)) continue;
        if (!out.empty() && iv.lo <= out.back().hi) {
          out.back().hi = iv.hi;
        } else {
          out.push_back(iv);
        }
      }
    }
    return out;
  }

  // Union of two sorted lists of disjoint intervals.
  static std::vector<Interval> merged(const std::vector<Interval>& a, const std::vector<Interval>& b) {
    std::vector<Interval> v = a;
    v.insert(v.end(), b.begin(), b.end());
    std::sort(v.begin(), v.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
    std::vector<Interval> out;
    for (const Interval& x : v) {
      if (!out.empty() && x.lo <= out.back().hi) {
        out.back().hi = std::max(out.back().hi, x.hi);
      } else {
        out.push_back(x);
      }
    }
    return out;
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
  if (!(p.gouge_tolerance > 0) || !(p.gouge_tolerance < p.ball_radius))
    bad("gouge_tolerance must be > 0 and < the ball radius (got " + std::to_string(p.gouge_tolerance) + ")");
}

struct FaceResult {
  Toolpath path;
  FaceCoverage coverage;
  IsoDirection dir = IsoDirection::V;
  FacePathStats stats;
};

FaceResult face_in_direction(const PatchGrid& grid, int face, IsoDirection dir, double delta,
                             const IsoParams& p, const ClearanceModel& model,
                             const ProgressSlice& progress) {
  const PatchGrid g = dir == IsoDirection::U ? grid.transposed() : grid;
  FaceResult r;
  r.dir = dir;
  r.coverage = p.pattern == IsoPattern::Uniform
                   ? uniform_coverage(g, face, dir, delta, p, progress)
                   : adaptive_coverage(g, face, dir, delta, p, progress);
  r.path = face_toolpath(g, r.coverage.curves, p, model, &r.stats);
  return r;
}

// The faster of the requested directions (Auto: both) on one face.
FaceResult best_direction(const PatchGrid& grid, int face, double delta, const IsoParams& params,
                          const ClearanceModel& model, const ProgressSlice& progress) {
  std::vector<IsoDirection> dirs{params.direction};
  if (params.direction == IsoDirection::Auto) dirs = {IsoDirection::V, IsoDirection::U};
  FaceResult best;
  double best_len = 0;
  const double n = double(dirs.size());
  for (std::size_t di = 0; di < dirs.size(); ++di) {
    FaceResult r = face_in_direction(grid, face, dirs[di], delta, params, model,
                                     progress.sub(double(di) / n, double(di + 1) / n));
    const double len = measure(r.path).feed;
    if (di == 0 || len < best_len) {
      best = std::move(r);
      best_len = len;
    }
  }
  return best;
}

void check_faces(const std::vector<int>& faces, std::size_t count) {
  if (faces.empty()) throw InvalidArgument("faces: no face given");
  std::set<int> seen;
  for (int f : faces) {
    if (f < 0 || f >= static_cast<int>(count))
      throw InvalidArgument("faces: index " + std::to_string(f) + " is out of range (the shape has " +
                            std::to_string(count) + " faces, indices 0.." +
                            std::to_string(count - 1) + ")");
    if (!seen.insert(f).second) throw InvalidArgument("faces: index " + std::to_string(f) + " given twice");
  }
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
  check_faces(faces, all.size());
  const double delta = stepover_for_scallop(params.ball_radius, params.scallop_height);
  // Algorithm 1 runs a hair inside delta so that rounding (and the 1e-9
  // tangential slack of the root finder) never lets a pair exceed delta.
  const double delta_work = delta * (1.0 - 4e-9);
  IsoResult result;
  result.metrics.delta = delta;
  std::vector<PatchGrid> grids;
  ClearanceModel model(params.gouge_tolerance);
  for (int f : faces) {
    try {
      grids.push_back(PatchGrid::from_face(all[static_cast<std::size_t>(f)], f));
    } catch (const Standard_Failure& e) {
      throw GeometryError(face_label(f) + ": OpenCASCADE failed: " + e.GetMessageString());
    }
    // The ball is kept clear of every picked face, its own included where it
    // curves tighter than the ball.
    model.add(grids.back());
  }
  model.build();
  double max_dist = 0.0;
  const double nf = double(faces.size());
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const int f = faces[k];
    FaceResult best;
    try {
      best = best_direction(grids[k], f, delta_work, params, model,
                            ProgressSlice(progress).sub(double(k) / nf, double(k + 1) / nf));
    } catch (const Standard_Failure& e) {
      throw GeometryError(face_label(f) + ": OpenCASCADE failed: " + e.GetMessageString());
    }
    result.curves.insert(result.curves.end(), best.coverage.curves.begin(), best.coverage.curves.end());
    result.face_direction.push_back(best.dir);
    result.metrics.sub_isocurves += best.stats.curves;
    result.metrics.unreachable_length += best.stats.unreachable_length;
    max_dist = std::max(max_dist, best.coverage.max_iso_distance);
    result.path.append(best.path);
  }
  report_progress(progress, 1.0);
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
