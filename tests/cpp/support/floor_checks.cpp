#include "support/floor_checks.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "pocketing/geom2d.h"

namespace isocam::test {
namespace {

struct Capsule {
  double ax, ay, az, bx, by, bz;  // ball centres
};

// Lowest z of the capsule of radius r on the vertical line through (x, y);
// +inf if the line misses it.
double capsule_bottom(const Capsule& c, double x, double y, double r) {
  double best = 1e300;
  for (int e = 0; e < 2; ++e) {
    const double cx = e ? c.bx : c.ax, cy = e ? c.by : c.ay, cz = e ? c.bz : c.az;
    const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
    if (d2 <= r * r) best = std::min(best, cz - std::sqrt(r * r - d2));
  }
  const double dx = c.bx - c.ax, dy = c.by - c.ay, dz = c.bz - c.az;
  const double L2 = dx * dx + dy * dy + dz * dz;
  if (L2 <= 0) return best;
  const double wx = x - c.ax, wy = y - c.ay, wz = -c.az;  // (x, y, z) - A = w + z e_z
  const double qa = 1.0 - dz * dz / L2;
  if (qa < 1e-12) return best;
  const double wd = wx * dx + wy * dy + wz * dz;
  const double qb = 2.0 * (wz - wd * dz / L2);
  const double qc = wx * wx + wy * wy + wz * wz - wd * wd / L2 - r * r;
  const double disc = qb * qb - 4 * qa * qc;
  if (disc < 0) return best;
  const double z = (-qb - std::sqrt(disc)) / (2 * qa);
  const double t = (wd + z * dz) / L2;
  if (t >= 0 && t <= 1) best = std::min(best, z);
  return best;
}

}  // namespace

FloorMeasure measure_floor(const Toolpath& path, double r, const std::vector<Loop>& where,
                           const std::function<double(double, double)>& floor_z, double step) {
  std::vector<Seg> wsegs;
  for (const Loop& l : where) wsegs.insert(wsegs.end(), l.begin(), l.end());
  const pocket::WindingIndex inside(wsegs);
  std::vector<Capsule> caps;
  for (std::size_t i = 1; i < path.size(); ++i)
    if (path.kind[i] == static_cast<std::uint8_t>(MoveKind::Feed))
      caps.push_back(
          {path.x[i - 1], path.y[i - 1], path.z[i - 1] + r, path.x[i], path.y[i], path.z[i] + r});
  // Grid of capsules by their plan bounding boxes.
  const double cell = 2 * r;
  auto key = [](long i, long j) { return i * 1000003L + j; };
  std::unordered_map<long, std::vector<int>> grid;
  for (std::size_t k = 0; k < caps.size(); ++k) {
    const Capsule& c = caps[k];
    const long i0 = static_cast<long>(std::floor((std::min(c.ax, c.bx) - r) / cell));
    const long i1 = static_cast<long>(std::floor((std::max(c.ax, c.bx) + r) / cell));
    const long j0 = static_cast<long>(std::floor((std::min(c.ay, c.by) - r) / cell));
    const long j1 = static_cast<long>(std::floor((std::max(c.ay, c.by) + r) / cell));
    for (long i = i0; i <= i1; ++i)
      for (long j = j0; j <= j1; ++j) grid[key(i, j)].push_back(static_cast<int>(k));
  }
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const Loop& l : where)
    for (const Seg& s : l)
      for (double t : {0.0, 0.5, 1.0}) {
        const P2 p = s.at(t);
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x),
        y1 = std::max(y1, p.y);
      }
  FloorMeasure m;
  std::vector<double> left;
  for (double y = y0 + 0.5 * step; y < y1; y += step)
    for (double x = x0 + 0.5 * step; x < x1; x += step) {
      // The plan position of the centre of a ball touching the floor here.
      const double h = 1e-4, zx = (floor_z(x + h, y) - floor_z(x - h, y)) / (2 * h);
      const double zy = (floor_z(x, y + h) - floor_z(x, y - h)) / (2 * h);
      const double nn = std::sqrt(1 + zx * zx + zy * zy);
      if (inside.at({x - r * zx / nn, y - r * zy / nn}) < 1) continue;
      double env = 1e300;
      auto it = grid.find(
          key(static_cast<long>(std::floor(x / cell)), static_cast<long>(std::floor(y / cell))));
      if (it != grid.end())
        for (int k : it->second)
          env = std::min(env, capsule_bottom(caps[static_cast<std::size_t>(k)], x, y, r));
      ++m.samples;
      if (env > 1e299) {
        ++m.uncovered;
        continue;
      }
      const double d = env - floor_z(x, y);
      left.push_back(d);
      m.max_gouge = std::max(m.max_gouge, -d);
    }
  if (!left.empty()) {
    std::sort(left.begin(), left.end());
    m.max_scallop = std::max(0.0, left.back());
    m.p99_scallop =
        std::max(0.0, left[static_cast<std::size_t>(0.99 * static_cast<double>(left.size() - 1))]);
    double sum = 0;
    for (double d : left) sum += std::max(0.0, d);
    m.mean_scallop = sum / static_cast<double>(left.size());
  }
  return m;
}

}  // namespace isocam::test
