#include "geometry/trim_domain.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <BRepClass_FaceClassifier.hxx>
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
    : face_(TopoDS::Face(face.Oriented(TopAbs_FORWARD))), grid_(&grid), label_(face_label) {
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
  }
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
  Handle(Geom_Surface) s = BRep_Tool::Surface(face_);
  GeomAPI_ProjectPointOnSurf proj(p, s, fmin_[0] - 1e-9, fmax_[0] + 1e-9, fmin_[1] - 1e-9,
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
  const int level_dir = iso_v ? 1 : 0, run_dir = 1 - level_dir;
  double f = to_face(level_dir, level);
  // A line lying on a boundary edge is a tangency the hatcher cannot judge:
  // look a hair inside (1e-9 of the range).
  const double span = fmax_[level_dir] - fmin_[level_dir], nudge = 1e-9 * span;
  f = std::clamp(f, fmin_[level_dir] + nudge, fmax_[level_dir] - nudge);
  Handle(Geom2d_Line) line = iso_v ? new Geom2d_Line(gp_Pnt2d(0, f), gp_Dir2d(1, 0))
                                   : new Geom2d_Line(gp_Pnt2d(f, 0), gp_Dir2d(0, 1));
  const int h = hatcher_->AddHatching(Geom2dAdaptor_Curve(line));
  hatcher_->Trim(h);
  std::vector<Interval> out;
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
      if (gb > ga) out.push_back({ga, gb});
    }
  }
  hatcher_->RemHatching(h);
  if (!ok) {
    throw GeometryError(label(label_) + ": the trimming hatcher failed on the iso-line at " +
                        std::to_string(level));
  }
  std::sort(out.begin(), out.end(), [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  return out;
}

bool TrimDomain::contains(double u, double v) const {
  const gp_Pnt2d p(to_face(0, u), to_face(1, v));
  BRepClass_FaceClassifier c(face_, p, 1e-7);
  return c.State() == TopAbs_IN || c.State() == TopAbs_ON;
}

}  // namespace isocam
