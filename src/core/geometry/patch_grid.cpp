#include "geometry/patch_grid.h"

#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <GeomConvert_ApproxSurface.hxx>
#include <GeomConvert_BSplineSurfaceToBezierSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Precision.hxx>
#include <Standard_Failure.hxx>
#include <TColGeom_Array2OfBezierSurface.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColStd_Array2OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <algorithm>
#include <cmath>
#include <string>

#include "isocam/errors.h"

namespace isocam {
namespace {

std::string label(int face) {
  return "face " + std::to_string(face) + " (Face" + std::to_string(face + 1) + ")";
}

// The face's surface as a non-periodic B-spline covering [u1,u2]x[v1,v2].
// `same_params` tells whether the result keeps the face's parameters (B-spline
// and Bezier surfaces) or reparametrises them (the NURBS form of an analytic
// surface: a monotone map per direction).
Handle(Geom_BSplineSurface) to_bspline(Handle(Geom_Surface) surf, double u1, double u2, double v1,
                                       double v2, bool* same_params) {
  *same_params = true;
  while (auto trimmed = Handle(Geom_RectangularTrimmedSurface)::DownCast(surf)) {
    surf = trimmed->BasisSurface();
  }
  if (auto bs = Handle(Geom_BSplineSurface)::DownCast(surf)) {
    auto copy = Handle(Geom_BSplineSurface)::DownCast(bs->Copy());
    if (copy->IsUPeriodic()) copy->SetUNotPeriodic();
    if (copy->IsVPeriodic()) copy->SetVNotPeriodic();
    return copy;
  }
  if (auto bz = Handle(Geom_BezierSurface)::DownCast(surf)) {
    return GeomConvert::SurfaceToBSplineSurface(bz);
  }
  // Analytic surfaces: exact rational conversion of the bounded piece.
  *same_params = false;
  Handle(Geom_RectangularTrimmedSurface) piece =
      new Geom_RectangularTrimmedSurface(surf, u1, u2, v1, v2);
  try {
    return GeomConvert::SurfaceToBSplineSurface(piece);
  } catch (const Standard_Failure&) {
    // Not convertible exactly (offset surface, ...): approximate closely.
    GeomConvert_ApproxSurface approx(piece, 1e-6, GeomAbs_C2, GeomAbs_C2, 9, 9, 200, 1);
    if (!approx.HasResult()) throw;
    return approx.Surface();
  }
}

}  // namespace

namespace {
// de Casteljau in a buffer of N points (H4 is initialised on construction,
// so a buffer no larger than needed keeps this cheap).
template <std::size_t N>
H4 casteljau_in(const H4* cps, int n, double t) {
  std::array<H4, N> b;
  std::copy(cps, cps + n, b.begin());
  for (int k = 1; k < n; ++k)
    for (int i = 0; i + k < n; ++i)
      b[static_cast<std::size_t>(i)] =
          b[static_cast<std::size_t>(i)] * (1 - t) + b[static_cast<std::size_t>(i) + 1] * t;
  return b[0];
}
}  // namespace

H4 casteljau(const H4* cps, int degree, double t) {
  const int n = degree + 1;
  if (n <= 4) return casteljau_in<4>(cps, n, t);
  if (n <= 10) return casteljau_in<10>(cps, n, t);
  if (n > 32) {
    std::vector<H4> v(cps, cps + n);
    for (int k = 1; k < n; ++k)
      for (int i = 0; i + k < n; ++i) v[i] = v[i] * (1 - t) + v[i + 1] * t;
    return v[0];
  }
  return casteljau_in<32>(cps, n, t);
}

void restrict_h4(const H4* cps, int degree, double a, double b, H4* out) {
  // de Casteljau twice: keep the right part at a, then the left part of that.
  const int n = degree + 1;
  // Right part at a: r_i = the i-th from the right of the triangle.
  std::vector<H4> tri(cps, cps + n), right(static_cast<std::size_t>(n));
  right[static_cast<std::size_t>(n - 1)] = tri[static_cast<std::size_t>(n - 1)];
  for (int k = 1; k < n; ++k) {
    for (int i = 0; i + k < n; ++i)
      tri[static_cast<std::size_t>(i)] =
          tri[static_cast<std::size_t>(i)] * (1 - a) + tri[static_cast<std::size_t>(i) + 1] * a;
    right[static_cast<std::size_t>(n - 1 - k)] = tri[static_cast<std::size_t>(n - 1 - k)];
  }
  // right[] now are the control points of [a, 1]; take its left part at t.
  const double t = a < 1.0 ? (b - a) / (1.0 - a) : 1.0;
  std::vector<H4> left(static_cast<std::size_t>(n));
  left[0] = right[0];
  for (int k = 1; k < n; ++k) {
    for (int i = 0; i + k < n; ++i)
      right[static_cast<std::size_t>(i)] =
          right[static_cast<std::size_t>(i)] * (1 - t) + right[static_cast<std::size_t>(i) + 1] * t;
    left[static_cast<std::size_t>(k)] = right[0];
  }
  std::copy(left.begin(), left.end(), out);
}

namespace {
int find_span(const std::vector<double>& br, double t) {
  const int n = static_cast<int>(br.size()) - 1;
  auto it = std::upper_bound(br.begin(), br.end(), t);
  int i = static_cast<int>(it - br.begin()) - 1;
  return std::clamp(i, 0, n - 1);
}
gp_Pnt project(const H4& h) { return gp_Pnt(h.x / h.w, h.y / h.w, h.z / h.w); }
}  // namespace

int PiecewiseBezier::span_of(double t) const { return find_span(breaks, t); }
int PatchGrid::span_of_u(double u) const { return find_span(ub_, u); }

gp_Pnt PiecewiseBezier::eval(double t) const {
  const int i = span_of(t);
  const double a = breaks[static_cast<std::size_t>(i)], b = breaks[static_cast<std::size_t>(i) + 1];
  return project(casteljau(span(i), degree, (t - a) / (b - a)));
}

PatchGrid PatchGrid::from_face(const TopoDS_Face& face, int face_label) {
  Handle(Geom_Surface) surf = BRep_Tool::Surface(face);
  if (surf.IsNull()) throw GeometryError(label(face_label) + " has no surface");
  double u1, u2, v1, v2;
  BRepTools::UVBounds(face, u1, u2, v1, v2);
  if (!(u2 - u1 > Precision::PConfusion()) || !(v2 - v1 > Precision::PConfusion())) {
    throw GeometryError(label(face_label) + " is degenerate: empty parameter range");
  }
  PatchGrid g;
  try {
    Handle(Geom_BSplineSurface) bs = to_bspline(surf, u1, u2, v1, v2, &g.same_params_);
    double bu1, bu2, bv1, bv2;
    bs->Bounds(bu1, bu2, bv1, bv2);
    u1 = std::max(u1, bu1);
    u2 = std::min(u2, bu2);
    v1 = std::max(v1, bv1);
    v2 = std::min(v2, bv2);
    GeomConvert_BSplineSurfaceToBezierSurface conv(bs, u1, u2, v1, v2, Precision::PConfusion());
    const int nu = conv.NbUPatches(), nv = conv.NbVPatches();
    TColGeom_Array2OfBezierSurface patches(1, nu, 1, nv);
    conv.Patches(patches);
    TColStd_Array1OfReal uk(1, nu + 1), vk(1, nv + 1);
    conv.UKnots(uk);
    conv.VKnots(vk);
    g.pu_ = bs->UDegree();
    g.pv_ = bs->VDegree();
    g.rational_ = bs->IsURational() || bs->IsVRational();
    for (int i = 1; i <= nu + 1; ++i) g.ub_.push_back(uk(i));
    for (int j = 1; j <= nv + 1; ++j) g.vb_.push_back(vk(j));
    g.cps_.reserve(static_cast<std::size_t>(nu * nv * (g.pu_ + 1) * (g.pv_ + 1)));
    for (int j = 1; j <= nv; ++j) {
      for (int i = 1; i <= nu; ++i) {
        const Handle(Geom_BezierSurface)& p = patches(i, j);
        if (p->UDegree() != g.pu_ || p->VDegree() != g.pv_) {
          throw GeometryError(label(face_label) + ": inconsistent patch degrees");
        }
        for (int b = 1; b <= g.pv_ + 1; ++b) {
          for (int a = 1; a <= g.pu_ + 1; ++a) {
            const gp_Pnt& q = p->Pole(a, b);
            const double w = g.rational_ ? p->Weight(a, b) : 1.0;
            g.cps_.push_back({q.X() * w, q.Y() * w, q.Z() * w, w});
          }
        }
      }
    }
  } catch (const Standard_Failure& e) {
    throw GeometryError(label(face_label) + ": OpenCASCADE could not convert its surface (" +
                        e.GetMessageString() + ")");
  }
  g.flip_normal_ = face.Orientation() == TopAbs_REVERSED;
  g.finish();
  if (!(g.size_ > 1e-9)) throw GeometryError(label(face_label) + " is degenerate: zero size");
  // A face whose surface collapses to a curve has no normal anywhere.
  int regular = 0;
  for (int a = 0; a <= 4; ++a) {
    for (int b = 0; b <= 4; ++b) {
      const double u = g.umin() + (g.umax() - g.umin()) * (0.1 + 0.2 * a);
      const double v = g.vmin() + (g.vmax() - g.vmin()) * (0.1 + 0.2 * b);
      const SurfaceDerivs d = g.d1(u, v);
      // Relative to the derivatives themselves, so that the test does not
      // depend on the face's size or its parametrisation.
      const double m = d.su.Magnitude() * d.sv.Magnitude();
      if (m > 0 && d.su.Crossed(d.sv).Magnitude() > 1e-10 * m) ++regular;
    }
  }
  if (regular == 0) throw GeometryError(label(face_label) + " is degenerate: it has no area");
  return g;
}

void PatchGrid::finish() {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const H4& h : cps_) {
    const double p[3] = {h.x / h.w, h.y / h.w, h.z / h.w};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  }
  size_ = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                    (hi[2] - lo[2]) * (hi[2] - lo[2]));
  sv_bound_.assign(static_cast<std::size_t>(patches_u() * patches_v() * kStripParts), 0.0);
  std::vector<H4> row(static_cast<std::size_t>(pu_ + 1)),
      part(static_cast<std::size_t>((pu_ + 1) * (pv_ + 1)));
  for (int j = 0; j < patches_v(); ++j) {
    const double dv = vb_[static_cast<std::size_t>(j) + 1] - vb_[static_cast<std::size_t>(j)];
    for (int i = 0; i < patches_u(); ++i) {
      const H4* p = patch(i, j);
      const double u0 = ub_[static_cast<std::size_t>(i)], u1 = ub_[static_cast<std::size_t>(i) + 1];
      for (int s = 0; s < kStripParts; ++s) {
        const double a0 = double(s) / kStripParts, a1 = double(s + 1) / kStripParts;
        double m = 0.0;
        if (!rational_) {
          // The part's control net: each v-row restricted to [a0, a1] in u.
          for (int b = 0; b <= pv_; ++b) {
            for (int a = 0; a <= pu_; ++a) row[static_cast<std::size_t>(a)] = p[a + (pu_ + 1) * b];
            restrict_h4(row.data(), pu_, a0, a1, &part[static_cast<std::size_t>((pu_ + 1) * b)]);
          }
          for (int b = 0; b < pv_; ++b)
            for (int a = 0; a <= pu_; ++a) {
              const H4 d = part[static_cast<std::size_t>(a + (pu_ + 1) * (b + 1))] -
                           part[static_cast<std::size_t>(a + (pu_ + 1) * b)];
              m = std::max(m, std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z) * pv_ / dv);
            }
        } else {
          const double v0 = vb_[static_cast<std::size_t>(j)];
          for (int a = 0; a <= 3; ++a)
            for (int b = 0; b <= 6; ++b)
              m = std::max(m, d1(u0 + (u1 - u0) * (a0 + (a1 - a0) * a / 3.0), v0 + dv * b / 6.0)
                                  .sv.Magnitude());
          m *= 1.25;
        }
        sv_bound_[static_cast<std::size_t>((j * patches_u() + i) * kStripParts + s)] = m;
      }
    }
  }
}

