// Raster coverage and clearance checks of a pocketing path (pocket_check.h).
// Independent of the offset engine: only exact point-to-segment distances,
// winding numbers of the input loops and a Euclidean distance transform.
#include <algorithm>
#include <cmath>
#include <limits>

#include "isocam/errors.h"
#include "isocam/pocket_check.h"
#include "pocketing/geom2d.h"

namespace isocam {

using namespace pocket;

namespace {

struct Raster {
  double x0, y0, c;
  long nx, ny;
  P2 centre(long i, long j) const {
    return {x0 + (static_cast<double>(i) + 0.5) * c, y0 + (static_cast<double>(j) + 0.5) * c};
  }
  std::size_t at(long i, long j) const { return static_cast<std::size_t>(j * nx + i); }
  std::size_t size() const { return static_cast<std::size_t>(nx * ny); }

  // Calls f(index) for every cell whose centre is within rr of s.
  template <class F>
  void stamp(const Seg& s, double rr, F&& f) const {
    const double len = s.length();
    const int pieces = std::max(1, static_cast<int>(std::ceil(len / std::max(rr, 10.0 * c))));
    for (int k = 0; k < pieces; ++k) {
      const Seg p = s.sub(static_cast<double>(k) / pieces, static_cast<double>(k + 1) / pieces);
      const Box2 b = seg_box(p);
      const long i0 = std::max(0L, static_cast<long>(std::floor((b.x0 - rr - x0) / c)));
      const long i1 = std::min(nx - 1, static_cast<long>(std::ceil((b.x1 + rr - x0) / c)));
      const long j0 = std::max(0L, static_cast<long>(std::floor((b.y0 - rr - y0) / c)));
      const long j1 = std::min(ny - 1, static_cast<long>(std::ceil((b.y1 + rr - y0) / c)));
      for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i)
          if (nearest_on_seg(p, centre(i, j)).d <= rr) f(at(i, j));
    }
  }
};

// Squared distance transform along one line (Felzenszwalb & Huttenlocher).
void edt_1d(const std::vector<double>& f, std::vector<double>& d, std::vector<long>& v,
            std::vector<double>& z) {
  const auto n = static_cast<long>(f.size());
  long k = 0;
  v[0] = 0;
  z[0] = -1e300;
  z[1] = 1e300;
  for (long q = 1; q < n; ++q) {
    auto sq = [](long a) { return static_cast<double>(a) * static_cast<double>(a); };
    double s;
    for (;;) {
      const long p = v[static_cast<std::size_t>(k)];
      s = ((f[static_cast<std::size_t>(q)] + sq(q)) - (f[static_cast<std::size_t>(p)] + sq(p))) /
          (2.0 * static_cast<double>(q - p));
      if (s <= z[static_cast<std::size_t>(k)] && k > 0) {
        --k;
        continue;
      }
      break;
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k + 1)] = 1e300;
  }
  k = 0;
  for (long q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(k + 1)] < static_cast<double>(q)) ++k;
    const long p = v[static_cast<std::size_t>(k)];
    d[static_cast<std::size_t>(q)] =
        static_cast<double>((q - p) * (q - p)) + f[static_cast<std::size_t>(p)];
  }
}

// Squared distances (in cells) to the nearest seed cell.
std::vector<double> edt(const Raster& R, const std::vector<std::uint8_t>& seed) {
  const double inf = 1e20;
  std::vector<double> g(R.size());
  for (std::size_t i = 0; i < g.size(); ++i) g[i] = seed[i] ? 0.0 : inf;
  const long m = std::max(R.nx, R.ny);
  std::vector<double> f(static_cast<std::size_t>(m)), d(static_cast<std::size_t>(m));
  std::vector<long> v(static_cast<std::size_t>(m));
  std::vector<double> z(static_cast<std::size_t>(m) + 1);
  for (long j = 0; j < R.ny; ++j) {
    f.resize(static_cast<std::size_t>(R.nx));
    d.resize(static_cast<std::size_t>(R.nx));
    for (long i = 0; i < R.nx; ++i) f[static_cast<std::size_t>(i)] = g[R.at(i, j)];
    edt_1d(f, d, v, z);
    for (long i = 0; i < R.nx; ++i) g[R.at(i, j)] = d[static_cast<std::size_t>(i)];
  }
  for (long i = 0; i < R.nx; ++i) {
    f.resize(static_cast<std::size_t>(R.ny));
    d.resize(static_cast<std::size_t>(R.ny));
    for (long j = 0; j < R.ny; ++j) f[static_cast<std::size_t>(j)] = g[R.at(i, j)];
    edt_1d(f, d, v, z);
    for (long j = 0; j < R.ny; ++j) g[R.at(i, j)] = d[static_cast<std::size_t>(j)];
  }
  return g;
}

