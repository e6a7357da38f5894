// 5-axis strip finishing (isocam/five_axis.h): the strip half-width against
// its closed form on flat ground, the A/C convention and the unwrapped C,
// the tool posed on a plane (the disc's lowest point on the plane, the axis
// at the lead angle from the normal, along the feed), arguments refused by
// name, and the same path on one thread and on several; the nearest point
// of a surface (the exact check's projection) against a sphere's radial
// foot and as a stationary point on MAT; the bull nose: its
// strip against a brute-force Minkowski sum, between the ball's and the
// flat end's, posed on a plane, and kept off a convex and a concave
// cylinder by a sampled torus that shares nothing with the core.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <GeomConvert.hxx>
#include <GeomLProp_SLProps.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <cmath>
#include <gp_Ax3.hxx>
#include <gp_Cylinder.hxx>
#include <gp_Pln.hxx>
#include <random>
#include <string>

#include "finishing/five_axis_pose.h"
#include "finishing/five_axis_tool.h"
#include "geometry/patch_grid.h"
#include "isocam/errors.h"
#include "isocam/five_axis.h"
#include "support/models.h"
#include "support/same_path.h"

namespace isocam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A Bezier saddle, 16 x 12 mm, 1.5 mm up and down (concave along y).
TopoDS_Face bezier_saddle() {
  TColgp_Array2OfPnt poles(1, 3, 1, 3);
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j)
      poles(i, j) =
          gp_Pnt(8.0 * (i - 1), 6.0 * (j - 1), 1.5 * ((i - 2) * (i - 2) - (j - 2) * (j - 2)));
  return BRepBuilderAPI_MakeFace(new Geom_BezierSurface(poles), 1e-7).Face();
}

TEST(FiveAxis, HalfWidthOnFlatGroundIsTheEllipses) {
  // The lower edge seen along the feed: z = R sin(l) (1 - sqrt(1 - x^2 / R^2)).
  for (double lead : {2.0, 5.0, 15.0}) {
    for (double h : {0.002, 0.01, 0.05}) {
      const double R = 3.0, s = R * std::sin(lead * kDeg);
      const double expect = h < s ? R * std::sqrt(1 - std::pow(1 - h / s, 2)) : R;
      EXPECT_NEAR(flat_end_half_width(R, lead, 0.0, 0.0, h), expect, 1e-6 * R) << lead << " " << h;
    }
  }
  // Convex ground narrows the strip, concave widens it.
  const double flat = flat_end_half_width(3, 5, 0, 0.0, 0.01);
  EXPECT_LT(flat_end_half_width(3, 5, 0, 0.05, 0.01), flat);
  EXPECT_GT(flat_end_half_width(3, 5, 0, -0.02, 0.01), flat);
  // A side tilt makes the edge lopsided: the smaller side counts.
  EXPECT_LT(flat_end_half_width(3, 5, 10, 0.0, 0.01), flat);
  // Several times the ball's: 2 sqrt(2 r h - h^2) / 2 for a ball of radius 3.
  EXPECT_GT(flat, 3.0 * std::sqrt(2 * 3 * 0.01 - 1e-4));
}

TEST(FiveAxis, AxesToAcFollowsTheConventionAndUnwrapsC) {
  std::vector<double> i, j, k, a, c;
  std::vector<char> ok;
  // The axis at A = 20 deg turning about z through 720 degrees, then vertical.
  for (int q = 0; q <= 72; ++q) {
    const double A = 20 * kDeg, C = (q * 10.0) * kDeg;
    i.push_back(std::sin(A) * std::sin(C));
    j.push_back(-std::sin(A) * std::cos(C));
    k.push_back(std::cos(A));
  }
  i.push_back(0);
  j.push_back(0);
  k.push_back(1);
  axes_to_ac(i, j, k, 0, 90, &a, &c, &ok);
  ASSERT_EQ(a.size(), i.size());
  for (std::size_t q = 0; q < i.size(); ++q) {
    ASSERT_TRUE(ok[q]);
    const double A = a[q] * kDeg, C = c[q] * kDeg;
    EXPECT_NEAR(std::sin(A) * std::sin(C), i[q], 1e-12);
    EXPECT_NEAR(-std::sin(A) * std::cos(C), j[q], 1e-12);
    EXPECT_NEAR(std::cos(A), k[q], 1e-12);
    if (q > 0) {
      EXPECT_LE(std::abs(c[q] - c[q - 1]), 10.0 + 1e-9) << q;  // no unwind
    }
  }
  EXPECT_NEAR(c[72], 720.0, 1e-9);
  EXPECT_NEAR(c.back(), c[72], 1e-12);  // vertical: C kept
  // An axis pointing down needs A > 90: out of the default range.
  axes_to_ac({0.0}, {-0.5}, {-0.8660254037844386}, 0, 90, &a, &c, &ok);
  EXPECT_FALSE(ok[0]);
  // With negative A allowed, the branch (-A, C + 180) that moves less.
  axes_to_ac({0.0, 0.0}, {-0.5, 0.5}, {0.8660254037844386, 0.8660254037844386}, -90, 90, &a, &c,
             &ok);
  EXPECT_NEAR(a[0], 30.0, 1e-9);
  EXPECT_NEAR(a[1], -30.0, 1e-9);
  EXPECT_NEAR(c[1], c[0], 1e-9);
}

