// Elber & Cohen, Algorithm 1 (adaptive isocurve extraction), with the
// guards and the face/direction orchestration around it.
#include "isocam/adaptive_isocurve.h"

#include <Standard_Failure.hxx>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "finishing/coverage.h"
#include "finishing/stepover.h"
#include "geometry/iso_distance.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"

namespace isocam {

std::string face_label(int face) {
  return "face " + std::to_string(face) + " (Face" + std::to_string(face + 1) + ")";
}

namespace {
void check_radius(double r) {
  if (!std::isfinite(r) || !(r > 0) || r > 1e5)
    throw InvalidArgument("ball_radius = " + std::to_string(r) +
                          " is out of range: must be > 0 and <= 1e5 mm");
}
}  // namespace

double stepover_for_scallop(double r, double h) {
  check_radius(r);
  if (!std::isfinite(h) || !(h > 0) || h > r)
    throw InvalidArgument(
        "scallop_height = " + std::to_string(h) +
        " is out of range: must be > 0 and <= ball_radius = " + std::to_string(r));
  return 2.0 * std::sqrt(2.0 * r * h - h * h);
}

double scallop_for_stepover(double r, double delta) {
  check_radius(r);
  if (!std::isfinite(delta) || delta < 0 || delta > 2 * r)
    throw InvalidArgument("delta = " + std::to_string(delta) +
                          " is out of range: must be >= 0 and <= the ball diameter " +
                          std::to_string(2 * r));
  const double half = 0.5 * delta;
  return half >= r ? r : r - std::sqrt(r * r - half * half);
}

namespace {

// Algorithm 1 works a hair inside delta so that rounding (and the 1e-9
// tangential slack of the root finder) never lets a pair exceed delta.
constexpr double kWorkingDelta = 1.0 - 4e-9;

// The tolerance of each piece of an iso-distance between levels v1 and v2.
std::vector<double> piece_deltas(const PatchGrid& g, const StepoverField& field,
                                 const std::vector<IsoDistancePiece>& pieces, double v1,
                                 double v2) {
  std::vector<double> d;
  d.reserve(pieces.size());
  for (const IsoDistancePiece& p : pieces)
    d.push_back(kWorkingDelta * field.delta(g.span_of_u(0.5 * (p.a + p.b)), v1, v2));
  return d;
}

// The largest iso-distance of the pieces and the scallop it guarantees.
void measure_pair(const PatchGrid& g, const StepoverField& field,
                  const std::vector<IsoDistancePiece>& pieces, double v1, double v2,
                  FaceCoverage* out) {
  for (const IsoDistancePiece& p : pieces) {
    const double m = max_iso_distance({p});
    out->max_iso_distance = std::max(out->max_iso_distance, m);
    out->guaranteed_scallop =
        std::max(out->guaranteed_scallop, field.scallop(g.span_of_u(0.5 * (p.a + p.b)), v1, v2, m));
  }
}

// Parts of d (whole parts of u-spans of the grid, clipped to d) where the
// strip between levels v1 and v2 may be wider than 2 delta along the
// surface.
std::vector<Interval> too_wide(const PatchGrid& g, const StepoverField& field, double v1, double v2,
                               const Interval& d) {
  std::vector<Interval> out;
  const auto& br = g.ubreaks();
  const int parts = PatchGrid::kStripParts;
  int first = static_cast<int>(std::upper_bound(br.begin(), br.end(), d.lo) - br.begin()) - 1;
  first = std::clamp(first, 0, g.patches_u() - 1);
  for (int i = first; i < g.patches_u() && br[static_cast<std::size_t>(i)] < d.hi; ++i) {
    const double u0 = br[static_cast<std::size_t>(i)], u1 = br[static_cast<std::size_t>(i) + 1];
    for (int s = 0; s < parts; ++s) {
      const double w = g.strip_width_bound(i, s, v1, v2);
      if (w <= 2.0 * kWorkingDelta * field.delta(i, v1, v2)) continue;
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

struct Level {
  double v;
  PiecewiseBezier curve;
};

class AdaptiveRecursion {
 public:
  AdaptiveRecursion(const PatchGrid& g, int face, IsoDirection dir, const StepoverField& field,
                    const IsoParams& p, const ProgressSlice& progress)
      : g_(g),
        face_(face),
        dir_(dir),
        field_(field),
        params_(p),
        progress_(progress),
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
    double strips = 2.0;  // how many strips of width delta the widest part needs
    for (const Interval& d : domain) {
      const auto pieces = iso_distance_squared(c1.curve, c2.curve, d.lo, d.hi);
      const std::vector<double> deltas = piece_deltas(g_, field_, pieces, c1.v, c2.v);
      const std::vector<Interval> chord = exceeding(pieces, deltas);
      if (!chord.empty())
        for (std::size_t k = 0; k < pieces.size(); ++k)
          strips = std::max(strips, std::ceil(max_iso_distance({pieces[k]}) / deltas[k]));
      const std::vector<Interval> wide = too_wide(g_, field_, c1.v, c2.v, d);
      const std::vector<Interval> here = merged(chord, wide);
      for (const Interval& ok : complement(here, d.lo, d.hi)) {
        accept(c1, c2, ok, here.empty() ? &pieces : nullptr);
      }
      refine.insert(refine.end(), here.begin(), here.end());
    }
    if (refine.empty()) return;
    if (depth >= params_.max_depth) {
      throw GeometryError(face_label(face_) + ": Algorithm 1 needs more than max_depth = " +
                          std::to_string(params_.max_depth) +
                          " levels of middle isocurves near v = " + std::to_string(c1.v));
    }
    if (c2.v - c1.v < params_.min_param_gap * (g_.vmax() - g_.vmin())) {
      throw GeometryError(face_label(face_) +
                          ": isocurves closer than min_param_gap in parameter are still more than "
                          "delta apart near v = " +
                          std::to_string(c1.v) + " (the surface is singular there)");
    }
    // The paper inserts the middle isocurve at the mid parameter. Where the
    // pair needs k strips, the level at floor(k/2)/k of the way leaves
    // halves that need whole numbers of strips (the iso-distance is close to
    // linear in v once the curves are near), so the curves end up close to
    // delta apart instead of anywhere in (delta/2, delta]: a shorter path
    // with the same guarantee, which every accepted pair still proves.
    const double k = std::min(strips, 1e6);
    const double vm = c1.v + (c2.v - c1.v) * std::floor(0.5 * k) / k;
    const Level mid{vm, g_.iso_v(vm)};
    for (const Interval& e : refine) out_.curves.push_back({face_, dir_, vm, e.lo, e.hi});
    aux(c1, mid, refine, depth + 1);
    aux(mid, c2, refine, depth + 1);
  }

  // Union of two sorted lists of disjoint intervals.
  static std::vector<Interval> merged(const std::vector<Interval>& a,
                                      const std::vector<Interval>& b) {
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
  // iso-distance left, the scallop it guarantees, and the progress.
  void accept(const Level& c1, const Level& c2, const Interval& ok,
              const std::vector<IsoDistancePiece>* whole) {
    measure_pair(g_, field_,
                 whole ? *whole : iso_distance_squared(c1.curve, c2.curve, ok.lo, ok.hi), c1.v,
                 c2.v, &out_);
    out_.strips.push_back({c1.v, c2.v, ok});
    done_ += (c2.v - c1.v) * (ok.hi - ok.lo);
    progress_.report(std::min(1.0, done_ / area_));
  }

  const PatchGrid& g_;
  int face_;
  IsoDirection dir_;
  const StepoverField& field_;
  const IsoParams& params_;
  ProgressSlice progress_;
  double area_;
  double done_ = 0.0;
  FaceCoverage out_;
};

// True if every adjacent pair of complete isocurves at `n` equal steps is
// within delta; fills `measured` with the largest iso-distance and scallop
// when it is.
bool uniform_ok(const PatchGrid& g, int n, const StepoverField& field, FaceCoverage* measured,
                const ProgressSlice& progress) {
  const double dv = (g.vmax() - g.vmin()) / n;
  double v1 = g.vmin();
  PiecewiseBezier prev = g.iso_v(v1);
  FaceCoverage m;
  for (int k = 1; k <= n; ++k) {
    progress.check();
    const double v2 = k == n ? g.vmax() : g.vmin() + k * dv;
    PiecewiseBezier next = g.iso_v(v2);
    const auto pieces = iso_distance_squared(prev, next, g.umin(), g.umax());
    // The iso-distance, and the strip width as Algorithm 1 checks it: two
    // curves that collapse to one point (the poles of a sphere) are not
    // within delta of the surface between them.
    if (!exceeding(pieces, piece_deltas(g, field, pieces, v1, v2)).empty() ||
        !too_wide(g, field, v1, v2, {g.umin(), g.umax()}).empty())
      return false;
    measure_pair(g, field, pieces, v1, v2, &m);
    m.strips.push_back({v1, v2, {g.umin(), g.umax()}});
    prev = std::move(next);
    v1 = v2;
  }
  *measured = std::move(m);
  return true;
}

}  // namespace

FaceCoverage adaptive_coverage(const PatchGrid& grid, int face, IsoDirection dir,
                               const StepoverField& field, const IsoParams& params,
                               const ProgressSlice& progress) {
  return AdaptiveRecursion(grid, face, dir, field, params, progress).run();
}

FaceCoverage uniform_coverage(const PatchGrid& g, int face, IsoDirection dir,
                              const StepoverField& field, const IsoParams& params,
                              const ProgressSlice& progress) {
  // Doubling then bisection on the number of steps; the answer is verified,
  // so the guarantee holds even where validity is not monotone in n.
  // Progress: the doubling has no known end, so each of its rounds goes
  // half way to 1/2; the bisection then counts its log2 rounds up to 1.
  FaceCoverage m;
  int hi = 1;
  double shown = 0.0;
  while (!uniform_ok(g, hi, field, &m, progress)) {
    hi *= 2;
    if (hi > (1 << 20) || g.vmax() - g.vmin() < params.min_param_gap * hi * (g.vmax() - g.vmin()))
      throw GeometryError(face_label(face) + ": no uniform isocurve spacing reaches delta");
    shown += 0.5 * (0.5 - shown);
    progress.report(shown);
  }
  int lo = hi / 2;  // lo fails (or is 0)
  const double rounds = std::max(1.0, std::ceil(std::log2(double(hi - lo))));
  int round = 0;
  FaceCoverage c = m;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (uniform_ok(g, mid, field, &m, progress)) {
      hi = mid;
      c = m;
    } else {
      lo = mid;
    }
    progress.report(0.5 + 0.5 * std::min(1.0, ++round / rounds));
  }
  progress.report(1.0);
  const double dv = (g.vmax() - g.vmin()) / hi;
  for (int k = 0; k <= hi; ++k) {
    c.curves.push_back({face, dir, k == hi ? g.vmax() : g.vmin() + k * dv, g.umin(), g.umax()});
  }
  return c;
}

}  // namespace isocam
