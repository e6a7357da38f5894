#include "geometry/clearance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <gp_Vec.hxx>
#include <limits>
#include <string>

#include "bits.h"
#include "isocam/errors.h"

namespace isocam {

constexpr int kMaxNet = 100;  // control points per patch: degree 9 x 9, 2 x 32, ...

// The budgets of the queries, each with what bounds it.
//
// Segments asked about at once by blocked() and patch_blocked(): one bit
// each of a std::uint32_t mask.
constexpr int kBatch = 32;
// blocked() walks the hierarchy with a fixed stack: each step pops one node
// and pushes at most its two children, so a walk needs at most depth + 1
// entries. The tree is split at medians (balanced, depth about
// log2(patches / 4)); 128 entries would take some 2^127 patches, so a
// deeper tree is a bug, reported as "hierarchy too deep", not an overflow.
constexpr std::size_t kWalkStack = 128;
// add_piece() stores a piece split while it is larger than max_piece, at
// most this many halvings deep (65536 pieces from one patch): a guard for a
// net whose box does not shrink under subdivision (a degenerate patch), not
// a limit that ordinary patches meet (a halving per level shrinks a 100 mm
// patch to max_piece = 2 mm in about 12 levels).
constexpr int kMaxStoredSplits = 16;
// patch_blocked() examines at most this many pieces per segment asked
// about; a segment still undecided then counts as blocked (it costs some
// path, never a gouge). This bounds the time of one query; the queries that
// reach it are segments grazing the surface at about d, where the band eps
// between "clear" and "blocked" is thin against the pieces' size.
constexpr int kPiecesPerSegment = 4000;
// A piece this many halvings below its patch that is still undecided counts
// as blocked. The split takes the longer direction, so each parameter has
// been halved about 30 times: a box that subdivision shrinks (it must, the
// net converges to the surface) is by then a billionth of the patch across,
// under eps for any patch below eps * 1e9 (100 km at eps = 1e-4). A piece
// undecided there comes from a degenerate net, not from a slow case.
constexpr int kMaxPieceSplits = 60;
// A box whose longest side is e has its diagonal under e sqrt(3).
constexpr double kSqrt3 = 1.7320508075688772;
// The start of a running minimum or of an empty box's bounds: any value
// replaces it.
constexpr double kInf = std::numeric_limits<double>::infinity();

// A control net being subdivided (fixed storage: no allocation per piece).
struct ClearanceModel::Net {
  int pu = 0, pv = 0, depth = 0;
  bool inside = true;                     // known to lie inside the face's trimmed domain
  double u0 = 0, u1 = 1, v0 = 0, v1 = 1;  // its grid parameters
  std::array<H4, kMaxNet> c;              // (a, b) at a + (pu + 1) * b
  int size() const { return (pu + 1) * (pv + 1); }
  H4& at(int a, int b) { return c[static_cast<std::size_t>(a + (pu + 1) * b)]; }
  const H4& at(int a, int b) const { return c[static_cast<std::size_t>(a + (pu + 1) * b)]; }
};

namespace {

gp_Pnt project(const H4& h) { return gp_Pnt(h.x / h.w, h.y / h.w, h.z / h.w); }

using Net = ClearanceModel::Net;

void split_net(const H4* n, int pu, int pv, bool along_u, H4* l, H4* r);

// Splits the net at the parametric middle in u (along_u) or v.
void split(const Net& n, bool along_u, Net& l, Net& r) {
  l = n;
  r = n;
  l.depth = r.depth = n.depth + 1;
  if (along_u) {
    l.u1 = r.u0 = 0.5 * (n.u0 + n.u1);
  } else {
    l.v1 = r.v0 = 0.5 * (n.v0 + n.v1);
  }
  split_net(n.c.data(), n.pu, n.pv, along_u, l.c.data(), r.c.data());
}

// An oriented box around points, in a frame taken from four corner points
// (so a nearly flat piece of surface gets a thin box).
struct Obb {
  gp_XYZ axes[3] = {gp_XYZ(1, 0, 0), gp_XYZ(0, 1, 0), gp_XYZ(0, 0, 1)};
  double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};

