#include "support/checks.h"

#include <algorithm>
#include <cmath>

#include <BRepClass_FaceClassifier.hxx>
#include <Bnd_Box.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopoDS.hxx>
#include <gp_Pnt2d.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <BRepTools.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Surface.hxx>
#include <gp_Vec.hxx>

#include "geometry/patch_grid.h"

namespace isocam::test {

std::int64_t SegmentIndex::key(long i, long j, long k) const {
  return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
         (static_cast<std::int64_t>(k) * 83492791);
}

void SegmentIndex::add(const gp_Pnt& a, const gp_Pnt& b) {
  const std::size_t id = segs_.size();
  segs_.emplace_back(a, b);
  auto lo = [&](double x, double y) { return static_cast<long>(std::floor(std::min(x, y) / cell_)); };
  auto hi = [&](double x, double y) { return static_cast<long>(std::floor(std::max(x, y) / cell_)); };
  for (long i = lo(a.X(), b.X()); i <= hi(a.X(), b.X()); ++i)
    for (long j = lo(a.Y(), b.Y()); j <= hi(a.Y(), b.Y()); ++j)
      for (long k = lo(a.Z(), b.Z()); k <= hi(a.Z(), b.Z()); ++k) grid_[key(i, j, k)].push_back(id);
}

void SegmentIndex::add_polyline(const std::vector<gp_Pnt>& pts) {
  if (pts.size() == 1) add(pts[0], pts[0]);
  for (std::size_t i = 1; i < pts.size(); ++i) add(pts[i - 1], pts[i]);
}

double SegmentIndex::distance(const gp_Pnt& p, double cap) const {
  double best = cap;
  const long reach = static_cast<long>(std::ceil(cap / cell_));
  const long ci = static_cast<long>(std::floor(p.X() / cell_));
  const long cj = static_cast<long>(std::floor(p.Y() / cell_));
  const long ck = static_cast<long>(std::floor(p.Z() / cell_));
  for (long i = ci - reach; i <= ci + reach; ++i)
    for (long j = cj - reach; j <= cj + reach; ++j)
      for (long k = ck - reach; k <= ck + reach; ++k) {
        auto it = grid_.find(key(i, j, k));
        if (it == grid_.end()) continue;
        for (std::size_t id : it->second) {
          const gp_Pnt& a = segs_[id].first;
          const gp_Pnt& b = segs_[id].second;
          const gp_Vec ab(a, b), ap(a, p);
          const double l2 = ab.SquareMagnitude();
          const double s = l2 > 0 ? std::clamp(ap.Dot(ab) / l2, 0.0, 1.0) : 0.0;
          best = std::min(best, p.Distance(a.Translated(ab * s)));
        }
      }
  return best;
}

namespace {

template <class Map>
std::vector<std::vector<gp_Pnt>> sample_curves(const TopoDS_Face& face, int face_index,
                                               const IsoResult& result, double step, Map map) {
  const PatchGrid grid = PatchGrid::from_face(face, face_index);
  const PatchGrid gridT = grid.transposed();
  std::vector<std::vector<gp_Pnt>> out;
  for (const SubIsocurve& c : result.curves) {
    if (c.face != face_index) continue;
    const PatchGrid& g = c.dir == IsoDirection::U ? gridT : grid;
    // Sample finely in parameter first, then thin to the spatial step.
    const int n = 4000;
    std::vector<gp_Pnt> pts;
    for (int i = 0; i <= n; ++i) {
      const double t = c.t0 + (c.t1 - c.t0) * i / n;
      const gp_Pnt p = map(g, t, c.level);
      if (pts.empty() || i == n || pts.back().Distance(p) >= step * 0.5) pts.push_back(p);
    }
    out.push_back(std::move(pts));
  }
  return out;
}

}  // namespace

std::vector<std::vector<gp_Pnt>> contact_curves(const TopoDS_Face& face, int face_index,
                                                const IsoResult& result, double step) {
  return sample_curves(face, face_index, result, step,
                       [](const PatchGrid& g, double t, double v) { return g.eval(t, v); });
}

std::vector<std::vector<gp_Pnt>> tip_curves(const TopoDS_Face& face, int face_index,
                                            const IsoResult& result, double r, double step) {
  return sample_curves(face, face_index, result, step, [r](const PatchGrid& g, double t, double v) {
    const gp_Pnt c = g.eval(t, v).Translated(g.normal(t, v) * r);
    return gp_Pnt(c.X(), c.Y(), c.Z() - r);
  });
}

double coverage_gap(const TopoDS_Face& face, const SegmentIndex& curves, int n, double cap) {
  Handle(Geom_Surface) s = BRep_Tool::Surface(face);
  const TopoDS_Face fwd = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  double u1, u2, v1, v2;
  BRepTools::UVBounds(face, u1, u2, v1, v2);
  double worst = 0.0;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = u1 + (u2 - u1) * i / n, v = v1 + (v2 - v1) * j / n;
      BRepClass_FaceClassifier inside(fwd, gp_Pnt2d(u, v), 1e-9);
      if (inside.State() != TopAbs_IN) continue;
      worst = std::max(worst, curves.distance(s->Value(u, v), cap));
    }
  return worst;
}

