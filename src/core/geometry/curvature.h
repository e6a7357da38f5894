// Normal curvatures of a PatchGrid's surface, sampled per patch, for the
// curvature-aware stepover and the length lower bound L*.
//
// Sign convention: kappa > 0 where the surface is convex as seen by the ball
// (it bends away from the normal that points away from the material),
// kappa < 0 where it is concave. kappa = -(d2S[t, t] . N) for a unit tangent t.
#pragma once

#include <algorithm>
#include <cstddef>

#include "geometry/patch_grid.h"

namespace isocam {

struct CurvatureSample {
  bool ok = false;                  // false at a degenerate point (a pole): no tangent plane
  double k_cross = 0.0;             // across the feed of an iso-v curve: the larger of the
                                    // normal curvatures in the direction N x Su and along Sv
  double k_min = 0.0, k_max = 0.0;  // principal curvatures
  double area = 0.0;                // |Su x Sv| (the area element per unit du dv)
};

// At local coordinates (s, t) in (0, 1) of patch (i, j). Second derivatives
// are central differences of the exact first derivatives, with a step of
// 1e-4 of the patch, inside the patch (so s, t must keep 1e-4 from its edge).
CurvatureSample curvature_at(const PatchGrid& g, int i, int j, double s, double t);

// A bound on one curvature of patch (i, j) (`which`, e.g. &CurvatureSample::
// k_max): its largest over the samples at the local coordinates at x at,
// raised by a quarter of the sampled spread as a margin for what falls
// between; `none` where no sample is regular (a pole).
template <std::size_t N>
double patch_curvature_bound(const PatchGrid& g, int i, int j, const double (&at)[N],
                             double CurvatureSample::*which, double none) {
  double lo = 0.0, hi = 0.0;
  bool any = false;
  for (double s : at)
    for (double t : at) {
      const CurvatureSample c = curvature_at(g, i, j, s, t);
      if (!c.ok) continue;
      lo = any ? std::min(lo, c.*which) : c.*which;
      hi = any ? std::max(hi, c.*which) : c.*which;
      any = true;
    }
  return any ? hi + 0.25 * (hi - lo) : none;
}

}  // namespace isocam
