// 5-axis strip finishing (isocam/five_axis.h): a short driver over named
// phases, per face: trace the paths by the constant-scallop front with the
// tilted flat end's strip width (trace_face), measure the certificate on
// them, clip them to the trimmed face and zig-zag (clip_face), pose the
// tool along them with the gouge, shank and other-face checks (pose_run,
// finishing/five_axis_pose.cpp); then link all runs (link_runs,
// finishing/five_axis_link.cpp) and give the rotary angles (axes_to_ac).
#include "isocam/five_axis.h"

#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include "finishing/coverage.h"
#include "finishing/face_failure.h"
#include "finishing/five_axis_link.h"
#include "finishing/five_axis_pose.h"
#include "finishing/five_axis_tool.h"
#include "finishing/scallop_front.h"
#include "finishing/strip_isocurves.h"
#include "finishing/task_pool.h"
#include "geometry/clearance.h"
#include "geometry/trim_domain.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"

namespace isocam {
namespace {

using namespace five_axis;  // the job and the posing (finishing/five_axis_pose.h)

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

void require(bool ok, const std::string& name, double v, const std::string& rule) {
  if (!ok) throw InvalidArgument(name + " must be " + rule + " (got " + num(v) + ")");
}

void validate(const FiveAxisParams& p) {
  require(std::isfinite(p.tool_radius) && p.tool_radius > 0, "tool_radius", p.tool_radius,
          "> 0 mm");
  require(std::isfinite(p.corner_radius) && p.corner_radius >= 0 && p.corner_radius < p.tool_radius,
          "corner_radius", p.corner_radius,
          ">= 0 and < tool_radius mm (0: a flat end; a ball end, corner_radius = tool_radius, "
          "has no flat bottom to tilt)");
  require(std::isfinite(p.tool_length) && p.tool_length > p.tool_radius, "tool_length",
          p.tool_length, "> tool_radius");
  require(p.lead_angle > 0 && p.lead_angle < 60, "lead_angle", p.lead_angle,
          "in (0, 60) degrees (0 leaves the whole flat bottom on the surface)");
  require(std::abs(p.tilt_angle) < 45, "tilt_angle", p.tilt_angle, "in (-45, 45) degrees");
  require(p.max_lead_angle >= p.lead_angle && p.max_lead_angle < 80, "max_lead_angle",
          p.max_lead_angle, ">= lead_angle and < 80 degrees");
  require(p.scallop_height > 0 && p.scallop_height < p.tool_radius, "scallop_height",
          p.scallop_height, "in (0, tool_radius) mm");
  require(std::isfinite(p.gouge_tolerance) && p.gouge_tolerance > 0, "gouge_tolerance",
          p.gouge_tolerance, "> 0 mm");
  require(std::isfinite(p.chord_tolerance) && p.chord_tolerance >= 0, "chord_tolerance",
          p.chord_tolerance, ">= 0 mm (0: derived)");
  require(p.posted_resolution >= 0 && p.posted_resolution < 0.1, "posted_resolution",
          p.posted_resolution, "in [0, 0.1) mm");
  require(p.max_axis_step >= 0.05 && p.max_axis_step <= 10, "max_axis_step", p.max_axis_step,
          "in [0.05, 10] degrees");
  require(p.a_min >= -120 && p.a_min < p.a_max, "a_min", p.a_min, ">= -120 and < a_max degrees");
  require(p.a_max <= 120, "a_max", p.a_max, "<= 120 degrees");
  require(std::isfinite(p.safe_z), "safe_z", p.safe_z, "finite");
  require(std::isfinite(p.air_clearance) && p.air_clearance > 0, "air_clearance", p.air_clearance,
          "> 0 mm");
  require(std::isfinite(p.feed_rate) && p.feed_rate > 0, "feed_rate", p.feed_rate, "> 0 mm/min");
  require(std::isfinite(p.plunge_rate) && p.plunge_rate > 0, "plunge_rate", p.plunge_rate,
          "> 0 mm/min");
  require(std::isfinite(p.rapid_rate) && p.rapid_rate > 0, "rapid_rate", p.rapid_rate,
          "> 0 mm/min");
  require(std::isfinite(p.rotary_rate) && p.rotary_rate > 0, "rotary_rate", p.rotary_rate,
          "> 0 deg/min");
  require(p.threads >= 0, "threads", p.threads, ">= 0 (0: one per core)");
  check_max_moves(p.max_moves);
}

// A point of a path with the next path's point q at distance d: what the
// certificate measures (pair_cusp()).
struct CertPair {
  StripFrame f;
  ParamPt q;
  double d = 0;
  gp_Pnt q_point;  // the surface point at q
};

// Phase 1: the paths of one face in one working grid.
struct Traced {
  std::vector<std::vector<FrontPiece>> paths;
  std::vector<CertPair> pairs;
  double length = 0, max_spacing = 0, cusp = 0, max_width = 0, gap = 0;
  int min_hits = 0;
  bool capped = false;
};

// The frame at uv with the feed `feed` (its tangential part), curvatures filled.
StripFrame frame_with(const PatchGrid& g, const ParamPt& uv, const gp_Vec& feed) {
  StripFrame f;
  ContactFrame c;
  if (!contact_frame(g, uv, feed, &c)) return f;  // feed null: skipped
  f.uv = uv;
  f.p = c.p;
  f.normal = c.n;
  f.feed = c.f;
  f.across = c.a;
  f.kappa_feed = normal_curvature(g, uv, c.f);
  f.kappa_across = normal_curvature(g, uv, c.a);
  return f;
}

// The cusp between a path's point (frame f) and the next path at distance
// d, q the next path's point there: the largest as the edge at f, at q and
// at the ground between (the parameters' midpoint) sees it (the spacing
// was the least of the three widths, so each edge meets h there). The
// leads are the job's there, or lead_f at f, lead_q at q and the larger
// between where those are more (leads the exact check raised).
double pair_cusp(const PatchGrid& g, const Job& job, const CertPair& c, double lead_f = 0.0,
                 double lead_q = 0.0) {
  double cu = job.edge(c.f, lead_f).cusp(c.d);
  const ParamPt mid{0.5 * (c.q.u + c.f.uv.u), 0.5 * (c.q.v + c.f.uv.v)};
  const ParamPt at[2] = {c.q, mid};
  const double leads[2] = {lead_q, std::max(lead_f, lead_q)};
  for (int k = 0; k < 2; ++k) {
    const StripFrame fx = frame_with(g, at[k], c.f.feed);
    if (fx.feed.SquareMagnitude() > 0.5) cu = std::max(cu, job.edge(fx, leads[k]).cusp(c.d));
  }
  return cu;
}

// Definition 1 sampled: the largest distance from a point of the face
// (inside its wires) to the nearest path.
double sampled_gap(const PatchGrid& g, const TrimDomain& trim, bool transposed,
                   const PathIndex& index) {
  const int n = 64;
  double gap = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const double u = g.umin() + (g.umax() - g.umin()) * (a + 0.5) / n;
      const double v = g.vmin() + (g.vmax() - g.vmin()) * (b + 0.5) / n;
      if (!(transposed ? trim.contains(v, u) : trim.contains(u, v))) continue;
      gap = std::max(gap, index.distance(g.eval(u, v)));
    }
  return gap;
}

// The paths for strips spaced for the cusp h (the target), with the
// certificate: for each point p with a successor, the distance d to the
// next path and pair_cusp() there.
Traced trace_face(const PatchGrid& g, const TrimDomain& trim, bool transposed, const Job& job,
                  const RaisedLeads& hint, double h, const ProgressSlice& progress) {
  Traced out;
  const StripWidth width = [&job, &hint, h](const StripFrame& f) {
    return job.width(f, h, hint.at(f.p, 2));
  };
  FrontSettings s;
  s.sample_max = std::min(job.flat_width, job.p.tool_radius);
  s.min_spacing = 0.02 * job.flat_width;
  const std::size_t max_paths = static_cast<std::size_t>(8.0 * g.size() / s.min_spacing) + 100;
  PathIndex index(job.flat_width);
  std::vector<FrontPiece> front = start_front(g, job.flat_width, s.sample_max);
  std::size_t samples = 0;
  while (!front.empty()) {
    progress.check();
    // Progress: where the front is in v (it starts at vmin), not beyond 0.99.
    double v = 0.0, n = 0.0;
    for (const FrontPiece& pc : front)
      for (const FrontPoint& x : pc) {
        v += x.uv.v;
        n += 1;
      }
    if (n > 0) progress.report(std::min(0.99, (v / n - g.vmin()) / (g.vmax() - g.vmin())));
    if (out.paths.size() >= max_paths || samples > 20000000) {
      out.capped = true;
      out.paths.push_back(front);
      break;
    }
    for (const FrontPiece& pc : front) index.add(pc);
    FrontStep step = advance_front(g, &front, width, s, index);
    out.min_hits += step.min_hits;
    PathIndex next(job.flat_width);
    for (const FrontPiece& pc : step.next) next.add(pc);
    for (const FrontPiece& pc : front) {
      samples += pc.size();
      for (std::size_t k = 0; k < pc.size(); ++k) {
        if (k > 0) out.length += pc[k - 1].p.Distance(pc[k].p);
        if (!pc[k].has_next) continue;
        const StripFrame f = frame_at(g, pc, k);
        if (f.feed.SquareMagnitude() < 0.5) continue;
        gp_Pnt at;
        const double d = next.distance(pc[k].p, &at);
        out.max_spacing = std::max(out.max_spacing, d);
        out.max_width = std::max(out.max_width, pc[k].spacing);
        CertPair c{f, {}, d, {}};
        nearest_on(g, at, pc[k].uv, &c.q);
        c.q_point = g.eval(c.q.u, c.q.v);
        out.cusp = std::max(out.cusp, pair_cusp(g, job, c, hint.at(f.p), hint.at(at)));
        out.pairs.push_back(c);
      }
    }
    out.paths.push_back(std::move(front));
    front = std::move(step.next);
  }
  out.gap = sampled_gap(g, trim, transposed, index);
  return out;
}

// The NormalIsocurves strategy: adaptive isocurves of the grid's v
// (finishing/strip_isocurves.h) spaced for the cusp h, with the same
// certificate as trace_face(), the next path's point taken at the same u
// (farther than the nearest, so the cusp measured is not less).
Traced trace_isocurves(const PatchGrid& g, const TrimDomain& trim, bool transposed, const Job& job,
                       const RaisedLeads& hint, double h, const ProgressSlice& progress) {
  Traced out;
  IsoStripSettings s;
  s.sample_max = std::min(job.flat_width, job.p.tool_radius);
  IsoStripPaths iso = strip_isocurves(
      g, [&job, &hint, h](const StripFrame& f) { return job.width(f, h, hint.at(f.p, 2)); }, s,
      [&progress](double f) {
        progress.check();
        progress.report(f);
      });
  out.min_hits = iso.min_hits;
  out.capped = iso.capped;
  PathIndex index(job.flat_width);
  for (std::size_t i = 0; i < iso.paths.size(); ++i)
    for (std::size_t j = 0; j < iso.paths[i].size(); ++j) {
      const FrontPiece& pc = iso.paths[i][j];
      index.add(pc);
      for (std::size_t k = 0; k < pc.size(); ++k) {
        if (k > 0) out.length += pc[k - 1].p.Distance(pc[k].p);
        if (!pc[k].has_next) continue;
        const StripFrame f = frame_at(g, pc, k);
        if (f.feed.SquareMagnitude() < 0.5) continue;
        const ParamPt& q = iso.next[i][j][k];
        const gp_Pnt at = g.eval(q.u, q.v);
        const CertPair c{f, q, pc[k].p.Distance(at), at};
        out.max_spacing = std::max(out.max_spacing, c.d);
        out.max_width = std::max(out.max_width, pc[k].spacing);
        out.cusp = std::max(out.cusp, pair_cusp(g, job, c, hint.at(f.p), hint.at(at)));
        out.pairs.push_back(c);
      }
    }
  out.paths = std::move(iso.paths);
  out.gap = sampled_gap(g, trim, transposed, index);
  return out;
}

// Phase 2: the runs of contact points inside the face (bisection at the
// wires), zig-zag: every other path run back (its runs in reverse order,
// each marked `back`; its points stay in the traced order, the poser
// reverses them).
std::vector<ClippedRun> clip_face(const PatchGrid& g, const TrimDomain& trim, bool transposed,
                                  const Traced& t, double tol) {
  auto inside = [&](const ParamPt& q) {
    return transposed ? trim.contains(q.v, q.u) : trim.contains(q.u, q.v);
  };
  auto lerp = [](const ParamPt& a, const ParamPt& b, double f) {
    return ParamPt{a.u + f * (b.u - a.u), a.v + f * (b.v - a.v)};
  };
  std::vector<ClippedRun> runs;
  for (std::size_t i = 0; i < t.paths.size(); ++i) {
    std::vector<Run> path_runs;
    for (const FrontPiece& pc : t.paths[i]) {
      Run cur;
      bool in = false;
      ParamPt prev{};
      for (std::size_t k = 0; k < pc.size(); ++k) {
        const int parts = k == 0 ? 1 : 4;
        for (int q = 1; q <= parts; ++q) {
          const ParamPt x = k == 0 ? pc[0].uv : lerp(pc[k - 1].uv, pc[k].uv, double(q) / parts);
          const bool s = inside(x);
          if (k > 0 && s != in) {
            const ParamPt lo = in ? prev : x, hi = in ? x : prev;  // lo inside
            cur.push_back(bisect_to_edge(g, lo, hi, g.eval(hi.u, hi.v), inside, tol));
            if (in) {
              if (cur.size() >= 2) path_runs.push_back(cur);
              cur.clear();
            }
          }
          if (s && (q == parts)) cur.push_back(x);
          in = s;
          prev = x;
        }
      }
      if (cur.size() >= 2) path_runs.push_back(cur);
    }
    const bool back = i % 2 == 1;
    if (back) std::reverse(path_runs.begin(), path_runs.end());
    for (Run& r : path_runs) runs.push_back({std::move(r), back});
  }
  return runs;
}

// The certificate again with the leads the poses used where the exact
// check raised them: each pair's points take the largest raised lead posed
// within half a path sample of them (positions between the samples
// included), the pairs near no raised position keep what the trace
// measured. The spacing followed the leads the curvature asks for; this
// makes the certificate hold for the leads posted.
double posed_cusp(const PatchGrid& g, const Job& job, const Traced& t, const RaisedLeads& leads) {
  double cusp = t.cusp;
  for (const CertPair& c : t.pairs) {
    const double lf = leads.at(c.f.p), lq = leads.at(c.q_point);
    if (lf > 0 || lq > 0) cusp = std::max(cusp, pair_cusp(g, job, c, lf, lq));
  }
  return cusp;
}

void check_faces(const std::vector<int>& faces, std::size_t count) {
  if (faces.empty()) throw InvalidArgument("faces: no face picked");
  std::set<int> seen;
  for (int f : faces) {
    if (f < 0 || f >= static_cast<int>(count))
      throw InvalidArgument("faces: index " + std::to_string(f) +
                            " is out of range (the shape has " + std::to_string(count) + " faces)");
    if (!seen.insert(f).second)
      throw InvalidArgument("faces: index " + std::to_string(f) + " given twice");
  }
}

Budget make_budget(const FiveAxisParams& p) {
  Budget b;
  b.posted = 0.5 * std::sqrt(3.0) * p.posted_resolution;
  // The cutting end's points are within sqrt(R^2 + rc^2) of the tip.
  b.axis = std::hypot(p.tool_radius, p.corner_radius) * kAxisDeviation;
  b.chord = p.chord_tolerance > 0 ? p.chord_tolerance : (p.scallop_height - b.posted - b.axis) / 4;
  if (!(p.scallop_height - b.error() > 0))
    throw InvalidArgument(
        "scallop_height must exceed the chord tolerance, the posted rounding and "
        "the axis step's error (" +
        num(b.error()) + " mm; got " + num(p.scallop_height) + ")");
  return b;
}

void check_budget(const std::vector<TopoDS_Face>& all, const std::vector<int>& faces,
                  const Job& job) {
  double area = 0.0;
  for (int f : faces) {
    GProp_GProps props;
    BRepGProp::SurfaceProperties(all[static_cast<std::size_t>(f)], props);
    area += std::abs(props.Mass());
  }
  const double est = area / job.flat_width / (0.25 * job.flat_width) + double(faces.size());
  check_work_budget(
      est, job.p.max_moves,
      num(area) + " mm^2 of faces at a strip width of about " + num(job.flat_width) + " mm");
}

// The tracings of a face compared, one offered at a time: one beats the
// best so far if it covers the face (no sampled gap wider than half the
// strip) and meets h' by its certificate where the best does not, else if
// it is the shorter (the other strategy's length counted a ninth more: the
// one asked for is kept unless the other is shorter by more than a tenth).
// It notes the shortest length offered of each strategy (for the warning).
struct Choice {
  Choice() = default;
  explicit Choice(const Job& face_job) : job(&face_job) {}

