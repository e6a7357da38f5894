// Definition 4: the symbolic squared iso-distance against point-wise
// evaluation, and its crossings with delta^2 on curves built to cross many
// times and to touch tangentially.
#include <gtest/gtest.h>

#include <BRepPrimAPI_MakeSphere.hxx>
#include <TopoDS.hxx>
#include <cmath>

#include "geometry/iso_distance.h"
#include "isocam/brep_io.h"
#include "support/models.h"

namespace isocam {
namespace {

void expect_matches_pointwise(const PatchGrid& g, double v1, double v2) {
  const PiecewiseBezier c1 = g.iso_v(v1), c2 = g.iso_v(v2);
  const double a = g.umin() + 0.1 * (g.umax() - g.umin());
  const double b = g.umax() - 0.05 * (g.umax() - g.umin());
  const auto pieces = iso_distance_squared(c1, c2, a, b);
  ASSERT_FALSE(pieces.empty());
  EXPECT_DOUBLE_EQ(pieces.front().a, a);
  EXPECT_DOUBLE_EQ(pieces.back().b, b);
  for (const IsoDistancePiece& p : pieces) {
    for (int i = 0; i <= 10; ++i) {
      const double s = i / 10.0, t = p.a + (p.b - p.a) * s;
      const double symbolic = p.num.eval(s) / p.den.eval(s);
      const double direct = c1.eval(t).SquareDistance(c2.eval(t));
      EXPECT_NEAR(symbolic, direct, 1e-9 * (1 + direct)) << "t = " << t;
    }
  }
}

TEST(IsoDistance, PolynomialBsplineMatchesPointwise) {
  const PatchGrid g = PatchGrid::from_face(test::face(test::load("MAT.brep"), 0), 0);
  EXPECT_FALSE(g.rational());
  expect_matches_pointwise(g, g.vmin() + 3.3, g.vmin() + 4.1);
  expect_matches_pointwise(g.transposed(), g.umin() + 10.7, g.umin() + 30.2);
}

TEST(IsoDistance, RationalSphereMatchesPointwise) {
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(25.0).Shape();
  const PatchGrid g = PatchGrid::from_face(test::face(sphere, 0), 0);
  EXPECT_TRUE(g.rational());
  expect_matches_pointwise(g, -0.7, 0.4);
  expect_matches_pointwise(g.transposed(), 1.0, 2.5);
}

// Two one-span curves of degree n: C1(t) = (100 t, 0, 0), C2(t) = (100 t, 0,
// h(t)) with h in Bernstein form, so Delta = h exactly.
std::pair<PiecewiseBezier, PiecewiseBezier> curves_with_gap(const Bernstein& h) {
  PiecewiseBezier c1, c2;
  c1.degree = c2.degree = h.degree();
  c1.breaks = c2.breaks = {0.0, 1.0};
  for (int i = 0; i <= h.degree(); ++i) {
    const double x = 100.0 * i / h.degree();
    c1.cps.push_back({x, 0, 0, 1});
    c2.cps.push_back({x, 0, h[static_cast<std::size_t>(i)], 1});
  }
  return {c1, c2};
}

Bernstein with_roots(const std::vector<double>& roots, double scale) {
  Bernstein f = Bernstein::constant(scale, 0);
  for (double r : roots) f = f * Bernstein({-r, 1.0 - r});
  return f;
}

// The contract of exceeding(): every t where Delta > delta (1 + 1e-8) lies
// in a reported interval, every t where Delta < delta (1 - 1e-8) outside all
// (the band between is the roots' conditioning, not a missed crossing).
void expect_exact_zero_set(const Bernstein& h, double delta, std::size_t expected_parts) {
  const auto [c1, c2] = curves_with_gap(h);
  const auto ex = exceeding(iso_distance_squared(c1, c2, 0.0, 1.0), delta);
  EXPECT_EQ(ex.size(), expected_parts);
  for (int i = 0; i <= 200000; ++i) {
    const double t = i / 200000.0, d = h.eval(t);
    bool inside = false;
    for (const Interval& iv : ex) inside = inside || (t >= iv.lo && t <= iv.hi);
    if (d > delta * (1 + 1e-8)) {
      EXPECT_TRUE(inside) << "missed excess at t = " << t;
    }
    if (d < delta * (1 - 1e-8)) {
      EXPECT_FALSE(inside) << "false excess at t = " << t << " Delta - delta = " << d - delta;
    }
  }
}

TEST(IsoDistance, ZeroSetIsCompleteForManyCrossings) {
  const double delta = 0.5;
  const std::vector<double> roots = {0.02, 0.11, 0.2, 0.2005, 0.43, 0.5, 0.66, 0.81};
  // h = delta + 1e3 * prod(t - r_i): crosses delta at all eight roots, two of
  // them 5e-4 apart; h > delta before the first root (even count).
  expect_exact_zero_set(Bernstein::constant(delta, 0) + with_roots(roots, 1e3), delta, 5);
  // Fifteen crossings of a degree-15 polynomial.
  std::vector<double> many;
  for (int k = 0; k < 15; ++k) many.push_back(0.03 + k * 0.0651);
  expect_exact_zero_set(Bernstein::constant(delta, 0) + with_roots(many, 1e6), delta, 8);
}

TEST(IsoDistance, TangentialTouchIsResolved) {
  const double delta = 0.5;
  // Touches delta at t = 0.37 from below: never exceeds.
  const Bernstein below = Bernstein::constant(delta, 0) - with_roots({0.37, 0.37}, 2.0);
  auto [a1, a2] = curves_with_gap(below);
  EXPECT_TRUE(exceeding(iso_distance_squared(a1, a2, 0.0, 1.0), delta).empty());
  EXPECT_NEAR(max_iso_distance(iso_distance_squared(a1, a2, 0.0, 1.0)), delta, 1e-9);
  // Touches from above: exceeds everywhere but at one point.
  const Bernstein above = Bernstein::constant(delta, 0) + with_roots({0.37, 0.37}, 2.0);
  auto [b1, b2] = curves_with_gap(above);
  const auto ex = exceeding(iso_distance_squared(b1, b2, 0.0, 1.0), delta);
  ASSERT_FALSE(ex.empty());
  EXPECT_NEAR(ex.front().lo, 0.0, 1e-15);
  EXPECT_NEAR(ex.back().hi, 1.0, 1e-15);
}

TEST(IsoDistance, ConstantGapOnSphereLatitudes) {
  // Two latitudes of a sphere are a constant chord apart at equal longitude:
  // Delta^2 - delta^2 is identically +-epsilon, the hardest case for a root
  // finder; the answer must be all or nothing.
  const TopoDS_Shape sphere = BRepPrimAPI_MakeSphere(25.0).Shape();
  // OpenCASCADE's sphere: u is the longitude, v the latitude, so iso-v
  // curves are latitude circles (the same rational parametrisation in u).
  const PatchGrid lat = PatchGrid::from_face(test::face(sphere, 0), 0);
  const double v1 = -0.3, v2 = 0.2;
  const auto pieces = iso_distance_squared(lat.iso_v(v1), lat.iso_v(v2), lat.umin(), lat.umax());
  const double chord = lat.eval(0.3, v1).Distance(lat.eval(0.3, v2));
  EXPECT_NEAR(max_iso_distance(pieces), chord, 1e-9);
  EXPECT_TRUE(exceeding(pieces, chord * (1 + 1e-7)).empty());
  const auto all = exceeding(pieces, chord * (1 - 1e-7));
  ASSERT_EQ(all.size(), 1u);
  EXPECT_NEAR(all[0].lo, lat.umin(), 1e-12);
  EXPECT_NEAR(all[0].hi, lat.umax(), 1e-12);
}

}  // namespace
}  // namespace isocam
