// The sculptured floor pass (floor_path.cpp, ball_drop.cpp).
#pragma once

#include <BRepAdaptor_Surface.hxx>
#include <TopoDS_Face.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <vector>

#include "isocam/pocketing.h"
#include "pocketing/pocket_plan.h"

namespace isocam::pocket {

// A ball of radius R lowered onto the floor faces along -Z: the highest
// centre at which it touches them (vertex, edge or facet of a fine mesh of
// the faces, deflection `mesh_tol`), i.e. the floor's ball-end offset
// surface. The contact point is refined on the exact surface for facet
// contacts (Newton on S + R N = centre in x and y).
class BallDrop {
 public:
  BallDrop(const std::vector<TopoDS_Face>& faces, double radius, double mesh_tol);
  struct Contact {
    bool hit = false;
    double tip_z = 0.0;  // centre z - R
    gp_Pnt cc;           // contact point on the floor
    int face = -1;
    double u = 0.0, v = 0.0;  // its parameters on the face
  };
  Contact drop(double x, double y) const;
  double radius() const { return r_; }
  const std::vector<TopoDS_Face>& faces() const { return faces_; }
  const BRepAdaptor_Surface& surface(int face) const {
    return surf_[static_cast<std::size_t>(face)];
  }

 private:
  struct Tri {
    gp_Pnt p[3];
    gp_Pnt2d uv[3];
    int face;
  };
  void refine(double x, double y, Contact& c) const;
  std::vector<TopoDS_Face> faces_;
  std::vector<BRepAdaptor_Surface> surf_;
  double r_, mesh_tol_;
  std::vector<Tri> tris_;
  double gx0_ = 0, gy0_ = 0, cell_ = 1;
  long nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> grid_;
};

// Plan-view path interval across the loop at a CL point (Suh & Lee eq.
// 11-18): the normal curvature of the floor in the vertical plane across
// the loop gives the distance between ball centres that leaves a scallop
// of height h; its plan projection is the interval. `across` is the unit
// horizontal direction across the loop.
double path_interval(const BallDrop& floor, const BallDrop::Contact& c, P2 across, double h);

// Ball-end pass on the floor faces over the region (flat levels are done
// separately): offset tree with the interval of eq. 11-18 taken as the
// smallest along each node's loops, CL points by the plan-view deviation
// (tolerance) and the floor deviation (floor_tolerance).
void sculptured_floor_pass(const std::vector<TopoDS_Face>& faces, const std::vector<Loop>& region,
                           const PocketParams& p, Toolpath& path, PocketMetrics& m,
                           const ProgressSlice& progress);

}  // namespace isocam::pocket
