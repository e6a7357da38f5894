// The samples a constant-scallop certificate is measured on, Definition 1
// on them, and the clip of paths to the face's wires (scallop_coverage.h).
#include "finishing/scallop_coverage.h"

#include "finishing/stepover.h"
#include "geometry/curvature.h"

namespace isocam {
namespace {

// Per patch of a grid (index j * patches_u + i), the factor in (0, 1] by
// which the coverage checks sample it finer than on flat ground: the chord
// that leaves h on the patch's most convex ground (the largest principal
// curvature of 3 x 3 samples, raised by a quarter of their spread) over the
// flat one, so that no uncovered sliver as narrow as the stepover the ball
// allows there falls between two samples.
std::vector<double> convex_refinement(const PatchGrid& g, double r, double h, double e) {
  static constexpr double kAt[3] = {1.0 / 6, 0.5, 5.0 / 6};
  const double flat = stepover_chord_with_error(r, h, 0.0, e);
  std::vector<double> out(static_cast<std::size_t>(g.patches_u() * g.patches_v()), 1.0);
  for (int j = 0; j < g.patches_v(); ++j)
    for (int i = 0; i < g.patches_u(); ++i) {
      const double k = patch_curvature_bound(g, i, j, kAt, &CurvatureSample::k_max, 0.0);
      out[static_cast<std::size_t>(j * g.patches_u() + i)] =
          std::clamp(stepover_chord_with_error(r, h, k, e) / flat, 1.0 / 16, 1.0);
    }
  return out;
}

// Levels of one parameter about `step` apart in space: per span of its
// breaks (`breaks`), as many as the span's longest side across `side(k, s)`
// (the distance between the span's two ends along the other parameter's
// break s) asks, at the middles of equal parts: f(level).
template <class Side, class F>
void for_each_level(const std::vector<double>& breaks, std::size_t others, double step, Side side,
                    F f) {
  for (std::size_t k = 0; k + 1 < breaks.size(); ++k) {
    double longest = 0.0;
    for (std::size_t s = 0; s < others; ++s) longest = std::max(longest, side(k, s));
    const int n = std::clamp(static_cast<int>(std::ceil(longest / step)), 1, 512);
    for (int b = 0; b < n; ++b) f(breaks[k] + (b + 0.5) / n * (breaks[k + 1] - breaks[k]));
  }
}

// Points of the face's boundary (its wires and the untrimmed sides): where
// the iso-lines of both parameters, about `step` apart, enter and leave the
// face (TrimDomain::inside() in the working grid's terms).
std::vector<ParamPt> boundary_samples(const PatchGrid& g, const TrimDomain& trim, bool transposed,
                                      double step) {
  std::vector<ParamPt> out;
  auto f = [&out](double u, double v) { out.push_back({u, v}); };
  const auto& ub = g.ubreaks();
  const auto& vb = g.vbreaks();
  // Iso-v lines of the working grid (face iso-u lines when transposed).
  for_each_level(
      vb, ub.size(), step,
      [&](std::size_t j, std::size_t i) {
        return g.eval(ub[i], vb[j]).Distance(g.eval(ub[i], vb[j + 1]));
      },
      [&](double v) {
        for (const Interval& in : trim.inside(!transposed, v, g.umin(), g.umax())) {
          f(in.lo, v);
          f(in.hi, v);
        }
      });
  for_each_level(
      ub, vb.size(), step,
      [&](std::size_t i, std::size_t j) {
        return g.eval(ub[i], vb[j]).Distance(g.eval(ub[i + 1], vb[j]));
      },
      [&](double u) {
        for (const Interval& in : trim.inside(transposed, u, g.vmin(), g.vmax())) {
          f(u, in.lo);
          f(u, in.hi);
        }
      });
  return out;
}

}  // namespace

FaceSampling::FaceSampling(const PatchGrid& g, const TrimDomain& trim, bool transposed, double step,
                           double r, double h, double e)
    : g_(g),
      trim_(trim),
      transposed_(transposed),
      step_(step),
      refine_(convex_refinement(g, r, h, e)),
      boundary_(boundary_samples(g, trim, transposed, step)) {}

void raise_coverage(const Gap& q, double r, double e, double* max_gap, double* scallop) {
  // Concave ground tighter than the ball: it cannot touch there (its offset
  // folds; the clearance cut reports that path as unreachable).
  if (q.kappa * r <= -1.0) return;
  *max_gap = std::max(*max_gap, q.d);
  *scallop = raise_scallop(*scallop, r, 2 * q.d, q.kappa, e);
}

Gap gap_at(const PatchGrid& g, const PathIndex& index, double u, double v) {
  Gap out;
  out.x = g.eval(u, v);
  out.d = index.distance(out.x, &out.at, 0.0, &out.end);
  if (out.x.Distance(out.at) >= 1e-12)
    out.kappa = normal_curvature(g, {u, v}, gp_Vec(out.x, out.at));
  return out;
}

double raise_scallop(double so_far, double r, double c, double kappa, double e) {
  if (so_far > e && c <= stepover_chord_with_error(r, so_far, kappa, e)) return so_far;
  return std::max(so_far, scallop_with_error(r, c, kappa, e));
}

double chord_of_arc(double s, double kappa) {
  const double half = 0.5 * std::abs(kappa) * s;
  return half < 1e-6 ? s : 2.0 * std::sin(std::min(half, 0.5 * M_PI)) / std::abs(kappa);
}

ParamPt uv_at(const FrontPiece& pc, double t) {
  const std::size_t k = std::min(static_cast<std::size_t>(std::max(t, 0.0)), pc.size() - 2);
  const double f = t - double(k);
  return {pc[k].uv.u + f * (pc[k + 1].uv.u - pc[k].uv.u),
          pc[k].uv.v + f * (pc[k + 1].uv.v - pc[k].uv.v)};
}

std::vector<std::pair<double, double>> WireClip::inside_runs(const FrontPiece& pc) const {
  std::vector<std::pair<double, double>> runs;
  bool in = inside(pc[0].uv);
  double start = 0.0;
  for (std::size_t k = 0; k + 1 < pc.size(); ++k) {
    using RectClass = TrimDomain::RectClass;
    RectClass state = classify(pc[k].uv, pc[k + 1].uv);
    // An end inside (or the previous run open) contradicts "outside": test it.
    if (state == RectClass::Outside && (in || inside(pc[k + 1].uv))) state = RectClass::Boundary;
    if (state == RectClass::Inside && in) continue;
    std::vector<double> ts;
    if (state == RectClass::Boundary)
      for (int q = 1; q < 8; ++q) ts.push_back(double(k) + q / 8.0);
    ts.push_back(double(k + 1));
    double tp = double(k);
    for (double t : ts) {
      const bool s = state == RectClass::Outside ? false : inside(uv_at(pc, t));
      if (in && !s) runs.emplace_back(start, boundary(pc, tp, t));
      if (!in && s) start = boundary(pc, t, tp);
      in = s;
      tp = t;
    }
  }
  if (in) runs.emplace_back(start, double(pc.size() - 1));
  return runs;
}

FrontPiece WireClip::contact(const FrontPiece& pc, double a, double b) const {
  FrontPiece out;
  for (double t = a;; t = std::min(b, std::floor(t) + 1.0)) {
    FrontPoint x;
    x.uv = uv_at(pc, t);
    x.p = g_.eval(x.uv.u, x.uv.v);
    out.push_back(x);
    if (t >= b) break;
  }
  return out;
}

void WireClip::add_inside(const FrontPiece& pc, PathIndex* index, PathIndex* also) const {
  if (pc.size() < 2) return;
  for (const auto& [a, b] : inside_runs(pc)) {
    const FrontPiece c = contact(pc, a, b);
    index->add(c);
    if (also) also->add(c);
  }
}

bool WireClip::inside(const ParamPt& uv) const {
  return transposed_ ? trim_.contains(uv.v, uv.u) : trim_.contains(uv.u, uv.v);
}

TrimDomain::RectClass WireClip::classify(const ParamPt& a, const ParamPt& b) const {
  const double u0 = std::min(a.u, b.u), u1 = std::max(a.u, b.u);
  const double v0 = std::min(a.v, b.v), v1 = std::max(a.v, b.v);
  return transposed_ ? trim_.classify_rect(v0, v1, u0, u1) : trim_.classify_rect(u0, u1, v0, v1);
}

double WireClip::boundary(const FrontPiece& pc, double t_in, double t_out) const {
  for (int it = 0; it < 60; ++it) {
    const ParamPt a = uv_at(pc, t_in), b = uv_at(pc, t_out);
    if (g_.eval(a.u, a.v).Distance(g_.eval(b.u, b.v)) <= 1e-4 * tol_) break;
    const double m = 0.5 * (t_in + t_out);
    (inside(uv_at(pc, m)) ? t_in : t_out) = m;
  }
  return t_in;
}

}  // namespace isocam
