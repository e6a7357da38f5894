#include "geometry/curvature.h"

#include <algorithm>
#include <cmath>

namespace isocam {

CurvatureSample curvature_at(const PatchGrid& g, int i, int j, double s, double t) {
  const auto& ub = g.ubreaks();
  const auto& vb = g.vbreaks();
  const double u0 = ub[static_cast<std::size_t>(i)], u1 = ub[static_cast<std::size_t>(i) + 1];
  const double v0 = vb[static_cast<std::size_t>(j)], v1 = vb[static_cast<std::size_t>(j) + 1];
  const double u = u0 + (u1 - u0) * s, v = v0 + (v1 - v0) * t;
  const double hu = 1e-4 * (u1 - u0), hv = 1e-4 * (v1 - v0);
  const SurfaceDerivs d = g.d1_on_span(i, u, v);
  const SurfaceDerivs dup = g.d1_on_span(i, u + hu, v), dum = g.d1_on_span(i, u - hu, v);
  const SurfaceDerivs dvp = g.d1_on_span(i, u, v + hv), dvm = g.d1_on_span(i, u, v - hv);
  const gp_Vec suu = (dup.su - dum.su) / (2 * hu);
  const gp_Vec svv = (dvp.sv - dvm.sv) / (2 * hv);
  // Su_v and Sv_u agree for a smooth surface; their mean halves the error.
  const gp_Vec suv = ((dvp.su - dvm.su) / (2 * hv) + (dup.sv - dum.sv) / (2 * hu)) * 0.5;
  CurvatureSample out;
  const gp_Vec cross = d.su.Crossed(d.sv);
  out.area = cross.Magnitude();
  const double E = d.su.Dot(d.su), F = d.su.Dot(d.sv), G = d.sv.Dot(d.sv);
  const double det = E * G - F * F;
  if (!(det > 1e-20 * std::max(E * G, 1e-300)) || out.area <= 0) return out;
  const gp_Vec n = g.normal(u, v, &d);
  // Second fundamental form with the sign that makes convex positive.
  const double L = -suu.Dot(n), M = -suv.Dot(n), N = -svv.Dot(n);
  // Normal curvature in the direction a Su + b Sv.
  auto kappa = [&](double a, double b) {
    return (L * a * a + 2 * M * a * b + N * b * b) / (E * a * a + 2 * F * a * b + G * b * b);
  };
  // N x Su is a Su + b Sv with (a, b) solving the first fundamental form.
  const gp_Vec across = n.Crossed(d.su);
  const double ru = across.Dot(d.su), rv = across.Dot(d.sv);
  const double a = (G * ru - F * rv) / det, b = (E * rv - F * ru) / det;
  out.k_cross = std::max(kappa(a, b), kappa(0.0, 1.0));
  // Principal curvatures: roots of det(II - k I) = 0.
  const double qa = det, qb = -(E * N + G * L - 2 * F * M), qc = L * N - M * M;
  const double mid = -qb / (2 * qa);
  const double disc = std::sqrt(std::max(0.0, mid * mid - qc / qa));
  out.k_min = mid - disc;
  out.k_max = mid + disc;
  out.ok = true;
  return out;
}

}  // namespace isocam
