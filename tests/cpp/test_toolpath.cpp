// The Toolpath's contract (isocam/toolpath.h): arc centres absent until the
// first arc, then one per move (NaN for the others), through add, add_arc
// and append; measure() takes an arc along the arc (a helix if z changes).
#include <gtest/gtest.h>

#include <cmath>

#include "isocam/toolpath.h"

namespace isocam {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The centre columns are empty or one per move (the header's invariant).
void expect_consistent(const Toolpath& t) {
  EXPECT_EQ(t.x.size(), t.size());
  EXPECT_EQ(t.y.size(), t.size());
  EXPECT_EQ(t.z.size(), t.size());
  EXPECT_EQ(t.cx.size(), t.cy.size());
  EXPECT_TRUE(t.cx.empty() || t.cx.size() == t.size());
  EXPECT_EQ(t.has_arcs(), !t.cx.empty());
  for (std::size_t i = 0; i < t.cx.size(); ++i)
    EXPECT_EQ(is_arc(t.kind[i]), !std::isnan(t.cx[i])) << "move " << i;
}

TEST(Toolpath, CentresOnlyOnceThereIsAnArc) {
  Toolpath t;
  t.add(MoveKind::Rapid, 0, 0, 5);
  t.add(MoveKind::Plunge, 0, 0, 0);
  EXPECT_FALSE(t.has_arcs());
  EXPECT_TRUE(t.cx.empty());
  expect_consistent(t);
  t.add_arc(true, 2, 0, 0, 1, 0);  // G3 half turn about (1, 0)
  t.add(MoveKind::Feed, 3, 0, 0);
  ASSERT_TRUE(t.has_arcs());
  expect_consistent(t);
  EXPECT_EQ(t.kind[2], static_cast<std::uint8_t>(MoveKind::ArcCCW));
  EXPECT_EQ(t.cx[2], 1.0);
  EXPECT_EQ(t.cy[2], 0.0);
}

TEST(Toolpath, AppendKeepsTheCentresAligned) {
  Toolpath lines, arcs;
  lines.add(MoveKind::Rapid, 0, 0, 5);
  lines.add(MoveKind::Feed, 1, 0, 5);
  arcs.add(MoveKind::Feed, 2, 0, 5);
  arcs.add_arc(false, 4, 0, 5, 3, 0);
  Toolpath a = lines;  // no arcs, then arcs
  a.append(arcs);
  expect_consistent(a);
  ASSERT_EQ(a.size(), 4u);
  EXPECT_EQ(a.cx[3], 3.0);
  Toolpath b = arcs;  // arcs, then no arcs
  b.append(lines);
  expect_consistent(b);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b.cx[1], 3.0);
  Toolpath c = lines;  // neither has arcs: the columns stay empty
  c.append(lines);
  EXPECT_FALSE(c.has_arcs());
  expect_consistent(c);
}

TEST(Toolpath, MeasureTakesArcsAlongTheArc) {
  Toolpath t;
  t.add(MoveKind::Rapid, 2, 0, 0);
  t.add_arc(true, -2, 0, 0, 0, 0);   // G3 (2,0) -> (-2,0) about 0: half turn, 2 pi
  t.add_arc(true, 0, -2, 0, 0, 0);   // G3 on to (0,-2): a quarter, pi
  t.add_arc(false, 0, -2, 0, 0, 0);  // G2 ending where it starts: a full turn, 4 pi
  t.add_arc(false, 2, 0, 3, 0, 0);   // G2 (0,-2) -> (2,0): three quarters, 3 pi, rising 3 mm
  const PathLengths m = measure(t);
  EXPECT_EQ(m.arcs, 4);
  EXPECT_EQ(m.cutting_moves, 4);
  const double helix = std::hypot(3 * kPi, 3.0);
  EXPECT_NEAR(m.feed, 2 * kPi + kPi + 4 * kPi + helix, 1e-12);
  EXPECT_EQ(m.rapid, 0.0);
  EXPECT_EQ(m.retracts, 0);
  // Arcs are cut at the horizontal feed: 1 mm/s at 60 mm/min.
  const PathTimes times = estimate_time(t, 60.0, 30.0, 1000.0);
  EXPECT_NEAR(times.feed, m.feed, 1e-12);
  EXPECT_NEAR(times.total, m.feed, 1e-12);
}

TEST(Toolpath, MeasureCountsMovesByKind) {
  Toolpath t;
  t.add(MoveKind::Rapid, 0, 0, 10);
  t.add(MoveKind::Rapid, 0, 0, 1);
  t.add(MoveKind::Plunge, 0, 0, 0);  // 1 mm
  t.add(MoveKind::Feed, 3, 4, 0);    // 5 mm
  t.add(MoveKind::Ramp, 3, 4, -1);   // 1 mm
  t.add(MoveKind::Plunge, 3, 4, 2);  // fed lift, 3 mm: the retract
  t.add(MoveKind::Rapid, 3, 4, 10);  // the same retract, 8 mm
  const PathLengths m = measure(t);
  EXPECT_DOUBLE_EQ(m.feed, 5.0);
  EXPECT_DOUBLE_EQ(m.plunge, 4.0);
  EXPECT_DOUBLE_EQ(m.ramp, 1.0);
  EXPECT_DOUBLE_EQ(m.rapid, 17.0);
  EXPECT_EQ(m.retracts, 1);
  EXPECT_EQ(m.arcs, 0);
  EXPECT_EQ(m.cutting_moves, 1);
  EXPECT_FALSE(t.has_arcs());
}

}  // namespace
}  // namespace isocam
