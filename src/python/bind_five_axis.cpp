// Bindings of 5-axis strip finishing (isocam/five_axis.h): parameters in,
// flat numpy arrays out (move kind, tip xyz, axis ijk, rotary a c).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Standard_Failure.hxx>
#include <memory>

#include "isocam/brep_io.h"
#include "isocam/errors.h"
#include "isocam/five_axis.h"
#include "path_arrays.h"

namespace py = pybind11;
using namespace isocam;

namespace {

struct PyFiveAxisResult {
  py::array_t<std::uint8_t> kind;
  py::array_t<double> xyz, ijk, ac;
  FiveAxisMetrics metrics;
  std::vector<std::string> warnings;
  std::vector<int> skipped_faces;
};

PyFiveAxisResult run(const std::string& brep, const std::vector<int>& faces,
                     const FiveAxisParams& params, Progress* progress) {
  FiveAxisResult r;
  {
    py::gil_scoped_release release;
    try {
      r = five_axis_finish(read_brep(brep), faces, params, progress);
    } catch (const Standard_Failure& e) {
      throw GeometryError(std::string("OpenCASCADE failed: ") + e.GetMessageString());
    }
  }
  PyFiveAxisResult out;
  out.kind = py_path::kind_array(r.path);
  out.xyz = py_path::xyz_array(r.path);
  out.ijk = py_path::columns(r.i, r.j, &r.k);
  out.ac = py_path::columns(r.a, r.c, nullptr);
  out.metrics = r.metrics;
  out.warnings = std::move(r.warnings);
  out.skipped_faces = std::move(r.skipped_faces);
  return out;
}

}  // namespace

