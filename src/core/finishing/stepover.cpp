#include "finishing/stepover.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/curvature.h"

namespace isocam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Half the angle phi between the contact normals, or a negative value where
// the ball leaves no cusp.
double half_angle(double r, double h, double kappa) {
  const double den = 4.0 * (1.0 + r * kappa) * (1.0 + h * kappa);
  if (!(den > 0)) return -1.0;
  const double q = (2.0 * r * h - h * h) / den;  // the flat (w/4)^2 as kappa -> 0
  const double x = std::abs(kappa) * std::sqrt(q);
  if (x >= 1.0) return -1.0;
  return std::asin(x);  // phi / 2
}

// Samples of the patch interior at which curvatures are taken.
constexpr double kSample[4] = {0.125, 0.375, 0.625, 0.875};

}  // namespace

double stepover_arc(double r, double h, double kappa) {
  const double a = half_angle(r, h, kappa);
  if (a < 0) return kInf;
  if (std::abs(kappa) < 1e-12) return 2.0 * std::sqrt(2.0 * r * h - h * h);
  return 4.0 * a / std::abs(kappa);  // w = rho phi_full = 2 rho phi
}

double stepover_chord(double r, double h, double kappa) {
  const double a = half_angle(r, h, kappa);
  if (a < 0) return kInf;
  if (std::abs(kappa) < 1e-12) return 2.0 * std::sqrt(2.0 * r * h - h * h);
  return 2.0 * std::sin(2.0 * a) / std::abs(kappa);  // chord 2 rho sin(phi)
}

double scallop_for_chord(double r, double c, double kappa) {
  if (!(c > 0)) return 0.0;
  // stepover_chord grows with h from 0, but on convex ground tighter than
  // the ball it turns back before h reaches r: the cusp is the smallest h
  // it reaches c at. A scan on a geometric grid brackets that crossing,
  // bisection locates it.
  double lo = 0.0, hi = -1.0;
  for (int k = 0; k <= 64; ++k) {
    const double h = r * std::pow(1e-9, 1.0 - k / 64.0) * (k == 64 ? 1 - 1e-12 : 1.0);
    if (stepover_chord(r, h, kappa) >= c) {
      hi = h;
      break;
    }
    lo = h;
  }
  if (hi < 0) return r;  // the balls do not meet
  for (int it = 0; it < 200 && hi - lo > 1e-13 * r; ++it) {
    const double mid = 0.5 * (lo + hi);
    (stepover_chord(r, mid, kappa) < c ? lo : hi) = mid;
  }
  return hi;
}

// Concave ground at least as tight as the ball: the ball leaves no cusp
// (it cannot reach the bottom, where the clearance cut leaves material and
// reports it as unreachable), as stepover_chord() says.
bool ball_fits(double r, double kappa) { return 1.0 + r * kappa > 0; }

double scallop_with_error(double r, double c, double kappa, double e) {
  if (!ball_fits(r, kappa)) return e;
  const double grow = 1.0 + e * kappa;  // > 0: e < r
  return e + scallop_for_chord(r - e, c * grow, kappa / grow);
}

double stepover_chord_with_error(double r, double h, double kappa, double e) {
  if (!(h > e)) return 0.0;
  if (!ball_fits(r, kappa)) return kInf;
  const double grow = 1.0 + e * kappa;
  return stepover_chord(r - e, h - e, kappa / grow) / grow;
}

double stepover_arc_with_error(double r, double h, double kappa, double e) {
  if (!(h > e)) return 0.0;
  if (!ball_fits(r, kappa)) return kInf;
  const double grow = 1.0 + e * kappa;
  return stepover_arc(r - e, h - e, kappa / grow) / grow;
}

StepoverField::StepoverField(const PatchGrid& g, const IsoParams& p, double e)
    : g_(g),
      r_(p.ball_radius),
      e_(e),
      flat_(stepover_chord_with_error(p.ball_radius, p.scallop_height, 0.0, e)),
      nu_(g.patches_u()) {
  const std::size_t n = static_cast<std::size_t>(g.patches_u() * g.patches_v());
  kappa_.assign(n, 0.0);
  delta_.assign(n, flat_);
  for (int j = 0; j < g.patches_v(); ++j)
    for (int i = 0; i < g.patches_u(); ++i) {
      const std::size_t k = static_cast<std::size_t>(j * nu_ + i);
      kappa_[k] = patch_curvature_bound(g, i, j, kSample, &CurvatureSample::k_cross, 0.0);
      // Concave ground would allow a wider step; the curvature bound takes
      // at most twice the flat one (which also bounds the step where the
      // ball cannot reach), the flat bound never more than the flat one.
      const double curved = stepover_chord_with_error(r_, p.scallop_height, kappa_[k], e_);
      delta_[k] = p.scallop_bound == IsoScallopBound::Curvature ? std::min(2.0 * flat_, curved)
                                                                : std::min(flat_, curved);
    }
}

