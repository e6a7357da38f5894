// The two guarantees (material left, overcut) add up from their parts and
// stay within the budgets, and the air moves between passes: clear of the
// whole model (checked against an independent cloud of it, not the core's
// clearance model), no lower than they must be, and much cheaper than
// retracting to the safe height.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeSphere.hxx>
#include <algorithm>
#include <cmath>
#include <iostream>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "support/checks.h"
#include "support/expected.h"
#include "support/models.h"

namespace isocam {
namespace {

const double kPosted = 0.5 * std::sqrt(3.0);  // posted rounding per unit of resolution

struct BudgetCase {
  double h, overcut, resolution;
  IsoScallopBound bound;
};

// On a sphere of 10 mm (convex: where the flat stepover alone would leave
// higher cusps) for several budgets and both bounds: the certificate's
// parts add up as the header says, both numbers are within their budgets,
// and the scallop measured on the cut (an independent sampling of the
// face) and the ball centre's distance from the face are within them.
TEST(Guarantees, BudgetsAddUpAndHoldOnASphere) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  const TopoDS_Face face = test::face(sphere, 0);
  const test::FaceCloud cloud(face, 400);
  const BudgetCase cases[] = {
      {0.01, 0.005, 0.001, IsoScallopBound::Curvature},  // the defaults
      {0.01, 0.005, 0.001, IsoScallopBound::Flat},
      {0.05, 0.02, 0.001, IsoScallopBound::Curvature},
      {0.05, 0.003, 0.0, IsoScallopBound::Flat},
      {0.02, 0.01, 0.0001, IsoScallopBound::Curvature},
  };
  for (const BudgetCase& c : cases) {
    IsoParams p;
    p.ball_radius = 3.0;
    p.scallop_height = c.h;
    p.overcut_tolerance = c.overcut;
    p.posted_resolution = c.resolution;
    p.scallop_bound = c.bound;
    p.direction = IsoDirection::V;
    p.safe_z = 100;
    const IsoResult res = adaptive_isocurve(sphere, {0}, p);
    const IsoMetrics& m = res.metrics;
    const double posted = kPosted * c.resolution;
    const double chord = std::min(c.overcut - p.gouge_tolerance - posted, 0.1 * (c.h - posted));
    // The core sums the same parts: 1e-15 mm and 1e-12, 1e-9 relative are
    // rounding, not slack in the budgets.
    EXPECT_NEAR(m.chord_tolerance, chord, 1e-15);
    EXPECT_NEAR(m.guaranteed_overcut, chord + p.gouge_tolerance + posted, 1e-15);
    EXPECT_LE(m.guaranteed_overcut, c.overcut * (1 + 1e-12));
    EXPECT_LE(m.guaranteed_scallop, c.h * (1 + 1e-9));
    // Not needlessly fine: the cusp takes most of what the chords leave.
    EXPECT_GT(m.guaranteed_scallop, 0.8 * c.h);
    // Where a 3-axis tool reaches from above (not under the equator).
    const test::ModelCloud reach(face, 200);
    const test::ScallopCheck s =
        test::measure_scallop(face, res.path, p.ball_radius, 120, 0.02, 1.0, &reach);
    const double closest = test::min_centre_distance(cloud, res.path, p.ball_radius, 3000);
    std::cout << "h " << c.h << " overcut " << c.overcut << " resolution " << c.resolution
              << (c.bound == IsoScallopBound::Flat ? " flat" : " curvature") << ": chord "
              << m.chord_tolerance << ", scallop measured " << s.max << " <= guaranteed "
              << m.guaranteed_scallop << ", centre distance " << closest << " (r - overcut "
              << p.ball_radius - m.guaranteed_overcut << ")\n";
    EXPECT_EQ(s.uncovered, 0);
    EXPECT_LE(s.max, m.guaranteed_scallop);
    // The path is not posted here, so its rounding is not spent; 1e-6 mm:
    // the check's distance (its cloud's refinement).
    EXPECT_GE(closest, p.ball_radius - m.guaranteed_overcut + posted - 1e-6);
  }
}

// An override of the chord tolerance counts in the certificate and must fit
// both budgets.
TEST(Guarantees, ChordOverrideCountsAndMustFit) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(10.0).Shape();
  IsoParams p;
  p.scallop_height = 0.05;
  p.overcut_tolerance = 0.02;
  p.chord_tolerance = 0.015;
  p.direction = IsoDirection::V;
  p.safe_z = 100;
  const IsoResult res = adaptive_isocurve(sphere, {0}, p);
  EXPECT_DOUBLE_EQ(res.metrics.chord_tolerance, 0.015);
  // chord + gouge_tolerance + posted rounding; 1e-15 mm: rounding.
  EXPECT_NEAR(res.metrics.guaranteed_overcut, 0.015 + 0.001 + kPosted * 0.001, 1e-15);
  EXPECT_LE(res.metrics.guaranteed_scallop, 0.05 * (1 + 1e-9));
  auto message = [&](const IsoParams& q) -> std::string {
    try {
      adaptive_isocurve(sphere, {0}, q);
    } catch (const InvalidArgument& e) {
      return e.what();
    }
    return "no error";
  };
  IsoParams q = p;
  q.chord_tolerance = 0.019;  // 0.019 + 0.001 + 0.00087 > 0.02
  EXPECT_NE(message(q).find("chord_tolerance"), std::string::npos) << message(q);
  EXPECT_NE(message(q).find("overcut_tolerance"), std::string::npos) << message(q);
  q = p;
  q.overcut_tolerance = 0.1;
  q.chord_tolerance = 0.048;  // leaves no room for the cusp
  EXPECT_NE(message(q).find("scallop_height"), std::string::npos) << message(q);
  q = p;
  q.overcut_tolerance = 0.0015;  // under gouge + posted rounding
  EXPECT_NE(message(q).find("overcut_tolerance"), std::string::npos) << message(q);
  for (double bad : {0.0, -1.0, std::nan(""), 5.0}) {
    q = p;
    q.overcut_tolerance = bad;
    EXPECT_NE(message(q).find("overcut_tolerance"), std::string::npos) << bad;
  }
  for (double bad : {-0.001, 0.5, std::nan("")}) {
    q = p;
    q.posted_resolution = bad;
    EXPECT_NE(message(q).find("posted_resolution"), std::string::npos) << bad;
  }
  q = p;
  q.chord_tolerance = std::nan("");
  EXPECT_NE(message(q).find("chord_tolerance"), std::string::npos);
  q = p;
  q.air_clearance = 0;
  EXPECT_NE(message(q).find("air_clearance"), std::string::npos);
  q = p;
  q.plunge_rate = -5;
  EXPECT_NE(message(q).find("plunge_rate"), std::string::npos);
  q = p;
  q.rapid_rate = std::numeric_limits<double>::infinity();
  EXPECT_NE(message(q).find("rapid_rate"), std::string::npos);
}

