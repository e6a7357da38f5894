#include "support/pocket_checks.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "pocketing/geom2d.h"

namespace isocam::test {
int bad_arcs(const std::vector<Loop>& region, const Toolpath& path, double z, double tol,
             int& checked) {
  std::vector<Seg> segs;
  for (const Loop& l : region) segs.insert(segs.end(), l.begin(), l.end());
  const pocket::SegGrid grid(segs, 1.0);
  auto boundary_distance = [&](const std::vector<Loop>&, P2 p) { return grid.distance(p); };
  int bad = 0;
  checked = 0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (!is_arc(path.kind[i])) continue;
    if (std::abs(path.z[i] - z) > 1e-9) continue;
    ++checked;
    const P2 c{path.cx[i], path.cy[i]}, a{path.x[i - 1], path.y[i - 1]}, b{path.x[i], path.y[i]};
    const double ra = std::hypot(a.x - c.x, a.y - c.y), rb = std::hypot(b.x - c.x, b.y - c.y);
    bool ok = std::abs(ra - rb) <= tol;
    const Seg arc =
        Seg::arc_between(c, a, b, path.kind[i] == static_cast<std::uint8_t>(MoveKind::ArcCCW));
    const double d0 = boundary_distance(region, a);
    for (double t : {0.1, 0.25, 0.5, 0.75, 0.9, 1.0})
      if (std::abs(boundary_distance(region, arc.at(t)) - d0) > tol) ok = false;
    bad += ok ? 0 : 1;
  }
  return bad;
}

std::string CaseReport::line() const {
  const PocketMetrics& m = result.metrics;
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(3);
  s << "loops " << m.loops << ", tree depth " << m.tree_depth << ", CL points " << m.cl_points
    << " (" << m.arcs << " G2/G3), cutting " << m.cutting_length << " mm, rapid " << m.rapid_length
    << " mm, retracts " << m.retracts << ", feed links " << m.feed_links << ", reduced steps "
    << m.reduced_intervals << " | area " << coverage.region_area << " mm2, uncut "
    << coverage.uncut_area << " mm2 (reachable " << coverage.uncut_reachable_area
    << ", unreachable corners " << coverage.unreachable_area << ") | min clearance "
    << clearance.min_distance << ", outside " << clearance.outside << " | arcs bad " << arcs_bad
    << "/" << arcs_checked << " | " << seconds * 1e3 << " ms";
  return s.str();
}

CaseReport run_case(const std::vector<Loop>& engine_region, const std::vector<Loop>& truth,
                    const PocketParams& p, double cell) {
  CaseReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  rep.result = spiral_pocket(engine_region, {0.0}, p);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CoverageParams cp;
  cp.tool_radius = p.tool_radius;
  cp.cell = cell;
  cp.tolerance = 2 * p.tolerance;
  cp.z_floor = 0.0;
  rep.coverage = pocket_coverage(truth, rep.result.path, cp);
  rep.clearance = pocket_clearance(truth, rep.result.path, 0.0, 0.05);
  rep.arcs_bad = bad_arcs(engine_region, rep.result.path, 0.0, 1e-4, rep.arcs_checked);
  return rep;
}

double corner_area(double r, const std::vector<double>& interior_angles) {
  double a = 0.0;
  for (double th : interior_angles) {
    const double half = 0.5 * th;  // the tool's disk touches both sides
    a += r * r * (1.0 / std::tan(half) - (3.14159265358979323846 - th) / 2.0);
  }
  return a;
}

}  // namespace isocam::test
