// Ordering, offsetting, linearisation, gouge trimming and linking of one
// face's coverage.
#include <algorithm>
#include <cmath>
#include <functional>
#include <gp.hxx>
#include <gp_Ax1.hxx>

#include "finishing/coverage.h"
#include "toolpath/linearize.h"

namespace isocam {
namespace {

gp_Pnt centre_at(const PatchGrid& g, int span, double t, double level, double r) {
  const SurfaceDerivs d = g.d1_on_span(span, t, level);
  return d.p.Translated(g.normal(t, level, &d) * r);
}

// Ball centres along a sub-isocurve, span by span with one-sided evaluation
// so that a C0 span break (a crease) is seen from both sides. Where the
// normal jumps at a convex crease the ball rolls around the crease: centres
// on the circle of radius r about the crease point, from the incoming normal
// to the outgoing one, within the chord tolerance. (At a concave crease the
// two offsets cross; the clearance trimming removes what overlaps.)
CentrePolyline centres_along(const PatchGrid& g, const SubIsocurve& c, bool forward, double r,
                             double tol) {
  std::vector<double> knots{c.t0};
  for (double b : g.ubreaks())
    if (b > c.t0 && b < c.t1) knots.push_back(b);
  knots.push_back(c.t1);
  if (!forward) std::reverse(knots.begin(), knots.end());
  CentrePolyline out;
  gp_Vec n_in;
  for (std::size_t k = 0; k + 1 < knots.size(); ++k) {
    const double a = knots[k], b = knots[k + 1];
    const int span = g.span_of_u(0.5 * (a + b));
    std::vector<double> ts;
    const auto seg = linearize([&](double t) { return centre_at(g, span, t, c.level, r); }, a, b,
                               tol, {}, 2, &ts);
    const SurfaceDerivs d0 = g.d1_on_span(span, a, c.level);
    const gp_Vec n_out = g.normal(a, c.level, &d0);
    if (!out.pts.empty() && out.pts.back().Distance(seg.front()) > 1e-9) {
      const gp_Vec travel = forward ? d0.su : -d0.su;
      const double angle = n_in.Angle(n_out);
      if (n_in.Dot(travel) < 0 && angle > 1e-9) {
        const double step = 2.0 * std::acos(std::max(-1.0, 1.0 - tol / r));
        const int steps = static_cast<int>(std::ceil(angle / step));
        const gp_Ax1 axis(gp::Origin(), gp_Dir(n_in.Crossed(n_out)));
        for (int s = 1; s < steps; ++s)
          out.push(d0.p.Translated(n_in.Rotated(axis, angle * s / steps) * r), a);
      }
    }
    for (std::size_t i = 0; i < seg.size(); ++i) out.push(seg[i], ts[i]);
    const SurfaceDerivs d1 = g.d1_on_span(span, b, c.level);
    n_in = g.normal(b, c.level, &d1);
  }
  return out;
}

// Splits a centre polyline into the runs where the ball keeps `clearance`
// from the model and is reachable from above: the column of centres straight
// above each kept centre (the tool lifted to clear the model, its shank as
// wide as the ball) keeps `clearance` too (ClearanceModel::clear_above()), so
// a 3-axis tool finishes only what it can reach, and every vertical lift from
// and entry to a piece is clear. The columns are checked at every vertex and
// at the cut ends (located as below); between two vertices, at most a chord
// of the linearisation apart, the chord itself is checked, not the columns
// above its inner points. Vertices are tested first; a boundary between a clear and
// a violating vertex is located by bisection on the curve parameter (to 1e-2
// of the chord tolerance). A chord between two clear vertices that is itself
// not clear (another part of the model comes near the chord, not the curve)
// is refined by curve points until its pieces are clear or shorter than the
// chord tolerance, so that only what truly violates is cut away.
class RunSplitter {
 public:
  RunSplitter(std::function<gp_Pnt(double)> at, const ClearanceModel& model, double clearance,
              double tol)
      : at_(std::move(at)), model_(model), clearance_(clearance), tol_(tol) {}

  // Length of the line's chords left out although the ball at both ends is
  // clear: only the column above an end is not (undersides, overhangs).
  double from_above() const { return from_above_; }

  std::vector<CentrePolyline> split(const CentrePolyline& line) {
    // A vertex is kept if its column is clear (which proves the ball there
    // clear). For the report, a dropped vertex's ball is proven clear by a
    // clear chord next to it, or else tested on its own.
    const std::size_t n = line.pts.size();
    std::vector<char> chord(n, 1), ok(n, 1), ball(n, 1);
    if (n > 1) model_.clear_polyline(line.pts.data(), n, clearance_, &chord[1]);
    model_.clear_above(line.pts.data(), n, clearance_, ok.data());
    for (std::size_t i = 0; i < n; ++i) {
      const bool sure = (i > 0 && chord[i]) || (i + 1 < n && chord[i + 1]);
      ball[i] = ok[i] || sure || model_.clear(line.pts[i], clearance_);
      if (i > 0 && ball[i - 1] && ball[i] && !(ok[i - 1] && ok[i]))
        from_above_ += line.pts[i - 1].Distance(line.pts[i]);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const double t = line.t[i];
      if (!ok[i]) {
        if (i > 0 && ok[i - 1]) end_at(boundary(line.t[i - 1], t));
        flush();
        continue;
      }
      if (i > 0 && !ok[i - 1]) {
        const double ta = boundary(t, line.t[i - 1]);
        cur_.push(at_(ta), ta);
      }
      if (cur_.pts.empty()) {
        cur_.push(line.pts[i], t);
      } else if (chord[i] && cur_.t.back() == line.t[i - 1]) {
        cur_.push(line.pts[i], t);
      } else {
        extend(cur_.t.back(), cur_.pts.back(), t, line.pts[i], 0);
      }
    }
    flush();
    return std::move(runs_);
  }

