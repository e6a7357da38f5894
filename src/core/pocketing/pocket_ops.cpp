// The operations on B-rep input: pocketing picked floor faces (islands from
// the floor's inner wires and from the material standing above each level,
// as FreeCAD's Pocket Shape), and z-level roughing between the stock and
// the model's manufacturing offset (Elber & Cohen section 4, Figure 4).
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <Bnd_Box.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "pocketing/floor_path.h"
#include "pocketing/pocket_emit.h"

namespace isocam {

using namespace pocket;

namespace {

// The k-th of n equal parts of a progress slice.
ProgressSlice part(const ProgressSlice& ps, std::size_t k, std::size_t n) {
  const double dn = static_cast<double>(n);
  return ps.sub(static_cast<double>(k) / dn, static_cast<double>(k + 1) / dn);
}

// Sections are taken this far above a level: material at the level itself
// (the floor) is not in the way of a tool whose tip is there.
double section_lift(const PocketParams& p) { return std::max(1e-3, 0.1 * p.tolerance); }

bool same_region(const std::vector<Loop>& a, const std::vector<Loop>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].size() != b[i].size()) return false;
    for (std::size_t j = 0; j < a[i].size(); ++j) {
      const Seg &s = a[i][j], &t = b[i][j];
      if (s.kind != t.kind || s.a.x != t.a.x || s.a.y != t.a.y || s.b.x != t.b.x ||
          s.b.y != t.b.y || s.c.x != t.c.x || s.c.y != t.c.y || s.r != t.r || s.sweep != t.sweep)
        return false;
    }
  }
  return true;
}

// Pockets `base` (outline and fixed islands) at each level, with the
// material of `model` at and above each level (plus `below` under it, grown
// by `grow`) as further islands; plans are reused while the region stays
// the same.
void pocket_levels(const std::vector<Loop>& base, const TopoDS_Shape& model,
                   const std::vector<double>& levels, double below, double grow,
                   const PocketParams& p, PocketResult& res, const ProgressSlice& progress) {
  std::vector<Loop> material, plan_region;
  FlatPlan plan;
  bool have_plan = false;
  const double lift = section_lift(p);
  for (std::size_t i = 0; i < levels.size(); ++i) {
    const ProgressSlice ps = part(progress, i, levels.size());
    const double z = levels[i];
    std::vector<Loop> sec = section_region(model, z - below + lift, p.tolerance);
    if (!sec.empty()) {
      sec.insert(sec.end(), material.begin(), material.end());
      material = resolve_loops(sec);
    }
    std::vector<Loop> region = base;
    const std::vector<Loop> islands = grow > 0 ? dilate_region(material, grow) : material;
    for (const Loop& l : islands) region.push_back(reversed(l));
    if (!have_plan || !same_region(region, plan_region)) {
      plan = make_flat_plan(region, p, default_snap(region), ps);
      plan_region = std::move(region);
      have_plan = true;
    }
    emit_flat_plan(plan, z, p, res.path, res.metrics);
    ++res.metrics.levels;
  }
}

struct FloorInfo {
  bool planar = false;    // a horizontal plane
  bool vertical = false;  // a plane containing Z: no floor
  double z = 0.0, zmin = 0.0, zmax = 0.0;
};

FloorInfo classify(const TopoDS_Face& face) {
  FloorInfo f;
  BRepAdaptor_Surface s(face, false);
  Bnd_Box box;
  BRepBndLib::AddOptimal(face, box, false, false);
  double x0, y0, x1, y1;
  box.Get(x0, y0, f.zmin, x1, y1, f.zmax);
  if (s.GetType() == GeomAbs_Plane) {
    const gp_Dir n = s.Plane().Axis().Direction();
    if (std::abs(std::abs(n.Z()) - 1.0) < 1e-9) {
      f.planar = true;
      f.z = s.Plane().Location().Z();
    } else if (std::abs(n.Z()) < 1e-9) {
      f.vertical = true;
    }
  }
  return f;
}

void check_has_solid(const TopoDS_Shape& shape, const std::string& name) {
  TopTools_IndexedMapOfShape solids, faces;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  if (solids.Extent() > 0) return;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  throw InvalidArgument(name + ": not a solid (it has " + std::to_string(faces.Extent()) +
                        " faces and no solid): Z-level roughing needs the material as a closed "
                        "solid, or it would cut through the model; make a solid of it first");
}

void note(PocketResult& res, const std::string& msg) {
  res.warnings.push_back(msg);
  ++res.metrics.warnings;
}

}  // namespace