double PatchGrid::strip_width_bound(int i, int s, double v1, double v2) const {
  // L(u) = integral of |dS/dv| over [v1, v2] <= sum over the patch rows of
  // the row's bound times the part of [v1, v2] inside the row.
  double length = 0.0;
  for (int j = find_span(vb_, v1); j < patches_v(); ++j) {
    const double lo = std::max(v1, vb_[static_cast<std::size_t>(j)]);
    const double hi = std::min(v2, vb_[static_cast<std::size_t>(j) + 1]);
    if (lo >= v2) break;
    if (hi > lo) length += sv_bound(i, s, j) * (hi - lo);
  }
  return length;
}

PatchGrid PatchGrid::transposed() const {
  PatchGrid t;
  t.pu_ = pv_;
  t.pv_ = pu_;
  t.rational_ = rational_;
  t.same_params_ = same_params_;
  t.flip_normal_ = !flip_normal_;  // Sv x Su = -(Su x Sv)
  t.ub_ = vb_;
  t.vb_ = ub_;
  t.cps_.resize(cps_.size());
  const int nu = patches_u(), nv = patches_v();
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const H4* src = patch(i, j);
      H4* dst = &t.cps_[static_cast<std::size_t>((i * nv + j) * (pu_ + 1) * (pv_ + 1))];
      for (int b = 0; b <= pv_; ++b)
        for (int a = 0; a <= pu_; ++a) dst[b + (pv_ + 1) * a] = src[a + (pu_ + 1) * b];
    }
  }
  t.finish();
  return t;
}

