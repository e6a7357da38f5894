// Flat-floor spiral pocketing: parameters, the plan (offset tree + cutting
// order), and the moves with G2/G3 arcs.
#include "pocketing/pocket_emit.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "isocam/errors.h"

namespace isocam {

using namespace pocket;

namespace pocket {

void check_params(const PocketParams& p, bool sculptured) {
  auto bad = [](const std::string& name, double v, const std::string& limit) {
    std::ostringstream m;
    m << name << " = " << v << " is out of range: " << limit;
    throw InvalidArgument(m.str());
  };
  const double r = p.tool_radius;
  if (!std::isfinite(r) || r <= 0) bad("tool_radius", r, "must be > 0");
  if (!std::isfinite(p.stepover) || p.stepover <= 0 || p.stepover > 2 * r)
    bad("stepover", p.stepover,
        "must be > 0 and <= the tool diameter 2 x tool_radius = " + std::to_string(2 * r));
  if (!std::isfinite(p.tolerance) || p.tolerance <= 0 || p.tolerance > 0.25 * r)
    bad("tolerance", p.tolerance, "must be > 0 and <= tool_radius / 4");
  if (!std::isfinite(p.floor_tolerance) || p.floor_tolerance <= 0)
    bad("floor_tolerance", p.floor_tolerance, "must be > 0");
  if (sculptured &&
      (!std::isfinite(p.scallop_height) || p.scallop_height <= 0 || p.scallop_height >= r))
    bad("scallop_height", p.scallop_height, "must be > 0 and < tool_radius");
  if (r > 1e5) bad("tool_radius", r, "must be <= 1e5 mm");
  if (!std::isfinite(p.safe_z) || std::abs(p.safe_z) > 1e6)
    bad("safe_z", p.safe_z, "must be finite and within 1e6 mm of z = 0");
  check_max_moves(p.max_moves);
  if (!std::isfinite(p.min_arc_chord) || p.min_arc_chord < 0)
    bad("min_arc_chord", p.min_arc_chord, "must be >= 0");
}

void check_depths(const std::vector<double>& depths, double safe_z) {
  if (depths.empty()) throw InvalidArgument("depths: at least one z level is needed");
  for (std::size_t i = 0; i < depths.size(); ++i) {
    const std::string level =
        "depths: level " + std::to_string(i) + " = " + std::to_string(depths[i]);
    if (!std::isfinite(depths[i]) || std::abs(depths[i]) > 1e6)
      throw InvalidArgument(level + " is out of range: must be finite and within 1e6 mm of z = 0");
    if (i > 0 && !(depths[i] < depths[i - 1]))
      throw InvalidArgument(level + ": levels must decrease strictly (top to bottom)");
    if (depths[i] >= safe_z)
      throw InvalidArgument(level + " is not below safe_z = " + std::to_string(safe_z));
  }
}

void check_plan_budget(const std::vector<Loop>& region, const PocketParams& p, std::size_t levels) {
  const Box2 box = loops_box(region);
  if (box.empty()) return;
  const double far =
      std::max({std::abs(box.x0), std::abs(box.y0), std::abs(box.x1), std::abs(box.y1)});
  const double extent = std::max(box.size(), far);
  check_tolerance_ratio("tolerance", p.tolerance, extent);
  check_tolerance_ratio("stepover", p.stepover, extent);
  double perimeter = 0.0, segs = 0.0;
  for (const Loop& l : region)
    for (const Seg& s : l) {
      perimeter += s.length();
      segs += 1.0;
    }
  const double area = std::abs(region_area(region));
  if (!(perimeter > 0)) return;
  // Levels: at least (area / perimeter) / stepover (the inradius of a
  // convex region is at least area / perimeter); each level has about
  // twice the profile's segments (an arc at each convex corner).
  const double per_level = area / perimeter / p.stepover * 2.0 * segs + segs;
  std::ostringstream how;
  how.precision(3);
  how << area << " mm^2 at a stepover of " << p.stepover << " mm, " << segs << " segments along "
      << perimeter << " mm of profile, " << levels << " z level(s)";
  check_work_budget(per_level * static_cast<double>(levels), p.max_moves, how.str());
}

void check_path_budget(const Toolpath& path, const PocketParams& p) {
  if (static_cast<double>(path.size()) > p.max_moves)
    check_work_budget(static_cast<double>(path.size()), p.max_moves, "the path computed so far");
}

FlatPlan make_flat_plan(const std::vector<Loop>& region, const PocketParams& p, double snap,
                        const ProgressSlice& progress) {
  FlatPlan plan;
  TreeOptions to;
  to.radius = p.tool_radius;
  to.cov_tol = p.tolerance;
  to.snap = snap;
  to.max_segments = p.max_moves;
  check_plan_budget(region, p, 1);
  const Step st{p.stepover, p.tool_radius};
  plan.tree = build_offset_tree(
      region, to, [st](TreeNode&) { return st; }, progress);
  OrderOptions oo;
  oo.radius = p.tool_radius;
  oo.snap = snap;
  oo.progress = progress;
  plan.cuts = order_cuts(plan.tree, oo);
  plan.snap = snap;
  return plan;
}

void move_to_start(Toolpath& path, P2 s, double z, LinkKind link, double safe_z) {
  if (link == LinkKind::Feed) {
    if (path.size() > 0 && std::hypot(path.x.back() - s.x, path.y.back() - s.y) > 0)
      path.add(MoveKind::Feed, s.x, s.y, z);
    return;
  }
  if (path.size() > 0) path.add(MoveKind::Rapid, path.x.back(), path.y.back(), safe_z);
  path.add(MoveKind::Rapid, s.x, s.y, safe_z);
  path.add(MoveKind::Plunge, s.x, s.y, z);
}

void emit_seg_flat(Toolpath& path, const Seg& s, double z, double min_chord) {
  if (s.kind == SegKind::Line) {
    path.add(MoveKind::Feed, s.b.x, s.b.y, z);
    return;
  }
  // Arcs of at most a half turn: a G2/G3 is exact, but one whose end comes
  // back near its start is ill-conditioned for controllers.
  const int n = std::max(1, static_cast<int>(std::ceil(std::abs(s.sweep) / kPi - 1e-9)));
  for (int k = 0; k < n; ++k) {
    Seg piece = s.sub(static_cast<double>(k) / n, static_cast<double>(k + 1) / n);
    if (k + 1 == n) piece.b = s.b;
    const P2 from{path.x.back(), path.y.back()};
    if (dist(from, piece.b) < min_chord)
      path.add(MoveKind::Feed, piece.b.x, piece.b.y, z);
    else
      path.add_arc(s.sweep > 0, piece.b.x, piece.b.y, z, s.c.x, s.c.y);
  }
}

void emit_flat_plan(const FlatPlan& plan, double z, const PocketParams& p, Toolpath& path,
                    PocketMetrics& m) {
  const bool climb = p.direction == CutDirection::Climb;
  bool first = true;
  for (const LoopCut& cut : plan.cuts) {
    const Loop& loop = plan.tree.nodes[static_cast<std::size_t>(cut.node)]
                           .loops[static_cast<std::size_t>(cut.loop)];
    const Loop trav = loop_from(loop, cut.seg, cut.t, climb, plan.snap);
    if (trav.empty()) continue;
    // A new level starts with a retract even if its first cut could link.
    const LinkKind link = first ? LinkKind::Start : cut.link;
    move_to_start(path, trav.front().a, z, link, p.safe_z);
    if (link == LinkKind::Feed) ++m.feed_links;
    for (const Seg& s : trav) emit_seg_flat(path, s, z, p.min_arc_chord);
    check_path_budget(path, p);
    ++m.loops;
    first = false;
  }
  int depth = 0;
  for (const TreeNode& n : plan.tree.nodes) depth = std::max(depth, n.depth);
  m.tree_depth = std::max(m.tree_depth, depth);
  m.reduced_intervals += plan.tree.reduced;
  if (!plan.tree.nodes.empty()) {
    m.min_interval =
        m.min_interval > 0 ? std::min(m.min_interval, plan.tree.min_step) : plan.tree.min_step;
    m.max_interval = std::max(m.max_interval, plan.tree.max_step);
  }
}

void measure_path(const Toolpath& path, PocketMetrics& m) {
  const PathLengths len = measure(path);
  report_lengths(len, m);
  m.arcs = len.arcs;
  m.cl_points = len.cutting_moves;
}

}  // namespace pocket

std::vector<Loop> make_region(const Loop& boundary, const std::vector<Loop>& islands) {
  std::vector<Loop> region;
  region.push_back(signed_area(boundary) >= 0 ? boundary : reversed(boundary));
  for (const Loop& l : islands) region.push_back(signed_area(l) <= 0 ? l : reversed(l));
  return region;
}

PocketResult spiral_pocket(const std::vector<Loop>& region, const std::vector<double>& depths,
                           const PocketParams& params, Progress* progress) {
  check_params(params, false);
  check_depths(depths, params.safe_z);
  const ProgressSlice ps(progress);
  PocketResult res;
  if (region.empty()) return res;
  check_plan_budget(region, params, depths.size());
  const FlatPlan plan = make_flat_plan(region, params, default_snap(region), ps.sub(0.0, 0.9));
  for (double z : depths) {
    emit_flat_plan(plan, z, params, res.path, res.metrics);
    ++res.metrics.levels;
  }
  measure_path(res.path, res.metrics);
  ps.report(1.0);
  return res;
}

}  // namespace isocam
