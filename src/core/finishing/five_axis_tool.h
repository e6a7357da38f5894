// Internal: the tilted flat end and bull nose of isocam/five_axis.h: the
// orientation at a contact point, the lower edge seen along the feed (Lee
// 1998, section 2), the strip half-width, the lead that keeps the bottom off
// concave ground to second order, and the exact check of the cutting end
// against the face.
//
// The bull nose as a Minkowski sum. Below the height rc along the axis the
// tool of radius R and corner radius rc is exactly the set of points within
// rc of its CORE DISC: the disc of radius R - rc centred on the axis at rc
// above the tip (the corner circles' centres fill its rim; the flat bottom
// is the core disc lowered by rc). So every question about the bull nose is
// the flat end's question about the core disc, then offset by rc:
//   * contact: the core disc's lowest rim point (along N) is at P + rc N;
//   * the edge seen along the feed: a projection maps a Minkowski sum to the
//     sum of the projections, so the tool's silhouette in the plane across
//     the feed is EXACTLY the core disc's ellipse offset by rc (its outer
//     parallel curve), not a first-order approximation (EdgeProfile);
//   * the gouge: a point of the core disc at signed height d above the face
//     digs in by rc - d (tool_depth).
// rc = 0 is the flat end, rc = R would be the ball of radius R (refused:
// no flat bottom to tilt). Above rc the tool is the cylinder of radius R,
// which contains the rest of the Minkowski sum; its side is not part of
// the edge (conservative for the strip: it could only cut more).
#pragma once

#include <algorithm>
#include <cmath>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <limits>

#include "finishing/scallop_front.h"
#include "geometry/patch_grid.h"

