#include "geometry/trim_domain.h"

#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dAdaptor_Curve.hxx>
#include <Geom2dConvert.hxx>
#include <Geom2dConvert_BSplineCurveToBezierCurve.hxx>
#include <Geom2dHatch_Hatcher.hxx>
#include <Geom2dHatch_Intersector.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_BezierCurve.hxx>
#include <Geom2d_Conic.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <HatchGen_Domain.hxx>
#include <Precision.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <gp_Dir2d.hxx>
#include <gp_Pnt2d.hxx>
#include <string>

#include "isocam/errors.h"

namespace isocam {
namespace {
constexpr int kMaxSpanDegree = 25;
std::string label(int face) {
  return "face " + std::to_string(face) + " (Face" + std::to_string(face + 1) + ")";
}
// The classifier's answer for a point as the class of a rectangle around it
// that no boundary meets (ON: undecided).
TrimDomain::RectClass rect_class(TopAbs_State st) {
  return st == TopAbs_IN    ? TrimDomain::RectClass::Inside
         : st == TopAbs_OUT ? TrimDomain::RectClass::Outside
                            : TrimDomain::RectClass::Boundary;
}
// The largest distance from an edge's end to the nearest unused edge start
// (each start used once), or -1 if the counts differ: 0 for loops that
// close exactly.
double loop_gap(const std::vector<std::array<double, 4>>& ends) {
  std::vector<bool> used(ends.size(), false);
  double gap = 0;
  for (const auto& e : ends) {
    double best = 1e300;
    std::size_t at = ends.size();
    for (std::size_t k = 0; k < ends.size(); ++k) {
      if (used[k]) continue;
      const double d = std::hypot(ends[k][0] - e[2], ends[k][1] - e[3]);
      if (d < best) {
        best = d;
        at = k;
      }
    }
    if (at == ends.size()) return -1.0;
    used[at] = true;
    gap = std::max(gap, best);
  }
  return gap;
}
}  // namespace

// The domain is read from the face oriented FORWARD: exploring a REVERSED
// face reverses its edges too, which would turn the domain inside out in the
// surface's own parameter plane.
TrimDomain::TrimDomain(const TopoDS_Face& face, const PatchGrid& grid, int face_label)
    : face_(TopoDS::Face(face.Oriented(TopAbs_FORWARD))),
      surface_(BRep_Tool::Surface(face)),
      grid_(&grid),
      label_(face_label) {
  std::vector<std::array<double, 4>> edge_ends;  // oriented start (x, y), end (x, y)
  idle_classifiers_.push_back(std::make_unique<BRepTopAdaptor_FClass2d>(face_, 1e-9));
  BRepTools::UVBounds(face_, fmin_[0], fmax_[0], fmin_[1], fmax_[1]);
  const double range = std::max(fmax_[0] - fmin_[0], fmax_[1] - fmin_[1]);
  hatcher_ = std::make_unique<Geom2dHatch_Hatcher>(
      Geom2dHatch_Intersector(Precision::PConfusion(), Precision::PConfusion()), 1e-10 * range,
      1e-8 * grid.size(), true, true);
  for (TopExp_Explorer ex(face_, TopAbs_EDGE); ex.More(); ex.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(ex.Current());
    double f, l;
    Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(edge, face_, f, l);
    if (pc.IsNull()) throw GeometryError(label(face_label) + ": an edge has no p-curve");
    if (std::abs(l - f) <= Precision::PConfusion()) continue;
    hatcher_->AddElement(Geom2dAdaptor_Curve(new Geom2d_TrimmedCurve(pc, f, l)),
                         edge.Orientation());
    add_boundary_boxes(*pc, f, l, range);
    // An internal or external edge is no part of a loop around the face.
    const int sign = edge.Orientation() == TopAbs_FORWARD    ? 1
                     : edge.Orientation() == TopAbs_REVERSED ? -1
                                                             : 0;
    if (!add_spans(pc, f, l, sign)) spans_exact_ = false;
    if (sign != 0) {
      gp_Pnt2d a = pc->Value(f), b = pc->Value(l);
      if (sign < 0) std::swap(a, b);
      edge_ends.push_back({a.X(), a.Y(), b.X(), b.Y()});
    }
  }
  // The winding number needs closed loops: each edge's end meets another's
  // start. The largest gap (and rounding between a B-spline's Bezier arcs)
  // bounds where a ray could slip between two.
  const double gap = spans_exact_ ? loop_gap(edge_ends) : -1.0;
  winding_ok_ = gap >= 0 && gap <= 1e-3 * range;
  join_gap_ = 2.0 * std::max(gap, 1e-9 * range);
  on_tol_ = 1e-9 * range;
  if (winding_ok_) {
    for (const Span2& sp : spans_) {
      const double* c = &span_cps_[sp.first];
      const int n = sp.degree;
      joins_.push_back({c[0] / c[2], c[1] / c[2]});
      joins_.push_back({c[3 * n] / c[3 * n + 2], c[3 * n + 1] / c[3 * n + 2]});
    }
  }
  quad_.push_back({{fmin_[0] - 1e-9 * range, fmin_[1] - 1e-9 * range},
                   {fmax_[0] + 1e-9 * range, fmax_[1] + 1e-9 * range},
                   RectClass::Boundary,
                   -1});
  std::vector<int> all(boundary_.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  build_quadtree(0, all, 0);
  if (!grid.same_params_as_face()) {
    // Tabulate the monotone maps; the margin is twice the largest
    // interpolation error seen at the midpoints. In a periodic direction the
    // projection may answer a seam point with either end of the period:
    // each value is taken in the period nearest its neighbour's.
    const int n = 128;
    for (int dir = 0; dir < 2; ++dir) {
      const bool periodic = dir == 0 ? surface_->IsUPeriodic() : surface_->IsVPeriodic();
      const double period = periodic ? (dir == 0 ? surface_->UPeriod() : surface_->VPeriod()) : 0.0;
      auto near = [periodic, period](double f, double ref) {
        return periodic ? f + period * std::round((ref - f) / period) : f;
      };
      const double g0 = dir == 0 ? grid.umin() : grid.vmin();
      const double g1 = dir == 0 ? grid.umax() : grid.vmax();
      // Start from the middle, where no seam is.
      const double fmid = to_face(dir, 0.5 * (g0 + g1));
      std::vector<double> f(static_cast<std::size_t>(n) + 1);
      f[static_cast<std::size_t>(n / 2)] = near(to_face(dir, g0 + (g1 - g0) * (n / 2) / n), fmid);
      for (int k = n / 2 + 1; k <= n; ++k)
        f[static_cast<std::size_t>(k)] =
            near(to_face(dir, g0 + (g1 - g0) * k / n), f[static_cast<std::size_t>(k) - 1]);
      for (int k = n / 2 - 1; k >= 0; --k)
        f[static_cast<std::size_t>(k)] =
            near(to_face(dir, g0 + (g1 - g0) * k / n), f[static_cast<std::size_t>(k) + 1]);
      double err = 0;
      for (int k = 0; k <= n; ++k) {
        table_g_[dir].push_back(g0 + (g1 - g0) * k / n);
        table_f_[dir].push_back(f[static_cast<std::size_t>(k)]);
        if (k > 0) {
          const double gm = g0 + (g1 - g0) * (k - 0.5) / n;
          const double lin =
              0.5 * (f[static_cast<std::size_t>(k)] + f[static_cast<std::size_t>(k) - 1]);
          err = std::max(err, std::abs(near(to_face(dir, gm), lin) - lin));
        }
      }
      table_margin_[dir] = 2.0 * err + 1e-9 * range;
      // A map that is affine (a plane's, an extrusion's along its
      // direction) to within 1e-10 of the range at every tabulated point
      // and midpoint is taken as such: to_face() then needs no projection
      // (which near the edges is most of the work of contains()).
      const double a = (f.back() - f.front()) / (g1 - g0), b = f.front() - a * g0;
      double off = err;
      for (int k = 0; k <= n; ++k)
        off = std::max(off, std::abs(f[static_cast<std::size_t>(k)] -
                                     (a * table_g_[dir][static_cast<std::size_t>(k)] + b)));
      if (off <= 1e-10 * range) affine_[dir] = {a, b};
    }
  }
}

void TrimDomain::add_boundary_boxes(const Geom2d_Curve& pc, double f, double l, double range) {
  // 32 chords per edge; each box grows by twice the chord's sagitta at its
  // middle (the p-curves are smooth) so that it holds the curve.
  const int n = 32;
  gp_Pnt2d a = pc.Value(f);
  for (int k = 1; k <= n; ++k) {
    const double ta = f + (l - f) * (k - 1) / n, tb = f + (l - f) * k / n;
    const gp_Pnt2d b = pc.Value(tb), m = pc.Value(0.5 * (ta + tb));
    const double sag =
        2.0 * m.Distance(gp_Pnt2d(0.5 * (a.X() + b.X()), 0.5 * (a.Y() + b.Y()))) + 1e-9 * range;
    boundary_.push_back({{std::min(a.X(), b.X()) - sag, std::min(a.Y(), b.Y()) - sag},
                         {std::max(a.X(), b.X()) + sag, std::max(a.Y(), b.Y()) + sag}});
    a = b;
  }
}

bool TrimDomain::add_spans(const Handle(Geom2d_Curve) & pc, double f, double l, int sign) {
  Handle(Geom2d_Curve) basis = pc;
  if (auto t = Handle(Geom2d_TrimmedCurve)::DownCast(basis)) basis = t->BasisCurve();
  // Lines, conics, Bezier and B-spline curves have an exact (rational)
  // B-spline form; an offset curve has not.
  if (!basis->IsKind(STANDARD_TYPE(Geom2d_Line)) && !basis->IsKind(STANDARD_TYPE(Geom2d_Conic)) &&
      !basis->IsKind(STANDARD_TYPE(Geom2d_BezierCurve)) &&
      !basis->IsKind(STANDARD_TYPE(Geom2d_BSplineCurve)))
    return false;
  Handle(Geom2d_BSplineCurve) bs;
  try {
    bs = Geom2dConvert::CurveToBSplineCurve(new Geom2d_TrimmedCurve(pc, f, l));
  } catch (const Standard_Failure&) {
    return false;
  }
  if (bs.IsNull()) return false;
  Geom2dConvert_BSplineCurveToBezierCurve arcs(bs);
  for (int i = 1; i <= arcs.NbArcs(); ++i) {
    const Handle(Geom2d_BezierCurve) arc = arcs.Arc(i);
    if (arc->Degree() > kMaxSpanDegree) return false;
    Span2 span;
    span.first = span_cps_.size();
    span.degree = arc->Degree();
    span.sign = sign;
    span.box = {{1e300, 1e300}, {-1e300, -1e300}};
    for (int k = 1; k <= arc->NbPoles(); ++k) {
      const gp_Pnt2d p = arc->Pole(k);
      const double w = arc->Weight(k);
      if (!(w > 0)) return false;
      span_cps_.insert(span_cps_.end(), {p.X() * w, p.Y() * w, w});
      span.box.lo[0] = std::min(span.box.lo[0], p.X());
      span.box.lo[1] = std::min(span.box.lo[1], p.Y());
      span.box.hi[0] = std::max(span.box.hi[0], p.X());
      span.box.hi[1] = std::max(span.box.hi[1], p.Y());
    }
    spans_.push_back(span);
  }
  return true;
}

namespace {

// The box of the span's projected control points (homogeneous, 3 each,
// degree n), which holds its curve: the weights are positive.
void hull_box(const double* c, int n, double lo[2], double hi[2]) {
  lo[0] = lo[1] = 1e300;
  hi[0] = hi[1] = -1e300;
  for (int k = 0; k <= n; ++k) {
    const double x = c[3 * k] / c[3 * k + 2], y = c[3 * k + 1] / c[3 * k + 2];
    lo[0] = std::min(lo[0], x);
    lo[1] = std::min(lo[1], y);
    hi[0] = std::max(hi[0], x);
    hi[1] = std::max(hi[1], y);
  }
}

// The halves [0, 1/2] and [1/2, 1] of the span (homogeneous control
// points, 3 each, degree n) by de Casteljau's construction; the two share
// their middle point to the bit.
void split_half(const double* c, int n, double* l, double* r) {
  double w[3 * (kMaxSpanDegree + 1)];
  std::copy(c, c + 3 * (n + 1), w);
  for (int j = 0; j < 3; ++j) {
    l[j] = w[j];
    r[3 * n + j] = w[3 * n + j];
  }
  for (int s = 1; s <= n; ++s) {
    for (int k = 0; k + s <= n; ++k)
      for (int j = 0; j < 3; ++j) w[3 * k + j] = 0.5 * (w[3 * k + j] + w[3 * (k + 1) + j]);
    for (int j = 0; j < 3; ++j) {
      l[3 * s + j] = w[j];
      r[3 * (n - s) + j] = w[3 * (n - s) + j];
    }
  }
}

// Where the rational Bezier span (homogeneous control points, 3 each,
// degree n) lies against the closed rectangle [lo, hi]: 1 it misses it, 0
// it meets it, -1 not decided. Its curve lies in the hull of its projected
// control points (the weights are positive) and passes through the end
// ones: a hull box that misses proves a miss, an end point inside proves a
// meet; otherwise the span is split at its middle. A straight span parallel
// to an axis is its own hull box: the box decides (a point on the side of
// a parameter rectangle, where halving would never prove the meet). `budget`
// bounds the boxes tested; when it runs out, or after 40 halvings, the
// answer is -1.
int span_meets(const double* c, int n, const double lo[2], const double hi[2], int depth,
               int* budget) {
  if (--*budget < 0) return -1;
  for (int k : {0, n}) {
    const double x = c[3 * k] / c[3 * k + 2], y = c[3 * k + 1] / c[3 * k + 2];
    if (x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1]) return 0;
  }
  double blo[2], bhi[2];
  hull_box(c, n, blo, bhi);
  if (blo[0] > hi[0] || bhi[0] < lo[0] || blo[1] > hi[1] || bhi[1] < lo[1]) return 1;
  if (n == 1 && (blo[0] == bhi[0] || blo[1] == bhi[1])) return 0;
  if (depth >= 40) return -1;
  double l[3 * (kMaxSpanDegree + 1)], r[3 * (kMaxSpanDegree + 1)];
  split_half(c, n, l, r);
  const int a = span_meets(l, n, lo, hi, depth + 1, budget);
  if (a == 0) return 0;
  const int b = span_meets(r, n, lo, hi, depth + 1, budget);
  return b == 0 ? 0 : std::min(a, b);
}

// The point (x, y) turned by `quarter` quarter turns clockwise: the ray
// towards +x of the turned plane is the ray towards +x, -y, -x, +y of the
// face's. A turn keeps winding numbers.
inline void turn(int quarter, double x, double y, double* tx, double* ty) {
  switch (quarter) {
    case 0:
      *tx = x, *ty = y;
      break;
    case 1:
      *tx = -y, *ty = x;
      break;
    case 2:
      *tx = -x, *ty = -y;
      break;
    default:
      *tx = y, *ty = -x;
      break;
  }
}

// The signed crossings of the ray from (px, py) towards +x of the plane
// turned by `quarter` (the point given turned) by the rational Bezier span
// (homogeneous control points, degree n): a crossing upwards +1, downwards
// -1, "up" meaning y > py (so a crossing is a change of that side, counted
// once where the curve touches the line). A span whose hull box lies right
// of the point crosses it as its end points' sides change; one left of it,
// above or below it, never; one whose box holds the point is halved. False
// (undecided) if the box still holds it after 48 halvings or when `budget`
// runs out.
bool span_crossings(const double* c, int n, int quarter, double px, double py, int depth,
                    int* budget, int* count) {
  if (--*budget < 0) return false;
  double blo[2] = {1e300, 1e300}, bhi[2] = {-1e300, -1e300}, ends[2] = {0, 0};
  for (int k = 0; k <= n; ++k) {
    double x, y;
    turn(quarter, c[3 * k] / c[3 * k + 2], c[3 * k + 1] / c[3 * k + 2], &x, &y);
    blo[0] = std::min(blo[0], x);
    blo[1] = std::min(blo[1], y);
    bhi[0] = std::max(bhi[0], x);
    bhi[1] = std::max(bhi[1], y);
    if (k == 0) ends[0] = y;
    if (k == n) ends[1] = y;
  }
  if (blo[1] > py || bhi[1] <= py || bhi[0] < px) return true;
  if (blo[0] > px) {
    *count += static_cast<int>(ends[1] > py) - static_cast<int>(ends[0] > py);
    return true;
  }
  if (depth >= 48) return false;
  double l[3 * (kMaxSpanDegree + 1)], r[3 * (kMaxSpanDegree + 1)];
  split_half(c, n, l, r);
  return span_crossings(l, n, quarter, px, py, depth + 1, budget, count) &&
         span_crossings(r, n, quarter, px, py, depth + 1, budget, count);
}

}  // namespace

int TrimDomain::curves_meet(const double lo[2], const double hi[2]) const {
  if (!spans_exact_) return -1;
  int budget = 4000, answer = 1;
  for (const Span2& s : spans_) {
    if (s.box.lo[0] > hi[0] || s.box.hi[0] < lo[0] || s.box.lo[1] > hi[1] || s.box.hi[1] < lo[1])
      continue;
    const int m = span_meets(&span_cps_[s.first], s.degree, lo, hi, 0, &budget);
    if (m == 0) return 0;
    answer = std::min(answer, m);
  }
  return answer;
}

int TrimDomain::winding_class(double fu, double fv) const {
  // On a p-curve to within the classifier's tolerance: on the boundary.
  const double lo[2] = {fu - on_tol_, fv - on_tol_}, hi[2] = {fu + on_tol_, fv + on_tol_};
  const int meets = curves_meet(lo, hi);
  if (meets == 0) return 2;
  if (meets < 0) return -1;
  // A ray through a join's gap could miss the crossing there: the first of
  // the four axis rays that passes no join closer than the gap.
  for (int quarter = 0; quarter < 4; ++quarter) {
    double px, py;
    turn(quarter, fu, fv, &px, &py);
    bool clear = true;
    for (const auto& j : joins_) {
      double jx, jy;
      turn(quarter, j[0], j[1], &jx, &jy);
      if (std::abs(jy - py) <= join_gap_ && jx + join_gap_ >= px) {
        clear = false;
        break;
      }
    }
    if (!clear) continue;
    int budget = 4000, total = 0;
    for (const Span2& s : spans_) {
      if (s.sign == 0) continue;
      double ax, ay, bx, by;  // the box's corners turned
      turn(quarter, s.box.lo[0], s.box.lo[1], &ax, &ay);
      turn(quarter, s.box.hi[0], s.box.hi[1], &bx, &by);
      if (std::min(ay, by) > py || std::max(ay, by) <= py || std::max(ax, bx) < px) continue;
      int count = 0;
      if (!span_crossings(&span_cps_[s.first], s.degree, quarter, px, py, 0, &budget, &count))
        return -1;
      total += s.sign * count;
    }
    return total == 0 || total == 1 ? total : -1;
  }
  return -1;
}

TopAbs_State TrimDomain::point_state(double fu, double fv) const {
  const int w = winding_ok_ ? winding_class(fu, fv) : -1;
  if (w >= 0) return w == 1 ? TopAbs_IN : w == 0 ? TopAbs_OUT : TopAbs_ON;
  return classify_point(fu, fv);
}

double TrimDomain::face_approx(int dir, double g) const {
  if (grid_->same_params_as_face()) return g;
  const auto& tg = table_g_[dir];
  const auto& tf = table_f_[dir];
  const std::size_t k = static_cast<std::size_t>(
      std::clamp<std::ptrdiff_t>(std::upper_bound(tg.begin(), tg.end(), g) - tg.begin(), 1,
                                 static_cast<std::ptrdiff_t>(tg.size()) - 1));
  const double s = (g - tg[k - 1]) / (tg[k] - tg[k - 1]);
  return tf[k - 1] + s * (tf[k] - tf[k - 1]);
}

void TrimDomain::build_quadtree(int node, const std::vector<int>& boxes, int depth) {
  std::vector<int> here;
  for (int b : boxes)
    if (boundary_[static_cast<std::size_t>(b)].meets(quad_[static_cast<std::size_t>(node)].lo,
                                                     quad_[static_cast<std::size_t>(node)].hi))
      here.push_back(b);
  QuadNode& n = quad_[static_cast<std::size_t>(node)];
  if (here.empty()) {
    const double c[2] = {0.5 * (n.lo[0] + n.hi[0]), 0.5 * (n.lo[1] + n.hi[1])};
    const TopAbs_State st = classify_point(c[0], c[1]);
    n.state = rect_class(st);
    // The winding number must agree with the classifier wherever both
    // decide (a wire not closed in the plane, an orientation taken the
    // other way, would show here): else it is not used on this face.
    const int w = winding_ok_ ? winding_class(c[0], c[1]) : -1;
    if ((w == 0 || w == 1) && st != TopAbs_ON && (w == 1) != (st == TopAbs_IN)) winding_ok_ = false;
    return;
  }
  if (depth >= 9) return;  // undecided leaf along the boundary
  const double mid[2] = {0.5 * (n.lo[0] + n.hi[0]), 0.5 * (n.lo[1] + n.hi[1])};
  const double lo[2] = {n.lo[0], n.lo[1]}, hi[2] = {n.hi[0], n.hi[1]};
  n.first_child = static_cast<int>(quad_.size());
  for (int k = 0; k < 4; ++k) {
    QuadNode c;
    c.lo[0] = k & 1 ? mid[0] : lo[0];
    c.hi[0] = k & 1 ? hi[0] : mid[0];
    c.lo[1] = k & 2 ? mid[1] : lo[1];
    c.hi[1] = k & 2 ? hi[1] : mid[1];
    quad_.push_back(c);
  }
  const int first = quad_[static_cast<std::size_t>(node)].first_child;
  for (int k = 0; k < 4; ++k) build_quadtree(first + k, here, depth + 1);
}

// The class all the leaves that meet [lo, hi] agree on, Boundary if they do
// not; Outside if none meets it.
TrimDomain::RectClass TrimDomain::query_quadtree(int node, const double lo[2],
                                                 const double hi[2]) const {
  const QuadNode& n = quad_[static_cast<std::size_t>(node)];
  if (n.leaf()) return n.state;
  bool seen = false;
  RectClass state = RectClass::Outside;
  for (int k = 0; k < 4; ++k) {
    const QuadNode& c = quad_[static_cast<std::size_t>(n.first_child + k)];
    if (c.lo[0] > hi[0] || c.hi[0] < lo[0] || c.lo[1] > hi[1] || c.hi[1] < lo[1]) continue;
    const RectClass s = query_quadtree(n.first_child + k, lo, hi);
    if (s == RectClass::Boundary) return s;
    if (!seen) {
      seen = true;
      state = s;
    } else if (state != s) {
      return RectClass::Boundary;
    }
  }
  return state;
}

std::size_t TrimDomain::RectHash::operator()(const RectKey& k) const {
  std::size_t h = 1469598103934665603ull + static_cast<std::size_t>(k.kind);
  for (double x : k.c) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
    h ^= h >> 29;
  }
  return h;
}

