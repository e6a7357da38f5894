#include "finishing/face_side.h"

#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>

namespace isocam {

bool open_face_turned_down(const TopoDS_Shape& shape, const TopoDS_Face& face,
                           const PatchGrid& grid) {
  TopTools_IndexedDataMapOfShapeListOfShape solids;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SOLID, solids);
  const int k = solids.FindIndex(face);
  if (k > 0 && !solids(k).IsEmpty()) return false;
  double up = 0.0;
  for (int a = 0; a <= 8; ++a)
    for (int b = 0; b <= 8; ++b) {
      const double u = grid.umin() + (grid.umax() - grid.umin()) * (0.05 + 0.1125 * a);
      const double v = grid.vmin() + (grid.vmax() - grid.vmin()) * (0.05 + 0.1125 * b);
      const SurfaceDerivs d = grid.d1(u, v);
      up += grid.normal(u, v, &d).Z() * d.su.Crossed(d.sv).Magnitude();
    }
  return up < 0.0;
}

}  // namespace isocam
