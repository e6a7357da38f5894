// 5-axis strip finishing (isocam/five_axis.h): the strip half-width against
// its closed form on flat ground, the A/C convention and the unwrapped C,
// the tool posed on a plane (the disc's lowest point on the plane, the axis
// at the lead angle from the normal, along the feed), and arguments refused
// by name.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BezierSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Face.hxx>
#include <cmath>
#include <gp_Pln.hxx>
#include <string>

#include "isocam/errors.h"
#include "isocam/five_axis.h"

namespace isocam {
namespace {

constexpr double kDeg = M_PI / 180.0;

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

TEST(FiveAxis, BadArgumentsAreNamed) {
  FiveAxisParams p;
  p.corner_radius = 1.0;
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
}

}  // namespace
}  // namespace isocam
