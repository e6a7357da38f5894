// Which side of a face the ball is on (issue 15).
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include "geometry/patch_grid.h"

namespace isocam {

// True for an open face of `shape` (one that bounds no solid of it) whose
// away-from-material normal points down on average (weighted by area,
// sampled 9 x 9): its orientation puts the ball under it, where a 3-axis
// tool coming from above cannot be. A face of a solid is never reported
// (the material is inside the solid).
bool open_face_turned_down(const TopoDS_Shape& shape, const TopoDS_Face& face,
                           const PatchGrid& grid);

}  // namespace isocam
