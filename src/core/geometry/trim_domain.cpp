#include "geometry/trim_domain.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <BRepTopAdaptor_FClass2d.hxx>
#include <TopoDS_Edge.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Geom2dAdaptor_Curve.hxx>
#include <Geom2dHatch_Hatcher.hxx>
#include <Geom2dHatch_Intersector.hxx>
#include <Geom2d_Line.hxx>
#include <Geom2d_TrimmedCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <HatchGen_Domain.hxx>
#include <Precision.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <gp_Dir2d.hxx>
#include <gp_Pnt2d.hxx>

#include "isocam/errors.h"

namespace isocam {
namespace {
std::string label(int face) {
  return "face " + std::to_string(face) + " (Face" + std::to_string(face + 1) + ")";
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
  classifier_ = std::make_unique<BRepTopAdaptor_FClass2d>(face_, 1e-9);
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
    hatcher_->AddElement(Geom2dAdaptor_Curve(new Geom2d_TrimmedCurve(pc, f, l)), edge.Orientation());
    add_boundary_boxes(*pc, f, l, range);
  }
  quad_.push_back({{fmin_[0] - 1e-9 * range, fmin_[1] - 1e-9 * range},
                    {fmax_[0] + 1e-9 * range, fmax_[1] + 1e-9 * range}, 0, -1});
  std::vector<int> all(boundary_.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
  build_quadtree(0, all, 0);
  if (!grid.same_params_as_face()) {
    // Tabulate the monotone maps; the margin is twice the largest
    // interpolation error seen at the midpoints.
    const int n = 128;
    for (int dir = 0; dir < 2; ++dir) {
      const double g0 = dir == 0 ? grid.umin() : grid.vmin();
      const double g1 = dir == 0 ? grid.umax() : grid.vmax();
      double err = 0;
      for (int k = 0; k <= n; ++k) {
        const double g = g0 + (g1 - g0) * k / n;
        table_g_[dir].push_back(g);
        table_f_[dir].push_back(to_face(dir, g));
        if (k > 0) {
          const double gm = g - 0.5 * (g1 - g0) / n;
          const double lin = 0.5 * (table_f_[dir][static_cast<std::size_t>(k)] +
                                    table_f_[dir][static_cast<std::size_t>(k) - 1]);
          err = std::max(err, std::abs(to_face(dir, gm) - lin));
        }
      }
      table_margin_[dir] = 2.0 * err + 1e-9 * range;
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
    const double sag = 2.0 * m.Distance(gp_Pnt2d(0.5 * (a.X() + b.X()), 0.5 * (a.Y() + b.Y()))) +
                       1e-9 * range;
    boundary_.push_back({{std::min(a.X(), b.X()) - sag, std::min(a.Y(), b.Y()) - sag},
                         {std::max(a.X(), b.X()) + sag, std::max(a.Y(), b.Y()) + sag}});
    a = b;
  }
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
    const TopAbs_State st =
        classifier_->Perform(gp_Pnt2d(0.5 * (n.lo[0] + n.hi[0]), 0.5 * (n.lo[1] + n.hi[1])));
    n.state = st == TopAbs_IN ? 1 : st == TopAbs_OUT ? -1 : 0;
    return;
  }
  if (depth >= 9) return;  // undecided leaf along the boundary
  const double mid[2] = {0.5 * (n.lo[0] + n.hi[0]), 0.5 * (n.lo[1] + n.hi[1])};
  const double lo[2] = {n.lo[0], n.lo[1]}, hi[2] = {n.hi[0], n.hi[1]};
  n.state = 2;
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

int TrimDomain::query_quadtree(int node, const double lo[2], const double hi[2]) const {
  const QuadNode& n = quad_[static_cast<std::size_t>(node)];
  if (n.state != 2) return n.state;
  int state = 3;  // none seen yet
  for (int k = 0; k < 4; ++k) {
    const QuadNode& c = quad_[static_cast<std::size_t>(n.first_child + k)];
    if (c.lo[0] > hi[0] || c.hi[0] < lo[0] || c.lo[1] > hi[1] || c.hi[1] < lo[1]) continue;
    const int s = query_quadtree(n.first_child + k, lo, hi);
    if (s == 0) return 0;
    if (state == 3) {
      state = s;
    } else if (state != s) {
      return 0;
    }
  }
  return state == 3 ? -1 : state;
}

int TrimDomain::classify_rect(double u0, double u1, double v0, double v1) const {
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
    return -1;
  const bool within = lo[0] >= quad_[0].lo[0] && hi[0] <= quad_[0].hi[0] &&
                      lo[1] >= quad_[0].lo[1] && hi[1] <= quad_[0].hi[1];
  const int s = query_quadtree(0, lo, hi);
  return !within && s == 1 ? 0 : s;
}

TrimDomain::~TrimDomain() = default;
TrimDomain::TrimDomain(TrimDomain&&) noexcept = default;
TrimDomain& TrimDomain::operator=(TrimDomain&&) noexcept = default;

double TrimDomain::to_face(int dir, double g) const {
  if (grid_->same_params_as_face()) return g;
  // The NURBS form of an analytic surface maps each parameter on its own:
  // project a grid point onto the face's surface and read one coordinate.
  const double other = dir == 0 ? 0.5 * (grid_->vmin() + grid_->vmax())
                                : 0.5 * (grid_->umin() + grid_->umax());
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
    if ((to_face(dir, m) < f) == rising) lo = m; else hi = m;
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

bool TrimDomain::hatch(bool iso_v, double f, double t0, double t1, std::vector<Interval>* out) const {
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
  std::sort(out->begin(), out->end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  return ok;
}

bool TrimDomain::contains(double u, double v) const {
  // By the quadtree: a point in an undecided cell along the boundary (a cell
  // 1/512 of the parameter range wide) counts as inside, which errs on the
  // side of protecting the face.
  const double p[2] = {face_approx(0, u), face_approx(1, v)};
  const QuadNode& root = quad_[0];
  if (p[0] < root.lo[0] || p[0] > root.hi[0] || p[1] < root.lo[1] || p[1] > root.hi[1]) return false;
  return query_quadtree(0, p, p) >= 0;
}

bool TrimDomain::contains_exact(double u, double v) const {
  const int quick = classify_rect(u, u, v, v);
  if (quick != 0) return quick > 0;
  return classifier_->Perform(gp_Pnt2d(to_face(0, u), to_face(1, v))) != TopAbs_OUT;
}

}  // namespace isocam
