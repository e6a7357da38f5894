// Internal: the tilted flat end of isocam/five_axis.h: its orientation at a
// contact point, its lower edge seen along the feed (Lee 1998, section 2),
// the strip half-width, the lead that keeps the disc off concave ground to
// second order, and the exact check of the disc against the face.
#pragma once

#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>

#include "finishing/scallop_front.h"
#include "geometry/patch_grid.h"

namespace isocam {

constexpr double kDegree = 0.017453292519943295;

// A tool position: the tip (centre of the bottom face) and the unit axis.
struct ToolPose {
  gp_Pnt tip;
  gp_Vec axis;
};

// The contact frame: N away from the material, F the feed, A = N x F.
struct ContactFrame {
  gp_Pnt p;
  gp_Vec n, f, a;
};

// The axis tilted by `lead` towards F and `tilt` towards A (radians), and
// the tip that puts the disc's lowest rim point (along N) on P.
ToolPose pose_at(const ContactFrame& c, double radius, double lead, double tilt);

// The height D(x) of the tool's lower edge above the ground at the offset
// x across the feed (the ground the circle of curvature kappa_a, convex >
// 0), for the pose's orientation relative to the frame. `reach` receives
// the edge's extent on each side (x_min < 0 < x_max).
class EdgeProfile {
 public:
  EdgeProfile(const ContactFrame& c, double radius, double lead, double tilt, double kappa_a);
  double height(double x) const;  // +inf outside the reach
  double x_min() const { return x0_ - m_; }
  double x_max() const { return x0_ + m_; }
  // The smaller side's half-width within h (its reach if it stays within h).
  double half_width(double h) const;
  // The cusp of two such edges `spacing` apart: D(spacing / 2) on the
  // smaller side (+inf beyond the reach).
  double cusp(double spacing) const;
  // The lowest D over the reach: < 0 means the edge is below the ground
  // across the feed (a local gouge at the sides).
  double lowest() const;

 private:
  double side_width(double h, double sign) const;
  double x0_, m_, phi_, z0_, s_, t_, kappa_;
};

// The smallest lead >= base (radians, at most max_lead) that keeps the disc
// off the ground to second order with a 25% curvature margin:
// -kappa_a R <= sin l and -kappa_f R cos^2 l <= sin l (five_axis.h).
double lead_for(double base, double max_lead, double radius, double kappa_f, double kappa_a);

// The frame at uv of the grid with the feed along `dir` (its tangential
// part); false where the normal or the feed is degenerate.
bool contact_frame(const PatchGrid& g, const ParamPt& uv, const gp_Vec& dir, ContactFrame* out);

// The most the disc of the pose goes below the surface of `g` near uv (a
// positive depth, 0 if it stays above): samples of the rim (48) and two
// inner rings, each against its nearest surface point found by Newton's
// method from uv; points whose nearest point is on the grid's boundary (the
// disc overhangs the untrimmed surface) or outside `inside` do not count.
template <class Inside>
double disc_depth(const PatchGrid& g, const ParamPt& uv, const ToolPose& pose, double radius,
                  const Inside& inside);

// Nearest point of g to x by Newton from uv; false if it ends on the
// rectangle's boundary. `foot` receives its parameters.
bool nearest_on(const PatchGrid& g, const gp_Pnt& x, ParamPt uv, ParamPt* foot);

template <class Inside>
double disc_depth(const PatchGrid& g, const ParamPt& uv, const ToolPose& pose, double radius,
                  const Inside& inside) {
  gp_Vec e1 = pose.axis.Crossed(gp_Vec(0, 0, 1));
  if (e1.Magnitude() < 1e-6) e1 = pose.axis.Crossed(gp_Vec(1, 0, 0));
  e1.Normalize();
  const gp_Vec e2 = pose.axis.Crossed(e1);
  double depth = 0.0;
  const struct {
    double r;
    int n;
  } rings[] = {{1.0, 48}, {0.66, 24}, {0.33, 12}};
  for (const auto& ring : rings)
    for (int q = 0; q < ring.n; ++q) {
      const double th = 2 * M_PI * q / ring.n;
      const gp_Pnt x =
          pose.tip.Translated((e1 * std::cos(th) + e2 * std::sin(th)) * (radius * ring.r));
      ParamPt foot;
      if (!nearest_on(g, x, uv, &foot) || !inside(foot)) continue;
      const SurfaceDerivs d = g.d1(foot.u, foot.v);
      const double hgt = gp_Vec(d.p, x).Dot(g.normal(foot.u, foot.v, &d));
      depth = std::max(depth, -hgt);
    }
  return depth;
}

}  // namespace isocam
