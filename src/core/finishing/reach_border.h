// Border passes where the reach ends (issue 10).
//
// Passes are cut exactly where the ball or the column above it stops being
// clear (cut_planned()), and clipped to the face's wires. Where that happens
// at different places on two adjacent passes -- a reach boundary or a wire
// crossing the strip between them, or running along it -- the surface
// between is cut by one pass only, from up to the whole strip away: the
// cusp the pair was spaced for does not bound what is left there.
// border_pieces() inserts middle passes over exactly those parts of the
// strips until the one pass that reaches is close enough alone, and
// certifies what it accepts.
#pragma once

#include <vector>

#include "finishing/coverage.h"
#include "finishing/stepover.h"
#include "geometry/trim_domain.h"

namespace isocam {

// One face in one direction, planned and cut.
struct BorderFace {
  int face = 0;
  IsoDirection dir = IsoDirection::V;
  bool iso_v = true;                 // the curves are iso-v lines of the face's own grid
  const PatchGrid* grid = nullptr;   // working grid (its iso-v curves are the passes)
  const TrimDomain* trim = nullptr;  // the face's domain
  const StepoverField* field = nullptr;
  const FaceCoverage* coverage = nullptr;  // its strips
  std::vector<const CutPiece*> cut;        // the pieces cut from those curves
};

struct BorderCut {
  std::vector<CutPiece> pieces;  // the middle passes' pieces (working grid)
  int curves = 0;                // middle sub-isocurves planned
  // The largest scallop bound of a part of a strip cut from one side only
  // (StepoverField::scallop() at twice the distance to the pass that cuts
  // it, see reach_border.cpp); at most scallop_height unless the halving ran
  // out of depth.
  double max_scallop = 0.0;
};

// For every strip of the coverage: where exactly one of its two curves
// keeps a piece (the other cut by the clearance, by the reach from above or
// by the face's wires), the single-sided bound; above scallop_height, a
// middle curve over those parts, planned and cut against `model` as the
// passes are (its parts the ball cannot take are left out and not counted
// as unreachable: they are not needed), and the two halves again, at most 4
// levels deep. Nothing is added where the coverage's own pairs hold.
BorderCut border_pieces(const BorderFace& face, const IsoParams& params,
                        const ClearanceModel& model);

}  // namespace isocam