PocketResult pocket_faces(const TopoDS_Shape& shape, const std::vector<int>& faces,
                          const FacePocketParams& fp, Progress* progress) {
  const PocketParams& p = fp.pocket;
  check_params(p, false);
  check_depths(fp.depths, p.safe_z);
  const std::vector<TopoDS_Face> all = faces_of(shape);
  if (all.empty()) throw InvalidArgument("shape: no faces in the B-rep");
  if (faces.empty()) throw InvalidArgument("faces: no face given");
  std::set<int> seen;
  for (int f : faces) {
    if (f < 0 || f >= static_cast<int>(all.size())) {
      std::ostringstream m;
      m << "faces: index " << f << " is out of range (the shape has " << all.size()
        << " faces, 0-based)";
      throw InvalidArgument(m.str());
    }
    if (!seen.insert(f).second)
      throw InvalidArgument("faces: face index " + std::to_string(f) + " is given twice");
  }
  const ProgressSlice ps(progress);
  PocketResult res;
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const ProgressSlice fs = part(ps, k, faces.size());
    const std::string name = "Face" + std::to_string(faces[k] + 1);
    const TopoDS_Face& face = all[static_cast<std::size_t>(faces[k])];
    try {
      const FloorInfo info = classify(face);
      if (info.vertical) {
        note(res, name + ": a vertical face is not a floor; skipped");
        continue;
      }
      const std::vector<Loop> base = face_region(face, p.tolerance);
      if (base.empty() || region_area(base) <= p.tolerance * p.tolerance) {
        note(res, name + ": the face has no area in plan view; skipped");
        continue;
      }
      const std::size_t before = res.path.size();
      if (info.planar) {
        pocket_levels(base, shape, fp.depths, 0.0, 0.0, p, res, fs);
      } else {
        if (!fp.ball_end) {
          note(res, name + ": a sculptured floor needs a ball-end tool; skipped");
          continue;
        }
        check_params(p, true);
        // Flat levels above the floor (where the model has solids, also
        // down through it: its material is an island there), then the ball
        // follows the floor.
        const bool solids =
            !section_region(shape, info.zmin + 0.5 * (info.zmax - info.zmin), p.tolerance).empty();
        const double z_stop = solids ? info.zmin : info.zmax;
        std::vector<double> above;
        for (double z : fp.depths)
          if (z > z_stop + 1e-6) above.push_back(z);
        if (!above.empty()) pocket_levels(base, shape, above, 0.0, 0.0, p, res, fs.sub(0.0, 0.5));
        sculptured_floor_pass({face}, base, p, res.path, res.metrics, fs.sub(0.5, 1.0));
        check_path_budget(res.path, p);
        ++res.metrics.levels;
      }
      if (res.path.size() == before) note(res, name + ": too small for the tool; nothing to cut");
    } catch (const GeometryError& e) {
      note(res, name + ": " + e.what());
    } catch (const Standard_Failure& e) {
      note(res, name + ": OpenCASCADE failed (" + e.GetMessageString() + ")");
    }
  }
  measure_path(res.path, res.metrics);
  ps.report(1.0);
  return res;
}

PocketResult zlevel_roughing(const TopoDS_Shape& model, const TopoDS_Shape& stock,
                             const RoughingParams& rp, Progress* progress) {
  const PocketParams& p = rp.pocket;
  check_params(p, false);
  check_depths(rp.depths, p.safe_z);
  if (!std::isfinite(rp.stock_to_leave) || rp.stock_to_leave < 0)
    throw InvalidArgument("stock_to_leave = " + std::to_string(rp.stock_to_leave) +
                          " is out of range: must be >= 0");
  if (model.IsNull()) throw InvalidArgument("model: empty shape");
  if (stock.IsNull()) throw InvalidArgument("stock: empty shape");
  // The material is what the model's solids enclose (section_region): a
  // model of faces, wires or vertices only encloses nothing, and the tool
  // would clear the stock straight through it.
  check_has_solid(model, "model");
  check_has_solid(stock, "stock");
  const ProgressSlice ps(progress);
  PocketResult res;
  const double lift = section_lift(p);
  std::vector<Loop> material, plan_region;
  FlatPlan plan;
  bool have_plan = false;
  try {
    for (std::size_t i = 0; i < rp.depths.size(); ++i) {
      const ProgressSlice ls = part(ps, i, rp.depths.size());
      const double z = rp.depths[i];
      // The outline of the stock grown by 2 r: the tool centres may go up
      // to r outside the stock, so that stock next to the model's offset
      // near the stock's edge is within reach (the outermost loop then
      // just touches the stock).
      const std::vector<Loop> outline = section_region(stock, z + lift, p.tolerance);
      // The model's material at and above the level (and stock_to_leave below).
      std::vector<Loop> sec = section_region(model, z - rp.stock_to_leave + lift, p.tolerance);
      if (!sec.empty()) {
        sec.insert(sec.end(), material.begin(), material.end());
        material = resolve_loops(sec);
      }
      if (outline.empty()) continue;
      std::vector<Loop> region = dilate_region(outline, 2.0 * p.tool_radius);
      const std::vector<Loop> keep =
          rp.stock_to_leave > 0 ? dilate_region(material, rp.stock_to_leave) : material;
      for (const Loop& l : keep) region.push_back(reversed(l));
      if (!have_plan || !same_region(region, plan_region)) {
        plan = make_flat_plan(region, p, default_snap(region), ls);
        plan_region = std::move(region);
        have_plan = true;
      }
      emit_flat_plan(plan, z, p, res.path, res.metrics);
      ++res.metrics.levels;
    }
  } catch (const Standard_Failure& e) {
    throw GeometryError(std::string("zlevel_roughing: OpenCASCADE failed (") +
                        e.GetMessageString() + ")");
  }
  measure_path(res.path, res.metrics);
  ps.report(1.0);
  return res;
}

}  // namespace isocam
