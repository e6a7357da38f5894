// The sampling lattice of a face's offset for plane tracing: lattice lines,
// crease strips and continuous evaluation (see plane_trace.h).
#include <algorithm>
#include <cmath>
#include <functional>
#include <gp.hxx>
#include <gp_Ax1.hxx>

#include "finishing/plane_trace.h"

namespace isocam {
namespace {

using Strip = OffsetLattice::Strip;

// Per span of the grid along u (along_u) or v, an upper estimate of the
// length of the iso-curves across it: the longest control polygon row of
// any of its patches.
std::vector<double> span_lengths(const PatchGrid& g, bool along_u) {
  const int pu = g.degree_u(), pv = g.degree_v();
  const int spans = along_u ? g.patches_u() : g.patches_v();
  const int others = along_u ? g.patches_v() : g.patches_u();
  auto at = [](const H4& h) { return gp_Pnt(h.x / h.w, h.y / h.w, h.z / h.w); };
  std::vector<double> len(static_cast<std::size_t>(spans), 0.0);
  for (int i = 0; i < spans; ++i) {
    for (int j = 0; j < others; ++j) {
      const H4* p = along_u ? g.patch(i, j) : g.patch(j, i);
      const int rows = along_u ? pv : pu, steps = along_u ? pu : pv;
      for (int row = 0; row <= rows; ++row) {
        double l = 0.0;
        for (int k = 0; k < steps; ++k) {
          const int i0 = along_u ? k + (pu + 1) * row : row + (pu + 1) * k;
          const int i1 = along_u ? k + 1 + (pu + 1) * row : row + (pu + 1) * (k + 1);
          l += at(p[i0]).Distance(at(p[i1]));
        }
        len[static_cast<std::size_t>(i)] = std::max(len[static_cast<std::size_t>(i)], l);
      }
    }
  }
  return len;
}

// The strips along one direction: each span cut into ceil(length / cell)
// parts (2 to 64, at most about 4096 in all), and a crease strip at every
// interior break k (between spans k-1 and k) for which `crease(k)` holds.
std::vector<Strip> strips(const std::vector<double>& breaks, const std::vector<double>& len,
                          double cell, const std::function<bool(int)>& crease) {
  std::vector<int> parts(len.size());
  long total = 0;
  for (std::size_t i = 0; i < len.size(); ++i) {
    parts[i] = static_cast<int>(std::clamp(std::ceil(len[i] / cell), 2.0, 64.0));
    total += parts[i];
  }
  const long cap = 4096;
  if (total > cap)
    for (int& p : parts) p = std::max(1, static_cast<int>(double(p) * cap / double(total)));
  std::vector<Strip> out;
  for (std::size_t i = 0; i < len.size(); ++i) {
    const int span = static_cast<int>(i);
    if (i > 0 && crease(span)) out.push_back({breaks[i], breaks[i], span - 1, span});
    for (int s = 0; s < parts[i]; ++s) {
      const double a = breaks[i] + (breaks[i + 1] - breaks[i]) * s / parts[i];
      const double b = s + 1 == parts[i]
                           ? breaks[i + 1]
                           : breaks[i] + (breaks[i + 1] - breaks[i]) * (s + 1) / parts[i];
      out.push_back({a, b, span, -1});
    }
  }
  return out;
}

// Strip and position in it of lattice coordinate x (clamped).
const Strip& locate(const std::vector<Strip>& s, double x, double* frac) {
  const double n = double(s.size());
  x = std::clamp(x, 0.0, n);
  const std::size_t k = std::min(static_cast<std::size_t>(x), s.size() - 1);
  *frac = x - double(k);
  return s[k];
}

// Turns a toward b by the fraction s of the angle between them.
gp_Vec turn(const gp_Vec& a, const gp_Vec& b, double s) {
  const gp_Vec axis = a.Crossed(b);
  if (axis.Magnitude() <= 1e-15) {
    const gp_Vec m = a * (1 - s) + b * s;
    return m.Magnitude() > 1e-15 ? m.Normalized() : a;
  }
  return a.Rotated(gp_Ax1(gp::Origin(), gp_Dir(axis)), a.Angle(b) * s);
}

// Normals across a break this far apart (rad) make it a crease. An exactly
// G1 joint of two polynomial spans agrees to about 1e-15.
constexpr double kCreaseAngle = 1e-8;

}  // namespace

gp_Vec OffsetLattice::normal_on(int iu, int jv, double u, double v, gp_Pnt* p) const {
  // v-span jv: a parameter on its boundary is moved inside by 1e-10 of the
  // span (moving the point by as little), so that the span's own polynomial
  // is evaluated (d1_on_span chooses the u-span exactly).
  const std::vector<double>& vb = grid_->vbreaks();
  const double v0 = vb[static_cast<std::size_t>(jv)], v1 = vb[static_cast<std::size_t>(jv) + 1];
  const double eps = 1e-10 * (v1 - v0);
  const double vv = std::clamp(v, v0 + eps, v1 - eps);
  const SurfaceDerivs d = grid_->d1_on_span(iu, u, vv);
  if (p) *p = d.p;
  return grid_->normal(u, vv, &d);
}

OffsetPoint OffsetLattice::at(double x, double y) const {
  double s, t;
  const Strip& su = locate(us_, x, &s);
  const Strip& sv = locate(vs_, y, &t);
  const double u = su.hi >= 0 ? su.p0 : su.p0 + (su.p1 - su.p0) * s;
  const double v = sv.hi >= 0 ? sv.p0 : sv.p0 + (sv.p1 - sv.p0) * t;
  gp_Pnt p;
  const gp_Vec n0 = normal_on(su.span, sv.span, u, v, &p);
  // On a crease strip the contact point stays on the crease (the surface is
  // continuous there) and the normal turns from one side's to the other's.
  auto n_at = [&](int jv, const gp_Vec* known) {
    const gp_Vec a = known ? *known : normal_on(su.span, jv, u, v, nullptr);
    return su.hi >= 0 ? turn(a, normal_on(su.hi, jv, u, v, nullptr), s) : a;
  };
  gp_Vec n = n_at(sv.span, &n0);
  if (sv.hi >= 0) n = turn(n, n_at(sv.hi, nullptr), t);
  return {{std::clamp(x, 0.0, double(cells_u())), std::clamp(y, 0.0, double(cells_v()))},
          {u, v},
          p.Translated(n * r_),
          n};
}

OffsetLattice::OffsetLattice(const PatchGrid& grid, const TrimDomain& trim, double r)
    : grid_(&grid), r_(r) {
  const std::vector<double>& ub = grid.ubreaks();
  const std::vector<double>& vb = grid.vbreaks();
  // A break is a crease where the normals of the two spans differ at any of
  // three points inside each span of the other direction.
  auto crease = [&](bool along_u, int k) {
    const std::vector<double>& other = along_u ? vb : ub;
    for (std::size_t j = 0; j + 1 < other.size(); ++j)
      for (double f : {0.25, 0.5, 0.75}) {
        const double w = other[j] + (other[j + 1] - other[j]) * f;
        const int jj = static_cast<int>(j);
        const gp_Vec a = along_u
                             ? normal_on(k - 1, jj, ub[static_cast<std::size_t>(k)], w, nullptr)
                             : normal_on(jj, k - 1, w, vb[static_cast<std::size_t>(k)], nullptr);
        const gp_Vec b = along_u ? normal_on(k, jj, ub[static_cast<std::size_t>(k)], w, nullptr)
                                 : normal_on(jj, k, w, vb[static_cast<std::size_t>(k)], nullptr);
        if (a.Angle(b) > kCreaseAngle) return true;
      }
    return false;
  };
  const double cell = 0.25 * r;
  us_ = strips(ub, span_lengths(grid, true), cell, [&](int k) { return crease(true, k); });
  vs_ = strips(vb, span_lengths(grid, false), cell, [&](int k) { return crease(false, k); });
  centres_.resize(static_cast<std::size_t>((cells_u() + 1) * (cells_v() + 1)));
  for (int b = 0; b <= cells_v(); ++b)
    for (int a = 0; a <= cells_u(); ++a) centres_[node(a, b)] = at(a, b).centre;
  used_.resize(static_cast<std::size_t>(cells_u() * cells_v()));
  for (int b = 0; b < cells_v(); ++b)
    for (int a = 0; a < cells_u(); ++a) {
      const Strip& su = us_[static_cast<std::size_t>(a)];
      const Strip& sv = vs_[static_cast<std::size_t>(b)];
      used_[static_cast<std::size_t>(a + cells_u() * b)] =
          trim.classify_rect(su.p0, su.p1, sv.p0, sv.p1) != TrimDomain::RectClass::Outside;
    }
}

bool OffsetLattice::range(int axis, double* lo, double* hi) const {
  *lo = 1e300;
  *hi = -1e300;
  for (int b = 0; b < cells_v(); ++b)
    for (int a = 0; a < cells_u(); ++a) {
      if (!used(a, b)) continue;
      for (int k = 0; k < 4; ++k) {
        const double x = axis_coord(centre(a + (k & 1), b + (k >> 1)), axis);
        *lo = std::min(*lo, x);
        *hi = std::max(*hi, x);
      }
    }
  return *lo <= *hi;
}

}  // namespace isocam
