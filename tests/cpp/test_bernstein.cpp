// The Bernstein algebra under the symbolic iso-distance: each operation is
// checked against point-wise evaluation, the root isolation against
// polynomials whose roots are known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geometry/bernstein.h"

namespace isocam {
namespace {

// Power basis sum a_i t^i to Bernstein form: b_k = sum_{i<=k} C(k,i)/C(n,i) a_i.
Bernstein from_power(const std::vector<double>& a) {
  const int n = static_cast<int>(a.size()) - 1;
  auto binom = [](int nn, int k) {
    double r = 1;
    for (int i = 1; i <= k; ++i) r = r * (nn - k + i) / i;
    return r;
  };
  std::vector<double> b(a.size(), 0.0);
  for (int k = 0; k <= n; ++k)
    for (int i = 0; i <= k; ++i) b[k] += binom(k, i) / binom(n, i) * a[i];
  return Bernstein(b);
}

// prod (t - r_i) as a Bernstein polynomial, scaled by s.
Bernstein with_roots(const std::vector<double>& roots, double s = 1.0) {
  Bernstein f = Bernstein::constant(s, 0);
  for (double r : roots) f = f * Bernstein({-r, 1.0 - r});
  return f;
}

Bernstein random_poly(std::mt19937& rng, int degree) {
  std::uniform_real_distribution<double> d(-2, 2);
  std::vector<double> c(degree + 1);
  for (double& v : c) v = d(rng);
  return Bernstein(c);
}

TEST(Bernstein, ProductSumElevationRestrictionMatchPointwise) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const Bernstein f = random_poly(rng, 1 + trial % 6), g = random_poly(rng, 2 + trial % 5);
    const Bernstein prod = f * g, sum = f + g, diff = f - g, up = f.elevated(f.degree() + 4);
    const Bernstein piece = f.restricted(0.2, 0.7);
    for (int i = 0; i <= 20; ++i) {
      const double t = i / 20.0;
      EXPECT_NEAR(prod.eval(t), f.eval(t) * g.eval(t), 1e-12);
      EXPECT_NEAR(sum.eval(t), f.eval(t) + g.eval(t), 1e-12);
      EXPECT_NEAR(diff.eval(t), f.eval(t) - g.eval(t), 1e-12);
      EXPECT_NEAR(up.eval(t), f.eval(t), 1e-12);
      EXPECT_NEAR(piece.eval(t), f.eval(0.2 + 0.5 * t), 1e-12);
    }
  }
}

TEST(Bernstein, PowerBasisConversionIsExact) {
  const Bernstein f = from_power({1.0, -3.0, 0.5, 2.0});
  for (double t : {0.0, 0.3, 0.77, 1.0})
    EXPECT_NEAR(f.eval(t), 1 - 3 * t + 0.5 * t * t + 2 * t * t * t, 1e-14);
}

TEST(Bernstein, FindsEveryCrossingOfManyRoots) {
  // Nine simple roots, two of them 1e-4 apart: positive exactly between
  // alternate pairs.
  const std::vector<double> roots = {0.05, 0.1, 0.31, 0.3101, 0.45, 0.6, 0.72, 0.9, 0.97};
  const Bernstein f = with_roots(roots, -1.0);  // f(0) > 0 since 9 roots and s = -1
  const auto iv = positive_intervals(f, 1e-12, 0.0);
  ASSERT_EQ(iv.size(), 5u);
  EXPECT_NEAR(iv[0].lo, 0.0, 1e-15);
  // 1e-10: the close pair's roots are conditioned to about that.
  EXPECT_NEAR(iv[0].hi, 0.05, 1e-10);
  for (std::size_t k = 1; k < 5; ++k) {
    EXPECT_NEAR(iv[k].lo, roots[2 * k - 1], 1e-10);
    EXPECT_NEAR(iv[k].hi, roots[2 * k], 1e-10);
  }
}

TEST(Bernstein, TangentialTouchFromBelowIsNotAnExcess) {
  // (t - 0.4)^2 (t - 2) <= 0 on [0, 1], touching zero at 0.4. Subdivision
  // alone cannot prove the touch non-positive; the slack (far below any
  // length we care about) does.
  const Bernstein f = with_roots({0.4, 0.4, 2.0}, 1.0);  // = (t-0.4)^2 (t-2) <= 0
  EXPECT_TRUE(positive_intervals(f, 1e-12, 1e-12).empty());
  // The same touch from above is positive everywhere but at one point.
  const Bernstein g = with_roots({0.4, 0.4, 2.0}, -1.0);
  const auto iv = positive_intervals(g, 1e-12, 1e-12);
  ASSERT_FALSE(iv.empty());
  EXPECT_NEAR(iv.front().lo, 0.0, 1e-15);
  EXPECT_NEAR(iv.back().hi, 1.0, 1e-15);
  // Only where g <= slack, |t - 0.4| <= sqrt(slack / 1.6), may be left out.
  double covered = 0;
  for (const Interval& i : iv) covered += i.hi - i.lo;
  EXPECT_GT(covered, 1.0 - 2.02 * std::sqrt(1e-12 / 1.6));
}

TEST(Bernstein, MaxRatioMatchesDenseSampling) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const Bernstein num = random_poly(rng, 6);
    std::vector<double> dc(5);
    for (double& v : dc) v = 0.5 + std::uniform_real_distribution<double>(0, 1)(rng);
    const Bernstein den(dc);
    double sampled = -1e300;
    for (int i = 0; i <= 20000; ++i)
      sampled = std::max(sampled, num.eval(i / 20000.0) / den.eval(i / 20000.0));
    const double bound = max_ratio(num, den, 1e-9);
    EXPECT_GE(bound, sampled - 1e-12);
    EXPECT_LE(bound, sampled + 1e-6 * (1 + std::abs(sampled)));
  }
}

}  // namespace
}  // namespace isocam
