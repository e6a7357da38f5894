// Border passes where the reach ends (issue 10): the places between two
// adjacent passes that only one of them reaches get middle passes until
// the one pass that reaches is close enough alone.
#include "finishing/reach_border.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "geometry/iso_distance.h"

namespace isocam {
namespace {

using Intervals = std::vector<Interval>;

// Sorted, disjoint, touching ones merged.
Intervals normalised(Intervals v) {
  std::sort(v.begin(), v.end(), [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
  Intervals out;
  for (const Interval& x : v) {
    if (!(x.hi > x.lo)) continue;
    if (!out.empty() && x.lo <= out.back().hi) {
      out.back().hi = std::max(out.back().hi, x.hi);
    } else {
      out.push_back(x);
    }
  }
  return out;
}

// Both normalised.
Intervals intersection(const Intervals& a, const Intervals& b) {
  Intervals out;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double lo = std::max(a[i].lo, b[j].lo), hi = std::min(a[i].hi, b[j].hi);
    if (hi > lo) out.push_back({lo, hi});
    (a[i].hi < b[j].hi ? i : j) += 1;
  }
  return out;
}

// The parts of [lo, hi] in exactly one of a and b (normalised).
Intervals exactly_one(const Intervals& a, const Intervals& b, double lo, double hi) {
  const Intervals only_a = intersection(a, complement(b, lo, hi));
  const Intervals only_b = intersection(b, complement(a, lo, hi));
  Intervals both = only_a;
  both.insert(both.end(), only_b.begin(), only_b.end());
  return normalised(both);
}

class BorderRefiner {
 public:
  BorderRefiner(const BorderFace& f, const IsoParams& p, const ClearanceModel& model)
      : f_(f), p_(p), model_(model) {
    for (const CutPiece* piece : f.cut) {
      const auto [lo, hi] = std::minmax_element(piece->t.begin(), piece->t.end());
      kept_[piece->level].push_back({*lo, *hi});
    }
    for (auto& [level, v] : kept_) v = normalised(v);
  }

  BorderCut run() {
    for (const CoverageStrip& s : f_.coverage->strips) refine(s.v1, s.v2, {s.span}, 0);
    return std::move(out_);
  }

 private:
  // The strip between levels v1 < v2 over `dom`: where exactly one curve
  // keeps a piece (the other is cut there: no clearance, no reach from
  // above, or outside the face's wires), the material between is cut from
  // that side alone. A point there is, across the strip, no farther than the
  // pair's iso-distance m from the curve that keeps it, nor farther than
  // hypot(l, m / 2) from the nearest kept end of the other (l: the part's
  // length, halved if the other keeps both its ends), whichever is less,
  // call it d; a ball d away leaves what two passes 2 d apart leave at their
  // cusp (StepoverField::scallop()). Parts where that exceeds the scallop
  // height get a middle pass (clipped to the face and cut as every pass
  // is), which halves their strip, up to kMaxDepth times; the bound of what
  // is accepted enters the certificate.
  void refine(double v1, double v2, const Intervals& dom, int depth) {
    const Intervals& k1 = kept(v1);
    const Intervals& k2 = kept(v2);
    const PiecewiseBezier c1 = f_.grid->iso_v(v1), c2 = f_.grid->iso_v(v2);
    Intervals over;
    for (const Interval& d : dom)
      for (const Interval& x : exactly_one(k1, k2, d.lo, d.hi)) {
        if (!(x.hi - x.lo > kMinPart * (f_.grid->umax() - f_.grid->umin()))) continue;
        const bool first_keeps = covers(k1, 0.5 * (x.lo + x.hi));
        const double reach = end_reach(first_keeps ? k2 : k1, x, v1, v2);
        double worst = 0.0;
        for (const IsoDistancePiece& piece : iso_distance_squared(c1, c2, x.lo, x.hi)) {
          const double m = max_iso_distance({piece});
          const double dist = std::min(m, std::hypot(reach, 0.5 * m));
          const int span = f_.grid->span_of_u(0.5 * (piece.a + piece.b));
          worst = std::max(worst, f_.field->scallop(span, v1, v2, 2.0 * dist));
        }
        if (worst <= p_.scallop_height || depth >= kMaxDepth) {
          out_.max_scallop = std::max(out_.max_scallop, worst);
        } else {
          over.push_back(x);
        }
      }
    if (over.empty()) return;
    const double vm = 0.5 * (v1 + v2);
    std::vector<SubIsocurve> mids;
    for (const Interval& x : over)
      for (const Interval& in : f_.trim->inside(f_.iso_v, vm, x.lo, x.hi))
        mids.push_back({f_.face, f_.dir, vm, in.lo, in.hi});
    const std::vector<PlannedCurve> plan = plan_face(*f_.grid, mids, p_);
    FacePathStats stats;
    std::vector<CutPiece> cut =
        cut_planned(*f_.grid, plan.data(), plan.data() + plan.size(), p_, model_, &stats);
    out_.curves += stats.curves;
    for (const CutPiece& piece : cut) {
      const auto [lo, hi] = std::minmax_element(piece.t.begin(), piece.t.end());
      kept_[vm].push_back({*lo, *hi});
    }
    kept_[vm] = normalised(kept_[vm]);
    std::move(cut.begin(), cut.end(), std::back_inserter(out_.pieces));
    refine(v1, vm, over, depth + 1);
    refine(vm, v2, over, depth + 1);
  }

  const Intervals& kept(double v) { return kept_[v]; }

  static bool covers(const Intervals& v, double t) {
    for (const Interval& x : v)
      if (x.lo <= t && t <= x.hi) return true;
    return false;
  }

  // How far along the part x a point is at most from the nearest end of
  // `other` (the curve that does not keep x) that other keeps: the part's
  // length (the larger of its lengths on the two levels, summed over 16
  // chords) if it keeps one end, half of it if both, infinite if neither.
  double end_reach(const Intervals& other, const Interval& x, double v1, double v2) const {
    bool lo_end = false, hi_end = false;
    for (const Interval& y : other) {
      lo_end = lo_end || y.hi == x.lo;
      hi_end = hi_end || y.lo == x.hi;
    }
    if (!lo_end && !hi_end) return std::numeric_limits<double>::infinity();
    double length = 0.0;
    for (double v : {v1, v2}) {
      double l = 0.0;
      gp_Pnt prev = f_.grid->eval(x.lo, v);
      for (int k = 1; k <= 16; ++k) {
        const gp_Pnt q = f_.grid->eval(x.lo + (x.hi - x.lo) * k / 16.0, v);
        l += prev.Distance(q);
        prev = q;
      }
      length = std::max(length, l);
    }
    return lo_end && hi_end ? 0.5 * length : length;
  }

  static constexpr int kMaxDepth = 4;
  // Parts shorter than this (relative to the curves' range) are rounding.
  static constexpr double kMinPart = 1e-9;

  const BorderFace& f_;
  const IsoParams& p_;
  const ClearanceModel& model_;
  std::map<double, Intervals> kept_;  // per level: the parts its pieces keep
  BorderCut out_;
};

}  // namespace

BorderCut border_pieces(const BorderFace& face, const IsoParams& params,
                        const ClearanceModel& model) {
  return BorderRefiner(face, params, model).run();
}

}  // namespace isocam