TEST(FiveAxis, PosedOnAPlaneAtTheLead) {
  const TopoDS_Face face =
      BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 2), gp_Dir(0, 0, 1)), 0, 20, 0, 12).Face();
  FiveAxisParams p;
  p.lead_angle = 7.0;
  p.direction = IsoDirection::V;  // passes along x, stepping across the 12 mm
  const FiveAxisResult r = five_axis_finish(face, {0}, p);
  ASSERT_GT(r.path.size(), 10u);
  ASSERT_EQ(r.i.size(), r.path.size());
  int feeds = 0;
  for (std::size_t q = 1; q < r.path.size(); ++q) {
    if (r.path.kind[q] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    ++feeds;
    const gp_Vec axis(r.i[q], r.j[q], r.k[q]);
    EXPECT_NEAR(axis.Magnitude(), 1.0, 1e-12);
    EXPECT_NEAR(axis.Angle(gp_Vec(0, 0, 1)), 7.0 * kDeg, 1e-9);
    // The disc's lowest rim point is on the plane: tip z - R sin(lead).
    EXPECT_NEAR(r.path.z[q] - p.tool_radius * std::sin(7.0 * kDeg), 2.0, 1e-9);
    // The axis leans along the feed (the move's direction).
    const gp_Vec move(r.path.x[q] - r.path.x[q - 1], r.path.y[q] - r.path.y[q - 1], 0);
    if (move.Magnitude() > 1e-6) {
      EXPECT_GT(move.Dot(gp_Vec(axis.X(), axis.Y(), 0)), 0);
    }
    // A and C give the axis back.
    const double A = r.a[q] * kDeg, C = r.c[q] * kDeg;
    EXPECT_NEAR(std::sin(A) * std::sin(C), axis.X(), 1e-9);
    EXPECT_NEAR(-std::sin(A) * std::cos(C), axis.Y(), 1e-9);
  }
  EXPECT_GT(feeds, 10);
  EXPECT_LE(r.metrics.guaranteed_scallop, p.scallop_height + 1e-12);
  EXPECT_NEAR(
      r.metrics.flat_strip_width,
      2 * flat_end_half_width(
              3, 7, 0, 0, p.scallop_height - (r.metrics.guaranteed_overcut - p.gouge_tolerance)),
      1e-9);
  // 12 mm across at the strip width: about 12 / w + 1 passes.
  EXPECT_LE(r.metrics.paths, static_cast<int>(12 / r.metrics.flat_strip_width) + 2);
  EXPECT_EQ(r.metrics.unreachable_length, 0.0);
}

// The nearest point of a sphere of radius 20 (its rational NURBS form) to
// a point at distance rho from the centre is the radial one, |rho - 20|
// away: from a start 3 % of the range off, on both sides, the concave one
// to within 6 mm of the centre (where a first-order step shrinks the
// error by only rho / 20 each time).
TEST(FiveAxis, NearestPointOnASphereIsRadial) {
  Handle(Geom_SphericalSurface) sphere = new Geom_SphericalSurface(gp_Ax3(), 20.0);
  Handle(Geom_BSplineSurface) nurbs = GeomConvert::SurfaceToBSplineSurface(
      new Geom_RectangularTrimmedSurface(sphere, 0.2, 2.9, -1.2, 1.1));
  const PatchGrid g = PatchGrid::from_face(BRepBuilderAPI_MakeFace(nurbs, 1e-7).Face(), 0);
  std::mt19937 rng(11);
  const double du = g.umax() - g.umin(), dv = g.vmax() - g.vmin();
  std::uniform_real_distribution<double> U(g.umin() + 0.1 * du, g.umax() - 0.1 * du),
      V(g.vmin() + 0.1 * dv, g.vmax() - 0.1 * dv), rho(6.0, 40.0), off(-0.03, 0.03);
  for (int k = 0; k < 500; ++k) {
    const ParamPt uv{U(rng), V(rng)};
    const gp_Pnt q = g.eval(uv.u, uv.v);
    const gp_Pnt x(gp_Vec(q.XYZ()).Normalized().XYZ() * rho(rng));
    ParamPt foot;
    SurfaceDerivs at;
    ASSERT_TRUE(nearest_on(g, x, {uv.u + off(rng) * du, uv.v + off(rng) * dv}, &foot, &at)) << k;
    EXPECT_LT(g.eval(foot.u, foot.v).Distance(q), 1e-7) << k << " rho " << x.Distance(gp::Origin());
    EXPECT_LT(at.p.Distance(q), 1e-7) << k;
  }
}

