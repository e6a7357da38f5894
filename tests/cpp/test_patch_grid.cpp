// The patch grid's evaluation (PatchGrid::eval, d1, d2) against
// OpenCASCADE's own (Geom_Surface::D2) on surfaces whose grid parameters are the face's:
// MAT's bicubic B-spline, a rational B-spline (a sphere's NURBS form) and
// Bezier surfaces of degree 5 x 4 and 12 x 11 (each size of buffer the
// evaluation chooses by degree), over the whole parameter range, span
// breaks included.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRep_Tool.hxx>
#include <GeomConvert.hxx>
#include <Geom_BSplineSurface.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_RectangularTrimmedSurface.hxx>
#include <Geom_SphericalSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS.hxx>
#include <cmath>
#include <random>

#include "geometry/patch_grid.h"
#include "support/models.h"

namespace isocam {
namespace {

// Compares value, first and second derivatives at a 23 x 19 lattice over the range
// and at 400 random points, relative to the surface's size.
void expect_matches_occt(const TopoDS_Face& face, const char* name) {
  const PatchGrid g = PatchGrid::from_face(face, 0);
  ASSERT_TRUE(g.same_params_as_face()) << name;
  const Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  const double tol = 1e-10 * g.size();
  int checked = 0;
  auto check = [&](double u, double v) {
    gp_Pnt p;
    gp_Vec su, sv, suu, svv, suv;
    s->D2(u, v, p, su, sv, suu, svv, suv);
    const gp_Pnt q = g.eval(u, v);
    const SurfaceDerivs d = g.d1(u, v);
    const SurfaceDerivs2 d2 = g.d2(u, v);
    EXPECT_LE(q.Distance(p), tol) << name << " eval at " << u << ", " << v;
    EXPECT_LE(d.p.Distance(p), tol) << name << " d1 at " << u << ", " << v;
    // Derivatives scale with the size over the parameter range.
    const double dtol = 1e-9 * (1.0 + su.Magnitude() + sv.Magnitude());
    EXPECT_LE((d.su - su).Magnitude(), dtol) << name << " su at " << u << ", " << v;
    EXPECT_LE((d.sv - sv).Magnitude(), dtol) << name << " sv at " << u << ", " << v;
    // d2's point and first derivatives are d1's.
    EXPECT_LE(d2.p.Distance(d.p), tol) << name << " d2 at " << u << ", " << v;
    EXPECT_LE((d2.su - d.su).Magnitude(), dtol) << name << " d2 su at " << u << ", " << v;
    EXPECT_LE((d2.sv - d.sv).Magnitude(), dtol) << name << " d2 sv at " << u << ", " << v;
    const double d2tol = 1e-8 * (1.0 + suu.Magnitude() + suv.Magnitude() + svv.Magnitude());
    EXPECT_LE((d2.suu - suu).Magnitude(), d2tol) << name << " suu at " << u << ", " << v;
    EXPECT_LE((d2.suv - suv).Magnitude(), d2tol) << name << " suv at " << u << ", " << v;
    EXPECT_LE((d2.svv - svv).Magnitude(), d2tol) << name << " svv at " << u << ", " << v;
    ++checked;
  };
  for (int a = 0; a <= 22; ++a)
    for (int b = 0; b <= 18; ++b)
      check(g.umin() + (g.umax() - g.umin()) * a / 22.0,
            g.vmin() + (g.vmax() - g.vmin()) * b / 18.0);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(g.umin(), g.umax()), V(g.vmin(), g.vmax());
  for (int k = 0; k < 400; ++k) check(U(rng), V(rng));
  EXPECT_EQ(checked, 23 * 19 + 400);
}

TopoDS_Face bezier_face(int nu, int nv) {
  TColgp_Array2OfPnt poles(1, nu + 1, 1, nv + 1);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> z(-5.0, 5.0);
  for (int i = 1; i <= nu + 1; ++i)
    for (int j = 1; j <= nv + 1; ++j) poles(i, j) = gp_Pnt(10.0 * i, 8.0 * j, z(rng));
  Handle(Geom_BezierSurface) s = new Geom_BezierSurface(poles);
  return BRepBuilderAPI_MakeFace(s, 1e-7).Face();
}

TEST(PatchGrid, BicubicBsplineMatchesOcct) {
  expect_matches_occt(test::face(test::load("MAT.brep"), 0), "MAT");
}

TEST(PatchGrid, RationalBsplineMatchesOcct) {
  Handle(Geom_SphericalSurface) sphere = new Geom_SphericalSurface(gp_Ax3(), 20.0);
  Handle(Geom_RectangularTrimmedSurface) part =
      new Geom_RectangularTrimmedSurface(sphere, 0.2, 2.9, -1.2, 1.1);
  Handle(Geom_BSplineSurface) nurbs = GeomConvert::SurfaceToBSplineSurface(part);
  ASSERT_TRUE(nurbs->IsURational() || nurbs->IsVRational());
  const TopoDS_Face face = BRepBuilderAPI_MakeFace(nurbs, 1e-7).Face();
  expect_matches_occt(face, "sphere NURBS");
}

TEST(PatchGrid, HigherDegreesMatchOcct) {
  expect_matches_occt(bezier_face(5, 4), "Bezier 5 x 4");
  expect_matches_occt(bezier_face(12, 11), "Bezier 12 x 11");
}

}  // namespace
}  // namespace isocam
