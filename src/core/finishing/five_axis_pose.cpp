// Phase 3 of 5-axis strip finishing: the tool posed along each run
// (finishing/five_axis_pose.h).
#include "finishing/five_axis_pose.h"

#include <array>

namespace isocam::five_axis {
namespace {

// The axis at s (0 at p, 1 at q) of the machine's interpolation between
// two: A and C of each (C of the other where one is vertical, C unwrapped
// to the nearest branch, as axes_to_ac() posts them), interpolated.
gp_Vec ac_lerp(const gp_Vec& p, const gp_Vec& q, double s) {
  auto ac = [](const gp_Vec& v, double* A, double* C) {
    const double r = std::hypot(v.X(), v.Y());
    *A = std::atan2(r, v.Z());
    *C = r < 1e-12 ? std::nan("") : std::atan2(v.X(), -v.Y());
  };
  double a1, c1, a2, c2;
  ac(p, &a1, &c1);
  ac(q, &a2, &c2);
  if (std::isnan(c1)) c1 = std::isnan(c2) ? 0.0 : c2;
  if (std::isnan(c2)) c2 = c1;
  c2 += 2 * M_PI * std::round((c1 - c2) / (2 * M_PI));
  const double A = (1 - s) * a1 + s * a2, C = (1 - s) * c1 + s * c2;
  return gp_Vec(std::sin(A) * std::sin(C), -std::sin(A) * std::cos(C), std::cos(A));
}

class Poser {
 public:
  // g: the face's grid as traced (transposed or not); own: the face's
  // grid in the model (the face the tool cuts).
  Poser(const PatchGrid& g, const TrimDomain& trim, bool transposed, const PatchGrid& own,
        const Job& job)
      : g_(g), trim_(trim), transposed_(transposed), own_(&own), job_(job) {}

  // The run posed and checked into out. A run the zig-zag runs back is
  // posed along its own direction, or with lag_on_return along the traced
  // one (the pass before's tilt kept) and then reversed.
  void run(const ClippedRun& c, PoseOut* out) const {
    if (!c.back) return run(c.r, out);
    if (!job_.p.lag_on_return) return run(Run(c.r.rbegin(), c.r.rend()), out);
    const std::size_t first = out->runs.size();
    run(c.r, out);
    std::reverse(out->runs.begin() + static_cast<std::ptrdiff_t>(first), out->runs.end());
    for (std::size_t k = first; k < out->runs.size(); ++k)
      std::reverse(out->runs[k].begin(), out->runs[k].end());
  }

 private:
  void run(const Run& r, PoseOut* out) const {
    // The samples, each fed along the chord of its neighbours; between two
    // the position, feed and lead interpolated by the parameter t along
    // the segment, so that a pose depends on where it is only.
    std::vector<Posed> pts;
    std::vector<gp_Pnt> at(r.size());
    for (std::size_t k = 0; k < r.size(); ++k) at[k] = g_.eval(r[k].u, r[k].v);
    std::vector<gp_Vec> feed(r.size());
    std::size_t prev_k = 0;
    for (std::size_t k = 0; k < r.size(); ++k) {
      const std::size_t a = k > 0 ? k - 1 : k, b = k + 1 < r.size() ? k + 1 : k;
      feed[k] = gp_Vec(at[a], at[b]);
      if (feed[k].SquareMagnitude() > 1e-300) feed[k].Normalize();
      Posed x;
      if (!pose(r[k], feed[k], &x)) continue;
      if (!pts.empty()) {
        const Posed prev = pts.back();
        const Segment seg{r[prev_k], r[k], feed[prev_k], feed[k], prev.lead, x.lead};
        refine(seg, prev, 0.0, x, 1.0, 0, &pts, &out->unconverged);
      }
      pts.push_back(x);
      prev_k = k;
    }
    // The checks, splitting the run where a position fails.
    std::vector<Posed> cur;
    auto flush = [&]() {
      if (cur.size() >= 2) out->runs.push_back(cur);
      cur.clear();
    };
    for (std::size_t k = 0; k < pts.size(); ++k) {
      Posed& x = pts[k];
      bool ok = true;
      if (x.swing) {
        ++out->swings_split;
        ok = false;
      } else if (x.depth > job_.p.gouge_tolerance) {
        ++out->gouge_left;
        ok = false;
      } else if (!job_.capsule_clear(x.pose.tip, x.pose.axis) ||
                 (!cur.empty() &&
                  !job_.model->clear(
                      cur.back().pose.tip.Translated(cur.back().pose.axis * job_.p.tool_radius),
                      x.pose.tip.Translated(x.pose.axis * job_.p.tool_radius), job_.shank_clear))) {
        ++out->shank_left;
        ok = false;
      } else if (!others_clear(cur.empty() ? nullptr : &cur.back().pose, x.pose)) {
        ++out->others_left;
        ok = false;
      } else if (!a_reachable(x.pose.axis)) {
        ++out->range_left;
        ok = false;
      }
      if (!ok) {
        // A failed swing leaves no contact path out: its two ends touch the
        // same point (the tool lifts at one and comes down at the other).
        if (k > 0 && !x.swing) out->unreachable += pts[k - 1].pose.tip.Distance(x.pose.tip);
        flush();
        continue;
      }
      out->raised += x.raised ? 1 : 0;
      out->max_lead = std::max(out->max_lead, x.lead);
      cur.push_back(x);
    }
    flush();
  }

