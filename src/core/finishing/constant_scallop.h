// Internal: the constant-scallop pattern (IsoPattern::ConstantScallop), after
// Y.S. Lee, "Non-isoparametric tool path planning by machining strip
// evaluation for 5-axis sculptured surface machining" (CAD 30(7), 1998),
// here for the ball end in 3 axes.
//
// Contract, per picked face (in the direction asked, or under Auto the one
// whose paths are shorter before the clearance cuts):
//  - The start path is the face grid's boundary isocurve at the low end of
//    the other parameter (v = vmin for V, u = umin for U), over the whole
//    untrimmed parameter range; where that boundary collapses to a pole,
//    the isocurve a quarter of the flat stepover away from it.
//  - Each next path is found from the current one, point by point (samples
//    at most the flat stepover apart in space): a march on the surface along
//    N x T (T the feed, N the normal), (du, dv) solved from the first
//    fundamental form at each step, by the spacing D = min(w(p), w(m), w(q))
//    with w the strip width (scallop_front.h, pluggable) at the point p, the
//    midpoint m and the new point q, found by a fixed point on one march.
//    Why the minimum and not the paper's mean (w_p + w_q) / 2: the cusp
//    between two passes forms on the ground between them, and its height
//    stays under h only if the spacing is under the width that ground's
//    curvature allows; the mean exceeds it on the side of the smaller
//    width, the minimum over both ends and the middle does not (the width
//    decreases with the curvature across).
//  - Folds (new points running backwards along the feed) and loops
//    (self-intersections in the parameter plane) are cut out; points that
//    reach the boundary of the parameter rectangle stop on it (a march step
//    that would leave it slides along it when that keeps most of its
//    length), and a point that cannot move at all has no successor: the
//    path splits there and each part goes on as a path of its own. The
//    front ends when no point moves.
//  - The spacing is never below min_spacing (2% of the flat stepover): where
//    the strip width asks for less, that spacing is used and a warning says
//    how often; a cap on the number of paths and samples ends the face with
//    a warning (never a hang).
//  - The contact polylines are clipped to the trimmed face exactly as the
//    parallel planes are (TrimDomain::classify_rect, then contains() with
//    bisection at the boundary), offset to the ball centre S + r N within
//    the chord tolerance, and cut by the global clearance model where the
//    ball would come closer than r - chord_tolerance - gouge_tolerance.
//  - Where the front leaves ground uncovered (a fold, a turn back, a wedge
//    between its parts, a pass clipped away beside a hole's wire), new paths
//    start there: seeds on the face's samples (scallop_coverage.h: inside
//    the wires, finer on convex patches, and on the boundary) whose cusp
//    against the paths' parts inside the wires exceeds h, a few rounds.
//  - The certificate is measured, not intended, with the centres up to
//    e = chord_tolerance + sqrt(3)/2 posted_resolution off the offset
//    (scallop_with_error(), e included): for every sample of a path whose
//    successor is on the next path, the cusp of that pair (its chord on the
//    circle of the largest curvature across seen between them); and on
//    every sample of the face, the cusp its distance to the clipped contact
//    polylines leaves (where a successor was cut out, this is what measures
//    the ground beyond), beside the end of a piece at the local maximum of
//    that distance climbed to from the samples there. guaranteed_scallop
//    is the larger; max_spacing the largest chord or twice the largest
//    sample distance. The default strip width is spaced for the whole
//    number to be h (ball_strip_width(r, h, e)).

#pragma once

#include <optional>
#include <string>
#include <vector>

#include "finishing/coverage.h"
#include "finishing/scallop_front.h"
#include "geometry/trim_domain.h"
#include "isocam/progress.h"

namespace isocam {

struct ScallopFace {
  int index = 0;  // in the shape, for messages
  const PatchGrid* grid = nullptr;
  const TrimDomain* trim = nullptr;
};

struct ScallopPieces {
  std::vector<CutPiece> pieces;              // zig-zag per face, faces in order; no grid
  std::vector<IsoDirection> face_direction;  // U or V per face
  int paths = 0;                             // paths over all faces (pieces of a path count once)
  int curves = 0;                            // contact-polyline pieces inside the faces
  double unreachable_length = 0.0;           // centre path cut away: no clearance
  double unreachable_from_above = 0.0;       // of it: the column above not clear
  double max_spacing = 0.0;                  // measured, see the header
  double guaranteed_scallop = 0.0;           // measured, see the header
  double max_width = 0.0;                    // the largest strip width used
  std::vector<std::string> warnings;
  // Per face: why the geometry defeated it (face_failure.h; its direction
  // Auto, nothing of it in the rest), nothing if it did not.
  std::vector<std::optional<std::string>> failed;
};

// `width` null: ball_strip_width(r, h). Faces (and under Auto their two
// directions) on params.threads threads; the result does not depend on
// their number. A face that OpenCASCADE or the trimmed domain fails on is
// left out, named in `failed`; throws Cancelled if the progress asks.
ScallopPieces constant_scallop_pieces(const std::vector<ScallopFace>& faces,
                                      const IsoParams& params, const ClearanceModel& model,
                                      Progress* progress, const StripWidth& width = nullptr);

}  // namespace isocam
