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

// The same with the ball centres off the offset S + r N by up to e (the
// chords' sag and the rounding of the posted coordinates): every point
// within r - e of the ideal centres is still cut, so what is left lies
// outside balls of radius r - e about them, which touch S + e N (curvature
// kappa / (1 + e kappa), contact chords scaled by 1 + e kappa). Material
// left above S: e plus the cusp of those balls above S + e N.
double scallop_with_error(double r, double c, double kappa, double e);
// Inverse in c: the chord between contact points on S that leaves at most
// h above S with centre error e (needs e < h; +inf where no cusp forms).
double stepover_chord_with_error(double r, double h, double kappa, double e);
// The arc on the surface between those two contact points (the strip width
// of the constant-scallop pattern); +inf where no cusp forms.
double stepover_arc_with_error(double r, double h, double kappa, double e);

// How the two user budgets are split (isocurve_job.cpp, split_budget()).
// Material left above the design: e + cusp <= scallop_height, with e =
// chord + posted the largest distance of a posted ball centre from the
// exact offset. Cut below the design: chord + gouge + posted <=
// overcut_tolerance (the clearance check keeps every computed centre at
// least r - chord - gouge from the model; rounding moves it by posted).
struct ErrorBudget {
  double chord = 0.0;   // chord tolerance of the linearisation
  double gouge = 0.0;   // accuracy of the clearance check
  double posted = 0.0;  // sqrt(3)/2 x the posted resolution
  double centre_error() const { return chord + posted; }
  double overcut() const { return chord + gouge + posted; }
};

// Per patch of a working grid (its curves are the iso-v curves): the largest
// curvature across the feed, and the iso-distance tolerance delta that keeps
// the scallop under h there. The curvature is sampled (4 x 4 per patch) and
// raised by a quarter of the sampled spread as a margin for what falls
// between samples.
class StepoverField {
 public:
  // `e`: the centre error of the budget (scallop_with_error()).
  StepoverField(const PatchGrid& g, const IsoParams& p, double e);
  // The tolerance for the strip between iso-v levels v1 < v2 over u-span i:
  // the smallest over the patch rows the strip touches. Flat bound: the
  // flat delta, but never more than the curvature bound's on convex ground
  // (so that the guarantee holds there too); the curvature bound: up to
  // twice the flat delta on concave ground.
  double delta(int i, double v1, double v2) const;
  // The scallop height guaranteed where adjacent curves over u-span i,
  // between v1 and v2, are at most c apart: the largest over those rows,
  // the centre error included (scallop_with_error()).
  double scallop(int i, double v1, double v2, double c) const;
  double flat_delta() const { return flat_; }
  // The largest tolerance of any patch.
  double max_delta() const;

 private:
  template <class F>
  void rows(double v1, double v2, F f) const;
  const PatchGrid& g_;
  double r_, e_, flat_;
  int nu_;
  std::vector<double> kappa_, delta_;
};

// ParallelPlanes' certificate (isocurve_job.cpp): the most material left
// above the face by passes whose ball centres are at most d apart on the
// offset S + r N, with centre error e. For a given centre distance the cusp
// is lower than flat on convex ground (the centres spread over a wider
// circle than the ground) and higher on concave ground (over a narrower
// one), so the cusp on the face's most concave curvature in any direction
// bounds it: k_min, sampled as StepoverField samples (4 x 4 per patch,
// inside the trimmed face) and lowered by a quarter of the patch's spread,
// flat where all is convex. Samples where the ball does not fit leave no
// cusp (scallop_with_error()). r where the balls do not meet or the
// centres are farther apart than that ground's circle of centres allows:
// no bound.
double plane_pass_scallop(const PatchGrid& g, const TrimDomain* trim, double r, double d, double e);

// Elber & Cohen's yardstick made a bound: L* = integral over the face (inside
// its wires) of dA / w_max, with w_max the largest stepover over all feed
// directions at the point, that is the stepover across the direction of
// least (most concave) normal curvature. No path that keeps the scallop under
// h everywhere is much shorter. Midpoint rule on 4 x 4 points per patch.
double lower_bound_length(const PatchGrid& g, const TrimDomain* trim, double r, double h);

}  // namespace isocam
