// The constant-scallop pattern (IsoPattern::ConstantScallop, after Lee 1998):
// on a plane, a cylinder, a sphere cap and the Figure 2 ruled surface, every
// face point within half the largest spacing of the path's contact points
// (Definition 1 with the strip half-width, on an independent dense
// sampling), the scallop measured on the swept balls under the requested
// height, the certificate true, no gouge; shorter than the Adaptive pattern
// where isocurves crowd; and a strip width that shrinks to nothing ends in a
// warning, not a hang.
#include <gtest/gtest.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <algorithm>
#include <cmath>
#include <functional>
#include <gp_Pln.hxx>
#include <iostream>
#include <random>

#include "finishing/constant_scallop.h"
#include "finishing/scallop_front.h"
#include "geometry/patch_grid.h"
#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "support/checks.h"
#include "support/models.h"
#include "support/same_path.h"

namespace isocam {
namespace {

IsoParams scallop_params(double r, double h) {
  IsoParams p;
  p.ball_radius = r;
  p.scallop_height = h;
  p.pattern = IsoPattern::ConstantScallop;
  p.safe_z = 1000;
  return p;
}

// The contact points of the feed moves: each ball centre (tip + r z)
// projected onto the face's surface by OpenCASCADE, joined move by move.
test::SegmentIndex contact_segments(const TopoDS_Face& face, const Toolpath& t, double r,
                                    double cell) {
  Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  test::SegmentIndex out(cell);
  auto foot = [&](std::size_t i, gp_Pnt* q) {
    GeomAPI_ProjectPointOnSurf proj(gp_Pnt(t.x[i], t.y[i], t.z[i] + r), s);
    if (proj.NbPoints() == 0) return false;
    *q = proj.NearestPoint();
    return true;
  };
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    gp_Pnt a, b;
    if (foot(i - 1, &a) && foot(i, &b)) out.add(a, b);
  }
  return out;
}

struct Checked {
  double gap = 0.0, scallop = 0.0, closest = 0.0;
  int uncovered = 0;
};

// The invariants on one face: coverage, measured scallop, no gouge.
Checked check_face(const TopoDS_Shape& shape, int face_index, const IsoResult& res,
                   const IsoParams& p) {
  const TopoDS_Face face = test::face(shape, face_index);
  Checked c;
  const double delta = res.metrics.delta;
  c.gap = test::coverage_gap(face, contact_segments(face, res.path, p.ball_radius, delta), 120,
                             2 * delta);
  // Where a 3-axis tool reaches from above (not under the equator).
  const test::ModelCloud reach(face, 200);
  const test::ScallopCheck s =
      test::measure_scallop(face, res.path, p.ball_radius, 120, 0.02, 1.0, &reach);
  c.scallop = s.max;
  c.uncovered = s.uncovered;
  const test::FaceCloud cloud(face, 400);
  c.closest = test::min_centre_distance(cloud, res.path, p.ball_radius, 4000);
  std::cout << "  coverage gap " << c.gap << " (largest spacing " << res.metrics.delta_max
            << ", flat stepover " << delta << "), measured scallop " << c.scallop << " ("
            << s.uncovered << " of " << s.samples << " uncovered), certified "
            << res.metrics.guaranteed_scallop << ", max spacing measured "
            << res.metrics.max_iso_distance << ", cutting " << res.metrics.cutting_length
            << " mm, L* " << res.metrics.lower_bound_length << ", closest centre " << c.closest
            << "\n";
  return c;
}

// The largest distance of a posted ball centre from the exact offset: the
// chord tolerance used plus the rounding of the posted coordinates.
double centre_error(const IsoResult& res, const IsoParams& p) {
  return res.metrics.chord_tolerance + std::sqrt(3.0) / 2 * p.posted_resolution;
}

void expect_invariants(const Checked& c, const IsoResult& res, const IsoParams& p) {
  // Definition 1 with the strip half-width: no face point farther than half
  // the largest spacing (plus the chord tolerance and the sampling).
  EXPECT_LT(c.gap,
            0.5 * res.metrics.delta_max + res.metrics.chord_tolerance + 0.02 * res.metrics.delta);
  EXPECT_EQ(c.uncovered, 0);
  // The scallop as cut, and the certificate true (chords cut into a convex
  // offset, which lowers cusps; the 3% covers what the sampling misses).
  EXPECT_LE(c.scallop, 1.03 * p.scallop_height + 1e-4);
  EXPECT_LE(c.scallop, res.metrics.guaranteed_scallop * 1.03 + 1e-4);
  // The strips are spaced for the cusp the centres' error (chord and posted
  // rounding, see adaptive_isocurve.h) leaves, and a face whose certificate
  // measures more is spaced again: the whole guarantee within the height.
  EXPECT_LE(res.metrics.guaranteed_scallop, p.scallop_height * (1 + 1e-9));
  EXPECT_GT(res.metrics.guaranteed_scallop, centre_error(res, p));
  EXPECT_GE(c.closest, p.ball_radius - res.metrics.chord_tolerance - p.gouge_tolerance - 1e-6);
}

TEST(ConstantScallop, PlaneGetsPassesOneStepoverApart) {
  const TopoDS_Face plate = BRepBuilderAPI_MakeFace(gp_Pln(gp::Origin(), gp::DZ()), 0, 40, 0, 30);
  IsoParams p = scallop_params(3.0, 0.05);
  p.direction = IsoDirection::V;  // start on the 40 mm side, step across the 30 mm one
  const IsoResult res = adaptive_isocurve(plate, {0}, p);
  // The engine spaces the strips for the cusp that balls of radius r - e
  // leave on the design offset by e, e the centres' error (chord and posted
  // rounding): on flat ground the flat stepover of h - e for r - e.
  const double e = centre_error(res, p);
  const double delta = stepover_for_scallop(p.ball_radius - e, p.scallop_height - e);
  EXPECT_NEAR(res.metrics.delta, delta, 1e-9);
  EXPECT_TRUE(res.curves.empty());
  // On flat ground the strip width is the flat stepover everywhere: the
  // passes are that far apart, and the 30 mm side needs ceil(30 / delta) + 1.
  EXPECT_NEAR(res.metrics.max_iso_distance, delta, 1e-3 * delta);
  EXPECT_NEAR(res.metrics.guaranteed_scallop, p.scallop_height, 1e-3 * p.scallop_height);
  EXPECT_EQ(res.metrics.sub_isocurves, static_cast<int>(std::ceil(30 / delta)) + 1);
  std::cout << "plane:\n";
  expect_invariants(check_face(plate, 0, res, p), res, p);
}

TEST(ConstantScallop, CylinderConvexGroundKeepsTheScallop) {
  const TopoDS_Shape cyl = BRepPrimAPI_MakeCylinder(8.0, 20.0).Shape();
  IsoParams p = scallop_params(3.0, 0.05);
  p.chord_tolerance = 0.002;
  p.direction = IsoDirection::U;  // paths along the axis, stepping round it
  const IsoResult res = adaptive_isocurve(cyl, {0}, p);
  std::cout << "cylinder:\n";
  const Checked c = check_face(cyl, 0, res, p);
  expect_invariants(c, res, p);
  // Convex: the strip is narrower than on flat ground, and used.
  EXPECT_LT(res.metrics.delta_max, res.metrics.delta);
  EXPECT_GT(c.scallop, 0.7 * p.scallop_height);
}

TEST(ConstantScallop, SphereCapIsCoveredWithoutGouge) {
  const TopoDS_Shape cap = BRepPrimAPI_MakeSphere(20.0, M_PI / 6, M_PI / 2).Shape();
  IsoParams p = scallop_params(3.0, 0.05);
  p.chord_tolerance = 0.002;
  const IsoResult res = adaptive_isocurve(cap, {0}, p);
  std::cout << "sphere cap:\n";
  expect_invariants(check_face(cap, 0, res, p), res, p);
}

TEST(ConstantScallop, Figure2IsCoveredAndShorterThanAdaptive) {
  const TopoDS_Face f = test::figure2_ruled_surface();
  IsoParams p = scallop_params(5.0, 0.1);
  const IsoResult res = adaptive_isocurve(f, {0}, p);
  p.pattern = IsoPattern::Adaptive;
  const IsoResult adaptive = adaptive_isocurve(f, {0}, p);
  p.pattern = IsoPattern::ConstantScallop;
  std::cout << "Figure 2: adaptive " << adaptive.metrics.cutting_length << " mm\n";
  expect_invariants(check_face(f, 0, res, p), res, p);
  EXPECT_LT(res.metrics.cutting_length, adaptive.metrics.cutting_length);
}

// Under Auto both directions are traced and the one whose program is
// shorter is kept. On two small faces of Ball (r 1: the ball centres' paths
// far from the contact's), the contact polylines' lengths pointed to the
// direction that cuts 3.1 and 3.7 times more (the choice before); Auto must
// cut no more than the better of the two directions asked for alone.
TEST(ConstantScallop, AutoKeepsTheDirectionThatCutsLess) {
  const TopoDS_Shape ball = test::load("Ball.brep");
  for (int face : {11, 15}) {
    IsoParams p = scallop_params(1.0, 0.01);
    p.protect_unpicked_faces = true;
    double fixed[2];
    for (IsoDirection d : {IsoDirection::U, IsoDirection::V}) {
      p.direction = d;
      fixed[d == IsoDirection::V] = adaptive_isocurve(ball, {face}, p).metrics.cutting_length;
    }
    p.direction = IsoDirection::Auto;
    const double automatic = adaptive_isocurve(ball, {face}, p).metrics.cutting_length;
    std::cout << "Ball face " << face << ": iso-U " << fixed[0] << " mm, iso-V " << fixed[1]
              << " mm, Auto " << automatic << " mm\n";
    EXPECT_GT(std::max(fixed[0], fixed[1]), 2 * std::min(fixed[0], fixed[1]));
    EXPECT_LE(automatic, std::min(fixed[0], fixed[1]) * (1 + 1e-9));
  }
}

// A trimmed face (face.brep: a plate with two holes): the paths are clipped
// to the wires, so no contact point of a feed move lies outside the face,
// the trimmed domain is covered within the spacing, and the certificate
// counts what the clipping leaves.
TEST(ConstantScallop, TrimmedPlateIsClippedToItsWiresAndCovered) {
  const TopoDS_Shape shape = test::load("face.brep");
  const TopoDS_Face face = test::face(shape, 0);
  const IsoParams p = scallop_params(3.0, 0.05);
  const IsoResult res = adaptive_isocurve(shape, {0}, p);
  Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  int outside = 0, feeds = 0;
  test::SegmentIndex contacts(res.metrics.delta);
  gp_Pnt prev;
  bool have = false;
  for (std::size_t i = 0; i < res.path.size(); ++i) {
    const bool feed = res.path.kind[i] == static_cast<std::uint8_t>(MoveKind::Feed);
    GeomAPI_ProjectPointOnSurf proj(
        gp_Pnt(res.path.x[i], res.path.y[i], res.path.z[i] + p.ball_radius), s);
    ASSERT_GT(proj.NbPoints(), 0);
    const gp_Pnt foot = proj.NearestPoint();
    if (feed) {
      ++feeds;
      if (!test::in_face(face, foot, 1e-6)) ++outside;
      // A feed move whose middle is on the face cuts (links over a hole do not).
      GeomAPI_ProjectPointOnSurf mid(gp_Pnt((prev.XYZ() + foot.XYZ()) * 0.5), s);
      if (have && mid.NbPoints() > 0 && test::in_face(face, mid.NearestPoint(), 1e-6))
        contacts.add(prev, foot);
    }
    prev = foot;
    have = true;
  }
  EXPECT_EQ(outside, 0) << "of " << feeds << " feed points";
  const double gap = test::coverage_gap(face, contacts, 200, 2 * res.metrics.delta);
  std::cout << "face.brep: " << res.metrics.sub_isocurves << " pieces, coverage gap " << gap
            << " (largest spacing " << res.metrics.delta_max << "), cutting "
            << res.metrics.cutting_length << " mm, L* " << res.metrics.lower_bound_length
            << ", unreachable " << res.metrics.unreachable_length << " mm\n";
  // Paths are computed on the untrimmed surface and clipped (as isocurves
  // are): where a hole's wire runs along the passes, the pass that would cut
  // next to it is clipped away. The engine samples the wires and starts new
  // paths where that leaves ground beyond the strip, so every face point is
  // within half the largest spacing (and the sampling); the certificate,
  // measured on the clipped paths, bounds what the gap leaves.
  EXPECT_LT(gap, 0.5 * res.metrics.delta_max + p.chord_tolerance + 0.02 * res.metrics.delta);
  EXPECT_GE(res.metrics.max_iso_distance, 1.8 * gap);
  EXPECT_GE(res.metrics.guaranteed_scallop, 0.9 * scallop_for_stepover(p.ball_radius, 2 * gap));
  EXPECT_LE(res.metrics.guaranteed_scallop, p.scallop_height * (1 + 1e-9));
}

// A strip width that shrinks to nothing (a pluggable one: a tool that
// cannot cut a strip): the minimum spacing is used, a warning says so, and
// the face is still covered in finitely many paths.
TEST(ConstantScallop, VanishingStripWidthEndsInAWarning) {
  const TopoDS_Face plate = BRepBuilderAPI_MakeFace(gp_Pln(gp::Origin(), gp::DZ()), 0, 10, 0, 3);
  IsoParams p = scallop_params(3.0, 0.05);
  // The engine is called directly: the chord tolerance the job would derive.
  p.chord_tolerance = 0.002;
  PatchGrid grid = PatchGrid::from_face(plate, 0);
  const TrimDomain trim(plate, grid, 0);
  ClearanceModel model(p.gouge_tolerance, 2 * p.ball_radius);
  model.add(grid, &trim);
  model.build();
  const StripWidth nothing = [](const StripFrame& f) { return f.p.X() > 5 ? 1e-12 : 1.0; };
  const ScallopPieces out =
      constant_scallop_pieces({{0, &grid, &trim}}, p, model, nullptr, nothing);
  ASSERT_EQ(out.warnings.size(), 1u);
  EXPECT_NE(out.warnings[0].find("minimum"), std::string::npos) << out.warnings[0];
  const double flat = stepover_for_scallop(p.ball_radius, p.scallop_height);
  EXPECT_LE(out.max_spacing, 1.0 + 1e-6);
  EXPECT_GT(out.paths, 3.0 / (0.02 * flat));  // the narrow half at the minimum spacing
}

// Beside a reach border the certificate's samples get a short path each
// (ReachBorder::cover()); where the ball reaches only a sliver about the
// sample, that path must keep it. On shell1 at r 2 with the chord
// tolerance set to 0.00091 mm (a tenth of the room), one such sample (face
// 73, beside the grid's side u = 1) got a path whose points about it were
// dropped (within an eighth of a stepover of the side's clamped point) and
// both ends of which the ball does not reach: the cut kept nothing and
// the certificate read 0.0108 mm against h 0.01.
TEST(ConstantScallop, ASpotPathKeepsTheSampleItWasMadeFor) {
  const TopoDS_Shape s = test::load("shell1.brep");
  IsoParams p = scallop_params(2.0, 0.01);
  p.chord_tolerance = 0.00091;
  std::vector<int> all;
  for (std::size_t f = 0; f < faces_of(s).size(); ++f) all.push_back(static_cast<int>(f));
  const IsoResult res = adaptive_isocurve(s, all, p);
  std::cout << "shell1, r 2, chord 0.00091: certified " << res.metrics.guaranteed_scallop << "\n";
  EXPECT_LE(res.metrics.guaranteed_scallop, p.scallop_height * (1 + 1e-9));
}

// The certificate's climb (ReachBorder::climb()) can end on ground the
// ball does not reach from above, past the reach border; the reachable
// ground before that border is then sampled along it as an unreached
// sample's is. On Ball (r 1, h 0.05, every face) a wall of face 17 has
// such a spot between two samples, one just past the border: the posted
// program's simulation read 0.0503 mm left there, and the ball centres
// themselves leave 0.054 mm within 0.02 mm of it, while the climb's peak,
// unreached, was dropped. Measured here on the path's own ball centres.
TEST(ConstantScallop, AClimbPastTheReachBorderSamplesTheBorder) {
  const TopoDS_Shape s = test::load("Ball.brep");
  const IsoParams p = scallop_params(1.0, 0.05);
  std::vector<int> all;
  for (std::size_t f = 0; f < faces_of(s).size(); ++f) all.push_back(static_cast<int>(f));
  const IsoResult res = adaptive_isocurve(s, all, p);
  const test::SegmentIndex tips = test::feed_segments(res.path, 0.5);
  Handle(Geom_Surface) surface = BRep_Tool::Surface(test::face(s, 16));
  GeomAPI_ProjectPointOnSurf proj(gp_Pnt(8.1753, 1.5739, 11.286), surface);
  ASSERT_GT(proj.NbPoints(), 0);
  double u0, v0;
  proj.LowerDistanceParameters(u0, v0);
  gp_Pnt x;
  gp_Vec su, sv;
  surface->D1(u0, v0, x, su, sv);
  // The ground within 0.02 mm, 0.0005 mm apart: material left = distance to
  // the nearest ball centre - r.
  const double du = 0.0005 / su.Magnitude(), dv = 0.0005 / sv.Magnitude();
  double left = 0.0;
  for (int a = -40; a <= 40; ++a)
    for (int b = -40; b <= 40; ++b) {
      const gp_Pnt q = surface->Value(u0 + a * du, v0 + b * dv);
      if (q.Distance(x) > 0.02) continue;
      left = std::max(
          left, tips.distance(q.Translated(gp_Vec(0, 0, -p.ball_radius)), 2.0) - p.ball_radius);
    }
  std::cout << "Ball, r 1, h 0.05: left beside face 17's reach border " << left << ", certified "
            << res.metrics.guaranteed_scallop << "\n";
  EXPECT_LE(left, res.metrics.guaranteed_scallop);
}

// The strip width's curvature beside a pole of the parametrisation (a
// sphere's, on the grid's side v = vmax): the parameters' directions
// degenerate there and the exact derivatives' solve cancels (59.6 against
// 1/R = 0.1 1e-10 of the way from the pole on Ball's sphere), so it is
// taken a little inside; with the pole's normal there it read 0.059.
TEST(ScallopFront, CurvatureBesideAPoleIsTheSurfaces) {
  const double R = 10.0;
  const PatchGrid g = PatchGrid::from_face(test::face(BRepPrimAPI_MakeSphere(R).Shape(), 0), 0);
  for (double f : {1e-3, 1e-7, 1e-10, 0.0})
    for (double side : {g.vmin(), g.vmax()}) {
      const double u = g.umin() + 0.3 * (g.umax() - g.umin());
      const double v = side + (side == g.vmin() ? f : -f) * (g.vmax() - g.vmin());
      const gp_Vec n = g.normal(u, v);
      for (int k = 0; k < 8; ++k) {
        const double th = k * M_PI / 8;
        gp_Vec e1 = n.Crossed(std::fabs(n.X()) < 0.9 ? gp_Vec(1, 0, 0) : gp_Vec(0, 1, 0));
        e1.Normalize();
        const gp_Vec t = e1 * std::cos(th) + n.Crossed(e1) * std::sin(th);
        EXPECT_NEAR(normal_curvature(g, {u, v}, t), 1.0 / R, 1e-6 / R)
            << "v " << v << " direction " << k;
      }
    }
}

// A piece through the points (positions only).
FrontPiece piece_through(const std::vector<gp_Pnt>& pts) {
  FrontPiece pc;
  for (const gp_Pnt& p : pts) {
    FrontPoint x;
    x.p = p;
    pc.push_back(x);
  }
  return pc;
}

// The certificate climbs from the samples whose nearest point on the pieces
// kept ends one (ReachBorder::climb()): the index says which those are.
TEST(PathIndex, SaysWhenTheNearestPointEndsAPiece) {
  const auto piece = piece_through;
  PathIndex index(1.0);
  index.add(piece({gp_Pnt(0, 0, 0), gp_Pnt(1, 0, 0), gp_Pnt(2, 0, 0)}));
  index.add(piece({gp_Pnt(0, 2, 0), gp_Pnt(1, 2, 0)}));
  struct Case {
    gp_Pnt q;
    double d;
    bool end;
  };
  for (const Case& c :
       {Case{gp_Pnt(2.5, 0.1, 0), std::hypot(0.5, 0.1), true},
        Case{gp_Pnt(-0.3, 0, 0.4), 0.5, true}, Case{gp_Pnt(1.0, 0.3, 0), 0.3, false},
        Case{gp_Pnt(1.9, -0.2, 0), 0.2, false}, Case{gp_Pnt(1.3, 2.4, 0), 0.5, true},
        Case{gp_Pnt(0.5, 1.6, 0), 0.4, false}}) {
    bool end = !c.end;
    EXPECT_NEAR(index.distance(c.q, nullptr, 0.0, &end), c.d, 1e-12);
    EXPECT_EQ(end, c.end) << c.q.X() << " " << c.q.Y() << " " << c.q.Z();
  }
}

// The gap filling measures a sample's gap again only where a piece added
// since comes within it (PathIndex::within(), constant_scallop.cpp's
// Tracer::fill_gaps()): it must say so wherever some segment does, to the
// last rounding, and not elsewhere. Against a scan of every segment, the
// distance along the segment's line clamped to its ends (no code shared).
TEST(PathIndex, WithinAgreesWithAScanOfEverySegment) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> at(-3.0, 3.0), step(-0.4, 0.4), unit(0.0, 1.0);
  PathIndex index(0.7);
  std::vector<std::pair<gp_Pnt, gp_Pnt>> segs;
  for (int n = 0; n < 40; ++n) {
    std::vector<gp_Pnt> pts{gp_Pnt(at(rng), at(rng), at(rng))};
    for (int k = 0; k < 6; ++k)
      pts.push_back(pts.back().Translated(gp_Vec(step(rng), step(rng), step(rng))));
    index.add(piece_through(pts));
    for (std::size_t k = 1; k < pts.size(); ++k) segs.emplace_back(pts[k - 1], pts[k]);
  }
  int near = 0, far = 0;
  for (int n = 0; n < 3000; ++n) {
    const gp_Pnt p(at(rng), at(rng), at(rng));
    const double d = 1.2 * index.cell() * unit(rng);
    double best = 1e300;
    for (const auto& [a, b] : segs) {
      const gp_Vec ab(a, b);
      const double t = std::clamp(gp_Vec(a, p).Dot(ab) / ab.SquareMagnitude(), 0.0, 1.0);
      best = std::min(best, p.Distance(a.Translated(ab * t)));
    }
    if (std::abs(best - d) < 1e-9) continue;  // a tie: either answer
    EXPECT_EQ(index.within(p, d), best <= d) << "distance " << best << " d " << d;
    (best <= d ? near : far) += 1;
  }
  EXPECT_GT(near, 300);  // both answers are tested
  EXPECT_GT(far, 300);
}

TEST(ConstantScallop, OneAndManyThreadsGiveTheSamePathOnOneFace) {
  // One face: its paths are cut on the threads (constant_scallop.cpp,
  // cut_faces()); MAT leaves ground the ball does not reach from above, so
  // the reach border adds paths after them, its samples probed on the
  // threads and settled in order (ReachBorder::fill()).
  const TopoDS_Shape s = test::load("MAT.brep");
  IsoParams p = scallop_params(3.0, 0.05);
  p.safe_z = 400;
  p.threads = 1;
  const IsoResult one = adaptive_isocurve(s, {0}, p);
  p.threads = 3;
  const IsoResult three = adaptive_isocurve(s, {0}, p);
  EXPECT_GT(one.metrics.unreachable_length, 0.0);
  EXPECT_TRUE(test::same_path(one.path, three.path));
  EXPECT_EQ(one.metrics.guaranteed_scallop, three.metrics.guaranteed_scallop);
  EXPECT_DOUBLE_EQ(one.metrics.unreachable_length, three.metrics.unreachable_length);
}

}  // namespace
}  // namespace isocam