  bool inside(const ParamPt& q) const {
    return transposed_ ? trim_.contains_uncached(q.v, q.u) : trim_.contains_uncached(q.u, q.v);
  }
  double depth(const Posed& x) const {
    return tool_depth(g_, x.uv, x.pose, job_.tool, [this](const ParamPt& q) { return inside(q); });
  }
  bool a_reachable(const gp_Vec& axis) const {
    const double A = std::acos(std::clamp(axis.Z(), -1.0, 1.0)) / kDegree;
    const double eps = 1e-9;
    return (A >= job_.p.a_min - eps && A <= job_.p.a_max + eps) ||
           (-A >= job_.p.a_min - eps && -A <= job_.p.a_max + eps);
  }
  // The pose at uv with the feed along dir, its lead the job's there (at
  // least min_lead), raised while the exact check finds it digging in.
  bool pose(const ParamPt& uv, const gp_Vec& dir, Posed* x, double min_lead = 0.0) const {
    ContactFrame c;
    if (!contact_frame(g_, uv, dir, &c)) return false;
    const double kf = normal_curvature(g_, uv, c.f), ka = normal_curvature(g_, uv, c.a);
    x->uv = uv;
    const double curvature_lead = job_.lead_at(kf, ka);
    x->lead = std::max(curvature_lead, min_lead);
    x->raised = x->lead > job_.lead + 1e-9;
    x->pose = pose_at(c, job_.tool, x->lead, job_.tilt);
    // The exact check: raise the lead in 2 degree steps while the end digs in.
    x->depth = depth(*x);
    while (x->depth > job_.p.gouge_tolerance && x->lead < job_.max_lead) {
      x->lead = std::min(job_.max_lead, x->lead + 2 * kDegree);
      x->raised = true;
      x->pose = pose_at(c, job_.tool, x->lead, job_.tilt);
      x->depth = depth(*x);
    }
    x->raised_exact = x->lead > curvature_lead + 1e-9;
    return true;
  }
  struct Segment {
    ParamPt a, b;
    gp_Vec fa, fb;
    double la, lb;
  };
  // Positions inserted between a (at parameter ta on `seg`) and b (at tb),
  // not included, into out; *unconverged counts the halvings stopped at
  // the depth limit with the poses still apart.
  void refine(const Segment& seg, const Posed& a, double ta, const Posed& b, double tb, int level,
              std::vector<Posed>* out, int* unconverged) const {
    const double turn = a.pose.axis.Angle(b.pose.axis);
    const double t = 0.5 * (ta + tb);
    const ParamPt m{seg.a.u + t * (seg.b.u - seg.a.u), seg.a.v + t * (seg.b.v - seg.a.v)};
    Posed x;
    if (!pose(m, seg.fa * (1 - t) + seg.fb * t, &x, (1 - t) * seg.la + t * seg.lb)) return;
    const gp_Pnt mid((a.pose.tip.XYZ() + b.pose.tip.XYZ()) * 0.5);
    if (turn <= job_.step && mid.Distance(x.pose.tip) <= job_.b.chord &&
        ac_lerp(a.pose.axis, b.pose.axis, 0.5).Angle(x.pose.axis) <= kAxisDeviation)
      return;
    if (level >= kMaxHalvings) {
      ++*unconverged;
      if (!swing_clear(a, b, &x)) out->push_back(x);
      return;
    }
    refine(seg, a, ta, x, t, level + 1, out, unconverged);
    out->push_back(x);
    refine(seg, x, t, b, tb, level + 1, out, unconverged);
  }
  // Where the halving ends with the poses apart (the pose jumps: the exact
  // check raised the lead on one side and not on the other), the swing the
  // machine makes between a and b (the tip along the chord, A and C
  // interpolated) is checked as every position is: at poses no more than
  // the axis step apart, the cutting end against the face and the shank
  // against the model. False if one fails, *x then that pose, marked to
  // split the run there.
  bool swing_clear(const Posed& a, const Posed& b, Posed* x) const {
    const int n =
        std::max(2, static_cast<int>(std::ceil(a.pose.axis.Angle(b.pose.axis) / job_.step)));
    for (int k = 1; k < n; ++k) {
      const double s = static_cast<double>(k) / n;
      Posed w;
      w.uv = {(1 - s) * a.uv.u + s * b.uv.u, (1 - s) * a.uv.v + s * b.uv.v};
      w.pose.tip = gp_Pnt(a.pose.tip.XYZ() * (1 - s) + b.pose.tip.XYZ() * s);
      w.pose.axis = ac_lerp(a.pose.axis, b.pose.axis, s);
      w.depth = depth(w);
      if (w.depth > job_.p.gouge_tolerance || !job_.capsule_clear(w.pose.tip, w.pose.axis)) {
        w.swing = true;
        *x = w;
        return false;
      }
    }
    return true;
  }