void bind_five_axis(py::module_& m) {
  py::enum_<FiveAxisStrategy>(m, "FiveAxisStrategy")
      .value("StripEvaluation", FiveAxisStrategy::StripEvaluation)
      .value("NormalIsocurves", FiveAxisStrategy::NormalIsocurves);
  py::class_<FiveAxisParams>(m, "FiveAxisParams",
                             "Parameters of 5-axis strip finishing (mm, degrees)")
      .def(py::init<>())
      .def_readwrite("tool_radius", &FiveAxisParams::tool_radius)
      .def_readwrite("corner_radius", &FiveAxisParams::corner_radius,
                     "mm, 0 <= rc < tool_radius: 0 a flat end, > 0 a bull nose")
      .def_readwrite("tool_length", &FiveAxisParams::tool_length)
      .def_readwrite("lead_angle", &FiveAxisParams::lead_angle, "degrees")
      .def_readwrite("tilt_angle", &FiveAxisParams::tilt_angle, "degrees")
      .def_readwrite("max_lead_angle", &FiveAxisParams::max_lead_angle, "degrees")
      .def_readwrite("scallop_height", &FiveAxisParams::scallop_height)
      .def_readwrite("gouge_tolerance", &FiveAxisParams::gouge_tolerance)
      .def_readwrite("chord_tolerance", &FiveAxisParams::chord_tolerance, "0: derived")
      .def_readwrite("posted_resolution", &FiveAxisParams::posted_resolution)
      .def_readwrite("max_axis_step", &FiveAxisParams::max_axis_step, "degrees")
      .def_readwrite("a_min", &FiveAxisParams::a_min, "degrees")
      .def_readwrite("a_max", &FiveAxisParams::a_max, "degrees")
      .def_readwrite("direction", &FiveAxisParams::direction)
      .def_readwrite("strategy", &FiveAxisParams::strategy,
                     "StripEvaluation (Lee 1998) or NormalIsocurves (Elber & Cohen)")
      .def_readwrite("safe_z", &FiveAxisParams::safe_z)
      .def_readwrite("air_clearance", &FiveAxisParams::air_clearance)
      .def_readwrite("low_links", &FiveAxisParams::low_links,
                     "links between runs kept low where proven clear and quicker")
      .def_readwrite("lag_on_return", &FiveAxisParams::lag_on_return,
                     "passes run back keep the forward passes' tilt (the tool lags)")
      .def_readwrite("feed_rate", &FiveAxisParams::feed_rate, "mm/min")
      .def_readwrite("plunge_rate", &FiveAxisParams::plunge_rate, "mm/min")
      .def_readwrite("rapid_rate", &FiveAxisParams::rapid_rate, "mm/min")
      .def_readwrite("rotary_rate", &FiveAxisParams::rotary_rate, "deg/min (A and C)")
      .def_readwrite("protect_unpicked_faces", &FiveAxisParams::protect_unpicked_faces)
      .def_readwrite("max_moves", &FiveAxisParams::max_moves)
      .def_readwrite("threads", &FiveAxisParams::threads, "0: one per core");

  py::class_<FiveAxisMetrics>(m, "FiveAxisMetrics")
      .def_readonly("cutting_length", &FiveAxisMetrics::cutting_length)
      .def_readonly("rapid_length", &FiveAxisMetrics::rapid_length)
      .def_readonly("plunge_length", &FiveAxisMetrics::plunge_length)
      .def_readonly("machine_time", &FiveAxisMetrics::machine_time, "s")
      .def_readonly("cutting_time", &FiveAxisMetrics::cutting_time, "s")
      .def_readonly("rotary_travel_a", &FiveAxisMetrics::rotary_travel_a, "degrees")
      .def_readonly("rotary_travel_c", &FiveAxisMetrics::rotary_travel_c, "degrees")
      .def_readonly("chord_tolerance", &FiveAxisMetrics::chord_tolerance)
      .def_readonly("flat_strip_width", &FiveAxisMetrics::flat_strip_width)
      .def_readonly("max_spacing", &FiveAxisMetrics::max_spacing)
      .def_readonly("guaranteed_scallop", &FiveAxisMetrics::guaranteed_scallop)
      .def_readonly("guaranteed_overcut", &FiveAxisMetrics::guaranteed_overcut)
      .def_readonly("coverage_gap", &FiveAxisMetrics::coverage_gap)
      .def_readonly("unreachable_length", &FiveAxisMetrics::unreachable_length)
      .def_readonly("max_lead_used", &FiveAxisMetrics::max_lead_used, "degrees")
      .def_readonly("lead_raised_points", &FiveAxisMetrics::lead_raised_points)
      .def_readonly("unconverged_moves", &FiveAxisMetrics::unconverged_moves)
      .def_readonly("swings_split", &FiveAxisMetrics::swings_split)
      .def_readonly("isocurve_faces", &FiveAxisMetrics::isocurve_faces)
      .def_readonly("paths", &FiveAxisMetrics::paths)
      .def_readonly("retracts", &FiveAxisMetrics::retracts)
      .def_readonly("low_links", &FiveAxisMetrics::low_links)
      .def_readonly("safe_hops", &FiveAxisMetrics::safe_hops);

  py::class_<PyFiveAxisResult>(m, "FiveAxisResult")
      .def_readonly("kind", &PyFiveAxisResult::kind, "uint8 (N,): RAPID, FEED, PLUNGE")
      .def_readonly("xyz", &PyFiveAxisResult::xyz,
                    "float64 (N,3): tool tip (bottom face centre), mm")
      .def_readonly("ijk", &PyFiveAxisResult::ijk, "float64 (N,3): unit tool axis")
      .def_readonly("ac", &PyFiveAxisResult::ac,
                    "float64 (N,2): A, C (degrees), axis = (sinA sinC, -sinA cosC, cosA)")
      .def_readonly("metrics", &PyFiveAxisResult::metrics)
      .def_readonly("warnings", &PyFiveAxisResult::warnings)
      .def_readonly("skipped_faces", &PyFiveAxisResult::skipped_faces,
                    "picked faces (0-based indices in the shape) the geometry defeated: no path "
                    "on them; `warnings` says why");

  m.def(
      "five_axis_finish",
      [](const std::string& brep, const std::vector<int>& faces, const FiveAxisParams& params,
         std::shared_ptr<Progress> progress) { return run(brep, faces, params, progress.get()); },
      py::arg("brep"), py::arg("faces"), py::arg("params"), py::arg("progress") = nullptr,
      "5-axis strip finishing of the faces (0-based) with a tilted flat end or bull nose.\n"
      "Raises ValueError for bad arguments, RuntimeError for geometry failures.");
  m.def("flat_end_half_width", &flat_end_half_width, py::arg("radius"), py::arg("lead"),
        py::arg("tilt"), py::arg("kappa_across"), py::arg("h"));
  m.def("strip_half_width", &strip_half_width, py::arg("radius"), py::arg("corner_radius"),
        py::arg("lead"), py::arg("tilt"), py::arg("kappa_across"), py::arg("h"),
        "x_h (mm) of the tilted flat end (corner_radius 0) or bull nose, as five_axis.h says");
}
