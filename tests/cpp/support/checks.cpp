#include "support/checks.h"

#include <BRepBndLib.hxx>
#include <BRepClass_FaceClassifier.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GeomAPI_ProjectPointOnCurve.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom_Surface.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <algorithm>
#include <cmath>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include "geometry/patch_grid.h"
#include "isocam/brep_io.h"

namespace isocam::test {

std::int64_t SegmentIndex::key(long i, long j, long k) const {
  return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
         (static_cast<std::int64_t>(k) * 83492791);
}

void SegmentIndex::add(const gp_Pnt& a, const gp_Pnt& b) {
  const std::size_t id = segs_.size();
  segs_.emplace_back(a, b);
  auto lo = [&](double x, double y) {
    return static_cast<long>(std::floor(std::min(x, y) / cell_));
  };
  auto hi = [&](double x, double y) {
    return static_cast<long>(std::floor(std::max(x, y) / cell_));
  };
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

std::int64_t ModelCloud::key(long i, long j, long k) const {
  return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
         (static_cast<std::int64_t>(k) * 83492791);
}

ModelCloud::ModelCloud(const std::vector<TopoDS_Face>& faces, int n, bool trimmed) {
  for (const TopoDS_Face& f : faces) add_face(f, n, trimmed);
  index();
}

ModelCloud::ModelCloud(const std::vector<TopoDS_Face>& faces, double spacing, bool trimmed) {
  for (const TopoDS_Face& f : faces) {
    Bnd_Box b;
    BRepBndLib::Add(f, b);
    double x0, y0, z0, x1, y1, z1;
    b.Get(x0, y0, z0, x1, y1, z1);
    const double side = std::max({x1 - x0, y1 - y0, z1 - z0});
    add_face(f, std::clamp(static_cast<int>(std::ceil(side / spacing)), 8, 600), trimmed);
  }
  index();
}

void ModelCloud::add_face(const TopoDS_Face& face, int n, bool trimmed) {
  Surface s;
  s.surf = BRep_Tool::Surface(face);
  BRepTools::UVBounds(face, s.u1, s.u2, s.v1, s.v2);
  s.du = (s.u2 - s.u1) / n;
  s.dv = (s.v2 - s.v1) / n;
  const TopoDS_Face fwd = TopoDS::Face(face.Oriented(TopAbs_FORWARD));
  if (trimmed) {
    s.inside = std::make_shared<BRepTopAdaptor_FClass2d>(fwd, 1e-7);
    for (TopExp_Explorer ex(fwd, TopAbs_EDGE); ex.More(); ex.Next()) {
      Surface::Edge e;
      e.curve = BRep_Tool::Curve(TopoDS::Edge(ex.Current()), e.first, e.last);
      if (!e.curve.IsNull()) s.edges.push_back(e);
    }
  }
  const int f = static_cast<int>(surfs_.size());
  std::vector<char> in(static_cast<std::size_t>((n + 1) * (n + 1)), 1);
  auto at = [n](int i, int j) { return static_cast<std::size_t>(i * (n + 1) + j); };
  if (trimmed)
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        const TopAbs_State st = s.inside->Perform(gp_Pnt2d(s.u1 + s.du * i, s.v1 + s.dv * j));
        in[at(i, j)] = st == TopAbs_IN || st == TopAbs_ON;
      }
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      if (!in[at(i, j)]) continue;
      bool near_wire = false;
      for (int a = std::max(0, i - 3); a <= std::min(n, i + 3) && !near_wire; ++a)
        for (int b = std::max(0, j - 3); b <= std::min(n, j + 3) && !near_wire; ++b)
          near_wire = !in[at(a, b)];
      const double u = s.u1 + s.du * i, v = s.v1 + s.dv * j;
      const gp_Pnt q = s.surf->Value(u, v);
      pts_.push_back({q, f, u, v, near_wire});
      for (const auto& [a, b] : {std::pair<int, int>{i + 1, j}, {i, j + 1}})
        if (a <= n && b <= n)
          max_step_ =
              std::max(max_step_, q.Distance(s.surf->Value(s.u1 + s.du * a, s.v1 + s.dv * b)));
    }
  surfs_.push_back(s);
}