template <class Decide>
int TrimDomain::cached(bool use, const RectKey& key, Decide decide) const {
  if (!use) return decide();
  CacheShard& shard = (*cache_)[RectHash()(key) % kCacheShards];
  {
    const std::lock_guard<std::mutex> guard(shard.lock);
    const auto it = shard.answers.find(key);
    if (it != shard.answers.end()) return it->second;
  }
  const int answer = decide();  // the same on every thread: no race on what is stored
  const std::lock_guard<std::mutex> guard(shard.lock);
  if (shard.answers.size() >= 8192) shard.answers.clear();  // at most 128k answers a face
  shard.answers.emplace(key, answer);
  return answer;
}

TrimDomain::RectClass TrimDomain::classify_rect(double u0, double u1, double v0, double v1,
                                                bool cache) const {
  double lo[2] = {face_approx(0, u0), face_approx(1, v0)};
  double hi[2] = {face_approx(0, u1), face_approx(1, v1)};
  for (int d = 0; d < 2; ++d) {
    if (lo[d] > hi[d]) std::swap(lo[d], hi[d]);
    lo[d] -= table_margin_[d];
    hi[d] += table_margin_[d];
  }
  // Outside the face's parameter rectangle there is no face.
  if (hi[0] < quad_[0].lo[0] || lo[0] > quad_[0].hi[0] || hi[1] < quad_[0].lo[1] ||
      lo[1] > quad_[0].hi[1])
    return RectClass::Outside;
  const bool within = lo[0] >= quad_[0].lo[0] && hi[0] <= quad_[0].hi[0] &&
                      lo[1] >= quad_[0].lo[1] && hi[1] <= quad_[0].hi[1];
  const RectClass s = query_quadtree(0, lo, hi);
  if (s == RectClass::Outside || (s == RectClass::Inside && within)) return s;
  // Along the boundary the quadtree stops at cells 1/512 of the range wide:
  // below that, a rectangle that no p-curve meets lies wholly on one side,
  // which its centre tells.
  // The cache keeps ints (contains() stores 0/1 there): the RectClass
  // values.
  return static_cast<RectClass>(cached(cache, {{u0, u1, v0, v1}, 0}, [&] {
    if (curves_meet(lo, hi) != 1) return static_cast<int>(RectClass::Boundary);
    return static_cast<int>(rect_class(point_state(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]))));
  }));
}

