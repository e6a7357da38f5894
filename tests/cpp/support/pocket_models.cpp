#include "support/pocket_models.h"

#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <GC_MakeArcOfEllipse.hxx>
#include <GC_MakeSegment.hxx>
#include <GeomAPI_Interpolate.hxx>
#include <Geom_BSplineCurve.hxx>
#include <Geom_BezierSurface.hxx>
#include <Geom_Plane.hxx>
#include <ShapeFix_Face.hxx>
#include <TColgp_Array2OfPnt.hxx>
#include <TColgp_HArray1OfPnt.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Wire.hxx>
#include <cmath>
#include <gp_Elips.hxx>
#include <gp_Pln.hxx>

namespace isocam::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

gp_Pnt pnt(P2 p) { return gp_Pnt(p.x, p.y, 0.0); }

TopoDS_Wire wire_of(const Loop& loop) {
  BRepBuilderAPI_MakeWire mw;
  for (const Seg& s : loop) {
    if (s.kind == SegKind::Line) {
      mw.Add(BRepBuilderAPI_MakeEdge(GC_MakeSegment(pnt(s.a), pnt(s.b)).Value()).Edge());
    } else {
      const P2 m = s.at(0.5);
      mw.Add(
          BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(pnt(s.a), pnt(m), pnt(s.b)).Value()).Edge());
    }
  }
  return mw.Wire();
}

// A B-spline interpolating `pts` (closed and periodic if `periodic`).
Handle(Geom_BSplineCurve) interpolate(const std::vector<gp_Pnt>& pts, bool periodic) {
  Handle(TColgp_HArray1OfPnt) arr = new TColgp_HArray1OfPnt(1, static_cast<int>(pts.size()));
  for (std::size_t i = 0; i < pts.size(); ++i) arr->SetValue(static_cast<int>(i) + 1, pts[i]);
  GeomAPI_Interpolate interp(arr, periodic, 1e-9);
  interp.Perform();
  return interp.Curve();
}

TopoDS_Wire blob_wire(double cx, double cy, double r, int lobes, double amp) {
  std::vector<gp_Pnt> pts;
  const int n = 8 * lobes + 8;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * i / n;
    const double rr = r * (1 + amp * std::sin(lobes * t));
    pts.emplace_back(cx + rr * std::cos(t), cy + rr * std::sin(t), 0);
  }
  return BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(interpolate(pts, true)).Edge()).Wire();
}

TopoDS_Face make_face(const TopoDS_Wire& outer, const std::vector<TopoDS_Wire>& holes) {
  BRepBuilderAPI_MakeFace mf(gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), outer, true);
  for (const TopoDS_Wire& w : holes) mf.Add(w);
  ShapeFix_Face fix(mf.Face());
  fix.FixOrientation();
  fix.Perform();
  return TopoDS::Face(fix.Face());
}

}  // namespace

Loop rect(double x0, double y0, double x1, double y1) {
  const P2 a{x0, y0}, b{x1, y0}, c{x1, y1}, d{x0, y1};
  return {Seg::line(a, b), Seg::line(b, c), Seg::line(c, d), Seg::line(d, a)};
}

Loop circle(double cx, double cy, double r, bool ccw) {
  const double s = ccw ? kPi : -kPi;
  Seg h1 = Seg::arc({cx, cy}, r, 0.0, s);
  Seg h2 = Seg::arc({cx, cy}, r, s, s);
  h2.a = h1.b;
  h2.b = h1.a;
  return {h1, h2};
}

Loop dumbbell(double side, double neck, double len) {
  const double y0 = 0.5 * (side - neck), y1 = 0.5 * (side + neck);
  const double x1 = side, x2 = side + len, x3 = 2 * side + len;
  const std::vector<P2> p{{0, 0},     {x1, 0},    {x1, y0}, {x2, y0}, {x2, 0},    {x3, 0},
                          {x3, side}, {x2, side}, {x2, y1}, {x1, y1}, {x1, side}, {0, side}};
  Loop l;
  for (std::size_t i = 0; i < p.size(); ++i) l.push_back(Seg::line(p[i], p[(i + 1) % p.size()]));
  return l;
}

Loop u_shape(double w, double h, double slot, double depth) {
  const double s0 = 0.5 * (w - slot), s1 = 0.5 * (w + slot);
  const std::vector<P2> p{{0, 0},          {w, 0},          {w, h},  {s1, h},
                          {s1, h - depth}, {s0, h - depth}, {s0, h}, {0, h}};
  Loop l;
  for (std::size_t i = 0; i < p.size(); ++i) l.push_back(Seg::line(p[i], p[(i + 1) % p.size()]));
  return l;
}