  // True if `t` is taken (then moved from).
  bool offer(Traced& t, FiveAxisStrategy st) {
    const FiveAxisStrategy asked = job->p.strategy;
    double& l = st == asked ? asked_length : used_length;
    l = std::min(l, t.length);
    if (any && !beats(t, st)) return false;
    best = std::move(t);
    strategy = st;
    any = true;
    return true;
  }

  Traced best;
  FiveAxisStrategy strategy = FiveAxisStrategy::StripEvaluation;  // best's
  // The shortest offered of the strategy asked for and of the other.
  double asked_length = std::numeric_limits<double>::infinity();
  double used_length = std::numeric_limits<double>::infinity();

 private:
  bool meets(const Traced& x) const {
    return 2 * x.gap <= 1.05 * std::max(x.max_width, job->flat_width) && x.cusp <= job->h_eff;
  }
  double weighted(const Traced& x, FiveAxisStrategy st) const {
    return st == job->p.strategy ? x.length : x.length / 0.9;
  }
  bool beats(const Traced& t, FiveAxisStrategy st) const {
    if (meets(t) != meets(best)) return meets(t);
    return weighted(t, st) < weighted(best, strategy);
  }

  const Job* job = nullptr;
  bool any = false;
};

// One picked face: the direction and strategy chosen (traced, measured),
// its paths clipped to the face and posed. Throws what the geometry throws.
struct FaceRun {
  Choice chosen;  // the last tracings' (the face's paths: chosen.best)
  PoseOut posed;
  int respaced = 0;  // times traced again for the leads the exact check raised
};

// One direction's paths for the cusp h': spaced for `target` first; where
// the measured certificate exceeds h' (the next path runs a little farther
// than the march went, where points were resampled, cut out or joined),
// again for a target scaled down by the excess (the cusp grows about
// linearly with the target), up to three times.
Traced trace_to(const PatchGrid& g, const Face& face, bool transposed, FiveAxisStrategy strategy,
                const Job& job, const RaisedLeads& hint, double target,
                const ProgressSlice& slice) {
  Traced t;
  for (int attempt = 0; attempt < 4; ++attempt) {
    t = strategy == FiveAxisStrategy::NormalIsocurves
            ? trace_isocurves(g, *face.trim, transposed, job, hint, target, slice)
            : trace_face(g, *face.trim, transposed, job, hint, target, slice);
    if (t.cusp <= job.h_eff) break;
    target *= 0.98 * job.h_eff / t.cusp;
  }
  return t;
}

FaceRun finish_face(const Face& face, const Job& job, const ProgressSlice& slice) {
  const FiveAxisParams& p = job.p;
  std::vector<IsoDirection> dirs{IsoDirection::V, IsoDirection::U};
  if (p.direction != IsoDirection::Auto) dirs = {p.direction};
  // The strategies traced: the one asked for; with StripEvaluation the
  // adaptive isocurves too, used where they are shorter by more than a
  // tenth (the march's front folds where the strip width changes fast
  // along it: on MAT's rugged ground it traced 9 x the isocurves' length).
  std::vector<FiveAxisStrategy> strategies{p.strategy};
  if (p.strategy == FiveAxisStrategy::StripEvaluation)
    strategies.push_back(FiveAxisStrategy::NormalIsocurves);
  struct Candidate {
    bool transposed;
    FiveAxisStrategy strategy;
  };
  std::vector<Candidate> cands;
  for (FiveAxisStrategy st : strategies)
    for (IsoDirection d : dirs) cands.push_back({d == IsoDirection::U, st});
  RaisedLeads raised(0.5 * std::min(job.flat_width, p.tool_radius));
  // The candidates traced at once, each on its own grid, then compared in
  // order (the result does not depend on the threads). The tracing is the
  // first half of the face's progress, the posing the second.
  std::vector<std::optional<PatchGrid>> grids(cands.size());
  std::vector<Traced> traced(cands.size());
  TaskProgress tracing(slice.sub(0.0, 0.5), cands.size());
  for_each_index(cands.size(), p.threads, [&](std::size_t k) {
    const bool tr = cands[k].transposed;
    grids[k].emplace(tr ? face.grid.transposed() : face.grid);
    traced[k] =
        trace_to(*grids[k], face, tr, cands[k].strategy, job, raised, job.h_eff, tracing.task(k));
  });
  std::optional<PatchGrid> best_grid;
  FaceRun out;
  out.chosen = Choice(job);
  bool best_transposed = false;
  for (std::size_t k = 0; k < cands.size(); ++k)
    if (out.chosen.offer(traced[k], cands[k].strategy)) {
      best_grid.emplace(std::move(*grids[k]));
      best_transposed = cands[k].transposed;
    }
  const PatchGrid& g = *best_grid;
  // Where the exact check raised leads above what the curvature asks for,
  // the strips there are narrower than spaced for: the certificate is
  // measured again with the leads posed, and if it exceeds h' the paths
  // are traced again with the spacing following the leads raised so far
  // (each point spaced for the largest raised within two radii of it: the
  // paths move, their new points fall between the positions raised, and
  // the check raises the lead there about as much; with one radius MAT's
  // certificate still exceeded h' after three times), from the second
  // time on also for a target scaled down by the excess, and posed again,
  // up to three times.
  const double ends[5] = {0.5, 0.8, 0.9, 0.96, 1.0};
  double target = job.h_eff;
  // The runs the attempt before posed, by their samples: a run traced
  // again unchanged is posed as before (its poses depend on it alone).
  using RunKey = std::pair<bool, std::vector<double>>;
  auto key = [](const ClippedRun& c) {
    RunKey k{c.back, {}};
    k.second.reserve(2 * c.r.size());
    for (const ParamPt& q : c.r) k.second.insert(k.second.end(), {q.u, q.v});
    return k;
  };
  std::map<RunKey, PoseOut> posed_before;
  for (int attempt = 0; attempt < 4; ++attempt) {
    if (attempt > 0) {
      // Each strategy traced again (a march that was the shorter may fold
      // where the raised leads narrow its strips), the better kept.
      std::vector<Traced> again(strategies.size());
      for_each_index(strategies.size(), p.threads, [&](std::size_t k) {
        again[k] = trace_to(g, face, best_transposed, strategies[k], job, raised, target,
                            slice.sub(ends[attempt], ends[attempt]));
      });
      out.chosen = Choice(job);
      for (std::size_t k = 0; k < strategies.size(); ++k) out.chosen.offer(again[k], strategies[k]);
    }
    const std::vector<ClippedRun> clipped =
        clip_face(g, *face.trim, best_transposed, out.chosen.best, 0.1 * job.b.chord);
    // The runs posed at once, each into its own part, joined in order.
    slice.report(ends[attempt]);
    const ProgressSlice posing = slice.sub(ends[attempt], ends[attempt + 1]);
    std::atomic<std::size_t> posed_runs{0};
    std::vector<PoseOut> parts(clipped.size());
    std::vector<RunKey> keys(clipped.size());
    for_each_index(clipped.size(), p.threads, [&](std::size_t k) {
      slice.check();
      keys[k] = key(clipped[k]);
      const auto same = posed_before.find(keys[k]);
      if (same != posed_before.end())
        parts[k] = same->second;
      else
        pose_run(g, *face.trim, best_transposed, face.grid, job, clipped[k], &parts[k]);
      posing.report(double(++posed_runs) / double(clipped.size()));
    });
    posed_before.clear();
    if (attempt < 3)  // (the last attempt is posed for good)
      for (std::size_t k = 0; k < clipped.size(); ++k)
        posed_before.emplace(std::move(keys[k]), parts[k]);
    out.posed = PoseOut();
    for (PoseOut& part : parts) out.posed.append(std::move(part));
    raised.add(g, out.posed.runs);
    out.chosen.best.cusp = posed_cusp(g, job, out.chosen.best, raised);
    if (out.chosen.best.cusp <= job.h_eff || attempt == 3) break;
    ++out.respaced;
    if (attempt >= 1) target *= 0.98 * job.h_eff / out.chosen.best.cusp;
  }
  return out;
}

}  // namespace

