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
}  // namespace

// The domain is read from the face oriented FORWARD: exploring a REVERSED
// face reverses its edges too, which would turn the domain inside out in the
// surface's own parameter plane.
TrimDomain::TrimDomain(const TopoDS_Face& face, const PatchGrid& grid, int face_label)
    : face_(TopoDS::Face(face.Oriented(TopAbs_FORWARD))),
      surface_(BRep_Tool::Surface(face)),
      grid_(&grid),
      label_(face_label) {
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
    if (!add_spans(pc, f, l)) spans_exact_ = false;
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

bool TrimDomain::add_spans(const Handle(Geom2d_Curve) & pc, double f, double l) {
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

// Does the rational Bezier span (homogeneous control points, 3 each, degree
// n) miss the closed rectangle [lo, hi]? Its curve lies in the hull of its
// projected control points (the weights are positive) and passes through
// the end ones: a hull box that misses proves a miss, an end point inside
// proves a meet; otherwise the span is split at its middle. `budget` bounds
// the boxes tested; when it runs out the answer is "meets" (not proved).
bool span_misses(const double* c, int n, const double lo[2], const double hi[2], int depth,
                 int* budget) {
  if (--*budget < 0) return false;
  double blo[2] = {1e300, 1e300}, bhi[2] = {-1e300, -1e300};
  for (int k = 0; k <= n; ++k) {
    const double x = c[3 * k] / c[3 * k + 2], y = c[3 * k + 1] / c[3 * k + 2];
    blo[0] = std::min(blo[0], x);
    blo[1] = std::min(blo[1], y);
    bhi[0] = std::max(bhi[0], x);
    bhi[1] = std::max(bhi[1], y);
    if ((k == 0 || k == n) && x >= lo[0] && x <= hi[0] && y >= lo[1] && y <= hi[1]) return false;
  }
  if (blo[0] > hi[0] || bhi[0] < lo[0] || blo[1] > hi[1] || bhi[1] < lo[1]) return true;
  if (depth >= 40) return false;
  double l[3 * (kMaxSpanDegree + 1)], r[3 * (kMaxSpanDegree + 1)], w[3 * (kMaxSpanDegree + 1)];
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
  return span_misses(l, n, lo, hi, depth + 1, budget) &&
         span_misses(r, n, lo, hi, depth + 1, budget);
}

}  // namespace

bool TrimDomain::curves_miss(const double lo[2], const double hi[2]) const {
  if (!spans_exact_) return false;
  int budget = 4000;
  for (const Span2& s : spans_) {
    if (s.box.lo[0] > hi[0] || s.box.hi[0] < lo[0] || s.box.lo[1] > hi[1] || s.box.hi[1] < lo[1])
      continue;
    if (!span_misses(&span_cps_[s.first], s.degree, lo, hi, 0, &budget)) return false;
  }
  return true;
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
    const TopAbs_State st = classify_point(0.5 * (n.lo[0] + n.hi[0]), 0.5 * (n.lo[1] + n.hi[1]));
    n.state = rect_class(st);
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
int TrimDomain::cached(const RectKey& key, Decide decide) const {
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

TrimDomain::RectClass TrimDomain::classify_rect(double u0, double u1, double v0, double v1) const {
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
  return static_cast<RectClass>(cached({{u0, u1, v0, v1}, 0}, [&] {
    if (!curves_miss(lo, hi)) return static_cast<int>(RectClass::Boundary);
    return static_cast<int>(
        rect_class(classify_point(0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]))));
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

bool TrimDomain::contains(double u, double v) const {
  const RectClass quick = classify_rect(u, u, v, v);
  if (quick != RectClass::Boundary) return quick == RectClass::Inside;
  // On the boundary to within rounding: the classifier, at the exact face
  // parameters.
  return cached({{u, u, v, v}, 1}, [&] {
           return classify_point(to_face(0, u), to_face(1, v)) != TopAbs_OUT ? 1 : 0;
         }) > 0;
}

}  // namespace isocam
