// The squared iso-distance of Elber & Cohen, Definition 4:
//   Delta^2(t) = || C1(t) - C2(t) ||^2
// between two isocurves of one patch grid, built symbolically and exactly as
// a piecewise rational function num/den in Bernstein form, one piece per
// Bezier span of the common domain. For rational curves C_k = P_k / w_k:
//   num = || P1 w2 - P2 w1 ||^2,  den = (w1 w2)^2  (> 0);
// for polynomial curves den == 1 and num = || P1 - P2 ||^2.
#pragma once

#include <vector>

#include "geometry/bernstein.h"
#include "geometry/patch_grid.h"

namespace isocam {

struct IsoDistancePiece {
  double a = 0, b = 0;  // global parameter interval; local t in [0,1] maps to it
  Bernstein num, den;
};

// Pieces covering [a, b] (a < b, within the curves' common breaks).
std::vector<IsoDistancePiece> iso_distance_squared(const PiecewiseBezier& c1,
                                                   const PiecewiseBezier& c2, double a, double b);

// Sub-intervals of [a, b] where Delta > delta (Algorithm 1's split points are
// their ends). A tangential excess smaller than 1e-9 delta^2 is ignored.
std::vector<Interval> exceeding(const std::vector<IsoDistancePiece>& pieces, double delta);
// The same with a tolerance per piece (deltas[k] for pieces[k]).
std::vector<Interval> exceeding(const std::vector<IsoDistancePiece>& pieces,
                                const std::vector<double>& deltas);

// max of Delta over the pieces (an upper bound within 1e-9 relative).
double max_iso_distance(const std::vector<IsoDistancePiece>& pieces);

// Complement of sorted disjoint `holes` within [a, b].
std::vector<Interval> complement(const std::vector<Interval>& holes, double a, double b);

}  // namespace isocam