  Obb(const gp_Pnt* pts, int n, const gp_Pnt corners[4]) {
    const gp_Vec t1 = gp_Vec(corners[0], corners[1]) + gp_Vec(corners[2], corners[3]);
    const gp_Vec t2 = gp_Vec(corners[0], corners[2]) + gp_Vec(corners[1], corners[3]);
    const gp_Vec nrm = t1.Crossed(t2);
    if (nrm.Magnitude() > 1e-12 && t1.Magnitude() > 1e-12) {
      axes[2] = nrm.Normalized().XYZ();
      axes[0] = t1.Normalized().XYZ();
      axes[1] = axes[2].Crossed(axes[0]);
    }
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < 3; ++j) {
        const double s = pts[k].XYZ().Dot(axes[j]);
        lo[j] = std::min(lo[j], s);
        hi[j] = std::max(hi[j], s);
      }
  }
  double extent() const { return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}); }
  gp_Pnt local(const gp_Pnt& p) const {
    return gp_Pnt(p.XYZ().Dot(axes[0]), p.XYZ().Dot(axes[1]), p.XYZ().Dot(axes[2]));
  }
};

}  // namespace

double segment_box_distance(const gp_Pnt& a, const gp_Pnt& b, const double lo[3],
                            const double hi[3]) {
  // Exact: along p(t) = a + t (b - a) each axis contributes a piecewise
  // linear excess (0 inside its slab), so the squared distance is a convex
  // piecewise quadratic whose pieces end where p(t) crosses a slab plane.
  // Minimise it on each piece in closed form.
  const double pa[3] = {a.X(), a.Y(), a.Z()};
  const double dir[3] = {b.X() - a.X(), b.Y() - a.Y(), b.Z() - a.Z()};
  double ts[8];
  int n = 0;
  ts[n++] = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (dir[k] == 0.0) continue;
    for (double plane : {lo[k], hi[k]}) {
      const double t = (plane - pa[k]) / dir[k];
      if (t > 0.0 && t < 1.0) ts[n++] = t;
    }
  }
  ts[n++] = 1.0;
  for (int i = 1; i < n; ++i)  // insertion sort of at most 8 values
    for (int j = i; j > 0 && ts[j - 1] > ts[j]; --j) std::swap(ts[j - 1], ts[j]);
  double best = kInf;
  for (int i = 0; i + 1 < n; ++i) {
    const double t0 = ts[i], t1 = ts[i + 1], tm = 0.5 * (t0 + t1);
    // Excess on each axis is alpha + beta t on this piece.
    double A = 0, B = 0, C = 0;
    for (int k = 0; k < 3; ++k) {
      const double p = pa[k] + tm * dir[k];
      double alpha = 0, beta = 0;
      if (p < lo[k]) {
        alpha = lo[k] - pa[k];
        beta = -dir[k];
      } else if (p > hi[k]) {
        alpha = pa[k] - hi[k];
        beta = dir[k];
      }
      A += beta * beta;
      B += 2 * alpha * beta;
      C += alpha * alpha;
    }
    double t = A > 0 ? std::clamp(-B / (2 * A), t0, t1) : (B > 0 ? t0 : t1);
    best = std::min(best, std::max(0.0, (A * t + B) * t + C));
    if (best == 0.0) break;
  }
  return std::sqrt(best);
}

double segment_box_bound2(const gp_Pnt& a, const gp_Pnt& b, const double lo[3],
                          const double hi[3]) {
  const double pa[3] = {a.X(), a.Y(), a.Z()}, pb[3] = {b.X(), b.Y(), b.Z()};
  double e2 = 0;
  for (int k = 0; k < 3; ++k) {
    const double e =
        std::max({0.0, lo[k] - std::max(pa[k], pb[k]), std::min(pa[k], pb[k]) - hi[k]});
    e2 += e * e;
  }
  return e2;
}

bool segment_box_beyond(const gp_Pnt& a, const gp_Pnt& b, const double lo[3], const double hi[3],
                        double d) {
  const double e2 = segment_box_bound2(a, b, lo, hi);
  if (e2 >= d * d) return true;
  // For a point the bound is the distance.
  if (a.X() == b.X() && a.Y() == b.Y() && a.Z() == b.Z()) return false;
  return segment_box_distance(a, b, lo, hi) >= d;
}

void ClearanceModel::Box::add(const gp_Pnt& p) {
  const double q[3] = {p.X(), p.Y(), p.Z()};
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min(lo[k], q[k]);
    hi[k] = std::max(hi[k], q[k]);
  }
}

