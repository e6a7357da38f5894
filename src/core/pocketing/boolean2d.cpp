// Resolving closed line/arc loops into the region of winding number >= 1
// (Suh & Lee, section 2.2, done with winding numbers instead of the loop
// orientation test so that nested loops, Figure 2.10, need no special case).
//
// 1. Every segment is split at its intersections with all others (sort and
//    sweep on bounding boxes); points within `snap` share one vertex.
// 2. Pieces that coincide (overlapping collinear lines or co-circular arcs)
//    are grouped; a group counts its pieces with their directions.
// 3. A piece is kept when the winding number just right of it is < 1 and
//    just left of it (right + the group's count) is >= 1: it then bounds the
//    region with the region on its left. Only the right side is queried, so
//    the left/right decision of a piece can never contradict itself.
// 4. Kept pieces are chained into loops: at a vertex with several ways on,
//    the one reached first turning clockwise from the way back is taken,
//    which keeps to the boundary of one face (touching loops stay apart).
// 5. Consecutive pieces of one original segment are merged again.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "pocketing/geom2d.h"

namespace isocam {

using namespace pocket;

namespace {

struct Piece {
  int src = 0;
  double t0 = 0.0, t1 = 0.0;
  int v0 = 0, v1 = 0;
  int group = -1;
};

struct Edge {
  int piece;
  bool rev;        // travelled against the source segment's direction
  int from, to;    // vertices
  double out_ang;  // direction leaving `from`
  double in_ang;   // direction arriving at `to`
  bool used = false;
};

double dir_angle(P2 from, P2 to) { return angle_of(to - from); }

// Sub-segment of a piece in its travel direction, with exact end vertices.
Seg piece_seg(const std::vector<Seg>& segs, const Piece& pc, bool rev, const VertexSet& V) {
  Seg s = segs[static_cast<std::size_t>(pc.src)].sub(pc.t0, pc.t1);
  s.a = V[pc.v0];
  s.b = V[pc.v1];
  return rev ? s.reversed() : s;
}

// Short chord length used to compare directions of ways leaving a vertex.
double probe_length(const Seg& s, double scale) {
  double h = std::min(0.25 * s.length(), 1e-3 * scale);
  if (s.kind == SegKind::Arc) h = std::min(h, 0.05 * s.r);
  return std::max(h, 1e-300);
}

// The phases of resolve_loops, in order; each states what it takes and
// what it guarantees to the next.

// The segments that take part: those longer than 0.05 snap (shorter ones
// are below the snapping distance and would only make zero-length pieces).
std::vector<Seg> usable_segments(const std::vector<Loop>& loops, double snap) {
  std::vector<Seg> segs;
  for (const Loop& l : loops)
    for (const Seg& s : l)
      if (s.length() > 0.05 * snap) segs.push_back(s);
  return segs;
}

// Phase 1: the split points of every segment, as (parameter, vertex) pairs
// in V, unsorted. Each segment's end points are snapped to shared vertices
// first and the segment moved onto them, so that the loops are closed
// exactly (the ray-crossing count of phase 3 relies on it); then every pair
// of segments whose boxes overlap (sort and sweep on x) adds its
// intersections to both. Points within `snap` share one vertex.
std::vector<std::vector<std::pair<double, int>>> split_points(std::vector<Seg>& segs, double snap,
                                                              VertexSet& V) {
  const std::size_t n = segs.size();
  std::vector<std::vector<std::pair<double, int>>> splits(n);
  for (std::size_t i = 0; i < n; ++i) {
    const int va = V.insert(segs[i].a), vb = V.insert(segs[i].b);
    segs[i].a = V[va];
    segs[i].b = V[vb];
    splits[i].push_back({0.0, va});
    splits[i].push_back({1.0, vb});
  }
  std::vector<Box2> box(n);
  for (std::size_t i = 0; i < n; ++i) box[i] = seg_box(segs[i]);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return box[a].x0 < box[b].x0; });
  std::vector<Hit> hits;
  for (std::size_t a = 0; a < n; ++a) {
    const std::size_t i = order[a];
    for (std::size_t b = a + 1; b < n; ++b) {
      const std::size_t j = order[b];
      if (box[j].x0 > box[i].x1 + snap) break;
      if (!box[i].overlaps(box[j], snap)) continue;
      hits.clear();
      intersect_segs(segs[i], segs[j], snap, hits);
      for (const Hit& h : hits) {
        const int v = V.insert(h.p);
        splits[i].push_back({h.t1, v});
        splits[j].push_back({h.t2, v});
      }
    }
  }
  return splits;
}