PiecewiseBezier PatchGrid::iso_v(double v) const {
  PiecewiseBezier c;
  c.degree = pu_;
  c.breaks = ub_;
  const int j = find_span(vb_, v);
  const double t = (v - vb_[static_cast<std::size_t>(j)]) /
                   (vb_[static_cast<std::size_t>(j) + 1] - vb_[static_cast<std::size_t>(j)]);
  c.cps.resize(static_cast<std::size_t>(patches_u() * (pu_ + 1)));
  std::array<H4, 32> column;
  for (int i = 0; i < patches_u(); ++i) {
    const H4* p = patch(i, j);
    for (int a = 0; a <= pu_; ++a) {
      for (int b = 0; b <= pv_; ++b) column[static_cast<std::size_t>(b)] = p[a + (pu_ + 1) * b];
      c.cps[static_cast<std::size_t>(i * (pu_ + 1) + a)] = casteljau(column.data(), pv_, t);
    }
  }
  return c;
}

namespace {
// The Bernstein basis of degree n at t into b[0..n], its derivative's
// weights into db[0..n] and its second derivative's into d2b[0..n] (each
// optional): sum_k b[k] P_k is the Bezier curve of P_0..P_n at t, sum_k
// db[k] P_k its derivative in t (n (P_{k+1} - P_k) weighted by the basis of
// degree n - 1), sum_k d2b[k] P_k its second (n (n - 1) (P_{k+2} - 2 P_{k+1}
// + P_k) weighted by the basis of degree n - 2). The basis is built up by
// the recurrence B_k^j = (1 - t) B_k^{j-1} + t B_{k-1}^{j-1}: convex
// combinations, as stable as de Casteljau's, without its triangle of
// points; the derivatives' weights are taken on the way up.
template <std::size_t N>
void bernstein(int n, double t, std::array<double, N>* b, std::array<double, N>* db,
               std::array<double, N>* d2b = nullptr) {
  auto& B = *b;
  // B of degree j - 1 raised to degree j.
  auto raise = [&B, t](int j) {
    double carry = 0.0;
    for (int k = 0; k < j; ++k) {
      const double x = B[static_cast<std::size_t>(k)];
      B[static_cast<std::size_t>(k)] = carry + (1 - t) * x;
      carry = t * x;
    }
    B[static_cast<std::size_t>(j)] = carry;
  };
  // B[k] of the degree it holds, 0 outside 0..j.
  auto at = [&B](int k, int j) { return k >= 0 && k <= j ? B[static_cast<std::size_t>(k)] : 0.0; };
  B[0] = 1.0;
  for (int j = 1; j < n - 1; ++j) raise(j);
  if (d2b) {
    auto& D = *d2b;
    for (int k = 0; k <= n; ++k)
      D[static_cast<std::size_t>(k)] =
          n < 2 ? 0.0 : n * (n - 1) * (at(k - 2, n - 2) - 2 * at(k - 1, n - 2) + at(k, n - 2));
  }
  if (n >= 2) raise(n - 1);
  // B holds degree n - 1 (or 0 when n = 0): the derivative's weights, then
  // one step more.
  if (db) {
    auto& D = *db;
    for (int k = 0; k <= n; ++k)
      D[static_cast<std::size_t>(k)] = n * ((k > 0 ? B[static_cast<std::size_t>(k) - 1] : 0.0) -
                                            (k < n ? B[static_cast<std::size_t>(k)] : 0.0));
  }
  if (n > 0) raise(n);
}

H4 axpy(const H4& acc, double s, const H4& p) {
  return {acc.x + s * p.x, acc.y + s * p.y, acc.z + s * p.z, acc.w + s * p.w};
}
}  // namespace