 private:
  // cur_ ends at (ta, pa), clear; pb is clear: add the chord, refined.
  void extend(double ta, const gp_Pnt& pa, double tb, const gp_Pnt& pb, int depth) {
    if (model_.clear(pa, pb, clearance_)) {
      cur_.push(pb, tb);
      return;
    }
    if (pa.Distance(pb) <= tol_ || depth >= 20) {
      flush();
      cur_.push(pb, tb);
      return;
    }
    const double tm = 0.5 * (ta + tb);
    const gp_Pnt pm = at_(tm);
    if (good(pm)) {
      extend(ta, pa, tm, pm, depth + 1);
      extend(tm, pm, tb, pb, depth + 1);
      return;
    }
    end_at(boundary(ta, tm));
    flush();
    const double t2 = boundary(tb, tm);
    cur_.push(at_(t2), t2);
    extend(t2, cur_.pts.back(), tb, pb, depth + 1);
  }

  // The last clear parameter from t_ok (clear) towards t_bad (not clear):
  // a clear point with a point not clear within 1e-2 of the chord
  // tolerance beyond it (in space). Bisection finds it, but its last steps
  // probe points within a hair of the clearance, where each query subdivides
  // down to the model's tolerance; so first the crossing is predicted from
  // the witness of t_bad and two probes placed just either side of it. Only
  // clear() answers move the bracket: a poor prediction costs probes, never
  // the contract.
  double boundary(double t_ok, double t_bad) const {
    gp_Pnt p_ok = at_(t_ok), p_bad = at_(t_bad);
    const double goal = 1e-2 * tol_;
    auto probe = [&](double t) {
      const gp_Pnt p = at_(t);
      if (good(p)) {
        t_ok = t;
        p_ok = p;
      } else {
        t_bad = t;
        p_bad = p;
      }
    };
    auto inside = [&](double t) { return (t - t_ok) * (t_bad - t) > 0; };
    ClearanceModel::Witness w;
    // (A query that ran out of budget has no witness: plain bisection.)
    if (p_ok.Distance(p_bad) > goal && !good(p_bad, &w) && w.grid) {
      const double t_star = crossing(t_ok, p_ok, t_bad, p_bad, w);
      // Probes 1/4 of the goal either side of the prediction, farther
      // (doubling) while they land on the wrong side.
      const double dt =
          std::copysign(0.25 * goal * std::abs(t_bad - t_ok) / p_ok.Distance(p_bad), t_bad - t_ok);
      for (int k = 0; k < 3 && std::isfinite(t_star) && inside(t_star - dt * (1 << k)); ++k) {
        probe(t_star - dt * (1 << k));
        if (t_ok == t_star - dt * (1 << k)) break;
      }
      for (int k = 0; k < 3 && std::isfinite(t_star) && inside(t_star + dt * (1 << k)) &&
                      p_ok.Distance(p_bad) > goal;
           ++k) {
        probe(t_star + dt * (1 << k));
        if (t_bad == t_star + dt * (1 << k)) break;
      }
    }
    for (int it = 0; it < 60 && p_ok.Distance(p_bad) > goal; ++it) probe(0.5 * (t_ok + t_bad));
    return t_ok;
  }

  // Where the distance from the path to the witness's piece of surface (its
  // local minimum near the witness) crosses the clearance, by the Illinois
  // variant of regula falsi; NaN if it does not change sign over the
  // bracket.
  double crossing(double ta, gp_Pnt pa, double tb, gp_Pnt pb, ClearanceModel::Witness w) const {
    ClearanceModel::Witness wa = w;
    double fa = ClearanceModel::local_distance(pa, &wa) - clearance_;
    double fb = ClearanceModel::local_distance(pb, &w) - clearance_;
    if (!(fa > 0 && fb < 0)) return std::nan("");
    // The probes around the prediction are 1/4 of the goal apart from it: a
    // step under 1/100 of the goal (the method converges superlinearly, so
    // the last step bounds the error) is close enough.
    const double enough = 1e-2 * 1e-4 * tol_;
    int side = 0;
    gp_Pnt last = pb;
    for (int it = 0; it < 40 && pa.Distance(pb) > enough; ++it) {
      const double t = (ta * fb - tb * fa) / (fb - fa);
      const gp_Pnt pt = at_(t);
      if (it > 0 && pt.Distance(last) < enough) return t;
      last = pt;
      ClearanceModel::Witness wt = w;
      const double ft = ClearanceModel::local_distance(pt, &wt) - clearance_;
      if (ft == 0) return t;
      if (ft > 0) {
        ta = t;
        pa = pt;
        fa = ft;
        if (side > 0) fb *= 0.5;
        side = 1;
      } else {
        tb = t;
        pb = pt;
        fb = ft;
        w = wt;
        if (side < 0) fa *= 0.5;
        side = -1;
      }
    }
    return (ta * fb - tb * fa) / (fb - fa);
  }

