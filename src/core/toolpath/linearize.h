// Linearisation of parametric curves into chords within a tolerance.
#pragma once

#include <functional>
#include <gp_Pnt.hxx>
#include <vector>

namespace isocam {

// Points of f on [t0, t1] such that every chord stays within `tol` of the
// curve, checked at the quarter points of each chord's parameter interval
// after an initial split at `breaks` (e.g. Bezier span ends, where the
// curvature may jump) and into at least `min_pieces` pieces between them.
// The first point is f(t0), the last f(t1); t1 < t0 walks backwards.
// If `params` is given it receives the parameter of each point.
std::vector<gp_Pnt> linearize(const std::function<gp_Pnt(double)>& f, double t0, double t1,
                              double tol, const std::vector<double>& breaks, int min_pieces = 2,
                              std::vector<double>* params = nullptr);

}  // namespace isocam
