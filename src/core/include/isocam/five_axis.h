// 5-axis strip finishing with a tilted flat-end or bull-nose tool: non-isoparametric
// passes placed by the machining strip width, after Y.S. Lee, "Non-
// isoparametric tool path planning by machining strip evaluation for 5-axis
// sculptured surface machining" (CAD 30(7), 1998), sections 2-5.
//
// The tool. A flat end of radius R: a cylinder whose bottom face is a disc
// of radius R; or a bull nose of radius R and corner radius rc (0 < rc < R):
// a cylinder whose bottom face, a disc of radius R - rc, meets its side in
// a quarter torus (tube radius rc). The posted point is the TOOL TIP = THE
// CENTRE OF THE BOTTOM FACE; the tool axis is the unit vector from the tip
// up the shank.
//
// The bull nose is treated as the flat end of its CORE DISC (radius R -
// rc, centred on the axis rc above the tip) grown by rc: below the height
// rc the tool is exactly the set of points within rc of the core disc.
// Everything below holds for it with R replaced by R - rc and the ground by
// its offset by rc (finishing/five_axis_tool.h says what is exact): the
// tip is P + rc N + (R - rc) unit(N - (N.axis) axis) - rc axis; the lower
// edge seen along the feed is the core disc's ellipse offset by rc (exact:
// the silhouette of a Minkowski sum), wider at the bottom than the ellipse
// alone and than a ball of radius rc; the rear-gouge conditions hold for
// the core disc against the ground offset by rc (normal curvature kappa /
// (1 + rc kappa)), and where the corner does not fit the concave ground
// (rc kappa <= -0.8, margin included) no lead helps; the exact check digs
// balls of radius rc centred on the core disc's samples into the face.
//
// The orientation (Lee's section 2). At a contact point P with unit normal
// N (away from the material), feed direction F (unit, tangent) and across
// direction A = N x F, the axis is N tilted by the lead angle l towards the
// feed and by the tilt angle t towards A:
//   axis = unit(cos l cos t N + sin l F + cos l sin t A),
// and the tip is where the lowest rim point of the disc (lowest along N)
// touches P: tip = P + R unit(N - (N.axis) axis). With t = 0 the disc rises
// behind the contact at the angle l: seen along the feed, in the normal
// plane across it, its lower edge is an ellipse of semi-axes R (across) and
// R sin l (along N) (radius of curvature R / sin l at the contact).
//
// The strip (section 2). Across the feed the tool's lower edge stands
// above the ground, approximated by the circle of its normal curvature
// across the feed kappa_a (convex > 0), by D(x) at the offset x from the
// contact; the strip machined within the scallop height h' is |x| <= x_h
// with D(x_h) = h' (x_h <= the disc's reach across). With a tilt the two
// sides differ; the smaller side counts on both (the zig-zag reverses the
// feed). Adjacent paths are spaced by the strip width 2 x_h at both paths
// and between them (sections 3-5: the orthogonal march of the constant-
// scallop engine, finishing/scallop_front.h), so the cusp between them is
// at most h'.
//
// No gouge of the cutting end (the "rear gouge" of the flat bottom on
// concave ground). To second order the disc stays above the surface iff
//   -kappa_a R <= sin l   and   -kappa_f R cos^2 l <= sin l
// (kappa_f the normal curvature along the feed): on concave ground a small
// lead lets the heel of the disc dig in behind the contact and its sides
// dig in across. Where the conditions ask for more than the lead angle, the
// lead there is RAISED (to the smallest angle that meets them with 25%
// curvature margin, never above max_lead_angle): a larger lead lifts the
// heel and narrows the strip (R / sin l shrinks), which the spacing then
// follows. Lowering the lead would only make the heel dig deeper. Every
// posted position is then checked exactly: the disc (its rim at 48 points
// and two inner rings) against the picked face it cuts, by the signed
// distance along the face normal at the nearest surface point; a position
// deeper than the gouge tolerance gets its lead raised in 2 degree steps up
// to max_lead_angle, and if that does not clear it the position is left out
// (its length reported as unreachable). The warnings say how many points
// had their lead raised and how far.
//
// No gouge of the shank (with protect_unpicked_faces, against the whole
// model, else the picked faces): the capsule of radius R - gouge_tolerance
// around the axis from R to tool_length above the tip must be clear of
// every face (trimmed to its wires) at each posted position and along each
// move; what fails is cut away and reported as unreachable.
//
// No gouge of the cutting end in the model's other faces (a wall beside
// the picked face, a neighbour under the disc where it overhangs the
// face's edge; with protect_unpicked_faces the unpicked faces too): the
// cutting end below R lies within the ball of radius R sqrt(5) / 2 about
// its middle; a clearance query of that ball (along a move, its sweep)
// against the model without the face cut finds the faces near it, and
// each gets the exact check above from the point found, the side of the
// cylinder sampled too (24 points at R / 2 and at R), counting a point
// behind the face only where the face's point nearest it lies in the tool
// (behind a face's plane is not in its material far from the face), and
// over the face's edge how deep the edge point lies in the tool. Along a
// move the depth is 1-Lipschitz in m = the tip's travel + sqrt(2) R x the
// axis turn, so at most (d_a + d_b + m) / 2 between poses of depths d_a,
// d_b; a move where that exceeds the gouge tolerance is halved (its middle
// pose checked) until it does not or m <= R / 20. A position where a face
// is deeper than the gouge tolerance is left out ("where the cutting end
// meets another face" in the warnings) and reported as unreachable.
//
// Rotary axes. A table-tilting A/C machine with tool-centre-point control:
// the tool axis relative to the part is
//   (sin A sin C, -sin A cos C, cos A),
// A (degrees) within [a_min, a_max], C (degrees) unwrapped: each point's C
// is the branch nearest the previous one (no 360 degree unwinds between
// neighbours), and where sin A is about 0 (the axis vertical) C keeps the
// previous value. With a_min < 0 the branch (-A, C + 180) is taken where it
// moves less. Positions whose axis needs A outside the range are left out
// (unreachable). Where the axis is near vertical, a lead that follows the
// zig-zag's feed turns C by half a turn between passes; lag_on_return
// keeps the tilt's side instead (A from 0 suffices). Coordinates x, y, z
// are the tip in the part (work) frame.
//
// Links (finishing/five_axis_link.h). Each run is entered by a fed move
// along its start axis over the air clearance and left by a rapid retract
// along its end axis. Between two consecutive runs the link is LOW where
// that is proven clear and estimated quicker: retract by a lift d (the air
// clearance, doubled until clear, then lowered by two bisection steps
// towards the last lift that failed), one rapid to the next start's tip +
// d axis with A and C linear (as the machine interpolates them), down that
// axis to the approach point. Along that rapid the whole tool (the
// cylinder of radius R up to tool_length) is proven to keep the air
// clearance from the model: it is checked at positions so close that no
// point of the tool moves more than the air clearance between two, each
// with 1.5 x the air clearance. The retract and the descent along the axis
// are checked as the hops' are (the shank capsule over their length).
// Otherwise (no lift up to 32 x the air clearance is clear, the link is
// longer than 5 tool diameters, or the hop is estimated no slower) the run
// is left to the safe height and the next entered from there: both ends of
// that move are at the safe height with the axis pointing up (A <= 90
// degrees), so the tool is above the model. Link moves are rapids: the
// machine must move G0 straight with A and C linear under TCP, as the
// check assumes (else set low_links false).
//
// The guarantees (stated, and measured by the tests from outside). Let c
// be the chord tolerance, p = sqrt(3)/2 x posted_resolution, and g the
// gouge tolerance. Between two posted positions the machine moves the tip
// straight and A and C linearly; each move is refined until the axis turns
// by at most max_axis_step (1 degree), the tip's midpoint is within c of the
// exact tip, and the axis the machine interpolates at the middle is within
// 2e-4 rad of the exact one (near A = 0, where C turns fast, this inserts
// positions; a pass over the pole turns C there at a nearly vertical axis),
// so the cutting end is within e = c + p + 2e-4 sqrt(R^2 + rc^2) of an
// exact position (its points are within that distance of the tip; checked
// at the midpoints, not bounded between them). The strips are spaced for
// h' = h - e, so
//   guaranteed_scallop = e + max over adjacent pairs of D(c_pair / 2) <= h,
// c_pair measured from each sample of a path to the next path. Nothing is
// cut deeper than guaranteed_overcut = e + g below the picked face.
// Not covered: places listed as unreachable, gaps the front leaves (the
// sampled coverage below reports them), and faces the warnings name.
#pragma once