std::vector<Loop> random_region(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const int n = 7 + static_cast<int>(U(rng) * 6);
  std::vector<P2> v;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * kPi * (i + 0.3 * U(rng)) / n;
    const double r = 35 + 25 * U(rng);
    v.push_back({r * std::cos(t), r * std::sin(t)});
  }
  Loop outer;
  for (int i = 0; i < n; ++i) {
    const P2 a = v[static_cast<std::size_t>(i)], b = v[static_cast<std::size_t>((i + 1) % n)];
    if (U(rng) < 0.5) {
      outer.push_back(Seg::line(a, b));
      continue;
    }
    // An arc through a and b bulging out or in by up to 30% of the chord.
    const double chord = std::hypot(b.x - a.x, b.y - a.y);
    const double sag = (U(rng) - 0.4) * 0.6 * chord;
    if (std::abs(sag) < 0.02 * chord) {
      outer.push_back(Seg::line(a, b));
      continue;
    }
    const double half = 0.5 * chord;
    const double rad = (half * half + sag * sag) / (2 * std::abs(sag));
    const P2 m{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
    const P2 dir{(b.x - a.x) / chord, (b.y - a.y) / chord};
    const P2 right{dir.y, -dir.x};  // outward for a ccw loop
    const double off = rad - std::abs(sag);
    const double side = sag > 0 ? -1.0 : 1.0;  // centre opposite the bulge
    const P2 c{m.x + side * off * right.x, m.y + side * off * right.y};
    outer.push_back(Seg::arc_between(c, a, b, sag > 0));
  }
  std::vector<Loop> region{outer};
  const int islands = static_cast<int>(U(rng) * 4);
  for (int k = 0; k < islands; ++k) {
    const double cx = (U(rng) - 0.5) * 50, cy = (U(rng) - 0.5) * 50;
    if (U(rng) < 0.5) {
      region.push_back(circle(cx, cy, 3 + 8 * U(rng), false));
    } else {
      const double s = 3 + 6 * U(rng);
      region.push_back(reversed(rect(cx - s, cy - 0.7 * s, cx + s, cy + 0.7 * s)));
    }
  }
  return region;
}

TopoDS_Face face_with_islands(const std::vector<Loop>& loops) {
  std::vector<TopoDS_Wire> holes;
  for (std::size_t i = 1; i < loops.size(); ++i) holes.push_back(wire_of(loops[i]));
  return make_face(wire_of(loops[0]), holes);
}

TopoDS_Face bspline_blob_face(double cx, double cy, double r, int lobes, double amp) {
  return make_face(blob_wire(cx, cy, r, lobes, amp), {});
}

TopoDS_Face bspline_islands_face() {
  return make_face(wire_of(rect(0, 0, 160, 100)),
                   {blob_wire(45, 50, 18, 3, 0.25), blob_wire(115, 48, 20, 5, 0.15)});
}

TopoDS_Face bspline_boundary_face() {
  // Four wavy B-spline sides between the corners of a 150 x 110 box.
  const std::vector<gp_Pnt> corner{{0, 0, 0}, {150, 0, 0}, {150, 110, 0}, {0, 110, 0}};
  BRepBuilderAPI_MakeWire mw;
  for (int k = 0; k < 4; ++k) {
    const gp_Pnt a = corner[static_cast<std::size_t>(k)],
                 b = corner[static_cast<std::size_t>((k + 1) % 4)];
    const gp_Vec d(a, b);
    const gp_Vec out(d.Y(), -d.X(), 0);  // outward for a ccw loop
    std::vector<gp_Pnt> pts;
    for (int i = 0; i <= 6; ++i) {
      const double t = i / 6.0;
      const double bump = 0.08 * std::sin(kPi * t) * std::sin(3 * kPi * t + k);
      pts.push_back(a.Translated(t * d + bump * out));
    }
    mw.Add(BRepBuilderAPI_MakeEdge(interpolate(pts, false)).Edge());
  }
  return make_face(mw.Wire(), {wire_of(reversed(circle(75, 55, 12, true)))});
}

namespace {

TopoDS_Edge seg_edge(gp_Pnt a, gp_Pnt b) {
  return BRepBuilderAPI_MakeEdge(GC_MakeSegment(a, b).Value()).Edge();
}

TopoDS_Edge arc_edge(gp_Pnt a, gp_Pnt c, gp_Pnt b) {
  // The arc about c from a to b, counter-clockwise (through the bisector).
  const double t0 = std::atan2(a.Y() - c.Y(), a.X() - c.X());
  double t1 = std::atan2(b.Y() - c.Y(), b.X() - c.X());
  while (t1 <= t0) t1 += 2 * kPi;
  const double r = a.Distance(c), tm = 0.5 * (t0 + t1);
  const gp_Pnt m(c.X() + r * std::cos(tm), c.Y() + r * std::sin(tm), 0);
  return BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(a, m, b).Value()).Edge();
}