  // The cutting end against the model's other faces (its own face is the
  // exact check's): at the pose x and, from `prev` (if given), along the
  // move to it. A clearance query finds a face near the cutting end (within
  // its ball, end_ball(); along a move, the ball's sweep); that face gets
  // the exact check (its side sampled too), from the point found, and is
  // left out of the next query, until one is clear. Along a move: see
  // sweep_clear(). False where one digs in deeper than the gouge tolerance,
  // and where the query cannot show which face is near (kMaxOthers).
  bool others_clear(const ToolPose* prev, const ToolPose& x) const {
    constexpr int kMaxOthers = 8;
    std::array<const PatchGrid*, kMaxOthers> skip{own_};
    int n = 1;
    const gp_Pnt c1 = job_.end_centre(x), c0 = prev ? job_.end_centre(*prev) : c1;
    // The axis turning between the two poses takes the ball's centre off
    // the chord by at most R / 2 (1 - cos(turn / 2)).
    const double turn = prev ? prev->axis.Angle(x.axis) : 0.0;
    const double d = job_.end_ball() + 0.5 * job_.p.tool_radius * (1 - std::cos(0.5 * turn));
    const double tol = job_.p.gouge_tolerance;
    for (;;) {
      ClearanceModel::Witness w;
      if (job_.model->clear_except(c0, c1, d, skip.data(), n, &w)) return true;
      if (!w.grid || n == kMaxOthers) return false;
      const auto f = job_.faces.find(w.grid);
      if (f == job_.faces.end()) return false;
      const ParamPt uv{w.u, w.v};
      const double dx = other_depth(*f->second, uv, x);
      if (dx > tol) return false;
      if (prev) {
        const double dp = other_depth(*f->second, uv, *prev);
        if (dp > tol || !sweep_clear(*f->second, uv, *prev, dp, x, dx, 0)) return false;
      }
      skip[static_cast<std::size_t>(n++)] = w.grid;
    }
  }
  // The signed depth of the cutting end (disc and side) in another face,
  // the exact check's Newton from uv on it.
  double other_depth(const Face& f, const ParamPt& uv, const ToolPose& x) const {
    return signed_tool_depth(
        f.grid, uv, x, job_.tool,
        [&f](const ParamPt& q) { return f.trim->contains_uncached(q.u, q.v); }, true);
  }
  // The move from a to b (signed depths da, db in f) keeps the cutting end
  // within the gouge tolerance of f: no point of the tool moves more than
  // m = |tip step| + sqrt(2) R x (axis turn) between them, so the depth is
  // 1-Lipschitz in that measure and at most (da + db + m) / 2 between the
  // two; where that is over the tolerance the move is halved at its middle
  // pose (checked as a position) until it is not, or until m <= R / 20: a
  // tool that touches f along the move (the disc over a convex edge, level
  // with the side face below it) is checked at poses that far apart.
  bool sweep_clear(const Face& f, const ParamPt& uv, const ToolPose& a, double da,
                   const ToolPose& b, double db, int level) const {
    const double tol = job_.p.gouge_tolerance, r = job_.p.tool_radius;
    const double m = a.tip.Distance(b.tip) + std::sqrt(2.0) * r * a.axis.Angle(b.axis);
    if (0.5 * (da + db + m) <= tol || m <= 0.05 * r) return true;
    if (level >= 2 * kMaxHalvings) return false;
    const ToolPose mid{gp_Pnt((a.tip.XYZ() + b.tip.XYZ()) * 0.5), ac_lerp(a.axis, b.axis, 0.5)};
    const double dm = other_depth(f, uv, mid);
    return dm <= tol && sweep_clear(f, uv, a, da, mid, dm, level + 1) &&
           sweep_clear(f, uv, mid, dm, b, db, level + 1);
  }

  const PatchGrid& g_;
  const TrimDomain& trim_;
  bool transposed_;
  const PatchGrid* own_;
  const Job& job_;
};

}  // namespace

void RaisedLeads::add(const PatchGrid& g, const std::vector<std::vector<Posed>>& runs) {
  for (const std::vector<Posed>& run : runs)
    for (const Posed& x : run)
      if (x.raised_exact) {
        const gp_Pnt p = g.eval(x.uv.u, x.uv.v);
        cells_[key(cell(p.X()), cell(p.Y()), cell(p.Z()))].push_back({p, x.lead});
      }
}

void pose_run(const PatchGrid& g, const TrimDomain& trim, bool transposed, const PatchGrid& own,
              const Job& job, const ClippedRun& c, PoseOut* out) {
  Poser(g, trim, transposed, own, job).run(c, out);
}

}  // namespace isocam::five_axis
