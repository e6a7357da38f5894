// Internal: phase 4 of 5-axis strip finishing (isocam/five_axis.h, "Links"):
// the posed runs linked into one toolpath, low between runs where proven
// clear, else through the safe height; the A/C angles one axis at a time
// (axes_to_ac() is built on it); and the machine time with the rotary axes
// timed.
#pragma once

#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <vector>

#include "finishing/five_axis_tool.h"
#include "geometry/clearance.h"
#include "isocam/five_axis.h"
#include "isocam/toolpath.h"

namespace isocam {

// axes_to_ac() one axis at a time: the angles (degrees) of each unit axis
// given the ones before it, as the posted program carries them. A copy
// tells what the next axis would get without committing to it.
class AcTracker {
 public:
  AcTracker(double a_min, double a_max) : a_min_(a_min), a_max_(a_max) {}
  // The angles of the unit axis (i, j, k); false if no A within [a_min,
  // a_max] gives it (then the previous angles, or its own A and C if none).
  bool next(double i, double j, double k, double* a, double* c);

 private:
  double a_min_, a_max_, pa_ = 0.0, pc_ = 0.0;
  bool have_ = false;
};

// The unit axis of the angles A and C (degrees): (sin A sin C, -sin A cos C, cos A).
gp_Vec axis_of_ac(double a_deg, double c_deg);

struct LinkContext {
  const FiveAxisParams& p;
  const ClearanceModel& model;
  double shank_clear;  // the query distance of the shank capsule (radius R - 2 gouge tolerance)
  double safe_z;       // tip z of the moves through the safe height (above the model)
};

struct Linked {
  Toolpath path;
  std::vector<gp_Vec> axis;
  int dropped = 0;  // runs left out: no retract along the axis up to the safe height is clear
  double dropped_length = 0;
  int low_links = 0, safe_hops = 0;
};

// The runs (each at least two poses, in order) linked as the header says.
Linked link_runs(const std::vector<std::vector<ToolPose>>& runs, const LinkContext& ctx);

// The time (s) of the moves, the first not counted (as estimate_time()):
// each move takes the longest of its tip length at its kind's rate and
// |dA| and |dC| at the rotary rate (no acceleration). `feed` is the feed
// moves' share, `plunge` the fed entries'.
PathTimes five_axis_times(const Toolpath& path, const std::vector<double>& a,
                          const std::vector<double>& c, const FiveAxisParams& p);

}  // namespace isocam
