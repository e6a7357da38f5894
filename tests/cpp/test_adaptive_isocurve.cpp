// Adaptive isocurve finishing on real and built faces: the coverage of
// Definition 1, the path following the offset of the curves, no gouge, and
// the paper's Figure 2 comparison against uniform isocurves.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <TopoDS.hxx>
#include <algorithm>
#include <functional>
#include <iostream>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "support/checks.h"
#include "support/expected.h"
#include "support/models.h"
#include "support/same_path.h"

namespace isocam {
namespace {

struct FaceCase {
  const char* name;
  std::function<TopoDS_Shape()> shape;
  int face;
  double r, h, chord;
  IsoDirection dir;
};

std::ostream& operator<<(std::ostream& os, const FaceCase& c) { return os << c.name; }

// The path really drives the ball along the offset of every curve: each
// sampled tip point of the offset curves lies within the chord tolerance of
// a feed move, or else the ball could not be there: its centre, or the
// vertical ray up from it (a 3-axis tool comes from above), is closer than r
// to the model (a point of some face that close is found: the core protects
// the whole model by default), by more than half the gouge tolerance, which
// is where the core leaves material and reports it. (The
// core may keep a point down to r - chord - gouge: its chords, not the
// exact offset, must clear that; it must drop none the ball clears.)
void expect_path_follows_curves(const TopoDS_Face& face, int face_index, const IsoResult& res,
                                double r, double chord, double gouge, const test::FaceCloud& own,
                                const test::ModelCloud& model) {
  const test::SegmentIndex feeds = test::feed_segments(res.path, 1.0);
  double unreachable = 0;
  int off_path = 0;
  for (const auto& curve : test::tip_curves(face, face_index, res, r, res.metrics.delta / 4)) {
    for (const gp_Pnt& q : curve) {
      // 1e-6 mm: the index's distance to a segment, rounding only.
      if (feeds.distance(q, 1.0) <= chord + 1e-6) continue;
      if (off_path++ % 4 == 0) {  // a sample of them
        const gp_Pnt centre(q.X(), q.Y(), q.Z() + r);
        unreachable = std::max(unreachable, std::min({own.distance(centre), model.distance(centre),
                                                      model.column_distance(centre, r)}));
      }
    }
  }
  std::cout << "  points off the path: " << off_path << ", their largest clearance " << unreachable
            << ", unreachable length " << res.metrics.unreachable_length << "\n";
  if (off_path > 0) {
    EXPECT_LT(unreachable, r - 0.5 * gouge);
    EXPECT_GT(res.metrics.unreachable_length, 0.0);
  }
}

// Every face of the shape, trimmed, sampled about r / 8 apart (the picked
// face, where the offset folds, gets a denser cloud of its own).
test::ModelCloud whole_model(const TopoDS_Shape& shape, double r) {
  return test::ModelCloud(faces_of(shape), r / 8, true);
}

class AdaptiveOnFace : public ::testing::TestWithParam<FaceCase> {};

TEST_P(AdaptiveOnFace, CoversTheFaceWithinDeltaAndNeverGouges) {
  const FaceCase& c = GetParam();
  const TopoDS_Shape shape = c.shape();
  const TopoDS_Face face = test::face(shape, c.face);
  IsoParams p;
  p.ball_radius = c.r;
  p.scallop_height = c.h;
  p.chord_tolerance = c.chord;  // 0: derived from the budgets
  // An override must fit the overcut budget (chord + gouge + posted rounding).
  if (c.chord > 0) p.overcut_tolerance = c.chord + p.gouge_tolerance + 0.001;
  p.direction = c.dir;
  p.safe_z = 1000;
  const IsoResult res = adaptive_isocurve(shape, {c.face}, p);
  const double chord = res.metrics.chord_tolerance;
  if (c.chord > 0) {
    EXPECT_EQ(chord, c.chord);
  }
  EXPECT_LE(res.metrics.guaranteed_overcut, p.overcut_tolerance);
  // The flat stepover for the cusp the budget leaves: the centres may be
  // off the offset by the chord tolerance and the posted rounding.
  const double e = res.metrics.chord_tolerance + 0.5 * std::sqrt(3.0) * p.posted_resolution;
  const double delta = 2.0 * std::sqrt(2.0 * (c.r - e) * (c.h - e) - (c.h - e) * (c.h - e));
  // 1e-12 mm here and 1e-12, 1e-9 relative below: the same arithmetic in
  // the core, rounding only.
  EXPECT_NEAR(res.metrics.delta, delta, 1e-12);
  EXPECT_GT(res.metrics.sub_isocurves, 2);
  // The curvature-aware bound (the default) works to a tolerance per patch,
  // under delta on convex ground, up to 2 delta on concave ground.
  EXPECT_GT(res.metrics.delta_max, 0.0);
  EXPECT_LE(res.metrics.delta_max, 2 * delta * (1 + 1e-12));
  EXPECT_LE(res.metrics.max_iso_distance, res.metrics.delta_max);
  EXPECT_LE(res.metrics.guaranteed_scallop, c.h * (1 + 1e-9));

  // Definition 1 on an independent dense sampling of the face.
  test::SegmentIndex contacts(delta);
  for (const auto& curve : test::contact_curves(face, c.face, res, delta / 20))
    contacts.add_polyline(curve);
  const double gap = test::coverage_gap(face, contacts, 150, 2 * delta);
  std::cout << c.name << ": delta " << delta << " coverage gap " << gap << " sub-isocurves "
            << res.metrics.sub_isocurves << " cutting length " << res.metrics.cutting_length
            << "\n";
  EXPECT_LT(gap, res.metrics.delta_max);

  const test::FaceCloud cloud(face, 600);
  expect_path_follows_curves(face, c.face, res, c.r, chord, p.gouge_tolerance, cloud,
                             whole_model(shape, c.r));

  // No gouge: the ball centre stays at least r (less the chord tolerance,
  // the most a chord can cut into the offset, and the clearance check's
  // tolerance) from the face, checked against a dense cloud of the face
  // refined by local projection (1e-6 mm: that refinement's accuracy).
  const double closest = test::min_centre_distance(cloud, res.path, c.r, 4000);
  EXPECT_GE(closest, c.r - chord - p.gouge_tolerance - 1e-6);
}

TopoDS_Shape mat() { return test::load("MAT.brep"); }
TopoDS_Shape wing() { return test::scaled(test::load("wing.brep"), 50.0); }
TopoDS_Shape sphere() { return BRepPrimAPI_MakeSphere(25.0).Shape(); }
TopoDS_Shape cylinder() { return BRepPrimAPI_MakeCylinder(15.0, 40.0).Shape(); }
TopoDS_Shape torus() { return BRepPrimAPI_MakeTorus(30.0, 10.0).Shape(); }
TopoDS_Shape figure2() { return test::figure2_ruled_surface(); }
TopoDS_Shape creased() { return test::figure2_ruled_surface(true); }

INSTANTIATE_TEST_SUITE_P(
    Faces, AdaptiveOnFace,
    ::testing::Values(
        FaceCase{"MAT_bicubic_6160_patches", mat, 0, 3.0, 0.05, 0.01, IsoDirection::Auto},
        FaceCase{"wing_degree8_ruled", wing, 0, 3.0, 0.02, 0.01, IsoDirection::V},
        FaceCase{"sphere_rational_with_poles", sphere, 0, 3.0, 0.02, 0.01, IsoDirection::U},
        FaceCase{"sphere_latitudes", sphere, 0, 3.0, 0.02, 0.0, IsoDirection::V},
        FaceCase{"cylinder_rational", cylinder, 0, 2.0, 0.01, 0.0, IsoDirection::Auto},
        FaceCase{"torus_rational", torus, 0, 3.0, 0.05, 0.01, IsoDirection::Auto},
        FaceCase{"figure2_ruled", figure2, 0, 5.0, 0.1, 0.01, IsoDirection::V},
        FaceCase{"convex_C0_creases", creased, 0, 5.0, 0.1, 0.01, IsoDirection::V}),
    [](const ::testing::TestParamInfo<FaceCase>& tp) { return std::string(tp.param.name); });

TEST(AdaptiveIsocurve, ShorterThanUniformIsocurvesOnFigure2) {
  // The paper's Figure 2 argument: complete isocurves equally spaced in
  // parameter must be spaced for the widest part and are redundant where the
  // surface is narrow; adaptive sub-isocurves are not.
  const TopoDS_Face f = test::figure2_ruled_surface();
  IsoParams p;
  p.ball_radius = 5.0;
  p.scallop_height = 0.1;
  p.direction = IsoDirection::V;
  p.safe_z = 100;
  const IsoResult adaptive = adaptive_isocurve(f, {0}, p);
  p.pattern = IsoPattern::Uniform;
  const IsoResult uniform = adaptive_isocurve(f, {0}, p);
  std::cout << "Figure 2: adaptive " << adaptive.metrics.cutting_length << " mm ("
            << adaptive.metrics.sub_isocurves << " sub-isocurves), uniform "
            << uniform.metrics.cutting_length << " mm (" << uniform.metrics.sub_isocurves
            << " isocurves)\n";
  EXPECT_LE(uniform.metrics.max_iso_distance, uniform.metrics.delta);
  EXPECT_LE(adaptive.metrics.max_iso_distance, adaptive.metrics.delta);
  EXPECT_TRUE(
      test::meets_expected("AdaptiveIsocurve/figure2_ruled", "adaptive_over_uniform_length",
                           adaptive.metrics.cutting_length / uniform.metrics.cutting_length));
}

// The scallop, measured on the cut (test::measure_scallop), on convex ground,
// where the paper's flat-ground stepover alone would leave cusps higher than
// asked: both bounds narrow the stepover there (the flat one never widens it
// on concave ground), so the certificate, chords included, holds and stays
// under h under either bound, and the cut is not needlessly fine.
TEST(AdaptiveIsocurve, ScallopMeasuredUnderTheRequestedHeightOnConvexGround) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  const TopoDS_Face face = test::face(sphere, 0);
  IsoParams p;
  p.ball_radius = 3.0;
  p.scallop_height = 0.05;
  p.direction = IsoDirection::V;
  p.safe_z = 100;
  const IsoScallopBound bounds[2] = {IsoScallopBound::Flat, IsoScallopBound::Curvature};
  for (int k = 0; k < 2; ++k) {
    p.scallop_bound = bounds[k];
    const IsoResult res = adaptive_isocurve(sphere, {0}, p);
    // Where a 3-axis tool reaches from above (not under the equator).
    const test::ModelCloud reach(face, 200);
    const test::ScallopCheck s =
        test::measure_scallop(face, res.path, p.ball_radius, 150, 0.02, 1.0, &reach);
    std::cout << (k ? "curvature" : "flat") << " bound: measured scallop " << s.max << " over "
              << s.samples << " samples (" << s.uncovered << " uncovered), certified "
              << res.metrics.guaranteed_scallop << ", cutting length " << res.metrics.cutting_length
              << "\n";
    EXPECT_EQ(s.uncovered, 0);
    EXPECT_LE(s.max, res.metrics.guaranteed_scallop);
    EXPECT_LE(res.metrics.guaranteed_scallop, p.scallop_height * (1 + 1e-9));
    EXPECT_GT(s.max, 0.7 * p.scallop_height);
  }
}

TEST(AdaptiveIsocurve, AutoPicksTheShorterDirection) {
  const TopoDS_Shape s = test::scaled(test::load("wing.brep"), 50.0);
  IsoParams p;
  p.scallop_height = 0.05;
  p.safe_z = 1000;
  double len[2];
  for (IsoDirection d : {IsoDirection::U, IsoDirection::V}) {
    p.direction = d;
    len[d == IsoDirection::V] = adaptive_isocurve(s, {1}, p).metrics.cutting_length;
  }
  p.direction = IsoDirection::Auto;
  const IsoResult a = adaptive_isocurve(s, {1}, p);
  EXPECT_NEAR(a.metrics.cutting_length, std::min(len[0], len[1]), 1e-9);
  ASSERT_EQ(a.face_direction.size(), 1u);
  EXPECT_EQ(a.face_direction[0], len[0] < len[1] ? IsoDirection::U : IsoDirection::V);
}

TEST(AdaptiveIsocurve, PathShapeRetractsAndSafeHeight) {
  // The path starts and ends at the safe height; every piece is entered by
  // a vertical fed plunge after a rapid (from the safe height only the
  // first, the others from a hop) and left by a vertical lift; adjacent
  // pieces are linked without lifts.
  const TopoDS_Shape s = test::figure2_ruled_surface();
  IsoParams p;
  p.ball_radius = 5;
  p.scallop_height = 0.1;
  p.direction = IsoDirection::V;
  p.safe_z = 50;
  const IsoResult r = adaptive_isocurve(s, {0}, p);
  const Toolpath& t = r.path;
  ASSERT_GT(t.size(), 3u);
  EXPECT_EQ(t.kind[0], static_cast<std::uint8_t>(MoveKind::Rapid));
  EXPECT_DOUBLE_EQ(t.z[0], 50.0);
  // Down from there at rapid to near the surface, then fed (straight down,
  // or along the normal where the piece starts on a steep wall).
  std::size_t first = 1;
  while (first < t.size() && t.kind[first] == static_cast<std::uint8_t>(MoveKind::Rapid)) ++first;
  ASSERT_LT(first, t.size());
  EXPECT_TRUE(t.kind[first] == static_cast<std::uint8_t>(MoveKind::Plunge) ||
              t.kind[first] == static_cast<std::uint8_t>(MoveKind::Ramp));
  EXPECT_LT(t.z[first - 1] - t.z[first], 50.0 - t.z[first]);
  EXPECT_EQ(t.kind.back(), static_cast<std::uint8_t>(MoveKind::Rapid));
  EXPECT_DOUBLE_EQ(t.z.back(), 50.0);
  int plunges = 0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    // A plunge move going up is a lift fed where a rapid would pass near the
    // model (beside the end of the reach from above): straight up, from a
    // cutting position or a fed lift.
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Plunge) && t.z[i] > t.z[i - 1]) {
      EXPECT_EQ(t.x[i], t.x[i - 1]);
      EXPECT_EQ(t.y[i], t.y[i - 1]);
      EXPECT_NE(t.kind[i - 1], static_cast<std::uint8_t>(MoveKind::Rapid));
      continue;
    }
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Plunge) ||
        t.kind[i] == static_cast<std::uint8_t>(MoveKind::Ramp)) {
      ++plunges;
      EXPECT_EQ(t.kind[i - 1], static_cast<std::uint8_t>(MoveKind::Rapid));
      EXPECT_LT(t.z[i], t.z[i - 1]);
    }
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Feed)) {
      EXPECT_LT(t.z[i], 50.0);
    }
  }
  EXPECT_EQ(plunges, r.metrics.retracts);
  EXPECT_LT(r.metrics.retracts, r.metrics.sub_isocurves);
}