FiveAxisResult five_axis_finish(const TopoDS_Shape& shape, const std::vector<int>& faces,
                                const FiveAxisParams& p, Progress* progress) {
  if (shape.IsNull()) throw InvalidArgument("brep: the shape is empty (no faces)");
  const std::vector<TopoDS_Face> all = faces_of(shape);
  if (all.empty()) throw InvalidArgument("brep: the shape has no faces");
  check_faces(faces, all.size());
  validate(p);
  Bnd_Box box;
  for (const TopoDS_Face& f : all) BRepBndLib::Add(f, box, false);
  if (box.IsVoid()) throw InvalidArgument("brep: the faces have no extent");
  const double extent = std::sqrt(box.SquareExtent());
  check_tolerance_ratio("scallop_height", p.scallop_height, extent);

  Job job{p, make_budget(p), Cutter{p.tool_radius, p.corner_radius}};
  job.h_eff = p.scallop_height - job.b.error();
  job.lead = p.lead_angle * kDegree;
  job.max_lead = p.max_lead_angle * kDegree;
  job.tilt = p.tilt_angle * kDegree;
  job.step = p.max_axis_step * kDegree;
  {
    const ContactFrame flat{gp_Pnt(0, 0, 0), gp_Vec(0, 0, 1), gp_Vec(1, 0, 0), gp_Vec(0, 1, 0)};
    job.flat_width = 2 * EdgeProfile(flat, job.tool, job.lead, job.tilt, 0.0).half_width(job.h_eff);
  }
  check_budget(all, faces, job);
  FiveAxisResult result;
  FiveAxisMetrics& m = result.metrics;
  m.chord_tolerance = job.b.chord;
  m.flat_strip_width = job.flat_width;

  // The model: the picked faces and (protect_unpicked_faces) the others. A
  // face that cannot be built is left out with a warning: a picked one is
  // skipped (habit 4, face_failure.h), an unpicked one left unprotected.
  ClearanceModel model(p.gouge_tolerance, 2.0 * p.tool_radius);
  std::vector<std::unique_ptr<Face>> model_faces;
  std::vector<Face*> picked(faces.size(), nullptr);
  std::vector<std::string> skipped(faces.size());  // per picked face: why, "" if finished
  for (std::size_t i = 0; i < all.size(); ++i) {
    const int f = static_cast<int>(i);
    const auto at = std::find(faces.begin(), faces.end(), f);
    if (at == faces.end() && !p.protect_unpicked_faces) continue;
    const std::optional<std::string> failed = face_failure(f, [&] {
      auto face = std::make_unique<Face>(Face{f, PatchGrid::from_face(all[i], f), std::nullopt});
      face->trim.emplace(all[i], face->grid, f);
      model.add(face->grid, &*face->trim);
      if (at != faces.end()) picked[static_cast<std::size_t>(at - faces.begin())] = face.get();
      model_faces.push_back(std::move(face));
    });
    if (failed && at != faces.end()) {
      skipped[static_cast<std::size_t>(at - faces.begin())] = *failed;
      result.warnings.push_back(skipped_face_warning(*failed, false));
    } else if (failed) {
      result.warnings.push_back(*failed + "; it is not protected from the shank");
    }
  }
  model.build();
  job.model = &model;
  for (const std::unique_ptr<Face>& f : model_faces) job.faces.emplace(&f->grid, f.get());
  job.shank_clear = model.query_distance(p.tool_radius - 2 * p.gouge_tolerance);

  const ProgressSlice all_progress(progress);
  std::vector<std::vector<Posed>> runs;
  for (std::size_t fi = 0; fi < picked.size(); ++fi) {
    if (!skipped[fi].empty()) continue;
    const Face& face = *picked[fi];
    const ProgressSlice slice = all_progress.sub(0.9 * double(fi) / double(picked.size()),
                                                 0.9 * double(fi + 1) / double(picked.size()));
    FaceRun run;
    const std::optional<std::string> failed =
        face_failure(face.index, [&] { run = finish_face(face, job, slice); });
    if (failed) {
      skipped[fi] = *failed;
      result.warnings.push_back(skipped_face_warning(*failed, true));
      continue;
    }
    const Traced& best = run.chosen.best;
    const PoseOut& posed = run.posed;
    m.max_spacing = std::max(m.max_spacing, best.max_spacing);
    m.coverage_gap = std::max(m.coverage_gap, best.gap);
    m.guaranteed_scallop = std::max(m.guaranteed_scallop, best.cusp);
    m.paths += static_cast<int>(best.paths.size());
    // A gap the front left wider than the strips: material may be left there.
    if (2 * best.gap > 1.05 * std::max(best.max_width, job.flat_width))
      result.warnings.push_back(face_label(face.index) + ": the paths leave a gap of " +
                                num(best.gap) +
                                " mm to the nearest path (sampled), wider than half the strip");
    if (best.min_hits > 0)
      result.warnings.push_back(face_label(face.index) +
                                ": the strip width asked for less than the "
                                "minimum spacing at " +
                                std::to_string(best.min_hits) + " points");
    if (best.capped)
      result.warnings.push_back(face_label(face.index) + ": the paths stopped at the cap");
    if (run.chosen.strategy != p.strategy) {
      ++m.isocurve_faces;
      result.warnings.push_back(
          face_label(face.index) +
          // (longer, they are used only where the march's paths fail)
          (run.chosen.used_length < run.chosen.asked_length
               ? ": the adaptive isocurves' paths (" + num(run.chosen.used_length) +
                     " mm) are shorter than the strip march's (" + num(run.chosen.asked_length) +
                     " mm: its front folds where the strip width changes fast along it)"
               : ": the strip march's paths leave a gap wider than half the strip or exceed "
                 "the scallop height by their certificate, the adaptive isocurves' do not") +
          "; the isocurves are used on this face");
    }
    if (run.respaced > 0)
      result.warnings.push_back(face_label(face.index) + ": traced again " +
                                std::to_string(run.respaced) +
                                (run.respaced == 1 ? " time" : " times") +
                                " with the strips narrowed where the exact check raised the lead");
    m.unreachable_length += posed.unreachable;
    m.lead_raised_points += posed.raised;
    m.unconverged_moves += posed.unconverged;
    m.swings_split += posed.swings_split;
    if (posed.unconverged > 0)
      result.warnings.push_back(
          face_label(face.index) + ": at " + std::to_string(posed.unconverged) +
          " moves the tool's pose still changed by more than the tolerances after " +
          std::to_string(kMaxHalvings) +
          " halvings between two positions; the swing there was checked, and the path split at " +
          std::to_string(posed.swings_split) + " of them where it would gouge or hit the model");
    m.max_lead_used = std::max(m.max_lead_used, posed.max_lead / kDegree);
    if (posed.raised > 0)
      result.warnings.push_back(face_label(face.index) + ": the lead was raised above " +
                                num(p.lead_angle) + " deg (up to " + num(posed.max_lead / kDegree) +
                                " deg) at " + std::to_string(posed.raised) +
                                " positions to keep the bottom off concave ground (rear gouge); "
                                "the strips there are narrower");
    if (posed.gouge_left + posed.shank_left + posed.others_left + posed.range_left > 0)
      result.warnings.push_back(
          face_label(face.index) + ": positions left out: " + std::to_string(posed.gouge_left) +
          " where the cutting end would gouge even at " + num(p.max_lead_angle) + " deg lead, " +
          std::to_string(posed.shank_left) + " where the shank meets the model, " +
          std::to_string(posed.others_left) + " where the cutting end meets another face, " +
          std::to_string(posed.range_left) + " where A would leave [" + num(p.a_min) + ", " +
          num(p.a_max) + "] deg");
    for (auto& r : run.posed.runs) runs.push_back(std::move(r));
  }
  for (std::size_t fi = 0; fi < faces.size(); ++fi)
    if (!skipped[fi].empty()) result.skipped_faces.push_back(faces[fi]);
  if (result.skipped_faces.size() == faces.size()) throw_every_face_failed(skipped);
  // The guarantees: the cusp measured plus the positions' error.
  m.guaranteed_scallop += job.b.error();
  m.guaranteed_overcut = job.b.error() + p.gouge_tolerance;
  if (m.guaranteed_scallop > p.scallop_height * (1 + 1e-9))
    result.warnings.push_back("the measured cusp between adjacent paths (" +
                              num(m.guaranteed_scallop) +
                              " mm with the positions' error) exceeds the scallop height " +
                              num(p.scallop_height) + " mm (see guaranteed_scallop)");

  double zmin, zmax, x0, y0, x1, y1;
  box.Get(x0, y0, zmin, x1, y1, zmax);
  const double safe_z = std::max(p.safe_z, zmax + p.air_clearance);
  std::vector<std::vector<ToolPose>> poses;
  poses.reserve(runs.size());
  for (const std::vector<Posed>& r : runs) {
    poses.emplace_back();
    for (const Posed& x : r) poses.back().push_back(x.pose);
  }
  Linked linked = link_runs(poses, LinkContext{p, model, job.shank_clear, safe_z});
  m.low_links = linked.low_links;
  m.safe_hops = linked.safe_hops;
  if (linked.dropped > 0) {
    m.unreachable_length += linked.dropped_length;
    result.warnings.push_back(std::to_string(linked.dropped) +
                              " runs left out: no retract along the tool axis clears the model");
  }
  all_progress.report(0.95);
  result.path = std::move(linked.path);
  for (const gp_Vec& a : linked.axis) {
    result.i.push_back(a.X());
    result.j.push_back(a.Y());
    result.k.push_back(a.Z());
  }
  std::vector<char> ok;
  axes_to_ac(result.i, result.j, result.k, p.a_min, p.a_max, &result.a, &result.c, &ok);
  report_lengths(measure(result.path), m);
  const PathTimes t = five_axis_times(result.path, result.a, result.c, p);
  m.machine_time = t.total;
  m.cutting_time = t.feed;
  for (std::size_t k = 1; k < result.a.size(); ++k) {
    m.rotary_travel_a += std::abs(result.a[k] - result.a[k - 1]);
    m.rotary_travel_c += std::abs(result.c[k] - result.c[k - 1]);
  }
  all_progress.report(1.0);
  return result;
}

