// The tilted flat end and bull nose (see five_axis_tool.h and isocam/five_axis.h).
#include "finishing/five_axis_tool.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isocam {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

gp_Vec unit_or(const gp_Vec& v, const gp_Vec& fallback) {
  const double m = v.Magnitude();
  return m > 1e-300 ? v / m : fallback;
}

// The ground's height below the tangent line at the offset x (curvature
// kappa, convex > 0): -kappa x^2 / (1 + sqrt(1 - kappa^2 x^2)); beyond a
// convex circle's reach -inf, beyond a concave one's +inf (a wall).
double ground(double kappa, double x) {
  const double q = 1.0 - kappa * kappa * x * x;
  if (q <= 0) return kappa > 0 ? -kInf : kInf;
  return -kappa * x * x / (1.0 + std::sqrt(q));
}

}  // namespace

ToolPose pose_at(const ContactFrame& c, const Cutter& tool, double lead, double tilt) {
  ToolPose out;
  out.axis = unit_or(c.n * (std::cos(lead) * std::cos(tilt)) + c.f * std::sin(lead) +
                         c.a * (std::cos(lead) * std::sin(tilt)),
                     c.n);
  const gp_Vec up = unit_or(c.n - out.axis * c.n.Dot(out.axis), -c.f);
  out.tip = c.p.Translated(c.n * tool.corner + up * tool.core() - out.axis * tool.corner);
  return out;
}

// The core disc's rim relative to P: rc N + R' ((1 + cos th) u + sin th
// e2), R' = R - rc, u the unit vector from its lowest rim point to its
// centre, e2 = axis x u; across the feed x(th) = x0 + m cos(th - phi), along
// N z(th) = z0 + s cos th + t sin th (z0 = rc + s).
EdgeProfile::EdgeProfile(const ContactFrame& c, const Cutter& tool, double lead, double tilt,
                         double kappa_a)
    : kappa_(kappa_a), rc_(tool.corner) {
  const ToolPose pose = pose_at(c, tool, lead, tilt);
  const gp_Vec u = unit_or(c.n - pose.axis * c.n.Dot(pose.axis), -c.f);
  const gp_Vec e2 = pose.axis.Crossed(u);
  const double r = tool.core();
  const double p = r * u.Dot(c.a), q = r * e2.Dot(c.a);
  x0_ = p;
  m_ = std::hypot(p, q);
  phi_ = std::atan2(q, p);
  s_ = r * u.Dot(c.n);
  z0_ = rc_ + s_;
  t_ = r * e2.Dot(c.n);
  ux_ = p;
  vx_ = q;
}

// The flat end (rc = 0): the lower arc of the ellipse in closed form. The
// bull nose: the ellipse's outer parallel curve at rc, its point of outward
// normal n = (sin psi, -cos psi) being the ellipse's support point for n
// plus rc n; its x grows strictly with psi over [-pi/2, pi/2] (left end to
// right end of the lower arc), so psi is found by Newton's method inside a
// bracket.
double EdgeProfile::edge(double x, double* psi) const {
  if (rc_ == 0.0) {
    if (!(m_ > 0)) return kInf;
    const double w = std::acos(std::clamp((x - x0_) / m_, -1.0, 1.0));
    double z = kInf;
    for (double th : {phi_ + w, phi_ - w})
      z = std::min(z, z0_ + s_ * std::cos(th) + t_ * std::sin(th));
    return z;
  }
  // The ellipse c0 + U cos th + V sin th, U = (ux, s), V = (vx, t): x(psi) -
  // x, its derivative in *dx and the point's z in *z.
  auto at = [this, x](double p, double* dx, double* z) {
    const double nx = std::sin(p), nz = -std::cos(p);
    const double a = ux_ * nx + s_ * nz, b = vx_ * nx + t_ * nz, l = std::sqrt(a * a + b * b);
    if (!(l > 0)) {
      *dx = -rc_ * nz;
      *z = z0_ + rc_ * nz;
      return x0_ + rc_ * nx - x;
    }
    const double da = -ux_ * nz + s_ * nx, db = -vx_ * nz + t_ * nx;  // d/dpsi of a, b
    const double dl = (a * da + b * db) / l;
    *z = z0_ + (s_ * a + t_ * b) / l + rc_ * nz;
    *dx = (ux_ * da + vx_ * db) / l - (ux_ * a + vx_ * b) * dl / (l * l) - rc_ * nz;
    return x0_ + (ux_ * a + vx_ * b) / l + rc_ * nx - x;
  };
  // Newton's method from *psi kept inside a bracket (bisection where it
  // would leave it), to 1e-12 mm in x.
  double lo = -0.5 * M_PI, hi = 0.5 * M_PI, p = std::clamp(*psi, lo, hi), dx = 0.0, z = 0.0;
  for (int it = 0; it < 100; ++it) {
    const double f = at(p, &dx, &z);
    if (std::abs(f) <= 1e-12 || hi - lo < 1e-15) break;
    (f < 0 ? lo : hi) = p;
    const double next = dx > 0 ? p - f / dx : lo - 1.0;
    p = next > lo && next < hi ? next : 0.5 * (lo + hi);
  }
  *psi = p;
  return z;
}

