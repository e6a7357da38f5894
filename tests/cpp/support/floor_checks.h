// Measuring what a ball-end path leaves on a floor z = f(x, y): at each
// sample point, the lowest point of the ball swept along the feed moves
// (spheres at the ends, cylinders between) minus the floor's height. A
// positive value is material left (the scallop), a negative one a gouge.
#pragma once

#include <functional>
#include <vector>

#include "isocam/pocketing.h"

namespace isocam::test {

struct FloorMeasure {
  double max_scallop = 0.0;  // largest material left
  double p99_scallop = 0.0;  // 99th percentile
  double mean_scallop = 0.0;
  double max_gouge = 0.0;  // largest depth below the floor (>= 0)
  long samples = 0;
  long uncovered = 0;  // samples no ball passes over
};

// Samples (x, y) on a grid of `step` over the floor points a ball can
// touch: those whose ball centre, (x, y) + R n(x, y) in plan, lies inside
// `centres` (the region shrunk by R; n from the floor's gradient).
FloorMeasure measure_floor(const Toolpath& path, double ball_radius,
                           const std::vector<Loop>& centres,
                           const std::function<double(double, double)>& floor_z, double step);

}  // namespace isocam::test
