// Adaptive isocurve finishing with a ball-end tool.
// G. Elber, E. Cohen, "Tool Path Generation for Freeform Surface Models",
// Algorithm 1 and Definitions 1-4.
//
// Contract: for every picked face, adjacent (sub-)isocurves of the returned
// coverage are never farther apart than delta (the iso-distance of
// Definition 4). With the flat bound (the paper's) delta is the stepover that
// gives the requested scallop height on flat ground:
// r - sqrt(r^2 - (delta/2)^2) = h. With the curvature-aware bound (the
// default) delta varies per Bezier patch with the normal curvature across the
// feed, so that the scallop stays under h on convex ground too (where the flat
// delta leaves a higher cusp) and concave ground is not over-cut; see
// finishing/stepover.h. The ball centre is
// driven on the exact offset S + r N (N pointing away from the material, as
// the face orientation says), each sub-isocurve linearised within the chord
// tolerance, and the path is returned in tool-tip coordinates. No gouge is
// global: wherever a centre (or a chord between centres) would come closer
// than r - chord_tolerance - gouge_tolerance to any picked face (and, with
// protect_unpicked_faces, any other face of the shape), its own included
// where it curves tighter than the ball, trimmed faces counting only inside
// their wires, the path is cut away there, and the length left out is
// reported.
//
// Reach from above (a 3-axis tool, issue 15): a centre is kept only if the
// column of centres straight above it, up to where nothing of the model can
// come that close, keeps the same r - chord_tolerance - gouge_tolerance from
// the whole model (checked at every centre of the planned path and where a
// pass is cut, ClearanceModel::clear_above(); the tool there is the ball and
// a shank as wide as it). So undersides and places under an overhang are left
// out (unreachable_from_above_length, and a warning), and every vertical move
// from or to a pass -- the lift to the safe height, a plunge from straight
// above -- keeps the cutting clearance. An open face (one that bounds no
// solid of the shape) is finished from the sides a vertical tool reaches
// (sampled, finishing/face_side.h): taken reversed where only the other side
// is reached, from both sides where both are, each said in `warnings`.
// Where of two adjacent passes only one keeps a piece (the other cut by the
// clearance, the reach or the face's wires), middle passes are added until
// that one alone leaves at most scallop_height (finishing/reach_border.h);
// that bound is part of guaranteed_scallop.
//
// The guarantees (GuaranteedScallop, GuaranteedOvercut of the FreeCAD op).
// Let c be the chord tolerance, g the gouge tolerance and p = sqrt(3)/2 x
// posted_resolution (the most that rounding each posted axis to half a step
// moves a point). Every exact ball centre of a pass is within e = c + p of a
// posted one, so everything within r - e of the exact centres is cut: the
// material left above the design is at most e plus the cusp of balls of
// radius r - e on the design offset by e (scallop_with_error(),
// finishing/stepover.h), which the curves are spaced for:
//   guaranteed_scallop = max over adjacent pairs (e + cusp) <= scallop_height.
// Every computed centre of a feed move (pass, link, fed entry) keeps r - c - g
// from the whole model (the clearance check, geometry/clearance.h), a posted
// one r - c - g - p, so nothing is cut deeper than
//   guaranteed_overcut = c + g + p <= overcut_tolerance.
// c is derived unless overridden: c = min(overcut_tolerance - g - p,
// (scallop_height - p) / 4); an override must fit both budgets. Rapid moves
// keep air_clearance + r from the whole model, but a lift straight up from
// a cutting position, which keeps the cutting clearance r - c - g as the fed
// entries do (finishing/coverage.h, link_pieces()). Not covered: faces listed in `warnings` as not
// protected, and the length reported as unreachable (material left there).
#pragma once

#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

#include "isocam/progress.h"
#include "isocam/toolpath.h"
#include "isocam/work_budget.h"

