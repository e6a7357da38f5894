// The ball-end pass on a sculptured pocket floor (Suh & Lee sections 2-2.3).
//
// Plan view: the offset tree of the region, first at r from the walls, then
// at the path interval of eq. 11-18 (the smallest along each node's loops,
// as the paper takes it), reduced where a larger one would leave material.
// CL points: each plan segment is cut into chords within the plan-view
// deviation epsilon (`tolerance`): inscribed chords where the arc turns
// left (towards the region, away from the walls), circumscribed ones where
// it turns right (towards a wall or island), so a chord never comes closer
// to a wall than the arc. A chord is then split until the tip z between
// its ends is within the floor deviation delta (`floor_tolerance`) of the
// straight line (checked at 1/4, 1/2, 3/4): flat stretches take few points,
// as the paper's two-tolerance subdivision does.
#include "pocketing/floor_path.h"

#include <algorithm>
#include <cmath>

#include "isocam/errors.h"
#include "pocketing/pocket_emit.h"

namespace isocam::pocket {
namespace {

class Sampler {
 public:
  Sampler(const BallDrop& floor, double eps, double delta)
      : floor_(floor), eps_(eps), delta_(delta) {}

  P3 at(P2 q) const {
    const BallDrop::Contact c = floor_.drop(q.x, q.y);
    if (!c.hit) throw GeometryError("sculptured floor: the tool centre is off the floor");
    return {q.x, q.y, c.tip_z};
  }

  // CL points after `a` along the plan segment (the last is its end).
  void segment(const Seg& s, std::vector<P3>& out) const {
    std::vector<P2> plan;
    if (s.kind == SegKind::Line) {
      plan.push_back(s.b);
    } else {
      const double r = s.r, span = std::abs(s.sweep);
      const bool inscribed = s.sweep > 0;
      const double half =
          inscribed ? std::acos(std::max(-1.0, 1.0 - eps_ / r)) : std::acos(r / (r + eps_));
      const int n = std::max(1, static_cast<int>(std::ceil(span / (2.0 * half) - 1e-9)));
      const double da = s.sweep / n;
      if (inscribed) {
        for (int k = 1; k <= n; ++k) plan.push_back(k == n ? s.b : s.c + r * polar(s.a0 + k * da));
      } else {
        const double rr = r / std::cos(0.5 * std::abs(da));
        for (int k = 0; k < n; ++k) plan.push_back(s.c + rr * polar(s.a0 + (k + 0.5) * da));
        plan.push_back(s.b);
      }
    }
    P3 prev = at(s.a);
    for (P2 q : plan) {
      const P3 next = at(q);
      chord(prev, next, 0, out);
      prev = next;
    }
  }

  // CL points of a whole loop, per segment: runs of lines and left-turning
  // arcs are covered by the longest chords that stay within epsilon on the
  // region's side of the plan path and never cross to the wall's side (the
  // points go to the run's last segment; the others stay empty); arcs
  // turning right (towards a wall or island) get circumscribed chords.
  void loop(const Loop& l, std::vector<std::vector<P3>>& per_seg) const {
    const std::size_t n = l.size();
    per_seg.assign(n, {});
    auto right_arc = [&](std::size_t j) { return l[j].kind == SegKind::Arc && l[j].sweep < 0; };
    std::size_t k = 0;
    while (k < n) {
      if (right_arc(k)) {
        // A run of arcs turning right: two chords along the tangents at
        // its ends, meeting outside the path (on the region's side).
        std::size_t best = n;
        P2 corner, x;
        for (std::size_t m = k; m < n && right_arc(m) && tangent_ok(l, k, m, x); ++m) {
          best = m;
          corner = x;
        }
        if (best == n) {
          segment(l[k], per_seg[k]);
          ++k;
          continue;
        }
        const P3 c3 = at(corner);
        chord(at(l[k].a), c3, 0, per_seg[best]);
        chord(c3, at(l[best].b), 0, per_seg[best]);
        k = best + 1;
        continue;
      }
      std::size_t best = n;
      for (std::size_t m = k; m < n && !right_arc(m) && chord_ok(l, k, m); ++m) best = m;
      if (best == n) {  // one arc too curved for a single chord
        segment(l[k], per_seg[k]);
        ++k;
        continue;
      }
      chord(at(l[k].a), at(l[best].b), 0, per_seg[best]);
      k = best + 1;
    }
  }

