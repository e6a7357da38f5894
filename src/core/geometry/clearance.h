// Global clearance of the ball: is any point of a set of surfaces closer
// than d to a segment of ball-centre positions?
//
// This is what makes "no gouge" global rather than local: the centre on the
// offset S + r N is r from its own contact point, but where the surface
// curves tighter than the ball (the offset folds over itself) or another
// face comes near, another surface point can be closer. The query works on
// the (rational) Bezier patches directly, exactly up to a stated tolerance:
//  - a bounding volume hierarchy of the patches' control-net boxes culls;
//  - a patch is subdivided (de Casteljau) until either an oriented box of its
//    control net (axes from the patch's own frame, so a nearly flat piece
//    gets a thin box) is provably at least d - eps from the segment, or a
//    point of the surface (a corner of the piece, which the surface
//    interpolates) is closer than d: a witness;
//  - so "clear" proves every point at least d - eps away, "not clear" shows
//    one closer than d; the band eps between is what lets the subdivision
//    end (a piece whose box is under eps / sqrt(3) across is one or the
//    other).
#pragma once

#include <algorithm>
#include <cstdint>
#include <gp_Pnt.hxx>
#include <gp_XYZ.hxx>
#include <limits>
#include <vector>

#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"

namespace isocam {

class ClearanceModel {
 public:
  // eps: the accuracy of the answers (see clear()); max_piece: pieces of
  // surface larger than this are stored split (a few ball radii is a good
  // size).
  ClearanceModel(double eps, double max_piece) : eps_(eps), max_piece_(max_piece) {}
  // Adds every patch of the grid (which must outlive the model); with `trim`
  // (the face's domain, which must outlive the model too) only the part of the surface inside the
  // face counts: pieces outside it are skipped and a witness must lie inside it.
  void add(const PatchGrid& grid, const TrimDomain* trim = nullptr);
  // Builds the hierarchy; call once after the last add().
  void build();

  // Where a query found the model too close: a point (u, v) of a face's
  // grid.
  struct Witness {
    const PatchGrid* grid = nullptr;
    double u = 0.0, v = 0.0;
  };

  // False if some surface point is closer than d to the segment [a, b]
  // (then `witness`, if given, receives that point); true if none is closer
  // than d - eps. Between the two either answer may come. A query that
  // cannot be decided within its work budget answers false with no witness
  // (it costs path, never a gouge).
  bool clear(const gp_Pnt& a, const gp_Pnt& b, double d, Witness* witness = nullptr) const;
  bool clear(const gp_Pnt& c, double d, Witness* witness = nullptr) const {
    return clear(c, c, d, witness);
  }
  // clear() with the faces of the n grids `skip` left out: for a tool that
  // touches those faces by design, which another check measures.
  bool clear_except(const gp_Pnt& a, const gp_Pnt& b, double d, const PatchGrid* const* skip, int n,
                    Witness* witness = nullptr) const;

  // clear() of each segment [pts[k], pts[k + 1]] of a polyline of n points,
  // into out[k] (k < n - 1), with the same guarantee. Runs of consecutive
  // segments share the subdivision of the surface near them: cheaper than a
  // query each.
  void clear_polyline(const gp_Pnt* pts, std::size_t n, double d, char* out) const;

  // Reach from above (a 3-axis tool): the column of ball centres straight
  // above c, from c up to where no point of the model can be within d
  // (top() + d), as one segment query. "Clear" proves that a ball-end tool
  // lifted straight up from c -- its ball and a shank as wide as the ball --
  // keeps d - eps from every point of the model, as clear() does for a
  // segment; "not clear" shows a point closer than d.
  bool clear_above(const gp_Pnt& c, double d, Witness* witness = nullptr) const;
  // The witness's point (of an earlier query on this model) shows the
  // column above c blocked: it is closer to the column than d less twice
  // eps (a margin for the rounding of its evaluation), so clear_above(c, d)
  // would answer false: no piece that holds the point is ever passed, as
  // none is beyond d - eps or under eps across with no corner within d.
  // False for a witness without a point (a query out of its budget).
  bool witness_blocks_above(const Witness& w, const gp_Pnt& c, double d) const;
  // clear_above() of each of n centres into out[k], batched as
  // clear_polyline() is (neighbouring columns share the subdivision).
  void clear_above(const gp_Pnt* pts, std::size_t n, double d, char* out) const;
  // The highest z of the model's control nets (which bound it); -1e300 for
  // an empty model.
  double top() const { return nodes_.empty() ? -1e300 : nodes_.front().box.hi[2]; }

