// Where the reach from above ends (issue 10): the scallop guarantee holds on
// every sample a 3-axis tool reaches, measured on the cut (not inferred),
// also between two passes of which only one reaches; and an open face is
// finished from the sides a vertical tool reaches.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakePolygon.hxx>
#include <BRep_Builder.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <gp_Pln.hxx>
#include <iostream>
#include <string>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "support/checks.h"
#include "support/models.h"

namespace isocam {
namespace {

IsoParams params(double r, double h, IsoDirection dir) {
  IsoParams p;
  p.ball_radius = r;
  p.scallop_height = h;
  p.direction = dir;
  p.safe_z = 50;
  return p;
}

// A 20 x 20 mm plate at z = 0 under a roof at z = 3 whose edge runs
// diagonally across it (from x = 12 at y = -1 to x = 16 at y = 21): every
// pass along x is cut where the column above its centres meets the roof,
// each at another x, so that between two neighbouring passes the surface
// beyond the shorter one is cut from one side only (before the border
// passes: up to a whole stepover away, four times the cusp the pair was
// spaced for).
TEST(ReachBorder, ScallopHoldsWhereTheReachEndsAcrossThePasses) {
  const TopoDS_Face plate = BRepBuilderAPI_MakeFace(gp_Pln(), 0, 20, 0, 20).Face();
  BRepBuilderAPI_MakePolygon edge(gp_Pnt(12, -1, 3), gp_Pnt(22, -1, 3), gp_Pnt(22, 21, 3),
                                  gp_Pnt(16, 21, 3), true);
  const TopoDS_Face roof = BRepBuilderAPI_MakeFace(edge.Wire(), true).Face();
  const TopoDS_Shape shape = test::compound({plate, roof});
  for (IsoDirection dir : {IsoDirection::U, IsoDirection::V}) {
    const IsoParams p = params(1.0, 0.01, dir);
    const IsoResult res = adaptive_isocurve(shape, {0}, p);
    const test::ModelCloud reach(faces_of(shape), p.ball_radius / 8, true);
    const test::ScallopCheck s =
        test::measure_scallop(plate, res.path, p.ball_radius, 200, 0.01, 1.0, &reach);
    std::cout << (dir == IsoDirection::U ? "U" : "V") << ": scallop measured " << s.max
              << " <= guaranteed " << res.metrics.guaranteed_scallop << " (asked "
              << p.scallop_height << "), unreachable samples " << s.unreachable << "/" << s.samples
              << ", sub-isocurves " << res.metrics.sub_isocurves << "\n";
    // The roof hides about a third of the plate (x > 11 + y / 5 less r).
    EXPECT_GT(s.unreachable, s.samples / 5);
    EXPECT_LT(s.unreachable, s.samples / 2);
    EXPECT_EQ(s.uncovered, 0);
    EXPECT_LE(s.max, res.metrics.guaranteed_scallop);
    EXPECT_LE(res.metrics.guaranteed_scallop, p.scallop_height * (1 + 1e-9));
  }
}

// A vertical open face alone is reached on both sides: it is finished from
// both (the ball centres r from it on either side), each side within the
// guarantee, and the result says so.
TEST(ReachBorder, OpenVerticalWallIsFinishedFromBothSides) {
  const gp_Pln wall_plane(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0), gp_Dir(0, 1, 0)));
  const TopoDS_Face wall = BRepBuilderAPI_MakeFace(wall_plane, 0, 10, 0, 5).Face();
  const IsoParams p = params(1.0, 0.02, IsoDirection::Auto);
  const IsoResult res = adaptive_isocurve(wall, {0}, p);
  bool said = false;
  for (const std::string& w : res.warnings)
    said = said || w.find("(Face1) is an open face that a vertical tool reaches on both sides") !=
                       std::string::npos;
  EXPECT_TRUE(said);
  EXPECT_EQ(res.face_direction.size(), 1u);
  int front = 0, back = 0;
  for (std::size_t i = 0; i < res.path.size(); ++i) {
    if (res.path.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    front += res.path.x[i] > 0.9;
    back += res.path.x[i] < -0.9;
  }
  EXPECT_GT(front, 20);
  EXPECT_GT(back, 20);
  for (const TopoDS_Face& side : {wall, TopoDS::Face(wall.Reversed())}) {
    const test::ScallopCheck s =
        test::measure_scallop(side, res.path, p.ball_radius, 100, 0.01, 1.0);
    EXPECT_EQ(s.uncovered, 0);
    EXPECT_LE(s.max, res.metrics.guaranteed_scallop);
  }
}

}  // namespace
}  // namespace isocam
