// The simulator on cases whose answer is known in closed form.
#include <gtest/gtest.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <TopoDS.hxx>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <gp_Ax2.hxx>
#include <gp_Pln.hxx>
#include <sstream>
#include <string>

#include "gcode_sim.h"

namespace {

using gsim::Program;
using gsim::Result;
using gsim::Sample;

constexpr double kR = 3.0;  // ball radius

std::string feed(double x, double y, double z) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "STRAIGHT_FEED(%.4f, %.4f, %.4f, 0.0000, 0.0000, 0.0000)\n", x, y,
                z);
  return buf;
}
std::string rapid(double x, double y, double z) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "STRAIGHT_TRAVERSE(%.4f, %.4f, %.4f, 0.0000, 0.0000, 0.0000)\n", x,
                y, z);
  return buf;
}

Program parse(const std::string& text, double sag = 1e-5) {
  std::istringstream in("SET_FEED_RATE(1000.0000)\n" + text);
  return gsim::parse_canon(in, sag);
}

// The face numbers (1-based) whose surface normal at the middle is `dir`.
int face_facing(const TopoDS_Shape& shape, double nx, double ny, double nz) {
  const auto faces = gsim::faces_of(shape);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    BRepAdaptor_Surface s(TopoDS::Face(faces[i]));
    if (s.GetType() != GeomAbs_Plane) continue;
    gp_Dir n = s.Plane().Axis().Direction();
    if (faces[i].Orientation() == TopAbs_REVERSED) n.Reverse();
    if (n.X() * nx + n.Y() * ny + n.Z() * nz > 0.999) return static_cast<int>(i) + 1;
  }
  return 0;
}

gsim::Options options(double scallop = -1) {
  gsim::Options o;
  o.ball_radius = kR;
  o.scallop = scallop;
  return o;
}

// A 6 x 6 x 5 plate, top face z = 5.
TopoDS_Shape plate() { return BRepPrimAPI_MakeBox(6.0, 6.0, 5.0).Shape(); }

TEST(GcodeSimFaces, NumberedLikeFreeCAD) {
  const TopoDS_Shape box = plate();
  EXPECT_EQ(gsim::faces_of(box).size(), 6u);
  EXPECT_EQ(face_facing(box, 0, 0, 1), 6);  // BRepPrim's box: Face6 is the top
}

TEST(GcodeSimPlate, StraightPassBelowTheTopCutsExactlyThatDeep) {
  const TopoDS_Shape box = plate();
  const int top = face_facing(box, 0, 0, 1);
  const auto samples = gsim::sample_faces(box, {top}, 0.02, 2);
  // Tip 0.03 below the top along y = 3: overcut 0.03 on the line y = 3.
  const Program prog =
      parse(rapid(-4, 3, 20) + rapid(-4, 3, 4.97) + feed(10, 3, 4.97) + rapid(10, 3, 20));
  const Result r = gsim::measure(samples, prog, options());
  EXPECT_NEAR(r.overcut.value, 0.03, 2e-4);
  EXPECT_NEAR(r.overcut.at.y, 3.0, 0.02);
  EXPECT_EQ(r.overcut.face, top);
  EXPECT_EQ(r.overcut.move, 2);  // the feed, not a rapid
  EXPECT_DOUBLE_EQ(r.rapid_overcut.value, 0.0);
  // A convex plate is reachable everywhere; the single pass leaves the rest
  // uncovered (residual capped at max_residual).
  EXPECT_EQ(r.reachable_samples, r.picked_samples);
  EXPECT_NEAR(r.left.value, options().max_residual, 1e-12);
  EXPECT_GT(r.uncovered_samples, 0u);
  EXPECT_EQ(prog.feeds, 1);
  EXPECT_EQ(prog.rapids, 3);
  EXPECT_NEAR(prog.feed_length, 14.0, 1e-9);
  EXPECT_NEAR(prog.feed_time_min, 14.0 / 1000.0, 1e-12);
}