#include <TopoDS_Shape.hxx>
#include <string>
#include <vector>

#include "isocam/adaptive_isocurve.h"
#include "isocam/progress.h"
#include "isocam/toolpath.h"
#include "isocam/work_budget.h"

namespace isocam {

// How the contact paths are placed.
enum class FiveAxisStrategy {
  // Non-isoparametric: each path from the one before by the strip-width
  // march (Lee's sections 3-5, above). The adaptive isocurves below are
  // traced too and used on a face where they are shorter by more than a
  // tenth (after covering the face and meeting h', as for the direction),
  // with a warning naming it: where the strip width changes fast along the
  // front (a flat end on rugged ground, its lead raised in the hollows)
  // the front folds and the march's paths grow many times longer.
  StripEvaluation,
  // Adaptive isocurves (Elber & Cohen, Algorithm 1) with the tilted tool's
  // strip width in place of the ball's: the boundary isocurves first, then
  // the middle isocurve added, only over the stretch where two adjacent
  // ones are farther apart (at the same parameter) than the width there;
  // the tool along each isocurve oriented by the surface normal there (the
  // paper's normal isocurve) tilted by the lead along the isocurve. The
  // poses, checks, links and guarantees are the same as above.
  NormalIsocurves,
};

struct FiveAxisParams {
  double tool_radius = 3.0;          // mm, R > 0 (a 6 mm flat end)
  double corner_radius = 0.0;        // mm, 0 <= rc < R: 0 a flat end, > 0 a bull nose
  double tool_length = 30.0;         // mm above the tip that must stay clear (> R)
  double lead_angle = 5.0;           // degrees, 0 < lead < 60
  double tilt_angle = 0.0;           // degrees, |tilt| < 45
  double max_lead_angle = 45.0;      // degrees, lead <= it < 80: the most a raise may use
  double scallop_height = 0.01;      // mm, 0 < h < R
  double gouge_tolerance = 0.001;    // mm, > 0
  double chord_tolerance = 0.0;      // mm; 0: derived ((h - p) / 4)
  double posted_resolution = 0.001;  // mm, >= 0, < 0.1
  double max_axis_step = 1.0;        // degrees, 0.05 .. 10: axis change per move
  double a_min = 0.0, a_max = 90.0;  // degrees, -120 <= a_min < a_max <= 120
  IsoDirection direction = IsoDirection::Auto;  // start path: iso-V at vmin, iso-U at umin
  FiveAxisStrategy strategy = FiveAxisStrategy::StripEvaluation;
  double safe_z = 0.0;         // tip z for moves between passes (raised to clear the model)
  double air_clearance = 1.0;  // mm, > 0: approach and retract along the axis
  // Low links between consecutive runs where proven clear and quicker than
  // the hop through the safe height (see "Links" above); false: every run
  // entered and left through the safe height.
  bool low_links = true;
  // The passes the zig-zag runs back: false, the axis leads along their own
  // feed (where it is near vertical C turns half a turn between passes);
  // true, they keep the tilt of the passes run forward (posed as if traced
  // forward, then run back: the tool lags, tilted against the feed by the
  // lead angle). The poses are those of the forward direction, so the
  // checks and guarantees are the same.
  bool lag_on_return = false;
  double feed_rate = 1200.0, plunge_rate = 400.0, rapid_rate = 5000.0;  // mm/min, > 0
  double rotary_rate = 3600.0;  // deg/min, > 0: the A and C speed machine_time assumes
  bool protect_unpicked_faces = true;
  double max_moves = kDefaultMaxMoves;
  int threads = 0;  // directions traced and runs posed at once; 0: one per core
};

struct FiveAxisMetrics {
  double cutting_length = 0.0, rapid_length = 0.0, plunge_length = 0.0;  // tip, mm
  // s: each move at least its tip length at its rate and |dA|, |dC| at the
  // rotary rate (no acceleration); cutting_time: the feed moves'
  double machine_time = 0.0, cutting_time = 0.0;
  double rotary_travel_a = 0.0, rotary_travel_c = 0.0;  // sum of |dA|, |dC| over moves (degrees)
  double chord_tolerance = 0.0;                         // used
  double flat_strip_width = 0.0;                        // 2 x_h on flat ground at the lead angle
  double max_spacing = 0.0;  // largest measured distance between adjacent paths
  double guaranteed_scallop = 0.0, guaranteed_overcut = 0.0;  // see the header
  double coverage_gap = 0.0;        // sampled: largest distance from a face point to a path
  double unreachable_length = 0.0;  // contact path left out (gouge, shank, A range)
  double max_lead_used = 0.0;       // degrees
  int lead_raised_points = 0;       // posted positions whose lead was raised
  // Moves between two posted positions whose poses (tip off the chord, axis
  // off the interpolated one, or turn) still differ by more than the
  // tolerances after 12 halvings (the pose jumps where the exact check
  // raised the lead on one side only). There the swing the machine makes
  // (tip along the chord, A and C interpolated) is checked at poses no more
  // than max_axis_step apart, as positions are: the cutting end against the
  // face, the shank against the model. swings_split of them failed and the
  // path is split there (the tool lifts instead of swinging).
  int unconverged_moves = 0, swings_split = 0;
  int paths = 0, retracts = 0;
  // StripEvaluation: the faces where the adaptive isocurves were used
  // instead of the march (shorter by over a tenth, or the march's paths
  // failed their certificate; a warning names each).
  int isocurve_faces = 0;
  int low_links = 0, safe_hops = 0;  // links between runs: low, or through the safe height
};

struct FiveAxisResult {
  Toolpath path;                // tip positions (the bottom face's centre), work frame
  std::vector<double> i, j, k;  // tool axis per move (unit)
  std::vector<double> a, c;     // rotary angles per move (degrees), see the header
  FiveAxisMetrics metrics;
  std::vector<std::string> warnings;
  // The picked faces skipped (indices in the shape, in the order given):
  // no path on them, a warning each says why (see below).
  std::vector<int> skipped_faces;
};

// A picked face whose geometry defeats the job (degenerate, OpenCASCADE
// failing on it) is skipped with a warning naming it and the reason, and
// the other faces are finished (ENGINEERING.md, habit 4); it stays in the
// clearance model if it could be built there, else the warning says it is
// not protected. Throws InvalidArgument for bad parameters (naming the
// argument) or bad face indices, GeometryError naming every face with its
// reason when every picked face is skipped, Cancelled if the progress asks.
FiveAxisResult five_axis_finish(const TopoDS_Shape& shape, const std::vector<int>& faces,
                                const FiveAxisParams& params, Progress* progress = nullptr);

// The A/C angles (degrees) of a sequence of unit axes, as the header says;
// false at `bad[k]` where no A within [a_min, a_max] gives the axis.
void axes_to_ac(const std::vector<double>& i, const std::vector<double>& j,
                const std::vector<double>& k, double a_min, double a_max, std::vector<double>* a,
                std::vector<double>* c, std::vector<char>* ok);

// The strip half-width x_h (mm) of the tilted flat end (corner_radius 0) or
// bull nose on ground of normal curvature kappa_across (convex > 0) for the
// scallop h, lead and tilt in degrees (the smaller side); the edge's reach
// (R on flat ground without tilt) if it stays within h up to there.
double strip_half_width(double radius, double corner_radius, double lead_deg, double tilt_deg,
                        double kappa_across, double h);
// strip_half_width with corner_radius 0.
double flat_end_half_width(double radius, double lead_deg, double tilt_deg, double kappa_across,
                           double h);

}  // namespace isocam
