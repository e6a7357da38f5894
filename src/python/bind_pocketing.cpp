// Bindings of spiral pocketing and z-level roughing (isocam/pocketing.h,
// isocam/pocket_check.h). Converts arguments, releases the GIL, calls the
// core, returns flat numpy arrays. No algorithm lives here.
//
// Profiles cross as float64 arrays of shape (M, 5), one row per segment:
// (x, y, cx, cy, dir): the segment starts at (x, y) and ends at the next
// row's (x, y) (the last at the first's); dir 0 is a line (cx, cy ignored,
// NaN when returned), +1 an arc counter-clockwise about (cx, cy), -1 clockwise.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Standard_Failure.hxx>
#include <cmath>
#include <limits>
#include <memory>
#include <string>

#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "isocam/pocket_check.h"
#include "isocam/pocketing.h"
#include "path_arrays.h"

namespace py = pybind11;

namespace {

using namespace isocam;

struct PyPocketResult {
  py::array_t<std::uint8_t> kind;
  py::array_t<double> xyz, centre;
  PocketMetrics metrics;
  std::vector<std::string> warnings;
};

PyPocketResult to_python(PocketResult&& r) {
  PyPocketResult out;
  out.kind = py_path::kind_array(r.path);
  out.xyz = py_path::xyz_array(r.path);
  out.centre = py_path::centre_array(r.path);
  out.metrics = std::move(r.metrics);
  out.warnings = std::move(r.warnings);
  return out;
}

// Runs `f` with the GIL released, OpenCASCADE failures as GeometryError.
template <class F>
PocketResult run(F&& f) {
  py::gil_scoped_release release;
  try {
    return f();
  } catch (const Standard_Failure& e) {
    throw GeometryError(std::string("OpenCASCADE failed: ") + e.GetMessageString());
  }
}

Loop profile_from_array(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                        const std::string& name) {
  if (a.ndim() != 2 || a.shape(1) != 5)
    throw InvalidArgument(name +
                          ": a profile must be a float array of shape (M, 5): x, y, cx, cy, dir");
  const auto m = static_cast<std::size_t>(a.shape(0));
  if (m < 1) throw InvalidArgument(name + ": a profile needs at least one segment");
  auto v = a.unchecked<2>();
  Loop loop;
  for (std::size_t i = 0; i < m; ++i) {
    const auto r = static_cast<py::ssize_t>(i), nx = static_cast<py::ssize_t>((i + 1) % m);
    const double dir = v(r, 4);
    // The centre columns of a line are ignored (NaN there is fine).
    for (int c : {0, 1, 4})
      if (!std::isfinite(v(r, c))) throw InvalidArgument(name + ": a profile value is not finite");
    if (dir != 0.0 && !(std::isfinite(v(r, 2)) && std::isfinite(v(r, 3))))
      throw InvalidArgument(name + ": an arc's centre is not finite");
    const P2 from{v(r, 0), v(r, 1)}, to{v(nx, 0), v(nx, 1)};
    if (dir == 0.0) {
      loop.push_back(Seg::line(from, to));
    } else if (dir == 1.0 || dir == -1.0) {
      loop.push_back(Seg::arc_between({v(r, 2), v(r, 3)}, from, to, dir > 0));
    } else {
      throw InvalidArgument(name + ": dir must be 0 (line), 1 (ccw arc) or -1 (cw arc)");
    }
  }
  return loop;
}

py::array_t<double> array_from_profile(const Loop& loop) {
  py::array_t<double> a({static_cast<py::ssize_t>(loop.size()), py::ssize_t(5)});
  auto v = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    const Seg& s = loop[i];
    v(r, 0) = s.a.x;
    v(r, 1) = s.a.y;
    const bool arc = s.kind == SegKind::Arc;
    v(r, 2) = arc ? s.c.x : std::numeric_limits<double>::quiet_NaN();
    v(r, 3) = arc ? s.c.y : std::numeric_limits<double>::quiet_NaN();
    v(r, 4) = arc ? (s.sweep > 0 ? 1.0 : -1.0) : 0.0;
  }
  return a;
}

using ProfileArray = py_path::DoubleArray;

std::vector<Loop> region_from_arrays(const std::vector<ProfileArray>& profiles) {
  std::vector<Loop> region;
  for (std::size_t i = 0; i < profiles.size(); ++i)
    region.push_back(profile_from_array(profiles[i], "profiles[" + std::to_string(i) + "]"));
  return region;
}

}  // namespace

