// Bad input raises the documented error, naming the argument or the face.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepTools.hxx>
#include <Geom_BezierSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <sstream>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "support/models.h"

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
