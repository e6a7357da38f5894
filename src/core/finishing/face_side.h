// Which side of a face the ball is on (issue 15).
#pragma once

#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

#include "geometry/clearance.h"
#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"

namespace isocam {

// True for an open face of `shape`: one that bounds no solid of it, so that
// the material may be on either side (a face of a solid has it inside).
bool is_open_face(const TopoDS_Shape& shape, const TopoDS_Face& face);

// True if the face's away-from-material normal (the grid's) points down on
// average (weighted by area, sampled 9 x 9).
bool normal_points_down(const PatchGrid& grid);

// The sides of an open face that a 3-axis ball-end tool is to finish.
enum class FaceSides {
  AsOriented,  // the side its orientation gives (the grid's normal)
  Reversed,    // the other side only
  Both,        // each side where the tool reaches it
};

// The sides of an open face a vertical tool reaches: on a 16 x 16 sampling
// of the face inside its wires, the ball of radius r touching each side and
// the column above it (ClearanceModel::clear_above() at `clearance`, the
// cutting clearance's query distance) tested. A side with a reachable sample
// is finished (both if both have one: a vertical wall can be reached on one
// side at its foot and on the other at its top); where neither has, the side
// whose normal points up on average. The reach is then decided exactly where
// the passes are cut; the sampling only picks the sides to plan, so a part
// of a side reachable between samples of a side that has none is left (as
// unreachable from above).
FaceSides open_face_sides(const PatchGrid& grid, const TrimDomain& trim,
                          const ClearanceModel& model, double r, double clearance);

}  // namespace isocam
