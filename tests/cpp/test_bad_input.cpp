// Bad input raises the documented error, naming the argument or the face.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <Geom_BezierSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <sstream>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "support/checks.h"
#include "support/models.h"
#include "support/same_path.h"

namespace isocam {
namespace {

template <class E>
void expect_error(const std::function<void()>& f, const std::string& needle) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning '" << needle << "'";
  } catch (const E& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

IsoParams good() {
  IsoParams p;
  p.ball_radius = 3;
  p.scallop_height = 0.05;
  p.safe_z = 100;
  return p;
}

TEST(BadInput, ScallopOutOfRange) {
  const TopoDS_Shape s = test::figure2_ruled_surface();
  for (double h : {0.0, -0.1, 3.0, 5.0}) {
    IsoParams p = good();
    p.scallop_height = h;
    expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {0}, p); }, "scallop_height");
  }
}

TEST(BadInput, ChordToleranceAndRadius) {
  const TopoDS_Shape s = test::figure2_ruled_surface();
  IsoParams p = good();
  p.chord_tolerance = -0.01;  // 0 is valid: derived from the budgets
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {0}, p); }, "chord_tolerance");
  p = good();
  p.ball_radius = -1;
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {0}, p); }, "ball_radius");
  p = good();
  p.max_depth = 0;
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {0}, p); }, "max_depth");
}

TEST(BadInput, EmptyOrUnreadableBrep) {
  expect_error<InvalidArgument>([] { read_brep(""); }, "brep");
  expect_error<InvalidArgument>([] { read_brep("   \n"); }, "empty");
  expect_error<InvalidArgument>([] { read_brep("this is not a B-rep"); }, "brep");
  expect_error<InvalidArgument>([] { adaptive_isocurve(TopoDS_Shape(), {0}, good()); }, "brep");
}

TEST(BadInput, FaceIndexOutOfRangeOrRepeated) {
  const TopoDS_Shape s = test::figure2_ruled_surface();
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {1}, good()); }, "out of range");
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {-1}, good()); }, "faces");
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {}, good()); }, "no face");
  expect_error<InvalidArgument>([&] { adaptive_isocurve(s, {0, 0}, good()); }, "twice");
}

TEST(BadInput, DegenerateFace) {
  // All poles on one line: a surface with no area.
  TColgp_Array2OfPnt poles(1, 3, 1, 3);
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j) poles(i, j) = gp_Pnt(10.0 * i + j, 0, 0);
  Handle(Geom_BezierSurface) s = new Geom_BezierSurface(poles);
  const TopoDS_Face f = BRepBuilderAPI_MakeFace(s, 1e-7).Face();
  expect_error<GeometryError>([&] { adaptive_isocurve(f, {0}, good()); }, "Face1");
}

// A Bezier face with all its poles on one line (no area), lying `below` mm
// under the origin, away from the other faces of the tests.
TopoDS_Face degenerate_face(double below) {
  TColgp_Array2OfPnt poles(1, 3, 1, 3);
  for (int i = 1; i <= 3; ++i)
    for (int j = 1; j <= 3; ++j) poles(i, j) = gp_Pnt(10.0 * i + j, 50, -below);
  Handle(Geom_BezierSurface) s = new Geom_BezierSurface(poles);
  return BRepBuilderAPI_MakeFace(s, 1e-7).Face();
}

// The warnings that name `label` (e.g. "Face2").
std::vector<std::string> naming(const IsoResult& r, const std::string& label) {
  std::vector<std::string> out;
  for (const std::string& w : r.warnings)
    if (w.find(label) != std::string::npos) out.push_back(w);
  return out;
}