double EdgeProfile::height(double x) const {
  double psi = 0.0;
  return height(x, &psi);
}

double EdgeProfile::height(double x, double* psi) const {
  if (x < x_min() || x > x_max()) return kInf;
  return edge(x, psi) - ground(kappa_, x);
}

// The scan and bisection start each solve of the edge's normal angle from
// the previous one (a near x).
double EdgeProfile::side_width(double h, double sign) const {
  const double reach = sign > 0 ? x_max() : -x_min();
  if (!(reach > 0)) return 0.0;
  const int n = 96;
  double lo = 0.0, psi = 0.0;
  for (int k = 1; k <= n; ++k) {
    const double x = reach * k / n;
    if (height(sign * x, &psi) >= h) {
      double hi = x;
      for (int it = 0; it < 50; ++it) {
        const double mid = 0.5 * (lo + hi);
        (height(sign * mid, &psi) >= h ? hi : lo) = mid;
      }
      return lo;
    }
    lo = x;
  }
  return reach;
}

double EdgeProfile::half_width(double h) const {
  return std::min(side_width(h, 1), side_width(h, -1));
}

double EdgeProfile::cusp(double spacing) const {
  const double x = 0.5 * spacing;
  return std::max(height(x), height(-x));
}

double EdgeProfile::lowest() const {
  double low = kInf, psi = -0.5 * M_PI;
  for (int k = 0; k <= 200; ++k)
    low = std::min(low, height(x_min() + (x_max() - x_min()) * k / 200.0, &psi));
  return low;
}

double lead_for(double base, double max_lead, const Cutter& tool, double kappa_f, double kappa_a) {
  // The concave part of kappa with the margin, on the ground offset by rc;
  // -1 where the corner does not fit (no lead keeps it off).
  auto offset = [&tool](double kappa) {
    const double k = 1.25 * std::min(0.0, kappa), d = 1.0 + tool.corner * k;
    return d > 0 ? -k / d * tool.core() : -1.0;
  };
  const double ka = offset(kappa_a), kf = offset(kappa_f);
  if (ka < 0 || kf < 0) return max_lead;
  auto ok = [&](double l) {
    const double c = std::cos(l);
    return std::sin(l) >= ka && std::sin(l) >= kf * c * c;
  };
  if (ok(base) || !ok(max_lead)) return ok(base) ? base : max_lead;
  double lo = base, hi = max_lead;
  for (int it = 0; it < 40; ++it) {
    const double mid = 0.5 * (lo + hi);
    (ok(mid) ? hi : lo) = mid;
  }
  return hi;
}

bool contact_frame(const PatchGrid& g, const ParamPt& uv, const gp_Vec& dir, ContactFrame* out) {
  const SurfaceDerivs d = g.d1(uv.u, uv.v);
  out->p = d.p;
  out->n = g.normal(uv.u, uv.v, &d);
  gp_Vec f = dir - out->n * dir.Dot(out->n);
  const double m = f.Magnitude();
  if (!(m > 1e-12) || !(out->n.Magnitude() > 0.5)) return false;
  out->f = f / m;
  out->a = out->n.Crossed(out->f);
  return true;
}