// The pieces between consecutive split points of each segment (sorts
// `splits`), in segment order and along each segment. A split point at the
// vertex the current piece starts from is skipped unless the piece would be
// longer than 4 snap (a whole circle from one vertex back to it); so no
// piece has zero length. Every piece has group -1.
std::vector<Piece> cut_pieces(const std::vector<Seg>& segs,
                              std::vector<std::vector<std::pair<double, int>>>& splits,
                              double snap) {
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    auto& sp = splits[i];
    std::sort(sp.begin(), sp.end());
    const double len = segs[i].length();
    std::size_t k = 0;
    for (std::size_t m = 1; m < sp.size(); ++m) {
      if (sp[m].second == sp[k].second) {
        // Same vertex again: a closed piece only if it is long (a circle).
        if ((sp[m].first - sp[k].first) * len <= 4.0 * snap) continue;
      }
      pieces.push_back(
          {static_cast<int>(i), sp[k].first, sp[m].first, sp[k].second, sp[m].second, -1});
      k = m;
    }
  }
  return pieces;
}

// Groups of coincident pieces (overlapping collinear lines, co-circular
// arcs): the first piece of a group is its representative.
struct Groups {
  std::vector<int> rep;   // representative piece of each group
  std::vector<int> mult;  // signed count of its pieces relative to the representative's direction
};

// Phase 2: puts every piece in a group (sets Piece::group). Two pieces
// coincide when they have the same end vertices and their midpoints are
// within 8 snap; a piece counts +1 when it runs the representative's way,
// -1 against it (for a closed piece, one vertex at both ends, the tangents
// at the midpoints tell). Groups are numbered by their vertex pairs in
// increasing order, then by piece order.
Groups group_coincident(const std::vector<Seg>& segs, std::vector<Piece>& pieces, double snap) {
  std::map<std::pair<int, int>, std::vector<int>> by_ends;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const Piece& pc = pieces[p];
    by_ends[{std::min(pc.v0, pc.v1), std::max(pc.v0, pc.v1)}].push_back(static_cast<int>(p));
  }
  Groups groups;
  for (auto& [ends, list] : by_ends) {
    for (std::size_t a = 0; a < list.size(); ++a) {
      Piece& pa = pieces[static_cast<std::size_t>(list[a])];
      if (pa.group >= 0) continue;
      pa.group = static_cast<int>(groups.rep.size());
      groups.rep.push_back(list[a]);
      groups.mult.push_back(1);
      const Seg& sa = segs[static_cast<std::size_t>(pa.src)];
      const double tm = 0.5 * (pa.t0 + pa.t1);
      const P2 ma = sa.at(tm);
      const P2 ta = sa.tangent(tm);
      for (std::size_t b = a + 1; b < list.size(); ++b) {
        Piece& pb = pieces[static_cast<std::size_t>(list[b])];
        if (pb.group >= 0) continue;
        const Seg& sb = segs[static_cast<std::size_t>(pb.src)];
        const double tmb = 0.5 * (pb.t0 + pb.t1);
        if (dist(sb.at(tmb), ma) > 8.0 * snap) continue;
        pb.group = pa.group;
        const bool same = pa.v0 != pa.v1 ? pb.v0 == pa.v0 : dot(sb.tangent(tmb), ta) > 0;
        groups.mult.back() += same ? 1 : -1;
      }
    }
  }
  return groups;
}

