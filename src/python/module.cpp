// The one pybind11 module: converts arguments, releases the GIL, calls the
// core, returns flat numpy arrays (ENGINEERING.md, habits 2-4). No algorithm
// lives here.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Standard_Failure.hxx>
#include <algorithm>
#include <memory>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "isocam/adaptive_isocurve.h"
#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "path_arrays.h"

namespace py = pybind11;
using namespace isocam;

void bind_pocketing(py::module_& m);  // bind_pocketing.cpp
void bind_five_axis(py::module_& m);  // bind_five_axis.cpp

namespace {

const char* direction_name(IsoDirection d) {
  return d == IsoDirection::U ? "U" : d == IsoDirection::V ? "V" : "Auto";
}

struct PyIsoResult {
  py::array_t<std::uint8_t> kind;
  py::array_t<double> xyz;
  IsoMetrics metrics;
  std::vector<std::string> face_direction;
  std::vector<SubIsocurve> curves;
  std::vector<std::string> warnings;
  IsoPlaneAxis plane_axis = IsoPlaneAxis::Auto;
  std::vector<int> skipped_faces;
};

PyIsoResult to_python(IsoResult&& r) {
  PyIsoResult out;
  out.kind = py_path::kind_array(r.path);
  out.xyz = py_path::xyz_array(r.path);
  out.metrics = r.metrics;
  for (IsoDirection d : r.face_direction) out.face_direction.emplace_back(direction_name(d));
  out.curves = std::move(r.curves);
  out.warnings = std::move(r.warnings);
  out.plane_axis = r.plane_axis;
  out.skipped_faces = std::move(r.skipped_faces);
  return out;
}

PyIsoResult run_adaptive(const std::string& brep, const std::vector<int>& faces,
                         const IsoParams& params, Progress* progress) {
  IsoResult r;
  {
    py::gil_scoped_release release;
    try {
      const TopoDS_Shape shape = read_brep(brep);
      r = adaptive_isocurve(shape, faces, params, progress);
    } catch (const Standard_Failure& e) {
      throw GeometryError(std::string("OpenCASCADE failed: ") + e.GetMessageString());
    }
  }
  return to_python(std::move(r));
}

// The names a caller of this module sets: the fields of the bound classes
// (IsoParams.scallop_height, PocketParams.tolerance, ...) and the functions'
// own arguments (brep, faces, depths, ...), read from the bound module
// itself (properties of its classes; the signature pybind11 writes as the
// first line of each function's docstring), so that no list is kept by hand.
std::set<std::string> argument_names(const py::module_& m) {
  std::set<std::string> names;
  const std::regex parameter(R"(([A-Za-z_][A-Za-z0-9_]*)\s*:)");
  const py::object property = py::module_::import("builtins").attr("property");
  for (const auto item : m.attr("__dict__").cast<py::dict>()) {
    const py::object value = py::reinterpret_borrow<py::object>(item.second);
    if (py::isinstance<py::type>(value)) {
      for (const auto member : value.attr("__dict__").cast<py::dict>())
        if (py::isinstance(member.second, property)) names.insert(py::str(member.first));
    } else if (py::hasattr(value, "__doc__") && PyCallable_Check(value.ptr())) {
      const py::object doc = value.attr("__doc__");
      if (doc.is_none()) continue;
      const std::string text = py::str(doc);
      const std::string signature = text.substr(0, text.find(')'));
      const auto open = signature.find('(');
      if (open == std::string::npos) continue;
      for (std::sregex_iterator it(signature.begin() + static_cast<std::ptrdiff_t>(open),
                                   signature.end(), parameter),
           end;
           it != end; ++it)
        names.insert((*it)[1]);
    }
  }
  return names;
}

// The names of `known` that `message` mentions as whole words, in order:
// the core's InvalidArgument messages name the arguments they are about
// (isocam/errors.h), e.g. "chord_tolerance (...) does not fit
// overcut_tolerance (...)".
py::tuple arguments_named(const std::string& message, const std::set<std::string>& known) {
  const std::regex word(R"([A-Za-z_][A-Za-z0-9_]*)");
  std::vector<std::string> found;
  for (std::sregex_iterator it(message.begin(), message.end(), word), end; it != end; ++it) {
    const std::string name = it->str();
    if (known.count(name) && std::find(found.begin(), found.end(), name) == found.end())
      found.push_back(name);
  }
  return py::cast(found);
}

}  // namespace

