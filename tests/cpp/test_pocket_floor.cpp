// Sculptured pocket floors with a ball-end tool (Suh & Lee sections 2.3,
// eq. 11-18, and the case study of section 3).
//
// The case study is rebuilt in code (support/pocket_models.h): a pocket of
// about 200 x 200 mm with twelve boundary curves, an island of eight
// curves, a smooth convex cubic Bezier floor; tool radius 6, epsilon =
// delta = 0.5, cusp height 0.4. The paper reports 633 CL points; we print
// ours next to it and measure the scallop on the floor (the lowest point of
// the swept ball minus the floor, on a 1 mm grid over the area the ball can
// reach).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "isocam/pocket_check.h"
#include "isocam/pocketing.h"
#include "pocketing/floor_path.h"
#include "pocketing/pocket_emit.h"
#include "support/floor_checks.h"
#include "support/pocket_models.h"

namespace isocam {
namespace {

struct FloorRun {
  Toolpath path;
  PocketMetrics metrics;
  test::FloorMeasure floor;
  CoverageReport plan;
};

// Runs the floor pass over the case study with the given tolerances.
FloorRun case_study(double eps, double delta, double cusp) {
  const double R = 6.0;
  const std::vector<Loop> region = face_region(test::case_study_outline(), 0.01);
  PocketParams p;
  p.tool_radius = R;
  p.tolerance = eps;
  p.floor_tolerance = delta;
  p.scallop_height = cusp;
  p.safe_z = 60;
  FloorRun run;
  pocket::sculptured_floor_pass({test::case_study_floor()}, region, p, run.path, run.metrics, {});
  pocket::measure_path(run.path, run.metrics);
  // The scallop where a ball can rest: the region shrunk by R.
  const std::vector<Loop> reach = offset_region(region, R);
  run.floor = test::measure_floor(run.path, R, reach, test::case_study_floor_z, 1.0);
  // Plan view: every reachable point under a ball's centre track, with the
  // feed moves flattened (the rapids lifted off the plane).
  Toolpath flat;
  for (std::size_t i = 0; i < run.path.size(); ++i) {
    if (run.path.kind[i] == static_cast<std::uint8_t>(MoveKind::Feed)) {
      flat.add(MoveKind::Feed, run.path.x[i], run.path.y[i], 0.0);
    } else {
      flat.add(MoveKind::Rapid, run.path.x[i], run.path.y[i], 1.0);
      flat.add(MoveKind::Plunge, run.path.x[i], run.path.y[i], 0.0);
    }
  }
  CoverageParams cp;
  cp.tool_radius = R;
  cp.cell = 0.25;
  cp.tolerance = eps + 0.01;
  run.plan = pocket_coverage(region, flat, cp);
  std::cout << "    epsilon " << eps << ", delta " << delta << ", cusp " << cusp << ": CL points "
            << run.metrics.cl_points << " (paper: 633), loops " << run.metrics.loops
            << ", interval " << run.metrics.min_interval << "-" << run.metrics.max_interval
            << " mm, retracts " << run.metrics.retracts << ", feed links " << run.metrics.feed_links
            << "\n"
            << "    floor: scallop max " << run.floor.max_scallop << " (99% "
            << run.floor.p99_scallop << ", mean " << run.floor.mean_scallop << "), gouge max "
            << run.floor.max_gouge << " mm over " << run.floor.samples
            << " points; plan uncut reachable " << run.plan.uncut_reachable_area << " mm2\n";
  return run;
}

TEST(PocketFloor, PaperCaseStudy) {
  const FloorRun run = case_study(0.5, 0.5, 0.4);
  EXPECT_GT(run.metrics.cl_points, 100);
  EXPECT_EQ(run.floor.uncovered, 0);
  EXPECT_EQ(run.plan.uncut_reachable_area, 0.0);
  // The interval keeps the cusp under 0.4; the straight moves between CL
  // points may leave or take up to delta more (the paper's floor deviation).
  EXPECT_LE(run.floor.max_scallop, 0.4 + 0.5);
  EXPECT_LE(run.floor.max_gouge, 0.5 + 0.02);
  // Eq. 18 projects the interval on the plan: a little under the flat
  // stepover where the floor slopes; it is reduced (never below half of
  // it) where a wider one would leave a higher cusp in a corner.
  const double flat = 2 * std::sqrt(2 * 6 * 0.4 - 0.4 * 0.4);
  EXPECT_GT(run.metrics.max_interval, 0.95 * flat);
  EXPECT_GT(run.metrics.min_interval, 0.45 * flat);
}

TEST(PocketFloor, TightTolerancesKeepTheScallop) {
  // With epsilon = delta = 0.01 what is left is the scallop of the path
  // interval alone (eq. 11-18): under the requested height, and no gouge
  // beyond the CL deviation and the floor mesh's accuracy.
  const FloorRun run = case_study(0.01, 0.01, 0.4);
  EXPECT_EQ(run.plan.uncut_reachable_area, 0.0);
  EXPECT_LE(run.floor.max_scallop, 0.4 + 0.02);
  EXPECT_GT(run.floor.max_scallop, 0.3);  // the interval is not wastefully small
  EXPECT_LE(run.floor.max_gouge, 0.02);
}

TEST(PocketFloor, PocketFacesDispatchesASculpturedFloor) {
  // pocket_faces on the untrimmed floor patch: flat levels above it are
  // skipped (no solid), the ball follows the floor; a flat tool is refused.
  FacePocketParams fp;
  fp.pocket.tool_radius = 6;
  fp.pocket.stepover = 6;
  fp.pocket.tolerance = 0.1;
  fp.pocket.floor_tolerance = 0.1;
  fp.pocket.scallop_height = 0.5;
  fp.pocket.safe_z = 60;
  fp.depths = {10, 0};  // both below the floor's top: no flat level
  fp.ball_end = true;
  const PocketResult res = pocket_faces(test::case_study_floor(), {0}, fp);
  EXPECT_TRUE(res.warnings.empty());
  EXPECT_EQ(res.metrics.levels, 1);
  EXPECT_GT(res.metrics.cl_points, 50);
  fp.ball_end = false;
  const PocketResult flat = pocket_faces(test::case_study_floor(), {0}, fp);
  ASSERT_EQ(flat.warnings.size(), 1u);
  EXPECT_NE(flat.warnings[0].find("ball-end"), std::string::npos);
  EXPECT_EQ(flat.path.size(), 0u);
}

}  // namespace
}  // namespace isocam