namespace {
// The parameter step (du, dv) whose image under the tangent map is the
// tangential part of v (least squares); false where the map is singular.
bool tangent_step(const SurfaceDerivs& d, const gp_Vec& v, double* du, double* dv) {
  const double E = d.su.Dot(d.su), F = d.su.Dot(d.sv), G = d.sv.Dot(d.sv);
  const double det = E * G - F * F;
  if (!(det > 1e-300)) return false;
  const double bu = v.Dot(d.su), bv = v.Dot(d.sv);
  *du = (G * bu - F * bv) / det;
  *dv = (E * bv - F * bu) / det;
  return true;
}

// Newton's step is taken where the Hessian of the squared distance is at
// least kMinCurve times the metric (E, F, G) in every direction; else a
// multiple of the metric is added to make it so (near a focal point, or
// beyond one on the concave side), and a step is then at most 1 /
// kMinCurve times Gauss-Newton's.
constexpr double kMinCurve = 0.1;

// Newton's step (du, dv) towards the nearest point to x from d (Hessian
// shifted as kMinCurve says); false where the metric is singular. The
// Hessian of |S - x|^2 / 2 is the metric less the second derivatives
// dotted with r = x - S.
bool newton_step(const SurfaceDerivs2& d, const gp_Vec& r, double* du, double* dv) {
  const double E = d.su.Dot(d.su), F = d.su.Dot(d.sv), G = d.sv.Dot(d.sv);
  const double m = E * G - F * F;
  if (!(m > 1e-300)) return false;
  double a = E - d.suu.Dot(r), b = F - d.suv.Dot(r), c = G - d.svv.Dot(r);
  // The smallest lambda with det(H - lambda M) = 0 (M the metric).
  const double p = a * G + c * E - 2 * b * F, q = a * c - b * b;
  const double lambda = (p - std::sqrt(std::max(0.0, p * p - 4 * m * q))) / (2 * m);
  if (lambda < kMinCurve) {
    const double shift = kMinCurve - lambda;
    a += shift * E;
    b += shift * F;
    c += shift * G;
  }
  const double det = a * c - b * b;
  if (!(det > 1e-300)) return false;
  const double gu = r.Dot(d.su), gv = r.Dot(d.sv);
  *du = (c * gu - b * gv) / det;
  *dv = (a * gv - b * gu) / det;
  return true;
}

// The same along one parameter alone (su, suu: its derivatives), the other
// held on a side of the rectangle.
double newton_step_1d(const gp_Vec& su, const gp_Vec& suu, const gp_Vec& r) {
  const double E = su.Dot(su);
  if (!(E > 1e-300)) return 0.0;
  return r.Dot(su) / std::max(E - suu.Dot(r), kMinCurve * E);
}
}  // namespace

bool nearest_on(const PatchGrid& g, const gp_Pnt& x, ParamPt uv, ParamPt* foot, SurfaceDerivs* at) {
  bool clamped = false;
  SurfaceDerivs2 d;
  ParamPt d_at{};  // where d was evaluated
  // The last point that lowered the distance, and its squared distance.
  ParamPt best = uv;
  double best_f = std::numeric_limits<double>::infinity();
  const double range = g.umax() - g.umin() + g.vmax() - g.vmin();
  for (int it = 0; it < 12; ++it) {
    d = g.d2(uv.u, uv.v);
    d_at = uv;
    const gp_Vec r(d.p, x);
    const double f = r.SquareMagnitude();
    if (f > best_f + 1e-12 * (1.0 + std::sqrt(best_f))) {
      // The step overshot (the surface curves away within it): halved.
      uv = {0.5 * (best.u + uv.u), 0.5 * (best.v + uv.v)};
      continue;
    }
    best = uv;
    best_f = f;
    double du, dv;
    if (!tangent_step(d, r, &du, &dv)) break;
    // Converged where Gauss-Newton's step would move the point by under
    // 1e-9 mm (the tangential part of x - S: the height at the foot is
    // stationary, so its error is far smaller).
    if ((d.su * du + d.sv * dv).SquareMagnitude() < 1e-18) {
      clamped = false;
      break;
    }
    newton_step(d, r, &du, &dv);
    // A parameter on a side of the rectangle with the step outwards stays
    // there, and the other is solved alone.
    const bool hold_u = (uv.u <= g.umin() && du < 0) || (uv.u >= g.umax() && du > 0);
    const bool hold_v = (uv.v <= g.vmin() && dv < 0) || (uv.v >= g.vmax() && dv > 0);
    if (hold_u) {
      du = 0.0;
      dv = hold_v ? 0.0 : newton_step_1d(d.sv, d.svv, r);
    } else if (hold_v) {
      dv = 0.0;
      du = newton_step_1d(d.su, d.suu, r);
    }
    // A step that would leave the rectangle is shortened to end on its side
    // (its direction kept: clipping one parameter could turn it uphill).
    double scale = 1.0;
    auto fit = [&scale](double from, double step, double lo, double hi) {
      if (from + scale * step > hi) scale = std::max(0.0, (hi - from) / step);
      if (from + scale * step < lo) scale = std::max(0.0, (lo - from) / step);
    };
    fit(uv.u, du, g.umin(), g.umax());
    fit(uv.v, dv, g.vmin(), g.vmax());
    const ParamPt nx{std::clamp(uv.u + scale * du, g.umin(), g.umax()),
                     std::clamp(uv.v + scale * dv, g.vmin(), g.vmax())};
    clamped = hold_u || hold_v || scale < 1.0;
    const bool done = std::abs(nx.u - uv.u) + std::abs(nx.v - uv.v) < 1e-13 * range;
    uv = nx;
    if (done) break;
  }
  // A last step not evaluated (or one that overshot) is not taken.
  if (d_at.u != uv.u || d_at.v != uv.v) uv = best;
  *foot = uv;
  if (at) *at = d_at.u == uv.u && d_at.v == uv.v ? static_cast<SurfaceDerivs>(d) : g.d1(uv.u, uv.v);
  return !clamped;
}