  // The distance from q to the nearest point of the witness's face found by
  // Newton's method from the witness (a local minimum of the untrimmed
  // surface: an estimate, not a proof of anything); moves the witness
  // there. For predictions that clear() calls then verify.
  static double local_distance(const gp_Pnt& q, Witness* witness);

  double tolerance() const { return eps_; }
  // The distance to query so that whatever clear() passes keeps at least
  // `keep` from the model.
  double query_distance(double keep) const { return keep + eps_; }

  struct Net;  // a control net being subdivided (defined in clearance.cpp)

 private:
  struct Box {
    // Empty: any point added replaces the infinite bounds.
    static constexpr double kInf = std::numeric_limits<double>::infinity();
    double lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    void add(const gp_Pnt& p);
    void add(const Box& b);
  };
  struct Patch {
    int pu = 0, pv = 0;
    bool rational = false;  // some weight is not 1
    std::size_t first = 0;  // index of the control net in cps_
    Box box;                // axis-aligned box of the control net
    gp_XYZ axes[3];         // and an oriented one: axes, then bounds along them
    double olo[3] = {0, 0, 0}, ohi[3] = {0, 0, 0};
    const TrimDomain* trim =
        nullptr;  // the face's domain if the patch meets its boundary, else null
    const PatchGrid* grid = nullptr;        // the face's grid
    double u0 = 0, u1 = 0, v0 = 0, v1 = 0;  // the patch's grid parameters
  };
  struct Node {
    Box box;
    int left = -1, right = -1;       // children, or -1 for a leaf
    int patch_lo = 0, patch_hi = 0;  // leaf: patches [lo, hi) of order_
  };

  int build_node(int lo, int hi);
  void add_piece(const Net& net, const PatchGrid& grid, const TrimDomain* trim);
  // Up to 32 segments at once (bit k for segs[k]; `mask` the ones asked
  // about; kBatch in clearance.cpp): the ones some surface point comes
  // closer than d to. With one segment, `witness` receives the point found.
  // `skip`: grids whose patches are left out (count n).
  struct Segment;
  struct Skip {
    const PatchGrid* const* grids;
    int n;
    bool has(const PatchGrid* g) const { return std::find(grids, grids + n, g) != grids + n; }
  };
  std::uint32_t blocked(const Segment* segs, int count, double d, Witness* witness,
                        const Skip& skip = Skip{nullptr, 0}) const;
  std::uint32_t patch_blocked(const Patch& p, const Segment* segs, std::uint32_t mask, double d,
                              Witness* witness) const;
  struct PatchQuery;  // patch_blocked()'s state and phases (clearance.cpp)

  double eps_, max_piece_;
  std::vector<H4> cps_;
  std::vector<Patch> patches_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

// The distance between segment [a, b] and an axis box (exact).
double segment_box_distance(const gp_Pnt& a, const gp_Pnt& b, const double lo[3],
                            const double hi[3]);
// A lower bound of its square (the box of the segment against the box):
// cheap, and exact for a point.
double segment_box_bound2(const gp_Pnt& a, const gp_Pnt& b, const double lo[3], const double hi[3]);
// segment_box_distance(a, b, lo, hi) >= d, trying the cheap bound first.
bool segment_box_beyond(const gp_Pnt& a, const gp_Pnt& b, const double lo[3], const double hi[3],
                        double d);

}  // namespace isocam
