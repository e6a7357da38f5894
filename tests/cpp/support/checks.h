// Invariant checks for toolpaths (ENGINEERING.md, habit 9): coverage in the
// sense of Definition 1, no gouge, and that the path really cuts the curves.
#pragma once

#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <cstdint>
#include <gp_Pnt.hxx>
#include <memory>
#include <unordered_map>
#include <vector>

#include "isocam/adaptive_isocurve.h"

class BRepTopAdaptor_FClass2d;

namespace isocam::test {

// Nearest distance from a point to a set of segments, by a uniform hash grid.
class SegmentIndex {
 public:
  explicit SegmentIndex(double cell) : cell_(cell) {}
  void add(const gp_Pnt& a, const gp_Pnt& b);
  void add_polyline(const std::vector<gp_Pnt>& pts);
  // The distance, or `cap` if no segment is within `cap`.
  double distance(const gp_Pnt& p, double cap) const;
  std::size_t size() const { return segs_.size(); }

 private:
  std::int64_t key(long i, long j, long k) const;
  double cell_;
  std::vector<std::pair<gp_Pnt, gp_Pnt>> segs_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid_;
};

// The contact curves S(t, level) of the result's sub-isocurves on `face`
// (whose index in the shape is `face_index`), sampled at spacing <= step.
std::vector<std::vector<gp_Pnt>> contact_curves(const TopoDS_Face& face, int face_index,
                                                const IsoResult& result, double step);

// The same curves mapped to the ball's tip: S + r N - r z.
std::vector<std::vector<gp_Pnt>> tip_curves(const TopoDS_Face& face, int face_index,
                                            const IsoResult& result, double r, double step);

// Largest distance from an n x n sampling of the face (its own surface and
// parameter bounds, independent of the core's representation; only samples
// inside the face's trimmed domain count) to the curves; Definition 1 holds
// if it is below delta. Capped at `cap`.
double coverage_gap(const TopoDS_Face& face, const SegmentIndex& curves, int n, double cap);

// True if the surface point p (on the face's surface) lies in the face's
// trimmed domain, within `tol` of it.
bool in_face(const TopoDS_Face& face, const gp_Pnt& p, double tol);

// Faces as a dense cloud of surface points (n x n over each face's parameter
// bounds) for distance queries that do not miss a far part of a face: the
// nearest sample is refined by a local projection onto its surface, so a
// returned distance is that of a true surface point (an upper bound of the
// exact distance, equal to it when the cloud is fine enough to land in the
// right basin, which a spacing well below the ball radius ensures). With
// `trimmed`, only samples inside each face's wires are kept, so the cloud is
// the model as the B-rep bounds it, not the untrimmed surfaces.
class ModelCloud {
 public:
  ModelCloud(const TopoDS_Face& face, int n)
      : ModelCloud(std::vector<TopoDS_Face>{face}, n, false) {}
  ModelCloud(const std::vector<TopoDS_Face>& faces, int n, bool trimmed);
  // Each face sampled n_f x n_f with n_f from its size: samples about
  // `spacing` apart along the larger side of its bounding box, n_f <= 600.
  ModelCloud(const std::vector<TopoDS_Face>& faces, double spacing, bool trimmed);
  struct Hit {
    double distance = 1e300;
    gp_Pnt point;   // the surface point
    int face = -1;  // its index in the faces given
  };
  // With `only`, the nearest point of the faces f with (*only)[f] != 0.
  Hit nearest(const gp_Pnt& p, const std::vector<char>* only = nullptr) const;
  // The nearest point of every face (of those in `only`, if given) that has
  // a sample within `radius` of p.
  std::vector<Hit> nearest_per_face(const gp_Pnt& p, double radius,
                                    const std::vector<char>* only = nullptr) const;
  double distance(const gp_Pnt& p) const { return nearest(p).distance; }
  // Reach from above: the distance from the model to the vertical ray up
  // from c (a ball centred at c lifted straight up: a 3-axis tool with a
  // shank as wide as the ball), or `cap` if nothing is within `cap`. The
  // nearest samples to the ray (the nearest of each face) are refined by
  // local projections alternating with the ray's nearest point, so the
  // distance is that of a true surface point, as nearest() gives.
  double column_distance(const gp_Pnt& c, double cap) const;
  double spacing() const { return cell_; }

