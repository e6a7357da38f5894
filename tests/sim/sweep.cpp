// The swept ball against the sampled design: residual, overcut, reach.
//
// Two grids. A coarse one holds the ball-centre segments (each in the cells
// its bounding box meets). A fine one buckets the samples; per occupied fine
// cell the segments that can come within r + max_residual of it are gathered
// once, sorted by a lower bound of their distance to the cell, and each
// sample of the cell scans them nearest first, stopping when the bound passes
// the best distance found. The same fine cells answer the reach test (is any
// model sample inside the ball that touches p from outside, or, for a 3-axis
// tool, inside the column swept by that ball lifted straight up?).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>

#include "gcode_sim.h"

namespace gsim {
namespace {

struct Box {
  Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  void add(const Vec3& p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
};

double seg_dist(const Vec3& p, const Vec3& a, const Vec3& b) {
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z;
  const double wx = p.x - a.x, wy = p.y - a.y, wz = p.z - a.z;
  const double uu = ux * ux + uy * uy + uz * uz;
  double t = uu > 0 ? (wx * ux + wy * uy + wz * uz) / uu : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  const double dx = wx - t * ux, dy = wy - t * uy, dz = wz - t * uz;
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

double box_dist2(const Vec3& p, const Box& b) {
  const double dx = std::max({b.lo.x - p.x, 0.0, p.x - b.hi.x});
  const double dy = std::max({b.lo.y - p.y, 0.0, p.y - b.hi.y});
  const double dz = std::max({b.lo.z - p.z, 0.0, p.z - b.hi.z});
  return dx * dx + dy * dy + dz * dz;
}

// A uniform grid over `origin` .. with cell `size` and n cells a side.
struct Grid {
  Vec3 origin;
  double size = 1;
  long nx = 1, ny = 1, nz = 1;
  long clampi(double v, double o, long n) const {
    return std::clamp(static_cast<long>(std::floor((v - o) / size)), 0L, n - 1);
  }
  void range(const Vec3& lo, const Vec3& hi, long (&a)[3], long (&b)[3]) const {
    a[0] = clampi(lo.x, origin.x, nx), b[0] = clampi(hi.x, origin.x, nx);
    a[1] = clampi(lo.y, origin.y, ny), b[1] = clampi(hi.y, origin.y, ny);
    a[2] = clampi(lo.z, origin.z, nz), b[2] = clampi(hi.z, origin.z, nz);
  }
  long key(long i, long j, long k) const { return (k * ny + j) * nx + i; }
  long cells() const { return nx * ny * nz; }
};

Grid grid_over(const Box& b, double size, long max_cells) {
  Grid g;
  g.origin = b.lo;
  for (;;) {
    g.size = size;
    g.nx = static_cast<long>(std::ceil((b.hi.x - b.lo.x) / size)) + 1;
    g.ny = static_cast<long>(std::ceil((b.hi.y - b.lo.y) / size)) + 1;
    g.nz = static_cast<long>(std::ceil((b.hi.z - b.lo.z) / size)) + 1;
    if (static_cast<double>(g.nx) * static_cast<double>(g.ny) * static_cast<double>(g.nz) <=
        static_cast<double>(max_cells))
      return g;
    size *= 1.25;
  }
}

template <class F>
void parallel_for(std::size_t n, int threads, F&& body) {
  std::atomic<std::size_t> next{0};
  auto worker = [&](int t) {
    for (std::size_t k; (k = next.fetch_add(16)) < n;)
      for (std::size_t i = k; i < std::min(n, k + 16); ++i) body(i, t);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& th : pool) th.join();
}

struct Cell {
  std::size_t begin = 0, end = 0;  // into the sorted sample order
  Box box;                         // tight box of its samples
  bool picked = false;
};

// A ball-centre segment (tip + r along z).
struct CSeg {
  Vec3 a, b;
  int move;
  bool rapid;
};

// The ball-centre segments, each in the coarse cells its bounding box meets
// (cells in CSR form: entries[start[c] .. start[c + 1]]).
struct SegmentIndex {
  std::vector<CSeg> segs;
  Grid grid;
  std::vector<long> start;
  std::vector<int> entries;
};

SegmentIndex index_segments(const Program& program, double r, const Box& region, double R) {
  SegmentIndex ix;
  ix.segs.reserve(program.segments.size());
  for (const Segment& s : program.segments)
    ix.segs.push_back({{s.a.x, s.a.y, s.a.z + r}, {s.b.x, s.b.y, s.b.z + r}, s.move, s.rapid});
  ix.grid = grid_over(region, std::max(2.0, R / 2), 8L << 20);
  ix.start.assign(static_cast<std::size_t>(ix.grid.cells()) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {  // count, then fill
    for (std::size_t i = 0; i < ix.segs.size(); ++i) {
      Box b;
      b.add(ix.segs[i].a);
      b.add(ix.segs[i].b);
      if (b.hi.x < region.lo.x || b.lo.x > region.hi.x || b.hi.y < region.lo.y ||
          b.lo.y > region.hi.y || b.hi.z < region.lo.z || b.lo.z > region.hi.z)
        continue;
      long a[3], c[3];
      ix.grid.range(b.lo, b.hi, a, c);
      for (long k = a[2]; k <= c[2]; ++k)
        for (long j = a[1]; j <= c[1]; ++j)
          for (long q = a[0]; q <= c[0]; ++q) {
            const std::size_t key = static_cast<std::size_t>(ix.grid.key(q, j, k));
            if (pass == 0)
              ++ix.start[key + 1];
            else
              ix.entries[static_cast<std::size_t>(ix.start[key]++)] = static_cast<int>(i);
          }
    }
    if (pass == 0) {
      for (std::size_t k = 1; k < ix.start.size(); ++k) ix.start[k] += ix.start[k - 1];
      ix.entries.resize(static_cast<std::size_t>(ix.start.back()));
    } else {
      for (std::size_t k = ix.start.size() - 1; k > 0; --k) ix.start[k] = ix.start[k - 1];
      ix.start[0] = 0;
    }
  }
  return ix;
}

// The samples sorted by fine cell; per occupied cell its range and tight
// box; and, for the reach test's inner loop, each sample as floats relative
// to its cell's box corner (exact to ~1e-7 mm), in sorted order.
struct SampleIndex {
  Grid grid;
  std::vector<std::size_t> order;  // sorted position -> sample
  std::vector<Cell> cells;
  std::vector<int> cell_of;  // fine cell -> index into cells, -1 empty
  std::vector<float> fx, fy, fz;
};

SampleIndex index_samples(const std::vector<Sample>& samples, const Box& region, double cell) {
  SampleIndex ix;
  ix.grid = grid_over(region, cell, 48L << 20);
  const Grid& g = ix.grid;
  std::vector<std::pair<long, std::size_t>> keyed(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Vec3& p = samples[i].p;
    keyed[i] = {g.key(g.clampi(p.x, g.origin.x, g.nx), g.clampi(p.y, g.origin.y, g.ny),
                      g.clampi(p.z, g.origin.z, g.nz)),
                i};
  }
  std::sort(keyed.begin(), keyed.end());
  ix.order.resize(samples.size());
  ix.cell_of.assign(static_cast<std::size_t>(g.cells()), -1);
  for (std::size_t i = 0; i < keyed.size();) {
    Cell c;
    c.begin = i;
    while (i < keyed.size() && keyed[i].first == keyed[c.begin].first) {
      const Sample& s = samples[keyed[i].second];
      ix.order[i] = keyed[i].second;
      c.box.add(s.p);
      c.picked = c.picked || s.picked;
      ++i;
    }
    c.end = i;
    ix.cell_of[static_cast<std::size_t>(keyed[c.begin].first)] = static_cast<int>(ix.cells.size());
    ix.cells.push_back(c);
  }
  ix.fx.resize(samples.size());
  ix.fy.resize(samples.size());
  ix.fz.resize(samples.size());
  for (const Cell& c : ix.cells)
    for (std::size_t k = c.begin; k < c.end; ++k) {
      const Vec3& p = samples[ix.order[k]].p;
      ix.fx[k] = static_cast<float>(p.x - c.box.lo.x);
      ix.fy[k] = static_cast<float>(p.y - c.box.lo.y);
      ix.fz[k] = static_cast<float>(p.z - c.box.lo.z);
    }
  return ix;
}

// Per sample: the move whose swept ball is nearest, and a rapid's own cut.
struct Nearest {
  std::vector<double> rapid_dist;  // r where no rapid cuts deeper than every feed
  std::vector<int> best_move, rapid_move;
};

// Residuals: per occupied fine cell, the segments that can come within
// R = r + max_residual of it, sorted by a lower bound of their distance to
// the cell (distance to its centre minus its half diagonal); each sample
// scans them nearest first and stops once the bound passes its best.
Nearest nearest_segments(const std::vector<Sample>& samples, const SampleIndex& six,
                         const SegmentIndex& seg, const Options& o, Result& res) {
  const double r = o.ball_radius, R = o.ball_radius + o.max_residual;
  const int threads = std::max(1, o.threads);
  Nearest n;
  n.rapid_dist.assign(samples.size(), r);
  n.best_move.assign(samples.size(), -1);
  n.rapid_move.assign(samples.size(), -1);
  std::vector<std::vector<int>> stamp(static_cast<std::size_t>(threads),
                                      std::vector<int>(seg.segs.size(), -1));
  std::vector<std::vector<std::pair<double, int>>> cand(static_cast<std::size_t>(threads));
  parallel_for(six.cells.size(), threads, [&](std::size_t ci, int t) {
    const Cell& c = six.cells[ci];
    const Vec3 m{0.5 * (c.box.lo.x + c.box.hi.x), 0.5 * (c.box.lo.y + c.box.hi.y),
                 0.5 * (c.box.lo.z + c.box.hi.z)};
    const double hd = 0.5 * std::sqrt((c.box.hi.x - c.box.lo.x) * (c.box.hi.x - c.box.lo.x) +
                                      (c.box.hi.y - c.box.lo.y) * (c.box.hi.y - c.box.lo.y) +
                                      (c.box.hi.z - c.box.lo.z) * (c.box.hi.z - c.box.lo.z));
    auto& list = cand[static_cast<std::size_t>(t)];
    auto& st = stamp[static_cast<std::size_t>(t)];
    list.clear();
    long a[3], b[3];
    seg.grid.range({c.box.lo.x - R, c.box.lo.y - R, c.box.lo.z - R},
                   {c.box.hi.x + R, c.box.hi.y + R, c.box.hi.z + R}, a, b);
    for (long k = a[2]; k <= b[2]; ++k)
      for (long j = a[1]; j <= b[1]; ++j)
        for (long q = a[0]; q <= b[0]; ++q) {
          const std::size_t key = static_cast<std::size_t>(seg.grid.key(q, j, k));
          for (long e = seg.start[key]; e < seg.start[key + 1]; ++e) {
            const int si = seg.entries[static_cast<std::size_t>(e)];
            if (st[static_cast<std::size_t>(si)] == static_cast<int>(ci)) continue;
            st[static_cast<std::size_t>(si)] = static_cast<int>(ci);
            const CSeg& s = seg.segs[static_cast<std::size_t>(si)];
            const double lb = seg_dist(m, s.a, s.b) - hd;
            if (lb < R) list.emplace_back(lb, si);
          }
        }
    std::sort(list.begin(), list.end());
    for (std::size_t k = c.begin; k < c.end; ++k) {
      const std::size_t i = six.order[k];
      const Vec3& p = samples[i].p;
      double best_feed = R, best_rapid = r;
      int arg_feed = -1, arg_rapid = -1;
      for (const auto& [lb, si] : list) {
        if (lb >= best_feed && lb >= best_rapid) break;
        const CSeg& s = seg.segs[static_cast<std::size_t>(si)];
        const double d = seg_dist(p, s.a, s.b);
        if (s.rapid) {
          if (d < best_rapid) best_rapid = d, arg_rapid = si;
        } else if (d < best_feed) {
          best_feed = d, arg_feed = si;
        }
      }
      const bool rapid_nearest = arg_rapid >= 0 && best_rapid < best_feed;
      const int arg = rapid_nearest ? arg_rapid : arg_feed;
      res.residual[i] = arg >= 0 ? (rapid_nearest ? best_rapid : best_feed) - r : o.max_residual;
      n.best_move[i] = arg >= 0 ? seg.segs[static_cast<std::size_t>(arg)].move : -1;
      // A rapid's own cut: where it comes nearer than every feed (a retract
      // from a feed's end shares that end's depth, which the feed made).
      n.rapid_dist[i] = arg_rapid >= 0 && best_rapid < best_feed - 1e-9 ? best_rapid : r;
      n.rapid_move[i] = arg_rapid >= 0 ? seg.segs[static_cast<std::size_t>(arg_rapid)].move : -1;
    }
  });
  return n;
}

// Reach: the ball of radius rr = r + reach_margin touching p from outside
// (centre p + rr N) holds no model sample closer than rr - reach_tol to its
// centre; from above (o.from_above), nor to the vertical ray up from its
// centre (the ball lifted straight up past the model's top: the tool and its
// shank, as wide as the ball, coming down from above). Per picked cell, the
// cells whose box comes that close to the box of its centres (extended up to
// the top of the region) are gathered once; each centre then tests their
// samples. An open face (o.two_sided faces) is reachable from either side.
void reach(const std::vector<Sample>& samples, const SampleIndex& six, const Options& o,
           Result& res) {
  const int threads = std::max(1, o.threads);
  const double rr = o.ball_radius + o.reach_margin;
  const double lim = rr - o.reach_tol, lim2 = lim * lim;
  const float l2 = static_cast<float>(lim2);
  double top = -1e300;  // the model's highest sample
  for (const Cell& c : six.cells) top = std::max(top, c.box.hi.z);
  std::vector<std::vector<int>> near(static_cast<std::size_t>(threads));
  parallel_for(six.cells.size(), threads, [&](std::size_t ci, int t) {
    const Cell& c = six.cells[ci];
    if (!c.picked) return;
    Box qbox;
    for (std::size_t k = c.begin; k < c.end; ++k) {
      const Sample& s = samples[six.order[k]];
      qbox.add({s.p.x + rr * s.n[0], s.p.y + rr * s.n[1], s.p.z + rr * s.n[2]});
      if (s.open) qbox.add({s.p.x - rr * s.n[0], s.p.y - rr * s.n[1], s.p.z - rr * s.n[2]});
    }
    if (o.from_above) qbox.hi.z = std::max(qbox.hi.z, top);
    auto& list = near[static_cast<std::size_t>(t)];
    list.clear();
    long a[3], b[3];
    six.grid.range({qbox.lo.x - lim, qbox.lo.y - lim, qbox.lo.z - lim},
                   {qbox.hi.x + lim, qbox.hi.y + lim, qbox.hi.z + lim}, a, b);
    for (long k = a[2]; k <= b[2]; ++k)
      for (long j = a[1]; j <= b[1]; ++j)
        for (long q = a[0]; q <= b[0]; ++q) {
          const int other = six.cell_of[static_cast<std::size_t>(six.grid.key(q, j, k))];
          if (other < 0) continue;
          const Box& ob = six.cells[static_cast<std::size_t>(other)].box;  // box-to-box distance
          const double dx = std::max({ob.lo.x - qbox.hi.x, 0.0, qbox.lo.x - ob.hi.x});
          const double dy = std::max({ob.lo.y - qbox.hi.y, 0.0, qbox.lo.y - ob.hi.y});
          const double dz = std::max({ob.lo.z - qbox.hi.z, 0.0, qbox.lo.z - ob.hi.z});
          if (dx * dx + dy * dy + dz * dz < lim2) list.push_back(other);
        }
    // Is the ball of centre q (and with from_above, the ray up from q) clear?
    auto clear_at = [&](const Vec3& q) {
      for (int other : list) {
        const Cell& oc = six.cells[static_cast<std::size_t>(other)];
        if (o.from_above) {
          // The distance from the box to the ray: below q as to a point, beside
          // it horizontally.
          const Vec3 at{q.x, q.y, std::clamp(q.z, oc.box.lo.z, std::max(q.z, oc.box.hi.z))};
          if (box_dist2(at, oc.box) >= lim2) continue;
        } else if (box_dist2(q, oc.box) >= lim2) {
          continue;
        }
        const float qx = static_cast<float>(q.x - oc.box.lo.x);
        const float qy = static_cast<float>(q.y - oc.box.lo.y);
        const float qz = static_cast<float>(q.z - oc.box.lo.z);
        int hit = 0;
        if (o.from_above) {
          for (std::size_t m = oc.begin; m < oc.end; ++m) {
            const float dx = six.fx[m] - qx, dy = six.fy[m] - qy;
            const float dz = std::min(six.fz[m] - qz, 0.0f);  // above q: beside the ray
            hit |= dx * dx + dy * dy + dz * dz < l2;
          }
        } else {
          for (std::size_t m = oc.begin; m < oc.end; ++m) {
            const float dx = six.fx[m] - qx, dy = six.fy[m] - qy, dz = six.fz[m] - qz;
            hit |= dx * dx + dy * dy + dz * dz < l2;
          }
        }
        if (hit) return false;
      }
      return true;
    };
    for (std::size_t k = c.begin; k < c.end; ++k) {
      const std::size_t i = six.order[k];
      const Sample& s = samples[i];
      if (!s.picked || (s.n[0] == 0 && s.n[1] == 0 && s.n[2] == 0)) continue;
      bool clear = clear_at({s.p.x + rr * s.n[0], s.p.y + rr * s.n[1], s.p.z + rr * s.n[2]});
      if (!clear && s.open)
        clear = clear_at({s.p.x - rr * s.n[0], s.p.y - rr * s.n[1], s.p.z - rr * s.n[2]});
      res.reachable[i] = clear ? 1 : 0;
    }
  });
}

// Maxima with where they occur, counts and areas.
void summarise(const std::vector<Sample>& samples, const Nearest& n, const Options& o,
               Result& res) {
  const double r = o.ball_radius;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    const double d = res.residual[i];
    if (-d > res.overcut.value) res.overcut = {-d, s.p, s.face, n.best_move[i]};
    if (d < -1e-4) ++res.overcut_samples;
    if (r - n.rapid_dist[i] > res.rapid_overcut.value)
      res.rapid_overcut = {r - n.rapid_dist[i], s.p, s.face, n.rapid_move[i]};
    if (!s.picked) continue;
    ++res.picked_samples;
    res.picked_area += s.area;
    if (!res.reachable[i]) continue;
    ++res.reachable_samples;
    res.reachable_area += s.area;
    if (n.best_move[i] < 0) ++res.uncovered_samples;
    if (o.scallop > 0 && d <= o.scallop) res.covered_area += s.area;
    if (d > res.left.value) res.left = {d, s.p, s.face, n.best_move[i]};
  }
}

}  // namespace

Result measure(const std::vector<Sample>& samples, const Program& program, const Options& o) {
  if (!(o.ball_radius > 0)) throw std::runtime_error("ball radius must be > 0");
  if (!(o.max_residual > 0)) throw std::runtime_error("max residual must be > 0");
  if (!(o.cell > 0)) throw std::runtime_error("cell must be > 0");
  if (!(o.reach_margin >= 0) || !(o.reach_tol >= 0))
    throw std::runtime_error("reach margin and tolerance must be >= 0");
  Result res;
  res.samples = samples.size();
  res.residual.assign(samples.size(), o.max_residual);
  res.reachable.assign(samples.size(), 0);
  if (samples.empty()) return res;

  const double R = o.ball_radius + o.max_residual, rr = o.ball_radius + o.reach_margin;
  Box region;
  for (const Sample& s : samples) region.add(s.p);
  const double pad = std::max(R, 2 * rr) + 1.0;
  region.lo = {region.lo.x - pad, region.lo.y - pad, region.lo.z - pad};
  region.hi = {region.hi.x + pad, region.hi.y + pad, region.hi.z + pad};

  const SegmentIndex seg = index_segments(program, o.ball_radius, region, R);
  const SampleIndex six = index_samples(samples, region, o.cell);
  const Nearest n = nearest_segments(samples, six, seg, o, res);
  reach(samples, six, o, res);
  summarise(samples, n, o, res);
  return res;
}

}  // namespace gsim
