// 5-axis flat end against 3-axis ball end at the same scallop height (issue
// 13): a 6 mm flat end tilted by the default lead (5 degrees) against a 6 mm
// ball end (ConstantScallop and Adaptive patterns), on the Figure 2 ruled
// surface, the hill of the house on the hill and MAT: compute time, cutting
// length, number of paths, machine time (tip moves at the rates, the 5-axis
// rotary moves at FiveAxisParams::rotary_rate), the guarantees and the
// rotary travel; the 5-axis op with its low links and with every run left
// through the safe height, side by side (a second table: the links, and the
// machine time with and without the rotary timing).
// Usage: isocam_five_axis_bench SOURCE_DIR [CASE]  (writes
// bench/five_axis_results.md; CASE: only that case, 0-based, to
// bench/five_axis_results_CASE.md)
#include <BRepGProp.hxx>
#include <GProp_GProps.hxx>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/five_axis.h"
#include "support/models.h"

using namespace isocam;

namespace {

std::string num(double v, int d) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(d) << v;
  return s.str();
}

struct Case {
  std::string name;
  std::function<TopoDS_Shape()> shape;
  std::function<std::vector<int>(const TopoDS_Shape&)> faces;
  double h;
  // Every 5-axis variant below, or only the two strategies with low links
  // (MAT: one 5-axis run there takes about 4 min on 2 cores).
  bool all_variants = true;
};

