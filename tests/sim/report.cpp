// The simulator's outputs: a JSON summary and a residual map.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <ostream>
#include <string>

#include "gcode_sim.h"

namespace gsim {
namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

std::string extreme(const Extreme& e) {
  std::string s = "{\"max\": " + fixed(e.value, 6);
  if (e.face > 0) {
    s += ", \"at\": [" + fixed(e.at.x, 4) + ", " + fixed(e.at.y, 4) + ", " + fixed(e.at.z, 4) +
         "], \"face\": " + std::to_string(e.face) + ", \"move\": " + std::to_string(e.move);
  } else {
    s += ", \"at\": null, \"face\": 0, \"move\": -1";
  }
  return s + "}";
}

}  // namespace

void write_json(std::ostream& out, const std::vector<Sample>& samples, const Program& program,
                const Options& o, const Result& r, double spacing, const std::vector<int>& picked,
                int face_count) {
  // The sampled area of each face (its points' shares): shows that the
  // numbering and the wires are read as FreeCAD reads them.
  std::vector<double> area(static_cast<std::size_t>(face_count), 0.0);
  for (const Sample& s : samples)
    if (s.face >= 1 && s.face <= face_count) area[static_cast<std::size_t>(s.face - 1)] += s.area;
  std::string areas;
  for (std::size_t i = 0; i < area.size(); ++i) areas += (i ? ", " : "") + fixed(area[i], 4);
  std::string faces;
  for (std::size_t i = 0; i < picked.size(); ++i)
    faces += (i ? ", " : "") + std::to_string(picked[i]);
  const double reach_frac = r.picked_area > 0 ? r.reachable_area / r.picked_area : 0.0;
  out << "{\n"
      << "  \"ball_radius\": " << num(o.ball_radius) << ",\n"
      << "  \"spacing\": " << num(spacing) << ",\n"
      << "  \"faces\": " << face_count << ",\n"
      << "  \"picked\": [" << faces << "],\n"
      << "  \"samples\": " << r.samples << ",\n"
      << "  \"picked_samples\": " << r.picked_samples << ",\n"
      << "  \"reachable_samples\": " << r.reachable_samples << ",\n"
      << "  \"uncovered_samples\": " << r.uncovered_samples << ",\n"
      << "  \"overcut_samples\": " << r.overcut_samples << ",\n"
      << "  \"picked_area\": " << fixed(r.picked_area, 4) << ",\n"
      << "  \"face_areas\": [" << areas << "],\n"
      << "  \"reachable_fraction\": " << fixed(reach_frac, 6) << ",\n"
      << "  \"unreachable_fraction\": " << fixed(r.picked_area > 0 ? 1 - reach_frac : 0.0, 6)
      << ",\n"
      << "  \"coverage\": "
      << (o.scallop > 0 && r.reachable_area > 0 ? fixed(r.covered_area / r.reachable_area, 6)
                                                : std::string("null"))
      << ",\n"
      << "  \"scallop\": " << (o.scallop > 0 ? num(o.scallop) : std::string("null")) << ",\n"
      << "  \"max_residual\": " << num(o.max_residual) << ",\n"
      << "  \"reach_margin\": " << num(o.reach_margin) << ",\n"
      << "  \"reach_tol\": " << num(o.reach_tol) << ",\n"
      << "  \"reach_from_above\": " << (o.from_above ? "true" : "false") << ",\n"
      << "  \"left\": " << extreme(r.left) << ",\n"
      << "  \"overcut\": " << extreme(r.overcut) << ",\n"
      << "  \"rapid_overcut\": " << extreme(r.rapid_overcut) << ",\n"
      << "  \"moves\": {\"total\": " << program.moves.size() << ", \"rapids\": " << program.rapids
      << ", \"feeds\": " << program.feeds << ", \"arcs\": " << program.arcs
      << ", \"segments\": " << program.segments.size() << "},\n"
      << "  \"lengths\": {\"cutting\": "
      << fixed(program.feed_length - program.plunge_length + program.arc_length, 3)
      << ", \"feed\": " << fixed(program.feed_length + program.arc_length, 3)
      << ", \"plunge\": " << fixed(program.plunge_length, 3)
      << ", \"arc\": " << fixed(program.arc_length, 3)
      << ", \"rapid\": " << fixed(program.rapid_length, 3) << "},\n"
      << "  \"feed_time_min\": " << fixed(program.feed_time_min, 4) << ",\n"
      << "  \"rapid_rate\": " << num(o.rapid_rate) << ",\n"
      << "  \"machine_time_min\": "
      << fixed(program.feed_time_min + program.rapid_length / o.rapid_rate, 4) << "\n"
      << "}\n";
}

void write_map(std::ostream& out, const std::vector<Sample>& samples, const Result& r,
               double step) {
  if (!(step > 0)) throw std::runtime_error("map step must be > 0");
  double x0 = 1e300, y0 = 1e300;
  for (const Sample& s : samples)
    if (s.picked) x0 = std::min(x0, s.p.x), y0 = std::min(y0, s.p.y);
  // Per cell: deepest overcut, most material left where reachable, any sample.
  struct Agg {
    double cut = 0, left = -1;
    bool any_reachable = false;
  };
  std::map<std::pair<long, long>, Agg> cells;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i];
    if (!s.picked) continue;
    const std::pair<long, long> key{static_cast<long>(std::floor((s.p.x - x0) / step)),
                                    static_cast<long>(std::floor((s.p.y - y0) / step))};
    Agg& a = cells[key];
    const double d = r.residual[i];
    a.cut = std::min(a.cut, d);
    if (r.reachable[i]) {
      a.any_reachable = true;
      a.left = std::max(a.left, d);
    }
  }
  out << "# x y residual (mm; > 0 material left on reachable points, < 0 overcut, nan unreachable)"
      << " step " << step << "\n";
  char buf[128];
  for (const auto& [key, a] : cells) {
    const double v = a.cut < -1e-4 ? a.cut : a.any_reachable ? std::max(0.0, a.left) : NAN;
    std::snprintf(buf, sizeof buf, "%.4f %.4f %s\n",
                  x0 + (static_cast<double>(key.first) + 0.5) * step,
                  y0 + (static_cast<double>(key.second) + 0.5) * step,
                  std::isfinite(v) ? fixed(v, 6).c_str() : "nan");
    out << buf;
  }
}

}  // namespace gsim