// On MAT (a bicubic B-spline face with small radii), from points up to 1.5
// mm off the surface on both sides: the foot found is a stationary point
// of the distance (x - S at it along the normal, to 1e-8 mm) no farther
// than the start, or on a side of the parameter rectangle (false).
TEST(FiveAxis, NearestPointOnMatIsStationary) {
  const PatchGrid g = PatchGrid::from_face(test::face(test::load("MAT.brep"), 0), 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(g.umin(), g.umax()), V(g.vmin(), g.vmax()), h(-1.5, 1.5),
      j(-0.5, 0.5);
  int interior = 0;
  for (int k = 0; k < 4000; ++k) {
    const ParamPt uv{U(rng), V(rng)};
    const SurfaceDerivs d = g.d1(uv.u, uv.v);
    const gp_Vec n = g.normal(uv.u, uv.v, &d);
    const gp_Pnt x =
        d.p.Translated(n * h(rng) + d.su.Normalized() * j(rng) + d.sv.Normalized() * j(rng));
    ParamPt foot;
    SurfaceDerivs at;
    const bool on = nearest_on(g, x, uv, &foot, &at);
    const gp_Vec r(at.p, x);
    EXPECT_LE(r.Magnitude(), x.Distance(d.p) + 1e-12) << k;
    if (!on) {
      EXPECT_TRUE(foot.u == g.umin() || foot.u == g.umax() || foot.v == g.vmin() ||
                  foot.v == g.vmax())
          << k;
      continue;
    }
    ++interior;
    const gp_Vec m = g.normal(foot.u, foot.v, &at);
    EXPECT_LT((r - m * r.Dot(m)).Magnitude(), 1e-8)
        << k << " at " << foot.u << ", " << foot.v << " from " << uv.u << ", " << uv.v;
  }
  EXPECT_GT(interior, 3000);
}

TEST(FiveAxis, DepthCountsTheToolUnderAFacesEdge) {
  // The face z = -x for x in [-9.9, 0] (falling towards its edge x = 0),
  // the axis vertical, the bottom 0.3 mm below the edge and reaching 0.05
  // mm inside it: every point of the bottom is nearest the plane beyond the
  // edge, yet the tool is under the face's edge strip. Along the normal
  // (1, 0, 1) / sqrt 2 at the edge point (0, 0, 0), the point (s, 0, s) is
  // in the flat end where s >= -0.05 (its side), so it reaches 0.05 sqrt 2
  // below the face there. A bull nose (rc 1, its bottom 1 mm below the
  // edge): the point is in its corner where its distance to the core disc
  // (radius 2, centre (2.95, 0, 0)) is at most 1: (0.95 - s)^2 + s^2 = 1.
  const gp_Ax3 frame(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 1), gp_Dir(-1, 0, 1));
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(gp_Pln(frame), 0, 14, -10, 10).Face();
  const PatchGrid g = PatchGrid::from_face(face, 1);
  const auto anywhere = [](const ParamPt&) { return true; };
  const ParamPt contact{2.0, 0.0};
  ToolPose pose{gp_Pnt(2.95, 0, -0.3), gp_Vec(0, 0, 1)};
  EXPECT_NEAR(tool_depth(g, contact, pose, Cutter{3.0, 0.0}, anywhere), 0.05 * std::sqrt(2.0),
              1e-9);
  // The same edge as a trim (the face's half u < 1.4, the edge at x = -1):
  // the tool 1 mm further in, the same depth below the trimmed edge.
  const auto trimmed = [](const ParamPt& q) { return q.u >= 1.4142135623730951; };
  ToolPose in{gp_Pnt(1.95, 0, 0.7), gp_Vec(0, 0, 1)};
  EXPECT_NEAR(tool_depth(g, contact, in, Cutter{3.0, 0.0}, trimmed), 0.05 * std::sqrt(2.0), 1e-6);
  const double s = (1.9 - std::sqrt(1.9 * 1.9 + 8 * 0.0975)) / 4;  // 2 s^2 - 1.9 s - 0.0975 = 0
  pose.tip.SetZ(-1.0);
  EXPECT_NEAR(tool_depth(g, contact, pose, Cutter{3.0, 1.0}, anywhere), -s * std::sqrt(2.0), 1e-6);
  // Wholly beyond the edge: nothing under the face.
  pose.tip.SetX(3.05);
  EXPECT_EQ(tool_depth(g, contact, pose, Cutter{3.0, 0.0}, anywhere), 0.0);
  EXPECT_EQ(tool_depth(g, contact, pose, Cutter{3.0, 1.0}, anywhere), 0.0);
}

// Where the rim crosses the face's edge between two of its samples, the
// part over the face may dig in where neither sample does. A pose of the
// posted program on a piece of MAT (u and v from 0.3 and 0.4 of its range
// to a tenth more; the tool beyond the edge u = 844.1, the face rising to
// it): the rim sampled 7.5 deg apart stays above the face (the samples
// over it at 142.5 deg, the next over the edge), but between them it is
// 0.035 mm under it. Measured apart from the core: 3600 rim points, each
// projected by OpenCASCADE onto the piece, its depth along the normal
// where the foot is inside the piece's parameter range.
TEST(FiveAxis, DepthCountsTheRimWhereItCrossesTheEdge) {
  const TopoDS_Face mat = test::face(test::load("MAT.brep"), 0);
  const Handle(Geom_Surface) s = BRep_Tool::Surface(mat);
  double u0, u1, v0, v1;
  s->Bounds(u0, u1, v0, v1);
  const double a = u0 + 0.3 * (u1 - u0), b = u0 + 0.4 * (u1 - u0), c = v0 + 0.4 * (v1 - v0),
               d = v0 + 0.5 * (v1 - v0);
  const PatchGrid g = PatchGrid::from_face(BRepBuilderAPI_MakeFace(s, a, b, c, d, 1e-7).Face(), 0);
  const double A = 13.227 * M_PI / 180, C = 61.037 * M_PI / 180;
  const ToolPose pose{gp_Pnt(841.498, 839.697, 3.523),
                      gp_Vec(std::sin(A) * std::sin(C), -std::sin(A) * std::cos(C), std::cos(A))};
  const gp_Vec e1 = pose.axis.Crossed(gp_Vec(0, 0, 1)).Normalized(), e2 = pose.axis.Crossed(e1);
  double deepest = -1.0;
  for (int k = 0; k < 3600; ++k) {
    const double th = 2 * M_PI * k / 3600;
    const gp_Pnt x = pose.tip.Translated((e1 * std::cos(th) + e2 * std::sin(th)) * 3.0);
    GeomAPI_ProjectPointOnSurf proj(x, s, a, b, c, d);
    if (proj.NbPoints() == 0) continue;
    double u, v;
    proj.LowerDistanceParameters(u, v);
    if (u <= a + 1e-9 || u >= b - 1e-9 || v <= c + 1e-9 || v >= d - 1e-9) continue;
    GeomLProp_SLProps props(s, u, v, 1, 1e-9);
    deepest = std::max(deepest, -gp_Vec(props.Value(), x).Dot(gp_Vec(props.Normal())));
  }
  ASSERT_GT(deepest, 0.03);
  const auto anywhere = [](const ParamPt&) { return true; };
  const double depth = tool_depth(g, {844.2, 841.0}, pose, Cutter{3.0, 0.0}, anywhere);
  EXPECT_GE(depth, deepest - 1e-4);
  EXPECT_LE(depth, deepest + 0.01);  // (the tool below the edge point counts too)
}

