#include "support/models.h"

#include <BRepAdaptor_Surface.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRep_Builder.hxx>
#include <Bnd_Box.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <Standard_Failure.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TopoDS_Compound.hxx>
#include <cmath>
#include <gp_Trsf.hxx>
#include <stdexcept>

#include "isocam/brep_io.h"

namespace isocam::test {

std::string data_path(const std::string& name) {
  return std::string(ISOCAM_TEST_DATA) + "/" + name;
}

TopoDS_Shape load(const std::string& name) { return read_brep_file(data_path(name)); }

TopoDS_Face face(const TopoDS_Shape& shape, int index) {
  return faces_of(shape).at(static_cast<std::size_t>(index));
}

TopoDS_Face figure2_ruled_surface(bool creased) {
  // u: 10 poles of a cubic with interior knots of multiplicity 3 (three
  // Bezier spans); v: linear between the two rails.
  const double xs[10] = {0, 33, 67, 100, 133, 167, 200, 233, 267, 300};
  // Smooth: poles 2-3-4 and 5-6-7 collinear and equally spaced (C1 joints).
  const double smooth[10] = {100, 100, 16, 10, 4, 4, 10, 16, 100, 100};
  const double crease[10] = {100, 100, 30, 10, 10, 10, 10, 30, 100, 100};
  const double* width = creased ? crease : smooth;
  TColgp_Array2OfPnt poles(1, 10, 1, 2);
  for (int i = 0; i < 10; ++i) {
    poles(i + 1, 1) = gp_Pnt(xs[i], 0, 0);
    // The far rail is raised, so the surface twists where the width changes.
    poles(i + 1, 2) = gp_Pnt(xs[i], width[i], creased ? 10.0 + 5.0 * ((i % 3) == 1) : 5.0);
  }
  TColStd_Array1OfReal uk(1, 4), vk(1, 2);
  TColStd_Array1OfInteger um(1, 4), vm(1, 2);
  uk(1) = 0;
  uk(2) = 1;
  uk(3) = 2;
  uk(4) = 3;
  um(1) = 4;
  um(2) = 3;
  um(3) = 3;
  um(4) = 4;
  vk(1) = 0;
  vk(2) = 1;
  vm(1) = 2;
  vm(2) = 2;
  Handle(Geom_BSplineSurface) s = new Geom_BSplineSurface(poles, uk, vk, um, vm, 3, 1);
  return BRepBuilderAPI_MakeFace(s, 1e-7).Face();
}

TopoDS_Face smooth_hill() {
  // z = a smooth bump plus a gentle wave, interpolated by a B-spline
  // surface through 13 x 13 points.
  const int n = 13;
  TColgp_Array2OfPnt pts(1, n, 1, n);
  for (int i = 1; i <= n; ++i)
    for (int j = 1; j <= n; ++j) {
      const double x = 150.0 * (i - 1) / (n - 1), y = 150.0 * (j - 1) / (n - 1);
      const double bump =
          25.0 * std::exp(-((x - 75) * (x - 75) + (y - 75) * (y - 75)) / (2 * 45.0 * 45.0));
      pts(i, j) = gp_Pnt(x, y, bump + 3.0 * std::sin(x / 25.0) * std::cos(y / 30.0));
    }
  GeomAPI_PointsToBSplineSurface fit(pts, 3, 3, GeomAbs_C2, 1e-3);
  return BRepBuilderAPI_MakeFace(fit.Surface(), 1e-7).Face();
}

TopoDS_Shape house_on_the_hill() {
  const TopoDS_Shape hill = BRepPrimAPI_MakePrism(smooth_hill(), gp_Vec(0, 0, -30)).Shape();
  // The house: walls from below the ground to z = 45 on the slope, and a
  // gable roof (a triangular prism) on them.
  const TopoDS_Shape walls = BRepPrimAPI_MakeBox(gp_Pnt(85, 55, 0), 40, 30, 45).Shape();
  BRepBuilderAPI_MakePolygon gable(gp_Pnt(85, 55, 45), gp_Pnt(85, 85, 45), gp_Pnt(85, 70, 58),
                                   true);
  const TopoDS_Face gable_face = BRepBuilderAPI_MakeFace(gable.Wire(), true).Face();
  const TopoDS_Shape roof = BRepPrimAPI_MakePrism(gable_face, gp_Vec(40, 0, 0)).Shape();
  BRepAlgoAPI_Fuse house(walls, roof);
  BRepAlgoAPI_Fuse fused(hill, house.Shape());
  if (!fused.IsDone()) throw std::runtime_error("house_on_the_hill: the fuse failed");
  ShapeUpgrade_UnifySameDomain unify(fused.Shape(), true, true, true);
  unify.Build();
  return unify.Shape();
}

std::vector<int> house_on_the_hill_picked(const TopoDS_Shape& shape) {
  std::vector<int> picked;
  const auto faces = faces_of(shape);
  for (std::size_t i = 0; i < faces.size(); ++i) {
    Bnd_Box b;
    BRepBndLib::Add(faces[i], b);
    double x0, y0, z0, x1, y1, z1;
    b.Get(x0, y0, z0, x1, y1, z1);
    // Not the block's bottom (below the ground everywhere) nor its four
    // sides (x or y at the block's edge along their whole extent).
    const bool bottom = z1 < 0.0;
    const bool side = (x1 - x0 < 1e-3 && (x0 < 1e-3 || x0 > 150 - 1e-3)) ||
                      (y1 - y0 < 1e-3 && (y0 < 1e-3 || y0 > 150 - 1e-3));
    if (!bottom && !side) picked.push_back(static_cast<int>(i));
  }
  return picked;
}

TopoDS_Shape scaled(const TopoDS_Shape& shape, double factor) {
  gp_Trsf t;
  t.SetScale(gp_Pnt(0, 0, 0), factor);
  return BRepBuilderAPI_Transform(shape, t, true).Shape();
}

TopoDS_Shape compound(const std::vector<TopoDS_Shape>& shapes) {
  BRep_Builder b;
  TopoDS_Compound c;
  b.MakeCompound(c);
  for (const TopoDS_Shape& s : shapes) b.Add(c, s);
  return c;
}

}  // namespace isocam::test