gp_Pnt PatchGrid::eval(double u, double v) const {
  const int i = find_span(ub_, u);
  if (pu_ <= 3 && pv_ <= 3) return derivs_in<4, 0>(i, u, v).p;
  if (pu_ <= 9 && pv_ <= 9) return derivs_in<10, 0>(i, u, v).p;
  return derivs_in<32, 0>(i, u, v).p;
}

SurfaceDerivs PatchGrid::d1(double u, double v) const {
  return d1_on_span(find_span(ub_, u), u, v);
}

SurfaceDerivs2 PatchGrid::d2(double u, double v) const {
  const int i = find_span(ub_, u);
  if (pu_ <= 3 && pv_ <= 3) return derivs_in<4, 2>(i, u, v);
  if (pu_ <= 9 && pv_ <= 9) return derivs_in<10, 2>(i, u, v);
  return derivs_in<32, 2>(i, u, v);
}

template <std::size_t N, int kOrder>
SurfaceDerivs2 PatchGrid::derivs_in(int i, double u, double v) const {
  const int j = find_span(vb_, v);
  const double du = ub_[static_cast<std::size_t>(i) + 1] - ub_[static_cast<std::size_t>(i)];
  const double dv = vb_[static_cast<std::size_t>(j) + 1] - vb_[static_cast<std::size_t>(j)];
  const double s = (u - ub_[static_cast<std::size_t>(i)]) / du;
  const double t = (v - vb_[static_cast<std::size_t>(j)]) / dv;
  std::array<double, N> bu, dbu, d2bu, bv, dbv, d2bv;
  bernstein<N>(pu_, s, &bu, kOrder >= 1 ? &dbu : nullptr, kOrder >= 2 ? &d2bu : nullptr);
  bernstein<N>(pv_, t, &bv, kOrder >= 1 ? &dbv : nullptr, kOrder >= 2 ? &d2bv : nullptr);
  const H4* p = patch(i, j);
  // Rows in u first (value and u-derivatives), then combined in v.
  H4 A{0, 0, 0, 0}, Au{0, 0, 0, 0}, Av{0, 0, 0, 0};
  H4 Auu{0, 0, 0, 0}, Auv{0, 0, 0, 0}, Avv{0, 0, 0, 0};
  for (int b = 0; b <= pv_; ++b) {
    H4 row{0, 0, 0, 0}, row_u{0, 0, 0, 0}, row_uu{0, 0, 0, 0};
    for (int a = 0; a <= pu_; ++a) {
      const H4& q = p[a + (pu_ + 1) * b];
      row = axpy(row, bu[static_cast<std::size_t>(a)], q);
      if constexpr (kOrder >= 1) row_u = axpy(row_u, dbu[static_cast<std::size_t>(a)], q);
      if constexpr (kOrder >= 2) row_uu = axpy(row_uu, d2bu[static_cast<std::size_t>(a)], q);
    }
    const std::size_t bb = static_cast<std::size_t>(b);
    A = axpy(A, bv[bb], row);
    if constexpr (kOrder >= 1) {
      Au = axpy(Au, bv[bb], row_u);
      Av = axpy(Av, dbv[bb], row);
    }
    if constexpr (kOrder >= 2) {
      Auu = axpy(Auu, bv[bb], row_uu);
      Auv = axpy(Auv, dbv[bb], row_u);
      Avv = axpy(Avv, d2bv[bb], row);
    }
  }
  SurfaceDerivs2 d;
  d.p = project(A);
  if constexpr (kOrder >= 1) {
    Au = Au * (1.0 / du);
    Av = Av * (1.0 / dv);
    const gp_Vec P(d.p.X(), d.p.Y(), d.p.Z());
    d.su = (gp_Vec(Au.x, Au.y, Au.z) - P * Au.w) / A.w;
    d.sv = (gp_Vec(Av.x, Av.y, Av.z) - P * Av.w) / A.w;
  }
  if constexpr (kOrder >= 2) {
    // The quotient rule twice: S = X / w, so X = w S and each derivative of
    // X is that of w S by Leibniz's rule, solved for S's.
    Auu = Auu * (1.0 / (du * du));
    Auv = Auv * (1.0 / (du * dv));
    Avv = Avv * (1.0 / (dv * dv));
    const gp_Vec P(d.p.X(), d.p.Y(), d.p.Z());
    d.suu = (gp_Vec(Auu.x, Auu.y, Auu.z) - d.su * (2 * Au.w) - P * Auu.w) / A.w;
    d.suv = (gp_Vec(Auv.x, Auv.y, Auv.z) - d.su * Av.w - d.sv * Au.w - P * Auv.w) / A.w;
    d.svv = (gp_Vec(Avv.x, Avv.y, Avv.z) - d.sv * (2 * Av.w) - P * Avv.w) / A.w;
  }
  return d;
}