TEST(GcodeSimPlate, ParallelPassesLeaveTheFlatCusp) {
  const TopoDS_Shape box = plate();
  const int top = face_facing(box, 0, 0, 1);
  const double spacing = 0.01, w = 1.0;
  const auto samples = gsim::sample_faces(box, {top}, spacing, 2);
  std::string text = rapid(-4, -3, 20);
  for (int k = 0; k <= 12; ++k) {  // y = -3 .. 9, the tip exactly on the top
    const double y = -3 + k * w;
    text += feed(k % 2 ? 10 : -4, y, 5.0) + feed(k % 2 ? -4 : 10, y, 5.0);
  }
  const Result r = gsim::measure(samples, parse(text), options(0.05));
  const double cusp = kR - std::sqrt(kR * kR - w * w / 4);
  // The residual has a kink at the cusp; a sample is at most `spacing`/2
  // away from it (along y), where the slope is (w/2)/sqrt(r^2 - (w/2)^2).
  const double slope = (w / 2) / std::sqrt(kR * kR - w * w / 4);
  EXPECT_LE(r.left.value, cusp + 1e-9);
  EXPECT_GE(r.left.value, cusp - slope * spacing);
  EXPECT_NEAR(std::fmod(r.left.at.y + 3.0, w), w / 2, spacing);
  EXPECT_LT(r.overcut.value, 1e-9);
  EXPECT_EQ(r.uncovered_samples, 0u);
  EXPECT_EQ(r.reachable_samples, r.picked_samples);
  // Coverage: the whole plate within 0.05 > cusp.
  EXPECT_NEAR(r.covered_area / r.reachable_area, 1.0, 1e-9);
  EXPECT_NEAR(r.picked_area, 36.0, 1e-3);
}

TEST(GcodeSimPlate, RapidThroughThePartIsAnOvercutOfItsOwn) {
  const TopoDS_Shape box = plate();
  const int top = face_facing(box, 0, 0, 1);
  const auto samples = gsim::sample_faces(box, {top}, 0.05, 2);
  // A rapid 0.5 below the top across the plate.
  const Program prog =
      parse(rapid(-4, 2, 20) + rapid(-4, 2, 4.5) + rapid(10, 2, 4.5) + rapid(10, 2, 20));
  const Result r = gsim::measure(samples, prog, options());
  EXPECT_NEAR(r.rapid_overcut.value, 0.5, 2e-3);
  EXPECT_NEAR(r.overcut.value, 0.5, 2e-3);
  EXPECT_EQ(r.rapid_overcut.move, 2);
  EXPECT_EQ(r.rapid_overcut.face, top);
}

TEST(GcodeSimPlate, OvercutOnAnUnpickedFaceCounts) {
  const TopoDS_Shape box = plate();
  const int top = face_facing(box, 0, 0, 1), side = face_facing(box, 1, 0, 0);
  const auto samples = gsim::sample_faces(box, {top}, 0.02, 2);
  // Pass down the side x = 6, the ball 0.02 into it.
  const double xc = 6 + kR - 0.02;
  const Program prog =
      parse(rapid(xc, 3, 20) + rapid(xc, 3, 3) + feed(xc, 3, -1) + rapid(xc, 3, 20));
  const Result r = gsim::measure(samples, prog, options());
  EXPECT_NEAR(r.overcut.value, 0.02, 2e-4);
  EXPECT_EQ(r.overcut.face, side);
}