 private:
  struct Sample {
    gp_Pnt p;
    int face;
    double u, v;
    bool near_wire;  // a sample within three cells of it is outside the face
  };
  struct Surface {
    Handle(Geom_Surface) surf;
    double u1, u2, v1, v2, du, dv;
    // Trimmed: the face's classifier, and its edges' 3D curves (where the
    // nearest point of the face lies when it is not inside).
    std::shared_ptr<BRepTopAdaptor_FClass2d> inside;
    struct Edge {
      Handle(Geom_Curve) curve;
      double first, last;
    };
    std::vector<Edge> edges;
  };
  // The distance from p to the face's edges (the nearest point on them).
  static Hit nearest_on_edges(const Surface& s, const gp_Pnt& p);
  std::vector<Surface> surfs_;
  std::vector<Sample> pts_;
  double cell_ = 1.0;
  double max_step_ = 0.0;  // the largest distance between neighbouring samples
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid_;
  // The samples by x-y cell alone (the same cell size), for column queries.
  std::unordered_map<std::int64_t, std::vector<std::size_t>> columns_;
  std::int64_t key(long i, long j, long k) const;
  void add_face(const TopoDS_Face& face, int n, bool trimmed);
  Hit refine(const gp_Pnt& p, std::size_t sample, double sample_distance) const;
  void index();
};
using FaceCloud = ModelCloud;

// Smallest distance from the ball centre to the face, over up to `checks`
// feed-move end points and midpoints of the path (tip coordinates).
double min_centre_distance(const FaceCloud& face, const Toolpath& path, double r, int checks);

// A path checked against a whole model, independently of the core (only
// OpenCASCADE's own surfaces and face classification):
//  - clearance: every feed move, sampled at `step`, keeps the ball centre
//    (tip + r z) at a distance from the trimmed model (all its faces);
//  - coverage (Definition 1): an n x n sampling of each picked face (inside
//    its wires) against the path's contact points (each sampled centre's
//    nearest point on each picked face it touches, within 0.05 mm of r: a
//    ball on an edge touches both faces). A sample where the ball cannot
//    touch -- its centre p + r N(p) is closer than r - reach_tol to the model
//    -- or that a 3-axis tool cannot reach from above -- the vertical ray up
//    from that centre comes as close (ModelCloud::column_distance()) -- is
//    unreachable and counted apart; that is computed here, not taken from
//    the core. A sample of an open face (one that bounds no solid) counts as
//    reachable if it is so from either side. The gap of a reachable sample
//    is its distance to the contacts or to the nearest unreachable sample,
//    whichever is less: where the reach ends the core cuts the passes, and
//    the border covers what is near it.
struct WholeModelCheck {
  double min_clearance = 1e300;          // smallest centre distance to the model
  gp_Pnt closest_centre, closest_point;  // where: the ball centre, the model point
  int closest_face = -1;                 // and the point's face (index in the shape)
  double max_gap = 0.0;                  // largest sample-to-contact distance, reachable samples
  gp_Pnt worst;                          // the sample where it is
  int worst_face = -1;                   // and its face (index in the shape)
  std::vector<double> face_gap;          // max_gap of each picked face
  int samples = 0, unreachable = 0;
};
WholeModelCheck check_whole_model(const TopoDS_Shape& shape, const std::vector<int>& picked,
                                  const Toolpath& path, double r, double step, int n,
                                  double reach_tol, double gap_cap);

// coverage_gap() over the samples of `face` (a face of `shape`, sampled
// n x n inside its wires) that a 3-axis ball-end tool of radius r reaches,
// decided as check_whole_model() does against `model` (the whole model);
// each sample's gap is its distance to the curves or to the nearest
// unreachable sample, whichever is less. Capped at `cap`.
double reachable_coverage_gap(const TopoDS_Face& face, const TopoDS_Shape& shape,
                              const ModelCloud& model, double r, double reach_tol,
                              const SegmentIndex& curves, int n, double cap);

// The scallop measured, not inferred: over an n x n sampling of the face
// (inside its wires), the height above each surface point p, along its
// normal N (away from the material), at which the ray p + t N first enters
// one of the balls swept along the feed moves (centres sampled every `step`
// mm). That height is the material the path leaves at p. Samples no ball
// reaches within `cap` are counted apart (not in `max`). With `model` (the
// whole model), samples a 3-axis tool cannot reach from above -- the vertical
// ray up from p + r N comes closer than r - 0.002 to the model
// (ModelCloud::column_distance()) -- are counted apart too (`unreachable`).
struct ScallopCheck {
  double max = 0.0;
  int samples = 0, uncovered = 0, unreachable = 0;
};
ScallopCheck measure_scallop(const TopoDS_Face& face, const Toolpath& path, double r, int n,
                             double step, double cap, const ModelCloud* model = nullptr);

// The feed moves of a path as segments.
SegmentIndex feed_segments(const Toolpath& path, double cell);

}  // namespace isocam::test
