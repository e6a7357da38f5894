// Checks of a pocketing path against its region, independent of how the
// path was made (used by the tests and to compare with FreeCAD's own
// operations in the benchmark). ENGINEERING.md habit 9: the invariants are
// that no tool centre comes closer than r to a wall or island, and that
// every point a tool of radius r can reach is cut.
#pragma once

#include <vector>

#include "isocam/profile2d.h"
#include "isocam/toolpath.h"

namespace isocam {

struct CoverageParams {
  double tool_radius = 3.0;  // r, > 0
  double cell = 0.1;         // raster cell (mm), > 0
  double tolerance = 1e-3;   // a cell centre within r + tolerance of a move is cut
  double z_floor = 0.0;      // only moves at this height (within z_tolerance) cut the floor
  double z_tolerance = 1e-6;
};

// On a raster of cell centres inside the region:
//   uncut: not within r (+ tolerance) of any move at the floor height;
//   reachable: within r of a cell centre that is a valid tool centre (at
//     least r from every wall and island, exact distances), so a tool could
//     cut it (conservative: misses at most a sliver of one cell next to
//     the walls, never counts an unreachable point);
//   unreachable: not reachable (corners narrower than the tool).
// Areas are cell counts times cell^2.
struct CoverageReport {
  double region_area = 0.0;
  double uncut_area = 0.0;
  double uncut_reachable_area = 0.0;  // the invariant: 0
  double unreachable_area = 0.0;
  double worst_x = 0.0, worst_y = 0.0;  // an uncut reachable cell (if any)
  long cells = 0;
};
CoverageReport pocket_coverage(const std::vector<Loop>& region, const Toolpath& path,
                               const CoverageParams& params);

// Tool-centre clearance of the moves at the floor height (cutting moves and
// links), sampled every `step` mm along each move.
struct ClearanceReport {
  double min_distance = 0.0;  // to the region's loops
  long samples = 0;
  long outside = 0;  // samples outside the region
  double worst_x = 0.0, worst_y = 0.0;
};
ClearanceReport pocket_clearance(const std::vector<Loop>& region, const Toolpath& path,
                                 double z_floor, double step, double z_tolerance = 1e-6);

}  // namespace isocam
