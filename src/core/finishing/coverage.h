// Internal: isocurve coverages of one face and the path through them.
#pragma once

#include <functional>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <optional>
#include <string>
#include <vector>

#include "geometry/clearance.h"
#include "geometry/patch_grid.h"
#include "isocam/adaptive_isocurve.h"

namespace isocam {

// Two adjacent curves of a coverage: levels v1 < v2, accepted (within their
// tolerance) over `span` of the curve parameter.
struct CoverageStrip {
  double v1 = 0.0, v2 = 0.0;
  Interval span;
};

// A set of sub-isocurves of one face that is a valid coverage (Definition 1)
// in the iso-distance sense: adjacent curves are at most delta apart (delta
// per patch, from the StepoverField).
struct FaceCoverage {
  std::vector<SubIsocurve> curves;
  std::vector<CoverageStrip> strips;  // the adjacent pairs measured
  double max_iso_distance = 0.0;      // measured over all adjacent pairs
  double guaranteed_scallop = 0.0;    // the cusp those distances leave (stepover.h)
};

class StepoverField;

// `grid` is in working orientation: the curves are its iso-v curves (the
// caller transposes the face's grid for IsoDirection::U). `face` and `dir`
// only label the result and the errors.
FaceCoverage adaptive_coverage(const PatchGrid& grid, int face, IsoDirection dir,
                               const StepoverField& field, const IsoParams& params,
                               const ProgressSlice& progress);

// Baseline: complete isocurves equally spaced in parameter, with the fewest
// curves for which every adjacent pair is at most delta apart.
FaceCoverage uniform_coverage(const PatchGrid& grid, int face, IsoDirection dir,
                              const StepoverField& field, const IsoParams& params,
                              const ProgressSlice& progress);

struct FacePathStats {
  int curves = 0;                   // sub-isocurves with something to cut
  double unreachable_length = 0.0;  // ball-centre path left out: no clearance
  // the part of it left out only because the column above is not clear
  double unreachable_from_above = 0.0;
};

// Ball centres with the curve parameter of each.
struct CentrePolyline {
  std::vector<gp_Pnt> pts;
  std::vector<double> t;
  void push(const gp_Pnt& p, double s) {
    pts.push_back(p);
    t.push_back(s);
  }
  double length() const {
    double s = 0;
    for (std::size_t i = 1; i < pts.size(); ++i) s += pts[i - 1].Distance(pts[i]);
    return s;
  }
};

// A piece of path: ball centres along (part of) one sub-isocurve, every
// chord clear of the model.
struct CutPiece {
  // Working grid: the curve is its iso-v line at `level`. Null for a
  // parallel-plane curve, which has no iso level (`level` is its plane).
  const PatchGrid* grid = nullptr;
  double level = 0.0;
  std::vector<gp_Pnt> pts;  // ball centres
  std::vector<double> t;    // curve parameter of each
  // Without a grid: the face's normals at the contact points of the first
  // and the last centre, where the pattern knows them (the entries and
  // lifts beside a wall go out along them, link_pieces()).
  std::optional<gp_Vec> front_normal, back_normal;
  double length() const;
  void reverse();
};

// One sub-isocurve of a face, planned: the ball centre driven on the offset
// surface, linearised within the chord tolerance, in the direction the
// zig-zag gives it.
struct PlannedCurve {
  SubIsocurve curve;
  CentrePolyline line;
};

// A face's curves planned in cross-iso order, zig-zag. Curves that offset
// to a point (a boundary collapsed to a pole) are left out.
std::vector<PlannedCurve> plan_face(const PatchGrid& grid, std::vector<SubIsocurve> curves,
                                    const IsoParams& params);

// The pieces of planned curves [first, last) of one face: the parts where
// the ball would come closer than r to the model, or a vertical tool could
// not reach from above (the column of centres above comes as close,
// ClearanceModel::clear_above()), are cut away (exactly where they start, to
// the clearance model's tolerance). Curves are independent:
// ranges of them can be cut on several threads. `stats` receives the number
// of curves and the length left out.
std::vector<CutPiece> cut_planned(const PatchGrid& grid, const PlannedCurve* first,
                                  const PlannedCurve* last, const IsoParams& params,
                                  const ClearanceModel& model, FacePathStats* stats);

// The runs of a ball-centre polyline (vertices `pts` at increasing curve
// parameters `t`; `at` evaluates the exact curve) where the ball keeps
// `clearance` from the model, cut exactly where they start to violate, as
// cut_planned() does for isocurves (reach from above included; the length
// left out for that alone is added to *from_above if given). The pieces have
// no grid (null): links to them are straight.
std::vector<CutPiece> clear_pieces(const std::vector<gp_Pnt>& pts, const std::vector<double>& t,
                                   const std::function<gp_Pnt(double)>& at,
                                   const ClearanceModel& model, double clearance, double tol,
                                   double* from_above = nullptr);

// Orders and links pieces (of one face or many) into a path. Greedy: from
// the end of a piece, the nearest piece end (either direction) that a feed
// link reaches with the ball clear of the model -- along the offset surface
// between pieces of one face, a straight move otherwise -- not farther than
// 8 r and not slower (at the params' rates) than a hop to the nearest
// piece. Where none is, a hop: a rapid straight up, across at the lowest
// height tried (max of the two ends + air_clearance x 2^k) whose move the
// model clears by r + air_clearance, down to the lowest height tried
// (air_clearance x 2^k above the entry) from which the descent clears it
// as much, and the rest of the entry fed (a plunge, a ramp along the pass,
// or out along the normal beside a wall); the lift fed where a rapid would
// graze the model, or first fed out of the pass beside a wall (along the
// normal, or back along it and up; AirMoves in isocurve_link.cpp). The
// lift, the move out and the fed entry keep the cutting clearance; hops
// that find nothing clear below the safe height go to it. The path starts
// at the safe height above its first point and ends with a retract to it.
Toolpath link_pieces(std::vector<CutPiece> pieces, const IsoParams& params,
                     const ClearanceModel& model);

std::string face_label(int face);

}  // namespace isocam
