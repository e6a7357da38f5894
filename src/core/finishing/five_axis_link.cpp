// Phase 4 of 5-axis strip finishing (finishing/five_axis_link.h): the runs
// linked, low where proven clear and quicker, else through the safe height;
// the A/C angles; the machine time with the rotary axes timed.
#include "finishing/five_axis_link.h"

#include <algorithm>
#include <cmath>

namespace isocam {

bool AcTracker::next(double i, double j, double k, double* a, double* c) {
  const double s = std::hypot(i, j);
  const double A = std::atan2(s, k) / kDegree;
  const bool vertical = s < 1e-9;
  const double C = vertical ? pc_ : std::atan2(i, -j) / kDegree;
  double best = 1e300, ba = 0, bc = 0;
  for (int branch = 0; branch < 2; ++branch) {
    const double ca = branch ? -A : A;
    double cc = branch && !vertical ? C + 180.0 : C;
    if (ca < a_min_ - 1e-9 || ca > a_max_ + 1e-9) continue;
    if (have_) cc += 360.0 * std::round((pc_ - cc) / 360.0);
    const double cost = have_ ? std::abs(ca - pa_) + std::abs(cc - pc_) : std::abs(ca);
    if (cost < best) {
      best = cost;
      ba = ca;
      bc = cc;
    }
  }
  const bool ok = best < 1e300;
  if (ok) {
    pa_ = ba;
    pc_ = bc;
    have_ = true;
  }
  *a = have_ ? pa_ : A;
  *c = have_ ? pc_ : C;
  return ok;
}

gp_Vec axis_of_ac(double a_deg, double c_deg) {
  const double A = a_deg * kDegree, C = c_deg * kDegree;
  return gp_Vec(std::sin(A) * std::sin(C), -std::sin(A) * std::cos(C), std::cos(A));
}

namespace {

// A move's time (s): its tip length at `rate` (mm/min), |dA| and |dC| at
// the rotary rate (deg/min), whichever is longest.
double move_seconds(double length, double rate, double da, double dc, double rotary) {
  return 60.0 * std::max({length / rate, std::abs(da) / rotary, std::abs(dc) / rotary});
}

// The lifts tried: the air clearance doubled up to 2^kDoublings times.
constexpr int kDoublings = 5;
// Links longer than this many tool diameters go through the safe height
// (they would cost many checks, and a rapid up there is then about as quick).
constexpr double kMaxLinkDiameters = 5.0;
// A link needing more positions checked than this goes through the safe height.
constexpr int kMaxSamples = 4000;

struct Angles {
  double a = 0, c = 0;
};

class Linker {
 public:
  explicit Linker(const LinkContext& ctx)
      : c_(ctx), p_(ctx.p), margin_(ctx.p.air_clearance), ac_(ctx.p.a_min, ctx.p.a_max) {}

  Linked run(const std::vector<std::vector<ToolPose>>& runs) {
    // The retracts along the axis at both ends of each run that let the
    // tool go straight up to the safe height; a run without both is left out.
    std::vector<Kept> kept;
    for (const std::vector<ToolPose>& r : runs) {
      Kept k{&r, {}, {}};
      if (retract(r.front(), &k.rs) && retract(r.back(), &k.re)) {
        kept.push_back(k);
        continue;
      }
      ++out_.dropped;
      for (std::size_t q = 1; q < r.size(); ++q)
        out_.dropped_length += r[q - 1].tip.Distance(r[q].tip);
    }
    for (std::size_t i = 0; i < kept.size(); ++i) {
      const std::vector<ToolPose>& run = *kept[i].poses;
      const ToolPose& s = run.front();
      const double lift = i == 0 ? -1.0 : low_lift(kept[i - 1], kept[i]);
      if (lift > 0) {
        const ToolPose& e = kept[i - 1].poses->back();
        ++out_.low_links;
        add(MoveKind::Rapid, e.tip.Translated(e.axis * lift), e.axis);
        add(MoveKind::Rapid, s.tip.Translated(s.axis * lift), s.axis);
      } else {
        if (i > 0) {
          ++out_.safe_hops;
          leave(kept[i - 1]);
        }
        const gp_Pnt& rs = kept[i].rs;
        add(MoveKind::Rapid, gp_Pnt(rs.X(), rs.Y(), std::max(c_.safe_z, rs.Z())), s.axis);
        if (rs.Z() < c_.safe_z) add(MoveKind::Rapid, rs, s.axis);
      }
      const gp_Pnt approach = s.tip.Translated(s.axis * p_.air_clearance);
      if (approach.Distance(gp_Pnt(out_.path.x.back(), out_.path.y.back(), out_.path.z.back())) >
          1e-9)
        add(MoveKind::Rapid, approach, s.axis);
      add(MoveKind::Plunge, s.tip, s.axis);
      for (std::size_t k = 1; k < run.size(); ++k) add(MoveKind::Feed, run[k].tip, run[k].axis);
    }
    if (!kept.empty()) leave(kept.back());
    return std::move(out_);
  }