// A cylinder of radius 10 along x (x = 0 .. 10): a straight pass along its top
// and a full circle around it (an arc move), both 0.01 into the material.
TEST(GcodeSimCylinder, StraightPassAndFullCircleArc) {
  const double rc = 10.0;
  const TopoDS_Shape cyl =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), rc, 10.0).Shape();
  int side = 0;
  const auto faces = gsim::faces_of(cyl);
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (BRepAdaptor_Surface(TopoDS::Face(faces[i])).GetType() == GeomAbs_Cylinder)
      side = static_cast<int>(i) + 1;
  ASSERT_GT(side, 0);
  const auto samples = gsim::sample_faces(cyl, {side}, 0.04, 2);

  // Straight: tip at z = rc - 0.01 (ball centre rc + r - 0.01).
  Result r = gsim::measure(
      samples,
      parse(rapid(-5, 0, 30) + rapid(-5, 0, rc - 0.01) + feed(15, 0, rc - 0.01) + rapid(15, 0, 30)),
      options());
  EXPECT_NEAR(r.overcut.value, 0.01, 1e-4);
  EXPECT_NEAR(r.overcut.at.z, rc, 1e-3);
  EXPECT_EQ(r.overcut.face, side);

  // The arc: G19 (YZ plane), ball centre on the circle of radius
  // rc + r - 0.01 around the axis, so the tip circle is centred at z = -r.
  // Written as G-code and read back through rs274 itself.
  const double rho = rc + kR - 0.01;
  char ngc[512];
  std::snprintf(
      ngc, sizeof ngc,
      "G21 G90 G17\nG0 X5 Y0 Z%.4f\nG1 Z%.4f F600\nG19 G3 Y0 Z%.4f J0 K%.4f\nG17\nG0 Z40\nM2\n",
      40.0, rho - kR, rho - kR, -rho);
  const std::string file = ::testing::TempDir() + "gsim_arc.ngc";
  {
    std::ofstream out(file);
    out << ngc;
  }
  std::istringstream canon(gsim::run_rs274("rs274", file, ""));
  const Program prog = gsim::parse_canon(canon, 1e-5);
  EXPECT_EQ(prog.arcs, 1);
  EXPECT_NEAR(prog.arc_length, 2 * M_PI * rho, 1e-6);
  r = gsim::measure(samples, prog, options());
  EXPECT_NEAR(r.overcut.value, 0.01, 2e-4);
  EXPECT_NEAR(r.overcut.at.x, 5.0, 0.03);
  // All around the circle, not only at the top: the overcut band x = 5 +- a.
  std::size_t below = 0;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].face == side && r.residual[i] < -0.009 && samples[i].p.z < -5) ++below;
  EXPECT_GT(below, 10u);
}

// A box with a half-cylinder groove of radius 2 < r along x: the groove is
// out of the ball's reach, the top is not.
TEST(GcodeSimReach, GrooveNarrowerThanTheBallIsUnreachable) {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(20.0, 20.0, 10.0).Shape();
  const TopoDS_Shape bar =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-1, 10, 10), gp_Dir(1, 0, 0)), 2.0, 22.0).Shape();
  const TopoDS_Shape part = BRepAlgoAPI_Cut(box, bar).Shape();
  std::vector<int> picked;
  const auto faces = gsim::faces_of(part);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    BRepAdaptor_Surface s(TopoDS::Face(faces[i]));
    if (s.GetType() == GeomAbs_Cylinder ||
        (s.GetType() == GeomAbs_Plane && std::fabs(s.Plane().Location().Z() - 10) < 1e-9 &&
         std::fabs(s.Plane().Axis().Direction().Z()) > 0.999))
      picked.push_back(static_cast<int>(i) + 1);
  }
  ASSERT_EQ(picked.size(), 3u);  // the top in two halves and the groove
  const auto samples = gsim::sample_faces(part, picked, 0.05, 2);
  const Result r = gsim::measure(samples, parse(rapid(0, 0, 50)), options());
  const double top = 20 * 20 - 20 * 4, groove = M_PI * 2 * 20;
  EXPECT_NEAR(r.picked_area, top + groove, 0.5);
  EXPECT_NEAR(r.reachable_area / r.picked_area, top / (top + groove), 0.01);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!samples[i].picked) continue;
    const bool in_groove = samples[i].p.z < 10 - 1e-6;
    if (in_groove) {
      EXPECT_FALSE(r.reachable[i]) << samples[i].p.y << " " << samples[i].p.z;
    }
  }
}