TEST(FiveAxis, OtherFaceDepthCountsTheSideAndNotBehindAConvexEdge) {
  // A wall x = 0 (material at x > 0: the face's normal -x), y in [-10, 10],
  // z in [0, 3]; a flat end R 3 whose side stands 0.1 mm into it.
  const auto inside = [](const ParamPt&) { return true; };
  const Cutter flat{3.0, 0.0};
  const gp_Ax3 wall_frame(gp_Pnt(0, 0, 0), gp_Dir(-1, 0, 0), gp_Dir(0, 1, 0));
  const PatchGrid wall =
      PatchGrid::from_face(BRepBuilderAPI_MakeFace(gp_Pln(wall_frame), -10, 10, -3, 0).Face(), 1);
  const ParamPt mid{0.0, -1.5};  // (v runs down: the frame's y is N x X = -z)
  const ToolPose upright{gp_Pnt(-2.9, 0, 0.5), gp_Vec(0, 0, 1)};
  EXPECT_NEAR(signed_tool_depth(wall, mid, upright, flat, inside, true), 0.1, 1e-9);
  // Leaning 10 degrees towards the wall, the disc's rim 0.47 mm off it and
  // the side at R above the tip 0.05 mm into it (2.93 mm high): only the
  // side sees it. The side reaches further in the higher it is, so the
  // wall's deepest point in the tool is its top edge's at y = 0 (the edge
  // point nearest the side samples above the wall): R - its distance from
  // the axis.
  const double a = 10 * kDeg;
  const ToolPose lean{gp_Pnt(0.05 - 3.0 * (std::sin(a) + std::cos(a)), 0, 0.5),
                      gp_Vec(std::sin(a), 0, std::cos(a))};
  const gp_Vec to_top(lean.tip, gp_Pnt(0, 0, 3));
  const double top_in = 3.0 - (to_top - lean.axis * to_top.Dot(lean.axis)).Magnitude();
  EXPECT_GT(top_in, 0.05);
  EXPECT_NEAR(signed_tool_depth(wall, mid, lean, flat, inside, true), top_in, 1e-6);
  EXPECT_EQ(tool_depth(wall, mid, lean, flat, inside), 0.0);
  // The side face below a convex edge: x = 0 with its normal +x (material
  // at x < 0), z in [-6, 0]; the disc over the edge 0.01 mm above it and
  // reaching 2 mm beyond it. Every disc point is behind the face's plane
  // (up to 4 mm) but none is in its material: the edge point nearest each
  // is 0.01 mm below the tool.
  const gp_Ax3 side_frame(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), gp_Dir(0, 1, 0));
  const PatchGrid side =
      PatchGrid::from_face(BRepBuilderAPI_MakeFace(gp_Pln(side_frame), -10, 10, -6, 0).Face(), 1);
  const ToolPose over{gp_Pnt(-1.0, 0, 0.01), gp_Vec(0, 0, 1)};
  EXPECT_NEAR(signed_tool_depth(side, ParamPt{0.0, -1.0}, over, flat, inside, true), -0.01, 1e-6);
  // depth_inside: a point in the flat end 0.2 above the bottom and 0.5 in
  // from the side; one beside a bull nose's corner (R 3, rc 1: the corner
  // circle's centre at radius 2 and height 1), 1.2042 from it.
  const ToolPose tip0{gp_Pnt(0, 0, 0), gp_Vec(0, 0, 1)};
  EXPECT_NEAR(depth_inside(gp_Pnt(2.5, 0, 0.2), tip0, flat), 0.2, 1e-12);
  EXPECT_NEAR(depth_inside(gp_Pnt(0, 2.9, 0.2), tip0, Cutter{3.0, 1.0}), 1.0 - std::hypot(0.9, 0.8),
              1e-12);
  EXPECT_NEAR(depth_inside(gp_Pnt(0, 0, -0.3), tip0, flat), -0.3, 1e-12);
}

// A face the tool only touches is not dug into, though the tool lies
// behind its plane: the side of a block (x = 0, its normal -x, material
// at x > 0, z in [-3, 0]) with the flat end on the block's top at its
// edge, overhanging it by 2.5 mm. The rim over the top lies up to 3.5 mm
// behind the side's plane, the feet there on the side's top edge, on the
// tool's bottom (before, that counted 3.5 mm: a cylinder patch's passes
// along its end edge were left out). Lowered 0.1 mm, the side's top edge
// is 0.1 mm inside the tool, and that counts.
TEST(FiveAxis, OtherFaceTouchedAtItsEdgeIsNotDugInto) {
  const auto inside = [](const ParamPt&) { return true; };
  const Cutter flat{3.0, 0.0};
  const gp_Ax3 frame(gp_Pnt(0, 0, 0), gp_Dir(-1, 0, 0), gp_Dir(0, 1, 0));
  const PatchGrid side =
      PatchGrid::from_face(BRepBuilderAPI_MakeFace(gp_Pln(frame), -10, 10, 0, 3).Face(), 1);
  const ParamPt mid{0.0, 1.5};  // (v runs down: z = -v)
  const ToolPose on_top{gp_Pnt(0.5, 0, 0), gp_Vec(0, 0, 1)};
  EXPECT_LE(signed_tool_depth(side, mid, on_top, flat, inside, true), 1e-6);
  const ToolPose lowered{gp_Pnt(0.5, 0, -0.1), gp_Vec(0, 0, 1)};
  EXPECT_NEAR(signed_tool_depth(side, mid, lowered, flat, inside, true), 0.1, 1e-6);
}

TEST(FiveAxis, LagOnReturnKeepsTheTiltsSideAndC) {
  // The plane above: by default the axis leans along each pass's feed, so
  // C turns half a turn between the zig-zag's passes; with lag_on_return
  // the passes run back keep the forward passes' tilt: every feed move has
  // the same axis, C stays, and the path cut is the same.
  const TopoDS_Face face =
      BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 2), gp_Dir(0, 0, 1)), 0, 20, 0, 12).Face();
  FiveAxisParams p;
  p.lead_angle = 7.0;
  p.direction = IsoDirection::V;
  const FiveAxisResult lead = five_axis_finish(face, {0}, p);
  p.lag_on_return = true;
  const FiveAxisResult lag = five_axis_finish(face, {0}, p);
  ASSERT_GT(lag.metrics.paths, 3);
  EXPECT_EQ(lag.metrics.paths, lead.metrics.paths);
  EXPECT_NEAR(lag.metrics.cutting_length, lead.metrics.cutting_length, 1e-6);
  EXPECT_GE(lead.metrics.rotary_travel_c, 180.0 * (lead.metrics.paths - 1) - 1e-6);
  EXPECT_LT(lag.metrics.rotary_travel_c, 1e-6);
  int along = 0, against = 0;
  gp_Vec first;
  for (std::size_t q = 1; q < lag.path.size(); ++q) {
    if (lag.path.kind[q] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    const gp_Vec axis(lag.i[q], lag.j[q], lag.k[q]);
    if (first.SquareMagnitude() == 0) first = axis;
    EXPECT_LT(axis.Angle(first), 1e-9);
    EXPECT_NEAR(lag.path.z[q] - p.tool_radius * std::sin(7.0 * kDeg), 2.0, 1e-9);
    const gp_Vec move(lag.path.x[q] - lag.path.x[q - 1], lag.path.y[q] - lag.path.y[q - 1], 0);
    if (move.Magnitude() > 1e-3) ++(move.Dot(gp_Vec(axis.X(), axis.Y(), 0)) > 0 ? along : against);
  }
  // Half the passes lead, half lag.
  EXPECT_GT(along, 10);
  EXPECT_GT(against, 10);
  EXPECT_LE(lag.metrics.guaranteed_scallop, p.scallop_height + 1e-12);
  EXPECT_EQ(lag.metrics.unreachable_length, 0.0);
  EXPECT_LT(lag.metrics.machine_time, lead.metrics.machine_time);
}