TopAbs_State TrimDomain::classify_point(double fu, double fv) const {
  std::unique_ptr<BRepTopAdaptor_FClass2d> classifier;
  {
    const std::lock_guard<std::mutex> guard(*classifiers_lock_);
    if (!idle_classifiers_.empty()) {
      classifier = std::move(idle_classifiers_.back());
      idle_classifiers_.pop_back();
    }
  }
  if (!classifier) classifier = std::make_unique<BRepTopAdaptor_FClass2d>(face_, 1e-9);
  const TopAbs_State state = classifier->Perform(gp_Pnt2d(fu, fv));
  const std::lock_guard<std::mutex> guard(*classifiers_lock_);
  idle_classifiers_.push_back(std::move(classifier));
  return state;
}

TrimDomain::~TrimDomain() = default;
TrimDomain::TrimDomain(TrimDomain&&) noexcept = default;
TrimDomain& TrimDomain::operator=(TrimDomain&&) noexcept = default;

double TrimDomain::to_face(int dir, double g) const {
  if (grid_->same_params_as_face()) return g;
  if (affine_[dir]) return affine_[dir]->first * g + affine_[dir]->second;
  // The NURBS form of an analytic surface maps each parameter on its own:
  // project a grid point onto the face's surface and read one coordinate.
  const double other =
      dir == 0 ? 0.5 * (grid_->vmin() + grid_->vmax()) : 0.5 * (grid_->umin() + grid_->umax());
  const gp_Pnt p = dir == 0 ? grid_->eval(g, other) : grid_->eval(other, g);
  GeomAPI_ProjectPointOnSurf proj(p, surface_, fmin_[0] - 1e-9, fmax_[0] + 1e-9, fmin_[1] - 1e-9,
                                  fmax_[1] + 1e-9);
  if (proj.NbPoints() == 0)
    throw GeometryError(label(label_) + ": cannot map its NURBS parameters back to the face");
  double fu, fv;
  proj.LowerDistanceParameters(fu, fv);
  return dir == 0 ? fu : fv;
}

