#include "toolpath/linearize.h"

#include <algorithm>
#include <gp_Vec.hxx>

namespace isocam {
namespace {

double distance_to_segment(const gp_Pnt& p, const gp_Pnt& a, const gp_Pnt& b) {
  const gp_Vec ab(a, b), ap(a, p);
  const double l2 = ab.SquareMagnitude();
  if (l2 <= 0) return a.Distance(p);
  const double s = std::clamp(ap.Dot(ab) / l2, 0.0, 1.0);
  return p.Distance(a.Translated(ab * s));
}

struct Refiner {
  const std::function<gp_Pnt(double)>& f;
  double tol;
  std::vector<gp_Pnt>& out;
  std::vector<double>* params;

  void run(double ta, const gp_Pnt& pa, double tb, const gp_Pnt& pb, int depth) {
    const double tm = 0.5 * (ta + tb);
    const gp_Pnt pm = f(tm);
    if (depth < 30) {
      const gp_Pnt q1 = f(0.5 * (ta + tm)), q3 = f(0.5 * (tm + tb));
      const double dev = std::max({distance_to_segment(pm, pa, pb), distance_to_segment(q1, pa, pb),
                                   distance_to_segment(q3, pa, pb)});
      // The chord's largest deviation need not fall on a quarter point: keep
      // a 10% margin so the tolerance holds between them too.
      if (dev > 0.9 * tol) {
        run(ta, pa, tm, pm, depth + 1);
        run(tm, pm, tb, pb, depth + 1);
        return;
      }
    }
    out.push_back(pb);
    if (params) params->push_back(tb);
  }
};

}  // namespace

std::vector<gp_Pnt> linearize(const std::function<gp_Pnt(double)>& f, double t0, double t1,
                              double tol, const std::vector<double>& breaks, int min_pieces,
                              std::vector<double>* params) {
  std::vector<double> knots{t0};
  const double lo = std::min(t0, t1), hi = std::max(t0, t1);
  std::vector<double> inner;
  for (double b : breaks)
    if (b > lo + 1e-12 * (hi - lo) && b < hi - 1e-12 * (hi - lo)) inner.push_back(b);
  std::sort(inner.begin(), inner.end(),
            [&](double a, double b) { return t1 >= t0 ? a < b : a > b; });
  knots.insert(knots.end(), inner.begin(), inner.end());
  knots.push_back(t1);

  std::vector<gp_Pnt> out{f(t0)};
  if (params) params->assign(1, t0);
  Refiner r{f, tol, out, params};
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    const double a = knots[k], b = knots[k + 1];
    gp_Pnt pa = out.back();
    for (int i = 1; i <= min_pieces; ++i) {
      const double tb = a + (b - a) * i / min_pieces;
      const gp_Pnt pb = f(tb);
      r.run(a + (b - a) * (i - 1) / min_pieces, pa, tb, pb, 0);
      pa = pb;
    }
  }
  return out;
}

}  // namespace isocam
