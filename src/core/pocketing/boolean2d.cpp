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

}  // namespace

std::vector<Loop> resolve_loops(const std::vector<Loop>& loops, double snap) {
  if (snap <= 0.0) snap = default_snap(loops);
  const double scale = std::max(loops_box(loops).size(), snap);
  std::vector<Seg> segs;
  for (const Loop& l : loops)
    for (const Seg& s : l)
      if (s.length() > 0.05 * snap) segs.push_back(s);
  if (segs.empty()) return {};
  const std::size_t n = segs.size();

  // 1. Split points.
  // End points snap to shared vertices, so that the loops are closed
  // exactly (the ray-crossing count relies on it).
  VertexSet V(snap);
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

  // Pieces between consecutive split points.
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i < n; ++i) {
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

  // 2. Coincident pieces: same end vertices and the same midpoint.
  std::map<std::pair<int, int>, std::vector<int>> by_ends;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const Piece& pc = pieces[p];
    by_ends[{std::min(pc.v0, pc.v1), std::max(pc.v0, pc.v1)}].push_back(static_cast<int>(p));
  }
  std::vector<int> group_rep;   // representative piece of each group
  std::vector<int> group_mult;  // signed count relative to the representative
  for (auto& [ends, list] : by_ends) {
    for (std::size_t a = 0; a < list.size(); ++a) {
      Piece& pa = pieces[static_cast<std::size_t>(list[a])];
      if (pa.group >= 0) continue;
      pa.group = static_cast<int>(group_rep.size());
      group_rep.push_back(list[a]);
      group_mult.push_back(1);
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
        group_mult.back() += same ? 1 : -1;
      }
    }
  }

  // 3. Keep the pieces that bound the region.
  const WindingIndex wind(segs);
  const double h_probe = 0.01 * snap;
  std::vector<Edge> edges;
  std::vector<std::vector<int>> out(static_cast<std::size_t>(V.size()));
  for (std::size_t g = 0; g < group_rep.size(); ++g) {
    const int mult = group_mult[g];
    if (mult == 0) continue;
    const Piece& pc = pieces[static_cast<std::size_t>(group_rep[g])];
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
    Edge e{group_rep[g],
           rev,
           rev ? pc.v1 : pc.v0,
           rev ? pc.v0 : pc.v1,
           dir_angle(es.a, point_near_start(es, hp)),
           dir_angle(point_near_end(es, hp), es.b)};
    out[static_cast<std::size_t>(e.from)].push_back(static_cast<int>(edges.size()));
    edges.push_back(e);
  }

  // 4. Chain the kept pieces into loops.
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
      double best_cw = 1e300;
      auto consider = [&](int ei) {
        double cw = wrap_2pi(back - edges[static_cast<std::size_t>(ei)].out_ang);
        if (cw < 1e-12) cw = kTwoPi;  // straight back: the last resort
        if (cw < best_cw) {
          best_cw = cw;
          best = ei;
        }
      };
      for (int ei : out[static_cast<std::size_t>(v)])
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

  // 5. Merge pieces of one source segment, build the loops.
  std::vector<Loop> result;
  const double min_area = 1e4 * snap * snap;
  for (auto& chain : chains) {
    auto mergeable = [&](int ea, int eb) {
      const Edge& a = edges[static_cast<std::size_t>(ea)];
      const Edge& b = edges[static_cast<std::size_t>(eb)];
      const Piece& pa = pieces[static_cast<std::size_t>(a.piece)];
      const Piece& pb = pieces[static_cast<std::size_t>(b.piece)];
      if (pa.src != pb.src || a.rev != b.rev) return false;
      return a.rev ? pa.t0 == pb.t1 : pa.t1 == pb.t0;
    };
    // Rotate so that the chain does not start inside a mergeable run.
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
    if (std::abs(signed_area(loop)) < min_area || loop_length(loop) < 20.0 * snap) continue;
    result.push_back(std::move(loop));
  }
  return result;
}

}  // namespace isocam
