// Z-level roughing (Elber & Cohen section 4, Figure 4): a dome on a plate
// inside a box of stock. At every level:
//   - no tool centre comes closer than r + stock_to_leave (minus the
//     tolerance) to the model's material at and above the level, none is
//     inside it;
//   - every point of the stock that a tool kept that far from the model can
//     reach is cut (raster of 0.2 mm cells).
#include <gtest/gtest.h>

#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <cmath>
#include <iostream>
#include <map>

#include "isocam/pocket_check.h"
#include "isocam/pocketing.h"
#include "pocketing/geom2d.h"

namespace isocam {
namespace {

TEST(PocketRoughing, DomeOnAPlate) {
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 100, 80, 10).Shape();
  const TopoDS_Shape dome = BRepPrimAPI_MakeSphere(gp_Pnt(50, 40, 0), 30).Shape();
  const TopoDS_Shape model = BRepAlgoAPI_Fuse(plate, dome).Shape();
  const TopoDS_Shape stock = BRepPrimAPI_MakeBox(gp_Pnt(-2, -2, 0), 104, 84, 34).Shape();
  RoughingParams rp;
  rp.pocket.tool_radius = 3;
  rp.pocket.stepover = 3;
  rp.pocket.tolerance = 0.01;
  rp.pocket.safe_z = 40;
  rp.stock_to_leave = 0.5;
  rp.depths = {28, 22, 16, 10.5, 4};
  const PocketResult res = zlevel_roughing(model, stock, rp);
  const PocketMetrics& m = res.metrics;
  std::cout << "    levels " << m.levels << ", loops " << m.loops << ", cutting "
            << m.cutting_length << " mm, rapid " << m.rapid_length << " mm, retracts " << m.retracts
            << ", feed links " << m.feed_links << ", G2/G3 " << m.arcs << "\n";
  ASSERT_EQ(m.levels, 5);
  const double r = rp.pocket.tool_radius, keep = r + rp.stock_to_leave;
  std::vector<Loop> material;  // at and above the level (and stock_to_leave below)
  for (double z : rp.depths) {
    std::vector<Loop> sec = section_region(model, z - rp.stock_to_leave + 1e-3, 0.001);
    sec.insert(sec.end(), material.begin(), material.end());
    material = resolve_loops(sec);
    // Clearance from the material, at this level.
    std::vector<Seg> msegs;
    for (const Loop& l : material) msegs.insert(msegs.end(), l.begin(), l.end());
    const pocket::SegGrid grid(msegs, 2.0);
    const pocket::WindingIndex inside(msegs);
    double min_d = 1e300;
    long samples = 0;
    for (std::size_t i = 1; i < res.path.size(); ++i) {
      if (res.path.z[i] != z || res.path.z[i - 1] != z) continue;
      const P2 a{res.path.x[i - 1], res.path.y[i - 1]}, b{res.path.x[i], res.path.y[i]};
      const auto k = static_cast<MoveKind>(res.path.kind[i]);
      const Seg s =
          (k == MoveKind::ArcCW || k == MoveKind::ArcCCW)
              ? Seg::arc_between({res.path.cx[i], res.path.cy[i]}, a, b, k == MoveKind::ArcCCW)
              : Seg::line(a, b);
      const int n = std::max(1, static_cast<int>(std::ceil(s.length() / 0.2)));
      for (int j = 0; j <= n; ++j) {
        const P2 p = s.at(static_cast<double>(j) / n);
        ASSERT_LT(inside.at(p), 1) << "tool centre inside the model at z " << z;
        min_d = std::min(min_d, grid.distance(p));
        ++samples;
      }
    }
    // Coverage: the stock's section, with the material grown by
    // stock_to_leave as islands; the tool may go r outside the stock.
    const std::vector<Loop> stock_sec = section_region(stock, z + 1e-3, 0.001);
    std::vector<Loop> region = dilate_region(stock_sec, 2 * r);
    for (const Loop& l : dilate_region(material, rp.stock_to_leave)) region.push_back(reversed(l));
    region = resolve_loops(region);
    CoverageParams cp;
    cp.tool_radius = r;
    cp.cell = 0.2;
    cp.tolerance = 0.02;
    cp.z_floor = z;
    const CoverageReport cov = pocket_coverage(region, res.path, cp);
    // Only the stock's own points must be cut: count the uncut reachable
    // ones inside the stock outline by restricting the region to it.
    std::vector<Loop> in_stock = stock_sec;
    for (const Loop& l : dilate_region(material, rp.stock_to_leave))
      in_stock.push_back(reversed(l));
    const CoverageReport cov_stock = pocket_coverage(resolve_loops(in_stock), res.path, cp);
    std::cout << "    z " << z << ": " << samples << " centre samples, min distance to the model "
              << min_d << " (>= " << keep << "), uncut reachable " << cov.uncut_reachable_area
              << " mm2, stock left uncut " << cov_stock.uncut_area << " mm2 (against the model)\n";
    EXPECT_GT(samples, 0);
    if (!material.empty()) {
      EXPECT_GE(min_d, keep - 0.02) << "z " << z;
    }
    EXPECT_EQ(cov.uncut_reachable_area, 0.0)
        << "at " << cov.worst_x << ", " << cov.worst_y << ", z " << z;
  }
}

}  // namespace
}  // namespace isocam
