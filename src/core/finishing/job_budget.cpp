#include "finishing/job_budget.h"

#include <BRepBndLib.hxx>
#include <BRepGProp.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "isocam/errors.h"

namespace isocam {

void check_job_limits(const IsoParams& p) {
  if (p.ball_radius > 1e5)
    throw InvalidArgument("ball_radius = " + std::to_string(p.ball_radius) +
                          " mm is out of range: must be <= 1e5 mm");
  if (std::abs(p.safe_z) > 1e6)
    throw InvalidArgument("safe_z = " + std::to_string(p.safe_z) +
                          " mm is out of range: must be within 1e6 mm of z = 0");
  check_max_moves(p.max_moves);
}

void check_job_budget(const std::vector<TopoDS_Face>& all, const std::vector<int>& faces,
                      const IsoParams& user, const IsoParams& p, double delta) {
  Bnd_Box box;
  for (const TopoDS_Face& f : all) BRepBndLib::Add(f, box, false);
  if (box.IsVoid()) throw InvalidArgument("brep: the faces have no extent");
  double x0, y0, z0, x1, y1, z1;
  box.Get(x0, y0, z0, x1, y1, z1);
  const double far = std::max(
      {std::abs(x0), std::abs(y0), std::abs(z0), std::abs(x1), std::abs(y1), std::abs(z1)});
  const double size = std::sqrt(box.SquareExtent());
  const double extent = std::max(size, far);
  if (user.chord_tolerance > 0)
    check_tolerance_ratio("chord_tolerance", user.chord_tolerance, extent);
  check_tolerance_ratio("scallop_height", user.scallop_height, extent);
  check_tolerance_ratio("overcut_tolerance", user.overcut_tolerance, extent);
  double area = 0.0;
  for (int f : faces) {
    GProp_GProps props;
    BRepGProp::SurfaceProperties(all[static_cast<std::size_t>(f)], props);
    area += std::abs(props.Mass());
  }
  if (!std::isfinite(area)) throw InvalidArgument("brep: the picked faces' area is not finite");
  const double length = area / (2.0 * delta);
  const double chord = std::min(size, std::sqrt(8.0 * p.chord_tolerance * (size + p.ball_radius)));
  const double estimate = length / std::max(chord, 1e-300) + static_cast<double>(faces.size());
  std::ostringstream how;
  how.precision(3);
  how << area << " mm^2 of faces at a stepover of about " << 2 * delta << " mm, chords up to "
      << chord << " mm";
  check_work_budget(estimate, p.max_moves, how.str());
}

}  // namespace isocam