  // Ends the run at the clear curve point of parameter t. The chord to it
  // from the run's last point must be clear too: near a violation the curve
  // bends toward the model, and a chord cuts inside it by up to the chord
  // tolerance. Where it is not, the end moves back toward the last point.
  void end_at(double t) {
    if (cur_.pts.empty() || t == cur_.t.back()) return;
    for (int it = 0; it < 40; ++it) {
      const gp_Pnt p = at_(t);
      if (model_.clear(cur_.pts.back(), p, clearance_) && good(p)) {
        cur_.push(p, t);
        return;
      }
      if (p.Distance(cur_.pts.back()) <= 1e-4 * tol_) return;
      t = 0.5 * (t + cur_.t.back());
    }
  }

  void flush() {
    if (cur_.pts.size() > 1) runs_.push_back(std::move(cur_));
    cur_ = CentrePolyline();
  }

  // A centre the tool may take: the ball and the column above it clear.
  bool good(const gp_Pnt& p, ClearanceModel::Witness* w = nullptr) const {
    return model_.clear_above(p, clearance_, w);
  }

  std::function<gp_Pnt(double)> at_;
  const ClearanceModel& model_;
  double clearance_, tol_;
  double from_above_ = 0.0;
  CentrePolyline cur_;
  std::vector<CentrePolyline> runs_;
};

}  // namespace

double CutPiece::length() const {
  double s = 0;
  for (std::size_t i = 1; i < pts.size(); ++i) s += pts[i - 1].Distance(pts[i]);
  return s;
}

void CutPiece::reverse() {
  std::reverse(pts.begin(), pts.end());
  std::reverse(t.begin(), t.end());
  std::swap(front_normal, back_normal);
}

std::vector<PlannedCurve> plan_face(const PatchGrid& g, std::vector<SubIsocurve> curves,
                                    const IsoParams& params) {
  std::sort(curves.begin(), curves.end(), [](const SubIsocurve& a, const SubIsocurve& b) {
    return a.level < b.level || (a.level == b.level && a.t0 < b.t0);
  });
  std::vector<PlannedCurve> out;
  bool forward = true;
  for (const SubIsocurve& c : curves) {
    CentrePolyline line = centres_along(g, c, forward, params.ball_radius, params.chord_tolerance);
    // A boundary collapsed to a pole offsets to a single point: nothing to cut.
    if (line.length() <= 1e-6) continue;
    forward = !forward;  // zig-zag
    out.push_back({c, std::move(line)});
  }
  return out;
}

std::vector<CutPiece> cut_planned(const PatchGrid& g, const PlannedCurve* first,
                                  const PlannedCurve* last, const IsoParams& params,
                                  const ClearanceModel& model, FacePathStats* stats) {
  const double r = params.ball_radius, tol = params.chord_tolerance;
  // A chord of the offset may cut into it by the chord tolerance; the
  // clearance check is exact to the gouge tolerance.
  const double clearance = model.query_distance(r - tol - params.gouge_tolerance);
  FacePathStats st;
  std::vector<CutPiece> pieces;
  for (const PlannedCurve* pc = first; pc != last; ++pc) {
    const SubIsocurve& c = pc->curve;
    ++st.curves;
    double kept = 0;
    RunSplitter splitter([&](double t) { return centre_at(g, g.span_of_u(t), t, c.level, r); },
                         model, clearance, tol);
    for (CentrePolyline& run : splitter.split(pc->line)) {
      kept += run.length();
      pieces.push_back({&g, c.level, std::move(run.pts), std::move(run.t), {}, {}});
    }
    const double dropped = std::max(0.0, pc->line.length() - kept);
    st.unreachable_length += dropped;
    st.unreachable_from_above += std::min(dropped, splitter.from_above());
  }
  if (stats) *stats = st;
  return pieces;
}

std::vector<CutPiece> clear_pieces(const std::vector<gp_Pnt>& pts, const std::vector<double>& t,
                                   const std::function<gp_Pnt(double)>& at,
                                   const ClearanceModel& model, double clearance, double tol,
                                   double* from_above) {
  CentrePolyline line;
  line.pts = pts;
  line.t = t;
  std::vector<CutPiece> out;
  RunSplitter splitter(at, model, clearance, tol);
  double kept = 0.0;
  for (CentrePolyline& run : splitter.split(line)) {
    kept += run.length();
    out.push_back({nullptr, 0.0, std::move(run.pts), std::move(run.t), {}, {}});
  }
  if (from_above)
    *from_above += std::min(std::max(0.0, line.length() - kept), splitter.from_above());
  return out;
}

}  // namespace isocam