double TrimDomain::to_grid(int dir, double f) const {
  if (grid_->same_params_as_face()) return f;
  double lo = dir == 0 ? grid_->umin() : grid_->vmin();
  double hi = dir == 0 ? grid_->umax() : grid_->vmax();
  const bool rising = to_face(dir, hi) >= to_face(dir, lo);
  for (int it = 0; it < 60 && hi - lo > 1e-13 * (1 + std::abs(hi)); ++it) {
    const double m = 0.5 * (lo + hi);
    if ((to_face(dir, m) < f) == rising)
      lo = m;
    else
      hi = m;
  }
  return 0.5 * (lo + hi);
}

std::vector<Interval> TrimDomain::inside(bool iso_v, double level, double t0, double t1) const {
  // The hatcher keeps the lines it is given: one caller at a time.
  const std::lock_guard<std::mutex> lock(*hatcher_lock_);
  const int level_dir = iso_v ? 1 : 0;
  const double f = to_face(level_dir, level);
  const double span = fmax_[level_dir] - fmin_[level_dir];
  // A line lying on an edge (a boundary iso-line, a seam) is a tangency the
  // hatcher may not judge: then look a hair off it, inward first.
  for (double nudge : {1e-9, 1e-7, -1e-7, 1e-5, -1e-5}) {
    double g = std::clamp(f, fmin_[level_dir] + 1e-9 * span, fmax_[level_dir] - 1e-9 * span);
    if (nudge != 1e-9) g = std::clamp(g + nudge * span, fmin_[level_dir], fmax_[level_dir]);
    std::vector<Interval> out;
    if (hatch(iso_v, g, t0, t1, &out)) return out;
  }
  throw GeometryError(label(label_) + ": the trimming hatcher failed on the iso-line at " +
                      std::to_string(level));
}

