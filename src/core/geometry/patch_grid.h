// A face's surface as a grid of (rational) Bezier patches in homogeneous
// coordinates (w x, w y, w z, w). Every surface type reaches this form:
// B-spline and Bezier surfaces exactly (knot insertion), analytic surfaces
// (plane, cylinder, cone, sphere, torus, revolution, extrusion) exactly via
// OpenCASCADE's NURBS conversion, anything else (offset surfaces, ...) by a
// B-spline approximation within 1e-6 mm.
//
// Isocurves of the grid are exact piecewise (rational) Bezier curves, which
// is what the symbolic iso-distance of Definition 4 needs.
#pragma once

#include <TopoDS_Face.hxx>
#include <array>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <vector>

namespace isocam {

struct H4 {  // homogeneous point
  double x = 0, y = 0, z = 0, w = 1;
  H4 operator+(const H4& o) const { return {x + o.x, y + o.y, z + o.z, w + o.w}; }
  H4 operator-(const H4& o) const { return {x - o.x, y - o.y, z - o.z, w - o.w}; }
  H4 operator*(double s) const { return {x * s, y * s, z * s, w * s}; }
};

// A piecewise Bezier curve over the breakpoints `breaks` (span i covers
// [breaks[i], breaks[i+1]]), degree p, (p+1) homogeneous control points a span.
struct PiecewiseBezier {
  int degree = 0;
  std::vector<double> breaks;
  std::vector<H4> cps;

  int spans() const { return static_cast<int>(breaks.size()) - 1; }
  const H4* span(int i) const { return &cps[static_cast<std::size_t>(i * (degree + 1))]; }
  int span_of(double t) const;  // clamped to [0, spans()-1]
  gp_Pnt eval(double t) const;
};

struct SurfaceDerivs {
  gp_Pnt p;
  gp_Vec su, sv;
};
// ... and the second derivatives.
struct SurfaceDerivs2 : SurfaceDerivs {
  gp_Vec suu, suv, svv;
};

class PatchGrid {
 public:
  // Throws GeometryError (naming `face_label`) if the face is degenerate or
  // its surface cannot be represented.
  static PatchGrid from_face(const TopoDS_Face& face, int face_label);

  int degree_u() const { return pu_; }
  int degree_v() const { return pv_; }
  bool rational() const { return rational_; }
  // True if (u, v) of the grid are the face's own surface parameters (B-spline
  // and Bezier faces); false for analytic faces, whose NURBS form maps each
  // parameter by its own monotone function.
  bool same_params_as_face() const { return same_params_; }
  const std::vector<double>& ubreaks() const { return ub_; }
  const std::vector<double>& vbreaks() const { return vb_; }
  double umin() const { return ub_.front(); }
  double umax() const { return ub_.back(); }
  double vmin() const { return vb_.front(); }
  double vmax() const { return vb_.back(); }
  int patches_u() const { return static_cast<int>(ub_.size()) - 1; }
  int patches_v() const { return static_cast<int>(vb_.size()) - 1; }
  int span_of_u(double u) const;

  // The same surface with u and v exchanged; the material side is kept (the
  // normal of the transposed grid is the same vector in space).
  PatchGrid transposed() const;
  // The same surface with the material on the other side (the normal
  // reversed, as for the face taken reversed); the parameters are kept.
  PatchGrid other_side() const {
    PatchGrid g = *this;
    g.flip_normal_ = !flip_normal_;
    return g;
  }

  // The iso-v curve S(., v) as an exact piecewise Bezier in u.
  PiecewiseBezier iso_v(double v) const;

  gp_Pnt eval(double u, double v) const;
  SurfaceDerivs d1(double u, double v) const;
  // d1 on u-span `ui` (its polynomial extended), for one-sided limits at a
  // span break where the surface is only C0.
  SurfaceDerivs d1_on_span(int ui, double u, double v) const;
  // d1 with the second derivatives too.
  SurfaceDerivs2 d2(double u, double v) const;
  // Unit normal pointing away from the material (the face orientation's
  // side). At a degenerate point (a pole) the limit from the interior.
  // `at`, if given, is d1(u, v) already computed.
  gp_Vec normal(double u, double v, const SurfaceDerivs* at = nullptr) const;

  // Bounding box diagonal of the control net (a scale for tolerances).
  double size() const { return size_; }

  // Each u-span is cut into kStripParts equal parts for the bounds below.
  static constexpr int kStripParts = 8;
  // An upper bound of |dS/dv| over part s of u-span i and v-span j: exact
  // hull bound for polynomial patches (dS/dv is a convex combination of
  // pv * dP / dv over the part's control net), a sampled maximum with a 25%
  // margin for rational ones.
  double sv_bound(int i, int s, int j) const {
    return sv_bound_[static_cast<std::size_t>((j * patches_u() + i) * kStripParts + s)];
  }
  // Upper bound of the arc length across the strip v1 <= v <= v2, along any
  // iso-u curve within part s of u-span i.
  double strip_width_bound(int i, int s, double v1, double v2) const;

  // Control net of patch (i, j): point (a, b) at index a + (pu + 1) * b.
  const H4* patch(int i, int j) const {
    return &cps_[static_cast<std::size_t>((j * patches_u() + i) * (pu_ + 1) * (pv_ + 1))];
  }

 private:
  void finish();
  // The point at (u, v) in u-span i and its derivatives up to kOrder (0:
  // the point alone, for eval(); 1: d1(); 2: d2()).
  template <std::size_t N, int kOrder>
  SurfaceDerivs2 derivs_in(int i, double u, double v) const;

  int pu_ = 0, pv_ = 0;
  bool rational_ = false;
  bool flip_normal_ = false;  // true: away-from-material normal is -(Su x Sv)
  bool same_params_ = true;
  std::vector<double> ub_, vb_;
  // Patch (i, j) (i along u), control point (a, b): index a + (pu+1) * b.
  std::vector<H4> cps_;
  std::vector<double> sv_bound_;
  double size_ = 0.0;
};

// Evaluate Bernstein form of homogeneous points at local t in [0, 1].
H4 casteljau(const H4* cps, int degree, double t);
// The control points of the same curve restricted to [a, b] within [0, 1].
void restrict_h4(const H4* cps, int degree, double a, double b, H4* out);

}  // namespace isocam