 private:
  struct Kept {
    const std::vector<ToolPose>* poses;
    gp_Pnt rs, re;  // the retracts at the start and the end
  };

  // Up from the end of r to the safe height.
  void leave(const Kept& r) {
    const ToolPose& e = r.poses->back();
    add(MoveKind::Rapid, r.re, e.axis);
    if (r.re.Z() < c_.safe_z) add(MoveKind::Rapid, gp_Pnt(r.re.X(), r.re.Y(), c_.safe_z), e.axis);
  }

  void add(MoveKind k, const gp_Pnt& q, const gp_Vec& a) {
    out_.path.add(k, q.X(), q.Y(), q.Z());
    out_.axis.push_back(a);
    double A, C;
    ac_.next(a.X(), a.Y(), a.Z(), &A, &C);
  }

  // The shank capsule (radius R - 2 gouge tolerance, from R above the tip
  // to tool_length + extra) clear of the model: the shank along a retract
  // of `extra` along the axis.
  bool capsule_clear(const ToolPose& x, double extra) const {
    return c_.model.clear(x.tip.Translated(x.axis * p_.tool_radius),
                          x.tip.Translated(x.axis * (p_.tool_length + extra)), c_.shank_clear);
  }

  // The retract along the axis from x that lets the tool go straight up to
  // the safe height clear of the model; false if none up to the safe height.
  bool retract(const ToolPose& x, gp_Pnt* r) const {
    for (double d = p_.air_clearance;; d *= 2) {
      *r = x.tip.Translated(x.axis * d);
      const bool top = r->Z() >= c_.safe_z;
      if (capsule_clear(x, d)) {
        if (top) return true;
        const gp_Pnt up(r->X(), r->Y(), c_.safe_z);
        bool clear = true;
        for (double s : {p_.tool_radius, 0.5 * (p_.tool_radius + p_.tool_length), p_.tool_length})
          clear = clear && c_.model.clear(r->Translated(x.axis * s), up.Translated(x.axis * s),
                                          c_.shank_clear);
        if (clear) return true;
      }
      if (top || d > 1e4) return false;
    }
  }

  // The whole tool at (tip, axis), the cylinder of radius R from the tip
  // to tool_length up the axis (a bull nose lies inside it), at least
  // `keep` from the model: its first R in the ball about tip + R/2 axis of
  // radius R sqrt(5)/2 (the slab's rim circles are on that sphere), the
  // rest in the capsule of radius R about the axis from R to tool_length.
  bool tool_clear(const gp_Pnt& tip, const gp_Vec& axis, double keep) const {
    const double R = p_.tool_radius;
    return c_.model.clear(tip.Translated(axis * (0.5 * R)),
                          c_.model.query_distance(0.5 * std::sqrt(5.0) * R + keep)) &&
           c_.model.clear(tip.Translated(axis * R), tip.Translated(axis * p_.tool_length),
                          c_.model.query_distance(R + keep));
  }

  // The tool moved as the machine moves it from (from, u) to (to, v): the
  // tip straight, A and C linear, proven to keep margin_ from the model.
  // Why the samples suffice: the tool turns relative to the part by
  // Rz(C) Rx(A), at the angular velocity C' z + A' u (u horizontal), so a
  // point w of the tool (|w| <= sqrt(L^2 + R^2) from the tip, its
  // horizontal part <= L sin|A| + R) moves at most
  //   |d tip| + sqrt(L^2 + R^2) |dA| + (L sin|A|max + R) |dC|
  // over a step (angles in radians; |A| <= its larger end, A being linear).
  // Steps of at most margin_ of that put every tool point between two
  // samples within margin_ / 2 of where it is at one of them; the tool at
  // each sample keeping 1.5 margin_ then keeps margin_ all along.
  bool sweep_clear(const gp_Pnt& from, const Angles& u, const gp_Pnt& to, const Angles& v) const {
    const double R = p_.tool_radius, L = p_.tool_length;
    const double a_top = std::max(std::abs(u.a), std::abs(v.a));
    const double s = a_top >= 90.0 ? 1.0 : std::sin(a_top * kDegree);
    const double travel = from.Distance(to) + std::hypot(L, R) * std::abs(v.a - u.a) * kDegree +
                          (L * s + R) * std::abs(v.c - u.c) * kDegree;
    const double n_real = std::ceil(travel / margin_);
    if (n_real > kMaxSamples) return false;
    const int n = std::max(1, static_cast<int>(n_real));
    auto sample_clear = [&](int k) {
      const double t = double(k) / n;
      const gp_Pnt tip(from.XYZ() + (to.XYZ() - from.XYZ()) * t);
      return tool_clear(tip, axis_of_ac(u.a + t * (v.a - u.a), u.c + t * (v.c - u.c)),
                        1.5 * margin_);
    };
    // The ends first: where a link too low fails, soonest.
    if (!sample_clear(0) || !sample_clear(n)) return false;
    for (int k = 1; k < n; ++k)
      if (!sample_clear(k)) return false;
    return true;
  }