namespace {
// The interval of t where S + t N is in the cylinder of radius r about the
// axis from base, at heights >= h0 along it (unbounded above); false where
// the line misses it.
bool line_in_cylinder(const gp_Pnt& s, const gp_Vec& n, const gp_Pnt& base, const gp_Vec& axis,
                      double r, double h0, double* lo, double* hi) {
  const gp_Vec w(base, s);
  const double wa = w.Dot(axis), na = n.Dot(axis);
  *lo = -kInf;
  *hi = kInf;
  if (std::abs(na) > 1e-12) {
    (na > 0 ? *lo : *hi) = (h0 - wa) / na;
  } else if (wa < h0) {
    return false;
  }
  const gp_Vec wp = w - axis * wa, np = n - axis * na;
  const double qa = np.Dot(np), qb = 2 * wp.Dot(np), qc = wp.Dot(wp) - r * r;
  if (qa > 1e-15) {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) return false;
    const double sq = std::sqrt(disc);
    *lo = std::max(*lo, (-qb - sq) / (2 * qa));
    *hi = std::min(*hi, (-qb + sq) / (2 * qa));
  } else if (qc > 0) {
    return false;
  }
  return *lo <= *hi;
}
}  // namespace

double depth_below(const PatchGrid& g, const ParamPt& e, const ToolPose& pose, const Cutter& tool) {
  SurfaceDerivs d = g.d1(e.u, e.v);
  const gp_Pnt s = d.p;
  const gp_Vec n = g.normal(e.u, e.v, &d);
  double entry = kInf, lo, hi;
  if (line_in_cylinder(s, n, pose.tip, pose.axis, tool.radius, tool.corner, &lo, &hi)) entry = lo;
  if (tool.corner > 0) {
    // The distance from S + t N to the core disc, convex in t; the line
    // meets the corner within R of the disc's centre c: |t - tc| <= R.
    const gp_Pnt c = pose.tip.Translated(pose.axis * tool.corner);
    auto dist = [&](double t) {
      const gp_Vec y(c, s.Translated(n * t));
      const double h = y.Dot(pose.axis);
      const double out = std::max(0.0, (y - pose.axis * h).Magnitude() - tool.core());
      return std::hypot(h, out);
    };
    const double tc = gp_Vec(s, c).Dot(n);
    double in = 0.0;
    const double closest = -golden_max([&](double t) { return -dist(t); }, tc - tool.radius,
                                       tc + tool.radius, 80, &in);
    if (closest <= tool.corner) {
      double out = tc - tool.radius;  // dist there >= rc
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (out + in);
        (dist(mid) <= tool.corner ? in : out) = mid;
      }
      entry = std::min(entry, in);
    }
  }
  return -entry;
}

double depth_inside(const gp_Pnt& e, const ToolPose& pose, const Cutter& tool) {
  const gp_Vec d(pose.tip, e);
  const double z = d.Dot(pose.axis);
  const double r = (d - pose.axis * z).Magnitude();
  if (tool.corner > 0 && z < tool.corner && r > tool.core())
    return tool.corner - std::hypot(r - tool.core(), z - tool.corner);
  return std::min(z, tool.radius - r);
}

ParamPt predicted_foot(const PatchGrid& g, const ParamPt& foot, const SurfaceDerivs& d,
                       const gp_Vec& step) {
  double du, dv;
  if (!tangent_step(d, step, &du, &dv)) return foot;
  return {std::clamp(foot.u + du, g.umin(), g.umax()), std::clamp(foot.v + dv, g.vmin(), g.vmax())};
}

}  // namespace isocam