void ModelCloud::index() {
  if (pts_.empty()) return;
  Bnd_Box box;
  for (const Sample& q : pts_) box.Add(q.p);
  cell_ = std::max(1e-6, std::sqrt(box.SquareExtent()) / 50.0);
  for (std::size_t k = 0; k < pts_.size(); ++k) {
    const gp_Pnt& p = pts_[k].p;
    grid_[key(static_cast<long>(std::floor(p.X() / cell_)),
              static_cast<long>(std::floor(p.Y() / cell_)),
              static_cast<long>(std::floor(p.Z() / cell_)))]
        .push_back(k);
    columns_[key(static_cast<long>(std::floor(p.X() / cell_)),
                 static_cast<long>(std::floor(p.Y() / cell_)), 0)]
        .push_back(k);
  }
}

namespace {
// The point of the vertical ray up from c nearest to p, and the distance.
gp_Pnt on_ray(const gp_Pnt& c, const gp_Pnt& p) {
  return gp_Pnt(c.X(), c.Y(), std::max(c.Z(), p.Z()));
}
}  // namespace

double ModelCloud::column_distance(const gp_Pnt& c, double cap) const {
  // The nearest sample of each face within cap + one sample step of the ray
  // (the x-y cells around it, samples above c - that), each refined.
  const double reach_d = cap + max_step_;
  const long reach = static_cast<long>(std::ceil(reach_d / cell_));
  const long ci = static_cast<long>(std::floor(c.X() / cell_));
  const long cj = static_cast<long>(std::floor(c.Y() / cell_));
  std::unordered_map<int, std::pair<double, std::size_t>> best;
  for (long i = ci - reach; i <= ci + reach; ++i)
    for (long j = cj - reach; j <= cj + reach; ++j) {
      auto it = columns_.find(key(i, j, 0));
      if (it == columns_.end()) continue;
      for (std::size_t id : it->second) {
        const gp_Pnt& q = pts_[id].p;
        if (q.Z() < c.Z() - reach_d) continue;
        const double d = q.Distance(on_ray(c, q));
        if (d > reach_d) continue;
        auto b = best.find(pts_[id].face);
        if (b == best.end() || d < b->second.first) best[pts_[id].face] = {d, id};
      }
    }
  double out = cap;
  for (const auto& [f, b] : best) {
    // Alternate: the ray's point nearest the surface point, the surface
    // point nearest that (a local projection from the sample).
    double d = b.first;
    gp_Pnt x = pts_[b.second].p;
    for (int it = 0; it < 4; ++it) {
      const Hit h = refine(on_ray(c, x), b.second, 1e300);
      const double dh = h.point.Distance(on_ray(c, h.point));
      if (!(dh < d - 1e-12)) break;
      d = dh;
      x = h.point;
    }
    out = std::min(out, d);
  }
  return out;
}

ModelCloud::Hit ModelCloud::nearest(const gp_Pnt& p, const std::vector<char>* only) const {
  // Nearest sample by growing shells of cells, then a local projection.
  const long ci = static_cast<long>(std::floor(p.X() / cell_));
  const long cj = static_cast<long>(std::floor(p.Y() / cell_));
  const long ck = static_cast<long>(std::floor(p.Z() / cell_));
  Hit hit;
  if (pts_.empty()) return hit;
  std::size_t arg = 0;
  for (long reach = 0; reach < 200; ++reach) {
    for (long i = ci - reach; i <= ci + reach; ++i)
      for (long j = cj - reach; j <= cj + reach; ++j)
        for (long k = ck - reach; k <= ck + reach; ++k) {
          if (std::max({std::labs(i - ci), std::labs(j - cj), std::labs(k - ck)}) != reach)
            continue;
          auto it = grid_.find(key(i, j, k));
          if (it == grid_.end()) continue;
          for (std::size_t id : it->second) {
            if (only && !(*only)[static_cast<std::size_t>(pts_[id].face)]) continue;
            const double d = p.Distance(pts_[id].p);
            if (d < hit.distance) {
              hit.distance = d;
              arg = id;
            }
          }
        }
    if (hit.distance < static_cast<double>(reach) * cell_) break;  // farther shells are farther
  }
  // The face nearest p has a sample within its distance plus one sample
  // step: refine the nearest sample of every face within that reach, not
  // only of the face of the nearest sample.
  Hit best = refine(p, arg, hit.distance);
  for (const Hit& h : nearest_per_face(p, hit.distance + max_step_, only))
    if (h.distance < best.distance) best = h;
  return best;
}

