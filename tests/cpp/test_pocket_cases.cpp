// Spiral pocketing on the cases of the issue, built in code, and on
// tests/data/face.brep. Invariants checked on each:
//   - no tool centre closer than r (minus the tolerance of the free-curve
//     approximation) to a wall or island, none outside the region;
//   - every point of the region that a tool of radius r can reach is cut
//     (raster of 0.1 mm cells): the uncut area is only the corners the tool
//     cannot reach, compared with the exact corner area where known;
//   - every G2/G3 is an exact arc of an offset profile, in its direction.
// Each case prints its numbers (run ctest -V or the test binary).
#include <gtest/gtest.h>

#include <BRepAdaptor_Surface.hxx>
#include <chrono>
#include <cmath>
#include <iostream>

#include "isocam/brep_io.h"
#include "isocam/pocketing.h"
#include "pocketing/pocket_emit.h"
#include "support/expected.h"
#include "support/models.h"
#include "support/pocket_checks.h"
#include "support/pocket_models.h"

namespace isocam {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kCell = 0.1;

PocketParams params(double r, double stepover, double tol = 0.01) {
  PocketParams p;
  p.tool_radius = r;
  p.stepover = stepover;
  p.tolerance = tol;
  p.safe_z = 10;
  return p;
}

// clearance_slack: how much nearer than r a tool centre may come: 1e-9 mm
// (rounding) where the region is exact (lines and arcs), the free-curve
// approximation's tolerance where its profiles approximate B-splines, plus
// 5 % for the truth's own approximation (at tol / 50, truth_of) and rounding.
// corner: the area the tool cannot reach (mm^2), or -1 if not known.
void expect_invariants(const test::CaseReport& rep, double r, double clearance_slack,
                       double corner) {
  std::cout << "    " << rep.line() << "\n";
  EXPECT_GT(rep.result.metrics.loops, 0);
  EXPECT_EQ(rep.clearance.outside, 0)
      << "at " << rep.clearance.worst_x << ", " << rep.clearance.worst_y;
  EXPECT_GE(rep.clearance.min_distance, r - clearance_slack)
      << "at " << rep.clearance.worst_x << ", " << rep.clearance.worst_y;
  EXPECT_EQ(rep.coverage.uncut_reachable_area, 0.0)
      << "uncut reachable cell at " << rep.coverage.worst_x << ", " << rep.coverage.worst_y;
  EXPECT_EQ(rep.arcs_bad, 0);
  if (corner >= 0) {
    // Uncut = the unreachable corners, within the raster's resolution
    // (cells along the corner arcs: about perimeter * cell / 2).
    EXPECT_NEAR(rep.coverage.uncut_area, corner, 0.15 * corner + 0.5)
        << "expected corner area " << corner;
  }
}

// The true region of a face at a fine tolerance (for the checks).
std::vector<Loop> truth_of(const TopoDS_Face& f, double tol) { return face_region(f, tol / 50); }

TEST(PocketCases, IslandsThatMerge) {
  const std::vector<Loop> region{test::rect(0, 0, 120, 80), test::circle(45, 40, 10, false),
                                 test::circle(75, 40, 10, false)};
  const double r = 3;
  const auto plan = pocket::make_flat_plan(region, params(r, 2.4), 1e-6, {});
  // The grown islands are apart at level 0 and one island from level 2 on.
  int holes0 = 0, holes_deep = 0;
  for (const auto& n : plan.tree.nodes) {
    if (n.depth == 0) holes0 = static_cast<int>(n.loops.size()) - 1;
    if (n.depth == 3) holes_deep = static_cast<int>(n.loops.size()) - 1;
  }
  EXPECT_EQ(holes0, 2);
  EXPECT_EQ(holes_deep, 1);
  expect_invariants(test::run_case(region, region, params(r, 2.4), kCell), r, 1e-9,
                    test::corner_area(r, {kPi / 2, kPi / 2, kPi / 2, kPi / 2}));
}

TEST(PocketCases, IslandMeetingTheBoundaryMakesALake) {
  const std::vector<Loop> region{test::rect(0, 0, 100, 60), test::circle(50, 18, 10, false)};
  const double r = 3;
  const auto plan = pocket::make_flat_plan(region, params(r, 2.4), 1e-6, {});
  bool lake = false;  // a node with no island left although the input has one
  for (const auto& n : plan.tree.nodes) lake = lake || (n.depth > 0 && n.loops.size() == 1);
  EXPECT_TRUE(lake);
  expect_invariants(test::run_case(region, region, params(r, 2.4), kCell), r, 1e-9,
                    test::corner_area(r, {kPi / 2, kPi / 2, kPi / 2, kPi / 2}));
}

TEST(PocketCases, NarrowNeckMakesBrothers) {
  const std::vector<Loop> region{test::dumbbell(40, 10, 30)};
  const double r = 3;
  const auto plan = pocket::make_flat_plan(region, params(r, 2.0), 1e-6, {});
  int max_children = 0;
  for (const auto& n : plan.tree.nodes)
    max_children = std::max(max_children, static_cast<int>(n.children.size()));
  EXPECT_EQ(max_children, 2);
  // 8 convex right-angle corners; the 4 reflex ones are reachable.
  expect_invariants(test::run_case(region, region, params(r, 2.0), kCell), r, 1e-9,
                    test::corner_area(r, std::vector<double>(8, kPi / 2)));
}

TEST(PocketCases, FullDiameterStepoverLeavesNothing) {
  // 100 % stepover: the interval is reduced where it would leave cusps.
  const std::vector<Loop> region{test::rect(0, 0, 90, 70), reversed(test::rect(30, 25, 50, 40)),
                                 test::circle(70, 20, 6, false)};
  const double r = 3;
  const test::CaseReport rep = test::run_case(region, region, params(r, 6.0), kCell);
  EXPECT_GT(rep.result.metrics.reduced_intervals, 0);
  expect_invariants(rep, r, 1e-9, test::corner_area(r, {kPi / 2, kPi / 2, kPi / 2, kPi / 2}));
}

TEST(PocketCases, BSplineIslands) {
  const TopoDS_Face f = test::bspline_islands_face();
  const double r = 4, tol = 0.01;
  const std::vector<Loop> region = face_region(f, tol);
  ASSERT_EQ(region.size(), 3u);
  expect_invariants(test::run_case(region, truth_of(f, tol), params(r, 3.0, tol), kCell), r,
                    tol * 1.05, test::corner_area(r, {kPi / 2, kPi / 2, kPi / 2, kPi / 2}));
}

TEST(PocketCases, BSplineBoundaryOnly) {
  const TopoDS_Face f = test::bspline_boundary_face();
  const double r = 3, tol = 0.01;
  const std::vector<Loop> region = face_region(f, tol);
  ASSERT_EQ(region.size(), 2u);
  // The B-spline sides meet at the box corners at angles near 90 degrees;
  // the corner area is not known in closed form: only the invariants.
  expect_invariants(test::run_case(region, truth_of(f, tol), params(r, 2.5, tol), kCell), r,
                    tol * 1.05, -1);
}

TEST(PocketCases, FaceBrepPlanarWithTwoHoles) {
  const TopoDS_Shape shape = test::load("face.brep");
  const std::vector<TopoDS_Face> faces = faces_of(shape);
  ASSERT_EQ(faces.size(), 1u);
  const double z = BRepAdaptor_Surface(faces[0]).Plane().Location().Z();
  const double r = 3, tol = 0.01;
  FacePocketParams fp;
  fp.pocket = params(r, 2.4, tol);
  fp.pocket.safe_z = z + 10;
  fp.depths = {z + 2, z};
  const auto t0 = std::chrono::steady_clock::now();
  const PocketResult res = pocket_faces(shape, {0}, fp);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(res.warnings.empty()) << res.warnings.front();
  EXPECT_EQ(res.metrics.levels, 2);
  const std::vector<Loop> truth = face_region(faces[0], tol / 50);
  ASSERT_EQ(truth.size(), 3u);  // outline + two circular holes
  test::CaseReport rep;
  rep.result = res;
  rep.seconds = seconds;
  CoverageParams cp;
  cp.tool_radius = r;
  cp.cell = kCell;
  cp.tolerance = 2 * tol;
  cp.z_floor = z;
  rep.coverage = pocket_coverage(truth, res.path, cp);
  rep.clearance = pocket_clearance(truth, res.path, z, 0.05);
  rep.arcs_bad = test::bad_arcs(truth, res.path, z, 1e-6, rep.arcs_checked);
  EXPECT_GT(rep.arcs_checked, 0);  // circular holes give G2/G3 moves
  // A slot with round ends (radius 30 > r): no corner the tool cannot reach.
  expect_invariants(rep, r, 1e-9, 0.0);
  // One retract to go down to the second level; the rest is one spiral.
  EXPECT_TRUE(test::meets_expected("PocketCases/face_brep", "retracts", res.metrics.retracts));
}

TEST(PocketCases, ConventionalReversesTheLoops) {
  const std::vector<Loop> region{test::rect(0, 0, 60, 40), test::circle(30, 20, 6, false)};
  PocketParams p = params(3, 2.4);
  const PocketResult climb = spiral_pocket(region, {0.0}, p);
  p.direction = CutDirection::Conventional;
  const PocketResult conv = spiral_pocket(region, {0.0}, p);
  // The same loops run the other way: only the sum's order differs (1e-6 mm).
  EXPECT_NEAR(climb.metrics.cutting_length, conv.metrics.cutting_length, 1e-6);
  // The outermost loop runs counter-clockwise (climb: the wall on the
  // right) or clockwise: the signed area of its last moves tells.
  auto last_loop_area = [](const Toolpath& path) {
    // The last loop ends where it started: the moves after that point.
    const std::size_t n = path.size() - 1;
    std::size_t j = n - 1;
    while (j > 0 && (path.x[j] != path.x[n] || path.y[j] != path.y[n])) --j;
    double a = 0;
    for (std::size_t i = j + 1; i <= n; ++i)
      a += 0.5 * (path.x[i - 1] * path.y[i] - path.x[i] * path.y[i - 1]);
    return a;
  };
  EXPECT_NE(last_loop_area(climb.path) > 0, last_loop_area(conv.path) > 0);
}

}  // namespace
}  // namespace isocam