void axes_to_ac(const std::vector<double>& i, const std::vector<double>& j,
                const std::vector<double>& k, double a_min, double a_max, std::vector<double>* a,
                std::vector<double>* c, std::vector<char>* ok) {
  a->resize(i.size());
  c->resize(i.size());
  ok->resize(i.size());
  AcTracker t(a_min, a_max);
  for (std::size_t q = 0; q < i.size(); ++q)
    (*ok)[q] = t.next(i[q], j[q], k[q], &(*a)[q], &(*c)[q]);
}

double strip_half_width(double radius, double corner_radius, double lead_deg, double tilt_deg,
                        double kappa_across, double h) {
  if (!(radius > 0) || !(corner_radius >= 0 && corner_radius < radius) || !(h > 0) ||
      !(lead_deg > 0 && lead_deg < 90) || !(std::abs(tilt_deg) < 90))
    throw InvalidArgument(
        "strip_half_width: radius > 0, 0 <= corner_radius < radius, h > 0, 0 < lead < 90, "
        "|tilt| < 90 (got " +
        num(radius) + ", " + num(corner_radius) + ", " + num(h) + ", " + num(lead_deg) + ", " +
        num(tilt_deg) + ")");
  const ContactFrame flat{gp_Pnt(0, 0, 0), gp_Vec(0, 0, 1), gp_Vec(1, 0, 0), gp_Vec(0, 1, 0)};
  return EdgeProfile(flat, Cutter{radius, corner_radius}, lead_deg * kDegree, tilt_deg * kDegree,
                     kappa_across)
      .half_width(h);
}

double flat_end_half_width(double radius, double lead_deg, double tilt_deg, double kappa_across,
                           double h) {
  return strip_half_width(radius, 0.0, lead_deg, tilt_deg, kappa_across, h);
}

}  // namespace isocam
