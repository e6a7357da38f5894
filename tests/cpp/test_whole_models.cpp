// Whole models (issue 3): several trimmed faces meeting at concave and
// convex edges. The ball keeps at least r (less the stated tolerances) from
// every face of the model, checked against OpenCASCADE's own surfaces and
// face classification; the picked faces are covered within delta except
// where the ball cannot touch, which the check computes itself; and the
// pieces are linked with fewer retracts than there are pieces.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "support/checks.h"
#include "support/models.h"

namespace isocam {
namespace {

struct WholeCase {
  const char* name;
  TopoDS_Shape (*shape)();
  std::vector<int> (*picked)(const TopoDS_Shape&);
  double r, h;
  int samples;  // per face side, for the coverage check
  // The faces whose coverage is asserted (indices into the picked list;
  // empty: all). See the house case for why not all.
  std::vector<std::size_t> covered;
};

std::ostream& operator<<(std::ostream& os, const WholeCase& c) { return os << c.name; }

TopoDS_Shape shell1() { return test::load("shell1.brep"); }
std::vector<int> all_faces(const TopoDS_Shape& s) {
  std::vector<int> v(faces_of(s).size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<int>(i);
  return v;
}

class WholeModel : public ::testing::TestWithParam<WholeCase> {};

TEST_P(WholeModel, NoGougeCoveredWhereReachableAndLinked) {
  const WholeCase& c = GetParam();
  const TopoDS_Shape shape = c.shape();
  const std::vector<int> picked = c.picked(shape);
  IsoParams p;
  p.ball_radius = c.r;
  p.scallop_height = c.h;
  p.protect_unpicked_faces = true;
  p.safe_z = 200;
  const IsoResult res = adaptive_isocurve(shape, picked, p);
  const double delta = res.metrics.delta;
  const test::WholeModelCheck w =
      test::check_whole_model(shape, picked, res.path, c.r, delta / 4, c.samples, 0.002, 4 * delta);
  std::cout << "  worst gap " << w.max_gap << " at (" << w.worst.X() << ", " << w.worst.Y() << ", "
            << w.worst.Z() << ") on face " << w.worst_face << "\n";
  std::cout << "  " << c.name << ": " << picked.size() << " faces, L " << res.metrics.cutting_length
            << " mm, " << res.metrics.sub_isocurves << " sub-isocurves, " << res.metrics.retracts
            << " retracts; min clearance " << w.min_clearance << " (r " << c.r << "), max gap "
            << w.max_gap << " (delta " << delta << ", largest local " << res.metrics.delta_max
            << "), unreachable samples " << w.unreachable << "/" << w.samples
            << ", unreachable length " << res.metrics.unreachable_length << " (from above "
            << res.metrics.unreachable_from_above_length << ")\n";
  // No gouge against any face of the model, links included (they are feed
  // moves too): the core's own bound, r less its chord and clearance-check
  // tolerances; 1e-4 mm is headroom for the check's distance (the nearest
  // sample of its cloud refined by a local projection onto the face), not
  // for the core.
  EXPECT_GE(w.min_clearance, c.r - res.metrics.chord_tolerance - p.gouge_tolerance - 1e-4)
      << "ball centre (" << w.closest_centre.X() << ", " << w.closest_centre.Y() << ", "
      << w.closest_centre.Z() << ") from face " << w.closest_face << " at (" << w.closest_point.X()
      << ", " << w.closest_point.Y() << ", " << w.closest_point.Z() << ")";
  // Definition 1 on every sample the ball can touch, and the scallop
  // guarantee the curvature-aware bound gives.
  for (std::size_t k = 0; k < picked.size(); ++k) {
    const bool asserted =
        c.covered.empty() || std::find(c.covered.begin(), c.covered.end(), k) != c.covered.end();
    if (asserted) {
      EXPECT_LE(w.face_gap[k], res.metrics.delta_max) << "face " << picked[k];
    } else {
      std::cout << "    face " << picked[k] << ": largest gap " << w.face_gap[k]
                << " (not asserted)\n";
    }
  }
  // 1e-6 relative: the certificate's rounding, not a looser budget.
  EXPECT_LE(res.metrics.guaranteed_scallop, c.h * (1 + 1e-6));
  EXPECT_GT(w.samples, 1000);  // the check saw the model (c.samples per face side)
  // Linking: far fewer retracts than pieces.
  EXPECT_LT(res.metrics.retracts, res.metrics.sub_isocurves);
}

INSTANTIATE_TEST_SUITE_P(
    Models, WholeModel,
    ::testing::Values(WholeCase{"house_on_the_hill",
                                test::house_on_the_hill,
                                test::house_on_the_hill_picked,
                                3.0,
                                0.05,
                                120,
                                {}},
                      // Faces 27 and 31: walls whose normals point down on
                      // average by microns; taken reversed for that, though
                      // only their own side is reached, they left gaps of
                      // 0.95 and 0.56 mm; finished from the side a vertical
                      // tool reaches (face_side.h): 0.22 and 0.11 mm.
                      WholeCase{"shell1_99_faces", shell1, all_faces, 2.0, 0.02, 30, {}}),
    [](const ::testing::TestParamInfo<WholeCase>& tp) { return std::string(tp.param.name); });

// The house has concave corners (walls on the hill): there the ball cannot
// touch, the check finds such samples and the core reports the length of
// path it left out.
TEST(WholeModelHouse, ConcaveCornersAreFoundAndReported) {
  const TopoDS_Shape shape = test::house_on_the_hill();
  const std::vector<int> picked = test::house_on_the_hill_picked(shape);
  ASSERT_GE(picked.size(), 6u);
  IsoParams p;
  p.ball_radius = 3.0;
  p.scallop_height = 0.1;
  p.protect_unpicked_faces = true;
  p.safe_z = 200;
  const IsoResult res = adaptive_isocurve(shape, picked, p);
  const test::WholeModelCheck w =
      test::check_whole_model(shape, picked, res.path, p.ball_radius, res.metrics.delta / 4, 60,
                              0.002, 4 * res.metrics.delta);
  EXPECT_GT(w.unreachable, 0);
  EXPECT_GT(res.metrics.unreachable_length, 0.0);
}

}  // namespace
}  // namespace isocam
