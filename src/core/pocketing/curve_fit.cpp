// From the B-rep to line/arc profiles in the XY plane.
//
// Lines stay lines and circles in a horizontal plane stay arcs (exact).
// Every other curve -- ellipses, B-splines, Bezier curves, tilted circles,
// offset curves -- is projected on XY and replaced by a chain of arcs (and
// lines where it is straight) through points of the curve: greedily the
// longest arc through the curve's points at t0, (t0+t1)/2 and t1 whose
// distance to the curve stays within `tolerance` at all check points.
// Check points come from GCPnts_QuasiUniformDeflection at tolerance / 20,
// plus the midpoints between them, so the chain is within the tolerance of
// the projected curve up to that sampling. Arcs are what Suh & Lee's
// offsets of free curves are approximated by too (section 2.1); here the
// approximation is done once, before offsetting, and since offsetting a
// region moves its boundary by at most the boundary's own displacement,
// every offset stays within `tolerance` of the true offset.
#include "pocketing/curve_fit.h"

#include <BRepAdaptor_Curve.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <GCPnts_QuasiUniformDeflection.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <cmath>
#include <gp_Circ.hxx>

#include "isocam/errors.h"

namespace isocam::pocket {
namespace {

P2 xy(const gp_Pnt& p) { return {p.X(), p.Y()}; }

// The arc through three points, or a line when they are (nearly) collinear.
bool arc_through(P2 a, P2 m, P2 b, Seg& out) {
  const double d = 2.0 * cross(m - a, b - a);
  const double chord = dist(a, b);
  if (std::abs(d) <= 1e-9 * chord * chord || chord <= 0) {
    out = Seg::line(a, b);
    return true;
  }
  const double a2 = dot(a, a), m2 = dot(m, m), b2 = dot(b, b);
  const P2 c{(a2 * (m.y - b.y) + m2 * (b.y - a.y) + b2 * (a.y - m.y)) / d,
             (a2 * (b.x - m.x) + m2 * (a.x - b.x) + b2 * (m.x - a.x)) / d};
  const double r = dist(a, c);
  if (r > 1e4 * chord) {  // practically straight
    out = Seg::line(a, b);
    return true;
  }
  // A counter-clockwise arc bulges to the right of its chord a->b.
  out = Seg::arc_between(c, a, b, cross(b - a, m - a) < 0);
  return true;
}

// Greedy arc fit of the parameter range [u0, u1] of curve `c` (projected).
void fit_free_curve(const BRepAdaptor_Curve& c, double u0, double u1, double tol, Loop& out) {
  GCPnts_QuasiUniformDeflection sampler(c, 0.05 * tol, u0, u1);
  std::vector<double> us;
  if (sampler.IsDone() && sampler.NbPoints() >= 2) {
    for (int i = 1; i <= sampler.NbPoints(); ++i) us.push_back(sampler.Parameter(i));
  } else {
    for (int i = 0; i <= 64; ++i) us.push_back(u0 + (u1 - u0) * i / 64.0);
  }
  if (us.front() > us.back()) std::reverse(us.begin(), us.end());
  std::vector<P2> pts(us.size());
  for (std::size_t i = 0; i < us.size(); ++i) pts[i] = xy(c.Value(us[i]));
  std::vector<P2> mids(us.size());
  for (std::size_t i = 0; i + 1 < us.size(); ++i) mids[i] = xy(c.Value(0.5 * (us[i] + us[i + 1])));
  auto fits = [&](std::size_t i, std::size_t j, Seg& s) {
    const P2 m = xy(c.Value(0.5 * (us[i] + us[j])));
    arc_through(pts[i], m, pts[j], s);
    if (s.kind == SegKind::Arc && std::abs(s.sweep) > 1.5 * kPi) return false;
    for (std::size_t k = i; k < j; ++k) {
      if (k > i && nearest_on_seg(s, pts[k]).d > tol) return false;
      if (nearest_on_seg(s, mids[k]).d > tol) return false;
    }
    return true;
  };
  std::size_t i = 0;
  const std::size_t last = us.size() - 1;
  while (i < last) {
    // Exponential then binary search for the farthest end that fits.
    Seg best = Seg::line(pts[i], pts[i + 1]);
    std::size_t good = i + 1, step = 1, bad = last + 1;
    Seg s;
    while (good < last) {
      const std::size_t j = std::min(last, good + step);
      if (fits(i, j, s)) {
        good = j;
        best = s;
        step *= 2;
      } else {
        bad = j;
        break;
      }
    }
    while (bad - good > 1) {
      const std::size_t j = (good + bad) / 2;
      if (fits(i, j, s)) {
        good = j;
        best = s;
      } else {
        bad = j;
      }
    }
    best.a = pts[i];
    best.b = pts[good];
    out.push_back(best);
    i = good;
  }
}

bool horizontal_circle(const BRepAdaptor_Curve& c, gp_Circ& circ) {
  if (c.GetType() != GeomAbs_Circle) return false;
  circ = c.Circle();
  return std::abs(std::abs(circ.Axis().Direction().Z()) - 1.0) < 1e-9;
}

}  // namespace

void append_edge(const TopoDS_Edge& edge, double tol, Loop& out) {
  if (BRep_Tool::Degenerated(edge)) return;
  BRepAdaptor_Curve c(edge);
  double u0 = c.FirstParameter(), u1 = c.LastParameter();
  const bool rev = edge.Orientation() == TopAbs_REVERSED;
  Loop piece;
  gp_Circ circ;
  if (c.GetType() == GeomAbs_Line) {
    piece.push_back(Seg::line(xy(c.Value(u0)), xy(c.Value(u1))));
  } else if (horizontal_circle(c, circ)) {
    // Angles in the circle's frame turn counter-clockwise in XY when its
    // axis points up, clockwise when down.
    const double sgn = circ.Axis().Direction().Z() > 0 ? 1.0 : -1.0;
    const P2 ctr = xy(circ.Location());
    const P2 a = xy(c.Value(u0)), b = xy(c.Value(u1));
    Seg s = Seg::arc(ctr, circ.Radius(), angle_of(a - ctr), sgn * (u1 - u0));
    s.a = a;
    s.b = b;
    piece.push_back(s);
  } else {
    fit_free_curve(c, u0, u1, tol, piece);
  }
  if (rev) piece = reversed(piece);
  for (Seg& s : piece) {
    if (!out.empty()) s.a = out.back().b;  // exact chaining
    if (s.length() > 0) out.push_back(s);
  }
}

Loop loop_of_wire(const TopoDS_Wire& wire, const TopoDS_Face* face, double tol) {
  Loop loop;
  try {
    if (face) {
      for (BRepTools_WireExplorer ex(wire, *face); ex.More(); ex.Next())
        append_edge(ex.Current(), tol, loop);
    } else {
      for (BRepTools_WireExplorer ex(wire); ex.More(); ex.Next())
        append_edge(ex.Current(), tol, loop);
    }
  } catch (const Standard_Failure& e) {
    throw GeometryError(std::string("pocketing: cannot read a wire (") + e.GetMessageString() +
                        ")");
  }
  if (loop.empty()) return loop;
  // Close the chain exactly (the gap is the wire's own tolerance).
  loop.back().b = loop.front().a;
  return loop;
}

}  // namespace isocam::pocket

namespace isocam {

using namespace pocket;

std::vector<Loop> face_region(const TopoDS_Shape& shape, double tol) {
  if (!(tol > 0)) throw InvalidArgument("tolerance must be > 0");
  if (shape.ShapeType() != TopAbs_FACE)
    throw InvalidArgument("face_region: the shape is not a face");
  const TopoDS_Face face = TopoDS::Face(shape);
  const TopoDS_Wire outer = BRepTools::OuterWire(face);
  std::vector<Loop> region;
  Loop boundary = loop_of_wire(outer, &face, tol);
  if (boundary.empty()) return region;
  region.push_back(signed_area(boundary) >= 0 ? boundary : reversed(boundary));
  for (TopExp_Explorer ex(face, TopAbs_WIRE); ex.More(); ex.Next()) {
    const TopoDS_Wire w = TopoDS::Wire(ex.Current());
    if (w.IsSame(outer)) continue;
    Loop island = loop_of_wire(w, &face, tol);
    if (island.empty() || std::abs(signed_area(island)) <= 0) continue;
    region.push_back(signed_area(island) <= 0 ? island : reversed(island));
  }
  return region;
}

}  // namespace isocam