ModelCloud::Hit ModelCloud::refine(const gp_Pnt& p, std::size_t arg, double dist) const {
  Hit hit;
  hit.distance = dist;
  const Sample& q = pts_[arg];
  const Surface& s = surfs_[static_cast<std::size_t>(q.face)];
  hit.point = q.p;
  hit.face = q.face;
  // Local projection: Newton on |S(u, v) - p|^2 from the sample, kept in a
  // window of two cells around it (Gauss-Newton where the Hessian is not
  // positive, as behind a surface that curves tighter than the distance).
  // On a trimmed face only iterates inside it count (the window of a sample
  // away from the wires is inside); if the search leaves the face, the
  // nearest point may be on its edges, which are searched too.
  double u = q.u, v = q.v;
  bool left = false;
  const double ulo = std::max(s.u1, q.u - 2 * s.du), uhi = std::min(s.u2, q.u + 2 * s.du);
  const double vlo = std::max(s.v1, q.v - 2 * s.dv), vhi = std::min(s.v2, q.v + 2 * s.dv);
  for (int it = 0; it < 12; ++it) {
    gp_Pnt x;
    gp_Vec su, sv, suu, svv, suv;
    s.surf->D2(u, v, x, su, sv, suu, svv, suv);
    const gp_Vec d(p, x);
    const double here = d.Magnitude();
    if (q.near_wire && s.inside->Perform(gp_Pnt2d(u, v)) == TopAbs_OUT) {
      left = true;
    } else if (here < hit.distance) {
      hit.distance = here;
      hit.point = x;
    }
    const double gu = su.Dot(d), gv = sv.Dot(d);
    double a11 = su.Dot(su) + suu.Dot(d), a12 = su.Dot(sv) + suv.Dot(d),
           a22 = sv.Dot(sv) + svv.Dot(d);
    if (!(a11 > 0 && a11 * a22 - a12 * a12 > 0)) {
      a11 = su.Dot(su);
      a12 = su.Dot(sv);
      a22 = sv.Dot(sv);
    }
    const double det = a11 * a22 - a12 * a12;
    if (!(det > 0)) break;
    const double stepu = (a22 * gu - a12 * gv) / det, stepv = (a11 * gv - a12 * gu) / det;
    const double nu = std::clamp(u - stepu, ulo, uhi), nv = std::clamp(v - stepv, vlo, vhi);
    if (std::abs(nu - u) < 1e-12 * (s.u2 - s.u1 + 1) &&
        std::abs(nv - v) < 1e-12 * (s.v2 - s.v1 + 1))
      break;
    u = nu;
    v = nv;
  }
  if (left) {
    const Hit edge = nearest_on_edges(s, p);
    if (edge.distance < hit.distance) {
      hit.distance = edge.distance;
      hit.point = edge.point;
    }
  }
  return hit;
}