SurfaceDerivs PatchGrid::d1_on_span(int i, double u, double v) const {
  // Buffers sized to the degree: they are initialised on every call.
  if (pu_ <= 3 && pv_ <= 3) return derivs_in<4, 1>(i, u, v);
  if (pu_ <= 9 && pv_ <= 9) return derivs_in<10, 1>(i, u, v);
  return derivs_in<32, 1>(i, u, v);
}

gp_Vec PatchGrid::normal(double u, double v, const SurfaceDerivs* at) const {
  auto raw = [this](double uu, double vv) {
    const SurfaceDerivs d = d1(uu, vv);
    return d.su.Crossed(d.sv);
  };
  const double eps = 1e-14 * size_ * size_;
  gp_Vec n = at ? at->su.Crossed(at->sv) : raw(u, v);
  if (n.Magnitude() <= eps) {
    // A pole or a collapsed edge: take the limit from the interior.
    const double su = u < 0.5 * (umin() + umax()) ? 1.0 : -1.0;
    const double sv = v < 0.5 * (vmin() + vmax()) ? 1.0 : -1.0;
    for (double h = 1e-7; h < 1e-2 && n.Magnitude() <= eps; h *= 10.0) {
      n = raw(u, v + sv * h * (vmax() - vmin())) + raw(u + su * h * (umax() - umin()), v);
    }
    if (n.Magnitude() <= eps) return gp_Vec(0, 0, 1);
  }
  n.Normalize();
  return flip_normal_ ? -n : n;
}

}  // namespace isocam