TEST(FiveAxis, LagOnReturnOnASaddle) {
  // The Bezier saddle (leads raised on its concave side): the same
  // guarantee and passes with lag_on_return. (Here the normal leans far
  // more than the lead, so C follows the normal and travels as much.)
  const TopoDS_Face face = bezier_saddle();
  FiveAxisParams p;
  p.scallop_height = 0.02;
  const FiveAxisResult lead = five_axis_finish(face, {0}, p);
  p.lag_on_return = true;
  const FiveAxisResult lag = five_axis_finish(face, {0}, p);
  const FiveAxisMetrics& m = lag.metrics;
  EXPECT_EQ(m.paths, lead.metrics.paths);
  EXPECT_NEAR(m.cutting_length, lead.metrics.cutting_length, 1e-3 * lead.metrics.cutting_length);
  EXPECT_LE(m.guaranteed_scallop, p.scallop_height + 1e-12);
  EXPECT_EQ(m.unreachable_length, 0.0);
  EXPECT_EQ(m.unconverged_moves, 0);
}

// The bull nose on flat ground without tilt, by brute force: its core disc
// (radius R' = R - rc, rc up) seen along the feed is the half-ellipse
// z = rc + R' sin(l) (1 - sqrt(1 - x^2 / R'^2)); the tool's edge is its
// Minkowski sum with the disc of radius rc, the least over x' of that minus
// sqrt(rc^2 - (x - x')^2) (sampled every rc / 2000). x_h where the edge
// reaches h.
double brute_bull_half_width(double R, double rc, double lead_deg, double h) {
  const double r = R - rc, s = r * std::sin(lead_deg * kDeg);
  auto edge = [&](double x) {
    double z = 1e300;
    const int n = 4000;
    for (int k = 0; k <= n; ++k) {
      const double xp = std::clamp(x - rc + 2 * rc * k / n, -r, r);
      const double d = x - xp;
      if (std::abs(d) > rc) continue;
      z = std::min(z, rc + s * (1 - std::sqrt(1 - xp * xp / (r * r))) - std::sqrt(rc * rc - d * d));
    }
    return z;
  };
  // The edge is convex with its lowest point at 0: it grows with x > 0.
  double lo = 0, hi = R;
  if (edge(hi) < h) return R;
  for (int it = 0; it < 40; ++it) (edge(0.5 * (lo + hi)) >= h ? hi : lo) = 0.5 * (lo + hi);
  return lo;
}

TEST(FiveAxis, BullNoseHalfWidthIsTheOffsetEllipses) {
  for (double lead : {3.0, 5.0, 15.0})
    for (double h : {0.002, 0.01, 0.05}) {
      const double got = strip_half_width(3, 1, lead, 0, 0, h);
      EXPECT_NEAR(got, brute_bull_half_width(3, 1, lead, h), 2e-4) << lead << " " << h;
      // Wider than the ball of radius rc, narrower than the flat end.
      EXPECT_GT(got, std::sqrt(2 * 1 * h - h * h)) << lead << " " << h;
      EXPECT_LT(got, flat_end_half_width(3, lead, 0, 0, h)) << lead << " " << h;
    }
  // rc -> 0 tends to the flat end's; the strip narrows as rc grows.
  const double flat = flat_end_half_width(3, 5, 0, 0, 0.01);
  EXPECT_NEAR(strip_half_width(3, 1e-6, 5, 0, 0, 0.01), flat, 1e-5);
  EXPECT_EQ(strip_half_width(3, 0, 5, 0, 0, 0.01), flat);
  double prev = flat;
  for (double rc : {0.25, 0.5, 1.0, 2.0, 2.9}) {
    const double w = strip_half_width(3, rc, 5, 0, 0, 0.01);
    EXPECT_LT(w, prev) << rc;
    EXPECT_GT(w, std::sqrt(2 * rc * 0.01 - 1e-4)) << rc;
    prev = w;
  }
  // Curved ground and a tilt act as on the flat end.
  const double bull = strip_half_width(3, 1, 5, 0, 0, 0.01);
  EXPECT_LT(strip_half_width(3, 1, 5, 0, 0.05, 0.01), bull);
  EXPECT_GT(strip_half_width(3, 1, 5, 0, -0.02, 0.01), bull);
  EXPECT_LT(strip_half_width(3, 1, 5, 10, 0, 0.01), bull);
}