ModelCloud::Hit ModelCloud::nearest_on_edges(const Surface& s, const gp_Pnt& p) {
  Hit hit;
  for (const Surface::Edge& e : s.edges) {
    for (double t : {e.first, e.last}) {
      const gp_Pnt x = e.curve->Value(t);
      if (p.Distance(x) < hit.distance) {
        hit.distance = p.Distance(x);
        hit.point = x;
      }
    }
    GeomAPI_ProjectPointOnCurve proj(p, e.curve, e.first, e.last);
    if (proj.NbPoints() > 0 && proj.LowerDistance() < hit.distance) {
      hit.distance = proj.LowerDistance();
      hit.point = proj.NearestPoint();
    }
  }
  return hit;
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
  const std::size_t stride =
      std::max<std::size_t>(1, centres.size() / static_cast<std::size_t>(checks));
  double best = 1e300;
  for (std::size_t i = 0; i < centres.size(); i += stride)
    best = std::min(best, face.distance(centres[i]));
  return best;
}

std::vector<ModelCloud::Hit> ModelCloud::nearest_per_face(const gp_Pnt& p, double radius,
                                                          const std::vector<char>* only) const {
  // The nearest sample of each face within `radius` (cells within reach),
  // each refined on its own surface.
  const long reach = static_cast<long>(std::ceil(radius / cell_));
  const long ci = static_cast<long>(std::floor(p.X() / cell_));
  const long cj = static_cast<long>(std::floor(p.Y() / cell_));
  const long ck = static_cast<long>(std::floor(p.Z() / cell_));
  std::unordered_map<int, std::pair<double, std::size_t>> best;
  for (long i = ci - reach; i <= ci + reach; ++i)
    for (long j = cj - reach; j <= cj + reach; ++j)
      for (long k = ck - reach; k <= ck + reach; ++k) {
        auto it = grid_.find(key(i, j, k));
        if (it == grid_.end()) continue;
        for (std::size_t id : it->second) {
          const int f = pts_[id].face;
          if (only && !(*only)[static_cast<std::size_t>(f)]) continue;
          const double d = p.Distance(pts_[id].p);
          if (d > radius) continue;
          auto b = best.find(f);
          if (b == best.end() || d < b->second.first) best[f] = {d, id};
        }
      }
  std::vector<Hit> out;
  for (const auto& [f, b] : best) out.push_back(refine(p, b.second, b.first));
  return out;
}

namespace {

// Calls f(p, n) for an (n+1) x (n+1) sampling of the face's parameter bounds,
// at the points inside its wires (poles, where the normal is undefined, are
// skipped: their neighbours are sampled), n the unit normal pointing away
// from the material.
template <class F>
void for_each_face_sample(const TopoDS_Face& face, int n, F f) {
  Handle(Geom_Surface) surf = BRep_Tool::Surface(face);
  const BRepTopAdaptor_FClass2d classifier(TopoDS::Face(face.Oriented(TopAbs_FORWARD)), 1e-9);
  const bool reversed = face.Orientation() == TopAbs_REVERSED;
  double u1, u2, v1, v2;
  BRepTools::UVBounds(face, u1, u2, v1, v2);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double u = u1 + (u2 - u1) * i / n, v = v1 + (v2 - v1) * j / n;
      if (classifier.Perform(gp_Pnt2d(u, v)) != TopAbs_IN) continue;
      gp_Pnt p;
      gp_Vec su, sv;
      surf->D1(u, v, p, su, sv);
      gp_Vec nrm = su.Crossed(sv);
      if (nrm.Magnitude() < 1e-12) continue;
      nrm.Normalize();
      if (reversed) nrm.Reverse();
      f(p, nrm);
    }
}

}  // namespace

