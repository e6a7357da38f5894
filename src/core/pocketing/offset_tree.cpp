// Suh & Lee's offset procedure (section 2, Figure 2.2) and offset tree
// (section 2.3, Figure 2.20): the boundary shrinks and the islands grow,
// first by the tool radius, then step by step by the path interval; every
// connected piece is a node, its pieces one step further in are its
// children. A piece that would vanish at the next step ends the branch.
//
// Coverage. Let C be a node, L its loops, K the loops of C shrunk by s and
// a the reach (the tool radius r on a flat floor, half the interval on a
// sculptured one). A point p of C is within a of L when its distance to the
// complement of C is <= a, and within a of K when p is within a of C shrunk
// by s (inside it, deeper nodes take over). So what the step leaves is
//   U = (C shrunk by a) \ ((C shrunk by s) grown by a),
// empty whenever s <= a. For s > a it is computed (with a - cov_tol) and
// the step is reduced while U contains a disk of radius cov_tol: sharp
// corners of inner loops, narrow fingers and the middle of the last loops
// would otherwise be left uncut (or with a high scallop), as FreeCAD's
// offset pocket leaves them.
#include <algorithm>
#include <cmath>
#include <deque>

#include "isocam/errors.h"
#include "isocam/work_budget.h"
#include "pocketing/pocket_plan.h"

namespace isocam::pocket {
namespace {

bool leaves_material(const std::vector<Loop>& node, const std::vector<Loop>& children, double rc,
                     double tol, double snap) {
  std::vector<Loop> u = offset_region(node, rc, snap);
  if (u.empty()) return false;
  if (!children.empty())
    for (const Loop& l : dilate_region(children, rc, snap)) u.push_back(reversed(l));
  u = resolve_loops(u, snap);
  return !u.empty() && !offset_region(u, tol, snap).empty();
}

}  // namespace

OffsetTree build_offset_tree(const std::vector<Loop>& region, const TreeOptions& opt,
                             const StepFunction& step_of, const ProgressSlice& progress) {
  OffsetTree tree;
  const double r = opt.radius;
  const std::vector<Loop> start = offset_region(region, r, opt.snap);
  double total_area = 0.0;
  for (auto& comp : region_components(start)) {
    TreeNode n;
    n.loops = std::move(comp);
    total_area += region_area(n.loops);
    tree.roots.push_back(static_cast<int>(tree.nodes.size()));
    tree.nodes.push_back(std::move(n));
  }
  tree.min_step = 1e300;
  tree.max_step = 0.0;
  std::deque<int> queue(tree.roots.begin(), tree.roots.end());
  // Every step shrinks the region by at least the smallest reach; a tree
  // deeper than the region is wide can only come from a numerical failure.
  const double size = pocket::loops_box(region).size();
  double done_area = 0.0;
  double segments = 0.0;  // in all nodes so far: held to the work budget
  while (!queue.empty()) {
    progress.check();
    const int id = queue.front();
    queue.pop_front();
    const Step st = step_of(tree.nodes[static_cast<std::size_t>(id)]);
    double s = st.step;
    const double reach = std::min(st.reach, r);
    if (!(s > 0.0) || !(reach > opt.cov_tol))
      throw GeometryError("pocketing: the path interval is not positive");
    const std::vector<Loop>& loops = tree.nodes[static_cast<std::size_t>(id)].loops;
    std::vector<Loop> inner = offset_region(loops, s, opt.snap);
    const double rc = reach - opt.cov_tol;
    if (s > rc && leaves_material(loops, inner, rc, opt.cov_tol, opt.snap)) {
      // Bisect for the largest step that leaves nothing; rc always does.
      double lo = rc, hi = s;
      std::vector<Loop> lo_inner = offset_region(loops, lo, opt.snap);
      for (int it = 0; it < 4; ++it) {
        const double mid = 0.5 * (lo + hi);
        std::vector<Loop> mid_inner = offset_region(loops, mid, opt.snap);
        if (leaves_material(loops, mid_inner, rc, opt.cov_tol, opt.snap)) {
          hi = mid;
        } else {
          lo = mid;
          lo_inner = std::move(mid_inner);
        }
      }
      s = lo;
      inner = std::move(lo_inner);
      ++tree.reduced;
    }
    tree.nodes[static_cast<std::size_t>(id)].step = s;
    tree.min_step = std::min(tree.min_step, s);
    tree.max_step = std::max(tree.max_step, s);
    // The steps from the root to here add up to at least depth x the smallest
    // step taken anywhere; more than the region is wide cannot happen.
    if (static_cast<double>(tree.nodes[static_cast<std::size_t>(id)].depth) * tree.min_step > size)
      throw GeometryError("pocketing: the offsets do not shrink the region (numerical failure)");
    const double area = region_area(loops);
    double inner_area = 0.0;
    for (auto& comp : region_components(inner)) {
      TreeNode n;
      n.loops = std::move(comp);
      n.parent = id;
      n.depth = tree.nodes[static_cast<std::size_t>(id)].depth + 1;
      inner_area += region_area(n.loops);
      for (const Loop& l : n.loops) segments += static_cast<double>(l.size());
      const int child = static_cast<int>(tree.nodes.size());
      tree.nodes[static_cast<std::size_t>(id)].children.push_back(child);
      tree.nodes.push_back(std::move(n));
      queue.push_back(child);
    }
    if (segments > opt.max_segments)
      check_work_budget(segments, opt.max_segments, "the offset loops computed so far");
    done_area += std::max(0.0, area - inner_area);
    if (total_area > 0) progress.report(std::min(1.0, done_area / total_area));
  }
  if (tree.nodes.empty()) tree.min_step = 0.0;
  return tree;
}

}  // namespace isocam::pocket