TEST(AdaptiveIsocurve, CancelStopsTheWork) {
  Progress progress;
  progress.request_cancel();
  IsoParams p;
  p.safe_z = 100;
  EXPECT_THROW(adaptive_isocurve(test::load("MAT.brep"), {0}, p, &progress), Cancelled);
}

TEST(AdaptiveIsocurve, ProgressReachesOne) {
  Progress progress;
  IsoParams p;
  p.scallop_height = 0.05;
  p.safe_z = 100;
  adaptive_isocurve(test::load("MAT.brep"), {0}, p, &progress);
  EXPECT_DOUBLE_EQ(progress.fraction.load(), 1.0);
}

}  // namespace
}  // namespace isocam

namespace isocam {
namespace {

// Trimmed faces: the path stays inside the trimmed domain and covers it.
struct TrimCase {
  const char* name;
  const char* file;
  int face;
  double r, h;
};

class AdaptiveOnTrimmedFace : public ::testing::TestWithParam<TrimCase> {};

// The face as the core finished it: reversed where it reports an open face
// finished from its other side (the side a vertical tool reaches).
TopoDS_Face finished_side(const TopoDS_Face& face, int index, const IsoResult& res) {
  const std::string said =
      "(Face" + std::to_string(index + 1) + ") is an open face whose orientation";
  for (const std::string& w : res.warnings)
    if (w.find(said) != std::string::npos) return TopoDS::Face(face.Reversed());
  return face;
}

TEST_P(AdaptiveOnTrimmedFace, StaysInsideAndCoversTheTrimmedDomain) {
  const TrimCase& c = GetParam();
  const TopoDS_Shape shape = test::load(c.file);
  const TopoDS_Face given = test::face(shape, c.face);
  IsoParams p;
  p.ball_radius = c.r;
  p.scallop_height = c.h;
  p.safe_z = 1000;
  const IsoResult res = adaptive_isocurve(shape, {c.face}, p);
  // An open face reached only on its other side is finished from there: the
  // core takes it reversed and says so; the checks below then use it so.
  const TopoDS_Face face = finished_side(given, c.face, res);
  const double delta = res.metrics.delta;
  // No contact point outside the trimmed domain (1e-6 mm: the hatcher's and
  // the classifier's tolerances).
  int outside = 0, checked = 0;
  test::SegmentIndex contacts(delta);
  for (const auto& curve : test::contact_curves(face, c.face, res, delta / 20)) {
    contacts.add_polyline(curve);
    for (const gp_Pnt& q : curve) {
      if (++checked % 7) continue;
      if (!test::in_face(face, q, 1e-6)) ++outside;
    }
  }
  EXPECT_EQ(outside, 0) << "of " << checked / 7 << " contact points checked";
  // Coverage of the trimmed domain (Definition 1), on an independent
  // sampling classified against the face's own wires.
  const double gap = test::coverage_gap(face, contacts, 200, 2 * delta);
  std::cout << c.name << ": delta " << delta << " coverage gap " << gap << " sub-isocurves "
            << res.metrics.sub_isocurves << "\n";
  EXPECT_LT(gap, res.metrics.delta_max);
  expect_path_follows_curves(face, c.face, res, c.r, res.metrics.chord_tolerance, p.gouge_tolerance,
                             test::FaceCloud(face, 400), whole_model(shape, c.r));
}

INSTANTIATE_TEST_SUITE_P(
    Faces, AdaptiveOnTrimmedFace,
    ::testing::Values(TrimCase{"plane_with_two_holes", "face.brep", 0, 3.0, 0.05},
                      TrimCase{"reversed_plane_with_hole", "Ball.brep", 5, 1.0, 0.01},
                      TrimCase{"trimmed_reversed_sphere", "Ball.brep", 16, 1.0, 0.01},
                      TrimCase{"trimmed_cylinder", "Ball.brep", 13, 1.0, 0.01},
                      TrimCase{"trimmed_bspline", "shell1.brep", 10, 1.0, 0.01}),
    [](const ::testing::TestParamInfo<TrimCase>& tp) { return std::string(tp.param.name); });

}  // namespace
}  // namespace isocam

namespace isocam {
namespace {

TEST(AdaptiveIsocurve, OneAndManyThreadsGiveTheSamePath) {
  // shell1: 99 trimmed B-spline faces, computed on 1 and on 4 threads.
  const TopoDS_Shape s = test::load("shell1.brep");
  std::vector<int> faces;
  for (int f = 0; f < 99; ++f) faces.push_back(f);
  IsoParams p;
  p.scallop_height = 0.05;
  p.safe_z = 100;
  p.threads = 1;
  const IsoResult one = adaptive_isocurve(s, faces, p);
  p.threads = 4;
  const IsoResult four = adaptive_isocurve(s, faces, p);
  EXPECT_TRUE(test::same_path(one.path, four.path));
  EXPECT_EQ(one.metrics.sub_isocurves, four.metrics.sub_isocurves);
  EXPECT_LT(one.metrics.retracts, one.metrics.sub_isocurves);
}

}  // namespace
}  // namespace isocam
