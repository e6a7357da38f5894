// Cutting order by the offset tree and spiral linking (Suh & Lee section
// 2.3). Their rule: the deepest profile first, then its father; at a node
// with brothers not yet machined, the deepest node of a brother next; so the
// tool always works outward, towards the walls and the islands.
//
// Here the brother taken next is the one nearest to the tool, and a node's
// own loops (its outer profile and grown islands) are cut nearest first,
// each from its point nearest to the tool. The move there is a feed link
// (no retract) when
//   (a) it stays inside the allowed region (the region shrunk by r, the
//       tree's roots): checked exactly against those loops, and
//   (b) it runs inside the area already cut, except for its last `step`
//       (the band between the loop and the ones inside it, which the link
//       steps over as a spiral does). The cut area is a raster of cells
//       whose whole square is within r of a loop already cut.
// Otherwise the tool retracts.
#include <algorithm>
#include <cmath>

#include "pocketing/pocket_plan.h"

namespace isocam::pocket {
namespace {

class CutMap {
 public:
  CutMap(const Box2& box, double cell)
      : x0_(box.x0),
        y0_(box.y0),
        cell_(cell),
        nx_(static_cast<long>(std::ceil((box.x1 - box.x0) / cell)) + 1),
        ny_(static_cast<long>(std::ceil((box.y1 - box.y0) / cell)) + 1),
        bits_(static_cast<std::size_t>(nx_ * ny_), 0) {}

  double cell() const { return cell_; }

  // Marks the cells whose centre is within rr of the segment.
  void mark(const Seg& s, double rr) {
    const double len = s.length();
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / std::max(rr, 4.0 * cell_))));
    for (int k = 0; k < pieces; ++k) {
      const Seg p = s.sub(static_cast<double>(k) / pieces, static_cast<double>(k + 1) / pieces);
      const Box2 b = seg_box(p);
      const long i0 = std::max(0L, static_cast<long>(std::floor((b.x0 - rr - x0_) / cell_)));
      const long i1 = std::min(nx_ - 1, static_cast<long>(std::ceil((b.x1 + rr - x0_) / cell_)));
      const long j0 = std::max(0L, static_cast<long>(std::floor((b.y0 - rr - y0_) / cell_)));
      const long j1 = std::min(ny_ - 1, static_cast<long>(std::ceil((b.y1 + rr - y0_) / cell_)));
      for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i) {
          auto& bit = bits_[static_cast<std::size_t>(j * nx_ + i)];
          if (bit) continue;
          const P2 c{x0_ + (static_cast<double>(i) + 0.5) * cell_,
                     y0_ + (static_cast<double>(j) + 0.5) * cell_};
          if (nearest_on_seg(p, c).d <= rr) bit = 1;
        }
    }
  }

  bool covered(P2 p) const {
    const auto i = static_cast<long>(std::floor((p.x - x0_) / cell_));
    const auto j = static_cast<long>(std::floor((p.y - y0_) / cell_));
    if (i < 0 || j < 0 || i >= nx_ || j >= ny_) return false;
    return bits_[static_cast<std::size_t>(j * nx_ + i)] != 0;
  }

 private:
  double x0_, y0_, cell_;
  long nx_, ny_;
  std::vector<std::uint8_t> bits_;
};

class Orderer {
 public:
  Orderer(const OffsetTree& tree, const OrderOptions& opt)
      : tree_(tree),
        opt_(opt),
        allowed_segs_(collect_allowed()),
        allowed_(allowed_segs_),
        map_(map_box(), std::max(opt.radius / 6.0, map_box().size() / 3000.0)) {}

  std::vector<LoopCut> run() {
    std::vector<int> roots = tree_.roots;
    while (!roots.empty()) {
      const std::size_t k = pick(roots);
      const int id = roots[k];
      roots.erase(roots.begin() + static_cast<std::ptrdiff_t>(k));
      visit(id);
    }
    return std::move(cuts_);
  }