bool in_face(const TopoDS_Face& face, const gp_Pnt& p, double tol) {
  const TopoDS_Face fwd = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  ShapeAnalysis_Surface sas(BRep_Tool::Surface(face));
  const gp_Pnt2d uv = sas.ValueOfUV(p, 1e-9);
  BRepClass_FaceClassifier c(fwd, uv, tol);
  return c.State() == TopAbs_IN || c.State() == TopAbs_ON;
}

std::int64_t FaceCloud::key(long i, long j, long k) const {
  return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
         (static_cast<std::int64_t>(k) * 83492791);
}

FaceCloud::FaceCloud(const TopoDS_Face& face, int n) : surf_(BRep_Tool::Surface(face)) {
  BRepTools::UVBounds(face, u1_, u2_, v1_, v2_);
  du_ = (u2_ - u1_) / n;
  dv_ = (v2_ - v1_) / n;
  Bnd_Box box;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = u1_ + du_ * i, v = v1_ + dv_ * j;
      pts_.push_back(surf_->Value(u, v));
      uv_.emplace_back(u, v);
      box.Add(pts_.back());
    }
  cell_ = std::sqrt(box.SquareExtent()) / 50.0;
  for (std::size_t k = 0; k < pts_.size(); ++k) {
    const gp_Pnt& p = pts_[k];
    grid_[key(static_cast<long>(std::floor(p.X() / cell_)), static_cast<long>(std::floor(p.Y() / cell_)),
              static_cast<long>(std::floor(p.Z() / cell_)))]
        .push_back(k);
  }
}

double FaceCloud::distance(const gp_Pnt& p) const {
  // Nearest sample by growing shells of cells, then a local projection.
  const long ci = static_cast<long>(std::floor(p.X() / cell_));
  const long cj = static_cast<long>(std::floor(p.Y() / cell_));
  const long ck = static_cast<long>(std::floor(p.Z() / cell_));
  double best = 1e300;
  std::size_t arg = 0;
  for (long reach = 0; reach < 200; ++reach) {
    for (long i = ci - reach; i <= ci + reach; ++i)
      for (long j = cj - reach; j <= cj + reach; ++j)
        for (long k = ck - reach; k <= ck + reach; ++k) {
          if (std::max({std::labs(i - ci), std::labs(j - cj), std::labs(k - ck)}) != reach) continue;
          auto it = grid_.find(key(i, j, k));
          if (it == grid_.end()) continue;
          for (std::size_t id : it->second) {
            const double d = p.Distance(pts_[id]);
            if (d < best) {
              best = d;
              arg = id;
            }
          }
        }
    if (best < static_cast<double>(reach) * cell_) break;  // farther shells are farther
  }
  const auto [u, v] = uv_[arg];
  GeomAPI_ProjectPointOnSurf proj(p, surf_, std::max(u1_, u - 2 * du_), std::min(u2_, u + 2 * du_),
                                  std::max(v1_, v - 2 * dv_), std::min(v2_, v + 2 * dv_),
                                  Extrema_ExtAlgo_Grad);
  return proj.NbPoints() > 0 ? std::min(best, proj.LowerDistance()) : best;
}

double min_centre_distance(const FaceCloud& face, const Toolpath& path, double r, int checks) {
  std::vector<gp_Pnt> centres;
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (path.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    const gp_Pnt a(path.x[i - 1], path.y[i - 1], path.z[i - 1] + r);
    const gp_Pnt b(path.x[i], path.y[i], path.z[i] + r);
    centres.push_back(b);
    centres.push_back(gp_Pnt((a.XYZ() + b.XYZ()) * 0.5));
  }
  const std::size_t stride = std::max<std::size_t>(1, centres.size() / static_cast<std::size_t>(checks));
  double best = 1e300;
  for (std::size_t i = 0; i < centres.size(); i += stride) best = std::min(best, face.distance(centres[i]));
  return best;
}

SegmentIndex feed_segments(const Toolpath& path, double cell) {
  SegmentIndex idx(cell);
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (path.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    idx.add(gp_Pnt(path.x[i - 1], path.y[i - 1], path.z[i - 1]), gp_Pnt(path.x[i], path.y[i], path.z[i]));
  }
  return idx;
}

}  // namespace isocam::test
