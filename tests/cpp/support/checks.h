// Invariant checks for toolpaths (ENGINEERING.md, habit 9): coverage in the
// sense of Definition 1, no gouge, and that the path really cuts the curves.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Geom_Surface.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt.hxx>

#include "isocam/adaptive_isocurve.h"

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

// The face as a dense cloud of surface points (n x n over its parameter
// bounds) for distance queries that do not miss a far part of the face:
// the nearest sample is refined by a local projection onto the surface, so a
// returned distance is that of a true surface point (an upper bound of the
// exact distance, equal to it when the cloud is fine enough to land in the
// right basin, which a spacing well below the ball radius ensures).
class FaceCloud {
 public:
  FaceCloud(const TopoDS_Face& face, int n);
  double distance(const gp_Pnt& p) const;
  double spacing() const { return cell_; }

 private:
  Handle(Geom_Surface) surf_;
  double u1_, u2_, v1_, v2_, du_, dv_;
  double cell_;
  std::vector<gp_Pnt> pts_;
  std::vector<std::pair<double, double>> uv_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> grid_;
  std::int64_t key(long i, long j, long k) const;
};

// Smallest distance from the ball centre to the face, over up to `checks`
// feed-move end points and midpoints of the path (tip coordinates).
double min_centre_distance(const FaceCloud& face, const Toolpath& path, double r, int checks);

// The feed moves of a path as segments.
SegmentIndex feed_segments(const Toolpath& path, double cell);

}  // namespace isocam::test
