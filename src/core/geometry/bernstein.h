// Scalar polynomials in Bernstein form on the local interval [0, 1].
//
// These carry the symbolic part of Elber & Cohen's Definition 4: the squared
// iso-distance between two (rational) Bezier isocurve spans is built exactly
// from differences and products of Bernstein polynomials, and its crossings
// with delta^2 are isolated with convex-hull bounds and subdivision (Lane and
// Riesenfeld): a coefficient range that excludes zero proves there is no root,
// a single sign change in the coefficients proves there is exactly one
// (variation diminishing property), so no crossing can be missed.
#pragma once

#include <utility>
#include <vector>

namespace isocam {

class Bernstein {
 public:
  Bernstein() = default;
  explicit Bernstein(std::vector<double> coeffs) : c_(std::move(coeffs)) {}
  static Bernstein constant(double value, int degree);

  int degree() const { return static_cast<int>(c_.size()) - 1; }
  const std::vector<double>& coeffs() const { return c_; }
  double operator[](std::size_t i) const { return c_[i]; }

  double eval(double t) const;  // de Casteljau, stable on [0, 1]
  double min_coeff() const;     // lower bound of the polynomial on [0, 1]
  double max_coeff() const;     // upper bound of the polynomial on [0, 1]

  Bernstein elevated(int to_degree) const;
  // The same polynomial re-parameterised on [a, b] within [0, 1].
  Bernstein restricted(double a, double b) const;
  std::pair<Bernstein, Bernstein> split(double t) const;

  friend Bernstein operator*(const Bernstein& f, const Bernstein& g);
  friend Bernstein operator+(const Bernstein& f, const Bernstein& g);
  friend Bernstein operator-(const Bernstein& f, const Bernstein& g);
  friend Bernstein operator*(double s, const Bernstein& f);

 private:
  std::vector<double> c_;
};

struct Interval {
  double lo = 0.0, hi = 0.0;
};

// The maximal sub-intervals of [0, 1] on which f > 0, in increasing order.
// Roots are located to within `t_tol` by subdivision and then refined by
// bisection to machine precision where a single sign change isolates them.
// An interval narrower than `t_tol` whose hull is not provably <= `slack`
// is reported as positive (conservative: the caller inserts a curve there);
// `slack` >= 0 lets a tangential touch that exceeds zero by less than it count
// as non-positive.
std::vector<Interval> positive_intervals(const Bernstein& f, double t_tol, double slack);

// max over [0, 1] of num/den (den > 0 there), to within relative `rel_tol`,
// by branch and bound on the coefficient hulls. Returns the upper bound.
double max_ratio(const Bernstein& num, const Bernstein& den, double rel_tol);

}  // namespace isocam
