// Invariant checks of pocketing paths (ENGINEERING.md habit 9), on top of
// the core's raster coverage and clearance (isocam/pocket_check.h):
// G2/G3 exactness, and a one-line report of a case.
#pragma once

#include <string>
#include <vector>

#include "isocam/pocket_check.h"
#include "isocam/pocketing.h"

namespace isocam::test {

// Every G2/G3 of the path at height z: its start and end are at the same
// distance from its centre, and every point of the arc, taken
// in its direction, is at the same distance from the region's loops as its
// ends (within `tol`, e.g. 1e-4 mm: vertices are snapped at 1e-7 of the
// model size): an exact arc of an offset profile, not the
// complementary arc or a wrong radius. Returns the number of bad arcs and
// counts the arcs checked.
int bad_arcs(const std::vector<Loop>& region, const Toolpath& path, double z, double tol,
             int& checked);

struct CaseReport {
  PocketResult result;
  CoverageReport coverage;
  ClearanceReport clearance;
  int arcs_checked = 0, arcs_bad = 0;
  double seconds = 0.0;
  std::string line() const;
};

// Runs spiral_pocket at z = 0 and checks it against `truth` (the true
// region; `engine_region` is what the engine was given).
CaseReport run_case(const std::vector<Loop>& engine_region, const std::vector<Loop>& truth,
                    const PocketParams& p, double cell);

// The 2D area of the corners of a polygon that a tool of radius r cannot
// reach: r^2 (tan(a/2) - a/2) ... summed over convex corners of interior
// angle theta, with a = pi - theta.
double corner_area(double r, const std::vector<double>& interior_angles);

}  // namespace isocam::test