// The largest-area face among `picked`.
int largest(const TopoDS_Shape& shape, const std::vector<int>& picked) {
  const std::vector<TopoDS_Face> all = faces_of(shape);
  int best = picked.front();
  double area = -1;
  for (int f : picked) {
    GProp_GProps g;
    BRepGProp::SurfaceProperties(all[static_cast<std::size_t>(f)], g);
    if (g.Mass() > area) {
      area = g.Mass();
      best = f;
    }
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: isocam_five_axis_bench SOURCE_DIR\n";
    return 2;
  }
  const std::string root = argv[1];
  const std::vector<Case> cases = {
      {"Figure 2 ruled surface", [] { return TopoDS_Shape(test::figure2_ruled_surface()); },
       [](const TopoDS_Shape&) { return std::vector<int>{0}; }, 0.01},
      {"hill (house on the hill, the hill's top face)", test::house_on_the_hill,
       [](const TopoDS_Shape& s) {
         return std::vector<int>{largest(s, test::house_on_the_hill_picked(s))};
       },
       0.01},
      {"MAT.brep", [] { return test::load("MAT.brep"); },
       [](const TopoDS_Shape&) { return std::vector<int>{0}; }, 0.01, false},
  };
  const int only = argc > 2 ? std::atoi(argv[2]) : -1;
  std::ostringstream t;
  t << "| model (h) | tool, pattern | time (s) | cutting (mm) | paths | machine / cutting time "
       "(min) "
       "| guaranteed scallop / overcut (mm) | unreachable (mm) | rotary travel A / C (deg) |\n";
  t << "|---|---|---|---|---|---|---|---|---|\n";
  std::ostringstream links;
  links << "\n| model | 5-axis linking | low links / safe-height hops | rapid (mm) | machine time "
           "(min) | without the rotary timing (min) |\n|---|---|---|---|---|---|\n";
  for (std::size_t ci = 0; ci < cases.size(); ++ci) {
    if (only >= 0 && static_cast<std::size_t>(only) != ci) continue;
    const Case& c = cases[ci];
    const TopoDS_Shape shape = c.shape();
    const std::vector<int> faces = c.faces(shape);
    auto row = [&](const std::string& tool, double secs, double cut, int paths, double machine,
                   double cutting, double gs, double go, double unreach, const std::string& rot) {
      t << "| " << c.name << " (" << c.h << ") | " << tool << " | " << num(secs, 2) << " | "
        << num(cut, 0) << " | " << paths << " | " << num(machine / 60, 1) << " / "
        << num(cutting / 60, 1) << " | " << num(gs, 4) << " / " << num(go, 4) << " | "
        << num(unreach, 1) << " | " << rot << " |\n";
      std::cout << c.name << " / " << tool << ": " << num(secs, 2) << " s, cutting " << num(cut, 0)
                << " mm, machine " << num(machine / 60, 1) << " min" << std::endl;
    };
    // The 5-axis runs: low links (the default), then every run through the
    // safe height (the linking before issue 13's low links); machine time
    // with the rotary moves timed, and without (tip moves only, as before);
    // NormalIsocurves; A allowed from -90 deg (the C branch turned half a
    // turn where that is the shorter rotary move); and the passes run back
    // lagging (lag_on_return: the tilt keeps its side, A from 0).
    struct Run5 {
      FiveAxisStrategy strategy;
      bool low;
      double a_min;
      bool lag = false;
    };
    for (const Run5 run : {Run5{FiveAxisStrategy::StripEvaluation, true, 0.0},
                           Run5{FiveAxisStrategy::StripEvaluation, false, 0.0},
                           Run5{FiveAxisStrategy::NormalIsocurves, true, 0.0},
                           Run5{FiveAxisStrategy::StripEvaluation, true, -90.0},
                           Run5{FiveAxisStrategy::StripEvaluation, true, 0.0, true}}) {
      const bool low = run.low;
      const bool iso = run.strategy == FiveAxisStrategy::NormalIsocurves;
      if (!c.all_variants && !(low && run.a_min == 0.0 && !run.lag)) continue;
      const std::string a_range =
          std::string(run.a_min < 0 ? ", A from -90" : "") + (run.lag ? ", lag on return" : "");
      FiveAxisParams p;
      p.scallop_height = c.h;
      p.low_links = low;
      p.strategy = run.strategy;
      p.a_min = run.a_min;
      p.lag_on_return = run.lag;
      const auto t0 = std::chrono::steady_clock::now();
      const FiveAxisResult r = five_axis_finish(shape, faces, p);
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const FiveAxisMetrics& m = r.metrics;
      const std::string label =
          std::string("5-axis flat end 6 mm, lead 5 deg, ") + (iso ? "NormalIsocurves, " : "") +
          (low ? "low links" : "safe height") + a_range +
          (m.isocurve_faces > 0 ? " (isocurves used on " + std::to_string(m.isocurve_faces) +
                                      " of " + std::to_string(faces.size()) + " faces)"
                                : "");
      row(label, secs, m.cutting_length, m.paths, m.machine_time, m.cutting_time,
          m.guaranteed_scallop, m.guaranteed_overcut, m.unreachable_length,
          num(m.rotary_travel_a, 0) + " / " + num(m.rotary_travel_c, 0));
      const PathTimes tip = estimate_time(r.path, p.feed_rate, p.plunge_rate, p.rapid_rate);
      links << "| " << c.name << " | " << (iso ? "NormalIsocurves, " : "")
            << (low ? "low links" : "safe height") << a_range << " | " << m.low_links << " / "
            << m.safe_hops << " | " << num(m.rapid_length, 0) << " | "
            << num(m.machine_time / 60, 2) << " | " << num(tip.total / 60, 2) << " |\n";
      for (const std::string& w : r.warnings) std::cout << "  warning: " << w << "\n";
    }
    for (IsoPattern pat : {IsoPattern::ConstantScallop, IsoPattern::Adaptive}) {
      IsoParams p;
      p.ball_radius = 3.0;
      p.scallop_height = c.h;
      p.pattern = pat;
      p.safe_z = 1000;
      const auto t0 = std::chrono::steady_clock::now();
      const IsoResult r = adaptive_isocurve(shape, faces, p);
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const IsoMetrics& m = r.metrics;
      row(std::string("3-axis ball 6 mm, ") +
              (pat == IsoPattern::Adaptive ? "Adaptive" : "ConstantScallop"),
          secs, m.cutting_length, m.sub_isocurves, m.machine_time, m.cutting_time,
          m.guaranteed_scallop, m.guaranteed_overcut, m.unreachable_length, "-");
    }
  }
  std::ofstream(root + "/bench/five_axis_results" +
                (only >= 0 ? "_" + std::to_string(only) : std::string()) + ".md")
      << t.str() << links.str();
  std::cout << t.str() << links.str();
  return 0;
}