TEST(FiveAxis, BullNosePosedOnAPlane) {
  const TopoDS_Face face =
      BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 2), gp_Dir(0, 0, 1)), 0, 20, 0, 12).Face();
  FiveAxisParams p;
  p.corner_radius = 1.0;
  p.lead_angle = 7.0;
  p.direction = IsoDirection::V;
  const FiveAxisResult r = five_axis_finish(face, {0}, p);
  int feeds = 0;
  const double l = 7.0 * kDeg;
  for (std::size_t q = 1; q < r.path.size(); ++q) {
    if (r.path.kind[q] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    ++feeds;
    EXPECT_NEAR(gp_Vec(r.i[q], r.j[q], r.k[q]).Angle(gp_Vec(0, 0, 1)), l, 1e-9);
    // The corner's lowest point on the plane: the tip (R - rc) sin l +
    // rc (1 - cos l) above it.
    EXPECT_NEAR(r.path.z[q] - 2.0, 2.0 * std::sin(l) + 1.0 * (1 - std::cos(l)), 1e-9);
  }
  EXPECT_GT(feeds, 10);
  EXPECT_LE(r.metrics.guaranteed_scallop, p.scallop_height + 1e-12);
  const double h_eff = p.scallop_height - (r.metrics.guaranteed_overcut - p.gouge_tolerance);
  EXPECT_NEAR(r.metrics.flat_strip_width, 2 * strip_half_width(3, 1, 7, 0, 0, h_eff), 1e-9);
  EXPECT_LE(r.metrics.paths, static_cast<int>(12 / r.metrics.flat_strip_width) + 2);
  EXPECT_EQ(r.metrics.unreachable_length, 0.0);
}

// The deepest the bull nose (R, rc) of each posted feed position goes into
// the solid bounded by the cylinder of radius rho about the line x = 0,
// z = zc along y (convex: the material inside it; concave: outside), within
// |y - 4| < 4. The torus sampled as circles: at the angle phi up its
// corner, the circle of radius R - rc + rc sin(phi), rc (1 - cos(phi)) up
// the axis from the tip; and the flat bottom's rings.
double cylinder_overcut(const FiveAxisResult& r, double R, double rc, double rho, double zc,
                        bool convex) {
  double worst = 0.0;
  for (std::size_t q = 0; q < r.path.size(); ++q) {
    if (r.path.kind[q] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    const gp_Vec a(r.i[q], r.j[q], r.k[q]);
    gp_Vec e1 = a.Crossed(gp_Vec(0, 1, 0));
    if (e1.Magnitude() < 1e-6) e1 = a.Crossed(gp_Vec(1, 0, 0));
    e1.Normalize();
    const gp_Vec e2 = a.Crossed(e1);
    const gp_Pnt tip(r.path.x[q], r.path.y[q], r.path.z[q]);
    auto probe = [&](double radius, double up) {
      for (int k = 0; k < 180; ++k) {
        const double th = 2 * M_PI * k / 180;
        const gp_Pnt x = tip.Translated(a * up + (e1 * std::cos(th) + e2 * std::sin(th)) * radius);
        if (std::abs(x.Y() - 4.0) >= 4.0) continue;
        const double d = std::hypot(x.X(), x.Z() - zc);
        worst = std::max(worst, convex ? rho - d : d - rho);
      }
    };
    for (int k = 0; k <= 24; ++k) {
      const double phi = 0.5 * M_PI * k / 24;
      probe(R - rc + rc * std::sin(phi), rc * (1 - std::cos(phi)));
    }
    for (double f : {0.25, 0.5, 0.75}) probe(f * (R - rc), 0.0);
  }
  return worst;
}

TEST(FiveAxis, BullNoseStaysOffConvexAndConcaveCylinders) {
  // Convex: the top of a cylinder of radius 20 (axis 18 below the origin);
  // concave: the bottom of a trough of radius 15 (axis 15 above), its
  // face reversed so that the normal points away from the material.
  const gp_Ax3 low(gp_Pnt(0, 0, -18), gp_Dir(0, 1, 0), gp_Dir(1, 0, 0));
  const gp_Ax3 high(gp_Pnt(0, 0, 15), gp_Dir(0, 1, 0), gp_Dir(1, 0, 0));
  const TopoDS_Face convex =
      BRepBuilderAPI_MakeFace(gp_Cylinder(low, 20), -M_PI / 2 - 0.4, -M_PI / 2 + 0.4, 0, 8).Face();
  TopoDS_Face concave =
      BRepBuilderAPI_MakeFace(gp_Cylinder(high, 15), M_PI / 2 - 0.5, M_PI / 2 + 0.5, 0, 8).Face();
  concave.Reverse();
  struct Case {
    TopoDS_Face face;
    double rho, zc;
    bool convex;
  } cases[] = {{convex, 20, -18, true}, {concave, 15, 15, false}};
  for (const Case& c : cases) {
    FiveAxisParams p;
    p.corner_radius = 1.0;
    p.scallop_height = 0.02;
    p.direction = IsoDirection::U;  // passes along the axis, stepping round
    const FiveAxisResult r = five_axis_finish(c.face, {0}, p);
    EXPECT_GT(r.metrics.paths, 3) << c.convex;
    EXPECT_LE(r.metrics.guaranteed_scallop, p.scallop_height + 1e-12) << c.convex;
    EXPECT_EQ(r.metrics.unreachable_length, 0.0) << c.convex;
    const double over = cylinder_overcut(r, 3, 1, c.rho, c.zc, c.convex);
    EXPECT_LE(over, r.metrics.guaranteed_overcut) << c.convex;
    // The strips: convex ground narrows them, concave widens them, against
    // the plane's (the largest spacing measured between paths).
    const double flat = 2 * strip_half_width(3, 1, 5, 0, 0, 0.02);
    if (c.convex) {
      EXPECT_LT(r.metrics.max_spacing, flat);
    } else {
      EXPECT_GT(r.metrics.max_spacing, flat);
    }
  }
}

void expect_refused(FiveAxisParams p, const std::string& name) {
  const TopoDS_Face face =
      BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 0, 5, 0, 5).Face();
  try {
    five_axis_finish(face, {0}, p);
    ADD_FAILURE() << "accepted " << name;
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

// Habit 4: a degenerate picked face (all poles on one line, no area) beside
// a good one is skipped with a warning naming it, and the good face is
// finished as if picked alone; every picked face degenerate is an error.
TEST(FiveAxis, DegenerateFaceBesideAGoodOneIsSkipped) {
  TColgp_Array2OfPnt poles(1, 3, 1, 3);
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j) poles(i, j) = gp_Pnt(10.0 * i + j, 50, -40);
  const TopoDS_Face bad = BRepBuilderAPI_MakeFace(new Geom_BezierSurface(poles), 1e-7).Face();
  BRep_Builder b;
  TopoDS_Compound shape;
  b.MakeCompound(shape);
  b.Add(shape, BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 2), gp_Dir(0, 0, 1)), 0, 20, 0, 12));
  b.Add(shape, bad);
  FiveAxisParams p;
  p.direction = IsoDirection::V;
  const FiveAxisResult both = five_axis_finish(shape, {0, 1}, p);
  const FiveAxisResult alone = five_axis_finish(shape, {0}, p);
  EXPECT_EQ(both.skipped_faces, std::vector<int>{1});
  int naming = 0;
  for (const std::string& w : both.warnings)
    if (w.find("Face2") != std::string::npos) {
      ++naming;
      EXPECT_NE(w.find("degenerate"), std::string::npos) << w;
      EXPECT_NE(w.find("skipped"), std::string::npos) << w;
    }
  EXPECT_EQ(naming, 1);
  ASSERT_GT(both.path.size(), 10u);
  EXPECT_EQ(both.path.z, alone.path.z);
  EXPECT_EQ(both.i, alone.i);
  try {
    five_axis_finish(shape, {1}, p);
    ADD_FAILURE() << "no exception";
  } catch (const GeometryError& e) {
    EXPECT_NE(std::string(e.what()).find("Face2"), std::string::npos) << e.what();
  }
}

