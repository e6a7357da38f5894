// The trimmed domain of a face (its wires in UV, holes included), queried
// along iso-lines of the face's PatchGrid: Elber & Cohen compute isocurves on
// the untrimmed surface and trim them afterwards (section 3); this is that
// trim, exact up to OpenCASCADE's 2D intersection tolerance, done with
// OpenCASCADE's 2D hatcher on the edges' p-curves.
#pragma once

#include <memory>
#include <vector>

#include <TopoDS_Face.hxx>

#include "geometry/bernstein.h"
#include "geometry/patch_grid.h"

class Geom2dHatch_Hatcher;

namespace isocam {

class TrimDomain {
 public:
  // `grid` is the face's grid in its own orientation (not transposed).
  TrimDomain(const TopoDS_Face& face, const PatchGrid& grid, int face_label);
  ~TrimDomain();
  TrimDomain(TrimDomain&&) noexcept;
  TrimDomain& operator=(TrimDomain&&) noexcept;

  // The parts of [t0, t1] inside the face along the iso-line of the grid at
  // `level`: for an iso-v line (`iso_v` true) v = level and t runs along u;
  // otherwise u = level and t runs along v. Grid parameters in and out.
  std::vector<Interval> inside(bool iso_v, double level, double t0, double t1) const;

  // True if the grid point (u, v) is inside the face or on its boundary.
  bool contains(double u, double v) const;

 private:
  // Grid parameter -> face parameter, per direction (0: u, 1: v).
  double to_face(int dir, double g) const;
  double to_grid(int dir, double f) const;

  TopoDS_Face face_;
  const PatchGrid* grid_;
  int label_;
  double fmin_[2], fmax_[2];  // the face's parameter bounds
  std::unique_ptr<Geom2dHatch_Hatcher> hatcher_;
};

}  // namespace isocam
