#include "support/models.h"

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <gp_Trsf.hxx>

#include "isocam/brep_io.h"

namespace isocam::test {

std::string data_path(const std::string& name) { return std::string(ISOCAM_TEST_DATA) + "/" + name; }

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
  uk(1) = 0; uk(2) = 1; uk(3) = 2; uk(4) = 3;
  um(1) = 4; um(2) = 3; um(3) = 3; um(4) = 4;
  vk(1) = 0; vk(2) = 1;
  vm(1) = 2; vm(2) = 2;
  Handle(Geom_BSplineSurface) s = new Geom_BSplineSurface(poles, uk, vk, um, vm, 3, 1);
  return BRepBuilderAPI_MakeFace(s, 1e-7).Face();
}

TopoDS_Shape scaled(const TopoDS_Shape& shape, double factor) {
  gp_Trsf t;
  t.SetScale(gp_Pnt(0, 0, 0), factor);
  return BRepBuilderAPI_Transform(shape, t, true).Shape();
}

}  // namespace isocam::test
