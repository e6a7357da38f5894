// Checks of an adaptive isocurve job against the limits of
// isocam/work_budget.h, before any work.
#pragma once

#include <TopoDS_Face.hxx>
#include <vector>

#include "isocam/adaptive_isocurve.h"

namespace isocam {

// Sizes that no job needs: ball_radius <= 1e5 mm, |safe_z| <= 1e6 mm,
// max_moves >= 1. Throws InvalidArgument naming the argument and value.
void check_job_limits(const IsoParams& p);

// The user's tolerances (scallop height, overcut tolerance and a chord
// tolerance given as an override: `user`) against the extent of the model
// (all its faces), then the estimated number of moves against max_moves,
// with the chord tolerance used (`p`, derived from the budgets unless
// overridden; a derived one is as fine as the scallop height leaves room
// for, and the move estimate bounds the work it makes):
// the picked faces' area / (2 delta) (the curvature bound spaces curves up
// to 2 delta apart) is the length of the passes, and a chord of an offset
// curve of radius rho within the chord tolerance eps is at most
// sqrt(8 eps rho) long, rho at most the model's extent plus r. So the
// estimate is a lower bound of the path's moves, up to the area.
void check_job_budget(const std::vector<TopoDS_Face>& all, const std::vector<int>& faces,
                      const IsoParams& user, const IsoParams& p, double delta);

}  // namespace isocam