// The kept pieces as directed edges, and the edges leaving each vertex.
struct BoundaryEdges {
  std::vector<Edge> edges;
  std::vector<std::vector<int>> out;  // per vertex of V: indices into edges
};

// Phase 3: the groups that bound the region, one edge each (the group's
// representative piece), directed so that the region is on its left. The
// winding number is queried just right of the representative's midpoint
// (0.01 snap off it); left of it is that plus the group's count. A group is
// kept when exactly one side is in the region (winding >= 1); only the
// right side is queried, so the decision can never contradict itself.
// Edges come in group order; their angles are those of short chords at
// each end (probe_length), for phase 4's turn test.
BoundaryEdges boundary_edges(const std::vector<Seg>& segs, const std::vector<Piece>& pieces,
                             const Groups& groups, const VertexSet& V, double snap, double scale) {
  const WindingIndex wind(segs);
  const double h_probe = 0.01 * snap;
  BoundaryEdges b;
  b.out.resize(static_cast<std::size_t>(V.size()));
  for (std::size_t g = 0; g < groups.rep.size(); ++g) {
    const int mult = groups.mult[g];
    if (mult == 0) continue;
    const Piece& pc = pieces[static_cast<std::size_t>(groups.rep[g])];
    const Seg& s = segs[static_cast<std::size_t>(pc.src)];
    const double tm = 0.5 * (pc.t0 + pc.t1);
    const P2 t = s.tangent(tm);
    const P2 q = s.at(tm) + h_probe * P2{t.y, -t.x};  // just right of the piece
    const int w_right = wind.at(q);
    const int w_left = w_right + mult;
    bool rev;
    if (w_right < 1 && w_left >= 1)
      rev = false;
    else if (w_right >= 1 && w_left < 1)
      rev = true;
    else
      continue;
    const Seg es = piece_seg(segs, pc, rev, V);
    const double hp = probe_length(es, scale);
    Edge e{groups.rep[g],
           rev,
           rev ? pc.v1 : pc.v0,
           rev ? pc.v0 : pc.v1,
           dir_angle(es.a, point_near_start(es, hp)),
           dir_angle(point_near_end(es, hp), es.b)};
    b.out[static_cast<std::size_t>(e.from)].push_back(static_cast<int>(b.edges.size()));
    b.edges.push_back(e);
  }
  return b;
}

// Phase 4: the edges chained into closed loops (lists of edge indices, each
// edge in at most one). From an unused edge, at each vertex the unused way
// on reached first turning clockwise from the way back is taken (straight
// back only as the last resort), which keeps to the boundary of one face, so
// loops that touch at a vertex stay apart; the chain closes when that way is
// its first edge. A chain that meets a dead end (only possible numerically)
// or does not close within as many steps as there are edges is dropped.
// Marks the edges it visits used.
std::vector<std::vector<int>> chain_loops(BoundaryEdges& b) {
  std::vector<Edge>& edges = b.edges;
  std::vector<std::vector<int>> chains;
  for (std::size_t e0 = 0; e0 < edges.size(); ++e0) {
    if (edges[e0].used) continue;
    std::vector<int> chain{static_cast<int>(e0)};
    edges[e0].used = true;
    const int start = edges[e0].from;
    bool closed = false;
    for (std::size_t guard = 0; guard <= edges.size(); ++guard) {
      const Edge& cur = edges[static_cast<std::size_t>(chain.back())];
      const int v = cur.to;
      const double back = cur.in_ang + kPi;  // the way back, as an angle
      int best = -1;
      // Clockwise turns are in (0, 2 pi]: anything beats "none found yet".
      double best_cw = std::numeric_limits<double>::infinity();
      auto consider = [&](int ei) {
        double cw = wrap_2pi(back - edges[static_cast<std::size_t>(ei)].out_ang);
        if (cw < 1e-12) cw = kTwoPi;  // straight back: the last resort
        if (cw < best_cw) {
          best_cw = cw;
          best = ei;
        }
      };
      for (int ei : b.out[static_cast<std::size_t>(v)])
        if (!edges[static_cast<std::size_t>(ei)].used) consider(ei);
      if (v == start) consider(static_cast<int>(e0));
      if (best < 0) break;  // dead end (numerical): drop the chain
      if (best == static_cast<int>(e0)) {
        closed = true;
        break;
      }
      edges[static_cast<std::size_t>(best)].used = true;
      chain.push_back(best);
    }
    if (closed) chains.push_back(std::move(chain));
  }
  return chains;
}