  // Splits the plan chord a-b until the floor deviation holds.
  void chord(const P3& a, const P3& b, int depth, std::vector<P3>& out) const {
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    bool ok = depth >= 24 || len < 1e-3;
    std::vector<P3> mid(3);
    if (!ok) {
      ok = true;
      for (int k = 0; k < 3; ++k) {
        const double t = 0.25 * (k + 1);
        mid[static_cast<std::size_t>(k)] = at({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
        if (std::abs(mid[static_cast<std::size_t>(k)].z - (a.z + t * (b.z - a.z))) > delta_)
          ok = false;
      }
    }
    if (ok) {
      out.push_back(b);
      return;
    }
    chord(a, mid[1], depth + 1, out);
    chord(mid[1], b, depth + 1, out);
  }

 private:
  // The chord from the start of segment k to the end of segment m: the plan
  // path between stays on its right (the wall's side of a chord is its
  // right, region on the left), at most epsilon from it, and in order.
  bool chord_ok(const Loop& l, std::size_t k, std::size_t m) const {
    const P2 a = l[k].a, b = l[m].b;
    const double len = dist(a, b);
    if (len < 1e-9) return false;
    const P2 u = (1.0 / len) * (b - a);
    auto ok = [&](P2 q) {
      const double side = cross(u, q - a), along = dot(u, q - a);
      return side <= 1e-9 && side >= -eps_ && along >= -1e-9 && along <= len + 1e-9;
    };
    for (std::size_t j = k; j <= m; ++j) {
      if (j < m && !ok(l[j].b)) return false;
      if (l[j].kind == SegKind::Arc)
        for (double t : {0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875})
          if (!ok(l[j].at(t))) return false;
    }
    return true;
  }

  // The tangents at the start of arc k and the end of arc m (a run turning
  // right) meet at x within epsilon of the run, turning less than 90 deg.
  bool tangent_ok(const Loop& l, std::size_t k, std::size_t m, P2& x) const {
    const P2 a = l[k].a, b = l[m].b, ta = start_tangent(l[k]), tb = end_tangent(l[m]);
    const double turn = cross(ta, tb);
    if (!(turn < 0) || dot(ta, tb) <= 0) return false;
    // a + s ta = b - t tb
    const P2 d = b - a;
    const double den = cross(ta, tb);
    const double sa = cross(d, tb) / den, tbv = cross(d, ta) / den;
    if (sa < 0 || -tbv < 0) return false;
    x = a + sa * ta;
    double near = 1e300;
    for (std::size_t j = k; j <= m; ++j) near = std::min(near, nearest_on_seg(l[j], x).d);
    return near <= eps_;
  }

  const BallDrop& floor_;
  double eps_, delta_;
};

// Samples the node's loops and returns the smallest interval along them
// (eq. 11-18 at every CL point, across the direction of travel).
double sample_node(TreeNode& node, const Sampler& sampler, const BallDrop& floor, double h) {
  double w = 1e300;
  node.cl.assign(node.loops.size(), {});
  for (std::size_t l = 0; l < node.loops.size(); ++l) {
    sampler.loop(node.loops[l], node.cl[l]);
    P2 prev = node.loops[l].front().a;
    for (const auto& pts : node.cl[l])
      for (const P3& q3 : pts) {
        const P2 q{q3.x, q3.y};
        if (dist(q, prev) > 1e-9) {
          const BallDrop::Contact c = floor.drop(q.x, q.y);
          w = std::min(w, path_interval(floor, c, left_normal(unit(q - prev)), h));
        }
        prev = q;
      }
  }
  return w;
}

}  // namespace

void sculptured_floor_pass(const std::vector<TopoDS_Face>& faces, const std::vector<Loop>& region,
                           const PocketParams& p, Toolpath& path, PocketMetrics& m,
                           const ProgressSlice& progress) {
  {
    // The tolerances against the region's extent (isocam/work_budget.h).
    const Box2 box = loops_box(region);
    const double extent = std::max(
        {box.size(), std::abs(box.x0), std::abs(box.y0), std::abs(box.x1), std::abs(box.y1)});
    check_tolerance_ratio("floor_tolerance", p.floor_tolerance, extent);
    check_tolerance_ratio("scallop_height", p.scallop_height, extent);
  }
  const double mesh_tol = std::clamp(0.1 * p.floor_tolerance, 1e-3, 0.01);
  const BallDrop floor(faces, p.tool_radius, mesh_tol);
  const Sampler sampler(floor, p.tolerance, p.floor_tolerance);
  const double snap = default_snap(region);
  TreeOptions to;
  to.radius = p.tool_radius;
  to.cov_tol = p.tolerance;
  to.snap = snap;
  to.max_segments = p.max_moves;
  const double h = p.scallop_height;
  const OffsetTree tree = build_offset_tree(
      region, to,
      [&](TreeNode& n) {
        const double w = sample_node(n, sampler, floor, h);
        return Step{w, 0.5 * w};
      },
      progress.sub(0.0, 0.9));
  OrderOptions oo;
  oo.radius = p.tool_radius;
  oo.snap = snap;
  oo.vertices_only = true;
  oo.progress = progress;
  const std::vector<LoopCut> cuts = order_cuts(tree, oo);
  const bool climb = p.direction == CutDirection::Climb;
  bool first = true;
  for (const LoopCut& cut : cuts) {
    const TreeNode& node = tree.nodes[static_cast<std::size_t>(cut.node)];
    const auto& segs = node.cl[static_cast<std::size_t>(cut.loop)];
    const auto n = static_cast<int>(segs.size());
    // The loop's CL points from the start vertex round to it again; the
    // start moves back to the beginning of its chord run.
    int start = cut.seg;
    for (int k = 0; k < n && segs[static_cast<std::size_t>((start + n - 1) % n)].empty(); ++k)
      start = (start + n - 1) % n;
    std::vector<P3> pts;
    const Loop& loop = node.loops[static_cast<std::size_t>(cut.loop)];
    pts.push_back(sampler.at(loop[static_cast<std::size_t>(start)].a));
    for (int k = 0; k < n; ++k) {
      const auto& s = segs[static_cast<std::size_t>((start + k) % n)];
      pts.insert(pts.end(), s.begin(), s.end());
    }
    if (!climb) std::reverse(pts.begin(), pts.end());
    const P3 s0 = pts.front();
    if (first || cut.link == LinkKind::Retract) {
      move_to_start(path, {s0.x, s0.y}, s0.z, LinkKind::Retract, p.safe_z);
    } else if (path.size() > 0) {
      // A feed link that follows the floor (a straight 3D move could dip
      // into a convex floor).
      const P3 from{path.x.back(), path.y.back(), path.z.back()};
      std::vector<P3> link;
      sampler.chord(from, s0, 0, link);
      for (const P3& q : link) path.add(MoveKind::Feed, q.x, q.y, q.z);
      ++m.feed_links;
    }
    for (std::size_t i = 1; i < pts.size(); ++i)
      path.add(MoveKind::Feed, pts[i].x, pts[i].y, pts[i].z);
    ++m.loops;
    first = false;
  }
  int depth = 0;
  for (const TreeNode& nd : tree.nodes) depth = std::max(depth, nd.depth);
  m.tree_depth = std::max(m.tree_depth, depth);
  m.reduced_intervals += tree.reduced;
  if (!tree.nodes.empty()) {
    m.min_interval = m.min_interval > 0 ? std::min(m.min_interval, tree.min_step) : tree.min_step;
    m.max_interval = std::max(m.max_interval, tree.max_step);
  }
  progress.report(1.0);
}

}  // namespace isocam::pocket