void bind_pocketing(py::module_& m) {
  py::enum_<CutDirection>(m, "CutDirection")
      .value("Climb", CutDirection::Climb)
      .value("Conventional", CutDirection::Conventional);

  py::class_<PocketParams>(m, "PocketParams", "Parameters of spiral pocketing (mm)")
      .def(py::init<>())
      .def_readwrite("tool_radius", &PocketParams::tool_radius)
      .def_readwrite("stepover", &PocketParams::stepover, "path interval on a flat floor, mm")
      .def_readwrite("tolerance", &PocketParams::tolerance,
                     "free curves to arcs, and the plan-view deviation epsilon of CL points")
      .def_readwrite("floor_tolerance", &PocketParams::floor_tolerance,
                     "floor deviation delta of CL points")
      .def_readwrite("scallop_height", &PocketParams::scallop_height, "sculptured floor")
      .def_readwrite("direction", &PocketParams::direction)
      .def_readwrite("safe_z", &PocketParams::safe_z)
      .def_readwrite("min_arc_chord", &PocketParams::min_arc_chord)
      .def_readwrite("max_moves", &PocketParams::max_moves,
                     "work budget: a job estimated to need more moves is refused");

  py::class_<PocketMetrics>(m, "PocketMetrics")
      .def_readonly("cutting_length", &PocketMetrics::cutting_length)
      .def_readonly("rapid_length", &PocketMetrics::rapid_length)
      .def_readonly("plunge_length", &PocketMetrics::plunge_length)
      .def_readonly("retracts", &PocketMetrics::retracts)
      .def_readonly("feed_links", &PocketMetrics::feed_links)
      .def_readonly("loops", &PocketMetrics::loops)
      .def_readonly("levels", &PocketMetrics::levels)
      .def_readonly("tree_depth", &PocketMetrics::tree_depth)
      .def_readonly("arcs", &PocketMetrics::arcs)
      .def_readonly("cl_points", &PocketMetrics::cl_points)
      .def_readonly("min_interval", &PocketMetrics::min_interval)
      .def_readonly("max_interval", &PocketMetrics::max_interval)
      .def_readonly("reduced_intervals", &PocketMetrics::reduced_intervals)
      .def_readonly("warnings", &PocketMetrics::warnings, "faces skipped (count)");

  py::class_<PyPocketResult>(m, "PocketResult")
      .def_readonly("kind", &PyPocketResult::kind,
                    "uint8 (N,): RAPID, FEED, PLUNGE, ARC_CW (G2), ARC_CCW (G3)")
      .def_readonly("xyz", &PyPocketResult::xyz, "float64 (N,3): move end points, tool tip, mm")
      .def_readonly("centre", &PyPocketResult::centre,
                    "float64 (N,2): arc centres (NaN for other moves)")
      .def_readonly("metrics", &PyPocketResult::metrics)
      .def_readonly("warnings", &PyPocketResult::warnings,
                    "list of str: the faces skipped, each with its reason (as finishing)");

  m.def(
      "pocket_faces",
      [](const std::string& brep, const std::vector<int>& faces, const PocketParams& params,
         const std::vector<double>& depths, bool ball_end, std::shared_ptr<Progress> progress) {
        FacePocketParams fp;
        fp.pocket = params;
        fp.depths = depths;
        fp.ball_end = ball_end;
        return to_python(
            run([&] { return pocket_faces(read_brep(brep), faces, fp, progress.get()); }));
      },
      py::arg("brep"), py::arg("faces"), py::arg("params"), py::arg("depths"),
      py::arg("ball_end") = false, py::arg("progress") = nullptr,
      "Spiral pocketing (Suh & Lee) of the floor faces (0-based FaceN-1 indices) of the B-rep "
      "text\n"
      "at the z levels `depths` (top to bottom). Islands: the floors' inner wires and the "
      "material\n"
      "of the shape's solids above each level. A non-planar floor needs ball_end=True.\n"
      "Faces that cannot be pocketed are reported in the result's warnings.");

  m.def(
      "zlevel_roughing",
      [](const std::string& model, const std::string& stock, const PocketParams& params,
         const std::vector<double>& depths, double stock_to_leave,
         std::shared_ptr<Progress> progress) {
        RoughingParams rp;
        rp.pocket = params;
        rp.depths = depths;
        rp.stock_to_leave = stock_to_leave;
        return to_python(run([&] {
          return zlevel_roughing(read_brep(model), read_brep(stock), rp, progress.get());
        }));
      },
      py::arg("model"), py::arg("stock"), py::arg("params"), py::arg("depths"),
      py::arg("stock_to_leave") = 0.5, py::arg("progress") = nullptr,
      "Z-level roughing: at each level, the region between the stock's outline and the model's\n"
      "material grown by the tool radius + stock_to_leave, cleared by spiral pocketing.");

  m.def(
      "spiral_pocket",
      [](const ProfileArray& boundary, const std::vector<ProfileArray>& islands,
         const PocketParams& params, const std::vector<double>& depths,
         std::shared_ptr<Progress> progress) {
        const Loop b = profile_from_array(boundary, "boundary");
        std::vector<Loop> isl;
        for (std::size_t i = 0; i < islands.size(); ++i)
          isl.push_back(profile_from_array(islands[i], "islands[" + std::to_string(i) + "]"));
        const std::vector<Loop> region = make_region(b, isl);
        return to_python(
            run([&] { return spiral_pocket(region, depths, params, progress.get()); }));
      },
      py::arg("boundary"), py::arg("islands"), py::arg("params"), py::arg("depths"),
      py::arg("progress") = nullptr,
      "Spiral pocketing of a region given as profiles: arrays (M, 5) of rows (x, y, cx, cy, dir),\n"
      "dir 0 line, +1 ccw arc, -1 cw arc about (cx, cy), each segment ending at the next row.");

  m.def(
      "face_region",
      [](const std::string& brep, int face, double tolerance) {
        std::vector<Loop> region;
        {
          py::gil_scoped_release release;
          const std::vector<TopoDS_Face> faces = faces_of(read_brep(brep));
          if (face < 0 || face >= static_cast<int>(faces.size()))
            throw InvalidArgument("face: index " + std::to_string(face) +
                                  " is out of range (0-based)");
          region = face_region(faces[static_cast<std::size_t>(face)], tolerance);
        }
        std::vector<py::array_t<double>> out;
        for (const Loop& l : region) out.push_back(array_from_profile(l));
        return out;
      },
      py::arg("brep"), py::arg("face"), py::arg("tolerance"),
      "The face's outline projected on XY as profiles (outer first, counter-clockwise; islands\n"
      "clockwise), free curves as arcs within `tolerance`.");

  m.def(
      "pocket_coverage",
      [](const std::vector<ProfileArray>& profiles, const py::array_t<std::uint8_t>& kind,
         const ProfileArray& xyz, const ProfileArray& centre, double tool_radius, double z_floor,
         double cell, double tolerance) {
        const std::vector<Loop> region = region_from_arrays(profiles);
        const Toolpath path = py_path::path_from_arrays(kind, xyz, centre);
        CoverageParams cp;
        cp.tool_radius = tool_radius;
        cp.cell = cell;
        cp.tolerance = tolerance;
        cp.z_floor = z_floor;
        cp.z_tolerance = 1e-3;
        CoverageReport c;
        ClearanceReport cl;
        {
          py::gil_scoped_release release;
          c = pocket_coverage(region, path, cp);
          cl = pocket_clearance(region, path, z_floor, std::max(cell * 0.5, 0.01), 1e-3);
        }
        py::dict d;
        d["region_area"] = c.region_area;
        d["uncut_area"] = c.uncut_area;
        d["uncut_reachable_area"] = c.uncut_reachable_area;
        d["unreachable_area"] = c.unreachable_area;
        d["min_clearance"] = cl.min_distance;
        d["outside_samples"] = cl.outside;
        return d;
      },
      py::arg("profiles"), py::arg("kind"), py::arg("xyz"), py::arg("centre"),
      py::arg("tool_radius"), py::arg("z_floor"), py::arg("cell") = 0.1,
      py::arg("tolerance") = 1e-3,
      "Raster check of a pocketing path (any origin, e.g. FreeCAD's own operations) against its\n"
      "region: uncut area, of it the part a tool of this radius could reach, unreachable corners,\n"
      "and the tool centre's smallest clearance to the region's walls at the floor height.");
}