TEST(FiveAxis, OneAndManyThreadsGiveTheSamePath) {
  // A Bezier saddle, 16 x 12 mm (the lead raised on its concave side), both
  // directions traced and the runs posed on 1 and on 4 threads.
  const TopoDS_Face face = bezier_saddle();
  FiveAxisParams p;
  p.scallop_height = 0.02;
  p.threads = 1;
  const FiveAxisResult one = five_axis_finish(face, {0}, p);
  p.threads = 4;
  const FiveAxisResult four = five_axis_finish(face, {0}, p);
  ASSERT_GT(one.path.size(), 100u);
  EXPECT_GT(one.metrics.paths, 3);
  EXPECT_TRUE(test::same_path(one.path, four.path));
  EXPECT_EQ(one.i, four.i);
  EXPECT_EQ(one.j, four.j);
  EXPECT_EQ(one.k, four.k);
  EXPECT_EQ(one.metrics.guaranteed_scallop, four.metrics.guaranteed_scallop);
  EXPECT_EQ(one.metrics.lead_raised_points, four.metrics.lead_raised_points);
  EXPECT_EQ(one.metrics.unreachable_length, four.metrics.unreachable_length);
  EXPECT_LE(one.metrics.guaranteed_scallop, p.scallop_height + 1e-12);
  EXPECT_EQ(one.metrics.unconverged_moves, 0);
}

TEST(FiveAxis, SpacingFollowsTheLeadsTheExactCheckRaised) {
  // A valley z = c x^4 (12 x 10 mm, c = 0.001), the passes along it: flat
  // at the bottom, its curvature growing fast up the sides, so the disc's
  // rim meets steeper ground than the curvature at the contact tells and
  // the exact check raises the lead beyond what that curvature asks for.
  // The certificate measured with the leads posed exceeds h' on the first
  // paths; they are traced again with the strips narrowed there, and the
  // guarantee holds for the leads posted.
  const double a = 6.0, c = 0.001;
  TColgp_Array2OfPnt poles(1, 5, 1, 2);  // x^4 on [-a, a]: Bezier ordinates c a^4 (+-1)
  for (int i = 1; i <= 5; ++i)
    for (int j = 1; j <= 2; ++j)
      poles(i, j) = gp_Pnt(-a + 2 * a * (i - 1) / 4.0, 10.0 * (j - 1),
                           c * std::pow(a, 4) * ((5 - i) % 2 == 0 ? 1 : -1));
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(new Geom_BezierSurface(poles), 1e-7).Face();
  FiveAxisParams p;
  p.scallop_height = 0.02;
  p.direction = IsoDirection::U;  // the passes along y
  const FiveAxisResult r = five_axis_finish(face, {0}, p);
  int again = 0;
  for (const std::string& w : r.warnings)
    if (w.find("traced again") != std::string::npos) ++again;
  EXPECT_EQ(again, 1);
  EXPECT_GT(r.metrics.lead_raised_points, 100);
  EXPECT_LE(r.metrics.guaranteed_scallop, p.scallop_height + 1e-12);
  EXPECT_EQ(r.metrics.unreachable_length, 0.0);
  EXPECT_LE(2 * r.metrics.coverage_gap, 1.05 * r.metrics.flat_strip_width);
  // Each position is posed by where it is on its segment (contact, feed
  // and the least lead interpolated along it), so the halving between two
  // positions converges also where the exact check raised the lead; but
  // at the start of a pass, where the disc overhangs the face's edge y = 0
  // and the valley's side rises beyond it, the check of the tool under the
  // edge raises the lead at some positions and not at their neighbours (6
  // moves, 5 to 7 degrees): there the swing is checked, and clear.
  EXPECT_LE(r.metrics.unconverged_moves, 8);
  EXPECT_EQ(r.metrics.swings_split, 0);
}