// The move from path point i-1 to i as a segment in XY.
Seg move_seg(const Toolpath& path, std::size_t i) {
  const P2 a{path.x[i - 1], path.y[i - 1]}, b{path.x[i], path.y[i]};
  if (is_arc(path.kind[i]))
    return Seg::arc_between({path.cx[i], path.cy[i]}, a, b,
                            path.kind[i] == static_cast<std::uint8_t>(MoveKind::ArcCCW));
  return Seg::line(a, b);
}

}  // namespace

CoverageReport pocket_coverage(const std::vector<Loop>& region, const Toolpath& path,
                               const CoverageParams& prm) {
  if (!(prm.tool_radius > 0)) throw InvalidArgument("tool_radius must be > 0");
  if (!(prm.cell > 0)) throw InvalidArgument("cell must be > 0");
  CoverageReport rep;
  const Box2 box = loops_box(region);
  if (box.empty()) return rep;
  Raster R{box.x0, box.y0, prm.cell, static_cast<long>(std::ceil((box.x1 - box.x0) / prm.cell)),
           static_cast<long>(std::ceil((box.y1 - box.y0) / prm.cell))};
  if (R.size() > 200'000'000)
    throw InvalidArgument("cell is too small for the region (raster > 2e8 cells)");
  std::vector<Seg> segs;
  for (const Loop& l : region) segs.insert(segs.end(), l.begin(), l.end());
  const WindingIndex wind(segs);
  std::vector<std::uint8_t> inside(R.size()), near(R.size(), 0), cut(R.size(), 0);
  for (long j = 0; j < R.ny; ++j)
    for (long i = 0; i < R.nx; ++i) inside[R.at(i, j)] = wind.at(R.centre(i, j)) >= 1;
  const double r = prm.tool_radius;
  for (const Seg& s : segs) R.stamp(s, r * (1 - 1e-12), [&](std::size_t k) { near[k] = 1; });
  std::vector<std::uint8_t> centre_ok(R.size());
  for (std::size_t k = 0; k < R.size(); ++k) centre_ok[k] = inside[k] && !near[k];
  const std::vector<double> d2 = edt(R, centre_ok);
  const double reach2 = (r / prm.cell) * (r / prm.cell);
  for (std::size_t i = 1; i < path.size(); ++i) {
    const bool a_at = std::abs(path.z[i - 1] - prm.z_floor) <= prm.z_tolerance;
    const bool b_at = std::abs(path.z[i] - prm.z_floor) <= prm.z_tolerance;
    if (!b_at) continue;
    const Seg s =
        a_at ? move_seg(path, i) : Seg::line({path.x[i], path.y[i]}, {path.x[i], path.y[i]});
    R.stamp(s, r + prm.tolerance, [&](std::size_t k) { cut[k] = 1; });
  }
  const double a = prm.cell * prm.cell;
  double worst = -1;
  for (long j = 0; j < R.ny; ++j)
    for (long i = 0; i < R.nx; ++i) {
      const std::size_t k = R.at(i, j);
      if (!inside[k]) continue;
      ++rep.cells;
      const bool reach = d2[k] <= reach2;
      if (!reach) rep.unreachable_area += a;
      if (cut[k]) continue;
      rep.uncut_area += a;
      if (reach) {
        rep.uncut_reachable_area += a;
        // Report the deepest one (farthest inside the reachable set).
        if (reach2 - d2[k] > worst) {
          worst = reach2 - d2[k];
          rep.worst_x = R.centre(i, j).x;
          rep.worst_y = R.centre(i, j).y;
        }
      }
    }
  rep.region_area = static_cast<double>(rep.cells) * a;
  return rep;
}

ClearanceReport pocket_clearance(const std::vector<Loop>& region, const Toolpath& path,
                                 double z_floor, double step, double z_tol) {
  if (!(step > 0)) throw InvalidArgument("step must be > 0");
  ClearanceReport rep;
  rep.min_distance = 1e300;
  std::vector<Seg> segs;
  for (const Loop& l : region) segs.insert(segs.end(), l.begin(), l.end());
  const WindingIndex wind(segs);
  const SegGrid grid(segs, 1.0);
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (std::abs(path.z[i - 1] - z_floor) > z_tol || std::abs(path.z[i] - z_floor) > z_tol)
      continue;
    const Seg s = move_seg(path, i);
    const int n = std::max(1, static_cast<int>(std::ceil(s.length() / step)));
    for (int k = 0; k <= n; ++k) {
      const P2 p = s.at(static_cast<double>(k) / n);
      const double d = grid.distance(p);
      ++rep.samples;
      const bool out = wind.at(p) < 1;
      if (out) ++rep.outside;
      if (d < rep.min_distance || out) {
        if (d < rep.min_distance) rep.min_distance = d;
        rep.worst_x = p.x;
        rep.worst_y = p.y;
      }
    }
  }
  return rep;
}

}  // namespace isocam
