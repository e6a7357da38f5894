#include "isocam/work_budget.h"

#include <cmath>
#include <sstream>

#include "isocam/errors.h"

namespace isocam {

void check_tolerance_ratio(const std::string& name, double tol, double extent) {
  if (!(tol > 0) || !std::isfinite(tol)) {
    std::ostringstream m;
    m << name << " = " << tol << " is out of range: must be a finite number > 0";
    throw InvalidArgument(m.str());
  }
  if (!std::isfinite(extent)) throw InvalidArgument("model: its extent is not finite");
  if (extent / tol > kMaxExtentToTolerance) {
    std::ostringstream m;
    m << name << " = " << tol << " mm is too fine for a model that extends " << extent
      << " mm (from the origin): the ratio " << extent / tol << " exceeds " << kMaxExtentToTolerance
      << "; coarsen " << name << " or move/scale the model";
    throw InvalidArgument(m.str());
  }
}

void check_max_moves(double max_moves) {
  if (!std::isfinite(max_moves) || max_moves < 1) {
    std::ostringstream m;
    m << "max_moves = " << max_moves << " is out of range: must be a finite number >= 1";
    throw InvalidArgument(m.str());
  }
}

void check_work_budget(double estimate, double max_moves, const std::string& how) {
  if (!(estimate <= max_moves)) {
    std::ostringstream m;
    m.precision(3);
    m << "work budget: about " << estimate << " moves (" << how << ") exceed max_moves = ";
    if (max_moves < 1e6)
      m << static_cast<long>(max_moves);
    else
      m << max_moves;
    m << "; raise max_moves (the operation's MaxMoves) or coarsen the tolerances";
    throw InvalidArgument(m.str());
  }
}

}  // namespace isocam