WholeModelCheck check_whole_model(const TopoDS_Shape& shape, const std::vector<int>& picked,
                                  const Toolpath& path, double r, double step, int n,
                                  double reach_tol, double gap_cap) {
  const std::vector<TopoDS_Face> all = faces_of(shape);
  std::vector<TopoDS_Face> mine;
  std::vector<char> is_picked(all.size(), 0);
  for (int f : picked) {
    mine.push_back(all.at(static_cast<std::size_t>(f)));
    is_picked[static_cast<std::size_t>(f)] = 1;
  }
  const ModelCloud model(all, r / 4, true);
  WholeModelCheck out;
  out.face_gap.assign(picked.size(), 0.0);
  // Ball centres along the feed moves, and their contact points on each
  // face they touch, as runs per face.
  SegmentIndex contacts(gap_cap);
  std::unordered_map<int, std::vector<gp_Pnt>> runs;
  std::unordered_map<int, long> last_seen;
  long centre = 0;
  auto flush = [&](int face) {
    contacts.add_polyline(runs[face]);
    runs[face].clear();
  };
  auto flush_all = [&]() {
    for (auto& run : runs) flush(run.first);
  };
  const double touch = r + 0.05;  // a ball farther than this does not cut the face
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (path.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) {
      flush_all();
      ++centre;
      continue;
    }
    const gp_Pnt a(path.x[i - 1], path.y[i - 1], path.z[i - 1] + r);
    const gp_Pnt b(path.x[i], path.y[i], path.z[i] + r);
    const int k = std::max(1, static_cast<int>(std::ceil(a.Distance(b) / step)));
    for (int s = 1; s <= k; ++s, ++centre) {
      const gp_Pnt c(a.XYZ() + (b.XYZ() - a.XYZ()) * (double(s) / k));
      const ModelCloud::Hit nearest = model.nearest(c);
      if (nearest.distance < out.min_clearance) {
        out.min_clearance = nearest.distance;
        out.closest_centre = c;
        out.closest_point = nearest.point;
        out.closest_face = nearest.face;
      }
      for (const ModelCloud::Hit& h :
           model.nearest_per_face(c, touch + 2 * model.spacing(), &is_picked)) {
        if (h.distance > touch) continue;
        auto seen = last_seen.find(h.face);
        if (seen == last_seen.end() || seen->second != centre - 1) flush(h.face);
        last_seen[h.face] = centre;
        runs[h.face].push_back(h.point);
      }
    }
  }
  flush_all();
  // Faces that bound no solid: the tool may be on either side of them.
  TopTools_IndexedDataMapOfShapeListOfShape solids;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SOLID, solids);
  // Reachable: the ball touching p from the side of n, and that ball lifted
  // straight up, keep r - reach_tol from the model.
  auto reachable = [&](const gp_Pnt& p, const gp_Vec& nrm) {
    const gp_Pnt c = p.Translated(nrm * r);
    return model.distance(c) >= r - reach_tol && model.column_distance(c, r) >= r - reach_tol;
  };
  // First the reach of every sample; then the gap of each reachable one: its
  // distance to the contacts or to the nearest unreachable sample, whichever
  // is less (the core cuts a pass where the reach ends, so a point near that
  // border is covered by the border, not necessarily by a pass: where the
  // reach is ragged -- a wall leaning out by microns, which the tool lifted
  // from its foot would graze -- no pass spacing covers every thin part).
  std::vector<std::vector<std::pair<gp_Pnt, bool>>> face_samples(mine.size());
  SegmentIndex unreachable(gap_cap);
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const int in_solids = solids.FindIndex(mine[k]);
    const bool open = in_solids == 0 || solids(in_solids).IsEmpty();
    for_each_face_sample(mine[k], n, [&](const gp_Pnt& p, const gp_Vec& nrm) {
      const bool ok = reachable(p, nrm) || (open && reachable(p, -nrm));
      face_samples[k].push_back({p, ok});
      if (!ok) unreachable.add(p, p);
    });
  }
  for (std::size_t k = 0; k < mine.size(); ++k) {
    for (const auto& [p, ok] : face_samples[k]) {
      ++out.samples;
      if (!ok) {
        ++out.unreachable;
        continue;
      }
      const double gap = std::min(contacts.distance(p, gap_cap), unreachable.distance(p, gap_cap));
      out.face_gap[k] = std::max(out.face_gap[k], gap);
      if (gap > out.max_gap) {
        out.max_gap = gap;
        out.worst = p;
        out.worst_face = picked[k];
      }
    }
  }
  return out;
}

