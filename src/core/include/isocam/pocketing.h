// Island-aware spiral pocketing and z-level roughing.
// Y.S. Suh, K. Lee, "NC Tool Path Generation of Arbitrarily Shaped
// Pockets", sections 2 to 2.3.
//
// Contract (flat floor): the tool centre runs on the boundaries of the
// region shrunk by the tool radius r, then by the path interval step after
// step (profile2d.h: exact line/arc offsets; self-loops, lakes, merged
// islands and splits resolved by winding numbers). It never comes closer
// than r to a wall or an island, minus the approximation tolerance of free
// curves; every point of the region within reach of a tool of radius r is
// within r of a cutting move (the interval is reduced where a larger one
// would leave material, see offset_tree.cpp). Loops are cut deepest first,
// climbing the offset tree (section 2.3), joined by short feed links inside
// the cut area wherever possible and by a retract elsewhere. Circular arcs
// of the profile come out as G2/G3 arcs.
//
// Sculptured floor (ball-end tool): the same plan-view loops, the first at r
// from the walls, then at the interval that keeps the scallop under
// `scallop_height` from the floor's normal curvature across the loop
// (eq. 11-18, the smallest along the loop; reduced where a wider one would
// leave a higher cusp in a corner or in the middle of the last loops, so
// every floor point is within half an interval of a pass); the tool tip z
// is that of the ball resting on the floor (its ball-end offset, no gouge),
// sampled with the plan-view deviation `tolerance` (epsilon) and the floor
// deviation `floor_tolerance` (delta), so flat stretches take few points.
#pragma once

#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

#include "isocam/profile2d.h"
#include "isocam/progress.h"
#include "isocam/toolpath.h"
#include "isocam/work_budget.h"

namespace isocam {

enum class CutDirection {
  Climb,         // material on the right of the travel (spindle M3)
  Conventional,  // the reverse
};

struct PocketParams {
  double tool_radius = 3.0;       // mm, > 0
  double stepover = 3.0;          // mm, path interval on a flat floor, 0 < s <= 2 r
  double tolerance = 0.01;        // mm: free curves to arcs; plan-view deviation epsilon
  double floor_tolerance = 0.01;  // mm: floor deviation delta of CL points (sculptured)
  double scallop_height = 0.01;   // mm: sculptured floor, 0 < h < r
  CutDirection direction = CutDirection::Climb;
  double safe_z = 10.0;         // tool-tip z for retracts
  double min_arc_chord = 0.05;  // mm: arcs with a shorter chord are output as G1
  // The work budget: a job whose estimated number of moves (the region's
  // area / stepover, at the region's own segments per length, times the
  // levels) exceeds it is refused before the work; the offset tree and the
  // path are held to it while they grow (isocam/work_budget.h).
  double max_moves = kDefaultMaxMoves;
};

struct PocketMetrics {
  double cutting_length = 0.0;  // feed and arc moves, links included (mm)
  double rapid_length = 0.0;
  double plunge_length = 0.0;
  int retracts = 0;           // lifts straight up (measure(), isocam/toolpath.h)
  int feed_links = 0;         // loop-to-loop links cut without a retract
  int loops = 0;              // profiles cut (all levels)
  int levels = 0;             // z levels
  int tree_depth = 0;         // deepest offset step (section 2.3's tree)
  int arcs = 0;               // G2/G3 moves
  int cl_points = 0;          // cutting move end points (the paper's CL data)
  double min_interval = 0.0;  // smallest / largest path interval used (mm)
  double max_interval = 0.0;
  int reduced_intervals = 0;  // steps reduced so that no material is left
  int warnings = 0;           // faces skipped (the reasons are in PocketResult::warnings)
};

// The path has G2/G3 arcs (MoveKind::ArcCW/ArcCCW, centres in path.cx/cy)
// where the profile has circular arcs; rapids, feeds and plunges otherwise.
// Warnings as the finishing results give them (IsoResult, FiveAxisResult):
// one message per face skipped, naming it and the reason.
struct PocketResult {
  Toolpath path;
  PocketMetrics metrics;
  std::vector<std::string> warnings;
};

// A region from an outer profile and islands given in any orientation.
std::vector<Loop> make_region(const Loop& boundary, const std::vector<Loop>& islands);

// Flat floor: pocket the region (loops, region on the left: outer profile
// counter-clockwise, islands clockwise; any overlap is resolved) at each z
// of `depths` (top to bottom). Throws InvalidArgument for bad parameters,
// Cancelled on cancel.
PocketResult spiral_pocket(const std::vector<Loop>& region, const std::vector<double>& depths,
                           const PocketParams& params, Progress* progress = nullptr);

/** @name From the B-rep */
///@{
// The floor face's outline projected on XY: the outer wire as a
// counter-clockwise profile, inner wires as islands. Lines and circles in a
// horizontal plane are kept exact; other curves (ellipses, B-splines, tilted
// circles ...) become arcs within `tolerance` of their projection.
std::vector<Loop> face_region(const TopoDS_Shape& face, double tolerance);

// The material of the solids of `model` at height z, as a region.
std::vector<Loop> section_region(const TopoDS_Shape& model, double z, double tolerance);

struct FacePocketParams {
  PocketParams pocket;
  std::vector<double> depths;  // step-down levels, top to bottom (the last is FinalDepth)
  bool ball_end = false;       // the tool is a ball end (required by a non-planar floor)
};

// Pocket the picked floor faces of `shape` (0-based FreeCAD FaceN-1
// indices). Islands: the floor's inner wires and the material of the
// shape's solids above each level inside the outline (as FreeCAD's Pocket
// Shape). A planar horizontal floor is cut at every level down to it; a
// sculptured floor is cut at the levels above it and then followed by the
// ball (ball_end required). A face that cannot be pocketed (too small for
// the tool, vertical) is reported in `warnings` and skipped.
PocketResult pocket_faces(const TopoDS_Shape& shape, const std::vector<int>& faces,
                          const FacePocketParams& params, Progress* progress = nullptr);

struct RoughingParams {
  PocketParams pocket;
  std::vector<double> depths;   // z levels, top to bottom
  double stock_to_leave = 0.5;  // mm, >= 0: left on the model (sides and floors)
};

// Z-level roughing (Elber & Cohen section 4, Figure 4): at every level the
// region between the stock's outline and the model's manufacturing offset
// (the material of the model at and above the level, grown by the tool
// radius plus stock_to_leave) is cleared with the spiral pocketing engine.
PocketResult zlevel_roughing(const TopoDS_Shape& model, const TopoDS_Shape& stock,
                             const RoughingParams& params, Progress* progress = nullptr);
///@}

}  // namespace isocam