// A solid sphere: a 3-axis tool reaches its upper half only (the ball that
// touches a point below the equator, lifted straight up, goes through the
// sphere); the ball alone reaches all of it.
TEST(GcodeSimReach, SphereIsReachableFromAboveOnItsUpperHalf) {
  const TopoDS_Shape ball = BRepPrimAPI_MakeSphere(10.0).Shape();
  const auto samples = gsim::sample_faces(ball, {1}, 0.1, 2);
  gsim::Options o = options();
  Result r = gsim::measure(samples, parse(rapid(0, 0, 50)), o);
  EXPECT_NEAR(r.reachable_area / r.picked_area, 0.5, 0.005);
  int wrong = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double z = samples[i].p.z;
    if (std::fabs(z) > 0.05 && bool(r.reachable[i]) != (z > 0)) ++wrong;
  }
  EXPECT_EQ(wrong, 0);
  o.from_above = false;
  r = gsim::measure(samples, parse(rapid(0, 0, 50)), o);
  EXPECT_EQ(r.reachable_samples, r.picked_samples);
}

// A face turned down: as an open face it is reachable (from its upper side);
// as the bottom of a box it is not.
TEST(GcodeSimReach, OpenFaceIsReachableFromItsUpperSide) {
  const TopoDS_Shape plate =
      BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(0, 0, -1)), 0, 20, 0, 20).Face();
  auto samples = gsim::sample_faces(plate, {1}, 0.1, 2);
  ASSERT_LT(samples.front().n[2], -0.999f);  // the ball would be under it
  Result r = gsim::measure(samples, parse(rapid(0, 0, 50)), options());
  EXPECT_EQ(r.reachable_samples, r.picked_samples);
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(20.0, 20.0, 10.0).Shape();
  const int bottom = face_facing(box, 0, 0, -1);
  ASSERT_GT(bottom, 0);
  samples = gsim::sample_faces(box, {bottom}, 0.1, 2);
  r = gsim::measure(samples, parse(rapid(0, 0, 50)), options());
  EXPECT_GT(r.picked_samples, 1000u);
  EXPECT_EQ(r.reachable_samples, 0u);
}

TEST(GcodeSimCanon, RejectsWhatItCannotSimulate) {
  EXPECT_THROW(parse("USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n"), std::runtime_error);
  EXPECT_THROW(parse("SET_G5X_OFFSET(1, 10.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n"),
               std::runtime_error);
  EXPECT_THROW(parse("STRAIGHT_FEED(1.0000, abc, 0.0000)\n"), std::runtime_error);
  EXPECT_THROW(parse("STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 5.0000, 0.0000, 0.0000)\n"),
               std::runtime_error);  // a rotary axis
  std::istringstream no_feed("STRAIGHT_FEED(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n");
  EXPECT_THROW(gsim::parse_canon(no_feed, 1e-5), std::runtime_error);
  EXPECT_THROW(gsim::run_rs274("rs274", "/nonexistent/file.ngc", ""), std::runtime_error);
}

TEST(GcodeSimCanon, ArcTurnsAndDirections) {
  // XY arc from (10,0) around (0,0): counterclockwise to (0,10) is a quarter,
  // clockwise a three-quarter turn; rotation 2 adds a full circle.
  const std::string start = rapid(10, 0, 0);
  Program p = parse(
      start + "ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, 1, 0.0000, 0.0000, 0.0000, 0.0000)\n");
  EXPECT_NEAR(p.arc_length, M_PI * 10 / 2, 1e-9);
  p = parse(start +
            "ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, -1, 0.0000, 0.0000, 0.0000, 0.0000)\n");
  EXPECT_NEAR(p.arc_length, 3 * M_PI * 10 / 2, 1e-9);
  p = parse(start +
            "ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, 2, 0.0000, 0.0000, 0.0000, 0.0000)\n");
  EXPECT_NEAR(p.arc_length, 5 * M_PI * 10 / 2, 1e-9);
  // The pieces stay on the circle (clockwise: through (0,-10)).
  p = parse(start +
            "ARC_FEED(0.0000, 10.0000, 0.0000, 0.0000, -1, 0.0000, 0.0000, 0.0000, 0.0000)\n");
  double ymin = 0;
  for (const auto& s : p.segments) {
    ymin = std::min(ymin, s.b.y);
    EXPECT_NEAR(std::hypot(s.b.x, s.b.y), 10.0, 1e-9);
  }
  EXPECT_NEAR(ymin, -10.0, 1e-4);
}

}  // namespace
