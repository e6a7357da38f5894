// Internal: isocurve coverages of one face and the path through them.
#pragma once

#include <string>
#include <vector>

#include "geometry/clearance.h"
#include "geometry/patch_grid.h"
#include "isocam/adaptive_isocurve.h"

namespace isocam {

// A set of sub-isocurves of one face that is a valid coverage (Definition 1)
// in the iso-distance sense: adjacent curves are at most delta apart.
struct FaceCoverage {
  std::vector<SubIsocurve> curves;
  double max_iso_distance = 0.0;  // measured over all adjacent pairs
};

// `grid` is in working orientation: the curves are its iso-v curves (the
// caller transposes the face's grid for IsoDirection::U). `face` and `dir`
// only label the result and the errors.
FaceCoverage adaptive_coverage(const PatchGrid& grid, int face, IsoDirection dir,
                               double delta, const IsoParams& params,
                               const ProgressSlice& progress);

// Baseline: complete isocurves equally spaced in parameter, with the fewest
// curves for which every adjacent pair is at most delta apart.
FaceCoverage uniform_coverage(const PatchGrid& grid, int face, IsoDirection dir,
                              double delta, const IsoParams& params,
                              const ProgressSlice& progress);

struct FacePathStats {
  int curves = 0;                   // sub-isocurves with something to cut
  double unreachable_length = 0.0;  // ball-centre path left out: no clearance
};

// Orders the curves (cross-iso order, zig-zag), drives the ball centre on the
// offset surface, linearises within the chord tolerance, cuts away the parts
// where the ball would come closer than r to the model (exactly where they
// start, to the clearance model's tolerance) and links adjacent curves by
// feed moves on the offset surface where the link keeps the clearance,
// others by a retract to safe_z. The path starts with a rapid to the safe
// height above its first point and ends with a retract.
Toolpath face_toolpath(const PatchGrid& grid, std::vector<SubIsocurve> curves,
                       const IsoParams& params, const ClearanceModel& model,
                       FacePathStats* stats);

std::string face_label(int face);

}  // namespace isocam