template <class F>
void StepoverField::rows(double v1, double v2, F f) const {
  const auto& vb = g_.vbreaks();
  const int j0 =
      std::clamp(static_cast<int>(std::upper_bound(vb.begin(), vb.end(), v1) - vb.begin()) - 1, 0,
                 g_.patches_v() - 1);
  for (int j = j0; j < g_.patches_v(); ++j) {
    if (j > j0 && vb[static_cast<std::size_t>(j)] >= v2) break;
    f(static_cast<std::size_t>(j * nu_));
  }
}

double StepoverField::delta(int i, double v1, double v2) const {
  double d = kInf;
  rows(v1, v2,
       [&](std::size_t row) { d = std::min(d, delta_[row + static_cast<std::size_t>(i)]); });
  return d;
}

double StepoverField::max_delta() const {
  return delta_.empty() ? flat_ : *std::max_element(delta_.begin(), delta_.end());
}

double StepoverField::scallop(int i, double v1, double v2, double c) const {
  double h = 0.0;
  rows(v1, v2, [&](std::size_t row) {
    h = std::max(h, scallop_with_error(r_, c, kappa_[row + static_cast<std::size_t>(i)], e_));
  });
  return h;
}

double plane_pass_scallop(const PatchGrid& g, const TrimDomain* trim, double r, double d,
                          double e) {
  const auto& ub = g.ubreaks();
  const auto& vb = g.vbreaks();
  double kappa = 0.0;  // the most concave, where the ball fits
  for (int j = 0; j < g.patches_v(); ++j)
    for (int i = 0; i < g.patches_u(); ++i) {
      const double u0 = ub[static_cast<std::size_t>(i)], v0 = vb[static_cast<std::size_t>(j)];
      const double du = ub[static_cast<std::size_t>(i) + 1] - u0;
      const double dv = vb[static_cast<std::size_t>(j) + 1] - v0;
      double lo = kInf, hi = -kInf;
      for (double s : kSample)
        for (double t : kSample) {
          if (trim && !trim->contains(u0 + du * s, v0 + dv * t)) continue;
          const CurvatureSample c = curvature_at(g, i, j, s, t);
          if (!c.ok || !ball_fits(r, c.k_min)) continue;
          lo = std::min(lo, c.k_min);
          hi = std::max(hi, c.k_min);
        }
      if (!(hi >= lo)) continue;
      const double margin = lo - 0.25 * (hi - lo);
      kappa = std::min(kappa, ball_fits(r, margin) ? margin : lo);
    }
  // Balls of radius r - e about centres d apart on the circle of radius R
  // = 1/|kappa| - r (concave; the flat limit R -> inf), the cusp measured
  // from S + e N: [R - sqrt(R^2 - d^2/4)] + [(r - e) - sqrt((r - e)^2 -
  // d^2/4)], plus e. Centres farther apart than 2 (r - e) or than the
  // circle allows: no bound.
  const double re = r - e, q = 0.25 * d * d;
  if (q > re * re) return r;
  const double ball = re - std::sqrt(re * re - q);
  if (kappa >= 0) return e + ball;
  const double big = 1.0 / -kappa - r;
  if (q > big * big) return r;
  return std::min(r, e + ball + big - std::sqrt(big * big - q));
}

double lower_bound_length(const PatchGrid& g, const TrimDomain* trim, double r, double h) {
  const auto& ub = g.ubreaks();
  const auto& vb = g.vbreaks();
  double sum = 0.0;
  for (int j = 0; j < g.patches_v(); ++j)
    for (int i = 0; i < g.patches_u(); ++i) {
      const double du = ub[static_cast<std::size_t>(i) + 1] - ub[static_cast<std::size_t>(i)];
      const double dv = vb[static_cast<std::size_t>(j) + 1] - vb[static_cast<std::size_t>(j)];
      for (double s : kSample)
        for (double t : kSample) {
          if (trim && !trim->contains(ub[static_cast<std::size_t>(i)] + du * s,
                                      vb[static_cast<std::size_t>(j)] + dv * t))
            continue;
          const CurvatureSample c = curvature_at(g, i, j, s, t);
          const double w = stepover_arc(r, h, c.k_min);
          if (std::isfinite(w)) sum += c.area * du * dv / 16.0 / w;
        }
    }
  return sum;
}

}  // namespace isocam