gp_Pnt centre(const Toolpath& t, std::size_t i, double r) {
  return gp_Pnt(t.x[i], t.y[i], t.z[i] + r);
}

// The smallest distance from the ball centre moving from a to b to the
// model, sampled every `step` mm.
double segment_clearance(const test::ModelCloud& model, const gp_Pnt& a, const gp_Pnt& b,
                         double step) {
  const int n = std::max(1, static_cast<int>(std::ceil(a.Distance(b) / step)));
  double d = 1e300;
  for (int k = 0; k <= n; ++k) {
    const double s = double(k) / n;
    d = std::min(d, model.distance(gp_Pnt(a.XYZ() * (1 - s) + b.XYZ() * s)));
  }
  return d;
}

struct AirCase {
  const char* name;
  TopoDS_Shape (*shape)();
  std::vector<int> (*picked)(const TopoDS_Shape&);
  double r, h;  // the shares of air time and long entries: tests/data/expected.txt
  IsoPattern pattern = IsoPattern::Adaptive;
};

TopoDS_Shape mat() { return test::load("MAT.brep"); }
std::vector<int> first_face(const TopoDS_Shape&) { return {0}; }

class AirMoves : public ::testing::TestWithParam<AirCase> {};

// Every rapid keeps the ball r + air_clearance from the whole model, except
// a lift straight up from a cutting position (or from the end of a fed move
// out of it, along the normal or back along the pass, beside a wall), which
// keeps the cutting clearance (r - overcut) as the fed entries and that
// move out do; every entry is fed only from near the surface (above it, or
// out along the normal on a wall); lifts stay below the safe height where a
// lower hop is clear, and the air time is a small part of what retracting
// to the safe height would take.
TEST_P(AirMoves, ClearOfTheWholeModelLowAndCheap) {
  const AirCase& c = GetParam();
  const TopoDS_Shape shape = c.shape();
  IsoParams p;
  p.ball_radius = c.r;
  p.scallop_height = c.h;
  p.safe_z = 60;
  p.pattern = c.pattern;
  const IsoResult res = adaptive_isocurve(shape, c.picked(shape), p);
  const Toolpath& t = res.path;
  const double r = c.r, cut = r - res.metrics.guaranteed_overcut;
  const test::ModelCloud model(faces_of(shape), r / 8, true);
  const double slack = 1e-3;  // the cloud's refinement, the clearance model's band
  const double safe_c = p.safe_z + r;
  int lifts = 0, low_lifts = 0, entries = 0, long_entries = 0;
  double air_minutes = 0, safe_minutes = 0;
  double worst_rapid = 1e300, worst_lift = 1e300, worst_entry = 1e300;
  for (std::size_t i = 1; i < t.size(); ++i) {
    const gp_Pnt a = centre(t, i - 1, r), b = centre(t, i, r);
    const bool vertical = std::abs(a.X() - b.X()) + std::abs(a.Y() - b.Y()) < 1e-12;
    const auto kind = static_cast<MoveKind>(t.kind[i]);
    const auto before = static_cast<MoveKind>(t.kind[i - 1]);
    if (kind == MoveKind::Plunge && before != MoveKind::Rapid) {
      // A lift fed, keeping the cutting clearance: straight up (where a
      // rapid would pass nearer than r plus the posted rounding to the
      // model, up a wall), or, from the end of a pass, first out of it
      // (along the normal, or back along it and up, beside a wall). A
      // retract to the safe height would begin with the lift straight up.
      EXPECT_TRUE((vertical && b.Z() > a.Z()) || before == MoveKind::Feed) << "move " << i;
      worst_lift = std::min(worst_lift, segment_clearance(model, a, b, 0.05));
      if (vertical) safe_minutes += a.Distance(b) / p.plunge_rate;
      continue;
    }
    if (kind == MoveKind::Plunge || kind == MoveKind::Ramp) {
      ++entries;
      EXPECT_EQ(t.kind[i - 1], static_cast<std::uint8_t>(MoveKind::Rapid)) << "move " << i;
      worst_entry = std::min(worst_entry, segment_clearance(model, a, b, 0.05));
      if (a.Distance(b) > 4 * p.air_clearance) ++long_entries;

      continue;
    }
    if (kind != MoveKind::Rapid) continue;
    const bool lift =
        vertical && b.Z() > a.Z() && t.kind[i - 1] != static_cast<std::uint8_t>(MoveKind::Rapid);
    if (lift) {
      worst_lift = std::min(worst_lift, segment_clearance(model, a, b, 0.05));
      if (i + 1 < t.size()) {  // a hop, not the final retract
        ++lifts;
        if (b.Z() < safe_c - 1e-9) ++low_lifts;
        // The hop that retracting would make: up to the safe height, across,
        // and the entry fed all the way down.
        const gp_Pnt& entry = centre(
            t,
            [&] {
              std::size_t j = i + 1;
              while (j < t.size() && t.kind[j] == static_cast<std::uint8_t>(MoveKind::Rapid)) ++j;
              return j;
            }(),
            r);
        const double across = std::hypot(entry.X() - a.X(), entry.Y() - a.Y());
        safe_minutes +=
            (safe_c - a.Z() + across) / p.rapid_rate + (safe_c - entry.Z()) / p.plunge_rate;
      }
    } else {
      worst_rapid = std::min(worst_rapid, segment_clearance(model, a, b, 0.25));
    }
  }
  for (std::size_t i = 1; i < t.size(); ++i) {
    const double len = centre(t, i - 1, r).Distance(centre(t, i, r));
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Rapid)) air_minutes += len / p.rapid_rate;
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Plunge))
      air_minutes += len / p.plunge_rate;
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Ramp)) air_minutes += len / p.feed_rate;
  }
  // The program's last lift: fed beside a wall only as far as out of the
  // pass (then a rapid), like the other lifts.
  double final_fed = 0;
  for (std::size_t i = t.size() - 1;
       i > 0 && t.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed); --i)
    if (t.kind[i] == static_cast<std::uint8_t>(MoveKind::Plunge))
      final_fed += centre(t, i - 1, r).Distance(centre(t, i, r));
  std::cout << c.name << ": " << lifts << " hops (" << low_lifts << " below the safe height), "
            << entries << " entries; clearance of rapids " << worst_rapid << " (r + air "
            << r + p.air_clearance << "), of lifts " << worst_lift << ", of entries " << worst_entry
            << " (r - overcut " << cut << "); air time " << air_minutes << " min against "
            << safe_minutes << " min for retracts to the safe height; " << long_entries
            << " entries fed farther than 4 air_clearance; the final lift fed " << final_fed
            << " mm\n";
  EXPECT_GE(worst_rapid, r + p.air_clearance - slack);
  EXPECT_GE(worst_lift, cut - slack);
  EXPECT_GE(worst_entry, cut - slack);
  EXPECT_EQ(entries, res.metrics.retracts);  // one entry per lift, the final retract and the start
  ASSERT_GT(lifts, 0);
  // The shares (tests/data/expected.txt, AirMoves/<case>): hops below the
  // safe height, air time against retracting to it, and entries fed from
  // farther than 4 air_clearance (the fed part of an entry starts at the
  // lowest height whose rapid descent is clear, about air_clearance above
  // the surface).
  const std::string name = std::string("AirMoves/") + c.name;
  EXPECT_TRUE(test::meets_expected(name, "low_lift_share", double(low_lifts) / lifts));
  EXPECT_TRUE(test::meets_expected(name, "air_time_share", air_minutes / safe_minutes));
  EXPECT_TRUE(test::meets_expected(name, "long_entry_share",
                                   entries > 0 ? double(long_entries) / entries : 0.0))
      << long_entries << " of " << entries;
  EXPECT_TRUE(test::meets_expected(name, "final_fed_lift", final_fed));
  // The estimate adds the moves up at the rates (1e-9 relative: the same
  // lengths summed in another order).
  const PathLengths len = measure(t);
  EXPECT_NEAR(res.metrics.machine_time,
              60 * ((len.feed + len.ramp) / p.feed_rate + len.plunge / p.plunge_rate +
                    len.rapid / p.rapid_rate),
              1e-9 * res.metrics.machine_time);
  EXPECT_NEAR(res.metrics.cutting_time, 60 * len.feed / p.feed_rate,
              1e-9 * res.metrics.cutting_time);
}

INSTANTIATE_TEST_SUITE_P(
    Models, AirMoves,
    ::testing::Values(AirCase{"MAT", mat, first_face, 3.0, 0.05},
                      AirCase{"house_on_the_hill", test::house_on_the_hill,
                              test::house_on_the_hill_picked, 3.0, 0.05},
                      // Its last pass ends beside a wall.
                      AirCase{"house_on_the_hill_fine", test::house_on_the_hill,
                              test::house_on_the_hill_picked, 3.0, 0.01},
                      // Its passes run up and down the walls.
                      AirCase{"house_on_the_hill_ConstantScallop", test::house_on_the_hill,
                              test::house_on_the_hill_picked, 3.0, 0.05,
                              IsoPattern::ConstantScallop}),
    [](const ::testing::TestParamInfo<AirCase>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace isocam
