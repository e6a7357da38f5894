// 5-axis strip finishing's links (isocam/five_axis.h, "Links"): on the
// tilted top of a box beside a tower (which sets the safe height), several
// passes linked low against the same passes linked through the safe
// height: fewer trips up there, less machine time, the same cutting; every
// rapid swept by a check that shares nothing with the core (the tool a
// cylinder, the model's faces sampled from OpenCASCADE) cuts nothing, and
// the low links keep the air clearance they state; the machine time
// recomputed from the posted moves with the rotary axes timed.
#include <gtest/gtest.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <algorithm>
#include <cmath>
#include <gp_Ax1.hxx>
#include <gp_Trsf.hxx>
#include <iostream>
#include <vector>

#include "isocam/five_axis.h"

namespace isocam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Points of every face of the shape about `spacing` apart (the faces of a
// box fill their parameter rectangles).
std::vector<gp_Pnt> sample_faces(const TopoDS_Shape& shape, double spacing) {
  std::vector<gp_Pnt> out;
  for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next()) {
    const TopoDS_Face f = TopoDS::Face(ex.Current());
    double u0, u1, v0, v1;
    BRepTools::UVBounds(f, u0, u1, v0, v1);
    const BRepAdaptor_Surface s(f);
    const int nu = 1 + static_cast<int>((u1 - u0) / spacing);
    const int nv = 1 + static_cast<int>((v1 - v0) / spacing);
    for (int i = 0; i <= nu; ++i)
      for (int j = 0; j <= nv; ++j)
        out.push_back(s.Value(u0 + (u1 - u0) * i / nu, v0 + (v1 - v0) * j / nv));
  }
  return out;
}

// The distance from q to the solid cylinder of radius R from `tip` up the
// unit `axis` over L; inside, minus the depth.
double cylinder_distance(const gp_Pnt& q, const gp_Pnt& tip, const gp_Vec& axis, double R,
                         double L) {
  const gp_Vec w(tip, q);
  const double h = w.Dot(axis);
  const double r = (w - axis * h).Magnitude();
  const double dh = std::max(-h, h - L), dr = r - R;
  if (dh <= 0 && dr <= 0) return std::max(dh, dr);
  return std::hypot(std::max(dh, 0.0), std::max(dr, 0.0));
}

// The least distance from the sampled model to the tool along move k (the
// tip straight, A and C linear as posted, every 0.05 mm of tip travel and
// 0.25 degree); points farther than the tool's reach + 5 count as 5.
double rapid_clearance(const FiveAxisResult& r, std::size_t k, const std::vector<gp_Pnt>& model,
                       double R, double L) {
  const gp_Pnt p0(r.path.x[k - 1], r.path.y[k - 1], r.path.z[k - 1]);
  const gp_Pnt p1(r.path.x[k], r.path.y[k], r.path.z[k]);
  const double da = r.a[k] - r.a[k - 1], dc = r.c[k] - r.c[k - 1];
  const int n = 1 + static_cast<int>(std::max(p0.Distance(p1) / 0.05,
                                              std::max(std::abs(da), std::abs(dc)) / 0.25));
  const double reach = std::hypot(R, L) + 5.0;
  double least = 5.0;
  for (int q = 0; q <= n; ++q) {
    const double t = double(q) / n;
    const gp_Pnt tip(p0.XYZ() + (p1.XYZ() - p0.XYZ()) * t);
    const double A = (r.a[k - 1] + t * da) * kDeg, C = (r.c[k - 1] + t * dc) * kDeg;
    const gp_Vec axis(std::sin(A) * std::sin(C), -std::sin(A) * std::cos(C), std::cos(A));
    for (const gp_Pnt& x : model)
      if (x.Distance(tip) < reach) least = std::min(least, cylinder_distance(x, tip, axis, R, L));
  }
  return least;
}

// A low link: a rapid that is not along the axis (the retracts and
// descents are) with neither end at the safe height (the old links' other
// rapids go up to it, across it and down from it).
bool is_low_link(const FiveAxisResult& r, std::size_t k, double safe) {
  if (r.path.kind[k] != static_cast<std::uint8_t>(MoveKind::Rapid)) return false;
  if (std::abs(r.path.z[k - 1] - safe) < 1e-5 || std::abs(r.path.z[k] - safe) < 1e-5) return false;
  const gp_Vec move(r.path.x[k] - r.path.x[k - 1], r.path.y[k] - r.path.y[k - 1],
                    r.path.z[k] - r.path.z[k - 1]);
  const gp_Vec axis(r.i[k], r.j[k], r.k[k]);
  return move.Magnitude() > 1e-9 && move.Crossed(axis).Magnitude() > 1e-6 * move.Magnitude();
}

// The traverses at the safe height: rapids with both ends up there (to
// 1e-5 mm: the core takes the model's top from a bounding box grown by
// the shape's tolerance).
int safe_traverses(const FiveAxisResult& r, double safe) {
  int n = 0;
  for (std::size_t k = 1; k < r.path.size(); ++k)
    if (r.path.kind[k] == static_cast<std::uint8_t>(MoveKind::Rapid) &&
        std::abs(r.path.z[k] - safe) < 1e-5 && std::abs(r.path.z[k - 1] - safe) < 1e-5)
      ++n;
  return n;
}

