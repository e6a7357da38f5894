// Dense points on the design surface, inside each face's wires.
#include <BRepAdaptor_Curve2d.hxx>
#include <BRepTools.hxx>
#include <BRepTopAdaptor_FClass2d.hxx>
#include <BRep_Tool.hxx>
#include <BndLib_Add2dCurve.hxx>
#include <Bnd_Box2d.hxx>
#include <GeomAdaptor_Surface.hxx>
#include <GeomLProp_SLProps.hxx>
#include <Geom_Surface.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <gp_Pnt2d.hxx>
#include <stdexcept>
#include <thread>

#include "gcode_sim.h"

namespace gsim {

std::vector<TopoDS_Shape> faces_of(const TopoDS_Shape& shape) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(shape, TopAbs_FACE, map);
  std::vector<TopoDS_Shape> faces;
  for (int i = 1; i <= map.Extent(); ++i) faces.push_back(map(i));
  return faces;
}

namespace {

// One face's parameter rectangle split into cells; each cell gets its own
// grid, from the largest |Su| and |Sv| seen on it, so that neighbours are
// about `spacing` apart in 3D even where the parametrisation is uneven.
struct FaceJob {
  TopoDS_Face face;
  int number = 0;
  bool picked = false;
  bool open = false;
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  int cu = 1, cv = 1;
  // Cells that a piece of a boundary p-curve may cross: their points are
  // classified one by one; every other cell is wholly in or out.
  std::vector<char> boundary;
};

// The boundary is tracked on sub-cells, kSub x kSub per cell.
constexpr int kSub = 8;

// Marks the sub-cells met by the bounding boxes of 256 pieces of each
// edge's p-curve.
void mark_boundary_cells(FaceJob& job) {
  const int nu = job.cu * kSub, nv = job.cv * kSub;
  job.boundary.assign(static_cast<std::size_t>(nu * nv), 0);
  const double du = (job.u1 - job.u0) / nu, dv = (job.v1 - job.v0) / nv;
  for (TopExp_Explorer e(job.face, TopAbs_EDGE); e.More(); e.Next()) {
    const TopoDS_Edge& edge = TopoDS::Edge(e.Current());
    BRepAdaptor_Curve2d pc(edge, job.face);
    const double f = pc.FirstParameter(), l = pc.LastParameter();
    for (int k = 0; k < 256; ++k) {
      Bnd_Box2d box;
      BndLib_Add2dCurve::Add(pc, f + (l - f) * k / 256, f + (l - f) * (k + 1) / 256, 0.0, box);
      if (box.IsVoid()) continue;
      double a0, b0, a1, b1;
      box.Get(a0, b0, a1, b1);
      const double eu = 1e-3 * du, ev = 1e-3 * dv;
      const int i0 = std::clamp(static_cast<int>(std::floor((a0 - eu - job.u0) / du)), 0, nu - 1);
      const int i1 = std::clamp(static_cast<int>(std::floor((a1 + eu - job.u0) / du)), 0, nu - 1);
      const int j0 = std::clamp(static_cast<int>(std::floor((b0 - ev - job.v0) / dv)), 0, nv - 1);
      const int j1 = std::clamp(static_cast<int>(std::floor((b1 + ev - job.v0) / dv)), 0, nv - 1);
      for (int i = i0; i <= i1; ++i)
        for (int j = j0; j <= j1; ++j) job.boundary[static_cast<std::size_t>(i * nv + j)] = 1;
    }
  }
}

constexpr int kMaxPerCellSide = 4000;

void sample_cell(const FaceJob& job, GeomAdaptor_Surface& surf, const Handle(Geom_Surface) & geom,
                 BRepTopAdaptor_FClass2d& inside, int i, int j, double spacing,
                 std::vector<Sample>& out) {
  const double du = (job.u1 - job.u0) / job.cu, dv = (job.v1 - job.v0) / job.cv;
  const double a0 = job.u0 + i * du, b0 = job.v0 + j * dv;
  double mu = 0, mv = 0;
  for (int s = 0; s <= 2; ++s) {
    for (int t = 0; t <= 2; ++t) {
      gp_Pnt p;
      gp_Vec su, sv;
      surf.D1(a0 + du * s / 2, b0 + dv * t / 2, p, su, sv);
      mu = std::max(mu, su.Magnitude());
      mv = std::max(mv, sv.Magnitude());
    }
  }
  // 1.3: the speed may peak between the 3 x 3 points seen.
  const int nu =
      std::clamp(static_cast<int>(std::ceil(1.3 * mu * du / spacing)), 1, kMaxPerCellSide);
  const int nv =
      std::clamp(static_cast<int>(std::ceil(1.3 * mv * dv / spacing)), 1, kMaxPerCellSide);
  const bool flip = job.face.Orientation() == TopAbs_REVERSED;
  // Per sub-cell: 1 boundary (classify each point), else its centre's answer.
  const int snv = job.cv * kSub;
  signed char state[kSub][kSub];
  for (int a = 0; a < kSub; ++a)
    for (int b = 0; b < kSub; ++b) {
      const int gi = i * kSub + a, gj = j * kSub + b;
      if (job.boundary[static_cast<std::size_t>(gi * snv + gj)]) {
        state[a][b] = 1;
        continue;
      }
      const TopAbs_State st =
          inside.Perform(gp_Pnt2d(a0 + du * (a + 0.5) / kSub, b0 + dv * (b + 0.5) / kSub));
      state[a][b] = st == TopAbs_IN || st == TopAbs_ON ? 2 : 0;
    }
  for (int a = 0; a < nu; ++a) {
    const double u = a0 + du * (a + 0.5) / nu;
    for (int b = 0; b < nv; ++b) {
      const double v = b0 + dv * (b + 0.5) / nv;
      const int sa = std::min(kSub - 1, (2 * a + 1) * kSub / (2 * nu));
      const int sb = std::min(kSub - 1, (2 * b + 1) * kSub / (2 * nv));
      if (state[sa][sb] == 0) continue;
      if (state[sa][sb] == 1) {
        const TopAbs_State st = inside.Perform(gp_Pnt2d(u, v));
        if (st != TopAbs_IN && st != TopAbs_ON) continue;
      }
      gp_Pnt p;
      gp_Vec su, sv;
      surf.D1(u, v, p, su, sv);
      gp_Vec n = su.Crossed(sv);
      Sample s;
      s.p = {p.X(), p.Y(), p.Z()};
      s.area = static_cast<float>(n.Magnitude() * (du / nu) * (dv / nv));
      s.face = job.number;
      s.picked = job.picked;
      s.open = job.open;
      bool ok = n.Magnitude() > 1e-12 * (1 + su.Magnitude() * sv.Magnitude());
      if (!ok) {  // a pole or other degenerate point: ask for the limit normal
        GeomLProp_SLProps props(geom, u, v, 1, 1e-9);
        if (props.IsNormalDefined()) {
          n = gp_Vec(props.Normal());
          ok = true;
        }
      }
      if (ok) {
        n.Normalize();
        if (flip) n.Reverse();
        s.n = {static_cast<float>(n.X()), static_cast<float>(n.Y()), static_cast<float>(n.Z())};
      }
      out.push_back(s);
    }
  }
}

}  // namespace

