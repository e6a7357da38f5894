// The trimmed domain of a face (its wires in UV, holes included), queried
// along iso-lines of the face's PatchGrid: Elber & Cohen compute isocurves on
// the untrimmed surface and trim them afterwards (section 3); this is that
// trim, exact up to OpenCASCADE's 2D intersection tolerance, done with
// OpenCASCADE's 2D hatcher on the edges' p-curves.
#pragma once

#include <Geom_Surface.hxx>
#include <TopAbs_State.hxx>
#include <TopoDS_Face.hxx>
#include <array>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/bernstein.h"
#include "geometry/patch_grid.h"

class Geom2dHatch_Hatcher;
class BRepTopAdaptor_FClass2d;
class Geom2d_Curve;

namespace isocam {

class TrimDomain {
 public:
  // `grid` is the face's grid in its own orientation (not transposed).
  TrimDomain(const TopoDS_Face& face, const PatchGrid& grid, int face_label);
  ~TrimDomain();
  TrimDomain(TrimDomain&&) noexcept;
  TrimDomain& operator=(TrimDomain&&) noexcept;

  // The parts of [t0, t1] inside the face along the iso-line of the grid at
  // `level`: for an iso-v line (`iso_v` true) v = level and t runs along u;
  // otherwise u = level and t runs along v. Grid parameters in and out.
  // Thread-safe: the hatcher it uses is locked.
  std::vector<Interval> inside(bool iso_v, double level, double t0, double t1) const;

  // True if the grid point (u, v) is inside the face or on its boundary, to
  // the face classifier's tolerance (1e-9 in the face's parameters). The
  // quadtree and the exact rectangle test decide where they can, the
  // classifier (one projection per parameter on analytic faces) elsewhere.
  bool contains(double u, double v) const { return contains(u, v, true); }
  // contains() without its cache (the same answer): for callers whose
  // points do not come again, where storing each answer costs more than it
  // saves (the 5-axis checks' Newton feet: 2% of them asked again on MAT,
  // against 80 to 97% of the 3-axis ops' queries).
  bool contains_uncached(double u, double v) const { return contains(u, v, false); }

  // Where the grid rectangle [u0, u1] x [v0, v1] lies: entirely outside the
  // face, entirely inside, or it meets the boundary (Boundary also when,
  // rarely, it could not be decided: a p-curve that grazes it to within
  // rounding, or one with no exact Bezier form). A rectangle reported
  // Inside or Outside is so.
  enum class RectClass : int { Outside = -1, Boundary = 0, Inside = 1 };
  RectClass classify_rect(double u0, double u1, double v0, double v1) const {
    return classify_rect(u0, u1, v0, v1, true);
  }

  int face_label() const { return label_; }  // the face index it was built with
  // True if contains() decides points near the edges by the winding number
  // (the face's wires close as loops and the winding agreed with the
  // classifier wherever the quadtree asked it); false: the classifier.
  bool uses_winding() const { return winding_ok_; }

 private:
  // The two above, with their answers cached or not (`cache`).
  bool contains(double u, double v, bool cache) const;
  RectClass classify_rect(double u0, double u1, double v0, double v1, bool cache) const;
  // Grid parameter -> face parameter, per direction (0: u, 1: v).
  double to_face(int dir, double g) const;
  double to_grid(int dir, double f) const;
  // The hatcher's domains along the face iso-line at face parameter f;
  // false if it could not decide.
  bool hatch(bool iso_v, double f, double t0, double t1, std::vector<Interval>* out) const;

  void add_boundary_boxes(const Geom2d_Curve& pc, double f, double l, double range);
  // Adds the p-curve on [f, l] as rational Bezier spans; false if it has no
  // exact Bezier form (an offset curve, a degree above the supported one).
  // `sign`: the span's direction along its wire's loop (Span2::sign).
  bool add_spans(const Handle(Geom2d_Curve) & pc, double f, double l, int sign);
  // Whether a p-curve meets the closed face-parameter rectangle [lo, hi]:
  // 1 none does, 0 one does (each proved on the spans' control hulls under
  // subdivision), -1 not decided.
  int curves_meet(const double lo[2], const double hi[2]) const;
  // The winding number of the oriented p-curves about the face-parameter
  // point (fu, fv), by signed crossings of the ray towards +u (each span
  // right of the point counts the change of side of its end points, one
  // that straddles it is halved; the ray along -v, -u or +v where one along
  // +u passes a join of two p-curves closer than their gap): 1 inside, 0
  // outside, 2 on a p-curve (within on_tol_), -1 if it could not be decided
  // (the classifier answers).
  int winding_class(double fu, double fv) const;
  // Tabulated face(grid) maps for analytic faces, with a margin that bounds
  // their interpolation error.
  double face_approx(int dir, double g) const;