// Habit 4: a degenerate picked face beside a good one is skipped with a
// warning naming it; the good face is finished exactly as if it had been
// picked alone (the degenerate face cannot be in the clearance model
// either, so the job is the same), for every pattern.
TEST(BadInput, DegenerateFaceBesideAGoodOneIsSkipped) {
  const TopoDS_Face good_face = test::figure2_ruled_surface();
  const TopoDS_Shape s = test::compound({good_face, degenerate_face(40)});
  for (IsoPattern pattern : {IsoPattern::Adaptive, IsoPattern::ParallelPlanes,
                             IsoPattern::ConstantScallop, IsoPattern::Uniform}) {
    IsoParams p = good();
    p.pattern = pattern;
    const IsoResult both = adaptive_isocurve(s, {0, 1}, p);
    const IsoResult alone = adaptive_isocurve(s, {0}, p);
    const int pi = static_cast<int>(pattern);
    EXPECT_EQ(both.skipped_faces, std::vector<int>{1}) << pi;
    EXPECT_TRUE(alone.skipped_faces.empty()) << pi;
    const std::vector<std::string> w = naming(both, "Face2");
    ASSERT_EQ(w.size(), 1u) << pi;
    EXPECT_NE(w[0].find("degenerate"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("skipped"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("not protected"), std::string::npos) << w[0];
    EXPECT_TRUE(naming(both, "Face1").empty()) << pi;
    ASSERT_GT(both.path.size(), 2u) << pi;
    EXPECT_TRUE(test::same_path(both.path, alone.path)) << pi;
    EXPECT_EQ(both.metrics.cutting_length, alone.metrics.cutting_length) << pi;
    EXPECT_EQ(both.metrics.lower_bound_length, alone.metrics.lower_bound_length) << pi;
    EXPECT_EQ(both.face_direction.size(), 2u) << pi;
    EXPECT_EQ(both.face_direction[1], IsoDirection::Auto) << pi;
    if (pattern != IsoPattern::Adaptive) continue;
    // Definition 1 on an independent sampling of the good face.
    const double delta = both.metrics.delta;
    test::SegmentIndex contacts(delta);
    for (const auto& curve : test::contact_curves(good_face, 0, both, delta / 20))
      contacts.add_polyline(curve);
    EXPECT_LT(test::coverage_gap(good_face, contacts, 100, 2 * delta), both.metrics.delta_max);
  }
}

// A face whose planning trips a guard (Algorithm 1 needs more levels than
// max_depth on the long ruled surface, not on a small flat square) is
// skipped with the guard's message; it stays in the clearance model, and
// the square is finished as if picked alone.
TEST(BadInput, GuardTrippedOnOneFaceSkipsIt) {
  TColgp_Array2OfPnt poles(1, 2, 1, 2);
  for (int i = 1; i <= 2; ++i)
    for (int j = 1; j <= 2; ++j) poles(i, j) = gp_Pnt(-60.0 + 10.0 * i, 10.0 * j, 0);
  const TopoDS_Face square = BRepBuilderAPI_MakeFace(new Geom_BezierSurface(poles), 1e-7).Face();
  const TopoDS_Shape s = test::compound({test::figure2_ruled_surface(), square});
  IsoParams p = good();
  p.max_depth = 5;
  const IsoResult both = adaptive_isocurve(s, {0, 1}, p);
  const IsoResult alone = adaptive_isocurve(s, {1}, p);
  EXPECT_EQ(both.skipped_faces, std::vector<int>{0});
  const std::vector<std::string> w = naming(both, "Face1");
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("max_depth"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("skipped"), std::string::npos) << w[0];
  EXPECT_EQ(w[0].find("not protected"), std::string::npos) << w[0];
  ASSERT_GT(both.path.size(), 2u);
  EXPECT_EQ(both.path.z, alone.path.z);
  EXPECT_EQ(both.curves.size(), alone.curves.size());
  for (const SubIsocurve& c : both.curves) EXPECT_EQ(c.face, 1);
}

// Every picked face failing is still an error, naming each face.
TEST(BadInput, EveryPickedFaceDegenerateIsAnError) {
  const TopoDS_Shape s = test::compound({degenerate_face(40), degenerate_face(60)});
  for (IsoPattern pattern : {IsoPattern::Adaptive, IsoPattern::ParallelPlanes}) {
    IsoParams p = good();
    p.pattern = pattern;
    try {
      adaptive_isocurve(s, {0, 1}, p);
      ADD_FAILURE() << "no exception";
    } catch (const GeometryError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("no picked face could be finished"), std::string::npos) << m;
      EXPECT_NE(m.find("Face1"), std::string::npos) << m;
      EXPECT_NE(m.find("Face2"), std::string::npos) << m;
    }
  }
}

TEST(BadInput, SafeHeightBelowThePath) {
  IsoParams p = good();
  p.safe_z = 0.0;  // the surface rises to 15 mm
  expect_error<InvalidArgument>([&] { adaptive_isocurve(test::figure2_ruled_surface(), {0}, p); },
                                "safe_z");
}

TEST(BadInput, RecursionGuardEndsInAnError) {
  IsoParams p = good();
  p.max_depth = 2;
  expect_error<GeometryError>([&] { adaptive_isocurve(test::load("MAT.brep"), {0}, p); },
                              "max_depth");
}

}  // namespace
}  // namespace isocam