std::vector<Sample> sample_faces(const TopoDS_Shape& shape, const std::vector<int>& picked,
                                 double spacing, int threads) {
  if (!(spacing > 0)) throw std::runtime_error("spacing must be > 0");
  const std::vector<TopoDS_Shape> faces = faces_of(shape);
  for (int k : picked)
    if (k < 1 || k > static_cast<int>(faces.size()))
      throw std::runtime_error("face " + std::to_string(k) + " does not exist: the model has " +
                               std::to_string(faces.size()) + " faces");
  // Faces that bound no solid (open faces): a tool may be on either side.
  TopTools_IndexedDataMapOfShapeListOfShape solids;
  TopExp::MapShapesAndAncestors(shape, TopAbs_FACE, TopAbs_SOLID, solids);
  std::vector<FaceJob> jobs;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    FaceJob job;
    job.face = TopoDS::Face(faces[f]);
    job.number = static_cast<int>(f) + 1;
    job.picked = std::find(picked.begin(), picked.end(), job.number) != picked.end();
    const int in_solids = solids.FindIndex(job.face);
    job.open = in_solids == 0 || solids(in_solids).IsEmpty();
    BRepTools::UVBounds(job.face, job.u0, job.u1, job.v0, job.v1);
    // Cells of about 2 mm, from the lengths of a 9 x 9 net of iso-lines.
    Handle(Geom_Surface) geom = BRep_Tool::Surface(job.face);
    if (geom.IsNull())
      throw std::runtime_error("face " + std::to_string(job.number) + " has no surface");
    double lu = 0, lv = 0;
    for (int a = 0; a <= 8; ++a) {
      double su = 0, sv = 0;
      gp_Pnt pu0 = geom->Value(job.u0, job.v0 + (job.v1 - job.v0) * a / 8);
      gp_Pnt pv0 = geom->Value(job.u0 + (job.u1 - job.u0) * a / 8, job.v0);
      for (int b = 1; b <= 32; ++b) {
        gp_Pnt pu =
            geom->Value(job.u0 + (job.u1 - job.u0) * b / 32, job.v0 + (job.v1 - job.v0) * a / 8);
        gp_Pnt pv =
            geom->Value(job.u0 + (job.u1 - job.u0) * a / 8, job.v0 + (job.v1 - job.v0) * b / 32);
        su += pu.Distance(pu0);
        sv += pv.Distance(pv0);
        pu0 = pu;
        pv0 = pv;
      }
      lu = std::max(lu, su);
      lv = std::max(lv, sv);
    }
    job.cu = std::clamp(static_cast<int>(std::ceil(lu / 2.0)), 1, 1000);
    job.cv = std::clamp(static_cast<int>(std::ceil(lv / 2.0)), 1, 1000);
    mark_boundary_cells(job);
    jobs.push_back(job);
  }
  // Work items: (face, cell row); results kept in order for reproducibility.
  std::vector<std::pair<int, int>> items;
  for (std::size_t f = 0; f < jobs.size(); ++f)
    for (int i = 0; i < jobs[f].cu; ++i) items.emplace_back(static_cast<int>(f), i);
  std::vector<std::vector<Sample>> parts(items.size());
  std::atomic<std::size_t> next{0};
  std::string error;
  std::atomic<bool> failed{false};
  auto worker = [&]() {
    int face = -1;
    GeomAdaptor_Surface surf;
    Handle(Geom_Surface) geom;
    std::unique_ptr<BRepTopAdaptor_FClass2d> inside;
    try {
      for (std::size_t k; (k = next++) < items.size() && !failed;) {
        const FaceJob& job = jobs[static_cast<std::size_t>(items[k].first)];
        if (items[k].first != face) {
          face = items[k].first;
          geom = BRep_Tool::Surface(job.face);
          surf.Load(geom);
          inside = std::make_unique<BRepTopAdaptor_FClass2d>(job.face, 1e-7);
        }
        for (int j = 0; j < job.cv; ++j)
          sample_cell(job, surf, geom, *inside, items[k].second, j, spacing, parts[k]);
      }
    } catch (const Standard_Failure& e) {
      if (!failed.exchange(true))
        error = std::string("OpenCASCADE failed while sampling: ") + e.GetMessageString();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failed) throw std::runtime_error(error);
  std::vector<Sample> all;
  std::size_t total = 0;
  for (const auto& p : parts) total += p.size();
  all.reserve(total);
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}

}  // namespace gsim