  // The lift of the low link from the end of `prev` to the start of
  // `next`, or -1 for the hop through the safe height (isocam/five_axis.h,
  // "Links").
  double low_lift(const Kept& prev, const Kept& next) const {
    if (!p_.low_links) return -1.0;
    const ToolPose &e = prev.poses->back(), &s = next.poses->front();
    const gp_Pnt &re = prev.re, &rs = next.rs;
    AcTracker t = ac_;  // ac_ is at e's angles: the link's move posts from there
    Angles u, v;
    t.next(e.axis.X(), e.axis.Y(), e.axis.Z(), &u.a, &u.c);
    if (!t.next(s.axis.X(), s.axis.Y(), s.axis.Z(), &v.a, &v.c)) return -1.0;
    const double rot = p_.rotary_rate, rapid = p_.rapid_rate, safe = c_.safe_z;
    const double da = v.a - u.a, dc = v.c - u.c;
    const gp_Pnt up_e(re.X(), re.Y(), std::max(safe, re.Z())),
        up_s(rs.X(), rs.Y(), std::max(safe, rs.Z()));
    const gp_Pnt approach = s.tip.Translated(s.axis * p_.air_clearance);
    const double hop = move_seconds(e.tip.Distance(re), rapid, 0, 0, rot) +
                       move_seconds(up_e.Z() - re.Z(), rapid, 0, 0, rot) +
                       move_seconds(up_e.Distance(up_s), rapid, da, dc, rot) +
                       move_seconds(up_s.Z() - rs.Z(), rapid, 0, 0, rot) +
                       move_seconds(rs.Distance(approach), rapid, 0, 0, rot);
    auto at = [&](const ToolPose& x, double d) { return x.tip.Translated(x.axis * d); };
    auto low = [&](double d) {
      return move_seconds(d, rapid, 0, 0, rot) +
             move_seconds(at(e, d).Distance(at(s, d)), rapid, da, dc, rot) +
             move_seconds(d - p_.air_clearance, rapid, 0, 0, rot);
    };
    auto clear = [&](double d) {
      return capsule_clear(e, d) && capsule_clear(s, d) && sweep_clear(at(e, d), u, at(s, d), v);
    };
    const double air = p_.air_clearance;
    if (at(e, air).Distance(at(s, air)) > kMaxLinkDiameters * 2 * p_.tool_radius) return -1.0;
    double d = air;
    for (int k = 0;; ++k, d *= 2) {
      if (k > kDoublings || low(d) >= hop) return -1.0;
      if (clear(d)) break;
    }
    // Lowered by two bisection steps towards the last lift that failed.
    if (d > air) {
      double lo = 0.5 * d;
      for (int it = 0; it < 2; ++it) {
        const double mid = 0.5 * (lo + d);
        (clear(mid) ? d : lo) = mid;
      }
    }
    return d;
  }

  const LinkContext& c_;
  const FiveAxisParams& p_;
  double margin_;  // what every link keeps from the model: the air clearance
  AcTracker ac_;   // at the last move added
  Linked out_;
};

}  // namespace

Linked link_runs(const std::vector<std::vector<ToolPose>>& runs, const LinkContext& ctx) {
  return Linker(ctx).run(runs);
}

PathTimes five_axis_times(const Toolpath& path, const std::vector<double>& a,
                          const std::vector<double>& c, const FiveAxisParams& p) {
  PathTimes t;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const double len =
        std::sqrt(std::pow(path.x[k] - path.x[k - 1], 2) + std::pow(path.y[k] - path.y[k - 1], 2) +
                  std::pow(path.z[k] - path.z[k - 1], 2));
    const double da = a[k] - a[k - 1], dc = c[k] - c[k - 1];
    switch (static_cast<MoveKind>(path.kind[k])) {
      case MoveKind::Rapid:
        t.rapid += move_seconds(len, p.rapid_rate, da, dc, p.rotary_rate);
        break;
      case MoveKind::Plunge:
        t.plunge += move_seconds(len, p.plunge_rate, da, dc, p.rotary_rate);
        break;
      default:  // Feed (the op posts no arcs nor ramps)
        t.feed += move_seconds(len, p.feed_rate, da, dc, p.rotary_rate);
        break;
    }
  }
  t.total = t.feed + t.plunge + t.rapid;
  return t;
}

}  // namespace isocam
