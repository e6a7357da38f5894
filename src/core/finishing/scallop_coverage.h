// Internal: what the constant-scallop pattern measures its certificate on
// (constant_scallop.cpp): the samples of a face, Definition 1 on them
// against the contact polylines, and the clip of paths to the face's wires.
//
// The certificate is measured, not intended. A face is sampled about `step`
// apart in space, finer on convex patches (where the ball allows a
// narrower stepover, so a sliver left uncovered there is as narrow), and on
// its boundary (its wires and untrimmed sides, where a pass clipped away
// leaves ground beside the wire). At each sample, d the distance to the
// nearest contact polyline and kappa the normal curvature there towards
// it: the ball leaves at most the cusp of contact points 2 d apart on that
// curvature with the centres up to e off the exact offset
// (scallop_with_error(), e included). At a boundary sample the same number
// is the height of the ball d away on that ground.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "finishing/scallop_front.h"
#include "geometry/trim_domain.h"

namespace isocam {

class FaceSampling {
 public:
  // The samples of the grid `g` (transposed: the face's grid with u and v
  // exchanged, as `trim` is not), for a ball of radius r, the scallop h and
  // the centres' error e.
  FaceSampling(const PatchGrid& g, const TrimDomain& trim, bool transposed, double step, double r,
               double h, double e);

  // f(u, v) at every sample inside the face, then at the boundary samples.
  template <class F>
  void for_each(F f) const;
  // The samples, in for_each()'s order.
  std::vector<ParamPt> points() const {
    std::vector<ParamPt> out;
    for_each([&](double u, double v) { out.push_back({u, v}); });
    return out;
  }

 private:
  const PatchGrid& g_;
  const TrimDomain& trim_;
  bool transposed_;
  double step_;
  std::vector<double> refine_;  // per patch j * patches_u + i: the factor on step, (0, 1]
  std::vector<ParamPt> boundary_;
};

// The distance from the face point (u, v) to the nearest contact polyline,
// and the normal curvature there towards it: across the feed of the path
// that cuts there (0 on the path).
struct Gap {
  double d = 0.0, kappa = 0.0;
  gp_Pnt x;          // the ground point
  gp_Pnt at;         // that nearest point
  bool end = false;  // it ends a polyline (PathIndex::distance())
};
Gap gap_at(const PatchGrid& g, const PathIndex& index, double u, double v);

// Definition 1 at a sample of gap q, for a ball of radius r with the
// centres up to e off: its distance raises max_gap, its cusp scallop (never
// lowered). Samples on concave ground tighter than the ball, where it
// cannot touch, count in neither.
void raise_coverage(const Gap& q, double r, double e, double* max_gap, double* scallop);

// The larger of `so_far` and the scallop that contact points a chord c
// apart leave on ground of curvature kappa with the centres up to e off
// (scallop_with_error()); solved only where the closed-form chord for
// so_far says that it is larger (the chord grows with the cusp while the
// cusp is small against the ball).
double raise_scallop(double so_far, double r, double c, double kappa, double e);

// The chord of an arc of length s on a circle of curvature kappa.
double chord_of_arc(double s, double kappa);

// Contact points of a piece as a curve: parameter t in [k, k+1] runs
// straight in (u, v) from sample k to k+1 (working grid).
ParamPt uv_at(const FrontPiece& pc, double t);

// The clip of pieces to the trimmed face, as the parallel planes are clipped
// (TrimDomain::classify_rect, then contains() with bisection at the
// boundary to 1e-4 of `tol` in space).
class WireClip {
 public:
  WireClip(const PatchGrid& g, const TrimDomain& trim, bool transposed, double tol)
      : g_(g), trim_(trim), transposed_(transposed), tol_(tol) {}

  // The parameter intervals of the piece inside the face: a segment whose
  // rectangle may meet the boundary is also tested at 7 interior points.
  std::vector<std::pair<double, double>> inside_runs(const FrontPiece& pc) const;
  // The contact polyline of the piece over [a, b] (its samples between).
  FrontPiece contact(const FrontPiece& pc, double a, double b) const;
  // The contact polylines of the piece's parts inside the face into `index`
  // (and into `also`, if given).
  void add_inside(const FrontPiece& pc, PathIndex* index, PathIndex* also = nullptr) const;

 private:
  bool inside(const ParamPt& uv) const;
  TrimDomain::RectClass classify(const ParamPt& a, const ParamPt& b) const;
  // Between t_in (inside) and t_out, the end of the inside part.
  double boundary(const FrontPiece& pc, double t_in, double t_out) const;

  const PatchGrid& g_;
  const TrimDomain& trim_;
  bool transposed_;
  double tol_;
};

template <class F>
void FaceSampling::for_each(F f) const {
  const auto& ub = g_.ubreaks();
  const auto& vb = g_.vbreaks();
  for (int j = 0; j < g_.patches_v(); ++j)
    for (int i = 0; i < g_.patches_u(); ++i) {
      const std::size_t iu = static_cast<std::size_t>(i), jv = static_cast<std::size_t>(j);
      const double at = step_ * refine_[static_cast<std::size_t>(j * g_.patches_u() + i)];
      // The patch's longer sides by their corners; at most 512 samples a side.
      const gp_Pnt c00 = g_.eval(ub[iu], vb[jv]), c11 = g_.eval(ub[iu + 1], vb[jv + 1]);
      const gp_Pnt c10 = g_.eval(ub[iu + 1], vb[jv]), c01 = g_.eval(ub[iu], vb[jv + 1]);
      const double su = std::max(c00.Distance(c10), c01.Distance(c11));
      const double sv = std::max(c00.Distance(c01), c10.Distance(c11));
      const int nu = std::clamp(static_cast<int>(std::ceil(su / at)), 1, 512);
      const int nv = std::clamp(static_cast<int>(std::ceil(sv / at)), 1, 512);
      for (int a = 0; a < nu; ++a)
        for (int b = 0; b < nv; ++b) {
          const double s = (a + 0.5) / nu, t = (b + 0.5) / nv;
          const double u = ub[iu] + s * (ub[iu + 1] - ub[iu]),
                       v = vb[jv] + t * (vb[jv + 1] - vb[jv]);
          if (transposed_ ? trim_.contains(v, u) : trim_.contains(u, v)) f(u, v);
        }
    }
  for (const ParamPt& b : boundary_) f(b.u, b.v);
}

}  // namespace isocam