// Phase 5: one chain as a loop, consecutive edges of one source segment
// travelled the same way and meeting at the same parameter merged into one
// segment again (the chain is first rotated so that it does not start
// inside such a run). The loop's segments end exactly at the chain's
// vertices.
Loop merged_loop(std::vector<int>& chain, const std::vector<Edge>& edges,
                 const std::vector<Piece>& pieces, const std::vector<Seg>& segs,
                 const VertexSet& V) {
  auto mergeable = [&](int ea, int eb) {
    const Edge& a = edges[static_cast<std::size_t>(ea)];
    const Edge& b = edges[static_cast<std::size_t>(eb)];
    const Piece& pa = pieces[static_cast<std::size_t>(a.piece)];
    const Piece& pb = pieces[static_cast<std::size_t>(b.piece)];
    if (pa.src != pb.src || a.rev != b.rev) return false;
    return a.rev ? pa.t0 == pb.t1 : pa.t1 == pb.t0;
  };
  std::size_t rot = 0;
  while (rot < chain.size() &&
         mergeable(chain[(rot + chain.size() - 1) % chain.size()], chain[rot]))
    ++rot;
  if (rot == chain.size()) rot = 0;
  std::rotate(chain.begin(), chain.begin() + static_cast<std::ptrdiff_t>(rot), chain.end());
  Loop loop;
  for (std::size_t k = 0; k < chain.size();) {
    std::size_t m = k + 1;
    while (m < chain.size() && mergeable(chain[m - 1], chain[m])) ++m;
    const Edge& ef = edges[static_cast<std::size_t>(chain[k])];
    const Edge& el = edges[static_cast<std::size_t>(chain[m - 1])];
    const Piece& pf = pieces[static_cast<std::size_t>(ef.piece)];
    const Piece& pl = pieces[static_cast<std::size_t>(el.piece)];
    const Seg& src = segs[static_cast<std::size_t>(pf.src)];
    Seg s = ef.rev ? src.sub(pl.t0, pf.t1).reversed() : src.sub(pf.t0, pl.t1);
    s.a = V[ef.from];
    s.b = V[el.to];
    loop.push_back(s);
    k = m;
  }
  return loop;
}

// A loop too small to be more than snapping noise: area under 1e4 snap^2
// or length under 20 snap.
bool negligible(const Loop& loop, double snap) {
  return std::abs(signed_area(loop)) < 1e4 * snap * snap || loop_length(loop) < 20.0 * snap;
}

}  // namespace

std::vector<Loop> resolve_loops(const std::vector<Loop>& loops, double snap) {
  if (snap <= 0.0) snap = default_snap(loops);
  const double scale = std::max(loops_box(loops).size(), snap);
  std::vector<Seg> segs = usable_segments(loops, snap);
  if (segs.empty()) return {};

  VertexSet V(snap);
  auto splits = split_points(segs, snap, V);  // 1
  std::vector<Piece> pieces = cut_pieces(segs, splits, snap);
  const Groups groups = group_coincident(segs, pieces, snap);              // 2
  BoundaryEdges b = boundary_edges(segs, pieces, groups, V, snap, scale);  // 3
  std::vector<std::vector<int>> chains = chain_loops(b);                   // 4

  std::vector<Loop> result;  // 5
  for (auto& chain : chains) {
    Loop loop = merged_loop(chain, b.edges, pieces, segs, V);
    if (!negligible(loop, snap)) result.push_back(std::move(loop));
  }
  return result;
}

}  // namespace isocam
