#include "path_arrays.h"

#include <cstring>
#include <utility>

#include "isocam/errors.h"

namespace isocam::py_path {

py::array_t<std::uint8_t> kind_array(const Toolpath& path) {
  py::array_t<std::uint8_t> out(static_cast<py::ssize_t>(path.size()));
  if (!path.empty()) std::memcpy(out.mutable_data(), path.kind.data(), path.size());
  return out;
}

py::array_t<double> columns(const std::vector<double>& a, const std::vector<double>& b,
                            const std::vector<double>* c) {
  const auto n = static_cast<py::ssize_t>(a.size());
  const py::ssize_t w = c ? 3 : 2;
  py::array_t<double> out({n, w});
  auto o = out.mutable_unchecked<2>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    o(i, 0) = a[k];
    o(i, 1) = b[k];
    if (c) o(i, 2) = (*c)[k];
  }
  return out;
}

py::array_t<double> xyz_array(const Toolpath& path) { return columns(path.x, path.y, &path.z); }

py::array_t<double> centre_array(const Toolpath& path) {
  if (path.has_arcs()) return columns(path.cx, path.cy, nullptr);
  const std::vector<double> none(path.size(), Toolpath::kNoCentre);
  return columns(none, none, nullptr);
}

Toolpath path_from_arrays(const py::array_t<std::uint8_t>& kind, const DoubleArray& xyz,
                          const DoubleArray& centre) {
  const auto n = kind.size();
  if (xyz.ndim() != 2 || xyz.shape(0) != n || xyz.shape(1) != 3)
    throw InvalidArgument("xyz: must have shape (N, 3) with N = len(kind)");
  if (centre.ndim() != 2 || centre.shape(0) != n || centre.shape(1) != 2)
    throw InvalidArgument("centre: must have shape (N, 2) with N = len(kind)");
  auto k = kind.unchecked<1>();
  auto p = xyz.unchecked<2>();
  auto c = centre.unchecked<2>();
  Toolpath path;
  for (py::ssize_t i = 0; i < n; ++i) {
    if (k(i) > static_cast<std::uint8_t>(MoveKind::Ramp))
      throw InvalidArgument("kind: move kinds are 0 to 5");
    if (is_arc(k(i)))
      path.add_arc(k(i) == static_cast<std::uint8_t>(MoveKind::ArcCCW), p(i, 0), p(i, 1), p(i, 2),
                   c(i, 0), c(i, 1));
    else
      path.add(static_cast<MoveKind>(k(i)), p(i, 0), p(i, 1), p(i, 2));
  }
  return path;
}

void bind_move_kinds(py::module_& m) {
  const std::pair<const char*, MoveKind> kinds[] = {
      {"RAPID", MoveKind::Rapid},  {"FEED", MoveKind::Feed},      {"PLUNGE", MoveKind::Plunge},
      {"ARC_CW", MoveKind::ArcCW}, {"ARC_CCW", MoveKind::ArcCCW}, {"RAMP", MoveKind::Ramp},
  };
  for (const auto& [name, k] : kinds) m.attr(name) = static_cast<int>(k);
}

}  // namespace isocam::py_path