namespace isocam {

enum class IsoDirection {
  Auto,  // per face, the direction whose planned path (before clearance cuts) is shorter
  U,     // iso-U curves: u constant, the curve runs along v
  V,     // iso-V curves: v constant, the curve runs along u
};

enum class IsoPattern {
  Adaptive,  // Algorithm 1: sub-isocurves only where needed
  Uniform,   // baseline: complete isocurves equally spaced in parameter
  // Baseline of the paper's Figures 2b/3b: the ball centre driven on the
  // offset S + r N in parallel planes of constant x (or y) delta apart, as
  // commercial raster finishing does. See "ParallelPlanes" below.
  ParallelPlanes,
  // Non-isoparametric passes placed by the machining strip width (Y.S. Lee
  // 1998): see "ConstantScallop" below.
  ConstantScallop,
};

// The planes of IsoPattern::ParallelPlanes.
enum class IsoPlaneAxis {
  Auto,  // the axis whose pieces are shorter in all, over all picked faces (before linking)
  X,     // planes x = const (the passes run along y)
  Y,     // planes y = const (the passes run along x)
};

// Both keep guaranteed_scallop <= scallop_height.
enum class IsoScallopBound {
  Flat,       // the paper's flat-ground delta, narrowed as Curvature's on convex ground
  Curvature,  // delta per patch from the curvature across the feed (up to 2 x flat)
};

struct IsoParams {
  double ball_radius = 3.0;  // mm, > 0
  // The two budgets (see "The guarantees" above): the most material left
  // above the design where the ball reaches, and the deepest cut below it.
  double scallop_height = 0.01;      // mm, 0 < h < ball_radius
  double overcut_tolerance = 0.005;  // mm, gouge_tolerance + posted rounding < it < ball_radius
  // 0: derived from the budgets (min(overcut room, (h - posted) / 10)); > 0:
  // an override, which must fit both budgets (the certificate includes it).
  double chord_tolerance = 0.0;  // mm, >= 0
  // The step of the coordinates the post-processor writes: 0.001 for 3
  // decimals (FreeCAD's linuxcnc post by default); 0 if it writes them
  // exactly. Each axis is rounded by up to half of it.
  double posted_resolution = 0.001;  // mm, >= 0, < 0.1
  IsoDirection direction = IsoDirection::Auto;
  IsoPattern pattern = IsoPattern::Adaptive;
  IsoScallopBound scallop_bound = IsoScallopBound::Curvature;
  IsoPlaneAxis plane_axis = IsoPlaneAxis::Auto;  // ParallelPlanes only
  double safe_z = 0.0;                           // tool-tip z for retracts; must clear the path
  // The gap kept between the ball and the model by rapid moves between
  // passes (hops), and the height above an entry point from which the
  // entry is fed: stock left thinner than this is safe from rapids.
  double air_clearance = 1.0;  // mm, > 0
  // Rates of the machine-time estimate (and of the choice between a feed
  // link and a hop): horizontal feed, vertical (pure-Z) feed, rapids.
  double feed_rate = 1200.0;       // mm/min, > 0
  double plunge_rate = 400.0;      // mm/min, > 0
  double rapid_rate = 5000.0;      // mm/min, > 0
  int max_depth = 30;              // recursion guard of Algorithm 1 (>= 1)
  double gouge_tolerance = 0.001;  // mm: accuracy of the global clearance check
  // Keep the ball clear of the faces not picked too (the whole model; each
  // face trimmed to its wires exactly). Off: only the picked faces count.
  bool protect_unpicked_faces = true;
  int threads = 0;              // faces computed in parallel; 0: one per core
  double min_param_gap = 1e-9;  // relative to the face's parameter range (> 0)
  // The work budget: a job whose estimated number of moves (from the faces'
  // area, the stepover and the chord length the chord tolerance allows)
  // exceeds it is refused before the work (isocam/work_budget.h).
  double max_moves = kDefaultMaxMoves;
};

// One sub-isocurve: on face `face`, the curve of constant `level` in the
// direction `dir` (U or V), over parameters [t0, t1] of the other direction.
// Parameters are those of the face's Bezier-patch representation (see
// geometry/patch_grid.h), which equal the face's own parameters for B-spline
// and Bezier surfaces.
struct SubIsocurve {
  int face = 0;
  IsoDirection dir = IsoDirection::V;
  double level = 0.0;
  double t0 = 0.0, t1 = 0.0;
};

struct IsoMetrics {
  // The flat-ground iso-distance tolerance: the stepover whose cusp is what
  // the budget leaves, e + cusp(r - e) = scallop_height (e = chord + posted).
  double delta = 0.0;
  // The largest tolerance used on any patch (the curvature bound allows up
  // to 2 delta on concave ground, less than delta on convex ground): the
  // delta of Definition 1 that the coverage meets everywhere.
  double delta_max = 0.0;
  double cutting_length = 0.0;  // feed moves (mm)
  double rapid_length = 0.0;    // rapid moves (mm)
  double plunge_length = 0.0;   // fed entries: plunges (vertical feed) and ramps (mm)
  // Estimated with the rates of IsoParams (s): every move, the first (from
  // wherever the machine is) excepted; and the feed moves alone (the passes
  // and the links along the surface, not the entries).
  double machine_time = 0.0;
  double cutting_time = 0.0;
  double chord_tolerance = 0.0;  // the chord tolerance used (derived or the override)
  int sub_isocurves = 0;
  int retracts = 0;
  double max_iso_distance = 0.0;  // largest iso-distance left between adjacent curves
  // The most material left above the design where the ball reaches (see
  // "The guarantees"): over every accepted pair of adjacent curves, the
  // cusp of its largest iso-distance on ground of the largest curvature
  // across the feed there (sampled per patch, finishing/stepover.h), for
  // centres off the exact offset by chord + posted rounding, plus that
  // error. <= scallop_height under either bound for Adaptive and Uniform;
  // ParallelPlanes and ConstantScallop: the same kind of bound from what
  // they measured, which can exceed it (see below); the ball radius means
  // no bound (the balls of adjacent passes do not meet).
  double guaranteed_scallop = 0.0;
  // The deepest cut below the design: chord + gouge tolerance + posted
  // rounding, <= overcut_tolerance.
  double guaranteed_overcut = 0.0;
  // L* = integral over the picked faces (inside their wires) of dA / w_max:
  // a lower bound on the cutting length of any path with that scallop.
  double lower_bound_length = 0.0;
  // Length of ball-centre path left out because the ball cannot follow the
  // offset there without coming closer than r - chord_tolerance -
  // gouge_tolerance to a face (a concave region tighter than the ball):
  // material is left there; or because a 3-axis tool cannot reach the place
  // from above (see unreachable_from_above_length). All of it, in all.
  double unreachable_length = 0.0;
  // The part of unreachable_length left out although the ball there would
  // be clear: the column of centres straight above it is not (an underside,
  // a place under an overhang), so the tool could only get there through the
  // part. Counted per chord of the planned path with both ends clear (to the
  // chord length); material is left there.
  double unreachable_from_above_length = 0.0;
};

struct IsoResult {
  Toolpath path;
  IsoMetrics metrics;
  std::vector<SubIsocurve> curves;               // the coverage, in machining order
  std::vector<IsoDirection> face_direction;      // direction used per picked face (given order)
  std::vector<std::string> warnings;             // e.g. a face that could not be protected
  IsoPlaneAxis plane_axis = IsoPlaneAxis::Auto;  // ParallelPlanes: the axis used (X or Y)
  // The picked faces skipped (indices in the shape, in the order given):
  // the geometry defeated a phase on them (see adaptive_isocurve() below);
  // no path on them, and a warning each says why.
  std::vector<int> skipped_faces;
};

// ParallelPlanes (the baseline the adaptive isocurves are compared with):
// planes of constant x (or y) delta apart, centred over the range that the
// ball centre takes on the picked faces; in each plane the ball centre
// follows the curves where the plane meets the offset S + r N of each face
// (rolling around the face's own creases), within the chord tolerance and
// every vertex exactly in its plane; kept where the contact point is inside
// the trimmed face, cut by the same global clearance check, zig-zag across
// the planes and linked like the isocurve pieces (straight feed links,
// checked for clearance, or retracts). All picked faces share one set of
// planes. The curves are traced on a lattice of cells about r/4 across, so
// a loop of a plane curve smaller than that can be missed. For this pattern:
//  - `curves` is empty and every `face_direction` is Auto (there are no
//    isocurves); `plane_axis` says which axis was used;
//  - `sub_isocurves` counts the plane-curve pieces inside the faces (before
//    the clearance cuts, as for isocurves);
//  - `max_iso_distance` is the largest distance between adjacent passes on
//    the offset surface, to first order: delta / sqrt(1 - n_a^2) with n_a
//    the surface normal's component along the plane axis, taken at the
//    vertices of the traced plane curves (where they cross the lattice) and
//    the ends of the pieces cut. It equals delta on flat ground and grows
//    without bound on walls facing the axis (capped at 1e6 delta), which is
//    the pattern's weakness (the paper's Figure 3b);
//  - `guaranteed_scallop` is a bound from that spacing, the same kind as
//    the other patterns' (measured where they measure): per face, e plus
//    the cusp of balls of radius r - e whose centres are the face's largest
//    pass distance apart, on the face's most concave ground in any
//    direction (for a given centre distance concave ground leaves the
//    highest cusp, convex ground less than flat; plane_pass_scallop(),
//    finishing/stepover.h), the largest over the faces. Nothing spaces the
//    planes for it, so it exceeds scallop_height wherever the planes run
//    steeply or over concave ground, and it is the ball radius r -- no
//    bound: the balls of adjacent passes do not meet -- where the spacing
//    exceeds about 2 r (walls).

// ConstantScallop: per face, a start path on the face's boundary isocurve
// (v = vmin for V, u = umin for U; Auto: the direction with the shorter
// paths), then each next path from the one before by a march on the surface
// across the feed, by the spacing that the strip width (the stepover of
// finishing/stepover.h on the curvature across the feed) allows at both
// paths and between them; folds and loops cut out, the paths clipped to the
// trimmed face and cut by the same global clearance check, zig-zag, linked
// like the other pieces (finishing/constant_scallop.h). For this pattern:
//  - `curves` is empty; `face_direction` is the direction of the start path;
//  - `sub_isocurves` counts the path pieces inside the faces;
//  - `max_iso_distance` is the largest distance measured from a sample of a
//    path to the next path, and `guaranteed_scallop` the centres' error e
//    (see "The guarantees") plus the cusp of that distance on the largest
//    curvature across seen between them (measured at the samples, as the
//    other patterns measure per patch). The strips are spaced for a cusp
//    of the whole scallop_height (the budget is not split yet), so the
//    guarantee can exceed the scallop height by e.
//  - `delta_max` is the largest spacing used.

// delta from (r, h): the flat-ground stepover, 2 sqrt(2 r h - h^2); r finite
// and > 0, 0 < h <= r, else InvalidArgument.
double stepover_for_scallop(double ball_radius, double scallop_height);
// Inverse: flat-ground scallop height left by adjacent curves delta apart;
// r finite and > 0, 0 <= delta <= 2 r, else InvalidArgument.
double scallop_for_stepover(double ball_radius, double delta);

// Per-face failures (ENGINEERING.md, habit 4): a picked face whose geometry
// defeats the job -- degenerate, OpenCASCADE failing on it, its planning
// tripping a guard (max_depth, min_param_gap, the uniform spacing) -- is
// skipped: no path on it, its index in `skipped_faces`, a warning naming it
// ("face N (FaceN+1)") and the reason, and the other faces are finished as
// if it had not been picked. It stays in the clearance model if it could be
// built there (the ball is kept clear of it); otherwise the warning says it
// is not protected. Under Auto a direction that fails beside one that does
// not is left out with a warning. Its entry of `face_direction` is Auto.
//
// Throws InvalidArgument for bad parameters (the work budget included), an
// out-of-range or duplicate face index, or an empty shape; GeometryError,
// naming every face with its reason, only when every picked face is
// skipped; Cancelled if progress->cancel_requested.
IsoResult adaptive_isocurve(const TopoDS_Shape& shape, const std::vector<int>& faces,
                            const IsoParams& params, Progress* progress = nullptr);

}  // namespace isocam