double reachable_coverage_gap(const TopoDS_Face& face, const TopoDS_Shape& shape,
                              const ModelCloud& model, double r, double reach_tol,
                              const SegmentIndex& curves, int n, double cap) {
  TopTools_IndexedDataMapOfShapeListOfShape solids;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SOLID, solids);
  const int in_solids = solids.FindIndex(face);
  const bool open = in_solids == 0 || solids(in_solids).IsEmpty();
  auto reachable = [&](const gp_Pnt& p, const gp_Vec& nrm) {
    const gp_Pnt c = p.Translated(nrm * r);
    return model.distance(c) >= r - reach_tol && model.column_distance(c, r) >= r - reach_tol;
  };
  std::vector<gp_Pnt> reached;
  SegmentIndex unreachable(cap);
  for_each_face_sample(face, n, [&](const gp_Pnt& p, const gp_Vec& nrm) {
    if (reachable(p, nrm) || (open && reachable(p, -nrm))) {
      reached.push_back(p);
    } else {
      unreachable.add(p, p);
    }
  });
  double worst = 0.0;
  for (const gp_Pnt& p : reached)
    worst = std::max(worst, std::min(curves.distance(p, cap), unreachable.distance(p, cap)));
  return worst;
}

ScallopCheck measure_scallop(const TopoDS_Face& face, const Toolpath& path, double r, int n,
                             double step, double cap, const ModelCloud* model) {
  // Ball centres in a hash grid of cell r.
  std::unordered_map<std::int64_t, std::vector<gp_Pnt>> grid;
  auto cell = [r](double x) { return static_cast<long>(std::floor(x / r)); };
  auto key = [](long i, long j, long k) {
    return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
           (static_cast<std::int64_t>(k) * 83492791);
  };
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (path.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    const gp_Pnt a(path.x[i - 1], path.y[i - 1], path.z[i - 1] + r);
    const gp_Pnt b(path.x[i], path.y[i], path.z[i] + r);
    const int k = std::max(1, static_cast<int>(std::ceil(a.Distance(b) / step)));
    for (int s = 0; s <= k; ++s) {
      const gp_Pnt c(a.XYZ() + (b.XYZ() - a.XYZ()) * (double(s) / k));
      grid[key(cell(c.X()), cell(c.Y()), cell(c.Z()))].push_back(c);
    }
  }
  ScallopCheck out;
  for_each_face_sample(face, n, [&](const gp_Pnt& p, const gp_Vec& nrm) {
    ++out.samples;
    if (model && model->column_distance(p.Translated(nrm * r), r) < r - 0.002) {
      ++out.unreachable;
      return;
    }
    // Balls that the ray can enter below `cap` have centres within r + cap.
    double best = cap;
    const gp_Pnt mid = p.Translated(nrm * (0.5 * cap));
    for (long a = cell(mid.X()) - 2; a <= cell(mid.X()) + 2; ++a)
      for (long b = cell(mid.Y()) - 2; b <= cell(mid.Y()) + 2; ++b)
        for (long c = cell(mid.Z()) - 2; c <= cell(mid.Z()) + 2; ++c) {
          auto it = grid.find(key(a, b, c));
          if (it == grid.end()) continue;
          for (const gp_Pnt& q : it->second) {
            const gp_Vec pc(q, p);  // p - c
            const double bb = nrm.Dot(pc), cc = pc.SquareMagnitude() - r * r;
            if (cc <= 0) {
              best = 0;  // p is inside the ball: cut down to the surface
              continue;
            }
            const double disc = bb * bb - cc;
            if (bb < 0 && disc >= 0) best = std::min(best, -bb - std::sqrt(disc));
          }
        }
    if (best >= cap) {
      ++out.uncovered;
      return;
    }
    out.max = std::max(out.max, best);
  });
  return out;
}

SegmentIndex feed_segments(const Toolpath& path, double cell) {
  SegmentIndex idx(cell);
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (path.kind[i] != static_cast<std::uint8_t>(MoveKind::Feed)) continue;
    idx.add(gp_Pnt(path.x[i - 1], path.y[i - 1], path.z[i - 1]),
            gp_Pnt(path.x[i], path.y[i], path.z[i]));
  }
  return idx;
}

}  // namespace isocam::test