 private:
  const TreeNode& node(int id) const { return tree_.nodes[static_cast<std::size_t>(id)]; }

  std::vector<Seg> collect_allowed() const {
    std::vector<Seg> segs;
    for (int id : tree_.roots)
      for (const Loop& l : node(id).loops) segs.insert(segs.end(), l.begin(), l.end());
    return segs;
  }

  Box2 map_box() const {
    Box2 b;
    for (const Seg& s : allowed_segs_) b.add(seg_box(s));
    b.x0 -= opt_.radius;
    b.y0 -= opt_.radius;
    b.x1 += opt_.radius;
    b.y1 += opt_.radius;
    return b;
  }

  // Subtree heights of all nodes, without recursion (a tree can be tens of
  // thousands of levels deep: a tiny stepover on a large face). A node's
  // children come after it in tree_.nodes (the tree is built breadth first),
  // but the order is not relied on: nodes are finished from a post-order.
  std::vector<int> subtree_heights() const {
    std::vector<int> h(tree_.nodes.size(), 0);
    std::vector<int> order;
    order.reserve(tree_.nodes.size());
    std::vector<int> stack(tree_.roots.begin(), tree_.roots.end());
    while (!stack.empty()) {
      const int id = stack.back();
      stack.pop_back();
      order.push_back(id);
      for (int c : node(id).children) stack.push_back(c);
    }
    for (auto it = order.rbegin(); it != order.rend(); ++it)
      for (int c : node(*it).children)
        h[static_cast<std::size_t>(*it)] =
            std::max(h[static_cast<std::size_t>(*it)], 1 + h[static_cast<std::size_t>(c)]);
    return h;
  }

  int height(int id) const {
    if (heights_.empty()) heights_ = subtree_heights();
    return heights_[static_cast<std::size_t>(id)];
  }

