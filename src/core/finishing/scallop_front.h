// Internal: the geometry of the constant-scallop pattern (Y.S. Lee 1998,
// sections 3-5): the machining strip width at a contact point, the march
// along the surface across the feed (the parameter increments (du, dv) from
// the first fundamental form), and one step of the front of paths.
//
// A path is a list of pieces; a piece is a polyline of contact points given
// by their grid parameters, in feed order. The contact curve between two
// samples is the surface image of the straight segment between their
// parameters.
#pragma once

#include <cstdint>
#include <functional>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <unordered_map>
#include <vector>

#include "geometry/patch_grid.h"

namespace isocam {

struct ParamPt {
  double u = 0.0, v = 0.0;
};

// What a strip-width function sees at a contact point.
struct StripFrame {
  ParamPt uv;
  gp_Pnt p;                   // contact point
  gp_Vec normal;              // unit, away from the material
  gp_Vec feed;                // unit tangent of the path
  gp_Vec across;              // unit, normal x feed (towards the uncovered side)
  double kappa_across = 0.0;  // normal curvature along `across` (convex > 0)
  double kappa_feed = 0.0;    // normal curvature along `feed`
};

// The width of the strip that one pass machines within the scallop height,
// measured on the surface across the feed, at a contact point: the spacing
// to the adjacent pass on ground of that curvature. Pluggable so that the
// 5-axis tools give theirs (the tilted flat end's effective cutting shape).
using StripWidth = std::function<double(const StripFrame&)>;

// The ball end's: stepover_arc_with_error(r, h, kappa_across, e)
// (finishing/stepover.h), the strip within which balls whose centres are up
// to e off the exact offset leave at most h, e included; capped at twice the
// flat one (where the ball leaves no cusp).
StripWidth ball_strip_width(double r, double h, double e = 0.0);

struct FrontPoint {
  ParamPt uv;
  gp_Pnt p;
  // Filled when the point is marched: the spacing used, the largest
  // curvature across seen on the way, whether it reached the next path (a
  // point that meets the domain boundary at once has no successor).
  double spacing = 0.0, kappa = 0.0;
  bool has_next = false;
  // The direction the front moved in to reach this point (unit, in space).
  // A point whose march would turn back against it (more than about 75
  // degrees) is on a boundary the front has reached: it has no successor,
  // so the front never sweeps back over what it covered.
  gp_Vec came;
};
using FrontPiece = std::vector<FrontPoint>;

struct FrontSettings {
  double sample_max = 1.0;   // longest 3D step between samples of a piece
  double min_spacing = 0.0;  // spacing never below this (then min_hits counts)
  double max_spacing = 1e300;
};

// One step of the front over the grid's full parameter rectangle: every
// point of every piece marched across the feed (to the left of the feed,
// N x T) by the spacing that makes the strips of the two paths just
// overlap; folds (points whose successor runs backwards along the feed)
// and loops (self-intersections in the parameter plane) cut out; points
// that meet the boundary of the rectangle at once dropped (the piece splits
// there); the new pieces resampled to `sample_max`. The source pieces get
// their points' spacing filled in. `min_hits` counts the points whose
// spacing was raised to min_spacing. A new point closer than 0.7 of its
// spacing to a path so far (`done`, the current one included) is dropped:
// it lies where those paths' strips already cut (a concave turn of the
// current path, or a front meeting another), so the front never sweeps back
// over what is covered.
// The squared distance from p to the segment ab; t (if given): where on it,
// in [0, 1].
double to_segment2(const gp_Pnt& p, const gp_Pnt& a, const gp_Pnt& b, double* t = nullptr);

// The contact polylines of the paths so far, for nearest-distance queries
// (a uniform hash grid of segments, cells `cell` wide).
class PathIndex {
 public:
  explicit PathIndex(double cell) : cell_(cell) {}
  void add(const FrontPiece& piece);
  // The distance to the nearest segment, or 2 cell if none is that near;
  // `at`, if given, receives the nearest point (p itself if none is near).
  // With `enough` > 0 the search may stop at the first segment that near:
  // the answer is then at most `enough` (not the least distance).
  // `end`, if given, is set when the nearest point is the first or last
  // point of a piece added (where the ground beyond is the cap of a pass's
  // end, not a strip between two passes).
  double distance(const gp_Pnt& p, gp_Pnt* at = nullptr, double enough = 0.0,
                  bool* end = nullptr) const;
  // Some segment is within d of p (distance <= d): the cells the cube of
  // half-side d about p meets, and no others (a few for d under a cell).
  bool within(const gp_Pnt& p, double d) const;
  double cell() const { return cell_; }

 private:
  long idx(double x) const;
  double cell_;
  std::vector<std::pair<gp_Pnt, gp_Pnt>> segs_;
  std::vector<std::uint8_t> ends_;  // per segment: 1 first of its piece, 2 last
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid_;
};

struct FrontStep {
  std::vector<FrontPiece> next;
  int min_hits = 0;
};
FrontStep advance_front(const PatchGrid& g, std::vector<FrontPiece>* front, const StripWidth& width,
                        const FrontSettings& s, const PathIndex& done);

// The parameter direction (a, b) with a Su + b Sv the tangential part of
// `dir`: the first fundamental form [E F; F G] (a, b) = (dir.Su, dir.Sv).
// False at a degenerate point (a pole), where there is no such direction.
bool param_direction(const SurfaceDerivs& d, const gp_Vec& dir, double* a, double* b);

// The normal curvature at uv along the tangential part of `dir` (convex >
// 0); 0 at a degenerate point.
double normal_curvature(const PatchGrid& g, const ParamPt& uv, const gp_Vec& dir);

// The frame at uv with the feed along the tangential part of `feed_guess`
// (curvatures filled; feed null where that part is degenerate).
StripFrame make_frame(const PatchGrid& g, const ParamPt& uv, const gp_Vec& feed_guess);

// The frame at a point of a piece (feed from its neighbours).
StripFrame frame_at(const PatchGrid& g, const FrontPiece& piece, std::size_t k);

// The start path: the grid's iso-v boundary at vmin (or, where that
// boundary collapses to a point, the iso-v a quarter of the flat stepover
// `w0` away from it), sampled at sample_max.
std::vector<FrontPiece> start_front(const PatchGrid& g, double w0, double sample_max);

// Resamples a piece so that consecutive samples are at most `step` apart in
// space (points inserted on the parameter segment) and not closer than
// step / 8 (ends kept).
void resample(const PatchGrid& g, FrontPiece* piece, double step);

}  // namespace isocam
