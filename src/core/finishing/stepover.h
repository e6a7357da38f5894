// Stepover and scallop of a ball-end tool on curved ground, and the
// per-patch iso-distance tolerance that Algorithm 1 works to.
//
// On ground of normal curvature kappa across the feed (convex > 0, see
// geometry/curvature.h) two passes of a ball of radius r whose contact points
// are an arc w apart leave a cusp of height h with (law of cosines in the
// plane across the feed, rho = 1/|kappa|, centres at rho +- r from the
// centre of curvature, the cusp at rho +- h):
//   1 - cos(phi) = (2 r h - h^2) / (2 (rho + s r)(rho + s h)),  w = 2 rho phi,
// s the sign of kappa; kappa -> 0 gives the flat w = 2 sqrt(2 r h - h^2).
// Written with kappa instead of rho so that it is stable as kappa -> 0.
#pragma once

#include <vector>

#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"
#include "isocam/adaptive_isocurve.h"

namespace isocam {

// Arc stepover w on ground of curvature kappa for scallop h; +inf where the
// ball cannot leave a cusp (concave ground at least as tight as the ball).
double stepover_arc(double r, double h, double kappa);
// The chord between the two contact points of that arc (what the
// iso-distance of Definition 4 measures).
double stepover_chord(double r, double h, double kappa);
// Inverse of stepover_chord in h: the scallop left by contact points a chord
// c apart on ground of curvature kappa (r if the balls do not meet).
double scallop_for_chord(double r, double c, double kappa);

// Per patch of a working grid (its curves are the iso-v curves): the largest
// curvature across the feed, and the iso-distance tolerance delta that keeps
// the scallop under h there. The curvature is sampled (4 x 4 per patch) and
// raised by a quarter of the sampled spread as a margin for what falls
// between samples.
class StepoverField {
 public:
  StepoverField(const PatchGrid& g, const IsoParams& p);
  // The tolerance for the strip between iso-v levels v1 < v2 over u-span i:
  // the smallest over the patch rows the strip touches. Flat bound: the
  // flat delta everywhere.
  double delta(int i, double v1, double v2) const;
  // The scallop height guaranteed where adjacent curves over u-span i,
  // between v1 and v2, are at most c apart: the largest over those rows.
  double scallop(int i, double v1, double v2, double c) const;
  double flat_delta() const { return flat_; }
  // The largest tolerance of any patch.
  double max_delta() const;

 private:
  template <class F>
  void rows(double v1, double v2, F f) const;
  const PatchGrid& g_;
  double r_, flat_;
  int nu_;
  std::vector<double> kappa_, delta_;
};

// Elber & Cohen's yardstick made a bound: L* = integral over the face (inside
// its wires) of dA / w_max, with w_max the largest stepover over all feed
// directions at the point, that is the stepover across the direction of
// least (most concave) normal curvature. No path that keeps the scallop under
// h everywhere is much shorter. Midpoint rule on 4 x 4 points per patch.
double lower_bound_length(const PatchGrid& g, const TrimDomain* trim, double r, double h);

}  // namespace isocam
