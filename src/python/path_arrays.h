// The one conversion between a Toolpath (isocam/toolpath.h) and numpy
// arrays, used by every operation's binding, and the move-kind constants.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <vector>

#include "isocam/toolpath.h"

namespace isocam::py_path {

namespace py = pybind11;

// uint8 (N,): the move kinds (module attributes RAPID ... RAMP).
py::array_t<std::uint8_t> kind_array(const Toolpath& path);
// float64 (N, 3): the move end points (tool tip, mm).
py::array_t<double> xyz_array(const Toolpath& path);
// float64 (N, 2): the arc centres, NaN for the moves that are not arcs (all
// of them when the path has none).
py::array_t<double> centre_array(const Toolpath& path);
// float64 (N, 2) or (N, 3) (c null): a, b (and c) as columns, all of a's size.
py::array_t<double> columns(const std::vector<double>& a, const std::vector<double>& b,
                            const std::vector<double>* c);

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
// The inverse: a path from kind (N,), xyz (N, 3) and centre (N, 2) (read for
// arcs only). Throws InvalidArgument for other shapes or unknown kinds.
Toolpath path_from_arrays(const py::array_t<std::uint8_t>& kind, const DoubleArray& xyz,
                          const DoubleArray& centre);

// Sets the module's RAPID, FEED, PLUNGE, ARC_CW, ARC_CCW, RAMP: plain ints
// (Python compares them with the kind arrays), the MoveKind values.
void bind_move_kinds(py::module_& m);

}  // namespace isocam::py_path