bool TrimDomain::hatch(bool iso_v, double f, double t0, double t1,
                       std::vector<Interval>* out) const {
  const int run_dir = iso_v ? 0 : 1;
  Handle(Geom2d_Line) line = iso_v ? new Geom2d_Line(gp_Pnt2d(0, f), gp_Dir2d(1, 0))
                                   : new Geom2d_Line(gp_Pnt2d(f, 0), gp_Dir2d(0, 1));
  const int h = hatcher_->AddHatching(Geom2dAdaptor_Curve(line));
  hatcher_->Trim(h);
  bool ok = hatcher_->TrimDone(h) && !hatcher_->TrimFailed(h);
  if (ok) {
    hatcher_->ComputeDomains(h);
    ok = hatcher_->IsDone(h);
  }
  if (ok) {
    for (int i = 1; i <= hatcher_->NbDomains(h); ++i) {
      const HatchGen_Domain& d = hatcher_->Domain(h, i);
      const double a = d.HasFirstPoint() ? d.FirstPoint().Parameter() : fmin_[run_dir];
      const double b = d.HasSecondPoint() ? d.SecondPoint().Parameter() : fmax_[run_dir];
      double ga = to_grid(run_dir, a), gb = to_grid(run_dir, b);
      if (ga > gb) std::swap(ga, gb);
      ga = std::max(ga, t0);
      gb = std::min(gb, t1);
      if (gb > ga) out->push_back({ga, gb});
    }
  }
  hatcher_->RemHatching(h);
  std::sort(out->begin(), out->end(),
            [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  return ok;
}

bool TrimDomain::contains(double u, double v, bool cache) const {
  const RectClass quick = classify_rect(u, u, v, v, cache);
  if (quick != RectClass::Boundary) return quick == RectClass::Inside;
  // On the boundary to within rounding: the classifier, at the exact face
  // parameters.
  return cached(cache, {{u, u, v, v}, 1}, [&] {
           return point_state(to_face(0, u), to_face(1, v)) != TopAbs_OUT ? 1 : 0;
         }) > 0;
}

}  // namespace isocam
