// Internal: phase 3 of 5-axis strip finishing (isocam/five_axis.h): the
// job's settings every phase reads, and the tool posed along the runs of
// contact points with every check a posted position must pass (the exact
// check of the cutting end against its face, raising the lead; the shank
// against the model; the cutting end against the other faces near it,
// along the moves too; the swing where the pose jumps; A within its
// range). five_axis.cpp traces, clips and links; this poses.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <optional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "finishing/five_axis_tool.h"
#include "finishing/scallop_front.h"
#include "geometry/clearance.h"
#include "geometry/patch_grid.h"
#include "geometry/trim_domain.h"
#include "isocam/five_axis.h"

namespace isocam::five_axis {

// The most the axis the machine interpolates (A and C linear between two
// posted positions) may differ from the exact axis at the middle (radians):
// the rim then moves by at most R x this (in the budget's axis term).
constexpr double kAxisDeviation = 2e-4;
// The deepest the refinement halves a segment between two run samples.
constexpr int kMaxHalvings = 12;

// The job's derived numbers (isocam/five_axis.h, "The guarantees").
struct Budget {
  double chord = 0, posted = 0, axis = 0;
  double error() const { return chord + posted + axis; }
};

struct Face {
  int index = 0;
  PatchGrid grid;
  std::optional<TrimDomain> trim;
};

// The settings every phase reads.
struct Job {
  const FiveAxisParams& p;
  Budget b;
  Cutter tool;                                        // tool_radius and corner_radius
  double h_eff = 0;                                   // the cusp the strips are spaced for
  double lead = 0, max_lead = 0, tilt = 0, step = 0;  // radians
  double flat_width = 0;                              // strip width on flat ground at the lead
  const ClearanceModel* model = nullptr;
  double shank_clear = 0;  // the query distance of the shank capsule
  // The model's faces by their grids (to check the cutting end against a
  // face a clearance query finds near it).
  std::unordered_map<const PatchGrid*, const Face*> faces{};

  double lead_at(double kf, double ka) const { return lead_for(lead, max_lead, tool, kf, ka); }
  // The edge at a frame with the lead the job uses there, or `raised` if
  // that is more (a lead the exact check raised).
  EdgeProfile edge(const StripFrame& f, double raised = 0.0) const {
    const ContactFrame c{f.p, f.normal, f.feed, f.across};
    return EdgeProfile(c, tool, std::max(lead_at(f.kappa_feed, f.kappa_across), raised), tilt,
                       f.kappa_across);
  }
  double width(const StripFrame& f, double h, double raised = 0.0) const {
    return 2 * edge(f, raised).half_width(h);
  }
  bool capsule_clear(const gp_Pnt& tip, const gp_Vec& axis) const {
    return model->clear(tip.Translated(axis * p.tool_radius), tip.Translated(axis * p.tool_length),
                        shank_clear);
  }
  // The cutting end below the shank capsule (the cylinder of radius R from
  // the tip up to R) lies within the ball of radius sqrt(5) / 2 R about
  // its middle: the faces a clearance query finds within it are the ones
  // to check it against.
  gp_Pnt end_centre(const ToolPose& x) const {
    return x.tip.Translated(x.axis * (0.5 * p.tool_radius));
  }
  double end_ball() const { return model->query_distance(0.5 * std::sqrt(5.0) * p.tool_radius); }
};

// Phase 3: the tool posed along each run, refined until each move's
// midpoint is within the chord tolerance and the axis turns by at most the
// axis step; positions that gouge (after raising the lead), hit the model
// with the shank or need A outside the range are left out.
struct Posed {
  ParamPt uv;
  ToolPose pose;
  double lead = 0;
  double depth = 0;           // tool_depth of the pose, computed once by Poser::pose
  bool raised = false;        // lead above the job's lead
  bool raised_exact = false;  // ... and above what the curvature asks for there
  bool swing = false;         // a pose of a checked swing that failed: the run splits here
};

struct PoseOut {
  std::vector<std::vector<Posed>> runs;
  double unreachable = 0, max_lead = 0;
  int raised = 0, gouge_left = 0, shank_left = 0, range_left = 0;
  int others_left = 0;   // positions where the cutting end meets another face
  int unconverged = 0;   // refinements that reached their depth limit
  int swings_split = 0;  // ... whose swing failed its check

  // o's runs after these, its counts added.
  void append(PoseOut&& o) {
    for (std::vector<Posed>& r : o.runs) runs.push_back(std::move(r));
    unreachable += o.unreachable;
    max_lead = std::max(max_lead, o.max_lead);
    raised += o.raised;
    gouge_left += o.gouge_left;
    shank_left += o.shank_left;
    range_left += o.range_left;
    others_left += o.others_left;
    unconverged += o.unconverged;
    swings_split += o.swings_split;
  }
};

// The largest lead posed near a point: the positions whose lead the exact
// check raised (above what the curvature asks for), hashed by contact
// point in cells `radius` wide; the largest per point kept over every
// posing added.
class RaisedLeads {
 public:
  explicit RaisedLeads(double radius) : r_(radius) {}
  void add(const PatchGrid& g, const std::vector<std::vector<Posed>>& runs);
  // The largest raised lead within `reach` radii of p, 0 if none: the lead
  // posed at p (reach 1), or the one a path traced again between positions
  // raised is spaced for (reach 2: its points fall between them, where the
  // exact check raises about as much).
  double at(const gp_Pnt& p, long reach = 1) const {
    if (cells_.empty()) return 0.0;
    double lead = 0.0;
    const double r = double(reach) * r_;
    const long cx = cell(p.X()), cy = cell(p.Y()), cz = cell(p.Z());
    for (long i = cx - reach; i <= cx + reach; ++i)
      for (long j = cy - reach; j <= cy + reach; ++j)
        for (long k = cz - reach; k <= cz + reach; ++k) {
          const auto it = cells_.find(key(i, j, k));
          if (it == cells_.end()) continue;
          for (const auto& [q, l] : it->second)
            if (q.Distance(p) <= r) lead = std::max(lead, l);
        }
    return lead;
  }

 private:
  long cell(double x) const { return static_cast<long>(std::floor(x / r_)); }
  static std::int64_t key(long i, long j, long k) {
    return (std::int64_t(i) & 0x1FFFFF) | ((std::int64_t(j) & 0x1FFFFF) << 21) |
           ((std::int64_t(k) & 0x1FFFFF) << 42);
  }
  double r_;
  std::unordered_map<std::int64_t, std::vector<std::pair<gp_Pnt, double>>> cells_;
};

// Phase 2's result: a run of contact points inside the face, `back` if
// the zig-zag runs it back (its points stay in the traced order).
using Run = std::vector<ParamPt>;
struct ClippedRun {
  Run r;
  bool back = false;
};

// The run c of the face's grid g (as traced: `transposed` if u and v were
// exchanged) posed and checked into out; `own` is the face's grid in the
// model (the face the tool cuts, left out of the check against the
// others). Runs are independent: any number may be posed at once.
void pose_run(const PatchGrid& g, const TrimDomain& trim, bool transposed, const PatchGrid& own,
              const Job& job, const ClippedRun& c, PoseOut* out);

}  // namespace isocam::five_axis