void ClearanceModel::Box::add(const Box& b) {
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::min(lo[k], b.lo[k]);
    hi[k] = std::max(hi[k], b.hi[k]);
  }
}

void ClearanceModel::add(const PatchGrid& g, const TrimDomain* trim) {
  const std::size_t n = static_cast<std::size_t>((g.degree_u() + 1) * (g.degree_v() + 1));
  if (n > static_cast<std::size_t>(kMaxNet))
    throw GeometryError("surface degree " + std::to_string(g.degree_u()) + " x " +
                        std::to_string(g.degree_v()) + " has more than " + std::to_string(kMaxNet) +
                        " control points per patch");
  for (int j = 0; j < g.patches_v(); ++j) {
    for (int i = 0; i < g.patches_u(); ++i) {
      Net net;
      net.pu = g.degree_u();
      net.pv = g.degree_v();
      net.u0 = g.ubreaks()[static_cast<std::size_t>(i)];
      net.u1 = g.ubreaks()[static_cast<std::size_t>(i) + 1];
      net.v0 = g.vbreaks()[static_cast<std::size_t>(j)];
      net.v1 = g.vbreaks()[static_cast<std::size_t>(j) + 1];
      std::copy(g.patch(i, j), g.patch(i, j) + n, net.c.begin());
      add_piece(net, g, trim);
    }
  }
}

void ClearanceModel::add_piece(const Net& net, const PatchGrid& grid, const TrimDomain* trim) {
  TrimDomain::RectClass state = TrimDomain::RectClass::Inside;
  if (trim) {
    state = trim->classify_rect(net.u0, net.u1, net.v0, net.v1);
    if (state == TrimDomain::RectClass::Outside) return;  // no part of the face here
  }
  const int n = net.size();
  std::array<gp_Pnt, kMaxNet> pts;
  Box box;
  for (int k = 0; k < n; ++k) {
    pts[static_cast<std::size_t>(k)] = project(net.c[static_cast<std::size_t>(k)]);
    box.add(pts[static_cast<std::size_t>(k)]);
  }
  const gp_Pnt corners[4] = {pts[0], project(net.at(net.pu, 0)), project(net.at(0, net.pv)),
                             pts[static_cast<std::size_t>(n - 1)]};
  const Obb obb(pts.data(), n, corners);
  // Large pieces are stored split (to about max_piece_), so that a query
  // starts from pieces whose oriented boxes are already tight.
  if (obb.extent() > max_piece_ && net.depth < kMaxStoredSplits) {
    const double lu = corners[0].Distance(corners[1]) + corners[2].Distance(corners[3]);
    const double lv = corners[0].Distance(corners[2]) + corners[1].Distance(corners[3]);
    Net left, right;
    split(net, lu >= lv, left, right);
    add_piece(left, grid, trim);
    add_piece(right, grid, trim);
    return;
  }
  Patch p;
  p.pu = net.pu;
  p.pv = net.pv;
  p.u0 = net.u0;
  p.u1 = net.u1;
  p.v0 = net.v0;
  p.v1 = net.v1;
  for (int k = 0; k < n && !p.rational; ++k)
    p.rational = net.c[static_cast<std::size_t>(k)].w != 1.0;
  p.trim = state == TrimDomain::RectClass::Boundary ? trim : nullptr;
  p.grid = &grid;
  p.first = cps_.size();
  cps_.insert(cps_.end(), net.c.begin(), net.c.begin() + n);
  p.box = box;
  for (int k = 0; k < 3; ++k) {
    p.axes[k] = obb.axes[k];
    p.olo[k] = obb.lo[k];
    p.ohi[k] = obb.hi[k];
  }
  patches_.push_back(p);
}

void ClearanceModel::build() {
  order_.resize(patches_.size());
  for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
  nodes_.clear();
  if (!patches_.empty()) build_node(0, static_cast<int>(patches_.size()));
}