// The machine time recomputed from the moves: each the longest of its tip
// length at its rate and |dA|, |dC| at the rotary rate.
double machine_seconds(const FiveAxisResult& r, const FiveAxisParams& p) {
  double s = 0;
  for (std::size_t k = 1; k < r.path.size(); ++k) {
    const double len = std::hypot(r.path.x[k] - r.path.x[k - 1], r.path.y[k] - r.path.y[k - 1],
                                  r.path.z[k] - r.path.z[k - 1]);
    const auto kind = static_cast<MoveKind>(r.path.kind[k]);
    const double rate = kind == MoveKind::Rapid    ? p.rapid_rate
                        : kind == MoveKind::Plunge ? p.plunge_rate
                                                   : p.feed_rate;
    s += 60.0 * std::max({len / rate, std::abs(r.a[k] - r.a[k - 1]) / p.rotary_rate,
                          std::abs(r.c[k] - r.c[k - 1]) / p.rotary_rate});
  }
  return s;
}

TEST(FiveAxisLinks, LowLinksSaveTripsAndTimeAndKeepTheToolClear) {
  // A box 20 x 12 x 6 whose top is tilted by 20 degrees about x, and a
  // tower 25 mm high beside it, which sets the safe height.
  gp_Trsf tilt;
  tilt.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), 20 * kDeg);
  BRep_Builder builder;
  TopoDS_Compound box;
  builder.MakeCompound(box);
  builder.Add(box, BRepBuilderAPI_Transform(
                       BRepPrimAPI_MakeBox(gp_Pnt(-10, -6, -6), 20, 12, 6).Shape(), tilt)
                       .Shape());
  builder.Add(box, BRepPrimAPI_MakeBox(gp_Pnt(25, -3, -6), 5, 6, 31).Shape());
  // The safe height: the model's top (the tower's) + the air clearance.
  double top = -1e300;
  for (TopExp_Explorer ex(box, TopAbs_VERTEX); ex.More(); ex.Next())
    top = std::max(top, BRep_Tool::Pnt(TopoDS::Vertex(ex.Current())).Z());
  // The tilted top: the higher of the two faces normal to (0, -sin 20, cos 20).
  const gp_Dir up(0, -std::sin(20 * kDeg), std::cos(20 * kDeg));
  int top_face = -1, index = 0;
  double best = -1e300;
  for (TopExp_Explorer ex(box, TopAbs_FACE); ex.More(); ex.Next(), ++index) {
    const BRepAdaptor_Surface s(TopoDS::Face(ex.Current()));
    if (s.GetType() != GeomAbs_Plane || !s.Plane().Axis().Direction().IsParallel(up, 1e-9))
      continue;
    const double z = s.Plane().Location().Z();
    if (z > best) {
      best = z;
      top_face = index;
    }
  }
  ASSERT_GE(top_face, 0);

  FiveAxisParams p;
  p.scallop_height = 0.05;
  const double safe = top + p.air_clearance;
  FiveAxisParams hops = p;
  hops.low_links = false;
  const FiveAxisResult low = five_axis_finish(box, {top_face}, p);
  const FiveAxisResult old = five_axis_finish(box, {top_face}, hops);
  ASSERT_GE(low.metrics.paths, 4);
  EXPECT_EQ(old.metrics.low_links, 0);
  EXPECT_GT(low.metrics.low_links, 0);
  EXPECT_EQ(low.metrics.low_links + low.metrics.safe_hops, old.metrics.safe_hops);
  // The same cutting, fewer trips through the safe height, less time.
  EXPECT_NEAR(low.metrics.cutting_length, old.metrics.cutting_length, 1e-9);
  EXPECT_LT(safe_traverses(low, safe), safe_traverses(old, safe));
  EXPECT_LT(low.metrics.machine_time, old.metrics.machine_time);
  EXPECT_LT(low.metrics.rapid_length, old.metrics.rapid_length);
  // The machine time as the moves give it, rotary moves timed.
  EXPECT_NEAR(low.metrics.machine_time, machine_seconds(low, p), 1e-9 * low.metrics.machine_time);
  EXPECT_NEAR(old.metrics.machine_time, machine_seconds(old, hops),
              1e-9 * old.metrics.machine_time);

  // Every rapid cuts nothing of the model (the tool touches the face where
  // a retract starts, within the overcut); the low links keep the air
  // clearance less the clearance query's accuracy (the gouge tolerance).
  const std::vector<gp_Pnt> model = sample_faces(box, 0.25);
  int links = 0;
  double least_link = 5.0;
  for (std::size_t k = 1; k < low.path.size(); ++k) {
    if (low.path.kind[k] != static_cast<std::uint8_t>(MoveKind::Rapid)) continue;
    const double clear = rapid_clearance(low, k, model, p.tool_radius, p.tool_length);
    EXPECT_GE(clear, -low.metrics.guaranteed_overcut) << "rapid " << k;
    if (is_low_link(low, k, safe)) {
      ++links;
      least_link = std::min(least_link, clear);
      EXPECT_GE(clear, p.air_clearance - p.gouge_tolerance) << "link " << k;
    }
  }
  EXPECT_EQ(links, low.metrics.low_links);
  std::cout << "links low / safe height: " << low.metrics.low_links << " / "
            << low.metrics.safe_hops << " (before: 0 / " << old.metrics.safe_hops
            << "); machine time " << low.metrics.machine_time << " s (before "
            << old.metrics.machine_time << " s); rapid " << low.metrics.rapid_length
            << " mm (before " << old.metrics.rapid_length << " mm); least sampled link clearance "
            << least_link << " mm\n";
}

}  // namespace
}  // namespace isocam