  // The node among `ids` to go to next: nearest to the tool, or at the very
  // start the one with the deepest subtree.
  std::size_t pick(const std::vector<int>& ids) const {
    std::size_t best = 0;
    double best_v = 1e300;
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const double v = have_pos_ ? nearest_on_loops(node(ids[k]).loops, pos_).distance
                                 : -static_cast<double>(height(ids[k]));
      if (v < best_v) {
        best_v = v;
        best = k;
      }
    }
    return best;
  }

  // Depth first: the children of a node (nearest to the tool first, each
  // with its whole subtree) before the node itself. An explicit stack, not
  // recursion, for the same reason as subtree_heights().
  void visit(int root) {
    struct Frame {
      int id;
      std::vector<int> todo;
    };
    std::vector<Frame> stack;
    stack.push_back({root, node(root).children});
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (!f.todo.empty()) {
        const std::size_t k = pick(f.todo);
        const int c = f.todo[k];
        f.todo.erase(f.todo.begin() + static_cast<std::ptrdiff_t>(k));
        stack.push_back({c, node(c).children});  // f is not used after this
        continue;
      }
      const int id = f.id;
      stack.pop_back();
      cut_node(id);
    }
  }

  // Cuts the loops of one node, nearest to the tool first.
  void cut_node(int id) {
    opt_.progress.check();
    const TreeNode& n = node(id);
    std::vector<int> todo(n.loops.size());
    for (std::size_t i = 0; i < todo.size(); ++i) todo[i] = static_cast<int>(i);
    while (!todo.empty()) {
      std::size_t k = 0;
      LoopCut cut;
      cut.node = id;
      if (have_pos_) {
        double best = 1e300;
        for (std::size_t m = 0; m < todo.size(); ++m) {
          const NearestOnLoops q =
              nearest_on_loops({n.loops[static_cast<std::size_t>(todo[m])]}, pos_);
          if (q.distance < best) {
            best = q.distance;
            k = m;
            cut.seg = q.seg;
            cut.t = q.t;
          }
        }
      }
      cut.loop = todo[k];
      todo.erase(todo.begin() + static_cast<std::ptrdiff_t>(k));
      const Loop& loop = n.loops[static_cast<std::size_t>(cut.loop)];
      if (opt_.vertices_only && cut.t > 0.0) {
        if (cut.t >= 0.5) cut.seg = (cut.seg + 1) % static_cast<int>(loop.size());
        cut.t = 0.0;
      }
      const P2 start = loop[static_cast<std::size_t>(cut.seg)].at(cut.t);
      if (!have_pos_)
        cut.link = LinkKind::Start;
      else
        cut.link = feed_link_ok(pos_, start, n.step) ? LinkKind::Feed : LinkKind::Retract;
      cuts_.push_back(cut);
      const double rr = opt_.radius - 0.75 * map_.cell();
      for (const Seg& s : loop) map_.mark(s, rr);
      pos_ = start;
      have_pos_ = true;
    }
  }

  bool inside_allowed(P2 a, P2 b) const {
    const Seg ln = Seg::line(a, b);
    const Box2 lb = seg_box(ln);
    std::vector<double> ts{0.0, 1.0};
    std::vector<Hit> hits;
    for (const Seg& s : allowed_segs_) {
      if (!lb.overlaps(seg_box(s), opt_.snap)) continue;
      hits.clear();
      intersect_segs(ln, s, opt_.snap, hits);
      for (const Hit& h : hits) ts.push_back(h.t1);
    }
    std::sort(ts.begin(), ts.end());
    for (std::size_t i = 1; i < ts.size(); ++i) {
      if (ts[i] - ts[i - 1] <= 1e-12) continue;
      const P2 m = ln.at(0.5 * (ts[i - 1] + ts[i]));
      if (allowed_.at(m) >= 1) continue;
      double d = 1e300;
      for (const Seg& s : allowed_segs_) d = std::min(d, nearest_on_seg(s, m).d);
      if (d > 10.0 * opt_.snap) return false;
    }
    return true;
  }

  bool feed_link_ok(P2 from, P2 to, double step) const {
    const double len = dist(from, to);
    if (len <= opt_.snap) return true;
    if (!inside_allowed(from, to)) return false;
    const double exempt = step + map_.cell();
    const int n = static_cast<int>(std::ceil(len / (0.5 * map_.cell())));
    for (int i = 0; i <= n; ++i) {
      const P2 q = from + (static_cast<double>(i) / n) * (to - from);
      if (dist(q, to) <= exempt) continue;
      if (!map_.covered(q)) return false;
    }
    return true;
  }

  const OffsetTree& tree_;
  OrderOptions opt_;
  std::vector<Seg> allowed_segs_;
  WindingIndex allowed_;
  CutMap map_;
  std::vector<LoopCut> cuts_;
  bool have_pos_ = false;
  P2 pos_;
  mutable std::vector<int> heights_;
};

}  // namespace

std::vector<LoopCut> order_cuts(const OffsetTree& tree, const OrderOptions& opt) {
  if (tree.nodes.empty()) return {};
  return Orderer(tree, opt).run();
}

Loop loop_from(const Loop& loop, int seg, double t, bool climb, double snap) {
  Loop out;
  const auto n = static_cast<int>(loop.size());
  const Seg& first = loop[static_cast<std::size_t>(seg)];
  if (t > 0.0 && t < 1.0) {
    Seg head = first.sub(t, 1.0);
    if (head.length() > snap) out.push_back(head);
    for (int k = 1; k < n; ++k) out.push_back(loop[static_cast<std::size_t>((seg + k) % n)]);
    Seg tail = first.sub(0.0, t);
    if (tail.length() > snap) out.push_back(tail);
    if (!out.empty()) out.back().b = out.front().a;
  } else {
    const int s0 = t >= 1.0 ? (seg + 1) % n : seg;
    for (int k = 0; k < n; ++k) out.push_back(loop[static_cast<std::size_t>((s0 + k) % n)]);
  }
  return climb ? out : reversed(out);
}

}  // namespace isocam::pocket