int ClearanceModel::build_node(int lo, int hi) {
  const int id = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Box box, centres;
  for (int k = lo; k < hi; ++k) {
    const Box& b = patches_[static_cast<std::size_t>(order_[static_cast<std::size_t>(k)])].box;
    box.add(b);
    centres.add(
        gp_Pnt(0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0.5 * (b.lo[2] + b.hi[2])));
  }
  nodes_[static_cast<std::size_t>(id)].box = box;
  if (hi - lo <= 4) {
    nodes_[static_cast<std::size_t>(id)].patch_lo = lo;
    nodes_[static_cast<std::size_t>(id)].patch_hi = hi;
    return id;
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (centres.hi[k] - centres.lo[k] > centres.hi[axis] - centres.lo[axis]) axis = k;
  const int mid = (lo + hi) / 2;
  std::nth_element(order_.begin() + lo, order_.begin() + mid, order_.begin() + hi,
                   [&](int x, int y) {
                     const Box& bx = patches_[static_cast<std::size_t>(x)].box;
                     const Box& by = patches_[static_cast<std::size_t>(y)].box;
                     return bx.lo[axis] + bx.hi[axis] < by.lo[axis] + by.hi[axis];
                   });
  const int left = build_node(lo, mid);
  const int right = build_node(mid, hi);
  nodes_[static_cast<std::size_t>(id)].left = left;
  nodes_[static_cast<std::size_t>(id)].right = right;
  return id;
}

// A segment of ball-centre positions, with what the distance tests reuse.
struct ClearanceModel::Segment {
  gp_Pnt a, b;
  gp_XYZ ab;
  double ab2 = 0.0;
  Segment() = default;
  Segment(const gp_Pnt& p, const gp_Pnt& q)
      : a(p), b(q), ab(q.XYZ() - p.XYZ()), ab2(ab.SquareModulus()) {}
};

bool ClearanceModel::clear(const gp_Pnt& a, const gp_Pnt& b, double d, Witness* witness) const {
  const Segment seg(a, b);
  return blocked(&seg, 1, d, witness) == 0;
}

bool ClearanceModel::clear_except(const gp_Pnt& a, const gp_Pnt& b, double d,
                                  const PatchGrid* const* skip, int n, Witness* witness) const {
  const Segment seg(a, b);
  return blocked(&seg, 1, d, witness, Skip{skip, n}) == 0;
}

void ClearanceModel::clear_polyline(const gp_Pnt* pts, std::size_t n, double d, char* out) const {
  std::array<Segment, kBatch> segs;
  for (std::size_t first = 0; first + 1 < n; first += kBatch) {
    const int count = static_cast<int>(std::min<std::size_t>(kBatch, n - 1 - first));
    for (int k = 0; k < count; ++k)
      segs[static_cast<std::size_t>(k)] = Segment(pts[first + k], pts[first + k + 1]);
    const std::uint32_t hit = blocked(segs.data(), count, d, nullptr);
    for (int k = 0; k < count; ++k) out[first + static_cast<std::size_t>(k)] = !(hit >> k & 1u);
  }
}

namespace {
double squared_point_segment_distance(const gp_XYZ& p, const gp_XYZ& a, const gp_XYZ& ab,
                                      double ab2) {
  const gp_XYZ ap = p - a;
  const double t = ab2 > 0 ? std::clamp(ap.Dot(ab) / ab2, 0.0, 1.0) : 0.0;
  return (ap - ab * t).SquareModulus();
}

// The top of the column above c that clear_above() queries.
gp_Pnt column_top(const gp_Pnt& c, double top, double d) {
  return gp_Pnt(c.X(), c.Y(), std::max(c.Z(), top + d));
}
}  // namespace

bool ClearanceModel::clear_above(const gp_Pnt& c, double d, Witness* witness) const {
  return clear(c, column_top(c, top(), d), d, witness);
}

bool ClearanceModel::witness_blocks_above(const Witness& w, const gp_Pnt& c, double d) const {
  if (w.grid == nullptr || d <= 2 * eps_) return false;
  const gp_XYZ a = c.XYZ(), ab = column_top(c, top(), d).XYZ() - a;
  const double keep = d - 2 * eps_;
  return squared_point_segment_distance(w.grid->eval(w.u, w.v).XYZ(), a, ab, ab.SquareModulus()) <
         keep * keep;
}

void ClearanceModel::clear_above(const gp_Pnt* pts, std::size_t n, double d, char* out) const {
  std::array<Segment, 32> segs;
  const double z = top();
  for (std::size_t first = 0; first < n; first += 32) {
    const int count = static_cast<int>(std::min<std::size_t>(32, n - first));
    for (int k = 0; k < count; ++k) {
      const gp_Pnt& c = pts[first + static_cast<std::size_t>(k)];
      segs[static_cast<std::size_t>(k)] = Segment(c, column_top(c, z, d));
    }
    const std::uint32_t hit = blocked(segs.data(), count, d, nullptr);
    // A batch that runs out of work budget counts all its undecided columns
    // blocked; a long column beside a wall is such a slow case, so the
    // blocked ones of a batch are asked again one by one.
    for (int k = 0; k < count; ++k)
      out[first + static_cast<std::size_t>(k)] =
          !(hit >> k & 1u) ||
          (count > 1 && blocked(&segs[static_cast<std::size_t>(k)], 1, d, nullptr) == 0);
  }
}

std::uint32_t ClearanceModel::blocked(const Segment* segs, int count, double d, Witness* witness,
                                      const Skip& skip) const {
  if (nodes_.empty() || count == 0) return 0;
  const std::uint32_t all = count == kBatch ? ~0u : (1u << count) - 1u;
  const double keep = d - eps_;  // what a box must be beyond to be passed
  // The segments of `mask` that are not beyond the box.
  auto near = [&](std::uint32_t mask, const double lo[3], const double hi[3]) {
    for (std::uint32_t m = mask; m; m &= m - 1) {
      const Segment& s = segs[lowest_bit(m)];
      if (segment_box_beyond(s.a, s.b, lo, hi, keep)) mask &= ~(m & -m);
    }
    return mask;
  };
  // Nearest node first (for the lowest segment asked about): the answers
  // do not depend on the order (a witness blocks its segment, and the set of
  // pieces that would be examined for a segment is fixed), but a query that
  // is not clear usually stops at its first node. The tree is balanced, so
  // its depth is about log2(patches / 4).
  std::array<std::pair<int, std::uint32_t>, kWalkStack> stack;
  std::size_t top = 0;
  std::uint32_t hit = 0;
  const std::uint32_t root = near(all, nodes_[0].box.lo, nodes_[0].box.hi);
  if (!root) return 0;
  stack[top++] = {0, root};
  while (top > 0 && hit != all) {
    const auto [id, asked] = stack[--top];
    const std::uint32_t mask = asked & ~hit;
    if (!mask) continue;
    const Node& n = nodes_[static_cast<std::size_t>(id)];
    if (n.left >= 0) {
      const Node& l = nodes_[static_cast<std::size_t>(n.left)];
      const Node& r = nodes_[static_cast<std::size_t>(n.right)];
      const std::uint32_t near_l = near(mask, l.box.lo, l.box.hi);
      const std::uint32_t near_r = near(mask, r.box.lo, r.box.hi);
      if (top + 2 > stack.size()) throw GeometryError("clearance: hierarchy too deep");
      const Segment& s = segs[lowest_bit(mask)];
      const bool left_first = segment_box_bound2(s.a, s.b, l.box.lo, l.box.hi) <=
                              segment_box_bound2(s.a, s.b, r.box.lo, r.box.hi);
      if (left_first ? near_r : near_l)
        stack[top++] = {left_first ? n.right : n.left, left_first ? near_r : near_l};
      if (left_first ? near_l : near_r)
        stack[top++] = {left_first ? n.left : n.right, left_first ? near_l : near_r};
      continue;
    }
    for (int k = n.patch_lo; k < n.patch_hi; ++k) {
      const Patch& p = patches_[static_cast<std::size_t>(order_[static_cast<std::size_t>(k)])];
      if (skip.n > 0 && skip.has(p.grid)) continue;
      std::uint32_t m = near(mask & ~hit, p.box.lo, p.box.hi);
      for (std::uint32_t b = m; b; b &= b - 1) {
        const Segment& s = segs[lowest_bit(b)];
        auto local = [&p](const gp_Pnt& q) {
          return gp_Pnt(q.XYZ().Dot(p.axes[0]), q.XYZ().Dot(p.axes[1]), q.XYZ().Dot(p.axes[2]));
        };
        if (segment_box_beyond(local(s.a), local(s.b), p.olo, p.ohi, keep)) m &= ~(b & -b);
      }
      if (m) hit |= patch_blocked(p, segs, m, d, witness);
    }
  }
  return hit;
}

namespace {

// A piece of a patch on the per-thread work stack; its control net is
// `size` homogeneous points at `first` in the work buffer (pieces are
// pushed and popped in stack order, so the buffer is a stack too).
struct Piece {
  double u0, u1, v0, v1;
  std::size_t first;
  int depth;
  bool inside;         // known to lie inside the face's trimmed domain
  std::uint32_t mask;  // the segments it is still near
};

struct Work {
  std::vector<Piece> pieces;
  std::vector<H4> cps;
};

// Reused across queries: no allocation once warm.
Work& work() {
  thread_local Work w;
  return w;
}

// de Casteljau split of a (pu x pv) net at its parametric middle in u
// (along_u) or v, into `l` and `r` (same layout: point (a, b) at
// a + (pu + 1) b).
void split_net(const H4* n, int pu, int pv, bool along_u, H4* l, H4* r) {
  const int m = along_u ? pu : pv;  // degree along the split
  const int lines = along_u ? pv + 1 : pu + 1;
  const int stride = along_u ? 1 : pu + 1;  // between points of a line
  const int step = along_u ? pu + 1 : 1;    // between lines
  H4 w[kMaxNet];                            // one line of the net: up to kMaxNet points
  for (int line = 0; line < lines; ++line) {
    const int base = line * step;
    for (int k = 0; k <= m; ++k) w[k] = n[base + k * stride];
    l[base] = w[0];
    r[base + m * stride] = w[m];
    for (int s = 1; s <= m; ++s) {
      for (int k = 0; k + s <= m; ++k) w[k] = (w[k] + w[k + 1]) * 0.5;
      l[base + s * stride] = w[0];
      r[base + (m - s) * stride] = w[m - s];
    }
  }
}

}  // namespace

// One patch_blocked() query: the patch's pieces on the thread's work stack
// (the patch's whole net first) and the segments found blocked so far. The
// member functions are its phases, called in order by patch_blocked() for
// each piece popped.
struct ClearanceModel::PatchQuery {
  const Patch& patch;
  const Segment* segs;
  double d2, keep;
  Witness* witness;
  std::size_t sz;  // control points per piece
  Work& w = work();
  std::uint32_t hit = 0;            // segments shown blocked
  std::array<H4, kMaxNet> c;        // the current piece's net
  std::array<gp_Pnt, kMaxNet> pts;  // and its points in space
  gp_Pnt corners[4];                // its corners (points of the surface)

  PatchQuery(const ClearanceModel& model, const Patch& p, const Segment* s, std::uint32_t mask,
             double d, Witness* wit)
      : patch(p),
        segs(s),
        d2(d * d),
        keep(d - model.eps_),
        witness(wit),
        sz(static_cast<std::size_t>((p.pu + 1) * (p.pv + 1))) {
    w.pieces.clear();
    w.cps.assign(model.cps_.begin() + static_cast<std::ptrdiff_t>(patch.first),
                 model.cps_.begin() + static_cast<std::ptrdiff_t>(patch.first + sz));
    w.pieces.push_back({patch.u0, patch.u1, patch.v0, patch.v1, 0, 0, patch.trim == nullptr, mask});
  }

  // The squared distance from q to the segment of bit `bit`.
  double dist2(const gp_XYZ& q, std::uint32_t bit) const {
    const Segment& s = segs[lowest_bit(bit)];
    return squared_point_segment_distance(q, s.a.XYZ(), s.ab, s.ab2);
  }

  // Pops the top piece into `piece` and its net into c; false when none is
  // left.
  bool pop(Piece& piece) {
    if (w.pieces.empty()) return false;
    piece = w.pieces.back();
    w.pieces.pop_back();
    std::copy(w.cps.begin() + static_cast<std::ptrdiff_t>(piece.first), w.cps.end(), c.begin());
    w.cps.resize(piece.first);
    return true;
  }

  // Out of budget: `m` and every segment a piece still on the stack is near
  // count as blocked (slow cases cost some path, never a gouge).
  void give_up(std::uint32_t m) {
    hit |= m;
    for (const Piece& rest : w.pieces) hit |= rest.mask;
  }

  // False if the piece lies outside the face; otherwise records whether it
  // lies wholly inside (then its points need no further trim test).
  bool on_face(Piece& piece) const {
    if (piece.inside) return true;
    const TrimDomain::RectClass state =
        patch.trim->classify_rect(piece.u0, piece.u1, piece.v0, piece.v1);
    if (state == TrimDomain::RectClass::Outside) return false;
    piece.inside = state == TrimDomain::RectClass::Inside;
    return true;
  }

  // The piece's control points in space (pts) and its corners.
  void load_points() {
    const int pu = patch.pu, pv = patch.pv;
    // A polynomial net keeps w = 1 exactly under subdivision (averages of
    // ones): no division needed.
    if (patch.rational) {
      for (std::size_t k = 0; k < sz; ++k) pts[k] = project(c[k]);
    } else {
      for (std::size_t k = 0; k < sz; ++k) pts[k].SetCoord(c[k].x, c[k].y, c[k].z);
    }
    corners[0] = pts[0];
    corners[1] = pts[static_cast<std::size_t>(pu)];
    corners[2] = pts[static_cast<std::size_t>((pu + 1) * pv)];
    corners[3] = pts[sz - 1];
  }

  // Witnesses: a corner of the piece is a point of the surface (and, on a
  // trimmed face, must be a point of the face); every segment of `m` closer
  // than d to one is blocked (added to hit, the last such corner given as
  // the witness). Returns the segments of `m` still undecided.
  std::uint32_t corner_witnesses(const Piece& piece, std::uint32_t m) {
    const double cu[4] = {piece.u0, piece.u1, piece.u0, piece.u1};
    const double cv[4] = {piece.v0, piece.v0, piece.v1, piece.v1};
    for (int k = 0; k < 4 && m; ++k) {
      int inside = piece.inside ? 1 : -1;  // -1: not asked yet
      for (std::uint32_t b = m; b; b &= b - 1) {
        if (dist2(corners[k].XYZ(), b & -b) >= d2) continue;
        if (inside < 0) inside = patch.trim->contains(cu[k], cv[k]) ? 1 : 0;
        if (!inside) break;
        hit |= b & -b;
        if (witness) *witness = {patch.grid, cu[k], cv[k]};
      }
      m &= ~hit;
    }
    return m;
  }

  // The segments of `m` not provably beyond d - eps of the piece's oriented
  // box (a frame from its corners, so a nearly flat piece gets a thin box).
  std::uint32_t near_box(const Obb& box, std::uint32_t m) const {
    for (std::uint32_t b = m; b; b &= b - 1) {
      const Segment& s = segs[lowest_bit(b)];
      if (segment_box_beyond(box.local(s.a), box.local(s.b), box.lo, box.hi, keep)) m &= ~(b & -b);
    }
    return m;
  }

  // Splits the piece across the longer parametric direction of its control
  // net and pushes both halves, near `m`. The half on the side of the corner
  // nearer the (first) segment goes on top, so that a witness, if any, is
  // met early (the answers do not depend on the order, only the work).
  void push_halves(const Piece& piece, std::uint32_t m) {
    const double lu = corners[0].Distance(corners[1]) + corners[2].Distance(corners[3]);
    const double lv = corners[0].Distance(corners[2]) + corners[1].Distance(corners[3]);
    const bool along_u = lu >= lv;
    const std::size_t at = w.cps.size();
    w.cps.resize(at + 2 * sz);
    const bool low_nearer = dist2(corners[0].XYZ(), m & -m) <= dist2(corners[3].XYZ(), m & -m);
    H4* bottom = w.cps.data() + at;
    split_net(c.data(), patch.pu, patch.pv, along_u, low_nearer ? bottom + sz : bottom,
              low_nearer ? bottom : bottom + sz);
    Piece lo = piece, hi = piece;
    lo.depth = hi.depth = piece.depth + 1;
    lo.mask = hi.mask = m;
    if (along_u) {
      lo.u1 = hi.u0 = 0.5 * (piece.u0 + piece.u1);
    } else {
      lo.v1 = hi.v0 = 0.5 * (piece.v0 + piece.v1);
    }
    Piece& below = low_nearer ? hi : lo;
    Piece& above = low_nearer ? lo : hi;
    below.first = at;
    above.first = at + sz;
    w.pieces.push_back(below);
    w.pieces.push_back(above);
  }
};

// Subdivides the patch depth first until each segment of `mask` is decided:
// blocked by a corner witness, or clear because every piece near it is
// outside the face, provably beyond d - eps, or smaller than eps across.
std::uint32_t ClearanceModel::patch_blocked(const Patch& patch, const Segment* segs,
                                            std::uint32_t mask, double d, Witness* witness) const {
  PatchQuery q(*this, patch, segs, mask, d, witness);
  int budget = kPiecesPerSegment * bit_count(mask);
  Piece piece{};
  while ((mask & ~q.hit) && q.pop(piece)) {
    std::uint32_t m = piece.mask & ~q.hit;
    if (!m) continue;
    if (--budget < 0) {
      q.give_up(m);
      break;
    }
    if (!q.on_face(piece)) continue;
    q.load_points();
    m = q.corner_witnesses(piece, m);
    if (!m) continue;
    const Obb box(q.pts.data(), static_cast<int>(q.sz), q.corners);
    m = q.near_box(box, m);
    if (!m) continue;
    // A piece this small with no corner closer than d has no point closer
    // than d - eps (its box's diagonal is under eps).
    if (box.extent() * kSqrt3 <= eps_) continue;
    // Subdivision that does not shrink the box (it should): not proved.
    if (piece.depth > kMaxPieceSplits) {
      q.hit |= m;
      continue;
    }
    q.push_halves(piece, m);
  }
  return q.hit;
}

double ClearanceModel::local_distance(const gp_Pnt& q, Witness* w) {
  const PatchGrid& g = *w->grid;
  // Newton's method on f(u, v) = |S(u, v) - q|^2 / 2 over the grid's
  // rectangle, second derivatives of S by central differences of the first
  // (h: far above rounding, far below the curvature's scale); a step that
  // does not lower f is halved, one that still does not ends the search.
  const double lo[2] = {g.umin(), g.vmin()}, hi[2] = {g.umax(), g.vmax()};
  const double h[2] = {1e-5 * (hi[0] - lo[0]), 1e-5 * (hi[1] - lo[1])};
  double u = std::clamp(w->u, lo[0], hi[0]), v = std::clamp(w->v, lo[1], hi[1]);
  SurfaceDerivs d = g.d1(u, v);
  double f = q.SquareDistance(d.p);
  for (int it = 0; it < 30; ++it) {
    const double uc = std::clamp(u, lo[0] + h[0], hi[0] - h[0]);
    const double vc = std::clamp(v, lo[1] + h[1], hi[1] - h[1]);
    const SurfaceDerivs pu = g.d1(uc + h[0], vc), mu = g.d1(uc - h[0], vc);
    const SurfaceDerivs pv = g.d1(uc, vc + h[1]), mv = g.d1(uc, vc - h[1]);
    const gp_Vec suu = (pu.su - mu.su) / (2 * h[0]), svv = (pv.sv - mv.sv) / (2 * h[1]);
    const gp_Vec suv = 0.5 * ((pu.sv - mu.sv) / (2 * h[0]) + (pv.su - mv.su) / (2 * h[1]));
    const gp_Vec e(q, d.p);
    const double gu = e.Dot(d.su), gv = e.Dot(d.sv);
    const double huu = d.su.Dot(d.su) + e.Dot(suu), hvv = d.sv.Dot(d.sv) + e.Dot(svv);
    const double huv = d.su.Dot(d.sv) + e.Dot(suv);
    const double det = huu * hvv - huv * huv;
    double du, dv;
    if (huu > 0 && det > 1e-12 * huu * hvv) {
      du = -(hvv * gu - huv * gv) / det;
      dv = -(huu * gv - huv * gu) / det;
    } else {  // not convex here: a gradient step
      const double n2 = d.su.SquareMagnitude() + d.sv.SquareMagnitude();
      if (!(n2 > 0)) break;
      du = -gu / n2;
      dv = -gv / n2;
    }
    double step = 1.0, nu = u, nv = v;
    SurfaceDerivs nd = d;
    bool lower = false;
    for (int k = 0; k < 30 && !lower; ++k, step *= 0.5) {
      nu = std::clamp(u + step * du, lo[0], hi[0]);
      nv = std::clamp(v + step * dv, lo[1], hi[1]);
      nd = g.d1(nu, nv);
      lower = q.SquareDistance(nd.p) <= f;
    }
    if (!lower) break;
    // The distance is stationary at the minimum: parameters to 1e-10 of
    // the range put it within rounding.
    const bool still =
        std::abs(nu - u) <= 1e-10 * (hi[0] - lo[0]) && std::abs(nv - v) <= 1e-10 * (hi[1] - lo[1]);
    u = nu;
    v = nv;
    d = nd;
    f = q.SquareDistance(d.p);
    if (still) break;
  }
  w->u = u;
  w->v = v;
  return std::sqrt(f);
}

}  // namespace isocam