// A B-spline from a to b through a wave of amplitude `amp` to the left.
TopoDS_Edge wave_edge(gp_Pnt a, gp_Pnt b, double amp, double waves) {
  const gp_Vec d(a, b);
  const gp_Vec left(-d.Y(), d.X(), 0);
  std::vector<gp_Pnt> pts;
  for (int i = 0; i <= 8; ++i) {
    const double t = i / 8.0;
    pts.push_back(a.Translated(t * d + amp * std::sin(kPi * t) * std::sin(waves * kPi * t) /
                                           d.Magnitude() * left));
  }
  return BRepBuilderAPI_MakeEdge(interpolate(pts, false)).Edge();
}

}  // namespace

TopoDS_Face case_study_outline() {
  BRepBuilderAPI_MakeWire outer;  // twelve curves, counter-clockwise
  outer.Add(seg_edge({20, 0, 0}, {120, 0, 0}));
  outer.Add(wave_edge({120, 0, 0}, {180, 0, 0}, 6, 2));
  outer.Add(arc_edge({180, 0, 0}, {180, 20, 0}, {200, 20, 0}));
  outer.Add(seg_edge({200, 20, 0}, {200, 120, 0}));
  outer.Add(wave_edge({200, 120, 0}, {200, 180, 0}, -8, 1));
  outer.Add(arc_edge({200, 180, 0}, {180, 180, 0}, {180, 200, 0}));
  outer.Add(wave_edge({180, 200, 0}, {60, 200, 0}, 5, 3));
  outer.Add(seg_edge({60, 200, 0}, {20, 200, 0}));
  outer.Add(arc_edge({20, 200, 0}, {20, 180, 0}, {0, 180, 0}));
  outer.Add(seg_edge({0, 180, 0}, {0, 100, 0}));
  const gp_Elips el(gp_Ax2(gp_Pnt(0, 60, 0), gp_Dir(0, 0, 1), gp_Dir(0, 1, 0)), 40, 15);
  outer.Add(BRepBuilderAPI_MakeEdge(
                GC_MakeArcOfEllipse(el, gp_Pnt(0, 100, 0), gp_Pnt(0, 20, 0), true).Value())
                .Edge());
  outer.Add(arc_edge({0, 20, 0}, {20, 20, 0}, {20, 0, 0}));
  BRepBuilderAPI_MakeWire island;  // eight curves
  island.Add(seg_edge({80, 80, 0}, {120, 80, 0}));
  island.Add(arc_edge({120, 80, 0}, {120, 90, 0}, {130, 90, 0}));
  island.Add(seg_edge({130, 90, 0}, {130, 110, 0}));
  island.Add(wave_edge({130, 110, 0}, {115, 125, 0}, 3, 1));
  island.Add(seg_edge({115, 125, 0}, {95, 125, 0}));
  island.Add(arc_edge({95, 125, 0}, {95, 100, 0}, {70, 100, 0}));
  island.Add(wave_edge({70, 100, 0}, {70, 90, 0}, 2, 1));
  island.Add(arc_edge({70, 90, 0}, {80, 90, 0}, {80, 80, 0}));
  return make_face(outer.Wire(), {island.Wire()});
}

namespace {
double bezier_z(int i, int j) {
  // Convex dome: 0 on the corners, higher inside.
  static const double z[4][4] = {
      {0, 10, 10, 0}, {10, 30, 30, 10}, {10, 30, 30, 10}, {0, 10, 10, 0}};
  return z[i][j];
}
}  // namespace

TopoDS_Face case_study_floor() {
  TColgp_Array2OfPnt poles(1, 4, 1, 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      poles.SetValue(i + 1, j + 1, gp_Pnt(-20 + 80 * i, -20 + 80 * j, bezier_z(i, j)));
  Handle(Geom_BezierSurface) s = new Geom_BezierSurface(poles);
  return BRepBuilderAPI_MakeFace(s, 1e-7).Face();
}

double case_study_floor_z(double x, double y) {
  const double u = (x + 20) / 240, v = (y + 20) / 240;
  auto b = [](int k, double t) {
    const double c[4] = {1, 3, 3, 1};
    return c[k] * std::pow(t, k) * std::pow(1 - t, 3 - k);
  };
  double z = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) z += b(i, u) * b(j, v) * bezier_z(i, j);
  return z;
}

}  // namespace isocam::test
