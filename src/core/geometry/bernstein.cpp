#include "geometry/bernstein.h"

#include <algorithm>
#include <cmath>
#include <queue>

namespace isocam {
namespace {

// Binomial coefficients as doubles; exact for the degrees we meet (< 60).
double binom(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  k = std::min(k, n - k);
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

int sign_changes(const std::vector<double>& c) {
  int changes = 0, last = 0;
  for (double v : c) {
    const int s = (v > 0) - (v < 0);
    if (s == 0) continue;
    if (last != 0 && s != last) ++changes;
    last = s;
  }
  return changes;
}

// Root of f in (0, 1) where f(0) and f(1) have opposite signs, by bisection
// (about 55 halvings reach double precision; robust where Newton is not).
double bisect_root(const Bernstein& f) {
  double a = 0.0, b = 1.0;
  const bool rising = f[static_cast<std::size_t>(f.degree())] > 0;
  for (int it = 0; it < 60 && b - a > 1e-15; ++it) {
    const double m = 0.5 * (a + b);
    const double fm = f.eval(m);
    if ((fm > 0) == rising) {
      b = m;
    } else {
      a = m;
    }
  }
  return 0.5 * (a + b);
}

void append_merged(std::vector<Interval>& out, Interval iv) {
  if (!out.empty() && iv.lo <= out.back().hi + 1e-15) {
    out.back().hi = std::max(out.back().hi, iv.hi);
  } else {
    out.push_back(iv);
  }
}

void positive_rec(const Bernstein& f, double a, double b, double t_tol, double slack, int depth,
                  std::vector<Interval>& out) {
  const double hi = f.max_coeff();
  if (hi <= slack) return;  // provably (almost) non-positive
  const double lo = f.min_coeff();
  if (lo > 0) {
    append_merged(out, {a, b});
    return;
  }
  const auto& c = f.coeffs();
  if (sign_changes(c) == 1 && c.front() != 0.0 && c.back() != 0.0) {
    // Exactly one simple root in (a, b).
    const double r = a + (b - a) * bisect_root(f);
    if (c.front() > 0) {
      append_merged(out, {a, r});
    } else {
      append_merged(out, {r, b});
    }
    return;
  }
  if (b - a < t_tol || depth > 60) {
    // Unresolved (a double root or a cluster): be conservative.
    if (f.eval(0.5) > 0 || hi > slack) append_merged(out, {a, b});
    return;
  }
  auto halves = f.split(0.5);
  const double m = 0.5 * (a + b);
  positive_rec(halves.first, a, m, t_tol, slack, depth + 1, out);
  positive_rec(halves.second, m, b, t_tol, slack, depth + 1, out);
}

}  // namespace

Bernstein Bernstein::constant(double value, int degree) {
  return Bernstein(std::vector<double>(static_cast<std::size_t>(degree) + 1, value));
}

double Bernstein::eval(double t) const {
  std::vector<double> b = c_;
  const double s = 1.0 - t;
  for (std::size_t k = 1; k < b.size(); ++k) {
    for (std::size_t i = 0; i + k < b.size(); ++i) b[i] = s * b[i] + t * b[i + 1];
  }
  return b.empty() ? 0.0 : b[0];
}

double Bernstein::min_coeff() const { return *std::min_element(c_.begin(), c_.end()); }
double Bernstein::max_coeff() const { return *std::max_element(c_.begin(), c_.end()); }

Bernstein Bernstein::elevated(int to) const {
  const int n = degree();
  if (to <= n) return *this;
  // Elevation by r at once: c'_k = sum_j C(n,j) C(r,k-j) / C(n+r,k) c_j.
  const int r = to - n;
  std::vector<double> e(static_cast<std::size_t>(to) + 1, 0.0);
  for (int k = 0; k <= to; ++k) {
    double s = 0.0;
    for (int j = std::max(0, k - r); j <= std::min(n, k); ++j) {
      s += binom(n, j) * binom(r, k - j) * c_[static_cast<std::size_t>(j)];
    }
    e[static_cast<std::size_t>(k)] = s / binom(to, k);
  }
  return Bernstein(std::move(e));
}

std::pair<Bernstein, Bernstein> Bernstein::split(double t) const {
  const std::size_t n = c_.size();
  std::vector<double> b = c_, left(n), right(n);
  const double s = 1.0 - t;
  left[0] = b[0];
  right[n - 1] = b[n - 1];
  for (std::size_t k = 1; k < n; ++k) {
    for (std::size_t i = 0; i + k < n; ++i) b[i] = s * b[i] + t * b[i + 1];
    left[k] = b[0];
    right[n - 1 - k] = b[n - 1 - k];
  }
  return {Bernstein(std::move(left)), Bernstein(std::move(right))};
}

Bernstein Bernstein::restricted(double a, double b) const {
  if (a <= 0.0 && b >= 1.0) return *this;
  Bernstein right = a > 0.0 ? split(a).second : *this;
  if (b >= 1.0) return right;
  return right.split((b - a) / (1.0 - a)).first;
}

Bernstein operator*(const Bernstein& f, const Bernstein& g) {
  // Product in Bernstein form:
  //   h_k = sum_{i+j=k} C(m,i) C(n,j) / C(m+n,k) f_i g_j.
  const int m = f.degree(), n = g.degree();
  std::vector<double> h(static_cast<std::size_t>(m + n) + 1, 0.0);
  for (int i = 0; i <= m; ++i) {
    const double fi = binom(m, i) * f[static_cast<std::size_t>(i)];
    for (int j = 0; j <= n; ++j) {
      h[static_cast<std::size_t>(i + j)] += fi * binom(n, j) * g[static_cast<std::size_t>(j)];
    }
  }
  for (int k = 0; k <= m + n; ++k) h[static_cast<std::size_t>(k)] /= binom(m + n, k);
  return Bernstein(std::move(h));
}

namespace {
template <class Op>
Bernstein combine(const Bernstein& f, const Bernstein& g, Op op) {
  const int d = std::max(f.degree(), g.degree());
  Bernstein a = f.elevated(d), b = g.elevated(d);
  std::vector<double> c(static_cast<std::size_t>(d) + 1);
  for (std::size_t i = 0; i < c.size(); ++i) c[i] = op(a[i], b[i]);
  return Bernstein(std::move(c));
}
}  // namespace

Bernstein operator+(const Bernstein& f, const Bernstein& g) {
  return combine(f, g, [](double x, double y) { return x + y; });
}
Bernstein operator-(const Bernstein& f, const Bernstein& g) {
  return combine(f, g, [](double x, double y) { return x - y; });
}
Bernstein operator*(double s, const Bernstein& f) {
  std::vector<double> c = f.coeffs();
  for (double& v : c) v *= s;
  return Bernstein(std::move(c));
}

std::vector<Interval> positive_intervals(const Bernstein& f, double t_tol, double slack) {
  std::vector<Interval> out;
  if (f.degree() < 0) return out;
  positive_rec(f, 0.0, 1.0, t_tol, slack, 0, out);
  return out;
}

double max_ratio(const Bernstein& num, const Bernstein& den, double rel_tol) {
  // Branch and bound. With num and den at the same degree and den's
  // coefficients positive, num/den <= max_k num_k/den_k on the piece (num is
  // a combination of the same Bernstein basis as den); the bound is exact for
  // a constant ratio and converges quadratically under subdivision. The
  // lower bound is the actual ratio at the piece's ends.
  const int d = std::max(num.degree(), den.degree());
  struct Piece {
    Bernstein n, d;
    double upper;
    bool operator<(const Piece& o) const { return upper < o.upper; }
  };
  auto upper = [](const Bernstein& n, const Bernstein& dd) {
    double u = -1e300;
    for (std::size_t k = 0; k < n.coeffs().size(); ++k) {
      if (!(dd[k] > 0)) return 1e300;  // no bound without a positive denominator
      u = std::max(u, n[k] / dd[k]);
    }
    return u;
  };
  auto at_ends = [](const Bernstein& n, const Bernstein& dd) {
    const std::size_t k = static_cast<std::size_t>(n.degree());
    return std::max(n[0] / dd[0], n[k] / dd[k]);
  };
  const Bernstein n0 = num.elevated(d), d0 = den.elevated(d);
  double best = at_ends(n0, d0);
  std::priority_queue<Piece> queue;
  queue.push({n0, d0, upper(n0, d0)});
  for (int it = 0; it < 2000 && !queue.empty(); ++it) {
    const Piece& top = queue.top();
    if (top.upper <= best + rel_tol * std::abs(best) + 1e-300) return top.upper;
    auto ns = top.n.split(0.5);
    auto ds = top.d.split(0.5);
    queue.pop();
    best = std::max({best, at_ends(ns.first, ds.first), at_ends(ns.second, ds.second)});
    queue.push({ns.first, ds.first, upper(ns.first, ds.first)});
    queue.push({ns.second, ds.second, upper(ns.second, ds.second)});
  }
  return queue.empty() ? best : std::max(best, queue.top().upper);
}

}  // namespace isocam