// The leads the exact check raised, looked up by position on a plane: the
// lead posed at a point is the largest raised within one radius (1 mm)
// of it; the one a path traced again is spaced for, within two (cells two
// apart included); a lead raised only to what the curvature asks for is
// not kept.
TEST(FiveAxis, RaisedLeadsWithinOneAndTwoRadii) {
  TColgp_Array2OfPnt poles(1, 2, 1, 2);
  for (int i = 1; i <= 2; ++i)
    for (int j = 1; j <= 2; ++j) poles(i, j) = gp_Pnt(40.0 * (i - 1), 20.0 * (j - 1), 0.0);
  const PatchGrid g =
      PatchGrid::from_face(BRepBuilderAPI_MakeFace(new Geom_BezierSurface(poles), 1e-7).Face(), 0);
  auto at_x = [](double x, double lead, bool exact) {
    five_axis::Posed q;
    q.uv = {x / 40.0, 0.5};  // (x, 10, 0)
    q.lead = lead;
    q.raised_exact = exact;
    return q;
  };
  five_axis::RaisedLeads leads(1.0);
  EXPECT_EQ(leads.at(gp_Pnt(10, 10, 0), 2), 0.0);
  leads.add(g, {{at_x(10.0, 0.15, true), at_x(13.0, 0.2, true), at_x(30.0, 0.5, false)}});
  EXPECT_EQ(leads.at(gp_Pnt(10.9, 10, 0)), 0.15);
  EXPECT_EQ(leads.at(gp_Pnt(11.5, 10, 0)), 0.0);
  EXPECT_EQ(leads.at(gp_Pnt(11.5, 10, 0), 2), 0.2);
  EXPECT_EQ(leads.at(gp_Pnt(11.05, 10, 0)), 0.0);
  EXPECT_EQ(leads.at(gp_Pnt(11.05, 10, 0), 2), 0.2);
  EXPECT_EQ(leads.at(gp_Pnt(13, 11.9, 0), 2), 0.2);
  EXPECT_EQ(leads.at(gp_Pnt(15.1, 10, 0), 2), 0.0);
  EXPECT_EQ(leads.at(gp_Pnt(30, 10, 0), 2), 0.0);
}

// The op on one face with NormalIsocurves and with StripEvaluation, at
// the scallop height h (the other parameters the defaults).
struct BothStrategies {
  FiveAxisResult iso, strip;
};
BothStrategies both_strategies(const TopoDS_Face& face, double h) {
  FiveAxisParams p;
  p.scallop_height = h;
  p.strategy = FiveAxisStrategy::NormalIsocurves;
  BothStrategies out{five_axis_finish(face, {0}, p), {}};
  p.strategy = FiveAxisStrategy::StripEvaluation;
  out.strip = five_axis_finish(face, {0}, p);
  return out;
}

TEST(FiveAxis, NormalIsocurvesMeetTheScallopOnASaddle) {
  // The Bezier saddle above: adaptive isocurves with the tilted flat end's
  // strip, the lead raised on the concave side as for the other strategy.
  const double h = 0.02;
  const auto [iso, strip] = both_strategies(bezier_saddle(), h);
  const FiveAxisMetrics& m = iso.metrics;
  ASSERT_GT(iso.path.size(), 100u);
  EXPECT_GT(m.paths, 3);
  EXPECT_LE(m.guaranteed_scallop, h + 1e-12);
  EXPECT_LE(m.max_spacing, 2 * 3.0);
  EXPECT_LE(2 * m.coverage_gap, 1.05 * m.flat_strip_width);
  EXPECT_EQ(m.unreachable_length, 0.0);
  EXPECT_GT(m.lead_raised_points, 0);
  EXPECT_NE(iso.path.x, strip.path.x);
  EXPECT_EQ(strip.metrics.isocurve_faces, 0);  // the march kept: the shorter
  for (const std::string& w : iso.warnings) EXPECT_EQ(w.find("gap"), std::string::npos) << w;
}

// Where the strip width changes fast along the front, the march's front
// folds: on a piece of MAT (u and v from 0.3 to 0.5 of its range; bumps
// whose concave ground narrows the flat end's strip from 1.65 mm to the
// minimum spacing) it cut 1134 mm against the adaptive isocurves' 441
// (its first tracing was the shorter; the tracing again for the leads the
// exact check raised folded). StripEvaluation traces both, each time, and
// uses the isocurves where they are over a tenth shorter, with a warning
// naming the face; the leads raised differ, so the paths a little too.
TEST(FiveAxis, StripEvaluationUsesTheIsocurvesWhereTheMarchFolds) {
  const TopoDS_Face mat = test::face(test::load("MAT.brep"), 0);
  const Handle(Geom_Surface) s = BRep_Tool::Surface(mat);
  double u0, u1, v0, v1;
  s->Bounds(u0, u1, v0, v1);
  const TopoDS_Face piece =
      BRepBuilderAPI_MakeFace(s, u0 + 0.3 * (u1 - u0), u0 + 0.5 * (u1 - u0), v0 + 0.3 * (v1 - v0),
                              v0 + 0.5 * (v1 - v0), 1e-7)
          .Face();
  const double h = 0.01;
  const auto [iso, strip] = both_strategies(piece, h);
  EXPECT_LE(strip.metrics.cutting_length, 1.1 * iso.metrics.cutting_length);
  EXPECT_LE(strip.metrics.guaranteed_scallop, h);
  const auto used = std::find_if(strip.warnings.begin(), strip.warnings.end(), [](const auto& w) {
    return w.find("Face1") != std::string::npos &&
           w.find("isocurves are used") != std::string::npos;
  });
  ASSERT_NE(used, strip.warnings.end());
  for (const std::string& w : iso.warnings)
    EXPECT_EQ(w.find("isocurves are used"), std::string::npos);
  EXPECT_EQ(strip.metrics.isocurve_faces, 1);
  EXPECT_EQ(iso.metrics.isocurve_faces, 0);
}

TEST(FiveAxis, BadArgumentsAreNamed) {
  FiveAxisParams p;
  p.corner_radius = 3.0;  // a ball: no flat bottom
  expect_refused(p, "corner_radius");
  p.corner_radius = -0.5;
  expect_refused(p, "corner_radius");
  p = {};
  p.lead_angle = 0.0;
  expect_refused(p, "lead_angle");
  p = {};
  p.a_max = 200;
  expect_refused(p, "a_max");
  p = {};
  p.scallop_height = 0.0005;
  expect_refused(p, "scallop_height");
  p = {};
  p.tool_length = 1.0;
  expect_refused(p, "tool_length");
  p = {};
  p.threads = -1;
  expect_refused(p, "threads");
}

}  // namespace
}  // namespace isocam