namespace isocam {

constexpr double kDegree = 0.017453292519943295;

// The cutting end: radius R and corner radius rc (0 <= rc < R).
struct Cutter {
  double radius = 0, corner = 0;
  double core() const { return radius - corner; }  // the core disc's radius
};

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
// the tip that puts the tool's lowest point (along N) on P: the core disc's
// lowest rim point at P + rc N, the tip rc below the core disc's centre.
ToolPose pose_at(const ContactFrame& c, const Cutter& tool, double lead, double tilt);

// The height D(x) of the tool's lower edge above the ground at the offset
// x across the feed (the ground the circle of curvature kappa_a, convex >
// 0), for the pose's orientation relative to the frame; x_min() < 0 <
// x_max() its extent. The edge is exact for the tool moving along F (the
// core disc's projected rim, an ellipse, offset by rc: solved for the
// outward normal's angle by Newton's method); what is approximated is the
// flat end's too:
// the ground is its circle of curvature across the feed, the feed is taken
// straight and the orientation constant, and D is the gap along N, at
// least the true distance to the circle (so the width is not over-estimated).
class EdgeProfile {
 public:
  EdgeProfile(const ContactFrame& c, const Cutter& tool, double lead, double tilt, double kappa_a);
  double height(double x) const;  // +inf outside the reach
  double x_min() const { return x0_ - m_ - rc_; }
  double x_max() const { return x0_ + m_ + rc_; }
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
  // height() and the tool's lowest point at x above the tangent line, the
  // bull nose's edge solved for its normal angle from *psi (then its value).
  double height(double x, double* psi) const;
  double edge(double x, double* psi) const;
  double x0_, m_, phi_, z0_, s_, t_, kappa_, rc_;
  double ux_ = 0, vx_ = 0;  // the rim's x = x0 + ux cos th + vx sin th
};

// The smallest lead >= base (radians, at most max_lead) that keeps the core
// disc off the ground offset by rc to second order: -k_a (R - rc) <= sin l
// and -k_f (R - rc) cos^2 l <= sin l with k = 1.25 kappa / (1 + 1.25 rc
// kappa) on concave ground (the offset's normal curvature, exact along the
// principal directions, with a 25% margin; five_axis.h); max_lead where
// the corner does not fit (1 + 1.25 rc kappa <= 0: no lead helps).
double lead_for(double base, double max_lead, const Cutter& tool, double kappa_f, double kappa_a);

// The frame at uv of the grid with the feed along `dir` (its tangential
// part); false where the normal or the feed is degenerate.
bool contact_frame(const PatchGrid& g, const ParamPt& uv, const gp_Vec& dir, ContactFrame* out);

// The most the cutting end of the pose goes below the surface of `g` near
// uv (a positive depth, 0 if it stays above): samples of the core disc's
// rim (48) and two inner rings, each against its nearest surface point
// found by Newton's method (from uv, or from the foot of the ring's sample
// before moved by the step between the two samples), digging in by rc -
// (its signed height). A point whose nearest point is off the face (on
// the grid's boundary, where the tool overhangs the untrimmed surface, or
// outside `inside`) is over the face's edge: there the depth counted is
// the tool's below the face's edge point E nearest it (depth_below), the
// clamped foot, or where the parameter segment from uv to the foot leaves
// the face (bisection). So a tool that overhangs the edge on ground rising
// beyond it, and reaches under the face there, is seen; one wholly beyond
// the edge is not. The rim's deepest sample over the edge is refined
// between its neighbours (the side standing on the rim may reach under the
// edge along a stretch shorter than the samples' spacing).
template <class Inside>
double tool_depth(const PatchGrid& g, const ParamPt& uv, const ToolPose& pose, const Cutter& tool,
                  const Inside& inside);

// tool_depth() signed: the deepest sample's depth, negative where every
// sample stays above the surface (how far the nearest is), -inf where none
// counts (uv outside the face and each sample over its edge). With `other`
// the face is another than the one the tool cuts (a wall beside it, a
// neighbour under the overhanging disc): the cylinder's side is sampled as
// well (24 points at each of the heights max(rc, R / 2) and R), a sample
// counts its depth below the face only where its foot lies in the tool,
// more than 1e-6 mm in (touching is not: a face tangent to the tool at its
// edge), else how far that foot is outside (behind a face's plane is not in its
// material far from the face, a side face below a convex edge); and a
// sample over the face's edge counts how deep the edge point nearest it
// lies inside the tool (depth_inside: a corner of the face poking into the
// tool), not the tool's depth below it (which assumes the material under
// the edge is the face's, true only of the face the tool cuts).
template <class Inside>
double signed_tool_depth(const PatchGrid& g, const ParamPt& uv, const ToolPose& pose,
                         const Cutter& tool, const Inside& inside, bool other);

// How deep the point e lies inside the tool of the pose (the distance to
// its surface; negative outside, then at most the distance in magnitude).
double depth_inside(const gp_Pnt& e, const ToolPose& pose, const Cutter& tool);

// How far the tool of the pose reaches below the surface point at e along
// its normal (negative: how far above it; -inf where the line misses the
// tool): the line through it met exactly with the cylinder of radius R
// above the height rc and, for a bull nose, the corner (the points within
// rc of the core disc: its entry found by bisection on the distance, which
// is convex along the line).
double depth_below(const PatchGrid& g, const ParamPt& e, const ToolPose& pose, const Cutter& tool);

// Nearest point of g to x by Newton's method on the squared distance from
// uv (its Hessian kept positive definite, a step that raises the distance
// halved, a parameter at a side of the rectangle held there while the step
// points out), until Gauss-Newton's step would move the point by under
// 1e-9 mm, at most 12 evaluations; false if it ends on the rectangle's
// boundary. `foot` receives its parameters and `at` (if given) the
// surface's point and derivatives there.
bool nearest_on(const PatchGrid& g, const gp_Pnt& x, ParamPt uv, ParamPt* foot,
                SurfaceDerivs* at = nullptr);

// The foot moved from `foot` (derivatives d there) by the parameter step
// whose tangent image is the tangential part of `step`, clamped to the grid.
ParamPt predicted_foot(const PatchGrid& g, const ParamPt& foot, const SurfaceDerivs& d,
                       const gp_Vec& step);

// The largest value of f met by a golden-section search for its maximum on
// [a, b] (`iterations` steps; f unimodal there), *at its argument.
template <class F>
double golden_max(const F& f, double a, double b, int iterations, double* at = nullptr) {
  const double k = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - k * (b - a), x2 = a + k * (b - a), f1 = f(x1), f2 = f(x2);
  double best = std::max(f1, f2), best_x = f1 >= f2 ? x1 : x2;
  for (int it = 0; it < iterations; ++it) {
    if (f1 >= f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - k * (b - a);
      f1 = f(x1);
      if (f1 > best) {
        best = f1;
        best_x = x1;
      }
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + k * (b - a);
      f2 = f(x2);
      if (f2 > best) {
        best = f2;
        best_x = x2;
      }
    }
  }
  if (at) *at = best_x;
  return best;
}

// The inside end of the parameter segment from `in` (inside) to `out`
// (outside, its surface point p_out) bisected at the boundary of `inside`
// until the two ends are within `tol` mm on the surface (one evaluation
// and one inside() a step).
template <class Inside>
ParamPt bisect_to_edge(const PatchGrid& g, ParamPt in, ParamPt out, gp_Pnt p_out,
                       const Inside& inside, double tol) {
  gp_Pnt p_in = g.eval(in.u, in.v);
  for (int it = 0; it < 60 && p_in.SquareDistance(p_out) > tol * tol; ++it) {
    const ParamPt mid{0.5 * (in.u + out.u), 0.5 * (in.v + out.v)};
    const gp_Pnt p_mid = g.eval(mid.u, mid.v);
    if (inside(mid)) {
      in = mid;
      p_in = p_mid;
    } else {
      out = mid;
      p_out = p_mid;
    }
  }
  return in;
}

template <class Inside>
double tool_depth(const PatchGrid& g, const ParamPt& uv, const ToolPose& pose, const Cutter& tool,
                  const Inside& inside) {
  return std::max(0.0, signed_tool_depth(g, uv, pose, tool, inside, false));
}

template <class Inside>
double signed_tool_depth(const PatchGrid& g, const ParamPt& uv, const ToolPose& pose,
                         const Cutter& tool, const Inside& inside, bool other) {
  gp_Vec e1 = pose.axis.Crossed(gp_Vec(0, 0, 1));
  if (e1.Magnitude() < 1e-6) e1 = pose.axis.Crossed(gp_Vec(1, 0, 0));
  e1.Normalize();
  const gp_Vec e2 = pose.axis.Crossed(e1);
  // A sample of the tool: on the core disc at the fraction r of its
  // radius, or (height > 0) on the side at that height above the tip.
  auto point = [&](double th, double r, double height = 0.0) {
    const gp_Vec out = e1 * std::cos(th) + e2 * std::sin(th);
    return height > 0.0 ? pose.tip.Translated(pose.axis * height + out * tool.radius)
                        : pose.tip.Translated(pose.axis * tool.corner + out * (tool.core() * r));
  };
  // The signed depth at the tool's point x, its Newton from `start`:
  // against its foot if that is on the face (*over false), else the
  // tool's below the face's edge point nearest it (*over true).
  // The bisection for the edge point ends where the two ends are within
  // kEdgeTol mm of each other on the surface (each step one evaluation
  // and one inside(), which near the edge is the face classifier's work).
  constexpr double kEdgeTol = 1e-5;
  // How deep inside the tool another face's point must lie to count as in
  // it (mm): touching is not.
  constexpr double kTouch = 1e-6;
  const bool uv_inside = inside(uv);
  // `offset`: what the sample digs in at height 0 (rc on the core disc,
  // whose points stand for the corner around them; 0 on the side).
  auto probe = [&](const gp_Pnt& x, double offset, const ParamPt& start, ParamPt* foot,
                   SurfaceDerivs* d, bool* on, bool* over) {
    *on = nearest_on(g, x, start, foot, d);
    const bool foot_inside = inside(*foot);
    *over = !*on || !foot_inside;
    if (!*over) {
      const double below = offset - gp_Vec(d->p, x).Dot(g.normal(foot->u, foot->v, d));
      if (!other) return below;
      // Another face: behind it counts only where its point lies in the
      // tool (behind a face's plane is not in its material far from it),
      // touching not included: a face tangent to the tool at its edge (a
      // cylinder patch's end cap at a contact on their common edge) has
      // the tool's rim behind its plane while the material there is the
      // face's being cut.
      const double in = depth_inside(d->p, pose, tool);
      return in > kTouch ? std::max(below, in) : in;
    }
    if (!uv_inside) return -std::numeric_limits<double>::infinity();
    const ParamPt e = foot_inside ? *foot : bisect_to_edge(g, uv, *foot, d->p, inside, kEdgeTol);
    return other ? depth_inside(g.eval(e.u, e.v), pose, tool) : depth_below(g, e, pose, tool);
  };
  double depth = -std::numeric_limits<double>::infinity();
  // The rim's deepest sample over the edge (its angle and Newton start).
  double edge_best = -std::numeric_limits<double>::infinity(), edge_th = 0.0;
  ParamPt edge_start = uv;
  // The rim samples' sides of the edge (over it or not) and feet, to find
  // where the rim crosses the edge.
  constexpr int kRim = 48;
  bool rim_over[kRim];
  ParamPt rim_foot[kRim];
  struct Ring {
    double r;
    int n;
    double height;  // > 0: on the side
  };
  // The core disc's rim and two inner rings, then the side's two rings.
  const Ring rings[] = {{1.0, kRim, 0.0},
                        {0.66, 24, 0.0},
                        {0.33, 12, 0.0},
                        {1.0, 24, std::max(tool.corner, 0.5 * tool.radius)},
                        {1.0, 24, tool.radius}};
  for (const Ring& ring : rings) {
    if (ring.height > 0.0 && !other) break;
    // Each sample's Newton starts where its neighbour's foot on the ring
    // predicts it (that foot moved by the tangential part of the step
    // between the two samples: a first Newton step for free), the first
    // from uv.
    bool have_prev = false;
    gp_Pnt prev_x;
    ParamPt prev_foot;
    SurfaceDerivs prev_d;
    for (int q = 0; q < ring.n; ++q) {
      const double th = 2 * M_PI * q / ring.n;
      const gp_Pnt x = point(th, ring.r, ring.height);
      const ParamPt start =
          have_prev ? predicted_foot(g, prev_foot, prev_d, gp_Vec(prev_x, x)) : uv;
      ParamPt foot;
      SurfaceDerivs d;
      bool on, over;
      const double s =
          probe(x, ring.height > 0.0 ? 0.0 : tool.corner, start, &foot, &d, &on, &over);
      have_prev = on;
      prev_x = x;
      prev_foot = foot;
      prev_d = d;
      depth = std::max(depth, s);
      if (&ring != rings) continue;
      rim_over[q] = over;
      rim_foot[q] = foot;
      if (over && s > edge_best) {
        edge_best = s;
        edge_th = th;
        edge_start = start;
      }
    }
  }
  // Where the rim overhangs the edge, the side standing on it may reach
  // under the face along a stretch of the edge shorter than the samples'
  // spacing: the deepest rim sample over the edge is refined by a golden
  // section search between its neighbours. And where the rim crosses the
  // edge between two samples, the part of it over the face near the edge
  // may dig in where neither sample does (the face rising to its edge
  // there, the rim dropping below it; 0.03 mm on a piece of MAT between
  // samples 7.5 deg apart): the stretch between them is searched too, on
  // the face the tool cuts and on the others (there it first found, on a
  // convex cylinder patch's first pass run along its end edge, rim points
  // near the contact 0.14 mm behind the end face's plane with their feet
  // on the tool's bottom, touching at the contact, and counted that as
  // depth: 44 positions were left out, until touching stopped counting as
  // in the tool, above).
  const double span = 2 * M_PI / kRim;
  auto rim_depth = [&](double a, double b, const ParamPt& start) {
    auto f = [&](double th) {
      ParamPt foot;
      SurfaceDerivs d;
      bool on, over;
      return probe(point(th, 1.0), tool.corner, start, &foot, &d, &on, &over);
    };
    depth = std::max(depth, golden_max(f, a, b, 24));
  };
  if (edge_best > -std::numeric_limits<double>::infinity())
    rim_depth(edge_th - span, edge_th + span, edge_start);
  for (int q = 0; q < kRim; ++q) {
    const int next = (q + 1) % kRim;
    if (rim_over[q] != rim_over[next])
      rim_depth(q * span, (q + 1) * span, rim_over[q] ? rim_foot[next] : rim_foot[q]);
  }
  return depth;
}

}  // namespace isocam