PYBIND11_MODULE(isocam_core, m) {
  m.doc() = "IsoCAM core: adaptive isocurve finishing (Elber & Cohen) for ball-end tools";

  static py::exception<Cancelled> cancelled(m, "CancelledError", PyExc_RuntimeError);
  // InvalidArgument -> InvalidArgumentError, a ValueError whose `arguments`
  // are the names (fields of the parameter classes, arguments of the
  // functions) its message is about, for a caller to map to its own inputs.
  static py::exception<InvalidArgument> invalid(m, "InvalidArgumentError", PyExc_ValueError);
  static std::set<std::string> known;  // filled once the module is bound
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InvalidArgument& e) {
      py::object error = py::handle(invalid.ptr())(e.what());
      error.attr("arguments") = arguments_named(e.what(), known);
      PyErr_SetObject(invalid.ptr(), error.ptr());
    } catch (const Cancelled& e) {
      // The C API call, not cancelled(e.what()): pybind11 2.12 deprecates
      // that call operator, and its replacement py::set_error is not in 2.10.
      PyErr_SetString(cancelled.ptr(), e.what());
    } catch (const GeometryError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });

  py::enum_<IsoDirection>(m, "IsoDirection")
      .value("Auto", IsoDirection::Auto)
      .value("U", IsoDirection::U)
      .value("V", IsoDirection::V);
  py::enum_<IsoPattern>(m, "IsoPattern")
      .value("Adaptive", IsoPattern::Adaptive)
      .value("Uniform", IsoPattern::Uniform)
      .value("ParallelPlanes", IsoPattern::ParallelPlanes)
      .value("ConstantScallop", IsoPattern::ConstantScallop);
  py::enum_<IsoPlaneAxis>(m, "IsoPlaneAxis")
      .value("Auto", IsoPlaneAxis::Auto)
      .value("X", IsoPlaneAxis::X)
      .value("Y", IsoPlaneAxis::Y);
  py::enum_<IsoScallopBound>(m, "IsoScallopBound")
      .value("Flat", IsoScallopBound::Flat)
      .value("Curvature", IsoScallopBound::Curvature);

  py::class_<IsoParams>(m, "IsoParams", "Parameters of adaptive isocurve finishing (mm)")
      .def(py::init<>())
      .def_readwrite("ball_radius", &IsoParams::ball_radius)
      .def_readwrite("scallop_height", &IsoParams::scallop_height)
      .def_readwrite("overcut_tolerance", &IsoParams::overcut_tolerance)
      .def_readwrite("chord_tolerance", &IsoParams::chord_tolerance, "0: derived from the budgets")
      .def_readwrite("posted_resolution", &IsoParams::posted_resolution)
      .def_readwrite("air_clearance", &IsoParams::air_clearance)
      .def_readwrite("feed_rate", &IsoParams::feed_rate, "mm/min")
      .def_readwrite("plunge_rate", &IsoParams::plunge_rate, "mm/min")
      .def_readwrite("rapid_rate", &IsoParams::rapid_rate, "mm/min")
      .def_readwrite("direction", &IsoParams::direction)
      .def_readwrite("pattern", &IsoParams::pattern)
      .def_readwrite("scallop_bound", &IsoParams::scallop_bound)
      .def_readwrite("plane_axis", &IsoParams::plane_axis)
      .def_readwrite("safe_z", &IsoParams::safe_z)
      .def_readwrite("max_depth", &IsoParams::max_depth)
      .def_readwrite("gouge_tolerance", &IsoParams::gouge_tolerance)
      .def_readwrite("protect_unpicked_faces", &IsoParams::protect_unpicked_faces)
      .def_readwrite("threads", &IsoParams::threads)
      .def_readwrite("min_param_gap", &IsoParams::min_param_gap)
      .def_readwrite("max_moves", &IsoParams::max_moves,
                     "work budget: a job estimated to need more moves is refused");

  py::class_<Progress, std::shared_ptr<Progress>>(
      m, "Progress", "Shared progress/cancel flag; poll .fraction from another thread")
      .def(py::init<>())
      .def("cancel", &Progress::request_cancel)
      .def_property_readonly("fraction", [](const Progress& p) { return p.fraction.load(); })
      .def_property_readonly("cancelled",
                             [](const Progress& p) { return p.cancel_requested.load(); });

  py::class_<IsoMetrics>(m, "IsoMetrics")
      .def_readonly("delta", &IsoMetrics::delta)
      .def_readonly("delta_max", &IsoMetrics::delta_max)
      .def_readonly("cutting_length", &IsoMetrics::cutting_length)
      .def_readonly("rapid_length", &IsoMetrics::rapid_length)
      .def_readonly("plunge_length", &IsoMetrics::plunge_length)
      .def_readonly("sub_isocurves", &IsoMetrics::sub_isocurves)
      .def_readonly("retracts", &IsoMetrics::retracts)
      .def_readonly("max_iso_distance", &IsoMetrics::max_iso_distance)
      .def_readonly("guaranteed_scallop", &IsoMetrics::guaranteed_scallop)
      .def_readonly("guaranteed_overcut", &IsoMetrics::guaranteed_overcut)
      .def_readonly("chord_tolerance", &IsoMetrics::chord_tolerance)
      .def_readonly("machine_time", &IsoMetrics::machine_time, "s")
      .def_readonly("cutting_time", &IsoMetrics::cutting_time, "s")
      .def_readonly("unreachable_length", &IsoMetrics::unreachable_length)
      .def_readonly("unreachable_from_above_length", &IsoMetrics::unreachable_from_above_length)
      .def_readonly("lower_bound_length", &IsoMetrics::lower_bound_length);

  py::class_<SubIsocurve>(m, "SubIsocurve")
      .def_readonly("face", &SubIsocurve::face)
      .def_property_readonly("direction",
                             [](const SubIsocurve& c) { return direction_name(c.dir); })
      .def_readonly("level", &SubIsocurve::level)
      .def_readonly("t0", &SubIsocurve::t0)
      .def_readonly("t1", &SubIsocurve::t1);

  py::class_<PyIsoResult>(m, "IsoResult")
      .def_readonly("kind", &PyIsoResult::kind, "uint8 (N,): RAPID, FEED, PLUNGE, RAMP")
      .def_readonly("xyz", &PyIsoResult::xyz, "float64 (N,3): move end points, tool tip, mm")
      .def_readonly("metrics", &PyIsoResult::metrics)
      .def_readonly("face_direction", &PyIsoResult::face_direction)
      .def_readonly("curves", &PyIsoResult::curves)
      .def_readonly("warnings", &PyIsoResult::warnings)
      .def_readonly("plane_axis", &PyIsoResult::plane_axis, "ParallelPlanes: the axis used")
      .def_readonly("skipped_faces", &PyIsoResult::skipped_faces,
                    "picked faces (0-based indices in the shape) the geometry defeated: no path "
                    "on them; `warnings` says why");

  py_path::bind_move_kinds(m);

  m.def("stepover_for_scallop", &stepover_for_scallop, py::arg("ball_radius"),
        py::arg("scallop_height"), "Flat-ground stepover delta = 2 sqrt(2 r h - h^2)");
  m.def("scallop_for_stepover", &scallop_for_stepover, py::arg("ball_radius"), py::arg("delta"));
  m.def(
      "adaptive_isocurve",
      [](const std::string& brep, const std::vector<int>& faces, const IsoParams& params,
         std::shared_ptr<Progress> progress) {
        return run_adaptive(brep, faces, params, progress.get());
      },
      py::arg("brep"), py::arg("faces"), py::arg("params"), py::arg("progress") = nullptr,
      "Adaptive isocurve finishing of the faces (0-based FaceN-1 indices) of the B-rep text.\n"
      "Raises ValueError for bad arguments, RuntimeError for geometry failures,\n"
      "CancelledError when progress.cancel() was called.");
  bind_pocketing(m);
  bind_five_axis(m);
  known = argument_names(m);
}
