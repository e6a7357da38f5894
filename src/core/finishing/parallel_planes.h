// Internal: the parallel-plane contouring baseline (IsoPattern::ParallelPlanes;
// Elber & Cohen, Figures 2b and 3b): what adaptive isocurves are compared with.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "finishing/coverage.h"
#include "geometry/trim_domain.h"
#include "isocam/progress.h"

namespace isocam {

// A picked face: its grid in its own orientation and its trimmed domain.
struct PlaneFace {
  int index = 0;  // in the shape, for messages
  const PatchGrid* grid = nullptr;
  const TrimDomain* trim = nullptr;
};

struct PlanePieces {
  std::vector<CutPiece> pieces;         // zig-zag across the planes; no grid (null)
  IsoPlaneAxis axis = IsoPlaneAxis::X;  // the axis used
  int curves = 0;                       // plane-curve pieces inside the faces
  double unreachable_length = 0.0;      // centre path cut away: no clearance
  double unreachable_from_above = 0.0;  // of it: the column above not clear
  // Largest first-order distance between adjacent passes where the ball
  // cuts (IsoMetrics::max_iso_distance for ParallelPlanes), and the same per
  // face (0 for a face that failed).
  double max_pass_distance = 0.0;
  std::vector<double> face_pass_distance;
  // Per face: why the geometry defeated it (face_failure.h), its pieces left
  // out; nothing if it did not.
  std::vector<std::optional<std::string>> failed;
};

// The pieces of the planes of constant x or y (params.plane_axis; Auto: the
// one with the shorter cutting length over all faces) delta apart, centred
// over the range of the ball centre's coordinate on the faces (a face's
// range is taken over its trimmed part, at the lattice of plane_trace.h).
// In each plane the ball centre follows the curves where the plane meets a
// face's offset S + r N, linearised within the chord tolerance, kept where
// it is inside the trimmed face (its contact point is), and cut by the
// clearance model exactly where the ball would come closer than r -
// chord_tolerance - model.tolerance() to it. Faces are computed on
// params.threads threads; the result does not depend on their number.
// A face that OpenCASCADE or the trimmed domain fails on is left out, named
// in `failed` (the others keep their planes); throws Cancelled if the
// progress asks.
PlanePieces parallel_plane_pieces(const std::vector<PlaneFace>& faces, double delta,
                                  const IsoParams& params, const ClearanceModel& model,
                                  Progress* progress);

}  // namespace isocam
