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
//    gets a thin box) is provably farther than d from the segment, or a
//    point of the surface (a corner of the piece, which the surface
//    interpolates) is closer than d: a witness;
//  - a piece smaller than `eps` that is neither is taken as clear, so the
//    answer is exact to within eps.
#pragma once

#include <vector>

#include <gp_Pnt.hxx>
#include <gp_XYZ.hxx>

#include "geometry/patch_grid.h"

namespace isocam {

class ClearanceModel {
 public:
  explicit ClearanceModel(double eps) : eps_(eps) {}
  // Adds every patch of the grid.
  void add(const PatchGrid& grid);
  // Builds the hierarchy; call once after the last add().
  void build();

  // False if some surface point is closer than d to the segment [a, b].
  bool clear(const gp_Pnt& a, const gp_Pnt& b, double d) const;
  bool clear(const gp_Pnt& c, double d) const { return clear(c, c, d); }

  double tolerance() const { return eps_; }

 private:
  struct Box {
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    void add(const gp_Pnt& p);
    void add(const Box& b);
  };
  struct Patch {
    int pu = 0, pv = 0;
    std::size_t first = 0;  // index of the control net in cps_
    Box box;                // axis-aligned box of the control net
    gp_XYZ axes[3];         // and an oriented one: axes, then bounds along them
    double olo[3] = {0, 0, 0}, ohi[3] = {0, 0, 0};
  };
  struct Node {
    Box box;
    int left = -1, right = -1;  // children, or -1 for a leaf
    int patch_lo = 0, patch_hi = 0;  // leaf: patches [lo, hi) of order_
  };

  int build_node(int lo, int hi);
  bool patch_clear(const Patch& p, const gp_Pnt& a, const gp_Pnt& b, double d) const;

  double eps_;
  std::vector<H4> cps_;
  std::vector<Patch> patches_;
  std::vector<int> order_;
  std::vector<Node> nodes_;
};

// Lower bound of the distance between segment [a, b] and an axis box.
double segment_box_distance(const gp_Pnt& a, const gp_Pnt& b, const double lo[3],
                            const double hi[3]);

}  // namespace isocam