  struct Box2 {
    double lo[2], hi[2];
    bool meets(const double a[2], const double b[2]) const {
      return lo[0] <= b[0] && hi[0] >= a[0] && lo[1] <= b[1] && hi[1] >= a[1];
    }
  };
  // A quadtree over the face's parameter rectangle: a node that no boundary
  // box meets is wholly Inside or Outside the face (one classifier call
  // decides); nodes that meet the boundary are split down to a depth, below
  // which they stay undecided leaves (Boundary).
  struct QuadNode {
    double lo[2], hi[2];
    RectClass state = RectClass::Boundary;  // of a leaf
    int first_child = -1;  // children at first_child .. first_child + 3, or -1: a leaf
    bool leaf() const { return first_child < 0; }
  };
  void build_quadtree(int node, const std::vector<int>& boxes, int depth);
  RectClass query_quadtree(int node, const double lo[2], const double hi[2]) const;

  TopoDS_Face face_;
  Handle(Geom_Surface) surface_;  // the face's own surface (with its location)
  // OpenCASCADE's classifier is not safe to run on two threads at once (two
  // clearance queries classifying on one face crashed in Perform): each
  // call of classify_point() takes an idle one from this pool (or builds
  // one) and gives it back, so each classifier runs on one thread at a time
  // and two threads do not wait for each other's classification. The lock
  // is held only to take and give back.
  mutable std::vector<std::unique_ptr<BRepTopAdaptor_FClass2d>> idle_classifiers_;
  std::unique_ptr<std::mutex> classifiers_lock_ = std::make_unique<std::mutex>();
  TopAbs_State classify_point(double fu, double fv) const;
  // The winding number's answer where it has one, else the classifier's.
  TopAbs_State point_state(double fu, double fv) const;
  const PatchGrid* grid_;
  std::vector<Box2> boundary_;  // boxes that contain the edges' p-curves
  // The p-curves as rational Bezier spans: homogeneous control points
  // (x w, y w, w) at span_cps_[first ..], with the box of their hull.
  struct Span2 {
    std::size_t first = 0;
    int degree = 0;
    int sign = 0;  // +1 along the edge's orientation, -1 against it, 0: not on a wire's loop
    Box2 box;
  };
  std::vector<Span2> spans_;
  std::vector<double> span_cps_;  // 3 per control point
  bool spans_exact_ = true;       // every p-curve has its spans
  // The span ends (in face parameters) and how far apart two that meet may
  // lie; winding_class() is used only if the wires' p-curves close up to
  // that gap and it agreed with the classifier at the quadtree's leaves.
  std::vector<std::array<double, 2>> joins_;
  double join_gap_ = 0;
  double on_tol_ = 0;  // a point this near a p-curve is on the boundary
  bool winding_ok_ = false;
  std::vector<QuadNode> quad_;
  std::vector<double> table_g_[2], table_f_[2];
  double table_margin_[2] = {0, 0};
  std::optional<std::pair<double, double>> affine_[2];  // to_face() = a g + b where set
  int label_;
  double fmin_[2], fmax_[2];  // the face's parameter bounds
  std::unique_ptr<Geom2dHatch_Hatcher> hatcher_;
  std::unique_ptr<std::mutex> hatcher_lock_ = std::make_unique<std::mutex>();

  // The answers that took the exact test or the classifier, by rectangle
  // (a point is a rectangle of no size): the clearance queries along a path
  // ask about the same pieces of surface again and again. Sharded, each
  // shard locked; a full shard is emptied.
  struct RectKey {
    double c[4];
    int kind;  // 0: classify_rect, 1: contains
    bool operator==(const RectKey& o) const {
      return kind == o.kind && c[0] == o.c[0] && c[1] == o.c[1] && c[2] == o.c[2] && c[3] == o.c[3];
    }
  };
  struct RectHash {
    std::size_t operator()(const RectKey& k) const;
  };
  struct CacheShard {
    std::mutex lock;
    std::unordered_map<RectKey, int, RectHash> answers;
  };
  static constexpr std::size_t kCacheShards = 16;
  std::unique_ptr<std::array<CacheShard, kCacheShards>> cache_ =
      std::make_unique<std::array<CacheShard, kCacheShards>>();
  // Looks `key` up, or computes it with `decide` and stores it; with `use`
  // false only computes it.
  template <class Decide>
  int cached(bool use, const RectKey& key, Decide decide) const;
};

}  // namespace isocam
