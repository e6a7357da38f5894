// Adaptive isocurves spaced by a strip width (finishing/strip_isocurves.h,
// the 5-axis NormalIsocurves strategy) on the Figure 2 ruled surface, whose
// ruling is 100 mm wide at the ends and 5-10 mm in the middle: checked by
// its own search of the curve above each sample, every two adjacent curves
// within the width at the same u, each sample covered from vmin to vmax;
// sub-isocurves only where needed (fewer samples than complete isocurves at
// the finest spacing used), the progress rising with v; a width of nothing
// ends at the minimum spacing; a cancel stops it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "finishing/strip_isocurves.h"
#include "geometry/patch_grid.h"
#include "support/models.h"

namespace isocam {
namespace {

// For each u sampled, the levels v that have a point there (ascending).
std::map<double, std::vector<double>> levels_at(const IsoStripPaths& iso) {
  std::map<double, std::vector<double>> at;
  for (const std::vector<FrontPiece>& path : iso.paths)
    for (const FrontPiece& pc : path)
      for (const FrontPoint& x : pc) at[x.uv.u].push_back(x.uv.v);
  for (auto& [u, vs] : at) std::sort(vs.begin(), vs.end());
  return at;
}

TEST(StripIsocurves, AdjacentCurvesWithinTheWidthOnlyWhereNeeded) {
  const PatchGrid g = PatchGrid::from_face(test::figure2_ruled_surface(), 0);
  const double w = 3.0;
  IsoStripSettings s;
  s.sample_max = 1.0;
  std::vector<double> reported;
  const IsoStripPaths iso = strip_isocurves(
      g, [w](const StripFrame&) { return w; }, s, [&reported](double f) { reported.push_back(f); });
  // The progress rises from 0 to 1 through values between.
  ASSERT_GT(reported.size(), 10u);
  EXPECT_EQ(reported.front(), 0.0);
  EXPECT_EQ(reported.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end()));
  EXPECT_TRUE(
      std::any_of(reported.begin(), reported.end(), [](double f) { return f > 0.3 && f < 0.7; }));
  EXPECT_EQ(iso.min_hits, 0);
  EXPECT_FALSE(iso.capped);
  const auto at = levels_at(iso);
  ASSERT_GT(at.size(), 300u);  // 300 mm at 1 mm
  double widest = 0.0, finest = g.vmax() - g.vmin();
  std::size_t points = 0;
  for (const auto& [u, vs] : at) {
    ASSERT_GE(vs.size(), 2u);
    EXPECT_EQ(vs.front(), g.vmin());
    EXPECT_EQ(vs.back(), g.vmax());
    for (std::size_t k = 0; k + 1 < vs.size(); ++k) {
      const double d = g.eval(u, vs[k]).Distance(g.eval(u, vs[k + 1]));
      EXPECT_LE(d, w + 1e-9) << "u " << u << " v " << vs[k];
      widest = std::max(widest, d);
      finest = std::min(finest, vs[k + 1] - vs[k]);
    }
    points += vs.size();
  }
  EXPECT_GT(widest, 0.5 * w);  // not spaced closer than halving needs
  // Complete isocurves at the finest spacing would have this many points.
  const double complete = double(at.size()) * ((g.vmax() - g.vmin()) / finest + 1);
  std::cout << points << " points in " << iso.paths.size() << " levels; complete isocurves "
            << complete << "\n";
  EXPECT_LT(double(points), 0.5 * complete);
  // The module's own partners agree with the search above.
  for (std::size_t i = 0; i < iso.paths.size(); ++i)
    for (std::size_t j = 0; j < iso.paths[i].size(); ++j)
      for (std::size_t k = 0; k < iso.paths[i][j].size(); ++k) {
        const FrontPoint& x = iso.paths[i][j][k];
        const std::vector<double>& vs = at.at(x.uv.u);
        const auto it = std::upper_bound(vs.begin(), vs.end(), x.uv.v);
        ASSERT_EQ(x.has_next, it != vs.end());
        if (x.has_next) {
          EXPECT_EQ(iso.next[i][j][k].v, *it);
        }
      }
}

TEST(StripIsocurves, WidthOfNothingStopsAtTheMinimumSpacing) {
  const PatchGrid g = PatchGrid::from_face(test::figure2_ruled_surface(), 0);
  IsoStripSettings s;
  s.sample_max = 5.0;
  s.min_dv = 1e-3;
  const IsoStripPaths iso = strip_isocurves(
      g, [](const StripFrame&) { return 0.0; }, s, [](double) {});
  EXPECT_GT(iso.min_hits, 0);
  EXPECT_LT(iso.paths.size(), 2050u);  // about 1 / min_dv levels
}

TEST(StripIsocurves, CancelStopsIt) {
  const PatchGrid g = PatchGrid::from_face(test::figure2_ruled_surface(), 0);
  int calls = 0;
  EXPECT_THROW(strip_isocurves(
                   g, [](const StripFrame&) { return 0.5; }, IsoStripSettings{},
                   [&calls](double) {
                     if (++calls > 3) throw std::runtime_error("cancelled");
                   }),
               std::runtime_error);
}

}  // namespace
}  // namespace isocam
