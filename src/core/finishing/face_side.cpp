#include "finishing/face_side.h"

#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>

namespace isocam {

bool is_open_face(const TopoDS_Shape& shape, const TopoDS_Face& face) {
  TopTools_IndexedDataMapOfShapeListOfShape solids;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SOLID, solids);
  const int k = solids.FindIndex(face);
  return !(k > 0 && !solids(k).IsEmpty());
}

bool normal_points_down(const PatchGrid& grid) {
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

FaceSides open_face_sides(const PatchGrid& grid, const TrimDomain& trim,
                          const ClearanceModel& model, double r, double clearance) {
  constexpr int kSamples = 16;
  bool as_oriented = false, reversed = false;
  for (int a = 0; a < kSamples && !(as_oriented && reversed); ++a)
    for (int b = 0; b < kSamples && !(as_oriented && reversed); ++b) {
      const double u = grid.umin() + (grid.umax() - grid.umin()) * (a + 0.5) / kSamples;
      const double v = grid.vmin() + (grid.vmax() - grid.vmin()) * (b + 0.5) / kSamples;
      if (!trim.contains(u, v)) continue;
      const SurfaceDerivs d = grid.d1(u, v);
      const gp_Vec n = grid.normal(u, v, &d) * r;
      if (!as_oriented) as_oriented = model.clear_above(d.p.Translated(n), clearance);
      if (!reversed) reversed = model.clear_above(d.p.Translated(-n), clearance);
    }
  if (as_oriented && reversed) return FaceSides::Both;
  if (as_oriented) return FaceSides::AsOriented;
  if (reversed) return FaceSides::Reversed;
  return normal_points_down(grid) ? FaceSides::Reversed : FaceSides::AsOriented;
}

}  // namespace isocam
