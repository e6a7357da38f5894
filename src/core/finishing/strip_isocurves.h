// Internal: adaptive isocurves spaced by a strip width (G. Elber, E. Cohen,
// "Tool Path Generation for Freeform Surface Models", Algorithm 1, with the
// strip of any tool in place of the ball's iso-distance): the NormalIsocurves
// strategy of the 5-axis op, where the tool is oriented along each isocurve
// by the surface normal there (the paper's normal isocurve) tilted by the
// lead.
//
// The curves are iso-v curves S(., v) of the grid (transpose it for iso-u),
// sampled at one list of u shared by all, fine enough that consecutive
// samples of the curves are at most sample_max apart in space (checked at
// 17 levels of v). Algorithm 1: the boundary curves v = vmin and v = vmax
// first; between two adjacent curves va < vb, at every sample u where
// |S(u, va) - S(u, vb)| exceeds the strip width W(u) (the least of the
// widths at S(u, va), S(u, vb) and S(u, (va + vb) / 2), the feed along the
// isocurve), the middle curve v = (va + vb) / 2 is added over that stretch
// of samples (grown by one sample each side), and the two new pairs are
// treated alike over it. So adjacent curves are never farther apart, at
// the samples and at the same u, than the width (the distance at the same
// u bounds the distance to the next curve from above).
#pragma once

#include <functional>
#include <vector>

#include "finishing/scallop_front.h"
#include "geometry/patch_grid.h"

namespace isocam {

struct IsoStripSettings {
  double sample_max = 1.0;  // longest 3D step between samples of a curve
  // A pair of curves closer in v than this fraction of the v range is not
  // split further (counted in min_hits): a degenerate place where the width
  // shrinks to nothing.
  double min_dv = 1e-6;
  std::size_t max_points = 20000000;  // all curves' samples; over it: capped
};

struct IsoStripPaths {
  // One path per level of v, ascending; its pieces (sub-isocurves) in
  // ascending u. has_next: the point has a curve above it at its u.
  std::vector<std::vector<FrontPiece>> paths;
  // For each point with has_next, the same u on the next curve above.
  std::vector<std::vector<std::vector<ParamPt>>> next;
  int min_hits = 0;
  bool capped = false;
};

// `progress` is called now and then with the fraction of the v range
// done, never less than before (it may throw to cancel).
IsoStripPaths strip_isocurves(const PatchGrid& g, const StripWidth& width,
                              const IsoStripSettings& s,
                              const std::function<void(double)>& progress);

}  // namespace isocam
